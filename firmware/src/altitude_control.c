/* altitude_control.c - SSC and baseline altitude laws (fc/altitude_control.h). */
#include "fc/altitude_control.h"

/* ---------------------------------------------------------------------- */
/* parameters                                                              */
/* ---------------------------------------------------------------------- */

void fc_altitude_control_set_mass(fc_altitude_control_params *p, fc_real mass_kg)
{
    fc_arith ar = {0u};
    p->theta0_kg = mass_kg;
    /* payload changes of up to -25 % / +25 % around the nominal mass */
    p->mass_min_kg = fc_mul(&ar, mass_kg, FC_C(0.75f, RATIO), FC_SHIFT(MASS, RATIO, MASS));
    p->mass_max_kg = fc_mul(&ar, mass_kg, FC_C(1.25f, RATIO), FC_SHIFT(MASS, RATIO, MASS));
}

void fc_altitude_control_default_params(fc_altitude_control_params *p, fc_real dt_s, fc_real mass_kg)
{
    fc_arith ar = {0u};
    p->law = FC_ALT_LAW_SSC;
    p->modulation = FC_SSC_MODULATION_CONSTANT;
    p->adaptive = false;
    p->velocity_measured = true;
    p->dt_s = dt_s;
    p->gravity_mps2 = FC_C(9.81f, ACCEL);
    fc_altitude_control_set_mass(p, mass_kg);
    p->ground_gain_max = FC_C(1.1f, RATIO);
    p->tilt_cos_min = FC_C(0.5f, RATIO);
    /* thrust in [0, 2 x weight] as in the dissertation's simulation */
    p->thrust_min_n = FC_INT(0, FORCE);
    p->thrust_max_n = fc_mul(&ar, mass_kg, FC_C(2.0f * 9.81f, ACCEL), FC_SHIFT(MASS, ACCEL, FORCE));
    p->thrust_authority_n = p->thrust_max_n;
    /* 4.4: tau_av = 0.1, K1 = l0 = 2, a_m = 5, kappa_m = 1, rho = 50, gamma = 5, for
     * its 4 kg vehicle. For another mass the law is scaled so that the closed
     * loop is the same in accelerations: forces (rho, delta, k0 |sigma|) and
     * Theta's gain gamma scale with m / 4 kg, kappa_m (acceleration per newton)
     * with 4 kg / m; l0, a_m and tau_av are rates and stay. */
    const fc_real mass_ratio = fc_mul(&ar, mass_kg, FC_C(0.25f, RATIO), FC_SHIFT(MASS, RATIO, RATIO));
    p->l0_per_s = FC_C(2.0f, GAIN);
    p->tau_av_s = FC_C(0.1f, DT);
    p->a_m_per_s = FC_C(5.0f, GAIN);
    p->kappa_m_per_kg = fc_div(&ar, FC_C(1.0f, GAIN), mass_ratio, FC_DIV_SHIFT(GAIN, RATIO, GAIN));
    p->rho_n = fc_mul(&ar, FC_C(50.0f, FORCE), mass_ratio, FC_SHIFT(FORCE, RATIO, FORCE));
    p->delta_n = fc_mul(&ar, FC_C(0.5f, FORCE), mass_ratio, FC_SHIFT(FORCE, RATIO, FORCE));
    p->k0_ns_per_m = fc_mul(&ar, FC_C(1.0f, GAIN), mass_ratio, FC_SHIFT(GAIN, RATIO, GAIN));
    p->tau_f_s = FC_C(0.01f, DT);
    p->gamma = fc_mul(&ar, FC_C(5.0f, GAIN), mass_ratio, FC_SHIFT(GAIN, RATIO, GAIN));
    p->actuator_lag_s = FC_INT(0, DT);
    /* baselines, tuned by the rules in the header for w_v = 8 rad/s, zeta = 1,
     * and the disturbance bounds of 4.4 */
    p->boundary_layer_mps = FC_C(0.05f, VEL);
    p->stw_k1 = fc_mul(&ar, mass_kg, FC_C(1.5f * 4.47f, GAIN), FC_SHIFT(MASS, GAIN, GAIN)); /* L = 20 m/s^3 */
    p->stw_k2_nps = fc_mul(&ar, mass_kg, FC_C(1.1f * 20.0f, GAIN), FC_SHIFT(MASS, GAIN, GAIN));
    p->pid_kp_v_n_per_mps = fc_mul(&ar, mass_kg, FC_C(16.0f, GAIN), FC_SHIFT(MASS, GAIN, GAIN));
    p->pid_ki_v_n_per_m = fc_mul(&ar, mass_kg, FC_C(16.0f, GAIN), FC_SHIFT(MASS, GAIN, GAIN));
    p->pid_kp_z_per_s = FC_C(2.0f, GAIN);
    p->pid_ki_z_per_s2 = FC_C(0.5f, GAIN);
    p->pid_vel_limit_mps = FC_C(3.0f, VEL);
}

static bool all_finite(const fc_altitude_control_params *p)
{
    const fc_real values[] = {
        p->dt_s, p->gravity_mps2, p->theta0_kg, p->mass_min_kg, p->mass_max_kg,
        p->ground_gain_max, p->tilt_cos_min, p->thrust_min_n, p->thrust_max_n, p->l0_per_s,
        p->tau_av_s, p->a_m_per_s, p->kappa_m_per_kg, p->rho_n, p->delta_n, p->k0_ns_per_m,
        p->tau_f_s, p->gamma, p->actuator_lag_s, p->boundary_layer_mps,
        p->stw_k1, p->stw_k2_nps, p->pid_kp_z_per_s, p->pid_ki_z_per_s2, p->pid_kp_v_n_per_mps,
        p->pid_ki_v_n_per_m, p->pid_vel_limit_mps};
    for (unsigned i = 0u; i < sizeof values / sizeof values[0]; i++) {
        if (!fc_is_finite(values[i])) {
            return false;
        }
    }
    return true;
}

/* Remark 9: the eta-dynamics of relative degree two are minimum phase over
 * kp in [kp_min, ...] (kp_min = 1/m_max) when these three hold. */
static bool relative_degree_two_minimum_phase(const fc_altitude_control_params *p)
{
    fc_arith ar = {0u};
    const fc_real kp_min = fc_div(&ar, FC_INT(1, MASS), p->mass_max_kg, FC_DIV_SHIFT(MASS, MASS, RATIO));
    const fc_real tau_f_l0 = fc_mul(&ar, p->tau_f_s, p->l0_per_s, FC_SHIFT(DT, GAIN, RATIO));
    const fc_real tau_av_kappa_l0 =
        fc_mul(&ar, fc_mul(&ar, p->tau_av_s, p->kappa_m_per_kg, FC_SHIFT(DT, GAIN, RATIO)), p->l0_per_s,
               FC_SHIFT(RATIO, GAIN, RATIO));
    const fc_real third = fc_add(
        &ar, fc_mul(&ar, tau_av_kappa_l0, fc_sub(&ar, FC_INT(1, RATIO), tau_f_l0), FC_SHIFT(RATIO, RATIO, RATIO)),
        fc_mul(&ar, fc_mul(&ar, p->tau_f_s, kp_min, FC_SHIFT(DT, RATIO, RATIO)),
               fc_add(&ar, p->a_m_per_s, p->l0_per_s), FC_SHIFT(RATIO, GAIN, RATIO)));
    return ar.saturated == 0u && tau_f_l0 < FC_INT(1, RATIO) && tau_av_kappa_l0 < kp_min && third < kp_min;
}

/* Upper bounds: what the fixed formats hold (GAIN +-32768, VEL and ACCEL +-512,
 * MASS +-128), applied in both backends so that they accept the same tunings
 * and no float intermediate can overflow. */
static bool gains_in_range(const fc_altitude_control_params *p)
{
    const fc_real gain_max = FC_INT(30000, GAIN);
    const fc_real gains[] = {p->l0_per_s,      p->a_m_per_s,       p->kappa_m_per_kg,      p->k0_ns_per_m,
                             p->gamma,         p->stw_k1,          p->stw_k2_nps,          p->pid_kp_z_per_s,
                             p->pid_ki_z_per_s2, p->pid_kp_v_n_per_mps, p->pid_ki_v_n_per_m};
    for (unsigned i = 0u; i < sizeof gains / sizeof gains[0]; i++) {
        if (gains[i] > gain_max) {
            return false;
        }
    }
    return p->kappa_m_per_kg >= FC_C(0.01f, GAIN) && p->gravity_mps2 <= FC_INT(100, ACCEL) &&
           p->boundary_layer_mps >= FC_C(1.0e-3f, VEL) && p->boundary_layer_mps <= FC_INT(500, VEL) &&
           p->pid_vel_limit_mps <= FC_INT(500, VEL);
}

