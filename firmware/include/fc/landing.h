/*
 * fc/landing.h - the landing mission: a small explicit state machine
 * (SPEC "landing mission", dissertation 1.1 and 2.6.7), stepped by
 * fc_controller_step. It decides; the altitude law flies what it decides.
 *
 *   IDLE ----LAND/HOLD----> HOLD ---settled---> OBSERVE ---pad learnt---> DESCEND
 *   DESCEND ---contact seen---> TOUCHDOWN ---confirmed---> DISARM (thrust ramp) --> LANDED
 *   OBSERVE/DESCEND/TOUCHDOWN --(a reason below)--> ABORT ---back at the hold point---> HOLD
 *
 * HOLD / OBSERVE: the reference (3.6) takes the gear to hold_height above
 *   the pad's mean level (learnt), clear of its heave: z_d = c, z_r_bias =
 *   gear + hold, the offset starting from where the vehicle is. OBSERVE is
 *   HOLD while the pad estimator's confidence is not yet enough.
 * DESCEND: (3.6) around the pad's estimated motion (z_d, z_d', z_d'' now):
 *   z_r = z_d + (gear - dip) + z_0 e^(-t/tau_d). The reference follows the
 *   pad's speed, so the gear meets the surface with a relative speed near
 *   dip / tau_d when the offset has decayed to dip: the planned touchdown. The
 *   touchdown window opens when the reference's gear is window_m above the
 *   surface (touchdown_window in the output): no contact is planned before.
 * TOUCHDOWN: the gear height from the range finder (range k_h - gear) is below
 *   contact_height_m and the vehicle stays above its reference by dip / 2 (the
 *   pad holds it while the reference goes on down); confirmed after
 *   contact_confirm_s of samples that all say so (a sample that does not
 *   restarts the time); lost, back to DESCEND, when the gear is 3 contact
 *   heights off the surface or the vehicle back on its reference.
 *   Pressing (press_at_contact): once the range finder puts the gear within contact_height_m of
 *   the surface inside the window, the reference jumps to where (3.6) ends,
 *   dip below the surface (moving with the pad), until the gear is 3 contact
 *   heights off again. Near the surface the ground effect cushions the vehicle,
 *   and a reference that still approaches at dip / tau_d leaves it resting on
 *   the pad with little downward force: a pad starting down (its deceleration
 *   at the top of the heave) then outruns it and the gear hops. Pressed, the
 *   vehicle stays on the surface. Contact is still seen and confirmed against
 *   the unpressed (3.6) reference, so the press cannot confirm itself: a
 *   vehicle pressed while a few mm up is on the surface before (3.6) has gone
 *   dip / 2 under it. Off where the ranger's noise is near contact_height_m
 *   (a press on a noisy sample drives the vehicle into the pad).
 * DESCEND, shaped (descent_shaping): the offset of (3.6) above the surface
 *   is no longer a fixed exponential of time but integrated from a rate,
 *     offset' = max(v_f, -offset / tau_d),   0 <= offset <= its start,
 *   v_f the descent field v_zd of (2.25)-(2.28) (fc/descent_shaping.h)
 *   through 1/(shaping_filter_s s + 1) (the field follows the horizontal
 *   error and its noise), v_zd at the vehicle's position relative to the pad
 *   centre (x, y from the position setpoint, z the height above the pad's
 *   estimate) and the pad's attitude. (3.6)'s own rate -offset / tau_d is
 *   the fastest descent: the planned touchdown (dip / tau_d) stays as
 *   unshaped; the field slows the descent, holds it or climbs (up to the
 *   start) when the horizontal regulation is poor ((2.26), (2.27)) or when
 *   the pad rolls or pitches, which moves the vehicle's position in the pad
 *   frame off the pad's normal ((2.28), the aversive term): an asymmetric
 *   touchdown on a tilted deck tips the vehicle towards its low side.
 *   z_r = z_d + (gear - dip) + offset, z_r' = z_d' + offset', z_r'' = z_d''.
 *   Committed: once the reference's gear is within shaping_commit_m of the
 *   surface (offset <= dip + commit), or the range finder has put the gear
 *   at the surface (3 contact heights), the rate is (3.6)'s to the end of
 *   the descent. A vehicle that the field held just above a rolling deck
 *   would be met by its rising side; above the commit height the deck's
 *   swept volume is clear, and a committed final approach is as unshaped.
 *   The window opens at the same offset as unshaped.
 * DISARM: the thrust ramps from its value at contact to 0 over ramp_s; then
 *   LANDED, motors off.
 * ABORT (from DESCEND; from TOUCHDOWN only by the operator): horizontal
 *   error, tilt, prediction confidence, pad acceleration, a range finder gone
 *   quiet, or the operator (request HOLD). Once the range finder has put the
 *   gear within 3 contact heights of the surface only the operator aborts:
 *   climbing away from the surface would be the riskier move. The reference
 *   climbs back to the hold point; after abort_retries_max aborts the mission
 *   stays in HOLD.
 * Every transition carries a reason (fc_landing_reason) for the platform's log.
 */
