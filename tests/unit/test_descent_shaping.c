/*
 * Tests of the descent velocity field (2.25)-(2.28), one source for both backends.
 */
#include "test_support.h"

#include "fc/descent_shaping.h"

static fc_descent_shaping_params default_params(void)
{
    fc_descent_shaping_params p;
    p.k_r_m2ps = fc_from_float(0.05f, FC_GAIN_FRAC);
    p.delta_h_m = fc_from_float(0.1f, FC_LENGTH_FRAC);
    p.k_c_per_s = fc_from_float(0.8f, FC_GAIN_FRAC);
    p.u_zbias_mps = fc_from_float(0.2f, FC_VEL_FRAC);
    p.k_a_mps = fc_from_float(0.3f, FC_GAIN_FRAC);
    p.delta_a_m = fc_from_float(0.2f, FC_LENGTH_FRAC);
    p.max_descent_mps = fc_from_float(1.0f, FC_VEL_FRAC);
    p.max_climb_mps = fc_from_float(2.0f, FC_VEL_FRAC);
    return p;
}

static double g(fc_real x, int frac) { return ts_val(x, frac); }

/* the formulas in double, from the parameters as the backend holds them */
static double reference(const fc_descent_shaping_params *p, double dx, double dy, double dz, double qw,
                        double qx, double qy, double qz, double *rat, double *con, double *ave)
{
    const double kr = g(p->k_r_m2ps, FC_GAIN_FRAC), dh0 = g(p->delta_h_m, FC_LENGTH_FRAC);
    const double kc = g(p->k_c_per_s, FC_GAIN_FRAC), ub = g(p->u_zbias_mps, FC_VEL_FRAC);
    const double ka = g(p->k_a_mps, FC_GAIN_FRAC), da = g(p->delta_a_m, FC_LENGTH_FRAC);
    const double dh = hypot(dx, dy);
    /* d in the pad frame: R(q)^T d */
    const double n = sqrt(qw * qw + qx * qx + qy * qy + qz * qz);
    qw /= n, qx /= n, qy /= n, qz /= n;
    const double r00 = 1 - 2 * (qy * qy + qz * qz), r01 = 2 * (qx * qy - qw * qz), r02 = 2 * (qx * qz + qw * qy);
    const double r10 = 2 * (qx * qy + qw * qz), r11 = 1 - 2 * (qx * qx + qz * qz), r12 = 2 * (qy * qz - qw * qx);
    const double px = r00 * dx + r10 * dy + (2 * (qx * qz - qw * qy)) * dz;
    const double py = r01 * dx + r11 * dy + (2 * (qy * qz + qw * qx)) * dz;
    (void)r02, (void)r12;
    *rat = -kr / (dh + dh0);
    *con = kc * dh - ub;
    *ave = ka * hypot(px, py) / (fabs(dz) + da);
    return *rat + *con + *ave;
}

static void test_terms_match_formulas(void **state)
{
    (void)state;
    const fc_descent_shaping_params p = default_params();
    fc_descent_shaping ds;
    assert_int_equal(fc_descent_shaping_init(&ds, &p), FC_INIT_OK);
    ts_rng rng = ts_rng_seed(7u);
    ts_check c = ts_check_begin("descent terms (2.26)-(2.28)");
    for (int k = 0; k < 2000; k++) {
        double dx, dy, dz, qw, qx, qy, qz;
        const fc_real fdx = ts_in(ts_uniform(&rng, -1.5f, 1.5f), FC_LENGTH_FRAC, &dx);
        const fc_real fdy = ts_in(ts_uniform(&rng, -1.5f, 1.5f), FC_LENGTH_FRAC, &dy);
        const fc_real fdz = ts_in(ts_uniform(&rng, 0.0f, 3.0f), FC_LENGTH_FRAC, &dz);
        /* pad rolled/pitched up to ~0.3 rad */
        const float ax = ts_uniform(&rng, -0.15f, 0.15f), ay = ts_uniform(&rng, -0.15f, 0.15f);
        const float az = ts_uniform(&rng, -1.5f, 1.5f);
        const float nn = sqrtf(1.0f + ax * ax + ay * ay + az * az);
        const fc_real fqw = ts_in(1.0f / nn, FC_UNIT_FRAC, &qw), fqx = ts_in(ax / nn, FC_UNIT_FRAC, &qx);
        const fc_real fqy = ts_in(ay / nn, FC_UNIT_FRAC, &qy), fqz = ts_in(az / nn, FC_UNIT_FRAC, &qz);
        const fc_descent_shaping_input in = {fc_vec3_make(fdx, fdy, fdz), fc_quat_make(fqw, fqx, fqy, fqz)};
        fc_descent_shaping_output out;
        const fc_step_status st = fc_descent_shaping_step(&ds, &in, &out);
        double rat, con, ave;
        const double v = reference(&p, dx, dy, dz, qw, qx, qy, qz, &rat, &con, &ave);
        /* fixed: hypot and one division, a few VEL LSB (more for the rotated
         * pad vector: UNIT quaternion rounding times ~2 m) */
        ts_close(&c, g(out.rational_mps, FC_VEL_FRAC), rat, ts_tol(FC_VEL_FRAC, 8, 16, 1.0), "rat %d", k);
        ts_close(&c, g(out.conical_mps, FC_VEL_FRAC), con, ts_tol(FC_VEL_FRAC, 8, 16, 2.0), "con %d", k);
        ts_close(&c, g(out.aversive_mps, FC_VEL_FRAC), ave, ts_tol(FC_VEL_FRAC, 32, 64, 2.0), "ave %d", k);
        const double clamped = fmin(fmax(v, -1.0), 2.0);
        ts_close(&c, g(out.vz_mps, FC_VEL_FRAC), clamped, ts_tol(FC_VEL_FRAC, 48, 128, 2.0), "v %d", k);
        assert_true((st & ~FC_STEP_OUTPUT_LIMITED) == 0u);
        if (v > 2.0 + 1e-4 || v < -1.0 - 1e-4) {
            assert_true((st & FC_STEP_OUTPUT_LIMITED) != 0u);
        }
    }
    ts_check_end(&c);
}

