/*
 * Host tests of the glue itself (cf_glue.c): the firmware's entry points
 * called as the stabilizer calls them, with the firmware's types (setpoint_t,
 * state_t, sensorData_t, control_t: crazyflie-firmware's own header when the
 * build has CRAZYFLIE_BASE, else tests/fw-types), PARAM written and LOG read
 * by name through their tables, the app task run as appMain. The setpoints
 * are the firmware's sequences: the high-level commander's trajectory
 * setpoints, MotionCommander's hover setpoints, cflib's world velocity
 * setpoints, the supervisor's level-out and null setpoint, a selection of
 * the controller in flight.
 */
#include <stdarg.h>
#include <stdio.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <math.h>
#include <string.h>
#include <cmocka.h>

#include "autoconf.h" /* first, as in cf_glue.c: controller.h declares the OOT entry points under it */
#include "FreeRTOS.h"
#include "app.h"
#include "controller.h"
#include "log.h"
#include "param.h"
#include "platform_defaults.h"
#include "range.h"
#include "stabilizer_types.h"
#include "stm32f4xx.h"
#include "task.h"

#include "cf_test_plant.h"

#define PI 3.14159265358979323846

/* ---- the stand-ins' state (tests/fw) ------------------------------------------ */

CoreDebug_Type cf_test_core_debug;
uint32_t cf_test_dwt_step;
static DWT_Type dwt;

DWT_Type *cf_test_dwt(void)
{
    dwt.CYCCNT += cf_test_dwt_step;
    return &dwt;
}

static float range_down_mm;

float rangeGet(rangeDirection_t direction)
{
    return direction == rangeDown ? range_down_mm : 0.0f;
}

/* The app task: appMain runs until it waits, then returns here. */
static jmp_buf task_wait;
static int notifications;

TaskHandle_t xTaskGetCurrentTaskHandle(void)
{
    return &task_wait;
}

BaseType_t xTaskNotifyGive(TaskHandle_t task)
{
    (void)task;
    notifications++;
    return pdTRUE;
}

uint32_t ulTaskNotifyTake(BaseType_t clear_on_exit, TickType_t ticks_to_wait)
{
    (void)clear_on_exit;
    (void)ticks_to_wait;
    longjmp(task_wait, 1);
}

void vTaskDelay(TickType_t ticks)
{
    (void)ticks;
    longjmp(task_wait, 1);
}

/* One pass of the app task's loop (or its start, at boot). */
static void app_task_runs(void)
{
    if (setjmp(task_wait) == 0) {
        appMain();
    }
}

/* ---- PARAM and LOG by name ------------------------------------------------------- */

static void *var(const cf_test_var *table, const char *name, int type)
{
    for (const cf_test_var *v = table; v->name != NULL; v++) {
        if (strcmp(v->name, name) == 0) {
            assert_int_equal(v->type, type);
            return v->address;
        }
    }
    fail_msg("no variable %s", name);
    return NULL;
}

static void param_set_u8(const char *name, uint8_t value)
{
    *(uint8_t *)var(cf_test_param_fcssc, name, PARAM_UINT8) = value;
}

static uint8_t param_u8(const char *name)
{
    return *(const uint8_t *)var(cf_test_param_fcssc, name, PARAM_UINT8);
}

static float param_float(const char *name)
{
    return *(const float *)var(cf_test_param_fcssc, name, PARAM_FLOAT);
}

static void param_set_float(const char *name, float value)
{
    *(float *)var(cf_test_param_fcssc, name, PARAM_FLOAT) = value;
}

static float log_float(const char *name)
{
    return *(const float *)var(cf_test_log_fcssc, name, LOG_FLOAT);
}

static uint8_t log_u8(const char *name)
{
    return *(const uint8_t *)var(cf_test_log_fcssc, name, LOG_UINT8);
}

static uint32_t log_u32(const char *name)
{
    return *(const uint32_t *)var(cf_test_log_fcssc, name, LOG_UINT32);
}

