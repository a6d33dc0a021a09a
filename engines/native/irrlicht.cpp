// Irrlicht's line–sphere test as Debian's libirrlicht-dev installs it,
// audited as a plugin: irr::core::line3d<T>::getIntersectionWithSphere
// (irrlicht/line3d.h), a header template compiled into the application, in
// float (line3df, as applications use it) and in double (line3d<f64>). No
// library code runs: nothing is linked.
//
// What it does: q = c − start, c_ = |q| (a square root), v = q·û with û =
// (end − start) normalized (vector3d::normalize: 1/sqrt(x² + y² + z²) in
// f64, each coordinate multiplied and rounded back to T), d = r² − (c_² −
// v²), a miss when d < 0, else outdistance = v − sqrt(d), the distance from
// start to the first intersection of the LINE: no sign test and no test
// against the segment's end, so a sphere behind start, or start inside the
// sphere, gives a negative distance.
//
// The mapping: the line from start = o to end = o + d (rounded once per
// coordinate in T), so û is the direction of d. The answer is the point an
// application makes of the distance, start + getVector().normalize()·dist,
// in T (irrlicht's vector ops): answer=point, whose t rayverify derives as
// (p − o)·d/(d·d). The distance is in units of length, so a t answer would
// need a division by |d| that Irrlicht never makes.
//
// Contract: query=nearest_hit,range=ray,ends=[),inside=far_root,tangent=hit,
// answer=point: what "the first intersection of a ray" promises; a hit
// behind the origin is judged line_not_ray, as raylib's (the function's
// design). Float and double.
//
// Cost: a handful of vector operations and two square roots per call, in the
// caller's code.
#include <line3d.h>
#include <IrrCompileConfig.h>

#include "rayverify_plugin.h"

namespace {

template <class T, class Case, class Answer>
void intersect_batch(const Case* cases, Answer* answers, size_t count) {
    using vec = irr::core::vector3d<T>;
    for (size_t i = 0; i < count; ++i) {
        const Case& k = cases[i];
        const vec origin(k.origin[0], k.origin[1], k.origin[2]);
        const vec direction(k.direction[0], k.direction[1], k.direction[2]);
        const irr::core::line3d<T> line(origin, origin + direction);
        irr::f64 distance = 0;
        Answer& a = answers[i];
        if (!line.getIntersectionWithSphere(vec(k.centre[0], k.centre[1], k.centre[2]), k.radius, distance)) {
            a.count = 0;
            continue;
        }
        const vec point = line.start + line.getVector().normalize() * static_cast<T>(distance);
        a.count = 1;
        a.point[0] = point.X;
        a.point[1] = point.Y;
        a.point[2] = point.Z;
    }
}

}  // namespace

extern "C" {

RAYVERIFY_PLUGIN_EXPORT const rayverify_plugin_info_v2* rayverify_plugin_describe_v2(void) {
    static const rayverify_plugin_info_v2 info = {
        RAYVERIFY_PLUGIN_ABI_VERSION_2,
        "irrlicht",
        "Irrlicht (libirrlicht-dev headers), irr::core::line3d<T>::getIntersectionWithSphere (irrlicht/line3d.h)",
        "q = c - start, v = q.normalize(end - start), disc = r^2 - (|q|^2 - v^2), dist = v - sqrt(disc); "
        "point start + normalize(end - start) dist",
        "Debian 12 package libirrlicht-dev 1.8.5, float (line3df) and double (line3d<f64>), as packaged "
        "(a header template, compiled with rayverify's FP flags)",
        "query=nearest_hit,range=ray,ends=[),inside=far_root,tangent=hit,faces=both,unit_direction=no,answer=point",
        nullptr,
        RAYVERIFY_FLOAT | RAYVERIFY_DOUBLE};
    return &info;
}

RAYVERIFY_PLUGIN_EXPORT void rayverify_plugin_intersect_batch_float(const rayverify_case_float* cases,
                                                                    rayverify_answer_float* answers, size_t count) {
    intersect_batch<irr::f32>(cases, answers, count);
}

RAYVERIFY_PLUGIN_EXPORT void rayverify_plugin_intersect_batch_double(const rayverify_case_double* cases,
                                                                     rayverify_answer_double* answers, size_t count) {
    intersect_batch<irr::f64>(cases, answers, count);
}

// The function is a header template: the version is that of the headers it
// was compiled from (IRRLICHT_SDK_VERSION).
RAYVERIFY_PLUGIN_EXPORT const char* rayverify_plugin_library_version(void) { return IRRLICHT_SDK_VERSION; }

}  // extern "C"
