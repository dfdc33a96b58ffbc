/*
 * Tests of the processor-in-the-loop wire (tools/pil/pil_wire.h),
 * both backends: each listing fills exactly its mailbox, and a controller
 * built from the parameters that crossed the wire and stepped on inputs that
 * crossed it gives, word for word, the outputs of the controller it came from.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "fc/controller.h"
#include "pil_wire.h"

#define F(x, KIND) fc_from_float((float)(x), FC_##KIND##_FRAC)

static void test_listings_fill_their_mailboxes_exactly(void **state)
{
    (void)state;
    uint32_t words[PIL_OUTPUT_WORDS + 1u];
    uint32_t airframe = (uint32_t)FC_AIRFRAME_CRAZYFLIE2, variant = (uint32_t)FC_ALT_VARIANT_SSC;
    fc_controller_params p;
    fc_controller_default_params(&p, FC_AIRFRAME_CRAZYFLIE2, FC_ALT_VARIANT_SSC, F(0.002, DT));
    fc_controller_inputs in;
    memset(&in, 0, sizeof in);
    fc_controller_outputs out;
    memset(&out, 0, sizeof out);
    pil_internals internals;
    memset(&internals, 0, sizeof internals);
    uint32_t status = 0u;
    const unsigned sizes[3] = {PIL_PARAM_WORDS, PIL_INPUT_WORDS, PIL_OUTPUT_WORDS};
    for (unsigned message = 0u; message < 3u; message++) {
        for (int delta = -1; delta <= 1; delta++) {
            pil_wire w = {words, (unsigned)((int)sizes[message] + delta), 0u, true};
            bool ok = false;
            if (message == 0u) {
                ok = pil_wire_params(&w, &airframe, &variant, &p);
            } else if (message == 1u) {
                ok = pil_wire_inputs(&w, &in);
            } else {
                ok = pil_wire_outputs(&w, &status, &out, &internals);
            }
            assert_int_equal(ok, delta == 0);
            assert_int_equal(w.at, sizes[message]);
        }
    }
}

/* A vehicle off its setpoint, tilted and turning, the range finder on. */
static fc_controller_inputs inputs_at(unsigned k)
{
    fc_controller_inputs in;
    memset(&in, 0, sizeof in);
    const double t = 0.002 * k;
    in.imu.gyro_radps = fc_vec3_make(F(0.3, RATE), F(-0.2, RATE), F(0.1, RATE));
    in.imu.accel_mps2 = fc_vec3_make(F(0.4, ACCEL), F(-0.3, ACCEL), F(9.7, ACCEL));
    in.attitude_external = fc_quat_identity();
    in.heading_rad = F(0.3 - 0.2 * t, ANGLE);
    in.heading_fresh = k % 5u == 2u;
    in.position_m = fc_vec3_make(F(0.05, LENGTH), F(-0.04, LENGTH), F(0.4 - 0.1 * t, LENGTH));
    in.velocity_mps = fc_vec3_make(F(0.1, VEL), F(0.05, VEL), F(-0.1, VEL));
    in.range_m = F(0.38 - 0.1 * t, LENGTH);
    in.range_fresh = k % 10u == 0u;
    in.position_setpoint_m = fc_vec3_zero();
    in.yaw_setpoint_rad = F(0.2, ANGLE);
    in.command = FC_COMMAND_LAND;
    return in;
}

