#include "corpus/corpus_io.h"

#include <sys/stat.h>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "corpus/case_stream.h"
#include "support/process.h"

using namespace rayverify;
namespace fs = std::filesystem;
using test_support::scratch_directory;

namespace {

using limits = std::numeric_limits<double>;

bool same_bits(double a, double b) {
    if (std::isnan(a) || std::isnan(b))
        return std::isnan(a) && std::isnan(b) && std::signbit(a) == std::signbit(b);
    return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}

double parse(std::string_view token) { return parse_exact_double(token, "t.txt", 1, "ox"); }

// The message of the input_error f throws; a test failure if it throws nothing.
template <class F>
std::string error_of(F&& f) {
    try {
        f();
    } catch (const input_error& e) {
        return e.what();
    }
    ADD_FAILURE() << "no input_error thrown";
    return "";
}

// Boundary values first: zeros, subnormals, the ends of the normal range, non-finite.
const std::vector<double> boundary_values = {
    0.0, -0.0, 1.0, -1.0, 0.1, 1.0 / 3, 4100, 3.0, -1e-300,
    limits::denorm_min(), -limits::denorm_min(), 2 * limits::denorm_min(), 0x1.23p-1060,
    0x0.fffffffffffffp-1022, limits::min(), -limits::min(), limits::max(), limits::lowest(),
    limits::epsilon(), 1 + limits::epsilon(),
    limits::infinity(), -limits::infinity(), limits::quiet_NaN(), -limits::quiet_NaN()};

corpus_case sample_case(std::string id) {
    corpus_case c;
    c.id = std::move(id);
    c.family = "tangent";
    c.geometry = {{0.1, -0.0, -5}, {0, 0, 1}, {limits::denorm_min(), 0x1.8p+1, 4100}, 1};
    return c;
}

void expect_same_case(const corpus_case& a, const corpus_case& b) {
    EXPECT_EQ(a.id, b.id);
    EXPECT_EQ(a.family, b.family);
    const auto& g = a.geometry;
    const auto& h = b.geometry;
    const double x[] = {g.origin.x,    g.origin.y, g.origin.z, g.direction.x, g.direction.y,
                        g.direction.z, g.centre.x, g.centre.y, g.centre.z,    g.radius};
    const double y[] = {h.origin.x,    h.origin.y, h.origin.z, h.direction.x, h.direction.y,
                        h.direction.z, h.centre.x, h.centre.y, h.centre.z,    h.radius};
    for (int i = 0; i < 10; ++i) EXPECT_TRUE(same_bits(x[i], y[i])) << a.id << " input " << i;
    ASSERT_EQ(a.tmin.has_value(), b.tmin.has_value()) << a.id;
    ASSERT_EQ(a.tmax.has_value(), b.tmax.has_value()) << a.id;
    EXPECT_TRUE(!a.tmin || same_bits(*a.tmin, *b.tmin)) << a.id;
    EXPECT_TRUE(!a.tmax || same_bits(*a.tmax, *b.tmax)) << a.id;
}

// Each test gets its own directory, removed afterwards.
class CorpusFiles : public ::testing::Test {
protected:
    fs::path write(const std::string& name, const std::string& contents) {
        const fs::path path = dir_ / name;
        std::ofstream(path, std::ios::binary) << contents;
        return path;
    }
    // The message of the error reading a file with these contents throws.
    std::string read_error(const std::string& name, const std::string& contents) {
        const fs::path path = write(name, contents);
        return error_of([&] { read_corpus_file(path); });
    }
    // The "file:line" a message names.
    std::string at(const std::string& name, int line) const {
        return fmt::format("{}:{}", (dir_ / name).string(), line);
    }

    scratch_directory scratch_{"rayverify_corpus_io_test"};
    const fs::path dir_ = scratch_.path();
};

const std::string unit_case = "0 0 -5 0 0 1 0 0 0 1";  // the ten numbers of a simple hit

}  // namespace

TEST(HexFloat, RoundTripsBoundaryValues) {
    for (double x : boundary_values) {
        EXPECT_TRUE(same_bits(parse(hex_float(x)), x)) << hex_float(x);
        EXPECT_TRUE(same_bits(parse(shortest_decimal(x)), x)) << shortest_decimal(x);
    }
}

