/* position_control.c - horizontal PID and acceleration control (fc/position_control.h). */
#include "fc/position_control.h"

#define GRAVITY_MPS2 FC_C(9.80665f, ACCEL)
/* The per-axis parts of the law, inlined where they are used (two or three
 * times a step): on the ATmega a call of their five 32-bit arguments and its
 * register saves cost more than the copies. */
#define AXIS_INLINE static inline __attribute__((always_inline))

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
    pc->kp = fc_gain_of(p->kp_per_s2, FC_RATIO_FRAC);
    pc->kd = fc_gain_of(p->kd_per_s, FC_RATIO_FRAC);
    pc->ki_dt = fc_gain_of_product(p->ki_per_s3, FC_RATIO_FRAC, p->dt_s, FC_DT_FRAC);
    pc->fb_dt = fc_gain_of_product(p->accel_fb_gain_per_s, FC_RATIO_FRAC, p->dt_s, FC_DT_FRAC);
    pc->mass = fc_gain_of(p->mass_kg, FC_MASS_FRAC);
    /* tan(tilt_max) once (cos(1.4) = 0.17, so tan <= 5.8) */
    fc_real sin_tilt, cos_tilt;
    fc_sincos(ar, p->tilt_max_rad, &sin_tilt, &cos_tilt);
    pc->tan_tilt_max = fc_gain_of(fc_div(ar, sin_tilt, cos_tilt, FC_DIV_SHIFT(UNIT, UNIT, RATIO)), FC_RATIO_FRAC);
    if (ar->saturated != 0u) {
        return FC_INIT_BAD_PARAM;
    }
    pc->ready = true;
    return FC_INIT_OK;
}

/* (x, y) scaled to length limit if it is longer, its direction kept (the
 * saturations of 2.6.4); true when that changed it. Inside by the 1-norm (the
 * common case) it takes no product; else fc_vec3_clamp_norm_report on (x, y, 0). */
static bool clamp_norm2(fc_arith *ar, fc_real *x, fc_real *y, fc_real limit, int frac)
{
    if (fc_norm1_within(*x, *y, FC_INT(0, UNIT), limit)) {
        return false;
    }
    bool clamped = false;
    const fc_vec3 v = fc_vec3_clamp_norm_report(ar, fc_vec3_make(*x, *y, FC_INT(0, UNIT)), limit, frac, &clamped);
    *x = v.x;
    *y = v.y;
    return clamped;
}

/* One axis of the horizontal PID (2.6.4): k_P e + k_D e_v + I + a_ff. */
AXIS_INLINE fc_real pid_axis(fc_arith *ar, const fc_position_control *pc, fc_real e_m, fc_real ev_mps,
                             fc_real integral_mps2, fc_real ff_mps2)
{
    const fc_real a_p = fc_mul_gain(ar, e_m, pc->kp, FC_GAIN_SHIFT(LENGTH, ACCEL));
    const fc_real a_d = fc_mul_gain(ar, ev_mps, pc->kd, FC_GAIN_SHIFT(VEL, ACCEL));
    return fc_add_inline(ar, fc_add_inline(ar, fc_add_inline(ar, a_p, a_d), integral_mps2), ff_mps2);
}

/* v / 2 in UNIT16 from the UNIT16 v (the format one FRAC up, rounded);
 * float: v itself. A quaternion is formed from these throughout and then
 * normalised, so its scale, 1/2 in fixed and 1 in float, is free. */
static fc_real16 half16(fc_arith *ar, fc_real v)
{
    return fc_narrow16(ar, v, FC_UNIT16_FRAC + 1, FC_UNIT16_FRAC);
}

/* The attitude setpoint from the thrust direction and the heading (header):
 * q_tilt and q_yaw in UNIT16 at half scale, both with w >= 0 and so their
 * product too (no sign flip after), the product exact in UNIT16_SQ and
 * normalised by one reciprocal root in 32 bits. */
