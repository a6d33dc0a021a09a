/* The rayverify plugin for ray_sphere_cast.c: RaySphere called on each
 * segment's end points exactly as rayverify hands them over (its segment
 * entry, rayverify_plugin.h), with no wrapper computing p1 from a ray: every
 * verdict is about the segment the function received.
 *
 * The contract says what RaySphere promises: the nearest contact on the
 * closed segment (ends=[]: a contact at p0 or p1 counts), contact at the
 * start when p0 is inside (inside=clamp), a tangent segment touches
 * (tangent=hit), fractions along p1 - p0 (cast=segment). */
#include "ray_sphere_cast.h"
#include "rayverify_plugin.h"

RAYVERIFY_PLUGIN_EXPORT const rayverify_plugin_info_v2* rayverify_plugin_describe_v2(void) {
    static const rayverify_plugin_info_v2 info = {
        RAYVERIFY_PLUGIN_ABI_VERSION_2,
        "physics_segment",
        "Ericson, Real-Time Collision Detection (2005), 5.3.2 IntersectRaySphere, on the segment",
        "d = p1-p0, m = p0-c, b = m.d, C = m.m-r^2; C>0 && b>0: miss; t = (-b - sqrt(b^2 - (d.d)C))/(d.d), "
        "max(t, 0), t <= 1",
        "float throughout, no FMA contraction, no fast math (examples/physics_segment/CMakeLists.txt)",
        "query=nearest_hit,range=interval,ends=[],inside=clamp,tangent=hit,faces=both,cast=segment",
        NULL,
        RAYVERIFY_FLOAT};
    return &info;
}

RAYVERIFY_PLUGIN_EXPORT int rayverify_plugin_thread_safe(void) { return 1; }

RAYVERIFY_PLUGIN_EXPORT void rayverify_plugin_intersect_segments_float(const rayverify_segment_float* segments,
                                                                       rayverify_answer_float* answers, size_t count) {
    for (size_t i = 0; i < count; ++i) {
        float fraction = 0.0f;
        answers[i].count = RaySphere(segments[i].p0, segments[i].p1, segments[i].centre, segments[i].radius, &fraction);
        if (answers[i].count == 1) answers[i].t[0] = fraction;
    }
}
