/*
 * test_quat.c - unit quaternions (fc/quat.h, src/quat.c).
 *
 * One source for both backends. References are double-precision quaternion
 * algebra on the quantised inputs. Tolerances (see test_support.h):
 *   fixed, in LSBs of UNIT (quaternion components, unit vectors) or of the
 *   vector's own format / of ANGLE:
 *     mul 4; associativity and q q* 8; norm_sq 1; normalize 4 near unit
 *     length, otherwise 4 + |u_i| 2 LSB of RATIO (1/|q| is held in RATIO);
 *     rotate/rotate_inv 6 of the vector's format, rotate_inv(rotate) 12,
 *     plus 2 |1 - |q|^2| |v| for a quantised q that is unit only to its input
 *     rounding (rotate assumes |q| = 1);
 *     from_axis_angle 8 (sin/cos 5 + half-angle rounding 2 + scaling 1);
 *     to_axis_angle: angle 10 ANGLE LSB, axis 1 + 0.6 / |v| UNIT LSB;
 *     from_rotation_vector: series branch 4, sin/cos branch 8 + 1 per rad;
 *     from_rpy 12 (three sin/cos pairs); to_rpy 4 ANGLE LSB + 6 UNIT LSB /
 *     cos(pitch) (the conditioning of roll/yaw and of asin near gimbal lock);
 *     integration over N steps: N (0.5 ANGLE LSB + 4 UNIT LSB), |q| = 1
 *     within 8 UNIT LSB at every step.
 *   float: ulps relative to the magnitude involved (1 for unit quaternions,
 *     |v| for rotated vectors): mul 4, associativity 8, rotate 8, round trip
 *     16, from_axis_angle 4, from_rpy 6, to_rpy 4 + 6 / cos(pitch), and
 *     N 2 ulps for an N-step integration.
 */
#include "test_support.h"
#include "fc/quat.h"

typedef struct dvec {
    double x, y, z;
} dvec;

typedef struct dquat {
    double w, x, y, z;
} dquat;

/* ---- double-precision reference algebra --------------------------------- */

static dquat dq_mul(dquat p, dquat q)
{
    const dquat r = {p.w * q.w - p.x * q.x - p.y * q.y - p.z * q.z,
                     p.w * q.x + p.x * q.w + p.y * q.z - p.z * q.y,
                     p.w * q.y - p.x * q.z + p.y * q.w + p.z * q.x,
                     p.w * q.z + p.x * q.y - p.y * q.x + p.z * q.w};
    return r;
}

static dquat dq_conj(dquat q)
{
    const dquat r = {q.w, -q.x, -q.y, -q.z};
    return r;
}

static double dq_norm(dquat q)
{
    return sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
}

static dquat dq_scale(dquat q, double k)
{
    const dquat r = {q.w * k, q.x * k, q.y * k, q.z * k};
    return r;
}

/* q [0, v] q* */
static dvec dq_rotate(dquat q, dvec v)
{
    const dquat p = {0.0, v.x, v.y, v.z};
    const dquat r = dq_mul(dq_mul(q, p), dq_conj(q));
    const dvec out = {r.x, r.y, r.z};
    return out;
}

static double dv_norm(dvec v)
{
    return sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
}

/* The rotation by q/|q|. A quantised quaternion is unit only to its input
 * rounding; fc_quat_rotate assumes |q| = 1, and for |q|^2 = 1 - e its result
 * may differ from this by up to 2 |e| |v| (rotate_slack): input rounding,
 * not an error of the function. */
static dvec dq_rotate_unit(dquat q, dvec v)
{
    return dq_rotate(dq_scale(q, 1.0 / dq_norm(q)), v);
}

static double rotate_slack(dquat q, dvec v)
{
    return 2.0 * fabs(1.0 - dq_norm(q) * dq_norm(q)) * dv_norm(v);
}

static dquat dq_axis_angle(dvec axis, double angle)
{
    const double s = sin(angle / 2.0);
    const dquat q = {cos(angle / 2.0), axis.x * s, axis.y * s, axis.z * s};
    return q;
}

/* exp of the rotation vector theta: [cos(a/2), sin(a/2)/a theta] */
static dquat dq_rotation_vector(dvec theta)
{
    const double a = sqrt(theta.x * theta.x + theta.y * theta.y + theta.z * theta.z);
    const double k = a > 0.0 ? sin(a / 2.0) / a : 0.5;
    const dquat q = {cos(a / 2.0), theta.x * k, theta.y * k, theta.z * k};
    return q;
}

/* q_z(yaw) q_y(pitch) q_x(roll) */
static dquat dq_rpy(double roll, double pitch, double yaw)
{
    const dvec ex = {1.0, 0.0, 0.0}, ey = {0.0, 1.0, 0.0}, ez = {0.0, 0.0, 1.0};
    return dq_mul(dq_axis_angle(ez, yaw), dq_mul(dq_axis_angle(ey, pitch), dq_axis_angle(ex, roll)));
}

static double wrap_pi(double a)
{
    while (a > TS_PI) {
        a -= 2.0 * TS_PI;
    }
    while (a < -TS_PI) {
        a += 2.0 * TS_PI;
    }
    return a;
}

/* ---- conversions ---------------------------------------------------------- */

static fc_quat quat_in(double w, double x, double y, double z, dquat *ref)
{
    return fc_quat_make(ts_in((float)w, FC_UNIT_FRAC, &ref->w), ts_in((float)x, FC_UNIT_FRAC, &ref->x),
                        ts_in((float)y, FC_UNIT_FRAC, &ref->y), ts_in((float)z, FC_UNIT_FRAC, &ref->z));
}

static fc_quat quat_from_d(dquat q, dquat *ref)
{
    return quat_in(q.w, q.x, q.y, q.z, ref);
}

static dquat qval(fc_quat q)
{
    const dquat r = {ts_val(q.w, FC_UNIT_FRAC), ts_val(q.x, FC_UNIT_FRAC), ts_val(q.y, FC_UNIT_FRAC),
                     ts_val(q.z, FC_UNIT_FRAC)};
    return r;
}

static fc_vec3 vec_in(double x, double y, double z, int frac, dvec *ref)
{
    return fc_vec3_make(ts_in((float)x, frac, &ref->x), ts_in((float)y, frac, &ref->y),
                        ts_in((float)z, frac, &ref->z));
}

static dvec vval(fc_vec3 v, int frac)
{
    const dvec r = {ts_val(v.x, frac), ts_val(v.y, frac), ts_val(v.z, frac)};
    return r;
}

/* A random unit quaternion (double), w of either sign. */
static dquat rand_unit_dquat(ts_rng *rng)
{
    dquat q;
    double n;
    do {
        q.w = (double)ts_uniform(rng, -1.0f, 1.0f);
        q.x = (double)ts_uniform(rng, -1.0f, 1.0f);
        q.y = (double)ts_uniform(rng, -1.0f, 1.0f);
        q.z = (double)ts_uniform(rng, -1.0f, 1.0f);
        n = dq_norm(q);
    } while (n < 0.2 || n > 1.0);
    return dq_scale(q, 1.0 / n);
}

static dvec rand_unit_dvec(ts_rng *rng)
{
    dvec v;
    double n;
    do {
        v.x = (double)ts_uniform(rng, -1.0f, 1.0f);
        v.y = (double)ts_uniform(rng, -1.0f, 1.0f);
        v.z = (double)ts_uniform(rng, -1.0f, 1.0f);
        n = sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
    } while (n < 0.2 || n > 1.0);
    v.x /= n;
    v.y /= n;
    v.z /= n;
    return v;
}

/* ---- comparisons ---------------------------------------------------------- */

static void close_quat(ts_check *c, fc_quat q, dquat ref, double tol, const char *label, int i)
{
    const dquat v = qval(q);
    (void)ts_close(c, v.w, ref.w, tol, "%s #%d w", label, i);
    (void)ts_close(c, v.x, ref.x, tol, "%s #%d x", label, i);
    (void)ts_close(c, v.y, ref.y, tol, "%s #%d y", label, i);
    (void)ts_close(c, v.z, ref.z, tol, "%s #%d z", label, i);
}

