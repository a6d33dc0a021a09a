// raylib — raylib's GetRayCollisionSphere (src/rmodels.c, raysan5/raylib
// 6.0-322-gabe23bf8) with raymath's Vector3DotProduct, Vector3Length and
// Vector3Normalize (src/raymath.h):
//
//   v = c − o,  b = v·d,  L = |v|,  disc = r² − (L² − b²);  hit = disc ≥ 0
//   L < r (origin inside):  t = b + √disc,  normal = −normalize(P − c)
//   otherwise:              t = b − √disc,  normal = normalize(P − c)
//   P = o + d·t  (Vector3Add(position, Vector3Scale(direction, t)))
//
// There is no test of the roots' signs: a sphere wholly behind the origin is
// reported as a hit at a negative distance (by design of the formula: the
// judge names it line_not_ray). Float only (raylib's Vector3 is float); C
// with no FMA contraction (x86-64 baseline, SSE2); √ is sqrtf, and
// 1.0f/length an IEEE division (no reciprocal estimate).
//
// Contract: assumes a unit direction (the projection b is used as a
// distance), nearest hit on the closed ray t ≥ 0, the far root from inside,
// a tangent a hit; answers with the hit point (its t derived from it) and
// gives the normal.
#pragma once

#include <cmath>

#include "core/intersection.h"
#include "core/ray_sphere_case.h"

namespace rayverify::intersectors {

inline constexpr contract raylib_contract{.query = query_kind::nearest_hit,
                                          .range = range_source::ray,
                                          .lower_end = end_kind::closed,
                                          .assumes_unit_direction = true,
                                          .answer = answer_kind::point,
                                          .outputs = {.normal = true}};

inline answer<float> raylib(const ray_sphere<float>& s, float /*tmin*/, float /*tmax*/) {
    const vec3<float> ray_sphere_pos = s.centre - s.origin;
    const float vector = dot(ray_sphere_pos, s.direction);
    const float distance = std::sqrt(dot(ray_sphere_pos, ray_sphere_pos));
    const float d = s.radius * s.radius - (distance * distance - vector * vector);
    if (!(d >= 0.0f)) return {};

    const bool inside = distance < s.radius;
    const float t = inside ? vector + std::sqrt(d) : vector - std::sqrt(d);
    answer<float> out;
    out.point = {s.origin.x + s.direction.x * t, s.origin.y + s.direction.y * t, s.origin.z + s.direction.z * t};
    // Vector3Normalize: v · (1/|v|), left as it is when |v| = 0.
    const vec3<float> w = out.point - s.centre;
    const float length = std::sqrt(dot(w, w));
    vec3<float> n = w;
    if (length != 0.0f) {
        const float inverse = 1.0f / length;
        n = {w.x * inverse, w.y * inverse, w.z * inverse};
    }
    out.normal = inside ? vec3<float>{-n.x, -n.y, -n.z} : n;
    const float derived = parameter_of_point(s, out.point);
    out.roots = {1, derived, derived};
    return out;
}

}  // namespace rayverify::intersectors
