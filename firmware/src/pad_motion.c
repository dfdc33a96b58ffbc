/* pad_motion.c - the pad's heave, learnt by recursive least squares on a
 * grid of sinusoids, and predicted ahead (fc/pad_motion.h). */
#include "fc/pad_motion.h"

#include <stddef.h>

static bool pad_motion_params_valid(const fc_pad_motion_params *p)
{
    if (p->mode_count < 1u || p->mode_count > FC_PAD_MAX_MODES) {
        return false;
    }
    if (!fc_in_range(p->period_min_s, FC_C(0.5f, TIME), FC_INT(60, TIME)) ||
        !fc_in_range(p->period_max_s, p->period_min_s, FC_INT(60, TIME))) {
        return false;
    }
    for (unsigned k = 0u; k < p->mode_count; k++) {
        /* ascending and inside the band: distinct columns of phi, ordered bands */
        const fc_real lower = k == 0u ? p->period_min_s : p->mode_period_s[k - 1u];
        if (!fc_in_range(p->mode_period_s[k], lower, p->period_max_s) || (k > 0u && p->mode_period_s[k] == lower)) {
            return false;
        }
    }
    return fc_in_range(p->frequency_gain, FC_INT(0, UNIT), FC_INT(1, UNIT)) &&
           fc_in_range(p->adapt_amplitude_min_m, FC_C(1e-4f, LENGTH), FC_INT(10, LENGTH)) &&
           fc_in_range(p->dt_s, FC_C(1e-4f, DT), FC_C(0.1f, DT)) &&
           fc_in_range(p->forgetting, FC_C(0.9f, UNIT), FC_C(0.99999f, UNIT)) &&
           fc_in_range(p->covariance_init, FC_C(0.01f, MAT), FC_INT(100, MAT)) &&
           fc_in_range(p->covariance_trace_max, p->covariance_init, FC_INT(127, MAT)) &&
           fc_in_range(p->outlier_m, FC_C(0.001f, LENGTH), FC_INT(100, LENGTH)) && p->outlier_reset_count >= 1u &&
           fc_in_range(p->horizon_s, FC_C(0.05f, TIME), FC_INT(60, TIME)) &&
           fc_in_range(p->observe_min_s, FC_INT(0, TIME), FC_INT(600, TIME)) &&
           fc_in_range(p->tolerance_m, FC_C(0.001f, LENGTH), FC_INT(10, LENGTH)) &&
           fc_in_range(p->error_average_gain, FC_C(1e-4f, UNIT), FC_INT(1, UNIT));
}

/* phi[0], the regressor of the level theta[0]: 1 at every step (only the
 * modes' entries turn), so the sums over phi take it as the constant. */
#define LEVEL_REGRESSOR FC_INT(1, UNIT)

/* Where mode k's sine and cosine sit in phi (and its a_k, b_k in theta). */
static unsigned sin_of(unsigned k)
{
    return 1u + 2u * k;
}

static unsigned cos_of(unsigned k)
{
    return 2u + 2u * k;
}

/* An angle in GAIN (any size) wrapped into [-pi, pi] and given as an ANGLE. */
static fc_real wrapped_angle(fc_arith *ar, fc_real angle_gain)
{
    const fc_real pi = FC_C(3.14159265f, GAIN), two_pi = FC_C(6.28318531f, GAIN);
    /* at most 60 s x 12.6 rad/s / 2 pi = 121 turns (the parameter bounds) */
    for (unsigned turns = 0u; turns < 128u; turns++) {
        if (angle_gain > pi) {
            angle_gain = fc_sub(ar, angle_gain, two_pi);
        } else if (angle_gain < -pi) {
            angle_gain = fc_add(ar, angle_gain, two_pi);
        } else {
            break;
        }
    }
    return fc_convert(ar, angle_gain, FC_GAIN_FRAC, FC_ANGLE_FRAC);
}

/* w = 2 pi / T */
static fc_real omega_of(fc_arith *ar, fc_real period_s)
{
    return fc_div(ar, FC_TWO_PI, period_s, FC_DIV_SHIFT(ANGLE, TIME, RATE));
}

static fc_real geometric_mean_s(fc_arith *ar, fc_real a_s, fc_real b_s)
{
    return fc_sqrt(ar, fc_mul(ar, a_s, b_s, FC_SHIFT(TIME, TIME, TIME)), FC_TIME_FRAC);
}

/* w_k; its gains and the rotation by w_k dt per step follow before the phases
 * next turn (update_rotations), the rotation by w_k H when a prediction is
 * asked for. */
static void set_mode_frequency(fc_pad_motion *pm, unsigned k, fc_real omega_radps)
{
    pm->omega_radps[k] = omega_radps;
    pm->rotation_stale = (uint8_t)(pm->rotation_stale | (1u << k));
}

/* c_0 x2^(n-1) + ... + c_(n-1) by Horner's rule, UNIT (one loop for both
 * series: on the ATmega the products are calls, and flash is short). */
static fc_real series_in_x2(fc_arith *ar, fc_real x2, const fc_real *c, unsigned n)
{
    fc_real p = c[0];
    for (unsigned i = 1u; i < n; i++) {
        p = fc_add(ar, c[i], fc_mul(ar, x2, p, FC_SHIFT(UNIT, UNIT, UNIT)));
    }
    return p;
}

