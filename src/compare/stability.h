// Stability tallies: per target, the agreeing and disagreeing cases by
// decade of the near root's condition number κ (compare/conditioning.h), the
// causes of the disagreements, and each error against the κ·u line a
// backward-stable algorithm stays below. Pure functions: no I/O, no state.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "compare/audit.h"
#include "compare/conditioning.h"
#include "compare/judge.h"
#include "core/ray_sphere_case.h"
#include "oracle/oracle.h"

namespace rayverify {

// Condition buckets by decade: index 0 holds κ < 10, index i holds
// 10^i ≤ κ < 10^(i+1) up to `condition_decades − 1` (which holds everything
// finite above), then κ = +∞, then misses (no κ).
inline constexpr int condition_decades = 18;
inline constexpr int condition_bucket_count = condition_decades + 2;
int condition_bucket(const stability_measures& s);
std::string condition_bucket_label(int bucket);

// The reference line: a backward-stable algorithm's nearest-root error is at
// most about γ·κ ulps (relative error γ·κ·u, and |t|/ulp(t) ≤ 1/u). A variant
// whose agreeing cases all stay below `stability_factor`·max(κ, 1) ulps is
// called stable.
inline constexpr double stability_factor = 16;

// One agreeing answer's error over the reference line (nullopt where none is
// judged): its near root's ulps / max(κ, 1) where κ is finite; at a root
// exactly at 0, where κ is not, |t| / (u·κ·|t|), the same line in absolute
// terms (κ·|t| is finite there; the finite-κ form equals it up to
// ulp(t*)/(u·|t*|) ∈ (1, 2]); the larger of the two where both apply.
// Inline: the stability tallies call it for every agreeing case-target, and
// a call returned its optional through memory, a stall each time.
// `near_ulp`: the score's, or a bound on it (the excess is then bounded alike).
inline std::optional<double> excess_over_line(const std::optional<double>& near_ulp, const case_score& score,
                                              const stability_measures& m, const exact_solution& exact,
                                              precision prec) {
    std::optional<double> excess;
    if (near_ulp && m.near_condition && std::isfinite(*m.near_condition))
        excess = *near_ulp / std::max(*m.near_condition, 1.0);
    if (score.zero_root_error) {
        const std::optional<double>& absolute_condition =
            exact.near_root.sign == 0 ? m.near_absolute_condition : m.far_absolute_condition;
        if (absolute_condition && std::isfinite(*absolute_condition) && *absolute_condition > 0) {
            const double u = unit_roundoff(prec);
            excess = std::max(excess.value_or(0.0), *score.zero_root_error / (u * *absolute_condition));
        }
    }
    return excess;
}
inline std::optional<double> excess_over_line(const case_score& score, const stability_measures& m,
                                              const exact_solution& exact, precision prec) {
    return excess_over_line(score.near_ulp, score, m, exact, prec);
}

// Per target and condition bucket.
struct bucket_tally {
    std::size_t cases = 0;          // scored cases (neither invalid nor outside the contract)
    std::size_t misclassified = 0;  // wrong class
    std::size_t disagreements = 0;
    // Causes of the disagreements (compare/judge.h): rounding, told apart by
    // conditioning, and what the formula does by design.
    std::size_t conditioning_limited = 0, algorithmic = 0, by_design = 0;
    error_statistics near_root_ulp;                          // over the agreeing cases
};

struct stability_tally {
    std::array<bucket_tally, condition_bucket_count> buckets{};
    bucket_tally all;  // every bucket together
    // Against the reference line, over agreeing cases with finite κ or a
    // root exactly at 0 (excess_over_line).
    std::size_t judged = 0;
    std::size_t above_line = 0;        // excess > stability_factor
    std::size_t well_conditioned = 0;  // judged cases with κ < 10^3
    std::size_t well_conditioned_above = 0;
    error_statistics excess;
    bool stable() const { return judged > 0 && above_line == 0; }
};

struct stability_totals {
    std::vector<stability_tally> overall;                              // aligned with targets
    std::map<std::string, std::vector<stability_tally>> by_family;    // family → aligned with targets
};

// Per target over some cases (mergeable, bounded): the bucket counts (their
// near_root_ulp left empty), the agreeing cases' errors per bucket, and the
// excess over the reference line.
struct stability_samples {
    std::array<bucket_tally, condition_bucket_count> buckets{};
    std::array<error_summary, condition_bucket_count> near_ulp;
    error_summary excess;
    std::size_t above_line = 0, well_conditioned = 0, well_conditioned_above = 0;
    void merge(const stability_samples& other);
};

// Like audit_accumulator: any order, one per thread or shard, merged exactly.
struct stability_accumulator {
    explicit stability_accumulator(std::vector<audit_target> targets = {});
    void add(const audited_case& c, std::size_t index);
    void merge(const stability_accumulator& other);
    stability_totals finish(unsigned threads = 1) const;  // on `threads` threads

    // The whole run's samples of each target (aligned with targets).
    std::vector<stability_samples> overall() const { return merged_over_families(by_family, targets.size()); }

    std::vector<audit_target> targets;
    std::map<std::string, std::vector<stability_samples>> by_family;  // family → aligned with targets
};

}  // namespace rayverify
