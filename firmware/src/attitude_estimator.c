/*
 * attitude_estimator.c - complementary attitude filter (fc/attitude_estimator.h).
 * One source for both backends.
 *
 * The dissertation (§2.5) names the design: gyro integration corrected by the
 * accelerometer's vertical, with the gyro bias estimated and less trust in the
 * accelerometer while the vehicle accelerates. The correction is the explicit
 * complementary filter with bias correction (Mahony, Hamel and Pflimlin,
 * IEEE TAC 53(5), 2008) with a single vector measurement, the up direction; the kinematics are the
 * quaternion form under (2.1), q' = 1/2 q (x) [0, w_body], integrated by the
 * exponential map.
 *
 * Formats of the step's intermediates (fixed backend). The correction runs
 * in 16-bit values and 16 x 16-bit products (fc/scalar.h); the rate, the
 * bias and the attitude it corrects keep 32 bits:
 *   a          ACCEL    |a_i| <= accel_range <= 256, |a| <= 444 < 512
 *   v_a, v_hat UNIT16   unit vectors: a / |a| (fc_vec3_direction16, which
 *                       also gives |a| for the trust) and the third row of R(q)
 *                       from q rounded to UNIT16
 *   e, w e     UNIT16   |e| = sin(tilt error) <= 1, each rounded once
 *   weight     RATIO    in [0, 1], UNIT16 where it scales e
 *   Kp         RATE16   <= 20 rad/s; Kp w e exact in RATE (Q14 + Q10 = Q24)
 *   gyro - b + Kp w e  RATE  <= 100 + 0.8 + 20 < 128 (with the heading's Kp w_h e_h
 *              the init bounds gyro_range + bias_limit + 2 Kp by 127); times dt/2,
 *              the step's half-angle, in UNIT inside fc_quat_advance_body_rate
 *              where it is below 2^-5 rad (else times dt <= 2.6 rad per
 *              component, ANGLE < 8, for its exponential map)
 *   Ki dt      Q(ki_dt16_frac), 16 bits: w_c (w_c dt) <= 1 in the finest of
 *              four formats that holds it (a slow crossover's keeps 11 bits)
 *   b          UNIT   Q30 holding rad/s: |b| <= 0.8, so |b - Ki dt w e| <= 1.8 < 2
 *              (the heading's step is taken after the clamp: the same bound)
 *   alignment  ACCEL x UNIT products summed in fc_acc (64 bits in fixed), mean in ACCEL
 */
#include "fc/attitude_estimator.h"

#include <stddef.h>

#include "attitude_heading.h"

/* Below this length the accelerometer's direction is not trusted (a
 * vector of a few LSB has hardly a direction); with the trust band below g
 * the weight is 0 there anyway. */
#define MIN_DIRECTION_NORM_MPS2 FC_C(0.01f, ACCEL)

/* ---- defaults and init ------------------------------------------------ */

/* Ki dt (UNIT, in (0, 1]) in 16 bits, in the finest of Q26, Q22, Q18 and
 * Q14 that holds it: at least 11 significant bits whatever the crossover
 * (w_c = 0.1 rad/s at 500 Hz makes it 2e-5: 1342 LSB of Q26). Four formats,
 * so that the bias step's shift is one of four constants (bias_step). In
 * float the format is a label and the value is kept whole. */
static void set_ki_dt16(fc_attitude_estimator *est, fc_real ki_dt)
{
    static const uint8_t fracs[] = {26u, 22u, 18u, FC_UNIT16_FRAC};
    fc_arith probe = {0u};
    for (size_t i = 0u; i < sizeof fracs / sizeof fracs[0]; i++) {
        probe.saturated = 0u;
        est->ki_dt16 = fc_narrow16(&probe, ki_dt, FC_UNIT_FRAC, (int)fracs[i]);
        est->ki_dt16_frac = fracs[i];
        if (probe.saturated == 0u) {
            return; /* Ki dt <= 1 fits Q14 at the latest */
        }
    }
}

void fc_attitude_estimator_coast(fc_attitude_estimator *est, bool coast)
{
    est->coasting = coast;
}

