// test_allocation_oracle.cpp - control allocation (fc/allocation.h) against
// Eigen: the effectiveness matrix against its definition (2.5), computed in
// double, the authorities and the normalised effectiveness B = N A against
// their definitions (fc/allocation.h, "Normalised units"), computed in double
// from that A, and the pseudo-inverse against Eigen's
// CompleteOrthogonalDecomposition.
//
// Geometries: the three presets and kCases random ones (std::mt19937, fixed
// seed): n in [4, 8] rotors at 0.05-1 m from the centre at jittered angles,
// heights within +-0.1 m, axes within 25 deg of +z, T_max 0.05-30 N per vehicle
// (+-20 % per rotor), Q_max = +-(0.005-0.03 m) T_max with alternating signs,
// u_min in [0, 0.3], r = s = 2. Every input is quantised into the backend
// (oracle::Quantiser) and read back exactly, so only the library's own error
// is measured. Geometries whose D A has cond > 50 (rare: an unlucky draw close
// to rank loss) are skipped for the accuracy checks and counted.
//
// Checks and bounds (fixed: LSB of Q24, the MAT format; float: absolute, in the
// unit of the entry):
//   effectiveness   A (N, N m) vs T d_z and T (l x d) + Q d in double.
//                   fixed: l x d is rounded to LEVER (Q24, 0.5 LSB of a metre:
//                   T/2 LSB of MAT once multiplied by T in N) and each product
//                   once more: bound 1.5 + T/2 LSB. float: a few roundings of
//                   the terms: bound 4 eps (|T| |l| + |Q| + |T|).
//   authority       F_max = sum_i |A_0i| (FORCE) and the moment authorities
//                   sum_i |A_ki| / 2 (MOMENT) vs the same sums of |A| in double.
//                   fixed, in LSB of FORCE / MOMENT: each T d_z rounded once to
//                   FORCE (n/2 LSB); each moment entry as A above (1.5 + T/2
//                   LSB of MOMENT, the same Q24), half their sum plus the
//                   halving's rounding: sum_i (1.5 + T_i/2) / 2 + 1/2 LSB.
//                   float: the entries' bounds (eps T d_z; the 4 eps (...) of
//                   A) summed, halved for the moments, plus n eps of the sum.
//   normalised      B = N A, N = diag(1 / F_max, 1 / authority_k) from the
//                   double sums above: B_ki = A_ki / F_max (thrust row, which
//                   sums to 1 in absolute value) and 2 A_ki / sum_i |A_ki|
//                   (moment rows, sum 2). The library forms it from D A
//                   (the row scales 2^e_k, checked to be exact powers of two
//                   with the row's largest entry of D A in (0.5, 1]) times
//                   rn_k = c_k / sum_i |(D A)_ki| (c_0 = 1, c_k = 2); 2^e
//                   cancels. With e_ki the bound of (D A)_ki (fixed: T 2^e
//                   rounded once, exact for e >= -4, l x d as above scaled by
//                   T 2^e: 1.5 + T 2^e / 2 LSB; float: 4 eps (T 2^e (|l| + 1) +
//                   |Q| 2^e)) and S_k = sum_i |(D A)_ki|: rn_k is within
//                   rn_k (sum_i e_ki / S_k) plus its own rounding (fixed: 1/2
//                   LSB of RATIO, Q24; float: the n - 1 additions of S_k and
//                   the division, (n + 1) eps / 2 relative), and
//                   B_ki = (D A)_ki rn_k rounded once more (1/2 LSB; eps / 2
//                   relative): bound rn_k e_ki + |B_ki| rel(rn_k) + that rounding.
//   pinv            P = pinv(B) vs COD of the library's own B (read back
//                   exactly): the error of fc_mat_pinv, which grows with
//                   cond^2 (normal equations): bound 2 cond^2 LSB (fixed),
//                   4 eps cond^2 max|P| (float), as in oracle_pinv; in fixed
//                   plus P's rounding to the step's 16 bits (PINV16, Q12:
//                   half an LSB, 2^-13 = 2048 LSB of Q24).
//   pinv_chain      P N (the physical pseudo-inverse pinv(A) the step applies:
//                   x = N w with the library's authorities, v = P x) against
//                   COD of A in double from the definition: everything
//                   together, relative to max|pinv(A)|. Column k of P N is
//                   scaled by 1 / the library's authority k, so it carries
//                   that authority's relative error rel(authority_k) =
//                   |authority_k / authority_lib,k - 1| (the authority check
//                   bounds it; in fixed it reaches 2e-5, the smallest random
//                   vehicles' yaw authority being a few thousand LSB of
//                   MOMENT) on top of B's and P's, which grow with cond(B)^2:
//                   bound 2e-6 cond(B)^2 + max_k rel(authority_k) (fixed),
//                   8 eps cond(B)^2 + the same (float); in fixed plus P's
//                   rounding to PINV16 (2^-13), which column k of P N
//                   carries as 2^-13 / authority_k: 2^-13 max_k (1 /
//                   authority_k) over max|pinv(A)|.
//   accept          every geometry inside the documented range limits (row sums
//                   of |A| <= 1500 N, 100 N m, F_max >= 1/16 N) whose
//                   max|pinv(B)| (double) is <= 7.9 inits OK, and none with
//                   max|pinv(B)| >= 8.1 does (the library's rule: a P entry
//                   above 8 - 2^-12, the largest PINV16 value, is rank
//                   deficient; the margin: kPinvLimit); one beyond the range
//                   limits gives FC_INIT_BAD_PARAM.
//   rank            geometries built rank deficient (all rotors on one line
//                   through the centre of mass, a coaxial stack, one spin
//                   direction on a planar layout, n < 4) must give
//                   FC_INIT_RANK_DEFICIENT.
#include "oracle_common.hpp"

