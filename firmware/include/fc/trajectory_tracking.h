/*
 * fc/trajectory_tracking.h - trajectory tracking for a velocity-input plant,
 * dissertation 2.6.6, per axis (a vec3 of independent axes).
 *
 * Plant (2.18)-(2.23): the velocity follows the command u through
 * P(s) = k_P / (s + a_P), so  x'' + a_P x' = k_P u  (2.22).
 * With e = r - x (2.15)-(2.17), the law (2.24)
 *
 *     u = k_P^-1 (r'' + alpha r' + beta r - (alpha - a_P) x' - beta x)
 *
 * gives the error dynamics e'' + alpha e' + beta e = 0 (2.14). alpha and beta
 * are set at init from a wanted damping zeta and natural frequency w_n:
 * alpha = 2 zeta w_n, beta = w_n^2, per axis. It is evaluated as
 *
 *     u = k_P^-1 (r'' + alpha (r' - x') + beta (r - x) + a_P x')
 *
 * (the same law, written on the errors so that nothing cancels in fixed).
 * The gains are held in RATIO (Q24) for resolution at small values.
 * The law is static: no step size, no state but the arithmetic record.
 */
#ifndef FC_TRAJECTORY_TRACKING_H
#define FC_TRAJECTORY_TRACKING_H

#include "fc/vec3.h"
#include "fc/status.h"

typedef struct fc_trajectory_tracking_params {
    fc_vec3 k_p_per_s;      /* RATIO: k_P of (2.18) per axis, [0.01, 100] 1/s */
    fc_vec3 a_p_per_s;      /* RATIO: a_P of (2.18) per axis, [0, 100] 1/s */
    fc_vec3 zeta;           /* RATIO: wanted damping of (2.14) per axis, [0.1, 2] */
    fc_vec3 omega_n_radps;  /* RATE: wanted natural frequency of (2.14) per axis, [0.01, 10] rad/s */
    fc_vec3 u_max_mps;      /* VEL: |u| limit per axis, (0, 100] m/s */
} fc_trajectory_tracking_params;

typedef struct fc_trajectory_tracking_input {
    fc_vec3 r_m;            /* LENGTH: reference r */
    fc_vec3 r_dot_mps;      /* VEL: r' */
    fc_vec3 r_ddot_mps2;    /* ACCEL: r'' */
    fc_vec3 x_m;            /* LENGTH: measured output x */
    fc_vec3 x_dot_mps;      /* VEL: x' */
} fc_trajectory_tracking_input;

typedef struct fc_trajectory_tracking {
    fc_vec3 inv_k_p_s;      /* RATIO: k_P^-1 per axis, [0.01, 100] s */
    fc_vec3 a_p_per_s;      /* RATIO: a_P per axis */
    fc_vec3 alpha_per_s;    /* RATIO: 2 zeta w_n per axis, <= 40 */
    fc_vec3 beta_per_s2;    /* RATIO: w_n^2 per axis, <= 100 */
    fc_vec3 u_max_mps;      /* VEL */
    bool ready;
    fc_arith ar;
} fc_trajectory_tracking;

fc_init_result fc_trajectory_tracking_init(fc_trajectory_tracking *tt, const fc_trajectory_tracking_params *p);

/* u_mps (VEL): the velocity command (2.24), clamped per axis to +-u_max.
 * Bad input (a non-finite component): u = 0 on that axis and FC_STEP_BAD_INPUT. */
fc_step_status fc_trajectory_tracking_step(fc_trajectory_tracking *tt, const fc_trajectory_tracking_input *in,
                                           fc_vec3 *u_mps);

#endif /* FC_TRAJECTORY_TRACKING_H */
