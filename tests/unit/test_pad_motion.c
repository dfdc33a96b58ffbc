/*
 * Tests of the pad-motion estimator (fc/pad_motion.h), one source for both
 * backends: the heave of a pad off the frequency grid, a sum of three
 * sinusoids, a pad that stops, outliers, bad samples and parameters.
 */
#include <string.h>

#include "test_support.h"

#include "fc/pad_motion.h"

#define DT_S 0.002

typedef struct heave {
    int count;
    double amplitude_m[3], omega_radps[3], phase_rad[3];
    double base_m;
} heave;

static void heave_eval(const heave *h, double t, double *z, double *vz, double *az)
{
    *z = h->base_m;
    *vz = 0.0;
    *az = 0.0;
    for (int k = 0; k < h->count; k++) {
        const double a = h->amplitude_m[k], w = h->omega_radps[k], ph = w * t + h->phase_rad[k];
        *z += a * sin(ph);
        *vz += a * w * cos(ph);
        *az -= a * w * w * sin(ph);
    }
}

static fc_pad_motion_params params(double p0, double p1, double p2)
{
    fc_pad_motion_params p;
    p.dt_s = fc_from_float((float)DT_S, FC_DT_FRAC);
    p.mode_count = 3u;
    p.mode_period_s[0] = fc_from_float((float)p0, FC_TIME_FRAC);
    p.mode_period_s[1] = fc_from_float((float)p1, FC_TIME_FRAC);
    p.mode_period_s[2] = fc_from_float((float)p2, FC_TIME_FRAC);
    p.period_min_s = fc_from_float((float)(0.7 * p0), FC_TIME_FRAC);
    p.period_max_s = fc_from_float((float)(1.45 * p2), FC_TIME_FRAC);
    p.frequency_gain = FC_C(0.1f, UNIT);
    p.adapt_amplitude_min_m = FC_C(0.003f, LENGTH);
    p.forgetting = FC_C(0.998f, UNIT);
    p.covariance_init = FC_INT(10, MAT);
    p.covariance_trace_max = FC_INT(120, MAT);
    p.outlier_m = FC_C(0.5f, LENGTH);
    p.outlier_reset_count = 25u;
    p.horizon_s = FC_C(1.0f, TIME);
    p.observe_min_s = FC_INT(5, TIME);
    p.tolerance_m = FC_C(0.02f, LENGTH);
    p.error_average_gain = FC_C(0.02f, UNIT);
    return p;
}

/* Gaussian noise (Box-Muller on a fixed LCG: the same numbers every run). */
static double noise(uint32_t *state, double sigma)
{
    *state = *state * 1664525u + 1013904223u;
    const double u1 = ((double)(*state >> 8) + 1.0) / 16777217.0;
    *state = *state * 1664525u + 1013904223u;
    const double u2 = (double)(*state >> 8) / 16777216.0;
    return sigma * sqrt(-2.0 * log(u1)) * cos(2.0 * TS_PI * u2);
}

typedef struct run_result {
    double max_z_error_m, max_vz_error_mps, max_az_error_mps2, max_ahead_error_m;
    double final_confidence, final_heave_bound_m, final_accel_bound_mps2, true_heave_m, true_accel_mps2;
    double confidence_at_check, final_dominant_period_s;
} run_result;

/* Runs the estimator on heave h sampled every sample_every steps with noise
 * sigma for duration_s; errors measured over [check_from_s, duration_s]. */
