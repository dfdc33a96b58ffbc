/*
 * scenario.c - scenario files: the table of every section and key, parsing
 * with libinih (line numbers from a counting reader), validation, and the
 * construction of the plant, sensors and flight-software configuration.
 */
#include "scenario.h"

#include <ctype.h>
#include <dirent.h>
#include <errno.h>
#include <ini.h>
#include <limits.h>
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "rng.h"

#ifndef SIM_SCENARIO_DIR
#define SIM_SCENARIO_DIR "scenarios"
#endif

#define PI 3.14159265358979323846
#define DEG (PI / 180.0)
#define LIST_MAX 8

/* ---------------------------------------------------------------------- */
/* variant names (fc_altitude_variant order)                               */
/* ---------------------------------------------------------------------- */

const char *const sim_variant_names[FSW_VARIANT_COUNT] = {
    "ssc",          "ssc-adaptive",      "ssc-norm",      "ssc-norm-adaptive", "ssc-extra",    "ssc-rel2",
    "ssc-rel2-adaptive", "ssc-rel2-norm", "pid",           "smc",               "smc-boundary", "super-twisting",
};

int sim_variant_from_name(const char *name)
{
    for (int i = 0; i < FSW_VARIANT_COUNT; i++) {
        if (strcmp(name, sim_variant_names[i]) == 0) {
            return i;
        }
    }
    return -1;
}

bool sim_variant_is_adaptive(int variant)
{
    return variant >= 0 && variant < FSW_VARIANT_COUNT && strstr(sim_variant_names[variant], "adaptive") != NULL;
}

void fsw_config_defaults(fsw_config *c)
{
    c->airframe = FSW_AIRFRAME_HEXA_4KG;
    c->variant = 0;
    c->dt_s = 0.002;
    c->use_external_attitude = -1;
    c->mass_kg = c->ref_tau_s = c->ref_offset_init_m = c->ref_bias_m = (double)NAN;
    c->thrust_min_n = c->thrust_max_n = c->ground_gain_max = (double)NAN;
    c->actuator_lag_s = (double)NAN;
    c->rho_n = c->gamma = c->tau_av_s = c->l0_per_s = c->a_m_per_s = c->kappa_m_per_kg = (double)NAN;
    c->rho_scale = c->gamma_scale = c->kappa_m_scale = c->bandwidth_scale = c->authority_scale = (double)NAN;
    c->horizontal_kp_per_s2 = c->horizontal_kd_per_s = c->tilt_max_rad = (double)NAN;
    c->accel_fb_gain_per_s = (double)NAN;
    c->pid_kp_z_per_s = c->pid_ki_z_per_s2 = c->pid_kp_v_n_per_mps = c->pid_ki_v_n_per_m = (double)NAN;
    c->velocity_output = 0;
    c->landing_gear_height_m = c->landing_touchdown_dip_m = (double)NAN;
    c->descent_shaping = -1;
    c->shaping_k_r_m2ps = c->shaping_delta_h_m = c->shaping_k_c_per_s = (double)NAN;
    c->shaping_u_zbias_mps = c->shaping_k_a_mps = c->shaping_delta_a_m = c->shaping_max_climb_mps = c->shaping_commit_m = (double)NAN;
    for (int i = 0; i < 3; i++) {
        c->velocity_k_p_per_s[i] = c->velocity_a_p_per_s[i] = 1.0;
    }
    c->target_image = NULL;
}

/* ---------------------------------------------------------------------- */
/* the file as written: one field per key                                  */
/* ---------------------------------------------------------------------- */

typedef struct raw_rotor {
    v3 position_m, axis;
    double spin, thrust_max_n, torque_ratio_m, thrust_exponent, torque_exponent, speed_min, motor_tau_s, efficiency;
} raw_rotor;

typedef struct raw_list {
    int count;
    double v[LIST_MAX];
} raw_list;

typedef struct raw {
    /* [scenario] */
    char name[SCENARIO_NAME_MAX], description[SCENARIO_TEXT_MAX];
    double duration_s, plant_rate_hz, seed;
    /* [controller] */
    int airframe, variant, attitude_external;
    double rate_hz, nominal_mass_kg, z_r_tau_s, z_r_init_m, z_r_bias_m, thrust_min_n, thrust_max_n, ground_gain_max,
        rho_n, gamma, tau_av_s, l0_per_s, a_m_per_s, kappa_m_per_kg, hkp, hkd, tilt_max_deg, rho_scale, gamma_scale,
        kappa_m_scale, bandwidth_scale, authority_scale, actuator_lag_s, pid_kp_z, pid_ki_z, pid_kp_v, pid_ki_v, accel_fb_gain;
    int figure;
    int output_velocity;
    v3 fsw_k_p, fsw_a_p;
    /* [vehicle] */
    double mass_kg, gravity_mps2, drag, rotor_count, arm_m, rotor_z_m, thrust_max_n_rotor, torque_ratio_m,
        thrust_exponent, torque_exponent, speed_min, motor_tau_s, first_spin;
    v3 inertia, inertia_per_kg;
    int layout;
    int input_velocity;
    v3 plant_k_p, plant_a_p;
    double velocity_tilt_max_deg;
    /* [rotor.N] */
    raw_rotor rotor[PLANT_MAX_ROTORS];
    /* [mass] */
    double mass_tau_s;
    raw_list step_times, step_masses;
    /* [ground_effect] */
    int ge_enabled;
    double ge_radius, ge_rho;
    /* [gear] */
    double gear_height, feet, foot_radius, first_foot_deg;
    /* [contact] */
    int contact_enabled;
    double stiffness, damping_ratio, friction, slip_speed;
    /* [pad] */
    int pad_model;
    double pad_base, pad_amplitude, pad_period;
    raw_list wave_amplitudes, wave_periods, wave_phases_deg;
    double roll_amplitude_deg, roll_period_s, roll_phase_deg, pitch_amplitude_deg, pitch_period_s, pitch_phase_deg;
    /* [landing] */
    int descent_shaping; /* -1: the firmware's default */
    double shaping_k_r, shaping_delta_h, shaping_k_c, shaping_u_zbias, shaping_k_a, shaping_delta_a, shaping_max_climb,
        shaping_commit;
    /* [initial] */
    double init_x, init_y, init_height, init_yaw_deg, init_roll_deg, init_pitch_deg;
    v3 init_velocity;
    int init_motors_hover;
    /* [mission] */
    int mission_command;
    /* [wind], [fault] */
    wind_params wind;
    int fault_kind;
    double fault_start_s, fault_delay_s, fault_duration_s, fault_scale;
    v3 fault_vector;
    /* landing overrides */
    double land_hold_m, land_tau_s, land_accel_max, land_conf_start, land_gear_m, land_dip_m;
    double track_start_s, disarm_delay_s, touchdown_planned_s, end_after_landed_s, end_after_motors_off_s, sp_x, sp_y,
        sp_yaw_deg, yaw_amplitude_deg, yaw_frequency_hz;
    int landing, disarm_on_contact;
    /* sensors */
    imu_params imu;
    position_params position;
    altitude_params altitude;
    int range_finder;
    attitude_sensor_params attitude;
    int heading_enabled;
    heading_sensor_params heading;
    double noise_scale;
    /* [metrics] */
    metric_params metrics;
    int error_until_contact; /* -1: as [mission] landing */
    /* [montecarlo] */
    montecarlo_params mc;
    double mc_delay_steps_max;
} raw;

typedef enum key_kind { K_DOUBLE, K_INT, K_BOOL, K_ENUM, K_VEC3, K_LIST, K_STRING, K_STRING_LONG } key_kind;

static const char *const airframe_names[] = {"crazyflie2", "f450", "hexa-4kg", NULL};
static const char *const attitude_names[] = {"estimator", "external", NULL};
static const char *const layout_names[] = {"quad-x", "hexa-x", "custom", NULL};
static const char *const output_names[] = {"rotors", "velocity", NULL};
static const char *const pad_names[] = {"still", "sine", "waves", NULL};
static const char *const motors_names[] = {"off", "hover", NULL};
static const char *const altitude_names[] = {"position", "absolute", "range", NULL};
static const char *const command_names[] = {"track", "land", NULL};
static const char *const fault_names[] = {"none",       "hold-command",  "range-dropout", "gust",
                                          "torque",     "pad-amplitude", "pad-period",    "position-lost",
                                          "imu-lost",   NULL};
static const char *const range_finder_names[] = {"auto", "on", "off", NULL};
static const char *const figure_names[] = {"none", "4.4", "4.5", "4.6", "4.7", "accel-feedback", NULL};
static const char *variant_names_z[FSW_VARIANT_COUNT + 1];

#define OPEN_LO 1  /* the lower bound is excluded */
#define OPTIONAL 2 /* NaN default: "not set" is meaningful */

typedef struct key_def {
    const char *section; /* "rotor" for [rotor.N] */
    const char *key;
    key_kind kind;
    size_t offset;       /* in raw (rotor keys: in raw_rotor) */
    double lo, hi;
    const char *const *names; /* K_ENUM */
    int flags;
} key_def;

#define R(f) offsetof(raw, f)
#define RR(f) offsetof(raw_rotor, f)
#define BIG 1e9

