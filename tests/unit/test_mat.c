/*
 * test_mat.c - small matrices (fc/mat.h, src/mat.c).
 *
 * One source for both backends. Entries are MAT (Q7.24 in fixed). References
 * are double-precision linear algebra on the quantised inputs. Tolerances
 * (see test_support.h):
 *   fixed, in LSBs of MAT (or of the vector's format for mul_vec):
 *     zero/identity/transpose: exact; mul, mul_vec: 1 (one rounding of the
 *     64-bit accumulator); solve: 2 n LSB times the condition number of A,
 *     relative to max(|x|, 1) (Gauss-Jordan with pivoting is backward stable
 *     to about n roundings); pinv: the same for the Gram matrix, relative to
 *     |A+| max(|A|, 1), and the Moore-Penrose identities with that error of
 *     A+ carried through the products.
 *   float: 2n ulps of the sum of |terms| for products; 2 n ulps times the
 *     condition number for solve and pinv.
 */
#include "test_support.h"
#include "fc/mat.h"

typedef struct dmat {
    int rows, cols;
    double a[FC_MAT_MAX_ROWS][FC_MAT_MAX_COLS];
} dmat;

/* ---- construction and double helpers --------------------------------------- */

/* rows x cols of random entries in [-r, r] quantised to MAT; *ref the quantised values */
static fc_mat rand_mat(ts_rng *rng, int rows, int cols, float r, dmat *ref)
{
    fc_mat m;
    assert_int_equal(fc_mat_zero(&m, rows, cols), FC_MAT_OK);
    ref->rows = rows;
    ref->cols = cols;
    for (int i = 0; i < rows; i++) {
        for (int j = 0; j < cols; j++) {
            m.a[i][j] = ts_in(ts_uniform(rng, -r, r), FC_MAT_FRAC, &ref->a[i][j]);
        }
    }
    return m;
}

/* from a table of floats */
static fc_mat mat_in(int rows, int cols, const float *v, dmat *ref)
{
    fc_mat m;
    assert_int_equal(fc_mat_zero(&m, rows, cols), FC_MAT_OK);
    ref->rows = rows;
    ref->cols = cols;
    for (int i = 0; i < rows; i++) {
        for (int j = 0; j < cols; j++) {
            m.a[i][j] = ts_in(v[i * cols + j], FC_MAT_FRAC, &ref->a[i][j]);
        }
    }
    return m;
}

static dmat dval(const fc_mat *m)
{
    dmat d;
    d.rows = m->rows;
    d.cols = m->cols;
    for (int i = 0; i < FC_MAT_MAX_ROWS; i++) {
        for (int j = 0; j < FC_MAT_MAX_COLS; j++) {
            d.a[i][j] = ts_val(m->a[i][j], FC_MAT_FRAC);
        }
    }
    return d;
}

static dmat dmul(const dmat *a, const dmat *b)
{
    dmat r;
    r.rows = a->rows;
    r.cols = b->cols;
    for (int i = 0; i < r.rows; i++) {
        for (int j = 0; j < r.cols; j++) {
            double s = 0.0;
            for (int k = 0; k < a->cols; k++) {
                s += a->a[i][k] * b->a[k][j];
            }
            r.a[i][j] = s;
        }
    }
    return r;
}

static dmat dtranspose(const dmat *a)
{
    dmat r;
    r.rows = a->cols;
    r.cols = a->rows;
    for (int i = 0; i < r.rows; i++) {
        for (int j = 0; j < r.cols; j++) {
            r.a[i][j] = a->a[j][i];
        }
    }
    return r;
}

/* x = A^-1 B by Gauss-Jordan with partial pivoting in double */
static dmat dsolve(const dmat *a, const dmat *b)
{
    dmat w = *a, x = *b;
    const int n = a->rows;
    for (int c = 0; c < n; c++) {
        int p = c;
        for (int r = c + 1; r < n; r++) {
            if (fabs(w.a[r][c]) > fabs(w.a[p][c])) {
                p = r;
            }
        }
        for (int j = 0; j < n; j++) {
            const double t = w.a[c][j];
            w.a[c][j] = w.a[p][j];
            w.a[p][j] = t;
        }
        for (int j = 0; j < x.cols; j++) {
            const double t = x.a[c][j];
            x.a[c][j] = x.a[p][j];
            x.a[p][j] = t;
        }
        const double piv = w.a[c][c];
        for (int j = 0; j < n; j++) {
            w.a[c][j] /= piv;
        }
        for (int j = 0; j < x.cols; j++) {
            x.a[c][j] /= piv;
        }
        for (int r = 0; r < n; r++) {
            if (r != c) {
                const double f = w.a[r][c];
                for (int j = 0; j < n; j++) {
                    w.a[r][j] -= f * w.a[c][j];
                }
                for (int j = 0; j < x.cols; j++) {
                    x.a[r][j] -= f * x.a[c][j];
                }
            }
        }
    }
    return x;
}

