// The oracle's filter: enclosures of exact values in double-word arithmetic
// with rigorous error bounds (core/double_word.h: two_sum, two_prod, the
// double-word operations, and `bounded` values whose error bounds propagate
// through +, −, ×, √ and ÷), and what an enclosure settles by itself: a sign,
// a comparison, a correctly rounded value, a ULP error. Each answer is
// uncertain (an empty optional, a sign 0) where the bound cannot settle it;
// oracle.cpp then asks the next stage (refinement.h, then the exact route).
//
// Range. The filter runs only when every input is 0 or has magnitude in
// [2^−80, 2^80] (otherwise the exact route runs). Every input is then an
// integer multiple of 2^−132, so every exact polynomial quantity of degree k
// (a, b′, C: 2; Δ′: 4) is 0 or at least 2^−132k in magnitude, and all of them
// stay below 2^330: every product the filter forms is far from the underflow
// threshold (the smallest nonzero root is above 2^−440, a hit-point term
// above 2^−520, their low words above 2^−630), and nothing overflows. The
// relative bounds of the double-word operations, which assume no underflow,
// therefore hold.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <type_traits>

#include "core/double_word.h"
#include "core/float_bits.h"
#include "core/ray_sphere_case.h"
#include "oracle/oracle.h"

namespace rayverify::oracle_internal {

using enclosure = exact_solution::enclosure;

inline bool known(const enclosure& x) { return x.err < std::numeric_limits<double>::infinity(); }
inline bounded bounded_of(const enclosure& x) { return {{x.hi, x.lo}, x.err}; }

// A sign the filter may leave undecided (CGAL's Uncertain<Sign>): −1, 0 or
// +1 when certain, empty when the bound cannot tell.
using uncertain_sign = std::optional<int>;

// sign(x) of a bounded value, when its bound decides it (never 0: no bound
// proves a value exactly zero).
inline uncertain_sign sign_of(const bounded& x) {
    const int s = certain_sign(x);
    return s != 0 ? uncertain_sign(s) : std::nullopt;
}

// compare(x, m) when the enclosure decides it (never equal, as above).
inline uncertain_comparison compare(const enclosure& x, double m) {
    if (!known(x)) return std::nullopt;
    if (exceeds(x.hi, x.lo, x.err, m)) return comparison::larger;
    if (exceeds(-x.hi, -x.lo, x.err, -m)) return comparison::smaller;
    return std::nullopt;
}

// sign(x) when the enclosure decides it (never 0, as above).
inline uncertain_sign sign_of(const enclosure& x) {
    const uncertain_comparison c = compare(x, 0.0);
    return c ? uncertain_sign(static_cast<int>(*c)) : std::nullopt;
}

// Filter range: 0 or 2^−80 ≤ |x| ≤ 2^80 (see the range note above), for the
// magnitude of a double or of two lanes (double_word.h), without a branch; a
// NaN fails every comparison, ±inf the upper one.
template <class T>
inline auto within_filter_range(T magnitude) {
    return (magnitude == 0.0) | ((magnitude >= 0x1p-80) & (magnitude <= 0x1p80));
}

inline bool in_filter_range(double x) { return within_filter_range(std::fabs(x)); }

// The exponent of ulp(x) in precision p for 2^e ≤ |x| < 2^(e+1) (core/float_bits.h).
inline int ulp_exponent_in(precision p, long e) {
    return static_cast<int>(with_precision(p, [e]<class T>(std::type_identity<T>) { return ulp_exponent_of_binade<T>(e); }));
}

// Every input of the case in the filter range, tested two inputs at a time:
// every filtered answer asks it first.
inline bool in_filter_range(const ray_sphere<double>& g) {
    const double_pair inputs[5] = {{g.origin.x, g.origin.y},       {g.origin.z, g.direction.x},
                                   {g.direction.y, g.direction.z}, {g.centre.x, g.centre.y},
                                   {g.centre.z, g.radius}};
    auto inside = within_filter_range(fabs_lanes(inputs[0]));
#pragma GCC unroll 4
    for (int k = 1; k < 5; ++k) inside &= within_filter_range(fabs_lanes(inputs[k]));
    return in_both_lanes(inside);
}

// RN(x) in T in a few operations, where the rounding y of hi to T is normal
// in T and far from overflow: x − y = (hi − y) + lo ± err, hi − y exact (y is hi rounded
// to T; 0 for double), so RN(x) = y when |RN((hi − y) + lo)| + err stays
// below y's half gap on the nearer side (a quarter ulp below a power of two,
// taken on both sides), with a margin of 2^−50 for the roundings of the
// test. Empty where that does not hold; round_enclosure then decides.
template <class T>
inline std::optional<double> round_normalised(const enclosure& x) {
    static_assert(std::is_same_v<T, float> || std::is_same_v<T, double>);
    constexpr int digits = std::numeric_limits<T>::digits;
    constexpr double smallest = std::is_same_v<T, float> ? 0x1p-126 : 0x1p-1000;
    constexpr double largest = std::is_same_v<T, float> ? 0x1p127 : 0x1p1000;
    const T y = static_cast<T>(x.hi);
    const double magnitude = std::fabs(static_cast<double>(y));
    if (!(magnitude >= smallest && magnitude <= largest)) return std::nullopt;
    const std::uint64_t bits = std::bit_cast<std::uint64_t>(static_cast<double>(y));
    const double binade = std::bit_cast<double>(bits & 0x7FF0000000000000ull);  // 2^e ≤ |y| < 2^(e+1)
    const bool power_of_two = magnitude == binade;
    const double half_gap = binade * (power_of_two ? 0x1p-1 : 1.0) * exact_power_of_two(-digits);
    const double rest = (x.hi - static_cast<double>(y)) + x.lo;
    if (std::fabs(rest) + x.err < half_gap * (1 - 0x1p-50)) return static_cast<double>(y);
    return std::nullopt;
}
inline std::optional<double> round_normalised(precision p, const enclosure& x) {
    return p == precision::binary64 ? round_normalised<double>(x) : round_normalised<float>(x);
}

// RN(x) in precision p when the whole enclosure lies strictly inside one
// rounding interval; `sign` is x's sign, when known (for a result that
// rounds to zero). Ties and anything at a boundary are left to the next stage.
std::optional<double> round_enclosure(precision p, const enclosure& x, uncertain_sign sign);

// The exponent of ulp(x) in precision p, when the enclosure settles x's
// sign and binade.
std::optional<int> ulp_exponent_of(precision p, const enclosure& x);

// The figures below come in two forms: a double, NaN where the bound does
// not settle the figure (never a figure's value), and an optional built from
// it here. A double comes back in a register; an optional<double> came back
// through the stack, written as two words and read as one, a load that waits
// for both stores (a third of such a function's time in an audit).
inline std::optional<double> settled_unless_nan(double figure) {
    if (std::isnan(figure)) return std::nullopt;
    return figure;
}

// RN(|difference| / 2^ulp_exponent) when the bound settles it, else NaN.
double rounded_ulp_ratio_or_nan(bounded difference, int ulp_exponent);
inline std::optional<double> rounded_ulp_ratio(bounded difference, int ulp_exponent) {
    return settled_unless_nan(rounded_ulp_ratio_or_nan(difference, ulp_exponent));
}

// |value − x| / ulp(x) in precision p, correctly rounded, when the enclosure
// settles x's sign, its binade, value ≠ x and the rounding of the ratio
// (+inf for a non-finite value).
std::optional<double> ulp_error_from(precision p, const enclosure& x, double value);
// The same with ulp(x)'s exponent already known (empty: the binade is open),
// NaN where unsettled, and as an optional.
double ulp_error_or_nan(const enclosure& x, std::optional<int> ulp_exponent, double value);
inline std::optional<double> ulp_error_from(const enclosure& x, std::optional<int> ulp_exponent, double value) {
    return settled_unless_nan(ulp_error_or_nan(x, ulp_exponent, value));
}

// Bounds on |value − x| / ulp(x), ulp(x) = 2^ulp_exponent, from the
// enclosure alone; value finite. Empty where the enclosure is unknown, the
// binade open, or the scaled bounds would leave the normal range.
std::optional<figure_bracket> ulp_error_bracket_from(const enclosure& x, std::optional<int> ulp_exponent,
                                                     double value);

// Coordinate `axis` of o + t·d from an enclosure of t: o exactly when d's
// coordinate is 0, else o + t·d in double-words.
enclosure hit_coordinate_enclosure(const ray_sphere<double>& g, const enclosure& t, int axis);

// RN of a hit coordinate in precision p when its enclosure settles it.
std::optional<double> round_hit_coordinate(precision p, const ray_sphere<double>& g, const enclosure& t, int axis);

// Everything the filter settles for one case; what it leaves unknown (a sign
// 0 with a root not provably nonzero, an empty optional) the exact state
// answers.
struct filtered_case {
    // Written out, so that GCC 12 sets the members one by one: the implicit
    // constructor had it clear all 152 bytes with a `rep stos` first, whose
    // start-up was a tenth of a filtered solve.
    filtered_case() noexcept {}
    uncertain_sign discriminant_sign;  // empty: the next stage must classify
    enclosure roots[2];
    uncertain_sign sign[2];
    std::optional<double> rounded[2];
    std::optional<double> hit[3];  // the front root's: static_filter_case at oracle_depth::everything only
};

// The filter on one case: Δ′'s sign, the roots' enclosures, signs and
// roundings, as far as the bounds settle them (no hit point: solve_exact
// rounds none, and rounded_hit_coordinate rounds one from a root's enclosure
// when asked).
// `discriminant`, when given, is a tighter enclosure of Δ′ than the filter's
// own (refinement.h's, from an expansion, for a near-tangent line). With
// `unit_direction`, a is taken to be 1 (what a unit-direction formula solves).
filtered_case filter_case(const ray_sphere<double>& g, precision prec,
                          const std::optional<bounded>& discriminant = std::nullopt, bool unit_direction = false);

}  // namespace rayverify::oracle_internal
