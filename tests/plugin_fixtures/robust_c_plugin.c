/* robust_sphere.h from a C project built with -ffast-math: this file is
 * compiled -std=c99 -ffast-math, as a game engine's sources are, and calls the
 * C interface (src/intersectors/robust_sphere_c.h), whose one translation
 * unit robust_sphere_c.cpp is compiled strictly as its own object and linked
 * in; the plugin is linked without -ffast-math (no crtfastmath.o). One plugin
 * per query (ROBUST_QUERY: 0 line roots, 1 nearest hit in the open interval,
 * 2 any hit), audited by robust_cxx17_test with the library's verdicts. */
#include <stddef.h>

#include "rayverify_plugin.h"
#include "robust_sphere_c.h"

#if !defined(ROBUST_QUERY)
#error "ROBUST_QUERY: 0 line roots, 1 nearest hit, 2 any hit, 3 segment hit"
#endif

#if ROBUST_QUERY == 0
#define NAME "robust_c_fastmath"
#define CONTRACT "query=line_roots,reports_tangent=yes"
#define TANGENT_RULE "Δ′ == 0 (exact)"
#elif ROBUST_QUERY == 1
#define NAME "robust_nearest_c_fastmath"
#define CONTRACT "query=nearest_hit,range=interval"
#define TANGENT_RULE 0
#elif ROBUST_QUERY == 2
#define NAME "robust_any_hit_c_fastmath"
#define CONTRACT "query=any_hit,range=interval"
#define TANGENT_RULE 0
#else
#define NAME "robust_segment_c_fastmath"
#define CONTRACT "query=nearest_hit,range=interval,ends=[],inside=clamp,cast=segment"
#define TANGENT_RULE 0
#endif

RAYVERIFY_PLUGIN_EXPORT const rayverify_plugin_info_v2* rayverify_plugin_describe_v2(void) {
    static const rayverify_plugin_info_v2 info = {
        RAYVERIFY_PLUGIN_ABI_VERSION_2,
        NAME,
        "rayverify robust_sphere_c.h from C (tests/plugin_fixtures/robust_c_plugin.c)",
        "as the built-in robust variants",
        "caller -std=c99 -O2 -ffast-math; robust_sphere_c.cpp -std=c++17 -O2 -ffp-contract=off",
        CONTRACT,
        TANGENT_RULE,
        RAYVERIFY_FLOAT | RAYVERIFY_DOUBLE};
    return &info;
}

/* One case of either precision through the C interface: SUFFIX is "" for
 * double, _f for float. */
#define ANSWER(T, SUFFIX)                                                                                       \
    for (size_t i = 0; i < n; ++i) {                                                                            \
        const T* o = cases[i].origin;                                                                           \
        const T* d = cases[i].direction;                                                                        \
        const T* c = cases[i].centre;                                                                           \
        T t[2];                                                                                                 \
        if (ROBUST_QUERY == 0) {                                                                                \
            answers[i].count = robust_sphere_line_roots##SUFFIX(o, d, c, cases[i].radius, t);                  \
            if (answers[i].count > 0) answers[i].t[0] = t[0], answers[i].t[1] = t[1];                          \
        } else if (ROBUST_QUERY == 1) {                                                                         \
            answers[i].count = robust_sphere_nearest_hit##SUFFIX(o, d, c, cases[i].radius, cases[i].tmin,       \
                                                                 cases[i].tmax, ROBUST_SPHERE_OPEN,             \
                                                                 ROBUST_SPHERE_OPEN, t);                        \
            if (answers[i].count > 0) answers[i].t[0] = answers[i].t[1] = t[0];                                \
        } else {                                                                                                \
            answers[i].count = robust_sphere_any_hit##SUFFIX(o, d, c, cases[i].radius, cases[i].tmin,           \
                                                             cases[i].tmax, ROBUST_SPHERE_OPEN,                 \
                                                             ROBUST_SPHERE_OPEN);                               \
        }                                                                                                       \
    }

#if ROBUST_QUERY == 3
/* The segment query on the ends as given, through the C interface. */
#define SEGMENTS(T, SUFFIX)                                                                                      \
    for (size_t i = 0; i < n; ++i) {                                                                            \
        T f = 0;                                                                                                \
        answers[i].count = robust_sphere_segment_hit##SUFFIX(segments[i].p0, segments[i].p1, segments[i].centre, \
                                                             segments[i].radius, ROBUST_SPHERE_CLOSED,          \
                                                             ROBUST_SPHERE_CLOSED, ROBUST_SPHERE_CONTACT, &f);  \
        answers[i].t[0] = answers[i].t[1] = f;                                                                  \
    }

RAYVERIFY_PLUGIN_EXPORT void rayverify_plugin_intersect_segments_double(const rayverify_segment_double* segments,
                                                                        rayverify_answer_double* answers, size_t n) {
    SEGMENTS(double, )
}

RAYVERIFY_PLUGIN_EXPORT void rayverify_plugin_intersect_segments_float(const rayverify_segment_float* segments,
                                                                       rayverify_answer_float* answers, size_t n) {
    SEGMENTS(float, _f)
}
#else
RAYVERIFY_PLUGIN_EXPORT void rayverify_plugin_intersect_batch_double(const rayverify_case_double* cases,
                                                                     rayverify_answer_double* answers, size_t n) {
    ANSWER(double, )
}

RAYVERIFY_PLUGIN_EXPORT void rayverify_plugin_intersect_batch_float(const rayverify_case_float* cases,
                                                                    rayverify_answer_float* answers, size_t n) {
    ANSWER(float, _f)
}
#endif
