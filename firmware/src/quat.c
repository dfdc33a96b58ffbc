/* quat.c - unit quaternions (fc/quat.h). One source for both backends. */
#include "fc/quat.h"

/* shift of a product of two UNIT values giving a UNIT value */
#define UNIT_X_UNIT FC_SHIFT(UNIT, UNIT, UNIT)

/* |q|^2 this close to 1 is unit length to the resolution of the format: a
 * quaternion scaled to unit length by fc_quat_normalize, its four components
 * rounded, lands within 3.5 UNIT LSB of it (each rounding moves |q|^2 by
 * |q_i| LSB at most, the factor's rounding by 1 and the sum's by 1/2). In
 * float it is below half an ulp of 1: there it means |q|^2 == 1 exactly. */
#define UNIT_LENGTH_SQ_TOLERANCE FC_C(4.0f / 1073741824.0f, UNIT) /* 4 UNIT LSB, 3.7e-9 */

static fc_real twice(fc_arith *ar, fc_real a)
{
    return fc_add(ar, a, a);
}

fc_quat fc_quat_mul(fc_arith *ar, fc_quat p, fc_quat q)
{
    /* (2.8): each component is a 4-term dot product, rounded once */
    const fc_real w = fc_dot4(ar, p.w, q.w, fc_neg(ar, p.x), q.x, fc_neg(ar, p.y), q.y,
                              fc_neg(ar, p.z), q.z, UNIT_X_UNIT);
    const fc_real x = fc_dot4(ar, p.w, q.x, p.x, q.w, p.y, q.z, fc_neg(ar, p.z), q.y, UNIT_X_UNIT);
    const fc_real y = fc_dot4(ar, p.w, q.y, fc_neg(ar, p.x), q.z, p.y, q.w, p.z, q.x, UNIT_X_UNIT);
    const fc_real z = fc_dot4(ar, p.w, q.z, p.x, q.y, fc_neg(ar, p.y), q.x, p.z, q.w, UNIT_X_UNIT);
    return fc_quat_make(w, x, y, z);
}

fc_quat fc_quat_conj(fc_arith *ar, fc_quat q)
{
    return fc_quat_make(q.w, fc_neg(ar, q.x), fc_neg(ar, q.y), fc_neg(ar, q.z));
}

fc_real fc_quat_norm_sq(fc_arith *ar, fc_quat q)
{
    return fc_dot4(ar, q.w, q.w, q.x, q.x, q.y, q.y, q.z, q.z, UNIT_X_UNIT);
}

/* inlined: the shift is then a constant (a run-time shift is a loop on the ATmega) */
static inline __attribute__((always_inline)) fc_quat quat_scale(fc_arith *ar, fc_quat q, fc_real k, int shift)
{
    return fc_quat_make(fc_mul(ar, q.w, k, shift), fc_mul(ar, q.x, k, shift),
                        fc_mul(ar, q.y, k, shift), fc_mul(ar, q.z, k, shift));
}

bool fc_quat_is_finite(fc_quat q)
{
    return fc_is_finite(q.w) && fc_is_finite3(q.x, q.y, q.z);
}

fc_quat fc_quat_normalize(fc_arith *ar, fc_quat q, bool *ok)
{
    /* No finiteness test of the components first: a NaN or an infinity in
     * any of them makes |q|^2 NaN or +inf (a sum of squares, no inf - inf),
     * which the test of |q|^2 below rejects, with the same result. */
    /* A fixed quaternion longer than sqrt(2) would saturate |q|^2 in UNIT:
     * quarter it first (the direction is all that matters). */
    fc_arith probe = {0u};
    fc_real norm_sq = fc_quat_norm_sq(&probe, q);
    /* unit already (a quaternion this function returned, say), the common
     * case, first: scaling would move each component by rounding alone.
     * Such a |q|^2 is a number and far above the smallest taken below, so
     * the answer is the one the tests below give. */
    if (probe.saturated == 0u && fc_within(fc_sub(ar, FC_INT(1, UNIT), norm_sq), UNIT_LENGTH_SQ_TOLERANCE)) {
        *ok = true;
        return q;
    }
    if (probe.saturated != 0u) {
        q = quat_scale(ar, q, FC_C(0.25f, UNIT), UNIT_X_UNIT);
        norm_sq = fc_quat_norm_sq(ar, q);
    }
    if (!fc_is_finite(norm_sq) || norm_sq < FC_C(1.0e-4f, UNIT)) {
        *ok = false;
        return fc_quat_identity();
    }
    *ok = true;
    const fc_real one_minus_norm_sq = fc_sub(ar, FC_INT(1, UNIT), norm_sq);
    if (fc_within(one_minus_norm_sq, UNIT_LENGTH_SQ_TOLERANCE)) {
        /* unit already (a quaternion this function returned, say): scaling
         * would move each component by rounding alone */
        return q;
    }
    if (fc_abs(ar, one_minus_norm_sq) < FC_C(3.0e-5f, UNIT)) {
        /* |q|^2 = 1 - e: 1/|q| = 1 + e/2 + O(e^2), the O(e^2) below 1e-9 here */
        const fc_real inv_norm = fc_add(ar, FC_INT(1, UNIT),
                                        fc_mul(ar, one_minus_norm_sq, FC_C(0.5f, UNIT), UNIT_X_UNIT));
        return quat_scale(ar, q, inv_norm, UNIT_X_UNIT);
    }
    /* 1/|q| up to 100 (|q|^2 >= 1e-4): RATIO format */
    const fc_real inv_norm = fc_rsqrt(ar, norm_sq, FC_UNIT_FRAC, FC_RATIO_FRAC);
    return quat_scale(ar, q, inv_norm, FC_SHIFT(UNIT, RATIO, UNIT));
}

