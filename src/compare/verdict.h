// Judging one variant's answer on one case against the exact answer.
// Pure functions: no I/O, no state.
#pragma once

#include <array>
#include <functional>
#include <optional>
#include <string>
#include <string_view>

#include "core/intersection.h"
#include "core/ray_sphere_case.h"
#include "intersectors/registry.h"
#include "oracle/oracle.h"

namespace rayverify {

// The verdict kinds, in report order. Each has a one-line meaning
// (verdict_meaning) that the README and `explain` print.
enum class verdict_kind {
    agree,
    false_miss,          // exact: hit; variant: miss
    false_hit,           // exact: miss; variant: hit
    tangent_split,       // exact: tangent; variant: two distinct roots
    tangent_missed,      // exact: tangent; variant: miss
    false_tangent,       // exact: two distinct roots; variant: one (tangent) root
    wrong_root,          // a returned root is nearer the other exact root than its own
    wrong_side,          // a root's side of the origin (t > 0 or not) differs: self-hit or lost hit
    non_finite,          // a NaN or infinity where the exact root is finite
    malformed_output,    // count outside the contract, or roots out of order
    contract_violation,  // the case breaks the variant's assumption (reported apart, not scored)
    invalid,             // the case itself is invalid at this precision (not scored)
};
inline constexpr int verdict_kind_count = 12;

std::string_view verdict_name(verdict_kind k);
std::string_view verdict_meaning(verdict_kind k);
// A disagreement is any verdict that is neither agree nor one of the two
// kinds that are not scored (contract_violation, invalid).
bool is_disagreement(verdict_kind k);

// A variant's answer, widened to double (float values are exact in double),
// plus the hit point o + t·d it implies, evaluated in the variant's own
// precision, for the root it would use as "nearest in front".
struct variant_output {
    root_pair<double> roots;
    std::optional<int> front_root;            // index (0 or 1) of the nearest root in front
    std::optional<vec3<double>> hit_point;    // o + t·d for that root, in the variant's precision
    // The interval the variant was asked, for kinds that take one
    // (takes_interval); a variant_output without it is judged on (0, +inf).
    std::optional<ray_interval<double>> interval;
};

// Run a variant's function in precision T on the case and widen its answer.
template <class T>
variant_output evaluate(const std::function<root_pair<T>(const ray_sphere<T>&)>& run, const contract& promises,
                        const ray_sphere<T>& input);

// Run a variant in precision T on the case, asking kinds that take an
// interval for `interval` (the others ignore it), and widen its answer.
template <class T>
variant_output evaluate(const variant& v, const ray_sphere<T>& input, ray_interval<T> interval);

// Does exact root i lie in the open interval (tmin, tmax)? Decided exactly
// (infinite bounds by sign). Requires exact.cls != miss.
bool exact_root_in(const exact_solution& exact, root_index i, ray_interval<double> interval);
// The nearest exact root in the open interval; nullopt for none (or a miss).
std::optional<root_index> exact_nearest_in(const exact_solution& exact, ray_interval<double> interval);

// Does the case satisfy the variant's assumptions at this precision?
// A unit direction means |d·d − 1| ≤ 8ε (what normalising in that precision yields).
std::optional<std::string> contract_breach(const contract& promises, const ray_sphere<double>& input,
                                           precision prec);

struct case_score {
    verdict_kind verdict = verdict_kind::agree;
    std::string detail;  // one sentence a person can act on; empty for agree
    // Error of each returned root against its exact counterpart: |t − t*| / ulp(t*)
    // and Herbie bits log2(1 + ulps between t and RN(t*)). Present when both exist.
    std::optional<double> near_ulp, far_ulp, near_bits, far_bits;
    // Error of the hit point, per coordinate, in ulps (when the verdict is agree
    // and there is a hit in front).
    std::optional<std::array<double, 3>> hit_point_ulp;
};

// Judge `output` against `exact` (which must be valid) under `promises`.
case_score score_case(const contract& promises, const variant_output& output,
                      const exact_solution& exact, const ray_sphere<double>& input);

}  // namespace rayverify
