// godot — Godot's Geometry3D::segment_intersects_sphere (core/math/
// geometry_3d.cpp in Godot 4.x, geometry_3d.h before; unchanged since Godot 3
// apart from casts), returning a point and a normal:
//
//   p = c − from,  rel = to − from,  L = |rel|;  L < CMP_EPSILON: false
//   n = rel / L,  s = n·p,  dist = |n·s − p|;  dist ≥ r: false
//   h² = r² − dist²,  t = s;  h² ≥ CMP_EPSILON: t −= √h²
//   t < 0 or t > L: false;  result = from + n·t,  normal = (result − c).normalized()
//
// CMP_EPSILON = 1e-5 (core/math/math_defs.h), compared as (real_t)CMP_EPSILON.
// Only the near root is ever computed, so a segment starting inside misses,
// and near a tangent (h² < 1e-5, absolute, in squared distance units) the
// point is the closest approach s, not a root: by design.
//
// Build modelled: real_t = float (the default) and double (precision=double);
// the x86-64 baseline (SSE2: no FMA instruction, so nothing is contracted);
// divisions and √ IEEE (no reciprocal estimate). Checked operation for
// operation against segment_intersects_sphere: sphere_pos = c − from,
// rel = to − from, rel_l = rel.length() = √((x² + y²) + z²), normal = rel / rel_l
// (each coordinate divided), sphere_d = normal.dot(sphere_pos) =
// (x·x′ + y·y′) + z·z′, ray_distance = sphere_pos.distance_to(normal·sphere_d)
// = (normal·sphere_d − sphere_pos).length(), inters_d2 = r·r − dist·dist,
// result = from + normal·inters_d, normal = (result − c).normalized() (zero
// stays zero, else each coordinate divided by √(length²)).
//
// Mapping (the test wrapper, not Godot's code): the ray's range becomes the
// segment from = o + tmin·d (o when tmin = 0), to = o + tmax·d, each
// coordinate rounded once in real_t. A ray without tmax ends at
// to = o + L·d with L = segment_length() (core/intersection.h): the power of
// two with L·|d|∞ ≥ 2(|o − c|₁ + r) ≥ 2·|t*|·|d| for every root t*, capped
// where L·|d|∞ would pass a quarter of real_t's largest value. The answer is
// the point p; the t judged is the point's parameter along the case's ray,
// (p − o)·d/(d·d) in double-word arithmetic rounded once to real_t
// (parameter_of_point), reported beside the point.
//
// Contract: nearest hit on the segment [from, to] (closed), front faces only
// (starting inside misses), a tangent a miss (dist ≥ r), any direction
// length; answers with the hit point and gives the normal.
#pragma once

#include <cmath>

#include "core/intersection.h"
#include "core/ray_sphere_case.h"
#include "intersectors/scalar_math.h"

namespace rayverify::intersectors {
namespace godot_math {

template <class T>
T length(vec3<T> v) {
    return sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
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
    return divided(v, sqrt(length_squared));
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

// segment_intersects_sphere(from, to, c, r) itself; s gives c and r, and the
// ray (s.origin, s.direction) the t of the answer's point (parameter_of_point).
template <class T>
answer<T> godot_between(const ray_sphere<T>& s, const vec3<T>& from, const vec3<T>& to) {
    const T epsilon = static_cast<T>(0.00001);  // (real_t)CMP_EPSILON

    const vec3<T> sphere_pos = step("sphere_pos", s.centre - from);
    const vec3<T> rel = to - from;
    const T rel_l = step("rel_l", godot_math::length(rel));
    if (rel_l < epsilon) return {};
    const vec3<T> normal = godot_math::divided(rel, rel_l);
    const T sphere_d = step("sphere_d", dot(normal, sphere_pos));
    const T ray_distance = step("ray_distance", godot_math::length(sphere_d * normal - sphere_pos));
    if (ray_distance >= s.radius) return {};
    const T inters_d2 = step("inters_d2", s.radius * s.radius - ray_distance * ray_distance);
    T inters_d = sphere_d;
    if (inters_d2 >= epsilon) inters_d -= sqrt(inters_d2);
    step("inters_d", inters_d);
    if (inters_d < 0 || inters_d > rel_l) return {};

    answer<T> out;
    out.point = from + inters_d * normal;
    out.normal = godot_math::normalized(out.point - s.centre);
    const T t = parameter_of_point(s, out.point);
    out.roots = {1, t, t};
    return out;
}

// A ray case: the segment from o + tmin·d to o + tmax·d (or o + L·d), as above.
template <class T>
answer<T> godot(const ray_sphere<T>& s, T tmin, T tmax) {
    const vec3<T> from = tmin == 0 ? s.origin : s.origin + tmin * s.direction;
    const vec3<T> to = s.origin + (isinf(tmax) ? segment_length(s) : tmax) * s.direction;
    return godot_between(s, from, to);
}

// A segment case: its end points as given (s.origin = p0; s.direction, p1 − p0
// rounded, only measures the answer's t).
template <class T>
answer<T> godot_segment(const ray_sphere<T>& s, const vec3<T>& p1) {
    return godot_between(s, s.origin, p1);
}

}  // namespace rayverify::intersectors
