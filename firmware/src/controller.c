/* controller.c - the flight controller's one entry point (fc/controller.h).
 *
 * fc_controller_step is the sequence of the parts below, each with its own
 * state in fc_controller (one struct a part) and its own section here:
 *   heading        the setpoint's heading, its trigonometry cached
 *   sense          the attitude and rate in use (filter or platform)
 *   mission        the command, arming, a new task's clean start
 *   guard          the input gates, the failsafe's watch, the held height
 *   pad samples    the range finder's gear height and pad samples, the pad
 *                  model in its minor frame
 *   rate groups    the minor frame; the position loop's held setpoint
 *   vertical plan  what the thrust follows: the reference, the landing's
 *                  ramp, or the failsafe's descent
 *   flight         the altitude law, the attitude setpoint and law, the
 *                  allocation (or the velocity output)
 * The airframe presets are controller_params.c's. */
#include "fc/controller.h"
#include "controller_params.h"

#include <stddef.h>

/* ---------------------------------------------------------------------- */
/* outputs and resets                                                     */
/* ---------------------------------------------------------------------- */

static void motors_off(const fc_controller *ctl, fc_controller_outputs *out)
{
    for (int i = 0; i < FC_MAX_ROTORS; i++) {
        out->rotor_speed[i] = FC_INT(0, UNIT);
    }
    out->rotor_count = ctl->ready ? ctl->allocation.rotor_count : 0u;
    out->motors_on = false;
    out->thrust_n = FC_INT(0, FORCE);
    out->moment_nm = fc_vec3_zero();
    out->output = ctl->ready ? ctl->p.output : FC_OUTPUT_ROTORS;
    out->velocity_cmd_mps = fc_vec3_zero();
    out->yaw_rate_cmd_radps = FC_INT(0, RATE);
    if (out->output == FC_OUTPUT_VELOCITY) {
        out->rotor_count = 0u; /* no rotor output in this mode */
    }
}

static void reset_loops(fc_controller *ctl)
{
    fc_altitude_control_reset(&ctl->altitude);
    fc_attitude_control_reset(&ctl->attitude);
    fc_allocation_reset(&ctl->allocation);
    fc_position_control_reset(&ctl->position);
    ctl->groups.have_demand = false;
    ctl->groups.have_attitude_setpoint = false; /* level until the position loop's next attitude frame */
    ctl->last_saturation = 0u;
    ctl->last_thrust_n = FC_INT(0, FORCE);
}

/* The bits of a module's status that the controller passes on. */
static fc_step_status passed_on(fc_step_status module_status)
{
    return module_status & (FC_STEP_BAD_INPUT | FC_STEP_OUTPUT_LIMITED | FC_STEP_ARITH_SATURATED | FC_STEP_DEGRADED);
}

/* The telemetry fields that only some paths of a ready step write (the
 * failsafe has no reference, a disarmed step runs no loop): their values when
 * not written. The others every path of a ready step writes once. */
static void telemetry_defaults(fc_controller_telemetry *tm)
{
    tm->reference.z_m = FC_INT(0, LENGTH);
    tm->reference.vz_mps = FC_INT(0, VEL);
    tm->reference.az_mps2 = FC_INT(0, ACCEL);
    tm->allocation_saturation = 0u;
    tm->altitude_status = FC_STEP_OK;
    tm->attitude_status = FC_STEP_OK;
    tm->allocation_status = FC_STEP_OK;
    tm->touchdown_window = false;
    tm->descent_blocked_by = FC_REASON_NONE;
    tm->descent_shaping_mps = FC_INT(0, VEL);
    tm->land_state = FC_LAND_AIRBORNE;
    tm->failsafe_cause = FC_FAILSAFE_NONE;
    tm->arming_blocked_by = FC_ARMING_OK;
    tm->command_refused = false;
}

/* The whole telemetry of a controller that is not ready. */
static void telemetry_not_ready(const fc_controller *ctl, fc_controller_telemetry *tm)
{
    telemetry_defaults(tm);
    tm->attitude = ctl->guard.last_attitude;
    tm->attitude_setpoint = ctl->guard.last_attitude;
    tm->rate_radps = fc_vec3_zero();
    tm->tilt_cos = FC_INT(1, RATIO);
    tm->estimator_status = FC_STEP_OK;
    tm->altitude = (fc_altitude_control_output){0};
    tm->pad = (fc_pad_motion_estimate){0};
    tm->gear_height_m = ctl->pad.gear_height_m;
    tm->landing_state = FC_LANDING_IDLE;
    tm->landing_reason = FC_REASON_NONE;
    tm->landing_changed = false;
    tm->aborts = 0u;
    tm->vertical = (fc_vertical_estimate){0};
    tm->armed = false;
}

/* Level at the heading: the shortest rotation about z, [cos psi/2, 0, 0, sin psi/2]
 * from (cos psi, sin psi) by the half-angle formula, normalised. Its own
 * saturation record: 1 + cos psi reaches 2 at psi = 0, which UNIT holds only
 * to its last LSB in fixed (the direction is what counts, normalised all the same). */
static fc_quat level_at_heading(fc_real heading_cos, fc_real heading_sin)
{
    fc_arith ar = {0u};
    fc_quat q;
    if (heading_cos >= FC_INT(0, UNIT)) {
        q = (fc_quat){fc_add(&ar, FC_INT(1, UNIT), heading_cos), FC_INT(0, UNIT), FC_INT(0, UNIT), heading_sin};
    } else {
        /* the same rotation without the cancellation near psi = pi */
        q = (fc_quat){heading_sin, FC_INT(0, UNIT), FC_INT(0, UNIT), fc_sub(&ar, FC_INT(1, UNIT), heading_cos)};
    }
    bool ok = false;
    const fc_quat n = fc_quat_normalize(&ar, q, &ok);
    return ok ? n : fc_quat_identity();
}

/* The velocity output's own parameters (the law's are its init's). */
static bool velocity_output_valid(const fc_controller_params *p)
{
    if (p->output != FC_OUTPUT_ROTORS && (p->output != FC_OUTPUT_VELOCITY || !FC_VELOCITY_OUTPUT)) {
        return false;
    }
    return fc_in_range(p->velocity.yaw_gain_per_s, FC_INT(0, RATIO), FC_INT(20, RATIO)) &&
           p->velocity.yaw_rate_max_radps > FC_INT(0, RATE) && p->velocity.yaw_rate_max_radps <= FC_INT(10, RATE);
}

/* ---------------------------------------------------------------------- */
/* heading                                                                */
/* ---------------------------------------------------------------------- */

static void heading_init(fc_controller_heading *h)
{
    h->yaw_rad = FC_INT(0, ANGLE);
    h->yaw_cos = FC_INT(1, UNIT);
    h->yaw_sin = FC_INT(0, UNIT);
    h->level = level_at_heading(h->yaw_cos, h->yaw_sin);
}

/* The heading's (cos, sin) and level attitude, recomputed only when the setpoint changes. */
static void update_heading(fc_controller_heading *h, fc_arith *ar, fc_real yaw_rad)
{
    if (yaw_rad != h->yaw_rad) {
        h->yaw_rad = yaw_rad;
        fc_sincos(ar, yaw_rad, &h->yaw_sin, &h->yaw_cos);
        h->level = level_at_heading(h->yaw_cos, h->yaw_sin);
    }
}

/* Level at the heading of the setpoint (0 if it is no angle). */
static fc_quat level_attitude(fc_controller_heading *h, fc_arith *ar, fc_real yaw_rad)
{
    update_heading(h, ar, fc_within(yaw_rad, FC_C(7.0f, ANGLE)) ? yaw_rad : FC_INT(0, ANGLE));
    return h->level;
}

/* ---------------------------------------------------------------------- */
/* sense                                                                  */
/* ---------------------------------------------------------------------- */

