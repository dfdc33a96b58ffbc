/*
 * Tests of the landing mission's state machine (fc/landing.h), both
 * backends, on synthetic inputs: the vehicle is put where the test says, so
 * each transition and each reason is checked on its own. The closed loop
 * (plant, sensors, faults) is the SIL's: sim_host/tests (sim.abort.*).
 */
#include <string.h>

#include "test_support.h"

#include "fc/controller.h"
#include "fc/landing.h"

#define DT_S 0.002

static fc_real len(double m) { return fc_from_float((float)m, FC_LENGTH_FRAC); }

typedef struct world {
    fc_landing lm;
    fc_landing_params p;
    fc_pad_motion_estimate pad;
    fc_landing_input in;
    fc_landing_output out;
    double z_m;          /* the vehicle's CG */
    double pad_z_m;      /* the pad's surface */
    double gear_m;
    bool follow;         /* the vehicle sits on its reference (a perfect altitude loop) */
    bool on_pad;         /* ... but not below the pad's surface */
    bool range_dead;     /* the range finder quiet */
} world;

static void world_init(world *w)
{
    memset(w, 0, sizeof *w);
    fc_controller_params cp;
    fc_controller_default_params(&cp, FC_AIRFRAME_HEXA_4KG, FC_ALT_VARIANT_SSC, fc_from_float((float)DT_S, FC_DT_FRAC));
    w->p = cp.landing;
    assert_int_equal(fc_landing_init(&w->lm, &w->p), FC_INIT_OK);
    w->gear_m = ts_val(w->p.gear_height_m, FC_LENGTH_FRAC);
    w->z_m = 3.0;
    w->pad_z_m = 0.0;
    w->follow = true;
    w->on_pad = true;
    /* a learnt, still pad */
    w->pad.learning = true;
    w->pad.confidence = FC_C(0.9f, UNIT);
    w->pad.accel_bound_mps2 = FC_C(0.1f, ACCEL);
    w->pad.mean_m = len(0.0);
    w->pad.now.z_m = len(0.0);
    w->in.request = FC_LANDING_REQUEST_LAND;
    w->in.horizontal_error_m = len(0.02);
    w->in.tilt_cos = FC_INT(1, RATIO);
    w->in.thrust_n = FC_INT(40, FORCE);
    w->in.pad = &w->pad;
}

/* One step: the range finder samples every 5 steps (100 Hz). */
static void step(world *w, long k)
{
    w->in.z_m = len(w->z_m);
    w->in.range_fresh = !w->range_dead && k % 5 == 0;
    w->in.gear_height_m = len(w->z_m - w->pad_z_m - w->gear_m);
    const fc_step_status st = fc_landing_step(&w->lm, &w->in, &w->out);
    assert_true((st & (FC_STEP_NOT_READY | FC_STEP_ARITH_SATURATED)) == 0u);
    if (w->follow && w->out.fly_reference) {
        w->z_m = ts_val(w->out.reference.z_m, FC_LENGTH_FRAC);
        if (w->on_pad && w->z_m < w->pad_z_m + w->gear_m) {
            w->z_m = w->pad_z_m + w->gear_m; /* held by the pad */
        }
    }
}

/* Steps until the state is `state` (at most max_steps); returns the step count. */
static long run_until(world *w, fc_landing_state state, long max_steps)
{
    for (long k = 0; k < max_steps; k++) {
        step(w, k);
        if (w->out.state == state) {
            return k;
        }
    }
    return -1;
}

