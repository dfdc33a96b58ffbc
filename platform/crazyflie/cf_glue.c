/*
 * cf_glue.c - the fc flight controller as crazyflie-firmware's out-of-tree
 * controller (CONFIG_CONTROLLER_OOT; select it with stabilizer.controller).
 *
 * Thin on purpose: fields are copied out of the firmware's structs into a
 * cf_sample and back into control_t; the app's life cycle is cf_app.c and
 * every conversion and decision cf_convert.c, which the host tests cover.
 *
 * Timing: the stabilizer calls the controller on every tick of its 1 kHz
 * loop; the library steps at 500 Hz (its dt is CF_STEP_DT_S), on the first
 * call after a selection and every second call from there, and the output
 * of the last step is written again on the calls in between, with
 * controlMode set on every call. LOG fcssc.cycles is the last step's core
 * cycles (DWT), fcssc.cycMax the most since the selection.
 *
 * Initialisation: fc_controller_init needs more stack than the stabilizer
 * task (1.8 KB) has, so the app task (appMain, CONFIG_APP_STACKSIZE in
 * app-config) keeps a spare controller initialised with the present
 * parameters; a selection, a command after DISARM and reinit copy it
 * (cf_app.h). No initialisation waits in the flight path: a switch to this
 * controller in flight flies from its first call.
 *
 * Output: controlModeForceTorque, the library's body thrust (N) and body
 * moments (N m). The firmware's own mixer then applies the motor order, arm
 * length, THRUST2TORQUE, battery compensation and idle thrust it knows.
 */
#include <stddef.h>

#include "autoconf.h" /* first: without CONFIG_CONTROLLER_OOT, controller.h hides the prototypes below */

#if !defined(CONFIG_CONTROLLER_OOT) || !defined(CONFIG_APP_ENABLE)
#error "the fc app needs CONFIG_CONTROLLER_OOT=y and CONFIG_APP_ENABLE=y (see app-config)"
#endif

/* The platforms the app can fly: force and torque go through the quadrotor
 * power distribution (power_distribution_quadrotor.c), in newtons only with
 * the battery-compensated thrust curve of the cf2 or the cf21bl. Checked
 * before any platform header, so that the reason is the first error. */
#if defined(CONFIG_PLATFORM_FLAPPER) || defined(CONFIG_POWER_DISTRIBUTION_FLAPPER)
#error "the fc app cannot fly the Flapper: its power distribution takes legacy control only (it asserts controlModeLegacy), and this app commands force and torque"
#elif !defined(CONFIG_POWER_DISTRIBUTION_QUADROTOR)
#error "the fc app needs the quadrotor power distribution (CONFIG_POWER_DISTRIBUTION_QUADROTOR): it is the one that takes controlModeForceTorque"
#elif !defined(CONFIG_PLATFORM_CF2) && !defined(CONFIG_PLATFORM_CF21BL)
#error "the fc app knows the airframe of the cf2 and cf21bl platforms only: platform_defaults has no calibrated thrust or torque constants for this one"
#elif !defined(CONFIG_ENABLE_THRUST_BAT_COMPENSATED)
#error "the fc app needs CONFIG_ENABLE_THRUST_BAT_COMPENSATED: without it THRUST_MAX and THRUST2TORQUE are placeholders and force mode is not in newtons (legacy PWM only)"
#endif

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

#include "cf_app.h"
#include "cf_convert.h"
#include "fc/controller.h"

_Static_assert(modeDisable == CF_MODE_DISABLE && modeAbs == CF_MODE_ABS && modeVelocity == CF_MODE_VELOCITY,
               "stab_mode_t values differ");
_Static_assert(RATE_MAIN_LOOP == 1000 && ATTITUDE_RATE == 500, "CF_STEP_DT_S assumes 500 Hz of a 1 kHz loop");

/* The platform's constants (platform_defaults_*.h) at compile time. */
static const cf_airframe platform_airframe = {CF_MASS, ARM_LENGTH, THRUST_MAX, THRUST_MIN, THRUST2TORQUE};

/* Static, not on a task's stack; all zero is cf_app_reset's state but for a
 * spare result that nothing reads before the first spare is made. */
static cf_app app;

/* PARAM fcssc */
static cf_tuning tuning = CF_TUNING_INITIALIZER;
static uint8_t track;   /* 0: motors off; 1: track the pad (fc_controller_command) */
static uint8_t mission; /* CF_MISSION_*: 0 follow track, 1 hold, 2 land */
static uint8_t reinit;  /* write 1: restart the controller with the present parameters */

static TaskHandle_t volatile worker; /* the app task, once appMain runs */

