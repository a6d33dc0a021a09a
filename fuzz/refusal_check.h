// What every reader's refusal of a fuzz input must look like, shared by the
// fuzz targets' checks: an input_error that names the file it was given, a
// line that exists in the input, and a message that starts with the file.
// Returns the violated rule, or nullopt when the refusal is well formed.
#pragma once

#include <algorithm>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

#include "core/input_error.h"

namespace rayverify::fuzz {

inline std::optional<std::string> check_refusal(const input_error& e, std::string_view input, const std::string& file) {
    const auto lines = static_cast<std::size_t>(std::count(input.begin(), input.end(), '\n')) + 1;
    if (e.file() != file) return "error names file '" + e.file() + "': " + e.what();
    if (e.line() > lines) return "error names a line past the end: " + std::string(e.what());
    if (!std::string_view(e.what()).starts_with(file)) return "message does not start with the file";
    return std::nullopt;
}

}  // namespace rayverify::fuzz
