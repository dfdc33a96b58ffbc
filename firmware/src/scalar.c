/*
 * scalar.c - the backend functions that are too large to inline.
 *
 * This is the only file with two implementations: everything above it in
 * firmware/ is one source. The fixed implementations use integer arithmetic
 * only (no float, so the ATmega fixed image links no soft-float routines).
 */
#include "fc/scalar.h"

#if !FC_NUMERIC_FIXED
/* libm's single-precision functions, for the float backend below */
#include <math.h>
#endif

#if FC_NUMERIC_FIXED

/* Constant tables: in program memory on the ATmega (read by LPM), where a
 * const array would otherwise be copied into its 8 KB of RAM at start-up. */
#if defined(__AVR__)
#include <avr/pgmspace.h>
#define FC_ROM_TABLE PROGMEM
#define FC_ROM_READ_U16(address) pgm_read_word(address)
#else
#define FC_ROM_TABLE
#define FC_ROM_READ_U16(address) (*(address))
#endif


/* ----------------------------------------------------------------------- */
/* fixed backend                                                           */
/* ----------------------------------------------------------------------- */

/* A Q30 constant, folded at compile time. */
#define Q30(X) FC_C(X, UNIT)

/* fc_div: on the ATmega, where an int64_t division is a 64-round libgcc
 * loop, fc_div is the assembly of fc/scalar_avr.h (restoring division in
 * 32-bit halves, the same value: atmega.scalar_equivalence), which leaves
 * den == 0 and shifts outside 0..31 to this definition. The host's
 * test_scalar.test_div_exact checks it against an exact quotient. */
#if defined(__AVR__)
fc_real fc_fx_div_portable(fc_arith *ar, fc_real num, fc_real den, int shift)
#else
fc_real fc_div(fc_arith *ar, fc_real num, fc_real den, int shift)
#endif
{
    if (den == 0) {
        ar->saturated = 1u;
        return num > 0 ? FC_REAL_MAX : (num < 0 ? FC_REAL_MIN : 0);
    }
    const int64_t scaled_num = fc_fx_rescale(ar, (int64_t)num, -shift);
    const int64_t den64 = den;
    if (scaled_num > INT64_MAX / 2 || scaled_num < -(INT64_MAX / 2)) {
        /* |quotient| >= 2^62 / 2^31: saturated whatever the divisor; this also
         * keeps the rounding below from overflowing */
        return fc_fx_saturate(ar, (scaled_num > 0) == (den > 0) ? INT64_MAX : -INT64_MAX);
    }
    const int64_t half_den = (den64 > 0 ? den64 : -den64) / 2;
    /* round to nearest: push the dividend half a divisor away from zero */
    const int64_t rounded = scaled_num >= 0 ? scaled_num + half_den : scaled_num - half_den;
    return fc_fx_saturate(ar, rounded / den64);
}

/* x << n and x >> n for a run-time n in [0, 31]: whole bytes first (moves
 * on the ATmega, where a C shift by a variable count is a loop of n rounds),
 * then the 0..7 bits left. Plain shifts elsewhere. */
static uint32_t shl_u32(uint32_t x, int n)
{
#if defined(__AVR__)
    uint8_t k = (uint8_t)n;
    while (k >= 8u) {
        x <<= 8;
        k = (uint8_t)(k - 8u);
    }
    return x << k;
#else
    return x << n;
#endif
}

static uint32_t shr_u32(uint32_t x, int n)
{
#if defined(__AVR__)
    uint8_t k = (uint8_t)n;
    while (k >= 8u) {
        x >>= 8;
        k = (uint8_t)(k - 8u);
    }
    return x >> k;
#else
    return x >> n;
#endif
}

#define SQRT_SEGMENT_SHIFT 25 /* M in [2^30, 2^32) cut into segments of 2^25 */

/* The knots of isqrt_u32's first guess that enclose segment k (0..95) of M:
 * 2^16 sqrt(t) at t = 1/4 + k/128 and at the next knot, rounded, less 2^15
 * (0 to 2^15: 16 bits). The root is exact whatever they hold: a wrong knot
 * would cost steps, not a wrong value. */
static void sqrt_knots(uint8_t k, uint16_t *at_start, uint16_t *at_end)
{
    static const uint16_t knot_q16[97] FC_ROM_TABLE = {
        0, 508, 1008, 1502, 1988, 2467, 2940, 3407, 3868, 4323, 4772, 5217, 5656, 6090, 6519, 6944,
        7364, 7780, 8192, 8600, 9003, 9403, 9799, 10191, 10580, 10965, 11347, 11726, 12101, 12474,
        12843, 13209, 13573, 13934, 14291, 14647, 14999, 15349, 15697, 16041, 16384, 16724, 17062,
        17398, 17731, 18062, 18391, 18718, 19043, 19366, 19686, 20005, 20322, 20637, 20951, 21262,
        21572, 21879, 22186, 22490, 22793, 23094, 23394, 23691, 23988, 24283, 24576, 24868, 25158,
        25447, 25735, 26021, 26305, 26589, 26871, 27151, 27431, 27709, 27985, 28261, 28535, 28808,
        29080, 29351, 29620, 29889, 30156, 30422, 30687, 30951, 31214, 31475, 31736, 31995, 32254,
        32511, 32768
    };
    *at_start = FC_ROM_READ_U16(&knot_q16[k]);
    *at_end = FC_ROM_READ_U16(&knot_q16[k + 1u]);
}

/* floor(sqrt(m)) of a 32-bit m, and m - floor(sqrt(m))^2 in *remainder:
 *   M = m 4^k in [2^30, 2^32)                (normalised by pairs of bits)
 *   S0 = the chord of 2^16 sqrt(M / 2^32)    (the table above: M's segment
 *        and the position in it, one 16 x 16-bit product; within 2 of
 *        sqrt(M): the chord's sag of at most 1 on the first segment, the
 *        knots' and the product's roundings)
 *   S = floor(sqrt(M))                       (S0 stepped, S^2 kept by adds)
 *   floor(sqrt(m)) = floor(S / 2^k)          (sqrt(m) = sqrt(M) / 2^k)
 * Exact for every m whatever the first guess (the steps make it so; the
 * guess, within -2..+1 of S over every M, only bounds their number). For
 * fc_sqrt and fc_hypot3; fc_sqrt_unit16 has its own root (sqrt16_digits;
 * on the ATmega a chord and steps of its own in assembly). */
static uint16_t isqrt_u32(uint32_t m, uint32_t *remainder)
{
    if (m == 0u) {
        *remainder = 0u;
        return 0u;
    }
    uint32_t big_m = m;
    uint8_t k = 0u;
    while (big_m < ((uint32_t)1u << 24)) {
        big_m <<= 8; /* whole bytes first: moves on the ATmega */
        k = (uint8_t)(k + 4u);
    }
    while (big_m < ((uint32_t)1u << 30)) {
        big_m <<= 2;
        k++;
    }
    /* the chord (a C shift by 25 or 9 is a loop of that many rounds on the
     * ATmega at -Os: fc_fx_extract's bytes) */
    const uint8_t segment = (uint8_t)(fc_fx_extract(big_m, 0u, SQRT_SEGMENT_SHIFT) - 32u);
    const uint16_t position_q16 = (uint16_t)fc_fx_extract(big_m, 0u, SQRT_SEGMENT_SHIFT - 16);
    uint16_t knot_start, knot_end;
    sqrt_knots(segment, &knot_start, &knot_end);
    const uint32_t rise_q16 = (uint32_t)(uint16_t)(knot_end - knot_start) * position_q16;
    uint16_t root = (uint16_t)(32768u + knot_start + (uint16_t)(rise_q16 >> 16));
    /* the steps: (S - 1)^2 = S^2 - 2 S + 1, and (S + 1)^2 <= M compared
     * as M - S^2 >= 2 S + 1 (no sum beyond 32 bits; false at S = 2^16 - 1,
     * as M < 2^32) */
    uint32_t square = (uint32_t)root * root;
    while (square > big_m) {
        square -= ((uint32_t)root << 1) - 1u;
        root--;
    }
    while (big_m - square >= ((uint32_t)root << 1) + 1u) {
        square += ((uint32_t)root << 1) + 1u;
        root++;
    }
    if (k == 0u) {
        *remainder = big_m - square;
        return root;
    }
    root = (uint16_t)(root >> k);
    *remainder = m - (uint32_t)root * root;
    return root;
}