void fc_attitude_estimator_default_params(fc_attitude_estimator_params *p, fc_real dt_s)
{
    if (p == NULL) {
        return;
    }
    p->dt_s = dt_s;
    p->crossover_radps = FC_C(1.0f, RATE);
    p->damping = FC_C(0.70710678f, RATIO);
    p->gyro_bias_limit_radps = FC_C(0.2f, RATE);
    p->gravity_mps2 = FC_C(9.81f, ACCEL);
    p->accel_trust_band_mps2 = FC_C(2.0f, ACCEL);
    p->gyro_range_radps = FC_C(35.0f, RATE);              /* 2000 deg/s */
    p->accel_range_mps2 = FC_C(16.0f * 9.80665f, ACCEL); /* 16 g */
    p->gyro_jump_radps = FC_INT(2, RATE);
    p->gyro_accel_max_radps2 = FC_INT(1000, GAIN);
    p->alignment_samples = 100u;
    p->heading_weight = FC_INT(1, RATIO);
    p->heading_hold_s = FC_C(0.1f, DT);
}

static bool params_in_range(const fc_attitude_estimator_params *p)
{
    if (!fc_in_range(p->dt_s, FC_INT(0, DT), FC_C(0.1f, DT)) || !(p->dt_s > FC_INT(0, DT))) {
        return false;
    }
    if (!fc_in_range(p->crossover_radps, FC_INT(0, RATE), FC_C(10.0f, RATE)) ||
        !(p->crossover_radps > FC_INT(0, RATE))) {
        return false;
    }
    if (!fc_in_range(p->damping, FC_INT(0, RATIO), FC_C(10.0f, RATIO)) ||
        !(p->damping > FC_INT(0, RATIO))) {
        return false;
    }
    if (!fc_in_range(p->gyro_bias_limit_radps, FC_INT(0, RATE), FC_C(0.8f, RATE))) {
        return false;
    }
    if (!fc_in_range(p->gravity_mps2, FC_C(1.0f, ACCEL), FC_C(100.0f, ACCEL))) {
        return false;
    }
    /* the trust reaches 0 before free fall, where the direction is meaningless */
    if (!fc_in_range(p->accel_trust_band_mps2, FC_C(0.01f, ACCEL), p->gravity_mps2) ||
        !(p->accel_trust_band_mps2 < p->gravity_mps2)) {
        return false;
    }
    if (!fc_in_range(p->gyro_range_radps, FC_INT(0, RATE), FC_C(100.0f, RATE)) ||
        !(p->gyro_range_radps > FC_INT(0, RATE))) {
        return false;
    }
    /* a range below g would reject the accelerometer at rest */
    if (!fc_in_range(p->accel_range_mps2, p->gravity_mps2, FC_C(256.0f, ACCEL)) ||
        !(p->accel_range_mps2 > p->gravity_mps2)) {
        return false;
    }
    if (!fc_in_range(p->gyro_jump_radps, FC_INT(0, RATE), FC_INT(100, RATE)) ||
        !(p->gyro_accel_max_radps2 > FC_INT(0, GAIN)) ||
        !fc_in_range(p->gyro_accel_max_radps2, FC_INT(0, GAIN), FC_INT(30000, GAIN))) {
        return false;
    }
    return p->alignment_samples >= 1u && p->alignment_samples <= 32767u;
}

static void reset_state(fc_attitude_estimator *est)
{
    est->ar.saturated = 0u;
    est->attitude = fc_quat_identity();
    est->gyro_bias_fine = fc_vec3_zero();
    est->gyro_bias_radps = fc_vec3_zero();
    est->rate_radps = fc_vec3_zero();
    est->last_gyro_radps = fc_vec3_zero();
    est->gyro_slack_radps = FC_INT(0, RATE);
    est->have_gyro = false;
    est->coasting = false;
    est->alignment_sum[0] = fc_acc_zero();
    est->alignment_sum[1] = fc_acc_zero();
    est->alignment_sum[2] = fc_acc_zero();
    est->accel_weight = FC_INT(0, RATIO);
    est->heading_cos = FC_INT(1, UNIT);
    est->heading_sin = FC_INT(0, UNIT);
    est->heading_rad = FC_INT(0, ANGLE);
    est->heading_steps_left = 0u;
    est->alignment_count = 0u;
    est->aligned = false;
}

