/* Misbehaving plugins for plugin_test.cpp, one per FIXTURE_* definition.
 *   FIXTURE_GARBAGE     loads fine, answers nonsense chosen by origin.x:
 *                       0 → count 3, 1 → NaN roots, 2 → roots out of order, else → a correct answer
 *                       (for the unit sphere at the origin, direction +z), in double and float
 *   FIXTURE_BAD_ABI     describes itself with ABI version 999
 *   FIXTURE_NO_DOUBLE   has no rayverify_plugin_intersect_double
 *   FIXTURE_BAD_NAME    names itself "two words" */
#include <math.h>

#include "rayverify_plugin.h"

RAYVERIFY_PLUGIN_EXPORT const rayverify_plugin_info* rayverify_plugin_describe(void) {
#if defined(FIXTURE_BAD_ABI)
    static const rayverify_plugin_info info = {999, "bad_abi", 0, 0, RAYVERIFY_LINE_ROOTS, 0, 0, 0, 0};
#elif defined(FIXTURE_BAD_NAME)
    static const rayverify_plugin_info info = {RAYVERIFY_PLUGIN_ABI_VERSION, "two words", 0, 0, RAYVERIFY_LINE_ROOTS,
                                               0, 0, 0, 0};
#else
    static const rayverify_plugin_info info = {RAYVERIFY_PLUGIN_ABI_VERSION, "garbage", "plugin_test fixture", 0,
                                               RAYVERIFY_LINE_ROOTS, 0, 1, 0, "never"};
#endif
    return &info;
}

#define GARBAGE_BODY(T, SQRT)                                                      \
    const T z = o[2] - c[2];                                                       \
    const T disc = z * z - (z * z - r * r);                                        \
    (void)d;                                                                       \
    (void)tmin;                                                                    \
    (void)tmax;                                                                    \
    if (o[0] == 0) return 3;                                                       \
    if (o[0] == 1) {                                                               \
        roots[0] = roots[1] = (T)NAN;                                              \
        return 2;                                                                  \
    }                                                                              \
    roots[0] = -z - SQRT(disc);                                                    \
    roots[1] = -z + SQRT(disc);                                                    \
    if (o[0] == 2) {                                                               \
        const T swap = roots[0];                                                   \
        roots[0] = roots[1];                                                       \
        roots[1] = swap;                                                           \
    }                                                                              \
    return 2;

#if !defined(FIXTURE_NO_DOUBLE)
RAYVERIFY_PLUGIN_EXPORT int rayverify_plugin_intersect_double(const double o[3], const double d[3],
                                                              const double c[3], double r, double tmin,
                                                              double tmax, double roots[2]) {
    GARBAGE_BODY(double, sqrt)
}
#endif

RAYVERIFY_PLUGIN_EXPORT int rayverify_plugin_intersect_float(const float o[3], const float d[3], const float c[3],
                                                             float r, float tmin, float tmax, float roots[2]) {
    GARBAGE_BODY(float, sqrtf)
}
