// seed003_reduced — "Ray-Sphere Intersection - From Math to Code" (2020),
// reproduced exactly as published, bugs included: the reduced quadratic
// formula for a unit direction.
//
//   f = o − c,  p = d̂·f,  q = f·f − r²,  Δ = p² − q
//   Δ < 0: 0 roots;  dist1 = −p − √Δ, dist2 = −p + √Δ;
//   returns 2 when Δ > 1e-7, else 1 (the article's tangent margin)
//
// Contract: assumes a unit direction; both roots of the line (distances may be
// negative, as the article notes); reports "tangent" whenever Δ ≤ 1e-7, an
// absolute epsilon that ignores scale; no clamp. The comparison `Δ > 1e-7`
// is against a double literal, as in the article.
#pragma once

#include <cmath>

#include "core/intersection.h"
#include "core/ray_sphere_case.h"
#include "intersectors/scalar_math.h"

namespace rayverify::intersectors {

inline constexpr contract seed003_reduced_contract{.query = query_kind::line_roots,
                                                   .assumes_unit_direction = true,
                                                   .reports_tangent = true,
                                                   .tangent_rule = "Δ ≤ 1e-7 (absolute)",
                                                   .tangent_threshold = 1e-7};

template <class T>
root_pair<T> seed003_reduced(const ray_sphere<T>& s) {
    const vec3<T> o_minus_c = step("o − c", s.origin - s.centre);
    const T p = step("p", dot(s.direction, o_minus_c));
    const T q = step("q", dot(o_minus_c, o_minus_c) - (s.radius * s.radius));
    const T discriminant = step("Δ", (p * p) - q);
    if (discriminant < T(0)) return {};
    const T d_root = step("√Δ", sqrt(discriminant));
    const T dist1 = -p - d_root;
    const T dist2 = -p + d_root;
    return {(discriminant > 1e-7) ? 2 : 1, dist1, dist2};
}

}  // namespace rayverify::intersectors
