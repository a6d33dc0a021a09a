// Checks of numeric options on their text, before CLI11 converts it: CLI11
// 2.1 would wrap "-5" into an unsigned 2^64 − 5, saturate 2^64 to 2^64 − 1
// and let "nan" through a range check (every comparison with NaN is false).
#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <limits>

#include "cli/commands.h"

namespace rayverify::cli {

CLI::Validator whole_number(std::uint64_t min, std::uint64_t max) {
    const std::string range = max == std::numeric_limits<std::uint64_t>::max()
                                  ? fmt::format("a whole number ≥ {} below 2^64", min)
                                  : fmt::format("a whole number from {} to {}", min, max);
    return CLI::Validator(
        [min, max, range](std::string& text) -> std::string {
            std::uint64_t value = 0;
            const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
            if (text.empty() || error != std::errc() || end != text.data() + text.size() || value < min ||
                value > max)
                return fmt::format("'{}' is not {}", text, range);
            return {};
        },
        range.substr(2));
}

CLI::Validator finite_number(double min, double max, bool above_min) {
    const std::string range = fmt::format("a number {} {} and ≤ {}", above_min ? ">" : "≥", min, max);
    return CLI::Validator(
        [min, max, above_min, range](std::string& text) -> std::string {
            double value = 0;
            const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
            const bool in_range = std::isfinite(value) && (above_min ? value > min : value >= min) && value <= max;
            if (text.empty() || error != std::errc() || end != text.data() + text.size() || !in_range)
                return fmt::format("'{}' is not {}", text, range);
            return {};
        },
        range.substr(2));
}

}  // namespace rayverify::cli