static void wake_worker(void)
{
    if (worker != NULL) {
        xTaskNotifyGive(worker);
    }
}

/* The core's cycle counter (DWT), for LOG fcssc.cycles. */
static void cycle_counter_start(void)
{
    CoreDebug->DEMCR |= CoreDebug_DEMCR_TRCENA_Msk;
    DWT->CTRL |= DWT_CTRL_CYCCNTENA_Msk;
}

void appMain(void)
{
    if (!cf_airframe_use(&platform_airframe)) {
        app.telemetry.init_result = (uint8_t)FC_INIT_BAD_PARAM; /* no spare: the motors stay off */
        for (;;) {
            vTaskDelay(M2T(1000));
        }
    }
    worker = xTaskGetCurrentTaskHandle();
    for (;;) {
        /* a parameter written from cfclient is seen within 20 ms */
        (void)cf_app_worker(&app, &tuning);
        (void)ulTaskNotifyTake(pdTRUE, M2T(20));
    }
}

void controllerOutOfTreeInit(void)
{
    /* at boot and whenever stabilizer.controller selects this controller */
    cycle_counter_start();
    cf_app_select(&app);
    reinit = 0u;
    wake_worker();
}

bool controllerOutOfTreeTest(void)
{
    /* the spare is made in the app task: its result is LOG fcssc.init */
    return true;
}

static void sample_of(const setpoint_t *setpoint, const sensorData_t *sensors, const state_t *state, cf_sample *s)
{
    s->gyro_dps[0] = sensors->gyro.x;
    s->gyro_dps[1] = sensors->gyro.y;
    s->gyro_dps[2] = sensors->gyro.z;
    s->acc_g[0] = sensors->acc.x;
    s->acc_g[1] = sensors->acc.y;
    s->acc_g[2] = sensors->acc.z;
    s->quat_xyzw[0] = state->attitudeQuaternion.x;
    s->quat_xyzw[1] = state->attitudeQuaternion.y;
    s->quat_xyzw[2] = state->attitudeQuaternion.z;
    s->quat_xyzw[3] = state->attitudeQuaternion.w;
    s->yaw_deg = state->attitude.yaw;
    s->pos_m[0] = state->position.x;
    s->pos_m[1] = state->position.y;
    s->pos_m[2] = state->position.z;
    s->vel_mps[0] = state->velocity.x;
    s->vel_mps[1] = state->velocity.y;
    s->vel_mps[2] = state->velocity.z;
    s->sp_pos_m[0] = setpoint->position.x;
    s->sp_pos_m[1] = setpoint->position.y;
    s->sp_pos_m[2] = setpoint->position.z;
    s->sp_vel_mps[0] = setpoint->velocity.x;
    s->sp_vel_mps[1] = setpoint->velocity.y;
    s->sp_vel_mps[2] = setpoint->velocity.z;
    s->sp_acc_mps2[0] = setpoint->acceleration.x;
    s->sp_acc_mps2[1] = setpoint->acceleration.y;
    s->sp_acc_mps2[2] = setpoint->acceleration.z;
    s->sp_velocity_body = setpoint->velocity_body;
    s->sp_yaw_deg = setpoint->attitude.yaw;
    s->sp_yaw_rate_dps = setpoint->attitudeRate.yaw;
    s->sp_thrust = setpoint->thrust;
    s->sp_mode_x = (uint8_t)setpoint->mode.x;
    s->sp_mode_y = (uint8_t)setpoint->mode.y;
    s->sp_mode_z = (uint8_t)setpoint->mode.z;
    s->sp_mode_yaw = (uint8_t)setpoint->mode.yaw;
    s->range_mm = rangeGet(rangeDown);
}

void controllerOutOfTree(control_t *control, const setpoint_t *setpoint, const sensorData_t *sensors,
                         const state_t *state, const stabilizerStep_t stabilizerStep)
{
    (void)stabilizerStep; /* the app keeps its own phase from the selection (cf_app_tick) */
    cf_sample s;
    sample_of(setpoint, sensors, state, &s);
    const cf_app_commands cmd = {mission, track, reinit != 0u};
    reinit = 0u;
    const uint32_t start = DWT->CYCCNT;
    if (cf_app_tick(&app, &s, &tuning, &cmd)) {
        const uint32_t cycles = DWT->CYCCNT - start;
        app.telemetry.step_cycles = cycles;
        if (cycles > app.telemetry.step_cycles_max) {
            app.telemetry.step_cycles_max = cycles;
        }
    }
    if (cmd.reinit) {
        wake_worker();
    }
    control->controlMode = controlModeForceTorque;
    control->thrustSi = app.held.thrust_n;
    control->torqueX = app.held.torque_nm[0];
    control->torqueY = app.held.torque_nm[1];
    control->torqueZ = app.held.torque_nm[2];
}

