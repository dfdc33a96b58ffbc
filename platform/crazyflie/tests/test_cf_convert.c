/*
 * Host tests of the Crazyflie app's conversions and decisions (cf_convert.c),
 * in the numeric backend of the `fc` library this build selected. The frame
 * conventions are checked physically (which way the nose points), and the
 * quaternion/Euler pair against the formulas the firmware's estimators use to
 * publish state.attitude from their quaternion.
 */
#include <stdarg.h>
#include <stdio.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <math.h>
#include <string.h>
#include <cmocka.h>

#include "cf_app.h"
#include "cf_convert.h"
#include "cf_test_plant.h"

#define D(x, KIND) val((x), FC_##KIND##_FRAC)
#define PI 3.14159265358979323846

/* Exact value of a backend number. */
static double val(fc_real x, int frac)
{
#if FC_NUMERIC_FIXED
    return ldexp((double)x, -frac);
#else
    (void)frac;
    return (double)x;
#endif
}

/* |got - want| within a few LSB of the format in fixed, a few float ulps in float. */
static void near_fmt_double(double got, double want, int frac, double lsb)
{
#if FC_NUMERIC_FIXED
    const double tol = lsb * ldexp(1.0, -frac) + 4.0 * 1.2e-7 * fabs(want);
#else
    (void)frac;
    (void)lsb;
    const double tol = 4.0 * 1.2e-7 * fabs(want) + 1e-12;
#endif
    if (!(fabs(got - want) <= tol)) {
        print_error("got %.9g, want %.9g (tol %.3g)\n", got, want, tol);
        fail();
    }
}

static void near_abs_double(double got, double want, double tol)
{
    if (!(fabs(got - want) <= tol)) {
        print_error("got %.9g, want %.9g (tol %.3g)\n", got, want, tol);
        fail();
    }
}

/* Values under test are often floats: compared in double, promoted on purpose
 * (clang's -Wdouble-promotion flags the implicit promotion of an argument). */
#define near_fmt(got, want, frac, lsb) near_fmt_double((double)(got), (double)(want), (frac), (lsb))
#define near_abs(got, want, tol) near_abs_double((double)(got), (double)(want), (tol))

/* The cf2's platform constants (platform_defaults_cf2.h, 2.1+ propellers), as cf_glue.c passes them. */
static const cf_airframe cf2_airframe = {0.029f, 0.046f, 0.12f, 0.012817578f, 0.0069928949f};
/* The cf21bl's (platform_defaults_cf21bl.h, 200 mN per motor). */
static const cf_airframe cf21bl_airframe = {0.0393f, 0.050f, 0.2f, 0.02136263f, 0.00569278844f};

/* The app's tuning as loaded at boot (the library's Crazyflie defaults). */
static const cf_tuning *loaded(void)
{
    static cf_tuning t = CF_TUNING_INITIALIZER;
    (void)cf_tuning_prepare(&t);
    return &t;
}

static cf_sample hover_sample(void)
{
    cf_sample s;
    memset(&s, 0, sizeof s);
    s.acc_g[2] = 1.0f;
    s.quat_xyzw[3] = 1.0f;
    s.pos_m[2] = 0.18f;
    s.sp_mode_x = s.sp_mode_y = s.sp_mode_z = CF_MODE_ABS;
    s.sp_pos_m[2] = 0.5f;
    return s;
}

/* ---- units ------------------------------------------------------------------ */

static void test_units(void **state)
{
    (void)state;
    near_abs(cf_rad_from_deg(180.0f), PI, 1e-6);
    near_abs(cf_rad_from_deg(-90.0f), -PI / 2, 1e-6);
    near_abs(cf_mps2_from_g(1.0f), 9.81, 1e-6);
    near_abs(cf_mps2_from_g(-2.0f), -19.62, 1e-5);
    near_abs(cf_wrap_pi(1.5f * (float)PI), -PI / 2, 1e-6);
    near_abs(cf_wrap_pi(-7.0f), -7.0 + 2 * PI, 1e-6);
    near_abs(cf_wrap_pi(0.25f), 0.25, 0.0);
    assert_true(isnan(cf_wrap_pi(NAN)));
    assert_false(isfinite(cf_wrap_pi(INFINITY)));
}

/* ---- quaternions ---------------------------------------------------------------- */

static void test_quat_component_order(void **state)
{
    (void)state;
    /* scalar last in, scalar first out */
    const fc_quat q = cf_quat_from_xyzw(0.1f, -0.2f, 0.3f, 0.9273618f);
    near_fmt(D(q.w, UNIT), (double)0.9273618f, FC_UNIT_FRAC, 1);
    near_fmt(D(q.x, UNIT), (double)0.1f, FC_UNIT_FRAC, 1);
    near_fmt(D(q.y, UNIT), (double)-0.2f, FC_UNIT_FRAC, 1);
    near_fmt(D(q.z, UNIT), (double)0.3f, FC_UNIT_FRAC, 1);
    float xyzw[4];
    cf_quat_to_xyzw(q, xyzw);
    near_abs(xyzw[0], 0.1, 1e-7);
    near_abs(xyzw[1], -0.2, 1e-7);
    near_abs(xyzw[2], 0.3, 1e-7);
    near_abs(xyzw[3], 0.9273618, 1e-7);
}

