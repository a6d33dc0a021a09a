/* A user's ray–sphere intersector as a rayverify plugin: the Ray Tracing Gems
 * ch.7 final form (Haines, Günther, Akenine-Möller, "Precision Improvements
 * for Ray/Sphere Intersection"), written the way it sits in a renderer.
 *
 * Build:  cc -O2 -shared -fPIC -I <rayverify>/src/plugin rtg_sphere.c -o librtg_sphere.so
 * Audit:  rayverify audit --plugin ./librtg_sphere.so */
#include <math.h>

#include "rayverify_plugin.h"

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

RAYVERIFY_PLUGIN_EXPORT const rayverify_plugin_info* rayverify_plugin_describe(void) {
    static const rayverify_plugin_info info = {
        RAYVERIFY_PLUGIN_ABI_VERSION,
        "rtg_sphere",
        "Ray Tracing Gems ch.7 final form, as a plugin",
        "b' = -f.d, disc = r^2 - |f + (b'/a)d|^2, q = b' + sign(b')sqrt(a disc), t = C/q, q/a",
        RAYVERIFY_LINE_ROOTS,
        0,         /* any direction length */
        1,         /* reports a tangent */
        0,         /* no clamp */
        "disc == 0"};
    return &info;
}

RAYVERIFY_PLUGIN_EXPORT int rayverify_plugin_intersect_double(const double o[3], const double d[3],
                                                              const double c[3], double r, double tmin,
                                                              double tmax, double roots[2]) {
    const double f[3] = {o[0] - c[0], o[1] - c[1], o[2] - c[2]};
    const double a = dot3(d, d);
    const double b = -dot3(f, d);
    const double C = dot3(f, f) - r * r;
    (void)tmin; /* both roots of the line are returned; rayverify judges them all */
    (void)tmax;

    /* Discriminant from the vector perpendicular to d (RTG eq. 7.5): no b^2 - aC cancellation. */
    const double s = b / a;
    const double l[3] = {f[0] + s * d[0], f[1] + s * d[1], f[2] + s * d[2]};
    const double disc = r * r - dot3(l, l);
    if (disc < 0) return 0;

    /* Stable roots (RTG eq. 7.8): never subtract nearly equal numbers. */
    const double q = b + copysign(sqrt(a * disc), b);
    double t0 = C / q, t1 = q / a;
    if (t0 > t1) {
        const double swap = t0;
        t0 = t1;
        t1 = swap;
    }
    roots[0] = t0;
    roots[1] = t1;
    return disc == 0 ? 1 : 2;
}
