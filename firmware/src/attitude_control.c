/* attitude_control.c - quaternion attitude control (fc/attitude_control.h).
 * One source for both backends; the math is written out in the header. */
#include "fc/attitude_control.h"

/* Parameter ranges: inside the fixed format of each field, in both backends
 * (so the float build cannot overflow to inf either). */
#define MAX_DT_S FC_C(1.0f, DT)
#define MAX_INERTIA_KGM2 FC_C(1.99f, INERTIA)
#define MAX_GAIN FC_C(30000.0f, GAIN)
#define MAX_INTEGRAL_LIMIT FC_C(4.0f, ANGLE)
#define MAX_AUTHORITY_NM FC_C(100.0f, MOMENT)
#define MAX_MOMENT_LIMIT FC_C(1.99f, RATIO)
/* J / authority (s^2) inside INERTIA */
#define MAX_INERTIA_NORM FC_C(1.99f, INERTIA)
/* Rates beyond this are out of range (a gyro reads up to 35 rad/s). */
#define MAX_RATE_RADPS FC_C(100.0f, RATE)
/* Below this |w^2 + z^2| of the error the heading is undefined (header). */
#define MIN_HEADING_NORM_SQ FC_C(1.0e-4f, UNIT16_SQ)
/* Up to this d = 1 - (w^2 + z^2) the half heading (c, s) = (w, z) / sqrt(1 - d)
 * takes the series 1 + d/2 of the root (attitude_error): what it leaves out,
 * 3 d^2/8 (1 + 2 d) at most, stays below 0.4 of the backend's resolution
 * (fixed: a UNIT16 LSB at d = 2^-7, tilt errors up to 10 deg; float: 2^-24
 * at d = 2^-12), so that with the roundings (c, s) stays within the bound of
 * fc_unit2_16 (1.32 UNIT16 LSB; 4 2^-24 in float) that the error's accuracy
 * rests on (test_attitude_control.error_tol_at). */
#if FC_NUMERIC_FIXED
#define SERIES_MAX_D FC_C(0.0078125f, UNIT16_SQ)
#else
#define SERIES_MAX_D FC_C(2.44140625e-4f, UNIT16_SQ)
#endif

/* The 16-bit law's own Q-formats (fc/attitude_control.h, Formats): what its
 * products read, each chosen from the range the law can reach (and RATE16,
 * fc/scalar.h). */
#define FC_ANGLE16_FRAC 12    /* [-8, 8) rad, 2.4e-4 rad: the error (|e| <= 2) and the integral (<= 4) */
#define FC_NGAIN16_FRAC 12    /* [-8, 8), 2.4e-4: the gains times J / authority */
#define FC_NINERTIA16_FRAC 15 /* [-1, 1) s^2, 3.1e-5: the inertia differences / authority */
#define FC_WW16_FRAC 5        /* [-1024, 1024) rad^2/s^2, 0.031: w_i w_j */
#define FC_NSUM_FRAC 22       /* [-512, 512), 2.4e-7: the normalised moment as it is summed */
/* gain x error and gain x integral are exact in Q24, gain x rate in Q22 (the sum's) */
_Static_assert(FC_NGAIN16_FRAC + FC_ANGLE16_FRAC == FC_NSUM_FRAC + 2, "kp e is not Q24");
_Static_assert(FC_NGAIN16_FRAC + FC_RATE16_FRAC == FC_NSUM_FRAC, "kd r is not the sum's format");
/* the narrowings of the step that drop 16 bits take the high half */
_Static_assert(FC_ANGLE_FRAC - FC_ANGLE16_FRAC == 16, "ANGLE -> ANGLE16 is not a high half");

/* a product of two UNIT16 values is an ANGLE as it stands (attitude_error) */
_Static_assert(FC_UNIT16_SQ_FRAC == FC_ANGLE_FRAC, "UNIT16 x UNIT16 is not ANGLE");
/* A held moment below this (half a NORM16 LSB) is zero (fixed rounding would
 * stall the decay). */
#define HOLD_ZERO FC_C(3.0e-5f, NSUM)
/* The largest normalised gain and inertia difference (their 16-bit formats). */
#define MAX_NORM_GAIN FC_C(7.99f, RATIO)
#define MAX_NORM_INERTIA_DIFF FC_C(0.99f, INERTIA)

