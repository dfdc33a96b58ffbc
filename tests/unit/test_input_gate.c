/*
 * Tests of the plausibility gates and the command rate limits
 * (fc/input_gate.h), both backends.
 *
 * The step is dt = 1/512 s (about the Crazyflie's 500 Hz): it and every
 * multiple of it used here are exact in DT (Q30), TIME (Q16) and float, so
 * the counts of steps below are the header's times divided by dt with no
 * rounding to argue about. The limits are the Crazyflie's (controller_params:
 * top speed 5 m/s, position noise 0.1 m) with an acceleration of 20 m/s^2.
 * Each gate is checked on both sides: a sample inside its slack by a few per
 * cent passes, a glitch outside it (still inside the numeric input range) is
 * rejected, so a gate that rejects everything fails as surely as one that
 * rejects nothing.
 */
#include <string.h>

#include "test_support.h"

#include "fc/input_gate.h"

#define F(x, KIND) fc_from_float((float)(x), FC_##KIND##_FRAC)
#define D(x, KIND) ((double)fc_to_float((x), FC_##KIND##_FRAC))

#define DT_S (1.0 / 512.0)
#define STEPS_PER_S 512
#define SPEED_MAX 5.0
#define ACCEL_MAX 20.0
#define POSITION_JUMP 0.1
/* the defaults of fc_input_gate_default_params */
#define VELOCITY_JUMP 0.5
#define SETPOINT_SPEED 2.0
#define YAW_RATE 2.0
#define PAD_SPEED 3.0
#define PAD_ACCEL 10.0
#define PAD_JERK 50.0
#define REANCHOR_S 1.0
/* a yaw rate that is no command: NaN in float, beyond the 100 rad/s accepted in fixed */
#if FC_NUMERIC_FIXED
#define NAN_OR_BEYOND_RATE 120.0
#else
#define NAN_OR_BEYOND_RATE NAN
#endif

typedef struct fixture {
    fc_input_gate g;
    fc_input_gate_params p;
    fc_gated_inputs in;   /* the sample of the next step */
    fc_gated_inputs out;
} fixture;

/* fc_input_gate_step on a sample held as fc_gated_inputs. */
static bool gate_step(fc_input_gate *g, const fc_gated_inputs *s, bool use_pad, bool limit_commands,
                      fc_gated_inputs *out)
{
    const fc_input_gate_input in = {&s->position_m,         &s->velocity_mps,     &s->pad,
                                    &s->position_setpoint_m, s->yaw_setpoint_rad, s->yaw_rate_setpoint_radps};
    return fc_input_gate_step(g, &in, use_pad, limit_commands, out);
}

/* A vehicle at (1, 2, 3) m moving at (0.5, 0, -0.2) m/s over a pad at 0.5 m
 * (0.2 m/s, 0.5 m/s^2), its setpoint where it is, yaw 0. */
static void fixture_init(fixture *f)
{
    memset(f, 0, sizeof *f);
    fc_input_gate_default_params(&f->p, F(DT_S, DT), F(SPEED_MAX, VEL), F(ACCEL_MAX, ACCEL), F(POSITION_JUMP, LENGTH));
    assert_int_equal(fc_input_gate_init(&f->g, &f->p), FC_INIT_OK);
    f->in.position_m = fc_vec3_make(F(1, LENGTH), F(2, LENGTH), F(3, LENGTH));
    f->in.velocity_mps = fc_vec3_make(F(0.5, VEL), F(0, VEL), F(-0.2, VEL));
    f->in.pad.z_m = F(0.5, LENGTH);
    f->in.pad.vz_mps = F(0.2, VEL);
    f->in.pad.az_mps2 = F(0.5, ACCEL);
    f->in.position_setpoint_m = f->in.position_m;
    f->in.yaw_setpoint_rad = F(0, ANGLE);
}

static bool step(fixture *f, bool use_pad, bool limit_commands)
{
    return gate_step(&f->g, &f->in, use_pad, limit_commands, &f->out);
}