static void test_full_landing(void **state)
{
    (void)state;
    static world w;
    world_init(&w);
    const fc_landing_state expected[] = {FC_LANDING_HOLD, FC_LANDING_OBSERVE, FC_LANDING_DESCEND,
                                         FC_LANDING_TOUCHDOWN, FC_LANDING_DISARM, FC_LANDING_LANDED};
    const fc_landing_reason reasons[] = {FC_REASON_COMMANDED, FC_REASON_HOLD_SETTLED, FC_REASON_PAD_LEARNT,
                                         FC_REASON_CONTACT, FC_REASON_CONTACT_CONFIRMED, FC_REASON_RAMP_DONE};
    bool window_before_contact = false;
    for (unsigned i = 0u; i < sizeof expected / sizeof expected[0]; i++) {
        long k = 0;
        for (; k < 60000; k++) {
            step(&w, k);
            if (w.out.state == FC_LANDING_DESCEND && w.out.touchdown_window) {
                window_before_contact = true;
            }
            if (w.out.state == expected[i]) {
                break;
            }
        }
        assert_true(k < 60000);
        assert_int_equal(w.out.reason, reasons[i]);
        if (expected[i] == FC_LANDING_OBSERVE) {
            /* settled at the hold point: the gear hold_height above the pad's mean */
            assert_true(fabs(w.z_m - w.gear_m - ts_val(w.p.hold_height_m, FC_LENGTH_FRAC)) <=
                        ts_val(w.p.hold_settle_m, FC_LENGTH_FRAC));
        }
    }
    assert_true(window_before_contact);
    assert_false(w.out.motors_on);
    assert_int_equal(w.out.aborts, 0);
}

/* The ramp: from the thrust at contact to zero over ramp_s, linearly. */
static void test_thrust_ramp(void **state)
{
    (void)state;
    static world w;
    world_init(&w);
    assert_true(run_until(&w, FC_LANDING_DISARM, 100000) >= 0);
    const double ramp_s = ts_val(w.p.ramp_s, FC_TIME_FRAC);
    double previous = 41.0;
    long k = 0;
    step(&w, 0);
    for (; w.out.state == FC_LANDING_DISARM && k < 100000; k++) {
        const double thrust = ts_val(w.out.ramp_thrust_n, FC_FORCE_FRAC);
        assert_false(w.out.fly_reference);
        assert_true(w.out.motors_on);
        assert_true(thrust <= previous + 1e-6);
        previous = thrust;
        step(&w, k + 1);
    }
    assert_true(fabs((double)k * DT_S - ramp_s) < 0.01);
    assert_int_equal(w.out.state, FC_LANDING_LANDED);
}

/* Pressing: the gear within contact height in the window puts the reference
 * where (3.6) ends (gear dip below the surface); 3 contact heights off, (3.6) again. */
static void test_press_at_contact(void **state)
{
    (void)state;
    static world w;
    world_init(&w);
    w.p.press_at_contact = true; /* the Crazyflie's; the hexa's default is off */
    assert_int_equal(fc_landing_init(&w.lm, &w.p), FC_INIT_OK);
    long k = 0;
    for (; k < 100000 && !(w.out.state == FC_LANDING_DESCEND && w.out.touchdown_window); k++) {
        step(&w, k);
    }
    assert_true(k < 100000);
    const double dip_m = ts_val(w.p.touchdown_dip_m, FC_LENGTH_FRAC);
    const double contact_m = ts_val(w.p.contact_height_m, FC_LENGTH_FRAC);
    const double pressed_z_m = w.pad_z_m + w.gear_m - dip_m;
    w.follow = false;
    w.z_m = w.pad_z_m + w.gear_m + 0.5 * contact_m; /* floating just above the surface */
    /* pressed from the first range sample that says so (one every 5 steps) */
    long j = 1;
    for (; j <= 5; j++) {
        step(&w, k + j);
    }
    assert_true(fabs(ts_val(w.out.reference.z_m, FC_LENGTH_FRAC) - pressed_z_m) < 1e-3);
    /* the press does not confirm itself: (3.6) is not yet dip / 2 under the vehicle */
    assert_int_equal(w.out.state, FC_LANDING_DESCEND);
    assert_true(fabs(ts_val(w.out.reference.vz_mps, FC_VEL_FRAC)) < 1e-3);
    /* lifted clear of the surface: back on (3.6), above the pressed level */
    w.z_m = w.pad_z_m + w.gear_m + 4.0 * contact_m;
    for (long i = 0; i < 10; i++) {
        step(&w, k + j + i);
    }
    assert_int_equal(w.out.state, FC_LANDING_DESCEND);
    assert_true(ts_val(w.out.reference.z_m, FC_LENGTH_FRAC) > pressed_z_m + 1e-3);
}

