// hearn_baker — Ray Tracing Gems ch.7 (Haines, Günther, Akenine-Möller,
// "Precision Improvements for Ray/Sphere Intersection"), the final form:
// the Hearn–Baker discriminant (perpendicular-vector form) with stable roots.
//
//   f = o − c,  a = d·d,  b′ = −f·d,  C = f·f − r²
//   l = f + (b′/a)·d                   (f minus its projection on d)
//   Δ = r² − l·l;  Δ < 0: miss          (= (b′² − aC)/a without cancellation)
//   q = b′ + sign(b′)·√(aΔ),  roots C/q and q/a, then ordered
//
// Contract: any direction length; both roots of the line, ordered, negative
// roots included; reports a tangent when Δ == 0; no clamp; sign(0) = +1.
// Known failure: C = f·f − r² still cancels when the origin is near the
// surface; b′ = 0 and Δ = 0 gives C/q = 0/0.
#pragma once

#include <cmath>
#include <utility>

#include "core/intersection.h"
#include "core/ray_sphere_case.h"
#include "intersectors/scalar_math.h"

namespace rayverify::intersectors {

inline constexpr contract hearn_baker_contract{
    .query = query_kind::line_roots, .reports_tangent = true, .tangent_rule = "Δ == 0"};

template <class T>
root_pair<T> hearn_baker(const ray_sphere<T>& s) {
    const vec3<T> f = step("f", s.origin - s.centre);
    const T a = step("a", dot(s.direction, s.direction));
    const T b_prime = step("b′", -dot(f, s.direction));
    const T C = step("C", dot(f, f) - s.radius * s.radius);

    // Discriminant from the perpendicular vector (RTG eq. 7.5).
    const vec3<T> l = step("l", f + (b_prime / a) * s.direction);
    const T discriminant = step("Δ", s.radius * s.radius - dot(l, l));
    if (discriminant < 0) return {};

    // Stable roots (RTG eq. 7.8).
    const T q = step("q", b_prime + copysign(sqrt(a * discriminant), b_prime));
    T t0 = C / q;
    T t1 = q / a;
    if (t0 > t1) std::swap(t0, t1);
    return {discriminant == 0 ? 1 : 2, t0, t1};
}

}  // namespace rayverify::intersectors
