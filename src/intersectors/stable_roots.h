// stable_roots — the quadratic with cancellation-free roots (Press et al.,
// Numerical Recipes §5.6; Ray Tracing Gems ch.7 method 1; pbrt, Jolt, Mitsuba
// `solve_quadratic`).
//
//   f = o − c,  a = d·d,  b = 2 d·f,  C = f·f − r²,  Δ = b² − 4aC
//   Δ < 0: miss;  q = −½ (b + sign(b) √Δ),  roots q/a and C/q, then ordered
//
// Contract: any direction length; both roots of the line, ordered, negative
// roots included; reports a tangent when Δ == 0; no clamp. sign(0) = +1
// (copysign). Known failure: b = 0 and Δ = 0 gives q = 0 and C/q = 0/0 = NaN;
// the discriminant still cancels like `naive`.
#pragma once

#include <cmath>
#include <utility>

#include "core/intersection.h"
#include "core/ray_sphere_case.h"
#include "intersectors/scalar_math.h"

namespace rayverify::intersectors {

inline constexpr contract stable_roots_contract{
    .query = query_kind::line_roots, .reports_tangent = true, .tangent_rule = "Δ == 0"};

template <class T>
root_pair<T> stable_roots(const ray_sphere<T>& s) {
    const vec3<T> f = step("f", s.origin - s.centre);
    const T a = step("a", dot(s.direction, s.direction));
    const T b = step("b", T(2) * dot(s.direction, f));
    const T C = step("C", dot(f, f) - s.radius * s.radius);
    const T discriminant = step("Δ", b * b - T(4) * a * C);
    if (discriminant < 0) return {};
    const T q = step("q", T(-0.5) * (b + copysign(sqrt(discriminant), b)));
    T t0 = q / a;
    T t1 = C / q;
    if (t0 > t1) std::swap(t0, t1);
    return {discriminant == 0 ? 1 : 2, t0, t1};
}

}  // namespace rayverify::intersectors