static const key_def keys[] = {
    {"scenario", "name", K_STRING, R(name), 0, 0, NULL, 0},
    {"scenario", "description", K_STRING_LONG, R(description), 0, 0, NULL, 0},
    {"scenario", "duration_s", K_DOUBLE, R(duration_s), 0.0, 36000.0, NULL, OPEN_LO},
    {"scenario", "plant_rate_hz", K_DOUBLE, R(plant_rate_hz), 100.0, 200000.0, NULL, 0},
    {"scenario", "seed", K_INT, R(seed), 0.0, 4294967295.0, NULL, 0},
    {"scenario", "figure", K_ENUM, R(figure), 0, 0, figure_names, 0},

    {"controller", "airframe", K_ENUM, R(airframe), 0, 0, airframe_names, 0},
    {"controller", "variant", K_ENUM, R(variant), 0, 0, variant_names_z, 0},
    {"controller", "rate_hz", K_DOUBLE, R(rate_hz), 10.0, 20000.0, NULL, 0},
    {"controller", "attitude", K_ENUM, R(attitude_external), 0, 0, attitude_names, 0},
    {"controller", "nominal_mass_kg", K_DOUBLE, R(nominal_mass_kg), 0.0, 100.0, NULL, OPEN_LO | OPTIONAL},
    {"controller", "z_r_tau_s", K_DOUBLE, R(z_r_tau_s), 0.0, 1000.0, NULL, OPEN_LO | OPTIONAL},
    {"controller", "z_r_init_m", K_DOUBLE, R(z_r_init_m), -100.0, 100.0, NULL, OPTIONAL},
    {"controller", "z_r_bias_m", K_DOUBLE, R(z_r_bias_m), -100.0, 100.0, NULL, OPTIONAL},
    {"controller", "thrust_min_n", K_DOUBLE, R(thrust_min_n), 0.0, 2000.0, NULL, OPTIONAL},
    {"controller", "thrust_max_n", K_DOUBLE, R(thrust_max_n), 0.0, 2000.0, NULL, OPEN_LO | OPTIONAL},
    {"controller", "ground_gain_max", K_DOUBLE, R(ground_gain_max), 1.0, 10.0, NULL, OPTIONAL},
    {"controller", "rho_n", K_DOUBLE, R(rho_n), 0.0, 2000.0, NULL, OPTIONAL},
    {"controller", "gamma", K_DOUBLE, R(gamma), 0.0, 10000.0, NULL, OPTIONAL},
    {"controller", "actuator_lag_s", K_DOUBLE, R(actuator_lag_s), 0.0, 1.0, NULL, OPTIONAL},
    {"controller", "tau_av_s", K_DOUBLE, R(tau_av_s), 0.0, 1.0, NULL, OPEN_LO | OPTIONAL},
    {"controller", "l0_per_s", K_DOUBLE, R(l0_per_s), 0.0, 1000.0, NULL, OPEN_LO | OPTIONAL},
    {"controller", "a_m_per_s", K_DOUBLE, R(a_m_per_s), 0.0, 1000.0, NULL, OPEN_LO | OPTIONAL},
    {"controller", "kappa_m_per_kg", K_DOUBLE, R(kappa_m_per_kg), 0.0, 1000.0, NULL, OPEN_LO | OPTIONAL},
    {"controller", "rho_scale", K_DOUBLE, R(rho_scale), 0.0, 1000.0, NULL, OPEN_LO | OPTIONAL},
    {"controller", "gamma_scale", K_DOUBLE, R(gamma_scale), 0.0, 1000.0, NULL, OPEN_LO | OPTIONAL},
    {"controller", "kappa_m_scale", K_DOUBLE, R(kappa_m_scale), 0.0, 1000.0, NULL, OPEN_LO | OPTIONAL},
    {"controller", "bandwidth_scale", K_DOUBLE, R(bandwidth_scale), 0.0, 1000.0, NULL, OPEN_LO | OPTIONAL},
    {"controller", "authority_scale", K_DOUBLE, R(authority_scale), 0.0, 1000.0, NULL, OPEN_LO | OPTIONAL},
    {"controller", "horizontal_kp_per_s2", K_DOUBLE, R(hkp), 0.0, 1000.0, NULL, OPTIONAL},
    {"controller", "horizontal_kd_per_s", K_DOUBLE, R(hkd), 0.0, 1000.0, NULL, OPTIONAL},
    {"controller", "tilt_max_deg", K_DOUBLE, R(tilt_max_deg), 0.0, 68.0, NULL, OPEN_LO | OPTIONAL},
    {"controller", "accel_fb_gain_per_s", K_DOUBLE, R(accel_fb_gain), 0.0, 10.0, NULL, OPTIONAL},
    {"controller", "pid_kp_z_per_s", K_DOUBLE, R(pid_kp_z), 0.0, 1000.0, NULL, OPTIONAL},
    {"controller", "pid_ki_z_per_s2", K_DOUBLE, R(pid_ki_z), 0.0, 1000.0, NULL, OPTIONAL},
    {"controller", "pid_kp_v_n_per_mps", K_DOUBLE, R(pid_kp_v), 0.0, 1000.0, NULL, OPTIONAL},
    {"controller", "pid_ki_v_n_per_m", K_DOUBLE, R(pid_ki_v), 0.0, 1000.0, NULL, OPTIONAL},

    {"controller", "output", K_ENUM, R(output_velocity), 0, 0, output_names, 0},
    {"controller", "velocity_k_p_per_s", K_VEC3, R(fsw_k_p), 0.01, 100.0, NULL, 0},
    {"controller", "velocity_a_p_per_s", K_VEC3, R(fsw_a_p), 0.0, 100.0, NULL, 0},
    {"vehicle", "input", K_ENUM, R(input_velocity), 0, 0, output_names, 0},
    {"vehicle", "velocity_k_p_per_s", K_VEC3, R(plant_k_p), 0.0, 100.0, NULL, OPEN_LO},
    {"vehicle", "velocity_a_p_per_s", K_VEC3, R(plant_a_p), 0.0, 100.0, NULL, 0},
    {"vehicle", "velocity_tilt_max_deg", K_DOUBLE, R(velocity_tilt_max_deg), 0.0, 80.0, NULL, OPEN_LO},
    {"vehicle", "mass_kg", K_DOUBLE, R(mass_kg), 0.0, 1000.0, NULL, OPEN_LO},
    {"vehicle", "inertia_kgm2", K_VEC3, R(inertia), 0.0, 1000.0, NULL, OPEN_LO},
    {"vehicle", "inertia_per_kg_m2", K_VEC3, R(inertia_per_kg), -100.0, 100.0, NULL, 0},
    {"vehicle", "gravity_mps2", K_DOUBLE, R(gravity_mps2), 0.0, 100.0, NULL, OPEN_LO},
    {"vehicle", "drag_n_per_mps", K_DOUBLE, R(drag), 0.0, 1000.0, NULL, 0},
    {"vehicle", "layout", K_ENUM, R(layout), 0, 0, layout_names, 0},
    {"vehicle", "rotor_count", K_INT, R(rotor_count), 1.0, PLANT_MAX_ROTORS, NULL, 0},
    {"vehicle", "arm_m", K_DOUBLE, R(arm_m), 0.0, 16.0, NULL, OPEN_LO},
    {"vehicle", "rotor_z_m", K_DOUBLE, R(rotor_z_m), -5.0, 5.0, NULL, 0},
    {"vehicle", "thrust_max_n", K_DOUBLE, R(thrust_max_n_rotor), 0.0, 1000.0, NULL, OPEN_LO},
    {"vehicle", "torque_ratio_m", K_DOUBLE, R(torque_ratio_m), 0.0, 1.0, NULL, 0},
    {"vehicle", "thrust_exponent", K_DOUBLE, R(thrust_exponent), 0.5, 4.0, NULL, 0},
    {"vehicle", "torque_exponent", K_DOUBLE, R(torque_exponent), 0.5, 4.0, NULL, 0},
    {"vehicle", "speed_min", K_DOUBLE, R(speed_min), 0.0, 0.99, NULL, 0},
    {"vehicle", "motor_tau_s", K_DOUBLE, R(motor_tau_s), 0.0, 2.0, NULL, 0},
    {"vehicle", "first_spin", K_DOUBLE, R(first_spin), -1.0, 1.0, NULL, 0},

    {"rotor", "position_m", K_VEC3, RR(position_m), -16.0, 16.0, NULL, 0},
    {"rotor", "axis", K_VEC3, RR(axis), -1.0, 1.0, NULL, 0},
    {"rotor", "spin", K_DOUBLE, RR(spin), -1.0, 1.0, NULL, 0},
    {"rotor", "thrust_max_n", K_DOUBLE, RR(thrust_max_n), 0.0, 1000.0, NULL, OPEN_LO},
    {"rotor", "torque_ratio_m", K_DOUBLE, RR(torque_ratio_m), 0.0, 1.0, NULL, 0},
    {"rotor", "thrust_exponent", K_DOUBLE, RR(thrust_exponent), 0.5, 4.0, NULL, 0},
    {"rotor", "torque_exponent", K_DOUBLE, RR(torque_exponent), 0.5, 4.0, NULL, 0},
    {"rotor", "speed_min", K_DOUBLE, RR(speed_min), 0.0, 0.99, NULL, 0},
    {"rotor", "motor_tau_s", K_DOUBLE, RR(motor_tau_s), 0.0, 2.0, NULL, 0},
    {"rotor", "efficiency", K_DOUBLE, RR(efficiency), 0.0, 2.0, NULL, 0},

    {"mass", "filter_tau_s", K_DOUBLE, R(mass_tau_s), 0.0, 10.0, NULL, OPEN_LO},
    {"mass", "step_times_s", K_LIST, R(step_times), 0.0, 36000.0, NULL, 0},
    {"mass", "step_masses_kg", K_LIST, R(step_masses), 0.0, 1000.0, NULL, OPEN_LO},

    {"ground_effect", "enabled", K_BOOL, R(ge_enabled), 0, 0, NULL, 0},
    {"ground_effect", "rotor_radius_m", K_DOUBLE, R(ge_radius), 0.0, 10.0, NULL, OPEN_LO},
    {"ground_effect", "rho", K_DOUBLE, R(ge_rho), 0.0, 100.0, NULL, 0},

    {"gear", "height_m", K_DOUBLE, R(gear_height), 0.0, 10.0, NULL, OPEN_LO},
    {"gear", "feet", K_INT, R(feet), 1.0, PLANT_MAX_FEET, NULL, 0},
    {"gear", "foot_radius_m", K_DOUBLE, R(foot_radius), 0.0, 10.0, NULL, 0},
    {"gear", "first_foot_deg", K_DOUBLE, R(first_foot_deg), -360.0, 360.0, NULL, 0},

    {"contact", "enabled", K_BOOL, R(contact_enabled), 0, 0, NULL, 0},
    {"contact", "stiffness_n_per_m", K_DOUBLE, R(stiffness), 0.0, 1e8, NULL, OPEN_LO},
    {"contact", "damping_ratio", K_DOUBLE, R(damping_ratio), 0.0, 10.0, NULL, 0},
    {"contact", "friction", K_DOUBLE, R(friction), 0.0, 10.0, NULL, 0},
    {"contact", "slip_speed_mps", K_DOUBLE, R(slip_speed), 0.0, 10.0, NULL, OPEN_LO},

    {"pad", "model", K_ENUM, R(pad_model), 0, 0, pad_names, 0},
    {"pad", "base_m", K_DOUBLE, R(pad_base), -1000.0, 1000.0, NULL, 0},
    {"pad", "amplitude_m", K_DOUBLE, R(pad_amplitude), 0.0, 100.0, NULL, 0},
    {"pad", "period_s", K_DOUBLE, R(pad_period), 0.0, 10000.0, NULL, OPEN_LO},
    {"pad", "wave_amplitudes_m", K_LIST, R(wave_amplitudes), 0.0, 100.0, NULL, 0},
    {"pad", "wave_periods_s", K_LIST, R(wave_periods), 0.0, 10000.0, NULL, OPEN_LO},
    {"pad", "wave_phases_deg", K_LIST, R(wave_phases_deg), -360.0, 360.0, NULL, 0},
    {"pad", "roll_amplitude_deg", K_DOUBLE, R(roll_amplitude_deg), 0.0, 45.0, NULL, 0},
    {"pad", "roll_period_s", K_DOUBLE, R(roll_period_s), 0.0, 10000.0, NULL, OPEN_LO},
    {"pad", "roll_phase_deg", K_DOUBLE, R(roll_phase_deg), -360.0, 360.0, NULL, 0},
    {"pad", "pitch_amplitude_deg", K_DOUBLE, R(pitch_amplitude_deg), 0.0, 45.0, NULL, 0},
    {"pad", "pitch_period_s", K_DOUBLE, R(pitch_period_s), 0.0, 10000.0, NULL, OPEN_LO},
    {"pad", "pitch_phase_deg", K_DOUBLE, R(pitch_phase_deg), -360.0, 360.0, NULL, 0},

    {"landing", "descent_shaping", K_BOOL, R(descent_shaping), 0, 0, NULL, 0},
    {"landing", "k_r_m2ps", K_DOUBLE, R(shaping_k_r), 0.0, 100.0, NULL, OPTIONAL},
    {"landing", "delta_h_m", K_DOUBLE, R(shaping_delta_h), 0.01, 100.0, NULL, OPTIONAL},
    {"landing", "k_c_per_s", K_DOUBLE, R(shaping_k_c), 0.0, 100.0, NULL, OPTIONAL},
    {"landing", "u_zbias_mps", K_DOUBLE, R(shaping_u_zbias), -50.0, 50.0, NULL, OPTIONAL},
    {"landing", "k_a_mps", K_DOUBLE, R(shaping_k_a), 0.0, 100.0, NULL, OPTIONAL},
    {"landing", "delta_a_m", K_DOUBLE, R(shaping_delta_a), 0.01, 100.0, NULL, OPTIONAL},
    {"landing", "max_climb_mps", K_DOUBLE, R(shaping_max_climb), 0.001, 50.0, NULL, OPTIONAL},
    {"landing", "commit_m", K_DOUBLE, R(shaping_commit), 0.0, 1.0, NULL, OPTIONAL},

    {"initial", "x_m", K_DOUBLE, R(init_x), -1000.0, 1000.0, NULL, 0},
    {"initial", "y_m", K_DOUBLE, R(init_y), -1000.0, 1000.0, NULL, 0},
    {"initial", "height_m", K_DOUBLE, R(init_height), -10.0, 1000.0, NULL, OPTIONAL},
    {"initial", "yaw_deg", K_DOUBLE, R(init_yaw_deg), -180.0, 180.0, NULL, 0},
    {"initial", "roll_deg", K_DOUBLE, R(init_roll_deg), -90.0, 90.0, NULL, 0},
    {"initial", "pitch_deg", K_DOUBLE, R(init_pitch_deg), -90.0, 90.0, NULL, 0},
    {"initial", "velocity_mps", K_VEC3, R(init_velocity), -100.0, 100.0, NULL, 0},
    {"initial", "motors", K_ENUM, R(init_motors_hover), 0, 0, motors_names, 0},

    {"controller", "landing_gear_height_m", K_DOUBLE, R(land_gear_m), 0.0, 10.0, NULL, OPEN_LO | OPTIONAL},
    {"controller", "landing_touchdown_dip_m", K_DOUBLE, R(land_dip_m), 0.0, 1.0, NULL, OPEN_LO | OPTIONAL},
    {"controller", "landing_hold_height_m", K_DOUBLE, R(land_hold_m), 0.0, 100.0, NULL, OPEN_LO | OPTIONAL},
    {"controller", "landing_descent_tau_s", K_DOUBLE, R(land_tau_s), 0.05, 100.0, NULL, OPTIONAL},
    {"controller", "landing_pad_accel_max_mps2", K_DOUBLE, R(land_accel_max), 0.0, 100.0, NULL, OPEN_LO | OPTIONAL},
    {"controller", "landing_confidence_start", K_DOUBLE, R(land_conf_start), 0.0, 1.0, NULL, OPEN_LO | OPTIONAL},

    {"mission", "command", K_ENUM, R(mission_command), 0, 0, command_names, 0},
    {"mission", "track_start_s", K_DOUBLE, R(track_start_s), 0.0, 36000.0, NULL, 0},

    {"wind", "mean_mps", K_VEC3, R(wind.mean_mps), -100.0, 100.0, NULL, 0},
    {"wind", "gust_std_mps", K_DOUBLE, R(wind.gust_std_mps), 0.0, 100.0, NULL, 0},
    {"wind", "gust_tau_s", K_DOUBLE, R(wind.gust_tau_s), 0.0, 1000.0, NULL, OPEN_LO},

    {"fault", "kind", K_ENUM, R(fault_kind), 0, 0, fault_names, 0},
    {"fault", "start_s", K_DOUBLE, R(fault_start_s), 0.0, 36000.0, NULL, OPTIONAL},
    {"fault", "delay_s", K_DOUBLE, R(fault_delay_s), 0.0, 1000.0, NULL, 0},
    {"fault", "duration_s", K_DOUBLE, R(fault_duration_s), 0.0, 36000.0, NULL, OPTIONAL},
    {"fault", "scale", K_DOUBLE, R(fault_scale), 0.0, 100.0, NULL, 0},
    {"fault", "vector", K_VEC3, R(fault_vector), -1000.0, 1000.0, NULL, 0},
    {"mission", "landing", K_BOOL, R(landing), 0, 0, NULL, 0},
    {"mission", "disarm_on_contact", K_BOOL, R(disarm_on_contact), 0, 0, NULL, 0},
    {"mission", "disarm_delay_s", K_DOUBLE, R(disarm_delay_s), 0.0, 100.0, NULL, 0},
    {"mission", "touchdown_planned_s", K_DOUBLE, R(touchdown_planned_s), 0.0, 36000.0, NULL, OPTIONAL},
    {"mission", "end_after_landed_s", K_DOUBLE, R(end_after_landed_s), 0.0, 36000.0, NULL, OPTIONAL},
    {"mission", "end_after_motors_off_s", K_DOUBLE, R(end_after_motors_off_s), 0.0, 36000.0, NULL, OPTIONAL},
    {"mission", "setpoint_x_m", K_DOUBLE, R(sp_x), -1000.0, 1000.0, NULL, 0},
    {"mission", "setpoint_y_m", K_DOUBLE, R(sp_y), -1000.0, 1000.0, NULL, 0},
    {"mission", "setpoint_yaw_deg", K_DOUBLE, R(sp_yaw_deg), -180.0, 180.0, NULL, 0},
    {"mission", "yaw_amplitude_deg", K_DOUBLE, R(yaw_amplitude_deg), 0.0, 90.0, NULL, 0},
    {"mission", "yaw_frequency_hz", K_DOUBLE, R(yaw_frequency_hz), 0.0, 10.0, NULL, 0},

    {"sensors", "noise_scale", K_DOUBLE, R(noise_scale), 0.0, 100.0, NULL, 0},

    {"imu", "rate_hz", K_DOUBLE, R(imu.rate_hz), 0.0, 100000.0, NULL, 0},
    {"imu", "delay_s", K_DOUBLE, R(imu.delay_s), 0.0, 1.0, NULL, 0},
    {"imu", "gyro_noise_radps", K_DOUBLE, R(imu.gyro_noise_radps), 0.0, 10.0, NULL, 0},
    {"imu", "gyro_lsb_radps", K_DOUBLE, R(imu.gyro_lsb_radps), 0.0, 1.0, NULL, 0},
    {"imu", "gyro_bias_radps", K_VEC3, R(imu.gyro_bias_radps), -1.0, 1.0, NULL, 0},
    {"imu", "gyro_bias_std_radps", K_DOUBLE, R(imu.gyro_bias_std_radps), 0.0, 1.0, NULL, 0},
    {"imu", "accel_noise_mps2", K_DOUBLE, R(imu.accel_noise_mps2), 0.0, 100.0, NULL, 0},
    {"imu", "accel_lsb_mps2", K_DOUBLE, R(imu.accel_lsb_mps2), 0.0, 10.0, NULL, 0},
    {"imu", "accel_bias_mps2", K_VEC3, R(imu.accel_bias_mps2), -10.0, 10.0, NULL, 0},
    {"imu", "accel_bias_std_mps2", K_DOUBLE, R(imu.accel_bias_std_mps2), 0.0, 10.0, NULL, 0},

    {"position_sensor", "rate_hz", K_DOUBLE, R(position.rate_hz), 0.0, 100000.0, NULL, 0},
    {"position_sensor", "delay_s", K_DOUBLE, R(position.delay_s), 0.0, 10.0, NULL, 0},
    {"position_sensor", "noise_m", K_DOUBLE, R(position.noise_m), 0.0, 100.0, NULL, 0},
    {"position_sensor", "lsb_m", K_DOUBLE, R(position.lsb_m), 0.0, 10.0, NULL, 0},
    {"position_sensor", "velocity_noise_mps", K_DOUBLE, R(position.velocity_noise_mps), 0.0, 100.0, NULL, 0},
    {"position_sensor", "velocity_lsb_mps", K_DOUBLE, R(position.velocity_lsb_mps), 0.0, 10.0, NULL, 0},

    {"altitude_sensor", "source", K_ENUM, R(altitude.source), 0, 0, altitude_names, 0},
    {"altitude_sensor", "rate_hz", K_DOUBLE, R(altitude.rate_hz), 0.0, 100000.0, NULL, 0},
    {"altitude_sensor", "delay_s", K_DOUBLE, R(altitude.delay_s), 0.0, 10.0, NULL, 0},
    {"altitude_sensor", "noise_m", K_DOUBLE, R(altitude.noise_m), 0.0, 100.0, NULL, 0},
    {"altitude_sensor", "lsb_m", K_DOUBLE, R(altitude.lsb_m), 0.0, 10.0, NULL, 0},
    {"altitude_sensor", "range_max_m", K_DOUBLE, R(altitude.range_max_m), 0.0, 1000.0, NULL, OPEN_LO},
    {"altitude_sensor", "range_finder", K_ENUM, R(range_finder), 0, 0, range_finder_names, 0},

    {"attitude_sensor", "rate_hz", K_DOUBLE, R(attitude.rate_hz), 0.0, 100000.0, NULL, 0},
    {"attitude_sensor", "delay_s", K_DOUBLE, R(attitude.delay_s), 0.0, 10.0, NULL, 0},
    {"attitude_sensor", "noise_rad", K_DOUBLE, R(attitude.noise_rad), 0.0, 1.0, NULL, 0},

    {"heading_sensor", "enabled", K_BOOL, R(heading_enabled), 0, 0, NULL, 0},
    {"heading_sensor", "rate_hz", K_DOUBLE, R(heading.rate_hz), 0.0, 100000.0, NULL, 0},
    {"heading_sensor", "delay_s", K_DOUBLE, R(heading.delay_s), 0.0, 10.0, NULL, 0},
    {"heading_sensor", "noise_rad", K_DOUBLE, R(heading.noise_rad), 0.0, 1.0, NULL, 0},
    {"heading_sensor", "bias_rad", K_DOUBLE, R(heading.bias_rad), -3.2, 3.2, NULL, 0},

    {"metrics", "transient_s", K_DOUBLE, R(metrics.transient_s), 0.0, 36000.0, NULL, OPTIONAL},
    {"metrics", "mass_step_window_s", K_DOUBLE, R(metrics.mass_step_window_s), 0.0, 36000.0, NULL, OPEN_LO},
    {"metrics", "bounce_height_m", K_DOUBLE, R(metrics.bounce_height_m), 0.0, 10.0, NULL, OPEN_LO},
    {"metrics", "error_until_contact", K_BOOL, R(error_until_contact), 0, 0, NULL, 0},

    {"montecarlo", "mass_rel", K_DOUBLE, R(mc.mass_rel), 0.0, 0.9, NULL, 0},
    {"montecarlo", "velocity_response_rel", K_DOUBLE, R(mc.velocity_response_rel), 0.0, 0.9, NULL, 0},
    {"montecarlo", "pad_amplitude_min_m", K_DOUBLE, R(mc.pad_amplitude_min_m), 0.0, 100.0, NULL, OPTIONAL},
    {"montecarlo", "pad_amplitude_max_m", K_DOUBLE, R(mc.pad_amplitude_max_m), 0.0, 100.0, NULL, OPTIONAL},
    {"montecarlo", "pad_period_min_s", K_DOUBLE, R(mc.pad_period_min_s), 0.1, 1000.0, NULL, OPTIONAL},
    {"montecarlo", "pad_period_max_s", K_DOUBLE, R(mc.pad_period_max_s), 0.1, 1000.0, NULL, OPTIONAL},
    {"montecarlo", "gust_std_max_mps", K_DOUBLE, R(mc.gust_std_max_mps), 0.0, 100.0, NULL, OPTIONAL},
    {"montecarlo", "inertia_rel", K_DOUBLE, R(mc.inertia_rel), 0.0, 0.9, NULL, 0},
    {"montecarlo", "pad_amplitude_rel", K_DOUBLE, R(mc.pad_amplitude_rel), 0.0, 0.9, NULL, 0},
    {"montecarlo", "pad_period_rel", K_DOUBLE, R(mc.pad_period_rel), 0.0, 0.9, NULL, 0},
    {"montecarlo", "noise_scale_min", K_DOUBLE, R(mc.noise_scale_min), 0.0, 100.0, NULL, 0},
    {"montecarlo", "noise_scale_max", K_DOUBLE, R(mc.noise_scale_max), 0.0, 100.0, NULL, 0},
    {"montecarlo", "delay_steps_max", K_INT, R(mc_delay_steps_max), 0.0, 50.0, NULL, 0},
    {"montecarlo", "motor_tau_rel", K_DOUBLE, R(mc.motor_tau_rel), 0.0, 0.9, NULL, 0},
    {"montecarlo", "rotor_efficiency_min", K_DOUBLE, R(mc.rotor_efficiency_min), 0.0, 1.0, NULL, 0},
    {"montecarlo", "initial_offset_m", K_DOUBLE, R(mc.initial_offset_m), 0.0, 100.0, NULL, 0},
    {"montecarlo", "ground_effect_rho_rel", K_DOUBLE, R(mc.ground_effect_rho_rel), 0.0, 0.9, NULL, 0},
    {"montecarlo", "rotor_efficiency_max", K_DOUBLE, R(mc.rotor_efficiency_max), 0.0, 1.0, NULL, OPEN_LO},
    {"montecarlo", "mass_step_rel", K_DOUBLE, R(mc.mass_step_rel), 0.0, 0.9, NULL, 0},
    {"montecarlo", "mass_max_rel", K_DOUBLE, R(mc.mass_max_rel), 0.0, 10.0, NULL, OPTIONAL},
    {"montecarlo", "mass_step_time_min_s", K_DOUBLE, R(mc.mass_step_time_min_s), 0.0, 36000.0, NULL, 0},
    {"montecarlo", "mass_step_time_max_s", K_DOUBLE, R(mc.mass_step_time_max_s), 0.0, 36000.0, NULL, 0},
    {"montecarlo", "diverged_error_m", K_DOUBLE, R(mc.diverged_error_m), 0.0, 1000.0, NULL, OPEN_LO},
    {"montecarlo", "diverged_position_m", K_DOUBLE, R(mc.diverged_position_m), 0.0, 1000.0, NULL, OPEN_LO},
    {"montecarlo", "diverged_tilt_deg", K_DOUBLE, R(mc.diverged_tilt_deg), 0.0, 180.0, NULL, OPEN_LO},
    {"montecarlo", "accel_bias_max_mps2", K_DOUBLE, R(mc.accel_bias_max_mps2), 0.0, 10.0, NULL, 0},
    {"montecarlo", "fault_height_min_m", K_DOUBLE, R(mc.fault_height_min_m), 0.0, 99.0, NULL, OPTIONAL},
    {"montecarlo", "fault_height_max_m", K_DOUBLE, R(mc.fault_height_max_m), 0.0, 99.0, NULL, OPTIONAL},
    {"montecarlo", "range_finder_probability", K_DOUBLE, R(mc.range_finder_probability), 0.0, 1.0, NULL, OPTIONAL},
};
#define KEY_COUNT ((int)(sizeof keys / sizeof keys[0]))

