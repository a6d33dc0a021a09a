// What a floating-point intersector returns, and the contract it states.
#pragma once

#include <string_view>

namespace rayverify {

// Which answer an intersector gives.
enum class query_kind {
    // Both roots of the line o + t·d (t of any sign), ordered t0 ≤ t1.
    // count: 0 miss, 1 tangent reported, 2 two roots. Whatever the count, t0
    // and t1 are the variant's near and far roots (equal for most variants
    // when they report a tangent) and both are judged.
    line_roots,
    // The nearest hit on the closed ray t ≥ 0. count: 0 miss, 1 hit with
    // distance t0 (t1 unused). A variant that clamps returns t0 = 0 when the
    // origin is inside the sphere.
    nearest_on_ray,
};

// A miss is a value: count == 0. Roots are only meaningful for count > 0.
template <class T>
struct root_pair {
    int count = 0;
    T t0{};
    T t1{};
};

// What an intersector promises and assumes, stated next to its formula.
struct contract {
    query_kind query = query_kind::line_roots;
    bool assumes_unit_direction = false;  // a = d·d is taken to be 1
    bool reports_tangent = false;         // may return count 1 for a tangent line
    bool clamps_to_zero = false;          // nearest_on_ray: t < 0 is returned as 0
    std::string_view tangent_rule = "never";  // when it reports a tangent, e.g. "Δ ≤ 1e-7"
};

}  // namespace rayverify