TEST(HexFloat, RoundTripsRandomBitPatterns) {
    const unsigned seed = 20240611;
    std::mt19937_64 bits(seed);
    for (int i = 0; i < 20000; ++i) {
        const double x = std::bit_cast<double>(bits());
        ASSERT_TRUE(same_bits(parse(hex_float(x)), x))
            << "seed " << seed << " index " << i << ": " << hex_float(x);
        ASSERT_TRUE(same_bits(parse(shortest_decimal(x)), x)) << "seed " << seed << " index " << i;
    }
}

// The same text as C's %a (through fmt's {:a}) for every class of double:
// random bit patterns (NaNs with payloads and either sign among them),
// subnormals, powers of two and the boundary values.
TEST(HexFloat, IsTheTextOfPrintfsPercentA) {
    const unsigned seed = 20261126;
    std::mt19937_64 bits(seed);
    std::vector<double> values(boundary_values.begin(), boundary_values.end());
    for (int i = 0; i < 200000; ++i) values.push_back(std::bit_cast<double>(bits()));
    for (int i = 0; i < 20000; ++i) values.push_back(std::bit_cast<double>(bits() >> 12));  // subnormals
    for (int e = -1074; e <= 1023; ++e) values.push_back(std::ldexp(1.0, e));
    for (std::size_t i = 0; i < values.size(); ++i) {
        const double x = values[i];
        ASSERT_EQ(hex_float(x), fmt::format("{:a}", x)) << "seed " << seed << " value " << i;
        ASSERT_EQ(hex_float(-x), fmt::format("{:a}", -x)) << "seed " << seed << " value " << i;
    }
}

TEST(HexFloat, TextForms) {
    EXPECT_EQ(hex_float(3.0), "0x1.8p+1");
    EXPECT_EQ(hex_float(-0.0), "-0x0p+0");
    EXPECT_EQ(hex_float(limits::infinity()), "inf");
    EXPECT_EQ(hex_float(-limits::infinity()), "-inf");
    EXPECT_EQ(hex_float(limits::quiet_NaN()), "nan");
    EXPECT_EQ(shortest_decimal(0.1), "0.1");
}

TEST(ParseExactDouble, DecimalAndHexFormsAgree) {
    const std::pair<const char*, const char*> same[] = {
        {"0.1", "0x1.999999999999ap-4"},
        {"3", "0x1.8p+1"},
        {"8", "0X1P3"},
        {"+2", "+0x1p1"},
        {"4100", "0x1.004p+12"},
        {"-0", "-0x0p+0"},
        {"-0.5", "-0x.8p0"},
        {"4.9406564584124654e-324", "0x1p-1074"},
        {"-1e-300", "-0x1.56e1fc2f8f359p-997"},
        {"2.2250738585072014e-308", "0x1p-1022"},
        {"1.7976931348623157e308", "0x1.fffffffffffffp+1023"}};
    for (const auto& [decimal, hex] : same) {
        EXPECT_TRUE(same_bits(parse(decimal), parse(hex))) << decimal << " vs " << hex;
        EXPECT_TRUE(same_bits(parse(hex), parse(hex_float(parse(hex))))) << hex;
    }
    EXPECT_TRUE(std::signbit(parse("-0x0p+0")));
    EXPECT_EQ(parse("-0x1p-1074"), -limits::denorm_min());
    EXPECT_EQ(parse("0x0.0000000000001p-1022"), limits::denorm_min());
}

