/* A nearest-hit intersector on the ray's own interval, with its normal: the
 * closest-approach test of Embree and Cycles, both faces, written as a
 * renderer's C code would. Version 2 of the plugin ABI.
 *
 *   rd2 = 1/(d·d), c0 = c − o, p = (c0·d)·rd2, perp = c0 − p·d, l2 = perp·perp
 *   miss unless l2 ≤ r²;  h = √((r² − l2)·rd2);  t = p − h, else p + h, first in [tmin, tmax]
 *   normal = (o + t·d) − c
 *
 * Contract: query=nearest_hit,range=interval,ends=[] (both ends closed), the far
 * root from inside, a tangent a hit, any direction length; also the normal.
 * Runs in float and in double. */
#include <math.h>

#include "rayverify_plugin.h"

RAYVERIFY_PLUGIN_EXPORT const rayverify_plugin_info_v2* rayverify_plugin_describe_v2(void) {
    static const rayverify_plugin_info_v2 info = {
        RAYVERIFY_PLUGIN_ABI_VERSION_2,
        "nearest_sphere",
        "closest approach, as Embree 4 and Cycles (examples/plugin_v2/nearest_sphere.c)",
        "p = (c - o).d / d.d, perp = (c - o) - p d, h = sqrt((r^2 - perp.perp) / d.d), t = p -+ h",
        "plain C, no FMA contraction",
        "query=nearest_hit,range=interval,ends=[],normal=yes",
        NULL,
        RAYVERIFY_FLOAT | RAYVERIFY_DOUBLE};
    return &info;
}

#define NEAREST_BODY(T, SQRT)                                                                        \
    for (size_t i = 0; i < n; ++i) {                                                                 \
        const T* o = cases[i].origin;                                                                \
        const T* d = cases[i].direction;                                                             \
        const T* c = cases[i].centre;                                                                \
        const T r = cases[i].radius;                                                                 \
        const T rd2 = (T)1 / (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);                              \
        const T c0[3] = {c[0] - o[0], c[1] - o[1], c[2] - o[2]};                                     \
        const T p = (c0[0] * d[0] + c0[1] * d[1] + c0[2] * d[2]) * rd2;                              \
        const T perp[3] = {c0[0] - p * d[0], c0[1] - p * d[1], c0[2] - p * d[2]};                    \
        const T l2 = perp[0] * perp[0] + perp[1] * perp[1] + perp[2] * perp[2];                      \
        answers[i].count = 0;                                                                        \
        if (!(l2 <= r * r)) continue;                                                                \
        {                                                                                            \
            const T h = SQRT((r * r - l2) * rd2);                                                    \
            const T front = p - h, back = p + h;                                                     \
            T t;                                                                                     \
            int k;                                                                                   \
            if (cases[i].tmin <= front && front <= cases[i].tmax)                                    \
                t = front;                                                                           \
            else if (cases[i].tmin <= back && back <= cases[i].tmax)                                 \
                t = back;                                                                            \
            else                                                                                     \
                continue;                                                                            \
            answers[i].count = 1;                                                                    \
            answers[i].t[0] = answers[i].t[1] = t;                                                   \
            for (k = 0; k < 3; ++k) answers[i].normal[k] = (o[k] + t * d[k]) - c[k];                 \
        }                                                                                            \
    }

RAYVERIFY_PLUGIN_EXPORT void rayverify_plugin_intersect_batch_double(const rayverify_case_double* cases,
                                                                     rayverify_answer_double* answers, size_t n) {
    NEAREST_BODY(double, sqrt)
}

RAYVERIFY_PLUGIN_EXPORT void rayverify_plugin_intersect_batch_float(const rayverify_case_float* cases,
                                                                    rayverify_answer_float* answers, size_t n) {
    NEAREST_BODY(float, sqrtf)
}
