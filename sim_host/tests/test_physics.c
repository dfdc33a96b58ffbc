/*
 * test_physics.c - the plant against closed-form physics (sim.physics.*).
 *
 * Each test builds a plant directly (no scenario file), runs it, and compares
 * with what mechanics says, with a stated tolerance:
 *   free_fall           z = z0 - g t^2 / 2, v = -g t (rotors off): 1e-9 m
 *   hover               sum of rotor thrusts = m g / k_g(h) at the hover speed; at rest after 5 s: 1e-9 m
 *   torque_free         world angular momentum and rotational energy conserved (1e-9 relative), |q| = 1
 *   ground_effect_gain  k_g(h) = 1/(1 - rho (R/4h)^2) above the floor, k_g_max below it, and the thrust follows
 *   rest_on_pad         a vehicle dropped on a still pad comes to rest at the static deflection m g / (n k)
 *   energy_no_control   free flight and a lossless bounce conserve mechanical energy
 *   mass_filter         m(t) = m1 + (m0 - m1) e^(-(t - ts)/tau) after a step (4.84)
 *   pad_derivatives     the pad's velocity and acceleration are the derivatives of its height
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "plant.h"

#define G 9.81
#define PI 3.14159265358979323846

/* A 4 kg hexa-X like seed-4.4's, rotors off, no ground effect, no contact. */
static void base_params(plant_params *p)
{
    memset(p, 0, sizeof *p);
    p->mass_kg = 4.0;
    p->inertia_kgm2 = v3_make(0.082, 0.082, 0.149);
    p->gravity_mps2 = G;
    p->rotor_count = 6;
    for (int i = 0; i < 6; i++) {
        const double a = (-30.0 + 60.0 * i) * PI / 180.0;
        plant_rotor *r = &p->rotor[i];
        r->position_m = v3_make(0.45 * cos(a), 0.45 * sin(a), 0.0);
        r->axis = v3_make(0.0, 0.0, 1.0);
        r->thrust_max_n = 13.08;
        r->torque_max_nm = (i % 2 == 0 ? -1.0 : 1.0) * 0.016 * 13.08;
        r->thrust_exponent = 2.0;
        r->torque_exponent = 2.0;
        r->speed_min = 0.0;
        r->tau_s = 0.0;
        r->efficiency = 1.0;
    }
    p->mass_tau_s = 0.01;
    p->ground_effect = false;
    p->ge_radius_m = 0.16;
    p->ge_rho = 1.184;
    p->gear_height_m = 0.18;
    p->foot_count = 4;
    for (int k = 0; k < 4; k++) {
        const double a = (45.0 + 90.0 * k) * PI / 180.0;
        p->foot_m[k] = v3_make(0.3 * cos(a), 0.3 * sin(a), -0.18);
    }
    p->contact = false;
    p->contact_stiffness_n_per_m = 2.0e4;
    p->contact_damping_ns_per_m = 0.0;
    p->friction = 0.0;
    p->slip_speed_mps = 0.01;
    p->pad.model = PAD_STILL;
}

static plant_state state_at(double z)
{
    plant_state s;
    memset(&s, 0, sizeof s);
    s.p = v3_make(0.0, 0.0, z);
    s.q = quat_identity();
    s.m = 4.0;
    return s;
}

static void run(plant *pl, double duration, double h)
{
    const long n = lround(duration / h);
    for (long k = 0; k < n; k++) {
        plant_step(pl, h);
    }
}

static void test_free_fall(void **state)
{
    (void)state;
    plant_params p;
    base_params(&p);
    assert_null(plant_params_check(&p));
    plant pl;
    const plant_state s0 = state_at(100.0);
    plant_init(&pl, &p, &s0);
    run(&pl, 2.0, 1.0 / 4000.0);
    const double t = pl.t;
    assert_true(fabs(pl.s.p.z - (100.0 - 0.5 * G * t * t)) < 1e-9);
    assert_true(fabs(pl.s.v.z + G * t) < 1e-9);
    assert_true(fabs(pl.s.p.x) < 1e-12 && fabs(pl.s.p.y) < 1e-12);
    /* the accelerometer of a falling body reads zero */
    plant_diag d;
    plant_diagnose(&pl, &d);
    assert_true(v3_norm(d.specific_force_b) < 1e-12);
}

