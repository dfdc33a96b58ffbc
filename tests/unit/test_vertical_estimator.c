/*
 * Tests of the vertical channel (fc/vertical_estimator.h), both backends:
 * speed and accelerometer bias (the complementary loop's fast bias and the
 * reported average of it), dead reckoning on the averaged bias, the gear
 * height from the range finder, the hover thrust, the thrust model without
 * an accelerometer.
 *
 * dt = 1/512 s: the step and its multiples are exact in DT, TIME and float.
 * The vehicle is the F450's 1.5 kg (weight 14.7 N) with the default params:
 * w_v = 1 rad/s, the bias averaged over tau_b = 2 s, w_h = 2 rad/s, hover
 * thrust averaged over 2 s in [0.5, 1.5] x weight, range gaps counted up to
 * 0.1 s. References are computed from the quantised inputs (fc_to_float of
 * what was passed in).
 *
 * Fixed-point floor of the fast bias b_f (the loop's, v.bias_fast_mps2):
 * the speed moves by round((a - b_f) dt) VEL LSB a step, the speed
 * correction by round(2 w_v dt r) and the bias by round(w_v^2 dt r) ACCEL
 * LSB, with 2 w_v dt = 2^-8 and w_v^2 dt = 2^-9. A bias error under
 * 3 x 256 LSB gives a drift the speed correction cancels with |r| < 256 LSB,
 * where the bias step rounds to 0: the bias can stop up to 768 LSB =
 * 1.8e-4 m/s^2 off. In float the same argument with the ulp of b (1.5e-8
 * near 0.2) gives under 1e-5 m/s^2.
 * Floor of the reported (averaged) bias b_a: it moves by
 * round((dt / tau_b) (b_f - b_a)) with dt / tau_b = 2^-10, which rounds to 0
 * once |b_f - b_a| < 0.5 x 2^10 = 512 ACCEL LSB (the roundings of a moving
 * b_f, 0.5 LSB a step through the lag of gain 2^10, stay within the same
 * 512 LSB): b_a can stop up to 768 + 512 LSB = 3.05e-4 m/s^2 off. In float,
 * 2^10 x 0.5 ulp(b) = 7.6e-6 near 0.2 on top of the fast bias's: under
 * 2e-5 m/s^2.
 */
#include <string.h>

#include "test_support.h"

#include "fc/vertical_estimator.h"

#define F(x, KIND) fc_from_float((float)(x), FC_##KIND##_FRAC)
#define D(x, KIND) ((double)fc_to_float((x), FC_##KIND##_FRAC))

#define DT_S (1.0 / 512.0)
#define STEPS_PER_S 512
#define G 9.80665
#define WEIGHT_N (1.5 * G)
#define W_V 1.0
#define W_H 2.0
#define HOVER_TAU_S 2.0
#define BIAS_TAU_S 2.0 /* tau_b, bias_average_tau_s */
#define RANGE_EVERY 5 /* a range sample every 5 steps (~100 Hz) */

#if FC_NUMERIC_FIXED
#define BIAS_FLOOR 2.0e-4     /* the fast bias's (header) */
#define AVG_BIAS_FLOOR 3.1e-4 /* the reported, averaged bias's (header) */
#else
#define BIAS_FLOOR 1.0e-5
#define AVG_BIAS_FLOOR 2.0e-5
#endif
/* The speed error left with it: the correction 2 w_v dt r balances the
 * drift b_err dt, r = b_err / (2 w_v), plus the band in which that
 * correction rounds to 0 (0.5 x 256 VEL LSB in fixed: 3.1e-5 m/s). */
#define SPEED_FLOOR (BIAS_FLOOR / (2.0 * W_V) + 128.0 * ts_resolution(FC_VEL_FRAC))

typedef struct fixture {
    fc_vertical_estimator v;
    fc_vertical_estimator_params p;
    fc_vertical_estimator_input in;
    fc_quat attitude;     /* in.attitude points here */
    fc_vec3 accel_mps2;   /* in.accel_mps2 points here */
    fc_vertical_estimate out;
    fc_step_status status;
    double g;   /* the estimator's gravity, as held */
} fixture;

/* Level, the accelerometer reading gravity, a good zero speed, no range
 * sample, the thrust the nominal weight, no hover learning. */
static void fixture_init(fixture *f)
{
    memset(f, 0, sizeof *f);
    fc_vertical_estimator_default_params(&f->p, F(DT_S, DT), F(G, ACCEL), F(WEIGHT_N, FORCE));
    assert_int_equal(fc_vertical_estimator_init(&f->v, &f->p), FC_INIT_OK);
    f->g = D(f->p.gravity_mps2, ACCEL);
    f->in.attitude = &f->attitude;
    f->in.accel_mps2 = &f->accel_mps2;
    f->attitude = fc_quat_identity();
    f->accel_mps2 = fc_vec3_make(F(0, ACCEL), F(0, ACCEL), f->p.gravity_mps2);
    f->in.accel_ok = true;
    f->in.vz_mps = F(0, VEL);
    f->in.vz_ok = true;
    f->in.gear_height_m = F(0, LENGTH);
    f->in.gear_height_fresh = false;
    f->in.thrust_n = F(WEIGHT_N, FORCE);
    f->in.tilt_cos = FC_INT(1, RATIO);
    f->in.learn_hover = false;
}

