/*
 * cf_convert.h - what the Crazyflie app does besides copying fields: unit and
 * frame conversions between crazyflie-firmware's numbers and the library's,
 * the parameters a user tunes from cfclient, and the few decisions of the app
 * (which command, which setpoint, the virtual pad). Plain C, no Crazyflie
 * header: the host tests (tests/test_cf_convert.c) cover all of it in both
 * numeric backends, and cf_glue.c only copies fields in and out.
 *
 * The firmware's conventions (crazyflie-firmware master, stabilizer_types.h):
 *   sensorData.gyro   body frame, deg/s
 *   sensorData.acc    body frame, G; specific force: level at rest reads (0, 0, +1)
 *   state.attitudeQuaternion  body -> world, scalar LAST (x, y, z, w)
 *   state.attitude    legacy Euler in degrees with the pitch sign inverted
 *                     (legacy pitch = -pitch of the ZYX angles); roll and yaw are not
 *   state.position, state.velocity  world frame, z up, m and m/s
 *   control (controlModeForceTorque)  thrustSi in N along body z, torque[] in N m
 *                     about the body axes (x forward, y left, z up)
 * The library's (fc/controller.h): world ENU z up, body FLU, q body -> world,
 * scalar FIRST (w, x, y, z), SI units. So the frames agree and only the units,
 * the quaternion's component order and the legacy pitch sign change.
 */
#ifndef CF_CONVERT_H
#define CF_CONVERT_H

#include <stdbool.h>
#include <stdint.h>

#include "fc/controller.h"

/* The firmware's GRAVITY_MAGNITUDE, and the library's default g. */
#define CF_GRAVITY_MPS2 9.81f
/* The controller's fixed step: RATE_DO_EXECUTE(ATTITUDE_RATE, tick), 500 Hz of
 * the 1 kHz stabilizer loop. */
#define CF_STEP_DT_S 0.002f
#define CF_PI_F 3.14159265f

/* Values of the firmware's stab_mode_t (cf_glue.c checks them at compile time). */
#define CF_MODE_DISABLE 0u
#define CF_MODE_ABS 1u
#define CF_MODE_VELOCITY 2u

/* The altitude law the app starts with: SSC with the adaptive Theta (4.4), which
 * learns the real vehicle's mass (a Crazyflie with decks is heavier than the
 * preset's 27 g). */
#define CF_DEFAULT_VARIANT ((uint8_t)FC_ALT_VARIANT_SSC_ADAPTIVE)
/* tau_zr of the reference (3.6) on the Crazyflie. The 4.4 value, 0.1 s, starts
 * the approach with z_r'' = z_r_init / tau^2 = 100 m/s^2 per metre of offset, far
 * beyond the ~8 m/s^2 a Crazyflie can add to gravity: 2 s keeps it at 0.25 m/s^2
 * per metre. The only default that differs from fc_controller_default_params. */
#define CF_DEFAULT_TAU_ZR_S 2.0f
/* The approach offset taken from the present height is kept inside
 * [-this, this]: the reference starts where the vehicle is, above or below. */
#define CF_APPROACH_OFFSET_MAX_M 4.0f
/* How far a velocity setpoint's integrated point may lead the vehicle, per
 * axis: a vehicle held back does not wind up a run-away target. */
#define CF_VELOCITY_LEAD_MAX_M 1.0f
/* The commander's height moves the tracked height at most this fast: an
 * absolute z that steps (a new hover height) becomes a ramp the library's
 * pad gate accepts (fc/input_gate.h: 3 m/s and a 0.1 m jump). */
#define CF_COMMAND_Z_SPEED_MAX_MPS 1.0f
/* loaded_variant before any defaults were loaded */
#define CF_TUNING_NONE 0xFFu

/* Values of the "mission" parameter (PARAM fcssc.mission). */
#define CF_MISSION_FOLLOW 0u /* the command is the "track" parameter's (0 motors off, 1 track the pad) */
#define CF_MISSION_HOLD 1u   /* FC_COMMAND_HOLD: hold above the pad and learn it; aborts a descent */
#define CF_MISSION_LAND 2u   /* FC_COMMAND_LAND: hold, learn, descend, touch down, motors off */