/* Inlined where the step calls it: a call on the ATmega saves and restores
 * most of the register file, more than the body of these helpers costs. */
#define STEP_INLINE static inline __attribute__((always_inline))

static bool finite_in(fc_real x, fc_real lo, fc_real hi)
{
    return fc_is_finite(x) && x >= lo && x <= hi;
}

static bool positive_upto(fc_real x, fc_real max)
{
    return fc_is_finite(x) && x > FC_INT(0, UNIT) && x <= max;
}

static bool vec_positive_upto(fc_vec3 v, fc_real max)
{
    return positive_upto(v.x, max) && positive_upto(v.y, max) && positive_upto(v.z, max);
}

static bool vec_in(fc_vec3 v, fc_real lo, fc_real hi)
{
    return finite_in(v.x, lo, hi) && finite_in(v.y, lo, hi) && finite_in(v.z, lo, hi);
}

static bool attitude_params_valid(const fc_attitude_control_params *p)
{
    const fc_real zero = FC_INT(0, UNIT);
    return positive_upto(p->dt_s, MAX_DT_S) && vec_positive_upto(p->inertia_kgm2, MAX_INERTIA_KGM2) &&
           vec_in(p->kp_per_s2, zero, MAX_GAIN) && vec_in(p->kd_per_s, zero, MAX_GAIN) &&
           vec_in(p->ki_per_s3, zero, MAX_GAIN) &&
           vec_positive_upto(p->integral_limit_rad, MAX_INTEGRAL_LIMIT) &&
           finite_in(p->yaw_weight, FC_INT(0, RATIO), FC_INT(1, RATIO)) &&
           vec_positive_upto(p->authority_nm, MAX_AUTHORITY_NM) &&
           vec_positive_upto(p->moment_limit, MAX_MOMENT_LIMIT);
}

/* x / authority per axis (INERTIA over MOMENT gives INERTIA: s^2 for J) */
static fc_vec3 per_authority(fc_arith *ar, fc_vec3 x, fc_vec3 authority)
{
    const int shift = FC_DIV_SHIFT(INERTIA, MOMENT, INERTIA);
    return fc_vec3_make(fc_div(ar, x.x, authority.x, shift), fc_div(ar, x.y, authority.y, shift),
                        fc_div(ar, x.z, authority.z, shift));
}

static bool vec_within(fc_vec3 v, fc_real limit)
{
    return fc_vec3_within(v, limit);
}

/* k J / authority per axis (RATIO), false beyond the 16-bit format. */
static bool normalised_gain(fc_arith *ar, fc_vec3 k, fc_vec3 inertia_norm, fc_vec3_16 *out)
{
    const int shift = FC_SHIFT(GAIN, INERTIA, RATIO);
    const fc_vec3 g = fc_vec3_make(fc_mul(ar, k.x, inertia_norm.x, shift), fc_mul(ar, k.y, inertia_norm.y, shift),
                                   fc_mul(ar, k.z, inertia_norm.z, shift));
    *out = fc_vec3_narrow16(ar, g, FC_RATIO_FRAC, FC_NGAIN16_FRAC);
    return vec_within(g, MAX_NORM_GAIN);
}

/* The step's 16-bit constants: the gains in normalised moment per unit of
 * error (k J / authority), the inertia differences, the budget in NSUM. */
static bool normalised_gains(fc_attitude_control *c, const fc_attitude_control_params *p)
{
    fc_arith ar = {0u};
    const bool in_range = normalised_gain(&ar, p->kp_per_s2, c->inertia_norm, &c->gain_p) &&
                          normalised_gain(&ar, p->ki_per_s3, c->inertia_norm, &c->gain_i) &&
                          normalised_gain(&ar, p->kd_per_s, c->inertia_norm, &c->gain_d);
    c->inertia_diff16 = fc_vec3_narrow16(&ar, c->inertia_diff_norm, FC_INERTIA_FRAC, FC_NINERTIA16_FRAC);
    c->moment_limit_sum = fc_vec3_convert(&ar, p->moment_limit, FC_RATIO_FRAC, FC_NSUM_FRAC);
    return in_range && ar.saturated == 0u;
}

