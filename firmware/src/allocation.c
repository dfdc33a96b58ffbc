/*
 * allocation.c - control allocation for any rotor geometry (fc/allocation.h),
 * dissertation 2.4, (2.2)-(2.6). One source for both backends.
 *
 * Rows of the controlled wrench: 0 = F_z, 1 = M_x, 2 = M_y, 3 = M_z.
 */
#include "fc/allocation.h"

#include <stddef.h>

/* Local Q-formats: a rotor's T_max times a moment row's scale 2^e, in 1/m
 * (about 1 / the longest lever of that row): Q11.20 ([-2048, 2048) 1/m) for
 * e >= 0 and Q7.24 ([-128, 128) 1/m) for e < 0 (scaled_entry). */
#define FC_PER_M_FRAC 20
#define FC_PER_M_FINE_FRAC 24

#define ROTOR_SQRT (1u << 0)          /* r_i = 2: u = sqrt(v), u^r = u u */
#define ROTOR_SQUARE_TORQUE (1u << 1) /* s_i = 2: u^s = u u */
#define ROTOR_NONLINEAR (1u << 2)     /* r_i != s_i: the torque correction applies */
#define ROTOR_SHIFTS (1u << 3)        /* |P_i0| >= 1/32: takes part in the thrust shift */

#define ROWS 4

/* Ranges checked at init (fc/allocation.h). */
#define AXIS_NORM_SQ_TOLERANCE FC_C(1.0e-4f, UNIT)
#define POSITION_MAX FC_C(16.0f, LENGTH)
#define THRUST_MAX_LIMIT FC_C(250.0f, FORCE)
#define TORQUE_MAX_LIMIT FC_C(16.0f, MOMENT)
#define EXPONENT_LOW FC_C(0.5f, RATIO)
#define EXPONENT_HIGH FC_C(4.0f, RATIO)
#define FORCE_ROW_SUM_LIMIT FC_C(1500.0f, FORCE)
#define MOMENT_ROW_SUM_LIMIT FC_C(100.0f, MOMENT)
/* Bounds of the scaled intermediates of D A (kept well inside their formats). */
#define SCALED_THRUST_F_LIMIT FC_C(100.0f, RATIO)   /* T 2^e0, row 0 */
#define SCALED_THRUST_M_LIMIT FC_C(1000.0f, PER_M)            /* T 2^ek, e >= 0 */
#define SCALED_THRUST_M_FINE_LIMIT FC_C(100.0f, PER_M_FINE)  /* T 2^ek, e < 0 */
#define SCALED_TORQUE_LIMIT FC_C(100.0f, MAT)       /* Q 2^ek */
/* The least F_max: 1 / F_max must fit PER_FORCE. */
#define THRUST_TOTAL_MIN FC_C(1.0f / 16.0f, FORCE)
/* Row scales 2^e, e in [-16, 14] (exact in GAIN). */
#define ROW_SCALE_MIN FC_C(1.0f / 65536.0f, GAIN)
#define ROW_SCALE_MAX FC_INT(16384, GAIN)
/* A pinv entry above this is a geometry too close to rank loss for the
 * formats: the largest PINV16 value, 8 - 2^-12 (exact in MAT and float). */
#define PINV_ENTRY_LIMIT FC_C(32767.0f / 4096.0f, MAT)
/* Share of the collective below which a rotor does not take part in the shift. */
#define SHIFT_SHARE_MIN FC_C(1.0f / 32.0f, MAT)

/* ---- helpers ----------------------------------------------------------- */

static fc_real component(fc_vec3 v, int k)
{
    return k == 0 ? v.x : (k == 1 ? v.y : v.z);
}

static bool rotor_is_finite(const fc_rotor_params *r)
{
    return fc_vec3_is_finite(r->axis_unit) && fc_vec3_is_finite(r->position_m) &&
           fc_is_finite(r->thrust_max_n) && fc_is_finite(r->torque_max_nm) &&
           fc_is_finite(r->thrust_exponent) && fc_is_finite(r->torque_exponent) &&
           fc_is_finite(r->speed_min);
}

static bool within(fc_arith *ar, fc_real x, fc_real limit)
{
    return fc_abs(ar, x) <= limit;
}

static bool rotor_params_valid(fc_arith *ar, const fc_rotor_params *r)
{
    if (!rotor_is_finite(r)) {
        return false;
    }
    /* |d|^2 within 1e-4 of 1; a component of 2 or more saturates the dot in
     * fixed (and so fails too) */
    const fc_real norm_sq = fc_vec3_dot(ar, r->axis_unit, r->axis_unit, FC_SHIFT(UNIT, UNIT, UNIT));
    if (!within(ar, fc_sub(ar, norm_sq, FC_INT(1, UNIT)), AXIS_NORM_SQ_TOLERANCE)) {
        return false;
    }
    if (!within(ar, r->position_m.x, POSITION_MAX) || !within(ar, r->position_m.y, POSITION_MAX) ||
        !within(ar, r->position_m.z, POSITION_MAX)) {
        return false;
    }
    if (!(r->thrust_max_n > FC_INT(0, FORCE)) || !(r->thrust_max_n <= THRUST_MAX_LIMIT)) {
        return false;
    }
    if (!within(ar, r->torque_max_nm, TORQUE_MAX_LIMIT)) {
        return false;
    }
    if (!(r->thrust_exponent > EXPONENT_LOW) || !(r->thrust_exponent <= EXPONENT_HIGH) ||
        !(r->torque_exponent > EXPONENT_LOW) || !(r->torque_exponent <= EXPONENT_HIGH)) {
        return false;
    }
    return r->speed_min >= FC_INT(0, UNIT) && r->speed_min < FC_INT(1, UNIT);
}

/* x^e for a UNIT x, with the exact square for e = 2. */
static fc_real power(fc_arith *ar, fc_real x_unit, fc_real exponent_ratio, bool square)
{
    if (square) {
        return fc_mul(ar, x_unit, x_unit, FC_SHIFT(UNIT, UNIT, UNIT));
    }
    return fc_pow_unit(ar, x_unit, exponent_ratio);
}

/* Entry (row, rotor) of A in its own format: FORCE for row 0, MOMENT for the others. */
static fc_real physical_entry(fc_arith *ar, const fc_allocation_rotor *r, int row)
{
    if (row == 0) {
        return fc_mul(ar, r->thrust_max_n, r->axis_unit.z, FC_SHIFT(FORCE, UNIT, FORCE));
    }
    /* (2.5): T_max (l x d) + Q_max d */
    return fc_add(ar,
                  fc_mul(ar, r->thrust_max_n, component(r->lever_m, row - 1),
                         FC_SHIFT(FORCE, LEVER, MOMENT)),
                  fc_mul(ar, r->torque_max_nm, component(r->axis_unit, row - 1),
                         FC_SHIFT(MOMENT, UNIT, MOMENT)));
}

/* The scaled thrust and torque of a rotor for a row, checked against their limits. */
static bool scaled_entry(fc_arith *ar, const fc_allocation_rotor *r, int row, fc_real scale,
                         fc_real *entry)
{
    if (row == 0) {
        /* T 2^e0 (exact in fixed for e0 >= -4), then times d_z */
        const fc_real thrust = fc_mul(ar, r->thrust_max_n, scale, FC_SHIFT(FORCE, GAIN, RATIO));
        *entry = fc_mul(ar, thrust, r->axis_unit.z, FC_SHIFT(RATIO, UNIT, MAT));
        return within(ar, thrust, SCALED_THRUST_F_LIMIT);
    }
    /* scale first, multiply second: one rounding of each product in MAT, not a
     * rounding in MOMENT blown up by 2^e (Crazyflie yaw row: 2^10). T 2^e (1/m)
     * is exact in PER_M (Q20, up to 2048 1/m) for e >= 0; for e < 0 it is
     * below T and PER_M_FINE (Q24) keeps the bits Q20 would round away. */
    const fc_real lever = component(r->lever_m, row - 1);
    fc_real lever_part;
    bool ok;
    if (scale >= FC_INT(1, GAIN)) {
        const fc_real thrust = fc_mul(ar, r->thrust_max_n, scale, FC_SHIFT(FORCE, GAIN, PER_M));
        lever_part = fc_mul(ar, thrust, lever, FC_SHIFT(PER_M, LEVER, MAT));
        ok = within(ar, thrust, SCALED_THRUST_M_LIMIT);
    } else {
        const fc_real thrust = fc_mul(ar, r->thrust_max_n, scale, FC_SHIFT(FORCE, GAIN, PER_M_FINE));
        lever_part = fc_mul(ar, thrust, lever, FC_SHIFT(PER_M_FINE, LEVER, MAT));
        ok = within(ar, thrust, SCALED_THRUST_M_FINE_LIMIT);
    }
    const fc_real torque = fc_mul(ar, r->torque_max_nm, scale, FC_SHIFT(MOMENT, GAIN, MAT));
    *entry = fc_add(ar, lever_part,
                    fc_mul(ar, torque, component(r->axis_unit, row - 1), FC_SHIFT(MAT, UNIT, MAT)));
    /* a rotor whose lever has no component on this row needs no bound on T 2^e */
    return (ok || lever == FC_INT(0, LEVER)) && within(ar, torque, SCALED_TORQUE_LIMIT);
}