static void test_hover(void **state)
{
    (void)state;
    plant_params p;
    base_params(&p);
    p.ground_effect = true;
    plant pl;
    const double h = 0.4; /* CG (and rotor plane) 0.4 m above the pad */
    const plant_state s0 = state_at(h);
    plant_init(&pl, &p, &s0);
    const double u = plant_hover_speed(&pl);
    assert_true(u > 0.0 && u < 1.0);
    const double kg = 1.0 / (1.0 - 1.184 * pow(0.16 / (4.0 * h), 2.0));
    /* T = T_max u^2 per rotor: 6 T k_g = m g, i.e. the rotors make m g / k_g */
    const double thrust_per_rotor = 13.08 * u * u;
    assert_true(fabs(6.0 * thrust_per_rotor - 4.0 * G / kg) < 1e-9);
    double cmd[6];
    for (int i = 0; i < 6; i++) {
        cmd[i] = u;
    }
    plant_set_command(&pl, cmd, 6);
    run(&pl, 5.0, 1.0 / 4000.0);
    assert_true(fabs(pl.s.p.z - h) < 1e-9);
    assert_true(v3_norm(pl.s.v) < 1e-9);
    assert_true(v3_norm(pl.s.w) < 1e-12); /* alternating spins: no net yaw moment */
    plant_diag d;
    plant_diagnose(&pl, &d);
    assert_true(fabs(d.specific_force_b.z - G) < 1e-9);
}

static void test_torque_free(void **state)
{
    (void)state;
    plant_params p;
    base_params(&p);
    p.inertia_kgm2 = v3_make(0.05, 0.082, 0.149); /* three different moments */
    plant pl;
    plant_state s0 = state_at(1000.0);
    s0.w = v3_make(1.0, 0.2, 3.0); /* near the stable axis, but not on it */
    s0.q = quat_normalize(quat_make(0.9, 0.1, -0.3, 0.2));
    plant_init(&pl, &p, &s0);
    const v3 l0 = plant_angular_momentum_world(&pl);
    const double e0 = 0.5 * v3_dot(v3_mul(p.inertia_kgm2, pl.s.w), pl.s.w);
    for (int k = 0; k < 10; k++) {
        run(&pl, 1.0, 1.0 / 4000.0);
        const v3 l = plant_angular_momentum_world(&pl);
        const double e = 0.5 * v3_dot(v3_mul(p.inertia_kgm2, pl.s.w), pl.s.w);
        assert_true(v3_norm(v3_sub(l, l0)) / v3_norm(l0) < 1e-9);
        assert_true(fabs(e - e0) / e0 < 1e-9);
        assert_true(fabs(quat_norm(pl.s.q) - 1.0) < 1e-12);
    }
    /* the body rate did change (it is not a trivial spin about a principal axis) */
    assert_true(v3_norm(v3_sub(pl.s.w, s0.w)) > 0.1);
}