static void assert_vec3_eq(fc_vec3 a, fc_vec3 b)
{
    TS_ASSERT_REAL_EQ(a.x, b.x);
    TS_ASSERT_REAL_EQ(a.y, b.y);
    TS_ASSERT_REAL_EQ(a.z, b.z);
}

/* The measurements of out are exactly those of s (the pad's z when the pad
 * is used; its speed and acceleration too when the commands are not limited:
 * pad_ff). Without use_pad the pad is not looked at. */
static void assert_measurements_are(const fc_gated_inputs *out, const fc_gated_inputs *s, bool pad_ff)
{
    assert_vec3_eq(out->position_m, s->position_m);
    assert_vec3_eq(out->velocity_mps, s->velocity_mps);
    if (pad_ff) {
        TS_ASSERT_REAL_EQ(out->pad.z_m, s->pad.z_m);
        TS_ASSERT_REAL_EQ(out->pad.vz_mps, s->pad.vz_mps);
        TS_ASSERT_REAL_EQ(out->pad.az_mps2, s->pad.az_mps2);
    }
}

/* ---- the gates ----------------------------------------------------------- */

typedef enum gate_kind {
    GATE_SPEED,          /* |v| <= speed_max */
    GATE_VELOCITY_JUMP,  /* |v - v_last| <= accel_max t + velocity_jump */
    GATE_POSITION_JUMP,  /* |p - p_last| <= speed_max t + position_jump */
    GATE_PAD_SPEED,      /* |z_d'| <= pad_speed_max */
    GATE_PAD_ACCEL,      /* |z_d''| <= pad_accel_max */
    GATE_PAD_JUMP,       /* |z_d - z_d,last| <= pad_speed_max t + position_jump */
} gate_kind;

/* The sample s with the quantity of gate `kind` put `over` its limit (t = dt
 * after the last accepted sample): over = 0.97 is inside it, 1.03 outside. */
static fc_gated_inputs probe(const fc_gated_inputs *s, gate_kind kind, double over)
{
    fc_gated_inputs x = *s;
    switch (kind) {
    case GATE_SPEED:
        x.velocity_mps.y = F(over * SPEED_MAX, VEL);
        break;
    case GATE_VELOCITY_JUMP: /* slack 20/512 + 0.5 = 0.539 m/s, under the top speed */
        x.velocity_mps.z = F(D(s->velocity_mps.z, VEL) + over * (ACCEL_MAX * DT_S + VELOCITY_JUMP), VEL);
        break;
    case GATE_POSITION_JUMP: /* slack 5/512 + 0.1 = 0.110 m */
        x.position_m.y = F(D(s->position_m.y, LENGTH) - over * (SPEED_MAX * DT_S + POSITION_JUMP), LENGTH);
        break;
    case GATE_PAD_SPEED:
        x.pad.vz_mps = F(-over * PAD_SPEED, VEL);
        break;
    case GATE_PAD_ACCEL:
        x.pad.az_mps2 = F(over * PAD_ACCEL, ACCEL);
        break;
    case GATE_PAD_JUMP: /* slack 3/512 + 0.1 = 0.106 m */
        x.pad.z_m = F(D(s->pad.z_m, LENGTH) + over * (PAD_SPEED * DT_S + POSITION_JUMP), LENGTH);
        break;
    }
    return x;
}

/* Each gate: a sample 3 % inside its slack is accepted; a glitch 3 % outside
 * it, one step later, is rejected and the last accepted sample is flown on;
 * the good sample after the glitch is accepted again (its slack is counted
 * from the last accepted sample, 2 dt earlier, so it is larger still). */
