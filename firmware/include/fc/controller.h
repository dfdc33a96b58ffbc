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
 *   horizontal position PID -> wanted acceleration -> F = m (a_des - g - I_a) (2.11),
 *              its direction and the heading give the attitude setpoint
 *              (fc/position_control.h, no trigonometry per step); outer group.
 *              I_a, the acceleration feedback (2.10), Figure 2.8, integrates
 *              k_a (a - a_des) with a the IMU's specific force rotated to the
 *              world by the attitude in use, less gravity, horizontal only
 *              (fc_controller_measured_accel); horizontal.accel_fb_gain_per_s
 *              = 0 flies without it
 *   attitude   quaternion attitude control (2.9) -> body moments
 *   allocation thrust and moments -> normalised rotor speeds (2.2)-(2.6)
 * Rate groups. The inner group (attitude estimate and control, allocation, the
 * altitude law and its reference, the landing manager) runs on every step. The
 * outer group runs once every outer_divider steps (a major frame), its parts
 * spread over minor frames of their own so that no two add up in one step:
 *   minor frame 0  the position loop's demand: the measured acceleration, the
 *                  horizontal PID, F = m (a_des - g - I_a) and its limits, both
 *                  integrators (fc_position_control_demand), at dt outer_divider;
 *                  F waits for the next frame
 *   minor frame 1  the position loop's attitude: F's direction and the heading
 *                  give the attitude setpoint (fc_position_control_attitude),
 *                  held from here to the next frame 1 (until the first after
 *                  arming, a reset or a level phase, the setpoint is level at
 *                  the heading; a reset or a level phase between frames 0 and
 *                  1 drops the demand: the loop never runs out of its frames)
 *   minor frame 2  the pad model, at dt outer_divider; a range sample waits for
 *                  it (the newest one) and is carried to that step along the
 *                  model's own vertical speed; between its runs the pad's
 *                  trajectory is extrapolated, z + z' t + z'' t^2 / 2
 *   minor frames 3 and on  the work of the pad model's next step that
 *                  needs no sample, one slice a frame: the
 *                  covariance update of the newest sample in two parts (the
 *                  first with the rotations of adapted frequencies and the
 *                  summary of the newest fit, the second with the phases
 *                  turned to the next step), then the RLS gain for those phases
 *                  (fc_pad_motion_work_ahead; what no frame did, the model's
 *                  next step does first)
 * These frames are for outer_divider >= 5. With 2 to 4 the position loop
 * runs whole in frame 0, the pad model in frame 1 and its work ahead from
 * frame 2; with outer_divider 1 both run on every step, as one group. The
 * default puts the outer group at 100 Hz or the step rate if that is slower,
 * the Crazyflie firmware's position rate; the position input rarely comes
 * faster.
 * Safety (SPEC "Safety contract"):
 *   arming     a command that arms (TRACK_PAD, HOLD, LAND) is refused while
 *              the filter has not aligned, the IMU sample or the platform's
 *              attitude is not usable, or the inputs the command needs are
 *              not (FC_STEP_REFUSED, the reason in arming_blocked_by); it
 *              arms at the first step that passes
 *   commands   a value outside fc_controller_command is refused and the mode
 *              kept (FC_STEP_REFUSED, command_refused); only a valid DISARM
 *              stops the motors in flight
 *   inputs     position, velocity, setpoints and (tracking) the pad pass
 *              the plausibility gates of fc/input_gate.h; a rejected sample
 *              is bad input: for failsafe.bad_input_hold_s the last accepted
 *              ones are flown, the height carried along the vertical
 *              estimate's speed and Theta not adapting
 *              (fc_altitude_control_hold), then FAILSAFE (fc/failsafe.h)
 *   IMU        a gyro sample that is not usable is never replaced by an
 *              old rate: with the platform's attitude the rate is its change
 *              over the step, with the filter's (which holds still without
 *              a gyro) the attitude law is not run and the moments are zero;
 *              no usable sample for failsafe.imu_timeout_s: FAILSAFE
 *   FAILSAFE   level at the heading (the attitude law's integral holds
 *              the trim: see controller_params.c), a vertical-speed loop at
 *              failsafe.descent_mps on the vertical estimate
 *              (fc/vertical_estimator.h: speed, accelerometer bias, hover
 *              thrust learnt in flight); the motors stop only when the land
 *              detector (fc/land_detector.h) says LANDED. The landing state
 *              says so (FC_LANDING_FAILSAFE, FC_REASON_INPUTS_LOST; the cause
 *              in failsafe_cause), FC_STEP_DEGRADED is set. Every input good
 *              for bad_input_hold_s again: the mission resumes from HOLD.
 *   landing    the mission's LANDED stops the motors only if no fresh range
 *              sample puts the gear above the land detector's airborne
 *              height; if one does, the landing aborts (FC_REASON_CONTACT_LOST).
 * Frames: world ENU (z up), body FLU; q is body -> world.
 */
