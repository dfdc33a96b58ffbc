/*
 * test_allocation.c - control allocation (fc/allocation.h), both backends.
 *
 * The demand is normalised (NORM16: thrust / F_max, moment / authority,
 * fc/allocation.h); the achieved wrench (the forward model of the allocated
 * speeds, out->thrust_n and out->moment_nm) is physical. A demand written in N
 * and N m goes through fc_allocation_normalise (demand_make), which rounds it
 * to NORM16 (an LSB is 2^-14 of the authority: 4.8e-7 N m of the Crazyflie's
 * roll, 8 LSB of MOMENT; 7.2e-4 N m of the hexa's, 12 000 LSB, far beyond the
 * round-trip bounds). What the achieved wrench is compared with is the
 * physical value of the demand actually passed (fc_allocation_physical of the
 * quantised demand: demanded()), so that rounding is not counted as
 * allocation error, and no tolerance below grows with it (the quad's
 * speed recovery carries the rounding into its reference speeds instead).
 *
 * Round trips: a feasible demand is made by the library's own forward model
 * from random speeds (xorshift32, fixed seed), normalised, allocated, and the
 * achieved wrench compared with the physical value of that demand. Tolerances:
 *   fixed  in LSB of the output format (FORCE 2^-20 N, MOMENT 2^-24 N m),
 *          derived from the step's formats (v_error: P's rounding to PINV16
 *          times the demand, the 16-bit copies ROTOR16 where a scale gave
 *          way; the roots' 2^-16) and the output's rounding;
 *   float  relative to the axis' sum_i |A_ki| (the most all rotors together
 *          give on that axis: F_max for F_z, twice the authority for a moment).
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdio.h>
#include <float.h>
#include <math.h>
#include <cmocka.h>

#include "fc/allocation.h"
#include "test_support.h"

/* ---- helpers ----------------------------------------------------------- */

#define FIXED (FC_NUMERIC_FIXED != 0)
#define EPS ((double)FLT_EPSILON)

static float to_f(fc_real x, int frac)
{
    return fc_to_float(x, frac);
}

static fc_real from_f(float x, int frac)
{
    return fc_from_float(x, frac);
}

/* The exact value of a backend number (fc_to_float rounds a 31-bit Q-value). */
static double exact(fc_real x, int frac)
{
    return ts_val(x, frac);
}

static uint32_t rng_state = 0x2545F491u;

static void rng_seed(uint32_t seed)
{
    rng_state = seed;
}

static float uniform(float lo, float hi)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 17;
    rng_state ^= rng_state << 5;
    return lo + (hi - lo) * (float)(rng_state >> 8) * (1.0f / 16777216.0f);
}

typedef void (*preset_fn)(fc_allocation_params *);

static const preset_fn presets[] = {fc_allocation_preset_crazyflie2, fc_allocation_preset_f450,
                                    fc_allocation_preset_hexa_x_4kg};
static const char *const preset_names[] = {"crazyflie2", "f450", "hexa_x_4kg"};
#define PRESET_COUNT 3

/* A normalised value (NORM16) from a float, rounded to nearest; and back, exactly. */
static fc_real16 norm16(float x)
{
    fc_arith ar = {0u};
    return fc_narrow16(&ar, from_f(x, FC_RATIO_FRAC), FC_RATIO_FRAC, FC_NORM16_FRAC);
}

static float norm_value(fc_real16 x)
{
    return to_f(fc_widen16(x, FC_NORM16_FRAC, FC_RATIO_FRAC), FC_RATIO_FRAC);
}

/* A demand given in normalised units (fractions of F_max and of the authorities). */
static fc_allocation_demand demand_norm(float thrust, float mx, float my, float mz)
{
    fc_allocation_demand d;
    d.thrust = norm16(thrust);
    d.moment.x = norm16(mx);
    d.moment.y = norm16(my);
    d.moment.z = norm16(mz);
    return d;
}

/* A demand in N and N m, normalised by a's authorities (fc_allocation_normalise). */
static fc_allocation_demand demand_make(const fc_allocation *a, float thrust_n, float mx, float my, float mz)
{
    return fc_allocation_normalise(a, from_f(thrust_n, FC_FORCE_FRAC),
                                   fc_vec3_make(from_f(mx, FC_MOMENT_FRAC), from_f(my, FC_MOMENT_FRAC),
                                                from_f(mz, FC_MOMENT_FRAC)));
}

/* Row k of a wrench [F_z; M_x; M_y; M_z] in N or N m. */
static float wrench_row(fc_real thrust_n, fc_vec3 moment_nm, int row)
{
    switch (row) {
    case 0:
        return to_f(thrust_n, FC_FORCE_FRAC);
    case 1:
        return to_f(moment_nm.x, FC_MOMENT_FRAC);
    case 2:
        return to_f(moment_nm.y, FC_MOMENT_FRAC);
    default:
        return to_f(moment_nm.z, FC_MOMENT_FRAC);
    }
}

static float achieved(const fc_allocation_output *out, int row)
{
    return wrench_row(out->thrust_n, out->moment_nm, row);
}

/* Row k of the physical value of the demand as passed (quantised to NORM16). */
static float demanded(const fc_allocation *a, const fc_allocation_demand *d, int row)
{
    fc_real thrust_n;
    fc_vec3 moment_nm;
    fc_allocation_physical(a, d, &thrust_n, &moment_nm);
    return wrench_row(thrust_n, moment_nm, row);
}

static float row_lsb(int row)
{
    return row == 0 ? 1.0f / 1048576.0f : 1.0f / 16777216.0f;
}

/* What a normalised 1 stands for on row k: F_max (FORCE) or the moment
 * authority (MOMENT), as the allocation holds it. */
static fc_real authority_of_row(const fc_allocation *a, int row)
{
    switch (row) {
    case 0:
        return a->thrust_max_n;
    case 1:
        return a->moment_authority_nm.x;
    case 2:
        return a->moment_authority_nm.y;
    default:
        return a->moment_authority_nm.z;
    }
}

/* sum_i |A_ki| in N or N m: F_max for F_z, twice the authority for a moment
 * (fc/allocation.h; in fixed within 1 LSB of the sum, the halving's rounding) */
static float row_abs_sum(const fc_allocation *a, int row)
{
    return row == 0 ? to_f(a->thrust_max_n, FC_FORCE_FRAC)
                    : 2.0f * to_f(authority_of_row(a, row), FC_MOMENT_FRAC);
}

/* |error| in the unit of the bounds: LSB in fixed, relative to sum_i |A_ki| in float */
static float error_units(const fc_allocation *a, int row, float error)
{
    return FIXED ? fabsf(error) / row_lsb(row) : fabsf(error) / row_abs_sum(a, row);
}

/* Fixed: the speed of a rotor with r = 2 is v's root to 16 bits
 * (fc_sqrt_unit16, within 2^-17), so the rotor's v = u^2 is met within 2^-16
 * and the wrench within 2^-16 of sum_i |A_ki|: in N or N m. */
static float speed_rounding(const fc_allocation *a, int row)
{
    return FIXED ? row_abs_sum(a, row) * (1.0f / 65536.0f) : 0.0f;
}

/* ---- the 16-bit step's roundings (fixed; fc/allocation.h, Formats) ------ */

/* Half an LSB of ROTOR16 (Q14), 2^-15: one 16-bit copy of a part R_i or Y_i
 * that the desaturation scales, or of a slack it compares. */
#define PART16_ROUNDING ldexp(1.0, -FC_ROTOR16_FRAC - 1)
/* Half an LSB of PINV16 (Q12), 2^-13: P's rounding to 16 bits at most. */
#define PINV16_ROUNDING ldexp(1.0, -FC_PINV16_FRAC - 1)

/* dp[k] = max_i |P_ik - pinv(B)_ik|: P as the step multiplies it (PINV16,
 * fc_allocation_pinv_normalised) against the pseudo-inverse of the
 * library's own B (fc_allocation_effectiveness_normalised) in double, by the
 * normal equations B^T (B B^T)^-1 (the tested geometries are well
 * conditioned). At most half a PINV16 LSB plus the 32-bit P's own error
 * (2 cond^2 LSB of MAT, oracle.allocation): 0 to 1e-7 for the quads' 1 and
 * 1/2, 1/3 of an LSB (8.1e-5) for the hexa's 1/3 and 2/3. Float: P's
 * rounding to float. */
static void pinv_rounding(const fc_allocation *a, double dp[4])
{
    fc_mat b, p;
    assert_int_equal(fc_allocation_effectiveness_normalised(a, &b), FC_MAT_OK);
    assert_int_equal(fc_allocation_pinv_normalised(a, &p), FC_MAT_OK);
    const int n = b.cols;
    double g[4][8]; /* [B B^T | I], reduced to [I | (B B^T)^-1] */
    for (int r = 0; r < 4; r++) {
        for (int c = 0; c < 4; c++) {
            double sum = 0.0;
            for (int i = 0; i < n; i++) {
                sum += exact(b.a[r][i], FC_MAT_FRAC) * exact(b.a[c][i], FC_MAT_FRAC);
            }
            g[r][c] = sum;
            g[r][4 + c] = r == c ? 1.0 : 0.0;
        }
    }
    for (int c = 0; c < 4; c++) {
        int pivot = c;
        for (int r = c + 1; r < 4; r++) {
            if (fabs(g[r][c]) > fabs(g[pivot][c])) {
                pivot = r;
            }
        }
        for (int j = 0; j < 8; j++) {
            const double t = g[c][j];
            g[c][j] = g[pivot][j];
            g[pivot][j] = t;
        }
        const double inv = 1.0 / g[c][c];
        for (int j = 0; j < 8; j++) {
            g[c][j] *= inv;
        }
        for (int r = 0; r < 4; r++) {
            if (r != c) {
                const double f = g[r][c];
                for (int j = 0; j < 8; j++) {
                    g[r][j] -= f * g[c][j];
                }
            }
        }
    }
    for (int k = 0; k < 4; k++) {
        dp[k] = 0.0;
        for (int i = 0; i < n; i++) {
            double want = 0.0;
            for (int r = 0; r < 4; r++) {
                want += exact(b.a[r][i], FC_MAT_FRAC) * g[r][4 + k];
            }
            dp[k] = fmax(dp[k], fabs(exact(p.a[i][k], FC_MAT_FRAC) - want));
        }
        if (FIXED) {
            assert_true(dp[k] <= PINV16_ROUNDING + 1e-6);
        }
    }
}