fc_init_result fc_attitude_control_init(fc_attitude_control *c, const fc_attitude_control_params *p)
{
    c->ready = 0u;
    c->ar.saturated = 0u;
    c->p = *p;
    c->integral_rad_s = fc_vec3_zero();
    c->last_moment = fc_vec3_zero();
    c->last_error_rad = fc_vec3_zero();
    c->integral_hold = 0u;
    c->inertia_norm = fc_vec3_zero();
    c->inertia_diff_norm = fc_vec3_zero();
    c->gain_p = fc_vec3_16_zero();
    c->gain_i = fc_vec3_16_zero();
    c->gain_d = fc_vec3_16_zero();
    c->inertia_diff16 = fc_vec3_16_zero();
    c->moment_limit_sum = fc_vec3_zero();
    c->hold_decay = FC_INT(0, UNIT);
    if (!attitude_params_valid(p)) {
        return FC_INIT_BAD_PARAM;
    }
    fc_arith ar = {0u};
    const fc_vec3 j = p->inertia_kgm2;
    /* w x J w = ((Jz - Jy) wy wz, (Jx - Jz) wz wx, (Jy - Jx) wx wy) for diagonal J;
     * both per authority, so that the law gives normalised moments */
    const fc_vec3 j_diff = fc_vec3_make(fc_sub(&ar, j.z, j.y), fc_sub(&ar, j.x, j.z), fc_sub(&ar, j.y, j.x));
    c->inertia_norm = per_authority(&ar, j, p->authority_nm);
    c->inertia_diff_norm = per_authority(&ar, j_diff, p->authority_nm);
    if (!vec_positive_upto(c->inertia_norm, MAX_INERTIA_NORM) ||
        !vec_within(c->inertia_diff_norm, MAX_NORM_INERTIA_DIFF) ||
        !normalised_gains(c, p)) {
        return FC_INIT_BAD_PARAM;
    }
    /* ZOH pole of the decay of the held moment: e^(-dt/tau) */
    const fc_real dt_over_tau =
        fc_mul(&ar, p->dt_s, FC_C(1.0f / FC_ATTITUDE_CONTROL_HOLD_TAU_S, RATIO), FC_SHIFT(DT, RATIO, RATIO));
    c->hold_decay = fc_exp_neg(&ar, dt_over_tau);
    if (ar.saturated != 0u) {
        return FC_INIT_BAD_PARAM;
    }
    c->ready = 1u;
    return FC_INIT_OK;
}

void fc_attitude_control_reset(fc_attitude_control *c)
{
    c->integral_rad_s = fc_vec3_zero();
}

void fc_attitude_control_hold_integral(fc_attitude_control *c, bool hold)
{
    c->integral_hold = hold ? 1u : 0u;
}

void fc_attitude_control_default_params(fc_attitude_control_params *p, fc_real dt_s, fc_vec3 inertia_kgm2)
{
    fc_arith ar = {0u};
    const fc_real kp_tilt =
        FC_C(FC_ATTITUDE_CONTROL_DEFAULT_WN_TILT * FC_ATTITUDE_CONTROL_DEFAULT_WN_TILT, GAIN);
    const fc_real kd_tilt =
        FC_C(2.0f * FC_ATTITUDE_CONTROL_DEFAULT_ZETA_TILT * FC_ATTITUDE_CONTROL_DEFAULT_WN_TILT, GAIN);
    const fc_real kp_yaw =
        FC_C(FC_ATTITUDE_CONTROL_DEFAULT_WN_YAW * FC_ATTITUDE_CONTROL_DEFAULT_WN_YAW, GAIN);
    const fc_real kd_yaw =
        FC_C(2.0f * FC_ATTITUDE_CONTROL_DEFAULT_ZETA_YAW * FC_ATTITUDE_CONTROL_DEFAULT_WN_YAW, GAIN);
    p->dt_s = dt_s;
    p->inertia_kgm2 = inertia_kgm2;
    p->kp_per_s2 = fc_vec3_make(kp_tilt, kp_tilt, kp_yaw);
    p->kd_per_s = fc_vec3_make(kd_tilt, kd_tilt, kd_yaw);
    p->ki_per_s3 = fc_vec3_make(FC_INT(0, GAIN), FC_INT(0, GAIN), FC_INT(0, GAIN));
    p->integral_limit_rad = fc_vec3_make(FC_C(0.2f, ANGLE), FC_C(0.2f, ANGLE), FC_C(0.2f, ANGLE));
    p->yaw_weight = FC_INT(1, RATIO);
    p->authority_nm = fc_vec3_scale(&ar, inertia_kgm2, FC_C(FC_ATTITUDE_CONTROL_DEFAULT_ALPHA_MAX, GAIN),
                                    FC_SHIFT(INERTIA, GAIN, MOMENT));
    p->moment_limit = fc_vec3_make(FC_INT(1, RATIO), FC_INT(1, RATIO), FC_INT(1, RATIO));
}

