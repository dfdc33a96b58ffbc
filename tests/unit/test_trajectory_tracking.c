/*
 * Tests of the trajectory-tracking law (2.24) on the velocity-input plant
 * (2.18)-(2.23), one source for both backends.
 */
#include "test_support.h"

#include "fc/trajectory_tracking.h"

static fc_real ratio(double x) { return fc_from_float((float)x, FC_RATIO_FRAC); }

static fc_trajectory_tracking_params default_params(void)
{
    fc_trajectory_tracking_params p;
    p.k_p_per_s = fc_vec3_make(ratio(1.8), ratio(1.5), ratio(2.5));
    p.a_p_per_s = fc_vec3_make(ratio(1.6), ratio(1.2), ratio(3.0));
    p.zeta = fc_vec3_make(ratio(0.7), ratio(0.5), ratio(0.9));
    p.omega_n_radps = fc_vec3_make(fc_from_float(2.0f, FC_RATE_FRAC), fc_from_float(1.5f, FC_RATE_FRAC),
                                   fc_from_float(3.0f, FC_RATE_FRAC));
    p.u_max_mps = fc_vec3_make(FC_INT(20, VEL), FC_INT(20, VEL), FC_INT(20, VEL));
    return p;
}

/* the reference: a smooth sine per axis */
static void reference(double t, int axis, double *r, double *rd, double *rdd)
{
    const double a = 0.5 + 0.2 * axis, w = 0.8 + 0.3 * axis;
    *r = a * sin(w * t);
    *rd = a * w * cos(w * t);
    *rdd = -a * w * w * sin(w * t);
}

/* e'' + alpha e' + beta e = 0 (2.14), underdamped, from e(0) = e0, e'(0) = ed0 */
static double error_dynamics(double t, double zeta, double wn, double e0, double ed0)
{
    const double sigma = zeta * wn, wd = wn * sqrt(1.0 - zeta * zeta);
    return exp(-sigma * t) * (e0 * cos(wd * t) + (ed0 + sigma * e0) / wd * sin(wd * t));
}

static void test_error_dynamics_on_plant(void **state)
{
    (void)state;
    const fc_trajectory_tracking_params p = default_params();
    fc_trajectory_tracking tt;
    assert_int_equal(fc_trajectory_tracking_init(&tt, &p), FC_INIT_OK);
    const double kp[3] = {ts_val(p.k_p_per_s.x, FC_RATIO_FRAC), ts_val(p.k_p_per_s.y, FC_RATIO_FRAC),
                          ts_val(p.k_p_per_s.z, FC_RATIO_FRAC)};
    const double ap[3] = {ts_val(p.a_p_per_s.x, FC_RATIO_FRAC), ts_val(p.a_p_per_s.y, FC_RATIO_FRAC),
                          ts_val(p.a_p_per_s.z, FC_RATIO_FRAC)};
    const double zeta[3] = {ts_val(p.zeta.x, FC_RATIO_FRAC), ts_val(p.zeta.y, FC_RATIO_FRAC),
                            ts_val(p.zeta.z, FC_RATIO_FRAC)};
    const double wn[3] = {ts_val(p.omega_n_radps.x, FC_RATE_FRAC), ts_val(p.omega_n_radps.y, FC_RATE_FRAC),
                          ts_val(p.omega_n_radps.z, FC_RATE_FRAC)};
    double x[3] = {0.6, -0.4, 0.3}, v[3] = {0.0, 0.2, -0.1};
    double e0[3], ed0[3];
    for (int i = 0; i < 3; i++) {
        double r, rd, rdd;
        reference(0.0, i, &r, &rd, &rdd);
        e0[i] = r - x[i];
        ed0[i] = rd - v[i];
    }
    const double dt = 0.001;
    const int substeps = 10;
    double worst = 0.0;
    for (int k = 0; k < 6000; k++) {
        const double t = k * dt;
        double r[3], rd[3], rdd[3];
        for (int i = 0; i < 3; i++) {
            reference(t, i, &r[i], &rd[i], &rdd[i]);
            const double expected = error_dynamics(t, zeta[i], wn[i], e0[i], ed0[i]);
            worst = fmax(worst, fabs((r[i] - x[i]) - expected));
        }
        const fc_trajectory_tracking_input in = {
            fc_vec3_make(fc_from_float((float)r[0], FC_LENGTH_FRAC), fc_from_float((float)r[1], FC_LENGTH_FRAC),
                         fc_from_float((float)r[2], FC_LENGTH_FRAC)),
            fc_vec3_make(fc_from_float((float)rd[0], FC_VEL_FRAC), fc_from_float((float)rd[1], FC_VEL_FRAC),
                         fc_from_float((float)rd[2], FC_VEL_FRAC)),
            fc_vec3_make(fc_from_float((float)rdd[0], FC_ACCEL_FRAC), fc_from_float((float)rdd[1], FC_ACCEL_FRAC),
                         fc_from_float((float)rdd[2], FC_ACCEL_FRAC)),
            fc_vec3_make(fc_from_float((float)x[0], FC_LENGTH_FRAC), fc_from_float((float)x[1], FC_LENGTH_FRAC),
                         fc_from_float((float)x[2], FC_LENGTH_FRAC)),
            fc_vec3_make(fc_from_float((float)v[0], FC_VEL_FRAC), fc_from_float((float)v[1], FC_VEL_FRAC),
                         fc_from_float((float)v[2], FC_VEL_FRAC))};
        fc_vec3 u;
        assert_int_equal(fc_trajectory_tracking_step(&tt, &in, &u), FC_STEP_OK);
        const double ui[3] = {ts_val(u.x, FC_VEL_FRAC), ts_val(u.y, FC_VEL_FRAC), ts_val(u.z, FC_VEL_FRAC)};
        /* the plant (2.23) in double, u held over the step (semi-implicit Euler, fine substeps) */
        for (int s = 0; s < substeps; s++) {
            for (int i = 0; i < 3; i++) {
                v[i] += (-ap[i] * v[i] + kp[i] * ui[i]) * (dt / substeps);
                x[i] += v[i] * (dt / substeps);
            }
        }
    }
    print_message("tracking (2.24): worst |e - e_(2.14)| %.3g m over 6 s (initial |e| <= 0.6 m)\n", worst);
    /* the sampling (u held 1 ms) perturbs the e-dynamics by O(dt) */
    assert_true(worst < 5e-3);
    /* and the error has decayed: exp(-zeta w_n 6 s) <= 2e-2 */
    for (int i = 0; i < 3; i++) {
        double r, rd, rdd;
        reference(6.0, i, &r, &rd, &rdd);
        assert_true(fabs(r - x[i]) < 1.5e-2);
    }
}