static bool altitude_params_valid(const fc_altitude_control_params *p)
{
    const fc_real zero = FC_INT(0, UNIT);
    return all_finite(p) && gains_in_range(p) && p->law < FC_ALT_LAW_COUNT &&
           p->modulation <= FC_SSC_MODULATION_EXTRA && p->dt_s > zero &&
           p->dt_s <= FC_C(0.1f, DT) && p->gravity_mps2 > zero && p->mass_min_kg > zero &&
           p->mass_min_kg <= p->theta0_kg && p->theta0_kg <= p->mass_max_kg &&
           p->ground_gain_max >= FC_INT(1, RATIO) && p->ground_gain_max <= FC_INT(10, RATIO) &&
           p->mass_max_kg <= FC_INT(100, MASS) && p->thrust_max_n <= FC_INT(2000, FORCE) &&
           p->thrust_authority_n >= FC_C(1.0f / 16.0f, FORCE) && p->thrust_authority_n <= FC_INT(2000, FORCE) &&
           p->rho_n <= FC_INT(2000, FORCE) && p->delta_n <= FC_INT(2000, FORCE) &&
           p->tau_av_s >= FC_C(1.0e-3f, DT) && p->tau_av_s <= FC_INT(1, DT) &&
           (p->velocity_measured || (p->tau_f_s >= FC_C(1.0e-3f, DT) && p->tau_f_s <= FC_INT(1, DT))) &&
           p->tilt_cos_min > zero &&
           p->tilt_cos_min <= FC_INT(1, RATIO) && p->thrust_min_n >= zero &&
           p->thrust_max_n > p->thrust_min_n && p->l0_per_s > zero && p->tau_av_s > zero &&
           p->a_m_per_s > zero && p->kappa_m_per_kg > zero && p->rho_n >= zero &&
           p->delta_n >= zero && p->k0_ns_per_m >= zero &&
           (p->velocity_measured || p->tau_f_s > zero) && p->gamma >= zero && p->boundary_layer_mps > zero &&
           p->actuator_lag_s >= zero && p->actuator_lag_s <= FC_INT(1, DT) &&
           p->stw_k1 >= zero && p->stw_k2_nps >= zero && p->pid_kp_z_per_s >= zero &&
           p->pid_ki_z_per_s2 >= zero && p->pid_kp_v_n_per_mps >= zero &&
           p->pid_ki_v_n_per_m >= zero && p->pid_vel_limit_mps > zero &&
           (p->velocity_measured || p->law != FC_ALT_LAW_SSC || relative_degree_two_minimum_phase(p));
}

void fc_altitude_control_variant_params(fc_altitude_control_params *p, fc_altitude_variant v, fc_real dt_s,
                                        fc_real mass_kg)
{
    fc_arith ar = {0u};
    fc_altitude_control_default_params(p, dt_s, mass_kg);
    switch (v) {
    case FC_ALT_VARIANT_SSC_ADAPTIVE:
        p->adaptive = true;
        break;
    case FC_ALT_VARIANT_SSC_NORM:
        p->modulation = FC_SSC_MODULATION_NORM_OBSERVER;
        break;
    case FC_ALT_VARIANT_SSC_NORM_ADAPTIVE:
        p->modulation = FC_SSC_MODULATION_NORM_OBSERVER;
        p->adaptive = true;
        break;
    case FC_ALT_VARIANT_SSC_EXTRA:
        p->modulation = FC_SSC_MODULATION_EXTRA;
        break;
    case FC_ALT_VARIANT_SSC_REL2:
    case FC_ALT_VARIANT_SSC_REL2_ADAPTIVE:
    case FC_ALT_VARIANT_SSC_REL2_NORM:
        p->velocity_measured = false;
        p->kappa_m_per_kg = fc_mul(&ar, p->kappa_m_per_kg, FC_C(0.5f, RATIO), FC_SHIFT(GAIN, RATIO, GAIN));
        p->adaptive = v == FC_ALT_VARIANT_SSC_REL2_ADAPTIVE;
        if (v == FC_ALT_VARIANT_SSC_REL2_NORM) {
            p->modulation = FC_SSC_MODULATION_NORM_OBSERVER;
        }
        break;
    case FC_ALT_VARIANT_PID:
        p->law = FC_ALT_LAW_PID;
        break;
    case FC_ALT_VARIANT_SMC:
        p->law = FC_ALT_LAW_SMC_SIGN;
        break;
    case FC_ALT_VARIANT_SMC_BOUNDARY:
        p->law = FC_ALT_LAW_SMC_BOUNDARY;
        break;
    case FC_ALT_VARIANT_SUPER_TWISTING:
        p->law = FC_ALT_LAW_SUPER_TWISTING;
        break;
    case FC_ALT_VARIANT_SSC:
    case FC_ALT_VARIANT_COUNT:
    default:
        break;
    }
}

/* First-order pole e^(-dt/tau) and its input gain 1 - e^(-dt/tau), dt and tau in DT. */
static void first_order_zoh(fc_arith *ar, fc_real dt_s, fc_real tau_s, fc_real *pole, fc_real *gain)
{
    const fc_real dt_over_tau = fc_div(ar, dt_s, tau_s, FC_DIV_SHIFT(DT, DT, RATIO));
    *pole = fc_exp_neg(ar, dt_over_tau);
    *gain = fc_sub(ar, FC_INT(1, UNIT), *pole);
}

static void eta_observer_zoh(fc_arith *ar, fc_real rate_per_s, fc_real dt_s, fc_real *pole, fc_real *in_gain_s)
{
    *pole = fc_exp_neg(ar, fc_mul(ar, rate_per_s, dt_s, FC_SHIFT(GAIN, DT, RATIO)));
    *in_gain_s = fc_div(ar, fc_sub(ar, FC_INT(1, UNIT), *pole), rate_per_s, FC_DIV_SHIFT(UNIT, GAIN, DT));
}

/* The constants of the feed-forward bound and of the adaptation's proportional
 * part. Extreme but valid parameters push some intermediates past their
 * formats; each is capped where it no longer changes the law (products in a
 * scratch fc_arith: fixed saturates at the format's end, float does not, and
 * the cap gives both the same value), so that both backends accept the same
 * tunings with the same constants. */
static void adaptation_and_feed_forward_constants(fc_altitude_control *c)
{
    fc_arith *ar = &c->ar;
    fc_arith scratch = {0u};
    const fc_altitude_control_params *p = &c->p;
    /* z_r'' fed forward: what the thrust gives level for every Theta inside its
     * bounds, [thrust_min kp_max - g, thrust_max kp_min - g] (kp = 1/Theta),
     * capped at 400 m/s^2 (ACCEL holds 512) and widened to hold 0 so that it never
     * biases a steady flight */
    const fc_real accel_cap = FC_INT(400, ACCEL);
    const fc_real thrust_up = fc_min(fc_mul(&scratch, p->thrust_max_n, c->kp_min_per_kg, FC_SHIFT(FORCE, RATIO, ACCEL)),
                                     accel_cap);
    const fc_real thrust_down = fc_min(
        fc_mul(&scratch, p->thrust_min_n, c->kp_max_per_kg, FC_SHIFT(FORCE, RATIO, ACCEL)), accel_cap);
    c->ref_accel_max_mps2 = fc_max(fc_sub(ar, thrust_up, p->gravity_mps2), FC_INT(0, ACCEL));
    c->ref_accel_min_mps2 = fc_min(fc_sub(ar, thrust_down, p->gravity_mps2), FC_INT(0, ACCEL));
    /* damping of the adaptive mode: gamma_p = 2 zeta sqrt(gamma Theta0) / g (header,
     * "Adaptation in discrete time"), capped like the gains (GAIN holds 32768) */
    const fc_real gain_cap = FC_INT(30000, GAIN);
    const fc_real gamma_theta0 = fc_min(fc_mul(&scratch, p->gamma, p->theta0_kg, FC_SHIFT(GAIN, MASS, GAIN)), gain_cap);
    const fc_real two_zeta = fc_div(ar, FC_C(2.0f * FC_ALT_THETA_DAMPING, RATIO), c->lag_divisor,
                                    FC_DIV_SHIFT(RATIO, RATIO, RATIO)); /* the lag schedule */
    const fc_real two_zeta_sqrt =
        fc_mul(ar, two_zeta, fc_sqrt(ar, gamma_theta0, FC_GAIN_FRAC), FC_SHIFT(RATIO, GAIN, GAIN));
    const fc_real gamma_p = fc_min(fc_div(&scratch, two_zeta_sqrt, p->gravity_mps2, FC_DIV_SHIFT(GAIN, ACCEL, GAIN)),
                                   gain_cap);
    c->k.gamma_p = fc_gain_of(gamma_p, FC_GAIN_FRAC);
    /* its low-pass: tau_p = 1/(4 w_theta), w_theta = g sqrt(gamma/Theta0), a lag of
     * atan(1/4) at the mode: dt/tau_p = 4 g sqrt(gamma/Theta0) dt, capped at 100
     * (e^-100 is 0 in both backends; RATIO holds 128) */
    const fc_real gamma_over_theta0 =
        fc_min(fc_div(&scratch, p->gamma, p->theta0_kg, FC_DIV_SHIFT(GAIN, MASS, GAIN)), gain_cap);
    const fc_real mode_rate_per_s = fc_mul(ar, p->gravity_mps2, fc_sqrt(ar, gamma_over_theta0, FC_GAIN_FRAC),
                                           FC_SHIFT(ACCEL, GAIN, GAIN)); /* <= 100 x 174, inside GAIN */
    const fc_real mode_rate_dt =
        fc_min(fc_mul(&scratch, mode_rate_per_s, p->dt_s, FC_SHIFT(GAIN, DT, RATIO)), FC_INT(25, RATIO));
    const fc_real dt_over_tau_p = fc_mul(ar, FC_INT(4, RATIO), mode_rate_dt, FC_SHIFT(RATIO, RATIO, RATIO));
    c->k.damping_lp = fc_gain_of(fc_sub(ar, FC_INT(1, UNIT), fc_exp_neg(ar, dt_over_tau_p)), FC_UNIT_FRAC);
    /* the bound of sigma phi in the proportional part: (Theta_max - Theta_min)/gamma_p
     * (<= 100 kg), no more than 10^4 so that gamma_p times it stays inside MASS for a
     * tiny gamma_p */
    c->sigma_phi_max = FC_INT(10000, SIGMA_PHI);
    if (gamma_p >= FC_C(0.01f, GAIN)) {
        c->sigma_phi_max = fc_div(ar, fc_sub(ar, c->theta_max_kg, c->theta_min_kg), gamma_p,
                                  FC_DIV_SHIFT(MASS, GAIN, SIGMA_PHI));
    }
}

/* The lag schedule (header, "Lag schedule"): d = 1 + w_theta L with
 * w_theta = g sqrt(gamma/Theta0) of the tuning given, capped at 100, and
 * gamma <- gamma/d; the damping ratio is divided by d where gamma_p is formed. */
