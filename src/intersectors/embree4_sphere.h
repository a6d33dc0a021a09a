// embree4 — Embree 4's sphere point primitive, SphereIntersector1::intersect
// (kernels/geometry/sphere_intersector.h, RenderKit/embree v4.4.1-8-g93040c7a),
// one lane of its vfloat4 evaluation:
//
//   rd2 = rcp(d·d),  c0 = c − o,  projC0 = (c0·d)·rd2,  perp = c0 − projC0·d
//   l2 = perp·perp,  r2 = r²;  miss unless l2 ≤ r2
//   td = √((r2 − l2)·rd2),  t_front = projC0 − td,  t_back = projC0 + td
//   hit t_front if tnear ≤ t_front ≤ tfar, else t_back if tnear ≤ t_back ≤ tfar
//   Ng = ±td·d − perp (unnormalised; − for the front hit, + for the back)
//
// with Embree's dot (common/math/vec3.h): madd(x, x′, madd(y, y′, z·z′)).
// Float only: Embree's rays and spheres are float.
//
// Build modelled: aarch64 (NEON, as on Apple silicon and ARM servers), where
// madd is a fused vfmaq_f32 and rcp(x) is the division 1.0f/x (vdivq_f32,
// vfloat4_sse2.h): correctly rounded and the same on every such CPU. On x86
// rcp is the hardware estimate _mm_rcp_ps (or rcp14) refined by one Newton
// step, and the estimate differs between CPU vendors, so that form is not
// modelled (CLARIFICATIONS: one documented, portable form). Back-face culling
// (EMBREE_BACKFACE_CULLING_SPHERES) off, as by default; no filter function,
// so the first valid hit is the answer; minimum-width enlargement off.
//
// Contract: nearest hit in [tnear, tfar] (both ends closed), the far root
// from inside, a tangent a hit, any direction length; also gives the normal Ng.
#pragma once

#include <cmath>

#include "core/intersection.h"
#include "core/ray_sphere_case.h"

namespace rayverify::intersectors {
namespace embree {

// madd(a, b, c) = a·b + c, fused (vfmaq_f32).
inline float madd(float a, float b, float c) { return std::fma(a, b, c); }
inline float dot(vec3<float> a, vec3<float> b) { return madd(a.x, b.x, madd(a.y, b.y, a.z * b.z)); }

}  // namespace embree

inline constexpr contract embree4_contract{.query = query_kind::nearest_hit,
                                           .range = range_source::interval,
                                           .lower_end = end_kind::closed,
                                           .upper_end = end_kind::closed,
                                           .outputs = {.normal = true}};

inline answer<float> embree4(const ray_sphere<float>& s, float tnear, float tfar) {
    const vec3<float>& d = s.direction;
    const float rd2 = 1.0f / embree::dot(d, d);
    const vec3<float> c0 = s.centre - s.origin;
    const float projC0 = embree::dot(c0, d) * rd2;
    const vec3<float> perp = c0 - projC0 * d;
    const float l2 = embree::dot(perp, perp);
    const float r2 = s.radius * s.radius;
    if (!(l2 <= r2)) return {};

    const float td = std::sqrt((r2 - l2) * rd2);
    const float t_front = projC0 - td;
    const float t_back = projC0 + td;
    const bool valid_front = tnear <= t_front && t_front <= tfar;
    const bool valid_back = tnear <= t_back && t_back <= tfar;
    if (!valid_front && !valid_back) return {};

    // The first hit and its geometric normal.
    const float t = valid_front ? t_front : t_back;
    const float td_signed = valid_front ? -td : td;
    answer<float> out;
    out.roots = {1, t, t};
    out.normal = td_signed * d - perp;
    return out;
}

}  // namespace rayverify::intersectors
