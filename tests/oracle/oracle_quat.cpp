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

std::mt19937 rng(kSeed);
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
// fixed: every component is one fc_dot4, one rounding to nearest (0.5 LSB) plus
//   the 2 bits each product drops before the sum (4 * 2^-58, 2^-26 LSB); the
//   double reference is exact to ~1e-7 LSB. Measured 0.50 LSB; bound 1 LSB.
// float: 4 products and 3 sums of |.| <= 1 values, a few float roundings of
//   6e-8 each; measured ~2 eps (2.4e-7); bound 1e-6 (8 eps).
bool check_mul()
{
    const double bound = pick(1.0, 1e-6);
    Check check("quat_mul", unit_name(FC_UNIT_FRAC), bound_text(1.0, 1e-6));
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

// ---- rotation of a vector ------------------------------------------------
// Eigen's q * v evaluates v + w t + q_v x t, t = 2 q_v x v (the library's
// formula too); it equals q v q* for a unit q. The reference is given the same
// quantised q as the library (unit to ~1e-7, not to 1e-16), so both evaluate
// one function of the same input and the check measures the arithmetic only.
//
// fixed: q_v x v rounds 0.5 LSB, doubled to t: 1 LSB; w t adds |w| * 1 + 0.5,
//   q_v x t adds ~|q_v| * 1 * sqrt(2) + 0.5; the sum of the error terms stays
//   below ~3.5 LSB of the vector's format. Measured up to ~2.2 LSB; bound 4 LSB.
// float, LENGTH vectors of components up to 500 m: float rounding of ~1000 m
//   intermediates is 6e-5 m per operation; measured ~1.2e-4 m (~2 ulp of
//   500 m); bound 5e-4 m (4 ulp of the largest intermediate, 2^-13 = 1.2e-4).
// float, unit vectors: bound 1e-6 as for the product.
//
// LENGTH vectors use components in [-500, 500] m: the fixed algorithm builds
// t = 2 q_v x v, up to 2|v| per component, which has to fit in the vector's
// own format ([-2048, 2048) m for LENGTH); see check_rotate_full_range.
constexpr double kLengthMax = 500.0;

bool check_rotate(bool inverse, int frac, bool unit_vectors)
{
    const double fixed_bound = 4.0;
    const double float_bound = unit_vectors ? 1e-6 : 5e-4;
    const double bound = pick(fixed_bound, float_bound);
    std::string name = inverse ? "quat_rotate_inv" : "quat_rotate";
    name += unit_vectors ? ".unit_vector" : ".length";
    Check check(name, unit_name(frac), bound_text(fixed_bound, float_bound));
    for (int i = 0; i < kCases; i++) {
        const fc_quat q = random_quat(1.0);
        const Vector3d v_in = unit_vectors
                                  ? Vector3d(random_direction<3>())
                                  : Vector3d(uniform(-kLengthMax, kLengthMax), uniform(-kLengthMax, kLengthMax),
                                             uniform(-kLengthMax, kLengthMax));
        const fc_vec3 v = quantise_vec(v_in, frac);
        fc_arith ar = {0u};
        const fc_vec3 got = inverse ? fc_quat_rotate_inv(&ar, q, v) : fc_quat_rotate(&ar, q, v);
        const Quaterniond qe = to_eigen(q);
        const Vector3d ve = to_eigen(v, frac);
        const Vector3d want = inverse ? Vector3d(qe.conjugate() * ve) : Vector3d(qe * ve);
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
// fixed, rsqrt branch: 1/|q| (0.77 .. 3.3) is rounded to Q24, a relative error
//   of up to 2^-25 / 0.77 = 3.9e-8, i.e. up to ~42 LSB of Q30 on a component
//   of size ~1, plus 0.5 LSB of the final product. Measured ~24 LSB; bound 48
//   LSB (the Q24 resolution of 1/|q| is the limit, not the arithmetic).
// fixed, near-unit branch: the dropped second-order term 3/8 e^2 < 2.4e-10
//   (0.25 LSB) and two roundings: measured ~1 LSB; bound 2 LSB.
// fixed, quartered: q/4 loses 2 bits (0.5 LSB of Q30 on each component,
//   relative 2^-31/|q/4|), then as the rsqrt branch: measured ~25 LSB; bound 48.
// float: sqrt, division and product, a few eps: measured ~1.5e-7; bound 1e-6.
enum class NormRange { General, NearUnit, Long };

bool check_normalize(NormRange range)
{
    const double fixed_bound = range == NormRange::NearUnit ? 2.0 : 48.0;
    const double float_bound = 1e-6;
    const double bound = pick(fixed_bound, float_bound);
    const char *name = range == NormRange::General    ? "quat_normalize.0.3-1.3"
                       : range == NormRange::NearUnit ? "quat_normalize.near_unit"
                                                      : "quat_normalize.1.45-1.95";
    Check check(name, unit_name(FC_UNIT_FRAC), bound_text(fixed_bound, float_bound));
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
// fixed: theta = w dt is rounded to ANGLE (Q28: 1.9e-9 rad per component, so
//   ~1 LSB of Q30 on the half angle), the series of the exponential and the
//   product round 0.5 LSB each, the renormalisation two more: measured up to
//   ~2.5 LSB; bound 4 LSB.
//   With the larger rates (angles 0.5 .. 3.5 rad, the sin/cos/division
//   branch), fc_sin/fc_cos add a few LSB and sin(a/2)/a is divided in Q30:
//   measured up to ~5 LSB; bound 8 LSB.
// float: a few roundings of unit quantities: measured ~2.5e-7; bound 1e-6.
bool check_integrate(bool world, double rate_max, double dt_min, double dt_max)
{
    const bool large = rate_max > 10.0;
    const double fixed_bound = large ? 8.0 : 4.0;
    const double float_bound = 1e-6;
    const double bound = pick(fixed_bound, float_bound);
    std::string name = world ? "quat_integrate_world" : "quat_integrate_body";
    name += large ? ".fast" : "";
    Check check(name, unit_name(FC_UNIT_FRAC), bound_text(fixed_bound, float_bound));
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

} // namespace

int main()
{
    std::printf("oracle_quat: backend %s, seed 0x%08X, %d cases per check\n", kBackend,
                static_cast<unsigned>(kSeed), kCases);
    bool ok = true;
    ok &= check_mul();
    ok &= check_rotate(false, FC_LENGTH_FRAC, false);
    ok &= check_rotate(true, FC_LENGTH_FRAC, false);
    ok &= check_rotate(false, FC_UNIT_FRAC, true);
    ok &= check_rotate(true, FC_UNIT_FRAC, true);
    ok &= check_normalize(NormRange::General);
    ok &= check_normalize(NormRange::NearUnit);
    ok &= check_normalize(NormRange::Long);
    ok &= check_integrate(false, 10.0, 0.001, 0.01);
    ok &= check_integrate(true, 10.0, 0.001, 0.01);
    ok &= check_integrate(false, 100.0, 0.005, 0.02);
    ok &= check_integrate(true, 100.0, 0.005, 0.02);
    std::printf("oracle_quat: %s\n", ok ? "all checks passed" : "SOME CHECKS FAILED");
    return ok ? 0 : 1;
}
