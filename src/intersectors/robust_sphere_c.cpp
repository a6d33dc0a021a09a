// The C interface of robust_sphere.h (robust_sphere_c.h): each function is
// the header's query of the same name, its ends chosen at run time. Compile
// this file strictly as its own object (never -ffast-math: robust_sphere.h
// stops such a build with #error), whatever the rest of the project uses.
#include "robust_sphere_c.h"

#include "robust_sphere.h"

namespace {

namespace rs = robust_sphere;

template <class T>
rs::ray<T> ray_of(const T origin[3], const T direction[3]) {
    return {{origin[0], origin[1], origin[2]}, {direction[0], direction[1], direction[2]}};
}

template <class T>
rs::sphere<T> sphere_of(const T centre[3], T radius) {
    return {{centre[0], centre[1], centre[2]}, radius};
}

template <class T>
int line_roots(const T origin[3], const T direction[3], const T centre[3], T radius, T t[2]) {
    const rs::line_roots<T> roots = rs::intersect_line(ray_of(origin, direction), sphere_of(centre, radius));
    if (roots.count > 0) t[0] = roots.t0, t[1] = roots.t1;
    return roots.count;
}

// A query's four instantiations, one for each pair of ends.
template <class T, class Query>
auto with_ends(robust_sphere_end lower, robust_sphere_end upper, Query query) {
    using rs::ends;
    if (lower == ROBUST_SPHERE_CLOSED)
        return upper == ROBUST_SPHERE_CLOSED ? query.template operator()<ends::closed, ends::closed>()
                                             : query.template operator()<ends::closed, ends::open>();
    return upper == ROBUST_SPHERE_CLOSED ? query.template operator()<ends::open, ends::closed>()
                                         : query.template operator()<ends::open, ends::open>();
}

template <class T>
struct nearest_query {
    rs::ray<T> r;
    rs::sphere<T> s;
    T tmin, tmax;
    template <rs::ends Lower, rs::ends Upper>
    rs::ray_hit<T> operator()() const {
        return rs::nearest_hit<Lower, Upper>(r, s, tmin, tmax);
    }
};

template <class T>
struct any_query {
    rs::ray<T> r;
    rs::sphere<T> s;
    T tmin, tmax;
    template <rs::ends Lower, rs::ends Upper>
    bool operator()() const {
        return rs::any_hit<Lower, Upper>(r, s, tmin, tmax);
    }
};

template <class T>
int nearest_hit(const T origin[3], const T direction[3], const T centre[3], T radius, T tmin, T tmax,
                robust_sphere_end lower, robust_sphere_end upper, T* t) {
    const rs::ray_hit<T> hit = with_ends<T>(
        lower, upper, nearest_query<T>{ray_of(origin, direction), sphere_of(centre, radius), tmin, tmax});
    if (hit.found) *t = hit.t;
    return hit.found ? 1 : 0;
}

template <class T>
int any_hit(const T origin[3], const T direction[3], const T centre[3], T radius, T tmin, T tmax,
            robust_sphere_end lower, robust_sphere_end upper) {
    return with_ends<T>(lower, upper,
                        any_query<T>{ray_of(origin, direction), sphere_of(centre, radius), tmin, tmax})
               ? 1
               : 0;
}

template <class T>
struct segment_query {
    rs::segment<T> g;
    rs::sphere<T> s;
    bool contact;
    template <rs::ends Start, rs::ends End>
    rs::ray_hit<T> operator()() const {
        return contact ? rs::segment_hit<Start, End, rs::start_inside::contact>(g, s)
                       : rs::segment_hit<Start, End, rs::start_inside::exit>(g, s);
    }
};

template <class T>
int segment_hit(const T p0[3], const T p1[3], const T centre[3], T radius, robust_sphere_end start,
                robust_sphere_end end, robust_sphere_start_inside inside, T* fraction) {
    const rs::segment<T> g{{p0[0], p0[1], p0[2]}, {p1[0], p1[1], p1[2]}};
    const rs::ray_hit<T> hit =
        with_ends<T>(start, end, segment_query<T>{g, sphere_of(centre, radius), inside == ROBUST_SPHERE_CONTACT});
    if (hit.found) *fraction = hit.t;
    return hit.found ? 1 : 0;
}

}  // namespace

extern "C" {

int robust_sphere_line_roots(const double origin[3], const double direction[3], const double centre[3],
                             double radius, double t[2]) {
    return line_roots(origin, direction, centre, radius, t);
}

int robust_sphere_line_roots_f(const float origin[3], const float direction[3], const float centre[3], float radius,
                               float t[2]) {
    return line_roots(origin, direction, centre, radius, t);
}

int robust_sphere_nearest_hit(const double origin[3], const double direction[3], const double centre[3],
                              double radius, double tmin, double tmax, robust_sphere_end lower,
                              robust_sphere_end upper, double* t) {
    return nearest_hit(origin, direction, centre, radius, tmin, tmax, lower, upper, t);
}

int robust_sphere_nearest_hit_f(const float origin[3], const float direction[3], const float centre[3], float radius,
                                float tmin, float tmax, robust_sphere_end lower, robust_sphere_end upper, float* t) {
    return nearest_hit(origin, direction, centre, radius, tmin, tmax, lower, upper, t);
}

int robust_sphere_any_hit(const double origin[3], const double direction[3], const double centre[3], double radius,
                          double tmin, double tmax, robust_sphere_end lower, robust_sphere_end upper) {
    return any_hit(origin, direction, centre, radius, tmin, tmax, lower, upper);
}

int robust_sphere_any_hit_f(const float origin[3], const float direction[3], const float centre[3], float radius,
                            float tmin, float tmax, robust_sphere_end lower, robust_sphere_end upper) {
    return any_hit(origin, direction, centre, radius, tmin, tmax, lower, upper);
}

int robust_sphere_segment_hit(const double p0[3], const double p1[3], const double centre[3], double radius,
                              robust_sphere_end start, robust_sphere_end end, robust_sphere_start_inside inside,
                              double* fraction) {
    return segment_hit(p0, p1, centre, radius, start, end, inside, fraction);
}

int robust_sphere_segment_hit_f(const float p0[3], const float p1[3], const float centre[3], float radius,
                                robust_sphere_end start, robust_sphere_end end, robust_sphere_start_inside inside,
                                float* fraction) {
    return segment_hit(p0, p1, centre, radius, start, end, inside, fraction);
}

}  // extern "C"
