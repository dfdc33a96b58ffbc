/* input_gate.c - plausibility gates and command rate limits (fc/input_gate.h). */
#include "fc/input_gate.h"

#include <stddef.h>

#define GATE_PI_RAD FC_C(3.14159265f, ANGLE)
#define GATE_TWO_PI_RAD FC_C(6.28318531f, ANGLE)

void fc_input_gate_default_params(fc_input_gate_params *p, fc_real dt_s, fc_real speed_max_mps,
                                  fc_real accel_max_mps2, fc_real position_jump_m)
{
    p->dt_s = dt_s;
    p->speed_max_mps = speed_max_mps;
    p->accel_max_mps2 = accel_max_mps2;
    p->position_jump_m = position_jump_m;
    p->velocity_jump_mps = FC_C(0.5f, VEL);
    p->setpoint_speed_mps = FC_INT(2, VEL);
    p->yaw_rate_max_radps = FC_INT(2, RATE);
    p->pad_speed_max_mps = FC_INT(3, VEL);
    p->pad_accel_max_mps2 = FC_INT(10, ACCEL);
    p->pad_jerk_max_mps3 = FC_INT(50, GAIN);
    p->reanchor_s = FC_INT(1, TIME);
}

static bool gate_params_valid(const fc_input_gate_params *p)
{
    const bool finite = fc_is_finite(p->dt_s) && fc_is_finite(p->speed_max_mps) && fc_is_finite(p->accel_max_mps2) &&
                        fc_is_finite(p->position_jump_m) && fc_is_finite(p->velocity_jump_mps) &&
                        fc_is_finite(p->setpoint_speed_mps) && fc_is_finite(p->yaw_rate_max_radps) &&
                        fc_is_finite(p->pad_speed_max_mps) && fc_is_finite(p->pad_accel_max_mps2) &&
                        fc_is_finite(p->pad_jerk_max_mps3) && fc_is_finite(p->reanchor_s);
    const fc_real speed_max = FC_INT(100, VEL);
    return finite && p->dt_s > FC_INT(0, DT) && p->dt_s <= FC_C(0.1f, DT) && p->speed_max_mps > FC_INT(0, VEL) &&
           p->speed_max_mps <= speed_max && p->accel_max_mps2 > FC_INT(0, ACCEL) &&
           p->accel_max_mps2 <= FC_INT(200, ACCEL) && p->position_jump_m > FC_INT(0, LENGTH) &&
           p->position_jump_m <= FC_INT(100, LENGTH) && p->velocity_jump_mps > FC_INT(0, VEL) &&
           p->velocity_jump_mps <= speed_max && p->setpoint_speed_mps > FC_INT(0, VEL) &&
           p->setpoint_speed_mps <= speed_max && p->yaw_rate_max_radps > FC_INT(0, RATE) &&
           p->yaw_rate_max_radps <= FC_INT(100, RATE) && p->pad_speed_max_mps > FC_INT(0, VEL) &&
           p->pad_speed_max_mps <= speed_max && p->pad_accel_max_mps2 > FC_INT(0, ACCEL) &&
           p->pad_accel_max_mps2 <= FC_INT(200, ACCEL) && p->pad_jerk_max_mps3 > FC_INT(0, GAIN) &&
           p->pad_jerk_max_mps3 <= FC_INT(10000, GAIN) && p->reanchor_s > FC_INT(0, TIME) &&
           p->reanchor_s <= FC_INT(600, TIME);
}