/* sin and cos of a step angle x, UNIT. The angle is small in practice
 * (w_k <= 12.6 rad/s: 0.13 rad at dt 0.01 s): for |x| <= 0.5 their series;
 * beyond (dt up to 0.1 s) fc_sincos. Every adapted frequency needs one pair,
 * all in the same minor frame: on the Cortex-M4F the series take a fraction
 * of libm's sinf and cosf (tools/bench.sh). */
static void step_sin_cos(fc_arith *ar, fc_real x_rad, fc_real *sin_out, fc_real *cos_out)
{
    if (fc_abs(ar, x_rad) > FC_C(0.5f, ANGLE)) {
        fc_sincos(ar, x_rad, sin_out, cos_out);
        return;
    }
    /* the Taylor coefficients of sin x / x and cos x in x^2, the highest first
     * (to x^6 and x^8: truncation below 6e-9 and 3e-10 for |x| <= 0.5, under
     * float's and UNIT's resolution) */
    static const fc_real sin_over_x_series[] = {FC_C(-1.0f / 5040.0f, UNIT), FC_C(1.0f / 120.0f, UNIT),
                                                FC_C(-1.0f / 6.0f, UNIT), FC_INT(1, UNIT)};
    static const fc_real cos_series[] = {FC_C(1.0f / 40320.0f, UNIT), FC_C(-1.0f / 720.0f, UNIT),
                                         FC_C(1.0f / 24.0f, UNIT), FC_C(-0.5f, UNIT), FC_INT(1, UNIT)};
    const unsigned sin_terms = (unsigned)(sizeof sin_over_x_series / sizeof sin_over_x_series[0]);
    const unsigned cos_terms = (unsigned)(sizeof cos_series / sizeof cos_series[0]);
    const fc_real x2 = fc_mul(ar, x_rad, x_rad, FC_SHIFT(ANGLE, ANGLE, UNIT));
    *sin_out = fc_mul(ar, x_rad, series_in_x2(ar, x2, sin_over_x_series, sin_terms), FC_SHIFT(ANGLE, UNIT, UNIT));
    *cos_out = series_in_x2(ar, x2, cos_series, cos_terms);
}

/* cos and sin of w_k dt for the modes whose w_k changed: the sine and cosine
 * of the step, out of the sample's step (FC_PAD_WORK_COVARIANCE_HEAD); and
 * w_k, w_k^2 as the gains the model's derivatives are formed with (so the
 * estimate of a step that adapts w_k has its derivatives of the w_k before). */
static void update_rotations(fc_pad_motion *pm)
{
    fc_arith *ar = &pm->ar;
    for (unsigned k = 0u; k < pm->p.mode_count && pm->rotation_stale != 0u; k++) {
        if ((pm->rotation_stale & (1u << k)) != 0u) {
            const fc_real step_angle = fc_mul(ar, pm->omega_radps[k], pm->p.dt_s, FC_SHIFT(RATE, DT, ANGLE));
            step_sin_cos(ar, step_angle, &pm->step_sin[k], &pm->step_cos[k]);
            pm->omega_gain[k] = fc_gain_of(pm->omega_radps[k], FC_RATE_FRAC);
            pm->omega_sq_gain[k] =
                fc_gain_of_product(pm->omega_radps[k], FC_RATE_FRAC, pm->omega_radps[k], FC_RATE_FRAC);
        }
    }
    pm->rotation_stale = 0u;
}

/* S = s0 I over the n parameters in use. */
static void covariance_restart(fc_pad_motion *pm)
{
    for (unsigned i = 0u; i < FC_PAD_MAX_PARAMS; i++) {
        for (unsigned j = 0u; j < FC_PAD_MAX_PARAMS; j++) {
            pm->s[i][j] = (i == j && i < pm->n) ? pm->p.covariance_init : FC_INT(0, MAT);
        }
    }
    pm->deferred |= (uint8_t)FC_PAD_WORK_SAMPLE_GAIN; /* the gain of the S before is void */
}

void fc_pad_motion_reset(fc_pad_motion *pm)
{
    for (unsigned i = 0u; i < FC_PAD_MAX_PARAMS; i++) {
        pm->theta[i] = FC_INT(0, LENGTH);
        pm->theta_old[i] = FC_INT(0, LENGTH);
        pm->theta_new[i] = FC_INT(0, LENGTH);
    }
    covariance_restart(pm);
    pm->error_mean_m = FC_INT(0, LENGTH);
    pm->observed_s = FC_INT(0, TIME);
    pm->since_sample_s = FC_INT(0, TIME);
    pm->since_snapshot_s = FC_INT(0, TIME);
    pm->snapshots = 0u;
    pm->outliers_in_row = 0u;
    pm->learning = false;
    /* S starts again from s0 I: no update of it left */
    pm->deferred &= (uint8_t)~(FC_PAD_WORK_COVARIANCE_HEAD | FC_PAD_WORK_COVARIANCE_TAIL);
    pm->deferred |= (uint8_t)FC_PAD_WORK_SUMMARY;
    pm->covariance_inflate = false;
    /* the rotations the head would have brought up to date: so a changed w_k
     * waits only while the head is deferred, and the summary and the phases,
     * which run after the head, find them current */
    update_rotations(pm);
}

