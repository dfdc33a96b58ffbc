/*
 * Tests of the velocity output (fc/controller.h FC_OUTPUT_VELOCITY), both
 * backends: the controller flies a vehicle that takes velocity commands and
 * follows them as v' = -a_P v + k_P u per axis (2.18)-(2.23), simulated here
 * in double precision with its landing gear on a still pad at z = 0.
 */
#include "controller_support.h"

#define DT_S 0.01
#define GEAR_M 0.45
#define G_MPS2 9.81

static const double k_p[3] = {1.67, 1.67, 2.5};
static const double a_p[3] = {1.67, 1.67, 2.5};

/* The M600-class parameters of m600-deck: the hexa's mission at 100 Hz, 10 kg,
 * the platform's attitude, the velocity output with the response above. */
static void velocity_params(fc_controller_params *p)
{
    fc_controller_default_params(p, FC_AIRFRAME_HEXA_4KG, FC_ALT_VARIANT_SSC, F(DT_S, DT));
    p->use_external_attitude = true;
    fc_controller_set_mass(p, F(10.0, MASS));
    p->landing.gear_height_m = F(GEAR_M, LENGTH);
    p->landing.touchdown_dip_m = F(0.1, LENGTH);
    fc_velocity_output_params v;
    fc_controller_velocity_defaults(&v, fc_vec3_make(F(k_p[0], RATIO), F(k_p[1], RATIO), F(k_p[2], RATIO)),
                                    fc_vec3_make(F(a_p[0], RATIO), F(a_p[1], RATIO), F(a_p[2], RATIO)));
    fc_controller_set_velocity_output(p, &v);
}

typedef struct vehicle {
    double p[3], v[3], a_z;
    bool motors_on;
} vehicle;

/* The controller's inputs from the vehicle: level, range to the pad every step. */
static fc_controller_inputs inputs_of(const vehicle *veh, fc_controller_command command)
{
    fc_controller_inputs in = level_at_rest(veh->p[2]);
    in.imu.accel_mps2 = fc_vec3_make(F(0, ACCEL), F(0, ACCEL), F(G_MPS2 + veh->a_z, ACCEL));
    in.position_m = fc_vec3_make(F(veh->p[0], LENGTH), F(veh->p[1], LENGTH), F(veh->p[2], LENGTH));
    in.velocity_mps = fc_vec3_make(F(veh->v[0], VEL), F(veh->v[1], VEL), F(veh->v[2], VEL));
    in.range_m = F(veh->p[2], LENGTH);
    in.range_fresh = true;
    in.command = command;
    return in;
}

/* One step of the vehicle under the command (Euler, 10 substeps); the gear
 * stops it on the pad, and with the motors off it rests there. */
static void vehicle_step(vehicle *veh, const fc_controller_outputs *out)
{
    double u[3] = {D(out->velocity_cmd_mps.x, VEL), D(out->velocity_cmd_mps.y, VEL), D(out->velocity_cmd_mps.z, VEL)};
    veh->motors_on = out->motors_on;
    const double h = DT_S / 10.0;
    for (int s = 0; s < 10; s++) {
        for (int i = 0; i < 3; i++) {
            double a = veh->motors_on ? -a_p[i] * veh->v[i] + k_p[i] * u[i] : (i == 2 ? -G_MPS2 : 0.0);
            if (i == 2) {
                veh->a_z = a;
            }
            veh->v[i] += h * a;
            veh->p[i] += h * veh->v[i];
        }
        if (veh->p[2] <= GEAR_M) {
            /* on the pad: it holds the vehicle, the feet's friction stops it */
            veh->p[2] = GEAR_M;
            veh->v[0] = veh->v[1] = 0.0;
            veh->v[2] = veh->v[2] > 0.0 ? veh->v[2] : 0.0;
            veh->a_z = 0.0;
        }
    }
}

static void arm(fc_controller *ctl, const vehicle *veh)
{
    align_disarmed(ctl, inputs_of(veh, FC_COMMAND_DISARM));
}

static void test_params_validated(void **state)
{
    (void)state;
    static fc_controller ctl;
    fc_controller_params p;
    velocity_params(&p);
    assert_int_equal(fc_controller_init(&ctl, &p), FC_INIT_OK);
    /* the same vehicle with the rotor output: the hexa's rotors cannot carry 10 kg */
    p.output = FC_OUTPUT_ROTORS;
    assert_int_equal(fc_controller_init(&ctl, &p), FC_INIT_THRUST_TOO_LOW);
    velocity_params(&p);
    p.velocity.tracking.k_p_per_s.z = F(0, RATIO);
    assert_int_equal(fc_controller_init(&ctl, &p), FC_INIT_BAD_PARAM);
    velocity_params(&p);
    p.velocity.yaw_rate_max_radps = F(0, RATE);
    assert_int_equal(fc_controller_init(&ctl, &p), FC_INIT_BAD_PARAM);
    velocity_params(&p);
    p.velocity.yaw_gain_per_s = F(-1, RATIO);
    assert_int_equal(fc_controller_init(&ctl, &p), FC_INIT_BAD_PARAM);
    velocity_params(&p);
    p.output = FC_OUTPUT_KIND_COUNT;
    assert_int_equal(fc_controller_init(&ctl, &p), FC_INIT_BAD_PARAM);
    fc_controller_inputs in = level_at_rest(1.0);
    fc_controller_outputs out;
    assert_int_equal(fc_controller_step(&ctl, &in, &out), FC_STEP_NOT_READY);
    assert_false(out.motors_on);
    assert_true(out.velocity_cmd_mps.z == FC_INT(0, VEL));
}

