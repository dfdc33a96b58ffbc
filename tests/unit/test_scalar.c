/*
 * test_scalar.c - the numeric backend (fc/scalar.h, src/scalar.c).
 *
 * One source for both backends. Tolerances (see test_support.h):
 *   fixed: LSBs of the output's Q-format:
 *          fc_mul, fc_div, fc_convert, fc_sqrt, fc_hypot3: 0.5 LSB (rounded to nearest)
 *          fc_dot2/3/4, fc_acc_*: 1 LSB (one rounding; dropped guard bits are far below it)
 *          fc_rsqrt: 1 LSB of frac_out + 2^-28 relative (its Newton iterate
 *          1/sqrt(m) in (1, 2] is held in Q29: 2 LSB of it)
 *          fc_sin/fc_cos: 5 LSB of UNIT ("a few UNIT LSB", scalar.h)
 *          fc_atan2: 4 LSB of ANGLE; fc_asin: 4 LSB of ANGLE + 4 UNIT LSB of its
 *          argument times the condition 1/sqrt(1 - x^2)
 *          fc_exp_neg: 2 LSB of UNIT
 *          fc_pow_unit: 4 LSB of UNIT + x^e (1 + e) 2 LSB of RATIO (it is
 *          exp(e ln x) with ln x and e ln x held in RATIO: their rounding is
 *          a relative error of the result)
 *   float: ulps relative to the reference: 0.5 for one correctly rounded
 *          operation, 2 for the libm functions, 2n for an n-term sum
 *          (relative to the sum of the magnitudes of the terms).
 */
#include "test_support.h"

/* exact value of a double, rounded to nearest, in format frac (fixed reference) */
static double round_to_format(double x, int frac)
{
#if FC_NUMERIC_FIXED
    return ldexp(nearbyint(ldexp(x, frac)), -frac);
#else
    (void)frac;
    return (double)(float)x;
#endif
}

/* ---- macros and constants ---------------------------------------------- */

static void test_shift_macros(void **state)
{
    (void)state;
    assert_int_equal(FC_FRAC(UNIT), 30);
    assert_int_equal(FC_FRAC(LENGTH), 20);
    /* rate (24) * dt (30) -> angle (28): shift 26 */
    assert_int_equal(FC_SHIFT(RATE, DT, ANGLE), 26);
    assert_int_equal(FC_SHIFT(UNIT, UNIT, UNIT), 30);
    assert_int_equal(FC_SHIFT(MASS, ACCEL, FORCE), 24 + 22 - 20);
    /* unit (30) / angle (28) -> unit (30): the dividend goes up by 28 */
    assert_int_equal(FC_DIV_SHIFT(UNIT, ANGLE, UNIT), 28);
    assert_int_equal(FC_DIV_SHIFT(FORCE, MASS, ACCEL), 22 + 24 - 20);
}

static void test_int_and_c_constants(void **state)
{
    (void)state;
    /* FC_INT is exact */
    TS_ASSERT_CLOSE(ts_val(FC_INT(1, UNIT), FC_UNIT_FRAC), 1.0, 0.0);
    TS_ASSERT_CLOSE(ts_val(FC_INT(-1, UNIT), FC_UNIT_FRAC), -1.0, 0.0);
    TS_ASSERT_CLOSE(ts_val(FC_INT(0, ANGLE), FC_ANGLE_FRAC), 0.0, 0.0);
    TS_ASSERT_CLOSE(ts_val(FC_INT(3, LENGTH), FC_LENGTH_FRAC), 3.0, 0.0);
    TS_ASSERT_CLOSE(ts_val(FC_INT(-2047, LENGTH), FC_LENGTH_FRAC), -2047.0, 0.0);
    TS_ASSERT_CLOSE(ts_val(FC_INT(32767, GAIN), FC_GAIN_FRAC), 32767.0, 0.0);
    /* FC_C of a float constant: its value rounded to nearest in the format */
    TS_ASSERT_CLOSE(ts_val(FC_C(0.5f, UNIT), FC_UNIT_FRAC), 0.5, 0.0);
    TS_ASSERT_CLOSE(ts_val(FC_C(-0.25f, ANGLE), FC_ANGLE_FRAC), -0.25, 0.0);
    TS_ASSERT_CLOSE(ts_val(FC_C(1.5f, RATIO), FC_RATIO_FRAC), 1.5, 0.0);
    TS_ASSERT_CLOSE(ts_val(FC_C(0.1f, RATIO), FC_RATIO_FRAC), round_to_format((double)0.1f, FC_RATIO_FRAC),
                    0.0);
    TS_ASSERT_CLOSE(ts_val(FC_C(-0.1f, RATIO), FC_RATIO_FRAC),
                    round_to_format(-(double)0.1f, FC_RATIO_FRAC), 0.0);
    TS_ASSERT_CLOSE(ts_val(FC_C(1.0e-5f, UNIT), FC_UNIT_FRAC), round_to_format((double)1.0e-5f, FC_UNIT_FRAC),
                    0.0);
    TS_ASSERT_CLOSE(ts_val(FC_C(9.81f, ACCEL), FC_ACCEL_FRAC), round_to_format((double)9.81f, FC_ACCEL_FRAC),
                    0.0);
#if FC_NUMERIC_FIXED
    TS_ASSERT_REAL_EQ(FC_INT(1, UNIT), (fc_real)1 << 30);
    TS_ASSERT_REAL_EQ(FC_C(0.5f, UNIT), (fc_real)1 << 29);
    TS_ASSERT_REAL_EQ(FC_C(0.1f, RATIO), 1677722);  /* 0.1f * 2^24 = 1677721.625 */
    TS_ASSERT_REAL_EQ(FC_C(-0.1f, RATIO), -1677722);
    /* the range is symmetric, so negation never overflows */
    TS_ASSERT_REAL_EQ(FC_REAL_MAX, INT32_MAX);
    TS_ASSERT_REAL_EQ(FC_REAL_MIN, -INT32_MAX);
#else
    TS_ASSERT_REAL_EQ(FC_C(0.1f, RATIO), 0.1f);
    TS_ASSERT_REAL_EQ(FC_INT(7, LENGTH), 7.0f);
    TS_ASSERT_REAL_EQ(FC_REAL_MAX, FLT_MAX);
    TS_ASSERT_REAL_EQ(FC_REAL_MIN, -FLT_MAX);
#endif
}

/* FC_PI and FC_HALF_PI are pi and pi/2 rounded to the nearest ANGLE value
 * (fixed) or the nearest float (float). */
static void test_pi_constants(void **state)
{
    (void)state;
    ts_check c = ts_check_begin("FC_PI, FC_HALF_PI: 0.5 LSB of ANGLE / 0.5 ulp");
    (void)ts_close(&c, ts_val(FC_PI, FC_ANGLE_FRAC), TS_PI, ts_tol(FC_ANGLE_FRAC, 0.5, 0.5, TS_PI), "FC_PI");
    (void)ts_close(&c, ts_val(FC_HALF_PI, FC_ANGLE_FRAC), TS_PI / 2.0,
                   ts_tol(FC_ANGLE_FRAC, 0.5, 0.5, TS_PI / 2.0), "FC_HALF_PI");
    ts_check_end(&c);
}

/* ---- conversions --------------------------------------------------------- */

static void test_from_float_to_float(void **state)
{
    (void)state;
    /* representable values go through unchanged */
    const float exact[] = {0.0f, 1.0f, -1.0f, 0.5f, -0.75f, 1.9990234375f, -2.0f, 0.0009765625f};
    for (size_t i = 0; i < sizeof exact / sizeof exact[0]; i++) {
        const float back = fc_to_float(fc_from_float(exact[i], FC_UNIT_FRAC), FC_UNIT_FRAC);
        TS_ASSERT_CLOSE((double)back, (double)exact[i], 0.0);
    }
    TS_ASSERT_CLOSE((double)fc_to_float(fc_from_float(-1234.5f, FC_LENGTH_FRAC), FC_LENGTH_FRAC), -1234.5,
                    0.0);
#if FC_NUMERIC_FIXED
    /* round to nearest: x = (n + f) LSB gives n for f < 0.5 and n + 1 for f > 0.5 */
    const float lsb = 1.0f / 1048576.0f; /* LENGTH */
    TS_ASSERT_REAL_EQ(fc_from_float(1000.0f * lsb + 0.25f * lsb, FC_LENGTH_FRAC), 1000);
    TS_ASSERT_REAL_EQ(fc_from_float(1000.0f * lsb + 0.75f * lsb, FC_LENGTH_FRAC), 1001);
    TS_ASSERT_REAL_EQ(fc_from_float(-1000.0f * lsb - 0.25f * lsb, FC_LENGTH_FRAC), -1000);
    TS_ASSERT_REAL_EQ(fc_from_float(-1000.0f * lsb - 0.75f * lsb, FC_LENGTH_FRAC), -1001);
    /* every raw value a float holds exactly comes back unchanged
     * (|raw| < 2^24), including odd values in [2^23, 2^24) */
    ts_rng rng = ts_rng_seed(101u);
    ts_check c = ts_check_begin("fc_from_float(fc_to_float(raw)) == raw");
    for (int i = 0; i < 20000; i++) {
        const int32_t raw = ts_rand_range(&rng, -16777215, 16777215);
        const float x = fc_to_float(raw, FC_UNIT_FRAC);
        (void)ts_close(&c, (double)fc_from_float(x, FC_UNIT_FRAC), (double)raw, 0.0, "raw %ld",
                       (long)raw);
    }
    ts_check_end(&c);
    /* the smallest such case, spelled out: 2^23 + 1 LSB */
    TS_ASSERT_REAL_EQ(fc_from_float(8388609.0f / 1073741824.0f, FC_UNIT_FRAC), 8388609);
    TS_ASSERT_REAL_EQ(fc_from_float(-8388609.0f / 1073741824.0f, FC_UNIT_FRAC), -8388609);
    /* out of range saturates symmetrically; NaN gives 0 */
    TS_ASSERT_REAL_EQ(fc_from_float(3.0f, FC_UNIT_FRAC), FC_REAL_MAX);
    TS_ASSERT_REAL_EQ(fc_from_float(-3.0f, FC_UNIT_FRAC), FC_REAL_MIN);
    TS_ASSERT_REAL_EQ(fc_from_float(2.0f, FC_UNIT_FRAC), FC_REAL_MAX);
    TS_ASSERT_REAL_EQ(fc_from_float(1.0e9f, FC_LENGTH_FRAC), FC_REAL_MAX);
    TS_ASSERT_REAL_EQ(fc_from_float(NAN, FC_UNIT_FRAC), 0);
    /* fc_to_float of the extremes */
    TS_ASSERT_CLOSE((double)fc_to_float(FC_REAL_MAX, FC_UNIT_FRAC), 2.0, 1.0e-9);
    TS_ASSERT_CLOSE((double)fc_to_float(FC_REAL_MIN, FC_ANGLE_FRAC), -8.0, 1.0e-8);
#else
    /* float: the identity for any format */
    TS_ASSERT_REAL_EQ(fc_from_float(0.1f, FC_UNIT_FRAC), 0.1f);
    TS_ASSERT_REAL_EQ(fc_from_float(1.0e9f, FC_LENGTH_FRAC), 1.0e9f);
    TS_ASSERT_REAL_EQ(fc_to_float(-3.25e-7f, FC_GAIN_FRAC), -3.25e-7f);
    assert_true(isnan(fc_to_float(fc_from_float(NAN, FC_UNIT_FRAC), FC_UNIT_FRAC)));
#endif
}

/* ---- add, sub, neg, abs --------------------------------------------------- */

static void test_add_sub_neg_abs(void **state)
{
    (void)state;
    fc_arith ar = {0};
    ts_rng rng = ts_rng_seed(202u);
    ts_check c = ts_check_begin("add/sub/neg/abs in LENGTH");
    for (int i = 0; i < 2000; i++) {
        double ra, rb;
        const fc_real a = ts_in(ts_uniform(&rng, -1000.0f, 1000.0f), FC_LENGTH_FRAC, &ra);
        const fc_real b = ts_in(ts_uniform(&rng, -1000.0f, 1000.0f), FC_LENGTH_FRAC, &rb);
        /* fixed: exact; float: one rounding (0.5 ulp of the result) */
        const double sum_tol = ts_tol(FC_LENGTH_FRAC, 0.0, 0.5, ra + rb);
        const double dif_tol = ts_tol(FC_LENGTH_FRAC, 0.0, 0.5, ra - rb);
        (void)ts_close(&c, ts_val(fc_add(&ar, a, b), FC_LENGTH_FRAC), ra + rb, sum_tol, "add %d", i);
        (void)ts_close(&c, ts_val(fc_sub(&ar, a, b), FC_LENGTH_FRAC), ra - rb, dif_tol, "sub %d", i);
        (void)ts_close(&c, ts_val(fc_neg(&ar, a), FC_LENGTH_FRAC), -ra, 0.0, "neg %d", i);
        (void)ts_close(&c, ts_val(fc_abs(&ar, a), FC_LENGTH_FRAC), fabs(ra), 0.0, "abs %d", i);
    }
    ts_check_end(&c);
    TS_ASSERT_REAL_EQ(fc_abs(&ar, FC_C(-0.5f, UNIT)), FC_C(0.5f, UNIT));
    TS_ASSERT_REAL_EQ(fc_abs(&ar, FC_C(0.5f, UNIT)), FC_C(0.5f, UNIT));
    TS_ASSERT_REAL_EQ(fc_neg(&ar, FC_INT(0, UNIT)), FC_INT(0, UNIT));
    /* the full range is usable without saturating */
    TS_ASSERT_REAL_EQ(fc_add(&ar, FC_REAL_MAX, FC_REAL_MIN), FC_INT(0, UNIT));
    TS_ASSERT_REAL_EQ(fc_neg(&ar, FC_REAL_MIN), FC_REAL_MAX);
    TS_ASSERT_REAL_EQ(fc_abs(&ar, FC_REAL_MIN), FC_REAL_MAX);
    assert_int_equal(ar.saturated, 0);
}

static void test_add_sub_neg_saturation(void **state)
{
    (void)state;
#if FC_NUMERIC_FIXED
    fc_arith ar = {0};
    TS_ASSERT_REAL_EQ(fc_add(&ar, FC_REAL_MAX, 1), INT32_MAX);
    assert_int_equal(ar.saturated, 1);
    ar.saturated = 0;
    TS_ASSERT_REAL_EQ(fc_add(&ar, FC_INT(2000, LENGTH), FC_INT(100, LENGTH)), INT32_MAX);
    assert_int_equal(ar.saturated, 1);
    ar.saturated = 0;
    TS_ASSERT_REAL_EQ(fc_add(&ar, FC_INT(-2000, LENGTH), FC_INT(-100, LENGTH)), -INT32_MAX);
    assert_int_equal(ar.saturated, 1);
    ar.saturated = 0;
    TS_ASSERT_REAL_EQ(fc_sub(&ar, FC_REAL_MIN, 1), -INT32_MAX);
    assert_int_equal(ar.saturated, 1);
    ar.saturated = 0;
    TS_ASSERT_REAL_EQ(fc_sub(&ar, FC_REAL_MAX, FC_REAL_MIN), INT32_MAX);
    assert_int_equal(ar.saturated, 1);
    ar.saturated = 0;
    /* INT32_MIN is outside the symmetric range: negating it saturates */
    TS_ASSERT_REAL_EQ(fc_neg(&ar, INT32_MIN), INT32_MAX);
    assert_int_equal(ar.saturated, 1);
    ar.saturated = 0;
    TS_ASSERT_REAL_EQ(fc_abs(&ar, INT32_MIN), INT32_MAX);
    assert_int_equal(ar.saturated, 1);
    /* the flag is sticky: a later normal operation does not clear it */
    (void)fc_add(&ar, 1, 1);
    assert_int_equal(ar.saturated, 1);
#else
    /* float: nothing saturates and the flag is never set; overflow is inf */
    fc_arith ar = {0};
    const fc_real big = fc_add(&ar, FC_REAL_MAX, FC_REAL_MAX);
    assert_false(fc_is_finite(big));
    assert_true(big > 0.0f);
    assert_false(fc_is_finite(fc_sub(&ar, FC_REAL_MIN, FC_REAL_MAX)));
    TS_ASSERT_REAL_EQ(fc_neg(&ar, FC_REAL_MIN), FC_REAL_MAX);
    assert_int_equal(ar.saturated, 0);
#endif
}

