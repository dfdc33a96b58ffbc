/*
 * fc/allocation.h - control allocation for any rotor geometry (dissertation 2.4,
 * (2.2)-(2.6)).
 *
 * Model. Rotor i (body frame FLU) has a unit thrust axis d_i, a position l_i, a
 * normalised speed u_i = w_i / w_max,i in [u_min,i, 1] and
 *
 *     T_i = T_max,i u_i^r_i      along d_i            (thrust)
 *     Q_i = Q_max,i u_i^s_i      along d_i            (reaction torque)
 *     T_max = 1/2 C_T w_max^r,   Q_max = 1/2 C_Q w_max^s.
 *
 * The normalisation by w_max is what keeps every quantity inside the fixed
 * formats: speeds are UNIT in [0, 1], thrusts FORCE and moments MOMENT, with
 * no C_T w^r of 1e7 and no C_T of 1e-8 anywhere. Q_max is signed: Q_max > 0
 * when the rotor's reaction torque on the body points along +d_i (for d_i up:
 * a propeller turning clockwise seen from above), Q_max < 0 for the other
 * spin. The wrench (2.2)-(2.3) is
 *
 *     F = sum T_i d_i,     M = sum (l_i x d_i) T_i + Q_i d_i.
 *
 * Controlled axes. The allocation controls four: w = [F_z, M_x, M_y, M_z], F_z
 * the force along body z. The effectiveness matrix A (4 x n) has the columns
 *
 *     A_i = [T_max,i d_i.z ; T_max,i (l_i x d_i) + Q_max,i d_i]           (2.5)
 *
 * (the wrench of rotor i at full speed), so that with r_i = s_i the map is the
 * linear w = A v in v_i = u_i^r_i. Body-x/y forces are a by-product: zero for
 * planar rotors (all d_i = z), and for tilted rotors whatever the allocated
 * speeds give (fc_allocation_forward_wrench reports them). A geometry whose A
 * has rank < 4 is rejected at init (FC_INIT_RANK_DEFICIENT).
 *
 * Normalised units (SPEC "Units between modules", PX4's control_allocator):
 * the demand arrives as fractions of what the airframe can give. The
 * authorities come from A at init: the maximum thrust F_max = sum_i A_0i
 * (every rotor at full speed), and per moment axis half the row's absolute
 * sum, sum_i |A_ki| / 2 (for a symmetric layout the moment with the rotors
 * that push that way at full speed and the others stopped). With
 * N = diag(1 / authority) the allocation works on the normalised
 * effectiveness B = N A, whose thrust row sums to 1 and whose moment rows
 * sum to 2 in absolute value; the demand x = N w is what the attitude and
 * altitude laws output (NORM16, within [-2, 2)), so the step scales nothing.
 *
 * Inverse, r = s. At init: B is formed from D A, D = diag(2^e_k) powers of two
 * chosen so the largest entry of each row of D A lies in (0.5, 1] (exact, and
 * the formats then hold A of a 30 g Crazyflie and of a 4 kg hexacopter
 * alike), each row then scaled by 1 / its absolute sum (one rounding in MAT);
 * P = pinv(B) (n x 4, MAT). fc_mat_pinv's result is refined by two
 * Newton-Schulz steps P <- P (2 I - B P), which take its cond^2-sized error
 * (it solves the normal equations) down to the rounding of the products;
 * the step holds P in 16 bits (PINV16, Formats).
 * Step: v = P x, u_i = v_i^(1/r_i) (fc_sqrt_unit16 for r = 2, fc_pow_unit
 * otherwise).
 * For n > 4 this is the least-norm v; the null space of A is not used, not
 * even to desaturate.
 *
 * Inverse, r != s (2.4)/(2.6). The true wrench is W(v) = A v + delta(v) with
 * delta(v) = sum Q_max,i d_i (v_i^(s_i/r_i) - v_i) (moment rows only; N delta
 * in the normalised units the step works in): the
 * reaction torque that the linear model puts at u^r but that grows as u^s. The
 * allocation iterates on the r = s solution with that correction (a chord /
 * quasi-Newton method with the constant Jacobian A):
 *
 *     v_0 = alloc(w - delta_warm),   v_k+1 = alloc(w - delta(v_k)),
 *
 * newton_iterations passes per step, alloc the desaturating linear allocation
 * below. delta_warm is delta of the previous step's solution (zero after init
 * and after fc_allocation_reset): with slowly varying demands the first pass
 * is already one step of the iteration. Each pass contracts the error by about
 * max |1 - (s/r) v^(s/r - 1)| over [v_min, 1] (0.15 to 0.2 for s/r = 1.15).
 * Measured (unit.allocation, 1000 feasible random demands per preset, cold
 * start: the warm start cleared before every step), the worst yaw residual
 * |M_z - M_z,d| over the preset's yaw authority sum |Q_max,i|:
 *
 *     r = 2, s = 2.3     crazyflie2   f450      hexa_x_4kg
 *       0 passes         1.3e-2       1.2e-2    3.7e-3
 *       1 pass           9.4e-4       7.9e-4    1.8e-4
 *       2 passes         7.1e-5       6.0e-5    8.4e-6
 *       3 passes         6.4e-6       5.3e-6    4.6e-7
 *     r = 2.2, s = 1.8: 1.7e-2, 1.6e-3, 1.6e-4, 1.7e-5 (worst preset)
 *
 * (float; fixed the same down to the rounding of the 16-bit demand). About
 * 13x per pass. F_z, M_x and M_y carry only the
 * rounding of r = s for planar rotors (delta is along z). Warm-started on a
 * slowly varying demand (1 Hz at 500 Hz), one pass per step gives 6.4e-6.
 * Cost per pass: n fc_pow_unit and one alloc, plus n fc_pow_unit for the warm
 * start of the next step.
 *
 * Saturation, in this priority (what gives way first comes first), like PX4's
 * sequential desaturation: the demand is split into collective thrust t (the
 * pinv column of F_z, p_T), roll/pitch R and yaw Y, v = t p_T + a R + b Y, with
 * a, b in [0, 1]; every rotor must stay in [u_min, 1], i.e. v_i in [v_min,i, 1].
 *   1. yaw gives way first: if some b in [0, 1] fits with t and R as demanded,
 *      b is the largest such (|M_z| reduced toward 0, nothing else touched);
 *   2. otherwise the collective thrust shifts, up or down, to make room: t is
 *      the demand clamped to the interval where a R fits with no yaw;
 *   3. roll and pitch are reduced last, together (a, the largest in [0, 1] for
 *      which some t fits with no yaw, scales both, so the direction of
 *      (M_x, M_y) is kept); then b is the largest that fits t p_T + a R.
 * Roll/pitch outrank thrust outranks yaw, so at full or zero thrust yaw gets
 * only the room the thrust leaves. Steps 2-3 assume no yaw: where some yaw
 * would have widened the room for thrust or roll/pitch, that room is not used
 * (never for a quad-X, whose diagonal rotors share a spin direction). a is
 * found in closed form from the rotor pairs (when the interval of t at a = 1
 * is empty: n (n - 1) comparisons, the pairs that bind compared by cross
 * products, one division), b from the rotors (one division), both only when
 * needed, each rounded down to the largest 16-bit value that fits. Rotors
 * whose share of the collective |p_T,i| is below 1/32 (none in a vehicle
 * whose rotors all point up) do not take part in steps 2-3; their command
 * is clamped.
 * Reported in out->saturation, per axis not delivered, in the direction it fell
 * short (a positive demand not met sets _POS): a < 1 sets the roll and pitch
 * bits of the non-zero demands, b < 1 the yaw bit, a thrust shift down
 * FC_SAT_THRUST_HIGH and up FC_SAT_THRUST_LOW; a demand beyond what all rotors
 * together can give in that axis (clamped first) sets its bit too. Any bit also
 * sets FC_STEP_OUTPUT_LIMITED.
 *
 * Bad input (a non-finite demand component): the whole demand is replaced by the
 * last good demand (zero thrust and moment after init: all rotors at u_min) and
 * the step reports FC_STEP_BAD_INPUT. Not ready (init failed or not run): every
 * speed and thrust is 0 (motors stopped) and FC_STEP_NOT_READY. Outputs are
 * always finite; speed[i] is in [u_min,i, 1] for i < rotor_count, 0 above.
 *
 * Formats (fixed backend): the demand NORM16; axes and speeds UNIT; positions
 * LENGTH; l x d LEVER; thrusts and F_max FORCE; moments, Q_max and the moment
 * authorities MOMENT; exponents RATIO; D A, B and P in MAT at init, the row
 * scales 2^e in GAIN (e in [-16, 14], exact). The linear step and its
 * desaturation multiply 16 x 16 bits into 32 (fc_mul16; only the r != s
 * correction and the midpoint of an empty interval of t, a rounding case,
 * keep 32-bit products), in their own formats:
 *   P           PINV16, Q3.12: [-8, 8), resolution 2.4e-4, rounded to nearest
 *   x           NORM16 as given; the collective t, when it shifts, RATIO and
 *               multiplied as a NORM16 value and its remainder (exact)
 *   P_ik x_k    PX, Q5.26 in 32 bits, [-32, 32): the parts t P_i0, R_i, Y_i and
 *               v_i are exact sums of the products, and v_i (in [v_min, 1])
 *               goes to the root as it is (UNIT, exactly), not rounded to 16
 *               bits: a 16-bit v (Q14 to hold 1) would add up to 2^-15, 1.4
 *               16-bit steps of the speed at hover and 6.6 at u_min 0.15
 *   R_i, Y_i    ROTOR16, Q1.14, [-2, 2), 6.1e-5: copies where the desaturation
 *               scales or compares them, with a rotor's slacks 1 - v_i and
 *               v_i - v_min
 *   s_i         NORM16 (collective units); the roll/pitch pairs' s_j - s_i and
 *               high_j - low_i PAIR16, Q2.13, [-4, 4), 1.2e-4; q_i = 1 / P_i0
 *               in the finest of Q16, Q14, Q12 and Q10 that holds it
 *   a, b        UNIT16, rounded down (what they scale stays inside its bound)
 * Whether a bound binds is decided on the exact 32-bit values, the 16-bit
 * copies formed only for those that do. Error: with nothing saturated, v_i
 * is within sum_k |x_k| 2^-13 (P's rounding; 0 for entries PINV16 holds, a
 * quad-X's 1 and 1/2) of pinv(B) x, so the wrench is within sum_k |x_k|
 * 2^-13 of each axis' sum_i |B_ki| (F_max, twice a moment authority): at
 * hover (x_0 = 1/2, small moments) within 2^-14 of it. When an axis gives
 * way, the rotor that limits its scale stays within 2^-14 (|c| + 1) of its
 * bound (|c| the scaled part, |Y_i| or |s_j - s_i|; 2^-14 (|c| + 3) for a
 * pair), and each axis kept is within a further 2^-15 of its sum_i |B_ki|
 * (the 16-bit copy of R_i or Y_i). The speeds of rotors with r = 2 are v's
 * roots to 16 bits (fc_sqrt_unit16: within 2^-17 of sqrt(v), the
 * resolution of a 16-bit motor command). For a quad-X and a hexa-X the
 * 16-bit values hold every NORM16 demand (|R_i| < 2, |Y_i| <= 1, |s_i| < 2);
 * a geometry whose P takes one of them out of its format at an extreme
 * demand saturates it (FC_STEP_ARITH_SATURATED), the speeds still in
 * [u_min, 1].
 * Range limits checked at init (both backends): |l| components <= 16 m,
 * 0 < T_max <= 250 N, |Q_max| <= 16 N m, each row of A summed in absolute value
 * <= 1500 N (F_z) and <= 100 N m (moments), the largest entry of each row >=
 * 3.1e-5 (else the axis counts as rank deficient) and the intermediates of D A
 * inside their formats: T_max 2^e <= 100 for the F_z row (d_z of the largest
 * entry's rotor not far below the others'), <= 1000 1/m for a moment row with
 * 2^e >= 1 and <= 100 1/m with 2^e < 1 (a rotor's T_max not above ~1000 times
 * its row's largest entry in N m), |Q_max| 2^e <= 100. A P entry above
 * 8 - 2^-12, the largest PINV16 value (a geometry close to rank loss, for the
 * formats), is treated as rank deficient.
 */