STEP_INLINE bool rate_valid(const fc_vec3 *r)
{
    return fc_vec3_within(*r, MAX_RATE_RADPS);
}

/* q in UNIT16, *ok as fc_quat16_normalize gives them. Fixed: its test for
 * a q that is unit at 16 bits (the usual case: the estimator's attitude and
 * the position loop's setpoint arrive normalised) inlined, on the
 * components rounded without a saturation test (fc_quat16_round_unit: one
 * of 2 or more wraps to -2, whose square alone is four times one, so that
 * q fails the test) and their squares summed unsigned (quat.c); else that
 * function. */
STEP_INLINE fc_quat16 quat16_unit(fc_arith *ar, const fc_quat *q, bool *ok)
{
#if FC_NUMERIC_FIXED
    const fc_quat16 r = fc_quat16_round_unit(*q);
    const uint32_t norm_sq = (uint32_t)fc_sq16(r.w) + (uint32_t)fc_sq16(r.x) + (uint32_t)fc_sq16(r.y) +
                             (uint32_t)fc_sq16(r.z);
    const uint32_t one = (uint32_t)FC_INT(1, UNIT16_SQ);
    const uint32_t off = norm_sq > one ? norm_sq - one : one - norm_sq;
    if (off <= (uint32_t)FC_QUAT16_UNIT_SQ_TOLERANCE) {
        *ok = true;
        return r;
    }
#endif
    return fc_quat16_normalize(ar, *q, ok);
}

/* p* (x) q with w >= 0: fc_quat16_conj_mul and fc_quat16_shortest (the same
 * bits) inlined into the step. No saturation test (fc_dot4_round16): p and q
 * are unit within FC_QUAT16_UNIT_SQ_TOLERANCE (quat16_unit), so that each
 * component of the product is at most |p| |q|, near 1, inside UNIT16's 2. */
STEP_INLINE fc_quat16 error_quat16(const fc_quat16 *p, const fc_quat16 *q)
{
    const int sq = FC_UNIT16_SQ_FRAC, to = FC_UNIT16_FRAC;
    fc_quat16 r = {
        fc_dot4_round16(p->w, q->w, p->x, q->x, p->y, q->y, p->z, q->z, sq, to),
        fc_dot4_round16(p->w, q->x, fc_neg16(p->x), q->w, fc_neg16(p->y), q->z, p->z, q->y, sq, to),
        fc_dot4_round16(p->w, q->y, p->x, q->z, fc_neg16(p->y), q->w, fc_neg16(p->z), q->x, sq, to),
        fc_dot4_round16(p->w, q->z, fc_neg16(p->x), q->y, p->y, q->x, fc_neg16(p->z), q->w, sq, to)};
    if (r.w < FC_INT16(0, UNIT16)) {
        r.w = fc_neg16(r.w);
        r.x = fc_neg16(r.x);
        r.y = fc_neg16(r.y);
        r.z = fc_neg16(r.z);
    }
    return r;
}

/* v k for a UNIT16 v and a 32-bit k in UNIT16_SQ, as UNIT16, for |v k| < 2
 * (no saturation test, fc_round16): its only use is the series branch,
 * where v is e.w or e.z with e.w^2 + e.z^2 = 1 - d <= 1 + SERIES_MAX_D and
 * k = 1 + d/2 <= 1 + SERIES_MAX_D/2. */
