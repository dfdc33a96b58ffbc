/*
 * test_attitude_control.c - quaternion attitude control (fc/attitude_control.h).
 *
 * One source for both backends. The reference is a double-precision copy of
 * the law in the header (ref_law below),
 *
 *     m = -(Kp e + Ki I + Kd (w - w_ff)) + dJ w_i w_j,   K = k J / authority,
 *                                                        dJ = (J_k - J_j) / authority,
 *
 * then the budget. Its constants come either from the parameters, in double
 * (ref_from: the header's law; the comparison includes the step's 16-bit
 * constants) or from the 16-bit constants init stored, widened exactly
 * (ref_stored: the comparison measures the step's arithmetic only).
 * test_normalisation checks the stored constants against k J / authority.
 * The error e is either computed in double from the attitudes (ref_law: the
 * whole step) or the step's own (its telemetry, ref_law_at: the law alone).
 *
 * Moments are compared in the law's normalised units (moment / authority,
 * fc_attitude_control_output.moment). The tolerance of each component is
 * derived per case from the values of that case (ref_law, field tol):
 *   constants (ref_from only): |K_stored - K| |x| per term, x = e, I, r, and
 *     |dJ_stored - dJ| |w_i w_j|. Fixed: K in NGAIN16 (Q12, half LSB 2^-13)
 *     after J / authority in INERTIA (2^-31, times k) and k J / authority in
 *     RATIO (2^-25); dJ in NINERTIA16 (Q15, 2^-16) after INERTIA (2^-31).
 *     Float: two roundings of 2^-24 relative (J / authority, times k).
 *   the inputs as the step reads them, times |K| (+ its constant's bound):
 *     e: the attitude error's own (ref_law: error_tol_at(N), 16-bit
 *        quaternions in fixed; ref_law_at: none), times yaw_weight on z (+
 *        the weighting's rounding to ANGLE, 2^-29), then to ANGLE16 (Q12,
 *        2^-13);
 *     I: ANGLE -> ANGLE16 (2^-13); r = w - w_ff: RATE -> RATE16 (Q10, 2^-11,
 *        plus |r| - 32767/1024 beyond the format: saturation);
 *     w_i w_j: each rate to RATE16 (2^-11: |w_j| 2^-11 + |w_k| 2^-11 +
 *        2^-22), the product to WW16 (Q5, 2^-6), times |dJ|;
 *   the sum: Kp e + Ki I from Q24 to NSUM (Q22, 2^-23); Kd r and dJ ww are
 *     exact in Q22;
 *   float instead of the format roundings: gamma_5 (5 roundings of 2^-24 on
 *     the longest path: the yaw weighting, the product, the dot product's
 *     add, the two adds of the sum) times the sum of |terms|;
 *   the budget (only where the moment can reach it): the budget in NSUM
 *     (2^-23), the roll/pitch factor's spread over the raw moments' bounds
 *     (evaluated, not linearised), its rounding to UNIT (2^-31 |m|) and the
 *     product's to NSUM (2^-23); float 2 x 2^-24 relative;
 *   the output: NSUM -> NORM16 (2^-15) in fixed; none in float (fc_real16 is
 *     float).
 * The closed loops fly a rigid body integrated in double (explicit Euler at
 * 1 kHz) with the controller at 500 Hz, once with the library and once with
 * ref_law in the same plant (moment x authority, N m), and compare the two.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <string.h>
#include <math.h>
#include <cmocka.h>
#include "fc/attitude_control.h"
#include "test_support.h"

/* ---- conversions (test side only; exact in double) ------------------- */

static fc_real R(double x, int frac)
{
#if FC_NUMERIC_FIXED
    const double scaled = x * ldexp(1.0, frac);
    if (scaled >= 2147483647.0) {
        return FC_REAL_MAX;
    }
    if (scaled <= -2147483647.0) {
        return FC_REAL_MIN;
    }
    return (fc_real)llround(scaled);
#else
    (void)frac;
    return (fc_real)x;
#endif
}

static double D(fc_real x, int frac)
{
    return ts_val(x, frac);
}

#define RU(x) R((x), FC_UNIT_FRAC)
#define RRATE(x) R((x), FC_RATE_FRAC)

/* A normalised output moment (NORM16) as a double, exactly: widened to RATIO. */
static double DN(fc_real16 x)
{
    return D(fc_widen16(x, FC_NORM16_FRAC, FC_RATIO_FRAC), FC_RATIO_FRAC);
}

/* A 16-bit constant of the step (fc_real16) as a double, exactly. */
static double D16(fc_real16 x, int frac)
{
    return ts_val16(x, frac);
}

/* The step's own formats (fc/attitude_control.h, "Formats"; the FC_*16_FRAC
 * at the top of attitude_control.c) */
#define ANGLE16_FRAC 12    /* the error and the integral as the products read them */
#define RATE16_FRAC 10     /* the rate and the rate error */
#define NGAIN16_FRAC 12    /* c->gain_p, gain_i, gain_d */
#define NINERTIA16_FRAC 15 /* c->inertia_diff16 */
#define WW16_FRAC 5        /* w_i w_j */
#define NSUM_FRAC 22       /* the sum, the budget, the held moment */

/* Half an LSB of a Q-format in fixed (a rounding to nearest into it); none in
 * float, where the step's narrowings are no-ops. */
static double half_lsb(int frac)
{
    return FC_NUMERIC_FIXED ? ldexp(1.0, -frac - 1) : 0.0;
}

/* |x16 - x| for x rounded into a 16-bit format: half an LSB, and beyond the
 * format (32767 LSB) the saturation. None in float. */
static double q16_err(double x, int frac)
{
#if FC_NUMERIC_FIXED
    const double over = fabs(x) - 32767.0 * ldexp(1.0, -frac);
    return half_lsb(frac) + (over > 0.0 ? over : 0.0);
#else
    (void)x;
    (void)frac;
    return 0.0;
#endif
}

/* float's unit roundoff and gamma_n = n u / (1 - n u): the bound of n roundings */
#define FLOAT_U ldexp(1.0, -24)
static double gamma_n(int n)
{
    return (double)n * FLOAT_U / (1.0 - (double)n * FLOAT_U);
}

/* The output's rounding from NSUM to NORM16: at most half an LSB (2^-15 of
 * the authority) in fixed; none in float, where fc_real16 is float. */
#define NORM16_HALF_LSB half_lsb(FC_NORM16_FRAC)
/* The budget as the step holds it: moment_limit (RATIO) rounded to NSUM. */
#define LIMIT_HALF_LSB half_lsb(NSUM_FRAC)

static const double kPi = 3.14159265358979323846;
static const double kDeg = 3.14159265358979323846 / 180.0;

/* ---- double quaternions ---------------------------------------------- */

typedef struct dq {
    double w, x, y, z;
} dq;

static dq dq_make(double w, double x, double y, double z)
{
    const dq q = {w, x, y, z};
    return q;
}

static dq dq_mul(dq p, dq q)
{
    return dq_make(
        p.w * q.w - p.x * q.x - p.y * q.y - p.z * q.z, p.w * q.x + p.x * q.w + p.y * q.z - p.z * q.y,
        p.w * q.y - p.x * q.z + p.y * q.w + p.z * q.x, p.w * q.z + p.x * q.y - p.y * q.x + p.z * q.w);
}

static dq dq_conj(dq q)
{
    return dq_make(q.w, -q.x, -q.y, -q.z);
}

static dq dq_normalize(dq q)
{
    const double n = sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
    return dq_make(q.w / n, q.x / n, q.y / n, q.z / n);
}

static dq dq_axis_angle(double ax, double ay, double az, double angle)
{
    const double n = sqrt(ax * ax + ay * ay + az * az);
    const double s = sin(angle / 2.0) / n;
    return dq_make(cos(angle / 2.0), ax * s, ay * s, az * s);
}

static dq dq_neg(dq q)
{
    return dq_make(-q.w, -q.x, -q.y, -q.z);
}

static fc_quat to_fc(dq q)
{
    return fc_quat_make(RU(q.w), RU(q.x), RU(q.y), RU(q.z));
}

static dq from_fc(fc_quat q)
{
    return dq_make(D(q.w, FC_UNIT_FRAC), D(q.x, FC_UNIT_FRAC), D(q.y, FC_UNIT_FRAC), D(q.z, FC_UNIT_FRAC));
}

/* ---- parameters -------------------------------------------------------- */

static const double kHexaJ[3] = {0.082, 0.082, 0.149};
static const double kCfJ[3] = {1.66e-5, 1.66e-5, 2.93e-5};

static fc_vec3 vec_from(const double v[3], int frac)
{
    return fc_vec3_make(R(v[0], frac), R(v[1], frac), R(v[2], frac));
}

static fc_vec3 vec_all(double x, int frac)
{
    return fc_vec3_make(R(x, frac), R(x, frac), R(x, frac));
}

/* A budget given in N m per axis as the law's normalised moment_limit:
 * limit_nm / authority_nm (RATIO). */
static fc_vec3 limit_of(const fc_attitude_control_params *p, double nm_x, double nm_y, double nm_z)
{
    return fc_vec3_make(R(nm_x / D(p->authority_nm.x, FC_MOMENT_FRAC), FC_RATIO_FRAC),
                        R(nm_y / D(p->authority_nm.y, FC_MOMENT_FRAC), FC_RATIO_FRAC),
                        R(nm_z / D(p->authority_nm.z, FC_MOMENT_FRAC), FC_RATIO_FRAC));
}

/* The largest normalised budget init accepts: "unclamped" for the tests whose
 * moments stay below it (they check FC_STEP_OUTPUT_LIMITED is not set). */
#define LIMIT_MAX 1.99

/* The 4 kg hexa: the default authority (J * 50 rad/s^2: 4.1, 4.1, 7.45 N m)
 * and a budget of +-2 N m on each axis. */
static fc_attitude_control_params hexa_params(void)
{
    fc_attitude_control_params p;
    fc_attitude_control_default_params(&p, R(0.002, FC_DT_FRAC), vec_from(kHexaJ, FC_INERTIA_FRAC));
    p.moment_limit = limit_of(&p, 2.0, 2.0, 2.0);
    return p;
}

/* The parameters as the backend holds them, in double; jn and djn are J /
 * authority and (Jz - Jy, Jx - Jz, Jy - Jx) / authority as init computed
 * them (32-bit), mlim the normalised budget, auth the authority (N m).
 * gp, gi, gd, dj are the law's constants Kp, Ki, Kd, dJ the reference uses,
 * and *_tol bound how far the step's own constants are from them (zero when
 * they are the step's own). */
typedef struct ref_params {
    double dt, j[3], jn[3], djn[3], auth[3], kp[3], kd[3], ki[3], ilim[3], yaw_weight, mlim[3];
    double gp[3], gi[3], gd[3], dj[3];
    double gp_tol[3], gi_tol[3], gd_tol[3], dj_tol[3];
} ref_params;

static void vec_to(fc_vec3 v, int frac, double out[3])
{
    out[0] = D(v.x, frac);
    out[1] = D(v.y, frac);
    out[2] = D(v.z, frac);
}

static void vec16_to(fc_vec3_16 v, int frac, double out[3])
{
    out[0] = D16(v.x, frac);
    out[1] = D16(v.y, frac);
    out[2] = D16(v.z, frac);
}

/* |K_stored - k J / authority| for a normalised gain K (double, from the
 * parameters). Fixed: J / authority rounded to INERTIA (2^-31, times k), k
 * times it to RATIO (2^-25), that to NGAIN16 (2^-13). Float: two roundings
 * (the quotient, the product). */
static double gain_const_tol(double k, double gain)
{
#if FC_NUMERIC_FIXED
    (void)gain;
    return half_lsb(NGAIN16_FRAC) + half_lsb(FC_RATIO_FRAC) + k * half_lsb(FC_INERTIA_FRAC);
#else
    (void)k;
    return ((1.0 + FLOAT_U) * (1.0 + FLOAT_U) - 1.0) * fabs(gain);
#endif
}

/* |dJ_stored - (J_k - J_j) / authority|. Fixed: the difference is exact in
 * INERTIA, the quotient rounded to it (2^-31), then to NINERTIA16 (2^-16).
 * Float: two roundings (the difference, the quotient). */
static double dj_const_tol(double dj)
{
#if FC_NUMERIC_FIXED
    (void)dj;
    return half_lsb(NINERTIA16_FRAC) + half_lsb(FC_INERTIA_FRAC);
#else
    return ((1.0 + FLOAT_U) * (1.0 + FLOAT_U) - 1.0) * fabs(dj);
#endif
}

/* From an initialised controller: its parameters and what init derived; the
 * law's constants from the parameters in double (the header's law), with the
 * bounds of the step's stored ones. */