fc_init_result fc_pad_motion_init(fc_pad_motion *pm, const fc_pad_motion_params *p)
{
    pm->ready = false;
    pm->ar.saturated = 0u;
    pm->n = 1u;
    pm->rotation_stale = 0u;
    pm->deferred = 0u;
    /* phases start at t = 0: sin 0, cos 0 (and zero past n) */
    pm->phi[0] = LEVEL_REGRESSOR;
    pm->phi16[0] = FC_INT16(1, UNIT16);
    for (unsigned k = 0u; k < FC_PAD_MAX_MODES; k++) {
        pm->phi[sin_of(k)] = FC_INT(0, UNIT);
        pm->phi[cos_of(k)] = k < p->mode_count ? FC_INT(1, UNIT) : FC_INT(0, UNIT);
        pm->phi16[sin_of(k)] = FC_INT16(0, UNIT16);
        pm->phi16[cos_of(k)] = k < p->mode_count ? FC_INT16(1, UNIT16) : FC_INT16(0, UNIT16);
    }
    if (!pad_motion_params_valid(p)) {
        return FC_INIT_BAD_PARAM;
    }
    pm->p = *p;
    pm->n = (uint8_t)(1u + 2u * p->mode_count);
    fc_arith *ar = &pm->ar;
    for (unsigned k = 0u; k < p->mode_count; k++) {
        /* the band of mode k: between the geometric means with its neighbours */
        const fc_real longest = k + 1u < p->mode_count ? geometric_mean_s(ar, p->mode_period_s[k], p->mode_period_s[k + 1u])
                                                        : p->period_max_s;
        const fc_real shortest = k > 0u ? geometric_mean_s(ar, p->mode_period_s[k - 1u], p->mode_period_s[k])
                                        : p->period_min_s;
        pm->omega_min_radps[k] = omega_of(ar, longest);
        pm->omega_max_radps[k] = omega_of(ar, shortest);
        set_mode_frequency(pm, k, omega_of(ar, p->mode_period_s[k]));
    }
    update_rotations(pm);
    pm->amplitude_min_sq =
        fc_mul(ar, p->adapt_amplitude_min_m, p->adapt_amplitude_min_m, FC_SHIFT(LENGTH, LENGTH, RATIO));
    pm->one_minus_lambda = fc_sub(ar, FC_INT(1, UNIT), p->forgetting);
    /* 1/lambda - 1 = (1 - lambda) / lambda */
    pm->inflation = fc_gain_of(fc_div(ar, pm->one_minus_lambda, p->forgetting, FC_DIV_SHIFT(UNIT, UNIT, UNIT)),
                               FC_UNIT_FRAC);
    pm->step_s = fc_convert(ar, p->dt_s, FC_DT_FRAC, FC_TIME_FRAC);
    /* 1/tolerance <= 1000 (tolerance >= 1 mm): GAIN */
    pm->inv_tolerance =
        fc_gain_of(fc_div(ar, FC_INT(1, LENGTH), p->tolerance_m, FC_DIV_SHIFT(LENGTH, LENGTH, GAIN)), FC_GAIN_FRAC);
    if (pm->ar.saturated != 0u) {
        return FC_INIT_BAD_PARAM;
    }
    fc_pad_motion_reset(pm);
    pm->ready = true;
    return FC_INIT_OK;
}

/* ---------------------------------------------------------------------- */
/* the model                                                               */
/* ---------------------------------------------------------------------- */

/* PARAMETERS_PAST_N: the entries of theta, its snapshots, phi and S past the
 * n = 1 + 2K in use are zero, always (reset and covariance_restart write
 * them so, and every update of them adds products of zeros). The sums over
 * parameters therefore run over all FC_PAD_MAX_PARAMS: constant bounds,
 * unrolled where the compiler unrolls, the same result to the bit. */

/* theta' phi16: LENGTH x UNIT16 summed into LENGTH (over every entry: those
 * past n are zero, PARAMETERS_PAST_N; phi16[0] stands for LEVEL_REGRESSOR). */
static fc_real model_value(fc_arith *ar, const fc_real *theta, const fc_real16 *phi16)
{
    fc_real z_m = theta[0];
    for (unsigned i = 1u; i < FC_PAD_MAX_PARAMS; i++) {
        z_m = fc_add_inline(ar, z_m, fc_mul_by16(ar, theta[i], phi16[i], FC_SHIFT(LENGTH, UNIT16, LENGTH)));
    }
    return z_m;
}