#ifndef FC_CONTROLLER_H
#define FC_CONTROLLER_H

#include "fc/allocation.h"
#include "fc/altitude_control.h"
#include "fc/altitude_reference.h"
#include "fc/attitude_control.h"
#include "fc/attitude_estimator.h"
#include "fc/failsafe.h"
#include "fc/input_gate.h"
#include "fc/land_detector.h"
#include "fc/landing.h"
#include "fc/pad_motion.h"
#include "fc/position_control.h"
#include "fc/quat.h"
#include "fc/status.h"
#include "fc/trajectory_tracking.h"
#include "fc/vertical_estimator.h"

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

/* Why arming is refused (telemetry arming_blocked_by). */
typedef enum fc_arming_check {
    FC_ARMING_OK = 0,
    FC_ARMING_NOT_ALIGNED,      /* the attitude filter has not finished its alignment */
    FC_ARMING_IMU_BAD,          /* the IMU sample is not usable */
    FC_ARMING_ATTITUDE_BAD,     /* the platform's attitude is not a usable quaternion */
    FC_ARMING_INPUTS_BAD,       /* position, velocity, setpoints (or the pad, tracking) not usable */
    FC_ARMING_AWAIT_DISARM,     /* the failsafe landed: a DISARM before the next arming */
    FC_ARMING_CHECK_COUNT
} fc_arming_check;

/* What the step drives (fc_controller_outputs.output). */
typedef enum fc_output_kind {
    FC_OUTPUT_ROTORS = 0,   /* rotor speeds through the allocation: the inner loop is ours */
    FC_OUTPUT_VELOCITY,     /* velocity commands to a vehicle whose own autopilot flies its
                             * rotors (a DJI-class M600, dissertation 2.6.6): see below */
    FC_OUTPUT_KIND_COUNT
} fc_output_kind;

/* FC_VELOCITY_OUTPUT 0 builds the library without the velocity output (an
 * image that only drives rotors, the ATmega's: the tracking law is not
 * linked); fc_controller_init then refuses FC_OUTPUT_VELOCITY. */
#ifndef FC_VELOCITY_OUTPUT
#define FC_VELOCITY_OUTPUT 1
#endif

/* The velocity output (FC_OUTPUT_VELOCITY). The vehicle takes a world
 * velocity command u per axis and follows it as v' = -a_P v + k_P u
 * (2.18)-(2.23); fc_controller_step forms u by the tracking law (2.24)
 * (fc/trajectory_tracking.h) with r = (pad centre x, y; z_r of the landing
 * manager), r' = (0, 0, z_r'), r'' = (0, 0, z_r''), x and x' the measured
 * position and velocity. The mission, the gates and the failsafe are the
 * rotor path's; where that path sets a body thrust T (the thrust ramp of
 * DISARM, the hover held on a lost contact, the failsafe's speed loop) the
 * vertical command is the one that asks the vehicle for the same vertical
 * acceleration a = g (T k_h / T_h - 1), T_h the hover thrust:
 * u_z = (a + a_P v_z) / k_P, (2.23) solved for u, and the horizontal
 * command is 0 (stop and level). The attitude law and the allocation do
 * not run, the rotor outputs are 0 (rotor_count 0), the hover thrust is not
 * learnt. Heading: yaw_rate_cmd = yaw_gain (psi_sp - psi) + psi_sp',
 * clamped to yaw_rate_max, 0 in the failsafe and on the pad. The thrust
 * checks of fc_controller_init (1.5 x weight, the rotors' sum) are the
 * vehicle autopilot's and are not made. */
