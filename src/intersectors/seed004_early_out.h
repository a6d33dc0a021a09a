// seed004_early_out — the DirectX-era RayToSphere (seed 004), reproduced
// exactly as published: early-out, nearest root, clamp to zero.
//
//   v = o − c,  b = v·d̂,  C = v·v − r²
//   C > 0 and b > 0: miss (origin outside, pointing away)
//   Δ = b² − C;  Δ < 0: miss
//   t = −b − √Δ;  t < 0 ⇒ t = 0 (origin inside)
//
// Contract: assumes a unit direction; answers "nearest hit on the closed ray
// t ≥ 0" with one distance; clamps to 0 when the origin is inside, so an
// inside origin is indistinguishable from a hit at the origin; no tangent
// report.
#pragma once

#include <cmath>

#include "core/intersection.h"
#include "core/ray_sphere_case.h"
#include "intersectors/scalar_math.h"

namespace rayverify::intersectors {

inline constexpr contract seed004_early_out_contract{.query = query_kind::nearest_hit,
                                                     .range = range_source::ray,
                                                     .lower_end = end_kind::closed,
                                                     .inside = inside_rule::clamp,
                                                     .assumes_unit_direction = true};

template <class T>
root_pair<T> seed004_early_out(const ray_sphere<T>& s) {
    const vec3<T> v1 = step("f", s.origin - s.centre);
    const T b = step("b", dot(v1, s.direction));
    const T C = step("C", dot(v1, v1) - (s.radius * s.radius));
    if (C > T(0) && b > T(0)) return {};
    const T discriminant = step("Δ", b * b - C);
    if (discriminant < T(0)) return {};
    T t = -b - sqrt(discriminant);
    if (t < T(0)) t = T(0);
    return {1, t, t};
}

}  // namespace rayverify::intersectors
