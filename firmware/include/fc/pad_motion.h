/*
 * fc/pad_motion.h - learning the pad's heave online and predicting it ahead
 * (the OBSERVE phase of the landing mission, SPEC "landing mission").
 *
 * Model: the pad's height as a constant plus K sinusoids of frequencies w_k
 * (starting on a grid spanning what the pad may do, then adapted),
 *
 *     z_pad(t) = c + sum_k a_k sin(w_k t) + b_k cos(w_k t) = theta' phi(t),
 *     phi(t)   = [1, sin w_1 t, cos w_1 t, ..., sin w_K t, cos w_K t],
 *
 * linear in theta = [c, a_1, b_1, ...], fitted by recursive least squares
 * with exponential forgetting (window T_w = dt_sample / (1 - lambda)), so the
 * amplitude and phase of each grid mode follow the pad and a sinusoid between
 * two grid frequencies is carried by its neighbours over the window:
 *
 *     e     = y - theta' phi                     (a-priori residual)
 *     g     = P phi / (lambda + phi' P phi)
 *     theta = theta + g e
 *     P     = (P - g phi' P) / lambda
 *
 * Frequency: if the pad's frequency is w_k + d, the fitted complex amplitude
 * C_k = b_k - i a_k of mode k turns at d rad/s. After each sample the turn
 * since the previous one, d_arg = (a_prev b - b_prev a) / |C|^2, gives
 *     w_k += kappa d_arg / T_sample,
 * each w_k kept inside its own band (edges: the geometric means of neighbouring
 * start periods, and the period band at the ends) so modes never merge, and
 * only while |C_k| is above a floor (a mode without energy has no phase).
 *
 * P is kept scaled, P = (1 - lambda) S: S stays near the inverse of the
 * regressors' correlation (order 1 to 100) instead of 1e-3, which is what
 * the fixed backend can resolve (MAT, Q24). S's trace is bounded (no
 * inflation by 1/lambda beyond trace_max): no covariance wind-up.
 *
 * phi(t) is propagated without t: each (sin, cos) pair is rotated by w_k dt
 * per step and renormalised, so it never loses precision (at the start of the
 * next step, so that the rotation of a changed w_k can be formed between).
 * The fit and the model's values read phi rounded to 16 bits (phi16, UNIT16:
 * within 2^-15 of phi): the products with it are 32 x 16-bit (fc_mul_by16),
 * and the fit is exact for the regressor it reads, so the rounding costs the
 * model 2^-15 of sum (|a_k| + |b_k|) at most (0.03 mm a metre of heave),
 * far below what a range finder resolves. The phases themselves stay 32-bit.
 * Derivatives are the model's:  z' = sum w_k (a_k cos - b_k sin),
 * z'' = -sum w_k^2 (a_k sin + b_k cos); the prediction at t + H rotates the
 * pairs by w_k H (H fixed at init), fc_pad_motion_predict_ahead.
 *
 * Confidence: the fit is checked against what it predicted. Two snapshots of
 * theta are kept, renewed alternately every H seconds; each new sample is
 * compared with theta_old' phi(t), a prediction made between H and 2H ago
 * (phi is absolute in time, so an old theta with today's phi is exactly the
 * old prediction). The mean of |that error| (exponential, per sample) against
 * a tolerance gives confidence = clamp(1 - mean / tolerance, 0, 1), and 0
 * before the estimator has observed for observe_min_s and has a snapshot H old.
 *
 * Bounds for the landing manager: heave <= sum (|a_k| + |b_k|) and
 * |z''| <= sum w_k^2 (|a_k| + |b_k|) (|a| + |b| >= amplitude), no square root.
 *
 * Measurement: the pad's surface height y (LENGTH, world z), a sample when
 * `fresh` (the range finder's rate, below the step rate); between samples the
 * model runs on. A sample further than outlier_m from the model's value is not
 * used; outlier_reset_count of them in a row restart the estimate from the
 * newest sample (the pad is not what the model says any more).
 */
#ifndef FC_PAD_MOTION_H
#define FC_PAD_MOTION_H

#include "fc/altitude_reference.h"
#include "fc/scalar.h"
#include "fc/status.h"

#define FC_PAD_MAX_MODES 3 /* n = 7 <= 8: a row of S phi fits one fc_acc */
#define FC_PAD_MAX_PARAMS (1 + 2 * FC_PAD_MAX_MODES)