static void check_gate(gate_kind kind, const char *name)
{
    fixture f;
    fixture_init(&f);
    if (kind == GATE_SPEED) {
        /* start near the top speed, so that only the speed gate is probed */
        f.in.velocity_mps.y = F(0.97 * SPEED_MAX, VEL);
    }
    assert_true(step(&f, true, false)); /* the first sample: the reference */
    const fc_gated_inputs good = f.in;

    f.in = probe(&good, kind, 0.97);
    if (!step(&f, true, false)) {
        fail_msg("%s: a sample 3 %% inside the gate was rejected", name);
    }
    assert_measurements_are(&f.out, &f.in, true);
    const fc_gated_inputs accepted = f.in;

    f.in = probe(&accepted, kind, 1.03);
    if (step(&f, true, false)) {
        fail_msg("%s: a glitch 3 %% outside the gate was accepted", name);
    }
    assert_measurements_are(&f.out, &accepted, true);

    f.in = accepted;
    if (!step(&f, true, false)) {
        fail_msg("%s: the good sample after the glitch was rejected", name);
    }
    assert_measurements_are(&f.out, &accepted, true);
}

static void test_speed_gate(void **state)
{
    (void)state;
    check_gate(GATE_SPEED, "speed");
}

static void test_velocity_jump_gate(void **state)
{
    (void)state;
    check_gate(GATE_VELOCITY_JUMP, "velocity jump");
}

static void test_position_jump_gate(void **state)
{
    (void)state;
    check_gate(GATE_POSITION_JUMP, "position jump");
}

static void test_pad_speed_gate(void **state)
{
    (void)state;
    check_gate(GATE_PAD_SPEED, "pad speed");
}

static void test_pad_accel_gate(void **state)
{
    (void)state;
    check_gate(GATE_PAD_ACCEL, "pad acceleration");
}

static void test_pad_jump_gate(void **state)
{
    (void)state;
    check_gate(GATE_PAD_JUMP, "pad jump");
}

/* The issue's glitches, each inside the numeric input range (500 m/s,
 * 500 m/s^2, 2000 m): vz = -100 m/s, pad az = +400 m/s^2, z - 100 m. Each is
 * rejected with the last accepted sample kept; the pad's only with use_pad
 * (without it the pad is not looked at). */
static void test_issue_glitches_rejected(void **state)
{
    (void)state;
    for (int which = 0; which < 3; which++) {
        fixture f;
        fixture_init(&f);
        assert_true(step(&f, true, true));
        const fc_gated_inputs good = f.in;
        if (which == 0) {
            f.in.velocity_mps.z = F(-100, VEL);
        } else if (which == 1) {
            f.in.pad.az_mps2 = F(400, ACCEL);
        } else {
            f.in.position_m.z = F(D(good.position_m.z, LENGTH) - 100.0, LENGTH);
        }
        assert_false(step(&f, true, true));
        assert_measurements_are(&f.out, &good, true);
        if (which == 1) {
            assert_true(step(&f, false, true)); /* the pad ignored without use_pad */
        }
    }
}

/* A vehicle flying at 4.5 m/s (90 % of its top speed) along x for 2 s, its
 * position integrated exactly: every good sample is accepted, and a position
 * glitch of 0.5 m every 50 steps is rejected each time with the last good
 * sample flown on. */
static void test_moving_vehicle_passes_glitches_do_not(void **state)
{
    (void)state;
    fixture f;
    fixture_init(&f);
    const double speed = 4.5;
    f.in.velocity_mps = fc_vec3_make(F(speed, VEL), F(0, VEL), F(0, VEL));
    int rejected_good = 0, accepted_glitches = 0;
    for (int k = 0; k < 2 * STEPS_PER_S; k++) {
        const double x = 1.0 + speed * DT_S * k;
        f.in.position_m.x = F(x, LENGTH);
        const fc_gated_inputs last = f.out;
        const bool glitch = k > 0 && k % 50 == 0;
        if (glitch) {
            f.in.position_m.x = F(x + 0.5, LENGTH);
        }
        const bool accepted = step(&f, false, false);
        if (glitch) {
            accepted_glitches += accepted ? 1 : 0;
            assert_vec3_eq(f.out.position_m, last.position_m);
        } else {
            rejected_good += accepted ? 0 : 1;
        }
    }
    assert_int_equal(rejected_good, 0);
    assert_int_equal(accepted_glitches, 0);
}

/* The slack grows with the time since the last accepted sample: after 100
 * steps of an implausible velocity (6 m/s), the vehicle is 4 m/s x 101 dt =
 * 0.79 m further, beyond position_jump but within 5 m/s x 101 dt + 0.1 =
 * 1.09 m: accepted. */
