// JSON as rayverify writes it. Numbers are spelled in their shortest
// round-trip form (json_number_text): nlohmann's dump() spells a double by
// Grisu2, which is not always shortest (0.04266 comes out as
// 0.042659999999999997), and every figure is printed to four digits
// (compare/error_figures.h), so that each output's figures read as printed.
// json_text writes a whole nlohmann document so, laid out as dump() lays it
// out; json_line writes a document straight into a string, byte for byte as
// json_text writes the same document: compact, members in the order
// written, strings escaped as nlohmann escapes valid UTF-8. The per-case
// lines of an audit are written this way, a few hundred values for every
// case, without building a document first (tests/json_line_test.cpp checks
// the bytes on every shipped case).
#pragma once

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <string_view>
#include <utility>

#include "core/remembered_by_bits.h"
#include "corpus/corpus_io.h"

namespace rayverify {

// The shortest text that reads back as the finite double x (std::to_chars,
// which is exact), with ".0" after an integer as nlohmann writes one
// ("2.0", "1e+21", "0.04266", "-5e-324"); at most 25 bytes, written at
// `out`. Returns the end.
char* json_number_text(char* out, double x);
// What json_number_text writes for the double nearest ±digits·10^exponent,
// spelled from the digits (no conversion from binary): where the decimal has
// at most 15 significant digits and its nearest double is normal, that
// double's shortest round-trip form is the decimal itself, trailing zeros
// dropped, and only the layout (fixed or scientific, ".0" after an
// integer) is left to choose. 0 < digits < 10^15 (asserted); at most 25
// bytes. Returns the end.
char* json_decimal_text(char* out, bool negative, std::uint64_t digits, int exponent);

// The document as nlohmann's dump(indent) lays it out (indent < 0: compact;
// otherwise one member or element a line), with every floating-point number
// spelled by json_number_text and a non-finite one as null.
std::string json_text(const nlohmann::ordered_json& document, int indent = -1);

// Does JSON write this byte escaped? Control characters, '"' and '\\'.
constexpr bool json_escapes(char ch) {
    const auto byte = static_cast<unsigned char>(ch);
    return byte <= 0x1F || ch == '"' || ch == '\\';
}

namespace json_escaping {
// Might one of the eight bytes of w be one JSON escapes? The word test may report
// a byte that is not one (a borrow from the byte below), never misses one.
inline bool may_escape(std::uint64_t w) {
    constexpr std::uint64_t ones = 0x0101010101010101ull, highs = 0x8080808080808080ull;
    const auto any_below = [&](std::uint64_t v, unsigned n) { return (v - ones * n) & ~v & highs; };
    return (any_below(w, 0x20) | any_below(w ^ (ones * '"'), 1) | any_below(w ^ (ones * '\\'), 1)) != 0;
}
// The length of s's prefix written as it is: eight bytes at a time while no
// byte of the word can be one to escape, then byte by byte. Most texts are
// short names with nothing to escape: the last eight bytes (or the first and
// last four) are tested as one word, overlapping those before, rather than
// byte by byte.
inline std::size_t plain_prefix(std::string_view s) {
    const std::size_t n = s.size();
    std::size_t i = 0;
    if (n >= 8) {
        std::uint64_t w;
        for (; i + 8 <= n; i += 8) {
            std::memcpy(&w, s.data() + i, 8);
            if (may_escape(w)) break;
        }
        if (i == n) return n;
        if (i + 8 > n) {  // the rest, within the last eight bytes
            std::memcpy(&w, s.data() + n - 8, 8);
            if (!may_escape(w)) return n;
        }
    } else if (n >= 4) {
        std::uint32_t first, last;
        std::memcpy(&first, s.data(), 4);
        std::memcpy(&last, s.data() + n - 4, 4);
        if (!may_escape(first | std::uint64_t{last} << 32)) return n;
    }
    while (i < n && !json_escapes(s[i])) ++i;
    return i;
}
}  // namespace json_escaping

// s escaped as nlohmann escapes valid UTF-8 (bytes from 0x80 as they are),
// handed to put(std::string_view) piece by piece in order; the quotes
// around it are the caller's. Runs of characters written as they are go in
// one piece.
template <class Put>
void json_escaped(std::string_view s, Put&& put) {
    const std::size_t plain = json_escaping::plain_prefix(s);
    put(s.substr(0, plain));
    for (std::size_t i = plain; i < s.size(); ++i) {
        const char ch = s[i];
        const auto byte = static_cast<unsigned char>(ch);
        switch (byte) {
            case '\b': put("\\b"); break;
            case '\t': put("\\t"); break;
            case '\n': put("\\n"); break;
            case '\f': put("\\f"); break;
            case '\r': put("\\r"); break;
            case '"': put("\\\""); break;
            case '\\': put("\\\\"); break;
            default:
                if (byte <= 0x1F) {
                    constexpr char hex[] = "0123456789abcdef";
                    const char escape[] = {'\\', 'u', '0', '0', hex[byte >> 4], hex[byte & 0xF]};
                    put(std::string_view(escape, sizeof escape));
                } else {
                    put(s.substr(i, 1));
                }
        }
    }
}

// A member name fixed in the code ("t0", "near_ulp"): checked when compiled
// to need no escaping, so that json_line copies it as it is.
class json_name {
public:
    template <std::size_t N>
    consteval json_name(const char (&text)[N]) : json_name(std::string_view(text, N - 1)) {}  // NOLINT: implicit from a literal
    // A name from a table fixed in the code (error_figures' case_name).
    consteval explicit json_name(std::string_view text) : text_(text) {
        for (const char ch : text_)
            if (json_escapes(ch)) throw "a json_name must be written without escapes; use key_text";
    }
    std::string_view text() const { return text_; }

private:
    std::string_view text_;
};

class json_line {
public:
    json_line() = default;
    // Written into the given string's storage (its text is dropped), with
    // room for about expected_size bytes from the start: a caller writing
    // line after line reuses one allocation. The storage keeps its text's
    // length and is widened to expected_size only, not to its capacity:
    // std::string zero-fills what it widens, and a line widened to the
    // longest line's capacity cleared kilobytes it never wrote.
    explicit json_line(std::string&& storage, std::size_t expected_size = 0) : out_(std::move(storage)) {
        out_.resize(std::max(out_.size(), expected_size));
    }