/* Fixed: how far a rotor's v can be from pinv(B) x for a demand with
 * |x_k| <= x_max[k] (normalised): the step forms v as the exact sum of the
 * products of P (PINV16) and x (NORM16), so P's rounding, sum_k dp_k
 * x_max_k; 4 LSB of RATIO (2^-24) for the 32-bit chain that made P (B and
 * its refined pseudo-inverse, as before the step was 16-bit); and `parts`
 * times a ROTOR16 rounding (2^-15) where the desaturation scaled or
 * compared a 16-bit copy. In units of v. */
static double v_error(const fc_allocation *a, const double x_max[4], int parts)
{
    double dp[4];
    pinv_rounding(a, dp);
    double e = 4.0 / 16777216.0 + parts * PART16_ROUNDING;
    for (int k = 0; k < 4; k++) {
        e += dp[k] * x_max[k];
    }
    return e;
}

/* The largest |x_k| of a demand, per axis (for v_error). */
static void demand_size(const fc_allocation_demand *d, double x_max[4])
{
    x_max[0] = fabs((double)norm_value(d->thrust));
    x_max[1] = fabs((double)norm_value(d->moment.x));
    x_max[2] = fabs((double)norm_value(d->moment.y));
    x_max[3] = fabs((double)norm_value(d->moment.z));
}

/* The bound of a round trip in the unit of error_units: fixed 8 LSB of the
 * output plus the error of v (v_error, in units of v) on every rotor, i.e.
 * v_error times the sum_i |A_ki| (the allocation resolves v, not the
 * wrench: a 4 kg hexa's 23 N m of sum_i |A_1i| makes that 6 LSB of MOMENT
 * per 2^-24 of v), plus the speeds' 16-bit roots (speed_rounding); float
 * relative. */
static float round_trip_bound(const fc_allocation *a, int row, float float_rel, double v_err)
{
    if (FIXED) {
        return 8.0f + ((float)v_err * row_abs_sum(a, row) + speed_rounding(a, row)) / row_lsb(row);
    }
    return float_rel;
}

/* Every output finite, speeds inside [u_min, 1] and zero above the count. */
static void assert_outputs_valid(const fc_allocation_params *p, const fc_allocation_output *out)
{
    for (int i = 0; i < FC_MAX_ROTORS; i++) {
        const float u = to_f(out->speed[i], FC_UNIT_FRAC);
        assert_true(isfinite(u));
        assert_true(isfinite(to_f(out->rotor_thrust_n[i], FC_FORCE_FRAC)));
        if (i < p->rotor_count) {
            assert_true(out->speed[i] >= p->rotor[i].speed_min);
            assert_true(out->speed[i] <= FC_INT(1, UNIT));
        } else {
            assert_true(out->speed[i] == FC_INT(0, UNIT));
        }
    }
    assert_true(isfinite(achieved(out, 0)) && isfinite(achieved(out, 1)) &&
                isfinite(achieved(out, 2)) && isfinite(achieved(out, 3)));
}

/* Random speeds whose v = u^r lie in [c - w, c + w], c the middle of [v_min, 1]
 * and w = spread * (1 - v_min) / 2 (r = 2 here). */
static void random_speeds(const fc_allocation_params *p, float spread, fc_real *speed)
{
    for (int i = 0; i < p->rotor_count; i++) {
        const float u_min = to_f(p->rotor[i].speed_min, FC_UNIT_FRAC);
        const float v_min = u_min * u_min;
        const float centre = 0.5f * (1.0f + v_min);
        const float half = spread * 0.5f * (1.0f - v_min);
        speed[i] = from_f(sqrtf(uniform(centre - half, centre + half)), FC_UNIT_FRAC);
    }
}

static fc_allocation_demand demand_of_speeds(fc_allocation *a, const fc_real *speed)
{
    fc_real thrust_n;
    fc_vec3 moment_nm;
    fc_allocation_forward(a, speed, &thrust_n, &moment_nm);
    return fc_allocation_normalise(a, thrust_n, moment_nm);
}

/* ---- init --------------------------------------------------------------- */

static void test_presets_init(void **state)
{
    (void)state;
    for (int k = 0; k < PRESET_COUNT; k++) {
        fc_allocation_params p;
        fc_allocation a;
        presets[k](&p);
        assert_int_equal(fc_allocation_init(&a, &p), FC_INIT_OK);
        assert_int_equal(a.ready, 1);
        /* hover at half of F_max: every rotor at the same speed, nothing saturated */
        const fc_allocation_demand d = demand_norm(0.5f, 0.0f, 0.0f, 0.0f);
        const float hover_n = demanded(&a, &d, 0);
        assert_true(fabsf(hover_n - 0.5f * row_abs_sum(&a, 0)) <= (FIXED ? row_lsb(0) : 1e-7f * hover_n));
        fc_allocation_output out;
        assert_int_equal(fc_allocation_step(&a, &d, &out), FC_STEP_OK);
        assert_int_equal(out.saturation, 0);
        assert_outputs_valid(&p, &out);
        for (int i = 1; i < p.rotor_count; i++) {
            assert_true(fabsf(to_f(out.speed[i], FC_UNIT_FRAC) - to_f(out.speed[0], FC_UNIT_FRAC)) <=
                        (FIXED ? 1e-7f : 1e-7f));
        }
        assert_true(fabsf(achieved(&out, 0) - hover_n) <=
                    (FIXED ? 4.0f * row_lsb(0) + speed_rounding(&a, 0) : 1e-6f * hover_n));
    }
}

static void test_crazyflie_effectiveness(void **state)
{
    (void)state;
    fc_allocation_params p;
    fc_allocation a;
    fc_allocation_preset_crazyflie2(&p);
    assert_int_equal(fc_allocation_init(&a, &p), FC_INIT_OK);
    fc_mat m;
    assert_int_equal(fc_allocation_effectiveness(&a, &m), FC_MAT_OK);
    assert_int_equal(m.rows, 4);
    assert_int_equal(m.cols, 4);
    const float arm = 0.046f * 0.70710678f;
    const float q = 0.12f * 0.00699f;
    /* M1 front-right, M2 back-right, M3 back-left, M4 front-left */
    const float want[4][4] = {{0.12f, 0.12f, 0.12f, 0.12f},
                              {-0.12f * arm, -0.12f * arm, 0.12f * arm, 0.12f * arm},
                              {-0.12f * arm, 0.12f * arm, 0.12f * arm, -0.12f * arm},
                              {-q, q, -q, q}};
    for (int k = 0; k < 4; k++) {
        for (int i = 0; i < 4; i++) {
            assert_true(fabsf(to_f(m.a[k][i], FC_MAT_FRAC) - want[k][i]) <= 2e-7f);
        }
    }
    /* row scales: powers of two with the largest entry of D A in (0.5, 1] */
    const float expect_scale[4] = {8.0f, 256.0f, 256.0f, 1024.0f};
    for (int k = 0; k < 4; k++) {
        assert_true(to_f(a.row_scale[k], FC_GAIN_FRAC) == expect_scale[k]);
        float largest = 0.0f;
        for (int i = 0; i < 4; i++) {
            largest = fmaxf(largest, fabsf(want[k][i]) * expect_scale[k]);
        }
        assert_true(largest > 0.5f && largest <= 1.0f);
    }
    /* B = N A: a symmetric quad's entries all share their row's magnitude, so
     * the thrust row is 1/4 (absolute sum 1) and the moment rows 1/2 (sum 2),
     * with the signs of A. Fixed: the entries of a row of D A are equal in
     * magnitude (the preset's coordinates are +-the same value), so
     * B = round(|DA| round(c / (4 |DA|))) is c/4 within |DA| 0.5 LSB (the
     * RATIO rounding of the row's 1/sum, |DA| <= 1) + 0.5 LSB (the product in
     * MAT): 1 LSB. Float: the sum (3 |DA| may round), the division and the
     * product: 3 eps of the entry, 4 eps allowed. */
    fc_mat n;
    assert_int_equal(fc_allocation_effectiveness_normalised(&a, &n), FC_MAT_OK);
    assert_int_equal(n.rows, 4);
    assert_int_equal(n.cols, 4);
    for (int k = 0; k < 4; k++) {
        const float size = k == 0 ? 0.25f : 0.5f;
        const float entry_tol = FIXED ? 1.0f / 16777216.0f : 4.0f * FLT_EPSILON * size;
        double row_sum = 0.0; /* exact in double */
        for (int i = 0; i < 4; i++) {
            const float b = to_f(n.a[k][i], FC_MAT_FRAC);
            const float expect = want[k][i] > 0.0f ? size : -size;
            assert_true(fabsf(b - expect) <= entry_tol);
            row_sum += fabs((double)b);
        }
        /* the absolute sums 1 (thrust) and 2 (moments): four entries' bounds */
        assert_true(fabs(row_sum - 4.0 * (double)size) <= 4.0 * (double)entry_tol);
    }
}

static fc_init_result init_planar(fc_allocation *a, int count, const float xy[][2],
                                  const float *torque_sign)
{
    fc_allocation_params p;
    fc_allocation_preset_f450(&p);
    p.rotor_count = (uint8_t)count;
    for (int i = 0; i < count; i++) {
        p.rotor[i] = p.rotor[0];
        p.rotor[i].position_m = fc_vec3_make(from_f(xy[i][0], FC_LENGTH_FRAC),
                                             from_f(xy[i][1], FC_LENGTH_FRAC), FC_INT(0, LENGTH));
        p.rotor[i].torque_max_nm = from_f(0.128f * torque_sign[i], FC_MOMENT_FRAC);
    }
    return fc_allocation_init(a, &p);
}