/* The down-pointing ToF ranger (Flow deck v2 / Z-ranger deck): rangeGet(rangeDown)
 * is the last reading in whole mm (range.c keeps a uint16). The deck driver gives
 * the estimator only readings below its RANGE_OUTLIER_LIMIT, 5000 mm ("outliers
 * typically occur as >8 m"); the app takes the same ones. */
#define CF_RANGE_MAX_MM 5000.0f

/* ---- units --------------------------------------------------------------- */

float cf_rad_from_deg(float deg);
float cf_mps2_from_g(float g);
/* An angle wrapped into [-pi, pi]. */
float cf_wrap_pi(float angle_rad);

/* ---- quaternions ----------------------------------------------------------- */

/* The firmware's scalar-last quaternion as the library's (w, x, y, z). */
fc_quat cf_quat_from_xyzw(float x, float y, float z, float w);
/* The library's quaternion as the firmware's order: xyzw[0..3] = x, y, z, w. */
void cf_quat_to_xyzw(fc_quat q, float xyzw[4]);
/* state.attitude (legacy Euler, degrees, pitch inverted) as a body -> world
 * quaternion: the ZYX rotation of (roll, -pitch_legacy, yaw). For estimators that
 * publish only the Euler angles; the app itself uses state.attitudeQuaternion. */
fc_quat cf_quat_from_legacy_rpy_deg(float roll_deg, float pitch_legacy_deg, float yaw_deg);

/* ---- the firmware's numbers of one step ------------------------------------ */

/* What cf_glue.c copies out of sensorData_t, state_t and setpoint_t, field by
 * field, in the firmware's units. */
typedef struct cf_sample {
    float gyro_dps[3];     /* sensorData.gyro: body, deg/s */
    float acc_g[3];        /* sensorData.acc: body, G */
    float quat_xyzw[4];    /* state.attitudeQuaternion: x, y, z, w */
    float yaw_deg;         /* state.attitude.yaw (legacy Euler: yaw is not inverted) */
    float pos_m[3];        /* state.position: world, z up */
    float vel_mps[3];      /* state.velocity: world */
    float sp_pos_m[3];     /* setpoint.position */
    float sp_vel_mps[3];   /* setpoint.velocity (world, or body x/y when sp_velocity_body) */
    float sp_acc_mps2[3];  /* setpoint.acceleration (the high-level commander's) */
    bool sp_velocity_body; /* setpoint.velocity_body: x/y velocity in the body's heading frame */
    float sp_yaw_deg;      /* setpoint.attitude.yaw */
    float sp_yaw_rate_dps; /* setpoint.attitudeRate.yaw (mode.yaw velocity: hover, MotionCommander, level-out) */
    float sp_thrust;       /* setpoint.thrust (legacy PWM units; 0 = no thrust asked) */
    float range_mm;        /* rangeGet(rangeDown): the down ranger's last reading, mm (0: none yet) */
    uint8_t sp_mode_x, sp_mode_y, sp_mode_z, sp_mode_yaw; /* setpoint.mode.*: CF_MODE_* */
} cf_sample;

/* ---- the airframe ------------------------------------------------------------ */

/* The firmware's platform constants (platform_defaults_*.h), which cf_glue.c
 * passes at compile time. */
typedef struct cf_airframe {
    float mass_kg;              /* CF_MASS */
    float arm_m;                /* ARM_LENGTH: centre to each motor */
    float thrust_max_n;         /* THRUST_MAX, per motor */
    float thrust_min_n;         /* THRUST_MIN, per motor */
    float torque_per_thrust_m;  /* THRUST2TORQUE */
} cf_airframe;

/* The library's Crazyflie preset (FC_AIRFRAME_CRAZYFLIE2): the cf2 with 2.1+
 * propellers, 27 g. */
#define CF_AIRFRAME_PRESET_ARM_M 0.046f
#define CF_AIRFRAME_PRESET_MASS_KG 0.027f
#define CF_AIRFRAME_PRESET_JXY_KGM2 1.66e-5f
#define CF_AIRFRAME_PRESET_JZ_KGM2 2.93e-5f

/* The airframe the parameters are made for (cf_tuning_prepare,
 * cf_params_from_tuning): the preset's gains and layout (quad-X, the
 * firmware's motor order) with the platform's arm, rotor thrust range,
 * torque per thrust and mass; the inertia is the preset's scaled by mass
 * and arm squared (platform_defaults has none). NULL: the library's preset
 * as it is (the default). Returns false, and keeps the last one, for
 * values outside what a Crazyflie-class quad has. */