/* z, z', z'' of the model theta at the phases phi16. */
static fc_vertical_trajectory model_trajectory(fc_pad_motion *pm, const fc_real16 *phi16)
{
    fc_arith *ar = &pm->ar;
    const int to_length = FC_SHIFT(LENGTH, UNIT16, LENGTH);
    fc_vertical_trajectory t;
    t.z_m = pm->theta[0];
    t.vz_mps = FC_INT(0, VEL);
    t.az_mps2 = FC_INT(0, ACCEL);
    for (unsigned k = 0u; k < pm->p.mode_count; k++) {
        const fc_real a = pm->theta[sin_of(k)], b = pm->theta[cos_of(k)];
        const fc_real16 sin_k = phi16[sin_of(k)], cos_k = phi16[cos_of(k)];
        /* z = c + sum (a sin + b cos), z' = sum w (a cos - b sin),
         * z'' = -sum w^2 (a sin + b cos): four products a mode */
        const fc_real wave_m = fc_add_inline(ar, fc_mul_by16(ar, a, sin_k, to_length), fc_mul_by16(ar, b, cos_k, to_length));
        const fc_real rate_part =
            fc_sub_inline(ar, fc_mul_by16(ar, a, cos_k, to_length), fc_mul_by16(ar, b, sin_k, to_length));
        t.z_m = fc_add_inline(ar, t.z_m, wave_m);
        t.vz_mps = fc_add_inline(ar, t.vz_mps, fc_mul_gain(ar, rate_part, pm->omega_gain[k], FC_GAIN_SHIFT(LENGTH, VEL)));
        t.az_mps2 =
            fc_sub_inline(ar, t.az_mps2, fc_mul_gain(ar, wave_m, pm->omega_sq_gain[k], FC_GAIN_SHIFT(LENGTH, ACCEL)));
    }
    return t;
}

/* (sin, cos) rotated by the angle whose (cos, sin) is (rc, rs). */
static void rotate(fc_arith *ar, fc_real *s, fc_real *c, fc_real rc, fc_real rs)
{
    const fc_real s_new = fc_dot2(ar, *s, rc, *c, rs, FC_SHIFT(UNIT, UNIT, UNIT));
    const fc_real c_new = fc_dot2(ar, *c, rc, fc_neg(ar, *s), rs, FC_SHIFT(UNIT, UNIT, UNIT));
    *s = s_new;
    *c = c_new;
}

/* (1 - s^2 - c^2) / 2 of a phase pair, the defect of its length, in 16 bits:
 * one step's rotation and roundings leave it at a few 2^-30, so a 16-bit
 * value of UNIT's resolution (range +-2^-15) holds it exactly. */
#define FC_PHASE_DEFECT16_FRAC 30

/* One step of every phase, renormalised by one Newton step of 1/sqrt:
 * (s, c) (3 - s^2 - c^2) / 2 = (s, c) + (s, c) d, d = (1 - s^2 - c^2) / 2,
 * which keeps s^2 + c^2 at 1 to second order; then phi16. */
static void advance_phases(fc_pad_motion *pm)
{
    fc_arith *ar = &pm->ar;
    /* the rotations are current: a changed w_k leaves the head deferred
     * (rls_update), which runs before the phases */
    for (unsigned k = 0u; k < pm->p.mode_count; k++) {
        fc_real *sin_k = &pm->phi[sin_of(k)], *cos_k = &pm->phi[cos_of(k)];
        rotate(ar, sin_k, cos_k, pm->step_cos[k], pm->step_sin[k]);
        const fc_real norm_sq = fc_dot2(ar, *sin_k, *sin_k, *cos_k, *cos_k, FC_SHIFT(UNIT, UNIT, UNIT));
        const fc_real half_defect = fc_mul_by16(ar, fc_sub_inline(ar, FC_INT(1, UNIT), norm_sq),
                                                (fc_real16)FC_C(0.5f, UNIT16), FC_SHIFT(UNIT, UNIT16, UNIT));
        /* a defect beyond 2^-15 (none in practice) is corrected by 2^-15 a
         * step: a scratch record, the renormalisation still converges */
        fc_arith scratch = {0u};
        const fc_real16 d = fc_narrow16(&scratch, half_defect, FC_UNIT_FRAC, FC_PHASE_DEFECT16_FRAC);
        const int to_unit = FC_SHIFT(UNIT, PHASE_DEFECT16, UNIT);
        *sin_k = fc_add_inline(ar, *sin_k, fc_mul_by16(ar, *sin_k, d, to_unit));
        *cos_k = fc_add_inline(ar, *cos_k, fc_mul_by16(ar, *cos_k, d, to_unit));
        pm->phi16[sin_of(k)] = fc_narrow16(ar, *sin_k, FC_UNIT_FRAC, FC_UNIT16_FRAC);
        pm->phi16[cos_of(k)] = fc_narrow16(ar, *cos_k, FC_UNIT_FRAC, FC_UNIT16_FRAC);
    }
}

/* ---------------------------------------------------------------------- */
/* recursive least squares                                                 */
/* ---------------------------------------------------------------------- */

static void restart_from(fc_pad_motion *pm, fc_real height_m)
{
    fc_pad_motion_reset(pm);
    pm->theta[0] = height_m; /* the level is the first sample; the modes start at zero */
    pm->learning = true;
}

/* S back to s0 I when rounding has made it lose positive diagonal (fixed
 * backend, a long run without excitation): never observed in the tests. */
static bool covariance_usable(const fc_pad_motion *pm)
{
    for (unsigned i = 0u; i < pm->n; i++) {
        if (!(pm->s[i][i] > FC_INT(0, MAT))) {
            return false;
        }
    }
    return true;
}

/* What a sample at the current phases needs that is not the sample: the
 * RLS gain g (it depends on phi and S only) with the S phi that S's update
 * needs too, and the model's values the sample is checked against
 * (fc_pad_motion_work_ahead may do this before the sample comes: theta, its
 * snapshots and S only change when a step takes a sample):
 * FC_PAD_WORK_SAMPLE_GAIN. */
