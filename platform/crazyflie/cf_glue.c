/*
 * cf_glue.c - the fc flight controller as crazyflie-firmware's out-of-tree
 * controller (CONFIG_CONTROLLER_OOT; select it with stabilizer.controller).
 *
 * Thin on purpose: fields are copied out of the firmware's structs into a
 * cf_sample and back into control_t; every conversion and decision is in
 * cf_convert.c, which the host tests cover. The only calls into the library are
 * fc_controller_init and fc_controller_step (fc/controller.h).
 *
 * Timing: the stabilizer calls the controller on every tick of its 1 kHz loop;
 * the library steps at ATTITUDE_RATE (500 Hz, its dt is CF_STEP_DT_S) and the
 * output of the last step is written again on the ticks in between, with
 * controlMode set on every call.
 *
 * Initialisation runs in the app task: fc_controller_init needs over 2 KB of
 * stack (the allocation's pseudo-inverse), more than the stabilizer task has
 * (STABILIZER_TASK_STACKSIZE, 1.8 KB, which calls controllerOutOfTreeInit when
 * stabilizer.controller changes) or the system task (1.2 KB, at boot). Init
 * and the start of a command only ask for it; appMain (CONFIG_APP_STACKSIZE in
 * app-config) does it, and until it is done the stabilizer leaves the library
 * alone and the motors off.
 *
 * Output: controlModeForceTorque, the library's body thrust (N) and body
 * moments (N m). The firmware's own mixer then applies the motor order, arm
 * length, THRUST2TORQUE, battery compensation and idle thrust it knows; the
 * library's allocation still runs on the same Crazyflie model (arm 0.046 m,
 * 0.12 N per motor, torque/thrust 0.00699 m) and feeds its saturation back to
 * the altitude and attitude integrators.
 */
#include <stddef.h>

#include "autoconf.h" /* first: without CONFIG_CONTROLLER_OOT, controller.h hides the prototypes below */
#include "FreeRTOS.h"
#include "app.h"
#include "controller.h"
#include "log.h"
#include "param.h"
#include "range.h"
#include "stabilizer_types.h"
#include "task.h"

#include "cf_convert.h"
#include "fc/controller.h"

#if !defined(CONFIG_CONTROLLER_OOT) || !defined(CONFIG_APP_ENABLE)
#error "the fc app needs CONFIG_CONTROLLER_OOT=y and CONFIG_APP_ENABLE=y (see app-config)"
#endif

_Static_assert(modeDisable == CF_MODE_DISABLE && modeAbs == CF_MODE_ABS, "stab_mode_t values differ");
_Static_assert(RATE_MAIN_LOOP == 1000 && ATTITUDE_RATE == 500, "CF_STEP_DT_S assumes 500 Hz of a 1 kHz loop");

/* Static, not on the stabilizer task's stack. */
static fc_controller ctl;
static fc_controller_params params;
static fc_controller_inputs inputs;
static fc_controller_outputs outputs;
static cf_session session;
static cf_force_torque held;   /* the last step's output, written on every tick */
static cf_telemetry telemetry; /* LOG fcssc */
static bool usable;            /* the last (re)initialisation succeeded */

/* PARAM fcssc */
static cf_tuning tuning = CF_TUNING_INITIALIZER;
static uint8_t track;  /* 0: motors off; 1: track the pad (fc_controller_command) */
static uint8_t mission; /* CF_MISSION_*: 0 follow track, 1 hold, 2 land */
static uint8_t reinit; /* write 1: re-initialise with the present parameters */

/* Requests to (re)initialise, served by appMain. Each counter has one writer. */
static volatile uint32_t init_requested; /* the stabilizer (or Init) */
static volatile uint32_t init_done;      /* appMain: the request it served last */
static volatile bool init_has_height;    /* false: the approach starts from z_init */
static volatile float init_z_m, init_pad_z_m;
static TaskHandle_t volatile worker;   /* the app task, once appMain runs */

static void request_init(bool has_height, float z_m, float pad_z_m)
{
    init_has_height = has_height;
    init_z_m = z_m;
    init_pad_z_m = pad_z_m;
    __sync_synchronize();
    init_requested = init_requested + 1u;
    if (worker != NULL) {
        xTaskNotifyGive(worker);
    }
}

static bool init_pending(void)
{
    return init_done != init_requested;
}

/* (Re)initialise the library with the tuning (in the app task). */
static void setup(bool has_height, float z_m, float pad_z_m)
{
    (void)cf_tuning_prepare(&tuning);
    const float offset = has_height ? cf_approach_offset_m(&tuning, z_m, pad_z_m) : tuning.z_init;
    fc_init_result result = FC_INIT_BAD_PARAM;
    if (cf_params_from_tuning(&tuning, offset, &params)) {
        result = fc_controller_init(&ctl, &params);
    }
    telemetry.init_result = (uint8_t)result;
    usable = result == FC_INIT_OK;
}