fc_init_result fc_attitude_estimator_init(fc_attitude_estimator *est,
                                          const fc_attitude_estimator_params *p)
{
    if (est == NULL) {
        return FC_INIT_BAD_PARAM;
    }
    est->ready = false;
    reset_state(est);
    est->kp16_radps = FC_INT16(0, RATE16);
    est->ki_dt16 = 0;
    est->ki_dt16_frac = FC_UNIT16_FRAC;
    est->inv_band_s2pm = FC_INT(0, RATIO);
    est->inv_alignment_samples = FC_INT(0, UNIT);
    est->gyro_bias_limit_fine = FC_INT(0, UNIT);
    est->half_dt_s = FC_INT(0, DT);
    est->heading_hold_steps = 0u;
    if (p == NULL || !params_in_range(p)) {
        return FC_INIT_BAD_PARAM;
    }

    fc_arith ar = {0u};
    /* zeta w_c <= 100 and w_c dt <= 1 cannot leave RATE and RATIO */
    const fc_real zeta_wc = fc_mul(&ar, p->damping, p->crossover_radps, FC_SHIFT(RATIO, RATE, RATE));
    const fc_real wc_dt = fc_mul(&ar, p->crossover_radps, p->dt_s, FC_SHIFT(RATE, DT, RATIO));
    const fc_real range_dt = fc_mul(&ar, p->gyro_range_radps, p->dt_s, FC_SHIFT(RATE, DT, RATIO));
    if (zeta_wc > FC_C(10.0f, RATE) || wc_dt > FC_C(0.1f, RATIO) || range_dt > FC_C(2.0f, RATIO)) {
        return FC_INIT_BAD_PARAM;
    }
    /* Kp = 2 zeta w_c (the factor 2 as an addition: the float backend ignores shifts) */
    const fc_real kp = fc_add(&ar, zeta_wc, zeta_wc);
    const fc_real kp_dt = fc_mul(&ar, kp, p->dt_s, FC_SHIFT(RATE, DT, RATIO));
    if (kp_dt > FC_C(0.5f, RATIO)) {
        return FC_INIT_BAD_PARAM;
    }
    /* Ki = w_c^2 <= 100 (RATE format, s^-2); Ki dt = w_c (w_c dt) <= 1: UNIT format,
     * rad/s per unit of |e| */
    const fc_real ki = fc_mul(&ar, p->crossover_radps, p->crossover_radps, FC_SHIFT(RATE, RATE, RATE));
    const fc_real ki_dt = fc_mul(&ar, ki, p->dt_s, FC_SHIFT(RATE, DT, UNIT));
    uint16_t heading_hold_steps = 0u;
    if (!fc_attitude_heading_params_ok(p, kp, &heading_hold_steps)) {
        return FC_INIT_BAD_PARAM;
    }
    /* 1/band <= 100 (band >= 0.01 m/s2) */
    const fc_real inv_band =
        fc_div(&ar, FC_INT(1, RATIO), p->accel_trust_band_mps2, FC_DIV_SHIFT(RATIO, ACCEL, RATIO));
    /* 1/N as UNIT; N <= 32767 is exact in GAIN */
    const fc_real inv_n = fc_div(&ar, FC_INT(1, GAIN), FC_INT(p->alignment_samples, GAIN),
                                 FC_DIV_SHIFT(GAIN, GAIN, UNIT));
    const fc_real bias_limit = fc_convert(&ar, p->gyro_bias_limit_radps, FC_RATE_FRAC, FC_UNIT_FRAC);
    const fc_real slack_step = fc_mul(&ar, p->gyro_accel_max_radps2, p->dt_s, FC_SHIFT(GAIN, DT, RATE));
    if (ar.saturated != 0u || slack_step > FC_INT(100, RATE)) {
        return FC_INIT_BAD_PARAM;
    }

    est->p = *p;
    est->kp16_radps = fc_narrow16(&ar, kp, FC_RATE_FRAC, FC_RATE16_FRAC); /* Kp <= 20 < 32 */
    set_ki_dt16(est, ki_dt);
    est->inv_band_s2pm = inv_band;
    est->inv_alignment_samples = inv_n;
    est->gyro_bias_limit_fine = bias_limit;
    est->half_dt_s = fc_mul(&ar, p->dt_s, FC_C(0.5f, UNIT), FC_SHIFT(DT, UNIT, DT));
    est->heading_hold_steps = heading_hold_steps;
    est->gyro_slack_step_radps = slack_step;
    est->ready = true;
    return FC_INIT_OK;
}

/* by component: a struct copy is a byte loop at -Os on the ATmega */
static void copy_vec3(fc_vec3 *to, const fc_vec3 *from)
{
    to->x = from->x;
    to->y = from->y;
    to->z = from->z;
}

/* ---- the step ---------------------------------------------------------- */