/* ---- multiplication ------------------------------------------------------- */

typedef struct mul_case {
    const char *name;
    int frac_a, frac_b, frac_out, shift;
    float lo_a, hi_a, lo_b, hi_b;
} mul_case;

static const mul_case mul_cases[] = {
    {"RATE*DT->ANGLE", FC_RATE_FRAC, FC_DT_FRAC, FC_ANGLE_FRAC, FC_SHIFT(RATE, DT, ANGLE), -35.0f, 35.0f,
     0.0f, 0.01f},
    {"UNIT*UNIT->UNIT", FC_UNIT_FRAC, FC_UNIT_FRAC, FC_UNIT_FRAC, FC_SHIFT(UNIT, UNIT, UNIT), -1.0f, 1.0f,
     -1.0f, 1.0f},
    {"LENGTH*RATIO->LENGTH", FC_LENGTH_FRAC, FC_RATIO_FRAC, FC_LENGTH_FRAC,
     FC_SHIFT(LENGTH, RATIO, LENGTH), -1000.0f, 1000.0f, -2.0f, 2.0f},
    {"MASS*ACCEL->FORCE", FC_MASS_FRAC, FC_ACCEL_FRAC, FC_FORCE_FRAC, FC_SHIFT(MASS, ACCEL, FORCE), 0.0f,
     2.0f, -20.0f, 20.0f},
    {"INERTIA*RATE->MOMENT", FC_INERTIA_FRAC, FC_RATE_FRAC, FC_MOMENT_FRAC,
     FC_SHIFT(INERTIA, RATE, MOMENT), 0.0f, 1.0e-4f, -30.0f, 30.0f},
    {"GAIN*ANGLE->RATE", FC_GAIN_FRAC, FC_ANGLE_FRAC, FC_RATE_FRAC, FC_SHIFT(GAIN, ANGLE, RATE), 0.0f, 20.0f,
     -3.0f, 3.0f},
};

static void test_mul_values(void **state)
{
    (void)state;
    fc_arith ar = {0};
    ts_rng rng = ts_rng_seed(303u);
    for (size_t k = 0; k < sizeof mul_cases / sizeof mul_cases[0]; k++) {
        const mul_case *mc = &mul_cases[k];
        ts_check c = ts_check_begin(mc->name);
        for (int i = 0; i < 2000; i++) {
            double ra, rb;
            const fc_real a = ts_in(ts_uniform(&rng, mc->lo_a, mc->hi_a), mc->frac_a, &ra);
            const fc_real b = ts_in(ts_uniform(&rng, mc->lo_b, mc->hi_b), mc->frac_b, &rb);
            const double ref = ra * rb;
            /* fixed: rounded to nearest, 0.5 LSB; float: 0.5 ulp */
            (void)ts_close(&c, ts_val(fc_mul(&ar, a, b, mc->shift), mc->frac_out), ref,
                           ts_tol(mc->frac_out, 0.5, 0.5, ref), "%.9g * %.9g", ra, rb);
        }
        ts_check_end(&c);
    }
    assert_int_equal(ar.saturated, 0);
}

static void test_mul_rounds_to_nearest(void **state)
{
    (void)state;
    fc_arith ar = {0};
#if FC_NUMERIC_FIXED
    /* raw cases: a * b / 2^shift */
    TS_ASSERT_REAL_EQ(fc_mul(&ar, 5, 1, 2), 1);   /* 1.25 -> 1 */
    TS_ASSERT_REAL_EQ(fc_mul(&ar, 7, 1, 2), 2);   /* 1.75 -> 2 */
    TS_ASSERT_REAL_EQ(fc_mul(&ar, -5, 1, 2), -1); /* -1.25 -> -1 */
    TS_ASSERT_REAL_EQ(fc_mul(&ar, -7, 1, 2), -2); /* -1.75 -> -2 */
    TS_ASSERT_REAL_EQ(fc_mul(&ar, 3, 3, 4), 1);   /* 0.5625 -> 1 */
    TS_ASSERT_REAL_EQ(fc_mul(&ar, 1, 7, 4), 0);   /* 0.4375 -> 0 (truncation would give 0 too) */
    TS_ASSERT_REAL_EQ(fc_mul(&ar, -3, 3, 4), -1); /* -0.5625 -> -1 (truncation would give 0) */
    /* a product just below 1/2 LSB and just above */
    TS_ASSERT_REAL_EQ(fc_mul(&ar, (1 << 29) - 1, 1, 30), 0);
    TS_ASSERT_REAL_EQ(fc_mul(&ar, (1 << 29) + 1, 1, 30), 1);
    /* 0.999999 * 0.999999 in UNIT: the exact product, rounded */
    TS_ASSERT_REAL_EQ(fc_mul(&ar, INT32_MAX, INT32_MAX, 32), (fc_real)((((int64_t)INT32_MAX * INT32_MAX) +
                                                                      ((int64_t)1 << 31)) >> 32));
    /* shift 0 is the plain product, a negative shift scales up */
    TS_ASSERT_REAL_EQ(fc_mul(&ar, 1000, -1000, 0), -1000000);
    TS_ASSERT_REAL_EQ(fc_mul(&ar, 3, 5, -4), 240);
    /* random operands: |result * 2^shift - a b| <= 2^(shift-1) */
    ts_rng rng = ts_rng_seed(304u);
    int checked = 0;
    for (int i = 0; i < 20000; i++) {
        const int shift = 16 + (int)(ts_rand_u32(&rng) % 15u); /* 16..30 */
        const int32_t a = ts_rand_range(&rng, -INT32_MAX, INT32_MAX);
        /* |b| < 2^shift keeps the result inside int32 */
        const int32_t b = ts_rand_range(&rng, -((1 << shift) - 1), (1 << shift) - 1);
        const int64_t exact = (int64_t)a * b;
        const fc_real r = fc_mul(&ar, a, b, shift);
        const int64_t diff = (int64_t)r * ((int64_t)1 << shift) - exact; /* below 2^62 */
        const int64_t half = (int64_t)1 << (shift - 1);
        if (diff > half || diff < -half) {
            fail_msg("fc_mul(%ld, %ld, %d) = %ld: off by %lld / 2^%d", (long)a, (long)b, shift, (long)r,
                     (long long)diff, shift);
        }
        checked++;
    }
    assert_int_equal(checked, 20000);
#else
    /* float: the shift is ignored, the result is the float product */
    const float a = 1.2345678f, b = -7.654321f;
    TS_ASSERT_REAL_EQ(fc_mul(&ar, a, b, FC_SHIFT(UNIT, UNIT, UNIT)), a * b);
    TS_ASSERT_REAL_EQ(fc_mul(&ar, a, b, 0), a * b);
    TS_ASSERT_REAL_EQ(fc_mul(&ar, a, b, -17), a * b);
#endif
    assert_int_equal(ar.saturated, 0);
}

static void test_mul_saturation(void **state)
{
    (void)state;
    fc_arith ar = {0};
#if FC_NUMERIC_FIXED
    /* 1.99 * 1.99 in UNIT is out of range */
    TS_ASSERT_REAL_EQ(fc_mul(&ar, FC_REAL_MAX, FC_REAL_MAX, 30), INT32_MAX);
    assert_int_equal(ar.saturated, 1);
    ar.saturated = 0;
    TS_ASSERT_REAL_EQ(fc_mul(&ar, FC_REAL_MAX, FC_REAL_MIN, 30), -INT32_MAX);
    assert_int_equal(ar.saturated, 1);
    ar.saturated = 0;
    /* 100 m * 100 m as a LENGTH (10000 > 2048) */
    TS_ASSERT_REAL_EQ(fc_mul(&ar, FC_INT(100, LENGTH), FC_INT(100, LENGTH), FC_SHIFT(LENGTH, LENGTH, LENGTH)),
                      INT32_MAX);
    assert_int_equal(ar.saturated, 1);
    ar.saturated = 0;
    TS_ASSERT_REAL_EQ(fc_mul(&ar, FC_INT(-100, LENGTH), FC_INT(100, LENGTH), FC_SHIFT(LENGTH, LENGTH, LENGTH)),
                      -INT32_MAX);
    assert_int_equal(ar.saturated, 1);
    ar.saturated = 0;
    /* a negative shift whose scaling overflows 64 bits saturates too */
    TS_ASSERT_REAL_EQ(fc_mul(&ar, 1 << 20, 1 << 20, -30), INT32_MAX);
    assert_int_equal(ar.saturated, 1);
    ar.saturated = 0;
    TS_ASSERT_REAL_EQ(fc_mul(&ar, -(1 << 20), 1 << 20, -30), -INT32_MAX);
    assert_int_equal(ar.saturated, 1);
    ar.saturated = 0;
    /* just inside the range: no flag */
    TS_ASSERT_REAL_EQ(fc_mul(&ar, FC_C(1.5f, UNIT), FC_C(1.25f, UNIT), 30), FC_C(1.875f, UNIT));
    assert_int_equal(ar.saturated, 0);
#else
    TS_ASSERT_REAL_EQ(fc_mul(&ar, 1.0e20f, 1.0e10f, 30), 1.0e20f * 1.0e10f);
    assert_false(fc_is_finite(fc_mul(&ar, FC_REAL_MAX, 2.0f, 30)));
    assert_int_equal(ar.saturated, 0);
#endif
}

/* ---- fixed internals (fixed only) ---------------------------------------- */
#if FC_NUMERIC_FIXED
static void test_fx_saturate_and_rescale(void **state)
{
    (void)state;
    fc_arith ar = {0};
    TS_ASSERT_REAL_EQ(fc_fx_saturate(&ar, 12345), 12345);
    TS_ASSERT_REAL_EQ(fc_fx_saturate(&ar, INT32_MAX), INT32_MAX);
    TS_ASSERT_REAL_EQ(fc_fx_saturate(&ar, -(int64_t)INT32_MAX), -INT32_MAX);
    assert_int_equal(ar.saturated, 0);
    TS_ASSERT_REAL_EQ(fc_fx_saturate(&ar, (int64_t)INT32_MAX + 1), INT32_MAX);
    assert_int_equal(ar.saturated, 1);
    ar.saturated = 0;
    TS_ASSERT_REAL_EQ(fc_fx_saturate(&ar, INT32_MIN), -INT32_MAX);
    assert_int_equal(ar.saturated, 1);
    ar.saturated = 0;
    assert_true(fc_fx_rescale(&ar, 6, 2) == 2);    /* 1.5 -> 2 */
    assert_true(fc_fx_rescale(&ar, 5, 2) == 1);    /* 1.25 -> 1 */
    assert_true(fc_fx_rescale(&ar, -7, 2) == -2);  /* -1.75 -> -2 */
    assert_true(fc_fx_rescale(&ar, 9, 0) == 9);
    assert_true(fc_fx_rescale(&ar, -9, -3) == -72);
    assert_int_equal(ar.saturated, 0);
    assert_true(fc_fx_rescale(&ar, (int64_t)1 << 40, -30) == INT64_MAX);
    assert_int_equal(ar.saturated, 1);
    ar.saturated = 0;
    assert_true(fc_fx_rescale(&ar, -((int64_t)1 << 40), -30) == -INT64_MAX);
    assert_int_equal(ar.saturated, 1);
}
#endif

/* ---- division ------------------------------------------------------------- */

typedef struct div_case {
    const char *name;
    int frac_num, frac_den, frac_out, shift;
    float lo_num, hi_num, lo_den, hi_den; /* the denominator's sign is drawn separately */
} div_case;

static const div_case div_cases[] = {
    {"UNIT/ANGLE->UNIT", FC_UNIT_FRAC, FC_ANGLE_FRAC, FC_UNIT_FRAC, FC_DIV_SHIFT(UNIT, ANGLE, UNIT), -1.0f,
     1.0f, 0.5f, 7.9f},
    {"LENGTH/LENGTH->UNIT", FC_LENGTH_FRAC, FC_LENGTH_FRAC, FC_UNIT_FRAC, FC_DIV_SHIFT(LENGTH, LENGTH, UNIT),
     -100.0f, 100.0f, 100.0f, 2000.0f},
    {"FORCE/MASS->ACCEL", FC_FORCE_FRAC, FC_MASS_FRAC, FC_ACCEL_FRAC, FC_DIV_SHIFT(FORCE, MASS, ACCEL), -40.0f,
     40.0f, 0.5f, 2.0f},
    {"RATIO/RATIO->RATIO", FC_RATIO_FRAC, FC_RATIO_FRAC, FC_RATIO_FRAC, FC_DIV_SHIFT(RATIO, RATIO, RATIO),
     -100.0f, 100.0f, 1.0f, 100.0f},
    {"LENGTH/VEL->TIME", FC_LENGTH_FRAC, FC_VEL_FRAC, FC_TIME_FRAC, FC_DIV_SHIFT(LENGTH, VEL, TIME), -2000.0f,
     2000.0f, 0.1f, 500.0f},
};

static void test_div_values(void **state)
{
    (void)state;
    fc_arith ar = {0};
    ts_rng rng = ts_rng_seed(404u);
    for (size_t k = 0; k < sizeof div_cases / sizeof div_cases[0]; k++) {
        const div_case *dc = &div_cases[k];
        ts_check c = ts_check_begin(dc->name);
        for (int i = 0; i < 2000; i++) {
            double rn, rd;
            const float sign = (ts_rand_u32(&rng) & 0x100u) != 0u ? -1.0f : 1.0f;
            const fc_real n = ts_in(ts_uniform(&rng, dc->lo_num, dc->hi_num), dc->frac_num, &rn);
            const fc_real d = ts_in(sign * ts_uniform(&rng, dc->lo_den, dc->hi_den), dc->frac_den, &rd);
            const double ref = rn / rd;
            /* fixed: rounded to nearest, 0.5 LSB (plus the double reference's
             * own rounding); float: 0.5 ulp */
            (void)ts_close(&c, ts_val(fc_div(&ar, n, d, dc->shift), dc->frac_out), ref,
                           ts_tol(dc->frac_out, 0.5 + 1.0e-6, 0.5, ref), "%.9g / %.9g", rn, rd);
        }
        ts_check_end(&c);
    }
    assert_int_equal(ar.saturated, 0);
}

