/*
 * scalar_test_avr.c - the ATmega image of atmega.scalar_equivalence: the fixed
 * backend's products as the ATmega computes them (fc/scalar_avr.h: assembly
 * multiply, results taken from the 32-bit halves) against the portable
 * definition written with C int64_t (fc_fx_rescale, fc_fx_add64,
 * fc_fx_saturate of fc/scalar.h, which avr-gcc computes through libgcc), on
 * the same target, over edge operands and pseudo-random ones, for every right
 * shift 1..33, 36, 38 and 40 as a compile-time constant (what the library uses) and through
 * a run-time shift (a shift passed to a function that is not inlined).
 * Compared: the value and the fc_arith saturation flag of fc_mul_inline,
 * fc_dot2_inline (the port's inline forms, as at the hot sites), fc_dot3,
 * fc_dot4, fc_acc_mac/fc_acc_result (8 products) and fc_convert;
 * and the functions of scalar.c with an ATmega-only path: fc_div (restoring
 * division in 32-bit halves, every shift 0..31) against its int64_t form,
 * fc_sqrt and fc_hypot3 (Heron step by restoring rounds) and fc_sqrt_unit16
 * (a chord and steps in assembly; also swept over its edges) against the
 * digit-by-digit square
 * root of the uint64_t value rounded to nearest, fc_narrow16 (shifts 10 and
 * 12..16; also at its saturation bounds) against the rounded value saturated
 * at +-INT16_MAX, and
 * fc_hypot3_within against that root compared, fc_mul16 (MULS/MULSU
 * assembly) against the C product of its operands, fc_add and fc_sub (ADD
 * and the V flag) against the int64_t sum saturated; the out-of-line products
 * that every other unit calls on the ATmega (fc_fx_mul_outline,
 * fc_fx_dot2/3/4_outline: a run-time shift narrowed by bytes and bits)
 * against the int64_t form; fc_mul_gain's product by a 16-bit mantissa (the
 * port's fc_fx_mul_gain_avr: two 16 x 16 products and a run-time shift
 * by bytes and bits) against fc_fx_mul_gain_reference, for every shift
 * -2..49 and some far beyond, operands at their edges and pseudo-random.
 *
 * No I/O: the counts are in scalar_test_cases / scalar_test_failures and the
 * first failure in scalar_test_first; scalar_test_done = 1 at the end, then
 * sleep with interrupts off (ends the simavr run). Read by scalar_test_host.c.
 */
#include <avr/interrupt.h>
#include <avr/sleep.h>
#include <stdint.h>

#include "fc/scalar.h"

#if !FC_NUMERIC_FIXED
#error "scalar_test_avr.c tests the fixed backend"
#endif

volatile uint32_t scalar_test_cases;
volatile uint32_t scalar_test_failures;
volatile uint8_t scalar_test_done;
/* the first failure: operation code, shift, got, expected */
volatile int32_t scalar_test_first[4];

static uint32_t rng_state = 0x2545F491u;

static uint32_t rng_next(void)
{
    /* xorshift32 (Marsaglia 2003) */
    uint32_t x = rng_state;
    x ^= x << 13;
    x ^= x >> 17;
    x ^= x << 5;
    rng_state = x;
    return x;
}

#define EDGE_COUNT 14
static const int32_t edges[EDGE_COUNT] = {
    INT32_MIN, INT32_MIN + 1, INT32_MAX, INT32_MAX - 1, 0, 1, -1, 2, -2,
    (int32_t)0x40000000, -(int32_t)0x40000000, (int32_t)0x3FFFFFFF, 46341, -46341,
};

/* an operand: an edge value, a full-range random one, or a random one of a
 * random bit length (small values, the common case in the library) */
static int32_t operand(void)
{
    const uint32_t pick = rng_next();
    switch (pick & 3u) {
    case 0:
        return edges[(pick >> 8) % EDGE_COUNT];
    case 1:
        return (int32_t)rng_next();
    default: {
        const uint8_t bits = (uint8_t)((pick >> 8) & 31u);
        return (int32_t)rng_next() >> bits;
    }
    }
}

static void check(uint8_t op, uint8_t shift, int32_t got, uint8_t got_sat, int32_t want, uint8_t want_sat)
{
    scalar_test_cases++;
    if (got != want || got_sat != want_sat) {
        if (scalar_test_failures == 0u) {
            scalar_test_first[0] = op;
            scalar_test_first[1] = shift;
            scalar_test_first[2] = got;
            scalar_test_first[3] = want;
        }
        scalar_test_failures++;
    }
}

/* ---- the portable definition, in C int64_t ---------------------------- */

