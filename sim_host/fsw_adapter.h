/*
 * fsw_adapter.h - the flight software as the simulator sees it: plain doubles
 * in, plain doubles out, one backend per function table.
 *
 * fsw_adapter.c is compiled twice, once with each numeric backend of the
 * firmware library (FC_NUMERIC_FIXED = 0 and 1), and each copy is partially
 * linked with its own build of the firmware sources into one object whose only
 * global symbol is its table, fsw_float_backend or fsw_fixed_backend (see
 * sim_host/CMakeLists.txt). The rest of the simulator includes no firmware
 * header and never sees an fc_real: what crosses this line is converted with
 * fc_from_float / fc_to_float in the adapter, so the same plant flies both
 * backends through the same entry point (fc_controller_init / _step).
 */
#ifndef SIM_FSW_ADAPTER_H
#define SIM_FSW_ADAPTER_H

#include <stddef.h>

#define FSW_MAX_ROTORS 8

/* The firmware's airframes (fc_airframe) and commands (fc_controller_command),
 * by value: the adapter checks that they agree with the firmware's enums. */
enum { FSW_AIRFRAME_CRAZYFLIE2 = 0, FSW_AIRFRAME_F450 = 1, FSW_AIRFRAME_HEXA_4KG = 2, FSW_AIRFRAME_COUNT = 3 };
enum { FSW_COMMAND_DISARM = 0, FSW_COMMAND_TRACK_PAD = 1, FSW_COMMAND_HOLD = 2, FSW_COMMAND_LAND = 3 };
/* fc_landing_state and fc_landing_reason, by value (names in sim.c). */
#define FSW_LANDING_STATE_COUNT 9
#define FSW_LANDING_REASON_COUNT 19
enum { FSW_LANDING_DESCEND = 3, FSW_LANDING_LANDED = 6, FSW_LANDING_ABORT = 7, FSW_LANDING_FAILSAFE = 8 };
/* fc_altitude_variant has FSW_VARIANT_COUNT values, named in sim_variants.c. */
#define FSW_VARIANT_COUNT 12
/* allocation_saturation's collective thrust bits (fc/status.h) */
#define FSW_SAT_THRUST_HIGH 0x40u
#define FSW_SAT_THRUST_LOW 0x80u

/* What the simulator chooses; a NaN override (or -1 for the ints) keeps the
 * firmware default of fc_controller_default_params. */
typedef struct fsw_config {
    int airframe;          /* FSW_AIRFRAME_* */
    int variant;           /* fc_altitude_variant value */
    double dt_s;           /* the controller's fixed step */
    int use_external_attitude; /* 1: the platform's attitude; 0: the firmware's filter; -1: default */
    /* overrides of the defaults (NaN: keep) */
    double mass_kg;        /* nominal mass: Theta0 and the mass bounds follow it */
    double ref_tau_s;      /* (3.6) tau_zr */
    double ref_offset_init_m; /* z_r_init */
    double ref_bias_m;     /* z_r_bias */
    double thrust_min_n, thrust_max_n; /* the altitude law's clamp */
    double ground_gain_max;
    double rho_n, gamma, tau_av_s, l0_per_s, a_m_per_s, kappa_m_per_kg;
    double actuator_lag_s; /* the altitude law's lag schedule (NaN: the default, 0) */
    /* factors on the variant's defaults (NaN: 1), e.g. to carry the 4 kg gains to a 27 g vehicle */
    double rho_scale, gamma_scale, kappa_m_scale;
    /* the tuning knobs, factors on the law's own gains (NaN: 1; fsw_adapter.c's
     * scale_law_gains says which): bandwidth the error dynamics', authority the force's */
    double bandwidth_scale, authority_scale;
    double horizontal_kp_per_s2, horizontal_kd_per_s, tilt_max_rad;
    /* k_a of the acceleration feedback (2.10); NaN: the preset's, 0: none */
    double accel_fb_gain_per_s;
    /* the pid law's gains (fc/altitude_control.h, "Baselines"); with both
     * integral gains 0 it is a PD with gravity feed-forward: the dissertation's
     * PD of section 4.5. */
    double pid_kp_z_per_s, pid_ki_z_per_s2, pid_kp_v_n_per_mps, pid_ki_v_n_per_m;
    /* the landing mission */
    double landing_gear_height_m; /* CG to the bottom of the gear, as the firmware knows it */
    double landing_touchdown_dip_m; /* how far below the surface the descent's reference ends */
    double landing_hold_height_m, landing_descent_tau_s, landing_pad_accel_max_mps2, landing_confidence_start;
    /* descent shaping (2.25)-(2.28) (fc/landing.h): 1 on, 0 off, -1 the default
     * (off); its gains k_r, delta_h, k_c, u_zbias, k_a, delta_a (NaN: default) */
    int descent_shaping;
    double shaping_k_r_m2ps, shaping_delta_h_m, shaping_k_c_per_s, shaping_u_zbias_mps, shaping_k_a_mps,
        shaping_delta_a_m, shaping_max_climb_mps, shaping_commit_m;
    /* the velocity output (fc/controller.h FC_OUTPUT_VELOCITY): 1 to fly it, with
     * the vehicle's identified first-order response k_P, a_P per axis (2.18) */
    int velocity_output;
    double velocity_k_p_per_s[3], velocity_a_p_per_s[3];
    /* processor in the loop (fsw_pil_backend): the ATmega image that runs the step */
    const char *target_image;
} fsw_config;