static run_result fly(const fc_pad_motion_params *p, const heave *h, int sample_every, double sigma, double duration_s,
                      double check_from_s)
{
    fc_pad_motion pm;
    assert_int_equal(fc_pad_motion_init(&pm, p), FC_INIT_OK);
    run_result r = {0};
    uint32_t rng = 12345u;
    const long steps = lround(duration_s / DT_S);
    const double horizon_s = ts_val(p->horizon_s, FC_TIME_FRAC);
    fc_pad_motion_estimate est;
    for (long k = 0; k < steps; k++) {
        const double t = (double)k * DT_S;
        double z, vz, az;
        heave_eval(h, t, &z, &vz, &az);
        fc_pad_motion_sample s = {fc_from_float((float)(z + noise(&rng, sigma)), FC_LENGTH_FRAC),
                                  k % sample_every == 0};
        const fc_step_status st = fc_pad_motion_step(&pm, &s, &est);
        assert_true((st & (FC_STEP_NOT_READY | FC_STEP_ARITH_SATURATED)) == 0u);
        if (t >= check_from_s) {
            /* the prediction is H after this step's time */
            double za, vza, aza;
            heave_eval(h, t + horizon_s, &za, &vza, &aza);
            fc_vertical_trajectory ahead;
            fc_pad_motion_predict_ahead(&pm, &ahead);
            r.max_z_error_m = fmax(r.max_z_error_m, fabs(ts_val(est.now.z_m, FC_LENGTH_FRAC) - z));
            r.max_vz_error_mps = fmax(r.max_vz_error_mps, fabs(ts_val(est.now.vz_mps, FC_VEL_FRAC) - vz));
            r.max_az_error_mps2 = fmax(r.max_az_error_mps2, fabs(ts_val(est.now.az_mps2, FC_ACCEL_FRAC) - az));
            r.max_ahead_error_m = fmax(r.max_ahead_error_m, fabs(ts_val(ahead.z_m, FC_LENGTH_FRAC) - za));
            if (fabs(t - check_from_s) < 0.5 * DT_S) {
                r.confidence_at_check = ts_val(est.confidence, FC_UNIT_FRAC);
            }
        }
        r.true_heave_m = fmax(r.true_heave_m, fabs(z - h->base_m));
        r.true_accel_mps2 = fmax(r.true_accel_mps2, fabs(az));
    }
    r.final_confidence = ts_val(est.confidence, FC_UNIT_FRAC);
    r.final_heave_bound_m = ts_val(est.heave_bound_m, FC_LENGTH_FRAC);
    r.final_dominant_period_s = ts_val(est.dominant_period_s, FC_TIME_FRAC);
    r.final_accel_bound_mps2 = ts_val(est.accel_bound_mps2, FC_ACCEL_FRAC);
    return r;
}

/* The Crazyflie family's fastest corner: 9 cm peak to peak at 2.12 s, below
 * the first start period (2.5 s), 4 mm noise (the family's noise x2). */
static void test_fast_pad(void **state)
{
    (void)state;
    fc_pad_motion_params p = params(2.5, 4.5, 8.0);
    p.period_min_s = FC_C(1.8f, TIME); /* the Crazyflie's band */
    const heave h = {1, {0.045, 0, 0}, {2.0 * TS_PI / 2.12, 0, 0}, {0.3, 0, 0}, 0.045};
    const run_result r = fly(&p, &h, 10, 0.004, 40.0, 20.0);
    print_message("fast pad: |dz| %.4f m |dvz| %.4f m/s |dz(t+1s)| %.4f m conf %.3f (at 20 s %.3f) period %.3f s\n",
                  r.max_z_error_m, r.max_vz_error_mps, r.max_ahead_error_m, r.final_confidence,
                  r.confidence_at_check, r.final_dominant_period_s);
    assert_true(r.max_z_error_m < 0.010);
    assert_true(r.max_ahead_error_m < 0.012);
    assert_true(r.final_confidence > 0.6);
    assert_true(fabs(r.final_dominant_period_s - 2.12) < 0.1);
}

/* The Crazyflie pad: 5 cm peak to peak (3.1) at a 4 s period, off the
 * start grid (2.5, 4.5, 8 s): the middle mode's frequency adapts to it;
 * a 50 Hz ToF with 2 mm noise. */
static void test_single_sine_off_grid(void **state)
{
    (void)state;
    const fc_pad_motion_params p = params(2.5, 4.5, 8.0);
    const heave h = {1, {0.025, 0, 0}, {2.0 * TS_PI / 4.0, 0, 0}, {0.3, 0, 0}, 0.025};
    const run_result r = fly(&p, &h, 10, 0.002, 40.0, 20.0);
    print_message("cf pad: |dz| %.4f m |dvz| %.4f m/s |daz| %.3f m/s2 |dz(t+1s)| %.4f m conf %.3f bounds %.4f m "
                  "%.3f m/s2 (true %.4f, %.3f)\n",
                  r.max_z_error_m, r.max_vz_error_mps, r.max_az_error_mps2, r.max_ahead_error_m, r.final_confidence,
                  r.final_heave_bound_m, r.final_accel_bound_mps2, r.true_heave_m, r.true_accel_mps2);
    assert_true(r.max_z_error_m < 0.006); /* 2 mm noise: the largest of 10^4 errors */
    assert_true(r.max_vz_error_mps < 0.012);
    assert_true(r.max_ahead_error_m < 0.009);
    assert_true(r.final_confidence > 0.6);
    assert_true(r.final_heave_bound_m >= r.true_heave_m * 0.98);
    assert_true(r.final_heave_bound_m <= r.true_heave_m * 1.6);
    assert_true(r.final_accel_bound_mps2 >= r.true_accel_mps2 * 0.9);
    print_message("cf pad: dominant period %.3f s\n", r.final_dominant_period_s);
    assert_true(r.final_dominant_period_s > 3.8 && r.final_dominant_period_s < 4.2);
}