static void step(fixture *f)
{
    f->status = fc_vertical_estimator_step(&f->v, &f->in, &f->out);
    assert_true((f->status & (FC_STEP_NOT_READY | FC_STEP_ARITH_SATURATED)) == 0u);
}

/* The accelerometer of a level vehicle whose world-z specific force is g + a. */
static void set_level_accel(fixture *f, double a_mps2)
{
    f->attitude = fc_quat_identity();
    f->accel_mps2 = fc_vec3_make(F(0, ACCEL), F(0, ACCEL), F(f->g + a_mps2, ACCEL));
}

/* The world-z acceleration the estimator sees in it (quantised input). */
static double level_accel_held(const fixture *f)
{
    return D(f->accel_mps2.z, ACCEL) - f->g;
}

static double vz(const fixture *f) { return ts_val(f->out.vz_mps, FC_VEL_FRAC); }
static double bias(const fixture *f) { return ts_val(f->out.accel_bias_mps2, FC_ACCEL_FRAC); }
static double fast_bias(const fixture *f) { return ts_val(f->v.bias_fast_mps2, FC_ACCEL_FRAC); }
static double gear(const fixture *f) { return ts_val(f->out.gear_height_m, FC_LENGTH_FRAC); }
static double hover(const fixture *f) { return ts_val(f->out.hover_thrust_n, FC_FORCE_FRAC); }

/* ---- speed and bias ------------------------------------------------------ */

/* The reported bias's share of a bias error the fast loop starts with: the
 * fast bias's error is -beta (1 + w t) e^(-w t) (w = w_v), and the average,
 * b_a' = (b_f - b_a) / tau_b from b_a(0) = 0, carries
 *     -beta E(t),  E(t) = e^(-t/tau_b) + (1/tau_b) int_0^t e^(-(t-s)/tau_b) (1 + w s) e^(-w s) ds
 *                       = e^(-t/tau_b) (1 + (1/tau_b) [e^(c s) ((1 + w s)/c - w/c^2)]_0^t),  c = 1/tau_b - w
 * (w = 1, tau_b = 2: E = 4 e^(-t/2) - (3 + t) e^(-t)). E falls from 1 without
 * a sign change (E' = e^(-t) ((2 + t) - 2 e^(t/2)) < 0 for t > 0 there): a
 * lag of a monotone error is monotone, the average never overshoots. */
static double averaged_bias_lag(double t)
{
    const double alpha = 1.0 / BIAS_TAU_S, c = alpha - W_V;
    const double primitive_t = exp(c * t) * ((1.0 + W_V * t) / c - W_V / (c * c));
    const double primitive_0 = 1.0 / c - W_V / (c * c);
    return exp(-alpha * t) * (1.0 + alpha * (primitive_t - primitive_0));
}

/* A constant accelerometer bias beta (+-0.2 m/s^2) on a vehicle at rest with
 * a good speed input: the errors (e = v_m - v, fast bias error) obey
 * s^2 + 2 w_v s + w_v^2 = 0; from e(0) = 0 and a bias error -beta the fast
 * bias error is -beta (1 + w_v t) e^(-w_v t) and the speed error
 * beta t e^(-w_v t) (at most 0.074 m/s, at t = 1 s): the loop flies on the
 * fast bias, so the speed is exactly as before the averaging. Checked at
 * every step: the fast bias (v.bias_fast_mps2) and the speed against that
 * envelope (x 1.05 for the discretisation, whose poles are within
 * w_v dt = 0.2 % of the continuous ones) plus the backend's floors (header,
 * SPEED_FLOOR); the reported bias against its lag, beta (1 - E(t)) above,
 * within 5 % of the error it still carries (the same discretisation, and the
 * average's step of dt / tau_b = 0.05 % per step) plus its floor, and
 * monotone (never away from beta by more than 1 LSB / ulp a step). After 30 s
 * |beta| E = 0.2 x 4 e^-15 = 2.4e-7: the bias is within its floor. */