static void test_div_rounds_to_nearest(void **state)
{
    (void)state;
    fc_arith ar = {0};
#if FC_NUMERIC_FIXED
    TS_ASSERT_REAL_EQ(fc_div(&ar, 1, 3, 0), 0);   /* 0.33 */
    TS_ASSERT_REAL_EQ(fc_div(&ar, 2, 3, 0), 1);   /* 0.67 (truncation gives 0) */
    TS_ASSERT_REAL_EQ(fc_div(&ar, -2, 3, 0), -1); /* -0.67 */
    TS_ASSERT_REAL_EQ(fc_div(&ar, 2, -3, 0), -1);
    TS_ASSERT_REAL_EQ(fc_div(&ar, -2, -3, 0), 1);
    TS_ASSERT_REAL_EQ(fc_div(&ar, 11, 4, 0), 3);  /* 2.75 */
    TS_ASSERT_REAL_EQ(fc_div(&ar, -9, 4, 0), -2); /* -2.25 */
    TS_ASSERT_REAL_EQ(fc_div(&ar, 1, 3, 2), 1);   /* 4/3 */
    /* 0.5 / 1.5 in UNIT: round(2^30 / 3) = round(357913941.33) */
    TS_ASSERT_REAL_EQ(fc_div(&ar, FC_C(0.5f, UNIT), FC_C(1.5f, UNIT), FC_DIV_SHIFT(UNIT, UNIT, UNIT)), 357913941);
    /* random raw operands against the exactly rounded quotient (a separate
     * record: some of these quotients are out of range and saturate) */
    fc_arith ar_random = {0};
    ts_rng rng = ts_rng_seed(405u);
    for (int i = 0; i < 20000; i++) {
        const int shift = (int)(ts_rand_u32(&rng) % 31u); /* 0..30 */
        const int32_t n = ts_rand_range(&rng, -(1 << 30), 1 << 30);
        int32_t d = ts_rand_range(&rng, -INT32_MAX, INT32_MAX);
        if (d == 0) {
            d = 1;
        }
        const fc_real q = fc_div(&ar_random, n, d, shift);
        if (q == FC_REAL_MAX || q == FC_REAL_MIN) {
            continue; /* out of range: checked in test_div_saturation */
        }
        /* |q d - n 2^shift| <= |d| / 2, in 128-bit-free arithmetic: |n 2^shift| < 2^61 */
        const int64_t num = (int64_t)n * ((int64_t)1 << shift);
        const int64_t residual = (int64_t)q * d - num;
        const int64_t ad = d < 0 ? -(int64_t)d : (int64_t)d;
        if (2 * (residual < 0 ? -residual : residual) > ad) {
            fail_msg("fc_div(%ld, %ld, %d) = %ld: residual %lld", (long)n, (long)d, shift, (long)q,
                     (long long)residual);
        }
    }
#else
    const float n = 1.0f, d = 3.0f;
    TS_ASSERT_REAL_EQ(fc_div(&ar, n, d, 30), n / d);
    TS_ASSERT_REAL_EQ(fc_div(&ar, -7.5f, 0.25f, -3), -30.0f);
#endif
    assert_int_equal(ar.saturated, 0);
}

static void test_div_saturation(void **state)
{
    (void)state;
#if FC_NUMERIC_FIXED
    fc_arith ar = {0};
    /* 100 / 0.5 = 200 does not fit RATIO [-128, 128) */
    TS_ASSERT_REAL_EQ(fc_div(&ar, FC_INT(100, RATIO), FC_C(0.5f, RATIO), FC_DIV_SHIFT(RATIO, RATIO, RATIO)),
                      INT32_MAX);
    assert_int_equal(ar.saturated, 1);
    ar.saturated = 0;
    TS_ASSERT_REAL_EQ(fc_div(&ar, FC_INT(-100, RATIO), FC_C(0.5f, RATIO), FC_DIV_SHIFT(RATIO, RATIO, RATIO)),
                      -INT32_MAX);
    assert_int_equal(ar.saturated, 1);
    ar.saturated = 0;
    TS_ASSERT_REAL_EQ(fc_div(&ar, FC_INT(100, RATIO), FC_C(-0.5f, RATIO), FC_DIV_SHIFT(RATIO, RATIO, RATIO)),
                      -INT32_MAX);
    assert_int_equal(ar.saturated, 1);
    ar.saturated = 0;
    /* a tiny denominator */
    TS_ASSERT_REAL_EQ(fc_div(&ar, FC_INT(1, UNIT), 1, FC_DIV_SHIFT(UNIT, UNIT, UNIT)), INT32_MAX);
    assert_int_equal(ar.saturated, 1);
#else
    fc_arith ar = {0};
    /* float: no saturation, no flag */
    TS_ASSERT_REAL_EQ(fc_div(&ar, 100.0f, 0.5f, 0), 200.0f);
    assert_false(fc_is_finite(fc_div(&ar, 1.0e30f, 1.0e-30f, 0)));
    assert_int_equal(ar.saturated, 0);
#endif
}

/* Both backends: a zero denominator sets the flag and gives +-FC_REAL_MAX
 * toward the sign of the numerator, or 0 for 0/0. */
static void test_div_by_zero(void **state)
{
    (void)state;
    fc_arith ar = {0};
    const fc_real zero = FC_INT(0, RATIO);
    TS_ASSERT_REAL_EQ(fc_div(&ar, FC_C(0.5f, UNIT), zero, FC_DIV_SHIFT(UNIT, RATIO, UNIT)), FC_REAL_MAX);
    assert_int_equal(ar.saturated, 1);
    ar.saturated = 0;
    TS_ASSERT_REAL_EQ(fc_div(&ar, FC_C(-0.5f, UNIT), zero, FC_DIV_SHIFT(UNIT, RATIO, UNIT)), FC_REAL_MIN);
    assert_int_equal(ar.saturated, 1);
    ar.saturated = 0;
    TS_ASSERT_REAL_EQ(fc_div(&ar, FC_INT(0, UNIT), zero, FC_DIV_SHIFT(UNIT, RATIO, UNIT)), FC_INT(0, UNIT));
    assert_int_equal(ar.saturated, 1);
    ar.saturated = 0;
    /* a non-zero denominator does not touch the flag */
    (void)fc_div(&ar, FC_C(0.5f, UNIT), FC_C(2.0f, RATIO), FC_DIV_SHIFT(UNIT, RATIO, UNIT));
    assert_int_equal(ar.saturated, 0);
}

/* A quotient out of range whose dividend also overflows the 64-bit left
 * shift (TIME / DT -> RATIO: shift 38) must saturate toward the sign of the
 * quotient, with the flag set and no signed overflow. */
static void test_div_saturation_large_shift(void **state)
{
    (void)state;
    fc_arith ar = {0};
    const int shift = FC_DIV_SHIFT(TIME, DT, RATIO);
    /* 1000 s / 0.5 s = 2000: out of RATIO */
    const fc_real pos = fc_div(&ar, FC_INT(1000, TIME), FC_C(0.5f, DT), shift);
#if FC_NUMERIC_FIXED
    TS_ASSERT_REAL_EQ(pos, FC_REAL_MAX);
    assert_int_equal(ar.saturated, 1);
    ar.saturated = 0;
    TS_ASSERT_REAL_EQ(fc_div(&ar, FC_INT(-1000, TIME), FC_C(0.5f, DT), shift), FC_REAL_MIN);
    assert_int_equal(ar.saturated, 1);
#else
    TS_ASSERT_REAL_EQ(pos, 2000.0f);
    assert_int_equal(ar.saturated, 0);
#endif
}

/* ---- format change -------------------------------------------------------- */

static void test_convert(void **state)
{
    (void)state;
    fc_arith ar = {0};
    ts_rng rng = ts_rng_seed(505u);
    ts_check c = ts_check_begin("fc_convert");
    for (int i = 0; i < 2000; i++) {
        double r;
        /* ANGLE -> UNIT (left shift, exact for |a| < 2) */
        const fc_real a = ts_in(ts_uniform(&rng, -1.99f, 1.99f), FC_ANGLE_FRAC, &r);
        (void)ts_close(&c, ts_val(fc_convert(&ar, a, FC_ANGLE_FRAC, FC_UNIT_FRAC), FC_UNIT_FRAC), r, 0.0,
                       "ANGLE->UNIT %.9g", r);
        /* UNIT -> LENGTH (right shift: rounded to nearest) */
        const fc_real u = ts_in(ts_uniform(&rng, -1.99f, 1.99f), FC_UNIT_FRAC, &r);
        (void)ts_close(&c, ts_val(fc_convert(&ar, u, FC_UNIT_FRAC, FC_LENGTH_FRAC), FC_LENGTH_FRAC), r,
                       ts_tol(FC_LENGTH_FRAC, 0.5, 0.0, r), "UNIT->LENGTH %.9g", r);
        /* VEL -> LENGTH */
        const fc_real v = ts_in(ts_uniform(&rng, -500.0f, 500.0f), FC_VEL_FRAC, &r);
        (void)ts_close(&c, ts_val(fc_convert(&ar, v, FC_VEL_FRAC, FC_LENGTH_FRAC), FC_LENGTH_FRAC), r,
                       ts_tol(FC_LENGTH_FRAC, 0.5, 0.0, r), "VEL->LENGTH %.9g", r);
    }
    ts_check_end(&c);
    assert_int_equal(ar.saturated, 0);
#if FC_NUMERIC_FIXED
    TS_ASSERT_REAL_EQ(fc_convert(&ar, 6, 30, 28), 2);   /* 1.5 LSB -> 2 */
    TS_ASSERT_REAL_EQ(fc_convert(&ar, 5, 30, 28), 1);   /* 1.25 -> 1 */
    TS_ASSERT_REAL_EQ(fc_convert(&ar, -7, 30, 28), -2); /* -1.75 -> -2 */
    TS_ASSERT_REAL_EQ(fc_convert(&ar, -3, 28, 30), -12);
    TS_ASSERT_REAL_EQ(fc_convert(&ar, 12345, 20, 20), 12345);
    assert_int_equal(ar.saturated, 0);
    /* 100 m does not fit UNIT */
    TS_ASSERT_REAL_EQ(fc_convert(&ar, FC_INT(100, LENGTH), FC_LENGTH_FRAC, FC_UNIT_FRAC), INT32_MAX);
    assert_int_equal(ar.saturated, 1);
    ar.saturated = 0;
    TS_ASSERT_REAL_EQ(fc_convert(&ar, FC_INT(-100, LENGTH), FC_LENGTH_FRAC, FC_UNIT_FRAC), -INT32_MAX);
    assert_int_equal(ar.saturated, 1);
#else
    TS_ASSERT_REAL_EQ(fc_convert(&ar, 123.456f, FC_LENGTH_FRAC, FC_UNIT_FRAC), 123.456f);
    assert_int_equal(ar.saturated, 0);
#endif
}

/* ---- dot products and accumulators --------------------------------------- */

static void test_dot2_dot3_dot4(void **state)
{
    (void)state;
    fc_arith ar = {0};
    ts_rng rng = ts_rng_seed(606u);
    /* UNIT x UNIT -> UNIT and LENGTH x RATIO -> LENGTH */
    const struct {
        const char *name;
        int fa, fb, fout, shift;
        float ra, rb;
    } cases[] = {
        {"UNIT.UNIT->UNIT", FC_UNIT_FRAC, FC_UNIT_FRAC, FC_UNIT_FRAC, FC_SHIFT(UNIT, UNIT, UNIT), 0.99f, 0.49f},
        {"LENGTH.RATIO->LENGTH", FC_LENGTH_FRAC, FC_RATIO_FRAC, FC_LENGTH_FRAC,
         FC_SHIFT(LENGTH, RATIO, LENGTH), 500.0f, 1.0f},
        {"RATE.INERTIA->MOMENT", FC_RATE_FRAC, FC_INERTIA_FRAC, FC_MOMENT_FRAC,
         FC_SHIFT(RATE, INERTIA, MOMENT), 30.0f, 1.0e-3f},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        ts_check c = ts_check_begin(cases[k].name);
        for (int i = 0; i < 1000; i++) {
            fc_real a[4], b[4];
            double ra[4], rb[4];
            for (int j = 0; j < 4; j++) {
                a[j] = ts_in(ts_uniform(&rng, -cases[k].ra, cases[k].ra), cases[k].fa, &ra[j]);
                b[j] = ts_in(ts_uniform(&rng, -cases[k].rb, cases[k].rb), cases[k].fb, &rb[j]);
            }
            double ref = 0.0, mag = 0.0;
            for (int n = 2; n <= 4; n++) {
                ref = 0.0;
                mag = 0.0;
                for (int j = 0; j < n; j++) {
                    ref += ra[j] * rb[j];
                    mag += fabs(ra[j] * rb[j]);
                }
                fc_real r;
                if (n == 2) {
                    r = fc_dot2(&ar, a[0], b[0], a[1], b[1], cases[k].shift);
                } else if (n == 3) {
                    r = fc_dot3(&ar, a[0], b[0], a[1], b[1], a[2], b[2], cases[k].shift);
                } else {
                    r = fc_dot4(&ar, a[0], b[0], a[1], b[1], a[2], b[2], a[3], b[3], cases[k].shift);
                }
                /* fixed: one rounding, 1 LSB; float: 2n ulps of the sum of |terms| */
                (void)ts_close(&c, ts_val(r, cases[k].fout), ref, ts_tol(cases[k].fout, 1.0, 2.0 * n, mag),
                               "dot%d #%d", n, i);
            }
        }
        ts_check_end(&c);
    }
    /* exact small cases */
    TS_ASSERT_REAL_EQ(fc_dot2(&ar, FC_C(0.5f, UNIT), FC_C(0.5f, UNIT), FC_C(-0.5f, UNIT), FC_C(0.25f, UNIT),
                              FC_SHIFT(UNIT, UNIT, UNIT)),
                      FC_C(0.125f, UNIT));
    TS_ASSERT_REAL_EQ(fc_dot3(&ar, FC_INT(1, UNIT), FC_C(0.25f, UNIT), FC_INT(1, UNIT), FC_C(0.25f, UNIT),
                              FC_INT(1, UNIT), FC_C(0.5f, UNIT), FC_SHIFT(UNIT, UNIT, UNIT)),
                      FC_INT(1, UNIT));
    TS_ASSERT_REAL_EQ(fc_dot4(&ar, FC_C(0.5f, UNIT), FC_C(0.5f, UNIT), FC_C(0.5f, UNIT), FC_C(0.5f, UNIT),
                              FC_C(0.5f, UNIT), FC_C(0.5f, UNIT), FC_C(0.5f, UNIT), FC_C(0.5f, UNIT),
                              FC_SHIFT(UNIT, UNIT, UNIT)),
                      FC_INT(1, UNIT));
    assert_int_equal(ar.saturated, 0);
}

/* Products near 2^62 accumulate without wrapping the 64-bit sum; a result out
 * of range saturates with the flag. */
static void test_dot_wide_intermediate(void **state)
{
    (void)state;
    fc_arith ar = {0};
#if FC_NUMERIC_FIXED
    const fc_real m = FC_REAL_MAX;
    /* four products of (2^31 - 1)^2: about 2^64 in all, 4 after >> 62 */
    TS_ASSERT_REAL_EQ(fc_dot4(&ar, m, m, m, m, m, m, m, m, 62), 4);
    TS_ASSERT_REAL_EQ(fc_dot4(&ar, m, -m, m, -m, m, -m, m, -m, 62), -4);
    TS_ASSERT_REAL_EQ(fc_dot3(&ar, m, m, m, m, m, m, 62), 3);
    TS_ASSERT_REAL_EQ(fc_dot2(&ar, m, m, m, m, 33), (1 << 30) - 1); /* 2^30 - 1 + 2^-32 */
    /* cancellation of huge terms is exact */
    TS_ASSERT_REAL_EQ(fc_dot4(&ar, m, m, m, -m, m, m, m, -m, 30), 0);
    assert_int_equal(ar.saturated, 0);
    /* (1500 m)^2 + (1500 m)^2 as a LENGTH-format number does not fit: saturates */
    TS_ASSERT_REAL_EQ(fc_dot3(&ar, FC_INT(1500, LENGTH), FC_INT(1500, LENGTH), FC_INT(1500, LENGTH),
                              FC_INT(1500, LENGTH), 0, 0, FC_SHIFT(LENGTH, LENGTH, LENGTH)),
                      INT32_MAX);
    assert_int_equal(ar.saturated, 1);
    ar.saturated = 0;
    TS_ASSERT_REAL_EQ(fc_dot4(&ar, m, -m, m, -m, 0, 0, 0, 0, 30), -INT32_MAX);
    assert_int_equal(ar.saturated, 1);
    ar.saturated = 0;
    TS_ASSERT_REAL_EQ(fc_dot2(&ar, m, m, m, m, 30), INT32_MAX);
    assert_int_equal(ar.saturated, 1);
#else
    /* float: large operands, no flag */
    TS_ASSERT_CLOSE((double)fc_dot3(&ar, 1500.0f, 1500.0f, 1500.0f, 1500.0f, 1500.0f, 1500.0f, 0),
                    3.0 * 1500.0 * 1500.0, 0.0);
    assert_int_equal(ar.saturated, 0);
#endif
}