/**
 * The fc controller: start and stop the pad tracking and the landing mission,
 * tune the altitude law. Gains take effect at the next start: when a command
 * starts from motors off, when reinit is written 1, or when the controller is
 * selected again (the app task has a controller ready with them within 20 ms).
 */
PARAM_GROUP_START(fcssc)
/** @brief Landing mission: 0 as track says, 1 hold above the pad and learn it (aborts a descent), 2 land (needs a live commander setpoint) */
PARAM_ADD(PARAM_UINT8, mission, &mission)
/** @brief With mission 0: 0 motors off (the controller's DISARM); 1 track the pad (needs a live commander setpoint) */
PARAM_ADD(PARAM_UINT8, track, &track)
/** @brief Write 1 to restart the controller with the parameters below, in flight without a motor gap (reads back 0) */
PARAM_ADD(PARAM_UINT8, reinit, &reinit)
/** @brief Altitude law: 0 ssc, 1 ssc-adaptive, 2 ssc-norm, ... (fc_altitude_variant); a change loads its gains */
PARAM_ADD(PARAM_UINT8, variant, &tuning.variant)
/** @brief l0 (K1) of sigma = e' + l0 e [1/s] */
PARAM_ADD(PARAM_FLOAT, l0, &tuning.l0)
/** @brief Constant modulation rho [N] */
PARAM_ADD(PARAM_FLOAT, rho, &tuning.rho)
/** @brief Adaptation gain gamma of Theta' = -gamma sigma phi */
PARAM_ADD(PARAM_FLOAT, gamma, &tuning.gamma)
/** @brief Averaging filter time constant tau_av [s] */
PARAM_ADD(PARAM_FLOAT, tauAv, &tuning.tau_av)
/** @brief Prediction-error pole a_m [1/s] */
PARAM_ADD(PARAM_FLOAT, aM, &tuning.a_m)
/** @brief Prediction-error gain kappa_m [1/kg] */
PARAM_ADD(PARAM_FLOAT, kappaM, &tuning.kappa_m)
/** @brief k0 of rho = rho_bar + k0 |sigma_tilde| [N s/m] */
PARAM_ADD(PARAM_FLOAT, k0, &tuning.k0)
/** @brief Margin delta of the norm observer's modulation [N] */
PARAM_ADD(PARAM_FLOAT, delta, &tuning.delta)
/** @brief Nominal Theta = m / (k_h k_g), and Theta at the start [kg] */
PARAM_ADD(PARAM_FLOAT, theta0, &tuning.theta0)
/** @brief Reference time constant tau_zr [s] */
PARAM_ADD(PARAM_FLOAT, tauZr, &tuning.tau_zr)
/** @brief Approach offset z_r_init when offAuto is 0 [m] */
PARAM_ADD(PARAM_FLOAT, zInit, &tuning.z_init)
/** @brief Height held above the pad, z_r_bias [m] */
PARAM_ADD(PARAM_FLOAT, zBias, &tuning.z_bias)
/** @brief 1: the approach starts from the present height (no jump of the reference) */
PARAM_ADD(PARAM_UINT8, offAuto, &tuning.offset_auto)
/** @brief 1: tracking holds the commander's height (z of position, velocity and high-level setpoints); 0: padZ + zBias */
PARAM_ADD(PARAM_UINT8, cmdZ, &tuning.command_z)
/** @brief Virtual pad: mean height [m] */
PARAM_ADD(PARAM_FLOAT, padZ, &tuning.pad_z)
/** @brief Virtual pad: heave amplitude [m] */
PARAM_ADD(PARAM_FLOAT, padAmp, &tuning.pad_amp)
/** @brief Virtual pad: heave frequency [Hz] */
PARAM_ADD(PARAM_FLOAT, padFreq, &tuning.pad_freq)
/** @brief Horizontal PD: acceleration per m of position error [1/s^2] */
PARAM_ADD(PARAM_FLOAT, hKp, &tuning.h_kp)
/** @brief Horizontal PD: acceleration per m/s of velocity [1/s] */
PARAM_ADD(PARAM_FLOAT, hKd, &tuning.h_kd)
/** @brief Range finder: CG to the sensor along body -z, added to its reading [m] (at once; calibrate: gearH reads 0 on the ground) */
PARAM_ADD(PARAM_FLOAT, rngOff, &tuning.range_offset_m)
PARAM_GROUP_STOP(fcssc)

/**
 * The fc controller's altitude law and state.
 */
