// Conditioning: how hard a case is for *any* floating-point algorithm, the
// measures a disagreement's cause and the stability tallies are read from.
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

#include "core/ray_sphere_case.h"
#include "oracle/oracle.h"

namespace rayverify {

inline constexpr double conditioning_gamma = 8;  // γ above

struct stability_measures {
    bool valid = false;                  // false for an invalid case (nothing below is set)
    line_class cls = line_class::miss;   // exact class (from the oracle)
    // κ of the near and far roots; nullopt for a miss; +inf for a tangent or a zero root.
    std::optional<double> near_condition, far_condition;
    // The absolute condition κ·|t| of each root (how far relative input
    // perturbations of size 1 move t): finite at a root exactly at 0, where
    // κ is not; +inf for a tangent; nullopt for a miss.
    std::optional<double> near_absolute_condition, far_absolute_condition;
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

// One case's measures at each precision in use, formed once per case by the
// audit (audit_case) and shared by the judge's causes, the stability tallies,
// the plot sample and the per-case lines.
struct case_stability {
    std::optional<stability_measures> at_float, at_double;
    const stability_measures& at(precision p) const { return p == precision::binary32 ? *at_float : *at_double; }
};

}  // namespace rayverify
