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
#include <type_traits>

#include "core/intersection.h"
#include "core/ray_sphere_case.h"
#include "intersectors/scalar_math.h"

namespace rayverify::intersectors {

inline constexpr contract raylib_contract{.query = query_kind::nearest_hit,
                                          .range = range_source::ray,
                                          .lower_end = end_kind::closed,
                                          .assumes_unit_direction = true,
                                          .answer = answer_kind::point,
                                          .outputs = {.normal = true}};

// Float: C's float (or a traced float, for explain).
template <class Float = float>
inline answer<Float> raylib(const ray_sphere<Float>& s, std::type_identity_t<Float> /*tmin*/,
                     std::type_identity_t<Float> /*tmax*/) {
    const vec3<Float> ray_sphere_pos = step("raySpherePos", s.centre - s.origin);
    const Float vector = step("vector", dot(ray_sphere_pos, s.direction));
    const Float distance = step("distance", sqrt(dot(ray_sphere_pos, ray_sphere_pos)));
    const Float d = step("d", s.radius * s.radius - step("dist² − vec²", distance * distance - vector * vector));
    if (!(d >= 0.0f)) return {};

    const bool inside = distance < s.radius;
    const Float t = step("t", inside ? vector + sqrt(d) : vector - sqrt(d));
    answer<Float> out;
    out.point = {s.origin.x + s.direction.x * t, s.origin.y + s.direction.y * t, s.origin.z + s.direction.z * t};
    step("point", out.point);
    // Vector3Normalize: v · (1/|v|), left as it is when |v| = 0.
    const vec3<Float> w = out.point - s.centre;
    const Float length = sqrt(dot(w, w));
    vec3<Float> n = w;
    if (length != 0.0f) {
        const Float inverse = Float(1.0f) / length;
        n = {w.x * inverse, w.y * inverse, w.z * inverse};
    }
    out.normal = inside ? vec3<Float>{-n.x, -n.y, -n.z} : n;
    const Float derived = parameter_of_point(s, out.point);
    out.roots = {1, derived, derived};
    return out;
}

}  // namespace rayverify::intersectors