static void test_law_matches_2_24(void **state)
{
    (void)state;
    const fc_trajectory_tracking_params p = default_params();
    fc_trajectory_tracking tt;
    assert_int_equal(fc_trajectory_tracking_init(&tt, &p), FC_INIT_OK);
    const double zeta = ts_val(p.zeta.x, FC_RATIO_FRAC), wn = ts_val(p.omega_n_radps.x, FC_RATE_FRAC);
    const double alpha = 2 * zeta * wn, beta = wn * wn;
    const double kp = ts_val(p.k_p_per_s.x, FC_RATIO_FRAC), ap = ts_val(p.a_p_per_s.x, FC_RATIO_FRAC);
    ts_rng rng = ts_rng_seed(3u);
    ts_check c = ts_check_begin("u of (2.24)");
    for (int k = 0; k < 1000; k++) {
        double r, rd, rdd, x, xd;
        fc_trajectory_tracking_input in;
        in.r_m = fc_vec3_make(ts_in(ts_uniform(&rng, -3, 3), FC_LENGTH_FRAC, &r), FC_INT(0, LENGTH), FC_INT(0, LENGTH));
        in.r_dot_mps = fc_vec3_make(ts_in(ts_uniform(&rng, -2, 2), FC_VEL_FRAC, &rd), FC_INT(0, VEL), FC_INT(0, VEL));
        in.r_ddot_mps2 = fc_vec3_make(ts_in(ts_uniform(&rng, -2, 2), FC_ACCEL_FRAC, &rdd), FC_INT(0, ACCEL), FC_INT(0, ACCEL));
        in.x_m = fc_vec3_make(ts_in(ts_uniform(&rng, -3, 3), FC_LENGTH_FRAC, &x), FC_INT(0, LENGTH), FC_INT(0, LENGTH));
        in.x_dot_mps = fc_vec3_make(ts_in(ts_uniform(&rng, -2, 2), FC_VEL_FRAC, &xd), FC_INT(0, VEL), FC_INT(0, VEL));
        fc_vec3 u;
        const fc_step_status st = fc_trajectory_tracking_step(&tt, &in, &u);
        const double expected = (rdd + alpha * rd + beta * r - (alpha - ap) * xd - beta * x) / kp;
        const double lim = fmin(fmax(expected, -20.0), 20.0);
        assert_true((st & ~FC_STEP_OUTPUT_LIMITED) == 0u);
        /* fixed: gains in Q24 (alpha, beta from rounded products), sums in ACCEL: tens of VEL LSB */
        ts_close(&c, ts_val(u.x, FC_VEL_FRAC), lim, ts_tol(FC_VEL_FRAC, 64, 64, 30.0), "%d", k);
        TS_ASSERT_REAL_EQ(u.y, FC_INT(0, VEL));
    }
    ts_check_end(&c);
}

