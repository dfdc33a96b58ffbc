/* trajectory_tracking.c - the tracking law (2.24) (fc/trajectory_tracking.h). */
#include "fc/trajectory_tracking.h"

static bool vec_in_range(fc_vec3 v, fc_real lo, fc_real hi)
{
    return fc_in_range(v.x, lo, hi) && fc_in_range(v.y, lo, hi) && fc_in_range(v.z, lo, hi);
}

fc_init_result fc_trajectory_tracking_init(fc_trajectory_tracking *tt, const fc_trajectory_tracking_params *p)
{
    tt->ready = false;
    tt->ar.saturated = 0u;
    if (!vec_in_range(p->k_p_per_s, FC_C(0.01f, RATIO), FC_INT(100, RATIO)) ||
        !vec_in_range(p->a_p_per_s, FC_INT(0, RATIO), FC_INT(100, RATIO)) ||
        !vec_in_range(p->zeta, FC_C(0.1f, RATIO), FC_INT(2, RATIO)) ||
        !vec_in_range(p->omega_n_radps, FC_C(0.01f, RATE), FC_INT(10, RATE)) ||
        !vec_in_range(p->u_max_mps, FC_C(0.001f, VEL), FC_INT(100, VEL))) {
        return FC_INIT_BAD_PARAM;
    }
    fc_arith *ar = &tt->ar;
    /* alpha = 2 zeta w_n, beta = w_n^2 (below (2.24)) */
    const fc_vec3 zeta_wn = fc_vec3_mul_elementwise(ar, p->zeta, p->omega_n_radps, FC_SHIFT(RATIO, RATE, RATIO));
    tt->alpha_per_s = fc_vec3_add(ar, zeta_wn, zeta_wn);
    tt->beta_per_s2 = fc_vec3_mul_elementwise(ar, p->omega_n_radps, p->omega_n_radps, FC_SHIFT(RATE, RATE, RATIO));
    tt->inv_k_p_s = fc_vec3_make(fc_div(ar, FC_INT(1, RATIO), p->k_p_per_s.x, FC_DIV_SHIFT(RATIO, RATIO, RATIO)),
                                 fc_div(ar, FC_INT(1, RATIO), p->k_p_per_s.y, FC_DIV_SHIFT(RATIO, RATIO, RATIO)),
                                 fc_div(ar, FC_INT(1, RATIO), p->k_p_per_s.z, FC_DIV_SHIFT(RATIO, RATIO, RATIO)));
    tt->a_p_per_s = p->a_p_per_s;
    tt->u_max_mps = p->u_max_mps;
    if (ar->saturated != 0u) {
        return FC_INIT_BAD_PARAM;
    }
    tt->ready = true;
    return FC_INIT_OK;
}

/* (2.24) on one axis; *limited when clamped, *bad when an input is not finite */
static fc_real axis_law(fc_arith *ar, fc_real alpha, fc_real beta, fc_real r, fc_real r_dot, fc_real r_ddot,
                        fc_real x, fc_real x_dot, fc_real inv_k_p, fc_real a_p, fc_real u_max, bool *limited,
                        bool *bad)
{
    if (!fc_is_finite(r) || !fc_is_finite(r_dot) || !fc_is_finite(r_ddot) || !fc_is_finite(x) ||
        !fc_is_finite(x_dot)) {
        *bad = true;
        return FC_INT(0, VEL);
    }
    const fc_real e = fc_sub(ar, r, x);             /* LENGTH (2.15) */
    const fc_real e_dot = fc_sub(ar, r_dot, x_dot); /* VEL (2.16) */
    /* r'' + alpha e' + beta e + a_P x' in ACCEL */
    const fc_real damping = fc_dot2(ar, alpha, e_dot, a_p, x_dot, FC_SHIFT(RATIO, VEL, ACCEL));
    const fc_real stiffness = fc_mul(ar, beta, e, FC_SHIFT(RATIO, LENGTH, ACCEL));
    const fc_real sum = fc_add(ar, fc_add(ar, r_ddot, damping), stiffness);
    const fc_real u = fc_mul(ar, inv_k_p, sum, FC_SHIFT(RATIO, ACCEL, VEL));
    const fc_real u_limited = fc_clamp(u, fc_neg(ar, u_max), u_max);
    if (u_limited != u) {
        *limited = true;
    }
    return u_limited;
}

fc_step_status fc_trajectory_tracking_step(fc_trajectory_tracking *tt, const fc_trajectory_tracking_input *in,
                                           fc_vec3 *u_mps)
{
    *u_mps = fc_vec3_zero();
    if (!tt->ready) {
        return FC_STEP_NOT_READY;
    }
    fc_arith *ar = &tt->ar;
    ar->saturated = 0u;
    bool limited = false;
    bool bad = false;
    u_mps->x = axis_law(ar, tt->alpha_per_s.x, tt->beta_per_s2.x, in->r_m.x, in->r_dot_mps.x, in->r_ddot_mps2.x, in->x_m.x, in->x_dot_mps.x,
                        tt->inv_k_p_s.x, tt->a_p_per_s.x, tt->u_max_mps.x, &limited, &bad);
    u_mps->y = axis_law(ar, tt->alpha_per_s.y, tt->beta_per_s2.y, in->r_m.y, in->r_dot_mps.y, in->r_ddot_mps2.y, in->x_m.y, in->x_dot_mps.y,
                        tt->inv_k_p_s.y, tt->a_p_per_s.y, tt->u_max_mps.y, &limited, &bad);
    u_mps->z = axis_law(ar, tt->alpha_per_s.z, tt->beta_per_s2.z, in->r_m.z, in->r_dot_mps.z, in->r_ddot_mps2.z, in->x_m.z, in->x_dot_mps.z,
                        tt->inv_k_p_s.z, tt->a_p_per_s.z, tt->u_max_mps.z, &limited, &bad);
    fc_step_status status = FC_STEP_OK;
    if (bad) {
        status |= FC_STEP_BAD_INPUT;
    }
    if (limited) {
        status |= FC_STEP_OUTPUT_LIMITED;
    }
    if (ar->saturated != 0u) {
        status |= FC_STEP_ARITH_SATURATED;
    }
    return status;
}