/* lo <= x <= hi for bounds that are numbers: false for a NaN x and for an
 * infinite one, as fc_in_range, without its test of x. */
static bool between(fc_real x, fc_real lo, fc_real hi)
{
    return x >= lo && x <= hi;
}

/* |a - b| <= slack on each axis, as b - slack <= a <= b + slack: a bound
 * that leaves RATE saturates to its edge, which a sample inside the gyro
 * range (<= 100 rad/s) cannot pass, so the comparison is exact and its
 * saturation is not the step's. b (a sample that passed) and slack (<= 100
 * rad/s) are numbers, and so are the bounds. */
static bool within_of(const fc_vec3 *a, const fc_vec3 *b, fc_real slack)
{
    fc_arith scratch = {0u};
    return between(a->x, fc_sub_inline(&scratch, b->x, slack), fc_add_inline(&scratch, b->x, slack)) &&
           between(a->y, fc_sub_inline(&scratch, b->y, slack), fc_add_inline(&scratch, b->y, slack)) &&
           between(a->z, fc_sub_inline(&scratch, b->z, slack), fc_add_inline(&scratch, b->z, slack));
}

/* Inside the range, and (after the first, unless gyro_jump is 0) no further
 * from the last good sample than the airframe can turn in the time since:
 * the slack grows by gyro_accel_max dt a step and starts again from
 * gyro_jump at each good one. */
static bool gyro_valid(fc_attitude_estimator *est, const fc_vec3 *gyro)
{
    fc_arith *ar = &est->ar;
    const fc_real slack = fc_min(fc_add_inline(ar, est->gyro_slack_radps, est->gyro_slack_step_radps), FC_INT(100, RATE));
    const bool checked = est->have_gyro && est->p.gyro_jump_radps > FC_INT(0, RATE);
    const bool ok = fc_vec3_within(*gyro, est->p.gyro_range_radps) &&
                    (!checked || within_of(gyro, &est->last_gyro_radps, slack));
    if (ok) {
        copy_vec3(&est->last_gyro_radps, gyro);
        est->have_gyro = true;
        est->gyro_slack_radps = est->p.gyro_jump_radps;
    } else {
        est->gyro_slack_radps = slack;
    }
    return ok;
}

/* A valid accelerometer sample: inside its range, and a direction (not the
 * zero vector; a vector of a few LSB has a direction, but no trust). */
static bool accel_valid(const fc_attitude_estimator *est, const fc_vec3 *accel)
{
    return fc_vec3_within(*accel, est->p.accel_range_mps2) &&
           (accel->x != FC_INT(0, ACCEL) || accel->y != FC_INT(0, ACCEL) || accel->z != FC_INT(0, ACCEL));
}


/* Trust of the accelerometer (RATIO): 1 - ||a| - g| / band, clamped to [0, 1].
 * |a| <= 444 and g <= 100: |a| - g and its magnitude stay inside ACCEL, and
 * 1 - falloff inside RATIO (below), with no saturation to test. */
static fc_real accel_trust(fc_attitude_estimator *est, fc_real norm_mps2)
{
    fc_arith *ar = &est->ar;
    const fc_real difference = norm_mps2 - est->p.gravity_mps2;
    const fc_real deviation = difference < FC_INT(0, ACCEL) ? -difference : difference;
    if (!(deviation < est->p.accel_trust_band_mps2) || norm_mps2 < MIN_DIRECTION_NORM_MPS2) {
        return FC_INT(0, RATIO);
    }
    /* deviation < band, so the product stays below 1 (but for the rounding
     * of 1/band); inline: a product of every step */
    const fc_real falloff = fc_mul_inline(ar, deviation, est->inv_band_s2pm, FC_SHIFT(ACCEL, RATIO, RATIO));
    return fc_clamp(FC_INT(1, RATIO) - falloff, FC_INT(0, RATIO), FC_INT(1, RATIO));
}

/* v_hat = R(q)^T e_z, the world's up direction seen in the body: the third
 * row of the rotation matrix of q, from q rounded to UNIT16 (products exact
 * in UNIT16_SQ, each component rounded once; each sum of two products is
 * within 1/2 + 2^-13, so twice it fits, and x^2 + y^2 <= 1 + 2^-12: every
 * component within +-(1 + 2^-11), far inside UNIT16, rounded by fc_round16
 * without a saturation test). */