static ref_params ref_from(const fc_attitude_control *c)
{
    const fc_attitude_control_params *p = &c->p;
    ref_params r;
    r.dt = D(p->dt_s, FC_DT_FRAC);
    vec_to(p->inertia_kgm2, FC_INERTIA_FRAC, r.j);
    vec_to(c->inertia_norm, FC_INERTIA_FRAC, r.jn);
    vec_to(c->inertia_diff_norm, FC_INERTIA_FRAC, r.djn);
    vec_to(p->authority_nm, FC_MOMENT_FRAC, r.auth);
    vec_to(p->kp_per_s2, FC_GAIN_FRAC, r.kp);
    vec_to(p->kd_per_s, FC_GAIN_FRAC, r.kd);
    vec_to(p->ki_per_s3, FC_GAIN_FRAC, r.ki);
    vec_to(p->integral_limit_rad, FC_ANGLE_FRAC, r.ilim);
    r.yaw_weight = D(p->yaw_weight, FC_RATIO_FRAC);
    vec_to(p->moment_limit, FC_RATIO_FRAC, r.mlim);
    for (int i = 0; i < 3; i++) {
        const double jn = r.j[i] / r.auth[i];
        r.gp[i] = r.kp[i] * jn;
        r.gi[i] = r.ki[i] * jn;
        r.gd[i] = r.kd[i] * jn;
        r.dj[i] = (r.j[(i + 2) % 3] - r.j[(i + 1) % 3]) / r.auth[i];
        r.gp_tol[i] = gain_const_tol(r.kp[i], r.gp[i]);
        r.gi_tol[i] = gain_const_tol(r.ki[i], r.gi[i]);
        r.gd_tol[i] = gain_const_tol(r.kd[i], r.gd[i]);
        r.dj_tol[i] = dj_const_tol(r.dj[i]);
    }
    return r;
}

/* The same with the constants the step stored (widened exactly): the
 * comparison then measures the step's arithmetic alone. */
static ref_params ref_stored(const fc_attitude_control *c)
{
    ref_params r = ref_from(c);
    vec16_to(c->gain_p, NGAIN16_FRAC, r.gp);
    vec16_to(c->gain_i, NGAIN16_FRAC, r.gi);
    vec16_to(c->gain_d, NGAIN16_FRAC, r.gd);
    vec16_to(c->inertia_diff16, NINERTIA16_FRAC, r.dj);
    for (int i = 0; i < 3; i++) {
        r.gp_tol[i] = r.gi_tol[i] = r.gd_tol[i] = r.dj_tol[i] = 0.0;
    }
    return r;
}

/* ---- the law in double (the header's equations) ----------------------- */

static void ref_error(dq q, dq qd, double err[3])
{
    dq e = dq_mul(dq_conj(dq_normalize(qd)), dq_normalize(q));
    if (e.w < 0.0) {
        e = dq_neg(e);
    }
    const double n_sq = e.w * e.w + e.z * e.z;
    double c = 1.0, s = 0.0;
    if (n_sq >= 1e-4) {
        c = e.w / sqrt(n_sq);
        s = e.z / sqrt(n_sq);
    }
    err[0] = 2.0 * (e.x * c + e.y * s);
    err[1] = 2.0 * (e.y * c - e.x * s);
    err[2] = 2.0 * s;
}

/* Tolerance of the attitude error (rad), for a tilt error N = cos(tilt_e / 2)
 * away from upside down (N >= 0.01, the heading split's threshold), the
 * quaternions given unit to well below a UNIT16 LSB (as every test here
 * gives them). With d the error of the error quaternion e (2-norm), U that
 * of fc_unit2_16's (c, s) against e's own (w, z) / N, and r the rounding of
 * the tilt's dot product: the heading 2 s is off by 2 (d / N' + U) and the
 * tilt 2 R(c, s) (x, y) by 2 (d_xy + S (d_wz / N' + sqrt(2) U) + r), S =
 * |(x, y)|, where N' = (N + N_e) / 2 >= N (1 - d / 0.02) (the two normalised
 * vectors differ by at most 2 d / (N + N_e)). With N^2 + S^2 = 1 and
 * d_xy^2 + d_wz^2 <= d^2, N times either is below 2 (1.01 d + U + r):
 *   fixed (L = 2^-14, UNIT16): q and q_d rounded to UNIT16, 0.5 L a
 *     component, 1 L each in norm, and e's four roundings 1 L: d = 3.01 L
 *     (the 32-bit inputs' own 2^-30); U = 1.32 L (test_scalar's
 *     unit2_16_bound_lsb); r = 0 (exact 16 x 16-bit products);
 *   float (u = 2^-24, each rounding within u relative): fc_quat_normalize
 *     5 u each (|q|^2 in 4 u, 1/sqrt 2 u of that and two roundings, the
 *     product u), e's 4-term sums 4 u a component, 8 u in norm: d = 18 u;
 *     U = 4 u (test_scalar's unit2_16_bound_lsb); r = u (the dot product's
 *     2 u S, N S <= 1/2). */
static double error_tol_at(double n)
{
#if FC_NUMERIC_FIXED
    const double lsb = ldexp(1.0, -FC_UNIT16_FRAC);
    const double d = 3.01 * lsb, unit2 = 1.32 * lsb, dot = 0.0;
#else
    const double u = ldexp(1.0, -24);
    const double d = 18.0 * u, unit2 = 4.0 * u, dot = u;
#endif
    return 2.0 * (1.01 * d + unit2 + dot) / n;
}

/* ... and for the tilt errors of the tests below, up to 90 deg (N >= 0.707) */
#define ERROR_TOL_RAD error_tol_at(0.7071)

/* N = cos(tilt_e / 2) of a pair, at least 0.01 (the heading split's threshold) */
static double pair_n(dq q, dq qd)
{
    const dq e = dq_mul(dq_conj(dq_normalize(qd)), dq_normalize(q));
    const double n = sqrt(e.w * e.w + e.z * e.z);
    return n > 0.01 ? n : 0.01;
}

/* The reference's moment, clamped as the library does (m), before the budget
 * (raw), and the bound of |library - m| per axis (tol; the header's comment). */
typedef struct ref_out {
    double m[3], raw[3], tol[3];
} ref_out;

/* The moment for the attitude error err (unweighted, known to within etol
 * of the step's), the rates w, w_ff and the integral state I, all as the
 * backend holds them. */
static ref_out ref_core(const ref_params *p, const double err[3], double etol, const double w[3],
                        const double wff[3], const double integral[3])
{
    ref_out o;
    const double e[3] = {err[0], err[1], err[2] * p->yaw_weight};
    double raw_tol[3];
    for (int i = 0; i < 3; i++) {
        /* (w x J w) / authority = ((Jz - Jy) wy wz, (Jx - Jz) wz wx, (Jy - Jx) wx wy) / authority */
        const int j = (i + 1) % 3, k = (i + 2) % 3;
        const double ww = w[j] * w[k];
        const double r = w[i] - wff[i];
        o.raw[i] = -(p->gp[i] * e[i] + p->gi[i] * integral[i] + p->gd[i] * r) + p->dj[i] * ww;
        /* what the step reads, against e, I, r and w_j w_k */
        /* (yaw: 2 (yaw_weight s) with the product rounded, one ANGLE LSB) */
        const double de = (i == 2 ? p->yaw_weight * etol + 2.0 * half_lsb(FC_ANGLE_FRAC) : etol) +
                          q16_err(e[i], ANGLE16_FRAC);
        const double di = q16_err(integral[i], ANGLE16_FRAC);
        const double dr = q16_err(r, RATE16_FRAC);
        const double dwj = q16_err(w[j], RATE16_FRAC), dwk = q16_err(w[k], RATE16_FRAC);
        const double ww16_mag = (fabs(w[j]) + dwj) * (fabs(w[k]) + dwk);
        const double dww = fabs(w[j]) * dwk + fabs(w[k]) * dwj + dwj * dwk + q16_err(ww16_mag, WW16_FRAC);
        /* the step's constants, at most this far from the reference's */
        const double gp = fabs(p->gp[i]) + p->gp_tol[i], gi = fabs(p->gi[i]) + p->gi_tol[i];
        const double gd = fabs(p->gd[i]) + p->gd_tol[i], dj = fabs(p->dj[i]) + p->dj_tol[i];
        const double consts = p->gp_tol[i] * fabs(e[i]) + p->gi_tol[i] * fabs(integral[i]) +
                              p->gd_tol[i] * fabs(r) + p->dj_tol[i] * fabs(ww);
        const double inputs = gp * de + gi * di + gd * dr + dj * dww;
#if FC_NUMERIC_FIXED
        /* Kp e + Ki I from Q24 to NSUM; the rest of the sum is exact */
        const double sum_round = half_lsb(NSUM_FRAC);
#else
        const double terms = gp * (fabs(e[i]) + de) + gi * fabs(integral[i]) + gd * fabs(r) + dj * fabs(ww);
        const double sum_round = gamma_n(5) * terms;
#endif
        raw_tol[i] = consts + inputs + sum_round;
        o.m[i] = o.raw[i];
    }
    /* the budget: roll and pitch scaled by one factor f, yaw clamped. The
     * library's factor is within [f_lo, f_hi]: its raw moments within
     * raw_tol, its budget within LIMIT_HALF_LSB */
    const double dl = LIMIT_HALF_LSB;
    double f = 1.0, f_lo = 1.0, f_hi = 1.0;
    for (int a = 0; a < 2; a++) {
        const double x = fabs(o.raw[a]), lim = p->mlim[a];
        if (x > lim) {
            f = fmin(f, lim / x);
        }
        if (x + raw_tol[a] > lim - dl) {
            f_lo = fmin(f_lo, (lim - dl) / (x + raw_tol[a]));
        }
        if (x - raw_tol[a] > lim + dl) {
            f_hi = fmin(f_hi, (lim + dl) / (x - raw_tol[a]));
        }
    }
    for (int a = 0; a < 2; a++) {
        o.m[a] = o.raw[a] * f;
        o.tol[a] = raw_tol[a];
        if (f_lo < 1.0) {
            /* f_lib m_lib - f m = f_lib (m_lib - m) + m (f_lib - f); the
             * factor rounded to UNIT and the product to NSUM (float: two
             * roundings); the hard clamp at the budget as held */
            const double mag = fabs(o.raw[a]) + raw_tol[a];
#if FC_NUMERIC_FIXED
            const double scale_round = mag * half_lsb(FC_UNIT_FRAC) + half_lsb(NSUM_FRAC);
#else
            const double scale_round = gamma_n(2) * mag * f_hi;
#endif
            o.tol[a] = f_hi * raw_tol[a] + fabs(o.raw[a]) * fmax(f_hi - f, f - f_lo) + scale_round + dl;
        }
    }
    o.tol[2] = raw_tol[2];
    if (fabs(o.m[2]) > p->mlim[2]) {
        o.m[2] = o.m[2] > 0.0 ? p->mlim[2] : -p->mlim[2];
    }
    if (fabs(o.raw[2]) + raw_tol[2] > p->mlim[2] - dl) {
        o.tol[2] += dl; /* a clamp moves by no more than its bound */
    }
    for (int i = 0; i < 3; i++) {
        o.tol[i] += NORM16_HALF_LSB;
    }
    return o;
}

/* From the attitudes: the error in double (ref_error), within error_tol_at(N)
 * of the step's: the whole step against the header. */
static ref_out ref_law(const ref_params *p, dq q, dq qd, const double w[3], const double wff[3],
                       const double integral[3])
{
    double err[3];
    ref_error(q, qd, err);
    return ref_core(p, err, error_tol_at(pair_n(q, qd)), w, wff, integral);
}

/* From the step's own error (its telemetry, exactly what it used): the law
 * alone, without the error's rounding (tested on its own above). */
static ref_out ref_law_at(const ref_params *p, fc_vec3 error_rad, const double w[3], const double wff[3],
                          const double integral[3])
{
    double err[3];
    vec_to(error_rad, FC_ANGLE_FRAC, err);
    return ref_core(p, err, 0.0, w, wff, integral);
}

/* The bound of an output on axis i: the budget as the step holds it (NSUM)
 * plus the output's rounding (a moment clamped there may round up to NORM16
 * by half an LSB). */
static double out_bound(const ref_params *r, int i)
{
    return r->mlim[i] + LIMIT_HALF_LSB + NORM16_HALF_LSB;
}

/* the largest |error| / tol of every comparison (printed at the end) */
static double g_worst_ratio = 0.0;

/* The library's output within ref->tol of ref->m on every axis; returns the
 * largest |error| / tol. */
static double assert_moment_within(const fc_vec3_16 *m, const ref_out *ref)
{
    const double got[3] = {DN(m->x), DN(m->y), DN(m->z)};
    double worst = 0.0;
    for (int i = 0; i < 3; i++) {
        const double err = fabs(got[i] - ref->m[i]);
        if (!(err <= ref->tol[i])) {
            print_error("axis %d: moment %.9g, reference %.9g, error %.3g, tolerance %.3g\n", i, got[i],
                        ref->m[i], err, ref->tol[i]);
            fail();
        }
        worst = fmax(worst, err / ref->tol[i]);
    }
    g_worst_ratio = fmax(g_worst_ratio, worst);
    return worst;
}

/* One step's input values, held by the test: fc_attitude_control_step reads
 * them by reference (step_sample). */
typedef struct att_sample {
    fc_quat attitude;
    fc_quat attitude_desired;
    fc_vec3 rate_radps;
    fc_vec3 rate_ff_radps;
    uint8_t allocation_saturation;
} att_sample;

