/* Misbehaving plugins for plugin_test.cpp and plugin_isolate_test.cpp, one per FIXTURE_* definition.
 *   FIXTURE_GARBAGE     loads fine, answers nonsense chosen by origin.x:
 *                       0 → count 3, 1 → NaN roots, 2 → roots out of order, else → a correct answer
 *                       (for the unit sphere at the origin, direction +z), in double and float
 *   FIXTURE_BAD_ABI     describes itself with ABI version 999
 *   FIXTURE_NO_DOUBLE   has no rayverify_plugin_intersect_double
 *   FIXTURE_BAD_NAME    names itself "two words"
 *   FIXTURE_CRASH       "crashy": by radius, 3 → SIGSEGV (a store to address 16), 4 → abort(),
 *                       5 → exit(7), else the textbook roots of the line, in double and float
 *   FIXTURE_HANG        "hangs": never returns when radius == 3, else as FIXTURE_CRASH
 *   FIXTURE_MODAL       "modal": misbehaves as the environment variable FIXTURE_MODE says, read when loaded:
 *                       ctor_crash (SIGSEGV in a constructor), ctor_exit / describe_exit / call_exit
 *                       (exit(0) there), overrun (writes roots[2]), underrun (writes roots[-1]),
 *                       nan (NaN roots, count 2, always), escape_name (a name holding ESC [31m);
 *                       else the textbook roots of the line, in double and float */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "rayverify_plugin.h"

#if defined(FIXTURE_MODAL)
static const char* mode = "";
static int is_mode(const char* m) { return strcmp(mode, m) == 0; }

__attribute__((constructor)) static void on_load(void) {
    const char* m = getenv("FIXTURE_MODE");
    mode = m ? m : "";
    if (is_mode("ctor_crash")) {
        volatile int* volatile nowhere = (volatile int*)16;
        *nowhere = 1;
    }
    if (is_mode("ctor_exit")) exit(0);
}
#endif

RAYVERIFY_PLUGIN_EXPORT const rayverify_plugin_info* rayverify_plugin_describe(void) {
#if defined(FIXTURE_MODAL)
    static const rayverify_plugin_info info = {RAYVERIFY_PLUGIN_ABI_VERSION, "modal", "fixture_plugin.c", 0,
                                               RAYVERIFY_LINE_ROOTS, 0, 0, 0, 0};
    static const rayverify_plugin_info escaped = {RAYVERIFY_PLUGIN_ABI_VERSION, "\x1b[31mred", 0, 0,
                                                  RAYVERIFY_LINE_ROOTS, 0, 0, 0, 0};
    if (is_mode("describe_exit")) exit(0);
    return is_mode("escape_name") ? &escaped : &info;
#elif defined(FIXTURE_BAD_ABI)
    static const rayverify_plugin_info info = {999, "bad_abi", 0, 0, RAYVERIFY_LINE_ROOTS, 0, 0, 0, 0};
#elif defined(FIXTURE_CRASH)
    static const rayverify_plugin_info info = {RAYVERIFY_PLUGIN_ABI_VERSION, "crashy", "plugin_isolate_test fixture", 0,
                                               RAYVERIFY_LINE_ROOTS, 0, 0, 0, 0};
#elif defined(FIXTURE_HANG)
    static const rayverify_plugin_info info = {RAYVERIFY_PLUGIN_ABI_VERSION, "hangs", "plugin_isolate_test fixture", 0,
                                               RAYVERIFY_LINE_ROOTS, 0, 0, 0, 0};
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

#if defined(FIXTURE_CRASH) || defined(FIXTURE_HANG) || defined(FIXTURE_MODAL)
static void misbehave(double r) {
#if defined(FIXTURE_MODAL)
    (void)r;
    if (is_mode("call_exit")) exit(0);
#elif defined(FIXTURE_CRASH)
    if (r == 3) {
        /* Address 16, in the unmapped first page, not 0: a sanitizer build's null check would exit first.
         * Volatile twice: the compiler must load the pointer and store. */
        volatile int* volatile nowhere = (volatile int*)16;
        *nowhere = 1;
    }
    if (r == 4) abort();
    if (r == 5) exit(7);
#else
    if (r == 3)
        for (;;) sleep(1);
#endif
}

#if defined(FIXTURE_MODAL)
#define MODAL_ROOTS(T)                                                             \
    if (is_mode("overrun") || is_mode("underrun")) {                               \
        T* volatile outside = roots; /* volatile: the compiler keeps the store */  \
        outside[is_mode("overrun") ? 2 : -1] = 1;                                  \
    }                                                                              \
    if (is_mode("nan")) {                                                          \
        roots[0] = roots[1] = (T)NAN;                                              \
        return 2;                                                                  \
    }
#else
#define MODAL_ROOTS(T)
#endif

/* The textbook roots of a t^2 + 2 b t + C = 0. */
#define BODY(T, SQRT)                                                              \
    const T f[3] = {o[0] - c[0], o[1] - c[1], o[2] - c[2]};                        \
    const T a = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];                           \
    const T b = f[0] * d[0] + f[1] * d[1] + f[2] * d[2];                           \
    const T C = f[0] * f[0] + f[1] * f[1] + f[2] * f[2] - r * r;                   \
    const T disc = b * b - a * C;                                                  \
    (void)tmin;                                                                    \
    (void)tmax;                                                                    \
    misbehave(r);                                                                  \
    MODAL_ROOTS(T)                                                                 \
    if (disc < 0) return 0;                                                        \
    roots[0] = (-b - SQRT(disc)) / a;                                              \
    roots[1] = (-b + SQRT(disc)) / a;                                              \
    return 2;
#else
#define BODY(T, SQRT) GARBAGE_BODY(T, SQRT)
#endif

#if !defined(FIXTURE_NO_DOUBLE)
RAYVERIFY_PLUGIN_EXPORT int rayverify_plugin_intersect_double(const double o[3], const double d[3],
                                                              const double c[3], double r, double tmin,
                                                              double tmax, double roots[2]) {
    BODY(double, sqrt)
}
#endif

RAYVERIFY_PLUGIN_EXPORT int rayverify_plugin_intersect_float(const float o[3], const float d[3], const float c[3],
                                                             float r, float tmin, float tmax, float roots[2]) {
    BODY(float, sqrtf)
}
