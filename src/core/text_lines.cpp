#include "core/text_lines.h"

#include "core/input_error.h"

namespace rayverify {

namespace {

// RFC 3629 well-formed UTF-8: no overlong forms, surrogates or code points past U+10FFFF.
bool is_valid_utf8(std::string_view s) {
    for (std::size_t i = 0; i < s.size();) {
        const auto b = static_cast<unsigned char>(s[i]);
        if (b < 0x80) {
            ++i;
            continue;
        }
        if (b < 0xC2 || b > 0xF4) return false;
        const std::size_t n = b >= 0xF0 ? 3 : b >= 0xE0 ? 2 : 1;  // continuation bytes
        // The second byte's range is what excludes overlong forms, surrogates and > U+10FFFF.
        const unsigned lo = b == 0xE0 ? 0xA0 : b == 0xF0 ? 0x90 : 0x80;
        const unsigned hi = b == 0xED ? 0x9F : b == 0xF4 ? 0x8F : 0xBF;
        if (s.size() - i <= n) return false;
        for (std::size_t k = 1; k <= n; ++k) {
            const unsigned c = static_cast<unsigned char>(s[i + k]);
            if (c < (k == 1 ? lo : 0x80u) || c > (k == 1 ? hi : 0xBFu)) return false;
        }
        i += n + 1;
    }
    return true;
}

}  // namespace

void check_text_line(const std::string& file, std::size_t number, std::string_view line) {
    if (line.size() > max_text_line_bytes) throw input_error(file, number, "", "line is longer than 1 MB");
    if (line.find('\r') != std::string_view::npos)
        throw input_error(file, number, "",
                          "line contains a carriage return not followed by a newline (CR-only line endings, "
                          "as old Mac files have?): save the file with \\n or \\r\\n line endings");
    if (line.find('\0') != std::string_view::npos)
        throw input_error(file, number, "", "line contains a NUL byte (binary file?)");
    if (!is_valid_utf8(line)) throw input_error(file, number, "", "line is not valid UTF-8 text");
    if (line.find(byte_order_mark) != std::string_view::npos)
        throw input_error(file, number, "",
                          "line contains a byte order mark (U+FEFF), as where files were concatenated");
}

}  // namespace rayverify
