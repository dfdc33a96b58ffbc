/* position_control.c - horizontal PID and acceleration control (fc/position_control.h). */
#include "fc/position_control.h"

#define GRAVITY_MPS2 FC_C(9.80665f, ACCEL)
#define UNIT_X_UNIT FC_SHIFT(UNIT, UNIT, UNIT)

static bool position_params_valid(const fc_position_control_params *p)
{
    return fc_in_range(p->dt_s, FC_C(1.0e-5f, DT), FC_C(0.1f, DT)) &&
           fc_in_range(p->kp_per_s2, FC_INT(0, RATIO), FC_INT(100, RATIO)) &&
           fc_in_range(p->ki_per_s3, FC_INT(0, RATIO), FC_INT(100, RATIO)) &&
           fc_in_range(p->kd_per_s, FC_INT(0, RATIO), FC_INT(100, RATIO)) &&
           fc_in_range(p->error_max_m, FC_C(0.001f, LENGTH), FC_INT(100, LENGTH)) &&
           fc_in_range(p->integral_max_mps2, FC_INT(0, ACCEL), FC_INT(50, ACCEL)) &&
           fc_in_range(p->accel_max_mps2, FC_C(0.001f, ACCEL), FC_INT(50, ACCEL)) &&
           fc_in_range(p->mass_kg, FC_C(0.001f, MASS), FC_INT(100, MASS)) &&
           fc_in_range(p->accel_fb_gain_per_s, FC_INT(0, RATIO), FC_INT(10, RATIO)) &&
           fc_in_range(p->accel_fb_max_mps2, FC_INT(0, ACCEL), FC_INT(20, ACCEL)) &&
           fc_in_range(p->tilt_max_rad, FC_C(0.01f, ANGLE), FC_C(1.4f, ANGLE)) &&
           fc_in_range(p->thrust_min_n, FC_C(0.001f, FORCE), FC_INT(1000, FORCE)) &&
           fc_in_range(p->thrust_max_n, FC_C(0.001f, FORCE), FC_INT(1000, FORCE)) &&
           p->thrust_max_n > p->thrust_min_n;
}

void fc_position_control_reset(fc_position_control *pc)
{
    pc->integral_mps2 = fc_vec3_zero();
    pc->accel_fb_mps2 = fc_vec3_zero();
}

fc_init_result fc_position_control_init(fc_position_control *pc, const fc_position_control_params *p)
{
    pc->ready = false;
    pc->ar.saturated = 0u;
    fc_position_control_reset(pc);
    if (!position_params_valid(p)) {
        return FC_INIT_BAD_PARAM;
    }
    fc_arith *ar = &pc->ar;
    pc->p = *p;
    pc->ki_dt = fc_mul(ar, p->ki_per_s3, p->dt_s, FC_SHIFT(RATIO, DT, RATIO));
    pc->fb_dt = fc_mul(ar, p->accel_fb_gain_per_s, p->dt_s, FC_SHIFT(RATIO, DT, RATIO));
    /* tan(tilt_max) once (cos(1.4) = 0.17, so tan <= 5.8) */
    fc_real sin_tilt, cos_tilt;
    fc_sincos(ar, p->tilt_max_rad, &sin_tilt, &cos_tilt);
    pc->tan_tilt_max = fc_div(ar, sin_tilt, cos_tilt, FC_DIV_SHIFT(UNIT, UNIT, RATIO));
    if (ar->saturated != 0u) {
        return FC_INIT_BAD_PARAM;
    }
    pc->ready = true;
    return FC_INIT_OK;
}

static fc_vec3 horizontal(fc_vec3 v)
{
    return fc_vec3_make(v.x, v.y, FC_INT(0, UNIT));
}

/* The horizontal position and velocity errors; zero, and false, when an input is not finite. */
static bool horizontal_errors(fc_arith *ar, const fc_position_control_input *in, fc_vec3 *e_m, fc_vec3 *ev_mps)
{
    if (!(fc_vec3_is_finite(in->position_m) && fc_vec3_is_finite(in->velocity_mps) &&
          fc_vec3_is_finite(in->position_sp_m) && fc_vec3_is_finite(in->velocity_sp_mps))) {
        *e_m = fc_vec3_zero();
        *ev_mps = fc_vec3_zero();
        return false;
    }
    *e_m = horizontal(fc_vec3_sub(ar, in->position_sp_m, in->position_m));
    *ev_mps = horizontal(fc_vec3_sub(ar, in->velocity_sp_mps, in->velocity_mps));
    return true;
}

/* (k v_x, k v_y, 0): the product of a horizontal vector (v_z = 0) and a gain. */
static fc_vec3 horizontal_scaled(fc_arith *ar, fc_vec3 v, fc_real k, int shift)
{
    return fc_vec3_make(fc_mul(ar, v.x, k, shift), fc_mul(ar, v.y, k, shift), FC_INT(0, UNIT));
}

