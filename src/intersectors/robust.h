// robust — rayverify's own intersector (robust_sphere.h), in the registry's
// shape: three query levels, each the same exact decisions.
//
//   f = o − c,  a = d·d,  b′ = d·f,  C = f·f − r²,  Δ′ = a·r² − |d × f|²
//   class from the exact sign of Δ′, root signs from those of C and b′,
//   roots q/a and C/q with q = −(b′ + sign(b′)√Δ′), rounded to nearest:
//   a certified double (float) or double-word (double) fast path, and exact
//   expansion arithmetic where its bounds do not decide.
//
// Contracts: robust — both roots of the line, a tangent (count 1) exactly
// when Δ′ = 0; robust_nearest — the nearest root in the open interval
// (tmin, tmax); robust_any_hit — is there a root in (tmin, tmax). Any
// direction length, no clamp. robust_sphere.h also answers closed ends
// (ends::closed); the registry's interval kinds are open at both ends.
// robust_bounded and robust_bounded_nearest are the same queries in the
// bounded tier (roots::bounded): the same exact decisions, double roots
// within 2^-44 relative instead of correctly rounded (float: the same).
// Known failure: none intended; the audit, hunts and tests look for one.
#pragma once

#include <limits>

#include "core/intersection.h"
#include "core/ray_sphere_case.h"
#include "intersectors/robust_sphere.h"

namespace rayverify::intersectors {

inline constexpr contract robust_contract{
    .query = query_kind::line_roots, .reports_tangent = true, .tangent_rule = "Δ′ == 0 (exact)"};
inline constexpr contract robust_nearest_contract{.query = query_kind::nearest_hit, .range = range_source::interval};
inline constexpr contract robust_any_hit_contract{.query = query_kind::any_hit, .range = range_source::interval};
inline constexpr contract robust_bounded_contract = robust_contract;
inline constexpr contract robust_bounded_nearest_contract = robust_nearest_contract;

template <class T>
robust_sphere::ray<T> robust_ray(const ray_sphere<T>& s) {
    return {{s.origin.x, s.origin.y, s.origin.z}, {s.direction.x, s.direction.y, s.direction.z}};
}

template <class T>
robust_sphere::sphere<T> robust_target(const ray_sphere<T>& s) {
    return {{s.centre.x, s.centre.y, s.centre.z}, s.radius};
}

template <class T>
    requires robust_sphere::detail::supported<T>
root_pair<T> robust(const ray_sphere<T>& s) {
    const robust_sphere::line_roots<T> r = robust_sphere::intersect_line(robust_ray(s), robust_target(s));
    return {r.count, r.t0, r.t1};
}

template <class T>
    requires robust_sphere::detail::supported<T>
root_pair<T> robust_nearest(const ray_sphere<T>& s, T tmin = T(0), T tmax = std::numeric_limits<T>::infinity()) {
    const robust_sphere::ray_hit<T> h = robust_sphere::nearest_hit(robust_ray(s), robust_target(s), tmin, tmax);
    return h.found ? root_pair<T>{1, h.t, h.t} : root_pair<T>{};
}

template <class T>
    requires robust_sphere::detail::supported<T>
root_pair<T> robust_bounded(const ray_sphere<T>& s) {
    const robust_sphere::line_roots<T> r =
        robust_sphere::intersect_line<robust_sphere::roots::bounded>(robust_ray(s), robust_target(s));
    return {r.count, r.t0, r.t1};
}

template <class T>
    requires robust_sphere::detail::supported<T>
root_pair<T> robust_bounded_nearest(const ray_sphere<T>& s, T tmin = T(0),
                                    T tmax = std::numeric_limits<T>::infinity()) {
    using robust_sphere::ends;
    const robust_sphere::ray_hit<T> h = robust_sphere::nearest_hit<ends::open, ends::open, robust_sphere::roots::bounded>(
        robust_ray(s), robust_target(s), tmin, tmax);
    return h.found ? root_pair<T>{1, h.t, h.t} : root_pair<T>{};
}

template <class T>
    requires robust_sphere::detail::supported<T>
root_pair<T> robust_any_hit(const ray_sphere<T>& s, T tmin = T(0), T tmax = std::numeric_limits<T>::infinity()) {
    return robust_sphere::any_hit(robust_ray(s), robust_target(s), tmin, tmax) ? root_pair<T>{1, 0, 0}
                                                                               : root_pair<T>{};
}

}  // namespace rayverify::intersectors
