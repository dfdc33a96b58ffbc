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

/* The PI action of a weighted direction error we (UNIT16, body; the header's
 * w e or w_h e_h): Kp we joins *rate_radps (RATE), the rate that is
 * integrated; b' = -Ki we, forward Euler, each component clamped to the bias
 * limit (attitude_estimator.c). */
void fc_attitude_correct_by(fc_attitude_estimator *est, fc_vec3 *rate_radps, fc_vec3_16 we);

/* The heading parameters in their ranges (fc/attitude_estimator.h), with
 * kp_radps (RATE) the filter's Kp; *hold_steps = heading_hold_s in steps. */
bool fc_attitude_heading_params_ok(const fc_attitude_estimator_params *p, fc_real kp_radps, uint16_t *hold_steps);

/* The heading correction of one step from the held sample: w_h e_h =
 * w_h s v_hat, v_hat the estimated up direction (body); Kp w_h e_h joins
 * *rate_radps (RATE) and the bias takes -Ki dt w_h e_h, clamped. */
void fc_attitude_heading_correct(fc_attitude_estimator *est, fc_vec3 *rate_radps);

#endif /* FC_ATTITUDE_HEADING_H */