static __attribute__((noinline)) int32_t ref_narrow(fc_arith *ar, int64_t value, int shift)
{
    return fc_fx_saturate(ar, fc_fx_rescale(ar, value, shift));
}

static __attribute__((noinline)) int32_t ref_dot(fc_arith *ar, const int32_t *a, const int32_t *b, int n, int shift)
{
    int64_t p[4] = {0, 0, 0, 0};
    for (int i = 0; i < n; i++) {
        p[i] = (int64_t)a[i] * b[i];
    }
    if (shift >= 32) {
        return fc_fx_narrow_sum(ar, p[0], p[1], p[2], p[3], shift); /* the sum in quarters */
    }
    return ref_narrow(ar, fc_fx_add64(fc_fx_add64(p[0], p[1]), fc_fx_add64(p[2], p[3])), shift);
}

static __attribute__((noinline)) int32_t ref_acc(fc_arith *ar, const int32_t *a, const int32_t *b, int shift)
{
    int64_t acc = 0;
    for (int i = 0; i < 8; i++) {
        acc += ((int64_t)a[i] * b[i]) >> FC_ACC_GUARD_BITS;
    }
    return ref_narrow(ar, acc, shift - FC_ACC_GUARD_BITS);
}

/* fc_div as it was, in int64_t */
static __attribute__((noinline)) int32_t ref_div(fc_arith *ar, int32_t num, int32_t den, int shift)
{
    if (den == 0) {
        ar->saturated = 1u;
        return num > 0 ? FC_REAL_MAX : (num < 0 ? FC_REAL_MIN : 0);
    }
    const int64_t scaled_num = fc_fx_rescale(ar, (int64_t)num, -shift);
    const int64_t den64 = den;
    if (scaled_num > INT64_MAX / 2 || scaled_num < -(INT64_MAX / 2)) {
        return fc_fx_saturate(ar, (scaled_num > 0) == (den > 0) ? INT64_MAX : -INT64_MAX);
    }
    const int64_t half_den = (den64 > 0 ? den64 : -den64) / 2;
    const int64_t rounded = scaled_num >= 0 ? scaled_num + half_den : scaled_num - half_den;
    return fc_fx_saturate(ar, rounded / den64);
}

/* round(sqrt(v)) by the digit-by-digit method in uint64_t */
static __attribute__((noinline)) uint32_t ref_sqrt(uint64_t v)
{
    uint64_t root = 0u;
    uint64_t bit = (uint64_t)1u << 62;
    uint64_t rest = v;
    while (bit > rest) {
        bit >>= 2;
    }
    while (bit != 0u) {
        if (rest >= root + bit) {
            rest -= root + bit;
            root = (root >> 1) + bit;
        } else {
            root >>= 1;
        }
        bit >>= 2;
    }
    if (v - root * root > root) {
        root++;
    }
    return (uint32_t)root;
}

#define OP_DIV 10u
#define OP_SQRT 11u
#define OP_HYPOT3 12u
#define OP_HYPOT3_WITHIN 13u
#define OP_MUL_OUTLINE 14u
#define OP_DOT2_OUTLINE 15u
#define OP_DOT3_OUTLINE 16u
#define OP_DOT4_OUTLINE 17u
#define OP_SQRT_UNIT16 18u
#define OP_NARROW16 19u
#define OP_MUL16 20u
#define OP_MUL_BY16 21u
#define OP_ADD 22u
#define OP_SUB 23u
#define OP_MUL_GAIN 24u

/* fc_narrow16's value: the rounded shift, saturated at +-INT16_MAX */
static int32_t ref_narrow16(fc_arith *ar, int32_t x, int shift)
{
    const int32_t r = ref_narrow(ar, (int64_t)x, shift);
    if (r > INT16_MAX || r < -INT16_MAX) {
        ar->saturated = 1u;
        return r > 0 ? INT16_MAX : -INT16_MAX;
    }
    return r;
}

/* one narrowing of x by shift against the portable definition */
static void check_narrow16(int32_t x, uint8_t shift, int32_t got, const fc_arith *got_ar)
{
    fc_arith want = {0u};
    const int32_t r = ref_narrow16(&want, x, shift);
    check(OP_NARROW16, shift, got, got_ar->saturated, r, want.saturated);
}

/* fc_narrow16 at the shifts the library uses, each a constant (the port
 * specialises on it): 16 (the high half and bit 15), 12 and 14
 * (fc_fx_low16_asr), 10, 13 and 15 (fc_convert) */
