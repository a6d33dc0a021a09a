/* A plugin that changes the floating-point environment, as real libraries do,
 * for fp_environment_test.cpp. Version 2, float and double, thread-safe: the
 * textbook roots of the line (a = d.d, b = d.f, C = f.f - r^2, Δ = b^2 - aC,
 * t = (-b -+ sqrt Δ) / a), computed in whatever environment it is called in.
 * FIXTURE_FP_MODE, read when the library loads, says what it changes:
 *   load_ftz_daz, load_upward, load_unmask_invalid, load_x87
 *       in its constructor: FTZ+DAZ, rounding upward, FE_INVALID trapped, the
 *       x87 unit at single precision;
 *   batch_ftz_daz, batch_downward, batch_toward_zero, batch_unmask, batch_x87
 *       at the end of every batch: FTZ+DAZ, rounding downward or toward zero,
 *       FE_INVALID, FE_DIVBYZERO and FE_OVERFLOW trapped, the x87 unit at
 *       single precision, left so for its caller;
 *   anything else: nothing.
 * Its name is FIXTURE_NAME ("fp_hostile" unless defined). Built once more with
 * -ffast-math on its link line and without rayverify::plugin_api's link
 * options, as a project's release flags would link it: GCC's crtfastmath.o
 * then sets FTZ+DAZ when it loads. */
#define _GNU_SOURCE
#include <fenv.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "rayverify_plugin.h"

#ifndef FIXTURE_NAME
#define FIXTURE_NAME "fp_hostile"
#endif

static const char* mode = "";
static int is_mode(const char* m) { return strcmp(mode, m) == 0; }

#if defined(__x86_64__)
#include <xmmintrin.h>
static void set_ftz_daz(void) { _mm_setcsr(_mm_getcsr() | 0x8040u); }
static void set_x87_single(void) {
    unsigned short word;
    __asm__ __volatile__("fnstcw %0" : "=m"(word));
    word = (unsigned short)(word & ~0x0300u); /* precision control 00: single */
    __asm__ __volatile__("fldcw %0" : : "m"(word));
}
#else
static void set_ftz_daz(void) {}
static void set_x87_single(void) {}
#endif

__attribute__((constructor)) static void on_load(void) {
    const char* m = getenv("FIXTURE_FP_MODE");
    mode = m ? m : "";
    if (is_mode("load_ftz_daz")) set_ftz_daz();
    if (is_mode("load_upward")) fesetround(FE_UPWARD);
    if (is_mode("load_unmask_invalid")) feenableexcept(FE_INVALID);
    if (is_mode("load_x87")) set_x87_single();
}

static void after_batch(void) {
    if (is_mode("batch_ftz_daz")) set_ftz_daz();
    if (is_mode("batch_downward")) fesetround(FE_DOWNWARD);
    if (is_mode("batch_toward_zero")) fesetround(FE_TOWARDZERO);
    if (is_mode("batch_unmask")) feenableexcept(FE_INVALID | FE_DIVBYZERO | FE_OVERFLOW);
    if (is_mode("batch_x87")) set_x87_single();
}

RAYVERIFY_PLUGIN_EXPORT const rayverify_plugin_info_v2* rayverify_plugin_describe_v2(void) {
    static const rayverify_plugin_info_v2 info = {RAYVERIFY_PLUGIN_ABI_VERSION_2,
                                                  FIXTURE_NAME,
                                                  "tests/plugin_fixtures/fp_environment_plugin.c",
                                                  "t = (-b -+ sqrt(b^2 - aC)) / a",
                                                  0,
                                                  "query=line_roots",
                                                  0,
                                                  RAYVERIFY_FLOAT | RAYVERIFY_DOUBLE};
    return &info;
}

RAYVERIFY_PLUGIN_EXPORT int rayverify_plugin_thread_safe(void) { return 1; }

#define LINE_ROOTS(T, SQRT)                                                                  \
    for (size_t i = 0; i < count; ++i) {                                                     \
        const T* o = cases[i].origin;                                                        \
        const T* d = cases[i].direction;                                                     \
        const T f[3] = {o[0] - cases[i].centre[0], o[1] - cases[i].centre[1], o[2] - cases[i].centre[2]}; \
        const T a = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];                                 \
        const T b = d[0] * f[0] + d[1] * f[1] + d[2] * f[2];                                 \
        const T c = f[0] * f[0] + f[1] * f[1] + f[2] * f[2] - cases[i].radius * cases[i].radius; \
        const T disc = b * b - a * c;                                                        \
        if (!(disc >= 0)) {                                                                  \
            answers[i].count = 0;                                                            \
            continue;                                                                        \
        }                                                                                    \
        const T s = SQRT(disc);                                                              \
        answers[i].count = 2; /* a tangent: two equal roots */                         \
        answers[i].t[0] = (-b - s) / a;                                                      \
        answers[i].t[1] = (-b + s) / a;                                                      \
    }                                                                                        \
    after_batch();

RAYVERIFY_PLUGIN_EXPORT void rayverify_plugin_intersect_batch_double(const rayverify_case_double* cases,
                                                                     rayverify_answer_double* answers, size_t count) {
    LINE_ROOTS(double, sqrt)
}

RAYVERIFY_PLUGIN_EXPORT void rayverify_plugin_intersect_batch_float(const rayverify_case_float* cases,
                                                                    rayverify_answer_float* answers, size_t count) {
    LINE_ROOTS(float, sqrtf)
}
