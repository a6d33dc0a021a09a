// The registry of floating-point intersectors: every variant with its name,
// source, formula and contract, callable in float and in double. The CLI,
// tests and benchmarks iterate over it instead of naming variants.
#pragma once

#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>

#include "core/intersection.h"
#include "core/ray_sphere_case.h"

namespace rayverify {

// One case of a batch call: the inputs in precision T and the range they are
// asked on (as run_*_in would be; (0, +inf) or the contract's fixed range otherwise).
template <class T>
struct batch_case {
    ray_sphere<T> input;
    ray_interval<T> interval;
    // A segment case's p1 as the target receives it (input.origin is p0);
    // read by a target that takes segment ends (variant::takes_segment_ends).
    vec3<T> segment_end{};
    bool segment = false;  // a segment case: segment_end holds its p1
};

// A library audited as its package installs it (an --engine target, or a
// plugin that says which version of the library it wraps answered): named in
// reports beside the target.
struct library_identity {
    std::string name;     // e.g. "Embree 3"; empty when only the version is known
    std::string version;  // as the library reports it, else as its package manager does; empty when unknown
    std::string source;   // where it comes from, e.g. "Debian package libembree-dev", "npm package three"
    // What of the library's own set-up decides its answers and may differ
    // between machines running the same binary, e.g. "kernel avx2, Embree's
    // choice for this CPU"; empty when nothing does (rayverify_plugin.h,
    // rayverify_plugin_library_configuration).
    std::string configuration;
};

// One timed pass of a target's plain function over many cases: given the
// cases, it sets up once (outside the timed region) and returns the pass
// itself, which bench runs many times and which returns the sum of the hit
// counts. A target whose calls go through a harness (an in-process plugin: its
// guard buffer, crash marker and floating-point environment) sets and checks
// the harness once per pass, not once per case, so that bench times the
// formula as it times a built-in's inlined loop (bench/timing.cpp).
template <class T>
using timed_pass_fn = std::function<std::function<long long()>(std::span<const ray_sphere<T>>)>;

struct variant {
    std::string name;      // stable identifier used on the command line and in reports
    std::string citation;  // where the formula comes from
    std::string formula;   // one line, in the paper's notation
    contract promises;
    // Empty when the variant does not run in that precision. A std::function
    // so that a variant can carry state (a plugin's loaded symbol, a mutant).
    // For a kind that takes an interval (takes_interval(promises.query)) these
    // answer for the default interval (0, +inf), and run_*_in take the ray's.
    std::function<root_pair<float>(const ray_sphere<float>&)> run_float;
    std::function<root_pair<double>(const ray_sphere<double>&)> run_double;
    // False when the functions must never run concurrently (a plugin: its ABI
    // promises calls from one thread); an audit with such a variant runs on one thread.
    bool thread_safe = true;
    // True when a segment case reaches the batch functions below with its
    // end points (batch_case::segment): a plugin exporting the segment entry
    // (rayverify_plugin.h), alone (contract cast=segment: segment cases only)
    // or beside its ray batch (an engine whose API takes two points).
    bool takes_segment_ends = false;
    // Set only for a built-in port whose engine takes two points
    // (RAYVERIFY_SEGMENT_ENDS in variants.def): a segment case answered from
    // its ray form (s.origin = p0) and p1 as given.
    std::function<answer<float>(const ray_sphere<float>&, const vec3<float>&)> segment_answer_float{};
    std::function<answer<double>(const ray_sphere<double>&, const vec3<double>&)> segment_answer_double{};
    // True when the class, every root's side and every interval decision are
    // exact for all inputs by construction (robust_sphere.h), not just on the
    // cases audited so far: `recommend` prefers it when no wrong ray is allowed.
    bool exact_decisions = false;
    // Set only for kinds that take an interval: the same intersector, asked
    // for (tmin, tmax).
    std::function<root_pair<float>(const ray_sphere<float>&, float, float)> run_float_in{};
    std::function<root_pair<double>(const ray_sphere<double>&, double, double)> run_double_in{};
    // Set only when the contract names outputs beside t or a point answer
    // (contract::outputs, contract::answer): the whole answer on (tmin, tmax),
    // which run_* and run_*_in return the roots of.
    std::function<answer<float>(const ray_sphere<float>&, float, float)> answer_float{};
    std::function<answer<double>(const ray_sphere<double>&, double, double)> answer_double{};
    // Set only for a variant that answers many cases in one call (a plugin of
    // ABI version 2): answers[i] for cases[i]. The audit calls it once per
    // chunk of cases; the single-case functions above call it with one.
    std::function<void(std::span<const batch_case<float>>, std::span<answer<float>>)> batch_float{};
    std::function<void(std::span<const batch_case<double>>, std::span<answer<double>>)> batch_double{};
    // Set only for a target whose per-call harness bench should leave out of
    // its timings (an in-process plugin): its plain function over many cases
    // in one pass (timed_pass_fn).
    timed_pass_fn<float> timed_pass_float{};
    timed_pass_fn<double> timed_pass_double{};
    // An engine's port: which build of the engine it models (precision of the
    // rays and of the arithmetic, real or unfused multiply-adds, how a
    // reciprocal is computed, flags that change rounding); empty for a
    // formula. Printed beside the variant.
    std::string build{};
    // Set for a target that is a library as shipped (see library_identity).
    std::optional<library_identity> library{};
    // The floating-point environment its calls run in when it is not the
    // IEEE default, and how it came about ("FTZ+DAZ, set when the library
    // loaded ...", "rounding upward (--fp-env upward)"); empty otherwise.
    std::string fp_environment{};

    bool runs_in(precision p) const {
        return p == precision::binary32 ? static_cast<bool>(run_float) : static_cast<bool>(run_double);
    }
};

// Run a variant in precision T on (tmin, tmax): through run_*_in when its kind
// takes an interval, else its plain function (whose answer does not depend on
// an interval; the judge filters its roots into one: compare/judge.h).
template <class T>
root_pair<T> run_in(const variant& v, const ray_sphere<T>& s, ray_interval<T> interval) {
    if constexpr (std::is_same_v<T, float>)
        return v.run_float_in ? v.run_float_in(s, interval.tmin, interval.tmax) : v.run_float(s);
    else
        return v.run_double_in ? v.run_double_in(s, interval.tmin, interval.tmax) : v.run_double(s);
}

// The variant's whole answer in precision T on (tmin, tmax): its answer
// function when it has one, else its roots alone.
template <class T>
answer<T> answer_in(const variant& v, const ray_sphere<T>& s, ray_interval<T> interval) {
    if constexpr (std::is_same_v<T, float>) {
        if (v.answer_float) return v.answer_float(s, interval.tmin, interval.tmax);
    } else {
        if (v.answer_double) return v.answer_double(s, interval.tmin, interval.tmax);
    }
    return {run_in(v, s, interval)};
}

// All built-in variants, in a fixed order (the order of reports).
std::span<const variant> builtin_variants();

// The built-in published formulas (variants.def's textbook family), in the
// registry's order: what `bench --audit` times.
std::span<const std::string_view> textbook_variant_names();

// nullptr when no built-in variant has that name.
const variant* find_builtin_variant(std::string_view name);

}  // namespace rayverify