static void test_output_limited(void **state)
{
    (void)state;
    fc_trajectory_tracking_params p = default_params();
    p.u_max_mps = fc_vec3_make(FC_INT(1, VEL), FC_INT(2, VEL), FC_INT(3, VEL));
    fc_trajectory_tracking tt;
    assert_int_equal(fc_trajectory_tracking_init(&tt, &p), FC_INIT_OK);
    fc_trajectory_tracking_input in;
    in.r_m = fc_vec3_make(FC_INT(10, LENGTH), FC_INT(-10, LENGTH), FC_INT(0, LENGTH));
    in.r_dot_mps = fc_vec3_zero();
    in.r_ddot_mps2 = fc_vec3_zero();
    in.x_m = fc_vec3_zero();
    in.x_dot_mps = fc_vec3_zero();
    fc_vec3 u;
    assert_int_equal(fc_trajectory_tracking_step(&tt, &in, &u), FC_STEP_OUTPUT_LIMITED);
    TS_ASSERT_REAL_EQ(u.x, FC_INT(1, VEL));
    TS_ASSERT_REAL_EQ(u.y, FC_INT(-2, VEL));
    TS_ASSERT_REAL_EQ(u.z, FC_INT(0, VEL));
}

static void test_bad_input_and_params(void **state)
{
    (void)state;
    fc_trajectory_tracking_params p = default_params();
    fc_trajectory_tracking tt;
    fc_trajectory_tracking_input in;
    in.r_m = fc_vec3_zero();
    in.r_dot_mps = fc_vec3_zero();
    in.r_ddot_mps2 = fc_vec3_zero();
    in.x_m = fc_vec3_zero();
    in.x_dot_mps = fc_vec3_zero();
    fc_vec3 u;
    p.zeta.y = ratio(0.0);
    assert_int_equal(fc_trajectory_tracking_init(&tt, &p), FC_INIT_BAD_PARAM);
    assert_int_equal(fc_trajectory_tracking_step(&tt, &in, &u), FC_STEP_NOT_READY);
    TS_ASSERT_REAL_EQ(u.x, FC_INT(0, VEL));
    p = default_params();
    p.k_p_per_s.y = ratio(0.0);
    assert_int_equal(fc_trajectory_tracking_init(&tt, &p), FC_INIT_BAD_PARAM);
    p = default_params();
    p.omega_n_radps.z = fc_from_float(20.0f, FC_RATE_FRAC);
    assert_int_equal(fc_trajectory_tracking_init(&tt, &p), FC_INIT_BAD_PARAM);
    p = default_params();
    p.u_max_mps.z = FC_INT(0, VEL);
    assert_int_equal(fc_trajectory_tracking_init(&tt, &p), FC_INIT_BAD_PARAM);
#if !FC_NUMERIC_FIXED
    p = default_params();
    p.a_p_per_s.x = NAN;
    assert_int_equal(fc_trajectory_tracking_init(&tt, &p), FC_INIT_BAD_PARAM);
    p = default_params();
    assert_int_equal(fc_trajectory_tracking_init(&tt, &p), FC_INIT_OK);
    in.x_dot_mps.y = INFINITY;
    in.r_m.x = 1.0f;
    assert_int_equal(fc_trajectory_tracking_step(&tt, &in, &u), FC_STEP_BAD_INPUT);
    assert_true(u.y == 0.0f && isfinite(u.x) && u.x > 0.0f);
#endif
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_error_dynamics_on_plant),
        cmocka_unit_test(test_law_matches_2_24),
        cmocka_unit_test(test_output_limited),
        cmocka_unit_test(test_bad_input_and_params),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