#ifndef FC_LANDING_H
#define FC_LANDING_H

#include "fc/altitude_reference.h"
#include "fc/descent_shaping.h"
#include "fc/pad_motion.h"
#include "fc/status.h"

typedef enum fc_landing_state {
    FC_LANDING_IDLE = 0,  /* not flying a landing (disarmed, or tracking the pad) */
    FC_LANDING_HOLD,      /* going to / holding the hold point */
    FC_LANDING_OBSERVE,   /* at the hold point, learning the pad */
    FC_LANDING_DESCEND,
    FC_LANDING_TOUCHDOWN, /* contact seen, being confirmed */
    FC_LANDING_DISARM,    /* thrust ramp-down */
    FC_LANDING_LANDED,    /* motors off on the pad */
    FC_LANDING_ABORT,     /* climbing back to the hold point */
    FC_LANDING_FAILSAFE,  /* inputs lost: level, controlled descent (set by fc_controller) */
    FC_LANDING_STATE_COUNT
} fc_landing_state;

typedef enum fc_landing_reason {
    FC_REASON_NONE = 0,
    FC_REASON_COMMANDED,            /* the request changed (LAND, HOLD, or disarm) */
    FC_REASON_HOLD_SETTLED,         /* at the hold point */
    FC_REASON_PAD_LEARNT,           /* confidence, accelerations and position allow a descent */
    FC_REASON_CONTACT,              /* the range finder sees the gear on the pad */
    FC_REASON_CONTACT_LOST,         /* ... and then not */
    FC_REASON_CONTACT_CONFIRMED,
    FC_REASON_RAMP_DONE,            /* motors off */
    FC_REASON_ABORT_COMMANDED,      /* HOLD requested during a descent */
    FC_REASON_ABORT_HORIZONTAL,     /* horizontal error beyond its limit */
    FC_REASON_ABORT_TILT,           /* tilt beyond its limit */
    FC_REASON_ABORT_CONFIDENCE,     /* the pad's prediction is no longer trusted */
    FC_REASON_ABORT_PAD_ACCEL,      /* the pad accelerates too hard for a safe contact */
    FC_REASON_ABORT_RANGE_LOST,     /* no range sample for range_timeout_s */
    FC_REASON_ABORT_CLIMB_DONE,     /* back at the hold point after an abort */
    FC_REASON_RETRIES_EXHAUSTED,    /* too many aborts: holding */
    FC_REASON_INPUTS_LOST,          /* position or velocity bad too long: failsafe (fc_controller) */
    FC_REASON_INPUTS_BACK,          /* good again: the mission resumes from HOLD */
    FC_REASON_FAILSAFE_LANDED,      /* failsafe descent ended on the ground: motors off */
    FC_REASON_COUNT
} fc_landing_reason;