#ifndef FC_ALLOCATION_H
#define FC_ALLOCATION_H

#include "fc/mat.h"
#include "fc/status.h"
#include "fc/vec3.h"

#define FC_MAX_ROTORS 8
/* The format of the lever arms l_i x d_i: Q7.24, [-128, 128) m, resolution
 * 6e-8 m (finer than LENGTH, so that T_max (l x d) keeps MAT's resolution). */
#define FC_LEVER_FRAC 24
/* The step's formats (header: Formats). P = pinv(B) in 16 bits: Q3.12,
 * [-8, 8), resolution 2.4e-4 (init rejects a larger entry). */
#define FC_PINV16_FRAC 12
/* A product P_ik x_k (PINV16 x NORM16) and the sums of them, in 32 bits:
 * Q5.26, [-32, 32), exact (the parts t P_i0, R_i, Y_i and v_i, v_min). */
#define FC_PX_FRAC 26
/* The 16-bit copies of R_i and Y_i and a rotor's slacks 1 - v_i, v_i - v_min
 * that the desaturation compares: Q1.14, [-2, 2), resolution 6.1e-5. */
#define FC_ROTOR16_FRAC 14
/* The roll/pitch room's pair constraints a (s_j - s_i) <= high_j - low_i
 * (collective units): Q2.13, [-4, 4), resolution 1.2e-4. */