/* What the parts of a step work from. */
typedef struct step_context {
    fc_attitude_estimate estimate;
    const fc_quat *attitude;        /* the estimate in use (the telemetry's) */
    bool attitude_ok;               /* the platform's attitude usable (always, with the filter) */
    const fc_controller_inputs *raw; /* this step's inputs as given */
    bool rate_known;                /* false: no rate, the attitude law does not run */
    bool imu_ok;                    /* gyro and accelerometer usable */
    fc_real tilt_cos;               /* RATIO: k_h */
    fc_controller_command command;  /* the one flown: the input's if valid, else the mode kept */
    const fc_gated_inputs *in;      /* position, velocity, setpoints, pad: what the gates let through */
    fc_real height_m;               /* LENGTH: the z flown on, in->position_m.z or the reckoned one */
    fc_real vz_mps;                 /* VEL: its speed */
    bool inputs_ok;                 /* this step's were accepted */
    bool holding;                   /* not accepted, and within the hold before the failsafe */
    bool range_fresh;
} step_context;

/* The filter runs on every step, armed or not, to stay aligned; with the
 * platform's attitude in use it only checks the IMU and forms the rate
 * (fc_attitude_estimator_rate_step), and the heading input goes unused. */
static fc_step_status estimator_step(fc_controller *ctl, const fc_controller_inputs *in, fc_attitude_estimate *est)
{
    if (ctl->p.use_external_attitude) {
        return fc_attitude_estimator_rate_step(&ctl->estimator, &in->imu, est);
    }
    const fc_step_status heading_status =
        in->heading_fresh ? fc_attitude_estimator_take_heading(&ctl->estimator, in->heading_rad) : FC_STEP_OK;
    return fc_attitude_estimator_step(&ctl->estimator, &in->imu, est) | heading_status;
}

/* The attitude in use: the filter's, or the platform's if it is a usable
 * quaternion, taken at the attitude law's resolution (fc_quat16_normalize:
 * UNIT16 in fixed, 6.1e-5 a component; for a quaternion already unit its
 * rounding, with no 32-bit square). */
static fc_quat attitude_in_use(fc_controller *ctl, const fc_controller_inputs *in, const fc_attitude_estimate *est,
                               fc_step_status *status)
{
    if (!ctl->p.use_external_attitude) {
        return est->attitude;
    }
    bool ok = false;
    const fc_quat16 q = fc_quat16_normalize(&ctl->ar, in->attitude_external, &ok);
    if (!ok) {
        *status |= FC_STEP_BAD_INPUT;
        return ctl->guard.last_attitude;
    }
    return fc_quat16_widen(q);
}

/* The body rate the attitude law damps with; false when none is known. A
 * gyro sample that is not usable is never stood in for by an old rate: with
 * the platform's attitude the rate is its change over the step,
 * 2 vec(q_last* q) / dt (the sign of the shortest rotation); with the
 * filter's there is nothing to take it from (the filter holds still without
 * a gyro). */
static bool rate_in_use(fc_controller *ctl, const fc_attitude_estimate *est, const fc_quat *attitude,
                        bool attitude_fresh, fc_vec3 *rate_radps)
{
    fc_arith *ar = &ctl->ar;
    const bool external_fresh = ctl->p.use_external_attitude && attitude_fresh;
    bool known = true;
    if (est->gyro_ok) {
        *rate_radps = est->rate_radps;
    } else if (external_fresh) {
        const fc_quat last = ctl->guard.last_external_attitude;
        const fc_quat turn = fc_quat_shortest(ar, fc_quat_mul(ar, fc_quat_conj(ar, last), *attitude));
        const fc_vec3 half_angle = fc_quat_vector_part(turn);
        const fc_vec3 angle = fc_vec3_add(ar, half_angle, half_angle);
        *rate_radps = fc_vec3_scale(ar, angle, ctl->inv_dt_per_s, FC_SHIFT(UNIT, GAIN, RATE));
    } else {
        *rate_radps = fc_vec3_zero();
        known = false;
    }
    if (external_fresh) {
        ctl->guard.last_external_attitude = *attitude;
    }
    return known;
}

/* k_h = cos(roll) cos(pitch): the world-z component of the body z axis,
 * 1 - 2(x^2 + y^2), from x and y rounded to UNIT16 (the squares exact):
 * within 4 (|x| + |y|) 2^-15 <= 2^-12 of it. */
static fc_real tilt_cos_of(fc_arith *ar, fc_quat q)
{
    const fc_real16 x = fc_narrow16(ar, q.x, FC_UNIT_FRAC, FC_UNIT16_FRAC);
    const fc_real16 y = fc_narrow16(ar, q.y, FC_UNIT_FRAC, FC_UNIT16_FRAC);
    const fc_real xx_yy = fc_dot2_16(x, x, y, y); /* UNIT16_SQ, below 2^29 */
    return fc_convert(ar, FC_INT(1, UNIT16_SQ) - 2 * xx_yy, FC_UNIT16_SQ_FRAC, FC_RATIO_FRAC);
}

/* Attitude and rate: the filter (or the platform's estimate), the IMU's state. */
static fc_step_status sense(fc_controller *ctl, const fc_controller_inputs *in, step_context *c,
                            fc_controller_telemetry *tm)
{
    tm->estimator_status = estimator_step(ctl, in, &c->estimate);
    fc_step_status attitude_status = FC_STEP_OK;
    /* the telemetry's attitude and rate are the step's own (and the
     * setpoint's telemetry, on the paths without one) */
    tm->attitude = attitude_in_use(ctl, in, &c->estimate, &attitude_status);
    c->attitude = &tm->attitude;
    c->attitude_ok = attitude_status == FC_STEP_OK;
    c->imu_ok = c->estimate.gyro_ok && c->estimate.accel_ok;
    c->rate_known = rate_in_use(ctl, &c->estimate, c->attitude, c->attitude_ok, &tm->rate_radps);
    c->tilt_cos = tilt_cos_of(&ctl->ar, tm->attitude);
    c->raw = in;
    if (ctl->p.use_external_attitude) {
        ctl->guard.last_attitude = tm->attitude; /* what a bad sample of the platform's is stood in for by */
    }
    tm->tilt_cos = c->tilt_cos;
    return passed_on(tm->estimator_status) | attitude_status;
}

/* The body rate of the heading's turn, yaw_rate_setpoint about the world's up
 * axis seen in the body (R(q)^T (0, 0, r)), fed forward to the attitude law;
 * zero, and no rotation computed, without a rate. */
static fc_vec3 yaw_rate_feedforward(fc_controller *ctl, const step_context *c)
{
    const fc_real rate = c->in->yaw_rate_setpoint_radps;
    if (rate == FC_INT(0, RATE)) {
        return fc_vec3_zero();
    }
    return fc_quat_rotate_inv(&ctl->ar, *c->attitude, fc_vec3_make(FC_INT(0, RATE), FC_INT(0, RATE), rate));
}

/* ---------------------------------------------------------------------- */
/* mission                                                                */
/* ---------------------------------------------------------------------- */

static void mission_init(fc_controller_mission *m)
{
    m->last_command = FC_COMMAND_DISARM;
    m->mode = FC_COMMAND_DISARM;
    m->armed = false;
    m->await_disarm = false;
}

static bool command_arms(fc_controller_command command)
{
    return command == FC_COMMAND_TRACK_PAD || command == FC_COMMAND_HOLD || command == FC_COMMAND_LAND;
}

static fc_landing_request landing_request_of(fc_controller_command command)
{
    switch (command) {
    case FC_COMMAND_HOLD:
        return FC_LANDING_REQUEST_HOLD;
    case FC_COMMAND_LAND:
        return FC_LANDING_REQUEST_LAND;
    case FC_COMMAND_DISARM:
    case FC_COMMAND_TRACK_PAD:
    case FC_COMMAND_COUNT:
    default:
        return FC_LANDING_REQUEST_NONE;
    }
}

/* The command: a value outside the enum is refused and the mode kept. */
static fc_step_status take_command(fc_controller *ctl, fc_controller_command requested, step_context *c,
                                   fc_controller_telemetry *tm)
{
    const bool known = requested == FC_COMMAND_DISARM || command_arms(requested);
    if (!known) {
        c->command = ctl->mission.mode;
        tm->command_refused = true;
        return FC_STEP_REFUSED;
    }
    ctl->mission.mode = requested;
    c->command = requested;
    return FC_STEP_OK;
}

