/*
 * fc/controller.h - the whole flight controller: one object, one fixed-step
 * entry point. The Crazyflie app, the ATmega image, the SIL harness and the
 * benchmarks call fc_controller_init and fc_controller_step and nothing deeper,
 * so what is measured is what flies.
 *
 * One step (at the dt fixed at init):
 *   attitude   complementary filter on the IMU (2.5), or the platform's own estimate
 *   pad        the pad's height from the range finder (z - range k_h) learnt and
 *              predicted (fc/pad_motion.h); outer group, see below
 *   mission    TRACK_PAD: z_r (3.6) around the pad trajectory the platform gives
 *              (the 4.4 task); HOLD / LAND: the landing manager (fc/landing.h)
 *              chooses the reference, the thrust ramp and when the motors stop
 *   altitude   the altitude law (SSC or a baseline) -> body thrust, tilt compensated
 *   horizontal position PID -> wanted acceleration -> F = m (a_des - g) (2.11),
 *              its direction and the heading give the attitude setpoint
 *              (fc/position_control.h, no trigonometry per step); outer group
 *   attitude   quaternion attitude control (2.9) -> body moments
 *   allocation thrust and moments -> normalised rotor speeds (2.2)-(2.6)
 * Rate groups. The inner group (attitude estimate and control, allocation, the
 * altitude law and its reference, the landing manager) runs on every step. The
 * outer group runs once every outer_divider steps (a major frame), each part
 * in a minor frame of its own so that the two never add up in one step:
 *   minor frame 0  the horizontal position loop, at dt outer_divider; its
 *                  attitude setpoint is held for the major frame (until its
 *                  first run after arming, a reset or a level phase, the
 *                  setpoint is level at the heading: the loop never runs
 *                  out of its frame)
 *   minor frame 1  the pad model, at dt outer_divider; a range sample waits for
 *                  it (the newest one) and is carried to that step along the
 *                  model's own vertical speed; between its runs the pad's
 *                  trajectory is extrapolated, z + z' t + z'' t^2 / 2
 *   minor frames 2 and on (outer_divider >= 3)  the work of the pad model's
 *                  next step that needs no sample, one piece a frame: the
 *                  covariance update of the newest sample in two parts (the
 *                  first with the rotations of adapted frequencies, the second
 *                  with the phases turned to the next step), then the summary
 *                  of the newest fit and the RLS gain for those phases
 *                  (fc_pad_motion_work_ahead; what no frame did, the model's
 *                  next step does first)
 * (with outer_divider 1 both run on every step, as one group). The default
 * puts the outer group at 100 Hz or the step rate if that is slower, the
 * Crazyflie firmware's position rate; the position input rarely comes faster.
 * Bad input: position, velocity, setpoints (and the pad trajectory when
 * tracking it) that are not numbers inside the physical range are replaced by
 * the last good ones for failsafe.bad_input_hold_s; beyond that the step
 * falls back to FAILSAFE: level attitude, a descent at failsafe.descent_mps
 * on the vertical speed integrated from the accelerometer, motors off once it
 * stops descending (on the ground) or after failsafe.max_s. The landing state
 * says so (FC_LANDING_FAILSAFE, FC_REASON_INPUTS_LOST), FC_STEP_DEGRADED is set.
 * Frames: world ENU (z up), body FLU; q is body -> world.
 */
#ifndef FC_CONTROLLER_H
#define FC_CONTROLLER_H

#include "fc/allocation.h"
#include "fc/altitude_control.h"
#include "fc/altitude_reference.h"
#include "fc/attitude_control.h"
#include "fc/attitude_estimator.h"
#include "fc/landing.h"
#include "fc/pad_motion.h"
#include "fc/position_control.h"
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
    FC_COMMAND_HOLD,         /* landing mission: hold above the pad and learn it; aborts a descent */
    FC_COMMAND_LAND,         /* landing mission: hold, learn, descend, touch down, motors off */
    FC_COMMAND_COUNT
} fc_controller_command;

typedef struct fc_failsafe_params {
    fc_real bad_input_hold_s;   /* TIME: bad inputs replaced by the last good ones this long, [0, 10] */
    fc_real descent_mps;        /* VEL: the failsafe's descent rate, (0, 5] */
    fc_real speed_gain_per_s;   /* GAIN: vertical-speed loop gain, (0, 50] */
    fc_real max_s;              /* TIME: motors off after this long in failsafe, (0, 600] */
} fc_failsafe_params;

#define FC_OUTER_DIVIDER_MAX 10u        /* the outer group's longest major frame, in steps */

