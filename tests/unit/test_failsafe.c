/*
 * Tests of the input guard and the failsafe descent (fc/failsafe.h), both
 * backends.
 *
 * dt = 1/512 s: the step and its multiples are exact in DT, TIME (Q16) and
 * float, so the guard's times are counts of steps: a timer that must exceed
 * T (strictly, as the header's "longer than") fires at step floor(T/dt) + 1
 * (0.5 s: step 257; 50 ms = 25.6 dt: step 26, the quantisation of 0.05 in
 * Q16 being 1.5e-5 s, far from a step boundary).
 *
 * The descent is checked in a 1-D closed loop, m v' = T k_h - m g (level,
 * k_h = 1, the thrust held over the step), for the F450's nominal 1.5 kg
 * and a true mass of nominal +-20 %, with the defaults k_p = 2 /s,
 * k_i = k_p^2 / 4 = 1 /s^2, and the speed setpoint's ramp: v_sp starts at
 * the speed seen at the first fc_failsafe_step after entering and moves
 * s dt = 1/512 m/s a step (setpoint_accel s = 1 m/s^2) to -descent, which it
 * reaches after t1 = |v0 + descent| / s. With r = T_h / (m g) and the mass
 * error d = (r - 1) g, e = v_sp - v obeys
 *     e'' + r k_p e' + r k_i e = v_sp''
 * (v' = d + r a, a = k_p e + I, I' = k_i e): the ramp's start sets
 * e'(0) = -s - d from e(0) = 0, I = 0, and its end is an impulse s at t1,
 * so e is the free response from (0, -s - d) plus s times the free response
 * from (0, 1) started at t1.
 */
#include <string.h>

#include "test_support.h"

#include "fc/failsafe.h"
#include "fc/vertical_estimator.h"

#define F(x, KIND) fc_from_float((float)(x), FC_##KIND##_FRAC)
#define D(x, KIND) ((double)fc_to_float((x), FC_##KIND##_FRAC))

#define DT_S (1.0 / 512.0)
#define STEPS_PER_S 512
#define G 9.80665
#define MASS_NOMINAL 1.5
#define WEIGHT_N (MASS_NOMINAL * G)
#define KP 2.0
#define KI (KP * KP / 4.0)
#define HOLD_STEPS 257      /* 0.5 s / dt = 256, exceeded at 257 */
#define IMU_TIMEOUT_STEPS 26 /* 0.05 s / dt = 25.6 */
#define SETPOINT_ACCEL 1.0   /* s, the default setpoint_accel_mps2 */

static fc_failsafe_params default_params(double descent_mps)
{
    fc_failsafe_params p;
    fc_failsafe_default_params(&p, F(DT_S, DT), F(G, ACCEL), F(descent_mps, VEL));
    return p;
}

static void init_failsafe(fc_failsafe *f, double descent_mps)
{
    const fc_failsafe_params p = default_params(descent_mps);
    assert_int_equal(fc_failsafe_init(f, &p), FC_INIT_OK);
}

/* ---- the guard ----------------------------------------------------------- */

typedef struct guard {
    fc_failsafe f;
    fc_failsafe_watch_input in;
    fc_failsafe_watch_output out;
} guard;

static void guard_init(guard *g)
{
    memset(g, 0, sizeof *g);
    init_failsafe(&g->f, 0.5);
    g->in.armed = true;
    g->in.inputs_ok = true;
    g->in.had_good_inputs = true;
    g->in.imu_ok = true;
}

static void watch(guard *g) { g->out = fc_failsafe_watch(&g->f, &g->in); }

/* Steps of watch() until active; returns the count (or max + 1). */
static int steps_until_active(guard *g, int max_steps)
{
    for (int k = 1; k <= max_steps; k++) {
        watch(g);
        if (g->out.active) {
            return k;
        }
    }
    return max_steps + 1;
}

/* Inputs bad: HOLD (fly the last good ones) for bad_input_hold_s = 0.5 s,
 * i.e. 256 steps, then ACTIVE at step 257, entered once, cause INPUTS_LOST. */
static void test_hold_then_active_after_hold_time(void **state)
{
    (void)state;
    guard g;
    guard_init(&g);
    watch(&g);
    assert_false(g.out.active || g.out.hold);
    g.in.inputs_ok = false;
    for (int k = 1; k < HOLD_STEPS; k++) {
        watch(&g);
        if (g.out.active || !g.out.hold) {
            fail_msg("step %d of bad inputs: active %d hold %d (expected the hold)", k, g.out.active, g.out.hold);
        }
    }
    watch(&g);
    assert_true(g.out.active);
    assert_true(g.out.entered);
    assert_int_equal(g.out.cause, FC_FAILSAFE_INPUTS_LOST);
    watch(&g);
    assert_true(g.out.active);
    assert_false(g.out.entered);
}

