/*
 * Tests of the landing reference (3.6) and the altitude law (SSC and baselines),
 * one source for both backends.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>

#include "seed44_altitude_loop.h"

#define DT_500HZ 0.002

static fc_real dt_of(double dt) { return fc_from_float((float)dt, FC_DT_FRAC); }
static fc_real mass_of(double kg) { return fc_from_float((float)kg, FC_MASS_FRAC); }

/* A reproducible uniform number in [lo, hi] (LCG of Numerical Recipes). */
static double uniform(uint32_t *seed, double lo, double hi)
{
    *seed = *seed * 1664525u + 1013904223u;
    return lo + (hi - lo) * ((double)(*seed >> 8) / 16777216.0);
}

/* ---------------------------------------------------------------------- */
/* reference (3.6)                                                          */
/* ---------------------------------------------------------------------- */

static void test_reference_matches_3_6(void **state)
{
    (void)state;
    const double tau = 0.1, offset = 1.0, bias = 0.18;
    (void)tau;
    fc_altitude_reference ref;
    const fc_altitude_reference_params p = {dt_of(DT_500HZ), fc_from_float((float)tau, FC_TIME_FRAC),
                                            fc_from_float((float)offset, FC_LENGTH_FRAC),
                                            fc_from_float((float)bias, FC_LENGTH_FRAC)};
    assert_int_equal(fc_altitude_reference_init(&ref, &p), FC_INIT_OK);
    const double tau_q = (double)fc_to_float(p.tau_s, FC_TIME_FRAC); /* tau as the backend holds it */
    /* float: relative 1e-5 after 500 multiplications of the decay; fixed: the
     * decay per step carries ~1e-9 relative error, 500 steps ~ 1e-6 */
    double worst_z = 0.0, worst_v = 0.0, worst_a = 0.0;
    for (int k = 0; k < 500; k++) {
        const double t = k * DT_500HZ;
        const fc_vertical_trajectory pad = {fc_from_float((float)seed44_pad_z(t), FC_LENGTH_FRAC),
                                            fc_from_float((float)seed44_pad_vz(t), FC_VEL_FRAC),
                                            fc_from_float((float)seed44_pad_az(t), FC_ACCEL_FRAC)};
        fc_vertical_trajectory r;
        assert_int_equal(fc_altitude_reference_step(&ref, &pad, &r), FC_STEP_OK);
        const double decay = exp(-t / tau_q);
        const double z = seed44_pad_z(t) + bias + offset * decay;
        const double v = seed44_pad_vz(t) - offset / tau_q * decay;
        const double a = seed44_pad_az(t) + offset / (tau_q * tau_q) * decay;
        worst_z = fmax(worst_z, fabs((double)fc_to_float(r.z_m, FC_LENGTH_FRAC) - z));
        worst_v = fmax(worst_v, fabs((double)fc_to_float(r.vz_mps, FC_VEL_FRAC) - v));
        worst_a = fmax(worst_a, fabs((double)fc_to_float(r.az_mps2, FC_ACCEL_FRAC) - a));
    }
    print_message("reference (3.6): worst |dz| %.2e m, |dv| %.2e m/s, |da| %.2e m/s2\n", worst_z, worst_v, worst_a);
    /* fixed: the three terms read the decay rounded to UNIT16, off by half
     * its LSB (2^-15) at most, on top of the 32-bit error */
    const double decay_read = FC_NUMERIC_FIXED ? ldexp(1.0, -15) : 0.0;
    assert_true(worst_z < 2e-5 + offset * decay_read);
    assert_true(worst_v < 2e-4 + offset / tau_q * decay_read);
    assert_true(worst_a < 2e-3 + offset / (tau_q * tau_q) * decay_read); /* of 100 m/s2 at t = 0 */
}

static void test_reference_restart_and_bad_input(void **state)
{
    (void)state;
    fc_altitude_reference ref;
    const fc_altitude_reference_params p = {dt_of(DT_500HZ), fc_from_float(2.0f, FC_TIME_FRAC),
                                            fc_from_float(0.5f, FC_LENGTH_FRAC), FC_INT(0, LENGTH)};
    assert_int_equal(fc_altitude_reference_init(&ref, &p), FC_INIT_OK);
    const fc_vertical_trajectory still = {FC_INT(0, LENGTH), FC_INT(0, VEL), FC_INT(0, ACCEL)};
    fc_vertical_trajectory r;
    for (int k = 0; k < 1000; k++) {
        (void)fc_altitude_reference_step(&ref, &still, &r);
    }
    fc_altitude_reference_restart(&ref, fc_from_float(2.0f, FC_LENGTH_FRAC));
    assert_int_equal(fc_altitude_reference_step(&ref, &still, &r), FC_STEP_OK);
    assert_float_equal((double)fc_to_float(r.z_m, FC_LENGTH_FRAC), 2.0f, 1e-5f);
    assert_float_equal((double)fc_to_float(r.vz_mps, FC_VEL_FRAC), -1.0f, 1e-4f);
    assert_float_equal((double)fc_to_float(r.az_mps2, FC_ACCEL_FRAC), 0.5f, 1e-4f);
#if !FC_NUMERIC_FIXED
    const fc_vertical_trajectory bad = {NAN, 0.0f, 0.0f};
    assert_true((fc_altitude_reference_step(&ref, &bad, &r) & FC_STEP_BAD_INPUT) != 0u);
    assert_true(isfinite(r.z_m) && isfinite(r.vz_mps) && isfinite(r.az_mps2));
#endif
    fc_altitude_reference_params zero_tau = p;
    zero_tau.tau_s = FC_INT(0, TIME);
    assert_int_equal(fc_altitude_reference_init(&ref, &zero_tau), FC_INIT_BAD_PARAM);
    assert_int_equal(fc_altitude_reference_step(&ref, &still, &r), FC_STEP_NOT_READY);
}

/* ---------------------------------------------------------------------- */
/* blocks of the SSC against their analytic responses                      */
/* ---------------------------------------------------------------------- */

