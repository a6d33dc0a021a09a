// godot — Godot's Geometry3D::segment_intersects_sphere (core/math/
// geometry_3d.cpp in Godot 4.x, geometry_3d.h before; unchanged since Godot 3
// apart from casts), returning a point and a normal:
//
//   p = c − from,  rel = to − from,  L = |rel|;  L < CMP_EPSILON: false
//   n = rel / L,  s = n·p,  dist = |n·s − p|;  dist ≥ r: false
//   h² = r² − dist²,  t = s;  h² ≥ CMP_EPSILON: t −= √h²
//   t < 0 or t > L: false;  result = from + n·t,  normal = (result − c).normalized()
//
// CMP_EPSILON = 1e-5 (core/math/math_defs.h). Only the near root is ever
// computed, so a segment starting inside misses, and near a tangent
// (h² < 1e-5, absolute, in squared distance units) the point is the closest
// approach s, not a root: by design. Builds: real_t = float (the default)
// and double (precision=double); x86-64 baseline (no FMA to contract into).
// Vector3::length is √(x² + y² + z²), dot x·x′ + y·y′ + z·z′, division by a
// scalar divides each coordinate.
//
// The ray's range maps to the segment from = o + tmin·d, to = o + tmax·d
// (each coordinate rounded in real_t; tmin = 0 gives o), and a ray without
// tmax to to = o + L·d with L = segment_length() (core/intersection.h), a
// power of two past every root. The answer is the point; its t along the
// case's ray is derived (parameter_of_point) and reported beside it.
//
// Contract: nearest hit on the segment [from, to] (closed), front faces only
// (starting inside misses), a tangent a miss (dist ≥ r), any direction
// length; answers with the hit point and gives the normal.
#pragma once

#include <cmath>

#include "core/intersection.h"
#include "core/ray_sphere_case.h"

namespace rayverify::intersectors {
namespace godot_math {

template <class T>
T length(vec3<T> v) {
    return std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
}

template <class T>
vec3<T> divided(vec3<T> v, T s) {
    return {v.x / s, v.y / s, v.z / s};
}

// Vector3::normalized(): zero stays zero.
template <class T>
vec3<T> normalized(vec3<T> v) {
    const T length_squared = v.x * v.x + v.y * v.y + v.z * v.z;
    if (length_squared == 0) return {};
    return divided(v, std::sqrt(length_squared));
}

}  // namespace godot_math

inline constexpr contract godot_contract{.query = query_kind::nearest_hit,
                                         .range = range_source::segment,
                                         .lower_end = end_kind::closed,
                                         .upper_end = end_kind::closed,
                                         .inside = inside_rule::miss,
                                         .tangent_is_hit = false,
                                         .front_faces_only = true,
                                         .answer = answer_kind::point,
                                         .outputs = {.normal = true}};

template <class T>
answer<T> godot(const ray_sphere<T>& s, T tmin, T tmax) {
    const vec3<T> from = tmin == 0 ? s.origin : s.origin + tmin * s.direction;
    const vec3<T> to = s.origin + (std::isinf(tmax) ? segment_length(s) : tmax) * s.direction;
    const T epsilon = static_cast<T>(0.00001);  // (real_t)CMP_EPSILON

    const vec3<T> sphere_pos = s.centre - from;
    const vec3<T> rel = to - from;
    const T rel_l = godot_math::length(rel);
    if (rel_l < epsilon) return {};
    const vec3<T> normal = godot_math::divided(rel, rel_l);
    const T sphere_d = dot(normal, sphere_pos);
    const T ray_distance = godot_math::length(sphere_d * normal - sphere_pos);
    if (ray_distance >= s.radius) return {};
    const T inters_d2 = s.radius * s.radius - ray_distance * ray_distance;
    T inters_d = sphere_d;
    if (inters_d2 >= epsilon) inters_d -= std::sqrt(inters_d2);
    if (inters_d < 0 || inters_d > rel_l) return {};

    answer<T> out;
    out.point = from + inters_d * normal;
    out.normal = godot_math::normalized(out.point - s.centre);
    const T t = parameter_of_point(s, out.point);
    out.roots = {1, t, t};
    return out;
}

}  // namespace rayverify::intersectors