static void test_rank_deficient(void **state)
{
    (void)state;
    fc_allocation a;
    const float alternate[6] = {1.0f, -1.0f, 1.0f, -1.0f, 1.0f, -1.0f};
    const float same[4] = {1.0f, 1.0f, 1.0f, 1.0f};
    /* all rotors on the body x axis: no roll moment */
    const float on_x[4][2] = {{-0.3f, 0.0f}, {-0.1f, 0.0f}, {0.1f, 0.0f}, {0.3f, 0.0f}};
    assert_int_equal(init_planar(&a, 4, on_x, alternate), FC_INIT_RANK_DEFICIENT);
    assert_int_equal(a.ready, 0);
    /* all on the diagonal y = x: M_x = -M_y, the rows are dependent (not zero) */
    const float diagonal[4][2] = {{-0.3f, -0.3f}, {-0.1f, -0.1f}, {0.1f, 0.1f}, {0.3f, 0.3f}};
    assert_int_equal(init_planar(&a, 4, diagonal, alternate), FC_INIT_RANK_DEFICIENT);
    /* quad-X with one spin direction: the yaw row is the thrust row times Q/T */
    const float quad[4][2] = {{0.16f, -0.16f}, {-0.16f, -0.16f}, {-0.16f, 0.16f}, {0.16f, 0.16f}};
    assert_int_equal(init_planar(&a, 4, quad, same), FC_INIT_RANK_DEFICIENT);
    assert_int_equal(init_planar(&a, 4, quad, alternate), FC_INIT_OK);
    /* three rotors: rank 3 at most */
    const float tri[3][2] = {{0.2f, 0.0f}, {-0.1f, 0.17f}, {-0.1f, -0.17f}};
    assert_int_equal(init_planar(&a, 3, tri, alternate), FC_INIT_RANK_DEFICIENT);
    /* coaxial only: six rotors stacked on the z axis */
    fc_allocation_params p;
    fc_allocation_preset_hexa_x_4kg(&p);
    for (int i = 0; i < 6; i++) {
        p.rotor[i].position_m = fc_vec3_make(FC_INT(0, LENGTH), FC_INT(0, LENGTH),
                                             from_f(0.05f * (float)i - 0.1f, FC_LENGTH_FRAC));
    }
    assert_int_equal(fc_allocation_init(&a, &p), FC_INIT_RANK_DEFICIENT);
    /* not ready: motors stopped (whatever the demand: half of F_max here) */
    fc_allocation_output out;
    const fc_allocation_demand d = demand_norm(0.5f, 0.0f, 0.0f, 0.0f);
    assert_int_equal(fc_allocation_step(&a, &d, &out), FC_STEP_NOT_READY);
    for (int i = 0; i < FC_MAX_ROTORS; i++) {
        assert_true(out.speed[i] == FC_INT(0, UNIT));
    }
    fc_mat m;
    assert_int_equal(fc_allocation_effectiveness(&a, &m), FC_MAT_BAD_SIZE);
    assert_int_equal(m.rows, 0);
}

static void expect_bad(const fc_allocation_params *p)
{
    fc_allocation a;
    assert_int_equal(fc_allocation_init(&a, p), FC_INIT_BAD_PARAM);
    assert_int_equal(a.ready, 0);
    fc_allocation_output out;
    const fc_allocation_demand d = demand_norm(0.5f, 0.0f, 0.0f, 0.0f);
    assert_int_equal(fc_allocation_step(&a, &d, &out), FC_STEP_NOT_READY);
    for (int i = 0; i < FC_MAX_ROTORS; i++) {
        assert_true(out.speed[i] == FC_INT(0, UNIT));
        assert_true(out.rotor_thrust_n[i] == FC_INT(0, FORCE));
    }
}

static void test_bad_params(void **state)
{
    (void)state;
    fc_allocation_params good;
    fc_allocation_params p;
    fc_allocation a;
    fc_allocation_preset_f450(&good);
    assert_int_equal(fc_allocation_init(&a, &good), FC_INIT_OK);
    assert_int_equal(fc_allocation_init(&a, NULL), FC_INIT_BAD_PARAM);
    assert_int_equal(fc_allocation_init(NULL, &good), FC_INIT_BAD_PARAM);

    p = good;
    p.rotor_count = 0u;
    expect_bad(&p);
    p = good;
    p.rotor_count = FC_MAX_ROTORS + 1u;
    expect_bad(&p);
    p = good;
    p.newton_iterations = FC_ALLOCATION_MAX_ITERATIONS + 1u;
    expect_bad(&p);
    p = good;
    p.rotor[2].axis_unit = fc_vec3_make(FC_INT(0, UNIT), FC_INT(0, UNIT), FC_C(0.99f, UNIT));
    expect_bad(&p);
    p = good;
    p.rotor[1].axis_unit = fc_vec3_zero();
    expect_bad(&p);
    p = good;
    p.rotor[3].thrust_max_n = FC_INT(0, FORCE);
    expect_bad(&p);
    p = good;
    p.rotor[3].thrust_max_n = FC_C(-1.0f, FORCE);
    expect_bad(&p);
    p = good;
    p.rotor[0].thrust_exponent = FC_C(0.5f, RATIO);
    expect_bad(&p);
    p = good;
    p.rotor[0].thrust_exponent = FC_C(4.01f, RATIO);
    expect_bad(&p);
    p = good;
    p.rotor[1].torque_exponent = FC_C(0.4f, RATIO);
    expect_bad(&p);
    p = good;
    p.rotor[1].torque_exponent = FC_C(4.5f, RATIO);
    expect_bad(&p);
    p = good;
    p.rotor[2].speed_min = FC_INT(1, UNIT);
    expect_bad(&p);
    p = good;
    p.rotor[2].speed_min = FC_C(-0.01f, UNIT);
    expect_bad(&p);
    p = good;
    p.rotor[0].position_m.x = FC_C(20.0f, LENGTH);
    expect_bad(&p);
    /* F_max below 1/16 N (1 / F_max must fit PER_FORCE): four 0.0155 N rotors
     * give 0.062 N; four 0.016 N rotors, 0.064 N, are fine */
    fc_allocation_preset_crazyflie2(&p);
    for (int i = 0; i < 4; i++) {
        p.rotor[i].thrust_max_n = FC_C(0.0155f, FORCE);
    }
    expect_bad(&p);
    for (int i = 0; i < 4; i++) {
        p.rotor[i].thrust_max_n = FC_C(0.016f, FORCE);
    }
    assert_int_equal(fc_allocation_init(&a, &p), FC_INIT_OK);
    /* exponents at the edges of (0.5, 4] are fine */
    p = good;
    p.rotor[0].thrust_exponent = FC_C(4.0f, RATIO);
    p.rotor[1].torque_exponent = FC_C(0.51f, RATIO);
    assert_int_equal(fc_allocation_init(&a, &p), FC_INIT_OK);
#if !FC_NUMERIC_FIXED
    p = good;
    p.rotor[1].position_m.y = NAN;
    expect_bad(&p);
    p = good;
    p.rotor[2].torque_max_nm = INFINITY;
    expect_bad(&p);
    p = good;
    p.rotor[3].speed_min = NAN;
    expect_bad(&p);
    p = good;
    p.rotor[0].thrust_exponent = NAN;
    expect_bad(&p);
#endif
}

/* ---- round trips -------------------------------------------------------- */

/* Worst error per row over `cases` feasible random demands; cold = reset the
 * warm start before every step. Returns the bound's v_error (fixed). */
static double round_trip(const fc_allocation_params *p, int cases, float spread, bool cold,
                         float worst[4], int *saturated_steps, float bound[4])
{
    fc_allocation a;
    assert_int_equal(fc_allocation_init(&a, p), FC_INIT_OK);
    double x_max[4] = {0.0, 0.0, 0.0, 0.0}; /* the largest |x_k| passed */
    for (int k = 0; k < 4; k++) {
        worst[k] = 0.0f;
    }
    *saturated_steps = 0;
    for (int c = 0; c < cases; c++) {
        fc_real speed[FC_MAX_ROTORS];
        random_speeds(p, spread, speed);
        const fc_allocation_demand d = demand_of_speeds(&a, speed);
        double size[4];
        demand_size(&d, size);
        for (int k = 0; k < 4; k++) {
            x_max[k] = fmax(x_max[k], size[k]);
        }
        if (cold) {
            fc_allocation_reset(&a);
        }
        fc_allocation_output out;
        const fc_step_status status = fc_allocation_step(&a, &d, &out);
        assert_int_equal(status & (fc_step_status)~FC_STEP_OUTPUT_LIMITED, FC_STEP_OK);
        assert_outputs_valid(p, &out);
        if (out.saturation != 0u) {
            (*saturated_steps)++;
        }
        for (int k = 0; k < 4; k++) {
            worst[k] = fmaxf(worst[k], error_units(&a, k, achieved(&out, k) - demanded(&a, &d, k)));
        }
    }
    /* r != s: the step allocates x - N delta(v) (planar rotors: along z),
     * |N delta| <= sum_i |N Q_max,i| max_v |v^(s/r) - v| = 2 max_v |...| */
    double excess = 0.0;
    for (int i = 0; i < p->rotor_count; i++) {
        const double ratio = exact(p->rotor[i].torque_exponent, FC_RATIO_FRAC) /
                             exact(p->rotor[i].thrust_exponent, FC_RATIO_FRAC);
        for (int j = 1; j <= 1000; j++) {
            const double v = j / 1000.0;
            excess = fmax(excess, fabs(pow(v, ratio) - v));
        }
    }
    x_max[3] += 2.0 * (excess + 0.001); /* on a 1e-3 grid: the slope is 0 at the maximum, 1e-3 is ample */
    const double v_err = v_error(&a, x_max, 0);
    for (int k = 0; k < 4; k++) {
        bound[k] = round_trip_bound(&a, k, 1e-6f, v_err);
    }
    return v_err;
}