/* The landing mission through the velocity output: hold, learn, descend on
 * the reference (tracked within centimetres by (2.24)), touch down slowly,
 * motors off on the pad. The rotor outputs stay 0. */
static void test_landing_tracks_the_descent(void **state)
{
    (void)state;
    static fc_controller ctl;
    fc_controller_params p;
    velocity_params(&p);
    assert_int_equal(fc_controller_init(&ctl, &p), FC_INIT_OK);
    vehicle veh = {{0.3, -0.2, GEAR_M + 1.5}, {0.0, 0.0, 0.0}, 0.0, true};
    arm(&ctl, &veh);
    fc_controller_outputs out;
    bool landed = false;
    int descent_k = -1;
    double start_speed = 0.0, early_error = 0.0, late_error = 0.0, touchdown_speed = -1.0, fastest_descent = 0.0;
    for (int k = 0; k < 6000 && !landed; k++) {
        const fc_controller_inputs in = inputs_of(&veh, FC_COMMAND_LAND);
        const double vz_before = veh.v[2];
        (void)fc_controller_step(&ctl, &in, &out);
        assert_int_equal(out.output, FC_OUTPUT_VELOCITY);
        assert_int_equal(out.rotor_count, 0);
        for (int i = 0; i < FC_MAX_ROTORS; i++) {
            assert_true(out.rotor_speed[i] == FC_INT(0, UNIT));
        }
        assert_true(fabs(D(out.velocity_cmd_mps.z, VEL)) <= 1.5 + 1e-5);
        const fc_landing_state s = out.telemetry.landing_state;
        if (s == FC_LANDING_DESCEND && veh.p[2] > GEAR_M + 0.05) {
            descent_k = descent_k < 0 ? k : descent_k;
            if (k < descent_k + 20) { /* the reference's speed at its start */
                start_speed = fmin(start_speed, D(out.telemetry.reference.vz_mps, VEL));
            }
            const double e = fabs(veh.p[2] - D(out.telemetry.reference.z_m, LENGTH));
            if (k < descent_k + 300) {
                early_error = fmax(early_error, e);
            } else {
                late_error = fmax(late_error, e);
            }
            fastest_descent = fmin(fastest_descent, veh.v[2]);
        }
        assert_true(s != FC_LANDING_ABORT && s != FC_LANDING_FAILSAFE);
        const bool was_airborne = veh.p[2] > GEAR_M;
        vehicle_step(&veh, &out);
        if (was_airborne && veh.p[2] <= GEAR_M && touchdown_speed < 0.0) {
            touchdown_speed = -vz_before;
        }
        if (s == FC_LANDING_LANDED) {
            landed = true;
            assert_false(out.motors_on);
            assert_true(out.velocity_cmd_mps.z == FC_INT(0, VEL));
            assert_true(veh.p[2] <= GEAR_M + 1e-9); /* on the pad, not in the air */
        }
    }
    /* (3.6) starts with a step of its speed, r'(0): with e(0) = 0 and e'(0) =
     * r'(0), (2.14) at zeta = 1 gives e = r'(0) t e^(-w_n t), its peak
     * r'(0) / (w_n e) at t = 1 / w_n, under 1 cm from 3 s on (w_n = 2 rad/s) */
    const double w_n = D(p.velocity.tracking.omega_n_radps.z, RATE);
    const double peak = fabs(start_speed) / (w_n * exp(1.0));
    print_message("descent: r'(0) %.3f m/s, |z - z_r| peak %.4f m (2.14: %.4f), from 3 s on %.4f m; "
                  "fastest %.3f m/s, touchdown %.3f m/s\n",
                  start_speed, early_error, peak, late_error, fastest_descent, touchdown_speed);
    assert_true(descent_k >= 0);
    assert_true(landed);
    assert_true(start_speed < -0.3);
    assert_true(early_error < 1.1 * peak + 0.005 && early_error > 0.8 * peak);
    assert_true(late_error < 0.01);
    assert_true(fastest_descent < -0.2);         /* it did descend */
    assert_true(touchdown_speed >= 0.0 && touchdown_speed < 0.15);
    assert_true(fabs(veh.p[0]) < 0.05 && fabs(veh.p[1]) < 0.05); /* over the pad's centre */
}

