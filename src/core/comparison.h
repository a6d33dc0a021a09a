// The result of comparing two values, as CGAL's Comparison_result:
// compare(a, b) is always sign(a − b), `smaller` when a < b. Every exact
// comparison the oracle answers, and the judge and the scene audit ask,
// returns one, with its arguments in the order its name reads: the oracle's
// compare_to_root(value, i) is compare(value, t*ᵢ). A comparison a stage of
// the oracle cannot settle is an uncertain_comparison, empty, and the next
// stage settles it.
#pragma once

#include <optional>

namespace rayverify {

enum class comparison : signed char { smaller = -1, equal = 0, larger = 1 };

using uncertain_comparison = std::optional<comparison>;

// compare(a, b) for values ordered by < (neither a NaN).
template <class T>
constexpr comparison compare(const T& a, const T& b) {
    return a < b ? comparison::smaller : b < a ? comparison::larger : comparison::equal;
}

// compare(b, a), given compare(a, b).
constexpr comparison opposite(comparison c) { return static_cast<comparison>(-static_cast<int>(c)); }

// The comparison whose sign(a − b) is `sign` (−1, 0 or +1; any negative or positive value).
constexpr comparison comparison_of_sign(int sign) {
    return sign < 0 ? comparison::smaller : sign > 0 ? comparison::larger : comparison::equal;
}

}  // namespace rayverify