static fc_vec3_16 estimated_up_body(fc_quat16 q)
{
    const int sq = FC_UNIT16_SQ_FRAC, to = FC_UNIT16_FRAC;
    const fc_vec3_16 up = {
        fc_round16(2 * fc_dot2_16(q.x, q.z, fc_neg16(q.w), q.y), sq, to),                    /* 2(xz - wy) */
        fc_round16(2 * fc_dot2_16(q.y, q.z, q.w, q.x), sq, to),                              /* 2(yz + wx) */
        fc_round16(FC_INT(1, UNIT16_SQ) - 2 * fc_sumsq2_16(q.x, q.y), sq, to)};               /* 1 - 2(x^2 + y^2) */
    return up;
}

/* Alignment: accumulate a / N; after N valid samples, the attitude whose up
 * is the mean specific force (fc_quat_from_up: its roll and pitch, yaw 0 or
 * the heading given). The products a_i (1/N) enter the accumulators
 * unrounded: each is at most max |a| / N, so the sum of N of them stays
 * below max |a| and cannot wrap, and the mean is rounded once (N roundings
 * of a / N would add up to N/2 ACCEL LSB). */
static void align(fc_attitude_estimator *est, fc_vec3 accel_mps2)
{
    fc_arith *ar = &est->ar;
    const fc_real inv_n = est->inv_alignment_samples;
    est->alignment_sum[0] = fc_acc_mac(est->alignment_sum[0], accel_mps2.x, inv_n);
    est->alignment_sum[1] = fc_acc_mac(est->alignment_sum[1], accel_mps2.y, inv_n);
    est->alignment_sum[2] = fc_acc_mac(est->alignment_sum[2], accel_mps2.z, inv_n);
    est->alignment_count++;
    if (est->alignment_count < est->p.alignment_samples) {
        return;
    }
    const int mean_shift = FC_SHIFT(ACCEL, UNIT, ACCEL);
    const fc_vec3 m = fc_vec3_make(fc_acc_result(ar, est->alignment_sum[0], mean_shift),
                                   fc_acc_result(ar, est->alignment_sum[1], mean_shift),
                                   fc_acc_result(ar, est->alignment_sum[2], mean_shift));
    const fc_real yaw = est->heading_steps_left > 0u ? est->heading_rad : FC_INT(0, ANGLE);
    est->attitude = fc_quat_from_up(ar, m, yaw);
    est->aligned = true;
}

/* Kp we is exactly a RATE value: the product's FRAC is RATE's */
_Static_assert(FC_UNIT16_FRAC + FC_RATE16_FRAC == FC_RATE_FRAC, "UNIT16 x RATE16 is not RATE");

/* Ki dt we (UNIT16 x Q(ki_dt16_frac)) rounded to the bias's Q30: a
 * constant shift for each of the four formats set_ki_dt16 chooses from */
static fc_vec3 bias_step(fc_arith *ar, const fc_attitude_estimator *est, fc_vec3_16 we)
{
    const fc_real16 ki_dt = est->ki_dt16;
    const fc_vec3 product = fc_vec3_make(fc_mul16(we.x, ki_dt), fc_mul16(we.y, ki_dt), fc_mul16(we.z, ki_dt));
    switch (est->ki_dt16_frac) {
    case 26u:
        return fc_vec3_convert(ar, product, FC_UNIT16_FRAC + 26, FC_UNIT_FRAC);
    case 22u:
        return fc_vec3_convert(ar, product, FC_UNIT16_FRAC + 22, FC_UNIT_FRAC);
    case 18u:
        return fc_vec3_convert(ar, product, FC_UNIT16_FRAC + 18, FC_UNIT_FRAC);
    default:
        return fc_vec3_convert(ar, product, FC_UNIT16_FRAC + FC_UNIT16_FRAC, FC_UNIT_FRAC);
    }
}

/* The PI action (attitude_heading.h) in 16 x 16-bit products: Kp we exact
 * in RATE, Ki dt we rounded to the bias's Q30 (bias_step). One copy for the
 * tilt's and the heading's errors. The sums cannot leave their formats (the
 * bounds of the table at the top: the rate below 128 after both actions,
 * |b - Ki dt we| < 2), so they are formed without a saturation test. */