static const char *const sections[] = {"scenario",        "controller",      "vehicle",         "mass",
                                       "ground_effect",   "gear",            "contact",         "pad",
                                       "initial",         "mission",         "sensors",         "imu",
                                       "position_sensor", "altitude_sensor", "attitude_sensor", "heading_sensor",
                                       "metrics",         "montecarlo",      "wind",            "fault",
                                       "landing",         NULL};

static void raw_defaults(raw *r)
{
    memset(r, 0, sizeof *r);
    /* the dissertation's 4.4 vehicle and task, unless the file says otherwise */
    r->duration_s = 60.0;
    r->plant_rate_hz = 4000.0;
    r->seed = 1.0;
    r->airframe = FSW_AIRFRAME_HEXA_4KG;
    r->variant = 1; /* ssc-adaptive */
    r->rate_hz = 500.0;
    r->attitude_external = 0;
    r->nominal_mass_kg = r->z_r_tau_s = r->z_r_init_m = r->z_r_bias_m = (double)NAN;
    r->thrust_min_n = r->thrust_max_n = r->ground_gain_max = (double)NAN;
    r->actuator_lag_s = (double)NAN;
    r->rho_n = r->gamma = r->tau_av_s = r->l0_per_s = r->a_m_per_s = r->kappa_m_per_kg = (double)NAN;
    r->hkp = r->hkd = r->tilt_max_deg = r->accel_fb_gain = (double)NAN;
    r->pid_kp_z = r->pid_ki_z = r->pid_kp_v = r->pid_ki_v = (double)NAN;
    r->land_hold_m = r->land_tau_s = r->land_accel_max = r->land_conf_start = r->land_gear_m = r->land_dip_m = (double)NAN;
    r->wind.gust_tau_s = 2.0;
    r->fault_start_s = r->fault_duration_s = (double)NAN; /* from the first DESCEND; the kind's duration */
    r->fault_scale = 1.0;
    r->mc.pad_amplitude_min_m = r->mc.pad_amplitude_max_m = (double)NAN;
    r->mc.pad_period_min_s = r->mc.pad_period_max_s = r->mc.gust_std_max_mps = (double)NAN;
    r->mc.mass_max_rel = (double)NAN;
    r->rho_scale = r->gamma_scale = r->kappa_m_scale = r->bandwidth_scale = r->authority_scale = (double)NAN;
    r->fsw_k_p = r->fsw_a_p = r->plant_k_p = r->plant_a_p = v3_make(1.0, 1.0, 1.0);
    r->velocity_tilt_max_deg = 25.0;
    r->mass_kg = 4.0;
    r->inertia = v3_make(0.082, 0.082, 0.149);
    r->gravity_mps2 = 9.81;
    r->layout = LAYOUT_HEXA_X;
    r->rotor_count = 6.0;
    r->arm_m = 0.45;
    r->thrust_max_n_rotor = 13.08;
    r->torque_ratio_m = 0.016;
    r->thrust_exponent = 2.0;
    r->torque_exponent = 2.0;
    r->speed_min = 0.0;
    r->motor_tau_s = 0.0;
    r->first_spin = -1.0;
    for (int i = 0; i < PLANT_MAX_ROTORS; i++) {
        raw_rotor *rr = &r->rotor[i];
        rr->position_m = rr->axis = v3_make((double)NAN, (double)NAN, (double)NAN);
        rr->spin = rr->thrust_max_n = rr->torque_ratio_m = rr->thrust_exponent = rr->torque_exponent = (double)NAN;
        rr->speed_min = rr->motor_tau_s = rr->efficiency = (double)NAN;
    }
    r->mass_tau_s = 0.01;
    r->ge_enabled = 1;
    r->ge_radius = 0.16;
    r->ge_rho = 1.184;
    r->gear_height = 0.18;
    r->feet = 4.0;
    r->foot_radius = 0.3;
    r->first_foot_deg = 45.0;
    r->contact_enabled = 0;
    r->stiffness = 2.0e4;
    r->damping_ratio = 0.7;
    r->friction = 0.8;
    r->slip_speed = 0.01;
    r->pad_model = PAD_SINE;
    r->pad_amplitude = 0.18;
    r->pad_period = 10.0;
    r->roll_period_s = r->pitch_period_s = 10.0;
    r->descent_shaping = -1;
    r->shaping_k_r = r->shaping_delta_h = r->shaping_k_c = (double)NAN;
    r->shaping_u_zbias = r->shaping_k_a = r->shaping_delta_a = r->shaping_max_climb = r->shaping_commit = (double)NAN;
    r->init_height = (double)NAN;
    r->init_motors_hover = 1;
    r->touchdown_planned_s = (double)NAN;
    r->end_after_landed_s = r->end_after_motors_off_s = (double)NAN;
    r->disarm_delay_s = 0.0;
    r->noise_scale = 1.0;
    r->altitude.source = ALTITUDE_FROM_POSITION;
    r->altitude.range_max_m = 4.0;
    r->metrics.transient_s = (double)NAN;
    r->metrics.mass_step_window_s = 10.0;
    r->metrics.bounce_height_m = 0.002;
    r->error_until_contact = -1;
    r->mc.noise_scale_min = 1.0;
    r->mc.noise_scale_max = 1.0;
    r->mc.rotor_efficiency_min = 1.0;
    r->mc.rotor_efficiency_max = 1.0;
    r->mc.mass_step_time_min_s = r->mc.mass_step_time_max_s = (double)NAN; /* the transient .. the end */
    r->mc.diverged_error_m = 1.0;
    r->mc.diverged_position_m = 2.0;
    r->mc.diverged_tilt_deg = 60.0;
    r->mc.fault_height_min_m = r->mc.fault_height_max_m = r->mc.range_finder_probability = (double)NAN;
}

