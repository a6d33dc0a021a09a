// Floating-point values as bits: the ordered-integer line, neighbours, ulp and
// the distance between two values in representable steps. One place for
// every such helper (as pbrt-v4's util/float.h); tests/float_bits_test.cpp
// checks each against an independent computation.
//
// The ordered line. IEEE binary formats encode sign and magnitude, so the
// bit patterns of non-negative values increase with the value and those of
// negative values decrease. ordered_index maps x to an integer that increases
// with x, one step per representable value: +0 and −0 both map to 0, the
// smallest subnormal to ±1, the largest finite value to ±(2^(w−1) − 2^(p−1) − 1),
// ±infinity one beyond it. Everything is integer arithmetic (no long double,
// which is plain double on some platforms).
//
// ulp, as glibc's libm tests define it: for 2^e ≤ |x| < 2^(e+1),
// ulp(x) = 2^(max(e, emin) − p + 1), p = 24 or 53, emin = −126 or −1022;
// ulp(0) is the smallest subnormal.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

#include "core/ray_sphere_case.h"

namespace rayverify {

template <class T>
using float_bits_t = std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>;

// x's position on the ordered line; x must not be NaN.
template <class T>
std::int64_t ordered_index(T x) {
    static_assert(std::is_floating_point_v<T> && (sizeof(T) == 4 || sizeof(T) == 8));
    using bits = float_bits_t<T>;
    constexpr bits sign_bit = bits{1} << (sizeof(T) * 8 - 1);
    const bits raw = std::bit_cast<bits>(x);
    const auto magnitude = static_cast<std::int64_t>(raw & ~sign_bit);
    return (raw & sign_bit) ? -magnitude : magnitude;
}

// The value at position i on the ordered line (0 gives +0); |i| must not
// exceed the position of infinity.
template <class T>
T from_ordered_index(std::int64_t i) {
    using bits = float_bits_t<T>;
    constexpr bits sign_bit = bits{1} << (sizeof(T) * 8 - 1);
    const bits magnitude = static_cast<bits>(i < 0 ? -i : i);
    return std::bit_cast<T>(i < 0 ? (magnitude | sign_bit) : magnitude);
}

// The position of +infinity on the ordered line.
template <class T>
constexpr std::int64_t infinity_index() {
    return static_cast<std::int64_t>(std::bit_cast<float_bits_t<T>>(std::numeric_limits<T>::infinity()));
}

// The next representable value above (below) a finite y, as nextafter toward
// +inf (−inf): the largest finite value steps to infinity; −0 and +0 step alike.
template <class T>
T next_up(T y) {
    return from_ordered_index<T>(ordered_index(y) + 1);
}
template <class T>
T next_down(T y) {
    return from_ordered_index<T>(ordered_index(y) - 1);
}

// x moved by `steps` representable values (crossing zero as one value); NaN
// when that runs past ±infinity. x must not be NaN.
template <class T>
T step_by(T x, std::int64_t steps) {
    const std::int64_t limit = infinity_index<T>();
    const std::int64_t from = ordered_index(x);
    // Room to each end of the line, in unsigned arithmetic (it can exceed 2^63).
    const std::uint64_t room = steps >= 0 ? static_cast<std::uint64_t>(limit) - static_cast<std::uint64_t>(from)
                                          : static_cast<std::uint64_t>(from) + static_cast<std::uint64_t>(limit);
    const std::uint64_t distance = steps >= 0 ? static_cast<std::uint64_t>(steps)
                                              : std::uint64_t{0} - static_cast<std::uint64_t>(steps);
    if (distance > room) return std::numeric_limits<T>::quiet_NaN();
    return from_ordered_index<T>(from + steps);
}

// 2^k exactly, −1074 ≤ k ≤ 1023, from its bits (no libm call); +inf for
// k = 1024, as ldexp.
constexpr double exact_power_of_two(int k) {
    if (k >= -1022) return std::bit_cast<double>(static_cast<std::uint64_t>(k + 1023) << 52);
    return std::bit_cast<double>(std::uint64_t{1} << (k + 1074));
}

// e with 2^e ≤ |x| < 2^(e+1) for a finite nonzero x: std::ilogb, from the bits.
inline int binade_of(double x) {
    const std::uint64_t magnitude = std::bit_cast<std::uint64_t>(x) & ~(std::uint64_t{1} << 63);
    const int biased = static_cast<int>(magnitude >> 52);
    if (biased != 0) return biased - 1023;
    return -1011 - std::countl_zero(magnitude);  // subnormal: the top bit of the significand
}

// The exponent of ulp(x) as defined above for 2^e ≤ |x| < 2^(e+1):
// max(e, emin) − p + 1 (the exponent of ulp(0) for e ≤ emin).
template <class T>
constexpr long ulp_exponent_of_binade(long e) {
    constexpr int p = std::numeric_limits<T>::digits;
    constexpr int emin = std::numeric_limits<T>::min_exponent - 1;
    return (e > emin ? e : emin) - p + 1;
}

// ulp(x) as defined above, exact in double; x finite.
template <class T>
double ulp_of(T x) {
    constexpr int emin = std::numeric_limits<T>::min_exponent - 1;
    return exact_power_of_two(static_cast<int>(ulp_exponent_of_binade<T>(x == 0 ? emin : binade_of(x))));
}

// How many representable steps separate a and b (0 when equal; ±0 are one
// value; an infinity is one step beyond the largest finite value). Neither
// may be NaN.
template <class T>
std::uint64_t ulps_between(T a, T b) {
    const std::int64_t i = ordered_index(a), j = ordered_index(b);
    // |i − j| ≤ 2^64 − 2: computed in unsigned arithmetic, where it cannot overflow.
    return i >= j ? static_cast<std::uint64_t>(i) - static_cast<std::uint64_t>(j)
                  : static_cast<std::uint64_t>(j) - static_cast<std::uint64_t>(i);
}

// Herbie's "bits of error": log2(1 + ulps between computed and RN(exact)).
inline double error_bits(std::uint64_t ulps_between_rounded) {
    return std::log2(1.0 + static_cast<double>(ulps_between_rounded));
}

// ulps_between in precision p, for two values of p carried as doubles.
inline std::uint64_t ulps_between_in(precision p, double a, double b) {
    return with_precision(
        p, [&]<class T>(std::type_identity<T>) { return ulps_between(static_cast<T>(a), static_cast<T>(b)); });
}

}  // namespace rayverify