static void test_discretisation_constants(void **state)
{
    (void)state;
    fc_altitude_control c;
    fc_altitude_control_params p;
    fc_altitude_control_default_params(&p, dt_of(DT_500HZ), mass_of(4.0));
    assert_int_equal(fc_altitude_control_init(&c, &p), FC_INIT_OK);
    const double dt = (double)fc_to_float(p.dt_s, FC_DT_FRAC);
    const double a = exp(-dt / 0.1), b = exp(-5.0 * dt), cc = (a - b) / (5.0 - 10.0);
    /* ZOH constants of (4.5) and (4.7): to float precision, or ~1e-8 in fixed */
    assert_float_equal((double)fc_to_float(c.avg_pole, FC_UNIT_FRAC), (float)a, 2e-7f);
    assert_float_equal((double)fc_to_float(c.pred_pole, FC_UNIT_FRAC), (float)b, 2e-7f);
    assert_float_equal((double)fc_to_float(c.pred_gain, FC_RATIO_FRAC), (float)(1.0 * cc), 2e-7f);
    /* norm observer (4.40): pole kp_min/(kappa_m tau_av), kp_min = 1/m_max = 1/5 kg */
    assert_float_equal((double)fc_to_float(c.obs_pole, FC_UNIT_FRAC), (float)exp(-dt * 0.2 / 0.1), 2e-7f);
    /* Theta bounds (4.15): [m_min / k_g_max, m_max] = [3/1.1, 5] */
    assert_float_equal((double)fc_to_float(c.theta_min_kg, FC_MASS_FRAC), 3.0f / 1.1f, 1e-5f);
    assert_float_equal((double)fc_to_float(c.theta_max_kg, FC_MASS_FRAC), 5.0f, 1e-5f);
}

/* With sigma far above any sigma_bar the relay stays at +rho: u0_av and
 * sigma_bar then follow the closed forms of (4.7) and (4.5) for a held input. */
static void test_relay_filter_and_prediction_loop_analytic(void **state)
{
    (void)state;
    fc_altitude_control c;
    fc_altitude_control_params p;
    fc_altitude_control_default_params(&p, dt_of(DT_500HZ), mass_of(4.0));
    p.thrust_max_n = fc_from_float(2000.0f, FC_FORCE_FRAC); /* no clamp in this test */
    p.theta0_kg = mass_of(4.0);
    assert_int_equal(fc_altitude_control_init(&c, &p), FC_INIT_OK);
    const double rho = 50.0, tau_av = 0.1, a_m = 5.0, kappa = 1.0, dt = (double)fc_to_float(p.dt_s, FC_DT_FRAC);
    fc_vertical_trajectory zr = {0};
    fc_altitude_control_input in = {0};
    in.reference = &zr;
    in.z_m = fc_from_float(100.0f, FC_LENGTH_FRAC); /* e = 100 m: sigma = 200 m/s */
    /* u_nom = Theta0 (g + z_r'') = 439 N keeps the anti-windup band [u_nom - u_max,
     * u_nom - u_min] clear of u0_av in [0, rho] */
    zr.az_mps2 = fc_from_float(100.0f, FC_ACCEL_FRAC);
    in.tilt_cos = FC_INT(1, RATIO);
    double worst_av = 0.0, worst_bar = 0.0;
    for (int k = 0; k < 300; k++) {
        fc_altitude_control_output out;
        (void)fc_altitude_control_step(&c, &in, &out);
        const double t = (k + 1) * dt; /* states after k + 1 updates */
        const double u0_av = rho * (1.0 - exp(-t / tau_av));
        const double sigma_bar = kappa * rho * (exp(-t / tau_av) - exp(-a_m * t)) / (a_m - 1.0 / tau_av);
        worst_av = fmax(worst_av, fabs((double)fc_to_float(c.u0_av_n, FC_FORCE_FRAC) - u0_av));
        worst_bar = fmax(worst_bar, fabs((double)fc_to_float(c.sigma_bar_mps, FC_VEL_FRAC) - sigma_bar));
        assert_true(out.sigma_tilde_mps > FC_INT(0, VEL));
    }
    print_message("held relay: worst |u0_av - closed form| %.2e N, |sigma_bar - closed form| %.2e m/s\n",
                  worst_av, worst_bar);
    /* exact ZOH: the only errors are rounding (float ~1e-5 N after 300 steps),
     * and in fixed the coefficients' own: each a gain of 15 bits (fc/scalar.h,
     * fc_gain), within eps = 2^-15 of itself relatively. u0_av = rho (1 - (1 - g)^k)
     * moves by rho k g (1 - g)^(k-1) eps <= rho eps / e; sigma_bar by at most its
     * peak (2.5 m/s) times eps for its pole's and its input's coefficient each,
     * and by kappa_m / a_m times u0_av's error through its input */
#if FC_NUMERIC_FIXED
    const double eps = ldexp(1.0, -15), av_bound = rho * eps / exp(1.0);
    assert_true(worst_av < av_bound + 1e-4);
    assert_true(worst_bar < 2.0 * 2.5 * eps + kappa / a_m * av_bound + 1e-5);
#else
    assert_true(worst_av < 1e-4);
    assert_true(worst_bar < 1e-5);
#endif
}

static void test_lead_filter_realisation(void **state)
{
    (void)state;
    /* (4.18) with e = ramp v t: sigma_hat -> v + l0 e - l0 tau_f v ... exactly,
     * sigma_hat(t) = l0 v t + v (1 - tau_f l0)(1 - e^(-t/tau_f)) for x_f(0) = e(0) = 0 */
    fc_altitude_control c;
    fc_altitude_control_params p;
    fc_altitude_control_variant_params(&p, FC_ALT_VARIANT_SSC_REL2, dt_of(0.001), mass_of(4.0));
    assert_int_equal(fc_altitude_control_init(&c, &p), FC_INIT_OK);
    const double v = 0.5, l0 = 2.0, tau_f = 0.01, dt = (double)fc_to_float(p.dt_s, FC_DT_FRAC);
    double worst = 0.0;
    for (int k = 0; k < 200; k++) {
        const double t = k * dt;
        fc_vertical_trajectory zr = {0};
        fc_altitude_control_input in = {0};
        in.reference = &zr;
        in.z_m = fc_from_float((float)(v * t), FC_LENGTH_FRAC);
        in.tilt_cos = FC_INT(1, RATIO);
        fc_altitude_control_output out;
        (void)fc_altitude_control_step(&c, &in, &out);
        /* the filter sees the ramp sampled and held: compare after the first
         * tau_f, where the ZOH lag of half a step (v dt / 2 in e) is the difference */
        const double expected = l0 * v * t + v * (1.0 - tau_f * l0) * (1.0 - exp(-t / tau_f));
        if (t > 5.0 * tau_f) {
            worst = fmax(worst, fabs((double)fc_to_float(out.sigma_mps, FC_VEL_FRAC) - expected));
        }
    }
    print_message("lead filter (4.18) on a ramp: worst |sigma_hat - analytic| %.2e m/s\n", worst);
    /* the sampled realisation lags the continuous one by half a step: v dt / (2 tau_f) */
    assert_true(worst < v * dt / (2.0 * tau_f) * 1.1 + 1e-4);
}