/* Bad inputs: the command stays finite and bounded, the step says so; held
 * for failsafe.bad_input_hold_s they put the vehicle into the failsafe, which
 * comes down level at failsafe.descent_mps and stops the motors only on the pad. */
static void test_bad_inputs_and_failsafe_descend(void **state)
{
    (void)state;
    static fc_controller ctl;
    fc_controller_params p;
    velocity_params(&p);
    assert_int_equal(fc_controller_init(&ctl, &p), FC_INIT_OK);
    vehicle veh = {{0.0, 0.0, GEAR_M + 3.0}, {0.0, 0.0, 0.0}, 0.0, true};
    arm(&ctl, &veh);
    fc_controller_outputs out;
    for (int k = 0; k < 300; k++) { /* 3 s of the mission's hold */
        const fc_controller_inputs in = inputs_of(&veh, FC_COMMAND_LAND);
        (void)fc_controller_step(&ctl, &in, &out);
        vehicle_step(&veh, &out);
    }
    const double descent = D(p.failsafe.descent_mps, VEL);
    bool entered = false, landed = false;
    double slowest = 0.0, fastest = 0.0;
    int descent_samples = 0, entered_at = -1;
    for (int k = 0; k < 3000 && !landed; k++) {
        fc_controller_inputs in = inputs_of(&veh, FC_COMMAND_LAND);
        in.position_m = fc_vec3_make(F(NAN_OR_LIMIT, LENGTH), F(NAN_OR_LIMIT, LENGTH), F(NAN_OR_LIMIT, LENGTH));
        in.velocity_mps = fc_vec3_make(F(NAN_OR_LIMIT, VEL), F(NAN_OR_LIMIT, VEL), F(NAN_OR_LIMIT, VEL));
        const fc_step_status status = fc_controller_step(&ctl, &in, &out);
        assert_true((status & FC_STEP_BAD_INPUT) != 0u);
        const double u[3] = {D(out.velocity_cmd_mps.x, VEL), D(out.velocity_cmd_mps.y, VEL),
                             D(out.velocity_cmd_mps.z, VEL)};
        for (int i = 0; i < 3; i++) {
            assert_true(isfinite(u[i]) && fabs(u[i]) <= 3.0 + 1e-5);
        }
        if (out.telemetry.landing_state == FC_LANDING_FAILSAFE) {
            entered = true;
            entered_at = entered_at < 0 ? k : entered_at;
            assert_true((status & FC_STEP_DEGRADED) != 0u);
            /* level and still horizontally */
            assert_true(out.velocity_cmd_mps.x == FC_INT(0, VEL) && out.velocity_cmd_mps.y == FC_INT(0, VEL));
            assert_true(out.yaw_rate_cmd_radps == FC_INT(0, RATE));
            if (veh.p[2] > GEAR_M + 0.3 && k > entered_at + 100) { /* from 1 s after it began */
                slowest = descent_samples == 0 ? veh.v[2] : fmax(slowest, veh.v[2]);
                fastest = fmin(fastest, veh.v[2]);
                descent_samples++;
            }
        }
        if (out.motors_on) {
            assert_int_equal(out.output, FC_OUTPUT_VELOCITY);
        } else {
            assert_true(entered);
            assert_true(veh.p[2] <= GEAR_M + 0.05); /* never a stop in the air */
            landed = true;
        }
        vehicle_step(&veh, &out);
    }
    print_message("failsafe descent: %d samples, between %.3f and %.3f m/s (setpoint %.3f)\n", descent_samples,
                  slowest, fastest, -descent);
    assert_true(entered);
    assert_true(landed);
    assert_true(descent_samples > 100);
    /* the rate held within 25 %, never a drop */
    assert_true(slowest < -0.75 * descent && fastest > -1.25 * descent);
}

/* The rotor output is what it was: no velocity command. */
static void test_rotor_output_unchanged(void **state)
{
    (void)state;
    static fc_controller ctl;
    fc_controller_params p;
    init_at_500_hz(&ctl, &p, FC_AIRFRAME_HEXA_4KG, FC_ALT_VARIANT_SSC);
    fc_controller_inputs in = level_at_rest(1.0);
    align_disarmed(&ctl, in);
    fc_controller_outputs out;
    (void)fc_controller_step(&ctl, &in, &out);
    assert_true(out.motors_on);
    assert_int_equal(out.output, FC_OUTPUT_ROTORS);
    assert_int_equal(out.rotor_count, 6);
    assert_true(out.velocity_cmd_mps.x == FC_INT(0, VEL) && out.velocity_cmd_mps.z == FC_INT(0, VEL));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_params_validated),
        cmocka_unit_test(test_landing_tracks_the_descent),
        cmocka_unit_test(test_bad_inputs_and_failsafe_descend),
        cmocka_unit_test(test_rotor_output_unchanged),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