/* The header's "hold: inputs bad, within the hold": once ACTIVE (beyond the
 * hold) the hold flag must be down, or a caller flies the last good inputs
 * during the failsafe.  */
static void test_hold_not_reported_once_active(void **state)
{
    (void)state;
    guard g;
    guard_init(&g);
    g.in.inputs_ok = false;
    assert_int_equal(steps_until_active(&g, 1000), HOLD_STEPS);
    if (g.out.hold) {
        fail_msg("watch() reports hold = true together with active = true beyond "
                 "bad_input_hold_s; the header says hold is 'inputs bad, within the hold'");
    }
}

/* Without good inputs ever (nothing to hold): ACTIVE at the first bad step,
 * and no hold. */
static void test_active_at_once_without_good_inputs(void **state)
{
    (void)state;
    guard g;
    guard_init(&g);
    g.in.had_good_inputs = false;
    g.in.inputs_ok = false;
    watch(&g);
    assert_true(g.out.active && g.out.entered);
    assert_false(g.out.hold);
    assert_int_equal(g.out.cause, FC_FAILSAFE_INPUTS_LOST);
}

/* A bad stretch shorter than the hold (256 steps) never activates, and the
 * next one starts the hold over (its timer was cleared by the good step). */
static void test_short_bad_stretch_restarts_hold(void **state)
{
    (void)state;
    guard g;
    guard_init(&g);
    for (int round = 0; round < 3; round++) {
        g.in.inputs_ok = false;
        for (int k = 1; k < HOLD_STEPS; k++) {
            watch(&g);
            assert_false(g.out.active);
        }
        g.in.inputs_ok = true;
        watch(&g);
        assert_false(g.out.active || g.out.hold);
    }
}

/* IMU unusable longer than imu_timeout_s = 50 ms: ACTIVE at step 26, cause
 * IMU_LOST, the other inputs good. A dropout of 25 steps does nothing and
 * the next one needs 26 steps again. */
static void test_imu_timeout(void **state)
{
    (void)state;
    guard g;
    guard_init(&g);
    g.in.imu_ok = false;
    for (int k = 1; k < IMU_TIMEOUT_STEPS; k++) {
        watch(&g);
        assert_false(g.out.active);
    }
    g.in.imu_ok = true;
    watch(&g);
    g.in.imu_ok = false;
    assert_int_equal(steps_until_active(&g, 1000), IMU_TIMEOUT_STEPS);
    assert_true(g.out.entered);
    assert_int_equal(g.out.cause, FC_FAILSAFE_IMU_LOST);
}

/* ACTIVE ends when every input has been good for the hold time again: 257
 * good steps (a bad IMU or input step in between starts the count over);
 * `left` is set at that step only, the cause cleared. */
static void test_leaves_after_good_inputs_for_hold(void **state)
{
    (void)state;
    guard g;
    guard_init(&g);
    g.in.inputs_ok = false;
    assert_int_equal(steps_until_active(&g, 1000), HOLD_STEPS);
    g.in.inputs_ok = true;
    for (int k = 1; k < 200; k++) {
        watch(&g);
        assert_true(g.out.active);
    }
    g.in.imu_ok = false; /* one bad IMU step: the count starts over */
    watch(&g);
    assert_true(g.out.active);
    g.in.imu_ok = true;
    for (int k = 1; k < HOLD_STEPS; k++) {
        watch(&g);
        if (!g.out.active) {
            fail_msg("left after %d good steps (expected %d)", k, HOLD_STEPS);
        }
        assert_false(g.out.left);
    }
    watch(&g);
    assert_false(g.out.active);
    assert_true(g.out.left);
    assert_int_equal(g.out.cause, FC_FAILSAFE_NONE);
    watch(&g);
    assert_false(g.out.left);
}

/* Disarmed: everything cleared at once; armed again with bad inputs, the
 * hold starts from zero (257 steps, not 1). */
static void test_reset_when_disarmed(void **state)
{
    (void)state;
    guard g;
    guard_init(&g);
    g.in.inputs_ok = false;
    assert_int_equal(steps_until_active(&g, 1000), HOLD_STEPS);
    g.in.armed = false;
    watch(&g);
    assert_false(g.out.active || g.out.hold || g.out.entered || g.out.left);
    assert_false(g.f.active);
    assert_int_equal(g.f.cause, FC_FAILSAFE_NONE);
    g.in.armed = true;
    assert_int_equal(steps_until_active(&g, 1000), HOLD_STEPS);
}

