/*
 * test_sensors.c - the sensor models (sim.sensors.*): seeded and reproducible,
 * noise of the stated deviation, bias, quantisation to the LSB, sample rate
 * and delay.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "plant.h"
#include "sensors.h"

#define G 9.81

/* A point mass (one rotor, unused) moving up at 1 m/s, level, spinning about z. */
static void moving_plant(plant *pl)
{
    plant_params p;
    memset(&p, 0, sizeof p);
    p.mass_kg = 1.0;
    p.inertia_kgm2 = v3_make(0.01, 0.01, 0.02);
    p.gravity_mps2 = G;
    p.rotor_count = 1;
    p.rotor[0].axis = v3_make(0.0, 0.0, 1.0);
    p.rotor[0].thrust_max_n = 1.0;
    p.rotor[0].thrust_exponent = p.rotor[0].torque_exponent = 2.0;
    p.rotor[0].efficiency = 1.0;
    p.mass_tau_s = 0.01;
    p.foot_count = 1;
    p.gear_height_m = 0.1;
    p.foot_m[0] = v3_make(0.0, 0.0, -0.1);
    plant_state s;
    memset(&s, 0, sizeof s);
    s.p = v3_make(0.0, 0.0, 10.0);
    s.v = v3_make(0.0, 0.0, 1.0);
    s.q = quat_identity();
    s.w = v3_make(0.0, 0.0, 0.5);
    s.m = 1.0;
    plant_init(pl, &p, &s);
}

static sensor_params noisy(void)
{
    sensor_params sp;
    memset(&sp, 0, sizeof sp);
    sp.noise_scale = 1.0;
    sp.imu.gyro_noise_radps = 0.01;
    sp.imu.accel_noise_mps2 = 0.05;
    sp.imu.gyro_bias_radps = v3_make(0.02, -0.01, 0.0);
    sp.position.noise_m = 0.003;
    sp.position.velocity_noise_mps = 0.02;
    sp.altitude.source = ALTITUDE_FROM_POSITION;
    return sp;
}

/* Runs n controller steps of dt (plant steps of dt/4), collecting gyro x. */
static void collect(const sensor_params *sp, uint64_t seed, int n, double *gyro_x, double *pos_z)
{
    plant pl;
    moving_plant(&pl);
    sensors s;
    const double dt = 0.002;
    sensors_init(&s, sp, dt, seed);
    for (int k = 0; k < n; k++) {
        const double t = k * dt;
        sensors_sample(&s, &pl, t);
        sensor_readout r;
        sensors_read(&s, t, &r);
        gyro_x[k] = r.gyro_radps.x;
        pos_z[k] = r.position_m.z - pl.s.p.z;
        for (int j = 0; j < 4; j++) {
            if (j > 0) {
                sensors_sample(&s, &pl, t + j * dt / 4.0);
            }
            plant_step(&pl, dt / 4.0);
        }
    }
}

#define N 20000
static double a1[N], b1[N], a2[N], b2[N];

static void test_seeded(void **state)
{
    (void)state;
    const sensor_params sp = noisy();
    collect(&sp, 42, N, a1, b1);
    collect(&sp, 42, N, a2, b2);
    assert_memory_equal(a1, a2, sizeof a1);
    assert_memory_equal(b1, b2, sizeof b1);
    collect(&sp, 43, N, a2, b2);
    int same = 0;
    for (int k = 0; k < N; k++) {
        same += a1[k] == a2[k];
    }
    assert_true(same < N / 100);
}

static void test_noise_and_bias(void **state)
{
    (void)state;
    const sensor_params sp = noisy();
    collect(&sp, 7, N, a1, b1);
    double mean = 0.0, var = 0.0, pmean = 0.0, pvar = 0.0;
    for (int k = 0; k < N; k++) {
        mean += a1[k];
        pmean += b1[k];
    }
    mean /= N;
    pmean /= N;
    for (int k = 0; k < N; k++) {
        var += (a1[k] - mean) * (a1[k] - mean);
        pvar += (b1[k] - pmean) * (b1[k] - pmean);
    }
    const double sd = sqrt(var / (N - 1)), psd = sqrt(pvar / (N - 1));
    /* 20000 samples: the deviation within 3 %, the mean within 4 standard errors */
    assert_true(fabs(sd - 0.01) < 0.03 * 0.01);
    assert_true(fabs(mean - 0.02) < 4.0 * 0.01 / sqrt(N));
    assert_true(fabs(psd - 0.003) < 0.03 * 0.003);
    assert_true(fabs(pmean) < 4.0 * 0.003 / sqrt(N));
}

static void test_quantised(void **state)
{
    (void)state;
    sensor_params sp = noisy();
    sp.imu.gyro_lsb_radps = 0.001;
    sp.position.lsb_m = 0.001;
    plant pl;
    moving_plant(&pl);
    sensors s;
    sensors_init(&s, &sp, 0.002, 1);
    for (int k = 0; k < 1000; k++) {
        sensors_sample(&s, &pl, k * 0.002);
        sensor_readout r;
        sensors_read(&s, k * 0.002, &r);
        const double q = r.gyro_radps.x / 0.001, pz = r.position_m.z / 0.001;
        assert_true(fabs(q - nearbyint(q)) < 1e-9);
        assert_true(fabs(pz - nearbyint(pz)) < 1e-6);
        plant_step(&pl, 0.002);
    }
}