static void compare_narrow16(int32_t x)
{
    fc_arith got16 = {0u}, got15 = {0u}, got14 = {0u}, got13 = {0u}, got12 = {0u}, got10 = {0u};
    check_narrow16(x, 16u, fc_narrow16(&got16, x, 30, 14), &got16);
    check_narrow16(x, 15u, fc_narrow16(&got15, x, 28, 13), &got15);
    check_narrow16(x, 14u, fc_narrow16(&got14, x, 28, 14), &got14);
    check_narrow16(x, 13u, fc_narrow16(&got13, x, 27, 14), &got13);
    check_narrow16(x, 12u, fc_narrow16(&got12, x, 26, 14), &got12);
    check_narrow16(x, 10u, fc_narrow16(&got10, x, 24, 14), &got10);
}

/* fc_narrow16 on either side of its saturation bounds +-(2^16 - 1) 2^(n - 1)
 * and of the rounding steps (n - 1 bits of x set) for n = 10..16 */
static void sweep_narrow16(void)
{
    for (uint8_t n = 10; n <= 16; n++) {
        const int32_t bound = (int32_t)(((uint32_t)1u << 16) - 1u) << (n - 1);
        const int32_t half = (int32_t)((uint32_t)1u << (n - 1));
        for (int32_t d = -2; d <= 2; d++) {
            compare_narrow16(bound + d);
            compare_narrow16(-bound + d);
            compare_narrow16(half + d);
            compare_narrow16(-half + d);
            compare_narrow16(3 * half + d);
            compare_narrow16(-3 * half + d);
        }
    }
    for (int32_t d = 0; d <= 2; d++) {
        compare_narrow16(INT32_MAX - d);
        compare_narrow16(INT32_MIN + d);
    }
}

/* fc_mul16, fc_mul16_unsigned and fc_umul16 (the port's MULS/MULSU/MUL assembly) against
 * the C product of the values widened to int32_t or uint32_t (libgcc), for the low
 * halves of x and y and for the operands at their edges */
static __attribute__((noinline)) int32_t ref_mul16(int16_t x, int16_t y)
{
    return (int32_t)x * (int32_t)y;
}

static __attribute__((noinline)) int32_t ref_mul16_unsigned(uint16_t x, int16_t y)
{
    return (int32_t)x * (int32_t)y;
}

static __attribute__((noinline)) uint32_t ref_umul16(uint16_t x, uint16_t y)
{
    return (uint32_t)x * (uint32_t)y;
}

static void compare_mul16(int32_t x, int32_t y)
{
    const int16_t x16 = (int16_t)x, y16 = (int16_t)y;
    check(OP_MUL16, 0u, fc_mul16(x16, y16), 0u, ref_mul16(x16, y16), 0u);
    check(OP_MUL16, 1u, fc_mul16(x16, INT16_MAX), 0u, ref_mul16(x16, INT16_MAX), 0u);
    check(OP_MUL16, 2u, fc_mul16(-INT16_MAX, y16), 0u, ref_mul16(-INT16_MAX, y16), 0u);
    check(OP_MUL16, 3u, fc_mul16(INT16_MIN, y16), 0u, ref_mul16(INT16_MIN, y16), 0u);
    const uint16_t xu = (uint16_t)x;
    check(OP_MUL16, 4u, fc_mul16_unsigned(xu, y16), 0u, ref_mul16_unsigned(xu, y16), 0u);
    check(OP_MUL16, 5u, fc_mul16_unsigned(UINT16_MAX, y16), 0u, ref_mul16_unsigned(UINT16_MAX, y16), 0u);
    check(OP_MUL16, 6u, fc_mul16_unsigned(xu, -INT16_MAX), 0u, ref_mul16_unsigned(xu, -INT16_MAX), 0u);
    const uint16_t yu = (uint16_t)y;
    check(OP_MUL16, 7u, (int32_t)fc_umul16(xu, yu), 0u, (int32_t)ref_umul16(xu, yu), 0u);
    check(OP_MUL16, 8u, (int32_t)fc_umul16(UINT16_MAX, yu), 0u, (int32_t)ref_umul16(UINT16_MAX, yu), 0u);
    check(OP_MUL16, 9u, (int32_t)fc_umul16(xu, UINT16_MAX), 0u, (int32_t)ref_umul16(xu, UINT16_MAX), 0u);
}

/* fc_mul_by16 (two 16 x 16 products) against the 64-bit product narrowed
 * as every product is, with b the high half of the 32-bit operand (its edge
 * values reach +-INT16_MAX) */
static int16_t factor16(int32_t b)
{
    const int16_t high = (int16_t)(b >> 16);
    return high == INT16_MIN ? -INT16_MAX : high;
}