/* ---- the descent: closed loop -------------------------------------------- */

/* Bounds on |e(t)| and |e'(t)| for e'' + c1 e' + c0 e = 0, e(0) = e0,
 * e'(0) = de0: the sum of the modes' magnitudes (real poles), the
 * amplitude of the oscillation (complex), or the double pole's (|e0| + |b| t). */
static void mode_bounds(double c1, double c0, double e0, double de0, double t, double *env, double *denv)
{
    const double disc = c1 * c1 - 4.0 * c0;
    const double sigma = -0.5 * c1;
    if (fabs(disc) < 1e-6) {
        const double b = de0 - sigma * e0;
        *env = (fabs(e0) + fabs(b) * t) * exp(sigma * t);
        *denv = (fabs(b) + fabs(sigma) * (fabs(e0) + fabs(b) * t)) * exp(sigma * t);
    } else if (disc > 0.0) {
        const double s1 = sigma + 0.5 * sqrt(disc), s2 = sigma - 0.5 * sqrt(disc);
        const double b = (de0 - s1 * e0) / (s2 - s1), a = e0 - b;
        *env = fabs(a) * exp(s1 * t) + fabs(b) * exp(s2 * t);
        *denv = fabs(a * s1) * exp(s1 * t) + fabs(b * s2) * exp(s2 * t);
    } else {
        const double w = 0.5 * sqrt(-disc);
        const double amplitude = hypot(e0, (de0 - sigma * e0) / w);
        *env = amplitude * exp(sigma * t);
        *denv = amplitude * hypot(sigma, w) * exp(sigma * t);
    }
}

/* One failsafe step and one plant step: returns the body thrust. */
static double descent_step(fc_failsafe *f, double *v, double mass, double hover_n, double vz_seen)
{
    const fc_failsafe_input in = {F(vz_seen, VEL), F(hover_n, FORCE), FC_INT(1, RATIO), F(0, FORCE),
                                  F(2.5 * WEIGHT_N, FORCE), FC_LAND_AIRBORNE};
    const double thrust = ts_val(fc_failsafe_step(f, &in), FC_FORCE_FRAC);
    assert_true(f->ar.saturated == 0u);
    *v += (thrust / mass - G) * DT_S;
    return thrust;
}

/* The descent rate, T_h the nominal weight, true mass nominal x {0.8, 1, 1.2},
 * descent 0.3 (Crazyflie) and 0.5 m/s, from rest (v_sp from 0 to -descent in
 * t1 = descent / s = 0.3 or 0.5 s). The speed error (header) is bounded by
 * the envelope of the free response from (0, -s - d) plus s times that of
 * the free response from (0, 1) from t1 on (mode_bounds, each); the slowest
 * pole is -0.69 /s (r = 1.25), and neither the integral (|I| <= 1.97 < 3)
 * nor the acceleration (|a| <= 2.26 < 4) limits are reached, so the loop is
 * linear. Checked at every step: |v_sp(t) - v| <= envelope + 3 dt
 * |e'|-envelope (the Euler step's O(dt) error, 2 dt, and the setpoint's
 * one-step lead: it moves on the step itself, dt) + 1e-4 m/s
 * (quantisation); and what that implies: within +-25 % of descent from 6 s
 * on (the envelope is <= 22.1 % there: descent 0.3, m x 0.8, whose mass
 * error d = 2.45 m/s^2 dominates the start), within 1 % from 11 s on
 * (<= 0.70 %). After 30 s the integral holds the whole mass error,
 * I = g (1/r - 1), within 2e-3 m/s^2 (the transient is 1e-8 by then; the
 * floor is fixed's: the integral step k_i dt e rounds to 0 for
 * |e| < 0.5 x 512 VEL LSB = 6e-5 m/s, i.e. |I error| < k_p 6e-5). */