/* ---------------------------------------------------------------------- */
/* norm observers upper-bound what they observe (property tests)            */
/* ---------------------------------------------------------------------- */

/* Random but smooth signal: a sum of two sinusoids of random amplitude and rate. */
typedef struct random_wave { double a1, w1, p1, a2, w2, p2, mean; } random_wave;
static random_wave make_wave(uint32_t *seed, double mean, double amplitude)
{
    random_wave r = {uniform(seed, 0, amplitude), uniform(seed, 0.2, 8.0), uniform(seed, 0, 6.28),
                     uniform(seed, 0, amplitude / 3), uniform(seed, 5.0, 40.0), uniform(seed, 0, 6.28), mean};
    return r;
}
static double wave_at(const random_wave *r, double t)
{
    return r->mean + r->a1 * sin(r->w1 * t + r->p1) + r->a2 * sin(r->w2 * t + r->p2);
}

/* Relative degree one: eta1 of (4.36) driven by the controller's own signals and
 * a time-varying kp inside its bounds; (4.38) in its tight form,
 * |d_eq2| <= c_eta w5 + w4 + |w4 - w4 of the last step|. */
static void test_norm_observer_bounds_d_eq2(void **state)
{
    (void)state;
    uint32_t seed = 12345u;
    double worst_ratio = 0.0;
    for (int run = 0; run < 20; run++) {
        fc_altitude_control c;
        fc_altitude_control_params p;
        fc_altitude_control_variant_params(&p, FC_ALT_VARIANT_SSC_NORM, dt_of(DT_500HZ), mass_of(4.0));
        p.thrust_max_n = fc_from_float(2000.0f, FC_FORCE_FRAC);
        assert_int_equal(fc_altitude_control_init(&c, &p), FC_INIT_OK);
        const double kappa = 1.0, a_m = 5.0, tau_av = 0.1, l0 = 2.0, g = 9.81;
        const double kp_min = 1.0 / 5.0, kp_max = 1.1 / 3.0;
        const random_wave kp_wave = make_wave(&seed, (kp_min + kp_max) / 2, (kp_max - kp_min) / 2.6);
        const random_wave z_wave = make_wave(&seed, 0.0, 0.5), zr_wave = make_wave(&seed, 0.0, 0.5);
        double eta1 = 0.0;
        const int substeps = 20;
        const double h = DT_500HZ / substeps;
        for (int k = 0; k < 2000; k++) {
            const double t = k * DT_500HZ, dt = 1e-4;
            fc_vertical_trajectory zr = {0};
            fc_altitude_control_input in = {0};
            in.reference = &zr;
            in.z_m = fc_from_float((float)wave_at(&z_wave, t), FC_LENGTH_FRAC);
            in.vz_mps = fc_from_float((float)((wave_at(&z_wave, t + dt) - wave_at(&z_wave, t - dt)) / (2 * dt)), FC_VEL_FRAC);
            zr.z_m = fc_from_float((float)wave_at(&zr_wave, t), FC_LENGTH_FRAC);
            zr.vz_mps = fc_from_float((float)((wave_at(&zr_wave, t + dt) - wave_at(&zr_wave, t - dt)) / (2 * dt)), FC_VEL_FRAC);
            zr.az_mps2 = fc_from_float((float)((wave_at(&zr_wave, t + dt) - 2 * wave_at(&zr_wave, t) + wave_at(&zr_wave, t - dt)) / (dt * dt)), FC_ACCEL_FRAC);
            in.tilt_cos = FC_INT(1, RATIO);
            fc_altitude_control_output out;
            (void)fc_altitude_control_step(&c, &in, &out);
            const double u_nom = (double)fc_to_float(out.u_nom_n, FC_FORCE_FRAC);
            const double sigma = (double)fc_to_float(out.sigma_mps, FC_VEL_FRAC);
            const double e_dot = (double)fc_to_float(in.vz_mps, FC_VEL_FRAC) - (double)fc_to_float(zr.vz_mps, FC_VEL_FRAC);
            const double z_r_acc = (double)fc_to_float(zr.az_mps2, FC_ACCEL_FRAC);
            /* d_eq2 (4.37) at this step, from eta1 driven by the previous steps */
            const double kp = wave_at(&kp_wave, t);
            const double u_d = u_nom + (-g - z_r_acc + l0 * e_dot) / kp;
            const double d_eq2 = -eta1 + kp / kappa * eta1 - kp / kappa * u_d - a_m / kappa * sigma;
            const double bound = (double)fc_to_float(out.observer_bound_n, FC_FORCE_FRAC);
            worst_ratio = fmax(worst_ratio, fabs(d_eq2) / bound);
            assert_true(fabs(d_eq2) <= bound * (1.0 + 1e-4) + 1e-3);
            /* advance (4.36) over the step with this step's inputs held and kp varying */
            for (int i = 0; i < substeps; i++) {
                const double kpi = wave_at(&kp_wave, t + i * h);
                const double u_di = u_nom + (-g - z_r_acc + l0 * e_dot) / kpi;
                eta1 += h / tau_av * (kpi / kappa * (-eta1 + u_di) + a_m / kappa * sigma);
            }
        }
    }
    print_message("norm observer (4.40)-(4.43): max |d_eq2| / bound over 20 random runs = %.3f\n", worst_ratio);
}

/* Relative degree two: the eta-dynamics (4.67)-(4.69) for a kp held inside its
 * bounds and a random kp D; |d_eq3| (4.81) <= c_f w_f + c_s w_s. */