static fc_step_status step_sample(fc_attitude_control *c, const att_sample *s, fc_attitude_control_output *out)
{
    const fc_attitude_control_input in = {&s->attitude, &s->attitude_desired, &s->rate_radps, &s->rate_ff_radps,
                                          s->allocation_saturation};
    return fc_attitude_control_step(c, &in, out);
}

static att_sample make_input(dq q, dq qd, const double w[3], const double wff[3])
{
    att_sample in;
    memset(&in, 0, sizeof in);
    in.attitude = to_fc(q);
    in.attitude_desired = to_fc(qd);
    in.rate_radps = vec_from(w, FC_RATE_FRAC);
    in.rate_ff_radps = vec_from(wff, FC_RATE_FRAC);
    in.allocation_saturation = 0u;
    return in;
}

/* the rates as the backend holds them */
static void rates_held(const double w[3], double out[3])
{
    for (int i = 0; i < 3; i++) {
        out[i] = D(RRATE(w[i]), FC_RATE_FRAC);
    }
}

static const double kZero3[3] = {0.0, 0.0, 0.0};

/* ---- init ------------------------------------------------------------- */

static void test_default_params(void **state)
{
    (void)state;
    const fc_attitude_control_params p = hexa_params();
    fc_attitude_control c;
    assert_int_equal(fc_attitude_control_init(&c, &p), FC_INIT_OK);
    const ref_params r = ref_from(&c);
    /* kp = wn^2, kd = 2 zeta wn: tilt wn 10 rad/s zeta 0.8, yaw wn 5 rad/s zeta 0.9 */
    assert_true(fabs(r.kp[0] - 100.0) < 1e-4 && fabs(r.kp[1] - 100.0) < 1e-4 && fabs(r.kp[2] - 25.0) < 1e-4);
    assert_true(fabs(r.kd[0] - 16.0) < 1e-4 && fabs(r.kd[1] - 16.0) < 1e-4 && fabs(r.kd[2] - 9.0) < 1e-4);
    assert_true(r.ki[0] == 0.0 && r.ki[1] == 0.0 && r.ki[2] == 0.0);
    assert_true(fabs(r.yaw_weight - 1.0) < 1e-6);
    /* default authority J * 50 rad/s^2, within 1e-7 N m (fixed: J rounded to
     * INERTIA, 4.7e-10 x 50, and the product to MOMENT, 3.0e-8), and the whole
     * of it as the budget */
    fc_attitude_control_params d;
    fc_attitude_control_default_params(&d, R(0.002, FC_DT_FRAC), vec_from(kCfJ, FC_INERTIA_FRAC));
    const double auth[3] = {D(d.authority_nm.x, FC_MOMENT_FRAC), D(d.authority_nm.y, FC_MOMENT_FRAC),
                            D(d.authority_nm.z, FC_MOMENT_FRAC)};
    for (int i = 0; i < 3; i++) {
        assert_true(fabs(auth[i] - 50.0 * kCfJ[i]) < 1e-7);
    }
    assert_true(d.moment_limit.x == FC_INT(1, RATIO) && d.moment_limit.y == FC_INT(1, RATIO) &&
                d.moment_limit.z == FC_INT(1, RATIO));
    assert_int_equal(fc_attitude_control_init(&c, &d), FC_INIT_OK);
}

static void expect_bad(const fc_attitude_control_params *p)
{
    fc_attitude_control c;
    memset(&c, 0xA5, sizeof c);
    assert_int_equal(fc_attitude_control_init(&c, p), FC_INIT_BAD_PARAM);
    const dq q = dq_axis_angle(1.0, 0.0, 0.0, 0.5);
    const att_sample in = make_input(q, dq_make(1.0, 0.0, 0.0, 0.0), kZero3, kZero3);
    fc_attitude_control_output out;
    memset(&out, 0x5A, sizeof out);
    assert_int_equal(step_sample(&c, &in, &out), FC_STEP_NOT_READY);
    assert_true(out.moment.x == FC_INT16(0, NORM16) && out.moment.y == FC_INT16(0, NORM16) &&
                out.moment.z == FC_INT16(0, NORM16));
}

/* Parameter set number k with one field spoiled; false past the last one. */
static bool spoil(fc_attitude_control_params *p, int k)
{
    /* clang-format off */
    switch (k) {
    case 0: p->dt_s = FC_INT(0, DT); break;
    case 1: p->dt_s = R(-0.002, FC_DT_FRAC); break;
    case 2: p->dt_s = R(1.5, FC_DT_FRAC); break;
    case 3: p->inertia_kgm2.x = FC_INT(0, INERTIA); break;
    case 4: p->inertia_kgm2.z = R(-0.1, FC_INERTIA_FRAC); break;
    case 5: p->kp_per_s2.y = R(-1.0, FC_GAIN_FRAC); break;
    case 6: p->kd_per_s.z = R(-0.5, FC_GAIN_FRAC); break;
    case 7: p->ki_per_s3.x = R(-0.5, FC_GAIN_FRAC); break;
    case 8: p->integral_limit_rad.y = FC_INT(0, ANGLE); break;
    case 9: p->yaw_weight = R(-0.1, FC_RATIO_FRAC); break;
    case 10: p->yaw_weight = R(1.1, FC_RATIO_FRAC); break;
    case 11: p->moment_limit.z = FC_INT(0, RATIO); break;
    case 12: p->moment_limit.x = R(-0.5, FC_RATIO_FRAC); break;
    case 13: p->authority_nm.x = FC_INT(0, MOMENT); break;
    case 14: p->authority_nm.z = R(-4.0, FC_MOMENT_FRAC); break;
    /* above the ranges (in fixed the conversion saturates, still above) */
    case 15: p->kd_per_s.x = R(40000.0, FC_GAIN_FRAC); break;
    case 16: p->inertia_kgm2.y = R(2.5, FC_INERTIA_FRAC); break;
    case 17: p->moment_limit.y = R(2.5, FC_RATIO_FRAC); break;
    case 18: p->integral_limit_rad.x = R(5.0, FC_ANGLE_FRAC); break;
    case 19: p->authority_nm.y = R(120.0, FC_MOMENT_FRAC); break;
#if !FC_NUMERIC_FIXED
    case 20: p->dt_s = NAN; break;
    case 21: p->kp_per_s2.x = INFINITY; break;
    case 22: p->inertia_kgm2.y = NAN; break;
    case 23: p->yaw_weight = NAN; break;
    case 24: p->moment_limit.y = INFINITY; break;
    case 25: p->integral_limit_rad.z = NAN; break;
    case 26: p->authority_nm.x = NAN; break;
#endif
    default: return false;
    }
    /* clang-format on */
    return true;
}

static void test_bad_params(void **state)
{
    (void)state;
    const fc_attitude_control_params good = hexa_params();
    fc_attitude_control_params p = good;
    int n = 0;
    while (spoil(&p, n)) {
        expect_bad(&p);
        p = good;
        n++;
    }
    assert_int_equal(n, FC_NUMERIC_FIXED ? 20 : 27);
    /* the edges are accepted: zero gains, yaw_weight 0 and 1 */
    fc_attitude_control c;
    p = good;
    p.kp_per_s2 = vec_all(0.0, FC_GAIN_FRAC);
    p.yaw_weight = FC_INT(0, RATIO);
    assert_int_equal(fc_attitude_control_init(&c, &p), FC_INIT_OK);
    /* a zeroed, never initialised controller is not ready either */
    memset(&c, 0, sizeof c);
    const att_sample in =
        make_input(dq_make(1.0, 0.0, 0.0, 0.0), dq_make(1.0, 0.0, 0.0, 0.0), kZero3, kZero3);
    fc_attitude_control_output out;
    assert_int_equal(step_sample(&c, &in, &out), FC_STEP_NOT_READY);
}

/* ---- normalised units ------------------------------------------------- */

/* The stored constants of an initialised controller against k J / authority
 * and (J_k - J_j) / authority computed in double from its raw parameters,
 * each within gain_const_tol / dj_const_tol (fixed: half an LSB of the 16-bit
 * format plus the 32-bit roundings before it). Returns the largest
 * |error| / bound. */
static double assert_constants(const fc_attitude_control *c)
{
    const ref_params r = ref_from(c); /* constants from the parameters, in double */
    const ref_params s = ref_stored(c);
    double worst = 0.0;
    for (int i = 0; i < 3; i++) {
        const double got[4] = {s.gp[i], s.gi[i], s.gd[i], s.dj[i]};
        const double want[4] = {r.gp[i], r.gi[i], r.gd[i], r.dj[i]};
        const double tol[4] = {r.gp_tol[i], r.gi_tol[i], r.gd_tol[i], r.dj_tol[i]};
        for (int k = 0; k < 4; k++) {
            const double err = fabs(got[k] - want[k]);
            if (!(err <= tol[k])) {
                print_error("axis %d constant %d (Kp, Ki, Kd, dJ): stored %.12g, k J / A %.12g, error %.3g, "
                            "bound %.3g\n",
                            i, k, got[k], want[k], err, tol[k]);
                fail();
            }
            if (tol[k] > 0.0) {
                worst = fmax(worst, err / tol[k]);
            }
        }
    }
    return worst;
}

/* m = -Kp e per axis with Kp = kp J / authority from the parameters (not from
 * what init derived): J and authority differ per axis and J / authority is
 * 0.025, 0.016, 0.12 (not 1, so an unnormalised moment is far outside the
 * tolerance); kd and ki set (their constants are checked) but zero rate and
 * integral, no w x J w, a 6 deg tilt about (1, -2, 0) and a 4 deg heading
 * error, e the step's own error (its telemetry; yaw_weight 1). The stored
 * constants Kp, Ki, Kd, dJ against k J / authority. Then init's range of J /
 * authority and of the authority. */
