/*
 * fc/scalar.h - the numeric backend: one algorithm source, two number types.
 *
 * Every algorithm in firmware/ is written once against the functions below.
 * The build selects the backend with FC_NUMERIC_FIXED (CMake option FC_NUMERIC):
 *
 *   float  fc_real is IEEE single. Shifts are ignored, nothing saturates.
 *   fixed  fc_real is int32_t in a Q-format that depends on what the signal is
 *          (table below). Products go through a 64-bit intermediate, are
 *          rounded to nearest and saturate symmetrically to +-INT32_MAX;
 *          a saturation sets fc_arith.saturated, which the caller owns and
 *          reads (the library has no global state, so the flag travels with
 *          the caller, like the Q bit of a Cortex-M APSR but in a struct).
 *
 * How a multiply is written: the caller names the formats of both operands
 * and of the result, and FC_SHIFT turns them into the right shift:
 *
 *     angle = fc_mul(&ar, rate_radps, dt_s, FC_SHIFT(RATE, DT, ANGLE));
 *
 * reads "rate times dt gives an angle"; in fixed it is
 * (rate * dt) >> (24 + 30 - 28), in float it is rate * dt.
 *
 * Q-formats, chosen per kind of signal from its range (int32: 1 sign bit,
 * 31 - FRAC integer bits, FRAC fraction bits; resolution = 2^-FRAC):
 *
 *   name      FRAC  range             resolution   used for
 *   UNIT       30   [-2, 2)           9.3e-10      quaternion components, sin/cos,
 *                                                  direction cosines, unit vectors
 *   ANGLE      28   [-8, 8) rad       3.7e-9 rad   angles, wrapped to [-pi, pi]
 *   RATE       24   [-128, 128) rad/s 6.0e-8       body rates (gyro: 2000 deg/s = 35 rad/s)
 *   ACCEL      22   [-512, 512) m/s2  2.4e-7       accelerations (16 g = 157 m/s2)
 *   VEL        22   [-512, 512) m/s   2.4e-7       velocities, the sliding variable
 *   LENGTH     20   [-2048, 2048) m   9.5e-7 m     positions, altitudes, arms
 *   FORCE      20   [-2048, 2048) N   9.5e-7 N     thrusts, the SSC control signal
 *   MOMENT     24   [-128, 128) N m   6.0e-8 N m   body moments (Crazyflie: 5e-3 N m)
 *   MASS       24   [-128, 128) kg    6.0e-8 kg    mass, the SSC parameter Theta
 *   INERTIA    30   [-2, 2) kg m2     9.3e-10      moments of inertia (Crazyflie: 1.7e-5)
 *   DT         30   [-2, 2) s         9.3e-10 s    the fixed step and filter time constants
 *   TIME       16   [-32768, 32768) s 1.5e-5 s     mission time
 *   RATIO      24   [-128, 128)       6.0e-8       dimensionless factors (k_g, k_h, weights)
 *   GAIN       16   [-32768, 32768)   1.5e-5       controller gains of mixed units
 *   MAT        24   [-128, 128)       6.0e-8       entries of the allocation matrices
 *   PER_FORCE  26   [-32, 32) 1/N     1.5e-8 1/N   1 / the airframe's maximum thrust
 *
 * and, for the signals of the inner loop that need 15 bits and not 31
 * (fc_real16: int16_t in fixed, float in float):
 *
 *   UNIT16     14   [-2, 2)           6.1e-5       the attitude error's quaternions
 *                                                  (fc_quat16), its half-heading c, s
 *   NORM16     14   [-2, 2)           6.1e-5       the normalised wrench between the inner
 *                                                  loop's modules (fc_wrench16): thrust
 *                                                  as a fraction of the airframe's
 *                                                  maximum, moments of their authority
 *   RATE16     10   [-32, 32) rad/s   9.8e-4 rad/s body rates as the attitude law and the
 *                                                  filter's integration read them (a
 *                                                  2000 deg/s gyro's LSB is 1.1e-3)
 *
 * A product of two fc_real16 is exact in an fc_real, in the format whose FRAC
 * is the sum of theirs (UNIT16 x UNIT16: UNIT16_SQ, Q28), and so is the sum of
 * two such products: one 16 x 16 -> 32 multiply (4 MULs on the ATmega against
 * 16 for fc_mul), no rounding and no range check.
 *
 * Functions of the form fc_xxx(&ar, ...) may saturate in fixed; the others
 * cannot. Division and square root are kept out of hot paths: reciprocals of
 * constants are computed at init (fixed division is a 64-bit divide).
 */
#ifndef FC_SCALAR_H
#define FC_SCALAR_H

#include <stdbool.h>
#include <stdint.h>

#ifndef FC_NUMERIC_FIXED
#define FC_NUMERIC_FIXED 0
#endif

#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error "fc/scalar.h: the fixed backend splits 64-bit products assuming little-endian"
#endif

/* ---- Q-formats (see the table above) ---------------------------------- */
#define FC_UNIT_FRAC 30
#define FC_ANGLE_FRAC 28
#define FC_RATE_FRAC 24
#define FC_ACCEL_FRAC 22
#define FC_VEL_FRAC 22
#define FC_LENGTH_FRAC 20
#define FC_FORCE_FRAC 20
#define FC_MOMENT_FRAC 24
#define FC_MASS_FRAC 24
#define FC_INERTIA_FRAC 30
#define FC_DT_FRAC 30
#define FC_TIME_FRAC 16
#define FC_RATIO_FRAC 24
#define FC_GAIN_FRAC 16
#define FC_MAT_FRAC 24
#define FC_PER_FORCE_FRAC 26
/* 16-bit formats (fc_real16, below) */
#define FC_UNIT16_FRAC 14
#define FC_UNIT16_SQ_FRAC 28 /* a product of two UNIT16 values: 2 x 14 */
#define FC_NORM16_FRAC 14    /* the normalised wrench: room for 2x the authority */
#define FC_RATE16_FRAC 10    /* body rates read by 16-bit products */

/* Right shift of a product: operand formats A and B, result format OUT. */
#define FC_SHIFT(A, B, OUT) (FC_##A##_FRAC + FC_##B##_FRAC - FC_##OUT##_FRAC)
/* Left shift of a dividend: NUM / DEN gives OUT. */
#define FC_DIV_SHIFT(NUM, DEN, OUT) (FC_##OUT##_FRAC + FC_##DEN##_FRAC - FC_##NUM##_FRAC)
/* The FRAC of a named format, for the functions that take one. */
#define FC_FRAC(KIND) (FC_##KIND##_FRAC)

/* Saturation record, owned by the caller (a module keeps one in its state). */
typedef struct fc_arith {
    uint8_t saturated; /* set to 1 by any saturating operation; cleared by the owner */
} fc_arith;

#if FC_NUMERIC_FIXED
/* ======================================================================= */
/* fixed backend: the portable definition                                  */
/* ======================================================================= */
/*
 * Every primitive below is written the plain way: the exact result in an
 * int64_t (or in 32 bits where it cannot overflow), rounded to nearest and
 * saturated symmetrically at +-INT32_MAX by fc_fx_narrow. This is the
 * definition: the host and Cortex-M builds run it as it stands, the unit
 * tests compare against it, and a port (fc/scalar_avr.h, the ATmega's) may
 * replace the few primitives it lists, bit for bit (atmega.scalar_equivalence
 * checks it on the target).
 */