static void test_eta_norm_observer_bounds_d_eq3(void **state)
{
    (void)state;
    uint32_t seed = 777u;
    double worst_ratio = 0.0;
    for (int run = 0; run < 20; run++) {
        fc_altitude_control c;
        fc_altitude_control_params p;
        fc_altitude_control_variant_params(&p, FC_ALT_VARIANT_SSC_REL2_NORM, dt_of(DT_500HZ), mass_of(4.0));
        p.thrust_max_n = fc_from_float(2000.0f, FC_FORCE_FRAC);
        assert_int_equal(fc_altitude_control_init(&c, &p), FC_INIT_OK);
        const double kappa = 0.5, a_m = 5.0, tau_av = 0.1, tau_f = 0.01, l0 = 2.0, g = 9.81;
        const double kp = uniform(&seed, 1.0 / 5.0, 1.1 / 3.0);
        const random_wave z_wave = make_wave(&seed, 0.0, 0.5), zr_wave = make_wave(&seed, 0.0, 0.5);
        double eta1 = 0.0, eta2 = 0.0, eta3 = 0.0;
        const int substeps = 40;
        const double h = DT_500HZ / substeps;
        for (int k = 0; k < 2500; k++) {
            const double t = k * DT_500HZ, dt = 1e-4;
            fc_vertical_trajectory zr = {0};
            fc_altitude_control_input in = {0};
            in.reference = &zr;
            in.z_m = fc_from_float((float)wave_at(&z_wave, t), FC_LENGTH_FRAC);
            zr.z_m = fc_from_float((float)wave_at(&zr_wave, t), FC_LENGTH_FRAC);
            zr.az_mps2 = fc_from_float((float)((wave_at(&zr_wave, t + dt) - 2 * wave_at(&zr_wave, t) + wave_at(&zr_wave, t - dt)) / (dt * dt)), FC_ACCEL_FRAC);
            in.tilt_cos = FC_INT(1, RATIO);
            fc_altitude_control_output out;
            (void)fc_altitude_control_step(&c, &in, &out);
            const double d_eq3 = eta1 + eta2 / kappa + a_m / kappa * eta3;
            const double bound = (double)fc_to_float(out.observer_bound_n, FC_FORCE_FRAC);
            worst_ratio = fmax(worst_ratio, fabs(d_eq3) / bound);
            assert_true(fabs(d_eq3) <= bound * (1.0 + 1e-3) + 1e-3);
            /* kp D = kp u_nom - g - z_r'' - l0^2 e, held over the step */
            const double e = (double)fc_to_float(out.error_m, FC_LENGTH_FRAC);
            const double kp_d = kp * (double)fc_to_float(out.u_nom_n, FC_FORCE_FRAC) - g -
                                (double)fc_to_float(zr.az_mps2, FC_ACCEL_FRAC) - l0 * l0 * e;
            for (int i = 0; i < substeps; i++) {
                const double d1 = (eta2 + a_m * eta3) / (kappa * tau_av);
                const double d2 = (-kp * eta1 + (l0 * tau_f - 1.0) * eta2 + l0 * eta3 + kp_d) / tau_f;
                const double d3 = eta2;
                eta1 += h * d1;
                eta2 += h * d2;
                eta3 += h * d3;
            }
        }
    }
    print_message("eta norm observer (4.3.2): max |d_eq3| / bound over 20 random runs = %.3f\n", worst_ratio);
}

/* The impulse response h(t) from kp D to d_eq3 of the eta-dynamics (4.67)-(4.69),
 * by RK4 from eta2(0+) = 1/tau_f; worst of |h(t)| / majorant(t) over [0, t_end]
 * and the L1 norms of both. */
typedef struct eta_tuning {
    double tau_av, tau_f, kappa, a_m, l0;
} eta_tuning;

static double eta_majorant_ratio(const eta_tuning *e, double kp, double c_f, double l_f, double c_s, double l_s,
                                 double *h_l1, double *majorant_l1)
{
    double eta[3] = {0.0, 1.0 / e->tau_f, 0.0};
    const double h = 2e-5, t_end = 12.0;
    double worst = 0.0, l1 = 0.0;
    for (int k = 0; k * h < t_end; k++) {
        const double t = k * h;
        const double out = eta[0] + eta[1] / e->kappa + e->a_m / e->kappa * eta[2];
        const double majorant = c_f * exp(-l_f * t) + c_s * exp(-l_s * t);
        worst = fmax(worst, fabs(out) / majorant);
        l1 += fabs(out) * h;
        double k_sum[3] = {0.0, 0.0, 0.0}, stage[3], d[3];
        static const double weight[4] = {1.0, 2.0, 2.0, 1.0}, at[4] = {0.0, 0.5, 0.5, 1.0};
        for (int s = 0; s < 4; s++) {
            for (int i = 0; i < 3; i++) {
                stage[i] = eta[i] + (s == 0 ? 0.0 : at[s] * h * d[i]);
            }
            d[0] = (stage[1] + e->a_m * stage[2]) / (e->kappa * e->tau_av);
            d[1] = (-kp * stage[0] + (e->l0 * e->tau_f - 1.0) * stage[1] + e->l0 * stage[2]) / e->tau_f;
            d[2] = stage[1];
            for (int i = 0; i < 3; i++) {
                k_sum[i] += weight[s] * d[i];
            }
        }
        for (int i = 0; i < 3; i++) {
            eta[i] += h / 6.0 * k_sum[i];
        }
    }
    *h_l1 = l1;
    *majorant_l1 = c_f / l_f + c_s / l_s;
    return worst;
}

/* The majorant computed at init (header, NORM_OBSERVER, relative degree two)
 * covers h(t) for every kp of a fine grid over [kp_min, kp_max], with the
 * constants of the cell that holds it, for the default tuning and another one;
 * and it is tight: its integral is within a factor 1.6 of the L1 norm of h at
 * the cell's worst end (pi/2 is what an exponential envelope of a damped
 * oscillation costs). */