static void compare_mul_by16(uint8_t shift, int32_t a, int16_t b, int32_t got, uint8_t got_sat)
{
    fc_arith r = {0u};
    const int32_t want = ref_narrow(&r, (int64_t)a * b, shift);
    check(OP_MUL_BY16, shift, got, got_sat, want, r.saturated);
}

/* fc_add and fc_sub (the port's ADD/SUB with the V flag, called) and
 * fc_add_inline, fc_sub_inline (the same inlined) against the sum
 * in int64_t saturated at +-INT32_MAX (so -2^31 saturates too) */
static __attribute__((noinline)) int32_t ref_sum(fc_arith *ar, int64_t sum)
{
    return fc_fx_saturate(ar, sum);
}

static void compare_add_sub(int32_t x, int32_t y)
{
    fc_arith got = {0u}, want = {0u};
    int32_t value = fc_add(&got, x, y);
    check(OP_ADD, 0u, value, got.saturated, ref_sum(&want, (int64_t)x + y), want.saturated);
    got.saturated = 0u;
    want.saturated = 0u;
    value = fc_sub(&got, x, y);
    check(OP_SUB, 0u, value, got.saturated, ref_sum(&want, (int64_t)x - y), want.saturated);
    /* the inlined forms (reported with 1 in the shift's place) */
    got.saturated = 0u;
    want.saturated = 0u;
    value = fc_add_inline(&got, x, y);
    check(OP_ADD, 1u, value, got.saturated, ref_sum(&want, (int64_t)x + y), want.saturated);
    got.saturated = 0u;
    want.saturated = 0u;
    value = fc_sub_inline(&got, x, y);
    check(OP_SUB, 1u, value, got.saturated, ref_sum(&want, (int64_t)x - y), want.saturated);
}

/* fc_mul_gain: the port (fc_fx_mul_gain_shift, out of line) against the
 * portable definition in int64_t, for the shifts -2..49 (the port's 1..46,
 * where it hands over, and beyond), with the 16-bit mantissa m and its
 * edges */
static __attribute__((noinline)) int32_t ref_mul_gain(fc_arith *ar, int32_t x, int16_t m, int shift)
{
    return fc_fx_mul_gain_reference(ar, x, m, shift);
}

#define MANTISSA_EDGE_COUNT 10
static const int16_t mantissa_edges[MANTISSA_EDGE_COUNT] = {
    INT16_MIN, -INT16_MAX, INT16_MAX, 0, 1, -1, 16384, -16384, 16383, -16385,
};

/* the shift as the gain's frac and a signal's shift_in_out (fc_mul_gain),
 * split both ways and not at all */
static void compare_mul_gain_at(int32_t x, int16_t m, int shift)
{
    const int in_out = shift > 0 && shift < 100 ? shift % 7 - 3 : 0;
    fc_arith got = {0u}, want = {0u};
    const int32_t value = fc_fx_mul_gain_shift(&got, x, m, (int8_t)(shift - in_out), in_out);
    check(OP_MUL_GAIN, (uint8_t)shift, value, got.saturated, ref_mul_gain(&want, x, m, shift), want.saturated);
}

static void compare_mul_gain(int32_t x, int16_t m)
{
    static const int8_t far[] = {-128, -40, -32, -31, 63, 64, 100, 127};
    for (int shift = -2; shift <= 49; shift++) {
        compare_mul_gain_at(x, m, shift);
    }
    for (uint8_t i = 0; i < sizeof far; i++) {
        compare_mul_gain_at(x, m, far[i]);
    }
}

/* a mantissa: an edge, a full-range random one, or one of [2^14, 2^15) (what
 * fc_gain_of makes) */
static int16_t mantissa_operand(void)
{
    const uint32_t pick = rng_next();
    switch (pick & 3u) {
    case 0:
        return mantissa_edges[(pick >> 8) % MANTISSA_EDGE_COUNT];
    case 1:
        return (int16_t)rng_next();
    default: {
        const int16_t size = (int16_t)(0x4000u | (rng_next() & 0x3FFFu));
        return (pick & 0x100u) != 0u ? (int16_t)-size : size;
    }
    }
}

/* the 16-bit root of a UNIT value: sqrt(x 2^2) of Q32 rounded to Q16,
 * then Q30 (x of 1 and above: 1) */
static void compare_sqrt_unit16(int32_t x)
{
    fc_arith got = {0u};
    const int32_t value = fc_sqrt_unit16(&got, x);
    const int32_t want = x <= 0 ? 0
                         : x >= FC_INT(1, UNIT) ? FC_INT(1, UNIT)
                                                : (int32_t)(ref_sqrt((uint64_t)x << 2) << 14);
    check(OP_SQRT_UNIT16, 0u, value, got.saturated, want, 0u);
}