/* v / 2 in UNIT16 from the UNIT16 v (the format one FRAC up, rounded);
 * float: v itself. A quaternion is formed from these throughout and then
 * normalised, so its scale, 1/2 in fixed and 1 in float, is free. */
static fc_real16 half16(fc_arith *ar, fc_real v)
{
    return fc_narrow16(ar, v, FC_UNIT16_FRAC + 1, FC_UNIT16_FRAC);
}

/* The attitude setpoint from the thrust direction and the heading (header):
 * q_tilt and q_yaw in UNIT16 at half scale, their product exact in UNIT16_SQ
 * (each component of either within 1), normalised in 32 bits. */
static fc_quat attitude_setpoint(fc_arith *ar, fc_vec3_16 b3, fc_real16 c, fc_real16 s)
{
    const fc_real one = FC_INT(1, UNIT16);
    const fc_real16 tilt_w = half16(ar, one + b3.z), tilt_x = half16(ar, -b3.y), tilt_y = half16(ar, b3.x);
    fc_real16 yaw_w, yaw_z;
    if (c >= FC_INT16(0, UNIT16)) {
        yaw_w = half16(ar, one + c);
        yaw_z = half16(ar, s);
    } else {
        yaw_w = half16(ar, s);
        yaw_z = half16(ar, one - c);
    }
    /* q_tilt (x) q_yaw, (2.8) with the zero components of q_tilt (z) and
     * q_yaw (x, y) left out: 6 products instead of 16 */
    const int sq = FC_UNIT16_SQ_FRAC;
    const fc_quat q_product = fc_quat_make(
        fc_convert(ar, fc_mul16(tilt_w, yaw_w), sq, FC_UNIT_FRAC),
        fc_convert(ar, fc_dot2_16(tilt_x, yaw_w, tilt_y, yaw_z), sq, FC_UNIT_FRAC),
        fc_convert(ar, fc_dot2_16(fc_neg16(tilt_x), yaw_z, tilt_y, yaw_w), sq, FC_UNIT_FRAC),
        fc_convert(ar, fc_mul16(tilt_w, yaw_z), sq, FC_UNIT_FRAC));
    /* at half scale |q_tilt| >= 0.7 (b3_z > 0), |q_yaw| >= 0.35: the product is well away from zero */
    bool ok = false;
    const fc_quat q = fc_quat_normalize(ar, q_product, &ok);
    return fc_quat_shortest(ar, q);
}

