/*
 * plant.h - the multirotor, the pad and their contact, in double precision.
 *
 * State (world ENU, body FLU, q body -> world):
 *   p, v       centre of mass position and velocity, world
 *   q          attitude; w body angular velocity
 *   m          mass, m' = (mu(t) - m) / tau_m: the filter 1/(tau_m s + 1) of (4.84)
 *   u_i        normalised rotor speeds, u_i' = (u_cmd,i - u_i) / tau_i (first-order motor lag)
 * Equations ((2.1), (3.3) in vector form):
 *   p' = v
 *   m v' = R F_b + F_contact - c_d (v - v_wind) - m g e_z
 *   q' = 1/2 q (x) [0, w]
 *   I(m) w' = M_b + M_contact + M_disturbance - w x I(m) w
 * Rotors (2.2)-(2.3): T_i = eff_i T_max,i u_i^r_i along d_i, Q_i = eff_i Q_max,i u_i^s_i
 * along d_i (Q_max signed by the spin), the thrust scaled by the ground-effect
 * gain (3.2) of that rotor's height above the pad,
 *   k_g,i = 1 / (1 - rho (R / (4 h_i))^2),  h_i >= h_min,i (the rotor's height when the gear touches),
 * F_b = sum k_g,i T_i d_i,  M_b = sum l_i x (k_g,i T_i d_i) + Q_i d_i.
 * Contact: each foot of the landing gear below the pad's plane pushes back with
 * a spring-damper k d + c d' (never pulling) and slides against regularised Coulomb
 * friction mu F_n v_t / sqrt(|v_t|^2 + v_s^2).
 * A deck that rolls and pitches (pad roll/pitch amplitudes > 0): the pad's
 * plane turns about its centre (0, 0, z_pad) with R_pad = R_y(pitch) R_x(roll),
 * normal n = R_pad e_z; a foot's depth is measured along n, the spring-damper
 * pushes along n against the foot's speed relative to the surface point under
 * it (v_pad e_z + w_pad x r), friction acts on the tangential part of that
 * relative speed; a rotor's ground-effect height is its distance from the
 * plane along n. With both amplitudes 0 the level pad's code runs unchanged.
 * Integration: classical RK4 at the plant step, inputs (u_cmd) held over the step;
 * q is renormalised after each step. m' v and I' w are neglected ((H2.a), (H2.b)).
 *
 * Velocity input (velocity_input, the Matrice 600 case of dissertation 2.6.6):
 * the vehicle's own autopilot takes a world velocity command u and yaw rate
 * r and flies its rotors so that, in free air, each axis follows the
 * first-order response (2.18)-(2.23)
 *   v' = -a_P v + k_P u   (per axis, k_P and a_P of velocity_k_p, velocity_a_p),
 * i.e. its thrust is F = m (-a_P v + k_P u + g e_z) + c_d v (the drag at v is
 * part of the identified response; wind acts through c_d wind / m), with F_z
 * in [0, thrust_max] and the tilt of F at most velocity_tilt_max. The
 * thrust |F| acts along body z; the vehicle's attitude loop (a PD at 20 rad/s,
 * far faster than the translation, as 2.6.6 assumes) turns body z towards
 * F's direction at the heading psi, psi' = r, against the contact's moments. Contact and friction as above act on the
 * CG; ground effect and the rotor states are not modelled (its velocity
 * loop absorbs the first). Motors off: F = 0.
 */
#ifndef SIM_PLANT_H
#define SIM_PLANT_H

#include <stdbool.h>

#include "vmath.h"

#define PLANT_MAX_ROTORS 8
#define PLANT_MAX_FEET 8
#define PAD_MAX_WAVES 8
#define PLANT_MAX_MASS_STEPS 8

typedef enum pad_model { PAD_STILL = 0, PAD_SINE, PAD_WAVES } pad_model;

/* The pad's height: still (base), (3.1) z = base + A/2 sin(w t) + A/2, or a
 * sum of sinusoids base + sum a_k sin(w_k t + phi_k). */