static void test_normalisation(void **state)
{
    (void)state;
    static const double kJ[3] = {0.03, 0.05, 0.09};
    static const double kA[3] = {1.2, 3.1, 0.75};
    const double kp = 64.0; /* exact in GAIN and in float */
    fc_attitude_control_params p;
    fc_attitude_control_default_params(&p, R(0.002, FC_DT_FRAC), vec_from(kJ, FC_INERTIA_FRAC));
    p.kp_per_s2 = vec_all(kp, FC_GAIN_FRAC);
    p.kd_per_s = vec_all(9.7, FC_GAIN_FRAC);
    p.ki_per_s3 = vec_all(23.3, FC_GAIN_FRAC);
    p.yaw_weight = FC_INT(1, RATIO);
    p.authority_nm = vec_from(kA, FC_MOMENT_FRAC);
    p.moment_limit = vec_all(1.0, FC_RATIO_FRAC);
    fc_attitude_control c;
    assert_int_equal(fc_attitude_control_init(&c, &p), FC_INIT_OK);

    /* the stored 16-bit constants, within their bounds of k J / A */
    const double worst_const = assert_constants(&c);
    print_message("normalisation (%s): stored constants within %.2f of their bound of k J / A\n",
                  FC_NUMERIC_FIXED ? "fixed" : "float", worst_const);
    const ref_params r = ref_from(&c);
    for (int i = 0; i < 3; i++) {
        /* not vacuous: each bound far below its constant (0.05 % of the
         * smallest, Kd = 9.7 x 0.016; dJ 0.02..0.033) */
        assert_true(r.gp_tol[i] < 5e-4 * r.gp[i] && r.gi_tol[i] < 5e-4 * r.gi[i] &&
                    r.gd_tol[i] < 1e-3 * r.gd[i] && r.dj_tol[i] < 1e-3 * fabs(r.dj[i]));
    }

    const dq qd = dq_make(1.0, 0.0, 0.0, 0.0);
    const dq q = dq_mul(dq_axis_angle(0.0, 0.0, 1.0, 4.0 * kDeg), dq_axis_angle(1.0, -2.0, 0.0, 6.0 * kDeg));
    const att_sample in = make_input(q, qd, kZero3, kZero3);
    fc_attitude_control_output out;
    assert_int_equal(step_sample(&c, &in, &out), FC_STEP_OK);
    const double e[3] = {D(out.attitude_error_rad.x, FC_ANGLE_FRAC), D(out.attitude_error_rad.y, FC_ANGLE_FRAC),
                         D(out.attitude_error_rad.z, FC_ANGLE_FRAC)};
    /* the error is the one asked for: (0.047, -0.094, 0.070) rad */
    double e_ref[3];
    ref_error(q, qd, e_ref);
    const double m[3] = {DN(out.moment.x), DN(out.moment.y), DN(out.moment.z)};
    const double jn_held[3] = {D(c.inertia_norm.x, FC_INERTIA_FRAC), D(c.inertia_norm.y, FC_INERTIA_FRAC),
                               D(c.inertia_norm.z, FC_INERTIA_FRAC)};
    for (int i = 0; i < 3; i++) {
        assert_true(fabs(e[i] - e_ref[i]) < ERROR_TOL_RAD && fabs(e[i]) > 0.04);
        const double jn = kJ[i] / kA[i];
        /* Kp = kp J / A from the raw parameters (J and A as given to init) */
        const double gain = r.gp[i];
        const double expect = -gain * e[i];
#if FC_NUMERIC_FIXED
        /* J / authority as init holds it (32-bit): J rounded to INERTIA
         * (2^-31), the authority to MOMENT (2^-25), the quotient to INERTIA
         * (2^-31) */
        const double jn_tol = jn * (ldexp(1.0, -31) / kJ[i] + ldexp(1.0, -25) / kA[i]) + ldexp(1.0, -31);
        /* Kp stored (its bound, times |e|), e to ANGLE16 (2^-13, times Kp),
         * Kp e to NSUM (2^-23), the output to NORM16 (2^-15) */
        const double tol = r.gp_tol[i] * fabs(e[i]) + (gain + r.gp_tol[i]) * half_lsb(ANGLE16_FRAC) +
                           half_lsb(NSUM_FRAC) + NORM16_HALF_LSB;
#else
        /* relative roundings of u = 2^-24: J, the authority (a divisor) and
         * J / authority; then Kp stored (two roundings) and Kp e (one; the
         * zero terms of the sums add exactly; fc_real16 is float: no NORM16
         * rounding) */
        const double u = FLOAT_U;
        const double jn_tol = ((1.0 + u) * (1.0 + u) / (1.0 - u) - 1.0) * jn;
        const double tol = (pow(1.0 + u, 3.0) - 1.0) * fabs(expect);
#endif
        if (!(fabs(jn_held[i] - jn) <= jn_tol && fabs(m[i] - expect) <= tol)) {
            print_error("axis %d: J/A %.12g (expected %.12g, tolerance %.3g), moment %.9g (expected %.9g, "
                        "tolerance %.3g)\n",
                        i, jn_held[i], jn, jn_tol, m[i], expect, tol);
            fail();
        }
        /* not vacuous: the tolerance is far below the moment (fixed: mostly
         * e to ANGLE16, 2^-13 of an error of 0.047..0.094 rad; J / A is 8 to 60
         * times from 1: an unnormalised moment is far outside) */
        assert_true(tol < 5e-3 * fabs(expect));
    }

    /* init: J / authority above 1.99 (2.0, 1.995, 9e4) and an authority <= 0
     * are rejected; 1.98 is accepted. The gains here are small (k J / A < 8
     * at J / A = 2: the normalised gains are not what is rejected) */
    fc_attitude_control_params small = p;
    small.kp_per_s2 = vec_all(3.0, FC_GAIN_FRAC);
    small.kd_per_s = vec_all(1.0, FC_GAIN_FRAC);
    small.ki_per_s3 = vec_all(0.5, FC_GAIN_FRAC);
    fc_attitude_control_params bad = small;
    bad.authority_nm.z = R(kJ[2] / 2.0, FC_MOMENT_FRAC);
    expect_bad(&bad);
    bad = small;
    bad.authority_nm.x = R(kJ[0] / 1.995, FC_MOMENT_FRAC);
    expect_bad(&bad);
    bad = small;
    bad.authority_nm.z = R(1.0e-6, FC_MOMENT_FRAC);
    expect_bad(&bad);
    bad = small;
    bad.authority_nm.y = FC_INT(0, MOMENT);
    expect_bad(&bad);
    bad = small;
    bad.authority_nm.z = R(-0.75, FC_MOMENT_FRAC);
    expect_bad(&bad);
    fc_attitude_control_params edge = small;
    edge.authority_nm.z = R(kJ[2] / 1.98, FC_MOMENT_FRAC);
    assert_int_equal(fc_attitude_control_init(&c, &edge), FC_INIT_OK);
    assert_true(fabs(D(c.inertia_norm.z, FC_INERTIA_FRAC) - 1.98) < 1e-5);
    (void)assert_constants(&c);
}

/* Init's range of the step's 16-bit constants (header): a normalised gain k J
 * / authority of 8 or more and |J_k - J_j| / authority of 1 s^2 or more are
 * FC_INIT_BAD_PARAM, each on its own axis and gain; 7.98 and 0.98 are
 * accepted and stored within their bounds. */
static void test_normalised_ranges(void **state)
{
    (void)state;
    /* the hexa at the default authority: J / A = 1/50 on every axis, the
     * default gains (Kp 2, 2, 0.5) */
    const fc_attitude_control_params good = hexa_params();
    fc_attitude_control c;
    assert_int_equal(fc_attitude_control_init(&c, &good), FC_INIT_OK);
    const ref_params r0 = ref_from(&c);
    /* k for a normalised gain g on axis i (J / A from the parameters) */
#define K_FOR(g, i) R((g) / (r0.j[i] / r0.auth[i]), FC_GAIN_FRAC)
    fc_attitude_control_params p = good;
    p.kp_per_s2.x = K_FOR(8.0, 0);
    expect_bad(&p);
    p = good;
    p.kp_per_s2.z = K_FOR(8.5, 2);
    expect_bad(&p);
    p = good;
    p.kd_per_s.y = K_FOR(8.0, 1);
    expect_bad(&p);
    p = good;
    p.ki_per_s3.z = K_FOR(9.0, 2);
    expect_bad(&p);
    /* just under 7.99: accepted, stored near 7.98 (NGAIN16 reaches 7.9998) */
    p = good;
    p.kp_per_s2.y = K_FOR(7.98, 1);
    p.kd_per_s.z = K_FOR(7.98, 2);
    p.ki_per_s3.x = K_FOR(7.98, 0);
    assert_int_equal(fc_attitude_control_init(&c, &p), FC_INIT_OK);
    (void)assert_constants(&c);
    const ref_params s = ref_stored(&c);
    assert_true(fabs(s.gp[1] - 7.98) < 1e-3 && fabs(s.gd[2] - 7.98) < 1e-3 && fabs(s.gi[0] - 7.98) < 1e-3);
#undef K_FOR

    /* |dJ| / authority: J and authority of 1 kg m^2 and 1 N m scale, gains
     * small (J / A up to 1.5, k J / A < 8) */
    fc_attitude_control_params d = good;
    d.kp_per_s2 = vec_all(4.0, FC_GAIN_FRAC);
    d.kd_per_s = vec_all(2.0, FC_GAIN_FRAC);
    d.ki_per_s3 = vec_all(1.0, FC_GAIN_FRAC);
    d.authority_nm = vec_all(1.0, FC_MOMENT_FRAC);
    d.moment_limit = vec_all(1.0, FC_RATIO_FRAC);
    static const double kBadJ[3][3] = {
        {1.2, 0.2, 0.2},  /* dJ = (0, 1.0, -1.0): both signs at 1 */
        {1.5, 0.2, 0.2},  /* (0, 1.3, -1.3) */
        {0.2, 0.2, 1.21}, /* (1.01, -1.01, 0): roll */
    };
    for (int k = 0; k < 3; k++) {
        p = d;
        p.inertia_kgm2 = vec_from(kBadJ[k], FC_INERTIA_FRAC);
        expect_bad(&p);
    }
    /* over the authority: Jx - Jz = 0.5 kg m^2 with 0.5 N m on y is 1.0 s^2 */
    p = d;
    p.inertia_kgm2 = vec_all(0.1, FC_INERTIA_FRAC);
    p.inertia_kgm2.x = R(0.6, FC_INERTIA_FRAC);
    p.authority_nm.y = R(0.5, FC_MOMENT_FRAC);
    p.authority_nm.z = R(0.5, FC_MOMENT_FRAC);
    expect_bad(&p);
    p.authority_nm.y = R(0.52, FC_MOMENT_FRAC); /* 0.96 s^2 on y, -1.0 on z */
    expect_bad(&p);
    p.authority_nm.z = R(0.52, FC_MOMENT_FRAC); /* 0.96 and -0.96 */
    assert_int_equal(fc_attitude_control_init(&c, &p), FC_INIT_OK);
    /* just under: 0.98 and -0.98 */
    static const double kEdgeJ[3] = {1.18, 0.2, 0.2};
    p = d;
    p.inertia_kgm2 = vec_from(kEdgeJ, FC_INERTIA_FRAC);
    assert_int_equal(fc_attitude_control_init(&c, &p), FC_INIT_OK);
    (void)assert_constants(&c);
    const ref_params sd = ref_stored(&c);
    assert_true(fabs(sd.dj[1] - 0.98) < 1e-4 && fabs(sd.dj[2] + 0.98) < 1e-4 && sd.dj[0] == 0.0);
}

/* ---- the error quaternion ---------------------------------------------- */

/* q and -q (and q_d and -q_d) are one attitude: the same moment. A 150 deg
 * error is corrected the short way (against its axis), a 210 deg one too. */
static void test_error_sign(void **state)
{
    (void)state;
    const fc_attitude_control_params p = hexa_params();
    fc_attitude_control c;
    assert_int_equal(fc_attitude_control_init(&c, &p), FC_INIT_OK);
    const ref_params r = ref_from(&c);
    const dq qd = dq_axis_angle(0.2, -0.4, 1.0, 0.7);
    const double w[3] = {0.3, -0.2, 0.1};
    double held_w[3];
    rates_held(w, held_w);
    const double angles[] = {0.4, 150.0 * kDeg, 210.0 * kDeg};
    for (int a = 0; a < 3; a++) {
        /* the current attitude: qd turned by the angle about body axis (1, 2, 0.5) */
        const dq q = dq_mul(qd, dq_axis_angle(1.0, 2.0, 0.5, angles[a]));
        fc_vec3_16 m[4];
        const dq qs[4] = {q, dq_neg(q), q, dq_neg(q)};
        const dq qds[4] = {qd, qd, dq_neg(qd), dq_neg(qd)};
        for (int k = 0; k < 4; k++) {
            const att_sample in = make_input(qs[k], qds[k], w, kZero3);
            fc_attitude_control_output out;
            const fc_step_status st = step_sample(&c, &in, &out);
            assert_int_equal(st & (FC_STEP_BAD_INPUT | FC_STEP_NOT_READY | FC_STEP_ARITH_SATURATED), 0);
            m[k] = out.moment;
        }
        const ref_out ref = ref_law(&r, from_fc(to_fc(q)), from_fc(to_fc(qd)), held_w, kZero3, kZero3);
        for (int k = 0; k < 4; k++) {
            (void)assert_moment_within(&m[k], &ref);
        }
        /* the direction: the P part opposes the error axis for 150 deg, follows it for 210 */
        const ref_out no_rate = ref_law(&r, q, qd, kZero3, kZero3, kZero3);
        const double along = no_rate.m[0] * 1.0 + no_rate.m[1] * 2.0 + no_rate.m[2] * 0.5;
        if (angles[a] < kPi) {
            assert_true(along < 0.0);
        } else {
            assert_true(along > 0.0);
        }
    }
}

/* (2.9) q_e = q (x) q_d*, its vector part taken into the body frame, is the
 * error the library uses: for a tilt error, attitude_error = 2 vec(q_d* (x) q)
 * = 2 R(q)^T vec(q (x) q_d*) (shortest sign). Checked with the library's own
 * quaternion functions against the step's telemetry. */
static void test_error_is_2_9_in_body_frame(void **state)
{
    (void)state;
    const fc_attitude_control_params p = hexa_params();
    fc_attitude_control c;
    assert_int_equal(fc_attitude_control_init(&c, &p), FC_INIT_OK);
    /* same heading 1.1 rad, desired tilted 10 deg about x, current 35 deg about (1, -1, 0) */
    const dq yaw = dq_axis_angle(0.0, 0.0, 1.0, 1.1);
    const dq qd = dq_mul(yaw, dq_axis_angle(1.0, 0.0, 0.0, 10.0 * kDeg));
    const dq q = dq_mul(qd, dq_axis_angle(1.0, -1.0, 0.0, 35.0 * kDeg));
    const att_sample in = make_input(q, qd, kZero3, kZero3);
    fc_attitude_control_output out;
    step_sample(&c, &in, &out);

    fc_arith ar = {0u};
    const fc_quat qe_world =
        fc_quat_shortest(&ar, fc_quat_mul(&ar, in.attitude, fc_quat_conj(&ar, in.attitude_desired)));
    const fc_vec3 v_body = fc_quat_rotate_inv(&ar, in.attitude, fc_quat_vector_part(qe_world));
    const double expect[3] = {2.0 * D(v_body.x, FC_UNIT_FRAC), 2.0 * D(v_body.y, FC_UNIT_FRAC),
                              2.0 * D(v_body.z, FC_UNIT_FRAC)};
    const double got[3] = {D(out.attitude_error_rad.x, FC_ANGLE_FRAC),
                           D(out.attitude_error_rad.y, FC_ANGLE_FRAC),
                           D(out.attitude_error_rad.z, FC_ANGLE_FRAC)};
    /* the body error axis is (1, -1, 0)/sqrt 2 with 2 sin(35/2 deg) */
    const double mag = 2.0 * sin(17.5 * kDeg) / sqrt(2.0);
    for (int i = 0; i < 3; i++) {
        assert_true(fabs(got[i] - expect[i]) < ERROR_TOL_RAD);
    }
    assert_true(fabs(got[0] - mag) < ERROR_TOL_RAD && fabs(got[1] + mag) < ERROR_TOL_RAD &&
                fabs(got[2]) < ERROR_TOL_RAD);
}

