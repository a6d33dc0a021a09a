#include "intersectors/registry.h"

#include <array>
#include <limits>
#include <string>

#include "intersectors/fma_discriminant.h"
#include "intersectors/geometric.h"
#include "intersectors/half_b.h"
#include "intersectors/hearn_baker.h"
#include "intersectors/hearn_baker_any_hit.h"
#include "intersectors/hearn_baker_nearest.h"
#include "intersectors/hearn_baker_unit.h"
#include "intersectors/naive.h"
#include "intersectors/robust.h"
#include "intersectors/seed003_reduced.h"
#include "intersectors/seed004_early_out.h"
#include "intersectors/stable_roots.h"

namespace rayverify {
namespace {

#define RAYVERIFY_BOTH_PRECISIONS(fn) &intersectors::fn<float>, &intersectors::fn<double>

// A kind that takes an interval: run_float_in/run_double_in answer for the
// interval given, run_float/run_double for the default (0, +inf).
template <class T>
using interval_fn = root_pair<T> (*)(const ray_sphere<T>&, T, T);

template <interval_fn<float> F, interval_fn<double> D>
variant interval_variant(std::string name, std::string citation, std::string formula, contract promises) {
    variant v{std::move(name), std::move(citation), std::move(formula), promises,
              [](const ray_sphere<float>& s) { return F(s, 0.0f, std::numeric_limits<float>::infinity()); },
              [](const ray_sphere<double>& s) { return D(s, 0.0, std::numeric_limits<double>::infinity()); }};
    v.run_float_in = F;
    v.run_double_in = D;
    return v;
}

#define RAYVERIFY_INTERVAL_VARIANT(fn, citation, formula) \
    interval_variant<&intersectors::fn<float>, &intersectors::fn<double>>(#fn, citation, formula, intersectors::fn##_contract)

// The robust variants decide exactly by construction (robust_sphere.h).
variant with_exact_decisions(variant v) {
    v.exact_decisions = true;
    return v;
}

const std::array<variant, 16> registry{{
    {"naive", "seed 000 / seed 001 (textbook quadratic)",
     "b = 2d·f, C = f·f − r², Δ = b² − 4aC, t = (−b ∓ √Δ)/2a", intersectors::naive_contract,
     RAYVERIFY_BOTH_PRECISIONS(naive)},
    {"half_b", "Ray Tracing in One Weekend §6.2",
     "h = d·(c − o), Δ = h² − aC, t = (h ∓ √Δ)/a", intersectors::half_b_contract,
     RAYVERIFY_BOTH_PRECISIONS(half_b)},
    {"seed003_reduced", "seed 003 (GLM-style reduced quadratic, as published)",
     "p = d̂·f, q = f·f − r², Δ = p² − q, t = −p ∓ √Δ, tangent if Δ ≤ 1e-7",
     intersectors::seed003_reduced_contract, RAYVERIFY_BOTH_PRECISIONS(seed003_reduced)},
    {"seed004_early_out", "seed 004 (DirectX RayToSphere, as published)",
     "b = f·d̂, C = f·f − r², miss if C > 0 ∧ b > 0, t = max(0, −b − √(b² − C))",
     intersectors::seed004_early_out_contract, RAYVERIFY_BOTH_PRECISIONS(seed004_early_out)},
    {"geometric", "seed 000 closest approach (three.js, PhysX)",
     "t_ca = (c − o)·d̂, d² = |c − o|² − t_ca², miss if d² > r², t = t_ca ∓ √(r² − d²)",
     intersectors::geometric_contract, RAYVERIFY_BOTH_PRECISIONS(geometric)},
    {"stable_roots", "Numerical Recipes §5.6; RTG ch.7 method 1",
     "q = −½(b + sign(b)√Δ), t = q/a, C/q", intersectors::stable_roots_contract,
     RAYVERIFY_BOTH_PRECISIONS(stable_roots)},
    {"hearn_baker", "Ray Tracing Gems ch.7 final form (Hearn–Baker Δ + stable roots)",
     "b′ = −f·d, Δ = r² − |f + (b′/a)d|², q = b′ + sign(b′)√(aΔ), t = C/q, q/a",
     intersectors::hearn_baker_contract, RAYVERIFY_BOTH_PRECISIONS(hearn_baker)},
    {"fma_discriminant", "naive with Kahan's FMA difference of products (pbrt-v4)",
     "Δ = DifferenceOfProducts(b, b, 4a, C), t = (−b ∓ √Δ)/2a",
     intersectors::fma_discriminant_contract, RAYVERIFY_BOTH_PRECISIONS(fma_discriminant)},
    RAYVERIFY_INTERVAL_VARIANT(hearn_baker_any_hit,
                               "Ray Tracing Gems ch.7 final form, any-hit in (tmin, tmax) (shadow rays)",
                               "miss if C > 0 ∧ b′ < 0 ∧ tmin ≥ 0; hit if C < 0 ∧ (tmin, tmax) ⊇ (0, ∞); "
                               "Δ = r² − |f + (b′/a)d|²; then only the roots the answer needs, C/q and q/a"),
    RAYVERIFY_INTERVAL_VARIANT(hearn_baker_nearest, "Ray Tracing Gems ch.7 final form, nearest root in (tmin, tmax)",
                               "Δ = r² − |f + (b′/a)d|², q = b′ + sign(b′)√(aΔ); near C/q if C > 0 ∧ b′ > 0, "
                               "far q/a only if needed"),
    {"hearn_baker_unit", "Ray Tracing Gems ch.7 final form with a = d·d = 1",
     "b′ = −f·d̂, Δ = r² − |f + b′d̂|², q = b′ + sign(b′)√Δ, t = C/q, q",
     intersectors::hearn_baker_unit_contract, RAYVERIFY_BOTH_PRECISIONS(hearn_baker_unit)},
    RAYVERIFY_INTERVAL_VARIANT(hearn_baker_unit_nearest,
                               "Ray Tracing Gems ch.7 final form with a = 1, nearest root in (tmin, tmax)",
                               "Δ = r² − |f + b′d̂|², q = b′ + sign(b′)√Δ; near C/q if C > 0 ∧ b′ > 0, "
                               "far q only if needed"),
    RAYVERIFY_INTERVAL_VARIANT(hearn_baker_unit_any_hit,
                               "Ray Tracing Gems ch.7 final form with a = 1, any-hit in (tmin, tmax) (shadow rays)",
                               "as hearn_baker_any_hit with a = 1: Δ = r² − |f + b′d̂|², roots C/q and q only as needed"),
    with_exact_decisions(
        {"robust", "rayverify robust_sphere.h (certified double/double-word filter, Shewchuk expansions)",
         "sign of Δ′ = a·r² − |d × f|², C, b′ exact; q = −(b′ + sign(b′)√Δ′), t = q/a, C/q rounded to nearest",
         intersectors::robust_contract, RAYVERIFY_BOTH_PRECISIONS(robust)}),
    with_exact_decisions(RAYVERIFY_INTERVAL_VARIANT(
        robust_nearest, "rayverify robust_sphere.h, nearest root in (tmin, tmax)",
        "as robust; the roots' comparisons with tmin and tmax exact, only the roots needed")),
    with_exact_decisions(RAYVERIFY_INTERVAL_VARIANT(
        robust_any_hit, "rayverify robust_sphere.h, any root in (tmin, tmax) (shadow rays)",
        "as robust_nearest, answering only whether a root lies in the interval")),
}};

#undef RAYVERIFY_INTERVAL_VARIANT

#undef RAYVERIFY_BOTH_PRECISIONS

}  // namespace

std::span<const variant> builtin_variants() { return registry; }

const variant* find_builtin_variant(std::string_view name) {
    for (const variant& v : registry)
        if (v.name == name) return &v;
    return nullptr;
}

}  // namespace rayverify