static void test_descent_rate_with_mass_error(void **state)
{
    (void)state;
    const double descents[] = {0.3, 0.5};
    const double mass_factors[] = {0.8, 1.0, 1.2};
    for (size_t i = 0; i < 2; i++) {
        for (size_t j = 0; j < 3; j++) {
            fc_failsafe f;
            init_failsafe(&f, descents[i]);
            const double descent = D(f.p.descent_mps, VEL), s = D(f.p.setpoint_accel_mps2, ACCEL);
            const double mass = MASS_NOMINAL * mass_factors[j];
            const double hover_n = D(F(WEIGHT_N, FORCE), FORCE);
            const double r = hover_n / (mass * G), d = (r - 1.0) * G;
            const double t1 = descent / s;
            double v = 0.0;
            ts_check envelope = ts_check_begin("descent speed error within its envelope");
            ts_check band25 = ts_check_begin("descent within +-25 % from 6 s");
            ts_check band1 = ts_check_begin("descent within +-1 % from 11 s");
            for (int k = 0; k < 30 * STEPS_PER_S; k++) {
                const double t = k * DT_S;
                const double e = -fmin(s * t, descent) - v; /* v_sp(t) - v */
                double env, denv;
                mode_bounds(r * KP, r * KI, 0.0, -s - d, t, &env, &denv);
                if (t >= t1) {
                    double env_end, denv_end;
                    mode_bounds(r * KP, r * KI, 0.0, 1.0, t - t1, &env_end, &denv_end);
                    env += s * env_end;
                    denv += s * denv_end;
                }
                (void)ts_close(&envelope, e, 0.0, env + 3.0 * DT_S * denv + 1e-4, "m x %.1f descent %.1f t %.3f",
                               mass_factors[j], descent, t);
                if (t >= 6.0) {
                    (void)ts_close(&band25, -v, descent, 0.25 * descent, "m x %.1f t %.3f", mass_factors[j], t);
                }
                if (t >= 11.0) {
                    (void)ts_close(&band1, -v, descent, 0.01 * descent, "m x %.1f t %.3f", mass_factors[j], t);
                }
                (void)descent_step(&f, &v, mass, hover_n, v);
            }
            ts_check_end(&envelope);
            ts_check_end(&band25);
            ts_check_end(&band1);
            TS_ASSERT_CLOSE(ts_val(f.integral_mps2, FC_ACCEL_FRAC), G * (1.0 / r - 1.0), 2e-3);
        }
    }
}

/* The setpoint ramp from a climb (header): entering the failsafe (watch:
 * inputs bad, none ever good) at v0 = +0.5 m/s, descent 0.5 m/s, the mass
 * nominal (T_h right, as once learnt). The setpoint starts at v0 and moves
 * s dt = 1/512 m/s a step: after the k-th step it is exactly
 * max(v0 - k s dt, -descent) (all exact in VEL and in float), -descent from
 * step |v0 + descent| / (s dt) = 512 on, i.e. after |v0 + descent| / s = 1 s.
 * Its rate -s is fed forward, so the first step asks
 * T_h (1 + ((k_p + k_i dt) (-s dt) - s) / g): the vehicle starts down at s.
 * With T_h right the loop then follows the ramp with the one step the
 * setpoint leads by, e = -s dt, and nothing for the integral to build:
 * per step e' = e - (k_p e + I) dt, so |e| stays under s dt while the ramp
 * runs and decays after it (double pole at -k_p / 2). Checked at every step:
 * |e| <= s dt + 1e-4 (the quantisation, as above), no overshoot of the
 * descent rate beyond that, and the rate within 1 % of descent from 2 s on
 * (s dt (1 + p t) e^(-p t), far under). Then the failsafe is left and
 * entered again while falling at 2 m/s: the setpoint starts anew at that
 * speed (-2 + s dt after the first step), not where it was. */