typedef int32_t fc_real;
typedef int16_t fc_real16; /* the 16-bit formats of the table above */
typedef int64_t fc_acc;    /* a sum of up to eight products (fc_acc_mac) */

/* The primitives must be inlined where they are used: only then is the
 * shift a constant (on the ATmega a 32-bit shift by a variable is a loop). */
#define FC_FX_INLINE static inline __attribute__((always_inline))

#define FC_REAL_MAX INT32_MAX
#define FC_REAL_MIN (-INT32_MAX) /* symmetric: negation never overflows */
#define FC_REAL16_MAX INT16_MAX  /* symmetric as fc_real: -INT16_MAX is the least */

/* A constant in format KIND, folded at compile time (no run-time float).
 * X must be a float constant expression; it is rounded to nearest. */
#define FC_C(X, KIND)                                                                     \
    ((fc_real)((X) * (float)((uint32_t)1u << FC_##KIND##_FRAC) + ((X) < 0.0f ? -0.5f : 0.5f)))
/* An integer constant in format KIND (exact), and in 16-bit format KIND. */
#define FC_INT(N, KIND) ((fc_real)((int32_t)(N) * ((int32_t)1 << FC_##KIND##_FRAC)))
#define FC_INT16(N, KIND) ((fc_real16)((N) * ((int32_t)1 << FC_##KIND##_FRAC)))

/* fc_acc_mac drops these bits of each product, so eight of them cannot wrap. */
#define FC_ACC_GUARD_BITS 3

/* ---- rounding and saturation of a 64-bit intermediate ------------------ */

/* value saturated to +-INT32_MAX (a saturation sets ar->saturated). */
FC_FX_INLINE fc_real fc_fx_saturate(fc_arith *ar, int64_t value)
{
    if (value > (int64_t)FC_REAL_MAX) {
        ar->saturated = 1u;
        return FC_REAL_MAX;
    }
    if (value < (int64_t)FC_REAL_MIN) {
        ar->saturated = 1u;
        return FC_REAL_MIN;
    }
    return (fc_real)value;
}

/* a + b, clamped at +-INT64_MAX (then saturated by whatever narrows it). */
FC_FX_INLINE int64_t fc_fx_add64(int64_t a, int64_t b)
{
    int64_t sum;
    const bool overflowed = __builtin_add_overflow(a, b, &sum);
    if (overflowed) {
        return a > 0 ? INT64_MAX : -INT64_MAX;
    }
    return sum;
}

/* value / 2^shift rounded to nearest (shift > 0), or value 2^-shift clamped
 * at +-INT64_MAX (shift < 0). */
FC_FX_INLINE int64_t fc_fx_rescale(fc_arith *ar, int64_t value, int shift)
{
    if (shift > 0) {
        return fc_fx_add64(value, (int64_t)1 << (shift - 1)) >> shift; /* arithmetic shift (gcc) */
    }
    if (shift < 0) {
        const int64_t limit = INT64_MAX >> (-shift);
        if (value > limit || value < -limit) {
            ar->saturated = 1u;
            return value > 0 ? INT64_MAX : -INT64_MAX;
        }
        return value * ((int64_t)1 << (-shift));
    }
    return value;
}

/* A 64-bit value as its two 32-bit halves (value = 2^32 high + low, high
 * read as signed): scalar.c's square roots work on them, and so does the
 * ATmega's port, where every int64_t operation is a libgcc call. */
typedef struct fc_fx_wide {
    uint32_t low;
    uint32_t high;
} fc_fx_wide;

FC_FX_INLINE fc_fx_wide fc_fx_split(int64_t value)
{
    /* by a union, not by a shift: a 64-bit shift is a loop on the ATmega (all
     * targets of this library are little-endian) */
    const union {
        int64_t whole;
        fc_fx_wide half;
    } split = {value};
    return split.half;
}

FC_FX_INLINE int64_t fc_fx_join(fc_fx_wide value)
{
    const union {
        fc_fx_wide half;
        int64_t whole;
    } join = {value};
    return join.whole;
}

/* a + b modulo 2^64. */
FC_FX_INLINE fc_fx_wide fc_fx_add_wide_wrap(fc_fx_wide a, fc_fx_wide b)
{
    fc_fx_wide sum;
    sum.low = a.low + b.low;
    sum.high = a.high + b.high + (sum.low < a.low ? 1u : 0u);
    return sum;
}

/* Shifts, defined with the halves' other helpers at the end of this backend
 * (or by the port, where a C shift by a constant is a loop): bits
 * [shift, shift + 31] of high:low (0 < shift < 32); a >> n, arithmetic, and
 * a 2^n modulo 2^32 (0 <= n < 32). */
FC_FX_INLINE uint32_t fc_fx_extract(uint32_t low, uint32_t high, int shift);
FC_FX_INLINE int32_t fc_fx_asr32(int32_t a, int n);
FC_FX_INLINE int32_t fc_fx_shl32(int32_t a, int n);

/* value / 2^shift rounded to nearest and saturated, value given as halves,
 * for 0 < shift < 32: the carry of the rounding by hand, the range checked
 * on the high half alone (a 32-bit core does it in a few instructions, where
 * the int64_t form compares 64-bit values). The same result as
 * fc_fx_saturate(fc_fx_rescale(value, shift)). */
FC_FX_INLINE fc_real fc_fx_narrow_wide(fc_arith *ar, fc_fx_wide value, int shift)
{
    const uint32_t low = value.low;
    int32_t high = (int32_t)value.high;
    const uint32_t low_rounded = low + ((uint32_t)1 << (shift - 1));
    if (low_rounded < low && high != INT32_MAX) {
        high += 1; /* the carry of the rounding */
    }
    /* the quotient fits 32 bits iff the bits of high above shift - 1 are all
     * sign, i.e. -2^(shift-1) <= high < 2^(shift-1) */
    const int32_t bound = (int32_t)1 << (shift - 1);
    if (high >= bound || high < -bound) {
        ar->saturated = 1u;
        return high < 0 ? FC_REAL_MIN : FC_REAL_MAX;
    }
    const int32_t result = (int32_t)fc_fx_extract(low_rounded, (uint32_t)high, shift);
    if (result == INT32_MIN) {
        ar->saturated = 1u; /* symmetric range: -2^31 is not a value */
        return FC_REAL_MIN;
    }
    return result;
}

/* value / 2^shift rounded to nearest and saturated, any shift: how every
 * product leaves its intermediate (fc_fx_narrow_wide for the shifts of the
 * library's formats). */
FC_FX_INLINE fc_real fc_fx_narrow(fc_arith *ar, int64_t value, int shift)
{
    if (shift > 0 && shift < 32) {
        return fc_fx_narrow_wide(ar, fc_fx_split(value), shift);
    }
    return fc_fx_saturate(ar, fc_fx_rescale(ar, value, shift));
}

/* A sum of up to four products (each below 2^62 in magnitude) narrowed by
 * shift with one rounding. Below a shift of 32 the sum is clamped, not
 * wrapped: one that reaches 2^63 saturates anyway. From 32 on each product
 * is floored by 4 first so that nothing clamps. */
FC_FX_INLINE fc_real fc_fx_narrow_sum(fc_arith *ar, int64_t p0, int64_t p1, int64_t p2, int64_t p3, int shift)
{
    if (shift >= 32) {
        const int64_t quarters = (p0 >> 2) + (p1 >> 2) + (p2 >> 2) + (p3 >> 2);
        return fc_fx_saturate(ar, fc_fx_rescale(ar, quarters, shift - 2));
    }
    return fc_fx_narrow(ar, fc_fx_add64(fc_fx_add64(p0, p1), fc_fx_add64(p2, p3)), shift);
}

/* The port: it defines FC_PORT_<NAME> for each primitive it replaces (the
 * list at its top), and the portable definition of that one is left out. */
#if defined(__AVR__)
#include "fc/scalar_avr.h"
#endif

/* ---- the primitives ---------------------------------------------------- */

/* a + b and a - b, saturated. (port: FC_PORT_ADD) */
#ifndef FC_PORT_ADD
FC_FX_INLINE fc_real fc_add(fc_arith *ar, fc_real a, fc_real b)
{
    int32_t sum;
    if (__builtin_add_overflow(a, b, &sum) || sum == INT32_MIN) {
        ar->saturated = 1u; /* a sum beyond the range has the sign of a */
        return a > 0 ? FC_REAL_MAX : FC_REAL_MIN;
    }
    return sum;
}

FC_FX_INLINE fc_real fc_sub(fc_arith *ar, fc_real a, fc_real b)
{
    int32_t difference;
    if (__builtin_sub_overflow(a, b, &difference) || difference == INT32_MIN) {
        ar->saturated = 1u; /* a difference beyond the range: a >= 0 above it */
        return a >= 0 ? FC_REAL_MAX : FC_REAL_MIN;
    }
    return difference;
}
#endif

/* fc_add_inline, fc_sub_inline: the same sums, for the sites that run at
 * every step; a port that makes fc_add and fc_sub calls (FC_PORT_ADD) keeps
 * these inline. */
#ifndef FC_PORT_ADD
FC_FX_INLINE fc_real fc_add_inline(fc_arith *ar, fc_real a, fc_real b)
{
    return fc_add(ar, a, b);
}

FC_FX_INLINE fc_real fc_sub_inline(fc_arith *ar, fc_real a, fc_real b)
{
    return fc_sub(ar, a, b);
}
#endif

FC_FX_INLINE fc_real fc_neg(fc_arith *ar, fc_real a)
{
    if (a == INT32_MIN) {
        ar->saturated = 1u; /* -2^31 is not a value: its negation saturates */
        return FC_REAL_MAX;
    }
    return -a;
}

FC_FX_INLINE fc_real fc_abs(fc_arith *ar, fc_real a)
{
    return a < 0 ? fc_neg(ar, a) : a;
}

/* a b / 2^shift, rounded, saturated; a0 b0 + a1 b1 (+ ...) / 2^shift with
 * one rounding. fc_mul_inline and fc_dot2_inline are the same values, for
 * the sites so frequent that a port which forms the products out of line
 * should form them inline there. (port: FC_PORT_PRODUCTS) */
#ifndef FC_PORT_PRODUCTS
FC_FX_INLINE fc_real fc_mul(fc_arith *ar, fc_real a, fc_real b, int shift)
{
    return fc_fx_narrow(ar, (int64_t)a * b, shift);
}

FC_FX_INLINE fc_real fc_dot2(fc_arith *ar, fc_real a0, fc_real b0, fc_real a1, fc_real b1, int shift)
{
    return fc_fx_narrow_sum(ar, (int64_t)a0 * b0, (int64_t)a1 * b1, 0, 0, shift);
}

FC_FX_INLINE fc_real fc_dot3(fc_arith *ar, fc_real a0, fc_real b0, fc_real a1, fc_real b1, fc_real a2, fc_real b2,
                             int shift)
{
    return fc_fx_narrow_sum(ar, (int64_t)a0 * b0, (int64_t)a1 * b1, (int64_t)a2 * b2, 0, shift);
}

FC_FX_INLINE fc_real fc_dot4(fc_arith *ar, fc_real a0, fc_real b0, fc_real a1, fc_real b1, fc_real a2, fc_real b2,
                             fc_real a3, fc_real b3, int shift)
{
    return fc_fx_narrow_sum(ar, (int64_t)a0 * b0, (int64_t)a1 * b1, (int64_t)a2 * b2, (int64_t)a3 * b3, shift);
}

FC_FX_INLINE fc_real fc_mul_inline(fc_arith *ar, fc_real a, fc_real b, int shift)
{
    return fc_mul(ar, a, b, shift);
}

FC_FX_INLINE fc_real fc_dot2_inline(fc_arith *ar, fc_real a0, fc_real b0, fc_real a1, fc_real b1, int shift)
{
    return fc_dot2(ar, a0, b0, a1, b1, shift);
}
#endif

/* An accumulator for sums of up to eight products (matrix rows): each
 * product enters floored by 2^FC_ACC_GUARD_BITS, the sum is kept modulo
 * 2^64, and rounded once at the end. (port: FC_PORT_ACC_MAC) */
FC_FX_INLINE fc_acc fc_acc_zero(void)
{
    return 0;
}

#ifndef FC_PORT_ACC_MAC
FC_FX_INLINE fc_acc fc_acc_mac(fc_acc acc, fc_real a, fc_real b)
{
    const int64_t term = ((int64_t)a * b) >> FC_ACC_GUARD_BITS; /* arithmetic shift (gcc) */
    return (fc_acc)((uint64_t)acc + (uint64_t)term);
}
#endif

FC_FX_INLINE fc_real fc_acc_result(fc_arith *ar, fc_acc acc, int shift)
{
    return fc_fx_narrow(ar, acc, shift - FC_ACC_GUARD_BITS);
}

/* num 2^shift / den, rounded to nearest; den == 0 saturates toward the sign
 * of num (scalar.c). */
fc_real fc_div(fc_arith *ar, fc_real num, fc_real den, int shift);

/* (h >> 1) + (h & 1): floor((h + 1) / 2), the last bit of a rounding
 * shift, never beyond the range. (port: FC_PORT_HALVE_ROUNDED) */
#ifndef FC_PORT_HALVE_ROUNDED
FC_FX_INLINE int32_t fc_fx_halve_rounded(int32_t h)
{
    return (h >> 1) + (h & 1);
}
#endif

/* floor((a + 2^(n-1)) / 2^n) for 0 < n < 32: a / 2^n rounded to nearest,
 * never beyond the range. (port: FC_PORT_ROUND_ASR32) */
#ifndef FC_PORT_ROUND_ASR32
FC_FX_INLINE int32_t fc_fx_round_asr32(int32_t a, int n)
{
    /* floor(a / 2^(n-1)) + 1, halved: in 32 bits */
    return fc_fx_halve_rounded(fc_fx_asr32(a, n - 1));
}
#endif

/* Change of format: a value in format FROM re-expressed in format TO,
 * rounded and saturated as fc_fx_narrow, in 32 bits. */
FC_FX_INLINE fc_real fc_convert(fc_arith *ar, fc_real a, int frac_from, int frac_to)
{
    const int shift = frac_from - frac_to;
    if (shift > 0 && shift < 32) {
        return fc_fx_round_asr32(a, shift);
    }
    if (shift < 0 && shift > -32) {
        /* a 2^n saturates beyond +-INT32_MAX, i.e. for |a| > INT32_MAX >> n */
        const int32_t limit = (int32_t)((uint32_t)INT32_MAX >> (uint32_t)(-shift));
        if (a > limit || a < -limit) {
            ar->saturated = 1u;
            return a > 0 ? FC_REAL_MAX : FC_REAL_MIN;
        }
        return fc_fx_shl32(a, -shift);
    }
    return fc_fx_narrow(ar, (int64_t)a, shift);
}

/* fc_convert to a finer format (frac_to > frac_from) without the saturation
 * test, for an x the caller has bounded (a clamp or a documented range,
 * written next to the use). PRECONDITION: |x| 2^(frac_to - frac_from) <=
 * INT32_MAX, where both give the same value; beyond it the result is
 * undefined (wraps). Float: x. */
FC_FX_INLINE fc_real fc_widen_bounded(fc_real x, int frac_from, int frac_to)
{
    return fc_fx_shl32(x, frac_to - frac_from);
}

FC_FX_INLINE bool fc_is_finite(fc_real a)
{
    (void)a;
    return true;
}

FC_FX_INLINE bool fc_is_finite3(fc_real a, fc_real b, fc_real c)
{
    (void)a;
    (void)b;
    (void)c;
    return true;
}

/* ---- 16-bit values (fc_real16; formats in the table above) ------------- */

/* x (format frac_from) in the 16-bit format frac_to <= frac_from: rounded to
 * nearest (fc_convert) and saturated at +-FC_REAL16_MAX. (port: FC_PORT_NARROW16) */
#ifndef FC_PORT_NARROW16
FC_FX_INLINE fc_real16 fc_narrow16(fc_arith *ar, fc_real x, int frac_from, int frac_to)
{
    const fc_real r = fc_convert(ar, x, frac_from, frac_to);
    if (r > FC_REAL16_MAX || r < -FC_REAL16_MAX) {
        ar->saturated = 1u;
        return r > 0 ? FC_REAL16_MAX : -FC_REAL16_MAX;
    }
    return (fc_real16)r;
}
#endif

/* bits shift .. shift + 15 of t as a 16-bit value (0 < shift < 17): the
 * last step of fc_round16. (port: FC_PORT_LOW16_ASR) */
#ifndef FC_PORT_LOW16_ASR
FC_FX_INLINE fc_real16 fc_fx_low16_asr(uint32_t t, int shift)
{
    return (fc_real16)fc_fx_asr32((fc_real)t, shift);
}
#endif

/* fc_narrow16 without the saturation test, for an x the caller has bounded
 * (a clamp or a documented range, written next to the use). PRECONDITION:
 * |x| / 2^(frac_from - frac_to) < FC_REAL16_MAX + 1/2 (x rounds into
 * +-FC_REAL16_MAX), where both give the same value; beyond it the result
 * is undefined (wraps). Float: x. */
FC_FX_INLINE fc_real16 fc_round16(fc_real x, int frac_from, int frac_to)
{
    if (frac_from - frac_to == 16) {
        /* the high half of x + 2^15 (no 32-bit shift) */
        return (fc_real16)(uint16_t)(((uint32_t)x + 0x8000u) >> 16);
    }
    if (frac_from == frac_to) {
        return (fc_real16)x;
    }
    /* floor((x + 2^(shift-1)) / 2^shift), as fc_convert rounds; the sum
     * stays below 2^31 under the precondition */
    const int shift = frac_from - frac_to;
    return fc_fx_low16_asr((uint32_t)x + ((uint32_t)1 << (shift - 1)), shift);
}

/* x (16-bit format frac_from) in the 32-bit format frac_to >= frac_from,
 * exactly (|x| < 2^15: a shift of up to 16 bits stays inside 32). */
FC_FX_INLINE fc_real fc_widen16(fc_real16 x, int frac_from, int frac_to)
{
    fc_arith never = {0u};
    return frac_from == frac_to ? (fc_real)x : fc_convert(&never, (fc_real)x, frac_from, frac_to);
}

/* a b, exact (below 2^31 in magnitude for operands within +-FC_REAL16_MAX),
 * in the format whose FRAC is the sum of the operands'; and the same for an
 * unsigned 16-bit a (the low half of a 32-bit value): |a b| < 2^31; and for
 * both unsigned (the roots' mantissas): a b < 2^32, unsigned.
 * (port: FC_PORT_MUL16) */
#ifndef FC_PORT_MUL16
FC_FX_INLINE fc_real fc_mul16(fc_real16 a, fc_real16 b)
{
    return (fc_real)a * b;
}

FC_FX_INLINE fc_real fc_mul16_unsigned(uint16_t a, fc_real16 b)
{
    return (fc_real)a * b;
}

FC_FX_INLINE uint32_t fc_umul16(uint16_t a, uint16_t b)
{
    return (uint32_t)a * b;
}
#endif

/* a0 b0 + a1 b1, exact, as fc_mul16. */
FC_FX_INLINE fc_real fc_dot2_16(fc_real16 a0, fc_real16 b0, fc_real16 a1, fc_real16 b1)
{
    return fc_mul16(a0, b0) + fc_mul16(a1, b1);
}

/* a a, exact, as fc_mul16 (a port may form the cross product once), and
 * a^2 + b^2, as fc_dot2_16(a, a, b, b). (port: FC_PORT_SQ16) */
#ifndef FC_PORT_SQ16
FC_FX_INLINE fc_real fc_sq16(fc_real16 a)
{
    return fc_mul16(a, a);
}
#endif

FC_FX_INLINE fc_real fc_sumsq2_16(fc_real16 a, fc_real16 b)
{
    return fc_sq16(a) + fc_sq16(b);
}

/* a0 b0 + .. + a3 b3 rounded to nearest into the 16-bit format frac_to
 * (frac_to < the products' FRAC), saturated at +-FC_REAL16_MAX; the sum is
 * formed exactly, so the operands must keep it below 2^31 (UNIT16 values
 * within +-1.4: each product below 2^29). */
FC_FX_INLINE fc_real16 fc_dot4_16(fc_arith *ar, fc_real16 a0, fc_real16 b0, fc_real16 a1, fc_real16 b1,
                                  fc_real16 a2, fc_real16 b2, fc_real16 a3, fc_real16 b3, int frac_products,
                                  int frac_to)
{
    const fc_real sum = fc_dot2_16(a0, b0, a1, b1) + fc_dot2_16(a2, b2, a3, b3);
    return fc_narrow16(ar, sum, frac_products, frac_to);
}

/* fc_dot4_16 without the saturation test (fc_round16), for a sum the caller
 * has bounded (the reason written next to the use). PRECONDITION: the
 * rounded sum within +-FC_REAL16_MAX, where both give the same value. */
FC_FX_INLINE fc_real16 fc_dot4_round16(fc_real16 a0, fc_real16 b0, fc_real16 a1, fc_real16 b1, fc_real16 a2,
                                       fc_real16 b2, fc_real16 a3, fc_real16 b3, int frac_products, int frac_to)
{
    const fc_real sum = fc_dot2_16(a0, b0, a1, b1) + fc_dot2_16(a2, b2, a3, b3);
    return fc_round16(sum, frac_products, frac_to);
}

/* x / 2 rounded to nearest, ties up: fc_mul(ar, x, 1/2, shift) bit for bit,
 * which cannot saturate. */
FC_FX_INLINE fc_real fc_half(fc_real x)
{
    return fc_fx_halve_rounded(x);
}

FC_FX_INLINE fc_real16 fc_neg16(fc_real16 a)
{
    return (fc_real16)-a; /* never -INT16_MIN: the range is symmetric */
}

/* a b / 2^shift for a 32-bit a and a 16-bit b (a state times a 16-bit
 * factor): fc_mul(ar, a, b, shift), bit for bit, for 1 <= shift <= 31, from
 * two 16 x 16 products instead of a 64-bit one. With a = 2^16 a_high + a_low
 * (a_low the unsigned low half) the product is 2^16 a_high b + a_low b, each
 * term exact in 32 bits (|a_high b| <= 2^30, |a_low b| < 2^31). From shift
 * 16 on the result is below 2^30 and never saturates; below 16 it is
 * a_high b 2^(16 - shift) plus the low product rounded, formed in 32 bits
 * where |a_high b| leaves that room, else by fc_mul. */
FC_FX_INLINE fc_real fc_mul_by16(fc_arith *ar, fc_real a, fc_real16 b, int shift)
{
    const fc_real16 a_high = (fc_real16)(uint16_t)((uint32_t)a >> 16); /* the high half, signed */
    const fc_real high = fc_mul16(a_high, b);                           /* weight 2^16 */
    const fc_real low = fc_mul16_unsigned((uint16_t)a, b);              /* weight 1 */
    if (shift == 16) {
        return high + fc_fx_asr32(low + ((fc_real)1 << 15), 16);
    }
    if (shift > 16) {
        /* floor(a b / 2^16) exactly, then rounded: 2^(shift - 1) is a
         * multiple of 2^16, so the floor loses nothing the rounding needs */
        const fc_real floor16 = high + fc_fx_asr32(low, 16);
        return fc_fx_asr32(floor16 + ((fc_real)1 << (shift - 17)), shift - 16);
    }
    /* |low rounded| <= 2^(31 - shift): the sum stays below 2^31 while
     * |high| 2^(16 - shift) <= 2^31 - 2^(31 - shift) - 1 */
    const fc_real high_limit = (INT32_MAX >> (16 - shift)) - ((fc_real)1 << 15);
    if (high > high_limit || high < -high_limit) {
        return fc_mul(ar, a, b, shift);
    }
    return fc_fx_shl32(high, 16 - shift) + fc_fx_asr32(low + ((fc_real)1 << (shift - 1)), shift);
}

/* ---- helpers on halves and shifts (fc_fx_narrow, scalar.c's roots) ---- */

/* a b exactly, signed and unsigned, as halves; the shifts declared before
 * fc_fx_narrow_wide. (port: FC_PORT_HALVES) */
#ifndef FC_PORT_HALVES
FC_FX_INLINE fc_fx_wide fc_fx_mul_wide(int32_t a, int32_t b)
{
    return fc_fx_split((int64_t)a * b);
}

FC_FX_INLINE fc_fx_wide fc_fx_umul_wide(uint32_t a, uint32_t b)
{
    const uint64_t whole = (uint64_t)a * b;
    fc_fx_wide product;
    product.low = (uint32_t)whole;
    product.high = (uint32_t)(whole >> 32);
    return product;
}

/* (fc_fx_extract, fc_fx_asr32, fc_fx_shl32: declared above, before
 * fc_fx_narrow_wide) */
FC_FX_INLINE uint32_t fc_fx_extract(uint32_t low, uint32_t high, int shift)
{
    return (high << (32 - shift)) | (low >> shift);
}

FC_FX_INLINE int32_t fc_fx_asr32(int32_t a, int n)
{
    /* cppcheck-suppress shiftTooManyBitsSigned ; the arithmetic right shift of a
     * negative value, gcc's and clang's defined behaviour (docs/misra-deviations.md D12) */
    return a >> n;
}

FC_FX_INLINE int32_t fc_fx_shl32(int32_t a, int n)
{
    return (int32_t)((uint32_t)a << n);
}
#endif

#else
/* ======================================================================= */
/* float backend                                                           */
/* ======================================================================= */
typedef float fc_real;

/* Division and square roots inlined where they are used (an FPU does each
 * in one instruction: VDIV.F32, VSQRT.F32 with -fno-math-errno), except on
 * the ATmega, where they are soft-float calls anyway and avr-libc's sqrt
 * is the double one (scalar.c). */
#if defined(__AVR__)
#define FC_FLOAT_INLINE_MATH 0
#else
#define FC_FLOAT_INLINE_MATH 1
#endif

#define FC_REAL_MAX 3.40282347e+38f
#define FC_REAL_MIN (-3.40282347e+38f)

#define FC_C(X, KIND) ((fc_real)(X))
#define FC_INT(N, KIND) ((fc_real)(N))

static inline fc_real fc_add(fc_arith *ar, fc_real a, fc_real b)
{
    (void)ar;
    return a + b;
}

static inline fc_real fc_sub(fc_arith *ar, fc_real a, fc_real b)
{
    (void)ar;
    return a - b;
}

static inline fc_real fc_add_inline(fc_arith *ar, fc_real a, fc_real b)
{
    return fc_add(ar, a, b);
}

static inline fc_real fc_sub_inline(fc_arith *ar, fc_real a, fc_real b)
{
    return fc_sub(ar, a, b);
}

static inline fc_real fc_neg(fc_arith *ar, fc_real a)
{
    (void)ar;
    return -a;
}

static inline fc_real fc_abs(fc_arith *ar, fc_real a)
{
    (void)ar;
    return a < 0.0f ? -a : a;
}

static inline fc_real fc_mul(fc_arith *ar, fc_real a, fc_real b, int shift)
{
    (void)ar;
    (void)shift;
    return a * b;
}

static inline fc_real fc_dot2(fc_arith *ar, fc_real a0, fc_real b0, fc_real a1, fc_real b1,
                              int shift)
{
    (void)ar;
    (void)shift;
    return a0 * b0 + a1 * b1;
}

static inline fc_real fc_dot3(fc_arith *ar, fc_real a0, fc_real b0, fc_real a1, fc_real b1,
                              fc_real a2, fc_real b2, int shift)
{
    (void)ar;
    (void)shift;
    return a0 * b0 + a1 * b1 + a2 * b2;
}

/* (the fixed backend's products inlined on the ATmega too: here fc_mul and fc_dot2) */
static inline fc_real fc_mul_inline(fc_arith *ar, fc_real a, fc_real b, int shift)
{
    return fc_mul(ar, a, b, shift);
}

static inline fc_real fc_dot2_inline(fc_arith *ar, fc_real a0, fc_real b0, fc_real a1, fc_real b1, int shift)
{
    return fc_dot2(ar, a0, b0, a1, b1, shift);
}

static inline fc_real fc_dot4(fc_arith *ar, fc_real a0, fc_real b0, fc_real a1, fc_real b1,
                              fc_real a2, fc_real b2, fc_real a3, fc_real b3, int shift)
{
    (void)ar;
    (void)shift;
    return a0 * b0 + a1 * b1 + a2 * b2 + a3 * b3;
}

typedef float fc_acc;

static inline fc_acc fc_acc_zero(void)
{
    return 0.0f;
}

static inline fc_acc fc_acc_mac(fc_acc acc, fc_real a, fc_real b)
{
    return acc + a * b;
}

static inline fc_real fc_acc_result(fc_arith *ar, fc_acc acc, int shift)
{
    (void)ar;
    (void)shift;
    return acc;
}

/* num / den; den == 0 gives +-FC_REAL_MAX (or 0 for 0/0) instead of inf/NaN. */
#if FC_FLOAT_INLINE_MATH
static inline fc_real fc_div(fc_arith *ar, fc_real num, fc_real den, int shift)
{
    (void)shift;
    if (den == 0.0f) {
        ar->saturated = 1u;
        return num > 0.0f ? FC_REAL_MAX : (num < 0.0f ? FC_REAL_MIN : 0.0f);
    }
    return num / den;
}
#else
fc_real fc_div(fc_arith *ar, fc_real num, fc_real den, int shift);
#endif


static inline fc_real fc_convert(fc_arith *ar, fc_real a, int frac_from, int frac_to)
{
    (void)ar;
    (void)frac_from;
    (void)frac_to;
    return a;
}

static inline fc_real fc_widen_bounded(fc_real x, int frac_from, int frac_to)
{
    (void)frac_from;
    (void)frac_to;
    return x;
}

static inline bool fc_is_finite(fc_real a)
{
    /* a - a is +0 for every finite a and NaN for an infinity or a NaN: the
     * same answer as isfinite, compared with the zero the FPU's VCMP takes
     * as an immediate (isfinite compares |a| with the largest float, a
     * literal load at every test) */
    return a - a == 0.0f;
}

/* a, b and c all finite. With an FPU by one comparison: the sum of the
 * three a - a is +0 when each is and NaN when any is NaN (soft-float: the
 * additions cost more than the comparisons they save). */
static inline bool fc_is_finite3(fc_real a, fc_real b, fc_real c)
{
#if FC_FLOAT_INLINE_MATH
    return (a - a) + (b - b) + (c - c) == 0.0f;
#else
    return fc_is_finite(a) && fc_is_finite(b) && fc_is_finite(c);
#endif
}

/* ---- 16-bit values: float here too, the same expressions as fc_real's ---- */
typedef float fc_real16;
#define FC_REAL16_MAX FC_REAL_MAX
#define FC_INT16(N, KIND) ((fc_real16)(N))

static inline fc_real16 fc_narrow16(fc_arith *ar, fc_real x, int frac_from, int frac_to)
{
    (void)ar;
    (void)frac_from;
    (void)frac_to;
    return x;
}

static inline fc_real16 fc_round16(fc_real x, int frac_from, int frac_to)
{
    (void)frac_from;
    (void)frac_to;
    return x;
}

static inline fc_real fc_widen16(fc_real16 x, int frac_from, int frac_to)
{
    (void)frac_from;
    (void)frac_to;
    return x;
}

static inline fc_real fc_mul16(fc_real16 a, fc_real16 b)
{
    return a * b;
}

static inline fc_real fc_dot2_16(fc_real16 a0, fc_real16 b0, fc_real16 a1, fc_real16 b1)
{
    return a0 * b0 + a1 * b1;
}

static inline fc_real fc_sq16(fc_real16 a)
{
    return a * a;
}

static inline fc_real fc_sumsq2_16(fc_real16 a, fc_real16 b)
{
    return a * a + b * b;
}

static inline fc_real16 fc_dot4_16(fc_arith *ar, fc_real16 a0, fc_real16 b0, fc_real16 a1, fc_real16 b1,
                                   fc_real16 a2, fc_real16 b2, fc_real16 a3, fc_real16 b3, int frac_products,
                                   int frac_to)
{
    (void)ar;
    (void)frac_products;
    (void)frac_to;
    return a0 * b0 + a1 * b1 + a2 * b2 + a3 * b3;
}

static inline fc_real16 fc_dot4_round16(fc_real16 a0, fc_real16 b0, fc_real16 a1, fc_real16 b1, fc_real16 a2,
                                        fc_real16 b2, fc_real16 a3, fc_real16 b3, int frac_products, int frac_to)
{
    (void)frac_products;
    (void)frac_to;
    return a0 * b0 + a1 * b1 + a2 * b2 + a3 * b3;
}

static inline fc_real fc_half(fc_real x)
{
    return x * 0.5f;
}

static inline fc_real16 fc_neg16(fc_real16 a)
{
    return -a;
}

static inline fc_real fc_mul_by16(fc_arith *ar, fc_real a, fc_real16 b, int shift)
{
    return fc_mul(ar, a, b, shift);
}

#endif /* FC_NUMERIC_FIXED */

/* ---- backend-neutral helpers ------------------------------------------ */

static inline fc_real fc_min(fc_real a, fc_real b)
{
    return a < b ? a : b;
}

static inline fc_real fc_max(fc_real a, fc_real b)
{
    return a > b ? a : b;
}

static inline fc_real fc_clamp(fc_real a, fc_real lo, fc_real hi)
{
    return a < lo ? lo : (a > hi ? hi : a);
}

/* x is a number in [lo, hi]: a NaN fails (the parameter checks of init). */
static inline bool fc_in_range(fc_real x, fc_real lo, fc_real hi)
{
    return fc_is_finite(x) && x >= lo && x <= hi;
}

/* x is a number with |x| <= limit: a NaN fails, and so does an infinity
 * whatever the limit. */
static inline __attribute__((always_inline)) bool fc_within(fc_real x, fc_real limit)
{
#if FC_NUMERIC_FIXED
    /* -limit <= x <= limit as one unsigned comparison: x + limit modulo 2^32
     * is in [0, 2 limit] exactly for those x when 0 <= limit <= INT32_MAX
     * (the 2 limit + 1 values there are the images of the interval's), and
     * a negative limit holds no x; a constant limit folds */
    if (__builtin_constant_p(limit) != 0) {
        return limit >= 0 && (uint32_t)x + (uint32_t)limit <= 2u * (uint32_t)limit;
    }
    return x <= limit && x >= -limit;
#else
    /* one comparison of |x| (a NaN compares false), with a limit past the
     * largest float taken as the largest float so that an infinity fails: the
     * same answer as finite && -limit <= x <= limit, for every limit, NaN too;
     * a constant limit folds (the input checks, ~30 a step) */
    return __builtin_fabsf(x) <= (limit > FC_REAL_MAX ? FC_REAL_MAX : limit);
#endif
}

/* fc_within(x, limit) for a limit formed at run time (the norm clamps'
 * remainders, fc_norm1_within): the same answer. With an FPU by the sign of
 * |x| - limit, one comparison with the zero VCMP takes as an immediate and
 * no test of the limit: the difference of two floats is 0 only when they
 * are equal (IEEE gradual underflow, the FPU's default) and has the sign of
 * their order otherwise, and an infinite |x| against an infinite limit
 * gives NaN, which fails. Fixed, and soft-float (where the subtraction costs
 * more than the test it saves): fc_within. */
static inline __attribute__((always_inline)) bool fc_within_runtime(fc_real x, fc_real limit)
{
#if !FC_NUMERIC_FIXED && defined(FC_FLOAT_INLINE_MATH) && FC_FLOAT_INLINE_MATH
    return __builtin_fabsf(x) - limit <= 0.0f;
#else
    return fc_within(x, limit);
#endif
}

/* -1, 0 or +1 as a UNIT value (the relay of the sliding-mode laws). */
static inline fc_real fc_sign_unit(fc_real a)
{
    if (a > FC_INT(0, UNIT)) {
        return FC_INT(1, UNIT);
    }
    if (a < FC_INT(0, UNIT)) {
        return FC_INT(-1, UNIT);
    }
    return FC_INT(0, UNIT);
}

/* ---- functions of the backend (scalar.c) ------------------------------ */

#if !FC_NUMERIC_FIXED && defined(FC_FLOAT_INLINE_MATH) && FC_FLOAT_INLINE_MATH
/* (float, inlined: the same expressions as scalar.c's out-of-line ones) */
static inline fc_real fc_sqrt(fc_arith *ar, fc_real x, int frac)
{
    (void)ar;
    (void)frac;
    return x > 0.0f ? __builtin_sqrtf(x) : 0.0f;
}

static inline fc_real fc_hypot3(fc_arith *ar, fc_real a, fc_real b, fc_real c)
{
    (void)ar;
    return __builtin_sqrtf(a * a + b * b + c * c);
}

static inline fc_real fc_rsqrt(fc_arith *ar, fc_real x, int frac_in, int frac_out)
{
    (void)frac_in;
    (void)frac_out;
    if (!(x > 0.0f)) {
        ar->saturated = 1u;
        return FC_REAL_MAX;
    }
    return 1.0f / __builtin_sqrtf(x);
}
#else
/* sqrt of x in format frac, result in the same format; x <= 0 gives 0. */
fc_real fc_sqrt(fc_arith *ar, fc_real x, int frac);

/* sqrt(a^2 + b^2 + c^2) in the format of a, b and c; the squares are summed
 * in 64 bits in fixed, so no intermediate overflows. */
fc_real fc_hypot3(fc_arith *ar, fc_real a, fc_real b, fc_real c);

/* 1/sqrt(x): x in format frac_in, result in format frac_out; x <= 0 saturates. */
fc_real fc_rsqrt(fc_arith *ar, fc_real x, int frac_in, int frac_out);
#endif

/* sqrt(x) for a UNIT x in [0, 1] (x <= 0 gives 0, x > 1 gives 1), as a UNIT
 * value to 16 bits: in fixed the root of x in Q32 (32 bits) rounded to Q16,
 * within 2^-17 of sqrt(x): the resolution of a 16-bit motor command, for
 * the rotor speeds of the allocation (a 30-bit root takes a 64-bit radicand,
 * some 4 times the ATmega's cycles). Float: fc_sqrt. */
#if FC_NUMERIC_FIXED
#ifndef FC_PORT_SQRT_UNIT16 /* (port: FC_PORT_SQRT_UNIT16) */
fc_real fc_sqrt_unit16(fc_arith *ar, fc_real x_unit);
#endif
#else
static inline fc_real fc_sqrt_unit16(fc_arith *ar, fc_real x_unit)
{
    return fc_sqrt(ar, x_unit, FC_UNIT_FRAC);
}
#endif

/* (c, s) = (a, b) / sqrt(a^2 + b^2) for UNIT16 a and b, given their n_sq =
 * fc_dot2_16(a, a, b, b) (UNIT16_SQ) of at least 2^-14; c and s UNIT16. Fixed:
 * 1/sqrt from fc_rsqrt's table and one Newton step, in 16 x 16-bit products
 * (no 64-bit one): c and s within 1.33 UNIT16 LSB of the exact ratio
 * (half an LSB of rounding and the table's and the step's relative error,
 * derived in test_scalar.test_unit2_16). Float:
 * fc_rsqrt and two products. */
#if FC_NUMERIC_FIXED
void fc_unit2_16(fc_arith *ar, fc_real16 a, fc_real16 b, fc_real n_sq, fc_real16 *c_out, fc_real16 *s_out);
#else
static inline void fc_unit2_16(fc_arith *ar, fc_real16 a, fc_real16 b, fc_real n_sq, fc_real16 *c_out,
                               fc_real16 *s_out)
{
    const fc_real inv_n = fc_rsqrt(ar, n_sq, FC_UNIT16_SQ_FRAC, FC_RATIO_FRAC);
    *c_out = a * inv_n;
    *s_out = b * inv_n;
}
#endif

/* The direction of (a, b, c) in UNIT16, direction[0..2] = (a, b, c) / |.|,
 * and *length = |.| in the components' format; false (all 0) for the zero
 * vector, and in float for a length that is not a finite number. Fixed: the
 * vector scaled by a power of two into 16-bit components, 1/|.| as in
 * fc_unit2_16 and the length from their squares' sum times it (one Heron
 * step, no root): the direction within 2.2 UNIT16 LSB of the exact one, the
 * length within 1.37 2^-14 of itself (test_scalar.test_direction16 derives
 * both bounds).
 * Float: the root and a reciprocal. */
#if FC_NUMERIC_FIXED
bool fc_direction16(fc_arith *ar, fc_real a, fc_real b, fc_real c, fc_real16 direction[3], fc_real *length);
#else
static inline bool fc_direction16(fc_arith *ar, fc_real a, fc_real b, fc_real c, fc_real16 direction[3],
                                  fc_real *length)
{
    const fc_real n = fc_hypot3(ar, a, b, c);
    if (!(n > 0.0f) || !fc_is_finite(n)) {
        direction[0] = 0.0f;
        direction[1] = 0.0f;
        direction[2] = 0.0f;
        *length = 0.0f;
        return false;
    }
    const fc_real inv_n = 1.0f / n;
    direction[0] = a * inv_n;
    direction[1] = b * inv_n;
    direction[2] = c * inv_n;
    *length = n;
    return true;
}
#endif

/* fc_hypot3(a, b, c) <= limit (limit >= 0), the same answer as that comparison;
 * in fixed without the root: the rounded root R of S = a^2 + b^2 + c^2 is the
 * integer with R^2 - R < S <= R^2 + R, so R <= limit iff S <= limit^2 + limit,
 * compared in 64 bits (the norm clamps, whose vectors are mostly inside). */
#if FC_NUMERIC_FIXED
bool fc_hypot3_within(fc_real a, fc_real b, fc_real c, fc_real limit);
#else
/* float: sqrt(S) <= limit iff S <= limit^2 for limit >= 0, no root; inline,
 * a compare of squares (six norm clamps a step in position control). A NaN
 * or an overflowed S (inf) compares false, as does a negative limit. */
static inline bool fc_hypot3_within(fc_real a, fc_real b, fc_real c, fc_real limit)
{
    const fc_real sum = a * a + b * b + c * c;
    return limit >= 0.0f && sum <= limit * limit;
}
#endif
/* Whether fc_hypot3(a, b, c) would saturate (its root beyond FC_REAL_MAX), told
 * without the root: for a caller that leaves out a norm it does not need and
 * keeps its saturation record as the norm would have left it. Never in float. */
static inline bool fc_hypot3_saturates(fc_real a, fc_real b, fc_real c)
{
#if FC_NUMERIC_FIXED
    return !fc_hypot3_within(a, b, c, FC_REAL_MAX);
#else
    (void)a;
    (void)b;
    (void)c;
    return false;
#endif
}

/* sin and cos of an ANGLE, results in UNIT. Accuracy in fixed: a few UNIT LSB. */
fc_real fc_sin(fc_arith *ar, fc_real angle_rad);
fc_real fc_cos(fc_arith *ar, fc_real angle_rad);

/* Both at once: the values of fc_sin and fc_cos, bit for bit; in fixed for
 * the cost of one (one range reduction). */
void fc_sincos(fc_arith *ar, fc_real angle_rad, fc_real *sin_out, fc_real *cos_out);

/* atan2(y, x) as an ANGLE in [-pi, pi]; y and x in any one common format. */
fc_real fc_atan2(fc_arith *ar, fc_real y, fc_real x);

/* asin of a UNIT value (clamped to [-1, 1]), as an ANGLE. */
fc_real fc_asin(fc_arith *ar, fc_real x_unit);

/* exp(-x) for x >= 0 in RATIO, result in UNIT: the pole of a discretised
 * first-order filter, e^(-dt/tau). Init-time use. */
fc_real fc_exp_neg(fc_arith *ar, fc_real x_ratio);

/* x^e for x in [0, 1] (UNIT) and e > 0 (RATIO), result in UNIT: a rotor's
 * normalised thrust against its normalised speed, T = T_max (w / w_max)^r.
 * Fixed: exp(e ln x) with both series, error a few 1e-7. */
fc_real fc_pow_unit(fc_arith *ar, fc_real x_unit, fc_real exponent_ratio);

/* Conversions for hosts and the Cortex-M (never called inside the library:
 * on the ATmega fixed image they would pull in soft-float). */
static inline fc_real fc_from_float(float x, int frac)
{
#if FC_NUMERIC_FIXED
    const float scaled = x * (float)((uint32_t)1u << frac);
    if (!(scaled == scaled)) {
        return 0;
    }
    if (scaled >= 2147483647.0f) {
        return FC_REAL_MAX;
    }
    if (scaled <= -2147483647.0f) {
        return FC_REAL_MIN;
    }
    return (fc_real)__builtin_roundf(scaled); /* one rounding: adding 0.5f would round twice */
#else
    (void)frac;
    return x;
#endif
}

static inline float fc_to_float(fc_real x, int frac)
{
#if FC_NUMERIC_FIXED
    return (float)x / (float)((uint32_t)1u << frac);
#else
    (void)frac;
    return x;
#endif
}

/* pi and its multiples in ANGLE. In fixed they are written as integers:
 * FC_C folds through a 24-bit float, 23 LSB off for pi in Q28. */
#if FC_NUMERIC_FIXED
#define FC_PI ((fc_real)843314857)         /* round(pi 2^28) */
#define FC_TWO_PI ((fc_real)1686629713)    /* round(2 pi 2^28) */
#define FC_HALF_PI ((fc_real)421657428)    /* round(pi/2 2^28) */
#define FC_QUARTER_PI ((fc_real)210828714) /* round(pi/4 2^28) */
#else
#define FC_PI 3.14159265f
#define FC_TWO_PI 6.28318531f
#define FC_HALF_PI 1.57079633f
#define FC_QUARTER_PI 0.785398163f
#endif

/* ======================================================================= */
/* Gains fixed at init: fc_gain and fc_mul_gain                            */
/* ======================================================================= */
/*
 * A constant the step multiplies a signal by, known once init has run (a
 * gain, a filter's coefficient, a pole's distance from 1, the airframe's
 * thrust limit), whose size the airframe decides: in fixed a 16-bit
 * mantissa with its own binary exponent, value = mantissa 2^-frac, the
 * exponent chosen at init as the finest that holds the value (|mantissa| in
 * [2^14, 2^15) for every value but 0): 15 significant bits, within 2^-15 of
 * the value relatively, for a 27 g and a 4 kg airframe alike. In float it is
 * the float, and the same source line serves both:
 *
 *     c->l0 = fc_gain_of(p->l0_per_s, FC_GAIN_FRAC);                     (init)
 *     l0_e = fc_mul_gain(ar, e_m, c->l0, FC_GAIN_SHIFT(LENGTH, VEL));     (step)
 *
 * reads "l0 times a LENGTH gives a VEL". The product x m / 2^(frac_x + frac
 * - frac_out) is rounded to nearest and saturated at +-INT32_MAX as fc_mul's
 * (a saturation sets ar->saturated), the same value as fc_mul of x and the
 * gain written out in 32 bits, but a 32 x 16-bit multiply (on the ATmega,
 * fc/scalar_avr.h, two 16 x 16 products and a narrowing by bytes and bits,
 * where fc_mul forms a 64-bit product).
 *
 * 15 bits hold little of a pole b near 1 (e^(-dt/tau) = 0.98 at 500 Hz and
 * 100 ms): a filter x <- b x + (1 - b) u is written x <- x + g (u - x) with the
 * gain g = 1 - b, which they hold to 2^-15 of itself.
 */

/* The right shift of a product by a gain, less the gain's own frac: the
 * signal's format IN and the result's OUT. */
#define FC_GAIN_SHIFT(IN, OUT) (FC_##IN##_FRAC - FC_##OUT##_FRAC)

#if FC_NUMERIC_FIXED
typedef struct fc_gain {
    int16_t mantissa; /* |mantissa| in [2^14, 2^15), or 0 */
    int8_t frac;      /* value = mantissa 2^-frac */
} fc_gain;

/* The gain of a value in format frac (init time; scalar.c): the mantissa
 * rounded to nearest, never saturated. */
fc_gain fc_gain_of(fc_real value, int frac);

/* The gain of the product a b (a in format frac_a, b in frac_b), from the
 * exact product: one rounding, to the mantissa, and never saturated, where
 * fc_gain_of(fc_mul(...)) would round twice and saturate beyond the format. */
fc_gain fc_gain_of_product(fc_real a, int frac_a, fc_real b, int frac_b);

/* The gain as a value in format frac, rounded to nearest and saturated
 * (tests, telemetry). */
fc_real fc_gain_to_real(fc_arith *ar, fc_gain g, int frac);


/* x m / 2^shift rounded to nearest and saturated, any shift: the portable
 * definition of the product, the reference of the ports and of the ATmega
 * equivalence test. |x m| < 2^46, so from a shift of 47 on the value is 0,
 * and from a left shift of 31 on every product but 0 saturates, as at 31
 * (fc_fx_narrow takes shifts from -62 to 63). */
FC_FX_INLINE fc_real fc_fx_mul_gain_reference(fc_arith *ar, fc_real x, int16_t mantissa, int shift)
{
    if (shift > 46) {
        return 0;
    }
    return fc_fx_narrow(ar, (int64_t)x * mantissa, shift < -31 ? -31 : shift);
}

/* (port: FC_PORT_MUL_GAIN) */
#ifndef FC_PORT_MUL_GAIN
FC_FX_INLINE fc_real fc_fx_mul_gain_shift(fc_arith *ar, fc_real x, int16_t mantissa, int8_t frac, int shift_in_out)
{
    return fc_fx_mul_gain_reference(ar, x, mantissa, frac + shift_in_out);
}
#endif

/* x g, x in format frac_x, the result in frac_out: shift_in_out =
 * FC_GAIN_SHIFT(X, OUT) = frac_x - frac_out. */
FC_FX_INLINE fc_real fc_mul_gain(fc_arith *ar, fc_real x, fc_gain g, int shift_in_out)
{
    return fc_fx_mul_gain_shift(ar, x, g.mantissa, g.frac, shift_in_out);
}
#else
typedef float fc_gain;

static inline fc_gain fc_gain_of(fc_real value, int frac)
{
    (void)frac;
    return value;
}

static inline fc_gain fc_gain_of_product(fc_real a, int frac_a, fc_real b, int frac_b)
{
    (void)frac_a;
    (void)frac_b;
    return a * b;
}

static inline fc_real fc_gain_to_real(fc_arith *ar, fc_gain g, int frac)
{
    (void)ar;
    (void)frac;
    return g;
}

static inline fc_real fc_mul_gain(fc_arith *ar, fc_real x, fc_gain g, int shift_in_out)
{
    (void)ar;
    (void)shift_in_out;
    return x * g;
}
#endif
/* ======================================================================= */

#endif /* FC_SCALAR_H */