#define FC_PAIR16_FRAC 13
/* Upper bound of newton_iterations (passes of the r != s correction). */
#define FC_ALLOCATION_MAX_ITERATIONS 4

typedef struct fc_rotor_params {
    fc_vec3 axis_unit;       /* UNIT: thrust axis d_i, |d_i| = 1 within 1e-4 (on |d|^2) */
    fc_vec3 position_m;      /* LENGTH: l_i from the centre of mass, each component <= 16 m */
    fc_real thrust_max_n;    /* FORCE: T_max,i = 1/2 C_T w_max^r, in (0, 250] N */
    fc_real torque_max_nm;   /* MOMENT: Q_max,i = 1/2 C_Q w_max^s, signed (+: torque along +d_i) */
    fc_real thrust_exponent; /* RATIO: r, in (0.5, 4] */
    fc_real torque_exponent; /* RATIO: s, in (0.5, 4] */
    fc_real speed_min;       /* UNIT: u_min,i, in [0, 1) (idle speed / w_max) */
} fc_rotor_params;

typedef struct fc_allocation_params {
    uint8_t rotor_count;               /* n, in [1, FC_MAX_ROTORS] (rank 4 needs n >= 4) */
    fc_rotor_params rotor[FC_MAX_ROTORS];
    uint8_t newton_iterations;         /* passes of the r != s correction, <= MAX_ITERATIONS */
} fc_allocation_params;