static void near_abs(double got, double want, double tol)
{
    if (!(fabs(got - want) <= tol)) {
        fail_msg("got %.9g, want %.9g (+- %.3g)", got, want, tol);
    }
}

/* ---- the vehicle and the stabilizer's loop ---------------------------------------- */

typedef struct vehicle {
    plant pl;
    setpoint_t sp;
    sensorData_t sensors;
    state_t state;
    control_t control;
    stabilizerStep_t step;
    bool app_flies;      /* this controller selected: the stabilizer calls it */
    int calls;           /* calls of controllerOutOfTree */
    int calls_no_thrust; /* of which without thrust */
} vehicle;

/* What the estimator and the sensors give the stabilizer (units of
 * stabilizer_types.h: G, deg/s, legacy Euler degrees with pitch inverted). */
static void vehicle_sense(vehicle *v)
{
    const plant *pl = &v->pl;
    const double w = pl->q[0], x = pl->q[1], y = pl->q[2], z = pl->q[3];
    v->sensors.gyro.x = (float)(pl->w[0] * 180.0 / PI);
    v->sensors.gyro.y = (float)(pl->w[1] * 180.0 / PI);
    v->sensors.gyro.z = (float)(pl->w[2] * 180.0 / PI);
    v->sensors.acc.x = v->sensors.acc.y = 0.0f;
    v->sensors.acc.z = (float)(pl->f_body_z / PLANT_G);
    v->state.attitudeQuaternion.x = (float)x;
    v->state.attitudeQuaternion.y = (float)y;
    v->state.attitudeQuaternion.z = (float)z;
    v->state.attitudeQuaternion.w = (float)w;
    v->state.attitude.roll = (float)(atan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y)) * 180.0 / PI);
    v->state.attitude.pitch = (float)(-asin(2 * (w * y - z * x)) * 180.0 / PI);
    v->state.attitude.yaw = (float)(plant_yaw_rad(pl) * 180.0 / PI);
    v->state.position.x = (float)pl->p[0];
    v->state.position.y = (float)pl->p[1];
    v->state.position.z = (float)pl->p[2];
    v->state.velocity.x = (float)pl->v[0];
    v->state.velocity.y = (float)pl->v[1];
    v->state.velocity.z = (float)pl->v[2];
}

/* One tick of the stabilizer's 1 kHz loop, then 1 ms of flight. Another
 * controller (app_flies false) holds a level hover at the weight. */
static void stabilizer_tick(vehicle *v)
{
    vehicle_sense(v);
    cf_force_torque ft = {(float)(v->pl.mass_kg * PLANT_G), {0.0f, 0.0f, 0.0f}};
    if (v->app_flies) {
        controllerOutOfTree(&v->control, &v->sp, &v->sensors, &v->state, v->step);
        assert_int_equal(v->control.controlMode, controlModeForceTorque);
        ft.thrust_n = v->control.thrustSi;
        ft.torque_nm[0] = v->control.torqueX;
        ft.torque_nm[1] = v->control.torqueY;
        ft.torque_nm[2] = v->control.torqueZ;
        v->calls++;
        if (!(ft.thrust_n > 0.0f)) {
            v->calls_no_thrust++;
        }
    }
    plant_step(&v->pl, &ft, 0.001);
    v->step++;
}

static void ticks(vehicle *v, int n)
{
    for (int i = 0; i < n; i++) {
        stabilizer_tick(v);
    }
}

/* The plant with the platform's mass (CF_MASS), its inertia scaled as the
 * app scales the preset's (cf_convert.h). */
static void plant_is_the_platform(plant *pl)
{
    const double arm_ratio = (double)ARM_LENGTH / 0.046;
    const double scale = (double)CF_MASS / PLANT_MASS_KG * arm_ratio * arm_ratio;
    pl->mass_kg = (double)CF_MASS;
    for (int k = 0; k < 3; k++) {
        pl->inertia[k] *= scale;
    }
}