/* The error against ref_error for random attitude pairs, every tilt and
 * heading error, within error_tol_at(N). */
/* |library - reference| x N of the attitude error of one pair (N = cos(tilt_e
 * / 2), which the heading split divides by) */
static double error_pair_worst(fc_attitude_control *c, const fc_attitude_control_params *p, dq q, dq qd)
{
    assert_int_equal(fc_attitude_control_init(c, p), FC_INIT_OK);
    const att_sample in = make_input(q, qd, kZero3, kZero3);
    fc_attitude_control_output out;
    (void)step_sample(c, &in, &out);
    /* the reference from the quaternions as the backend holds them */
    double ref[3];
    ref_error(from_fc(in.attitude), from_fc(in.attitude_desired), ref);
    const double got[3] = {D(out.attitude_error_rad.x, FC_ANGLE_FRAC), D(out.attitude_error_rad.y, FC_ANGLE_FRAC),
                           D(out.attitude_error_rad.z, FC_ANGLE_FRAC)};
    const dq e_ref = dq_mul(dq_conj(from_fc(in.attitude_desired)), from_fc(in.attitude));
    const double n = sqrt(e_ref.w * e_ref.w + e_ref.z * e_ref.z);
    double worst = 0.0;
    for (int i = 0; i < 3; i++) {
        const double e = fabs(got[i] - ref[i]) * n; /* N >= 0.01: the heading split's threshold */
        worst = e > worst ? e : worst;
    }
    return worst;
}

static void test_error_accuracy(void **state)
{
    (void)state;
    const fc_attitude_control_params p = hexa_params();
    fc_attitude_control c;
    ts_rng rng = ts_rng_seed(4242u);
    double worst = 0.0;
    for (int k = 0; k < 20000; k++) {
        double v[8];
        for (int i = 0; i < 8; i++) {
            v[i] = (double)ts_rand_u32(&rng) / 4294967296.0 * 2.0 - 1.0;
        }
        const dq q = dq_normalize(dq_make(v[0], v[1], v[2], v[3]));
        const dq qd = dq_normalize(dq_make(v[4], v[5], v[6], v[7]));
        worst = fmax(worst, error_pair_worst(&c, &p, q, qd));
    }
    /* small tilt errors, on both sides of where the half heading takes the
     * root's series (1 - N^2 = 2^-7 in fixed, a tilt error of 10.1 deg; 2^-12
     * in float, 1.8 deg), any heading error */
    for (int k = 0; k < 20000; k++) {
        double v[8];
        for (int i = 0; i < 8; i++) {
            v[i] = (double)ts_rand_u32(&rng) / 4294967296.0;
        }
        const dq qd = dq_normalize(dq_make(2.0 * v[0] - 1.0, 2.0 * v[1] - 1.0, 2.0 * v[2] - 1.0, 2.0 * v[3] - 1.0));
        const double tilt = (k % 2 == 0 ? 12.0 : 3.0) * kDeg * v[4];
        const dq tilt_q = dq_axis_angle(cos(2.0 * kPi * v[5]), sin(2.0 * kPi * v[5]), 0.0, tilt);
        const dq head_q = dq_axis_angle(0.0, 0.0, 1.0, (2.0 * v[6] - 1.0) * kPi);
        const dq q = dq_normalize(dq_mul(qd, v[7] < 0.5 ? dq_mul(head_q, tilt_q) : dq_mul(tilt_q, head_q)));
        worst = fmax(worst, error_pair_worst(&c, &p, q, qd));
    }
    print_message("attitude error (%s): worst %.3g rad x N over 40000 pairs (tolerance %.3g)\n",
                  FC_NUMERIC_FIXED ? "fixed" : "float", worst, error_tol_at(1.0));
    assert_true(worst <= error_tol_at(1.0));
}

/* A pure heading error gives a pure z moment, also about a tilted desired
 * attitude (the error rotation about the body z axis). */
static void test_pure_yaw(void **state)
{
    (void)state;
    fc_attitude_control_params p = hexa_params();
    /* unclamped here (|Mz| up to 7.1 N m, 0.95 of the authority; st == OK below) */
    p.moment_limit = vec_all(LIMIT_MAX, FC_RATIO_FRAC);
    fc_attitude_control c;
    assert_int_equal(fc_attitude_control_init(&c, &p), FC_INIT_OK);
    const ref_params r = ref_from(&c);
    const dq desired[2] = {dq_make(1.0, 0.0, 0.0, 0.0), dq_axis_angle(0.6, 0.8, 0.0, 25.0 * kDeg)};
    const double psi[3] = {0.3, -1.2, 2.5};
    for (int d = 0; d < 2; d++) {
        for (int k = 0; k < 3; k++) {
            const dq q = dq_mul(desired[d], dq_axis_angle(0.0, 0.0, 1.0, psi[k]));
            const att_sample in = make_input(q, desired[d], kZero3, kZero3);
            fc_attitude_control_output out;
            const fc_step_status st = step_sample(&c, &in, &out);
            assert_int_equal(st, FC_STEP_OK);
            const ref_out ref =
                ref_law(&r, from_fc(in.attitude), from_fc(in.attitude_desired), kZero3, kZero3, kZero3);
            (void)assert_moment_within(&out.moment, &ref);
            /* the reference is the header's: no roll or pitch, Mz / authority_z
             * = -(kp_z Jz / authority_z) 2 sin(psi/2) (up to the quaternions'
             * rounding to the held format: 1e-6 of Kp) */
            const double mz = -r.gp[2] * 2.0 * sin(psi[k] / 2.0);
            assert_true(fabs(ref.m[0]) <= 1e-6 * r.gp[2] && fabs(ref.m[1]) <= 1e-6 * r.gp[2] &&
                        fabs(ref.m[2] - mz) <= 1e-6 * r.gp[2]);
            assert_true(fabs(D(out.attitude_error_rad.z, FC_ANGLE_FRAC) - 2.0 * sin(psi[k] / 2.0)) < ERROR_TOL_RAD);
        }
    }
}

/* The tilt part does not depend on the heading error; yaw_weight scales only
 * the heading part (0: heading ignored, yaw rate still damped). */
static void test_tilt_heading_split(void **state)
{
    (void)state;
    fc_attitude_control_params p = hexa_params();
    /* unclamped here (|M| up to 5.6 N m, 1.4 of the authority; checked below) */
    p.moment_limit = vec_all(LIMIT_MAX, FC_RATIO_FRAC);
    fc_attitude_control c;
    const dq qd = dq_axis_angle(0.0, 0.0, 1.0, 0.8);
    const dq tilt = dq_axis_angle(0.5, 1.0, 0.0, 40.0 * kDeg); /* world axis: horizontal */
    const double w[3] = {0.0, 0.0, 0.5};
    for (int weight = 0; weight <= 2; weight++) {
        p.yaw_weight = R(0.5 * weight, FC_RATIO_FRAC);
        assert_int_equal(fc_attitude_control_init(&c, &p), FC_INIT_OK);
        const ref_params r = ref_from(&c);
        fc_vec3_16 m_tilt_only = fc_vec3_16_zero();
        ref_out ref_tilt_only;
        memset(&ref_tilt_only, 0, sizeof ref_tilt_only);
        for (int k = 0; k < 2; k++) {
            /* current heading 0.8 (= desired) or 0.8 - 1.0 rad, both tilted by 40 deg */
            const dq q = dq_mul(tilt, dq_axis_angle(0.0, 0.0, 1.0, 0.8 - 1.0 * k));
            const att_sample in = make_input(q, qd, w, kZero3);
            fc_attitude_control_output out;
            assert_int_equal(step_sample(&c, &in, &out), FC_STEP_OK);
            double held_w[3];
            rates_held(w, held_w);
            const ref_out ref =
                ref_law(&r, from_fc(in.attitude), from_fc(in.attitude_desired), held_w, kZero3, kZero3);
            (void)assert_moment_within(&out.moment, &ref);
            /* the tilt error is 2 sin(20 deg) whatever the heading error */
            const double ex = D(out.attitude_error_rad.x, FC_ANGLE_FRAC);
            const double ey = D(out.attitude_error_rad.y, FC_ANGLE_FRAC);
            assert_true(fabs(sqrt(ex * ex + ey * ey) - 2.0 * sin(20.0 * kDeg)) < ERROR_TOL_RAD);
            if (k == 0) {
                m_tilt_only = out.moment;
                ref_tilt_only = ref;
            } else {
                /* the tilt axis in the body turns with the heading, its size
                 * does not: the references' sizes agree (up to the
                 * quaternions' rounding to the held format: 1e-6 of Kp), the
                 * library's each within the hypot of its tolerances */
                const double a0 = hypot(DN(m_tilt_only.x), DN(m_tilt_only.y));
                const double a1 = hypot(DN(out.moment.x), DN(out.moment.y));
                const double ref_diff =
                    fabs(hypot(ref_tilt_only.m[0], ref_tilt_only.m[1]) - hypot(ref.m[0], ref.m[1]));
                assert_true(ref_diff <= 1e-6 * r.gp[0]);
                assert_true(fabs(a0 - a1) <= hypot(ref_tilt_only.tol[0], ref_tilt_only.tol[1]) +
                                                 hypot(ref.tol[0], ref.tol[1]) + ref_diff);
                /* heading error -1 rad -> error.z = -2 sin(0.5);
                 * Mz / authority_z = -(Jz / authority_z) (kp w e_z + kd wz) */
                const double ez = D(out.attitude_error_rad.z, FC_ANGLE_FRAC);
                assert_true(fabs(ez + 2.0 * sin(0.5)) < ERROR_TOL_RAD);
                const double mz = -(r.gp[2] * r.yaw_weight * ez + r.gd[2] * held_w[2]);
                /* that is the law at the step's own error (its telemetry),
                 * the library within that law's tolerance */
                const ref_out at = ref_law_at(&r, out.attitude_error_rad, held_w, kZero3, kZero3);
                assert_true(fabs(at.m[2] - mz) < 1e-12);
                assert_true(fabs(DN(out.moment.z) - mz) <= at.tol[2]);
            }
        }
    }
}

/* ---- the moment budget: roll and pitch first ------------------------- */

static void test_short_budget_tilt_first(void **state)
{
    (void)state;
    fc_attitude_control_params p = hexa_params();
    /* short budget: 1 N m roll/pitch, 0.2 N m yaw (0.244, 0.244, 0.0268 of the authority) */
    p.moment_limit = limit_of(&p, 1.0, 1.0, 0.2);
    fc_attitude_control c;
    assert_int_equal(fc_attitude_control_init(&c, &p), FC_INIT_OK);
    const ref_params r = ref_from(&c);
    const dq qd = dq_make(1.0, 0.0, 0.0, 0.0);
    /* tilt about the body axis at 30 deg from x: sizes 5 deg (inside the budget)
     * and 30 deg (Jx kp 2 sin 15 = 4.2 N m, far outside) */
    const double tilts[2] = {5.0 * kDeg, 30.0 * kDeg};
    for (int t = 0; t < 2; t++) {
        const dq q_tilt = dq_axis_angle(cos(30.0 * kDeg), sin(30.0 * kDeg), 0.0, tilts[t]);
        /* the same tilt with a 90 deg heading error on top (yaw demand 0.149*25*1.41 = 5.3 N m) */
        const dq q_both = dq_mul(dq_axis_angle(0.0, 0.0, 1.0, 90.0 * kDeg), q_tilt);
        fc_attitude_control_output out_tilt, out_both;
        const att_sample in_tilt = make_input(q_tilt, qd, kZero3, kZero3);
        const att_sample in_both = make_input(q_both, qd, kZero3, kZero3);
        const fc_step_status st_tilt = step_sample(&c, &in_tilt, &out_tilt);
        const fc_step_status st_both = step_sample(&c, &in_both, &out_both);
        const ref_out ref_tilt = ref_law(&r, from_fc(in_tilt.attitude), qd, kZero3, kZero3, kZero3);
        const ref_out ref = ref_law(&r, from_fc(in_both.attitude), qd, kZero3, kZero3, kZero3);
        (void)assert_moment_within(&out_tilt.moment, &ref_tilt);
        (void)assert_moment_within(&out_both.moment, &ref);
        /* roll and pitch keep their full moment (the same as without the
         * heading error): so in the reference (up to the quaternions'
         * rounding to the held format: 1e-6 of Kp), and the library's two
         * within their two tolerances */
        for (int i = 0; i < 2; i++) {
            const double ref_diff = fabs(ref.m[i] - ref_tilt.m[i]);
            assert_true(ref_diff <= 1e-6 * r.gp[i]);
            assert_true(fabs(DN(i == 0 ? out_both.moment.x : out_both.moment.y) -
                             DN(i == 0 ? out_tilt.moment.x : out_tilt.moment.y)) <=
                        ref.tol[i] + ref_tilt.tol[i] + ref_diff);
        }
        /* yaw gets its own budget and no more: -limit exactly in NSUM (the
         * budget rounded to it), so the output is that rounded to NORM16 */
        assert_true(fabs(DN(out_both.moment.z) + r.mlim[2]) <= LIMIT_HALF_LSB + NORM16_HALF_LSB);
        assert_true((st_both & FC_STEP_OUTPUT_LIMITED) != 0u);
        if (t == 0) {
            /* inside the budget: roll/pitch untouched, only yaw clamped */
            assert_int_equal(st_tilt & FC_STEP_OUTPUT_LIMITED, 0);
            assert_true(fabs(ref.raw[0] - ref.m[0]) < 1e-12 && fabs(ref.raw[1] - ref.m[1]) < 1e-12);
        } else {
            /* outside: roll at its limit, pitch scaled with it so the tilt axis is kept
             * (My/Mx = tan 30 deg), never reduced further to give yaw room */
            assert_true((st_tilt & FC_STEP_OUTPUT_LIMITED) != 0u);
            const double mx = DN(out_both.moment.x), my = DN(out_both.moment.y);
            /* at the budget as held (NSUM), the factor's rounding to UNIT
             * (2^-31 of the raw moment) and the product's to NSUM (float: two
             * roundings of the limit), the output's rounding to NORM16 */
            const double at_limit_tol =
                LIMIT_HALF_LSB +
                (FC_NUMERIC_FIXED ? (fabs(ref.raw[0]) + ref.tol[0]) * half_lsb(FC_UNIT_FRAC) + half_lsb(NSUM_FRAC)
                                  : gamma_n(2) * r.mlim[0]) +
                NORM16_HALF_LSB;
            assert_true(fabs(fabs(mx) - r.mlim[0]) <= at_limit_tol);
            /* the tilt axis' direction to the error's rounding (with, in
             * fixed, its rounding to ANGLE16; Kp x = Kp y) over its size
             * 2 sin(tilt/2); d tan / d angle = 1.34 at 30 deg. The output's
             * rounding (h each) moves my/mx by up to h (1 + |my/mx|) / |mx|. */
            const double ratio_tol =
                1e-5 + 1.34 * (ERROR_TOL_RAD + half_lsb(ANGLE16_FRAC)) / (2.0 * sin(tilts[t] / 2.0)) +
                NORM16_HALF_LSB * (1.0 + tan(30.0 * kDeg)) / fabs(mx);
            assert_true(fabs(my / mx - tan(30.0 * kDeg)) < ratio_tol);
            assert_true(fabs(my) < r.mlim[1]);
        }
        /* always inside the limits (and their rounding to NORM16) */
        assert_true(fabs(DN(out_both.moment.x)) <= out_bound(&r, 0) &&
                    fabs(DN(out_both.moment.y)) <= out_bound(&r, 1) &&
                    fabs(DN(out_both.moment.z)) <= out_bound(&r, 2));
    }
}