fc_step_status fc_position_control_step(fc_position_control *pc, const fc_position_control_input *in,
                                        fc_position_control_output *out)
{
    out->accel_des_mps2 = fc_vec3_zero();
    out->thrust_world_n = fc_vec3_zero();
    out->attitude_sp = fc_quat_identity();
    out->thrust_n = FC_INT(0, FORCE);
    if (!pc->ready) {
        return FC_STEP_NOT_READY;
    }
    fc_arith *ar = &pc->ar;
    ar->saturated = 0u;
    const fc_position_control_params *p = &pc->p;
    fc_step_status status = FC_STEP_OK;

    /* inputs */
    fc_vec3 e_m;
    fc_vec3 ev_mps;
    const bool integrate = horizontal_errors(ar, in, &e_m, &ev_mps);
    if (!integrate) {
        status |= FC_STEP_BAD_INPUT;
    }
    fc_vec3 ff = in->accel_ff_mps2;
    if (!fc_vec3_is_finite(ff)) {
        ff = fc_vec3_zero();
        status |= FC_STEP_BAD_INPUT;
    }
    const bool meas_ok = fc_vec3_is_finite(in->accel_meas_mps2);
    if (!meas_ok) {
        status |= FC_STEP_BAD_INPUT;
    }
    fc_real hc = in->heading_cos;
    fc_real hs = in->heading_sin;
    {
        fc_arith scratch = {0u};
        const fc_real n2 = fc_dot2(&scratch, hc, hc, hs, hs, UNIT_X_UNIT);
        if (!fc_is_finite(hc) || !fc_is_finite(hs) || scratch.saturated != 0u || !(n2 >= FC_C(0.25f, UNIT)) ||
            !(n2 <= FC_C(1.5f, UNIT))) {
            hc = FC_INT(1, UNIT);
            hs = FC_INT(0, UNIT);
            status |= FC_STEP_BAD_INPUT;
        }
    }

    /* 2.6.4: the error vector saturated by its length, its direction kept */
    e_m = fc_vec3_clamp_norm(ar, e_m, p->error_max_m, FC_FRAC(LENGTH));
    /* PID: k_P e + k_D e_v + I + a_ff,h */
    const fc_vec3 a_p = horizontal_scaled(ar, e_m, p->kp_per_s2, FC_SHIFT(RATIO, LENGTH, ACCEL));
    const fc_vec3 a_d = horizontal_scaled(ar, ev_mps, p->kd_per_s, FC_SHIFT(RATIO, VEL, ACCEL));
    const fc_vec3 a_unsat =
        fc_vec3_add(ar, fc_vec3_add(ar, fc_vec3_add(ar, a_p, a_d), pc->integral_mps2), horizontal(ff));
    bool limited = false;
    const fc_vec3 a_h = fc_vec3_clamp_norm_report(ar, a_unsat, p->accel_max_mps2, FC_FRAC(ACCEL), &limited);
    const fc_vec3 a_des = fc_vec3_make(a_h.x, a_h.y, ff.z);

    /* (2.11) with the acceleration feedback: F = m (a_des - g - I_a), g = (0, 0, -g0) */
    const fc_vec3 a_req = fc_vec3_sub(ar, fc_vec3_make(a_des.x, a_des.y, fc_add(ar, a_des.z, GRAVITY_MPS2)),
                                      pc->accel_fb_mps2);
    fc_vec3 force = fc_vec3_scale(ar, a_req, p->mass_kg, FC_SHIFT(MASS, ACCEL, FORCE));
    /* limits: vertical floor, tilt (horizontal part, direction kept), collective */
    bool thrust_limited = false;
    if (force.z < p->thrust_min_n) {
        force.z = p->thrust_min_n;
        thrust_limited = true;
    }
    /* beyond the FORCE range (F_z tan > 2048 N) it saturates to "no tilt limit",
     * and the collective limit below still holds: a scratch record */
    fc_arith scratch_h = {0u};
    const fc_real force_h_max = fc_mul(&scratch_h, force.z, pc->tan_tilt_max, FC_SHIFT(FORCE, RATIO, FORCE));
    const fc_vec3 force_h = horizontal(force);
    bool tilt_limited = false;
    const fc_vec3 force_h_lim = fc_vec3_clamp_norm_report(ar, force_h, force_h_max, FC_FRAC(FORCE), &tilt_limited);
    if (tilt_limited) {
        limited = true;
        force.x = force_h_lim.x;
        force.y = force_h_lim.y;
    }
    bool collective_limited = false;
    const fc_vec3 force_lim = fc_vec3_clamp_norm_report(ar, force, p->thrust_max_n, FC_FRAC(FORCE), &collective_limited);
    if (collective_limited) {
        thrust_limited = true;
        limited = true;
        force = force_lim;
    }
    if (limited || thrust_limited) {
        status |= FC_STEP_OUTPUT_LIMITED;
    }

    /* attitude setpoint and collective thrust along body z: the direction
     * in UNIT16 and the length in one (force.z >= thrust_min > 0) */
    fc_vec3_16 b3;
    fc_real force_norm_n;
    (void)fc_vec3_direction16(ar, force, &b3, &force_norm_n);
    out->attitude_sp = attitude_setpoint(ar, b3, fc_narrow16(ar, hc, FC_UNIT_FRAC, FC_UNIT16_FRAC),
                                         fc_narrow16(ar, hs, FC_UNIT_FRAC, FC_UNIT16_FRAC));
    out->thrust_n = fc_min(force_norm_n, p->thrust_max_n);
    out->thrust_world_n = force;
    out->accel_des_mps2 = a_des;

    /* integrator with conditional integration (anti-windup) */
    if (integrate) {
        fc_arith scratch = {0u};
        const bool unwinding = fc_vec3_dot(&scratch, e_m, a_unsat, FC_SHIFT(LENGTH, ACCEL, LENGTH)) < FC_INT(0, LENGTH);
        if (!limited || unwinding) {
            const fc_vec3 inc = horizontal_scaled(ar, e_m, pc->ki_dt, FC_SHIFT(RATIO, LENGTH, ACCEL));
            pc->integral_mps2 =
                fc_vec3_clamp_norm(ar, fc_vec3_add(ar, pc->integral_mps2, inc), p->integral_max_mps2, FC_FRAC(ACCEL));
        }
    }
    /* acceleration feedback (Figure 2.8), frozen while the thrust is limited */
    if (meas_ok && in->accel_meas_ok && !thrust_limited) {
        const fc_vec3 a_err = fc_vec3_sub(ar, in->accel_meas_mps2, a_des);
        const fc_vec3 inc = fc_vec3_scale(ar, a_err, pc->fb_dt, FC_SHIFT(RATIO, ACCEL, ACCEL));
        pc->accel_fb_mps2 =
            fc_vec3_clamp_norm(ar, fc_vec3_add(ar, pc->accel_fb_mps2, inc), p->accel_fb_max_mps2, FC_FRAC(ACCEL));
    }
    if (ar->saturated != 0u) {
        status |= FC_STEP_ARITH_SATURATED;
    }
    return status;
}
