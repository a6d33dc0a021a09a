/* Template: does anything block the ray in (t_min, t_max)? The shadow-ray (or
 * occlusion) query: a yes or no, no distance. The body tests whether either
 * root of the textbook quadratic lies in the open interval. Replace the body
 * with your own; keep the contract.
 *
 * Build:  cc -O2 -shared -fPIC -I <rayverify>/src/plugin any_hit.c -o libmine.so -lm
 * Audit:  rayverify audit --plugin ./libmine.so */
#include <math.h>

#include "rayverify_plugin.h"

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

RAYVERIFY_PLUGIN_EXPORT const rayverify_plugin_info* rayverify_plugin_describe(void) {
    static const rayverify_plugin_info info = {
        RAYVERIFY_PLUGIN_ABI_VERSION,
        "occluded_sphere",
        "textbook quadratic as an occlusion test",
        "b' = d.f, disc = b'^2 - a C, hit when (-b' -+ sqrt(disc))/a lies in (t_min, t_max)",
        RAYVERIFY_ANY_HIT_IN_INTERVAL, /* count 1 when some root lies in (tmin, tmax); roots unused */
        0,                             /* any direction length */
        0,                             /* unused by ANY_HIT_IN_INTERVAL */
        0,                             /* unused by ANY_HIT_IN_INTERVAL */
        NULL};
    return &info;
}

RAYVERIFY_PLUGIN_EXPORT int rayverify_plugin_intersect_double(const double o[3], const double d[3],
                                                              const double c[3], double r, double tmin,
                                                              double tmax, double roots[2]) {
    const double f[3] = {o[0] - c[0], o[1] - c[1], o[2] - c[2]};
    const double a = dot3(d, d);
    const double b = dot3(d, f);
    const double C = dot3(f, f) - r * r;
    const double discriminant = b * b - a * C;
    (void)roots; /* an any-hit answer is its count */
    if (discriminant < 0) return 0;
    const double sqrtd = sqrt(discriminant);
    const double t0 = (-b - sqrtd) / a, t1 = (-b + sqrtd) / a;
    return (tmin < t0 && t0 < tmax) || (tmin < t1 && t1 < tmax);
}
