/*
 * The safety contract of fc_controller (SPEC "Safety contract", fc/controller.h):
 * the failsafe lands and stops the motors only on the ground, an unknown
 * command keeps the mode, arming waits for what the command needs, the
 * parameters agree across modules, and one glitched sample cannot swing
 * the thrust or the moments to a limit. Both backends.
 */
#include "controller_support.h"

/* Inputs bad for longer than failsafe.bad_input_hold_s: FAILSAFE (level, a
 * descent below hover thrust). Here the IMU says at rest, as on the ground,
 * and there is no range finder: the land detector sees a vehicle that does
 * not move while the loop pushes it down, ramps the thrust down and stops
 * the motors at LANDED; arming again needs a DISARM first. */
static void test_failsafe_lands_on_the_ground(void **state)
{
    (void)state;
    static fc_controller ctl;
    fc_controller_params p;
    init_at_500_hz(&ctl, &p, FC_AIRFRAME_HEXA_4KG, FC_ALT_VARIANT_SSC);
    fc_controller_inputs in = level_at_rest(1.0);
    fc_controller_outputs out;
    align_disarmed(&ctl, in);
    for (int k = 0; k < 500; k++) {
        (void)fc_controller_step(&ctl, &in, &out);
    }
    in.velocity_mps.x = F(1000, VEL); /* beyond the physical range: bad (saturates in fixed) */
    bool entered = false, stopped = false;
    double first_failsafe_thrust_n = 0.0, hover_n = 0.0;
    int entered_at = 0;
    for (int k = 0; k < 3000; k++) { /* 6 s */
        const fc_step_status st = fc_controller_step(&ctl, &in, &out);
        assert_true((st & FC_STEP_BAD_INPUT) != 0u);
        if (k < 240) {
            assert_true(out.motors_on); /* 0.48 s on the last good inputs */
            assert_int_not_equal(out.telemetry.landing_state, FC_LANDING_FAILSAFE);
        }
        if (out.telemetry.landing_state == FC_LANDING_FAILSAFE && !entered) {
            entered = true;
            entered_at = k;
            first_failsafe_thrust_n = D(out.thrust_n, FORCE);
            hover_n = D(out.telemetry.vertical.hover_thrust_n, FORCE);
            assert_int_equal(out.telemetry.landing_reason, FC_REASON_INPUTS_LOST);
            assert_int_equal(out.telemetry.failsafe_cause, FC_FAILSAFE_INPUTS_LOST);
            assert_true(out.telemetry.landing_changed);
            assert_true((st & FC_STEP_DEGRADED) != 0u);
        }
        if (entered && out.motors_on) {
            /* level setpoint */
            assert_true(fabs(D(out.telemetry.attitude_setpoint.x, UNIT)) < 1e-6);
            assert_true(fabs(D(out.telemetry.attitude_setpoint.y, UNIT)) < 1e-6);
        }
        if (entered && !out.motors_on) {
            stopped = true;
            assert_int_equal(out.telemetry.landing_state, FC_LANDING_LANDED);
            assert_int_equal(out.telemetry.landing_reason, FC_REASON_FAILSAFE_LANDED);
            assert_int_equal(out.telemetry.land_state, FC_LAND_LANDED);
            print_message("failsafe: motors off %.2f s after it began\n", (k - entered_at) * 0.002);
            /* the speed setpoint to -0.5 m/s at 1 m/s^2 (0.5 s: from then the
             * loop asks for under 0.9 x hover), contact (0.35 s), the ramp
             * from below 0.9 to 0.3 hover (<= 0.6 s), maybe landed and landed
             * (0.6 s), and 0.1 s of margin */
            assert_true((k - entered_at) * 0.002 <= 0.5 + 0.35 + 0.6 + 0.6 + 0.1);
            break;
        }
    }
    /* the descent's first step from rest: the setpoint one step of 1 m/s^2
     * below 0, e = -0.002 m/s, its rate -1 m/s^2 fed forward:
     * T_h (1 + (k_p e + k_i e dt - 1) / g), the learnt hover thrust (its
     * nominal 39.24 N within its bounds) */
    print_message("failsafe thrust %.2f N (learnt hover %.2f N)\n", first_failsafe_thrust_n, hover_n);
    assert_true(entered && stopped);
    assert_true(hover_n >= 0.5 * 39.24 && hover_n <= 1.5 * 39.24);
    const double first_accel = -(2.0 + 0.002) * 0.002 - 1.0;
    assert_true(fabs(first_failsafe_thrust_n - hover_n * (1.0 + first_accel / 9.81)) < 1e-3 * hover_n);
    /* good inputs and a command that arms: refused until a DISARM */
    in = level_at_rest(1.0);
    assert_true((fc_controller_step(&ctl, &in, &out) & FC_STEP_REFUSED) != 0u);
    assert_false(out.motors_on);
    assert_int_equal(out.telemetry.arming_blocked_by, FC_ARMING_AWAIT_DISARM);
    in.command = FC_COMMAND_DISARM;
    (void)fc_controller_step(&ctl, &in, &out);
    assert_false(out.motors_on);
    in.command = FC_COMMAND_TRACK_PAD;
    (void)fc_controller_step(&ctl, &in, &out);
    assert_true(out.motors_on);
    assert_int_equal(out.telemetry.landing_state, FC_LANDING_IDLE);
}

