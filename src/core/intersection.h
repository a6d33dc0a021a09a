// What a floating-point intersector returns, and the contract it states.
#pragma once

#include <limits>
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
    // Is there a root in the open interval (tmin, tmax)? The variant takes the
    // interval (variant::run_*_in; without one it answers for (0, +inf)).
    // count: 0 no root in the interval, 1 some root in it; t0 and t1 unused.
    any_hit_in_interval,
    // The nearest root in the open interval (tmin, tmax), taken like
    // any_hit_in_interval. count: 0 none, 1 the root in t0 (t1 unused).
    nearest_in_interval,
};

constexpr const char* query_kind_name(query_kind k) {
    switch (k) {
        case query_kind::line_roots: return "line_roots";
        case query_kind::nearest_on_ray: return "nearest_on_ray";
        case query_kind::any_hit_in_interval: return "any_hit_in_interval";
        case query_kind::nearest_in_interval: return "nearest_in_interval";
    }
    return "?";
}

// The kind named `name` (as query_kind_name spells it); line_roots for an unknown name.
constexpr query_kind query_kind_from_name(std::string_view name) {
    for (query_kind k : {query_kind::nearest_on_ray, query_kind::any_hit_in_interval, query_kind::nearest_in_interval})
        if (name == query_kind_name(k)) return k;
    return query_kind::line_roots;
}

// True for the kinds that take the ray's interval (tmin, tmax).
constexpr bool takes_interval(query_kind k) {
    return k == query_kind::any_hit_in_interval || k == query_kind::nearest_in_interval;
}

// The interval a ray takes roots in, open at both ends: tmin < t < tmax.
// A case without an interval is asked for (0, +inf): the ray in front of its
// origin, a root exactly at the origin excluded (a renderer's self-hit).
template <class T>
struct ray_interval {
    T tmin = T(0);
    T tmax = std::numeric_limits<T>::infinity();
    constexpr bool contains(T t) const { return t > tmin && t < tmax; }
};

// What a renderer asks of a ray–sphere test (a scene names one per ray kind):
// any_hit: is there a root in the ray's interval (a shadow ray); nearest_hit:
// the nearest root in the interval; both_roots: the near and far roots;
// hit_point_normal: the nearest root, its hit point o + t·d and the normal there.
enum class ray_query { any_hit, nearest_hit, both_roots, hit_point_normal };

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
