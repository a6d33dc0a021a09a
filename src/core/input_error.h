// The one exception type of rayverify: bad input (a corpus line, a file, a
// command-line value). It carries where the problem is so the message can
// name file, line and field. Numeric code never throws; a miss is a value.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>

#include "core/ray_sphere_case.h"
#include "core/target_name.h"

namespace rayverify {

// What printable does with bytes above ASCII: show them as \xNN (the text
// need not be UTF-8), or keep them (text known to be UTF-8, e.g. a JSON
// string that parsed).
enum class non_ascii_bytes { escape, keep };

// Text of an input repeated in a message: control characters (and, unless
// kept, every byte that is not ASCII) shown as \xNN, so that binary garbage
// gives a one-line message.
inline std::string printable(std::string_view text, non_ascii_bytes above_ascii = non_ascii_bytes::escape) {
    static constexpr char digits[] = "0123456789ABCDEF";
    std::string out;
    for (const char c : text) {
        const auto byte = static_cast<unsigned char>(c);
        if (byte < 0x20 || byte == 0x7f || (byte > 0x7f && above_ascii == non_ascii_bytes::escape))
            out += {'\\', 'x', digits[byte >> 4], digits[byte & 15]};
        else
            out += c;
    }
    return out;
}

class input_error : public std::runtime_error {
public:
    // file may be empty (command line); line 0 means "the whole file";
    // field may be empty.
    input_error(std::string file, std::size_t line, std::string field, const std::string& problem)
        : std::runtime_error(compose(file, line, field, problem)),
          file_(std::move(file)),
          line_(line),
          field_(std::move(field)) {}

    const std::string& file() const { return file_; }
    std::size_t line() const { return line_; }
    const std::string& field() const { return field_; }

private:
    static std::string compose(const std::string& file, std::size_t line, const std::string& field,
                               const std::string& problem) {
        std::string where = file.empty() ? std::string("<command line>") : file;
        if (line > 0) where += ":" + std::to_string(line);
        if (!field.empty()) where += ": field '" + field + "'";
        // A file name, a field or a value the user gave may hold an escape
        // sequence or a newline: the message shows them escaped, one line.
        return escaped_control(where + ": " + problem);
    }

    std::string file_;
    std::size_t line_;
    std::string field_;
};

// An intersector running outside rayverify's own code (an isolated plugin,
// an external program) that died, hung or answered garbage on a case: bad
// input (exit 2), naming the intersector and the case, which is kept whole so
// that the CLI can print it as a corpus line to paste into a corpus.
class case_failure : public input_error {
public:
    case_failure(std::string file, std::string field, const std::string& problem, corpus_case failing)
        : input_error(std::move(file), 0, std::move(field), problem), failing_(std::move(failing)) {}

    const corpus_case& failing_case() const { return failing_; }

private:
    corpus_case failing_;
};

}  // namespace rayverify
