/*
 * bench_run.h - the benchmark's workload, shared by the ATmega2560 bench
 * image (platform/atmega/bench) and the Cortex-M4F one (platform/cortex-m4-bench).
 *
 * Three workloads, chosen at build time by BENCH_WORKLOAD_CRAZYFLIE and
 * BENCH_WORKLOAD_F450:
 *   0  the hexa 4 kg with ssc-adaptive tracking the pad (FC_COMMAND_TRACK_PAD),
 *      the dissertation's 4.4 vehicle (with BENCH_WORKLOAD_F450: the F450
 *      quad, the ATmega image's airframe, the same law and command);
 *   1  the Crazyflie 2.x with ssc flying the landing mission (FC_COMMAND_LAND,
 *      as in sim_host/scenarios/cf2-pad.ini): the quad the Cortex-M4F flies,
 *      on the platform's attitude as the app does (use_external_attitude: the
 *      filter only forms the rate), with a range sample on vectors 0 and 4
 *      (the pad model's update; the 50 Hz ToF gives one every tenth step at
 *      500 Hz).
 * Both at 500 Hz, the loop rate issue 7's targets are stated for and the SIL
 * scenarios fly. fc_controller_init once, then the warm-up steps at rest (the
 * estimator's alignment; the Crazyflie's pad model learns from a range sample
 * every tenth step), then bench_timed_begin() and BENCH_ROUNDS rounds over the
 * BENCH_VECTORS fixed input vectors below, armed, then
 * bench_timed_end(). The tools outside (simavr host program, QEMU plugin)
 * time fc_controller_step and each module's step by symbol, only between the
 * two markers. Constants are FC_C/FC_INT: no soft-float in the fixed image.
 */
#ifndef BENCH_RUN_H
#define BENCH_RUN_H

#include "fc/controller.h"

/* an image may time each timed step itself (the M4F's DWT->CYCCNT path) */
#ifndef BENCH_STEP_BEFORE
#define BENCH_STEP_BEFORE() ((void)0)
#define BENCH_STEP_AFTER() ((void)0)
#endif

#ifndef BENCH_WORKLOAD_CRAZYFLIE
#define BENCH_WORKLOAD_CRAZYFLIE 0
#endif
#ifndef BENCH_WORKLOAD_F450
#define BENCH_WORKLOAD_F450 0
#endif

#define BENCH_VECTORS 8
#define BENCH_ROUNDS 2

typedef struct bench_vector {
    fc_real gyro[3];   /* RATE */
    fc_real accel[3];  /* ACCEL */
    fc_real pos[3];    /* LENGTH */
    fc_real vel[3];    /* VEL */
    fc_real pad_z, pad_vz, pad_az;
} bench_vector;