/* A ship's deck: three waves (9, 6.5 and 13 s), 1 m peak to peak at most,
 * a 100 Hz range finder with 5 mm noise. Broadband: a fixed grid (6.5, 9.5,
 * 14 s, no frequency adaptation) with a short window (1 s) fits it locally. */
static void test_three_waves(void **state)
{
    (void)state;
    fc_pad_motion_params p = params(6.5, 9.5, 14.0);
    p.forgetting = FC_C(0.99f, UNIT);
    p.frequency_gain = FC_INT(0, UNIT);
    p.tolerance_m = FC_C(0.1f, LENGTH);
    p.horizon_s = FC_C(1.0f, TIME);
    const heave h = {3,
                     {0.30, 0.15, 0.05},
                     {2.0 * TS_PI / 9.0, 2.0 * TS_PI / 6.5, 2.0 * TS_PI / 13.0},
                     {0.0, 60.0 * TS_PI / 180.0, 200.0 * TS_PI / 180.0},
                     0.0};
    const run_result r = fly(&p, &h, 5, 0.005, 60.0, 30.0);
    print_message("deck: |dz| %.4f m |dvz| %.4f m/s |daz| %.3f m/s2 |dz(t+1s)| %.4f m conf %.3f\n", r.max_z_error_m,
                  r.max_vz_error_mps, r.max_az_error_mps2, r.max_ahead_error_m, r.final_confidence);
    assert_true(r.max_z_error_m < 0.02);
    assert_true(r.max_vz_error_mps < 0.05);
    assert_true(r.max_ahead_error_m < 0.15);
    assert_true(r.final_confidence > 0.3);
}

/* A still pad: the modes die out, the level is the pad's, confidence is high. */
static void test_still_pad(void **state)
{
    (void)state;
    const fc_pad_motion_params p = params(2.5, 5.0, 10.0);
    const heave h = {0, {0}, {0}, {0}, 0.7};
    const run_result r = fly(&p, &h, 10, 0.002, 30.0, 15.0);
    assert_true(r.max_z_error_m < 0.002);
    assert_true(r.max_vz_error_mps < 0.005);
    assert_true(r.final_confidence > 0.8);
    assert_true(r.final_accel_bound_mps2 < 0.02);
}

/* Confidence is 0 before observe_min_s and until a prediction H..2H old was checked. */
static void test_no_confidence_before_observing(void **state)
{
    (void)state;
    fc_pad_motion_params p = params(2.5, 5.0, 10.0);
    p.observe_min_s = FC_INT(8, TIME);
    fc_pad_motion pm;
    assert_int_equal(fc_pad_motion_init(&pm, &p), FC_INIT_OK);
    fc_pad_motion_estimate est;
    for (int k = 0; k < 3999; k++) { /* 7.998 s */
        const fc_pad_motion_sample s = {FC_C(0.3f, LENGTH), k % 10 == 0};
        fc_pad_motion_step(&pm, &s, &est);
        assert_true(ts_val(est.confidence, FC_UNIT_FRAC) == 0.0);
    }
    assert_true(est.learning);
}