void fc_attitude_correct_by(fc_attitude_estimator *est, fc_vec3 *rate_radps, fc_vec3_16 we)
{
    fc_arith *ar = &est->ar;
    const fc_real16 kp = est->kp16_radps;
    rate_radps->x += fc_mul16(we.x, kp);
    rate_radps->y += fc_mul16(we.y, kp);
    rate_radps->z += fc_mul16(we.z, kp);
    const fc_vec3 step = bias_step(ar, est, we);
    const fc_vec3 bias = fc_vec3_make(est->gyro_bias_fine.x - step.x, est->gyro_bias_fine.y - step.y,
                                      est->gyro_bias_fine.z - step.z);
    est->gyro_bias_fine = fc_vec3_clamp_each(ar, bias, est->gyro_bias_limit_fine);
    est->gyro_bias_radps = fc_vec3_convert(ar, est->gyro_bias_fine, FC_UNIT_FRAC, FC_RATE_FRAC);
}

/* The trust of a valid accelerometer sample and, where it is above 0, its
 * direction (UNIT16). No test of the components first: one beyond g + band
 * makes |a| leave the band, and the trust is 0 all the same (|a| of a valid
 * sample, below 444, does not saturate its ACCEL length). */
static fc_real accel_weight_and_direction(fc_attitude_estimator *est, const fc_vec3 *accel_mps2,
                                          fc_vec3_16 *up_measured)
{
    fc_real norm_mps2 = FC_INT(0, ACCEL);
    if (!fc_vec3_direction16(&est->ar, *accel_mps2, up_measured, &norm_mps2)) {
        return FC_INT(0, RATIO);
    }
    return accel_trust(est, norm_mps2);
}

/* w e, e = v_a x v_hat (UNIT16): each component of e the difference of two
 * exact products rounded once, then w e rounded once. Both are bounded far
 * inside UNIT16 ([-2, 2)): |e_i| <= |v_a| |v_hat| <= (1 + 2^-13)(1 + 2^-11)
 * (fc_vec3_direction16's components, estimated_up_body's) and w <= 1, so
 * the roundings are fc_vec3_16_cross's and fc_vec3_16_scale's without their
 * saturation tests. */
static fc_vec3_16 weighted_tilt_error(const fc_vec3_16 *a, const fc_vec3_16 *b, fc_real16 weight16)
{
    const int sq = FC_UNIT16_SQ_FRAC, to = FC_UNIT16_FRAC;
    const fc_real16 ex = fc_round16(fc_dot2_16(a->y, b->z, fc_neg16(a->z), b->y), sq, to);
    const fc_real16 ey = fc_round16(fc_dot2_16(a->z, b->x, fc_neg16(a->x), b->z), sq, to);
    const fc_real16 ez = fc_round16(fc_dot2_16(a->x, b->y, fc_neg16(a->y), b->x), sq, to);
    const fc_vec3_16 we = {fc_round16(fc_mul16(ex, weight16), sq, to), fc_round16(fc_mul16(ey, weight16), sq, to),
                           fc_round16(fc_mul16(ez, weight16), sq, to)};
    return we;
}

/* One corrected integration step, with the accelerometer's sample when
 * accel_ok; returns the weight used (RATIO). */
static fc_real correct_and_integrate(fc_attitude_estimator *est, bool accel_ok, const fc_vec3 *accel_mps2)
{
    fc_arith *ar = &est->ar;
    fc_vec3 rate = fc_vec3_make(est->rate_radps.x, est->rate_radps.y, est->rate_radps.z); /* gyro - b, RATE; by component (copy_vec3) */
    fc_real weight = FC_INT(0, RATIO);
    fc_vec3_16 up_measured = fc_vec3_16_zero();
    if (accel_ok) {
        weight = accel_weight_and_direction(est, accel_mps2, &up_measured);
    }
    if (weight > FC_INT(0, RATIO)) {
        const fc_vec3_16 up_estimated = estimated_up_body(fc_quat16_round_unit(est->attitude));
        const fc_real16 weight16 = fc_round16(weight, FC_RATIO_FRAC, FC_UNIT16_FRAC); /* in (0, 1]: no saturation */
        fc_attitude_correct_by(est, &rate, weighted_tilt_error(&up_measured, &up_estimated, weight16));
    }
    if (est->heading_steps_left > 0u) {
        /* the same actions for the heading's w_h e_h (attitude_heading.c) */
        fc_attitude_heading_correct(est, &rate);
    }
    /* q <- q (x) exp(rate dt / 2) */
    fc_quat_advance_body_rate(ar, &est->attitude, &rate, est->half_dt_s);
    return weight;
}

