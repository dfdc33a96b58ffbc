// oracle_scalar.cpp - fc_sin and fc_cos against std::sin and std::cos.
//
// Not an Eigen check (Eigen's array sin is std::sin): it sits here because the
// quaternion exponential (oracle_quat, group integrate_fast) depends on it,
// and it isolates the range reduction of the fixed backend. Angles are
// quantised to ANGLE (Q28), results are UNIT (Q30); the reference is the
// double sin/cos of the quantised angle.
//
// Two ranges:
//   |a| <= pi/4     no range reduction: the Taylor polynomial alone
//   |a| <= pi       the reduction by multiples of pi/2 as well
//
// fixed: fc/scalar.h specifies "a few UNIT LSB". The polynomial to r^9 / r^10
//   in Q30 with its roundings: measured 2.4 LSB on |a| <= pi/4. The range
//   reduction subtracts the Q28 constants pi/2 and 2 pi (FC_HALF_PI 421657428,
//   FC_TWO_PI 1686629713, exact to 0.5 LSB of Q28) and adds under 2 LSB:
//   measured 3.9 LSB on |a| <= pi. Bound 6 LSB for both. (The first Q28
//   constants, FC_C(1.57079633f, ANGLE) folded through a float, commit
//   1fa71d4, were 4.4e-8 rad off: 47 LSB beyond pi/4 and 94 LSB beyond 3pi/4.)
// float: sinf/cosf are within ~1 ulp; bound 1e-6 (8 eps) as for the other
//   unit quantities.
#include "oracle_common.hpp"

using namespace oracle;

namespace {

constexpr double kPi = 3.14159265358979323846;

bool check_sincos(double a_max, const char *name)
{
    std::mt19937 rng(seed_for(name));
    Quantiser quantise(rng);
    std::uniform_real_distribution<double> angle(-a_max, a_max);
    constexpr double fixed_bound = 6.0;
    constexpr double float_bound = 1e-6;
    Check check(name, unit_name(FC_UNIT_FRAC), bound_text(fixed_bound, float_bound));
    for (int i = 0; i < kCases; i++) {
        fc_real a = quantise(angle(rng), FC_ANGLE_FRAC);
        double ae = to_double(a, FC_ANGLE_FRAC);
        if (std::fabs(ae) > a_max) { // the dither may step just outside the range
            a = fc_from_float(static_cast<float>(std::copysign(a_max, ae) * 0.999999), FC_ANGLE_FRAC);
            ae = to_double(a, FC_ANGLE_FRAC);
        }
        fc_arith ar = {0u};
        const fc_real s = fc_sin(&ar, a);
        const fc_real c = fc_cos(&ar, a);
        const double err = std::max(error_units(to_double(s, FC_UNIT_FRAC) - std::sin(ae), FC_UNIT_FRAC),
                                    error_units(to_double(c, FC_UNIT_FRAC) - std::cos(ae), FC_UNIT_FRAC));
        const auto describe = [&] {
            char buf[160];
            std::snprintf(buf, sizeof buf, "angle %.12f rad: sin %.12f (want %.12f) cos %.12f (want %.12f)", ae,
                          to_double(s, FC_UNIT_FRAC), std::sin(ae), to_double(c, FC_UNIT_FRAC), std::cos(ae));
            return std::string(buf);
        };
        check.record(err, pick(fixed_bound, float_bound), describe);
        if (ar.saturated != 0u) {
            check.fail("saturation flag set, " + describe());
        }
    }
    return check.summary();
}

} // namespace

int main()
{
    std::printf("oracle_scalar: backend %s, seed 0x%08X, %d cases per check\n", kBackend,
                static_cast<unsigned>(kSeed), kCases);
    bool ok = true;
    ok &= check_sincos(kPi / 4.0, "sincos.quarter_pi");
    ok &= check_sincos(kPi, "sincos.pi");
    std::printf("oracle_scalar: %s\n", ok ? "all checks passed" : "SOME CHECKS FAILED");
    return ok ? 0 : 1;
}