static void test_setpoint_ramp_from_climb(void **state)
{
    (void)state;
    guard g;
    guard_init(&g);
    fc_failsafe *f = &g.f;
    g.in.had_good_inputs = false;
    g.in.inputs_ok = false;
    watch(&g);
    assert_true(g.out.entered);
    const double descent = D(f->p.descent_mps, VEL), s = D(f->p.setpoint_accel_mps2, ACCEL);
    assert_true(s == SETPOINT_ACCEL);
    const double v0 = 0.5, p = 0.5 * KP, t1 = fabs(v0 + descent) / s;
    const int ramp_steps = (int)lround(t1 * STEPS_PER_S);
    assert_int_equal(ramp_steps, STEPS_PER_S);
    const double hover_n = D(F(WEIGHT_N, FORCE), FORCE);
    double v = v0;
    ts_check setpoint = ts_check_begin("setpoint on its ramp, exactly");
    ts_check loop = ts_check_begin("speed error within one step of the ramp");
    ts_check overshoot = ts_check_begin("no descent overshoot");
    ts_check band1 = ts_check_begin("descent within +-1 % from 2 s");
    const double tol = s * DT_S + 1e-4;
    (void)p;
    for (int k = 1; k <= 15 * STEPS_PER_S; k++) {
        const double t = (k - 1) * DT_S; /* the time of this step's speed */
        (void)ts_close(&loop, v0 - fmin(s * t, v0 + descent) - v, 0.0, tol, "t %.3f", t);
        (void)ts_close(&overshoot, fmax(-v - descent, 0.0), 0.0, tol, "t %.3f", t);
        if (t >= 2.0) {
            (void)ts_close(&band1, -v, descent, 0.01 * descent, "t %.3f", t);
        }
        const double thrust = descent_step(f, &v, MASS_NOMINAL, hover_n, v);
        const double expected_sp = fmax(v0 - k * s * DT_S, -descent);
        (void)ts_close(&setpoint, ts_val(f->speed_setpoint_mps, FC_VEL_FRAC), expected_sp, 0.0, "step %d", k);
        if (k == 1) {
            /* 1e-5 relative: the inputs' quantisation (FORCE, VEL) and the load factor in RATIO */
            TS_ASSERT_CLOSE(thrust, hover_n * (1.0 + ((KP + KI * DT_S) * (-s * DT_S) - s) / G), 1e-5 * hover_n);
        }
        if (k == ramp_steps) {
            TS_ASSERT_REAL_EQ(f->speed_setpoint_mps, -f->p.descent_mps);
        }
    }
    ts_check_end(&setpoint);
    ts_check_end(&loop);
    ts_check_end(&overshoot);
    ts_check_end(&band1);
    /* leave (good inputs for the hold) and enter again, falling at 2 m/s */
    g.in.inputs_ok = true;
    for (int k = 0; k < HOLD_STEPS; k++) {
        watch(&g);
    }
    assert_true(g.out.left);
    g.in.inputs_ok = false;
    watch(&g);
    assert_true(g.out.entered);
    (void)descent_step(f, &v, MASS_NOMINAL, hover_n, -2.0);
    TS_ASSERT_CLOSE(ts_val(f->speed_setpoint_mps, FC_VEL_FRAC), -2.0 + s * DT_S, 0.0);
}

/* The whole chain: the vertical estimator learns the hover thrust and the
 * accelerometer bias (+-0.2 m/s^2) over 30 s of hover with a good speed
 * input (the vehicle 20 % heavier or lighter than nominal); then the inputs
 * are lost and the failsafe descends 30 s on the estimator's dead-reckoned
 * speed (accelerometer less the learnt bias) and its learnt hover thrust.
 * Bound: T_h is learnt to m g (test_vertical_estimator: within 2e-3 N),
 * so r = 1 +- 1.4e-4 and, the setpoint ramping from rest for
 * t1 = descent / s, the speed error is s (t - t1) e^-(t - t1) - s t e^-t
 * (header; within the sum of the two, 11.3 % of descent 0.3 at 6 s and
 * 1.1e-3 m/s at 10 s); the speed seen drifts from the true one by the
 * averaged bias left (its floor, <= 3.1e-4 m/s^2 in fixed, and
 * 0.2 x 4 e^-15 = 2.4e-7 of the average's lag after 30 s: 9.3e-3 m/s over
 * 30 s) and 0.5 VEL LSB a step (3.7e-3 m/s over 15360 steps in fixed).
 * Checked: the true rate within +-25 % from 6 s and within 5 % (0.3 m/s:
 * 15 mm/s; 14.1 mm/s of it accounted for) from 10 s. */