static void test_eta_majorant_covers_impulse_response(void **state)
{
    (void)state;
    for (int tuning = 0; tuning < 2; tuning++) {
        fc_altitude_control c;
        fc_altitude_control_params p;
        fc_altitude_control_variant_params(&p, FC_ALT_VARIANT_SSC_REL2_NORM, dt_of(DT_500HZ), mass_of(4.0));
        eta_tuning e = {0.1, 0.01, 0.5, 5.0, 2.0};
        if (tuning == 1) {
            e.tau_f = 0.02;
            e.a_m = 8.0;
            e.kappa = 0.3;
            p.tau_f_s = fc_from_float((float)e.tau_f, FC_DT_FRAC);
            p.a_m_per_s = fc_from_float((float)e.a_m, FC_GAIN_FRAC);
            p.kappa_m_per_kg = fc_from_float((float)e.kappa, FC_GAIN_FRAC);
        }
        assert_int_equal(fc_altitude_control_init(&c, &p), FC_INIT_OK);
        const double kp_min = (double)fc_to_float(c.eta_kp_per_kg[0], FC_RATIO_FRAC);
        const double kp_max = (double)fc_to_float(c.eta_kp_per_kg[FC_ALT_ETA_CELLS], FC_RATIO_FRAC);
        assert_true(fabs(kp_min - 1.0 / 5.0) < 1e-4 && fabs(kp_max - 1.1 / 3.0) < 1e-4);
        double worst = 0.0, worst_l1_ratio = 0.0;
        const int points = 24;
        for (int i = 0; i <= points; i++) {
            const double kp = kp_min + (kp_max - kp_min) * i / points;
            int cell = 0;
            while (cell + 1 < FC_ALT_ETA_CELLS &&
                   kp > (double)fc_to_float(c.eta_kp_per_kg[cell + 1], FC_RATIO_FRAC)) {
                cell++;
            }
            const double c_f = (double)fc_to_float(c.eta_fast_gain_kg_per_s[cell], FC_GAIN_FRAC);
            const double c_s = (double)fc_to_float(c.eta_slow_gain_kg_per_s[cell], FC_GAIN_FRAC);
            const double l_f = -log((double)fc_to_float(c.eta_fast_pole[cell], FC_UNIT_FRAC)) / DT_500HZ;
            const double l_s = -log((double)fc_to_float(c.eta_slow_pole[cell], FC_UNIT_FRAC)) / DT_500HZ;
            double h_l1, majorant_l1;
            const double ratio = eta_majorant_ratio(&e, kp, c_f, l_f, c_s, l_s, &h_l1, &majorant_l1);
            worst = fmax(worst, ratio);
            const bool cell_end = fabs(kp - (double)fc_to_float(c.eta_kp_per_kg[cell], FC_RATIO_FRAC)) < 1e-6 &&
                                  (cell == 0 || i == 0);
            if (i == 0 || cell_end) {
                worst_l1_ratio = fmax(worst_l1_ratio, majorant_l1 / h_l1);
            }
        }
        print_message("tuning %d: max |h| / majorant over kp %.3f; majorant L1 / h L1 at kp_min %.3f\n", tuning,
                      worst, worst_l1_ratio);
        assert_true(worst <= 1.0 + 2e-3);
        assert_true(worst_l1_ratio <= 1.6);
    }
}

/* A tuning whose eta-dynamics leave the range the majorant is computed in
 * (c1 = (kp - l0 tau_av kappa_m) tau_f/(tau_av kappa_m) > 3) is rejected in both
 * backends, only where the eta observer runs. */
static void test_eta_majorant_range_rejected(void **state)
{
    (void)state;
    fc_altitude_control c;
    fc_altitude_control_params p;
    fc_altitude_control_variant_params(&p, FC_ALT_VARIANT_SSC_REL2_NORM, dt_of(DT_500HZ), mass_of(4.0));
    p.tau_f_s = fc_from_float(0.1f, FC_DT_FRAC);
    p.tau_av_s = fc_from_float(0.002f, FC_DT_FRAC);
    p.l0_per_s = fc_from_float(0.5f, FC_GAIN_FRAC);
    p.a_m_per_s = fc_from_float(1.0f, FC_GAIN_FRAC);
    p.kappa_m_per_kg = fc_from_float(0.5f, FC_GAIN_FRAC);
    assert_int_equal(fc_altitude_control_init(&c, &p), FC_INIT_BAD_PARAM);
    p.modulation = FC_SSC_MODULATION_CONSTANT;
    assert_int_equal(fc_altitude_control_init(&c, &p), FC_INIT_OK);
}

/* ---------------------------------------------------------------------- */
/* closed loop on the 4.4 altitude plant                                    */
/* ---------------------------------------------------------------------- */

static seed44_metrics fly(fc_altitude_variant v, double rate_hz)
{
    fc_altitude_control_params p;
    fc_altitude_control_variant_params(&p, v, dt_of(1.0 / rate_hz), mass_of(4.0));
    seed44_metrics m;
    assert_true(seed44_run(&p, rate_hz, 60.0, &m));
    return m;
}

static void test_seed44_ssc_adaptive_meets_spec(void **state)
{
    (void)state;
    const seed44_metrics m = fly(FC_ALT_VARIANT_SSC_ADAPTIVE, 500.0);
    print_message("ssc-adaptive 500 Hz: rms %.3f mm, mass step %.2f mm, tv %.0f N/s, theta %.4f (theta* %.4f)\n",
                  m.rms_error_m * 1e3, m.mass_step_peak_error_m * 1e3, m.control_tv_per_s, m.theta_end_kg,
                  m.theta_star_end_kg);
    assert_int_equal(m.nan_outputs, 0);
    /* issue 29's targets */
    assert_true(m.rms_error_m <= 0.0015);
    assert_true(m.mass_step_peak_error_m <= 0.012);
    assert_true(m.theta_rel_error <= 0.01);
}

/* The adaptive mode (sigma, Theta) of "Adaptation in discrete time" is damped at
 * both rates: Theta settles, with no limit cycle, before and after the mass step. */
static void test_adaptation_settles_at_500_and_250_hz(void **state)
{
    (void)state;
    const double rates[] = {500.0, 250.0};
    const double theta_error_max[] = {0.01, 0.02};
    for (int i = 0; i < 2; i++) {
        fc_altitude_control_params p;
        fc_altitude_control_variant_params(&p, FC_ALT_VARIANT_SSC_ADAPTIVE, dt_of(1.0 / rates[i]), mass_of(4.0));
        seed44_metrics before, after;
        assert_true(seed44_run(&p, rates[i], 30.0, &before)); /* last 10 s before the mass step */
        assert_true(seed44_run(&p, rates[i], 60.0, &after));
        print_message("%3.0f Hz: Theta swing %.5f kg (20-30 s), %.5f kg (50-60 s); theta error %.5f\n", rates[i],
                      before.theta_swing_kg, after.theta_swing_kg, after.theta_rel_error);
        assert_true(before.theta_swing_kg <= 0.005);
        assert_true(after.theta_swing_kg <= 0.005);
        assert_true(after.theta_rel_error <= theta_error_max[i]);
    }
}

