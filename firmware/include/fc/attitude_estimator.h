/*
 * fc/attitude_estimator.h - complementary attitude filter (dissertation §2.5).
 *
 * The gyro is integrated on the unit quaternion (fc_quat_advance_body_rate:
 * q + q (x) [0, w dt/2] brought back to unit length, 16 x 16-bit products in
 * fixed; the exponential map for half-angles w_i dt/2 beyond 2^-5 rad); the
 * accelerometer's gravity direction corrects the roll and pitch through a PI
 * law on the direction error (the explicit complementary filter of Mahony,
 * Hamel and Pflimlin, 2008):
 *
 *   v_hat = R(q)^T e_z                 estimated up direction, body frame
 *   v_a   = a / |a|                    measured up direction (specific force)
 *   e     = v_a x v_hat                direction error (|e| = sin of the tilt error)
 *   w     = trust(|a|) in [0, 1]       1 at |a| = g, 0 at ||a| - g| >= band
 *   q    <- q (x) exp((gyro - b + Kp w e) dt / 2)
 *   b    <- clamp(b - Ki dt w e, +-gyro_bias_limit)
 *
 * Linearised about a small tilt error theta under a constant gyro bias beta,
 * theta'' + Kp theta' + Ki theta = beta', so with Kp = 2 zeta w_c and
 * Ki = w_c^2 the tilt error is a second-order system of natural frequency w_c
 * and damping zeta, and the bias estimate b converges to beta (its components
 * perpendicular to the up direction; the heading is not observable from
 * gravity, so neither is the bias about the up axis).
 *
 * Heading: gravity says nothing of the yaw, which follows the gyro's bias
 * about the up axis unless something else measures it (a motion-capture or
 * lighthouse yaw, a compass). fc_attitude_estimator_take_heading gives the
 * filter such a sample, psi_m; for heading_hold_s after it each step adds the
 * heading error as a second direction error, about the estimated up axis:
 *
 *   h     = (R(q) e_x)_xy               the body x axis's horizontal part, world
 *   s     = h x (cos psi_m, sin psi_m)  = |h| sin(psi_m - psi); +-1 beyond 90 deg
 *   e_h   = s v_hat                     the rotation about the up axis, body frame
 *   q    <- ... + Kp w_h e_h,  b <- clamp(b - Ki dt w_h e_h)  after the tilt's
 *
 * e_h is perpendicular to e, so the two loops do not mix: with heading_weight
 * w_h the heading error is the same second-order system as the tilt's, of
 * natural frequency sqrt(w_h) w_c and damping sqrt(w_h) zeta, and the bias
 * about the up axis becomes observable and is estimated. A sample held at the
 * end of the alignment gives its initial yaw (0 without one). A held sample
 * is not turned with the gyro: turning at r rad/s with samples every T s the
 * estimate lags the yaw by r (T - dt) / 2, the samples' mean age, besides the
 * sensor's own delay (4 mrad at 1 rad/s, samples at 100 Hz, steps at 500 Hz:
 * computed and measured).
 *
 * Alignment: the first alignment_samples valid accelerometer samples are
 * averaged; roll and pitch come from the mean (yaw 0). Until then the output
 * attitude is the identity and `aligned` is false (status FC_STEP_OK).
 *
 * Bad input (a non-finite component, a zero-length accelerometer vector, a
 * gyro component beyond gyro_range, an accelerometer component beyond
 * accel_range, a gyro component further from the last good sample than
 * gyro_jump_radps + gyro_accel_max_radps2 t, t since that sample: a glitch no
 * airframe flies) sets FC_STEP_BAD_INPUT; a bad accelerometer sample gives a
 * gyro-only step (weight 0, bias held), a bad gyro sample holds the attitude,
 * the bias and the last good rate. FC_STEP_DEGRADED marks an aligned step
 * without accelerometer correction (weight 0).
 *
 * Parameter ranges (init returns FC_INIT_BAD_PARAM outside them); the upper
 * bounds keep every fixed-point intermediate inside its format:
 *   dt_s                   (0, 0.1] s
 *   crossover_radps        (0, 10] rad/s, and crossover * dt <= 0.1
 *   damping                (0, 10], and Kp = 2 zeta w_c <= 20 rad/s, Kp dt <= 0.5
 *   gyro_bias_limit_radps  [0, 0.8] rad/s
 *   gravity_mps2           [1, 100] m/s2
 *   accel_trust_band_mps2  [0.01 m/s2, gravity)  (trust is 0 in free fall)
 *   gyro_range_radps       (0, 100] rad/s, and gyro_range * dt <= 2 rad
 *   accel_range_mps2       (gravity, 256] m/s2
 *   gyro_jump_radps        [0, 100] rad/s, 0: no check of the change
 *   gyro_accel_max_radps2  (0, 30000] rad/s2, and times dt <= 100 rad/s
 *   alignment_samples      [1, 32767]
 *   heading_weight         [0, 1]; above 0 also gyro_range + bias_limit + 2 Kp <= 127 rad/s
 *   heading_hold_s         [dt_s, 1] s
 */
