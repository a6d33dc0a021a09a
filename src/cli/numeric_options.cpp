// Checks of numeric options on their text, before CLI11 converts it: CLI11
// 2.1 would wrap "-5" into an unsigned 2^64 − 5, saturate 2^64 to 2^64 − 1
// and let "nan" through a range check (every comparison with NaN is false).
// Every numeric option states its limits in one spelling, `numeric_limits_text`,
// in its help and in its error: "whole number ≥ 1 and ≤ 4096",
// "number > 0 and ≤ 3600" (tests/cli_test.cpp checks every command's --help).
#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <limits>

#include "cli/commands.h"

namespace rayverify::cli {

std::string numeric_limits_text(std::string_view kind, std::string_view min, bool above_min, std::string_view max,
                                bool below_max) {
    return fmt::format("{} {} {} and {} {}", kind, above_min ? ">" : "≥", min, below_max ? "<" : "≤", max);
}

CLI::Validator whole_number(std::uint64_t min, std::uint64_t max) {
    const bool unbounded = max == std::numeric_limits<std::uint64_t>::max();
    const std::string range = numeric_limits_text("whole number", std::to_string(min), false,
                                                  unbounded ? "2^64" : std::to_string(max), unbounded);
    return CLI::Validator(
        [min, max, range](std::string& text) -> std::string {
            std::uint64_t value = 0;
            const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
            if (text.empty() || error != std::errc() || end != text.data() + text.size() || value < min ||
                value > max)
                return fmt::format("'{}' is not a {}", text, range);
            return {};
        },
        range);
}

CLI::Validator finite_number(double min, double max, bool above_min) {
    const std::string range = numeric_limits_text("number", fmt::format("{}", min), above_min, fmt::format("{}", max));
    return CLI::Validator(
        [min, max, above_min, range](std::string& text) -> std::string {
            double value = 0;
            const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
            const bool in_range = std::isfinite(value) && (above_min ? value > min : value >= min) && value <= max;
            if (text.empty() || error != std::errc() || end != text.data() + text.size() || !in_range)
                return fmt::format("'{}' is not a {}", text, range);
            return {};
        },
        range);
}

}  // namespace rayverify::cli