static void lag_schedule(fc_altitude_control *c)
{
    fc_arith *ar = &c->ar;
    fc_arith scratch = {0u};
    fc_altitude_control_params *p = &c->p;
    const fc_real gamma_over_theta0 =
        fc_min(fc_div(&scratch, p->gamma, p->theta0_kg, FC_DIV_SHIFT(GAIN, MASS, GAIN)), FC_INT(30000, GAIN));
    const fc_real mode_rate_per_s = fc_mul(ar, p->gravity_mps2, fc_sqrt(ar, gamma_over_theta0, FC_GAIN_FRAC),
                                           FC_SHIFT(ACCEL, GAIN, GAIN));
    const fc_real lag_phase =
        fc_min(fc_mul(&scratch, mode_rate_per_s, p->actuator_lag_s, FC_SHIFT(GAIN, DT, RATIO)), FC_INT(99, RATIO));
    c->lag_divisor = fc_add(ar, FC_INT(1, RATIO), lag_phase);
    p->gamma = fc_div(ar, p->gamma, c->lag_divisor, FC_DIV_SHIFT(GAIN, RATIO, GAIN));
}

static void compute_discretisation(fc_altitude_control *c)
{
    fc_arith *ar = &c->ar;
    const fc_altitude_control_params *p = &c->p;
    fc_altitude_gains *k = &c->k;
    /* averaging filter (4.7): a = e^(-dt/tau_av) */
    fc_real avg_gain;
    first_order_zoh(ar, p->dt_s, p->tau_av_s, &c->avg_pole, &avg_gain);
    k->avg = fc_gain_of(avg_gain, FC_UNIT_FRAC);
    /* prediction-error loop (4.5): b = e^(-a_m dt), c = (a - b)/(a_m - 1/tau_av) */
    const fc_real a_m_dt = fc_mul(ar, p->a_m_per_s, p->dt_s, FC_SHIFT(GAIN, DT, RATIO));
    c->pred_pole = fc_exp_neg(ar, a_m_dt);
    k->pred_decay = fc_gain_of(fc_sub(ar, FC_INT(1, UNIT), c->pred_pole), FC_UNIT_FRAC);
    const fc_real inv_tau_av = fc_div(ar, FC_INT(1, DT), p->tau_av_s, FC_DIV_SHIFT(DT, DT, GAIN));
    const fc_real pole_gap = fc_sub(ar, p->a_m_per_s, inv_tau_av); /* GAIN, 1/s */
    const fc_real pole_gap_dt = fc_mul(ar, pole_gap, p->dt_s, FC_SHIFT(GAIN, DT, RATIO));
    fc_real c_s; /* DT */
    if (fc_abs(ar, pole_gap_dt) < FC_C(1.0e-3f, RATIO)) {
        /* a_m ~ 1/tau_av: c = dt e^(-a_m dt) (1 + O(gap dt)), the average of both poles */
        const fc_real mean_pole = fc_mul(ar, fc_add(ar, c->avg_pole, c->pred_pole), FC_C(0.5f, UNIT),
                                         FC_SHIFT(UNIT, UNIT, UNIT));
        c_s = fc_mul(ar, p->dt_s, mean_pole, FC_SHIFT(DT, UNIT, DT));
    } else {
        const fc_real pole_diff = fc_sub(ar, c->avg_pole, c->pred_pole);
        c_s = fc_div(ar, pole_diff, pole_gap, FC_DIV_SHIFT(UNIT, GAIN, DT));
    }
    c->pred_gain = fc_mul(ar, p->kappa_m_per_kg, c_s, FC_SHIFT(GAIN, DT, RATIO));
    k->pred_input = fc_gain_of_product(p->kappa_m_per_kg, FC_GAIN_FRAC, c_s, FC_DT_FRAC);
    /* plant gain bounds (4.15) with the tilt compensated: kp = k_g / m in
     * [1/m_max, k_g_max/m_min]; Theta bounds are their inverses */
    c->kp_max_per_kg = fc_div(ar, p->ground_gain_max, p->mass_min_kg, FC_DIV_SHIFT(RATIO, MASS, RATIO));
    c->theta_min_kg = fc_div(ar, p->mass_min_kg, p->ground_gain_max, FC_DIV_SHIFT(MASS, RATIO, MASS));
    c->theta_max_kg = p->mass_max_kg;
    c->kp_min_per_kg = fc_div(ar, FC_INT(1, MASS), c->theta_max_kg, FC_DIV_SHIFT(MASS, MASS, RATIO));
    k->kp_max = fc_gain_of(c->kp_max_per_kg, FC_RATIO_FRAC);
    k->kp_min = fc_gain_of(c->kp_min_per_kg, FC_RATIO_FRAC);
    c->kp_max_over_kappa =
        fc_div(ar, c->kp_max_per_kg, p->kappa_m_per_kg, FC_DIV_SHIFT(RATIO, GAIN, RATIO));
    /* c_eta = max |1 - kp/kappa_m| over [kp_min, kp_max], the coefficient of eta1
     * in d_eq2 (4.37); (4.38) bounds it by 1 + kp_max/kappa_m */
    const fc_real kp_min_over_kappa =
        fc_div(ar, c->kp_min_per_kg, p->kappa_m_per_kg, FC_DIV_SHIFT(RATIO, GAIN, RATIO));
    k->eta1 = fc_gain_of(fc_max(fc_abs(ar, fc_sub(ar, FC_INT(1, RATIO), kp_min_over_kappa)),
                                fc_abs(ar, fc_sub(ar, FC_INT(1, RATIO), c->kp_max_over_kappa))),
                         FC_RATIO_FRAC);
    c->inv_kappa_kg = fc_div(ar, FC_INT(1, GAIN), p->kappa_m_per_kg, FC_DIV_SHIFT(GAIN, GAIN, MASS));
    c->a_m_over_kappa = fc_div(ar, p->a_m_per_s, p->kappa_m_per_kg, FC_DIV_SHIFT(GAIN, GAIN, MASS));
    k->inv_kappa = fc_gain_of(c->inv_kappa_kg, FC_MASS_FRAC);
    k->a_m_over_kappa = fc_gain_of(c->a_m_over_kappa, FC_MASS_FRAC);
    /* norm observer (4.40): pole kp_min/(kappa_m tau_av) = 1/(kappa_m m_max tau_av);
     * input w4 / tau_av, so the ZOH input gain is (1 - p) kappa_m / kp_min = (1 - p) kappa_m m_max */
    const fc_real obs_tau_s = fc_mul(ar, fc_mul(ar, p->kappa_m_per_kg, p->mass_max_kg, FC_SHIFT(GAIN, MASS, RATIO)),
                                     p->tau_av_s, FC_SHIFT(RATIO, DT, DT));
    fc_real obs_in;
    first_order_zoh(ar, p->dt_s, obs_tau_s, &c->obs_pole, &obs_in);
    k->obs_decay = fc_gain_of(obs_in, FC_UNIT_FRAC);
    c->obs_gain = fc_mul(ar, obs_in, fc_mul(ar, p->kappa_m_per_kg, p->mass_max_kg, FC_SHIFT(GAIN, MASS, RATIO)),
                         FC_SHIFT(UNIT, RATIO, RATIO));
    k->obs_input = fc_gain_of(c->obs_gain, FC_RATIO_FRAC);
    /* lead filter (4.18) */
    k->lead = fc_gain_of(FC_INT(0, UNIT), FC_UNIT_FRAC);
    k->lead_inv_tau = k->lead;
    k->lead_state = k->lead;
    if (p->tau_f_s > FC_INT(0, DT)) {
        fc_real lead_pole, lead_gain;
        first_order_zoh(ar, p->dt_s, p->tau_f_s, &lead_pole, &lead_gain);
        k->lead = fc_gain_of(lead_gain, FC_UNIT_FRAC);
        k->lead_inv_tau = fc_gain_of(fc_div(ar, FC_INT(1, DT), p->tau_f_s, FC_DIV_SHIFT(DT, DT, GAIN)), FC_GAIN_FRAC);
        k->lead_state = fc_gain_of(
            fc_sub(ar, FC_INT(1, RATIO), fc_mul(ar, p->tau_f_s, p->l0_per_s, FC_SHIFT(DT, GAIN, RATIO))), FC_RATIO_FRAC);
    }
    /* gamma dt and l0^2 from their exact products; the tunings accepted are
     * still those that hold them in RATIO and GAIN (beyond, ar saturates) */
    (void)fc_mul(ar, p->gamma, p->dt_s, FC_SHIFT(GAIN, DT, RATIO));
    (void)fc_mul(ar, p->l0_per_s, p->l0_per_s, FC_SHIFT(GAIN, GAIN, GAIN));
    k->gamma_dt = fc_gain_of_product(p->gamma, FC_GAIN_FRAC, p->dt_s, FC_DT_FRAC);
    k->l0_sq = fc_gain_of_product(p->l0_per_s, FC_GAIN_FRAC, p->l0_per_s, FC_GAIN_FRAC);
    adaptation_and_feed_forward_constants(c);
    k->l0 = fc_gain_of(p->l0_per_s, FC_GAIN_FRAC);
    k->k0 = fc_gain_of(p->k0_ns_per_m, FC_GAIN_FRAC);
    k->rho = fc_gain_of(p->rho_n, FC_FORCE_FRAC);
    k->thrust_max = fc_gain_of(p->thrust_max_n, FC_FORCE_FRAC);
    k->thrust_min = fc_gain_of(p->thrust_min_n, FC_FORCE_FRAC);
    k->inv_thrust_authority = fc_gain_of(
        fc_div(ar, FC_INT(1, PER_FORCE), p->thrust_authority_n, FC_DIV_SHIFT(PER_FORCE, FORCE, PER_FORCE)),
        FC_PER_FORCE_FRAC);
    /* the baselines */
    k->theta0 = fc_gain_of(p->theta0_kg, FC_MASS_FRAC);
    k->dt = fc_gain_of(p->dt_s, FC_DT_FRAC);
    k->inv_boundary_layer =
        fc_gain_of(fc_div(ar, FC_INT(1, VEL), p->boundary_layer_mps, FC_DIV_SHIFT(VEL, VEL, GAIN)), FC_GAIN_FRAC);
    k->stw_k1 = fc_gain_of(p->stw_k1, FC_GAIN_FRAC);
    k->pid_kp_z = fc_gain_of(p->pid_kp_z_per_s, FC_GAIN_FRAC);
    k->pid_ki_z = fc_gain_of(p->pid_ki_z_per_s2, FC_GAIN_FRAC);
    k->pid_kp_v = fc_gain_of(p->pid_kp_v_n_per_mps, FC_GAIN_FRAC);
    k->pid_ki_v = fc_gain_of(p->pid_ki_v_n_per_m, FC_GAIN_FRAC);
}