/* The firmware at boot: the controller selected (controllerInit from
 * stabilizerInit, before the app task runs), then the app task starts. */
static vehicle *boot(double x, double y, double z)
{
    static vehicle v;
    memset(&v, 0, sizeof v);
    plant_at(&v.pl, x, y, z, 0.0);
    plant_is_the_platform(&v.pl);
    range_down_mm = 0.0f;
    param_set_u8("mission", 0u);
    param_set_u8("track", 0u);
    controllerOutOfTreeInit();
    app_task_runs();
    v.app_flies = true;
    return &v;
}

/* ---- setpoints as the firmware fills them ------------------------------------------ */

/* crtp_commander_high_level.c: x, y, z and yaw absolute, with velocity and acceleration. */
static void sp_high_level(setpoint_t *sp, const double p[3], const double vel[3], const double acc[3], double yaw_deg)
{
    memset(sp, 0, sizeof *sp);
    sp->position.x = (float)p[0];
    sp->position.y = (float)p[1];
    sp->position.z = (float)p[2];
    sp->velocity.x = (float)vel[0];
    sp->velocity.y = (float)vel[1];
    sp->velocity.z = (float)vel[2];
    sp->acceleration.x = (float)acc[0];
    sp->acceleration.y = (float)acc[1];
    sp->acceleration.z = (float)acc[2];
    sp->attitude.yaw = (float)yaw_deg;
    sp->mode.x = sp->mode.y = sp->mode.z = modeAbs;
    sp->mode.roll = sp->mode.pitch = sp->mode.quat = modeDisable;
    sp->mode.yaw = modeAbs;
}

/* crtp_commander_generic.c's hover decoder (MotionCommander): x, y velocity
 * in the body's heading frame, z absolute, yaw rate (after the decoder's sign). */
static void sp_hover(setpoint_t *sp, double vx, double vy, double yaw_rate_dps, double z)
{
    memset(sp, 0, sizeof *sp);
    sp->mode.z = modeAbs;
    sp->position.z = (float)z;
    sp->mode.yaw = modeVelocity;
    sp->attitudeRate.yaw = (float)yaw_rate_dps;
    sp->mode.roll = sp->mode.pitch = modeAbs;
    sp->mode.x = sp->mode.y = modeVelocity;
    sp->velocity.x = (float)vx;
    sp->velocity.y = (float)vy;
    sp->velocity_body = true;
}

/* crtp_commander_generic.c's velocity decoder (cflib's
 * send_velocity_world_setpoint): x, y, z velocity in the world, yaw rate. */
static void sp_velocity_world(setpoint_t *sp, double vx, double vy, double vz, double yaw_rate_dps)
{
    memset(sp, 0, sizeof *sp);
    sp->mode.x = sp->mode.y = sp->mode.z = modeVelocity;
    sp->velocity.x = (float)vx;
    sp->velocity.y = (float)vy;
    sp->velocity.z = (float)vz;
    sp->mode.yaw = modeVelocity;
    sp->attitudeRate.yaw = (float)yaw_rate_dps;
}

/* supervisor.c, supervisorStateWarningLevelOut: the setpoint as it was, with
 * x, y disabled, roll and pitch 0, yaw at rate 0. */
static void sp_level_out(setpoint_t *sp)
{
    sp->mode.x = modeDisable;
    sp->mode.y = modeDisable;
    sp->mode.roll = modeAbs;
    sp->mode.pitch = modeAbs;
    sp->mode.yaw = modeVelocity;
    sp->attitude.roll = 0;
    sp->attitude.pitch = 0;
    sp->attitudeRate.yaw = 0;
}

static double horizontal_distance(const vehicle *v, double x, double y)
{
    return hypot(v->pl.p[0] - x, v->pl.p[1] - y);
}

/* ---- tests ---------------------------------------------------------------------------- */

