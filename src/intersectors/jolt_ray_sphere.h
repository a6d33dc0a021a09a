// jolt — Jolt Physics' RaySphere (Jolt/Geometry/RaySphere.h, the overload
// returning a fraction; jrouwe/JoltPhysics v5.5.0-182-g3b47ec39) with
// FindRoot (Jolt/Math/FindRoot.h), as SphereShape::CastRay calls it:
//
//   f = o − c,  a = |d|²,  b = 2 d·f,  C = |f|² − r²
//   FindRoot: det = DifferenceOfProducts(b, b, 4a, C);  det < 0: none
//             q = (b + Sign(b)·√det) / −2,  x1 = q/a,  x2 = C/q (q = 0: x2 = x1)
//   none: C ≤ 0 ? 0 (origin inside) : miss;  ordered; x1 ≥ 0: x1;  x2 ≥ 0: 0;  else miss
//   CastRay keeps the hit when fraction < 1 + FLT_EPSILON (RayCastResult's initial mFraction)
//
// A Jolt ray is a segment: origin and direction, hits as fractions of the
// direction. The ray's range (tmin, tmax) maps to origin o + tmin·d and
// direction (tmax − tmin)·d, both in float; a ray without tmax gets
// direction L·d with L = segment_length() (core/intersection.h), a power of
// two past every root, so that the fraction f is the root t = f·L exactly.
// Float only (Vec3 is float; JPH_DOUBLE_PRECISION widens positions, not
// this function).
//
// Build modelled: JPH_CROSS_PLATFORM_DETERMINISTIC (-ffp-contract=off, no
// JPH_USE_FMADD): DifferenceOfProducts is b·b − (4a)·C in two roundings, and
// Vec3::Dot is the SSE4.1 ReduceSum (x + y) + (z + 0). The default x86 build
// (USE_FMADD with -ffp-contract=fast) lets the compiler fuse C's r² as well,
// so its rounding depends on the compiler and is not modelled.
//
// Contract: nearest hit on the segment [from, to] (closed; to be exact
// fraction < 1 + FLT_EPSILON, a sliver past `to` accepted), clamped to the
// start when the origin is inside (fraction 0), a tangent a hit, any
// direction length.
#pragma once

#include <cfloat>
#include <cmath>
#include <utility>

#include "core/intersection.h"
#include "core/ray_sphere_case.h"

namespace rayverify::intersectors {
namespace jolt_math {

// Vec3::Dot under JPH_CROSS_PLATFORM_DETERMINISTIC: products, then (x + y) + (z + 0).
inline float dot(vec3<float> a, vec3<float> b) { return (a.x * b.x + a.y * b.y) + (a.z * b.z + 0.0f); }

// FindRoot<float>: the roots of a x² + b x + c = 0; the count.
inline int find_root(float a, float b, float c, float& x1, float& x2) {
    if (a == 0.0f) {
        if (b == 0.0f) {
            if (c == 0.0f) {
                x1 = x2 = 0.0f;
                return 1;
            }
            return 0;
        }
        x1 = x2 = -c / b;
        return 1;
    }
    const float det = b * b - (4.0f * a) * c;  // DifferenceOfProducts without JPH_USE_FMADD
    if (det < 0.0f) return 0;
    const float sign = b < 0.0f ? -1.0f : 1.0f;  // Sign(): 1 for ±0
    const float q = (b + sign * std::sqrt(det)) / -2.0f;
    x1 = q / a;
    if (q == 0.0f) {
        x2 = x1;
        return 1;
    }
    x2 = c / q;
    return 2;
}

// RaySphere: the fraction of the direction at the hit, FLT_MAX for none.
inline float ray_sphere(vec3<float> origin, vec3<float> direction, vec3<float> centre, float radius) {
    const vec3<float> center_origin = origin - centre;
    const float a = dot(direction, direction);
    const float b = 2.0f * dot(direction, center_origin);
    const float c = dot(center_origin, center_origin) - radius * radius;
    float fraction1 = 0, fraction2 = 0;
    if (find_root(a, b, c, fraction1, fraction2) == 0) return c <= 0.0f ? 0.0f : FLT_MAX;
    if (fraction1 > fraction2) std::swap(fraction1, fraction2);
    if (fraction1 >= 0.0f) return fraction1;
    if (fraction2 >= 0.0f) return 0.0f;
    return FLT_MAX;
}

}  // namespace jolt_math

inline constexpr contract jolt_contract{.query = query_kind::nearest_hit,
                                        .range = range_source::segment,
                                        .lower_end = end_kind::closed,
                                        .upper_end = end_kind::closed,
                                        .inside = inside_rule::clamp};

inline root_pair<float> jolt(const ray_sphere<float>& s, float tmin, float tmax) {
    const float length = std::isinf(tmax) ? segment_length(s) : tmax - tmin;
    const vec3<float> origin = tmin == 0.0f ? s.origin : s.origin + tmin * s.direction;
    const float fraction = jolt_math::ray_sphere(origin, length * s.direction, s.centre, s.radius);
    if (!(fraction < 1.0f + FLT_EPSILON)) return {};
    const float t = tmin == 0.0f ? fraction * length : tmin + fraction * length;
    return {1, t, t};
}

}  // namespace rayverify::intersectors