/* The normalised wrench (NORM16; header: normalised units). */
typedef struct fc_allocation_demand {
    fc_real16 thrust;  /* F_z / F_max, along body z: 1 is every rotor at full speed */
    fc_vec3_16 moment; /* (M_x, M_y, M_z) / authority, body frame */
} fc_allocation_demand;

typedef struct fc_allocation_output {
    fc_real speed[FC_MAX_ROTORS];          /* UNIT: u_i in [u_min,i, 1]; 0 for i >= n */
    fc_real rotor_thrust_n[FC_MAX_ROTORS]; /* FORCE: T_i = T_max,i u_i^r_i; 0 for i >= n */
    fc_real thrust_n;                      /* FORCE: achieved F_z (forward model) */
    fc_vec3 moment_nm;                     /* MOMENT: achieved M (forward model) */
    uint8_t saturation;                    /* FC_SAT_* bits: axes not delivered */
} fc_allocation_output;

/* What init derives per rotor; what the step reads first (the ATmega
 * reaches a field up to 63 bytes from a pointer without an addition). */
typedef struct fc_allocation_rotor {
    fc_real16 pinv[4];        /* PINV16: row i of P = pinv(B) */
    fc_real v_min;            /* PX: u_min,i^r_i */
    fc_real speed_min;        /* UNIT: u_min,i */
    uint8_t flags;            /* ROTOR_* (allocation.c) */
    uint8_t shift_gain_frac;  /* 16, 14, 12 or 10: the finest Q-format that holds |q_i| */
    fc_real16 shift_gain;     /* Q(shift_gain_frac): q_i = 1 / P_i0 (collective per unit v_i) */
    fc_real shift_low;        /* RATIO: lower bound of t from this rotor (at a = 0) */
    fc_real shift_high;       /* RATIO: upper bound of t from this rotor (at a = 0) */
    fc_real inv_thrust_exponent; /* RATIO: 1/r_i */
    fc_real exponent_ratio;   /* RATIO: s_i / r_i */
    fc_vec3 torque_norm;      /* MAT: N Q_max,i d_i, the reaction torque's column of B */
    fc_vec3 axis_unit;        /* UNIT: d_i */
    fc_vec3 lever_m;          /* LEVER: l_i x d_i */
    fc_real thrust_max_n;     /* FORCE: T_max,i */
    fc_real torque_max_nm;    /* MOMENT: Q_max,i */
    fc_real thrust_exponent;  /* RATIO: r_i */
    fc_real torque_exponent;  /* RATIO: s_i */
} fc_allocation_rotor;