typedef enum fc_landing_request {
    FC_LANDING_REQUEST_NONE = 0,    /* not flying the mission: IDLE */
    FC_LANDING_REQUEST_HOLD,        /* hold and learn; abort any descent */
    FC_LANDING_REQUEST_LAND
} fc_landing_request;

typedef struct fc_landing_params {
    fc_real dt_s;                   /* DT: the fixed step */
    fc_real gear_height_m;          /* LENGTH: CG to the bottom of the gear, (0, 10] */
    fc_real hold_height_m;          /* LENGTH: gear above the pad's mean while holding, (0, 100] */
    fc_real hold_tau_s;             /* TIME: tau of (3.6) to the hold point, [0.05, 100] */
    fc_real hold_settle_m;          /* LENGTH: |z - z_r| and |z - hold point| within this ... , (0, 10] */
    fc_real hold_settle_s;          /* TIME: ... for this long: settled, [0, 600] */
    fc_real descent_tau_s;          /* TIME: tau of (3.6) in the descent, [0.05, 100] */
    fc_real touchdown_dip_m;        /* LENGTH: the reference's gear ends this far below the surface, (0, 1] */
    fc_real touchdown_window_m;     /* LENGTH: contact expected once the reference's gear is this close, [0, 1] */
    fc_real contact_height_m;       /* LENGTH: gear height from range under which contact is seen, (0, 1] */
    fc_real contact_confirm_s;      /* TIME: [0, 10] */
    bool press_at_contact;          /* pressing (above): for a vehicle the ground effect floats */
    fc_real ramp_s;                 /* TIME: thrust ramp-down after touchdown, (0, 10] */
    fc_real confidence_start;       /* UNIT: confidence to start a descent, (0, 1] */
    fc_real confidence_abort;       /* UNIT: a descent aborts below this, [0, confidence_start] */
    fc_real horizontal_start_m;     /* LENGTH: largest horizontal error to start a descent, (0, 100] */
    fc_real horizontal_abort_m;     /* LENGTH: ... to go on with it, >= horizontal_start_m */
    fc_real tilt_cos_abort;         /* RATIO: a descent aborts while k_h is below this, [0, 1] */
    fc_real pad_accel_max_mps2;     /* ACCEL: the pad's acceleration bound to start or go on, (0, 100] */
    fc_real range_timeout_s;        /* TIME: (0, 10] */
    uint8_t abort_retries_max;      /* descents after the first that an abort may lead to */
    bool descent_shaping;           /* the descent's rate from (2.25)-(2.28) (above); false: (3.6) */
    fc_descent_shaping_params shaping; /* checked at init only with descent_shaping */
    fc_real shaping_commit_m;       /* LENGTH: the reference's gear above the surface where the shaped
                                     * descent commits to (3.6), [0, 1] (with descent_shaping) */
    fc_real shaping_filter_s;       /* TIME: the field's first-order filter, [dt, 10] (with descent_shaping) */
} fc_landing_params;

typedef struct fc_landing_input {
    fc_landing_request request;
    fc_real z_m;                    /* LENGTH: the vehicle's CG, world z */
    fc_real horizontal_error_m;     /* LENGTH: |p_xy - pad centre|, >= 0 */
    fc_real tilt_cos;               /* RATIO: k_h */
    fc_real gear_height_m;          /* LENGTH: gear above the pad from the range finder (range k_h - gear) */
    bool range_fresh;               /* gear_height_m is a new sample */
    fc_real thrust_n;               /* FORCE: the thrust of the previous step (the ramp starts from it) */
    const fc_pad_motion_estimate *pad;
    fc_real offset_x_m, offset_y_m; /* LENGTH: the vehicle minus the pad centre, world (read when shaped) */
    fc_quat pad_attitude;           /* UNIT: the pad's attitude, pad -> world (read when shaped; zero: level) */
} fc_landing_input;