static void test_slack_grows_with_time_since_accepted(void **state)
{
    (void)state;
    fixture f;
    fixture_init(&f);
    f.in.velocity_mps = fc_vec3_make(F(4, VEL), F(0, VEL), F(0, VEL));
    assert_true(step(&f, false, false));
    const fc_gated_inputs good = f.in;
    f.in.velocity_mps.x = F(6, VEL);
    for (int k = 0; k < 100; k++) {
        assert_false(step(&f, false, false));
    }
    f.in = good;
    f.in.position_m.x = F(D(good.position_m.x, LENGTH) + 4.0 * 101 * DT_S, LENGTH);
    assert_true(step(&f, false, false));
    assert_measurements_are(&f.out, &f.in, false);
}

/* Re-anchoring: the position frame moves by 10 m and stays there. With
 * dt = 1/512 s, reanchor_s = 1 s is 512 steps: the checks see rejected_s =
 * (k - 1) dt at the k-th rejection, so rejections 1..512 keep the old sample,
 * the 513th makes the new one the reference (out is it, still reported
 * rejected), and the next consistent sample is accepted. A sample that fails
 * an absolute check (speed) never becomes the reference, however long. */
static void test_reanchor_after_reanchor_s(void **state)
{
    (void)state;
    fixture f;
    fixture_init(&f);
    assert_true(step(&f, false, false));
    const fc_gated_inputs old = f.in;
    f.in.position_m.x = F(D(old.position_m.x, LENGTH) + 10.0, LENGTH);
    const fc_gated_inputs moved = f.in;
    for (int k = 1; k <= (int)(REANCHOR_S * STEPS_PER_S); k++) {
        if (step(&f, false, false)) {
            fail_msg("rejection %d of a 10 m jump accepted", k);
        }
        assert_measurements_are(&f.out, &old, false);
    }
    assert_false(step(&f, false, false)); /* the re-anchoring step */
    assert_measurements_are(&f.out, &moved, false);
    assert_true(step(&f, false, false));
    assert_measurements_are(&f.out, &moved, false);

    /* an implausible speed for 3 s: never the reference */
    f.in.velocity_mps.x = F(6, VEL);
    const fc_gated_inputs kept = f.out;
    for (int k = 0; k < 3 * STEPS_PER_S; k++) {
        assert_false(step(&f, false, false));
        assert_measurements_are(&f.out, &kept, false);
    }
    /* ... but the first plausible sample after them re-anchors at once (the
     * rejections in a row already exceed reanchor_s) */
    f.in = moved;
    f.in.position_m.y = F(D(moved.position_m.y, LENGTH) + 20.0, LENGTH);
    const fc_gated_inputs far = f.in;
    assert_false(step(&f, false, false));
    assert_measurements_are(&f.out, &far, false);
    assert_true(step(&f, false, false));
}

/* reset() forgets the reference: a sample 10 m away is accepted next. */
static void test_reset_forgets_reference(void **state)
{
    (void)state;
    fixture f;
    fixture_init(&f);
    assert_true(step(&f, false, false));
    fc_input_gate_reset(&f.g);
    f.in.position_m.z = F(D(f.in.position_m.z, LENGTH) + 10.0, LENGTH);
    assert_true(step(&f, false, false));
    assert_measurements_are(&f.out, &f.in, false);
}

/* The pad's jump is checked against the last accepted *pad* sample. When the
 * pad starts being used (use_pad false -> true, e.g. TRACK_PAD commanded in
 * flight) there is no such sample: a pad at rest 1 m up must be accepted
 * (absolute checks only), not compared with a pad never accepted (the zeros
 * of init). */