static void test_round_trip_r_equals_s(void **state)
{
    (void)state;
    /* measured (fixed, LSB of F_z/M_x/M_y/M_z; the speeds' 16-bit roots
     * dominate, and the hexa's P rounded to PINV16): crazyflie 6/3/3/2, f450
     * 342/825/891/93, hexa 732/3650/3180/464 (bounds 16/12/12/8.9,
     * 528/1330/1330/141, 3050/14600/12700/787, i.e. 2^-16 of sum_i |A_ki|,
     * a few LSB, and for the hexa P's rounding, 1/3 of a PINV16 LSB on its
     * 1/3 and 2/3, times the largest demand); float, relative to
     * sum_i |A_ki|: below 2e-7 (bound 1e-6) */
    rng_seed(0x0A110C01u);
    for (int k = 0; k < PRESET_COUNT; k++) {
        fc_allocation_params p;
        presets[k](&p);
        /* the hexa's least-norm solution is a projection of the random v: a
         * narrower spread keeps it inside the bounds */
        const float spread = p.rotor_count == 4 ? 0.9f : 0.35f;
        float worst[4], bound[4];
        int saturated;
        round_trip(&p, 2000, spread, false, worst, &saturated, bound);
        print_message("round trip r=s %-11s worst F_z %.3g M_x %.3g M_y %.3g M_z %.3g %s "
                      "(bounds %.3g %.3g %.3g %.3g)\n",
                      preset_names[k], (double)worst[0], (double)worst[1], (double)worst[2],
                      (double)worst[3], FIXED ? "LSB" : "rel", (double)bound[0], (double)bound[1],
                      (double)bound[2], (double)bound[3]);
        assert_int_equal(saturated, 0);
        for (int r = 0; r < 4; r++) {
            assert_true(worst[r] <= bound[r]);
        }
    }
}

static void test_round_trip_other_exponents(void **state)
{
    (void)state;
    /* r = s != 2 (u = v^(1/r) through fc_pow_unit), linear in v = u^r */
    rng_seed(0x0A110C06u);
    const float exponents[2] = {1.5f, 3.0f};
    for (int e = 0; e < 2; e++) {
        fc_allocation_params p;
        fc_allocation_preset_f450(&p);
        for (int i = 0; i < 4; i++) {
            p.rotor[i].thrust_exponent = from_f(exponents[e], FC_RATIO_FRAC);
            p.rotor[i].torque_exponent = from_f(exponents[e], FC_RATIO_FRAC);
        }
        float worst[4], bound[4];
        int saturated;
        round_trip(&p, 1000, 0.6f, false, worst, &saturated, bound);
        print_message("round trip r=s=%.1f f450 worst F_z %.3g M_x %.3g M_y %.3g M_z %.3g %s\n",
                      (double)exponents[e], (double)worst[0], (double)worst[1], (double)worst[2],
                      (double)worst[3], FIXED ? "LSB" : "rel");
        assert_int_equal(saturated, 0);
        for (int r = 0; r < 4; r++) {
            assert_true(worst[r] <= (FIXED ? 4.0f : 1.0f) * bound[r]);
        }
    }
}

static void test_round_trip_quad_speeds_unique(void **state)
{
    (void)state;
    /* a quad's A is square: the allocation must return the speeds that made
     * the demand. The demand passed is the generating wrench rounded to NORM16
     * (up to 2^-15 per axis; through P, |P_i0| = 1 and |P_ik| = 1/2, that moves
     * v by up to 7.6e-5 and u by up to 1.4e-4 at the lowest speed drawn, 7x
     * the bound): the speeds that make the demand passed are the generating
     * ones moved by P times that rounding, v = u_gen^2 + P (x - w / authority).
     * P is the library's (fc_allocation_pinv_normalised), used only to carry
     * the rounding: its own error, 1e-7 relative (the F450's 1 and 1/2 are
     * exact in PINV16), is 1e-11 of v there. */
    rng_seed(0x0A110C02u);
    fc_allocation_params p;
    fc_allocation a;
    fc_allocation_preset_f450(&p);
    assert_int_equal(fc_allocation_init(&a, &p), FC_INIT_OK);
    fc_mat pinv;
    assert_int_equal(fc_allocation_pinv_normalised(&a, &pinv), FC_MAT_OK);
    float worst = 0.0f;
    double worst_shift = 0.0;
    for (int c = 0; c < 1000; c++) {
        fc_real speed[FC_MAX_ROTORS];
        random_speeds(&p, 0.9f, speed);
        fc_real thrust_n;
        fc_vec3 moment_nm;
        fc_allocation_forward(&a, speed, &thrust_n, &moment_nm);
        const fc_allocation_demand d = fc_allocation_normalise(&a, thrust_n, moment_nm);
        const fc_real w[4] = {thrust_n, moment_nm.x, moment_nm.y, moment_nm.z};
        const fc_real16 x[4] = {d.thrust, d.moment.x, d.moment.y, d.moment.z};
        double rounding[4];
        for (int k = 0; k < 4; k++) {
            const int frac = k == 0 ? FC_FORCE_FRAC : FC_MOMENT_FRAC;
            rounding[k] = (double)norm_value(x[k]) - exact(w[k], frac) / exact(authority_of_row(&a, k), frac);
        }
        fc_allocation_output out;
        (void)fc_allocation_step(&a, &d, &out);
        for (int i = 0; i < 4; i++) {
            const double u_gen = exact(speed[i], FC_UNIT_FRAC);
            double v = u_gen * u_gen;
            for (int k = 0; k < 4; k++) {
                v += exact(pinv.a[i][k], FC_MAT_FRAC) * rounding[k];
            }
            const double u_want = sqrt(v);
            worst_shift = fmax(worst_shift, fabs(u_want - u_gen));
            worst = fmaxf(worst, (float)fabs(exact(out.speed[i], FC_UNIT_FRAC) - u_want));
        }
    }
    print_message("quad speeds recovered: worst |u - u_want| %.3g (the NORM16 rounding moved u_gen by up to "
                  "%.3g)\n",
                  (double)worst, worst_shift);
    assert_true(worst <= (FIXED ? 2e-5f : 2e-6f));
}

/* A hexa with its rotors tilted 15 deg sideways, alternately (a 3-fold
 * symmetric pattern that adds yaw authority) and the whole frame's rotors
 * 10 deg forward: the body-x force is the by-product. */
static void tilted_hexa(fc_allocation_params *p)
{
    fc_allocation_preset_hexa_x_4kg(p);
    const float tilt = 0.25881905f;    /* sin 15 deg, tangential */
    const float forward = 0.17364818f; /* sin 10 deg */
    for (int i = 0; i < 6; i++) {
        const float x = to_f(p->rotor[i].position_m.x, FC_LENGTH_FRAC);
        const float y = to_f(p->rotor[i].position_m.y, FC_LENGTH_FRAC);
        const float r = sqrtf(x * x + y * y);
        const float sign = (i % 2 == 0) ? 1.0f : -1.0f;
        /* tangential direction (-y, x)/r */
        float d[3] = {-sign * tilt * y / r + forward, sign * tilt * x / r, 1.0f};
        const float norm = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        p->rotor[i].axis_unit = fc_vec3_make(from_f(d[0] / norm, FC_UNIT_FRAC),
                                             from_f(d[1] / norm, FC_UNIT_FRAC),
                                             from_f(d[2] / norm, FC_UNIT_FRAC));
    }
}

static void test_round_trip_tilted(void **state)
{
    (void)state;
    rng_seed(0x0A110C03u);
    fc_allocation_params p;
    tilted_hexa(&p);
    float worst[4], bound[4];
    int saturated;
    round_trip(&p, 2000, 0.35f, false, worst, &saturated, bound);
    print_message("round trip tilted hexa worst F_z %.3g M_x %.3g M_y %.3g M_z %.3g %s\n",
                  (double)worst[0], (double)worst[1], (double)worst[2], (double)worst[3],
                  FIXED ? "LSB" : "rel");
    assert_int_equal(saturated, 0);
    for (int r = 0; r < 4; r++) {
        assert_true(worst[r] <= bound[r]);
    }
    /* the by-product: the body-x force, sum T_i d_i over the rotors */
    fc_allocation a;
    assert_int_equal(fc_allocation_init(&a, &p), FC_INIT_OK);
    fc_allocation_output out;
    const fc_allocation_demand d = demand_make(&a, 40.0f, 0.0f, -3.0f, 0.0f);
    assert_int_equal(fc_allocation_step(&a, &d, &out), FC_STEP_OK);
    fc_vec3 force, moment;
    fc_allocation_forward_wrench(&a, out.speed, &force, &moment);
    float want[3] = {0.0f, 0.0f, 0.0f};
    for (int i = 0; i < 6; i++) {
        const float t = to_f(out.rotor_thrust_n[i], FC_FORCE_FRAC);
        want[0] += t * to_f(p.rotor[i].axis_unit.x, FC_UNIT_FRAC);
        want[1] += t * to_f(p.rotor[i].axis_unit.y, FC_UNIT_FRAC);
        want[2] += t * to_f(p.rotor[i].axis_unit.z, FC_UNIT_FRAC);
    }
    print_message("tilted hexa, pitch -3 N m at 40 N: by-product force (%.4g, %.4g) N\n",
                  (double)to_f(force.x, FC_FORCE_FRAC), (double)to_f(force.y, FC_FORCE_FRAC));
    assert_true(force.z == out.thrust_n);
    assert_true(moment.x == out.moment_nm.x && moment.y == out.moment_nm.y && moment.z == out.moment_nm.z);
    assert_true(fabsf(to_f(force.x, FC_FORCE_FRAC) - want[0]) <= 1e-5f);
    assert_true(fabsf(to_f(force.y, FC_FORCE_FRAC) - want[1]) <= 1e-5f);
    assert_true(fabsf(to_f(force.z, FC_FORCE_FRAC) - want[2]) <= 1e-5f);
    assert_true(to_f(force.x, FC_FORCE_FRAC) > 5.0f);
}

/* r and s on every rotor, and the passes of the correction. */
static void with_exponents(fc_allocation_params *p, float r, float s, int iterations)
{
    for (int i = 0; i < p->rotor_count; i++) {
        p->rotor[i].thrust_exponent = from_f(r, FC_RATIO_FRAC);
        p->rotor[i].torque_exponent = from_f(s, FC_RATIO_FRAC);
    }
    p->newton_iterations = (uint8_t)iterations;
}

static void with_torque_exponent(fc_allocation_params *p, float s, int iterations)
{
    with_exponents(p, 2.0f, s, iterations);
}

/* Worst |M_z - M_z,d| / sum|Q_max| over feasible random demands, cold start
 * (the warm start reset before every step), per number of passes; F_z, M_x and
 * M_y must stay within the r = s bounds (planar rotors: the correction is
 * along z). Returns nothing; asserts the bounds and that every pass helps. */