// Hex floats written every way a person or another tool might write one (a
// point anywhere or none, leading and trailing zeros, either case, exponents
// from below the subnormals to past the largest double), read as exactly
// what they spell or refused: against strtod's reading (exact for a value a
// double holds) and an exactness decided apart from both, from the odd part
// of the significand and of the value. Covers the short path for the forms a
// corpus holds (at most 16 significant digits) and the general one.
TEST(ParseExactDouble, HexFormsReadExactlyOrRefused) {
    const unsigned seed = 20261130;
    std::mt19937_64 random(seed);
    const auto draw = [&](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(random); };
    int accepted = 0, refused = 0;
    for (int i = 0; i < 100000; ++i) {
        // m: 1 to 16 hex digits, the point after `integer` of them.
        const int digits = draw(1, 16);
        std::uint64_t m = 0;
        std::string text;
        for (int k = 0; k < digits; ++k) {
            const int d = k == 0 ? draw(0, 15) : (draw(0, 3) == 0 ? 0 : draw(0, 15));
            m = m << 4 | static_cast<std::uint64_t>(d);
            text += "0123456789abcdef"[d];
        }
        const int integer = draw(0, digits);
        const int fraction = digits - integer;
        std::string token = draw(0, 1) ? "-" : "";
        token += draw(0, 1) ? "0x" : "0X";
        token += std::string(static_cast<std::size_t>(draw(0, 2)), '0') + text.substr(0, integer);
        if (fraction > 0 || draw(0, 1)) token += "." + text.substr(integer);
        token += std::string(static_cast<std::size_t>(fraction > 0 ? draw(0, 3) : 0), '0');  // zeros past 16 digits
        if (integer == 0 && fraction == 0) token += "0";
        const int exponent = draw(-1150, 1100);
        token += fmt::format("{}{}{}", draw(0, 1) ? 'p' : 'P', exponent >= 0 && draw(0, 1) ? "+" : "", exponent);
        for (char& c : token)
            if (draw(0, 3) == 0 && c >= 'a' && c <= 'f') c = static_cast<char>(c - 'a' + 'A');

        // Exact iff m·2^p is 0 or a double: its odd part below 2^53, its lowest bit at or above
        // 2^−1074, its highest below 2^1024.
        const long long p = exponent - 4LL * fraction;
        bool exact = true;
        if (m != 0) {
            const int trailing = std::countr_zero(m);
            const std::uint64_t odd = m >> trailing;
            const long long low = p + trailing, high = low + std::bit_width(odd) - 1;
            exact = std::bit_width(odd) <= 53 && low >= -1074 && high <= 1023;
        }
        if (!exact) {
            EXPECT_FALSE(error_of([&] { parse(token); }).empty()) << token << " (seed " << seed << ")";
            ++refused;
            continue;
        }
        const double read = parse(token), reference = std::strtod(token.c_str(), nullptr);
        EXPECT_TRUE(same_bits(read, reference)) << token << " read " << hex_float(read) << " (seed " << seed << ")";
        ++accepted;
    }
    EXPECT_GT(accepted, 10000);
    EXPECT_GT(refused, 10000);
}

TEST(ParseExactDouble, AcceptsNanAndInfinitySpellings) {
    for (const char* t : {"nan", "NaN", "-nan", "NAN"}) EXPECT_TRUE(std::isnan(parse(t))) << t;
    for (const char* t : {"inf", "+inf", "Infinity", "INF"})
        EXPECT_EQ(parse(t), limits::infinity()) << t;
    for (const char* t : {"-inf", "-INFINITY"}) EXPECT_EQ(parse(t), -limits::infinity()) << t;
}

TEST(ParseExactDouble, RejectsMalformedTokensNamingFileLineAndField) {
    const std::pair<const char*, const char*> bad[] = {
        {"1.0abc", "expected a number"},
        {"abc", "expected a number"},
        {"0x", "expected a number"},
        {"", "expected a number"},
        {"+-1", "expected a number"},
        {"--1", "expected a number"},
        {"1e", "expected a number"},
        {"0xinf", "expected a number"},
        {"nan(1)", "expected a number"},
        {"1,5", "expected a number"},
        {"0x1.8q1", "expected a number"},
        {"0x1p+-5", "expected a number"},  // from_chars read it as 0x1p-5
        {"0x1p-+5", "expected a number"},
        {"1e+-5", "expected a number"},
        {"0x1p", "expected a number"},
        {"1e999", "out of double range"},
        {"-1e999", "out of double range"},
        {"0x1p2000", "out of double range"},
        {"0x1p1024", "out of double range"},
        {"1e-400", "not exactly representable"},
        {"-2e-324", "not exactly representable"},
        {"0x1p-1075", "not exactly representable"},
        {"0x1.00000000000008p0", "not exactly representable"},
        {"0x1.8p-1075", "not exactly representable"}};
    for (const auto& [token, problem] : bad) {
        const std::string message =
            error_of([&malformed = token] { parse_exact_double(malformed, "corpus/x.txt", 17, "dx"); });
        EXPECT_NE(message.find(fmt::format("corpus/x.txt:17: field 'dx': {}", problem)),
                  std::string::npos)
            << token << " -> " << message;
        EXPECT_NE(message.find(fmt::format("got '{}'", token)), std::string::npos) << message;
    }
}

