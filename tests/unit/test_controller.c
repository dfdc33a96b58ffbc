/*
 * Tests of the whole controller through its one entry point (fc/controller.h),
 * both backends. The closed loop here is a small 6-DOF check of the composition
 * (the rotor model is the library's own forward map); the independent plant is
 * the SIL's (sim_host).
 */
#include "controller_support.h"

static void test_every_airframe_and_variant_inits(void **state)
{
    (void)state;
    static fc_controller ctl; /* large: keep it off the stack */
    for (int a = 0; a < FC_AIRFRAME_COUNT; a++) {
        for (int v = 0; v < FC_ALT_VARIANT_COUNT; v++) {
            fc_controller_params p;
            fc_controller_default_params(&p, (fc_airframe)a, (fc_altitude_variant)v, F(0.002, DT));
            const fc_init_result r = fc_controller_init(&ctl, &p);
            if (r != FC_INIT_OK) {
                print_message("airframe %d variant %d: init %d\n", a, v, (int)r);
            }
            assert_int_equal(r, FC_INIT_OK);
        }
    }
}

static void test_disarmed_motors_off(void **state)
{
    (void)state;
    static fc_controller ctl;
    fc_controller_params p;
    init_at_500_hz(&ctl, &p, FC_AIRFRAME_HEXA_4KG, FC_ALT_VARIANT_SSC_ADAPTIVE);
    fc_controller_inputs in = level_at_rest(1.0);
    in.command = FC_COMMAND_DISARM;
    fc_controller_outputs out;
    (void)fc_controller_step(&ctl, &in, &out);
    assert_false(out.motors_on);
    assert_int_equal(out.rotor_count, 6);
    for (int i = 0; i < FC_MAX_ROTORS; i++) {
        assert_true(out.rotor_speed[i] == FC_INT(0, UNIT));
    }
    /* arming waits for the filter's alignment, with its reason */
    in.command = FC_COMMAND_TRACK_PAD;
    assert_true((fc_controller_step(&ctl, &in, &out) & FC_STEP_REFUSED) != 0u);
    assert_false(out.motors_on);
    assert_int_equal(out.telemetry.arming_blocked_by, FC_ARMING_NOT_ALIGNED);
    align_disarmed(&ctl, in);
    /* armed: speeds inside [u_min, 1] for the six rotors, 0 above */
    assert_int_equal(fc_controller_step(&ctl, &in, &out) & FC_STEP_REFUSED, 0u);
    assert_true(out.motors_on);
    assert_int_equal(out.telemetry.arming_blocked_by, FC_ARMING_OK);
    for (int i = 0; i < 6; i++) {
        assert_true(out.rotor_speed[i] >= p.allocation.rotor[i].speed_min);
        assert_true(out.rotor_speed[i] <= FC_INT(1, UNIT));
    }
    for (int i = 6; i < FC_MAX_ROTORS; i++) {
        assert_true(out.rotor_speed[i] == FC_INT(0, UNIT));
    }
}

static void test_bad_params_not_ready(void **state)
{
    (void)state;
    static fc_controller ctl;
    fc_controller_params p;
    fc_controller_default_params(&p, FC_AIRFRAME_CRAZYFLIE2, FC_ALT_VARIANT_SSC, F(0.002, DT));
    p.altitude.dt_s = F(0.004, DT); /* modules on different steps */
    assert_int_equal(fc_controller_init(&ctl, &p), FC_INIT_BAD_PARAM);
    fc_controller_inputs in = level_at_rest(0.5);
    fc_controller_outputs out;
    assert_int_equal(fc_controller_step(&ctl, &in, &out), FC_STEP_NOT_READY);
    assert_false(out.motors_on);
    fc_controller_default_params(&p, FC_AIRFRAME_CRAZYFLIE2, FC_ALT_VARIANT_SSC, F(0.002, DT));
    p.allocation.rotor_count = 0;
    assert_true(fc_controller_init(&ctl, &p) != FC_INIT_OK);
    fc_controller_default_params(&p, FC_AIRFRAME_CRAZYFLIE2, FC_ALT_VARIANT_SSC, F(0.002, DT));
    p.horizontal.tilt_max_rad = F(0, ANGLE);
    assert_int_equal(fc_controller_init(&ctl, &p), FC_INIT_BAD_PARAM);
}