static dmat didentity(int n)
{
    dmat r;
    r.rows = n;
    r.cols = n;
    for (int i = 0; i < FC_MAT_MAX_ROWS; i++) {
        for (int j = 0; j < FC_MAT_MAX_COLS; j++) {
            r.a[i][j] = i == j ? 1.0 : 0.0;
        }
    }
    return r;
}

static dmat dinverse(const dmat *a)
{
    const dmat id = didentity(a->rows);
    return dsolve(a, &id);
}

/* infinity-norm condition number */
static double dcond(const dmat *a)
{
    const dmat inv = dinverse(a);
    double na = 0.0, ni = 0.0;
    for (int i = 0; i < a->rows; i++) {
        double sa = 0.0, si = 0.0;
        for (int j = 0; j < a->cols; j++) {
            sa += fabs(a->a[i][j]);
            si += fabs(inv.a[i][j]);
        }
        na = fmax(na, sa);
        ni = fmax(ni, si);
    }
    return na * ni;
}

/* Moore-Penrose pseudo-inverse of a full-rank matrix, in double */
static dmat dpinv(const dmat *a)
{
    const dmat at = dtranspose(a);
    if (a->rows <= a->cols) {
        const dmat g = dmul(a, &at);
        const dmat gi = dinverse(&g);
        return dmul(&at, &gi);
    }
    const dmat g = dmul(&at, a);
    return dsolve(&g, &at);
}

static double dmax_abs(const dmat *a)
{
    double m = 0.0;
    for (int i = 0; i < a->rows; i++) {
        for (int j = 0; j < a->cols; j++) {
            m = fmax(m, fabs(a->a[i][j]));
        }
    }
    return m;
}

static void close_mat(ts_check *c, const dmat *got, const dmat *ref, double tol, const char *label)
{
    assert_int_equal(got->rows, ref->rows);
    assert_int_equal(got->cols, ref->cols);
    for (int i = 0; i < ref->rows; i++) {
        for (int j = 0; j < ref->cols; j++) {
            (void)ts_close(c, got->a[i][j], ref->a[i][j], tol, "%s [%d][%d]", label, i, j);
        }
    }
}

/* every entry, inside and outside the used block, is zero */
static void assert_all_zero(const fc_mat *m)
{
    for (int i = 0; i < FC_MAT_MAX_ROWS; i++) {
        for (int j = 0; j < FC_MAT_MAX_COLS; j++) {
            TS_ASSERT_REAL_EQ(m->a[i][j], FC_INT(0, MAT));
        }
    }
}

static void fill_garbage(fc_mat *m)
{
    m->rows = 5;
    m->cols = 7;
    for (int i = 0; i < FC_MAT_MAX_ROWS; i++) {
        for (int j = 0; j < FC_MAT_MAX_COLS; j++) {
            m->a[i][j] = FC_C(-3.25f, MAT);
        }
    }
}

/* ---- zero, identity, transpose ------------------------------------------------ */

static void test_zero(void **state)
{
    (void)state;
    fc_mat m;
    const int good[][2] = {{3, 4}, {0, 0}, {8, 8}, {1, 8}, {8, 1}, {0, 5}};
    for (size_t k = 0; k < sizeof good / sizeof good[0]; k++) {
        fill_garbage(&m);
        assert_int_equal(fc_mat_zero(&m, good[k][0], good[k][1]), FC_MAT_OK);
        assert_int_equal(m.rows, good[k][0]);
        assert_int_equal(m.cols, good[k][1]);
        assert_all_zero(&m);
    }
    const int bad[][2] = {{9, 1}, {1, 9}, {9, 9}, {-1, 2}, {2, -1}, {100, 100}};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        fill_garbage(&m);
        assert_int_equal(fc_mat_zero(&m, bad[k][0], bad[k][1]), FC_MAT_BAD_SIZE);
        assert_int_equal(m.rows, 0);
        assert_int_equal(m.cols, 0);
        assert_all_zero(&m);
    }
}

static void test_identity(void **state)
{
    (void)state;
    fc_mat m;
    for (int n = 0; n <= FC_MAT_MAX_ROWS; n++) {
        fill_garbage(&m);
        assert_int_equal(fc_mat_identity(&m, n), FC_MAT_OK);
        assert_int_equal(m.rows, n);
        assert_int_equal(m.cols, n);
        for (int i = 0; i < FC_MAT_MAX_ROWS; i++) {
            for (int j = 0; j < FC_MAT_MAX_COLS; j++) {
                TS_ASSERT_REAL_EQ(m.a[i][j], (i == j && i < n) ? FC_INT(1, MAT) : FC_INT(0, MAT));
            }
        }
    }
    TS_ASSERT_CLOSE(ts_val(m.a[3][3], FC_MAT_FRAC), 1.0, 0.0);
    fill_garbage(&m);
    assert_int_equal(fc_mat_identity(&m, 9), FC_MAT_BAD_SIZE);
    assert_int_equal(m.rows, 0);
    assert_int_equal(m.cols, 0);
    assert_all_zero(&m);
    fill_garbage(&m);
    assert_int_equal(fc_mat_identity(&m, -1), FC_MAT_BAD_SIZE);
    assert_int_equal(m.rows, 0);
    assert_all_zero(&m);
}

