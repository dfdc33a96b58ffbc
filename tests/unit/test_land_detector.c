/*
 * Tests of the staged land detector (fc/land_detector.h), both backends.
 *
 * dt = 1/512 s. The documented default times (0.35 s of contact, 0.3 s to
 * maybe landed, 0.3 s more to landed) are not multiples of dt, and their
 * quantisation in TIME (Q16, 1.5e-5 s) or float is far smaller than the
 * distance to the nearest step (>= 0.2 dt), so the stage is reached at the
 * first step whose accumulated evidence time k dt reaches the documented
 * time: k = ceil(T / dt). Counting convention (from the header: each stage
 * needs its evidence "held for a time"): the contact timer counts the steps
 * that were still and pushing down; the low-thrust timer counts the steps in
 * contact with low thrust, the step GROUND_CONTACT is reached included.
 */
#include <string.h>

#include "test_support.h"

#include "fc/land_detector.h"

#define F(x, KIND) fc_from_float((float)(x), FC_##KIND##_FRAC)
#define D(x, KIND) ((double)fc_to_float((x), FC_##KIND##_FRAC))

#define DT_S (1.0 / 512.0)
#define STEPS_PER_S 512
#define HOVER_N 14.7
/* the documented defaults */
#define CONTACT_S 0.35
#define MAYBE_LANDED_S 0.3
#define LANDED_S 0.3

static int steps_for(double t_s) { return (int)ceil(t_s / DT_S); }

typedef struct fixture {
    fc_land_detector d;
    fc_land_detector_params p;
    fc_land_detector_input in;
} fixture;

/* On the ground: still, asked to descend, the thrust ramped down to 0.2 x
 * hover (under both ratios), no range finder. */
static void fixture_init(fixture *f)
{
    memset(f, 0, sizeof *f);
    fc_land_detector_default_params(&f->p, F(DT_S, DT));
    assert_int_equal(fc_land_detector_init(&f->d, &f->p), FC_INIT_OK);
    f->in.vz_mps = F(0, VEL);
    f->in.accel_z_mps2 = F(0, ACCEL);
    f->in.vertical_thrust_n = F(0.2 * HOVER_N, FORCE);
    f->in.hover_thrust_n = F(HOVER_N, FORCE);
    f->in.descending = true;
    f->in.gear_height_m = F(0, LENGTH);
    f->in.gear_height_age_s = F(0, TIME);
    f->in.gear_height_known = false;
}

static fc_land_state step(fixture *f)
{
    const fc_land_state s = fc_land_detector_step(&f->d, &f->in);
    assert_int_equal(s, f->d.state);
    return s;
}

/* Steps until `state` (at most max_steps); returns the number of steps taken,
 * or max_steps + 1 if it was not reached. */
static int steps_until(fixture *f, fc_land_state state, int max_steps)
{
    for (int k = 1; k <= max_steps; k++) {
        if (step(f) == state) {
            return k;
        }
    }
    return max_steps + 1;
}

static const int k_contact_steps_doc = 180;       /* ceil(0.35 x 512) = ceil(179.2) */
static const int k_maybe_steps_doc = 154;         /* ceil(0.3 x 512) = ceil(153.6) */
static const int k_landed_steps_doc = 308;        /* ceil(0.6 x 512) = ceil(307.2) */

/* The stages in order, each at its documented time, from the first step of
 * evidence: GROUND_CONTACT after ceil(0.35/dt) = 180 steps still and pushing
 * down; MAYBE_LANDED after ceil(0.3/dt) = 154 steps of low thrust counted
 * from that step (so at step 180 + 154 - 1); LANDED after ceil(0.6/dt) = 308
 * of them. The state never goes back while the evidence holds. */
static void test_stages_in_order_at_documented_times(void **state)
{
    (void)state;
    assert_int_equal(steps_for(CONTACT_S), k_contact_steps_doc);
    assert_int_equal(steps_for(MAYBE_LANDED_S), k_maybe_steps_doc);
    assert_int_equal(steps_for(MAYBE_LANDED_S + LANDED_S), k_landed_steps_doc);
    fixture f;
    fixture_init(&f);
    int first[FC_LAND_STATE_COUNT] = {0, 0, 0, 0};
    fc_land_state previous = FC_LAND_AIRBORNE;
    for (int k = 1; k <= 2 * STEPS_PER_S; k++) {
        const fc_land_state s = step(&f);
        assert_true(s == previous || s == previous + 1); /* in order, one stage at a time */
        if (s != previous) {
            first[s] = k;
        }
        previous = s;
    }
    assert_int_equal(previous, FC_LAND_LANDED);
    assert_int_equal(first[FC_LAND_GROUND_CONTACT], k_contact_steps_doc);
    assert_int_equal(first[FC_LAND_MAYBE_LANDED], k_contact_steps_doc + k_maybe_steps_doc - 1);
    assert_int_equal(first[FC_LAND_LANDED], k_contact_steps_doc + k_landed_steps_doc - 1);
}

