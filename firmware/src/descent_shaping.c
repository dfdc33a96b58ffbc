/* descent_shaping.c - the descent velocity field (2.25)-(2.28) (fc/descent_shaping.h). */
#include "fc/descent_shaping.h"

static bool descent_params_valid(const fc_descent_shaping_params *p)
{
    return fc_in_range(p->k_r_m2ps, FC_INT(0, GAIN), FC_INT(100, GAIN)) &&
           fc_in_range(p->delta_h_m, FC_C(0.01f, LENGTH), FC_INT(100, LENGTH)) &&
           fc_in_range(p->k_c_per_s, FC_INT(0, GAIN), FC_INT(100, GAIN)) &&
           fc_in_range(p->u_zbias_mps, FC_INT(-50, VEL), FC_INT(50, VEL)) &&
           fc_in_range(p->k_a_mps, FC_INT(0, GAIN), FC_INT(100, GAIN)) &&
           fc_in_range(p->delta_a_m, FC_C(0.01f, LENGTH), FC_INT(100, LENGTH)) &&
           fc_in_range(p->max_descent_mps, FC_C(0.001f, VEL), FC_INT(50, VEL)) &&
           fc_in_range(p->max_climb_mps, FC_C(0.001f, VEL), FC_INT(50, VEL));
}

fc_init_result fc_descent_shaping_init(fc_descent_shaping *ds, const fc_descent_shaping_params *p)
{
    ds->ready = false;
    ds->ar.saturated = 0u;
    if (!descent_params_valid(p)) {
        return FC_INIT_BAD_PARAM;
    }
    ds->p = *p;
    ds->ready = true;
    return FC_INIT_OK;
}

/* Each term is bounded to +-TERM_BOUND (far beyond the rate limits, <= 50 m/s)
 * before the sum so that the sum cannot leave the VEL range; a term beyond it
 * (a large gain over a small denominator, a far-off vehicle) is an output
 * limit, not an arithmetic fault: it is computed with a scratch fc_arith. */
#define TERM_BOUND FC_INT(128, VEL)

static fc_real bounded_term(fc_real v, const fc_arith *scratch, bool *big)
{
    if (scratch->saturated != 0u || v > TERM_BOUND || v < -TERM_BOUND) {
        *big = true;
        return v > FC_INT(0, VEL) ? TERM_BOUND : -TERM_BOUND;
    }
    return v;
}

fc_step_status fc_descent_shaping_step(fc_descent_shaping *ds, const fc_descent_shaping_input *in,
                                       fc_descent_shaping_output *out)
{
    out->vz_mps = FC_INT(0, VEL);
    out->rational_mps = FC_INT(0, VEL);
    out->conical_mps = FC_INT(0, VEL);
    out->aversive_mps = FC_INT(0, VEL);
    if (!ds->ready) {
        return FC_STEP_NOT_READY;
    }
    fc_arith *ar = &ds->ar;
    ar->saturated = 0u;
    const fc_descent_shaping_params *p = &ds->p;
    const fc_vec3 d = in->rel_position_m;
    const fc_real lim = FC_INT(1000, LENGTH);
    if (!fc_vec3_is_finite(d) || fc_abs(ar, d.x) > lim || fc_abs(ar, d.y) > lim || fc_abs(ar, d.z) > lim) {
        return FC_STEP_BAD_INPUT; /* hover: v = 0 */
    }
    fc_step_status status = FC_STEP_OK;
    bool ok = false;
    fc_quat q_pad = fc_quat_normalize(ar, in->pad_attitude, &ok);
    if (!ok) {
        q_pad = fc_quat_identity(); /* a level pad */
        status |= FC_STEP_BAD_INPUT;
    }
    bool big = false;
    /* |d_h| in the horizontal frame: the yaw rotation keeps it, so (d_x, d_y) */
    const fc_real dh_m = fc_hypot3(ar, d.x, d.y, FC_INT(0, LENGTH));
    /* (d_h)_pad: d in the pad frame, its in-plane part */
    const fc_vec3 d_pad = fc_quat_rotate_inv(ar, q_pad, d);
    const fc_real dh_pad_m = fc_hypot3(ar, d_pad.x, d_pad.y, FC_INT(0, LENGTH));
    /* (2.26) */
    fc_arith t1 = {0u};
    const fc_real rational = bounded_term(
        fc_neg(&t1, fc_div(&t1, p->k_r_m2ps, fc_add(&t1, dh_m, p->delta_h_m), FC_DIV_SHIFT(GAIN, LENGTH, VEL))),
        &t1, &big);
    /* (2.27) */
    fc_arith t2 = {0u};
    const fc_real conical = bounded_term(
        fc_sub(&t2, fc_mul(&t2, p->k_c_per_s, dh_m, FC_SHIFT(GAIN, LENGTH, VEL)), p->u_zbias_mps), &t2, &big);
    /* (2.28): k_a |(d_h)_pad| first (m^2/s, held in the LENGTH format for its
     * resolution; beyond its range the term is far above the limits), then
     * over |z| + delta_a */
    fc_arith t3 = {0u};
    const fc_real ka_d = fc_mul(&t3, p->k_a_mps, dh_pad_m, FC_SHIFT(GAIN, LENGTH, LENGTH));
    const fc_real aversive = bounded_term(
        fc_div(&t3, ka_d, fc_add(&t3, fc_abs(&t3, d.z), p->delta_a_m), FC_DIV_SHIFT(LENGTH, LENGTH, VEL)), &t3, &big);
    /* (2.25) */
    const fc_real sum = fc_add(ar, fc_add(ar, rational, conical), aversive);
    const fc_real lo = fc_neg(ar, p->max_descent_mps);
    const fc_real v = fc_clamp(sum, lo, p->max_climb_mps);
    if (v != sum || big) {
        status |= FC_STEP_OUTPUT_LIMITED;
    }
    out->vz_mps = v;
    out->rational_mps = rational;
    out->conical_mps = conical;
    out->aversive_mps = aversive;
    if (ar->saturated != 0u) {
        status |= FC_STEP_ARITH_SATURATED;
    }
    return status;
}