typedef struct fc_pad_motion_params {
    fc_real dt_s;                            /* DT: the fixed step, (0, 0.1] */
    uint8_t mode_count;                      /* K, 1..FC_PAD_MAX_MODES */
    fc_real mode_period_s[FC_PAD_MAX_MODES]; /* TIME: 2 pi / w_k at the start, ascending, inside the band */
    fc_real period_min_s, period_max_s;      /* TIME: the band the pad's periods lie in, [0.5, 60] s */
    fc_real frequency_gain;                  /* UNIT: kappa of the frequency adaptation, [0, 1] (0: a fixed grid) */
    fc_real adapt_amplitude_min_m;           /* LENGTH: a mode adapts its frequency above this amplitude, > 0 */
    fc_real forgetting;                      /* UNIT: lambda per sample, [0.9, 0.99999] */
    fc_real covariance_init;                 /* MAT: S(0) = s0 I, (0, 100] */
    fc_real covariance_trace_max;            /* MAT: no inflation while trace(S) exceeds it, [s0, 127] */
    fc_real outlier_m;                       /* LENGTH: a sample this far from the model is not used, (0, 100] */
    uint8_t outlier_reset_count;             /* that many outliers in a row restart the estimate, >= 1 */
    fc_real horizon_s;                       /* TIME: H, prediction horizon and snapshot period, (0, 60] */
    fc_real observe_min_s;                   /* TIME: no confidence before this much observation, [0, 600] */
    fc_real tolerance_m;                     /* LENGTH: the prediction error at which confidence is 0, (0, 10] */
    fc_real error_average_gain;              /* UNIT: per-sample weight of the error mean, (0, 1] */
} fc_pad_motion_params;

typedef struct fc_pad_motion_sample {
    fc_real height_m;  /* LENGTH: measured height of the pad's surface, world z */
    bool fresh;        /* a new measurement this step */
} fc_pad_motion_sample;

typedef struct fc_pad_motion_estimate {
    fc_vertical_trajectory now;      /* the pad at this step: z, z', z'' */
    fc_real mean_m;                  /* LENGTH: c, the level the pad moves about */
    fc_real heave_bound_m;           /* LENGTH: sum (|a_k| + |b_k|) >= the largest |z - c| */
    fc_real accel_bound_mps2;        /* ACCEL: sum w_k^2 (|a_k| + |b_k|) >= the largest |z''| */
    fc_real prediction_error_m;      /* LENGTH: mean |error| of predictions H..2H old */
    fc_real confidence;              /* UNIT: [0, 1] */
    fc_real observed_s;              /* TIME: since the first sample (saturates at 600 s) */
    uint8_t dominant_mode;           /* the mode of largest |a_k| + |b_k| */
    fc_real dominant_period_s;       /* TIME: its period, 2 pi / w_k */
    fc_real dominant_amplitude_m;    /* LENGTH: its |a_k| + |b_k| */
    bool learning;                   /* at least one sample taken */
} fc_pad_motion_estimate;

/* The fit's figures that change only when a sample is taken (pad_motion.c, summarise_fit). */
typedef struct fc_pad_motion_summary {
    fc_real heave_bound_m;           /* LENGTH */
    fc_real accel_bound_mps2;        /* ACCEL */
    fc_real dominant_amplitude_m;    /* LENGTH */
    fc_real dominant_period_s;       /* TIME */
    fc_real error_ratio;             /* UNIT: error mean / tolerance (in fixed it saturates above 2) */
    uint8_t dominant_mode;
    uint8_t saturated;               /* its arithmetic saturated */
} fc_pad_motion_summary;

/* The pieces of the next step that need no sample (pad_motion.c), the bits
 * of fc_pad_motion.deferred: a step leaves them to be done before the
 * next one, by fc_pad_motion_work_ahead in a spare minor frame or else by
 * that step itself. They run in the order of their bits, the order the
 * algorithm needs. */
#define FC_PAD_WORK_COVARIANCE_HEAD 0x01u /* the rotations w_k dt of the newest sample's frequencies,
                                              and S's update of that sample, its first rows */
#define FC_PAD_WORK_COVARIANCE_TAIL 0x02u /* the rest of S's update */
#define FC_PAD_WORK_PHASES 0x04u          /* phi turned from the last step's time to the next's */
#define FC_PAD_WORK_SUMMARY 0x08u         /* the fit's bounds, dominant mode and error ratio */
#define FC_PAD_WORK_SAMPLE_GAIN 0x10u     /* the RLS gain and model values at the next phases */

