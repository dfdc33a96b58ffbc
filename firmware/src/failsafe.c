/* failsafe.c - the input guard and the failsafe descent (fc/failsafe.h). */
#include "fc/failsafe.h"

void fc_failsafe_default_params(fc_failsafe_params *p, fc_real dt_s, fc_real gravity_mps2, fc_real descent_mps)
{
    p->dt_s = dt_s;
    p->gravity_mps2 = gravity_mps2;
    p->bad_input_hold_s = FC_C(0.5f, TIME);
    p->imu_timeout_s = FC_C(0.05f, TIME);
    p->descent_mps = descent_mps;
    p->speed_gain_per_s = FC_INT(2, GAIN);
    p->integral_limit_mps2 = FC_INT(3, ACCEL);
    p->accel_limit_mps2 = FC_INT(4, ACCEL);
    p->setpoint_accel_mps2 = FC_INT(1, ACCEL);
    p->ramp_s = FC_INT(1, TIME);
}

static bool failsafe_params_valid(const fc_failsafe_params *p)
{
    const bool finite = fc_is_finite(p->dt_s) && fc_is_finite(p->gravity_mps2) && fc_is_finite(p->bad_input_hold_s) &&
                        fc_is_finite(p->imu_timeout_s) && fc_is_finite(p->descent_mps) &&
                        fc_is_finite(p->speed_gain_per_s) && fc_is_finite(p->integral_limit_mps2) &&
                        fc_is_finite(p->accel_limit_mps2) && fc_is_finite(p->ramp_s) &&
                        fc_is_finite(p->setpoint_accel_mps2);
    const fc_real ten_s = FC_INT(10, TIME);
    return finite && p->dt_s > FC_INT(0, DT) && p->dt_s <= FC_C(0.1f, DT) && p->gravity_mps2 > FC_INT(0, ACCEL) &&
           p->gravity_mps2 <= FC_INT(100, ACCEL) && fc_in_range(p->bad_input_hold_s, FC_INT(0, TIME), ten_s) &&
           fc_in_range(p->imu_timeout_s, FC_INT(0, TIME), ten_s) && p->descent_mps > FC_INT(0, VEL) &&
           p->descent_mps <= FC_INT(5, VEL) && p->speed_gain_per_s > FC_INT(0, GAIN) &&
           p->speed_gain_per_s <= FC_INT(50, GAIN) && p->integral_limit_mps2 > FC_INT(0, ACCEL) &&
           p->integral_limit_mps2 <= FC_INT(10, ACCEL) && p->accel_limit_mps2 > FC_INT(0, ACCEL) &&
           p->accel_limit_mps2 <= FC_INT(10, ACCEL) && p->ramp_s > FC_INT(0, TIME) && p->ramp_s <= ten_s &&
           p->setpoint_accel_mps2 > FC_INT(0, ACCEL) && p->setpoint_accel_mps2 <= FC_INT(10, ACCEL);
}

fc_init_result fc_failsafe_init(fc_failsafe *f, const fc_failsafe_params *p)
{
    f->ready = false;
    f->ar.saturated = 0u;
    fc_failsafe_reset(f);
    if (!failsafe_params_valid(p)) {
        return FC_INIT_BAD_PARAM;
    }
    f->p = *p;
    fc_arith *ar = &f->ar;
    /* k_i dt = (k_p^2 / 4) dt, per step */
    const fc_real kp_dt = fc_mul(ar, p->speed_gain_per_s, p->dt_s, FC_SHIFT(GAIN, DT, RATIO));
    const fc_real kp_quarter = fc_mul(ar, p->speed_gain_per_s, FC_C(0.25f, UNIT), FC_SHIFT(GAIN, UNIT, RATIO));
    f->speed_integral_gain = fc_mul(ar, kp_dt, kp_quarter, FC_SHIFT(RATIO, RATIO, RATIO));
    f->setpoint_step_mps = fc_mul(ar, p->setpoint_accel_mps2, p->dt_s, FC_SHIFT(ACCEL, DT, VEL));
    f->inv_dt_per_s = fc_div(ar, FC_INT(1, DT), p->dt_s, FC_DIV_SHIFT(DT, DT, GAIN));
    f->inv_gravity_s2pm = fc_div(ar, FC_INT(1, ACCEL), p->gravity_mps2, FC_DIV_SHIFT(ACCEL, ACCEL, RATIO));
    f->ramp_gain = fc_div(ar, p->dt_s, p->ramp_s, FC_DIV_SHIFT(DT, TIME, UNIT));
    f->step_s = fc_convert(ar, p->dt_s, FC_DT_FRAC, FC_TIME_FRAC);
    f->ready = f->ar.saturated == 0u;
    return f->ready ? FC_INIT_OK : FC_INIT_BAD_PARAM;
}

static void clear_loop(fc_failsafe *f)
{
    f->setpoint_started = false;
    f->integral_mps2 = FC_INT(0, ACCEL);
    f->ramp_thrust_n = FC_INT(0, FORCE);
    f->ramping = false;
}

void fc_failsafe_reset(fc_failsafe *f)
{
    f->bad_input_s = FC_INT(0, TIME);
    f->good_input_s = FC_INT(0, TIME);
    f->imu_bad_s = FC_INT(0, TIME);
    f->active = false;
    f->cause = FC_FAILSAFE_NONE;
    clear_loop(f);
}

