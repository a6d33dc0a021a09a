// AArch64's single-precision reciprocal estimate and Newton step, bit for bit
// as the Arm Architecture Reference Manual defines them (shared/functions/
// float/fprecipestimate/FPRecipEstimate with RecipEstimate, and
// FPRecipStepFused), so a port that calls vrecpe/vrecps runs the same on any
// host. Unlike x86's rcpss, whose table each vendor chooses, FRECPE is
// architecturally exact: every conforming aarch64 CPU returns these bits.
//
// FPCR as Linux and macOS leave it: round to nearest, FZ = 0 (subnormals
// kept), DN = 0, AH = 0 (so no FEAT_RPRES 12-bit estimate).
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include "intersectors/scalar_math.h"
#include "intersectors/traced.h"

namespace rayverify::intersectors::neon {

// RecipEstimate: a in [256, 512) stands for a/512 ∈ [0.5, 1); the result in
// [256, 512) for result/256 ∈ [1, 2), the reciprocal of a's interval
// midpoint rounded to nearest.
constexpr int recip_estimate(int a) {
    a = a * 2 + 1;
    const int b = (1 << 19) / a;
    return (b + 1) / 2;
}

// FRECPE (vrecpe_f32): an 8-bit estimate of 1/x.
inline float frecpe(float x) {
    const std::uint32_t bits = std::bit_cast<std::uint32_t>(x);
    const std::uint32_t sign = bits & 0x80000000u;
    if (std::isnan(x)) return std::bit_cast<float>(bits | 0x00400000u);  // FPProcessNaN: quieted
    if (std::isinf(x)) return std::bit_cast<float>(sign);                // ±0
    if (x == 0.0f) return std::bit_cast<float>(sign | 0x7f800000u);      // ±inf
    // Below 2^-128 the estimate overflows: ±inf when rounding to nearest.
    if (std::fabs(x) < 0x1p-128f) return std::bit_cast<float>(sign | 0x7f800000u);

    // The fraction widened to 52 bits, a subnormal's normalised as the manual does.
    int exp = static_cast<int>((bits >> 23) & 0xffu);
    constexpr std::uint64_t mask52 = (std::uint64_t{1} << 52) - 1;
    std::uint64_t fraction = static_cast<std::uint64_t>(bits & 0x7fffffu) << 29;
    if (exp == 0) {
        if (((fraction >> 51) & 1u) == 0) {
            exp = -1;
            fraction = (fraction << 2) & mask52;
        } else {
            fraction = (fraction << 1) & mask52;
        }
    }
    const int scaled = 256 | static_cast<int>(fraction >> 44);  // '1':fraction<51:44>
    int result_exp = 253 - exp;
    const int estimate = recip_estimate(scaled);

    // The estimate's low 8 bits become the fraction; a result below the
    // normal range is denormalised.
    std::uint64_t out = static_cast<std::uint64_t>(estimate & 0xff) << 44;
    if (result_exp == 0) {
        out = (std::uint64_t{1} << 51) | (out >> 1);
    } else if (result_exp == -1) {
        out = (std::uint64_t{1} << 50) | (out >> 2);
        result_exp = 0;
    }
    return std::bit_cast<float>(sign | (static_cast<std::uint32_t>(result_exp) << 23) |
                                static_cast<std::uint32_t>(out >> 29));
}

// A traced run's FRECPE: the estimate's bits, standing for the 1/x it estimates.
inline traced<float> frecpe(traced<float> x) { return computed_apart(frecpe(x.value), traced<float>(1.0f) / x); }

// FRECPS (vrecps_f32): 2 − a·b with one rounding; ∞·0 gives 2.
template <class Float>
inline Float frecps(Float a, Float b) {
    if ((isinf(a) && b == 0.0f) || (a == 0.0f && isinf(b))) return 2.0f;
    return fma(-a, b, Float(2.0f));
}

}  // namespace rayverify::intersectors::neon