/* ---- the integral and its anti-windup --------------------------------- */

static fc_step_status step_with(fc_attitude_control *c, dq q, uint8_t sat, fc_attitude_control_output *out)
{
    att_sample in = make_input(q, dq_make(1.0, 0.0, 0.0, 0.0), kZero3, kZero3);
    in.allocation_saturation = sat;
    return step_sample(c, &in, out);
}

/* hold_integral: the integrals stay where they are (and still act on the
 * moment) until released; init clears the hold */
static void test_integral_hold(void **state)
{
    (void)state;
    fc_attitude_control_params p = hexa_params();
    p.ki_per_s3 = vec_all(20.0, FC_GAIN_FRAC);
    p.integral_limit_rad = vec_all(0.05, FC_ANGLE_FRAC);
    fc_attitude_control c;
    assert_int_equal(fc_attitude_control_init(&c, &p), FC_INIT_OK);
    const ref_params r = ref_from(&c);
    const dq q = dq_axis_angle(1.0, 1.0, 1.0, 5.0 * kDeg);
    fc_attitude_control_output out;
    /* 400 steps of 0.05 rad (per axis) x 2 ms: I = 0.04 rad s (below the
     * limit 0.05), Ki I = 0.016: well above the moment's tolerance */
    for (int k = 0; k < 400; k++) {
        step_with(&c, q, 0u, &out);
    }
    const fc_vec3 held = c.integral_rad_s;
    assert_true(held.x != FC_INT(0, ANGLE) && held.y != FC_INT(0, ANGLE) && held.z != FC_INT(0, ANGLE));
    fc_attitude_control_hold_integral(&c, true);
    for (int k = 0; k < 50; k++) {
        step_with(&c, q, 0u, &out);
        step_with(&c, dq_axis_angle(1.0, 1.0, 1.0, -5.0 * kDeg), 0u, &out);
    }
    assert_true(c.integral_rad_s.x == held.x && c.integral_rad_s.y == held.y && c.integral_rad_s.z == held.z);
    /* the held integral still acts: at zero error the moment is -Ki I
     * (normalised: Ki = ki J / authority) */
    step_with(&c, dq_make(1.0, 0.0, 0.0, 0.0), 0u, &out);
    double i_held[3];
    vec_to(held, FC_ANGLE_FRAC, i_held);
    const dq level = dq_make(1.0, 0.0, 0.0, 0.0);
    const ref_out ref = ref_law(&r, level, level, kZero3, kZero3, i_held);
    (void)assert_moment_within(&out.moment, &ref);
    const double m_expect = -r.gi[0] * i_held[0];
    assert_true(fabs(ref.m[0] - m_expect) < 1e-12 && fabs(m_expect) > 5.0 * ref.tol[0]);
    /* released, it integrates again */
    fc_attitude_control_hold_integral(&c, false);
    step_with(&c, q, 0u, &out);
    assert_true(D(c.integral_rad_s.x, FC_ANGLE_FRAC) > D(held.x, FC_ANGLE_FRAC));
    /* init clears the hold */
    fc_attitude_control_hold_integral(&c, true);
    assert_int_equal(fc_attitude_control_init(&c, &p), FC_INIT_OK);
    step_with(&c, q, 0u, &out);
    assert_true(c.integral_rad_s.x != FC_INT(0, ANGLE));
}

static void test_integral_anti_windup(void **state)
{
    (void)state;
    fc_attitude_control_params p = hexa_params();
    p.ki_per_s3 = vec_all(20.0, FC_GAIN_FRAC);
    p.integral_limit_rad = vec_all(0.05, FC_ANGLE_FRAC);
    fc_attitude_control c;
    assert_int_equal(fc_attitude_control_init(&c, &p), FC_INIT_OK);
    const ref_params r = ref_from(&c);
    /* a roll error of +5 deg: the P moment is negative, the integral grows and
     * pushes it further negative */
    const dq q = dq_axis_angle(1.0, 0.0, 0.0, 5.0 * kDeg);
    const double ex = 2.0 * sin(2.5 * kDeg);
    fc_attitude_control_output out;

    /* the allocator says roll cannot go more negative: the integral stays */
    for (int k = 0; k < 50; k++) {
        step_with(&c, q, FC_SAT_ROLL_NEG, &out);
    }
    assert_true(c.integral_rad_s.x == FC_INT(0, ANGLE));
    /* yaw and pitch bits do not stop roll... */
    step_with(&c, q, FC_SAT_PITCH_NEG | FC_SAT_YAW_NEG | FC_SAT_ROLL_POS, &out);
    /* it integrates the error as the products read it (ANGLE16): its
     * rounding on top of the error's tolerance */
    const double e_tol = ERROR_TOL_RAD + half_lsb(ANGLE16_FRAC);
    assert_true(fabs(D(c.integral_rad_s.x, FC_ANGLE_FRAC) - ex * r.dt) < r.dt * e_tol + 1e-7);
    /* ...and without any bit it integrates e dt per step */
    for (int k = 0; k < 9; k++) {
        step_with(&c, q, 0u, &out);
    }
    assert_true(fabs(D(c.integral_rad_s.x, FC_ANGLE_FRAC) - 10.0 * ex * r.dt) < 10.0 * r.dt * e_tol + 1e-6);
    const double m_before = DN(out.moment.x);
    /* the moment includes -Ki I (Ki = ki Jx / authority), with I the integral
     * the step starts from */
    double i_used[3];
    vec_to(c.integral_rad_s, FC_ANGLE_FRAC, i_used);
    step_with(&c, q, 0u, &out);
    const dq level = dq_make(1.0, 0.0, 0.0, 0.0);
    const ref_out ref = ref_law(&r, from_fc(to_fc(q)), level, kZero3, kZero3, i_used);
    (void)assert_moment_within(&out.moment, &ref);
    /* the reference is -(Kp ex + Ki I) on x (ex = 2 sin 2.5 deg) */
    assert_true(fabs(ref.m[0] + r.gp[0] * ex + r.gi[0] * i_used[0]) < 1e-6 * r.gp[0]);
    assert_true(DN(out.moment.x) < m_before);

    /* unwinding is allowed in the saturated direction's opposite: a negative
     * error with ROLL_NEG reported still decreases I */
    const double i_now = D(c.integral_rad_s.x, FC_ANGLE_FRAC);
    step_with(&c, dq_axis_angle(1.0, 0.0, 0.0, -5.0 * kDeg), FC_SAT_ROLL_NEG, &out);
    assert_true(D(c.integral_rad_s.x, FC_ANGLE_FRAC) < i_now);
    /* and blocked by ROLL_POS */
    const double i_now2 = D(c.integral_rad_s.x, FC_ANGLE_FRAC);
    step_with(&c, dq_axis_angle(1.0, 0.0, 0.0, -5.0 * kDeg), FC_SAT_ROLL_POS, &out);
    assert_true(D(c.integral_rad_s.x, FC_ANGLE_FRAC) == i_now2);

    /* the clamp at integral_limit */
    for (int k = 0; k < 2000; k++) {
        step_with(&c, q, 0u, &out);
    }
    assert_true(c.integral_rad_s.x == p.integral_limit_rad.x);

    /* reset clears it */
    fc_attitude_control_reset(&c);
    assert_true(c.integral_rad_s.x == FC_INT(0, ANGLE) && c.integral_rad_s.y == FC_INT(0, ANGLE) &&
                c.integral_rad_s.z == FC_INT(0, ANGLE));

    /* the own clamp: with a budget of 0.1 N m the roll moment is clamped
     * negative and the integral does not wind up */
    p.moment_limit = limit_of(&p, 0.1, 0.1, 0.1);
    assert_int_equal(fc_attitude_control_init(&c, &p), FC_INIT_OK);
    for (int k = 0; k < 100; k++) {
        const fc_step_status st = step_with(&c, q, 0u, &out);
        assert_true((st & FC_STEP_OUTPUT_LIMITED) != 0u);
    }
    assert_true(c.integral_rad_s.x == FC_INT(0, ANGLE));
    /* -limit exactly in NSUM (the budget rounded to it), rounded to NORM16 on
     * the way out */
    assert_true(fabs(DN(out.moment.x) + D(p.moment_limit.x, FC_RATIO_FRAC)) <= LIMIT_HALF_LSB + NORM16_HALF_LSB);

    /* ki = 0 disables an axis */
    p = hexa_params();
    assert_int_equal(fc_attitude_control_init(&c, &p), FC_INIT_OK);
    for (int k = 0; k < 100; k++) {
        step_with(&c, q, 0u, &out);
    }
    assert_true(c.integral_rad_s.x == FC_INT(0, ANGLE));
}

/* ---- bad input --------------------------------------------------------- */

