// pbrt_v4 — pbrt-v4's Sphere::BasicIntersect (src/pbrt/shapes.h, mmp/pbrt-v4
// commit 5f7a6068, June 2026; unchanged in substance since the v4 release),
// with the interval arithmetic of src/pbrt/util/math.h (class Interval) and
// the CPU rounding helpers of src/pbrt/util/float.h (AddRoundUp = NextFloatUp
// of the rounded sum, and so on), reproduced here.
//
// The sphere is a full sphere of radius r in object space, placed by
// renderFromObject = Translate(c); the ray is in render space. So the origin
// goes through Transform::operator()(Point3fi) with m = Translate(−c) (each
// coordinate (1·x + 0·y) + (0·z − c), error γ₃·(|x| + |c|)) and the direction
// through the Vector3fi form (error γ₃·|d|), both as intervals. Then, in
// interval arithmetic (every operation rounds outward by one float step):
//
//   a = dx² + dy² + dz²,  b = 2(d·o),  c = o·o − r²
//   v = o − (b / 2a)·d,  Δ = 4a (r + |v|)(r − |v|)    (pbrt-v4 §6.8.3)
//   Δ.low < 0: miss
//   q = −½(b ∓ √Δ) (sign by b's midpoint),  t0 = q/a,  t1 = c/q, ordered by low ends
//   t0.high > tMax or t1.low ≤ 0: miss;  t0.low ≤ 0: t1 (the far root), miss if t1.high > tMax
//   pHit = mid(o) + mid(t)·mid(d), reprojected: pHit · r / |pHit|;  φ test against phiMax = 2π
//
// Returned: the hit's interval midpoint as t, its interval [low, high], the
// reprojected hit point taken back to render space by Translate(c) as a
// Point3fi (its midpoint) and that interval's half-width as the error bound
// (InteractionFromIntersection: pError = γ₅·|pHit| in object space, then the
// transform's propagation). That bound is the reprojected point's distance to
// the surface (pbrt-v4 §6.8.5), not along the ray to o + t*·d, so the
// contract states point_error=surface: the box must hold a point of the
// sphere. A hit on the object's z axis is moved to x = 1e-5·r (for φ), off
// the sphere by about r·5e-11: inside γ₅·r in float, outside it in double.
// The normal is not modelled.
//
// Contract: nearest hit in (0, tMax] (BasicIntersect takes tMax, no tmin);
// decisions are made on interval ends, so a root whose interval reaches 0 is
// behind, and a discriminant whose interval reaches below 0 is a miss: an
// exact tangent is a miss by design (tangent=miss). Builds: Float = float
// (the default) and PBRT_FLOAT_AS_DOUBLE; CPU rounding helpers (NextFloatUp/
// Down of the round-to-nearest result, one float step wider than directed
// rounding would be); std::fma only in DifferenceOfProducts, unused here;
// atan2 from the host C library. Architecture: the x86-64 CPU build as
// pbrt's CMake makes it (no -march, so no FMA instruction for the compiler
// to contract into); divisions and √ IEEE, no reciprocal estimates.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <string>
#include <type_traits>

#include "core/intersection.h"
#include "core/ray_sphere_case.h"
#include "intersectors/scalar_math.h"
#include "intersectors/traced.h"

