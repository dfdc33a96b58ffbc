/*
 * test_vec3.c - three-vectors (fc/vec3.h, src/vec3.c).
 *
 * One source for both backends. Tolerances (see test_support.h):
 *   fixed: LSBs of the output's Q-format:
 *          add/sub/neg/convert-up: exact; scale, elementwise, convert-down,
 *          norm: 0.5 LSB (one rounding); dot, cross: 1 LSB (one rounding of
 *          a 64-bit sum); normalize: 1 UNIT LSB + |u_i| 0.6 LSB_in / |v|
 *          (the norm is rounded to the input's format first); clamp_norm:
 *          2 LSB of the vector's format.
 *   float: ulps relative to the reference (0.5 for one rounding, 2n for an
 *          n-term sum relative to the sum of |terms|, 4 for normalize and
 *          clamp_norm).
 */
#include "test_support.h"
#include "fc/vec3.h"

typedef struct dvec {
    double x, y, z;
} dvec;

/* A random vector with components in [-r, r], quantised to frac; *ref gets
 * the quantised values. */
static fc_vec3 rand_vec(ts_rng *rng, float r, int frac, dvec *ref)
{
    fc_vec3 v;
    v.x = ts_in(ts_uniform(rng, -r, r), frac, &ref->x);
    v.y = ts_in(ts_uniform(rng, -r, r), frac, &ref->y);
    v.z = ts_in(ts_uniform(rng, -r, r), frac, &ref->z);
    return v;
}

static fc_vec3 vec_in(float x, float y, float z, int frac, dvec *ref)
{
    return fc_vec3_make(ts_in(x, frac, &ref->x), ts_in(y, frac, &ref->y), ts_in(z, frac, &ref->z));
}

static double dnorm(dvec v)
{
    return sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
}

/* Compares all three components with one tolerance each. */
static void close_vec(ts_check *c, fc_vec3 v, int frac, dvec ref, double tol_x, double tol_y, double tol_z,
                      int i)
{
    (void)ts_close(c, ts_val(v.x, frac), ref.x, tol_x, "#%d x", i);
    (void)ts_close(c, ts_val(v.y, frac), ref.y, tol_y, "#%d y", i);
    (void)ts_close(c, ts_val(v.z, frac), ref.z, tol_z, "#%d z", i);
}

static void assert_vec_eq(fc_vec3 a, fc_vec3 b)
{
    TS_ASSERT_REAL_EQ(a.x, b.x);
    TS_ASSERT_REAL_EQ(a.y, b.y);
    TS_ASSERT_REAL_EQ(a.z, b.z);
}

static void test_make_and_zero(void **state)
{
    (void)state;
    const fc_vec3 v = fc_vec3_make(FC_C(1.5f, LENGTH), FC_C(-2.25f, LENGTH), FC_INT(7, LENGTH));
    TS_ASSERT_REAL_EQ(v.x, FC_C(1.5f, LENGTH));
    TS_ASSERT_REAL_EQ(v.y, FC_C(-2.25f, LENGTH));
    TS_ASSERT_REAL_EQ(v.z, FC_INT(7, LENGTH));
    const fc_vec3 z = fc_vec3_zero();
    TS_ASSERT_CLOSE(ts_val(z.x, FC_LENGTH_FRAC), 0.0, 0.0);
    TS_ASSERT_CLOSE(ts_val(z.y, FC_UNIT_FRAC), 0.0, 0.0);
    TS_ASSERT_CLOSE(ts_val(z.z, FC_ANGLE_FRAC), 0.0, 0.0);
}

static void test_add_sub_neg(void **state)
{
    (void)state;
    fc_arith ar = {0};
    ts_rng rng = ts_rng_seed(11u);
    ts_check c = ts_check_begin("vec3 add/sub/neg LENGTH");
    for (int i = 0; i < 1000; i++) {
        dvec ra, rb;
        const fc_vec3 a = rand_vec(&rng, 1000.0f, FC_LENGTH_FRAC, &ra);
        const fc_vec3 b = rand_vec(&rng, 1000.0f, FC_LENGTH_FRAC, &rb);
        const dvec sum = {ra.x + rb.x, ra.y + rb.y, ra.z + rb.z};
        const dvec dif = {ra.x - rb.x, ra.y - rb.y, ra.z - rb.z};
        const dvec neg = {-ra.x, -ra.y, -ra.z};
        /* fixed: exact; float: one rounding */
        close_vec(&c, fc_vec3_add(&ar, a, b), FC_LENGTH_FRAC, sum, ts_tol(FC_LENGTH_FRAC, 0.0, 0.5, sum.x),
                  ts_tol(FC_LENGTH_FRAC, 0.0, 0.5, sum.y), ts_tol(FC_LENGTH_FRAC, 0.0, 0.5, sum.z), i);
        close_vec(&c, fc_vec3_sub(&ar, a, b), FC_LENGTH_FRAC, dif, ts_tol(FC_LENGTH_FRAC, 0.0, 0.5, dif.x),
                  ts_tol(FC_LENGTH_FRAC, 0.0, 0.5, dif.y), ts_tol(FC_LENGTH_FRAC, 0.0, 0.5, dif.z), i);
        close_vec(&c, fc_vec3_neg(&ar, a), FC_LENGTH_FRAC, neg, 0.0, 0.0, 0.0, i);
        /* a - a and a + (-a) are exactly zero */
        assert_vec_eq(fc_vec3_sub(&ar, a, a), fc_vec3_zero());
        assert_vec_eq(fc_vec3_add(&ar, a, fc_vec3_neg(&ar, a)), fc_vec3_zero());
    }
    ts_check_end(&c);
    assert_int_equal(ar.saturated, 0);
}

