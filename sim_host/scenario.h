/*
 * scenario.h - a scenario file (INI, sim_host/scenarios/NAME.ini) turned into
 * the plant, sensors, flight-software configuration and mission of one run.
 *
 * The keys, their defaults and their ranges are the table in scenario.c; every
 * shipped scenario file documents them in its comments. An unknown section or
 * key, a value that does not parse or is out of range is an error
 * "FILE:LINE: key 'k' in [section]: reason" and nothing runs.
 */
#ifndef SIM_SCENARIO_H
#define SIM_SCENARIO_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "fsw_adapter.h"
#include "plant.h"
#include "sensors.h"

#define SCENARIO_NAME_MAX 64
#define SCENARIO_TEXT_MAX 256
#define SCENARIO_PATH_MAX 1024

typedef enum rotor_layout { LAYOUT_QUAD_X = 0, LAYOUT_HEXA_X, LAYOUT_CUSTOM } rotor_layout;

/* Monte-Carlo perturbations ([montecarlo]); each run draws from its own seed. */
typedef struct montecarlo_params {
    double mass_rel;              /* true mass x (1 + U(-a, a)) (the firmware's nominal stays) */
    double velocity_response_rel; /* a velocity-input vehicle's k_P and a_P, each axis, x (1 + U(-a, a)) (0: none) */
    double inertia_rel;
    double pad_amplitude_rel;     /* every pad amplitude x (1 + U(-a, a)) */
    double pad_period_rel;        /* every pad period x (1 + U(-a, a)) */
    double noise_scale_min, noise_scale_max; /* sensor noise x U(min, max) */
    int delay_steps_max;          /* position/altitude delay + U{0..n} controller steps */
    double motor_tau_rel;         /* every motor lag x (1 + U(-a, a)) */
    double rotor_efficiency_min;  /* one random rotor's efficiency x U(min, 1) */
    double initial_offset_m;      /* initial x, y + U(-a, a) */
    double ground_effect_rho_rel; /* rho of (3.2) x (1 + U(-a, a)) */
    /* landing families: absolute ranges (NaN: not used) */
    double pad_amplitude_min_m, pad_amplitude_max_m; /* peak to peak of the whole heave, U(min, max) */
    double pad_period_min_s, pad_period_max_s;       /* a sine's period, or each wave's, U(min, max) */
    double gust_std_max_mps;                         /* gust std U(0, max) (NaN: as the file) */
    double rotor_efficiency_max;  /* the weak rotor's factor is U(rotor_efficiency_min, this); 1 by default */
    /* a payload step: at U(mass_step_time_min_s, mass_step_time_max_s) the mass
     * prevailing then (after the other perturbations) steps by x (1 + U(-a, a)),
     * through the plant's mass filter (4.84); a = mass_step_rel, 0: none */
    double mass_step_rel;
    double mass_step_time_min_s, mass_step_time_max_s;
    /* the heaviest the drawn masses may be, x (1 + a) the file's mass (NaN: no
     * bound): caps the upper ends of the mass draw and of the payload step's
     * (the draws stay uniform on the shortened ranges; the number of draws,
     * and so every other perturbation of a seed, is unchanged) */
    double mass_max_rel;
    /* a run has diverged when, after the transient, |z - z_r| exceeds
     * diverged_error_m, or at any time the horizontal distance from the
     * setpoint exceeds diverged_position_m or the tilt diverged_tilt_deg, or an
     * output or the plant's state is not finite (sim_divergence) */
    double diverged_error_m;
    double diverged_position_m;
    double diverged_tilt_deg;
    /* the failsafe family (drawn last, each only when set) */
    double accel_bias_max_mps2;   /* the accelerometer's body-z bias + U(-a, a) (0: none) */
    double fault_height_min_m, fault_height_max_m; /* gear height of the hover the fault hits, U(min, max) (NaN: the file's) */
    double range_finder_probability; /* the run has the range finder with this probability (NaN: the file's) */
} montecarlo_params;

typedef enum mission_command { MISSION_TRACK = 0, MISSION_LAND } mission_command;

/* A fault injected at start_s, or in a landing run without start_s timed from
 * the first DESCEND the firmware reports (so that each abort cause is
 * exercised deterministically). */
typedef enum fault_kind {
    FAULT_NONE = 0,
    FAULT_HOLD_COMMAND,   /* the operator commands HOLD (abort) */
    FAULT_RANGE_DROPOUT,  /* the range finder goes quiet for duration_s */
    FAULT_GUST,           /* wind of `vector` m/s (world) for duration_s */
    FAULT_TORQUE,         /* a body moment of `vector` N m for duration_s */
    FAULT_PAD_AMPLITUDE,  /* the pad's heave grows by the factor `scale` from then on */
    FAULT_PAD_PERIOD,     /* the pad's frequencies jump by the factor `scale` (motion continuous) */
    FAULT_POSITION_LOST,  /* position and velocity inputs NaN for duration_s (the range finder keeps delivering) */
    FAULT_IMU_LOST        /* gyro and accelerometer inputs NaN for duration_s */
} fault_kind;

typedef struct fault_params {
    fault_kind kind;
    double start_s;               /* from the run's start (NaN: delay_s after the first DESCEND) */
    double delay_s;
    double duration_s;            /* INFINITY: to the end of the run */
    double scale;
    v3 vector;
} fault_params;

/* Whether the firmware gets the range finder's samples (range_m, range_fresh). */
typedef enum range_finder_mode {
    RANGE_FINDER_AUTO = 0, /* in landing missions (command = land) only */
    RANGE_FINDER_ON,       /* in every mission ([altitude_sensor] source = range) */
    RANGE_FINDER_OFF       /* never: range_fresh 0, range_m NaN */
} range_finder_mode;

