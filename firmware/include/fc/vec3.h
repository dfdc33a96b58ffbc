/*
 * fc/vec3.h - three-vectors of any signal kind.
 *
 * A vector holds one kind of signal (all three components in one Q-format).
 * Functions that multiply take the shift of the product (FC_SHIFT); the
 * others keep the operands' format.
 */
#ifndef FC_VEC3_H
#define FC_VEC3_H

#include "fc/scalar.h"

typedef struct fc_vec3 {
    fc_real x, y, z;
} fc_vec3;

static inline fc_vec3 fc_vec3_make(fc_real x, fc_real y, fc_real z)
{
    const fc_vec3 v = {x, y, z};
    return v;
}

/* The functions that take a shift are inlined where they are used: the
 * shift is then a constant (in fixed on the ATmega a run-time shift is a
 * loop, and the product's bytes are picked by moves only for a constant). */
#define FC_VEC3_INLINE static inline __attribute__((always_inline))

static inline fc_vec3 fc_vec3_zero(void)
{
    return fc_vec3_make(FC_INT(0, UNIT), FC_INT(0, UNIT), FC_INT(0, UNIT));
}

/* a + b and a - b, inlined too: a call passes the vectors by value (on the
 * ATmega the second on the stack, the result through memory), which costs
 * more than the three adds */
FC_VEC3_INLINE fc_vec3 fc_vec3_add(fc_arith *ar, fc_vec3 a, fc_vec3 b)
{
    return fc_vec3_make(fc_add_inline(ar, a.x, b.x), fc_add_inline(ar, a.y, b.y), fc_add_inline(ar, a.z, b.z));
}

FC_VEC3_INLINE fc_vec3 fc_vec3_sub(fc_arith *ar, fc_vec3 a, fc_vec3 b)
{
    return fc_vec3_make(fc_sub_inline(ar, a.x, b.x), fc_sub_inline(ar, a.y, b.y), fc_sub_inline(ar, a.z, b.z));
}

fc_vec3 fc_vec3_neg(fc_arith *ar, fc_vec3 v);

/* v * k: shift = FC_SHIFT(kind of v, kind of k, kind of the result). */
FC_VEC3_INLINE fc_vec3 fc_vec3_scale(fc_arith *ar, fc_vec3 v, fc_real k, int shift)
{
    return fc_vec3_make(fc_mul(ar, v.x, k, shift), fc_mul(ar, v.y, k, shift),
                        fc_mul(ar, v.z, k, shift));
}

/* Each component clamped to [-limit, limit] (limit >= 0, v's format). */
FC_VEC3_INLINE fc_vec3 fc_vec3_clamp_each(fc_arith *ar, fc_vec3 v, fc_real limit)
{
    const fc_real lo = fc_neg(ar, limit);
    return fc_vec3_make(fc_clamp(v.x, lo, limit), fc_clamp(v.y, lo, limit), fc_clamp(v.z, lo, limit));
}

/* Component-wise product (a diagonal matrix times a vector). */
FC_VEC3_INLINE fc_vec3 fc_vec3_mul_elementwise(fc_arith *ar, fc_vec3 a, fc_vec3 b, int shift)
{
    return fc_vec3_make(fc_mul(ar, a.x, b.x, shift), fc_mul(ar, a.y, b.y, shift),
                        fc_mul(ar, a.z, b.z, shift));
}

/* a . b, accumulated in 64 bits in fixed. */
FC_VEC3_INLINE fc_real fc_vec3_dot(fc_arith *ar, fc_vec3 a, fc_vec3 b, int shift)
{
    return fc_dot3(ar, a.x, b.x, a.y, b.y, a.z, b.z, shift);
}

/* a x b. */
FC_VEC3_INLINE fc_vec3 fc_vec3_cross(fc_arith *ar, fc_vec3 a, fc_vec3 b, int shift)
{
    /* each component is a difference of two products: one rounding each */
    return fc_vec3_make(fc_dot2(ar, a.y, b.z, fc_neg(ar, a.z), b.y, shift),
                        fc_dot2(ar, a.z, b.x, fc_neg(ar, a.x), b.z, shift),
                        fc_dot2(ar, a.x, b.y, fc_neg(ar, a.y), b.x, shift));
}

/* |v| in v's own format (no intermediate overflow: the squares are summed in
 * 64 bits in fixed). */
fc_real fc_vec3_norm(fc_arith *ar, fc_vec3 v, int frac);

/* v / |v| as a UNIT vector. A zero vector gives the zero vector and *ok = false. */
fc_vec3 fc_vec3_normalize(fc_arith *ar, fc_vec3 v, int frac, bool *ok);

/* The same with |v| already formed (norm = fc_vec3_norm(ar, v, frac)): a caller
 * that needs the length too takes one root, not two. */
fc_vec3 fc_vec3_divide_by_norm(fc_arith *ar, fc_vec3 v, fc_real norm, bool *ok);

/* Saturation that keeps the direction (dissertation 2.6.4): if |v| > max_norm,
 * v is scaled down to length max_norm; v and max_norm share format frac. */
fc_vec3 fc_vec3_clamp_norm(fc_arith *ar, fc_vec3 v, fc_real max_norm, int frac);

/* The same, and *clamped: whether the result differs from v (the test a
 * caller would make by comparing them, made only where v was scaled). */
fc_vec3 fc_vec3_clamp_norm_report(fc_arith *ar, fc_vec3 v, fc_real max_norm, int frac, bool *clamped);