bool cf_airframe_use(const cf_airframe *af);

/* ---- the parameters a user tunes (PARAM group "fcssc") --------------------- */

typedef struct cf_tuning {
    uint8_t variant;       /* fc_altitude_variant; a change loads that variant's gains */
    /* altitude law (fc_altitude_control_params), SI units */
    float l0;              /* l0 (K1), 1/s: sigma = e' + l0 e */
    float rho;             /* constant modulation rho, N */
    float gamma;           /* adaptation gain (4.83), kg s^2/m^2 */
    float tau_av;          /* averaging filter (4.7), s */
    float a_m;             /* prediction-error pole (4.5), 1/s */
    float kappa_m;         /* prediction-error gain (4.5), 1/kg */
    float k0;              /* rho = rho_bar + k0 |sigma_tilde|, N s/m */
    float delta;           /* margin delta of (4.39), N */
    float theta0;          /* nominal Theta = m / (k_h k_g) and Theta(0), kg */
    /* z_r: the app passes the library z_r_init = 0 and shapes the approach in the
     * trajectory it gives (cf_track_trajectory), from the height at each switch */
    /* reference (3.6) */
    float tau_zr;          /* s */
    float z_init;          /* z_r_init when offset_auto is 0, m */
    float z_bias;          /* z_r_bias: the height held above the pad, m */
    uint8_t offset_auto;   /* 1: z_r_init from the height when tracking starts (no jump of z_r) */
    uint8_t command_z;     /* 1: tracking follows the commander's height (its z is held; padZ unused) */
    /* the virtual pad: z_d = pad_z (or the commander's height - z_bias, command_z)
     * + pad_amp sin(2 pi pad_freq t), t from the command's start */
    float pad_z;           /* m, world */
    float pad_amp;         /* m */
    float pad_freq;        /* Hz */
    /* horizontal PD */
    float h_kp;            /* 1/s^2 */
    float h_kd;            /* 1/s */
    /* the range finder: range from the CG = reading + range_offset (takes effect at once) */
    float range_offset_m;  /* m; calibrate on the ground: gear height (LOG fcssc.gearH) reads 0 */
    uint8_t loaded_variant; /* whose gains are loaded; CF_TUNING_NONE at first */
} cf_tuning;

/* A tuning with no gains loaded yet (the first cf_tuning_prepare loads them). */
#define CF_TUNING_INITIALIZER                                                       \
    {                                                                              \
        .variant = CF_DEFAULT_VARIANT, .offset_auto = 1u, .command_z = 1u, .loaded_variant = CF_TUNING_NONE \
    }

/* Make the tuning usable: a variant out of range goes back to the loaded one (or
 * the default); the first call loads every gain from the library's Crazyflie
 * defaults, a later change of variant reloads the altitude-law gains of the new
 * variant. Returns true when it loaded gains. */
bool cf_tuning_prepare(cf_tuning *t);

/* The library's parameters for the tuning: the library's Crazyflie defaults
 * for the airframe of cf_airframe_use and t->variant at CF_STEP_DT_S, then every tuned
 * value that differs from the default written over it (an untouched value keeps
 * the library's number bit for bit), the platform's attitude estimate in use
 * (use_external_attitude) and z_r_init = offset_m. Returns false if a tuned
 * value is not finite (that value is left at its default; the app then does not
 * fly: fc_controller_init would not see the NaN in the fixed backend). Range
 * checks are fc_controller_init's. */
bool cf_params_from_tuning(const cf_tuning *t, float offset_m, fc_controller_params *p);

/* z_r_init for an approach that starts now at height z_m over a pad at pad_z_m:
 * with offset_auto the height above the hold point pad + bias, in
 * [-CF_APPROACH_OFFSET_MAX_M, CF_APPROACH_OFFSET_MAX_M] (no jump of the
 * reference, from above or below; 0 without a height); else t->z_init. */
float cf_approach_offset_m(const cf_tuning *t, float z_m, float pad_z_m);

/* ---- the app's decisions ---------------------------------------------------- */

