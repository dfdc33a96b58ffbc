/*
 * Tests of the horizontal position PID and the acceleration control (2.10),
 * (2.11) with the attitude setpoint, one source for both backends.
 */
#include "test_support.h"

#include "fc/position_control.h"

#define DT 0.002
#define G0 9.80665

static fc_real ratio(double x) { return fc_from_float((float)x, FC_RATIO_FRAC); }
static fc_real accel(double x) { return fc_from_float((float)x, FC_ACCEL_FRAC); }
static fc_real length(double x) { return fc_from_float((float)x, FC_LENGTH_FRAC); }
static fc_real force(double x) { return fc_from_float((float)x, FC_FORCE_FRAC); }

static fc_position_control_params default_params(void)
{
    fc_position_control_params p;
    p.dt_s = fc_from_float((float)DT, FC_DT_FRAC);
    p.kp_per_s2 = ratio(4.0);   /* w_n = 2 rad/s */
    p.ki_per_s3 = ratio(0.0);
    p.kd_per_s = ratio(2.8);    /* zeta = 0.7 */
    p.error_max_m = length(50.0);
    p.integral_max_mps2 = accel(2.0);
    p.accel_max_mps2 = accel(20.0);
    p.mass_kg = fc_from_float(1.5f, FC_MASS_FRAC);
    p.accel_fb_gain_per_s = ratio(0.0);
    p.accel_fb_max_mps2 = accel(2.0);
    p.tilt_max_rad = fc_from_float(0.6f, FC_ANGLE_FRAC);
    p.thrust_min_n = force(1.0);
    p.thrust_max_n = force(40.0);
    return p;
}

/* One step's input values, held by the test: fc_position_control_step reads
 * the vectors by reference and takes the heading on its own (step_sample). */
typedef struct pos_sample {
    fc_vec3 position_m;
    fc_vec3 velocity_mps;
    fc_vec3 position_sp_m;
    fc_vec3 velocity_sp_mps;
    fc_vec3 accel_ff_mps2;
    fc_vec3 accel_meas_mps2;
    bool accel_meas_ok;
    fc_real heading_cos;
    fc_real heading_sin;
} pos_sample;

static fc_step_status step_sample(fc_position_control *pc, const pos_sample *s, fc_position_control_output *out)
{
    const fc_position_control_input in = {&s->position_m,      &s->velocity_mps,  &s->position_sp_m,
                                          &s->velocity_sp_mps, &s->accel_ff_mps2, &s->accel_meas_mps2,
                                          s->accel_meas_ok};
    return fc_position_control_step(pc, &in, s->heading_cos, s->heading_sin, out);
}

static pos_sample still_input(void)
{
    pos_sample in;
    in.position_m = fc_vec3_zero();
    in.velocity_mps = fc_vec3_zero();
    in.position_sp_m = fc_vec3_zero();
    in.velocity_sp_mps = fc_vec3_zero();
    in.accel_ff_mps2 = fc_vec3_zero();
    in.accel_meas_mps2 = fc_vec3_zero();
    in.accel_meas_ok = true;
    in.heading_cos = FC_INT(1, UNIT);
    in.heading_sin = FC_INT(0, UNIT);
    return in;
}

/* x'' + k_D x' + k_P x = k_P (unit step, zeta < 1) */
static double step_response(double t, double kp, double kd)
{
    const double wn = sqrt(kp), zeta = kd / (2 * wn), wd = wn * sqrt(1 - zeta * zeta);
    return 1.0 - exp(-zeta * wn * t) * (cos(wd * t) + zeta * wn / wd * sin(wd * t));
}

/* the double integrator x'' = a + d over one step (exact for a held) */
static void plant(double *x, double *v, double a)
{
    *x += *v * DT + 0.5 * a * DT * DT;
    *v += a * DT;
}