/* The platform's constants reach the tuning (PARAM theta0 is the default
 * Theta of the airframe's mass); before the app task's first spare a live
 * setpoint gets motors off; the output is force/torque on every call. */
static void test_glue_boot_and_platform(void **state)
{
    (void)state;
    static vehicle v;
    memset(&v, 0, sizeof v);
    plant_at(&v.pl, 0.0, 0.0, 0.0, 0.0);
    plant_is_the_platform(&v.pl);
    controllerOutOfTreeInit();
    assert_true(controllerOutOfTreeTest());
    const double zero[3] = {0, 0, 0}, p[3] = {0, 0, 0.5};
    sp_high_level(&v.sp, p, zero, zero, 0.0);
    param_set_u8("track", 1u);
    v.app_flies = true;
    /* the library is not initialised in the stabilizer: no spare yet, motors off */
    ticks(&v, 4);
    assert_int_equal(v.calls_no_thrust, 4);
    assert_int_equal(log_u8("cmd"), 1u);
    app_task_runs(); /* the app task starts: the spare */
    assert_int_equal(log_u8("init"), 0u);
    near_abs((double)param_float("theta0"), (double)CF_MASS, 0.05 * (double)CF_MASS);
    v.calls_no_thrust = 0;
    stabilizer_tick(&v);
    /* tracking begins where the vehicle is, on the ground, toward 0.5 m */
    near_abs((double)log_float("zRef"), 0.0, 1e-3);
    ticks(&v, 5999);
    assert_int_equal(v.calls_no_thrust, 0);
    near_abs(v.pl.p[2], 0.5, 0.03);
    param_set_u8("track", 0u);
    ticks(&v, 2);
    assert_true(v.control.thrustSi == 0.0f);
    assert_int_equal(log_u8("cmd"), 0u);
}

/* LOG: thrust and moments are control_t's (what the mixer gets); the
 * legacy members the firmware's own LOG shows (stabilizer.thrust =
 * control.thrust, controller.ctr_yaw = control.yaw) alias torqueY and half of
 * torqueX in force/torque mode; cycles and cycMax from the core's counter. */
static void test_glue_log(void **state)
{
    (void)state;
    vehicle *v = boot(0.0, 0.0, 0.5);
    param_set_u8("track", 1u);
    const double zero[3] = {0, 0, 0}, p[3] = {0.1, 0, 0.5};
    sp_high_level(&v->sp, p, zero, zero, 30.0);
    cf_test_dwt_step = 1000u;
    ticks(v, 200);
    assert_true(log_float("thrust") == v->control.thrustSi);
    assert_true(log_float("tqX") == v->control.torqueX);
    assert_true(log_float("tqY") == v->control.torqueY);
    assert_true(log_float("tqZ") == v->control.torqueZ);
    assert_true(v->control.thrustSi > 0.0f);
    /* the leftovers of the union: stabilizer.thrust reads torqueY */
    float legacy_thrust;
    memcpy(&legacy_thrust, &v->control.thrust, sizeof legacy_thrust);
    assert_true(legacy_thrust == v->control.torqueY);
    /* and controller.ctr_yaw the low half of torqueX's bits (little-endian) */
    uint32_t torque_x_bits;
    memcpy(&torque_x_bits, &v->control.torqueX, sizeof torque_x_bits);
    assert_int_equal((uint16_t)v->control.yaw, torque_x_bits & 0xFFFFu);
    /* the step between two reads of the counter: one step */
    assert_int_equal(log_u32("cycles"), 1000u);
    cf_test_dwt_step = 7000u;
    ticks(v, 2);
    cf_test_dwt_step = 3000u;
    dwt.CYCCNT = 0xFFFFFFFFu - 4000u; /* the counter wraps within the step */
    ticks(v, 2);
    assert_int_equal(log_u32("cycles"), 3000u);
    assert_int_equal(log_u32("cycMax"), 7000u);
    /* a selection starts the maximum over */
    controllerOutOfTreeInit();
    ticks(v, 2);
    assert_int_equal(log_u32("cycMax"), 3000u);
    cf_test_dwt_step = 0u;
}

