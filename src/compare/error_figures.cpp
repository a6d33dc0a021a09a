// How an error figure is printed (error_figures.h): correctly rounded to
// figure_significant_digits digits. Where an exact power of ten scales it to
// four integer digits away from a tie, by arithmetic; elsewhere std::to_chars
// with a precision rounds the double's exact value as printf does (ties to
// even), and from_chars returns the double nearest that decimal.
#include "compare/error_figures.h"

#include <array>
#include <charconv>
#include <cmath>
#include <system_error>

#include <fmt/format.h>

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

// printed_figure without a decimal conversion where that is safe: x scaled
// by an exact power of ten to m in [1000, 10000) (one rounding, relative
// error ≤ 2^−53), m rounded to the integer n when m lies farther than
// 2^−40·m from every half-integer (so that the exact x·10^k rounds to n
// too), and n·10^−k formed by one multiplication or division of exact
// doubles (correctly rounded: the double nearest the decimal). nullopt
// where a scale beyond 10^22 is needed or m lies that near a tie.
std::optional<double> printed_without_conversion(double x) {
    const double magnitude = std::fabs(x);
    // The decimal exponent from the binary one (log10(2)·e, within one of
    // floor(log10(x))), put right by the loop.
    constexpr double log10_of_2 = 0.30102999566398120;
    int k = figure_significant_digits - 1 - static_cast<int>(std::floor(std::ilogb(magnitude) * log10_of_2));
    for (int attempt = 0; attempt < 3; ++attempt) {
        if (k < -22 || k > 22) return std::nullopt;
        const double m = k >= 0 ? magnitude * powers_of_ten[k] : magnitude / powers_of_ten[-k];
        if (m < 1000) {
            ++k;
            continue;
        }
        if (m >= 10000) {
            --k;
            continue;
        }
        const double n = std::floor(m + 0.5);
        if (std::fabs(std::fabs(m - std::floor(m)) - 0.5) <= 0x1p-40 * m) return std::nullopt;
        const double rounded = k >= 0 ? n / powers_of_ten[k] : n * powers_of_ten[-k];
        return std::copysign(rounded, x);
    }
    return std::nullopt;
}

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
