// oracle_common.hpp - shared scaffolding of the Eigen oracle tests.
//
// The library is C; its headers are included as C (extern "C") and compile
// unchanged as C++17. Every check draws its inputs from a std::mt19937 with a
// constant seed, quantises them into the backend of this build, computes the
// reference in double with Eigen from the QUANTISED inputs (so only the error
// of the function under test is measured), and records per case the error and
// the bound it must stay within.
//
// Units of the reported errors:
//   fixed  LSB of the output's Q-format (1 LSB of UNIT = 2^-30, of LENGTH = 2^-20, ...)
//   float  absolute error in the output's own unit (also shown as multiples of
//          FLT_EPSILON = 1.19e-7)
#ifndef FC_ORACLE_COMMON_HPP
#define FC_ORACLE_COMMON_HPP

extern "C" {
#include "fc/mat.h"
#include "fc/quat.h"
#include "fc/scalar.h"
#include "fc/vec3.h"
}

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace oracle {

constexpr bool kFixed = FC_NUMERIC_FIXED != 0;
constexpr const char *kBackend = kFixed ? "fixed" : "float";
// One constant seed for every run: a failure is reproducible by its case number.
// (FC_ORACLE_SEED lets a developer build the programs with another seed by hand
// to see how stable the worst errors are; the CMake build never sets it.)
#ifndef FC_ORACLE_SEED
#define FC_ORACLE_SEED 0x0FC0A11Eu
#endif
constexpr std::uint32_t kSeed = FC_ORACLE_SEED;
constexpr int kCases = 5000;

// Each check draws from its own stream, seeded from kSeed and its name (FNV-1a),
// so a check's cases and results do not depend on which other checks ran
// before it in the same process.
inline std::uint32_t seed_for(const std::string &name, int salt = 0)
{
    std::uint32_t h = 2166136261u;
    for (const char c : name) {
        h = (h ^ static_cast<unsigned char>(c)) * 16777619u;
    }
    return h ^ kSeed ^ (static_cast<std::uint32_t>(salt) * 2654435761u);
}

// The exact value of a backend number, as a double.
//
// Not fc_to_float: in fixed it goes through a float, whose 24-bit mantissa
// rounds a 31-bit Q-value by up to 2^-24 relative (64 LSB of a Q30 value near
// 1), more than the errors measured here. Inputs and outputs are therefore
// read back exactly: value * 2^-FRAC in fixed (exact in a double), the float
// itself in the float backend (identical to fc_to_float there).
inline double to_double(fc_real r, int frac)
{
#if FC_NUMERIC_FIXED
    return std::ldexp(static_cast<double>(r), -frac);
#else
    (void)frac;
    return static_cast<double>(r);
#endif
}

// A random double quantised into the backend: the representable value
// nearest x, starting from fc_from_float.
//
// In fixed, fc_from_float goes through a float, so a Q30 value it returns has
// only 24 significant bits (its low 6-7 bits are zero, and a unit quaternion
// made of such values is unit only to ~1e-7). Products of such values have
// all-zero low bits, which would hide any truncation of low bits inside the
// library's 64-bit accumulators (fc_dot2/3/4, fc_acc). The value is
// therefore refined by the residual x - value, rounded in the Q-format: the
// result is the Q-value nearest x (every bit populated, a unit quaternion
// unit to ~2e-9). The float backend keeps the float fc_from_float returned.
// Either way the reference reads the value back exactly (to_double), so the
// quantisation is part of the input, not of the error.
//
// (The generator argument is kept for the callers; quantising draws nothing.)
class Quantiser {
public:
    explicit Quantiser(std::mt19937 &) {}

    fc_real operator()(double x, int frac) const
    {
        fc_real r = fc_from_float(static_cast<float>(x), frac);
#if FC_NUMERIC_FIXED
        const double residual_lsb = std::ldexp(x - to_double(r, frac), frac);
        if (std::fabs(residual_lsb) < 1e6) { // not for x outside the format (saturated)
            const std::int64_t v = static_cast<std::int64_t>(r) + std::llround(residual_lsb);
            r = static_cast<fc_real>(std::clamp<std::int64_t>(v, FC_REAL_MIN, FC_REAL_MAX));
        }
#endif
        return r;
    }
};

// |error| in the reporting unit: LSB of format frac in fixed, absolute in float.
inline double error_units(double error, int frac)
{
    return kFixed ? std::fabs(error) * std::ldexp(1.0, frac) : std::fabs(error);
}

inline const char *unit_name(int frac)
{
    if (!kFixed) {
        return "abs";
    }
    switch (frac) {
    case FC_UNIT_FRAC:
        return "LSB(Q30)";
    case FC_LENGTH_FRAC:
        return "LSB(Q20)";
    case FC_MAT_FRAC:
        return "LSB(Q24)";
    default:
        return "LSB";
    }
}

// The record of one check: cases, the worst error, failures with the input.
class Check {
public:
    Check(std::string name, std::string unit, std::string bound_text)
        : name_(std::move(name)), unit_(std::move(unit)), bound_text_(std::move(bound_text))
    {
    }

    // err and bound in the same unit; describe() prints the input of a failure.
    void record(double err, double bound, const std::function<std::string()> &describe)
    {
        cases_++;
        const bool bad = !(err <= bound); // NaN fails
        if (err > worst_ || std::isnan(err)) {
            worst_ = err;
        }
        if (bound > 0.0 && err / bound > worst_ratio_) {
            worst_ratio_ = err / bound;
        }
        if (bad) {
            fail(describe() + " err " + fmt(err) + " > bound " + fmt(bound));
        }
    }

    // A failure that is not an error size (saturation flag, status code).
    void fail(const std::string &what)
    {
        failures_++;
        if (failures_ <= kMaxPrinted) {
            std::printf("  FAIL %s case %ld: %s\n", name_.c_str(), cases_, what.c_str());
        }
    }

    void skip() { skipped_++; }
    long cases() const { return cases_; }

    // Extra text for the summary line (e.g. the worst error / cond^2).
    void set_note(std::string note) { note_ = std::move(note); }

    bool summary() const
    {
        std::printf("oracle %-5s %-26s cases %5ld", kBackend, name_.c_str(), cases_);
        if (skipped_ > 0) {
            std::printf(" (skipped %ld)", skipped_);
        }
        std::printf("  worst %-10s %s", fmt(worst_).c_str(), unit_.c_str());
        if (!kFixed) {
            std::printf(" (%.2f eps)", worst_ / FLT_EPSILON);
        }
        std::printf("  bound %s  worst/bound %.2f", bound_text_.c_str(), worst_ratio_);
        if (!note_.empty()) {
            std::printf("  %s", note_.c_str());
        }
        const bool ok = failures_ == 0 && cases_ > 0;
        std::printf("  %s", ok ? "PASS" : "FAIL");
        if (failures_ > 0) {
            std::printf(" (%ld failures)", failures_);
        }
        std::printf("\n");
        return ok;
    }

    static std::string fmt(double v)
    {
        char buf[64];
        std::snprintf(buf, sizeof buf, kFixed ? "%.3f" : "%.3g", v);
        return buf;
    }

private:
    static constexpr long kMaxPrinted = 12;
    std::string name_, unit_, bound_text_, note_;
    long cases_ = 0, skipped_ = 0, failures_ = 0;
    double worst_ = 0.0, worst_ratio_ = 0.0;
};

// Both backends in one expression: the fixed bound in LSB, the float bound absolute.
inline double pick(double fixed_lsb, double float_abs)
{
    return kFixed ? fixed_lsb : float_abs;
}

inline std::string bound_text(double fixed_lsb, double float_abs)
{
    char buf[64];
    if (kFixed) {
        std::snprintf(buf, sizeof buf, "%g LSB", fixed_lsb);
    } else {
        std::snprintf(buf, sizeof buf, "%g", float_abs);
    }
    return buf;
}

} // namespace oracle

#endif // FC_ORACLE_COMMON_HPP
