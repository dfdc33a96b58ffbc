/* landing.c - the landing mission's state machine (fc/landing.h). */
#include "fc/landing.h"

static bool landing_params_valid(const fc_landing_params *p)
{
    return fc_in_range(p->dt_s, FC_C(1e-4f, DT), FC_C(0.1f, DT)) &&
           fc_in_range(p->gear_height_m, FC_C(0.001f, LENGTH), FC_INT(10, LENGTH)) &&
           fc_in_range(p->hold_height_m, FC_C(0.01f, LENGTH), FC_INT(100, LENGTH)) &&
           fc_in_range(p->hold_tau_s, FC_C(0.05f, TIME), FC_INT(100, TIME)) &&
           fc_in_range(p->hold_settle_m, FC_C(0.001f, LENGTH), FC_INT(10, LENGTH)) &&
           fc_in_range(p->hold_settle_s, FC_INT(0, TIME), FC_INT(600, TIME)) &&
           fc_in_range(p->descent_tau_s, FC_C(0.05f, TIME), FC_INT(100, TIME)) &&
           fc_in_range(p->touchdown_dip_m, FC_C(0.001f, LENGTH), FC_INT(1, LENGTH)) &&
           fc_in_range(p->touchdown_window_m, FC_INT(0, LENGTH), FC_INT(1, LENGTH)) &&
           fc_in_range(p->contact_height_m, FC_C(0.001f, LENGTH), FC_INT(1, LENGTH)) &&
           fc_in_range(p->contact_confirm_s, FC_INT(0, TIME), FC_INT(10, TIME)) &&
           fc_in_range(p->ramp_s, FC_C(0.05f, TIME), FC_INT(10, TIME)) &&
           fc_in_range(p->confidence_start, FC_C(0.01f, UNIT), FC_INT(1, UNIT)) &&
           fc_in_range(p->confidence_abort, FC_INT(0, UNIT), p->confidence_start) &&
           fc_in_range(p->horizontal_start_m, FC_C(0.001f, LENGTH), FC_INT(100, LENGTH)) &&
           fc_in_range(p->horizontal_abort_m, p->horizontal_start_m, FC_INT(100, LENGTH)) &&
           fc_in_range(p->tilt_cos_abort, FC_INT(0, RATIO), FC_INT(1, RATIO)) &&
           fc_in_range(p->pad_accel_max_mps2, FC_C(0.001f, ACCEL), FC_INT(100, ACCEL)) &&
           fc_in_range(p->range_timeout_s, FC_C(0.01f, TIME), FC_INT(10, TIME));
}

fc_init_result fc_landing_init(fc_landing *lm, const fc_landing_params *p)
{
    lm->ready = false;
    lm->ar.saturated = 0u;
    lm->state = FC_LANDING_IDLE;
    lm->reason = FC_REASON_NONE;
    if (!landing_params_valid(p)) {
        return FC_INIT_BAD_PARAM;
    }
    lm->p = *p;
    fc_arith *ar = &lm->ar;
    const fc_altitude_reference_params hold = {p->dt_s, p->hold_tau_s, FC_INT(0, LENGTH),
                                               fc_add(ar, p->gear_height_m, p->hold_height_m)};
    const fc_altitude_reference_params descent = {p->dt_s, p->descent_tau_s, FC_INT(0, LENGTH),
                                                  fc_sub(ar, p->gear_height_m, p->touchdown_dip_m)};
    if (fc_altitude_reference_init(&lm->hold_reference, &hold) != FC_INIT_OK ||
        fc_altitude_reference_init(&lm->descent_reference, &descent) != FC_INIT_OK) {
        return FC_INIT_BAD_PARAM;
    }
    lm->window_offset_m = fc_add(ar, p->touchdown_dip_m, p->touchdown_window_m);
    lm->stuck_error_m = fc_mul(ar, p->touchdown_dip_m, FC_C(0.5f, UNIT), FC_SHIFT(LENGTH, UNIT, LENGTH));
    lm->inv_ramp_per_s = fc_div(ar, FC_INT(1, TIME), p->ramp_s, FC_DIV_SHIFT(TIME, TIME, GAIN));
    lm->step_s = fc_convert(ar, p->dt_s, FC_DT_FRAC, FC_TIME_FRAC);
    lm->shaping.ready = false;
    lm->shaping_gain = FC_INT(0, UNIT);
    lm->shaped_commit_offset_m = FC_INT(0, LENGTH);
    if (p->descent_shaping) {
        if (fc_descent_shaping_init(&lm->shaping, &p->shaping) != FC_INIT_OK ||
            !fc_in_range(p->shaping_commit_m, FC_INT(0, LENGTH), FC_INT(1, LENGTH)) ||
            !fc_in_range(p->shaping_filter_s, lm->step_s, FC_INT(10, TIME))) {
            return FC_INIT_BAD_PARAM;
        }
        lm->shaping_gain = fc_div(ar, lm->step_s, p->shaping_filter_s, FC_DIV_SHIFT(TIME, TIME, UNIT));
        lm->shaped_commit_offset_m = fc_add(ar, p->touchdown_dip_m, p->shaping_commit_m);
    }
    if (ar->saturated != 0u) {
        return FC_INIT_BAD_PARAM;
    }
    lm->ready = true;
    fc_landing_reset(lm);
    return FC_INIT_OK;
}

