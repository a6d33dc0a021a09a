/* Template: a physics engine's segment cast, handed the segment's end points
 * exactly as the case gives them (rayverify_plugin.h's segment entry): no
 * wrapper of yours turns a ray into p1 = o + L.d, so every rounding judged is
 * your function's. The body is the textbook cast on the closed segment with
 * contact at the start when p0 is inside (the rule of Jolt, Bullet, ODE and
 * Godot), answering the fraction f along p1 - p0 (0 at p0, 1 at p1).
 * Replace the body with your own; keep the contract, or change it to what
 * your function promises (ends=[) for a cast that excludes its end, ...).
 *
 * Build:  cc -O2 -shared -fPIC -I <rayverify>/src/plugin segment.c -o libmine.so -lm
 * Audit:  rayverify audit --plugin ./libmine.so --corpus my_segments.txt
 *         (lines "id family segment p0x p0y p0z p1x p1y p1z cx cy cz r") */
#include <math.h>

#include "rayverify_plugin.h"

RAYVERIFY_PLUGIN_EXPORT const rayverify_plugin_info_v2* rayverify_plugin_describe_v2(void) {
    static const rayverify_plugin_info_v2 info = {
        RAYVERIFY_PLUGIN_ABI_VERSION_2,
        "segment_cast",
        "template: the textbook segment cast (examples/templates/segment.c)",
        "d = p1-p0, m = p0-c, b = m.d, C = m.m-r^2, disc = b^2-(d.d)C, f = (-b - sqrt(disc))/(d.d), max(f, 0) <= 1",
        "plain C, no FMA contraction",
        "query=nearest_hit,range=interval,ends=[],inside=clamp,tangent=hit,faces=both,cast=segment",
        NULL,
        RAYVERIFY_FLOAT | RAYVERIFY_DOUBLE};
    return &info;
}

/* This body keeps no state: rayverify may call it from every thread. */
RAYVERIFY_PLUGIN_EXPORT int rayverify_plugin_thread_safe(void) { return 1; }

/* One cast in double: 1 and the fraction of first contact, or 0. */
static int cast_double(const double p0[3], const double p1[3], const double c[3], double r, double* f) {
    const double d[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
    const double m[3] = {p0[0] - c[0], p0[1] - c[1], p0[2] - c[2]};
    const double a = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    const double b = m[0] * d[0] + m[1] * d[1] + m[2] * d[2];
    const double C = m[0] * m[0] + m[1] * m[1] + m[2] * m[2] - r * r;
    if (C > 0 && b > 0) return 0; /* outside, moving away */
    const double disc = b * b - a * C;
    if (disc < 0) return 0;
    double t = (-b - sqrt(disc)) / a;
    if (t < 0) t = 0; /* started inside: contact at the start */
    if (t > 1) return 0;
    *f = t;
    return 1;
}

/* The same in float. */
static int cast_float(const float p0[3], const float p1[3], const float c[3], float r, float* f) {
    const float d[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
    const float m[3] = {p0[0] - c[0], p0[1] - c[1], p0[2] - c[2]};
    const float a = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    const float b = m[0] * d[0] + m[1] * d[1] + m[2] * d[2];
    const float C = m[0] * m[0] + m[1] * m[1] + m[2] * m[2] - r * r;
    if (C > 0 && b > 0) return 0;
    const float disc = b * b - a * C;
    if (disc < 0) return 0;
    float t = (-b - sqrtf(disc)) / a;
    if (t < 0) t = 0;
    if (t > 1) return 0;
    *f = t;
    return 1;
}

/* Each answer arrives with count -1 and NaNs: write count and, for a hit, t[0] (the fraction). */
RAYVERIFY_PLUGIN_EXPORT void rayverify_plugin_intersect_segments_double(const rayverify_segment_double* segments,
                                                                        rayverify_answer_double* answers,
                                                                        size_t count) {
    for (size_t i = 0; i < count; ++i)
        answers[i].count =
            cast_double(segments[i].p0, segments[i].p1, segments[i].centre, segments[i].radius, &answers[i].t[0]);
}

RAYVERIFY_PLUGIN_EXPORT void rayverify_plugin_intersect_segments_float(const rayverify_segment_float* segments,
                                                                       rayverify_answer_float* answers, size_t count) {
    for (size_t i = 0; i < count; ++i)
        answers[i].count =
            cast_float(segments[i].p0, segments[i].p1, segments[i].centre, segments[i].radius, &answers[i].t[0]);
}
