/*
 * fc/descent_shaping.h - the vertical-velocity field of the landing descent,
 * dissertation 2.6.7, (2.25)-(2.28):
 *
 *     v_zd = v_rational + v_conical + v_aversive                         (2.25)
 *     v_rational = -k_r / (|d_h| + delta_h)                               (2.26)
 *     v_conical  =  k_c |d_h| - u_zbias                                   (2.27)
 *     v_aversive =  k_a |(d_h)_pad| / (|z| + delta_a)                     (2.28)
 *
 * d is the position of the vehicle relative to the pad centre (world ENU).
 * |d_h| is its horizontal length in a horizontal (heading, FLU-levelled)
 * frame: a yaw rotation keeps the horizontal length, so it is the length of
 * (d_x, d_y) of the world vector, unaffected by the vehicle's roll and pitch.
 * (d_h)_pad is d expressed in the pad frame (pad attitude q_pad, body ->
 * world, an input) and its in-pad-plane part (x, y of the pad frame): a
 * rolling or pitching pad makes it differ from |d_h| and the aversive term
 * climbs. |z| is the height above the pad, |d_z|.
 *
 * Sign (ENU, z up): v > 0 climbs. Centred, the rational and conical terms
 * descend (-k_r/delta_h - u_zbias); far off, k_c |d_h| dominates and the
 * vehicle climbs. The result is clamped to [-max_descent, max_climb].
 *
 * Cost: two divisions per step (the two rational terms have a variable
 * denominator; no reciprocal can be computed at init), accepted here.
 */
#ifndef FC_DESCENT_SHAPING_H
#define FC_DESCENT_SHAPING_H

#include "fc/quat.h"
#include "fc/status.h"

typedef struct fc_descent_shaping_params {
    fc_real k_r_m2ps;          /* GAIN: k_r of (2.26), [0, 100] m^2/s */
    fc_real delta_h_m;         /* LENGTH: delta_h of (2.26), [0.01, 100] m */
    fc_real k_c_per_s;         /* GAIN: k_c of (2.27), [0, 100] 1/s */
    fc_real u_zbias_mps;       /* VEL: u_zbias of (2.27), [-50, 50] m/s */
    fc_real k_a_mps;           /* GAIN: k_a of (2.28), [0, 100] m/s */
    fc_real delta_a_m;         /* LENGTH: delta_a of (2.28), [0.01, 100] m */
    fc_real max_descent_mps;   /* VEL: largest descent rate (> 0, <= 50), v >= -max_descent */
    fc_real max_climb_mps;     /* VEL: largest climb rate (> 0, <= 50), v <= max_climb */
} fc_descent_shaping_params;

typedef struct fc_descent_shaping_input {
    fc_vec3 rel_position_m; /* LENGTH: vehicle minus pad centre, world ENU, |components| <= 1000 */
    fc_quat pad_attitude;   /* UNIT: q_pad, pad frame -> world */
} fc_descent_shaping_input;

typedef struct fc_descent_shaping_output {
    fc_real vz_mps;          /* VEL: v_zd of (2.25), clamped */
    fc_real rational_mps;    /* VEL: (2.26) */
    fc_real conical_mps;     /* VEL: (2.27) */
    fc_real aversive_mps;    /* VEL: (2.28) */
} fc_descent_shaping_output;

typedef struct fc_descent_shaping {
    fc_descent_shaping_params p;
    bool ready;
    fc_arith ar;
} fc_descent_shaping;

fc_init_result fc_descent_shaping_init(fc_descent_shaping *ds, const fc_descent_shaping_params *p);

/* Bad input (non-finite or out-of-range position): the safe output is a hover
 * (v = 0). A zero-length or non-finite pad quaternion: the pad is taken level. */
fc_step_status fc_descent_shaping_step(fc_descent_shaping *ds, const fc_descent_shaping_input *in,
                                       fc_descent_shaping_output *out);

#endif /* FC_DESCENT_SHAPING_H */