fc_init_result fc_input_gate_init(fc_input_gate *g, const fc_input_gate_params *p)
{
    g->ready = false;
    g->ar.saturated = 0u;
    g->accepted = (fc_gated_inputs){0};
    fc_input_gate_reset(g);
    if (!gate_params_valid(p)) {
        return FC_INIT_BAD_PARAM;
    }
    g->p = *p;
    fc_arith *ar = &g->ar;
    fc_input_gate_step_limits *l = &g->per_step;
    l->step_s = fc_convert(ar, p->dt_s, FC_DT_FRAC, FC_TIME_FRAC);
    l->velocity_slack_mps = fc_add(ar, fc_mul(ar, p->accel_max_mps2, l->step_s, FC_SHIFT(ACCEL, TIME, VEL)),
                                   p->velocity_jump_mps);
    l->position_slack_m =
        fc_add(ar, fc_mul(ar, p->speed_max_mps, l->step_s, FC_SHIFT(VEL, TIME, LENGTH)), p->position_jump_m);
    l->pad_slack_m =
        fc_add(ar, fc_mul(ar, p->pad_speed_max_mps, l->step_s, FC_SHIFT(VEL, TIME, LENGTH)), p->position_jump_m);
    l->setpoint_step_m = fc_mul(ar, p->setpoint_speed_mps, p->dt_s, FC_SHIFT(VEL, DT, LENGTH));
    l->yaw_step_rad = fc_mul(ar, p->yaw_rate_max_radps, p->dt_s, FC_SHIFT(RATE, DT, ANGLE));
    l->pad_speed_step_mps = fc_mul(ar, p->pad_accel_max_mps2, p->dt_s, FC_SHIFT(ACCEL, DT, VEL));
    l->pad_accel_step_mps2 = fc_mul(ar, p->pad_jerk_max_mps3, p->dt_s, FC_SHIFT(GAIN, DT, ACCEL));
    g->accel_max = fc_gain_of(p->accel_max_mps2, FC_ACCEL_FRAC);
    g->speed_max = fc_gain_of(p->speed_max_mps, FC_VEL_FRAC);
    g->pad_speed_max = fc_gain_of(p->pad_speed_max_mps, FC_VEL_FRAC);
    g->ready = true;
    return FC_INIT_OK;
}

void fc_input_gate_reset(fc_input_gate *g)
{
    g->since_accepted_s = FC_INT(0, TIME);
    g->rejected_s = FC_INT(0, TIME);
    g->have_accepted = false;
    g->pad_accepted = false;
}

/* rate t + margin, t the time since the last accepted sample (in the
 * format of margin: time_shift = FC_GAIN_SHIFT(TIME, that format)): the
 * slack of a sample later than a step after it (one step's is formed at
 * init). */
static fc_real slack_over_interval(fc_input_gate *g, fc_gain rate, fc_real margin, int time_shift)
{
    return fc_add_inline(&g->ar, fc_mul_gain(&g->ar, g->since_accepted_s, rate, time_shift), margin);
}

/* low <= x <= high: fc_within(x, high) for low = -high, a number high >= 0
 * (a NaN or an infinite x fails both), with -high formed once by the
 * caller for several x. */
static inline __attribute__((always_inline)) bool gate_between(fc_real x, fc_real low, fc_real high)
{
    return x >= low && x <= high;
}

/* The measurements' absolute checks: numbers the airframe (and the pad) can be at. */
static bool plausible(const fc_input_gate *g, const fc_input_gate_input *in, bool use_pad)
{
    const bool pad_ok = !use_pad || (fc_within(in->pad->z_m, FC_C(FC_INPUT_MAX_LENGTH_M, LENGTH)) &&
                                     fc_within(in->pad->vz_mps, g->p.pad_speed_max_mps) &&
                                     fc_within(in->pad->az_mps2, g->p.pad_accel_max_mps2));
    const fc_real speed_max = g->p.speed_max_mps;
    const fc_real speed_min = -speed_max; /* speed_max in (0, 100] (gate_params_valid) */
    const fc_vec3 *v = in->velocity_mps;
    return fc_vec3_within(*in->position_m, FC_C(FC_INPUT_MAX_LENGTH_M, LENGTH)) &&
           gate_between(v->x, speed_min, speed_max) && gate_between(v->y, speed_min, speed_max) &&
           gate_between(v->z, speed_min, speed_max) && pad_ok;
}

/* |a - b| <= slack on each axis (the first axis that fails ends it), as
 * -slack <= a - b <= slack with -slack formed once (slack > 0: a margin
 * > 0 and a product >= 0; a and b numbers, so is a - b). */
static inline __attribute__((always_inline)) bool moved_within(fc_arith *ar, const fc_vec3 *a, const fc_vec3 *b,
                                                               fc_real slack)
{
    const fc_real low = -slack;
    return gate_between(fc_sub_inline(ar, a->x, b->x), low, slack) &&
           gate_between(fc_sub_inline(ar, a->y, b->y), low, slack) &&
           gate_between(fc_sub_inline(ar, a->z, b->z), low, slack);
}

/* |v - v_last| <= slack on each axis (the first axis that fails ends it):
 * moved_within without saturation, v and v_last passed the speed check
 * (|v_i| <= speed_max <= 100 m/s), so v - v_last is inside VEL. */