typedef struct fc_velocity_output_params {
    fc_trajectory_tracking_params tracking; /* (2.24): k_P, a_P, zeta, w_n, |u| limit per axis */
    fc_real yaw_gain_per_s;             /* RATIO: [0, 20] 1/s */
    fc_real yaw_rate_max_radps;         /* RATE: (0, 10] rad/s */
} fc_velocity_output_params;

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
    fc_input_gate_params gate;
    fc_vertical_estimator_params vertical;
    fc_land_detector_params land_detector;
    fc_failsafe_params failsafe;
    fc_output_kind output;              /* FC_OUTPUT_ROTORS unless set (fc_controller_set_velocity_output) */
    fc_velocity_output_params velocity; /* used with FC_OUTPUT_VELOCITY */
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
    fc_quat pad_attitude;               /* UNIT: the pad's attitude, pad -> world (a deck's roll and
                                         * pitch, e.g. from its markers); read only by a shaped
                                         * descent (landing.descent_shaping, the aversive term
                                         * (2.28)); a zero quaternion counts as a level pad */
    fc_real yaw_setpoint_rad;           /* ANGLE */
    fc_controller_command command;
    fc_real yaw_rate_setpoint_radps;    /* RATE: the rate of yaw_setpoint_rad (0: none), fed
                                         * forward to the attitude law as a turn about the
                                         * world's up axis; clamped to the gate's yaw_rate_max */
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
    fc_real descent_shaping_mps;        /* VEL: a shaped descent's v_zd of (2.25) (0 otherwise) */
    uint8_t aborts;
    fc_vertical_estimate vertical;      /* the failsafe's and the land detector's view */
    fc_land_state land_state;           /* the land detector's stage (in the failsafe) */
    fc_failsafe_cause failsafe_cause;   /* FC_FAILSAFE_NONE when not in the failsafe */
    fc_arming_check arming_blocked_by;  /* what refused the arming at this step */
    bool command_refused;               /* the command was not a fc_controller_command */
    bool armed;
} fc_controller_telemetry;

typedef struct fc_controller_outputs {
    fc_real rotor_speed[FC_MAX_ROTORS]; /* UNIT: w / w_max, 0 with the motors off */
    uint8_t rotor_count;
    bool motors_on;
    fc_real thrust_n;                   /* FORCE: body thrust demanded */
    fc_vec3 moment_nm;                  /* MOMENT: body moments demanded */
    fc_output_kind output;              /* which command is valid: the rotors' or the velocity's */
    fc_vec3 velocity_cmd_mps;           /* VEL: world ENU velocity command (FC_OUTPUT_VELOCITY), 0
                                         * otherwise and with the motors off */
    fc_real yaw_rate_cmd_radps;         /* RATE: about the world's up axis, as velocity_cmd_mps */
    fc_controller_telemetry telemetry;
} fc_controller_outputs;

/* What the step itself reads of the parameters (each module keeps its own):
 * the whole fc_controller_params would be a second copy of every module's,
 * some 1.2 KB the ATmega's 8 KiB of RAM cannot spare. */
typedef struct fc_controller_settings {
    fc_real dt_s;                       /* DT */
    uint8_t outer_divider;
    bool use_external_attitude;
    fc_real gear_height_m;              /* LENGTH: landing.gear_height_m */
    fc_real thrust_min_n, thrust_max_n; /* FORCE: the altitude law's limits */
    fc_real reference_offset_init_m;    /* LENGTH: reference.offset_init_m */
    fc_real range_fresh_s;              /* TIME: land_detector.range_fresh_s */
    fc_output_kind output;
    fc_real yaw_gain_per_s;             /* RATIO: velocity.yaw_gain_per_s */
    fc_real yaw_rate_max_radps;         /* RATE: velocity.yaw_rate_max_radps */
    fc_real inv_gravity_s2pm;           /* RATIO: 1 / g */
    fc_real gravity_mps2;               /* ACCEL */
    fc_real k_p_z_per_s;                /* RATIO: velocity.tracking.k_p_per_s.z */
    fc_gain dt;                         /* dt, s: the step's integrations */
    fc_gain half_dt_sq;                 /* dt^2 / 2, s^2 */
} fc_controller_settings;