STEP_INLINE fc_real16 scaled16(fc_arith *ar, fc_real16 v, fc_real k)
{
    return fc_round16(fc_mul_by16(ar, k, v, FC_SHIFT(UNIT16_SQ, UNIT16, UNIT16)), FC_UNIT16_FRAC,
                      FC_UNIT16_FRAC);
}

/* Attitude error per the header: (e_tilt.x, e_tilt.y, e_head.z), ANGLE, into
 * *err; returns s = sin(psi_e/2) (UNIT16) for the weighted heading part. In
 * fixed the quaternions are UNIT16: 16-bit products, each exact in 32 bits. */
STEP_INLINE fc_real16 attitude_error(fc_arith *ar, const fc_quat16 *q, const fc_quat16 *qd, fc_vec3 *err)
{
    /* (2.9) in the body frame: q_eb = q_d* (x) q = q* (x) (q (x) q_d*) (x) q, w >= 0 */
    const fc_quat16 e = error_quat16(qd, q);
    /* N^2 = w^2 + z^2 = cos^2(tilt_e/2); c = w/N, s = z/N: the half heading error */
    const fc_real n_sq = fc_sumsq2_16(e.w, e.z); /* UNIT16_SQ */
    fc_real16 c = FC_INT16(1, UNIT16);
    fc_real16 s = FC_INT16(0, UNIT16);
    /* 1 - N^2 = sin^2(tilt_e/2); 0 <= N^2 <= |e|^2, near 1: no saturation test */
    const fc_real d = FC_INT(1, UNIT16_SQ) - n_sq;
    if (fc_within(d, SERIES_MAX_D)) {
        /* a small tilt error: 1/N = 1 + d/2 + 3 d^2/8 + ..., cut after d/2 */
        const fc_real half_d = fc_half(d);
        const fc_real inv_n = FC_INT(1, UNIT16_SQ) + half_d; /* d <= SERIES_MAX_D: no saturation test */
        c = scaled16(ar, e.w, inv_n);
        s = scaled16(ar, e.z, inv_n);
    } else if (n_sq >= MIN_HEADING_NORM_SQ) {
        fc_unit2_16(ar, e.w, e.z, n_sq, &c, &s);
    } else {
        /* near upside down the heading is undefined: no heading part (header) */
    }
    /* tilt: the vector part (x, y) turned by -psi_e/2, i.e. the vector part of
     * the reduced-attitude quaternion; products of UNIT16 values are ANGLEs */
    const fc_real half_tx = fc_dot2_16(e.x, c, e.y, s);
    const fc_real half_ty = fc_dot2_16(e.y, c, fc_neg16(e.x), s);
    const fc_real half_hz = fc_widen16(s, FC_UNIT16_FRAC, FC_ANGLE_FRAC);
    /* each half at most |(e.x, e.y)| |(c, s)|, near 1, and |s| <= 1: twice
     * that is inside ANGLE's [-8, 8), no saturation test */
    err->x = half_tx + half_tx;
    err->y = half_ty + half_ty;
    err->z = half_hz + half_hz;
    return s;
}

/* dJ w_j w_k, one axis' share of w x J w (header), in NSUM; none where the
 * inertia difference is zero (roll and pitch alike: yaw on a symmetric quad) */
STEP_INLINE fc_real gyroscopic(fc_arith *ar, fc_real16 inertia_diff, fc_real16 w_j, fc_real16 w_k)
{
    if (inertia_diff == FC_INT16(0, NINERTIA16)) {
        return FC_INT(0, NSUM);
    }
    /* |w_j w_k| <= FC_REAL16_MAX^2 2^-15 < FC_REAL16_MAX in WW16: no saturation test */
    const fc_real16 ww = fc_round16(fc_mul16(w_j, w_k), 2 * FC_RATE16_FRAC, FC_WW16_FRAC);
    return fc_convert(ar, fc_mul16(inertia_diff, ww), FC_NINERTIA16_FRAC + FC_WW16_FRAC, FC_NSUM_FRAC);
}

