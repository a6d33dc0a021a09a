// The one way rayverify splits a text input into lines (corpora, results
// files, gate baselines, the corpus manifest, hunt files): each line with its
// number, without its end of line (\n or \r\n); a byte order mark skipped at
// the start of the file; an input_error naming the file and line for a line
// over 1 MB, a carriage return not followed by a newline, a NUL byte, invalid
// UTF-8 or a byte order mark anywhere else. A reader behind it sees only text
// that a writer can write back as the same lines.
#pragma once

#include <algorithm>
#include <cstddef>
#include <string>
#include <string_view>

namespace rayverify {

// U+FEFF in UTF-8. Skipped at the start of a file; anywhere else it is refused,
// since a token starting with it would not read back the same from a new file.
inline constexpr std::string_view byte_order_mark = "\xEF\xBB\xBF";

// The longest line a text reader takes (a corpus line is ~300 bytes).
inline constexpr std::size_t max_text_line_bytes = std::size_t{1} << 20;

// Throws input_error for the first of the refusals above that `line` (its end
// of line removed) meets.
void check_text_line(const std::string& file, std::size_t number, std::string_view line);

// Calls on_line(number, line) for every line of `contents`, in order, after
// check_text_line; numbers count from 1.
template <class F>
void for_each_text_line(const std::string& file, std::string_view contents, F&& on_line) {
    if (contents.starts_with(byte_order_mark)) contents.remove_prefix(byte_order_mark.size());
    for (std::size_t number = 1; !contents.empty(); ++number) {
        const std::size_t end = std::min(contents.find('\n'), contents.size());
        std::string_view line = contents.substr(0, end);
        contents.remove_prefix(std::min(end + 1, contents.size()));
        // A CRLF's carriage return goes, but not from a line already too long:
        // that one is refused for its length, whatever it ends with.
        if (line.size() <= max_text_line_bytes && line.ends_with('\r')) line.remove_suffix(1);
        check_text_line(file, number, line);
        on_line(number, line);
    }
}

}  // namespace rayverify