static void test_add_sub_neg_saturation(void **state)
{
    (void)state;
    fc_arith ar = {0};
    const fc_vec3 a = fc_vec3_make(FC_INT(2000, LENGTH), FC_INT(1, LENGTH), FC_INT(-2000, LENGTH));
    const fc_vec3 b = fc_vec3_make(FC_INT(100, LENGTH), FC_INT(1, LENGTH), FC_INT(-100, LENGTH));
    const fc_vec3 s = fc_vec3_add(&ar, a, b);
#if FC_NUMERIC_FIXED
    /* each component saturates on its own; the others are exact */
    TS_ASSERT_REAL_EQ(s.x, FC_REAL_MAX);
    TS_ASSERT_REAL_EQ(s.y, FC_INT(2, LENGTH));
    TS_ASSERT_REAL_EQ(s.z, FC_REAL_MIN);
    assert_int_equal(ar.saturated, 1);
    ar.saturated = 0;
    const fc_vec3 d = fc_vec3_sub(&ar, a, fc_vec3_neg(&ar, b));
    TS_ASSERT_REAL_EQ(d.x, FC_REAL_MAX);
    TS_ASSERT_REAL_EQ(d.z, FC_REAL_MIN);
    assert_int_equal(ar.saturated, 1);
    ar.saturated = 0;
    const fc_vec3 n = fc_vec3_neg(&ar, fc_vec3_make(INT32_MIN, 0, 5));
    TS_ASSERT_REAL_EQ(n.x, FC_REAL_MAX);
    TS_ASSERT_REAL_EQ(n.z, -5);
    assert_int_equal(ar.saturated, 1);
#else
    /* float: nothing saturates */
    TS_ASSERT_REAL_EQ(s.x, 2100.0f);
    TS_ASSERT_REAL_EQ(s.z, -2100.0f);
    assert_int_equal(ar.saturated, 0);
#endif
}

static void test_scale(void **state)
{
    (void)state;
    fc_arith ar = {0};
    ts_rng rng = ts_rng_seed(12u);
    const struct {
        const char *name;
        int frac_v, frac_k, frac_out, shift;
        float rv, lo_k, hi_k;
    } cases[] = {
        {"VEL*DT->LENGTH", FC_VEL_FRAC, FC_DT_FRAC, FC_LENGTH_FRAC, FC_SHIFT(VEL, DT, LENGTH), 50.0f, 0.0f, 0.1f},
        {"LENGTH*RATIO->LENGTH", FC_LENGTH_FRAC, FC_RATIO_FRAC, FC_LENGTH_FRAC, FC_SHIFT(LENGTH, RATIO, LENGTH),
         1000.0f, -2.0f, 2.0f},
        {"UNIT*ACCEL->ACCEL", FC_UNIT_FRAC, FC_ACCEL_FRAC, FC_ACCEL_FRAC, FC_SHIFT(UNIT, ACCEL, ACCEL), 1.0f,
         -160.0f, 160.0f},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        ts_check c = ts_check_begin(cases[k].name);
        for (int i = 0; i < 1000; i++) {
            dvec rv;
            double rk;
            const fc_vec3 v = rand_vec(&rng, cases[k].rv, cases[k].frac_v, &rv);
            const fc_real s = ts_in(ts_uniform(&rng, cases[k].lo_k, cases[k].hi_k), cases[k].frac_k, &rk);
            const dvec ref = {rv.x * rk, rv.y * rk, rv.z * rk};
            const int f = cases[k].frac_out;
            close_vec(&c, fc_vec3_scale(&ar, v, s, cases[k].shift), f, ref, ts_tol(f, 0.5, 0.5, ref.x),
                      ts_tol(f, 0.5, 0.5, ref.y), ts_tol(f, 0.5, 0.5, ref.z), i);
        }
        ts_check_end(&c);
    }
    /* scaling by one and by zero */
    const fc_vec3 v = fc_vec3_make(FC_C(1.25f, LENGTH), FC_C(-3.5f, LENGTH), FC_C(100.0f, LENGTH));
    assert_vec_eq(fc_vec3_scale(&ar, v, FC_INT(1, RATIO), FC_SHIFT(LENGTH, RATIO, LENGTH)), v);
    assert_vec_eq(fc_vec3_scale(&ar, v, FC_INT(0, RATIO), FC_SHIFT(LENGTH, RATIO, LENGTH)), fc_vec3_zero());
    assert_int_equal(ar.saturated, 0);
#if FC_NUMERIC_FIXED
    /* 1000 m * 3 is out of LENGTH */
    const fc_vec3 big = fc_vec3_scale(&ar, fc_vec3_make(FC_INT(1000, LENGTH), FC_INT(-1000, LENGTH), 0),
                                      FC_INT(3, RATIO), FC_SHIFT(LENGTH, RATIO, LENGTH));
    TS_ASSERT_REAL_EQ(big.x, FC_REAL_MAX);
    TS_ASSERT_REAL_EQ(big.y, FC_REAL_MIN);
    TS_ASSERT_REAL_EQ(big.z, 0);
    assert_int_equal(ar.saturated, 1);
#endif
}