static void test_bias_converges_with_speed_input(void **state)
{
    (void)state;
    const double betas[] = {0.2, -0.2};
    for (size_t i = 0; i < 2; i++) {
        fixture f;
        fixture_init(&f);
        set_level_accel(&f, betas[i]);
        const double beta = level_accel_held(&f);
        const double direction = beta > 0.0 ? 1.0 : -1.0;
        ts_check fast_env = ts_check_begin("fast bias error within (1 + t) e^-t envelope");
        ts_check speed_env = ts_check_begin("speed error within t e^-t envelope");
        ts_check avg_lag = ts_check_begin("reported bias on its lag beta (1 - E(t))");
        ts_check monotone = ts_check_begin("reported bias monotone towards beta");
        double previous = 0.0;
        for (int k = 1; k <= 30 * STEPS_PER_S; k++) {
            step(&f);
            const double t = k * DT_S;
            const double env_b = fabs(beta) * (1.0 + W_V * t) * exp(-W_V * t);
            const double env_v = fabs(beta) * t * exp(-W_V * t);
            const double lag = averaged_bias_lag(t);
            (void)ts_close(&fast_env, fast_bias(&f), beta, 1.05 * env_b + BIAS_FLOOR, "beta %g t %.3f", beta, t);
            (void)ts_close(&speed_env, vz(&f), 0.0, 1.05 * env_v + SPEED_FLOOR, "beta %g t %.3f", beta, t);
            (void)ts_close(&avg_lag, bias(&f), beta * (1.0 - lag), 0.05 * fabs(beta) * lag + AVG_BIAS_FLOOR,
                           "beta %g t %.3f", beta, t);
            const double moved = (bias(&f) - previous) * direction;
            (void)ts_close(&monotone, fmin(moved, 0.0), 0.0, ts_tol(FC_ACCEL_FRAC, 1.0, 1.0, beta), "beta %g t %.3f",
                           beta, t);
            previous = bias(&f);
        }
        ts_check_end(&fast_env);
        ts_check_end(&speed_env);
        ts_check_end(&avg_lag);
        ts_check_end(&monotone);
        TS_ASSERT_CLOSE(fast_bias(&f), beta, BIAS_FLOOR);
        TS_ASSERT_CLOSE(bias(&f), beta, 1.05 * fabs(beta) * averaged_bias_lag(30.0) + AVG_BIAS_FLOOR);
    }
}

/* Why the average: an oscillating vehicle and a speed input that comes late.
 * The vehicle's speed is v = A sin(W t) (A = 0.2 m/s, W = 2 pi rad/s: 1 Hz,
 * 3 cm of height), the accelerometer reads its acceleration (the step's
 * (v_k - v_(k-1)) / dt, so the prediction alone would be exact) plus
 * beta = 0.2 m/s^2, and v_m = v(t - D) with D = 50 ms (motion capture).
 * With x = v_est - v, eps = b_f - beta and n = v_m - v the loop is
 * x' = -eps + l1 (n - x), eps' = -l2 (n - x), so
 *     eps = -l2 s / (s^2 + l1 s + l2) n,  |eps| = w_v^2 W / (w_v^2 + W^2) |n|
 * (critically damped: |s^2 + 2 w_v s + w_v^2| = w_v^2 + W^2 at s = jW), with
 * |n| = 2 A sin(W D / 2) = 0.0626 m/s: the fast bias ripples by 9.7e-3 m/s^2
 * about beta. The average, b_a' = (b_f - b_a) / tau_b, passes
 * 1 / sqrt(1 + (W tau_b)^2) = 0.079 of it: 7.7e-4 m/s^2. Checked over the
 * last 10 s of 40 (ten periods; the start's transient, beta E(30) = 2.4e-7,
 * is gone): the fast bias's half peak-to-peak within 5 % of its amplitude
 * (the discrete loop: W dt = 1.2 %) plus its floor; the reported bias within
 * beta +- (1.05 x its amplitude + its floor) at every step, hence its ripple
 * under 1/8 of the fast one's. Dead reckoning from any instant of the
 * oscillation drifts at |b_a - beta| <= 1.1e-3 m/s (per s), not 9.7e-3. */
static void test_averaged_bias_filters_ripple(void **state)
{
    (void)state;
    const double amplitude = 0.2, omega = 2.0 * TS_PI, delay = 0.05, beta = 0.2;
    fixture f;
    fixture_init(&f);
    const double residual = 2.0 * amplitude * sin(0.5 * omega * delay);
    const double fast_amp = W_V * W_V * omega / (W_V * W_V + omega * omega) * residual;
    const double avg_amp = fast_amp / sqrt(1.0 + omega * BIAS_TAU_S * omega * BIAS_TAU_S);
    double fast_min = HUGE_VAL, fast_max = -HUGE_VAL, avg_min = HUGE_VAL, avg_max = -HUGE_VAL;
    ts_check band = ts_check_begin("reported bias within beta +- its ripple");
    for (int k = 1; k <= 40 * STEPS_PER_S; k++) {
        const double t = k * DT_S;
        const double v_now = amplitude * sin(omega * t), v_before = amplitude * sin(omega * (t - DT_S));
        set_level_accel(&f, (v_now - v_before) / DT_S + beta);
        f.in.vz_mps = F(amplitude * sin(omega * (t - delay)), VEL);
        step(&f);
        if (k > 30 * STEPS_PER_S) {
            fast_min = fmin(fast_min, fast_bias(&f));
            fast_max = fmax(fast_max, fast_bias(&f));
            avg_min = fmin(avg_min, bias(&f));
            avg_max = fmax(avg_max, bias(&f));
            (void)ts_close(&band, bias(&f), beta, 1.05 * avg_amp + AVG_BIAS_FLOOR, "t %.3f", t);
        }
    }
    ts_check_end(&band);
    const double fast_ripple = 0.5 * (fast_max - fast_min), avg_ripple = 0.5 * (avg_max - avg_min);
    TS_ASSERT_CLOSE(fast_ripple, fast_amp, 0.05 * fast_amp + BIAS_FLOOR);
    TS_ASSERT_CLOSE(avg_ripple, 0.0, 1.05 * avg_amp + AVG_BIAS_FLOOR);
    if (!(avg_ripple < fast_ripple / 8.0)) {
        fail_msg("reported bias ripples by %g m/s^2, the fast bias by %g: the average does not filter it", avg_ripple,
                 fast_ripple);
    }
}
/* The world-z row of R(q): a tilted vehicle (45 deg about (1, 1, 0)/sqrt 2,
 * then 30 deg of yaw) whose accelerometer reads R^T (0, 0, g + 0.3): the
 * speed, without a speed input, gains 0.3 m/s a second. A wrong row (sign,
 * index) gives another projection and fails by far more than the tolerance:
 * 512 roundings of 0.5 VEL LSB (6.1e-5 m/s) in fixed and the inputs'
 * quantisation (a few ACCEL LSB over 1 s), 1e-4 m/s in all. */