TEST(FormatCaseLine, HexFieldsDashForUnknownAndReadsBack) {
    corpus_case c = sample_case("tan-1");
    c.family = "";
    EXPECT_EQ(format_case_line(c),
              "tan-1 - 0x1.999999999999ap-4 -0x0p+0 -0x1.4p+2 0x0p+0 0x0p+0 0x1p+0 "
              "0x0.0000000000001p-1022 0x1.8p+1 0x1.004p+12 0x1p+0");
    c.tmax = 2.5;
    EXPECT_TRUE(format_case_line(c).ends_with(" 0x1p+0 - 0x1.4p+1"));
    c.id = "has space";
    EXPECT_NE(error_of([&] { format_case_line(c); }).find("field 'id'"), std::string::npos);
    EXPECT_TRUE(corpus_header_comment().starts_with("# id family ox oy oz dx dy dz cx cy cz r"));
}

TEST_F(CorpusFiles, ReadsTextWithCommentsBlanksAndOptionalInterval) {
    const std::string contents = "# provenance: hand-written\n"
                                 "\n"
                                 "a hit " + unit_case + "   # a trailing comment\r\n"
                                 "   \t\n"
                                 "b - 0x1p-1074 -0 +1e-300 0x1.8p+1 0X1P3 1 inf -inf nan 4100"
                                 " 0 10\n"
                                 "c - " + unit_case + " - 7\n";
    const fs::path path = write("t.txt", contents);
    const auto cases = read_corpus_file(path);
    ASSERT_EQ(cases.size(), 3u);
    EXPECT_EQ(cases[0].id, "a");
    EXPECT_EQ(cases[0].family, "hit");
    EXPECT_EQ(cases[0].geometry.origin.z, -5);
    EXPECT_FALSE(cases[0].tmin || cases[0].tmax);
    EXPECT_EQ(cases[0].source, at("t.txt", 3));
    EXPECT_EQ(cases[1].family, "");
    EXPECT_EQ(cases[1].geometry.origin.x, limits::denorm_min());
    EXPECT_TRUE(std::signbit(cases[1].geometry.origin.y));
    EXPECT_EQ(cases[1].geometry.direction.y, 8);
    EXPECT_TRUE(std::isnan(cases[1].geometry.centre.z));
    EXPECT_EQ(cases[1].tmin, 0.0);
    EXPECT_EQ(cases[1].tmax, 10.0);
    EXPECT_EQ(cases[1].source, at("t.txt", 5));
    EXPECT_FALSE(cases[2].tmin);
    EXPECT_EQ(cases[2].tmax, 7.0);
}

TEST_F(CorpusFiles, TextErrorsNameFileLineAndField) {
    std::string message = read_error("n.txt", "# c\na f " + unit_case + " 1\n");
    EXPECT_NE(message.find(at("n.txt", 2) + ": found 13 fields, expected 12"), std::string::npos)
        << message;
    message = read_error("d.txt", "a f 0 0 0 1.0abc 0 0 0 0 0 1\n");
    EXPECT_NE(message.find(at("d.txt", 1) + ": field 'dx': expected a number, got '1.0abc'"),
              std::string::npos)
        << message;
    message = read_error("r.txt", "\n\na f 0 0 0 0 0 1 0 0 0 1e-400\n");
    EXPECT_NE(message.find(at("r.txt", 3) +
                           ": field 'r': not exactly representable as a double (underflows"),
              std::string::npos)
        << message;
    message = read_error("i.txt", "a f " + unit_case + " 0 0x\n");
    EXPECT_NE(message.find(at("i.txt", 1) + ": field 'tmax'"), std::string::npos) << message;
}

TEST_F(CorpusFiles, BinaryGarbageGivesCleanErrors) {
    const std::pair<std::string, const char*> garbage[] = {
        {std::string("a f 0 0\0 0 0 1 0 0 0 1\n", 24), "NUL byte"},
        {"a f " + unit_case + " \xFF\n", "not valid UTF-8"},
        {"# overlong \xC0\x80\n", "not valid UTF-8"},
        {"# truncated \xE2\x82", "not valid UTF-8"},
        {"# surrogate \xED\xA0\x80\n", "not valid UTF-8"},
        {"# long " + std::string(1 << 20, 'x') + "\n", "longer than 1 MB"}};
    for (const auto& [contents, problem] : garbage) {
        const std::string message = read_error("g.txt", "# fine: Δ ≤ 1e-7\n" + contents);
        EXPECT_NE(message.find(at("g.txt", 2) + ": line"), std::string::npos) << message;
        EXPECT_NE(message.find(problem), std::string::npos) << message;
    }
}

