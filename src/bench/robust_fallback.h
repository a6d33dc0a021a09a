// How often robust_sphere.h's fast path leaves a case to its exact path, per
// family: the share of cases whose answer needed exact arithmetic, for each
// query level and precision. The answers are the same either way; this is
// what the fast path's cost figures leave out (bench prints both).
#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "core/ray_sphere_case.h"

namespace rayverify::bench {

struct robust_fallback_row {
    std::string family;
    std::string variant;    // robust, robust_nearest or robust_any_hit
    std::string precision;  // "float" or "double"
    std::size_t cases = 0;  // valid at that precision
    std::size_t exact = 0;  // of them, left to the exact path
};

// The robust variants' names, in registry order.
inline const char* const robust_variant_names[] = {"robust", "robust_nearest", "robust_any_hit"};

// Every robust variant in float and double on each family's cases (the
// interval ones asked on each case's interval, as the audit asks them).
std::vector<robust_fallback_row> robust_fallbacks(const std::map<std::string, std::vector<corpus_case>>& by_family);

}  // namespace rayverify::bench