static void test_pd_step_response(void **state)
{
    (void)state;
    const fc_position_control_params p = default_params();
    fc_position_control pc;
    assert_int_equal(fc_position_control_init(&pc, &p), FC_INIT_OK);
    const double kp = ts_val(p.kp_per_s2, FC_RATIO_FRAC), kd = ts_val(p.kd_per_s, FC_RATIO_FRAC);
    pos_sample in = still_input();
    in.position_sp_m = fc_vec3_make(FC_INT(1, LENGTH), FC_INT(0, LENGTH), FC_INT(0, LENGTH));
    double x = 0.0, v = 0.0, worst = 0.0;
    for (int k = 0; k < 5000; k++) {
        worst = fmax(worst, fabs(x - step_response(k * DT, kp, kd)));
        in.position_m.x = fc_from_float((float)x, FC_LENGTH_FRAC);
        in.velocity_mps.x = fc_from_float((float)v, FC_VEL_FRAC);
        fc_position_control_output out;
        assert_int_equal(step_sample(&pc, &in, &out), FC_STEP_OK);
        TS_ASSERT_REAL_EQ(out.accel_des_mps2.y, FC_INT(0, ACCEL));
        plant(&x, &v, ts_val(out.accel_des_mps2.x, FC_ACCEL_FRAC));
    }
    print_message("PD step on x'' = a: worst |x - x_analytic| %.3g m\n", worst);
    assert_true(worst < 1e-2); /* sampling at 500 Hz against the continuous response */
    assert_true(fabs(x - 1.0) < 1e-3);
}

static void test_integral_removes_bias(void **state)
{
    (void)state;
    fc_position_control_params p = default_params();
    p.ki_per_s3 = ratio(1.5);
    fc_position_control pc;
    assert_int_equal(fc_position_control_init(&pc, &p), FC_INIT_OK);
    pos_sample in = still_input();
    double x = 0.0, y = 0.0, vx = 0.0, vy = 0.0;
    const double dx = -0.3, dy = 0.2; /* wind */
    for (int k = 0; k < 15000; k++) {
        in.position_m = fc_vec3_make(length(x), length(y), FC_INT(0, LENGTH));
        in.velocity_mps = fc_vec3_make(fc_from_float((float)vx, FC_VEL_FRAC), fc_from_float((float)vy, FC_VEL_FRAC),
                                       FC_INT(0, VEL));
        fc_position_control_output out;
        assert_int_equal(step_sample(&pc, &in, &out), FC_STEP_OK);
        plant(&x, &vx, ts_val(out.accel_des_mps2.x, FC_ACCEL_FRAC) + dx);
        plant(&y, &vy, ts_val(out.accel_des_mps2.y, FC_ACCEL_FRAC) + dy);
    }
    assert_true(fabs(x) < 1e-3 && fabs(y) < 1e-3);
    TS_ASSERT_CLOSE(ts_val(pc.integral_mps2.x, FC_ACCEL_FRAC), -dx, 1e-3);
    TS_ASSERT_CLOSE(ts_val(pc.integral_mps2.y, FC_ACCEL_FRAC), -dy, 1e-3);
}

