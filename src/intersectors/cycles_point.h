// cycles_point — Blender Cycles' point-cloud primitive, point_intersect_test
// (src/kernel/geom/point_intersect.h, blender/cycles v5.0.0-435-g97dbe6f5),
// the only analytic sphere in Cycles (mesh spheres are triangles):
//
//   rd2 = 1/(d·d),  c0 = c − o,  projC0 = (c0·d)·rd2,  perp = c0 − projC0·d
//   l2 = perp·perp,  r2 = r²;  miss unless l2 ≤ r2
//   td = √((r2 − l2)·rd2),  t_front = projC0 − td
//   hit t_front if tmin ≤ t_front ≤ tmax, else miss ("Always back-face culling for now")
//
// Embree's formula with the back face culled: a ray starting inside a point
// never hits it. Float only. Build modelled: the x86-64 SSE4.2 CPU kernel,
// where dot is _mm_dp_ps(a, b, 0x7F): products rounded, then (x + y) + z, the
// plain sum's order; no FMA (that kernel has none; the AVX2 kernel, built
// with -ffp-contract=on, may fuse and is not modelled); -freciprocal-math
// changes nothing the source does not already write as 1/x.
//
// Contract: nearest hit in [tmin, tmax] (closed), front faces only (so the
// far root never, and starting inside is a miss), a tangent a hit, any
// direction length.
#pragma once

#include <cmath>
#include <type_traits>

#include "core/intersection.h"
#include "core/ray_sphere_case.h"
#include "intersectors/scalar_math.h"

namespace rayverify::intersectors {

inline constexpr contract cycles_point_contract{.query = query_kind::nearest_hit,
                                                .range = range_source::interval,
                                                .lower_end = end_kind::closed,
                                                .upper_end = end_kind::closed,
                                                .inside = inside_rule::miss,
                                                .front_faces_only = true};

// Float: the kernel's float (or a traced float, for explain).
template <class Float = float>
inline root_pair<Float> cycles_point(const ray_sphere<Float>& s, std::type_identity_t<Float> tmin,
                              std::type_identity_t<Float> tmax) {
    const vec3<Float>& d = s.direction;
    const Float rd2 = step("rd2", Float(1.0f) / dot(d, d));
    const vec3<Float> c0 = step("c0", s.centre - s.origin);
    const Float projC0 = step("projC0", dot(c0, d) * rd2);
    const vec3<Float> perp = step("perp", c0 - projC0 * d);
    const Float l2 = step("l2", dot(perp, perp));
    const Float r2 = step("r2", s.radius * s.radius);
    if (!(l2 <= r2)) return {};

    const Float td = step("td", sqrt(step("r2 − l2", r2 - l2) * rd2));
    const Float t_front = projC0 - td;
    if (!(tmin <= t_front && t_front <= tmax)) return {};
    return {1, t_front, t_front};
}

}  // namespace rayverify::intersectors