#if FC_NUMERIC_FIXED
/* fc_quat16_normalize in fixed (float: fc/quat.h) */

/* q rounded to the 16-bit format, saturated */
static fc_quat16 quat16_round(fc_arith *ar, fc_quat q)
{
    const fc_quat16 r = {fc_narrow16(ar, q.w, FC_UNIT_FRAC, FC_UNIT16_FRAC),
                         fc_narrow16(ar, q.x, FC_UNIT_FRAC, FC_UNIT16_FRAC),
                         fc_narrow16(ar, q.y, FC_UNIT_FRAC, FC_UNIT16_FRAC),
                         fc_narrow16(ar, q.z, FC_UNIT_FRAC, FC_UNIT16_FRAC)};
    return r;
}


/* FC_QUAT16_UNIT_SQ_TOLERANCE (fc/quat.h): a unit quaternion rounded to
 * UNIT16 lands within sum_i 2 |q_i| 2^-15 + 4 2^-30 <= 2^-13 + 2^-28 of
 * |q|^2 = 1 (sum_i |q_i| <= 2), a 32-bit one that is unit to a few Q30 LSB
 * within 2^-24 more. Such a q is within 2^-14 of unit length: 1 UNIT16 LSB at
 * most on a component. */
fc_quat16 fc_quat16_normalize(fc_arith *ar, fc_quat q, bool *ok)
{
    /* unit already at 16 bits (the usual case: a quaternion normalised
     * upstream): no 32-bit square. The rounding without its saturation test
     * (fc_quat16_round_unit): a component of 2 or more wraps to -2, whose
     * square is four times one, so that q fails the test below and takes
     * the long way. The squares sum unsigned (each at most 2^30; four of
     * -2 wrap the sum to 0, off by one all the same). */
    const fc_quat16 r = fc_quat16_round_unit(q);
    const uint32_t norm_sq =
        (uint32_t)fc_sq16(r.w) + (uint32_t)fc_sq16(r.x) + (uint32_t)fc_sq16(r.y) + (uint32_t)fc_sq16(r.z);
    const uint32_t one = (uint32_t)1u << FC_UNIT16_SQ_FRAC;
    const uint32_t off = norm_sq > one ? norm_sq - one : one - norm_sq;
    if (off <= (uint32_t)FC_QUAT16_UNIT_SQ_TOLERANCE) {
        *ok = true;
        return r;
    }
    return quat16_round(ar, fc_quat_normalize(ar, q, ok));
}
#endif

fc_quat16 fc_quat16_conj_mul(fc_arith *ar, fc_quat16 p, fc_quat16 q)
{
    /* (2.8) with p's vector part negated; the products of two UNIT16 values
     * are UNIT16_SQ, each sum rounded once to UNIT16 */
    const int sq = FC_UNIT16_SQ_FRAC, to = FC_UNIT16_FRAC;
    const fc_quat16 r = {
        fc_dot4_16(ar, p.w, q.w, p.x, q.x, p.y, q.y, p.z, q.z, sq, to),
        fc_dot4_16(ar, p.w, q.x, fc_neg16(p.x), q.w, fc_neg16(p.y), q.z, p.z, q.y, sq, to),
        fc_dot4_16(ar, p.w, q.y, p.x, q.z, fc_neg16(p.y), q.w, fc_neg16(p.z), q.x, sq, to),
        fc_dot4_16(ar, p.w, q.z, fc_neg16(p.x), q.y, p.y, q.x, fc_neg16(p.z), q.w, sq, to)};
    return r;
}

fc_quat16 fc_quat16_shortest(fc_quat16 q)
{
    if (q.w < FC_INT16(0, UNIT16)) {
        const fc_quat16 r = {fc_neg16(q.w), fc_neg16(q.x), fc_neg16(q.y), fc_neg16(q.z)};
        return r;
    }
    return q;
}

fc_quat fc_quat_shortest(fc_arith *ar, fc_quat q)
{
    if (q.w < FC_INT(0, UNIT)) {
        return fc_quat_make(fc_neg(ar, q.w), fc_neg(ar, q.x), fc_neg(ar, q.y), fc_neg(ar, q.z));
    }
    return q;
}

/* The entries of R(q) in UNIT (|r_ij| <= 1). The diagonal 1 - 2(..): the
 * same matrix as v + 2w (u x v) + 2 u x (u x v), also for a q that is unit
 * only to its rounding. The products inline, their shift a constant. */