static void test_pad_first_used_not_checked_against_nothing(void **state)
{
    (void)state;
    fixture f;
    fixture_init(&f);
    f.in.pad.z_m = F(1.0, LENGTH);
    f.in.pad.vz_mps = F(0, VEL);
    f.in.pad.az_mps2 = F(0, ACCEL);
    for (int k = 0; k < 10; k++) {
        assert_true(step(&f, false, true)); /* flying without the pad */
    }
    if (!step(&f, true, true)) {
        fail_msg("the first pad sample after use_pad turns on is rejected: its jump is "
                 "checked against a pad sample never accepted (1 m from 0, slack 0.106 m); the rejections last "
                 "reanchor_s = 1 s, past the failsafe's 0.5 s hold");
    }
    TS_ASSERT_REAL_EQ(f.out.pad.z_m, f.in.pad.z_m);
}

/* ---- the command limits -------------------------------------------------- */

/* The first sample's commands pass unchanged, however far; with
 * limit_commands false, every sample's do (setpoint, yaw, pad z', z''). */
static void test_commands_unchanged_first_and_when_off(void **state)
{
    (void)state;
    fixture f;
    fixture_init(&f);
    f.in.position_setpoint_m = fc_vec3_make(F(100, LENGTH), F(-50, LENGTH), F(20, LENGTH));
    f.in.yaw_setpoint_rad = F(3.0, ANGLE);
    assert_true(step(&f, true, true));
    assert_vec3_eq(f.out.position_setpoint_m, f.in.position_setpoint_m);
    TS_ASSERT_REAL_EQ(f.out.yaw_setpoint_rad, f.in.yaw_setpoint_rad);
    assert_measurements_are(&f.out, &f.in, true);

    f.in.position_setpoint_m = fc_vec3_make(F(-100, LENGTH), F(50, LENGTH), F(0, LENGTH));
    f.in.yaw_setpoint_rad = F(-1.0, ANGLE);
    f.in.pad.vz_mps = F(2.5, VEL);
    f.in.pad.az_mps2 = F(-9, ACCEL);
    assert_true(step(&f, true, false));
    assert_vec3_eq(f.out.position_setpoint_m, f.in.position_setpoint_m);
    TS_ASSERT_REAL_EQ(f.out.yaw_setpoint_rad, f.in.yaw_setpoint_rad);
    assert_measurements_are(&f.out, &f.in, true);
}

/* A step of the position command: each axis moves setpoint_speed dt =
 * 2/512 m a step towards it (exact in LENGTH and in float), and stops on it:
 * x 10 m away takes 2560 steps, z 1 mm away one. */
static void test_setpoint_rate_limit(void **state)
{
    (void)state;
    fixture f;
    fixture_init(&f);
    f.in.position_setpoint_m = fc_vec3_zero();
    assert_true(step(&f, false, true));
    f.in.position_setpoint_m = fc_vec3_make(F(10, LENGTH), F(-10, LENGTH), F(0.001, LENGTH));
    const double step_m = SETPOINT_SPEED * DT_S;
    const double tol = ts_tol(FC_LENGTH_FRAC, 0.5, 2.0, 10.0);
    for (int k = 1; k <= 2600; k++) {
        assert_true(step(&f, false, true));
        const double expected = fmin(k * step_m, 10.0);
        TS_ASSERT_CLOSE(ts_val(f.out.position_setpoint_m.x, FC_LENGTH_FRAC), expected, tol);
        TS_ASSERT_CLOSE(ts_val(f.out.position_setpoint_m.y, FC_LENGTH_FRAC), -expected, tol);
        TS_ASSERT_REAL_EQ(f.out.position_setpoint_m.z, f.in.position_setpoint_m.z);
    }
}

/* The yaw setpoint turns at most yaw_rate_max dt = 2/512 rad a step, the
 * short way round: from 3.0 to -3.0 rad is +0.283 rad through +-pi (73
 * steps), not -6.0 rad through 0; and back the other way. Every output is in
 * [-pi, pi]. Tolerance: the gate's pi and 2 pi are folded through a float
 * (FC_C), 23 and 46 LSB of ANGLE off; 64 LSB in fixed, 8 ulps of pi in float. */