/* 2^15 r + floor(l / 2^17) for r < 2^17: the 40 bits r:l[31..16] shifted
 * right by one (on the ATmega whole bytes by moves, then one bit of the five
 * bytes, instead of two shift loops of 15 and 17 rounds). */
static uint32_t heron_numerator(uint32_t r, uint32_t l)
{
#if defined(__AVR__)
    uint32_t word = (r << 16) | (l >> 16);
    uint8_t top = (uint8_t)(r >> 16);
    FC_AVR_SHR40(word, top, 1);
    return word;
#else
    return (r << 15) + (l >> 17);
#endif
}

/* floor(n / s) for s in [2^15, 2^16) and n / s < 2^17: the first quotient
 * bit from n's top half, then 16 restoring rounds (a 32-bit division is a
 * 32-round libgcc loop on the ATmega). */
static uint32_t heron_quotient(uint32_t n, uint32_t s)
{
#if !defined(__AVR__)
    return n / s; /* a hardware divide elsewhere */
#else
    uint32_t rest = n >> 16;
    uint32_t low = n << 16;
    uint32_t quotient = 0u;
    if (rest >= s) {
        rest -= s;
        quotient = 1u;
    }
    /* 16 rounds (rest below 2 s < 2^17): n's low half shifts out of low's top,
     * the quotient bits come in at its bottom */
    fc_avr_divide_rounds(&rest, &low, s, 16u);
    return (quotient << 16) | (low & 0xFFFFu);
#endif
}

/* a > b for unsigned 64-bit values held as halves */
static bool wide_above(fc_fx_wide a, fc_fx_wide b)
{
    return a.high > b.high || (a.high == b.high && a.low > b.low);
}

static fc_fx_wide wide_plus(fc_fx_wide a, uint32_t b)
{
    fc_fx_wide sum;
    sum.low = a.low + b;
    sum.high = a.high + (sum.low < b ? 1u : 0u);
    return sum;
}

static fc_fx_wide wide_minus(fc_fx_wide a, uint32_t b)
{
    fc_fx_wide difference;
    difference.low = a.low - b;
    difference.high = a.high - (a.low < b ? 1u : 0u);
    return difference;
}

/*
 * sqrt(v) rounded to nearest, v unsigned 64-bit as halves (below 2^64 - 2^32),
 * in 32-bit C and 32 x 32 -> 64 products only (on the ATmega a 64-bit C
 * operation is a libgcc loop). The rounded root R is the one integer with
 * R^2 - R < v <= R^2 + R ((R -+ 1/2)^2 = R^2 -+ R + 1/4 and v is an integer),
 * so any estimate is made exact by stepping R with R^2 kept incrementally;
 * the estimate is within a few units, so the steps are few:
 *   v 4^n = 2^32 m + l with m in [2^30, 2^32)   (normalised by pairs of bits)
 *   s = floor(sqrt(m)), r = m - s^2 <= 2 s        (16-bit root of the top half)
 *   sqrt(v 4^n) ~ 2^16 s + (2^32 r + l) / (2^17 s) (one Heron step, error < 4)
 *   R0 = that / 2^n.
 */
static uint32_t sqrt_rounded_wide(fc_fx_wide v)
{
    if (v.high == 0u && v.low == 0u) {
        return 0u;
    }
    /* normalise: whole bytes first, then pairs of bits */
    uint32_t m = v.high;
    uint32_t l = v.low;
    int n = 0;
    if (m == 0u) {
        m = l;
        l = 0u;
        n = 16;
    }
    while (m < ((uint32_t)1u << 24)) {
        m = (m << 8) | (l >> 24);
        l <<= 8;
        n += 4;
    }
    while (m < ((uint32_t)1u << 30)) {
        m = (m << 1) | (l >> 31);
        l <<= 1;
        m = (m << 1) | (l >> 31);
        l <<= 1;
        n += 1;
    }
    uint32_t r;
    const uint32_t s = isqrt_u32(m, &r); /* s in [2^15, 2^16), r = m - s^2 <= 2 s < 2^17 */
    /* (2^32 r + l) / (2^17 s) = (2^15 r + l / 2^17) / s: the numerator fits 32 bits */
    const uint32_t heron = heron_quotient(heron_numerator(r, l), s);
    const uint32_t top = s << 16;
    uint32_t root = top + heron < top ? UINT32_MAX : top + heron;
    root = shr_u32(root, n);
    /* exact by steps: R^2 - R < v <= R^2 + R */
    fc_fx_wide square = fc_fx_umul_wide(root, root);
    while (wide_above(v, wide_plus(square, root))) {
        square = wide_plus(wide_plus(square, root), root + 1u); /* (R + 1)^2 = R^2 + 2R + 1 */
        root++;
    }
    while (root > 0u && !wide_above(v, wide_minus(square, root))) {
        square = wide_plus(wide_minus(wide_minus(square, root), root), 1u); /* (R - 1)^2 */
        root--;
    }
    return root;
}

fc_real fc_sqrt(fc_arith *ar, fc_real x, int frac)
{
    (void)ar;
    if (x <= 0) {
        return 0;
    }
    /* sqrt(X / 2^f) * 2^f = sqrt(X * 2^f): X < 2^31 and f <= 31 keep X * 2^f < 2^62 */
    fc_fx_wide scaled;
    if (frac <= 0) {
        scaled.low = (uint32_t)x;
        scaled.high = 0u;
    } else {
        scaled.low = shl_u32((uint32_t)x, frac);
        scaled.high = shr_u32((uint32_t)x, 32 - frac); /* frac >= 1 here */
    }
    return (fc_real)sqrt_rounded_wide(scaled);
}

/* floor(sqrt(m)) of a 32-bit m and m - floor(sqrt(m))^2 in *remainder, digit
 * by digit: each round brings the next two bits of m down and decides one
 * bit of the root, the trial value b = (4 r + 1) 4^(15 - i) (r the i bits
 * so far) subtracted from what is left of m when it fits (Warren, Hacker's
 * Delight, 11-1). No product: 16 rounds of adds and shifts. */
#ifndef FC_PORT_SQRT_UNIT16
static uint16_t sqrt16_digits(uint32_t m, uint32_t *remainder)
{
    uint32_t rest = m;
    uint32_t root = 0u; /* r 4^(16 - i): r's bits above the trial bit */
    uint32_t bit = (uint32_t)1u << 30;
    while (bit != 0u) {
        const uint32_t trial = root | bit;
        root >>= 1;
        if (rest >= trial) {
            rest -= trial;
            root |= bit;
        }
        bit >>= 2;
    }
    *remainder = rest;
    return (uint16_t)root;
}
#endif

#ifndef FC_PORT_SQRT_UNIT16
fc_real fc_sqrt_unit16(fc_arith *ar, fc_real x_unit)
{
    (void)ar;
    if (x_unit <= 0) {
        return 0;
    }
    /* x in Q32 (1 itself held as 2^32 - 1, whose root rounds to 2^16 all the
     * same), its 16-bit root rounded: floor s with remainder r = m - s^2 is
     * rounded up iff m > (s + 1/2)^2 = s^2 + s + 1/4, i.e. r > s */
    _Static_assert(FC_UNIT_FRAC == 30, "the root in Q16 times 2^14 is UNIT");
    const uint32_t m = x_unit >= FC_INT(1, UNIT) ? UINT32_MAX : (uint32_t)x_unit << (32 - FC_UNIT_FRAC);
    uint32_t remainder;
    const uint32_t root_q16 = sqrt16_digits(m, &remainder);
    const uint32_t rounded_q16 = remainder > root_q16 ? root_q16 + 1u : root_q16;
    return (fc_real)(rounded_q16 << (FC_UNIT_FRAC - 16)); /* at most 2^16 2^14 = 2^30 (1 exactly) */
}
#endif

/* a^2 + b^2 + c^2: each square is at most 2^62, so three of them fit 64 bits
 * unsigned. One copy (its three products are the flash of a few hundred
 * bytes on the ATmega) for fc_hypot3 and fc_hypot3_within. */
static __attribute__((noinline)) fc_fx_wide sum_of_squares(fc_real a, fc_real b, fc_real c)
{
    const fc_fx_wide aa = fc_fx_mul_wide(a, a), bb = fc_fx_mul_wide(b, b);
    const fc_fx_wide ab = fc_fx_add_wide_wrap(aa, bb);
    if (c == 0) {
        return ab; /* a plane vector (the controller's horizontal error): one product fewer */
    }
    return fc_fx_add_wide_wrap(ab, fc_fx_mul_wide(c, c));
}

