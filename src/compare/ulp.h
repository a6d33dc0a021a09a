// Units in the last place, for values the variants return (all exactly
// representable in their precision). The exact counterpart, ulp of an exact
// root, lives in the oracle (exact_solution::root_ulp_error).
//
// Definition (as glibc's libm tests): for 2^e ≤ |x| < 2^(e+1),
// ulp(x) = 2^(max(e, emin) − p + 1), p = 24 or 53, emin = −126 or −1022;
// ulp(0) is the smallest subnormal.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

namespace rayverify {

template <class T>
double ulp_of(T x) {
    constexpr int p = std::numeric_limits<T>::digits;
    constexpr int emin = std::numeric_limits<T>::min_exponent - 1;
    if (x == 0) return std::ldexp(1.0, emin - p + 1);
    const int e = std::ilogb(x);
    return std::ldexp(1.0, (e > emin ? e : emin) - p + 1);
}

// How many representable T lie between a and b (0 when equal; ±0 are one
// number); +inf when either is NaN.
template <class T>
double ulps_between(T a, T b) {
    if (std::isnan(a) || std::isnan(b)) return std::numeric_limits<double>::infinity();
    using bits = std::conditional_t<sizeof(T) == 4, std::int32_t, std::int64_t>;
    // Map the sign-magnitude encoding onto a monotone integer line.
    const auto ordered = [](T x) -> long double {
        const bits raw = std::bit_cast<bits>(x);
        return raw < 0 ? -static_cast<long double>(raw & std::numeric_limits<bits>::max())
                       : static_cast<long double>(raw);
    };
    return static_cast<double>(std::fabs(ordered(a) - ordered(b)));
}

// Herbie's "bits of error": log2(1 + ulps between computed and RN(exact)).
inline double error_bits(double ulps_between_rounded) { return std::log2(1.0 + ulps_between_rounded); }

}  // namespace rayverify
