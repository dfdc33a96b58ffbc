/*
 * fc/quat.h - unit quaternions (Hamilton convention, scalar first).
 *
 * Components are in UNIT format. Convention used throughout the library:
 * q is the attitude of the body in the world frame (body -> world), so a
 * body-frame vector v_b is seen in the world as  v_w = q (x) [0, v_b] (x) q*.
 * Its kinematics are  q' = 1/2 [0, w_world] (x) q = 1/2 q (x) [0, w_body],
 * the first being the dissertation's form under (2.1) with w in {0}.
 * World frame ENU (z up), body frame FLU (dissertation 2.2).
 */
#ifndef FC_QUAT_H
#define FC_QUAT_H

#include "fc/vec3.h"

typedef struct fc_quat {
    fc_real w, x, y, z;
} fc_quat;

static inline fc_quat fc_quat_make(fc_real w, fc_real x, fc_real y, fc_real z)
{
    const fc_quat q = {w, x, y, z};
    return q;
}

static inline fc_quat fc_quat_identity(void)
{
    return fc_quat_make(FC_INT(1, UNIT), FC_INT(0, UNIT), FC_INT(0, UNIT), FC_INT(0, UNIT));
}

static inline fc_vec3 fc_quat_vector_part(fc_quat q)
{
    return fc_vec3_make(q.x, q.y, q.z);
}

/* Hamilton product p (x) q (2.7), (2.8): first rotate by q, then by p. */
fc_quat fc_quat_mul(fc_arith *ar, fc_quat p, fc_quat q);

/* q* = [w, -x, -y, -z]. */
fc_quat fc_quat_conj(fc_arith *ar, fc_quat q);

/* w^2 + x^2 + y^2 + z^2 in UNIT. */
fc_real fc_quat_norm_sq(fc_arith *ar, fc_quat q);

/* q / |q|. A quaternion of zero (or non-finite) length gives the identity and
 * *ok = false; otherwise *ok = true. Near unit length (the usual case after
 * one integration step) it costs no division and no square root. */
fc_quat fc_quat_normalize(fc_arith *ar, fc_quat q, bool *ok);

/* The same rotation with w >= 0 (the shortest path: rotation angle <= pi). */
fc_quat fc_quat_shortest(fc_arith *ar, fc_quat q);

/*
 * A unit quaternion in the 16-bit format (fc/scalar.h: UNIT16 in fixed,
 * 6.1e-5 a component; float as fc_quat), for the attitude error: its product
 * is 16 products of 16 bits. Made by fc_quat16_normalize (or as the product
 * of two such), so its components stay within 1 + 2^-13 and the sums of
 * fc_quat16_conj_mul within 32 bits.
 */
#if FC_NUMERIC_FIXED
typedef struct fc_quat16 {
    fc_real16 w, x, y, z;
} fc_quat16;
#else
typedef fc_quat fc_quat16; /* the same floats: no copies between the two */
#endif

/* fc_quat_normalize(q) in the 16-bit format, the same *ok. Fixed: q rounded
 * to UNIT16 as it is when that has |q|^2 within 2^-13 + 2^-24 of 1 (any unit
 * quaternion does: its rounding moves |q|^2 by 2^-13 at most), else
 * normalised in 32 bits first; components within 1.5 UNIT16 LSB of q/|q|.
 * Float: fc_quat_normalize itself (inlined). */
#if FC_NUMERIC_FIXED
fc_quat16 fc_quat16_normalize(fc_arith *ar, fc_quat q, bool *ok);

/* UNIT16_SQ: |q|^2 of a UNIT16 quaternion this close to 1 is unit length at
 * 16 bits, 2^-13 + 2^-24 (fc_quat16_normalize's test; quat.c derives it). */
#define FC_QUAT16_UNIT_SQ_TOLERANCE                                                                   \
    (((int32_t)1 << (FC_UNIT16_SQ_FRAC - 13)) + ((int32_t)1 << (FC_UNIT16_SQ_FRAC - 24)))
#else
static inline fc_quat16 fc_quat16_normalize(fc_arith *ar, fc_quat q, bool *ok)
{
    return fc_quat_normalize(ar, q, ok);
}
#endif

/* q in the 32-bit format (UNIT), exactly (inlined: four shifts; float: q). */
static inline fc_quat fc_quat16_widen(fc_quat16 q)
{
#if FC_NUMERIC_FIXED
    const int from = FC_UNIT16_FRAC, to = FC_UNIT_FRAC;
    return fc_quat_make(fc_widen16(q.w, from, to), fc_widen16(q.x, from, to), fc_widen16(q.y, from, to),
                        fc_widen16(q.z, from, to));
#else
    return q;
#endif
}

/* q rounded to the 16-bit format for a q within 2^-4 of unit length (a
 * unit quaternion, or one a step away from it): each component to the
 * nearest UNIT16 value, as fc_narrow16 rounds, with no saturation test (no
 * component comes near the format's edge). Float: q. */
static inline fc_quat16 fc_quat16_round_unit(fc_quat q)
{
#if FC_NUMERIC_FIXED
    /* the high half of q_i + 2^15 (the bits above UNIT16's LSB, rounded) */
    const fc_quat16 r = {(fc_real16)(uint16_t)(((uint32_t)q.w + 0x8000u) >> 16),
                         (fc_real16)(uint16_t)(((uint32_t)q.x + 0x8000u) >> 16),
                         (fc_real16)(uint16_t)(((uint32_t)q.y + 0x8000u) >> 16),
                         (fc_real16)(uint16_t)(((uint32_t)q.z + 0x8000u) >> 16)};
    return r;
#else
    return q;
#endif
}