    json_line& begin_object() { return open('{'); }
    json_line& end_object() { return close('}'); }
    json_line& begin_array() { return open('['); }
    json_line& end_array() { return close(']'); }

    // A member's name; its value follows. key_text takes any text and
    // escapes it as needed.
    json_line& key(json_name name) {
        const std::string_view text = name.text();
        return plain_key(take_separator(), std::span<const std::string_view>(&text, 1), text.size());
    }
    json_line& key_text(std::string_view name) { return key_text(std::span<const std::string_view>(&name, 1)); }
    // A name written from pieces, escaped as the one text they make. Pieces
    // with nothing to escape (a target's name, "/", its precision) are
    // written as key(json_name) writes a name, with one check for room.
    json_line& key_text(std::span<const std::string_view> pieces) {
        std::size_t size = 0;
        bool plain = true;
        for (std::string_view piece : pieces) {
            size += piece.size();
            plain = plain && json_escaping::plain_prefix(piece) == piece.size();
        }
        const bool comma = take_separator();
        if (plain) return plain_key(comma, pieces, size);
        after_key_ = true;
        if (comma) put(',');
        put('"');
        for (std::string_view piece : pieces) escaped(piece);
        put(std::string_view("\":"));
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
        put(b ? std::string_view("true") : std::string_view("false"));
        return *this;
    }
    template <class Integer>
        requires std::is_integral_v<Integer>
    json_line& value(Integer n) {
        separate();
        char* const at = room(24);
        used_ += static_cast<std::size_t>(std::to_chars(at, at + 24, n).ptr - at);
        return *this;
    }
    // A double as the string of its C99 hex float (hex_float's text), which
    // never needs escaping.
    json_line& hex(double x) {
        separate();
        char* const at = room(hex_float_max_size + 2);
        *at = '"';
        char* const end = write_hex_float(at + 1, x);
        *end = '"';
        used_ += static_cast<std::size_t>(end + 1 - at);
        return *this;
    }
    // A double as nlohmann writes one (null when not finite).
    json_line& value(double x) {
        separate();
        if (!std::isfinite(x)) {
            put("null");
            return *this;
        }
        put(shortest_text_of(x));
        return *this;
    }
    // The double nearest ±digits·10^exponent, written as value(double) writes
    // it (json_decimal_text's conditions).
    json_line& decimal(bool negative, std::uint64_t digits, int exponent) {
        separate();
        char* const at = room(25);
        used_ += static_cast<std::size_t>(json_decimal_text(at, negative, digits, exponent) - at);
        return *this;
    }
    json_line& null() {
        separate();
        put("null");
        return *this;
    }

