// hearn_baker_nearest — the Ray Tracing Gems ch.7 final form (hearn_baker.h)
// specialised to "the nearest root in (tmin, tmax)": one root returned, and
// where the signs of the roots' product and sum tell which root that is, only
// that root is computed.
//
//   f = o − c,  a = d·d,  b′ = −f·d,  C = f·f − r²
//   C > 0, b′ < 0, tmin ≥ 0: both roots behind the origin — miss (no Δ, no √)
//   l = f + (b′/a)·d,  Δ = r² − l·l;  Δ < 0: miss       (RTG eq. 7.5)
//   q = b′ + sign(b′)·√(aΔ), roots C/q and q/a          (RTG eq. 7.8)
//   C > 0, b′ > 0 (both in front): near = C/q; far = q/a only if near ≤ tmin
//   C < 0, tmin ≥ 0 (origin inside): only the far root, q/a or C/q by the sign of q
//   otherwise both roots, ordered, and the first inside the interval
//
// Contract: any direction length; answers nearest_hit for the open interval
// (tmin, tmax) (default (0, +∞)): count 1 and the root in t0 (= t1),
// or count 0. Same known failures as hearn_baker.
#pragma once

#include <cmath>
#include <limits>
#include <utility>

#include "core/intersection.h"
#include "core/ray_sphere_case.h"
#include "intersectors/scalar_math.h"

namespace rayverify::intersectors {

inline constexpr contract hearn_baker_nearest_contract{.query = query_kind::nearest_hit,
                                                       .range = range_source::interval};

// The nearest of the roots C/q and q/a of a t² − 2b′t + C = 0 in (tmin, tmax),
// computing only what the signs of C and b′ leave open. Shared by the unit-
// direction form (a = 1).
template <class T>
root_pair<T> nearest_stable_root(T a, T b_prime, T C, T q, T tmin, T tmax) {
    const auto found = [](T t) { return root_pair<T>{1, t, t}; };
    const auto inside = [&](T t) { return t > tmin && t < tmax; };
    if (C > 0 && b_prime > 0) {  // both roots in front: near C/q ≤ far q/a
        const T near = C / q;
        if (near >= tmax) return {};
        if (near > tmin) return found(near);
        const T far = q / a;
        return inside(far) ? found(far) : root_pair<T>{};
    }
    if (C < 0 && tmin >= 0) {  // origin inside: the near root is behind it
        const T far = q > 0 ? q / a : C / q;  // the positive one of q/a, C/q
        return inside(far) ? found(far) : root_pair<T>{};
    }
    T t0 = C / q, t1 = q / a;
    if (t0 > t1) std::swap(t0, t1);
    if (inside(t0)) return found(t0);
    if (inside(t1)) return found(t1);
    return {};
}

template <class T>
root_pair<T> hearn_baker_nearest(const ray_sphere<T>& s, T tmin = T(0),
                                 T tmax = std::numeric_limits<T>::infinity()) {
    const vec3<T> f = step("f", s.origin - s.centre);
    const T a = step("a", dot(s.direction, s.direction));
    const T b_prime = step("b′", -dot(f, s.direction));
    const T C = step("C", dot(f, f) - s.radius * s.radius);
    if (C > 0 && b_prime < 0 && tmin >= 0) return {};

    // Discriminant from the perpendicular vector (RTG eq. 7.5).
    const vec3<T> l = step("l", f + (b_prime / a) * s.direction);
    const T discriminant = step("Δ", s.radius * s.radius - dot(l, l));
    if (discriminant < 0) return {};

    // Stable roots (RTG eq. 7.8).
    const T q = step("q", b_prime + copysign(sqrt(a * discriminant), b_prime));
    return nearest_stable_root(a, b_prime, C, q, tmin, tmax);
}

}  // namespace rayverify::intersectors