static void close_vec(ts_check *c, fc_vec3 v, int frac, dvec ref, double tol, const char *label, int i)
{
    const dvec a = vval(v, frac);
    (void)ts_close(c, a.x, ref.x, tol, "%s #%d x", label, i);
    (void)ts_close(c, a.y, ref.y, tol, "%s #%d y", label, i);
    (void)ts_close(c, a.z, ref.z, tol, "%s #%d z", label, i);
}

static void assert_quat_eq(fc_quat a, fc_quat b)
{
    TS_ASSERT_REAL_EQ(a.w, b.w);
    TS_ASSERT_REAL_EQ(a.x, b.x);
    TS_ASSERT_REAL_EQ(a.y, b.y);
    TS_ASSERT_REAL_EQ(a.z, b.z);
}

/* Tolerance of a unit-quaternion component: lsb UNIT LSB / ulps float ulps. */
static double qtol(double lsb, double ulps)
{
    return ts_tol(FC_UNIT_FRAC, lsb, ulps, 1.0);
}

/* ---- construction ---------------------------------------------------------- */

static void test_make_identity_vector_part(void **state)
{
    (void)state;
    const fc_quat q = fc_quat_make(FC_C(0.5f, UNIT), FC_C(-0.5f, UNIT), FC_C(0.25f, UNIT), FC_C(0.75f, UNIT));
    TS_ASSERT_REAL_EQ(q.w, FC_C(0.5f, UNIT));
    TS_ASSERT_REAL_EQ(q.x, FC_C(-0.5f, UNIT));
    TS_ASSERT_REAL_EQ(q.y, FC_C(0.25f, UNIT));
    TS_ASSERT_REAL_EQ(q.z, FC_C(0.75f, UNIT));
    const fc_quat id = fc_quat_identity();
    TS_ASSERT_CLOSE(ts_val(id.w, FC_UNIT_FRAC), 1.0, 0.0);
    TS_ASSERT_CLOSE(ts_val(id.x, FC_UNIT_FRAC), 0.0, 0.0);
    TS_ASSERT_CLOSE(ts_val(id.y, FC_UNIT_FRAC), 0.0, 0.0);
    TS_ASSERT_CLOSE(ts_val(id.z, FC_UNIT_FRAC), 0.0, 0.0);
    const fc_vec3 v = fc_quat_vector_part(q);
    TS_ASSERT_REAL_EQ(v.x, q.x);
    TS_ASSERT_REAL_EQ(v.y, q.y);
    TS_ASSERT_REAL_EQ(v.z, q.z);
}

/* ---- product ------------------------------------------------------------- */

static void test_mul_hand_computed(void **state)
{
    (void)state;
    fc_arith ar = {0};
    const fc_real one = FC_INT(1, UNIT), mone = FC_INT(-1, UNIT), zero = FC_INT(0, UNIT);
    const fc_quat i = fc_quat_make(zero, one, zero, zero);
    const fc_quat j = fc_quat_make(zero, zero, one, zero);
    const fc_quat k = fc_quat_make(zero, zero, zero, one);
    /* Hamilton: i j = k, j k = i, k i = j, j i = -k, i i = j j = k k = -1 */
    assert_quat_eq(fc_quat_mul(&ar, i, j), k);
    assert_quat_eq(fc_quat_mul(&ar, j, k), i);
    assert_quat_eq(fc_quat_mul(&ar, k, i), j);
    assert_quat_eq(fc_quat_mul(&ar, j, i), fc_quat_make(zero, zero, zero, mone));
    assert_quat_eq(fc_quat_mul(&ar, i, i), fc_quat_make(mone, zero, zero, zero));
    assert_quat_eq(fc_quat_mul(&ar, k, k), fc_quat_make(mone, zero, zero, zero));
    /* (1, 2, 3, 4) (5, 6, 7, 8) = (-60, 12, 30, 24), here scaled by 1/8 and 1/16 */
    const fc_quat p = fc_quat_make(FC_C(0.125f, UNIT), FC_C(0.25f, UNIT), FC_C(0.375f, UNIT), FC_C(0.5f, UNIT));
    const fc_quat q =
        fc_quat_make(FC_C(0.3125f, UNIT), FC_C(0.375f, UNIT), FC_C(0.4375f, UNIT), FC_C(0.5f, UNIT));
    assert_quat_eq(fc_quat_mul(&ar, p, q), fc_quat_make(FC_C(-0.46875f, UNIT), FC_C(0.09375f, UNIT),
                                                        FC_C(0.234375f, UNIT), FC_C(0.1875f, UNIT)));
    /* (1, 1, 1, 1)/2 (1, -1, 1, -1)/2 = (1, -1, 1, 1)/2 */
    const fc_real h = FC_C(0.5f, UNIT), mh = FC_C(-0.5f, UNIT);
    assert_quat_eq(fc_quat_mul(&ar, fc_quat_make(h, h, h, h), fc_quat_make(h, mh, h, mh)),
                   fc_quat_make(h, mh, h, h));
    assert_int_equal(ar.saturated, 0);
}

static void test_mul_random(void **state)
{
    (void)state;
    fc_arith ar = {0};
    ts_rng rng = ts_rng_seed(21u);
    ts_check c = ts_check_begin("quat mul vs Hamilton product");
    for (int n = 0; n < 3000; n++) {
        dquat rp, rq;
        const fc_quat p = quat_from_d(rand_unit_dquat(&rng), &rp);
        const fc_quat q = quat_from_d(rand_unit_dquat(&rng), &rq);
        /* fixed 4 UNIT LSB; float 4 ulps */
        close_quat(&c, fc_quat_mul(&ar, p, q), dq_mul(rp, rq), qtol(4.0, 4.0), "p q", n);
    }
    ts_check_end(&c);
    assert_int_equal(ar.saturated, 0);
}

static void test_mul_identity_associativity(void **state)
{
    (void)state;
    fc_arith ar = {0};
    ts_rng rng = ts_rng_seed(22u);
    const fc_quat id = fc_quat_identity();
    ts_check c = ts_check_begin("associativity and q q*");
    for (int n = 0; n < 2000; n++) {
        dquat rp, rq, rr;
        const fc_quat p = quat_from_d(rand_unit_dquat(&rng), &rp);
        const fc_quat q = quat_from_d(rand_unit_dquat(&rng), &rq);
        const fc_quat r = quat_from_d(rand_unit_dquat(&rng), &rr);
        /* the identity is neutral on both sides, exactly */
        assert_quat_eq(fc_quat_mul(&ar, p, id), p);
        assert_quat_eq(fc_quat_mul(&ar, id, p), p);
        /* (p q) r = p (q r): fixed 8 LSB, float 8 ulps */
        const fc_quat left = fc_quat_mul(&ar, fc_quat_mul(&ar, p, q), r);
        const fc_quat right = fc_quat_mul(&ar, p, fc_quat_mul(&ar, q, r));
        close_quat(&c, left, qval(right), qtol(8.0, 8.0), "(pq)r", n);
        close_quat(&c, left, dq_mul(dq_mul(rp, rq), rr), qtol(8.0, 8.0), "(pq)r ref", n);
        /* q q* = |q|^2 (1, 0, 0, 0) */
        const dquat qq = {rq.w * rq.w + rq.x * rq.x + rq.y * rq.y + rq.z * rq.z, 0.0, 0.0, 0.0};
        close_quat(&c, fc_quat_mul(&ar, q, fc_quat_conj(&ar, q)), qq, qtol(4.0, 4.0), "q q*", n);
    }
    ts_check_end(&c);
    assert_int_equal(ar.saturated, 0);
}

static void test_conj(void **state)
{
    (void)state;
    fc_arith ar = {0};
    ts_rng rng = ts_rng_seed(23u);
    ts_check chk = ts_check_begin("conj: exact");
    for (int n = 0; n < 500; n++) {
        dquat rq;
        const fc_quat q = quat_from_d(rand_unit_dquat(&rng), &rq);
        const fc_quat c = fc_quat_conj(&ar, q);
        /* exact: w kept, the vector part negated */
        close_quat(&chk, c, dq_conj(rq), 0.0, "conj", n);
        assert_quat_eq(fc_quat_conj(&ar, c), q);
    }
    ts_check_end(&chk);
    assert_quat_eq(fc_quat_conj(&ar, fc_quat_identity()), fc_quat_identity());
    assert_int_equal(ar.saturated, 0);
}