static void check_yaw_turn(double from, double to, double direction)
{
    fixture f;
    fixture_init(&f);
    f.in.yaw_setpoint_rad = F(from, ANGLE);
    assert_true(step(&f, false, true));
    f.in.yaw_setpoint_rad = F(to, ANGLE);
    const double step_rad = YAW_RATE * DT_S;
    const double from_q = D(F(from, ANGLE), ANGLE), to_q = D(F(to, ANGLE), ANGLE);
    const double turn = remainder(to_q - from_q, 2.0 * TS_PI); /* the short way */
    assert_true(turn * direction > 0.0);
    const int steps = (int)ceil(fabs(turn) / step_rad);
    const double tol = ts_tol(FC_ANGLE_FRAC, 64.0, 8.0, TS_PI);
    for (int k = 1; k <= steps + 5; k++) {
        assert_true(step(&f, false, true));
        const double yaw = ts_val(f.out.yaw_setpoint_rad, FC_ANGLE_FRAC);
        assert_true(fabs(yaw) <= TS_PI + tol);
        const double expected = k < steps ? remainder(from_q + direction * k * step_rad, 2.0 * TS_PI) : to_q;
        TS_ASSERT_CLOSE(remainder(yaw - expected, 2.0 * TS_PI), 0.0, tol);
    }
}

static void test_yaw_rate_limit_short_way(void **state)
{
    (void)state;
    check_yaw_turn(3.0, -3.0, +1.0);
    check_yaw_turn(-3.0, 3.0, -1.0);
    check_yaw_turn(0.0, 1.0, +1.0);
    check_yaw_turn(0.5, -0.5, -1.0);
}

/* The yaw setpoint's rate (fed forward by the controller) passes as it is
 * within yaw_rate_max and is clamped to it beyond; a rate beyond 100 rad/s
 * (or NaN) is no command: the sample is rejected and the last rate kept. */
static void test_yaw_rate_feedforward(void **state)
{
    (void)state;
    const double cases[][2] = {{0.0, 0.0}, {1.5, 1.5}, {-1.5, -1.5}, {5.0, YAW_RATE}, {-50.0, -YAW_RATE}};
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        fixture f;
        fixture_init(&f);
        f.in.yaw_rate_setpoint_radps = F(cases[k][0], RATE);
        assert_true(gate_step(&f.g, &f.in, true, true, &f.out));
        assert_true(fabs(D(f.out.yaw_rate_setpoint_radps, RATE) - cases[k][1]) < 1e-6);
    }
    fixture f;
    fixture_init(&f);
    f.in.yaw_rate_setpoint_radps = F(1.0, RATE);
    assert_true(gate_step(&f.g, &f.in, true, true, &f.out));
    f.in.yaw_rate_setpoint_radps = F(NAN_OR_BEYOND_RATE, RATE);
    assert_false(gate_step(&f.g, &f.in, true, true, &f.out));
    assert_true(fabs(D(f.out.yaw_rate_setpoint_radps, RATE) - 1.0) < 1e-6);
}

/* The pad's feed-forward: z_d' moves at most pad_accel_max dt = 10/512 m/s
 * and z_d'' at most pad_jerk_max dt = 50/512 m/s^2 a step towards the sample
 * (z_d passes unchanged). Tolerance: one rounding of the product and of the
 * sum a step in fixed (k LSB after k steps), a few ulps in float. */
static void test_pad_feedforward_rate_limits(void **state)
{
    (void)state;
    fixture f;
    fixture_init(&f);
    f.in.pad.vz_mps = F(0, VEL);
    f.in.pad.az_mps2 = F(0, ACCEL);
    assert_true(step(&f, true, true));
    f.in.pad.vz_mps = F(2.5, VEL);
    f.in.pad.az_mps2 = F(-9, ACCEL);
    for (int k = 1; k <= 200; k++) {
        assert_true(step(&f, true, true));
        const double vz = fmin(k * PAD_ACCEL * DT_S, 2.5);
        const double az = fmax(-k * PAD_JERK * DT_S, -9.0);
        TS_ASSERT_CLOSE(ts_val(f.out.pad.vz_mps, FC_VEL_FRAC), vz, ts_tol(FC_VEL_FRAC, k, 2.0 * k, 2.5));
        TS_ASSERT_CLOSE(ts_val(f.out.pad.az_mps2, FC_ACCEL_FRAC), az, ts_tol(FC_ACCEL_FRAC, k, 2.0 * k, 9.0));
        TS_ASSERT_REAL_EQ(f.out.pad.z_m, f.in.pad.z_m);
    }
}

