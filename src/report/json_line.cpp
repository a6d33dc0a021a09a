#include "report/json_line.h"

#include <algorithm>
#include <cassert>
#include <charconv>
#include <cmath>
#include <cstring>

namespace rayverify {

char* json_number_text(char* out, double x) {
    // From 1e16 on, the plain form may pick fixed notation, whose digits are
    // the double's exact integer value (131745464716806488064), not the
    // shortest ones: the scientific form's are (1.3174546471680649e+20).
    char* const end = std::fabs(x) >= 1e16 ? std::to_chars(out, out + 25, x, std::chars_format::scientific).ptr
                                           : std::to_chars(out, out + 25, x).ptr;
    // An integer's text ("2", "-120") gets ".0", as nlohmann writes a double that
    // is an integer, so that a reader sees a floating-point number; where the
    // scientific form is shorter than that (7.39079152912e+15), it instead.
    if (std::find_if(out, end, [](char c) { return c == '.' || c == 'e' || c == 'n' || c == 'i'; }) == end) {
        char scientific[32];
        char* const scientific_end = std::to_chars(scientific, scientific + sizeof scientific, x,
                                                   std::chars_format::scientific).ptr;
        if (scientific_end - scientific < end - out + 2)
            return std::copy(scientific, scientific_end, out);
        std::memcpy(end, ".0", 2);
        return end + 2;
    }
    return end;
}

char* json_decimal_text(char* out, bool negative, std::uint64_t digits, int exponent) {
    assert(digits > 0 && digits < 1'000'000'000'000'000 && "at most 15 significant digits");
    for (; digits % 10 == 0 && digits != 0; digits /= 10) ++exponent;
    char text[20];  // the digits, most significant first
    char* const text_end = std::to_chars(text, text + sizeof text, digits).ptr;
    const int count = static_cast<int>(text_end - text);
    const int point = exponent + count - 1;  // the scientific form's exponent
    if (negative) *out++ = '-';
    const auto scientific = [&](char* at) {
        *at++ = text[0];
        if (count > 1) {
            *at++ = '.';
            at = std::copy(text + 1, text_end, at);
        }
        *at++ = 'e';
        *at++ = point < 0 ? '-' : '+';
        const int magnitude = point < 0 ? -point : point;
        if (magnitude < 10) *at++ = '0';
        return std::to_chars(at, at + 4, magnitude).ptr;
    };
    // json_number_text's choices: from 10^16 on the scientific form; below,
    // std::to_chars' shortest layout, fixed unless the scientific form is
    // shorter, and an integer gets ".0" unless its scientific form is shorter
    // than that.
    const int scientific_size = count + (count > 1 ? 1 : 0) + 2 + (point <= -100 || point >= 100 ? 3 : 2);
    if (point >= 16) return scientific(out);
    if (point >= count - 1) {  // an integer: the digits, then zeros
        const int integer_size = point + 1;
        if (scientific_size < integer_size + 2) return scientific(out);
        out = std::copy(text, text_end, out);
        out = std::fill_n(out, integer_size - count, '0');
        std::memcpy(out, ".0", 2);
        return out + 2;
    }
    const int fixed_size = point >= 0 ? count + 1 : count + 1 - point;
    if (scientific_size < fixed_size) return scientific(out);
    if (point >= 0) {  // d.ddd with the point inside the digits
        out = std::copy(text, text + point + 1, out);
        *out++ = '.';
        return std::copy(text + point + 1, text_end, out);
    }
    *out++ = '0';
    *out++ = '.';
    out = std::fill_n(out, -point - 1, '0');
    return std::copy(text, text_end, out);
}

namespace {

void write_indent(std::string& out, int indent, int depth) {
    out += '\n';
    out.append(static_cast<std::size_t>(indent) * static_cast<std::size_t>(depth), ' ');
}

// A string as dump() writes it: ASCII escaped here (as dump() escapes it),
// anything else by dump() itself, which checks that it is valid UTF-8 (and
// throws where it is not). A report holds thousands of strings; dump() sets
// up a serializer, an output adapter and the locale's decimal point for each.
void write_string(std::string& out, const std::string& text) {
    if (!std::all_of(text.begin(), text.end(), [](char ch) { return static_cast<unsigned char>(ch) < 0x80; })) {
        out += nlohmann::ordered_json(text).dump();
        return;
    }
    out += '"';
    json_escaped(text, [&out](std::string_view piece) { out += piece; });
    out += '"';
}

// An integer as dump() writes it: its decimal digits.
template <class Integer>
void write_integer(std::string& out, Integer n) {
    char text[24];
    out.append(text, std::to_chars(text, text + sizeof text, n).ptr);
}

void write_value(std::string& out, const nlohmann::ordered_json& value, int indent, int depth) {
    using value_t = nlohmann::ordered_json::value_t;
    const bool pretty = indent >= 0;
    switch (value.type()) {
        case value_t::object: {
            if (value.empty()) {
                out += "{}";
                return;
            }
            out += '{';
            bool first = true;
            for (const auto& [key, member] : value.items()) {
                if (!first) out += ',';
                first = false;
                if (pretty) write_indent(out, indent, depth + 1);
                write_string(out, key);
                out += pretty ? ": " : ":";
                write_value(out, member, indent, depth + 1);
            }
            if (pretty) write_indent(out, indent, depth);
            out += '}';
            return;
        }
        case value_t::array: {
            if (value.empty()) {
                out += "[]";
                return;
            }
            out += '[';
            bool first = true;
            for (const auto& element : value) {
                if (!first) out += ',';
                first = false;
                if (pretty) write_indent(out, indent, depth + 1);
                write_value(out, element, indent, depth + 1);
            }
            if (pretty) write_indent(out, indent, depth);
            out += ']';
            return;
        }
        case value_t::number_float: {
            const double x = value.get<double>();
            if (!std::isfinite(x)) {
                out += "null";
                return;
            }
            char text[32];
            out.append(text, json_number_text(text, x));
            return;
        }
        case value_t::string:
            write_string(out, value.get_ref<const std::string&>());
            return;
        case value_t::number_integer:
            write_integer(out, value.get<std::int64_t>());
            return;
        case value_t::number_unsigned:
            write_integer(out, value.get<std::uint64_t>());
            return;
        case value_t::boolean:
            out += value.get<bool>() ? "true" : "false";
            return;
        case value_t::null:
            out += "null";
            return;
        default:  // binary, discarded: nlohmann's own text
            out += value.dump();
            return;
    }
}

}  // namespace

std::string json_text(const nlohmann::ordered_json& document, int indent) {
    std::string out;
    write_value(out, document, indent, 0);
    return out;
}

}  // namespace rayverify