static void test_bad_input_is_safe(void **state)
{
    (void)state;
    static fc_controller ctl;
    fc_controller_params p;
    init_at_500_hz(&ctl, &p, FC_AIRFRAME_HEXA_4KG, FC_ALT_VARIANT_SSC_ADAPTIVE);
    fc_controller_inputs in = level_at_rest(1.0);
    fc_controller_outputs out;
    align_disarmed(&ctl, in);
    (void)fc_controller_step(&ctl, &in, &out);
#if !FC_NUMERIC_FIXED
    in.position_m.z = NAN;
    assert_true((fc_controller_step(&ctl, &in, &out) & FC_STEP_BAD_INPUT) != 0u);
    assert_true(out.motors_on); /* flying on the last good inputs */
    assert_int_equal(out.telemetry.landing_state, FC_LANDING_IDLE);
    in = level_at_rest(1.0);
    in.imu.gyro_radps.x = INFINITY;
    const fc_step_status s = fc_controller_step(&ctl, &in, &out);
    assert_true((s & FC_STEP_BAD_INPUT) != 0u);
    for (int i = 0; i < FC_MAX_ROTORS; i++) {
        assert_true(isfinite(out.rotor_speed[i]) && out.rotor_speed[i] >= 0.0f && out.rotor_speed[i] <= 1.0f);
    }
#else
    in.position_m.z = INT32_MAX;
    in.velocity_mps.z = INT32_MIN;
    in.imu.gyro_radps.x = INT32_MAX;
    (void)fc_controller_step(&ctl, &in, &out);
    for (int i = 0; i < FC_MAX_ROTORS; i++) {
        assert_true(out.rotor_speed[i] >= 0 && out.rotor_speed[i] <= FC_INT(1, UNIT));
    }
#endif
}

/* ---- a small 6-DOF check of the composition --------------------------- */

typedef struct body { double p[3], v[3], q[4], w[3], speed[FC_MAX_ROTORS]; } body;

static void rotate(const double q[4], const double v[3], double out[3])
{
    /* v' = q v q*, q = (w, x, y, z) */
    const double w = q[0], x = q[1], y = q[2], z = q[3];
    const double t[3] = {2 * (y * v[2] - z * v[1]), 2 * (z * v[0] - x * v[2]), 2 * (x * v[1] - y * v[0])};
    out[0] = v[0] + w * t[0] + (y * t[2] - z * t[1]);
    out[1] = v[1] + w * t[1] + (z * t[0] - x * t[2]);
    out[2] = v[2] + w * t[2] + (x * t[1] - y * t[0]);
}