static void test_descends_centred_climbs_far_off(void **state)
{
    (void)state;
    const fc_descent_shaping_params p = default_params();
    fc_descent_shaping ds;
    assert_int_equal(fc_descent_shaping_init(&ds, &p), FC_INIT_OK);
    fc_descent_shaping_output out;
    /* centred over a level pad, 1 m up: -k_r/delta_h - u_zbias = -0.7 m/s */
    fc_descent_shaping_input in = {fc_vec3_make(FC_INT(0, LENGTH), FC_INT(0, LENGTH), FC_INT(1, LENGTH)),
                                   fc_quat_identity()};
    assert_int_equal(fc_descent_shaping_step(&ds, &in, &out), FC_STEP_OK);
    assert_true(g(out.vz_mps, FC_VEL_FRAC) < -0.69 && g(out.vz_mps, FC_VEL_FRAC) > -0.71);
    assert_true(g(out.aversive_mps, FC_VEL_FRAC) == 0.0);
    /* 1.5 m off: climbs */
    in.rel_position_m.x = fc_from_float(1.5f, FC_LENGTH_FRAC);
    (void)fc_descent_shaping_step(&ds, &in, &out);
    assert_true(g(out.vz_mps, FC_VEL_FRAC) > 0.5);
    /* the descent rate falls monotonically with the horizontal offset near the centre */
    double last = -10.0;
    for (int k = 0; k <= 20; k++) {
        in.rel_position_m.x = fc_from_float(0.02f * (float)k, FC_LENGTH_FRAC);
        (void)fc_descent_shaping_step(&ds, &in, &out);
        const double v = g(out.vz_mps, FC_VEL_FRAC);
        assert_true(v > last);
        last = v;
    }
    /* far off and low: clamped at the climb limit */
    in.rel_position_m = fc_vec3_make(FC_INT(20, LENGTH), FC_INT(0, LENGTH), FC_INT(0, LENGTH));
    const fc_step_status st = fc_descent_shaping_step(&ds, &in, &out);
    assert_true((st & FC_STEP_OUTPUT_LIMITED) != 0u);
    assert_true((st & FC_STEP_ARITH_SATURATED) == 0u);
    TS_ASSERT_REAL_EQ(out.vz_mps, p.max_climb_mps);
}