static void test_mul_elementwise(void **state)
{
    (void)state;
    fc_arith ar = {0};
    ts_rng rng = ts_rng_seed(13u);
    ts_check c = ts_check_begin("diag(INERTIA) RATE -> MOMENT");
    const int f = FC_MOMENT_FRAC;
    for (int i = 0; i < 1000; i++) {
        dvec rj, rw;
        fc_vec3 j;
        j.x = ts_in(ts_uniform(&rng, 1.0e-5f, 3.0e-5f), FC_INERTIA_FRAC, &rj.x);
        j.y = ts_in(ts_uniform(&rng, 1.0e-5f, 3.0e-5f), FC_INERTIA_FRAC, &rj.y);
        j.z = ts_in(ts_uniform(&rng, 2.0e-5f, 5.0e-5f), FC_INERTIA_FRAC, &rj.z);
        const fc_vec3 w = rand_vec(&rng, 35.0f, FC_RATE_FRAC, &rw);
        const dvec ref = {rj.x * rw.x, rj.y * rw.y, rj.z * rw.z};
        close_vec(&c, fc_vec3_mul_elementwise(&ar, j, w, FC_SHIFT(INERTIA, RATE, MOMENT)), f, ref,
                  ts_tol(f, 0.5, 0.5, ref.x), ts_tol(f, 0.5, 0.5, ref.y), ts_tol(f, 0.5, 0.5, ref.z), i);
    }
    ts_check_end(&c);
    /* exact small case: (0.5, -2, 4) * (3, 0.25, -0.5) in RATIO */
    const fc_vec3 a = fc_vec3_make(FC_C(0.5f, RATIO), FC_C(-2.0f, RATIO), FC_C(4.0f, RATIO));
    const fc_vec3 b = fc_vec3_make(FC_C(3.0f, RATIO), FC_C(0.25f, RATIO), FC_C(-0.5f, RATIO));
    assert_vec_eq(fc_vec3_mul_elementwise(&ar, a, b, FC_SHIFT(RATIO, RATIO, RATIO)),
                  fc_vec3_make(FC_C(1.5f, RATIO), FC_C(-0.5f, RATIO), FC_C(-2.0f, RATIO)));
    assert_int_equal(ar.saturated, 0);
}

static void test_dot(void **state)
{
    (void)state;
    fc_arith ar = {0};
    ts_rng rng = ts_rng_seed(14u);
    ts_check c = ts_check_begin("dot UNIT.LENGTH -> LENGTH");
    const int f = FC_LENGTH_FRAC;
    for (int i = 0; i < 2000; i++) {
        dvec ru, rp;
        const fc_vec3 u = rand_vec(&rng, 0.577f, FC_UNIT_FRAC, &ru);
        const fc_vec3 p = rand_vec(&rng, 1000.0f, FC_LENGTH_FRAC, &rp);
        const double ref = ru.x * rp.x + ru.y * rp.y + ru.z * rp.z;
        const double mag = fabs(ru.x * rp.x) + fabs(ru.y * rp.y) + fabs(ru.z * rp.z);
        /* fixed: one rounding of the 64-bit sum, 1 LSB; float: 6 ulps of sum |terms| */
        (void)ts_close(&c, ts_val(fc_vec3_dot(&ar, u, p, FC_SHIFT(UNIT, LENGTH, LENGTH)), f), ref,
                       ts_tol(f, 1.0, 6.0, mag), "#%d", i);
    }
    ts_check_end(&c);
    /* orthogonal axes, parallel vectors */
    const fc_vec3 ex = fc_vec3_make(FC_INT(1, UNIT), 0, 0), ey = fc_vec3_make(0, FC_INT(1, UNIT), 0);
    TS_ASSERT_REAL_EQ(fc_vec3_dot(&ar, ex, ey, FC_SHIFT(UNIT, UNIT, UNIT)), FC_INT(0, UNIT));
    TS_ASSERT_REAL_EQ(fc_vec3_dot(&ar, ex, ex, FC_SHIFT(UNIT, UNIT, UNIT)), FC_INT(1, UNIT));
    const fc_vec3 a = fc_vec3_make(FC_INT(3, LENGTH), FC_INT(-4, LENGTH), FC_INT(12, LENGTH));
    /* |a|^2 = 169 m^2, as a LENGTH-format number */
    TS_ASSERT_REAL_EQ(fc_vec3_dot(&ar, a, a, FC_SHIFT(LENGTH, LENGTH, LENGTH)), FC_INT(169, LENGTH));
    assert_int_equal(ar.saturated, 0);
#if FC_NUMERIC_FIXED
    /* (1500 m)^2 * 3 does not fit a LENGTH-format number: saturates */
    const fc_vec3 big = fc_vec3_make(FC_INT(1500, LENGTH), FC_INT(1500, LENGTH), FC_INT(1500, LENGTH));
    TS_ASSERT_REAL_EQ(fc_vec3_dot(&ar, big, big, FC_SHIFT(LENGTH, LENGTH, LENGTH)), FC_REAL_MAX);
    assert_int_equal(ar.saturated, 1);
#endif
}

