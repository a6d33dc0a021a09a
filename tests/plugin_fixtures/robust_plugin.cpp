// robust_sphere.h built as a user's project builds it, into a version 2
// plugin, one per query level and tier (ROBUST_QUERY below), so that tests
// audit and hunt it through `rayverify audit --plugin` / `hunt --plugin` like
// any user's intersector. ROBUST_PLUGIN_SUFFIX names the build and
// ROBUST_PLUGIN_FLAGS states its flags: robust_fma_test builds it as GPU
// compilers do on a CPU (-mfma -ffp-contract=fast: every a·b + c may become
// one fused operation, as nvcc's default -fmad=true does), robust_cxx17_test
// as a C++17 project does, with gcc and with clang.
#include "rayverify_plugin.h"
#include "robust_sphere.h"

namespace rs = robust_sphere;

#if !defined(ROBUST_QUERY)
#error "ROBUST_QUERY: 0 line roots, 1 nearest hit, 2 any hit, 3 bounded line roots, 4 bounded nearest hit, 5 segment hit (contact at the start), 6 segment hit (the exit, open ends)"
#endif
#if !defined(ROBUST_PLUGIN_SUFFIX) || !defined(ROBUST_PLUGIN_FLAGS)
#error "ROBUST_PLUGIN_SUFFIX (\"_fma\") and ROBUST_PLUGIN_FLAGS (\"-O2 -mfma ...\") name and describe the build"
#endif

namespace {

#if ROBUST_QUERY == 0
constexpr const char* plugin_name = "robust" ROBUST_PLUGIN_SUFFIX;
constexpr const char* spec = "query=line_roots,reports_tangent=yes";
constexpr const char* tangent_rule = "Δ′ == 0 (exact)";
#elif ROBUST_QUERY == 1
constexpr const char* plugin_name = "robust_nearest" ROBUST_PLUGIN_SUFFIX;
constexpr const char* tangent_rule = nullptr;
constexpr const char* spec = "query=nearest_hit,range=interval";
#elif ROBUST_QUERY == 2
constexpr const char* plugin_name = "robust_any_hit" ROBUST_PLUGIN_SUFFIX;
constexpr const char* tangent_rule = nullptr;
constexpr const char* spec = "query=any_hit,range=interval";
#elif ROBUST_QUERY == 3
constexpr const char* plugin_name = "robust_bounded" ROBUST_PLUGIN_SUFFIX;
constexpr const char* spec = "query=line_roots,reports_tangent=yes";
constexpr const char* tangent_rule = "Δ′ == 0 (exact)";
#elif ROBUST_QUERY == 4
constexpr const char* plugin_name = "robust_bounded_nearest" ROBUST_PLUGIN_SUFFIX;
constexpr const char* tangent_rule = nullptr;
constexpr const char* spec = "query=nearest_hit,range=interval";
#elif ROBUST_QUERY == 5
constexpr const char* plugin_name = "robust_segment" ROBUST_PLUGIN_SUFFIX;
constexpr const char* tangent_rule = nullptr;
constexpr const char* spec = "query=nearest_hit,range=interval,ends=[],inside=clamp,cast=segment";
#else
constexpr const char* plugin_name = "robust_segment_exit" ROBUST_PLUGIN_SUFFIX;
constexpr const char* tangent_rule = nullptr;
constexpr const char* spec = "query=nearest_hit,range=interval,ends=(),inside=far_root,cast=segment";
#endif

template <class T, class Case, class Answer>
void answer_all(const Case* cases, Answer* answers, size_t n) {
    using rs::ends;
    for (size_t i = 0; i < n; ++i) {
        const Case& c = cases[i];
        const rs::ray<T> r{{c.origin[0], c.origin[1], c.origin[2]}, {c.direction[0], c.direction[1], c.direction[2]}};
        const rs::sphere<T> s{{c.centre[0], c.centre[1], c.centre[2]}, c.radius};
        Answer& a = answers[i];
#if ROBUST_QUERY == 0 || ROBUST_QUERY == 3
        constexpr rs::roots tier = ROBUST_QUERY == 0 ? rs::roots::correctly_rounded : rs::roots::bounded;
        const rs::line_roots<T> l = rs::intersect_line<tier>(r, s);
        a.count = l.count;
        a.t[0] = l.t0, a.t[1] = l.t1;
#elif ROBUST_QUERY == 1 || ROBUST_QUERY == 4
        constexpr rs::roots tier = ROBUST_QUERY == 1 ? rs::roots::correctly_rounded : rs::roots::bounded;
        const rs::ray_hit<T> h = rs::nearest_hit<ends::open, ends::open, tier>(r, s, c.tmin, c.tmax);
        a.count = h.found ? 1 : 0;
        a.t[0] = a.t[1] = h.t;
#else
        a.count = rs::any_hit(r, s, c.tmin, c.tmax) ? 1 : 0;
#endif
    }
}

// robust_sphere.h's segment query on the ends as given.
template <class T, class Segment, class Answer>
void answer_segments(const Segment* segments, Answer* answers, size_t n) {
    using rs::ends;
    for (size_t i = 0; i < n; ++i) {
        const Segment& g = segments[i];
        const rs::segment<T> seg{{g.p0[0], g.p0[1], g.p0[2]}, {g.p1[0], g.p1[1], g.p1[2]}};
        const rs::sphere<T> s{{g.centre[0], g.centre[1], g.centre[2]}, g.radius};
#if ROBUST_QUERY == 5
        const rs::ray_hit<T> h = rs::segment_hit(seg, s);
#else
        const rs::ray_hit<T> h = rs::segment_hit<ends::open, ends::open, rs::start_inside::exit>(seg, s);
#endif
        answers[i].count = h.found ? 1 : 0;
        answers[i].t[0] = answers[i].t[1] = h.t;
    }
}

}  // namespace

extern "C" {

RAYVERIFY_PLUGIN_EXPORT const rayverify_plugin_info_v2* rayverify_plugin_describe_v2(void) {
    static const rayverify_plugin_info_v2 info = {RAYVERIFY_PLUGIN_ABI_VERSION_2,
                                                  plugin_name,
                                                  "rayverify robust_sphere.h (tests/plugin_fixtures/robust_plugin.cpp)",
                                                  "as the built-in robust variants",
                                                  ROBUST_PLUGIN_FLAGS,
                                                  spec,
                                                  tangent_rule,
                                                  RAYVERIFY_FLOAT | RAYVERIFY_DOUBLE};
    return &info;
}

#if ROBUST_QUERY >= 5
RAYVERIFY_PLUGIN_EXPORT void rayverify_plugin_intersect_segments_double(const rayverify_segment_double* segments,
                                                                        rayverify_answer_double* answers, size_t n) {
    answer_segments<double>(segments, answers, n);
}

RAYVERIFY_PLUGIN_EXPORT void rayverify_plugin_intersect_segments_float(const rayverify_segment_float* segments,
                                                                       rayverify_answer_float* answers, size_t n) {
    answer_segments<float>(segments, answers, n);
}
#else
RAYVERIFY_PLUGIN_EXPORT void rayverify_plugin_intersect_batch_double(const rayverify_case_double* cases,
                                                                     rayverify_answer_double* answers, size_t n) {
    answer_all<double>(cases, answers, n);
}

RAYVERIFY_PLUGIN_EXPORT void rayverify_plugin_intersect_batch_float(const rayverify_case_float* cases,
                                                                    rayverify_answer_float* answers, size_t n) {
    answer_all<float>(cases, answers, n);
}
#endif

}  // extern "C"