static void test_hexa_tracks_the_4_4_reference(void **state)
{
    (void)state;
    static fc_controller ctl;
    fc_controller_params p;
    const double dt = 0.002, h = 0.00025, mass = 4.0, inertia[3] = {0.082, 0.082, 0.149}, g = 9.81;
    fc_controller_default_params(&p, FC_AIRFRAME_HEXA_4KG, FC_ALT_VARIANT_SSC_ADAPTIVE, F(dt, DT));
    assert_int_equal(fc_controller_init(&ctl, &p), FC_INIT_OK);
    fc_allocation rotors; /* the rotor model: the library's forward map */
    assert_int_equal(fc_allocation_init(&rotors, &p.allocation), FC_INIT_OK);
    body b = {{0.3, -0.2, 1.18 + 1.0}, {0, 0, 0}, {1, 0, 0, 0}, {0, 0, 0}, {0}};
    double worst_late_error = 0.0, worst_tilt = 0.0;
    for (int k = 0; k < (int)(12.0 / dt); k++) {
        const double t = k * dt;
        double up_body[3];
        const double q_conj[4] = {b.q[0], -b.q[1], -b.q[2], -b.q[3]};
        rotate(q_conj, (const double[3]){0, 0, g}, up_body); /* at rest the IMU reads +g up */
        fc_controller_inputs in = level_at_rest(b.p[2]);
        in.imu.gyro_radps = fc_vec3_make(F(b.w[0], RATE), F(b.w[1], RATE), F(b.w[2], RATE));
        in.imu.accel_mps2 = fc_vec3_make(F(up_body[0], ACCEL), F(up_body[1], ACCEL), F(up_body[2], ACCEL));
        in.position_m = fc_vec3_make(F(b.p[0], LENGTH), F(b.p[1], LENGTH), F(b.p[2], LENGTH));
        in.velocity_mps = fc_vec3_make(F(b.v[0], VEL), F(b.v[1], VEL), F(b.v[2], VEL));
        fc_controller_outputs out;
        (void)fc_controller_step(&ctl, &in, &out);
        fc_vec3 force, moment;
        fc_allocation_forward_wrench(&rotors, out.rotor_speed, &force, &moment);
        const double f_body[3] = {D(force.x, FORCE), D(force.y, FORCE), D(force.z, FORCE)};
        const double m_body[3] = {D(moment.x, MOMENT), D(moment.y, MOMENT), D(moment.z, MOMENT)};
        for (int i = 0; i < (int)(dt / h + 0.5); i++) {
            double f_world[3];
            rotate(b.q, f_body, f_world);
            for (int j = 0; j < 3; j++) {
                b.v[j] += h * (f_world[j] / mass - (j == 2 ? g : 0.0));
                b.p[j] += h * b.v[j];
            }
            const double jw[3] = {inertia[0] * b.w[0], inertia[1] * b.w[1], inertia[2] * b.w[2]};
            const double wxjw[3] = {b.w[1] * jw[2] - b.w[2] * jw[1], b.w[2] * jw[0] - b.w[0] * jw[2],
                                    b.w[0] * jw[1] - b.w[1] * jw[0]};
            for (int j = 0; j < 3; j++) {
                b.w[j] += h * (m_body[j] - wxjw[j]) / inertia[j];
            }
            /* q' = 1/2 q (x) [0, w] */
            const double w0 = b.q[0], x0 = b.q[1], y0 = b.q[2], z0 = b.q[3];
            b.q[0] += h * 0.5 * (-x0 * b.w[0] - y0 * b.w[1] - z0 * b.w[2]);
            b.q[1] += h * 0.5 * (w0 * b.w[0] + y0 * b.w[2] - z0 * b.w[1]);
            b.q[2] += h * 0.5 * (w0 * b.w[1] + z0 * b.w[0] - x0 * b.w[2]);
            b.q[3] += h * 0.5 * (w0 * b.w[2] + x0 * b.w[1] - y0 * b.w[0]);
            const double n = sqrt(b.q[0] * b.q[0] + b.q[1] * b.q[1] + b.q[2] * b.q[2] + b.q[3] * b.q[3]);
            for (int j = 0; j < 4; j++) {
                b.q[j] /= n;
            }
        }
        const double tilt = acos(fmin(1.0, 1.0 - 2.0 * (b.q[1] * b.q[1] + b.q[2] * b.q[2])));
        worst_tilt = fmax(worst_tilt, tilt);
        const double z_r = 0.18 + exp(-(t + dt) / 0.1);
        if (t > 6.0) {
            worst_late_error = fmax(worst_late_error, fabs(b.p[2] - z_r));
        }
    }
    print_message("hexa, 4.4 reference over a still pad: |e| after 6 s <= %.2f mm, tilt <= %.2f deg, "
                  "x %.3f y %.3f m\n", worst_late_error * 1e3, worst_tilt * 57.2958, b.p[0], b.p[1]);
    assert_true(worst_late_error < 0.01);
    assert_true(worst_tilt < 0.35);
    assert_true(fabs(b.p[0]) < 0.02 && fabs(b.p[1]) < 0.02);
}