static void test_anti_windup(void **state)
{
    (void)state;
    fc_position_control_params p = default_params();
    p.ki_per_s3 = ratio(2.0);
    p.accel_max_mps2 = accel(1.0);
    fc_position_control pc;
    assert_int_equal(fc_position_control_init(&pc, &p), FC_INIT_OK);
    pos_sample in = still_input();
    in.position_sp_m = fc_vec3_make(FC_INT(10, LENGTH), FC_INT(0, LENGTH), FC_INT(0, LENGTH));
    /* held away (the plant cannot follow): the output stays limited, the
     * integrator does not wind up */
    for (int k = 0; k < 2000; k++) {
        fc_position_control_output out;
        const fc_step_status st = step_sample(&pc, &in, &out);
        assert_true((st & FC_STEP_OUTPUT_LIMITED) != 0u);
        assert_true((st & FC_STEP_ARITH_SATURATED) == 0u);
        TS_ASSERT_CLOSE(ts_val(out.accel_des_mps2.x, FC_ACCEL_FRAC), 1.0, ts_tol(FC_ACCEL_FRAC, 2, 2, 1.0));
    }
    TS_ASSERT_REAL_EQ(pc.integral_mps2.x, FC_INT(0, ACCEL));
    /* unsaturated: it integrates, and stays bounded by integral_max */
    p.accel_max_mps2 = accel(50.0);
    p.kp_per_s2 = ratio(0.0);
    p.kd_per_s = ratio(0.0);
    assert_int_equal(fc_position_control_init(&pc, &p), FC_INIT_OK);
    for (int k = 0; k < 2000; k++) {
        fc_position_control_output out;
        (void)step_sample(&pc, &in, &out);
    }
    TS_ASSERT_CLOSE(ts_val(pc.integral_mps2.x, FC_ACCEL_FRAC), 2.0, ts_tol(FC_ACCEL_FRAC, 4, 4, 2.0));
}

/* saturated by a feedforward, the error opposing the output: integrating
 * helps to leave the limit, so it is allowed (conditional integration) */
static void test_integrates_out_of_saturation(void **state)
{
    (void)state;
    fc_position_control_params p = default_params();
    p.ki_per_s3 = ratio(2.0);
    p.kp_per_s2 = ratio(1.0);
    p.accel_max_mps2 = accel(1.0);
    fc_position_control pc;
    assert_int_equal(fc_position_control_init(&pc, &p), FC_INIT_OK);
    pos_sample in = still_input();
    in.position_sp_m.x = length(-0.5);
    in.accel_ff_mps2.x = accel(5.0);
    fc_position_control_output out;
    for (int k = 0; k < 100; k++) {
        assert_true((step_sample(&pc, &in, &out) & FC_STEP_OUTPUT_LIMITED) != 0u);
    }
    /* 100 steps of k_I dt e = 2 * 0.002 * -0.5 */
    TS_ASSERT_CLOSE(ts_val(pc.integral_mps2.x, FC_ACCEL_FRAC), -0.2, ts_tol(FC_ACCEL_FRAC, 200, 400, 0.2));
}

static void test_error_saturation_keeps_direction(void **state)
{
    (void)state;
    fc_position_control_params p = default_params();
    p.error_max_m = length(2.0);
    p.kd_per_s = ratio(0.0);
    p.kp_per_s2 = ratio(1.0);
    fc_position_control pc;
    assert_int_equal(fc_position_control_init(&pc, &p), FC_INIT_OK);
    pos_sample in = still_input();
    in.position_sp_m = fc_vec3_make(FC_INT(30, LENGTH), FC_INT(40, LENGTH), FC_INT(7, LENGTH));
    fc_position_control_output out;
    assert_int_equal(step_sample(&pc, &in, &out), FC_STEP_OK);
    /* |e| clipped to 2 m along (0.6, 0.8): a = (1.2, 1.6) */
    TS_ASSERT_CLOSE(ts_val(out.accel_des_mps2.x, FC_ACCEL_FRAC), 1.2, ts_tol(FC_ACCEL_FRAC, 8, 8, 2.0));
    TS_ASSERT_CLOSE(ts_val(out.accel_des_mps2.y, FC_ACCEL_FRAC), 1.6, ts_tol(FC_ACCEL_FRAC, 8, 8, 2.0));
    TS_ASSERT_REAL_EQ(out.accel_des_mps2.z, FC_INT(0, ACCEL));
}

