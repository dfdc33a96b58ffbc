// oracle_quat.cpp - the quaternion core (fc/quat.h) against Eigen::Quaterniond.
//
// Eigen's Quaternion is Hamilton (scalar first in the constructor
// Quaterniond(w, x, y, z), i j = k), its product is the Hamilton product and
// q * v rotates v by q (q v q*), the library's convention (fc/quat.h).
#include "oracle_common.hpp"

#include <Eigen/Geometry>

using namespace oracle;
using Eigen::AngleAxisd;
using Eigen::Quaterniond;
using Eigen::Vector3d;

namespace {

std::mt19937 rng(kSeed); // reseeded per check (seed_for)
Quantiser quantise(rng);

double uniform(double lo, double hi)
{
    return std::uniform_real_distribution<double>(lo, hi)(rng);
}

// A direction uniform on the sphere S^(n-1) (normalised Gaussian vector).
template <int N> Eigen::Matrix<double, N, 1> random_direction()
{
    std::normal_distribution<double> gauss(0.0, 1.0);
    Eigen::Matrix<double, N, 1> v;
    do {
        for (int i = 0; i < N; i++) {
            v[i] = gauss(rng);
        }
    } while (v.norm() < 1e-6);
    return v.normalized();
}

// A quaternion of the given length, direction uniform on S^3 (so both signs of w).
fc_quat random_quat(double length)
{
    const Eigen::Vector4d d = random_direction<4>() * length;
    return fc_quat_make(quantise(d[0], FC_UNIT_FRAC), quantise(d[1], FC_UNIT_FRAC),
                        quantise(d[2], FC_UNIT_FRAC), quantise(d[3], FC_UNIT_FRAC));
}

fc_vec3 quantise_vec(const Vector3d &v, int frac)
{
    return fc_vec3_make(quantise(v.x(), frac), quantise(v.y(), frac), quantise(v.z(), frac));
}

Quaterniond to_eigen(fc_quat q)
{
    return Quaterniond(to_double(q.w, FC_UNIT_FRAC), to_double(q.x, FC_UNIT_FRAC),
                       to_double(q.y, FC_UNIT_FRAC), to_double(q.z, FC_UNIT_FRAC));
}

Vector3d to_eigen(fc_vec3 v, int frac)
{
    return Vector3d(to_double(v.x, frac), to_double(v.y, frac), to_double(v.z, frac));
}

// Largest component error, in the reporting unit of format frac.
double quat_error(fc_quat got, const Quaterniond &want)
{
    const Quaterniond g = to_eigen(got);
    const double e = (g.coeffs() - want.coeffs()).cwiseAbs().maxCoeff();
    return error_units(e, FC_UNIT_FRAC);
}

double vec_error(fc_vec3 got, const Vector3d &want, int frac)
{
    return error_units((to_eigen(got, frac) - want).cwiseAbs().maxCoeff(), frac);
}

std::string show(fc_quat q)
{
    char buf[160];
    std::snprintf(buf, sizeof buf, "[%.12f %.12f %.12f %.12f]", to_double(q.w, FC_UNIT_FRAC),
                  to_double(q.x, FC_UNIT_FRAC), to_double(q.y, FC_UNIT_FRAC),
                  to_double(q.z, FC_UNIT_FRAC));
    return buf;
}

std::string show(fc_vec3 v, int frac)
{
    char buf[128];
    std::snprintf(buf, sizeof buf, "(%.9f %.9f %.9f)", to_double(v.x, frac), to_double(v.y, frac),
                  to_double(v.z, frac));
    return buf;
}

std::string show(const Quaterniond &q)
{
    char buf[160];
    std::snprintf(buf, sizeof buf, "[%.12f %.12f %.12f %.12f]", q.w(), q.x(), q.y(), q.z());
    return buf;
}

std::string show(const Vector3d &v)
{
    char buf[128];
    std::snprintf(buf, sizeof buf, "(%.9f %.9f %.9f)", v.x(), v.y(), v.z());
    return buf;
}

// In-range inputs must never saturate.
void expect_no_saturation(Check &check, const fc_arith &ar, const std::function<std::string()> &describe)
{
    if (ar.saturated != 0u) {
        check.fail("saturation flag set, " + describe());
    }
}

// ---- Hamilton product ---------------------------------------------------
// (Measured values here and below: the worst case over this program's seed
// and 6 other seeds of 5000 cases each.)
//
// fixed: every component is one fc_dot4, four products summed in 64 bits and
//   rounded once to nearest (0.5 LSB); the double reference is exact to ~1e-7
//   LSB. Measured 0.50 LSB; bound 1 LSB.
// float: 4 products and 3 sums of |.| <= 1 values, a few float roundings of
//   6e-8 each; measured 1.1e-7 (0.96 eps); bound 1e-6 (8 eps).
bool check_mul()
{
    const double bound = pick(1.0, 1e-6);
    Check check("quat_mul", unit_name(FC_UNIT_FRAC), bound_text(1.0, 1e-6));
    rng.seed(seed_for("quat_mul"));
    for (int i = 0; i < kCases; i++) {
        const fc_quat p = random_quat(1.0), q = random_quat(1.0);
        fc_arith ar = {0u};
        const fc_quat got = fc_quat_mul(&ar, p, q);
        const Quaterniond want = to_eigen(p) * to_eigen(q);
        const auto describe = [&] { return "p " + show(p) + " q " + show(q) + " got " + show(got) + " want " + show(want); };
        check.record(quat_error(got, want), bound, describe);
        expect_no_saturation(check, ar, describe);
    }
    return check.summary();
}

// ---- the 16-bit attitude-error product (fc_quat16) ------------------------
// p* (x) q with p and q made 16-bit by fc_quat16_normalize, against Eigen's
// p.conjugate() * q of the 32-bit inputs (normalised in double), in UNIT16
// LSB (2^-14) in fixed.
//
// fixed: each input component rounded to UNIT16 (0.5 LSB) and the product's
//   four 16 x 16 products summed exactly and rounded once (0.5 LSB): the
//   inputs' roundings reach a component through sum_i |q_i| <= 2 of them,
//   0.5 + 2 (0.5 + 0.5) = 2.5 LSB at most; an input accepted as unit at 16
//   bits is not rescaled (|q|^2 within 2^-12), which moves nothing here, the
//   inputs being unit to 2e-9. Measured 1.6 LSB; bound 2.5 LSB.
// float: fc_quat_normalize and fc_quat_mul of the conjugate; bound 1e-6 as
//   quat_mul's.
double quat16_error(const fc_quat16 &got, const Quaterniond &want)
{
#if FC_NUMERIC_FIXED
    const int frac = FC_UNIT16_FRAC;
    const Quaterniond g(std::ldexp(got.w, -frac), std::ldexp(got.x, -frac), std::ldexp(got.y, -frac),
                        std::ldexp(got.z, -frac));
#else
    const int frac = FC_UNIT16_FRAC;
    const Quaterniond g(got.w, got.x, got.y, got.z);
#endif
    return error_units((g.coeffs() - want.coeffs()).cwiseAbs().maxCoeff(), frac);
}

bool check_quat16_conj_mul()
{
    const double bound = pick(2.5, 1e-6);
    Check check("quat16_conj_mul", kFixed ? "LSB(Q14)" : "abs", bound_text(2.5, 1e-6));
    rng.seed(seed_for("quat16_conj_mul"));
    for (int i = 0; i < kCases; i++) {
        const fc_quat p = random_quat(1.0), q = random_quat(1.0);
        fc_arith ar = {0u};
        bool p_ok = false, q_ok = false;
        const fc_quat16 p16 = fc_quat16_normalize(&ar, p, &p_ok);
        const fc_quat16 q16 = fc_quat16_normalize(&ar, q, &q_ok);
        const fc_quat16 got = fc_quat16_conj_mul(&ar, p16, q16);
        const Quaterniond want = to_eigen(p).normalized().conjugate() * to_eigen(q).normalized();
        const auto describe = [&] { return "p " + show(p) + " q " + show(q) + " want " + show(want); };
        if (!p_ok || !q_ok) {
            check.fail("not ok, " + describe());
        }
        check.record(quat16_error(got, want), bound, describe);
        expect_no_saturation(check, ar, describe);
    }
    return check.summary();
}

// fc_quat16_normalize of quaternions of any length in (0.05, 1.9): a unit
// quaternion at 16 bits, the direction of q. fixed: the 32-bit normalisation
// (fc_quat_normalize: a few Q30 LSB) then one rounding to UNIT16, 0.5 LSB;
// but a q whose rounding is unit at 16 bits (|q|^2 within 2^-13 + 2^-24 of
// 1) is passed as it is, up to 2^-14 long or short: 1 LSB more. Measured
// 0.94 LSB; bound 1.5 LSB. float: as fc_quat_normalize, bound 1e-6.
bool check_quat16_normalize()
{
    const double bound = pick(1.5, 1e-6);
    Check check("quat16_normalize", kFixed ? "LSB(Q14)" : "abs", bound_text(1.5, 1e-6));
    rng.seed(seed_for("quat16_normalize"));
    for (int i = 0; i < kCases; i++) {
        const fc_quat q = random_quat(uniform(0.05, 1.9));
        fc_arith ar = {0u};
        bool ok = false;
        const fc_quat16 got = fc_quat16_normalize(&ar, q, &ok);
        const Quaterniond want = to_eigen(q).normalized();
        const auto describe = [&] { return "q " + show(q) + " want " + show(want); };
        if (!ok) {
            check.fail("not ok, " + describe());
        }
        check.record(quat16_error(got, want), bound, describe);
        expect_no_saturation(check, ar, describe);
    }
    return check.summary();
}

// ---- rotation of a vector ------------------------------------------------
// Reference: Eigen's q * v with q normalised in double, i.e. the rotation that
// q stands for (Eigen's q * v assumes a unit q; fc_quat_rotate_inv against
// q.conjugate() * v). The quantised q is unit only to ~2e-9 (fixed) or ~1e-7
// (float), and q v q* and the rotation by q/|q| differ by (|q|^2 - 1) |v|,
// which a function of a unit quaternion may carry either way: that amount is
// added to each case's bound (it is at most 2 LSB of Q30 on a unit vector,
// 4 LSB of Q20 at |v| = 2040 m, and much less on average).
//
// Inputs: random unit q, and v
//   Length500        LENGTH (Q20) components uniform in [-500, 500] m
//   UnitVector       UNIT (Q30) directions uniform on the sphere
//   LengthFullRange  LENGTH, |v| uniform in [0, 2040] m, random direction: the
//                    whole format ([-2048, 2048) m); the result, of the same
//                    length, is representable too (group rotate_full_range)
//
// fixed: fc_quat_rotate forms R(q) in UNIT (each entry a sum or a double of
//   products rounded to Q30: up to 2 LSB of Q30 off) and takes one 64-bit dot
//   product per component, rounded once (0.5 LSB of the vector's format). The
//   entry errors act on |v_x| + |v_y| + |v_z| <= sqrt(3) |v|, so the error is
//   at most 0.5 LSB + 2 sqrt(3) |v| LSB(Q30) (3.5 |v| 2^-30, in the vector's
//   own LSB 3.5 |v| 2^(FRAC-30)). Bound: 1 LSB + 4 |v| LSB(Q30) + the
//   allowance above: 5 LSB (Q30) for a unit vector, 1 + 3.4 LSB (Q20) at
//   866 m, 1 + 8 LSB at 2040 m. Measured 4.5 LSB (unit vectors), 2.9 LSB
//   (Length500), 7.9 LSB (full range), at most 0.74 of the per-case bound.
// float: relative to |v|, as the products round at float precision of their
//   size: measured 2.3e-7 on unit vectors and 2.2 eps |v| on LENGTH vectors;
//   bound 8 eps |v| (9.5e-7 for a unit vector) + the allowance.
//
// The full-range group exists because the first fc_quat_rotate (two cross
// products, commit 1fa71d4) built t = 2 q_v x v in the vector's own format and
// saturated for |v| beyond half the range (from ~1050 m in LENGTH), returning
// errors as large as v itself.
enum class RotateInput { Length500, UnitVector, LengthFullRange };

bool check_rotate(bool inverse, int frac, RotateInput input)
{
    constexpr double fixed_c0 = 1.0; // LSB of the vector's format
    constexpr double fixed_c1 = 4.0; // LSB of Q30 per unit of |v|
    constexpr double float_rel = 8.0 * FLT_EPSILON;
    std::string name = inverse ? "quat_rotate_inv" : "quat_rotate";
    name += input == RotateInput::Length500    ? ".length500"
            : input == RotateInput::UnitVector ? ".unit_vector"
                                               : ".length_full_range";
    Check check(name, unit_name(frac),
                kFixed ? "1 LSB + 4 |v| LSB(Q30) + |1-|q|^2| |v|" : "8 eps |v| + |1-|q|^2| |v|");
    rng.seed(seed_for(name));
    for (int i = 0; i < kCases; i++) {
        const fc_quat q = random_quat(1.0);
        Vector3d v_in;
        switch (input) {
        case RotateInput::Length500:
            v_in = Vector3d(uniform(-500.0, 500.0), uniform(-500.0, 500.0), uniform(-500.0, 500.0));
            break;
        case RotateInput::UnitVector:
            v_in = random_direction<3>();
            break;
        case RotateInput::LengthFullRange:
            v_in = random_direction<3>() * uniform(0.0, 2040.0);
            break;
        }
        const fc_vec3 v = quantise_vec(v_in, frac);
        fc_arith ar = {0u};
        const fc_vec3 got = inverse ? fc_quat_rotate_inv(&ar, q, v) : fc_quat_rotate(&ar, q, v);
        const Quaterniond qe = to_eigen(q);
        const Vector3d ve = to_eigen(v, frac);
        // the rotation q stands for: by q / |q|
        const Quaterniond qn = qe.normalized();
        const Vector3d want = inverse ? Vector3d(qn.conjugate() * ve) : Vector3d(qn * ve);
        // q is unit only to the input's resolution: q v q* and the rotation by
        // q/|q| differ by (|q|^2 - 1) |v|, which the function may carry either way
        const double allowance = std::fabs(1.0 - qe.squaredNorm()) * ve.norm();
        const double bound = kFixed ? fixed_c0 + fixed_c1 * ve.norm() * std::ldexp(1.0, frac - FC_UNIT_FRAC) +
                                          error_units(allowance, frac)
                                    : float_rel * std::max(ve.norm(), 1.0) + allowance;
        const auto describe = [&] {
            return "q " + show(q) + " v " + show(v, frac) + " got " + show(got, frac) + " want " + show(want);
        };
        check.record(vec_error(got, want, frac), bound, describe);
        expect_no_saturation(check, ar, describe);
    }
    return check.summary();
}

// ---- normalisation -------------------------------------------------------
// Reference: the quantised q divided by its exact length.
//
// Three ranges, one per branch of fc_quat_normalize:
//   lengths 0.3 .. 1.3        1/|q| by fc_rsqrt, held in RATIO (Q24)
//   |q|^2 = 1 +- 2.5e-5       first-order 1/|q| = 1 + (1 - |q|^2)/2, no rsqrt
//   lengths 1.45 .. 1.95      fixed: |q|^2 saturates UNIT, q is quartered first
//
// fixed, rsqrt branch: 1/|q| (0.77 .. 3.3) is rounded to Q24, an absolute
//   error of up to 2^-25 = 3e-8 that multiplies every component of q, so up
//   to |q| * 2^-25 = 3.9e-8 = 42 LSB of Q30 at |q| = 1.3, plus 0.5 LSB of the
//   final product. Measured 40.9 LSB; bound 48 LSB. The Q24 resolution of
//   1/|q| is the limit, not the arithmetic (a design choice of
//   fc_quat_normalize: RATIO covers 1/|q| up to 100; see the report).
// fixed, near-unit branch: the dropped second-order term 3/8 e^2 < 3.4e-10
//   (0.4 LSB) and two roundings: measured 1.2 LSB; bound 2 LSB.
// fixed, quartered: the Q24 rounding of 1/|q/4| on components of q/4 (up to
//   |q/4| * 2^-25 = 15.6 LSB), the rounding of q/4 itself (0.5 LSB, divided by
//   |q/4| >= 0.36: 1.4 LSB) and of the product: measured 16.5 LSB; bound 24.
// float: sqrt, division and product, a few eps: measured 1.5e-7; bound 1e-6.
enum class NormRange { General, NearUnit, Long };

bool check_normalize(NormRange range)
{
    const double fixed_bound = range == NormRange::General ? 48.0 : range == NormRange::NearUnit ? 2.0 : 24.0;
    const double float_bound = 1e-6;
    const double bound = pick(fixed_bound, float_bound);
    const char *name = range == NormRange::General    ? "quat_normalize.0.3-1.3"
                       : range == NormRange::NearUnit ? "quat_normalize.near_unit"
                                                      : "quat_normalize.1.45-1.95";
    Check check(name, unit_name(FC_UNIT_FRAC), bound_text(fixed_bound, float_bound));
    rng.seed(seed_for(name));
    for (int i = 0; i < kCases; i++) {
        double length = 1.0;
        switch (range) {
        case NormRange::General:
            length = uniform(0.3, 1.3);
            break;
        case NormRange::NearUnit:
            length = std::sqrt(1.0 + uniform(-2.5e-5, 2.5e-5));
            break;
        case NormRange::Long:
            length = uniform(1.45, 1.95);
            break;
        }
        const fc_quat q = random_quat(length);
        const Quaterniond qe = to_eigen(q);
        // in the near-unit range the quantised length must still be in the branch
        if (range == NormRange::NearUnit && std::fabs(1.0 - qe.squaredNorm()) >= 2.9e-5) {
            check.skip();
            continue;
        }
        fc_arith ar = {0u};
        bool ok = false;
        const fc_quat got = fc_quat_normalize(&ar, q, &ok);
        const Quaterniond want = qe.normalized();
        const auto describe = [&] { return "q " + show(q) + " got " + show(got) + " want " + show(want); };
        check.record(quat_error(got, want), bound, describe);
        if (!ok) {
            check.fail("ok == false, " + describe());
        }
        // quartering a long q in fixed is by design and raises no flag on ar
        expect_no_saturation(check, ar, describe);
    }
    return check.summary();
}

// ---- integration -----------------------------------------------------------
// Reference: q (x) exp(w dt / 2) = q * AngleAxis(|w| dt, w / |w|) for the body
// rate, AngleAxis * q for the world rate, normalised (the library renormalises
// its result), from the quantised q, w (RATE, Q24) and dt (DT, Q30).
//
// Two input ranges:
//   (group integrate)       rates uniform in +-10 rad/s per axis, dt in
//                           [0.001, 0.01] s: angles below 0.18 rad, the series
//                           branch of fc_quat_from_rotation_vector
//   (group integrate_fast)  rates in +-100 rad/s, dt in [0.005, 0.02] s:
//                           angles up to 3.5 rad, mostly the sin/cos/division
//                           branch (angle >= 0.5 rad)
//
// fixed, series branch: theta = w dt is rounded to ANGLE (Q28: 1.9e-9 rad per
//   component, ~1 LSB of Q30 on the half angle), the series and the product
//   round 0.5 LSB each, the renormalisation one more: measured 2.7 LSB; bound
//   4 LSB.
// fixed, sin/cos branch: fc_sin/fc_cos are specified to "a few UNIT LSB"
//   (fc/scalar.h, checked in oracle_scalar.cpp) and sin(a/2)/a is divided in
//   Q30: measured 6.2 LSB; bound 10 LSB. (With the first Q28 pi/2, rounded
//   through a float to 4.4e-8 rad too large, commit 1fa71d4, this group
//   measured 48 LSB.)
// float: a few roundings of unit quantities: measured 1.4e-7 (1.2 eps); bound
//   1e-6 (8 eps).
bool check_integrate(bool world, double rate_max, double dt_min, double dt_max)
{
    const bool large = rate_max > 10.0;
    const double fixed_bound = large ? 10.0 : 4.0;
    const double float_bound = 1e-6;
    const double bound = pick(fixed_bound, float_bound);
    std::string name = world ? "quat_integrate_world" : "quat_integrate_body";
    name += large ? ".fast" : "";
    Check check(name, unit_name(FC_UNIT_FRAC), bound_text(fixed_bound, float_bound));
    rng.seed(seed_for(name));
    for (int i = 0; i < kCases; i++) {
        const fc_quat q = random_quat(1.0);
        const Vector3d w_in(uniform(-rate_max, rate_max), uniform(-rate_max, rate_max),
                            uniform(-rate_max, rate_max));
        const fc_vec3 w = quantise_vec(w_in, FC_RATE_FRAC);
        const fc_real dt = quantise(uniform(dt_min, dt_max), FC_DT_FRAC);
        fc_arith ar = {0u};
        const fc_quat got = world ? fc_quat_integrate_world_rate(&ar, q, w, dt)
                                  : fc_quat_integrate_body_rate(&ar, q, w, dt);

        const Vector3d we = to_eigen(w, FC_RATE_FRAC);
        const double dte = to_double(dt, FC_DT_FRAC);
        const Quaterniond step(AngleAxisd(we.norm() * dte, we.normalized()));
        const Quaterniond qe = to_eigen(q);
        const Quaterniond want = (world ? Quaterniond(step * qe) : Quaterniond(qe * step)).normalized();
        const auto describe = [&] {
            char buf[96];
            std::snprintf(buf, sizeof buf, " dt %.9f", dte);
            return "q " + show(q) + " w " + show(w, FC_RATE_FRAC) + buf + " got " + show(got) + " want " +
                   show(want);
        };
        check.record(quat_error(got, want), bound, describe);
        expect_no_saturation(check, ar, describe);
    }
    return check.summary();
}


// fc_quat_advance_body_rate (the attitude filter's step, fc/quat.h) against
// the exact step q exp(w dt / 2) of Eigen, from a unit q (fc_quat_normalize of
// a random one), rates uniform in +-31.9 rad/s per axis and dt in [1, 10] ms
// (1 kHz to 100 Hz: the larger steps take its exponential map, or its
// fc_quat_normalize branch). The bound is derived per case, a = |w| dt the
// step's angle, as the largest component error (half the rotation's error,
// or the length's):
//   a^3 / 24          the step rotates by 2 atan(a/2), short by a^3/12
//   2^-15 a           (fixed) q rounded to UNIT16 in the increment
//   3/8 (a^2/4)^2     the Newton step leaves |q|^2 off by 3/4 of the square
//                     of its |p|^2 - 1 = a^2/4 (only where it is taken)
//   + 40 LSB          roundings: the half-angle's, the products, the increment's, the length
//                     error's (UNIT16 x 2^-26), the subtraction
// float: the same terms but the rounding of q, and 8 eps for the roundings.
bool check_advance()
{
    Check check("quat_advance_body", unit_name(FC_UNIT_FRAC), "a^3/24 + 2^-15 a + 3/8 (a^2/4)^2 + 40 LSB");
    rng.seed(seed_for("quat_advance_body"));
    for (int i = 0; i < kCases; i++) {
        fc_arith ar = {0u};
        bool ok = false;
        const fc_quat q = fc_quat_normalize(&ar, random_quat(1.0), &ok);
        const double rate_max = 31.9;
        const Vector3d w_in(uniform(-rate_max, rate_max), uniform(-rate_max, rate_max),
                            uniform(-rate_max, rate_max));
        const fc_vec3 w = quantise_vec(w_in, FC_RATE_FRAC);
        const double dt_s = uniform(0.001, 0.01);
        const fc_real half_dt = quantise(dt_s / 2.0, FC_DT_FRAC);
        fc_quat got = q;
        fc_quat_advance_body_rate(&ar, &got, &w, half_dt);

        const Vector3d we = to_eigen(w, FC_RATE_FRAC);
        const double dte = 2.0 * to_double(half_dt, FC_DT_FRAC);
        const Quaterniond step(AngleAxisd(we.norm() * dte, we.normalized()));
        const Quaterniond want = (to_eigen(q) * step).normalized();
        const double a = we.norm() * dte;
        const double length_error = a * a / 4.0;
        const double newton = length_error <= 3.0 * std::ldexp(1.0, -12) ? 0.375 * length_error * length_error : 0.0;
        const double analytic = a * a * a / 24.0 + (kFixed ? std::ldexp(a, -15) : 0.0) + newton;
        const double bound = error_units(analytic, FC_UNIT_FRAC) + pick(40.0, 8.0 * 1.2e-7);
        const auto describe = [&] {
            char buf[96];
            std::snprintf(buf, sizeof buf, " dt %.9f bound %.3g", dte, bound);
            return "q " + show(q) + " w " + show(w, FC_RATE_FRAC) + buf + " got " + show(got) + " want " +
                   show(want);
        };
        check.record(quat_error(got, want), bound, describe);
        expect_no_saturation(check, ar, describe);
    }
    return check.summary();
}

} // namespace

