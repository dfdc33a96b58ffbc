/*
 * attitude_heading.c - the heading aid of the complementary attitude filter
 * (fc/attitude_estimator.h, "Heading"). One source for both backends.
 *
 * A source of its own: the aid is optional (a vehicle without a heading
 * sensor, like the ATmega's, never runs it).
 *
 * Formats (fixed backend): the sample's cos and sin, the measured heading in
 * the body m_b and s are UNIT (|.| <= 1); w_h and w_h s are RATIO.
 */
#include "attitude_heading.h"

#include <stddef.h>

#define UNIT_X_UNIT FC_SHIFT(UNIT, UNIT, UNIT)

bool fc_attitude_heading_params_ok(const fc_attitude_estimator_params *p, fc_real kp_radps, uint16_t *hold_steps)
{
    if (!fc_in_range(p->heading_weight, FC_INT(0, RATIO), FC_INT(1, RATIO)) ||
        !fc_in_range(p->heading_hold_s, p->dt_s, FC_INT(1, DT))) {
        return false;
    }
    /* hold / dt rounded to whole steps, by additions (the same count in both
     * backends): one more step while it brings steps x dt nearer to the hold */
    fc_arith ar = {0u};
    uint16_t steps = 1u;
    fc_real covered_s = p->dt_s;
    while (steps < UINT16_MAX && fc_sub(&ar, p->heading_hold_s, covered_s) >
                                     fc_sub(&ar, fc_add(&ar, covered_s, p->dt_s), p->heading_hold_s)) {
        covered_s = fc_add(&ar, covered_s, p->dt_s);
        steps++;
    }
    *hold_steps = steps;
    /* the integrated rate, gyro - b + Kp w e + Kp w_h e_h, stays inside RATE:
     * with a heading loop (w_h <= 1) bounded by gyro_range + bias_limit + 2 Kp */
    const fc_real rate_bound = fc_add(&ar, fc_add(&ar, p->gyro_range_radps, p->gyro_bias_limit_radps),
                                      fc_add(&ar, kp_radps, kp_radps));
    return p->heading_weight == FC_INT(0, RATIO) || rate_bound <= FC_C(127.0f, RATE);
}

fc_step_status fc_attitude_estimator_take_heading(fc_attitude_estimator *est, fc_real yaw_rad)
{
    if (est == NULL || !est->ready) {
        return FC_STEP_NOT_READY;
    }
    if (!fc_within(yaw_rad, FC_C(7.0f, ANGLE))) {
        return FC_STEP_BAD_INPUT;
    }
    /* |yaw| <= 7 rad: sin and cos cannot saturate (their own record) */
    fc_arith ar = {0u};
    fc_sincos(&ar, yaw_rad, &est->heading_sin, &est->heading_cos);
    est->heading_rad = yaw_rad;
    est->heading_steps_left = est->heading_hold_steps;
    return FC_STEP_OK;
}

/* s of the header, in the body: with m_b = R(q)^T (cos psi_m, sin psi_m, 0)
 * the measured heading seen in the body, s = (R e_x x m)_z
 * = (e_x x m_b) . v_hat = m_b.y v_hat.z - m_b.z v_hat.y; and h . m = m_b.x,
 * whose sign says whether the error is beyond 90 deg. */
static fc_real heading_error(fc_attitude_estimator *est, fc_vec3 up_estimated)
{
    fc_arith *ar = &est->ar;
    const fc_vec3 heading_world = fc_vec3_make(est->heading_cos, est->heading_sin, FC_INT(0, UNIT));
    const fc_vec3 heading_body = fc_quat_rotate_inv(ar, est->attitude, heading_world);
    const fc_real s = fc_dot2(ar, heading_body.y, up_estimated.z, fc_neg(ar, heading_body.z), up_estimated.y,
                              UNIT_X_UNIT);
    if (heading_body.x < FC_INT(0, UNIT)) {
        /* more than 90 deg off: the whole correction, towards the nearer side */
        return s < FC_INT(0, UNIT) ? FC_INT(-1, UNIT) : FC_INT(1, UNIT);
    }
    return s;
}

void fc_attitude_heading_correct(fc_attitude_estimator *est, fc_vec3 *rate_radps)
{
    fc_arith *ar = &est->ar;
    /* v_hat = R(q)^T e_z */
    const fc_vec3 up_world = fc_vec3_make(FC_INT(0, UNIT), FC_INT(0, UNIT), FC_INT(1, UNIT));
    const fc_vec3 up_estimated = fc_quat_rotate_inv(ar, est->attitude, up_world);
    /* w_h e_h = (w_h s) v_hat, |w_h s| <= 1 */
    const fc_real weight = fc_mul(ar, heading_error(est, up_estimated), est->p.heading_weight,
                                  FC_SHIFT(UNIT, RATIO, UNIT));
    /* Kp w_h e_h <= 20 rad/s (the init's rate bound); |b| <= 0.8 and Ki dt <= 1
     * keep the bias step in UNIT */
    const fc_vec3 we = fc_vec3_scale(ar, up_estimated, weight, UNIT_X_UNIT);
    fc_attitude_correct_by(est, rate_radps, fc_vec3_narrow16(ar, we, FC_UNIT_FRAC, FC_UNIT16_FRAC));
}