static void test_attitude_setpoint(void **state)
{
    (void)state;
    const fc_position_control_params p = default_params();
    const double m = ts_val(p.mass_kg, FC_MASS_FRAC);
    const double tilt_max = ts_val(p.tilt_max_rad, FC_ANGLE_FRAC);
    fc_position_control pc;
    ts_rng rng = ts_rng_seed(11u);
    ts_check axis = ts_check_begin("body z = thrust direction");
    ts_check thrust = ts_check_begin("collective thrust = |F|");
    ts_check head = ts_check_begin("level heading");
    for (int k = 0; k < 2000; k++) {
        assert_int_equal(fc_position_control_init(&pc, &p), FC_INIT_OK);
        pos_sample in = still_input();
        double ax, ay, az;
        in.accel_ff_mps2 = fc_vec3_make(ts_in(ts_uniform(&rng, -8, 8), FC_ACCEL_FRAC, &ax),
                                        ts_in(ts_uniform(&rng, -8, 8), FC_ACCEL_FRAC, &ay),
                                        ts_in(ts_uniform(&rng, -3, 3), FC_ACCEL_FRAC, &az));
        const double psi = (double)ts_uniform(&rng, -3.14159f, 3.14159f);
        in.heading_cos = fc_from_float((float)cos(psi), FC_UNIT_FRAC);
        in.heading_sin = fc_from_float((float)sin(psi), FC_UNIT_FRAC);
        fc_position_control_output out;
        const fc_step_status st = step_sample(&pc, &in, &out);
        assert_true((st & ~FC_STEP_OUTPUT_LIMITED) == 0u);
        /* the wanted force (2.11) and its tilt limit, in double */
        double fx = m * ax, fy = m * ay, fz = m * (az + G0);
        const double fh = hypot(fx, fy), fh_max = fz * tan(tilt_max);
        if (fh > fh_max) {
            fx *= fh_max / fh;
            fy *= fh_max / fh;
            assert_true((st & FC_STEP_OUTPUT_LIMITED) != 0u);
        }
        const double f = sqrt(fx * fx + fy * fy + fz * fz);
        /* body z axis of q_sp */
        const fc_vec3 bz = fc_quat_rotate(&pc.ar, out.attitude_sp,
                                          fc_vec3_make(FC_INT(0, UNIT), FC_INT(0, UNIT), FC_INT(1, UNIT)));
        const double b[3] = {ts_val(bz.x, FC_UNIT_FRAC), ts_val(bz.y, FC_UNIT_FRAC), ts_val(bz.z, FC_UNIT_FRAC)};
        const double want[3] = {fx / f, fy / f, fz / f};
        /* fixed: the direction of F within 2.2 UNIT16 LSB a component
         * (fc_direction16), then q_tilt at half scale (|.| >= 0.7) rounded to
         * UNIT16, 2^-15 a component: the body z axis turns by at most twice
         * the relative error of the quaternion */
        const double axis_tol = FC_NUMERIC_FIXED ? 2.2 * 0x1p-14 + 2.0 * sqrt(3.0) * 0x1p-15 / 0.7
                                                 : ts_tol(FC_UNIT_FRAC, 256, 16, 1.0);
        for (int i = 0; i < 3; i++) {
            ts_close(&axis, b[i], want[i], axis_tol, "%d axis %d", k, i);
        }
        assert_true(acos(fmin(1.0, b[2])) <= tilt_max + 1e-5 + sqrt(3.0) * axis_tol);
        /* fixed: |F| within 1.37 2^-14 of itself (fc_direction16) */
        const double thrust_tol = FC_NUMERIC_FIXED ? 1.37 * 0x1p-14 * f : ts_tol(FC_FORCE_FRAC, 8, 16, f);
        ts_close(&thrust, ts_val(out.thrust_n, FC_FORCE_FRAC), f, thrust_tol, "%d", k);
        /* unit length and w >= 0 */
        const double qw = ts_val(out.attitude_sp.w, FC_UNIT_FRAC), qx = ts_val(out.attitude_sp.x, FC_UNIT_FRAC);
        const double qy = ts_val(out.attitude_sp.y, FC_UNIT_FRAC), qz = ts_val(out.attitude_sp.z, FC_UNIT_FRAC);
        assert_true(fabs(qw * qw + qx * qx + qy * qy + qz * qz - 1.0) < 1e-6 && qw >= 0.0);
        /* level (no horizontal force): q is the yaw rotation by psi */
        if (k % 4 == 0) {
            in.accel_ff_mps2 = fc_vec3_zero();
            assert_int_equal(fc_position_control_init(&pc, &p), FC_INIT_OK);
            assert_int_equal(step_sample(&pc, &in, &out), FC_STEP_OK);
            const double sgn = cos(psi / 2) >= 0 ? 1.0 : -1.0;
            /* fixed: cos, sin rounded to UNIT16 and halved, 1.5 2^-15 on each
             * of q_yaw's two components at half scale (|.| >= 0.7); the
             * normalised q moves by at most twice the relative error */
            const double head_tol = FC_NUMERIC_FIXED ? 2.0 * sqrt(2.0) * 1.5 * 0x1p-15 / 0.7
                                                     : ts_tol(FC_UNIT_FRAC, 64, 16, 1.0);
            ts_close(&head, ts_val(out.attitude_sp.w, FC_UNIT_FRAC), sgn * cos(psi / 2), head_tol, "w %d", k);
            ts_close(&head, ts_val(out.attitude_sp.z, FC_UNIT_FRAC), sgn * sin(psi / 2), head_tol, "z %d", k);
            TS_ASSERT_CLOSE(ts_val(out.attitude_sp.x, FC_UNIT_FRAC), 0.0, 1e-7);
        }
    }
    ts_check_end(&axis);
    ts_check_end(&thrust);
    ts_check_end(&head);
}