/* ---------------------------------------------------------------------- */
/* parsing                                                                 */
/* ---------------------------------------------------------------------- */

typedef struct parse_ctx {
    const char *file;
    FILE *fp;
    int line;             /* the line the reader handed out last */
    raw *r;
    char *err;
    size_t err_len;
    bool failed;
    int key_line[KEY_COUNT];                         /* where each key was set (0: not) */
    int rotor_key_line[PLANT_MAX_ROTORS][KEY_COUNT]; /* the same for [rotor.N] */
    int max_rotor_section;                           /* highest N of a [rotor.N] seen, -1 */
    const char *const *overrides;                    /* --set "section.key=value", applied after the file */
} parse_ctx;

/* The line number an override is known by: OVERRIDE_LINE + its index. */
#define OVERRIDE_LINE 1000000000

static void fail(parse_ctx *c, int line, const char *section, const char *key, const char *fmt, const char *detail)
{
    if (c->failed) {
        return;
    }
    c->failed = true;
    char reason[256];
    snprintf(reason, sizeof reason, fmt, detail != NULL ? detail : "");
    char where[SCENARIO_PATH_MAX + 64];
    if (line >= OVERRIDE_LINE) {
        snprintf(where, sizeof where, "--set '%.200s'", c->overrides[line - OVERRIDE_LINE]);
    } else {
        snprintf(where, sizeof where, "%s:%d", c->file, line);
    }
    if (key != NULL) {
        snprintf(c->err, c->err_len, "%s: key '%s' in [%s]: %s", where, key, section, reason);
    } else if (section != NULL) {
        snprintf(c->err, c->err_len, "%s: section [%s]: %s", where, section, reason);
    } else {
        snprintf(c->err, c->err_len, "%s: %s", where, reason);
    }
}