static void rotation_matrix(fc_arith *ar, fc_quat q, fc_real r[3][3])
{
    const fc_real xx = fc_mul_inline(ar, q.x, q.x, UNIT_X_UNIT);
    const fc_real yy = fc_mul_inline(ar, q.y, q.y, UNIT_X_UNIT), zz = fc_mul_inline(ar, q.z, q.z, UNIT_X_UNIT);
    const fc_real xy = fc_mul_inline(ar, q.x, q.y, UNIT_X_UNIT), xz = fc_mul_inline(ar, q.x, q.z, UNIT_X_UNIT);
    const fc_real yz = fc_mul_inline(ar, q.y, q.z, UNIT_X_UNIT), wx = fc_mul_inline(ar, q.w, q.x, UNIT_X_UNIT);
    const fc_real wy = fc_mul_inline(ar, q.w, q.y, UNIT_X_UNIT), wz = fc_mul_inline(ar, q.w, q.z, UNIT_X_UNIT);
    const fc_real half = FC_C(0.5f, UNIT); /* 2 (1/2 - ..) keeps every intermediate in [-1, 1] */
    r[0][0] = twice(ar, fc_sub(ar, half, fc_add(ar, yy, zz)));
    r[0][1] = twice(ar, fc_sub(ar, xy, wz));
    r[0][2] = twice(ar, fc_add(ar, xz, wy));
    r[1][0] = twice(ar, fc_add(ar, xy, wz));
    r[1][1] = twice(ar, fc_sub(ar, half, fc_add(ar, xx, zz)));
    r[1][2] = twice(ar, fc_sub(ar, yz, wx));
    r[2][0] = twice(ar, fc_sub(ar, xz, wy));
    r[2][1] = twice(ar, fc_add(ar, yz, wx));
    r[2][2] = twice(ar, fc_sub(ar, half, fc_add(ar, xx, yy)));
}

/* Row i of R(q) times v: one 64-bit dot product, so a vector anywhere in its
 * format rotates without an intermediate leaving it (the two-cross-product
 * form's 2 q_v x v does). */
static fc_real rotated_component(fc_arith *ar, const fc_real row[3], fc_vec3 v)
{
    return fc_dot3(ar, row[0], v.x, row[1], v.y, row[2], v.z, FC_UNIT_FRAC);
}

fc_vec3 fc_quat_rotate(fc_arith *ar, fc_quat q, fc_vec3 v)
{
    fc_real r[3][3];
    rotation_matrix(ar, q, r);
    return fc_vec3_make(rotated_component(ar, r[0], v), rotated_component(ar, r[1], v),
                        rotated_component(ar, r[2], v));
}

/* 2 sum + offset of UNIT16 products (UNIT16_SQ, exact), rounded to a UNIT16
 * entry of R(q): |entry| <= 1 + 2^-12 for a q within 2^-13 of unit length,
 * inside UNIT16's [-2, 2), and the sum of two products bounded by 1 stays
 * far inside 32 bits. */
static fc_real16 matrix_entry16(fc_arith *ar, fc_real sum, fc_real offset)
{
    return fc_narrow16(ar, 2 * sum + offset, FC_UNIT16_SQ_FRAC, FC_UNIT16_FRAC);
}

/* Row of R(q) times v: three 32 x 16 products, the vector's format kept. */
static fc_real rotated_component16(fc_arith *ar, fc_real16 r0, fc_real16 r1, fc_real16 r2, fc_vec3 v)
{
    const int keep = FC_UNIT16_FRAC; /* v (any format) x UNIT16 -> v's format */
    return fc_add_inline(ar, fc_add_inline(ar, fc_mul_by16(ar, v.x, r0, keep), fc_mul_by16(ar, v.y, r1, keep)),
                  fc_mul_by16(ar, v.z, r2, keep));
}

fc_vec3 fc_quat_rotate_horizontal(fc_arith *ar, fc_quat q, fc_vec3 v)
{
    /* R(q)'s first two rows as rotation_matrix forms them, from q rounded
     * to UNIT16: nine 16 x 16 products */
    const fc_quat16 h = fc_quat16_round_unit(q);
    const fc_real xx = fc_mul16(h.x, h.x), yy = fc_mul16(h.y, h.y), zz = fc_mul16(h.z, h.z);
    const fc_real xy = fc_mul16(h.x, h.y), xz = fc_mul16(h.x, h.z), yz = fc_mul16(h.y, h.z);
    const fc_real wx = fc_mul16(h.w, h.x), wy = fc_mul16(h.w, h.y), wz = fc_mul16(h.w, h.z);
    const fc_real one = FC_INT(1, UNIT16_SQ), zero = FC_INT(0, UNIT16_SQ);
    return fc_vec3_make(rotated_component16(ar, matrix_entry16(ar, -(yy + zz), one), matrix_entry16(ar, xy - wz, zero),
                                            matrix_entry16(ar, xz + wy, zero), v),
                        rotated_component16(ar, matrix_entry16(ar, xy + wz, zero), matrix_entry16(ar, -(xx + zz), one),
                                            matrix_entry16(ar, yz - wx, zero), v),
                        FC_INT(0, UNIT));
}

fc_vec3 fc_quat_rotate_inv(fc_arith *ar, fc_quat q, fc_vec3 v)
{
    return fc_quat_rotate(ar, fc_quat_conj(ar, q), v);
}