static void test_transpose(void **state)
{
    (void)state;
    ts_rng rng = ts_rng_seed(41u);
    const int sizes[][2] = {{3, 5}, {5, 3}, {1, 8}, {8, 8}, {4, 1}};
    for (size_t k = 0; k < sizeof sizes / sizeof sizes[0]; k++) {
        dmat ra;
        const fc_mat a = rand_mat(&rng, sizes[k][0], sizes[k][1], 100.0f, &ra);
        fc_mat t, tt;
        fill_garbage(&t);
        fc_mat_transpose(&a, &t);
        assert_int_equal(t.rows, a.cols);
        assert_int_equal(t.cols, a.rows);
        for (int i = 0; i < FC_MAT_MAX_ROWS; i++) {
            for (int j = 0; j < FC_MAT_MAX_COLS; j++) {
                /* the block is the transpose, the rest is zero */
                TS_ASSERT_REAL_EQ(t.a[i][j], (i < t.rows && j < t.cols) ? a.a[j][i] : FC_INT(0, MAT));
            }
        }
        fc_mat_transpose(&t, &tt);
        assert_int_equal(tt.rows, a.rows);
        assert_int_equal(tt.cols, a.cols);
        for (int i = 0; i < a.rows; i++) {
            for (int j = 0; j < a.cols; j++) {
                TS_ASSERT_REAL_EQ(tt.a[i][j], a.a[i][j]);
            }
        }
    }
}

/* ---- products ------------------------------------------------------------- */

static void test_mul(void **state)
{
    (void)state;
    fc_arith ar = {0};
    ts_rng rng = ts_rng_seed(42u);
    const int dims[][3] = {{3, 4, 2}, {4, 6, 4}, {6, 4, 6}, {8, 8, 8}, {1, 8, 1}, {8, 1, 8}, {2, 2, 2}};
    for (size_t k = 0; k < sizeof dims / sizeof dims[0]; k++) {
        ts_check c = ts_check_begin("mat mul");
        for (int rep = 0; rep < 50; rep++) {
            dmat ra, rb;
            const int n = dims[k][1];
            const fc_mat a = rand_mat(&rng, dims[k][0], n, 2.0f, &ra);
            const fc_mat b = rand_mat(&rng, n, dims[k][2], 7.9f / (float)n, &rb);
            fc_mat out;
            fill_garbage(&out);
            assert_int_equal(fc_mat_mul(&ar, &a, &b, &out), FC_MAT_OK);
            const dmat got = dval(&out);
            const dmat ref = dmul(&ra, &rb);
            /* fixed: 1 LSB; float: 2n ulps of the sum of |terms| (at most n 2 7.9/n) */
            close_mat(&c, &got, &ref, ts_tol(FC_MAT_FRAC, 1.0, 2.0 * n, 2.0 * 7.9), "A B");
            /* nothing outside the block */
            for (int i = 0; i < FC_MAT_MAX_ROWS; i++) {
                for (int j = 0; j < FC_MAT_MAX_COLS; j++) {
                    if (i >= out.rows || j >= out.cols) {
                        TS_ASSERT_REAL_EQ(out.a[i][j], FC_INT(0, MAT));
                    }
                }
            }
        }
        ts_check_end(&c);
    }
    /* the identity is neutral, exactly */
    dmat ra;
    const fc_mat a = rand_mat(&rng, 4, 6, 100.0f, &ra);
    fc_mat i4, i6, out;
    (void)fc_mat_identity(&i4, 4);
    (void)fc_mat_identity(&i6, 6);
    assert_int_equal(fc_mat_mul(&ar, &i4, &a, &out), FC_MAT_OK);
    for (int i = 0; i < 4; i++) {
        for (int j = 0; j < 6; j++) {
            TS_ASSERT_REAL_EQ(out.a[i][j], a.a[i][j]);
        }
    }
    assert_int_equal(fc_mat_mul(&ar, &a, &i6, &out), FC_MAT_OK);
    for (int i = 0; i < 4; i++) {
        for (int j = 0; j < 6; j++) {
            TS_ASSERT_REAL_EQ(out.a[i][j], a.a[i][j]);
        }
    }
    assert_int_equal(ar.saturated, 0);
    /* dimension mismatch: 4x6 times 4x6 */
    fill_garbage(&out);
    assert_int_equal(fc_mat_mul(&ar, &a, &a, &out), FC_MAT_BAD_SIZE);
    assert_int_equal(out.rows, 0);
    assert_int_equal(out.cols, 0);
    assert_all_zero(&out);
    assert_int_equal(fc_mat_mul(&ar, &i4, &i6, &out), FC_MAT_BAD_SIZE);
}

