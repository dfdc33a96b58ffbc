/* land_detector.c - the staged land detector (fc/land_detector.h). */
#include "fc/land_detector.h"

void fc_land_detector_default_params(fc_land_detector_params *p, fc_real dt_s)
{
    p->dt_s = dt_s;
    p->still_speed_mps = FC_C(0.1f, VEL);
    p->still_accel_mps2 = FC_INT(1, ACCEL);
    p->contact_thrust_ratio = FC_C(0.9f, RATIO);
    p->landed_thrust_ratio = FC_C(0.3f, RATIO);
    p->contact_s = FC_C(0.35f, TIME);
    p->maybe_landed_s = FC_C(0.3f, TIME);
    p->landed_s = FC_C(0.3f, TIME);
    p->airborne_gear_height_m = FC_C(0.05f, LENGTH);
    p->range_fresh_s = FC_C(0.3f, TIME);
}

static bool land_params_valid(const fc_land_detector_params *p)
{
    const bool finite = fc_is_finite(p->dt_s) && fc_is_finite(p->still_speed_mps) &&
                        fc_is_finite(p->still_accel_mps2) && fc_is_finite(p->contact_thrust_ratio) &&
                        fc_is_finite(p->landed_thrust_ratio) && fc_is_finite(p->contact_s) &&
                        fc_is_finite(p->maybe_landed_s) && fc_is_finite(p->landed_s) &&
                        fc_is_finite(p->airborne_gear_height_m) && fc_is_finite(p->range_fresh_s);
    const fc_real ten_s = FC_INT(10, TIME);
    return finite && p->dt_s > FC_INT(0, DT) && p->dt_s <= FC_C(0.1f, DT) && p->still_speed_mps > FC_INT(0, VEL) &&
           p->still_speed_mps <= FC_INT(2, VEL) && p->still_accel_mps2 > FC_INT(0, ACCEL) &&
           p->still_accel_mps2 <= FC_INT(5, ACCEL) && p->contact_thrust_ratio > FC_INT(0, RATIO) &&
           p->contact_thrust_ratio <= FC_INT(1, RATIO) && p->landed_thrust_ratio > FC_INT(0, RATIO) &&
           p->landed_thrust_ratio <= p->contact_thrust_ratio && fc_in_range(p->contact_s, FC_INT(0, TIME), ten_s) &&
           fc_in_range(p->maybe_landed_s, FC_INT(0, TIME), ten_s) && fc_in_range(p->landed_s, FC_INT(0, TIME), ten_s) &&
           p->airborne_gear_height_m > FC_INT(0, LENGTH) && p->airborne_gear_height_m <= FC_INT(1, LENGTH) &&
           p->range_fresh_s > FC_INT(0, TIME) && p->range_fresh_s <= ten_s;
}

fc_init_result fc_land_detector_init(fc_land_detector *d, const fc_land_detector_params *p)
{
    d->ready = false;
    d->ar.saturated = 0u;
    fc_land_detector_reset(d);
    if (!land_params_valid(p)) {
        return FC_INIT_BAD_PARAM;
    }
    d->p = *p;
    d->step_s = fc_convert(&d->ar, p->dt_s, FC_DT_FRAC, FC_TIME_FRAC);
    d->held_accel_mps2 = fc_mul(&d->ar, p->still_accel_mps2, FC_C(0.5f, UNIT), FC_SHIFT(ACCEL, UNIT, ACCEL));
    d->ready = true;
    return FC_INIT_OK;
}

void fc_land_detector_reset(fc_land_detector *d)
{
    d->state = FC_LAND_AIRBORNE;
    d->contact_timer_s = FC_INT(0, TIME);
    d->low_thrust_timer_s = FC_INT(0, TIME);
}

bool fc_land_detector_range_says_airborne(const fc_land_detector *d, const fc_land_detector_input *in)
{
    return in->gear_height_known && in->gear_height_age_s <= d->p.range_fresh_s &&
           in->gear_height_m > d->p.airborne_gear_height_m;
}

/* thrust < ratio x hover */
static bool thrust_below(fc_arith *ar, const fc_land_detector_input *in, fc_real ratio)
{
    return in->vertical_thrust_n < fc_mul(ar, in->hover_thrust_n, ratio, FC_SHIFT(FORCE, RATIO, FORCE));
}

/* t + dt while the condition holds, 0 when it does not (bounded). */
static fc_real land_timer(fc_land_detector *d, fc_real timer_s, bool condition)
{
    return condition ? fc_min(fc_add(&d->ar, timer_s, d->step_s), FC_INT(600, TIME)) : FC_INT(0, TIME);
}

fc_land_state fc_land_detector_step(fc_land_detector *d, const fc_land_detector_input *in)
{
    if (!d->ready) {
        return FC_LAND_AIRBORNE;
    }
    fc_arith *ar = &d->ar;
    ar->saturated = 0u;
    if (d->state == FC_LAND_LANDED) {
        return d->state;
    }
    const bool pushing_down = in->descending && thrust_below(ar, in, d->p.contact_thrust_ratio);
    /* the ground holds it: pushed down, yet not accelerating down by half of what the acceleration test allows */
    const bool held = pushing_down && fc_within(in->accel_z_mps2, d->held_accel_mps2);
    const bool still = fc_within(in->accel_z_mps2, d->p.still_accel_mps2) &&
                       (fc_within(in->vz_mps, d->p.still_speed_mps) || held);
    const bool contact = still && pushing_down && !fc_land_detector_range_says_airborne(d, in);
    d->contact_timer_s = land_timer(d, d->contact_timer_s, contact);
    /* each stage needs its evidence at this step, and held for its time */
    const bool in_contact = contact && d->contact_timer_s >= d->p.contact_s;
    const bool low_thrust = in_contact && thrust_below(ar, in, d->p.landed_thrust_ratio);
    d->low_thrust_timer_s = land_timer(d, d->low_thrust_timer_s, low_thrust);
    if (!in_contact) {
        d->state = FC_LAND_AIRBORNE;
    } else if (low_thrust && d->low_thrust_timer_s >= fc_add(ar, d->p.maybe_landed_s, d->p.landed_s)) {
        d->state = FC_LAND_LANDED;
    } else if (low_thrust && d->low_thrust_timer_s >= d->p.maybe_landed_s) {
        d->state = FC_LAND_MAYBE_LANDED;
    } else {
        d->state = FC_LAND_GROUND_CONTACT;
    }
    return d->state;
}