static char *trim(char *s)
{
    while (isspace((unsigned char)*s)) {
        s++;
    }
    char *end = s + strlen(s);
    while (end > s && isspace((unsigned char)end[-1])) {
        *--end = '\0';
    }
    return s;
}

/* "rotor.N" -> N (0..MAX-1), -2 for another section, -1 for a bad N. */
static int rotor_section_index(const char *section)
{
    if (strncmp(section, "rotor.", 6) != 0) {
        return -2;
    }
    const char *digits = section + 6;
    if (*digits == '\0') {
        return -1;
    }
    for (const char *p = digits; *p != '\0'; p++) {
        if (!isdigit((unsigned char)*p)) {
            return -1;
        }
    }
    const long n = strtol(digits, NULL, 10);
    return n >= 0 && n < PLANT_MAX_ROTORS ? (int)n : -1;
}

static bool section_known(const char *section)
{
    for (int i = 0; sections[i] != NULL; i++) {
        if (strcmp(section, sections[i]) == 0) {
            return true;
        }
    }
    return rotor_section_index(section) >= 0;
}

/* The reader: fgets that counts lines and checks section headers itself (inih
 * does not report a section until a key in it). */
static char *counting_reader(char *str, int num, void *stream)
{
    parse_ctx *c = stream;
    if (c->failed) {
        return NULL;
    }
    char *s = fgets(str, num, c->fp);
    if (s == NULL) {
        return NULL;
    }
    c->line++;
    char buf[512];
    snprintf(buf, sizeof buf, "%s", s);
    char *t = trim(buf);
    if (*t == '[') {
        char *close = strchr(t, ']');
        if (close == NULL) {
            fail(c, c->line, NULL, NULL, "syntax error: a section header without ']'%s", "");
            return NULL;
        }
        *close = '\0';
        char *name = trim(t + 1);
        if (!section_known(name)) {
            const int ri = rotor_section_index(name);
            fail(c, c->line, name, NULL,
                 ri == -1 ? "unknown section (rotor sections are [rotor.0] .. [rotor.7])%s" : "unknown section%s", "");
            return NULL;
        }
        const int ri = rotor_section_index(name);
        if (ri > c->max_rotor_section) {
            c->max_rotor_section = ri;
        }
    }
    return s;
}

static bool parse_double(const char *text, double *out)
{
    char *end;
    errno = 0;
    const double v = strtod(text, &end);
    if (end == text || *trim(end) != '\0' || errno == ERANGE || !isfinite(v)) {
        return false;
    }
    *out = v;
    return true;
}

static bool in_range(const key_def *k, double v)
{
    if ((k->flags & OPEN_LO) != 0 ? !(v > k->lo) : !(v >= k->lo)) {
        return false;
    }
    return v <= k->hi;
}

static void range_text(const key_def *k, char *buf, size_t len)
{
    snprintf(buf, len, "%s%g, %g]", (k->flags & OPEN_LO) != 0 ? "(" : "[", k->lo, k->hi);
}

/* Parses a comma-separated list of up to max numbers, each in range. */
static const char *parse_numbers(const key_def *k, const char *value, double *out, int max, int *count)
{
    char buf[512];
    snprintf(buf, sizeof buf, "%s", value);
    int n = 0;
    char *save = NULL;
    for (char *tok = strtok_r(buf, ",", &save); tok != NULL; tok = strtok_r(NULL, ",", &save)) {
        if (n >= max) {
            return "too many values";
        }
        double v;
        if (!parse_double(trim(tok), &v)) {
            return "not a number";
        }
        if (!in_range(k, v)) {
            return "out of range";
        }
        out[n++] = v;
    }
    *count = n;
    return NULL;
}

static int handler(void *user, const char *section, const char *name, const char *value)
{
    parse_ctx *c = user;
    if (c->failed) {
        return 0;
    }
    const int rotor = rotor_section_index(section);
    const char *table_section = rotor >= 0 ? "rotor" : section;
    int idx = -1;
    for (int i = 0; i < KEY_COUNT; i++) {
        if (strcmp(keys[i].section, table_section) == 0 && strcmp(keys[i].key, name) == 0) {
            idx = i;
            break;
        }
    }
    if (!section_known(section)) {
        fail(c, c->line, section, name, "unknown section%s", "");
        return 0;
    }
    if (idx < 0) {
        fail(c, c->line, section, name, "unknown key%s", "");
        return 0;
    }
    int *seen = rotor >= 0 ? &c->rotor_key_line[rotor][idx] : &c->key_line[idx];
    if (*seen != 0) {
        char detail[64];
        snprintf(detail, sizeof detail, "%d", *seen);
        fail(c, c->line, section, name, "set twice (first on line %s)", detail);
        return 0;
    }
    *seen = c->line;
    const key_def *k = &keys[idx];
    char *base = rotor >= 0 ? (char *)&c->r->rotor[rotor] : (char *)c->r;
    void *field = base + k->offset;
    char range[96];
    range_text(k, range, sizeof range);
    char vbuf[512];
    snprintf(vbuf, sizeof vbuf, "%s", value);
    const char *v = trim(vbuf);
    switch (k->kind) {
    case K_DOUBLE:
    case K_INT: {
        double d;
        if (!parse_double(v, &d)) {
            fail(c, c->line, section, name, "'%s' is not a number", v);
            return 0;
        }
        if (k->kind == K_INT && d != floor(d)) {
            fail(c, c->line, section, name, "'%s' is not an integer", v);
            return 0;
        }
        if (!in_range(k, d)) {
            char detail[160];
            snprintf(detail, sizeof detail, "%s is outside %s", v, range);
            fail(c, c->line, section, name, "%s", detail);
            return 0;
        }
        *(double *)field = d;
        break;
    }
    case K_BOOL: {
        int b;
        if (strcmp(v, "true") == 0 || strcmp(v, "yes") == 0 || strcmp(v, "on") == 0 || strcmp(v, "1") == 0) {
            b = 1;
        } else if (strcmp(v, "false") == 0 || strcmp(v, "no") == 0 || strcmp(v, "off") == 0 ||
                   strcmp(v, "0") == 0) {
            b = 0;
        } else {
            fail(c, c->line, section, name, "'%s' is not a boolean (true/false)", v);
            return 0;
        }
        *(int *)field = b;
        break;
    }
    case K_ENUM: {
        int found = -1;
        char choices[512] = "";
        for (int i = 0; k->names[i] != NULL; i++) {
            if (strcmp(v, k->names[i]) == 0) {
                found = i;
            }
            strncat(choices, i > 0 ? ", " : "", sizeof choices - strlen(choices) - 1);
            strncat(choices, k->names[i], sizeof choices - strlen(choices) - 1);
        }
        if (found < 0) {
            char detail[700];
            snprintf(detail, sizeof detail, "'%s' is not one of: %s", v, choices);
            fail(c, c->line, section, name, "%s", detail);
            return 0;
        }
        *(int *)field = found;
        break;
    }
    case K_VEC3: {
        double xyz[3];
        int n = 0;
        const char *why = parse_numbers(k, v, xyz, 3, &n);
        if (why == NULL && n != 3) {
            why = "needs three values x, y, z";
        }
        if (why != NULL) {
            char detail[200];
            snprintf(detail, sizeof detail, "'%s': %s", v, why);
            if (strcmp(why, "out of range") == 0) {
                snprintf(detail, sizeof detail, "'%s': a component is outside %s", v, range);
            }
            fail(c, c->line, section, name, "%s", detail);
            return 0;
        }
        *(v3 *)field = v3_make(xyz[0], xyz[1], xyz[2]);
        break;
    }
    case K_LIST: {
        raw_list *list = field;
        const char *why = parse_numbers(k, v, list->v, LIST_MAX, &list->count);
        if (why != NULL) {
            char detail[200];
            snprintf(detail, sizeof detail, "'%s': %s (at most 8 values, each in %s)", v, why, range);
            fail(c, c->line, section, name, "%s", detail);
            return 0;
        }
        break;
    }
    case K_STRING:
    case K_STRING_LONG: {
        const size_t cap = k->kind == K_STRING ? SCENARIO_NAME_MAX : SCENARIO_TEXT_MAX;
        if (strlen(v) >= cap) {
            fail(c, c->line, section, name, "too long%s", "");
            return 0;
        }
        snprintf((char *)field, cap, "%s", v);
        break;
    }
    }
    return 1;
}

static int key_index(const char *section, const char *key)
{
    for (int i = 0; i < KEY_COUNT; i++) {
        if (strcmp(keys[i].section, section) == 0 && strcmp(keys[i].key, key) == 0) {
            return i;
        }
    }
    return -1;
}

/* A consistency error tied to a key: its line if set, the file otherwise. */
static bool fail_key(parse_ctx *c, const char *section, const char *key, const char *reason)
{
    const int i = key_index(section, key);
    const int line = i >= 0 ? c->key_line[i] : 0;
    if (line > 0) {
        fail(c, line, section, key, "%s", reason);
    } else if (!c->failed) {
        c->failed = true;
        snprintf(c->err, c->err_len, "%s: key '%s' in [%s] (default): %s", c->file, key, section, reason);
    }
    return false;
}

static bool fail_rotor(parse_ctx *c, int rotor, const char *key, const char *reason)
{
    const int i = key_index("rotor", key);
    const int line = i >= 0 ? c->rotor_key_line[rotor][i] : 0;
    char section[32];
    snprintf(section, sizeof section, "rotor.%d", rotor);
    if (line > 0) {
        fail(c, line, section, key, "%s", reason);
    } else if (!c->failed) {
        c->failed = true;
        snprintf(c->err, c->err_len, "%s: [%s]: %s", c->file, section, reason);
    }
    return false;
}

/* The overrides "section.key=value" (fc-sil --set), each parsed as a line of
 * the file that replaces the file's own setting of the key. The key is what
 * follows the last '.' before the '=', so [rotor.N] keys work as well. */
static bool apply_overrides(parse_ctx *c, int count)
{
    for (int i = 0; i < count && !c->failed; i++) {
        const int line = OVERRIDE_LINE + i;
        char buf[512];
        snprintf(buf, sizeof buf, "%s", c->overrides[i]);
        char *eq = strchr(buf, '=');
        if (eq != NULL) {
            *eq = '\0';
        }
        char *dot = strrchr(buf, '.');
        if (eq == NULL || dot == NULL || dot == buf || dot[1] == '\0') {
            fail(c, line, NULL, NULL, "not section.key=value%s", "");
            break;
        }
        *dot = '\0';
        const char *section = trim(buf), *key = trim(dot + 1);
        const int rotor = rotor_section_index(section);
        const int idx = key_index(rotor >= 0 ? "rotor" : section, key);
        if (idx >= 0) {
            /* the file's setting is replaced, not set twice */
            int *seen = rotor >= 0 ? &c->rotor_key_line[rotor][idx] : &c->key_line[idx];
            *seen = 0;
        }
        if (rotor > c->max_rotor_section) {
            c->max_rotor_section = rotor;
        }
        c->line = line;
        (void)handler(c, section, key, eq + 1);
    }
    return !c->failed;
}

