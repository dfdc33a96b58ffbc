/*
 * fc/failsafe.h - the input guard and the failsafe descent (SPEC "Safety
 * contract"): when the inputs the mission flies on are gone, come down at a
 * held rate and stop the motors only once the land detector says LANDED.
 *
 * Guard (fc_failsafe_watch, every step):
 *   inputs bad (not finite, out of range, or rejected by the plausibility
 *   gates of fc_controller): HOLD for bad_input_hold_s, flying on the last
 *   good ones with the altitude law's adaptation and integrators frozen;
 *   beyond it, or at once when there never were good inputs: ACTIVE.
 *   IMU bad (a gyro or accelerometer sample not usable) longer than
 *   imu_timeout_s: ACTIVE.
 *   ACTIVE ends when every input has been good for bad_input_hold_s again.
 * Descent (fc_failsafe_step, while ACTIVE): a vertical-speed loop with
 * integral action around the learnt hover thrust T_h (fc/vertical_estimator.h),
 *     e = v_sp - v,   I += k_i e dt (|I| <= integral_limit),
 *     a = k_p e + I + v_sp' (|a| <= accel_limit),   T k_h = T_h (1 + a / g),
 * so neither a wrong nominal mass (T_h is learnt; I takes what is left) nor
 * the altitude law (its Theta holds the ground effect and the tilt, not the
 * mass) sets the rate. k_i = k_p^2 / 4 puts both poles of the speed error at
 * -k_p / 2. The setpoint v_sp starts at the speed the vehicle has when the
 * failsafe begins and moves to -descent at setpoint_accel, its rate fed
 * forward: a step from there (or a ramp the integral had to follow) leaves
 * an integral that overshoots the rate by some 14 % of the step (e^-2).
 * Once the land detector sees ground contact the integral is held
 * and the thrust ramps down, T_h dt / ramp_s a step; any sign of flight
 * returns the loop (the land detector's AIRBORNE).
 */
#ifndef FC_FAILSAFE_H
#define FC_FAILSAFE_H

#include <stdbool.h>

#include "fc/land_detector.h"
#include "fc/scalar.h"
#include "fc/status.h"

typedef enum fc_failsafe_cause {
    FC_FAILSAFE_NONE = 0,
    FC_FAILSAFE_INPUTS_LOST,    /* position, velocity, setpoints or the pad bad too long */
    FC_FAILSAFE_IMU_LOST        /* no usable IMU sample for imu_timeout_s */
} fc_failsafe_cause;

typedef struct fc_failsafe_params {
    fc_real dt_s;                 /* DT: the fixed step */
    fc_real gravity_mps2;         /* ACCEL */
    fc_real bad_input_hold_s;     /* TIME: [0, 10] */
    fc_real imu_timeout_s;        /* TIME: [0, 10] */
    fc_real descent_mps;          /* VEL: (0, 5] */
    fc_real speed_gain_per_s;     /* GAIN: k_p, (0, 50] */
    fc_real integral_limit_mps2;  /* ACCEL: (0, 10] */
    fc_real accel_limit_mps2;     /* ACCEL: (0, 10] */
    fc_real ramp_s;               /* TIME: hover thrust to zero once in contact, (0, 10] */
    fc_real setpoint_accel_mps2;  /* ACCEL: how fast the speed setpoint reaches -descent, (0, 10] */
} fc_failsafe_params;

typedef struct fc_failsafe_watch_input {
    bool armed;                   /* flying a command */
    bool inputs_ok;               /* this step's position, velocity, setpoints, pad usable */
    bool had_good_inputs;         /* there are last good ones to hold */
    bool imu_ok;                  /* this step's IMU sample usable */
} fc_failsafe_watch_input;

typedef struct fc_failsafe_watch_output {
    bool active;                  /* fly the failsafe descent */
    bool hold;                    /* inputs bad, within the hold: fly the last good ones, frozen */
    bool entered;                 /* became active at this step */
    bool left;                    /* stopped being active at this step */
    fc_failsafe_cause cause;
} fc_failsafe_watch_output;

typedef struct fc_failsafe_input {
    fc_real vz_mps;               /* VEL: the vertical speed estimate */
    fc_real hover_thrust_n;       /* FORCE: learnt */
    fc_real tilt_cos;             /* RATIO: k_h */
    fc_real thrust_min_n;         /* FORCE: body thrust limits */
    fc_real thrust_max_n;         /* FORCE */
    fc_land_state land_state;
} fc_failsafe_input;

typedef struct fc_failsafe {
    fc_failsafe_params p;
    fc_real speed_integral_gain;  /* RATIO: k_i dt = (k_p^2 / 4) dt, a step */
    fc_real setpoint_step_mps;    /* VEL: setpoint_accel dt */
    fc_real inv_dt_per_s;         /* GAIN: 1 / dt */
    fc_real speed_setpoint_mps;   /* VEL: v_sp */
    bool setpoint_started;
    fc_real inv_gravity_s2pm;     /* RATIO: 1 / g */
    fc_real ramp_gain;            /* UNIT: dt / ramp_s */
    fc_real step_s;               /* TIME: dt */
    fc_real bad_input_s;          /* TIME: inputs bad this long */
    fc_real good_input_s;         /* TIME: everything good again this long (while active) */
    fc_real imu_bad_s;            /* TIME: no usable IMU sample this long */
    fc_real integral_mps2;        /* ACCEL: I */
    fc_real ramp_thrust_n;        /* FORCE: the vertical thrust while ramping down */
    bool ramping;
    bool active;
    fc_failsafe_cause cause;
    bool ready;
    fc_arith ar;
} fc_failsafe;

/* Hold 0.5 s, IMU timeout 50 ms, k_p = 2 /s, |I| <= 3 and |a| <= 4 m/s^2, the
 * setpoint at 1 m/s^2, a ramp of 1 s; the descent rate is the airframe's
 * (fc_controller). */
void fc_failsafe_default_params(fc_failsafe_params *p, fc_real dt_s, fc_real gravity_mps2, fc_real descent_mps);

fc_init_result fc_failsafe_init(fc_failsafe *f, const fc_failsafe_params *p);

/* Not active, timers and loop cleared (disarmed). */
void fc_failsafe_reset(fc_failsafe *f);

/* The guard: one step of the timers above. */
fc_failsafe_watch_output fc_failsafe_watch(fc_failsafe *f, const fc_failsafe_watch_input *in);

/* The descent's body thrust for this step (FORCE, inside the limits). */
fc_real fc_failsafe_step(fc_failsafe *f, const fc_failsafe_input *in);

#endif /* FC_FAILSAFE_H */
