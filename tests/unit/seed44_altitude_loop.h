/*
 * seed44_altitude_loop.h - the dissertation's 4.4 altitude loop, for tests:
 * an altitude-only plant (3.4) in double precision, integrated with RK4 at
 * 20 kHz, flown by the library's reference (3.6) and altitude law at a fixed
 * controller rate, and the SPEC's metrics over the run.
 *
 * Plant: z'' = k_g(z - z_d) F / m(t) - g, F the thrust command held over the
 * controller step; m(t) = 1/(0.01 s + 1) mu(t), mu = 4.0 kg, 3.5 kg from t = 30 s
 * (4.84); k_g (3.2) with R = 0.16 m, rho = 1.184, evaluated no lower than the
 * landing-gear height 0.18 m (contact off, as in the dissertation); pad (3.1)
 * with A = 0.18 m, w = 2 pi/10 rad/s. The vehicle starts at rest on z_r(0).
 */
#ifndef SEED44_ALTITUDE_LOOP_H
#define SEED44_ALTITUDE_LOOP_H

#include <math.h>
#include <stdbool.h>
#include "fc/altitude_control.h"

typedef struct seed44_metrics {
    double rms_error_m;            /* from 5 tau_zr + 5 s to the end */
    double max_abs_error_m;
    double mass_step_peak_error_m; /* max |e| in the 10 s after the mass step */
    double control_tv_per_s;       /* sum |u[k+1] - u[k]| / run length */
    double theta_rel_error;        /* |Theta - Theta*| / Theta* at the end */
    double theta_end_kg, theta_star_end_kg;
    double theta_swing_kg;         /* half the peak-to-peak of Theta over the last 10 s */
    double min_gear_clearance_m;   /* gear above the pad, whole run (contact off: below 0 is through it) */
    double max_u0_av_over_rho;     /* max |u0_av| / rho over the run: (4.7) keeps it <= 1 */
    int nan_outputs;
} seed44_metrics;

#define SEED44_PAD_AMPLITUDE_M 0.18
#define SEED44_PAD_RATE_RADPS (2.0 * 3.14159265358979323846 / 10.0)
#define SEED44_GEAR_HEIGHT_M 0.18

static double seed44_pad_z(double t) { return SEED44_PAD_AMPLITUDE_M / 2.0 * sin(SEED44_PAD_RATE_RADPS * t) + SEED44_PAD_AMPLITUDE_M / 2.0; }
static double seed44_pad_vz(double t) { return SEED44_PAD_AMPLITUDE_M / 2.0 * SEED44_PAD_RATE_RADPS * cos(SEED44_PAD_RATE_RADPS * t); }
static double seed44_pad_az(double t) { return -SEED44_PAD_AMPLITUDE_M / 2.0 * SEED44_PAD_RATE_RADPS * SEED44_PAD_RATE_RADPS * sin(SEED44_PAD_RATE_RADPS * t); }

static double seed44_ground_gain(double height_m)
{
    const double h = height_m > SEED44_GEAR_HEIGHT_M ? height_m : SEED44_GEAR_HEIGHT_M;
    const double ratio = 0.16 / (4.0 * h);
    return 1.0 / (1.0 - 1.184 * ratio * ratio); /* (3.2) */
}

typedef struct seed44_state { double z, vz, m; } seed44_state;

static seed44_state seed44_derivative(seed44_state s, double t, double thrust_n, double mass_target)
{
    const seed44_state d = {s.vz, seed44_ground_gain(s.z - seed44_pad_z(t)) * thrust_n / s.m - 9.81,
                            (mass_target - s.m) / 0.01};
    return d;
}

static seed44_state seed44_add(seed44_state a, seed44_state d, double h)
{
    const seed44_state r = {a.z + h * d.z, a.vz + h * d.vz, a.m + h * d.m};
    return r;
}