/* fc_sqrt_unit16 where its port's steps decide: the smallest x, each power
 * of two and its neighbours (the normalisation's bytes and pairs of bits),
 * the top of its chord (x = 2^30 - 2^14, where the guess is clamped, and
 * the x above, which round to 1) and x on either side of the rounding
 * boundaries 4 x = R^2 + R of random roots R. */
static void sweep_sqrt_unit16(void)
{
    for (int32_t x = -2; x <= 300; x++) {
        compare_sqrt_unit16(x);
    }
    for (uint8_t j = 2; j <= 30; j++) {
        const int32_t p = (int32_t)((uint32_t)1u << j);
        compare_sqrt_unit16(p - 1);
        compare_sqrt_unit16(p);
        compare_sqrt_unit16(p + 1);
    }
    for (int32_t d = -3; d <= 3; d++) {
        compare_sqrt_unit16(FC_INT(1, UNIT) - (1 << 14) + d);
        compare_sqrt_unit16(INT32_MAX + (d <= 0 ? d : -d));
    }
    for (uint16_t i = 0; i < 400u; i++) {
        const uint32_t root = rng_next() & 0xFFFFu;
        const int32_t boundary = (int32_t)((root * root + root) >> 2);
        for (int32_t d = -1; d <= 1; d++) {
            compare_sqrt_unit16(boundary + d);
        }
    }
}

static void compare_div(int32_t num, int32_t den, int shift)
{
    fc_arith got = {0u}, want = {0u};
    const int32_t value = fc_div(&got, num, den, shift);
    check(OP_DIV, (uint8_t)shift, value, got.saturated, ref_div(&want, num, den, shift), want.saturated);
}

/* a magnitude of 1 to 31 bits, either sign */
static int32_t signed_bits(uint8_t bits, uint32_t pick)
{
    const int32_t size = (int32_t)((rng_next() | 0x80000000u) >> (32u - bits));
    return (pick & 1u) != 0u ? -size : size;
}

/* fc_div where its port's steps decide: dividends whose quotient lands
 * within one of a rounding tie (N = q d + ceil(d/2), both sides) and of the
 * saturation bound (q = INT32_MAX), quotients of every size (the rounds by
 * whole bytes and the bytes skipped), and the altitude law's tilt
 * compensation (shift 24, a Q24 divisor in [1/2, 1]) densely */
static void sweep_div(void)
{
    for (uint16_t i = 0; i < 1500u; i++) {
        const uint32_t pick = rng_next();
        const int shift = (int)(pick % 32u);
        const uint8_t den_bits = (uint8_t)(1u + (pick >> 8) % 31u);
        const int32_t den = signed_bits(den_bits, pick >> 16);
        const uint64_t d = (uint64_t)(den < 0 ? -(int64_t)den : (int64_t)den);
        const uint8_t q_bits = (uint8_t)(1u + (pick >> 20) % 31u);
        const uint64_t q = (rng_next() | 0x80000000u) >> (32u - q_bits);
        /* the tie above q, or the saturation bound */
        const uint64_t target = ((pick >> 28) & 1u) != 0u ? q * d + (d + 1u) / 2u
                                                           : (uint64_t)INT32_MAX * d + (d + 1u) / 2u;
        const uint64_t n = target >> shift;
        for (int32_t step = -1; step <= 1; step++) {
            const int64_t num = (int64_t)n + step;
            if (num >= 0 && num <= INT32_MAX) {
                const int32_t sign = ((pick >> 29) & 1u) != 0u ? -1 : 1;
                compare_div(sign * (int32_t)num, den, shift);
            }
        }
        compare_div(signed_bits((uint8_t)(1u + (pick >> 24) % 31u), pick >> 3), den, shift);
    }
    for (uint16_t i = 0; i < 1500u; i++) {
        const int32_t tilt = (int32_t)(((uint32_t)1u << 23) + rng_next() % (((uint32_t)1u << 23) + 1u));
        compare_div(signed_bits((uint8_t)(1u + rng_next() % 31u), rng_next()), tilt, 24);
    }
    for (int32_t den = -3; den <= 3; den++) {
        for (int32_t num = -3; num <= 3; num++) {
            compare_div(num, den, 0);
            compare_div(num, den, 31);
            compare_div(INT32_MAX - 3 + num, den == 0 ? INT32_MIN : den, 0);
            compare_div(INT32_MIN + 3 + num, INT32_MAX - 3 + den, 31);
        }
    }
}