/* The kp-independent coefficients of P(x) and M(x), x = tau_f s (header,
 * NORM_OBSERVER, relative degree two), all RATIO. */
typedef struct eta_coefficients {
    fc_real c2;          /* 1 - l0 tau_f */
    fc_real l0_tav_kappa; /* l0 tau_av kappa_m: c1 = (kp - this) q */
    fc_real q;           /* tau_f / (tau_av kappa_m), kg */
    fc_real am_tf_q;     /* a_m tau_f q: c0 = kp a_m tau_f q */
    fc_real m1;          /* (1 + a_m tau_av) tau_f / tau_av */
    fc_real m0;          /* a_m tau_f^2 / tau_av */
} eta_coefficients;

/* The majorant of g (h in the time scale x) for one kp:
 * |g(theta)| <= fast_gain e^(-fast_rate theta) + slow_gain e^(-slow_rate theta), RATIO. */
typedef struct eta_majorant {
    fc_real fast_gain;
    fc_real fast_rate;
    fc_real slow_gain;
    fc_real slow_rate;
} eta_majorant;

/* Products of two RATIO values, and (a x + b) x + c in RATIO: one copy each
 * for the init-time root and residues below (flash on the ATmega). */
static __attribute__((noinline)) fc_real ratio_mul(fc_arith *ar, fc_real a, fc_real b)
{
    return fc_mul(ar, a, b, FC_SHIFT(RATIO, RATIO, RATIO));
}

static __attribute__((noinline)) fc_real ratio_quadratic(fc_arith *ar, fc_real x, fc_real a, fc_real b, fc_real c)
{
    return fc_add(ar, ratio_mul(ar, fc_add(ar, ratio_mul(ar, a, x), b), x), c);
}

/* The majorant of the header for one kp. false where the roots leave what the
 * formats hold (c1, c0 <= 3, so every root is inside [-4, 0)) or the eta-dynamics
 * are not stable: init then rejects the tuning in both backends. */
static __attribute__((noinline)) bool eta_majorant_at(fc_arith *ar, const eta_coefficients *k, fc_real kp,
                                                      eta_majorant *m)
{
    const fc_real one = FC_INT(1, RATIO);
    const fc_real tiny = FC_C(1.0e-4f, RATIO);
    const fc_real c1 = ratio_mul(ar, fc_sub(ar, kp, k->l0_tav_kappa), k->q);
    const fc_real c0 = ratio_mul(ar, kp, k->am_tf_q);
    if (!(c1 > FC_INT(0, RATIO) && c0 > FC_INT(0, RATIO) && c1 <= FC_INT(3, RATIO) && c0 <= FC_INT(3, RATIO))) {
        return false;
    }
    /* Newton from -(1 + max c_i), left of every root (Cauchy's bound): where P is
     * concave too (x < -c2/3, where the fast root of these dynamics lies) the
     * iterates rise to the leftmost root without overshoot; elsewhere they pass it
     * once and come back from the right. The residual is checked below. */
    fc_real x = fc_neg(ar, fc_add(ar, one, fc_max(k->c2, fc_max(c1, c0))));
    fc_real poly = FC_INT(0, RATIO);
    for (unsigned i = 0u; i < 40u; i++) {
        /* P(x) = ((x + c2) x + c1) x + c0, P'(x) = (3 x + 2 c2) x + c1 */
        poly = fc_add(ar, ratio_mul(ar, ratio_quadratic(ar, x, one, k->c2, c1), x), c0);
        const fc_real slope = ratio_quadratic(ar, x, FC_INT(3, RATIO), fc_add(ar, k->c2, k->c2), c1);
        if (slope < tiny) {
            return false;
        }
        x = fc_sub(ar, x, fc_div(ar, poly, slope, FC_DIV_SHIFT(RATIO, RATIO, RATIO)));
    }
    const fc_real r = x;
    /* P(x) = (x - r)(x^2 + b1 x + b0): the pair's 2 s and s^2 + w^2 */
    const fc_real b1 = fc_add(ar, k->c2, r);
    if (!(fc_abs(ar, poly) < tiny && r < FC_INT(0, RATIO) && b1 > FC_INT(0, RATIO))) {
        return false;
    }
    const fc_real b0 = fc_div(ar, c0, fc_neg(ar, r), FC_DIV_SHIFT(RATIO, RATIO, RATIO));
    /* the fast residue M(r)/P'(r), P'(r) = r^2 + b1 r + b0 */
    const fc_real m_r = ratio_quadratic(ar, r, one, k->m1, k->m0);
    const fc_real p_r = ratio_quadratic(ar, r, one, b1, b0);
    if (!(b0 > FC_INT(0, RATIO) && p_r > tiny)) {
        return false;
    }
    const fc_real rho_f = fc_div(ar, m_r, p_r, FC_DIV_SHIFT(RATIO, RATIO, RATIO));
    /* the pair's part of g: value A = 1 - rho_f and slope m1 - c2 - rho_f r at 0
     * (g(0) = 1, g'(0) = m1 - c2 from M/P = 1/x + (m1 - c2)/x^2 + ...) */
    const fc_real value = fc_sub(ar, one, rho_f);
    const fc_real decay = ratio_mul(ar, b1, FC_C(0.5f, RATIO)); /* s */
    const fc_real decay_sq = ratio_mul(ar, decay, decay);
    const fc_real disc = fc_sub(ar, b0, decay_sq); /* w^2, or -nu^2 when overdamped */
    const fc_real slope0 = fc_sub(ar, fc_sub(ar, k->m1, k->c2), ratio_mul(ar, rho_f, r));
    const fc_real c_term = fc_add(ar, slope0, ratio_mul(ar, decay, value));
    m->fast_gain = fc_abs(ar, rho_f);
    m->fast_rate = fc_neg(ar, r);
    if (ratio_mul(ar, FC_INT(4, RATIO), disc) >= decay_sq) {
        /* w >= s/2: e^(-s t)(A cos wt + B sin wt), B = C/w, amplitude sqrt(A^2 + B^2) */
        const fc_real w = fc_sqrt(ar, disc, FC_RATIO_FRAC);
        const fc_real b = fc_div(ar, c_term, w, FC_DIV_SHIFT(RATIO, RATIO, RATIO));
        m->slow_gain = fc_hypot3(ar, value, b, FC_INT(0, RATIO));
        m->slow_rate = decay;
    } else {
        /* |part| <= e^(-s' t)(|A| + |C| t) <= (|A| + 2 |C|/(e s')) e^(-s' t/2),
         * s' = s - nu the slower real part (nu = 0 for a complex pair) */
        const fc_real nu = fc_sqrt(ar, fc_neg(ar, fc_min(disc, FC_INT(0, RATIO))), FC_RATIO_FRAC);
        const fc_real slower = fc_sub(ar, decay, nu);
        if (!(slower > tiny)) {
            return false;
        }
        m->slow_gain = fc_add(ar, fc_abs(ar, value),
                              fc_div(ar, ratio_mul(ar, FC_C(0.7357589f, RATIO), fc_abs(ar, c_term)), slower,
                                     FC_DIV_SHIFT(RATIO, RATIO, RATIO)));
        m->slow_rate = ratio_mul(ar, slower, FC_C(0.5f, RATIO));
    }
    return true;
}

/* The eta norm observer's constants (header, NORM_OBSERVER, relative degree two):
 * the grid kp_j over [kp_min, kp_max], and for each cell the larger gains and the
 * smaller rates of the majorants at its ends, c = gain/(tau_f kappa_m) and
 * l = rate/tau_f, with the ZOH of w' = -l w + v. false: the tuning is rejected. */
