// jolt, jolt_fma — Jolt Physics' RaySphere (Jolt/Geometry/RaySphere.h, the overload
// returning a fraction; jrouwe/JoltPhysics v5.5.0-182-g3b47ec39) with
// FindRoot (Jolt/Math/FindRoot.h), called directly:
//
//   f = o − c,  a = |d|²,  b = 2 d·f,  C = |f|² − r²
//   FindRoot: det = DifferenceOfProducts(b, b, 4a, C);  det < 0: none
//             q = (b + Sign(b)·√det) / −2,  x1 = q/a,  x2 = C/q (q = 0: x2 = x1)
//   none: C ≤ 0 ? 0 (origin inside) : miss;  ordered; x1 ≥ 0: x1;  x2 ≥ 0: 0;  else miss
//   CastRay keeps the hit when fraction < 1 + FLT_EPSILON (RayCastResult's initial mFraction)
//
// Mapping (the test wrapper, rayverify's code, not Jolt's): the function is
// called as an application calls it, RaySphere(origin, direction, centre,
// radius), with no scaling of its own. A case without tmax is a ray
// "extending infinitely in inRayDirection" (RaySphere.h), exactly this
// overload's contract: origin o + tmin·d (o when tmin = 0), direction d
// itself (scale 1), and the fraction is t − tmin, unbounded above, so every
// root is held. A bounded case is a RayCast segment, as CastRay takes one:
// origin o + tmin·d, direction (tmax − tmin)·d, each coordinate rounded in
// float, the hit kept while fraction < 1 + FLT_EPSILON (RayCastResult's
// initial mFraction) and t = tmin + fraction·(tmax − tmin). An earlier
// wrapper stretched d to a power-of-two segment past every root
// (segment_length, up to 2^36 on the corpus) and so made b² and 4aC
// overflow on far spheres where Jolt, given the ray, does not; any segment
// long enough to hold a far root has |D|·|o − c| ≥ |o − c|², so b² ≈ 4|o − c|⁴
// overflows float beyond |o − c| ≈ 2^31 whatever its length: only the
// unbounded call leaves overflow to the application's own ray. Float only
// (Vec3 is float; JPH_DOUBLE_PRECISION widens positions, not this function).
// The sphere is at c (SphereShape::CastRay calls it in the shape's space,
// with centre 0 and the origin already moved by o − c).
//
// Builds modelled (two targets; Jolt at the version above, x86-64):
//   jolt      JPH_CROSS_PLATFORM_DETERMINISTIC: no JPH_USE_FMADD,
//             -ffp-contract=off. DifferenceOfProducts is b·b − (4a)·C in
//             two roundings; Vec3::Dot is the products, then the SSE4.1
//             deterministic ReduceSum (x·x′ + y·y′) + (z·z′ + 0). Nothing
//             fused; the same on every CPU and compiler, as Jolt promises.
//   jolt_fma  the default x86-64 build (USE_AVX2, USE_FMADD: JPH_USE_FMADD,
//             -mfma, and -ffp-contract=fast as Build/CMakeLists.txt sets on
//             x86). DifferenceOfProducts is Kahan's form as Math.h writes it
//             with std::fma: cd = 4a·C, err = fma(−4a, C, cd),
//             dop = fma(b, b, −cd), det = dop + err. ReduceSum's
//             non-deterministic form (x·x′ + y·y′) + z·z′. The compiler
//             contracts one more expression, C = |f|² − r², into
//             fma(−r, r, |f|²), written here with std::fma. GCC also fuses
//             b + Sign(b)·√det, whose product by ±1 is exact: the same
//             value either way. Dot's products feed a shuffle as well as
//             the add and stay apart (GCC 12 and clang 14 at -O2 -mavx2
//             -mfma -ffp-contract=fast: vfnmadd for C, vmulps then vaddps
//             for the dot). FMA is exact, so this build too is the same on
//             every x86-64 CPU with FMA.
//
// Contract: nearest hit on the segment [from, to] (closed; to be exact
// fraction < 1 + FLT_EPSILON, a sliver past `to` accepted), or on the whole
// ray from o + tmin·d without tmax; clamped to the start when the origin is
// inside (fraction 0), a tangent a hit, any direction length.
#pragma once

#include <cfloat>
#include <cmath>
#include <type_traits>
#include <utility>

#include "core/intersection.h"
#include "core/ray_sphere_case.h"
#include "intersectors/scalar_math.h"

