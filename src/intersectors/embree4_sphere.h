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
// Float only: Embree's rays and spheres are float.
//
// Build modelled: Embree 4 for aarch64 (its NEON ISA, SSE emulated through
// common/simd/arm/sse2neon.h and emulation.h, as on Apple silicon and ARM
// servers), compiled with clang (-ffp-contract=on: only the explicit madds
// are fused, never an intrinsic's multiply into the next one's add), FPCR as
// the OS leaves it (round to nearest, FZ = 0, AH = 0). Operation for
// operation:
//   d·d: ray.dir is a Vec3ff, whose dot (common/math/vec3fa.h) is
//        reduce_add(a*b) on NEON, _mm_dp_ps(a, b, 0x7F) on NEON2X; both are
//        the products, then (x·x′ + y·y′) + z·z′ (lane 3 zeroed; vaddvq's
//        pairs or the shuffle sum), no FMA
//   rcp: the scalar rcp(float) of common/math/emath.h on __aarch64__:
//        vrecpe estimate (FRECPE, architecturally exact: neon_recip.h), then
//        two Newton steps r = vrecps(x, r)·r (FRECPS fused, the product
//        rounded apart); not 1.0f/x, and not the vfloat4 rcp (vdivq_f32)
//   the other dots (Vec3vf<M>, common/math/vec3.h): madd(x, x′, madd(y, y′,
//        z·z′)) with madd the fused vfmaq_f32; every other operation one
//        rounded NEON instruction (vmulq, vsubq, vsqrtq: correctly rounded)
// so the answer is the same on every aarch64 CPU, and portable here. On x86
// rcp is _mm_rcp_ss (rcp14 under AVX-512) and one Newton step, and that
// estimate differs between Intel and AMD: not modelled. Under
// -ffp-contract=fast (GCC's default) perp = c0 − projC0·d and r2 − l2 could
// fuse as well (clang 14 for aarch64 keeps a multiply and a subtraction from
// two inlined functions apart at -O2, and fuses them into fmls under
// -ffp-contract=fast): not modelled either. Back-face culling
// (EMBREE_BACKFACE_CULLING_SPHERES) off, as by default; no filter function,
// so the first valid hit is the answer; minimum-width enlargement off.
//
// Contract: nearest hit in [tnear, tfar] (both ends closed), the far root
// from inside, a tangent a hit, any direction length; also gives the normal Ng.
#pragma once

#include <cmath>
#include <type_traits>

#include "core/intersection.h"
#include "core/ray_sphere_case.h"
#include "intersectors/neon_recip.h"
#include "intersectors/scalar_math.h"

namespace rayverify::intersectors {
namespace embree {

// Float: Embree's float (or a traced float, for explain).

// madd(a, b, c) = a·b + c, fused (vfmaq_f32).
template <class Float>
inline Float madd(Float a, Float b, Float c) {
    return fma(a, b, c);
}

// Vec3vf<M>'s dot (common/math/vec3.h): madd(x, x′, madd(y, y′, z·z′)).
template <class Float>
inline Float dot(vec3<Float> a, vec3<Float> b) {
    return madd(a.x, b.x, madd(a.y, b.y, a.z * b.z));
}

// Vec3ff's dot on aarch64: the products, then vaddvq over [x, y, z, 0]:
// (x·x′ + y·y′) + (z·z′ + 0).
template <class Float>
inline Float dot_vec3ff(vec3<Float> a, vec3<Float> b) {
    const Float x = a.x * b.x, y = a.y * b.y, z = a.z * b.z;
    return (x + y) + (z + 0.0f);
}

// rcp(float) on __aarch64__ (common/math/emath.h): estimate, two Newton steps.
template <class Float>
inline Float rcp(Float x) {
    Float r = step("rcp estimate", neon::frecpe(x), "FRECPE's bits, bit for bit; exact: 1/(d·d)");
    r = neon::frecps(x, r) * r;
    r = neon::frecps(x, r) * r;
    return r;
}

}  // namespace embree

inline constexpr contract embree4_contract{.query = query_kind::nearest_hit,
                                           .range = range_source::interval,
                                           .lower_end = end_kind::closed,
                                           .upper_end = end_kind::closed,
                                           .outputs = {.normal = true}};

template <class Float = float>
inline answer<Float> embree4(const ray_sphere<Float>& s, std::type_identity_t<Float> tnear, std::type_identity_t<Float> tfar) {
    const vec3<Float>& d = s.direction;
    const Float rd2 = step("rd2", embree::rcp(embree::dot_vec3ff(d, d)));
    const vec3<Float> c0 = step("c0", s.centre - s.origin);
    const Float projC0 = step("projC0", embree::dot(c0, d) * rd2);
    const vec3<Float> perp = step("perp", c0 - projC0 * d);
    const Float l2 = step("l2", embree::dot(perp, perp));
    const Float r2 = step("r2", s.radius * s.radius);
    if (!(l2 <= r2)) return {};

    const Float td = step("td", sqrt(step("r2 − l2", r2 - l2) * rd2));
    const Float t_front = projC0 - td;
    const Float t_back = projC0 + td;
    const bool valid_front = tnear <= t_front && t_front <= tfar;
    const bool valid_back = tnear <= t_back && t_back <= tfar;
    if (!valid_front && !valid_back) return {};

    // The first hit and its geometric normal.
    const Float t = valid_front ? t_front : t_back;
    const Float td_signed = valid_front ? -td : td;
    answer<Float> out;
    out.roots = {1, t, t};
    out.normal = td_signed * d - perp;
    return out;
}

}  // namespace rayverify::intersectors
