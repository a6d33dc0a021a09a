// The error figures an audit measures on each agreeing answer, defined once:
// each row names the figure in report.json and shard states (`name`) and on
// per-case lines and gate baselines (`case_name`), and says how a case's
// score gives its value. Tallies, samples, shard write/read/check, reports,
// the gate and the schema test go through this table, so that a new figure is
// a row here (and its value in case_score), not a change in each of them.
//
// How every figure is printed is stated here too, once: correctly rounded to
// figure_significant_digits significant digits (printed_figure), wherever it
// appears (per-case lines, report.json, report.md, summaries, scene and
// stability reports, explain, gate baselines). What is decided on a figure
// (a verdict, the case that holds a maximum, a histogram bucket) is decided
// on its exact value, never on the printed one.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "compare/judge.h"

namespace rayverify {

// The significant digits every ULP, bits, scale and angle figure is printed with.
inline constexpr int figure_significant_digits = 4;

// x as it is printed: RN(x) (a double) correctly rounded to
// figure_significant_digits significant decimal digits, ties to even, as the
// double nearest that decimal (which every shortest-form writer, JSON's
// included, spells with those digits, trailing zeros dropped). 0, ±inf and
// NaN are themselves; a decimal beyond the largest double (x within 0.03% of
// it) has no nearest double, and x is returned unrounded.
double printed_figure(double x);
std::optional<double> printed_figure(const std::optional<double>& x);
// The decimal printed_figure(x) is nearest, ±digits·10^exponent (digits at
// most 10^figure_significant_digits), written into `out` where arithmetic
// alone finds it: x finite, not 0, scaled to four digits by a power of ten
// within 10^±22 and clear of a tie. False elsewhere (printed_figure then
// converts). For a writer that spells the figure from its digits, not from
// the double (json_line::decimal): the same decimal printed_figure rounds to.
struct printed_decimal {
    bool negative = false;
    std::uint32_t digits = 0;
    int exponent = 0;
};
bool printed_figure_decimal(double x, printed_decimal& out);
// printed_figure(a) == printed_figure(b), for non-negative a ≤ b, mostly
// without forming either (a few operations where both lie clear of a tie).
bool printed_alike(double a, double b);
// The printed figure as text for tables and sentences: "0.1235", "1.235e+04",
// "0", "inf", "nan".
std::string format_figure(double x);
// The same of a figure that may be absent: "-" for none (a table's cell).
std::string format_figure(const std::optional<double>& x);
// The rule above in one sentence, as reports state it.
std::string figure_printing_rule();

enum class error_figure : std::size_t {
    near_root_ulp,         // |t − t*| / ulp(t*) of the near (or only) root
    far_root_ulp,          // the same of the far root (line_roots)
    near_root_scaled_ulp,  // near_root_ulp, a root exactly at 0 in ulps of r/|d| instead
    near_root_bits,        // Herbie bits of the near root
    hit_point_ulp,         // the hit point's worst coordinate, in ulps
    scale_error_radius,    // |t − t*|·|d| / r, the largest over the returned roots
    scale_error_distance,  // |t − t*|·|d| / |o − c|
    bound_width_ulp,       // the widest claimed t interval, in representable values
    normal_angle,          // radians between the returned normal and ±n*
};

struct error_figure_definition {
    error_figure figure;
    std::string_view name;       // report.json's tallies and shard states
    std::string_view case_name;  // per-case lines, and the gate's figures (case_name + "_max", "_p99")
    bool gated;                  // compared against gate baselines (its max and p99)
    std::optional<double> case_score::*in_score;  // its value in a case's score
    // Its upper bound where the judge decided it to its printed digits
    // (case_score::figure_upper_bounds); null for a figure always exact.
    double case_score::upper_bounds::*upper_in_score = nullptr;
    // Its value in a case's score: a member read in place (a value formed
    // on each read came back through memory, a stall in the audit's hottest
    // loop).
    constexpr const std::optional<double>& of_case(const case_score& s) const { return s.*in_score; }
    // Its upper bound in a case's score that holds it (of_case(s) present):
    // the value itself where the figure is exact.
    constexpr double upper_of_case(const case_score& s) const {
        return s.figure_upper_bounds && upper_in_score ? *s.figure_upper_bounds.*upper_in_score : *of_case(s);
    }
};

inline constexpr std::array error_figures{
    error_figure_definition{error_figure::near_root_ulp, "near_root_ulp", "near_ulp", true, &case_score::near_ulp,
                            &case_score::upper_bounds::near_ulp},
    error_figure_definition{error_figure::far_root_ulp, "far_root_ulp", "far_ulp", true, &case_score::far_ulp,
                            &case_score::upper_bounds::far_ulp},
    error_figure_definition{error_figure::near_root_scaled_ulp, "near_root_scaled_ulp", "near_scaled_ulp", false,
                            &case_score::near_scaled_ulp, &case_score::upper_bounds::near_scaled_ulp},
    error_figure_definition{error_figure::near_root_bits, "near_root_bits", "near_bits", false,
                            &case_score::near_bits},
    error_figure_definition{error_figure::hit_point_ulp, "hit_point_ulp", "hit_point_ulp", false,
                            &case_score::hit_point_worst_ulp, &case_score::upper_bounds::hit_point_worst_ulp},
    error_figure_definition{error_figure::scale_error_radius, "scale_error_radius", "scale_error_radius", false,
                            &case_score::scale_error_radius, &case_score::upper_bounds::scale_error_radius},
    error_figure_definition{error_figure::scale_error_distance, "scale_error_distance", "scale_error_distance", false,
                            &case_score::scale_error_distance, &case_score::upper_bounds::scale_error_distance},
    error_figure_definition{error_figure::bound_width_ulp, "bound_width_ulp", "bound_width_ulp", false,
                            &case_score::bound_ulp},
    error_figure_definition{error_figure::normal_angle, "normal_angle", "normal_angle", false,
                            &case_score::normal_angle},
};

inline constexpr std::size_t error_figure_count = error_figures.size();

// Whether every figure of `s` prints as its exact value does: where it holds
// exact figures, and where each figure it holds to a bucket only
// (case_score::figure_upper_bounds) has bounds that print alike. Where not,
// what prints the case's own figures prints exact_figures' instead.
bool printed_as_exact(const case_score& s);

constexpr bool error_figures_in_enum_order() {
    for (std::size_t i = 0; i < error_figure_count; ++i)
        if (static_cast<std::size_t>(error_figures[i].figure) != i) return false;
    return true;
}
static_assert(error_figures_in_enum_order(), "error_figures lists every figure once, in the enum's order");

constexpr const error_figure_definition& definition_of(error_figure f) {
    return error_figures[static_cast<std::size_t>(f)];
}

// One value per error figure, indexed by the figure.
template <class T>
struct per_error_figure {
    std::array<T, error_figure_count> values{};
    T& operator[](error_figure f) { return values[static_cast<std::size_t>(f)]; }
    const T& operator[](error_figure f) const { return values[static_cast<std::size_t>(f)]; }
    auto begin() { return values.begin(); }
    auto end() { return values.end(); }
    auto begin() const { return values.begin(); }
    auto end() const { return values.end(); }
};

}  // namespace rayverify