/* One step's inputs (world ENU, body FLU, SI units). */
typedef struct fsw_inputs {
    double gyro_radps[3];    /* body rate, as the gyro reads it */
    double accel_mps2[3];    /* specific force, body: level at rest (0, 0, +g) */
    double attitude_q[4];    /* w, x, y, z: body -> world (used with external attitude) */
    double heading_rad;      /* a measured yaw for the flight software's attitude filter */
    int heading_fresh;       /* a new heading sample this step */
    double position_m[3];
    double velocity_mps[3];
    double pad_z_m, pad_vz_mps, pad_az_mps2; /* the pad trajectory for TRACK_PAD */
    double range_m;          /* range finder, CG to the pad along body -z */
    int range_fresh;         /* a new range sample this step */
    double position_setpoint_m[3];
    double pad_attitude_q[4]; /* w, x, y, z: the pad's attitude, pad -> world (all 0: level) */
    double yaw_setpoint_rad;
    double yaw_rate_setpoint_radps; /* its rate, fed forward */
    int command;             /* FSW_COMMAND_* */
} fsw_inputs;

/* One step's outputs and telemetry. */
typedef struct fsw_outputs {
    double rotor_speed[FSW_MAX_ROTORS]; /* u = w / w_max, 0 with the motors off */
    int rotor_count;
    int motors_on;
    double thrust_n;         /* body thrust demanded */
    double moment_nm[3];
    int output_velocity;     /* 1: the velocity command below is the output (not the rotors) */
    double velocity_cmd_mps[3]; /* world */
    double yaw_rate_cmd_radps;
    unsigned status;         /* fc_step_status of the step */
    /* telemetry */
    double attitude_q[4], attitude_setpoint_q[4];
    double rate_radps[3];
    double z_r_m, vz_r_mps, az_r_mps2;
    double tilt_cos;
    double alt_thrust_n, vertical_force_n, error_m, sigma_mps, sigma_tilde_mps, rho_n, u0_av_n, u_nom_n,
        theta_kg, observer_bound_n;
    int clamped;
    unsigned allocation_saturation;
    unsigned estimator_status, altitude_status, attitude_status, allocation_status;
    /* the landing mission */
    int landing_state, landing_reason, landing_changed, touchdown_window, aborts, descent_blocked_by;
    double descent_shaping_mps; /* a shaped descent's v_zd (2.25) */
    double pad_est_z_m, pad_est_vz_mps, pad_confidence, pad_accel_bound_mps2, pad_period_s, gear_height_m;
    /* the safety logic: the vertical estimate, the land detector's stage, the
     * failsafe's cause and what refused arming (fc/controller.h) */
    double vz_est_mps, hover_thrust_n, accel_bias_mps2;
    int land_state, failsafe_cause, arming_blocked_by;
    /* loop internals, for traces: the attitude error (tilt x, y, heading z) and
     * its integral, the horizontal loop's integral (x, y) */
    double attitude_error_rad[3], attitude_integral_rad_s[3], position_integral_mps2[2], accel_feedback_mps2[2];
} fsw_outputs;

/* What the firmware was configured with (for reports and for the plant's
 * cross-checks): the parameters after the overrides. */
typedef struct fsw_info {
    double mass_kg, theta0_kg, theta_min_kg, theta_max_kg;
    double thrust_min_n, thrust_max_n, ground_gain_max;
    double ref_tau_s, ref_offset_init_m, ref_bias_m;
    double rho_n, gamma;
    double accel_fb_gain_per_s; /* k_a of the acceleration feedback (2.10) */
    double failsafe_descent_mps; /* failsafe.descent_mps: the descent the failsafe should hold */
    int alignment_steps;     /* disarmed steps the attitude filter needs before arming */
    int rotor_count;
    int velocity_output;     /* the firmware outputs velocity commands */
    size_t state_bytes;      /* sizeof(fc_controller) */
} fsw_info;

typedef struct fsw_backend {
    const char *name;        /* "float" or "fixed" */
    /* A controller for cfg, or NULL (err says why: the failing init result). */
    void *(*create)(const fsw_config *cfg, fsw_info *info, char *err, size_t err_len);
    void (*destroy)(void *ctl);
    void (*step)(void *ctl, const fsw_inputs *in, fsw_outputs *out);
} fsw_backend;

extern const fsw_backend fsw_float_backend;
extern const fsw_backend fsw_fixed_backend;
#if defined(FSW_HAVE_PIL) && FSW_HAVE_PIL
/* The fixed backend's step run by the ATmega image in simavr (pil_avr.h):
 * processor in the loop. Built when libsimavr is there (sim_host/CMakeLists.txt). */
extern const fsw_backend fsw_pil_backend;
#endif

/* A config with every override off. */
void fsw_config_defaults(fsw_config *cfg);

#endif /* SIM_FSW_ADAPTER_H */