static void test_tilted_specific_force_projected(void **state)
{
    (void)state;
    fixture f;
    fixture_init(&f);
    const double half = 0.5 * 45.0 * TS_PI / 180.0, yaw_half = 0.5 * 30.0 * TS_PI / 180.0;
    /* q = q_yaw (about z) * q_tilt (about (1, 1, 0)/sqrt 2) */
    const double tw = cos(half), tx = sin(half) / sqrt(2.0), ty = tx;
    const double yw = cos(yaw_half), yz = sin(yaw_half);
    const double w = yw * tw, x = yw * tx - yz * ty, y = yw * ty + yz * tx, z = yz * tw;
    f.attitude.w = F(w, UNIT);
    f.attitude.x = F(x, UNIT);
    f.attitude.y = F(y, UNIT);
    f.attitude.z = F(z, UNIT);
    const double r20 = 2 * (x * z - w * y), r21 = 2 * (y * z + w * x), r22 = 1 - 2 * (x * x + y * y);
    const double up = f.g + 0.3;
    f.accel_mps2 = fc_vec3_make(F(r20 * up, ACCEL), F(r21 * up, ACCEL), F(r22 * up, ACCEL));
    f.in.vz_ok = false;
    for (int k = 0; k < STEPS_PER_S; k++) {
        step(&f);
    }
    TS_ASSERT_CLOSE(vz(&f), 0.3, 1e-4);
}

/* Without the speed input the speed runs on a - b alone: a level
 * acceleration a held 1 s gives v = N a dt after N = 512 steps, and the gear
 * height (known from a sample at step 0) h0 + a dt^2 N (N - 1) / 2 (it moves
 * by the speed before the step's update). Tolerance: one rounding of the
 * product a step (N x 0.5 VEL / LENGTH LSB in fixed; float sums of
 * multiples of 2^-10 are exact up to the input's quantisation). */
static void test_speed_propagates_without_speed_input(void **state)
{
    (void)state;
    fixture f;
    fixture_init(&f);
    set_level_accel(&f, 0.5);
    const double a = level_accel_held(&f);
    f.in.vz_ok = false;
    f.in.gear_height_m = F(1.0, LENGTH);
    f.in.gear_height_fresh = true;
    step(&f);
    f.in.gear_height_fresh = false;
    for (int k = 1; k < STEPS_PER_S; k++) {
        step(&f);
    }
    const double n = STEPS_PER_S;
    TS_ASSERT_CLOSE(vz(&f), n * a * DT_S, ts_tol(FC_VEL_FRAC, 0.5 * n, 4.0 * n, 0.5) + 1e-7);
    TS_ASSERT_CLOSE(gear(&f), 1.0 + a * DT_S * DT_S * n * (n - 1) / 2, ts_tol(FC_LENGTH_FRAC, 0.5 * n, 4.0 * n, 1.5));
}

/* The point of learning the bias: 30 s with the speed input learn a bias of
 * +0.2 m/s^2 (the average needs them: 0.2 E(t) is 4.4e-4 m/s^2 at 15 s,
 * 2.4e-7 at 30 s); the speed input then goes (position lost) and the
 * vehicle hovers 10 s with the same biased accelerometer, the prediction on
 * the averaged bias, which no longer moves. The speed drifts at its
 * residual error, |v| <= 10 s x (1.05 x 2.4e-7 + its floor) + 1e-4 (the
 * speed error left at 30 s, within SPEED_FLOOR, and roundings); without the
 * learnt bias it would be 2 m/s. */
static void test_learnt_bias_removed_in_dead_reckoning(void **state)
{
    (void)state;
    fixture f;
    fixture_init(&f);
    set_level_accel(&f, 0.2);
    for (int k = 0; k < 30 * STEPS_PER_S; k++) {
        step(&f);
    }
    const fc_real learnt = f.out.accel_bias_mps2;
    f.in.vz_ok = false;
    f.in.vz_mps = F(123, VEL); /* not looked at */
    for (int k = 0; k < 10 * STEPS_PER_S; k++) {
        step(&f);
        TS_ASSERT_REAL_EQ(f.out.accel_bias_mps2, learnt);
    }
    TS_ASSERT_CLOSE(vz(&f), 0.0, 10.0 * (1.05 * 0.2 * averaged_bias_lag(30.0) + AVG_BIAS_FLOOR) + 1e-4);
}