void appMain(void)
{
    worker = xTaskGetCurrentTaskHandle();
    for (;;) {
        const uint32_t request = init_requested;
        if (request != init_done) {
            __sync_synchronize();
            setup(init_has_height, init_z_m, init_pad_z_m);
            __sync_synchronize();
            init_done = request;
        }
        (void)ulTaskNotifyTake(pdTRUE, M2T(100));
    }
}

void controllerOutOfTreeInit(void)
{
    /* runs at boot and again whenever stabilizer.controller selects this
     * controller: everything starts over */
    cf_session_reset(&session);
    held = (cf_force_torque){0};
    telemetry.command = (uint8_t)FC_COMMAND_DISARM;
    reinit = 0u;
    request_init(false, 0.0f, 0.0f);
}

bool controllerOutOfTreeTest(void)
{
    /* the initialisation runs later, in the app task: its result is LOG fcssc.init */
    return true;
}

static void step(const setpoint_t *setpoint, const sensorData_t *sensors, const state_t *state)
{
    cf_sample s;
    s.gyro_dps[0] = sensors->gyro.x;
    s.gyro_dps[1] = sensors->gyro.y;
    s.gyro_dps[2] = sensors->gyro.z;
    s.acc_g[0] = sensors->acc.x;
    s.acc_g[1] = sensors->acc.y;
    s.acc_g[2] = sensors->acc.z;
    s.quat_xyzw[0] = state->attitudeQuaternion.x;
    s.quat_xyzw[1] = state->attitudeQuaternion.y;
    s.quat_xyzw[2] = state->attitudeQuaternion.z;
    s.quat_xyzw[3] = state->attitudeQuaternion.w;
    s.yaw_deg = state->attitude.yaw;
    s.pos_m[0] = state->position.x;
    s.pos_m[1] = state->position.y;
    s.pos_m[2] = state->position.z;
    s.vel_mps[0] = state->velocity.x;
    s.vel_mps[1] = state->velocity.y;
    s.vel_mps[2] = state->velocity.z;
    s.sp_pos_m[0] = setpoint->position.x;
    s.sp_pos_m[1] = setpoint->position.y;
    s.sp_pos_m[2] = setpoint->position.z;
    s.sp_yaw_deg = setpoint->attitude.yaw;
    s.sp_thrust = setpoint->thrust;
    s.sp_mode_x = (uint8_t)setpoint->mode.x;
    s.sp_mode_y = (uint8_t)setpoint->mode.y;
    s.sp_mode_z = (uint8_t)setpoint->mode.z;
    s.sp_mode_yaw = (uint8_t)setpoint->mode.yaw;
    s.range_mm = rangeGet(rangeDown);

    const fc_controller_command command = cf_command(mission, track, &s);
    if (cf_session_begin(&session, command, &s) || reinit != 0u) {
        reinit = 0u;
        request_init(true, s.pos_m[2], cf_pad_height_m(&session, &tuning));
    }
    fc_step_status status = FC_STEP_NOT_READY;
    cf_range_step(&session, s.range_mm, &tuning);
    if (!init_pending() && usable) {
        cf_inputs_from_sample(&s, &session, &tuning, command, &inputs);
        status = fc_controller_step(&ctl, &inputs, &outputs);
    } else {
        outputs = (fc_controller_outputs){0}; /* motors off */
    }
    cf_force_torque_from_outputs(&outputs, &held);
    cf_telemetry_from_outputs(&outputs, status, command, cf_pad_height_m(&session, &tuning), session.range_m,
                              &telemetry);
    cf_pad_advance(&session, &tuning, CF_STEP_DT_S);
}

void controllerOutOfTree(control_t *control, const setpoint_t *setpoint, const sensorData_t *sensors,
                         const state_t *state, const stabilizerStep_t stabilizerStep)
{
    if (RATE_DO_EXECUTE(ATTITUDE_RATE, stabilizerStep)) {
        step(setpoint, sensors, state);
    }
    control->controlMode = controlModeForceTorque;
    control->thrustSi = held.thrust_n;
    control->torqueX = held.torque_nm[0];
    control->torqueY = held.torque_nm[1];
    control->torqueZ = held.torque_nm[2];
}

/**
 * The fc controller: start and stop the pad tracking and the landing mission,
 * tune the altitude law. Gains take effect at the next (re)initialisation:
 * when a command starts from motors off, when reinit is written 1, or when
 * the controller is selected again.
 */