LOG_GROUP_START(fcssc)
/** @brief Sliding variable sigma (sigma_hat without z') [m/s] */
LOG_ADD(LOG_FLOAT, sigma, &app.telemetry.sigma)
/** @brief sigma_tilde, the relay's input [m/s] */
LOG_ADD(LOG_FLOAT, sigmaT, &app.telemetry.sigma_tilde)
/** @brief Modulation rho in use [N] */
LOG_ADD(LOG_FLOAT, rho, &app.telemetry.rho)
/** @brief Theta [kg] */
LOG_ADD(LOG_FLOAT, theta, &app.telemetry.theta)
/** @brief Averaged relay output u0_av [N] */
LOG_ADD(LOG_FLOAT, u0av, &app.telemetry.u0_av)
/** @brief Nominal control u_nom [N] */
LOG_ADD(LOG_FLOAT, unom, &app.telemetry.u_nom)
/** @brief Tracking error e = z - z_r [m] */
LOG_ADD(LOG_FLOAT, err, &app.telemetry.error)
/** @brief Reference z_r [m] */
LOG_ADD(LOG_FLOAT, zRef, &app.telemetry.z_ref)
/** @brief Reference speed z_r' [m/s] */
LOG_ADD(LOG_FLOAT, vzRef, &app.telemetry.vz_ref)
/** @brief Pad height z_d [m] */
LOG_ADD(LOG_FLOAT, padZ, &app.telemetry.pad_z)
/** @brief Body thrust commanded (control.thrustSi; stabilizer.thrust does not show it in force/torque mode) [N] */
LOG_ADD(LOG_FLOAT, thrust, &app.telemetry.thrust)
/** @brief Body moments commanded (control.torqueX/Y/Z) [N m] */
LOG_ADD(LOG_FLOAT, tqX, &app.telemetry.torque[0])
LOG_ADD(LOG_FLOAT, tqY, &app.telemetry.torque[1])
LOG_ADD(LOG_FLOAT, tqZ, &app.telemetry.torque[2])
/** @brief fc_step_status bits: 1 not ready, 2 bad input, 4 output limited, 8 fixed-point saturated, 16 degraded */
LOG_ADD(LOG_UINT16, status, &app.telemetry.status)
/** @brief Command in effect: 0 disarmed (motors off), 1 tracking the pad, 2 hold, 3 land */
LOG_ADD(LOG_UINT8, cmd, &app.telemetry.command)
/** @brief Result of the last (re)initialisation: 0 ok, 1 bad parameter, 2 rank deficient */
LOG_ADD(LOG_UINT8, init, &app.telemetry.init_result)
/** @brief Allocation saturation bits (FC_SAT_*) */
LOG_ADD(LOG_UINT8, sat, &app.telemetry.saturation)
/** @brief Landing state (fc_landing_state): 0 idle, 1 hold, 2 observe, 3 descend, 4 touchdown, 5 disarm (ramp), 6 landed, 7 abort, 8 failsafe */
LOG_ADD(LOG_UINT8, lState, &app.telemetry.landing_state)
/** @brief Reason of the newest landing transition (fc_landing_reason) */
LOG_ADD(LOG_UINT8, lReason, &app.telemetry.landing_reason)
/** @brief Aborts since the landing mission started */
LOG_ADD(LOG_UINT8, aborts, &app.telemetry.aborts)
/** @brief 1: the landing plan expects contact from now on */
LOG_ADD(LOG_UINT8, tdWin, &app.telemetry.touchdown_window)
/** @brief Confidence in the pad's prediction [0..1] */
LOG_ADD(LOG_FLOAT, padConf, &app.telemetry.pad_confidence)
/** @brief The pad's height learnt from the range finder [m] */
LOG_ADD(LOG_FLOAT, padEstZ, &app.telemetry.pad_est_z)
/** @brief The pad's vertical speed learnt from the range finder [m/s] */
LOG_ADD(LOG_FLOAT, padEstVz, &app.telemetry.pad_est_vz)
/** @brief Period of the pad's dominant heave [s] */
LOG_ADD(LOG_FLOAT, padPer, &app.telemetry.pad_period)
/** @brief Gear above the pad from the range finder [m] */
LOG_ADD(LOG_FLOAT, gearH, &app.telemetry.gear_height)
/** @brief Range input: the newest usable ranger sample, CG to the pad [m] */
LOG_ADD(LOG_FLOAT, range, &app.telemetry.range)
/** @brief Core cycles of the last controller step (DWT; 168 per microsecond) */
LOG_ADD(LOG_UINT32, cycles, &app.telemetry.step_cycles)
/** @brief Most core cycles of a step since the controller was selected */
LOG_ADD(LOG_UINT32, cycMax, &app.telemetry.step_cycles_max)
LOG_GROUP_STOP(fcssc)
