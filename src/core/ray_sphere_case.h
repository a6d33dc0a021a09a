// One ray–sphere test case: the ray o + t·d and the sphere |p − c| = r.
#pragma once

#include <array>
#include <cmath>
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
struct corpus_case {
    std::string id;
    std::string family;          // generator family, or "" when unknown
    ray_sphere<double> geometry;
    std::optional<double> tmin;  // optional ray interval, when the corpus gives one
    std::optional<double> tmax;
    std::string source;          // "file:line" the case was read from (for messages)
};

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

// Classify a case's validity at precision T (after rounding its inputs to T).
template <class T>
invalid_reason validity(const ray_sphere<double>& g) {
    const double in[10] = {g.origin.x,    g.origin.y,    g.origin.z, g.direction.x,
                           g.direction.y, g.direction.z, g.centre.x, g.centre.y,
                           g.centre.z,    g.radius};
    for (double v : in)
        if (!std::isfinite(v)) return invalid_reason::non_finite_input;
    if (g.radius < 0) return invalid_reason::negative_radius;
    for (double v : in)
        if (!std::isfinite(static_cast<T>(v))) return invalid_reason::not_representable;
    const vec3<T> d = vec3_cast<T>(g.direction);
    if (d.x == 0 && d.y == 0 && d.z == 0) return invalid_reason::zero_direction;
    return invalid_reason::none;
}

}  // namespace rayverify
