#include "intersectors/traced_variants.h"

#include <array>
#include <cstdio>
#include <type_traits>

#include "intersectors/traced.h"
// traced.h first: the intersectors below find its overloads when instantiated on traced scalars.
#include "intersectors/cycles_point.h"
#include "intersectors/embree4_sphere.h"
#include "intersectors/fma_discriminant.h"
#include "intersectors/geometric.h"
#include "intersectors/godot_segment.h"
#include "intersectors/half_b.h"
#include "intersectors/hearn_baker.h"
#include "intersectors/hearn_baker_any_hit.h"
#include "intersectors/hearn_baker_nearest.h"
#include "intersectors/hearn_baker_unit.h"
#include "intersectors/jolt_ray_sphere.h"
#include "intersectors/mitsuba3_sphere.h"
#include "intersectors/naive.h"
#include "intersectors/pbrt_v4_sphere.h"
#include "intersectors/raylib_collision.h"
#include "intersectors/robust.h"
#include "intersectors/seed003_reduced.h"
#include "intersectors/seed004_early_out.h"
#include "intersectors/stable_roots.h"
#include "intersectors/threejs_ray.h"
#include "intersectors/wald_origin_shift.h"

namespace rayverify {
namespace {

// The roots the run returned, as steps "answer t0" and "answer t1" ("answer t" for a single
// root); a root no operation produced (an any-hit answer's 0) is left out.
template <class T, class Result>
void record_roots(const Result& result) {
    const root_pair<traced<T>>* roots = nullptr;
    if constexpr (std::is_same_v<Result, root_pair<traced<T>>>)
        roots = &result;
    else
        roots = &result.roots;
    const auto produced = [](traced<T> t) { return t.ideal != exact_as_computed || t.value != 0; };
    if (roots->count == 1 && produced(roots->t0)) step("answer t", roots->t0);
    if (roots->count == 2) {
        step("answer t0", roots->t0);
        step("answer t1", roots->t1);
    }
}

// robust_sphere.h is a self-contained header that runs on float and double
// only: its static filter's own values (a, b′, C, Δ′ in double, from its
// filter_state) beside the exact values of the same quantities, derived from
// the exact inputs; then its roots, correctly rounded by construction.
template <class T>
void trace_robust_filter(const ray_sphere<T>& s) {
    using robust_sphere::detail::fast_solver;
    fast_solver<T, false> solver(intersectors::robust_ray(s), intersectors::robust_target(s));
    solver.line_class();  // tries Lagrange's form where b′² − aC cannot decide
    const auto filter = solver.filter_state();

    using W = traced<double>;
    const auto widen = [](vec3<T> v) { return vec3<W>{double(v.x), double(v.y), double(v.z)}; };
    const vec3<W> d = widen(s.direction), f = widen(s.origin) - widen(s.centre);
    const W r = double(s.radius);
    const W a = dot(d, d), b_prime = dot(d, f), C = dot(f, f) - r * r;
    const W discriminant = b_prime * b_prime - a * C;  // equal, exactly, to Lagrange's a·r² − |d × f|²
    step("a", computed_apart(filter.a, a));
    step("b′", computed_apart(filter.b_prime, b_prime));
    step("C", computed_apart(filter.C, C));
    const bool decided = filter.discriminant > filter.discriminant_bound || filter.discriminant < -filter.discriminant_bound;
    char note[160];
    std::snprintf(note, sizeof note, "%s in double, bound %.3g: %s",
                  filter.lagrange ? "Lagrange's a·r² − |d × f|²" : "b′² − aC", filter.discriminant_bound,
                  decided ? "the filter decides the class" : "left to the double-word and exact stages");
    step("Δ′", computed_apart(filter.discriminant, discriminant), note);
}

// The variant's own template run on traced T: a kind that takes no interval
// (s), or one that does (s, tmin, tmax); then its roots.
#define RAYVERIFY_PLAIN(fn, T) \
    [](const ray_sphere<T>& s, T, T) { record_roots<T>(intersectors::fn<traced<T>>(traced_inputs(s))); }
#define RAYVERIFY_RANGED(fn, T)                                                               \
    [](const ray_sphere<T>& s, T tmin, T tmax) {                                              \
        record_roots<T>(intersectors::fn<traced<T>>(traced_inputs(s), tmin, tmax));           \
    }
#define RAYVERIFY_BOTH(kind, fn) {#fn, kind(fn, float), kind(fn, double), {}}

constexpr std::string_view robust_what =
    "robust_sphere.h runs on float and double only: its static filter's values, computed in double, beside "
    "the exact values of the same quantities from the exact inputs";
constexpr trace_fn<float> robust_float = [](const ray_sphere<float>& s, float, float) { trace_robust_filter(s); };
constexpr trace_fn<double> robust_double = [](const ray_sphere<double>& s, double, double) { trace_robust_filter(s); };

const std::array<variant_trace, 29> traces{{
    RAYVERIFY_BOTH(RAYVERIFY_PLAIN, naive),
    RAYVERIFY_BOTH(RAYVERIFY_PLAIN, half_b),
    RAYVERIFY_BOTH(RAYVERIFY_PLAIN, seed003_reduced),
    RAYVERIFY_BOTH(RAYVERIFY_PLAIN, seed004_early_out),
    RAYVERIFY_BOTH(RAYVERIFY_PLAIN, geometric),
    RAYVERIFY_BOTH(RAYVERIFY_PLAIN, stable_roots),
    RAYVERIFY_BOTH(RAYVERIFY_PLAIN, hearn_baker),
    RAYVERIFY_BOTH(RAYVERIFY_PLAIN, fma_discriminant),
    RAYVERIFY_BOTH(RAYVERIFY_RANGED, hearn_baker_any_hit),
    RAYVERIFY_BOTH(RAYVERIFY_RANGED, hearn_baker_nearest),
    RAYVERIFY_BOTH(RAYVERIFY_PLAIN, hearn_baker_unit),
    RAYVERIFY_BOTH(RAYVERIFY_RANGED, hearn_baker_unit_nearest),
    RAYVERIFY_BOTH(RAYVERIFY_RANGED, hearn_baker_unit_any_hit),
    RAYVERIFY_BOTH(RAYVERIFY_PLAIN, wald_origin_shift),
    {"robust", robust_float, robust_double, robust_what},
    {"robust_nearest", robust_float, robust_double, robust_what},
    {"robust_any_hit", robust_float, robust_double, robust_what},
    {"robust_bounded", robust_float, robust_double, robust_what},
    {"robust_bounded_nearest", robust_float, robust_double, robust_what},
    {"pbrt_v4", RAYVERIFY_RANGED(pbrt_v4, float), RAYVERIFY_RANGED(pbrt_v4, double),
     "interval arithmetic: each end of an interval beside the value it encloses"},
    RAYVERIFY_BOTH(RAYVERIFY_RANGED, mitsuba3_preliminary),
    RAYVERIFY_BOTH(RAYVERIFY_RANGED, mitsuba3_ray_test),
    {"embree4", RAYVERIFY_RANGED(embree4, float), nullptr, {}},
    {"cycles_point", RAYVERIFY_RANGED(cycles_point, float), nullptr, {}},
    {"jolt", RAYVERIFY_RANGED(jolt, float), nullptr, {}},
    {"jolt_fma", RAYVERIFY_RANGED(jolt_fma, float), nullptr, {}},
    {"threejs", nullptr, RAYVERIFY_RANGED(threejs, double), {}},
    RAYVERIFY_BOTH(RAYVERIFY_RANGED, godot),
    {"raylib", RAYVERIFY_RANGED(raylib, float), nullptr, {}},
}};

#undef RAYVERIFY_BOTH
#undef RAYVERIFY_RANGED
#undef RAYVERIFY_PLAIN

}  // namespace

const variant_trace* find_builtin_trace(std::string_view name) {
    for (const variant_trace& t : traces)
        if (t.name == name) return &t;
    return nullptr;
}

}  // namespace rayverify