/* D A into out; false when a scaled intermediate leaves its bound. */
static bool build_normalised(fc_arith *ar, const fc_allocation *a, fc_mat *out)
{
    bool ok = true;
    (void)fc_mat_zero(out, ROWS, a->rotor_count);
    for (int k = 0; k < ROWS; k++) {
        for (int i = 0; i < a->rotor_count; i++) {
            ok = scaled_entry(ar, &a->rotor[i], k, a->row_scale[k], &out->a[k][i]) && ok;
        }
    }
    return ok;
}

/* The power of two 2^e (GAIN) that puts row_max 2^e in (0.5, 1]; false when e
 * would leave [-16, 14] (a row that is zero or too small to resolve).
 * shift_to_ratio names the product row_max (its format) x GAIN -> RATIO. */
static bool choose_row_scale(fc_arith *ar, fc_real row_max, int shift_to_ratio, fc_real *scale_out)
{
    fc_real scale = FC_INT(1, GAIN);
    for (int step = 0; step < 40; step++) {
        const fc_real scaled = fc_mul(ar, row_max, scale, shift_to_ratio);
        if (scaled > FC_INT(1, RATIO)) {
            if (scale <= ROW_SCALE_MIN) {
                return false;
            }
            scale = fc_mul(ar, scale, FC_C(0.5f, UNIT), FC_SHIFT(GAIN, UNIT, GAIN)); /* exact */
        } else if (scaled <= FC_C(0.5f, RATIO)) {
            if (scale >= ROW_SCALE_MAX) {
                return false;
            }
            scale = fc_add(ar, scale, scale);
        } else {
            *scale_out = scale;
            return true;
        }
    }
    return false;
}

/* ---- init -------------------------------------------------------------- */

static void clear(fc_allocation *a)
{
    *a = (fc_allocation){0};
    a->last_good.thrust = FC_INT16(0, NORM16);
    a->last_good.moment = fc_vec3_16_zero();
    a->delta_warm = fc_vec3_zero();
}

static void derive_rotor(fc_arith *ar, const fc_rotor_params *p, fc_allocation_rotor *r)
{
    r->axis_unit = p->axis_unit;
    r->lever_m = fc_vec3_cross(ar, p->position_m, p->axis_unit, FC_SHIFT(LENGTH, UNIT, LEVER));
    r->thrust_max_n = p->thrust_max_n;
    r->torque_max_nm = p->torque_max_nm;
    r->thrust_exponent = p->thrust_exponent;
    r->torque_exponent = p->torque_exponent;
    r->speed_min = p->speed_min;
    r->flags = 0u;
    if (p->thrust_exponent == FC_C(2.0f, RATIO)) {
        r->flags |= ROTOR_SQRT;
    }
    if (p->torque_exponent == FC_C(2.0f, RATIO)) {
        r->flags |= ROTOR_SQUARE_TORQUE;
    }
    if (p->thrust_exponent != p->torque_exponent) {
        r->flags |= ROTOR_NONLINEAR;
    }
    r->inv_thrust_exponent =
        fc_div(ar, FC_INT(1, RATIO), p->thrust_exponent, FC_DIV_SHIFT(RATIO, RATIO, RATIO));
    r->exponent_ratio =
        fc_div(ar, p->torque_exponent, p->thrust_exponent, FC_DIV_SHIFT(RATIO, RATIO, RATIO));
    const fc_real v_min = power(ar, p->speed_min, p->thrust_exponent, (r->flags & ROTOR_SQRT) != 0u);
    r->v_min = fc_convert(ar, v_min, FC_UNIT_FRAC, FC_PX_FRAC);
}

/* The authorities (fc/allocation.h): F_max = sum_i |A_0i| (FORCE) and per
 * moment axis sum_i |A_ki| / 2 (MOMENT), from the rotors as init derives them. */
static void authorities(fc_arith *ar, const fc_allocation_rotor *rotor, int count, fc_real *thrust_max_n,
                        fc_vec3 *moment_nm)
{
    fc_real sum[ROWS] = {FC_INT(0, FORCE), FC_INT(0, MOMENT), FC_INT(0, MOMENT), FC_INT(0, MOMENT)};
    for (int k = 0; k < ROWS; k++) {
        for (int i = 0; i < count; i++) {
            sum[k] = fc_add(ar, sum[k], fc_abs(ar, physical_entry(ar, &rotor[i], k)));
        }
    }
    const int half = FC_SHIFT(MOMENT, UNIT, MOMENT);
    *thrust_max_n = sum[0];
    *moment_nm = fc_vec3_make(fc_mul(ar, sum[1], FC_C(0.5f, UNIT), half), fc_mul(ar, sum[2], FC_C(0.5f, UNIT), half),
                              fc_mul(ar, sum[3], FC_C(0.5f, UNIT), half));
}

/* Row scales and authorities: FC_INIT_BAD_PARAM beyond the range limits,
 * FC_INIT_RANK_DEFICIENT for a row too small to scale. */
static fc_init_result derive_rows(fc_arith *ar, fc_allocation *a)
{
    for (int k = 0; k < ROWS; k++) {
        fc_real sum = FC_INT(0, MOMENT);
        fc_real largest = FC_INT(0, MOMENT);
        for (int i = 0; i < a->rotor_count; i++) {
            const fc_real entry = fc_abs(ar, physical_entry(ar, &a->rotor[i], k));
            sum = fc_add(ar, sum, entry);
            largest = fc_max(largest, entry);
        }
        const bool in_range = k == 0 ? sum <= FORCE_ROW_SUM_LIMIT : sum <= MOMENT_ROW_SUM_LIMIT;
        if (!in_range) {
            return FC_INIT_BAD_PARAM;
        }
        int shift_to_ratio = FC_SHIFT(MOMENT, GAIN, RATIO);
        if (k == 0) {
            shift_to_ratio = FC_SHIFT(FORCE, GAIN, RATIO);
        }
        if (!choose_row_scale(ar, largest, shift_to_ratio, &a->row_scale[k])) {
            return FC_INIT_RANK_DEFICIENT;
        }
    }
    authorities(ar, a->rotor, a->rotor_count, &a->thrust_max_n, &a->moment_authority_nm);
    /* 1 / F_max in PER_FORCE: F_max of at least 1/16 N */
    if (!(a->thrust_max_n >= THRUST_TOTAL_MIN)) {
        return FC_INIT_BAD_PARAM;
    }
    a->inv_thrust_max = fc_div(ar, FC_INT(1, PER_FORCE), a->thrust_max_n, FC_DIV_SHIFT(PER_FORCE, FORCE, PER_FORCE));
    return FC_INIT_OK;
}

/* Newton-Schulz steps P <- P (2 I - A P). fc_mat_pinv solves the normal
 * equations, whose error grows with cond(A)^2 but lies in the row space of A,
 * where each step squares it away; what is left is the rounding of the
 * products (oracle.allocation, fixed: worst 0.7 cond^2 LSB of MAT, against
 * 12 cond^2 without the steps). */
static void refine_pinv(fc_arith *ar, const fc_mat *a, fc_mat *p)
{
    fc_mat product;
    for (int step = 0; step < 2; step++) {
        (void)fc_mat_mul(ar, a, p, &product); /* A P: 4 x 4, near I */
        for (int i = 0; i < product.rows; i++) {
            for (int j = 0; j < product.cols; j++) {
                product.a[i][j] = fc_sub(ar, i == j ? FC_INT(2, MAT) : FC_INT(0, MAT), product.a[i][j]);
            }
        }
        /* P (2 I - A P) row by row, in place: row i needs only row i of P */
        for (int i = 0; i < p->rows; i++) {
            fc_real row[ROWS];
            for (int j = 0; j < ROWS; j++) {
                fc_acc sum = fc_acc_zero();
                for (int k = 0; k < ROWS; k++) {
                    sum = fc_acc_mac(sum, p->a[i][k], product.a[k][j]);
                }
                row[j] = fc_acc_result(ar, sum, FC_SHIFT(MAT, MAT, MAT));
            }
            for (int j = 0; j < ROWS; j++) {
                p->a[i][j] = row[j];
            }
        }
    }
}

/* B = N A from D A: each row of D A times row_norm (1 / its absolute sum,
 * 2 / it for the moment rows), the most each axis can get (demand_limit, in
 * NORM16: a moment row's 2 saturates to 2 - 2^-14, unreported) and each
 * rotor's reaction-torque column of B (torque_norm, for r != s). */