/* The high-level commander: take-off, go_to, land, then its stop. */
static void test_glue_high_level_commander(void **state)
{
    (void)state;
    vehicle *v = boot(0.0, 0.0, 0.0);
    param_set_u8("track", 1u);
    const double h = 0.5;
    double p[3], vel[3], acc[3];
    for (int i = 0; i < 4000; i++) { /* take-off to 0.5 m in 2 s */
        const double t = i * 1e-3;
        smooth(0, 0, 2.0, t, &p[0], &vel[0], &acc[0]);
        smooth(0, 0, 2.0, t, &p[1], &vel[1], &acc[1]);
        smooth(0, h, 2.0, t, &p[2], &vel[2], &acc[2]);
        sp_high_level(&v->sp, p, vel, acc, 0.0);
        stabilizer_tick(v);
        if (i > 200) {
            assert_true(fabs(v->pl.p[2] - p[2]) < 0.1);
        }
    }
    near_abs(v->pl.p[2], h, 0.03);
    for (int i = 0; i < 4000; i++) { /* go_to (0.5, 0.3, 0.5) in 2 s, yaw 45 deg */
        const double t = i * 1e-3;
        double yaw, yaw_rate, yaw_acc;
        smooth(0, 0.5, 2.0, t, &p[0], &vel[0], &acc[0]);
        smooth(0, 0.3, 2.0, t, &p[1], &vel[1], &acc[1]);
        smooth(h, h, 2.0, t, &p[2], &vel[2], &acc[2]);
        smooth(0, 45.0, 2.0, t, &yaw, &yaw_rate, &yaw_acc);
        sp_high_level(&v->sp, p, vel, acc, yaw);
        stabilizer_tick(v);
    }
    assert_true(horizontal_distance(v, 0.5, 0.3) < 0.05);
    near_abs(v->pl.p[2], h, 0.03);
    near_abs(plant_yaw_rad(&v->pl), PI / 4, 0.05);
    for (int i = 0; i < 3000; i++) { /* land: to 0 in 2 s */
        const double t = i * 1e-3;
        p[0] = 0.5;
        p[1] = 0.3;
        vel[0] = vel[1] = acc[0] = acc[1] = 0;
        smooth(h, 0.0, 2.0, t, &p[2], &vel[2], &acc[2]);
        sp_high_level(&v->sp, p, vel, acc, 45.0);
        stabilizer_tick(v);
    }
    assert_true(v->pl.p[2] < 0.03);
    assert_true(horizontal_distance(v, 0.5, 0.3) < 0.05);
    assert_int_equal(v->calls_no_thrust, 0);
    memset(&v->sp, 0, sizeof v->sp); /* stop: the null setpoint */
    ticks(v, 2);
    assert_true(v->control.thrustSi == 0.0f);
    assert_int_equal(log_u8("cmd"), 0u);
}

/* MotionCommander: hover setpoints at 10 Hz, forward 0.3 m/s for 2 s with the
 * nose at 90 deg, then up 0.2 m turning at 90 deg/s for 1 s. */
static void test_glue_motion_commander(void **state)
{
    (void)state;
    vehicle *v = boot(0.0, 0.0, 0.5);
    plant_at(&v->pl, 0.0, 0.0, 0.5, PI / 2);
    plant_is_the_platform(&v->pl);
    param_set_u8("track", 1u);
    double z = 0.5;
    for (int i = 0; i < 5000; i++) {
        if (i % 100 == 0) {
            sp_hover(&v->sp, i >= 1000 && i < 3000 ? 0.3 : 0.0, 0, 0, z);
        }
        stabilizer_tick(v);
    }
    near_abs(v->pl.p[1], 0.6, 0.05);
    near_abs(v->pl.p[0], 0.0, 0.05);
    for (int i = 0; i < 4000; i++) {
        if (i % 100 == 0) {
            z = i < 1000 ? 0.5 + 0.2 * (i + 100) / 1000.0 : 0.7;
            sp_hover(&v->sp, 0, 0, i < 1000 ? 90.0 : 0.0, z);
        }
        stabilizer_tick(v);
    }
    near_abs(v->pl.p[2], 0.7, 0.03);
    near_abs(fabs(plant_yaw_rad(&v->pl)), PI, 0.1);
    assert_int_equal(v->calls_no_thrust, 0);
}