static void enter(fc_landing *lm, fc_landing_state state, fc_landing_reason reason)
{
    lm->state = state;
    lm->reason = reason;
    lm->state_time_s = FC_INT(0, TIME);
    lm->settled_s = FC_INT(0, TIME);
}

/* The shaped descent (fc/landing.h) from offset_m above the surface's end
 * point (none below it), its field filter at rest, not committed. */
static void shaped_descent_start(fc_landing *lm, fc_real offset_m)
{
    lm->shaped_offset_m = fc_max(offset_m, FC_INT(0, LENGTH));
    lm->shaped_offset_max_m = lm->shaped_offset_m;
    lm->shaped_rate_mps = FC_INT(0, VEL);
    lm->shaping_committed = false;
}

void fc_landing_reset(fc_landing *lm)
{
    enter(lm, FC_LANDING_IDLE, lm->state == FC_LANDING_IDLE ? lm->reason : FC_REASON_COMMANDED);
    lm->since_range_s = FC_INT(10, TIME);
    lm->touchdown_thrust_n = FC_INT(0, FORCE);
    lm->hold_level_m = FC_INT(0, LENGTH);
    lm->gear_height_m = FC_INT(100, LENGTH);
    lm->pressing = false;
    lm->aborts = 0u;
    shaped_descent_start(lm, FC_INT(0, LENGTH));
}

/* Toward the hold point from height z: (3.6) restarted with the offset
 * from there; the level is the pad's learnt mean, or (nothing learnt yet)
 * the level under where the vehicle is now. */
static void start_hold(fc_landing *lm, const fc_landing_input *in)
{
    fc_arith *ar = &lm->ar;
    const fc_real above = fc_add_inline(ar, lm->p.gear_height_m, lm->p.hold_height_m);
    lm->hold_level_m = in->pad->learning ? in->pad->mean_m : fc_sub(ar, in->z_m, above);
    fc_altitude_reference_restart(&lm->hold_reference, fc_sub_inline(ar, in->z_m, fc_add_inline(ar, lm->hold_level_m, above)));
}

void fc_landing_force(fc_landing *lm, fc_landing_state state, fc_landing_reason reason)
{
    if (lm->ready && lm->state != state) {
        enter(lm, state, reason);
    }
}

/* ---------------------------------------------------------------------- */
/* conditions                                                              */
/* ---------------------------------------------------------------------- */

static bool range_alive(const fc_landing *lm)
{
    return lm->since_range_s <= lm->p.range_timeout_s;
}

/* Why a descent may not start now (FC_REASON_NONE: it may). */
static fc_landing_reason descent_blocked(const fc_landing *lm, const fc_landing_input *in)
{
    const fc_pad_motion_estimate *pad = in->pad;
    if (!range_alive(lm)) {
        return FC_REASON_ABORT_RANGE_LOST;
    }
    if (in->horizontal_error_m > lm->p.horizontal_start_m) {
        return FC_REASON_ABORT_HORIZONTAL;
    }
    if (in->tilt_cos < lm->p.tilt_cos_abort) {
        return FC_REASON_ABORT_TILT;
    }
    if (pad->confidence < lm->p.confidence_start) {
        return FC_REASON_ABORT_CONFIDENCE;
    }
    if (pad->accel_bound_mps2 > lm->p.pad_accel_max_mps2) {
        return FC_REASON_ABORT_PAD_ACCEL;
    }
    return FC_REASON_NONE;
}