static void test_rate_and_delay(void **state)
{
    (void)state;
    sensor_params sp;
    memset(&sp, 0, sizeof sp);
    sp.noise_scale = 1.0;
    sp.position.rate_hz = 50.0;  /* a sample every 20 ms */
    sp.position.delay_s = 0.03;  /* delivered 30 ms later */
    sp.imu.rate_hz = 1000.0;
    plant pl;
    moving_plant(&pl); /* z = 10 + t (no gravity effect on the check: v is read) */
    sensors s;
    const double dt = 0.002, h = 0.0005;
    sensors_init(&s, &sp, dt, 1);
    for (int k = 0; k < 500; k++) {
        const double t = k * dt;
        for (int j = 0; j < 4; j++) {
            sensors_sample(&s, &pl, t + j * h);
            if (j == 0) {
                sensor_readout r;
                sensors_read(&s, t, &r);
                /* newest sample taken at or before t - 30 ms, on the 20 ms grid */
                double taken = floor((t - 0.03 + 1e-9) / 0.02) * 0.02;
                if (taken < 0.0) {
                    taken = 0.0;
                }
                /* the plant's vertical velocity is 1 - g t: the sample's time is readable */
                const double expected_vz = 1.0 - G * taken;
                assert_true(fabs(r.velocity_mps.z - expected_vz) < 1e-9);
            }
            plant_step(&pl, h);
        }
    }
}

static void test_range_altitude(void **state)
{
    (void)state;
    sensor_params sp;
    memset(&sp, 0, sizeof sp);
    sp.noise_scale = 1.0;
    sp.altitude.source = ALTITUDE_RANGE;
    sp.altitude.range_max_m = 20.0;
    plant pl;
    moving_plant(&pl);
    pl.p.pad.model = PAD_STILL;
    pl.p.pad.base_m = 2.0;
    /* tilted 30 deg about x: the range along body -z is height / cos 30 */
    pl.s.q = quat_from_axis_angle(v3_make(1.0, 0.0, 0.0), 30.0 * 3.14159265358979323846 / 180.0);
    sensors s;
    sensors_init(&s, &sp, 0.002, 1);
    sensors_sample(&s, &pl, 0.0);
    sensor_readout r;
    sensors_read(&s, 0.0, &r);
    assert_true(r.altitude_is_range);
    assert_true(fabs(r.altitude_m - (10.0 - 2.0) / cos(30.0 * 3.14159265358979323846 / 180.0)) < 1e-9);
}

/* The heading channel: off unless enabled; on, the yaw of the sample taken at
 * or before t - delay on its grid, plus the bias, wrapped to [-pi, pi]. The
 * plant spins at 0.5 rad/s about z, so over 8 s the yaw passes the seam. */
static void test_heading_channel(void **state)
{
    (void)state;
    const double pi = 3.14159265358979323846;
    sensor_params sp;
    memset(&sp, 0, sizeof sp);
    sp.noise_scale = 1.0;
    plant pl;
    moving_plant(&pl);
    sensors s;
    sensors_init(&s, &sp, 0.002, 1);
    sensors_sample(&s, &pl, 0.0);
    sensor_readout r;
    sensors_read(&s, 0.0, &r);
    assert_false(r.has_heading);

    sp.heading.enabled = true;
    sp.heading.rate_hz = 100.0;
    sp.heading.delay_s = 0.01;
    sp.heading.bias_rad = 0.1;
    moving_plant(&pl);
    sensors_init(&s, &sp, 0.002, 1);
    const double dt = 0.002, h = 0.0005;
    double last_taken = -1.0;
    int fresh = 0, wrapped = 0;
    for (int k = 0; k < 4000; k++) {
        const double t = k * dt;
        for (int j = 0; j < 4; j++) {
            sensors_sample(&s, &pl, t + j * h);
            if (j == 0) {
                sensors_read(&s, t, &r);
                const double taken = floor((t - 0.01 + 1e-9) / 0.01) * 0.01;
                assert_true(r.has_heading == (taken >= 0.0));
                if (r.has_heading) {
                    assert_true(fabs(r.heading_sample_t - taken) < 1e-9);
                    const double truth = 0.5 * taken + 0.1;
                    const double expected = atan2(sin(truth), cos(truth));
                    assert_true(fabs(r.heading_rad - expected) < 1e-6);
                    assert_true(r.heading_rad >= -pi && r.heading_rad <= pi);
                    fresh += r.heading_sample_t != last_taken;
                    wrapped += truth > pi;
                    last_taken = r.heading_sample_t;
                }
            }
            plant_step(&pl, h);
        }
    }
    assert_int_equal(fresh, 799); /* 8 s at 100 Hz, the first 10 ms still in flight */
    assert_true(wrapped > 0);
}

int main(int argc, char **argv)
{
    /* one case by name (ctest runs them one by one), or all */
    if (argc > 1) {
        cmocka_set_test_filter(argv[1]);
    }
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_seeded),
        cmocka_unit_test(test_noise_and_bias),
        cmocka_unit_test(test_quantised),
        cmocka_unit_test(test_rate_and_delay),
        cmocka_unit_test(test_range_altitude),
        cmocka_unit_test(test_heading_channel),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