/* ---- rate groups ------------------------------------------------------ */

/* The outer group's major frame: 10 ms or one step, whichever is longer; its
 * modules' steps are dt times it, and init holds the parameters to that. */
static void test_outer_group_divider(void **state)
{
    (void)state;
    static fc_controller ctl;
    const struct { double dt_s; int divider; } cases[] = {{0.001, 10}, {0.002, 5}, {0.0025, 4}, {0.004, 2},
                                                          {0.01, 1}, {0.02, 1}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        fc_controller_params p;
        fc_controller_default_params(&p, FC_AIRFRAME_CRAZYFLIE2, FC_ALT_VARIANT_SSC, F(cases[i].dt_s, DT));
        assert_int_equal(p.outer_divider, cases[i].divider);
        assert_true(fabs(D(p.horizontal.dt_s, DT) - cases[i].divider * cases[i].dt_s) < 1e-6);
        assert_true(p.pad_motion.dt_s == p.horizontal.dt_s);
        assert_int_equal(fc_controller_init(&ctl, &p), FC_INIT_OK);
    }
    fc_controller_params p;
    fc_controller_default_params(&p, FC_AIRFRAME_CRAZYFLIE2, FC_ALT_VARIANT_SSC, F(0.002, DT));
    p.outer_divider = 0u;
    assert_int_equal(fc_controller_init(&ctl, &p), FC_INIT_BAD_PARAM);
    p.outer_divider = FC_OUTER_DIVIDER_MAX + 1u;
    assert_int_equal(fc_controller_init(&ctl, &p), FC_INIT_BAD_PARAM);
    p.outer_divider = 4u; /* the modules' steps no longer dt times it */
    assert_int_equal(fc_controller_init(&ctl, &p), FC_INIT_BAD_PARAM);
    fc_controller_default_params(&p, FC_AIRFRAME_CRAZYFLIE2, FC_ALT_VARIANT_SSC, F(0.002, DT));
    p.pad_motion.dt_s = p.dt_s;
    assert_int_equal(fc_controller_init(&ctl, &p), FC_INIT_BAD_PARAM);
}

static bool quat_equal(fc_quat a, fc_quat b)
{
    return a.w == b.w && a.x == b.x && a.y == b.y && a.z == b.z;
}

/* The position loop forms its demand in minor frame 0 and its attitude
 * setpoint in frame 1, held for the major frame; from arming to its first
 * attitude frame after a demand the setpoint is level at the heading. */
static void test_position_loop_once_a_major_frame(void **state)
{
    (void)state;
    static fc_controller ctl;
    fc_controller_params p;
    init_at_500_hz(&ctl, &p, FC_AIRFRAME_CRAZYFLIE2, FC_ALT_VARIANT_SSC);
    fc_controller_inputs in = level_at_rest(0.5);
    fc_controller_outputs out;
    align_disarmed(&ctl, in); /* a whole number of major frames: the next step is frame 0 */
    in.command = FC_COMMAND_DISARM;
    (void)fc_controller_step(&ctl, &in, &out); /* frame 0 disarmed: the loop does not run */
    in.command = FC_COMMAND_TRACK_PAD;
    fc_quat previous = fc_quat_identity();
    int changes = 0;
    for (int k = 1; k <= 30; k++) {
        /* a position error that grows every step: every run of the loop tilts further */
        in.position_m.x = F(0.01 * k, LENGTH);
        (void)fc_controller_step(&ctl, &in, &out);
        const fc_quat sp = out.telemetry.attitude_setpoint;
        if (k < 6) {
            /* armed in frame 1, no demand yet: level until the frame 1 after a frame 0 */
            assert_true(quat_equal(sp, fc_quat_identity()));
        } else if (!quat_equal(sp, previous)) {
            changes++;
            assert_int_equal(k % 5, 1); /* only in minor frame 1 */
        }
        previous = sp;
    }
    assert_int_equal(changes, 5); /* steps 6, 11, ..., 26 */
}