/* Why a descent must stop now (FC_REASON_NONE: it goes on). */
static fc_landing_reason descent_abort_reason(const fc_landing *lm, const fc_landing_input *in)
{
    if (in->request != FC_LANDING_REQUEST_LAND) {
        return FC_REASON_ABORT_COMMANDED;
    }
    if (in->horizontal_error_m > lm->p.horizontal_abort_m) {
        return FC_REASON_ABORT_HORIZONTAL;
    }
    if (in->tilt_cos < lm->p.tilt_cos_abort) {
        return FC_REASON_ABORT_TILT;
    }
    if (in->pad->accel_bound_mps2 > lm->p.pad_accel_max_mps2) {
        return FC_REASON_ABORT_PAD_ACCEL; /* a stated bound broken: before the confidence it also lowers */
    }
    if (in->pad->confidence < lm->p.confidence_abort) {
        return FC_REASON_ABORT_CONFIDENCE;
    }
    if (!range_alive(lm)) {
        return FC_REASON_ABORT_RANGE_LOST;
    }
    return FC_REASON_NONE;
}

/* Near the hold point (and the reference near it too) for hold_settle_s. */
static bool settled_at_hold(fc_landing *lm, const fc_landing_input *in, const fc_vertical_trajectory *reference)
{
    fc_arith *ar = &lm->ar;
    const fc_real hold_point =
        fc_add_inline(ar, lm->hold_level_m, fc_add_inline(ar, lm->p.gear_height_m, lm->p.hold_height_m));
    const bool near = fc_abs(ar, fc_sub_inline(ar, in->z_m, hold_point)) <= lm->p.hold_settle_m &&
                      fc_abs(ar, fc_sub(ar, reference->z_m, hold_point)) <= lm->p.hold_settle_m;
    lm->settled_s = near ? fc_min(fc_add(ar, lm->settled_s, lm->step_s), FC_INT(600, TIME)) : FC_INT(0, TIME);
    return near && lm->settled_s >= lm->p.hold_settle_s;
}

static void start_abort(fc_landing *lm, const fc_landing_input *in, fc_landing_reason reason)
{
    lm->gear_height_m = FC_INT(100, LENGTH);
    if (lm->aborts < 255u) {
        lm->aborts++;
    }
    start_hold(lm, in);
    enter(lm, FC_LANDING_ABORT, reason);
}

void fc_landing_abort(fc_landing *lm, const fc_landing_input *in, fc_landing_reason reason)
{
    if (lm->ready) {
        start_abort(lm, in, reason);
    }
}

/* ---------------------------------------------------------------------- */
/* one step                                                                */
/* ---------------------------------------------------------------------- */

/* The hold point's reference: (3.6) on the pad's level, which follows the estimate. */
static fc_step_status hold_reference(fc_landing *lm, const fc_landing_input *in, fc_vertical_trajectory *reference)
{
    if (in->pad->learning) {
        lm->hold_level_m = in->pad->mean_m;
    }
    const fc_vertical_trajectory level = {lm->hold_level_m, FC_INT(0, VEL), FC_INT(0, ACCEL)};
    return fc_altitude_reference_step(&lm->hold_reference, &level, reference);
}

/* The band of the gear at the surface: 3 contact heights. */
static fc_real contact_band_m(fc_landing *lm)
{
    return fc_mul(&lm->ar, lm->p.contact_height_m, FC_INT(3, RATIO), FC_SHIFT(LENGTH, RATIO, LENGTH));
}

/* The shaped descent (fc/landing.h): offset' = max(v_f, -offset / tau_d),
 * v_f the filtered v_zd of (2.25) from the vehicle's position relative to
 * the pad centre and the pad's attitude; (3.6)'s rate alone once committed. */