/* Body axis e (0, 1, 2) of q seen in the world: column e of R(q). */
static void body_axis_in_world(fc_quat q, int e, double out[3])
{
    const double w = D(q.w, UNIT), x = D(q.x, UNIT), y = D(q.y, UNIT), z = D(q.z, UNIT);
    const double r[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
                            {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
                            {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}};
    for (int i = 0; i < 3; i++) {
        out[i] = r[i][e];
    }
}

static void test_legacy_euler_physical(void **state)
{
    (void)state;
    double v[3];
    /* legacy pitch +30 deg is nose up (the legacy sign is inverted) */
    body_axis_in_world(cf_quat_from_legacy_rpy_deg(0.0f, 30.0f, 0.0f), 0, v);
    near_abs(v[0], cos(PI / 6), 1e-6);
    near_abs(v[2], 0.5, 1e-6);
    /* roll +20 deg lifts the left side (body y) */
    body_axis_in_world(cf_quat_from_legacy_rpy_deg(20.0f, 0.0f, 0.0f), 1, v);
    near_abs(v[2], sin(20 * PI / 180), 1e-6);
    /* yaw +40 deg turns the nose left (counter-clockwise seen from above, z up) */
    body_axis_in_world(cf_quat_from_legacy_rpy_deg(0.0f, 0.0f, 40.0f), 0, v);
    near_abs(v[0], cos(40 * PI / 180), 1e-6);
    near_abs(v[1], sin(40 * PI / 180), 1e-6);
}

static void test_legacy_euler_matches_estimator(void **state)
{
    (void)state;
    /* state.attitude is published from the estimator's quaternion (w, x, y, z) as
     * yaw = atan2(2(xy + wz), w^2 + x^2 - y^2 - z^2), pitch = asin(-2(xz - wy)),
     * roll = atan2(2(yz + wx), w^2 - x^2 - y^2 + z^2), legacy pitch = -pitch.
     * The conversion must invert exactly that. */
    const float cases[][3] = {{10.0f, -25.0f, 100.0f}, {-45.0f, 15.0f, -170.0f}, {5.0f, 60.0f, 0.5f}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        const fc_quat q = cf_quat_from_legacy_rpy_deg(cases[i][0], cases[i][1], cases[i][2]);
        const double w = D(q.w, UNIT), x = D(q.x, UNIT), y = D(q.y, UNIT), z = D(q.z, UNIT);
        const double yaw = atan2(2 * (x * y + w * z), w * w + x * x - y * y - z * z) * 180 / PI;
        const double pitch = asin(-2 * (x * z - w * y)) * 180 / PI;
        const double roll = atan2(2 * (y * z + w * x), w * w - x * x - y * y + z * z) * 180 / PI;
        near_abs(roll, cases[i][0], 1e-4);
        near_abs(-pitch, cases[i][1], 1e-4);
        near_abs(yaw, cases[i][2], 1e-4);
    }
}

/* ---- inputs ------------------------------------------------------------------------ */

static void test_inputs_units_and_frames(void **state)
{
    (void)state;
    cf_tuning t = CF_TUNING_INITIALIZER;
    assert_true(cf_tuning_prepare(&t));
    cf_session ss;
    cf_session_reset(&ss);
    cf_sample s = hover_sample();
    s.gyro_dps[0] = 90.0f;
    s.gyro_dps[1] = -180.0f;
    s.gyro_dps[2] = 360.0f;
    s.acc_g[0] = 0.1f;
    s.acc_g[1] = -0.2f;
    s.acc_g[2] = 1.05f;
    s.quat_xyzw[0] = 0.0f;
    s.quat_xyzw[1] = 0.0f;
    s.quat_xyzw[2] = 0.38268343f; /* 45 deg about z */
    s.quat_xyzw[3] = 0.92387953f;
    s.pos_m[0] = 1.5f;
    s.pos_m[1] = -2.25f;
    s.pos_m[2] = 0.75f;
    s.vel_mps[0] = 0.5f;
    s.vel_mps[1] = -0.25f;
    s.vel_mps[2] = -1.0f;
    fc_controller_inputs in;
    cf_inputs_from_sample(&s, &ss, &t, FC_COMMAND_TRACK_PAD, &in);
    near_fmt(D(in.imu.gyro_radps.x, RATE), PI / 2, FC_RATE_FRAC, 2);
    near_fmt(D(in.imu.gyro_radps.y, RATE), -PI, FC_RATE_FRAC, 2);
    near_fmt(D(in.imu.gyro_radps.z, RATE), 2 * PI, FC_RATE_FRAC, 2);
    near_fmt(D(in.imu.accel_mps2.x, ACCEL), 0.981, FC_ACCEL_FRAC, 2);
    near_fmt(D(in.imu.accel_mps2.y, ACCEL), -1.962, FC_ACCEL_FRAC, 2);
    near_fmt(D(in.imu.accel_mps2.z, ACCEL), 1.05 * 9.81, FC_ACCEL_FRAC, 2);
    near_fmt(D(in.attitude_external.w, UNIT), 0.92387953, FC_UNIT_FRAC, 2);
    near_fmt(D(in.attitude_external.z, UNIT), 0.38268343, FC_UNIT_FRAC, 2);
    near_fmt(D(in.attitude_external.x, UNIT), 0.0, FC_UNIT_FRAC, 1);
    /* position and velocity: both frames z up, copied */
    near_fmt(D(in.position_m.x, LENGTH), 1.5, FC_LENGTH_FRAC, 1);
    near_fmt(D(in.position_m.y, LENGTH), -2.25, FC_LENGTH_FRAC, 1);
    near_fmt(D(in.position_m.z, LENGTH), 0.75, FC_LENGTH_FRAC, 1);
    near_fmt(D(in.velocity_mps.x, VEL), 0.5, FC_VEL_FRAC, 1);
    near_fmt(D(in.velocity_mps.y, VEL), -0.25, FC_VEL_FRAC, 1);
    near_fmt(D(in.velocity_mps.z, VEL), -1.0, FC_VEL_FRAC, 1);
    assert_int_equal(in.command, FC_COMMAND_TRACK_PAD);
}

static void test_inputs_out_of_range(void **state)
{
    (void)state;
    cf_tuning t = CF_TUNING_INITIALIZER;
    (void)cf_tuning_prepare(&t);
    cf_session ss;
    cf_session_reset(&ss);
    cf_sample s = hover_sample();
    s.gyro_dps[0] = 1.0e5f;  /* 1745 rad/s: beyond RATE's 128 rad/s */
    s.gyro_dps[1] = -1.0e5f;
    fc_controller_inputs in;
    cf_inputs_from_sample(&s, &ss, &t, FC_COMMAND_DISARM, &in);
#if FC_NUMERIC_FIXED
    /* saturates, never wraps */
    assert_true(in.imu.gyro_radps.x == FC_REAL_MAX);
    assert_true(in.imu.gyro_radps.y == FC_REAL_MIN);
#else
    near_abs(D(in.imu.gyro_radps.x, RATE), 1.0e5 * PI / 180, 0.01);
    /* a NaN stays a NaN: the controller reports it (FC_STEP_BAD_INPUT) */
    s.pos_m[2] = NAN;
    cf_inputs_from_sample(&s, &ss, &t, FC_COMMAND_DISARM, &in);
    assert_true(isnan(D(in.position_m.z, LENGTH)));
#endif
}

/* The commander's modes as the firmware's controllers read them: an absolute
 * point is remembered (not the point where the command began), a velocity
 * moves it, the supervisor's level-out (x, y disabled, yaw rate 0) follows
 * the vehicle with no horizontal target and keeps the heading. */
static void test_setpoint_modes(void **state)
{
    (void)state;
    cf_tuning t = CF_TUNING_INITIALIZER;
    (void)cf_tuning_prepare(&t);
    cf_session ss;
    cf_session_reset(&ss);
    cf_sample s = hover_sample();
    s.pos_m[0] = 0.4f;
    s.pos_m[1] = -0.3f;
    s.yaw_deg = 90.0f;
    assert_true(cf_session_begin(&ss, FC_COMMAND_TRACK_PAD, &s, &t));
    near_abs(ss.sp_x_m, (double)0.4f, 0.0);
    near_abs(ss.sp_y_m, (double)-0.3f, 0.0);
    near_abs(ss.sp_yaw_rad, PI / 2, 1e-6);
    /* absolute x, y and yaw: used, and remembered */
    s.pos_m[0] = 5.0f;
    s.sp_pos_m[0] = 1.0f;
    s.sp_pos_m[1] = 2.0f;
    s.sp_yaw_deg = -90.0f;
    s.sp_mode_yaw = CF_MODE_ABS;
    cf_setpoint_step(&ss, &s, &t, CF_STEP_DT_S);
    fc_controller_inputs in;
    cf_inputs_from_sample(&s, &ss, &t, FC_COMMAND_TRACK_PAD, &in);
    near_fmt(D(in.position_setpoint_m.x, LENGTH), 1.0, FC_LENGTH_FRAC, 1);
    near_fmt(D(in.position_setpoint_m.y, LENGTH), 2.0, FC_LENGTH_FRAC, 1);
    near_fmt(D(in.yaw_setpoint_rad, ANGLE), -PI / 2, FC_ANGLE_FRAC, 4);
    /* a yaw setpoint beyond +-180 deg is wrapped */
    s.sp_yaw_deg = 270.0f;
    cf_setpoint_step(&ss, &s, &t, CF_STEP_DT_S);
    near_abs(ss.sp_yaw_rad, -PI / 2, 1e-6);
    /* the velocity of the world frame moves the point: 0.5 m/s in x for 0.2 s */
    s.pos_m[0] = 1.0f;
    s.pos_m[1] = 2.0f;
    s.sp_mode_x = s.sp_mode_y = CF_MODE_VELOCITY;
    s.sp_vel_mps[0] = 0.5f;
    s.sp_vel_mps[1] = 0.0f;
    s.sp_mode_yaw = CF_MODE_VELOCITY;
    s.sp_yaw_rate_dps = 45.0f;
    for (int i = 0; i < 100; i++) {
        cf_setpoint_step(&ss, &s, &t, CF_STEP_DT_S);
    }
    near_abs(ss.sp_x_m, 1.1, 1e-5);
    near_abs(ss.sp_y_m, 2.0, 1e-6);
    near_abs(ss.sp_yaw_rad, -PI / 2 + 0.2 * PI / 4, 1e-5);
    /* the hover setpoint's body frame: forward at yaw 90 deg is world +y */
    s.sp_velocity_body = true;
    for (int i = 0; i < 100; i++) {
        cf_setpoint_step(&ss, &s, &t, CF_STEP_DT_S);
    }
    near_abs(ss.sp_x_m, 1.1, 1e-5);
    near_abs(ss.sp_y_m, 2.1, 1e-5);
    /* a held-back vehicle: the point leads it by at most CF_VELOCITY_LEAD_MAX_M */
    for (int i = 0; i < 5000; i++) {
        cf_setpoint_step(&ss, &s, &t, CF_STEP_DT_S);
    }
    near_abs(ss.sp_y_m, 2.0 + (double)CF_VELOCITY_LEAD_MAX_M, 1e-5);
    /* the supervisor's level-out: x, y disabled, yaw at rate 0, z kept */
    s.sp_velocity_body = false;
    s.sp_mode_x = s.sp_mode_y = CF_MODE_DISABLE;
    s.sp_yaw_rate_dps = 0.0f;
    const float yaw_before = ss.sp_yaw_rad;
    s.pos_m[0] = 3.0f;
    s.pos_m[1] = -1.0f;
    s.vel_mps[0] = 0.2f;
    s.vel_mps[1] = 0.0f;
    cf_setpoint_step(&ss, &s, &t, CF_STEP_DT_S);
    near_abs(ss.sp_x_m, 3.0 + 0.2 * (double)t.h_kd / (double)t.h_kp, 1e-5);
    near_abs(ss.sp_y_m, -1.0, 1e-6);
    near_abs(ss.sp_yaw_rad, yaw_before, 0.0);
    /* the library's PD asks for no acceleration there (level) */
    near_abs(t.h_kp * (ss.sp_x_m - s.pos_m[0]) - t.h_kd * s.vel_mps[0], 0.0, 1e-5);
}

/* z from the commander: absolute with the high-level commander's feed-forward,
 * a velocity integrated, a step ramped; the level-out keeps it. */
static void test_commander_height(void **state)
{
    (void)state;
    cf_tuning t = CF_TUNING_INITIALIZER;
    (void)cf_tuning_prepare(&t);
    cf_session ss;
    cf_session_reset(&ss);
    cf_sample s = hover_sample();
    s.pos_m[2] = 0.5f;
    s.sp_pos_m[2] = 0.5f;
    assert_true(cf_session_begin(&ss, FC_COMMAND_TRACK_PAD, &s, &t));
    assert_false(ss.have_cmd_z);
    near_abs(cf_pad_height_m(&ss, &t), 0.0, 0.0); /* padZ until the commander gives a height */
    s.sp_vel_mps[2] = 0.1f;
    s.sp_acc_mps2[2] = 0.2f;
    cf_setpoint_step(&ss, &s, &t, CF_STEP_DT_S);
    assert_true(ss.have_cmd_z);
    fc_vertical_trajectory pad = cf_pad_trajectory(&ss, &t);
    near_abs(D(pad.z_m, LENGTH), 0.5 - (double)t.z_bias, 1e-5);
    near_abs(D(pad.vz_mps, VEL), 0.1, 1e-5);
    near_abs(D(pad.az_mps2, ACCEL), 0.2, 1e-5);
    /* a step of the height: a ramp at CF_COMMAND_Z_SPEED_MAX_MPS */
    s.sp_pos_m[2] = 1.5f;
    s.sp_vel_mps[2] = 0.0f;
    s.sp_acc_mps2[2] = 0.0f;
    for (int i = 0; i < 250; i++) {
        cf_setpoint_step(&ss, &s, &t, CF_STEP_DT_S);
    }
    near_abs(ss.cmd_z_m, 0.5 + 0.5 * (double)CF_COMMAND_Z_SPEED_MAX_MPS, 1e-4);
    near_abs(ss.cmd_vz_mps, CF_COMMAND_Z_SPEED_MAX_MPS, 0.0);
    /* a velocity: MotionCommander's up at 0.2 m/s for 1 s */
    s.pos_m[2] = ss.cmd_z_m;
    s.sp_mode_z = CF_MODE_VELOCITY;
    s.sp_vel_mps[2] = 0.2f;
    const float z0 = ss.cmd_z_m;
    for (int i = 0; i < 500; i++) {
        cf_setpoint_step(&ss, &s, &t, CF_STEP_DT_S);
    }
    near_abs(ss.cmd_z_m, (double)z0 + 0.2, 1e-4);
    near_abs(ss.cmd_vz_mps, 0.2, 1e-6);
    /* disabled: held */
    s.sp_mode_z = CF_MODE_DISABLE;
    const float z1 = ss.cmd_z_m;
    cf_setpoint_step(&ss, &s, &t, CF_STEP_DT_S);
    near_abs(ss.cmd_z_m, z1, 0.0);
    /* command_z off: the virtual pad's padZ as before */
    t.command_z = 0u;
    near_abs(cf_pad_height_m(&ss, &t), t.pad_z, 0.0);
}

static void test_command_gating(void **state)
{
    (void)state;
    cf_sample s = hover_sample();
    assert_int_equal(cf_command(0u, 0u, &s), FC_COMMAND_DISARM);
    assert_int_equal(cf_command(0u, 1u, &s), FC_COMMAND_TRACK_PAD);
    assert_int_equal(cf_command(0u, (uint8_t)FC_COMMAND_COUNT, &s), FC_COMMAND_DISARM);
    assert_int_equal(cf_command(0u, 200u, &s), FC_COMMAND_DISARM);
    /* the supervisor's (and a stopped commander's) null setpoint: motors off */
    cf_sample null_sp;
    memset(&null_sp, 0, sizeof null_sp);
    null_sp.quat_xyzw[3] = 1.0f;
    assert_false(cf_setpoint_live(&null_sp));
    assert_int_equal(cf_command(0u, 1u, &null_sp), FC_COMMAND_DISARM);
    /* a manual (attitude) setpoint with thrust asked for is live */
    null_sp.sp_thrust = 20000.0f;
    assert_true(cf_setpoint_live(&null_sp));
    assert_int_equal(cf_command(0u, 1u, &null_sp), FC_COMMAND_TRACK_PAD);
    /* a velocity-mode z alone is live too */
    null_sp.sp_thrust = 0.0f;
    null_sp.sp_mode_z = 2u;
    assert_true(cf_setpoint_live(&null_sp));
}

static void test_session_edges(void **state)
{
    (void)state;
    cf_session ss;
    cf_session_reset(&ss);
    cf_sample s = hover_sample();
    ss.pad_phase_rad = 1.0f;
    assert_false(cf_session_begin(&ss, FC_COMMAND_DISARM, &s, loaded()));
    assert_true(cf_session_begin(&ss, FC_COMMAND_TRACK_PAD, &s, loaded()));
    near_abs(ss.pad_phase_rad, 0.0, 0.0); /* the pad's time starts with the command */
    assert_false(cf_session_begin(&ss, FC_COMMAND_TRACK_PAD, &s, loaded()));
    assert_false(cf_session_begin(&ss, FC_COMMAND_DISARM, &s, loaded()));
    assert_true(cf_session_begin(&ss, FC_COMMAND_TRACK_PAD, &s, loaded()));
    /* Init resets: the next command is a new one */
    cf_session_reset(&ss);
    assert_true(cf_session_begin(&ss, FC_COMMAND_TRACK_PAD, &s, loaded()));
}

static void test_virtual_pad(void **state)
{
    (void)state;
    cf_tuning t = CF_TUNING_INITIALIZER;
    (void)cf_tuning_prepare(&t);
    t.pad_z = 0.3f;
    t.pad_amp = 0.1f;
    t.pad_freq = 0.5f; /* w = pi rad/s */
    cf_session ss;
    cf_session_reset(&ss);
    fc_vertical_trajectory p = cf_pad_trajectory(&ss, &t);
    near_fmt(D(p.z_m, LENGTH), 0.3, FC_LENGTH_FRAC, 2);
    near_fmt(D(p.vz_mps, VEL), 0.1 * PI, FC_VEL_FRAC, 4);
    near_fmt(D(p.az_mps2, ACCEL), 0.0, FC_ACCEL_FRAC, 4);
    /* a quarter period: 0.5 s of 500 Hz steps */
    for (int i = 0; i < 250; i++) {
        cf_pad_advance(&ss, &t, CF_STEP_DT_S);
    }
    p = cf_pad_trajectory(&ss, &t);
    near_abs(D(p.z_m, LENGTH), 0.4, 1e-5);
    near_abs(D(p.vz_mps, VEL), 0.0, 1e-4);
    near_abs(D(p.az_mps2, ACCEL), -0.1 * PI * PI, 1e-4);
    near_abs(cf_pad_height_m(&ss, &t), 0.4, 1e-5);
    /* many periods later the phase is still wrapped and the pad on its sine */
    for (int i = 0; i < 500 * 3600; i++) {
        cf_pad_advance(&ss, &t, CF_STEP_DT_S);
    }
    assert_true(ss.pad_phase_rad >= -(float)PI && ss.pad_phase_rad <= (float)PI);
    const double z = (double)cf_pad_height_m(&ss, &t);
    assert_true(z >= 0.2 - 1e-6 && z <= 0.4 + 1e-6);
    /* no heave: a still pad */
    t.pad_amp = 0.0f;
    p = cf_pad_trajectory(&ss, &t);
    near_fmt(D(p.z_m, LENGTH), 0.3, FC_LENGTH_FRAC, 2);
    near_abs(D(p.vz_mps, VEL), 0.0, 0.0);
}

/* ---- the landing mission: parameter -> command --------------------------------------------- */

static void test_mission_command(void **state)
{
    (void)state;
    cf_sample s = hover_sample();
    /* mission 0: the track parameter, as before */
    assert_int_equal(cf_command(CF_MISSION_FOLLOW, 0u, &s), FC_COMMAND_DISARM);
    assert_int_equal(cf_command(CF_MISSION_FOLLOW, 1u, &s), FC_COMMAND_TRACK_PAD);
    assert_int_equal(cf_command(CF_MISSION_FOLLOW, 2u, &s), FC_COMMAND_HOLD);
    assert_int_equal(cf_command(CF_MISSION_FOLLOW, 3u, &s), FC_COMMAND_LAND);
    /* land asked for, setpoint live: LAND, whatever track says */
    assert_int_equal(cf_command(CF_MISSION_LAND, 0u, &s), FC_COMMAND_LAND);
    assert_int_equal(cf_command(CF_MISSION_LAND, 1u, &s), FC_COMMAND_LAND);
    /* hold (the abort of a descent): HOLD, whatever track says */
    assert_int_equal(cf_command(CF_MISSION_HOLD, 0u, &s), FC_COMMAND_HOLD);
    assert_int_equal(cf_command(CF_MISSION_HOLD, 1u, &s), FC_COMMAND_HOLD);
    /* an unknown mission: HOLD (no descent, no motors off in flight) */
    assert_int_equal(cf_command(3u, 0u, &s), FC_COMMAND_HOLD);
    assert_int_equal(cf_command(255u, 1u, &s), FC_COMMAND_HOLD);
    /* stopped commander or supervisor: DISARM for every mission */
    cf_sample null_sp;
    memset(&null_sp, 0, sizeof null_sp);
    null_sp.quat_xyzw[3] = 1.0f;
    for (unsigned m = 0u; m < 256u; m++) {
        assert_int_equal(cf_command((uint8_t)m, 1u, &null_sp), FC_COMMAND_DISARM);
    }
    /* a command begins (re-initialisation) only from DISARM: LAND -> HOLD keeps the mission */
    cf_session ss;
    cf_session_reset(&ss);
    assert_true(cf_session_begin(&ss, cf_command(CF_MISSION_LAND, 0u, &s), &s, loaded()));
    assert_false(cf_session_begin(&ss, cf_command(CF_MISSION_HOLD, 0u, &s), &s, loaded()));
    assert_false(cf_session_begin(&ss, cf_command(CF_MISSION_LAND, 0u, &s), &s, loaded()));
    assert_false(cf_session_begin(&ss, cf_command(CF_MISSION_LAND, 0u, &null_sp), &s, loaded()));
    assert_true(cf_session_begin(&ss, cf_command(CF_MISSION_HOLD, 0u, &s), &s, loaded()));
}

/* ---- the range finder ----------------------------------------------------------------------- */

static void test_range_freshness(void **state)
{
    (void)state;
    cf_tuning t = CF_TUNING_INITIALIZER;
    (void)cf_tuning_prepare(&t);
    near_abs(t.range_offset_m, 0.0, 0.0); /* default: the reading as it is */
    cf_session ss;
    cf_session_reset(&ss);
    /* no deck (or no reading yet): 0 all along, never a sample */
    for (int i = 0; i < 10; i++) {
        cf_range_step(&ss, 0.0f, &t);
        assert_false(ss.range_fresh);
    }
    near_abs(ss.range_m, 0.0, 0.0);
    /* a new reading: mm -> m, fresh for one step, then held without being fresh */
    cf_range_step(&ss, 320.0f, &t);
    assert_true(ss.range_fresh);
    near_abs(ss.range_m, 0.32, 1e-7);
    for (int i = 0; i < 11; i++) {
        cf_range_step(&ss, 320.0f, &t);
        assert_false(ss.range_fresh);
        near_abs(ss.range_m, 0.32, 1e-7);
    }
    cf_range_step(&ss, 321.0f, &t);
    assert_true(ss.range_fresh);
    near_abs(ss.range_m, 0.321, 1e-7);
    /* the deck driver's outliers (>= 5000 mm) are no sample; the last one is kept */
    cf_range_step(&ss, 8190.0f, &t);
    assert_false(ss.range_fresh);
    near_abs(ss.range_m, 0.321, 1e-7);
    cf_range_step(&ss, 5000.0f, &t);
    assert_false(ss.range_fresh);
    cf_range_step(&ss, 4999.0f, &t);
    assert_true(ss.range_fresh);
    near_abs(ss.range_m, 4.999, 1e-6);
    /* ... and a reading after an outlier is new even if it equals the one before it */
    cf_range_step(&ss, 321.0f, &t);
    cf_range_step(&ss, 8190.0f, &t);
    cf_range_step(&ss, 321.0f, &t);
    assert_true(ss.range_fresh);
    /* on the pad the ranger may read 0: a change to it is a sample */
    cf_range_step(&ss, 0.0f, &t);
    assert_true(ss.range_fresh);
    near_abs(ss.range_m, 0.0, 0.0);
    /* not numbers: no sample */
    cf_range_step(&ss, NAN, &t);
    assert_false(ss.range_fresh);
    cf_range_step(&ss, -5.0f, &t);
    assert_false(ss.range_fresh);
    near_abs(ss.range_m, 0.0, 0.0);
    /* the offset (CG to sensor) is added; a negative range is 0 */
    t.range_offset_m = 0.015f;
    cf_range_step(&ss, 5.0f, &t);
    assert_true(ss.range_fresh);
    near_abs(ss.range_m, 0.020, 1e-7);
    t.range_offset_m = -0.010f;
    cf_range_step(&ss, 4.0f, &t);
    assert_true(ss.range_fresh);
    near_abs(ss.range_m, 0.0, 0.0);
    t.range_offset_m = NAN;
    cf_range_step(&ss, 6.0f, &t);
    assert_false(ss.range_fresh);
    /* Init starts over: the next reading is new */
    t.range_offset_m = 0.0f;
    cf_range_step(&ss, 300.0f, &t);
    cf_session_reset(&ss);
    assert_false(ss.range_fresh);
    cf_range_step(&ss, 300.0f, &t);
    assert_true(ss.range_fresh);
}

static void test_range_into_inputs(void **state)
{
    (void)state;
    cf_tuning t = CF_TUNING_INITIALIZER;
    (void)cf_tuning_prepare(&t);
    cf_session ss;
    cf_session_reset(&ss);
    cf_sample s = hover_sample();
    s.range_mm = 412.0f;
    fc_controller_inputs in;
    cf_range_step(&ss, s.range_mm, &t);
    cf_inputs_from_sample(&s, &ss, &t, FC_COMMAND_LAND, &in);
    assert_true(in.range_fresh);
    near_fmt(D(in.range_m, LENGTH), 0.412, FC_LENGTH_FRAC, 2);
    assert_int_equal(in.command, FC_COMMAND_LAND);
    cf_range_step(&ss, s.range_mm, &t);
    cf_inputs_from_sample(&s, &ss, &t, FC_COMMAND_LAND, &in);
    assert_false(in.range_fresh);
    near_fmt(D(in.range_m, LENGTH), 0.412, FC_LENGTH_FRAC, 2);
}

/* ---- outputs ---------------------------------------------------------------------------- */

static void test_force_torque(void **state)
{
    (void)state;
    fc_controller_outputs out;
    memset(&out, 0, sizeof out);
    out.motors_on = true;
    out.thrust_n = fc_from_float(0.3f, FC_FORCE_FRAC);
    out.moment_nm = fc_vec3_make(fc_from_float(1.0e-3f, FC_MOMENT_FRAC), fc_from_float(-2.0e-3f, FC_MOMENT_FRAC),
                                 fc_from_float(5.0e-4f, FC_MOMENT_FRAC));
    cf_force_torque ft;
    cf_force_torque_from_outputs(&out, &ft);
    near_fmt(ft.thrust_n, 0.3, FC_FORCE_FRAC, 1);
    near_fmt(ft.torque_nm[0], 1.0e-3, FC_MOMENT_FRAC, 1);
    near_fmt(ft.torque_nm[1], -2.0e-3, FC_MOMENT_FRAC, 1);
    near_fmt(ft.torque_nm[2], 5.0e-4, FC_MOMENT_FRAC, 1);
    /* motors off: nothing, whatever the fields hold */
    out.motors_on = false;
    cf_force_torque_from_outputs(&out, &ft);
    assert_true(ft.thrust_n == 0.0f && ft.torque_nm[0] == 0.0f && ft.torque_nm[1] == 0.0f && ft.torque_nm[2] == 0.0f);
    /* a thrust below zero is none */
    out.motors_on = true;
    out.thrust_n = fc_from_float(-0.1f, FC_FORCE_FRAC);
    cf_force_torque_from_outputs(&out, &ft);
    assert_true(ft.thrust_n == 0.0f);
#if !FC_NUMERIC_FIXED
    out.thrust_n = 0.2f;
    out.moment_nm.y = NAN;
    cf_force_torque_from_outputs(&out, &ft);
    assert_true(ft.thrust_n == 0.0f && ft.torque_nm[0] == 0.0f && ft.torque_nm[1] == 0.0f && ft.torque_nm[2] == 0.0f);
#endif
}

static void test_telemetry(void **state)
{
    (void)state;
    fc_controller_outputs out;
    memset(&out, 0, sizeof out);
    out.motors_on = true;
    out.thrust_n = fc_from_float(0.26f, FC_FORCE_FRAC);
    fc_altitude_control_output *a = &out.telemetry.altitude;
    a->sigma_mps = fc_from_float(-0.5f, FC_VEL_FRAC);
    a->sigma_tilde_mps = fc_from_float(0.125f, FC_VEL_FRAC);
    a->rho_n = fc_from_float(0.3375f, FC_FORCE_FRAC);
    a->theta_kg = fc_from_float(0.031f, FC_MASS_FRAC);
    a->u0_av_n = fc_from_float(-0.02f, FC_FORCE_FRAC);
    a->u_nom_n = fc_from_float(0.28f, FC_FORCE_FRAC);
    a->error_m = fc_from_float(0.05f, FC_LENGTH_FRAC);
    out.telemetry.reference.z_m = fc_from_float(1.2f, FC_LENGTH_FRAC);
    out.telemetry.reference.vz_mps = fc_from_float(-0.4f, FC_VEL_FRAC);
    out.telemetry.allocation_saturation = FC_SAT_YAW_POS;
    cf_telemetry tm;
    memset(&tm, 0, sizeof tm);
    cf_telemetry_from_outputs(&out, FC_STEP_OUTPUT_LIMITED, FC_COMMAND_TRACK_PAD, 0.3f, 0.25f, &tm);
    near_fmt(tm.sigma, -0.5, FC_VEL_FRAC, 1);
    near_fmt(tm.sigma_tilde, 0.125, FC_VEL_FRAC, 1);
    near_fmt(tm.rho, 0.3375, FC_FORCE_FRAC, 1);
    near_fmt(tm.theta, 0.031, FC_MASS_FRAC, 1);
    near_fmt(tm.u0_av, -0.02, FC_FORCE_FRAC, 1);
    near_fmt(tm.u_nom, 0.28, FC_FORCE_FRAC, 1);
    near_fmt(tm.error, 0.05, FC_LENGTH_FRAC, 1);
    near_fmt(tm.z_ref, 1.2, FC_LENGTH_FRAC, 1);
    near_fmt(tm.vz_ref, -0.4, FC_VEL_FRAC, 1);
    near_fmt(tm.thrust, 0.26, FC_FORCE_FRAC, 1);
    near_abs(tm.pad_z, 0.3, 1e-7);
    assert_int_equal(tm.status, FC_STEP_OUTPUT_LIMITED);
    assert_int_equal(tm.command, 1);
    assert_int_equal(tm.saturation, FC_SAT_YAW_POS);
}

static void test_telemetry_landing(void **state)
{
    (void)state;
    fc_controller_outputs out;
    memset(&out, 0, sizeof out);
    fc_controller_telemetry *ct = &out.telemetry;
    ct->landing_state = FC_LANDING_DESCEND;
    ct->landing_reason = FC_REASON_PAD_LEARNT;
    ct->aborts = 2u;
    ct->touchdown_window = true;
    ct->pad.confidence = fc_from_float(0.75f, FC_UNIT_FRAC);
    ct->pad.now.z_m = fc_from_float(0.04f, FC_LENGTH_FRAC);
    ct->pad.now.vz_mps = fc_from_float(-0.06f, FC_VEL_FRAC);
    ct->pad.dominant_period_s = fc_from_float(4.5f, FC_TIME_FRAC);
    ct->gear_height_m = fc_from_float(0.12f, FC_LENGTH_FRAC);
    cf_telemetry tm;
    memset(&tm, 0, sizeof tm);
    cf_telemetry_from_outputs(&out, FC_STEP_OK, FC_COMMAND_LAND, 0.0f, 0.14f, &tm);
    assert_int_equal(tm.command, 3);
    assert_int_equal(tm.landing_state, 3);
    assert_int_equal(tm.landing_reason, FC_REASON_PAD_LEARNT);
    assert_int_equal(tm.aborts, 2);
    assert_int_equal(tm.touchdown_window, 1);
    near_fmt(tm.pad_confidence, 0.75, FC_UNIT_FRAC, 1);
    near_fmt(tm.pad_est_z, 0.04, FC_LENGTH_FRAC, 1);
    near_fmt(tm.pad_est_vz, -0.06, FC_VEL_FRAC, 1);
    near_fmt(tm.pad_period, 4.5, FC_TIME_FRAC, 1);
    near_fmt(tm.gear_height, 0.12, FC_LENGTH_FRAC, 1);
    near_abs(tm.range, 0.14, 1e-7);
    assert_true(tm.thrust == 0.0f); /* motors off */
}

/* ---- tuning ------------------------------------------------------------------------------------ */

static void test_tuning_defaults_are_the_library_defaults(void **state)
{
    (void)state;
    assert_true(cf_airframe_use(NULL));
    for (uint8_t v = 0u; v < (uint8_t)FC_ALT_VARIANT_COUNT; v++) {
        cf_tuning t = CF_TUNING_INITIALIZER;
        t.variant = v;
        assert_true(cf_tuning_prepare(&t));
        assert_false(cf_tuning_prepare(&t)); /* nothing to load twice */
        fc_controller_params want, got;
        memset(&want, 0, sizeof want);
        memset(&got, 0, sizeof got);
        fc_controller_default_params(&want, FC_AIRFRAME_CRAZYFLIE2, (fc_altitude_variant)v, FC_C(0.002f, DT));
        assert_true(cf_params_from_tuning(&t, t.z_init, &got));
        /* untouched values are the library's numbers, bit for bit */
        const fc_altitude_control_params *a = &want.altitude, *b = &got.altitude;
        assert_true(a->law == b->law && a->modulation == b->modulation && a->adaptive == b->adaptive &&
                    a->velocity_measured == b->velocity_measured);
        assert_true(a->l0_per_s == b->l0_per_s);
        assert_true(a->rho_n == b->rho_n);
        assert_true(a->gamma == b->gamma);
        assert_true(a->tau_av_s == b->tau_av_s);
        assert_true(a->a_m_per_s == b->a_m_per_s);
        assert_true(a->kappa_m_per_kg == b->kappa_m_per_kg);
        assert_true(a->k0_ns_per_m == b->k0_ns_per_m);
        assert_true(a->delta_n == b->delta_n);
        assert_true(a->theta0_kg == b->theta0_kg);
        assert_true(want.reference.offset_init_m == got.reference.offset_init_m);
        assert_true(want.reference.bias_m == got.reference.bias_m);
        assert_true(want.horizontal.kp_per_s2 == got.horizontal.kp_per_s2);
        assert_true(want.horizontal.kd_per_s == got.horizontal.kd_per_s);
        assert_true(want.dt_s == got.dt_s && want.mass_kg == got.mass_kg);
        /* the two platform choices */
        assert_true(got.use_external_attitude);
        near_fmt(D(got.reference.tau_s, TIME), CF_DEFAULT_TAU_ZR_S, FC_TIME_FRAC, 1);
        /* and the result initialises */
        static fc_controller ctl;
        assert_int_equal(fc_controller_init(&ctl, &got), FC_INIT_OK);
    }
}

/* The library's fc_controller_default_params_for with the preset's own rotors,
 * mass and inertia gives the preset's parameters, byte for byte. */
static void test_default_params_for_is_the_preset(void **state)
{
    (void)state;
    for (uint8_t v = 0u; v < (uint8_t)FC_ALT_VARIANT_COUNT; v++) {
        static fc_controller_params want, got;
        memset(&want, 0, sizeof want);
        memset(&got, 0, sizeof got);
        fc_controller_default_params(&want, FC_AIRFRAME_CRAZYFLIE2, (fc_altitude_variant)v, FC_C(0.002f, DT));
        fc_allocation_params rotors;
        fc_allocation_preset_crazyflie2(&rotors);
        const fc_vec3 inertia = fc_vec3_make(FC_C(1.66e-5f, INERTIA), FC_C(1.66e-5f, INERTIA), FC_C(2.93e-5f, INERTIA));
        fc_controller_default_params_for(&got, FC_AIRFRAME_CRAZYFLIE2, &rotors, FC_C(0.027f, MASS), inertia,
                                         (fc_altitude_variant)v, FC_C(0.002f, DT));
        assert_memory_equal(&want, &got, sizeof want);
    }
}

static void test_tuning_overrides_and_variants(void **state)
{
    (void)state;
    cf_tuning t = CF_TUNING_INITIALIZER;
    assert_int_equal(t.variant, CF_DEFAULT_VARIANT);
    assert_true(cf_tuning_prepare(&t));
    t.l0 = 3.0f;
    t.rho = 0.5f;
    t.theta0 = 0.031f;
    t.z_bias = 0.3f;
    t.h_kp = 1.5f;
    fc_controller_params p;
    assert_true(cf_params_from_tuning(&t, 0.7f, &p));
    near_fmt(D(p.altitude.l0_per_s, GAIN), 3.0, FC_GAIN_FRAC, 1);
    near_fmt(D(p.altitude.rho_n, FORCE), 0.5, FC_FORCE_FRAC, 1);
    near_fmt(D(p.altitude.theta0_kg, MASS), 0.031, FC_MASS_FRAC, 1);
    near_fmt(D(p.reference.bias_m, LENGTH), 0.3, FC_LENGTH_FRAC, 1);
    near_fmt(D(p.reference.offset_init_m, LENGTH), 0.7, FC_LENGTH_FRAC, 1);
    near_fmt(D(p.horizontal.kp_per_s2, RATIO), 1.5, FC_RATIO_FRAC, 1);
    /* a new variant brings its own law gains; the rest stays as tuned */
    t.variant = (uint8_t)FC_ALT_VARIANT_SSC;
    assert_true(cf_tuning_prepare(&t));
    fc_controller_params d;
    fc_controller_default_params(&d, FC_AIRFRAME_CRAZYFLIE2, FC_ALT_VARIANT_SSC, FC_C(0.002f, DT));
    near_abs(t.l0, D(d.altitude.l0_per_s, GAIN), 0.0);
    near_abs(t.rho, D(d.altitude.rho_n, FORCE), 1e-6);
    near_abs(t.z_bias, 0.3, 1e-7);
    near_abs(t.h_kp, 1.5, 0.0);
    assert_true(cf_params_from_tuning(&t, 0.0f, &p));
    assert_false(p.altitude.adaptive);
    /* a variant out of range falls back to the loaded one */
    t.variant = 99u;
    assert_false(cf_tuning_prepare(&t));
    assert_int_equal(t.variant, FC_ALT_VARIANT_SSC);
    /* a value the library rejects: init says so */
    t.tau_av = -1.0f;
    assert_true(cf_params_from_tuning(&t, 0.0f, &p));
    static fc_controller ctl;
    assert_int_equal(fc_controller_init(&ctl, &p), FC_INIT_BAD_PARAM);
    /* a value that is not a number: refused before the library (fixed has no NaN) */
    t.tau_av = 0.1f;
    t.gamma = NAN;
    assert_false(cf_params_from_tuning(&t, 0.0f, &p));
    t.gamma = 0.0f;
    assert_false(cf_params_from_tuning(&t, INFINITY, &p));
}

static void test_approach_offset(void **state)
{
    (void)state;
    cf_tuning t = CF_TUNING_INITIALIZER;
    (void)cf_tuning_prepare(&t);
    t.z_bias = 0.18f;
    t.z_init = 1.0f;
    assert_int_equal(t.offset_auto, 1);
    near_abs(cf_approach_offset_m(&t, 1.0f, 0.0f), 0.82, 1e-6);
    near_abs(cf_approach_offset_m(&t, 1.0f, 0.5f), 0.32, 1e-6);
    near_abs(cf_approach_offset_m(&t, 0.05f, 0.0f), 0.05 - 0.18, 1e-6); /* below: the reference rises from there */
    near_abs(cf_approach_offset_m(&t, 50.0f, 0.0f), CF_APPROACH_OFFSET_MAX_M, 0.0);
    near_abs(cf_approach_offset_m(&t, -50.0f, 0.0f), -CF_APPROACH_OFFSET_MAX_M, 0.0);
    near_abs(cf_approach_offset_m(&t, NAN, 0.0f), 0.0, 0.0);
    t.offset_auto = 0u;
    near_abs(cf_approach_offset_m(&t, 0.05f, 0.0f), 1.0, 0.0);
}

/* ---- the chain, through the library ------------------------------------------------------------- */

static void test_chain_hover(void **state)
{
    (void)state;
    static fc_controller ctl;
    cf_tuning t = CF_TUNING_INITIALIZER;
    (void)cf_tuning_prepare(&t);
    cf_session ss;
    cf_session_reset(&ss);
    cf_sample s = hover_sample(); /* level, at rest, at the hold point over a pad at 0 */
    const fc_controller_command cmd = cf_command(0u, 1u, &s);
    assert_true(cf_session_begin(&ss, cmd, &s, &t));
    fc_controller_params p;
    assert_true(cf_params_from_tuning(&t, cf_approach_offset_m(&t, s.pos_m[2], cf_pad_height_m(&ss, &t)), &p));
    assert_int_equal(fc_controller_init(&ctl, &p), FC_INIT_OK);
    fc_controller_inputs in;
    fc_controller_outputs out;
    cf_force_torque ft;
    cf_telemetry tm;
    for (int i = 0; i < 50; i++) {
        cf_inputs_from_sample(&s, &ss, &t, cmd, &in);
        const fc_step_status st = fc_controller_step(&ctl, &in, &out);
        assert_true((st & (FC_STEP_NOT_READY | FC_STEP_BAD_INPUT)) == 0u);
        cf_force_torque_from_outputs(&out, &ft);
        cf_telemetry_from_outputs(&out, st, cmd, cf_pad_height_m(&ss, &t), ss.range_m, &tm);
        cf_pad_advance(&ss, &t, CF_STEP_DT_S);
    }
    /* flying: a thrust between the rotors' idle and full (4 x 0.12 N), small moments */
    assert_true(out.motors_on);
    assert_true(ft.thrust_n > 0.0f && ft.thrust_n <= 0.48f + 1e-4f);
    for (int k = 0; k < 3; k++) {
        assert_true(isfinite(ft.torque_nm[k]) && fabsf(ft.torque_nm[k]) < 1e-3f);
    }
    near_abs(tm.z_ref, 0.18, 2e-3); /* no approach offset at the hold point */
    assert_true(tm.theta > 0.0f);
    assert_int_equal(tm.command, FC_COMMAND_TRACK_PAD);
    /* the commander stops: motors off */
    s.sp_mode_x = s.sp_mode_y = s.sp_mode_z = CF_MODE_DISABLE;
    const fc_controller_command off = cf_command(0u, 1u, &s);
    assert_false(cf_session_begin(&ss, off, &s, &t));
    cf_inputs_from_sample(&s, &ss, &t, off, &in);
    (void)fc_controller_step(&ctl, &in, &out);
    cf_force_torque_from_outputs(&out, &ft);
    assert_true(ft.thrust_n == 0.0f);
}

/* The landing mission through the app's chain and the library: fcssc.mission = 2
 * with a live setpoint starts LAND (hold, observe, descend on the range finder's
 * samples of a still pad); writing 1 during the descent makes it HOLD, which the
 * library turns into an abort; the commander stopping disarms. The vehicle's
 * state is held (open loop): what is checked is the app's part. */
static void test_chain_land_then_hold_aborts(void **state)
{
    (void)state;
    static fc_controller ctl;
    cf_tuning t = CF_TUNING_INITIALIZER;
    (void)cf_tuning_prepare(&t);
    cf_session ss;
    cf_session_reset(&ss);
    cf_sample s = hover_sample();
    s.pos_m[2] = 0.32f; /* the hold point: pad 0 + gear 0.02 + hold 0.3 */
    uint8_t mission = CF_MISSION_LAND;
    fc_controller_command cmd = cf_command(mission, 0u, &s);
    assert_int_equal(cmd, FC_COMMAND_LAND);
    assert_true(cf_session_begin(&ss, cmd, &s, &t));
    fc_controller_params p;
    assert_true(cf_params_from_tuning(&t, cf_approach_offset_m(&t, s.pos_m[2], cf_pad_height_m(&ss, &t)), &p));
    assert_int_equal(fc_controller_init(&ctl, &p), FC_INIT_OK);
    fc_controller_inputs in;
    fc_controller_outputs out;
    cf_telemetry tm;
    memset(&tm, 0, sizeof tm);
    bool held = false, observed = false, descending = false, aborted = false;
    int descend_step = -1;
    for (int i = 0; i < 500 * 30 && !aborted; i++) {
        /* the ranger: a new reading every 25 ms (every 12.5 steps), +-1 mm of noise */
        s.range_mm = ((i * 2) / 25) % 2 == 0 ? 320.0f : 321.0f;
        if (descending && descend_step < 0) {
            descend_step = i;
        }
        if (descend_step >= 0 && i == descend_step + 100) {
            mission = CF_MISSION_HOLD; /* the operator aborts, 0.2 s into the descent */
        }
        cmd = cf_command(mission, 0u, &s);
        assert_false(cf_session_begin(&ss, cmd, &s, &t)); /* LAND -> HOLD: no re-initialisation */
        cf_range_step(&ss, s.range_mm, &t);
        cf_inputs_from_sample(&s, &ss, &t, cmd, &in);
        const fc_step_status st = fc_controller_step(&ctl, &in, &out);
        assert_true((st & (FC_STEP_NOT_READY | FC_STEP_BAD_INPUT)) == 0u);
        cf_telemetry_from_outputs(&out, st, cmd, cf_pad_height_m(&ss, &t), ss.range_m, &tm);
        assert_true(out.motors_on);
        held = held || tm.landing_state == FC_LANDING_HOLD;
        observed = observed || tm.landing_state == FC_LANDING_OBSERVE;
        descending = descending || tm.landing_state == FC_LANDING_DESCEND;
        aborted = tm.landing_state == FC_LANDING_ABORT;
    }
    assert_true(held && observed && descending);
    assert_true(aborted);
    assert_int_equal(tm.command, FC_COMMAND_HOLD);
    assert_int_equal(tm.landing_reason, FC_REASON_ABORT_COMMANDED);
    assert_int_equal(tm.aborts, 1);
    /* what the log shows of the pad and the range finder */
    near_abs(tm.range, 0.321, 1e-3);
    near_abs(tm.gear_height, 0.30, 2e-3);
    near_abs(tm.pad_est_z, 0.0, 3e-3);
    near_abs(tm.pad_est_vz, 0.0, 1e-2);
    assert_true(tm.pad_confidence >= 0.6f);
    /* the commander stops: DISARM, motors off, the mission back to idle */
    s.sp_mode_x = s.sp_mode_y = s.sp_mode_z = CF_MODE_DISABLE;
    cmd = cf_command(mission, 0u, &s);
    assert_int_equal(cmd, FC_COMMAND_DISARM);
    assert_false(cf_session_begin(&ss, cmd, &s, &t));
    cf_range_step(&ss, s.range_mm, &t);
    cf_inputs_from_sample(&s, &ss, &t, cmd, &in);
    const fc_step_status st = fc_controller_step(&ctl, &in, &out);
    cf_telemetry_from_outputs(&out, st, cmd, cf_pad_height_m(&ss, &t), ss.range_m, &tm);
    assert_false(out.motors_on);
    assert_int_equal(tm.landing_state, FC_LANDING_IDLE);
}

/* ---- the firmware's flows through the app (cf_app.c) and the library, closed loop ------------ */

/* What cf_glue.c copies out of sensorData_t and state_t for this plant; the
 * setpoint fields are the caller's. */
static void plant_sample(const plant *pl, cf_sample *s)
{
    for (int k = 0; k < 3; k++) {
        s->gyro_dps[k] = (float)(pl->w[k] * 180.0 / PI);
        s->pos_m[k] = (float)pl->p[k];
        s->vel_mps[k] = (float)pl->v[k];
    }
    s->acc_g[0] = s->acc_g[1] = 0.0f;
    s->acc_g[2] = (float)(pl->f_body_z / PLANT_G);
    s->quat_xyzw[0] = (float)pl->q[1];
    s->quat_xyzw[1] = (float)pl->q[2];
    s->quat_xyzw[2] = (float)pl->q[3];
    s->quat_xyzw[3] = (float)pl->q[0];
    s->yaw_deg = (float)(plant_yaw_rad(pl) * 180.0 / PI);
}

/* The setpoints the firmware hands the controller (stabilizer_types.h semantics). */
static void sp_clear(cf_sample *s)
{
    memset(s->sp_pos_m, 0, sizeof s->sp_pos_m);
    memset(s->sp_vel_mps, 0, sizeof s->sp_vel_mps);
    memset(s->sp_acc_mps2, 0, sizeof s->sp_acc_mps2);
    s->sp_velocity_body = false;
    s->sp_yaw_deg = s->sp_yaw_rate_dps = s->sp_thrust = 0.0f;
    s->sp_mode_x = s->sp_mode_y = s->sp_mode_z = s->sp_mode_yaw = CF_MODE_DISABLE;
}

/* The high-level commander's setpoint (crtp_commander_high_level.c): x, y, z
 * and yaw absolute, with velocity and acceleration. */
static void sp_high_level(cf_sample *s, const double p[3], const double v[3], const double a[3], double yaw_deg)
{
    sp_clear(s);
    for (int k = 0; k < 3; k++) {
        s->sp_pos_m[k] = (float)p[k];
        s->sp_vel_mps[k] = (float)v[k];
        s->sp_acc_mps2[k] = (float)a[k];
    }
    s->sp_yaw_deg = (float)yaw_deg;
    s->sp_mode_x = s->sp_mode_y = s->sp_mode_z = s->sp_mode_yaw = CF_MODE_ABS;
}

/* The hover setpoint MotionCommander sends (hoverDecoder): x, y velocity in
 * the body's heading frame, z absolute, yaw rate. */
static void sp_hover(cf_sample *s, double vx, double vy, double yaw_rate_dps, double z)
{
    sp_clear(s);
    s->sp_vel_mps[0] = (float)vx;
    s->sp_vel_mps[1] = (float)vy;
    s->sp_velocity_body = true;
    s->sp_mode_x = s->sp_mode_y = CF_MODE_VELOCITY;
    s->sp_pos_m[2] = (float)z;
    s->sp_mode_z = CF_MODE_ABS;
    s->sp_yaw_rate_dps = (float)yaw_rate_dps;
    s->sp_mode_yaw = CF_MODE_VELOCITY;
}

/* The supervisor's level-out (supervisor.c, supervisorStateWarningLevelOut):
 * x, y disabled, roll and pitch 0, yaw rate 0, z kept. */
static void sp_level_out(cf_sample *s)
{
    s->sp_mode_x = s->sp_mode_y = CF_MODE_DISABLE;
    s->sp_mode_yaw = CF_MODE_VELOCITY;
    s->sp_yaw_rate_dps = 0.0f;
}

typedef struct flow {
    cf_app app;
    cf_tuning tuning;
    cf_app_commands cmd;
    plant pl;
    cf_sample s;
    long tick;
    int zero_thrust_ticks; /* calls whose output had no thrust */
} flow;

static flow *flow_new(double x, double y, double z)
{
    static flow f;
    memset(&f, 0, sizeof f);
    assert_true(cf_airframe_use(&cf2_airframe));
    cf_app_reset(&f.app);
    f.tuning = (cf_tuning)CF_TUNING_INITIALIZER;
    assert_true(cf_app_worker(&f.app, &f.tuning)); /* the app task at boot */
    assert_false(cf_app_worker(&f.app, &f.tuning));
    assert_int_equal(cf_app_spare_result(&f.app), FC_INIT_OK);
    plant_at(&f.pl, x, y, z, 0.0);
    memset(&f.s, 0, sizeof f.s);
    sp_clear(&f.s);
    cf_app_select(&f.app); /* at boot the controller is selected */
    return &f;
}

/* One stabilizer tick: the app's call, then 1 ms of flight. */
static void flow_tick(flow *f)
{
    plant_sample(&f->pl, &f->s);
    (void)cf_app_tick(&f->app, &f->s, &f->tuning, &f->cmd);
    f->cmd.reinit = false;
    if (!(f->app.held.thrust_n > 0.0f)) {
        f->zero_thrust_ticks++;
    }
    plant_step(&f->pl, &f->app.held, 0.001);
    f->tick++;
}

static double horizontal_distance(const plant *pl, double x, double y)
{
    return hypot(pl->p[0] - x, pl->p[1] - y);
}

/* Take-off, go_to and land from the high-level commander, then its stop (a
 * null setpoint): tracking follows the commander's trajectory, the motors
 * stop with the null setpoint. */
static void test_flow_high_level_commander(void **state)
{
    (void)state;
    flow *f = flow_new(0.0, 0.0, 0.0);
    f->cmd.track = 1u; /* fcssc.track = 1, mission 0 */
    const double h = 0.5, pos0[3] = {0, 0, 0};
    double p[3], v[3], a[3];
    /* take-off: 0 -> 0.5 m in 2 s, then hold 2 s */
    for (int i = 0; i < 4000; i++) {
        const double t = i * 1e-3;
        for (int k = 0; k < 3; k++) {
            smooth(pos0[k], k == 2 ? h : pos0[k], 2.0, t, &p[k], &v[k], &a[k]);
        }
        sp_high_level(&f->s, p, v, a, 0.0);
        flow_tick(f);
        if (i > 200) {
            /* it follows the trajectory as it goes (within 10 cm) */
            assert_true(fabs(f->pl.p[2] - p[2]) < 0.1);
        }
    }
    near_abs(f->pl.p[2], h, 0.03);
    assert_true(horizontal_distance(&f->pl, 0, 0) < 0.03);
    /* go_to (0.5, 0.3, 0.5), yaw 0, in 2 s, then 2 s */
    for (int i = 0; i < 4000; i++) {
        const double t = i * 1e-3;
        smooth(0, 0.5, 2.0, t, &p[0], &v[0], &a[0]);
        smooth(0, 0.3, 2.0, t, &p[1], &v[1], &a[1]);
        smooth(h, h, 2.0, t, &p[2], &v[2], &a[2]);
        sp_high_level(&f->s, p, v, a, 0.0);
        flow_tick(f);
    }
    assert_true(horizontal_distance(&f->pl, 0.5, 0.3) < 0.05);
    near_abs(f->pl.p[2], h, 0.03);
    /* land: down to 0 in 2 s, then 1 s */
    for (int i = 0; i < 3000; i++) {
        const double t = i * 1e-3;
        p[0] = 0.5;
        p[1] = 0.3;
        v[0] = v[1] = a[0] = a[1] = 0;
        smooth(h, 0.0, 2.0, t, &p[2], &v[2], &a[2]);
        sp_high_level(&f->s, p, v, a, 0.0);
        flow_tick(f);
    }
    assert_true(f->pl.p[2] < 0.03);
    assert_true(horizontal_distance(&f->pl, 0.5, 0.3) < 0.05);
    /* stop: the high-level commander's null setpoint; motors off at the next step */
    sp_clear(&f->s);
    flow_tick(f);
    flow_tick(f);
    assert_true(f->app.held.thrust_n == 0.0f);
    assert_int_equal(f->app.telemetry.command, FC_COMMAND_DISARM);
}

/* MotionCommander: hover setpoints at 10 Hz, forward 0.3 m/s for 2 s with
 * the nose at 90 deg (world +y), a turn at 45 deg/s, up 0.2 m. */
static void test_flow_motion_commander(void **state)
{
    (void)state;
    flow *f = flow_new(0.0, 0.0, 0.5);
    plant_at(&f->pl, 0.0, 0.0, 0.5, PI / 2);
    f->cmd.track = 1u;
    double z = 0.5;
    for (int i = 0; i < 1000; i++) { /* hover, 1 s */
        if (i % 100 == 0) {
            sp_hover(&f->s, 0, 0, 0, z);
        }
        flow_tick(f);
    }
    assert_int_equal(f->zero_thrust_ticks, 0);
    assert_true(horizontal_distance(&f->pl, 0, 0) < 0.02);
    for (int i = 0; i < 2000; i++) { /* forward 0.3 m/s, 2 s */
        if (i % 100 == 0) {
            sp_hover(&f->s, 0.3, 0, 0, z);
        }
        flow_tick(f);
    }
    for (int i = 0; i < 2000; i++) { /* stop, settle */
        if (i % 100 == 0) {
            sp_hover(&f->s, 0, 0, 0, z);
        }
        flow_tick(f);
    }
    /* 0.6 m along the nose: world +y */
    near_abs(f->pl.p[1], 0.6, 0.05);
    near_abs(f->pl.p[0], 0.0, 0.05);
    /* up 0.2 m at 0.2 m/s (MotionCommander moves the hover height), turning 90 deg */
    for (int i = 0; i < 2000; i++) {
        if (i % 100 == 0) {
            z = i < 1000 ? 0.5 + 0.2 * (i + 100) / 1000.0 : 0.7;
            sp_hover(&f->s, 0, 0, i < 1000 ? 90.0 : 0.0, z);
        }
        flow_tick(f);
    }
    for (int i = 0; i < 2000; i++) {
        if (i % 100 == 0) {
            sp_hover(&f->s, 0, 0, 0, z);
        }
        flow_tick(f);
    }
    near_abs(f->pl.p[2], 0.7, 0.03);
    near_abs(fabs(plant_yaw_rad(&f->pl)), PI, 0.1); /* 90 + 90 deg */
    assert_int_equal(f->zero_thrust_ticks, 0);
}

/* The commander stops (cfclient's setpoints, the last one absolute): 0.5 s of
 * the same setpoint, then the supervisor's level-out, then after 2 s its
 * null setpoint. Tracking stays where the vehicle is (not at the point where
 * the command began), keeps its height, and the motors stop at the cut-off. */
static void test_flow_watchdog_level_out_then_cut(void **state)
{
    (void)state;
    flow *f = flow_new(0.0, 0.0, 0.5);
    f->cmd.track = 1u;
    const double zero[3] = {0, 0, 0};
    double p[3] = {0.0, 0.0, 0.5};
    for (int i = 0; i < 1000; i++) {
        sp_high_level(&f->s, p, zero, zero, 0.0);
        flow_tick(f);
    }
    /* a go_to by position setpoints to (0.6, 0, 0.5), then they stop */
    p[0] = 0.6;
    for (int i = 0; i < 3000; i++) {
        sp_high_level(&f->s, p, zero, zero, 0.0);
        flow_tick(f);
    }
    assert_true(horizontal_distance(&f->pl, 0.6, 0.0) < 0.05);
    for (int i = 0; i < 500; i++) { /* the setpoint ages: the firmware repeats it */
        flow_tick(f);
    }
    sp_level_out(&f->s);
    double x_min = 1e9;
    for (int i = 0; i < 1500; i++) { /* level-out until the 2 s watchdog */
        flow_tick(f);
        x_min = fmin(x_min, f->pl.p[0]);
        assert_true(f->app.held.thrust_n > 0.0f);
    }
    /* it did not fly back toward (0, 0), where the command began */
    assert_true(x_min > 0.5);
    near_abs(f->pl.p[2], 0.5, 0.05);
    /* level: no position target, the drift of a level vehicle (the firmware's PID does the same) */
    assert_true(horizontal_distance(&f->pl, 0.6, 0.0) < 0.3);
    /* the supervisor's null setpoint: motors off */
    sp_clear(&f->s);
    flow_tick(f);
    flow_tick(f);
    assert_true(f->app.held.thrust_n == 0.0f);
}

/* The airframe from the platform's constants: the cf2's and the cf21bl's
 * rotors give the library's thrust range and authority; the cf21bl (39.3 g,
 * 0.2 N a motor, 50 mm arms) takes off, goes to a point and lands. */
static void test_flow_airframe_cf21bl(void **state)
{
    (void)state;
    fc_controller_params p;
    assert_true(cf_airframe_use(&cf2_airframe));
    cf_tuning t = CF_TUNING_INITIALIZER;
    (void)cf_tuning_prepare(&t);
    assert_true(cf_params_from_tuning(&t, 0.0f, &p));
    near_abs(D(p.mass_kg, MASS), 0.029, 1e-4);
    near_abs(D(p.altitude.thrust_max_n, FORCE), 0.48, 1e-3);
    near_abs(D(p.allocation.rotor[0].torque_max_nm, MOMENT), -0.12 * 0.0069928949, 1e-6);
    static fc_controller ctl;
    assert_int_equal(fc_controller_init(&ctl, &p), FC_INIT_OK);
    assert_true(cf_airframe_use(&cf21bl_airframe));
    t = (cf_tuning)CF_TUNING_INITIALIZER;
    (void)cf_tuning_prepare(&t);
    assert_true(cf_params_from_tuning(&t, 0.0f, &p));
    near_abs(D(p.mass_kg, MASS), 0.0393, 1e-4);
    near_abs(D(p.altitude.thrust_max_n, FORCE), 0.8, 1e-3);
    near_abs(D(p.allocation.rotor[3].position_m.x, LENGTH), 0.05 * 0.70710678, 1e-4);
    near_abs(D(p.altitude.theta0_kg, MASS), 0.0393, 2e-3); /* Theta0 follows the mass (k_g at hover) */
    assert_int_equal(fc_controller_init(&ctl, &p), FC_INIT_OK);
    /* implausible constants are refused and the last airframe kept */
    cf_airframe bad = cf21bl_airframe;
    bad.thrust_min_n = bad.thrust_max_n;
    assert_false(cf_airframe_use(&bad));
    /* the cf2 with the thrust upgrade kit (CONFIG_CRAZYFLIE_THRUST_UPGRADE_KIT) */
    const cf_airframe upgrade_kit = {0.0325f, 0.046f, 0.18f, 0.01922636758983749f, 0.0051648627905205285f};
    assert_true(cf_airframe_use(&upgrade_kit));
    t = (cf_tuning)CF_TUNING_INITIALIZER;
    (void)cf_tuning_prepare(&t);
    assert_true(cf_params_from_tuning(&t, 0.0f, &p));
    near_abs(D(p.altitude.thrust_max_n, FORCE), 0.72, 1e-3);
    assert_int_equal(fc_controller_init(&ctl, &p), FC_INIT_OK);
    assert_true(cf_airframe_use(&cf21bl_airframe));
    /* fly it: a cf21bl plant */
    static flow f;
    memset(&f, 0, sizeof f);
    cf_app_reset(&f.app);
    f.tuning = (cf_tuning)CF_TUNING_INITIALIZER;
    assert_true(cf_app_worker(&f.app, &f.tuning));
    assert_int_equal(cf_app_spare_result(&f.app), FC_INIT_OK);
    plant_at(&f.pl, 0.0, 0.0, 0.0, 0.0);
    const double scale = 0.0393 / 0.027 * (0.05 / 0.046) * (0.05 / 0.046);
    f.pl.mass_kg = 0.0393;
    for (int k = 0; k < 3; k++) {
        f.pl.inertia[k] *= scale;
    }
    sp_clear(&f.s);
    cf_app_select(&f.app);
    f.cmd.track = 1u;
    double pos[3], v[3], a[3];
    for (int i = 0; i < 6000; i++) {
        const double tt = i * 1e-3;
        smooth(0.0, 0.3, 2.0, tt - 2.0, &pos[0], &v[0], &a[0]);
        pos[1] = v[1] = a[1] = 0.0;
        smooth(0.0, 0.5, 2.0, tt, &pos[2], &v[2], &a[2]);
        sp_high_level(&f.s, pos, v, a, 0.0);
        flow_tick(&f);
    }
    near_abs(f.pl.p[2], 0.5, 0.03);
    assert_true(horizontal_distance(&f.pl, 0.3, 0.0) < 0.05);
    assert_true(cf_airframe_use(NULL));
}

/* A landing over a pad at (0.3, 0) that began at (0, 0): the commander's
 * setpoints stop during the descent and the supervisor levels out. The
 * horizontal setpoint stays with the vehicle (the old hold point of the
 * command's start would be 0.3 m off: an abort on the horizontal error). */
static void test_flow_land_through_level_out(void **state)
{
    (void)state;
    flow *f = flow_new(0.0, 0.0, 0.32);
    f->cmd.mission = CF_MISSION_LAND;
    const double zero[3] = {0, 0, 0};
    const double pad[3] = {0.3, 0.0, 0.5};
    sp_high_level(&f->s, pad, zero, zero, 0.0);
    int descend_tick = -1;
    bool horizontal_abort = false;
    for (int i = 0; i < 40000 && descend_tick < 0; i++) {
        /* the ranger: CG to the pad at z = 0, a reading every 25 ms, +-1 mm */
        if (i % 25 == 0) {
            f->s.range_mm = (float)(floor(f->pl.p[2] * 1000.0) + (double)((i / 25) % 2));
        }
        flow_tick(f);
        if (f->app.telemetry.landing_state == FC_LANDING_DESCEND) {
            descend_tick = i;
        }
    }
    assert_true(descend_tick > 0);
    assert_true(horizontal_distance(&f->pl, 0.3, 0.0) < 0.05);
    sp_level_out(&f->s);
    for (int i = 0; i < 1500; i++) {
        if (i % 25 == 0) {
            f->s.range_mm = (float)(floor(f->pl.p[2] * 1000.0) + (double)((i / 25) % 2));
        }
        flow_tick(f);
        horizontal_abort = horizontal_abort || f->app.telemetry.landing_reason == FC_REASON_ABORT_HORIZONTAL;
    }
    assert_false(horizontal_abort);
    assert_true(horizontal_distance(&f->pl, 0.3, 0.0) < 0.1);
}

/* Switching to this controller in flight (stabilizer.controller = 6) from a
 * hover another controller flew: no call without thrust, and the height
 * reference starts at the vehicle's height. */
static void test_flow_in_flight_switch(void **state)
{
    (void)state;
    flow *f = flow_new(0.3, -0.2, 0.6);
    f->cmd.track = 1u;
    const double zero[3] = {0, 0, 0};
    const double p[3] = {0.3, -0.2, 0.5};
    /* the other controller's hover: the app is not called; the commander
     * holds (0.3, -0.2, 0.5) while the vehicle is 0.1 m above it */
    sp_high_level(&f->s, p, zero, zero, 0.0);
    cf_app_select(&f->app);
    f->zero_thrust_ticks = 0;
    flow_tick(f);
    const double first_thrust_n = (double)f->app.held.thrust_n;
    /* the first call flies, at about the weight */
    assert_true((double)f->app.held.thrust_n > 0.5 * PLANT_MASS_KG * PLANT_G);
    assert_true((double)f->app.held.thrust_n < 1.5 * PLANT_MASS_KG * PLANT_G);
    near_abs(f->app.telemetry.z_ref, 0.6, 1e-3);
    double z_min = 1e9;
    for (int i = 0; i < 6000; i++) {
        flow_tick(f);
        z_min = fmin(z_min, f->pl.p[2]);
    }
    assert_int_equal(f->zero_thrust_ticks, 0); /* the measured gap: no call without thrust */
    print_message("in-flight switch: calls without thrust %d, first call's thrust %.3f of the weight, "
                  "lowest %.3f m from 0.6 m toward 0.5 m\n",
                  f->zero_thrust_ticks, first_thrust_n / (PLANT_MASS_KG * PLANT_G), z_min);
    assert_true(z_min > 0.48); /* no dip: z_r starts at the vehicle and decays to the commander's height */
    near_abs(f->pl.p[2], 0.5, 0.03);
    /* a parameter written in flight and reinit: a new spare, taken without a gap */
    f->tuning.z_bias = 0.2f;
    assert_true(cf_app_worker(&f->app, &f->tuning));
    f->cmd.reinit = true;
    for (int i = 0; i < 2000; i++) {
        flow_tick(f);
    }
    assert_false(f->app.reinit_pending);
    assert_int_equal(f->zero_thrust_ticks, 0);
    near_abs(f->pl.p[2], 0.5, 0.03);
    /* a selection while the app task makes the next spare (a parameter just
     * changed): the published one flies at once, and the app task writes only
     * the other slot, then publishes it */
    f->tuning.h_kp *= 1.1f;
    const uint8_t published = f->app.published;
    static fc_controller published_spare;
    memcpy(&published_spare, &f->app.spare[published - 1u], sizeof published_spare);
    cf_app_select(&f->app);
    for (int i = 0; i < 100; i++) {
        flow_tick(f);
    }
    assert_int_equal(f->zero_thrust_ticks, 0);
    assert_true(cf_app_worker(&f->app, &f->tuning));
    assert_int_not_equal(f->app.published, published);
    assert_memory_equal(&published_spare, &f->app.spare[published - 1u], sizeof published_spare);
    assert_int_equal(cf_app_spare_result(&f->app), FC_INIT_OK);
    f->cmd.reinit = true; /* the new gains, still without a gap */
    for (int i = 0; i < 1000; i++) {
        flow_tick(f);
    }
    assert_int_equal(f->zero_thrust_ticks, 0);
    near_abs(f->pl.p[2], 0.5, 0.03);
}

/* HOLD -> TRACK -> LAND with the mission parameters, the commander holding
 * the pad's centre: z_r and the horizontal setpoint continuous at each switch. */
static void test_flow_hold_track_land_continuity(void **state)
{
    (void)state;
    flow *f = flow_new(0.0, 0.0, 0.6);
    const double zero[3] = {0, 0, 0};
    const double p[3] = {0.0, 0.0, 0.6};
    f->cmd.mission = CF_MISSION_HOLD;
    sp_high_level(&f->s, p, zero, zero, 0.0);
    for (int i = 0; i < 3000; i++) {
        flow_tick(f);
    }
    assert_int_equal(f->app.telemetry.command, FC_COMMAND_HOLD);
    const uint8_t missions[2] = {CF_MISSION_FOLLOW, CF_MISSION_LAND};
    for (int m = 0; m < 2; m++) {
        /* the switch lands on a step (even tick) */
        if (f->app.tick_phase != 0u) {
            flow_tick(f);
        }
        const float z_ref_before = f->app.telemetry.z_ref;
        const fc_vec3 sp_before = f->app.inputs.position_setpoint_m;
        f->cmd.mission = missions[m];
        f->cmd.track = 1u;
        flow_tick(f);
        const double z = f->pl.p[2];
        near_abs(f->app.telemetry.z_ref, z_ref_before, 0.01);
        assert_true(fabs((double)f->app.telemetry.z_ref - z) < 0.02);
        assert_true(f->app.inputs.position_setpoint_m.x == sp_before.x);
        assert_true(f->app.inputs.position_setpoint_m.y == sp_before.y);
        for (int i = 0; i < 3000; i++) {
            flow_tick(f);
        }
    }
    assert_int_equal(f->app.telemetry.command, FC_COMMAND_LAND);
    assert_int_equal(f->zero_thrust_ticks, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_units),
        cmocka_unit_test(test_quat_component_order),
        cmocka_unit_test(test_legacy_euler_physical),
        cmocka_unit_test(test_legacy_euler_matches_estimator),
        cmocka_unit_test(test_inputs_units_and_frames),
        cmocka_unit_test(test_inputs_out_of_range),
        cmocka_unit_test(test_setpoint_modes),
        cmocka_unit_test(test_commander_height),
        cmocka_unit_test(test_command_gating),
        cmocka_unit_test(test_session_edges),
        cmocka_unit_test(test_virtual_pad),
        cmocka_unit_test(test_force_torque),
        cmocka_unit_test(test_telemetry),
        cmocka_unit_test(test_tuning_defaults_are_the_library_defaults),
        cmocka_unit_test(test_default_params_for_is_the_preset),
        cmocka_unit_test(test_tuning_overrides_and_variants),
        cmocka_unit_test(test_approach_offset),
        cmocka_unit_test(test_chain_hover),
        cmocka_unit_test(test_mission_command),
        cmocka_unit_test(test_range_freshness),
        cmocka_unit_test(test_range_into_inputs),
        cmocka_unit_test(test_telemetry_landing),
        cmocka_unit_test(test_chain_land_then_hold_aborts),
        cmocka_unit_test(test_flow_high_level_commander),
        cmocka_unit_test(test_flow_motion_commander),
        cmocka_unit_test(test_flow_watchdog_level_out_then_cut),
        cmocka_unit_test(test_flow_land_through_level_out),
        cmocka_unit_test(test_flow_airframe_cf21bl),
        cmocka_unit_test(test_flow_in_flight_switch),
        cmocka_unit_test(test_flow_hold_track_land_continuity),
    };
    return cmocka_run_group_tests_name(FC_NUMERIC_FIXED ? "cf.convert (fixed)" : "cf.convert (float)", tests, NULL,
                                       NULL);
}