static __attribute__((noinline)) bool eta_observer_constants(fc_altitude_control *c)
{
    fc_arith *ar = &c->ar;
    const fc_altitude_control_params *p = &c->p;
    eta_coefficients k;
    const fc_real tav_kappa = fc_mul(ar, p->tau_av_s, p->kappa_m_per_kg, FC_SHIFT(DT, GAIN, RATIO));
    const fc_real tf_over_tav = fc_div(ar, p->tau_f_s, p->tau_av_s, FC_DIV_SHIFT(DT, DT, RATIO));
    const fc_real am_tf = fc_mul(ar, p->a_m_per_s, p->tau_f_s, FC_SHIFT(GAIN, DT, RATIO));
    k.c2 = fc_sub(ar, FC_INT(1, RATIO), fc_mul(ar, p->tau_f_s, p->l0_per_s, FC_SHIFT(DT, GAIN, RATIO)));
    k.l0_tav_kappa = fc_mul(ar, tav_kappa, p->l0_per_s, FC_SHIFT(RATIO, GAIN, RATIO));
    k.q = fc_div(ar, p->tau_f_s, tav_kappa, FC_DIV_SHIFT(DT, RATIO, RATIO));
    k.am_tf_q = ratio_mul(ar, am_tf, k.q);
    k.m1 = ratio_mul(ar, fc_add(ar, FC_INT(1, RATIO), fc_mul(ar, p->a_m_per_s, p->tau_av_s, FC_SHIFT(GAIN, DT, RATIO))),
                     tf_over_tav);
    k.m0 = ratio_mul(ar, am_tf, tf_over_tav);
    /* h(t) = g(t/tau_f) / (tau_f kappa_m) */
    const fc_real h0 = fc_div(ar, FC_INT(1, GAIN), fc_mul(ar, p->tau_f_s, p->kappa_m_per_kg, FC_SHIFT(DT, GAIN, RATIO)),
                              FC_DIV_SHIFT(GAIN, RATIO, GAIN));
    const fc_real kp_step =
        ratio_mul(ar, fc_sub(ar, c->kp_max_per_kg, c->kp_min_per_kg), FC_C(1.0f / (float)FC_ALT_ETA_CELLS, RATIO));
    eta_majorant previous = {0};
    for (unsigned j = 0u; j <= FC_ALT_ETA_CELLS; j++) {
        const fc_real kp = j == FC_ALT_ETA_CELLS
                               ? c->kp_max_per_kg
                               : fc_add(ar, c->kp_min_per_kg, ratio_mul(ar, FC_INT((int32_t)j, RATIO), kp_step));
        eta_majorant m;
        if (!eta_majorant_at(ar, &k, kp, &m)) {
            return false;
        }
        c->eta_kp_per_kg[j] = kp;
        if (j > 0u) {
            const unsigned cell = j - 1u;
            const int rate_shift = FC_DIV_SHIFT(RATIO, DT, GAIN);
            const int gain_shift = FC_SHIFT(RATIO, GAIN, GAIN);
            const fc_real fast_rate = fc_div(ar, fc_min(m.fast_rate, previous.fast_rate), p->tau_f_s, rate_shift);
            const fc_real slow_rate = fc_div(ar, fc_min(m.slow_rate, previous.slow_rate), p->tau_f_s, rate_shift);
            c->eta_fast_gain_kg_per_s[cell] = fc_mul(ar, fc_max(m.fast_gain, previous.fast_gain), h0, gain_shift);
            c->eta_slow_gain_kg_per_s[cell] = fc_mul(ar, fc_max(m.slow_gain, previous.slow_gain), h0, gain_shift);
            fc_real fast_in, slow_in;
            eta_observer_zoh(ar, fast_rate, p->dt_s, &c->eta_fast_pole[cell], &fast_in);
            eta_observer_zoh(ar, slow_rate, p->dt_s, &c->eta_slow_pole[cell], &slow_in);
            fc_altitude_gains *g = &c->k;
            g->eta_fast[cell] = fc_gain_of(c->eta_fast_gain_kg_per_s[cell], FC_GAIN_FRAC);
            g->eta_slow[cell] = fc_gain_of(c->eta_slow_gain_kg_per_s[cell], FC_GAIN_FRAC);
            g->eta_fast_decay[cell] = fc_gain_of(fc_sub(ar, FC_INT(1, UNIT), c->eta_fast_pole[cell]), FC_UNIT_FRAC);
            g->eta_slow_decay[cell] = fc_gain_of(fc_sub(ar, FC_INT(1, UNIT), c->eta_slow_pole[cell]), FC_UNIT_FRAC);
            g->eta_fast_input[cell] = fc_gain_of(fast_in, FC_DT_FRAC);
            g->eta_slow_input[cell] = fc_gain_of(slow_in, FC_DT_FRAC);
        }
        c->k.eta_kp[j] = fc_gain_of(kp, FC_RATIO_FRAC);
        previous = m;
    }
    return true;
}

/* The constants the modulation rho is built from (kp_max = k_g_max/m_min,
 * kp_max/kappa_m, 1/kappa_m, a_m/kappa_m, the norm observer's input gain)
 * must fit their fixed formats (RATIO, MASS +-128, GAIN +-32768), with a margin
 * below the saturated value. In fixed a larger one has saturated (and init
 * fails on ar.saturated); in float nothing saturates, and a tiny but positive
 * m_min (a denormal) gave kp_max = inf and rho = inf * 0 = NaN on the first step
 * (fuzz finding params-4). Checked in both backends so they accept the same
 * tunings, and with these bounds no float intermediate of rho can overflow. */
static bool derived_in_range(const fc_altitude_control *c)
{
    const fc_real ratio_max = FC_INT(100, RATIO);
    const fc_real mass_max = FC_INT(100, MASS);
    return fc_within(c->kp_max_per_kg, ratio_max) && fc_within(c->kp_max_over_kappa, ratio_max) &&
           fc_within(c->obs_gain, ratio_max) && fc_within(c->inv_kappa_kg, mass_max) &&
           fc_within(c->a_m_over_kappa, mass_max);
}

void fc_altitude_control_reset(fc_altitude_control *c)
{
    c->u0_av_n = FC_INT(0, FORCE);
    c->sigma_bar_mps = FC_INT(0, VEL);
    c->omega5_n = FC_INT(0, FORCE);
    c->last_omega4_n = FC_INT(0, FORCE);
    for (unsigned j = 0u; j < FC_ALT_ETA_CELLS; j++) {
        c->omega_eta_fast_mps[j] = FC_INT(0, VEL);
        c->omega_eta_slow_mps[j] = FC_INT(0, VEL);
    }
    for (unsigned j = 0u; j <= FC_ALT_ETA_CELLS; j++) {
        c->eta_last_kp_d_mps2[j] = FC_INT(0, ACCEL);
    }
    c->eta_primed = false;
    c->lead_state_m = FC_INT(0, LENGTH);
    c->theta_kg = c->p.theta0_kg;
    c->sigma_phi_lp = FC_INT(0, SIGMA_PHI);
    c->u0_n = FC_INT(0, FORCE);
    c->stw_v_n = FC_INT(0, FORCE);
    c->pid_int_z_m = FC_INT(0, LENGTH);
    c->pid_int_v_m = FC_INT(0, LENGTH);
    c->last_error_m = FC_INT(0, LENGTH);
    c->last_thrust_n = c->p.thrust_min_n;
    c->lead_primed = false;
}

fc_init_result fc_altitude_control_init(fc_altitude_control *c, const fc_altitude_control_params *p)
{
    c->ready = false;
    c->hold = false;
    c->ar.saturated = 0u;
    c->p = *p;
    c->k.inv_thrust_authority = fc_gain_of(FC_INT(0, PER_FORCE), FC_PER_FORCE_FRAC);
    if (!altitude_params_valid(p)) {
        c->p.thrust_min_n = FC_INT(0, FORCE);
        c->p.theta0_kg = FC_INT(0, MASS);
        fc_altitude_control_reset(c);
        return FC_INIT_BAD_PARAM;
    }
    lag_schedule(c);
    compute_discretisation(c);
    fc_altitude_control_reset(c);
    /* the eta norm observer's constants, only where it runs (SSC, relative degree
     * two, NORM_OBSERVER): another law does not depend on its ranges */
    bool eta_ok = true;
    for (unsigned j = 0u; j < FC_ALT_ETA_CELLS; j++) {
        c->eta_fast_gain_kg_per_s[j] = FC_INT(0, GAIN);
        c->eta_slow_gain_kg_per_s[j] = FC_INT(0, GAIN);
        c->eta_fast_pole[j] = FC_INT(0, UNIT);
        c->eta_slow_pole[j] = FC_INT(0, UNIT);
        c->k.eta_fast[j] = fc_gain_of(FC_INT(0, GAIN), FC_GAIN_FRAC);
        c->k.eta_slow[j] = c->k.eta_fast[j];
        c->k.eta_fast_decay[j] = c->k.eta_fast[j];
        c->k.eta_slow_decay[j] = c->k.eta_fast[j];
        c->k.eta_fast_input[j] = c->k.eta_fast[j];
        c->k.eta_slow_input[j] = c->k.eta_fast[j];
    }
    for (unsigned j = 0u; j <= FC_ALT_ETA_CELLS; j++) {
        c->eta_kp_per_kg[j] = FC_INT(0, RATIO);
        c->k.eta_kp[j] = fc_gain_of(FC_INT(0, RATIO), FC_RATIO_FRAC);
    }
    if (p->law == FC_ALT_LAW_SSC && !p->velocity_measured && p->modulation == FC_SSC_MODULATION_NORM_OBSERVER) {
        eta_ok = eta_observer_constants(c);
    }
    if (c->ar.saturated != 0u || !eta_ok || !derived_in_range(c)) {
        return FC_INIT_BAD_PARAM;
    }
    c->ready = true;
    return FC_INIT_OK;
}

/* ---------------------------------------------------------------------- */
/* one step                                                                */
/* ---------------------------------------------------------------------- */

/* What the measurements say this step: e, e', sigma_hat and phi. */
typedef struct tracking_signals {
    fc_real e_m;          /* LENGTH */
    fc_real e_dot_mps;    /* VEL: measured, or estimated from the lead filter */
    fc_real sigma_mps;    /* VEL: sigma (relative degree one) or sigma_hat (two) */
    fc_real phi_mps2;     /* ACCEL: g + z_r'' - l0 e', z_r'' inside what the thrust gives */
    fc_real az_ff_mps2;   /* ACCEL: the z_r'' in phi */
} tracking_signals;

/* Relative degree two: sigma_hat from the lead filter (4.18), and e' = sigma_hat - l0 e. */
static void lead_filter(fc_altitude_control *c, fc_real l0_e, tracking_signals *t)
{
    fc_arith *ar = &c->ar;
    if (!c->lead_primed) {
        c->lead_state_m = t->e_m; /* start in steady state: sigma_hat = l0 e */
        c->lead_primed = true;
    }
    /* (4.18): sigma_hat = (e - (1 - tau_f l0) x_f) / tau_f, then advance x_f */
    const fc_real lead_in =
        fc_sub(ar, t->e_m, fc_mul_gain(ar, c->lead_state_m, c->k.lead_state, FC_GAIN_SHIFT(LENGTH, LENGTH)));
    t->sigma_mps = fc_mul_gain(ar, lead_in, c->k.lead_inv_tau, FC_GAIN_SHIFT(LENGTH, VEL));
    /* f x_f + (1 - f) e as x_f + (1 - f)(e - x_f) */
    c->lead_state_m = fc_add(ar, c->lead_state_m, fc_mul_gain(ar, fc_sub(ar, t->e_m, c->lead_state_m), c->k.lead,
                                                              FC_GAIN_SHIFT(LENGTH, LENGTH)));
    t->e_dot_mps = fc_sub(ar, t->sigma_mps, l0_e); /* e' = sigma_hat - l0 e */
}