/* Without the speed input the prediction runs on the averaged bias, not on
 * the loop's fast one: the input goes 5 s into learning beta = 0.2 m/s^2,
 * when they differ most usefully here (fast error 0.2 x 6 e^-5 = 8.1e-3,
 * averaged 0.2 E(5) = 0.055 m/s^2). For the next 2 s (N = 1024 steps) the
 * speed moves by exactly round((a - b_a) dt) a step, b_a held:
 * v = v(5 s) + N (a - b_a) dt within N x 0.5 VEL LSB (fixed) or a few float
 * ulps a step; on the fast bias it would be N (a - b_f) dt, 0.094 m/s away. */
static void test_dead_reckoning_flies_on_averaged_bias(void **state)
{
    (void)state;
    fixture f;
    fixture_init(&f);
    set_level_accel(&f, 0.2);
    const double a = level_accel_held(&f);
    for (int k = 0; k < 5 * STEPS_PER_S; k++) {
        step(&f);
    }
    const double v_start = vz(&f), b_avg = bias(&f), b_fast = fast_bias(&f);
    const fc_real held = f.out.accel_bias_mps2;
    const int n = 2 * STEPS_PER_S;
    const double tol = ts_tol(FC_VEL_FRAC, 0.5 * n, 4.0 * n, 0.2) + 1e-7;
    assert_true(n * DT_S * fabs(b_fast - b_avg) > 100.0 * tol); /* the two are told apart */
    f.in.vz_ok = false;
    for (int k = 0; k < n; k++) {
        step(&f);
    }
    TS_ASSERT_REAL_EQ(f.out.accel_bias_mps2, held);
    TS_ASSERT_CLOSE(vz(&f), v_start + n * (a - b_avg) * DT_S, tol);
}
/* ---- gear height from the range finder ----------------------------------- */

/* The first sample sets the gear height; then each sample, T = 5 dt after
 * the previous, closes 2 w_h T = 5/128 of the error: after n samples of
 * 1.2 m from 1.0 m (at rest, good speed input) the error is
 * 0.2 (1 - 5/128)^n. The speed input is good, so the range does not touch
 * the speed (exactly 0: the accelerometer reads g). Tolerance: one rounding
 * of the correction a sample (n LENGTH LSB), float ulps likewise. */
static void test_range_corrects_gear_height(void **state)
{
    (void)state;
    fixture f;
    fixture_init(&f);
    assert_false(f.v.est.gear_height_known);
    f.in.gear_height_m = F(1.0, LENGTH);
    f.in.gear_height_fresh = true;
    step(&f);
    assert_true(f.out.gear_height_known);
    TS_ASSERT_REAL_EQ(f.out.gear_height_m, F(1.0, LENGTH));
    f.in.gear_height_m = F(1.2, LENGTH);
    const double target = D(f.in.gear_height_m, LENGTH);
    const double keep = 1.0 - 2.0 * W_H * RANGE_EVERY * DT_S;
    int samples = 0;
    for (int k = 1; k <= 200 * RANGE_EVERY; k++) {
        f.in.gear_height_fresh = k % RANGE_EVERY == 0;
        step(&f);
        if (f.in.gear_height_fresh) {
            samples++;
            const double expected = target - (target - 1.0) * pow(keep, samples);
            TS_ASSERT_CLOSE(gear(&f), expected, ts_tol(FC_LENGTH_FRAC, samples, 4.0 * samples, 1.2));
        }
        TS_ASSERT_REAL_EQ(f.out.vz_mps, FC_INT(0, VEL));
    }
}

/* Without the speed input the range corrects the speed too: the surface
 * comes up at 0.5 m/s (h_m = 4 - 0.5 t, level, a = 0) and the estimate
 * starts at rest. The loop (gains 2 w_h, w_h^2: a double pole at -2 rad/s,
 * type 2, so no error on a ramp) leaves a speed error of at most
 * 0.5 (1 + 2 t) e^(-2 t) = 2.5e-4 m/s at 5 s; sampled at T = 5/512 s its
 * poles are the roots of z^2 - (2 - 4T - 4T^2) z + (1 - 4T), both real and
 * of modulus <= sqrt(1 - 4T) ~ e^(-2T), as fast as the continuous ones:
 * 2e-3 m/s (and m) is that bound with a margin of 8 for the near-double
 * pole's split and the roundings. */
static void test_range_corrects_speed_without_speed_input(void **state)
{
    (void)state;
    fixture f;
    fixture_init(&f);
    f.in.vz_ok = false;
    for (int k = 0; k <= 5 * STEPS_PER_S; k++) {
        const double h_m = 4.0 - 0.5 * k * DT_S;
        f.in.gear_height_m = F(h_m, LENGTH);
        f.in.gear_height_fresh = k % RANGE_EVERY == 0;
        step(&f);
    }
    TS_ASSERT_CLOSE(vz(&f), -0.5, 2e-3);
    TS_ASSERT_CLOSE(gear(&f), 4.0 - 0.5 * 5.0, 2e-3);
}

/* A gap between range samples counts as at most range_period_max_s (0.1 s):
 * after 1 s without a sample, a sample 1 m above the estimate moves it by
 * 2 w_h 0.1 = 0.4 m (not 2 w_h 1 = 4 m, which would overshoot by 3 m). */
