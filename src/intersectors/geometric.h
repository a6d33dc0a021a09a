// geometric — the closest-approach construction of seed 000 ("there's a
// slicker route"), as used by three.js and PhysX.
//
//   L = c − o,  t_ca = L·d̂,  d² = L·L − t_ca²
//   d² > r²: miss (the early rejection, before any square root)
//   t = t_ca ∓ √(r² − d²)
//
// Contract: assumes a unit direction; both roots of the line, ordered,
// negative roots included; reports a tangent when d² == r² exactly; no clamp.
// Known failure: L·L − t_ca² cancels catastrophically for far spheres.
#pragma once

#include <cmath>

#include "core/intersection.h"
#include "core/ray_sphere_case.h"
#include "intersectors/scalar_math.h"

namespace rayverify::intersectors {

inline constexpr contract geometric_contract{.query = query_kind::line_roots,
                                             .assumes_unit_direction = true,
                                             .reports_tangent = true,
                                             .tangent_rule = "d² == r²"};

template <class T>
root_pair<T> geometric(const ray_sphere<T>& s) {
    const vec3<T> L = step("L", s.centre - s.origin);
    const T t_ca = step("t_ca", dot(L, s.direction));
    const T d2 = step("d²", dot(L, L) - t_ca * t_ca);
    const T r2 = step("r²", s.radius * s.radius);
    if (d2 > r2) return {};
    const T half_chord = step("√(r² − d²)", sqrt(step("r² − d²", r2 - d2)));
    return {d2 == r2 ? 1 : 2, t_ca - half_chord, t_ca + half_chord};
}

}  // namespace rayverify::intersectors