/* A burst of outliers is ignored; a lasting jump (another surface) restarts. */
static void test_outliers(void **state)
{
    (void)state;
    const fc_pad_motion_params p = params(2.5, 5.0, 10.0);
    fc_pad_motion pm;
    assert_int_equal(fc_pad_motion_init(&pm, &p), FC_INIT_OK);
    fc_pad_motion_estimate est;
    fc_pad_motion_sample s = {FC_C(0.2f, LENGTH), true};
    for (int k = 0; k < 5000; k++) {
        s.fresh = k % 10 == 0;
        fc_pad_motion_step(&pm, &s, &est);
    }
    /* five samples 3 m off: not used */
    s.height_m = FC_C(3.2f, LENGTH);
    for (int k = 0; k < 50; k++) {
        s.fresh = k % 10 == 0;
        const fc_step_status st = fc_pad_motion_step(&pm, &s, &est);
        assert_true(!s.fresh || (st & FC_STEP_BAD_INPUT) != 0u);
    }
    assert_true(fabs(ts_val(est.now.z_m, FC_LENGTH_FRAC) - 0.2) < 0.001);
    /* 25 in a row: the estimate restarts at the new surface */
    for (int k = 0; k < 250; k++) {
        s.fresh = k % 10 == 0;
        fc_pad_motion_step(&pm, &s, &est);
    }
    assert_true(fabs(ts_val(est.now.z_m, FC_LENGTH_FRAC) - 3.2) < 0.01);
    assert_true(ts_val(est.confidence, FC_UNIT_FRAC) == 0.0);
}

/* Any bit pattern as a sample: finite estimate, flagged, no saturation. */
static void test_bad_samples(void **state)
{
    (void)state;
    const fc_pad_motion_params p = params(2.5, 5.0, 10.0);
    fc_pad_motion pm;
    assert_int_equal(fc_pad_motion_init(&pm, &p), FC_INIT_OK);
    fc_pad_motion_estimate est;
    const float bad[] = {NAN, INFINITY, -INFINITY, 1e30f, -5000.0f};
    for (int k = 0; k < 2000; k++) {
        fc_pad_motion_sample s = {FC_C(0.1f, LENGTH), k % 10 == 0};
        if (k % 7 == 0) {
#if FC_NUMERIC_FIXED
            s.height_m = (k % 14 == 0) ? INT32_MAX : INT32_MIN + 1;
#else
            s.height_m = bad[(k / 7) % 5];
#endif
            s.fresh = true;
            const fc_step_status st = fc_pad_motion_step(&pm, &s, &est);
            assert_true((st & FC_STEP_BAD_INPUT) != 0u);
        } else {
            fc_pad_motion_step(&pm, &s, &est);
        }
        assert_true(fc_is_finite(est.now.z_m) && fc_is_finite(est.now.vz_mps) && fc_is_finite(est.now.az_mps2));
        assert_true(fc_is_finite(est.confidence) && fc_is_finite(est.accel_bound_mps2));
    }
    (void)bad;
    assert_true(fabs(ts_val(est.now.z_m, FC_LENGTH_FRAC) - 0.1) < 0.001);
}

/* The work of the next step done ahead of it (fc_pad_motion_work_ahead, in
 * the controller's spare minor frames), 0 to 3 slices between two steps in
 * turn (so also a step that finds S half updated), gives the same estimates, bit for bit, as leaving it all to the next
 * step; each slice does the pieces the header names, in its order. */