static void normalise_rows(fc_arith *ar, fc_allocation *a, fc_mat *m)
{
    fc_arith limit_ar = {0u};
    for (int k = 0; k < ROWS; k++) {
        fc_real row_abs_sum = FC_INT(0, MAT);
        for (int i = 0; i < a->rotor_count; i++) {
            row_abs_sum = fc_add(ar, row_abs_sum, fc_abs(ar, m->a[k][i]));
        }
        const fc_real row_target = k == 0 ? FC_INT(1, RATIO) : FC_INT(2, RATIO);
        a->row_norm[k] = fc_div(ar, row_target, row_abs_sum, FC_DIV_SHIFT(RATIO, MAT, RATIO));
        fc_real limit = FC_INT(0, MAT);
        for (int i = 0; i < a->rotor_count; i++) {
            m->a[k][i] = fc_mul(ar, m->a[k][i], a->row_norm[k], FC_SHIFT(MAT, RATIO, MAT));
            limit = fc_add(ar, limit, fc_abs(ar, m->a[k][i]));
        }
        a->demand_limit[k] = fc_narrow16(&limit_ar, limit, FC_MAT_FRAC, FC_NORM16_FRAC);
    }
    for (int i = 0; i < a->rotor_count; i++) {
        fc_allocation_rotor *r = &a->rotor[i];
        fc_real column[3];
        for (int k = 1; k < ROWS; k++) {
            const fc_real torque = fc_mul(ar, r->torque_max_nm, a->row_scale[k], FC_SHIFT(MOMENT, GAIN, MAT));
            const fc_real scaled = fc_mul(ar, torque, component(r->axis_unit, k - 1), FC_SHIFT(MAT, UNIT, MAT));
            column[k - 1] = fc_mul(ar, scaled, a->row_norm[k], FC_SHIFT(MAT, RATIO, MAT));
        }
        r->torque_norm = fc_vec3_make(column[0], column[1], column[2]);
    }
}

/* q_i (RATIO; 1/8 < |q_i| <= 32 for 1/32 <= |P_i0| < 8) in 16 bits, in the
 * finest of Q16, Q14, Q12 and Q10 that holds it: |q_i| is at least a quarter
 * of the format's bound, so the rounding is within 2^-14 of q_i (a q_i just
 * below the bound saturates to the largest value, within one LSB, 2^-15 of
 * q_i; unreported). */
static void set_shift_gain(fc_arith *ar, fc_allocation_rotor *r, fc_real gain)
{
    fc_arith gain_ar = {0u};
    const fc_real size = fc_abs(ar, gain);
    int frac = 10; /* Q(frac) holds |q| < 2^(15 - frac) */
    if (size < FC_C(0.5f, RATIO)) {
        frac = 16;
    } else if (size < FC_INT(2, RATIO)) {
        frac = 14;
    } else if (size < FC_INT(8, RATIO)) {
        frac = 12;
    } else {
        /* up to 32: Q10 */
    }
    r->shift_gain_frac = (uint8_t)frac;
    r->shift_gain = fc_narrow16(&gain_ar, gain, FC_RATIO_FRAC, frac);
}

/* P = pinv(B) and what the thrust shift needs per rotor. */
static fc_init_result derive_inverse(fc_arith *ar, fc_allocation *a)
{
    fc_mat normalised;
    fc_mat inverse;
    if (!build_normalised(ar, a, &normalised)) {
        return FC_INIT_BAD_PARAM;
    }
    if (a->rotor_count < ROWS) {
        return FC_INIT_RANK_DEFICIENT;
    }
    normalise_rows(ar, a, &normalised);
    fc_arith inv_ar = {0u};
    if (fc_mat_pinv(&inv_ar, &normalised, &inverse) != FC_MAT_OK || inv_ar.saturated != 0u) {
        return FC_INIT_RANK_DEFICIENT;
    }
    refine_pinv(&inv_ar, &normalised, &inverse);
    if (inv_ar.saturated != 0u) {
        return FC_INIT_RANK_DEFICIENT;
    }
    for (int i = 0; i < a->rotor_count; i++) {
        fc_allocation_rotor *r = &a->rotor[i];
        for (int k = 0; k < ROWS; k++) {
            if (!within(ar, inverse.a[i][k], PINV_ENTRY_LIMIT)) {
                return FC_INIT_RANK_DEFICIENT;
            }
            /* rounded to nearest; inside the limit it does not saturate */
            r->pinv[k] = fc_narrow16(ar, inverse.a[i][k], FC_MAT_FRAC, FC_PINV16_FRAC);
        }
        /* rotor i bounds the collective t: v_min <= t P_i0 + a R_i <= 1, i.e. with
         * q = 1/P_i0,  t in [low - a q R_i, high - a q R_i] where (low, high) is
         * (q v_min, q) for P_i0 > 0 and (q, q v_min) for P_i0 < 0; P_i0 the
         * PINV16 value the step multiplies */
        const fc_real share = fc_widen16(r->pinv[0], FC_PINV16_FRAC, FC_MAT_FRAC);
        if (fc_abs(ar, share) < SHIFT_SHARE_MIN) {
            continue;
        }
        r->flags |= ROTOR_SHIFTS;
        const fc_real gain = fc_div(ar, FC_INT(1, RATIO), share, FC_DIV_SHIFT(RATIO, MAT, RATIO));
        const fc_real at_min = fc_mul(ar, gain, r->v_min, FC_SHIFT(RATIO, PX, RATIO));
        r->shift_low = share > FC_INT(0, MAT) ? at_min : gain;
        r->shift_high = share > FC_INT(0, MAT) ? gain : at_min;
        set_shift_gain(ar, r, gain);
    }
    return FC_INIT_OK;
}

fc_init_result fc_allocation_init(fc_allocation *a, const fc_allocation_params *p)
{
    if (a == NULL) {
        return FC_INIT_BAD_PARAM;
    }
    clear(a);
    if (p == NULL || p->rotor_count < 1u || p->rotor_count > FC_MAX_ROTORS ||
        p->newton_iterations > FC_ALLOCATION_MAX_ITERATIONS) {
        return FC_INIT_BAD_PARAM;
    }
    fc_arith ar = {0u};
    for (int i = 0; i < p->rotor_count; i++) {
        if (!rotor_params_valid(&ar, &p->rotor[i])) {
            return FC_INIT_BAD_PARAM;
        }
    }
    a->rotor_count = p->rotor_count;
    a->newton_iterations = p->newton_iterations;
    for (int i = 0; i < a->rotor_count; i++) {
        derive_rotor(&ar, &p->rotor[i], &a->rotor[i]);
        if ((a->rotor[i].flags & ROTOR_NONLINEAR) != 0u) {
            a->nonlinear = 1u;
        }
    }
    fc_init_result result = derive_rows(&ar, a);
    if (result == FC_INIT_OK) {
        result = derive_inverse(&ar, a);
    }
    if (result != FC_INIT_OK) {
        clear(a);
        return result;
    }
    a->ready = 1u;
    return FC_INIT_OK;
}

void fc_allocation_reset(fc_allocation *a)
{
    a->delta_warm = fc_vec3_zero();
    a->last_good.thrust = FC_INT16(0, NORM16);
    a->last_good.moment = fc_vec3_16_zero();
}

/* ---- the forward model (2.2)-(2.3) -------------------------------------- */

/* The wrench of the speeds; the body-x/y force only when full_force (the step
 * needs F_z alone). Zero components of d_i and l_i x d_i (planar rotors: most
 * of them) are skipped: each product costs a 64-bit multiply on the ATmega. */
static void forward_model(fc_allocation *a, const fc_real *speed, bool full_force,
                          fc_vec3 *force_n, fc_vec3 *moment_nm, fc_real *rotor_thrust_n)
{
    fc_arith *ar = &a->ar;
    fc_acc force[3] = {fc_acc_zero(), fc_acc_zero(), fc_acc_zero()};
    fc_acc lever_moment[3] = {fc_acc_zero(), fc_acc_zero(), fc_acc_zero()};
    fc_acc torque_moment[3] = {fc_acc_zero(), fc_acc_zero(), fc_acc_zero()};
    for (int i = 0; i < a->rotor_count; i++) {
        const fc_allocation_rotor *r = &a->rotor[i];
        const fc_real u = fc_clamp(speed[i], FC_INT(0, UNIT), FC_INT(1, UNIT));
        const fc_real u_r = power(ar, u, r->thrust_exponent, (r->flags & ROTOR_SQRT) != 0u);
        const fc_real u_s = (r->flags & ROTOR_NONLINEAR) == 0u
                                ? u_r
                                : power(ar, u, r->torque_exponent,
                                        (r->flags & ROTOR_SQUARE_TORQUE) != 0u);
        const fc_real thrust = fc_mul(ar, r->thrust_max_n, u_r, FC_SHIFT(FORCE, UNIT, FORCE));
        const fc_real torque = fc_mul(ar, r->torque_max_nm, u_s, FC_SHIFT(MOMENT, UNIT, MOMENT));
        if (rotor_thrust_n != NULL) {
            rotor_thrust_n[i] = thrust;
        }
        for (int k = 0; k < 3; k++) {
            const fc_real axis = component(r->axis_unit, k);
            const fc_real lever = component(r->lever_m, k);
            if (axis != FC_INT(0, UNIT)) {
                if (full_force || k == 2) {
                    force[k] = fc_acc_mac(force[k], thrust, axis);
                }
                torque_moment[k] = fc_acc_mac(torque_moment[k], torque, axis);
            }
            if (lever != FC_INT(0, LEVER)) {
                lever_moment[k] = fc_acc_mac(lever_moment[k], thrust, lever);
            }
        }
    }
    fc_real f[3];
    fc_real m[3];
    for (int k = 0; k < 3; k++) {
        f[k] = fc_acc_result(ar, force[k], FC_SHIFT(FORCE, UNIT, FORCE));
        m[k] = fc_add(ar, fc_acc_result(ar, lever_moment[k], FC_SHIFT(FORCE, LEVER, MOMENT)),
                      fc_acc_result(ar, torque_moment[k], FC_SHIFT(MOMENT, UNIT, MOMENT)));
    }
    *force_n = fc_vec3_make(f[0], f[1], f[2]);
    *moment_nm = fc_vec3_make(m[0], m[1], m[2]);
}