static void test_range_gap_bounded(void **state)
{
    (void)state;
    fixture f;
    fixture_init(&f);
    f.in.gear_height_m = F(1.0, LENGTH);
    f.in.gear_height_fresh = true;
    step(&f);
    f.in.gear_height_fresh = false;
    for (int k = 0; k < STEPS_PER_S - 1; k++) {
        step(&f);
    }
    f.in.gear_height_m = F(2.0, LENGTH);
    f.in.gear_height_fresh = true;
    step(&f);
    TS_ASSERT_CLOSE(gear(&f), 1.4, ts_tol(FC_LENGTH_FRAC, 4.0, 8.0, 1.4) + ts_fixed_rel(0.4, 20));
}

/* The field's contract: "0 until the first range sample". A vehicle climbing
 * at 1 m/s for 1 s with no range finder must report 0, not an integrated
 * height. */
static void test_gear_height_zero_until_first_sample(void **state)
{
    (void)state;
    fixture f;
    fixture_init(&f);
    f.in.vz_mps = F(1.0, VEL);
    for (int k = 0; k < STEPS_PER_S; k++) {
        step(&f);
    }
    assert_false(f.out.gear_height_known);
    if (f.out.gear_height_m != FC_INT(0, LENGTH)) {
        fail_msg("gear_height_m = %g m before any range sample (documented: "
                 "0 until the first sample); predict() integrates the speed into it unconditionally",
                 gear(&f));
    }
}

/* ---- hover thrust -------------------------------------------------------- */

/* Hover thrust learning with a constant thrust T and tilt k_h, the vehicle
 * accelerating at a (accelerometer g + a along world z, the attitude tilted
 * to acos k_h about x so the specific force is consistent): the gradient step
 * is a first-order lag of time constant tau g / (a + g) <= 2 s towards
 * T k_h g / (a + g). After 20 s the lag leaves |T_h(0) - target| e^(-10 (a+g)/g)
 * (<= 7.4 N x 4.5e-5 here). The floor is the averaging's dead band, in
 * both backends: the step (dt/tau) x difference is lost once under half a
 * unit of T_h, i.e. for |difference| < (tau/dt) x 0.5 unit = 1024 x 0.5:
 * fixed, 0.5 FORCE LSB x 1024 = 4.9e-4 N (plus 1/g in RATIO, relative
 * 6e-7); float, 1024 x 0.5 ulp(T_h) (9.8e-4 N for T_h in [16, 32) N; the
 * bound takes a whole ulp for the rounding of the difference itself). */
static void check_hover_learning(double mass_factor, double tilt_cos, double a_mps2)
{
    fixture f;
    fixture_init(&f);
    const double phi = acos(tilt_cos);
    f.attitude.w = F(cos(phi / 2), UNIT);
    f.attitude.x = F(sin(phi / 2), UNIT);
    f.attitude.y = F(0, UNIT);
    f.attitude.z = F(0, UNIT);
    const double up = f.g + a_mps2;
    f.accel_mps2 = fc_vec3_make(F(0, ACCEL), F(sin(phi) * up, ACCEL), F(cos(phi) * up, ACCEL));
    f.in.vz_ok = false;
    f.in.thrust_n = F(mass_factor * (G + a_mps2) * 1.5 / tilt_cos, FORCE);
    f.in.tilt_cos = F(tilt_cos, RATIO);
    f.in.learn_hover = true;
    const double vertical = D(f.in.thrust_n, FORCE) * D(f.in.tilt_cos, RATIO);
    const double target = vertical * f.g / (a_mps2 + f.g);
    const double start = D(f.p.hover_thrust_n, FORCE);
    const double direction = target >= start ? 1.0 : -1.0;
    double previous = start;
    for (int k = 0; k < 20 * STEPS_PER_S; k++) {
        step(&f);
        /* a first-order lag never overshoots: monotone towards the target */
        assert_true((hover(&f) - previous) * direction >= -ts_tol(FC_FORCE_FRAC, 1.0, 2.0, target));
        previous = hover(&f);
    }
    const double lag = fabs(target - start) * exp(-20.0 / HOVER_TAU_S * (a_mps2 + f.g) / f.g);
    int exponent;
    (void)frexp(target, &exponent);
    const double ulp = ldexp(1.0, exponent - 24); /* float's ulp at the target */
    const double floor_n = FC_NUMERIC_FIXED ? 4.9e-4 + 1e-6 * target : (HOVER_TAU_S / DT_S) * ulp;
    TS_ASSERT_CLOSE(hover(&f), target, 1.05 * lag + floor_n);
}

static void test_hover_thrust_converges(void **state)
{
    (void)state;
    check_hover_learning(1.2, 1.0, 0.0);  /* 20 % heavier, level */
    check_hover_learning(0.8, 1.0, 0.0);  /* 20 % lighter */
    check_hover_learning(1.0, 0.9, 0.0);  /* tilted: T k_h holds it */
    check_hover_learning(1.1, 1.0, 1.0);  /* accelerating up: T k_h g / (a + g) */
}

/* The learnt value stays inside [hover_min, hover_max] = [0.5, 1.5] x weight:
 * a thrust of 2 x weight (and 0.2 x weight) held in "hover" for 20 s ends
 * exactly on the bound and never crosses it. */
