// Embree 3 as Debian's libembree3 installs it, audited as a plugin: a device,
// a scene with one RTC_GEOMETRY_TYPE_SPHERE_POINT geometry (one vertex:
// centre and radius, float4), committed, and rtcIntersect1 with an RTCRayHit
// whose tnear/tfar are the case's range. Built twice from this file: default
// scene flags (embree3) and RTC_SCENE_FLAG_ROBUST (embree3_robust, with
// RAYVERIFY_EMBREE_ROBUST defined).
//
// The library's test (kernels/geometry/sphere_intersector.h,
// SphereIntersector1::intersect): rd2 = rcp(d·d), c0 = c − o, p = (c0·d)·rd2,
// perp = c0 − p·d, l2 = perp·perp, hit when l2 <= r²; td = sqrt((r² − l2)·rd2);
// t_front = p − td counts when tnear <= t_front <= tfar, else t_back = p + td
// under the same test (so from inside, the far root). Both ends closed, a
// tangent (l2 == r²) a hit. On x86 rcp is the hardware estimate plus one
// Newton step and multiply-adds are fused where the device's ISA has FMA
// (AVX2): the library is what it is, and this plugin calls it as built.
//
// Contract: query=nearest_hit,range=interval,ends=[],inside=far_root,
// tangent=hit, any direction length; the answer is ray.tfar after the hit,
// and the geometric normal hit.Ng (normal=yes). Float only (Embree's rays
// and vertices are float).
//
// A ray Embree refuses: Debian's libembree3 is built with assertions on, and
// rtcIntersect1 asserts ray.valid() (kernels/common/ray.h: every |org| and
// |dir| coordinate <= FLT_LARGE = 1.844e18, tnear and tfar not NaN), which
// aborts the program. The plugin makes the same test first and, for a ray
// that would fail it, leaves the answer as rayverify handed it over (count
// -1): the verdict malformed_output says "the library does not answer this".
//
// Cost: one sphere per case means one vertex update per case:
// rtcUpdateGeometryBuffer + rtcCommitGeometry + rtcCommitScene, a BVH
// rebuild of a one-primitive scene through Embree's task scheduler (of the
// order of microseconds to tens of microseconds, far more than the ray
// itself). A case with the same sphere as the one before reuses the
// committed scene.
#include <embree3/rtcore.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>

#include "rayverify_plugin.h"

namespace {

#ifdef RAYVERIFY_EMBREE_ROBUST
constexpr const char* plugin_name = "embree3_robust";
constexpr const char* plugin_contract =
    "query=nearest_hit,range=interval,ends=[],inside=far_root,tangent=hit,faces=both,unit_direction=no,normal=yes";
constexpr const char* plugin_build =
    "Debian 12 package libembree-dev 3.13.5, float, as packaged (the device's ISA chosen at run time; "
    "x86 rcp = estimate + one Newton step); scene flags RTC_SCENE_FLAG_ROBUST";
#else
constexpr const char* plugin_name = "embree3";
constexpr const char* plugin_contract =
    "query=nearest_hit,range=interval,ends=[],inside=far_root,tangent=hit,faces=both,unit_direction=no,normal=yes";
constexpr const char* plugin_build =
    "Debian 12 package libembree-dev 3.13.5, float, as packaged (the device's ISA chosen at run time; "
    "x86 rcp = estimate + one Newton step); default scene flags";
#endif

// Embree's ray.valid() (kernels/common/ray.h), which its rtcIntersect1 asserts.
constexpr float embree_flt_large = 1.844E18f;
bool embree_accepts(const rayverify_case_float& k) {
    for (int axis = 0; axis < 3; ++axis)
        if (!(std::fabs(k.origin[axis]) <= embree_flt_large) || !(std::fabs(k.direction[axis]) <= embree_flt_large))
            return false;
    return !std::isnan(k.tmin) && !std::isnan(k.tmax);
}

void report_error(void*, RTCError code, const char* message) {
    std::fprintf(stderr, "%s: Embree error %d: %s\n", plugin_name, static_cast<int>(code), message ? message : "");
}

// One device, one scene, one geometry with one vertex, kept for the life of
// the library (never released: Embree's own static state may be gone by the
// time a static destructor would run at exit).
struct embree_world {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    RTCGeometry geometry = nullptr;
    float* vertex = nullptr;  // x, y, z, radius
    bool committed = false;

