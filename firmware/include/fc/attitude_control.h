/*
 * fc/attitude_control.h - quaternion attitude control (dissertation 2.6.1, (2.7)-(2.9)).
 *
 * In: the attitude q and the desired attitude q_d (both body -> world, fc/quat.h),
 * the body rate and an optional body-rate feed-forward. Out: the body moment
 * in normalised units (SPEC "Units between modules"): per axis a fraction of
 * the airframe's authority on that axis (the allocation's, fc/allocation.h).
 *
 * Error. (2.9) defines q_e = q (x) q_d*. With this library's convention
 * (v_w = q (x) v_b (x) q*) that product is a rotation in the world frame, and
 * "one must simply represent it in the body frame": conjugated into the body by
 * q it becomes
 *
 *     q* (x) q_e (x) q = q* (x) q (x) q_d* (x) q = q_d* (x) q  =: q_eb,
 *
 * the same scalar part (so the same shortest-path sign) with the vector part
 * rotated from world to body. q_eb is computed directly and taken with w >= 0
 * (the shortest way round); it is the rotation from the desired body frame to
 * the current one, so its axis points the way the moment must NOT go.
 *
 * Tilt first, heading second (Brescianini & D'Andrea 2013, "reduced attitude"):
 * q_eb = [w, x, y, z] is split exactly into a tilt part (a rotation about an
 * axis in the body xy-plane that aligns the body z axis with the desired one)
 * and a heading part (a rotation about z). With N = sqrt(w^2 + z^2),
 * c = w/N = cos(psi_e/2), s = z/N = sin(psi_e/2):
 *
 *     e_tilt = 2 (x c + y s,  y c - x s,  0)    |e_tilt| = 2 sin(tilt_e/2)
 *     e_head = 2 (0, 0, s)                      |e_head| = 2 sin(psi_e/2)
 *
 * The tilt part does not depend on how large the heading error is. The action
 * is on 2 x (vector part), not on the rotation vector: identical to first order
 * (2 sin(a/2) = a (1 - a^2/24): 4.5 % short at 60 deg), no trigonometry in the
 * step, and the error saturates by itself at large angles, so a big error asks
 * for a bounded angular acceleration. The split costs one 1/N: at small tilt
 * errors (1 - N^2 <= 2^-7 in fixed, tilt_e up to 10 deg; 2^-12 in float) the
 * series 1/N = 1 + (1 - N^2)/2, whose remainder stays below 0.4 of the
 * format's resolution, else fc_unit2_16 (division-free in fixed); the only
 * division in the step is the budget's ratio, and only when the roll/pitch
 * moment is clamped. N^2 < 1e-4 (tilt error within 1.2 deg of upside down)
 * leaves the heading undefined: the heading part is then zero and the tilt
 * part is 2 (x, y, 0).
 *
 * Law, per body axis (angular acceleration, then moment through the inertia):
 *
 *     e     = e_tilt + yaw_weight e_head                        (ANGLE)
 *     alpha = -(kp e + ki I + kd (w - w_ff))                    (rad/s^2, GAIN)
 *     m     = (J alpha + w x J w) / authority                   (normalised)
 *     I    <- clamp(I + e dt, +-integral_limit)                 (rad s, ANGLE)
 *
 * I is the exact integral of the error held over the step (the error is
 * sampled once per step, as the products read it); the moment of step k uses
 * I[k], the update gives I[k+1].
 * w x J w is ((Jz - Jy) wy wz, (Jx - Jz) wz wx, (Jy - Jx) wx wy) for the diagonal
 * J. Init divides J and the differences by the authority, per axis: J /
 * authority (s^2/rad, the inverse of the angular acceleration the axis can
 * reach) is within a factor of ten from a 27 g quad to a 4 kg hexa, so the
 * step needs no physical moment. yaw_weight in [0, 1] scales the heading
 * error (PX4's yaw weight): 1 corrects heading with kp.z, 0 leaves the heading
 * alone (yaw rate is still damped towards rate_ff.z: a yaw-rate mode).
 *
 * Budget: roll and pitch first. If (mx, my) leaves the box moment_limit.xy it
 * is scaled down as one vector (its direction, the tilt axis, is kept); Mz is
 * clamped to its own limit on its own. Yaw never takes room from roll/pitch
 * and roll/pitch are never reduced to make room for yaw. Where rotors share
 * one budget, the allocation decides what gives way and reports FC_SAT_* bits.
 *
 * Anti-windup: I is clamped to +-integral_limit, and an axis does not integrate
 * in a direction its moment cannot go: the allocation reported FC_SAT_<AXIS>_POS
 * (or _NEG) last time, or this step's own moment was clamped in that direction.
 * ki = 0 leaves that axis' integral at zero. fc_attitude_control_hold_integral
 * holds all three where they are (on the ground, where the feet and not the
 * moments set the attitude); the moment still uses them.
 *
 * Bad input (a quaternion of zero length or not finite, a rate not finite or
 * beyond +-100 rad/s): the step holds the last good moment and lets it decay
 * to zero with tau = FC_ATTITUDE_CONTROL_HOLD_TAU_S (exact ZOH pole
 * e^(-dt/tau), at init; below half a NORM16 LSB it is zero): one bad sample moves the
 * moment by 1 - e^(-dt/tau) (4 % at 500 Hz), a lasting fault fades out (95 %
 * in 3 tau). The integrals are frozen, the telemetry error is held. A bad
 * rate_ff alone is replaced by zero and the step runs normally. Both are
 * reported with FC_STEP_BAD_INPUT.
 *
 * The step in 16 bits (SPEC "Units between modules"). Init folds the inertia
 * into the gains: per axis Kp = kp J / authority, Ki = ki J / authority,
 * Kd = kd J / authority (normalised moment per rad, per rad s, per rad/s)
 * and dJ = (J_k - J_j) / authority, so that
 *
 *     m = -(Kp e + Ki I + Kd (w - w_ff)) + dJ w_i w_j,
 *
 * every product 16 x 16 -> 32. Init rejects (FC_INIT_BAD_PARAM) a normalised
 * gain above 7.99 (an axis that asks for 8 times its authority per unit of
 * error) and |dJ| above 0.99 s^2.
 *
 * Formats (fixed backend): quaternions UNIT in and UNIT16 for the error
 * (fc/quat.h: fc_quat16, 16-bit products: the error within 4.5 UNIT16 LSB /
 * N, 2.7e-4 rad / N, of the exact one; test_attitude_control); the error
 * ANGLE (telemetry) and, as the products read it, ANGLE16 (Q3.12, +-8 rad,
 * 2.4e-4 rad; the weighted heading part is 2 (yaw_weight s), a 32 x 16-bit
 * product, within one ANGLE LSB of the unweighted one times yaw_weight); the
 * integral ANGLE (rad s), read as ANGLE16 and advanced by the ANGLE16 error
 * times dt, a 32 x 16-bit product (exact but for its rounding to ANGLE);
 * rates RATE, read as RATE16 (Q5.10, 9.8e-4 rad/s, clamped to +-31.999
 * rad/s: beyond that every gain of a flyable airframe has saturated the
 * moment already); w_i w_j WW16 (Q10.5, 0.031 rad^2/s^2); the gains NGAIN16 (Q3.12: a gain of
 * 0.03 within 0.4 %); dJ NINERTIA16 (Q0.15); the moment summed in NSUM (Q9.22)
 * and out in NORM16; gains as parameters GAIN, inertia and J / authority
 * INERTIA, the authority MOMENT.
 */