static fc_quat attitude_setpoint(fc_arith *ar, fc_vec3_16 b3, fc_real16 c, fc_real16 s)
{
    const fc_real one = FC_INT(1, UNIT16);
    const fc_real16 tilt_w = half16(ar, one + b3.z), tilt_x = half16(ar, -b3.y), tilt_y = half16(ar, b3.x);
    fc_real16 yaw_w, yaw_z;
    if (c >= FC_INT16(0, UNIT16)) {
        yaw_w = half16(ar, one + c);
        yaw_z = half16(ar, s);
    } else if (s >= FC_INT16(0, UNIT16)) {
        yaw_w = half16(ar, s);
        yaw_z = half16(ar, one - c);
    } else {
        /* the left half plane's form negated: w = -sin psi > 0 */
        yaw_w = half16(ar, -s);
        yaw_z = half16(ar, c - one);
    }
    /* q_tilt (x) q_yaw, (2.8) with the zero components of q_tilt (z) and
     * q_yaw (x, y) left out: 6 products instead of 16 */
    const fc_real q_w = fc_mul16(tilt_w, yaw_w);
    const fc_real q_x = fc_dot2_16(tilt_x, yaw_w, tilt_y, yaw_z);
    const fc_real q_y = fc_dot2_16(fc_neg16(tilt_x), yaw_z, tilt_y, yaw_w);
    const fc_real q_z = fc_mul16(tilt_w, yaw_z);
    /* |q|^2 = |q_tilt|^2 |q_yaw|^2 (the norm of a product of quaternions),
     * the squares of the 16-bit factors exact in UNIT16_SQ: at half scale
     * |q_tilt|^2 >= 0.5 (b3_z >= 0) and |q_yaw|^2 >= 0.3 (|(c, s)|^2 >=
     * 0.25), so |q|^2 lies in [0.15, 2.5] */
    const fc_real tilt_sq = fc_mul16(tilt_w, tilt_w) + fc_dot2_16(tilt_x, tilt_x, tilt_y, tilt_y);
    const fc_real yaw_sq = fc_dot2_16(yaw_w, yaw_w, yaw_z, yaw_z);
    const fc_real norm_sq = fc_mul(ar, tilt_sq, yaw_sq, FC_SHIFT(UNIT16_SQ, UNIT16_SQ, UNIT16_SQ));
    /* fixed: 1 / (2 |q|), within UNIT's range where 1 / |q| (up to 2.6) is
     * not: the reciprocal root of 4 |q|^2, which is |q|^2 read with two
     * fraction bits fewer, and the products' shift one less doubles it
     * back. Float: 1 / |q| and plain products. */
    const fc_real half_inv_norm = fc_rsqrt(ar, norm_sq, FC_UNIT16_SQ_FRAC - 2, FC_UNIT_FRAC);
    const int to_unit = FC_SHIFT(UNIT16_SQ, UNIT, UNIT) - 1;
    return fc_quat_make(fc_mul(ar, q_w, half_inv_norm, to_unit), fc_mul(ar, q_x, half_inv_norm, to_unit),
                        fc_mul(ar, q_y, half_inv_norm, to_unit), fc_mul(ar, q_z, half_inv_norm, to_unit));
}

/* e . a_h,unsat < 0: the error drives the output back out of its limit. */
static bool unwinding(fc_real ex_m, fc_real ey_m, fc_real ax_mps2, fc_real ay_mps2)
{
    fc_arith scratch = {0u};
    return fc_dot2(&scratch, ex_m, ax_mps2, ey_m, ay_mps2, FC_SHIFT(LENGTH, ACCEL, LENGTH)) < FC_INT(0, LENGTH);
}

/* I_a += k_a dt (a_meas - a_des) on one axis (Figure 2.8): the increment of
 * a zero error is zero, and takes no product (the vertical axis in the
 * controller's use, where a_ff,z and the measured a_z are both 0). */
AXIS_INLINE fc_real feedback_axis(fc_arith *ar, fc_real fb_mps2, fc_real meas_mps2, fc_real des_mps2, fc_gain fb_dt)
{
    const fc_real err_mps2 = fc_sub_inline(ar, meas_mps2, des_mps2);
    if (err_mps2 == FC_INT(0, ACCEL)) {
        return fb_mps2;
    }
    return fc_add_inline(ar, fb_mps2, fc_mul_gain(ar, err_mps2, fb_dt, FC_GAIN_SHIFT(ACCEL, ACCEL)));
}