/* fixed: the products with a shift of 32 or more (the formats that drop 32
 * bits or more: RATE x RATE -> GAIN, UNIT x UNIT -> ANGLE, ...) are narrowed
 * on the 32-bit halves; they give bit for bit the values and flags of the
 * int64_t forms fc_fx_narrow and fc_fx_narrow_sum, at every such shift in
 * use and beyond, over edge and random operands. */
static void test_mul_dot_wide_shifts(void **state)
{
    (void)state;
#if FC_NUMERIC_FIXED
    ts_rng rng = ts_rng_seed(3232u);
    const int32_t edges[] = {INT32_MIN, INT32_MIN + 1, INT32_MAX, INT32_MAX - 1, 0, 1, -1,
                             (int32_t)0x40000000, -(int32_t)0x40000000, 46341, -46341};
    const size_t n_edges = sizeof edges / sizeof edges[0];
    unsigned cases = 0u;
    for (int shift = 32; shift <= 42; shift++) {
        for (int i = 0; i < 20000; i++) {
            int32_t a[4], b[4];
            for (int k = 0; k < 4; k++) {
                const uint32_t pick = ts_rand_u32(&rng);
                a[k] = (pick & 3u) == 0u ? edges[pick % n_edges] : (int32_t)ts_rand_u32(&rng) >> (pick % 31u);
                b[k] = (pick & 12u) == 0u ? edges[(pick >> 8) % n_edges]
                                          : (int32_t)ts_rand_u32(&rng) >> ((pick >> 8) % 31u);
            }
            fc_arith got = {0}, want = {0};
            const int64_t p[4] = {(int64_t)a[0] * b[0], (int64_t)a[1] * b[1], (int64_t)a[2] * b[2],
                                  (int64_t)a[3] * b[3]};
            assert_int_equal(fc_mul(&got, a[0], b[0], shift), fc_fx_narrow(&want, p[0], shift));
            assert_int_equal(got.saturated, want.saturated);
            assert_int_equal(fc_dot2(&got, a[0], b[0], a[1], b[1], shift),
                             fc_fx_narrow_sum(&want, p[0], p[1], 0, 0, shift));
            assert_int_equal(got.saturated, want.saturated);
            assert_int_equal(fc_dot3(&got, a[0], b[0], a[1], b[1], a[2], b[2], shift),
                             fc_fx_narrow_sum(&want, p[0], p[1], p[2], 0, shift));
            assert_int_equal(got.saturated, want.saturated);
            assert_int_equal(fc_dot4(&got, a[0], b[0], a[1], b[1], a[2], b[2], a[3], b[3], shift),
                             fc_fx_narrow_sum(&want, p[0], p[1], p[2], p[3], shift));
            assert_int_equal(got.saturated, want.saturated);
            cases++;
        }
    }
    print_message("wide shifts exact: %u cases\n", cases);
#else
    skip(); /* fixed backend only */
#endif
}

static void test_acc(void **state)
{
    (void)state;
    fc_arith ar = {0};
    ts_rng rng = ts_rng_seed(707u);
    /* the empty sum is zero */
    TS_ASSERT_REAL_EQ(fc_acc_result(&ar, fc_acc_zero(), FC_SHIFT(MAT, MAT, MAT)), FC_INT(0, MAT));
    ts_check c = ts_check_begin("fc_acc 8-term MAT.LENGTH->LENGTH");
    for (int i = 0; i < 2000; i++) {
        fc_acc acc = fc_acc_zero();
        double ref = 0.0, mag = 0.0;
        const int n = 1 + (int)(ts_rand_u32(&rng) % 8u);
        for (int j = 0; j < n; j++) {
            double ra, rb;
            const fc_real a = ts_in(ts_uniform(&rng, -2.0f, 2.0f), FC_MAT_FRAC, &ra);
            const fc_real b = ts_in(ts_uniform(&rng, -100.0f, 100.0f), FC_LENGTH_FRAC, &rb);
            acc = fc_acc_mac(acc, a, b);
            ref += ra * rb;
            mag += fabs(ra * rb);
        }
        /* fixed: one rounding, 1 LSB; float: 2n ulps of the sum of |terms| */
        (void)ts_close(&c, ts_val(fc_acc_result(&ar, acc, FC_SHIFT(MAT, LENGTH, LENGTH)), FC_LENGTH_FRAC), ref,
                       ts_tol(FC_LENGTH_FRAC, 1.0, 2.0 * n, mag), "sum of %d", n);
    }
    ts_check_end(&c);
    assert_int_equal(ar.saturated, 0);
#if FC_NUMERIC_FIXED
    /* eight products of (2^31 - 1)^2 fit the accumulator: 8 after >> 62 */
    fc_acc acc = fc_acc_zero();
    for (int j = 0; j < 8; j++) {
        acc = fc_acc_mac(acc, FC_REAL_MAX, FC_REAL_MAX);
    }
    TS_ASSERT_REAL_EQ(fc_acc_result(&ar, acc, 62), 8);
    assert_int_equal(ar.saturated, 0);
    /* and saturate positively as a MAT result */
    TS_ASSERT_REAL_EQ(fc_acc_result(&ar, acc, FC_SHIFT(MAT, MAT, MAT)), INT32_MAX);
    assert_int_equal(ar.saturated, 1);
    ar.saturated = 0;
    acc = fc_acc_zero();
    for (int j = 0; j < 8; j++) {
        acc = fc_acc_mac(acc, FC_REAL_MAX, FC_REAL_MIN);
    }
    TS_ASSERT_REAL_EQ(fc_acc_result(&ar, acc, 62), -8);
    TS_ASSERT_REAL_EQ(fc_acc_result(&ar, acc, FC_SHIFT(MAT, MAT, MAT)), -INT32_MAX);
    assert_int_equal(ar.saturated, 1);
#endif
}

/* fc_dot2 sums two full products (each below 2^62, the sum below 2^63) and
 * then rounds: the rounding must not overflow the 64-bit sum either. */
static void test_dot2_full_range_rounding(void **state)
{
    (void)state;
    fc_arith ar = {0};
#if FC_NUMERIC_FIXED
    const fc_real m = FC_REAL_MAX;
    /* 2 (2^31 - 1)^2 / 2^62 = 2 - 2^-29: rounds to 2 */
    TS_ASSERT_REAL_EQ(fc_dot2(&ar, m, m, m, m, 62), 2);
    TS_ASSERT_REAL_EQ(fc_dot2(&ar, m, m, m, m, 40), (fc_real)1 << 23);
    assert_int_equal(ar.saturated, 0);
#else
    TS_ASSERT_REAL_EQ(fc_dot2(&ar, FC_REAL_MAX, 0.5f, FC_REAL_MAX, 0.5f, 62), FC_REAL_MAX);
    assert_int_equal(ar.saturated, 0);
#endif
}

/* ---- square roots ---------------------------------------------------------- */

static void test_sqrt(void **state)
{
    (void)state;
    fc_arith ar = {0};
    ts_rng rng = ts_rng_seed(808u);
    const struct {
        const char *name;
        int frac;
        float hi;
    } cases[] = {{"sqrt UNIT", FC_UNIT_FRAC, 1.99f},
                 {"sqrt LENGTH", FC_LENGTH_FRAC, 2047.0f},
                 {"sqrt RATIO", FC_RATIO_FRAC, 127.0f},
                 {"sqrt RATIO small", FC_RATIO_FRAC, 1.0e-3f}};
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        ts_check c = ts_check_begin(cases[k].name);
        for (int i = 0; i < 2000; i++) {
            double r;
            const fc_real x = ts_in(ts_uniform(&rng, 0.0f, cases[k].hi), cases[k].frac, &r);
            const double ref = sqrt(r);
            /* fixed: rounded to nearest, 0.5 LSB; float: sqrtf is correctly rounded */
            (void)ts_close(&c, ts_val(fc_sqrt(&ar, x, cases[k].frac), cases[k].frac), ref,
                           ts_tol(cases[k].frac, 0.5 + 1.0e-6, 0.5, ref), "sqrt(%.9g)", r);
        }
        ts_check_end(&c);
    }
    /* perfect squares are exact */
    TS_ASSERT_REAL_EQ(fc_sqrt(&ar, FC_INT(4, LENGTH), FC_LENGTH_FRAC), FC_INT(2, LENGTH));
    TS_ASSERT_REAL_EQ(fc_sqrt(&ar, FC_C(0.25f, UNIT), FC_UNIT_FRAC), FC_C(0.5f, UNIT));
    TS_ASSERT_REAL_EQ(fc_sqrt(&ar, FC_INT(1, UNIT), FC_UNIT_FRAC), FC_INT(1, UNIT));
    /* x <= 0 gives 0 */
    TS_ASSERT_REAL_EQ(fc_sqrt(&ar, FC_INT(0, UNIT), FC_UNIT_FRAC), FC_INT(0, UNIT));
    TS_ASSERT_REAL_EQ(fc_sqrt(&ar, FC_C(-0.5f, UNIT), FC_UNIT_FRAC), FC_INT(0, UNIT));
    TS_ASSERT_REAL_EQ(fc_sqrt(&ar, FC_REAL_MIN, FC_UNIT_FRAC), FC_INT(0, UNIT));
    /* the largest input */
    TS_ASSERT_CLOSE(ts_val(fc_sqrt(&ar, FC_REAL_MAX, FC_UNIT_FRAC), FC_UNIT_FRAC),
                    sqrt(ts_val(FC_REAL_MAX, FC_UNIT_FRAC)),
                    ts_tol(FC_UNIT_FRAC, 0.5, 0.5, sqrt(ts_val(FC_REAL_MAX, FC_UNIT_FRAC))));
    assert_int_equal(ar.saturated, 0);
}

/* fixed: fc_sqrt and fc_hypot3 (32-bit halves, Heron estimate made exact by
 * steps) give bit for bit what the digit-by-digit square root of the 64-bit
 * value rounded to nearest gives (the definition, below in uint64_t), for
 * every frac and every bit length of the operand; float: nothing to check. */
#if FC_NUMERIC_FIXED
static uint32_t reference_sqrt_rounded(uint64_t v)
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
#endif

static void test_sqrt_hypot3_exact(void **state)
{
    (void)state;
#if FC_NUMERIC_FIXED
    ts_rng rng = ts_rng_seed(4242u);
    fc_arith ar = {0};
    unsigned cases = 0u;
    for (int frac = 0; frac <= 31; frac++) {
        for (int bits = 0; bits <= 31; bits++) {
            for (int i = 0; i < 64; i++) {
                fc_real x = (fc_real)(ts_rand_u32(&rng) >> (32 - (bits > 0 ? bits : 1)));
                if (i == 0) {
                    x = bits == 31 ? INT32_MAX : (fc_real)(((uint32_t)1u << bits) - 1u);
                } else if (i == 1) {
                    x = (fc_real)((uint32_t)1u << (bits < 31 ? bits : 30));
                }
                if (x <= 0) {
                    continue;
                }
                const uint32_t want = reference_sqrt_rounded((uint64_t)x << frac);
                assert_int_equal((uint32_t)fc_sqrt(&ar, x, frac), want);
                cases++;
            }
        }
    }
    for (int i = 0; i < 200000; i++) {
        const int shift_a = (int)(ts_rand_u32(&rng) % 32u), shift_b = (int)(ts_rand_u32(&rng) % 32u);
        const int shift_c = (int)(ts_rand_u32(&rng) % 32u);
        fc_real a = (fc_real)ts_rand_u32(&rng) >> shift_a;
        fc_real b = (fc_real)ts_rand_u32(&rng) >> shift_b;
        fc_real c = (fc_real)ts_rand_u32(&rng) >> shift_c;
        if (i < 27) {
            const fc_real corner[3] = {INT32_MIN, INT32_MAX, 0};
            a = corner[i % 3];
            b = corner[(i / 3) % 3];
            c = corner[i / 9];
        }
        const uint64_t sum = (uint64_t)((int64_t)a * a) + (uint64_t)((int64_t)b * b) + (uint64_t)((int64_t)c * c);
        const uint32_t root = reference_sqrt_rounded(sum);
        fc_arith h = {0};
        const fc_real got = fc_hypot3(&h, a, b, c);
        if (root > (uint32_t)INT32_MAX) {
            assert_int_equal(got, FC_REAL_MAX);
            assert_int_equal(h.saturated, 1);
        } else {
            assert_int_equal((uint32_t)got, root);
            assert_int_equal(h.saturated, 0);
        }
        cases++;
    }
    assert_int_equal(ar.saturated, 0);
    print_message("sqrt/hypot3 exact: %u cases\n", cases);
#else
    skip(); /* fixed backend only */
#endif
}

/* fixed: fc_sqrt_unit16 (the 16-bit root of x in Q32 digit by digit,
 * scalar.c's sqrt16_digits; on the ATmega the same rounds in assembly) is
 * the root of x 4 rounded to Q16, for x of every bit length and a sweep of
 * [0, 1]; a host model of the assembly's rounds over all 2^32 radicands
 * found no error. */
#if FC_NUMERIC_FIXED
static void assert_sqrt_unit16_exact(fc_arith *ar, uint32_t x)
{
    const fc_real got = fc_sqrt_unit16(ar, (fc_real)x);
    assert_int_equal((uint32_t)got, reference_sqrt_rounded((uint64_t)x << 2) << (FC_UNIT_FRAC - 16));
}
#endif

static void test_sqrt_unit16_exact(void **state)
{
    (void)state;
#if FC_NUMERIC_FIXED
    ts_rng rng = ts_rng_seed(1616u);
    fc_arith ar = {0};
    unsigned cases = 0u;
    for (uint32_t x = 0u; x <= (uint32_t)FC_INT(1, UNIT); x += 4099u) {
        assert_sqrt_unit16_exact(&ar, x);
        cases++;
    }
    for (int bits = 1; bits <= 30; bits++) {
        /* the least and the largest x of this bit length, then random ones */
        assert_sqrt_unit16_exact(&ar, (uint32_t)1u << (bits - 1));
        assert_sqrt_unit16_exact(&ar, ((uint32_t)1u << bits) - 1u);
        for (int i = 0; i < 2000; i++) {
            assert_sqrt_unit16_exact(&ar, ts_rand_u32(&rng) >> (32 - bits));
        }
        cases += 2002u;
    }
    assert_int_equal(ar.saturated, 0);
    print_message("sqrt_unit16 exact: %u cases\n", cases);
#else
    skip(); /* fixed backend only */
#endif
}

/* fixed: fc_rsqrt (products in 32-bit halves, a table in program memory on
 * the ATmega) gives bit for bit the values of its int64_t form (below), for
 * every pair of formats in use and inputs of every bit length. The reference's
 * table is computed here from its definition, so the test also checks the
 * literal table of scalar.c. */
