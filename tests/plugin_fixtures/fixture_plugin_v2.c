/* Version 2 fixture plugins for plugin_v2_test.cpp, one per FIXTURE_* definition.
 *   FIXTURE_TIGHT_BOUND   "too_tight": the nearest root of the line in front (stable roots, double
 *                         and float), claiming the interval [t, t] for it: too tight wherever t is
 *                         not exactly the root, so the audit must call it unsound_bound
 *   FIXTURE_BAD_CONTRACT  describes the contract "query=sideways"
 *   FIXTURE_NO_PRECISION  describes precisions = 0
 *   FIXTURE_BATCH_CRASH   "batch_crash": like TIGHT_BOUND without bounds, but stores to address 16
 *                         when a case of the batch has radius 3
 *   FIXTURE_MISSPELT      like TIGHT_BOUND, but its describe function is misspelt
 *                         rayverify_plugin_descibe_v2 */
#include <math.h>
#include <stddef.h>

#include "rayverify_plugin.h"

#if defined(FIXTURE_BAD_CONTRACT)
#define CONTRACT "query=sideways"
#elif defined(FIXTURE_TIGHT_BOUND)
#define CONTRACT "query=nearest_hit,range=interval,t_bounds=yes"
#else
#define CONTRACT "query=nearest_hit,range=interval"
#endif

#if defined(FIXTURE_NO_PRECISION)
#define PRECISIONS 0
#else
#define PRECISIONS (RAYVERIFY_FLOAT | RAYVERIFY_DOUBLE)
#endif

#if defined(FIXTURE_BATCH_CRASH)
#define NAME "batch_crash"
#else
#define NAME "too_tight"
#endif

#if defined(FIXTURE_MISSPELT)
#define DESCRIBE_V2 rayverify_plugin_descibe_v2
RAYVERIFY_PLUGIN_EXPORT const rayverify_plugin_info_v2* DESCRIBE_V2(void);
#else
#define DESCRIBE_V2 rayverify_plugin_describe_v2
#endif

RAYVERIFY_PLUGIN_EXPORT const rayverify_plugin_info_v2* DESCRIBE_V2(void) {
    static const rayverify_plugin_info_v2 info = {
        RAYVERIFY_PLUGIN_ABI_VERSION_2, NAME, "plugin_v2_test fixture", 0, 0, CONTRACT, 0, PRECISIONS};
    return &info;
}

#if defined(FIXTURE_BATCH_CRASH)
#define MISBEHAVE(r)                                               \
    if ((r) == 3) {                                                \
        volatile int* volatile nowhere = (volatile int*)16;        \
        *nowhere = 1;                                              \
    }
#else
#define MISBEHAVE(r)
#endif

/* The nearest root of a t^2 + 2 b t + C = 0 in (tmin, tmax), stable roots. */
#define BODY(T, SQRT)                                                                        \
    for (size_t i = 0; i < n; ++i) {                                                         \
        const T* o = cases[i].origin;                                                        \
        const T* d = cases[i].direction;                                                     \
        const T* c = cases[i].centre;                                                        \
        const T f[3] = {o[0] - c[0], o[1] - c[1], o[2] - c[2]};                              \
        const T a = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];                                 \
        const T b = f[0] * d[0] + f[1] * d[1] + f[2] * d[2];                                 \
        const T C = f[0] * f[0] + f[1] * f[1] + f[2] * f[2] - cases[i].radius * cases[i].radius; \
        const T disc = b * b - a * C;                                                        \
        T q, t0, t1, t;                                                                      \
        MISBEHAVE(cases[i].radius)                                                           \
        answers[i].count = 0;                                                                \
        if (!(disc >= 0)) continue;                                                          \
        q = -(b + (b < 0 ? -SQRT(disc) : SQRT(disc)));                                       \
        t0 = q / a;                                                                          \
        t1 = C / q;                                                                          \
        if (t0 > t1) {                                                                       \
            t = t0;                                                                          \
            t0 = t1;                                                                         \
            t1 = t;                                                                          \
        }                                                                                    \
        if (t0 > cases[i].tmin && t0 < cases[i].tmax)                                        \
            t = t0;                                                                          \
        else if (t1 > cases[i].tmin && t1 < cases[i].tmax)                                   \
            t = t1;                                                                          \
        else                                                                                 \
            continue;                                                                        \
        answers[i].count = 1;                                                                \
        answers[i].t[0] = answers[i].t[1] = t;                                               \
        answers[i].t_lower[0] = answers[i].t_upper[0] = t;                                   \
    }

RAYVERIFY_PLUGIN_EXPORT void rayverify_plugin_intersect_batch_double(const rayverify_case_double* cases,
                                                                     rayverify_answer_double* answers, size_t n) {
    BODY(double, sqrt)
}

RAYVERIFY_PLUGIN_EXPORT void rayverify_plugin_intersect_batch_float(const rayverify_case_float* cases,
                                                                    rayverify_answer_float* answers, size_t n) {
    BODY(float, sqrtf)
}
