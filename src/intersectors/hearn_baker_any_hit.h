// hearn_baker_any_hit — the Ray Tracing Gems ch.7 final form (hearn_baker.h)
// specialised to the shadow-ray question "is there a root in (tmin, tmax)?",
// deciding from signs wherever it can and computing at most the one root the
// answer depends on.
//
//   f = o − c,  a = d·d,  b′ = −f·d,  C = f·f − r²
//   roots t with a t² − 2b′t + C = 0: product C/a, sum 2b′/a
//   C > 0, b′ < 0, tmin ≥ 0: both roots behind the origin — miss (no Δ, no √)
//   C < 0, tmin ≤ 0, tmax = +∞: origin inside, the far root is in front — hit (no Δ, no √)
//   l = f + (b′/a)·d,  Δ = r² − l·l;  Δ < 0: miss       (RTG eq. 7.5)
//   C > 0, b′ ≥ 0, tmin ≤ 0, tmax = +∞: both roots in front — hit (no √)
//   otherwise q = b′ + sign(b′)·√(aΔ), near/far roots C/q and q/a (RTG eq. 7.8),
//   computed one at a time: the near root first when both are in front, only
//   the far root when the origin is inside and tmin ≥ 0.
//
// Contract: any direction length; answers any_hit for the open interval
// (tmin, tmax) (default (0, +∞)): count 1 when some root lies in it,
// else 0; t0, t1 unused (0). Same known failures as hearn_baker (C cancels
// near the surface; b′ = 0 with Δ = 0 gives C/q = 0/0, which compares false:
// a miss).
#pragma once

#include <cmath>
#include <limits>

#include "core/intersection.h"
#include "core/ray_sphere_case.h"
#include "intersectors/scalar_math.h"

namespace rayverify::intersectors {

inline constexpr contract hearn_baker_any_hit_contract{.query = query_kind::any_hit, .range = range_source::interval};

// Is one of the roots C/q, q/a of a t² − 2b′t + C = 0 in (tmin, tmax)?
// Computes the near root first when both are in front, only the far root
// when the origin is inside and tmin ≥ 0. Shared by the unit-direction form.
template <class T>
bool any_stable_root_in(T a, T b_prime, T C, T q, T tmin, T tmax) {
    const auto inside = [&](T t) { return t > tmin && t < tmax; };
    if (C > 0 && b_prime > 0) {  // both roots in front: near C/q ≤ far q/a
        const T near = C / q;
        if (near >= tmax) return false;
        return near > tmin || inside(q / a);
    }
    if (C < 0 && tmin >= 0) {  // origin inside: only the far root can be in (tmin, tmax)
        const T far = q > 0 ? q / a : C / q;  // the positive one of q/a, C/q
        return inside(far);
    }
    return inside(C / q) || inside(q / a);
}

template <class T>
root_pair<T> hearn_baker_any_hit(const ray_sphere<T>& s, T tmin = T(0),
                                 T tmax = std::numeric_limits<T>::infinity()) {
    constexpr root_pair<T> hit{1, T(0), T(0)};
    const vec3<T> f = step("f", s.origin - s.centre);
    const T a = step("a", dot(s.direction, s.direction));
    const T b_prime = step("b′", -dot(f, s.direction));
    const T C = step("C", dot(f, f) - s.radius * s.radius);
    const bool unbounded = tmax == std::numeric_limits<T>::infinity();

    // Decide from the signs of the roots' product and sum.
    if (C > 0 && b_prime < 0 && tmin >= 0) return {};
    if (C < 0 && tmin <= 0 && unbounded) return hit;

    // Discriminant from the perpendicular vector (RTG eq. 7.5).
    const vec3<T> l = step("l", f + (b_prime / a) * s.direction);
    const T discriminant = step("Δ", s.radius * s.radius - dot(l, l));
    if (discriminant < 0) return {};
    if (C > 0 && b_prime >= 0 && tmin <= 0 && unbounded) return hit;

    // Stable roots (RTG eq. 7.8), only as many as the answer needs.
    const T q = step("q", b_prime + copysign(sqrt(a * discriminant), b_prime));
    return any_stable_root_in(a, b_prime, C, q, tmin, tmax) ? hit : root_pair<T>{};
}

}  // namespace rayverify::intersectors