#ifndef FC_ATTITUDE_ESTIMATOR_H
#define FC_ATTITUDE_ESTIMATOR_H

#include <stdbool.h>
#include <stdint.h>

#include "fc/quat.h"
#include "fc/status.h"
#include "fc/vec3.h"

typedef struct fc_attitude_estimator_params {
    fc_real dt_s;                  /* DT: the fixed step */
    fc_real crossover_radps;       /* RATE: w_c, natural frequency of the tilt-error loop */
    fc_real damping;               /* RATIO: zeta; Kp = 2 zeta w_c, Ki = w_c^2 */
    fc_real gyro_bias_limit_radps; /* RATE: clamp of each bias component */
    fc_real gravity_mps2;          /* ACCEL: g, the specific force at rest */
    fc_real accel_trust_band_mps2; /* ACCEL: trust 1 at |a| = g, falling linearly to 0 at
                                    * ||a| - g| = band */
    fc_real gyro_range_radps;      /* RATE: a gyro component beyond this is bad input */
    fc_real accel_range_mps2;      /* ACCEL: an accel component beyond this is bad input */
    fc_real gyro_jump_radps;       /* RATE: a gyro component's change beyond this ... */
    fc_real gyro_accel_max_radps2; /* GAIN: ... plus this times the time since the last good
                                    * sample is bad input (the airframe's angular acceleration) */
    uint16_t alignment_samples;    /* valid accel samples averaged for the initial attitude */
    fc_real heading_weight;        /* RATIO: w_h, the heading loop's gains relative to the tilt
                                    * loop's; 0: no heading correction (a sample still gives
                                    * the alignment its yaw) */
    fc_real heading_hold_s;        /* DT: how long a heading sample keeps correcting */
} fc_attitude_estimator_params;

typedef struct fc_imu_sample {
    fc_vec3 gyro_radps; /* RATE, body frame (FLU) */
    fc_vec3 accel_mps2; /* ACCEL, body frame, specific force: level at rest reads (0, 0, +g) */
} fc_imu_sample;

typedef struct fc_attitude_estimate {
    fc_quat attitude;        /* UNIT, body -> world; the identity until aligned */
    fc_vec3 rate_radps;      /* RATE, body: gyro minus the bias estimate */
    fc_vec3 gyro_bias_radps; /* RATE, body: the bias estimate */
    fc_real accel_weight;    /* RATIO in [0, 1]: the accelerometer trust used in this step */
    bool aligned;            /* false until the initial alignment is complete */
    bool gyro_ok;            /* this step's gyro sample was usable (else rate_radps is an old one) */
    bool accel_ok;           /* this step's accelerometer sample was usable */
} fc_attitude_estimate;