/* A fresh range sample that puts the gear 3 m up keeps the motors running
 * whatever else the land detector sees (here: an IMU at rest, as if on the
 * ground, and a descent that pushes down). */
static void test_failsafe_never_stops_with_the_gear_up(void **state)
{
    (void)state;
    static fc_controller ctl;
    fc_controller_params p;
    init_at_500_hz(&ctl, &p, FC_AIRFRAME_CRAZYFLIE2, FC_ALT_VARIANT_SSC);
    fc_controller_inputs in = level_at_rest(3.0);
    in.range_m = F(3.0, LENGTH);
    fc_controller_outputs out;
    align_disarmed(&ctl, in);
    for (int k = 0; k < 10000; k++) { /* 20 s: 0.5 s of hold, then the failsafe */
        in.range_fresh = k % 10 == 0;
        if (k == 100) {
            in.position_m.z = F(NAN_OR_LIMIT, LENGTH);
        }
        (void)fc_controller_step(&ctl, &in, &out);
        assert_true(out.motors_on);
    }
    assert_int_equal(out.telemetry.landing_state, FC_LANDING_FAILSAFE);
    assert_int_equal(out.telemetry.land_state, FC_LAND_AIRBORNE);
}

/* An unknown command keeps the mode (here: flying), with its status bit. */
static void test_unknown_command_keeps_the_mode(void **state)
{
    (void)state;
    static fc_controller ctl;
    fc_controller_params p;
    init_at_500_hz(&ctl, &p, FC_AIRFRAME_HEXA_4KG, FC_ALT_VARIANT_SSC);
    fc_controller_inputs in = level_at_rest(1.0);
    fc_controller_outputs out;
    align_disarmed(&ctl, in);
    (void)fc_controller_step(&ctl, &in, &out);
    assert_true(out.motors_on);
    in.command = (fc_controller_command)FC_COMMAND_COUNT;
    const fc_step_status st = fc_controller_step(&ctl, &in, &out);
    assert_true((st & FC_STEP_REFUSED) != 0u);
    assert_true(out.telemetry.command_refused);
    assert_true(out.motors_on);
    in.command = (fc_controller_command)200;
    (void)fc_controller_step(&ctl, &in, &out);
    assert_true(out.motors_on);
    in.command = FC_COMMAND_DISARM;
    (void)fc_controller_step(&ctl, &in, &out);
    assert_false(out.motors_on);
    /* disarmed, an unknown command keeps it disarmed */
    in.command = (fc_controller_command)7;
    (void)fc_controller_step(&ctl, &in, &out);
    assert_false(out.motors_on);
}