static void test_norm_sq(void **state)
{
    (void)state;
    fc_arith ar = {0};
    ts_rng rng = ts_rng_seed(24u);
    ts_check c = ts_check_begin("norm_sq");
    for (int n = 0; n < 3000; n++) {
        /* lengths 0.3 .. 1.4 (|q|^2 < 2, inside UNIT) */
        const double len = (double)ts_uniform(&rng, 0.3f, 1.4f);
        dquat rq;
        const fc_quat q = quat_from_d(dq_scale(rand_unit_dquat(&rng), len), &rq);
        const double ref = rq.w * rq.w + rq.x * rq.x + rq.y * rq.y + rq.z * rq.z;
        /* fixed: one rounding, 1 LSB; float: 8 ulps */
        (void)ts_close(&c, ts_val(fc_quat_norm_sq(&ar, q), FC_UNIT_FRAC), ref, ts_tol(FC_UNIT_FRAC, 1.0, 8.0, ref),
                       "#%d", n);
    }
    ts_check_end(&c);
    TS_ASSERT_REAL_EQ(fc_quat_norm_sq(&ar, fc_quat_identity()), FC_INT(1, UNIT));
    const fc_real h = FC_C(0.5f, UNIT);
    TS_ASSERT_REAL_EQ(fc_quat_norm_sq(&ar, fc_quat_make(h, -h, h, -h)), FC_INT(1, UNIT));
    TS_ASSERT_REAL_EQ(fc_quat_norm_sq(&ar, fc_quat_make(0, 0, 0, 0)), FC_INT(0, UNIT));
    assert_int_equal(ar.saturated, 0);
#if FC_NUMERIC_FIXED
    /* |q|^2 = 9 does not fit UNIT: saturates with the flag */
    const fc_real big = FC_C(1.5f, UNIT);
    TS_ASSERT_REAL_EQ(fc_quat_norm_sq(&ar, fc_quat_make(big, big, big, big)), FC_REAL_MAX);
    assert_int_equal(ar.saturated, 1);
#endif
}

/* ---- normalisation ---------------------------------------------------------- */

static void test_normalize(void **state)
{
    (void)state;
    fc_arith ar = {0};
    ts_rng rng = ts_rng_seed(25u);
    ts_check near = ts_check_begin("normalize near unit length");
    ts_check far = ts_check_begin("normalize far from unit length");
    for (int n = 0; n < 3000; n++) {
        /* near: |q|^2 within 2.5e-5 of 1 (the division-free path);
         * far: lengths 0.05 .. 1.4 */
        const bool is_near = (n % 2) == 0;
        const double len = is_near ? 1.0 + (double)ts_uniform(&rng, -1.2e-5f, 1.2e-5f)
                                   : (double)ts_uniform(&rng, 0.05f, 1.4f);
        dquat rq;
        const fc_quat q = quat_from_d(dq_scale(rand_unit_dquat(&rng), len), &rq);
        const double qn = dq_norm(rq);
        const dquat ref = dq_scale(rq, 1.0 / qn);
        bool ok = false;
        const fc_quat u = fc_quat_normalize(&ar, q, &ok);
        assert_true(ok);
        if (is_near) {
            /* fixed 4 UNIT LSB; float 4 ulps */
            close_quat(&near, u, ref, qtol(4.0, 4.0), "near", n);
        } else {
            /* fixed: 4 UNIT LSB + |u_i| 2 LSB of RATIO (1/|q| is held in RATIO) */
            const double rel = ts_fixed_rel(2.0, FC_RATIO_FRAC);
            const dquat v = qval(u);
            (void)ts_close(&far, v.w, ref.w, qtol(4.0, 4.0) + fabs(ref.w) * rel, "far #%d w", n);
            (void)ts_close(&far, v.x, ref.x, qtol(4.0, 4.0) + fabs(ref.x) * rel, "far #%d x", n);
            (void)ts_close(&far, v.y, ref.y, qtol(4.0, 4.0) + fabs(ref.y) * rel, "far #%d y", n);
            (void)ts_close(&far, v.z, ref.z, qtol(4.0, 4.0) + fabs(ref.z) * rel, "far #%d z", n);
        }
#if FC_NUMERIC_FIXED
        /* fixed: what the near path returns is unit to the format's
         * resolution and comes back unchanged (no rescaling by rounding
         * noise). The far path's factor is held in RATIO (2^-24), so its
         * result is near unit and takes the near path once more first. Float
         * promises no more than |q|^2 == 1 exactly being kept. */
        bool again_ok = false;
        const fc_quat near_unit = is_near ? u : fc_quat_normalize(&ar, u, &again_ok);
        const fc_quat again = fc_quat_normalize(&ar, near_unit, &again_ok);
        assert_true(again_ok);
        assert_quat_eq(again, near_unit);
#endif
    }
    ts_check_end(&near);
    ts_check_end(&far);
    assert_int_equal(ar.saturated, 0);

    /* a long quaternion (components 1.5, |q| = 3: |q|^2 overflows UNIT in
     * fixed): normalised without a saturation reported to the caller */
    bool ok = false;
    const fc_real big = FC_C(1.5f, UNIT);
    const fc_quat u = fc_quat_normalize(&ar, fc_quat_make(big, -big, big, big), &ok);
    assert_true(ok);
    ts_check c = ts_check_begin("normalize (1.5, -1.5, 1.5, 1.5)");
    const dquat half = {0.5, -0.5, 0.5, 0.5};
    close_quat(&c, u, half, qtol(4.0, 4.0) + ts_fixed_rel(1.0, FC_RATIO_FRAC), "long", 0);
    ts_check_end(&c);
    assert_int_equal(ar.saturated, 0);
    /* (1.9, 0, 0, 0) -> the identity */
    ok = false;
    const fc_quat w = fc_quat_normalize(&ar, fc_quat_make(FC_C(1.9f, UNIT), 0, 0, 0), &ok);
    assert_true(ok);
    TS_ASSERT_CLOSE(ts_val(w.w, FC_UNIT_FRAC), 1.0, qtol(4.0, 4.0) + ts_fixed_rel(1.0, FC_RATIO_FRAC));
    TS_ASSERT_REAL_EQ(w.x, FC_INT(0, UNIT));

    /* zero and too short (|q|^2 < 1e-4): the identity and ok = false */
    ok = true;
    assert_quat_eq(fc_quat_normalize(&ar, fc_quat_make(0, 0, 0, 0), &ok), fc_quat_identity());
    assert_false(ok);
    ok = true;
    const fc_real small = FC_C(0.005f, UNIT);
    assert_quat_eq(fc_quat_normalize(&ar, fc_quat_make(small, -small, 0, 0), &ok), fc_quat_identity());
    assert_false(ok);
#if !FC_NUMERIC_FIXED
    /* float: NaN or infinite components give the identity and ok = false */
    ok = true;
    assert_quat_eq(fc_quat_normalize(&ar, fc_quat_make(NAN, 0.5f, 0.5f, 0.5f), &ok), fc_quat_identity());
    assert_false(ok);
    ok = true;
    assert_quat_eq(fc_quat_normalize(&ar, fc_quat_make(0.5f, 0.5f, 0.5f, NAN), &ok), fc_quat_identity());
    assert_false(ok);
    ok = true;
    assert_quat_eq(fc_quat_normalize(&ar, fc_quat_make(0.5f, INFINITY, 0.0f, 0.0f), &ok), fc_quat_identity());
    assert_false(ok);
#endif
}

static void test_shortest(void **state)
{
    (void)state;
    fc_arith ar = {0};
    ts_rng rng = ts_rng_seed(26u);
    ts_check c = ts_check_begin("shortest: same rotation");
    for (int n = 0; n < 1000; n++) {
        dquat rq;
        const fc_quat q = quat_from_d(rand_unit_dquat(&rng), &rq);
        const fc_quat s = fc_quat_shortest(&ar, q);
        if (rq.w < 0.0) {
            assert_quat_eq(s, fc_quat_make(-q.w, -q.x, -q.y, -q.z));
        } else {
            assert_quat_eq(s, q);
        }
        assert_true(ts_val(s.w, FC_UNIT_FRAC) >= 0.0);
        /* q and -q are the same rotation */
        dvec rv;
        const fc_vec3 v = vec_in(0.3, -0.6, 0.7, FC_UNIT_FRAC, &rv);
        close_vec(&c, fc_quat_rotate(&ar, s, v), FC_UNIT_FRAC, dq_rotate_unit(rq, rv),
                  qtol(6.0, 8.0) + rotate_slack(rq, rv), "rot", n);
    }
    ts_check_end(&c);
    /* w = 0 is kept */
    const fc_quat k = fc_quat_make(0, 0, 0, FC_INT(-1, UNIT));
    assert_quat_eq(fc_quat_shortest(&ar, k), k);
    assert_int_equal(ar.saturated, 0);
}