/* One axis of the law in the normalised units (header): -(Kp e + Ki I +
 * Kd r) + dJ w_j w_k with K = k J / authority, dJ = (J_k - J_j) / authority;
 * 16 x 16 -> 32 products summed in NSUM. The integral (ANGLE) is read by
 * its high half (ANGLE16) where Ki is not zero; with Ki = 0 (no integral
 * action: the integral stays zero, integrate_axis) its term is left out,
 * the same sum. No saturation test of the narrowing (fc_round16): ANGLE16
 * spans ANGLE's [-8, 8) and the integral is at most integral_limit <=
 * MAX_INTEGRAL_LIMIT = 4 (integrate_axis clamps). */
STEP_INLINE fc_real axis_moment(fc_arith *ar, fc_real16 gain_p, fc_real16 e, fc_real16 gain_i, fc_real integral,
                                fc_real16 gain_d, fc_real16 rate_err, fc_real gyro)
{
    /* |Kp e| <= 8 x 2 and |Ki I| <= 8 x 4: their sum is exact in Q24 */
    fc_real pi_q24 = fc_mul16(gain_p, e);
    if (gain_i != FC_INT16(0, NGAIN16)) {
        const fc_real16 integral16 = fc_round16(integral, FC_ANGLE_FRAC, FC_ANGLE16_FRAC);
        pi_q24 = fc_dot2_16(gain_p, e, gain_i, integral16);
    }
    const fc_real pi = fc_convert(ar, pi_q24, FC_NSUM_FRAC + 2, FC_NSUM_FRAC);
    const fc_real d = fc_mul16(gain_d, rate_err); /* NSUM as it stands */
    /* |pi + d| <= 7.99 (2 + 4) + 7.99 x 32 < 512, inside NSUM: no saturation
     * test; the gyroscopic term (up to 0.99 x 1024) can leave it: tested */
    return fc_sub_inline(ar, gyro, pi + d);
}

/* Conditional integration of one axis (header: anti-windup): I + e dt with
 * e as the products read it (ANGLE16), a 32 x 16-bit product. The integral
 * acts as -ki I on the moment: a positive step of I pushes the moment
 * negative, which the allocation's report of that direction (sat & sat_neg)
 * or this step's own clamp there (raw below moment) forbids; the same the
 * other way. Only the direction the step goes in is looked at. */
STEP_INLINE fc_real integrate_axis(fc_arith *ar, fc_real integral, fc_real16 e, fc_real dt, fc_real ki,
                                   fc_real limit, uint8_t sat, uint8_t sat_neg, uint8_t sat_pos, fc_real raw,
                                   fc_real moment)
{
    if (!(ki > FC_INT(0, GAIN))) {
        return FC_INT(0, ANGLE);
    }
    if (e > FC_INT16(0, ANGLE16) && ((sat & sat_neg) != 0u || raw < moment)) {
        return integral;
    }
    if (e < FC_INT16(0, ANGLE16) && ((sat & sat_pos) != 0u || raw > moment)) {
        return integral;
    }
    const fc_real step = fc_mul_by16(ar, dt, e, FC_SHIFT(DT, ANGLE16, ANGLE));
    /* |I| <= MAX_INTEGRAL_LIMIT = 4 and |e dt| <= 2 x 1: the sum is inside
     * ANGLE's [-8, 8), no saturation test; -limit neither: the limit is
     * validated positive */
    return fc_clamp(integral + step, -limit, limit);
}

/* Roll and pitch scaled down together into their box (the tilt axis is kept);
 * yaw clamped on its own. The limits are validated positive: -limit needs
 * no saturation test. */
static fc_vec3 limit_moment(fc_arith *ar, fc_vec3 m, fc_vec3 limit)
{
    const fc_real abs_x = fc_abs(ar, m.x);
    const fc_real abs_y = fc_abs(ar, m.y);
    if (abs_x > limit.x || abs_y > limit.y) {
        const int ratio_shift = FC_DIV_SHIFT(NSUM, NSUM, UNIT);
        fc_real f = FC_INT(1, UNIT);
        if (abs_x > limit.x) {
            f = fc_min(f, fc_div(ar, limit.x, abs_x, ratio_shift));
        }
        if (abs_y > limit.y) {
            f = fc_min(f, fc_div(ar, limit.y, abs_y, ratio_shift));
        }
        m.x = fc_mul(ar, m.x, f, FC_SHIFT(NSUM, UNIT, NSUM));
        m.y = fc_mul(ar, m.y, f, FC_SHIFT(NSUM, UNIT, NSUM));
        /* the hard clamp catches the last rounding of the scaling */
        m.x = fc_clamp(m.x, -limit.x, limit.x);
        m.y = fc_clamp(m.y, -limit.y, limit.y);
    }
    /* (unscaled, |m.x| and |m.y| are inside their limits already, or NaN,
     * which the clamp would pass through as well) */
    return fc_vec3_make(m.x, m.y, fc_clamp(m.z, -limit.z, limit.z));
}