fc_real fc_hypot3(fc_arith *ar, fc_real a, fc_real b, fc_real c)
{
    const uint32_t root = sqrt_rounded_wide(sum_of_squares(a, b, c));
    if (root > (uint32_t)INT32_MAX) {
        ar->saturated = 1u;
        return FC_REAL_MAX;
    }
    return (fc_real)root;
}

bool fc_hypot3_within(fc_real a, fc_real b, fc_real c, fc_real limit)
{
    const fc_fx_wide sum = sum_of_squares(a, b, c); /* < 3 2^62 */
    const uint32_t l = limit > 0 ? (uint32_t)limit : 0u;
    const fc_fx_wide bound = wide_plus(fc_fx_umul_wide(l, l), l); /* l^2 + l < 2^62 + 2^31 */
    return !wide_above(sum, bound);
}

/* Bit length of a positive value: X lies in [2^(len-1), 2^len). */
static int bit_length_u32(uint32_t x)
{
    int len = 0;
    while (x >= 256u) { /* whole bytes first */
        x >>= 8;
        len += 8;
    }
    while (x != 0u) {
        x >>= 1;
        len++;
    }
    return len;
}

/*
 * 1/sqrt(x), division-free: x = m * 4^j with m in [1/4, 1), a first guess of
 * y = 1/sqrt(m) in (1, 2] from a table, then Newton steps
 * y <- y (3 - m y^2) / 2, y held in Q29.
 */
#define RSQRT_Y_FRAC 29
#define RSQRT_SEGMENT_SHIFT 25 /* m in Q30 cut into segments of 2^25, i.e. 1/32 */
#define RSQRT_KNOT_FRAC 14     /* the table's 1/sqrt values: Q14, below 2^15 */
#define RSQRT_NEWTON_STEPS 2

/* The table's values at the start and the end of segment k of m (Q30:
 * k = m / 2^25 - 8, 0..23): 1/sqrt(1/4 + k/32) and 1/sqrt(1/4 + (k+1)/32). */
static void rsqrt_knots(uint32_t k, uint16_t *at_start, uint16_t *at_end)
{
    /* round(2^14 / sqrt(1/4 + k/32)), k = 0..24 (test_scalar.test_rsqrt_exact
     * derives the same values) */
    static const uint16_t knot_q14[25] FC_ROM_TABLE = {
        32768, 30894, 29309, 27945, 26755, 25705, 24770, 23930, 23170, 22479, 21845, 21263, 20724,
        20225, 19760, 19326, 18919, 18536, 18176, 17837, 17515, 17211, 16921, 16646, 16384};
    *at_start = FC_ROM_READ_U16(&knot_q14[k]);
    *at_end = FC_ROM_READ_U16(&knot_q14[k + 1u]);
}

/* The first guess of 1/sqrt(m), m in [1/4, 1) in Q30: the chord of 1/sqrt
 * over m's segment of the table, within 1.3e-3; the knots (Q14) minus their
 * difference times the position in the segment (Q16), a 16 x 16-bit
 * product, give Q30. (The constant shifts by fc_fx_extract: a C shift by 25
 * or 9 is a loop of that many rounds on the ATmega at -Os.) Inlined in its
 * two callers, both on the ATmega's step. */
static inline __attribute__((always_inline)) uint32_t rsqrt_chord_q30(uint32_t m_q30)
{
    uint16_t knot_start, knot_end;
    rsqrt_knots(fc_fx_extract(m_q30, 0u, RSQRT_SEGMENT_SHIFT) - 8u, &knot_start, &knot_end);
    const uint16_t position_q16 = (uint16_t)fc_fx_extract(m_q30, 0u, RSQRT_SEGMENT_SHIFT - 16);
    const uint32_t drop_q30 = fc_umul16((uint16_t)(knot_start - knot_end), position_q16);
    return ((uint32_t)knot_start << 16) - drop_q30;
}

fc_real fc_rsqrt(fc_arith *ar, fc_real x, int frac_in, int frac_out)
{
    if (x <= 0) {
        ar->saturated = 1u;
        return FC_REAL_MAX;
    }
    const int len = bit_length_u32((uint32_t)x);
    /* m = X 2^s in Q30 with its top bit at 28 or 29, and 30 - s - frac_in even */
    int s = 30 - len;
    if (((30 - s - frac_in) & 1) != 0) {
        s -= 1;
    }
    const int32_t m_q30 = s >= 0 ? (int32_t)shl_u32((uint32_t)x, s) : (int32_t)shr_u32((uint32_t)x, -s);
    const int j = (30 - s - frac_in) / 2; /* x = m * 2^(2j) */

    const int shift_to_y = RSQRT_KNOT_FRAC + 16 - RSQRT_Y_FRAC; /* Q30 to Q29 */
    int32_t y = (int32_t)(rsqrt_chord_q30((uint32_t)m_q30) >> shift_to_y);

    /* two Newton steps take 1.3e-3 to 3.4e-6 and then to the Q29 resolution:
     * at most 1.01 LSB from 1/sqrt(m) over all 805,306,368 values of m (an
     * exhaustive host run; the five steps from a linear guess this replaces
     * gave 1.00 LSB for three more steps, ~2,700 ATmega cycles). The
     * products are 32 x 32 -> 64 in halves (fc_fx_umul_wide), each shift a floor:
     *   y2 = y^2 / 2^28    Q30, below 2^34 (held as top 2^32 + low)
     *   my2 = m y2 / 2^30  Q30, m y^2 <= 1.003 after the guess, <= 1 after a step
     *   y <- y (3 - my2) / 2^31
     * (the values of the int64_t form, bit for bit: test_scalar.test_rsqrt_exact) */
    for (int i = 0; i < RSQRT_NEWTON_STEPS; i++) {
        const fc_fx_wide yy = fc_fx_umul_wide((uint32_t)y, (uint32_t)y);
        const uint32_t y2_low = fc_fx_extract(yy.low, yy.high, 2 * RSQRT_Y_FRAC - 30);
        const uint32_t y2_top = fc_fx_extract(yy.high, 0u, 2 * RSQRT_Y_FRAC - 30); /* bits 32.. of y2 */
        fc_fx_wide my2 = fc_fx_umul_wide((uint32_t)m_q30, y2_low);
        my2.high += (uint32_t)m_q30 * y2_top;
        const uint32_t my2_q30 = fc_fx_extract(my2.low, my2.high, 30);
        const uint32_t three_q30 = (uint32_t)3u << 30;
        /* 3 - m y^2 > 0 (m y^2 <= 1.003); kept at 0 if it were not */
        const uint32_t corr_q30 =
            my2.high < ((uint32_t)1u << 30) && my2_q30 <= three_q30 ? three_q30 - my2_q30 : 0u;
        const fc_fx_wide next = fc_fx_umul_wide((uint32_t)y, corr_q30);
        y = (int32_t)fc_fx_extract(next.low, next.high, 31); /* y (3 - m y^2) / 2 */
    }
    /* 1/sqrt(x) = y 2^-j, from Q29 to frac_out */
    return fc_convert(ar, y, RSQRT_Y_FRAC + j, frac_out);
}

/*
 * (c, s) = (a, b) / N, N = sqrt(n_sq), in 16-bit products: n_sq = m 4^-k with
 * m in [1/4, 1) (k = -1..6: n_sq is at least 2^-14 and, the components of a
 * rounded unit quaternion, below 4), y0 = fc_rsqrt's chord for 1/sqrt(m)
 * (within 1.3e-3), one Newton step y = y0 + y0 (1 - m y0^2) / 2 (within
 * 2.5e-6, plus the roundings of its 16-bit operands), then c = a y 2^k.
 *   m       Q28 in 32 bits, and Q16 in 16 for the step
 *   y0, y   Q15 unsigned, in (1, 2) (2 itself, at m = 1/4, held at 2 - 2^-15)
 *   m y0    Q31, its top half t Q15; t y0 = m y0^2 Q30; d = 1 - m y0^2 Q30,
 *           below 2^-8.5 in magnitude, taken to Q22 in 16 bits
 *   a y     Q29 (below 2^30: a <= N), c = a y 2^k Q29 rounded to UNIT16
 */
#define UNIT2_M_FRAC FC_UNIT16_SQ_FRAC
#define UNIT2_Y_FRAC 15
#define UNIT2_D16_FRAC 22

