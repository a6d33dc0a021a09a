// naive — the textbook quadratic (seed 000 "From sphere to quadratic", seed 001
// "Ray Tracing in One Weekend" §5 before its simplification).
//
//   f = o − c,  a = d·d,  b = 2 d·f,  C = f·f − r²,  Δ = b² − 4aC
//   Δ < 0: miss;  Δ = 0: tangent, t = −b / 2a;  Δ > 0: t = (−b ∓ √Δ) / 2a
//
// Contract: any direction length; returns both roots of the line, ordered,
// negative roots included; reports a tangent only when Δ is exactly 0; no clamp.
// Known failure (RTG ch.7): C loses r² once |f| ≳ 2^12·r in float, 2^26·r in
// double, so far small spheres vanish; −b ± √Δ cancels for the near root.
#pragma once

#include <cmath>

#include "core/intersection.h"
#include "core/ray_sphere_case.h"
#include "intersectors/scalar_math.h"

namespace rayverify::intersectors {

inline constexpr contract naive_contract{
    .query = query_kind::line_roots, .reports_tangent = true, .tangent_rule = "Δ == 0"};

template <class T>
root_pair<T> naive(const ray_sphere<T>& s) {
    const vec3<T> f = step("f", s.origin - s.centre);
    const T a = step("a", dot(s.direction, s.direction));
    const T b = step("b", T(2) * dot(s.direction, f));
    const T C = step("C", dot(f, f) - s.radius * s.radius);
    const T discriminant = step("Δ", b * b - T(4) * a * C);
    if (discriminant < 0) return {};
    if (discriminant == 0) {
        const T t = -b / (T(2) * a);
        return {1, t, t};
    }
    const T root = step("√Δ", sqrt(discriminant));
    return {2, (-b - root) / (T(2) * a), (-b + root) / (T(2) * a)};
}

}  // namespace rayverify::intersectors