/* A rate as the products read it: RATE16, clamped to its range first (by
 * design, header: not an arithmetic saturation). The clamp's 31.999 rounds
 * to FC_REAL16_MAX in RATE16, so the narrowing needs no saturation test. */
STEP_INLINE fc_real16 rate16(fc_arith *ar, fc_real rate)
{
    (void)ar;
    const fc_real limit = FC_C(31.999f, RATE);
    return fc_round16(fc_clamp(rate, -limit, limit), FC_RATE_FRAC, FC_RATE16_FRAC);
}

/* w - w_ff as RATE16; w16 = rate16(w) where there is no feed-forward (the
 * same value: roll and pitch, mostly) */
STEP_INLINE fc_real16 rate_error16(fc_arith *ar, fc_real rate, fc_real16 rate16_of_rate, fc_real rate_ff)
{
    if (rate_ff == FC_INT(0, RATE)) {
        return rate16_of_rate;
    }
    return rate16(ar, fc_sub(ar, rate, rate_ff));
}

static fc_real hold_decayed(fc_arith *ar, fc_real m, fc_real decay)
{
    const fc_real d = fc_mul(ar, m, decay, FC_SHIFT(NSUM, UNIT, NSUM));
    return fc_abs(ar, d) < HOLD_ZERO ? FC_INT(0, NSUM) : d;
}