static void r_not_s_case(float r_exp, float s_exp, const float *bound_yaw)
{
    for (int k = 0; k < PRESET_COUNT; k++) {
        float previous = 1.0f;
        for (int n_iter = 0; n_iter <= FC_ALLOCATION_MAX_ITERATIONS; n_iter++) {
            fc_allocation_params p;
            presets[k](&p);
            with_exponents(&p, r_exp, s_exp, n_iter);
            rng_seed(0x0A110C04u);
            float worst[4], bound[4];
            int saturated;
            const float spread = p.rotor_count == 4 ? 0.6f : 0.25f;
            const double v_err = round_trip(&p, 1000, spread, true, worst, &saturated, bound);
            fc_allocation a;
            assert_int_equal(fc_allocation_init(&a, &p), FC_INIT_OK);
            float yaw_authority = 0.0f;
            for (int i = 0; i < p.rotor_count; i++) {
                yaw_authority += fabsf(to_f(p.rotor[i].torque_max_nm, FC_MOMENT_FRAC));
            }
            /* back from the error unit to N m, then relative to sum |Q_max| */
            const float yaw_nm = FIXED ? worst[3] * row_lsb(3) : worst[3] * row_abs_sum(&a, 3);
            const float yaw_rel = yaw_nm / yaw_authority;
            /* fixed: nothing below 4 LSB of MOMENT, nor below the speeds'
             * roots (r = 2: u within 2^-17, Q_max u^s within s 2^-17 Q_max;
             * otherwise fc_pow_unit, a few 1e-7 on u and on the correction's
             * v^(s/r): 1e-6), the error of v (v_error, relative to sum_i
             * |A_3i| = sum |Q_max|) and the corrected demand's rounding to
             * NORM16 (half an LSB, 2^-15, of the yaw authority: 2^-16 of
             * sum |Q_max|) */
            const float floor_rel =
                FIXED ? 4.0f * row_lsb(3) / yaw_authority + (r_exp == 2.0f ? s_exp * (1.0f / 131072.0f) : 1e-6f) +
                            (float)v_err + 0.5f * (float)ldexp(1.0, -FC_NORM16_FRAC - 1)
                      : 0.0f;
            print_message("r=%.1f s=%.1f %-11s passes %d: worst yaw residual %.3g of sum|Q_max| "
                          "(bound %.3g; F_z %.3g M_x %.3g M_y %.3g %s)\n",
                          (double)r_exp, (double)s_exp, preset_names[k], n_iter, (double)yaw_rel,
                          (double)fmaxf(bound_yaw[n_iter], floor_rel), (double)worst[0],
                          (double)worst[1], (double)worst[2], FIXED ? "LSB" : "rel");
            assert_int_equal(saturated, 0);
            assert_true(yaw_rel <= fmaxf(bound_yaw[n_iter], floor_rel));
            assert_true(yaw_rel <= fmaxf(previous, floor_rel));
            previous = yaw_rel;
            for (int r = 0; r < 3; r++) {
                assert_true(worst[r] <= bound[r]);
            }
        }
    }
}

static void test_round_trip_r_not_s(void **state)
{
    (void)state;
    /* measured (float), crazyflie / f450 / hexa:
     *   0 passes 1.3e-2 / 1.2e-2 / 3.7e-3, 1: 9.4e-4 / 7.9e-4 / 1.8e-4,
     *   2: 7.1e-5 / 6.0e-5 / 8.4e-6,       3: 6.4e-6 / 5.3e-6 / 4.6e-7,
     *   4: 6.0e-7 / 4.5e-7 / 6.5e-8 (fixed: the same down to 2 LSB of MOMENT) */
    const float bound_yaw[FC_ALLOCATION_MAX_ITERATIONS + 1] = {2.5e-2f, 2e-3f, 1.5e-4f, 1.5e-5f,
                                                               1.5e-6f};
    r_not_s_case(2.0f, 2.3f, bound_yaw);
}

static void test_round_trip_r_not_s_pow(void **state)
{
    (void)state;
    /* neither exponent 2 (fc_pow_unit everywhere), s < r */
    const float bound_yaw[FC_ALLOCATION_MAX_ITERATIONS + 1] = {5e-2f, 5e-3f, 5e-4f, 5e-5f, 5e-6f};
    r_not_s_case(2.2f, 1.8f, bound_yaw);
}

static void test_r_not_s_warm_start(void **state)
{
    (void)state;
    /* a slowly varying demand (a 1 Hz wobble at 500 Hz) with one pass per step:
     * the warm start makes it two */
    fc_allocation_params p;
    fc_allocation a;
    fc_allocation_preset_f450(&p);
    with_torque_exponent(&p, 2.3f, 1);
    assert_int_equal(fc_allocation_init(&a, &p), FC_INIT_OK);
    float worst = 0.0f;
    for (int step = 0; step < 1000; step++) {
        const float phase = 6.2831853f * (float)step / 500.0f;
        const fc_allocation_demand d =
            demand_make(&a, 16.0f + 3.0f * sinf(phase), 0.3f * sinf(phase), 0.2f * cosf(phase),
                        0.15f * sinf(0.5f * phase));
        fc_allocation_output out;
        assert_int_equal(fc_allocation_step(&a, &d, &out), FC_STEP_OK);
        if (step >= 10) {
            worst = fmaxf(worst, fabsf(achieved(&out, 3) - demanded(&a, &d, 3)));
        }
    }
    const float rel = worst / (4.0f * 0.128f);
    print_message("r=2 s=2.3 f450, 1 pass, warm-started sequence: worst yaw residual %.3g of "
                  "sum|Q_max|\n",
                  (double)rel);
    assert_true(rel <= 2e-4f);
}

/* ---- saturation priorities ---------------------------------------------- */

/* A fresh Crazyflie allocation: the demands are normalised by its authorities. */
static void crazyflie(fc_allocation *a, fc_allocation_params *p)
{
    fc_allocation_preset_crazyflie2(p);
    assert_int_equal(fc_allocation_init(a, p), FC_INIT_OK);
}

/* One step of a freshly initialised Crazyflie allocation. */
static void step_crazyflie(fc_allocation *a, const fc_allocation_demand *d, fc_allocation_output *out,
                           fc_step_status *status)
{
    fc_allocation_params p;
    crazyflie(a, &p);
    *status = fc_allocation_step(a, d, out);
    assert_outputs_valid(&p, out);
    assert_int_equal(*status & FC_STEP_ARITH_SATURATED, 0);
}

/* The demand is inside NORM16's +-1.99 (not clamped by fc_allocation_normalise),
 * so what the step gives up is the allocation's doing. */
static void assert_not_clamped(const fc_allocation_demand *d)
{
    assert_true(fabsf(norm_value(d->thrust)) < 1.98f && fabsf(norm_value(d->moment.x)) < 1.98f &&
                fabsf(norm_value(d->moment.y)) < 1.98f && fabsf(norm_value(d->moment.z)) < 1.98f);
}

/* some rotor at a bound: the axis that gave way gave no more than it had to.
 * v_tol (fixed): how far inside its bound the step may leave that rotor's v
 * (the scale that gave way is rounded down, so that what it scales fits);
 * in u that is at most v_tol / (2 u) (u = v^(1/2), u >= u_min) plus the
 * root's 2^-17. Float: 1e-5. */
static bool some_rotor_at_bound(const fc_allocation_output *out, double v_tol)
{
    const float u_min = 0.32659863f;
    const float tol = FIXED ? (float)(v_tol / (2.0 * (double)u_min)) + 1.0f / 131072.0f : 1e-5f;
    for (int i = 0; i < 4; i++) {
        const float u = to_f(out->speed[i], FC_UNIT_FRAC);
        if (u >= 1.0f - tol || u <= u_min + tol) {
            return true;
        }
    }
    return false;
}

/* The largest (or smallest) |P_ik| of a column (P16 as the step multiplies it). */
static double pinv_column_size(const fc_allocation *a, int k, bool largest)
{
    fc_mat p;
    assert_int_equal(fc_allocation_pinv_normalised(a, &p), FC_MAT_OK);
    double m = fabs(exact(p.a[0][k], FC_MAT_FRAC));
    for (int i = 1; i < p.rows; i++) {
        const double size = fabs(exact(p.a[i][k], FC_MAT_FRAC));
        m = largest ? fmax(m, size) : fmin(m, size);
    }
    return m;
}

/* How far an axis that is kept may be from the demand when a lower one gave
 * way (N or N m): fixed 8 LSB of the output, plus the error of v (v_error
 * for this demand) with one ROTOR16 rounding (the 16-bit Y_i that b scales,
 * or the R_i in the rate that bounds the shifted collective: its rotor ends
 * within that of its bound, and the final clamp moves it no further), and
 * the roots' 2^-16, all times sum_i |A_ki|; float as before the step was
 * 16-bit. */
static float kept_tolerance(const fc_allocation *a, const fc_allocation_demand *d, int row)
{
    if (!FIXED) {
        return row == 0 ? 1e-6f : 1e-8f;
    }
    double x_max[4];
    demand_size(d, x_max);
    return 8.0f * row_lsb(row) + (float)v_error(a, x_max, 1) * row_abs_sum(a, row) + speed_rounding(a, row);
}

static void test_saturation_yaw(void **state)
{
    (void)state;
    fc_allocation a;
    fc_allocation_params p;
    crazyflie(&a, &p);
    /* Crazyflie at 0.3 N with a small roll: about 1.3e-3 N m of yaw is possible */
    const fc_allocation_demand d = demand_make(&a, 0.3f, 0.001f, -0.0005f, 0.003f);
    assert_not_clamped(&d);
    fc_allocation_output out;
    fc_step_status status;
    step_crazyflie(&a, &d, &out, &status);
    assert_int_equal(out.saturation, FC_SAT_YAW_POS);
    assert_true((status & FC_STEP_OUTPUT_LIMITED) != 0u);
    for (int r = 0; r < 3; r++) {
        assert_true(fabsf(achieved(&out, r) - demanded(&a, &d, r)) <= kept_tolerance(&a, &d, r));
    }
    assert_true(achieved(&out, 3) > 0.0005f && achieved(&out, 3) < 0.003f);
    /* b is rounded down (less than 2^-14 short of the largest that fits),
     * the slack and Y_i rounded to ROTOR16 (2^-15 each): the rotor that
     * limits b ends within 2^-14 (|Y_i| + 1) of its bound */
    const double yaw_part = pinv_column_size(&a, 3, true) * fabs((double)norm_value(d.moment.z));
    assert_true(some_rotor_at_bound(&out, ldexp(yaw_part, -FC_UNIT16_FRAC) + 2.0 * PART16_ROUNDING));
    /* near full thrust: yaw gives way before the thrust does */
    const fc_allocation_demand top = demand_make(&a, 0.46f, 0.0f, 0.0f, 0.001f);
    step_crazyflie(&a, &top, &out, &status);
    assert_int_equal(out.saturation, FC_SAT_YAW_POS);
    for (int r = 0; r < 3; r++) {
        assert_true(fabsf(achieved(&out, r) - demanded(&a, &top, r)) <= kept_tolerance(&a, &top, r));
    }
    assert_true(achieved(&out, 3) > 0.0f && achieved(&out, 3) < 0.001f);
    /* the other way (-0.003 N m: -1.79 of the yaw authority) */
    const fc_allocation_demand d2 = demand_make(&a, 0.3f, 0.0f, 0.0f, -0.003f);
    assert_not_clamped(&d2);
    step_crazyflie(&a, &d2, &out, &status);
    assert_int_equal(out.saturation, FC_SAT_YAW_NEG);
    assert_true(achieved(&out, 3) < -0.0005f);
}

