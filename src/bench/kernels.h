// The intersectors as concrete callables for timing: each entry is a generic
// lambda naming the intersector template directly, so a loop instantiated
// over it inlines the formula (no std::function or virtual call per case, as
// the registry's run_float/run_double would add). Both expand variants.def;
// tests/bench_test.cpp checks that each kernel returns exactly what the
// registry's function returns. Engine ports (a
// variant with a `build`) are not here: they run in the precisions their
// engines have, not in long double, and are timed through their functions.
#pragma once

#include <string_view>
#include <type_traits>

#include "intersectors/all.h"

namespace rayverify::bench {

// Calls visit(name, kernel) for every built-in formula (variants.def's
// RAYVERIFY_FORMULA entries), in registry order;
// kernel(s) works for ray_sphere<float> and <double>, and for <long double>
// where the intersector is written for it (has_long_double; robust_sphere.h
// is float and double only). kernel(s, tmin, tmax) asks a kind that takes an
// interval for (tmin, tmax) (kernel(s) for (0, +inf)); the other kinds ignore
// the interval, like run_in (registry.h).
template <class Visitor>
void for_each_kernel(Visitor&& visit) {
#define RAYVERIFY_KERNEL(fn)                                                                          \
    visit(std::string_view(#fn), [](const auto& s, auto... /*interval*/) -> decltype(intersectors::fn(s)) { \
        return intersectors::fn(s);                                                                   \
    })
#define RAYVERIFY_INTERVAL_KERNEL(fn)                                                                          \
    visit(std::string_view(#fn), [](const auto& s, auto... interval) -> decltype(intersectors::fn(s, interval...)) { \
        return intersectors::fn(s, interval...);                                                               \
    })
#define RAYVERIFY_SHAPE_plain RAYVERIFY_KERNEL
#define RAYVERIFY_SHAPE_interval RAYVERIFY_INTERVAL_KERNEL
#define RAYVERIFY_FORMULA(fn, shape, family, citation, formula) RAYVERIFY_SHAPE_##shape(fn);
#include "intersectors/variants.def"
#undef RAYVERIFY_SHAPE_interval
#undef RAYVERIFY_SHAPE_plain
#undef RAYVERIFY_INTERVAL_KERNEL
#undef RAYVERIFY_KERNEL
}

// Whether a kernel runs in long double.
template <class Kernel>
inline constexpr bool has_long_double = std::is_invocable_v<Kernel, const ray_sphere<long double>&>;

}  // namespace rayverify::bench