static void tracking(fc_altitude_control *c, const fc_altitude_control_input *in, tracking_signals *t)
{
    fc_arith *ar = &c->ar;
    const fc_altitude_control_params *p = &c->p;
    const fc_real e_m = fc_sub_inline(ar, in->z_m, in->reference->z_m); /* (4.1) */
    t->e_m = e_m;
    const fc_real l0_e = fc_mul_gain(ar, e_m, c->k.l0, FC_GAIN_SHIFT(LENGTH, VEL));
    fc_real e_dot_mps;
    if (p->velocity_measured || p->law != FC_ALT_LAW_SSC) {
        e_dot_mps = fc_sub_inline(ar, in->vz_mps, in->reference->vz_mps);
        t->sigma_mps = fc_add_inline(ar, e_dot_mps, l0_e); /* (4.2) */
    } else {
        lead_filter(c, l0_e, t);
        e_dot_mps = t->e_dot_mps;
    }
    t->e_dot_mps = e_dot_mps;
    const fc_real l0_e_dot = fc_mul_gain(ar, e_dot_mps, c->k.l0, FC_GAIN_SHIFT(VEL, ACCEL));
    /* z_r'' inside what the thrust can give (the start of (3.6) asks for z_r_init/tau_zr^2) */
    const fc_real az_ff = fc_clamp(in->reference->az_mps2, c->ref_accel_min_mps2, c->ref_accel_max_mps2);
    /* g + z_r'' with no saturation test: g in (0, 100] (init) and z_r'' inside
     * [ref_accel_min, ref_accel_max], which is [-g, max(thrust_up - g, 0)] at most with
     * thrust_up <= 400 (adaptation_and_feed_forward_constants): the sum is in [0, 400],
     * inside ACCEL's 512 */
    t->phi_mps2 = fc_sub_inline(ar, p->gravity_mps2 + az_ff, l0_e_dot); /* (4.83) */
    t->az_ff_mps2 = az_ff;
}

/* max |kp u_nom - psi| over kp in [kp_min, kp_max]: the expression is linear in
 * kp, so its largest magnitude is at one end of the range. The tight form of
 * (4.42)'s kp_max |u_nom| + |psi|, which adds two terms that u_nom ~ Theta psi
 * makes cancel. */
static fc_real plant_gain_bound_mps2(fc_altitude_control *c, fc_real u_nom_n, fc_real psi_mps2)
{
    fc_arith *ar = &c->ar;
    const fc_real at_max = fc_sub(ar, fc_mul_gain(ar, u_nom_n, c->k.kp_max, FC_GAIN_SHIFT(FORCE, ACCEL)), psi_mps2);
    const fc_real at_min = fc_sub(ar, fc_mul_gain(ar, u_nom_n, c->k.kp_min, FC_GAIN_SHIFT(FORCE, ACCEL)), psi_mps2);
    return fc_max(fc_abs(ar, at_max), fc_abs(ar, at_min));
}

/* w4 of (4.42): |kp U_d + a_m sigma| / kappa_m <= (w3 + a_m |sigma|) / kappa_m,
 * w3 = max over kp of |kp u_nom - phi|, phi = g + z_r'' - l0 e' (w1 of (4.43) is |phi|),
 * with all of z_r'' (U_d of (4.17)). */
static fc_real omega4_n(fc_altitude_control *c, const fc_altitude_control_input *in, const tracking_signals *t,
                        fc_real u_nom_n)
{
    fc_arith *ar = &c->ar;
    /* the part of z_r'' not fed forward is disturbance too: phi with all of it */
    const fc_real phi_full = fc_add(ar, t->phi_mps2, fc_sub(ar, in->reference->az_mps2, t->az_ff_mps2));
    const fc_real omega3 = plant_gain_bound_mps2(c, u_nom_n, phi_full);
    const fc_real from_omega3 = fc_mul_gain(ar, omega3, c->k.inv_kappa, FC_GAIN_SHIFT(ACCEL, FORCE));
    const fc_real from_sigma =
        fc_mul_gain(ar, fc_abs(ar, t->sigma_mps), c->k.a_m_over_kappa, FC_GAIN_SHIFT(VEL, FORCE));
    return fc_add(ar, from_omega3, from_sigma);
}

/* One state of an eta norm observer, w <- e^(-l dt) w + ((1 - e^(-l dt))/l) v
 * written w - (1 - e^(-l dt)) w + ((1 - e^(-l dt))/l) v. */
static fc_real eta_advance(fc_arith *ar, fc_real w_mps, fc_gain decay, fc_gain input_s, fc_real v_mps2)
{
    return fc_add(ar, fc_sub(ar, w_mps, fc_mul_gain(ar, w_mps, decay, FC_GAIN_SHIFT(VEL, VEL))),
                  fc_mul_gain(ar, v_mps2, input_s, FC_GAIN_SHIFT(ACCEL, VEL)));
}

/* The eta norm observers (4.3.2) on the cells of the kp range (header): the bound
 * of |d_eq3| (4.81) over the step ahead, and their advance. kp_j D = kp_j u_nom - psi,
 * psi = g + z_r'' + l0^2 e (D of (4.62)). */
static fc_real eta_observer_bound_n(fc_altitude_control *c, const fc_altitude_control_input *in,
                                    const tracking_signals *t, fc_real u_nom_n)
{
    fc_arith *ar = &c->ar;
    const fc_real l0_sq_e = fc_mul_gain(ar, t->e_m, c->k.l0_sq, FC_GAIN_SHIFT(LENGTH, ACCEL));
    const fc_real psi = fc_add(ar, fc_add(ar, c->p.gravity_mps2, in->reference->az_mps2), l0_sq_e);
    fc_real size[FC_ALT_ETA_CELLS + 1];   /* ACCEL: |kp_j D| */
    fc_real change[FC_ALT_ETA_CELLS + 1]; /* ACCEL: |kp_j D[k] - kp_j D[k-1]| */
    for (unsigned j = 0u; j <= FC_ALT_ETA_CELLS; j++) {
        const fc_real kp_d =
            fc_sub(ar, fc_mul_gain(ar, u_nom_n, c->k.eta_kp[j], FC_GAIN_SHIFT(FORCE, ACCEL)), psi);
        size[j] = fc_abs(ar, kp_d);
        change[j] = c->eta_primed ? fc_abs(ar, fc_sub(ar, kp_d, c->eta_last_kp_d_mps2[j])) : FC_INT(0, ACCEL);
        c->eta_last_kp_d_mps2[j] = kp_d;
    }
    c->eta_primed = true;
    fc_real bound = FC_INT(0, FORCE);
    for (unsigned j = 0u; j < FC_ALT_ETA_CELLS; j++) {
        /* |kp D| over the cell and over the step ahead (kp D linear in kp) */
        const fc_real v = fc_add(ar, fc_max(size[j], size[j + 1u]), fc_max(change[j], change[j + 1u]));
        /* Lemma 11 on each term, ZOH with v held; w between the samples lies
         * between w[k] and w[k+1] */
        const fc_real fast = eta_advance(ar, c->omega_eta_fast_mps[j], c->k.eta_fast_decay[j],
                                         c->k.eta_fast_input[j], v);
        const fc_real slow = eta_advance(ar, c->omega_eta_slow_mps[j], c->k.eta_slow_decay[j],
                                         c->k.eta_slow_input[j], v);
        const fc_real cell = fc_add(
            ar, fc_mul_gain(ar, fc_max(fast, c->omega_eta_fast_mps[j]), c->k.eta_fast[j], FC_GAIN_SHIFT(VEL, FORCE)),
            fc_mul_gain(ar, fc_max(slow, c->omega_eta_slow_mps[j]), c->k.eta_slow[j], FC_GAIN_SHIFT(VEL, FORCE)));
        c->omega_eta_fast_mps[j] = fast;
        c->omega_eta_slow_mps[j] = slow;
        bound = fc_max(bound, cell);
    }
    return bound;
}