#define R(x) FC_C(x, RATE)
#define A(x) FC_C(x, ACCEL)
#define L(x) FC_C(x, LENGTH)
#define V(x) FC_C(x, VEL)
static const bench_vector bench_vectors[BENCH_VECTORS] = {
    {{R(0.0f), R(0.0f), R(0.0f)}, {A(0.0f), A(0.0f), A(9.81f)}, {L(0.0f), L(0.0f), L(1.18f)},
     {V(0.0f), V(0.0f), V(0.0f)}, L(0.0f), V(0.0f), A(0.0f)},
    {{R(0.05f), R(-0.02f), R(0.01f)}, {A(0.1f), A(-0.2f), A(9.7f)}, {L(0.05f), L(-0.03f), L(1.10f)},
     {V(0.1f), V(-0.05f), V(-0.2f)}, L(0.05f), V(0.1f), A(-0.3f)},
    {{R(-0.3f), R(0.2f), R(-0.1f)}, {A(-0.5f), A(0.8f), A(9.9f)}, {L(-0.2f), L(0.1f), L(0.95f)},
     {V(-0.3f), V(0.2f), V(-0.4f)}, L(0.12f), V(0.25f), A(0.5f)},
    {{R(0.8f), R(-0.6f), R(0.4f)}, {A(1.2f), A(-1.5f), A(9.3f)}, {L(0.4f), L(-0.35f), L(0.70f)},
     {V(0.5f), V(-0.4f), V(-0.6f)}, L(0.20f), V(-0.1f), A(1.2f)},
    {{R(-1.5f), R(1.1f), R(-0.7f)}, {A(-2.0f), A(2.5f), A(8.5f)}, {L(-0.6f), L(0.5f), L(0.45f)},
     {V(-0.8f), V(0.6f), V(-0.3f)}, L(0.15f), V(-0.3f), A(-1.0f)},
    {{R(0.02f), R(0.03f), R(-0.04f)}, {A(0.05f), A(0.02f), A(10.2f)}, {L(0.01f), L(0.02f), L(0.30f)},
     {V(0.02f), V(0.01f), V(-0.15f)}, L(0.08f), V(0.2f), A(0.2f)},
    {{R(2.5f), R(-2.0f), R(1.5f)}, {A(3.0f), A(-2.0f), A(7.0f)}, {L(1.0f), L(-1.0f), L(2.0f)},
     {V(1.5f), V(-1.2f), V(0.8f)}, L(-0.1f), V(0.4f), A(-2.0f)},
    {{R(-0.01f), R(0.0f), R(0.02f)}, {A(0.0f), A(0.1f), A(9.8f)}, {L(0.0f), L(0.0f), L(0.10f)},
     {V(0.0f), V(0.0f), V(-0.05f)}, L(0.02f), V(0.05f), A(0.1f)},
};
/* The platform's attitude per vector (the Crazyflie workload flies on it, as
 * the app does): the roll and pitch of the vector's specific force, a small yaw. */
#define U(x) FC_C(x, UNIT)
static const fc_real bench_attitudes[BENCH_VECTORS][4] = {
    {U(1.000000f), U(0.000000f), U(0.000000f), U(0.000000f)},
    {U(0.999921f), U(-0.010282f), U(-0.005205f), U(0.004947f)},
    {U(0.998744f), U(0.040665f), U(0.024519f), U(-0.015996f)},
    {U(0.994621f), U(-0.078109f), U(-0.065080f), U(0.019813f)},
    {U(0.982279f), U(0.145933f), U(0.103894f), U(-0.055115f)},
    {U(0.999946f), U(0.001005f), U(-0.002441f), U(0.010002f)},
    {U(0.971348f), U(-0.124284f), U(-0.200133f), U(0.031367f)},
    {U(0.999974f), U(0.005102f), U(-0.000026f), U(-0.005000f)},
};
#undef U
#undef R
#undef A
#undef L
#undef V

/* Markers seen from outside by their address; noinline and with a side
 * effect so that the calls stay. */
static volatile uint8_t bench_phase;
__attribute__((noinline)) void bench_timed_begin(void);
__attribute__((noinline)) void bench_timed_end(void);
__attribute__((noinline)) void bench_timed_begin(void)
{
    bench_phase = 1;
}
__attribute__((noinline)) void bench_timed_end(void)
{
    bench_phase = 2;
}

static fc_controller bench_ctl;
static fc_controller_inputs bench_in;
static fc_controller_outputs bench_out;

/* the range finder of the Crazyflie workload: level, gear-to-pad plus the
 * CG's 2 cm above the gear, never below 2 cm */
static void bench_range(const bench_vector *v, bool fresh)
{
    const fc_real range = fc_sub(&bench_ctl.ar, v->pos[2], v->pad_z);
    bench_in.range_m = range > FC_C(0.02f, LENGTH) ? range : FC_C(0.02f, LENGTH);
    bench_in.range_fresh = BENCH_WORKLOAD_CRAZYFLIE && fresh;
}