#ifndef FC_ATTITUDE_CONTROL_H
#define FC_ATTITUDE_CONTROL_H

#include "fc/quat.h"
#include "fc/status.h"

/* Time constant of the decay of the held moment on bad input (DT). */
#define FC_ATTITUDE_CONTROL_HOLD_TAU_S 0.05f

/* Bandwidth of fc_attitude_control_default_params: kp = wn^2, kd = 2 zeta wn. */
#define FC_ATTITUDE_CONTROL_DEFAULT_WN_TILT 10.0f /* rad/s, roll and pitch */
#define FC_ATTITUDE_CONTROL_DEFAULT_ZETA_TILT 0.8f
#define FC_ATTITUDE_CONTROL_DEFAULT_WN_YAW 5.0f /* rad/s, heading */
#define FC_ATTITUDE_CONTROL_DEFAULT_ZETA_YAW 0.9f
/* Authority of the defaults: J times this angular acceleration (rad/s^2);
 * a placeholder, set authority_nm from the vehicle's allocation. */
#define FC_ATTITUDE_CONTROL_DEFAULT_ALPHA_MAX 50.0f

/* Ranges checked by init (the upper bounds keep every value inside its fixed
 * format, and the float build away from overflow). */
typedef struct fc_attitude_control_params {
    fc_real dt_s;               /* DT: the fixed step, (0, 1] s */
    fc_vec3 inertia_kgm2;       /* INERTIA: diagonal of J, each in (0, 1.99] */
    fc_vec3 kp_per_s2;          /* GAIN: rad/s^2 of angular acceleration per rad of error, [0, 30000] */
    fc_vec3 kd_per_s;           /* GAIN: rad/s^2 per rad/s of rate error, [0, 30000] */
    fc_vec3 ki_per_s3;          /* GAIN: rad/s^2 per rad s of integral, [0, 30000]; 0 disables an axis */
    fc_vec3 integral_limit_rad; /* ANGLE: bound of each integral state (rad s), (0, 4] */
    fc_real yaw_weight;         /* RATIO: weight of the heading error, [0, 1] */
    fc_vec3 authority_nm;       /* MOMENT: the moment a normalised 1 stands for, per axis
                                 * (fc_allocation_authority_of), (0, 100] */
    fc_vec3 moment_limit;       /* RATIO: per-axis budget +-limit, normalised, (0, 1.99] */
} fc_attitude_control_params;