static void test_a_controller_from_the_wire_steps_like_its_source(void **state)
{
    (void)state;
    /* the host's parameters, with overrides as fc-sil makes them */
    fc_controller_params host_params;
    fc_controller_default_params(&host_params, FC_AIRFRAME_CRAZYFLIE2, FC_ALT_VARIANT_SSC_ADAPTIVE, F(0.002, DT));
    fc_controller_set_mass(&host_params, F(0.03, MASS));
    host_params.reference.tau_s = F(2.0, TIME);
    host_params.altitude.rho_n = F(0.4, FORCE);
    host_params.altitude.delta_n = F(0.01, FORCE);
    host_params.landing.hold_height_m = F(0.25, LENGTH);
    uint32_t param_words[PIL_PARAM_WORDS];
    uint32_t airframe = (uint32_t)FC_AIRFRAME_CRAZYFLIE2, variant = (uint32_t)FC_ALT_VARIANT_SSC_ADAPTIVE;
    pil_wire w = {param_words, PIL_PARAM_WORDS, 0u, true};
    assert_true(pil_wire_params(&w, &airframe, &variant, &host_params));

    /* the target's: its own defaults, then the wire */
    fc_controller_params target_params;
    uint32_t target_airframe = 0u, target_variant = 0u;
    w = (pil_wire){param_words, PIL_PARAM_WORDS, 0u, false};
    assert_true(pil_wire_params(&w, &target_airframe, &target_variant, &target_params));
    assert_int_equal(target_airframe, airframe);
    assert_int_equal(target_variant, variant);

    static fc_controller host, target;
    assert_int_equal(fc_controller_init(&host, &host_params), FC_INIT_OK);
    assert_int_equal(fc_controller_init(&target, &target_params), FC_INIT_OK);
    for (unsigned k = 0u; k < 400u; k++) {
        const fc_controller_inputs host_in = inputs_at(k);
        uint32_t in_words[PIL_INPUT_WORDS];
        w = (pil_wire){in_words, PIL_INPUT_WORDS, 0u, true};
        fc_controller_inputs sent = host_in;
        assert_true(pil_wire_inputs(&w, &sent));
        fc_controller_inputs target_in;
        memset(&target_in, 0, sizeof target_in);
        w = (pil_wire){in_words, PIL_INPUT_WORDS, 0u, false};
        assert_true(pil_wire_inputs(&w, &target_in));

        fc_controller_outputs host_out, target_out;
        uint32_t host_status = fc_controller_step(&host, &host_in, &host_out);
        uint32_t target_status = fc_controller_step(&target, &target_in, &target_out);
        pil_internals host_internals = pil_internals_of(&host), target_internals = pil_internals_of(&target);
        uint32_t host_words[PIL_OUTPUT_WORDS], target_words[PIL_OUTPUT_WORDS];
        w = (pil_wire){host_words, PIL_OUTPUT_WORDS, 0u, true};
        assert_true(pil_wire_outputs(&w, &host_status, &host_out, &host_internals));
        w = (pil_wire){target_words, PIL_OUTPUT_WORDS, 0u, true};
        assert_true(pil_wire_outputs(&w, &target_status, &target_out, &target_internals));
        assert_memory_equal(host_words, target_words, sizeof host_words);

        /* and the words read back are the outputs */
        fc_controller_outputs read;
        memset(&read, 0, sizeof read);
        pil_internals read_internals;
        uint32_t read_status = 0u;
        w = (pil_wire){host_words, PIL_OUTPUT_WORDS, 0u, false};
        assert_true(pil_wire_outputs(&w, &read_status, &read, &read_internals));
        assert_int_equal(read_status, host_status);
        assert_memory_equal(read.rotor_speed, host_out.rotor_speed, sizeof read.rotor_speed);
        assert_true(read.thrust_n == host_out.thrust_n);
        assert_true(read.telemetry.altitude.theta_kg == host_out.telemetry.altitude.theta_kg);
        assert_true(read.telemetry.pad.now.z_m == host_out.telemetry.pad.now.z_m);
        assert_int_equal(read.telemetry.landing_state, host_out.telemetry.landing_state);
        assert_int_equal(read.motors_on, host_out.motors_on);
    }
    /* the run went somewhere: armed, the mission under way */
    assert_true(host.landing.state != FC_LANDING_IDLE);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_listings_fill_their_mailboxes_exactly),
        cmocka_unit_test(test_a_controller_from_the_wire_steps_like_its_source),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