/* Pushing down without low thrust (0.5 x hover: under the contact ratio 0.9,
 * over the landed ratio 0.3) reaches GROUND_CONTACT and stays there: MAYBE_LANDED
 * and LANDED need low thrust as well. */
static void test_contact_without_low_thrust_stays_in_contact(void **state)
{
    (void)state;
    fixture f;
    fixture_init(&f);
    f.in.vertical_thrust_n = F(0.5 * HOVER_N, FORCE);
    assert_int_equal(steps_until(&f, FC_LAND_GROUND_CONTACT, 1000), k_contact_steps_doc);
    for (int k = 0; k < 10 * STEPS_PER_S; k++) {
        assert_int_equal(step(&f), FC_LAND_GROUND_CONTACT);
    }
}

/* Never past AIRBORNE while the caller is not asking to descend (10 s still,
 * low thrust), nor while the thrust is not under the contact ratio (0.95 x
 * hover: pushing down is the evidence that something holds the vehicle). */
static void test_never_landed_while_not_descending(void **state)
{
    (void)state;
    for (int which = 0; which < 2; which++) {
        fixture f;
        fixture_init(&f);
        if (which == 0) {
            f.in.descending = false;
        } else {
            f.in.vertical_thrust_n = F(0.95 * HOVER_N, FORCE);
        }
        for (int k = 0; k < 10 * STEPS_PER_S; k++) {
            assert_int_equal(step(&f), FC_LAND_AIRBORNE);
        }
    }
}

typedef enum sign_of_flight {
    FLIGHT_MOTION,       /* |vz| 0.15 >= still 0.1 m/s, and |a_z| 0.6 > held 0.5 m/s^2 (a speed
                          * alone, with no acceleration while pushed down, is the ground holding
                          * the vehicle: test_held_despite_a_drifting_speed) */
    FLIGHT_ACCEL,        /* |a_z| 1.5 >= still 1 m/s^2 */
    FLIGHT_RANGE,        /* a fresh range sample putting the gear 0.06 > 0.05 m up */
    FLIGHT_COUNT
} sign_of_flight;

static void show_sign(fixture *f, sign_of_flight sign, bool on)
{
    f->in.vz_mps = F(on && sign == FLIGHT_MOTION ? -0.15 : 0.0, VEL);
    f->in.accel_z_mps2 = F(on && sign == FLIGHT_ACCEL ? 1.5 : on && sign == FLIGHT_MOTION ? -0.6 : 0.0, ACCEL);
    f->in.gear_height_known = true;
    f->in.gear_height_m = F(on && sign == FLIGHT_RANGE ? 0.06 : 0.0, LENGTH);
    f->in.gear_height_age_s = F(0.1, TIME);
}

/* Any sign of flight for one step, from GROUND_CONTACT and from MAYBE_LANDED,
 * puts the detector back to AIRBORNE at once, and the timers start over: the
 * next GROUND_CONTACT again takes the full 180 steps. */
static void test_airborne_at_once_on_any_sign_of_flight(void **state)
{
    (void)state;
    static const char *names[FLIGHT_COUNT] = {"motion", "acceleration", "range"};
    for (int sign = 0; sign < FLIGHT_COUNT; sign++) {
        for (int stage = FC_LAND_GROUND_CONTACT; stage <= FC_LAND_MAYBE_LANDED; stage++) {
            fixture f;
            fixture_init(&f);
            show_sign(&f, (sign_of_flight)sign, false);
            assert_true(steps_until(&f, (fc_land_state)stage, 1000) <= 1000);
            show_sign(&f, (sign_of_flight)sign, true);
            if (step(&f) != FC_LAND_AIRBORNE) {
                fail_msg("%s: stage %d not left at once", names[sign], stage);
            }
            show_sign(&f, (sign_of_flight)sign, false);
            assert_int_equal(steps_until(&f, FC_LAND_GROUND_CONTACT, 1000), k_contact_steps_doc);
        }
    }
}