static void prepare_sample(fc_pad_motion *pm)
{
    fc_arith *ar = &pm->ar;
    const unsigned n = FC_PAD_MAX_PARAMS; /* PARAMETERS_PAST_N */
    const fc_real16 *phi16 = pm->phi16;
    /* S phi (MAT; = (phi' S)' as S is symmetric) and phi' S phi (phi[0]:
     * LEVEL_REGRESSOR, no product), each product rounded: 6 roundings of
     * MAT's 6e-8 a row, far inside what the fit resolves */
    fc_real *s_phi = pm->pending_s_phi;
    /* phi' S phi <= (1 + K) trace(S) < 512: GAIN */
    fc_real phi_s_phi = FC_INT(0, GAIN);
    for (unsigned i = 0u; i < n; i++) {
        fc_real row = pm->s[i][0];
        for (unsigned j = 1u; j < n; j++) {
            row = fc_add_inline(ar, row, fc_mul_by16(ar, pm->s[i][j], phi16[j], FC_SHIFT(MAT, UNIT16, MAT)));
        }
        s_phi[i] = row;
        phi_s_phi = fc_add_inline(ar, phi_s_phi,
                           i == 0u ? fc_convert(ar, row, FC_MAT_FRAC, FC_GAIN_FRAC)
                                   : fc_mul_by16(ar, row, phi16[i], FC_SHIFT(MAT, UNIT16, GAIN)));
    }
    /* g = P phi / (lambda + phi' P phi) = S phi (1 - lambda) / (lambda + (1 - lambda) phi' S phi) */
    const fc_real denominator =
        fc_add_inline(ar, fc_convert(ar, pm->p.forgetting, FC_UNIT_FRAC, FC_RATIO_FRAC),
               fc_mul(ar, pm->one_minus_lambda, phi_s_phi, FC_SHIFT(UNIT, GAIN, RATIO)));
    const fc_real gain_scale = fc_div(ar, pm->one_minus_lambda, denominator, FC_DIV_SHIFT(UNIT, RATIO, UNIT));
    for (unsigned i = 0u; i < n; i++) {
        pm->pending_gain[i] = fc_mul(ar, gain_scale, s_phi[i], FC_SHIFT(UNIT, MAT, MAT)); /* MAT */
    }
    pm->prepared_z_m = model_value(ar, pm->theta, phi16);
    /* what theta_old (H..2H old) predicted for now, once there is one */
    pm->prepared_z_old_m = pm->snapshots >= 2u ? model_value(ar, pm->theta_old, phi16) : FC_INT(0, LENGTH);
}

/* The RLS update of theta with the a-priori residual e (see the header): theta
 * += g e; the update of S that goes with it is left pending
 * (update_covariance_rows), with the gain g and S phi it needs. */
static void rls_update(fc_pad_motion *pm, fc_real residual_m)
{
    fc_arith *ar = &pm->ar;
    for (unsigned i = 0u; i < FC_PAD_MAX_PARAMS; i++) { /* PARAMETERS_PAST_N */
        pm->theta[i] =
            fc_add_inline(ar, pm->theta[i], fc_mul(ar, pm->pending_gain[i], residual_m, FC_SHIFT(MAT, LENGTH, LENGTH)));
    }
    pm->deferred |= (uint8_t)(FC_PAD_WORK_COVARIANCE_HEAD | FC_PAD_WORK_COVARIANCE_TAIL);
}

/* FC_PAD_WORK_COVARIANCE_HEAD updates S's rows [0, COVARIANCE_SPLIT_ROW)
 * (with trace(S)), FC_PAD_WORK_COVARIANCE_TAIL the rest: for 3 modes (n = 7)
 * 13 and 15 of the 28 entries of the upper triangle. The head goes with the
 * summary and the tail with the phases (fc_pad_motion_work_ahead), so that
 * the two slices after a sample are about the same work. */
#define COVARIANCE_SPLIT_ROW 2u

/* Whether S's update of the newest sample inflates: not while trace(S) is
 * above its bound (a scratch sum: past the format is past the bound),
 * decided on S before its first row changes. */
static bool covariance_inflates(const fc_pad_motion *pm)
{
    fc_arith scratch = {0u};
    fc_real trace = FC_INT(0, MAT);
    for (unsigned i = 0u; i < FC_PAD_MAX_PARAMS; i++) { /* PARAMETERS_PAST_N */
        trace = fc_add_inline(&scratch, trace, pm->s[i][i]);
    }
    return scratch.saturated == 0u && trace <= pm->p.covariance_trace_max;
}

/* Rows [row_begin, row_end) of the newest sample's S = (S - g phi' S) /
 * lambda, the upper triangle mirrored (2 n (n + 1) / 2 = 56 products for 3
 * modes in all). Each entry reads only its own old value, so the update in
 * parts is the update in one, bit for bit. */