static void unit2_scaled(fc_arith *ar, fc_real16 v, uint16_t y_q15, int k, fc_real16 *out)
{
    int32_t v_y = fc_mul16_unsigned(y_q15, v); /* Q14 x Q15 = Q29 */
    if (k < 0) {
        /* k = -1 (n_sq in [1, 4)): halved, a floor (the rounding below is
         * at bit 14; a C division by 2 is a libgcc call on the ATmega) */
        v_y = (int32_t)fc_fx_extract((uint32_t)v_y, v_y < 0 ? UINT32_MAX : 0u, 1);
    }
    for (int i = 0; i < k; i++) {
        v_y *= 2; /* |c| <= 1: stays below 2^30 */
    }
    *out = fc_narrow16(ar, v_y, FC_UNIT16_FRAC + UNIT2_Y_FRAC, FC_UNIT16_FRAC);
}

/* y = 1/sqrt(m) in Q15 for m in [1/4, 1) given in Q28 ([2^26, 2^28)): the
 * chord and the Newton step above; y in (1, 2], 2 itself held as 2^16 - 1. */
static uint16_t rsqrt_newton_q15(uint32_t m)
{
    /* first guess: fc_rsqrt's chord (m in Q30 below 2^30), then Q15 */
    const uint32_t y0_wide = fc_fx_extract(rsqrt_chord_q30(m << (30 - UNIT2_M_FRAC)), 0u, 30 - UNIT2_Y_FRAC);
    const uint16_t y0 = y0_wide > UINT16_MAX ? UINT16_MAX : (uint16_t)y0_wide;
    /* one Newton step: m to Q16 and m y0 to Q15, each rounded (m below
     * 1 - 2^-17 keeps Q16 in 16 bits) */
    const uint32_t m_rounded = m + ((uint32_t)1u << (UNIT2_M_FRAC - 17));
    const uint16_t m_q16 = m_rounded >= (uint32_t)1u << UNIT2_M_FRAC
                               ? UINT16_MAX
                               : (uint16_t)fc_fx_extract(m_rounded, 0u, UNIT2_M_FRAC - 16);
    const uint32_t t_q31 = fc_umul16(m_q16, y0) + ((uint32_t)1u << 15);
    const uint16_t t_q15 = (uint16_t)(t_q31 >> 16); /* m y0 < 1.002: below 2^16 */
    const int32_t d_q30 = (int32_t)(((uint32_t)1u << 30) - fc_umul16(t_q15, y0)); /* 1 - m y0^2 */
    /* |d| < 2^-8.5: below 2^13.5 in Q22 (a floor, by a byte move) */
    const int16_t d_q22 = (int16_t)fc_fx_extract((uint32_t)d_q30, d_q30 < 0 ? UINT32_MAX : 0u, 8);
    /* y0 d / 2: Q15 x Q22 = Q37, the half Q38, rounded to Q15 */
    const int32_t half_step_q38 = fc_mul16_unsigned(y0, d_q22) + ((int32_t)1 << (UNIT2_D16_FRAC));
    const int32_t y = (int32_t)y0 + (int32_t)fc_fx_extract((uint32_t)half_step_q38,
                                                            half_step_q38 < 0 ? UINT32_MAX : 0u,
                                                            UNIT2_D16_FRAC + 1);
    return y > UINT16_MAX ? UINT16_MAX : (uint16_t)y;
}

void fc_unit2_16(fc_arith *ar, fc_real16 a, fc_real16 b, fc_real n_sq, fc_real16 *c_out, fc_real16 *s_out)
{
    /* m = n_sq 4^k in [1/4, 1): Q28 in [2^26, 2^28) */
    uint32_t m = n_sq > 0 ? (uint32_t)n_sq : 1u;
    int k = 0;
    if (m >= (uint32_t)1u << UNIT2_M_FRAC) {
        m >>= 2;
        k = -1;
    }
    while (m < (uint32_t)1u << (UNIT2_M_FRAC - 2)) {
        m <<= 2;
        k++;
    }
    const uint16_t y_q15 = rsqrt_newton_q15(m);
    unit2_scaled(ar, a, y_q15, k, c_out);
    unit2_scaled(ar, b, y_q15, k, s_out);
}

/*
 * The direction and the length of (a, b, c), in 16-bit products:
 *   v = M 2^e      v shifted left by k (k = 16 - e) until the largest |v_i|
 *                  holds bit 30, each M_i the top half rounded: the largest
 *                  |M_i| in [2^14, 2^15) (M exact where e <= 0)
 *   S = sum M_i^2  below 3 2^30: exact in 32 bits unsigned; |M| = sqrt(S)
 *                  in [2^14, 2^15 sqrt 3)
 *   y = 1/|M|      S/2^30 = m 4^-h, m in [1/4, 1) and h = 0 or 1, and
 *                  1/sqrt(m) by rsqrt_newton_q15 (Q15 within 2.5e-6
 *                  relative, and the roundings of its 16-bit operands)
 *   d_i = M_i / |M| the products M_i y (Q30), halved for h = 1, rounded to
 *                  UNIT16
 *   |M| = S y      r0 = the top half of S times y, within 7 of sqrt(S), and
 *                  one Heron step with y for 1/(2 r0):
 *                  |M| = r0 + (S - r0^2) y / 2^(31+h), in Q4
 *   |v| = |M| 2^e  rounded, or saturated where it leaves the format
 * The rounding of M moves the direction by at most (sqrt 3 / 2) 2^-14 (0.87
 * UNIT16 LSB), to which y's error and the output's rounding add what they
 * add in fc_unit2_16; it moves |M| by at most sqrt(3) / 2, the Heron step's
 * Q4 rounding adds 1/32 and its other errors 1/64
 * (test_scalar.test_direction16 derives both bounds).
 */
#define DIRECTION_TOP_BIT 30      /* the largest |v_i| 2^k in [2^30, 2^31) */
#define DIRECTION_LENGTH_FRAC 4   /* |M| in Q4 */
#define DIRECTION_RESIDUAL_SHIFT 8 /* S - r0^2 (below 2^21) to 16 bits */

/* M_i y (Q30, |.| <= 2^30 (1 + 3e-5): no saturation) rounded to UNIT16, half
 * up, halved first for h = 1: the rounding of floor(M_i y / 2) is
 * floor((M_i y + 2^16) / 2^17) */
static inline __attribute__((always_inline)) fc_real16 direction_component(int16_t m_i, uint16_t y_q15,
                                                                        bool halve)
{
    const int32_t m_y = fc_mul16_unsigned(y_q15, m_i); /* Q15 x Q15 = Q30 */
    if (halve) {
        return (fc_real16)fc_fx_asr32(m_y + ((int32_t)1 << 16), 30 + 1 - FC_UNIT16_FRAC);
    }
    return (fc_real16)fc_fx_asr32(m_y + ((int32_t)1 << 15), 30 - FC_UNIT16_FRAC);
}

/* |x| of an fc_real (symmetric: never INT32_MIN) */
static uint32_t magnitude_u32(fc_real x)
{
    return x < 0 ? (uint32_t)-x : (uint32_t)x;
}

/* The top half of a shifted component rounded to nearest (half up; a
 * positive one rounding up to 2^15 held at 2^15 - 1) */
static inline __attribute__((always_inline)) int16_t direction_mantissa(uint32_t shifted)
{
    const uint32_t half = (uint32_t)1u << 15;
    const uint32_t positive_max = (uint32_t)INT32_MAX;
    if (shifted <= positive_max && shifted > positive_max - half) {
        return INT16_MAX; /* would round to 2^31, past the positive half */
    }
    return (int16_t)(uint16_t)fc_fx_extract(shifted + half, 0u, 16);
}

/* |M| = sqrt(S) in Q4 from y = 2^(30+h) / sqrt(S) (Q15 of 1/sqrt(m)):
 * r0 = floor(S_hi y / 2^(14+h)) is sqrt(S) less S_lo y / 2^(30+h) < 4, less
 * the floor, within y's error (2^16 3e-5 < 2): |r0 - sqrt(S)| < 7, so
 * |S - r0^2| < 2 2^16 7 + 49 < 2^20 and 2^-8 of it fits 16 bits. The Heron
 * step's error is (r0 - sqrt S)^2 / (2 sqrt S) < 2^-9, its residual's floor
 * 2^8 / (2 sqrt S) <= 2^-7, its Q4 rounding 1/32: below half a Q4 LSB
 * before the rounding, so a whole root (an axis-aligned v) is exact. */