/* Arming needs usable inputs for the command: no position, no arming. */
static void test_arming_needs_the_inputs(void **state)
{
    (void)state;
    static fc_controller ctl;
    fc_controller_params p;
    init_at_500_hz(&ctl, &p, FC_AIRFRAME_CRAZYFLIE2, FC_ALT_VARIANT_SSC);
    fc_controller_inputs in = level_at_rest(0.0);
    fc_controller_outputs out;
    align_disarmed(&ctl, in);
    in.position_m.x = F(NAN_OR_LIMIT, LENGTH);
    in.command = FC_COMMAND_LAND;
    for (int k = 0; k < 1000; k++) {
        assert_true((fc_controller_step(&ctl, &in, &out) & FC_STEP_REFUSED) != 0u);
        assert_false(out.motors_on);
        assert_int_equal(out.telemetry.arming_blocked_by, FC_ARMING_INPUTS_BAD);
    }
    in.position_m.x = F(0, LENGTH);
    (void)fc_controller_step(&ctl, &in, &out);
    assert_true(out.motors_on);
}

/* The checks across modules at init, each with its own result. */
static void test_inconsistent_params_rejected(void **state)
{
    (void)state;
    static fc_controller ctl;
    fc_controller_params p;
    fc_controller_default_params(&p, FC_AIRFRAME_HEXA_4KG, FC_ALT_VARIANT_SSC, F(0.002, DT));
    p.gravity_mps2 = F(30.0, ACCEL);
    assert_int_equal(fc_controller_init(&ctl, &p), FC_INIT_GRAVITY_MISMATCH);
    fc_controller_default_params(&p, FC_AIRFRAME_HEXA_4KG, FC_ALT_VARIANT_SSC, F(0.002, DT));
    p.estimator.gravity_mps2 = F(3.0, ACCEL);
    assert_int_equal(fc_controller_init(&ctl, &p), FC_INIT_GRAVITY_MISMATCH);
    fc_controller_default_params(&p, FC_AIRFRAME_CRAZYFLIE2, FC_ALT_VARIANT_SSC, F(0.002, DT));
    p.mass_kg = F(50.0, MASS);
    assert_int_equal(fc_controller_init(&ctl, &p), FC_INIT_MASS_MISMATCH);
    /* a consistent 40 g: the Crazyflie's 0.48 N is under 1.5 x its 0.39 N weight */
    fc_controller_set_mass(&p, F(0.04, MASS));
    assert_int_equal(fc_controller_init(&ctl, &p), FC_INIT_THRUST_TOO_LOW);
    fc_controller_default_params(&p, FC_AIRFRAME_CRAZYFLIE2, FC_ALT_VARIANT_SSC, F(0.002, DT));
    p.altitude.thrust_max_n = F(4.8, FORCE); /* 10 x the rotors' 0.48 N */
    assert_int_equal(fc_controller_init(&ctl, &p), FC_INIT_THRUST_ABOVE_ROTORS);
    fc_controller_default_params(&p, FC_AIRFRAME_CRAZYFLIE2, FC_ALT_VARIANT_SSC, F(0.002, DT));
    p.altitude.thrust_max_n = F(0.3, FORCE); /* under 1.5 x 0.265 N */
    assert_int_equal(fc_controller_init(&ctl, &p), FC_INIT_THRUST_TOO_LOW);
    /* normalised units that are not the allocation's: a thrust or a moment
     * would mean something else to the allocation than to the law that set it */
    fc_controller_default_params(&p, FC_AIRFRAME_F450, FC_ALT_VARIANT_SSC, F(0.002, DT));
    p.altitude.thrust_authority_n = F(20.0, FORCE); /* the rotors give 32 N */
    assert_int_equal(fc_controller_init(&ctl, &p), FC_INIT_AUTHORITY_MISMATCH);
    fc_controller_default_params(&p, FC_AIRFRAME_F450, FC_ALT_VARIANT_SSC, F(0.002, DT));
    p.attitude.authority_nm.z = F(0.1, MOMENT);
    assert_int_equal(fc_controller_init(&ctl, &p), FC_INIT_AUTHORITY_MISMATCH);
}

/* ---- one glitched sample ---------------------------------------------- */