/* The start of (3.6) asks for more than the thrust gives: u0_av stays inside
 * what (4.7) makes of the relay, |u0_av| <= rho; with adaptation the gear does
 * not go through the pad, without it not by more than a few centimetres (this
 * plant has no contact; sim_host's seed-4.4-contact has). */
static void test_start_respects_thrust_limits(void **state)
{
    (void)state;
    const fc_altitude_variant variants[] = {FC_ALT_VARIANT_SSC, FC_ALT_VARIANT_SSC_ADAPTIVE, FC_ALT_VARIANT_SSC_NORM};
    for (int i = 0; i < 3; i++) {
        fc_altitude_control_params p;
        fc_altitude_control_variant_params(&p, variants[i], dt_of(DT_500HZ), mass_of(4.0));
        seed44_metrics m;
        assert_true(seed44_run(&p, 500.0, 3.0, &m));
        print_message("variant %d: max |u0_av|/rho %.4f, least gear clearance %.4f m\n", (int)variants[i],
                      m.max_u0_av_over_rho, m.min_gear_clearance_m);
        assert_true(m.max_u0_av_over_rho <= 1.0 + 1e-5);
        assert_true(m.min_gear_clearance_m >= (variants[i] == FC_ALT_VARIANT_SSC_ADAPTIVE ? -0.005 : -0.1));
    }
}

/* The tight bounds of the norm observer: rho no larger than needed, so ssc-norm
 * tracks at least as well as constant rho = 50 with at most half its control
 * variation. */
static void test_norm_observer_pays(void **state)
{
    (void)state;
    const seed44_metrics constant = fly(FC_ALT_VARIANT_SSC, 500.0);
    const seed44_metrics norm = fly(FC_ALT_VARIANT_SSC_NORM, 500.0);
    print_message("constant rho: rms %.3f mm tv %.0f N/s | norm observer: rms %.3f mm tv %.0f N/s\n",
                  constant.rms_error_m * 1e3, constant.control_tv_per_s, norm.rms_error_m * 1e3,
                  norm.control_tv_per_s);
    assert_true(norm.rms_error_m <= constant.rms_error_m);
    assert_true(norm.control_tv_per_s <= 0.5 * constant.control_tv_per_s);
}

/* Issue 29's target for relative degree two: the eta norm observer's rho is no
 * larger than needed, so ssc-rel2-norm tracks within twice ssc-rel2's rms. */
static void test_rel2_norm_observer_within_twice_constant(void **state)
{
    (void)state;
    const seed44_metrics constant = fly(FC_ALT_VARIANT_SSC_REL2, 500.0);
    const seed44_metrics norm = fly(FC_ALT_VARIANT_SSC_REL2_NORM, 500.0);
    print_message("rel2 constant rho: rms %.3f mm tv %.0f N/s | eta norm observer: rms %.3f mm tv %.0f N/s\n",
                  constant.rms_error_m * 1e3, constant.control_tv_per_s, norm.rms_error_m * 1e3,
                  norm.control_tv_per_s);
    assert_int_equal(norm.nan_outputs, 0);
    assert_true(norm.rms_error_m <= 2.0 * constant.rms_error_m);
}

static void test_seed44_every_variant_flies(void **state)
{
    (void)state;
    static const char *const names[FC_ALT_VARIANT_COUNT] = {
        "ssc", "ssc-adaptive", "ssc-norm", "ssc-norm-adaptive", "ssc-extra", "ssc-rel2",
        "ssc-rel2-adaptive", "ssc-rel2-norm", "pid", "smc", "smc-boundary", "super-twisting"};
    print_message("%-18s %10s %12s %12s %8s\n", "variant (500 Hz)", "rms_mm", "step_peak_mm", "tv_N_per_s", "theta");
    for (int v = 0; v < FC_ALT_VARIANT_COUNT; v++) {
        const seed44_metrics m = fly((fc_altitude_variant)v, 500.0);
        print_message("%-18s %10.3f %12.2f %12.0f %8.4f\n", names[v], m.rms_error_m * 1e3,
                      m.mass_step_peak_error_m * 1e3, m.control_tv_per_s, m.theta_rel_error);
        assert_int_equal(m.nan_outputs, 0);
        assert_true(m.rms_error_m < 0.25); /* every variant holds the vehicle near the pad */
    }
    /* relative degree two converges with a small tau_f */
    const seed44_metrics rel2 = fly(FC_ALT_VARIANT_SSC_REL2_ADAPTIVE, 500.0);
    assert_true(rel2.rms_error_m <= 0.003);
}

static void test_quasi_sliding_band_against_rate(void **state)
{
    (void)state;
    /* the discrete relay's band ~ rho dt / tau_av: ripple grows as the rate drops */
    const double rates[] = {1000.0, 500.0, 250.0};
    double tv_constant[3];
    for (int i = 0; i < 3; i++) {
        const seed44_metrics constant = fly(FC_ALT_VARIANT_SSC_ADAPTIVE, rates[i]);
        const seed44_metrics norm = fly(FC_ALT_VARIANT_SSC_NORM_ADAPTIVE, rates[i]);
        tv_constant[i] = constant.control_tv_per_s;
        print_message("%5.0f Hz: constant rho: rms %.3f mm tv %.0f N/s | norm-observer rho: rms %.3f mm tv %.0f N/s\n",
                      rates[i], constant.rms_error_m * 1e3, constant.control_tv_per_s, norm.rms_error_m * 1e3,
                      norm.control_tv_per_s);
        assert_int_equal(constant.nan_outputs + norm.nan_outputs, 0);
    }
    /* ripple per step ~ rho dt / tau_av, steps per second 1/dt: tv ~ rho / tau_av, so
     * about constant in the rate; it must not blow up at 250 Hz */
    assert_true(tv_constant[2] < 3.0 * tv_constant[0]);
}

/* ---------------------------------------------------------------------- */
/* anti-windup, limits, bad input, bad parameters                           */
/* ---------------------------------------------------------------------- */