/* ---------------------------------------------------------------------- */
/* building the scenario                                                   */
/* ---------------------------------------------------------------------- */

static double pick(double override, double dflt)
{
    return isnan(override) ? dflt : override;
}

/* [fault]: the kind, when it starts (start_s, or from the first DESCEND of a
 * landing run), how long it lasts (by default 1 s, the input losses to the end). */
static bool build_fault(parse_ctx *c, scenario *sc)
{
    const raw *r = c->r;
    fault_params *f = &sc->fault;
    f->kind = (fault_kind)r->fault_kind;
    f->start_s = r->fault_start_s;
    f->delay_s = r->fault_delay_s;
    const bool input_loss = f->kind == FAULT_POSITION_LOST || f->kind == FAULT_IMU_LOST;
    f->duration_s = pick(r->fault_duration_s, input_loss ? (double)INFINITY : 1.0);
    f->scale = r->fault_scale;
    f->vector = r->fault_vector;
    if (f->kind != FAULT_NONE && isnan(f->start_s) && (mission_command)r->mission_command != MISSION_LAND) {
        return fail_key(c, "fault", "kind", "a track mission has no DESCEND to time the fault from: set start_s");
    }
    return true;
}

/* [altitude_sensor] range_finder: what the firmware gets of the range channel. */
static bool build_range_finder(parse_ctx *c, scenario *sc)
{
    const raw *r = c->r;
    sc->range_finder = (range_finder_mode)r->range_finder;
    if (sc->range_finder == RANGE_FINDER_ON && r->altitude.source != ALTITUDE_RANGE) {
        return fail_key(c, "altitude_sensor", "range_finder", "on needs source = range");
    }
    if (sc->range_finder == RANGE_FINDER_OFF && r->altitude.source == ALTITUDE_RANGE &&
        (mission_command)r->mission_command == MISSION_TRACK) {
        return fail_key(c, "altitude_sensor", "range_finder",
                        "off: the platform's z cannot come from a range finder it does not have (source = range)");
    }
    return true;
}

static bool build(parse_ctx *c, scenario *sc)
{
    const raw *r = c->r;
    memset(sc, 0, sizeof *sc);
    snprintf(sc->name, sizeof sc->name, "%s", r->name);
    sc->figure = (scenario_figure)r->figure;
    snprintf(sc->description, sizeof sc->description, "%s", r->description);
    sc->duration_s = r->duration_s;
    sc->plant_rate_hz = r->plant_rate_hz;
    sc->seed = (uint64_t)r->seed;
    sc->controller_rate_hz = r->rate_hz;
    const double ratio = r->plant_rate_hz / r->rate_hz;
    if (fabs(ratio - nearbyint(ratio)) > 1e-9 || ratio < 1.0) {
        return fail_key(c, "scenario", "plant_rate_hz", "must be a whole multiple (>= 1) of [controller] rate_hz");
    }

    /* flight software */
    fsw_config *f = &sc->fsw;
    fsw_config_defaults(f);
    f->airframe = r->airframe;
    f->variant = r->variant;
    f->dt_s = 1.0 / r->rate_hz;
    f->use_external_attitude = r->attitude_external;
    f->mass_kg = r->nominal_mass_kg;
    f->ref_tau_s = r->z_r_tau_s;
    f->ref_offset_init_m = r->z_r_init_m;
    f->ref_bias_m = r->z_r_bias_m;
    f->thrust_min_n = r->thrust_min_n;
    f->thrust_max_n = r->thrust_max_n;
    f->ground_gain_max = r->ground_gain_max;
    f->rho_n = r->rho_n;
    f->gamma = r->gamma;
    f->actuator_lag_s = r->actuator_lag_s;
    f->tau_av_s = r->tau_av_s;
    f->l0_per_s = r->l0_per_s;
    f->a_m_per_s = r->a_m_per_s;
    f->kappa_m_per_kg = r->kappa_m_per_kg;
    f->rho_scale = r->rho_scale;
    f->gamma_scale = r->gamma_scale;
    f->kappa_m_scale = r->kappa_m_scale;
    f->bandwidth_scale = r->bandwidth_scale;
    f->authority_scale = r->authority_scale;
    f->horizontal_kp_per_s2 = r->hkp;
    f->horizontal_kd_per_s = r->hkd;
    f->tilt_max_rad = isnan(r->tilt_max_deg) ? (double)NAN : r->tilt_max_deg * DEG;
    f->accel_fb_gain_per_s = r->accel_fb_gain;
    f->pid_kp_z_per_s = r->pid_kp_z;
    f->pid_ki_z_per_s2 = r->pid_ki_z;
    f->pid_kp_v_n_per_mps = r->pid_kp_v;
    f->pid_ki_v_n_per_m = r->pid_ki_v;
    f->landing_gear_height_m = r->land_gear_m;
    f->landing_touchdown_dip_m = r->land_dip_m;
    f->landing_hold_height_m = r->land_hold_m;
    f->landing_descent_tau_s = r->land_tau_s;
    f->landing_pad_accel_max_mps2 = r->land_accel_max;
    f->landing_confidence_start = r->land_conf_start;
    f->descent_shaping = r->descent_shaping;
    f->shaping_k_r_m2ps = r->shaping_k_r;
    f->shaping_delta_h_m = r->shaping_delta_h;
    f->shaping_k_c_per_s = r->shaping_k_c;
    f->shaping_u_zbias_mps = r->shaping_u_zbias;
    f->shaping_k_a_mps = r->shaping_k_a;
    f->shaping_delta_a_m = r->shaping_delta_a;
    f->shaping_max_climb_mps = r->shaping_max_climb;
    f->shaping_commit_m = r->shaping_commit;
    f->velocity_output = r->output_velocity;
    f->velocity_k_p_per_s[0] = r->fsw_k_p.x;
    f->velocity_k_p_per_s[1] = r->fsw_k_p.y;
    f->velocity_k_p_per_s[2] = r->fsw_k_p.z;
    f->velocity_a_p_per_s[0] = r->fsw_a_p.x;
    f->velocity_a_p_per_s[1] = r->fsw_a_p.y;
    f->velocity_a_p_per_s[2] = r->fsw_a_p.z;

    /* plant */
    plant_params *p = &sc->plant;
    p->mass_kg = r->mass_kg;
    p->inertia_kgm2 = r->inertia;
    p->inertia_per_kg = r->inertia_per_kg;
    p->gravity_mps2 = r->gravity_mps2;
    p->drag_n_per_mps = r->drag;
    p->velocity_input = r->input_velocity == 1;
    p->velocity_k_p_per_s = r->plant_k_p;
    p->velocity_a_p_per_s = r->plant_a_p;
    p->velocity_tilt_max_rad = r->velocity_tilt_max_deg * DEG;
    sc->layout = (rotor_layout)r->layout;
    int n;
    if (sc->layout == LAYOUT_QUAD_X) {
        n = 4;
    } else if (sc->layout == LAYOUT_HEXA_X) {
        n = 6;
    } else {
        n = (int)r->rotor_count;
    }
    if (sc->layout != LAYOUT_CUSTOM && c->key_line[key_index("vehicle", "rotor_count")] != 0 &&
        (int)r->rotor_count != n) {
        return fail_key(c, "vehicle", "rotor_count", "disagrees with the layout (quad-x: 4, hexa-x: 6)");
    }
    if (c->max_rotor_section >= n) {
        char why[96];
        snprintf(why, sizeof why, "[rotor.%d] but the vehicle has %d rotors", c->max_rotor_section, n);
        return fail_key(c, "vehicle", "layout", why);
    }
    p->rotor_count = n;
    if (!(fabs(r->first_spin) == 1.0)) {
        return fail_key(c, "vehicle", "first_spin", "must be +1 or -1");
    }
    for (int i = 0; i < n; i++) {
        plant_rotor *rot = &p->rotor[i];
        const raw_rotor *o = &r->rotor[i];
        /* layouts numbered as the firmware's presets (fc/allocation.h): quad-x
         * front-right, back-right, back-left, front-left; hexa-x counter-clockwise
         * from 30 deg right of the nose; spins alternate from first_spin */
        double angle;
        if (sc->layout == LAYOUT_QUAD_X) {
            static const double quad_deg[4] = {-45.0, -135.0, 135.0, 45.0};
            angle = quad_deg[i] * DEG;
        } else if (sc->layout == LAYOUT_HEXA_X) {
            angle = (-30.0 + 60.0 * i) * DEG;
        } else {
            angle = 0.0;
        }
        v3 position = v3_make(r->arm_m * cos(angle), r->arm_m * sin(angle), r->rotor_z_m);
        if (sc->layout == LAYOUT_CUSTOM && isnan(o->position_m.x)) {
            return fail_rotor(c, i, "position_m", "a custom layout needs position_m for every rotor");
        }
        if (!isnan(o->position_m.x)) {
            position = o->position_m;
        }
        v3 axis = isnan(o->axis.x) ? v3_make(0.0, 0.0, 1.0) : o->axis;
        const double len = v3_norm(axis);
        if (!(len > 0.5)) {
            return fail_rotor(c, i, "axis", "the axis must have a length near 1");
        }
        axis = v3_scale(axis, 1.0 / len);
        const double spin_default = (i % 2 == 0) ? r->first_spin : -r->first_spin;
        const double spin = pick(o->spin, spin_default);
        if (!(fabs(spin) == 1.0)) {
            return fail_rotor(c, i, "spin", "must be +1 or -1");
        }
        rot->position_m = position;
        rot->axis = axis;
        rot->thrust_max_n = pick(o->thrust_max_n, r->thrust_max_n_rotor);
        rot->torque_max_nm = spin * pick(o->torque_ratio_m, r->torque_ratio_m) * rot->thrust_max_n;
        rot->thrust_exponent = pick(o->thrust_exponent, r->thrust_exponent);
        rot->torque_exponent = pick(o->torque_exponent, r->torque_exponent);
        rot->speed_min = pick(o->speed_min, r->speed_min);
        rot->tau_s = pick(o->motor_tau_s, r->motor_tau_s);
        rot->efficiency = pick(o->efficiency, 1.0);
    }
    p->mass_tau_s = r->mass_tau_s;
    if (r->step_times.count != r->step_masses.count) {
        return fail_key(c, "mass", "step_masses_kg", "needs as many values as step_times_s");
    }
    p->mass_step_count = r->step_times.count;
    for (int k = 0; k < p->mass_step_count; k++) {
        p->mass_step_time_s[k] = r->step_times.v[k];
        p->mass_step_kg[k] = r->step_masses.v[k];
        if (k > 0 && !(p->mass_step_time_s[k] > p->mass_step_time_s[k - 1])) {
            return fail_key(c, "mass", "step_times_s", "must increase");
        }
    }
    p->ground_effect = r->ge_enabled != 0;
    p->ge_radius_m = r->ge_radius;
    p->ge_rho = r->ge_rho;
    p->gear_height_m = r->gear_height;
    p->foot_count = (int)r->feet;
    for (int k = 0; k < p->foot_count; k++) {
        const double a = (r->first_foot_deg + 360.0 * k / p->foot_count) * DEG;
        p->foot_m[k] = v3_make(r->foot_radius * cos(a), r->foot_radius * sin(a), -r->gear_height);
    }
    p->contact = r->contact_enabled != 0;
    p->contact_stiffness_n_per_m = r->stiffness;
    /* damping per foot from the ratio, for the vehicle's share m / feet */
    p->contact_damping_ns_per_m = 2.0 * r->damping_ratio * sqrt(r->stiffness * r->mass_kg / p->foot_count);
    p->friction = r->friction;
    p->slip_speed_mps = r->slip_speed;
    pad_params *pad = &p->pad;
    pad->model = (pad_model)r->pad_model;
    pad->growth_start_s = (double)INFINITY;
    pad->growth_duration_s = 1.0;
    pad->growth_scale = 1.0;
    pad->warp_start_s = (double)INFINITY;
    pad->warp_factor = 1.0;
    pad->base_m = r->pad_base;
    pad->amplitude_m = r->pad_amplitude;
    pad->omega_radps = 2.0 * PI / r->pad_period;
    pad->roll_amplitude_rad = r->roll_amplitude_deg * DEG;
    pad->roll_omega_radps = 2.0 * PI / r->roll_period_s;
    pad->roll_phase_rad = r->roll_phase_deg * DEG;
    pad->pitch_amplitude_rad = r->pitch_amplitude_deg * DEG;
    pad->pitch_omega_radps = 2.0 * PI / r->pitch_period_s;
    pad->pitch_phase_rad = r->pitch_phase_deg * DEG;
    if (pad->model == PAD_WAVES) {
        if (r->wave_amplitudes.count == 0) {
            return fail_key(c, "pad", "wave_amplitudes_m", "the waves model needs at least one component");
        }
        if (r->wave_periods.count != r->wave_amplitudes.count) {
            return fail_key(c, "pad", "wave_periods_s", "needs one period per amplitude");
        }
        if (r->wave_phases_deg.count != 0 && r->wave_phases_deg.count != r->wave_amplitudes.count) {
            return fail_key(c, "pad", "wave_phases_deg", "needs one phase per amplitude (or none)");
        }
        pad->wave_count = r->wave_amplitudes.count;
        for (int k = 0; k < pad->wave_count; k++) {
            pad->wave_amplitude_m[k] = r->wave_amplitudes.v[k];
            pad->wave_omega_radps[k] = 2.0 * PI / r->wave_periods.v[k];
            pad->wave_phase_rad[k] = r->wave_phases_deg.count != 0 ? r->wave_phases_deg.v[k] * DEG : 0.0;
        }
    }
    /* a velocity-input vehicle: its rotors' thrust is what its autopilot has */
    p->velocity_thrust_max_n = 0.0;
    for (int i = 0; i < p->rotor_count; i++) {
        p->velocity_thrust_max_n += p->rotor[i].thrust_max_n;
    }
    const char *why = plant_params_check(p);
    if (why != NULL) {
        if (strstr(why, "velocity input") != NULL) {
            return fail_key(c, "vehicle", "input", why);
        }
        if (strstr(why, "ground effect") != NULL) {
            return fail_key(c, "gear", "height_m", why);
        }
        if (strstr(why, "contact") != NULL) {
            return fail_key(c, "contact", "stiffness_n_per_m", why);
        }
        if (strstr(why, "mass step") != NULL || strstr(why, "step masses") != NULL) {
            return fail_key(c, "mass", "step_masses_kg", why);
        }
        return fail_key(c, "vehicle", "layout", why);
    }

    /* sensors */
    sensor_params *s = &sc->sensors;
    s->imu = r->imu;
    s->position = r->position;
    s->altitude = r->altitude;
    s->attitude = r->attitude;
    s->heading = r->heading;
    s->heading.enabled = r->heading_enabled != 0;
    s->noise_scale = r->noise_scale;
    why = sensors_check(s, f->dt_s);
    if (why != NULL) {
        return fail_key(c, "sensors", "noise_scale", why);
    }

    /* mission, initial state, metrics, Monte-Carlo */
    mission_params *m = &sc->mission;
    m->command = (mission_command)r->mission_command;
    m->track_start_s = r->track_start_s;
    sc->wind = r->wind;
    if (!build_fault(c, sc)) {
        return false;
    }
    if (m->command == MISSION_LAND && r->altitude.source != ALTITUDE_RANGE) {
        return fail_key(c, "mission", "command", "land needs [altitude_sensor] source = range");
    }
    if (!build_range_finder(c, sc)) {
        return false;
    }
    m->landing = r->landing != 0;
    m->disarm_on_contact = r->disarm_on_contact != 0;
    m->disarm_delay_s = r->disarm_delay_s;
    m->touchdown_planned_s = r->touchdown_planned_s;
    m->end_after_landed_s = r->end_after_landed_s;
    m->end_after_motors_off_s = r->end_after_motors_off_s;
    m->setpoint_x_m = r->sp_x;
    m->setpoint_y_m = r->sp_y;
    m->setpoint_yaw_rad = r->sp_yaw_deg * DEG;
    m->yaw_amplitude_rad = r->yaw_amplitude_deg * DEG;
    m->yaw_frequency_hz = r->yaw_frequency_hz;
    if (m->disarm_on_contact && !p->contact) {
        return fail_key(c, "mission", "disarm_on_contact", "needs [contact] enabled = true");
    }
    initial_params *in = &sc->initial;
    in->x_m = r->init_x;
    in->y_m = r->init_y;
    in->height_m = r->init_height;
    in->yaw_rad = r->init_yaw_deg * DEG;
    in->roll_rad = r->init_roll_deg * DEG;
    in->pitch_rad = r->init_pitch_deg * DEG;
    in->velocity_mps = r->init_velocity;
    in->motors_hover = r->init_motors_hover != 0;
    sc->metrics = r->metrics;
    sc->metrics.error_until_contact = r->error_until_contact < 0 ? m->landing : r->error_until_contact != 0;
    sc->montecarlo = r->mc;
    sc->montecarlo.delay_steps_max = (int)r->mc_delay_steps_max;
    if (sc->montecarlo.noise_scale_max < sc->montecarlo.noise_scale_min) {
        return fail_key(c, "montecarlo", "noise_scale_max", "must not be below noise_scale_min");
    }
    montecarlo_params *mc = &sc->montecarlo;
    if (mc->rotor_efficiency_max < mc->rotor_efficiency_min) {
        return fail_key(c, "montecarlo", "rotor_efficiency_max", "must not be below rotor_efficiency_min");
    }
    if (isnan(mc->fault_height_min_m) != isnan(mc->fault_height_max_m)) {
        return fail_key(c, "montecarlo", isnan(mc->fault_height_min_m) ? "fault_height_min_m" : "fault_height_max_m",
                        "fault_height_min_m and fault_height_max_m go together");
    }
    if (mc->fault_height_max_m < mc->fault_height_min_m) {
        return fail_key(c, "montecarlo", "fault_height_max_m", "must not be below fault_height_min_m");
    }
    if (mc->mass_step_rel > 0.0) {
        /* default window: from the end of the transient (5 tau_zr + 5 s with the
         * nominal tau_zr = 0.1 s, or [metrics] transient_s) to the end less the
         * mass-step window, so the step's peak error is measured */
        if (isnan(mc->mass_step_time_min_s)) {
            mc->mass_step_time_min_s = isnan(sc->metrics.transient_s) ? 5.5 : sc->metrics.transient_s;
        }
        if (isnan(mc->mass_step_time_max_s)) {
            mc->mass_step_time_max_s = sc->duration_s - sc->metrics.mass_step_window_s;
        }
        if (!(mc->mass_step_time_max_s >= mc->mass_step_time_min_s)) {
            return fail_key(c, "montecarlo", "mass_step_time_max_s",
                            "must not be below mass_step_time_min_s (default: duration_s less "
                            "[metrics] mass_step_window_s, from the transient's end)");
        }
        if (sc->plant.mass_step_count >= PLANT_MAX_MASS_STEPS) {
            return fail_key(c, "montecarlo", "mass_step_rel", "[mass] step_times_s leaves no room for one more step");
        }
    }
    return true;
}