/* A row of eight products near the extremes: no wrap of the accumulator;
 * a result out of MAT saturates toward its sign with the flag. */
static void test_mul_saturation(void **state)
{
    (void)state;
    fc_arith ar = {0};
    fc_mat a, b, out;
    (void)fc_mat_zero(&a, 1, 8);
    (void)fc_mat_zero(&b, 8, 2);
    for (int k = 0; k < 8; k++) {
        a.a[0][k] = FC_INT(127, MAT);
        b.a[k][0] = FC_INT(-127, MAT);
        b.a[k][1] = k % 2 == 0 ? FC_INT(127, MAT) : FC_INT(-127, MAT); /* cancels to 0 */
    }
    assert_int_equal(fc_mat_mul(&ar, &a, &b, &out), FC_MAT_OK);
    TS_ASSERT_REAL_EQ(out.a[0][1], FC_INT(0, MAT));
#if FC_NUMERIC_FIXED
    TS_ASSERT_REAL_EQ(out.a[0][0], FC_REAL_MIN);
    assert_int_equal(ar.saturated, 1);
#else
    TS_ASSERT_REAL_EQ(out.a[0][0], -8.0f * 127.0f * 127.0f);
    assert_int_equal(ar.saturated, 0);
#endif
}

static void test_mul_vec(void **state)
{
    (void)state;
    fc_arith ar = {0};
    ts_rng rng = ts_rng_seed(43u);
    const struct {
        const char *name;
        int frac, rows, cols;
        float rx;
    } cases[] = {{"mul_vec MAT x FORCE", FC_FORCE_FRAC, 4, 6, 2.0f},
                 {"mul_vec MAT x RATE", FC_RATE_FRAC, 6, 4, 15.0f},
                 {"mul_vec MAT x MOMENT 8x8", FC_MOMENT_FRAC, 8, 8, 0.01f}};
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        ts_check c = ts_check_begin(cases[k].name);
        for (int rep = 0; rep < 200; rep++) {
            dmat ra;
            const int n = cases[k].cols;
            const fc_mat a = rand_mat(&rng, cases[k].rows, n, 1.0f, &ra);
            fc_real x[FC_MAT_MAX_COLS], y[FC_MAT_MAX_ROWS];
            double rx[FC_MAT_MAX_COLS];
            for (int j = 0; j < n; j++) {
                x[j] = ts_in(ts_uniform(&rng, -cases[k].rx, cases[k].rx), cases[k].frac, &rx[j]);
            }
            for (int i = 0; i < FC_MAT_MAX_ROWS; i++) {
                y[i] = FC_C(1.0f, UNIT); /* beyond rows: must stay untouched */
            }
            fc_mat_mul_vec(&ar, &a, x, y);
            for (int i = 0; i < cases[k].rows; i++) {
                double ref = 0.0, mag = 0.0;
                for (int j = 0; j < n; j++) {
                    ref += ra.a[i][j] * rx[j];
                    mag += fabs(ra.a[i][j] * rx[j]);
                }
                /* fixed: 1 LSB of x's format; float 2n ulps of the sum of |terms| */
                (void)ts_close(&c, ts_val(y[i], cases[k].frac), ref, ts_tol(cases[k].frac, 1.0, 2.0 * n, mag),
                               "row %d", i);
            }
            for (int i = cases[k].rows; i < FC_MAT_MAX_ROWS; i++) {
                TS_ASSERT_REAL_EQ(y[i], FC_C(1.0f, UNIT));
            }
        }
        ts_check_end(&c);
    }
    /* the identity returns x exactly */
    fc_mat id;
    (void)fc_mat_identity(&id, 3);
    const fc_real x[3] = {FC_C(1.25f, FORCE), FC_C(-2000.0f, FORCE), FC_C(0.001f, FORCE)};
    fc_real y[3];
    fc_mat_mul_vec(&ar, &id, x, y);
    for (int i = 0; i < 3; i++) {
        TS_ASSERT_REAL_EQ(y[i], x[i]);
    }
    assert_int_equal(ar.saturated, 0);
}

/* ---- solve ------------------------------------------------------------------ */

/* fixed: 2 n LSB times cond(A) relative to max(|x|max, 1); float: 2 n ulps
 * times cond(A) (Gauss-Jordan is backward stable to about n roundings) */
static double solve_tol(int n, double cond, double xmax)
{
    const double k = 2.0 * n * cond;
    return ts_tol(FC_MAT_FRAC, k * fmax(xmax, 1.0), k, fmax(xmax, 1.0));
}