#if FC_NUMERIC_FIXED
static int32_t reference_rsqrt(fc_arith *ar, int32_t x, int frac_in, int frac_out)
{
    if (x <= 0) {
        ar->saturated = 1u;
        return FC_REAL_MAX;
    }
    int len = 0;
    for (uint32_t v = (uint32_t)x; v != 0u; v >>= 1) {
        len++;
    }
    int s = 30 - len;
    if (((30 - s - frac_in) & 1) != 0) {
        s -= 1;
    }
    const int32_t m_q30 = s >= 0 ? (int32_t)((uint32_t)x << s) : (int32_t)((uint32_t)x >> (-s));
    const int j = (30 - s - frac_in) / 2;
    /* the first guess: the chord between the knots round(2^14 / sqrt(1/4 + k/32))
     * that enclose m, in Q30, taken to Q29 */
    const int k = (int)((uint32_t)m_q30 >> 25) - 8;
    const int64_t knot_start = llround(16384.0 / sqrt(0.25 + k / 32.0));
    const int64_t knot_end = llround(16384.0 / sqrt(0.25 + (k + 1) / 32.0));
    const int64_t position_q16 = ((uint32_t)m_q30 >> 9) & 0xFFFFu;
    int32_t y = (int32_t)(((knot_start << 16) - (knot_start - knot_end) * position_q16) >> 1);
    for (int i = 0; i < 2; i++) {
        const int64_t y2_q30 = ((int64_t)y * y) >> 28;
        const int64_t my2_q30 = ((int64_t)m_q30 * y2_q30) >> 30;
        const int64_t corr_q30 = ((int64_t)3 << 30) - my2_q30;
        y = (int32_t)(((int64_t)y * corr_q30) >> 31);
    }
    return fc_fx_saturate(ar, fc_fx_rescale(ar, (int64_t)y, 29 + j - frac_out));
}
#endif

/* fixed: the Newton iterate of fc_rsqrt (Q29, read out with frac_in 30 and
 * frac_out 29, where x is m itself) against 1/sqrt(m) over every 997th m of
 * [1/4, 1) in Q30 and the segment ends of its table. The bound, in Q29 LSB:
 *   roundings of the last step: m y^2 is floored twice in Q30, so
 *     y (3 - m y^2) / 2 comes out up to y 2^-30 <= 1 LSB (+ 2^-29) high, and
 *     the final floor takes up to 1 LSB off: 1 LSB (+ 2^-29) either way;
 *   Newton's truncation: y = (1 + e) / sqrt(m) steps to
 *     (1 - 3 e^2 / 2 - e^3 / 2) / sqrt(m), 3 e1^2 2^29 LSB for 1/sqrt(m) <= 2;
 *   e0, the chord's error: the sag h^2 max|f''| / 8 of f = m^-1/2 over a
 *     segment h = 1/32 wide, (3/4) 4^(5/2) / 8192 = 2.9e-3 on f >= 1.88 in
 *     the first (the worst relative), plus the knots' rounding (2^-15 on 1.88):
 *     below 1.6e-3;
 *   e1 after the first step: 1.5 e0^2 (1 + e0 / 3) plus its roundings
 *     (1 LSB on y >= 1: below 2^-28). */
static void test_rsqrt_q29_accuracy(void **state)
{
    (void)state;
#if FC_NUMERIC_FIXED
    double worst = 0.0;
    unsigned cases = 0u;
    for (uint32_t m = (uint32_t)1u << 28; m < ((uint32_t)1u << 30); m += 997u) {
        for (uint32_t edge = 0u; edge < 2u; edge++) {
            /* and the last value of m's table segment (2^25 wide) */
            const uint32_t x = edge == 0u ? m : (m | (((uint32_t)1u << 25) - 1u));
            fc_arith ar = {0};
            const fc_real y = fc_rsqrt(&ar, (fc_real)x, 30, 29);
            const double exact = 536870912.0 / sqrt((double)x / 1073741824.0);
            const double error = fabs((double)y - exact);
            worst = error > worst ? error : worst;
            assert_int_equal(ar.saturated, 0);
            cases++;
        }
    }
    const double e0 = 1.6e-3;
    const double e1 = 1.5 * e0 * e0 * (1.0 + e0 / 3.0) + ldexp(1.0, -28);
    const double bound = 1.0 + ldexp(1.0, -29) + 3.0 * e1 * e1 * ldexp(1.0, 29);
    print_message("rsqrt Q29: %u values, worst %.4f LSB (bound %.4f)\n", cases, worst, bound);
    assert_true(worst <= bound);
#else
    skip(); /* fixed backend only */
#endif
}

/* The 16-bit values (fixed): fc_narrow16 rounds to nearest (half up, as
 * fc_convert) and saturates at +-INT16_MAX with the flag, at the shifts the
 * library uses (16 by the high half, 15 and 14 by fc_convert); fc_widen16 is
 * exact; fc_dot4_16 is the exact sum rounded once; fc_round16 is
 * fc_narrow16 wherever that does not saturate. Float: the same values. */
#if FC_NUMERIC_FIXED
static void narrow16_check(int32_t x, int shift, fc_real16 got, uint8_t got_sat)
{
    const double exact = floor((double)x / ldexp(1.0, shift) + 0.5);
    const double want = exact > 32767.0 ? 32767.0 : (exact < -32767.0 ? -32767.0 : exact);
    if ((double)got != want || got_sat != (exact > 32767.0 || exact < -32767.0 ? 1 : 0)) {
        print_error("narrow16 of %ld by %d: %d (flag %u), expected %.0f\n", (long)x, shift, (int)got,
                    (unsigned)got_sat, want);
        fail();
    }
}
#endif

static void test_real16(void **state)
{
    (void)state;
#if FC_NUMERIC_FIXED
    ts_rng rng = ts_rng_seed(1616u);
    for (int i = 0; i < 200000; i++) {
        int32_t x = (int32_t)ts_rand_u32(&rng) >> (ts_rand_u32(&rng) % 24u);
        if (i < 8) {
            const int32_t edges[8] = {INT32_MAX, -INT32_MAX, 0x7FFF7FFF, 0x7FFF8000, -0x7FFF8000, -0x7FFF8001,
                                      0x8000, -0x8000};
            x = edges[i];
        }
        fc_arith a16 = {0}, a15 = {0}, a14 = {0};
        const fc_real16 n16 = fc_narrow16(&a16, x, 30, 14);
        const fc_real16 n15 = fc_narrow16(&a15, x, 28, 13);
        const fc_real16 n14 = fc_narrow16(&a14, x, 28, 14);
        narrow16_check(x, 16, n16, a16.saturated);
        narrow16_check(x, 15, n15, a15.saturated);
        narrow16_check(x, 14, n14, a14.saturated);
        /* fc_round16: fc_narrow16's value wherever that does not saturate
         * (its precondition), at the shifts the library uses */
        const int shifts[5] = {16, 15, 14, 8, 0};
        for (int k = 0; k < 5; k++) {
            fc_arith sat = {0};
            const fc_real16 n = fc_narrow16(&sat, x, 14 + shifts[k], 14);
            if (sat.saturated == 0u && fc_round16(x, 14 + shifts[k], 14) != n) {
                print_error("round16 of %ld by %d: %d, expected %d\n", (long)x, shifts[k],
                            (int)fc_round16(x, 14 + shifts[k], 14), (int)n);
                fail();
            }
        }
        const fc_real16 h = (fc_real16)(x % 32768);
        assert_int_equal(fc_widen16(h, 14, 30), (int32_t)h * 65536);
        assert_int_equal(fc_widen16(h, 12, 28), (int32_t)h * 65536);
    }
    /* a quaternion product's component: four products summed exactly, one rounding */
    fc_arith ar = {0};
    const fc_real16 r = fc_dot4_16(&ar, 16384, 16384, -8192, 8191, 3, 5, -1, 16383, 28, 14);
    const double exact = (16384.0 * 16384.0 - 8192.0 * 8191.0 + 15.0 - 16383.0) / 16384.0;
    assert_true((double)r == floor(exact + 0.5));
    assert_int_equal(ar.saturated, 0);
#else
    fc_arith ar = {0};
    assert_true(fc_narrow16(&ar, 0.75f, FC_UNIT_FRAC, FC_UNIT16_FRAC) == 0.75f);
    assert_true(fc_round16(0.75f, FC_UNIT_FRAC, FC_UNIT16_FRAC) == 0.75f);
    assert_true(fc_widen16(0.75f, FC_UNIT16_FRAC, FC_UNIT_FRAC) == 0.75f);
    assert_true(fc_dot4_16(&ar, 0.5f, 0.5f, 0.25f, 1.0f, 0.0f, 0.0f, 0.0f, 0.0f, 28, 14) == 0.5f);
#endif
}

/* The bound of fc_unit2_16's c and s, in UNIT16 LSB (2^-14), with |c|, |s| <= 1.
 * Fixed (scalar.c: c = a y 2^k, y = 1/sqrt(m) by a chord and one Newton step):
 *   0.5 for the rounding of a y 2^k to UNIT16 (the floor of k = -1 is 2^-29);
 *   2^14 times the relative error of y in (1, 2], the sum of
 *     Newton's truncation 1.5 e0^2 (1 + e0 / 3), e0 the first guess's error:
 *       the chord's 1.6e-3 (test_rsqrt_q29_accuracy) and its floor to Q15
 *       (2^-15 on y0 >= 1), below 1.64e-3;
 *     m rounded to Q16 (2^-17): d = 1 - m y0^2 moves by y0^2 2^-17
 *       <= (1 + e0)^2 4 2^-17, y by y0 / 2 of that: (1 + e0)^3 2^-16;
 *     m y0 rounded to Q15 (2^-16), times y0 <= 2 (1 + e0): (1 + e0)^2 2^-16;
 *     d floored to Q22: (1 + e0) 2^-23;
 *     y rounded to Q15 (or held at 2 - 2^-15 for 1/sqrt(m) = 2): 2^-16.
 * Float (u = 2^-24, each rounding within u relative): n_sq = a^2 + b^2 in
 * three roundings of positive terms (2 u), 1/sqrtf(n_sq) half that and two
 * of its own, the product a (1/N) one more: four roundings in all, within
 * gamma_4 = 4 u / (1 - 4 u) of the ratio. */
static double unit2_16_bound_lsb(void)
{
#if FC_NUMERIC_FIXED
    const double e0 = 1.64e-3;
    const double relative = 1.5 * e0 * e0 * (1.0 + e0 / 3.0) +
                            ldexp(pow(1.0 + e0, 3.0) + pow(1.0 + e0, 2.0) + 1.0, -16) + ldexp(1.0 + e0, -23);
    return 0.5 + ldexp(1.0, -15) + ldexp(relative, 14);
#else
    const double u = ldexp(1.0, -24);
    return ldexp(4.0 * u / (1.0 - 4.0 * u), 14);
#endif
}

/* fc_unit2_16: (c, s) against (a, b) / hypot(a, b) in double, over a grid of
 * UNIT16 pairs from the threshold 2^-14 of n_sq to components of 1.001 (n_sq
 * to 2: the k = -1 branch), and every pair of small ones near the threshold. */
static void unit2_check(int a, int b, double *worst)
{
    const fc_real16 a16 = FC_NUMERIC_FIXED ? (fc_real16)a : (fc_real16)((double)a / 16384.0);
    const fc_real16 b16 = FC_NUMERIC_FIXED ? (fc_real16)b : (fc_real16)((double)b / 16384.0);
    const fc_real n_sq = fc_dot2_16(a16, a16, b16, b16);
    fc_arith ar = {0};
    fc_real16 c = 0, s = 0;
    fc_unit2_16(&ar, a16, b16, n_sq, &c, &s);
    const double n = sqrt((double)a * a + (double)b * b);
    /* the results in UNIT16 LSB in both backends */
    const double got_c = FC_NUMERIC_FIXED ? (double)c : (double)c * 16384.0;
    const double got_s = FC_NUMERIC_FIXED ? (double)s : (double)s * 16384.0;
    const double err = fmax(fabs(got_c - 16384.0 * a / n), fabs(got_s - 16384.0 * b / n));
    *worst = err > *worst ? err : *worst;
    assert_int_equal(ar.saturated, 0);
}

static void test_unit2_16(void **state)
{
    (void)state;
    double worst = 0.0;
    unsigned cases = 0u;
    for (int a = -16400; a <= 16400; a += 37) {
        for (int b = -16400; b <= 16400; b += 41) {
            if ((double)a * a + (double)b * b >= 16384.0) {
                unit2_check(a, b, &worst);
                cases++;
            }
        }
    }
    for (int a = -160; a <= 160; a++) {
        for (int b = -160; b <= 160; b++) {
            if ((double)a * a + (double)b * b >= 16384.0) {
                unit2_check(a, b, &worst);
                cases++;
            }
        }
    }
    print_message("unit2_16: %u pairs, worst %.4f UNIT16 LSB (bound %.4f)\n", cases, worst, unit2_16_bound_lsb());
    assert_true(worst <= unit2_16_bound_lsb());
}

/* fc_direction16: the direction of v within, in UNIT16 LSB,
 *   fixed: half an LSB of the output's rounding, the mantissas' roundings
 *     (|M - v 2^-e| <= sqrt(3)/2 moves M / |M| by at most 2 |M - u| /
 *     (|M| + |u|) <= (sqrt(3)/2) 2^-14 (the inner-product Dunkl-Williams
 *     bound), and y's relative error (unit2_16_bound_lsb's, without its
 *     half LSB), plus 2^-15 for the k = -1 floor;
 *   float: five roundings (the squares' sum, the root, the reciprocal, the
 *     product) within gamma_5;
 * and the length within 1.37 2^e raw LSB (fixed: sqrt(3)/2 of the
 * mantissas and 1/32 + 1/64 of the Heron step, times 2^e, and half a raw
 * LSB of the final rounding for e < 4; at least 1 LSB for e <= 0), float
 * gamma_4 of itself; a whole length (axis-aligned and 3-4-5 vectors) exact
 * in fixed. */
static double direction16_bound_lsb(void)
{
#if FC_NUMERIC_FIXED
    return unit2_16_bound_lsb() + sqrt(3.0) / 2.0 * (1.0 + ldexp(1.0, -13));
#else
    const double u = ldexp(1.0, -24);
    return ldexp(5.0 * u / (1.0 - 5.0 * u), 14);
#endif
}

static void direction16_check(double x, double y, double z, double *worst_lsb, double *worst_length)
{
    fc_arith ar = {0};
    fc_real16 d[3] = {0, 0, 0};
    fc_real length = 0;
#if FC_NUMERIC_FIXED
    const fc_real v[3] = {(fc_real)x, (fc_real)y, (fc_real)z};
#else
    const fc_real v[3] = {(fc_real)x, (fc_real)y, (fc_real)z};
#endif
    const double vx = (double)v[0], vy = (double)v[1], vz = (double)v[2];
    const double n = sqrt(vx * vx + vy * vy + vz * vz);
    const bool ok = fc_direction16(&ar, v[0], v[1], v[2], d, &length);
    assert_true(ok);
    assert_int_equal(ar.saturated, 0);
    const double want[3] = {vx / n, vy / n, vz / n};
    for (int i = 0; i < 3; i++) {
        const double got = FC_NUMERIC_FIXED ? (double)d[i] : (double)d[i] * 16384.0;
        const double err = fabs(got - 16384.0 * want[i]);
        *worst_lsb = err > *worst_lsb ? err : *worst_lsb;
    }
#if FC_NUMERIC_FIXED
    /* in raw LSB, relative to its bound */
    const int e = (int)floor(log2(fmax(fmax(fabs(vx), fabs(vy)), fabs(vz)))) + 1 - 15;
    const double bound = fmax(1.37 * ldexp(1.0, e), 1.0);
    const double err_length = fabs((double)length - n) / bound;
#else
    const double u = ldexp(1.0, -24);
    const double err_length = fabs((double)length - n) / (n * 4.0 * u / (1.0 - 4.0 * u));
#endif
    *worst_length = err_length > *worst_length ? err_length : *worst_length;
}