fc_quat fc_quat_from_axis_angle(fc_arith *ar, fc_vec3 axis_unit, fc_real angle_rad)
{
    const fc_real half_angle = fc_mul(ar, angle_rad, FC_C(0.5f, UNIT), FC_SHIFT(ANGLE, UNIT, ANGLE));
    fc_real s, c;
    fc_sincos(ar, half_angle, &s, &c);
    const fc_vec3 v = fc_vec3_scale(ar, axis_unit, s, UNIT_X_UNIT);
    return fc_quat_make(c, v.x, v.y, v.z);
}

void fc_quat_to_axis_angle(fc_arith *ar, fc_quat q, fc_vec3 *axis_unit, fc_real *angle_rad)
{
    const fc_quat qs = fc_quat_shortest(ar, q);
    const fc_vec3 v = fc_quat_vector_part(qs);
    const fc_real sin_half = fc_vec3_norm(ar, v, FC_UNIT_FRAC);
    bool ok = false;
    const fc_vec3 axis = fc_vec3_normalize(ar, v, FC_UNIT_FRAC, &ok);
    *axis_unit = ok ? axis : fc_vec3_make(FC_INT(1, UNIT), FC_INT(0, UNIT), FC_INT(0, UNIT));
    /* angle = 2 atan2(|v|, w), w >= 0 so the angle is in [0, pi] */
    const fc_real half_angle = fc_atan2(ar, sin_half, qs.w);
    *angle_rad = fc_add(ar, half_angle, half_angle);
}

/* A level of fc_quat_from_rotation_vector's series: 1 - a2 c v, UNIT, v the
 * value of the level inside it; without one (nested false) v is 1, with no
 * product by it. */
static fc_real series_level(fc_arith *ar, fc_real a2, fc_real c, bool nested, fc_real v)
{
    const fc_real term = fc_mul(ar, a2, c, UNIT_X_UNIT);
    return fc_sub(ar, FC_INT(1, UNIT), nested ? fc_mul(ar, term, v, UNIT_X_UNIT) : term);
}

fc_quat fc_quat_from_rotation_vector(fc_arith *ar, fc_vec3 theta_rad)
{
    /* a^2 first: the branch is taken on a^2 < 1/4, so the small angles of a
     * step (|w| dt, 0.17 rad at 3.5 rad/s and 50 ms) need no root; a^2 of
     * an angle beyond sqrt(2) does not fit UNIT and takes the other branch
     * (its saturation in a probe, not reported) */
    fc_arith probe = {0u};
    const fc_real a2 = fc_vec3_dot(&probe, theta_rad, theta_rad, FC_SHIFT(ANGLE, ANGLE, UNIT));
    fc_real cos_half;          /* cos(a/2), UNIT */
    fc_real sin_half_over_a;   /* sin(a/2)/a, UNIT */
    if (probe.saturated == 0u && a2 < FC_C(0.25f, UNIT)) {
        /* series in a^2, nested (no division, and exact at a = 0 where
         * sin(a/2)/a is 0/0):
         *   cos(a/2)   = 1 - a^2/8 (1 - a^2/48 (1 - a^2/120))
         *   sin(a/2)/a = 1/2 (1 - a^2/24 (1 - a^2/80 (1 - a^2/168)))
         * cut after the last level that reaches 2^-45 (1/2^15 of a UNIT LSB):
         * all three for a < 0.5 rad (truncation below 4e-10), two below
         * a^2 = 2^-10 (a < 0.031 rad, 16 rad/s over a 2 ms step: a^6/46080 <
         * 2^-45), one below 2^-20 (a < 1e-3: a^4/384 < 2^-48); 11, 7 and 3
         * products */
        const bool third = a2 >= FC_C(1.0f / 1024.0f, UNIT);
        const bool second = a2 >= FC_C(1.0f / 1048576.0f, UNIT);
        fc_real cos_tail = FC_INT(1, UNIT);
        fc_real sin_tail = FC_INT(1, UNIT);
        if (third) {
            cos_tail = series_level(ar, a2, FC_C(1.0f / 120.0f, UNIT), false, cos_tail);
            sin_tail = series_level(ar, a2, FC_C(1.0f / 168.0f, UNIT), false, sin_tail);
        }
        if (second) {
            cos_tail = series_level(ar, a2, FC_C(1.0f / 48.0f, UNIT), third, cos_tail);
            sin_tail = series_level(ar, a2, FC_C(1.0f / 80.0f, UNIT), third, sin_tail);
        }
        cos_half = series_level(ar, a2, FC_C(1.0f / 8.0f, UNIT), second, cos_tail);
        sin_tail = series_level(ar, a2, FC_C(1.0f / 24.0f, UNIT), second, sin_tail);
        sin_half_over_a = fc_mul(ar, sin_tail, FC_C(0.5f, UNIT), UNIT_X_UNIT);
    } else {
        const fc_real angle = fc_vec3_norm(ar, theta_rad, FC_ANGLE_FRAC);
        const fc_real half_angle = fc_mul(ar, angle, FC_C(0.5f, UNIT), FC_SHIFT(ANGLE, UNIT, ANGLE));
        fc_real sin_half;
        fc_sincos(ar, half_angle, &sin_half, &cos_half);
        sin_half_over_a = fc_div(ar, sin_half, angle, FC_DIV_SHIFT(UNIT, ANGLE, UNIT));
    }
    /* (sin(a/2)/a) theta: UNIT times ANGLE is the UNIT vector part */
    const fc_vec3 v = fc_vec3_scale(ar, theta_rad, sin_half_over_a, FC_SHIFT(ANGLE, UNIT, UNIT));
    return fc_quat_make(cos_half, v.x, v.y, v.z);
}