    embree_world() {
        device = rtcNewDevice(nullptr);
        rtcSetDeviceErrorFunction(device, report_error, nullptr);
        scene = rtcNewScene(device);
#ifdef RAYVERIFY_EMBREE_ROBUST
        rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
#endif
        geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
        vertex = static_cast<float*>(
            rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), 1));
        vertex[0] = vertex[1] = vertex[2] = 0.0f;
        vertex[3] = 1.0f;
        rtcCommitGeometry(geometry);
        rtcAttachGeometry(scene, geometry);
    }

    // Make the scene hold the sphere (c, r), committing only when it changed.
    void set_sphere(const float c[3], float r) {
        const float wanted[4] = {c[0], c[1], c[2], r};
        const bool same = committed && std::memcmp(vertex, wanted, sizeof wanted) == 0;  // bit for bit
        if (same) return;
        vertex[0] = c[0];
        vertex[1] = c[1];
        vertex[2] = c[2];
        vertex[3] = r;
        rtcUpdateGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0);
        rtcCommitGeometry(geometry);
        rtcCommitScene(scene);
        committed = true;
    }
};

embree_world& world() {
    static embree_world* w = new embree_world;
    return *w;
}

}  // namespace

extern "C" {

RAYVERIFY_PLUGIN_EXPORT const rayverify_plugin_info_v2* rayverify_plugin_describe_v2(void) {
    static const rayverify_plugin_info_v2 info = {
        RAYVERIFY_PLUGIN_ABI_VERSION_2,
        plugin_name,
        "Embree 3 (libembree3), rtcIntersect1 on an RTC_GEOMETRY_TYPE_SPHERE_POINT geometry "
        "(embree3/rtcore_ray.h; kernels/geometry/sphere_intersector.h SphereIntersector1::intersect)",
        "p = (c - o).d rcp(d.d), perp = (c - o) - p d, td = sqrt((r^2 - perp.perp) rcp(d.d)), t = p -+ td in [tnear, tfar]",
        plugin_build,
        plugin_contract,
        nullptr,
        RAYVERIFY_FLOAT};
    return &info;
}

RAYVERIFY_PLUGIN_EXPORT void rayverify_plugin_intersect_batch_float(const rayverify_case_float* cases,
                                                                    rayverify_answer_float* answers, size_t count) {
    embree_world& w = world();
    RTCIntersectContext context;
    for (size_t i = 0; i < count; ++i) {
        const rayverify_case_float& k = cases[i];
        if (!embree_accepts(k)) continue;  // count stays -1: Embree would abort (see the top)
        w.set_sphere(k.centre, k.radius);

        RTCRayHit rayhit{};
        rayhit.ray.org_x = k.origin[0];
        rayhit.ray.org_y = k.origin[1];
        rayhit.ray.org_z = k.origin[2];
        rayhit.ray.dir_x = k.direction[0];
        rayhit.ray.dir_y = k.direction[1];
        rayhit.ray.dir_z = k.direction[2];
        rayhit.ray.tnear = k.tmin;
        rayhit.ray.tfar = k.tmax;
        rayhit.ray.time = 0.0f;
        rayhit.ray.mask = 0xFFFFFFFFu;
        rayhit.ray.id = 0;
        rayhit.ray.flags = 0;
        rayhit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rayhit.hit.primID = RTC_INVALID_GEOMETRY_ID;
        rayhit.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcInitIntersectContext(&context);
        rtcIntersect1(w.scene, &context, &rayhit);

        rayverify_answer_float& a = answers[i];
        if (rayhit.hit.geomID == RTC_INVALID_GEOMETRY_ID) {
            a.count = 0;
            continue;
        }
        a.count = 1;
        a.t[0] = a.t[1] = rayhit.ray.tfar;
        a.normal[0] = rayhit.hit.Ng_x;
        a.normal[1] = rayhit.hit.Ng_y;
        a.normal[2] = rayhit.hit.Ng_z;
    }
}

// The version the library reports at run time (rtcGetDeviceProperty).
RAYVERIFY_PLUGIN_EXPORT const char* rayverify_plugin_library_version(void) {
    static const std::string version = [] {
        RTCDevice device = world().device;
        return std::to_string(rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_VERSION_MAJOR)) + "." +
               std::to_string(rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_VERSION_MINOR)) + "." +
               std::to_string(rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_VERSION_PATCH));
    }();
    return version.c_str();
}

}  // extern "C"
