// One ray–sphere test case: the ray o + t·d and the sphere |p − c| = r.
#pragma once

#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>

#include "core/vec3.h"

namespace rayverify {

template <class T>
struct ray_sphere {
    vec3<T> origin;     // o
    vec3<T> direction;  // d, any length unless a variant's contract says unit
    vec3<T> centre;     // c
    T radius{};         // r
};

// The precision an intersector runs in. A float variant receives the case's
// inputs rounded to float and is judged against the exact answer for exactly
// those float inputs.
enum class precision { binary32, binary64 };
inline constexpr std::array every_precision{precision::binary32, precision::binary64};

// The one spelling of each precision (options, corpus and scene files, reports).
constexpr const char* precision_name(precision p) {
    return p == precision::binary32 ? "float" : "double";
}

// The precision named `name` ("float" or "double"); nullopt for any other name.
constexpr std::optional<precision> precision_from_name(std::string_view name) {
    for (const precision p : every_precision)
        if (name == precision_name(p)) return p;
    return std::nullopt;
}

// The one place a precision becomes a type (as pbrt's Dispatch): f called
// with std::type_identity<float> for binary32, std::type_identity<double>
// for binary64. Both calls must return the same type.
template <class F>
constexpr decltype(auto) with_precision(precision p, F&& f) {
    if (p == precision::binary32) return std::forward<F>(f)(std::type_identity<float>{});
    return std::forward<F>(f)(std::type_identity<double>{});
}

// x rounded to nearest-even in precision p, as a double (exact in double).
constexpr double rounded_to(precision p, double x) {
    return with_precision(p, [x]<class T>(std::type_identity<T>) { return static_cast<double>(static_cast<T>(x)); });
}

constexpr int significand_bits(precision p) { return p == precision::binary32 ? 24 : 53; }
// The unit roundoff u = 2^-p of precision p.
constexpr double unit_roundoff(precision p) { return p == precision::binary32 ? 0x1p-24 : 0x1p-53; }

// A case as it is stored in a corpus: double inputs plus provenance.
//
// Two forms. A ray case: o + t·d with an optional interval. A segment case
// (`segment_end` set, see make_segment): the cast from p0 = geometry.origin
// to p1 = *segment_end, parameterised by the fraction f of d = p1 − p0 taken
// exactly (a difference of doubles is not a double in general: the oracle
// carries it unrounded); tmin = 0 and tmax = 1, the ends' openness the
// contract's. geometry.direction then holds p1 − p0 rounded to double, for
// what reads a direction to scale a figure; what a target receives at a
// precision is target_input's.
struct corpus_case {
    std::string id;
    std::string family;          // generator family, or "" when unknown
    ray_sphere<double> geometry;
    std::optional<double> tmin;  // optional ray interval, when the corpus gives one
    std::optional<double> tmax;
    std::string source;          // "file:line" the case was read from (for messages)
    std::optional<vec3<double>> segment_end;  // p1 of a segment case; empty for a ray case

