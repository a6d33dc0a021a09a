// Internal to plugin/: a plugin library opened and checked in the process
// that calls it, and the variant it describes. Shared by load_plugin (in this
// process) and the child process of an isolated plugin (plugin_host).
#pragma once

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <span>
#include <type_traits>
#include <vector>

#include "core/fp_environment.h"
#include "core/ray_sphere_case.h"
#include "intersectors/registry.h"
#include "plugin/rayverify_plugin.h"

namespace rayverify::plugin_internal {

// What describe() (or describe_v2()) says, checked, its texts copied (NULL
// ones replaced by their defaults), and which precisions the library runs in.
struct plugin_description {
    int abi = RAYVERIFY_PLUGIN_ABI_VERSION;  // 1 or RAYVERIFY_PLUGIN_ABI_VERSION_2
    std::string name, citation, formula, tangent_rule;
    // Version 1: the contract's fields.
    int query = RAYVERIFY_LINE_ROOTS;
    bool assumes_unit_direction = false, reports_tangent = false, clamps_to_zero = false;
    // Version 2: the contract spec (core/contract.h), checked, and the build.
    std::string contract_spec, build;
    // Either version: rayverify_plugin_library_version(), when exported; empty otherwise.
    std::string library_version;
    // Either version: rayverify_plugin_library_configuration(), when exported; empty otherwise.
    std::string library_configuration;
    // The floating-point environment the process had once the library was
    // loaded and had described itself (a -ffast-math link's crtfastmath.o sets
    // FTZ+DAZ); the IEEE default for a library that changes nothing.
    fp_state environment_at_load = ieee_default_fp_state();
    bool has_float = false;
    bool has_double = true;  // version 1 always
    bool thread_safe = false;  // rayverify_plugin_thread_safe() returned nonzero
    // Version 2: which batch entries it exports (every precision it runs in):
    // the ray batch, the segment entry (rayverify_plugin_intersect_segments_*), or both.
    bool has_ray_batch = true;
    bool has_segment_entry = false;
};

struct opened_library {
    std::shared_ptr<void> handle;  // dlclose when the last copy goes
    rayverify_intersect_double_fn run_double = nullptr;  // version 1
    rayverify_intersect_float_fn run_float = nullptr;    // version 1; nullptr when the library has none
    rayverify_batch_double_fn batch_double = nullptr;    // version 2, when it runs in double
    rayverify_batch_float_fn batch_float = nullptr;      // version 2, when it runs in float
    // Version 2 with cast=segment, in place of the two batch functions.
    rayverify_segments_double_fn segments_double = nullptr;
    rayverify_segments_float_fn segments_float = nullptr;
    plugin_description description;
};

// Why a library cannot be used: the text after "LIBRARY: field '--plugin': ".
// `here`: the library is sound but said it cannot run on this machine
// (rayverify_plugin_unavailable), rather than being broken; the text is its
// reason.
class unusable_library : public std::runtime_error {
public:
    enum where { anywhere, here };
    explicit unusable_library(const std::string& problem, where w = anywhere)
        : std::runtime_error(problem), only_here(w == here) {}
    bool only_here;
};

// dlopen the library and check what it describes: version 2 when it exports
// rayverify_plugin_describe_v2, else version 1. Throws unusable_library
// (missing file or symbol, not loadable, another ABI version, no name, a name
// that is not one token, an unknown query kind; version 2: a contract spec
// that does not parse, no precision, a missing batch function; `here` when
// rayverify_plugin_unavailable gives a reason). The floating-point
// environment the library leaves (loading it, its constructors, its describe
// functions) is kept in the description, and the calling thread's is the
// IEEE default again when it returns or throws.
opened_library open_library(const std::filesystem::path& library);

// The environment a plugin's calls run in: the one chosen for its name
// (--fp-env), else the one its library set when it was loaded.
fp_state plugin_run_environment(const plugin_description& description, const fp_environment_choice& choice);
// How that environment came about, for reports: empty for the IEEE default
// nobody chose; "FTZ+DAZ, set when the library loaded (what GCC's
// crtfastmath.o sets: linked with -ffast-math?)"; "rounding upward (--fp-env
// upward)".
std::string plugin_environment_text(const plugin_description& description, const fp_environment_choice& choice);

// The variant the description stands for: name, citation, formula and
// contract; no run functions, thread_safe as rayverify_plugin_thread_safe() says (else one thread).
variant described_variant(const plugin_description& description);

// A version 2 answer as rayverify holds it (a point answer's t derived from
// its point), and the struct a plugin is handed, filled with NaN and count −1.
template <class T, class Answer>
answer<T> answer_from(const Answer& a, const contract& promises, const ray_sphere<T>& s) {
    answer<T> out;
    out.roots = {a.count, a.t[0], a.t[1]};
    out.t_lower = {a.t_lower[0], a.t_lower[1]};
    out.t_upper = {a.t_upper[0], a.t_upper[1]};
    out.point = {a.point[0], a.point[1], a.point[2]};
    out.point_error = {a.point_error[0], a.point_error[1], a.point_error[2]};
    out.normal = {a.normal[0], a.normal[1], a.normal[2]};
    if (promises.answer == answer_kind::point) {
        const T t = parameter_of_point(s, out.point);
        out.roots.t0 = out.roots.t1 = t;
    }
    return out;
}

template <class Answer>
Answer blank_answer() {
    Answer a;
    using T = std::remove_reference_t<decltype(a.t[0])>;
    const T nan = std::numeric_limits<T>::quiet_NaN();
    a.count = -1;
    for (T* member : {a.t, a.t_lower, a.t_upper}) member[0] = member[1] = nan;
    for (T* member : {a.point, a.point_error, a.normal}) member[0] = member[1] = member[2] = nan;
    return a;
}

template <class Case, class T>
Case case_for_plugin(const ray_sphere<T>& s, T tmin, T tmax) {
    return {{s.origin.x, s.origin.y, s.origin.z}, {s.direction.x, s.direction.y, s.direction.z},
            {s.centre.x, s.centre.y, s.centre.z}, s.radius, tmin, tmax};
}

// The struct a version 2 plugin is handed for one case: the ray and its
// interval (rayverify_case_*), or for cast=segment the end points as the
// target receives them (rayverify_segment_*: p0 is the input's origin).
template <class T, bool segment>
using plugin_case_t = std::conditional_t<
    segment, std::conditional_t<std::is_same_v<T, float>, rayverify_segment_float, rayverify_segment_double>,
    std::conditional_t<std::is_same_v<T, float>, rayverify_case_float, rayverify_case_double>>;

// Answers a batch whose cases may mix rays and segments: `rays(cases,
// answers)` for the ray cases, `segments(cases, answers)` for the segment
// cases (batch_case::segment), each called once with its cases in order (not
// at all when it has none), the answers put back in the batch's order.
template <class T, class Rays, class Segments>
void answer_by_form(std::span<const batch_case<T>> cases, std::span<answer<T>> out, const Rays& rays,
                    const Segments& segments) {
    const auto segment_count = static_cast<std::size_t>(
        std::count_if(cases.begin(), cases.end(), [](const batch_case<T>& c) { return c.segment; }));
    if (segment_count == 0) return rays(cases, out);
    if (segment_count == cases.size()) return segments(cases, out);
    for (const bool segment : {false, true}) {
        std::vector<batch_case<T>> part;
        std::vector<std::size_t> where;
        for (std::size_t i = 0; i < cases.size(); ++i)
            if (cases[i].segment == segment) {
                part.push_back(cases[i]);
                where.push_back(i);
            }
        std::vector<answer<T>> answers(part.size());
        if (segment)
            segments(std::span<const batch_case<T>>(part), std::span<answer<T>>(answers));
        else
            rays(std::span<const batch_case<T>>(part), std::span<answer<T>>(answers));
        for (std::size_t k = 0; k < where.size(); ++k) out[where[k]] = answers[k];
    }
}

template <class Case, class T>
Case plugin_case(const batch_case<T>& c) {
    if constexpr (std::is_same_v<Case, plugin_case_t<T, true>>) {
        const ray_sphere<T>& s = c.input;
        return {{s.origin.x, s.origin.y, s.origin.z},
                {c.segment_end.x, c.segment_end.y, c.segment_end.z},
                {s.centre.x, s.centre.y, s.centre.z},
                s.radius};
    } else {
        return case_for_plugin<Case>(c.input, c.interval.tmin, c.interval.tmax);
    }
}

// The case a failing call was on, as plugin_failure keeps it: the case
// announced on this thread (core/case_in_progress.h), else the inputs as
// given (widened exactly to double) with (tmin, tmax) when `interval_asked`.
template <class T>
corpus_case failing_case(const ray_sphere<T>& s, T tmin, T tmax, bool interval_asked);
// "on case ID (SOURCE)", or "on inputs given outside any audited case".
std::string failing_case_text();

// The roots buffer a call writes, with guard areas on both sides: a plugin
// that writes outside roots[0..1] is caught instead of silently scored (or
// corrupting rayverify's memory unnoticed).
template <class T>
struct guarded_roots {
    static constexpr int guard = 16;
    T cells[guard + 2 + guard];
    guarded_roots();
    T* roots() { return cells + guard; }
    bool intact() const;  // both guards as written
};

// What the guard areas around a plugin's outputs are filled with.
constexpr unsigned char guard_byte = 0xA5;

// A version 2 batch's answers as the plugin writes them, each blank_answer,
// between guard areas as guarded_roots: a plugin that writes past its
// `count` answers (or before the first) is caught.
template <class Answer>
class guarded_answers {
public:
    static constexpr std::size_t guard = 2;  // answers' worth of bytes on each side
    explicit guarded_answers(std::size_t count) : cells_(count + 2 * guard), count_(count) {
        std::memset(static_cast<void*>(cells_.data()), guard_byte, cells_.size() * sizeof(Answer));
        for (std::size_t i = 0; i < count; ++i) cells_[guard + i] = blank_answer<Answer>();
    }
    Answer* data() { return cells_.data() + guard; }
    std::span<const Answer> answers() const { return {cells_.data() + guard, count_}; }
    bool intact() const {
        const auto* bytes = reinterpret_cast<const unsigned char*>(cells_.data());
        const std::size_t guard_bytes = guard * sizeof(Answer);
        const auto clean = [](const unsigned char* p, std::size_t n) {
            return std::all_of(p, p + n, [](unsigned char b) { return b == guard_byte; });
        };
        return clean(bytes, guard_bytes) && clean(bytes + (guard + count_) * sizeof(Answer), guard_bytes);
    }

private:
    std::vector<Answer> cells_;
    std::size_t count_;
};

// The interval a plain run function passes as (tmin, tmax): the one its
// contract is judged on.
template <class T>
T interval_start(const contract& promises) {
    return promises.query == query_kind::line_roots ? -std::numeric_limits<T>::infinity() : T(0);
}

}  // namespace rayverify::plugin_internal
