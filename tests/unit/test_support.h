/*
 * test_support.h - shared helpers of the unit tests (header only).
 *
 * The same test source runs against both numeric backends. Inputs are made
 * with fc_from_float and read back with fc_to_float, and the double reference
 * is computed from that read-back value (the quantised input), so the input
 * rounding is never blamed on the function under test.
 *
 * Outputs are read with ts_val(), which is exact in both backends: in fixed,
 * fc_to_float would round a 31-bit result to a 24-bit float mantissa (up to
 * 64 LSB of UNIT for values near 1), too coarse for tolerances stated in LSBs.
 *
 * Tolerances are given per backend with ts_tol(frac, lsb, ulps, scale):
 *   fixed: lsb LSBs of the output's Q-format (lsb * 2^-frac);
 *   float: ulps float ulps relative to scale (ulps * FLT_EPSILON * |scale|),
 *          scale being the magnitude the rounding errors are relative to
 *          (usually the reference value, or the operands' magnitude when the
 *          result comes out of a cancellation).
 */
#ifndef FC_TEST_SUPPORT_H
#define FC_TEST_SUPPORT_H

#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <math.h>
#include <float.h>
#include <cmocka.h>

#include "fc/scalar.h"

#define TS_PI 3.14159265358979323846

/* ---- conversions -------------------------------------------------------- */

/* A float input quantised into format frac; *ref receives the value the
 * backend really holds, read back with fc_to_float (exact: a value made by
 * fc_from_float has at most 24 significant bits). */
static inline fc_real ts_in(float x, int frac, double *ref)
{
    const fc_real q = fc_from_float(x, frac);
    *ref = (double)fc_to_float(q, frac);
    return q;
}

/* Exact value of a backend number in format frac, as a double. */
static inline double ts_val(fc_real x, int frac)
{
#if FC_NUMERIC_FIXED
    return ldexp((double)x, -frac);
#else
    (void)frac;
    return (double)x;
#endif
}

/* Exact value of a 16-bit backend number (fc_real16) in format frac. */
static inline double ts_val16(fc_real16 x, int frac)
{
    return ts_val((fc_real)x, frac); /* int16_t -> int32_t or float -> float: exact */
}

/* ---- tolerances --------------------------------------------------------- */

static inline double ts_tol(int frac, double lsb, double ulps, double scale)
{
#if FC_NUMERIC_FIXED
    (void)ulps;
    (void)scale;
    return lsb * ldexp(1.0, -frac);
#else
    (void)frac;
    (void)lsb;
    /* the floor keeps a relative tolerance meaningful at a zero reference */
    return ulps * (double)FLT_EPSILON * fmax(fabs(scale), (double)FLT_MIN);
#endif
}

/* fixed only: a tolerance relative to |ref| of 2^-bits, for results computed
 * through an internal format of limited relative precision; 0 in float. */
static inline double ts_fixed_rel(double ref, int bits)
{
#if FC_NUMERIC_FIXED
    return ldexp(fabs(ref), -bits);
#else
    (void)ref;
    (void)bits;
    return 0.0;
#endif
}

/* One LSB of format frac in fixed; one float ulp at 1.0 in float. */
static inline double ts_resolution(int frac)
{
#if FC_NUMERIC_FIXED
    return ldexp(1.0, -frac);
#else
    (void)frac;
    return (double)FLT_EPSILON;
#endif
}

/* ---- a checker that sweeps many points and reports the worst ----------- */

typedef struct ts_check {
    const char *what;
    int count;
    int failures;
    double worst_ratio;    /* largest |actual - expected| / tol seen */
    double worst_err;
    double worst_tol;
} ts_check;

static inline ts_check ts_check_begin(const char *what)
{
    const ts_check c = {what, 0, 0, 0.0, 0.0, 0.0};
    return c;
}