fc_step_status fc_position_control_demand(fc_position_control *pc, const fc_position_control_input *in,
                                          fc_position_control_output *out)
{
    if (!pc->ready) {
        out->accel_des_mps2 = fc_vec3_zero();
        out->thrust_world_n = fc_vec3_zero();
        return FC_STEP_NOT_READY;
    }
    fc_arith *ar = &pc->ar;
    ar->saturated = 0u;
    const fc_position_control_params *p = &pc->p;
    fc_step_status status = FC_STEP_OK;

    /* inputs: the horizontal errors (zero when an input is not finite), the
     * feedforward */
    const bool integrate = fc_vec3_is_finite(*in->position_m) && fc_vec3_is_finite(*in->velocity_mps) &&
                           fc_vec3_is_finite(*in->position_sp_m) && fc_vec3_is_finite(*in->velocity_sp_mps);
    fc_real ex_m = FC_INT(0, LENGTH), ey_m = FC_INT(0, LENGTH);
    fc_real evx_mps = FC_INT(0, VEL), evy_mps = FC_INT(0, VEL);
    if (integrate) {
        ex_m = fc_sub_inline(ar, in->position_sp_m->x, in->position_m->x);
        ey_m = fc_sub_inline(ar, in->position_sp_m->y, in->position_m->y);
        evx_mps = fc_sub_inline(ar, in->velocity_sp_mps->x, in->velocity_mps->x);
        evy_mps = fc_sub_inline(ar, in->velocity_sp_mps->y, in->velocity_mps->y);
    } else {
        status |= FC_STEP_BAD_INPUT;
    }
    fc_vec3 ff = *in->accel_ff_mps2;
    if (!fc_vec3_is_finite(ff)) {
        ff = fc_vec3_zero();
        status |= FC_STEP_BAD_INPUT;
    }
    const bool meas_ok = fc_vec3_is_finite(*in->accel_meas_mps2);
    if (!meas_ok) {
        status |= FC_STEP_BAD_INPUT;
    }
    /* 2.6.4: the error vector saturated by its length, its direction kept */
    (void)clamp_norm2(ar, &ex_m, &ey_m, p->error_max_m, FC_FRAC(LENGTH));
    /* PID: k_P e + k_D e_v + I + a_ff,h, then |a_h| <= accel_max */
    const fc_real ax_unsat = pid_axis(ar, pc, ex_m, evx_mps, pc->integral_mps2.x, ff.x);
    const fc_real ay_unsat = pid_axis(ar, pc, ey_m, evy_mps, pc->integral_mps2.y, ff.y);
    fc_real ax_mps2 = ax_unsat, ay_mps2 = ay_unsat;
    bool limited = clamp_norm2(ar, &ax_mps2, &ay_mps2, p->accel_max_mps2, FC_FRAC(ACCEL));

    /* (2.11) with the acceleration feedback: F = m (a_des - g - I_a), g = (0, 0, -g0) */
    const fc_vec3 *fb = &pc->accel_fb_mps2;
    const int to_force = FC_GAIN_SHIFT(ACCEL, FORCE);
    fc_vec3 force = fc_vec3_make(fc_mul_gain(ar, fc_sub_inline(ar, ax_mps2, fb->x), pc->mass, to_force),
                                 fc_mul_gain(ar, fc_sub_inline(ar, ay_mps2, fb->y), pc->mass, to_force),
                                 fc_mul_gain(ar, fc_sub_inline(ar, fc_add_inline(ar, ff.z, GRAVITY_MPS2), fb->z), pc->mass, to_force));
    /* limits: vertical floor, tilt (horizontal part, direction kept), collective */
    bool thrust_limited = false;
    if (force.z < p->thrust_min_n) {
        force.z = p->thrust_min_n;
        thrust_limited = true;
    }
    /* beyond the FORCE range (F_z tan > 2048 N) it saturates to "no tilt limit",
     * and the collective limit below still holds: a scratch record */
    fc_arith scratch_h = {0u};
    const fc_real force_h_max = fc_mul_gain(&scratch_h, force.z, pc->tan_tilt_max, FC_GAIN_SHIFT(FORCE, FORCE));
    if (clamp_norm2(ar, &force.x, &force.y, force_h_max, FC_FRAC(FORCE))) {
        limited = true;
    }
    if (!fc_norm1_within(force.x, force.y, force.z, p->thrust_max_n)) {
        bool collective_limited = false;
        force = fc_vec3_clamp_norm_report(ar, force, p->thrust_max_n, FC_FRAC(FORCE), &collective_limited);
        if (collective_limited) {
            thrust_limited = true;
            limited = true;
        }
    }
    if (limited || thrust_limited) {
        status |= FC_STEP_OUTPUT_LIMITED;
    }

    out->thrust_world_n = force;
    out->accel_des_mps2 = fc_vec3_make(ax_mps2, ay_mps2, ff.z);

    /* integrator with conditional integration (anti-windup): while limited
     * only if the error drives the output back (e . a_h,unsat < 0) */
    if (integrate && (!limited || unwinding(ex_m, ey_m, ax_unsat, ay_unsat))) {
        const int to_accel = FC_GAIN_SHIFT(LENGTH, ACCEL);
        fc_real ix_mps2 = fc_add_inline(ar, pc->integral_mps2.x, fc_mul_gain(ar, ex_m, pc->ki_dt, to_accel));
        fc_real iy_mps2 = fc_add_inline(ar, pc->integral_mps2.y, fc_mul_gain(ar, ey_m, pc->ki_dt, to_accel));
        (void)clamp_norm2(ar, &ix_mps2, &iy_mps2, p->integral_max_mps2, FC_FRAC(ACCEL));
        pc->integral_mps2.x = ix_mps2;
        pc->integral_mps2.y = iy_mps2;
    }
    /* acceleration feedback (Figure 2.8), frozen while the thrust is limited */
    if (meas_ok && in->accel_meas_ok && !thrust_limited) {
        const fc_vec3 *meas = in->accel_meas_mps2;
        fc_vec3 i_a = fc_vec3_make(feedback_axis(ar, fb->x, meas->x, ax_mps2, pc->fb_dt),
                                   feedback_axis(ar, fb->y, meas->y, ay_mps2, pc->fb_dt),
                                   feedback_axis(ar, fb->z, meas->z, ff.z, pc->fb_dt));
        if (!fc_norm1_within(i_a.x, i_a.y, i_a.z, p->accel_fb_max_mps2)) {
            i_a = fc_vec3_clamp_norm(ar, i_a, p->accel_fb_max_mps2, FC_FRAC(ACCEL));
        }
        pc->accel_fb_mps2 = i_a;
    }
    if (ar->saturated != 0u) {
        status |= FC_STEP_ARITH_SATURATED;
    }
    return status;
}