static fc_step_status shaped_descent_reference(fc_landing *lm, const fc_landing_input *in,
                                               fc_vertical_trajectory *reference, bool *window, fc_real *v_zd)
{
    fc_arith *ar = &lm->ar;
    const fc_vertical_trajectory *pad = &in->pad->now;
    const fc_real offset = lm->shaped_offset_m;
    *window = offset <= lm->window_offset_m;
    /* (3.6)'s rate from here: the fastest descent, the planned touchdown's */
    const fc_real exp_rate =
        fc_neg(ar, fc_mul(ar, offset, lm->descent_reference.inv_tau_per_s, FC_SHIFT(LENGTH, GAIN, VEL)));
    const fc_descent_shaping_input din = {{in->offset_x_m, in->offset_y_m, fc_sub(ar, in->z_m, pad->z_m)},
                                          in->pad_attitude};
    fc_descent_shaping_output dout;
    /* a clamped field is its design (the rate limits), not a fault to report */
    const fc_step_status status = fc_descent_shaping_step(&lm->shaping, &din, &dout) &
                                  (FC_STEP_NOT_READY | FC_STEP_BAD_INPUT | FC_STEP_ARITH_SATURATED | FC_STEP_DEGRADED);
    *v_zd = dout.vz_mps;
    /* v_f' = (v_zd - v_f) / shaping_filter_s */
    lm->shaped_rate_mps = fc_add(
        ar, lm->shaped_rate_mps,
        fc_mul(ar, fc_sub(ar, dout.vz_mps, lm->shaped_rate_mps), lm->shaping_gain, FC_SHIFT(VEL, UNIT, VEL)));
    if (offset <= lm->shaped_commit_offset_m || lm->gear_height_m <= contact_band_m(lm) ||
        lm->state == FC_LANDING_TOUCHDOWN) {
        lm->shaping_committed = true;
    }
    fc_real rate = lm->shaping_committed ? exp_rate : fc_max(lm->shaped_rate_mps, exp_rate);
    if (rate > FC_INT(0, VEL) && offset >= lm->shaped_offset_max_m) {
        rate = FC_INT(0, VEL); /* climbs no higher than where the descent started */
    }
    reference->z_m = fc_add(ar, fc_add(ar, pad->z_m, lm->descent_reference.bias_m), offset);
    reference->vz_mps = fc_add(ar, pad->vz_mps, rate);
    reference->az_mps2 = pad->az_mps2;
    const fc_real next = fc_add(ar, offset, fc_mul(ar, rate, lm->p.dt_s, FC_SHIFT(VEL, DT, LENGTH)));
    lm->shaped_offset_m = fc_clamp(next, FC_INT(0, LENGTH), fc_max(lm->shaped_offset_max_m, FC_INT(0, LENGTH)));
    return status;
}

static fc_step_status descent_reference(fc_landing *lm, const fc_landing_input *in,
                                        fc_vertical_trajectory *reference, bool *window, fc_real *v_zd)
{
    if (lm->p.descent_shaping) {
        return shaped_descent_reference(lm, in, reference, window, v_zd);
    }
    const fc_real offset_now =
        fc_mul(&lm->ar, lm->descent_reference.offset_m, lm->descent_reference.decay, FC_SHIFT(LENGTH, UNIT, LENGTH));
    *window = offset_now <= lm->window_offset_m;
    return fc_altitude_reference_step(&lm->descent_reference, &in->pad->now, reference);
}

/* On the pad: the range finder puts the gear on the surface, and the vehicle
 * no longer follows the reference, which goes on to dip below the surface
 * (z - z_r >= dip / 2). The second cue keeps range noise during the last
 * centimetres of a descent (the vehicle on its reference) from counting. */
static bool contact_seen(fc_landing *lm, const fc_landing_input *in, const fc_vertical_trajectory *reference)
{
    fc_arith *ar = &lm->ar;
    const fc_real behind_m = fc_sub(ar, in->z_m, reference->z_m);
    return in->range_fresh && in->gear_height_m <= lm->p.contact_height_m && behind_m >= lm->stuck_error_m;
}

/* Contact lost, with hysteresis against the range finder's noise: the gear
 * clearly off the surface (3 contact heights), or the vehicle back on its
 * reference (flying again, not held by the pad). */
static bool contact_lost(fc_landing *lm, const fc_landing_input *in, const fc_vertical_trajectory *reference)
{
    const fc_real behind_m = fc_sub(&lm->ar, in->z_m, reference->z_m);
    return in->range_fresh && (in->gear_height_m > contact_band_m(lm) || behind_m <= FC_INT(0, LENGTH));
}

/* Where (3.6) ends: the gear dip below the pad's surface, moving with it. */
static void press_reference(fc_landing *lm, const fc_landing_input *in, fc_vertical_trajectory *reference)
{
    const fc_real pressed_z_m = fc_add(&lm->ar, in->pad->now.z_m, lm->descent_reference.bias_m);
    if (reference->z_m > pressed_z_m) {
        reference->z_m = pressed_z_m;
        reference->vz_mps = in->pad->now.vz_mps;
        reference->az_mps2 = in->pad->now.az_mps2;
    }
}

/* HOLD, OBSERVE and ABORT: the hold point's reference; OBSERVE starts the
 * descent when nothing blocks it, HOLD and ABORT end when settled there. */