typedef struct fc_allocation {
    /* what the step reads first, before the rotors (the ATmega reaches a
     * field up to 63 bytes from a pointer without an addition) */
    uint8_t rotor_count;
    uint8_t newton_iterations;
    uint8_t nonlinear;           /* 1 when some rotor has r_i != s_i */
    uint8_t ready;               /* 1 after a successful init */
    fc_arith ar;
    fc_real16 demand_limit[4];   /* NORM16: sum_i |B_ki|, the most any axis can get (at most 2 - 2^-14) */
    fc_allocation_demand last_good; /* held on bad input */
    fc_vec3 delta_warm;          /* RATIO: N delta(v) of the last solution (r != s) */
    fc_real thrust_max_n;        /* FORCE: F_max, the thrust a normalised 1 stands for */
    fc_vec3 moment_authority_nm; /* MOMENT: the moment a normalised 1 stands for, per axis */
    fc_allocation_rotor rotor[FC_MAX_ROTORS];
    fc_real inv_thrust_max;      /* PER_FORCE: 1 / F_max (fc_allocation_thrust_fraction) */
    fc_real row_scale[4];        /* GAIN: 2^e_k, the diagonal of D */
    fc_real row_norm[4];         /* RATIO: 1 / the absolute sum of row k of D A */
} fc_allocation;

/* Validates p (see the header comment and fc_rotor_params for the ranges),
 * builds D A and P = pinv(D A). FC_INIT_BAD_PARAM for a parameter out of range,
 * FC_INIT_RANK_DEFICIENT when A has rank < 4 (n < 4, all rotors on a line, a
 * coaxial-only layout, ...). On failure the allocation is not ready. */
fc_init_result fc_allocation_init(fc_allocation *a, const fc_allocation_params *p);

/* Rotor speeds for a normalised demand (see the header comment), and the
 * wrench and rotor thrusts they give by the forward model (2.2)-(2.3). */
fc_step_status fc_allocation_step(fc_allocation *a, const fc_allocation_demand *d,
                                  fc_allocation_output *out);

/* The step's speeds alone, for a caller that needs no forward model (the
 * controller): speed_unit[0..FC_MAX_ROTORS-1] (UNIT) and *saturation_bits (FC_SAT_*
 * bits) as fc_allocation_step gives out->speed and out->saturation, written
 * in place (no output struct to copy them from); the status too. */
fc_step_status fc_allocation_speeds(fc_allocation *a, const fc_allocation_demand *d, fc_real *speed_unit,
                                    uint8_t *saturation_bits);

/* The authorities of the rotors of p, as init computes them (header):
 * F_max (FORCE) and the moment authority per axis (MOMENT). For the modules
 * that output normalised units (fc_controller_default_params). false when p
 * is not a valid geometry (the values are then 0). */
