/*
 * fc/altitude_reference.h - the altitude reference of the landing (3.6):
 *
 *     z_r(t) = z_d(t) + z_r_bias + z_r_init e^(-t / tau_zr)
 *
 * built around any pad trajectory z_d(t) given with its first and second
 * derivatives (the SIL gives the true pad motion, the landing mission its
 * prediction), with the derivatives the altitude law needs:
 *
 *     z_r'  = z_d'  - (z_r_init / tau_zr)   e^(-t / tau_zr)
 *     z_r'' = z_d'' + (z_r_init / tau_zr^2) e^(-t / tau_zr)
 *
 * The decay e^(-t/tau) is propagated step by step: each step it loses the
 * share 1 - e^(-dt/tau) of itself, a gain (fc_gain, to 2^-15 of that share).
 */
#ifndef FC_ALTITUDE_REFERENCE_H
#define FC_ALTITUDE_REFERENCE_H

#include "fc/scalar.h"
#include "fc/status.h"

typedef struct fc_altitude_reference_params {
    fc_real dt_s;           /* DT: the fixed step */
    fc_real tau_s;          /* TIME: tau_zr, how fast the approach offset decays, (0, 1000] */
    fc_real offset_init_m;  /* LENGTH: z_r_init, the approach offset at t = 0 */
    fc_real bias_m;         /* LENGTH: z_r_bias, the landing-gear height */
} fc_altitude_reference_params;

/* A vertical trajectory with its derivatives (pad motion in, reference out). */
typedef struct fc_vertical_trajectory {
    fc_real z_m;      /* LENGTH */
    fc_real vz_mps;   /* VEL */
    fc_real az_mps2;  /* ACCEL */
} fc_vertical_trajectory;

typedef struct fc_altitude_reference {
    fc_real decay;              /* UNIT: e^(-t / tau), starts at 1 */
    fc_gain decay_loss_per_step; /* 1 - e^(-dt / tau) */
    fc_real offset_m;           /* LENGTH: z_r_init */
    fc_real bias_m;             /* LENGTH */
    fc_real offset_rate_mps;    /* VEL: z_r_init / tau */
    fc_real offset_accel_mps2;  /* ACCEL: z_r_init / tau^2 */
    fc_real inv_tau_per_s;      /* GAIN: 1 / tau, to restart with another offset */
    bool ready;
    fc_arith ar;
} fc_altitude_reference;

fc_init_result fc_altitude_reference_init(fc_altitude_reference *ref,
                                          const fc_altitude_reference_params *p);

/* Restart the decaying offset from offset_m (e.g. the current height above
 * the pad when a descent begins): t = 0 again. */
void fc_altitude_reference_restart(fc_altitude_reference *ref, fc_real offset_m);

/* The reference at the current step for pad trajectory pad, then advance one step. */
fc_step_status fc_altitude_reference_step(fc_altitude_reference *ref, const fc_vertical_trajectory *pad,
                                          fc_vertical_trajectory *reference);

#endif /* FC_ALTITUDE_REFERENCE_H */
