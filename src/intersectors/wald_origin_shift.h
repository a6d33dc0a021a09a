// wald_origin_shift — the textbook quadratic (naive.h) after the origin shift
// of Ingo Wald, "Improving Numerical Precision in Intersection Programs",
// Ray Tracing Gems II (2021), ch. 34: intersect from a point near the
// object, where the quadratic's coefficients are small, and add the shift
// back. The chapter's idea, in the form written here (its code is not
// reproduced; this is the shift to the point of the line nearest the centre):
//
//   t_s = ((c − o)·d) / (d·d),  o′ = o + t_s·d
//   f = o′ − c,  a = d·d,  b = 2 d·f,  C = f·f − r²,  Δ = b² − 4aC
//   Δ < 0: miss;  Δ = 0: tangent, t = t_s + (−b/2a);  Δ > 0: t = t_s + (−b ∓ √Δ)/2a
//
// After the shift |f| is about the line's distance to the centre, so C keeps
// r² (naive's far-sphere failure is gone) and b ≈ 0; what remains is the
// rounding of o′ itself (relative to |o| + |t_s·d|) and of t_s + t′.
//
// Contract: any direction length; both roots of the line, ordered, negative
// roots included; reports a tangent when Δ == 0; no clamp.
#pragma once

#include <cmath>

#include "core/intersection.h"
#include "core/ray_sphere_case.h"
#include "intersectors/scalar_math.h"

namespace rayverify::intersectors {

inline constexpr contract wald_origin_shift_contract{
    .query = query_kind::line_roots, .reports_tangent = true, .tangent_rule = "Δ == 0 after the shift"};

template <class T>
root_pair<T> wald_origin_shift(const ray_sphere<T>& s) {
    // Shift the origin to the point of the line nearest the centre.
    const T a = step("a", dot(s.direction, s.direction));
    const T t_shift = step("t_s", dot(s.centre - s.origin, s.direction) / a);
    const vec3<T> shifted = s.origin + t_shift * s.direction;

    // The textbook quadratic from there.
    const vec3<T> f = step("f", shifted - s.centre);
    const T b = step("b", T(2) * dot(s.direction, f));
    const T C = step("C", dot(f, f) - s.radius * s.radius);
    const T discriminant = step("Δ", b * b - T(4) * a * C);
    if (discriminant < 0) return {};
    if (discriminant == 0) {
        const T t = t_shift + -b / (T(2) * a);
        return {1, t, t};
    }
    const T root = step("√Δ", sqrt(discriminant));
    return {2, t_shift + (-b - root) / (T(2) * a), t_shift + (-b + root) / (T(2) * a)};
}

}  // namespace rayverify::intersectors