bool fc_allocation_authority_of(const fc_allocation_params *p, fc_real *thrust_max_n, fc_vec3 *moment_nm);

/* A thrust in N as the normalised demand's thrust (one product by 1/F_max):
 * for the thrusts a module sets in N (the failsafe, the landing's ramp). */
fc_real16 fc_allocation_thrust_fraction(const fc_allocation *a, fc_real thrust_n);

/* A demand in physical units as the normalised one (divisions: for the
 * library's edge and the tests, not for the step). */
fc_allocation_demand fc_allocation_normalise(const fc_allocation *a, fc_real thrust_n, fc_vec3 moment_nm);

/* The physical F_z (FORCE) and M (MOMENT) of a normalised demand. */
void fc_allocation_physical(const fc_allocation *a, const fc_allocation_demand *d, fc_real *thrust_n,
                            fc_vec3 *moment_nm);

/* The moment part alone: M (MOMENT) of a normalised moment (NORM16), as
 * fc_allocation_physical gives it. */
void fc_allocation_moment_nm(const fc_allocation *a, const fc_vec3_16 *moment, fc_vec3 *moment_nm);

/* Forgets the warm start of the r != s iteration and the last good demand. */
void fc_allocation_reset(fc_allocation *a);

/* The model (2.2)-(2.3) for the tests and the SIL: speed[0..n-1] (UNIT,
 * clamped to [0, 1]) to F_z (FORCE) and M (MOMENT). Zeros when not ready. */
void fc_allocation_forward(fc_allocation *a, const fc_real *speed, fc_real *thrust_n,
                           fc_vec3 *moment_nm);

/* The same with the whole force vector (FORCE): the body-x/y by-product too. */
void fc_allocation_forward_wrench(fc_allocation *a, const fc_real *speed, fc_vec3 *force_n,
                                  fc_vec3 *moment_nm);

/* A (4 x n) in MAT: entries in N (row 0) and N m (rows 1-3), the values
 * themselves (Q24 in fixed: entries beyond +-128 saturate). FC_MAT_BAD_SIZE
 * and a 0 x 0 matrix when not ready. For the oracle. */
fc_mat_status fc_allocation_effectiveness(const fc_allocation *a, fc_mat *out);

/* B = N A (4 x n, MAT): the normalised effectiveness the allocation inverts. */
fc_mat_status fc_allocation_effectiveness_normalised(const fc_allocation *a, fc_mat *out);

/* P = pinv(B) (n x 4, MAT) as the step multiplies it (its PINV16 values,
 * exact in MAT), so that pinv(A) = P N. */
fc_mat_status fc_allocation_pinv_normalised(const fc_allocation *a, fc_mat *out);

/* Presets from FC_C constants only; rotors numbered front-right, back-right,
 * back-left, front-left for the quads (the Crazyflie's M1..M4), and
 * counter-clockwise from front-right (30 deg right of the nose) for the hexa.
 * r = s = 2, newton_iterations 2. */

/* Crazyflie 2.x, quad-X: arm 0.046 m (motors at +-0.046/sqrt2 on x and y),
 * THRUST_MAX 0.12 N per motor, THRUST_MIN 0.0128 N (u_min = sqrt(0.0128/0.12)),
 * torque/thrust 0.00699 m; M1, M3 react along -z, M2, M4 along +z. */
void fc_allocation_preset_crazyflie2(fc_allocation_params *p);

/* F450, quad-X: 0.225 m arms, 10" props, 8 N max thrust per motor, torque/thrust
 * 0.016 m, u_min 0.15 (ESC idle); the Crazyflie's numbering and spins. */
void fc_allocation_preset_f450(fc_allocation_params *p);

/* Hexa-X for the 4 kg vehicle of the reference scenario: 0.45 m arms, 13.08 N
 * max thrust per rotor (thrust-to-weight 2 at 4 kg, 9.81 m/s^2), torque/thrust
 * 0.016 m, u_min 0.15, alternating spin (rotor 0 reacts along -z). */
void fc_allocation_preset_hexa_x_4kg(fc_allocation_params *p);

#endif /* FC_ALLOCATION_H */