static void compare_functions(const int32_t *a, const int32_t *b)
{
    compare_add_sub(a[0], b[0]);
    compare_add_sub(a[2], b[2]);
    const int shift = (int)(rng_next() % 32u);
    fc_arith got = {0u}, want = {0u};
    int32_t value = fc_div(&got, a[0], b[0], shift);
    check(OP_DIV, (uint8_t)shift, value, got.saturated, ref_div(&want, a[0], b[0], shift), want.saturated);
    const int frac = (int)(rng_next() % 32u);
    got.saturated = 0u;
    value = fc_sqrt(&got, a[1], frac);
    const int32_t want_sqrt = a[1] > 0 ? (int32_t)ref_sqrt((uint64_t)a[1] << frac) : 0;
    check(OP_SQRT, (uint8_t)frac, value, got.saturated, want_sqrt, 0u);
    compare_sqrt_unit16(a[1]);
    compare_narrow16(a[2]);
    compare_mul16(a[3], b[3]);
    compare_mul16(a[3] >> (rng_next() % 16u), b[3] >> (rng_next() % 16u)); /* small ones too */
    compare_narrow16(a[2] >> (rng_next() % 24u)); /* and values near the 16-bit range */
    got.saturated = 0u;
    value = fc_hypot3(&got, a[2], b[2], a[3]);
    const uint64_t sum = (uint64_t)((int64_t)a[2] * a[2]) + (uint64_t)((int64_t)b[2] * b[2]) +
                         (uint64_t)((int64_t)a[3] * a[3]);
    const uint32_t root = ref_sqrt(sum);
    const bool over = root > (uint32_t)INT32_MAX;
    check(OP_HYPOT3, 0u, value, got.saturated, over ? FC_REAL_MAX : (int32_t)root, over ? 1u : 0u);
    /* against a limit near the root (the boundary) or anywhere */
    const uint32_t pick = rng_next();
    int32_t limit = (int32_t)(over ? (uint32_t)INT32_MAX : root) - (int32_t)(pick % 3u) + 1;
    if ((pick & 0x30u) == 0u) {
        limit = b[3];
    }
    if (limit >= 0) {
        const bool within = fc_hypot3_within(a[2], b[2], a[3], limit);
        check(OP_HYPOT3_WITHIN, 0u, within ? 1 : 0, 0u, (!over && root <= (uint32_t)limit) ? 1 : 0, 0u);
    }
}

/* ---- the library's primitives, shift a compile-time constant ----------- */

#define OP_MUL 1u
#define OP_DOT2 2u
#define OP_DOT3 3u
#define OP_DOT4 4u
#define OP_ACC 5u
#define OP_CONVERT_DOWN 6u
#define OP_CONVERT_UP 7u
#define OP_MUL_RUNTIME 8u
#define OP_DOT4_RUNTIME 9u

static void compare_one(uint8_t shift, const int32_t *a, const int32_t *b, int32_t mul, uint8_t mul_sat,
                        int32_t dot2, uint8_t dot2_sat, int32_t dot3, uint8_t dot3_sat, int32_t dot4,
                        uint8_t dot4_sat, int32_t acc, uint8_t acc_sat, int32_t down, uint8_t down_sat, int32_t up,
                        uint8_t up_sat)
{
    fc_arith r = {0u};
    int32_t want = ref_narrow(&r, (int64_t)a[0] * b[0], shift);
    check(OP_MUL, shift, mul, mul_sat, want, r.saturated);
    r.saturated = 0u;
    want = ref_dot(&r, a, b, 2, shift);
    check(OP_DOT2, shift, dot2, dot2_sat, want, r.saturated);
    r.saturated = 0u;
    want = ref_dot(&r, a, b, 3, shift);
    check(OP_DOT3, shift, dot3, dot3_sat, want, r.saturated);
    r.saturated = 0u;
    want = ref_dot(&r, a, b, 4, shift);
    check(OP_DOT4, shift, dot4, dot4_sat, want, r.saturated);
    if (shift > FC_ACC_GUARD_BITS) {
        r.saturated = 0u;
        want = ref_acc(&r, a, b, shift);
        check(OP_ACC, shift, acc, acc_sat, want, r.saturated);
    }
    r.saturated = 0u;
    want = ref_narrow(&r, (int64_t)a[0], shift);
    check(OP_CONVERT_DOWN, shift, down, down_sat, want, r.saturated);
    r.saturated = 0u;
    want = ref_narrow(&r, (int64_t)a[0], -(int)shift);
    check(OP_CONVERT_UP, shift, up, up_sat, want, r.saturated);
}