static void test_saturation_thrust(void **state)
{
    (void)state;
    fc_allocation a;
    fc_allocation_params p;
    crazyflie(&a, &p);
    /* more than 4 x 0.12 N (1.46 F_max): thrust down to what fits, the moments kept */
    const fc_allocation_demand high = demand_make(&a, 0.7f, 0.0005f, -0.0007f, 0.0f);
    assert_not_clamped(&high);
    fc_allocation_output out;
    fc_step_status status;
    step_crazyflie(&a, &high, &out, &status);
    assert_int_equal(out.saturation, FC_SAT_THRUST_HIGH);
    assert_true((status & FC_STEP_OUTPUT_LIMITED) != 0u);
    assert_true(achieved(&out, 0) < 0.48f && achieved(&out, 0) > 0.4f);
    for (int r = 1; r < 4; r++) {
        assert_true(fabsf(achieved(&out, r) - demanded(&a, &high, r)) <= kept_tolerance(&a, &high, r));
    }
    /* t to 32 bits and q_i = 1 (exact): the rotor that bounds the collective
     * ends within its R_i's ROTOR16 rounding of its bound */
    assert_true(some_rotor_at_bound(&out, PART16_ROUNDING));
    /* within the thrust range but not with this moment: the thrust shifts down */
    const fc_allocation_demand near_top = demand_make(&a, 0.46f, 0.002f, 0.0f, 0.0f);
    step_crazyflie(&a, &near_top, &out, &status);
    assert_int_equal(out.saturation, FC_SAT_THRUST_HIGH);
    assert_true(fabsf(achieved(&out, 1) - demanded(&a, &near_top, 1)) <= kept_tolerance(&a, &near_top, 1));
    /* zero thrust demanded with a pitch moment: the thrust shifts up */
    const fc_allocation_demand low = demand_make(&a, 0.0f, 0.0f, 0.001f, 0.0f);
    step_crazyflie(&a, &low, &out, &status);
    assert_int_equal(out.saturation, FC_SAT_THRUST_LOW);
    assert_true(achieved(&out, 0) > 0.05f);
    for (int r = 1; r < 4; r++) {
        assert_true(fabsf(achieved(&out, r) - demanded(&a, &low, r)) <= kept_tolerance(&a, &low, r));
    }
    assert_true(some_rotor_at_bound(&out, PART16_ROUNDING));
}

static void test_saturation_roll_pitch(void **state)
{
    (void)state;
    fc_allocation a;
    fc_allocation_params p;
    crazyflie(&a, &p);
    /* far more roll and pitch than the Crazyflie has (1.92 and 0.96 of the
     * authority of 7.8e-3 N m: inside NORM16, so the direction of the demand
     * passed is (2, 1)), with some yaw: yaw gives way entirely, the thrust
     * moves to where roll/pitch get the most, and roll/pitch are scaled
     * together */
    const fc_allocation_demand d = demand_make(&a, 0.3f, 0.015f, 0.0075f, 0.0005f);
    assert_not_clamped(&d);
    fc_allocation_output out;
    fc_step_status status;
    step_crazyflie(&a, &d, &out, &status);
    assert_true((out.saturation & (FC_SAT_ROLL_POS | FC_SAT_PITCH_POS)) ==
                (FC_SAT_ROLL_POS | FC_SAT_PITCH_POS));
    assert_true((out.saturation & FC_SAT_YAW_POS) != 0u);
    assert_true((out.saturation & (FC_SAT_ROLL_NEG | FC_SAT_PITCH_NEG | FC_SAT_YAW_NEG)) == 0u);
    const float mx = achieved(&out, 1), my = achieved(&out, 2);
    const float dx = demanded(&a, &d, 1), dy = demanded(&a, &d, 2);
    assert_true(mx > 0.003f && mx < dx);
    /* direction kept: (mx, my) parallel to the demand passed (dx, dy) */
    const float cross = mx * dy - my * dx;
    const float sine = cross / (sqrtf(mx * mx + my * my) * sqrtf(dx * dx + dy * dy));
    print_message("roll/pitch saturation: achieved (%.6g, %.6g) N m of (%.6g, %.6g), yaw %.3g N m, "
                  "thrust %.4g N, direction error %.3g rad\n",
                  (double)mx, (double)my, (double)dx, (double)dy, (double)achieved(&out, 3),
                  (double)achieved(&out, 0), (double)sine);
    /* fixed: a scales the 16-bit R_i, so each moment is off by at most
     * kept_tolerance (one ROTOR16 rounding per rotor, the roots, the output's
     * LSB), and the direction by at most the two of them over |M| */
    const float off = FIXED ? hypotf(kept_tolerance(&a, &d, 1), kept_tolerance(&a, &d, 2)) : 0.0f;
    assert_true(fabsf(sine) <= (FIXED ? off / sqrtf(mx * mx + my * my) : 1e-5f));
    /* a is rounded down (less than 2^-14 short of the largest that fits the
     * 16-bit pair), the pair's e and c rounded to PAIR16 (2^-14 each, e + a c),
     * the two rates' R_i to ROTOR16 (2^-15 each; q_i = 1, exact): the rotors
     * of the pair that limits a end within 2^-14 (|c| + 3) of their bounds,
     * |c| = |s_j - s_i| <= 2 max |R_i| <= 2 (max|P_i1| |x_1| + max|P_i2| |x_2|) */
    const double rate_max = pinv_column_size(&a, 1, true) * fabs((double)norm_value(d.moment.x)) +
                            pinv_column_size(&a, 2, true) * fabs((double)norm_value(d.moment.y));
    const double v_tol =
        ldexp(2.0 * rate_max, -FC_UNIT16_FRAC) + ldexp(1.0, -FC_PAIR16_FRAC) + 2.0 * PART16_ROUNDING;
    assert_true(some_rotor_at_bound(&out, v_tol));
    /* yaw gave way (b = 0) but for the room that a's rounding down left: at
     * most v_tol on the rotor that limits b, which b Y_i fills, so b |x_3| <=
     * v_tol / min |P_i3| of the yaw authority; on top of the kept tolerance */
    const float yaw_room_left =
        (float)(v_tol / pinv_column_size(&a, 3, false)) * to_f(a.moment_authority_nm.z, FC_MOMENT_FRAC);
    assert_true(fabsf(achieved(&out, 3)) <= (FIXED ? kept_tolerance(&a, &d, 3) + yaw_room_left : 1e-7f));
    /* negative roll alone (-1.92 of the authority): only the roll bit (pitch
     * demand zero, thrust at the middle of the range is where roll gets the most) */
    const fc_allocation_demand d2 = demand_make(&a, 0.2657f, -0.015f, 0.0f, 0.0f);
    assert_not_clamped(&d2);
    step_crazyflie(&a, &d2, &out, &status);
    assert_true((out.saturation & (FC_SAT_ROLL_NEG | FC_SAT_ROLL_POS | FC_SAT_PITCH_POS |
                                   FC_SAT_PITCH_NEG | FC_SAT_YAW_POS | FC_SAT_YAW_NEG)) ==
                FC_SAT_ROLL_NEG);
    assert_true(achieved(&out, 1) < -0.005f);
    assert_true(fabsf(achieved(&out, 2)) <= kept_tolerance(&a, &d2, 2));
}

static void test_saturation_hexa(void **state)
{
    (void)state;
    /* the same priorities on six rotors: too much yaw at hover (1.2 N m, 1.91
     * of the yaw authority of 0.628 N m) */
    fc_allocation_params p;
    fc_allocation a;
    fc_allocation_preset_hexa_x_4kg(&p);
    assert_int_equal(fc_allocation_init(&a, &p), FC_INIT_OK);
    const fc_allocation_demand d = demand_make(&a, 39.24f, 2.0f, 1.0f, 1.2f);
    assert_not_clamped(&d);
    fc_allocation_output out;
    const fc_step_status status = fc_allocation_step(&a, &d, &out);
    assert_outputs_valid(&p, &out);
    assert_int_equal(status, FC_STEP_OUTPUT_LIMITED);
    assert_int_equal(out.saturation, FC_SAT_YAW_POS);
    /* the kept axes: a round trip's bound with one ROTOR16 rounding (the
     * 16-bit Y_i that b scales) in v */
    double x_max[4];
    demand_size(&d, x_max);
    const double v_err = v_error(&a, x_max, 1);
    for (int r = 0; r < 3; r++) {
        assert_true(error_units(&a, r, achieved(&out, r) - demanded(&a, &d, r)) <=
                    round_trip_bound(&a, r, 1e-6f, v_err));
    }
    assert_true(achieved(&out, 3) > 0.1f && achieved(&out, 3) < 1.2f);
}

/* ---- normalised units ---------------------------------------------------- */

/* |got - want| <= tol, printed on failure */
static void assert_near(const char *what, double got, double want, double tol)
{
    if (!(fabs(got - want) <= tol)) {
        fail_msg("%s = %.9g, expected %.9g (error %.3g > %.3g)", what, got, want, fabs(got - want), tol);
    }
}