void fc_allocation_forward_wrench(fc_allocation *a, const fc_real *speed, fc_vec3 *force_n,
                                  fc_vec3 *moment_nm)
{
    if (a->ready == 0u) {
        *force_n = fc_vec3_zero();
        *moment_nm = fc_vec3_zero();
        return;
    }
    forward_model(a, speed, true, force_n, moment_nm, NULL);
}

void fc_allocation_forward(fc_allocation *a, const fc_real *speed, fc_real *thrust_n,
                           fc_vec3 *moment_nm)
{
    fc_vec3 force;
    fc_allocation_forward_wrench(a, speed, &force, moment_nm);
    *thrust_n = force.z;
}

/* N delta(v) = sum N Q_max,i d_i (v_i^(s/r) - v_i) (RATIO) for v (UNIT): the
 * reaction torque the linear model misses when r != s (rotors with r = s add
 * nothing). */
static fc_vec3 torque_correction(fc_allocation *a, const fc_real *v)
{
    fc_arith *ar = &a->ar;
    fc_acc sum[3] = {fc_acc_zero(), fc_acc_zero(), fc_acc_zero()};
    for (int i = 0; i < a->rotor_count; i++) {
        const fc_allocation_rotor *r = &a->rotor[i];
        if ((r->flags & ROTOR_NONLINEAR) == 0u) {
            continue;
        }
        const fc_real excess =
            fc_sub(ar, fc_pow_unit(ar, v[i], r->exponent_ratio), v[i]); /* u^s - u^r */
        for (int k = 0; k < 3; k++) {
            sum[k] = fc_acc_mac(sum[k], component(r->torque_norm, k), excess);
        }
    }
    const int shift = FC_SHIFT(MAT, UNIT, RATIO);
    return fc_vec3_make(fc_acc_result(ar, sum[0], shift), fc_acc_result(ar, sum[1], shift),
                        fc_acc_result(ar, sum[2], shift));
}

/* ---- the desaturating linear allocation --------------------------------- */

/* The step in 16 x 16 -> 32-bit products (fc/allocation.h, Formats): the
 * demand x and the collective t in NORM16, P in PINV16, their products and
 * the sums of them (t P_i0, R_i, Y_i, v_i) exact in PX. What the
 * desaturation compares is narrowed to 16 bits only where a bound may bind:
 * R_i and Y_i (ROTOR16), a rotor's slack (ROTOR16), its collective shift
 * rate s_i (NORM16), the roll/pitch pair constraints (PAIR16); the scales
 * a and b are UNIT16. */
_Static_assert(FC_PINV16_FRAC + FC_NORM16_FRAC == FC_PX_FRAC, "P x is not PX");
#define SCALED_FRAC (FC_UNIT16_FRAC + FC_ROTOR16_FRAC) /* a R_i, b Y_i (Q28, exact) */
#define MOVED_FRAC (FC_UNIT16_FRAC + FC_NORM16_FRAC)   /* a s_i (Q28, exact) */
#define LIMITED_FRAC (FC_NORM16_FRAC + FC_UNIT16_FRAC) /* x_k keep (Q28, exact) */
#define REST_FRAC (FC_RATIO_FRAC + FC_PINV16_FRAC)     /* t's rest times P_i0 (Q36, exact) */

/* A fraction num/den with den > 0 (16-bit, num and den in one format), kept
 * as the pair: ratios are compared by cross products and divided once, at
 * the end. */
typedef struct fraction {
    fc_real16 num, den;
} fraction;

/* The sign of p - q: the difference of two 16 x 16 products, exact. */
static int ratio_compare(fraction p, fraction q)
{
    const fc_real diff = fc_dot2_16(p.num, q.den, fc_neg16(q.num), p.den);
    return diff < 0 ? -1 : (diff > 0 ? 1 : 0);
}

/* num / den for 0 <= num < den, both 16-bit values of one format (in fixed
 * den <= 2^15: |x| of a NORM16 -2 included), as a UNIT16 value rounded down:
 * what it scales stays inside its bound. Fixed: a restoring division of
 * FC_UNIT16_FRAC steps on 16 bits (the doubled remainder stays below 2^16),
 * no 32-bit divide. */
static fc_real16 fraction_down(fc_real num, fc_real den)
{
#if FC_NUMERIC_FIXED
    uint16_t remainder = (uint16_t)num;
    const uint16_t divisor = (uint16_t)den;
    uint16_t quotient = 0u;
    for (int bit = 0; bit < FC_UNIT16_FRAC; bit++) {
        remainder = (uint16_t)(remainder << 1);
        quotient = (uint16_t)(quotient << 1);
        if (remainder >= divisor) {
            remainder = (uint16_t)(remainder - divisor);
            quotient = (uint16_t)(quotient | 1u);
        }
    }
    return (fc_real16)quotient;
#else
    return num / den;
#endif
}

static fc_real16 ratio_unit(fraction r)
{
    if (r.num >= r.den) {
        return FC_INT16(1, UNIT16); /* untouched: no division */
    }
    return fraction_down(r.num, r.den);
}

/* The scales s in [0, 1] that satisfy a set of constraints s c <= e. */
typedef struct scale_interval {
    fraction low, high;
    bool zero_violates; /* some constraint fails even at s = 0 (e < 0 <= c) */
} scale_interval;

/* s = [0, 1], by field: a struct copy is a byte loop at -Os on the ATmega.
 * 0/1 and 1/1: a ratio's format cancels, any positive den stands for 1. */
static void interval_set_full(scale_interval *s)
{
    s->low.num = FC_INT16(0, UNIT16);
    s->low.den = FC_INT16(1, UNIT16);
    s->high.num = FC_INT16(1, UNIT16);
    s->high.den = FC_INT16(1, UNIT16);
    s->zero_violates = false;
}

/* One constraint s c <= e (c and e 16-bit, one format; e >= -FC_REAL16_MAX,
 * so that -e fits). The callers pass only constraints that may bind (their
 * exact 32-bit values fail e >= max(c, 0)). */
static void interval_constrain(scale_interval *s, fc_real16 c, fc_real16 e)
{
    if (c > 0) {
        /* s <= e / c; below zero it leaves no room at all (s = 0 the least bad) */
        if (e >= c) {
            return; /* a bound at or above 1: never binding (no products) */
        }
        fraction bound = {e, c};
        if (e < 0) {
            bound.num = FC_INT16(0, UNIT16);
            s->zero_violates = true;
        }
        if (s->high.num >= s->high.den || ratio_compare(bound, s->high) < 0) {
            s->high = bound;
        }
    } else if (c < 0) {
        /* s >= e / c = (-e) / (-c), a bound only when above zero */
        if (e < 0) {
            const fraction bound = {fc_neg16(e), fc_neg16(c)};
            if (s->low.num == 0 || ratio_compare(bound, s->low) > 0) {
                s->low = bound;
            }
        }
    } else if (e < 0) {
        s->zero_violates = true;
        s->high.num = FC_INT16(0, UNIT16);
    } else {
        /* c == 0 and e >= 0: every s fits */
    }
}

static bool interval_feasible(const scale_interval *s)
{
    if (s->zero_violates) {
        return false;
    }
    /* low = 0 (its numerator is 0 only as set by interval_set_full: a bound has
     * -e > 0): 0 <= high always, high.num >= 0; the product is not needed */
    if (s->low.num == 0) {
        return true;
    }
    return ratio_compare(s->low, s->high) <= 0;
}

/* What the desaturation works with, per rotor (the entries from n on are
 * neither written nor read: every loop runs to the one n, passed down, which
 * the analysers follow): the parts of v = t P_0 + a R + b Y, exact in PX,
 * and what the collective shift forms from them. */
typedef struct rotor_parts {
    fc_real v;              /* PX: v_i without yaw, x_0 P_i0 + R_i (after a shift t P_i0 + a R_i) */
    fc_real yaw;            /* PX: Y_i = P_i3 x_3 */
    fc_real roll_pitch;     /* PX: R_i = P_i1 x_1 + P_i2 x_2 (shift) */
    fc_real16 roll_pitch16; /* ROTOR16: R_i (shift) */
    fc_real16 rate16;       /* NORM16: s_i = q_i R_i (shift) */
} rotor_parts;