TEST_F(CorpusFiles, MissingUnreadableAndEmptyInputsAreLineZeroErrors) {
    const fs::path missing = dir_ / "missing.txt";
    EXPECT_EQ(error_of([&] { read_corpus({missing}); }), missing.string() + ": no such file");
    EXPECT_EQ(error_of([&] { read_corpus_file(dir_); }),
              dir_.string() + ": is a directory, expected a corpus file");
    const fs::path empty = write("empty.txt", "# only a comment\n\n");
    EXPECT_TRUE(read_corpus_file(empty).empty());
    EXPECT_EQ(error_of([&] { read_corpus({empty}); }),
              empty.string() + ": empty corpus: no cases found");
    fs::create_directory(dir_ / "nothing");
    EXPECT_NE(error_of([&] { read_corpus({dir_ / "nothing"}); }).find("empty corpus"),
              std::string::npos);
}

TEST_F(CorpusFiles, CsvWithReorderedQuotedAndUnknownColumns) {
    const fs::path path = write("c.CSV",
                                "# exported by hand\n"
                                " R , note, \"ID\",oz,oy,ox,dz,dy,dx,cz,cy,cx, Family ,tmax\n"
                                "2, x y z ,\"a\",-5,0,0,1,0,0,0,0,0x1p-1074,grazing,\n"
                                "\n"
                                "1,,b , 0.1 ,0,0,1,0,0,0,0,0,,\"3\"\n");
    const auto cases = read_corpus_file(path);
    ASSERT_EQ(cases.size(), 2u);
    EXPECT_EQ(cases[0].id, "a");
    EXPECT_EQ(cases[0].family, "grazing");
    EXPECT_EQ(cases[0].geometry.radius, 2);
    EXPECT_EQ(cases[0].geometry.origin.z, -5);
    EXPECT_EQ(cases[0].geometry.direction.z, 1);
    EXPECT_EQ(cases[0].geometry.centre.x, limits::denorm_min());
    EXPECT_FALSE(cases[0].tmin || cases[0].tmax);
    EXPECT_EQ(cases[0].source, at("c.CSV", 3));
    EXPECT_EQ(cases[1].id, "b");
    EXPECT_EQ(cases[1].family, "");
    EXPECT_EQ(cases[1].geometry.origin.z, 0.1);
    EXPECT_EQ(cases[1].tmax, 3.0);
    EXPECT_EQ(cases[1].source, at("c.CSV", 5));
}

TEST_F(CorpusFiles, CsvErrorsNameFileLineAndColumn) {
    std::string message = read_error("m.csv", "\nid,ox,oy,oz,dx,dy,cx,cy,cz,r\n");
    EXPECT_EQ(message,
              at("m.csv", 2) + ": field 'dz': required column is missing from the CSV header");
    const std::string header = "id,ox,oy,oz,dx,dy,dz,cx,cy,cz,r\n";
    message = read_error("w.csv", header + "a,0,0,-5,0,0,1,0,0,0\n");
    EXPECT_EQ(message,
              at("w.csv", 2) + ": found 10 fields, expected 11 as in the header on line 1");
    message = read_error("b.csv", header + "a,0,0,-5,0,abc,1,0,0,0,1\n");
    EXPECT_EQ(message, at("b.csv", 2) + ": field 'dy': expected a number, got 'abc'");
    message = read_error("e.csv", header + ",0,0,-5,0,0,1,0,0,0,1\n");
    EXPECT_NE(message.find(at("e.csv", 2) + ": field 'id'"), std::string::npos) << message;
    message = read_error("t.csv", "id,ox,oy,oz,dx,dy,dz,cx,cy,cz,r,DX\n");
    EXPECT_EQ(message, at("t.csv", 1) + ": field 'dx': column appears twice in the header");
}