static void test_bad_input(void **state)
{
    (void)state;
    const fc_attitude_control_params p = hexa_params();
    fc_attitude_control c;
    assert_int_equal(fc_attitude_control_init(&c, &p), FC_INIT_OK);
    const ref_params r = ref_from(&c);
    const dq qd = dq_make(1.0, 0.0, 0.0, 0.0);
    const dq q = dq_axis_angle(1.0, 1.0, 0.0, 8.0 * kDeg);
    const double w[3] = {0.2, 0.1, -0.3};
    const att_sample good = make_input(q, qd, w, kZero3);
    fc_attitude_control_output out;
    assert_int_equal(step_sample(&c, &good, &out), FC_STEP_OK);
    const fc_vec3_16 m0 = out.moment;
    const fc_vec3 e0 = out.attitude_error_rad;

    att_sample bad[6];
    int n_bad = 0;
    bad[n_bad] = good; /* zero-length attitude */
    bad[n_bad++].attitude = fc_quat_make(FC_INT(0, UNIT), FC_INT(0, UNIT), FC_INT(0, UNIT), FC_INT(0, UNIT));
    bad[n_bad] = good; /* zero-length desired attitude */
    bad[n_bad++].attitude_desired =
        fc_quat_make(FC_INT(0, UNIT), FC_INT(0, UNIT), FC_INT(0, UNIT), FC_INT(0, UNIT));
    bad[n_bad] = good; /* rate out of range (beyond 100 rad/s) */
    bad[n_bad++].rate_radps.y = RRATE(-120.0);
#if !FC_NUMERIC_FIXED
    bad[n_bad] = good;
    bad[n_bad++].attitude.x = NAN;
    bad[n_bad] = good;
    bad[n_bad++].attitude_desired.w = INFINITY;
    bad[n_bad] = good;
    bad[n_bad++].rate_radps.z = NAN;
#endif
    const double decay = exp(-r.dt / (double)FC_ATTITUDE_CONTROL_HOLD_TAU_S);
    /* The held moment is the unrounded (RATIO) one, m0 and the decayed output
     * are each rounded to NORM16: (1 + decay) half LSBs, on top of the 1e-6 N m
     * (now over the authority) allowed before for the decay factor. */
    const double hold_tol[3] = {1e-6 / r.auth[0] + (1.0 + decay) * NORM16_HALF_LSB,
                                1e-6 / r.auth[1] + (1.0 + decay) * NORM16_HALF_LSB,
                                1e-6 / r.auth[2] + (1.0 + decay) * NORM16_HALF_LSB};
    for (int b = 0; b < n_bad; b++) {
        assert_int_equal(fc_attitude_control_init(&c, &p), FC_INIT_OK);
        step_sample(&c, &good, &out);
        /* one bad sample: the last moment, decayed by one step; telemetry held */
        const fc_step_status st = step_sample(&c, &bad[b], &out);
        assert_int_equal(st, FC_STEP_BAD_INPUT);
        assert_true(fabs(DN(out.moment.x) - decay * DN(m0.x)) < hold_tol[0]);
        assert_true(fabs(DN(out.moment.y) - decay * DN(m0.y)) < hold_tol[1]);
        assert_true(fabs(DN(out.moment.z) - decay * DN(m0.z)) < hold_tol[2]);
        assert_true(out.attitude_error_rad.x == e0.x && out.attitude_error_rad.y == e0.y);
        /* a lasting fault fades to zero (1 s = 20 tau) */
        for (int k = 0; k < 500; k++) {
            assert_int_equal(step_sample(&c, &bad[b], &out), FC_STEP_BAD_INPUT);
            assert_true(fc_vec3_is_finite(fc_vec3_widen16(out.moment, FC_NORM16_FRAC, FC_RATIO_FRAC)));
            assert_true(fabs(DN(out.moment.x)) <= out_bound(&r, 0) && fabs(DN(out.moment.z)) <= out_bound(&r, 2));
        }
        assert_true(out.moment.x == FC_INT16(0, NORM16) && out.moment.y == FC_INT16(0, NORM16) &&
                    out.moment.z == FC_INT16(0, NORM16));
        /* and good input brings the control back */
        assert_int_equal(step_sample(&c, &good, &out), FC_STEP_OK);
        assert_true(out.moment.x == m0.x && out.moment.y == m0.y && out.moment.z == m0.z);
    }

    /* a bad feed-forward alone is ignored (taken as zero) and reported */
    att_sample bad_ff = good;
    bad_ff.rate_ff_radps.x = RRATE(110.0);
#if !FC_NUMERIC_FIXED
    bad_ff.rate_ff_radps.z = NAN;
#endif
    assert_int_equal(fc_attitude_control_init(&c, &p), FC_INIT_OK);
    assert_int_equal(step_sample(&c, &bad_ff, &out), FC_STEP_BAD_INPUT);
    assert_true(out.moment.x == m0.x && out.moment.y == m0.y && out.moment.z == m0.z);

    /* integrals are frozen while the input is bad */
    fc_attitude_control_params pi = p;
    pi.ki_per_s3 = vec_all(10.0, FC_GAIN_FRAC);
    assert_int_equal(fc_attitude_control_init(&c, &pi), FC_INIT_OK);
    step_sample(&c, &good, &out);
    const fc_vec3 i0 = c.integral_rad_s;
    for (int k = 0; k < 10; k++) {
        step_sample(&c, &bad[0], &out);
    }
    assert_true(c.integral_rad_s.x == i0.x && c.integral_rad_s.y == i0.y && c.integral_rad_s.z == i0.z);

    /* a non-unit but valid quaternion is normalised, not rejected */
    att_sample scaled = good;
    fc_arith ar = {0u};
    scaled.attitude =
        fc_quat_make(fc_mul(&ar, good.attitude.w, FC_C(0.5f, UNIT), FC_SHIFT(UNIT, UNIT, UNIT)),
                     fc_mul(&ar, good.attitude.x, FC_C(0.5f, UNIT), FC_SHIFT(UNIT, UNIT, UNIT)),
                     fc_mul(&ar, good.attitude.y, FC_C(0.5f, UNIT), FC_SHIFT(UNIT, UNIT, UNIT)),
                     fc_mul(&ar, good.attitude.z, FC_C(0.5f, UNIT), FC_SHIFT(UNIT, UNIT, UNIT)));
    assert_int_equal(fc_attitude_control_init(&c, &p), FC_INIT_OK);
    assert_int_equal(step_sample(&c, &scaled, &out), FC_STEP_OK);
    double held_w[3];
    rates_held(w, held_w);
    const ref_out ref = ref_law(&r, from_fc(good.attitude), qd, held_w, kZero3, kZero3);
    (void)assert_moment_within(&out.moment, &ref);
}

/* ---- against the double reference ------------------------------------- */

/* A deterministic spread of attitudes, rates and feed-forwards at both scales,
 * with the gyroscopic term, a yaw weight of 0.7 and the integral on (it
 * integrates the errors as they come; the reference takes the integral each
 * step starts from). The authorities differ per axis and are large enough
 * that the moments (angular accelerations up to ~320 rad/s^2) stay inside the
 * widest budget, 1.99: no clamping here (st == FC_STEP_OK). Each step against
 * the whole law from the attitudes (ref_law), the law at the step's own error
 * (ref_law_at: no error rounding in the tolerance) and that with the step's
 * stored constants (its arithmetic alone). */
static void test_matches_reference(void **state)
{
    (void)state;
    static const double kHexaAuth[3] = {30.0, 35.0, 60.0};
    static const double kCfAuth[3] = {6.0e-3, 7.0e-3, 5.0e-3};
    double worst_whole = 0.0, worst_law = 0.0, worst_arith = 0.0;
    double max_tol_whole = 0.0, max_tol_law = 0.0, max_tol_arith = 0.0, max_i = 0.0;
    for (int scale = 0; scale < 2; scale++) {
        const double *j = scale == 0 ? kHexaJ : kCfJ;
        fc_attitude_control_params p;
        fc_attitude_control_default_params(&p, R(0.002, FC_DT_FRAC), vec_from(j, FC_INERTIA_FRAC));
        p.yaw_weight = R(0.7, FC_RATIO_FRAC);
        p.ki_per_s3 = fc_vec3_make(R(40.0, FC_GAIN_FRAC), R(40.0, FC_GAIN_FRAC), R(15.0, FC_GAIN_FRAC));
        p.integral_limit_rad = vec_all(0.5, FC_ANGLE_FRAC);
        p.authority_nm = vec_from(scale == 0 ? kHexaAuth : kCfAuth, FC_MOMENT_FRAC);
        p.moment_limit = vec_all(LIMIT_MAX, FC_RATIO_FRAC);
        fc_attitude_control c;
        assert_int_equal(fc_attitude_control_init(&c, &p), FC_INIT_OK);
        const ref_params r = ref_from(&c);
        const ref_params rs = ref_stored(&c);
        for (int k = 0; k < 200; k++) {
            const double t = (double)k;
            const dq q = dq_axis_angle(sin(1.3 * t), cos(0.7 * t), sin(2.9 * t + 1.0), 3.0 * sin(0.37 * t));
            const dq qd = dq_axis_angle(cos(1.9 * t), sin(0.3 * t + 0.5), 0.8, 1.5 * cos(0.53 * t));
            const double w[3] = {6.0 * sin(0.9 * t), -4.0 * cos(1.7 * t), 3.0 * sin(2.3 * t + 0.2)};
            const double wff[3] = {(k % 3 == 0) ? 1.5 * cos(t) : 0.0, 0.0, (k % 2 == 0) ? -2.0 : 0.0};
            const att_sample in = make_input(q, qd, w, wff);
            double integral[3];
            vec_to(c.integral_rad_s, FC_ANGLE_FRAC, integral);
            fc_attitude_control_output out;
            const fc_step_status st = step_sample(&c, &in, &out);
            assert_int_equal(st, FC_STEP_OK);
            double held_w[3], held_ff[3];
            rates_held(w, held_w);
            rates_held(wff, held_ff);
            /* errors of any size here: the tolerance at this pair's N */
            const dq qh = from_fc(in.attitude), qdh = from_fc(in.attitude_desired);
            const ref_out whole = ref_law(&r, qh, qdh, held_w, held_ff, integral);
            const ref_out law = ref_law_at(&r, out.attitude_error_rad, held_w, held_ff, integral);
            const ref_out arith = ref_law_at(&rs, out.attitude_error_rad, held_w, held_ff, integral);
            worst_whole = fmax(worst_whole, assert_moment_within(&out.moment, &whole));
            worst_law = fmax(worst_law, assert_moment_within(&out.moment, &law));
            worst_arith = fmax(worst_arith, assert_moment_within(&out.moment, &arith));
            for (int i = 0; i < 3; i++) {
                max_tol_whole = fmax(max_tol_whole, whole.tol[i]);
                max_tol_law = fmax(max_tol_law, law.tol[i]);
                max_tol_arith = fmax(max_tol_arith, arith.tol[i]);
                max_i = fmax(max_i, fabs(integral[i]));
            }
        }
    }
    print_message("matches reference (%s): worst |error| / tolerance (largest tolerance): whole step %.3f "
                  "(%.3g), law at the step's error %.3f (%.3g), its arithmetic (stored constants) %.3f (%.3g); "
                  "largest |I| %.3f rad s\n",
                  FC_NUMERIC_FIXED ? "fixed" : "float", worst_whole, max_tol_whole, worst_law, max_tol_law,
                  worst_arith, max_tol_arith, max_i);
    /* not vacuous: the integral acted, and the tolerances are small (fixed:
     * the whole step within 4e-3 of the authority at N = 0.08, mostly the
     * error's 1/N, the law within 2e-3; float 1e-5 and 1e-6) */
    assert_true(max_i > 0.02);
    assert_true(max_tol_whole < (FC_NUMERIC_FIXED ? 4e-3 : 1e-5));
    assert_true(max_tol_law < (FC_NUMERIC_FIXED ? 2e-3 : 1e-6) && max_tol_arith <= max_tol_law);
}

/* RATE16 holds +-32 rad/s (header): a rate error beyond saturates there, and
 * so does a rate in w_i w_j. The step reads r = 31.999 (32767 LSB) for 40
 * rad/s: the same moment as the reference for that r (fixed); float takes 40.
 * Case 0: w.x = 40 rad/s (the rate and its product saturate); case 1: w.x = 20
 * rad/s with w_ff.x = -20 (only the rate error does). */
static void test_rate16_saturation(void **state)
{
    (void)state;
    static const double kHexaAuth[3] = {30.0, 35.0, 60.0};
    fc_attitude_control_params p;
    fc_attitude_control_default_params(&p, R(0.002, FC_DT_FRAC), vec_from(kHexaJ, FC_INERTIA_FRAC));
    p.authority_nm = vec_from(kHexaAuth, FC_MOMENT_FRAC);
    p.moment_limit = vec_all(LIMIT_MAX, FC_RATIO_FRAC);
    fc_attitude_control c;
    assert_int_equal(fc_attitude_control_init(&c, &p), FC_INIT_OK);
    const ref_params r = ref_from(&c);
#if FC_NUMERIC_FIXED
    const double rate16_max = 32767.0 * ldexp(1.0, -RATE16_FRAC);
#else
    const double rate16_max = (double)31.999f;
#endif
    const dq qd = dq_make(1.0, 0.0, 0.0, 0.0);
    const dq q = dq_axis_angle(1.0, 0.5, 0.2, 3.0 * kDeg);
    static const double kW[2][3] = {{40.0, 0.5, -0.3}, {20.0, 0.5, -0.3}};
    static const double kWff[2][3] = {{0.0, 0.0, 0.0}, {-20.0, 0.0, 0.0}};
    for (int k = 0; k < 2; k++) {
        const att_sample in = make_input(q, qd, kW[k], kWff[k]);
        fc_attitude_control_output out;
        const fc_step_status st = step_sample(&c, &in, &out);
        assert_int_equal(st & (FC_STEP_BAD_INPUT | FC_STEP_NOT_READY | FC_STEP_OUTPUT_LIMITED), 0);
        double w[3], wff[3];
        rates_held(kW[k], w);
        rates_held(kWff[k], wff);
        const ref_out full = ref_law(&r, from_fc(in.attitude), qd, w, wff, kZero3);
        /* what the step reads, in both backends: w.x and w.x - w_ff.x clamped
         * to 31.999 rad/s (in fixed that is 32767 LSB of RATE16); by design,
         * so no saturation is reported */
        assert_int_equal(st, FC_STEP_OK);
        double w_sat[3] = {w[0], w[1], w[2]}, wff_sat[3] = {wff[0], wff[1], wff[2]};
        w_sat[0] = fmin(w[0], rate16_max);
        wff_sat[0] = w_sat[0] - fmin(w[0] - wff[0], rate16_max);
        const ref_out sat = ref_law(&r, from_fc(in.attitude), qd, w_sat, wff_sat, kZero3);
        (void)assert_moment_within(&out.moment, &sat);
        /* and it is the clamp that moved it: Kd (40 - 32) = 0.35 off the
         * unclamped law, far beyond the tolerance without it */
        assert_true(sat.tol[0] < 0.01);
        assert_true(fabs(DN(out.moment.x) - full.m[0]) > 0.9 * r.gd[0] * (40.0 - rate16_max));
        print_message("rate16 clamp (case %d): Mx %.6f, reference at the clamp %.6f, at 40 rad/s %.6f\n", k,
                      DN(out.moment.x), sat.m[0], full.m[0]);
    }
}