namespace rayverify::intersectors {
namespace pbrt {

using std::sqrt;  // beside pbrt::sqrt of an interval below

template <class T>
using bits_of = std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>;

// NextFloatUp / NextFloatDown (util/float.h), including their treatment of
// ±0 and ±inf.
template <class T>
T next_float_up(T v) {
    if (std::isinf(v) && v > 0) return v;
    if (v == T(-0.0)) v = T(0);
    auto ui = std::bit_cast<bits_of<T>>(v);
    if (v >= 0)
        ++ui;
    else
        --ui;
    return std::bit_cast<T>(ui);
}

template <class T>
T next_float_down(T v) {
    if (std::isinf(v) && v < 0) return v;
    if (v == T(0)) v = T(-0.0);
    auto ui = std::bit_cast<bits_of<T>>(v);
    if (v > 0)
        --ui;
    else
        ++ui;
    return std::bit_cast<T>(ui);
}

// A traced run: the neighbour from the bits, standing for the value it bounds.
template <class T>
traced<T> next_float_up(traced<T> v) {
    return computed_apart(next_float_up(v.value), v);
}

template <class T>
traced<T> next_float_down(traced<T> v) {
    return computed_apart(next_float_down(v.value), v);
}

// gamma(n) = nε/(1 − nε), ε = MachineEpsilon = epsilon/2, in Float: a
// rounding error bound, 0 in exact arithmetic (rounding_error_bound).
template <class T>
constexpr T gamma(int n) {
    using P = plain_scalar_t<T>;
    constexpr P machine_epsilon = std::numeric_limits<P>::epsilon() * P(0.5);
    return rounding_error_bound(
        T((static_cast<P>(n) * machine_epsilon) / (P(1) - static_cast<P>(n) * machine_epsilon)));
}

// class Interval: [low, high], every operation rounded outward.
template <class T>
struct interval {
    T low{}, high{};

    static interval exactly(T v) { return {v, v}; }
    // Interval(low, high) orders its ends.
    static interval of(T a, T b) { return {std::min(a, b), std::max(a, b)}; }
    static interval from_value_and_error(T v, T err) {
        if (err == 0) return {v, v};
        return {next_float_down(v - err), next_float_up(v + err)};
    }
    T midpoint() const { return (low + high) / 2; }  // explicit operator Float
    bool contains_zero() const { return T(0) >= low && T(0) <= high; }  // InRange(0, i)

