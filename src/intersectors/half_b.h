// half_b — the b/2 form of "Ray Tracing in One Weekend" (v4, §6.2 "Simplifying
// the Ray-Sphere Intersection Code").
//
//   oc = c − o,  a = |d|²,  h = d·oc,  C = |oc|² − r²,  Δ = h² − aC
//   Δ < 0: miss;  else t = (h ∓ √Δ) / a
//
// Contract: any direction length; both roots of the line, ordered, negative
// roots included; never reports a tangent separately (a graze is two equal or
// nearly equal roots); no clamp. Same cancellation as `naive` in C.
#pragma once

#include <cmath>

#include "core/intersection.h"
#include "core/ray_sphere_case.h"
#include "intersectors/scalar_math.h"

namespace rayverify::intersectors {

inline constexpr contract half_b_contract{.query = query_kind::line_roots};

template <class T>
root_pair<T> half_b(const ray_sphere<T>& s) {
    const vec3<T> oc = step("oc", s.centre - s.origin);
    const T a = step("a", length_squared(s.direction));
    const T h = step("h", dot(s.direction, oc));
    const T C = step("C", length_squared(oc) - s.radius * s.radius);
    const T discriminant = step("Δ", h * h - a * C);
    if (discriminant < 0) return {};
    const T root = step("√Δ", sqrt(discriminant));
    return {2, (h - root) / a, (h + root) / a};
}

}  // namespace rayverify::intersectors