static void test_direction16(void **state)
{
    (void)state;
    ts_rng rng = ts_rng_seed(4242u);
    double worst = 0.0, worst_length = 0.0;
    unsigned cases = 0u;
    for (int i = 0; i < 200000; i++) {
        /* components of random sign and size, the largest from 1 raw LSB (fixed)
         * to the format's edge / sqrt 3 */
        const int top = 1 + (int)(ts_rand_u32(&rng) % 30u);
        double c[3];
        for (int k = 0; k < 3; k++) {
            const double mag = (double)(ts_rand_u32(&rng) >> (32 - top));
            c[k] = (ts_rand_u32(&rng) & 1u) != 0u ? -mag : mag;
        }
        if (c[0] == 0.0 && c[1] == 0.0 && c[2] == 0.0) {
            continue;
        }
#if !FC_NUMERIC_FIXED
        for (int k = 0; k < 3; k++) {
            c[k] = ldexp(c[k], -top); /* floats of any scale */
        }
#endif
        direction16_check(c[0], c[1], c[2], &worst, &worst_length);
        cases++;
    }
    /* the zero vector: no direction */
    fc_arith ar = {0};
    fc_real16 d[3] = {1, 1, 1};
    fc_real length = 1;
    assert_false(fc_direction16(&ar, 0, 0, 0, d, &length));
    assert_true(d[0] == 0 && d[1] == 0 && d[2] == 0 && length == 0);
#if FC_NUMERIC_FIXED
    /* whole lengths exact, at every scale */
    for (int j = 0; j <= 27; j++) {
        const fc_real unit = (fc_real)1 << j;
        assert_true(fc_direction16(&ar, 0, 0, unit, d, &length));
        assert_true(length == unit && d[2] == FC_INT16(1, UNIT16));
        assert_true(fc_direction16(&ar, 3 * unit, -4 * unit, 0, d, &length));
        assert_true(length == 5 * unit);
    }
    assert_int_equal(ar.saturated, 0);
#endif
    print_message("direction16: %u vectors, direction worst %.4f UNIT16 LSB (bound %.4f), length worst %.3f of "
                  "its bound\n",
                  cases, worst, direction16_bound_lsb(), worst_length);
    assert_true(worst <= direction16_bound_lsb());
    assert_true(worst_length <= 1.0);
}

#if FC_NUMERIC_FIXED
/* Case i of a 32 x 16-bit product test: first every pair of the formats'
 * edges, then random operands of every size and sign (never INT32_MIN or
 * INT16_MIN, outside the symmetric range). */
static void product_operands(ts_rng *rng, int i, int32_t *a_out, int16_t *b_out)
{
    static const int32_t edges32[] = {0, 1, -1, INT32_MAX, -INT32_MAX, 0x7fff0000, -0x7fff0000, 0xffff, -0xffff,
                                      0x10000};
    static const int16_t edges16[] = {0, 1, -1, INT16_MAX, -INT16_MAX, 0x4000, -0x4000};
    const size_t n32 = sizeof edges32 / sizeof edges32[0], n16 = sizeof edges16 / sizeof edges16[0];
    int32_t a = (int32_t)(ts_rand_u32(rng) >> (ts_rand_u32(rng) % 32u));
    a = (ts_rand_u32(rng) & 1u) != 0u ? -a : a;
    int16_t b = (int16_t)(ts_rand_u32(rng) >> (16u + ts_rand_u32(rng) % 16u));
    b = (int16_t)((ts_rand_u32(rng) & 1u) != 0u ? -b : b);
    if ((size_t)i < n32 * n16) {
        a = edges32[(size_t)i / n16];
        b = edges16[(size_t)i % n16];
    }
    *a_out = a == INT32_MIN ? -INT32_MAX : a;
    *b_out = b == INT16_MIN ? -INT16_MAX : b;
}
#endif

/* fc_mul_by16 against the exact product rounded to nearest (half up, as
 * every fixed product) and saturated at +-INT32_MAX with the flag, from
 * 64-bit integers: every shift 1..31, operands of every size and the
 * formats' edges. Float: fc_mul itself, skipped. */
static void test_mul_by16_exact(void **state)
{
    (void)state;
#if FC_NUMERIC_FIXED
    ts_rng rng = ts_rng_seed(1616u);
    unsigned cases = 0u, saturated = 0u;
    for (int shift = 1; shift <= 31; shift++) {
        for (int i = 0; i < 20000; i++) {
            int32_t a;
            int16_t b;
            product_operands(&rng, i, &a, &b);
            const int64_t exact = ((int64_t)a * b + ((int64_t)1 << (shift - 1))) >> shift; /* floor (gcc) */
            const bool over = exact > INT32_MAX || exact < -(int64_t)INT32_MAX;
            const int32_t want = over ? (exact > 0 ? INT32_MAX : -INT32_MAX) : (int32_t)exact;
            fc_arith ar = {0};
            assert_int_equal(fc_mul_by16(&ar, a, b, shift), want);
            assert_int_equal(ar.saturated, over ? 1u : 0u);
            saturated += over ? 1u : 0u;
            cases++;
        }
    }
    print_message("mul_by16 exact: %u cases, %u saturated\n", cases, saturated);
    assert_true(saturated > 0u);
#else
    skip(); /* fixed backend only */
#endif
}

/* fc_gain_of: the mantissa the finest that holds the value (|m| in
 * [2^14, 2^15), or 0), rounded to nearest, and fc_gain_to_real back; values
 * of 15 significant bits or fewer come back exactly. Float: the value itself. */
static void test_gain_of(void **state)
{
    (void)state;
    ts_rng rng = ts_rng_seed(2828u);
    const int fracs[] = {10, 14, 16, 20, 22, 24, 26, 30};
    for (size_t f = 0; f < sizeof fracs / sizeof fracs[0]; f++) {
        const int frac = fracs[f];
        for (int i = 0; i < 20000; i++) {
            int32_t v = (int32_t)(ts_rand_u32(&rng) >> (1u + ts_rand_u32(&rng) % 31u));
            v = (ts_rand_u32(&rng) & 1u) != 0u ? -v : v;
            const int32_t edges[] = {0, 1, -1, INT32_MAX, -INT32_MAX, 0x7fff8000, -0x7fff8000, 0x7fff, 0x8000, 0xffff};
            if ((size_t)i < sizeof edges / sizeof edges[0]) {
                v = edges[i];
            }
#if FC_NUMERIC_FIXED
            const fc_gain g = fc_gain_of(v, frac);
            const int32_t size = g.mantissa < 0 ? -g.mantissa : g.mantissa;
            if (v == 0) {
                assert_int_equal(g.mantissa, 0);
                continue;
            }
            assert_true(size >= 0x4000 && size <= 0x7fff);
            /* |m 2^-g.frac - v 2^-frac| <= half the mantissa's LSB */
            const double exact = ldexp((double)v, -frac);
            const double error = fabs(ldexp((double)g.mantissa, -g.frac) - exact);
            assert_true(error <= ldexp(0.5, -g.frac));
            fc_arith ar = {0u};
            const fc_real back = fc_gain_to_real(&ar, g, frac);
            if (ar.saturated != 0u) {
                /* a value within half a mantissa LSB of 2^31, rounded to it */
                assert_true(size == 0x4000 && fabs(exact) >= ldexp(1.0, 31 - frac) - ldexp(0.5, -g.frac));
                assert_int_equal(back, v > 0 ? INT32_MAX : -INT32_MAX);
                continue;
            }
            const int32_t size_v = v < 0 ? -v : v;
            if (size_v < 0x8000 || (size_v & ((1 << (32 - __builtin_clz((uint32_t)size_v) - 15)) - 1)) == 0) {
                assert_int_equal(back, v); /* 15 significant bits: exact */
            } else {
                assert_true(fabs(ldexp((double)back, -frac) - exact) <= ldexp(0.5, -g.frac) + ldexp(0.5, -frac));
            }
#else
            const fc_real value = ldexpf((float)v, -frac);
            fc_arith ar = {0u};
            assert_true(fc_gain_to_real(&ar, fc_gain_of(value, frac), frac) == value);
#endif
        }
    }
}

/* fc_mul_gain against the exact product x m / 2^shift rounded to nearest
 * (half up) and saturated at +-INT32_MAX with the flag, from 64-bit integers,
 * for shift = the gain's frac + FC_GAIN_SHIFT from -4 to 50; and against
 * fc_mul of the gain written in 32 bits, for gains of 15 significant bits.
 * Float: the float product. */
static void test_mul_gain_exact(void **state)
{
    (void)state;
#if FC_NUMERIC_FIXED
    ts_rng rng = ts_rng_seed(4646u);
    unsigned cases = 0u, saturated = 0u;
    for (int shift = -4; shift <= 50; shift++) {
        for (int i = 0; i < 4000; i++) {
            int32_t x;
            int16_t m;
            product_operands(&rng, i, &x, &m);
            const int64_t product = (int64_t)x * m;
            const int64_t exact = shift <= 0 ? product * ((int64_t)1 << -shift)
                                             : (product + ((int64_t)1 << (shift - 1))) >> shift; /* floor (gcc) */
            const bool over = exact > INT32_MAX || exact < -(int64_t)INT32_MAX;
            const int32_t want = over ? (exact > 0 ? INT32_MAX : -INT32_MAX) : (int32_t)exact;
            /* the gain m 2^-frac with frac = shift - FC_GAIN_SHIFT(LENGTH, VEL) */
            const fc_gain g = {m, (int8_t)(shift - FC_GAIN_SHIFT(LENGTH, VEL))};
            fc_arith ar = {0};
            assert_int_equal(fc_mul_gain(&ar, x, g, FC_GAIN_SHIFT(LENGTH, VEL)), want);
            assert_int_equal(ar.saturated, over ? 1u : 0u);
            saturated += over ? 1u : 0u;
            cases++;
        }
    }
    print_message("mul_gain exact: %u cases, %u saturated\n", cases, saturated);
    assert_true(saturated > 0u);
#endif
    /* a gain of 15 significant bits or fewer: the value of fc_mul */
    const fc_real gains[] = {FC_C(2.0f, GAIN), FC_C(0.75f, GAIN), FC_C(-3.5f, GAIN), FC_C(1.0f / 1024.0f, GAIN),
                             FC_INT(1000, GAIN)};
    ts_rng values = ts_rng_seed(4647u);
    for (size_t k = 0; k < sizeof gains / sizeof gains[0]; k++) {
        const fc_gain g = fc_gain_of(gains[k], FC_GAIN_FRAC);
        for (int i = 0; i < 2000; i++) {
            const float e = (float)ts_rand_u32(&values) / 4294967296.0f * 200.0f - 100.0f;
            const fc_real e_m = fc_from_float(e, FC_LENGTH_FRAC);
            fc_arith a = {0u}, b = {0u};
            const fc_real by_gain = fc_mul_gain(&a, e_m, g, FC_GAIN_SHIFT(LENGTH, VEL));
            const fc_real by_mul = fc_mul(&b, gains[k], e_m, FC_SHIFT(GAIN, LENGTH, VEL));
            assert_true(by_gain == by_mul);
            assert_int_equal(a.saturated, b.saturated);
        }
    }
}

static void test_rsqrt_exact(void **state)
{
    (void)state;
#if FC_NUMERIC_FIXED
    ts_rng rng = ts_rng_seed(5150u);
    const int fracs[] = {16, 20, 22, 24, 28, 30};
    unsigned cases = 0u;
    for (size_t a = 0; a < sizeof fracs / sizeof fracs[0]; a++) {
        for (size_t b = 0; b < sizeof fracs / sizeof fracs[0]; b++) {
            for (int i = 0; i < 20000; i++) {
                fc_real x = (fc_real)(ts_rand_u32(&rng) >> (1 + (ts_rand_u32(&rng) % 31u)));
                if (i < 31) {
                    x = (fc_real)((uint32_t)1u << i);
                } else if (i < 62) {
                    x = i == 61 ? INT32_MAX : (fc_real)(((uint32_t)1u << (i - 31)) - 1u);
                }
                fc_arith got_ar = {0}, want_ar = {0};
                const fc_real got = fc_rsqrt(&got_ar, x, fracs[a], fracs[b]);
                const fc_real want = reference_rsqrt(&want_ar, x, fracs[a], fracs[b]);
                assert_int_equal(got, want);
                assert_int_equal(got_ar.saturated, want_ar.saturated);
                cases++;
            }
        }
    }
    print_message("rsqrt exact: %u cases\n", cases);
#else
    skip(); /* fixed backend only */
#endif
}

/* fixed: fc_div for the shifts 0..31 (restoring division in 32-bit halves
 * on the ATmega, a 64-bit division elsewhere) against the exact quotient
 * num 2^shift / den in 128-bit integers: rounded to nearest, ties away from
 * zero (scalar.c: the dividend pushed half a divisor away from zero), beyond
 * +-FC_REAL_MAX saturated with the flag; den = 0 saturates toward the sign of
 * num (0 / 0 is 0) with the flag (scalar.h). Float: skipped. */
#if FC_NUMERIC_FIXED
__extension__ typedef unsigned __int128 ts_u128;

static int32_t reference_div(fc_arith *ar, int32_t num, int32_t den, int shift)
{
    if (den == 0) {
        ar->saturated = 1u;
        return num > 0 ? FC_REAL_MAX : (num < 0 ? FC_REAL_MIN : 0);
    }
    const bool negative = (num < 0) != (den < 0);
    const ts_u128 n = (ts_u128)(num < 0 ? -(int64_t)num : (int64_t)num) << shift;
    const ts_u128 d = (ts_u128)(den < 0 ? -(int64_t)den : (int64_t)den);
    ts_u128 q = n / d;
    if (2u * (n % d) >= d) {
        q++; /* the remainder is half the divisor or more: away from zero */
    }
    if (q > (ts_u128)FC_REAL_MAX) {
        ar->saturated = 1u;
        return negative ? FC_REAL_MIN : FC_REAL_MAX;
    }
    return negative ? -(int32_t)q : (int32_t)q;
}
#endif

static void test_div_exact(void **state)
{
    (void)state;
#if FC_NUMERIC_FIXED
    ts_rng rng = ts_rng_seed(6060u);
    const int32_t edges[] = {INT32_MIN, INT32_MIN + 1, INT32_MAX, INT32_MAX - 1, 0, 1, -1, 2, -2, 3, -3,
                             (int32_t)0x40000000, -(int32_t)0x40000000, 46341, -46341};
    const int n_edges = (int)(sizeof edges / sizeof edges[0]);
    unsigned cases = 0u;
    for (int shift = 0; shift < 32; shift++) {
        for (int i = 0; i < 20000; i++) {
            int32_t num = (int32_t)ts_rand_u32(&rng) >> (ts_rand_u32(&rng) % 32u);
            int32_t den = (int32_t)ts_rand_u32(&rng) >> (ts_rand_u32(&rng) % 32u);
            if (i < n_edges * n_edges) {
                num = edges[i % n_edges];
                den = edges[i / n_edges];
            }
            fc_arith got_ar = {0}, want_ar = {0};
            const fc_real got = fc_div(&got_ar, num, den, shift);
            const fc_real want = reference_div(&want_ar, num, den, shift);
            assert_int_equal(got, want);
            assert_int_equal(got_ar.saturated, want_ar.saturated);
            cases++;
        }
    }
    print_message("div exact: %u cases\n", cases);
#else
    skip(); /* fixed backend only */
#endif
}

