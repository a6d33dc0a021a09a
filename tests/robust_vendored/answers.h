// One case's answers from robust_sphere.h as a line of text, shared by the
// vendored build (main.cpp) and robust_sphere_test, which compares the two.
#pragma once

#include <cstdio>
#include <string>

#include "robust_sphere.h"

// v: ox oy oz dx dy dz cx cy cz r tmin tmax, every value representable in T.
template <class T>
std::string robust_answers(const double (&v)[12]) {
    namespace rs = robust_sphere;
    const rs::ray<T> r{{T(v[0]), T(v[1]), T(v[2])}, {T(v[3]), T(v[4]), T(v[5])}};
    const rs::sphere<T> s{{T(v[6]), T(v[7]), T(v[8])}, T(v[9])};
    const T tmin = T(v[10]), tmax = T(v[11]);
    const rs::line_roots<T> line = rs::intersect_line(r, s);
    const rs::ray_hit<T> open = rs::nearest_hit(r, s, tmin, tmax);
    const rs::ray_hit<T> closed = rs::nearest_hit<rs::ends::closed, rs::ends::closed>(r, s, tmin, tmax);
    const bool any = rs::any_hit(r, s, tmin, tmax);
    char text[256];
    std::snprintf(text, sizeof text, "%d %a %a %d %a %d %d %a %d %d", line.count, double(line.t0), double(line.t1),
                  open.found, double(open.t), int(open.which), closed.found, double(closed.t), int(closed.which),
                  any);
    return text;
}
