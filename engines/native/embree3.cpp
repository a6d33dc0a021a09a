// Embree 3 as Debian's libembree3 installs it, audited as a plugin: a device,
// a scene with one RTC_GEOMETRY_TYPE_SPHERE_POINT geometry (one vertex:
// centre and radius, float4), committed, and rtcIntersect1 with an RTCRayHit
// whose tnear/tfar are the case's range. Built several times from this file:
// default scene flags (embree3), RTC_SCENE_FLAG_ROBUST (embree3_robust, with
// RAYVERIFY_EMBREE_ROBUST defined), and one kernel pinned (embree3_sse2 ...
// embree3_avx512, with RAYVERIFY_EMBREE_PINNED_KERNEL and
// RAYVERIFY_EMBREE_TARGET_NAME defined).
//
// The kernel. Embree 3 picks one of the kernels it was built with (Debian's:
// sse2, sse4.2, avx, avx2, avx512) from the CPU's instruction set when the
// device is made, unless the device's configuration names one ("isa=sse2");
// the kernels answer differently (AVX2 fuses multiply-adds, AVX-512 takes the
// reciprocal estimate from rcp14ps instead of rcpps). The plugin reports the
// kernel its device runs (rayverify_plugin_library_configuration), as Embree
// itself says it: a second device made with "verbose=1" prints the targets
// the configuration enables and those compiled in, and the kernel is the
// highest target in both. A pinned kernel this CPU cannot run, or one the
// library was built without, makes the plugin unavailable here
// (rayverify_plugin_unavailable). For tests only, RAYVERIFY_TEST_EMBREE_KERNEL
// makes an unpinned target run that kernel, as on a CPU whose best kernel it
// is, and the configuration says so.
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
// |dir| coordinate <= FLT_LARGE = 1.844e18, tnear and tfar not NaN) and,
// in the BVH traversal (kernels/bvh/bvh_intersector1.cpp), tnear >= 0: a
// negative tnear (an interval that starts behind the origin, as the
// range-end families give) aborts the program. The plugin makes the same
// tests first and, for a ray that would fail them, leaves the answer as
// rayverify handed it over (count -1): the verdict malformed_output says
// "the library does not answer this".
//
// Cost: one sphere per case means one vertex update per case:
// rtcUpdateGeometryBuffer + rtcCommitGeometry + rtcCommitScene, a BVH
// rebuild of a one-primitive scene through Embree's task scheduler (of the
// order of microseconds to tens of microseconds, far more than the ray
// itself). A case with the same sphere as the one before reuses the
// committed scene.
#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "rayverify_plugin.h"