/* ---- parameters ---------------------------------------------------------- */

typedef struct param_field {
    const char *name;
    size_t offset;
    int frac;
    double max; /* the documented upper bound (accepted); the lower is 0 (rejected) */
} param_field;

#define FIELD(member, KIND, max) {#member, offsetof(fc_input_gate_params, member), FC_##KIND##_FRAC, max}

static void test_params_rejected(void **state)
{
    (void)state;
    static const param_field fields[] = {
        FIELD(dt_s, DT, 0.1),
        FIELD(speed_max_mps, VEL, 100.0),
        FIELD(accel_max_mps2, ACCEL, 200.0),
        FIELD(position_jump_m, LENGTH, 100.0),
        FIELD(velocity_jump_mps, VEL, 100.0),
        FIELD(setpoint_speed_mps, VEL, 100.0),
        FIELD(yaw_rate_max_radps, RATE, 100.0),
        FIELD(pad_speed_max_mps, VEL, 100.0),
        FIELD(pad_accel_max_mps2, ACCEL, 200.0),
        FIELD(pad_jerk_max_mps3, GAIN, 10000.0),
        FIELD(reanchor_s, TIME, 600.0),
    };
    fixture f;
    fixture_init(&f);
    for (size_t i = 0; i < sizeof fields / sizeof fields[0]; i++) {
        const double values[] = {fields[i].max, 0.0, -1.0, 1.05 * fields[i].max, (double)NAN};
        const fc_init_result expected[] = {FC_INIT_OK, FC_INIT_BAD_PARAM, FC_INIT_BAD_PARAM, FC_INIT_BAD_PARAM,
                                           FC_INIT_BAD_PARAM};
        const size_t count = FC_NUMERIC_FIXED ? 4u : 5u; /* no NaN in fixed */
        for (size_t j = 0; j < count; j++) {
            fc_input_gate_params p = f.p;
            *(fc_real *)(void *)((char *)&p + fields[i].offset) = fc_from_float((float)values[j], fields[i].frac);
            fc_input_gate g;
            if (fc_input_gate_init(&g, &p) != expected[j]) {
                fail_msg("%s = %g: init gave %d, expected %d", fields[i].name, values[j],
                         (int)fc_input_gate_init(&g, &p), (int)expected[j]);
            }
            if (expected[j] != FC_INIT_OK) {
                fc_gated_inputs out;
                assert_false(gate_step(&g, &f.in, true, true, &out)); /* not ready */
            }
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_speed_gate),
        cmocka_unit_test(test_velocity_jump_gate),
        cmocka_unit_test(test_position_jump_gate),
        cmocka_unit_test(test_pad_speed_gate),
        cmocka_unit_test(test_pad_accel_gate),
        cmocka_unit_test(test_pad_jump_gate),
        cmocka_unit_test(test_issue_glitches_rejected),
        cmocka_unit_test(test_moving_vehicle_passes_glitches_do_not),
        cmocka_unit_test(test_slack_grows_with_time_since_accepted),
        cmocka_unit_test(test_reanchor_after_reanchor_s),
        cmocka_unit_test(test_reset_forgets_reference),
        cmocka_unit_test(test_pad_first_used_not_checked_against_nothing),
        cmocka_unit_test(test_commands_unchanged_first_and_when_off),
        cmocka_unit_test(test_setpoint_rate_limit),
        cmocka_unit_test(test_yaw_rate_limit_short_way),
        cmocka_unit_test(test_yaw_rate_feedforward),
        cmocka_unit_test(test_pad_feedforward_rate_limits),
        cmocka_unit_test(test_params_rejected),
    };
    return cmocka_run_group_tests_name(FC_NUMERIC_FIXED ? "input_gate (fixed)" : "input_gate (float)", tests, NULL,
                                       NULL);
}