bool scenario_load(const char *path, const char *const *overrides, int override_count, scenario *sc, char *err,
                   size_t err_len)
{
    for (int i = 0; i < FSW_VARIANT_COUNT; i++) {
        variant_names_z[i] = sim_variant_names[i];
    }
    variant_names_z[FSW_VARIANT_COUNT] = NULL;
    static raw r; /* large; one load at a time */
    raw_defaults(&r);
    parse_ctx c;
    memset(&c, 0, sizeof c);
    c.file = path;
    c.r = &r;
    c.err = err;
    c.err_len = err_len;
    c.max_rotor_section = -1;
    c.overrides = overrides;
    c.fp = fopen(path, "r");
    if (c.fp == NULL) {
        snprintf(err, err_len, "%s: cannot open: %s", path, strerror(errno));
        return false;
    }
    const int result = ini_parse_stream(counting_reader, &c, handler, &c);
    fclose(c.fp);
    if (c.failed) {
        return false;
    }
    if (result > 0) {
        snprintf(err, err_len, "%s:%d: syntax error (expected 'key = value', '[section]' or a comment)", path,
                 result);
        return false;
    }
    if (result < 0) {
        snprintf(err, err_len, "%s: cannot read", path);
        return false;
    }
    if (!apply_overrides(&c, override_count) || !build(&c, sc)) {
        return false;
    }
    sc->overrides = overrides;
    sc->override_count = override_count;
    snprintf(sc->path, sizeof sc->path, "%s", path);
    if (sc->name[0] == '\0') {
        /* the file's base name without .ini */
        const char *base = strrchr(path, '/');
        base = base != NULL ? base + 1 : path;
        snprintf(sc->name, sizeof sc->name, "%s", base);
        char *dot = strrchr(sc->name, '.');
        if (dot != NULL && strcmp(dot, ".ini") == 0) {
            *dot = '\0';
        }
    }
    return true;
}

/* ---------------------------------------------------------------------- */
/* where the scenarios are                                                 */
/* ---------------------------------------------------------------------- */

/* Candidate scenario directories: next to the binary (build tree or install),
 * then the source tree's (compiled in). */
static int scenario_dirs(const char *argv0, char dirs[2][SCENARIO_PATH_MAX])
{
    int n = 0;
    char exe[SCENARIO_PATH_MAX];
    const ssize_t len = readlink("/proc/self/exe", exe, sizeof exe - 1);
    if (len > 0) {
        exe[len] = '\0';
    } else {
        snprintf(exe, sizeof exe, "%s", argv0 != NULL ? argv0 : "");
    }
    char *slash = strrchr(exe, '/');
    if (slash != NULL) {
        *slash = '\0';
        if (strlen(exe) + 11 < SCENARIO_PATH_MAX) {
            memcpy(dirs[n], exe, strlen(exe));
            memcpy(dirs[n] + strlen(exe), "/scenarios", 11);
            n++;
        }
    }
    snprintf(dirs[n++], SCENARIO_PATH_MAX, "%s", SIM_SCENARIO_DIR);
    return n;
}