// RFC 4180 quoting on one line: commas and "" inside quotes; anything else about quotes is an error.
TEST_F(CorpusFiles, CsvQuotedCellsMayHoldCommasAndQuotes) {
    const std::string header = "id,ox,oy,oz,dx,dy,dz,cx,cy,cz,r,family\n";
    const auto cases = read_corpus_file(
        write("q.csv", header + "\"a,b\",0,0,-5,0,0,1,0,0,0,1, \"say\"\"hi\"\"\" \n\"c\",0,0,-5,0,0,1,0,0,0,2,\"\"\n"));
    ASSERT_EQ(cases.size(), 2u);
    EXPECT_EQ(cases[0].id, "a,b");
    EXPECT_EQ(cases[0].family, "say\"hi\"");
    EXPECT_EQ(cases[0].geometry.radius, 1);
    EXPECT_EQ(cases[1].id, "c");
    EXPECT_EQ(cases[1].family, "");
    EXPECT_EQ(read_error("open.csv", header + "\"a,0,0,-5,0,0,1,0,0,0,1,f\n"),
              at("open.csv", 2) + ": cell 1 opens a double quote that the line never closes");
    EXPECT_EQ(read_error("after.csv", header + "\"a\"b,0,0,-5,0,0,1,0,0,0,1,f\n"),
              at("after.csv", 2) + ": cell 1 has text after its closing double quote");
    EXPECT_EQ(read_error("stray.csv", header + "a,0,0,-5,0,0,1,0,0,0,1,f\"\n"),
              at("stray.csv", 2) + ": cell 12 holds a double quote without being quoted (write \"\" inside a "
                                   "quoted cell)");
}

TEST_F(CorpusFiles, CarriageReturnsOnlyEndALineBeforeANewline) {
    const auto crlf = read_corpus_file(write("dos.txt", "a - " + unit_case + "\r\nb - " + unit_case + "\r\n"));
    EXPECT_EQ(crlf.size(), 2u);
    EXPECT_EQ(read_error("mac.txt", "a - " + unit_case + "\rb - " + unit_case + "\r"),
              at("mac.txt", 1) + ": line contains a carriage return not followed by a newline (CR-only line endings, "
                                 "as old Mac files have?): save the file with \\n or \\r\\n line endings");
}

// A directory's *.txt that is a dangling link or a FIFO is an error, never silently skipped.
TEST_F(CorpusFiles, DirectoryEntriesNamedLikeCorpusFilesMustBeFiles) {
    write("a.txt", "a - " + unit_case + "\n");
    fs::create_symlink("missing.txt", dir_ / "b.txt");
    EXPECT_EQ(error_of([&] { read_corpus({dir_}); }), (dir_ / "b.txt").string() + ": is a symbolic link to a missing file");
    fs::remove(dir_ / "b.txt");
    ASSERT_EQ(mkfifo((dir_ / "c.csv").c_str(), 0600), 0);
    EXPECT_EQ(error_of([&] { read_corpus({dir_}); }),
              (dir_ / "c.csv").string() + ": is not a regular file (a pipe, socket or device named like a corpus file)");
}

// The duplicate-id check across files holds at most 21.4 bytes per case, and
// still names the first definition exactly.
TEST_F(CorpusFiles, DuplicateIdsAcrossFilesAreFoundInBoundedMemory) {
    std::size_t total = 0;
    for (int f = 0; f < 4; ++f) {
        std::string text;
        for (int i = 0; i < 5000; ++i) text += fmt::format("file{}-case{} - {}\n", f, i, unit_case);
        write(fmt::format("part{}.txt", f), text);
        total += 5000;
    }
    case_stream stream({dir_}, {});
    std::vector<corpus_case> cases;
    std::vector<std::size_t> indices;
    while (stream.next(cases, indices)) cases.clear();
    EXPECT_EQ(stream.total(), total);
    EXPECT_LE(static_cast<double>(stream.id_check_bytes()), 21.4 * static_cast<double>(total));

    write("part4.txt", "again - " + unit_case + "\nfile2-case17 - " + unit_case + "\n");
    case_stream again({dir_}, {});
    EXPECT_EQ(error_of([&] {
                  while (again.next(cases, indices)) cases.clear();
              }),
              at("part4.txt", 2) + ": field 'id': duplicate id 'file2-case17', first defined at " + at("part2.txt", 18));
}

TEST_F(CorpusFiles, DuplicateIdsNameBothLocations) {
    std::string message =
        read_error("one.txt", "a f " + unit_case + "\n# x\na g " + unit_case + "\n");
    EXPECT_EQ(message, at("one.txt", 3) + ": field 'id': duplicate id 'a', first defined at " +
                           at("one.txt", 1));
    const fs::path first = write("first.txt", "x f " + unit_case + "\n");
    const fs::path second = write("second.csv",
                                  "id,ox,oy,oz,dx,dy,dz,cx,cy,cz,r\ny,0,0,-5,0,0,1,0,0,0,1\n"
                                  "x,0,0,-5,0,0,1,0,0,0,1\n");
    message = error_of([&] { read_corpus({first, second}); });
    EXPECT_EQ(message, at("second.csv", 3) + ": field 'id': duplicate id 'x', first defined at " +
                           at("first.txt", 1));
}