static void test_cross(void **state)
{
    (void)state;
    fc_arith ar = {0};
    ts_rng rng = ts_rng_seed(15u);
    /* r x F: LENGTH x FORCE -> MOMENT (arms of 0.05 m, thrusts up to 0.2 N) */
    ts_check c = ts_check_begin("cross LENGTH x FORCE -> MOMENT");
    const int f = FC_MOMENT_FRAC;
    for (int i = 0; i < 2000; i++) {
        dvec rr, rf;
        const fc_vec3 r = rand_vec(&rng, 0.05f, FC_LENGTH_FRAC, &rr);
        const fc_vec3 force = rand_vec(&rng, 0.2f, FC_FORCE_FRAC, &rf);
        const dvec ref = {rr.y * rf.z - rr.z * rf.y, rr.z * rf.x - rr.x * rf.z, rr.x * rf.y - rr.y * rf.x};
        const dvec mag = {fabs(rr.y * rf.z) + fabs(rr.z * rf.y), fabs(rr.z * rf.x) + fabs(rr.x * rf.z),
                          fabs(rr.x * rf.y) + fabs(rr.y * rf.x)};
        /* fixed: one rounding per component, 1 LSB; float: 4 ulps of sum |terms| */
        close_vec(&c, fc_vec3_cross(&ar, r, force, FC_SHIFT(LENGTH, FORCE, MOMENT)), f, ref,
                  ts_tol(f, 1.0, 4.0, mag.x), ts_tol(f, 1.0, 4.0, mag.y), ts_tol(f, 1.0, 4.0, mag.z), i);
        /* anti-commutative within one rounding each */
        const fc_vec3 ab = fc_vec3_cross(&ar, r, force, FC_SHIFT(LENGTH, FORCE, MOMENT));
        const fc_vec3 ba = fc_vec3_cross(&ar, force, r, FC_SHIFT(FORCE, LENGTH, MOMENT));
        const dvec nba = {-ts_val(ba.x, f), -ts_val(ba.y, f), -ts_val(ba.z, f)};
        close_vec(&c, ab, f, nba, ts_tol(f, 1.0, 8.0, mag.x), ts_tol(f, 1.0, 8.0, mag.y),
                  ts_tol(f, 1.0, 8.0, mag.z), i);
        /* a x a = 0 exactly */
        assert_vec_eq(fc_vec3_cross(&ar, r, r, FC_SHIFT(LENGTH, LENGTH, LENGTH)), fc_vec3_zero());
    }
    ts_check_end(&c);
    /* the right-handed basis, exactly */
    const fc_real one = FC_INT(1, UNIT);
    const fc_vec3 ex = fc_vec3_make(one, 0, 0), ey = fc_vec3_make(0, one, 0), ez = fc_vec3_make(0, 0, one);
    const int s = FC_SHIFT(UNIT, UNIT, UNIT);
    assert_vec_eq(fc_vec3_cross(&ar, ex, ey, s), ez);
    assert_vec_eq(fc_vec3_cross(&ar, ey, ez, s), ex);
    assert_vec_eq(fc_vec3_cross(&ar, ez, ex, s), ey);
    assert_vec_eq(fc_vec3_cross(&ar, ey, ex, s), fc_vec3_make(0, 0, FC_INT(-1, UNIT)));
    /* (1, 2, 3) x (4, 5, 6) = (-3, 6, -3) in RATIO */
    const fc_vec3 a = fc_vec3_make(FC_INT(1, RATIO), FC_INT(2, RATIO), FC_INT(3, RATIO));
    const fc_vec3 b = fc_vec3_make(FC_INT(4, RATIO), FC_INT(5, RATIO), FC_INT(6, RATIO));
    assert_vec_eq(fc_vec3_cross(&ar, a, b, FC_SHIFT(RATIO, RATIO, RATIO)),
                  fc_vec3_make(FC_INT(-3, RATIO), FC_INT(6, RATIO), FC_INT(-3, RATIO)));
    assert_int_equal(ar.saturated, 0);
}