/* The hexa's default: no press, the reference stays on (3.6). */
static void test_no_press_by_default(void **state)
{
    (void)state;
    static world w;
    world_init(&w);
    assert_false(w.p.press_at_contact);
    long k = 0;
    for (; k < 100000 && !(w.out.state == FC_LANDING_DESCEND && w.out.touchdown_window); k++) {
        step(&w, k);
    }
    assert_true(k < 100000);
    const double pressed_z_m = w.pad_z_m + w.gear_m - ts_val(w.p.touchdown_dip_m, FC_LENGTH_FRAC);
    w.follow = false;
    w.z_m = w.pad_z_m + w.gear_m + 0.5 * ts_val(w.p.contact_height_m, FC_LENGTH_FRAC);
    for (long j = 1; j <= 5; j++) {
        step(&w, k + j);
    }
    assert_true(ts_val(w.out.reference.z_m, FC_LENGTH_FRAC) > pressed_z_m + 1e-3);
}

typedef void (*fault_fn)(world *w);
static void fault_hold(world *w) { w->in.request = FC_LANDING_REQUEST_HOLD; }
static void fault_horizontal(world *w) { w->in.horizontal_error_m = len(1.0); }
static void fault_tilt(world *w) { w->in.tilt_cos = FC_C(0.8f, RATIO); }
static void fault_confidence(world *w) { w->pad.confidence = FC_C(0.05f, UNIT); }
static void fault_pad_accel(world *w) { w->pad.accel_bound_mps2 = FC_INT(5, ACCEL); }
static void fault_range(world *w) { w->range_dead = true; }

/* Each abort cause in DESCEND: ABORT with its reason, the climb back, HOLD. */
static void test_abort_causes(void **state)
{
    (void)state;
    const struct {
        fault_fn fault;
        fc_landing_reason reason;
    } cases[] = {
        {fault_hold, FC_REASON_ABORT_COMMANDED},       {fault_horizontal, FC_REASON_ABORT_HORIZONTAL},
        {fault_tilt, FC_REASON_ABORT_TILT},            {fault_confidence, FC_REASON_ABORT_CONFIDENCE},
        {fault_pad_accel, FC_REASON_ABORT_PAD_ACCEL},  {fault_range, FC_REASON_ABORT_RANGE_LOST},
    };
    for (unsigned c = 0u; c < sizeof cases / sizeof cases[0]; c++) {
        static world w;
        world_init(&w);
        assert_true(run_until(&w, FC_LANDING_DESCEND, 100000) >= 0);
        const double start_z = w.z_m;
        for (long k = 0; k < 100; k++) {
            step(&w, k);
        }
        assert_true(w.z_m < start_z); /* descending */
        cases[c].fault(&w);
        const long took = run_until(&w, FC_LANDING_ABORT, 1000);
        assert_true(took >= 0);
        assert_int_equal(w.out.reason, cases[c].reason);
        assert_true(w.out.changed);
        assert_int_equal(w.out.aborts, 1);
        /* the fault cleared: back to HOLD at the hold point, then it lands after all */
        w.in.request = FC_LANDING_REQUEST_LAND;
        w.in.horizontal_error_m = len(0.02);
        w.in.tilt_cos = FC_INT(1, RATIO);
        w.pad.confidence = FC_C(0.9f, UNIT);
        w.pad.accel_bound_mps2 = FC_C(0.1f, ACCEL);
        w.range_dead = false;
        assert_true(run_until(&w, FC_LANDING_HOLD, 20000) >= 0);
        assert_int_equal(w.out.reason, FC_REASON_ABORT_CLIMB_DONE);
        assert_true(run_until(&w, FC_LANDING_LANDED, 100000) >= 0);
    }
}

