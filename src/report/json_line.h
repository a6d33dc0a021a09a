// A JSON document written straight into a string, byte for byte as
// nlohmann::ordered_json::dump() writes the same document: compact, members
// in the order written, numbers in nlohmann's own shortest round-trip form
// (its Grisu2 to_chars), strings escaped as it escapes valid UTF-8. The
// per-case lines of an audit are written this way, a few hundred values for
// every case, without building a document first (tests/json_line_test.cpp
// checks the bytes against nlohmann's on every shipped case).
#pragma once

#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>

namespace rayverify {

class json_line {
public:
    json_line& begin_object() { return open('{'); }
    json_line& end_object() { return close('}'); }
    json_line& begin_array() { return open('['); }
    json_line& end_array() { return close(']'); }

    // A member's name; its value follows.
    json_line& key(std::string_view name) {
        separate();
        quoted(name);
        out_ += ':';
        after_key_ = true;
        return *this;
    }

    json_line& value(std::string_view text) {
        separate();
        quoted(text);
        return *this;
    }
    json_line& value(const char* text) { return value(std::string_view(text)); }
    json_line& value(const std::string& text) { return value(std::string_view(text)); }
    json_line& value(bool b) {
        separate();
        out_ += b ? "true" : "false";
        return *this;
    }
    template <class Integer>
        requires std::is_integral_v<Integer>
    json_line& value(Integer n) {
        separate();
        out_ += std::to_string(n);
        return *this;
    }
    // A double as nlohmann writes one (null when not finite).
    json_line& value(double x) {
        separate();
        if (!std::isfinite(x)) {
            out_ += "null";
            return *this;
        }
        std::array<char, 64> buffer{};
        char* const end = nlohmann::detail::to_chars(buffer.data(), buffer.data() + buffer.size(), x);
        out_.append(buffer.data(), static_cast<std::size_t>(end - buffer.data()));
        return *this;
    }
    json_line& null() {
        separate();
        out_ += "null";
        return *this;
    }

    // key(name).value(v)
    template <class T>
    json_line& member(std::string_view name, const T& v) {
        return key(name).value(v);
    }

    const std::string& text() const { return out_; }

private:
    json_line& open(char bracket) {
        separate();
        out_ += bracket;
        first_ = true;
        return *this;
    }
    json_line& close(char bracket) {
        out_ += bracket;
        first_ = false;
        return *this;
    }
    // The comma before a value or key that is not the first of its container.
    void separate() {
        if (after_key_) {
            after_key_ = false;
            return;
        }
        if (!first_ && !out_.empty()) out_ += ',';
        first_ = false;
    }
    void quoted(std::string_view s) {
        out_ += '"';
        for (const char ch : s) {
            const auto byte = static_cast<unsigned char>(ch);
            switch (byte) {
                case '\b': out_ += "\\b"; break;
                case '\t': out_ += "\\t"; break;
                case '\n': out_ += "\\n"; break;
                case '\f': out_ += "\\f"; break;
                case '\r': out_ += "\\r"; break;
                case '"': out_ += "\\\""; break;
                case '\\': out_ += "\\\\"; break;
                default:
                    if (byte <= 0x1F) {
                        constexpr char hex[] = "0123456789abcdef";
                        out_ += "\\u00";
                        out_ += hex[byte >> 4];
                        out_ += hex[byte & 0xF];
                    } else {
                        out_ += ch;
                    }
            }
        }
        out_ += '"';
    }

    std::string out_;
    bool first_ = true;       // the next value or key opens its container
    bool after_key_ = false;  // the next value is a member's, after its key
};

}  // namespace rayverify