static void write_output(const fc_attitude_estimator *est, fc_attitude_estimate *out)
{
    /* the identity until aligned (reset_state, align) */
    out->attitude.w = est->attitude.w;
    out->attitude.x = est->attitude.x;
    out->attitude.y = est->attitude.y;
    out->attitude.z = est->attitude.z;
    copy_vec3(&out->rate_radps, &est->rate_radps);
    copy_vec3(&out->gyro_bias_radps, &est->gyro_bias_radps);
    out->accel_weight = est->accel_weight;
    out->aligned = est->aligned;
}

static void write_safe_output(fc_attitude_estimate *out)
{
    out->attitude = fc_quat_identity();
    out->rate_radps = fc_vec3_zero();
    out->gyro_bias_radps = fc_vec3_zero();
    out->accel_weight = FC_INT(0, RATIO);
    out->aligned = false;
    out->gyro_ok = false;
    out->accel_ok = false;
}

/* The sample's checks, shared by both steps: a valid gyro sample, corrected
 * by the bias of the previous step, becomes the rate. */
typedef struct sample_check {
    bool gyro_ok, accel_ok;
} sample_check;

static sample_check check_sample(fc_attitude_estimator *est, const fc_imu_sample *imu)
{
    sample_check c = {false, false};
    if (imu == NULL) {
        return c;
    }
    c.gyro_ok = gyro_valid(est, &imu->gyro_radps);
    if (c.gyro_ok) {
        /* |gyro| <= gyro_range <= 100 and |b| <= 0.8: the difference stays
         * inside RATE, no saturation to test */
        const fc_vec3 *gyro = &imu->gyro_radps, *bias = &est->gyro_bias_radps;
        est->rate_radps.x = gyro->x - bias->x;
        est->rate_radps.y = gyro->y - bias->y;
        est->rate_radps.z = gyro->z - bias->z;
    }
    c.accel_ok = accel_valid(est, &imu->accel_mps2);
    return c;
}

static fc_step_status sample_status(sample_check c)
{
    if (c.gyro_ok && c.accel_ok) {
        return FC_STEP_OK;
    }
    return FC_STEP_BAD_INPUT;
}

/* Both steps' start (false, the safe output written, before a successful init)
 * and end (the output, and the status of the arithmetic). */
static bool step_begins(fc_attitude_estimator *est, fc_attitude_estimate *out)
{
    if (est == NULL || !est->ready) {
        if (out != NULL) {
            write_safe_output(out);
        }
        return false;
    }
    est->ar.saturated = 0u;
    return true;
}

static fc_step_status step_ends(fc_attitude_estimator *est, sample_check sample, fc_attitude_estimate *out,
                                fc_step_status status)
{
    if (out != NULL) {
        write_output(est, out);
        out->gyro_ok = sample.gyro_ok;
        out->accel_ok = sample.accel_ok;
    }
    if (est->ar.saturated != 0u) {
        status |= FC_STEP_ARITH_SATURATED;
    }
    return status;
}

fc_step_status fc_attitude_estimator_step(fc_attitude_estimator *est, const fc_imu_sample *imu,
                                          fc_attitude_estimate *out)
{
    if (!step_begins(est, out)) {
        return FC_STEP_NOT_READY;
    }
    const sample_check sample = check_sample(est, imu);
    fc_step_status status = sample_status(sample);

    fc_real weight = FC_INT(0, RATIO);
    if (!est->aligned) {
        if (sample.accel_ok) {
            align(est, imu->accel_mps2);
        }
    } else if (sample.gyro_ok) {
        weight = correct_and_integrate(est, sample.accel_ok && !est->coasting, &imu->accel_mps2);
        if (!(weight > FC_INT(0, RATIO))) {
            status |= FC_STEP_DEGRADED; /* gyro only */
        }
    } else {
        status |= FC_STEP_DEGRADED; /* attitude held */
    }
    est->accel_weight = weight;
    if (est->heading_steps_left > 0u) {
        est->heading_steps_left--; /* one step older */
    }
    return step_ends(est, sample, out, status);
}

fc_step_status fc_attitude_estimator_rate_step(fc_attitude_estimator *est, const fc_imu_sample *imu,
                                               fc_attitude_estimate *out)
{
    if (!step_begins(est, out)) {
        return FC_STEP_NOT_READY;
    }
    const sample_check sample = check_sample(est, imu);
    est->accel_weight = FC_INT(0, RATIO);
    return step_ends(est, sample, out, sample_status(sample));
}