PARAM_GROUP_START(fcssc)
/** @brief Landing mission: 0 as track says, 1 hold above the pad and learn it (aborts a descent), 2 land (needs a live commander setpoint) */
PARAM_ADD(PARAM_UINT8, mission, &mission)
/** @brief With mission 0: 0 motors off (the controller's DISARM); 1 track the pad (needs a live commander setpoint) */
PARAM_ADD(PARAM_UINT8, track, &track)
/** @brief Write 1 to re-initialise with the parameters below (reads back 0 when done) */
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
LOG_ADD(LOG_FLOAT, sigma, &telemetry.sigma)
/** @brief sigma_tilde, the relay's input [m/s] */
LOG_ADD(LOG_FLOAT, sigmaT, &telemetry.sigma_tilde)
/** @brief Modulation rho in use [N] */
LOG_ADD(LOG_FLOAT, rho, &telemetry.rho)
/** @brief Theta [kg] */
LOG_ADD(LOG_FLOAT, theta, &telemetry.theta)
/** @brief Averaged relay output u0_av [N] */
LOG_ADD(LOG_FLOAT, u0av, &telemetry.u0_av)
/** @brief Nominal control u_nom [N] */
LOG_ADD(LOG_FLOAT, unom, &telemetry.u_nom)
/** @brief Tracking error e = z - z_r [m] */
LOG_ADD(LOG_FLOAT, err, &telemetry.error)
/** @brief Reference z_r [m] */
LOG_ADD(LOG_FLOAT, zRef, &telemetry.z_ref)
/** @brief Reference speed z_r' [m/s] */
LOG_ADD(LOG_FLOAT, vzRef, &telemetry.vz_ref)
/** @brief Pad height z_d [m] */
LOG_ADD(LOG_FLOAT, padZ, &telemetry.pad_z)
/** @brief Body thrust command [N] */
LOG_ADD(LOG_FLOAT, thrust, &telemetry.thrust)
/** @brief Body moments [N m] */
LOG_ADD(LOG_FLOAT, tqX, &telemetry.torque[0])
LOG_ADD(LOG_FLOAT, tqY, &telemetry.torque[1])
LOG_ADD(LOG_FLOAT, tqZ, &telemetry.torque[2])
/** @brief fc_step_status bits: 1 not ready, 2 bad input, 4 output limited, 8 fixed-point saturated, 16 degraded */
LOG_ADD(LOG_UINT16, status, &telemetry.status)
/** @brief Command in effect: 0 disarmed (motors off), 1 tracking the pad, 2 hold, 3 land */
LOG_ADD(LOG_UINT8, cmd, &telemetry.command)
/** @brief Result of the last (re)initialisation: 0 ok, 1 bad parameter, 2 rank deficient */
LOG_ADD(LOG_UINT8, init, &telemetry.init_result)
/** @brief Allocation saturation bits (FC_SAT_*) */
LOG_ADD(LOG_UINT8, sat, &telemetry.saturation)
/** @brief Landing state (fc_landing_state): 0 idle, 1 hold, 2 observe, 3 descend, 4 touchdown, 5 disarm (ramp), 6 landed, 7 abort, 8 failsafe */
LOG_ADD(LOG_UINT8, lState, &telemetry.landing_state)
/** @brief Reason of the newest landing transition (fc_landing_reason) */
LOG_ADD(LOG_UINT8, lReason, &telemetry.landing_reason)
/** @brief Aborts since the landing mission started */
LOG_ADD(LOG_UINT8, aborts, &telemetry.aborts)
/** @brief 1: the landing plan expects contact from now on */
LOG_ADD(LOG_UINT8, tdWin, &telemetry.touchdown_window)
/** @brief Confidence in the pad's prediction [0..1] */
LOG_ADD(LOG_FLOAT, padConf, &telemetry.pad_confidence)
/** @brief The pad's height learnt from the range finder [m] */
LOG_ADD(LOG_FLOAT, padEstZ, &telemetry.pad_est_z)
/** @brief The pad's vertical speed learnt from the range finder [m/s] */
LOG_ADD(LOG_FLOAT, padEstVz, &telemetry.pad_est_vz)
/** @brief Period of the pad's dominant heave [s] */
LOG_ADD(LOG_FLOAT, padPer, &telemetry.pad_period)
/** @brief Gear above the pad from the range finder [m] */
LOG_ADD(LOG_FLOAT, gearH, &telemetry.gear_height)
/** @brief Range input: the newest usable ranger sample, CG to the pad [m] */
LOG_ADD(LOG_FLOAT, range, &telemetry.range)
LOG_GROUP_STOP(fcssc)