typedef struct fc_landing_output {
    fc_landing_state state;
    fc_landing_reason reason;       /* of the newest transition */
    bool changed;                   /* a transition at this step */
    bool fly_reference;             /* the altitude law tracks `reference` */
    fc_vertical_trajectory reference;
    bool motors_on;
    fc_real ramp_thrust_n;          /* FORCE: the thrust in DISARM (fly_reference false) */
    bool touchdown_window;          /* the plan expects contact from now on */
    uint8_t aborts;                 /* since the mission started */
    fc_landing_reason blocked_by;   /* OBSERVE: what keeps the descent from starting (NONE: nothing) */
    fc_real shaping_mps;            /* VEL: shaped DESCEND / TOUCHDOWN: v_zd of (2.25); 0 otherwise */
} fc_landing_output;

typedef struct fc_landing {
    fc_landing_params p;
    fc_altitude_reference hold_reference;     /* (3.6), tau = hold_tau, bias = gear + hold */
    fc_altitude_reference descent_reference;  /* (3.6), tau = descent_tau, bias = gear - dip */
    fc_landing_state state;
    fc_landing_reason reason;
    fc_real state_time_s;           /* TIME: in this state (saturates) */
    fc_real settled_s;              /* TIME */
    fc_real since_range_s;          /* TIME: since the newest range sample */
    fc_real touchdown_thrust_n;     /* FORCE */
    fc_real window_offset_m;        /* LENGTH: dip + window: the offset where the window opens */
    fc_real hold_level_m;           /* LENGTH: the pad level the hold point stands on */
    fc_real stuck_error_m;          /* LENGTH: dip / 2: z - z_r beyond it, the vehicle is held by the pad */
    fc_real gear_height_m;          /* LENGTH: the newest range sample in this descent (100 m: none yet) */
    bool pressing;                  /* the gear met the surface in the window: the reference at its end (dip below) */
    fc_real inv_ramp_per_s;         /* GAIN: 1 / ramp_s */
    fc_descent_shaping shaping;     /* (2.25)-(2.28), with p.descent_shaping */
    fc_real shaped_offset_m;        /* LENGTH: shaped: the offset above the surface's end point */
    fc_real shaped_offset_max_m;    /* LENGTH: shaped: the offset the descent started from */
    fc_real shaped_commit_offset_m; /* LENGTH: dip + shaping_commit_m */
    fc_real shaped_rate_mps;        /* VEL: the filtered field v_f */
    fc_real shaping_gain;           /* UNIT: dt / shaping_filter_s */
    bool shaping_committed;         /* the rest of this descent is (3.6)'s */
    fc_real step_s;                 /* TIME: dt */
    uint8_t aborts;
    bool ready;
    fc_arith ar;
} fc_landing;

fc_init_result fc_landing_init(fc_landing *lm, const fc_landing_params *p);

/* Back to IDLE (disarm, another command). */
void fc_landing_reset(fc_landing *lm);

/* Enters FAILSAFE (fc_controller: inputs lost) or leaves it for HOLD; reason logged. */
void fc_landing_force(fc_landing *lm, fc_landing_state state, fc_landing_reason reason);

/* ABORT now, climbing back to the hold point from in's height (fc_controller:
 * LANDED while the range finder puts the gear in the air). */
void fc_landing_abort(fc_landing *lm, const fc_landing_input *in, fc_landing_reason reason);

fc_step_status fc_landing_step(fc_landing *lm, const fc_landing_input *in, fc_landing_output *out);

/* Whether the next fc_landing_step reads in->horizontal_error_m: only in
 * OBSERVE (what keeps the descent from starting) and in DESCEND and
 * TOUCHDOWN (the aborts); in the other states it may be left unformed. */
bool fc_landing_reads_horizontal_error(const fc_landing *lm);

#endif /* FC_LANDING_H */