static void update_covariance_rows(fc_pad_motion *pm, unsigned row_begin, unsigned row_end)
{
    fc_arith *ar = &pm->ar;
    const unsigned n = FC_PAD_MAX_PARAMS; /* PARAMETERS_PAST_N */
    const fc_real *gain = pm->pending_gain;
    const fc_real *s_phi = pm->pending_s_phi;
    /* g_i (S phi)_j inlined on the ATmega too: it runs 28 times an update
     * (fc/scalar.h, fc_mul_inline) */
    for (unsigned i = row_begin; i < row_end; i++) {
        for (unsigned j = i; j < n; j++) {
            fc_real sij = fc_sub_inline(ar, pm->s[i][j], fc_mul_inline(ar, gain[i], s_phi[j], FC_SHIFT(MAT, MAT, MAT)));
            if (pm->covariance_inflate) {
                sij = fc_add_inline(ar, sij, fc_mul_gain(ar, sij, pm->inflation, FC_GAIN_SHIFT(MAT, MAT)));
            }
            pm->s[i][j] = sij;
            pm->s[j][i] = sij;
        }
    }
}

/* w_k += kappa d_arg / T_sample, d_arg = (a_prev b - b_prev a) / |C|^2 (the header). */
static void adapt_frequencies(fc_pad_motion *pm, const fc_real *amplitude_before)
{
    fc_arith *ar = &pm->ar;
    if (pm->p.frequency_gain == FC_INT(0, UNIT) || pm->since_sample_s <= FC_INT(0, TIME)) {
        return;
    }
    for (unsigned k = 0u; k < pm->p.mode_count; k++) {
        const size_t a_index = (size_t)2u * k;
        const fc_real a_prev = amplitude_before[a_index], b_prev = amplitude_before[a_index + 1u];
        const fc_real a = pm->theta[sin_of(k)], b = pm->theta[cos_of(k)];
        const fc_real size_sq = fc_dot2(ar, a, a, b, b, FC_SHIFT(LENGTH, LENGTH, RATIO));
        if (size_sq < pm->amplitude_min_sq) {
            continue;
        }
        const fc_real cross = fc_dot2(ar, a_prev, b, fc_neg(ar, b_prev), a, FC_SHIFT(LENGTH, LENGTH, RATIO));
        /* the turn in rad, |d_arg| <= 1 (a larger one is not a frequency error) */
        const fc_real turn = fc_clamp(fc_div(ar, cross, size_sq, FC_DIV_SHIFT(RATIO, RATIO, UNIT)),
                                      FC_INT(-1, UNIT), FC_INT(1, UNIT));
        const fc_real drift_radps = fc_div(ar, turn, pm->since_sample_s, FC_DIV_SHIFT(UNIT, TIME, RATE));
        const fc_real omega = fc_add(ar, pm->omega_radps[k],
                                     fc_mul(ar, pm->p.frequency_gain, drift_radps, FC_SHIFT(UNIT, RATE, RATE)));
        set_mode_frequency(pm, k, fc_clamp(omega, pm->omega_min_radps[k], pm->omega_max_radps[k]));
    }
}

/* What the estimate says of the fit itself: the bounds, the dominant mode and
 * the confidence's error ratio. They change only with theta, w_k or the error
 * mean, i.e. when a sample is taken or the estimate restarts, and are worked
 * out after that step, not on every step (FC_PAD_WORK_SUMMARY). */
static void summarise_fit(fc_pad_motion *pm)
{
    fc_arith summary_ar = {0u}; /* its own record: a saturation here stands for every step until the next */
    fc_arith *ar = &summary_ar;
    fc_pad_motion_summary *f = &pm->summary;
    f->heave_bound_m = FC_INT(0, LENGTH);
    f->accel_bound_mps2 = FC_INT(0, ACCEL);
    f->dominant_mode = 0u;
    fc_real largest = FC_INT(-1, LENGTH);
    for (unsigned k = 0u; k < pm->p.mode_count; k++) {
        const fc_real size = fc_add_inline(ar, fc_abs(ar, pm->theta[sin_of(k)]), fc_abs(ar, pm->theta[cos_of(k)]));
        f->heave_bound_m = fc_add_inline(ar, f->heave_bound_m, size);
        f->accel_bound_mps2 =
            fc_add_inline(ar, f->accel_bound_mps2, fc_mul_gain(ar, size, pm->omega_sq_gain[k], FC_GAIN_SHIFT(LENGTH, ACCEL)));
        if (size > largest) {
            largest = size;
            f->dominant_mode = (uint8_t)k;
        }
    }
    f->dominant_amplitude_m = fc_max(largest, FC_INT(0, LENGTH));
    f->dominant_period_s = fc_div(ar, FC_TWO_PI, pm->omega_radps[f->dominant_mode], FC_DIV_SHIFT(ANGLE, RATE, TIME));
    /* mean / tolerance for the confidence 1 - mean / tolerance */
    f->error_ratio = fc_mul_gain(ar, pm->error_mean_m, pm->inv_tolerance, FC_GAIN_SHIFT(LENGTH, UNIT));
    f->saturated = summary_ar.saturated; /* reported on every step the summary stands for */
}

/* ---------------------------------------------------------------------- */
/* deferred work: the pieces of the next step that need no sample          */
/* ---------------------------------------------------------------------- */

/* What a step needs done before it starts: all but the sample's gain, which
 * only a sample needs. */
#define PIECES_BEFORE_A_STEP                                                                                 \
    (FC_PAD_WORK_COVARIANCE_HEAD | FC_PAD_WORK_COVARIANCE_TAIL | FC_PAD_WORK_PHASES | FC_PAD_WORK_SUMMARY)