static fc_step_status hold_states_step(fc_landing *lm, const fc_landing_input *in, fc_landing_output *out)
{
    fc_arith *ar = &lm->ar;
    const fc_step_status status = hold_reference(lm, in, &out->reference);
    out->fly_reference = true;
    out->motors_on = true;
    if (lm->state == FC_LANDING_OBSERVE) {
        const bool may_retry = lm->aborts <= lm->p.abort_retries_max;
        if (!may_retry) {
            out->blocked_by = FC_REASON_RETRIES_EXHAUSTED;
        } else if (in->request != FC_LANDING_REQUEST_LAND) {
            out->blocked_by = FC_REASON_COMMANDED;
        } else {
            out->blocked_by = descent_blocked(lm, in);
        }
        if (out->blocked_by == FC_REASON_NONE) {
            /* (3.6) from here around the pad's motion */
            const fc_real surface_offset =
                fc_sub(ar, in->z_m, fc_add(ar, in->pad->now.z_m, lm->descent_reference.bias_m));
            fc_altitude_reference_restart(&lm->descent_reference, surface_offset);
            shaped_descent_start(lm, surface_offset);
            lm->gear_height_m = FC_INT(100, LENGTH);
            lm->pressing = false;
            enter(lm, FC_LANDING_DESCEND, FC_REASON_PAD_LEARNT);
        } else if (!range_alive(lm) && lm->state_time_s > lm->p.range_timeout_s) {
            /* nothing to learn from: back to HOLD, which waits for the range finder */
            enter(lm, FC_LANDING_HOLD, FC_REASON_ABORT_RANGE_LOST);
        } else {
            /* observing on */
        }
    } else if (settled_at_hold(lm, in, &out->reference)) {
        if (lm->state == FC_LANDING_ABORT) {
            const bool exhausted = lm->aborts > lm->p.abort_retries_max;
            enter(lm, FC_LANDING_HOLD, exhausted ? FC_REASON_RETRIES_EXHAUSTED : FC_REASON_ABORT_CLIMB_DONE);
        } else if (range_alive(lm)) {
            enter(lm, FC_LANDING_OBSERVE, FC_REASON_HOLD_SETTLED);
        } else {
            /* settled, but the range finder is quiet: hold on */
        }
    } else {
        /* on the way to the hold point */
    }
    return status;
}

/* DESCEND and TOUCHDOWN: (3.6) around the pad's motion; aborts, contact, its confirmation. */
static fc_step_status descent_states_step(fc_landing *lm, const fc_landing_input *in, fc_landing_output *out)
{
    const fc_step_status status =
        descent_reference(lm, in, &out->reference, &out->touchdown_window, &out->shaping_mps);
    out->fly_reference = true;
    out->motors_on = true;
    fc_landing_reason abort = descent_abort_reason(lm, in);
    if (in->range_fresh) {
        lm->gear_height_m = in->gear_height_m;
    }
    const fc_vertical_trajectory natural = out->reference; /* (3.6): contact is judged against it */
    if (lm->gear_height_m <= contact_band_m(lm)) {
        /* the gear at the surface: climbing away from it would be the riskier
         * move, and the reference may not lift the vehicle off (a touch while
         * the reference is still above would otherwise become a hop) */
        if (abort != FC_REASON_ABORT_COMMANDED) {
            abort = FC_REASON_NONE;
        }
        if (out->reference.z_m > in->z_m) {
            out->reference.z_m = in->z_m;
            out->reference.vz_mps = fc_min(out->reference.vz_mps, in->pad->now.vz_mps);
        }
    } else {
        lm->pressing = false;
    }
    if (lm->p.press_at_contact && out->touchdown_window && lm->gear_height_m <= lm->p.contact_height_m) {
        lm->pressing = true;
    }
    if (lm->pressing) {
        press_reference(lm, in, &out->reference);
    }
    if (lm->state == FC_LANDING_DESCEND) {
        if (abort != FC_REASON_NONE) {
            start_abort(lm, in, abort);
        } else if (contact_seen(lm, in, &natural)) {
            enter(lm, FC_LANDING_TOUCHDOWN, FC_REASON_CONTACT);
        } else {
            /* descending on */
        }
    } else if (abort == FC_REASON_ABORT_COMMANDED) {
        start_abort(lm, in, abort);
    } else if (contact_lost(lm, in, &natural)) {
        enter(lm, FC_LANDING_DESCEND, FC_REASON_CONTACT_LOST);
    } else if (in->range_fresh && !contact_seen(lm, in, &natural)) {
        /* not clearly off, not clearly on: the confirmation starts again */
        lm->state_time_s = FC_INT(0, TIME);
    } else if (lm->state_time_s >= lm->p.contact_confirm_s) {
        lm->touchdown_thrust_n =
            fc_is_finite(in->thrust_n) ? fc_max(in->thrust_n, FC_INT(0, FORCE)) : FC_INT(0, FORCE);
        enter(lm, FC_LANDING_DISARM, FC_REASON_CONTACT_CONFIRMED);
    } else {
        /* confirming */
    }
    return status;
}