/* Held by the ground (header): with no speed input and no range finder the
 * dead-reckoned speed drifts on the ground; pushed down, with the
 * acceleration inside half the still band (0.4 < 0.5 m/s^2), a speed of
 * -0.3 m/s (three times the still speed) does not keep it airborne: the
 * stages come on time. With the acceleration just outside half the band
 * (0.6 m/s^2) and the same speed, it stays AIRBORNE. */
static void test_held_despite_a_drifting_speed(void **state)
{
    (void)state;
    fixture f;
    fixture_init(&f);
    f.in.vz_mps = F(-0.3, VEL);
    f.in.accel_z_mps2 = F(0.4, ACCEL);
    assert_int_equal(steps_until(&f, FC_LAND_GROUND_CONTACT, 1000), k_contact_steps_doc);
    fixture_init(&f);
    f.in.vz_mps = F(-0.3, VEL);
    f.in.accel_z_mps2 = F(0.6, ACCEL);
    for (int k = 0; k < 1000; k++) {
        assert_int_equal(step(&f), FC_LAND_AIRBORNE);
    }
}

/* Just inside "still" (0.09 m/s, 0.9 m/s^2) and a fresh gear height of 4 cm
 * (under 5 cm) or a stale one of 3 m (age 0.31 s > 0.3 s): no sign of
 * flight, the vehicle lands on time. A vehicle without a range finder is
 * judged on the rest. */
static void test_evidence_just_inside_lands(void **state)
{
    (void)state;
    for (int which = 0; which < 3; which++) {
        fixture f;
        fixture_init(&f);
        f.in.vz_mps = F(-0.09, VEL);
        f.in.accel_z_mps2 = F(0.9, ACCEL);
        f.in.gear_height_known = which != 2;
        f.in.gear_height_m = F(which == 0 ? 0.04 : 3.0, LENGTH);
        f.in.gear_height_age_s = F(which == 0 ? 0.0 : 0.31, TIME);
        assert_int_equal(steps_until(&f, FC_LAND_LANDED, 1000), k_contact_steps_doc + k_landed_steps_doc - 1);
    }
}

/* The range rule on its own: fresh (age <= 0.3 s) and above 5 cm. */
static void test_range_says_airborne(void **state)
{
    (void)state;
    fixture f;
    fixture_init(&f);
    f.in.gear_height_known = true;
    f.in.gear_height_m = F(0.06, LENGTH);
    f.in.gear_height_age_s = F(0.29, TIME);
    assert_true(fc_land_detector_range_says_airborne(&f.d, &f.in));
    f.in.gear_height_age_s = F(0.31, TIME);
    assert_false(fc_land_detector_range_says_airborne(&f.d, &f.in));
    f.in.gear_height_age_s = F(0, TIME);
    f.in.gear_height_m = F(0.04, LENGTH);
    assert_false(fc_land_detector_range_says_airborne(&f.d, &f.in));
    f.in.gear_height_m = F(3, LENGTH);
    f.in.gear_height_known = false;
    assert_false(fc_land_detector_range_says_airborne(&f.d, &f.in));
}

/* LANDED is latched: motion, acceleration, full thrust and a fresh range
 * sample at 1 m change nothing for 5 s; reset() goes back to AIRBORNE and
 * the stages take their full times again. */
static void test_landed_latched_until_reset(void **state)
{
    (void)state;
    fixture f;
    fixture_init(&f);
    const fc_land_detector_input ground = f.in;
    assert_true(steps_until(&f, FC_LAND_LANDED, 1000) <= 1000);
    f.in.vz_mps = F(2, VEL);
    f.in.accel_z_mps2 = F(5, ACCEL);
    f.in.vertical_thrust_n = F(2 * HOVER_N, FORCE);
    f.in.descending = false;
    f.in.gear_height_known = true;
    f.in.gear_height_m = F(1, LENGTH);
    for (int k = 0; k < 5 * STEPS_PER_S; k++) {
        assert_int_equal(step(&f), FC_LAND_LANDED);
    }
    fc_land_detector_reset(&f.d);
    assert_int_equal(f.d.state, FC_LAND_AIRBORNE);
    f.in = ground;
    assert_int_equal(steps_until(&f, FC_LAND_LANDED, 1000), k_contact_steps_doc + k_landed_steps_doc - 1);
}

/* contact_s = 0 is a documented value ([0, 10]): "no hysteresis on contact".
 * It must not drop the evidence itself: a vehicle descending at 2 m/s with a
 * fresh range sample putting it 3 m up, its thrust low (a free fall), must
 * stay AIRBORNE. */