/* Why the command may not arm the vehicle now (FC_ARMING_OK: it may). */
static fc_arming_check arming_check(const fc_controller *ctl, const step_context *c)
{
    if (ctl->mission.await_disarm) {
        return FC_ARMING_AWAIT_DISARM;
    }
    if (!c->imu_ok) {
        return FC_ARMING_IMU_BAD;
    }
    if (ctl->p.use_external_attitude && !c->attitude_ok) {
        return FC_ARMING_ATTITUDE_BAD;
    }
    if (!ctl->p.use_external_attitude && !c->estimate.aligned) {
        return FC_ARMING_NOT_ALIGNED;
    }
    return c->inputs_ok ? FC_ARMING_OK : FC_ARMING_INPUTS_BAD;
}

/* Arming and disarming: only a valid DISARM disarms; a command that arms
 * does so at the first step whose checks pass. */
static fc_step_status arm(fc_controller *ctl, const step_context *c, fc_controller_telemetry *tm)
{
    if (!command_arms(c->command)) {
        ctl->mission.armed = false;
        ctl->mission.await_disarm = false;
    } else if (!ctl->mission.armed) {
        tm->arming_blocked_by = arming_check(ctl, c);
        ctl->mission.armed = tm->arming_blocked_by == FC_ARMING_OK;
    } else {
        /* armed, and staying so */
    }
    tm->armed = ctl->mission.armed;
    return tm->arming_blocked_by == FC_ARMING_OK ? FC_STEP_OK : FC_STEP_REFUSED;
}

static void landing_telemetry(const fc_controller *ctl, fc_controller_telemetry *tm, fc_landing_state state_before,
                              fc_landing_reason reason_before)
{
    tm->landing_state = ctl->landing.state;
    tm->landing_reason = ctl->landing.reason;
    tm->landing_changed = ctl->landing.state != state_before || ctl->landing.reason != reason_before;
    tm->aborts = ctl->landing.aborts;
}

/* A new task, not a switch between HOLD and LAND and not in the failsafe:
 * the loops start clean; (3.6) starts again from z_r_init when the task is
 * TRACK_PAD, its only user (any later switch to TRACK_PAD is a new task too,
 * so it always starts there). */
static void begin_task(fc_controller *ctl, fc_controller_command command)
{
    const fc_controller_command last = ctl->mission.last_command;
    if (last != command && !ctl->failsafe.active) {
        const bool from_mission = last == FC_COMMAND_HOLD || last == FC_COMMAND_LAND;
        const bool to_mission = command == FC_COMMAND_HOLD || command == FC_COMMAND_LAND;
        if (!(from_mission && to_mission)) {
            reset_loops(ctl);
            if (command == FC_COMMAND_TRACK_PAD) {
                fc_altitude_reference_restart(&ctl->reference, ctl->p.reference_offset_init_m);
            }
            fc_landing_reset(&ctl->landing);
        }
    }
    ctl->mission.last_command = command;
}

/* Motors off and the loops reset: disarmed, or landed. */
static fc_step_status stopped(fc_controller *ctl, fc_controller_outputs *out, fc_landing_state state_before,
                              fc_landing_reason reason_before)
{
    if (ctl->mission.last_command != FC_COMMAND_DISARM) {
        reset_loops(ctl);
    }
    ctl->mission.last_command = FC_COMMAND_DISARM;
    out->telemetry.attitude_setpoint = out->telemetry.attitude; /* no setpoint: the attitude itself */
    out->telemetry.altitude = (fc_altitude_control_output){0};
    landing_telemetry(ctl, &out->telemetry, state_before, reason_before);
    motors_off(ctl, out);
    return FC_STEP_OK;
}

/* Disarmed: the mission's monitors start again (after a failsafe landing
 * LANDED stays until DISARM), the motors off. */
static fc_step_status disarmed(fc_controller *ctl, fc_controller_outputs *out, fc_landing_state state_before,
                               fc_landing_reason reason_before)
{
    fc_failsafe_reset(&ctl->failsafe);
    fc_land_detector_reset(&ctl->land_detector);
    if (!ctl->mission.await_disarm) {
        fc_landing_reset(&ctl->landing);
    }
    return stopped(ctl, out, state_before, reason_before);
}

/* The failsafe's descent ended on the ground. */
static bool failsafe_landed(const fc_controller *ctl)
{
    return ctl->failsafe.active && ctl->land_detector.state == FC_LAND_LANDED;
}

/* After a failsafe landing: LANDED, disarmed, and the motors off until a DISARM. */
static fc_step_status stop_after_failsafe_landing(fc_controller *ctl, fc_controller_outputs *out,
                                                  fc_landing_state state_before, fc_landing_reason reason_before)
{
    fc_landing_force(&ctl->landing, FC_LANDING_LANDED, FC_REASON_FAILSAFE_LANDED);
    ctl->mission.armed = false;
    ctl->mission.await_disarm = true;
    fc_failsafe_reset(&ctl->failsafe);
    out->telemetry.land_state = FC_LAND_LANDED;
    return FC_STEP_DEGRADED | stopped(ctl, out, state_before, reason_before);
}

/* ---------------------------------------------------------------------- */
/* guard                                                                  */
/* ---------------------------------------------------------------------- */

static void guard_init(fc_controller_guard *g)
{
    g->last_attitude = fc_quat_identity();
    g->last_external_attitude = fc_quat_identity();
    g->reckoned_z_m = FC_INT(0, LENGTH);
}

/* The plausibility gates (fc/input_gate.h); the pad counts when tracking it. */
static fc_step_status gate_inputs(fc_controller *ctl, const fc_controller_inputs *in, step_context *c)
{
    const fc_input_gate_input raw = {&in->position_m,         &in->velocity_mps,     &in->pad,
                                     &in->position_setpoint_m, in->yaw_setpoint_rad, in->yaw_rate_setpoint_radps};
    c->inputs_ok = fc_input_gate_step(&ctl->gate, &raw, c->command == FC_COMMAND_TRACK_PAD, ctl->mission.armed, NULL);
    c->in = &ctl->gate.accepted;
    c->height_m = c->in->position_m.z;
    c->vz_mps = c->in->velocity_mps.z;
    return c->inputs_ok ? FC_STEP_OK : FC_STEP_BAD_INPUT;
}

/* The failsafe's guard (fc/failsafe.h): entering it, leaving it, the hold. */
static void watch_inputs(fc_controller *ctl, step_context *c)
{
    const fc_failsafe_watch_input watch_in = {ctl->mission.armed, c->inputs_ok, ctl->gate.have_accepted, c->imu_ok};
    const fc_failsafe_watch_output watch = fc_failsafe_watch(&ctl->failsafe, &watch_in);
    /* no position to hold: the filter on its gyro (fc_attitude_estimator_coast) */
    fc_attitude_estimator_coast(&ctl->estimator, watch.active);
    if (watch.entered) {
        fc_land_detector_reset(&ctl->land_detector);
        fc_landing_force(&ctl->landing, FC_LANDING_FAILSAFE, FC_REASON_INPUTS_LOST);
    }
    if (watch.left) {
        /* back: the mission starts again from HOLD (tracking from its reference) */
        ctl->mission.last_command = FC_COMMAND_DISARM;
        fc_landing_force(&ctl->landing, FC_LANDING_IDLE, FC_REASON_INPUTS_BACK);
    }
    c->holding = watch.hold;
}

/* The height the altitude law flies on: the measured one, or while the
 * inputs are held the last good one carried along the vertical estimate's
 * speed (dead reckoning: fresher than a frozen height). */
static void reckon_height(fc_controller *ctl, step_context *c, const fc_vertical_estimate *v)
{
    if (c->inputs_ok) {
        ctl->guard.reckoned_z_m = c->height_m;
    } else if (c->holding) {
        fc_arith *ar = &ctl->ar;
        ctl->guard.reckoned_z_m =
            fc_add_inline(ar, ctl->guard.reckoned_z_m, fc_mul_gain(ar, v->vz_mps, ctl->p.dt, FC_GAIN_SHIFT(VEL, LENGTH)));
        c->height_m = ctl->guard.reckoned_z_m;
        c->vz_mps = v->vz_mps;
    } else {
        /* neither measured nor held: the failsafe flies on the estimate itself */
    }
}

