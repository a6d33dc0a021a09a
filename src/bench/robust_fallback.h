// Which stage of robust_sphere.h answers a case, per family: its static
// filter alone (plain double with a priori bounds, inlined), its double-word
// refinement (double only, out of line), or its exact path, for each query
// level, tier and precision. The answers are the same either way; this is
// what the fast path's cost figures average over (bench prints both).
#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "core/ray_sphere_case.h"

namespace rayverify::bench {

struct robust_fallback_row {
    std::string family;
    std::string variant;      // robust, robust_nearest, robust_any_hit, robust_bounded or robust_bounded_nearest
    std::string precision;    // "float" or "double"
    std::size_t cases = 0;    // valid at that precision
    std::size_t refined = 0;  // of them, left by the static filter to the double-word stage (which answered)
    std::size_t exact = 0;    // left to the exact path
};

// The robust variants' names, in registry order.
inline const char* const robust_variant_names[] = {"robust", "robust_nearest", "robust_any_hit", "robust_bounded",
                                                   "robust_bounded_nearest"};

// Every robust variant in float and double on each family's cases (the
// interval ones asked on each case's interval, as the audit asks them).
std::vector<robust_fallback_row> robust_fallbacks(const std::map<std::string, std::vector<corpus_case>>& by_family);

}  // namespace rayverify::bench
