/* Template: the nearest hit in the ray's interval (t_min, t_max), the question
 * a path tracer asks of every object. The body is the sphere of "Ray Tracing in
 * One Weekend" (Shirley, Black, Hollasch, v4.0, sphere.h `hit`): half-b,
 * h = d·(c − o), the near root first, the far one when the near one is outside
 * (t_min, t_max). Replace the body with your own; keep the contract.
 *
 * Build:  cc -O2 -shared -fPIC -I <rayverify>/src/plugin nearest_in_interval.c -o libmine.so -lm
 * Audit:  rayverify audit --plugin ./libmine.so */
#include <math.h>

#include "rayverify_plugin.h"

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

RAYVERIFY_PLUGIN_EXPORT const rayverify_plugin_info* rayverify_plugin_describe(void) {
    static const rayverify_plugin_info info = {
        RAYVERIFY_PLUGIN_ABI_VERSION,
        "rtiow_sphere",
        "Ray Tracing in One Weekend v4.0, sphere::hit",
        "h = d.(c-o), disc = h^2 - a C, t = (h - sqrt(disc))/a, else (h + sqrt(disc))/a, in (t_min, t_max)",
        RAYVERIFY_NEAREST_IN_INTERVAL, /* roots[0]: the nearest root in the open interval (tmin, tmax) */
        0,                             /* any direction length */
        0,                             /* unused by NEAREST_IN_INTERVAL */
        0,                             /* unused by NEAREST_IN_INTERVAL */
        NULL};
    return &info;
}

/* This body keeps no state: rayverify may call it from every thread. */
RAYVERIFY_PLUGIN_EXPORT int rayverify_plugin_thread_safe(void) { return 1; }

RAYVERIFY_PLUGIN_EXPORT int rayverify_plugin_intersect_double(const double o[3], const double d[3],
                                                              const double c[3], double r, double tmin,
                                                              double tmax, double roots[2]) {
    const double oc[3] = {c[0] - o[0], c[1] - o[1], c[2] - o[2]};
    const double a = dot3(d, d);
    const double h = dot3(d, oc);
    const double C = dot3(oc, oc) - r * r;

    /* Reduced discriminant: h^2 - aC cancels for far spheres and near tangents. */
    const double discriminant = h * h - a * C;
    if (discriminant < 0) return 0;
    const double sqrtd = sqrt(discriminant);

    /* The nearest root that lies in the open interval: interval::surrounds. */
    double root = (h - sqrtd) / a;
    if (!(tmin < root && root < tmax)) {
        root = (h + sqrtd) / a;
        if (!(tmin < root && root < tmax)) return 0;
    }
    roots[0] = root;
    return 1;
}