/* Whether piece is deferred and among those of mask; if so it is taken off
 * the list, to be done now. */
static bool take_piece(fc_pad_motion *pm, unsigned mask, unsigned piece)
{
    if ((pm->deferred & mask & piece) == 0u) {
        return false;
    }
    pm->deferred &= (uint8_t)~piece;
    return true;
}

/* The deferred pieces among those of mask, in their order. */
static fc_step_status run_deferred(fc_pad_motion *pm, unsigned mask)
{
    fc_step_status status = FC_STEP_OK;
    if ((pm->deferred & mask) == 0u) {
        return status; /* the common case once the spare minor frames have done it all */
    }
    if (take_piece(pm, mask, FC_PAD_WORK_COVARIANCE_HEAD)) {
        update_rotations(pm);
        pm->covariance_inflate = covariance_inflates(pm);
        update_covariance_rows(pm, 0u, COVARIANCE_SPLIT_ROW);
    }
    if (take_piece(pm, mask, FC_PAD_WORK_COVARIANCE_TAIL)) {
        update_covariance_rows(pm, COVARIANCE_SPLIT_ROW, FC_PAD_MAX_PARAMS);
        if (!covariance_usable(pm)) {
            covariance_restart(pm);
            status = FC_STEP_DEGRADED;
        }
    }
    if (take_piece(pm, mask, FC_PAD_WORK_PHASES)) {
        advance_phases(pm);
    }
    if (take_piece(pm, mask, FC_PAD_WORK_SUMMARY)) {
        summarise_fit(pm);
    }
    /* (while not learning the next sample restarts the estimate, no RLS) */
    if (take_piece(pm, mask, FC_PAD_WORK_SAMPLE_GAIN) && pm->learning) {
        prepare_sample(pm);
    }
    return status;
}

/* A sample: used (RLS and the prediction check), or an outlier. */
static fc_step_status take_sample(fc_pad_motion *pm, fc_real height_m)
{
    fc_arith *ar = &pm->ar;
    pm->deferred |= (uint8_t)FC_PAD_WORK_SUMMARY; /* theta, w_k or the error mean change on every path below */
    if (!pm->learning) {
        restart_from(pm, height_m);
        return FC_STEP_OK;
    }
    (void)run_deferred(pm, FC_PAD_WORK_SAMPLE_GAIN);
    const fc_real residual = fc_sub_inline(ar, height_m, pm->prepared_z_m);
    if (fc_abs(ar, residual) > pm->p.outlier_m) {
        pm->outliers_in_row++;
        if (pm->outliers_in_row >= pm->p.outlier_reset_count) {
            restart_from(pm, height_m);
            return FC_STEP_DEGRADED;
        }
        return FC_STEP_BAD_INPUT;
    }
    pm->outliers_in_row = 0u;
    if (pm->snapshots >= 2u) {
        const fc_real error = fc_sub(ar, height_m, pm->prepared_z_old_m);
        const fc_real step = fc_mul(ar, pm->p.error_average_gain, fc_sub(ar, fc_abs(ar, error), pm->error_mean_m),
                                    FC_SHIFT(UNIT, LENGTH, LENGTH));
        pm->error_mean_m = fc_add(ar, pm->error_mean_m, step);
    }
    fc_real amplitude_before[2u * FC_PAD_MAX_MODES] = {0}; /* (zeroed for clang-tidy) */
    for (unsigned i = 0u; i + 1u < pm->n; i++) {
        amplitude_before[i] = pm->theta[1u + i];
    }
    rls_update(pm, residual);
    adapt_frequencies(pm, amplitude_before);
    pm->since_sample_s = FC_INT(0, TIME);
    return FC_STEP_OK;
}

/* Every H seconds: theta_old <- theta_new <- theta. */
static void renew_snapshots(fc_pad_motion *pm)
{
    fc_arith *ar = &pm->ar;
    pm->since_snapshot_s = fc_add_inline(ar, pm->since_snapshot_s, pm->step_s);
    if (pm->since_snapshot_s < pm->p.horizon_s) {
        return;
    }
    pm->since_snapshot_s = FC_INT(0, TIME);
    for (unsigned i = 0u; i < FC_PAD_MAX_PARAMS; i++) {
        pm->theta_old[i] = pm->theta_new[i];
        pm->theta_new[i] = pm->theta[i];
    }
    if (pm->snapshots < 2u) {
        pm->snapshots++;
        if (pm->snapshots == 2u) {
            /* the check starts pessimistic: confidence rises as predictions come true */
            pm->error_mean_m = pm->p.tolerance_m;
            pm->deferred |= (uint8_t)FC_PAD_WORK_SUMMARY;
        }
    }
}