/* The step's input, by reference: the caller holds the quaternions and
 * rates (the controller, its estimator's and its setpoint's own), the step
 * reads them in place instead of copying them. The pointers must be valid
 * (non-NULL, each to one object) for the call only: the step reads them
 * during the call and keeps none of them. Out of range (bad input, header
 * comment): a quaternion of zero length or not finite, a rate not finite or
 * beyond +-100 rad/s. */
typedef struct fc_attitude_control_input {
    const fc_quat *attitude;         /* UNIT: q, body -> world, of any nonzero length
                                      * (normalised by the step) */
    const fc_quat *attitude_desired; /* UNIT: q_d, body -> world, as attitude */
    const fc_vec3 *rate_radps;       /* RATE: body rate w, within +-100 rad/s */
    const fc_vec3 *rate_ff_radps;    /* RATE: body-rate feed-forward w_ff, within +-100 rad/s;
                                      * zero if unused (out of range: taken as zero) */
    uint8_t allocation_saturation;   /* FC_SAT_* bits of the last allocation (anti-windup) */
} fc_attitude_control_input;

typedef struct fc_attitude_control_output {
    fc_vec3_16 moment;          /* NORM16: body moment / authority, inside +-moment_limit */
    fc_vec3 attitude_error_rad; /* ANGLE: (e_tilt.x, e_tilt.y, e_head.z), unweighted, for
                                 * telemetry; desired -> current, body frame */
} fc_attitude_control_output;

typedef struct fc_attitude_control {
    fc_attitude_control_params p;
    fc_vec3 inertia_norm;      /* INERTIA: J / authority per axis (s^2) */
    fc_vec3 inertia_diff_norm; /* INERTIA: (Jz - Jy, Jx - Jz, Jy - Jx) / authority, for w x J w */
    fc_vec3_16 gain_p;         /* NGAIN16: kp J / authority, normalised moment per rad */
    fc_vec3_16 gain_i;         /* NGAIN16: ki J / authority, per rad s */
    fc_vec3_16 gain_d;         /* NGAIN16: kd J / authority, per rad/s */
    fc_vec3_16 inertia_diff16; /* NINERTIA16: inertia_diff_norm as the step reads it */
    fc_vec3 moment_limit_sum;  /* NSUM: moment_limit in the step's sum format */
    fc_real hold_decay;        /* UNIT: e^(-dt / HOLD_TAU), per step on bad input */
    fc_vec3 integral_rad_s;    /* ANGLE: I, the integral of e (rad s) */
    fc_vec3 last_moment;       /* NSUM: the last output, normalised (held on bad input) */
    fc_vec3 last_error_rad;    /* ANGLE: the last good error (held on bad input) */
    uint8_t integral_hold;     /* 1: the integrals do not integrate (hold_integral) */
    uint8_t ready;             /* 1 after a successful init */
    fc_arith ar;
} fc_attitude_control;

/* Validates p (finite; dt, inertia, authority, integral and moment limits > 0;
 * gains >= 0; yaw_weight in [0, 1]; J / authority <= 1.99) and clears the state. On FC_INIT_BAD_PARAM the
 * controller is not ready: _step gives zero moment and FC_STEP_NOT_READY. */
fc_init_result fc_attitude_control_init(fc_attitude_control *c, const fc_attitude_control_params *p);

/* One step of dt_s. out->moment is always finite and inside +-moment_limit. */
fc_step_status fc_attitude_control_step(fc_attitude_control *c, const fc_attitude_control_input *in,
                                        fc_attitude_control_output *out);

/* Clears the integrals (e.g. on the ground, before take-off). */
void fc_attitude_control_reset(fc_attitude_control *c);

/* hold = true: the steps from now on keep the integrals where they are (and
 * still apply them); false: they integrate again. Cleared by init. */
void fc_attitude_control_hold_integral(fc_attitude_control *c, bool hold);

/* Gains from the stated bandwidth (the DEFAULT_* above): kp = wn^2, kd = 2 zeta wn
 * per axis, no integral (ki = 0, integral_limit 0.2 rad s), yaw_weight 1,
 * authority = J * DEFAULT_ALPHA_MAX (replace it with the allocation's),
 * moment_limit 1 (the whole authority) per axis. */
void fc_attitude_control_default_params(fc_attitude_control_params *p, fc_real dt_s, fc_vec3 inertia_kgm2);

#endif /* FC_ATTITUDE_CONTROL_H */