/* What the app remembers between steps; cleared by controllerOutOfTreeInit. */
typedef struct cf_session {
    fc_controller_command last_command; /* the command of the previous step */
    /* the setpoint flown (cf_setpoint_step): the last absolute one, moved by
     * velocity setpoints, following the vehicle while the commander levels out */
    float sp_x_m, sp_y_m;               /* world */
    float sp_yaw_rad;                   /* heading */
    float cmd_z_m, cmd_vz_mps, cmd_az_mps2; /* the commander's height and its derivatives */
    bool have_cmd_z;                    /* the commander gave a height since the command began */
    /* the approach of the tracked height (3.6), owned by the app so that every
     * switch to tracking starts from the vehicle's height */
    float approach_offset_m;            /* z_r_init: vehicle height - tracked height at the switch */
    float approach_decay;               /* e^(-t / tau_zr), t from the switch */
    bool approach_pending;              /* switched into tracking: the next cf_setpoint_step starts it */
    float pad_phase_rad;                /* of the virtual pad, in [-pi, pi] */
    /* the range finder (cf_range_step) */
    float range_last_mm;                /* the reading of the previous step */
    float range_m;                      /* the newest usable sample, from the CG, m (0: none yet) */
    bool range_fresh;                   /* range_m is new at this step */
} cf_session;

void cf_session_reset(cf_session *s);

/* Whether the commander delivers a setpoint: a position or thrust is asked for.
 * The supervisor replaces the setpoint by a null one (every mode disabled,
 * thrust 0) when the vehicle may not fly, and so does a stopped commander. */
bool cf_setpoint_live(const cf_sample *s);

/* The command for this step. Without a live setpoint (the supervisor does not
 * let the vehicle fly, or no commander runs): FC_COMMAND_DISARM, whatever the
 * parameters say. Else by the "mission" parameter:
 *   CF_MISSION_FOLLOW (0)  the "track" parameter's value as an
 *                          fc_controller_command (0 DISARM, 1 TRACK_PAD, 2 HOLD,
 *                          3 LAND); DISARM when it is out of range
 *   CF_MISSION_HOLD (1)    FC_COMMAND_HOLD (from LAND: the library aborts the descent)
 *   CF_MISSION_LAND (2)    FC_COMMAND_LAND
 *   anything else          FC_COMMAND_HOLD: an unknown mission never starts a
 *                          descent and never stops the motors in flight */
fc_controller_command cf_command(uint8_t mission, uint8_t track, const cf_sample *s);

/* The command of this step against the last one. From DISARM to another
 * command: the setpoint starts at the vehicle's position, heading and height,
 * the pad's phase at 0; returns true (a new start: the app takes a freshly
 * initialised controller). Into TRACK_PAD from any other command: the
 * approach restarts at the next cf_setpoint_step. Remembers command for
 * the next call. */
bool cf_session_begin(cf_session *ss, fc_controller_command command, const cf_sample *s, const cf_tuning *t);

/* The commander's setpoint of this step into the session, as the firmware's
 * controllers read its modes (stabilizer_types.h), dt_s after the last:
 *   x, y   modeAbs: that point; modeVelocity: the point moves at that velocity
 *          (world, or the body's heading frame when velocity_body, as the
 *          hover setpoint sends it), at most CF_VELOCITY_LEAD_MAX_M ahead of
 *          the vehicle; modeDisable (the supervisor's level-out, or no
 *          position at all): no horizontal target, the point follows the
 *          vehicle ahead of it by velocity kd / kp, so the loop asks for no
 *          acceleration (level)
 *   yaw    modeAbs: that heading; modeVelocity: turned at that rate (0 in the
 *          level-out: held); modeDisable: held
 *   z      modeAbs: that height, with the velocity and acceleration as
 *          feed-forward (the high-level commander's); modeVelocity: moved at
 *          that speed; modeDisable: held (the level-out keeps z as it is).
 *          After the first height of a command, the height moves at most
 *          CF_COMMAND_Z_SPEED_MAX_MPS toward the commanded one.
 * Then, on the first step of tracking, the approach from the vehicle's
 * height (cf_approach_offset_m over this step's pad): z_r starts where the
 * vehicle is. */
void cf_setpoint_step(cf_session *ss, const cf_sample *s, const cf_tuning *t, float dt_s);

/* The height the tracking holds z_bias above, without the approach: the
 * commander's height less z_bias (command_z, once it gave one) or padZ, with
 * the virtual pad's heave; and its derivatives. */
fc_vertical_trajectory cf_pad_trajectory(const cf_session *ss, const cf_tuning *t);
float cf_pad_height_m(const cf_session *ss, const cf_tuning *t);
/* What the library tracks in TRACK_PAD (its own approach offset is 0): the
 * pad above plus the app's approach offset, decaying at tau_zr. */