fc_step_status fc_position_control_attitude(fc_position_control *pc, fc_real heading_cos, fc_real heading_sin,
                                            fc_position_control_output *out)
{
    if (!pc->ready) {
        out->attitude_sp = fc_quat_identity();
        out->thrust_n = FC_INT(0, FORCE);
        return FC_STEP_NOT_READY;
    }
    fc_arith *ar = &pc->ar;
    ar->saturated = 0u;
    fc_step_status status = FC_STEP_OK;
    fc_real16 hc, hs;
    {
        /* |(c, s)|^2 in [0.25, 1.5], of the UNIT16 values (exact products;
         * float: a NaN or an infinity fails the comparisons) */
        fc_arith scratch = {0u};
        hc = fc_narrow16(&scratch, heading_cos, FC_UNIT_FRAC, FC_UNIT16_FRAC);
        hs = fc_narrow16(&scratch, heading_sin, FC_UNIT_FRAC, FC_UNIT16_FRAC);
        const fc_real n2 = fc_dot2_16(hc, hc, hs, hs);
        if (scratch.saturated != 0u || !(n2 >= FC_C(0.25f, UNIT16_SQ)) || !(n2 <= FC_C(1.5f, UNIT16_SQ))) {
            hc = FC_INT16(1, UNIT16);
            hs = FC_INT16(0, UNIT16);
            status |= FC_STEP_BAD_INPUT;
        }
    }

    /* attitude setpoint and collective thrust along body z: the direction
     * in UNIT16 and the length in one (force.z >= thrust_min > 0) */
    fc_vec3_16 b3;
    fc_real force_norm_n;
    (void)fc_vec3_direction16(ar, out->thrust_world_n, &b3, &force_norm_n);
    out->attitude_sp = attitude_setpoint(ar, b3, hc, hs);
    out->thrust_n = fc_min(force_norm_n, pc->p.thrust_max_n);

    if (ar->saturated != 0u) {
        status |= FC_STEP_ARITH_SATURATED;
    }
    return status;
}

fc_step_status fc_position_control_step(fc_position_control *pc, const fc_position_control_input *in,
                                        fc_real heading_cos, fc_real heading_sin, fc_position_control_output *out)
{
    /* each half gives its safe output when not ready */
    const fc_step_status status = fc_position_control_demand(pc, in, out);
    return status | fc_position_control_attitude(pc, heading_cos, heading_sin, out);
}