static uint32_t direction_length_q4(uint32_t s, uint16_t y_q15, bool halve)
{
    const uint32_t top = fc_umul16((uint16_t)fc_fx_extract(s, 0u, 16), y_q15);
    const uint16_t r0 = (uint16_t)(halve ? fc_fx_extract(top, 0u, 15) : fc_fx_extract(top, 0u, 14));
    const int32_t residual = (int32_t)(s - fc_umul16(r0, r0));
    const int16_t residual16 = (int16_t)fc_fx_asr32(residual, DIRECTION_RESIDUAL_SHIFT);
    /* (S - r0^2) y / 2^(31+h) in Q4, rounded: the product (below 2^29)
     * shifted by 31 + h - 8 - 4 */
    const int32_t step = fc_mul16_unsigned(y_q15, residual16);
    const int32_t step_q4 =
        halve ? fc_fx_asr32(step + ((int32_t)1 << 19), 20) : fc_fx_asr32(step + ((int32_t)1 << 18), 19);
    return ((uint32_t)r0 << DIRECTION_LENGTH_FRAC) + (uint32_t)step_q4;
}

bool fc_direction16(fc_arith *ar, fc_real a, fc_real b, fc_real c, fc_real16 direction[3], fc_real *length)
{
    direction[0] = 0;
    direction[1] = 0;
    direction[2] = 0;
    *length = 0;
    /* the bits of the largest |v_i| are those of the three's OR */
    uint32_t top = magnitude_u32(a) | magnitude_u32(b) | magnitude_u32(c);
    if (top == 0u) {
        return false;
    }
    /* v 2^k with the largest at bit 30: whole bytes first (moves on the
     * ATmega), then bits, the three components in one loop */
    uint32_t va = (uint32_t)a, vb = (uint32_t)b, vc = (uint32_t)c;
    int k = 0;
    while (top < ((uint32_t)1u << (DIRECTION_TOP_BIT - 7))) {
        top <<= 8;
        va <<= 8;
        vb <<= 8;
        vc <<= 8;
        k += 8;
    }
    while (top < ((uint32_t)1u << DIRECTION_TOP_BIT)) {
        top <<= 1;
        va <<= 1;
        vb <<= 1;
        vc <<= 1;
        k++;
    }
    const int16_t m[3] = {direction_mantissa(va), direction_mantissa(vb), direction_mantissa(vc)};
    const uint32_t s = (uint32_t)fc_mul16(m[0], m[0]) + (uint32_t)fc_mul16(m[1], m[1]) +
                       (uint32_t)fc_mul16(m[2], m[2]);
    /* S / 2^30 = m 4^-h with m in [1/4, 1): h = 1 for S >= 2^30; m in Q28 */
    const bool halve = s >= (uint32_t)1u << 30;
    const uint32_t m_q28 = halve ? fc_fx_extract(s, 0u, 4) : fc_fx_extract(s, 0u, 2);
    const uint16_t y_q15 = rsqrt_newton_q15(m_q28);
    direction[0] = direction_component(m[0], y_q15, halve);
    direction[1] = direction_component(m[1], y_q15, halve);
    direction[2] = direction_component(m[2], y_q15, halve);

    /* |v| = |M| 2^e = |M|_Q4 2^(e - 4), e = 16 - k */
    const uint32_t length_q4 = direction_length_q4(s, y_q15, halve);
    const int shift = 16 - DIRECTION_LENGTH_FRAC - k;
    if (shift <= 0) {
        /* rounded to nearest (half up), below 2^16 */
        const uint32_t half = shl_u32(1u, -shift) >> 1;
        *length = (fc_real)shr_u32(length_q4 + half, -shift);
        return true;
    }
    /* |M| < 2^16 (Q4: below 2^20) leaves the format only for k = 0 (shift 12) */
    if (k == 0 && length_q4 >= (uint32_t)1u << (31 - 12)) {
        ar->saturated = 1u;
        *length = FC_REAL_MAX;
        return true;
    }
    /* shift in 1..12; for 5..7 bits a byte left and the rest back right, the
     * shorter loop (length_q4 2^8 < 2^28: nothing lost) */
    *length = (fc_real)(shift > 4 && shift < 8 ? shr_u32(length_q4 << 8, 8 - shift) : shl_u32(length_q4, shift));
    return true;
}

/* sin and cos of r in [-pi/4, pi/4], r and results in Q30 (Taylor to r^9 and r^10,
 * truncation below 2e-11). */
static void sincos_octant_q30(fc_arith *ar, int32_t r, int32_t *sin_out, int32_t *cos_out)
{
    const int32_t r2 = fc_mul(ar, r, r, 30);
    /* sin r = r (1 - r^2/6 (1 - r^2/20 (1 - r^2/42 (1 - r^2/72)))) */
    int32_t s = Q30(1.0f) - fc_mul(ar, r2, Q30(1.0f / 72.0f), 30);
    s = Q30(1.0f) - fc_mul(ar, fc_mul(ar, r2, Q30(1.0f / 42.0f), 30), s, 30);
    s = Q30(1.0f) - fc_mul(ar, fc_mul(ar, r2, Q30(1.0f / 20.0f), 30), s, 30);
    s = Q30(1.0f) - fc_mul(ar, fc_mul(ar, r2, Q30(1.0f / 6.0f), 30), s, 30);
    *sin_out = fc_mul(ar, r, s, 30);
    /* cos r = 1 - r^2/2 (1 - r^2/12 (1 - r^2/30 (1 - r^2/56 (1 - r^2/90)))) */
    int32_t c = Q30(1.0f) - fc_mul(ar, r2, Q30(1.0f / 90.0f), 30);
    c = Q30(1.0f) - fc_mul(ar, fc_mul(ar, r2, Q30(1.0f / 56.0f), 30), c, 30);
    c = Q30(1.0f) - fc_mul(ar, fc_mul(ar, r2, Q30(1.0f / 30.0f), 30), c, 30);
    c = Q30(1.0f) - fc_mul(ar, fc_mul(ar, r2, Q30(1.0f / 12.0f), 30), c, 30);
    *cos_out = Q30(1.0f) - fc_mul(ar, fc_mul(ar, r2, Q30(0.5f), 30), c, 30);
}

/* sin and cos of an ANGLE: reduce to [-pi, pi], then to a quarter turn n and a
 * remainder r in [-pi/4, pi/4]. */
static void sincos_fixed(fc_arith *ar, fc_real angle, fc_real *sin_out, fc_real *cos_out)
{
    const int32_t two_pi = FC_TWO_PI;
    const int32_t half_pi = FC_HALF_PI;
    int32_t a = angle;
    while (a > FC_PI) {
        a -= two_pi;
    }
    while (a < -FC_PI) {
        a += two_pi;
    }
    int quarter = 0;
    while (a > half_pi / 2) {
        a -= half_pi;
        quarter++;
    }
    while (a < -(half_pi / 2)) {
        a += half_pi;
        quarter--;
    }
    int32_t s, c;
    sincos_octant_q30(ar, a * 4 /* ANGLE Q28 -> Q30, |a| <= pi/4 */, &s, &c);
    switch ((unsigned)(quarter + 4) & 3u) { /* quarter in [-2, 2]: a remainder without a division */
    case 0:
        *sin_out = s;
        *cos_out = c;
        break;
    case 1:
        *sin_out = c;
        *cos_out = -s;
        break;
    case 2:
        *sin_out = -s;
        *cos_out = -c;
        break;
    default:
        *sin_out = -c;
        *cos_out = s;
        break;
    }
}

fc_real fc_sin(fc_arith *ar, fc_real angle_rad)
{
    fc_real s, c;
    sincos_fixed(ar, angle_rad, &s, &c);
    return s;
}

fc_real fc_cos(fc_arith *ar, fc_real angle_rad)
{
    fc_real s, c;
    sincos_fixed(ar, angle_rad, &s, &c);
    return c;
}

void fc_sincos(fc_arith *ar, fc_real angle_rad, fc_real *sin_out, fc_real *cos_out)
{
    sincos_fixed(ar, angle_rad, sin_out, cos_out);
}

/* atan t for t in [-tan(pi/8), tan(pi/8)], Q30 in, ANGLE out: Taylor to t^23
 * (truncation below 1e-10 rad). */
