// fma_discriminant — `naive` with the discriminant b² − 4aC evaluated as a
// difference of products with a fused multiply-add (Kahan's algorithm, as in
// pbrt-v4's DifferenceOfProducts):
//
//   w = 4a·C,  e = fma(−4a, C, w),  f = fma(b, b, −w),  Δ = f + e
//
// Everything else is `naive`: f = o − c, a = d·d, b = 2 d·f, C = f·f − r²,
// t = (−b ∓ √Δ)/2a. This isolates what an accurate Δ buys: it does not fix the
// rounding of C itself, nor the cancellation of the near root.
//
// Contract: any direction length; both roots of the line, ordered, negative
// roots included; reports a tangent when Δ == 0; no clamp. std::fma is exact
// regardless of -ffp-contract.
#pragma once

#include <cmath>

#include "core/intersection.h"
#include "core/ray_sphere_case.h"
#include "intersectors/scalar_math.h"

namespace rayverify::intersectors {

inline constexpr contract fma_discriminant_contract{
    .query = query_kind::line_roots, .reports_tangent = true, .tangent_rule = "Δ == 0"};

// Kahan: a·b − c·d with at most 1.5 ulp error.
template <class T>
T difference_of_products(T a, T b, T c, T d) {
    const T cd = c * d;
    const T error = fma(-c, d, cd);
    const T result = fma(a, b, -cd);
    return result + error;
}

template <class T>
root_pair<T> fma_discriminant(const ray_sphere<T>& s) {
    const vec3<T> f = step("f", s.origin - s.centre);
    const T a = step("a", dot(s.direction, s.direction));
    const T b = step("b", T(2) * dot(s.direction, f));
    const T C = step("C", dot(f, f) - s.radius * s.radius);
    const T discriminant = step("Δ", difference_of_products(b, b, T(4) * a, C));
    if (discriminant < 0) return {};
    if (discriminant == 0) {
        const T t = -b / (T(2) * a);
        return {1, t, t};
    }
    const T root = step("√Δ", sqrt(discriminant));
    return {2, (-b - root) / (T(2) * a), (-b + root) / (T(2) * a)};
}

}  // namespace rayverify::intersectors