static inline __attribute__((always_inline)) bool speed_changed_within(const fc_vec3 *v, const fc_vec3 *v_last,
                                                                       fc_real slack)
{
    const fc_real low = -slack;
    return gate_between(v->x - v_last->x, low, slack) && gate_between(v->y - v_last->y, low, slack) &&
           gate_between(v->z - v_last->z, low, slack);
}

/* The jumps since the last accepted sample, t ago, each against its slack
 * over t: one step's (the usual case) as formed at init, a longer
 * interval's formed here. The first check that fails ends it. */
static bool consistent(fc_input_gate *g, const fc_input_gate_input *in, bool use_pad)
{
    fc_arith *ar = &g->ar;
    const fc_input_gate_params *p = &g->p;
    const fc_input_gate_step_limits *l = &g->per_step;
    const fc_gated_inputs *last = &g->accepted;
    const bool one_step = g->since_accepted_s == l->step_s;
    const fc_real velocity_slack =
        one_step ? l->velocity_slack_mps
                 : slack_over_interval(g, g->accel_max, p->velocity_jump_mps, FC_GAIN_SHIFT(TIME, VEL));
    if (!speed_changed_within(in->velocity_mps, &last->velocity_mps, velocity_slack)) {
        return false;
    }
    const fc_real position_slack =
        one_step ? l->position_slack_m
                 : slack_over_interval(g, g->speed_max, p->position_jump_m, FC_GAIN_SHIFT(TIME, LENGTH));
    if (!moved_within(ar, in->position_m, &last->position_m, position_slack)) {
        return false;
    }
    if (!use_pad || !g->pad_accepted) {
        return true;
    }
    const fc_real pad_slack =
        one_step ? l->pad_slack_m
                 : slack_over_interval(g, g->pad_speed_max, p->position_jump_m, FC_GAIN_SHIFT(TIME, LENGTH));
    return fc_within(fc_sub_inline(ar, in->pad->z_m, last->pad.z_m), pad_slack);
}

/* last + (target - last) limited to +-step. */
static fc_real toward(fc_arith *ar, fc_real last, fc_real target, fc_real step)
{
    return fc_add_inline(ar, last, fc_clamp(fc_sub_inline(ar, target, last), fc_neg(ar, step), step));
}

/* toward without saturation, for the pad's speed and acceleration: the
 * last accepted value and the target both passed the pad's checks
 * (|z_d'| <= pad_speed_max <= 100 m/s, |z_d''| <= pad_accel_max <= 200
 * m/s^2; a limited value lies between the two it came from), so their
 * difference and the result stay inside VEL and ACCEL; step >= 0. */
static inline __attribute__((always_inline)) fc_real pad_toward(fc_real last, fc_real target, fc_real step)
{
    return last + fc_clamp(target - last, -step, step);
}

/* An angle in [-7, 7] rad (or a difference of two in [-pi, pi]) to [-pi, pi]:
 * one turn added or taken is enough, 7 - 2 pi < pi. */
static fc_real wrapped(fc_arith *ar, fc_real angle_rad)
{
    if (angle_rad > GATE_PI_RAD) {
        return fc_sub(ar, angle_rad, GATE_TWO_PI_RAD);
    }
    if (angle_rad < fc_neg(ar, GATE_PI_RAD)) {
        return fc_add(ar, angle_rad, GATE_TWO_PI_RAD);
    }
    return angle_rad;
}

static bool vec3_equal(fc_vec3 a, fc_vec3 b)
{
    return a.x == b.x && a.y == b.y && a.z == b.z;
}

/* The accepted position and yaw setpoints moved towards the command at their
 * rates (a command already reached, the usual case, stays as it is). */
static void limit_setpoints(fc_input_gate *g, const fc_input_gate_input *in)
{
    fc_arith *ar = &g->ar;
    fc_gated_inputs *accepted = &g->accepted;
    if (!vec3_equal(*in->position_setpoint_m, accepted->position_setpoint_m)) {
        const fc_real step_m = g->per_step.setpoint_step_m;
        fc_vec3 *setpoint = &accepted->position_setpoint_m;
        setpoint->x = toward(ar, setpoint->x, in->position_setpoint_m->x, step_m);
        setpoint->y = toward(ar, setpoint->y, in->position_setpoint_m->y, step_m);
        setpoint->z = toward(ar, setpoint->z, in->position_setpoint_m->z, step_m);
    }
    if (in->yaw_setpoint_rad != accepted->yaw_setpoint_rad) {
        const fc_real step_rad = g->per_step.yaw_step_rad;
        const fc_real last_yaw = wrapped(ar, accepted->yaw_setpoint_rad);
        const fc_real turn = wrapped(ar, fc_sub(ar, wrapped(ar, in->yaw_setpoint_rad), last_yaw));
        accepted->yaw_setpoint_rad = wrapped(ar, fc_add(ar, last_yaw, fc_clamp(turn, fc_neg(ar, step_rad), step_rad)));
    }
}

