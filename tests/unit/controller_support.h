/*
 * controller_support.h - what the tests of fc_controller share (header only):
 * inputs of a vehicle at rest, alignment before arming, the defaults at 500 Hz.
 */
#ifndef FC_CONTROLLER_SUPPORT_H
#define FC_CONTROLLER_SUPPORT_H

#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <math.h>
#include <string.h>
#include <cmocka.h>

#include "fc/controller.h"

#define F(x, KIND) fc_from_float((float)(x), FC_##KIND##_FRAC)
#define D(x, KIND) ((double)fc_to_float((x), FC_##KIND##_FRAC))
/* a bad value: NaN in float, beyond the input range in fixed */
#if FC_NUMERIC_FIXED
#define NAN_OR_LIMIT 3000.0
#else
#define NAN_OR_LIMIT NAN
#endif

static inline fc_controller_inputs level_at_rest(double z_m)
{
    fc_controller_inputs in;
    memset(&in, 0, sizeof in);
    in.imu.gyro_radps = fc_vec3_zero();
    in.imu.accel_mps2 = fc_vec3_make(F(0, ACCEL), F(0, ACCEL), F(9.81, ACCEL));
    in.attitude_external = fc_quat_identity();
    in.position_m = fc_vec3_make(F(0, LENGTH), F(0, LENGTH), F(z_m, LENGTH));
    in.velocity_mps = fc_vec3_zero();
    in.pad.z_m = F(0, LENGTH);
    in.pad.vz_mps = F(0, VEL);
    in.pad.az_mps2 = F(0, ACCEL);
    in.position_setpoint_m = fc_vec3_zero();
    in.yaw_setpoint_rad = F(0, ANGLE);
    in.command = FC_COMMAND_TRACK_PAD;
    return in;
}

/* Disarmed steps until the attitude filter has aligned (arming waits for it;
 * with the platform's attitude there is nothing to wait for). */
static inline void align_disarmed(fc_controller *ctl, fc_controller_inputs in)
{
    in.command = FC_COMMAND_DISARM;
    fc_controller_outputs out;
    for (unsigned k = 0u; k < ctl->estimator.p.alignment_samples; k++) {
        (void)fc_controller_step(ctl, &in, &out);
        assert_false(out.motors_on);
    }
    assert_true(ctl->p.use_external_attitude || ctl->estimator.aligned);
}

/* The defaults of an airframe and variant at 500 Hz, initialised. */
static inline void init_at_500_hz(fc_controller *ctl, fc_controller_params *p, fc_airframe airframe,
                           fc_altitude_variant variant)
{
    fc_controller_default_params(p, airframe, variant, F(0.002, DT));
    assert_int_equal(fc_controller_init(ctl, p), FC_INIT_OK);
}

#endif /* FC_CONTROLLER_SUPPORT_H */