/* t + dt while the condition holds, 0 when it does not (bounded). */
static fc_real failsafe_timer(fc_failsafe *f, fc_real timer_s, bool condition)
{
    return condition ? fc_min(fc_add_inline(&f->ar, timer_s, f->step_s), FC_INT(600, TIME)) : FC_INT(0, TIME);
}

fc_failsafe_watch_output fc_failsafe_watch(fc_failsafe *f, const fc_failsafe_watch_input *in)
{
    fc_failsafe_watch_output out = {false, false, false, false, FC_FAILSAFE_NONE};
    if (!f->ready || !in->armed) {
        fc_failsafe_reset(f);
        return out;
    }
    f->bad_input_s = failsafe_timer(f, f->bad_input_s, !in->inputs_ok);
    f->imu_bad_s = failsafe_timer(f, f->imu_bad_s, !in->imu_ok);
    if (f->active) {
        f->good_input_s = failsafe_timer(f, f->good_input_s, in->inputs_ok && in->imu_ok);
        if (f->good_input_s > f->p.bad_input_hold_s) {
            f->active = false;
            f->cause = FC_FAILSAFE_NONE;
            out.left = true;
        }
    } else {
        const bool imu_lost = f->imu_bad_s > f->p.imu_timeout_s;
        const bool inputs_lost = !in->inputs_ok && (f->bad_input_s > f->p.bad_input_hold_s || !in->had_good_inputs);
        if (imu_lost || inputs_lost) {
            f->active = true;
            f->cause = imu_lost ? FC_FAILSAFE_IMU_LOST : FC_FAILSAFE_INPUTS_LOST;
            f->good_input_s = FC_INT(0, TIME);
            clear_loop(f);
            out.entered = true;
        }
    }
    out.active = f->active;
    out.hold = !in->inputs_ok && in->had_good_inputs && !f->active;
    out.cause = f->cause;
    return out;
}

fc_real fc_failsafe_step(fc_failsafe *f, const fc_failsafe_input *in)
{
    if (!f->ready) {
        return FC_INT(0, FORCE);
    }
    fc_arith *ar = &f->ar;
    ar->saturated = 0u;
    /* the speed setpoint: from the speed at the start to -descent at setpoint_accel */
    if (!f->setpoint_started) {
        f->speed_setpoint_mps = in->vz_mps;
        f->setpoint_started = true;
    }
    const fc_real descent = fc_neg(ar, f->p.descent_mps);
    const fc_real setpoint_change = fc_clamp(fc_sub(ar, descent, f->speed_setpoint_mps),
                                             fc_neg(ar, f->setpoint_step_mps), f->setpoint_step_mps);
    f->speed_setpoint_mps = fc_add(ar, f->speed_setpoint_mps, setpoint_change);
    /* v_sp' fed forward: the ramp is followed without the integral */
    const fc_real setpoint_accel = fc_mul(ar, setpoint_change, f->inv_dt_per_s, FC_SHIFT(VEL, GAIN, ACCEL));
    const fc_real speed_error = fc_sub(ar, f->speed_setpoint_mps, in->vz_mps);
    const bool airborne = in->land_state == FC_LAND_AIRBORNE;
    if (airborne) {
        f->ramping = false;
        f->integral_mps2 = fc_clamp(
            fc_add(ar, f->integral_mps2, fc_mul(ar, f->speed_integral_gain, speed_error, FC_SHIFT(RATIO, VEL, ACCEL))),
            fc_neg(ar, f->p.integral_limit_mps2), f->p.integral_limit_mps2);
    }
    const fc_real proportional = fc_mul(ar, f->p.speed_gain_per_s, speed_error, FC_SHIFT(GAIN, VEL, ACCEL));
    const fc_real accel = fc_clamp(fc_add(ar, fc_add(ar, proportional, f->integral_mps2), setpoint_accel),
                                   fc_neg(ar, f->p.accel_limit_mps2), f->p.accel_limit_mps2);
    /* T k_h = T_h (1 + a / g) */
    const fc_real load_factor = fc_add(ar, FC_INT(1, RATIO), fc_mul(ar, accel, f->inv_gravity_s2pm, FC_SHIFT(ACCEL, RATIO, RATIO)));
    fc_real vertical_n = fc_mul(ar, in->hover_thrust_n, load_factor, FC_SHIFT(FORCE, RATIO, FORCE));
    if (!airborne) {
        /* in contact: the thrust ramps down from where it was (or the hover thrust) */
        if (!f->ramping) {
            f->ramping = true;
            f->ramp_thrust_n = fc_min(vertical_n, in->hover_thrust_n);
        }
        const fc_real ramp_step_n = fc_mul(ar, in->hover_thrust_n, f->ramp_gain, FC_SHIFT(FORCE, UNIT, FORCE));
        f->ramp_thrust_n = fc_max(fc_sub(ar, f->ramp_thrust_n, ramp_step_n), FC_INT(0, FORCE));
        vertical_n = fc_min(vertical_n, f->ramp_thrust_n);
    }
    const fc_real k_h = fc_max(in->tilt_cos, FC_C(0.5f, RATIO));
    const fc_real thrust_n = fc_div(ar, vertical_n, k_h, FC_DIV_SHIFT(FORCE, RATIO, FORCE));
    return fc_clamp(thrust_n, in->thrust_min_n, in->thrust_max_n);
}