static void test_descent_with_learnt_hover_and_accel_bias(void **state)
{
    (void)state;
    const double cases[][3] = {{1.2, 0.2, 0.3}, {0.8, -0.2, 0.3}, {1.2, -0.2, 0.5}, {0.8, 0.2, 0.5}};
    for (size_t c = 0; c < 4; c++) {
        const double mass = MASS_NOMINAL * cases[c][0], accel_bias = cases[c][1];
        fc_vertical_estimator_params vp;
        fc_vertical_estimator_default_params(&vp, F(DT_S, DT), F(G, ACCEL), F(WEIGHT_N, FORCE));
        fc_vertical_estimator est;
        assert_int_equal(fc_vertical_estimator_init(&est, &vp), FC_INIT_OK);
        fc_failsafe f;
        init_failsafe(&f, cases[c][2]);
        const double descent = D(f.p.descent_mps, VEL);
        fc_vertical_estimator_input vin;
        memset(&vin, 0, sizeof vin);
        const fc_quat level = fc_quat_identity();
        fc_vec3 accel_mps2 = fc_vec3_zero();
        vin.attitude = &level;
        vin.accel_mps2 = &accel_mps2;
        vin.accel_ok = true;
        vin.tilt_cos = FC_INT(1, RATIO);
        double v = 0.0, thrust = mass * G;
        fc_vertical_estimate ve;
        ts_check band25 = ts_check_begin("learnt-hover descent within +-25 % from 6 s");
        ts_check band5 = ts_check_begin("learnt-hover descent within +-5 % from 10 s");
        for (int k = 0; k < 60 * STEPS_PER_S; k++) {
            const bool hovering = k < 30 * STEPS_PER_S;
            /* the accelerometer reads the specific force of the thrust held over the last step */
            accel_mps2 = fc_vec3_make(F(0, ACCEL), F(0, ACCEL), F(thrust / mass + accel_bias, ACCEL));
            vin.vz_mps = F(v, VEL);
            vin.vz_ok = hovering;
            vin.thrust_n = F(thrust, FORCE);
            vin.learn_hover = hovering;
            (void)fc_vertical_estimator_step(&est, &vin, &ve);
            if (hovering) {
                continue; /* thrust m g, v = 0 */
            }
            const double t = (k - 30 * STEPS_PER_S) * DT_S;
            if (t >= 6.0) {
                (void)ts_close(&band25, -v, descent, 0.25 * descent, "case %zu t %.3f", c, t);
            }
            if (t >= 10.0) {
                (void)ts_close(&band5, -v, descent, 0.05 * descent, "case %zu t %.3f", c, t);
            }
            thrust = descent_step(&f, &v, mass, D(ve.hover_thrust_n, FORCE), D(ve.vz_mps, VEL));
        }
        ts_check_end(&band25);
        ts_check_end(&band5);
    }
}

/* The limits: a climb at 10 m/s held drives I to -3 and a to -4 m/s^2
 * (vertical thrust T_h (1 - 4/g)), and a fall at 10 m/s to +3 and +4
 * (T_h (1 + 4/g)); neither goes further in 10 s. The setpoint starts at the
 * speed seen and ramps at s = 1 m/s^2, so e = -+s t: I = k_i s t^2 / 2
 * reaches 3 at t = sqrt(6 / (k_i s)) = 2.45 s and |a| = k_p s t + I reaches
 * 4 at 1.46 s; at 10 s e = -+10 m/s (the climb's setpoint at 0, the fall's
 * at -0.5 after 9.5 s). Tolerance: the load factor in RATIO and the product
 * in FORCE, a few LSB. */
static void test_integral_and_accel_limits(void **state)
{
    (void)state;
    const double speeds[] = {10.0, -10.0};
    for (size_t i = 0; i < 2; i++) {
        fc_failsafe f;
        init_failsafe(&f, 0.5);
        const fc_failsafe_input in = {F(speeds[i], VEL), F(WEIGHT_N, FORCE), FC_INT(1, RATIO), F(0, FORCE),
                                      F(3 * WEIGHT_N, FORCE), FC_LAND_AIRBORNE};
        const double sign = speeds[i] > 0.0 ? -1.0 : 1.0;
        double thrust = 0.0;
        for (int k = 0; k < 10 * STEPS_PER_S; k++) {
            thrust = ts_val(fc_failsafe_step(&f, &in), FC_FORCE_FRAC);
            assert_true(fabs(ts_val(f.integral_mps2, FC_ACCEL_FRAC)) <= 3.0);
        }
        TS_ASSERT_REAL_EQ(f.integral_mps2, sign > 0.0 ? f.p.integral_limit_mps2 : -f.p.integral_limit_mps2);
        const double hover_n = D(in.hover_thrust_n, FORCE);
        TS_ASSERT_CLOSE(thrust, hover_n * (1.0 + sign * 4.0 / G), 1e-5 * hover_n);
    }
}

/* ---- the descent: in contact --------------------------------------------- */

static fc_failsafe_input contact_input(double vz_mps, fc_land_state land_state)
{
    const fc_failsafe_input in = {F(vz_mps, VEL), F(WEIGHT_N, FORCE), FC_INT(1, RATIO), F(0, FORCE),
                                  F(3 * WEIGHT_N, FORCE), land_state};
    return in;
}

/* Once in contact the thrust ramps down at T_h / ramp_s per second (1 s: T_h
 * / 512 a step) from where it was (here the hover thrust: descending at the
 * set rate with I > 0, the ramp starting from min(loop, T_h)), to 0 after
 * 512 steps, and stays there; the integral is held through contact (it had
 * been built over 1 s at 0.7 m/s down, the setpoint ramping from -0.7 to
 * -0.5 in its first 0.2 s, then 0.2 m/s too fast);
 * AIRBORNE again gives the speed loop's thrust back at once, and the next
 * contact ramps from it anew. Tolerance: k steps of one rounding of the
 * ramp step (0.5 FORCE LSB) in fixed, ulps of T_h in float. */