typedef struct pad_params {
    pad_model model;
    double base_m;
    double amplitude_m;   /* A of (3.1): peak to peak */
    double omega_radps;   /* w of (3.1) */
    int wave_count;
    double wave_amplitude_m[PAD_MAX_WAVES];
    double wave_omega_radps[PAD_MAX_WAVES];
    double wave_phase_rad[PAD_MAX_WAVES];
    /* a fault: from growth_start_s (INFINITY: never) the heave grows to growth_scale times (0: off) */
    double growth_start_s, growth_duration_s, growth_scale;
    /* a fault: from warp_start_s the pad's clock runs warp_factor times faster (its
     * frequencies scale, the motion stays continuous; 0: off) */
    double warp_start_s, warp_factor;
    /* a deck's roll and pitch (rad): amplitude sin(omega t + phase); 0: level */
    double roll_amplitude_rad, roll_omega_radps, roll_phase_rad;
    double pitch_amplitude_rad, pitch_omega_radps, pitch_phase_rad;
} pad_params;

typedef struct pad_state {
    double z_m, vz_mps, az_mps2;
    double roll_rad, pitch_rad, roll_rate_radps, pitch_rate_radps; /* 0 for a level pad */
} pad_state;

void pad_eval(const pad_params *p, double t, pad_state *out);

/* Whether the pad rolls or pitches (the tilting model of the contact is used). */
bool pad_tilts(const pad_params *p);

/* The pad's attitude (pad -> world, R_y(pitch) R_x(roll)), its normal n and
 * angular velocity (world). */
quat pad_attitude(const pad_state *pad);
v3 pad_normal(const pad_state *pad);
v3 pad_angular_velocity(const pad_state *pad);

/* Height of the world point x above the pad's plane along its normal. */
double pad_height_of(const pad_state *pad, v3 x);

typedef struct plant_rotor {
    v3 position_m;        /* l_i, body */
    v3 axis;              /* d_i, body, unit */
    double thrust_max_n;  /* T_max */
    double torque_max_nm; /* Q_max, signed: + reacts along +d_i */
    double thrust_exponent, torque_exponent; /* r, s */
    double speed_min;     /* u_min: the slowest a running motor turns */
    double tau_s;         /* motor lag; 0: none */
    double efficiency;    /* scales T and Q (a damaged or weak rotor < 1) */
} plant_rotor;

typedef struct plant_params {
    double mass_kg;               /* at t = 0 */
    v3 inertia_kgm2;              /* diagonal, at mass_kg */
    v3 inertia_per_kg;            /* dI/dm: I(m) = I0 + (m - m0) dI/dm (0: a payload at the CG) */
    double gravity_mps2;
    double drag_n_per_mps;        /* linear drag on the CG velocity (0: none) */
    int rotor_count;
    plant_rotor rotor[PLANT_MAX_ROTORS];
    /* mass change (4.84): mu steps to step_mass[k] at step_time[k] */
    double mass_tau_s;
    int mass_step_count;
    double mass_step_time_s[PLANT_MAX_MASS_STEPS];
    double mass_step_kg[PLANT_MAX_MASS_STEPS];
    /* ground effect (3.2) */
    bool ground_effect;
    double ge_radius_m, ge_rho;
    /* landing gear and contact */
    double gear_height_m;         /* CG to the bottom of the gear, along body -z */
    int foot_count;
    v3 foot_m[PLANT_MAX_FEET];    /* body */
    bool contact;
    double contact_stiffness_n_per_m; /* per foot */
    double contact_damping_ns_per_m;  /* per foot */
    double friction;
    double slip_speed_mps;
    pad_params pad;
    /* a velocity-input vehicle (above) */
    bool velocity_input;
    v3 velocity_k_p_per_s, velocity_a_p_per_s;
    double velocity_thrust_max_n;
    double velocity_tilt_max_rad;
} plant_params;

#define PLANT_STATE_DIM (3 + 3 + 4 + 3 + 1 + PLANT_MAX_ROTORS)