bool scenario_resolve(const char *name_or_path, const char *argv0, char *path, size_t path_len)
{
    const size_t len = strlen(name_or_path);
    if (strchr(name_or_path, '/') != NULL || (len > 4 && strcmp(name_or_path + len - 4, ".ini") == 0)) {
        snprintf(path, path_len, "%s", name_or_path);
        return access(path, R_OK) == 0;
    }
    char dirs[2][SCENARIO_PATH_MAX];
    const int n = scenario_dirs(argv0, dirs);
    for (int i = 0; i < n; i++) {
        snprintf(path, path_len, "%s/%s.ini", dirs[i], name_or_path);
        if (access(path, R_OK) == 0) {
            return true;
        }
    }
    return false;
}

static int compare_names(const void *a, const void *b)
{
    return strcmp((const char *)a, (const char *)b);
}

void scenario_list(const char *argv0, void (*emit)(const char *name, void *user), void *user)
{
    char dirs[2][SCENARIO_PATH_MAX];
    const int n = scenario_dirs(argv0, dirs);
    for (int i = 0; i < n; i++) {
        DIR *d = opendir(dirs[i]);
        if (d == NULL) {
            continue;
        }
        char names[64][SCENARIO_NAME_MAX];
        int count = 0;
        for (struct dirent *e = readdir(d); e != NULL && count < 64; e = readdir(d)) {
            const size_t len = strlen(e->d_name);
            if (len > 4 && len < SCENARIO_NAME_MAX && strcmp(e->d_name + len - 4, ".ini") == 0) {
                snprintf(names[count], SCENARIO_NAME_MAX, "%.*s", (int)(len - 4), e->d_name);
                count++;
            }
        }
        closedir(d);
        qsort(names, (size_t)count, sizeof names[0], compare_names);
        for (int k = 0; k < count; k++) {
            emit(names[k], user);
        }
        if (count > 0) {
            return;
        }
    }
}

/* ---------------------------------------------------------------------- */
/* Monte-Carlo                                                             */
/* ---------------------------------------------------------------------- */

/* A landing family: the heave's peak to peak and its longest period drawn
 * from absolute ranges (the shape of a wave set kept). */
static void perturb_pad_family(scenario *sc, rng *r)
{
    const montecarlo_params *mc = &sc->montecarlo;
    pad_params *pad = &sc->plant.pad;
    if (!isnan(mc->pad_amplitude_min_m) && !isnan(mc->pad_amplitude_max_m)) {
        const double peak_to_peak = rng_range(r, mc->pad_amplitude_min_m, mc->pad_amplitude_max_m);
        if (pad->model == PAD_SINE) {
            pad->amplitude_m = peak_to_peak;
        } else if (pad->model == PAD_WAVES) {
            double sum = 0.0;
            for (int k = 0; k < pad->wave_count; k++) {
                sum += pad->wave_amplitude_m[k];
            }
            for (int k = 0; k < pad->wave_count && sum > 0.0; k++) {
                pad->wave_amplitude_m[k] *= 0.5 * peak_to_peak / sum;
            }
        }
    }
    if (!isnan(mc->pad_period_min_s) && !isnan(mc->pad_period_max_s)) {
        const double period = rng_range(r, mc->pad_period_min_s, mc->pad_period_max_s);
        if (pad->model == PAD_SINE) {
            pad->omega_radps = 2.0 * PI / period;
        } else if (pad->model == PAD_WAVES) {
            /* every wave its own period in the range */
            pad->wave_omega_radps[0] = 2.0 * PI / period;
            for (int k = 1; k < pad->wave_count; k++) {
                pad->wave_omega_radps[k] = 2.0 * PI / rng_range(r, mc->pad_period_min_s, mc->pad_period_max_s);
            }
        }
    }
}

/* The failsafe family: a vertical accelerometer bias, the hover height the
 * fault hits (the reference's z_r_bias_m, CG above the pad, is that gear
 * height plus the gear's), whether the vehicle has a range finder. Drawn
 * after every other perturbation and each only when its keys are set, so the
 * draws of the scenarios without them are unchanged. */
static void perturb_failsafe_family(scenario *sc, rng *r)
{
    const montecarlo_params *mc = &sc->montecarlo;
    if (mc->accel_bias_max_mps2 > 0.0) {
        sc->sensors.imu.accel_bias_mps2.z += rng_range(r, -mc->accel_bias_max_mps2, mc->accel_bias_max_mps2);
    }
    if (!isnan(mc->fault_height_min_m)) {
        const double gear_height_m = rng_range(r, mc->fault_height_min_m, mc->fault_height_max_m);
        sc->fsw.ref_bias_m = gear_height_m + sc->plant.gear_height_m;
    }
    if (!isnan(mc->range_finder_probability) && rng_uniform(r) >= mc->range_finder_probability) {
        /* no range finder: a tracking platform takes its z from the position sensor */
        sc->range_finder = RANGE_FINDER_OFF;
        if (sc->mission.command == MISSION_TRACK && sc->sensors.altitude.source == ALTITUDE_RANGE) {
            sc->sensors.altitude.source = ALTITUDE_FROM_POSITION;
        }
    }
}

void scenario_perturb(scenario *sc, uint64_t seed)
{
    const montecarlo_params *mc = &sc->montecarlo;
    rng r;
    rng_seed(&r, seed, 100); /* stream 100: the perturbations (the sensors use 1..4) */
    plant_params *p = &sc->plant;
    /* mass_max_rel: the heaviest mass of the run, x the file's mass */
    const double mass_cap_kg = isnan(mc->mass_max_rel) ? (double)INFINITY : p->mass_kg * (1.0 + mc->mass_max_rel);
    const double mass_factor = 1.0 + rng_range(&r, -mc->mass_rel, fmin(mc->mass_rel, mc->mass_max_rel));
    p->mass_kg *= mass_factor;
    for (int k = 0; k < p->mass_step_count; k++) {
        p->mass_step_kg[k] *= mass_factor;
    }
    const double inertia_factor = 1.0 + rng_range(&r, -mc->inertia_rel, mc->inertia_rel);
    p->inertia_kgm2 = v3_scale(p->inertia_kgm2, inertia_factor);
    const double amp = 1.0 + rng_range(&r, -mc->pad_amplitude_rel, mc->pad_amplitude_rel);
    const double period = 1.0 + rng_range(&r, -mc->pad_period_rel, mc->pad_period_rel);
    p->pad.amplitude_m *= amp;
    p->pad.omega_radps /= period;
    for (int k = 0; k < p->pad.wave_count; k++) {
        p->pad.wave_amplitude_m[k] *= amp;
        p->pad.wave_omega_radps[k] /= period;
        p->pad.wave_phase_rad[k] = rng_range(&r, -PI, PI);
    }
    sc->sensors.noise_scale *= rng_range(&r, mc->noise_scale_min, mc->noise_scale_max);
    const int extra_steps = mc->delay_steps_max > 0 ? (int)(rng_uniform(&r) * (mc->delay_steps_max + 1)) : 0;
    sc->sensors.position.delay_s += extra_steps * sc->fsw.dt_s;
    sc->sensors.altitude.delay_s += extra_steps * sc->fsw.dt_s;
    sc->sensors.heading.delay_s += extra_steps * sc->fsw.dt_s;
    const double tau = 1.0 + rng_range(&r, -mc->motor_tau_rel, mc->motor_tau_rel);
    for (int i = 0; i < p->rotor_count; i++) {
        p->rotor[i].tau_s *= tau;
    }
    const int weak = (int)(rng_uniform(&r) * p->rotor_count);
    p->rotor[weak].efficiency *= rng_range(&r, mc->rotor_efficiency_min, mc->rotor_efficiency_max);
    sc->initial.x_m += rng_range(&r, -mc->initial_offset_m, mc->initial_offset_m);
    sc->initial.y_m += rng_range(&r, -mc->initial_offset_m, mc->initial_offset_m);
    p->ge_rho *= 1.0 + rng_range(&r, -mc->ground_effect_rho_rel, mc->ground_effect_rho_rel);
    perturb_pad_family(sc, &r);
    if (!isnan(mc->gust_std_max_mps)) {
        sc->wind.gust_std_mps = rng_range(&r, 0.0, mc->gust_std_max_mps);
    }
    /* drawn last, and only when asked for: the draws above (and so every
     * scenario without mass_step_rel) are as before */
    if (mc->mass_step_rel > 0.0 && p->mass_step_count < PLANT_MAX_MASS_STEPS) {
        const double t_step = rng_range(&r, mc->mass_step_time_min_s, mc->mass_step_time_max_s);
        /* the mass prevailing at t_step; the steps after it keep their masses */
        int at = 0;
        double mass_before = p->mass_kg;
        while (at < p->mass_step_count && p->mass_step_time_s[at] <= t_step) {
            mass_before = p->mass_step_kg[at];
            at++;
        }
        const double step_max = fmax(-mc->mass_step_rel, fmin(mc->mass_step_rel, mass_cap_kg / mass_before - 1.0));
        const double factor = 1.0 + rng_range(&r, -mc->mass_step_rel, step_max);
        for (int k = p->mass_step_count; k > at; k--) {
            p->mass_step_time_s[k] = p->mass_step_time_s[k - 1];
            p->mass_step_kg[k] = p->mass_step_kg[k - 1];
        }
        p->mass_step_time_s[at] = t_step;
        p->mass_step_kg[at] = mass_before * factor;
        p->mass_step_count++;
    }
    perturb_failsafe_family(sc, &r);
    /* a deck that rolls and pitches: its amplitudes and periods as the heave's,
     * random phases; drawn only then (the other scenarios' draws unchanged) */
    if (pad_tilts(&p->pad)) {
        p->pad.roll_amplitude_rad *= amp;
        p->pad.pitch_amplitude_rad *= amp;
        p->pad.roll_omega_radps /= 1.0 + rng_range(&r, -mc->pad_period_rel, mc->pad_period_rel);
        p->pad.pitch_omega_radps /= 1.0 + rng_range(&r, -mc->pad_period_rel, mc->pad_period_rel);
        p->pad.roll_phase_rad = rng_range(&r, -PI, PI);
        p->pad.pitch_phase_rad = rng_range(&r, -PI, PI);
    }
    /* last, and only when asked for (the other scenarios' draws unchanged):
     * the velocity-input vehicle's true response against the identified one */
    if (mc->velocity_response_rel > 0.0 && p->velocity_input) {
        const double a = mc->velocity_response_rel;
        double *k[6] = {&p->velocity_k_p_per_s.x, &p->velocity_k_p_per_s.y, &p->velocity_k_p_per_s.z,
                        &p->velocity_a_p_per_s.x, &p->velocity_a_p_per_s.y, &p->velocity_a_p_per_s.z};
        for (int i = 0; i < 6; i++) {
            *k[i] *= 1.0 + rng_range(&r, -a, a);
        }
    }
    sc->seed = seed;
}

double scenario_yaw_setpoint_rad(const mission_params *m, double t_s)
{
    const double since_start_s = t_s > m->track_start_s ? t_s - m->track_start_s : 0.0;
    return m->setpoint_yaw_rad + m->yaw_amplitude_rad * sin(2.0 * PI * m->yaw_frequency_hz * since_start_s);
}

double scenario_yaw_rate_setpoint_radps(const mission_params *m, double t_s)
{
    if (t_s <= m->track_start_s) {
        return 0.0;
    }
    const double w = 2.0 * PI * m->yaw_frequency_hz;
    return m->yaw_amplitude_rad * w * cos(w * (t_s - m->track_start_s));
}