static void check_ramp(double ramp_s)
{
    fc_failsafe f;
    fc_failsafe_params p = default_params(0.5);
    p.ramp_s = F(ramp_s, TIME);
    if (fc_failsafe_init(&f, &p) != FC_INIT_OK) {
        fail_msg("ramp_s = %g s (documented (0, 10]) refused at init: "
                 "fc_convert(ramp_s, TIME -> DT) saturates for ramp_s >= 2 s (DT is Q30, range [-2, 2))",
                 ramp_s);
    }
    const double hover_n = D(F(WEIGHT_N, FORCE), FORCE);
    /* build an integral: 1 s at 0.7 m/s down (the setpoint at -0.5 from 0.2 s on) */
    fc_failsafe_input in = contact_input(-0.7, FC_LAND_AIRBORNE);
    for (int k = 0; k < STEPS_PER_S; k++) {
        (void)fc_failsafe_step(&f, &in);
    }
    const fc_real integral = f.integral_mps2;
    assert_true(integral > FC_INT(0, ACCEL));
    /* at the set rate, then contact: the vertical thrust is T_h (1 + I/g) > T_h, the ramp starts at T_h */
    in = contact_input(-0.5, FC_LAND_GROUND_CONTACT);
    const int ramp_steps = (int)lround(ramp_s * STEPS_PER_S);
    for (int k = 1; k <= ramp_steps + 100; k++) {
        in.land_state = k < ramp_steps / 2 ? FC_LAND_GROUND_CONTACT : FC_LAND_MAYBE_LANDED;
        const double thrust = ts_val(fc_failsafe_step(&f, &in), FC_FORCE_FRAC);
        const double expected = fmax(hover_n * (1.0 - (double)k / ramp_steps), 0.0);
        TS_ASSERT_CLOSE(thrust, expected, ts_tol(FC_FORCE_FRAC, 0.5 * k + 1.0, 2.0 * k, hover_n));
        TS_ASSERT_REAL_EQ(f.integral_mps2, integral);
    }
    /* a sign of flight: the loop's thrust at once */
    in.land_state = FC_LAND_AIRBORNE;
    const double loop_n = hover_n * (1.0 + ts_val(integral, FC_ACCEL_FRAC) / G);
    TS_ASSERT_CLOSE(ts_val(fc_failsafe_step(&f, &in), FC_FORCE_FRAC), loop_n, 1e-5 * hover_n);
    /* on the ground (v = 0): the loop asks less than T_h; the ramp starts from that */
    in = contact_input(0.0, FC_LAND_GROUND_CONTACT);
    const double asked = hover_n * (1.0 + (-KP * 0.5 + ts_val(f.integral_mps2, FC_ACCEL_FRAC)) / G);
    assert_true(asked < hover_n);
    TS_ASSERT_CLOSE(ts_val(fc_failsafe_step(&f, &in), FC_FORCE_FRAC), asked - hover_n / ramp_steps,
                    1e-5 * hover_n);
}

static void test_ramp_down_in_contact(void **state)
{
    (void)state;
    check_ramp(1.0);
}

/* A documented ramp time of 5 s ((0, 10]): accepted, and the ramp takes 5 s.
 * */
static void test_long_ramp_accepted(void **state)
{
    (void)state;
    check_ramp(5.0);
}

/* Body thrust = vertical / max(k_h, 0.5), inside [thrust_min, thrust_max].
 * A first step at the set rate (-0.5 m/s) starts the setpoint there, at
 * -descent (e = 0, I = 0); then at the second step: at the set rate the
 * vertical thrust is T_h; tilted to k_h = 0.8 the body thrust is T_h / 0.8;
 * at k_h = 0.3 it is T_h / 0.5 (not / 0.3); with thrust_max 1.5 T_h at
 * k_h = 0.5 it is clamped to 1.5 T_h; climbing at 10 m/s (e = -10.5, a = -4:
 * 0.59 T_h) under thrust_min 0.7 T_h, clamped to 0.7 T_h. */