/* World-frame velocity setpoints at 10 Hz: 0.2 m/s along x and 0.1 m/s up
 * for 2 s while turning at 30 deg/s, then zero: the vehicle ends 0.4 m
 * along x and 0.2 m higher, turned 60 deg. */
static void test_glue_velocity_world(void **state)
{
    (void)state;
    vehicle *v = boot(0.0, 0.0, 0.5);
    param_set_u8("track", 1u);
    for (int i = 0; i < 5000; i++) {
        if (i % 100 == 0) {
            const bool moving = i >= 1000 && i < 3000;
            sp_velocity_world(&v->sp, moving ? 0.2 : 0.0, 0.0, moving ? 0.1 : 0.0, moving ? 30.0 : 0.0);
        }
        stabilizer_tick(v);
        if (i == 999) {
            /* zero velocities from the start: it holds where it began */
            assert_true(horizontal_distance(v, 0.0, 0.0) < 0.02);
            near_abs(v->pl.p[2], 0.5, 0.02);
        }
    }
    near_abs(v->pl.p[0], 0.4, 0.05);
    near_abs(v->pl.p[1], 0.0, 0.05);
    near_abs(v->pl.p[2], 0.7, 0.03);
    near_abs(plant_yaw_rad(&v->pl), PI / 3, 0.05);
    assert_int_equal(v->calls_no_thrust, 0);
}

/* The commander's setpoints stop: the last one repeats for 0.5 s, the
 * supervisor levels out until 2 s, then its null setpoint. The vehicle
 * stays where it was (not where the command began), keeps its height, and
 * the motors stop at the cut-off. */
static void test_glue_watchdog_level_out_then_cut(void **state)
{
    (void)state;
    vehicle *v = boot(0.0, 0.0, 0.5);
    param_set_u8("track", 1u);
    const double zero[3] = {0, 0, 0};
    double p[3] = {0.0, 0.0, 0.5};
    sp_high_level(&v->sp, p, zero, zero, 0.0);
    ticks(v, 1000);
    p[0] = 0.6;
    sp_high_level(&v->sp, p, zero, zero, 0.0);
    ticks(v, 3000);
    assert_true(horizontal_distance(v, 0.6, 0.0) < 0.05);
    ticks(v, 500); /* the setpoint ages */
    sp_level_out(&v->sp);
    double x_min = 1e9;
    for (int i = 0; i < 1500; i++) {
        stabilizer_tick(v);
        x_min = fmin(x_min, v->pl.p[0]);
    }
    assert_true(x_min > 0.5);
    near_abs(v->pl.p[2], 0.5, 0.05);
    assert_int_equal(v->calls_no_thrust, 0);
    memset(&v->sp, 0, sizeof v->sp);
    ticks(v, 2);
    assert_true(v->control.thrustSi == 0.0f);
}

/* stabilizer.controller = OutOfTree in flight: updateStateEstimatorAndControllerTypes
 * calls controllerOutOfTreeInit, then the same tick calls the controller.
 * The gap is the calls without thrust from there; a selection from below
 * the commander's height starts z_r at the vehicle too. */