static void test_solve_known(void **state)
{
    (void)state;
    fc_arith ar = {0};
    /* symmetric positive definite; x = (1, -0.5, 0.25) solves A x = b */
    const float av[9] = {4.0f, -2.0f, 1.0f, -2.0f, 4.0f, -2.0f, 1.0f, -2.0f, 4.0f};
    const float bv[3] = {5.25f, -4.5f, 3.0f};
    dmat ra, rb;
    const fc_mat a = mat_in(3, 3, av, &ra);
    const fc_mat b = mat_in(3, 1, bv, &rb);
    fc_mat x;
    assert_int_equal(fc_mat_solve(&ar, &a, &b, &x), FC_MAT_OK);
    assert_int_equal(x.rows, 3);
    assert_int_equal(x.cols, 1);
    const double tol = solve_tol(3, dcond(&ra), 1.0);
    ts_check c = ts_check_begin("solve known 3x3");
    (void)ts_close(&c, ts_val(x.a[0][0], FC_MAT_FRAC), 1.0, tol, "x0");
    (void)ts_close(&c, ts_val(x.a[1][0], FC_MAT_FRAC), -0.5, tol, "x1");
    (void)ts_close(&c, ts_val(x.a[2][0], FC_MAT_FRAC), 0.25, tol, "x2");
    ts_check_end(&c);

    /* a zero first pivot: the rows must be exchanged; x = (0.5, -1, 2) */
    const float pv[9] = {0.0f, 2.0f, 1.0f, 1.0f, 1.0f, 1.0f, 2.0f, 1.0f, 0.0f};
    const float qv[3] = {0.0f, 1.5f, 0.0f};
    dmat rp, rq;
    const fc_mat p = mat_in(3, 3, pv, &rp);
    const fc_mat q = mat_in(3, 1, qv, &rq);
    assert_int_equal(fc_mat_solve(&ar, &p, &q, &x), FC_MAT_OK);
    const double ptol = solve_tol(3, dcond(&rp), 2.0);
    ts_check c2 = ts_check_begin("solve with pivoting");
    (void)ts_close(&c2, ts_val(x.a[0][0], FC_MAT_FRAC), 0.5, ptol, "x0");
    (void)ts_close(&c2, ts_val(x.a[1][0], FC_MAT_FRAC), -1.0, ptol, "x1");
    (void)ts_close(&c2, ts_val(x.a[2][0], FC_MAT_FRAC), 2.0, ptol, "x2");
    ts_check_end(&c2);

    /* B = I gives the inverse: A A^-1 = I */
    fc_mat id, inv;
    (void)fc_mat_identity(&id, 3);
    assert_int_equal(fc_mat_solve(&ar, &a, &id, &inv), FC_MAT_OK);
    const dmat rinv = dval(&inv);
    const dmat prod = dmul(&ra, &rinv);
    const dmat rid = didentity(3);
    const dmat ref_inv = dinverse(&ra);
    ts_check c3 = ts_check_begin("inverse by solve");
    close_mat(&c3, &rinv, &ref_inv, solve_tol(3, dcond(&ra), dmax_abs(&ref_inv)), "A^-1");
    close_mat(&c3, &prod, &rid, 4.0 * solve_tol(3, dcond(&ra), dmax_abs(&ref_inv)), "A A^-1");
    ts_check_end(&c3);
    assert_int_equal(ar.saturated, 0);
}

static void test_solve_random(void **state)
{
    (void)state;
    fc_arith ar = {0};
    ts_rng rng = ts_rng_seed(44u);
    for (int n = 1; n <= FC_MAT_MAX_ROWS; n++) {
        ts_check c = ts_check_begin("solve random n x n");
        for (int rep = 0; rep < 40; rep++) {
            dmat ra, rb;
            fc_mat a = rand_mat(&rng, n, n, 1.0f, &ra);
            /* diagonally dominant: well conditioned */
            for (int i = 0; i < n; i++) {
                a.a[i][i] = ts_in(ts_uniform(&rng, 0.0f, 1.0f) < 0.5f ? -(float)n : (float)n, FC_MAT_FRAC,
                                  &ra.a[i][i]);
            }
            const int m = 1 + (int)(ts_rand_u32(&rng) % 3u);
            const fc_mat b = rand_mat(&rng, n, m, 4.0f, &rb);
            fc_mat x;
            assert_int_equal(fc_mat_solve(&ar, &a, &b, &x), FC_MAT_OK);
            const dmat ref = dsolve(&ra, &rb);
            const dmat got = dval(&x);
            close_mat(&c, &got, &ref, solve_tol(n, dcond(&ra), dmax_abs(&ref)), "x");
        }
        ts_check_end(&c);
    }
    assert_int_equal(ar.saturated, 0);
}