typedef struct fc_pad_motion {
    fc_pad_motion_params p;
    uint8_t n;                                   /* 1 + 2K parameters */
    fc_real omega_radps[FC_PAD_MAX_MODES];       /* RATE: w_k */
    fc_gain omega_gain[FC_PAD_MAX_MODES];        /* w_k, rad/s, for the derivatives (fc_gain: 2^-15
                                                    of z' and z'' at most) */
    fc_gain omega_sq_gain[FC_PAD_MAX_MODES];     /* w_k^2, 1/s^2 */
    fc_real step_cos[FC_PAD_MAX_MODES];          /* UNIT: cos w_k dt */
    fc_real step_sin[FC_PAD_MAX_MODES];          /* UNIT: sin w_k dt (32 bits: as a gain, 2^-15 of
                                                    it would turn the phases at w_k (1 +- 2^-15)) */
    uint8_t rotation_stale;                      /* bit k: step_cos/sin of mode k to form again */
    uint8_t deferred;                            /* FC_PAD_WORK_* bits: the pieces not yet done */
    fc_real omega_min_radps[FC_PAD_MAX_MODES];   /* RATE: the band of each mode */
    fc_real omega_max_radps[FC_PAD_MAX_MODES];   /* RATE */
    fc_real amplitude_min_sq;                    /* RATIO: adapt_amplitude_min^2 */
    fc_real since_sample_s;                      /* TIME: since the previous fresh sample */
    fc_gain inflation;                           /* 1/lambda - 1 (fc_gain: 2^-15 of itself moves the
                                                    window T_w by as little) */
    fc_real one_minus_lambda;                    /* UNIT */
    fc_gain inv_tolerance;                       /* 1/tolerance, 1/m */
    fc_real phi[FC_PAD_MAX_PARAMS];              /* UNIT: phi(t) itself, the phases of the modes
                                                    [1, sin w_1 t, cos w_1 t, ...], zero past n */
    fc_real16 phi16[FC_PAD_MAX_PARAMS];          /* UNIT16: phi rounded, the regressor the fit and the
                                                    model's values read (phi16[0] unused: 1) */
    fc_real theta[FC_PAD_MAX_PARAMS];            /* LENGTH */
    fc_real theta_old[FC_PAD_MAX_PARAMS];        /* LENGTH: snapshot H..2H old */
    fc_real theta_new[FC_PAD_MAX_PARAMS];        /* LENGTH: snapshot 0..H old */
    fc_real s[FC_PAD_MAX_PARAMS][FC_PAD_MAX_PARAMS]; /* MAT: scaled covariance S */
    fc_real pending_gain[FC_PAD_MAX_PARAMS];     /* MAT: the RLS gain g of the newest sample (for S's
                                                    update), or of the next once FC_PAD_WORK_SAMPLE_GAIN
                                                    is done */
    fc_real pending_s_phi[FC_PAD_MAX_PARAMS];    /* MAT: its S phi */
    bool covariance_inflate;                     /* S's update inflates: decided on S before its first row */
    fc_real prepared_z_m;                        /* LENGTH: theta' phi at the next phases, what the
                                                    model expects of the next sample */
    fc_real prepared_z_old_m;                    /* LENGTH: theta_old' phi (with two snapshots) */
    fc_real error_mean_m;                        /* LENGTH */
    fc_pad_motion_summary summary;               /* of theta, w_k and the error mean */
    fc_real observed_s;                          /* TIME */
    fc_real since_snapshot_s;                    /* TIME */
    fc_real step_s;                              /* TIME: dt */
    uint8_t snapshots;                           /* 0, 1, 2 (saturates): how many renewals so far */
    uint8_t outliers_in_row;
    bool learning;
    bool ready;
    fc_arith ar;
} fc_pad_motion;

fc_init_result fc_pad_motion_init(fc_pad_motion *pm, const fc_pad_motion_params *p);

/* Forget everything learnt (the next sample starts the estimate again). */
void fc_pad_motion_reset(fc_pad_motion *pm);

/* One step: take the sample if fresh and usable (finite, inside the input
 * range, not an outlier), advance the phases, give the estimate. A bad sample
 * is ignored (FC_STEP_BAD_INPUT). The estimate's trajectory, mean and
 * prediction error are the fit's with this step's sample; its figures of the
 * fit (the bounds, the dominant mode, the confidence) are summarised after a
 * step that takes a sample (fc_pad_motion_work_ahead, or the next step), so
 * they stand for the fit one sample older. Not ready: a zero estimate with
 * confidence 0. */
fc_step_status fc_pad_motion_step(fc_pad_motion *pm, const fc_pad_motion_sample *sample,
                                  fc_pad_motion_estimate *out);

/* The deferred pieces (FC_PAD_WORK_*) of the next step done ahead of it, one
 * slice per call, the first slice with a piece left of:
 *   1. FC_PAD_WORK_COVARIANCE_HEAD (13 of the 28 entries of S's upper
 *      triangle for 3 modes) and FC_PAD_WORK_SUMMARY
 *   2. FC_PAD_WORK_COVARIANCE_TAIL and FC_PAD_WORK_PHASES
 *   3. FC_PAD_WORK_SAMPLE_GAIN (S phi and phi' S phi: 42 + 6 products of
 *      32 x 16 bits; g; all of a sample's RLS update but theta += g e)
 * The slices are about the same size (the controller calls one per spare
 * minor frame; fc/controller.h). A caller with spare minor frames calls this
 * in them, between two steps; what is not done ahead the next
 * fc_pad_motion_step does first. The same values either way, bit for bit.
 * Returns FC_STEP_DEGRADED if S had to restart (see covariance_usable),
 * FC_STEP_ARITH_SATURATED as a step does; nothing left to do: FC_STEP_OK. */
fc_step_status fc_pad_motion_work_ahead(fc_pad_motion *pm);

/* The model's trajectory H (horizon_s) after the newest step's time, on demand:
 * the landing does not use it, so the step does not work it out. Ask for it
 * after fc_pad_motion_step and before fc_pad_motion_work_ahead (whose piece 2
 * turns the phases to the next step's time). Not ready: zero. */
void fc_pad_motion_predict_ahead(fc_pad_motion *pm, fc_vertical_trajectory *ahead);

#endif /* FC_PAD_MOTION_H */
