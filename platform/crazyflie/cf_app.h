/*
 * cf_app.h - the Crazyflie app's life cycle, without a Crazyflie header so
 * that the host tests replay the firmware's flows through it: selection of
 * the controller (controllerOutOfTreeInit), the 1 kHz calls of the
 * stabilizer (controllerOutOfTree), and the app task that initialises the
 * library (appMain).
 *
 * The hand-over. fc_controller_init needs more stack than the stabilizer
 * task has, so the app task initialises spare controllers in the
 * background, at boot and whenever a parameter changes, into two slots: it
 * writes the slot that is not published and then publishes it, so a whole
 * spare is there at every moment after the first, also while the next one
 * is being made. A start (the controller selected, a command after DISARM,
 * reinit) copies the published spare into the live controller: no
 * initialisation waits in the flight path, so a switch in flight has no
 * motor gap. The first step after a selection is taken on the first call,
 * and every second call from there (500 Hz). Only a selection before the
 * app task has published its first spare (at boot) waits, motors off.
 *
 * Concurrency: one writer per field. The stabilizer task (priority 5)
 * calls cf_app_select and cf_app_tick; the app task (lower) calls
 * cf_app_worker, which writes only the slot that is not published and then
 * the index; the stabilizer reads only the published slot; the stabilizer
 * preempts the app task, never the reverse.
 */
#ifndef CF_APP_H
#define CF_APP_H

#include <stdbool.h>
#include <stdint.h>

#include "cf_convert.h"

/* What the user sets (PARAM fcssc), read by the stabilizer at each step. */
typedef struct cf_app_commands {
    uint8_t mission;        /* CF_MISSION_* */
    uint8_t track;          /* with CF_MISSION_FOLLOW: the command */
    bool reinit;            /* take a spare made from the present tuning now */
} cf_app_commands;

typedef struct cf_app {
    fc_controller live;             /* the one that flies */
    fc_controller spare[2];         /* freshly initialised by the app task */
    cf_tuning spare_tuning[2];      /* what each spare was made from */
    uint8_t spare_result[2];        /* fc_init_result of each spare */
    volatile uint8_t published;     /* 1 + the slot of the newest whole spare; 0 none yet (all zero: cf_app_reset's) */
    fc_controller_params params;    /* the app task's scratch */
    bool live_usable;               /* live is a copy of a spare that initialised */
    bool select_pending;            /* selected: the next step takes the spare */
    bool reinit_pending;            /* reinit asked: taken once the spare matches the tuning */
    uint8_t tick_phase;             /* calls since the last step */
    cf_session session;
    fc_controller_inputs inputs;
    fc_controller_outputs outputs;
    cf_force_torque held;           /* the last step's output, written on every call */
    cf_telemetry telemetry;
} cf_app;

/* Everything cleared; no spare yet. */
void cf_app_reset(cf_app *app);

/* The app task's work: prepare the tuning (a variant change loads its gains)
 * and, when no spare is published or the published one was made from
 * another tuning, make one in the other slot and publish it. Returns true
 * when it made one. */
bool cf_app_worker(cf_app *app, cf_tuning *tuning);

/* fc_init_result of the published spare; FC_INIT_BAD_PARAM before the first. */
uint8_t cf_app_spare_result(const cf_app *app);

/* controllerOutOfTreeInit: the controller is selected (at boot, or in flight);
 * everything of the app's starts over and the next call steps. */
void cf_app_select(cf_app *app);

/* One call of the stabilizer's 1 kHz loop: steps the library on the first
 * call after a selection and every second call from there; app->held is
 * what to write into control_t. Returns true when it stepped. */
bool cf_app_tick(cf_app *app, const cf_sample *s, const cf_tuning *tuning, const cf_app_commands *cmd);

#endif /* CF_APP_H */
