// json_line writes what json_text writes for the same document, byte for
// byte, and json_text what nlohmann::ordered_json::dump() writes but for the
// spelling of floating-point numbers: escapes, nesting, layout and member
// order; numbers in their shortest round-trip form (never longer than
// nlohmann's Grisu2 text, often shorter: 0.04266, not 0.042659999999999997);
// and every per-case line of an audit of the shipped corpus is a document
// json_text writes to the same bytes.
#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <charconv>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "compare/audit.h"
#include "compare/stability.h"
#include "corpus/corpus_io.h"
#include "intersectors/registry.h"
#include "report/audit_report.h"
#include "report/json_line.h"

namespace rayverify {
namespace {

using json = nlohmann::ordered_json;

TEST(JsonLine, NumbersAreWrittenShortestAndReadBackExactly) {
    const std::uint64_t seed = std::random_device{}();
    std::printf("seed %llu\n", static_cast<unsigned long long>(seed));
    std::mt19937_64 rng(seed);
    std::vector<double> values = {0.0,   -0.0,  1.0,     -1.0,   0.1,    1e-5,   1e21,   1e22,  123456789.0,
                                  1e300, 1e-300, 5e-324, 2.2250738585072014e-308, std::numeric_limits<double>::max(),
                                  0.5,   3.0,   1e15,    1e16,   1e17,   -2.5e-7};
    for (int i = 0; i < 100000; ++i) {
        const double x = std::bit_cast<double>(rng());
        if (std::isfinite(x)) values.push_back(x);
        values.push_back(std::ldexp(static_cast<double>(rng() >> 11), static_cast<int>(rng() % 120) - 60));
    }
    for (const double x : values) {
        json_line line;
        line.value(x);
        const std::string text = line.take();
        ASSERT_EQ(text, json_text(json(x))) << std::hexfloat << x;
        const json read = json::parse(text);
        ASSERT_TRUE(read.is_number_float()) << text;  // an integer's text has ".0", as nlohmann writes it
        ASSERT_EQ(std::bit_cast<std::uint64_t>(read.get<double>()), std::bit_cast<std::uint64_t>(x)) << text;
        ASSERT_LE(text.size(), json(x).dump().size()) << text << " against nlohmann's " << json(x).dump();
    }
    for (const auto& [x, text] : {std::pair{0.04266, "0.04266"}, std::pair{2.0, "2.0"}, std::pair{-120.0, "-120.0"},
                                  std::pair{1e21, "1e+21"}, std::pair{5e-324, "5e-324"}, std::pair{0.1, "0.1"}}) {
        json_line line;
        line.value(x);
        EXPECT_EQ(line.take(), text);
    }
    for (const double x : {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::quiet_NaN()}) {
        json_line line;
        line.value(x);
        EXPECT_EQ(line.take(), json(x).dump());
    }
}

// A decimal spelled from its digits is what json_number_text writes for the
// double nearest it (std::from_chars rounds the decimal correctly): every
// one of one to four digits (and 10^4, a figure rounded up) at every
// exponent that scales it within 10^±40, and random decimals of up to 15
// digits across the normal range; each with both signs, through
// json_line::decimal as well.
TEST(JsonLine, ADecimalIsSpelledAsTheDoubleNearestIt) {
    const auto nearest = [](bool negative, std::uint64_t digits, int exponent) {
        char text[48];
        char* end = std::to_chars(text, text + sizeof text, digits).ptr;
        *end++ = 'e';
        end = std::to_chars(end, text + sizeof text, exponent).ptr;
        double x = 0;
        std::from_chars(text, end, x);
        return negative ? -x : x;
    };
    const auto check = [&](bool negative, std::uint64_t digits, int exponent) {
        char mine[32], theirs[32];
        const std::string_view spelled(mine, json_decimal_text(mine, negative, digits, exponent));
        const double x = nearest(negative, digits, exponent);
        const std::string_view expected(theirs, json_number_text(theirs, x));
        if (spelled != expected)
            return testing::AssertionFailure() << (negative ? "-" : "") << digits << "e" << exponent << ": spelled "
                                               << spelled << ", json_number_text " << expected;
        return testing::AssertionSuccess();
    };
    std::size_t checked = 0;
    for (std::uint64_t digits = 1; digits <= 10000; ++digits)
        for (int exponent = -44; exponent <= 40; ++exponent)
            for (const bool negative : {false, true}) {
                ASSERT_TRUE(check(negative, digits, exponent));
                ++checked;
            }
    const std::uint64_t seed = std::random_device{}();
    std::printf("seed %llu\n", static_cast<unsigned long long>(seed));
    std::mt19937_64 rng(seed);
    for (int i = 0; i < 200000; ++i) {
        const int count = 1 + static_cast<int>(rng() % 15);
        std::uint64_t digits = 1 + rng() % 9;
        for (int k = 1; k < count; ++k) digits = 10 * digits + rng() % 10;
        const int exponent = static_cast<int>(rng() % 601) - 300 - count;
        ASSERT_TRUE(check(rng() % 2 == 0, digits, exponent));
        ++checked;
    }
    json_line line;
    line.begin_array().decimal(false, 4267, -5).decimal(true, 12000, -1).decimal(false, 1, 21).end_array();
    EXPECT_EQ(line.take(), "[0.04267,-1200.0,1e+21]");
    std::printf("%zu decimals spelled as json_number_text writes their doubles\n", checked);
}

TEST(JsonLine, StringsNestingAndOrderAreWrittenAsNlohmannWritesThem) {
    const std::string awkward = std::string("quote \" backslash \\ tab \t newline \n cr \r bs \b ff \f nul ") +
                                std::string(1, '\0') + " unit \x1f del \x7f utf-8 t* ≈ 5, κ·u";
    json_line line;
    line.begin_object()
        .member("text", awkward)
        .member("count", -3)
        .member("big", std::size_t{18446744073709551615ull})
        .member("yes", true)
        .key("none")
        .null()
        .key("empty")
        .begin_object()
        .end_object()
        .key("list")
        .begin_array()
        .value(1.5)
        .begin_array()
        .end_array()
        .begin_object()
        .member("a", "b")
        .end_object()
        .value("x")
        .end_array()
        .key_text(awkward)
        .value(2.0)
        .end_object();
    json want;
    want["text"] = awkward;
    want["count"] = -3;
    want["big"] = std::size_t{18446744073709551615ull};
    want["yes"] = true;
    want["none"] = nullptr;
    want["empty"] = json::object();
    want["list"] = json::array({1.5, json::array(), json{{"a", "b"}}, "x"});
    want[awkward] = 2.0;
    const std::string written = line.take();
    EXPECT_EQ(written, json_text(want));
    EXPECT_EQ(written, want.dump()) << "no number here whose shortest text differs from nlohmann's";
}

// json_text lays a document out as nlohmann's dump does, compact and indented.
TEST(JsonLine, JsonTextLaysOutAsNlohmannDumps) {
    const json document = {{"a", 1},          {"b", json::array({1.5, json::object(), json::array(), "x"})},
                           {"c", json::object()}, {"d", {{"e", nullptr}, {"f", true}}},
                           {"g", -7},         {"h", std::numeric_limits<double>::infinity()}};
    EXPECT_EQ(json_text(document), document.dump());
    EXPECT_EQ(json_text(document, 2), document.dump(2));
    EXPECT_EQ(json_text(document, 4), document.dump(4));
    EXPECT_EQ(json_text(json{{"figure", 0.04266}}, 2), "{\n  \"figure\": 0.04266\n}");
}

// Strings of every length up to 40 with a byte to escape (or none) at every
// place: the word-at-a-time scan finds each.
TEST(JsonLine, EveryEscapeIsFoundWhereverItStands) {
    const std::string specials = std::string("\"\\\b\t\n\f\r\x01\x1f") + std::string(1, '\0');
    const std::string plain_bytes = "az09 _-.,:()[]{}+*!~\x7f";  // ASCII: any mix is valid UTF-8
    for (std::size_t length = 0; length <= 40; ++length)
        for (std::size_t at = 0; at <= length; ++at)
            for (std::size_t k = 0; k <= specials.size(); ++k) {
                std::string text;
                for (std::size_t i = 0; i < length; ++i) text += plain_bytes[(i * 7 + length) % plain_bytes.size()];
                if (at < length && k < specials.size()) text[at] = specials[k];
                json_line line;
                line.value(text);
                ASSERT_EQ(line.take(), json(text).dump()) << "length " << length << ", byte " << k << " at " << at;
                // json_text escapes an ASCII string itself, as a value and as a name.
                const json as_value = json::array({text}), as_name = {{text, 1}};
                ASSERT_EQ(json_text(as_value), as_value.dump()) << "length " << length << ", byte " << k;
                ASSERT_EQ(json_text(as_name, 2), as_name.dump(2)) << "length " << length << ", byte " << k;
            }
}

// json_text writes integers, booleans and null as dump() does, and leaves a
// string with a byte from 0x80 to dump(): valid UTF-8 as it is, invalid
// UTF-8 refused with nlohmann's own error.
TEST(JsonLine, JsonTextWritesEveryScalarAsDumpDoes) {
    const json scalars = json::array({std::numeric_limits<std::int64_t>::min(), std::int64_t{-1}, 0,
                                      std::numeric_limits<std::uint64_t>::max(), true, false, nullptr, "κ·u ≈ 5",
                                      json{{"t* ≈ 5", "ASCII \"quoted\""}}});
    EXPECT_EQ(json_text(scalars), scalars.dump());
    EXPECT_EQ(json_text(scalars, 2), scalars.dump(2));
    const json invalid = json::array({std::string("ab\xff")});
    EXPECT_THROW((void)invalid.dump(), json::type_error);
    EXPECT_THROW((void)json_text(invalid), json::type_error);
    const json invalid_name = {{std::string("\xc3("), 1}};
    EXPECT_THROW((void)json_text(invalid_name), json::type_error);
}

// A member's name written from pieces is the name they make, escaped as one
// text (an escape may stand in any piece, or a piece be empty).
TEST(JsonLine, AKeyFromPiecesIsTheKeyOfTheirJoin) {
    const std::vector<std::array<std::string_view, 3>> names = {
        {"naive", "/", "double"}, {"", "/", ""}, {"a\"b", "/", "c\nd"}, {"plugin\x01", "", "/float"}};
    for (const auto& pieces : names) {
        const std::string whole = std::string(pieces[0]) + std::string(pieces[1]) + std::string(pieces[2]);
        json_line line;
        line.begin_object().key_text(pieces).value(1).end_object();
        ASSERT_EQ(line.take(), (json{{whole, 1}}.dump())) << whole;
        // After another member: the comma, written with the name or before its escapes.
        line.begin_object().member("x", 0).key_text(pieces).value(1).end_object();
        ASSERT_EQ(line.take(), (json{{"x", 0}, {whole, 1}}.dump())) << whole;
    }
}

// hex() writes hex_float's text as a string; a writer given an earlier line's
// storage writes only its own text.
TEST(JsonLine, HexFloatsAndReusedStorage) {
    std::string storage;
    for (const double x : {0.0, -0.0, 1.0, -0x1.fffffffffffffp-1022, 0x1p-1074, 0x1.8p+1023, 3.0e-310,
                           std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
                           std::numeric_limits<double>::quiet_NaN()}) {
        json_line line(std::move(storage));
        line.begin_array().hex(x).value(-1).end_array();
        storage = line.take();
        EXPECT_EQ(storage, "[\"" + hex_float(x) + "\",-1]");
    }
    json_line line(std::string(5000, 'x'));
    line.begin_object().end_object();
    EXPECT_EQ(line.take(), "{}");
}

// Every per-case line of the shipped corpus, with every built-in variant:
// nlohmann reads it and json_text writes the same bytes back.
TEST(JsonLine, PerCaseLinesOfTheShippedCorpusAreNlohmannsBytes) {
    const std::vector<audit_target> targets = targets_for(builtin_variants());
    std::size_t lines = 0;
    for (const corpus_case& c : read_corpus({RAYVERIFY_CORPUS_DIR})) {
        const audited_case audited = audit_case(c, targets);
        const std::string line = per_case_line(audited, targets);
        ASSERT_EQ(json_text(json::parse(line)), line) << c.id;
        ++lines;
    }
    EXPECT_GT(lines, 2000u);
}

}  // namespace
}  // namespace rayverify