static void test_zero_contact_time_keeps_evidence(void **state)
{
    (void)state;
    fixture f;
    fixture_init(&f);
    fc_land_detector_params p = f.p;
    p.contact_s = F(0, TIME);
    assert_int_equal(fc_land_detector_init(&f.d, &p), FC_INIT_OK);
    f.in.vz_mps = F(-2, VEL);
    f.in.gear_height_known = true;
    f.in.gear_height_m = F(3, LENGTH);
    f.in.gear_height_age_s = F(0, TIME);
    for (int k = 1; k <= 2 * STEPS_PER_S; k++) {
        const fc_land_state s = step(&f);
        if (s != FC_LAND_AIRBORNE) {
            fail_msg("contact_s = 0: state %d at step %d while moving at 2 m/s with a "
                     "fresh range sample at 3 m",
                     (int)s, k);
        }
    }
}

/* maybe_landed_s = landed_s = 0 (documented [0, 10]): MAYBE_LANDED and
 * LANDED still need low thrust. In contact with 0.5 x hover (over the landed
 * ratio 0.3), the detector must stay in GROUND_CONTACT (a timer at 0 is not
 * evidence, even against a time of 0). */
static void test_zero_landed_times_still_need_low_thrust(void **state)
{
    (void)state;
    fixture f;
    fixture_init(&f);
    fc_land_detector_params p = f.p;
    p.maybe_landed_s = F(0, TIME);
    p.landed_s = F(0, TIME);
    assert_int_equal(fc_land_detector_init(&f.d, &p), FC_INIT_OK);
    f.in.vertical_thrust_n = F(0.5 * HOVER_N, FORCE);
    for (int k = 1; k <= 2 * STEPS_PER_S; k++) {
        const fc_land_state s = step(&f);
        if (s == FC_LAND_MAYBE_LANDED || s == FC_LAND_LANDED) {
            fail_msg("maybe_landed_s = landed_s = 0: state %d at step %d with the thrust "
                     "at 0.5 x hover (not low)",
                     (int)s, k);
        }
    }
}

/* Each documented bound: beyond it refused; a refused detector says AIRBORNE. */
static void test_params_rejected(void **state)
{
    (void)state;
    fixture f;
    fixture_init(&f);
    fc_land_detector_params bad[14];
    for (size_t i = 0; i < 14; i++) {
        bad[i] = f.p;
    }
    size_t n = 0;
    bad[n++].dt_s = F(0, DT);
    bad[n++].dt_s = F(0.11, DT);
    bad[n++].still_speed_mps = F(0, VEL);
    bad[n++].still_speed_mps = F(2.1, VEL);
    bad[n++].still_accel_mps2 = F(5.1, ACCEL);
    bad[n++].contact_thrust_ratio = F(1.01, RATIO);
    bad[n++].landed_thrust_ratio = F(0.95, RATIO); /* above the contact ratio */
    bad[n++].landed_thrust_ratio = F(0, RATIO);
    bad[n++].contact_s = F(-0.1, TIME);
    bad[n++].maybe_landed_s = F(10.5, TIME);
    bad[n++].landed_s = F(10.5, TIME);
    bad[n++].airborne_gear_height_m = F(0, LENGTH);
    bad[n++].airborne_gear_height_m = F(1.1, LENGTH);
    bad[n++].range_fresh_s = F(0, TIME);
    for (size_t i = 0; i < n; i++) {
        fc_land_detector d;
        if (fc_land_detector_init(&d, &bad[i]) != FC_INIT_BAD_PARAM) {
            fail_msg("bad parameter set %zu accepted", i);
        }
        for (int k = 0; k < 2 * STEPS_PER_S; k++) {
            assert_int_equal(fc_land_detector_step(&d, &f.in), FC_LAND_AIRBORNE);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_stages_in_order_at_documented_times),
        cmocka_unit_test(test_contact_without_low_thrust_stays_in_contact),
        cmocka_unit_test(test_never_landed_while_not_descending),
        cmocka_unit_test(test_airborne_at_once_on_any_sign_of_flight),
        cmocka_unit_test(test_held_despite_a_drifting_speed),
        cmocka_unit_test(test_evidence_just_inside_lands),
        cmocka_unit_test(test_range_says_airborne),
        cmocka_unit_test(test_landed_latched_until_reset),
        cmocka_unit_test(test_zero_contact_time_keeps_evidence),
        cmocka_unit_test(test_zero_landed_times_still_need_low_thrust),
        cmocka_unit_test(test_params_rejected),
    };
    return cmocka_run_group_tests_name(FC_NUMERIC_FIXED ? "land_detector (fixed)" : "land_detector (float)", tests,
                                       NULL, NULL);
}