fc_step_status fc_attitude_control_step(fc_attitude_control *c, const fc_attitude_control_input *in,
                                        fc_attitude_control_output *out)
{
    c->ar.saturated = 0u;
    if (c->ready == 0u) {
        out->moment = fc_vec3_16_zero();
        out->attitude_error_rad = fc_vec3_zero();
        return FC_STEP_NOT_READY;
    }
    fc_arith *ar = &c->ar;
    const fc_attitude_control_params *p = &c->p;
    fc_step_status status = FC_STEP_OK;

    bool q_ok = false;
    bool qd_ok = false;
    const fc_quat16 q = quat16_unit(ar, in->attitude, &q_ok);
    const fc_quat16 qd = quat16_unit(ar, in->attitude_desired, &qd_ok);
    const fc_vec3 *rate = in->rate_radps;
    const fc_vec3 *rate_ff = in->rate_ff_radps;
    const bool rate_ff_ok = rate_valid(rate_ff);
    if (!rate_ff_ok) {
        status |= FC_STEP_BAD_INPUT; /* and the feed-forward is taken as zero */
    }

    fc_vec3 moment;
    if (!q_ok || !qd_ok || !rate_valid(rate)) {
        /* hold the last good moment, decaying to zero; integrals frozen */
        moment = fc_vec3_make(hold_decayed(ar, c->last_moment.x, c->hold_decay),
                              hold_decayed(ar, c->last_moment.y, c->hold_decay),
                              hold_decayed(ar, c->last_moment.z, c->hold_decay));
        status |= FC_STEP_BAD_INPUT;
    } else {
        const fc_real16 s = attitude_error(ar, &q, &qd, &c->last_error_rad);
        const fc_vec3 *err = &c->last_error_rad;
        /* the heading part weighted: 2 (yaw_weight s), a 32 x 16-bit product
         * (at the usual weight 1 the unweighted part, the same value) */
        fc_real head = err->z;
        if (p->yaw_weight != FC_INT(1, RATIO)) {
            const fc_real half_head = fc_mul_by16(ar, p->yaw_weight, s, FC_SHIFT(RATIO, UNIT16, ANGLE));
            head = fc_add(ar, half_head, half_head);
        }
        /* what the 16-bit products read: the error by its high halves (the
         * integral likewise, axis_moment), the rates rounded to RATE16. No
         * saturation test (fc_round16): ANGLE16 spans ANGLE's [-8, 8), and
         * the error is at most 2 (header; twice a product of unit vectors,
         * and the heading part weighted by yaw_weight <= 1) */
        const fc_vec3_16 e16 = {fc_round16(err->x, FC_ANGLE_FRAC, FC_ANGLE16_FRAC),
                                fc_round16(err->y, FC_ANGLE_FRAC, FC_ANGLE16_FRAC),
                                fc_round16(head, FC_ANGLE_FRAC, FC_ANGLE16_FRAC)};
        const fc_vec3 *integral = &c->integral_rad_s;
        const fc_vec3_16 w16 = {rate16(ar, rate->x), rate16(ar, rate->y), rate16(ar, rate->z)};
        const fc_real zero = FC_INT(0, RATE);
        const fc_vec3_16 r16 = {rate_error16(ar, rate->x, w16.x, rate_ff_ok ? rate_ff->x : zero),
                                rate_error16(ar, rate->y, w16.y, rate_ff_ok ? rate_ff->y : zero),
                                rate_error16(ar, rate->z, w16.z, rate_ff_ok ? rate_ff->z : zero)};
        const fc_vec3_16 *kp = &c->gain_p, *ki = &c->gain_i, *kd = &c->gain_d, *dj = &c->inertia_diff16;
        const fc_vec3 raw = fc_vec3_make(
            axis_moment(ar, kp->x, e16.x, ki->x, integral->x, kd->x, r16.x, gyroscopic(ar, dj->x, w16.y, w16.z)),
            axis_moment(ar, kp->y, e16.y, ki->y, integral->y, kd->y, r16.y, gyroscopic(ar, dj->y, w16.z, w16.x)),
            axis_moment(ar, kp->z, e16.z, ki->z, integral->z, kd->z, r16.z, gyroscopic(ar, dj->z, w16.x, w16.y)));
        moment = limit_moment(ar, raw, c->moment_limit_sum);
        if (!fc_vec3_is_finite(moment)) {
            /* cannot happen with validated parameters and bounded inputs */
            moment = fc_vec3_zero();
            ar->saturated = 1u;
        }
        if (moment.x != raw.x || moment.y != raw.y || moment.z != raw.z) {
            status |= FC_STEP_OUTPUT_LIMITED;
        }
        /* anti-windup: the allocation's report and this step's own clamp;
         * a hold keeps all three (with ki = 0 an integral is zero anyway) */
        if (c->integral_hold == 0u) {
            const uint8_t sat = in->allocation_saturation;
            const fc_real dt = p->dt_s;
            fc_vec3 *i = &c->integral_rad_s;
            i->x = integrate_axis(ar, i->x, e16.x, dt, p->ki_per_s3.x, p->integral_limit_rad.x, sat, FC_SAT_ROLL_NEG,
                                  FC_SAT_ROLL_POS, raw.x, moment.x);
            i->y = integrate_axis(ar, i->y, e16.y, dt, p->ki_per_s3.y, p->integral_limit_rad.y, sat, FC_SAT_PITCH_NEG,
                                  FC_SAT_PITCH_POS, raw.y, moment.y);
            i->z = integrate_axis(ar, i->z, e16.z, dt, p->ki_per_s3.z, p->integral_limit_rad.z, sat, FC_SAT_YAW_NEG,
                                  FC_SAT_YAW_POS, raw.z, moment.z);
        }
    }
    c->last_moment = moment;
    /* |moment| <= moment_limit <= MAX_MOMENT_LIMIT < 2, NORM16's range
     * (limit_moment's clamps, or a held moment decaying from one): no
     * saturation test */
    out->moment = (fc_vec3_16){fc_round16(moment.x, FC_NSUM_FRAC, FC_NORM16_FRAC),
                               fc_round16(moment.y, FC_NSUM_FRAC, FC_NORM16_FRAC),
                               fc_round16(moment.z, FC_NSUM_FRAC, FC_NORM16_FRAC)};
    /* by component: a struct copy is a byte loop at -Os on the ATmega */
    out->attitude_error_rad = fc_vec3_make(c->last_error_rad.x, c->last_error_rad.y, c->last_error_rad.z);
    if (ar->saturated != 0u) {
        status |= FC_STEP_ARITH_SATURATED;
    }
    return status;
}