/* ---------------------------------------------------------------------- */
/* the outer group's minor frames (fc/controller.h)                       */
/* ---------------------------------------------------------------------- */

/* The position loop's demand half runs in minor frame 0; its attitude half
 * in frame 1 when the major frame has room for both halves, the pad model
 * and two slices of its work ahead (outer_divider >= 5), else with the
 * demand. */
static uint8_t position_attitude_frame(uint8_t divider)
{
    return divider >= 5u ? 1u : 0u;
}

/* The pad model, in the frame after the position loop's. */
static uint8_t pad_model_frame(uint8_t divider)
{
    return divider > 1u ? (uint8_t)(position_attitude_frame(divider) + 1u) : 0u;
}

/* A slice of the pad model's work ahead in each frame after its own, until
 * the major frame ends. */
static bool work_ahead_frame(uint8_t frame, uint8_t divider)
{
    return frame > pad_model_frame(divider);
}

/* ---------------------------------------------------------------------- */
/* pad samples                                                            */
/* ---------------------------------------------------------------------- */

static void pad_samples_init(fc_controller_pad_samples *ps)
{
    ps->gear_height_m = FC_INT(0, LENGTH);
    ps->gear_height_age_s = FC_INT(0, TIME);
    ps->gear_height_known = false;
    ps->pending_height_m = FC_INT(0, LENGTH);
    ps->pending_age_s = FC_INT(0, DT);
    ps->pending = false;
    ps->estimate = (fc_pad_motion_estimate){0};
    ps->model_vz_mps = FC_INT(0, VEL);
    ps->height_step_m = FC_INT(0, LENGTH);
    ps->height_step_change_m = FC_INT(0, LENGTH);
    ps->speed_step_mps = FC_INT(0, VEL);
}

/* The pad as the range finder sees it: a sample of its surface height
 * z - range k_h (a level pad under the vehicle), and the gear's height above
 * it. The sample waits for the pad model's minor frame (the newest one). */
static fc_step_status observe_pad(fc_controller_pad_samples *ps, fc_arith *ar, const fc_controller_settings *p,
                                  fc_real step_s, const fc_controller_inputs *in, const fc_gated_inputs *g,
                                  bool position_ok, fc_real tilt_cos, bool *range_fresh)
{
    const bool range_ok = fc_within(in->range_m, FC_INT(100, LENGTH)) && in->range_m >= FC_INT(0, LENGTH);
    *range_fresh = in->range_fresh && range_ok;
    ps->gear_height_age_s = fc_min(fc_add_inline(ar, ps->gear_height_age_s, step_s), FC_INT(600, TIME));
    if (*range_fresh) {
        const fc_real vertical_range = fc_mul(ar, in->range_m, tilt_cos, FC_SHIFT(LENGTH, RATIO, LENGTH));
        ps->gear_height_m = fc_sub_inline(ar, vertical_range, p->gear_height_m);
        ps->gear_height_age_s = FC_INT(0, TIME);
        ps->gear_height_known = true;
        if (position_ok) {
            ps->pending_height_m = fc_sub_inline(ar, g->position_m.z, vertical_range);
            ps->pending_age_s = FC_INT(0, DT);
            ps->pending = true;
        }
    }
    return in->range_fresh && !range_ok ? FC_STEP_BAD_INPUT : FC_STEP_OK;
}

/* The steps along the estimate's trajectory z(t) = z + z' t + z'' t^2 / 2
 * (constant z'') from the pad model's step on, at t = k dt:
 *   z'(t + dt) - z'(t) = z'' dt
 *   z(t + dt) - z(t)   = (z' + z'' dt / 2) dt + k z'' dt^2
 * so that each later step only adds (no product between two pad frames). */
static void start_extrapolation(fc_controller_pad_samples *ps, fc_arith *ar, const fc_controller_settings *p)
{
    const fc_vertical_trajectory *now = &ps->estimate.now;
    const fc_real half_rise_m = fc_mul_gain(ar, now->az_mps2, p->half_dt_sq, FC_GAIN_SHIFT(ACCEL, LENGTH));
    ps->speed_step_mps = fc_mul_gain(ar, now->az_mps2, p->dt, FC_GAIN_SHIFT(ACCEL, VEL));
    ps->height_step_m = fc_add_inline(ar, fc_mul_gain(ar, now->vz_mps, p->dt, FC_GAIN_SHIFT(VEL, LENGTH)), half_rise_m);
    ps->height_step_change_m = fc_add_inline(ar, half_rise_m, half_rise_m);
}

/* The estimate's trajectory one step later. */
static void extrapolate_one_step(fc_controller_pad_samples *ps, fc_arith *ar)
{
    fc_vertical_trajectory *now = &ps->estimate.now;
    now->z_m = fc_add_inline(ar, now->z_m, ps->height_step_m);
    now->vz_mps = fc_add_inline(ar, now->vz_mps, ps->speed_step_mps);
    ps->height_step_m = fc_add_inline(ar, ps->height_step_m, ps->height_step_change_m);
}

/* *to = *from field by field: the estimate goes to the telemetry at every
 * step, and a struct assignment is a byte loop on the ATmega at -Os. */
static void copy_pad_estimate(fc_pad_motion_estimate *to, const fc_pad_motion_estimate *from)
{
    to->now.z_m = from->now.z_m;
    to->now.vz_mps = from->now.vz_mps;
    to->now.az_mps2 = from->now.az_mps2;
    to->mean_m = from->mean_m;
    to->heave_bound_m = from->heave_bound_m;
    to->accel_bound_mps2 = from->accel_bound_mps2;
    to->prediction_error_m = from->prediction_error_m;
    to->confidence = from->confidence;
    to->observed_s = from->observed_s;
    to->dominant_mode = from->dominant_mode;
    to->dominant_period_s = from->dominant_period_s;
    to->dominant_amplitude_m = from->dominant_amplitude_m;
    to->learning = from->learning;
}

/* In the pad model's minor frame (pad_model_frame) the model takes the
 * waiting sample, carried to this step along the model's vertical speed,
 * and gives a new estimate; in the work-ahead frames (work_ahead_frame) it
 * does one slice of its next step ahead of it (fc_pad_motion_work_ahead),
 * which that step would do first otherwise. On the other steps the estimate
 * is the last one with its trajectory extrapolated to this step. */
static fc_step_status pad_step(fc_controller_pad_samples *ps, fc_pad_motion *model, fc_arith *ar,
                               const fc_controller_settings *p, uint8_t frame, fc_pad_motion_estimate *estimate)
{
    fc_step_status status = FC_STEP_OK;
    const uint8_t divider = p->outer_divider;
    if (work_ahead_frame(frame, divider)) {
        status = passed_on(fc_pad_motion_work_ahead(model));
    }
    if (frame == pad_model_frame(divider)) {
        fc_pad_motion_sample sample = {FC_INT(0, LENGTH), false};
        if (ps->pending) {
            const fc_real carried_m = fc_mul(ar, ps->model_vz_mps, ps->pending_age_s, FC_SHIFT(VEL, DT, LENGTH));
            sample.height_m = fc_add_inline(ar, ps->pending_height_m, carried_m);
            sample.fresh = true;
            ps->pending = false;
        }
        status |= passed_on(fc_pad_motion_step(model, &sample, &ps->estimate));
        ps->model_vz_mps = ps->estimate.now.vz_mps;
        if (divider > 1u) {
            start_extrapolation(ps, ar, p);
        }
    } else {
        extrapolate_one_step(ps, ar);
    }
    copy_pad_estimate(estimate, &ps->estimate);
    if (ps->pending) {
        ps->pending_age_s = fc_min(fc_add_inline(ar, ps->pending_age_s, p->dt_s), FC_C(1.0f, DT));
    }
    return status;
}