/* One function per shift S: the primitives inlined with S a constant. */
#define DEFINE_CASE(S)                                                                                 \
    static __attribute__((noinline)) void case_##S(const int32_t *a, const int32_t *b)                 \
    {                                                                                                  \
        fc_arith m = {0u}, d2 = {0u}, d3 = {0u}, d4 = {0u}, ac = {0u}, cd = {0u}, cu = {0u};           \
        const int32_t mul = fc_mul_inline(&m, a[0], b[0], S);                                          \
        const int32_t dot2 = fc_dot2_inline(&d2, a[0], b[0], a[1], b[1], S);                           \
        const int32_t dot3 = fc_dot3(&d3, a[0], b[0], a[1], b[1], a[2], b[2], S);                      \
        const int32_t dot4 = fc_dot4(&d4, a[0], b[0], a[1], b[1], a[2], b[2], a[3], b[3], S);          \
        int32_t acc = 0;                                                                               \
        if ((S) > FC_ACC_GUARD_BITS) {                                                                 \
            fc_acc sum = fc_acc_zero();                                                                \
            for (int i = 0; i < 8; i++) {                                                              \
                sum = fc_acc_mac(sum, a[i], b[i]);                                                     \
            }                                                                                          \
            acc = fc_acc_result(&ac, sum, (S) > FC_ACC_GUARD_BITS ? (S) : FC_ACC_GUARD_BITS + 1);      \
        }                                                                                              \
        const int32_t down = fc_convert(&cd, a[0], S, 0);                                              \
        const int32_t up = fc_convert(&cu, a[0], 0, S);                                                \
        compare_one(S, a, b, mul, m.saturated, dot2, d2.saturated, dot3, d3.saturated, dot4,           \
                    d4.saturated, acc, ac.saturated, down, cd.saturated, up, cu.saturated);            \
        if ((S) <= 31) {                                                                               \
            fc_arith m16 = {0u};                                                                       \
            const int16_t b16 = factor16(b[0]);                                                        \
            compare_mul_by16(S, a[0], b16, fc_mul_by16(&m16, a[0], b16, (S) <= 31 ? (S) : 31),         \
                             m16.saturated);                                                           \
        }                                                                                              \
    }

DEFINE_CASE(1) DEFINE_CASE(2) DEFINE_CASE(3) DEFINE_CASE(4) DEFINE_CASE(5) DEFINE_CASE(6) DEFINE_CASE(7)
DEFINE_CASE(8) DEFINE_CASE(9) DEFINE_CASE(10) DEFINE_CASE(11) DEFINE_CASE(12) DEFINE_CASE(13)
DEFINE_CASE(14) DEFINE_CASE(15) DEFINE_CASE(16) DEFINE_CASE(17) DEFINE_CASE(18) DEFINE_CASE(19)
DEFINE_CASE(20) DEFINE_CASE(21) DEFINE_CASE(22) DEFINE_CASE(23) DEFINE_CASE(24) DEFINE_CASE(25)
DEFINE_CASE(26) DEFINE_CASE(27) DEFINE_CASE(28) DEFINE_CASE(29) DEFINE_CASE(30) DEFINE_CASE(31)
/* shifts of 32 and more: products narrowed on the halves after a floor
 * (fc_fx_narrow_wide_far, fc_fx_narrow_quarters): the library's 32, 36 and
 * 38, the edges 33 and FC_FX_FAR_SHIFT_MAX + 2 = 40 (fc_mul's int64_t path
 * there); a sample, as the image's flash holds no more cases */
DEFINE_CASE(32) DEFINE_CASE(33) DEFINE_CASE(36) DEFINE_CASE(38) DEFINE_CASE(40)

#define CASE_COUNT 36
typedef void (*case_fn)(const int32_t *a, const int32_t *b);
static const case_fn cases[CASE_COUNT] = {
    case_1,  case_2,  case_3,  case_4,  case_5,  case_6,  case_7,  case_8,  case_9,  case_10, case_11, case_12,
    case_13, case_14, case_15, case_16, case_17, case_18, case_19, case_20, case_21, case_22, case_23, case_24,
    case_25, case_26, case_27, case_28, case_29, case_30, case_31, case_32, case_33, case_36, case_38, case_40,
};

