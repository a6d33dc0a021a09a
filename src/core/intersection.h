// What a floating-point intersector returns. What it promises is its contract
// (core/contract.h).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <string_view>

#include "core/contract.h"
#include "core/double_word.h"
#include "core/ray_sphere_case.h"

namespace rayverify {

// The bounds an interval variant is called with, in its own precision: a
// case without an interval is asked for (0, +inf).
template <class T>
struct ray_interval {
    T tmin = T(0);
    T tmax = std::numeric_limits<T>::infinity();
};

// What a renderer asks of a ray–sphere test (a scene names one per ray kind):
// any_hit: is there a root in the ray's interval (a shadow ray); nearest_hit:
// the nearest root in the interval; both_roots: the near and far roots;
// hit_point_normal: the nearest root, its hit point o + t·d and the normal there.
enum class ray_query { any_hit, nearest_hit, both_roots, hit_point_normal };
inline constexpr std::array every_ray_query{ray_query::any_hit, ray_query::nearest_hit, ray_query::both_roots,
                                            ray_query::hit_point_normal};

// The one spelling of each query (scene files, reports, messages).
constexpr const char* ray_query_name(ray_query q) {
    switch (q) {
        case ray_query::any_hit: return "any_hit";
        case ray_query::nearest_hit: return "nearest_hit";
        case ray_query::both_roots: return "both_roots";
        case ray_query::hit_point_normal: return "hit_point_normal";
    }
    return "?";
}

// The query named `name`; nullopt for any other name.
constexpr std::optional<ray_query> ray_query_from_name(std::string_view name) {
    for (const ray_query q : every_ray_query)
        if (name == ray_query_name(q)) return q;
    return std::nullopt;
}

// What a query asks beyond hit or miss, and so which figures judge and report
// it: the one place that says so (the scene audit, its tables and report, and
// bench's recommend read it).
struct query_requirements {
    bool first_hit_answers = false;  // any_hit: the first hit found answers the ray; no root is measured
    bool nearest_root = false;       // the nearest root's t, measured in ULPs
    bool far_root = false;           // the far root's t too (both_roots: the near root is the "nearest")
    bool hit_point = false;          // the nearest hit point (and its normal), measured in ULPs
};

constexpr query_requirements query_needs(ray_query q) {
    query_requirements needs;
    needs.first_hit_answers = q == ray_query::any_hit;
    needs.nearest_root = q != ray_query::any_hit;
    needs.far_root = q == ray_query::both_roots;
    needs.hit_point = q == ray_query::hit_point_normal;
    return needs;
}

// A miss is a value: count == 0. Roots are only meaningful for count > 0.
template <class T>
struct root_pair {
    int count = 0;
    T t0{};
    T t1{};
};

// A variant's whole answer: its roots and the optional outputs its contract
// names (contract::outputs); members it does not give are left as they are.
// For an answer=point variant, roots.t0 = roots.t1 is the t derived from
// `point` (parameter_of_point).
template <class T>
struct answer {
    root_pair<T> roots;
    std::array<T, 2> t_lower{}, t_upper{};  // t_bounds: root i of the answer lies in [t_lower[i], t_upper[i]]
    vec3<T> point{};                        // hit_point: the hit point the variant computes, at its hit
    vec3<T> point_error{};                  // point_error: |p*_k − point_k| ≤ point_error_k per coordinate
    vec3<T> normal{};                       // normal: at its hit, any length
};

// The t a returned point stands for: the parameter of its projection on the
// line, (p − o)·d / (d·d), evaluated in double-word arithmetic and rounded
// once to T (the differences p − o are exact, the sums and the quotient
// carry errors of order 2^-100 relative). Reported beside the point and
// judged like a returned t.
template <class T>
T parameter_of_point(const ray_sphere<T>& s, vec3<T> p) {
    dword along{}, length2{};
    for (int axis = 0; axis < 3; ++axis) {
        const double dk = static_cast<double>(s.direction[axis]);
        const dword offset = two_sum(static_cast<double>(p[axis]), -static_cast<double>(s.origin[axis]));
        along = along + offset * dword{dk, 0};
        length2 = length2 + two_prod(dk, dk);
    }
    return static_cast<T>(dw_value(along / length2));
}

// The length L a segment variant gets for a ray without tmax: a power of two
// with L·|d| ≥ 2(|o − c| + r) > every |t*|·|d| (a root's point lies on the
// sphere, so |t*|·|d| ≤ |o − c| + r), from |o − c|₁ + r over |d|∞ with a
// factor 2 to spare. Scaling d by L is exact, so a fraction f of the segment
// is the root t = f·L exactly. Capped where L·|d|∞ would pass a quarter of
// T's largest value (the segment may then stop short of a far root; only
// inputs near T's overflow threshold reach the cap).
template <class T>
T segment_length(const ray_sphere<T>& s) {
    double extent = static_cast<double>(s.radius), reach = 0;
    for (int axis = 0; axis < 3; ++axis) {
        extent += std::fabs(static_cast<double>(s.origin[axis]) - static_cast<double>(s.centre[axis]));
        reach = std::max(reach, std::fabs(static_cast<double>(s.direction[axis])));
    }
    if (!(extent > 0) || !(reach > 0) || !std::isfinite(extent / reach)) return T(1);
    const int wanted = std::ilogb(extent / reach) + 2;
    const int cap = std::ilogb(static_cast<double>(std::numeric_limits<T>::max()) / 4) - std::ilogb(reach) - 1;
    return static_cast<T>(std::ldexp(1.0, std::min(wanted, cap)));
}

}  // namespace rayverify
