#include "corpus/corpus_io.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <optional>
#include <stdexcept>
#include <system_error>
#include <unordered_map>
#include <utility>

#include "core/target_name.h"
#include "core/text_lines.h"
#include "corpus/manifest.h"

namespace rayverify {

namespace fs = std::filesystem;

namespace {

// Text-corpus field order; the CSV header uses the same names.
constexpr std::array<std::string_view, 14> field_names = {
    "id", "family", "ox", "oy", "oz", "dx", "dy", "dz", "cx", "cy", "cz", "r", "tmin", "tmax"};
constexpr std::size_t id_field = 0, family_field = 1, first_number_field = 2, tmin_field = 12;

// A segment case's end points in place of ox oy oz dx dy dz (text: after the
// keyword `segment`; CSV: these columns instead of those).
constexpr std::array<std::string_view, 6> segment_end_names = {"p0x", "p0y", "p0z", "p1x", "p1y", "p1z"};
constexpr std::string_view segment_keyword = "segment";

// A field's name as a message gives it: a segment's end coordinate in place of o or d.
std::string_view field_name(std::size_t i, bool segment) {
    return segment && i >= first_number_field && i < first_number_field + segment_end_names.size()
               ? segment_end_names[i - first_number_field]
               : field_names[i];
}

// The cells of one case by field index; nullopt when the corpus does not give the field.
using case_cells = std::array<std::optional<std::string_view>, field_names.size()>;

char ascii_lower(char c) { return c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c; }

bool iequals(std::string_view a, std::string_view b) {
    return std::ranges::equal(a, b,
                              [](char x, char y) { return ascii_lower(x) == ascii_lower(y); });
}

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

std::string_view trim(std::string_view s) {
    while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
    while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
    return s;
}

// An id or family must survive a trip through the text format: one token, not a comment.
// One word: no blank, and no control character (an id is echoed to the
// terminal, report.md and corpus lines: an ESC or a BEL would reach them raw).
bool is_plain_token(std::string_view s) {
    return !s.empty() && s.front() != '#' && s.find(byte_order_mark) == std::string_view::npos &&
           std::ranges::none_of(s, [](char c) { return is_space(c) || is_control_byte(static_cast<unsigned char>(c)); });
}

int hex_digit_value(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    c = ascii_lower(c);
    return c >= 'a' && c <= 'f' ? c - 'a' + 10 : -1;
}

// Where the significant digits of a significand such as "12.50" sit: the
// powers of the base of its first and last non-zero digit, and those digits.
// Lets us tell overflow from underflow, and check a hex float is exact,
// without trusting what from_chars left in its output on a range error.
struct digit_span {
    long long high = 0, low = 0;
    int high_digit = 0, low_digit = 0;  // high_digit 0: the significand is zero
};

digit_span span_of(std::string_view significand) {
    digit_span s;
    auto power = static_cast<long long>(std::min(significand.find('.'), significand.size()));
    for (char c : significand) {
        if (c == '.') continue;
        --power;
        const int d = hex_digit_value(c);
        if (d == 0) continue;
        if (s.high_digit == 0) s = {power, power, d, d};
        s.low = power;
        s.low_digit = d;
    }
    return s;
}

// The magnitude of a hex float's body (what follows "0x": hex digits with at
// most one point, 'p' or 'P', an optional sign and at most four decimal
// digits), computed exactly from its digits, when it has that form, at most
// 16 significant hex digits, and a value a double holds exactly: what a
// corpus's own numbers always are (hex_float writes them). Anything else is
// nullopt, and parse_exact_double's general path reads it, with its errors.
// A corpus file's numbers were a sixth of a large audit's time through
// from_chars and the general path's checks.
std::optional<double> exact_hex_magnitude(std::string_view body) {
    std::uint64_t significand = 0;
    int significant_digits = 0, fraction_digits = 0, digits = 0;
    bool point = false;
    std::size_t at = 0;
    for (; at < body.size(); ++at) {
        const char c = body[at];
        if (c == '.') {
            if (point) return std::nullopt;
            point = true;
            continue;
        }
        const int d = hex_digit_value(c);
        if (d < 0) break;
        ++digits;
        if (point) ++fraction_digits;
        if (significant_digits == 0 && d == 0) continue;
        if (++significant_digits > 16) return std::nullopt;
        significand = significand << 4 | static_cast<std::uint64_t>(d);
    }
    if (digits == 0 || at == body.size() || (body[at] != 'p' && body[at] != 'P')) return std::nullopt;
    std::string_view exponent_text = body.substr(at + 1);
    const bool negative_exponent = exponent_text.starts_with('-');
    if (exponent_text.starts_with('-') || exponent_text.starts_with('+')) exponent_text.remove_prefix(1);
    if (exponent_text.empty() || exponent_text.size() > 4) return std::nullopt;
    int exponent = 0;
    for (const char c : exponent_text) {
        if (c < '0' || c > '9') return std::nullopt;
        exponent = exponent * 10 + (c - '0');
    }
    if (significand == 0) return 0.0;
    // significand · 2^power, the significand's trailing zero bits moved into the power.
    const int trailing = std::countr_zero(significand);
    const std::uint64_t odd = significand >> trailing;
    const int power = (negative_exponent ? -exponent : exponent) - 4 * fraction_digits + trailing;
    const int width = std::bit_width(odd);
    if (width > 53 || width - 1 + power > 1023 || power < -1074) return std::nullopt;
    return std::ldexp(static_cast<double>(odd), power);  // exact: odd < 2^53, the result a double
}

// An exponent such as "+12" or "-3", saturated far outside any double's range.
long long exponent_of(std::string_view text) {
    const bool negative = !text.empty() && text.front() == '-';
    if (!text.empty() && (text.front() == '-' || text.front() == '+')) text.remove_prefix(1);
    long long e = 0;
    for (char c : text) e = std::min(e * 10 + (c - '0'), 1'000'000'000'000LL);
    return negative ? -e : e;
}

// `segment`: the cells of ox..dz hold p0x..p1z (segment_end_names).
corpus_case make_case(const case_cells& cells, const std::string& file, std::size_t line, bool segment = false) {
    const auto field = [segment](std::size_t i) { return std::string(field_name(i, segment)); };
    corpus_case c;
    c.id = std::string(cells[id_field].value_or(""));
    if (!is_plain_token(c.id))
        throw input_error(file, line, "id",
                          fmt::format("expected a token without spaces or control characters, got '{}'", c.id));
    if (cells[family_field] && *cells[family_field] != "-")
        c.family = std::string(*cells[family_field]);
    if (!c.family.empty() && !is_plain_token(c.family))
        throw input_error(file, line, "family",
                          fmt::format("expected a token without spaces or control characters, got '{}'", c.family));

    std::array<double, 10> v{};
    for (std::size_t i = 0; i < v.size(); ++i)
        v[i] = parse_exact_double(*cells[first_number_field + i], file, line,
                                  field(first_number_field + i));
    c.geometry = {{v[0], v[1], v[2]}, {v[3], v[4], v[5]}, {v[6], v[7], v[8]}, v[9]};
    if (segment) {
        make_segment(c, {v[0], v[1], v[2]}, {v[3], v[4], v[5]});
        c.source = fmt::format("{}:{}", file, line);
        return c;
    }

    const auto bound = [&](std::size_t i) -> std::optional<double> {
        if (!cells[i] || cells[i]->empty() || *cells[i] == "-") return std::nullopt;
        return parse_exact_double(*cells[i], file, line, field(i));
    };
    c.tmin = bound(tmin_field);
    c.tmax = bound(tmin_field + 1);
    c.source = fmt::format("{}:{}", file, line);
    return c;
}

std::vector<corpus_case> parse_text(const std::string& file, std::string_view contents) {
    std::vector<corpus_case> cases;
    std::vector<std::string_view> tokens;
    for_each_text_line(file, contents, [&](std::size_t number, std::string_view line) {
        tokens.clear();
        for (line = trim(line); !line.empty() && line.front() != '#'; line = trim(line)) {
            const auto end = std::ranges::find_if(line, is_space) - line.begin();
            tokens.push_back(line.substr(0, end));
            line.remove_prefix(end);
        }
        if (tokens.empty()) return;
        if (tokens.size() > 2 && tokens[2] == segment_keyword) {
            // id family segment p0x p0y p0z p1x p1y p1z cx cy cz r
            if (tokens.size() != 13)
                throw input_error(
                    file, number, "",
                    fmt::format("found {} fields in a segment line, expected 13 (id family segment p0x p0y p0z "
                                "p1x p1y p1z cx cy cz r; a segment's range is its fractions [0, 1], no tmin tmax)",
                                tokens.size()));
            case_cells cells;
            cells[id_field] = tokens[0];
            cells[family_field] = tokens[1];
            std::copy(tokens.begin() + 3, tokens.end(), cells.begin() + first_number_field);
            cases.push_back(make_case(cells, file, number, true));
            return;
        }
        if (tokens.size() != 12 && tokens.size() != 14)
            throw input_error(
                file, number, "",
                fmt::format("found {} fields, expected 12 (id family ox oy oz dx dy dz cx cy "
                            "cz r) or 14 (the same and tmin tmax); {}",
                            tokens.size(),
                            tokens.size() < field_names.size()
                                ? fmt::format("field '{}' is missing", field_names[tokens.size()])
                                : fmt::format("'{}' comes after tmax", tokens[field_names.size()])));
        case_cells cells;
        std::ranges::copy(tokens, cells.begin());
        cases.push_back(make_case(cells, file, number));
    });
    return cases;
}

// The cells of a CSV row (RFC 4180 quoting on one line): a cell in double
// quotes may hold commas, and "" stands for a quote; blanks around a cell are
// trimmed.
std::vector<std::string> csv_row_cells(std::string_view line, const std::string& file, std::size_t number) {
    std::vector<std::string> cells;
    for (std::size_t at = 0;;) {
        while (at < line.size() && is_space(line[at])) ++at;
        std::string cell;
        std::size_t end = 0;  // the comma after the cell, or line.size()
        if (at < line.size() && line[at] == '"') {
            std::size_t i = at + 1;
            for (;; ++i) {
                if (i >= line.size())
                    throw input_error(file, number, "",
                                      fmt::format("cell {} opens a double quote that the line never closes",
                                                  cells.size() + 1));
                if (line[i] != '"') {
                    cell += line[i];
                } else if (i + 1 < line.size() && line[i + 1] == '"') {
                    cell += '"';
                    ++i;
                } else {
                    break;
                }
            }
            end = std::min(line.find(',', i + 1), line.size());
            if (!trim(line.substr(i + 1, end - i - 1)).empty())
                throw input_error(file, number, "",
                                  fmt::format("cell {} has text after its closing double quote", cells.size() + 1));
        } else {
            end = std::min(line.find(',', at), line.size());
            const std::string_view plain = trim(line.substr(at, end - at));
            if (plain.find('"') != std::string_view::npos)
                throw input_error(file, number, "",
                                  fmt::format("cell {} holds a double quote without being quoted (write \"\" "
                                              "inside a quoted cell)",
                                              cells.size() + 1));
            cell = plain;
        }
        cells.push_back(std::move(cell));
        if (end == line.size()) return cells;
        at = end + 1;
    }
}

std::vector<corpus_case> parse_csv(const std::string& file, std::string_view contents) {
    std::vector<corpus_case> cases;
    // For each field, the index of its cell in a row, when the header names it.
    std::array<std::optional<std::size_t>, field_names.size()> column;
    std::size_t header_line = 0, width = 0;
    bool segments = false;  // the header names p0x..p1z: every row is a segment
    for_each_text_line(file, contents, [&](std::size_t number, std::string_view line) {
        if (trim(line).empty() || trim(line).front() == '#') return;
        const std::vector<std::string> cells = csv_row_cells(line, file, number);
        if (header_line == 0) {
            header_line = number;
            width = cells.size();
            // A segment file names p0x..p1z where a ray file names ox..dz; one form a file.
            const auto names = [&](std::string_view name) {
                return std::ranges::any_of(cells, [&](const std::string& cell) { return iequals(cell, name); });
            };
            segments = std::ranges::any_of(segment_end_names, names);
            if (segments) {
                for (std::size_t f = first_number_field; f < first_number_field + segment_end_names.size(); ++f)
                    if (names(field_names[f]))
                        throw input_error(file, number, std::string(field_names[f]),
                                          "a CSV file holds one form of case: its header names a segment's end "
                                          "points (p0x..p1z) and a ray's column too (write the rays and the "
                                          "segments to two files, or use the text format, whose lines may mix)");
                for (std::size_t f = tmin_field; f < field_names.size(); ++f)
                    if (names(field_names[f]))
                        throw input_error(file, number, std::string(field_names[f]),
                                          "a segment's range is its fractions [0, 1]: a segment file has no tmin or "
                                          "tmax column");
            }
            for (std::size_t i = 0; i < cells.size(); ++i) {
                std::size_t f = 0;
                while (f < field_names.size() && !iequals(field_name(f, segments), cells[i])) ++f;
                if (f == field_names.size()) continue;
                auto& slot = column[f];
                if (slot)
                    throw input_error(file, number, std::string(field_name(f, segments)),
                                      "column appears twice in the header");
                slot = i;
            }
            for (std::size_t f = 0; f < field_names.size(); ++f)
                if (!column[f] && f != family_field && f < tmin_field)
                    throw input_error(file, number, std::string(field_name(f, segments)),
                                      "required column is missing from the CSV header");
            return;
        }
        if (cells.size() != width)
            throw input_error(
                file, number, "",
                fmt::format("found {} fields, expected {} as in the header on line {}",
                            cells.size(), width, header_line));
        case_cells row;
        for (std::size_t f = 0; f < field_names.size(); ++f)
            if (column[f]) row[f] = cells[*column[f]];
        cases.push_back(make_case(row, file, number, segments));
    });
    return cases;
}

// corpus_case::source is "file:line"; the file part may itself contain ':'.
std::pair<std::string, std::size_t> split_source(const std::string& source) {
    const std::size_t colon = source.rfind(':');
    std::size_t line = 0;
    if (colon == std::string::npos ||
        std::from_chars(source.data() + colon + 1, source.data() + source.size(), line).ec !=
            std::errc{})
        return {source, 0};
    return {source.substr(0, colon), line};
}

// The first case whose id an earlier case already has, with that earlier case.
std::optional<std::pair<const corpus_case*, const corpus_case*>> find_duplicate_id(
    const std::vector<corpus_case>& cases) {
    std::unordered_map<std::string_view, const corpus_case*> first;
    for (const auto& c : cases)
        if (const auto [seen, inserted] = first.try_emplace(c.id, &c); !inserted)
            return std::pair{seen->second, &c};
    return std::nullopt;
}

void check_unique_ids(const std::vector<corpus_case>& cases) {
    const auto duplicate = find_duplicate_id(cases);
    if (!duplicate) return;
    const auto& [first, second] = *duplicate;
    auto [file, line] = split_source(second->source);
    throw input_error(
        std::move(file), line, "id",
        fmt::format("duplicate id '{}', first defined at {}", second->id, first->source));
}

}  // namespace

namespace {

bool is_corpus_file_name(const fs::path& file) {
    const std::string ext = file.extension().string();
    return iequals(ext, ".txt") || iequals(ext, ".csv");
}

// How many files named like corpus files lie anywhere under `dir`.
std::size_t corpus_files_below(const fs::path& dir) {
    std::size_t count = 0;
    std::error_code ec;
    for (fs::recursive_directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
        if (is_corpus_file_name(it->path()) && !it->is_directory(ec)) ++count;
    return count;
}

// The subdirectories of `dir` whose files its MANIFEST lists: corpora of
// their own by the manifest's say (corpus/edge beside the shipped corpus).
std::vector<std::string> manifest_subdirectories(const fs::path& dir) {
    std::vector<std::string> names;
    std::error_code ec;
    if (!fs::is_regular_file(dir / "MANIFEST", ec)) return names;
    for (const manifest_entry& entry : read_manifest(dir / "MANIFEST"))
        if (const std::size_t slash = entry.file.find('/'); slash != std::string::npos)
            names.push_back(entry.file.substr(0, slash));
    return names;
}

}  // namespace

corpus_argument list_corpus_argument(const fs::path& path) {
    corpus_argument argument{path, {}, {}};
    std::error_code ec;
    if (!fs::is_directory(path, ec)) {
        argument.files.push_back(path);
        return argument;
    }
    const std::vector<std::string> separate = manifest_subdirectories(path);
    for (fs::directory_iterator it(path, ec), end; !ec && it != end; it.increment(ec)) {
        std::error_code status_error;
        const fs::file_status status = fs::status(it->path(), status_error);
        if (fs::is_directory(status)) {
            // Never skipped in silence: a corpus of its own by the MANIFEST's
            // say, or refused while it holds corpus files.
            const std::string name = it->path().filename().string();
            const std::size_t held = corpus_files_below(it->path());
            if (held == 0) continue;
            if (std::ranges::find(separate, name) != separate.end()) {
                argument.separate_subdirectories.push_back(it->path());
                continue;
            }
            throw input_error(
                it->path().string(), 0, "",
                fmt::format("a subdirectory of {} holding {} corpus file{}, which --corpus {} does not read "
                            "(it reads a directory's own *.txt and *.csv files): name it with a --corpus of "
                            "its own (--corpus {}), or move its files",
                            path.string(), held, held == 1 ? "" : "s", path.string(), it->path().string()));
        }
        if (!is_corpus_file_name(it->path())) continue;
        // Named like a corpus file but not one: an error, never silently skipped.
        if (status.type() == fs::file_type::not_found && fs::is_symlink(it->symlink_status(status_error)))
            throw input_error(it->path().string(), 0, "", "is a symbolic link to a missing file");
        if (!fs::is_regular_file(status))
            throw input_error(it->path().string(), 0, "",
                              "is not a regular file (a pipe, socket or device named like a corpus file)");
        argument.files.push_back(it->path());
    }
    if (ec)
        throw input_error(path.string(), 0, "",
                          fmt::format("cannot list directory: {}", ec.message()));
    std::ranges::sort(argument.files);
    std::ranges::sort(argument.separate_subdirectories);
    return argument;
}

std::vector<fs::path> corpus_files(const fs::path& path) { return list_corpus_argument(path).files; }

std::string corpus_reading::text() const {
    std::string out;
    for (const argument_tally& a : arguments) {
        out += fmt::format("{}{}: {} file{}, {} case{}", out.empty() ? "" : "; ", escaped_control(a.argument.path.string()),
                           a.argument.files.size(), a.argument.files.size() == 1 ? "" : "s", a.cases,
                           a.cases == 1 ? "" : "s");
        for (const fs::path& sub : a.argument.separate_subdirectories)
            out += fmt::format(" ({}/ not read: a corpus of its own in {})", escaped_control(sub.filename().string()),
                               escaped_control((a.argument.path / "MANIFEST").string()));
    }
    return out;
}

double parse_exact_double(std::string_view token, const std::string& file, std::size_t line,
                          const std::string& field) {
    const auto fail = [&](std::string_view problem) {
        throw input_error(file, line, field, fmt::format("{}, got '{}'", problem, token));
    };
    // from_chars rejects a leading '+', so the sign is ours to handle.
    std::string_view body = token;
    const bool negative = body.starts_with('-');
    if (body.starts_with('-') || body.starts_with('+')) body.remove_prefix(1);
    const double sign = negative ? -1.0 : 1.0;
    if (iequals(body, "nan")) return std::copysign(std::numeric_limits<double>::quiet_NaN(), sign);
    if (iequals(body, "inf") || iequals(body, "infinity"))
        return sign * std::numeric_limits<double>::infinity();

    const bool hex = body.size() >= 2 && body[0] == '0' && ascii_lower(body[1]) == 'x';
    if (hex) {
        body.remove_prefix(2);
        if (const std::optional<double> magnitude = exact_hex_magnitude(body)) return negative ? -*magnitude : *magnitude;
    }
    // from_chars would also take "inf", "nan(...)" or a second sign here.
    const char first = body.empty() ? '\0' : body.front();
    const bool starts_as_number =
        first == '.' || (hex ? hex_digit_value(first) >= 0 : first >= '0' && first <= '9');
    double value = 0;
    const char* last = body.data() + body.size();
    const auto [end, ec] = std::from_chars(
        body.data(), last, value, hex ? std::chars_format::hex : std::chars_format::general);
    if (!starts_as_number || ec == std::errc::invalid_argument || end != last)
        fail("expected a number");

    const std::size_t e = body.find_first_of(hex ? "pP" : "eE");
    if (e != std::string_view::npos) {
        // from_chars takes "0x1p+-5" as 0x1p-5: an exponent is one optional sign and digits.
        std::string_view digits = body.substr(e + 1);
        if (digits.starts_with('+') || digits.starts_with('-')) digits.remove_prefix(1);
        if (digits.empty() || !std::ranges::all_of(digits, [](char c) { return c >= '0' && c <= '9'; }))
            fail("expected a number");
    }
    const digit_span s = span_of(body.substr(0, e));
    const long long exponent = e == std::string_view::npos ? 0 : exponent_of(body.substr(e + 1));
    if (hex && s.high_digit != 0) {
        // Bit positions of the leading and trailing one bits: a double holds 53
        // consecutive bits between 2^1023 and 2^-1074; from_chars would round the rest.
        const long long high =
            4 * s.high + std::bit_width(static_cast<unsigned>(s.high_digit)) - 1 + exponent;
        const long long low =
            4 * s.low + std::countr_zero(static_cast<unsigned>(s.low_digit)) + exponent;
        if (high > 1023) fail("out of double range");
        if (low < -1074 || high - low > 52)
            fail("not exactly representable as a double (more than 53 bits, or below 0x1p-1074)");
    }
    if (ec == std::errc::result_out_of_range) {
        if (hex || s.high + exponent >= 0) fail("out of double range");
        fail("not exactly representable as a double (underflows to zero)");
    }
    return negative ? -value : value;
}

namespace {

// x's eight hex digits, most significant first, lower case, stored at `at`
// (eight bytes, no terminating zero): the nibbles spread one to a byte and
// turned into ASCII a word at a time.
void store_hex_digits(char* at, std::uint32_t x) {
    std::uint64_t v = x;
    v = (v | v << 16) & 0x0000FFFF0000FFFFull;
    v = (v | v << 8) & 0x00FF00FF00FF00FFull;
    v = (v | v << 4) & 0x0F0F0F0F0F0F0F0Full;  // byte k holds nibble k (from the least significant)
    const std::uint64_t letter = ((v + 0x0606060606060606ull) >> 4) & 0x0101010101010101ull;  // nibble ≥ 10
    v += 0x3030303030303030ull + letter * ('a' - '0' - 10);
    // The most significant nibble's byte first in memory (big-endian stores it first already).
    if constexpr (std::endian::native == std::endian::little) v = __builtin_bswap64(v);
    std::memcpy(at, &v, 8);
}

}  // namespace

char* write_hex_float(char* at, double x) {
    if (std::signbit(x)) *at++ = '-';
    const auto put = [&](std::string_view s) {
        for (const char ch : s) *at++ = ch;
    };
    const std::uint64_t bits = std::bit_cast<std::uint64_t>(x);
    const int biased = static_cast<int>((bits >> 52) & 0x7FF);
    std::uint64_t fraction = bits & ((std::uint64_t{1} << 52) - 1);
    if (std::isnan(x)) {
        put("nan");
    } else if (std::isinf(x)) {
        put("inf");
    } else if (biased == 0 && fraction == 0) {
        put("0x0p+0");
    } else {
        // Normal: 0x1.<fraction>p<e>; subnormal: 0x0.<fraction>p-1022 (as C's
        // %a prints them), the fraction's trailing zero digits left out.
        put(biased == 0 ? "0x0" : "0x1");
        if (fraction != 0) {
            *at++ = '.';
            // The 13 nibbles as 16 digits (3 zeros after them, overwritten
            // below), then only up to the last nonzero nibble kept.
            const std::uint64_t nibbles = fraction << 12;
            store_hex_digits(at, static_cast<std::uint32_t>(nibbles >> 32));
            store_hex_digits(at + 8, static_cast<std::uint32_t>(nibbles));
            at += 13 - std::countr_zero(fraction) / 4;
        }
        const int exponent = biased == 0 ? -1022 : biased - 1023;
        put(exponent < 0 ? "p-" : "p+");
        // |exponent| ≤ 1023: its decimal digits without leading zeros.
        const int magnitude = exponent < 0 ? -exponent : exponent;
        if (magnitude >= 1000) *at++ = '1';
        if (magnitude >= 100) *at++ = static_cast<char>('0' + magnitude / 100 % 10);
        if (magnitude >= 10) *at++ = static_cast<char>('0' + magnitude / 10 % 10);
        *at++ = static_cast<char>('0' + magnitude % 10);
    }
    return at;
}

void append_hex_float(std::string& out, double x) {
    char text[hex_float_max_size];
    out.append(text, static_cast<std::size_t>(write_hex_float(text, x) - text));
}

std::string hex_float(double x) {
    std::string text;
    append_hex_float(text, x);
    return text;
}

std::string shortest_decimal(double x) { return fmt::format("{}", x); }

void append_case_line(std::string& line, const corpus_case& c) {
    if (!is_plain_token(c.id))
        throw input_error(c.source, 0, "id",
                          fmt::format("cannot be written as one token: '{}'", c.id));
    if (!c.family.empty() && (!is_plain_token(c.family) || c.family == "-"))
        throw input_error(c.source, 0, "family",
                          fmt::format("cannot be written as one token: '{}'", c.family));
    const auto& g = c.geometry;
    line += c.id;
    line += ' ';
    line += c.family.empty() ? "-" : c.family;
    if (c.segment_end) {
        line += ' ';
        line += segment_keyword;
    }
    // A segment's second point is p1 where a ray's is d; its range is fixed.
    const vec3<double>& second = c.segment_end ? *c.segment_end : g.direction;
    for (double v : {g.origin.x, g.origin.y, g.origin.z, second.x, second.y, second.z, g.centre.x, g.centre.y,
                     g.centre.z, g.radius}) {
        line += ' ';
        append_hex_float(line, v);
    }
    if (!c.segment_end && (c.tmin || c.tmax))
        for (const auto& bound : {c.tmin, c.tmax}) {
            line += ' ';
            if (bound)
                append_hex_float(line, *bound);
            else
                line += '-';
        }
}

std::string format_case_line(const corpus_case& c) {
    std::string line;
    line.reserve(c.id.size() + c.family.size() + 12 * 24);
    append_case_line(line, c);
    return line;
}

std::string segment_header_comment() {
    std::string header = fmt::format("# {} {} {}", field_names[id_field], field_names[family_field], segment_keyword);
    for (std::string_view name : segment_end_names) header += fmt::format(" {}", name);
    for (std::size_t i = first_number_field + segment_end_names.size(); i < tmin_field; ++i)
        header += fmt::format(" {}", field_names[i]);
    return header + "   (a segment: the cast from p0 to p1, fractions [0, 1])";
}

std::string corpus_header_comment() {
    std::string header = "#";
    for (std::size_t i = 0; i < tmin_field; ++i) header += fmt::format(" {}", field_names[i]);
    return header + " [tmin tmax]   (C99 hex floats, exact; '-' = none)";
}

std::vector<corpus_case> read_corpus_file(const fs::path& path) {
    const std::string file = path.string();
    std::error_code ec;
    const fs::file_status status = fs::status(path, ec);
    if (status.type() == fs::file_type::not_found) throw input_error(file, 0, "", "no such file");
    if (ec) throw input_error(file, 0, "", ec.message());
    if (fs::is_directory(status))
        throw input_error(file, 0, "", "is a directory, expected a corpus file");
    if (!fs::is_regular_file(status)) throw input_error(file, 0, "", "is not a regular file");

    // Refused by size before reading; the read is capped too, since some
    // regular files (/proc) report a size of 0 and a file may grow meanwhile.
    const auto too_large = [&](std::uintmax_t size) {
        return input_error(file, 0, "",
                           fmt::format("is {} bytes, over the {} MiB limit for one corpus file; "
                                       "split it into several files",
                                       size, max_corpus_file_bytes >> 20));
    };
    const std::uintmax_t size = fs::file_size(path, ec);
    if (!ec && size > max_corpus_file_bytes) throw too_large(size);

    std::ifstream in(path, std::ios::binary);
    if (!in)
        throw input_error(file, 0, "",
                          fmt::format("cannot open: {}", std::generic_category().message(errno)));
    std::string contents;
    if (!ec) contents.reserve(static_cast<std::size_t>(size));
    std::array<char, 1 << 16> chunk{};
    while (in.read(chunk.data(), chunk.size()) || in.gcount() > 0) {
        const auto n = static_cast<std::size_t>(in.gcount());
        if (contents.size() + n > max_corpus_file_bytes) throw too_large(contents.size() + n);
        contents.append(chunk.data(), n);
    }
    if (in.bad()) throw input_error(file, 0, "", "cannot read");

    return parse_corpus(file, contents, iequals(path.extension().string(), ".csv"));
}

std::vector<corpus_case> parse_corpus(const std::string& file, std::string_view contents,
                                      bool csv) {
    auto cases = csv ? parse_csv(file, contents) : parse_text(file, contents);
    check_unique_ids(cases);
    return cases;
}

std::vector<corpus_case> read_corpus(const std::vector<fs::path>& paths, corpus_reading* reading) {
    std::vector<corpus_case> cases;
    for (const auto& path : paths) {
        corpus_reading::argument_tally tally{list_corpus_argument(path), 0};
        for (const auto& file : tally.argument.files) {
            auto part = read_corpus_file(file);
            tally.cases += part.size();
            cases.insert(cases.end(), std::make_move_iterator(part.begin()),
                         std::make_move_iterator(part.end()));
        }
        if (reading != nullptr) reading->arguments.push_back(std::move(tally));
    }
    if (cases.empty()) {
        std::string names;
        for (const auto& path : paths) names += (names.empty() ? "" : ", ") + path.string();
        throw input_error(names, 0, "", "empty corpus: no cases found");
    }
    check_unique_ids(cases);
    return cases;
}

void write_corpus_file(const fs::path& path, const std::vector<corpus_case>& cases,
                       const std::vector<std::string>& header_comments) {
    // A corpus we could not read back is refused before anything is written.
    if (const auto duplicate = find_duplicate_id(cases))
        throw input_error(
            path.string(), 0, "id",
            fmt::format("duplicate id '{}' in the cases to write", duplicate->second->id));
    std::string out = corpus_header_comment() + '\n';
    if (std::ranges::any_of(cases, &corpus_case::is_segment)) out += segment_header_comment() + '\n';
    for (const auto& comment : header_comments)
        for (std::string_view rest = comment;;) {  // an embedded newline must not start a case line
            const std::size_t end = std::min(rest.find('\n'), rest.size());
            out += rest.substr(0, end).empty() ? "#\n" : fmt::format("# {}\n", rest.substr(0, end));
            if (end == rest.size()) break;
            rest.remove_prefix(end + 1);
        }
    for (const auto& c : cases) out += format_case_line(c) + '\n';
    write_file_atomically(path, out);
}

std::vector<std::string> split_csv_row(std::string_view line, const std::string& file, std::size_t number) {
    return csv_row_cells(line, file, number);
}

}  // namespace rayverify