    bool is_segment() const { return segment_end.has_value(); }
};

// Make `c` the segment case from p0 to p1 (geometry.origin = p0,
// geometry.direction = p1 − p0 rounded to double, f ∈ [0, 1]).
inline void make_segment(corpus_case& c, const vec3<double>& p0, const vec3<double>& p1) {
    c.geometry.origin = p0;
    c.geometry.direction = p1 - p0;
    c.segment_end = p1;
    c.tmin = 0.0;
    c.tmax = 1.0;
}

// Why a case cannot be scored at a given precision; valid when none applies.
enum class invalid_reason {
    none,
    non_finite_input,       // NaN or ±inf in some input
    zero_direction,         // d = 0 (exactly, after rounding to the precision)
    negative_radius,        // r < 0
    not_representable,      // finite in double, overflows when rounded to float
    bad_interval,           // tmin > tmax, or a NaN bound
};

const char* invalid_reason_name(invalid_reason r);

// A cast with no geometry to judge, which a contract with degenerate=miss
// (core/contract.h) hands to the target all the same: a zero direction, a
// non-finite input (NaN or ±inf, or a double that overflows the target's
// precision), a NaN bound or a reversed interval. A negative radius is the
// sphere's fault, not the cast's: it stays invalid.
constexpr bool degenerate_cast(invalid_reason r) {
    return r == invalid_reason::non_finite_input || r == invalid_reason::zero_direction ||
           r == invalid_reason::not_representable || r == invalid_reason::bad_interval;
}

// The inputs rounded to precision P (round to nearest), which is what a
// variant running in P receives.
template <class T, class S>
ray_sphere<T> rounded_to(const ray_sphere<S>& g) {
    return {vec3_cast<T>(g.origin), vec3_cast<T>(g.direction), vec3_cast<T>(g.centre),
            static_cast<T>(g.radius)};
}

// The same for a precision named at run time, kept in double (exact there).
inline ray_sphere<double> rounded_to(precision p, const ray_sphere<double>& g) {
    return with_precision(p, [&]<class T>(std::type_identity<T>) { return rounded_to<double>(rounded_to<T>(g)); });
}

// The checks every case's ten inputs share, in order: each finite, the
// radius not negative, each finite once rounded to T. Every solution and
// every judged case-target asks them: a valid case (nearly every one) is
// told by one test of all ten without a branch per input (an input finite
// in T is finite, and |x| ≤ max is false for a NaN and ±inf); the loops
// below name the first check an invalid case fails.
template <class T>
invalid_reason inputs_validity(const double (&in)[10], double radius) {
    bool finite_in_T = true;
#pragma GCC unroll 10
    for (double v : in) finite_in_T &= std::fabs(static_cast<T>(v)) <= std::numeric_limits<T>::max();
    if (finite_in_T && radius >= 0) return invalid_reason::none;
    for (double v : in)
        if (!std::isfinite(v)) return invalid_reason::non_finite_input;
    if (radius < 0) return invalid_reason::negative_radius;
    for (double v : in)
        if (!std::isfinite(static_cast<T>(v))) return invalid_reason::not_representable;
    return invalid_reason::none;
}

// Classify a case's validity at precision T (after rounding its inputs to T).
template <class T>
invalid_reason validity(const ray_sphere<double>& g) {
    const double in[10] = {g.origin.x,    g.origin.y,    g.origin.z, g.direction.x,
                           g.direction.y, g.direction.z, g.centre.x, g.centre.y,
                           g.centre.z,    g.radius};
    if (const invalid_reason r = inputs_validity<T>(in, g.radius); r != invalid_reason::none) return r;
    const vec3<T> d = vec3_cast<T>(g.direction);
    if (d.x == 0 && d.y == 0 && d.z == 0) return invalid_reason::zero_direction;
    return invalid_reason::none;
}

// What a target running in T receives for case c. A ray case: its inputs
// rounded to T. A segment case: p0, p1, c and r rounded to T, and the
// direction p1 − p0 computed in T (one rounding of the exact difference of
// the rounded ends): the direction a ray-form target is handed, whose
// rounding is the target's to answer for; the oracle solves the segment
// between the rounded ends exactly (judge's solve_case).
template <class T>
ray_sphere<T> target_input(const corpus_case& c) {
    if (!c.segment_end) return rounded_to<T>(c.geometry);
    const vec3<T> p0 = vec3_cast<T>(c.geometry.origin), p1 = vec3_cast<T>(*c.segment_end);
    return {p0, p1 - p0, vec3_cast<T>(c.geometry.centre), static_cast<T>(c.geometry.radius)};
}

// The same for a precision named at run time, kept in double (exact there).
inline ray_sphere<double> target_input(precision p, const corpus_case& c) {
    return with_precision(p, [&]<class T>(std::type_identity<T>) { return rounded_to<double>(target_input<T>(c)); });
}

// p1 of a segment case as a target running in T receives it.
template <class T>
vec3<T> segment_end_input(const corpus_case& c) {
    return vec3_cast<T>(*c.segment_end);
}

// A case's validity at precision T: a ray case's as validity<T> says; a
// segment case's from its ends: a non-finite end, centre or radius, a
// negative radius, an input or a difference p1 − p0 that overflows T, and
// p0 = p1 in T (a zero-length cast: zero_direction).
template <class T>
invalid_reason case_validity(const corpus_case& c) {
    if (!c.segment_end) return validity<T>(c.geometry);
    const ray_sphere<double>& g = c.geometry;
    const vec3<double>& p1 = *c.segment_end;
    const double in[10] = {g.origin.x, g.origin.y, g.origin.z, p1.x,       p1.y,
                           p1.z,       g.centre.x, g.centre.y, g.centre.z, g.radius};
    if (const invalid_reason r = inputs_validity<T>(in, g.radius); r != invalid_reason::none) return r;
    const vec3<T> d = target_input<T>(c).direction;
    if (!std::isfinite(d.x) || !std::isfinite(d.y) || !std::isfinite(d.z)) return invalid_reason::not_representable;
    if (d.x == 0 && d.y == 0 && d.z == 0) return invalid_reason::zero_direction;
    return invalid_reason::none;
}

}  // namespace rayverify
