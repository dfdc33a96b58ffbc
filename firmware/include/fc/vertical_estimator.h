/*
 * fc/vertical_estimator.h - the vertical channel the safety logic flies on
 * when the position input is gone: vertical speed, the accelerometer's bias
 * along it, the vertical acceleration, the gear's height from the range
 * finder, and the hover thrust learnt in flight (SPEC "Safety contract").
 *
 * Speed and bias: a complementary filter on the world-z specific force,
 *     a = (R f)_z - g                        (R: body -> world, f: accelerometer)
 *     v' = a - b + l1 (v_m - v),   b' = -l2 (v_m - v)
 * while the vertical speed input v_m is good; its error obeys
 * s^2 + l1 s + l2 = 0, so l1 = 2 w_v, l2 = w_v^2 (critically damped, w_v the
 * speed crossover). Without v_m the speed runs on a - b alone: an unknown
 * bias b makes it drift at b m/s per second, which is why the bias is learnt
 * while v_m is there. Then it runs on the bias averaged over
 * bias_average_tau_s: v_m comes late (a motion-capture or GNSS delay of tens
 * of ms against an accelerometer that is not), so while the vehicle
 * oscillates the residual, and b with it, ripples; the average does not.
 * At rest (disarmed, before a flight) nothing ripples: the loop runs at
 * 3 w_v and the average is b itself, so a flight starts with the bias the
 * vehicle learnt on its pad (1.7 % of it left after 2 s at w_v = 1 rad/s). Without an accelerometer sample (an IMU lost) the
 * acceleration is the thrust's against the hover thrust, a = g (T k_h / T_h - 1):
 * dead reckoning on the thrust model, the one estimate left (FC_STEP_DEGRADED).
 * Gear height: h' = v; a fresh range sample h_m corrects it by a second
 * complementary loop of crossover w_h, h += 2 w_h T (h_m - h), with T the
 * time since the previous sample; without v_m it corrects the speed too,
 * v += w_h^2 T (h_m - h) (the speed then is relative to the surface below,
 * which is what a descent onto it needs).
 * Hover thrust: the thrust that holds the vehicle, T_h = T k_h g / (a + g),
 * averaged over hover_tau_s by the gradient step
 *     T_h += (dt / tau) (T k_h - T_h (a + g) / g)
 * (no division per step), only while the caller says the flight is clean
 * (airborne, inputs good, thrust not saturated); bounded to
 * [hover_min_n, hover_max_n]. It is what a mass the vehicle carries weighs:
 * unlike the altitude law's Theta, which also holds the ground effect and
 * the tilt, it is a thrust the failsafe and the land detector can compare
 * against.
 */
#ifndef FC_VERTICAL_ESTIMATOR_H
#define FC_VERTICAL_ESTIMATOR_H

#include <stdbool.h>

#include "fc/quat.h"
#include "fc/status.h"
#include "fc/vec3.h"

typedef struct fc_vertical_estimator_params {
    fc_real dt_s;                   /* DT: the fixed step */
    fc_real gravity_mps2;           /* ACCEL: (0, 100] */
    fc_real speed_crossover_radps;  /* RATIO: w_v, (0, 10] */
    fc_real height_crossover_radps; /* RATIO: w_h, (0, 10] */
    fc_real accel_bias_limit_mps2;  /* ACCEL: clamp of the bias estimate, (0, 5] */
    fc_real accel_tau_s;            /* DT: low-pass of the reported acceleration, [dt, 1] */
    fc_real bias_average_tau_s;     /* TIME: averaging of the bias flown on without v_m, [0.1, 100] */
    fc_real hover_tau_s;            /* TIME: averaging time of the hover thrust, [0.1, 100] */
    fc_real hover_thrust_n;         /* FORCE: before anything is learnt (nominal m g), > 0 */
    fc_real hover_min_n;            /* FORCE: bounds of the learnt value, */
    fc_real hover_max_n;            /* FORCE: 0 < min <= hover_thrust_n <= max */
    fc_real range_period_max_s;     /* DT: a longer gap between range samples counts as this, (0, 1] */
} fc_vertical_estimator_params;