/* Which input a glitch hits, and how. */
typedef enum glitch_target {
    GLITCH_Z, GLITCH_X, GLITCH_VZ, GLITCH_VX, GLITCH_PAD_AZ, GLITCH_PAD_VZ, GLITCH_PAD_Z,
    GLITCH_SETPOINT_X, GLITCH_YAW_SETPOINT, GLITCH_GYRO_X, GLITCH_ACCEL_Z
} glitch_target;

/* value: added to the input (SI units); GATE_JUMP: the largest change the
 * gates let through (fc/input_gate.h), less 1 %, down for z and vz */
#define GATE_JUMP 1e9

static const struct {
    const char *name;
    glitch_target target;
    double value;
} glitches[] = {
    {"z - 100 m", GLITCH_Z, -100.0},
    {"x + 100 m", GLITCH_X, 100.0},
    {"z + the gate's jump", GLITCH_Z, GATE_JUMP},
    {"x + the gate's jump", GLITCH_X, GATE_JUMP},
    {"vz = -100 m/s", GLITCH_VZ, -100.0},
    {"vx = 100 m/s", GLITCH_VX, 100.0},
    {"vz - the gate's jump", GLITCH_VZ, GATE_JUMP},
    {"vx + the gate's jump", GLITCH_VX, GATE_JUMP},
    {"pad az = 400 m/s^2", GLITCH_PAD_AZ, 400.0},
    {"pad vz = 100 m/s", GLITCH_PAD_VZ, 100.0},
    {"pad z = 100 m", GLITCH_PAD_Z, 100.0},
    {"setpoint x = 100 m", GLITCH_SETPOINT_X, 100.0},
    {"yaw setpoint 3 rad", GLITCH_YAW_SETPOINT, 3.0},
    {"gyro x = 30 rad/s", GLITCH_GYRO_X, 30.0},
    {"accel z + 100 m/s^2", GLITCH_ACCEL_Z, 100.0},
};

static void apply_glitch(fc_controller_inputs *in, const fc_controller_params *p, glitch_target target, double value)
{
    const double dt = D(p->dt_s, DT);
    const double position_jump = 0.99 * (D(p->gate.position_jump_m, LENGTH) + D(p->gate.speed_max_mps, VEL) * dt);
    const double speed_jump = 0.99 * (D(p->gate.velocity_jump_mps, VEL) + D(p->gate.accel_max_mps2, ACCEL) * dt);
    const bool gate = value == GATE_JUMP;
    switch (target) {
    case GLITCH_Z:
        in->position_m.z = F(D(in->position_m.z, LENGTH) + (gate ? position_jump : value), LENGTH);
        break;
    case GLITCH_X:
        in->position_m.x = F(D(in->position_m.x, LENGTH) + (gate ? position_jump : value), LENGTH);
        break;
    case GLITCH_VZ:
        in->velocity_mps.z = F(D(in->velocity_mps.z, VEL) + (gate ? -speed_jump : value), VEL);
        break;
    case GLITCH_VX:
        in->velocity_mps.x = F(D(in->velocity_mps.x, VEL) + (gate ? speed_jump : value), VEL);
        break;
    case GLITCH_PAD_AZ:
        in->pad.az_mps2 = F(D(in->pad.az_mps2, ACCEL) + value, ACCEL);
        break;
    case GLITCH_PAD_VZ:
        in->pad.vz_mps = F(D(in->pad.vz_mps, VEL) + value, VEL);
        break;
    case GLITCH_PAD_Z:
        in->pad.z_m = F(D(in->pad.z_m, LENGTH) + value, LENGTH);
        break;
    case GLITCH_SETPOINT_X:
        in->position_setpoint_m.x = F(D(in->position_setpoint_m.x, LENGTH) + value, LENGTH);
        break;
    case GLITCH_YAW_SETPOINT:
        in->yaw_setpoint_rad = F(D(in->yaw_setpoint_rad, ANGLE) + value, ANGLE);
        break;
    case GLITCH_GYRO_X:
        in->imu.gyro_radps.x = F(D(in->imu.gyro_radps.x, RATE) + value, RATE);
        break;
    case GLITCH_ACCEL_Z:
    default:
        in->imu.accel_mps2.z = F(D(in->imu.accel_mps2.z, ACCEL) + value, ACCEL);
        break;
    }
}

