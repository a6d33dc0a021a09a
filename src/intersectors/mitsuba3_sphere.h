// mitsuba3 — Mitsuba 3's Sphere (src/shapes/sphere.cpp, mitsuba-renderer/
// mitsuba3 v3.9.1-12-gb45b0a93, drjit at dfccdd79), in its two scalar
// variants. The ray is Ray3f (o, d and maxt in the variant's Float; no mint);
// the sphere arithmetic runs in `Value`, which for a scalar, non-differentiable
// variant is double: scalar_rgb computes in double on float rays and rounds t
// to float at the end (mixed precision), scalar_rgb_double is double
// throughout. math::solve_quadratic (include/mitsuba/core/math.h):
//
//   Δ = fmsub(B, B, 4AC),  temp = −½(B + copysign(√Δ, B)),  x0 = temp/A,  x1 = C/temp, ordered
//   (A = 0: the linear root −C/B, valid when B ≠ 0)
//
// mitsuba3_preliminary — ray_intersect_preliminary_impl: the origin is first
// moved to the plane through the centre perpendicular to d,
//   plane_t = dot(−l, d) / norm(d),  l = o − c      (the division by |d|, not |d|²: for
//   plane_p = ray(Float(plane_t)) = fmadd(d, t, o)   a direction that is not unit length
//   o′ = plane_p − c                                   the shift is not to that plane)
// then A = |d|², B = 2·dot(o′, d), C = |o′|² − r², and near/far + plane_t;
// miss unless near ≤ maxt ∧ far ≥ 0, and miss when near < 0 ∧ far > maxt;
// t = near < 0 ? far : near, rounded to Float.
// mitsuba3_ray_test — ray_test_impl (shadow rays): the same without the shift
// (o′ = o − c), answering only hit or miss.
//
// A ray without tmax gets maxt = dr::Largest<Float>, as Mitsuba's own rays
// (Ray3f's default, spawn_ray).
//
// Contracts: nearest hit / any hit in [0, maxt] (no mint: tmax_only, both
// ends closed), the far root from inside, a tangent a hit, any direction
// length. Build modelled: x86-64 with AVX and FMA (DRJIT_X86_AVX,
// DRJIT_X86_FMA): dr::fmadd/fmsub are fused; a 3-vector of doubles is an AVX
// packet whose horizontal sum (dot, squared_norm) adds y + (z + x)
// (packet_avx.h, StaticArrayImpl<double, 3>); a 3-vector of floats is an SSE
// packet, fmadd lane by lane. Compiled with clang (no fusion beyond
// drjit's explicit fmadd/fmsub); divisions and √ IEEE, no reciprocal estimate.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/intersection.h"
#include "core/ray_sphere_case.h"
#include "intersectors/scalar_math.h"