/* |(x, y, z)| <= limit told without a product: true when |x| + |y| + |z| <=
 * limit (the 1-norm bounds the length), the common case of the norm clamps
 * (2.6.4), which then need neither squares nor a root. False says only
 * "not told so": the length may still be within the limit. */
FC_VEC3_INLINE bool fc_norm1_within(fc_real x, fc_real y, fc_real z, fc_real limit)
{
    /* what each component leaves of the limit: differences of values in
     * [0, limit], so nothing overflows; a NaN fails fc_within_runtime */
    if (!fc_within_runtime(x, limit)) {
        return false;
    }
    const fc_real after_x = limit - (x < FC_INT(0, UNIT) ? -x : x);
    if (!fc_within_runtime(y, after_x)) {
        return false;
    }
    return fc_within_runtime(z, after_x - (y < FC_INT(0, UNIT) ? -y : y));
}

/* Format change of all three components. */
FC_VEC3_INLINE fc_vec3 fc_vec3_convert(fc_arith *ar, fc_vec3 v, int frac_from, int frac_to)
{
    return fc_vec3_make(fc_convert(ar, v.x, frac_from, frac_to),
                        fc_convert(ar, v.y, frac_from, frac_to),
                        fc_convert(ar, v.z, frac_from, frac_to));
}

/* True when every component is a finite number (always true in fixed).
 * Inlined: called on every step, a few instructions each. */
FC_VEC3_INLINE bool fc_vec3_is_finite(fc_vec3 v)
{
    return fc_is_finite3(v.x, v.y, v.z);
}

/* Every component a number with |v_i| <= limit (fc_within). */
FC_VEC3_INLINE bool fc_vec3_within(fc_vec3 v, fc_real limit)
{
    return fc_within(v.x, limit) && fc_within(v.y, limit) && fc_within(v.z, limit);
}

/*
 * Three 16-bit values (fc_real16: int16_t in fixed, float in float): the
 * moments the inner loop's modules pass on (NORM16). In float the same
 * struct as fc_vec3, so no copies between the two.
 */
#if FC_NUMERIC_FIXED
typedef struct fc_vec3_16 {
    fc_real16 x, y, z;
} fc_vec3_16;
#else
typedef fc_vec3 fc_vec3_16;
#endif

/* v (format frac_from) rounded into the 16-bit format frac_to, saturated. */
FC_VEC3_INLINE fc_vec3_16 fc_vec3_narrow16(fc_arith *ar, fc_vec3 v, int frac_from, int frac_to)
{
    const fc_vec3_16 n = {fc_narrow16(ar, v.x, frac_from, frac_to), fc_narrow16(ar, v.y, frac_from, frac_to),
                          fc_narrow16(ar, v.z, frac_from, frac_to)};
    return n;
}

/* v (16-bit format frac_from) in the 32-bit format frac_to, exactly. */
FC_VEC3_INLINE fc_vec3 fc_vec3_widen16(fc_vec3_16 v, int frac_from, int frac_to)
{
    return fc_vec3_make(fc_widen16(v.x, frac_from, frac_to), fc_widen16(v.y, frac_from, frac_to),
                        fc_widen16(v.z, frac_from, frac_to));
}

/* The direction of v in UNIT16 and |v| (format of v): fc_direction16. */
static inline bool fc_vec3_direction16(fc_arith *ar, fc_vec3 v, fc_vec3_16 *direction, fc_real *length)
{
    fc_real16 d[3];
    const bool ok = fc_direction16(ar, v.x, v.y, v.z, d, length);
    const fc_vec3_16 r = {d[0], d[1], d[2]};
    *direction = r;
    return ok;
}

/* a x b of two 16-bit vectors: each component the difference of two exact
 * products (format frac_products, the sum of the operands' FRACs), rounded
 * once into the 16-bit format frac_to. */
FC_VEC3_INLINE fc_vec3_16 fc_vec3_16_cross(fc_arith *ar, fc_vec3_16 a, fc_vec3_16 b, int frac_products,
                                           int frac_to)
{
    const fc_vec3_16 c = {
        fc_narrow16(ar, fc_dot2_16(a.y, b.z, fc_neg16(a.z), b.y), frac_products, frac_to),
        fc_narrow16(ar, fc_dot2_16(a.z, b.x, fc_neg16(a.x), b.z), frac_products, frac_to),
        fc_narrow16(ar, fc_dot2_16(a.x, b.y, fc_neg16(a.y), b.x), frac_products, frac_to)};
    return c;
}

/* s v of 16-bit values: each exact product (format frac_product) rounded
 * into the 16-bit format frac_to. */
FC_VEC3_INLINE fc_vec3_16 fc_vec3_16_scale(fc_arith *ar, fc_vec3_16 v, fc_real16 s, int frac_product,
                                           int frac_to)
{
    const fc_vec3_16 r = {fc_narrow16(ar, fc_mul16(v.x, s), frac_product, frac_to),
                          fc_narrow16(ar, fc_mul16(v.y, s), frac_product, frac_to),
                          fc_narrow16(ar, fc_mul16(v.z, s), frac_product, frac_to)};
    return r;
}

static inline fc_vec3_16 fc_vec3_16_zero(void)
{
    const fc_vec3_16 z = {FC_INT16(0, NORM16), FC_INT16(0, NORM16), FC_INT16(0, NORM16)};
    return z;
}

#endif /* FC_VEC3_H */