static void test_norm(void **state)
{
    (void)state;
    fc_arith ar = {0};
    ts_rng rng = ts_rng_seed(16u);
    const struct {
        const char *name;
        int frac;
        float r;
    } cases[] = {{"norm UNIT", FC_UNIT_FRAC, 1.15f},
                 {"norm LENGTH", FC_LENGTH_FRAC, 1150.0f},
                 {"norm RATE", FC_RATE_FRAC, 35.0f},
                 {"norm ANGLE small", FC_ANGLE_FRAC, 1.0e-3f}};
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        ts_check c = ts_check_begin(cases[k].name);
        for (int i = 0; i < 2000; i++) {
            dvec rv;
            const fc_vec3 v = rand_vec(&rng, cases[k].r, cases[k].frac, &rv);
            const double ref = dnorm(rv);
            /* fixed: exact 64-bit sum of squares, rounded root: 0.5 LSB; float: 2 ulps */
            (void)ts_close(&c, ts_val(fc_vec3_norm(&ar, v, cases[k].frac), cases[k].frac), ref,
                           ts_tol(cases[k].frac, 0.5 + 1.0e-6, 2.0, ref), "#%d", i);
        }
        ts_check_end(&c);
    }
    /* LENGTH components of 1500 m: each square is 2.4e18 in Q40, far beyond
     * int32 and a naive int32 sum; the norm 1870.8 m fits LENGTH */
    dvec rv;
    const fc_vec3 big = vec_in(1500.0f, -1000.0f, 500.0f, FC_LENGTH_FRAC, &rv);
    TS_ASSERT_CLOSE(ts_val(fc_vec3_norm(&ar, big, FC_LENGTH_FRAC), FC_LENGTH_FRAC), dnorm(rv),
                    ts_tol(FC_LENGTH_FRAC, 0.5, 2.0, dnorm(rv)));
    const fc_vec3 diag = vec_in(1100.0f, 1100.0f, 1100.0f, FC_LENGTH_FRAC, &rv);
    TS_ASSERT_CLOSE(ts_val(fc_vec3_norm(&ar, diag, FC_LENGTH_FRAC), FC_LENGTH_FRAC), dnorm(rv),
                    ts_tol(FC_LENGTH_FRAC, 0.5, 2.0, dnorm(rv)));
    TS_ASSERT_REAL_EQ(fc_vec3_norm(&ar, fc_vec3_make(FC_INT(2, LENGTH), FC_INT(3, LENGTH), FC_INT(-6, LENGTH)),
                                   FC_LENGTH_FRAC),
                      FC_INT(7, LENGTH));
    TS_ASSERT_REAL_EQ(fc_vec3_norm(&ar, fc_vec3_zero(), FC_LENGTH_FRAC), FC_INT(0, LENGTH));
    assert_int_equal(ar.saturated, 0);
#if FC_NUMERIC_FIXED
    /* a norm beyond the format (2121 m > 2048 m) saturates with the flag */
    TS_ASSERT_REAL_EQ(fc_vec3_norm(&ar, fc_vec3_make(FC_INT(1500, LENGTH), FC_INT(1500, LENGTH), 0),
                                   FC_LENGTH_FRAC),
                      FC_REAL_MAX);
    assert_int_equal(ar.saturated, 1);
#endif
}