fc_vertical_trajectory cf_track_trajectory(const cf_session *ss, const cf_tuning *t);
/* The pad's phase and the approach's decay advanced by dt_s. */
void cf_pad_advance(cf_session *ss, const cf_tuning *t, float dt_s);

/* The range finder at this step (before cf_inputs_from_sample): a reading is a
 * new sample when it differs from the previous step's (the ranger updates
 * rangeDown at 40 Hz, the controller steps at 500 Hz, and the firmware keeps no
 * timestamp with it) and is usable: finite, in [0, CF_RANGE_MAX_MM). Then
 * ss->range_m = reading / 1000 + range_offset_m (negative: 0) and
 * ss->range_fresh; otherwise range_m keeps the last sample and range_fresh is
 * false. A ranger that stops (or a deck that is absent: 0 all along) gives no
 * fresh sample, which the landing mission sees as a lost range finder after
 * its range_timeout_s (0.3 s); a real reading repeated to the mm for that long
 * would look the same (a false abort, never a descent without the sensor). */
void cf_range_step(cf_session *ss, float range_mm, const cf_tuning *t);

/* The controller's inputs from the firmware's numbers: IMU in SI, the
 * quaternion reordered, position and velocity as they are (both z up), the x/y
 * setpoint and the heading of cf_setpoint_step, the tracked trajectory
 * (cf_track_trajectory), and the range finder of cf_range_step. */
void cf_inputs_from_sample(const cf_sample *s, const cf_session *ss, const cf_tuning *t,
                           fc_controller_command command, fc_controller_inputs *in);

/* ---- outputs ------------------------------------------------------------------ */

/* What goes into control_t in controlModeForceTorque. */
typedef struct cf_force_torque {
    float thrust_n;        /* body z, N, >= 0 */
    float torque_nm[3];    /* body x, y, z, N m */
} cf_force_torque;

/* The controller's body thrust and moments; zero while the motors are off (or
 * if a value were not finite). */
void cf_force_torque_from_outputs(const fc_controller_outputs *out, cf_force_torque *ft);

/* What the LOG group "fcssc" shows. */
typedef struct cf_telemetry {
    float sigma;           /* sigma (or sigma_hat), m/s */
    float sigma_tilde;     /* m/s */
    float rho;             /* modulation in use, N */
    float theta;           /* Theta, kg */
    float u0_av;           /* N */
    float u_nom;           /* N */
    float error;           /* e = z - z_r, m */
    float z_ref;           /* z_r, m */
    float vz_ref;          /* z_r', m/s */
    float pad_z;           /* z_d, m */
    float thrust;          /* body thrust command, N */
    float torque[3];       /* body moments, N m */
    uint16_t status;       /* fc_step_status bits of the last step */
    uint8_t command;       /* fc_controller_command in effect: 0 disarmed, 1 track, 2 hold, 3 land */
    uint8_t init_result;   /* fc_init_result of the last (re)initialisation */
    uint8_t saturation;    /* FC_SAT_* bits of the allocation */
    /* the landing mission */
    uint8_t landing_state;  /* fc_landing_state */
    uint8_t landing_reason; /* fc_landing_reason of the newest transition */
    uint8_t aborts;         /* aborts since the mission started */
    uint8_t touchdown_window; /* 1: the plan expects contact from now on */
    float pad_confidence;  /* of the pad's prediction, [0, 1] */
    float pad_est_z;       /* the pad's height as learnt from the range finder, m, world */
    float pad_est_vz;      /* its vertical speed, m/s */
    float pad_period;      /* the period of its dominant heave, s */
    float gear_height;     /* gear above the pad from the range finder (last sample), m */
    float range;           /* the range input: the newest sample from the CG, m */
    uint32_t step_cycles;  /* the last step's core cycles (DWT), 0 where not measured */
    uint32_t step_cycles_max; /* the most since the controller was selected */
} cf_telemetry;

/* The LOG fields from the step's outputs; pad_z_m is the virtual pad's height,
 * range_m the range input (cf_session.range_m). */
void cf_telemetry_from_outputs(const fc_controller_outputs *out, fc_step_status status,
                               fc_controller_command command, float pad_z_m, float range_m, cf_telemetry *tm);

#endif /* CF_CONVERT_H */
