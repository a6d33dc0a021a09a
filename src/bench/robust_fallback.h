// Which stage of robust_sphere.h answers a case, per family: its static
// filter alone (plain double with a priori bounds, inlined), its double-word
// refinement (double only, out of line), or its exact path, for each query
// level, tier and precision, the segment query included (on each family's
// rays as segments, segments_along). The answers are the same either way;
// this is what the fast path's cost figures average over (bench prints both).
#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "bench/timing.h"
#include "core/ray_sphere_case.h"

namespace rayverify::bench {

// robust_sphere.h's cost target: at most this many naive double tests per
// test (naive/double for the ray queries, naive_segment/double for the
// segment query), on these families, measured in the same run.
inline constexpr double robust_target_ratio = 2;
inline constexpr const char* robust_target_families[] = {"uniform", "far_sphere"};

// The segment query's name in the fallback rows and timings, and the naive
// double segment cast it is timed against.
inline constexpr const char* robust_segment_name = "robust_segment";
inline constexpr const char* naive_segment_name = "naive_segment";

// A ray case as the segment a physics engine casts along it: p0 = o, p1 =
// o + L·d rounded to T (L = segment_length, past every root of the ray), so
// that p1 − p0 is in general no value of T, as in an engine's cast.
template <class T>
struct segment_case {
    vec3<T> p0, p1, centre;
    T radius;
};

// The family's cases valid at T as such segments (those whose p1 is finite
// and differs from p0).
template <class T>
std::vector<segment_case<T>> segments_along(const std::vector<corpus_case>& cases);

// robust_sphere.h's segment_hit (closed ends, contact at the start) in float
// and double, and the naive double segment cast (the textbook quadratic on
// RN(p1 − p0), its first root in [0, 1]), on segments_along of each of
// `families`' cases, timed like time_variants' rows (`precisions` as there:
// empty is all; naive_segment/double, the ratio's reference, is always timed).
std::vector<timing_row> time_segment_queries(const std::map<std::string, std::vector<corpus_case>>& by_family,
                                             const timing_options& options);

struct robust_fallback_row {
    std::string family;
    std::string variant;      // robust, robust_nearest, robust_any_hit, robust_bounded or robust_bounded_nearest
    std::string precision;    // "float" or "double"
    std::size_t cases = 0;    // valid at that precision
    std::size_t refined = 0;  // of them, left by the static filter to the double-word stage (which answered)
    std::size_t exact = 0;    // left to the exact path
};

// The robust variants' names, in registry order (robust_fallbacks adds
// robust_segment_name's rows after them).
inline const char* const robust_variant_names[] = {"robust", "robust_nearest", "robust_any_hit", "robust_bounded",
                                                   "robust_bounded_nearest"};

// Every robust variant in float and double on each family's cases (the
// interval ones asked on each case's interval, as the audit asks them), then
// the segment query on segments_along them.
std::vector<robust_fallback_row> robust_fallbacks(const std::map<std::string, std::vector<corpus_case>>& by_family);

}  // namespace rayverify::bench