/* Flies 60 s of 4.4 at rate_hz with the given parameters; false if init failed. */
static bool seed44_run(const fc_altitude_control_params *params, double rate_hz, double duration_s,
                       seed44_metrics *m)
{
    const double dt = 1.0 / rate_hz, tau_zr = 0.1;
    fc_altitude_reference reference;
    const fc_altitude_reference_params rp = {fc_from_float((float)dt, FC_DT_FRAC), fc_from_float(0.1f, FC_TIME_FRAC),
                                             fc_from_float(1.0f, FC_LENGTH_FRAC), fc_from_float(0.18f, FC_LENGTH_FRAC)};
    fc_altitude_control ctl;
    if (fc_altitude_reference_init(&reference, &rp) != FC_INIT_OK || fc_altitude_control_init(&ctl, params) != FC_INIT_OK) {
        return false;
    }
    seed44_state s = {seed44_pad_z(0.0) + 0.18 + 1.0, 0.0, 4.0};
    const int substeps = (int)(20000.0 / rate_hz + 0.5);
    const double h = dt / substeps;
    const long steps = (long)(duration_s * rate_hz + 0.5);
    double sum_sq = 0.0, previous_u = 0.0, tv = 0.0;
    long window = 0;
    *m = (seed44_metrics){0};
    m->min_gear_clearance_m = 1e9;
    double theta_low = 1e9, theta_high = -1e9;
    double t = 0.0;
    for (long k = 0; k < steps; k++) {
        t = k * dt;
        const fc_vertical_trajectory pad = {fc_from_float((float)seed44_pad_z(t), FC_LENGTH_FRAC),
                                            fc_from_float((float)seed44_pad_vz(t), FC_VEL_FRAC),
                                            fc_from_float((float)seed44_pad_az(t), FC_ACCEL_FRAC)};
        fc_vertical_trajectory zr;
        (void)fc_altitude_reference_step(&reference, &pad, &zr);
        const fc_altitude_control_input in = {fc_from_float((float)s.z, FC_LENGTH_FRAC),
                                              fc_from_float((float)s.vz, FC_VEL_FRAC), &zr, FC_INT(1, RATIO), 0u};
        fc_altitude_control_output out;
        (void)fc_altitude_control_step(&ctl, &in, &out);
        const double u = (double)fc_to_float(out.thrust_n, FC_FORCE_FRAC);
        if (!isfinite(u)) {
            m->nan_outputs++;
        }
        if (k > 0) {
            tv += fabs(u - previous_u);
        }
        previous_u = u;
        const double z_r = seed44_pad_z(t) + 0.18 + 1.0 * exp(-t / tau_zr);
        const double e = s.z - z_r;
        if (t >= 5.0 * tau_zr + 5.0) {
            sum_sq += e * e;
            window++;
            if (fabs(e) > m->max_abs_error_m) m->max_abs_error_m = fabs(e);
        }
        if (t >= 30.0 && t < 40.0 && fabs(e) > m->mass_step_peak_error_m) {
            m->mass_step_peak_error_m = fabs(e);
        }
        m->theta_end_kg = (double)fc_to_float(out.theta_kg, FC_MASS_FRAC);
        if (t >= duration_s - 10.0) {
            theta_low = fmin(theta_low, m->theta_end_kg);
            theta_high = fmax(theta_high, m->theta_end_kg);
        }
        m->min_gear_clearance_m = fmin(m->min_gear_clearance_m, s.z - seed44_pad_z(t) - SEED44_GEAR_HEIGHT_M);
        const double rho = (double)fc_to_float(out.rho_n, FC_FORCE_FRAC);
        if (rho > 0.0) {
            const double u0_av = (double)fc_to_float(out.u0_av_n, FC_FORCE_FRAC);
            m->max_u0_av_over_rho = fmax(m->max_u0_av_over_rho, fabs(u0_av) / rho);
        }
        const double mass_target = t >= 30.0 ? 3.5 : 4.0;
        for (int i = 0; i < substeps; i++) {
            const double ti = t + i * h;
            const seed44_state k1 = seed44_derivative(s, ti, u, mass_target);
            const seed44_state k2 = seed44_derivative(seed44_add(s, k1, h / 2), ti + h / 2, u, mass_target);
            const seed44_state k3 = seed44_derivative(seed44_add(s, k2, h / 2), ti + h / 2, u, mass_target);
            const seed44_state k4 = seed44_derivative(seed44_add(s, k3, h), ti + h, u, mass_target);
            s.z += h / 6 * (k1.z + 2 * k2.z + 2 * k3.z + k4.z);
            s.vz += h / 6 * (k1.vz + 2 * k2.vz + 2 * k3.vz + k4.vz);
            s.m += h / 6 * (k1.m + 2 * k2.m + 2 * k3.m + k4.m);
        }
    }
    m->theta_swing_kg = (theta_high - theta_low) / 2.0;
    m->rms_error_m = window > 0 ? sqrt(sum_sq / (double)window) : 0.0;
    m->control_tv_per_s = tv / duration_s;
    m->theta_star_end_kg = s.m / seed44_ground_gain(s.z - seed44_pad_z(t));
    m->theta_rel_error = fabs(m->theta_end_kg - m->theta_star_end_kg) / m->theta_star_end_kg;
    return true;
}

#endif /* SEED44_ALTITUDE_LOOP_H */