/* The range sample of this step, then the pad model in its minor frame. */
static fc_step_status pad_samples_step(fc_controller *ctl, const fc_controller_inputs *in, uint8_t frame,
                                       step_context *c, fc_controller_telemetry *tm)
{
    fc_step_status status = observe_pad(&ctl->pad, &ctl->ar, &ctl->p, ctl->step_s, in, c->in, c->inputs_ok,
                                        c->tilt_cos, &c->range_fresh);
    status |= pad_step(&ctl->pad, &ctl->pad_motion, &ctl->ar, &ctl->p, frame, &tm->pad);
    tm->gear_height_m = ctl->pad.gear_height_m;
    return status;
}

/* ---------------------------------------------------------------------- */
/* rate groups                                                            */
/* ---------------------------------------------------------------------- */

static void rate_groups_init(fc_controller_rate_groups *g)
{
    g->minor_frame = 0u;
    g->position = (fc_position_control_output){0};
    g->position.attitude_sp = fc_quat_identity();
    g->demand_status = FC_STEP_OK;
    g->held_position_status = FC_STEP_OK;
    g->have_demand = false;
    g->have_attitude_setpoint = false;
}

/* This step's minor frame; the next step takes the one after it. */
static uint8_t next_minor_frame(fc_controller_rate_groups *g, uint8_t outer_divider)
{
    const uint8_t frame = g->minor_frame;
    g->minor_frame = (uint8_t)(frame + 1u < outer_divider ? frame + 1u : 0u);
    return frame;
}

/* The feedback's measured acceleration (fc/controller.h), horizontal only.
 * The altitude law (SSC or its baseline) owns the thrust's
 * magnitude and so z; the position loop's F_req,z only sets the tilt, with
 * F_req,h: an I_a,z would turn every vertical transient of the altitude law
 * (a mass step, a pad's heave) into a tilt error, while the mass error it
 * would correct is the altitude law's to correct (its sliding variable, Theta).
 * (2.10)-(2.11) are the position loop's, and its horizontal acceleration
 * g tan(tilt) under an altitude law that holds T cos(tilt) = m g does not
 * depend on the mass: what I_a,h corrects is a horizontal force the model
 * lacks (wind, drag, a thrust axis off the body's z) per unit of the true mass. */
bool fc_controller_measured_accel(fc_arith *ar, fc_quat attitude, fc_vec3 specific_force_mps2, bool usable,
                                  fc_vec3 *accel_world_mps2)
{
    *accel_world_mps2 = fc_vec3_zero();
    if (!usable) {
        return false;
    }
    /* g has no horizontal part: (R(q) f)_x and (R(q) f)_y */
    *accel_world_mps2 = fc_quat_rotate_horizontal(ar, attitude, specific_force_mps2);
    return true;
}

/* The position loop's demand half (minor frame 0), on the gated inputs and
 * the vertical estimate; its inputs by reference (fc/position_control.h). */
static fc_step_status position_demand(fc_controller *ctl, const step_context *c)
{
    const fc_gated_inputs *in = c->in;
    /* the newest IMU sample, no average over the major frame: k_a dt
     * is the low-pass (a_ff = 0, so a_des,z = 0 = a_z: I_a,z stays 0);
     * the estimator's accel_ok: in range and not all zero (fc/attitude_estimator.h) */
    fc_vec3 accel_world_mps2;
    const bool accel_ok =
        fc_controller_measured_accel(&ctl->ar, *c->attitude, c->raw->imu.accel_mps2,
                                     c->estimate.accel_ok && c->attitude_ok, &accel_world_mps2);
    /* the vertical from the vertical estimator; no velocity setpoint, no feedforward */
    const fc_vec3 position_m = fc_vec3_make(in->position_m.x, in->position_m.y, c->height_m);
    const fc_vec3 velocity_mps = fc_vec3_make(in->velocity_mps.x, in->velocity_mps.y, c->vz_mps);
    const fc_vec3 zero = fc_vec3_zero();
    const fc_position_control_input pin = {&position_m, &velocity_mps, &in->position_setpoint_m,
                                           &zero,       &zero,         &accel_world_mps2,
                                           accel_ok};
    return passed_on(fc_position_control_demand(&ctl->position, &pin, &ctl->groups.position));
}

/* The position loop (fc/position_control.h) in two halves: in minor frame 0
 * the demand, horizontal PID -> F = m (a_des - g - I_a), which waits in the
 * rate groups; in the attitude frame (position_attitude_frame) F's attitude
 * setpoint at the heading, held with the status of both halves until the
 * next attitude frame. Until its first attitude frame (after arming, a
 * reset or a level phase: at most outer_divider steps) the setpoint is level
 * at the heading; a reset or a level phase between the halves drops the
 * demand, and the attitude frame then keeps the level setpoint. */
static fc_step_status horizontal_step(fc_controller *ctl, const step_context *c, uint8_t frame, fc_quat *attitude_sp)
{
    const fc_gated_inputs *in = c->in;
    fc_controller_rate_groups *g = &ctl->groups;
    if (frame == 0u) {
        g->demand_status = position_demand(ctl, c);
        g->have_demand = true;
    }
    if (frame == position_attitude_frame(ctl->p.outer_divider) && g->have_demand) {
        update_heading(&ctl->heading, &ctl->ar, in->yaw_setpoint_rad);
        const fc_step_status attitude_status =
            fc_position_control_attitude(&ctl->position, ctl->heading.yaw_cos, ctl->heading.yaw_sin, &g->position);
        g->held_position_status = g->demand_status | passed_on(attitude_status);
        g->have_demand = false;
        g->have_attitude_setpoint = true;
    }
    if (!g->have_attitude_setpoint) {
        *attitude_sp = level_attitude(&ctl->heading, &ctl->ar, in->yaw_setpoint_rad);
        return FC_STEP_OK;
    }
    *attitude_sp = g->position.attitude_sp;
    return g->held_position_status;
}

/* ---------------------------------------------------------------------- */
/* vertical plan                                                          */
/* ---------------------------------------------------------------------- */

/* The hover thrust learns in clean flight only: armed and flying the
 * mission on good inputs, the thrust free, away from the surface. */
static bool hover_learnable(const fc_controller *ctl, const step_context *c)
{
    /* the flags first: each test only when those before it pass */
    if (ctl->p.output != FC_OUTPUT_ROTORS || !ctl->mission.armed || ctl->failsafe.active || !c->inputs_ok ||
        (ctl->last_saturation & (FC_SAT_THRUST_HIGH | FC_SAT_THRUST_LOW)) != 0u) {
        return false;
    }
    const fc_landing_state s = ctl->landing.state;
    if (s == FC_LANDING_TOUCHDOWN || s == FC_LANDING_DISARM || s == FC_LANDING_LANDED) {
        return false; /* on the surface */
    }
    const bool thrust_free = ctl->last_thrust_n > ctl->p.thrust_min_n && ctl->last_thrust_n < ctl->p.thrust_max_n;
    const bool near_surface = ctl->pad.gear_height_known && ctl->pad.gear_height_age_s <= ctl->p.range_fresh_s &&
                              ctl->pad.gear_height_m < FC_C(0.2f, LENGTH);
    return thrust_free && !near_surface;
}

/* The vertical channel (fc/vertical_estimator.h), every step. */
static fc_step_status vertical_step(fc_controller *ctl, const fc_controller_inputs *in, const step_context *c,
                                    fc_controller_telemetry *tm)
{
    const fc_vertical_estimator_input vin = {c->attitude,        &in->imu.accel_mps2, c->estimate.accel_ok,
                                             c->vz_mps,            c->inputs_ok,     ctl->pad.gear_height_m,
                                             c->range_fresh,     ctl->last_thrust_n, c->tilt_cos,
                                             hover_learnable(ctl, c), !ctl->mission.armed};
    return passed_on(fc_vertical_estimator_step(&ctl->vertical, &vin, &tm->vertical));
}

/* The failsafe's descent: the land detector on the thrust in force, then the
 * speed loop's thrust (or its ramp once in contact). */