fc_quat fc_quat_from_rpy(fc_arith *ar, fc_real roll_rad, fc_real pitch_rad, fc_real yaw_rad)
{
    const int half_shift = FC_SHIFT(ANGLE, UNIT, ANGLE);
    const fc_real half_roll = fc_mul(ar, roll_rad, FC_C(0.5f, UNIT), half_shift);
    const fc_real half_pitch = fc_mul(ar, pitch_rad, FC_C(0.5f, UNIT), half_shift);
    const fc_real half_yaw = fc_mul(ar, yaw_rad, FC_C(0.5f, UNIT), half_shift);
    fc_real cr, sr, cp, sp, cy, sy;
    fc_sincos(ar, half_roll, &sr, &cr);
    fc_sincos(ar, half_pitch, &sp, &cp);
    fc_sincos(ar, half_yaw, &sy, &cy);
    /* q = q_z(yaw) (x) q_y(pitch) (x) q_x(roll), expanded */
    const fc_real cp_cy = fc_mul(ar, cp, cy, UNIT_X_UNIT), sp_sy = fc_mul(ar, sp, sy, UNIT_X_UNIT);
    const fc_real sp_cy = fc_mul(ar, sp, cy, UNIT_X_UNIT), cp_sy = fc_mul(ar, cp, sy, UNIT_X_UNIT);
    return fc_quat_make(fc_dot2(ar, cr, cp_cy, sr, sp_sy, UNIT_X_UNIT),
                        fc_dot2(ar, sr, cp_cy, fc_neg(ar, cr), sp_sy, UNIT_X_UNIT),
                        fc_dot2(ar, cr, sp_cy, sr, cp_sy, UNIT_X_UNIT),
                        fc_dot2(ar, cr, cp_sy, fc_neg(ar, sr), sp_cy, UNIT_X_UNIT));
}

/* cos(a/2) and sin(a/2) (UNIT) of the angle a in [-pi, pi] whose cosine and
 * sine are cos_a and sin_a, each from whichever half-angle root is far from
 * 0 (a root near 0 would turn one LSB of cos a into sqrt(LSB)): for cos a >=
 * 0, c = sqrt((1 + cos a) / 2) >= 1/sqrt(2) and s = (sin a / 2) / c; else
 * s = +-sqrt((1 - cos a) / 2) with the sign of sin a and c = (sin a / 2) / s
 * (a = pi: s > 0, c = 0). 1/2 +- (cos a) / 2 stays within UNIT's range. */
static void half_angle_of(fc_arith *ar, fc_real cos_a, fc_real sin_a, fc_real *cos_half, fc_real *sin_half)
{
    const fc_real half_cos = fc_mul(ar, cos_a, FC_C(0.5f, UNIT), UNIT_X_UNIT);
    const fc_real half_sin = fc_mul(ar, sin_a, FC_C(0.5f, UNIT), UNIT_X_UNIT);
    if (cos_a >= FC_INT(0, UNIT)) {
        *cos_half = fc_sqrt(ar, fc_add(ar, FC_C(0.5f, UNIT), half_cos), FC_UNIT_FRAC);
        *sin_half = fc_div(ar, half_sin, *cos_half, FC_UNIT_FRAC);
        return;
    }
    const fc_real root = fc_sqrt(ar, fc_sub(ar, FC_C(0.5f, UNIT), half_cos), FC_UNIT_FRAC);
    *sin_half = sin_a < FC_INT(0, UNIT) ? fc_neg(ar, root) : root;
    *cos_half = fc_div(ar, half_sin, *sin_half, FC_UNIT_FRAC);
}

/* up_body = |up| (-sin pitch, sin roll cos pitch, cos roll cos pitch) for
 * q = q_z(yaw) q_y(pitch) q_x(roll), pitch in [-pi/2, pi/2]: with h =
 * |(up.y, up.z)| = |up| cos pitch, the cosines and sines of roll and pitch
 * are up.z/h, up.y/h, h/|up| and -up.x/|up|; their half angles give
 * q_y(pitch) q_x(roll) = (cp cr, cp sr, sp cr, -sp sr) (c, s: of the half
 * angles), and the yaw's q_z multiplies from the left. */