/* The modulation rho of the relay, and the advance of its observers. */
static fc_real modulation_n(fc_altitude_control *c, const fc_altitude_control_input *in, const tracking_signals *t,
                            fc_real u_nom_n, fc_real sigma_tilde_mps, fc_real *observer_bound)
{
    *observer_bound = FC_INT(0, FORCE);
    fc_arith *ar = &c->ar;
    const fc_altitude_control_params *p = &c->p;
    if (p->modulation == FC_SSC_MODULATION_CONSTANT) {
        return p->rho_n;
    }
    const fc_real k0_term = fc_mul_gain(ar, fc_abs(ar, sigma_tilde_mps), c->k.k0, FC_GAIN_SHIFT(VEL, FORCE));
    switch (p->modulation) {
    case FC_SSC_MODULATION_NORM_OBSERVER:
        if (p->velocity_measured) {
            /* (4.40)-(4.41) */
            const fc_real omega4 = omega4_n(c, in, t, u_nom_n);
            /* the held relay covers the step ahead: w4's change over the last step
             * bounds what the discretisation adds (header) */
            const fc_real hold_term = fc_abs(ar, fc_sub(ar, omega4, c->last_omega4_n));
            c->last_omega4_n = omega4;
            /* (4.38) with d_eq2 = -(1 - kp/kappa_m) eta1 - ...: |d_eq2| <= c_eta w5 + w4 */
            *observer_bound = fc_add(
                ar, fc_add(ar, fc_mul_gain(ar, c->omega5_n, c->k.eta1, FC_GAIN_SHIFT(FORCE, FORCE)), omega4),
                hold_term);
            const fc_real rho = fc_add(ar, *observer_bound, fc_add(ar, p->delta_n, k0_term));
            /* p w5 + obs_gain w4 as w5 - (1 - p) w5 + obs_gain w4 */
            const fc_real decay = fc_mul_gain(ar, c->omega5_n, c->k.obs_decay, FC_GAIN_SHIFT(FORCE, FORCE));
            c->omega5_n = fc_add(ar, fc_sub(ar, c->omega5_n, decay),
                                 fc_mul_gain(ar, omega4, c->k.obs_input, FC_GAIN_SHIFT(FORCE, FORCE)));
            return rho;
        }
        /* eta norm observers (4.3.2): rho = max over cells (c_f w_f + c_s w_s)
         * + delta + k0 |sigma_tilde| */
        const fc_real rho_bar = eta_observer_bound_n(c, in, t, u_nom_n);
        *observer_bound = rho_bar;
        return fc_add(ar, rho_bar, fc_add(ar, p->delta_n, k0_term));
    case FC_SSC_MODULATION_EXTRA: {
        /* (4.54): rho = c_eta |u0_av| + w4 + delta, c_eta as in (4.38) above */
        const fc_real omega4 = omega4_n(c, in, t, u_nom_n);
        *observer_bound =
            fc_add(ar, fc_mul_gain(ar, fc_abs(ar, c->u0_av_n), c->k.eta1, FC_GAIN_SHIFT(FORCE, FORCE)), omega4);
        return fc_add(ar, *observer_bound, p->delta_n);
    }
    case FC_SSC_MODULATION_CONSTANT:
    default:
        return p->rho_n;
    }
}

/* The SSC: returns the vertical force u = u_nom - u0_av and advances the
 * relay, the prediction-error loop and the averaging filter. */
static fc_real ssc_vertical_force(fc_altitude_control *c, const fc_altitude_control_input *in,
                                  const tracking_signals *t, fc_real u_nom_n, fc_altitude_control_output *out)
{
    fc_arith *ar = &c->ar;
    const fc_real sigma_tilde = fc_sub_inline(ar, t->sigma_mps, c->sigma_bar_mps); /* (4.4) */
    fc_real observer_bound;
    const fc_real rho = modulation_n(c, in, t, u_nom_n, sigma_tilde, &observer_bound);
    /* (4.8), rho sgn(sigma_tilde) as a choice of sign: the same value as the
     * product, without a multiplication */
    fc_real u0 = FC_INT(0, FORCE);
    if (sigma_tilde > FC_INT(0, VEL)) {
        u0 = rho;
    } else if (sigma_tilde < FC_INT(0, VEL)) {
        u0 = fc_neg(ar, rho);
    } else {
        /* on the surface sigma_tilde = 0: no relay action */
    }
    const fc_real u = fc_sub_inline(ar, u_nom_n, c->u0_av_n);                                           /* (4.6) */
    /* exact ZOH of (4.5) and (4.7) with u0 held over the step (see the header) */
    const fc_real relay_minus_average = fc_sub_inline(ar, u0, c->u0_av_n);
    /* b sigma_bar as sigma_bar - (1 - b) sigma_bar (a pole near 1: fc/scalar.h, fc_gain) */
    const fc_real decay = fc_mul_gain(ar, c->sigma_bar_mps, c->k.pred_decay, FC_GAIN_SHIFT(VEL, VEL));
    c->sigma_bar_mps = fc_add_inline(ar, fc_sub_inline(ar, c->sigma_bar_mps, decay),
                              fc_mul_gain(ar, relay_minus_average, c->k.pred_input, FC_GAIN_SHIFT(FORCE, VEL)));
    /* a u0_av + (1 - a) u0 written with one product */
    c->u0_av_n = fc_add_inline(ar, c->u0_av_n, fc_mul_gain(ar, relay_minus_average, c->k.avg, FC_GAIN_SHIFT(FORCE, FORCE)));
    c->u0_n = u0;
    out->sigma_tilde_mps = sigma_tilde;
    out->rho_n = rho;
    out->observer_bound_n = observer_bound;
    return u;
}

/* The baselines below are out of line (noinline): inlined, the SSC's step on the
 * ATmega carried their registers and frame. */

/* Baseline: first-order sliding mode, sign or boundary-layer relay. */
static __attribute__((noinline)) fc_real smc_vertical_force(fc_altitude_control *c, const tracking_signals *t, fc_real u_nom_n)
{
    fc_arith *ar = &c->ar;
    fc_real switching; /* UNIT in [-1, 1] */
    if (c->p.law == FC_ALT_LAW_SMC_SIGN) {
        switching = fc_sign_unit(t->sigma_mps);
    } else {
        const fc_real ratio = fc_mul_gain(ar, t->sigma_mps, c->k.inv_boundary_layer, FC_GAIN_SHIFT(VEL, UNIT));
        switching = fc_clamp(ratio, FC_INT(-1, UNIT), FC_INT(1, UNIT));
    }
    return fc_sub(ar, u_nom_n, fc_mul_gain(ar, switching, c->k.rho, FC_GAIN_SHIFT(UNIT, FORCE)));
}

/* Baseline: super-twisting. v is integrated only while the thrust is free. */
static __attribute__((noinline)) fc_real super_twisting_vertical_force(fc_altitude_control *c, const tracking_signals *t, fc_real u_nom_n,
                                             bool integrate)
{
    fc_arith *ar = &c->ar;
    const fc_real sqrt_abs_sigma = fc_sqrt(ar, fc_abs(ar, t->sigma_mps), FC_VEL_FRAC);
    const fc_real sign = fc_sign_unit(t->sigma_mps);
    const fc_real proportional = fc_mul(ar, fc_mul_gain(ar, sqrt_abs_sigma, c->k.stw_k1, FC_GAIN_SHIFT(VEL, FORCE)),
                                        sign, FC_SHIFT(FORCE, UNIT, FORCE));
    const fc_real u = fc_add(ar, fc_sub(ar, u_nom_n, proportional), c->stw_v_n);
    if (integrate) {
        const fc_real step_n = fc_mul_gain(ar, c->p.stw_k2_nps, c->k.dt, FC_GAIN_SHIFT(GAIN, FORCE));
        c->stw_v_n = fc_sub(ar, c->stw_v_n, fc_mul(ar, step_n, sign, FC_SHIFT(FORCE, UNIT, FORCE)));
    }
    return u;
}

/* Baseline: the Crazyflie's cascade, position PID -> velocity PID. */
static __attribute__((noinline)) fc_real pid_vertical_force(fc_altitude_control *c, const fc_altitude_control_input *in,
                                  const tracking_signals *t, bool integrate)
{
    fc_arith *ar = &c->ar;
    const fc_altitude_control_params *p = &c->p;
    /* position loop: velocity setpoint = z_r' - kp_z e - ki_z int e */
    const fc_altitude_gains *k = &c->k;
    const fc_real position_term = fc_add(ar, fc_mul_gain(ar, t->e_m, k->pid_kp_z, FC_GAIN_SHIFT(LENGTH, VEL)),
                                         fc_mul_gain(ar, c->pid_int_z_m, k->pid_ki_z, FC_GAIN_SHIFT(LENGTH, VEL)));
    const fc_real velocity_setpoint =
        fc_clamp(fc_sub(ar, in->reference->vz_mps, position_term), fc_neg(ar, p->pid_vel_limit_mps), p->pid_vel_limit_mps);
    const fc_real velocity_error = fc_sub(ar, in->vz_mps, velocity_setpoint);
    /* velocity loop: u = Theta0 (g + z_r'') - kp_v ev - ki_v int ev */
    const fc_real feed_forward =
        fc_mul_gain(ar, fc_add(ar, p->gravity_mps2, in->reference->az_mps2), k->theta0, FC_GAIN_SHIFT(ACCEL, FORCE));
    const fc_real velocity_term =
        fc_add(ar, fc_mul_gain(ar, velocity_error, k->pid_kp_v, FC_GAIN_SHIFT(VEL, FORCE)),
               fc_mul_gain(ar, c->pid_int_v_m, k->pid_ki_v, FC_GAIN_SHIFT(LENGTH, FORCE)));
    if (integrate) {
        c->pid_int_z_m = fc_add(ar, c->pid_int_z_m, fc_mul_gain(ar, t->e_m, k->dt, FC_GAIN_SHIFT(LENGTH, LENGTH)));
        c->pid_int_v_m =
            fc_add(ar, c->pid_int_v_m, fc_mul_gain(ar, velocity_error, k->dt, FC_GAIN_SHIFT(VEL, LENGTH)));
    }
    return fc_sub(ar, feed_forward, velocity_term);
}

/* The Theta of this step's u_nom (see the header, "Adaptation in discrete time"):
 * Theta_I advanced first by (4.83), Theta_I <- Theta_I - gamma dt sigma phi, with
 * sigma phi bounded (header, "Bounded learning rate"), projected onto
 * [Theta_min, Theta_max] and frozen unless learn; then
 * Theta = Theta_I - gamma_p [sigma phi]_lp, projected too, the low-pass fed 0
 * while held. */
