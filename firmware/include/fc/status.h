/*
 * fc/status.h - what an _init and a _step report.
 *
 * Every _init validates its parameters and returns an fc_init_result; a module
 * whose init failed stays in a defined safe state and its _step reports
 * FC_STEP_NOT_READY. Every _step returns a set of fc_step_status bits: the
 * outputs are always finite and inside their limits, the bits say what the
 * step had to do to keep them so.
 */
#ifndef FC_STATUS_H
#define FC_STATUS_H

#include <stdint.h>

typedef enum fc_init_result {
    FC_INIT_OK = 0,
    FC_INIT_BAD_PARAM,      /* a parameter is non-finite, out of range or inconsistent */
    FC_INIT_RANK_DEFICIENT, /* a geometry cannot produce the demanded axes */
    /* fc_controller_init's checks across modules (SPEC "Safety contract") */
    FC_INIT_GRAVITY_MISMATCH,   /* the modules do not share one g */
    FC_INIT_MASS_MISMATCH,      /* the modules do not share one nominal mass */
    FC_INIT_THRUST_TOO_LOW,     /* maximum thrust under 1.5 x the nominal weight */
    FC_INIT_THRUST_ABOVE_ROTORS, /* maximum thrust above what the rotors give */
    FC_INIT_AUTHORITY_MISMATCH   /* a module's normalised units are not the allocation's */
} fc_init_result;

typedef uint16_t fc_step_status;

#define FC_STEP_OK 0u
#define FC_STEP_NOT_READY (1u << 0)        /* init failed or was not run: safe output only */
#define FC_STEP_BAD_INPUT (1u << 1)        /* an input was NaN, infinite or out of range; it was
                                            * replaced by the last good value or ignored */
#define FC_STEP_OUTPUT_LIMITED (1u << 2)   /* an output was clamped to its limits */
#define FC_STEP_ARITH_SATURATED (1u << 3)  /* fixed-point arithmetic saturated somewhere */
#define FC_STEP_DEGRADED (1u << 4)         /* running on a fallback (e.g. no accelerometer trust) */
#define FC_STEP_REFUSED (1u << 5)          /* a command was refused (arming checks, an unknown
                                            * command): the mode was kept */

/* The physical range of inputs the library accepts, the same in both backends
 * (the fixed formats hold them: LENGTH +-2048 m, VEL and ACCEL +-512): a finite
 * value beyond it is bad input, like a NaN, so no intermediate overflows. */
#define FC_INPUT_MAX_LENGTH_M 2000.0f
#define FC_INPUT_MAX_SPEED_MPS 500.0f
#define FC_INPUT_MAX_ACCEL_MPS2 500.0f

/* Which demanded axes the control allocation could not deliver, and in which
 * direction (bits of a uint8_t). Fed back to the integrators of the attitude
 * and altitude loops so they stop winding up in the saturated direction. */
#define FC_SAT_ROLL_POS (1u << 0)
#define FC_SAT_ROLL_NEG (1u << 1)
#define FC_SAT_PITCH_POS (1u << 2)
#define FC_SAT_PITCH_NEG (1u << 3)
#define FC_SAT_YAW_POS (1u << 4)
#define FC_SAT_YAW_NEG (1u << 5)
#define FC_SAT_THRUST_HIGH (1u << 6)
#define FC_SAT_THRUST_LOW (1u << 7)

#endif /* FC_STATUS_H */