fc_quat fc_quat_from_up(fc_arith *ar, fc_vec3 up_body, fc_real yaw_rad)
{
    const fc_real length = fc_hypot3(ar, up_body.x, up_body.y, up_body.z);
    if (!(length > FC_INT(0, UNIT))) {
        return fc_quat_identity();
    }
    const fc_real h = fc_hypot3(ar, up_body.y, up_body.z, FC_INT(0, UNIT));
    fc_real cos_roll = FC_INT(1, UNIT), sin_roll = FC_INT(0, UNIT);
    if (h > FC_INT(0, UNIT)) {
        cos_roll = fc_div(ar, up_body.z, h, FC_UNIT_FRAC);
        sin_roll = fc_div(ar, up_body.y, h, FC_UNIT_FRAC);
    }
    const fc_real cos_pitch = fc_div(ar, h, length, FC_UNIT_FRAC);
    const fc_real sin_pitch = fc_div(ar, fc_neg(ar, up_body.x), length, FC_UNIT_FRAC);
    fc_real cr, sr, cp, sp;
    half_angle_of(ar, cos_roll, sin_roll, &cr, &sr);
    half_angle_of(ar, cos_pitch, sin_pitch, &cp, &sp);
    fc_quat q = fc_quat_make(fc_mul(ar, cp, cr, UNIT_X_UNIT), fc_mul(ar, cp, sr, UNIT_X_UNIT),
                             fc_mul(ar, sp, cr, UNIT_X_UNIT), fc_neg(ar, fc_mul(ar, sp, sr, UNIT_X_UNIT)));
    if (yaw_rad != FC_INT(0, ANGLE)) {
        fc_real sy, cy;
        fc_sincos(ar, fc_mul(ar, yaw_rad, FC_C(0.5f, UNIT), FC_SHIFT(ANGLE, UNIT, ANGLE)), &sy, &cy);
        q = fc_quat_mul(ar, fc_quat_make(cy, FC_INT(0, UNIT), FC_INT(0, UNIT), sy), q);
    }
    /* unit already, but for a vector whose lengths saturate (fixed) or whose
     * squares leave the float range: then the cosines and sines are no pair */
    bool ok;
    const fc_quat unit = fc_quat_normalize(ar, q, &ok);
    return ok ? unit : fc_quat_identity();
}

fc_vec3 fc_quat_to_rpy(fc_arith *ar, fc_quat q)
{
    const fc_real roll_num = twice(ar, fc_dot2(ar, q.w, q.x, q.y, q.z, UNIT_X_UNIT));
    const fc_real roll_den =
        fc_sub(ar, FC_INT(1, UNIT), twice(ar, fc_dot2(ar, q.x, q.x, q.y, q.y, UNIT_X_UNIT)));
    const fc_real sin_pitch = twice(ar, fc_dot2(ar, q.w, q.y, fc_neg(ar, q.z), q.x, UNIT_X_UNIT));
    const fc_real yaw_num = twice(ar, fc_dot2(ar, q.w, q.z, q.x, q.y, UNIT_X_UNIT));
    const fc_real yaw_den =
        fc_sub(ar, FC_INT(1, UNIT), twice(ar, fc_dot2(ar, q.y, q.y, q.z, q.z, UNIT_X_UNIT)));
    return fc_vec3_make(fc_atan2(ar, roll_num, roll_den), fc_asin(ar, sin_pitch),
                        fc_atan2(ar, yaw_num, yaw_den));
}

/* The rotation over one step of a constant rate: exp(rate dt / 2). */
static fc_quat step_rotation(fc_arith *ar, fc_vec3 rate_radps, fc_real dt_s)
{
    const fc_vec3 theta = fc_vec3_scale(ar, rate_radps, dt_s, FC_SHIFT(RATE, DT, ANGLE));
    return fc_quat_from_rotation_vector(ar, theta);
}

static fc_quat renormalised_or(fc_arith *ar, fc_quat candidate, fc_quat fallback)
{
    bool ok = false;
    const fc_quat n = fc_quat_normalize(ar, candidate, &ok);
    return ok ? n : fallback;
}

fc_quat fc_quat_integrate_body_rate(fc_arith *ar, fc_quat q, fc_vec3 rate_body_radps, fc_real dt_s)
{
    const fc_quat dq = step_rotation(ar, rate_body_radps, dt_s);
    return renormalised_or(ar, fc_quat_mul(ar, q, dq), q);
}

/* ---- the filter's step (fc_quat_advance_body_rate) ---------------------- */

/* Half the length error of a step's p, (|p|^2 - 1) / 2, as the 16-bit value
 * the Newton step multiplies: within 2^-11, 1.5e-8 an LSB. */
#define FC_HALF_LENGTH_ERROR16_FRAC 26
/* The Newton step takes |p|^2 within 3 2^-12 of 1 (the half error then fits
 * its 16 bits with the cross terms' share): it leaves |p|^2 off by
 * 3/4 (|p|^2 - 1)^2 <= 7e-6, which the next step removes with its own. */
#define NEWTON_WINDOW_UNIT16_SQ FC_C(3.0f / 4096.0f, UNIT16_SQ)
/* The 16-bit step takes half-angles w_i dt / 2 up to 2^-5 rad (31 rad/s at
 * 500 Hz); beyond, the exponential map. */
#define MAX_HALF_ANGLE_RAD FC_C(0.03125f, UNIT)

#if FC_NUMERIC_FIXED
/* fc_quat16_round_unit and low_half split a UNIT value at bit 16 */
_Static_assert(FC_UNIT_FRAC - FC_UNIT16_FRAC == 16, "UNIT16 is not UNIT's high half");

/* The high half of v rounded (v + 2^15 read from bit 16: fc_narrow16 to 16
 * bits less, for a v that cannot saturate it) */
static fc_real16 high_half(fc_real v)
{
    return (fc_real16)(uint16_t)(((uint32_t)v + 0x8000u) >> 16);
}

/* The low half of v as a signed 16-bit value: v - 2^16 h for h the rounded
 * high half (fc_narrow16 to 16 bits less), in [-2^15, 2^15). */
static fc_real16 low_half(fc_real v)
{
    return (fc_real16)(uint16_t)(uint32_t)v;
}