/* p* (x) q (2.8), each component one rounding; p, q from fc_quat16_normalize. */
fc_quat16 fc_quat16_conj_mul(fc_arith *ar, fc_quat16 p, fc_quat16 q);

/* The same rotation with w >= 0. */
fc_quat16 fc_quat16_shortest(fc_quat16 q);

/* q (x) [0, v] (x) q*: v from body to world; v of any format. */
fc_vec3 fc_quat_rotate(fc_arith *ar, fc_quat q, fc_vec3 v);

/* x and y of fc_quat_rotate, z 0: a world vector's horizontal part, from
 * R(q)'s first two rows with q and the entries rounded to UNIT16 (16 x 16
 * products). Fixed: each entry within 2^-13 + 2^-15 of R(q)'s, so each
 * component within that times |v_x| + |v_y| + |v_z|, plus its rounding (the
 * measured acceleration: below a 16 g accelerometer's LSB). For a q within
 * 2^-13 of unit length. */
fc_vec3 fc_quat_rotate_horizontal(fc_arith *ar, fc_quat q, fc_vec3 v);

/* q* (x) [0, v] (x) q: v from world to body. */
fc_vec3 fc_quat_rotate_inv(fc_arith *ar, fc_quat q, fc_vec3 v);

/* Rotation of angle_rad (ANGLE) about a UNIT axis. */
fc_quat fc_quat_from_axis_angle(fc_arith *ar, fc_vec3 axis_unit, fc_real angle_rad);

/* Axis (UNIT) and angle (ANGLE, in [0, pi]) of q; the identity gives axis x, angle 0. */
void fc_quat_to_axis_angle(fc_arith *ar, fc_quat q, fc_vec3 *axis_unit, fc_real *angle_rad);

/* Exponential map: the rotation by the rotation vector theta (ANGLE, |theta| <= 8 rad). */
fc_quat fc_quat_from_rotation_vector(fc_arith *ar, fc_vec3 theta_rad);

/* Roll-pitch-yaw (ZYX: yaw about z, then pitch about y, then roll about x), ANGLE. */
fc_quat fc_quat_from_rpy(fc_arith *ar, fc_real roll_rad, fc_real pitch_rad, fc_real yaw_rad);

/* The attitude whose body frame sees the world's up along up_body (any
 * length > 0, its components in one format), at heading yaw_rad (ANGLE):
 * fc_quat_from_rpy(atan2(up.y, up.z), atan2(-up.x, |(up.y, up.z)|), yaw),
 * from the half-angle roots of the tilt's cosines (no atan2, and sin/cos
 * only for a yaw other than 0). up along body x (no roll defined) takes
 * roll 0; up_body = 0 gives the identity. */
fc_quat fc_quat_from_up(fc_arith *ar, fc_vec3 up_body, fc_real yaw_rad);

/* (roll, pitch, yaw) of q as an ANGLE vector; pitch in [-pi/2, pi/2]. */
fc_vec3 fc_quat_to_rpy(fc_arith *ar, fc_quat q);

/* One step of q' = 1/2 q (x) [0, w_body] over dt_s, by the exponential map:
 * q (x) exp(w_body dt / 2), renormalised. rate in RATE, dt in DT. Exact for a
 * rate constant over the step. */
fc_quat fc_quat_integrate_body_rate(fc_arith *ar, fc_quat q, fc_vec3 rate_body_radps, fc_real dt_s);

/* One step of q' = 1/2 [0, w_world] (x) q over dt_s (the form under (2.1)). */
fc_quat fc_quat_integrate_world_rate(fc_arith *ar, fc_quat q, fc_vec3 rate_world_radps, fc_real dt_s);

/*
 * The attitude filter's step of q' = 1/2 q (x) [0, w_body], in place: with
 * the half-angle theta = w dt/2 (UNIT holding rad, formed once), q + q (x)
 * [0, theta] brought back to unit length by one Newton step,
 * (3 - |p|^2)/2 p. q must be unit (fc_quat_normalize's result or this
 * function's), rate in RATE, half_dt_s = dt/2 in DT. The rotation is
 * 2 atan(|w| dt/2) against the exact |w| dt: short by a fraction (|w| dt)^2/12
 * of the step (1e-4 at 10 rad/s and 500 Hz). In fixed the products are
 * 16 x 16: q rounded to UNIT16 (moving the increment by 2^-14 of itself)
 * times theta in two 16-bit parts, and |p|^2 formed from the halves of p.
 * A half-angle beyond 2^-5 rad on an axis (31 rad/s at 500 Hz) takes the
 * exponential map (fc_quat_integrate_body_rate), and a |p|^2 further than
 * 3 2^-12 from 1 fc_quat_normalize.
 */
void fc_quat_advance_body_rate(fc_arith *ar, fc_quat *q, const fc_vec3 *rate_radps, fc_real half_dt_s);

/* True when every component is finite. */
bool fc_quat_is_finite(fc_quat q);

#endif /* FC_QUAT_H */