static void test_solve_singular_and_bad_size(void **state)
{
    (void)state;
    fc_arith ar = {0};
    fc_mat x;
    dmat rd;
    /* row 1 = 2 row 0 */
    const float sv[9] = {1.0f, 2.0f, 3.0f, 2.0f, 4.0f, 6.0f, 1.0f, 0.0f, 1.0f};
    const float bv[3] = {1.0f, 2.0f, 3.0f};
    dmat rb;
    const fc_mat s = mat_in(3, 3, sv, &rd);
    const fc_mat b = mat_in(3, 1, bv, &rb);
    fill_garbage(&x);
    assert_int_equal(fc_mat_solve(&ar, &s, &b, &x), FC_MAT_RANK_DEFICIENT);
    assert_int_equal(x.rows, 3);
    assert_int_equal(x.cols, 1);
    assert_all_zero(&x);
    /* all zeros */
    fc_mat z;
    (void)fc_mat_zero(&z, 3, 3);
    fill_garbage(&x);
    assert_int_equal(fc_mat_solve(&ar, &z, &b, &x), FC_MAT_RANK_DEFICIENT);
    assert_all_zero(&x);
    /* a pivot below 1e-5 of the largest entry: [[1, 1], [1, 1 + 1e-7]] */
    const float nv[4] = {1.0f, 1.0f, 1.0f, 1.0000001f};
    const fc_mat ns = mat_in(2, 2, nv, &rd);
    fc_mat b2;
    (void)fc_mat_identity(&b2, 2);
    assert_int_equal(fc_mat_solve(&ar, &ns, &b2, &x), FC_MAT_RANK_DEFICIENT);
    assert_int_equal(x.rows, 2);
    assert_int_equal(x.cols, 2);
    assert_all_zero(&x);
    /* but a pivot of 1e-3 is not rank deficiency: x = A^-1 (0.01, 0) */
    const float ov[4] = {1.0f, 1.0f, 1.0f, 1.001f};
    const float cv[2] = {0.01f, 0.0f};
    dmat rc;
    const fc_mat ok = mat_in(2, 2, ov, &rd);
    const fc_mat cb = mat_in(2, 1, cv, &rc);
    assert_int_equal(fc_mat_solve(&ar, &ok, &cb, &x), FC_MAT_OK);
    const dmat xref = dsolve(&rd, &rc);
    const dmat xgot = dval(&x);
    ts_check c = ts_check_begin("solve with a 1e-3 pivot");
    close_mat(&c, &xgot, &xref, solve_tol(2, dcond(&rd), dmax_abs(&xref)), "x");
    ts_check_end(&c);
    /* sizes: A not square, B of the wrong height */
    fc_mat a34, b2x1;
    (void)fc_mat_zero(&a34, 3, 4);
    (void)fc_mat_zero(&b2x1, 2, 1);
    fill_garbage(&x);
    assert_int_equal(fc_mat_solve(&ar, &a34, &b, &x), FC_MAT_BAD_SIZE);
    assert_int_equal(x.rows, 0);
    assert_int_equal(x.cols, 0);
    assert_all_zero(&x);
    fill_garbage(&x);
    assert_int_equal(fc_mat_solve(&ar, &s, &b2x1, &x), FC_MAT_BAD_SIZE);
    assert_int_equal(x.rows, 0);
    assert_all_zero(&x);
    assert_int_equal(ar.saturated, 0);
}

/* ---- pseudo-inverse -------------------------------------------------------------- */

/* Checks A+ against the double pseudo-inverse and the four Moore-Penrose
 * conditions (products formed in double from the library's A+). */
static double check_pinv(const char *what, const fc_mat *a, const dmat *ra)
{
    fc_arith ar = {0};
    fc_mat p;
    fill_garbage(&p);
    assert_int_equal(fc_mat_pinv(&ar, a, &p), FC_MAT_OK);
    assert_int_equal(p.rows, a->cols);
    assert_int_equal(p.cols, a->rows);
    assert_int_equal(ar.saturated, 0);
    const dmat rp = dval(&p);
    const dmat ref = dpinv(ra);
    const dmat at = dtranspose(ra);
    const dmat g = ra->rows <= ra->cols ? dmul(ra, &at) : dmul(&at, ra);
    const int n = g.rows;
    const double cond = dcond(&g);
    /* the matrices used here are well conditioned: the tolerance argument
     * below assumes it */
    if (getenv("TS_VERBOSE") != NULL) {
        print_message("  %s: cond(G) = %.3g\n", what, cond);
    }
    assert_true(cond < 50.0);
    const double pmax = dmax_abs(&ref), amax = dmax_abs(ra);
    /* A+ itself: the Gram product rounds once per entry (1 LSB), the
     * Gauss-Jordan 4 n^2 times cond(G) relative to the largest entry */
    const double tol_p = solve_tol(n, cond, pmax * fmax(amax, 1.0));
    ts_check c = ts_check_begin(what);
    close_mat(&c, &rp, &ref, tol_p, "A+");
    /* A A+ A = A and A+ A A+ = A+ (the error of A+ times |A| |A| summed over
     * the inner dimensions) */
    const dmat aap = dmul(ra, &rp);
    const dmat apa = dmul(&rp, ra);
    const dmat aapa = dmul(&aap, ra);
    const dmat apaap = dmul(&apa, &rp);
    const double k = (double)(ra->rows * ra->cols);
    close_mat(&c, &aapa, ra, k * tol_p * amax * amax, "A A+ A");
    close_mat(&c, &apaap, &rp, k * tol_p * amax * pmax, "A+ A A+");
    /* A A+ and A+ A symmetric */
    const dmat aap_t = dtranspose(&aap), apa_t = dtranspose(&apa);
    close_mat(&c, &aap, &aap_t, 2.0 * k * tol_p * amax, "(A A+)^T");
    close_mat(&c, &apa, &apa_t, 2.0 * k * tol_p * amax, "(A+ A)^T");
    ts_check_end(&c);
    return tol_p;
}