static int32_t atan_small_angle(fc_arith *ar, int32_t t_q30)
{
    const int32_t t2 = fc_mul(ar, t_q30, t_q30, 30);
    /* acc <- 1/(2k+1) - t^2 acc for k = 10 .. 0, written out so that each
     * Q30(1)/(2k+1) is a constant (in a loop it was a run-time division) */
#define ATAN_TERM(K) acc = Q30(1.0f) / (2 * (K) + 1) - fc_mul(ar, t2, acc, 30)
    int32_t acc = Q30(1.0f / 23.0f);
    ATAN_TERM(10);
    ATAN_TERM(9);
    ATAN_TERM(8);
    ATAN_TERM(7);
    ATAN_TERM(6);
    ATAN_TERM(5);
    ATAN_TERM(4);
    ATAN_TERM(3);
    ATAN_TERM(2);
    ATAN_TERM(1);
    ATAN_TERM(0);
    return fc_mul(ar, t_q30, acc, 30 + 30 - FC_ANGLE_FRAC);
}

/* floor((num 2^30 + floor(den / 2)) / den) for num <= den, den > 0: the
 * quotient bits by restoring division in 32 bits (the remainder stays below
 * den <= 2^31, so twice it fits a uint32), then the rounding from the
 * remainder: floor((q den + rest + floor(den/2)) / den) = q + (rest >= den - floor(den/2)). */
static uint32_t ratio_q30_rounded(uint32_t num, uint32_t den)
{
    uint32_t quotient = 0u;
    uint32_t rest = num;
    if (rest >= den) { /* num == den */
        return (uint32_t)1u << 30;
    }
    for (int i = 0; i < 30; i++) {
        rest <<= 1;
        quotient <<= 1;
        if (rest >= den) {
            rest -= den;
            quotient |= 1u;
        }
    }
    return quotient + (rest >= den - den / 2u ? 1u : 0u);
}

fc_real fc_atan2(fc_arith *ar, fc_real y, fc_real x)
{
    /* magnitudes as uint32: |INT32_MIN| = 2^31 fits */
    const uint32_t ay = y < 0 ? 0u - (uint32_t)y : (uint32_t)y;
    const uint32_t ax = x < 0 ? 0u - (uint32_t)x : (uint32_t)x;
    const bool steep = ay > ax;
    /* ratio in [0, 1] as Q30: round(num 2^30 / den) */
    const uint32_t num = steep ? ax : ay;
    const uint32_t den = steep ? ay : ax;
    if (den == 0u) {
        return 0; /* x == y == 0 (den is the larger magnitude) */
    }
    const int32_t ratio = (int32_t)ratio_q30_rounded(num, den);
    /* atan(a) = pi/4 + atan((a - 1)/(a + 1)) brings a > tan(pi/8) into range */
    const int32_t tan_pi_8 = Q30(0.41421356f);
    int32_t angle;
    if (ratio > tan_pi_8) {
        /* both halved: ratio + 1 reaches 2^31 at 45 degrees */
        const int32_t t = fc_div(ar, (ratio - Q30(1.0f)) / 2, ratio / 2 + Q30(0.5f), 30);
        angle = FC_QUARTER_PI + atan_small_angle(ar, t);
    } else {
        angle = atan_small_angle(ar, ratio);
    }
    if (steep) {
        angle = FC_HALF_PI - angle;
    }
    if (x < 0) {
        angle = FC_PI - angle;
    }
    return y < 0 ? -angle : angle;
}

fc_real fc_asin(fc_arith *ar, fc_real x_unit)
{
    const fc_real x = fc_clamp(x_unit, -Q30(1.0f), Q30(1.0f));
    const fc_real one_minus_x2 = Q30(1.0f) - fc_mul(ar, x, x, 30);
    return fc_atan2(ar, x, fc_sqrt(ar, one_minus_x2, FC_UNIT_FRAC));
}

fc_real fc_exp_neg(fc_arith *ar, fc_real x_ratio)
{
    if (x_ratio <= 0) {
        return Q30(1.0f);
    }
    /* x = n ln2 + r, r in [0, ln2): e^-x = 2^-n e^-r */
    const int32_t ln2 = FC_C(0.69314718f, RATIO);
    const int32_t n = x_ratio / ln2;
    if (n >= 31) {
        return 0;
    }
    const int32_t r_q30 = (x_ratio - n * ln2) * (1 << (30 - FC_RATIO_FRAC));
    /* e^-r = 1 - r (1 - r/2 (1 - r/3 ( ... (1 - r/12)))) : truncation below 1e-10 */
    int32_t acc = Q30(1.0f);
    for (int k = 12; k >= 1; k--) {
        acc = Q30(1.0f) - fc_mul(ar, r_q30 / k, acc, 30);
    }
    return acc >> n;
}

/* ln x for x in (0, 1] (Q30) as RATIO: x = m 2^-k with m in [1, 2), then
 * ln m = 2 atanh(t), t = (m - 1)/(m + 1) in [0, 1/3), series to t^21. */
static int32_t log_unit_ratio(fc_arith *ar, int32_t x_q30)
{
    int k = 0;
    int32_t m = x_q30;
    while (m < (int32_t)0x40000000) { /* until m is in [2^30, 2^31) */
        m <<= 1;
        k++;
    }
    /* m in [2^30, 2^31) as a Q30 value in [1, 2); hold it as Q29 to add 1 safely */
    const int32_t m_q29 = m >> 1;
    const int32_t t_q30 = fc_div(ar, m_q29 - ((int32_t)1 << 29), m_q29 + ((int32_t)1 << 29), 30);
    const int32_t t2 = fc_mul(ar, t_q30, t_q30, 30);
    int32_t acc = Q30(1.0f / 21.0f);
    for (int j = 9; j >= 0; j--) {
        acc = Q30(1.0f) / (2 * j + 1) + fc_mul(ar, t2, acc, 30); /* 1/(2j+1) + t^2 acc */
    }
    /* ln m = 2 t acc, Q30 x Q30 -> RATIO with the factor 2 written out */
    const int32_t half_ln_m = fc_mul(ar, t_q30, acc, 30 + 30 - FC_RATIO_FRAC);
    const int32_t ln2 = FC_C(0.69314718f, RATIO);
    return half_ln_m + half_ln_m - k * ln2;
}

fc_real fc_pow_unit(fc_arith *ar, fc_real x_unit, fc_real exponent_ratio)
{
    if (x_unit <= 0) {
        return 0;
    }
    if (x_unit >= Q30(1.0f)) {
        return Q30(1.0f);
    }
    const int32_t ln_x = log_unit_ratio(ar, x_unit); /* <= 0 */
    fc_arith probe = {0u};
    const int32_t minus_e_ln_x = -fc_mul(&probe, exponent_ratio, ln_x, FC_RATIO_FRAC);
    if (probe.saturated != 0u) {
        return 0; /* e ln x below -128: x^e < 1e-55, zero in any format */
    }
    return fc_exp_neg(ar, minus_e_ln_x);
}

/* ======================================================================= */
/* Gains fixed at init (fc/scalar.h, fc_gain)                              */
/* ======================================================================= */

/* The 15 significant bits of value 2^-frac (value any 64-bit integer): drop =
 * the bits below them, the mantissa value / 2^drop rounded to nearest (half
 * up, as every product; exact for drop <= 0), one more dropped where the
 * rounding reaches 2^15. */
static fc_gain gain_of_wide(int64_t value, int frac)
{
    fc_gain g = {0, 0};
    if (value == 0) {
        return g;
    }
    uint64_t size = value < 0 ? 0u - (uint64_t)value : (uint64_t)value;
    int drop = -15;
    while (size != 0u) {
        size >>= 1;
        drop++;
    }
    int64_t mantissa = drop <= 0 ? value * ((int64_t)1 << -drop) : (value + ((int64_t)1 << (drop - 1))) >> drop;
    if (drop > 0 && (mantissa > INT16_MAX || mantissa < -INT16_MAX)) { /* only a rounding reaches 2^15 */
        drop++;
        mantissa = (value + ((int64_t)1 << (drop - 1))) >> drop; /* drop >= 1 here */
    }
    g.mantissa = (int16_t)mantissa;
    g.frac = (int8_t)(frac - drop);
    return g;
}

fc_gain fc_gain_of(fc_real value, int frac)
{
    return gain_of_wide(value, frac);
}

fc_gain fc_gain_of_product(fc_real a, int frac_a, fc_real b, int frac_b)
{
    return gain_of_wide((int64_t)a * b, frac_a + frac_b);
}