/* ---- rotation ------------------------------------------------------------- */

/* Known quarter turns about each axis, in UNIT and in LENGTH (100 m). */
static void test_rotate_known_quarter_turns(void **state)
{
    (void)state;
    fc_arith ar = {0};
    const double r2 = sqrt(0.5);
    const struct {
        const char *name;
        double q[4];
        double v[3], expected[3];
    } cases[] = {
        /* about x: y -> z, z -> -y, x fixed */
        {"x: y->z", {r2, r2, 0, 0}, {0, 1, 0}, {0, 0, 1}},
        {"x: z->-y", {r2, r2, 0, 0}, {0, 0, 1}, {0, -1, 0}},
        {"x: x->x", {r2, r2, 0, 0}, {1, 0, 0}, {1, 0, 0}},
        /* about y: z -> x, x -> -z */
        {"y: z->x", {r2, 0, r2, 0}, {0, 0, 1}, {1, 0, 0}},
        {"y: x->-z", {r2, 0, r2, 0}, {1, 0, 0}, {0, 0, -1}},
        {"y: y->y", {r2, 0, r2, 0}, {0, 1, 0}, {0, 1, 0}},
        /* about z: x -> y, y -> -x */
        {"z: x->y", {r2, 0, 0, r2}, {1, 0, 0}, {0, 1, 0}},
        {"z: y->-x", {r2, 0, 0, r2}, {0, 1, 0}, {-1, 0, 0}},
        {"z: z->z", {r2, 0, 0, r2}, {0, 0, 1}, {0, 0, 1}},
        /* about -z: x -> -y */
        {"-z: x->-y", {r2, 0, 0, -r2}, {1, 0, 0}, {0, -1, 0}},
        /* half turn about x: y -> -y */
        {"x 180: y->-y", {0, 1, 0, 0}, {0, 1, 0}, {0, -1, 0}},
    };
    const struct {
        int frac;
        double scale;
    } formats[] = {{FC_UNIT_FRAC, 0.9}, {FC_LENGTH_FRAC, 100.0}, {FC_ACCEL_FRAC, 9.81}};
    for (size_t f = 0; f < sizeof formats / sizeof formats[0]; f++) {
        const int frac = formats[f].frac;
        const double s = formats[f].scale;
        ts_check c = ts_check_begin("rotate quarter turns");
        for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
            dquat rq;
            const fc_quat q = quat_in(cases[k].q[0], cases[k].q[1], cases[k].q[2], cases[k].q[3], &rq);
            dvec rv;
            const fc_vec3 v = vec_in(s * cases[k].v[0], s * cases[k].v[1], s * cases[k].v[2], frac, &rv);
            const fc_vec3 out = fc_quat_rotate(&ar, q, v);
            const double slack = rotate_slack(rq, rv);
            /* against the rotation by the quantised q: fixed 6 LSB of the
             * vector's format, float 8 ulps of |v| */
            close_vec(&c, out, frac, dq_rotate_unit(rq, rv), ts_tol(frac, 6.0, 8.0, s) + slack, cases[k].name,
                      (int)f);
            /* against the ideal result: plus 4 |dq| |v| for the rounding of q */
            const dquat ideal_q = {cases[k].q[0], cases[k].q[1], cases[k].q[2], cases[k].q[3]};
            const double dq = fmax(fmax(fabs(rq.w - ideal_q.w), fabs(rq.x - ideal_q.x)),
                                   fmax(fabs(rq.y - ideal_q.y), fabs(rq.z - ideal_q.z)));
            const double sq = dv_norm(rv); /* the quantised length of v */
            const dvec ideal = {sq * cases[k].expected[0], sq * cases[k].expected[1], sq * cases[k].expected[2]};
            close_vec(&c, out, frac, ideal, ts_tol(frac, 6.0, 8.0, s) + slack + 4.0 * dq * s, cases[k].name,
                      (int)f);
            /* and back */
            close_vec(&c, fc_quat_rotate_inv(&ar, q, out), frac, rv, ts_tol(frac, 12.0, 16.0, s) + 2.0 * slack,
                      cases[k].name, (int)f);
        }
        ts_check_end(&c);
    }
    /* the identity leaves a vector alone, exactly */
    const fc_vec3 v = fc_vec3_make(FC_INT(100, LENGTH), FC_INT(-7, LENGTH), FC_C(0.5f, LENGTH));
    const fc_vec3 same = fc_quat_rotate(&ar, fc_quat_identity(), v);
    TS_ASSERT_REAL_EQ(same.x, v.x);
    TS_ASSERT_REAL_EQ(same.y, v.y);
    TS_ASSERT_REAL_EQ(same.z, v.z);
    assert_int_equal(ar.saturated, 0);
}

static void test_rotate_random_and_inverse(void **state)
{
    (void)state;
    fc_arith ar = {0};
    ts_rng rng = ts_rng_seed(27u);
    const struct {
        const char *name;
        int frac;
        float r;
    } formats[] = {{"rotate UNIT", FC_UNIT_FRAC, 0.55f},
                   {"rotate LENGTH", FC_LENGTH_FRAC, 550.0f},
                   {"rotate RATE", FC_RATE_FRAC, 35.0f}};
    for (size_t f = 0; f < sizeof formats / sizeof formats[0]; f++) {
        const int frac = formats[f].frac;
        ts_check c = ts_check_begin(formats[f].name);
        for (int n = 0; n < 2000; n++) {
            dquat rq;
            const fc_quat q = quat_from_d(rand_unit_dquat(&rng), &rq);
            dvec rv;
            const float r = formats[f].r;
            const fc_vec3 v = vec_in((double)ts_uniform(&rng, -r, r), (double)ts_uniform(&rng, -r, r),
                                     (double)ts_uniform(&rng, -r, r), frac, &rv);
            const double mag = dv_norm(rv);
            const double slack = rotate_slack(rq, rv);
            const fc_vec3 out = fc_quat_rotate(&ar, q, v);
            close_vec(&c, out, frac, dq_rotate_unit(rq, rv), ts_tol(frac, 6.0, 8.0, mag) + slack, "rotate", n);
            close_vec(&c, fc_quat_rotate_inv(&ar, q, v), frac, dq_rotate_unit(dq_conj(rq), rv),
                      ts_tol(frac, 6.0, 8.0, mag) + slack, "rotate_inv", n);
            /* round trip */
            close_vec(&c, fc_quat_rotate_inv(&ar, q, out), frac, rv, ts_tol(frac, 12.0, 16.0, mag) + 2.0 * slack,
                      "back", n);
        }
        ts_check_end(&c);
    }
    assert_int_equal(ar.saturated, 0);
}

/* fc_quat_rotate_horizontal: x and y of the rotation from R(q)'s rows with q
 * and the entries rounded to UNIT16, each entry within 2^-13 + 2^-15 of
 * R(q)'s (q's rounding moves 2(ab +- cd) by 2 x 2^-15 x (|a| + |b| + |c| +
 * |d|) <= 2^-13 at most, the entry's own by 2^-15); z is 0. Accelerations
 * up to 16 g. */