static void test_normalize(void **state)
{
    (void)state;
    fc_arith ar = {0};
    ts_rng rng = ts_rng_seed(17u);
    const struct {
        const char *name;
        int frac;
        float r;
    } cases[] = {{"normalize LENGTH", FC_LENGTH_FRAC, 1000.0f},
                 {"normalize LENGTH 0.1 m", FC_LENGTH_FRAC, 0.1f},
                 {"normalize UNIT", FC_UNIT_FRAC, 1.1f},
                 {"normalize ACCEL", FC_ACCEL_FRAC, 30.0f}};
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        ts_check c = ts_check_begin(cases[k].name);
        for (int i = 0; i < 2000; i++) {
            dvec rv;
            const fc_vec3 v = rand_vec(&rng, cases[k].r, cases[k].frac, &rv);
            const double n = dnorm(rv);
            if (n < 0.05 * (double)cases[k].r) {
                continue;
            }
            bool ok = false;
            const fc_vec3 u = fc_vec3_normalize(&ar, v, cases[k].frac, &ok);
            assert_true(ok);
            const dvec ref = {rv.x / n, rv.y / n, rv.z / n};
            /* fixed: 1 UNIT LSB + |u_i| 0.6 LSB_in / |v| (the norm is rounded
             * to the input format before the division); float: 4 ulps */
            const double rel = ts_fixed_rel(0.6 / n, cases[k].frac);
            close_vec(&c, u, FC_UNIT_FRAC, ref, ts_tol(FC_UNIT_FRAC, 1.0, 4.0, 1.0) + fabs(ref.x) * rel,
                      ts_tol(FC_UNIT_FRAC, 1.0, 4.0, 1.0) + fabs(ref.y) * rel,
                      ts_tol(FC_UNIT_FRAC, 1.0, 4.0, 1.0) + fabs(ref.z) * rel, i);
            /* unit length */
            (void)ts_close(&c, ts_val(fc_vec3_norm(&ar, u, FC_UNIT_FRAC), FC_UNIT_FRAC), 1.0,
                           ts_tol(FC_UNIT_FRAC, 2.0, 4.0, 1.0) + rel, "#%d |u|", i);
        }
        ts_check_end(&c);
    }
    /* axis-aligned: exact */
    bool ok = false;
    assert_vec_eq(fc_vec3_normalize(&ar, fc_vec3_make(0, FC_INT(-1500, LENGTH), 0), FC_LENGTH_FRAC, &ok),
                  fc_vec3_make(0, FC_INT(-1, UNIT), 0));
    assert_true(ok);
    /* the smallest non-zero vector still has a direction */
    ok = false;
    const fc_vec3 tiny = fc_vec3_normalize(&ar, fc_vec3_make(0, 0, FC_C(1.0e-6f, LENGTH)), FC_LENGTH_FRAC, &ok);
    assert_true(ok);
    TS_ASSERT_REAL_EQ(tiny.z, FC_INT(1, UNIT));
    assert_int_equal(ar.saturated, 0);
    /* zero vector: zero result and ok = false */
    ok = true;
    assert_vec_eq(fc_vec3_normalize(&ar, fc_vec3_zero(), FC_LENGTH_FRAC, &ok), fc_vec3_zero());
    assert_false(ok);
#if !FC_NUMERIC_FIXED
    /* float: non-finite input is refused the same way */
    ok = true;
    assert_vec_eq(fc_vec3_normalize(&ar, fc_vec3_make(NAN, 1.0f, 0.0f), FC_LENGTH_FRAC, &ok), fc_vec3_zero());
    assert_false(ok);
    ok = true;
    assert_vec_eq(fc_vec3_normalize(&ar, fc_vec3_make(0.0f, -INFINITY, 1.0f), FC_LENGTH_FRAC, &ok),
                  fc_vec3_zero());
    assert_false(ok);
#endif
}

static void test_clamp_norm(void **state)
{
    (void)state;
    fc_arith ar = {0};
    ts_rng rng = ts_rng_seed(18u);
    const struct {
        const char *name;
        int frac;
        float r, limit;
    } cases[] = {{"clamp_norm VEL to 5 m/s", FC_VEL_FRAC, 50.0f, 5.0f},
                 {"clamp_norm FORCE to 0.6 N", FC_FORCE_FRAC, 2.0f, 0.6f},
                 {"clamp_norm LENGTH to 100 m", FC_LENGTH_FRAC, 1100.0f, 100.0f},
                 {"clamp_norm ACCEL to 20", FC_ACCEL_FRAC, 290.0f, 20.0f}};
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        ts_check c = ts_check_begin(cases[k].name);
        const int f = cases[k].frac;
        double lim;
        const fc_real limit = ts_in(cases[k].limit, f, &lim);
        int clamped = 0;
        for (int i = 0; i < 2000; i++) {
            dvec rv;
            const fc_vec3 v = rand_vec(&rng, cases[k].r, f, &rv);
            const double n = dnorm(rv);
            const fc_vec3 out = fc_vec3_clamp_norm(&ar, v, limit, f);
            /* the reporting form: the same vector, and whether it differs from v */
            bool reported = true;
            assert_vec_eq(fc_vec3_clamp_norm_report(&ar, v, limit, f, &reported), out);
            assert_int_equal(reported, out.x != v.x || out.y != v.y || out.z != v.z);
            if (ts_val(fc_vec3_norm(&ar, v, f), f) <= lim) {
                /* inside the limit: unchanged, bit for bit */
                assert_vec_eq(out, v);
                continue;
            }
            clamped++;
            /* direction kept: out = v lim / |v|; fixed 2 LSB; float 4 ulps */
            const double k_ref = lim / n;
            const dvec ref = {rv.x * k_ref, rv.y * k_ref, rv.z * k_ref};
            close_vec(&c, out, f, ref, ts_tol(f, 2.0, 4.0, lim), ts_tol(f, 2.0, 4.0, lim),
                      ts_tol(f, 2.0, 4.0, lim), i);
            /* and the norm equals the limit */
            const dvec ro = {ts_val(out.x, f), ts_val(out.y, f), ts_val(out.z, f)};
            (void)ts_close(&c, dnorm(ro), lim, ts_tol(f, 3.0, 4.0, lim), "#%d |out|", i);
        }
        ts_check_end(&c);
        assert_true(clamped > 100);
    }
    /* a vector exactly at the limit is not touched (and not reported) */
    const fc_vec3 at = fc_vec3_make(FC_INT(3, VEL), FC_INT(4, VEL), 0);
    assert_vec_eq(fc_vec3_clamp_norm(&ar, at, FC_INT(5, VEL), FC_VEL_FRAC), at);
    bool reported = true;
    (void)fc_vec3_clamp_norm_report(&ar, at, FC_INT(5, VEL), FC_VEL_FRAC, &reported);
    assert_false(reported);
    (void)fc_vec3_clamp_norm_report(&ar, at, FC_INT(4, VEL), FC_VEL_FRAC, &reported);
    assert_true(reported);
    /* an axis-aligned vector is clamped exactly */
    assert_vec_eq(fc_vec3_clamp_norm(&ar, fc_vec3_make(0, 0, FC_INT(-40, VEL)), FC_INT(5, VEL), FC_VEL_FRAC),
                  fc_vec3_make(0, 0, FC_INT(-5, VEL)));
    /* a zero limit gives the zero vector */
    assert_vec_eq(fc_vec3_clamp_norm(&ar, at, FC_INT(0, VEL), FC_VEL_FRAC), fc_vec3_zero());
    assert_int_equal(ar.saturated, 0);
}