static void test_acceleration_feedback_corrects_mass(void **state)
{
    (void)state;
    fc_position_control_params p = default_params();
    p.accel_fb_gain_per_s = ratio(2.0);
    fc_position_control pc;
    assert_int_equal(fc_position_control_init(&pc, &p), FC_INIT_OK);
    const double m_true = 1.65; /* 10 % heavier than the model */
    pos_sample in = still_input();
    double a_meas = 0.0;
    for (int k = 0; k < 5000; k++) {
        in.accel_meas_mps2 = fc_vec3_make(FC_INT(0, ACCEL), FC_INT(0, ACCEL), accel(a_meas));
        fc_position_control_output out;
        assert_int_equal(step_sample(&pc, &in, &out), FC_STEP_OK);
        a_meas = ts_val(out.thrust_world_n.z, FC_FORCE_FRAC) / m_true - G0; /* (2.10) */
    }
    assert_true(fabs(a_meas) < 1e-3);
    /* bounded correction: with a 50 % mass error it stops at accel_fb_max */
    assert_int_equal(fc_position_control_init(&pc, &p), FC_INIT_OK);
    for (int k = 0; k < 5000; k++) {
        in.accel_meas_mps2 = fc_vec3_make(FC_INT(0, ACCEL), FC_INT(0, ACCEL), accel(a_meas));
        fc_position_control_output out;
        (void)step_sample(&pc, &in, &out);
        a_meas = ts_val(out.thrust_world_n.z, FC_FORCE_FRAC) / 2.25 - G0;
    }
    TS_ASSERT_CLOSE(ts_val(pc.accel_fb_mps2.z, FC_ACCEL_FRAC), -2.0, 1e-5);
    /* no measurement (accel_meas_ok false): I_a held, and no bad input */
    const fc_vec3 held = pc.accel_fb_mps2;
    in.accel_meas_mps2 = fc_vec3_make(FC_INT(0, ACCEL), FC_INT(0, ACCEL), accel(5.0));
    in.accel_meas_ok = false;
    fc_position_control_output out;
    assert_int_equal(step_sample(&pc, &in, &out) & FC_STEP_BAD_INPUT, 0);
    TS_ASSERT_REAL_EQ(pc.accel_fb_mps2.z, held.z);
}