static void test_rotate_horizontal(void **state)
{
    (void)state;
    fc_arith ar = {0};
    ts_rng rng = ts_rng_seed(31u);
    ts_check c = ts_check_begin("rotate_horizontal ACCEL");
    const double entry_error = FC_NUMERIC_FIXED ? ldexp(1.0, -13) + ldexp(1.0, -15) : 0.0;
    for (int n = 0; n < 4000; n++) {
        dquat rq;
        const fc_quat q = quat_from_d(rand_unit_dquat(&rng), &rq);
        dvec rv;
        const float r = 160.0f;
        const fc_vec3 v = vec_in((double)ts_uniform(&rng, -r, r), (double)ts_uniform(&rng, -r, r),
                                 (double)ts_uniform(&rng, -r, r), FC_ACCEL_FRAC, &rv);
        const double l1 = fabs(rv.x) + fabs(rv.y) + fabs(rv.z);
        dvec want = dq_rotate_unit(rq, rv);
        want.z = 0.0;
        const double tol = ts_tol(FC_ACCEL_FRAC, 4.0, 8.0, dv_norm(rv)) + entry_error * l1 + rotate_slack(rq, rv);
        close_vec(&c, fc_quat_rotate_horizontal(&ar, q, v), FC_ACCEL_FRAC, want, tol, "rotate_horizontal", n);
    }
    ts_check_end(&c);
    assert_int_equal(ar.saturated, 0);
}

/* Vectors of more than half their format's range (LENGTH: 1500 m of 2048 m)
 * rotate to vectors that fit; no intermediate may saturate. */
static void test_rotate_large_vector(void **state)
{
    (void)state;
    fc_arith ar = {0};
    const double r2 = sqrt(0.5);
    const struct {
        double q[4];
        double v[3];
    } cases[] = {
        {{r2, 0, 0, r2}, {1500, 0, 0}},     /* 90 deg about z: (0, 1500, 0) */
        {{0, 0, 0, 1}, {1500, 0, 0}},       /* 180 deg about z: (-1500, 0, 0) */
        {{r2, r2, 0, 0}, {0, 1200, -1200}}, /* 90 deg about x */
        {{0.5, 0.5, 0.5, 0.5}, {1000, -1000, 1000}},
    };
    ts_check c = ts_check_begin("rotate LENGTH vectors of 1500 m");
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        dquat rq;
        const fc_quat q = quat_in(cases[k].q[0], cases[k].q[1], cases[k].q[2], cases[k].q[3], &rq);
        dvec rv;
        const fc_vec3 v = vec_in(cases[k].v[0], cases[k].v[1], cases[k].v[2], FC_LENGTH_FRAC, &rv);
        const double tol = ts_tol(FC_LENGTH_FRAC, 6.0, 8.0, dv_norm(rv)) + rotate_slack(rq, rv);
        close_vec(&c, fc_quat_rotate(&ar, q, v), FC_LENGTH_FRAC, dq_rotate_unit(rq, rv), tol, "rotate", (int)k);
        close_vec(&c, fc_quat_rotate_inv(&ar, q, v), FC_LENGTH_FRAC, dq_rotate_unit(dq_conj(rq), rv), tol,
                  "rotate_inv", (int)k);
    }
    ts_check_end(&c);
    assert_int_equal(ar.saturated, 0);
}

/* ---- axis-angle ------------------------------------------------------------ */

static void test_axis_angle(void **state)
{
    (void)state;
    fc_arith ar = {0};
    ts_rng rng = ts_rng_seed(28u);
    ts_check from = ts_check_begin("from_axis_angle");
    ts_check to = ts_check_begin("to_axis_angle");
    ts_check trip = ts_check_begin("axis-angle round trip");
    for (int n = 0; n < 3000; n++) {
        dvec ra;
        const dvec axis_d = rand_unit_dvec(&rng);
        const fc_vec3 axis = vec_in(axis_d.x, axis_d.y, axis_d.z, FC_UNIT_FRAC, &ra);
        double rang;
        const fc_real angle = ts_in(ts_uniform(&rng, 0.02f, 3.12f), FC_ANGLE_FRAC, &rang);
        const fc_quat q = fc_quat_from_axis_angle(&ar, axis, angle);
        /* fixed 8 UNIT LSB, float 4 ulps */
        close_quat(&from, q, dq_axis_angle(ra, rang), qtol(8.0, 4.0), "from", n);

        /* to_axis_angle against the double result for the same quaternion */
        fc_vec3 axis_out;
        fc_real angle_out;
        fc_quat_to_axis_angle(&ar, q, &axis_out, &angle_out);
        const dquat rq = qval(q);
        const double sin_half = sqrt(rq.x * rq.x + rq.y * rq.y + rq.z * rq.z);
        const double ang_ref = 2.0 * atan2(sin_half, rq.w);
        (void)ts_close(&to, ts_val(angle_out, FC_ANGLE_FRAC), ang_ref, ts_tol(FC_ANGLE_FRAC, 10.0, 4.0, ang_ref),
                       "angle #%d", n);
        const dvec ax_ref = {rq.x / sin_half, rq.y / sin_half, rq.z / sin_half};
        /* fixed: 1 UNIT LSB + 0.6 UNIT LSB / |v| (normalize of the vector part) */
        const double ax_tol = qtol(1.0, 4.0) + ts_fixed_rel(0.6 / sin_half, FC_UNIT_FRAC);
        close_vec(&to, axis_out, FC_UNIT_FRAC, ax_ref, ax_tol, "axis", n);

        /* the round trip gives back the axis and the angle: those of the
         * quantised axis, which is unit only to its input rounding */
        const double an = dv_norm(ra);
        const dvec ra_unit = {ra.x / an, ra.y / an, ra.z / an};
        const double rang_trip = 2.0 * atan2(an * sin(rang / 2.0), cos(rang / 2.0));
        (void)ts_close(&trip, ts_val(angle_out, FC_ANGLE_FRAC), rang_trip,
                       ts_tol(FC_ANGLE_FRAC, 10.0, 8.0, rang) + ts_tol(FC_UNIT_FRAC, 16.0, 8.0, 1.0), "angle #%d",
                       n);
        close_vec(&trip, axis_out, FC_UNIT_FRAC, ra_unit,
                  qtol(2.0, 8.0) + ts_tol(FC_UNIT_FRAC, 10.0, 8.0, 1.0) / sin(rang / 2.0), "axis", n);
    }
    ts_check_end(&from);
    ts_check_end(&to);
    ts_check_end(&trip);

    /* the identity: axis x, angle 0, exactly */
    fc_vec3 axis_out;
    fc_real angle_out;
    fc_quat_to_axis_angle(&ar, fc_quat_identity(), &axis_out, &angle_out);
    TS_ASSERT_REAL_EQ(angle_out, FC_INT(0, ANGLE));
    TS_ASSERT_REAL_EQ(axis_out.x, FC_INT(1, UNIT));
    TS_ASSERT_REAL_EQ(axis_out.y, FC_INT(0, UNIT));
    TS_ASSERT_REAL_EQ(axis_out.z, FC_INT(0, UNIT));
    /* zero angle about any axis is the identity */
    const fc_quat z = fc_quat_from_axis_angle(&ar, fc_vec3_make(0, FC_INT(1, UNIT), 0), FC_INT(0, ANGLE));
    assert_quat_eq(z, fc_quat_identity());
    /* -q (w < 0) is the same rotation: angle in [0, pi], same axis */
    dvec ra;
    const fc_vec3 axis = vec_in(0.0, 0.6, -0.8, FC_UNIT_FRAC, &ra);
    double rang;
    const fc_real angle = ts_in(2.5f, FC_ANGLE_FRAC, &rang);
    const fc_quat q = fc_quat_from_axis_angle(&ar, axis, angle);
    fc_quat_to_axis_angle(&ar, fc_quat_make(-q.w, -q.x, -q.y, -q.z), &axis_out, &angle_out);
    const double an = dv_norm(ra);
    const dvec ra_unit = {ra.x / an, ra.y / an, ra.z / an};
    TS_ASSERT_CLOSE(ts_val(angle_out, FC_ANGLE_FRAC), 2.0 * atan2(an * sin(rang / 2.0), cos(rang / 2.0)),
                    ts_tol(FC_ANGLE_FRAC, 10.0, 8.0, rang) + ts_tol(FC_UNIT_FRAC, 16.0, 8.0, 1.0));
    ts_check c = ts_check_begin("to_axis_angle of -q");
    close_vec(&c, axis_out, FC_UNIT_FRAC, ra_unit, qtol(12.0, 8.0), "axis", 0);
    ts_check_end(&c);
    /* a half turn: angle pi */
    fc_quat_to_axis_angle(&ar, fc_quat_make(0, 0, 0, FC_INT(1, UNIT)), &axis_out, &angle_out);
    TS_ASSERT_CLOSE(ts_val(angle_out, FC_ANGLE_FRAC), TS_PI, ts_tol(FC_ANGLE_FRAC, 10.0, 4.0, TS_PI));
    TS_ASSERT_REAL_EQ(axis_out.z, FC_INT(1, UNIT));
    assert_int_equal(ar.saturated, 0);
}