/* The parts of the controller's own state, one job each (controller.c has
 * a section per part). */

/* The mission: the command flown, arming. */
typedef struct fc_controller_mission {
    fc_controller_command last_command; /* the mode flown at the last step (DISARM: none) */
    fc_controller_command mode;         /* the newest valid command: what an unknown one keeps */
    bool armed;
    bool await_disarm;                  /* landed by the failsafe: no arming before a DISARM */
} fc_controller_mission;

/* The input guard: what the step flies on while an input is not usable. */
typedef struct fc_controller_guard {
    fc_quat last_attitude;              /* the platform's attitude in use at the last step */
    fc_quat last_external_attitude;     /* the platform's, for a rate without a gyro */
    fc_real reckoned_z_m;               /* LENGTH: the height flown on while inputs are held */
} fc_controller_guard;

/* The rate groups (fc_controller_set_outer_divider): this step's place in
 * the major frame, and what the outer group's position loop hands from its
 * demand's frame to its attitude's and holds for the major frame. */
typedef struct fc_controller_rate_groups {
    uint8_t minor_frame;                /* 0..outer_divider - 1 */
    fc_position_control_output position; /* the loop's newest halves: F_req (thrust_world_n) from
                                         * the demand's frame, attitude_sp held from the attitude's */
    fc_step_status demand_status;       /* the demand half's status bits, until its attitude frame */
    fc_step_status held_position_status; /* both halves' status bits, reported while held */
    bool have_demand;                   /* position.thrust_world_n waits for its attitude frame */
    bool have_attitude_setpoint;        /* position.attitude_sp is the running loop's */
} fc_controller_rate_groups;

/* The range finder's samples: the gear's height above the pad, and the
 * pad's height waiting for the pad model's minor frame; the model's newest
 * estimate. */
typedef struct fc_controller_pad_samples {
    fc_real gear_height_m;              /* LENGTH: newest range sample as gear height */
    fc_real gear_height_age_s;          /* TIME: its age */
    bool gear_height_known;
    fc_real pending_height_m;           /* LENGTH: the newest range sample as pad height, waiting */
    fc_real pending_age_s;              /* DT: since it was taken */
    bool pending;
    fc_pad_motion_estimate estimate;    /* the pad model's newest output, its trajectory
                                         * (now) carried to this step */
    fc_real model_vz_mps;               /* VEL: the model's own z' (at its step) */
    fc_real height_step_m;              /* LENGTH: now.z_m's change over the next step */
    fc_real height_step_change_m;       /* LENGTH: that change's own a step, z'' dt^2 */
    fc_real speed_step_mps;             /* VEL: now.vz_mps's change a step, z'' dt */
} fc_controller_pad_samples;

/* The heading of the setpoint, kept between steps: trigonometry only when
 * it changes. */
typedef struct fc_controller_heading {
    fc_real yaw_rad;                    /* ANGLE */
    fc_real yaw_cos, yaw_sin;           /* UNIT */
    fc_quat level;                      /* level at that heading */
} fc_controller_heading;