static void test_hover_thrust_bounded(void **state)
{
    (void)state;
    const double factors[] = {2.0, 0.2};
    for (size_t i = 0; i < 2; i++) {
        fixture f;
        fixture_init(&f);
        f.in.thrust_n = F(factors[i] * WEIGHT_N, FORCE);
        f.in.learn_hover = true;
        for (int k = 0; k < 20 * STEPS_PER_S; k++) {
            step(&f);
            assert_true(f.out.hover_thrust_n >= f.p.hover_min_n && f.out.hover_thrust_n <= f.p.hover_max_n);
        }
        TS_ASSERT_REAL_EQ(f.out.hover_thrust_n, factors[i] > 1.0 ? f.p.hover_max_n : f.p.hover_min_n);
    }
}

/* It learns only when told (learn_hover) and only on an accelerometer sample:
 * 5 s of a thrust 1.3 x weight leave it exactly at the nominal otherwise. */
static void test_hover_thrust_learns_only_when_allowed(void **state)
{
    (void)state;
    for (int which = 0; which < 2; which++) {
        fixture f;
        fixture_init(&f);
        f.in.thrust_n = F(1.3 * WEIGHT_N, FORCE);
        f.in.learn_hover = which == 1;
        f.in.accel_ok = which == 0;
        f.in.vz_ok = false;
        for (int k = 0; k < 5 * STEPS_PER_S; k++) {
            step(&f);
        }
        TS_ASSERT_REAL_EQ(f.out.hover_thrust_n, f.p.hover_thrust_n);
    }
}

/* reset() clears speed, both biases, acceleration and the gear height, and keeps
 * the learnt hover thrust (the vehicle's, not the flight's). */
static void test_reset_keeps_hover_thrust(void **state)
{
    (void)state;
    fixture f;
    fixture_init(&f);
    set_level_accel(&f, 0.2);
    f.in.thrust_n = F(1.2 * WEIGHT_N, FORCE);
    f.in.learn_hover = true;
    f.in.gear_height_m = F(1.0, LENGTH);
    f.in.gear_height_fresh = true;
    for (int k = 0; k < 3 * STEPS_PER_S; k++) {
        step(&f);
    }
    const fc_real learnt = f.v.est.hover_thrust_n;
    assert_true(learnt > f.p.hover_thrust_n);
    fc_vertical_estimator_reset(&f.v);
    TS_ASSERT_REAL_EQ(f.v.est.hover_thrust_n, learnt);
    TS_ASSERT_REAL_EQ(f.v.est.vz_mps, FC_INT(0, VEL));
    TS_ASSERT_REAL_EQ(f.v.est.accel_bias_mps2, FC_INT(0, ACCEL));
    TS_ASSERT_REAL_EQ(f.v.bias_fast_mps2, FC_INT(0, ACCEL));
    TS_ASSERT_REAL_EQ(f.v.est.accel_z_mps2, FC_INT(0, ACCEL));
    TS_ASSERT_REAL_EQ(f.v.est.gear_height_m, FC_INT(0, LENGTH));
    assert_false(f.v.est.gear_height_known);
}

/* ---- without an accelerometer -------------------------------------------- */

/* accel_ok false (IMU lost): the acceleration is the thrust model's,
 * a = g (T k_h / T_h - 1). With T_h the nominal weight and T k_h = 1.1 x it,
 * a = 0.1 g: the speed gains 0.98 m/s in 1 s; the step says DEGRADED. At
 * T k_h = T_h it does not move at all. Tolerance: the load factor in RATIO
 * (relative 2^-21 of 1.1, times g) and one VEL rounding a step. */
static void test_thrust_model_without_accelerometer(void **state)
{
    (void)state;
    fixture f;
    fixture_init(&f);
    f.in.accel_ok = false;
    f.in.vz_ok = false;
    f.accel_mps2 = fc_vec3_make(F(0, ACCEL), F(0, ACCEL), F(0, ACCEL)); /* not looked at */
    f.in.thrust_n = F(1.1 * WEIGHT_N / 0.9, FORCE);
    f.in.tilt_cos = F(0.9, RATIO);
    const double ratio = D(f.in.thrust_n, FORCE) * D(f.in.tilt_cos, RATIO) / D(f.p.hover_thrust_n, FORCE);
    const double a = f.g * (ratio - 1.0);
    for (int k = 0; k < STEPS_PER_S; k++) {
        step(&f);
        assert_true((f.status & FC_STEP_DEGRADED) != 0u);
    }
    TS_ASSERT_CLOSE(vz(&f), a, 1e-4 + ts_fixed_rel(f.g * 1.1, 21) + ts_tol(FC_VEL_FRAC, 512.0, 512.0, 1.0));

    fixture h;
    fixture_init(&h);
    h.in.accel_ok = false;
    h.in.vz_ok = false;
    h.in.thrust_n = h.p.hover_thrust_n;
    for (int k = 0; k < STEPS_PER_S; k++) {
        step(&h);
    }
    TS_ASSERT_CLOSE(vz(&h), 0.0, ts_tol(FC_VEL_FRAC, 512.0, 0.0, 0.0) + 1e-9);
}