static fc_real failsafe_thrust(fc_controller *ctl, const step_context *c, fc_controller_telemetry *tm)
{
    fc_arith *ar = &ctl->ar;
    const fc_vertical_estimate *v = &tm->vertical;
    const fc_land_detector_input lin = {
        v->vz_mps, v->accel_z_mps2, fc_mul(ar, ctl->last_thrust_n, c->tilt_cos, FC_SHIFT(FORCE, RATIO, FORCE)),
        v->hover_thrust_n, true, ctl->pad.gear_height_m, ctl->pad.gear_height_age_s, ctl->pad.gear_height_known};
    tm->land_state = fc_land_detector_step(&ctl->land_detector, &lin);
    fc_real thrust_min_n = ctl->p.thrust_min_n;
    fc_real thrust_max_n = ctl->p.thrust_max_n;
    if (ctl->p.output == FC_OUTPUT_VELOCITY) {
        /* the vehicle's own autopilot has the thrust: [0, 2 T_h] */
        thrust_min_n = FC_INT(0, FORCE);
        thrust_max_n = fc_add(ar, v->hover_thrust_n, v->hover_thrust_n);
    }
    const fc_failsafe_input fin = {v->vz_mps, v->hover_thrust_n, c->tilt_cos, thrust_min_n, thrust_max_n,
                                   tm->land_state};
    return fc_failsafe_step(&ctl->failsafe, &fin);
}

/* The hover thrust, as a body thrust at this tilt. */
static fc_real hover_body_thrust_n(fc_controller *ctl, const step_context *c, const fc_vertical_estimate *v)
{
    const fc_real k_h = fc_max(c->tilt_cos, FC_C(0.5f, RATIO));
    return fc_div(&ctl->ar, v->hover_thrust_n, k_h, FC_DIV_SHIFT(FORCE, RATIO, FORCE));
}

/* The horizontal error to the pad's centre, |p_xy - sp_xy|, for a landing
 * step that reads it (fc_landing_reads_horizontal_error); for the others 0,
 * without the root, its saturation (fixed: past 2048 m) recorded as the
 * root would have recorded it. */
static fc_real horizontal_error_m(fc_arith *ar, const fc_gated_inputs *in, bool read)
{
    const fc_real dx = fc_sub_inline(ar, in->position_m.x, in->position_setpoint_m.x);
    const fc_real dy = fc_sub_inline(ar, in->position_m.y, in->position_setpoint_m.y);
    if (read) {
        return fc_hypot3(ar, dx, dy, FC_INT(0, LENGTH));
    }
    if (fc_hypot3_saturates(dx, dy, FC_INT(0, LENGTH))) {
        ar->saturated = 1u;
    }
    return FC_INT(0, LENGTH);
}

/* What the thrust follows at this step. */
typedef struct vertical_plan {
    bool fly_reference;  /* the altitude law tracks the telemetry's reference */
    bool motors_on;
    bool level;          /* the attitude setpoint is level at the heading */
    fc_real thrust_n;    /* FORCE: the body thrust when not flying the reference */
} vertical_plan;

/* HOLD and LAND: the landing manager's reference, or its thrust ramp. LANDED
 * while the range finder puts the gear in the air is not landed: the hover
 * thrust is held this step, and from the next the vehicle climbs back. */
static fc_step_status landing_plan(fc_controller *ctl, const step_context *c, fc_controller_telemetry *tm,
                                   vertical_plan *plan)
{
    fc_arith *ar = &ctl->ar;
    const fc_landing_input lin = {landing_request_of(c->command), c->height_m,
                                  horizontal_error_m(ar, c->in, fc_landing_reads_horizontal_error(&ctl->landing)),
                                  c->tilt_cos, ctl->pad.gear_height_m, c->range_fresh, ctl->last_thrust_n, &tm->pad,
                                  fc_sub_inline(ar, c->in->position_m.x, c->in->position_setpoint_m.x),
                                  fc_sub_inline(ar, c->in->position_m.y, c->in->position_setpoint_m.y), c->raw->pad_attitude};
    fc_landing_output lout;
    const fc_step_status status = passed_on(fc_landing_step(&ctl->landing, &lin, &lout));
    tm->reference = lout.reference;
    tm->touchdown_window = lout.touchdown_window;
    tm->descent_blocked_by = lout.blocked_by;
    tm->descent_shaping_mps = lout.shaping_mps;
    plan->fly_reference = lout.fly_reference;
    plan->motors_on = lout.motors_on;
    plan->thrust_n = lout.ramp_thrust_n;
    plan->level = !lout.fly_reference;
    const fc_land_detector_input range_in = {FC_INT(0, VEL),          FC_INT(0, ACCEL),           FC_INT(0, FORCE),
                                             FC_INT(0, FORCE),        false,                      ctl->pad.gear_height_m,
                                             ctl->pad.gear_height_age_s, ctl->pad.gear_height_known};
    if (!plan->motors_on && fc_land_detector_range_says_airborne(&ctl->land_detector, &range_in)) {
        fc_landing_abort(&ctl->landing, &lin, FC_REASON_CONTACT_LOST);
        plan->motors_on = true;
        plan->thrust_n = hover_body_thrust_n(ctl, c, &tm->vertical);
    }
    return status;
}

/* The failsafe's descent, the reference of TRACK_PAD, or the landing's. */
static fc_step_status plan_vertical(fc_controller *ctl, const step_context *c, fc_controller_telemetry *tm,
                                    vertical_plan *plan)
{
    *plan = (vertical_plan){true, true, false, FC_INT(0, FORCE)};
    if (ctl->failsafe.active) {
        plan->thrust_n = failsafe_thrust(ctl, c, tm);
        plan->fly_reference = false;
        plan->level = true;
        return FC_STEP_DEGRADED;
    }
    if (c->command == FC_COMMAND_TRACK_PAD) {
        return passed_on(fc_altitude_reference_step(&ctl->reference, &c->in->pad, &tm->reference));
    }
    return landing_plan(ctl, c, tm, plan);
}

/* The landing stopped the motors: the loops reset, no setpoint. */
static fc_step_status motors_stopped_by_landing(fc_controller *ctl, fc_controller_outputs *out)
{
    reset_loops(ctl);
    motors_off(ctl, out);
    out->telemetry.attitude_setpoint = out->telemetry.attitude; /* no setpoint: the attitude itself */
    return FC_STEP_OK;
}

/* ---------------------------------------------------------------------- */
/* flight                                                                 */
/* ---------------------------------------------------------------------- */

/* The thrust in the allocation's normalised units: the altitude law gives it
 * so on the reference; the failsafe, the ramp and the hover hold set N. */
static fc_real16 thrust_demand(fc_controller *ctl, const step_context *c, const vertical_plan *plan,
                               fc_controller_telemetry *tm, fc_real *thrust_n, fc_step_status *status)
{
    *thrust_n = plan->thrust_n;
    if (!plan->fly_reference) {
        return fc_allocation_thrust_fraction(&ctl->allocation, plan->thrust_n);
    }
    const fc_altitude_control_input altitude_in = {c->height_m, c->vz_mps, &tm->reference, c->tilt_cos,
                                                   ctl->last_saturation};
    /* Theta learns from measurements, and not once contact is planned: the press and
     * the pad's reaction are no parameter error (fc/altitude_control.h, "Adaptation
     * in discrete time") */
    fc_altitude_control_hold(&ctl->altitude, c->holding || tm->touchdown_window);
    tm->altitude_status = fc_altitude_control_step(&ctl->altitude, &altitude_in, &tm->altitude);
    *status |= passed_on(tm->altitude_status);
    *thrust_n = tm->altitude.thrust_n;
    return tm->altitude.thrust;
}

/* The attitude setpoint (the position loop's; level in the failsafe and the
 * ramp), then the attitude law's moments, normalised. */