static void test_bad_input(void **state)
{
    (void)state;
    const fc_position_control_params p = default_params();
    fc_position_control pc;
    assert_int_equal(fc_position_control_init(&pc, &p), FC_INIT_OK);
    pos_sample in = still_input();
    fc_position_control_output out;
    /* zero-length heading: taken as psi = 0 */
    in.heading_cos = FC_INT(0, UNIT);
    assert_int_equal(step_sample(&pc, &in, &out), FC_STEP_BAD_INPUT);
    TS_ASSERT_CLOSE(ts_val(out.attitude_sp.w, FC_UNIT_FRAC), 1.0, 1e-6);
    TS_ASSERT_CLOSE(ts_val(out.thrust_n, FC_FORCE_FRAC), 1.5 * G0, 1e-4);
    /* a vertical acceleration demand below free fall: floor of the thrust */
    in = still_input();
    in.accel_ff_mps2.z = accel(-20.0);
    assert_int_equal(step_sample(&pc, &in, &out), FC_STEP_OUTPUT_LIMITED);
    TS_ASSERT_REAL_EQ(out.thrust_n, p.thrust_min_n);
#if !FC_NUMERIC_FIXED
    in = still_input();
    in.position_m.x = NAN;
    in.position_sp_m.y = 3.0f;
    assert_int_equal(step_sample(&pc, &in, &out), FC_STEP_BAD_INPUT);
    assert_true(out.accel_des_mps2.x == 0.0f && out.accel_des_mps2.y == 0.0f);
    assert_true(isfinite(out.thrust_n) && out.thrust_n > 0.0f);
    in = still_input();
    in.accel_ff_mps2.z = INFINITY;
    in.accel_meas_mps2.x = NAN;
    assert_int_equal(step_sample(&pc, &in, &out), FC_STEP_BAD_INPUT);
    assert_true(isfinite(out.thrust_n) && isfinite(out.attitude_sp.w));
    assert_true(pc.accel_fb_mps2.x == 0.0f);
#endif
}

static void test_bad_params(void **state)
{
    (void)state;
    fc_position_control pc;
    fc_position_control_params p = default_params();
    const pos_sample in = still_input();
    fc_position_control_output out;
    p.dt_s = FC_INT(0, DT);
    assert_int_equal(fc_position_control_init(&pc, &p), FC_INIT_BAD_PARAM);
    assert_int_equal(step_sample(&pc, &in, &out), FC_STEP_NOT_READY);
    TS_ASSERT_REAL_EQ(out.thrust_n, FC_INT(0, FORCE));
    TS_ASSERT_REAL_EQ(out.attitude_sp.w, FC_INT(1, UNIT));
    p = default_params();
    p.thrust_max_n = p.thrust_min_n;
    assert_int_equal(fc_position_control_init(&pc, &p), FC_INIT_BAD_PARAM);
    p = default_params();
    p.tilt_max_rad = fc_from_float(1.5f, FC_ANGLE_FRAC);
    assert_int_equal(fc_position_control_init(&pc, &p), FC_INIT_BAD_PARAM);
    p = default_params();
    p.kp_per_s2 = ratio(-1.0);
    assert_int_equal(fc_position_control_init(&pc, &p), FC_INIT_BAD_PARAM);
    p = default_params();
    p.error_max_m = FC_INT(0, LENGTH);
    assert_int_equal(fc_position_control_init(&pc, &p), FC_INIT_BAD_PARAM);
#if !FC_NUMERIC_FIXED
    p = default_params();
    p.mass_kg = NAN;
    assert_int_equal(fc_position_control_init(&pc, &p), FC_INIT_BAD_PARAM);
#endif
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pd_step_response),
        cmocka_unit_test(test_integral_removes_bias),
        cmocka_unit_test(test_anti_windup),
        cmocka_unit_test(test_integrates_out_of_saturation),
        cmocka_unit_test(test_error_saturation_keeps_direction),
        cmocka_unit_test(test_attitude_setpoint),
        cmocka_unit_test(test_acceleration_feedback_corrects_mass),
        cmocka_unit_test(test_bad_input),
        cmocka_unit_test(test_bad_params),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