extern "C" {
#include "fc/allocation.h"
}

#include <Eigen/Dense>

using namespace oracle;
using Eigen::MatrixXd;
using Eigen::Vector3d;

namespace {

constexpr double kCondSkip = 50.0;
// The library rejects a geometry with an entry of P = pinv(B) above
// 8 - 2^-12 (the largest value of PINV16, the 16-bit format the step
// multiplies P in) as rank deficient (fc/allocation.h), B = N A the matrix it
// inverts: a geometry inside the range limits with max|pinv(B)| <=
// kPinvMustAccept (pinv of B in double) must be accepted, and one with
// max|pinv(B)| >= kPinvMustReject rejected. The margin of 0.1 is far above
// how much the library's 32-bit P (checked against the limit before its
// rounding to 16 bits) can differ from pinv(B) in double: the pinv bound
// (2 cond^2 LSB, 1e-3 at cond 100) plus ||P||_2^2 ||B_lib - B||_2 (8^2 x a
// few hundred LSB of Q24, 1e-3). (Until B replaced D A this check was
// "every geometry with cond(D A) <= 30 is accepted"; with B's row sums of 1
// and 2 the entries of P grew, and with P in 16 bits the limit is 8, not 16:
// the note of the accept line counts the geometries of cond(D A) <= 30
// rejected.)
constexpr double kPinvLimit = 32767.0 / 4096.0;
constexpr double kPinvMustAccept = kPinvLimit - 0.1;
constexpr double kPinvMustReject = kPinvLimit + 0.1;
constexpr double kPi = 3.14159265358979323846;

// The quantised parameters of a vehicle, read back in double.
struct Vehicle {
    fc_allocation_params params{};
    int n = 0;
    std::vector<Vector3d> axis, position;
    std::vector<double> thrust, torque;
};

void read_back(Vehicle &v)
{
    v.n = v.params.rotor_count;
    v.axis.clear();
    v.position.clear();
    v.thrust.clear();
    v.torque.clear();
    for (int i = 0; i < v.n; i++) {
        const fc_rotor_params &r = v.params.rotor[i];
        v.axis.emplace_back(to_double(r.axis_unit.x, FC_UNIT_FRAC), to_double(r.axis_unit.y, FC_UNIT_FRAC),
                            to_double(r.axis_unit.z, FC_UNIT_FRAC));
        v.position.emplace_back(to_double(r.position_m.x, FC_LENGTH_FRAC),
                                to_double(r.position_m.y, FC_LENGTH_FRAC),
                                to_double(r.position_m.z, FC_LENGTH_FRAC));
        v.thrust.push_back(to_double(r.thrust_max_n, FC_FORCE_FRAC));
        v.torque.push_back(to_double(r.torque_max_nm, FC_MOMENT_FRAC));
    }
}

// A (2.5) in double from the definition.
MatrixXd effectiveness_double(const Vehicle &v)
{
    MatrixXd a(4, v.n);
    for (int i = 0; i < v.n; i++) {
        const Vector3d lever = v.position[i].cross(v.axis[i]);
        a(0, i) = v.thrust[i] * v.axis[i].z();
        for (int k = 0; k < 3; k++) {
            a(1 + k, i) = v.thrust[i] * lever[k] + v.torque[i] * v.axis[i][k];
        }
    }
    return a;
}

MatrixXd to_eigen(const fc_mat &m)
{
    MatrixXd e(m.rows, m.cols);
    for (int i = 0; i < m.rows; i++) {
        for (int j = 0; j < m.cols; j++) {
            e(i, j) = to_double(m.a[i][j], FC_MAT_FRAC);
        }
    }
    return e;
}

double cond_of(const MatrixXd &m)
{
    const Eigen::JacobiSVD<MatrixXd> svd(m);
    const Eigen::VectorXd &sv = svd.singularValues();
    return sv(sv.size() - 1) > 0.0 ? sv(0) / sv(sv.size() - 1) : INFINITY;
}

Vehicle preset(void (*fn)(fc_allocation_params *))
{
    Vehicle v;
    fn(&v.params);
    read_back(v);
    return v;
}

Vehicle random_vehicle(std::mt19937 &rng, Quantiser &quantise)
{
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    Vehicle v;
    fc_allocation_params &p = v.params;
    p = fc_allocation_params{};
    const int n = 4 + static_cast<int>(rng() % 5u);
    p.rotor_count = static_cast<uint8_t>(n);
    p.newton_iterations = 2u;
    const double thrust = 0.05 + 29.95 * unit(rng) * unit(rng); // more small vehicles
    const double ratio = 0.005 + 0.025 * unit(rng);
    const double phase = 2.0 * kPi * unit(rng);
    const double u_min = 0.3 * unit(rng);
    for (int i = 0; i < n; i++) {
        fc_rotor_params &r = p.rotor[i];
        const double angle = phase + 2.0 * kPi * (i + 0.3 * (unit(rng) - 0.5)) / n;
        const double arm = 0.05 + 0.95 * unit(rng);
        const Vector3d position(arm * std::cos(angle), arm * std::sin(angle), 0.2 * (unit(rng) - 0.5));
        // an axis within 25 deg of +z, uniform in azimuth
        const double tilt = 25.0 * kPi / 180.0 * unit(rng);
        const double azimuth = 2.0 * kPi * unit(rng);
        const Vector3d axis(std::sin(tilt) * std::cos(azimuth), std::sin(tilt) * std::sin(azimuth),
                            std::cos(tilt));
        const double t = thrust * (0.8 + 0.4 * unit(rng));
        r.axis_unit = fc_vec3_make(quantise(axis.x(), FC_UNIT_FRAC), quantise(axis.y(), FC_UNIT_FRAC),
                                   quantise(axis.z(), FC_UNIT_FRAC));
        r.position_m = fc_vec3_make(quantise(position.x(), FC_LENGTH_FRAC),
                                    quantise(position.y(), FC_LENGTH_FRAC),
                                    quantise(position.z(), FC_LENGTH_FRAC));
        r.thrust_max_n = quantise(t, FC_FORCE_FRAC);
        r.torque_max_nm = quantise((i % 2 == 0 ? 1.0 : -1.0) * ratio * t, FC_MOMENT_FRAC);
        r.thrust_exponent = FC_C(2.0f, RATIO);
        r.torque_exponent = FC_C(2.0f, RATIO);
        r.speed_min = quantise(u_min, FC_UNIT_FRAC);
    }
    read_back(v);
    return v;
}

std::string show(const Vehicle &v)
{
    std::string s = "n " + std::to_string(v.n);
    char buf[160];
    for (int i = 0; i < v.n; i++) {
        std::snprintf(buf, sizeof buf, " | d (%.6f %.6f %.6f) l (%.6f %.6f %.6f) T %.6f Q %.6f",
                      v.axis[i].x(), v.axis[i].y(), v.axis[i].z(), v.position[i].x(), v.position[i].y(),
                      v.position[i].z(), v.thrust[i], v.torque[i]);
        s += buf;
    }
    return s;
}

struct Checks {
    Check effectiveness{"alloc.effectiveness", unit_name(FC_MAT_FRAC),
                        kFixed ? "1.5 + T/2 LSB" : "4 eps (T|l| + |Q| + T)"};
    Check authority{"alloc.authority", kFixed ? "LSB(Q20/Q24)" : "abs",
                    kFixed ? "n/2; sum(1.5 + T/2)/2 + 1/2 LSB" : "sum of the entries' + n eps"};
    Check normalised{"alloc.normalised", unit_name(FC_MAT_FRAC), "rn e + |B| rel(rn) + rounding"};
    Check pinv{"alloc.pinv", unit_name(FC_MAT_FRAC),
                kFixed ? "2 cond^2 LSB + 2048 (PINV16)" : "4 eps cond^2 max|P|"};
    Check chain{"alloc.pinv_chain", "rel",
                kFixed ? "2e-6 cond^2 + rel(authority) + PINV16" : "8 eps cond^2 + rel(authority)"};
    Check accept{"alloc.accept", "-", "OK iff max|pinv(B)| <= 8 (+-0.1)"};
    double worst_pinv_per_cond2 = 0.0;
    double worst_chain_per_cond2 = 0.0;
    double worst_authority_rel = 0.0; // the largest relative authority error met (pinv_chain)
    double worst_cond = 0.0;
    long out_of_range = 0; // rejected for the documented range limits (not counted as failures)
    long rejected_ill_conditioned = 0; // rejected with max|pinv(B)| > 15.9 (allowed)
    long rejected_cond_da_30 = 0; // of those, with cond(D A) <= 30 (the old criterion)
};

// All checks on one vehicle (a rejected one only for the accept check).
void check_vehicle(Checks &c, const Vehicle &v, const std::string &label)
{
    fc_allocation a;
    const fc_init_result init = fc_allocation_init(&a, &v.params);
    const MatrixXd a_double = effectiveness_double(v);
    const auto describe = [&] { return label + " " + show(v); };

    // the row scales the library should pick: 2^e with the largest entry in (0.5, 1]
    Eigen::Vector4d scale_double;
    for (int k = 0; k < 4; k++) {
        const double largest = a_double.row(k).cwiseAbs().maxCoeff();
        scale_double[k] = largest > 0.0 ? std::ldexp(1.0, -static_cast<int>(std::ceil(std::log2(largest)))) : 0.0;
    }
    // cond(D A), which the skip of the accuracy checks and the worst-cond
    // note refer to (as before B replaced D A)
    const double cond = cond_of(scale_double.asDiagonal() * a_double);
    // B = N A from the authorities as fc/allocation.h defines them, from |A|:
    // F_max = sum_i |A_0i|, sum_i |A_ki| / 2 per moment axis
    Eigen::Vector4d authority_double;
    authority_double[0] = a_double.row(0).cwiseAbs().sum();
    for (int k = 1; k < 4; k++) {
        authority_double[k] = 0.5 * a_double.row(k).cwiseAbs().sum();
    }
    const MatrixXd b_double = authority_double.cwiseInverse().asDiagonal() * a_double;
    // max|pinv(B)|; infinite for a B of rank < 4 (whose COD pseudo-inverse
    // would be finite)
    const double cond_b = cond_of(b_double);
    const double pinv_max =
        cond_b < 1e12
            ? Eigen::CompleteOrthogonalDecomposition<MatrixXd>(b_double).pseudoInverse().cwiseAbs().maxCoeff()
            : INFINITY;
    // the documented range limits (fc/allocation.h): sum_i |A_ki| <= 1500 N
    // (F_z) and <= 100 N m (moments), F_max >= 1/16 N; a vehicle near them
    // may go either way (the random ones have F_max >= 0.14 N)
    bool near_limits = a_double.row(0).cwiseAbs().sum() > 1490.0 || a_double.row(0).cwiseAbs().sum() < 0.0626;
    for (int k = 1; k < 4; k++) {
        near_limits = near_limits || a_double.row(k).cwiseAbs().sum() > 99.0;
    }
    if (init != FC_INIT_OK) {
        c.accept.record(0.0, 0.0, describe);
        if (near_limits) {
            c.out_of_range++;
            if (init != FC_INIT_BAD_PARAM) {
                c.accept.fail("init " + std::to_string(static_cast<int>(init)) +
                              " beyond the range limits, " + describe());
            }
        } else if (pinv_max > kPinvMustAccept) {
            c.rejected_ill_conditioned++;
            if (cond <= 30.0) {
                c.rejected_cond_da_30++;
            }
        } else {
            c.accept.fail("init " + std::to_string(static_cast<int>(init)) + " at max|pinv(B)| " +
                          std::to_string(pinv_max) + " (cond(D A) " + std::to_string(cond) + "), " + describe());
        }
        return;
    }
    c.accept.record(0.0, 0.0, describe);
    if (pinv_max >= kPinvMustReject) {
        c.accept.fail("init OK with max|pinv(B)| " + std::to_string(pinv_max) + ", " + describe());
    }
    if (!(cond <= kCondSkip)) {
        c.effectiveness.skip();
        c.authority.skip();
        c.normalised.skip();
        c.pinv.skip();
        c.chain.skip();
        return;
    }
    c.worst_cond = std::max(c.worst_cond, cond);

    // effectiveness
    fc_mat m;
    if (fc_allocation_effectiveness(&a, &m) != FC_MAT_OK || m.rows != 4 || m.cols != v.n) {
        c.effectiveness.fail("effectiveness status/size, " + describe());
        return;
    }
    const MatrixXd a_lib = to_eigen(m);
    double eff_err = 0.0, eff_ratio = -1.0, eff_bound = 0.0;
    for (int i = 0; i < v.n; i++) {
        for (int k = 0; k < 4; k++) {
            const double err = error_units(a_lib(k, i) - a_double(k, i), FC_MAT_FRAC);
            const double bound = kFixed ? 1.5 + 0.5 * v.thrust[i]
                                        : 4.0 * FLT_EPSILON *
                                              (v.thrust[i] * v.position[i].norm() + std::fabs(v.torque[i]) +
                                               v.thrust[i]);
            if (err / bound > eff_ratio) {
                eff_ratio = err / bound;
                eff_err = err;
                eff_bound = bound;
            }
        }
    }
    c.effectiveness.record(eff_err, eff_bound, describe);

    // the authorities: F_max = sum_i |A_0i|, sum_i |A_ki| / 2 per moment axis
    const int n = v.n;
    Eigen::Vector4d authority_lib, authority_bound;
    authority_lib << to_double(a.thrust_max_n, FC_FORCE_FRAC), to_double(a.moment_authority_nm.x, FC_MOMENT_FRAC),
        to_double(a.moment_authority_nm.y, FC_MOMENT_FRAC), to_double(a.moment_authority_nm.z, FC_MOMENT_FRAC);
    {
        double fixed_moment = 0.0, float_moment = 0.0, float_thrust = 0.0;
        for (int i = 0; i < n; i++) {
            fixed_moment += 1.5 + 0.5 * v.thrust[i];
            float_moment += 4.0 * FLT_EPSILON *
                            (v.thrust[i] * v.position[i].norm() + std::fabs(v.torque[i]) + v.thrust[i]);
            float_thrust += FLT_EPSILON * std::fabs(a_double(0, i));
        }
        // fixed in LSB of FORCE (row 0) and MOMENT; float absolute
        authority_bound[0] = kFixed ? 0.5 * n : float_thrust + n * FLT_EPSILON * authority_double[0];
        for (int k = 1; k < 4; k++) {
            authority_bound[k] =
                kFixed ? 0.5 * fixed_moment + 0.5 : 0.5 * float_moment + n * FLT_EPSILON * authority_double[k];
        }
    }
    // the relative error of the library's authorities, each within its bound
    // (checked here), carried by the columns of P N (pinv_chain)
    double authority_rel = 0.0;
    for (int k = 0; k < 4; k++) {
        const int frac = k == 0 ? FC_FORCE_FRAC : FC_MOMENT_FRAC;
        const double err = error_units(authority_lib[k] - authority_double[k], frac);
        c.authority.record(err, authority_bound[k],
                           [&] { return "row " + std::to_string(k) + " " + describe(); });
        authority_rel = std::max(authority_rel, std::fabs(authority_double[k] / authority_lib[k] - 1.0));
    }
    c.worst_authority_rel = std::max(c.worst_authority_rel, authority_rel);

    // the row scales (the struct's own, fixed-point exact): 2^e with the
    // largest entry of D A in (0.5, 1]
    Eigen::Vector4d scale;
    for (int k = 0; k < 4; k++) {
        scale[k] = to_double(a.row_scale[k], FC_GAIN_FRAC);
        const double largest = (scale[k] * a_double.row(k)).cwiseAbs().maxCoeff();
        if (scale[k] != scale_double[k] &&
            !(largest > 0.5 - 1e-6 && largest <= 1.0 + 1e-6)) { // a rounding at a power of two is fine
            c.normalised.fail("row scale " + std::to_string(k) + " = " + std::to_string(scale[k]) +
                              ", expected " + std::to_string(scale_double[k]) + ", " + describe());
        }
    }

    // B = N A in double (above), against the library's
    fc_mat b_lib;
    if (fc_allocation_effectiveness_normalised(&a, &b_lib) != FC_MAT_OK || b_lib.rows != 4 || b_lib.cols != n) {
        c.normalised.fail("normalised status/size, " + describe());
        return;
    }
    const MatrixXd b_eig = to_eigen(b_lib);
    const double lsb = std::ldexp(1.0, -FC_MAT_FRAC);
    double b_err = 0.0, b_ratio = -1.0, b_bound = 0.0;
    for (int k = 0; k < 4; k++) {
        // e_ki, the bound of (D A)_ki (value units), and S_k = sum_i |(D A)_ki|
        Eigen::VectorXd e(n);
        for (int i = 0; i < n; i++) {
            const double t2e = v.thrust[i] * scale[k];
            e[i] = kFixed ? (1.5 + 0.5 * t2e) * lsb
                          : 4.0 * FLT_EPSILON *
                                (t2e * (v.position[i].norm() + 1.0) + std::fabs(v.torque[i]) * scale[k]);
        }
        const double s_k = scale[k] * a_double.row(k).cwiseAbs().sum();
        const double rn = (k == 0 ? 1.0 : 2.0) / s_k;
        const double rel_rn = e.sum() / s_k + (kFixed ? 0.5 * lsb / rn : 0.5 * (n + 1) * FLT_EPSILON);
        for (int i = 0; i < n; i++) {
            const double b = std::fabs(b_double(k, i));
            const double bound_value = rn * e[i] + b * rel_rn + (kFixed ? 0.5 * lsb : 0.5 * FLT_EPSILON * b);
            const double bound = kFixed ? bound_value / lsb : bound_value;
            const double err = error_units(b_eig(k, i) - b_double(k, i), FC_MAT_FRAC);
            if (err / bound > b_ratio) {
                b_ratio = err / bound;
                b_err = err;
                b_bound = bound;
            }
        }
    }
    c.normalised.record(b_err, b_bound, describe);

    // pinv of the library's own B
    fc_mat p_lib;
    (void)fc_allocation_pinv_normalised(&a, &p_lib);
    const MatrixXd p_eig = to_eigen(p_lib);
    const double cond_lib = cond_of(b_eig);
    const MatrixXd p_want = Eigen::CompleteOrthogonalDecomposition<MatrixXd>(b_eig).pseudoInverse();
    const double p_scale = kFixed ? 1.0 : p_want.cwiseAbs().maxCoeff();
    const double p_err = error_units((p_eig - p_want).cwiseAbs().maxCoeff(), FC_MAT_FRAC);
    // fixed: P is held in PINV16 (Q12), rounded to nearest: half an LSB, in LSB of Q24
    const double p_rounding = kFixed ? std::ldexp(0.5, FC_MAT_FRAC - FC_PINV16_FRAC) : 0.0;
    c.worst_pinv_per_cond2 =
        std::max(c.worst_pinv_per_cond2, std::max(0.0, p_err - p_rounding) / (cond_lib * cond_lib * p_scale));
    c.pinv.record(p_err, pick(2.0, 4.0 * FLT_EPSILON) * cond_lib * cond_lib * p_scale + p_rounding, describe);

    // the whole chain: P N (the library's authorities) against pinv(A) from the definition
    const MatrixXd chain = p_eig * authority_lib.cwiseInverse().asDiagonal();
    const MatrixXd chain_want = Eigen::CompleteOrthogonalDecomposition<MatrixXd>(a_double).pseudoInverse();
    const double chain_err =
        (chain - chain_want).cwiseAbs().maxCoeff() / chain_want.cwiseAbs().maxCoeff();
    // fixed: P's rounding to PINV16 (2^-13) in column k of P N is 2^-13 / authority_k
    const double chain_rounding =
        kFixed ? std::ldexp(1.0, -FC_PINV16_FRAC - 1) * authority_lib.cwiseInverse().maxCoeff() /
                     chain_want.cwiseAbs().maxCoeff()
               : 0.0;
    c.worst_chain_per_cond2 =
        std::max(c.worst_chain_per_cond2, (chain_err - authority_rel - chain_rounding) / (cond_b * cond_b));
    c.chain.record(chain_err, pick(2e-6, 8.0 * FLT_EPSILON) * cond_b * cond_b + authority_rel + chain_rounding,
                   describe);
}

bool run_accuracy()
{
    std::mt19937 rng(kSeed ^ 0xA110Cu);
    Quantiser quantise(rng);
    Checks c;
    check_vehicle(c, preset(fc_allocation_preset_crazyflie2), "preset crazyflie2");
    check_vehicle(c, preset(fc_allocation_preset_f450), "preset f450");
    check_vehicle(c, preset(fc_allocation_preset_hexa_x_4kg), "preset hexa_x_4kg");
    for (int i = 0; i < kCases; i++) {
        check_vehicle(c, random_vehicle(rng, quantise), "random " + std::to_string(i));
    }
    char note[128];
    std::snprintf(note, sizeof note, "worst err/%s %.3g%s, worst cond %.1f",
                  kFixed ? "cond^2" : "(cond^2 max|P|)",
                  kFixed ? c.worst_pinv_per_cond2 : c.worst_pinv_per_cond2 / FLT_EPSILON, kFixed ? " LSB" : " eps",
                  c.worst_cond);
    c.pinv.set_note(note);
    std::snprintf(note, sizeof note, "worst (rel err - rel(authority))/cond^2 %.3g, largest rel(authority) %.3g",
                  c.worst_chain_per_cond2, c.worst_authority_rel);
    c.chain.set_note(note);
    std::snprintf(note, sizeof note,
                  "rejected: %ld beyond the range limits, %ld with max|pinv(B)| > %.1f "
                  "(%ld of them cond(D A) <= 30)",
                  c.out_of_range, c.rejected_ill_conditioned, kPinvMustAccept, c.rejected_cond_da_30);
    c.accept.set_note(note);
    bool ok = c.effectiveness.summary();
    ok &= c.authority.summary();
    ok &= c.normalised.summary();
    ok &= c.pinv.summary();
    ok &= c.chain.summary();
    ok &= c.accept.summary();
    return ok;
}

// Geometries of rank < 4, each with random sizes.
bool run_rank()
{
    // not dithered: the dither (up to 255 LSB of LENGTH, 2.4e-4 m) would move
    // the rotors off the line and make the geometry merely ill-conditioned
    std::mt19937 rng(kSeed ^ 0x4A4Bu);
    const auto quantise = [](double x, int frac) { return fc_from_float(static_cast<float>(x), frac); };
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    Check check("alloc.rank_deficient", "-", "FC_INIT_RANK_DEFICIENT");
    for (int c = 0; c < 2000; c++) {
        const int kind = c % 4;
        fc_allocation_params p{};
        const int n = kind == 3 ? 1 + static_cast<int>(rng() % 3u) : 4 + static_cast<int>(rng() % 5u);
        p.rotor_count = static_cast<uint8_t>(n);
        const double thrust = 0.1 + 20.0 * unit(rng);
        const double direction = 2.0 * kPi * unit(rng);
        for (int i = 0; i < n; i++) {
            fc_rotor_params &r = p.rotor[i];
            Vector3d position;
            const double s = 0.1 + 0.8 * unit(rng);
            switch (kind) {
            case 0: // on one line through the centre of mass (both sides)
                position = Vector3d(std::cos(direction), std::sin(direction), 0.0) * (i % 2 == 0 ? s : -s);
                break;
            case 1: // a coaxial stack on the z axis
                position = Vector3d(0.0, 0.0, 0.1 * i - 0.2);
                break;
            default: // a regular planar layout (kind 2: one spin direction; kind 3: n < 4)
                position = Vector3d(s * std::cos(direction + 2.0 * kPi * i / n),
                                    s * std::sin(direction + 2.0 * kPi * i / n), 0.0);
                break;
            }
            r.axis_unit = fc_vec3_make(FC_INT(0, UNIT), FC_INT(0, UNIT), FC_INT(1, UNIT));
            r.position_m = fc_vec3_make(quantise(position.x(), FC_LENGTH_FRAC),
                                        quantise(position.y(), FC_LENGTH_FRAC),
                                        quantise(position.z(), FC_LENGTH_FRAC));
            r.thrust_max_n = quantise(thrust, FC_FORCE_FRAC);
            const double sign = kind == 2 ? 1.0 : (i % 2 == 0 ? 1.0 : -1.0);
            // kind 2: one spin, all rotors the same T_max and Q_max: yaw row = thrust row * Q/T
            r.torque_max_nm = quantise(sign * 0.015 * thrust, FC_MOMENT_FRAC);
            if (kind == 2 && i > 0) {
                r.thrust_max_n = p.rotor[0].thrust_max_n;
                r.torque_max_nm = p.rotor[0].torque_max_nm;
            }
            r.thrust_exponent = FC_C(2.0f, RATIO);
            r.torque_exponent = FC_C(2.0f, RATIO);
            r.speed_min = FC_C(0.1f, UNIT);
        }
        fc_allocation a;
        const fc_init_result init = fc_allocation_init(&a, &p);
        check.record(init == FC_INIT_RANK_DEFICIENT ? 0.0 : 1.0, 0.0, [&] {
            return "kind " + std::to_string(kind) + " n " + std::to_string(n) + " init " +
                   std::to_string(static_cast<int>(init));
        });
    }
    return check.summary();
}

} // namespace

int main()
{
    std::printf("test_allocation_oracle: backend %s, seed 0x%08X, %d random geometries\n", kBackend,
                static_cast<unsigned>(kSeed), kCases);
    bool ok = run_accuracy();
    ok &= run_rank();
    std::printf("test_allocation_oracle: %s\n", ok ? "all checks passed" : "SOME CHECKS FAILED");
    return ok ? 0 : 1;
}
