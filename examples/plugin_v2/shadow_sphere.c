/* A shadow-ray test in float only: is some root in [0, tmax]? Mitsuba 3's
 * ray_test without its double arithmetic (the quadratic with stable roots,
 * all in float), as a float-only renderer has it. Version 2 of the plugin
 * ABI, float only: rayverify audits and shows a float row alone.
 *
 *   f = o − c, A = d·d, B = 2 d·f, C = f·f − r², Δ = B² − 4AC;  miss when Δ < 0
 *   q = −½(B + sign(B)√Δ), roots q/A and C/q;  hit unless both lie outside [0, tmax]
 *   or the segment lies wholly inside (near < 0 and far > tmax)
 *
 * Contract: query=any_hit,range=tmax_only,ends=[] (no tmin: from 0 to tmax, both
 * ends closed), any direction length. */
#include <math.h>

#include "rayverify_plugin.h"

RAYVERIFY_PLUGIN_EXPORT const rayverify_plugin_info_v2* rayverify_plugin_describe_v2(void) {
    static const rayverify_plugin_info_v2 info = {
        RAYVERIFY_PLUGIN_ABI_VERSION_2,
        "shadow_sphere",
        "Mitsuba 3 ray_test, in float (examples/plugin_v2/shadow_sphere.c)",
        "q = -(B + sign(B) sqrt(B^2 - 4AC))/2, roots q/A, C/q; hit when a root lies in [0, tmax]",
        "float only; plain C, no FMA contraction",
        "query=any_hit,range=tmax_only,ends=[]",
        NULL,
        RAYVERIFY_FLOAT};
    return &info;
}

RAYVERIFY_PLUGIN_EXPORT void rayverify_plugin_intersect_batch_float(const rayverify_case_float* cases,
                                                                    rayverify_answer_float* answers, size_t n) {
    for (size_t i = 0; i < n; ++i) {
        const float* o = cases[i].origin;
        const float* d = cases[i].direction;
        const float* c = cases[i].centre;
        const float r = cases[i].radius, tmax = cases[i].tmax;
        const float f[3] = {o[0] - c[0], o[1] - c[1], o[2] - c[2]};
        const float A = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        const float B = 2.0f * (d[0] * f[0] + d[1] * f[1] + d[2] * f[2]);
        const float C = f[0] * f[0] + f[1] * f[1] + f[2] * f[2] - r * r;
        const float disc = B * B - 4.0f * A * C;
        answers[i].count = 0;
        if (!(disc >= 0.0f)) continue;
        {
            const float q = -0.5f * (B + copysignf(sqrtf(disc), B));
            float near = q / A, far = C / q;
            if (near > far) {
                const float swap = near;
                near = far;
                far = swap;
            }
            if (!(near <= tmax && far >= 0.0f)) continue;
            if (near < 0.0f && far > tmax) continue;
            answers[i].count = 1;
        }
    }
}