/* The pad model runs in minor frame 2: a range sample taken in frame 3 waits
 * for the next frame 2; between the model's runs its trajectory is extrapolated
 * (here the pad stands still, so it stays put and the level is the sample). */
static void test_pad_model_in_its_minor_frame(void **state)
{
    (void)state;
    static fc_controller ctl;
    fc_controller_params p;
    init_at_500_hz(&ctl, &p, FC_AIRFRAME_CRAZYFLIE2, FC_ALT_VARIANT_SSC);
    fc_controller_inputs in = level_at_rest(0.5);
    in.command = FC_COMMAND_HOLD;
    fc_controller_outputs out;
    for (int k = 0; k < 12; k++) {
        in.range_m = F(0.4, LENGTH); /* the pad's surface 0.1 m up */
        in.range_fresh = k == 3;      /* minor frame 3 */
        (void)fc_controller_step(&ctl, &in, &out);
        const bool learnt = out.telemetry.pad.learning;
        assert_true(learnt == (k >= 7)); /* taken in frame 2 of the next major frame */
        if (learnt) {
            assert_true(fabs(D(out.telemetry.pad.now.z_m, LENGTH) - 0.1) < 1e-5);
            assert_true(fabs(D(out.telemetry.pad.mean_m, LENGTH) - 0.1) < 1e-5);
        }
        if (k == 3) {
            assert_true(fabs(D(out.telemetry.gear_height_m, LENGTH) - (0.4 - 0.02)) < 1e-5); /* at once */
        }
    }
}

/* The yaw setpoint's rate is fed forward to the attitude law (as a turn about
 * the world's up axis, seen in the body): level and still, tracking the pad,
 * a rate of +1 rad/s asks for a positive yaw moment at every step (the
 * damping term's kd (r_ff - r)); the same vehicle without it asks for none. */
static void test_yaw_rate_feedforward(void **state)
{
    (void)state;
    static fc_controller without, with;
    fc_controller_params p;
    init_at_500_hz(&without, &p, FC_AIRFRAME_CRAZYFLIE2, FC_ALT_VARIANT_SSC);
    init_at_500_hz(&with, &p, FC_AIRFRAME_CRAZYFLIE2, FC_ALT_VARIANT_SSC);
    fc_controller_inputs in = level_at_rest(0.5);
    align_disarmed(&without, in);
    align_disarmed(&with, in);
    fc_controller_inputs in_ff = in;
    in_ff.yaw_rate_setpoint_radps = F(1.0, RATE);
    fc_controller_outputs out, out_ff;
    for (int k = 0; k < 10; k++) {
        (void)fc_controller_step(&without, &in, &out);
        (void)fc_controller_step(&with, &in_ff, &out_ff);
        assert_true(out.motors_on && out_ff.motors_on);
        const double yaw_nm = D(out.moment_nm.z, MOMENT), yaw_ff_nm = D(out_ff.moment_nm.z, MOMENT);
        assert_true(fabs(yaw_nm) < 1e-7);
        assert_true(yaw_ff_nm > 1e-6);
    }
}

/* The heading input reaches the filter: after the alignment a heading of
 * 0.4 rad turns the estimate to it (the controller flies on it); a bad one is
 * reported as bad input by the estimator and the step, and ignored. */