/* Rotor i's bounds on the yaw scale b in room: v_min <= v_i + b Y_i <= 1
 * (v_i without yaw, PX). Whether a bound may bind is decided on the exact
 * 32-bit values (the upper one iff v_i + max(Y_i, 0) > 1, the lower iff
 * v_i + min(Y_i, 0) < v_min); only then are Y_i and the slack narrowed to
 * ROTOR16. A slack beyond +-2 is beyond every |Y_i| (at most 2 - 2^-14 in
 * ROTOR16) and saturates without changing the room: not reported (slack_ar). */
static inline __attribute__((always_inline)) void yaw_constrain(fc_arith *ar, fc_arith *slack_ar,
                                                                scale_interval *room, fc_real v, fc_real yaw,
                                                                fc_real v_min)
{
    /* v + max(Y, 0) and v + min(Y, 0): the larger and the smaller of v and v + Y */
    const fc_real with_yaw = fc_add_inline(ar, v, yaw);
    const bool up = fc_max(v, with_yaw) > FC_INT(1, PX);
    const bool down = fc_min(v, with_yaw) < v_min;
    if (up || down) {
        const fc_real16 yaw16 = fc_narrow16(ar, yaw, FC_PX_FRAC, FC_ROTOR16_FRAC);
        if (up) {
            const fc_real slack = fc_sub(ar, FC_INT(1, PX), v);
            interval_constrain(room, yaw16, fc_narrow16(slack_ar, slack, FC_PX_FRAC, FC_ROTOR16_FRAC));
        }
        if (down) {
            const fc_real slack = fc_sub_inline(ar, v, v_min);
            interval_constrain(room, fc_neg16(yaw16), fc_narrow16(slack_ar, slack, FC_PX_FRAC, FC_ROTOR16_FRAC));
        }
    }
}

/* The collective shift rate s_i = q_i R_i of a rotor (NORM16) for its R_i
 * (ROTOR16): q_i in Q(shift_gain_frac), so the product's FRAC is that plus
 * ROTOR16's, one of four constants (a narrowing by a constant shift). */
static fc_real16 shift_rate(fc_arith *ar, const fc_allocation_rotor *r, fc_real16 roll_pitch)
{
    const fc_real product = fc_mul16(r->shift_gain, roll_pitch);
    switch (r->shift_gain_frac) {
    case 16:
        return fc_narrow16(ar, product, 16 + FC_ROTOR16_FRAC, FC_NORM16_FRAC);
    case 14:
        return fc_narrow16(ar, product, 14 + FC_ROTOR16_FRAC, FC_NORM16_FRAC);
    case 12:
        return fc_narrow16(ar, product, 12 + FC_ROTOR16_FRAC, FC_NORM16_FRAC);
    default:
        return fc_narrow16(ar, product, 10 + FC_ROTOR16_FRAC, FC_NORM16_FRAC);
    }
}

/* The largest roll/pitch scale a in [0, 1] for which some collective fits
 * every shifting rotor with no yaw: a (s_j - s_i) <= high_j - low_i for
 * every pair. The pair may bind iff high_j - s_j < low_i - s_i or high_j <
 * low_i (the bounds of t at a = 1 and a = 0 cross), decided on the 32-bit
 * values; only then are both sides narrowed to PAIR16: s_j - s_i of two
 * NORM16 values fits it, and a high_j - low_i beyond +-4 is beyond every
 * |s_j - s_i| and saturates without changing the room (not reported). */
static fc_real16 roll_pitch_room(const fc_allocation *a, int n, const rotor_parts *parts)
{
    fc_arith pair_ar = {0u};
    scale_interval fit;
    interval_set_full(&fit);
    const fc_allocation_rotor *rj = a->rotor;
    const rotor_parts *qj = parts;
    for (int j = 0; j < n; j++, rj++, qj++) {
        if ((rj->flags & ROTOR_SHIFTS) == 0u) {
            continue;
        }
        const fc_real shift_high_j = rj->shift_high;
        const fc_real rate_j = fc_widen16(qj->rate16, FC_NORM16_FRAC, FC_RATIO_FRAC);
        const fc_real high_j = shift_high_j - rate_j; /* exact, as in shift_collective */
        const fc_allocation_rotor *ri = a->rotor;
        const rotor_parts *qi = parts;
        for (int i = 0; i < n; i++, ri++, qi++) {
            if (i == j || (ri->flags & ROTOR_SHIFTS) == 0u) {
                continue;
            }
            const fc_real rate_i = fc_widen16(qi->rate16, FC_NORM16_FRAC, FC_RATIO_FRAC);
            if (high_j < ri->shift_low - rate_i || shift_high_j < ri->shift_low) {
                /* exact: |s_j - s_i| < 4 and |high_j - low_i| <= 64 (RATIO) */
                const fc_real c = rate_j - rate_i;
                const fc_real e = shift_high_j - ri->shift_low;
                interval_constrain(&fit, fc_narrow16(&pair_ar, c, FC_RATIO_FRAC, FC_PAIR16_FRAC),
                                   fc_narrow16(&pair_ar, e, FC_RATIO_FRAC, FC_PAIR16_FRAC));
            }
        }
    }
    return ratio_unit(fit.high);
}

/* The FC_SAT_* bit of a row (0 F_z, 1 M_x, 2 M_y, 3 M_z) short in the positive
 * (demand above what was given) or negative direction. */
static uint8_t sat_bit(int row, bool positive)
{
    switch (row) {
    case 0:
        return positive ? FC_SAT_THRUST_HIGH : FC_SAT_THRUST_LOW;
    case 1:
        return positive ? FC_SAT_ROLL_POS : FC_SAT_ROLL_NEG;
    case 2:
        return positive ? FC_SAT_PITCH_POS : FC_SAT_PITCH_NEG;
    default:
        return positive ? FC_SAT_YAW_POS : FC_SAT_YAW_NEG;
    }
}

static uint8_t direction_bit(fc_real demand, int row)
{
    if (demand > 0) {
        return sat_bit(row, true);
    }
    if (demand < 0) {
        return sat_bit(row, false);
    }
    return 0u;
}

/* The normalised demand w (NORM16) clamped to what all rotors together can
 * give per axis (roll and pitch scaled together, by a factor rounded down)
 * into x, every |x_k| then at most FC_REAL16_MAX. Returns the bits of the
 * clamped axes. */
static uint8_t limit_demand(fc_allocation *a, const fc_allocation_demand *w, fc_real16 *x)
{
    fc_arith *ar = &a->ar;
    uint8_t saturation = 0u;
    x[0] = w->thrust;
    x[1] = w->moment.x;
    x[2] = w->moment.y;
    x[3] = w->moment.z;
    for (int k = 0; k < ROWS; k += 3) { /* F_z and M_z on their own */
        const fc_real16 limit = a->demand_limit[k];
        if (x[k] > limit) {
            x[k] = limit;
            saturation |= sat_bit(k, true);
        } else if (x[k] < fc_neg16(limit)) {
            x[k] = fc_neg16(limit);
            saturation |= sat_bit(k, false);
        } else {
            /* within the limit */
        }
    }
    fc_real16 keep = FC_INT16(1, UNIT16); /* roll/pitch: one factor, the direction kept */
    for (int k = 1; k <= 2; k++) {
        const fc_real16 limit = a->demand_limit[k];
        if (x[k] > limit || x[k] < fc_neg16(limit)) {
            const fc_real size = fc_abs(ar, x[k]); /* 32 bits: 2^15 for a NORM16 -2 */
            const fc_real16 factor = fraction_down(limit, size);
            if (factor < keep) {
                keep = factor;
            }
        }
    }
    if (keep < FC_INT16(1, UNIT16)) {
        saturation = (uint8_t)(saturation | direction_bit(x[1], 1) | direction_bit(x[2], 2));
        x[1] = fc_narrow16(ar, fc_mul16(x[1], keep), LIMITED_FRAC, FC_NORM16_FRAC);
        x[2] = fc_narrow16(ar, fc_mul16(x[2], keep), LIMITED_FRAC, FC_NORM16_FRAC);
    }
    return saturation;
}

/* v in [v_min, 1] (PX) for rotor r */
static bool rotor_fits(const fc_allocation_rotor *r, fc_real v)
{
    return v >= r->v_min && v <= FC_INT(1, PX);
}

/* The speeds as demanded, v_i = x_0 P_i0 + R_i + Y_i (t = x_0, a = b = 1),
 * into v_out (UNIT) for every rotor whose v_i with and without its yaw Y_i
 * lies in [v_min, 1]; returns the others (bit i for rotor i). When it
 * returns none, no bound binds (fc/allocation.h, step 1 with b = 1) and
 * v_out is the step's v. v_i + Y_i is formed only for a v_i in [v_min, 1]:
 * it cannot saturate then. Nothing else is kept: the desaturation forms
 * the parts again (the registers of this loop are the step's cycles). */