static void test_work_ahead_between_steps(void **state)
{
    (void)state;
    const fc_pad_motion_params p = params(2.5, 4.5, 8.0);
    fc_pad_motion inline_model, split_model;
    assert_int_equal(fc_pad_motion_init(&inline_model, &p), FC_INIT_OK);
    assert_int_equal(fc_pad_motion_init(&split_model, &p), FC_INIT_OK);
    assert_int_equal(fc_pad_motion_work_ahead(&split_model), FC_STEP_OK); /* the summary of the empty fit */
    const heave h = {1, {0.05}, {2.0 * TS_PI / 3.1}, {0.4}, 0.3};
    uint32_t rng = 99u;
    int covariance_ahead = 0, prepared_samples = 0;
    for (long k = 0; k < lround(30.0 / DT_S); k++) {
        double z, vz, az;
        heave_eval(&h, (double)k * DT_S, &z, &vz, &az);
        const fc_pad_motion_sample s = {fc_from_float((float)(z + noise(&rng, 0.002)), FC_LENGTH_FRAC), k % 5 == 0};
        if (s.fresh && (split_model.deferred & FC_PAD_WORK_SAMPLE_GAIN) == 0u) {
            prepared_samples++;
        }
        fc_pad_motion_estimate a, b;
        memset(&a, 0, sizeof a); /* the padding, compared below */
        memset(&b, 0, sizeof b);
        const fc_step_status sa = fc_pad_motion_step(&inline_model, &s, &a);
        const fc_step_status sb = fc_pad_motion_step(&split_model, &s, &b);
        assert_int_equal(sa, sb);
        assert_memory_equal(&a, &b, sizeof a);
        assert_memory_equal(inline_model.theta, split_model.theta, sizeof inline_model.theta);
        const long pieces = k % 4; /* 0 to 3 calls: every count after every step of the 5 (coprime) */
        for (long c = 0; c < pieces; c++) {
            const unsigned before = split_model.deferred;
            assert_int_equal(fc_pad_motion_work_ahead(&split_model), FC_STEP_OK);
            const unsigned done = before & ~(unsigned)split_model.deferred;
            if ((before & (FC_PAD_WORK_COVARIANCE_HEAD | FC_PAD_WORK_SUMMARY)) != 0u) {
                /* slice 1 first: S's first rows with the rotations, and the summary */
                assert_int_equal(done, before & (FC_PAD_WORK_COVARIANCE_HEAD | FC_PAD_WORK_SUMMARY));
                assert_int_equal(split_model.rotation_stale, 0);
                if ((before & FC_PAD_WORK_COVARIANCE_HEAD) != 0u) {
                    covariance_ahead++;
                }
            } else if ((before & (FC_PAD_WORK_COVARIANCE_TAIL | FC_PAD_WORK_PHASES)) != 0u) {
                /* slice 2: the rest of S and the phases */
                assert_int_equal(done, before & (FC_PAD_WORK_COVARIANCE_TAIL | FC_PAD_WORK_PHASES));
            } else {
                /* slice 3, or nothing left: the next sample's gain */
                assert_int_equal(split_model.deferred, 0);
            }
        }
    }
    assert_memory_equal(inline_model.s, split_model.s, sizeof inline_model.s);
    assert_true(covariance_ahead > 0);
    assert_true(prepared_samples > 0); /* samples taken on an S phi worked out ahead */
}

/* The phases turn by w dt a step, from the step's sine and cosine: by their
 * series for a small angle (dt 2 ms, 0.021 rad) and by fc_sincos for a large
 * one (dt 0.1 s, 1.05 rad); after 300 steps phi still holds sin and cos of
 * w t (float: 2e-5; fixed: the rounding of 300 turns, 2e-4). */
static void test_phases_turn_with_the_step(void **state)
{
    (void)state;
    const double dts[] = {0.002, 0.1};
    for (size_t d = 0; d < sizeof dts / sizeof dts[0]; d++) {
        fc_pad_motion_params p = params(0.6, 1.0, 2.0);
        p.dt_s = fc_from_float((float)dts[d], FC_DT_FRAC);
        p.period_min_s = fc_from_float(0.5f, FC_TIME_FRAC);
        fc_pad_motion pm;
        assert_int_equal(fc_pad_motion_init(&pm, &p), FC_INIT_OK);
        const double dt = (double)fc_to_float(p.dt_s, FC_DT_FRAC);
        const double omega = (double)fc_to_float(pm.omega_radps[0], FC_RATE_FRAC);
        const fc_pad_motion_sample none = {FC_INT(0, LENGTH), false};
        fc_pad_motion_estimate e;
        for (int k = 0; k <= 300; k++) {
            (void)fc_pad_motion_step(&pm, &none, &e);
            const double t = (double)k * dt;
            const double tol = FC_NUMERIC_FIXED ? 2e-4 : 2e-5;
            assert_true(fabs((double)fc_to_float(pm.phi[1], FC_UNIT_FRAC) - sin(omega * t)) < tol);
            assert_true(fabs((double)fc_to_float(pm.phi[2], FC_UNIT_FRAC) - cos(omega * t)) < tol);
        }
    }
}

/* With fewer modes than FC_PAD_MAX_MODES the entries past n stay zero (the
 * sums run over all of them, pad_motion.c PARAMETERS_PAST_N). */