static void test_heading_input_reaches_the_filter(void **state)
{
    (void)state;
    static fc_controller ctl;
    fc_controller_params p;
    init_at_500_hz(&ctl, &p, FC_AIRFRAME_CRAZYFLIE2, FC_ALT_VARIANT_SSC);
    assert_false(p.use_external_attitude);
    fc_controller_inputs in = level_at_rest(0.5);
    in.command = FC_COMMAND_DISARM; /* the filter runs disarmed too */
    fc_controller_outputs out;
    for (int k = 0; k < 5000; k++) { /* 10 s: the alignment, then 10 time constants */
        in.heading_rad = F(0.4, ANGLE);
        in.heading_fresh = k % 5 == 0;
        const fc_step_status st = fc_controller_step(&ctl, &in, &out);
        assert_int_equal(st & FC_STEP_BAD_INPUT, 0u);
    }
    const double w = D(out.telemetry.attitude.w, UNIT), z = D(out.telemetry.attitude.z, UNIT);
    const double yaw = 2.0 * atan2(z, w);
    print_message("heading 0.4 rad at 100 Hz for 10 s: estimated yaw %.5f rad\n", yaw);
    assert_true(fabs(yaw - 0.4) < 1e-3);
    in.heading_rad = F(7.5, ANGLE);
    in.heading_fresh = true;
    const fc_step_status st = fc_controller_step(&ctl, &in, &out);
    assert_true((st & FC_STEP_BAD_INPUT) != 0u);
    assert_true((out.telemetry.estimator_status & FC_STEP_BAD_INPUT) != 0u);
    assert_true(fabs(2.0 * atan2(D(out.telemetry.attitude.z, UNIT), D(out.telemetry.attitude.w, UNIT)) - yaw) <
                1e-4);
}

/* With the platform's attitude in use the filter only forms the rate: the
 * attitude is the external one from the first step (no alignment; in fixed
 * rounded to UNIT16, the attitude law's format), the rate
 * is the gyro's, the heading input goes unused (a bad one is no bad input),
 * and a bad gyro still is. */
static void test_external_attitude_skips_the_filter(void **state)
{
    (void)state;
    static fc_controller ctl;
    fc_controller_params p;
    fc_controller_default_params(&p, FC_AIRFRAME_CRAZYFLIE2, FC_ALT_VARIANT_SSC, F(0.002, DT));
    p.use_external_attitude = true;
    assert_int_equal(fc_controller_init(&ctl, &p), FC_INIT_OK);
    fc_controller_inputs in = level_at_rest(0.5);
    in.command = FC_COMMAND_DISARM;
    const double half_roll = 0.05; /* 0.1 rad of roll */
    in.attitude_external = fc_quat_make(F(cos(half_roll), UNIT), F(sin(half_roll), UNIT), F(0, UNIT), F(0, UNIT));
    in.imu.gyro_radps = fc_vec3_make(F(0.2, RATE), F(-0.1, RATE), F(0.05, RATE));
    in.heading_rad = F(7.5, ANGLE);
    in.heading_fresh = true;
    fc_controller_outputs out;
    const fc_step_status st = fc_controller_step(&ctl, &in, &out);
    assert_int_equal(st & FC_STEP_BAD_INPUT, 0u);
    assert_int_equal(out.telemetry.estimator_status, FC_STEP_OK);
    /* taken at the attitude law's resolution: UNIT16 in fixed, half an LSB */
    const double attitude_tol = FC_NUMERIC_FIXED ? 0.5 / (1 << FC_UNIT16_FRAC) : 1e-6;
    assert_true(fabs(D(out.telemetry.attitude.x, UNIT) - sin(half_roll)) <= attitude_tol);
    assert_true(fabs(D(out.telemetry.rate_radps.x, RATE) - 0.2) < 1e-6);
    assert_true(fabs(D(out.telemetry.rate_radps.y, RATE) + 0.1) < 1e-6);
    assert_true(fabs(D(out.telemetry.rate_radps.z, RATE) - 0.05) < 1e-6);
    in.imu.gyro_radps.x = F(40.0, RATE); /* beyond the 35 rad/s range */
    const fc_step_status bad = fc_controller_step(&ctl, &in, &out);
    assert_true((bad & FC_STEP_BAD_INPUT) != 0u);
    assert_true((out.telemetry.estimator_status & FC_STEP_BAD_INPUT) != 0u);
    /* never the last good rate: the platform's attitude did not move, so 0 */
    assert_true(fabs(D(out.telemetry.rate_radps.x, RATE)) < 1e-6);
}