static void bench_load(const bench_vector *v)
{
    const fc_real *q = bench_attitudes[v - bench_vectors];
    bench_in.attitude_external = fc_quat_make(q[0], q[1], q[2], q[3]);
    bench_in.imu.gyro_radps = fc_vec3_make(v->gyro[0], v->gyro[1], v->gyro[2]);
    bench_in.imu.accel_mps2 = fc_vec3_make(v->accel[0], v->accel[1], v->accel[2]);
    bench_in.position_m = fc_vec3_make(v->pos[0], v->pos[1], v->pos[2]);
    bench_in.velocity_mps = fc_vec3_make(v->vel[0], v->vel[1], v->vel[2]);
    bench_in.pad.z_m = v->pad_z;
    bench_in.pad.vz_mps = v->pad_vz;
    bench_in.pad.az_mps2 = v->pad_az;
}

/* FNV-1a over the rotor speeds, thrust and moments of every timed step: a
 * digest that shows whether a change of the library changed its outputs on
 * the target itself (the M4F image prints it; the SIL runs on the host). */
static uint32_t bench_digest = 2166136261u;

static void bench_digest_add(const void *data, unsigned size)
{
    const unsigned char *byte = (const unsigned char *)data;
    for (unsigned i = 0; i < size; i++) {
        bench_digest = (bench_digest ^ byte[i]) * 16777619u;
    }
}

/* Returns 0 when init succeeded and every step ran; the step statuses are
 * OR-ed into *status. */
static __attribute__((noinline)) int bench_run(uint16_t *status)
{
    fc_controller_params p;
#if BENCH_WORKLOAD_CRAZYFLIE
    fc_controller_default_params(&p, FC_AIRFRAME_CRAZYFLIE2, FC_ALT_VARIANT_SSC, FC_C(0.002f, DT));
    const fc_controller_command armed_command = FC_COMMAND_LAND;
    p.use_external_attitude = true; /* as the app flies (platform/crazyflie/cf_convert.c) */
#else
    const fc_airframe airframe = BENCH_WORKLOAD_F450 ? FC_AIRFRAME_F450 : FC_AIRFRAME_HEXA_4KG;
    fc_controller_default_params(&p, airframe, FC_ALT_VARIANT_SSC_ADAPTIVE, FC_C(0.002f, DT));
    const fc_controller_command armed_command = FC_COMMAND_TRACK_PAD;
#endif
    if (fc_controller_init(&bench_ctl, &p) != FC_INIT_OK) {
        return 1;
    }
    bench_in.position_setpoint_m = fc_vec3_make(FC_INT(0, LENGTH), FC_INT(0, LENGTH), FC_INT(0, LENGTH));
    bench_in.yaw_setpoint_rad = FC_INT(0, ANGLE);
    bench_in.command = FC_COMMAND_DISARM;
    bench_load(&bench_vectors[0]);
    const unsigned warmup = (unsigned)p.estimator.alignment_samples + 2u;
    for (unsigned i = 0; i < warmup; i++) {
        bench_range(&bench_vectors[0], i % 10u == 0u);
        (void)fc_controller_step(&bench_ctl, &bench_in, &bench_out);
    }
    bench_in.command = armed_command;
    uint16_t st = 0;
    bench_timed_begin();
    for (unsigned r = 0; r < BENCH_ROUNDS; r++) {
        for (unsigned k = 0; k < BENCH_VECTORS; k++) {
            bench_load(&bench_vectors[k]);
            bench_range(&bench_vectors[k], k == 0u || k == 4u);
            BENCH_STEP_BEFORE();
            const fc_step_status s = fc_controller_step(&bench_ctl, &bench_in, &bench_out);
            BENCH_STEP_AFTER();
            st = (uint16_t)(st | (uint16_t)s);
            bench_digest_add(bench_out.rotor_speed, sizeof bench_out.rotor_speed);
            bench_digest_add(&bench_out.thrust_n, sizeof bench_out.thrust_n);
            bench_digest_add(&bench_out.moment_nm, sizeof bench_out.moment_nm);
        }
    }
    bench_timed_end();
    *status = st;
    return 0;
}

#endif /* BENCH_RUN_H */