/* A descent does not start while anything is out of bounds. */
static void test_descent_gated(void **state)
{
    (void)state;
    static world w;
    world_init(&w);
    w.pad.confidence = FC_C(0.3f, UNIT);
    assert_true(run_until(&w, FC_LANDING_OBSERVE, 100000) >= 0);
    assert_int_equal(run_until(&w, FC_LANDING_DESCEND, 5000), -1);
    w.pad.confidence = FC_C(0.9f, UNIT);
    w.in.horizontal_error_m = len(0.3); /* above the start limit, below the abort limit */
    assert_int_equal(run_until(&w, FC_LANDING_DESCEND, 5000), -1);
    w.in.horizontal_error_m = len(0.05);
    w.in.request = FC_LANDING_REQUEST_HOLD;
    assert_int_equal(run_until(&w, FC_LANDING_DESCEND, 5000), -1);
    w.in.request = FC_LANDING_REQUEST_LAND;
    assert_true(run_until(&w, FC_LANDING_DESCEND, 5000) >= 0);
}

/* After abort_retries_max + 1 aborts the mission holds. */
static void test_retries_exhausted(void **state)
{
    (void)state;
    static world w;
    world_init(&w);
    const unsigned allowed = w.p.abort_retries_max + 1u;
    for (unsigned a = 0u; a < allowed; a++) {
        assert_true(run_until(&w, FC_LANDING_DESCEND, 100000) >= 0);
        w.in.tilt_cos = FC_C(0.5f, RATIO);
        assert_true(run_until(&w, FC_LANDING_ABORT, 100) >= 0);
        w.in.tilt_cos = FC_INT(1, RATIO);
    }
    assert_true(run_until(&w, FC_LANDING_HOLD, 20000) >= 0);
    assert_int_equal(w.out.reason, FC_REASON_RETRIES_EXHAUSTED);
    assert_int_equal(run_until(&w, FC_LANDING_DESCEND, 20000), -1);
}

/* The request withdrawn: IDLE, motors off, the reference not flown. */
static void test_request_none_is_idle(void **state)
{
    (void)state;
    static world w;
    world_init(&w);
    assert_true(run_until(&w, FC_LANDING_OBSERVE, 100000) >= 0);
    w.in.request = FC_LANDING_REQUEST_NONE;
    step(&w, 0);
    assert_int_equal(w.out.state, FC_LANDING_IDLE);
    assert_false(w.out.fly_reference);
    assert_false(w.out.motors_on);
}

static void test_params_rejected(void **state)
{
    (void)state;
    static world w;
    world_init(&w);
    fc_landing lm;
    fc_landing_params p = w.p;
    p.confidence_abort = FC_C(0.9f, UNIT); /* above the start threshold */
    assert_int_equal(fc_landing_init(&lm, &p), FC_INIT_BAD_PARAM);
    p = w.p;
    p.horizontal_abort_m = len(0.01);
    assert_int_equal(fc_landing_init(&lm, &p), FC_INIT_BAD_PARAM);
    p = w.p;
    p.ramp_s = FC_INT(0, TIME);
    assert_int_equal(fc_landing_init(&lm, &p), FC_INIT_BAD_PARAM);
    fc_landing_output out;
    assert_int_equal(fc_landing_step(&lm, &w.in, &out), FC_STEP_NOT_READY);
    assert_false(out.motors_on);
}

/* The shaped descent (descent_shaping, (2.25)-(2.28)) on a level pad: the
 * same course to LANDED, the window before the contact. */
