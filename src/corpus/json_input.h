// JSON read from an input (a results file, an npy companion, a program's
// answer): one function through which every such document is parsed, so that
// no exception of the JSON library reaches main as an internal error.
#pragma once

#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace rayverify {

// Parses `text`, one JSON document that begins on line `first_line` of
// `file`. Throws input_error naming the file, the line and the field (as a
// path such as "hit_point[1]") for a syntax error, a number outside the range
// of doubles (1e400), and a key given twice in one object (JSON leaves its
// meaning open; rayverify refuses it rather than keep one of the two).
nlohmann::ordered_json parse_json_input(std::string_view text, const std::string& file, std::size_t first_line = 1);

}  // namespace rayverify