    friend interval operator+(interval a, interval b) {
        return of(next_float_down(a.low + b.low), next_float_up(a.high + b.high));
    }
    friend interval operator-(interval a, interval b) {
        return of(next_float_down(a.low - b.high), next_float_up(a.high - b.low));
    }
    friend interval operator*(interval a, interval b) {
        const T lp[4] = {next_float_down(a.low * b.low), next_float_down(a.high * b.low),
                         next_float_down(a.low * b.high), next_float_down(a.high * b.high)};
        const T hp[4] = {next_float_up(a.low * b.low), next_float_up(a.high * b.low), next_float_up(a.low * b.high),
                         next_float_up(a.high * b.high)};
        return of(std::min({lp[0], lp[1], lp[2], lp[3]}), std::max({hp[0], hp[1], hp[2], hp[3]}));
    }
    friend interval operator/(interval a, interval b) {
        if (b.contains_zero()) return of(-std::numeric_limits<T>::infinity(), std::numeric_limits<T>::infinity());
        const T lq[4] = {next_float_down(a.low / b.low), next_float_down(a.high / b.low),
                         next_float_down(a.low / b.high), next_float_down(a.high / b.high)};
        const T hq[4] = {next_float_up(a.low / b.low), next_float_up(a.high / b.low), next_float_up(a.low / b.high),
                         next_float_up(a.high / b.high)};
        return of(std::min({lq[0], lq[1], lq[2], lq[3]}), std::max({hq[0], hq[1], hq[2], hq[3]}));
    }
    // operator*(Float f, Interval i)
    friend interval operator*(T f, interval i) {
        if (f > 0) return of(next_float_down(f * i.low), next_float_up(f * i.high));
        return of(next_float_down(f * i.high), next_float_up(f * i.low));
    }
};

template <class T>
interval<T> sqr(interval<T> i) {
    T alow = abs(i.low), ahigh = abs(i.high);
    if (alow > ahigh) std::swap(alow, ahigh);
    if (i.contains_zero()) return interval<T>::of(0, next_float_up(ahigh * ahigh));
    return interval<T>::of(next_float_down(alow * alow), next_float_up(ahigh * ahigh));
}

template <class T>
interval<T> sqrt(interval<T> i) {
    return interval<T>::of(std::max<T>(0, next_float_down(sqrt(i.low))), next_float_up(sqrt(i.high)));
}

// Point3fi / Vector3fi.
template <class T>
struct vec3i {
    interval<T> x, y, z;
};

template <class T>
vec3<T> midpoints(const vec3i<T>& v) {
    return {v.x.midpoint(), v.y.midpoint(), v.z.midpoint()};
}

// Transform::operator()(Point3fi) for Translate(delta): m = [I | delta], so
// each coordinate is (m00·x + m01·y) + (m02·z + m03) with the zero products
// written out, and the error of an exact point γ₃·(|x| + |0·y| + |0·z| + |delta|),
// of an approximate one (γ₃ + 1)·pInError + γ₃·(...).
template <class T>
vec3i<T> translate_point(const vec3i<T>& p, vec3<T> delta) {
    const vec3<T> v = midpoints(p);
    const vec3<T> in_error{(p.x.high - p.x.low) / 2, (p.y.high - p.y.low) / 2, (p.z.high - p.z.low) / 2};
    const bool exact = in_error.x == 0 && in_error.y == 0 && in_error.z == 0;
    const T zero = 0, one = 1;
    const auto row = [&](T m0, T m1, T m2, T m3) {
        const T value = (m0 * v.x + m1 * v.y) + (m2 * v.z + m3);
        T error = gamma<T>(3) * (abs(m0 * v.x) + abs(m1 * v.y) + abs(m2 * v.z) + abs(m3));
        if (!exact)
            error = (gamma<T>(3) + 1) * (abs(m0) * in_error.x + abs(m1) * in_error.y + abs(m2) * in_error.z) + error;
        return interval<T>::from_value_and_error(value, error);
    };
    return {row(one, zero, zero, delta.x), row(zero, one, zero, delta.y), row(zero, zero, one, delta.z)};
}

// Transform::operator()(Vector3fi) of an exact vector: the identity part of
// Translate, error γ₃·(|1·x| + |0·y| + |0·z|).
template <class T>
vec3i<T> translate_vector(vec3<T> d) {
    const T zero = 0, one = 1;
    const auto row = [&](T m0, T m1, T m2) {
        const T error = gamma<T>(3) * (abs(m0 * d.x) + abs(m1 * d.y) + abs(m2 * d.z));
        return interval<T>::from_value_and_error(m0 * d.x + m1 * d.y + m2 * d.z, error);
    };
    return {row(one, zero, zero), row(zero, one, zero), row(zero, zero, one)};
}

// Names an interval's ends as steps: each stands for the value the interval
// encloses, which is its ideal value (the γ_n bounds are 0 in exact arithmetic).
template <class T>
interval<T> step(const char* name, interval<T> i) {
    if constexpr (!std::is_same_v<T, plain_scalar_t<T>>) {
        const std::string base = name;
        step((base + " low").c_str(), i.low);
        step((base + " high").c_str(), i.high);
    }
    return i;
}

}  // namespace pbrt

inline constexpr contract pbrt_v4_contract{.query = query_kind::nearest_hit,
                                           .range = range_source::tmax_only,
                                           .upper_end = end_kind::closed,
                                           .tangent_is_hit = false,
                                           .outputs = {.t_bounds = true, .hit_point = true, .point_error = point_bound::surface}};

template <class T>
answer<T> pbrt_v4(const ray_sphere<T>& s, T /*tmin: none*/, T tmax) {
    using pbrt::interval;
    using I = interval<T>;
    const T radius = s.radius;
    // Transform the ray origin and direction to object space.
    const pbrt::vec3i<T> oi =
        pbrt::translate_point(pbrt::vec3i<T>{I::exactly(s.origin.x), I::exactly(s.origin.y), I::exactly(s.origin.z)},
                              vec3<T>{-s.centre.x, -s.centre.y, -s.centre.z});
    const pbrt::vec3i<T> di = pbrt::translate_vector(s.direction);

    // Compute sphere quadratic coefficients.
    const I a = step("a", pbrt::sqr(di.x) + pbrt::sqr(di.y) + pbrt::sqr(di.z));
    const I b = step("b", T(2) * (di.x * oi.x + di.y * oi.y + di.z * oi.z));
    const I c = step("c", pbrt::sqr(oi.x) + pbrt::sqr(oi.y) + pbrt::sqr(oi.z) - pbrt::sqr(I::exactly(radius)));

    // Compute sphere quadratic discriminant.
    const I b_over_2a = b / (T(2) * a);
    const pbrt::vec3i<T> v{oi.x - b_over_2a * di.x, oi.y - b_over_2a * di.y, oi.z - b_over_2a * di.z};
    const I length = step("|v|", pbrt::sqrt(pbrt::sqr(v.x) + pbrt::sqr(v.y) + pbrt::sqr(v.z)));
    const I discrim = step("Δ", T(4) * a * (I::exactly(radius) + length) * step("r − |v|", I::exactly(radius) - length));
    if (discrim.low < 0) return {};

    // Compute quadratic t values.
    const I root_discrim = pbrt::sqrt(discrim);
    const I q = step("q", b.midpoint() < 0 ? T(-0.5) * (b - root_discrim) : T(-0.5) * (b + root_discrim));
    I t0 = q / a, t1 = c / q;
    if (t0.low > t1.low) std::swap(t0, t1);

    // Check quadric shape t0 and t1 for nearest intersection.
    if (t0.high > tmax || t1.low <= 0) return {};
    I hit = t0;
    if (hit.low <= 0) {
        hit = t1;
        if (hit.high > tmax) return {};
    }

    // Compute sphere hit position and φ; a full sphere is clipped only by φ > phiMax = Radians(360).
    const vec3<T> o_mid = pbrt::midpoints(oi), d_mid = pbrt::midpoints(di);
    constexpr T pi = std::numbers::pi_v<plain_scalar_t<T>>;
    const T phi_max = (pi / 180) * T(360);
    const auto position = [&](const I& t) {
        const T tm = t.midpoint();
        vec3<T> p{o_mid.x + tm * d_mid.x, o_mid.y + tm * d_mid.y, o_mid.z + tm * d_mid.z};
        // Refine sphere intersection point.
        const T scale = radius / sqrt(p.x * p.x + p.y * p.y + p.z * p.z);
        p = {p.x * scale, p.y * scale, p.z * scale};
        if (p.x == 0 && p.y == 0) p.x = T(1e-5f) * radius;
        return p;
    };
    const auto clipped = [&](vec3<T> p) {
        T phi = atan2(p.y, p.x);
        if (phi < 0) phi += 2 * pi;
        return phi > phi_max;
    };
    vec3<T> p_hit = position(hit);
    if (clipped(p_hit)) {
        if (hit.low == t1.low && hit.high == t1.high) return {};
        if (t1.high > tmax) return {};
        hit = t1;
        p_hit = position(hit);
        if (clipped(p_hit)) return {};
    }

    // Error bounds for the sphere intersection, then renderFromObject.
    const T g5 = pbrt::gamma<T>(5);
    const pbrt::vec3i<T> object_point{I::from_value_and_error(p_hit.x, g5 * abs(p_hit.x)),
                                      I::from_value_and_error(p_hit.y, g5 * abs(p_hit.y)),
                                      I::from_value_and_error(p_hit.z, g5 * abs(p_hit.z))};
    const pbrt::vec3i<T> render_point = pbrt::translate_point(object_point, s.centre);

    answer<T> out;
    const T t = hit.midpoint();
    out.roots = {1, t, t};
    out.t_lower = {hit.low, hit.low};
    out.t_upper = {hit.high, hit.high};
    out.point = pbrt::midpoints(render_point);
    out.point_error = {(render_point.x.high - render_point.x.low) / 2, (render_point.y.high - render_point.y.low) / 2,
                       (render_point.z.high - render_point.z.low) / 2};
    return out;
}

}  // namespace rayverify::intersectors