static uint8_t demanded_speeds(fc_allocation *a, const fc_real16 *x, fc_real *v_out)
{
    fc_arith *ar = &a->ar;
    const fc_real16 thrust = x[0], roll = x[1], pitch = x[2], yaw = x[3];
    uint8_t outside = 0u;
    uint8_t bit = 1u;
    const fc_allocation_rotor *r = a->rotor;
    for (uint8_t i = a->rotor_count; i != 0u; i--) {
        const fc_real v = fc_add_inline(ar, fc_mul16(thrust, r->pinv[0]), fc_dot2_16(r->pinv[1], roll, r->pinv[2], pitch));
        /* exact: |v| <= 1 and |P_i3 x_3| < 16 (PINV16 times NORM16) */
        const fc_real demanded = rotor_fits(r, v) ? v + fc_mul16(r->pinv[3], yaw) : FC_REAL_MAX;
        if (rotor_fits(r, demanded)) {
            *v_out = fc_widen_bounded(demanded, FC_PX_FRAC, FC_UNIT_FRAC); /* v in [v_min, 1] */
        } else {
            outside = (uint8_t)(outside | bit);
        }
        bit = (uint8_t)(bit << 1);
        r++;
        v_out++;
    }
    return outside;
}

/* Step 1's parts: t = x_0, a = b = 1: R_i, Y_i and v_i = x_0 P_i0 + R_i,
 * as demanded_speeds forms them; returns the room for the yaw scale b that
 * the rotors of `outside` leave (bit i for rotor i; the others fit at b = 0
 * and b = 1, so at every b between). */
static scale_interval split_demand(fc_allocation *a, int n, const fc_real16 *x, uint8_t outside, rotor_parts *parts)
{
    fc_arith *ar = &a->ar;
    fc_arith slack_ar = {0u};
    scale_interval room;
    interval_set_full(&room);
    for (int i = 0; i < n; i++) {
        const fc_allocation_rotor *r = &a->rotor[i];
        rotor_parts *q = &parts[i];
        const fc_real roll_pitch = fc_dot2_16(r->pinv[1], x[1], r->pinv[2], x[2]);
        q->roll_pitch = roll_pitch;
        q->yaw = fc_mul16(r->pinv[3], x[3]);
        q->v = fc_add_inline(ar, fc_mul16(x[0], r->pinv[0]), roll_pitch);
        if ((outside & 1u) != 0u) {
            yaw_constrain(ar, &slack_ar, &room, q->v, q->yaw, r->v_min);
        }
        outside = (uint8_t)(outside >> 1);
    }
    return room;
}

/* Steps 2 and 3 (fc/allocation.h), when yaw alone cannot make room: the
 * largest roll/pitch scale a in [0, 1] for which some collective t fits
 * every rotor with no yaw, then t, the demand x_0 clamped to the interval
 * that fits a R; the parts' v becomes t P_0 + a R. Rotor i bounds t to
 * [low_i - a s_i, high_i - a s_i], s_i = q_i R_i (derive_inverse). Returns
 * the FC_SAT_* bits of a and t; the room for the yaw scale b that the
 * shifted parts leave goes to room (every rotor, as each v is formed). */
static uint8_t shift_collective(fc_allocation *a, int n, const fc_real16 *x, rotor_parts *parts,
                                scale_interval *room)
{
    fc_arith *ar = &a->ar;
    uint8_t saturation = 0u;
    /* the interval of t at a = 1; when it is empty some pair binds and a < 1
     * (a pair that is violated only at a = 0 leaves a = 1: roll_pitch_room
     * would say the same) */
    fc_real t_low = FC_REAL_MIN;
    fc_real t_high = FC_REAL_MAX;
    const fc_allocation_rotor *r = a->rotor;
    rotor_parts *q = parts;
    for (int i = 0; i < n; i++, r++, q++) {
        q->roll_pitch16 = fc_narrow16(ar, q->roll_pitch, FC_PX_FRAC, FC_ROTOR16_FRAC);
        q->rate16 = shift_rate(ar, r, q->roll_pitch16); /* 0 for a rotor that does not shift */
        const fc_real rate = fc_widen16(q->rate16, FC_NORM16_FRAC, FC_RATIO_FRAC);
        if ((r->flags & ROTOR_SHIFTS) != 0u) {
            /* the bounds of t at a = 1, low_i - s_i and high_i - s_i; exact:
             * |low_i|, |high_i| <= |q_i| <= 32 and |s_i| < 2 (RATIO) */
            t_low = fc_max(t_low, r->shift_low - rate);
            t_high = fc_min(t_high, r->shift_high - rate);
        }
    }
    fc_real16 roll_pitch_scale = FC_INT16(1, UNIT16);
    if (t_low > t_high) {
        roll_pitch_scale = roll_pitch_room(a, n, parts);
    }
    const bool scaled = roll_pitch_scale < FC_INT16(1, UNIT16);
    if (scaled) {
        /* the collective: the demand clamped to the interval that fits a R */
        t_low = FC_REAL_MIN;
        t_high = FC_REAL_MAX;
        r = a->rotor;
        q = parts;
        for (int i = 0; i < n; i++, r++, q++) {
            if ((r->flags & ROTOR_SHIFTS) != 0u) {
                const fc_real moved =
                    fc_convert(ar, fc_mul16(roll_pitch_scale, q->rate16), MOVED_FRAC, FC_RATIO_FRAC);
                /* exact: |low_i|, |high_i| <= 32 and |a s_i| < 2 (RATIO) */
                t_low = fc_max(t_low, r->shift_low - moved);
                t_high = fc_min(t_high, r->shift_high - moved);
            }
        }
    }
    const fc_real demanded = fc_widen16(x[0], FC_NORM16_FRAC, FC_RATIO_FRAC);
    fc_real t;
    if (t_low > t_high) {
        /* empty by a rounding (or a geometry that cannot hover): the middle */
        t = fc_mul(ar, fc_add(ar, t_low, t_high), FC_C(0.5f, UNIT), FC_SHIFT(RATIO, UNIT, RATIO));
    } else {
        t = fc_clamp(demanded, t_low, t_high);
    }
    if (t < demanded) {
        saturation |= FC_SAT_THRUST_HIGH;
    } else if (t > demanded) {
        saturation |= FC_SAT_THRUST_LOW;
    } else {
        /* the collective as demanded */
    }
    if (scaled) {
        saturation = (uint8_t)(saturation | direction_bit(x[1], 1) | direction_bit(x[2], 2));
    }
    /* v = t P_0 + a R: a = 1 keeps R exact (no product). t P_i0 to t's 32
     * bits, the rotor that bounds t on its bound: t = t16 + rest, t16 in
     * NORM16 and the rest (|rest| <= 2^-15) in RATIO's Q24, two 16-bit
     * values, two products */
    const fc_real16 t16 = fc_narrow16(ar, t, FC_RATIO_FRAC, FC_NORM16_FRAC);
    const fc_real16 rest =
        fc_narrow16(ar, fc_sub_inline(ar, t, fc_widen16(t16, FC_NORM16_FRAC, FC_RATIO_FRAC)), FC_RATIO_FRAC, FC_RATIO_FRAC);
    fc_arith slack_ar = {0u};
    interval_set_full(room);
    /* t P_i0 formed again only where P_i0 differs from the last rotor's (a
     * symmetric layout's rotors share one collective share); the first
     * rotor's is formed unless it is 0, the product's value for 0 */
    fc_real16 last_share = FC_INT16(0, PINV16);
    fc_real collective = FC_INT(0, PX);
    r = a->rotor;
    q = parts;
    for (int i = 0; i < n; i++, r++, q++) {
        const fc_real16 share = r->pinv[0];
        if (share != last_share) {
            collective = fc_add_inline(ar, fc_mul16(t16, share),
                                       fc_convert(ar, fc_mul16(rest, share), REST_FRAC, FC_PX_FRAC));
            last_share = share;
        }
        const fc_real roll_pitch =
            scaled ? fc_convert(ar, fc_mul16(roll_pitch_scale, q->roll_pitch16), SCALED_FRAC, FC_PX_FRAC)
                   : q->roll_pitch;
        q->v = fc_add_inline(ar, collective, roll_pitch);
        yaw_constrain(ar, &slack_ar, room, q->v, q->yaw, r->v_min);
    }
    return saturation;
}

/* Steps 1-3 (fc/allocation.h) when some rotor leaves [v_min, 1] as
 * demanded (outside: demanded_speeds' rotors): v (UNIT) into v_out for
 * every rotor; returns the FC_SAT_* bits of the scales and the shift. The
 * parts in the caller's stack frame (desaturate's): what this function
 * spills then lies within the 63 bytes the ATmega reaches from its frame
 * pointer. */
