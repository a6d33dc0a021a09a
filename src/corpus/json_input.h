// JSON read from an input (a results file, an npy companion, a program's
// answer): one function through which every document is parsed, so that no
// exception of the JSON library reaches main as an internal error.
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

// Runs `read`, which takes values out of a document `parse_json_input`
// returned; any exception of the JSON library it throws (a value of the
// wrong type, a missing key) becomes an input_error naming file, line and
// `what` (the kind of document: "not a shard state").
template <class Read>
decltype(auto) read_json_fields(const std::string& file, std::size_t line, const std::string& what, Read&& read);

}  // namespace rayverify

#include "core/input_error.h"

namespace rayverify {

template <class Read>
decltype(auto) read_json_fields(const std::string& file, std::size_t line, const std::string& what, Read&& read) {
    try {
        return read();
    } catch (const nlohmann::json::exception& e) {
        throw input_error(file, line, "", what + ": " + e.what());
    }
}

}  // namespace rayverify