/* The reported acceleration without an accelerometer: "the acceleration is
 * the thrust's against the hover thrust". After 1 s of a good accelerometer
 * reading +2 m/s^2, the IMU is lost with the thrust at the hover thrust
 * (model: a = 0): 1 s later (20 low-pass time constants of 50 ms) the
 * reported accel_z_mps2 must be the model's 0 within 0.01 m/s^2, not the
 * last accelerometer value held. The land detector's "still" reads it.
 * */
static void test_reported_accel_follows_thrust_model(void **state)
{
    (void)state;
    fixture f;
    fixture_init(&f);
    f.in.vz_ok = false;
    set_level_accel(&f, 2.0);
    for (int k = 0; k < STEPS_PER_S; k++) {
        step(&f);
    }
    TS_ASSERT_CLOSE(ts_val(f.out.accel_z_mps2, FC_ACCEL_FRAC), level_accel_held(&f), 1e-3);
    f.in.accel_ok = false;
    f.in.thrust_n = f.p.hover_thrust_n;
    for (int k = 0; k < STEPS_PER_S; k++) {
        step(&f);
    }
    const double reported = ts_val(f.out.accel_z_mps2, FC_ACCEL_FRAC);
    if (fabs(reported) > 0.01) {
        fail_msg("with accel_ok false the reported accel_z_mps2 stays at the last "
                 "accelerometer value (%g m/s^2) instead of the thrust model's acceleration (0): a stale value fed "
                 "to the land detector",
                 reported);
    }
}

/* ---- parameters ---------------------------------------------------------- */

/* Each documented bound: a value beyond it is refused, and the step then
 * says NOT_READY. */
static void test_params_rejected(void **state)
{
    (void)state;
    fixture f;
    fixture_init(&f);
    fc_vertical_estimator_params bad[18];
    size_t n = 0;
    for (size_t i = 0; i < 18; i++) {
        bad[i] = f.p;
    }
    bad[n++].dt_s = F(0, DT);
    bad[n++].dt_s = F(0.11, DT);
    bad[n++].gravity_mps2 = F(0, ACCEL);
    bad[n++].gravity_mps2 = F(101, ACCEL);
    bad[n++].speed_crossover_radps = F(0, RATIO);
    bad[n++].speed_crossover_radps = F(10.5, RATIO);
    bad[n++].height_crossover_radps = F(-1, RATIO);
    bad[n++].accel_bias_limit_mps2 = F(5.5, ACCEL);
    bad[n++].accel_tau_s = F(DT_S / 2, DT);
    bad[n++].accel_tau_s = F(1.1, DT);
    bad[n++].hover_tau_s = F(0.05, TIME);
    bad[n++].hover_tau_s = F(101, TIME);
    bad[n++].bias_average_tau_s = F(0.05, TIME);
    bad[n++].bias_average_tau_s = F(101, TIME);
    bad[n++].hover_min_n = F(0, FORCE);
    bad[n++].hover_thrust_n = F(2.0 * WEIGHT_N, FORCE); /* above hover_max */
    bad[n++].range_period_max_s = F(0, DT);
    bad[n++].range_period_max_s = F(1.1, DT);
    for (size_t i = 0; i < n; i++) {
        fc_vertical_estimator v;
        if (fc_vertical_estimator_init(&v, &bad[i]) != FC_INIT_BAD_PARAM) {
            fail_msg("bad parameter set %zu accepted", i);
        }
        fc_vertical_estimate out;
        assert_int_equal(fc_vertical_estimator_step(&v, &f.in, &out), FC_STEP_NOT_READY);
    }
#if !FC_NUMERIC_FIXED
    fc_vertical_estimator_params p = f.p;
    p.hover_tau_s = NAN;
    fc_vertical_estimator v;
    assert_int_equal(fc_vertical_estimator_init(&v, &p), FC_INIT_BAD_PARAM);
    p = f.p;
    p.bias_average_tau_s = NAN;
    assert_int_equal(fc_vertical_estimator_init(&v, &p), FC_INIT_BAD_PARAM);
#endif
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bias_converges_with_speed_input),
        cmocka_unit_test(test_tilted_specific_force_projected),
        cmocka_unit_test(test_speed_propagates_without_speed_input),
        cmocka_unit_test(test_learnt_bias_removed_in_dead_reckoning),
        cmocka_unit_test(test_dead_reckoning_flies_on_averaged_bias),
        cmocka_unit_test(test_averaged_bias_filters_ripple),
        cmocka_unit_test(test_range_corrects_gear_height),
        cmocka_unit_test(test_range_corrects_speed_without_speed_input),
        cmocka_unit_test(test_range_gap_bounded),
        cmocka_unit_test(test_gear_height_zero_until_first_sample),
        cmocka_unit_test(test_hover_thrust_converges),
        cmocka_unit_test(test_hover_thrust_bounded),
        cmocka_unit_test(test_hover_thrust_learns_only_when_allowed),
        cmocka_unit_test(test_reset_keeps_hover_thrust),
        cmocka_unit_test(test_thrust_model_without_accelerometer),
        cmocka_unit_test(test_reported_accel_follows_thrust_model),
        cmocka_unit_test(test_params_rejected),
    };
    return cmocka_run_group_tests_name(FC_NUMERIC_FIXED ? "vertical_estimator (fixed)" : "vertical_estimator (float)",
                                       tests, NULL, NULL);
}