typedef union plant_state {
    struct {
        v3 p, v;
        quat q;
        v3 w;
        double m;
        double u[PLANT_MAX_ROTORS];
    };
    double x[PLANT_STATE_DIM]; /* the same, as one vector for the RK4 combination */
} plant_state;

/* What the model computes besides the derivative (at one time and state). */
typedef struct plant_diag {
    v3 specific_force_b;   /* what an ideal accelerometer at the CG reads */
    v3 force_b, moment_b;  /* rotors only */
    v3 contact_force_w;
    double rotor_thrust_n[PLANT_MAX_ROTORS]; /* k_g T_i */
    double ground_gain;    /* thrust-weighted mean of k_g,i (the k_g of (3.4)) */
    double ground_gain_rotor[PLANT_MAX_ROTORS];
    double gear_clearance_m; /* lowest foot above the pad (negative: penetration) */
    int feet_in_contact;
    double mass_target_kg;
    pad_state pad;
} plant_diag;

typedef struct plant {
    plant_params p;
    plant_state s;
    double t;
    double u_cmd[PLANT_MAX_ROTORS]; /* held over the step */
    v3 wind_mps;                    /* air velocity, world: the drag acts on v - wind (held over the step) */
    v3 disturbance_moment_b;        /* an external body moment (held over the step) */
    double pad_cache_t;             /* the pad at the end of the last step */
    pad_state pad_cache;
    /* computed at init from p */
    v3 lever[PLANT_MAX_ROTORS];     /* l_i x d_i */
    double height_min[PLANT_MAX_ROTORS];
    double ge_c;                    /* rho (R/4)^2: k_g = h^2 / (h^2 - c) */
    /* velocity input: the command held over the step, the heading */
    v3 velocity_cmd_mps;
    double yaw_rate_cmd_radps;
    bool velocity_motors_on;
    double yaw_rad;
} plant;

/* Checks what the model needs (positive masses and inertias, the ground-effect
 * floor above the singularity, ...): NULL if fine, or a reason. */
const char *plant_params_check(const plant_params *p);

/* Ground-effect gain (3.2) at height h (no floor applied): 1/(1 - rho (R/(4h))^2). */
double plant_ground_gain(double radius_m, double rho, double height_m);

/* The lowest height a rotor can be at (gear touching a level pad). */
double plant_rotor_height_min(const plant_params *p, int i);

void plant_init(plant *pl, const plant_params *p, const plant_state *s0);

/* Rotor speeds for a level hover at the current height: sum k_g,i T_i = m g
 * with one common u (bisection). Returns that u, or -1 when it needs u > 1. */
double plant_hover_speed(const plant *pl);

/* Commanded normalised speeds (0 = motor off, otherwise clamped to [u_min, 1]). */
void plant_set_command(plant *pl, const double *u_cmd, int count);

/* Velocity input: the command (world, m/s), the yaw rate (rad/s) and
 * whether the motors run; a command that is not finite counts as 0. */
void plant_set_velocity_command(plant *pl, v3 velocity_mps, double yaw_rate_radps, bool motors_on);

/* One RK4 step of h seconds. */
void plant_step(plant *pl, double h);

/* Derivative and diagnostics at the current time and state (no step). */
void plant_diagnose(const plant *pl, plant_diag *d);

/* The lowest foot's height above the pad at the current time and state
 * (negative: penetration), and the pad then in *pad (if not NULL), without
 * the rest of plant_diagnose. */
double plant_gear_clearance(const plant *pl, pad_state *pad);

/* Mechanical energy (kinetic + rotational + potential, with z = 0 as reference). */
double plant_energy(const plant *pl);

/* Angular momentum in the world frame. */
v3 plant_angular_momentum_world(const plant *pl);

/* The mass target mu(t) of (4.84). */
double plant_mass_target(const plant_params *p, double t);

/* Inertia at mass m. */
v3 plant_inertia(const plant_params *p, double m);

#endif /* SIM_PLANT_H */
