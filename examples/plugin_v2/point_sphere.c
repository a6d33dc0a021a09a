/* An intersector that answers with a point, as three.js, raylib and Godot do:
 * the nearest hit point on the ray, from the geometric test for a unit
 * direction, in double only. Version 2 of the plugin ABI; rayverify judges the
 * point as a point (ULPs per coordinate) and derives its t.
 *
 *   v = c − o, tca = v·d, d2 = v·v − tca², miss when d2 > r²
 *   thc = √(r² − d2), t = tca − thc, or tca + thc from inside; miss when both < 0
 *   point = o + d·t
 *
 * Contract: query=nearest_hit,range=ray,ends=[) (t ≥ 0), unit_direction=yes,
 * answer=point. */
#include <math.h>

#include "rayverify_plugin.h"

RAYVERIFY_PLUGIN_EXPORT const rayverify_plugin_info_v2* rayverify_plugin_describe_v2(void) {
    static const rayverify_plugin_info_v2 info = {
        RAYVERIFY_PLUGIN_ABI_VERSION_2,
        "point_sphere",
        "three.js Ray.intersectSphere, in C (examples/plugin_v2/point_sphere.c)",
        "tca = (c - o).d, d2 = |c - o|^2 - tca^2, point o + d (tca -+ sqrt(r^2 - d2))",
        "double only; plain C, no FMA contraction",
        "query=nearest_hit,range=ray,ends=[),unit_direction=yes,answer=point",
        NULL,
        RAYVERIFY_DOUBLE};
    return &info;
}

RAYVERIFY_PLUGIN_EXPORT void rayverify_plugin_intersect_batch_double(const rayverify_case_double* cases,
                                                                     rayverify_answer_double* answers, size_t n) {
    for (size_t i = 0; i < n; ++i) {
        const double* o = cases[i].origin;
        const double* d = cases[i].direction;
        const double* c = cases[i].centre;
        const double r = cases[i].radius;
        const double v[3] = {c[0] - o[0], c[1] - o[1], c[2] - o[2]};
        const double tca = v[0] * d[0] + v[1] * d[1] + v[2] * d[2];
        const double d2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2] - tca * tca;
        answers[i].count = 0;
        if (d2 > r * r) continue;
        {
            const double thc = sqrt(r * r - d2);
            const double t0 = tca - thc, t1 = tca + thc;
            const double t = t0 < 0 ? t1 : t0;
            int k;
            if (t1 < 0) continue;
            answers[i].count = 1;
            for (k = 0; k < 3; ++k) answers[i].point[k] = o[k] + d[k] * t;
        }
    }
}