/* A mixer of orthogonal rows or columns of +-1 (Hadamard): its
 * pseudo-inverse is its transpose over k (k = rows x cols / min(rows, cols)),
 * to 1 MAT LSB (the Cholesky solve takes a square root). */
static void check_pinv_scaled_transpose(const fc_mat *h, const dmat *rh, double k)
{
    fc_arith ar = {0};
    fc_mat p;
    assert_int_equal(fc_mat_pinv(&ar, h, &p), FC_MAT_OK);
    for (int i = 0; i < h->cols; i++) {
        for (int j = 0; j < h->rows; j++) {
            TS_ASSERT_CLOSE(ts_val(p.a[i][j], FC_MAT_FRAC), rh->a[j][i] / k, 1.0 / 16777216.0);
        }
    }
}

/* A of full rank: its pseudo-inverse is a one-sided inverse, A A+ = I
 * when A is wide or square, A+ A = I when it is tall; tol_p is check_pinv's
 * tolerance on A+, times the longer side and the largest |a_ij|. */
static void check_pinv_inverts(const char *name, const fc_mat *a, const dmat *ra, double tol_p)
{
    fc_arith ar = {0};
    fc_mat p;
    assert_int_equal(fc_mat_pinv(&ar, a, &p), FC_MAT_OK);
    const dmat rp = dval(&p);
    const bool wide = a->rows <= a->cols;
    const dmat prod = wide ? dmul(ra, &rp) : dmul(&rp, ra);
    const dmat id = didentity(wide ? a->rows : a->cols);
    const double longer_side = (double)(wide ? a->cols : a->rows);
    ts_check c = ts_check_begin(name);
    close_mat(&c, &prod, &id, longer_side * dmax_abs(ra) * tol_p, wide ? "A A+" : "A+ A");
    ts_check_end(&c);
}

static void test_pinv_wide(void **state)
{
    (void)state;
    ts_rng rng = ts_rng_seed(45u);
    for (int rep = 0; rep < 30; rep++) {
        dmat ra;
        fc_mat a = rand_mat(&rng, 4, 6, 1.0f, &ra);
        /* a strong diagonal keeps the rows well apart */
        for (int i = 0; i < 4; i++) {
            a.a[i][i] = ts_in(2.0f, FC_MAT_FRAC, &ra.a[i][i]);
        }
        (void)check_pinv("pinv 4x6", &a, &ra);
    }
    /* an X-quadrotor-like Hadamard mixer, 4x8: rows orthogonal, A+ = A^T / 8 exactly */
    const float hv[32] = {1, 1, 1, 1, 1, 1, 1, 1,  -1, -1, 1, 1, -1, -1, 1, 1,
                          1, -1, -1, 1, 1, -1, -1, 1, -1, 1, -1, 1, -1, 1, -1, 1};
    dmat rh;
    const fc_mat h = mat_in(4, 8, hv, &rh);
    check_pinv_scaled_transpose(&h, &rh, 8.0);
    (void)check_pinv("pinv Hadamard 4x8", &h, &rh);
}

static void test_pinv_square(void **state)
{
    (void)state;
    ts_rng rng = ts_rng_seed(46u);
    for (int rep = 0; rep < 30; rep++) {
        dmat ra;
        fc_mat a = rand_mat(&rng, 4, 4, 1.0f, &ra);
        for (int i = 0; i < 4; i++) {
            a.a[i][i] = ts_in(2.5f, FC_MAT_FRAC, &ra.a[i][i]);
        }
        const double tol_p = check_pinv("pinv 4x4", &a, &ra);
        /* square and full rank: the pseudo-inverse is the inverse */
        check_pinv_inverts("pinv 4x4: A A+ = I", &a, &ra, tol_p);
    }
    /* the 4x4 X-quadrotor mixer (Hadamard): A+ = A^T / 4 exactly */
    const float hv[16] = {1, 1, 1, 1, -1, -1, 1, 1, 1, -1, -1, 1, -1, 1, -1, 1};
    dmat rh;
    const fc_mat h = mat_in(4, 4, hv, &rh);
    check_pinv_scaled_transpose(&h, &rh, 4.0);
}