/* A vector that fits its format but whose norm does not (LENGTH components of
 * 1500 m: |v| = 2121 m > 2048 m) must still come out with norm max_norm and
 * its direction kept. */
static void test_clamp_norm_beyond_format_range(void **state)
{
    (void)state;
    fc_arith ar = {0};
    dvec rv;
    const int f = FC_LENGTH_FRAC;
    const fc_vec3 v = vec_in(1500.0f, 1500.0f, 0.0f, f, &rv);
    const fc_vec3 out = fc_vec3_clamp_norm(&ar, v, FC_INT(100, LENGTH), f);
    const double k_ref = 100.0 / dnorm(rv);
    const dvec ref = {rv.x * k_ref, rv.y * k_ref, rv.z * k_ref};
    ts_check c = ts_check_begin("clamp_norm of (1500, 1500, 0) m to 100 m");
    close_vec(&c, out, f, ref, ts_tol(f, 2.0, 4.0, 100.0), ts_tol(f, 2.0, 4.0, 100.0),
              ts_tol(f, 2.0, 4.0, 100.0), 0);
    ts_check_end(&c);
}

/* fc_norm1_within: "within" only where |x| + |y| + |z| <= limit (so never
 * for a vector longer than the limit), exactly at that bound, for the
 * extremes of the format and a negative limit; float: NaN and infinities fail. */
static void test_norm1_within(void **state)
{
    (void)state;
    ts_rng rng = ts_rng_seed(23u);
    const int f = FC_ACCEL_FRAC;
    for (int i = 0; i < 2000; i++) {
        dvec rv;
        const fc_vec3 v = rand_vec(&rng, 10.0f, f, &rv);
        double lim_ref;
        const fc_real limit = ts_in(ts_uniform(&rng, 0.0f, 25.0f), f, &lim_ref);
        const bool within = fc_norm1_within(v.x, v.y, v.z, limit);
        const double l1 = fabs(rv.x) + fabs(rv.y) + fabs(rv.z);
        /* float: the sum's rounding may decide a case within a few ulps of the bound */
        const double slack = FC_NUMERIC_FIXED ? 0.0 : 4.0 * (double)FLT_EPSILON * l1;
        if (l1 < lim_ref - slack) {
            assert_true(within);
        } else if (l1 > lim_ref + slack) {
            assert_false(within);
        }
        if (within) {
            assert_true(dnorm(rv) <= lim_ref);
        }
    }
    /* on the bound: within; one LSB (float: one part in 2^20) beyond: not */
    const fc_real three = FC_INT(3, ACCEL), one = FC_INT(1, ACCEL), two = FC_INT(2, ACCEL);
    assert_true(fc_norm1_within(one, -two, FC_INT(0, ACCEL), three));
    assert_true(fc_norm1_within(FC_INT(0, ACCEL), FC_INT(0, ACCEL), -three, three));
    assert_false(fc_norm1_within(one, two, FC_C(1.0f / 1048576.0f, ACCEL), three));
    assert_false(fc_norm1_within(FC_INT(0, ACCEL), FC_INT(0, ACCEL), FC_INT(0, ACCEL), -one));
    /* the extremes of the format: no overflow */
    assert_true(fc_norm1_within(FC_REAL_MAX, FC_INT(0, ACCEL), FC_INT(0, ACCEL), FC_REAL_MAX));
    assert_false(fc_norm1_within(FC_REAL_MAX, FC_REAL_MIN, FC_REAL_MAX, FC_REAL_MAX));
    assert_false(fc_norm1_within(FC_REAL_MIN, one, FC_INT(0, ACCEL), FC_REAL_MAX));
#if !FC_NUMERIC_FIXED
    assert_false(fc_norm1_within(NAN, 0.0f, 0.0f, 1.0f));
    assert_false(fc_norm1_within(0.0f, 0.0f, INFINITY, INFINITY));
    assert_false(fc_norm1_within(0.0f, 0.0f, 0.0f, NAN));
#endif
}