static void test_shaped_full_landing(void **state)
{
    (void)state;
    static world w;
    world_init(&w);
    w.p.descent_shaping = true;
    assert_int_equal(fc_landing_init(&w.lm, &w.p), FC_INIT_OK);
    w.in.pad_attitude = fc_quat_identity();
    w.in.offset_x_m = len(0.02);
    w.in.offset_y_m = len(-0.01);
    bool window_before_contact = false;
    bool shaped = false;
    long k = 0;
    for (; k < 100000 && w.out.state != FC_LANDING_LANDED; k++) {
        step(&w, k);
        if (w.out.state == FC_LANDING_DESCEND && w.out.touchdown_window) {
            window_before_contact = true;
        }
        shaped = shaped || (w.out.state == FC_LANDING_DESCEND && w.out.shaping_mps < FC_INT(0, VEL));
    }
    assert_int_equal(w.out.state, FC_LANDING_LANDED);
    assert_true(window_before_contact);
    assert_true(shaped);
    assert_int_equal(w.out.aborts, 0);
}

/* (2.28): a pad tilted 40 deg under a centred vehicle holds the shaped
 * descent (no lower than where it started); level again, it goes on down. */
static void test_shaped_descent_holds_on_tilted_pad(void **state)
{
    (void)state;
    static world w;
    world_init(&w);
    w.p.descent_shaping = true;
    assert_int_equal(fc_landing_init(&w.lm, &w.p), FC_INIT_OK);
    /* 40 deg about x: q = (cos 20 deg, sin 20 deg, 0, 0) */
    const fc_quat tilted = {FC_C(0.93969262f, UNIT), FC_C(0.34202014f, UNIT), FC_INT(0, UNIT), FC_INT(0, UNIT)};
    w.in.pad_attitude = tilted;
    assert_true(run_until(&w, FC_LANDING_DESCEND, 100000) >= 0);
    const double start_m = w.z_m;
    for (long k = 0; k < 1500; k++) { /* 3 s */
        step(&w, k);
        assert_int_equal(w.out.state, FC_LANDING_DESCEND);
    }
    assert_true(w.out.shaping_mps > FC_INT(0, VEL)); /* the field climbs ... */
    assert_true(w.z_m >= start_m - 0.02);            /* ... capped where the descent started */
    w.in.pad_attitude = fc_quat_identity();
    for (long k = 0; k < 1500; k++) {
        step(&w, k);
    }
    assert_true(w.z_m < start_m - 0.3);
}

/* The shaped descent's own parameters are checked only when it is on. */
static void test_shaped_params_rejected(void **state)
{
    (void)state;
    static world w;
    world_init(&w);
    fc_landing lm;
    fc_landing_params p = w.p;
    p.shaping_commit_m = len(2.0);
    assert_int_equal(fc_landing_init(&lm, &p), FC_INIT_OK);
    p.descent_shaping = true;
    assert_int_equal(fc_landing_init(&lm, &p), FC_INIT_BAD_PARAM);
    p = w.p;
    p.descent_shaping = true;
    p.shaping.delta_a_m = FC_INT(0, LENGTH);
    assert_int_equal(fc_landing_init(&lm, &p), FC_INIT_BAD_PARAM);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_full_landing),      cmocka_unit_test(test_thrust_ramp),
        cmocka_unit_test(test_abort_causes),      cmocka_unit_test(test_descent_gated),
        cmocka_unit_test(test_retries_exhausted), cmocka_unit_test(test_request_none_is_idle),
        cmocka_unit_test(test_params_rejected),   cmocka_unit_test(test_press_at_contact),
        cmocka_unit_test(test_no_press_by_default), cmocka_unit_test(test_shaped_full_landing),
        cmocka_unit_test(test_shaped_descent_holds_on_tilted_pad), cmocka_unit_test(test_shaped_params_rejected),
    };
    return cmocka_run_group_tests_name(FC_NUMERIC_FIXED ? "landing (fixed)" : "landing (float)", tests, NULL, NULL);
}