static void test_body_thrust_tilt_and_limits(void **state)
{
    (void)state;
    const double hover_n = D(F(WEIGHT_N, FORCE), FORCE);
    const struct {
        double vz, tilt_cos, min_factor, max_factor, expected_factor;
    } cases[] = {
        {-0.5, 1.0, 0.0, 3.0, 1.0},       {-0.5, 0.8, 0.0, 3.0, 1.0 / 0.8}, {-0.5, 0.3, 0.0, 3.0, 2.0},
        {-0.5, 0.5, 0.0, 1.5, 1.5},       {10.0, 1.0, 0.7, 3.0, 0.7},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        fc_failsafe f;
        init_failsafe(&f, 0.5);
        fc_failsafe_input in = {F(-0.5, VEL),
                                F(hover_n, FORCE),
                                F(cases[i].tilt_cos, RATIO),
                                F(cases[i].min_factor * hover_n, FORCE),
                                F(cases[i].max_factor * hover_n, FORCE),
                                FC_LAND_AIRBORNE};
        (void)fc_failsafe_step(&f, &in);
        TS_ASSERT_REAL_EQ(f.speed_setpoint_mps, -f.p.descent_mps);
        TS_ASSERT_REAL_EQ(f.integral_mps2, FC_INT(0, ACCEL));
        in.vz_mps = F(cases[i].vz, VEL);
        const double thrust = ts_val(fc_failsafe_step(&f, &in), FC_FORCE_FRAC);
        /* 1e-5 relative: the inputs' quantisation (RATIO, FORCE) and one division */
        TS_ASSERT_CLOSE(thrust, cases[i].expected_factor * hover_n, 1e-5 * hover_n);
    }
}

/* ---- parameters ---------------------------------------------------------- */

static void test_params_rejected(void **state)
{
    (void)state;
    const fc_failsafe_params good = default_params(0.5);
    fc_failsafe_params bad[16];
    for (size_t i = 0; i < 16; i++) {
        bad[i] = good;
    }
    size_t n = 0;
    bad[n++].dt_s = F(0, DT);
    bad[n++].dt_s = F(0.11, DT);
    bad[n++].gravity_mps2 = F(0, ACCEL);
    bad[n++].bad_input_hold_s = F(-0.1, TIME);
    bad[n++].bad_input_hold_s = F(10.5, TIME);
    bad[n++].imu_timeout_s = F(10.5, TIME);
    bad[n++].descent_mps = F(0, VEL);
    bad[n++].descent_mps = F(5.5, VEL);
    bad[n++].speed_gain_per_s = F(0, GAIN);
    bad[n++].speed_gain_per_s = F(51, GAIN);
    bad[n++].integral_limit_mps2 = F(10.5, ACCEL);
    bad[n++].accel_limit_mps2 = F(0, ACCEL);
    bad[n++].ramp_s = F(0, TIME);
    bad[n++].setpoint_accel_mps2 = F(0, ACCEL);
    bad[n++].setpoint_accel_mps2 = F(-1, ACCEL);
    bad[n++].setpoint_accel_mps2 = F(10.5, ACCEL);
    for (size_t i = 0; i < n; i++) {
        fc_failsafe f;
        if (fc_failsafe_init(&f, &bad[i]) != FC_INIT_BAD_PARAM) {
            fail_msg("bad parameter set %zu accepted", i);
        }
        const fc_failsafe_input in = contact_input(-0.5, FC_LAND_AIRBORNE);
        TS_ASSERT_REAL_EQ(fc_failsafe_step(&f, &in), FC_INT(0, FORCE));
        const fc_failsafe_watch_input w = {true, false, false, false};
        assert_false(fc_failsafe_watch(&f, &w).active);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_hold_then_active_after_hold_time),
        cmocka_unit_test(test_hold_not_reported_once_active),
        cmocka_unit_test(test_active_at_once_without_good_inputs),
        cmocka_unit_test(test_short_bad_stretch_restarts_hold),
        cmocka_unit_test(test_imu_timeout),
        cmocka_unit_test(test_leaves_after_good_inputs_for_hold),
        cmocka_unit_test(test_reset_when_disarmed),
        cmocka_unit_test(test_descent_rate_with_mass_error),
        cmocka_unit_test(test_setpoint_ramp_from_climb),
        cmocka_unit_test(test_descent_with_learnt_hover_and_accel_bias),
        cmocka_unit_test(test_integral_and_accel_limits),
        cmocka_unit_test(test_ramp_down_in_contact),
        cmocka_unit_test(test_long_ramp_accepted),
        cmocka_unit_test(test_body_thrust_tilt_and_limits),
        cmocka_unit_test(test_params_rejected),
    };
    return cmocka_run_group_tests_name(FC_NUMERIC_FIXED ? "failsafe (fixed)" : "failsafe (float)", tests, NULL, NULL);
}
