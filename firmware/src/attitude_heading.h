/*
 * attitude_heading.h - between the attitude filter's two sources: the heading
 * aid (attitude_heading.c) as attitude_estimator.c calls it. Not a public
 * header: the module's interface is fc/attitude_estimator.h.
 */
#ifndef FC_ATTITUDE_HEADING_H
#define FC_ATTITUDE_HEADING_H

#include <stdbool.h>
#include <stdint.h>

#include "fc/attitude_estimator.h"

/* The PI action of a weighted direction error we (UNIT, body; the header's
 * w e or w_h e_h): Kp we joins *rate_radps (RATE), the rate that is
 * integrated; b' = -Ki we, forward Euler, each component clamped to the bias
 * limit. Always inline, so that each source builds it with its own products
 * (the heading's out of line on the ATmega, the tilt's inline: it runs on
 * every step). */
static inline __attribute__((always_inline)) void fc_attitude_correct_by(fc_attitude_estimator *est,
                                                                        fc_vec3 *rate_radps, fc_vec3 we)
{
    fc_arith *ar = &est->ar;
    const fc_vec3 proportional = fc_vec3_scale(ar, we, est->kp_radps, FC_SHIFT(UNIT, RATE, RATE));
    *rate_radps = fc_vec3_add(ar, *rate_radps, proportional);
    const fc_vec3 bias_step = fc_vec3_scale(ar, we, est->ki_dt_fine, FC_SHIFT(UNIT, UNIT, UNIT));
    est->gyro_bias_fine =
        fc_vec3_clamp_each(ar, fc_vec3_sub(ar, est->gyro_bias_fine, bias_step), est->gyro_bias_limit_fine);
}

/* The heading parameters in their ranges (fc/attitude_estimator.h), with
 * kp_radps (RATE) the filter's Kp; *hold_steps = heading_hold_s in steps. */
bool fc_attitude_heading_params_ok(const fc_attitude_estimator_params *p, fc_real kp_radps, uint16_t *hold_steps);

/* The heading correction of one step from the held sample: w_h e_h =
 * w_h s v_hat, v_hat the estimated up direction (body); Kp w_h e_h joins
 * *rate_radps (RATE) and the bias takes -Ki dt w_h e_h, clamped. */
void fc_attitude_heading_correct(fc_attitude_estimator *est, fc_vec3 *rate_radps);

#endif /* FC_ATTITUDE_HEADING_H */
