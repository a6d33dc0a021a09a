// What a floating-point intersector returns. What it promises is its contract
// (core/contract.h).
#pragma once

#include <limits>

#include "core/contract.h"

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

// A miss is a value: count == 0. Roots are only meaningful for count > 0.
template <class T>
struct root_pair {
    int count = 0;
    T t0{};
    T t1{};
};

}  // namespace rayverify
