// How an error figure is printed (error_figures.h): correctly rounded to
// figure_significant_digits digits. std::to_chars with a precision rounds the
// double's exact value as printf does (ties to even); from_chars returns the
// double nearest that decimal.
#include "compare/error_figures.h"

#include <charconv>
#include <cmath>
#include <system_error>

#include <fmt/format.h>

namespace rayverify {

double printed_figure(double x) {
    if (!std::isfinite(x) || x == 0) return x;
    char text[32];
    const std::to_chars_result written =
        std::to_chars(text, text + sizeof text, x, std::chars_format::scientific, figure_significant_digits - 1);
    double rounded = 0;
    const std::from_chars_result read = std::from_chars(text, written.ptr, rounded);
    return read.ec == std::errc{} ? rounded : x;
}

std::optional<double> printed_figure(const std::optional<double>& x) {
    return x ? std::optional<double>(printed_figure(*x)) : std::nullopt;
}

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
