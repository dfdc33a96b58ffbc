/* cf_app.c - the Crazyflie app's life cycle (cf_app.h). */
#include "cf_app.h"

#include <string.h>

void cf_app_reset(cf_app *app)
{
    memset(app, 0, sizeof *app);
    app->spare_result[0] = app->spare_result[1] = (uint8_t)FC_INIT_BAD_PARAM;
    cf_session_reset(&app->session);
    app->telemetry.command = (uint8_t)FC_COMMAND_DISARM;
}

uint8_t cf_app_spare_result(const cf_app *app)
{
    const uint8_t published = app->published;
    return published != 0u ? app->spare_result[published - 1u] : (uint8_t)FC_INIT_BAD_PARAM;
}

bool cf_app_worker(cf_app *app, cf_tuning *tuning)
{
    (void)cf_tuning_prepare(tuning);
    cf_tuning snapshot;
    memcpy(&snapshot, tuning, sizeof snapshot);
    const uint8_t published = app->published;
    if (published != 0u && memcmp(&snapshot, &app->spare_tuning[published - 1u], sizeof snapshot) == 0) {
        return false;
    }
    /* the slot the stabilizer does not read */
    const uint8_t slot = published == 1u ? 1u : 0u;
    fc_init_result result = FC_INIT_BAD_PARAM;
    /* the library's own approach offset is 0: the app shapes the approach (cf_track_trajectory) */
    if (cf_params_from_tuning(&snapshot, 0.0f, &app->params)) {
        result = fc_controller_init(&app->spare[slot], &app->params);
    }
    memcpy(&app->spare_tuning[slot], &snapshot, sizeof snapshot);
    app->spare_result[slot] = (uint8_t)result;
    __sync_synchronize();
    app->published = (uint8_t)(slot + 1u);
    return true;
}

void cf_app_select(cf_app *app)
{
    cf_session_reset(&app->session);
    app->held = (cf_force_torque){0};
    app->telemetry.command = (uint8_t)FC_COMMAND_DISARM;
    app->telemetry.step_cycles_max = 0u;
    app->select_pending = true;
    app->reinit_pending = false;
    app->tick_phase = 0u;
}

/* The live controller starts over as a copy of the published spare. */
static void take_spare(cf_app *app)
{
    const uint8_t slot = (uint8_t)(app->published - 1u);
    memcpy(&app->live, &app->spare[slot], sizeof app->live);
    app->live_usable = app->spare_result[slot] == (uint8_t)FC_INIT_OK;
    app->telemetry.init_result = app->spare_result[slot];
}

static bool spare_ready(const cf_app *app)
{
    return app->published != 0u;
}

static bool spare_matches(const cf_app *app, const cf_tuning *tuning)
{
    return spare_ready(app) && memcmp(&app->spare_tuning[app->published - 1u], tuning, sizeof *tuning) == 0;
}

/* Which controller this step flies: a selection or a start takes the
 * published spare (a start before the first flies the live one, reset by
 * its DISARM); reinit takes it once it was made from the present tuning. */
static void choose_controller(cf_app *app, bool began, const cf_tuning *tuning)
{
    if (app->select_pending) {
        if (spare_ready(app)) {
            take_spare(app);
            app->select_pending = false;
        }
    } else if (app->reinit_pending) {
        if (spare_matches(app, tuning)) {
            take_spare(app);
            app->reinit_pending = false;
        }
    } else if (began && spare_ready(app)) {
        take_spare(app);
    } else {
        /* the live controller flies on */
    }
}

static void step(cf_app *app, const cf_sample *s, const cf_tuning *tuning, const cf_app_commands *cmd)
{
    cf_session *ss = &app->session;
    const fc_controller_command command = cf_command(cmd->mission, cmd->track, s);
    const bool began = cf_session_begin(ss, command, s, tuning);
    choose_controller(app, began, tuning);
    const bool flies = !app->select_pending && app->live_usable;
    if (!flies) {
        /* motors off: the command begins (setpoint and approach from the
         * vehicle) at the first step that flies */
        cf_session_reset(ss);
    }
    cf_range_step(ss, s->range_mm, tuning);
    fc_step_status status = FC_STEP_NOT_READY;
    if (flies) {
        if (command != FC_COMMAND_DISARM) {
            cf_setpoint_step(ss, s, tuning, CF_STEP_DT_S);
        }
        cf_inputs_from_sample(s, ss, tuning, command, &app->inputs);
        status = fc_controller_step(&app->live, &app->inputs, &app->outputs);
    } else {
        app->outputs = (fc_controller_outputs){0}; /* motors off */
    }
    cf_force_torque_from_outputs(&app->outputs, &app->held);
    cf_telemetry_from_outputs(&app->outputs, status, command, cf_pad_height_m(ss, tuning), ss->range_m,
                              &app->telemetry);
    cf_pad_advance(ss, tuning, CF_STEP_DT_S);
}

bool cf_app_tick(cf_app *app, const cf_sample *s, const cf_tuning *tuning, const cf_app_commands *cmd)
{
    if (cmd->reinit) {
        app->reinit_pending = true;
    }
    const bool step_now = app->tick_phase == 0u;
    app->tick_phase = step_now ? 1u : 0u;
    if (step_now) {
        step(app, s, tuning, cmd);
    }
    return step_now;
}
