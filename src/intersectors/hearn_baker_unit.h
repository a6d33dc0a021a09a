// hearn_baker_unit — the Ray Tracing Gems ch.7 final form (hearn_baker.h)
// for a renderer that normalises its directions: with a = d·d = 1 the
// division b′/a, the product a·Δ and the division q/a disappear.
//
//   f = o − c,  b′ = −f·d̂,  C = f·f − r²
//   l = f + b′·d̂,  Δ = r² − l·l;  Δ < 0: miss            (RTG eq. 7.5, a = 1)
//   q = b′ + sign(b′)·√Δ,  roots C/q and q, then ordered  (RTG eq. 7.8, a = 1)
//
// hearn_baker_unit: both roots of the line, ordered, negative roots
// included; reports a tangent when Δ == 0; no clamp; sign(0) = +1.
// hearn_baker_unit_nearest: the nearest root in the open interval
// (tmin, tmax) (default (0, +∞)), computing one root where the signs of C and
// b′ allow (see hearn_baker_nearest.h).
// hearn_baker_unit_any_hit: whether a root lies in (tmin, tmax), deciding
// from signs where it can (see hearn_baker_any_hit.h).
// Contract of all three: assumes a unit direction (|d|² − 1 within 8ε; other cases
// are contract violations, not scored). Same known failures as hearn_baker.
#pragma once

#include <cmath>
#include <limits>
#include <utility>

#include "core/intersection.h"
#include "core/ray_sphere_case.h"
#include "intersectors/scalar_math.h"
#include "intersectors/hearn_baker_any_hit.h"
#include "intersectors/hearn_baker_nearest.h"

namespace rayverify::intersectors {

inline constexpr contract hearn_baker_unit_contract{.query = query_kind::line_roots,
                                                    .assumes_unit_direction = true,
                                                    .reports_tangent = true,
                                                    .tangent_rule = "Δ == 0"};

inline constexpr contract hearn_baker_unit_nearest_contract{
    .query = query_kind::nearest_hit, .range = range_source::interval, .assumes_unit_direction = true};

inline constexpr contract hearn_baker_unit_any_hit_contract{
    .query = query_kind::any_hit, .range = range_source::interval, .assumes_unit_direction = true};

template <class T>
root_pair<T> hearn_baker_unit(const ray_sphere<T>& s) {
    const vec3<T> f = step("f", s.origin - s.centre);
    const T b_prime = step("b′", -dot(f, s.direction));
    const T C = step("C", dot(f, f) - s.radius * s.radius);

    // Discriminant from the perpendicular vector, a = 1.
    const vec3<T> l = step("l", f + b_prime * s.direction);
    const T discriminant = step("Δ", s.radius * s.radius - dot(l, l));
    if (discriminant < 0) return {};

    // Stable roots, a = 1.
    const T q = step("q", b_prime + copysign(sqrt(discriminant), b_prime));
    T t0 = C / q;
    T t1 = q;
    if (t0 > t1) std::swap(t0, t1);
    return {discriminant == 0 ? 1 : 2, t0, t1};
}

template <class T>
root_pair<T> hearn_baker_unit_nearest(const ray_sphere<T>& s, T tmin = T(0),
                                      T tmax = std::numeric_limits<T>::infinity()) {
    const vec3<T> f = step("f", s.origin - s.centre);
    const T b_prime = step("b′", -dot(f, s.direction));
    const T C = step("C", dot(f, f) - s.radius * s.radius);
    if (C > 0 && b_prime < 0 && tmin >= 0) return {};

    const vec3<T> l = step("l", f + b_prime * s.direction);
    const T discriminant = step("Δ", s.radius * s.radius - dot(l, l));
    if (discriminant < 0) return {};

    const T q = step("q", b_prime + copysign(sqrt(discriminant), b_prime));
    return nearest_stable_root(T(1), b_prime, C, q, tmin, tmax);
}

template <class T>
root_pair<T> hearn_baker_unit_any_hit(const ray_sphere<T>& s, T tmin = T(0),
                                      T tmax = std::numeric_limits<T>::infinity()) {
    constexpr root_pair<T> hit{1, T(0), T(0)};
    const vec3<T> f = step("f", s.origin - s.centre);
    const T b_prime = step("b′", -dot(f, s.direction));
    const T C = step("C", dot(f, f) - s.radius * s.radius);
    const bool unbounded = tmax == std::numeric_limits<T>::infinity();
    if (C > 0 && b_prime < 0 && tmin >= 0) return {};
    if (C < 0 && tmin <= 0 && unbounded) return hit;

    const vec3<T> l = step("l", f + b_prime * s.direction);
    const T discriminant = step("Δ", s.radius * s.radius - dot(l, l));
    if (discriminant < 0) return {};
    if (C > 0 && b_prime >= 0 && tmin <= 0 && unbounded) return hit;

    const T q = step("q", b_prime + copysign(sqrt(discriminant), b_prime));
    return any_stable_root_in(T(1), b_prime, C, q, tmin, tmax) ? hit : root_pair<T>{};
}

}  // namespace rayverify::intersectors
