// The intersectors as concrete callables for timing: each entry is a generic
// lambda naming the intersector template directly, so a loop instantiated
// over it inlines the formula (no std::function or virtual call per case, as
// the registry's run_float/run_double would add). Names match the registry;
// tests/bench_test.cpp checks that both lists agree and that each kernel
// returns exactly what the registry's function returns. Engine ports (a
// variant with a `build`) are not here: they run in the precisions their
// engines have, not in long double, and are timed through their functions.
#pragma once

#include <string_view>
#include <type_traits>

#include "intersectors/fma_discriminant.h"
#include "intersectors/geometric.h"
#include "intersectors/half_b.h"
#include "intersectors/hearn_baker.h"
#include "intersectors/hearn_baker_any_hit.h"
#include "intersectors/hearn_baker_nearest.h"
#include "intersectors/hearn_baker_unit.h"
#include "intersectors/naive.h"
#include "intersectors/robust.h"
#include "intersectors/seed003_reduced.h"
#include "intersectors/seed004_early_out.h"
#include "intersectors/stable_roots.h"
#include "intersectors/wald_origin_shift.h"

namespace rayverify::bench {

// Calls visit(name, kernel) for every built-in formula, in registry order;
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
    RAYVERIFY_KERNEL(naive);
    RAYVERIFY_KERNEL(half_b);
    RAYVERIFY_KERNEL(seed003_reduced);
    RAYVERIFY_KERNEL(seed004_early_out);
    RAYVERIFY_KERNEL(geometric);
    RAYVERIFY_KERNEL(stable_roots);
    RAYVERIFY_KERNEL(hearn_baker);
    RAYVERIFY_KERNEL(fma_discriminant);
    RAYVERIFY_INTERVAL_KERNEL(hearn_baker_any_hit);
    RAYVERIFY_INTERVAL_KERNEL(hearn_baker_nearest);
    RAYVERIFY_KERNEL(hearn_baker_unit);
    RAYVERIFY_INTERVAL_KERNEL(hearn_baker_unit_nearest);
    RAYVERIFY_INTERVAL_KERNEL(hearn_baker_unit_any_hit);
    RAYVERIFY_KERNEL(wald_origin_shift);
    RAYVERIFY_KERNEL(robust);
    RAYVERIFY_INTERVAL_KERNEL(robust_nearest);
    RAYVERIFY_INTERVAL_KERNEL(robust_any_hit);
    RAYVERIFY_KERNEL(robust_bounded);
    RAYVERIFY_INTERVAL_KERNEL(robust_bounded_nearest);
#undef RAYVERIFY_INTERVAL_KERNEL
#undef RAYVERIFY_KERNEL
}

// Whether a kernel runs in long double.
template <class Kernel>
inline constexpr bool has_long_double = std::is_invocable_v<Kernel, const ray_sphere<long double>&>;

}  // namespace rayverify::bench