static void test_pinv_tall(void **state)
{
    (void)state;
    ts_rng rng = ts_rng_seed(47u);
    for (int rep = 0; rep < 30; rep++) {
        dmat ra;
        fc_mat a = rand_mat(&rng, 6, 4, 1.0f, &ra);
        for (int i = 0; i < 4; i++) {
            a.a[i][i] = ts_in(2.0f, FC_MAT_FRAC, &ra.a[i][i]);
        }
        const double tol_p = check_pinv("pinv 6x4", &a, &ra);
        /* full column rank: A+ A = I */
        check_pinv_inverts("pinv 6x4: A+ A = I", &a, &ra, tol_p);
    }
    /* the transposed 4x8 Hadamard mixer, 8x4: orthogonal columns, A+ = A^T / 8 exactly */
    const float hv[32] = {1, 1, 1, 1, 1, 1, 1, 1,  -1, -1, 1, 1, -1, -1, 1, 1,
                          1, -1, -1, 1, 1, -1, -1, 1, -1, 1, -1, 1, -1, 1, -1, 1};
    float tv[32];
    for (int i = 0; i < 8; i++) {
        for (int j = 0; j < 4; j++) {
            tv[i * 4 + j] = hv[j * 8 + i];
        }
    }
    dmat rh;
    const fc_mat h = mat_in(8, 4, tv, &rh);
    check_pinv_scaled_transpose(&h, &rh, 8.0);
    (void)check_pinv("pinv Hadamard 8x4", &h, &rh);
}

static void test_pinv_rank_deficient(void **state)
{
    (void)state;
    fc_arith ar = {0};
    ts_rng rng = ts_rng_seed(48u);
    dmat ra;
    /* wide 4x6: row 3 = row 0 + row 1 */
    fc_mat a = rand_mat(&rng, 4, 6, 1.0f, &ra);
    for (int j = 0; j < 6; j++) {
        a.a[3][j] = fc_add(&ar, a.a[0][j], a.a[1][j]);
    }
    fc_mat p;
    fill_garbage(&p);
    assert_int_equal(fc_mat_pinv(&ar, &a, &p), FC_MAT_RANK_DEFICIENT);
    assert_int_equal(p.rows, 6);
    assert_int_equal(p.cols, 4);
    assert_all_zero(&p);
    /* tall 6x4: column 3 = column 0 - column 2 */
    fc_mat t = rand_mat(&rng, 6, 4, 1.0f, &ra);
    for (int i = 0; i < 6; i++) {
        t.a[i][3] = fc_sub(&ar, t.a[i][0], t.a[i][2]);
    }
    fill_garbage(&p);
    assert_int_equal(fc_mat_pinv(&ar, &t, &p), FC_MAT_RANK_DEFICIENT);
    assert_int_equal(p.rows, 4);
    assert_int_equal(p.cols, 6);
    assert_all_zero(&p);
    /* square with a zero row */
    fc_mat s = rand_mat(&rng, 4, 4, 1.0f, &ra);
    for (int j = 0; j < 4; j++) {
        s.a[2][j] = FC_INT(0, MAT);
    }
    fill_garbage(&p);
    assert_int_equal(fc_mat_pinv(&ar, &s, &p), FC_MAT_RANK_DEFICIENT);
    assert_int_equal(p.rows, 4);
    assert_int_equal(p.cols, 4);
    assert_all_zero(&p);
    /* the zero matrix */
    fc_mat z;
    (void)fc_mat_zero(&z, 3, 5);
    assert_int_equal(fc_mat_pinv(&ar, &z, &p), FC_MAT_RANK_DEFICIENT);
    assert_int_equal(p.rows, 5);
    assert_int_equal(p.cols, 3);
    assert_all_zero(&p);
    assert_int_equal(ar.saturated, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_zero),
        cmocka_unit_test(test_identity),
        cmocka_unit_test(test_transpose),
        cmocka_unit_test(test_mul),
        cmocka_unit_test(test_mul_saturation),
        cmocka_unit_test(test_mul_vec),
        cmocka_unit_test(test_solve_known),
        cmocka_unit_test(test_solve_random),
        cmocka_unit_test(test_solve_singular_and_bad_size),
        cmocka_unit_test(test_pinv_wide),
        cmocka_unit_test(test_pinv_square),
        cmocka_unit_test(test_pinv_tall),
        cmocka_unit_test(test_pinv_rank_deficient),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