/* *to = *from field by field (a struct assignment is a byte loop on the
 * ATmega at -Os). */
static inline __attribute__((always_inline)) void gate_copy_vec3(fc_vec3 *to, const fc_vec3 *from)
{
    to->x = from->x;
    to->y = from->y;
    to->z = from->z;
}

/* A sample taken: its measurements, and its commands (the pad's speed and
 * acceleration, fed forward to the reference, among them) at their rates
 * from the last accepted ones unless limit_commands is off or this is the
 * first sample. Updates g->accepted in place. */
static void accept(fc_input_gate *g, const fc_input_gate_input *in, bool use_pad, bool limit_commands, bool first)
{
    fc_arith *ar = &g->ar;
    fc_gated_inputs *accepted = &g->accepted;
    gate_copy_vec3(&accepted->position_m, in->position_m);
    gate_copy_vec3(&accepted->velocity_mps, in->velocity_mps);
    if (use_pad) {
        if (g->pad_accepted && limit_commands) {
            fc_vertical_trajectory *pad = &accepted->pad;
            pad->z_m = in->pad->z_m;
            pad->vz_mps = pad_toward(pad->vz_mps, in->pad->vz_mps, g->per_step.pad_speed_step_mps);
            pad->az_mps2 = pad_toward(pad->az_mps2, in->pad->az_mps2, g->per_step.pad_accel_step_mps2);
        } else {
            accepted->pad = *in->pad;
        }
    }
    g->pad_accepted = use_pad;
    if (first || !limit_commands) {
        accepted->position_setpoint_m = *in->position_setpoint_m;
        accepted->yaw_setpoint_rad = in->yaw_setpoint_rad;
    } else {
        limit_setpoints(g, in);
    }
    /* the rate fed forward no faster than the setpoint may turn */
    const fc_real yaw_rate_max = g->p.yaw_rate_max_radps;
    accepted->yaw_rate_setpoint_radps = fc_clamp(in->yaw_rate_setpoint_radps, fc_neg(ar, yaw_rate_max), yaw_rate_max);
    g->since_accepted_s = FC_INT(0, TIME);
    g->have_accepted = true;
}

bool fc_input_gate_step(fc_input_gate *g, const fc_input_gate_input *in, bool use_pad, bool limit_commands,
                        fc_gated_inputs *out)
{
    if (!g->ready) {
        if (out != NULL) {
            *out = (fc_gated_inputs){0};
        }
        return false;
    }
    fc_arith *ar = &g->ar;
    ar->saturated = 0u;
    const fc_real step_s = g->per_step.step_s;
    /* times up to 600 s plus a step of at most 0.1 s: inside TIME, no saturation */
    g->since_accepted_s = fc_min(g->since_accepted_s + step_s, FC_INT(600, TIME));
    const bool commands_ok = fc_vec3_within(*in->position_setpoint_m, FC_C(FC_INPUT_MAX_LENGTH_M, LENGTH)) &&
                             fc_within(in->yaw_setpoint_rad, FC_C(7.0f, ANGLE)) &&
                             fc_within(in->yaw_rate_setpoint_radps, FC_INT(100, RATE));
    const bool absolute_ok = commands_ok && plausible(g, in, use_pad);
    if (!use_pad) {
        g->pad_accepted = false; /* a stale pad is no reference for the next one */
    }
    const bool first = !g->have_accepted;
    const bool accepted = absolute_ok && (first || consistent(g, in, use_pad));
    const bool reanchor = absolute_ok && !accepted && g->rejected_s >= g->p.reanchor_s;
    if (accepted || reanchor) {
        accept(g, in, use_pad, limit_commands, first);
    }
    g->rejected_s = accepted ? FC_INT(0, TIME) : fc_min(g->rejected_s + step_s, FC_INT(600, TIME));
    if (reanchor) {
        g->rejected_s = FC_INT(0, TIME);
    }
    if (out != NULL) {
        *out = g->accepted;
    }
    return accepted;
}
