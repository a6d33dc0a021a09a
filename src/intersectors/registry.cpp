#include "intersectors/registry.h"

#include <array>
#include <cstddef>
#include <limits>
#include <string>
#include <type_traits>

#include "intersectors/all.h"

namespace rayverify {
namespace {

// A kind that takes an interval: run_float_in/run_double_in answer for the
// interval given, run_float/run_double for the default (0, +inf).
template <class T>
using interval_fn = root_pair<T> (*)(const ray_sphere<T>&, T, T);

template <interval_fn<float> F, interval_fn<double> D>
variant interval_variant(std::string name, std::string citation, std::string formula, contract promises) {
    variant v{std::move(name), std::move(citation), std::move(formula), promises,
              [](const ray_sphere<float>& s) { return F(s, 0.0f, std::numeric_limits<float>::infinity()); },
              [](const ray_sphere<double>& s) { return D(s, 0.0, std::numeric_limits<double>::infinity()); }};
    v.run_float_in = F;
    v.run_double_in = D;
    return v;
}

// An engine's port: its function takes (s, tmin, tmax) (the interval is
// ignored by a fixed-range contract) and returns roots or a whole answer, in
// float, double or both (nullptr: the engine has no such build).
template <class T>
using answer_fn = answer<T> (*)(const ray_sphere<T>&, T, T);

template <class T, class Fn>
void bind_engine(variant& v, Fn fn) {
    constexpr T inf = std::numeric_limits<T>::infinity();
    const auto roots = [fn](const ray_sphere<T>& s, T tmin, T tmax) {
        if constexpr (std::is_same_v<decltype(fn(s, tmin, tmax)), answer<T>>)
            return fn(s, tmin, tmax).roots;
        else
            return fn(s, tmin, tmax);
    };
    const auto plain = [roots](const ray_sphere<T>& s) { return roots(s, T(0), inf); };
    const bool interval = takes_interval(v.promises);
    if constexpr (std::is_same_v<T, float>) {
        v.run_float = plain;
        if (interval) v.run_float_in = roots;
        if constexpr (std::is_same_v<Fn, answer_fn<float>>) v.answer_float = fn;
    } else {
        v.run_double = plain;
        if (interval) v.run_double_in = roots;
        if constexpr (std::is_same_v<Fn, answer_fn<double>>) v.answer_double = fn;
    }
}

template <class FloatFn, class DoubleFn>
variant engine_variant(std::string name, std::string citation, std::string formula, contract promises,
                       std::string build, FloatFn f, DoubleFn d) {
    variant v;
    v.name = std::move(name);
    v.citation = std::move(citation);
    v.formula = std::move(formula);
    v.promises = promises;
    v.build = std::move(build);
    if constexpr (!std::is_same_v<FloatFn, std::nullptr_t>) bind_engine<float>(v, f);
    if constexpr (!std::is_same_v<DoubleFn, std::nullptr_t>) bind_engine<double>(v, d);
    return v;
}

// The robust variants decide exactly by construction (robust_sphere.h).
variant with_exact_decisions(variant v) {
    v.exact_decisions = true;
    return v;
}

// A formula of variants.def as a variant: its shape says which functions it
// binds, its family whether its decisions are exact by construction.
#define RAYVERIFY_SHAPE_plain(fn, citation, formula)                                      \
    variant{#fn, citation, formula, intersectors::fn##_contract, &intersectors::fn<float>, \
            &intersectors::fn<double>}
#define RAYVERIFY_SHAPE_interval(fn, citation, formula) \
    interval_variant<&intersectors::fn<float>, &intersectors::fn<double>>(#fn, citation, formula, intersectors::fn##_contract)
#define RAYVERIFY_FAMILY_textbook(v) v
#define RAYVERIFY_FAMILY_robust(v) with_exact_decisions(v)
#define RAYVERIFY_IN_yes(fn, T) &intersectors::fn<T>
#define RAYVERIFY_IN_no(fn, T) nullptr

// The ports whose engine takes two points (RAYVERIFY_SEGMENT_ENDS) take a
// segment case's ends: in both precisions the port runs in.
template <std::size_t N>
std::array<variant, N> with_segment_ends(std::array<variant, N> list) {
    const auto attach = [&list](std::string_view name, auto in_float, auto in_double) {
        for (variant& v : list) {
            if (v.name != name) continue;
            v.takes_segment_ends = true;
            if (v.run_float) v.segment_answer_float = in_float;
            if (v.run_double) v.segment_answer_double = in_double;
        }
    };
#define RAYVERIFY_SEGMENT_ENDS(fn) attach(#fn, &intersectors::fn##_segment<float>, &intersectors::fn##_segment<double>);
#include "intersectors/variants.def"
    return list;
}

// Its size follows from the list.
const auto registry = with_segment_ends(std::to_array<variant>({
#define RAYVERIFY_FORMULA(fn, shape, family, citation, formula) \
    RAYVERIFY_FAMILY_##family(RAYVERIFY_SHAPE_##shape(fn, citation, formula)),
#define RAYVERIFY_PORT(fn, in_float, in_double, citation, formula, build)                                 \
    engine_variant(#fn, citation, formula, intersectors::fn##_contract, build, RAYVERIFY_IN_##in_float(fn, float), \
                   RAYVERIFY_IN_##in_double(fn, double)),
#include "intersectors/variants.def"
}));

// The textbook family's names, in the list's order.
const auto textbook_names = std::to_array<std::string_view>({
#define RAYVERIFY_FORMULA(fn, shape, family, citation, formula) RAYVERIFY_NAME_IF_##family(#fn)
#define RAYVERIFY_NAME_IF_textbook(name) name,
#define RAYVERIFY_NAME_IF_robust(name)
#include "intersectors/variants.def"
#undef RAYVERIFY_NAME_IF_robust
#undef RAYVERIFY_NAME_IF_textbook
});

#undef RAYVERIFY_IN_no
#undef RAYVERIFY_IN_yes
#undef RAYVERIFY_FAMILY_robust
#undef RAYVERIFY_FAMILY_textbook
#undef RAYVERIFY_SHAPE_interval
#undef RAYVERIFY_SHAPE_plain

}  // namespace

std::span<const variant> builtin_variants() { return registry; }

std::span<const std::string_view> textbook_variant_names() { return textbook_names; }

const variant* find_builtin_variant(std::string_view name) {
    for (const variant& v : registry)
        if (v.name == name) return &v;
    return nullptr;
}

}  // namespace rayverify