/* ---- exponential map ---------------------------------------------------------- */

/* Tolerance of from_rotation_vector at angle a (rad): the series branch below
 * 0.5 rad is 4 UNIT LSB, the sin/cos branch 8 + 1 per rad; float 4 ulps. */
static double rotvec_tol(double a)
{
    return a < 0.5 ? qtol(4.0, 4.0) : qtol(8.0 + a, 4.0);
}

static void test_from_rotation_vector(void **state)
{
    (void)state;
    fc_arith ar = {0};
    ts_rng rng = ts_rng_seed(29u);
    /* zero: the identity, exactly */
    assert_quat_eq(fc_quat_from_rotation_vector(&ar, fc_vec3_zero()), fc_quat_identity());
    const struct {
        const char *name;
        float lo, hi;
    } ranges[] = {{"rotation vector |theta| < 1e-3", 1.0e-6f, 1.0e-3f},
                  {"rotation vector |theta| < 0.5 (series)", 1.0e-3f, 0.4999f},
                  {"rotation vector 0.5 <= |theta| < pi", 0.5001f, 3.1f},
                  {"rotation vector pi < |theta| < 6", 3.2f, 6.0f}};
    for (size_t k = 0; k < sizeof ranges / sizeof ranges[0]; k++) {
        ts_check c = ts_check_begin(ranges[k].name);
        for (int n = 0; n < 2000; n++) {
            const dvec axis = rand_unit_dvec(&rng);
            const double a = (double)ts_uniform(&rng, ranges[k].lo, ranges[k].hi);
            dvec rt;
            const fc_vec3 theta = vec_in(axis.x * a, axis.y * a, axis.z * a, FC_ANGLE_FRAC, &rt);
            const fc_quat q = fc_quat_from_rotation_vector(&ar, theta);
            const double ra = sqrt(rt.x * rt.x + rt.y * rt.y + rt.z * rt.z);
            close_quat(&c, q, dq_rotation_vector(rt), rotvec_tol(ra), "exp", n);
            /* unit length */
            (void)ts_close(&c, dq_norm(qval(q)), 1.0, 2.0 * rotvec_tol(ra), "|q| #%d", n);
        }
        ts_check_end(&c);
    }
    assert_int_equal(ar.saturated, 0);
}

/* The branches meet at 0.5 rad, and the series' cuts at 2^-10 and 2^-5 rad
 * (a^2 = 2^-20, 2^-10): the step across each switch is the one of the exact
 * function. */
static void test_rotation_vector_continuity(void **state)
{
    (void)state;
    fc_arith ar = {0};
    const dvec axes[] = {{1.0, 0.0, 0.0}, {0.0, 0.0, -1.0}, {1.0 / 3.0, 2.0 / 3.0, -2.0 / 3.0}};
    const double switches[] = {1.0 / 1024.0, 1.0 / 32.0, 0.5};
    ts_check c = ts_check_begin("continuity at 2^-10, 2^-5 and 0.5 rad");
    for (size_t k = 0; k < sizeof axes / sizeof axes[0] * 3u; k++) {
        const dvec axis = axes[k / 3u];
        const double at = switches[k % 3u];
        for (int d = 1; d <= 64; d *= 2) {
            /* d ANGLE LSB (or d float steps) below and above the switch */
            const double step = ts_resolution(FC_ANGLE_FRAC) * d;
            dvec rlo, rhi;
            const double alo = at - step, ahi = at + step;
            const fc_vec3 tlo = vec_in(axis.x * alo, axis.y * alo, axis.z * alo, FC_ANGLE_FRAC, &rlo);
            const fc_vec3 thi = vec_in(axis.x * ahi, axis.y * ahi, axis.z * ahi, FC_ANGLE_FRAC, &rhi);
            const fc_quat qlo = fc_quat_from_rotation_vector(&ar, tlo);
            const fc_quat qhi = fc_quat_from_rotation_vector(&ar, thi);
            /* each side against the exact function */
            close_quat(&c, qlo, dq_rotation_vector(rlo), rotvec_tol(0.5), "below", d);
            close_quat(&c, qhi, dq_rotation_vector(rhi), rotvec_tol(0.5), "above", d);
            /* the jump across the switch against the exact jump */
            const dquat vlo = qval(qlo), vhi = qval(qhi);
            const dquat elo = dq_rotation_vector(rlo), ehi = dq_rotation_vector(rhi);
            const double tol = rotvec_tol(0.4) + rotvec_tol(0.5);
            (void)ts_close(&c, vhi.w - vlo.w, ehi.w - elo.w, tol, "jump w, %d LSB", d);
            (void)ts_close(&c, vhi.x - vlo.x, ehi.x - elo.x, tol, "jump x, %d LSB", d);
            (void)ts_close(&c, vhi.y - vlo.y, ehi.y - elo.y, tol, "jump y, %d LSB", d);
            (void)ts_close(&c, vhi.z - vlo.z, ehi.z - elo.z, tol, "jump z, %d LSB", d);
        }
    }
    ts_check_end(&c);
    assert_int_equal(ar.saturated, 0);
}

/* ---- roll, pitch, yaw ---------------------------------------------------------- */

static void test_rpy(void **state)
{
    (void)state;
    fc_arith ar = {0};
    ts_check from = ts_check_begin("from_rpy");
    ts_check to = ts_check_begin("to_rpy of the same quaternion");
    ts_check trip = ts_check_begin("rpy round trip");
    const int steps = 14;
    int n = 0;
    for (int i = 0; i <= steps; i++) {
        for (int j = 0; j <= steps; j++) {
            for (int k = 0; k <= steps; k++, n++) {
                double rr, rp, ry;
                const fc_real roll = ts_in(-3.1f + 6.2f * (float)i / (float)steps, FC_ANGLE_FRAC, &rr);
                const fc_real pitch = ts_in(-1.5f + 3.0f * (float)j / (float)steps, FC_ANGLE_FRAC, &rp);
                const fc_real yaw = ts_in(-3.1f + 6.2f * (float)k / (float)steps + 0.013f, FC_ANGLE_FRAC, &ry);
                const fc_quat q = fc_quat_from_rpy(&ar, roll, pitch, yaw);
                /* fixed 12 UNIT LSB, float 6 ulps */
                close_quat(&from, q, dq_rpy(rr, rp, ry), qtol(12.0, 6.0), "from_rpy", n);

                const fc_vec3 e = fc_quat_to_rpy(&ar, q);
                const dvec got = vval(e, FC_ANGLE_FRAC);
                /* the double Euler angles of the quaternion actually passed */
                const dquat d = qval(q);
                const double roll_ref =
                    atan2(2.0 * (d.w * d.x + d.y * d.z), 1.0 - 2.0 * (d.x * d.x + d.y * d.y));
                const double pitch_ref = asin(fmax(-1.0, fmin(1.0, 2.0 * (d.w * d.y - d.z * d.x))));
                const double yaw_ref = atan2(2.0 * (d.w * d.z + d.x * d.y), 1.0 - 2.0 * (d.y * d.y + d.z * d.z));
                const double cond = 1.0 / cos(rp);
                const double res = ts_resolution(FC_UNIT_FRAC);
                (void)ts_close(&to, got.x, roll_ref, ts_tol(FC_ANGLE_FRAC, 4.0, 4.0, roll_ref) + 6.0 * res * cond,
                               "roll #%d", n);
                (void)ts_close(&to, got.y, pitch_ref,
                               ts_tol(FC_ANGLE_FRAC, 4.0, 4.0, pitch_ref) + 6.0 * res * cond, "pitch #%d", n);
                (void)ts_close(&to, got.z, yaw_ref, ts_tol(FC_ANGLE_FRAC, 4.0, 4.0, yaw_ref) + 6.0 * res * cond,
                               "yaw #%d", n);
                /* round trip: from_rpy's error (12 LSB / 6 ulps per component)
                 * becomes an angle error of up to 4x that over cos(pitch) */
                const double trip_tol = ts_tol(FC_ANGLE_FRAC, 4.0, 4.0, TS_PI) + 54.0 * res * cond;
                (void)ts_close(&trip, wrap_pi(got.x - rr), 0.0, trip_tol, "roll #%d", n);
                (void)ts_close(&trip, got.y - rp, 0.0, trip_tol, "pitch #%d", n);
                (void)ts_close(&trip, wrap_pi(got.z - ry), 0.0, trip_tol, "yaw #%d", n);
            }
        }
    }
    ts_check_end(&from);
    ts_check_end(&to);
    ts_check_end(&trip);
    /* zero angles: the identity, exactly */
    assert_quat_eq(fc_quat_from_rpy(&ar, 0, 0, 0), fc_quat_identity());
    const fc_vec3 zero = fc_quat_to_rpy(&ar, fc_quat_identity());
    TS_ASSERT_REAL_EQ(zero.x, FC_INT(0, ANGLE));
    TS_ASSERT_REAL_EQ(zero.y, FC_INT(0, ANGLE));
    TS_ASSERT_REAL_EQ(zero.z, FC_INT(0, ANGLE));
    assert_int_equal(ar.saturated, 0);
}