static __attribute__((noinline)) uint8_t desaturation_steps(fc_allocation *a, const fc_real16 *x, uint8_t outside,
                                                          rotor_parts *parts, fc_real *v_out)
{
    fc_arith *ar = &a->ar;
    uint8_t saturation = 0u;
    /* 1. thrust and roll/pitch as demanded: yaw gives what room it must */
    const int n = a->rotor_count;
    scale_interval room = split_demand(a, n, x, outside, parts);
    if (!interval_feasible(&room)) {
        /* 3. roll/pitch last, 2. then the collective, and the room of b
         * there (b = 0 fits by construction: only its upper bounds matter) */
        saturation |= shift_collective(a, n, x, parts, &room);
    }
    /* 1. yaw: the largest b that fits; b = 1 keeps Y exact (no product) */
    const fc_real16 yaw_scale = ratio_unit(room.high);
    const bool yaw_scaled = yaw_scale < FC_INT16(1, UNIT16);
    if (yaw_scaled) {
        saturation |= direction_bit(x[3], 3);
    }
    const fc_allocation_rotor *r = a->rotor;
    const rotor_parts *q = parts;
    for (int i = 0; i < n; i++) {
        fc_real yaw = q->yaw;
        if (yaw_scaled) {
            const fc_real16 yaw16 = fc_narrow16(ar, yaw, FC_PX_FRAC, FC_ROTOR16_FRAC);
            yaw = fc_convert(ar, fc_mul16(yaw_scale, yaw16), SCALED_FRAC, FC_PX_FRAC);
        }
        const fc_real v = fc_clamp(fc_add_inline(ar, q->v, yaw), r->v_min, FC_INT(1, PX));
        *v_out = fc_widen_bounded(v, FC_PX_FRAC, FC_UNIT_FRAC); /* clamped to [v_min, 1] */
        r++;
        q++;
        v_out++;
    }
    return saturation;
}

/* desaturation_steps with its parts. Out of line: the step without
 * saturation does not pay for their stack frame. */
static __attribute__((noinline)) uint8_t desaturate(fc_allocation *a, const fc_real16 *x, uint8_t outside,
                                                    fc_real *v_out)
{
    rotor_parts parts[FC_MAX_ROTORS]; /* the first rotor_count written by split_demand */
    return desaturation_steps(a, x, outside, parts, v_out);
}

/* v (UNIT, in [v_min, 1]) for the normalised wrench w (NORM16: F_z, M_x,
 * M_y, M_z), with the priorities of fc/allocation.h; returns the FC_SAT_* bits. */
static uint8_t allocate_linear(fc_allocation *a, const fc_allocation_demand *w, fc_real *v_out)
{
    fc_real16 x[ROWS]; /* all written by limit_demand */
    uint8_t saturation = limit_demand(a, w, x);
    const uint8_t outside = demanded_speeds(a, x, v_out);
    if (outside != 0u) {
        saturation |= desaturate(a, x, outside, v_out);
    }
    return saturation;
}

/* ---- step -------------------------------------------------------------- */

/* A moment demand (NORM16) less the torque correction (RATIO), in NORM16:
 * beyond +-2 it saturates unreported, as limit_demand clamps it to at most
 * that anyway. */
static fc_real16 corrected_moment(fc_real16 demand, fc_real delta)
{
    fc_arith ar = {0u};
    const fc_real corrected = fc_sub(&ar, fc_widen16(demand, FC_NORM16_FRAC, FC_RATIO_FRAC), delta);
    return fc_narrow16(&ar, corrected, FC_RATIO_FRAC, FC_NORM16_FRAC);
}

/* r != s: the linear allocation iterated with the torque correction,
 * warm-started from the last step's (fc/allocation.h); v (UNIT) into v,
 * returns the FC_SAT_* bits of the last pass. */
static __attribute__((noinline)) uint8_t allocate_nonlinear(fc_allocation *a, const fc_allocation_demand *w,
                                                            fc_real *v)
{
    uint8_t saturation = 0u;
    fc_vec3 delta = a->delta_warm;
    for (int pass = 0; pass <= a->newton_iterations; pass++) {
        if (pass > 0) {
            delta = torque_correction(a, v);
        }
        const fc_allocation_demand corrected = {
            w->thrust,
            {corrected_moment(w->moment.x, delta.x), corrected_moment(w->moment.y, delta.y),
             corrected_moment(w->moment.z, delta.z)}};
        saturation = allocate_linear(a, &corrected, v);
    }
    a->delta_warm = torque_correction(a, v);
    return saturation;
}

static bool demand_is_finite(const fc_allocation_demand *d)
{
    return fc_is_finite(d->thrust) && fc_is_finite3(d->moment.x, d->moment.y, d->moment.z);
}

fc_step_status fc_allocation_speeds(fc_allocation *a, const fc_allocation_demand *d, fc_real *speed_unit,
                                    uint8_t *saturation_bits)
{
    for (int i = 0; i < FC_MAX_ROTORS; i++) {
        speed_unit[i] = FC_INT(0, UNIT);
    }
    *saturation_bits = 0u;
    if (a->ready == 0u) {
        return FC_STEP_NOT_READY;
    }
    a->ar.saturated = 0u;
    fc_step_status status = FC_STEP_OK;

    const fc_allocation_demand *demand = d;
    if (d == NULL || !demand_is_finite(d)) {
        demand = &a->last_good;
        status |= FC_STEP_BAD_INPUT;
    } else {
        /* by field: a struct copy is a byte loop at -Os on the ATmega */
        a->last_good.thrust = d->thrust;
        a->last_good.moment.x = d->moment.x;
        a->last_good.moment.y = d->moment.y;
        a->last_good.moment.z = d->moment.z;
    }

    /* v (UNIT) in speed_unit, the rotor_count entries written by
     * allocate_linear (the others stay 0), then the speeds in place */
    fc_real *v = speed_unit;
    /* the 16-bit demand as it is: the step's products are 16 x 16 bits */
    const uint8_t saturation =
        a->nonlinear != 0u ? allocate_nonlinear(a, demand, v) : allocate_linear(a, demand, v);

    /* u = v^(1/r); r = 2: the root to 16 bits (fc/allocation.h) */
    const fc_allocation_rotor *r = a->rotor;
    for (uint8_t i = a->rotor_count; i != 0u; i--) {
        /* the root lies in [0, 1] (fc_sqrt_unit16): only the power needs the upper bound */
        const fc_real u = (r->flags & ROTOR_SQRT) != 0u
                              ? fc_sqrt_unit16(&a->ar, *v)
                              : fc_min(fc_pow_unit(&a->ar, *v, r->inv_thrust_exponent), FC_INT(1, UNIT));
        *v = fc_max(u, r->speed_min);
        v++;
        r++;
    }

    *saturation_bits = saturation;
    if (saturation != 0u) {
        status |= FC_STEP_OUTPUT_LIMITED;
    }
    if (a->ar.saturated != 0u) {
        status |= FC_STEP_ARITH_SATURATED;
    }
    return status;
}

fc_step_status fc_allocation_step(fc_allocation *a, const fc_allocation_demand *d,
                                  fc_allocation_output *out)
{
    for (int i = 0; i < FC_MAX_ROTORS; i++) {
        out->rotor_thrust_n[i] = FC_INT(0, FORCE);
    }
    out->thrust_n = FC_INT(0, FORCE);
    out->moment_nm = fc_vec3_zero();
    fc_step_status status = fc_allocation_speeds(a, d, out->speed, &out->saturation);
    if (a->ready != 0u) {
        /* the model's products may saturate too: reported with the step's */
        fc_vec3 force;
        forward_model(a, out->speed, false, &force, &out->moment_nm, out->rotor_thrust_n);
        out->thrust_n = force.z;
        if (a->ar.saturated != 0u) {
            status |= FC_STEP_ARITH_SATURATED;
        }
    }
    return status;
}

/* ---- matrices for the oracle --------------------------------------------- */

fc_mat_status fc_allocation_effectiveness(const fc_allocation *a, fc_mat *out)
{
    if (a->ready == 0u) {
        (void)fc_mat_zero(out, 0, 0);
        return FC_MAT_BAD_SIZE;
    }
    fc_arith ar = {0u};
    (void)fc_mat_zero(out, ROWS, a->rotor_count);
    for (int i = 0; i < a->rotor_count; i++) {
        const fc_allocation_rotor *r = &a->rotor[i];
        out->a[0][i] = fc_mul(&ar, r->thrust_max_n, r->axis_unit.z, FC_SHIFT(FORCE, UNIT, MAT));
        for (int k = 1; k < ROWS; k++) {
            out->a[k][i] = fc_add(&ar,
                                  fc_mul(&ar, r->thrust_max_n, component(r->lever_m, k - 1),
                                         FC_SHIFT(FORCE, LEVER, MAT)),
                                  fc_mul(&ar, r->torque_max_nm, component(r->axis_unit, k - 1),
                                         FC_SHIFT(MOMENT, UNIT, MAT)));
        }
    }
    return FC_MAT_OK;
}

fc_mat_status fc_allocation_effectiveness_normalised(const fc_allocation *a, fc_mat *out)
{
    if (a->ready == 0u) {
        (void)fc_mat_zero(out, 0, 0);
        return FC_MAT_BAD_SIZE;
    }
    fc_arith ar = {0u};
    (void)build_normalised(&ar, a, out);
    for (int k = 0; k < ROWS; k++) {
        for (int i = 0; i < a->rotor_count; i++) {
            out->a[k][i] = fc_mul(&ar, out->a[k][i], a->row_norm[k], FC_SHIFT(MAT, RATIO, MAT));
        }
    }
    return FC_MAT_OK;
}