/* The measured acceleration of the feedback (2.10): R(q) f less gravity,
 * horizontal. Level at rest, and tilted at rest (the accelerometer reads
 * gravity in the body), give 0; tilted with the thrust holding the height
 * (f = g / cos along body z) gives g tan(roll) sideways; no sample, none.
 * Horizontal components within fc_quat_rotate_horizontal's bound, about
 * 2^-13 (|f_x| + |f_y| + |f_z|) in fixed, below a 16 g accelerometer's LSB
 * (4.8e-3 m/s2). */
static void test_measured_accel(void **state)
{
    (void)state;
    fc_arith ar = {0u};
    const double g = 9.81, roll = 0.2;
    const double horizontal_tol = FC_NUMERIC_FIXED ? 2e-3 : 1e-4;
    fc_vec3 a;
    /* level at rest */
    assert_true(fc_controller_measured_accel(&ar, fc_quat_identity(),
                                             fc_vec3_make(F(0, ACCEL), F(0, ACCEL), F(g, ACCEL)), true, &a));
    assert_true(fabs(D(a.x, ACCEL)) < 1e-5 && fabs(D(a.y, ACCEL)) < 1e-5 && fabs(D(a.z, ACCEL)) < 1e-5);
    /* rolled at rest: f = R^T (0, 0, g) = (0, g sin, g cos) */
    const fc_quat q = fc_quat_make(F(cos(roll / 2), UNIT), F(sin(roll / 2), UNIT), F(0, UNIT), F(0, UNIT));
    assert_true(fc_controller_measured_accel(
        &ar, q, fc_vec3_make(F(0, ACCEL), F(g * sin(roll), ACCEL), F(g * cos(roll), ACCEL)), true, &a));
    assert_true(fabs(D(a.x, ACCEL)) < horizontal_tol && fabs(D(a.y, ACCEL)) < horizontal_tol &&
                fabs(D(a.z, ACCEL)) < 1e-5);
    /* rolled, the thrust along body z holding the height: body z is (0, -sin, cos) in the world */
    assert_true(fc_controller_measured_accel(
        &ar, q, fc_vec3_make(F(0, ACCEL), F(0, ACCEL), F(g / cos(roll), ACCEL)), true, &a));
    assert_true(fabs(D(a.x, ACCEL)) < horizontal_tol);
    assert_true(fabs(D(a.y, ACCEL) + g * tan(roll)) < horizontal_tol);
    assert_true(fabs(D(a.z, ACCEL)) < 1e-5); /* the vertical axis is the altitude law's */
    /* no usable sample: false, and zero */
    assert_false(fc_controller_measured_accel(
        &ar, q, fc_vec3_make(F(0, ACCEL), F(0, ACCEL), F(g / cos(roll), ACCEL)), false, &a));
    assert_true(a.x == FC_INT(0, ACCEL) && a.y == FC_INT(0, ACCEL) && a.z == FC_INT(0, ACCEL));
    assert_int_equal(ar.saturated, 0u);
}

/* The Crazyflie on its own attitude (no alignment), tracking, holding its
 * position: count steps of the position loop's I_a. */
static void fly_steps(fc_controller *ctl, const fc_controller_inputs *in, int steps)
{
    fc_controller_outputs out;
    for (int k = 0; k < steps; k++) {
        (void)fc_controller_step(ctl, in, &out);
        assert_true(out.motors_on);
    }
}

static void init_external(fc_controller *ctl, double gain_per_s)
{
    fc_controller_params p;
    fc_controller_default_params(&p, FC_AIRFRAME_CRAZYFLIE2, FC_ALT_VARIANT_SSC, F(0.002, DT));
    p.use_external_attitude = true;
    p.horizontal.accel_fb_gain_per_s = F(gain_per_s, RATIO);
    assert_int_equal(fc_controller_init(ctl, &p), FC_INIT_OK);
}

/* fc_controller_step wires it: the IMU's sample and the attitude in use to
 * the position loop's feedback. At rest (level or tilted) I_a stays at 0; a
 * measured sideways acceleration the loop did not ask for moves I_a towards
 * it (horizontally only); a bad sample holds I_a; k_a = 0 flies without. */
