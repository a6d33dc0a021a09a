// Bullet Physics as Debian's libbullet installs it (btScalar = float: the
// package's default libraries are built without BT_USE_DOUBLE_PRECISION),
// audited as a plugin: a btCollisionWorld with one static btCollisionObject
// holding a btSphereShape, and btCollisionWorld::rayTest(from, to,
// ClosestRayResultCallback), as a game casts a ray.
//
// What the library does (BulletCollision/CollisionDispatch/btCollisionWorld.cpp,
// rayTestSingleInternal): a sphere is a convex shape, so the ray is a convex
// cast of a point (a btSphereShape of radius 0) against it, by
// btSubsimplexConvexCast (GJK on the Minkowski difference, at most 32
// iterations, stopping when |v|² <= 1e-4 absolute): an iterative solver, not
// a closed form. The hit is kept when the fraction is below the callback's
// closest fraction (1 at first), and the cast reports nothing when it ends
// with a zero normal, as it does from inside the sphere.
//
// Segment cases (p0, p1) are cast from p0 to p1 exactly as given, through
// the segment entry. On ray cases, the mapping: a case's (tmin, tmax) is the segment from = o + tmin·d (o when
// tmin = 0), to = o + tmax·d, each coordinate rounded once to float; a case
// without tmax gets to = o + L·d with L the power of two of
// rayverify::segment_length (L·|d|∞ >= 2(|o − c|₁ + r), past every root). The
// answer is the hit point the callback gives, m_hitPointWorld (from
// interpolated to `to` by the hit fraction, in float): answer=point, and its t
// is derived by rayverify as (p − o)·d/(d·d). The normal is m_hitNormalWorld.
//
// Contract: query=nearest_hit,range=segment,ends=[),inside=miss,tangent=hit,
// answer=point,normal=yes. Float only.
//
// Cost: per case, the sphere's radius and the object's transform are set and
// its broadphase AABB updated (updateSingleAabb), then one rayTest: a
// broadphase (btDbvtBroadphase) ray walk and the GJK cast.
#include <btBulletCollisionCommon.h>

#include <cstdio>
#include <string>

#include "native_glue.h"
#include "rayverify_plugin.h"

static_assert(sizeof(btScalar) == sizeof(float), "Debian's libbullet: btScalar is float");

namespace {

struct bullet_world {
    btDefaultCollisionConfiguration configuration;
    btCollisionDispatcher dispatcher{&configuration};
    btDbvtBroadphase broadphase;
    btCollisionWorld world{&dispatcher, &broadphase, &configuration};
    btSphereShape sphere{1.0f};
    btCollisionObject object;

    bullet_world() {
        object.setCollisionShape(&sphere);
        object.setWorldTransform(btTransform::getIdentity());
        world.addCollisionObject(&object);
    }
};

bullet_world& world() {
    static bullet_world* w = new bullet_world;  // kept for the life of the library
    return *w;
}

}  // namespace

extern "C" {

RAYVERIFY_PLUGIN_EXPORT const rayverify_plugin_info_v2* rayverify_plugin_describe_v2(void) {
    static const rayverify_plugin_info_v2 info = {
        RAYVERIFY_PLUGIN_ABI_VERSION_2,
        "bullet3",
        "Bullet Physics (libBulletCollision), btCollisionWorld::rayTest with ClosestRayResultCallback on a "
        "btSphereShape (btCollisionWorld.cpp rayTestSingleInternal, btSubsimplexConvexCast)",
        "GJK convex cast of a point along from->to against the sphere (|v|^2 <= 1e-4, 32 iterations); "
        "point = lerp(from, to, fraction)",
        "Debian 12 package libbullet-dev 3.24, float, as packaged (btScalar = float)",
        "query=nearest_hit,range=segment,ends=(),inside=miss,tangent=hit,faces=both,unit_direction=no,"
        "answer=point,normal=yes",
        nullptr,
        RAYVERIFY_FLOAT};
    return &info;
}

}  // extern "C"

namespace {

// One rayTest from `from` to `to` against the sphere, its answer a point and the normal.
void cast(const float centre[3], float radius, const float from[3], const float to[3], rayverify_answer_float& a) {
    bullet_world& w = world();
    w.sphere.setUnscaledRadius(radius);
    btTransform place = btTransform::getIdentity();
    place.setOrigin(btVector3(centre[0], centre[1], centre[2]));
    w.object.setWorldTransform(place);
    w.world.updateSingleAabb(&w.object);

    const btVector3 ray_from(from[0], from[1], from[2]), ray_to(to[0], to[1], to[2]);
    btCollisionWorld::ClosestRayResultCallback callback(ray_from, ray_to);
    w.world.rayTest(ray_from, ray_to, callback);
    if (!callback.hasHit()) {
        a.count = 0;
        return;
    }
    a.count = 1;
    for (int axis = 0; axis < 3; ++axis) {
        a.point[axis] = callback.m_hitPointWorld[axis];
        a.normal[axis] = callback.m_hitNormalWorld[axis];
    }
}

}  // namespace

extern "C" {

// Ray cases: the segment the mapping above forms from the ray and its interval.
RAYVERIFY_PLUGIN_EXPORT void rayverify_plugin_intersect_batch_float(const rayverify_case_float* cases,
                                                                    rayverify_answer_float* answers, size_t count) {
    for (size_t i = 0; i < count; ++i) {
        const rayverify_case_float& k = cases[i];
        float from[3], to[3], far = 0;
        rayverify_native::case_segment<float>(k.origin, k.direction, k.centre, k.radius, k.tmin, k.tmax, from, to,
                                              far);
        cast(k.centre, k.radius, from, to, answers[i]);
    }
}

// Segment cases: rayTest(p0, p1) with the case's end points as given, as a
// game casts between two points (rayverify_plugin.h's segment entry).
RAYVERIFY_PLUGIN_EXPORT void rayverify_plugin_intersect_segments_float(const rayverify_segment_float* segments,
                                                                       rayverify_answer_float* answers, size_t count) {
    for (size_t i = 0; i < count; ++i)
        cast(segments[i].centre, segments[i].radius, segments[i].p0, segments[i].p1, answers[i]);
}

// Bullet has no exported version function: btGetVersion() is inline in
// LinearMath/btScalar.h, so this is the version of the headers the plugin was
// built against (Debian's headers and library come from one source package).
RAYVERIFY_PLUGIN_EXPORT const char* rayverify_plugin_library_version(void) {
    static const std::string version = [] {
        const int v = btGetVersion();
        return std::to_string(v / 100) + "." + std::to_string(v % 100);
    }();
    return version.c_str();
}

}  // extern "C"
