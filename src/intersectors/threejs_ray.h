// threejs — three.js Ray.intersectSphere (src/math/Ray.js, mrdoob/three.js,
// the current ES-class form with the `t1 < 0` early-out; scratchapixel's
// geometric test), returning a point:
//
//   v = c − o,  tca = v·d,  d2 = v·v − tca²,  r2 = r²;  d2 > r2: null
//   thc = √(r2 − d2),  t0 = tca − thc,  t1 = tca + thc
//   t1 < 0: null;  target = at(t0 < 0 ? t1 : t0) = o + d·t  (Vector3.addScaledVector)
//
// JavaScript numbers are doubles and are never fused or reordered (the same
// on every engine and CPU), so double only; Vector3.dot is x·x′ + y·y′ + z·z′ left to right. The answer is the
// point; its t is derived (parameter_of_point) and reported beside it.
//
// Contract: assumes a unit direction (Ray.direction "must be normalized"),
// nearest hit on the closed ray t ≥ 0, the far root from inside, a tangent a
// hit; answers with the hit point.
#pragma once

#include <cmath>
#include <type_traits>

#include "core/intersection.h"
#include "core/ray_sphere_case.h"
#include "intersectors/scalar_math.h"

namespace rayverify::intersectors {

inline constexpr contract threejs_contract{.query = query_kind::nearest_hit,
                                           .range = range_source::ray,
                                           .lower_end = end_kind::closed,
                                           .assumes_unit_direction = true,
                                           .answer = answer_kind::point};

// Number: JavaScript's number, double (or a traced double, for explain).
template <class Number = double>
inline answer<Number> threejs(const ray_sphere<Number>& s, std::type_identity_t<Number> /*tmin*/,
                       std::type_identity_t<Number> /*tmax*/) {
    const vec3<Number> v = step("v", s.centre - s.origin);
    const Number tca = step("tca", dot(v, s.direction));
    const Number d2 = step("d2", dot(v, v) - tca * tca);
    const Number radius2 = step("radius2", s.radius * s.radius);
    if (d2 > radius2) return {};
    const Number thc = step("thc", sqrt(radius2 - d2));
    const Number t0 = tca - thc, t1 = tca + thc;
    if (t1 < 0) return {};
    const Number t = step("t", t0 < 0 ? t1 : t0);
    // at(t): target.copy(origin).addScaledVector(direction, t): o + d·t per coordinate.
    answer<Number> out;
    out.point = {s.origin.x + s.direction.x * t, s.origin.y + s.direction.y * t, s.origin.z + s.direction.z * t};
    step("point", out.point);
    const Number derived = parameter_of_point(s, out.point);
    out.roots = {1, derived, derived};
    return out;
}

}  // namespace rayverify::intersectors