static fc_real adapted_theta_kg(fc_altitude_control *c, const tracking_signals *t, bool learn)
{
    fc_arith *ar = &c->ar;
    /* inline products (fc/scalar.h, fc_mul_inline): here and u_nom's, every step */
    const fc_real sigma_phi = fc_mul_inline(ar, t->sigma_mps, t->phi_mps2, FC_SHIFT(VEL, ACCEL, SIGMA_PHI));
    if (learn) {
        const fc_real learnt = fc_clamp(sigma_phi, FC_C(-FC_ALT_THETA_LEARN_SIGMA_PHI, SIGMA_PHI),
                                        FC_C(FC_ALT_THETA_LEARN_SIGMA_PHI, SIGMA_PHI));
        const fc_real step_kg = fc_mul_gain(ar, learnt, c->k.gamma_dt, FC_GAIN_SHIFT(SIGMA_PHI, MASS));
        c->theta_kg = fc_clamp(fc_sub_inline(ar, c->theta_kg, step_kg), c->theta_min_kg, c->theta_max_kg);
    }
    /* the proportional part from sigma phi low-passed over tau_p (ZOH, one product:
     * s <- s + (1 - f)(sigma phi - s)): one glitched sample moves it by (1 - f) of its jump;
     * while held it fades out over tau_p */
    const fc_real lp_input = c->hold ? FC_INT(0, SIGMA_PHI) : sigma_phi;
    c->sigma_phi_lp = fc_add_inline(ar, c->sigma_phi_lp, fc_mul_gain(ar, fc_sub_inline(ar, lp_input, c->sigma_phi_lp),
                                                            c->k.damping_lp, FC_GAIN_SHIFT(SIGMA_PHI, SIGMA_PHI)));
    /* bounded so that the product stays inside MASS: beyond (Theta_max - Theta_min) / gamma_p
     * the projection below clips it anyway */
    const fc_real sigma_phi_bounded = fc_clamp(c->sigma_phi_lp, -c->sigma_phi_max, c->sigma_phi_max); /* >= 0 */
    const fc_real damping_kg = fc_mul_gain(ar, sigma_phi_bounded, c->k.gamma_p, FC_GAIN_SHIFT(SIGMA_PHI, MASS));
    return fc_clamp(fc_sub_inline(ar, c->theta_kg, damping_kg), c->theta_min_kg, c->theta_max_kg);
}

/* A body thrust in N as the normalised thrust the allocation takes. Inlined:
 * a call on the ATmega saves and restores more registers than it computes. */
static inline __attribute__((always_inline)) fc_real16 thrust_fraction(const fc_altitude_control *c,
                                                                       fc_real thrust_n)
{
    fc_arith ar = {0u};
    const fc_real share = fc_mul_gain(&ar, thrust_n, c->k.inv_thrust_authority, FC_GAIN_SHIFT(FORCE, RATIO));
    /* clamped into NORM16's range: no saturation test */
    return fc_round16(fc_clamp(share, FC_C(-1.99f, RATIO), FC_C(1.99f, RATIO)), FC_RATIO_FRAC, FC_NORM16_FRAC);
}

static void safe_output(const fc_altitude_control *c, fc_altitude_control_output *out)
{
    out->thrust_n = c->p.thrust_min_n;
    out->thrust = thrust_fraction(c, out->thrust_n);
    out->vertical_force_n = c->p.thrust_min_n;
    out->error_m = FC_INT(0, LENGTH);
    out->sigma_mps = FC_INT(0, VEL);
    out->sigma_tilde_mps = FC_INT(0, VEL);
    out->rho_n = FC_INT(0, FORCE);
    out->u0_av_n = FC_INT(0, FORCE);
    out->u_nom_n = FC_INT(0, FORCE);
    out->theta_kg = c->theta_kg;
    out->observer_bound_n = FC_INT(0, FORCE);
    out->clamped = false;
}

static bool input_valid(const fc_altitude_control_input *in)
{
    const fc_real length = FC_C(FC_INPUT_MAX_LENGTH_M, LENGTH);
    const fc_real speed = FC_C(FC_INPUT_MAX_SPEED_MPS, VEL);
    const fc_real accel = FC_C(FC_INPUT_MAX_ACCEL_MPS2, ACCEL);
    return fc_within(in->z_m, length) && fc_within(in->vz_mps, speed) && fc_within(in->reference->z_m, length) &&
           fc_within(in->reference->vz_mps, speed) && fc_within(in->reference->az_mps2, accel) &&
           fc_within(in->tilt_cos, FC_INT(1, RATIO));
}

void fc_altitude_control_hold(fc_altitude_control *c, bool hold)
{
    c->hold = hold;
}

fc_step_status fc_altitude_control_step(fc_altitude_control *c, const fc_altitude_control_input *in,
                                        fc_altitude_control_output *out)
{
    if (!c->ready) {
        safe_output(c, out);
        return FC_STEP_NOT_READY;
    }
    fc_arith *ar = &c->ar;
    ar->saturated = 0u;
    const fc_altitude_control_params *p = &c->p;
    if (!input_valid(in)) {
        /* hold the last thrust command: the filters and Theta are not fed garbage */
        safe_output(c, out);
        out->thrust_n = c->last_thrust_n;
        out->thrust = thrust_fraction(c, out->thrust_n);
        out->vertical_force_n = c->last_thrust_n;
        return FC_STEP_BAD_INPUT;
    }
    fc_step_status status = FC_STEP_OK;

    /* the thrust that can be delivered, as a vertical force at the current tilt */
    const fc_real tilt_cos = fc_clamp(in->tilt_cos, p->tilt_cos_min, FC_INT(1, RATIO));
    const fc_real u_max = fc_mul_gain(ar, tilt_cos, c->k.thrust_max, FC_GAIN_SHIFT(RATIO, FORCE));
    const fc_real u_min = fc_mul_gain(ar, tilt_cos, c->k.thrust_min, FC_GAIN_SHIFT(RATIO, FORCE));
    const bool was_clamped_high = c->last_thrust_n >= p->thrust_max_n ||
                                  (in->allocation_saturation & FC_SAT_THRUST_HIGH) != 0u;
    const bool was_clamped_low = c->last_thrust_n <= p->thrust_min_n ||
                                 (in->allocation_saturation & FC_SAT_THRUST_LOW) != 0u;
    /* Theta and the integrators learn only from a free thrust and inputs not held */
    const bool integrate = !was_clamped_high && !was_clamped_low && !c->hold;

    tracking_signals t;
    tracking(c, in, &t);
    fc_real theta_kg = c->theta_kg;
    if (p->law == FC_ALT_LAW_SSC && p->adaptive) {
        theta_kg = adapted_theta_kg(c, &t, integrate);
    }
    /* Theta phi (4.4), inside the vertical force the thrust can deliver: beyond it
     * z_r'' asks for an acceleration the airframe cannot make (the start of (3.6)) */
    const fc_real u_nom = fc_clamp(fc_mul_inline(ar, theta_kg, t.phi_mps2, FC_SHIFT(MASS, ACCEL, FORCE)), u_min, u_max);

    fc_real u;
    if (p->law != FC_ALT_LAW_SSC) {
        /* every field of out is written below; these three by the SSC only */
        out->sigma_tilde_mps = FC_INT(0, VEL);
        out->rho_n = FC_INT(0, FORCE);
        out->observer_bound_n = FC_INT(0, FORCE);
    }
    switch (p->law) {
    case FC_ALT_LAW_PID:
        u = pid_vertical_force(c, in, &t, integrate);
        break;
    case FC_ALT_LAW_SMC_SIGN:
    case FC_ALT_LAW_SMC_BOUNDARY:
        u = smc_vertical_force(c, &t, u_nom);
        break;
    case FC_ALT_LAW_SUPER_TWISTING:
        u = super_twisting_vertical_force(c, &t, u_nom, integrate);
        break;
    case FC_ALT_LAW_SSC:
    default: {
        u = ssc_vertical_force(c, in, &t, u_nom, out);
        /* anti-windup: the averaging filter's state stays inside the band the
         * actuator can deliver next step, u_nom - u0_av in [u_min, u_max], and
         * inside what (4.7) makes of a relay of amplitude rho, |u0_av| <= rho
         * (the two overlap: u_nom is in [u_min, u_max]). No saturation test:
         * u_nom - u_max is in [u_min - u_max, 0] and u_nom - u_min in
         * [0, u_max - u_min], with 0 <= u_min <= u_max <= thrust_max <= 2000 N
         * (init) inside FORCE's 2048; rho >= 0, so -rho is a value */
        const fc_real band_low = fc_max(u_nom - u_max, -out->rho_n);
        const fc_real band_high = fc_min(u_nom - u_min, out->rho_n);
        c->u0_av_n = fc_clamp(c->u0_av_n, band_low, band_high);
        break;
    }
    }
    /* tilt compensation: F = u / k_h, then the actuator's range. At a limit
     * counts as clamped: the anti-windup holds u0_av so that u lands exactly on
     * u_max or u_min while the loop still asks for more, and that is told on u
     * itself (F = u / k_h rounds either way of the thrust's limit) */
    const bool at_max = u >= u_max;
    const bool at_min = u <= u_min;
    const fc_real thrust_max_n = p->thrust_max_n;
    const fc_real thrust_min_n = p->thrust_min_n;
    fc_real thrust_n = fc_clamp(fc_div(ar, u, tilt_cos, FC_DIV_SHIFT(FORCE, RATIO, FORCE)), thrust_min_n, thrust_max_n);
    if (at_max) {
        thrust_n = thrust_max_n;
    } else if (at_min) {
        thrust_n = thrust_min_n;
    } else {
        /* F inside the actuator's range, or clamped onto its end */
    }
    /* clamped: at a limit of u, or F beyond the range (the clamp put it on an end) */
    const bool clamped = thrust_n >= thrust_max_n || thrust_n <= thrust_min_n;
    out->thrust_n = thrust_n;
    out->clamped = clamped;
    if (clamped) {
        status |= FC_STEP_OUTPUT_LIMITED;
    }
    out->thrust = thrust_fraction(c, thrust_n);
    c->last_thrust_n = thrust_n;
    c->last_error_m = t.e_m;

    out->vertical_force_n = u;
    out->error_m = t.e_m;
    out->sigma_mps = t.sigma_mps;
    out->u0_av_n = c->u0_av_n;
    out->u_nom_n = u_nom;
    out->theta_kg = c->theta_kg;
    if (ar->saturated != 0u) {
        status |= FC_STEP_ARITH_SATURATED;
    }
    return status;
}
