// JSON from an input: the one parser (corpus/json_input.h) names the line and
// field of what is wrong and keeps each value's line; one mapping per format
// (corpus/json_mapping.h): what a mapping writes reads back to the same value
// and the same JSON, and what is wrong in a document is named by its path; a
// shard's state file, written by an audit, reads back and writes again byte for byte.
#include <gtest/gtest.h>

#include <array>
#include <filesystem>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/input_error.h"
#include "corpus/json_input.h"
#include "corpus/json_mapping.h"
#include "report/shard_state.h"
#include "support/process.h"

namespace {

using json = nlohmann::ordered_json;
using rayverify::input_error;
using rayverify::json_io;

enum class colour { red, green };

std::optional<colour> colour_from_name(std::string_view name) {
    if (name == "red") return colour::red;
    if (name == "green") return colour::green;
    return std::nullopt;
}
const char* colour_name(colour c) { return c == colour::red ? "red" : "green"; }

void map_json(json_io& io, colour& c) { io.name(c, colour_name, colour_from_name, "red or green"); }

struct item {
    std::size_t count = 0;
    double exact = 0;
};

void map_json(json_io& io, item& i) {
    io.field("count", i.count);
    io.field("exact", i.exact);
    if (io.reading() && i.count > 100) io.fail("count", "is more than 100");
}

struct record {
    std::string name;
    bool on = false;
    colour shade = colour::red;
    std::vector<item> items;
    std::map<std::string, std::size_t> by_key;
    std::array<std::size_t, 2> pair{};
    std::optional<double> figure;                 // json_number's spelling, or null
    std::optional<std::string> note, link;        // note: absent when unset; link: null when unset
    json anything;
};

void map_json(json_io& io, record& r) {
    io.field("name", r.name);
    io.field("on", r.on);
    io.field("shade", r.shade);
    io.field("items", r.items);
    io.field("by_key", r.by_key);
    io.field("pair", r.pair, [](std::size_t i) { return i == 0 ? "first" : "second"; });
    io.field("figure", r.figure);
    io.optional_field("note", r.note);
    io.nullable_field("link", r.link);
    io.field("anything", r.anything);
}

record sample() {
    record r;
    r.name = "sphere";
    r.on = true;
    r.shade = colour::green;
    r.items = {item{}, item{7, 0.1}};  // 0.1: the hex float keeps every bit
    r.by_key = {{"b", 2}, {"a", 1}};
    r.pair = {3, 4};
    r.figure = std::numeric_limits<double>::infinity();
    r.link = "elsewhere";
    r.anything = json::parse(R"({"x":[1,"two",null]})");
    return r;
}

// The error reading `doc` as a record gives, "" when it reads.
std::string read_error(const json& doc) {
    try {
        (void)rayverify::from_json_mapped<record>(doc, "doc.json");
        return "";
    } catch (const input_error& e) {
        return e.what();
    }
}

TEST(JsonMapping, WhatIsWrittenReadsBackToTheSameValueAndTheSameJson) {
    const record written = sample();
    const json doc = rayverify::to_json_mapped(written);
    EXPECT_EQ(doc.dump(),
              R"({"name":"sphere","on":true,"shade":"green","items":[{"count":0,"exact":"0x0p+0"},)"
              R"({"count":7,"exact":"0x1.999999999999ap-4"}],"by_key":{"a":1,"b":2},"pair":[3,4],"figure":"inf",)"
              R"("link":"elsewhere","anything":{"x":[1,"two",null]}})");
    const record read = rayverify::from_json_mapped<record>(doc, "doc.json");
    EXPECT_EQ(read.name, written.name);
    EXPECT_EQ(read.shade, colour::green);
    ASSERT_EQ(read.items.size(), 2u);
    EXPECT_EQ(read.items[1].exact, 0.1);
    EXPECT_EQ(read.by_key, written.by_key);
    EXPECT_EQ(read.pair, written.pair);
    EXPECT_EQ(read.figure, written.figure);
    EXPECT_FALSE(read.note.has_value());
    EXPECT_EQ(read.link, written.link);
    EXPECT_EQ(rayverify::to_json_mapped(read), doc);
}

TEST(JsonMapping, OptionalMembersAreLeftOutAndNullableOnesWrittenAsNull) {
    record r = sample();
    r.link.reset();
    r.note = "kept";
    r.figure.reset();
    const json doc = rayverify::to_json_mapped(r);
    EXPECT_EQ(doc["note"], "kept");
    EXPECT_TRUE(doc["link"].is_null());
    EXPECT_TRUE(doc["figure"].is_null());
    const record read = rayverify::from_json_mapped<record>(doc, "doc.json");
    EXPECT_EQ(read.note, "kept");
    EXPECT_FALSE(read.link.has_value());
    EXPECT_FALSE(read.figure.has_value());
}

TEST(JsonMapping, EveryWrongValueIsNamedByItsPath) {
    const json good = rayverify::to_json_mapped(sample());
    ASSERT_EQ(read_error(good), "");
    const auto edited = [&](const std::string& pointer, const json& value) {
        json doc = good;
        doc[json::json_pointer(pointer)] = value;
        return read_error(doc);
    };
    EXPECT_EQ(edited("/items/1/count", -1), "doc.json: field 'items[1].count': is -1, expected a whole number ≥ 0");
    EXPECT_EQ(edited("/items/1/count", 101u), "doc.json: field 'items[1].count': is more than 100");
    EXPECT_EQ(edited("/items/0/exact", "0x1p+0x"), "doc.json: field 'items[0].exact': '0x1p+0x' is not a number");
    EXPECT_EQ(edited("/items/0", 3), "doc.json: field 'items[0]': is not a JSON object");
    EXPECT_EQ(edited("/items", json::object()), "doc.json: field 'items': is {}, expected an array");
    EXPECT_EQ(edited("/shade", "blue"), "doc.json: field 'shade': 'blue' is not red or green");
    EXPECT_EQ(edited("/pair/1", "x"), "doc.json: field 'pair[1] (second)': is \"x\", expected a whole number ≥ 0");
    EXPECT_EQ(edited("/pair", json::array({1})), "doc.json: field 'pair': has 1 entries, expected 2");
    EXPECT_EQ(edited("/by_key/a", true), "doc.json: field 'by_key.a': is true, expected a whole number ≥ 0");
    EXPECT_EQ(edited("/figure", "0x1p+0"),
              "doc.json: field 'figure': is \"0x1p+0\", expected a number, \"inf\", \"-inf\", \"nan\" or null");
    EXPECT_EQ(edited("/on", 1), "doc.json: field 'on': is 1, expected true or false");
    EXPECT_EQ(edited("/note", nullptr), "doc.json: field 'note': is null, expected a string");
    json without_name = good;
    without_name.erase("name");
    EXPECT_EQ(read_error(without_name), "doc.json: field 'name': is missing");
    EXPECT_EQ(read_error(json::array()), "doc.json: is not a JSON object");
}

// The error parsing `text` (a document starting on line 3 of "f.json") gives; "" when it parses.
std::string parse_error_of(std::string_view text) {
    try {
        (void)rayverify::parse_json_input(text, "f.json", 3);
        return "";
    } catch (const input_error& e) {
        return e.what();
    }
}

TEST(JsonInput, EachValuesLineIsKeptByItsPath) {
    // Worked by hand: a number is read one character past its end (here a
    // line break), a string's line is its own, an object's where it opens.
    const std::string text = "\xEF\xBB\xBF{\n  \"a\": 1\n  ,\"b\": [\n    true,\n    {\"c\": \"x\"}, 2.5],\n  \"d\": null\n}\n";
    const rayverify::located_json j = rayverify::parse_located_json_input(text, "f.json", 10);
    EXPECT_EQ(j.document["b"][1]["c"], "x");
    EXPECT_EQ(j.lines.at(""), 10u);
    EXPECT_EQ(j.lines.at("a"), 11u);
    EXPECT_EQ(j.lines.at("b"), 12u);
    EXPECT_EQ(j.lines.at("b[0]"), 13u);
    EXPECT_EQ(j.lines.at("b[1]"), 14u);
    EXPECT_EQ(j.lines.at("b[1].c"), 14u);
    EXPECT_EQ(j.lines.at("b[2]"), 14u);
    EXPECT_EQ(j.lines.at("d"), 15u);
    EXPECT_EQ(j.line_of("b[1].c.missing"), 14u);  // the nearest value that has a line
    EXPECT_EQ(j.line_of("nowhere"), 10u);
}

TEST(JsonInput, WhatIsNotJsonIsNamedByLineAndField) {
    EXPECT_EQ(parse_error_of("{\"a\": [1,\n 2,\n x]}"),
              "f.json:5: field 'a[2]': not valid JSON: syntax error while parsing value - invalid literal; last read: "
              "'2,<U+000A> x'");
    EXPECT_EQ(parse_error_of("{\"a\": 1,\n\"a\": 2}"), "f.json:3: field 'a': the key \"a\" is given twice in one object");
    EXPECT_EQ(parse_error_of("{\"a\": 1e400}"), "f.json:3: field 'a': number overflow parsing '1e400'");
    EXPECT_EQ(parse_error_of(std::string(65, '[') + std::string(65, ']')), "f.json:3: nested more than 64 levels deep");
    EXPECT_EQ(parse_error_of(std::string(64, '[') + std::string(64, ']')), "");
    // With lines kept, a duplicate key is named on its own line.
    try {
        (void)rayverify::parse_located_json_input("{\"a\": 1,\n\"a\": 2}", "f.json", 3);
        ADD_FAILURE() << "a duplicate key parsed";
    } catch (const input_error& e) {
        EXPECT_STREQ(e.what(), "f.json:4: field 'a': the key \"a\" is given twice in one object");
    }
}

// A shard's state as the audit writes it is what its mapping writes again
// from what it reads: the writer, the reader and the checks are one mapping.
TEST(JsonMapping, AShardStateReadsBackAndWritesAgainByteForByte) {
    rayverify::test_support::scratch_directory dir("json_mapping");
    const auto audit = rayverify::test_support::run_shell(
        "cd '" + dir.path().string() + "' && '" RAYVERIFY_CLI "' audit --generate uniform:60:1 --generate inside:50:3 --variant naive --variant robust --shard 2/3 --report s2 --per-case s2/cases.jsonl");
    ASSERT_TRUE(audit.exit_code == 0 || audit.exit_code == 1) << audit.output;
    const std::filesystem::path file = dir.path() / "s2" / rayverify::shard_state_file;
    const std::string text = rayverify::test_support::read_text(file);
    const json doc = json::parse(text);
    const rayverify::shard_header header = rayverify::read_shard_header(doc, file.string());
    EXPECT_EQ(header.shard.text(), "2/3");
    EXPECT_EQ(header.targets.size(), 4u);
    ASSERT_TRUE(header.per_case_file.has_value());
    const rayverify::audit_state state = rayverify::read_shard_state(doc, file.string(), header);
    EXPECT_EQ(rayverify::shard_document(header, state).dump() + "\n", text);
}

}  // namespace
