#include "intersectors/traced_variants.h"

#include <array>
#include <cstdio>
#include <type_traits>

#include "intersectors/traced.h"
// traced.h first: the intersectors below find its overloads when instantiated on traced scalars.
#include "intersectors/all.h"

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

constexpr std::string_view robust_what =
    "robust_sphere.h runs on float and double only: its static filter's values, computed in double, beside "
    "the exact values of the same quantities from the exact inputs";
constexpr trace_fn<float> robust_float = [](const ray_sphere<float>& s, float, float) { trace_robust_filter(s); };
constexpr trace_fn<double> robust_double = [](const ray_sphere<double>& s, double, double) { trace_robust_filter(s); };

// What a port's steps are when they are not plain arithmetic; else empty.
constexpr std::string_view port_what(std::string_view name) {
    return name == "pbrt_v4" ? "interval arithmetic: each end of an interval beside the value it encloses" : "";
}

// A textbook formula runs traced in its own shape; robust_sphere.h shows its filter.
#define RAYVERIFY_TRACE_textbook(fn, shape) {#fn, shape(fn, float), shape(fn, double), {}}
#define RAYVERIFY_TRACE_robust(fn, shape) {#fn, robust_float, robust_double, robust_what}
#define RAYVERIFY_SHAPE_plain RAYVERIFY_PLAIN
#define RAYVERIFY_SHAPE_interval RAYVERIFY_RANGED
#define RAYVERIFY_IN_yes(fn, T) RAYVERIFY_RANGED(fn, T)
#define RAYVERIFY_IN_no(fn, T) nullptr

// Every built-in variant (variants.def), in its order.
const auto traces = std::to_array<variant_trace>({
#define RAYVERIFY_FORMULA(fn, shape, family, citation, formula) RAYVERIFY_TRACE_##family(fn, RAYVERIFY_SHAPE_##shape),
#define RAYVERIFY_PORT(fn, in_float, in_double, citation, formula, build) \
    {#fn, RAYVERIFY_IN_##in_float(fn, float), RAYVERIFY_IN_##in_double(fn, double), port_what(#fn)},
#include "intersectors/variants.def"
});

#undef RAYVERIFY_IN_no
#undef RAYVERIFY_IN_yes
#undef RAYVERIFY_SHAPE_interval
#undef RAYVERIFY_SHAPE_plain
#undef RAYVERIFY_TRACE_robust
#undef RAYVERIFY_TRACE_textbook
#undef RAYVERIFY_RANGED
#undef RAYVERIFY_PLAIN

}  // namespace

const variant_trace* find_builtin_trace(std::string_view name) {
    for (const variant_trace& t : traces)
        if (t.name == name) return &t;
    return nullptr;
}

}  // namespace rayverify