/* (|p|^2 - 1) / 2 from the halves of p's components: p_i = 2^16 h_i + l_i,
 * h_i = p_i rounded to UNIT16 (into *high), |l_i| <= 2^15. In UNIT,
 * p_i^2 = 4 h_i^2 + h_i l_i / 2^13 + l_i^2 / 2^30: the last, below one LSB,
 * is left out (|p|^2 is then up to 4 LSB low), the others are 16 x 16
 * products. False when |p|^2 is further than the window from 1. p is within
 * 2^-4 of a unit quaternion: its components round without saturation and
 * the sums stay far inside 32 bits. */
static bool half_length_error(const fc_quat *p, fc_quat16 *high, fc_real16 *error)
{
    const fc_quat16 h = fc_quat16_round_unit(*p);
    const fc_real squares_off =
        fc_sumsq2_16(h.w, h.x) + fc_sumsq2_16(h.y, h.z) - FC_INT(1, UNIT16_SQ); /* UNIT16_SQ */
    if (!fc_within(squares_off, NEWTON_WINDOW_UNIT16_SQ)) {
        return false;
    }
    /* sum_i |h_i l_i| <= 2^15 sum_i |h_i| <= 2^30 (sum_i |p_i| <= 2 |p|) */
    const fc_real cross = fc_dot2_16(h.w, low_half(p->w), h.x, low_half(p->x)) +
                          fc_dot2_16(h.y, low_half(p->y), h.z, low_half(p->z));
    fc_arith never = {0u};
    const fc_real length_error = 4 * squares_off + fc_convert(&never, cross, FC_UNIT_FRAC + 13, FC_UNIT_FRAC);
    /* halved by reading it one FRAC finer; below 2^-11 + 2^-13: inside 16 bits */
    *error = (fc_real16)fc_convert(&never, length_error, FC_UNIT_FRAC + 1, FC_HALF_LENGTH_ERROR16_FRAC);
    *high = h;
    return true;
}
#else
static bool half_length_error(const fc_quat *p, fc_quat16 *high, fc_real16 *error)
{
    fc_arith none = {0u};
    const fc_real off = fc_quat_norm_sq(&none, *p) - 1.0f;
    *high = *p;
    *error = 0.5f * off;
    return fc_within(off, NEWTON_WINDOW_UNIT16_SQ);
}
#endif

/* The components of q (x) [0, v] = [-v . w, s w + v x w] (2.8) for 16-bit
 * q and v: each sum exact, in the format whose FRAC is the sum of the
 * operands' (|q| <= 1 + 2^-13, |v_i| <= 2^15 LSB: every sum below 2^30).
 * Operands by address, one component at a time: the ATmega keeps the
 * products in registers. */
static inline __attribute__((always_inline)) fc_real times_vector16_w(const fc_quat16 *q, const fc_vec3_16 *v)
{
    return -(fc_dot2_16(q->x, v->x, q->y, v->y) + fc_mul16(q->z, v->z));
}

static inline __attribute__((always_inline)) fc_real times_vector16_x(const fc_quat16 *q, const fc_vec3_16 *v)
{
    return fc_dot2_16(q->w, v->x, q->y, v->z) - fc_mul16(q->z, v->y);
}

static inline __attribute__((always_inline)) fc_real times_vector16_y(const fc_quat16 *q, const fc_vec3_16 *v)
{
    return fc_dot2_16(q->w, v->y, q->z, v->x) - fc_mul16(q->x, v->z);
}

static inline __attribute__((always_inline)) fc_real times_vector16_z(const fc_quat16 *q, const fc_vec3_16 *v)
{
    return fc_dot2_16(q->w, v->z, q->x, v->y) - fc_mul16(q->y, v->x);
}

#if FC_NUMERIC_FIXED
/* q_i + (q16 (x) [0, hi])_i + (q16 (x) [0, lo])_i: the first product UNIT
 * itself (UNIT16 x Q16), the second (UNIT16 x Q32, Q46) rounded to UNIT by
 * taking its high half */
static inline __attribute__((always_inline)) fc_real split_sum(fc_real q_i, fc_real by_hi, fc_real by_lo)
{
    return q_i + by_hi + fc_round16(by_lo, FC_UNIT16_FRAC + FC_UNIT_FRAC + 2, FC_UNIT_FRAC);
}

/* p = q + q16 (x) [0, theta] for theta = 2^16 hi + lo in Q32 (add_increment),
 * one component of p at a time: its six products and its sum stay in
 * registers, and only p is stored */
static inline __attribute__((always_inline)) void add_split_increment(const fc_quat *q, const fc_quat16 *q16,
                                                                     const fc_vec3_16 *hi, const fc_vec3_16 *lo,
                                                                     fc_quat *p)
{
    p->w = split_sum(q->w, times_vector16_w(q16, hi), times_vector16_w(q16, lo));
    p->x = split_sum(q->x, times_vector16_x(q16, hi), times_vector16_x(q16, lo));
    p->y = split_sum(q->y, times_vector16_y(q16, hi), times_vector16_y(q16, lo));
    p->z = split_sum(q->z, times_vector16_z(q16, hi), times_vector16_z(q16, lo));
}
#endif

