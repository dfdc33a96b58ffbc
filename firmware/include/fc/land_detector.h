/*
 * fc/land_detector.h - is the vehicle on the ground? Staged as PX4's land
 * detector is, from every piece of evidence the vehicle has (SPEC "Safety
 * contract"): the motors may stop on LANDED and on nothing less.
 *
 *   AIRBORNE --contact_s of pushing down without moving--> GROUND_CONTACT
 *   GROUND_CONTACT --maybe_landed_s of that with low thrust--> MAYBE_LANDED
 *   MAYBE_LANDED --landed_s more--> LANDED
 *   any stage --any sign of flight--> AIRBORNE (LANDED is kept until reset)
 *
 * Evidence (each step):
 *   still        |a_z| < still_accel_mps2, and either |vz| < still_speed_mps
 *                or held: pushing down (below) while |a_z| < still_accel / 2.
 *                Held needs no speed: with no speed input and no range finder
 *                the dead-reckoned speed drifts on the ground (an impact
 *                integrates to an offset), while the thrust short of hover
 *                by 1 - contact_thrust_ratio would accelerate a vehicle in
 *                the air down by about still_accel (0.1 g): only the ground
 *                stops it. A hover thrust learnt too high can make a vehicle
 *                in the air look held; the thrust then ramps down and it
 *                accelerates, which ends the contact long before LANDED.
 *   pushing down the caller is asking to descend and the vertical thrust
 *                T k_h is under contact_thrust_ratio x the hover thrust: in
 *                the air such a thrust accelerates the vehicle down within a
 *                fraction of contact_s, so it cannot stay still
 *   low thrust   T k_h under landed_thrust_ratio x the hover thrust (the
 *                caller ramps the thrust down once in contact)
 *   range        a range sample no older than range_fresh_s that puts the
 *                gear more than airborne_gear_height_m above the surface
 *                means airborne, whatever the rest says
 * GROUND_CONTACT needs still and pushing down; MAYBE_LANDED and LANDED need
 * low thrust as well. A vehicle with no range finder is judged on the rest.
 */
#ifndef FC_LAND_DETECTOR_H
#define FC_LAND_DETECTOR_H

#include <stdbool.h>

#include "fc/scalar.h"
#include "fc/status.h"

typedef enum fc_land_state {
    FC_LAND_AIRBORNE = 0,
    FC_LAND_GROUND_CONTACT,
    FC_LAND_MAYBE_LANDED,
    FC_LAND_LANDED,
    FC_LAND_STATE_COUNT
} fc_land_state;

typedef struct fc_land_detector_params {
    fc_real dt_s;                   /* DT: the fixed step */
    fc_real still_speed_mps;        /* VEL: (0, 2] */
    fc_real still_accel_mps2;       /* ACCEL: (0, 5] */
    fc_real contact_thrust_ratio;   /* RATIO: (0, 1] */
    fc_real landed_thrust_ratio;    /* RATIO: (0, contact_thrust_ratio] */
    fc_real contact_s;              /* TIME: [0, 10] */
    fc_real maybe_landed_s;         /* TIME: [0, 10] */
    fc_real landed_s;               /* TIME: [0, 10] */
    fc_real airborne_gear_height_m; /* LENGTH: (0, 1] */
    fc_real range_fresh_s;          /* TIME: (0, 10] */
} fc_land_detector_params;

typedef struct fc_land_detector_input {
    fc_real vz_mps;                 /* VEL: vertical speed estimate */
    fc_real accel_z_mps2;           /* ACCEL: vertical acceleration estimate */
    fc_real vertical_thrust_n;      /* FORCE: T k_h commanded */
    fc_real hover_thrust_n;         /* FORCE: the learnt hover thrust */
    bool descending;                /* the caller is asking to go down */
    fc_real gear_height_m;          /* LENGTH: the newest range sample as gear height */
    fc_real gear_height_age_s;      /* TIME: its age */
    bool gear_height_known;         /* a range sample has been seen */
} fc_land_detector_input;

typedef struct fc_land_detector {
    fc_land_detector_params p;
    fc_land_state state;
    fc_real contact_timer_s;        /* TIME: still and pushing down this long */
    fc_real low_thrust_timer_s;     /* TIME: ... with low thrust this long */
    fc_real step_s;                 /* TIME: dt */
    fc_real held_accel_mps2;        /* ACCEL: still_accel / 2 */
    bool ready;
    fc_arith ar;
} fc_land_detector;

/* 0.1 m/s and 1 m/s^2 still, contact under 0.9 and landed under 0.3 of the
 * hover thrust, 0.35 s of contact, 0.3 s of maybe landed and 0.3 s more to
 * landed (PX4's hysteresis times), airborne when a range sample younger than
 * 0.3 s puts the gear 5 cm up. */
void fc_land_detector_default_params(fc_land_detector_params *p, fc_real dt_s);

fc_init_result fc_land_detector_init(fc_land_detector *d, const fc_land_detector_params *p);

/* Back to AIRBORNE, the timers cleared (a new flight, or the failsafe's start). */
void fc_land_detector_reset(fc_land_detector *d);

/* The range rule alone: a fresh sample puts the gear above airborne_gear_height_m. */
bool fc_land_detector_range_says_airborne(const fc_land_detector *d, const fc_land_detector_input *in);

/* One step: the stage reached (also in d->state). */
fc_land_state fc_land_detector_step(fc_land_detector *d, const fc_land_detector_input *in);

#endif /* FC_LAND_DETECTOR_H */