TEST_F(CorpusFiles, DirectoryContributesTxtAndCsvSortedByName) {
    write("b.txt", "b1 f " + unit_case + "\nb2 f " + unit_case + "\n");
    write("a.csv", "id,ox,oy,oz,dx,dy,dz,cx,cy,cz,r\na1,0,0,-5,0,0,1,0,0,0,1\n");
    write("c.TXT", "c1 f " + unit_case + "\n");
    write("notes.md", "not a corpus\n");
    write("old.txt.tmp", "garbage\n");
    fs::create_directory(dir_ / "sub.txt");
    const fs::path extra = write("extra.dat", "z1 f " + unit_case + "\n");
    std::vector<std::string> ids;
    for (const auto& c : read_corpus({dir_, extra})) ids.push_back(c.id);
    EXPECT_EQ(ids, (std::vector<std::string>{"a1", "b1", "b2", "c1", "z1"}));
}

TEST_F(CorpusFiles, WrittenCorpusReadsBackIdentical) {
    std::vector<corpus_case> cases;
    for (std::size_t i = 0; i < boundary_values.size(); ++i) {
        corpus_case c = sample_case(fmt::format("case-{}", i));
        c.geometry.origin.x = boundary_values[i];
        c.geometry.radius = boundary_values[boundary_values.size() - 1 - i];
        if (i % 3 == 0) c.family = "";
        if (i % 4 == 1) c.tmin = boundary_values[i];
        if (i % 5 == 2) c.tmax = -boundary_values[i];
        cases.push_back(c);
    }
    const fs::path path = dir_ / "out.txt";
    write_corpus_file(path, cases, {"generated by corpus_io_test", "", "two\nlines"});
    EXPECT_FALSE(fs::exists(dir_ / "out.txt.tmp"));

    std::ifstream in(path);
    std::string first_lines[5];
    for (auto& line : first_lines) std::getline(in, line);
    EXPECT_EQ(first_lines[0], corpus_header_comment());
    EXPECT_EQ(first_lines[1], "# generated by corpus_io_test");
    EXPECT_EQ(first_lines[2], "#");
    EXPECT_EQ(first_lines[3], "# two");
    EXPECT_EQ(first_lines[4], "# lines");

    const auto back = read_corpus({path});
    ASSERT_EQ(back.size(), cases.size());
    for (std::size_t i = 0; i < cases.size(); ++i) {
        expect_same_case(back[i], cases[i]);
        EXPECT_EQ(back[i].source, fmt::format("{}:{}", path.string(), i + 6));
    }
}

TEST_F(CorpusFiles, AtomicWriteLeavesNothingBehindOnError) {
    const fs::path nowhere = dir_ / "no-such-dir" / "out.txt";
    const std::string message =
        error_of([&] { write_corpus_file(nowhere, {sample_case("a")}, {}); });
    EXPECT_EQ(message, nowhere.string() + ": cannot write into directory '" + (dir_ / "no-such-dir").string() +
                           "': No such file or directory");
    EXPECT_FALSE(fs::exists(nowhere));
    EXPECT_FALSE(fs::exists(dir_ / "no-such-dir"));

    fs::create_directory(dir_ / "taken");
    EXPECT_EQ(error_of([&] { write_file_atomically(dir_ / "taken", "x"); }),
              (dir_ / "taken").string() + ": is a directory, expected a file to write");

    const fs::path path = write("report.md", "old contents");
    write_file_atomically(path, "new contents\n");
    std::ifstream in(path);
    std::string line;
    std::getline(in, line);
    EXPECT_EQ(line, "new contents");
    std::vector<std::string> names;  // no temporary left beside it
    for (const auto& entry : fs::directory_iterator(dir_)) names.push_back(entry.path().filename().string());
    std::sort(names.begin(), names.end());
    EXPECT_EQ(names, (std::vector<std::string>{"report.md", "taken"}));

    const auto twice = [&] { write_corpus_file(path, {sample_case("a"), sample_case("a")}, {}); };
    EXPECT_EQ(error_of(twice),
              path.string() + ": field 'id': duplicate id 'a' in the cases to write");
}