fc_mat_status fc_allocation_pinv_normalised(const fc_allocation *a, fc_mat *out)
{
    if (a->ready == 0u) {
        (void)fc_mat_zero(out, 0, 0);
        return FC_MAT_BAD_SIZE;
    }
    (void)fc_mat_zero(out, a->rotor_count, ROWS);
    for (int i = 0; i < a->rotor_count; i++) {
        for (int k = 0; k < ROWS; k++) {
            out->a[i][k] = fc_widen16(a->rotor[i].pinv[k], FC_PINV16_FRAC, FC_MAT_FRAC);
        }
    }
    return FC_MAT_OK;
}

/* ---- normalised and physical units --------------------------------------- */

bool fc_allocation_authority_of(const fc_allocation_params *p, fc_real *thrust_max_n, fc_vec3 *moment_nm)
{
    *thrust_max_n = FC_INT(0, FORCE);
    *moment_nm = fc_vec3_zero();
    if (p == NULL || p->rotor_count < 1u || p->rotor_count > FC_MAX_ROTORS) {
        return false;
    }
    fc_arith ar = {0u};
    fc_allocation_rotor rotor[FC_MAX_ROTORS];
    for (int i = 0; i < p->rotor_count; i++) {
        if (!rotor_params_valid(&ar, &p->rotor[i])) {
            return false;
        }
        derive_rotor(&ar, &p->rotor[i], &rotor[i]);
    }
    authorities(&ar, rotor, p->rotor_count, thrust_max_n, moment_nm);
    return true;
}

fc_real16 fc_allocation_thrust_fraction(const fc_allocation *a, fc_real thrust_n)
{
    fc_arith ar = {0u};
    const fc_real share = fc_mul(&ar, thrust_n, a->inv_thrust_max, FC_SHIFT(FORCE, PER_FORCE, RATIO));
    return fc_narrow16(&ar, fc_clamp(share, FC_C(-1.99f, RATIO), FC_C(1.99f, RATIO)), FC_RATIO_FRAC,
                       FC_NORM16_FRAC);
}

/* x / authority in NORM16, within +-1.99; 0 for a zero authority (not ready). */
static fc_real16 fraction_of_authority(fc_arith *ar, fc_real x, fc_real authority)
{
    if (!(authority > FC_INT(0, MOMENT))) {
        return FC_INT16(0, NORM16);
    }
    /* x and authority share a format: the quotient is RATIO */
    const fc_real ratio = fc_div(ar, x, authority, FC_RATIO_FRAC);
    return fc_narrow16(ar, fc_clamp(ratio, FC_C(-1.99f, RATIO), FC_C(1.99f, RATIO)), FC_RATIO_FRAC,
                       FC_NORM16_FRAC);
}

fc_allocation_demand fc_allocation_normalise(const fc_allocation *a, fc_real thrust_n, fc_vec3 moment_nm)
{
    fc_arith ar = {0u};
    const fc_vec3 m = a->moment_authority_nm;
    const fc_allocation_demand d = {
        fraction_of_authority(&ar, thrust_n, a->thrust_max_n),
        {fraction_of_authority(&ar, moment_nm.x, m.x), fraction_of_authority(&ar, moment_nm.y, m.y), fraction_of_authority(&ar, moment_nm.z, m.z)}};
    return d;
}

void fc_allocation_moment_nm(const fc_allocation *a, const fc_vec3_16 *moment, fc_vec3 *moment_nm)
{
    fc_arith ar = {0u};
    const fc_vec3 *m = &a->moment_authority_nm;
    const int to_moment = FC_SHIFT(NORM16, MOMENT, MOMENT);
    moment_nm->x = fc_mul_by16(&ar, m->x, moment->x, to_moment);
    moment_nm->y = fc_mul_by16(&ar, m->y, moment->y, to_moment);
    moment_nm->z = fc_mul_by16(&ar, m->z, moment->z, to_moment);
}

void fc_allocation_physical(const fc_allocation *a, const fc_allocation_demand *d, fc_real *thrust_n,
                            fc_vec3 *moment_nm)
{
    fc_arith ar = {0u};
    *thrust_n = fc_mul_by16(&ar, a->thrust_max_n, d->thrust, FC_SHIFT(NORM16, FORCE, FORCE));
    fc_allocation_moment_nm(a, &d->moment, moment_nm);
}

/* ---- presets (FC_C constants only) -------------------------------------- */

/* A rotor in the body xy-plane, thrust along +z, r = s = 2. */
static void planar_rotor(fc_rotor_params *r, fc_real x_m, fc_real y_m, fc_real thrust_max_n,
                         fc_real torque_max_nm, fc_real speed_min)
{
    r->axis_unit = fc_vec3_make(FC_INT(0, UNIT), FC_INT(0, UNIT), FC_INT(1, UNIT));
    r->position_m = fc_vec3_make(x_m, y_m, FC_INT(0, LENGTH));
    r->thrust_max_n = thrust_max_n;
    r->torque_max_nm = torque_max_nm;
    r->thrust_exponent = FC_C(2.0f, RATIO);
    r->torque_exponent = FC_C(2.0f, RATIO);
    r->speed_min = speed_min;
}

static void clear_params(fc_allocation_params *p)
{
    *p = (fc_allocation_params){0};
    p->newton_iterations = 2u;
}

/* Quad-X, rotors front-right, back-right, back-left, front-left (Crazyflie
 * M1..M4); M1 and M3 react along -z. */
static void quad_x(fc_allocation_params *p, fc_real half_span_m, fc_real minus_half_span_m,
                   fc_real thrust_max_n, fc_real torque_max_nm, fc_real minus_torque_max_nm,
                   fc_real speed_min)
{
    clear_params(p);
    p->rotor_count = 4u;
    planar_rotor(&p->rotor[0], half_span_m, minus_half_span_m, thrust_max_n, minus_torque_max_nm,
                 speed_min);
    planar_rotor(&p->rotor[1], minus_half_span_m, minus_half_span_m, thrust_max_n, torque_max_nm,
                 speed_min);
    planar_rotor(&p->rotor[2], minus_half_span_m, half_span_m, thrust_max_n, minus_torque_max_nm,
                 speed_min);
    planar_rotor(&p->rotor[3], half_span_m, half_span_m, thrust_max_n, torque_max_nm, speed_min);
}

void fc_allocation_preset_crazyflie2(fc_allocation_params *p)
{
    /* arm 0.046 m at 45 deg; THRUST_MAX 0.12 N; torque/thrust 0.00699 m;
     * u_min = sqrt(THRUST_MIN / THRUST_MAX) = sqrt(0.0128 / 0.12) */
    quad_x(p, FC_C(0.046f * 0.70710678f, LENGTH), FC_C(-0.046f * 0.70710678f, LENGTH),
           FC_C(0.12f, FORCE), FC_C(0.12f * 0.00699f, MOMENT), FC_C(-0.12f * 0.00699f, MOMENT),
           FC_C(0.32659863f, UNIT));
}

void fc_allocation_preset_f450(fc_allocation_params *p)
{
    quad_x(p, FC_C(0.225f * 0.70710678f, LENGTH), FC_C(-0.225f * 0.70710678f, LENGTH),
           FC_C(8.0f, FORCE), FC_C(8.0f * 0.016f, MOMENT), FC_C(-8.0f * 0.016f, MOMENT),
           FC_C(0.15f, UNIT));
}

void fc_allocation_preset_hexa_x_4kg(fc_allocation_params *p)
{
    /* 0.45 m arms at -30, 30, 90, 150, 210, 270 deg from the nose (counter-
     * clockwise seen from above); T_max = 2 * 4 kg * 9.81 m/s^2 / 6 = 13.08 N */
    clear_params(p);
    p->rotor_count = 6u;
    const fc_real thrust = FC_C(13.08f, FORCE);
    const fc_real torque = FC_C(13.08f * 0.016f, MOMENT);
    const fc_real minus_torque = FC_C(-13.08f * 0.016f, MOMENT);
    const fc_real speed_min = FC_C(0.15f, UNIT);
    const fc_real x_far = FC_C(0.45f * 0.86602540f, LENGTH); /* 0.45 cos 30 deg */
    const fc_real x_far_neg = FC_C(-0.45f * 0.86602540f, LENGTH);
    const fc_real y_near = FC_C(0.225f, LENGTH); /* 0.45 sin 30 deg */
    const fc_real y_near_neg = FC_C(-0.225f, LENGTH);
    planar_rotor(&p->rotor[0], x_far, y_near_neg, thrust, minus_torque, speed_min);
    planar_rotor(&p->rotor[1], x_far, y_near, thrust, torque, speed_min);
    planar_rotor(&p->rotor[2], FC_INT(0, LENGTH), FC_C(0.45f, LENGTH), thrust, minus_torque,
                 speed_min);
    planar_rotor(&p->rotor[3], x_far_neg, y_near, thrust, torque, speed_min);
    planar_rotor(&p->rotor[4], x_far_neg, y_near_neg, thrust, minus_torque, speed_min);
    planar_rotor(&p->rotor[5], FC_INT(0, LENGTH), FC_C(-0.45f, LENGTH), thrust, torque, speed_min);
}