/* With rate = rate_ff and no attitude error only w x J w is left. */
static void test_gyroscopic_term(void **state)
{
    (void)state;
    const fc_attitude_control_params p = hexa_params();
    fc_attitude_control c;
    assert_int_equal(fc_attitude_control_init(&c, &p), FC_INIT_OK);
    const ref_params r = ref_from(&c);
    const dq q = dq_axis_angle(0.3, 0.2, 1.0, 0.9);
    const double w[3] = {2.0, -3.0, 4.0};
    const att_sample in = make_input(q, q, w, w);
    fc_attitude_control_output out;
    assert_int_equal(step_sample(&c, &in, &out), FC_STEP_OK);
    double hw[3];
    rates_held(w, hw);
    /* in N m from the inertia */
    const double gyro[3] = {(r.j[2] - r.j[1]) * hw[1] * hw[2], (r.j[0] - r.j[2]) * hw[2] * hw[0],
                            (r.j[1] - r.j[0]) * hw[0] * hw[1]};
    assert_true(fabs(gyro[0] + 0.804) < 1e-7 && fabs(gyro[1] + 0.536) < 1e-7 && gyro[2] == 0.0);
    /* normalised: dJ w_i w_j with dJ = (J_k - J_j) / authority, against the
     * law (constants from the parameters) and the step's arithmetic */
    const ref_out whole = ref_law(&r, from_fc(in.attitude), from_fc(in.attitude), hw, hw, kZero3);
    (void)assert_moment_within(&out.moment, &whole);
    /* the law at the step's own error (q = q_d: zero, or float's few eps),
     * and its arithmetic */
    const ref_out ref = ref_law_at(&r, out.attitude_error_rad, hw, hw, kZero3);
    const ref_params rs = ref_stored(&c);
    const ref_out arith = ref_law_at(&rs, out.attitude_error_rad, hw, hw, kZero3);
    (void)assert_moment_within(&out.moment, &ref);
    (void)assert_moment_within(&out.moment, &arith);
    /* and back in N m (moment x authority) against the inertia's: the law's
     * constants are the inertia's over the authority, so the whole step's
     * tolerance times the authority */
    const double m_nm[3] = {DN(out.moment.x) * r.auth[0], DN(out.moment.y) * r.auth[1],
                            DN(out.moment.z) * r.auth[2]};
    for (int i = 0; i < 3; i++) {
        assert_true(fabs(whole.m[i] * r.auth[i] - gyro[i]) < 1e-12);
        assert_true(fabs(m_nm[i] - gyro[i]) <= r.auth[i] * whole.tol[i]);
    }
    /* not vacuous: the tolerance (fixed: mostly w_i w_j to WW16, 2^-6,
     * through dJ, and the inputs' half LSBs through the gains) far below the
     * moment on x and y */
    assert_true(ref.tol[0] < 0.01 * fabs(ref.m[0]) && ref.tol[1] < 0.01 * fabs(ref.m[1]));
}

/* ---- closed loop on a rigid body --------------------------------------- */

typedef struct plant {
    dq q;
    double w[3];
} plant;

/* J w' = M - w x J w and q' = 1/2 q (x) [0, w], explicit Euler, renormalised. */
static void plant_step(plant *s, const double j[3], const double m[3], double dt)
{
    const double jw[3] = {j[0] * s->w[0], j[1] * s->w[1], j[2] * s->w[2]};
    const double wxjw[3] = {s->w[1] * jw[2] - s->w[2] * jw[1], s->w[2] * jw[0] - s->w[0] * jw[2],
                            s->w[0] * jw[1] - s->w[1] * jw[0]};
    const dq qdot = dq_mul(s->q, dq_make(0.0, 0.5 * s->w[0], 0.5 * s->w[1], 0.5 * s->w[2]));
    s->q = dq_normalize(
        dq_make(s->q.w + dt * qdot.w, s->q.x + dt * qdot.x, s->q.y + dt * qdot.y, s->q.z + dt * qdot.z));
    for (int i = 0; i < 3; i++) {
        s->w[i] += dt * (m[i] - wxjw[i]) / j[i];
    }
}

/* rotation angle of q_d* (x) q, rad */
static double error_angle(dq q, dq qd)
{
    const dq e = dq_mul(dq_conj(qd), q);
    const double v = sqrt(e.x * e.x + e.y * e.y + e.z * e.z);
    return 2.0 * atan2(v, fabs(e.w));
}

typedef struct loop_result {
    double settle_s;      /* last time the error was above 2 deg */
    double overshoot_deg; /* largest error past level, about the initial axis */
    double max_dev_deg;   /* largest angle between the library's and the reference's plant */
    double max_m_ratio;   /* largest |m_i| / out_bound_i of the library (the budget and
                           * the output's rounding, normalised) */
    int status_bad;       /* steps with a status other than OK / OUTPUT_LIMITED */
} loop_result;

#define PLANT_DT 0.001
#define CTRL_EVERY 2
#define LOOP_T 3.0

/* 60 deg tilt about the world-horizontal axis at 30 deg from x, heading 0.5 rad,
 * to level at the same heading. The library and ref_law each fly a plant. */
static loop_result closed_loop(const fc_attitude_control_params *p, const double j[3])
{
    fc_attitude_control c;
    assert_int_equal(fc_attitude_control_init(&c, p), FC_INIT_OK);
    const ref_params r = ref_from(&c);
    const double ax = cos(30.0 * kDeg), ay = sin(30.0 * kDeg);
    const dq qd = dq_axis_angle(0.0, 0.0, 1.0, 0.5);
    plant lib = {dq_mul(dq_axis_angle(ax, ay, 0.0, 60.0 * kDeg), qd), {0.0, 0.0, 0.0}};
    plant ref = lib;
    /* the plant's moments in N m: normalised x authority */
    double m_lib[3] = {0.0, 0.0, 0.0}, m_ref[3] = {0.0, 0.0, 0.0};
    loop_result res = {0.0, 0.0, 0.0, 0.0, 0};
    const int steps = (int)(LOOP_T / PLANT_DT + 0.5);
    for (int k = 0; k < steps; k++) {
        if (k % CTRL_EVERY == 0) {
            const att_sample in = make_input(lib.q, qd, lib.w, kZero3);
            fc_attitude_control_output out;
            const fc_step_status st = step_sample(&c, &in, &out);
            if ((st & ~(fc_step_status)FC_STEP_OUTPUT_LIMITED) != 0u) {
                res.status_bad++;
            }
            const double m_n[3] = {DN(out.moment.x), DN(out.moment.y), DN(out.moment.z)};
            for (int i = 0; i < 3; i++) {
                m_lib[i] = m_n[i] * r.auth[i];
                const double ratio = fabs(m_n[i]) / out_bound(&r, i);
                res.max_m_ratio = ratio > res.max_m_ratio ? ratio : res.max_m_ratio;
            }
            const ref_out m_ref_n = ref_law(&r, ref.q, qd, ref.w, kZero3, kZero3);
            for (int i = 0; i < 3; i++) {
                m_ref[i] = m_ref_n.m[i] * r.auth[i];
            }
        }
        plant_step(&lib, j, m_lib, PLANT_DT);
        plant_step(&ref, j, m_ref, PLANT_DT);
        const double t = (double)(k + 1) * PLANT_DT;
        if (error_angle(lib.q, qd) > 2.0 * kDeg) {
            res.settle_s = t;
        }
        /* signed error about the initial axis (world frame: q (x) q_d*) */
        const dq ew = dq_mul(lib.q, dq_conj(qd));
        const double sgn = ew.w < 0.0 ? -1.0 : 1.0;
        const double about = 2.0 * atan2(sgn * (ew.x * ax + ew.y * ay), fabs(ew.w));
        if (-about / kDeg > res.overshoot_deg) {
            res.overshoot_deg = -about / kDeg;
        }
        const double dev = error_angle(lib.q, ref.q) / kDeg;
        res.max_dev_deg = dev > res.max_dev_deg ? dev : res.max_dev_deg;
    }
    /* ends level */
    assert_true(error_angle(lib.q, qd) < 0.1 * kDeg);
    return res;
}

static const char *backend_name(void)
{
    return FC_NUMERIC_FIXED ? "fixed" : "float";
}

/* 4 kg hexa: Ix = Iy = 0.082, Iz = 0.149 kg m^2, +-2 N m (of the default
 * authority), default gains (wn 10 rad/s, zeta 0.8). Bounds: settling (below
 * 2 deg for good) < 0.6 s, overshoot < 2 deg; the library's flight within
 * 0.05 deg of the reference's. */
static void test_closed_loop_hexa(void **state)
{
    (void)state;
    const fc_attitude_control_params p = hexa_params();
    const loop_result res = closed_loop(&p, kHexaJ);
    print_message("hexa (%s): 60 deg tilt -> level: settling (< 2 deg) %.3f s, overshoot %.3f deg, "
                  "max deviation from double reference %.2e deg, peak |M|/limit %.3f\n",
                  backend_name(), res.settle_s, res.overshoot_deg, res.max_dev_deg, res.max_m_ratio);
    assert_int_equal(res.status_bad, 0);
    assert_true(res.settle_s < 0.6);
    assert_true(res.overshoot_deg < 2.0);
    assert_true(res.max_dev_deg < 0.05);
    assert_true(res.max_m_ratio <= 1.0);
    assert_true(res.max_m_ratio > 0.999); /* the budget was used: a saturated recovery */
}

/* Crazyflie: Ixx = Iyy = 1.66e-5, Izz = 2.93e-5 kg m^2, +-5e-3 N m (the
 * authority, all of it the budget: the default J * 50 rad/s^2 = 8.3e-4 N m
 * would need a budget of 6), default gains and a faster tuning (wn 20 rad/s,
 * zeta 0.8). The same bounds scaled by the bandwidth; the library within 0.05
 * deg of the double reference shows the formats hold at moments of 1e-4..5e-3
 * N m (2e-2..1 of the authority; NORM16's LSB is 3e-7 N m here). */
static void test_closed_loop_crazyflie(void **state)
{
    (void)state;
    for (int tuning = 0; tuning < 2; tuning++) {
        fc_attitude_control_params p;
        fc_attitude_control_default_params(&p, R(0.002, FC_DT_FRAC), vec_from(kCfJ, FC_INERTIA_FRAC));
        p.authority_nm = vec_all(5.0e-3, FC_MOMENT_FRAC);
        p.moment_limit = limit_of(&p, 5.0e-3, 5.0e-3, 5.0e-3);
        const double wn = tuning == 0 ? 10.0 : 20.0;
        if (tuning == 1) {
            p.kp_per_s2.x = p.kp_per_s2.y = FC_C(20.0f * 20.0f, GAIN);
            p.kd_per_s.x = p.kd_per_s.y = FC_C(2.0f * 0.8f * 20.0f, GAIN);
        }
        const loop_result res = closed_loop(&p, kCfJ);
        print_message(
            "crazyflie (%s, wn %.0f rad/s): 60 deg tilt -> level: settling (< 2 deg) %.3f s, "
            "overshoot %.3f deg, max deviation from double reference %.2e deg, peak |M|/limit %.3f\n",
            backend_name(), wn, res.settle_s, res.overshoot_deg, res.max_dev_deg, res.max_m_ratio);
        assert_int_equal(res.status_bad, 0);
        assert_true(res.settle_s < 6.0 / wn);
        assert_true(res.overshoot_deg < 2.0);
        assert_true(res.max_dev_deg < 0.05);
        assert_true(res.max_m_ratio <= 1.0);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_default_params),
        cmocka_unit_test(test_bad_params),
        cmocka_unit_test(test_normalisation),
        cmocka_unit_test(test_normalised_ranges),
        cmocka_unit_test(test_error_sign),
        cmocka_unit_test(test_error_is_2_9_in_body_frame),
        cmocka_unit_test(test_error_accuracy),
        cmocka_unit_test(test_pure_yaw),
        cmocka_unit_test(test_tilt_heading_split),
        cmocka_unit_test(test_short_budget_tilt_first),
        cmocka_unit_test(test_integral_anti_windup),
        cmocka_unit_test(test_integral_hold),
        cmocka_unit_test(test_bad_input),
        cmocka_unit_test(test_matches_reference),
        cmocka_unit_test(test_rate16_saturation),
        cmocka_unit_test(test_gyroscopic_term),
        cmocka_unit_test(test_closed_loop_hexa),
        cmocka_unit_test(test_closed_loop_crazyflie),
    };
    const int failed = cmocka_run_group_tests(tests, NULL, NULL);
    print_message("moments against ref_law (%s): worst |error| / tolerance %.3f over all tests\n",
                  FC_NUMERIC_FIXED ? "fixed" : "float", g_worst_ratio);
    return failed;
}