static void test_hypot3(void **state)
{
    (void)state;
    fc_arith ar = {0};
    ts_rng rng = ts_rng_seed(909u);
    const struct {
        const char *name;
        int frac;
        float hi;
    } cases[] = {{"hypot3 UNIT", FC_UNIT_FRAC, 1.1f},
                 {"hypot3 LENGTH", FC_LENGTH_FRAC, 1150.0f},
                 {"hypot3 ACCEL", FC_ACCEL_FRAC, 290.0f},
                 {"hypot3 RATE tiny", FC_RATE_FRAC, 1.0e-4f}};
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        ts_check c = ts_check_begin(cases[k].name);
        for (int i = 0; i < 2000; i++) {
            double ra, rb, rc;
            const float hi = cases[k].hi;
            const fc_real a = ts_in(ts_uniform(&rng, -hi, hi), cases[k].frac, &ra);
            const fc_real b = ts_in(ts_uniform(&rng, -hi, hi), cases[k].frac, &rb);
            const fc_real cc = ts_in(ts_uniform(&rng, -hi, hi), cases[k].frac, &rc);
            const double ref = sqrt(ra * ra + rb * rb + rc * rc);
            /* fixed: the 64-bit sum is exact, the root rounded: 0.5 LSB;
             * float: sqrtf(a a + b b + c c), 2 ulps */
            (void)ts_close(&c, ts_val(fc_hypot3(&ar, a, b, cc), cases[k].frac), ref,
                           ts_tol(cases[k].frac, 0.5 + 1.0e-6, 2.0, ref), "(%.9g, %.9g, %.9g)", ra, rb, rc);
        }
        ts_check_end(&c);
    }
    /* 1500 m, -1000 m, 500 m: the squares overflow int32 many times over */
    double ra, rb, rc;
    const fc_real a = ts_in(1500.0f, FC_LENGTH_FRAC, &ra);
    const fc_real b = ts_in(-1000.0f, FC_LENGTH_FRAC, &rb);
    const fc_real cc = ts_in(500.0f, FC_LENGTH_FRAC, &rc);
    TS_ASSERT_CLOSE(ts_val(fc_hypot3(&ar, a, b, cc), FC_LENGTH_FRAC), sqrt(ra * ra + rb * rb + rc * rc),
                    ts_tol(FC_LENGTH_FRAC, 0.5, 2.0, 1870.8));
    /* Pythagorean triple, exact */
    TS_ASSERT_REAL_EQ(fc_hypot3(&ar, FC_INT(2, LENGTH), FC_INT(-3, LENGTH), FC_INT(6, LENGTH)),
                      FC_INT(7, LENGTH));
    TS_ASSERT_REAL_EQ(fc_hypot3(&ar, 0, 0, 0), FC_INT(0, LENGTH));
    assert_int_equal(ar.saturated, 0);
#if FC_NUMERIC_FIXED
    /* a length out of the format saturates with the flag */
    TS_ASSERT_REAL_EQ(fc_hypot3(&ar, FC_REAL_MAX, FC_REAL_MIN, FC_REAL_MAX), INT32_MAX);
    assert_int_equal(ar.saturated, 1);
#endif
}

static void test_rsqrt(void **state)
{
    (void)state;
    fc_arith ar = {0};
    ts_rng rng = ts_rng_seed(1010u);
    const struct {
        const char *name;
        int frac_in, frac_out;
        float lo, hi;
    } cases[] = {
        {"rsqrt UNIT->RATIO", FC_UNIT_FRAC, FC_RATIO_FRAC, 1.0e-4f, 1.99f},
        {"rsqrt RATIO->RATIO", FC_RATIO_FRAC, FC_RATIO_FRAC, 0.01f, 127.0f},
        {"rsqrt LENGTH->UNIT", FC_LENGTH_FRAC, FC_UNIT_FRAC, 0.3f, 2047.0f},
        {"rsqrt UNIT->UNIT", FC_UNIT_FRAC, FC_UNIT_FRAC, 0.26f, 1.99f},
        {"rsqrt TIME->GAIN", FC_TIME_FRAC, FC_GAIN_FRAC, 0.001f, 30000.0f},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        ts_check c = ts_check_begin(cases[k].name);
        for (int i = 0; i < 2000; i++) {
            double r;
            /* log-uniform inputs */
            const float t = ts_uniform(&rng, 0.0f, 1.0f);
            const float x_f = cases[k].lo * powf(cases[k].hi / cases[k].lo, t);
            const fc_real x = ts_in(x_f, cases[k].frac_in, &r);
            const double ref = 1.0 / sqrt(r);
            /* fixed: 1 LSB of frac_out + 2^-28 relative (Q29 iterate);
             * float: two roundings, 2 ulps */
            const double tol = ts_tol(cases[k].frac_out, 1.0, 2.0, ref) + ts_fixed_rel(ref, 28);
            (void)ts_close(&c, ts_val(fc_rsqrt(&ar, x, cases[k].frac_in, cases[k].frac_out), cases[k].frac_out),
                           ref, tol, "rsqrt(%.9g)", r);
        }
        ts_check_end(&c);
    }
    TS_ASSERT_CLOSE(ts_val(fc_rsqrt(&ar, FC_C(0.25f, UNIT), FC_UNIT_FRAC, FC_RATIO_FRAC), FC_RATIO_FRAC), 2.0,
                    ts_tol(FC_RATIO_FRAC, 1.0, 1.0, 2.0));
    TS_ASSERT_CLOSE(ts_val(fc_rsqrt(&ar, FC_INT(1, UNIT), FC_UNIT_FRAC, FC_UNIT_FRAC), FC_UNIT_FRAC), 1.0,
                    ts_tol(FC_UNIT_FRAC, 1.0, 1.0, 1.0) + ts_fixed_rel(1.0, 28));
    assert_int_equal(ar.saturated, 0);
    /* x <= 0 saturates with the flag, both backends */
    TS_ASSERT_REAL_EQ(fc_rsqrt(&ar, FC_INT(0, UNIT), FC_UNIT_FRAC, FC_RATIO_FRAC), FC_REAL_MAX);
    assert_int_equal(ar.saturated, 1);
    ar.saturated = 0;
    TS_ASSERT_REAL_EQ(fc_rsqrt(&ar, FC_C(-0.5f, UNIT), FC_UNIT_FRAC, FC_RATIO_FRAC), FC_REAL_MAX);
    assert_int_equal(ar.saturated, 1);
#if !FC_NUMERIC_FIXED
    ar.saturated = 0;
    TS_ASSERT_REAL_EQ(fc_rsqrt(&ar, NAN, FC_UNIT_FRAC, FC_RATIO_FRAC), FC_REAL_MAX);
    assert_int_equal(ar.saturated, 1);
#else
    ar.saturated = 0;
    /* 1/sqrt(1 LSB of UNIT) = 2^15 does not fit RATIO */
    TS_ASSERT_REAL_EQ(fc_rsqrt(&ar, 1, FC_UNIT_FRAC, FC_RATIO_FRAC), FC_REAL_MAX);
    assert_int_equal(ar.saturated, 1);
#endif
}

/* ---- trigonometry ----------------------------------------------------------- */

/* sin and cos of angles in [lo, hi] against the double functions of the
 * quantised angle. fixed: 5 UNIT LSB ("a few", scalar.h); float: 2 ulps. */
static void check_sin_cos(const char *what, float lo, float hi, int steps)
{
    fc_arith ar = {0};
    ts_check c = ts_check_begin(what);
    for (int i = 0; i <= steps; i++) {
        double r;
        const fc_real a = ts_in(lo + (hi - lo) * (float)i / (float)steps, FC_ANGLE_FRAC, &r);
        const double s = sin(r), co = cos(r);
        (void)ts_close(&c, ts_val(fc_sin(&ar, a), FC_UNIT_FRAC), s, ts_tol(FC_UNIT_FRAC, 5.0, 2.0, s),
                       "sin(%.9g)", r);
        (void)ts_close(&c, ts_val(fc_cos(&ar, a), FC_UNIT_FRAC), co, ts_tol(FC_UNIT_FRAC, 5.0, 2.0, co),
                       "cos(%.9g)", r);
    }
    ts_check_end(&c);
    assert_int_equal(ar.saturated, 0);
}

static void test_sin_cos_octant(void **state)
{
    (void)state;
    check_sin_cos("sin/cos |a| <= pi/4", -0.785f, 0.785f, 4000);
    fc_arith ar = {0};
    TS_ASSERT_REAL_EQ(fc_sin(&ar, FC_INT(0, ANGLE)), FC_INT(0, UNIT));
    TS_ASSERT_REAL_EQ(fc_cos(&ar, FC_INT(0, ANGLE)), FC_INT(1, UNIT));
    assert_int_equal(ar.saturated, 0);
}

static void test_sin_cos_full_turn(void **state)
{
    (void)state;
    check_sin_cos("sin/cos |a| <= pi", -3.14159f, 3.14159f, 8000);
    /* the quarter turns */
    fc_arith ar = {0};
    double r;
    const fc_real q = ts_in(1.5707964f, FC_ANGLE_FRAC, &r);
    TS_ASSERT_CLOSE(ts_val(fc_sin(&ar, q), FC_UNIT_FRAC), sin(r), ts_tol(FC_UNIT_FRAC, 5.0, 2.0, 1.0));
    TS_ASSERT_CLOSE(ts_val(fc_cos(&ar, q), FC_UNIT_FRAC), cos(r), ts_tol(FC_UNIT_FRAC, 5.0, 2.0, cos(r)));
    const fc_real h = ts_in(-3.1415927f, FC_ANGLE_FRAC, &r);
    TS_ASSERT_CLOSE(ts_val(fc_sin(&ar, h), FC_UNIT_FRAC), sin(r), ts_tol(FC_UNIT_FRAC, 5.0, 2.0, sin(r)));
    TS_ASSERT_CLOSE(ts_val(fc_cos(&ar, h), FC_UNIT_FRAC), cos(r), ts_tol(FC_UNIT_FRAC, 5.0, 2.0, 1.0));
}

static void test_sin_cos_wrap(void **state)
{
    (void)state;
    /* beyond +-pi up to the edge of ANGLE ([-8, 8) rad) */
    check_sin_cos("sin/cos pi < |a| < 8", 3.1416f, 7.99f, 4000);
    check_sin_cos("sin/cos -8 < a < -pi", -7.99f, -3.1416f, 4000);
}

/* fc_sincos gives fc_sin's and fc_cos's values, bit for bit, over all of ANGLE. */
static void test_sincos_is_sin_and_cos(void **state)
{
    (void)state;
    for (int i = 0; i <= 16000; i++) {
        const fc_real a = fc_from_float(-7.99f + 15.98f * (float)i / 16000.0f, FC_ANGLE_FRAC);
        fc_arith pair = {0}, single = {0};
        fc_real s, c;
        fc_sincos(&pair, a, &s, &c);
        TS_ASSERT_REAL_EQ(s, fc_sin(&single, a));
        TS_ASSERT_REAL_EQ(c, fc_cos(&single, a));
        assert_int_equal(pair.saturated, single.saturated);
    }
}

/* atan2 around circles of several radii and formats: every quadrant.
 * fixed: 4 ANGLE LSB; float: 2 ulps. */
static void test_atan2_quadrants(void **state)
{
    (void)state;
    fc_arith ar = {0};
    const struct {
        const char *name;
        int frac;
        float radius;
    } cases[] = {{"atan2 UNIT r=1", FC_UNIT_FRAC, 1.0f},
                 {"atan2 LENGTH r=1500", FC_LENGTH_FRAC, 1500.0f},
                 {"atan2 ACCEL r=0.01", FC_ACCEL_FRAC, 0.01f},
                 {"atan2 UNIT r=1.9", FC_UNIT_FRAC, 1.9f}};
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        ts_check c = ts_check_begin(cases[k].name);
        const int steps = 3600;
        for (int i = 0; i < steps; i++) {
            const double t = -TS_PI + 2.0 * TS_PI * ((double)i + 0.37) / steps;
            double ry, rx;
            const fc_real y = ts_in((float)((double)cases[k].radius * sin(t)), cases[k].frac, &ry);
            const fc_real x = ts_in((float)((double)cases[k].radius * cos(t)), cases[k].frac, &rx);
            const double ref = atan2(ry, rx);
            (void)ts_close(&c, ts_val(fc_atan2(&ar, y, x), FC_ANGLE_FRAC), ref,
                           ts_tol(FC_ANGLE_FRAC, 4.0, 2.0, ref), "atan2(%.9g, %.9g)", ry, rx);
        }
        ts_check_end(&c);
    }
    assert_int_equal(ar.saturated, 0);
}

static void test_atan2_axes_and_origin(void **state)
{
    (void)state;
    fc_arith ar = {0};
    const fc_real one = FC_INT(1, UNIT), zero = FC_INT(0, UNIT);
    /* atan2(0, 0) = 0 by definition of the library */
    TS_ASSERT_REAL_EQ(fc_atan2(&ar, zero, zero), FC_INT(0, ANGLE));
    /* on the axes */
    TS_ASSERT_REAL_EQ(fc_atan2(&ar, zero, one), FC_INT(0, ANGLE));
    const struct {
        fc_real y, x;
        double ref;
    } cases[] = {
        {zero, FC_INT(-1, UNIT), TS_PI},
        {one, zero, TS_PI / 2.0},
        {FC_INT(-1, UNIT), zero, -TS_PI / 2.0},
        {FC_C(1.0e-6f, UNIT), zero, TS_PI / 2.0},
        {FC_C(-1.0e-6f, UNIT), zero, -TS_PI / 2.0},
        {zero, FC_C(-1.0e-6f, UNIT), TS_PI},
        {FC_REAL_MAX, zero, TS_PI / 2.0},
        {zero, FC_REAL_MIN, TS_PI},
    };
    ts_check c = ts_check_begin("atan2 on the axes");
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        (void)ts_close(&c, ts_val(fc_atan2(&ar, cases[k].y, cases[k].x), FC_ANGLE_FRAC), cases[k].ref,
                       ts_tol(FC_ANGLE_FRAC, 4.0, 2.0, cases[k].ref), "case %zu", k);
    }
    ts_check_end(&c);
    /* the range is [-pi, pi]: atan2(0, -1) is +pi, not -pi */
    assert_true(ts_val(fc_atan2(&ar, zero, FC_INT(-1, UNIT)), FC_ANGLE_FRAC) > 3.0);
    assert_int_equal(ar.saturated, 0);
}

/* On the diagonals |y| = |x| (a 45-degree direction, e.g. the half angle of
 * a quarter-turn quaternion): exact ratio 1. */
static void test_atan2_diagonals(void **state)
{
    (void)state;
    fc_arith ar = {0};
    const fc_real one = FC_INT(1, UNIT), mone = FC_INT(-1, UNIT);
    const struct {
        fc_real y, x;
        double ref;
    } cases[] = {
        {one, one, TS_PI / 4.0},
        {one, mone, 3.0 * TS_PI / 4.0},
        {mone, mone, -3.0 * TS_PI / 4.0},
        {mone, one, -TS_PI / 4.0},
        {FC_C(0.70710677f, UNIT), FC_C(0.70710677f, UNIT), TS_PI / 4.0},
        {FC_REAL_MAX, FC_REAL_MAX, TS_PI / 4.0},
        {FC_REAL_MIN, FC_REAL_MIN, -3.0 * TS_PI / 4.0},
    };
    ts_check c = ts_check_begin("atan2 on the diagonals");
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        (void)ts_close(&c, ts_val(fc_atan2(&ar, cases[k].y, cases[k].x), FC_ANGLE_FRAC), cases[k].ref,
                       ts_tol(FC_ANGLE_FRAC, 4.0, 2.0, cases[k].ref), "case %zu", k);
    }
    ts_check_end(&c);
    assert_int_equal(ar.saturated, 0);
}