static fc_vec3_16 moment_demand(fc_controller *ctl, const step_context *c, const vertical_plan *plan,
                                uint8_t frame, fc_controller_telemetry *tm, fc_step_status *status)
{
    if (plan->level) {
        tm->attitude_setpoint = level_attitude(&ctl->heading, &ctl->ar, c->in->yaw_setpoint_rad);
        ctl->groups.have_demand = false; /* the loop starts afresh after a level phase */
        ctl->groups.have_attitude_setpoint = false;
    } else {
        *status |= horizontal_step(ctl, c, frame, &tm->attitude_setpoint);
    }
    /* on the pad (contact being confirmed, the thrust ramp) the feet and not
     * the moments hold the attitude: the integrals hold their trim */
    fc_attitude_control_hold_integral(&ctl->attitude, ctl->landing.state == FC_LANDING_TOUCHDOWN ||
                                                          ctl->landing.state == FC_LANDING_DISARM);
    if (!c->rate_known) {
        *status |= FC_STEP_DEGRADED; /* no rate: no moments (the header says why) */
        return fc_vec3_16_zero();
    }
    const fc_vec3 rate_ff_radps = yaw_rate_feedforward(ctl, c);
    const fc_attitude_control_input attitude_in = {c->attitude, &tm->attitude_setpoint, &tm->rate_radps,
                                                   &rate_ff_radps, ctl->last_saturation};
    fc_attitude_control_output attitude_out;
    tm->attitude_status = fc_attitude_control_step(&ctl->attitude, &attitude_in, &attitude_out);
    *status |= passed_on(tm->attitude_status);
    return attitude_out.moment;
}

/* The rotor speeds of the normalised wrench, and what the next step reads of
 * them (the saturation, the thrust in force). */
static fc_step_status allocate(fc_controller *ctl, fc_real16 thrust, fc_vec3_16 moment, fc_real thrust_n,
                               fc_controller_outputs *out)
{
    fc_controller_telemetry *tm = &out->telemetry;
    const fc_allocation_demand demand = {thrust, moment};
    /* the speeds straight into the outputs; no forward model (fc/allocation.h) */
    uint8_t saturation;
    tm->allocation_status = fc_allocation_speeds(&ctl->allocation, &demand, out->rotor_speed, &saturation);
    ctl->last_saturation = saturation;
    ctl->last_thrust_n = thrust_n;
    tm->allocation_saturation = saturation;
    out->rotor_count = ctl->allocation.rotor_count;
    out->motors_on = true;
    out->output = FC_OUTPUT_ROTORS;
    out->velocity_cmd_mps = fc_vec3_zero();
    out->yaw_rate_cmd_radps = FC_INT(0, RATE);
    /* at the library's edge in N and N m: the thrust as set, the moments as sent */
    fc_allocation_moment_nm(&ctl->allocation, &demand.moment, &out->moment_nm);
    out->thrust_n = thrust_n;
    return passed_on(tm->allocation_status);
}

/* The rotors' path: thrust, moments, allocation. */
static fc_step_status fly_rotors(fc_controller *ctl, const step_context *c, const vertical_plan *plan,
                                 uint8_t frame, fc_controller_outputs *out)
{
    fc_controller_telemetry *tm = &out->telemetry;
    fc_step_status status = FC_STEP_OK;
    fc_real thrust_n;
    const fc_real16 thrust = thrust_demand(ctl, c, plan, tm, &thrust_n, &status);
    const fc_vec3_16 moment = moment_demand(ctl, c, plan, frame, tm, &status);
    return status | allocate(ctl, thrust, moment, thrust_n, out);
}

/* ---------------------------------------------------------------------- */
/* the velocity output (fc/controller.h, FC_OUTPUT_VELOCITY)              */
/* ---------------------------------------------------------------------- */

/* The vertical velocity command that asks the vehicle for the acceleration a
 * body thrust T would give, a = g (T k_h / T_h - 1): (2.23) solved for u,
 * u_z = (a + a_P v_z) / k_P, inside +-u_max. */
static fc_real velocity_of_thrust(fc_controller *ctl, const step_context *c, const fc_vertical_estimate *v,
                                  fc_real thrust_n)
{
    fc_arith *ar = &ctl->ar;
    const fc_trajectory_tracking *tt = &ctl->tracking;
    const fc_real vertical_n = fc_mul(ar, thrust_n, c->tilt_cos, FC_SHIFT(FORCE, RATIO, FORCE));
    const fc_real share = fc_div(ar, vertical_n, v->hover_thrust_n, FC_DIV_SHIFT(FORCE, FORCE, RATIO));
    const fc_real accel =
        fc_mul(ar, fc_sub(ar, share, FC_INT(1, RATIO)), ctl->p.gravity_mps2, FC_SHIFT(RATIO, ACCEL, ACCEL));
    const fc_real drag = fc_mul(ar, tt->a_p_per_s.z, v->vz_mps, FC_SHIFT(RATIO, VEL, ACCEL));
    const fc_real u = fc_mul(ar, tt->inv_k_p_s.z, fc_add(ar, accel, drag), FC_SHIFT(RATIO, ACCEL, VEL));
    return fc_clamp(u, fc_neg(ar, tt->u_max_mps.z), tt->u_max_mps.z);
}

/* The body thrust that stands for a vertical command u_z: the acceleration
 * it asks of the vehicle, a = k_P u_z - a_P v_z (2.23), as T = T_h (1 + a / g) / k_h
 * in [0, 2 T_h]. What the landing's ramp starts from and the land detector
 * weighs. */
static fc_real thrust_of_velocity(fc_controller *ctl, const step_context *c, const fc_vertical_estimate *v,
                                  fc_real u_z_mps)
{
    fc_arith *ar = &ctl->ar;
    const fc_real accel = fc_sub(ar, fc_mul(ar, ctl->p.k_p_z_per_s, u_z_mps, FC_SHIFT(RATIO, VEL, ACCEL)),
                                 fc_mul(ar, ctl->tracking.a_p_per_s.z, v->vz_mps, FC_SHIFT(RATIO, VEL, ACCEL)));
    const fc_real share =
        fc_add(ar, FC_INT(1, RATIO), fc_mul(ar, accel, ctl->p.inv_gravity_s2pm, FC_SHIFT(ACCEL, RATIO, RATIO)));
    const fc_real vertical_n = fc_mul(ar, v->hover_thrust_n, share, FC_SHIFT(FORCE, RATIO, FORCE));
    const fc_real k_h = fc_max(c->tilt_cos, FC_C(0.5f, RATIO));
    const fc_real thrust_n = fc_div(ar, vertical_n, k_h, FC_DIV_SHIFT(FORCE, RATIO, FORCE));
    return fc_clamp(thrust_n, FC_INT(0, FORCE), fc_add(ar, v->hover_thrust_n, v->hover_thrust_n));
}

/* The heading: yaw_gain (psi_sp - psi) + psi_sp', inside +-yaw_rate_max.
 * psi - psi_sp from the shortest rotation from the setpoint's level
 * attitude to the attitude, 2 q_z (its sine of the half angle, twice: the
 * angle for small errors, and its sign for any). */
static fc_real yaw_rate_command(fc_controller *ctl, const step_context *c)
{
    fc_arith *ar = &ctl->ar;
    const fc_quat setpoint = level_attitude(&ctl->heading, &ctl->ar, c->in->yaw_setpoint_rad);
    const fc_quat error = fc_quat_shortest(ar, fc_quat_mul(ar, fc_quat_conj(ar, setpoint), *c->attitude));
    const fc_real twice_z = fc_add(ar, error.z, error.z);
    const fc_real feedback = fc_mul(ar, ctl->p.yaw_gain_per_s, twice_z, FC_SHIFT(RATIO, UNIT, RATE));
    const fc_real rate = fc_sub(ar, c->in->yaw_rate_setpoint_radps, feedback);
    return fc_clamp(rate, fc_neg(ar, ctl->p.yaw_rate_max_radps), ctl->p.yaw_rate_max_radps);
}

/* The velocity output's step, motors on: the tracking law (2.24) on the
 * reference, or (the failsafe, the ramp, a lost contact) the vertical
 * command of the thrust that path set, level and still horizontally. */