static void test_ground_effect_gain(void **state)
{
    (void)state;
    plant_params p;
    base_params(&p);
    p.ground_effect = true;
    const double kg_max = 1.0 / (1.0 - 1.184 * pow(0.16 / (4.0 * 0.18), 2.0));
    assert_true(fabs(plant_ground_gain(0.16, 1.184, 0.18) - kg_max) < 1e-15);
    const double heights[] = {-0.3, 0.0, 0.1, 0.18, 0.2, 0.3, 0.5, 1.0, 3.0};
    double last = (double)INFINITY;
    for (unsigned k = 0; k < sizeof heights / sizeof heights[0]; k++) {
        const double h = heights[k];
        plant pl;
        plant_state s0 = state_at(h);
        for (int i = 0; i < 6; i++) {
            s0.u[i] = 0.7;
        }
        plant_init(&pl, &p, &s0);
        plant_diag d;
        plant_diagnose(&pl, &d);
        const double expected = h > 0.18 ? 1.0 / (1.0 - 1.184 * pow(0.16 / (4.0 * h), 2.0)) : kg_max;
        assert_true(fabs(d.ground_gain - expected) < 1e-12);
        /* the thrust follows the gain: 6 T_max u^2 k_g */
        assert_true(fabs(d.force_b.z - 6.0 * 13.08 * 0.49 * expected) < 1e-9);
        assert_true(d.ground_gain <= last + 1e-15); /* never rises with height */
        last = d.ground_gain;
        assert_true(isfinite(d.ground_gain) && d.ground_gain >= 1.0 && d.ground_gain <= kg_max + 1e-15);
    }
    /* far away the effect vanishes: below 0.1 % at 2 m */
    assert_true(plant_ground_gain(0.16, 1.184, 2.0) - 1.0 < 1e-3);
    /* a floor at or below the singularity of (3.2) is refused */
    p.gear_height_m = 0.04;
    assert_non_null(plant_params_check(&p));
}

static void test_rest_on_pad(void **state)
{
    (void)state;
    plant_params p;
    base_params(&p);
    p.contact = true;
    p.contact_stiffness_n_per_m = 2.0e4;
    p.contact_damping_ns_per_m = 2.0 * 0.7 * sqrt(2.0e4 * 4.0 / 4.0);
    p.friction = 0.8;
    p.pad.model = PAD_STILL;
    p.pad.base_m = 0.5;
    plant pl;
    plant_state s0 = state_at(0.5 + 0.18 + 0.01); /* gear 1 cm above the pad */
    s0.v = v3_make(0.05, -0.02, 0.0);             /* some sideways motion: friction stops it */
    plant_init(&pl, &p, &s0);
    run(&pl, 3.0, 1.0 / 4000.0);
    const double deflection = 4.0 * G / (4.0 * 2.0e4);
    plant_diag d;
    plant_diagnose(&pl, &d);
    assert_int_equal(d.feet_in_contact, 4);
    assert_true(fabs(-d.gear_clearance_m - deflection) < 0.01 * deflection);
    assert_true(fabs(d.contact_force_w.z - 4.0 * G) < 1e-3);
    assert_true(v3_norm(pl.s.v) < 1e-4);
    assert_true(v3_norm(pl.s.w) < 1e-3);
    const double tilt = acos(1.0 - 2.0 * (pl.s.q.x * pl.s.q.x + pl.s.q.y * pl.s.q.y));
    assert_true(tilt < 1e-4);
    /* it slid a little, then stuck */
    const double slid = sqrt(pl.s.p.x * pl.s.p.x + pl.s.p.y * pl.s.p.y);
    assert_true(slid < 0.01);
    const v3 before = pl.s.p;
    run(&pl, 1.0, 1.0 / 4000.0);
    assert_true(v3_norm(v3_sub(pl.s.p, before)) < 1e-5);
}

static void test_energy_no_control(void **state)
{
    (void)state;
    plant_params p;
    base_params(&p);
    plant pl;
    plant_state s0 = state_at(10.0);
    s0.v = v3_make(1.0, -2.0, 3.0);
    s0.w = v3_make(0.3, -0.5, 1.0);
    plant_init(&pl, &p, &s0);
    const double e0 = plant_energy(&pl);
    run(&pl, 1.0, 1.0 / 4000.0);
    assert_true(fabs(plant_energy(&pl) - e0) / e0 < 1e-9);

    /* a lossless contact (no damping, no friction): the drop bounces back */
    p.contact = true;
    p.contact_damping_ns_per_m = 0.0;
    p.friction = 0.0;
    s0 = state_at(0.18 + 0.05);
    plant_init(&pl, &p, &s0);
    const double e1 = plant_energy(&pl);
    double highest_after = 0.0;
    bool touched = false;
    for (int k = 0; k < 4000; k++) {
        plant_step(&pl, 1.0 / 8000.0);
        plant_diag d;
        plant_diagnose(&pl, &d);
        touched = touched || d.feet_in_contact > 0;
        if (touched && d.feet_in_contact == 0 && d.gear_clearance_m > highest_after) {
            highest_after = d.gear_clearance_m;
        }
    }
    assert_true(touched);
    assert_true(fabs(plant_energy(&pl) - e1) / e1 < 1e-4);
    /* back up to within 0.1 mm of the 5 cm it fell from */
    assert_true(fabs(highest_after - 0.05) < 1e-4);
}

