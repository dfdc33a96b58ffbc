/*
 * sim.h - one simulated flight: the plant at its step, the sensors, and the
 * flight software at its fixed step through fc_controller_step (via the
 * backend's adapter), with the SPEC's metrics and an optional trace.
 *
 * Loop, for each controller step k (t_k = k dt):
 *   sensors -> fsw_inputs (the pad's true trajectory, setpoints, command)
 *   fsw step -> rotor speeds (held until the next step), telemetry
 *   metrics and trace at t_k
 *   plant: dt / h RK4 steps of h, the sensors sampling at every step's start
 */
#ifndef SIM_SIM_H
#define SIM_SIM_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "fsw_adapter.h"
#include "scenario.h"

/* A metric that does not apply to the run (not a landing, not adaptive, ...) is NaN. */
typedef struct sim_metrics {
    double rms_error_m;
    double max_abs_error_m;
    double mass_step_peak_error_m;
    double control_tv_per_s;
    double theta_rel_error;
    double min_clearance_m;
    double touchdown_rel_speed_mps;
    double touchdown_time_s;
    double bounces;
    double max_tilt_deg;
    double nan_outputs;
    /* landing runs: the angle between the vehicle's body z and the pad's
     * normal at the first contact (plant step), and whether that contact came
     * before the firmware's touchdown window opened (1) or not (0) */
    double touchdown_rel_tilt_deg;
    double early_contact;
    /* seconds in the error window (after the transient, to the first contact in
     * a landing) with the thrust at a limit: the altitude law's clamp or the
     * allocation's collective thrust saturated */
    double thrust_saturated_s;
    /* the failsafe (sim.c's failsafe_acc): NaN unless the firmware entered
     * FAILSAFE or the scenario injects an input loss (position-lost, imu-lost) */
    double failsafe_entered;                /* 1: landing_state became FAILSAFE, 0: never */
    double failsafe_motor_stops_airborne;   /* motors 1 -> 0, gear > 0.05 m up, DISARM not commanded */
    double failsafe_descent_rate_mps;       /* median true -vz (relative to the pad) in the descent window */
    double failsafe_descent_rate_rel_error; /* |rate - failsafe.descent_mps| / failsafe.descent_mps */
    double failsafe_touchdown_speed_mps;    /* |relative vz| at the first contact after FAILSAFE began (plant step) */
    double failsafe_time_to_motors_off_s;   /* from FAILSAFE's start to motors off */
    /* context */
    double theta_end_kg, theta_star_end_kg;
    double final_height_m;          /* gear above the pad at the end */
    double max_position_error_m;    /* largest horizontal distance from the setpoint over the run */
    double settled_position_error_m; /* the same after the transient (the error window's start) */
    double nonfinite_state_steps;   /* controller steps at which the plant's state was not finite */
} sim_metrics;

/* The metric names and their order (for JSON, tables, Monte-Carlo). */
#define SIM_METRIC_COUNT 20
#define SIM_METRIC_FAILSAFE_FIRST 14 /* failsafe_entered and after: the failsafe's */
extern const char *const sim_metric_names[SIM_METRIC_COUNT];
double sim_metric_value(const sim_metrics *m, int index);

/* Trace columns (one row per recorded controller step). */
#define SIM_TRACE_COLUMNS(X)                                                                                         \
    X(t_s) X(pad_z_m) X(pad_vz_mps) X(z_r_m) X(z_m) X(vz_mps) X(error_m) X(x_m) X(y_m) X(roll_deg) X(pitch_deg)   \
    X(yaw_deg) X(tilt_deg) X(thrust_cmd_n) X(vertical_force_n) X(u_nom_n) X(u0_av_n) X(rho_n) X(sigma_mps)        \
    X(sigma_tilde_mps) X(theta_kg) X(theta_star_kg) X(adaptation_term_mps2) X(ground_gain) X(mass_kg)             \
    X(gear_clearance_m) X(contact_force_n) X(rotor_thrust_n) X(fsw_z_r_m) X(u_mean) X(u_min) X(u_max)          \
    X(motors_on) X(status) X(landing_state) X(fsw_gear_height_m) X(fsw_pad_z_m) X(fsw_pad_vz_mps) X(pad_confidence) X(fsw_pad_period_s) \
    X(moment_x_nm) X(moment_y_nm) X(moment_z_nm) X(saturation) X(att_err_x_rad) X(att_err_y_rad) X(att_err_z_rad) \
    X(att_int_x_rad_s) X(att_int_y_rad_s) X(att_int_z_rad_s) X(pos_int_x_mps2) X(pos_int_y_mps2)             \
    X(fsw_vz_est_mps) X(fsw_hover_thrust_n) X(fsw_accel_bias_mps2) X(land_state) X(failsafe_cause) \
    X(yaw_r_deg) X(k_h) X(accel_fb_x_mps2) X(accel_fb_y_mps2) X(velocity_cmd_x_mps) X(velocity_cmd_y_mps) \
    X(velocity_cmd_z_mps) X(yaw_rate_cmd_radps) X(pad_roll_deg) X(pad_pitch_deg) X(descent_shaping_mps)

enum {
#define SIM_TRACE_ENUM(name) SIM_COL_##name,
    SIM_TRACE_COLUMNS(SIM_TRACE_ENUM)
#undef SIM_TRACE_ENUM
        SIM_TRACE_COLUMN_COUNT
};
extern const char *const sim_trace_column_names[SIM_TRACE_COLUMN_COUNT];

typedef struct sim_trace {
    size_t rows, capacity;
    int decimation;            /* one row every this many controller steps */
    double *data;              /* rows x SIM_TRACE_COLUMN_COUNT */
} sim_trace;

typedef struct sim_options {
    const fsw_backend *backend;
    int variant;
    bool want_trace;
    int trace_decimation;      /* 1: every controller step */
    void (*progress)(double fraction, void *user); /* NULL: none */
    void *progress_user;
} sim_options;

#define SIM_MAX_EVENTS 64

/* A transition of the landing mission (fc_landing_state / fc_landing_reason values). */
typedef struct sim_event {
    double t_s;
    int state, reason;
} sim_event;

extern const char *const sim_landing_state_names[FSW_LANDING_STATE_COUNT];
extern const char *const sim_landing_reason_names[FSW_LANDING_REASON_COUNT];

typedef struct sim_result {
    sim_metrics metrics;
    fsw_info info;
    double wall_s;             /* the run's wall-clock time */
    double cpu_s;              /* the process's CPU time over the run */
    /* the landing mission */
    int event_count;
    sim_event events[SIM_MAX_EVENTS];
    int final_landing_state, aborts;
    int descent_blocked_by;    /* at the end (OBSERVE: why no descent) */
    double touchdown_planned_s; /* the firmware's touchdown window opened (NaN: never) */
    long controller_steps, plant_steps;
    uint64_t seed;
} sim_result;

/* Runs sc with opt. false (err set) if the flight software could not be created. */
bool sim_run(const scenario *sc, const sim_options *opt, sim_result *res, sim_trace *trace, char *err,
             size_t err_len);

void sim_trace_free(sim_trace *t);

/* The reference (3.6) the metrics use: z_r(t) = z_d + bias + init e^(-(t - t0)/tau). */
double sim_reference(const fsw_info *info, double pad_z_m, double t_since_start_s);

#endif /* SIM_SIM_H */