static void test_preset_authorities(void **state)
{
    (void)state;
    /* F_max = n T_max and the moment authorities sum_i |A_ki| / 2 by hand:
     * a quad-X at +-h = arm / sqrt 2 on x and y has |A_1i| = |A_2i| = T h and
     * |A_3i| = |Q_max|; the hexa's rotors at 0.45 m and -30, 30, ..., 270 deg
     * have sum |y| = 0.45 (4 sin 30 + 2) = 1.8 m and sum |x| = 0.45 4 cos 30. */
    const double cf_h = 0.046 / sqrt(2.0), f450_h = 0.225 / sqrt(2.0);
    const double hexa_y = 0.45 * (4.0 * 0.5 + 2.0), hexa_x = 0.45 * 4.0 * sqrt(3.0) / 2.0;
    const double want[PRESET_COUNT][4] = {
        {4.0 * 0.12, 4.0 * 0.12 * cf_h / 2.0, 4.0 * 0.12 * cf_h / 2.0, 4.0 * 0.12 * 0.00699 / 2.0},
        {4.0 * 8.0, 4.0 * 8.0 * f450_h / 2.0, 4.0 * 8.0 * f450_h / 2.0, 4.0 * 8.0 * 0.016 / 2.0},
        {6.0 * 13.08, 13.08 * hexa_y / 2.0, 13.08 * hexa_x / 2.0, 6.0 * 13.08 * 0.016 / 2.0}};
    /* the presets' largest T_max and arm coordinate, for the tolerance */
    const double thrust[PRESET_COUNT] = {0.12, 8.0, 13.08};
    const double coordinate[PRESET_COUNT] = {0.046 / sqrt(2.0), 0.225 / sqrt(2.0), 0.45};
    for (int k = 0; k < PRESET_COUNT; k++) {
        fc_allocation_params p;
        fc_allocation a;
        presets[k](&p);
        assert_int_equal(fc_allocation_init(&a, &p), FC_INIT_OK);
        const int n = p.rotor_count;
        const double got[4] = {exact(a.thrust_max_n, FC_FORCE_FRAC),
                               exact(a.moment_authority_nm.x, FC_MOMENT_FRAC),
                               exact(a.moment_authority_nm.y, FC_MOMENT_FRAC),
                               exact(a.moment_authority_nm.z, FC_MOMENT_FRAC)};
        /* Tolerances. Fixed: the preset's inputs are FC_C constants, each
         * within 1 LSB of its format (half an LSB for the rounding to it, and
         * up to as much again for the float FC_C computes X 2^FRAC in: the
         * hexa's 13.08 N is 1.4e7 LSB of FORCE); each entry of A is then
         * rounded to MOMENT: T (l x d) with l x d in LEVER (T/2 LSB) and both
         * products (1/2 LSB each), as the oracle bounds A, 1.5 + T/2 LSB. So
         * an entry T h + Q is within T LSB(LENGTH) + h LSB(FORCE) + LSB(MOMENT)
         * + (1.5 + T/2) LSB(MOMENT), and the moment authority, half the sum of
         * n entries, within n/2 of that plus the halving's rounding (1/2 LSB).
         * F_max = n T_max d_z with d_z = 1 (exact products): n LSB of FORCE.
         * Float: the presets' constants are products of two rounded floats
         * (1.5 eps relative), the entries one product more and the sums n - 1
         * additions: 16 eps relative. */
        const double lsb_force = ldexp(1.0, -FC_FORCE_FRAC), lsb_length = ldexp(1.0, -FC_LENGTH_FRAC);
        const double lsb_moment = ldexp(1.0, -FC_MOMENT_FRAC);
        const double entry = thrust[k] * lsb_length + coordinate[k] * lsb_force + lsb_moment +
                             (1.5 + 0.5 * thrust[k]) * lsb_moment;
        double worst = 0.0;
        for (int r = 0; r < 4; r++) {
            const double tol = FIXED ? (r == 0 ? n * lsb_force : 0.5 * n * entry + 0.5 * lsb_moment)
                                     : 16.0 * EPS * want[k][r];
            char what[64];
            snprintf(what, sizeof what, "%s authority %d", preset_names[k], r);
            assert_near(what, got[r], want[k][r], tol);
            worst = fmax(worst, fabs(got[r] - want[k][r]) / tol);
        }
        print_message("%-11s F_max %.6g N, authority (%.6g, %.6g, %.6g) N m (worst %.2g of the tolerance)\n",
                      preset_names[k], got[0], got[1], got[2], got[3], worst);
        /* fc_allocation_authority_of computes the same from the parameters */
        fc_real f_max;
        fc_vec3 m;
        assert_true(fc_allocation_authority_of(&p, &f_max, &m));
        assert_true(f_max == a.thrust_max_n);
        assert_true(m.x == a.moment_authority_nm.x && m.y == a.moment_authority_nm.y &&
                    m.z == a.moment_authority_nm.z);
    }
    /* not a geometry: false and zeros */
    fc_allocation_params bad;
    fc_allocation_preset_f450(&bad);
    bad.rotor[1].thrust_max_n = FC_INT(0, FORCE);
    fc_real f_max = FC_INT(1, FORCE);
    fc_vec3 m = fc_vec3_make(FC_INT(1, MOMENT), FC_INT(1, MOMENT), FC_INT(1, MOMENT));
    assert_false(fc_allocation_authority_of(&bad, &f_max, &m));
    assert_true(f_max == FC_INT(0, FORCE) && m.x == FC_INT(0, MOMENT) && m.y == FC_INT(0, MOMENT) &&
                m.z == FC_INT(0, MOMENT));
    bad.rotor_count = 0u;
    assert_false(fc_allocation_authority_of(&bad, &f_max, &m));
}

static void test_normalise_round_trip(void **state)
{
    (void)state;
    rng_seed(0x0A110C07u);
    for (int k = 0; k < PRESET_COUNT; k++) {
        fc_allocation_params p;
        fc_allocation a;
        presets[k](&p);
        assert_int_equal(fc_allocation_init(&a, &p), FC_INIT_OK);
        const float auth[4] = {to_f(a.thrust_max_n, FC_FORCE_FRAC), to_f(a.moment_authority_nm.x, FC_MOMENT_FRAC),
                               to_f(a.moment_authority_nm.y, FC_MOMENT_FRAC),
                               to_f(a.moment_authority_nm.z, FC_MOMENT_FRAC)};
        const int frac[4] = {FC_FORCE_FRAC, FC_MOMENT_FRAC, FC_MOMENT_FRAC, FC_MOMENT_FRAC};
        double worst_norm = 0.0, worst_phys = 0.0;
        for (int c = 0; c < 2000; c++) {
            /* physical demands within +-1.9 authorities */
            fc_real w[4];
            for (int r = 0; r < 4; r++) {
                w[r] = from_f(uniform(-1.9f, 1.9f) * auth[r], frac[r]);
            }
            const fc_allocation_demand d = fc_allocation_normalise(&a, w[0], fc_vec3_make(w[1], w[2], w[3]));
            const float x[4] = {norm_value(d.thrust), norm_value(d.moment.x), norm_value(d.moment.y),
                                norm_value(d.moment.z)};
            fc_real back_thrust;
            fc_vec3 back_moment;
            fc_allocation_physical(&a, &d, &back_thrust, &back_moment);
            const fc_real back[4] = {back_thrust, back_moment.x, back_moment.y, back_moment.z};
            for (int r = 0; r < 4; r++) {
                const double value = exact(w[r], frac[r]);
                const double ratio = value / exact(authority_of_row(&a, r), frac[r]);
                /* normalise: w / authority rounded to NORM16, half an LSB
                 * (2^-15) plus the quotient's rounding in RATIO (2^-25) before
                 * it; float: the division's rounding */
                const double norm_tol = FIXED ? ldexp(1.0, -15) + ldexp(1.0, -25) : EPS * fabs(ratio);
                worst_norm = fmax(worst_norm, fabs((double)x[r] - ratio) / norm_tol);
                assert_near("normalised", (double)x[r], ratio, norm_tol);
                /* physical: back within that times the authority, plus the
                 * product's rounding (half an LSB of FORCE or MOMENT) */
                const double phys_tol = FIXED ? norm_tol * (double)auth[r] + ldexp(0.5, -frac[r])
                                              : 3.0 * EPS * fabs(value);
                worst_phys = fmax(worst_phys, fabs(exact(back[r], frac[r]) - value) / phys_tol);
                assert_near("physical", exact(back[r], frac[r]), value, phys_tol);
            }
            /* the physical value of a normalised demand normalises back to it:
             * exactly in fixed (the product's half LSB of FORCE or MOMENT over
             * F_max or the authority, plus the quotient's 2^-25, stays below
             * half a NORM16 LSB, 2^-15, for F_max >= 1/16 N, which init
             * demands, and authorities above 2^-10 N m, as the presets' are:
             * the rounding to NORM16 lands on x again); within 2 ulp in float
             * (a product and a division) */
            const fc_allocation_demand again = fc_allocation_normalise(&a, back_thrust, back_moment);
            const fc_real16 first[4] = {d.thrust, d.moment.x, d.moment.y, d.moment.z};
            const fc_real16 second[4] = {again.thrust, again.moment.x, again.moment.y, again.moment.z};
            for (int r = 0; r < 4; r++) {
                if (FIXED) {
                    assert_true(first[r] == second[r]);
                } else {
                    assert_near("normalised again", (double)norm_value(second[r]), (double)norm_value(first[r]),
                                2.0 * EPS * fabs((double)norm_value(first[r])));
                }
            }
            /* the thrust alone: fc_allocation_thrust_fraction (a product by
             * 1 / F_max in PER_FORCE, 2^-27 relative of 1 / F_max at worst)
             * within one NORM16 LSB of the division */
            const fc_real16 fraction = fc_allocation_thrust_fraction(&a, w[0]);
            assert_near("thrust fraction", (double)norm_value(fraction), (double)x[0],
                        FIXED ? ldexp(1.0, -14) : 2.0 * EPS);
        }
        print_message("%-11s normalise/physical: worst %.3g / %.3g of the tolerance\n", preset_names[k],
                      worst_norm, worst_phys);
        /* beyond the range: clamped to +-1.99 (NORM16 holds [-2, 2)) */
        const fc_allocation_demand big = fc_allocation_normalise(
            &a, from_f(5.0f * auth[0], FC_FORCE_FRAC),
            fc_vec3_make(from_f(-3.0f * auth[1], FC_MOMENT_FRAC), FC_INT(0, MOMENT),
                         from_f(2.5f * auth[3], FC_MOMENT_FRAC)));
        assert_near("clamped thrust", (double)norm_value(big.thrust), 1.99, FIXED ? ldexp(1.0, -15) : 2.0 * EPS);
        assert_near("clamped roll", (double)norm_value(big.moment.x), -1.99, FIXED ? ldexp(1.0, -15) : 2.0 * EPS);
        assert_true(big.moment.y == FC_INT16(0, NORM16));
        assert_near("clamped yaw", (double)norm_value(big.moment.z), 1.99, FIXED ? ldexp(1.0, -15) : 2.0 * EPS);
    }
    /* not ready: a zero demand (no authority to divide by) */
    fc_allocation idle;
    fc_allocation_params p;
    fc_allocation_preset_f450(&p);
    p.rotor_count = 0u;
    assert_int_equal(fc_allocation_init(&idle, &p), FC_INIT_BAD_PARAM);
    const fc_allocation_demand zero =
        fc_allocation_normalise(&idle, FC_INT(10, FORCE),
                                fc_vec3_make(FC_INT(1, MOMENT), FC_INT(1, MOMENT), FC_INT(1, MOMENT)));
    assert_true(zero.thrust == FC_INT16(0, NORM16) && zero.moment.x == FC_INT16(0, NORM16) &&
                zero.moment.y == FC_INT16(0, NORM16) && zero.moment.z == FC_INT16(0, NORM16));
}