typedef struct fc_controller {
    fc_controller_settings p;
    fc_controller_mission mission;
    fc_controller_guard guard;
    fc_controller_rate_groups groups;
    fc_controller_pad_samples pad;
    fc_controller_heading heading;
    /* what the loops hand back to the next step */
    uint8_t last_saturation;            /* the allocation's FC_SAT_* */
    fc_real last_thrust_n;              /* FORCE: the body thrust in force */
    fc_real inv_dt_per_s;               /* GAIN: 1 / dt */
    fc_real step_s;                     /* TIME: dt */
    bool ready;
    fc_arith ar;
    /* The modules after the step's own fields: those stepped at every step
     * first, then the outer group's (position loop, pad model) and the
     * allocation, the largest. The order is for the Cortex-M4F: a VLDR/VSTR
     * reaches 1020 bytes from its base register, and in the one translation
     * unit (amalgamation/fc_library.c) the step addresses the modules' fields from
     * ctl, so a field placed further off costs an address computation at
     * each access; among the per-step modules, the order the bench's step
     * (tools/bench.sh) took the fewest cycles with. */
    fc_attitude_estimator estimator;
    fc_vertical_estimator vertical;
    fc_altitude_reference reference;
    fc_input_gate gate;
    fc_attitude_control attitude;
    fc_failsafe failsafe;
    fc_land_detector land_detector;
    fc_landing landing;
    fc_altitude_control altitude;
    fc_position_control position;
    fc_trajectory_tracking tracking;    /* (2.24), the velocity output's law */
    fc_pad_motion pad_motion;
    fc_allocation allocation;
} fc_controller;

/* Parameters for an airframe at step dt_s, with the altitude law of variant. */
void fc_controller_default_params(fc_controller_params *p, fc_airframe airframe, fc_altitude_variant variant,
                                  fc_real dt_s);

/* Parameters for a vehicle given by the platform's own rotors, mass and
 * inertia (the Crazyflie app: the firmware's platform constants): the gains
 * and limits of the preset gains_of, with everything that follows from the
 * rotors and the mass (authority, thrust range, gates, the altitude law's
 * mass-scaled gains) derived from them. */
void fc_controller_default_params_for(fc_controller_params *p, fc_airframe gains_of,
                                      const fc_allocation_params *rotors, fc_real mass_kg, fc_vec3 inertia_kgm2,
                                      fc_altitude_variant variant, fc_real dt_s);

/* The nominal mass, and everything that follows it: the position loop's
 * mass, the altitude law's Theta0 and mass bounds (-25 % / +25 %), the
 * hover thrust before it is learnt and its bounds. The gains stay. */
void fc_controller_set_mass(fc_controller_params *p, fc_real mass_kg);

/* The outer group's major frame in steps, [1, FC_OUTER_DIVIDER_MAX], and
 * the steps of the modules that run once a major frame (the position loop,
 * the pad model) with it: a platform whose core cannot run the outer group
 * at the default's 100 Hz gives it a longer frame. */
void fc_controller_set_outer_divider(fc_controller_params *p, uint8_t divider);

/* The velocity output (FC_OUTPUT_VELOCITY, above) with the law and the
 * vehicle's identified first-order velocity response in v. */
void fc_controller_set_velocity_output(fc_controller_params *p, const fc_velocity_output_params *v);

/* A velocity-input vehicle's tracking law for a first-order response of
 * k_P, a_P (1/s, per axis): the error dynamics (2.14) at zeta = 1 and
 * w_n = 1.5 rad/s horizontally, 2 rad/s vertically, |u| <= 3 m/s
 * horizontally and 1.5 m/s vertically; the heading at 1 /s, 0.5 rad/s. */
void fc_controller_velocity_defaults(fc_velocity_output_params *v, fc_vec3 k_p_per_s, fc_vec3 a_p_per_s);

fc_init_result fc_controller_init(fc_controller *ctl, const fc_controller_params *p);

/* The measured acceleration the position loop's feedback (2.10) takes, in
 * the world frame (ENU): the accelerometer's specific force f (body; +g along
 * body z at rest) rotated by the attitude q (body -> world), less gravity,
 * horizontal only: (R(q) f)_x, (R(q) f)_y, and z = 0 (controller.c says why).
 * false, and zero, when the sample or the attitude is not usable (usable
 * false): the feedback then holds. */
bool fc_controller_measured_accel(fc_arith *ar, fc_quat attitude, fc_vec3 specific_force_mps2, bool usable,
                                  fc_vec3 *accel_world_mps2);

/* One fixed step. The outputs are always finite and inside the actuator range;
 * the returned bits say what the step had to do to keep them so. */
fc_step_status fc_controller_step(fc_controller *ctl, const fc_controller_inputs *in, fc_controller_outputs *out);

#endif /* FC_CONTROLLER_H */