static fc_step_status velocity_output(fc_controller *ctl, const step_context *c, bool fly_reference, fc_real thrust_n,
                                      fc_controller_outputs *out)
{
    fc_controller_telemetry *tm = &out->telemetry;
    fc_step_status status = FC_STEP_OK;
    fc_vec3 u = fc_vec3_zero();
    fc_real yaw_rate = FC_INT(0, RATE);
    if (fly_reference) {
        const fc_gated_inputs *in = c->in;
        const fc_trajectory_tracking_input tin = {
            fc_vec3_make(in->position_setpoint_m.x, in->position_setpoint_m.y, tm->reference.z_m),
            fc_vec3_make(FC_INT(0, VEL), FC_INT(0, VEL), tm->reference.vz_mps),
            fc_vec3_make(FC_INT(0, ACCEL), FC_INT(0, ACCEL), tm->reference.az_mps2),
            fc_vec3_make(in->position_m.x, in->position_m.y, c->height_m),
            fc_vec3_make(in->velocity_mps.x, in->velocity_mps.y, c->vz_mps)};
        status |= passed_on(fc_trajectory_tracking_step(&ctl->tracking, &tin, &u));
        yaw_rate = yaw_rate_command(ctl, c);
    } else {
        u.z = velocity_of_thrust(ctl, c, &tm->vertical, thrust_n);
    }
    /* the thrust in force: the one the path set, or the one the law's command stands for */
    ctl->last_thrust_n = fly_reference ? thrust_of_velocity(ctl, c, &tm->vertical, u.z) : thrust_n;
    tm->attitude_setpoint = tm->attitude; /* the vehicle's own autopilot sets its attitude */
    tm->altitude = (fc_altitude_control_output){0}; /* the thrust path's law does not run */
    for (int i = 0; i < FC_MAX_ROTORS; i++) {
        out->rotor_speed[i] = FC_INT(0, UNIT);
    }
    out->rotor_count = 0u;
    out->motors_on = true;
    out->thrust_n = FC_INT(0, FORCE);
    out->moment_nm = fc_vec3_zero();
    out->output = FC_OUTPUT_VELOCITY;
    out->velocity_cmd_mps = u;
    out->yaw_rate_cmd_radps = yaw_rate;
    if (ctl->ar.saturated != 0u) {
        status |= FC_STEP_ARITH_SATURATED;
    }
    return status;
}

/* ---------------------------------------------------------------------- */
/* init and step                                                          */
/* ---------------------------------------------------------------------- */

fc_init_result fc_controller_init(fc_controller *ctl, const fc_controller_params *p)
{
    ctl->ready = false;
    ctl->p = (fc_controller_settings){p->dt_s,
                                      p->outer_divider,
                                      p->use_external_attitude,
                                      p->landing.gear_height_m,
                                      p->altitude.thrust_min_n,
                                      p->altitude.thrust_max_n,
                                      p->reference.offset_init_m,
                                      p->land_detector.range_fresh_s,
                                      p->output,
                                      p->velocity.yaw_gain_per_s,
                                      p->velocity.yaw_rate_max_radps,
                                      FC_INT(0, RATIO),
                                      p->gravity_mps2,
                                      p->velocity.tracking.k_p_per_s.z,
                                      fc_gain_of(p->dt_s, FC_DT_FRAC),
                                      fc_gain_of(FC_INT(0, DT), FC_DT_FRAC)};
    ctl->ar.saturated = 0u;
    /* dt^2 / 2, the pad trajectory's extrapolation (start_extrapolation) */
    const fc_real half_dt_s = fc_mul(&ctl->ar, p->dt_s, FC_C(0.5f, UNIT), FC_SHIFT(DT, UNIT, DT));
    ctl->p.half_dt_sq = fc_gain_of_product(p->dt_s, FC_DT_FRAC, half_dt_s, FC_DT_FRAC);
    mission_init(&ctl->mission);
    guard_init(&ctl->guard);
    rate_groups_init(&ctl->groups);
    pad_samples_init(&ctl->pad);
    heading_init(&ctl->heading); /* psi = 0 */
    ctl->last_saturation = 0u;
    ctl->last_thrust_n = FC_INT(0, FORCE);
    /* every module validates its own parameters; the first failure is the answer */
    fc_init_result result = FC_INIT_OK;
    const fc_init_result parts[] = {
        fc_attitude_estimator_init(&ctl->estimator, &p->estimator),
        fc_attitude_control_init(&ctl->attitude, &p->attitude),
        fc_allocation_init(&ctl->allocation, &p->allocation),
        fc_altitude_reference_init(&ctl->reference, &p->reference),
        fc_altitude_control_init(&ctl->altitude, &p->altitude),
        fc_position_control_init(&ctl->position, &p->horizontal),
        fc_pad_motion_init(&ctl->pad_motion, &p->pad_motion),
        fc_landing_init(&ctl->landing, &p->landing),
        fc_input_gate_init(&ctl->gate, &p->gate),
        fc_vertical_estimator_init(&ctl->vertical, &p->vertical),
        fc_land_detector_init(&ctl->land_detector, &p->land_detector),
        fc_failsafe_init(&ctl->failsafe, &p->failsafe),
        FC_VELOCITY_OUTPUT ? fc_trajectory_tracking_init(&ctl->tracking, &p->velocity.tracking) : FC_INIT_OK,
        velocity_output_valid(p) ? FC_INIT_OK : FC_INIT_BAD_PARAM,
    };
    for (unsigned i = 0u; i < sizeof parts / sizeof parts[0]; i++) {
        if (parts[i] != FC_INIT_OK && result == FC_INIT_OK) {
            result = parts[i];
        }
    }
    if (result == FC_INIT_OK) {
        result = fc_controller_params_agree(p);
    }
    ctl->step_s = fc_convert(&ctl->ar, p->dt_s, FC_DT_FRAC, FC_TIME_FRAC);
    ctl->inv_dt_per_s = fc_div(&ctl->ar, FC_INT(1, DT), p->dt_s, FC_DIV_SHIFT(DT, DT, GAIN));
    if (result == FC_INIT_OK) {
        /* g in (0, 100] (fc_controller_params_agree) */
        ctl->p.inv_gravity_s2pm = fc_div(&ctl->ar, FC_INT(1, RATIO), p->gravity_mps2, FC_DIV_SHIFT(RATIO, ACCEL, RATIO));
    }
    ctl->ready = result == FC_INIT_OK;
    return result;
}

fc_step_status fc_controller_step(fc_controller *ctl, const fc_controller_inputs *in_raw, fc_controller_outputs *out)
{
    fc_controller_telemetry *tm = &out->telemetry;
    if (!ctl->ready) {
        motors_off(ctl, out);
        telemetry_not_ready(ctl, tm);
        return FC_STEP_NOT_READY;
    }
    /* Outputs written once: the motors at the end of each path (off on the
     * paths that return early), the telemetry as it is formed, the fields
     * that only some paths form set first */
    telemetry_defaults(tm);
    ctl->ar.saturated = 0u;
    const uint8_t frame = next_minor_frame(&ctl->groups, ctl->p.outer_divider);
    const fc_landing_state state_before = ctl->landing.state;
    const fc_landing_reason reason_before = ctl->landing.reason;

    step_context c;
    fc_step_status status = sense(ctl, in_raw, &c, tm);
    status |= take_command(ctl, in_raw->command, &c, tm);
    status |= gate_inputs(ctl, in_raw, &c);
    status |= arm(ctl, &c, tm);
    watch_inputs(ctl, &c);
    tm->failsafe_cause = ctl->failsafe.cause;
    status |= pad_samples_step(ctl, in_raw, frame, &c, tm);
    status |= vertical_step(ctl, in_raw, &c, tm);
    reckon_height(ctl, &c, &tm->vertical);

    if (!ctl->mission.armed) {
        return status | disarmed(ctl, out, state_before, reason_before);
    }
    if (failsafe_landed(ctl)) {
        return status | stop_after_failsafe_landing(ctl, out, state_before, reason_before);
    }
    begin_task(ctl, c.command);
    vertical_plan plan;
    status |= plan_vertical(ctl, &c, tm, &plan);
    landing_telemetry(ctl, tm, state_before, reason_before);
    if (!plan.motors_on || !plan.fly_reference) {
        tm->altitude = (fc_altitude_control_output){0};
    }
    if (!plan.motors_on) {
        return status | motors_stopped_by_landing(ctl, out);
    }
    if (FC_VELOCITY_OUTPUT && ctl->p.output == FC_OUTPUT_VELOCITY) {
        return status | velocity_output(ctl, &c, plan.fly_reference, plan.thrust_n, out);
    }
    status |= fly_rotors(ctl, &c, &plan, frame, out);
    if (ctl->ar.saturated != 0u) {
        status |= FC_STEP_ARITH_SATURATED;
    }
    return status;
}