static void test_accel_feedback_wiring(void **state)
{
    (void)state;
    static fc_controller ctl;
    const double g = 9.81, roll = 0.1;
    const fc_quat q = fc_quat_make(F(cos(roll / 2), UNIT), F(sin(roll / 2), UNIT), F(0, UNIT), F(0, UNIT));
    /* level at rest */
    init_external(&ctl, 0.5);
    fc_controller_inputs in = level_at_rest(0.5);
    fly_steps(&ctl, &in, 100);
    assert_true(fabs(D(ctl.position.accel_fb_mps2.x, ACCEL)) < 1e-5);
    assert_true(fabs(D(ctl.position.accel_fb_mps2.y, ACCEL)) < 1e-5);
    /* rolled at rest: the accelerometer reads gravity in the body */
    init_external(&ctl, 0.5);
    in.attitude_external = q;
    in.imu.accel_mps2 = fc_vec3_make(F(0, ACCEL), F(g * sin(roll), ACCEL), F(g * cos(roll), ACCEL));
    fly_steps(&ctl, &in, 100);
    assert_true(fabs(D(ctl.position.accel_fb_mps2.x, ACCEL)) < 1e-4);
    assert_true(fabs(D(ctl.position.accel_fb_mps2.y, ACCEL)) < 1e-4);
    /* rolled, the thrust holding the height: a = (0, -g tan(roll)) measured,
     * 0 wanted: 20 runs of the loop (100 steps) move I_a by k_a 0.2 s a */
    in.imu.accel_mps2 = fc_vec3_make(F(0, ACCEL), F(0, ACCEL), F(g / cos(roll), ACCEL));
    fly_steps(&ctl, &in, 100);
    const double expected = -0.5 * 0.2 * g * tan(roll);
    const double i_a = D(ctl.position.accel_fb_mps2.y, ACCEL);
    assert_true(i_a < 0.0 && fabs(i_a - expected) < 0.05 * fabs(expected));
    assert_true(fabs(D(ctl.position.accel_fb_mps2.x, ACCEL)) < 1e-4);
    assert_true(ctl.position.accel_fb_mps2.z == FC_INT(0, ACCEL));
    /* a bad sample (beyond the accelerometer's range, or none): I_a held */
    const fc_vec3 held = ctl.position.accel_fb_mps2;
    in.imu.accel_mps2 = fc_vec3_make(F(0, ACCEL), F(NAN_OR_LIMIT, ACCEL), F(g, ACCEL));
    fly_steps(&ctl, &in, 10);
    in.imu.accel_mps2 = fc_vec3_zero();
    fly_steps(&ctl, &in, 10);
    assert_true(ctl.position.accel_fb_mps2.x == held.x && ctl.position.accel_fb_mps2.y == held.y &&
                ctl.position.accel_fb_mps2.z == held.z);
    /* k_a = 0: no feedback */
    init_external(&ctl, 0.0);
    in.imu.accel_mps2 = fc_vec3_make(F(0, ACCEL), F(0, ACCEL), F(g / cos(roll), ACCEL));
    fly_steps(&ctl, &in, 100);
    assert_true(ctl.position.accel_fb_mps2.x == FC_INT(0, ACCEL) && ctl.position.accel_fb_mps2.y == FC_INT(0, ACCEL));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_airframe_and_variant_inits),
        cmocka_unit_test(test_disarmed_motors_off),
        cmocka_unit_test(test_bad_params_not_ready),
        cmocka_unit_test(test_bad_input_is_safe),
        cmocka_unit_test(test_hexa_tracks_the_4_4_reference),
        cmocka_unit_test(test_outer_group_divider),
        cmocka_unit_test(test_position_loop_once_a_major_frame),
        cmocka_unit_test(test_pad_model_in_its_minor_frame),
        cmocka_unit_test(test_yaw_rate_feedforward),
        cmocka_unit_test(test_heading_input_reaches_the_filter),
        cmocka_unit_test(test_external_attitude_skips_the_filter),
        cmocka_unit_test(test_measured_accel),
        cmocka_unit_test(test_accel_feedback_wiring),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