fc_real fc_gain_to_real(fc_arith *ar, fc_gain g, int frac)
{
    return fc_fx_narrow(ar, (int64_t)g.mantissa, g.frac - frac);
}

#if defined(__AVR__)
/* ======================================================================= */
/* The ATmega's port (fc/scalar_avr.h): its out-of-line bodies            */
/* ======================================================================= */

/*
 * fc_fx_narrow_wide for a shift known only at run time (0 < shift < 32), the
 * out-of-line products' case. fc_fx_narrow_wide with a run-time shift builds
 * 2^(shift - 1) and its bound by 32-bit shift loops (up to 31 rounds each, a
 * few hundred cycles on the ATmega); here the value is shifted once:
 *   w = floor(v / 2^(shift-1))         (whole bytes by moves, 0..7 bits by ASR)
 *   floor((v + 2^(shift-1)) / 2^shift) = floor((w + 1) / 2)
 * (v = q 2^(s-1) + r, 0 <= r < 2^(s-1): both sides are floor((q + 1) / 2)), the
 * same value as fc_fx_narrow_wide, saturated the same way: the result is
 * inside +-INT32_MAX iff -2^32 < w < 2^32 - 1, i.e. high is 0 with low below
 * 2^32 - 1, or high is all ones with low above 0.
 */
FC_FX_INLINE fc_real narrow_wide_runtime(fc_arith *ar, fc_fx_wide value, int shift)
{
    uint32_t low = value.low;
    uint32_t high = value.high;
    /* unsigned: a signed / 8 and % 8 are libgcc divisions at -Os */
    const uint8_t s = (uint8_t)(shift - 1);
    const uint8_t bytes = (uint8_t)(s >> 3);
    if (bytes == 1) {
        low = (low >> 8) | (high << 24);
        high = (uint32_t)((int32_t)high >> 8);
    } else if (bytes == 2) {
        low = (low >> 16) | (high << 16);
        high = (uint32_t)((int32_t)high >> 16);
    } else if (bytes == 3) {
        low = (low >> 24) | (high << 8);
        high = (uint32_t)((int32_t)high >> 24);
    } else {
        /* s < 8: the bits alone */
    }
    FC_AVR_ASR64(low, high, s & 7u);
    if (high == 0u && low != UINT32_MAX) {
        return (fc_real)((low >> 1) + (low & 1u)); /* (w + 1) / 2 */
    }
    if (high == UINT32_MAX && low != 0u) {
        if (low == UINT32_MAX) {
            return 0; /* w = -1 */
        }
        /* w + 1 = low + 1 - 2^32 in [-2^32 + 2, -1]: halved, the top bit is the sign */
        return (fc_real)(((low + 1u) >> 1) | 0x80000000u);
    }
    ar->saturated = 1u;
    return (int32_t)high < 0 ? FC_REAL_MIN : FC_REAL_MAX;
}
#define OUTLINE_RUNTIME_SHIFT(shift) ((shift) > 0 && (shift) < 32)
/* the shifts of 32 and more (fc_fx_narrow_wide_far's): narrowed on the
 * halves, the floor by a counted ASR loop */
#define OUTLINE_FAR_SHIFT(shift, extra) ((shift) >= 32 && (shift) <= FC_FX_FAR_SHIFT_MAX + (extra))
FC_FX_INLINE fc_real narrow_quarters_runtime(fc_arith *ar, fc_fx_wide quarters, int shift)
{
    if (shift - 2 < 32) {
        return narrow_wide_runtime(ar, quarters, shift - 2);
    }
    return fc_fx_narrow_wide_far(ar, quarters, shift - 2);
}

/* The portable definition of the out-of-line products, for the shifts the
 * forms below do not take: one copy
 * for the four (fc_fx_narrow_sum of a single product, or of two or three,
 * is fc_fx_narrow's and fc_dot2/3's value: the missing terms are 0). */
static __attribute__((noinline)) fc_real narrow_products(fc_arith *ar, fc_real a0, fc_real b0, fc_real a1,
                                                         fc_real b1, fc_real a2, fc_real b2, fc_real a3, fc_real b3,
                                                         int shift)
{
    return fc_fx_narrow_sum(ar, (int64_t)a0 * b0, (int64_t)a1 * b1, (int64_t)a2 * b2, (int64_t)a3 * b3, shift);
}

/* The out-of-line products (the port's fc_mul, fc_dotN). For the shifts 1..31, the 64-bit sum is formed as the inlined
 * primitives form it and narrowed by narrow_wide_runtime (bit-identical:
 * atmega.scalar_equivalence), and so are the shifts of 32 and more up to
 * FC_FX_FAR_SHIFT_MAX (+ 2 for the sums); other shifts, and every shift
 * by the int64_t definition (narrow_products). */
fc_real fc_fx_mul_outline(fc_arith *ar, fc_real a, fc_real b, int shift)
{
    if (OUTLINE_RUNTIME_SHIFT(shift) || OUTLINE_FAR_SHIFT(shift, 0)) {
        const fc_fx_wide product = fc_fx_mul_wide(a, b);
        /* the library's most frequent shifts (UNIT x UNIT -> UNIT, the far
         * 32, and 22, 24) narrowed with the shift a constant, as inline: no
         * shift loops (the same functions, so the same values) */
        switch (shift) {
        case FC_UNIT_FRAC:
            return fc_fx_narrow_wide(ar, product, FC_UNIT_FRAC);
        case 32:
            return fc_fx_narrow_wide_far(ar, product, 32);
        case 22:
            return fc_fx_narrow_wide(ar, product, 22);
        case 24:
            return fc_fx_narrow_wide(ar, product, 24);
        default:
            return shift < 32 ? narrow_wide_runtime(ar, product, shift) : fc_fx_narrow_wide_far(ar, product, shift);
        }
    }
    return narrow_products(ar, a, b, 0, 0, 0, 0, 0, 0, shift);
}

fc_real fc_fx_dot2_outline(fc_arith *ar, fc_real a0, fc_real b0, fc_real a1, fc_real b1, int shift)
{
    if (OUTLINE_RUNTIME_SHIFT(shift)) {
        const fc_fx_wide sum = fc_fx_add_wide(fc_fx_mul_wide(a0, b0), fc_fx_mul_wide(a1, b1));
        /* as fc_fx_mul_outline: the quaternion products' 30 */
        return shift == FC_UNIT_FRAC ? fc_fx_narrow_wide(ar, sum, FC_UNIT_FRAC) : narrow_wide_runtime(ar, sum, shift);
    }
    if (OUTLINE_FAR_SHIFT(shift, 2)) {
        const fc_fx_wide quarters = fc_fx_quarters2(a0, b0, a1, b1);
        /* and 36; 32 is the allocation's ratio comparison (its saturated
         * steps) */
        switch (shift) {
        case 36:
            return fc_fx_narrow_quarters(ar, quarters, 36);
        case 32:
            return fc_fx_narrow_quarters(ar, quarters, 32);
        default:
            return narrow_quarters_runtime(ar, quarters, shift);
        }
    }
    return narrow_products(ar, a0, b0, a1, b1, 0, 0, 0, 0, shift);
}

/* fc_dot3 is fc_dot4 with a zero fourth term: the same sums (a product of
 * 0 adds nothing, clamped or wrapped), one copy of the code */
fc_real fc_fx_dot3_outline(fc_arith *ar, fc_real a0, fc_real b0, fc_real a1, fc_real b1, fc_real a2, fc_real b2,
                           int shift)
{
    return fc_fx_dot4_outline(ar, a0, b0, a1, b1, a2, b2, 0, 0, shift);
}

/* the four products formed by one loop (one copy of the multiply), then
 * summed in the order of the inlined forms: clamped, (p0 + p1) + (p2 + p3),
 * for the shifts below 32; each floored by 4 and wrapped for the far ones */