typedef struct fc_attitude_estimator {
    fc_arith ar;                       /* saturation record of the current step */
    fc_attitude_estimator_params p;    /* the validated parameters (formats as above) */
    fc_real16 kp16_radps;              /* RATE16: Kp = 2 zeta w_c <= 20, rad/s per unit of |e| */
    fc_real16 ki_dt16;                 /* Q(ki_dt16_frac): Ki dt = w_c^2 dt <= 1, the bias
                                        * step (rad/s) per unit of |e| */
    uint8_t ki_dt16_frac;              /* 26, 22, 18 or 14: the finest that holds Ki dt */
    fc_real inv_band_s2pm;             /* RATIO: 1 / accel_trust_band (<= 100) */
    fc_real inv_alignment_samples;     /* UNIT: 1 / alignment_samples */
    fc_real gyro_bias_limit_fine;      /* UNIT (Q30 holding rad/s): the bias clamp */
    fc_real half_dt_s;                 /* DT: dt / 2, the integration's factor */
    fc_quat attitude;                  /* UNIT: body -> world */
    fc_vec3 gyro_bias_fine;            /* UNIT (Q30 holding rad/s, |b| <= 0.8): the bias
                                        * estimate, held finer than RATE so that the small
                                        * per-step increments Ki dt w e are not rounded away */
    fc_vec3 gyro_bias_radps;           /* RATE: gyro_bias_fine rounded, as the rate and the
                                        * output read it */
    fc_vec3 rate_radps;                /* RATE: last good bias-corrected rate */
    fc_vec3 last_gyro_radps;           /* RATE: the last good gyro sample */
    fc_real gyro_slack_radps;          /* RATE: the change a next sample may make */
    fc_real gyro_slack_step_radps;     /* RATE: gyro_accel_max dt */
    bool have_gyro;                    /* last_gyro_radps holds a sample */
    bool coasting;                     /* fc_attitude_estimator_coast */
    fc_acc alignment_sum[3];           /* ACCEL x UNIT products: running sum of
                                        * a_i / alignment_samples, rounded once at the end
                                        * (bounded by max |a| whatever the sample count) */
    fc_real accel_weight;              /* RATIO: trust of the last step */
    fc_real heading_cos, heading_sin;  /* UNIT: of the newest heading sample */
    fc_real heading_rad;               /* ANGLE: the newest heading sample, for the alignment */
    uint16_t heading_hold_steps;       /* heading_hold_s in steps, round(hold / dt) >= 1 */
    uint16_t heading_steps_left;       /* steps the newest sample still corrects (0: none) */
    uint16_t alignment_count;          /* valid samples averaged so far */
    bool aligned;                      /* the alignment is complete */
    bool ready;                        /* init succeeded */
} fc_attitude_estimator;

/* Sensible defaults for a step of dt_s (DT): w_c = 1 rad/s, zeta = 0.7071
 * (Kp = 1.414 rad/s, Ki = 1 s^-2), bias limit 0.2 rad/s, g = 9.81 m/s2, trust
 * band 2 m/s2, gyro range 35 rad/s (2000 deg/s), accel range 16 g, gyro
 * changes of 2 rad/s plus 1000 rad/s^2 a second (the controller sets its
 * airframe's), 100
 * alignment samples, heading weight 1 (the tilt's gains), held 0.1 s (a sample
 * at 10 Hz or faster corrects all the time). */
void fc_attitude_estimator_default_params(fc_attitude_estimator_params *p, fc_real dt_s);

/* Validates p (ranges above), computes Kp, Ki dt, 1/band and 1/alignment_samples,
 * and starts the alignment. On FC_INIT_BAD_PARAM the state is safe: its step
 * reports FC_STEP_NOT_READY with the identity attitude. */
fc_init_result fc_attitude_estimator_init(fc_attitude_estimator *est,
                                          const fc_attitude_estimator_params *p);

/* A heading measurement (ANGLE, yaw about the world's up axis, |yaw| <= 7 rad)
 * for the steps of the next heading_hold_s; give it before the step of its
 * time. FC_STEP_BAD_INPUT (the sample ignored) for a non-finite or larger
 * value, FC_STEP_NOT_READY before a successful init. */
fc_step_status fc_attitude_estimator_take_heading(fc_attitude_estimator *est, fc_real yaw_rad);

/* Coasting: the gyro alone, the bias as learnt, no accelerometer correction
 * (FC_STEP_DEGRADED). For flight with nothing that holds the vehicle still
 * (the failsafe, its position lost): a multirotor's accelerometer then reads
 * along its thrust axis, so the correction would take any tilt for level and
 * the bias for what its drift needs, while the vehicle accelerates sideways;
 * with a held position it reads gravity, and the correction is right. */
void fc_attitude_estimator_coast(fc_attitude_estimator *est, bool coast);

/* One step of dt_s with one IMU sample; out is always written and finite. */
fc_step_status fc_attitude_estimator_step(fc_attitude_estimator *est, const fc_imu_sample *imu,
                                          fc_attitude_estimate *out);

/* The step for a vehicle whose attitude comes from elsewhere (the platform's
 * own estimator, fc_controller_params.use_external_attitude): the IMU sample
 * checked as fc_attitude_estimator_step checks it and the rate formed with the
 * bias as it stands (zero if the filter never ran), gyro - b; no alignment,
 * correction or integration. FC_STEP_BAD_INPUT as in the full step (the rate
 * of the last good sample kept); out is always written and finite, its
 * attitude the filter's (not advanced), its accel_weight 0. */
fc_step_status fc_attitude_estimator_rate_step(fc_attitude_estimator *est, const fc_imu_sample *imu,
                                               fc_attitude_estimate *out);

#endif /* FC_ATTITUDE_ESTIMATOR_H */