/* The shift only known at run time (as in fc_vec3_scale): the looping path. */
static __attribute__((noinline)) void case_runtime(const int32_t *a, const int32_t *b, int shift)
{
    fc_arith m = {0u}, d4 = {0u}, r = {0u};
    const int32_t mul = fc_mul_inline(&m, a[0], b[0], shift);
    const int32_t dot4 = fc_dot4(&d4, a[0], b[0], a[1], b[1], a[2], b[2], a[3], b[3], shift);
    int32_t want = ref_narrow(&r, (int64_t)a[0] * b[0], shift);
    check(OP_MUL_RUNTIME, (uint8_t)shift, mul, m.saturated, want, r.saturated);
    r.saturated = 0u;
    want = ref_dot(&r, a, b, 4, shift);
    check(OP_DOT4_RUNTIME, (uint8_t)shift, dot4, d4.saturated, want, r.saturated);
    /* the out-of-line products (scalar.c) */
    fc_arith o = {0u};
    r.saturated = 0u;
    int32_t got = fc_fx_mul_outline(&o, a[0], b[0], shift);
    want = ref_narrow(&r, (int64_t)a[0] * b[0], shift);
    check(OP_MUL_OUTLINE, (uint8_t)shift, got, o.saturated, want, r.saturated);
    o.saturated = 0u;
    r.saturated = 0u;
    got = fc_fx_dot2_outline(&o, a[0], b[0], a[1], b[1], shift);
    want = ref_dot(&r, a, b, 2, shift);
    check(OP_DOT2_OUTLINE, (uint8_t)shift, got, o.saturated, want, r.saturated);
    o.saturated = 0u;
    r.saturated = 0u;
    got = fc_fx_dot3_outline(&o, a[0], b[0], a[1], b[1], a[2], b[2], shift);
    want = ref_dot(&r, a, b, 3, shift);
    check(OP_DOT3_OUTLINE, (uint8_t)shift, got, o.saturated, want, r.saturated);
    o.saturated = 0u;
    r.saturated = 0u;
    got = fc_fx_dot4_outline(&o, a[0], b[0], a[1], b[1], a[2], b[2], a[3], b[3], shift);
    want = ref_dot(&r, a, b, 4, shift);
    check(OP_DOT4_OUTLINE, (uint8_t)shift, got, o.saturated, want, r.saturated);
}

#ifndef SCALAR_TEST_ROUNDS
#define SCALAR_TEST_ROUNDS 200
#endif

int main(void)
{
    int32_t a[8], b[8];
    /* every pair of edge values in the first product, the others random */
    for (uint8_t i = 0; i < EDGE_COUNT; i++) {
        for (uint8_t j = 0; j < EDGE_COUNT; j++) {
            for (uint8_t k = 0; k < 8; k++) {
                a[k] = operand();
                b[k] = operand();
            }
            a[0] = edges[i];
            b[0] = edges[j];
            for (uint8_t s = 0; s < CASE_COUNT; s++) {
                cases[s](a, b);
                case_runtime(a, b, (int)s + 1);
            }
            compare_functions(a, b);
        }
    }
    /* fc_mul_gain: every edge operand against every edge mantissa */
    for (uint8_t i = 0; i < EDGE_COUNT; i++) {
        for (uint8_t j = 0; j < MANTISSA_EDGE_COUNT; j++) {
            compare_mul_gain(edges[i], mantissa_edges[j]);
        }
    }
    /* all eight products at the format's corners: the clamped 64-bit sums */
    for (uint8_t i = 0; i < EDGE_COUNT; i++) {
        for (uint8_t k = 0; k < 8; k++) {
            a[k] = edges[i];
            b[k] = edges[(uint8_t)(i + k) % EDGE_COUNT];
        }
        for (uint8_t s = 0; s < CASE_COUNT; s++) {
            cases[s](a, b);
        }
    }
    sweep_sqrt_unit16();
    sweep_narrow16();
    sweep_div();
    for (uint16_t round = 0; round < SCALAR_TEST_ROUNDS; round++) {
        for (uint8_t k = 0; k < 8; k++) {
            a[k] = operand();
            b[k] = operand();
        }
        for (uint8_t s = 0; s < CASE_COUNT; s++) {
            cases[s](a, b);
        }
        case_runtime(a, b, (int)(rng_next() % CASE_COUNT) + 1); /* 1..36: the outlines' far shifts too */
        for (uint8_t k = 0; k < 4; k++) {
            compare_mul_gain(operand(), mantissa_operand());
        }
        for (uint8_t k = 0; k < 8; k++) {
            compare_functions(a, b);
            a[0] = operand();
            b[0] = operand();
            a[1] = operand();
            a[2] = operand();
            b[2] = operand();
            a[3] = operand();
        }
    }
    scalar_test_done = 1u;
    cli();
    set_sleep_mode(SLEEP_MODE_PWR_DOWN);
    sleep_enable();
    for (;;) {
        sleep_cpu();
    }
}