namespace rayverify::intersectors {

// Which of Jolt's builds a port models (see above).
enum class jolt_build { deterministic, fma };

namespace jolt_math {

// Vec3::Dot: the products, then ReduceSum under SSE4.1.
template <jolt_build B, class Float>
Float dot(vec3<Float> a, vec3<Float> b) {
    const Float x = a.x * b.x, y = a.y * b.y, z = a.z * b.z;
    if constexpr (B == jolt_build::deterministic)
        return (x + y) + (z + 0.0f);
    else
        return (x + y) + z;
}

// DifferenceOfProducts (Jolt/Math/Math.h): a·b − c·d.
template <jolt_build B, class Float>
Float difference_of_products(Float a, Float b, Float c, Float d) {
    if constexpr (B == jolt_build::deterministic) {
        return a * b - c * d;
    } else {
        const Float cd = c * d;
        const Float err = fma(-c, d, cd);
        const Float dop = fma(a, b, -cd);
        return dop + err;
    }
}

// FindRoot<Float>: the roots of a x² + b x + c = 0; the count.
template <jolt_build B, class Float>
int find_root(Float a, Float b, Float c, Float& x1, Float& x2) {
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
    const Float det = step("det", difference_of_products<B>(b, b, 4.0f * a, c));
    if (det < 0.0f) return 0;
    const Float sign = b < 0.0f ? -1.0f : 1.0f;  // Sign(): 1 for ±0
    const Float q = step("q", (b + sign * sqrt(det)) / -2.0f);
    x1 = q / a;
    if (q == 0.0f) {
        x2 = x1;
        return 1;
    }
    x2 = c / q;
    return 2;
}

// RaySphere: the fraction of the direction at the hit, FLT_MAX for none.
template <jolt_build B, class Float>
Float ray_sphere(vec3<Float> origin, vec3<Float> direction, vec3<Float> centre, Float radius) {
    const vec3<Float> center_origin = step("f", origin - centre);
    const Float a = step("a", dot<B>(direction, direction));
    const Float b = step("b", 2.0f * dot<B>(direction, center_origin));
    // C = |f|² − r²: contracted to one FMA under -ffp-contract=fast.
    const Float c = step("C", B == jolt_build::deterministic
                                  ? dot<B>(center_origin, center_origin) - radius * radius
                                  : fma(-radius, radius, dot<B>(center_origin, center_origin)));
    Float fraction1 = 0, fraction2 = 0;
    if (find_root<B>(a, b, c, fraction1, fraction2) == 0) return c <= 0.0f ? 0.0f : FLT_MAX;
    if (fraction1 > fraction2) std::swap(fraction1, fraction2);
    if (fraction1 >= 0.0f) return fraction1;
    if (fraction2 >= 0.0f) return 0.0f;
    return FLT_MAX;
}

// The case on (tmin, tmax) as a call of RaySphere (the mapping above).
template <jolt_build B, class Float>
root_pair<Float> ray_sphere_case(const rayverify::ray_sphere<Float>& s, Float tmin, Float tmax) {
    const vec3<Float> origin = tmin == 0.0f ? s.origin : s.origin + tmin * s.direction;
    if (isinf(tmax)) {
        const Float fraction = ray_sphere<B>(origin, s.direction, s.centre, s.radius);
        if (fraction == FLT_MAX) return {};
        const Float t = tmin == 0.0f ? fraction : tmin + fraction;
        return {1, t, t};
    }
    const Float length = tmax - tmin;
    const Float fraction = ray_sphere<B>(origin, length * s.direction, s.centre, s.radius);
    if (!(fraction < 1.0f + FLT_EPSILON)) return {};
    const Float t = tmin == 0.0f ? fraction * length : tmin + fraction * length;
    return {1, t, t};
}

}  // namespace jolt_math

inline constexpr contract jolt_contract{.query = query_kind::nearest_hit,
                                        .range = range_source::segment,
                                        .lower_end = end_kind::closed,
                                        .upper_end = end_kind::closed,
                                        .inside = inside_rule::clamp};
inline constexpr contract jolt_fma_contract = jolt_contract;

// Float: Jolt's float (or a traced float, for explain).
template <class Float = float>
inline root_pair<Float> jolt(const ray_sphere<Float>& s, std::type_identity_t<Float> tmin, std::type_identity_t<Float> tmax) {
    return jolt_math::ray_sphere_case<jolt_build::deterministic>(s, tmin, tmax);
}

template <class Float = float>
inline root_pair<Float> jolt_fma(const ray_sphere<Float>& s, std::type_identity_t<Float> tmin,
                          std::type_identity_t<Float> tmax) {
    return jolt_math::ray_sphere_case<jolt_build::fma>(s, tmin, tmax);
}

}  // namespace rayverify::intersectors