namespace {

#if defined(RAYVERIFY_EMBREE_PINNED_KERNEL)
constexpr const char* plugin_name = RAYVERIFY_EMBREE_TARGET_NAME;
constexpr const char* pinned_kernel = RAYVERIFY_EMBREE_PINNED_KERNEL;
constexpr const char* plugin_build =
    "Debian 12 package libembree-dev 3.13.5, float, as packaged, its kernel pinned (rtcNewDevice(\"isa="
    RAYVERIFY_EMBREE_PINNED_KERNEL "\")); default scene flags";
#elif defined(RAYVERIFY_EMBREE_ROBUST)
constexpr const char* plugin_name = "embree3_robust";
constexpr const char* pinned_kernel = nullptr;
constexpr const char* plugin_build =
    "Debian 12 package libembree-dev 3.13.5, float, as packaged (the device's kernel chosen at run time from the "
    "CPU); scene flags RTC_SCENE_FLAG_ROBUST";
#else
constexpr const char* plugin_name = "embree3";
constexpr const char* pinned_kernel = nullptr;
constexpr const char* plugin_build =
    "Debian 12 package libembree-dev 3.13.5, float, as packaged (the device's kernel chosen at run time from the "
    "CPU); default scene flags";
#endif
constexpr const char* plugin_contract =
    "query=nearest_hit,range=interval,ends=[],inside=far_root,tangent=hit,faces=both,unit_direction=no,normal=yes";
constexpr const char* test_kernel_variable = "RAYVERIFY_TEST_EMBREE_KERNEL";

// Embree's names of its kernels in verbose output, with the configuration's
// names for them, lowest first.
struct kernel_name {
    const char* in_verbose_output;
    const char* in_configuration;
};
constexpr kernel_name embree_kernels[] = {
    {"SSE2", "sse2"}, {"SSE4.2", "sse4.2"}, {"AVX", "avx"}, {"AVX2", "avx2"}, {"AVX512", "avx512"}};

bool is_kernel_name(const std::string& name) {
    for (const kernel_name& k : embree_kernels)
        if (name == k.in_configuration) return true;
    return false;
}

// The words of the verbose output's line that ends with `suffix`.
std::vector<std::string> targets_line(const std::string& verbose, const std::string& suffix) {
    std::istringstream lines(verbose);
    std::string line;
    while (std::getline(lines, line)) {
        const std::size_t at = line.find(suffix);
        if (at == std::string::npos) continue;
        std::istringstream words(line.substr(0, at));
        std::vector<std::string> out;
        for (std::string w; words >> w;)
            if (w != "Targets" && w != ":") out.push_back(w);
        return out;
    }
    return {};
}

// What Embree says of a device made with `config`: the kernel it runs (the
// highest target both enabled and compiled in, as Embree names it in its
// configuration; empty when the output names none) and the kernels compiled
// in. Embree prints it to std::cout when the device is made with verbose=1;
// the plugin reads it through std::cout's buffer (the library and the plugin
// share libstdc++'s std::cout), while rayverify loads the plugin on one thread.
struct kernel_report {
    bool device_made = false;
    std::string kernel;
    std::vector<std::string> compiled;  // configuration names
    std::string error;                  // when the device could not be made
};

kernel_report ask_embree(const std::string& config) {
    const std::string verbose_config = config.empty() ? "verbose=1" : config + ",verbose=1";
    std::ostringstream captured;
    std::streambuf* const previous = std::cout.rdbuf(captured.rdbuf());
    RTCDevice probe = rtcNewDevice(verbose_config.c_str());
    std::cout.rdbuf(previous);
    kernel_report out;
    if (probe == nullptr) {
        out.error = rtcGetDeviceError(nullptr) == RTC_ERROR_UNSUPPORTED_CPU ? "this CPU does not support it"
                                                                            : "rtcNewDevice failed";
        return out;
    }
    out.device_made = true;
    rtcReleaseDevice(probe);
    const std::vector<std::string> enabled = targets_line(captured.str(), "(supported)");
    const std::vector<std::string> compiled = targets_line(captured.str(), "(compile time enabled)");
    const auto has = [](const std::vector<std::string>& list, const char* name) {
        return std::find(list.begin(), list.end(), name) != list.end();
    };
    for (const kernel_name& k : embree_kernels) {
        if (!has(compiled, k.in_verbose_output)) continue;
        out.compiled.push_back(k.in_configuration);
        if (has(enabled, k.in_verbose_output)) out.kernel = k.in_configuration;
    }
    return out;
}

// How the device is configured and what runs: the configuration string
// passed to rtcNewDevice, the kernel, the line reported, and why the plugin
// cannot run here (empty when it can).
struct device_setup {
    std::string config;
    std::string configuration_line;
    std::string unavailable;
};

device_setup choose_device() {
    device_setup out;
    std::string forced;
    enum class chosen_by { embree, pin, test_hook } how = chosen_by::embree;
    if (pinned_kernel != nullptr) {
        forced = pinned_kernel;
        how = chosen_by::pin;
    } else if (const char* test = std::getenv(test_kernel_variable); test != nullptr && *test != '\0') {
        forced = test;
        how = chosen_by::test_hook;
        if (!is_kernel_name(forced)) {
            out.unavailable = std::string(test_kernel_variable) + "='" + forced +
                              "' names no Embree kernel (sse2, sse4.2, avx, avx2, avx512)";
            return out;
        }
    }
    if (!forced.empty()) out.config = "isa=" + forced;
    const kernel_report report = ask_embree(out.config);
    if (!forced.empty() && report.device_made &&
        std::find(report.compiled.begin(), report.compiled.end(), forced) == report.compiled.end()) {
        out.unavailable = "this Embree was built without its " + forced + " kernel";
        return out;
    }
    if (!report.device_made) {
        out.unavailable = forced.empty() ? "Embree could not make a device (" + report.error + ")"
                                         : "this CPU does not run Embree's " + forced + " kernel (" + report.error + ")";
        return out;
    }
    const std::string kernel = report.kernel.empty() ? "unknown (Embree's verbose output named none)" : report.kernel;
    switch (how) {
        case chosen_by::embree: out.configuration_line = "kernel " + kernel + ", Embree's choice for this CPU"; break;
        case chosen_by::pin: out.configuration_line = "kernel " + kernel + ", pinned with isa=" + forced; break;
        case chosen_by::test_hook:
            out.configuration_line = "kernel " + kernel + ", set by " + test_kernel_variable +
                                     " (a test hook: as on a CPU whose best kernel it is)";
            break;
    }
    return out;
}

// Embree's ray.valid() (kernels/common/ray.h) and tnear >= 0
// (kernels/bvh/bvh_intersector1.cpp), which its rtcIntersect1 asserts.
constexpr float embree_flt_large = 1.844E18f;
bool embree_accepts(const rayverify_case_float& k) {
    for (int axis = 0; axis < 3; ++axis)
        if (!(std::fabs(k.origin[axis]) <= embree_flt_large) || !(std::fabs(k.direction[axis]) <= embree_flt_large))
            return false;
    return !std::isnan(k.tmin) && !std::isnan(k.tmax) && k.tmin >= 0.0f;
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

    device_setup setup = choose_device();

    embree_world() {
        if (!setup.unavailable.empty()) return;  // no device: every case stays unanswered
        device = rtcNewDevice(setup.config.empty() ? nullptr : setup.config.c_str());
        if (device == nullptr) {
            setup.unavailable = "Embree could not make a device with \"" + setup.config + "\"";
            return;
        }
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
    if (w.device == nullptr) return;  // unavailable here: every count stays -1
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
        if (device == nullptr) return std::string();
        return std::to_string(rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_VERSION_MAJOR)) + "." +
               std::to_string(rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_VERSION_MINOR)) + "." +
               std::to_string(rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_VERSION_PATCH));
    }();
    return version.empty() ? nullptr : version.c_str();
}

// The kernel this device runs, and how it was chosen (see the top).
RAYVERIFY_PLUGIN_EXPORT const char* rayverify_plugin_library_configuration(void) {
    const std::string& line = world().setup.configuration_line;
    return line.empty() ? nullptr : line.c_str();
}

RAYVERIFY_PLUGIN_EXPORT const char* rayverify_plugin_unavailable(void) {
    const std::string& why = world().setup.unavailable;
    return why.empty() ? nullptr : why.c_str();
}

}  // extern "C"
