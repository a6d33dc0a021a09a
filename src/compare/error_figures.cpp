// How an error figure is printed (error_figures.h): correctly rounded to
// figure_significant_digits digits. Where an exact power of ten scales it to
// four integer digits away from a tie, by arithmetic; elsewhere std::to_chars
// with a precision rounds the double's exact value as printf does (ties to
// even), and from_chars returns the double nearest that decimal.
#include "compare/error_figures.h"

#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <system_error>

#include <fmt/format.h>

#include "core/float_bits.h"
#include "core/remembered_by_bits.h"

namespace rayverify {

namespace {

// 10^k for k in [0, 22], each exactly a double.
constexpr double exact_power_of_ten(int k) {
    double p = 1;
    for (int i = 0; i < k; ++i) p *= 10;
    return p;
}
constexpr std::array<double, 23> powers_of_ten = [] {
    std::array<double, 23> out{};
    for (int k = 0; k < 23; ++k) out[k] = exact_power_of_ten(k);
    return out;
}();

// |x| (finite, not 0) scaled by an exact power of ten to m in [1000, 10000)
// (one rounding, relative error ≤ 2^−53), as m and k with m ≈ |x|·10^k;
// nullopt where a scale beyond 10^22 is needed. The decimal exponent comes
// from the binary one (log10(2)·e, within one of floor(log10(x))), put right
// by the loop. Each step is a few instructions: the per-case lines and the
// plot sample ask it of every figure they print, twice where a figure is
// kept to its printed digits (printed_alike).
struct four_digit_scaling {
    double m;
    int k;
};
double scaled_by_power_of_ten(double magnitude, int k) {
    return k >= 0 ? magnitude * powers_of_ten[k] : magnitude / powers_of_ten[-k];
}
// floor(e·log10 2) as (e·78913) >> 18 (Ryu's log10Pow2; the shift floors):
// 78913/2^18 is log10 2 within 7.9·10^−7, and the two floors agree for every
// e in [−1074, 1023] (checked exhaustively; Ryu documents e ≥ 0). The
// scaling's loop would put an estimate one off right all the same.
int decimal_exponent_of_binary(int e) { return (e * 78913) >> 18; }

// The integer part of m in [0, 2^53), and the integer nearest it (halves
// up): conversions, where std::floor is a library call on baseline x86-64.
double integer_part(double m) { return static_cast<double>(static_cast<std::int64_t>(m)); }
double nearest_integer(double m) { return integer_part(m + 0.5); }

// Written into `out` (false where no scale within 10^±22 does), inlined:
// returned as an optional, the pair went through the stack and was reloaded
// by a load wider than the stores that wrote it.
[[gnu::always_inline]] inline bool scaled_to_four_digits(double magnitude, four_digit_scaling& out) {
    int k = figure_significant_digits - 1 - decimal_exponent_of_binary(binade_of(magnitude));
    for (int attempt = 0; attempt < 3; ++attempt) {
        if (k < -22 || k > 22) return false;
        const double m = scaled_by_power_of_ten(magnitude, k);
        if (m < 1000) {
            ++k;
            continue;
        }
        if (m >= 10000) {
            --k;
            continue;
        }
        out = {m, k};
        return true;
    }
    return false;
}

// Whether m lies farther than 2^−40·m from every half-integer, so that the
// exact |x|·10^k that m rounds rounds to the same integer as m.
bool clear_of_tie(double m) { return std::fabs((m - integer_part(m)) - 0.5) > 0x1p-40 * m; }

// printed_figure without a decimal conversion where that is safe: the
// decimal n·10^−k (printed_figure_decimal) formed by one multiplication or
// division of exact doubles (correctly rounded: the double nearest it).
std::optional<double> printed_without_conversion(double x) {
    printed_decimal d;
    if (!printed_figure_decimal(x, d)) return std::nullopt;
    const double n = d.digits;
    const double rounded = d.exponent <= 0 ? n / powers_of_ten[-d.exponent] : n * powers_of_ten[d.exponent];
    return std::copysign(rounded, x);
}

}  // namespace

// m rounded to the integer n when it is clear of a tie: the decimal n·10^−k.
bool printed_figure_decimal(double x, printed_decimal& out) {
    four_digit_scaling s;
    if (!std::isfinite(x) || x == 0 || !scaled_to_four_digits(std::fabs(x), s) || !clear_of_tie(s.m)) return false;
    out = {std::signbit(x), static_cast<std::uint32_t>(nearest_integer(s.m)), -s.k};
    return true;
}

namespace {

// printed_figure, worked out.
double rounded_to_printed_digits(double x) {
    if (const std::optional<double> fast = printed_without_conversion(x)) return *fast;
    char text[32];
    const std::to_chars_result written =
        std::to_chars(text, text + sizeof text, x, std::chars_format::scientific, figure_significant_digits - 1);
    double rounded = 0;
    const std::from_chars_result read = std::from_chars(text, written.ptr, rounded);
    return read.ec == std::errc{} ? rounded : x;
}

}  // namespace

// A per-case line prints a few hundred figures, and targets that answer
// alike give the same ones: the figures of recent values are remembered, per
// thread, as json_line remembers their texts.
double printed_figure(double x) {
    if (!std::isfinite(x) || x == 0) return x;
    static thread_local remembered_by_bits<double> recent;
    return recent.of(x, rounded_to_printed_digits);
}

bool printed_alike(double a, double b) {
    if (a == b) return true;
    // Both scaled alike, clear of ties: alike when they round to one integer.
    if (a > 0 && b > 0 && std::isfinite(a) && std::isfinite(b))
        if (four_digit_scaling sb; scaled_to_four_digits(b, sb)) {
            const double ma = scaled_by_power_of_ten(a, sb.k);
            if (ma >= 1000 && ma < 10000 && clear_of_tie(ma) && clear_of_tie(sb.m))
                return nearest_integer(ma) == nearest_integer(sb.m);
        }
    return printed_figure(a) == printed_figure(b);
}

bool printed_as_exact(const case_score& s) {
    if (!s.figure_upper_bounds) return true;
    for (const error_figure_definition& f : error_figures)
        if (f.upper_in_score && f.of_case(s) && !printed_alike(*f.of_case(s), f.upper_of_case(s))) return false;
    if (s.hit_point_ulp)
        for (int axis = 0; axis < 3; ++axis)
            if (!printed_alike((*s.hit_point_ulp)[axis], s.figure_upper_bounds->hit_point_ulp[axis])) return false;
    return true;
}

std::optional<double> printed_figure(const std::optional<double>& x) {
    return x ? std::optional<double>(printed_figure(*x)) : std::nullopt;
}

std::string format_figure(const std::optional<double>& x) { return x ? format_figure(*x) : std::string("-"); }

std::string format_figure(double x) {
    if (std::isnan(x)) return "nan";
    if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
    if (x == 0) return "0";
    return fmt::format("{:.{}g}", printed_figure(x), figure_significant_digits);
}

std::string figure_printing_rule() {
    return fmt::format("every ULP, bits, scale and angle figure is printed correctly rounded to {} significant "
                       "digits (the exact figure rounded to double, then to {} digits, ties to even); verdicts, "
                       "maxima and the case attaining each, and histogram buckets are decided on exact values",
                       figure_significant_digits, figure_significant_digits);
}

}  // namespace rayverify