/* Wind: a mean plus horizontal gusts, first-order Gauss-Markov per axis. */
typedef struct wind_params {
    v3 mean_mps;
    double gust_std_mps;
    double gust_tau_s;
} wind_params;

typedef struct mission_params {
    mission_command command;      /* track: FC_COMMAND_TRACK_PAD (the pad given); land: FC_COMMAND_LAND (range finder) */
    double track_start_s;         /* the command from here (DISARM before) */
    bool landing;                 /* a landing scenario: touchdown metrics are reported */
    bool disarm_on_contact;       /* the stand-in for the landing mission: cut the motors after touchdown */
    double disarm_delay_s;
    double touchdown_planned_s;   /* min_clearance_m is taken before this time (NaN: before first contact) */
    double end_after_landed_s;    /* a landing run ends this long after LANDED (motors off); NaN: runs its duration */
    double end_after_motors_off_s; /* any run ends this long after the firmware stopped its motors while armed (NaN: no) */
    double setpoint_x_m, setpoint_y_m, setpoint_yaw_rad;
    /* the heading reference of Figure 4.4: psi_r(t) = setpoint_yaw_rad +
     * yaw_amplitude_rad sin(2 pi yaw_frequency_hz (t - track_start_s)) from the
     * command's start (0 amplitude: a constant heading) */
    double yaw_amplitude_rad, yaw_frequency_hz;
} mission_params;

typedef struct initial_params {
    double x_m, y_m;
    double height_m;              /* CG above the pad at t = 0; NaN: at the reference z_r(0) */
    double yaw_rad;
    double roll_rad, pitch_rad;
    v3 velocity_mps;
    bool motors_hover;            /* rotors spinning at hover speed at t = 0 (else stopped) */
} initial_params;

typedef struct metric_params {
    double transient_s;           /* NaN: 5 tau_zr + 5 s (SPEC) */
    double mass_step_window_s;    /* 10 s (SPEC) */
    double bounce_height_m;       /* a rise of the gear above this between contacts counts as a bounce */
    bool error_until_contact;     /* the error window ends at the first contact (landing runs) */
} metric_params;

/* The dissertation's figure a scenario reproduces ([scenario] figure), drawn
 * by --plot from its PD and SSC runs (output.c). */
typedef enum scenario_figure {
    FIGURE_NONE = 0,
    FIGURE_4_4, /* F450: heading tracking, altitude over the ground, F_z k_h */
    FIGURE_4_5, /* Crazyflie: descent into ground effect */
    FIGURE_4_6, /* Crazyflie: tracking z_r */
    FIGURE_4_7, /* Crazyflie: landing on an oscillating platform */
    FIGURE_ACCEL_FEEDBACK /* not the dissertation's: each run flown with and
                           * without the acceleration feedback (main.c), side by side */
} scenario_figure;

typedef struct scenario {
    char name[SCENARIO_NAME_MAX];
    char description[SCENARIO_TEXT_MAX];
    char path[SCENARIO_PATH_MAX];
    double duration_s;
    double plant_rate_hz;
    uint64_t seed;
    scenario_figure figure;       /* [scenario] figure */
    /* flight software */
    fsw_config fsw;               /* variant: the scenario's default controller */
    double controller_rate_hz;
    /* plant, as built from [vehicle], [rotor.N], [mass], [ground_effect], [gear], [contact], [pad] */
    plant_params plant;
    rotor_layout layout;
    sensor_params sensors;
    range_finder_mode range_finder;
    mission_params mission;
    initial_params initial;
    metric_params metrics;
    montecarlo_params montecarlo;
    wind_params wind;
    fault_params fault;
    /* the command line's --set overrides it was loaded with (argv's strings) */
    const char *const *overrides;
    int override_count;
} scenario;

#define SCENARIO_OVERRIDES_MAX 32

/* Loads and validates a scenario, with override_count overrides
 * "section.key=value" (fc-sil --set) applied after the file, each replacing
 * the file's value. On error returns false with err holding
 * "FILE:LINE: key 'k' in [section]: reason" (or "FILE: reason"; an
 * override's error names it: "--set 'section.key=value': ..."). */
bool scenario_load(const char *path, const char *const *overrides, int override_count, scenario *sc, char *err,
                   size_t err_len);

/* Resolves NAME or FILE: a string with a '/' or ending in .ini is a path,
 * anything else is sim_host/scenarios/NAME.ini (next to the binary's
 * scenarios dir first, then the source tree's). Returns false if not found. */
bool scenario_resolve(const char *name_or_path, const char *argv0, char *path, size_t path_len);

/* Lists the shipped scenario names on out (one a line). */
void scenario_list(const char *argv0, void (*emit)(const char *name, void *user), void *user);

/* psi_r at time t (rad): the mission's heading reference, and its rate (rad/s). */
double scenario_yaw_setpoint_rad(const mission_params *m, double t_s);
double scenario_yaw_rate_setpoint_radps(const mission_params *m, double t_s);

/* Applies the Monte-Carlo perturbations of sc->montecarlo drawn from seed. */
void scenario_perturb(scenario *sc, uint64_t seed);

/* The variants, in fc_altitude_variant order. */
extern const char *const sim_variant_names[FSW_VARIANT_COUNT];
int sim_variant_from_name(const char *name); /* -1 if unknown */
bool sim_variant_is_adaptive(int variant);

#endif /* SIM_SCENARIO_H */