static void test_aversive_on_tilted_pad(void **state)
{
    (void)state;
    fc_descent_shaping_params p = default_params();
    p.k_r_m2ps = FC_INT(0, GAIN);
    p.k_c_per_s = FC_INT(0, GAIN);
    p.u_zbias_mps = FC_INT(0, VEL);
    fc_descent_shaping ds;
    assert_int_equal(fc_descent_shaping_init(&ds, &p), FC_INIT_OK);
    fc_descent_shaping_output out;
    /* directly above a pad rolled by 0.4 rad, 1 m up: (d)_pad = (0, sin 0.4, cos 0.4) */
    const double roll = 0.4;
    const fc_descent_shaping_input in = {
        fc_vec3_make(FC_INT(0, LENGTH), FC_INT(0, LENGTH), FC_INT(1, LENGTH)),
        fc_quat_make(fc_from_float((float)cos(roll / 2), FC_UNIT_FRAC), fc_from_float((float)sin(roll / 2), FC_UNIT_FRAC),
                     FC_INT(0, UNIT), FC_INT(0, UNIT))};
    assert_int_equal(fc_descent_shaping_step(&ds, &in, &out), FC_STEP_OK);
    const double expect = g(p.k_a_mps, FC_GAIN_FRAC) * sin(roll) / (1.0 + g(p.delta_a_m, FC_LENGTH_FRAC));
    TS_ASSERT_CLOSE(g(out.aversive_mps, FC_VEL_FRAC), expect, 1e-5);
    assert_true(out.aversive_mps > FC_INT(0, VEL)); /* climbs away from a tilting pad */
}

static void test_bad_input(void **state)
{
    (void)state;
    const fc_descent_shaping_params p = default_params();
    fc_descent_shaping ds;
    assert_int_equal(fc_descent_shaping_init(&ds, &p), FC_INIT_OK);
    fc_descent_shaping_output out;
    fc_descent_shaping_input in = {fc_vec3_make(FC_INT(2000, LENGTH) - 1, FC_INT(0, LENGTH), FC_INT(1, LENGTH)),
                                   fc_quat_identity()};
    assert_true((fc_descent_shaping_step(&ds, &in, &out) & FC_STEP_BAD_INPUT) != 0u);
    TS_ASSERT_REAL_EQ(out.vz_mps, FC_INT(0, VEL));
#if !FC_NUMERIC_FIXED
    in.rel_position_m.x = NAN;
    assert_true((fc_descent_shaping_step(&ds, &in, &out) & FC_STEP_BAD_INPUT) != 0u);
    assert_true(out.vz_mps == 0.0f);
    in.rel_position_m.x = 0.0f;
    in.pad_attitude.w = INFINITY;
    assert_true((fc_descent_shaping_step(&ds, &in, &out) & FC_STEP_BAD_INPUT) != 0u);
    assert_true(isfinite(out.vz_mps));
#endif
    /* zero quaternion: level pad, finite output */
    in.rel_position_m.x = FC_INT(0, LENGTH);
    in.pad_attitude = fc_quat_make(FC_INT(0, UNIT), FC_INT(0, UNIT), FC_INT(0, UNIT), FC_INT(0, UNIT));
    assert_true((fc_descent_shaping_step(&ds, &in, &out) & FC_STEP_BAD_INPUT) != 0u);
    assert_true(g(out.vz_mps, FC_VEL_FRAC) < 0.0 && g(out.vz_mps, FC_VEL_FRAC) >= -1.0);
}

static void test_bad_params(void **state)
{
    (void)state;
    fc_descent_shaping ds;
    fc_descent_shaping_output out;
    const fc_descent_shaping_input in = {fc_vec3_zero(), fc_quat_identity()};
    fc_descent_shaping_params p = default_params();
    p.delta_h_m = FC_INT(0, LENGTH);
    assert_int_equal(fc_descent_shaping_init(&ds, &p), FC_INIT_BAD_PARAM);
    assert_int_equal(fc_descent_shaping_step(&ds, &in, &out), FC_STEP_NOT_READY);
    TS_ASSERT_REAL_EQ(out.vz_mps, FC_INT(0, VEL));
    p = default_params();
    p.k_c_per_s = fc_from_float(-1.0f, FC_GAIN_FRAC);
    assert_int_equal(fc_descent_shaping_init(&ds, &p), FC_INIT_BAD_PARAM);
    p = default_params();
    p.max_climb_mps = FC_INT(0, VEL);
    assert_int_equal(fc_descent_shaping_init(&ds, &p), FC_INIT_BAD_PARAM);
    p = default_params();
    p.delta_a_m = FC_INT(0, LENGTH);
    assert_int_equal(fc_descent_shaping_init(&ds, &p), FC_INIT_BAD_PARAM);
#if !FC_NUMERIC_FIXED
    p = default_params();
    p.k_a_mps = NAN;
    assert_int_equal(fc_descent_shaping_init(&ds, &p), FC_INIT_BAD_PARAM);
#endif
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_terms_match_formulas),
        cmocka_unit_test(test_descends_centred_climbs_far_off),
        cmocka_unit_test(test_aversive_on_tilted_pad),
        cmocka_unit_test(test_bad_input),
        cmocka_unit_test(test_bad_params),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
