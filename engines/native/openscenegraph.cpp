// OpenSceneGraph's analytic segment–sphere test as Debian's
// libopenscenegraph-dev installs it, audited as a plugin:
// osg::LineSegment::intersectAndComputeRatios(const osg::BoundingSphere&,
// double&, double&) (osg/LineSegment, src/osg/LineSegment.cpp in libosg).
//
// Why this call: osgUtil::LineSegmentIntersector on a Geode with a
// ShapeDrawable sphere intersects the drawable's tessellated triangles, not a
// sphere; osgUtil tests a sphere analytically only to cull (its
// intersects(const BoundingSphere&), a yes/no). osg::LineSegment's
// intersectAndComputeRatios is the public call that takes a sphere and gives
// roots.
//
// What it does: the segment s→e is a Vec3d pair; osg::BoundingSphere is
// BoundingSpheref in Debian's build (OSG_USE_FLOAT_BOUNDINGSPHERE: centre
// Vec3f, radius float). In double: sm = s − c, c_ = sm·sm − r², se = e − s,
// a = se·se, b = 2 sm·se, disc = b² − 4ac, false when disc < 0; r1,2 = (−b ∓
// sqrt(disc))·(1/(2a)), the ratios of the LINE's two roots along s→e
// (unclipped); then false when both ratios are <= 0 or both >= 1, else true.
// So its decision is: some point of the segment's open interior (0, 1) lies
// in the closed ball [r1, r2], true also when the whole segment is inside.
//
// The mapping: the case's (tmin, tmax) is the segment s = o + tmin·d (o when
// tmin = 0), e = o + tmax·d, in double; a case without tmax gets e = o + L·d
// with L the power of two of rayverify::segment_length (past every root).
// The answer is its yes/no: the ratios are the line's roots whatever part of
// them lies on the segment, and rayverify judges no "line roots when the
// segment is touched" contract, so they are not handed over.
//
// Contract: query=any_hit,range=segment,ends=(),inside=clamp (a segment
// starting inside the sphere is a hit whatever its end),tangent=hit. Float
// only: the sphere is float in this build (a double case's centre would be
// rounded to float, another sphere); the float case's inputs are exact in
// the double segment arithmetic, whose ends are rounded once to double.
//
// Cost: one LineSegment::set and one call (a few double operations and a
// square root) per case; the LineSegment object is reused.
#include <osg/BoundingSphere>
#include <osg/LineSegment>
#include <osg/ref_ptr>
#include <osg/Version>

#include <type_traits>

#include "native_glue.h"
#include "rayverify_plugin.h"

static_assert(std::is_same_v<osg::BoundingSphere::value_type, float>,
              "Debian's OpenSceneGraph: osg::BoundingSphere is BoundingSpheref (OSG_USE_FLOAT_BOUNDINGSPHERE)");
static_assert(std::is_same_v<osg::LineSegment::vec_type, osg::Vec3d>, "osg::LineSegment is a pair of Vec3d");

namespace {

osg::LineSegment& segment() {
    static osg::ref_ptr<osg::LineSegment>* kept = new osg::ref_ptr<osg::LineSegment>(new osg::LineSegment);
    return **kept;  // kept for the life of the library
}

}  // namespace

extern "C" {

RAYVERIFY_PLUGIN_EXPORT const rayverify_plugin_info_v2* rayverify_plugin_describe_v2(void) {
    static const rayverify_plugin_info_v2 info = {
        RAYVERIFY_PLUGIN_ABI_VERSION_2,
        "openscenegraph",
        "OpenSceneGraph (libosg), osg::LineSegment::intersectAndComputeRatios(const BoundingSphere&, double&, double&) "
        "(osg/LineSegment, src/osg/LineSegment.cpp)",
        "sm = s - c, se = e - s, disc = (2 sm.se)^2 - 4 se.se (sm.sm - r^2), r1,2 = (-b -+ sqrt(disc))/(2a); "
        "hit unless both <= 0 or both >= 1",
        "Debian 12 package libopenscenegraph-dev 3.6.5, float sphere (BoundingSpheref) and double segment (Vec3d), "
        "as packaged",
        "query=any_hit,range=segment,ends=(),inside=clamp,tangent=hit,faces=both,unit_direction=no",
        nullptr,
        RAYVERIFY_FLOAT};
    return &info;
}

RAYVERIFY_PLUGIN_EXPORT void rayverify_plugin_intersect_batch_float(const rayverify_case_float* cases,
                                                                    rayverify_answer_float* answers, size_t count) {
    osg::LineSegment& line = segment();
    for (size_t i = 0; i < count; ++i) {
        const rayverify_case_float& k = cases[i];
        double from[3], to[3];
        float far = 0;
        rayverify_native::case_segment<double>(k.origin, k.direction, k.centre, k.radius, k.tmin, k.tmax, from, to,
                                               far);
        line.set(osg::Vec3d(from[0], from[1], from[2]), osg::Vec3d(to[0], to[1], to[2]));
        const osg::BoundingSphere sphere(osg::Vec3f(k.centre[0], k.centre[1], k.centre[2]), k.radius);
        double ratio1 = 0, ratio2 = 0;
        answers[i].count = line.intersectAndComputeRatios(sphere, ratio1, ratio2) ? 1 : 0;
    }
}

// The version libosg reports at run time.
RAYVERIFY_PLUGIN_EXPORT const char* rayverify_plugin_library_version(void) { return osgGetVersion(); }

}  // extern "C"