static void test_adaptation_frozen_while_clamped(void **state)
{
    (void)state;
    fc_altitude_control c;
    fc_altitude_control_params p;
    fc_altitude_control_variant_params(&p, FC_ALT_VARIANT_SSC_ADAPTIVE, dt_of(DT_500HZ), mass_of(4.0));
    assert_int_equal(fc_altitude_control_init(&c, &p), FC_INIT_OK);
    fc_vertical_trajectory zr = {0};
    fc_altitude_control_input in = {0};
    in.reference = &zr;
    in.z_m = fc_from_float(-50.0f, FC_LENGTH_FRAC); /* far below: full thrust */
    in.tilt_cos = FC_INT(1, RATIO);
    fc_altitude_control_output out;
    /* the relay winds u0_av down until the thrust command reaches its limit */
    int steps = 0;
    do {
        (void)fc_altitude_control_step(&c, &in, &out);
    } while (!out.clamped && ++steps < 1000);
    assert_true(out.clamped);
    (void)fc_altitude_control_step(&c, &in, &out); /* the first step that sees the clamp */
    const fc_real theta_before = c.theta_kg;
    for (int k = 0; k < 100; k++) {
        const fc_step_status s = fc_altitude_control_step(&c, &in, &out);
        assert_true((s & FC_STEP_OUTPUT_LIMITED) != 0u);
        assert_true(out.thrust_n <= p.thrust_max_n && out.thrust_n >= p.thrust_min_n);
    }
    assert_true(c.theta_kg == theta_before);
    /* the averaging filter stays inside what the clamped actuator delivers */
    assert_true((double)fc_to_float(c.u0_av_n, FC_FORCE_FRAC) >=
                (double)fc_to_float(out.u_nom_n, FC_FORCE_FRAC) - (double)fc_to_float(p.thrust_max_n, FC_FORCE_FRAC) - 1e-3);
}

static void test_tilt_compensation(void **state)
{
    (void)state;
    fc_altitude_control level, tilted;
    fc_altitude_control_params p;
    fc_altitude_control_variant_params(&p, FC_ALT_VARIANT_PID, dt_of(DT_500HZ), mass_of(4.0));
    assert_int_equal(fc_altitude_control_init(&level, &p), FC_INIT_OK);
    assert_int_equal(fc_altitude_control_init(&tilted, &p), FC_INIT_OK);
    fc_vertical_trajectory zr = {0};
    fc_altitude_control_input in = {0};
    in.reference = &zr;
    in.tilt_cos = FC_INT(1, RATIO);
    fc_altitude_control_output a, b;
    (void)fc_altitude_control_step(&level, &in, &a);
    in.tilt_cos = fc_from_float(0.8f, FC_RATIO_FRAC);
    (void)fc_altitude_control_step(&tilted, &in, &b);
    assert_float_equal((double)fc_to_float(b.thrust_n, FC_FORCE_FRAC), (double)fc_to_float(a.thrust_n, FC_FORCE_FRAC) / 0.8f, 1e-3f);
    /* beyond tilt_cos_min the compensation stops */
    in.tilt_cos = fc_from_float(0.1f, FC_RATIO_FRAC);
    (void)fc_altitude_control_step(&tilted, &in, &b);
    assert_true((double)fc_to_float(b.thrust_n, FC_FORCE_FRAC) <= (double)fc_to_float(a.thrust_n, FC_FORCE_FRAC) / 0.5 + 1e-2);
}

static void test_bad_input_holds_last_thrust(void **state)
{
    (void)state;
    fc_altitude_control c;
    fc_altitude_control_params p;
    fc_altitude_control_variant_params(&p, FC_ALT_VARIANT_SSC_ADAPTIVE, dt_of(DT_500HZ), mass_of(4.0));
    assert_int_equal(fc_altitude_control_init(&c, &p), FC_INIT_OK);
    fc_vertical_trajectory zr = {0};
    fc_altitude_control_input in = {0};
    in.reference = &zr;
    in.z_m = fc_from_float(0.5f, FC_LENGTH_FRAC);
    zr.z_m = fc_from_float(0.5f, FC_LENGTH_FRAC);
    in.tilt_cos = FC_INT(1, RATIO);
    fc_altitude_control_output good, bad;
    (void)fc_altitude_control_step(&c, &in, &good);
#if !FC_NUMERIC_FIXED
    in.z_m = NAN;
    assert_true((fc_altitude_control_step(&c, &in, &bad) & FC_STEP_BAD_INPUT) != 0u);
    assert_true(bad.thrust_n == good.thrust_n);
    in.z_m = 0.5f;
    zr.az_mps2 = INFINITY;
    assert_true((fc_altitude_control_step(&c, &in, &bad) & FC_STEP_BAD_INPUT) != 0u);
    assert_true(isfinite(bad.thrust_n));
#else
    /* fixed: any bit pattern is a number; beyond the physical input range
     * (fc/status.h) it is bad input like a NaN, and the last thrust is held */
    in.z_m = INT32_MAX;
    zr.az_mps2 = INT32_MIN;
    const fc_step_status s = fc_altitude_control_step(&c, &in, &bad);
    assert_true((s & FC_STEP_BAD_INPUT) != 0u);
    assert_true(bad.thrust_n == good.thrust_n);
    assert_true(bad.thrust_n >= p.thrust_min_n && bad.thrust_n <= p.thrust_max_n);
#endif
}

static void test_bad_params_rejected(void **state)
{
    (void)state;
    fc_altitude_control c;
    fc_altitude_control_params p;
    fc_altitude_control_default_params(&p, dt_of(DT_500HZ), mass_of(4.0));
    fc_altitude_control_params q = p;
    q.dt_s = FC_INT(0, DT);
    assert_int_equal(fc_altitude_control_init(&c, &q), FC_INIT_BAD_PARAM);
    fc_altitude_control_output out;
    fc_vertical_trajectory zr = {0};
    fc_altitude_control_input in = {0};
    in.reference = &zr;
    assert_int_equal(fc_altitude_control_step(&c, &in, &out), FC_STEP_NOT_READY);
    assert_true(out.thrust_n == FC_INT(0, FORCE));
    q = p;
    q.thrust_max_n = q.thrust_min_n;
    assert_int_equal(fc_altitude_control_init(&c, &q), FC_INIT_BAD_PARAM);
    q = p;
    q.mass_min_kg = mass_of(4.5); /* above Theta0 */
    assert_int_equal(fc_altitude_control_init(&c, &q), FC_INIT_BAD_PARAM);
    q = p;
    q.law = FC_ALT_LAW_COUNT;
    assert_int_equal(fc_altitude_control_init(&c, &q), FC_INIT_BAD_PARAM);
    /* relative degree two with kappa_m = 1 and m_max = 5 kg breaks Remark 9 */
    q = p;
    q.velocity_measured = false;
    assert_int_equal(fc_altitude_control_init(&c, &q), FC_INIT_BAD_PARAM);
    q.kappa_m_per_kg = fc_from_float(0.5f, FC_GAIN_FRAC);
    assert_int_equal(fc_altitude_control_init(&c, &q), FC_INIT_OK);
#if !FC_NUMERIC_FIXED
    q = p;
    q.gamma = NAN;
    assert_int_equal(fc_altitude_control_init(&c, &q), FC_INIT_BAD_PARAM);
#endif
}