/* Records one comparison; prints the first few failures with their label. */
__attribute__((format(printf, 5, 6))) static inline bool
ts_close(ts_check *c, double actual, double expected, double tol, const char *fmt, ...)
{
    const double err = fabs(actual - expected);
    const double ratio = tol > 0.0 ? err / tol : (err > 0.0 ? HUGE_VAL : 0.0);
    c->count++;
    if (!(ratio <= c->worst_ratio)) {
        c->worst_ratio = ratio;
        c->worst_err = err;
        c->worst_tol = tol;
    }
    if (ratio <= 1.0) {
        return true;
    }
    if (c->failures < 8) {
        char label[160];
        va_list args;
        va_start(args, fmt);
        vsnprintf(label, sizeof label, fmt, args);
        va_end(args);
        print_error("  %s [%s]: got %.12g, expected %.12g, error %.4g > tolerance %.4g\n", c->what,
                    label, actual, expected, err, tol);
    }
    c->failures++;
    return false;
}

/* Fails the test if any comparison of the sweep failed. Set TS_VERBOSE=1 in
 * the environment to see the worst error of every sweep. */
static inline void ts_check_end(const ts_check *c)
{
    if (getenv("TS_VERBOSE") != NULL) {
        print_message("  %-44s %5d points, worst %.3g (%.3g of tolerance %.3g)\n", c->what, c->count,
                      c->worst_err, c->worst_ratio, c->worst_tol);
    }
    if (c->failures != 0) {
        fail_msg("%s: %d of %d values outside tolerance (worst error %.4g = %.3g x tolerance %.4g)",
                 c->what, c->failures, c->count, c->worst_err, c->worst_ratio, c->worst_tol);
    }
    assert_true(c->count > 0);
}

/* A single comparison that fails at once. */
#define TS_ASSERT_CLOSE(actual, expected, tol)                                                 \
    do {                                                                                       \
        ts_check ts_single_ = ts_check_begin(#actual);                                         \
        (void)ts_close(&ts_single_, (actual), (expected), (tol), "%s:%d", __FILE__, __LINE__); \
        ts_check_end(&ts_single_);                                                             \
    } while (0)

/* Exact equality of two backend numbers, printed as raw values. */
#if FC_NUMERIC_FIXED
#define TS_ASSERT_REAL_EQ(actual, expected)                                                \
    do {                                                                                   \
        const fc_real ts_a_ = (actual), ts_e_ = (expected);                                \
        if (ts_a_ != ts_e_) {                                                              \
            fail_msg("%s = %ld, expected %ld (raw)", #actual, (long)ts_a_, (long)ts_e_);   \
        }                                                                                  \
    } while (0)
#else
#define TS_ASSERT_REAL_EQ(actual, expected)                                                \
    do {                                                                                   \
        const fc_real ts_a_ = (actual), ts_e_ = (expected);                                \
        if (!(ts_a_ == ts_e_)) {                                                           \
            fail_msg("%s = %.9g, expected %.9g", #actual, (double)ts_a_, (double)ts_e_);   \
        }                                                                                  \
    } while (0)
#endif

/* ---- reproducible random inputs ---------------------------------------- */

typedef struct ts_rng {
    uint32_t state;
} ts_rng;

static inline ts_rng ts_rng_seed(uint32_t seed)
{
    const ts_rng r = {seed};
    return r;
}

/* Numerical Recipes LCG; the top 24 bits are used. */
static inline uint32_t ts_rand_u32(ts_rng *r)
{
    r->state = r->state * 1664525u + 1013904223u;
    return r->state;
}

/* Uniform in [lo, hi). */
static inline float ts_uniform(ts_rng *r, float lo, float hi)
{
    const float u = (float)(ts_rand_u32(r) >> 8) * (1.0f / 16777216.0f);
    return lo + (hi - lo) * u;
}

/* Uniform raw int32 in [lo, hi] (fixed-backend bit-level tests). */
static inline int32_t ts_rand_range(ts_rng *r, int32_t lo, int32_t hi)
{
    const uint64_t span = (uint64_t)((int64_t)hi - (int64_t)lo) + 1u;
    const uint64_t draw = ((uint64_t)ts_rand_u32(r) << 32) | ts_rand_u32(r);
    return (int32_t)((int64_t)lo + (int64_t)(draw % span));
}

#endif /* FC_TEST_SUPPORT_H */
