// Glue shared by the native engine plugins (engines/native/): how a case's
// range becomes what a library takes (a segment's end points, a ray length),
// and a version string kept for the life of the library. Nothing here
// computes an intersection: each plugin calls its library for that.
#pragma once

#include <cmath>
#include <limits>

#include "core/intersection.h"  // segment_length: the engines' convention for a segment without tmax

namespace rayverify_native {

// The length L rayverify's own segment engines use for a case without tmax:
// a power of two with L·|d|∞ ≥ 2(|o − c|₁ + r), past every root of the line
// (rayverify::segment_length in core/intersection.h, the same function).
template <class T>
T segment_length(const T o[3], const T d[3], const T c[3], T r) {
    rayverify::ray_sphere<T> s;
    s.origin = {o[0], o[1], o[2]};
    s.direction = {d[0], d[1], d[2]};
    s.centre = {c[0], c[1], c[2]};
    s.radius = r;
    return rayverify::segment_length(s);
}

// The point o + t·d in the library's precision P, one rounding per
// coordinate; o itself when t = 0 (no rounding at all), o + L·d for t = +inf.
template <class P, class T>
void point_at(const T o[3], const T d[3], T t, P out[3]) {
    for (int k = 0; k < 3; ++k)
        out[k] = t == T(0) ? static_cast<P>(o[k]) : static_cast<P>(static_cast<P>(o[k]) + static_cast<P>(t) * static_cast<P>(d[k]));
}

// The segment a case's (tmin, tmax) stands for, in the library's precision
// P: from = o + tmin·d, to = o + tmax·d, with tmax = +inf replaced by the
// segment length L above. `far` is the t the segment's end stands for.
template <class P, class T>
void case_segment(const T o[3], const T d[3], const T c[3], T r, T tmin, T tmax, P from[3], P to[3], T& far) {
    far = std::isinf(tmax) && tmax > 0 ? segment_length(o, d, c, r) : tmax;
    point_at<P>(o, d, tmin, from);
    point_at<P>(o, d, far, to);
}

}  // namespace rayverify_native