typedef struct fc_vertical_estimator_input {
    const fc_quat *attitude;        /* UNIT: body -> world, of unit length (read at UNIT16); by
                                     * pointer, as the accelerometer sample: the caller's own,
                                     * not copied for each step */
    const fc_vec3 *accel_mps2;      /* ACCEL: specific force, body (read when accel_ok) */
    bool accel_ok;                  /* accel_mps2 is a good sample */
    fc_real vz_mps;                 /* VEL: measured vertical speed, world */
    bool vz_ok;                     /* vz_mps is a good sample */
    fc_real gear_height_m;          /* LENGTH: from the range finder */
    bool gear_height_fresh;         /* a new sample this step */
    fc_real thrust_n;               /* FORCE: the body thrust in force over this step */
    fc_real tilt_cos;               /* RATIO: k_h */
    bool learn_hover;               /* clean flight: the hover thrust may learn */
    bool at_rest;                   /* disarmed, on the ground: the bias is learnt fast */
} fc_vertical_estimator_input;

typedef struct fc_vertical_estimate {
    fc_real vz_mps;                 /* VEL: world (relative to the surface when only the range corrects it) */
    fc_real accel_z_mps2;           /* ACCEL: world, bias removed, low-passed */
    fc_real accel_bias_mps2;        /* ACCEL: the averaged bias */
    fc_real gear_height_m;          /* LENGTH: 0 until the first range sample */
    fc_real hover_thrust_n;         /* FORCE: vertical thrust that holds the vehicle */
    bool gear_height_known;         /* a range sample has been seen */
} fc_vertical_estimate;

typedef struct fc_vertical_estimator {
    fc_vertical_estimator_params p;
    /* the constants the step multiplies a signal by, as gains (fc/scalar.h,
     * fc_gain: a 16-bit mantissa and its own exponent in fixed) */
    fc_gain dt;                     /* dt, s */
    fc_gain speed_gain;             /* l1 dt = 2 w_v dt */
    fc_gain bias_gain_per_s;        /* l2 dt = w_v^2 dt, 1/s */
    fc_gain speed_gain_rest;        /* 3 l1 dt: at rest */
    fc_gain bias_gain_rest_per_s;   /* 9 l2 dt */
    fc_gain height_gain_per_s;      /* 2 w_h, times T a sample */
    fc_gain height_speed_gain_per_s2; /* w_h^2, times T a sample */
    fc_gain accel_filter_gain;      /* dt / accel_tau */
    fc_gain hover_gain;             /* dt / hover_tau */
    fc_gain bias_average_gain;      /* dt / bias_average_tau */
    fc_gain gravity_mps2;           /* g */
    fc_gain inv_gravity_s2pm;       /* 1 / g */
    fc_real bias_fast_mps2;         /* ACCEL: b of the complementary loop */
    fc_real range_gap_s;            /* DT: since the last range sample */
    fc_vertical_estimate est;
    bool ready;
    fc_arith ar;
} fc_vertical_estimator;

/* Crossovers 1 rad/s (speed and bias) and 2 rad/s (gear height), bias limit
 * 0.5 m/s^2 and averaged over 2 s, acceleration low-passed over 50 ms, hover thrust averaged over
 * 2 s inside [0.5, 1.5] x the nominal weight, range gaps counted up to 0.1 s. */
void fc_vertical_estimator_default_params(fc_vertical_estimator_params *p, fc_real dt_s, fc_real gravity_mps2,
                                          fc_real weight_n);

/* The hover thrust before it is learnt (the weight) and its bounds, [0.5, 1.5] x it. */
void fc_vertical_estimator_set_weight(fc_vertical_estimator_params *p, fc_real weight_n);

fc_init_result fc_vertical_estimator_init(fc_vertical_estimator *v, const fc_vertical_estimator_params *p);

/* Speed, bias and acceleration back to zero, the gear height unknown; the
 * learnt hover thrust is kept (it is the vehicle's, not the flight's). */
void fc_vertical_estimator_reset(fc_vertical_estimator *v);

fc_step_status fc_vertical_estimator_step(fc_vertical_estimator *v, const fc_vertical_estimator_input *in,
                                          fc_vertical_estimate *out);

#endif /* FC_VERTICAL_ESTIMATOR_H */
