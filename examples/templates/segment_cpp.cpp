// Template: the segment cast of segment.c in C++, one function template for
// both precisions (your engine's own, called as it is built), exported
// through the segment entry of rayverify_plugin.h. Replace cast() with your
// own; keep the contract, or change it to what your function promises.
//
// Build:  c++ -std=c++17 -O2 -shared -fPIC -I <rayverify>/src/plugin segment_cpp.cpp -o libmine.so
// Audit:  rayverify audit --plugin ./libmine.so --corpus my_segments.txt
#include <cmath>
#include <cstddef>

#include "rayverify_plugin.h"

namespace {

// 1 and the fraction of first contact on the closed segment p0 -> p1 (0 when p0 is inside), or 0.
template <class T>
int cast(const T p0[3], const T p1[3], const T c[3], T r, T& fraction) {
    const T d[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
    const T m[3] = {p0[0] - c[0], p0[1] - c[1], p0[2] - c[2]};
    const T a = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    const T b = m[0] * d[0] + m[1] * d[1] + m[2] * d[2];
    const T C = m[0] * m[0] + m[1] * m[1] + m[2] * m[2] - r * r;
    if (C > 0 && b > 0) return 0;  // outside, moving away
    const T disc = b * b - a * C;
    if (disc < 0) return 0;
    T t = (-b - std::sqrt(disc)) / a;
    if (t < 0) t = 0;  // started inside: contact at the start
    if (t > 1) return 0;
    fraction = t;
    return 1;
}

template <class Segment, class Answer>
void answer_all(const Segment* segments, Answer* answers, std::size_t count) {
    for (std::size_t i = 0; i < count; ++i)
        answers[i].count = cast(segments[i].p0, segments[i].p1, segments[i].centre, segments[i].radius, answers[i].t[0]);
}

}  // namespace

extern "C" {

RAYVERIFY_PLUGIN_EXPORT const rayverify_plugin_info_v2* rayverify_plugin_describe_v2(void) {
    static const rayverify_plugin_info_v2 info = {
        RAYVERIFY_PLUGIN_ABI_VERSION_2,
        "segment_cast_cpp",
        "template: the textbook segment cast in C++ (examples/templates/segment_cpp.cpp)",
        "d = p1-p0, m = p0-c, b = m.d, C = m.m-r^2, f = (-b - sqrt(b^2-(d.d)C))/(d.d), max(f, 0) <= 1",
        "C++17, no FMA contraction",
        "query=nearest_hit,range=interval,ends=[],inside=clamp,tangent=hit,faces=both,cast=segment",
        nullptr,
        RAYVERIFY_FLOAT | RAYVERIFY_DOUBLE};
    return &info;
}

RAYVERIFY_PLUGIN_EXPORT int rayverify_plugin_thread_safe(void) { return 1; }

RAYVERIFY_PLUGIN_EXPORT void rayverify_plugin_intersect_segments_double(const rayverify_segment_double* segments,
                                                                        rayverify_answer_double* answers,
                                                                        std::size_t count) {
    answer_all(segments, answers, count);
}

RAYVERIFY_PLUGIN_EXPORT void rayverify_plugin_intersect_segments_float(const rayverify_segment_float* segments,
                                                                       rayverify_answer_float* answers,
                                                                       std::size_t count) {
    answer_all(segments, answers, count);
}

}  // extern "C"