/* fc_quat_from_up against the double quaternion of the Euler angles of the
 * up vector actually passed: roll atan2(y, z), pitch atan2(-x, |(y, z)|),
 * over the tilts from level to upside down, three lengths and three yaws.
 * Tolerance: a few UNIT LSB / float ulps, plus the ACCEL rounding of the
 * lengths (hypot3) relative to h = |(y, z)|: roll's cosine and sine are
 * z / h and y / h, so near pitch +-pi/2 (h small) roll is as ill-conditioned
 * as atan2(y, z) itself. */
static void test_from_up(void **state)
{
    (void)state;
    fc_arith ar = {0};
    ts_check c = ts_check_begin("from_up");
    const double lengths[] = {9.81, 0.5, 60.0};
    const float yaws[] = {0.0f, 0.7f, -2.9f};
    const int steps = 16;
    int n = 0;
    for (int l = 0; l < 3; l++) {
        for (int k = 0; k < 3; k++) {
            double yaw_ref;
            const fc_real yaw = ts_in(yaws[k], FC_ANGLE_FRAC, &yaw_ref);
            for (int i = 0; i <= steps; i++) {
                for (int j = 0; j <= steps; j++, n++) {
                    const double roll = -3.1 + 6.2 * i / steps, pitch = -1.55 + 3.1 * j / steps;
                    double x, y, z;
                    const fc_vec3 up = fc_vec3_make(
                        ts_in((float)(-lengths[l] * sin(pitch)), FC_ACCEL_FRAC, &x),
                        ts_in((float)(lengths[l] * sin(roll) * cos(pitch)), FC_ACCEL_FRAC, &y),
                        ts_in((float)(lengths[l] * cos(roll) * cos(pitch)), FC_ACCEL_FRAC, &z));
                    const dquat ref = dq_rpy(atan2(y, z), atan2(-x, hypot(y, z)), yaw_ref);
                    const double tol = qtol(16.0, 16.0) + 4.0 * ts_resolution(FC_ACCEL_FRAC) / hypot(y, z);
                    close_quat(&c, fc_quat_from_up(&ar, up, yaw), ref, tol, "from_up", n);
                }
            }
        }
    }
    ts_check_end(&c);
    ts_check special = ts_check_begin("from_up, special cases");
    /* upside down, level: roll pi */
    double unused;
    const fc_vec3 down = fc_vec3_make(FC_INT(0, ACCEL), FC_INT(0, ACCEL), ts_in(-9.81f, FC_ACCEL_FRAC, &unused));
    close_quat(&special, fc_quat_from_up(&ar, down, FC_INT(0, ANGLE)), dq_rpy(TS_PI, 0.0, 0.0), qtol(4.0, 4.0), "down", 0);
    /* up along body x: no roll defined, roll 0 and pitch -pi/2 */
    const fc_vec3 along_x = fc_vec3_make(ts_in(9.81f, FC_ACCEL_FRAC, &unused), FC_INT(0, ACCEL), FC_INT(0, ACCEL));
    close_quat(&special, fc_quat_from_up(&ar, along_x, FC_INT(0, ANGLE)), dq_rpy(0.0, -TS_PI / 2.0, 0.0), qtol(4.0, 4.0),
               "along x", 0);
    ts_check_end(&special);
    /* level, and no vector at all: the identity, exactly */
    const fc_vec3 level = fc_vec3_make(FC_INT(0, ACCEL), FC_INT(0, ACCEL), ts_in(9.81f, FC_ACCEL_FRAC, &unused));
    assert_quat_eq(fc_quat_from_up(&ar, level, FC_INT(0, ANGLE)), fc_quat_identity());
    assert_quat_eq(fc_quat_from_up(&ar, fc_vec3_make(FC_INT(0, ACCEL), FC_INT(0, ACCEL), FC_INT(0, ACCEL)),
                                   FC_INT(0, ANGLE)),
                   fc_quat_identity());
    assert_int_equal(ar.saturated, 0);
}

/* ---- integration -------------------------------------------------------------- */

#define STEPS 500

/* N steps of a constant rate: tolerance N (0.5 ANGLE LSB + 4 UNIT LSB) in
 * fixed (each step's rotation angle is rounded to ANGLE, each product and
 * renormalisation to UNIT), N 2 ulps in float. */
static double integration_tol(int steps)
{
    return (double)steps * (ts_tol(FC_ANGLE_FRAC, 0.5, 0.0, 0.0) + ts_tol(FC_UNIT_FRAC, 4.0, 2.0, 1.0));
}

typedef fc_quat (*integrate_fn)(fc_arith *, fc_quat, fc_vec3, fc_real);

/* Integrates STEPS steps, checking |q| = 1 at each. */
static fc_quat integrate(fc_arith *ar, integrate_fn fn, fc_quat q, fc_vec3 rate, fc_real dt, ts_check *unit)
{
    for (int n = 0; n < STEPS; n++) {
        q = fn(ar, q, rate, dt);
        /* fixed 8 UNIT LSB, float 8 ulps */
        (void)ts_close(unit, dq_norm(qval(q)), 1.0, qtol(8.0, 8.0), "|q| step %d", n);
    }
    return q;
}

static void test_integrate_closed_form(void **state)
{
    (void)state;
    fc_arith ar = {0};
    double rdt;
    const fc_real dt = ts_in(0.002f, FC_DT_FRAC, &rdt);
    const struct {
        const char *name;
        double axis[3];
        double rate;
        double q0_axis[3];
        double q0_angle;
    } cases[] = {
        {"1 rad/s about x from identity", {1, 0, 0}, 1.0, {1, 0, 0}, 0.0},
        {"1 rad/s about (1,2,-2)/3 from identity", {1.0 / 3, 2.0 / 3, -2.0 / 3}, 1.0, {1, 0, 0}, 0.0},
        {"-2 rad/s about z from a tilt", {0, 0, 1}, -2.0, {0.6, 0.8, 0}, 0.9},
        {"3 rad/s about (0,0.6,0.8) from a yaw", {0, 0.6, 0.8}, 3.0, {0, 0, 1}, -2.0},
        {"30 rad/s about y, a fast flip", {0, 1, 0}, 30.0, {1, 0, 0}, 0.3},
    };
    ts_check unit = ts_check_begin("|q| = 1 while integrating");
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        ts_check c = ts_check_begin(cases[k].name);
        dvec rrate, rax;
        const double w = cases[k].rate;
        const fc_vec3 rate = vec_in(cases[k].axis[0] * w, cases[k].axis[1] * w, cases[k].axis[2] * w,
                                    FC_RATE_FRAC, &rrate);
        (void)vec_in(cases[k].q0_axis[0], cases[k].q0_axis[1], cases[k].q0_axis[2], FC_UNIT_FRAC, &rax);
        dquat rq0;
        const fc_quat q0 = quat_from_d(dq_axis_angle(rax, cases[k].q0_angle), &rq0);
        /* closed form over STEPS dt for the quantised rate and dt */
        const double t = STEPS * rdt;
        const dvec theta = {rrate.x * t, rrate.y * t, rrate.z * t};
        const dquat step_total = dq_rotation_vector(theta);
        const fc_quat qb = integrate(&ar, fc_quat_integrate_body_rate, q0, rate, dt, &unit);
        const fc_quat qw = integrate(&ar, fc_quat_integrate_world_rate, q0, rate, dt, &unit);
        /* body: q0 exp(w t / 2); world: exp(w t / 2) q0 */
        close_quat(&c, qb, dq_mul(rq0, step_total), integration_tol(STEPS), "body", (int)k);
        close_quat(&c, qw, dq_mul(step_total, rq0), integration_tol(STEPS), "world", (int)k);
        ts_check_end(&c);
    }
    ts_check_end(&unit);
    assert_int_equal(ar.saturated, 0);
}