namespace rayverify::intersectors {
namespace mitsuba {

// Mitsuba's double arithmetic in T's form: double, or a traced double when T is traced (explain).
template <class T>
using wide = same_form_t<T, double>;

// Horizontal sum of a 3-lane AVX double packet: y + (z + x).
template <class W>
inline W hsum(W x, W y, W z) {
    return y + (z + x);
}
template <class W>
inline W dot(vec3<W> a, vec3<W> b) {
    return hsum(a.x * b.x, a.y * b.y, a.z * b.z);
}
template <class W>
inline W squared_norm(vec3<W> v) {
    return mitsuba::dot(v, v);
}

template <class W>
struct roots {
    bool found = false;
    W near = 0, far = 0;
};

// math::solve_quadratic in Value = double.
template <class W>
inline roots<W> solve_quadratic(W a, W b, W c) {
    const bool linear_case = a == 0;
    const bool valid_linear = linear_case && b != 0;
    W x0 = -c / b, x1 = x0;
    const W discrim = step("discrim", fma(b, b, -(4.0 * a * c)));
    const bool valid_quadratic = !linear_case && discrim >= 0;
    if (valid_quadratic) {
        const W sqrt_discrim = sqrt(discrim);
        const W temp = step("temp", -0.5 * (b + copysign(sqrt_discrim, b)));
        const W x0p = temp / a, x1p = c / temp;
        // dr::minimum / dr::maximum (vminpd/vmaxpd: the second operand when either is NaN).
        const W x0m = x0p < x1p ? x0p : x1p, x1m = x0p > x1p ? x0p : x1p;
        x0 = linear_case ? x0 : x0m;
        x1 = linear_case ? x0 : x1m;
    }
    return {valid_linear || valid_quadratic, x0, x1};
}

// The sphere's answer from the origin o′ (relative to the centre) and the
// shift plane_t: nearest in [0, maxt], as double.
template <class W>
inline bool accept(const roots<W>& r, W maxt) {
    const bool out_bounds = !(r.near <= maxt && r.far >= 0.0);
    const bool in_bounds = r.near < 0.0 && r.far > maxt;
    return r.found && !out_bounds && !in_bounds;
}

template <class T>
vec3<wide<T>> widened(vec3<T> v) {
    return vec3_cast<wide<T>>(v);
}

template <class T>
wide<T> maxt_of(T maxt) {
    return isinf(maxt) && maxt > 0 ? static_cast<wide<T>>(std::numeric_limits<T>::max()) : static_cast<wide<T>>(maxt);
}

}  // namespace mitsuba

inline constexpr contract mitsuba3_preliminary_contract{.query = query_kind::nearest_hit,
                                                        .range = range_source::tmax_only,
                                                        .lower_end = end_kind::closed,
                                                        .upper_end = end_kind::closed};
inline constexpr contract mitsuba3_ray_test_contract{.query = query_kind::any_hit,
                                                     .range = range_source::tmax_only,
                                                     .lower_end = end_kind::closed,
                                                     .upper_end = end_kind::closed};

template <class T>
root_pair<T> mitsuba3_preliminary(const ray_sphere<T>& s, T /*tmin: none*/, T maxt_in) {
    using W = mitsuba::wide<T>;
    const vec3<W> center = mitsuba::widened(s.centre);
    const W radius = static_cast<W>(s.radius), maxt = mitsuba::maxt_of(maxt_in);
    const vec3<W> d = mitsuba::widened(s.direction);
    // Intersect the plane through the centre perpendicular to d first.
    const vec3<W> l = mitsuba::widened(s.origin) - center;
    const W plane_t = step("plane_t", mitsuba::dot(vec3<W>{-l.x, -l.y, -l.z}, d) / sqrt(mitsuba::squared_norm(d)));
    // ray(FloatP(plane_t)): fmadd(d, t, o) in the ray's Float.
    const T t_shift = static_cast<T>(plane_t);
    const vec3<T> plane_p{fma(s.direction.x, t_shift, s.origin.x), fma(s.direction.y, t_shift, s.origin.y),
                          fma(s.direction.z, t_shift, s.origin.z)};
    const vec3<W> o = step("o′", mitsuba::widened(plane_p) - center);

    const W A = step("A", mitsuba::squared_norm(d));
    const W B = step("B", 2.0 * mitsuba::dot(o, d));
    const W C = step("C", mitsuba::squared_norm(o) - radius * radius);
    mitsuba::roots<W> r = mitsuba::solve_quadratic(A, B, C);
    r.near += plane_t;
    r.far += plane_t;
    if (!mitsuba::accept(r, maxt)) return {};
    const T t = static_cast<T>(r.near < 0.0 ? r.far : r.near);
    return {1, t, t};
}

template <class T>
root_pair<T> mitsuba3_ray_test(const ray_sphere<T>& s, T /*tmin: none*/, T maxt_in) {
    using W = mitsuba::wide<T>;
    const vec3<W> o = step("o′", mitsuba::widened(s.origin) - mitsuba::widened(s.centre));
    const vec3<W> d = mitsuba::widened(s.direction);
    const W radius = static_cast<W>(s.radius);
    const W A = step("A", mitsuba::squared_norm(d));
    const W B = step("B", 2.0 * mitsuba::dot(o, d));
    const W C = step("C", mitsuba::squared_norm(o) - radius * radius);
    if (!mitsuba::accept(mitsuba::solve_quadratic(A, B, C), mitsuba::maxt_of(maxt_in))) return {};
    return {1, T(0), T(0)};
}

}  // namespace rayverify::intersectors
