// robust_sphere.h inside CUDA kernels, as a user vendors it: every query in
// float and double, both tiers, open and closed ends, and the hit point. Built
// by clang in CUDA mode for a GPU with no CUDA SDK (tests/CMakeLists.txt):
// without the SDK's headers nothing defines __global__ or threadIdx, so the
// kernel spells them as clang does; robust_sphere.h needs neither.
#define __global__ __attribute__((global))
#include "robust_sphere.h"

namespace rs = robust_sphere;

template <class T>
struct answers {
    rs::line_roots<T> line, bounded_line;
    rs::ray_hit<T> nearest, nearest_closed, bounded_nearest;
    bool any;
    rs::surface_point<T> point;
};

template <class T>
__global__ void intersect_all(const rs::ray<T>* rays, const rs::sphere<T>* spheres, const T* tmin, const T* tmax,
                              answers<T>* out, int n) {
    const int i = static_cast<int>(__nvvm_read_ptx_sreg_ctaid_x() * __nvvm_read_ptx_sreg_ntid_x() +
                                   __nvvm_read_ptx_sreg_tid_x());
    if (i >= n) return;
    using rs::ends;
    answers<T>& a = out[i];
    a.line = rs::intersect_line(rays[i], spheres[i]);
    a.bounded_line = rs::intersect_line<rs::roots::bounded>(rays[i], spheres[i]);
    a.nearest = rs::nearest_hit(rays[i], spheres[i], tmin[i], tmax[i]);
    a.nearest_closed = rs::nearest_hit<ends::closed, ends::open>(rays[i], spheres[i], tmin[i], tmax[i]);
    a.bounded_nearest = rs::nearest_hit<ends::open, ends::open, rs::roots::bounded>(rays[i], spheres[i], tmin[i], tmax[i]);
    a.any = rs::any_hit(rays[i], spheres[i], tmin[i], tmax[i]);
    a.point = rs::hit_point(rays[i], spheres[i], a.nearest.t, true);
}

template __global__ void intersect_all<float>(const rs::ray<float>*, const rs::sphere<float>*, const float*,
                                              const float*, answers<float>*, int);
template __global__ void intersect_all<double>(const rs::ray<double>*, const rs::sphere<double>*, const double*,
                                               const double*, answers<double>*, int);