static void test_glue_in_flight_switch(void **state)
{
    (void)state;
    const double starts[2] = {0.6, 0.4};
    for (int k = 0; k < 2; k++) {
        vehicle *v = boot(0.3, -0.2, starts[k]);
        v->app_flies = false; /* the PID controller hovers */
        param_set_u8("track", 1u);
        const double zero[3] = {0, 0, 0}, p[3] = {0.3, -0.2, 0.5};
        sp_high_level(&v->sp, p, zero, zero, 0.0);
        ticks(v, 3); /* the stabilizer's phase is not the app's */
        controllerOutOfTreeInit();
        v->app_flies = true;
        stabilizer_tick(v);
        const int gap_calls = v->calls_no_thrust;
        const double first_thrust = (double)v->control.thrustSi / (v->pl.mass_kg * PLANT_G);
        near_abs((double)log_float("zRef"), starts[k], 1e-3);
        double z_min = 1e9, z_max = -1e9;
        for (int i = 0; i < 6000; i++) {
            stabilizer_tick(v);
            z_min = fmin(z_min, v->pl.p[2]);
            z_max = fmax(z_max, v->pl.p[2]);
        }
        print_message("in-flight switch at %.1f m through cf_glue.c: %d of %d calls without thrust (first call: %d), "
                      "first thrust %.3f of the weight, height %.3f..%.3f m toward 0.5 m\n",
                      starts[k], v->calls_no_thrust, v->calls, gap_calls, first_thrust, z_min, z_max);
        assert_int_equal(v->calls_no_thrust, 0);
        assert_true(first_thrust > 0.5 && first_thrust < 1.5);
        /* no dip below the lower of start and target, no climb above the higher */
        assert_true(z_min > fmin(starts[k], 0.5) - 0.02);
        assert_true(z_max < fmax(starts[k], 0.5) + 0.02);
        near_abs(v->pl.p[2], 0.5, 0.03);
    }
}

/* HOLD -> TRACK -> LAND by PARAM mission and track, the commander holding
 * the pad's centre; then reinit in flight. z_r and the horizontal setpoint
 * stay continuous at each switch, no call without thrust. */
static void test_glue_hold_track_land(void **state)
{
    (void)state;
    vehicle *v = boot(0.0, 0.0, 0.6);
    const double zero[3] = {0, 0, 0}, p[3] = {0.0, 0.0, 0.6};
    sp_high_level(&v->sp, p, zero, zero, 0.0);
    param_set_u8("mission", 1u);
    ticks(v, 3000);
    assert_int_equal(log_u8("cmd"), 2u);
    const uint8_t missions[2] = {0u, 2u};
    const uint8_t commands[2] = {1u, 3u};
    for (int m = 0; m < 2; m++) {
        const float z_ref_before = log_float("zRef");
        param_set_u8("mission", missions[m]);
        param_set_u8("track", 1u);
        ticks(v, 2); /* a step falls in these two calls */
        assert_int_equal(log_u8("cmd"), commands[m]);
        near_abs((double)log_float("zRef"), (double)z_ref_before, 0.01);
        near_abs((double)log_float("zRef"), (double)v->pl.p[2], 0.02);
        ticks(v, 3000);
        assert_true(horizontal_distance(v, 0.0, 0.0) < 0.05);
    }
    assert_int_equal(v->calls_no_thrust, 0);
    /* reinit in flight: reads back 0, wakes the app task, no gap */
    param_set_u8("mission", 0u);
    ticks(v, 2000);
    param_set_float("zBias", param_float("zBias") + 0.05f);
    const int woken = notifications;
    param_set_u8("reinit", 1u);
    ticks(v, 1);
    assert_int_equal(param_u8("reinit"), 0u);
    assert_true(notifications > woken);
    app_task_runs();
    ticks(v, 2000);
    assert_int_equal(v->calls_no_thrust, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_glue_boot_and_platform),
        cmocka_unit_test(test_glue_log),
        cmocka_unit_test(test_glue_high_level_commander),
        cmocka_unit_test(test_glue_motion_commander),
        cmocka_unit_test(test_glue_velocity_world),
        cmocka_unit_test(test_glue_watchdog_level_out_then_cut),
        cmocka_unit_test(test_glue_in_flight_switch),
        cmocka_unit_test(test_glue_hold_track_land),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