/* DISARM: T = T_contact (1 - t / ramp), then LANDED with the motors off. */
static void disarm_step(fc_landing *lm, fc_landing_output *out)
{
    fc_arith *ar = &lm->ar;
    const fc_real elapsed =
        fc_min(fc_mul(ar, lm->state_time_s, lm->inv_ramp_per_s, FC_SHIFT(TIME, GAIN, UNIT)), FC_INT(1, UNIT));
    out->ramp_thrust_n =
        fc_mul(ar, lm->touchdown_thrust_n, fc_sub(ar, FC_INT(1, UNIT), elapsed), FC_SHIFT(FORCE, UNIT, FORCE));
    out->motors_on = elapsed < FC_INT(1, UNIT);
    if (!out->motors_on) {
        enter(lm, FC_LANDING_LANDED, FC_REASON_RAMP_DONE);
    }
}

/* The request: none ends the mission (IDLE); any other starts it from IDLE. */
static void follow_request(fc_landing *lm, const fc_landing_input *in)
{
    if (in->request == FC_LANDING_REQUEST_NONE) {
        if (lm->state != FC_LANDING_IDLE) {
            fc_landing_reset(lm);
        }
    } else if (lm->state == FC_LANDING_IDLE) {
        lm->aborts = 0u;
        start_hold(lm, in);
        enter(lm, FC_LANDING_HOLD, FC_REASON_COMMANDED);
    } else {
        /* the mission goes on */
    }
}

bool fc_landing_reads_horizontal_error(const fc_landing *lm)
{
    /* descent_blocked (OBSERVE) and descent_abort_reason (DESCEND, TOUCHDOWN)
     * are its only readers; a step's request moves the state only to HOLD or
     * IDLE before them, and neither reads it */
    const fc_landing_state s = lm->state;
    return s == FC_LANDING_OBSERVE || s == FC_LANDING_DESCEND || s == FC_LANDING_TOUCHDOWN;
}

fc_step_status fc_landing_step(fc_landing *lm, const fc_landing_input *in, fc_landing_output *out)
{
    *out = (fc_landing_output){0};
    out->state = lm->state;
    out->reason = lm->reason;
    if (!lm->ready) {
        out->state = FC_LANDING_IDLE;
        return FC_STEP_NOT_READY;
    }
    fc_arith *ar = &lm->ar;
    ar->saturated = 0u;
    fc_step_status status = FC_STEP_OK;
    const fc_landing_state before = lm->state;
    lm->state_time_s = fc_min(fc_add_inline(ar, lm->state_time_s, lm->step_s), FC_INT(600, TIME));
    lm->since_range_s =
        in->range_fresh ? FC_INT(0, TIME) : fc_min(fc_add_inline(ar, lm->since_range_s, lm->step_s), FC_INT(60, TIME));
    follow_request(lm, in);

    switch (lm->state) {
    case FC_LANDING_HOLD:
    case FC_LANDING_OBSERVE:
    case FC_LANDING_ABORT:
        status |= hold_states_step(lm, in, out);
        break;
    case FC_LANDING_DESCEND:
    case FC_LANDING_TOUCHDOWN:
        status |= descent_states_step(lm, in, out);
        break;
    case FC_LANDING_DISARM:
        disarm_step(lm, out);
        break;
    case FC_LANDING_FAILSAFE:
        out->motors_on = true; /* what flies is the controller's failsafe */
        break;
    case FC_LANDING_IDLE:
    case FC_LANDING_LANDED:
    case FC_LANDING_STATE_COUNT:
    default:
        break;
    }
    if (lm->state == FC_LANDING_TOUCHDOWN || lm->state == FC_LANDING_DISARM || lm->state == FC_LANDING_LANDED) {
        out->touchdown_window = true; /* touchdown declared: the window stays open to the end */
    }
    out->state = lm->state;
    out->reason = lm->reason;
    out->changed = lm->state != before;
    out->aborts = lm->aborts;
    if (ar->saturated != 0u) {
        status |= FC_STEP_ARITH_SATURATED;
    }
    return status;
}