/* ---- bad input and ranges ---------------------------------------------- */

/* fc_allocation_speeds (the controller's step) gives fc_allocation_step's
 * speeds, saturation and status, with the state carried the same way; and
 * fc_allocation_moment_nm fc_allocation_physical's moment. */
static void test_speeds_match_step(void **state)
{
    (void)state;
    rng_seed(0x5eed28u);
    for (int k = 0; k < PRESET_COUNT; k++) {
        fc_allocation_params p;
        presets[k](&p);
        fc_allocation a;
        fc_allocation b;
        assert_int_equal(fc_allocation_init(&a, &p), FC_INIT_OK);
        assert_int_equal(fc_allocation_init(&b, &p), FC_INIT_OK);
        const float thrust_max = to_f(a.thrust_max_n, FC_FORCE_FRAC);
        const fc_vec3 m = a.moment_authority_nm;
        for (int n = 0; n < 300; n++) {
            /* beyond the authorities too, so that every saturation case runs */
            const fc_allocation_demand d =
                demand_make(&a, thrust_max * uniform(-0.1f, 1.1f),
                            to_f(m.x, FC_MOMENT_FRAC) * uniform(-1.5f, 1.5f),
                            to_f(m.y, FC_MOMENT_FRAC) * uniform(-1.5f, 1.5f),
                            to_f(m.z, FC_MOMENT_FRAC) * uniform(-1.5f, 1.5f));
            fc_allocation_output out;
            const fc_step_status status = fc_allocation_step(&a, &d, &out);
            fc_real speed_unit[FC_MAX_ROTORS];
            uint8_t saturation_bits = 0xffu;
            assert_int_equal(fc_allocation_speeds(&b, &d, speed_unit, &saturation_bits), status);
            assert_int_equal(saturation_bits, out.saturation);
            for (int i = 0; i < FC_MAX_ROTORS; i++) {
                assert_true(speed_unit[i] == out.speed[i]);
            }
            fc_real thrust_n;
            fc_vec3 physical_nm;
            fc_vec3 moment_nm;
            fc_allocation_physical(&a, &d, &thrust_n, &physical_nm);
            fc_allocation_moment_nm(&a, &d.moment, &moment_nm);
            assert_true(moment_nm.x == physical_nm.x && moment_nm.y == physical_nm.y &&
                        moment_nm.z == physical_nm.z);
        }
    }
}

static void test_bad_input(void **state)
{
    (void)state;
    fc_allocation_params p;
    fc_allocation a;
    fc_allocation_preset_f450(&p);
    assert_int_equal(fc_allocation_init(&a, &p), FC_INIT_OK);
    fc_allocation_output out;
    /* no good demand yet: zero thrust and moment, all rotors at u_min */
    assert_int_equal(fc_allocation_step(&a, NULL, &out) & FC_STEP_BAD_INPUT, FC_STEP_BAD_INPUT);
    assert_outputs_valid(&p, &out);
    for (int i = 0; i < 4; i++) {
        assert_true(fabsf(to_f(out.speed[i], FC_UNIT_FRAC) - to_f(p.rotor[i].speed_min, FC_UNIT_FRAC)) <=
                    2e-9f);
    }
    /* a good demand, then a bad one: the good one is held */
    const fc_allocation_demand good = demand_make(&a, 20.0f, 0.5f, -0.3f, 0.1f);
    fc_allocation_output held;
    assert_int_equal(fc_allocation_step(&a, &good, &held), FC_STEP_OK);
    assert_int_equal(fc_allocation_step(&a, NULL, &out), FC_STEP_BAD_INPUT);
    for (int i = 0; i < FC_MAX_ROTORS; i++) {
        assert_true(out.speed[i] == held.speed[i]);
    }
#if !FC_NUMERIC_FIXED
    const float bad_values[3] = {NAN, INFINITY, -INFINITY};
    for (int b = 0; b < 3; b++) {
        for (int field = 0; field < 4; field++) {
            fc_allocation_demand d = good;
            if (field == 0) {
                d.thrust = bad_values[b];
            } else if (field == 1) {
                d.moment.x = bad_values[b];
            } else if (field == 2) {
                d.moment.y = bad_values[b];
            } else {
                d.moment.z = bad_values[b];
            }
            assert_int_equal(fc_allocation_step(&a, &d, &out), FC_STEP_BAD_INPUT);
            assert_outputs_valid(&p, &out);
            for (int i = 0; i < FC_MAX_ROTORS; i++) {
                assert_true(out.speed[i] == held.speed[i]);
            }
        }
    }
    /* a NaN right after init: u_min */
    assert_int_equal(fc_allocation_init(&a, &p), FC_INIT_OK);
    fc_allocation_demand nan_demand = good;
    nan_demand.moment.y = NAN;
    assert_int_equal(fc_allocation_step(&a, &nan_demand, &out) & FC_STEP_BAD_INPUT,
                     FC_STEP_BAD_INPUT);
    for (int i = 0; i < 4; i++) {
        assert_true(out.speed[i] == p.rotor[i].speed_min);
    }
#endif
}

/* One component of an extreme demand: the largest NORM16 value (in float the
 * largest float: a caller may pass anything), +-1, 0. */
static fc_real16 extreme_component(void)
{
    const float pick = uniform(0.0f, 5.0f);
    if (pick < 1.0f) {
        return FC_REAL16_MAX;
    }
    if (pick < 2.0f) {
        return fc_neg16(FC_REAL16_MAX);
    }
    if (pick < 3.0f) {
        return norm16(1.0f);
    }
    if (pick < 4.0f) {
        return norm16(-1.0f);
    }
    return FC_INT16(0, NORM16);
}

static void test_extreme_demands(void **state)
{
    (void)state;
    /* anything representable in, speeds in [u_min, 1] out, no arithmetic saturation */
    rng_seed(0x0A110C05u);
    for (int k = 0; k < PRESET_COUNT; k++) {
        for (int nonlinear = 0; nonlinear < 2; nonlinear++) {
            fc_allocation_params p;
            fc_allocation a;
            presets[k](&p);
            if (nonlinear != 0) {
                with_torque_exponent(&p, 2.3f, 3);
            }
            assert_int_equal(fc_allocation_init(&a, &p), FC_INIT_OK);
            for (int c = 0; c < 2000; c++) {
                /* NORM16 holds [-2, 2) in fixed: uniform over it, or its
                 * extremes (and +-1, 0) mixed per axis */
                fc_allocation_demand d;
                if (c % 2 == 0) {
                    d = demand_norm(uniform(-1.9999f, 1.9999f), uniform(-1.9999f, 1.9999f),
                                    uniform(-1.9999f, 1.9999f), uniform(-1.9999f, 1.9999f));
                } else {
                    d.thrust = extreme_component();
                    d.moment.x = extreme_component();
                    d.moment.y = extreme_component();
                    d.moment.z = extreme_component();
                }
                fc_allocation_output out;
                const fc_step_status status = fc_allocation_step(&a, &d, &out);
                assert_outputs_valid(&p, &out);
                assert_int_equal(status & (fc_step_status)~FC_STEP_OUTPUT_LIMITED, FC_STEP_OK);
                /* a bit in both directions of one axis never */
                assert_false((out.saturation & FC_SAT_ROLL_POS) && (out.saturation & FC_SAT_ROLL_NEG));
                assert_false((out.saturation & FC_SAT_YAW_POS) && (out.saturation & FC_SAT_YAW_NEG));
                assert_false((out.saturation & FC_SAT_THRUST_HIGH) &&
                             (out.saturation & FC_SAT_THRUST_LOW));
            }
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_presets_init),
        cmocka_unit_test(test_crazyflie_effectiveness),
        cmocka_unit_test(test_rank_deficient),
        cmocka_unit_test(test_bad_params),
        cmocka_unit_test(test_round_trip_r_equals_s),
        cmocka_unit_test(test_round_trip_other_exponents),
        cmocka_unit_test(test_round_trip_quad_speeds_unique),
        cmocka_unit_test(test_round_trip_tilted),
        cmocka_unit_test(test_round_trip_r_not_s),
        cmocka_unit_test(test_round_trip_r_not_s_pow),
        cmocka_unit_test(test_r_not_s_warm_start),
        cmocka_unit_test(test_saturation_yaw),
        cmocka_unit_test(test_saturation_thrust),
        cmocka_unit_test(test_saturation_roll_pitch),
        cmocka_unit_test(test_saturation_hexa),
        cmocka_unit_test(test_preset_authorities),
        cmocka_unit_test(test_normalise_round_trip),
        cmocka_unit_test(test_bad_input),
        cmocka_unit_test(test_speeds_match_step),
        cmocka_unit_test(test_extreme_demands),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
