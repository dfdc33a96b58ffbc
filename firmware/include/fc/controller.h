/*
 * fc/controller.h - the whole flight controller: one object, one fixed-step
 * entry point. The Crazyflie app, the ATmega image, the SIL harness and the
 * benchmarks call fc_controller_init and fc_controller_step and nothing deeper,
 * so what is measured is what flies.
 *
 * One step (at the dt fixed at init):
 *   attitude   complementary filter on the IMU (2.5), or the platform's own estimate
 *   reference  z_r (3.6) around the pad's trajectory
 *   altitude   the altitude law (SSC or a baseline) -> body thrust, tilt compensated
 *   horizontal PD on the position error -> wanted acceleration -> attitude setpoint
 *              (F = m (a_des - g) (2.11), its direction and the heading give q_d)
 *   attitude   quaternion attitude control (2.9) -> body moments
 *   allocation thrust and moments -> normalised rotor speeds (2.2)-(2.6)
 * Frames: world ENU (z up), body FLU; q is body -> world.
 */
#ifndef FC_CONTROLLER_H
#define FC_CONTROLLER_H

#include "fc/allocation.h"
#include "fc/altitude_control.h"
#include "fc/altitude_reference.h"
#include "fc/attitude_control.h"
#include "fc/attitude_estimator.h"
#include "fc/quat.h"
#include "fc/status.h"

typedef enum fc_airframe {
    FC_AIRFRAME_CRAZYFLIE2 = 0, /* 27 g quad-X, the firmware's own constants */
    FC_AIRFRAME_F450,           /* 1.2 kg quad-X */
    FC_AIRFRAME_HEXA_4KG,       /* 4 kg hexa-X, the dissertation's 4.4 vehicle */
    FC_AIRFRAME_COUNT
} fc_airframe;

typedef enum fc_controller_command {
    FC_COMMAND_DISARM = 0,   /* motors off, states reset */
    FC_COMMAND_TRACK_PAD,    /* follow the reference (3.6) over the pad: the 4.4 task */
    FC_COMMAND_COUNT
} fc_controller_command;

typedef struct fc_horizontal_params {
    fc_real kp_per_s2;       /* GAIN: wanted acceleration per m of position error */
    fc_real kd_per_s;        /* GAIN: per m/s of velocity error */
    fc_real tilt_max_rad;    /* ANGLE: the attitude setpoint's tilt limit */
} fc_horizontal_params;

typedef struct fc_controller_params {
    fc_real dt_s;                       /* DT: the fixed step of everything below */
    fc_real mass_kg;                    /* MASS: nominal */
    fc_real gravity_mps2;               /* ACCEL */
    bool use_external_attitude;         /* the platform's estimate instead of the filter */
    fc_attitude_estimator_params estimator;
    fc_attitude_control_params attitude;
    fc_allocation_params allocation;
    fc_altitude_reference_params reference;
    fc_altitude_control_params altitude;
    fc_horizontal_params horizontal;
} fc_controller_params;

typedef struct fc_controller_inputs {
    fc_imu_sample imu;                  /* body gyro (RATE) and specific force (ACCEL) */
    fc_quat attitude_external;          /* used with use_external_attitude */
    fc_vec3 position_m;                 /* LENGTH: world ENU, centre of mass */
    fc_vec3 velocity_mps;               /* VEL: world */
    fc_vertical_trajectory pad;         /* the pad's height and its derivatives */
    fc_vec3 position_setpoint_m;        /* LENGTH: x, y held over the pad (z unused) */
    fc_real yaw_setpoint_rad;           /* ANGLE */
    fc_controller_command command;
} fc_controller_inputs;

typedef struct fc_controller_telemetry {
    fc_quat attitude;                   /* estimate in use */
    fc_quat attitude_setpoint;
    fc_vec3 rate_radps;                 /* bias-corrected */
    fc_vertical_trajectory reference;   /* z_r, z_r', z_r'' */
    fc_altitude_control_output altitude;
    fc_real tilt_cos;                   /* RATIO: k_h */
    uint8_t allocation_saturation;      /* FC_SAT_* */
    fc_step_status estimator_status, altitude_status, attitude_status, allocation_status;
} fc_controller_telemetry;

typedef struct fc_controller_outputs {
    fc_real rotor_speed[FC_MAX_ROTORS]; /* UNIT: w / w_max, 0 with the motors off */
    uint8_t rotor_count;
    bool motors_on;
    fc_real thrust_n;                   /* FORCE: body thrust demanded */
    fc_vec3 moment_nm;                  /* MOMENT: body moments demanded */
    fc_controller_telemetry telemetry;
} fc_controller_outputs;

typedef struct fc_controller {
    fc_controller_params p;
    fc_attitude_estimator estimator;
    fc_attitude_control attitude;
    fc_allocation allocation;
    fc_altitude_reference reference;
    fc_altitude_control altitude;
    fc_controller_command last_command;
    uint8_t last_saturation;
    fc_quat last_attitude;
    fc_real horizontal_accel_max_mps2;  /* ACCEL: g tan(tilt_max) */
    bool ready;
    fc_arith ar;
} fc_controller;

/* Parameters for an airframe at step dt_s, with the altitude law of variant. */
void fc_controller_default_params(fc_controller_params *p, fc_airframe airframe, fc_altitude_variant variant,
                                  fc_real dt_s);

fc_init_result fc_controller_init(fc_controller *ctl, const fc_controller_params *p);

/* One fixed step. The outputs are always finite and inside the actuator range;
 * the returned bits say what the step had to do to keep them so. */
fc_step_status fc_controller_step(fc_controller *ctl, const fc_controller_inputs *in, fc_controller_outputs *out);

#endif /* FC_CONTROLLER_H */
