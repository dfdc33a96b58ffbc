/*
 * fc/input_gate.h - plausibility of the inputs the mission flies on (SPEC
 * "Safety contract": plausibility, not only finiteness). A sample inside the
 * numeric range can still be one the airframe cannot produce; such a sample
 * is rejected like a NaN, so that one glitch cannot swing the thrust or the
 * moments to a limit in one step.
 *
 * Measurements, each checked against the last accepted sample, t seconds
 * ago (per axis):
 *   velocity  |v| <= speed_max and |v - v_last| <= accel_max t + velocity_jump
 *   position  |p - p_last| <= speed_max t + position_jump
 *   pad       |z_d'| <= pad_speed_max, |z_d''| <= pad_accel_max and
 *             |z_d - z_d,last| <= pad_speed_max t + position_jump
 * A rejected sample leaves the last accepted one in place (the caller holds
 * it, then fails safe). After reanchor_s of rejections in a row the newest
 * sample that passes the absolute checks becomes the new reference, still
 * reported as rejected at that step, so that a sensor whose frame really
 * moved can be accepted again (its samples from then on must agree with it).
 * Commands and feed-forward, rate-limited rather than rejected (a new
 * setpoint is legitimate, a step in it is not what the loops should see):
 *   position setpoint  moves at most setpoint_speed t towards the command
 *   yaw setpoint       turns at most yaw_rate_max t, the short way round
 *   pad z_d', z_d''    change at most pad_accel_max t and pad_jerk_max t
 * Before the first accepted sample, and while the caller says the limits
 * are off (disarmed), commands pass unchanged; the pad's first sample once
 * it is in use (use_pad) has only its absolute checks and no limits.
 */
#ifndef FC_INPUT_GATE_H
#define FC_INPUT_GATE_H

#include <stdbool.h>

#include "fc/altitude_reference.h"
#include "fc/status.h"
#include "fc/vec3.h"

typedef struct fc_input_gate_params {
    fc_real dt_s;                 /* DT: the fixed step */
    fc_real speed_max_mps;        /* VEL: the vehicle's top speed, (0, 100] */
    fc_real accel_max_mps2;       /* ACCEL: its largest acceleration, (0, 200] */
    fc_real position_jump_m;      /* LENGTH: noise and a slow sensor's steps, (0, 100] */
    fc_real velocity_jump_mps;    /* VEL: (0, 100] */
    fc_real setpoint_speed_mps;   /* VEL: (0, 100] */
    fc_real yaw_rate_max_radps;   /* RATE: (0, 100] */
    fc_real pad_speed_max_mps;    /* VEL: (0, 100] */
    fc_real pad_accel_max_mps2;   /* ACCEL: (0, 200] */
    fc_real pad_jerk_max_mps3;    /* GAIN: (0, 10000] */
    fc_real reanchor_s;           /* TIME: (0, 600] */
} fc_input_gate_params;

/* What the gate looks at: the mission's inputs of fc_controller_inputs. */
typedef struct fc_gated_inputs {
    fc_vec3 position_m;           /* LENGTH */
    fc_vec3 velocity_mps;         /* VEL */
    fc_vertical_trajectory pad;   /* the pad's trajectory (checked when use_pad) */
    fc_vec3 position_setpoint_m;  /* LENGTH */
    fc_real yaw_setpoint_rad;     /* ANGLE */
    fc_real yaw_rate_setpoint_radps; /* RATE: its rate, fed forward; clamped to +-yaw_rate_max */
} fc_gated_inputs;

/* A sample for the gate, fc_gated_inputs's fields where the caller holds
 * them (the vectors by pointer: read in place, not copied for each step). */
typedef struct fc_input_gate_input {
    const fc_vec3 *position_m;                /* LENGTH */
    const fc_vec3 *velocity_mps;              /* VEL */
    const fc_vertical_trajectory *pad;        /* checked when use_pad */
    const fc_vec3 *position_setpoint_m;       /* LENGTH */
    fc_real yaw_setpoint_rad;                 /* ANGLE */
    fc_real yaw_rate_setpoint_radps;          /* RATE */
} fc_input_gate_input;

/* The limits over one step, formed at init from the parameters: a sample
 * a step after the last accepted one (the usual case) is checked against
 * these, any other against the limits over its own interval. */
typedef struct fc_input_gate_step_limits {
    fc_real step_s;              /* TIME: dt */
    fc_real velocity_slack_mps;  /* VEL: accel_max dt + velocity_jump */
    fc_real position_slack_m;    /* LENGTH: speed_max dt + position_jump */
    fc_real pad_slack_m;         /* LENGTH: pad_speed_max dt + position_jump */
    fc_real setpoint_step_m;     /* LENGTH: setpoint_speed dt */
    fc_real yaw_step_rad;        /* ANGLE: yaw_rate_max dt */
    fc_real pad_speed_step_mps;  /* VEL: pad_accel_max dt */
    fc_real pad_accel_step_mps2; /* ACCEL: pad_jerk_max dt */
} fc_input_gate_step_limits;

typedef struct fc_input_gate {
    fc_input_gate_params p;
    fc_input_gate_step_limits per_step;
    fc_gain accel_max;            /* accel_max_mps2, m/s^2: the slacks of a longer interval */
    fc_gain speed_max;            /* speed_max_mps, m/s */
    fc_gain pad_speed_max;        /* pad_speed_max_mps, m/s */
    fc_gated_inputs accepted;     /* the last accepted measurements, the limited commands */
    fc_real since_accepted_s;     /* TIME: since the last accepted measurement */
    fc_real rejected_s;           /* TIME: rejected in a row this long */
    bool have_accepted;
    bool pad_accepted;            /* accepted.pad is a sample (the pad was in use at the last acceptance) */
    bool ready;
    fc_arith ar;
} fc_input_gate;

/* Limits for a vehicle of top speed speed_max_mps and largest acceleration
 * accel_max_mps2 whose position comes with noise and steps up to
 * position_jump_m: velocity jumps of 0.5 m/s, setpoints at 2 m/s and 2 rad/s,
 * a pad of up to 3 m/s, 10 m/s^2 and 50 m/s^3, re-anchoring after 1 s. */
void fc_input_gate_default_params(fc_input_gate_params *p, fc_real dt_s, fc_real speed_max_mps,
                                  fc_real accel_max_mps2, fc_real position_jump_m);

fc_init_result fc_input_gate_init(fc_input_gate *g, const fc_input_gate_params *p);

/* Forget the reference: the next usable sample is accepted as it is. */
void fc_input_gate_reset(fc_input_gate *g);

/* One step: g->accepted holds what to fly on (in's measurements if
 * accepted, else the last accepted ones; the commands limited), and so does
 * out unless it is NULL (a caller that reads g->accepted in place). Returns
 * true when the measurements (and the pad, with use_pad) were accepted. */
bool fc_input_gate_step(fc_input_gate *g, const fc_input_gate_input *in, bool use_pad, bool limit_commands,
                        fc_gated_inputs *out);

#endif /* FC_INPUT_GATE_H */