/* Two controllers in lockstep over a vehicle held at its reference (no
 * plant: the same inputs for both), one of them fed the glitch at one step:
 * the difference of their outputs at that step is what the glitch did. The
 * bounds are issue 27's: 20 % of the hover thrust, 20 % of the moment
 * authority on each axis (the attitude loop's authority_nm). */
static void check_glitches(fc_airframe airframe, fc_altitude_variant variant, double dt_s, bool external_attitude)
{
    static fc_controller clean, glitched;
    fc_controller_params p;
    fc_controller_default_params(&p, airframe, variant, F(dt_s, DT));
    p.use_external_attitude = external_attitude;
    const double hover_n = D(p.mass_kg, MASS) * 9.81;
    const fc_vec3 authority = p.attitude.authority_nm;
    bool worst = false;
    for (size_t g = 0; g < sizeof glitches / sizeof glitches[0]; g++) {
        assert_int_equal(fc_controller_init(&clean, &p), FC_INIT_OK);
        assert_int_equal(fc_controller_init(&glitched, &p), FC_INIT_OK);
        const fc_controller_inputs at_rest = level_at_rest(0.18); /* the 4.4 reference's end */
        align_disarmed(&clean, at_rest);
        align_disarmed(&glitched, at_rest);
        fc_controller_outputs a, b;
        const int glitch_step = (int)(3.0 / dt_s);
        for (int k = 0; k <= glitch_step; k++) {
            fc_controller_inputs in = at_rest;
            (void)fc_controller_step(&clean, &in, &a);
            if (k == glitch_step) {
                apply_glitch(&in, &p, glitches[g].target, glitches[g].value);
            }
            (void)fc_controller_step(&glitched, &in, &b);
        }
        assert_true(a.motors_on && b.motors_on);
        const double thrust_change = fabs(D(b.thrust_n, FORCE) - D(a.thrust_n, FORCE)) / hover_n;
        const double roll = fabs(D(b.moment_nm.x, MOMENT) - D(a.moment_nm.x, MOMENT)) / D(authority.x, MOMENT);
        const double pitch = fabs(D(b.moment_nm.y, MOMENT) - D(a.moment_nm.y, MOMENT)) / D(authority.y, MOMENT);
        const double yaw = fabs(D(b.moment_nm.z, MOMENT) - D(a.moment_nm.z, MOMENT)) / D(authority.z, MOMENT);
        if (thrust_change > 0.2 || roll > 0.2 || pitch > 0.2 || yaw > 0.2) {
            print_message("airframe %d variant %d, %s: thrust %.3f, moments %.3f %.3f %.3f of their bounds\n",
                          (int)airframe, (int)variant, glitches[g].name, thrust_change, roll, pitch, yaw);
        }
        worst = worst || thrust_change > 0.2 || roll > 0.2 || pitch > 0.2 || yaw > 0.2;
    }
    assert_false(worst);
}

static void test_one_glitch_moves_little(void **state)
{
    (void)state;
    check_glitches(FC_AIRFRAME_CRAZYFLIE2, FC_ALT_VARIANT_SSC, 0.002, true);
    check_glitches(FC_AIRFRAME_F450, FC_ALT_VARIANT_SSC, 0.004, false);
    check_glitches(FC_AIRFRAME_HEXA_4KG, FC_ALT_VARIANT_SSC, 0.01, true);
    check_glitches(FC_AIRFRAME_HEXA_4KG, FC_ALT_VARIANT_SSC_ADAPTIVE, 0.002, false);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_failsafe_lands_on_the_ground),
        cmocka_unit_test(test_failsafe_never_stops_with_the_gear_up),
        cmocka_unit_test(test_unknown_command_keeps_the_mode),
        cmocka_unit_test(test_arming_needs_the_inputs),
        cmocka_unit_test(test_inconsistent_params_rejected),
        cmocka_unit_test(test_one_glitch_moves_little),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