static void test_convert(void **state)
{
    (void)state;
    fc_arith ar = {0};
    ts_rng rng = ts_rng_seed(19u);
    ts_check c = ts_check_begin("vec3 convert");
    for (int i = 0; i < 1000; i++) {
        dvec rv;
        /* VEL (22) -> LENGTH (20): rounded, 0.5 LSB */
        const fc_vec3 v = rand_vec(&rng, 500.0f, FC_VEL_FRAC, &rv);
        const double t = ts_tol(FC_LENGTH_FRAC, 0.5, 0.0, 0.0);
        close_vec(&c, fc_vec3_convert(&ar, v, FC_VEL_FRAC, FC_LENGTH_FRAC), FC_LENGTH_FRAC, rv, t, t, t, i);
        /* ANGLE (28) -> UNIT (30): exact */
        const fc_vec3 a = rand_vec(&rng, 1.99f, FC_ANGLE_FRAC, &rv);
        close_vec(&c, fc_vec3_convert(&ar, a, FC_ANGLE_FRAC, FC_UNIT_FRAC), FC_UNIT_FRAC, rv, 0.0, 0.0, 0.0, i);
    }
    ts_check_end(&c);
    assert_int_equal(ar.saturated, 0);
#if FC_NUMERIC_FIXED
    /* 100 m as UNIT saturates, the other components are untouched */
    const fc_vec3 s = fc_vec3_convert(&ar, fc_vec3_make(FC_INT(100, LENGTH), FC_C(0.5f, LENGTH), FC_INT(-100, LENGTH)),
                                      FC_LENGTH_FRAC, FC_UNIT_FRAC);
    TS_ASSERT_REAL_EQ(s.x, FC_REAL_MAX);
    TS_ASSERT_REAL_EQ(s.y, FC_C(0.5f, UNIT));
    TS_ASSERT_REAL_EQ(s.z, FC_REAL_MIN);
    assert_int_equal(ar.saturated, 1);
#else
    const fc_vec3 s = fc_vec3_make(100.0f, 0.5f, -1.0e6f);
    assert_vec_eq(fc_vec3_convert(&ar, s, FC_LENGTH_FRAC, FC_UNIT_FRAC), s);
    assert_int_equal(ar.saturated, 0);
#endif
}

static void test_is_finite(void **state)
{
    (void)state;
    assert_true(fc_vec3_is_finite(fc_vec3_zero()));
    assert_true(fc_vec3_is_finite(fc_vec3_make(FC_REAL_MAX, FC_REAL_MIN, FC_C(0.5f, UNIT))));
#if FC_NUMERIC_FIXED
    /* every int32 vector is finite */
    assert_true(fc_vec3_is_finite(fc_vec3_make(INT32_MIN, INT32_MAX, -1)));
#else
    const float bad[] = {NAN, INFINITY, -INFINITY};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        assert_false(fc_vec3_is_finite(fc_vec3_make(bad[k], 0.0f, 0.0f)));
        assert_false(fc_vec3_is_finite(fc_vec3_make(1.0f, bad[k], 0.0f)));
        assert_false(fc_vec3_is_finite(fc_vec3_make(1.0f, 2.0f, bad[k])));
    }
    assert_true(fc_vec3_is_finite(fc_vec3_make(FLT_MIN / 8.0f, -FLT_MAX, 1.0e-30f)));
#endif
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_make_and_zero),
        cmocka_unit_test(test_add_sub_neg),
        cmocka_unit_test(test_add_sub_neg_saturation),
        cmocka_unit_test(test_scale),
        cmocka_unit_test(test_mul_elementwise),
        cmocka_unit_test(test_dot),
        cmocka_unit_test(test_cross),
        cmocka_unit_test(test_norm),
        cmocka_unit_test(test_normalize),
        cmocka_unit_test(test_clamp_norm),
        cmocka_unit_test(test_clamp_norm_beyond_format_range),
        cmocka_unit_test(test_norm1_within),
        cmocka_unit_test(test_convert),
        cmocka_unit_test(test_is_finite),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
