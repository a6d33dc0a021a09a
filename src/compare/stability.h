// Stability: how hard a case is for *any* floating-point algorithm, and
// whether a variant's error is explained by that or by its formula.
// Pure functions: no I/O, no state.
//
// Notation (ARCHITECTURE.md): f = o − c, a = d·d, b′ = d·f, C = f·f − r²,
// a t² + 2b′t + C = 0, Δ′ = b′² − aC; the 10 inputs x = (o, d, c, r).
//
// Condition number of a simple root t (relative perturbations of the inputs).
// Implicit differentiation of F(t, x) = a t² + 2b′t + C gives
//   ∂t/∂x_i = −(∂F/∂x_i) / (∂F/∂t),   ∂F/∂t = 2(a t + b′) = ∓2√Δ′,
//   ∂F/∂o_k = 2p_k,  ∂F/∂c_k = −2p_k,  ∂F/∂d_k = 2t·p_k,  ∂F/∂r = −2r,
// with p = f + t·d (the root's point relative to the centre, |p| = r). So
//   κ(t) = Σ_i |∂t/∂x_i|·|x_i| / |t|
//        = ( Σ_k |p_k|·(|o_k| + |c_k| + |t|·|d_k|) + r² ) / ( √Δ′ · |t| ).
// κ = +∞ at a double root (Δ′ = 0: t moves like the square root of a
// perturbation) and at t = 0 (any perturbation is an infinite relative error).
// A miss has no real root and no κ.
//
// Distance to tangency: ρ = |Δ′| / (b′² + |a·C|), how close Δ′ is to zero
// relative to its two terms (ρ ∈ [0, 1] for a hit).
//
// Conditioning-limited misclassification. Perturbing every input by at most
// ε relative changes Δ′ by at most ε·M to first order, where
//   M = Σ_i |∂Δ′/∂x_i|·|x_i|
//     = 2( Σ_k |b′d_k − a f_k|·(|o_k| + |c_k|) + Σ_k |b′f_k − C d_k|·|d_k| + a r² ).
// An algorithm that is backward stable with backward error γ·u (u = 2^-24 in
// float, 2^-53 in double) may return either class when |Δ′| ≤ γ·u·M: the
// case is then inherently ambiguous at that precision. We take γ = 8 (the
// rounding of f = o − c, of three products and two sums in each dot product,
// and of the final difference) and report the margin |Δ′| / (u·M); a wrong
// class with margin ≤ 8 is conditioning-limited, otherwise algorithmic (a
// stable formula would have got it right).
//
// Everything is evaluated in double-double arithmetic (error-free sums and
// FMA products, ≈ 2^-104 relative to the magnitude of each term) on inputs
// scaled by powers of two (exact), so cancellation in Δ′, b′f − Cd and p does
// not swamp the result; exact decisions (class, t = 0) come from the oracle.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <array>
#include <map>
#include <span>

#include "compare/audit.h"
#include "compare/judge.h"
#include "core/ray_sphere_case.h"
#include "oracle/oracle.h"

namespace rayverify {

inline constexpr double conditioning_gamma = 8;  // γ above

struct stability_measures {
    bool valid = false;                  // false for an invalid case (nothing below is set)
    line_class cls = line_class::miss;   // exact class (from the oracle)
    // κ of the near and far roots; nullopt for a miss; +inf for a tangent or a zero root.
    std::optional<double> near_condition, far_condition;
    double tangency_distance = 0;        // ρ = |Δ′| / (b′² + |aC|)
    double tangency_margin = 0;          // |Δ′| / (u·M); +inf when M = 0
    double discriminant_sign = 0;        // sign of Δ′ (exact)
    double near_root = 0;                // double-double estimate of the near root, rounded to double
    double distance_ratio = 0;           // |o − c| / r (the far-sphere axis); +inf when r = 0
};

// The measures for `input` exactly as a variant in precision `prec` receives
// it (float inputs already rounded), given its exact solution (`exact` must
// be the oracle's answer for the same inputs and precision).
stability_measures measure_stability(const ray_sphere<double>& input, precision prec, const exact_solution& exact);

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

// One case's measures at each precision in use. (The cause of each target's
// disagreement is the judge's: case_score::cause.)
struct case_stability {
    std::optional<stability_measures> at_float, at_double;
    const stability_measures& at(precision p) const { return p == precision::binary32 ? *at_float : *at_double; }
};

case_stability assess_case(const audited_case& c);

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
    // Against the reference line, over agreeing cases with finite κ:
    // excess = near-root ulps / max(κ, 1).
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
    void add(const audited_case& c, const case_stability& s, std::size_t index);
    void merge(const stability_accumulator& other);
    stability_totals finish(unsigned threads = 1) const;  // on `threads` threads

    // The whole run's samples of each target (aligned with targets).
    std::vector<stability_samples> overall() const { return merged_over_families(by_family, targets.size()); }

    std::vector<audit_target> targets;
    std::map<std::string, std::vector<stability_samples>> by_family;  // family → aligned with targets

private:
    figure_batch figures_;
};

}  // namespace rayverify
