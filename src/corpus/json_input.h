// JSON read from an input (a results file, an npy companion, a program's
// answer): one function through which every such document is parsed, so that
// no exception of the JSON library reaches main as an internal error.
#pragma once

#include <cstddef>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace rayverify {

// Parses `text`, one JSON document that begins on line `first_line` of
// `file`. Throws input_error naming the file, the line and the field (as a
// path such as "hit_point[1]") for a syntax error, a number outside the range
// of doubles (1e400), and a key given twice in one object (JSON leaves its
// meaning open; rayverify refuses it rather than keep one of the two).
// It also refuses JSON nested more than json_input_max_depth levels deep (no
// input of rayverify nests more than a few levels; a million '[' is an attack).
nlohmann::ordered_json parse_json_input(std::string_view text, const std::string& file, std::size_t first_line = 1);

inline constexpr std::size_t json_input_max_depth = 64;

// A document with the line on which each of its values starts, by the path
// messages name it with ("spheres[2].radius"): for an input whose every field
// is checked after parsing (a scene), so that a message names its line.
struct located_json {
    nlohmann::ordered_json document;
    std::map<std::string, std::size_t> lines;
    // The line of `path`, or of its nearest enclosing value that has one; 0 when none.
    std::size_t line_of(std::string path) const;
};

// parse_json_input, and each value's line.
located_json parse_located_json_input(std::string_view text, const std::string& file, std::size_t first_line = 1);

}  // namespace rayverify