typedef struct fc_controller_params {
    fc_real dt_s;                       /* DT: the fixed step of the inner group */
    uint8_t outer_divider;              /* steps per major frame, [1, FC_OUTER_DIVIDER_MAX]:
                                         * horizontal.dt_s and pad_motion.dt_s are dt_s times it */
    fc_real mass_kg;                    /* MASS: nominal */
    fc_real gravity_mps2;               /* ACCEL */
    bool use_external_attitude;         /* the platform's estimate instead of the filter: the
                                         * filter then only checks the IMU and forms the rate,
                                         * gyro - b with b as init left it (0), so the platform's
                                         * gyro must be calibrated; heading_rad goes unused; the
                                         * attitude is taken in UNIT16 (fixed: 6.1e-5 a component),
                                         * the attitude law's resolution */
    fc_attitude_estimator_params estimator;
    fc_attitude_control_params attitude;
    fc_allocation_params allocation;
    fc_altitude_reference_params reference;
    fc_altitude_control_params altitude;
    fc_position_control_params horizontal;
    fc_pad_motion_params pad_motion;
    fc_landing_params landing;
    fc_failsafe_params failsafe;
} fc_controller_params;

typedef struct fc_controller_inputs {
    fc_imu_sample imu;                  /* body gyro (RATE) and specific force (ACCEL) */
    fc_quat attitude_external;          /* used with use_external_attitude */
    fc_real heading_rad;                /* ANGLE: a measured yaw (motion capture, compass) for the
                                         * filter's heading (fc/attitude_estimator.h) */
    bool heading_fresh;                 /* heading_rad is a new sample this step */
    fc_vec3 position_m;                 /* LENGTH: world ENU, centre of mass */
    fc_vec3 velocity_mps;               /* VEL: world */
    fc_vertical_trajectory pad;         /* TRACK_PAD: the pad's height and its derivatives */
    fc_real range_m;                    /* LENGTH: range finder, CG to the pad along body -z */
    bool range_fresh;                   /* range_m is a new sample this step */
    fc_vec3 position_setpoint_m;        /* LENGTH: x, y held over the pad (the pad's centre; z unused) */
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
    fc_pad_motion_estimate pad;         /* what the vehicle knows of the pad */
    fc_real gear_height_m;              /* LENGTH: gear above the pad from the range finder (last sample) */
    fc_landing_state landing_state;
    fc_landing_reason landing_reason;   /* of the newest transition */
    bool landing_changed;               /* a transition at this step */
    bool touchdown_window;              /* the landing plan expects contact from now on */
    fc_landing_reason descent_blocked_by; /* OBSERVE: what keeps the descent from starting */
    uint8_t aborts;
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
    fc_position_control position;
    fc_pad_motion pad_motion;
    fc_landing landing;
    fc_controller_command last_command;
    uint8_t last_saturation;
    fc_quat last_attitude;
    fc_real last_thrust_n;              /* FORCE */
    fc_real gear_height_m;              /* LENGTH: newest range sample as gear height */
    /* rate groups (see the top of this file) */
    uint8_t minor_frame;                /* this step's place in the major frame, 0..outer_divider - 1 */
    fc_quat held_attitude_setpoint;     /* the position loop's, held for the major frame */
    fc_step_status held_position_status; /* its status bits, reported while it is held */
    bool have_attitude_setpoint;        /* held_attitude_setpoint is the running loop's */
    fc_pad_motion_estimate pad_estimate; /* the pad model's newest output */
    fc_real pad_estimate_age_s;         /* DT: since the pad model made it */
    fc_real pending_pad_height_m;       /* LENGTH: the newest range sample as pad height, waiting */
    fc_real pending_pad_age_s;          /* DT: since it was taken */
    bool pad_sample_pending;
    /* bad input */
    fc_controller_inputs last_good;     /* the newest inputs that were usable */
    bool have_last_good;
    fc_real bad_input_s;                /* TIME: how long the inputs have been bad */
    fc_real good_input_s;               /* TIME: how long good again (in failsafe) */
    bool failsafe;
    fc_real failsafe_s;                 /* TIME */
    fc_real failsafe_vz_mps;            /* VEL: vertical speed integrated from the accelerometer */
    fc_real not_descending_s;           /* TIME */
    bool failsafe_landed;
    /* the heading of the setpoint, kept between steps (trigonometry only when it changes) */
    fc_real heading_rad, heading_cos, heading_sin;
    fc_quat heading_level;              /* level at that heading */
    fc_real step_s;                     /* TIME: dt */
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
