// A target's name (a plugin's, a results file's --name, a program's --name):
// one token, as the summary table, report.json, gate baselines and corpus
// comments print it. One rule for every kind of target.
#pragma once

#include <algorithm>
#include <cstdio>
#include <string>
#include <string_view>

namespace rayverify {

inline bool is_control_byte(unsigned char byte) { return byte < 0x20 || byte == 0x7f; }

// True when `name` is one token: not empty, no space, '/', '#' or control
// character (a newline would split a baseline's line, an escape sequence
// would reach the terminal).
inline bool is_target_name(std::string_view name) {
    return !name.empty() && name.find_first_of(" /#") == std::string_view::npos &&
           std::none_of(name.begin(), name.end(), [](char c) { return is_control_byte(static_cast<unsigned char>(c)); });
}

// `text` with control bytes shown as \xNN, so that it prints as one plain line.
inline std::string escaped_control(std::string_view text) {
    std::string out;
    for (const char c : text) {
        const auto byte = static_cast<unsigned char>(c);
        if (!is_control_byte(byte)) {
            out += c;
            continue;
        }
        char hex[8];
        std::snprintf(hex, sizeof hex, "\\x%02X", byte);
        out += hex;
    }
    return out;
}

}  // namespace rayverify