    // key(name).value(v)
    template <class T>
    json_line& member(json_name name, const T& v) {
        return key(name).value(v);
    }

    // The text, moved out; the writer is empty afterwards.
    std::string take() {
        out_.resize(used_);
        used_ = 0;
        first_ = true;
        after_key_ = false;
        return std::exchange(out_, {});
    }

private:
    // n writable bytes at the end of the text (the string grows geometrically;
    // its size runs ahead of the text, used_ bytes long, until take()).
    char* room(std::size_t n) {
        if (out_.size() - used_ < n) [[unlikely]]
            grow(n);
        return out_.data() + used_;
    }
    [[gnu::noinline]] void grow(std::size_t n) { out_.resize(std::max(2 * out_.size(), used_ + n + 256)); }
    void put(char ch) { *room(1) = ch, ++used_; }
    void put(std::string_view s) {
        copy_piece(room(s.size()), s);
        used_ += s.size();
    }
    // Most pieces of a line are short (names, verdicts, brackets with
    // quotes): copied by two overlapping fixed-size copies within the
    // piece, not by a call to memmove, which cost more than the copy.
    static void copy_piece(char* at, std::string_view s) {
        const std::size_t n = s.size();
        if (n >= 8 && n <= 16) {
            std::memcpy(at, s.data(), 8);
            std::memcpy(at + n - 8, s.data() + n - 8, 8);
        } else if (n >= 4 && n < 8) {
            std::memcpy(at, s.data(), 4);
            std::memcpy(at + n - 4, s.data() + n - 4, 4);
        } else if (n < 4) {
            for (std::size_t i = 0; i < n; ++i) at[i] = s[i];
        } else {
            std::memcpy(at, s.data(), n);
        }
    }

    // A name whose pieces need no escaping (`size` bytes in all), after a
    // comma where `comma` asks for one: written with one check for room.
    // Piece by piece, through put's out-of-line calls, each piece reloaded
    // the string's size and the text's length.
    json_line& plain_key(bool comma, std::span<const std::string_view> pieces, std::size_t size) {
        char* at = room(size + 4);
        if (comma) *at++ = ',';
        *at++ = '"';
        for (std::string_view piece : pieces) {
            copy_piece(at, piece);
            at += piece.size();
        }
        at[0] = '"';
        at[1] = ':';
        used_ += static_cast<std::size_t>(comma) + size + 3;
        after_key_ = true;
        return *this;
    }

    json_line& open(char bracket) {
        separate();
        put(bracket);
        first_ = true;
        return *this;
    }
    json_line& close(char bracket) {
        put(bracket);
        first_ = false;
        return *this;
    }
    // Whether a comma comes before the next value or key: not after a key,
    // nor before the first of its container (the state moves past it).
    bool take_separator() {
        if (after_key_) {
            after_key_ = false;
            return false;
        }
        const bool comma = !first_ && used_ != 0;
        first_ = false;
        return comma;
    }
    // The comma before a value or key that is not the first of its container.
    void separate() {
        if (take_separator()) put(',');
    }
    void quoted(std::string_view s) {
        put('"');
        escaped(s);
        put('"');
    }
    // s escaped as JSON requires (the quotes around it are the caller's).
    void escaped(std::string_view s) {
        json_escaped(s, [this](std::string_view piece) { put(piece); });
    }

    // json_number_text of a finite double. A per-case line repeats many
    // values (variants that compute alike give the same figures), so the
    // texts of recent values are kept, per thread, in a small table indexed
    // by a hash of the bits (a slot holds the last value that hashed to it).
    static std::string_view shortest_text_of(double x) {
        struct number_text {
            std::uint32_t size = 0;
            std::array<char, 28> text{};  // at most 24: "-1.2345678901234567e-308"
        };
        static thread_local remembered_by_bits<number_text> recent;
        const number_text& remembered = recent.of(x, [](double v) {
            number_text t;
            t.size = static_cast<std::uint32_t>(json_number_text(t.text.data(), v) - t.text.data());
            return t;
        });
        return {remembered.text.data(), remembered.size};
    }

    std::string out_;         // the text is its first used_ bytes
    std::size_t used_ = 0;
    bool first_ = true;       // the next value or key opens its container
    bool after_key_ = false;  // the next value is a member's, after its key
};

}  // namespace rayverify