fc_real fc_fx_dot4_outline(fc_arith *ar, fc_real a0, fc_real b0, fc_real a1, fc_real b1, fc_real a2, fc_real b2,
                           fc_real a3, fc_real b3, int shift)
{
    if (OUTLINE_RUNTIME_SHIFT(shift) || OUTLINE_FAR_SHIFT(shift, 2)) {
        const fc_real a[4] = {a0, a1, a2, a3};
        const fc_real b[4] = {b0, b1, b2, b3};
        fc_fx_wide p[4];
        for (uint8_t i = 0u; i < 4u; i++) {
            p[i] = fc_fx_mul_wide(a[i], b[i]);
        }
        if (OUTLINE_RUNTIME_SHIFT(shift)) {
            const fc_fx_wide sum = fc_fx_add_wide(fc_fx_add_wide(p[0], p[1]), fc_fx_add_wide(p[2], p[3]));
            return narrow_wide_runtime(ar, sum, shift);
        }
        for (uint8_t i = 0u; i < 4u; i++) {
            p[i] = fc_fx_asr_wide(p[i], 2);
        }
        const fc_fx_wide quarters = fc_fx_add_wide_wrap(fc_fx_add_wide_wrap(p[0], p[1]), fc_fx_add_wide_wrap(p[2], p[3]));
        return narrow_quarters_runtime(ar, quarters, shift);
    }
    return narrow_products(ar, a0, b0, a1, b1, a2, b2, a3, b3, shift);
}

/* fc_acc_mac: acc + floor(a b / 2^FC_ACC_GUARD_BITS) modulo 2^64, on the halves */
fc_acc fc_acc_mac(fc_acc acc, fc_real a, fc_real b)
{
    const fc_fx_wide term = fc_fx_asr_wide(fc_fx_mul_wide(a, b), FC_ACC_GUARD_BITS);
    return fc_fx_join(fc_fx_add_wide_wrap(fc_fx_split(acc), term));
}

/* The ATmega's fc_div (fc/scalar_avr.h), a function of its own section */
__asm__(".pushsection .text.fc_div,\"ax\",@progbits\n"
        ".global fc_div\n"
        ".type fc_div, @function\n"
        "fc_div:\n\t" FC_AVR_DIV_BODY "\n"
        ".size fc_div, .-fc_div\n"
        ".popsection");

/* The ATmega's product (fc/scalar_avr.h): the assembly, a function of its
 * own section (--gc-sections), and the shifts outside 1..46 by the portable
 * definition (its tail call) */
__asm__(".pushsection .text.fc_fx_mul_gain_avr,\"ax\",@progbits\n"
        ".global fc_fx_mul_gain_avr\n"
        ".type fc_fx_mul_gain_avr, @function\n"
        "fc_fx_mul_gain_avr:\n\t" FC_AVR_MUL_GAIN_BODY "\n"
        ".size fc_fx_mul_gain_avr, .-fc_fx_mul_gain_avr\n"
        ".popsection");

/* fc_add and fc_sub out of line (fc/scalar_avr.h, FC_AVR_ADD_CALL): a in
 * r22-r25 (the result), b in r18-r21, Z = &ar->saturated. As
 * FC_AVR_ADD_SATURATED, with r22 the LDI/CPI register and r0 the 1 stored. */
#define FC_AVR_ADD_CALLED(NAME, OP, CARRY)                                                      \
    ".pushsection .text." NAME ",\"ax\",@progbits\n"                                           \
    ".global " NAME "\n"                                                                       \
    ".type " NAME ", @function\n" NAME ":\n\t"                                                 \
    OP " r22, r18\n\t" CARRY " r23, r19\n\t" CARRY " r24, r20\n\t" CARRY " r25, r21\n\t"         \
    "brvs 1f\n\t"                                                                              \
    "cpi r22, 1\n\tcpc r23, __zero_reg__\n\tcpc r24, __zero_reg__\n\tcpc r25, __zero_reg__\n\t" \
    "brvs 2f\n\t"                                                                              \
    "ret\n"                                                                                    \
    "1:\n\tlsl r25\n\tsbc r22, r22\n\tmov r23, r22\n\tmovw r24, r22\n\t"                        \
    "subi r25, 0x80\n\tsbrc r25, 7\n"                                                          \
    "2:\n\tinc r22\n\t"                                                                        \
    "clr r0\n\tinc r0\n\tst Z, r0\n\t"                                                          \
    "ret\n"                                                                                    \
    ".size " NAME ", .-" NAME "\n"                                                              \
    ".popsection"

__asm__(FC_AVR_ADD_CALLED("fc_fx_add_avr", "add", "adc"));
__asm__(FC_AVR_ADD_CALLED("fc_fx_sub_avr", "sub", "sbc"));

/* fc_fx_mul_gain_reference for the shifts the assembly leaves, in 32-bit
 * halves (the int64_t form would be libgcc calls here): from 47
 * on 0; from 0 down x m 2^n, n = -shift, exact where |x m| <= INT32_MAX >> n,
 * otherwise saturated (for n >= 31 every product but 0) */
fc_real fc_fx_mul_gain_avr_far(fc_real x, int16_t mantissa, uint8_t shift, fc_arith *ar)
{
    const int left = -(int)(int8_t)shift;
    const fc_fx_wide p = fc_fx_mul_wide(x, mantissa);
    if (left < 0 || (p.low == 0u && p.high == 0u)) {
        return 0;
    }
    const uint32_t limit = left >= 31 ? 0u : (uint32_t)INT32_MAX >> (uint8_t)left;
    const bool fits = p.high == 0u ? p.low <= limit : (p.high == UINT32_MAX && p.low >= 0u - limit && limit != 0u);
    if (!fits) {
        ar->saturated = 1u;
        return (int32_t)p.high < 0 ? FC_REAL_MIN : FC_REAL_MAX;
    }
    return (fc_real)(p.low << (uint8_t)left);
}
#endif
/* ======================================================================= */

#else /* float backend */

/* ----------------------------------------------------------------------- */
/* float backend                                                           */
/* ----------------------------------------------------------------------- */
/* libm's single-precision functions (math.h, included at the top); avr-libc
 * maps them onto its double functions (double is 32 bits there), hence the
 * casts back to fc_real */

#if !FC_FLOAT_INLINE_MATH /* the others inline them (fc/scalar.h) */
fc_real fc_div(fc_arith *ar, fc_real num, fc_real den, int shift)
{
    (void)shift;
    if (den == 0.0f) {
        ar->saturated = 1u;
        return num > 0.0f ? FC_REAL_MAX : (num < 0.0f ? FC_REAL_MIN : 0.0f);
    }
    return num / den;
}

fc_real fc_sqrt(fc_arith *ar, fc_real x, int frac)
{
    (void)ar;
    (void)frac;
    return x > 0.0f ? (fc_real)sqrtf(x) : 0.0f;
}

fc_real fc_hypot3(fc_arith *ar, fc_real a, fc_real b, fc_real c)
{
    (void)ar;
    return (fc_real)sqrtf(a * a + b * b + c * c);
}

fc_real fc_rsqrt(fc_arith *ar, fc_real x, int frac_in, int frac_out)
{
    (void)frac_in;
    (void)frac_out;
    if (!(x > 0.0f)) {
        ar->saturated = 1u;
        return FC_REAL_MAX;
    }
    return 1.0f / (fc_real)sqrtf(x);
}

#endif

fc_real fc_sin(fc_arith *ar, fc_real angle_rad)
{
    (void)ar;
    return (fc_real)sinf(angle_rad);
}

fc_real fc_cos(fc_arith *ar, fc_real angle_rad)
{
    (void)ar;
    return (fc_real)cosf(angle_rad);
}

void fc_sincos(fc_arith *ar, fc_real angle_rad, fc_real *sin_out, fc_real *cos_out)
{
    (void)ar;
    /* two calls: avr-libc has no sincos, and newlib's sincosf (Cortex-M4F)
     * is slower than its sinf and cosf (tools/bench.sh); on the host gcc
     * pairs them into glibc's sincosf itself */
    *sin_out = (fc_real)sinf(angle_rad);
    *cos_out = (fc_real)cosf(angle_rad);
}

fc_real fc_atan2(fc_arith *ar, fc_real y, fc_real x)
{
    (void)ar;
    return (fc_real)atan2f(y, x);
}

fc_real fc_asin(fc_arith *ar, fc_real x_unit)
{
    (void)ar;
    return (fc_real)asinf(fc_clamp(x_unit, -1.0f, 1.0f));
}

fc_real fc_exp_neg(fc_arith *ar, fc_real x_ratio)
{
    (void)ar;
    return x_ratio <= 0.0f ? 1.0f : (fc_real)expf(-x_ratio);
}

fc_real fc_pow_unit(fc_arith *ar, fc_real x_unit, fc_real exponent_ratio)
{
    (void)ar;
    if (!(x_unit > 0.0f)) {
        return 0.0f;
    }
    if (x_unit >= 1.0f) {
        return 1.0f;
    }
    return (fc_real)powf(x_unit, exponent_ratio);
}

#endif