// Usage: oracle_quat [group]; without a group every check runs. CTest runs one
// group per test so that a failing group names itself in the test list.
int main(int argc, char **argv)
{
    const std::string group = argc > 1 ? argv[1] : "all";
    const auto run = [&](const char *name) { return group == "all" || group == name; };
    std::printf("oracle_quat: backend %s, seed 0x%08X, %d cases per check, group %s\n", kBackend,
                static_cast<unsigned>(kSeed), kCases, group.c_str());
    bool ok = true;
    bool known = group == "all";
    if (run("mul")) {
        known = true;
        ok &= check_mul();
    }
    if (run("quat16")) {
        known = true;
        ok &= check_quat16_conj_mul();
        ok &= check_quat16_normalize();
    }
    if (run("rotate")) {
        known = true;
        ok &= check_rotate(false, FC_LENGTH_FRAC, RotateInput::Length500);
        ok &= check_rotate(true, FC_LENGTH_FRAC, RotateInput::Length500);
        ok &= check_rotate(false, FC_UNIT_FRAC, RotateInput::UnitVector);
        ok &= check_rotate(true, FC_UNIT_FRAC, RotateInput::UnitVector);
    }
    if (run("rotate_full_range")) {
        known = true;
        ok &= check_rotate(false, FC_LENGTH_FRAC, RotateInput::LengthFullRange);
        ok &= check_rotate(true, FC_LENGTH_FRAC, RotateInput::LengthFullRange);
    }
    if (run("normalize")) {
        known = true;
        ok &= check_normalize(NormRange::General);
        ok &= check_normalize(NormRange::NearUnit);
        ok &= check_normalize(NormRange::Long);
    }
    if (run("integrate")) {
        known = true;
        ok &= check_integrate(false, 10.0, 0.001, 0.01);
        ok &= check_integrate(true, 10.0, 0.001, 0.01);
    }
    if (run("advance")) {
        known = true;
        ok &= check_advance();
    }
    if (run("integrate_fast")) {
        known = true;
        ok &= check_integrate(false, 100.0, 0.005, 0.02);
        ok &= check_integrate(true, 100.0, 0.005, 0.02);
    }
    if (!known) {
        std::printf("oracle_quat: unknown group '%s'\n", group.c_str());
        return 2;
    }
    std::printf("oracle_quat: %s\n", ok ? "all checks passed" : "SOME CHECKS FAILED");
    return ok ? 0 : 1;
}