/* asin on [-1, 1]: fixed 4 ANGLE LSB plus 4 UNIT LSB times the condition
 * 1/sqrt(1 - x^2) (an error in x is amplified by that much); float 2 ulps. */
static void test_asin(void **state)
{
    (void)state;
    fc_arith ar = {0};
    ts_check c = ts_check_begin("asin on [-1, 1]");
    const int steps = 4000;
    for (int i = 0; i <= steps; i++) {
        double r;
        const fc_real x = ts_in(-1.0f + 2.0f * (float)i / (float)steps, FC_UNIT_FRAC, &r);
        const double ref = asin(r);
        const double cond = fmin(1.0 / sqrt(fmax(1.0 - r * r, 1.0e-18)), 1.0e5);
        const double tol = ts_tol(FC_ANGLE_FRAC, 4.0, 2.0, ref) + ts_tol(FC_UNIT_FRAC, 4.0 * cond, 0.0, 0.0);
        (void)ts_close(&c, ts_val(fc_asin(&ar, x), FC_ANGLE_FRAC), ref, tol, "asin(%.9g)", r);
    }
    ts_check_end(&c);
    assert_int_equal(ar.saturated, 0);
    /* exact ends and clamping beyond +-1 */
    ts_check e = ts_check_begin("asin at and beyond +-1");
    const double half_pi_tol = ts_tol(FC_ANGLE_FRAC, 4.0, 2.0, TS_PI / 2.0);
    (void)ts_close(&e, ts_val(fc_asin(&ar, FC_INT(1, UNIT)), FC_ANGLE_FRAC), TS_PI / 2.0, half_pi_tol, "1");
    (void)ts_close(&e, ts_val(fc_asin(&ar, FC_INT(-1, UNIT)), FC_ANGLE_FRAC), -TS_PI / 2.0, half_pi_tol, "-1");
    (void)ts_close(&e, ts_val(fc_asin(&ar, FC_C(1.5f, UNIT)), FC_ANGLE_FRAC), TS_PI / 2.0, half_pi_tol, "1.5");
    (void)ts_close(&e, ts_val(fc_asin(&ar, FC_C(-1.9f, UNIT)), FC_ANGLE_FRAC), -TS_PI / 2.0, half_pi_tol,
                   "-1.9");
    (void)ts_close(&e, ts_val(fc_asin(&ar, FC_REAL_MAX), FC_ANGLE_FRAC), TS_PI / 2.0, half_pi_tol, "max");
    (void)ts_close(&e, ts_val(fc_asin(&ar, FC_REAL_MIN), FC_ANGLE_FRAC), -TS_PI / 2.0, half_pi_tol, "min");
    ts_check_end(&e);
    TS_ASSERT_REAL_EQ(fc_asin(&ar, FC_INT(0, UNIT)), FC_INT(0, ANGLE));
    assert_int_equal(ar.saturated, 0);
}

static void test_exp_neg(void **state)
{
    (void)state;
    fc_arith ar = {0};
    ts_check c = ts_check_begin("exp(-x) on [0, 25]");
    const int steps = 5000;
    for (int i = 0; i <= steps; i++) {
        double r;
        const fc_real x = ts_in(25.0f * (float)i / (float)steps, FC_RATIO_FRAC, &r);
        const double ref = exp(-r);
        /* fixed: 2 UNIT LSB; float: 2 ulps */
        (void)ts_close(&c, ts_val(fc_exp_neg(&ar, x), FC_UNIT_FRAC), ref, ts_tol(FC_UNIT_FRAC, 2.0, 2.0, ref),
                       "exp(-%.9g)", r);
    }
    ts_check_end(&c);
    /* the filter-pole use: dt / tau = 0.002 / 0.05 */
    double r;
    const fc_real x = ts_in(0.04f, FC_RATIO_FRAC, &r);
    TS_ASSERT_CLOSE(ts_val(fc_exp_neg(&ar, x), FC_UNIT_FRAC), exp(-r), ts_tol(FC_UNIT_FRAC, 2.0, 2.0, 1.0));
    /* x <= 0 gives exactly 1 */
    TS_ASSERT_REAL_EQ(fc_exp_neg(&ar, FC_INT(0, RATIO)), FC_INT(1, UNIT));
    TS_ASSERT_REAL_EQ(fc_exp_neg(&ar, FC_INT(-3, RATIO)), FC_INT(1, UNIT));
    /* far in the tail: 0 within an LSB */
    TS_ASSERT_CLOSE(ts_val(fc_exp_neg(&ar, FC_INT(40, RATIO)), FC_UNIT_FRAC), exp(-40.0),
                    ts_tol(FC_UNIT_FRAC, 1.0, 2.0, exp(-40.0)));
    TS_ASSERT_CLOSE(ts_val(fc_exp_neg(&ar, FC_INT(120, RATIO)), FC_UNIT_FRAC), 0.0,
                    ts_tol(FC_UNIT_FRAC, 1.0, 2.0, 1.0e-45));
    assert_int_equal(ar.saturated, 0);
}

static void test_pow_unit(void **state)
{
    (void)state;
    fc_arith ar = {0};
    const float exponents[] = {0.1f, 0.5f, 1.0f, 1.5f, 2.0f, 2.3f, 3.0f, 5.0f};
    for (size_t k = 0; k < sizeof exponents / sizeof exponents[0]; k++) {
        double re;
        const fc_real e = ts_in(exponents[k], FC_RATIO_FRAC, &re);
        ts_check c = ts_check_begin("x^e on (0, 1)");
        const int steps = 2000;
        for (int i = 1; i < steps; i++) {
            double rx;
            /* denser near 0, where the logarithm is large */
            const float t = (float)i / (float)steps;
            const fc_real x = ts_in(t * t, FC_UNIT_FRAC, &rx);
            const double ref = pow(rx, re);
            const double tol = ts_tol(FC_UNIT_FRAC, 4.0, 2.0, ref) +
                               ts_tol(FC_RATIO_FRAC, 2.0 * (1.0 + re) * ref, 0.0, 0.0);
            (void)ts_close(&c, ts_val(fc_pow_unit(&ar, x, e), FC_UNIT_FRAC), ref, tol, "%.9g^%.9g", rx, re);
        }
        ts_check_end(&c);
    }
    assert_int_equal(ar.saturated, 0);
    /* exact cases: x <= 0 gives 0, x >= 1 gives 1 */
    const fc_real two = FC_C(2.0f, RATIO);
    TS_ASSERT_REAL_EQ(fc_pow_unit(&ar, FC_INT(0, UNIT), two), FC_INT(0, UNIT));
    TS_ASSERT_REAL_EQ(fc_pow_unit(&ar, FC_C(-0.5f, UNIT), two), FC_INT(0, UNIT));
    TS_ASSERT_REAL_EQ(fc_pow_unit(&ar, FC_INT(1, UNIT), two), FC_INT(1, UNIT));
    TS_ASSERT_REAL_EQ(fc_pow_unit(&ar, FC_C(1.5f, UNIT), two), FC_INT(1, UNIT));
    /* 0.5^2 = 0.25, 0.25^0.5 = 0.5 */
    TS_ASSERT_CLOSE(ts_val(fc_pow_unit(&ar, FC_C(0.5f, UNIT), two), FC_UNIT_FRAC), 0.25,
                    ts_tol(FC_UNIT_FRAC, 4.0, 2.0, 0.25) + ts_tol(FC_RATIO_FRAC, 2.0 * 3.0 * 0.25, 0.0, 0.0));
    TS_ASSERT_CLOSE(ts_val(fc_pow_unit(&ar, FC_C(0.25f, UNIT), FC_C(0.5f, RATIO)), FC_UNIT_FRAC), 0.5,
                    ts_tol(FC_UNIT_FRAC, 4.0, 2.0, 0.5) + ts_tol(FC_RATIO_FRAC, 2.0 * 1.5 * 0.5, 0.0, 0.0));
    assert_int_equal(ar.saturated, 0);
}

/* ---- backend-neutral helpers ---------------------------------------------- */

static void test_min_max_clamp(void **state)
{
    (void)state;
    const fc_real a = FC_C(-0.75f, UNIT), b = FC_C(0.25f, UNIT), lo = FC_C(-0.5f, UNIT), hi = FC_C(0.5f, UNIT);
    TS_ASSERT_REAL_EQ(fc_min(a, b), a);
    TS_ASSERT_REAL_EQ(fc_min(b, a), a);
    TS_ASSERT_REAL_EQ(fc_max(a, b), b);
    TS_ASSERT_REAL_EQ(fc_max(b, a), b);
    TS_ASSERT_REAL_EQ(fc_min(b, b), b);
    TS_ASSERT_REAL_EQ(fc_max(FC_REAL_MIN, FC_REAL_MAX), FC_REAL_MAX);
    TS_ASSERT_REAL_EQ(fc_min(FC_REAL_MIN, FC_REAL_MAX), FC_REAL_MIN);
    TS_ASSERT_REAL_EQ(fc_clamp(a, lo, hi), lo);
    TS_ASSERT_REAL_EQ(fc_clamp(b, lo, hi), b);
    TS_ASSERT_REAL_EQ(fc_clamp(FC_C(0.75f, UNIT), lo, hi), hi);
    TS_ASSERT_REAL_EQ(fc_clamp(lo, lo, hi), lo);
    TS_ASSERT_REAL_EQ(fc_clamp(hi, lo, hi), hi);
    TS_ASSERT_REAL_EQ(fc_clamp(FC_REAL_MAX, lo, hi), hi);
    TS_ASSERT_REAL_EQ(fc_clamp(FC_REAL_MIN, lo, hi), lo);
    TS_ASSERT_REAL_EQ(fc_clamp(FC_INT(-1500, LENGTH), FC_INT(-1000, LENGTH), FC_INT(1000, LENGTH)),
                      FC_INT(-1000, LENGTH));
}

static void test_sign_unit(void **state)
{
    (void)state;
    TS_ASSERT_REAL_EQ(fc_sign_unit(FC_C(0.3f, RATIO)), FC_INT(1, UNIT));
    TS_ASSERT_REAL_EQ(fc_sign_unit(FC_INT(1500, LENGTH)), FC_INT(1, UNIT));
    TS_ASSERT_REAL_EQ(fc_sign_unit(FC_C(-0.3f, RATIO)), FC_INT(-1, UNIT));
    TS_ASSERT_REAL_EQ(fc_sign_unit(FC_REAL_MIN), FC_INT(-1, UNIT));
    TS_ASSERT_REAL_EQ(fc_sign_unit(FC_REAL_MAX), FC_INT(1, UNIT));
    TS_ASSERT_REAL_EQ(fc_sign_unit(FC_INT(0, UNIT)), FC_INT(0, UNIT));
    /* the smallest non-zero values */
#if FC_NUMERIC_FIXED
    TS_ASSERT_REAL_EQ(fc_sign_unit(1), FC_INT(1, UNIT));
    TS_ASSERT_REAL_EQ(fc_sign_unit(-1), FC_INT(-1, UNIT));
#else
    TS_ASSERT_REAL_EQ(fc_sign_unit(FLT_MIN), 1.0f);
    TS_ASSERT_REAL_EQ(fc_sign_unit(-FLT_MIN), -1.0f);
    TS_ASSERT_REAL_EQ(fc_sign_unit(-0.0f), 0.0f);
#endif
    /* the values are UNIT ones and zero */
    TS_ASSERT_CLOSE(ts_val(fc_sign_unit(FC_C(-2.5f, LENGTH)), FC_UNIT_FRAC), -1.0, 0.0);
    TS_ASSERT_CLOSE(ts_val(fc_sign_unit(FC_C(2.5f, LENGTH)), FC_UNIT_FRAC), 1.0, 0.0);
}

static void test_is_finite(void **state)
{
    (void)state;
    assert_true(fc_is_finite(FC_INT(0, UNIT)));
    assert_true(fc_is_finite(FC_REAL_MAX));
    assert_true(fc_is_finite(FC_REAL_MIN));
    assert_true(fc_is_finite(FC_C(-1.5f, UNIT)));
#if !FC_NUMERIC_FIXED
    assert_false(fc_is_finite(NAN));
    assert_false(fc_is_finite(-NAN));
    assert_false(fc_is_finite(INFINITY));
    assert_false(fc_is_finite(-INFINITY));
    assert_true(fc_is_finite(FLT_MIN / 4.0f)); /* subnormal */
#else
    /* every int32 is finite */
    assert_true(fc_is_finite(INT32_MIN));
#endif
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_shift_macros),
        cmocka_unit_test(test_int_and_c_constants),
        cmocka_unit_test(test_pi_constants),
        cmocka_unit_test(test_from_float_to_float),
        cmocka_unit_test(test_add_sub_neg_abs),
        cmocka_unit_test(test_add_sub_neg_saturation),
        cmocka_unit_test(test_mul_values),
        cmocka_unit_test(test_mul_rounds_to_nearest),
        cmocka_unit_test(test_mul_saturation),
#if FC_NUMERIC_FIXED
        cmocka_unit_test(test_fx_saturate_and_rescale),
#endif
        cmocka_unit_test(test_div_values),
        cmocka_unit_test(test_div_rounds_to_nearest),
        cmocka_unit_test(test_div_saturation),
        cmocka_unit_test(test_div_by_zero),
        cmocka_unit_test(test_convert),
        cmocka_unit_test(test_dot2_dot3_dot4),
        cmocka_unit_test(test_dot_wide_intermediate),
        cmocka_unit_test(test_mul_dot_wide_shifts),
        cmocka_unit_test(test_acc),
        cmocka_unit_test(test_sqrt),
        cmocka_unit_test(test_hypot3),
        cmocka_unit_test(test_sqrt_hypot3_exact),
        cmocka_unit_test(test_sqrt_unit16_exact),
        cmocka_unit_test(test_rsqrt),
        cmocka_unit_test(test_rsqrt_exact),
        cmocka_unit_test(test_rsqrt_q29_accuracy),
        cmocka_unit_test(test_real16),
        cmocka_unit_test(test_unit2_16),
        cmocka_unit_test(test_direction16),
        cmocka_unit_test(test_mul_by16_exact),
        cmocka_unit_test(test_gain_of),
        cmocka_unit_test(test_mul_gain_exact),
        cmocka_unit_test(test_div_exact),
        cmocka_unit_test(test_sin_cos_octant),
        cmocka_unit_test(test_sin_cos_full_turn),
        cmocka_unit_test(test_sin_cos_wrap),
        cmocka_unit_test(test_sincos_is_sin_and_cos),
        cmocka_unit_test(test_atan2_quadrants),
        cmocka_unit_test(test_atan2_axes_and_origin),
        cmocka_unit_test(test_asin),
        cmocka_unit_test(test_exp_neg),
        cmocka_unit_test(test_pow_unit),
        cmocka_unit_test(test_min_max_clamp),
        cmocka_unit_test(test_sign_unit),
        cmocka_unit_test(test_is_finite),
        /* last: in the fixed ASan/UBSan build a signed overflow in these
         * aborts the process, after every other test has reported */
        cmocka_unit_test(test_atan2_diagonals),
        cmocka_unit_test(test_div_saturation_large_shift),
        cmocka_unit_test(test_dot2_full_range_rounding),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