static void fill_estimate(fc_pad_motion *pm, fc_pad_motion_estimate *out)
{
    fc_arith *ar = &pm->ar;
    const fc_pad_motion_summary *f = &pm->summary;
    /* not learning, theta is zero (fc_pad_motion_reset): so is the trajectory */
    out->now = pm->learning ? model_trajectory(pm, pm->phi16) : (fc_vertical_trajectory){0};
    out->heave_bound_m = f->heave_bound_m;
    out->accel_bound_mps2 = f->accel_bound_mps2;
    out->dominant_mode = f->dominant_mode;
    out->dominant_amplitude_m = f->dominant_amplitude_m;
    out->dominant_period_s = f->dominant_period_s;
    out->mean_m = pm->theta[0];
    out->prediction_error_m = pm->error_mean_m;
    out->observed_s = pm->observed_s;
    out->learning = pm->learning;
    out->confidence = FC_INT(0, UNIT);
    if (pm->learning && pm->snapshots >= 2u && pm->observed_s >= pm->p.observe_min_s) {
        /* 1 - mean / tolerance, clamped to [0, 1] */
        out->confidence = fc_clamp(fc_sub(ar, FC_INT(1, UNIT), fc_min(f->error_ratio, FC_INT(1, UNIT))),
                                   FC_INT(0, UNIT), FC_INT(1, UNIT));
    }
    ar->saturated |= f->saturated;
}

fc_step_status fc_pad_motion_work_ahead(fc_pad_motion *pm)
{
    /* the slices of the header, about the same work each (the summary with
     * the head, the phases with the tail) */
    static const uint8_t slices[] = {
        FC_PAD_WORK_COVARIANCE_HEAD | FC_PAD_WORK_SUMMARY,
        FC_PAD_WORK_COVARIANCE_TAIL | FC_PAD_WORK_PHASES,
        FC_PAD_WORK_SAMPLE_GAIN,
    };
    if (!pm->ready) {
        return FC_STEP_NOT_READY;
    }
    pm->ar.saturated = 0u;
    fc_step_status status = FC_STEP_OK;
    for (size_t i = 0u; i < sizeof slices / sizeof slices[0]; i++) {
        if ((pm->deferred & slices[i]) != 0u) {
            status = run_deferred(pm, slices[i]);
            break;
        }
    }
    if (pm->ar.saturated != 0u) {
        status |= FC_STEP_ARITH_SATURATED;
    }
    return status;
}

void fc_pad_motion_predict_ahead(fc_pad_motion *pm, fc_vertical_trajectory *ahead)
{
    if (!pm->ready) {
        *ahead = (fc_vertical_trajectory){0};
        return;
    }
    fc_arith *ar = &pm->ar;
    fc_real phi_ahead[FC_PAD_MAX_PARAMS];
    for (unsigned i = 0u; i < FC_PAD_MAX_PARAMS; i++) {
        phi_ahead[i] = pm->phi[i];
    }
    for (unsigned k = 0u; k < pm->p.mode_count; k++) {
        /* the phases turned by w_k H */
        const fc_real ahead_rad =
            wrapped_angle(ar, fc_mul(ar, pm->omega_radps[k], pm->p.horizon_s, FC_SHIFT(RATE, TIME, GAIN)));
        fc_real ahead_sin, ahead_cos;
        fc_sincos(ar, ahead_rad, &ahead_sin, &ahead_cos);
        rotate(ar, &phi_ahead[sin_of(k)], &phi_ahead[cos_of(k)], ahead_cos, ahead_sin);
    }
    fc_real16 phi16_ahead[FC_PAD_MAX_PARAMS];
    for (unsigned i = 0u; i < FC_PAD_MAX_PARAMS; i++) {
        phi16_ahead[i] = fc_narrow16(ar, phi_ahead[i], FC_UNIT_FRAC, FC_UNIT16_FRAC);
    }
    *ahead = model_trajectory(pm, phi16_ahead);
}

fc_step_status fc_pad_motion_step(fc_pad_motion *pm, const fc_pad_motion_sample *sample,
                                  fc_pad_motion_estimate *out)
{
    if (!pm->ready) {
        *out = (fc_pad_motion_estimate){0};
        return FC_STEP_NOT_READY;
    }
    fc_arith *ar = &pm->ar;
    ar->saturated = 0u;
    /* what no minor frame did of the previous step's pieces: its sample's
     * covariance update, the summary, and the phases turned to this step's
     * time (with the rotations of the frequencies that sample left); the
     * sample's gain when a sample comes */
    fc_step_status status = run_deferred(pm, PIECES_BEFORE_A_STEP);
    if (sample->fresh) {
        if (fc_within(sample->height_m, FC_C(FC_INPUT_MAX_LENGTH_M, LENGTH))) {
            status |= take_sample(pm, sample->height_m);
        } else {
            status |= FC_STEP_BAD_INPUT;
        }
    }
    fill_estimate(pm, out);
    /* the phases turn to the next step's time when it comes: what its sample
     * changes in between (the rotations) can wait for a minor frame; the
     * gain is of the next step's phases */
    pm->deferred |= (uint8_t)(FC_PAD_WORK_PHASES | FC_PAD_WORK_SAMPLE_GAIN);
    if (pm->learning) {
        pm->since_sample_s = fc_min(fc_add_inline(ar, pm->since_sample_s, pm->step_s), FC_INT(60, TIME));
        pm->observed_s = fc_min(fc_add_inline(ar, pm->observed_s, pm->step_s), FC_INT(600, TIME));
        renew_snapshots(pm);
    }
    if (ar->saturated != 0u) {
        status |= FC_STEP_ARITH_SATURATED;
    }
    return status;
}