static void test_mass_filter(void **state)
{
    (void)state;
    plant_params p;
    base_params(&p);
    p.mass_step_count = 1;
    p.mass_step_time_s[0] = 1.0;
    p.mass_step_kg[0] = 3.5;
    plant pl;
    const plant_state s0 = state_at(100.0);
    plant_init(&pl, &p, &s0);
    const double h = 1.0 / 4000.0;
    for (int k = 0; k < 4000 + 200; k++) {
        plant_step(&pl, h);
        const double t = pl.t;
        const double expected = t <= 1.0 ? 4.0 : 3.5 + 0.5 * exp(-(t - 1.0) / 0.01);
        assert_true(fabs(pl.s.m - expected) < 1e-6);
    }
    /* a free-falling body falls the same whatever its mass */
    assert_true(fabs(pl.s.v.z + G * pl.t) < 1e-9);
}

static void test_pad_derivatives(void **state)
{
    (void)state;
    pad_params sine = {.model = PAD_SINE, .base_m = 0.2, .amplitude_m = 0.18, .omega_radps = 2.0 * PI / 10.0};
    pad_params waves = {.model = PAD_WAVES, .wave_count = 3};
    const double a[3] = {0.3, 0.15, 0.05}, T[3] = {9.0, 6.5, 13.0}, ph[3] = {0.0, 1.0, 3.5};
    for (int k = 0; k < 3; k++) {
        waves.wave_amplitude_m[k] = a[k];
        waves.wave_omega_radps[k] = 2.0 * PI / T[k];
        waves.wave_phase_rad[k] = ph[k];
    }
    const pad_params *models[2] = {&sine, &waves};
    for (int m = 0; m < 2; m++) {
        for (double t = 0.0; t < 20.0; t += 0.37) {
            pad_state s, sp, sm;
            const double dt = 1e-5;
            pad_eval(models[m], t, &s);
            pad_eval(models[m], t + dt, &sp);
            pad_eval(models[m], t - dt, &sm);
            assert_true(fabs((sp.z_m - sm.z_m) / (2.0 * dt) - s.vz_mps) < 1e-7);
            assert_true(fabs((sp.vz_mps - sm.vz_mps) / (2.0 * dt) - s.az_mps2) < 1e-7);
        }
    }
    /* (3.1): between 0 and A above the base */
    pad_state s;
    pad_eval(&sine, 2.5, &s);
    assert_true(fabs(s.z_m - (0.2 + 0.18)) < 1e-12);
    pad_eval(&sine, 7.5, &s);
    assert_true(fabs(s.z_m - 0.2) < 1e-12);
}

int main(int argc, char **argv)
{
    /* one case by name (ctest runs them one by one), or all */
    if (argc > 1) {
        cmocka_set_test_filter(argv[1]);
    }
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_free_fall),
        cmocka_unit_test(test_hover),
        cmocka_unit_test(test_torque_free),
        cmocka_unit_test(test_ground_effect_gain),
        cmocka_unit_test(test_rest_on_pad),
        cmocka_unit_test(test_energy_no_control),
        cmocka_unit_test(test_mass_filter),
        cmocka_unit_test(test_pad_derivatives),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