/* p = q + q (x) [0, theta] in UNIT for the half-angle theta (UNIT, |theta_i|
 * <= 2^-5), q rounded to UNIT16 in the product: in fixed theta is read in
 * Q32 (four times its UNIT value, below 2^27: exact) as 2^16 hi + lo, hi
 * rounded (theta in Q16) and lo the rest in Q32 as 16 bits, so that q16 hi
 * is UNIT itself and q16 lo (Q46) is rounded to UNIT by taking its high
 * half; the sum is q16 (x) theta rounded once, as from any other split.
 * |q_i| <= 1 and the increment within 2^-4: p stays far inside the format. */
static void add_increment(const fc_quat *q, fc_vec3 theta, fc_quat *p)
{
    const fc_quat16 q16 = fc_quat16_round_unit(*q);
#if FC_NUMERIC_FIXED
    const int q32 = FC_UNIT_FRAC + 2;
    /* |theta_i| <= 2^-5: at most 2^27 in Q32 */
    const fc_vec3 theta32 = fc_vec3_make(fc_widen_bounded(theta.x, FC_UNIT_FRAC, q32),
                                         fc_widen_bounded(theta.y, FC_UNIT_FRAC, q32),
                                         fc_widen_bounded(theta.z, FC_UNIT_FRAC, q32));
    const fc_vec3_16 hi = {high_half(theta32.x), high_half(theta32.y), high_half(theta32.z)};
    const fc_vec3_16 lo = {low_half(theta32.x), low_half(theta32.y), low_half(theta32.z)};
    add_split_increment(q, &q16, &hi, &lo, p);
#else
    p->w = q->w + times_vector16_w(&q16, &theta);
    p->x = q->x + times_vector16_x(&q16, &theta);
    p->y = q->y + times_vector16_y(&q16, &theta);
    p->z = q->z + times_vector16_z(&q16, &theta);
#endif
}

/* The rare paths of fc_quat_advance_body_rate out of line, their operands
 * by address: the quaternions they pass by value stay out of the step's
 * frame; cold, so that the step's code is laid out for the common path.
 * q <- q (x) exp(rate dt / 2) by the exponential map: */
static __attribute__((noinline, cold)) void advance_by_exponential(fc_arith *ar, fc_quat *q,
                                                                   const fc_vec3 *rate_radps, fc_real half_dt_s)
{
    *q = fc_quat_integrate_body_rate(ar, *q, *rate_radps, fc_add(ar, half_dt_s, half_dt_s));
}

/* q <- p normalised, q kept when p has no direction: */
static __attribute__((noinline, cold)) void renormalise_into(fc_arith *ar, fc_quat *q, const fc_quat *p)
{
    *q = renormalised_or(ar, *p, *q);
}

void fc_quat_advance_body_rate(fc_arith *ar, fc_quat *q, const fc_vec3 *rate_radps, fc_real half_dt_s)
{
    /* the half-angle of the step, w dt / 2; a rate whose half-angle leaves
     * UNIT (beyond 2 rad) saturates the probe, and takes the exponential map */
    fc_arith probe = {0u};
    const int to_unit = FC_SHIFT(RATE, DT, UNIT);
    const fc_vec3 theta = fc_vec3_make(fc_mul_inline(&probe, rate_radps->x, half_dt_s, to_unit),
                                       fc_mul_inline(&probe, rate_radps->y, half_dt_s, to_unit),
                                       fc_mul_inline(&probe, rate_radps->z, half_dt_s, to_unit));
    if (probe.saturated != 0u || !fc_vec3_within(theta, MAX_HALF_ANGLE_RAD)) {
        advance_by_exponential(ar, q, rate_radps, half_dt_s);
        return;
    }
    fc_quat p;
    add_increment(q, theta, &p);
    fc_quat16 p16;
    fc_real16 e;
    if (!half_length_error(&p, &p16, &e)) {
        renormalise_into(ar, q, &p);
        return;
    }
    if (e == FC_INT16(0, UNIT16)) {
        /* unit to the resolution of e (a slow turn's step): p - p16 0; by
         * component (a struct copy is a byte loop at -Os on the ATmega) */
        q->w = p.w;
        q->x = p.x;
        q->y = p.y;
        q->z = p.z;
        return;
    }
    /* p (1 - e) = p - p16 e: the product of the rounded p is off by
     * 2^-15 |e| <= 2^-26 */
    const int from = FC_UNIT16_FRAC + FC_HALF_LENGTH_ERROR16_FRAC;
    fc_arith never = {0u};
    q->w = p.w - fc_convert(&never, fc_mul16(p16.w, e), from, FC_UNIT_FRAC);
    q->x = p.x - fc_convert(&never, fc_mul16(p16.x, e), from, FC_UNIT_FRAC);
    q->y = p.y - fc_convert(&never, fc_mul16(p16.y, e), from, FC_UNIT_FRAC);
    q->z = p.z - fc_convert(&never, fc_mul16(p16.z, e), from, FC_UNIT_FRAC);
}

fc_quat fc_quat_integrate_world_rate(fc_arith *ar, fc_quat q, fc_vec3 rate_world_radps, fc_real dt_s)
{
    const fc_quat dq = step_rotation(ar, rate_world_radps, dt_s);
    return renormalised_or(ar, fc_quat_mul(ar, dq, q), q);
}