static void test_parameters_past_n_stay_zero(void **state)
{
    (void)state;
    fc_pad_motion_params p = params(2.5, 4.5, 8.0);
    p.mode_count = 1u;
    fc_pad_motion pm;
    assert_int_equal(fc_pad_motion_init(&pm, &p), FC_INIT_OK);
    const heave h = {1, {0.05}, {2.0 * TS_PI / 3.1}, {0.4}, 0.3};
    for (long k = 0; k < lround(20.0 / DT_S); k++) {
        double z, vz, az;
        heave_eval(&h, (double)k * DT_S, &z, &vz, &az);
        const fc_pad_motion_sample s = {fc_from_float((float)z, FC_LENGTH_FRAC), k % 5 == 0};
        fc_pad_motion_estimate est;
        fc_pad_motion_step(&pm, &s, &est);
        (void)fc_pad_motion_work_ahead(&pm);
        (void)fc_pad_motion_work_ahead(&pm);
    }
    assert_true(pm.learning);
    for (unsigned i = pm.n; i < FC_PAD_MAX_PARAMS; i++) {
        assert_true(pm.theta[i] == FC_INT(0, LENGTH));
        assert_true(pm.theta_old[i] == FC_INT(0, LENGTH));
        assert_true(pm.pending_s_phi[i] == FC_INT(0, MAT));
        for (unsigned j = 0u; j < FC_PAD_MAX_PARAMS; j++) {
            assert_true(pm.s[i][j] == FC_INT(0, MAT));
            assert_true(pm.s[j][i] == FC_INT(0, MAT));
        }
    }
    assert_true(fabs(ts_val(pm.theta[1], FC_LENGTH_FRAC)) + fabs(ts_val(pm.theta[2], FC_LENGTH_FRAC)) > 0.03);
}

static void test_params_rejected(void **state)
{
    (void)state;
    fc_pad_motion pm;
    fc_pad_motion_estimate est;
    const fc_pad_motion_params good = params(2.5, 5.0, 10.0);
    fc_pad_motion_params p = good;
    p.mode_count = 0u;
    assert_int_equal(fc_pad_motion_init(&pm, &p), FC_INIT_BAD_PARAM);
    p = good;
    p.mode_count = FC_PAD_MAX_MODES + 1u;
    assert_int_equal(fc_pad_motion_init(&pm, &p), FC_INIT_BAD_PARAM);
    p = good;
    p.mode_period_s[1] = p.mode_period_s[0];
    assert_int_equal(fc_pad_motion_init(&pm, &p), FC_INIT_BAD_PARAM);
    p = good;
    p.forgetting = FC_INT(1, UNIT);
    assert_int_equal(fc_pad_motion_init(&pm, &p), FC_INIT_BAD_PARAM);
    p = good;
    p.covariance_trace_max = FC_C(1.0f, MAT);
    assert_int_equal(fc_pad_motion_init(&pm, &p), FC_INIT_BAD_PARAM);
    p = good;
    p.dt_s = FC_INT(0, DT);
    assert_int_equal(fc_pad_motion_init(&pm, &p), FC_INIT_BAD_PARAM);
    const fc_pad_motion_sample s = {FC_C(0.1f, LENGTH), true};
    assert_int_equal(fc_pad_motion_step(&pm, &s, &est), FC_STEP_NOT_READY);
    assert_int_equal(fc_pad_motion_work_ahead(&pm), FC_STEP_NOT_READY);
    assert_true(ts_val(est.confidence, FC_UNIT_FRAC) == 0.0);
    fc_vertical_trajectory ahead = {FC_INT(1, LENGTH), FC_INT(1, VEL), FC_INT(1, ACCEL)};
    fc_pad_motion_predict_ahead(&pm, &ahead);
    assert_true(ahead.z_m == FC_INT(0, LENGTH) && ahead.vz_mps == FC_INT(0, VEL) && ahead.az_mps2 == FC_INT(0, ACCEL));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_single_sine_off_grid),
        cmocka_unit_test(test_fast_pad),
        cmocka_unit_test(test_three_waves),
        cmocka_unit_test(test_still_pad),
        cmocka_unit_test(test_no_confidence_before_observing),
        cmocka_unit_test(test_outliers),
        cmocka_unit_test(test_bad_samples),
        cmocka_unit_test(test_work_ahead_between_steps),
        cmocka_unit_test(test_parameters_past_n_stay_zero),
        cmocka_unit_test(test_phases_turn_with_the_step),
        cmocka_unit_test(test_params_rejected),
    };
    return cmocka_run_group_tests_name(FC_NUMERIC_FIXED ? "pad_motion (fixed)" : "pad_motion (float)", tests, NULL,
                                       NULL);
}