/* With the rate along the current rotation axis, q and the step commute: the
 * body and the world forms give the same attitude. Across that axis they
 * must not. */
static void test_integrate_body_vs_world(void **state)
{
    (void)state;
    fc_arith ar = {0};
    double rdt;
    const fc_real dt = ts_in(0.002f, FC_DT_FRAC, &rdt);
    ts_check unit = ts_check_begin("|q| = 1 while integrating");
    ts_check c = ts_check_begin("body = world for a rate along the axis of q");
    const dvec axes[] = {{1.0, 0.0, 0.0}, {0.0, 0.6, -0.8}, {2.0 / 3, -1.0 / 3, 2.0 / 3}};
    for (size_t k = 0; k < sizeof axes / sizeof axes[0]; k++) {
        dvec rax, rrate;
        (void)vec_in(axes[k].x, axes[k].y, axes[k].z, FC_UNIT_FRAC, &rax);
        dquat rq0;
        const fc_quat q0 = quat_from_d(dq_axis_angle(rax, 0.7), &rq0);
        const fc_vec3 rate = vec_in(axes[k].x * 1.5, axes[k].y * 1.5, axes[k].z * 1.5, FC_RATE_FRAC, &rrate);
        const fc_quat qb = integrate(&ar, fc_quat_integrate_body_rate, q0, rate, dt, &unit);
        const fc_quat qw = integrate(&ar, fc_quat_integrate_world_rate, q0, rate, dt, &unit);
        close_quat(&c, qb, qval(qw), integration_tol(STEPS), "body vs world", (int)k);
    }
    ts_check_end(&c);
    ts_check_end(&unit);
    /* a rate across the axis of q: the two forms differ by the exact amount */
    dvec rrate;
    const fc_vec3 rate = vec_in(0.0, 0.0, 1.5, FC_RATE_FRAC, &rrate);
    dquat rq0;
    const dvec ex = {1.0, 0.0, 0.0};
    const fc_quat q0 = quat_from_d(dq_axis_angle(ex, 0.7), &rq0);
    ts_check u2 = ts_check_begin("|q| = 1 while integrating");
    const dquat qb = qval(integrate(&ar, fc_quat_integrate_body_rate, q0, rate, dt, &u2));
    const dquat qw = qval(integrate(&ar, fc_quat_integrate_world_rate, q0, rate, dt, &u2));
    ts_check_end(&u2);
    const double t = STEPS * rdt;
    const dvec theta = {0.0, 0.0, rrate.z * t};
    const dquat eb = dq_mul(rq0, dq_rotation_vector(theta)), ew = dq_mul(dq_rotation_vector(theta), rq0);
    const double diff = fabs(qb.y - qw.y) + fabs(qb.z - qw.z);
    assert_true(diff > 0.1);
    TS_ASSERT_CLOSE(qb.y - qw.y, eb.y - ew.y, 2.0 * integration_tol(STEPS));
    assert_int_equal(ar.saturated, 0);
}

static void test_integrate_zero_rate(void **state)
{
    (void)state;
    fc_arith ar = {0};
    ts_rng rng = ts_rng_seed(30u);
    const fc_real dt = FC_C(0.002f, DT);
    ts_check c = ts_check_begin("zero rate keeps q");
    for (int n = 0; n < 200; n++) {
        dquat rq;
        const fc_quat q = quat_from_d(rand_unit_dquat(&rng), &rq);
        const dquat ref = dq_scale(rq, 1.0 / dq_norm(rq));
        close_quat(&c, fc_quat_integrate_body_rate(&ar, q, fc_vec3_zero(), dt), ref, qtol(4.0, 4.0), "body", n);
        close_quat(&c, fc_quat_integrate_world_rate(&ar, q, fc_vec3_zero(), dt), ref, qtol(4.0, 4.0), "world",
                   n);
    }
    ts_check_end(&c);
    /* zero dt too */
    const fc_vec3 rate = fc_vec3_make(FC_INT(3, RATE), FC_INT(-2, RATE), FC_INT(1, RATE));
    assert_quat_eq(fc_quat_integrate_body_rate(&ar, fc_quat_identity(), rate, FC_INT(0, DT)), fc_quat_identity());
    assert_quat_eq(fc_quat_integrate_world_rate(&ar, fc_quat_identity(), rate, FC_INT(0, DT)),
                   fc_quat_identity());
    assert_int_equal(ar.saturated, 0);
}

/* One step with a rotation angle above 0.5 rad (the sin/cos branch):
 * 20 rad/s over 0.05 s = 1 rad about x. */
static void test_integrate_large_step(void **state)
{
    (void)state;
    fc_arith ar = {0};
    double rdt;
    const fc_real dt = ts_in(0.05f, FC_DT_FRAC, &rdt);
    dvec rrate;
    const fc_vec3 rate = vec_in(20.0, 0.0, 0.0, FC_RATE_FRAC, &rrate);
    const dvec theta = {rrate.x * rdt, 0.0, 0.0};
    ts_check c = ts_check_begin("one step of 1 rad");
    close_quat(&c, fc_quat_integrate_body_rate(&ar, fc_quat_identity(), rate, dt), dq_rotation_vector(theta),
               rotvec_tol(1.0) + integration_tol(1), "body", 0);
    close_quat(&c, fc_quat_integrate_world_rate(&ar, fc_quat_identity(), rate, dt), dq_rotation_vector(theta),
               rotvec_tol(1.0) + integration_tol(1), "world", 0);
    ts_check_end(&c);
    assert_int_equal(ar.saturated, 0);
}

static void test_is_finite(void **state)
{
    (void)state;
    assert_true(fc_quat_is_finite(fc_quat_identity()));
    assert_true(fc_quat_is_finite(fc_quat_make(FC_REAL_MAX, FC_REAL_MIN, 0, FC_C(0.5f, UNIT))));
#if FC_NUMERIC_FIXED
    assert_true(fc_quat_is_finite(fc_quat_make(INT32_MIN, INT32_MAX, -1, 1)));
#else
    const float bad[] = {NAN, INFINITY, -INFINITY};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        assert_false(fc_quat_is_finite(fc_quat_make(bad[k], 0.0f, 0.0f, 0.0f)));
        assert_false(fc_quat_is_finite(fc_quat_make(1.0f, bad[k], 0.0f, 0.0f)));
        assert_false(fc_quat_is_finite(fc_quat_make(1.0f, 0.0f, bad[k], 0.0f)));
        assert_false(fc_quat_is_finite(fc_quat_make(1.0f, 0.0f, 0.0f, bad[k])));
    }
#endif
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_make_identity_vector_part),
        cmocka_unit_test(test_mul_hand_computed),
        cmocka_unit_test(test_mul_random),
        cmocka_unit_test(test_mul_identity_associativity),
        cmocka_unit_test(test_conj),
        cmocka_unit_test(test_norm_sq),
        cmocka_unit_test(test_normalize),
        cmocka_unit_test(test_shortest),
        cmocka_unit_test(test_rotate_known_quarter_turns),
        cmocka_unit_test(test_rotate_random_and_inverse),
        cmocka_unit_test(test_rotate_large_vector),
        cmocka_unit_test(test_rotate_horizontal),
        cmocka_unit_test(test_axis_angle),
        cmocka_unit_test(test_from_rotation_vector),
        cmocka_unit_test(test_rotation_vector_continuity),
        cmocka_unit_test(test_rpy),
        cmocka_unit_test(test_from_up),
        cmocka_unit_test(test_integrate_closed_form),
        cmocka_unit_test(test_integrate_body_vs_world),
        cmocka_unit_test(test_integrate_zero_rate),
        cmocka_unit_test(test_integrate_large_step),
        cmocka_unit_test(test_is_finite),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