/* The lag schedule (fc/altitude_control.h, "Lag schedule"): L = 0 leaves gamma
 * and gamma_p as they are; L > 0 divides gamma by d = 1 + g sqrt(gamma/Theta0) L
 * and gamma_p by d^(3/2); L outside [0, 1] s is rejected. */
static void test_lag_schedule(void **state)
{
    (void)state;
    fc_arith ar = {0u};
    fc_altitude_control c;
    fc_altitude_control_params p;
    fc_altitude_control_default_params(&p, dt_of(DT_500HZ), mass_of(4.0));
    p.adaptive = true;
    assert_int_equal(fc_altitude_control_init(&c, &p), FC_INIT_OK);
    assert_true(c.p.gamma == p.gamma);
    const double gamma_p0 = (double)fc_to_float(fc_gain_to_real(&ar, c.k.gamma_p, FC_GAIN_FRAC), FC_GAIN_FRAC);
    fc_altitude_control_params q = p;
    q.actuator_lag_s = fc_from_float(0.08f, FC_DT_FRAC);
    assert_int_equal(fc_altitude_control_init(&c, &q), FC_INIT_OK);
    const double d = 1.0 + 9.81 * sqrt(5.0 / 4.0) * 0.08;
    assert_float_equal((double)fc_to_float(c.p.gamma, FC_GAIN_FRAC), (float)(5.0 / d), 1e-3f);
    assert_float_equal((double)fc_to_float(fc_gain_to_real(&ar, c.k.gamma_p, FC_GAIN_FRAC), FC_GAIN_FRAC),
                       (float)(gamma_p0 / pow(d, 1.5)), 1e-3f);
    q.actuator_lag_s = fc_from_float(-0.01f, FC_DT_FRAC);
    assert_int_equal(fc_altitude_control_init(&c, &q), FC_INIT_BAD_PARAM);
    q.actuator_lag_s = fc_from_float(1.5f, FC_DT_FRAC);
    assert_int_equal(fc_altitude_control_init(&c, &q), FC_INIT_BAD_PARAM);
}

/* Fuzz finding params-4 (tests/fuzz/findings/params-4.bin): the Crazyflie's
 * ssc-norm tuning with m_min a denormal (2.66e-44 kg) was accepted in float;
 * kp_max = k_g_max / m_min = inf and the first step's rho was inf * 0 = NaN,
 * the thrust NaN from the second step. kp_max (and the other constants rho is
 * built from) must fit their fixed formats, in both backends. */
static void test_rho_constants_bounded_params_4(void **state)
{
    (void)state;
    static fc_altitude_control c;
    fc_altitude_control_params p;
    fc_altitude_control_default_params(&p, dt_of(DT_500HZ), mass_of(0.027));
    p.modulation = FC_SSC_MODULATION_NORM_OBSERVER;
    assert_int_equal(fc_altitude_control_init(&c, &p), FC_INIT_OK);
    fc_altitude_control_params q = p;
#if FC_NUMERIC_FIXED
    q.mass_min_kg = 1; /* one LSB, 6e-8 kg */
#else
    q.mass_min_kg = 2.66247e-44f; /* the finding's value */
#endif
    assert_int_equal(fc_altitude_control_init(&c, &q), FC_INIT_BAD_PARAM);
    fc_vertical_trajectory zr = {0};
    fc_altitude_control_input in = {0};
    in.reference = &zr;
    in.z_m = fc_from_float(0.8f, FC_LENGTH_FRAC);
    zr.z_m = fc_from_float(1.0f, FC_LENGTH_FRAC);
    in.tilt_cos = fc_from_float(0.95f, FC_RATIO_FRAC);
    fc_altitude_control_output out;
    for (int k = 0; k < 4; k++) {
        assert_true(fc_altitude_control_step(&c, &in, &out) & FC_STEP_NOT_READY);
        assert_true(fc_is_finite(out.rho_n) && fc_is_finite(out.thrust_n));
    }
    /* kp_max = 1.1 / 5 g = 220 /kg: beyond RATIO in fixed, so beyond it in float too */
    q = p;
    q.mass_min_kg = mass_of(0.005);
    assert_int_equal(fc_altitude_control_init(&c, &q), FC_INIT_BAD_PARAM);
    /* kp_max / kappa_m: kappa_m = 0.01 with kp_max = 54 /kg */
    q = p;
    q.kappa_m_per_kg = fc_from_float(0.01f, FC_GAIN_FRAC);
    assert_int_equal(fc_altitude_control_init(&c, &q), FC_INIT_BAD_PARAM);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_reference_matches_3_6),
        cmocka_unit_test(test_reference_restart_and_bad_input),
        cmocka_unit_test(test_discretisation_constants),
        cmocka_unit_test(test_relay_filter_and_prediction_loop_analytic),
        cmocka_unit_test(test_lead_filter_realisation),
        cmocka_unit_test(test_norm_observer_bounds_d_eq2),
        cmocka_unit_test(test_eta_norm_observer_bounds_d_eq3),
        cmocka_unit_test(test_eta_majorant_covers_impulse_response),
        cmocka_unit_test(test_eta_majorant_range_rejected),
        cmocka_unit_test(test_seed44_ssc_adaptive_meets_spec),
        cmocka_unit_test(test_adaptation_settles_at_500_and_250_hz),
        cmocka_unit_test(test_start_respects_thrust_limits),
        cmocka_unit_test(test_norm_observer_pays),
        cmocka_unit_test(test_rel2_norm_observer_within_twice_constant),
        cmocka_unit_test(test_seed44_every_variant_flies),
        cmocka_unit_test(test_quasi_sliding_band_against_rate),
        cmocka_unit_test(test_adaptation_frozen_while_clamped),
        cmocka_unit_test(test_tilt_compensation),
        cmocka_unit_test(test_bad_input_holds_last_thrust),
        cmocka_unit_test(test_bad_params_rejected),
        cmocka_unit_test(test_rho_constants_bounded_params_4),
        cmocka_unit_test(test_lag_schedule),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
