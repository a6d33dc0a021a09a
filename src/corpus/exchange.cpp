#include "corpus/exchange.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <sys/stat.h>

#include "core/hash.h"
#include "core/input_error.h"
#include "core/name_table.h"
#include "core/text_lines.h"
#include "corpus/case_stream.h"
#include "corpus/corpus_io.h"
#include "corpus/json_input.h"

namespace rayverify {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

// ---- Names ----------------------------------------------------------------------

namespace {
constexpr name_table<exchange_format, 3> exchange_format_names{
    {{exchange_format::csv, "csv"}, {exchange_format::jsonl, "jsonl"}, {exchange_format::npy, "npy"}}};
}  // namespace

std::string_view exchange_format_name(exchange_format f) { return name_in(exchange_format_names, f); }
std::optional<exchange_format> exchange_format_from_name(std::string_view name) {
    return value_in(exchange_format_names, name);
}
std::vector<std::string> every_exchange_format_name() { return names_in(exchange_format_names); }

std::optional<exchange_format> exchange_format_of(const fs::path& path) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    if (ext.empty()) return std::nullopt;
    return exchange_format_from_name(std::string_view(ext).substr(1));
}

fs::path sidecar_of(const fs::path& npy) {
    fs::path json_path = npy;
    return json_path.replace_extension(".json");
}

std::string exchange_fingerprint(std::string_view input_fingerprint, precision p) {
    fnv1a_digest digest;
    for (std::string_view part : {std::string_view("rayverify-exchange-v1;"), input_fingerprint,
                                  std::string_view(";"), std::string_view(precision_name(p))})
        digest.add(part);
    return digest.text();
}

namespace {

constexpr std::array<std::string_view, 14> case_column_names = {
    "id", "family", "ox", "oy", "oz", "dx", "dy", "dz", "cx", "cy", "cz", "r", "tmin", "tmax"};
constexpr std::size_t first_number_column = 2;  // ox
constexpr std::size_t npy_case_columns = 12;    // ox … r, tmin, tmax
// A segment's end as given, after those columns when the file holds a segment (cases_header::segments).
constexpr std::array<std::string_view, 3> segment_end_columns = {"p1x", "p1y", "p1z"};

// The answer columns, one table for every results format: the count and the
// two t's, then the optional groups (each all or none). A CSV and an .npy
// name each column; JSON lines give a group as arrays (`json_keys`, each of
// size / json_keys.size() numbers). t0 and t1 may be left out: an any_hit
// answer needs neither, a nearest_hit answer no t1 (check_recorded_values
// says which values a contract needs).
constexpr std::array<std::string_view, 3> answer_t_columns = {"count", "t0", "t1"};
constexpr std::string_view required_answer_column = "count";

enum class answer_group { t_bounds, hit_point, normal };

struct answer_group_columns {
    answer_group group;
    std::array<std::string_view, 4> columns;  // the first `size`
    std::size_t size;
    std::array<std::string_view, 2> json_keys;  // the first json_arrays
    std::size_t json_arrays;
};

constexpr std::array<answer_group_columns, 3> answer_groups = {{
    {answer_group::t_bounds, {"t0_lo", "t0_hi", "t1_lo", "t1_hi"}, 4, {"t0_bounds", "t1_bounds"}, 2},
    {answer_group::hit_point, {"px", "py", "pz", ""}, 3, {"hit_point", ""}, 1},
    {answer_group::normal, {"nx", "ny", "nz", ""}, 3, {"normal", ""}, 1},
}};

// The keys of an answer's JSON line: id, the t columns, each group's arrays.
std::vector<std::string> answer_json_keys() {
    std::vector<std::string> keys{"id"};
    keys.insert(keys.end(), answer_t_columns.begin(), answer_t_columns.end());
    for (const answer_group_columns& g : answer_groups)
        for (std::size_t k = 0; k < g.json_arrays; ++k) keys.emplace_back(g.json_keys[k]);
    return keys;
}

}  // namespace


std::vector<std::string> answer_columns() {
    std::vector<std::string> names(answer_t_columns.begin(), answer_t_columns.end());
    for (const answer_group_columns& g : answer_groups)
        names.insert(names.end(), g.columns.begin(), g.columns.begin() + static_cast<std::ptrdiff_t>(g.size));
    return names;
}

// ---- Numbers ----------------------------------------------------------------------

namespace {

// The shortest decimal that reads back as x in its precision (a float's own
// shortest form, e.g. "0.1" for 0.1f), or a C99 hex float; nan, inf, -inf.
std::string number_text(double x, precision p, number_style style) {
    if (std::isnan(x)) return "nan";
    if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
    if (style == number_style::hex) return hex_float(x);
    if (p == precision::binary64) return shortest_decimal(x);
    char buffer[64];
    const auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, static_cast<float>(x));
    return std::string(buffer, end);
}

json number_json(double x, precision p, number_style style) {
    if (!std::isfinite(x) || style == number_style::hex) return number_text(x, p, style);
    // "-0" would read back as the integer 0: a negative zero is written -0.0.
    if (x == 0 && std::signbit(x)) return json(-0.0);
    // The decimal as text, parsed back: nlohmann then writes the double's shortest form,
    // which for a float value is its float shortest form read as a double.
    return json::parse(number_text(x, p, style));
}

double in_precision(double x, precision p) {
    return p == precision::binary64 ? x : static_cast<double>(static_cast<float>(x));
}

// The float a value of a float results file stands for: the value itself
// when it is a float; else, when it is the double nearest to a decimal of at
// most 9 significant digits (as "%.9g", repr(np.float32) and shortest-form
// writers print floats), the float nearest to that decimal; else none: a
// double answer in a float file.
std::optional<float> float_value(double x) {
    const float f = static_cast<float>(x);
    if (!std::isfinite(x) || static_cast<double>(f) == x) return f;
    char buffer[64];
    const int n = std::snprintf(buffer, sizeof buffer, "%.9g", x);
    double back = 0;
    std::from_chars(buffer, buffer + n, back);
    if (back != x) return std::nullopt;
    float nearest = 0;
    const auto [end, ec] = std::from_chars(buffer, buffer + n, nearest);
    if (ec != std::errc() || !std::isfinite(nearest)) return std::nullopt;
    return nearest;
}

// ---- npy ----------------------------------------------------------------------------

void write_npy_header(std::ostream& out, precision p, std::size_t rows, std::size_t columns) {
    std::string dict = fmt::format("{{'descr': '{}', 'fortran_order': False, 'shape': ({}, {}), }}",
                                   with_precision(p, []<class T>(std::type_identity<T>) { return sizeof(T) == 4 ? "<f4" : "<f8"; }),
                                   rows, columns);
    // Magic (6), version (2), length (2), then the dict padded with spaces
    // and a newline to a multiple of 64 bytes, as NumPy writes it.
    const std::size_t unpadded = 10 + dict.size() + 1;
    dict.append((64 - unpadded % 64) % 64, ' ');
    dict += '\n';
    const auto length = static_cast<std::uint16_t>(dict.size());
    out.write("\x93NUMPY\x01\x00", 8);
    const char bytes[2] = {static_cast<char>(length & 0xff), static_cast<char>(length >> 8)};
    out.write(bytes, 2);
    out << dict;
}

template <class T>
void write_little_endian(std::ostream& out, T value) {
    static_assert(std::endian::native == std::endian::little, "npy output assumes a little-endian host");
    out.write(reinterpret_cast<const char*>(&value), sizeof value);
}

struct npy_array {
    precision prec = precision::binary64;
    std::size_t rows = 0, columns = 0;
    std::string_view data;
    double at(std::size_t row, std::size_t column) const {
        const std::size_t i = row * columns + column;
        if (prec == precision::binary32) {
            float f;
            std::memcpy(&f, data.data() + i * sizeof f, sizeof f);
            return f;
        }
        double d;
        std::memcpy(&d, data.data() + i * sizeof d, sizeof d);
        return d;
    }
};

// The value of `key` in an npy header dict, e.g. "'<f4'" or "(3, 12)".
std::optional<std::string_view> dict_value(std::string_view dict, std::string_view key) {
    const std::string quoted = fmt::format("'{}'", key);
    std::size_t at = dict.find(quoted);
    if (at == std::string_view::npos) return std::nullopt;
    at = dict.find(':', at + quoted.size());
    if (at == std::string_view::npos) return std::nullopt;
    std::string_view rest = dict.substr(at + 1);
    while (!rest.empty() && rest.front() == ' ') rest.remove_prefix(1);
    const std::size_t end = rest.starts_with('(') ? rest.find(')') + 1 : rest.find_first_of(",}");
    if (end == 0 || end == std::string_view::npos + 1 || end > rest.size()) return std::nullopt;
    return rest.substr(0, end);
}

npy_array parse_npy(const std::string& file, std::string_view bytes) {
    const auto fail = [&](const std::string& problem) { return input_error(file, 0, "npy", problem); };
    if (bytes.size() < 10 || bytes.substr(0, 6) != "\x93NUMPY")
        throw fail("not a NumPy .npy file (no \\x93NUMPY magic)");
    const auto major = static_cast<unsigned char>(bytes[6]);
    std::size_t length = 0, start = 0;
    if (major == 1) {
        length = static_cast<unsigned char>(bytes[8]) | static_cast<std::size_t>(static_cast<unsigned char>(bytes[9])) << 8;
        start = 10;
    } else if (major == 2 || major == 3) {
        if (bytes.size() < 12) throw fail("truncated header");
        for (int i = 3; i >= 0; --i) length = length << 8 | static_cast<unsigned char>(bytes[8 + i]);
        start = 12;
    } else {
        throw fail(fmt::format("npy format version {} (expected 1, 2 or 3)", major));
    }
    if (bytes.size() < start + length) throw fail("truncated header");
    const std::string_view dict = bytes.substr(start, length);
    npy_array a;
    const auto descr = dict_value(dict, "descr");
    if (descr == "'<f4'")
        a.prec = precision::binary32;
    else if (descr == "'<f8'")
        a.prec = precision::binary64;
    else
        throw fail(fmt::format("dtype {} (expected little-endian float32 '<f4' or float64 '<f8')",
                               descr ? std::string(*descr) : std::string("missing")));
    if (dict_value(dict, "fortran_order") != "False")
        throw fail("Fortran order (expected C order: np.ascontiguousarray)");
    const auto shape = dict_value(dict, "shape");
    if (!shape) throw fail("no shape in the header");
    std::size_t dims[2] = {0, 0};
    int found = 0;
    for (std::string_view s = shape->substr(1, shape->size() - 2); !s.empty();) {
        while (!s.empty() && (s.front() == ' ' || s.front() == ',')) s.remove_prefix(1);
        if (s.empty()) break;
        std::size_t value = 0;
        const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
        if (ec != std::errc() || found == 2) throw fail(fmt::format("shape {} (expected (rows, columns))", *shape));
        dims[found++] = value;
        s.remove_prefix(static_cast<std::size_t>(end - s.data()));
    }
    if (found != 2) throw fail(fmt::format("shape {} (expected a 2-D array (rows, columns))", *shape));
    a.rows = dims[0];
    a.columns = dims[1];
    a.data = bytes.substr(start + length);
    const std::size_t size = with_precision(a.prec, []<class T>(std::type_identity<T>) { return sizeof(T); });
    if (a.columns != 0 && a.rows > a.data.size() / size / a.columns)
        throw fail(fmt::format("holds {} bytes of data, its shape ({}, {}) needs {}", a.data.size(), a.rows,
                               a.columns, a.rows * a.columns * size));
    if (a.data.size() != a.rows * a.columns * size)
        throw fail(fmt::format("{} bytes after the data its shape ({}, {}) needs", a.data.size() - a.rows * a.columns * size,
                               a.rows, a.columns));
    return a;
}

}  // namespace

// ---- Cases out --------------------------------------------------------------------

namespace {

json header_json(const char* kind, precision p, const std::string& fingerprint) {
    return {{"rayverify", kind}, {"version", exchange_version}, {"precision", precision_name(p)}, {"fingerprint", fingerprint}};
}

// A text cell of a cases CSV, quoted as RFC 4180 says when it holds a comma
// (a scene ray's id "px3,7/shadow/...") or a quote (written ""); a line
// break cannot be written.
std::string csv_cell(const std::string& text, const std::string& source, const char* field) {
    if (text.find_first_of("\r\n") != std::string::npos)
        throw input_error(source, 0, field, fmt::format("'{}' cannot be written as one CSV cell", text));
    if (text.find_first_of(",\"") == std::string::npos) return text;
    std::string quoted = "\"";
    for (const char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
    return quoted + "\"";
}

}  // namespace

case_writer::case_writer(std::ostream& out, std::ostream* sidecar, exchange_format format, const cases_header& header)
    : out_(out), sidecar_(sidecar), format_(format), header_(header) {
    const char* numbers = header.numbers == number_style::hex ? "hex" : "decimal";
    switch (format) {
        case exchange_format::csv: {
            out_ << fmt::format("# rayverify cases v{} precision={} fingerprint={} cases={} numbers={}\n",
                                exchange_version, precision_name(header.prec), header.fingerprint, header.cases,
                                numbers);
            std::string row;
            for (std::string_view n : case_column_names) row += (row.empty() ? "" : ",") + std::string(n);
            if (header.segments)
                for (std::string_view n : segment_end_columns) row += "," + std::string(n);
            out_ << row << '\n';
            break;
        }
        case exchange_format::jsonl: {
            json h = header_json("cases", header.prec, header.fingerprint);
            h["cases"] = header.cases;
            h["numbers"] = numbers;
            out_ << h.dump() << '\n';
            break;
        }
        case exchange_format::npy: {
            write_npy_header(out_, header.prec, header.cases,
                             npy_case_columns + (header.segments ? segment_end_columns.size() : 0));
            json h = header_json("cases", header.prec, header.fingerprint);
            h["cases"] = header.cases;
            h["columns"] = json::array();
            for (std::size_t i = first_number_column; i < case_column_names.size(); ++i)
                h["columns"].push_back(case_column_names[i]);
            if (header.segments)
                for (std::string_view n : segment_end_columns) h["columns"].push_back(n);
            h["absent_bound"] = "nan";
            // The id list is streamed after the header's fields.
            std::string text = h.dump();
            text.pop_back();
            *sidecar_ << text << ",\"ids\":[";
            break;
        }
    }
}

void case_writer::write(const corpus_case& c) {
    const precision p = header_.prec;
    // What a target in p receives: a segment case in its ray form, o = p0 and
    // d = p1 − p0 computed in p, on (0, 1) (the answers are judged on the exact segment).
    const ray_sphere<double> g = target_input(p, c);
    const double values[10] = {g.origin.x, g.origin.y, g.origin.z, g.direction.x, g.direction.y,
                               g.direction.z, g.centre.x, g.centre.y, g.centre.z, g.radius};
    const auto bound = [&](const std::optional<double>& t) -> std::optional<double> {
        if (!t) return std::nullopt;
        return in_precision(*t, p);
    };
    const std::optional<double> bounds[2] = {bound(c.tmin), bound(c.tmax)};
    // A segment's end as given, in the file's precision (zeros for a ray case: unused).
    const vec3<double> end = c.segment_end.value_or(vec3<double>{});
    const std::array<double, 3> ends = {in_precision(end.x, p), in_precision(end.y, p), in_precision(end.z, p)};
    switch (format_) {
        case exchange_format::csv: {
            std::string row = csv_cell(c.id, c.source, "id") + "," + csv_cell(c.family, c.source, "family");
            for (double v : values) row += "," + number_text(in_precision(v, p), p, header_.numbers);
            for (const auto& b : bounds) row += "," + (b ? number_text(*b, p, header_.numbers) : std::string());
            if (header_.segments)
                for (double v : ends) row += "," + (c.segment_end ? number_text(v, p, header_.numbers) : std::string());
            out_ << row << '\n';
            break;
        }
        case exchange_format::jsonl: {
            json line = {{"id", c.id}, {"family", c.family}};
            for (std::size_t i = 0; i < 10; ++i)
                line[std::string(case_column_names[first_number_column + i])] =
                    number_json(in_precision(values[i], p), p, header_.numbers);
            line["tmin"] = bounds[0] ? number_json(*bounds[0], p, header_.numbers) : json(nullptr);
            line["tmax"] = bounds[1] ? number_json(*bounds[1], p, header_.numbers) : json(nullptr);
            if (c.segment_end)  // a segment's end as given, for a program that casts between two points
                for (std::size_t i = 0; i < ends.size(); ++i)
                    line[std::string(segment_end_columns[i])] = number_json(ends[i], p, header_.numbers);
            out_ << line.dump() << '\n';
            break;
        }
        case exchange_format::npy: {
            const double nan = std::numeric_limits<double>::quiet_NaN();
            const std::size_t columns = npy_case_columns + (header_.segments ? segment_end_columns.size() : 0);
            for (std::size_t i = 0; i < columns; ++i) {
                const double v = i < 10                 ? values[i]
                                 : i < npy_case_columns ? bounds[i - 10].value_or(nan)
                                 : c.segment_end        ? ends[i - npy_case_columns]
                                                        : nan;
                if (p == precision::binary32)
                    write_little_endian(out_, static_cast<float>(v));
                else
                    write_little_endian(out_, v);
            }
            *sidecar_ << (written_ ? "," : "") << json(c.id).dump();
            break;
        }
    }
    ++written_;
}

void case_writer::finish() {
    if (written_ != header_.cases)
        throw std::logic_error(fmt::format("case_writer: {} cases written, the header says {}", written_, header_.cases));
    if (format_ == exchange_format::npy) *sidecar_ << "]}\n";
}

// ---- Answers in -------------------------------------------------------------------

namespace {

// The header of a results file, from its fields.
struct parsed_header {
    precision prec = precision::binary64;
    std::string fingerprint;
};

precision precision_from(const std::string& text, const std::string& file, std::size_t line) {
    if (const std::optional<precision> p = precision_from_name(text)) return *p;
    throw input_error(file, line, "precision", fmt::format("'{}' (expected float or double)", text));
}

std::string fingerprint_from(const std::string& text, const std::string& file, std::size_t line) {
    if (!is_fingerprint_text(text))
        throw input_error(file, line, "fingerprint",
                          fmt::format("'{}' (expected the 16 hex digits of the cases' header)", text));
    return text;
}

// The JSON header object of a JSON-lines file or an npy companion.
parsed_header header_from_json(const json& h, const std::string& file, std::size_t line, const char* kind) {
    const auto field = [&](const char* key) -> std::string {
        if (!h.contains(key) || !h[key].is_string())
            throw input_error(file, line, key, fmt::format("the header needs \"{}\" (a string)", key));
        return h[key].get<std::string>();
    };
    if (!h.is_object() || !h.contains("rayverify"))
        throw input_error(file, line, "rayverify",
                          fmt::format("the first line must be the header {{\"rayverify\": \"{}\", \"version\": 1, "
                                      "\"precision\": ..., \"fingerprint\": ...}}",
                                      kind));
    if (field("rayverify") != kind)
        throw input_error(file, line, "rayverify",
                          fmt::format("'{}' (expected \"{}\"{})", h["rayverify"].get<std::string>(), kind,
                                      std::string(kind) == "results" ? ": a cases file is not an answer file" : ""));
    if (!h.contains("version") || !h["version"].is_number_integer() || h["version"].get<long long>() != exchange_version)
        throw input_error(file, line, "version", fmt::format("schema version {} (this rayverify reads version {})",
                                                             h.contains("version") ? h["version"].dump() : "missing",
                                                             exchange_version));
    return {precision_from(field("precision"), file, line), fingerprint_from(field("fingerprint"), file, line)};
}

// "# rayverify results v1 precision=float fingerprint=…" (CSV).
parsed_header header_from_comment(std::string_view line_text, const std::string& file, std::size_t line) {
    std::vector<std::string> words;
    std::istringstream in{std::string(line_text)};
    for (std::string w; in >> w;) words.push_back(w);
    if (words.size() < 4 || words[0] != "#" || words[1] != "rayverify")
        throw input_error(file, line, "header",
                          "the first line must be '# rayverify results v1 precision=float|double fingerprint=HEX'");
    if (words[2] != "results")
        throw input_error(file, line, "header",
                          fmt::format("'{}' (expected results{})", words[2],
                                      words[2] == "cases" ? ": a cases file is not an answer file" : ""));
    if (words[3] != fmt::format("v{}", exchange_version))
        throw input_error(file, line, "version",
                          fmt::format("schema version '{}' (this rayverify reads v{})", words[3], exchange_version));
    std::optional<std::string> prec, fingerprint;
    for (std::size_t i = 4; i < words.size(); ++i) {
        const std::size_t eq = words[i].find('=');
        const std::string key = words[i].substr(0, eq), value = eq == std::string::npos ? "" : words[i].substr(eq + 1);
        if (key == "precision")
            prec = value;
        else if (key == "fingerprint")
            fingerprint = value;
        else if (key != "cases" && key != "numbers")
            throw input_error(file, line, key, "unknown header field (known: precision, fingerprint, cases, numbers)");
    }
    if (!prec) throw input_error(file, line, "precision", "the header needs precision=float|double");
    if (!fingerprint) throw input_error(file, line, "fingerprint", "the header needs fingerprint=HEX (from the cases' header)");
    return {precision_from(*prec, file, line), fingerprint_from(*fingerprint, file, line)};
}

}  // namespace

void check_results_header(std::string_view text, exchange_format format, const std::string& file, std::size_t line) {
    if (format == exchange_format::csv)
        header_from_comment(text, file, line);
    else
        header_from_json(parse_json_input(text, file, line), file, line, "results");
}

namespace {

// Builds one answer from named values, checking each.
class answer_builder {
public:
    answer_builder(const std::string& file, std::size_t line, precision p) : file_(file), line_(line), prec_(p) {
        answer_.line = line;
    }

    void count(std::optional<double> value) {
        if (!value) throw input_error(file_, line_, "count", "missing (0 miss, 1 or 2 hits)");
        const double c = *value;
        if (!(c == std::floor(c)) || std::fabs(c) > 1e9)
            throw input_error(file_, line_, "count", fmt::format("'{}' is not a whole number", shortest_decimal(c)));
        if (c < 0 || c > 2)
            throw input_error(file_, line_, "count", fmt::format("{} is not 0 (a miss), 1 or 2 (hits)", shortest_decimal(c)));
        answer_.roots.count = static_cast<int>(c);
    }
    // A number of the results' precision; absent is NaN for t0 and t1 (and flagged, see t()).
    double value(std::optional<double> v, const char* field) const {
        if (!v) return std::numeric_limits<double>::quiet_NaN();
        if (prec_ == precision::binary64) return *v;
        if (const auto f = float_value(*v)) return *f;
        throw input_error(file_, line_, field,
                          fmt::format("{} is not a float (binary32) value, and the results are in float: a double "
                                      "answer? (write floats exactly, e.g. as C99 hex, or with at most 9 significant "
                                      "digits)",
                                      shortest_decimal(*v)));
    }
    // Count 1 without t1 is a tangent's root written once: t1 = t0. Any
    // other absent value stays absent (t0_given, t1_given), for the audit to
    // refuse where the contract needs it.
    void t(std::optional<double> t0, std::optional<double> t1) {
        answer_.roots.t0 = value(t0, "t0");
        answer_.roots.t1 = value(t1, "t1");
        answer_.t0_given = t0.has_value();
        answer_.t1_given = t1.has_value();
        if (!t1 && t0 && answer_.roots.count == 1) {
            answer_.roots.t1 = answer_.roots.t0;
            answer_.t1_given = true;
        }
    }
    // An optional group: every member or none.
    void group(const answer_group_columns& g, const std::array<std::optional<double>, 4>& values) {
        const auto given = std::count_if(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(g.size),
                                         [](const auto& v) { return v.has_value(); });
        if (given == 0) return;
        std::array<double, 4> v{};
        for (std::size_t i = 0; i < g.size; ++i) {
            const std::string name(g.columns[i]);
            if (!values[i]) throw input_error(file_, line_, name, "missing while others of its group are given (all or none)");
            v[i] = value(values[i], name.c_str());
        }
        switch (g.group) {
            case answer_group::t_bounds:
                answer_.t0_bounds = std::array<double, 2>{v[0], v[1]};
                answer_.t1_bounds = std::array<double, 2>{v[2], v[3]};
                break;
            case answer_group::hit_point: answer_.hit_point = vec3<double>{v[0], v[1], v[2]}; break;
            case answer_group::normal: answer_.normal = vec3<double>{v[0], v[1], v[2]}; break;
        }
    }
    // Every value of an answer, from its column by name: `cell` for the t
    // columns, `group_cell` for the optional groups' (absent: nullopt).
    template <class Cell, class GroupCell>
    void columns(Cell cell, GroupCell group_cell) {
        count(cell(answer_t_columns[0]));
        t(cell(answer_t_columns[1]), cell(answer_t_columns[2]));
        for (const answer_group_columns& g : answer_groups) {
            std::array<std::optional<double>, 4> values{};
            for (std::size_t i = 0; i < g.size; ++i) values[i] = group_cell(g.columns[i]);
            group(g, values);
        }
    }
    const recorded_answer& answer() const { return answer_; }

private:
    const std::string& file_;
    std::size_t line_;
    precision prec_;
    recorded_answer answer_;
};

void add_answer(results_file& r, std::string id, const recorded_answer& a, const std::string& file) {
    if (id.empty()) throw input_error(file, a.line, "id", "empty");
    // Stop at the first answer to no case: nothing after it is read or kept.
    if (r.scope && !r.scope->ids.count(id))
        throw input_error(file, a.line, "id", fmt::format("answer for '{}', which is not a case of this input", id));
    const auto [at, inserted] = r.book->by_id.emplace(std::move(id), a);
    if (!inserted)
        throw input_error(file, a.line, "id",
                          fmt::format("duplicate answer for case '{}', first given on line {}", at->first, at->second.line));
}

void check_fingerprint(const results_file& results_, const std::string& input_fingerprint);

results_file start_results(const std::string& file, exchange_format format, const parsed_header& h, std::size_t line,
                           const results_scope* scope) {
    results_file r;
    r.file = file;
    r.header_line = line;
    r.format = format;
    r.prec = h.prec;
    r.fingerprint = h.fingerprint;
    r.book = std::make_shared<answer_book>();
    r.book->source = file;
    r.book->prec = h.prec;
    r.scope = scope;
    // Answers for other cases are refused at their header, before a row is read.
    if (scope && !scope->input_fingerprint.empty()) check_fingerprint(r, scope->input_fingerprint);
    return r;
}

// A number written as text in a results file. A hex float is exact by its
// nature, so in a float file it must be a float: the 9-digit decimal rule
// (float_value) is for decimals, which cannot spell a float exactly.
std::optional<double> answer_number(std::string_view text, const std::string& file, std::size_t line,
                                    const std::string& field, precision p) {
    const double x = parse_exact_double(text, file, line, field);
    std::string_view digits = text.substr(std::min(text.find_first_not_of(" \t"), text.size()));
    if (!digits.empty() && (digits.front() == '-' || digits.front() == '+')) digits.remove_prefix(1);
    const bool hex = digits.size() > 1 && digits[0] == '0' && (digits[1] == 'x' || digits[1] == 'X');
    if (p == precision::binary32 && hex && std::isfinite(x) && static_cast<double>(static_cast<float>(x)) != x)
        throw input_error(file, line, field,
                          fmt::format("{} is a hex double that is not a float (binary32) value, and the results are "
                                      "in float: a double answer? (a hex value is read exactly, never rounded)",
                                      text));
    return x;
}

results_file parse_csv_results(const std::string& file, std::string_view text, const results_scope* scope) {
    std::optional<results_file> r;
    std::vector<std::string> columns;
    // Column index of each answer column (by name), when present.
    std::unordered_map<std::string, std::size_t> at;
    std::size_t header_row = 0;
    for_each_text_line(file, text, [&](std::size_t number, std::string_view line) {
        if (!r) {
            r = start_results(file, exchange_format::csv, header_from_comment(line, file, number), number, scope);
            return;
        }
        const std::string_view trimmed = line.substr(0, line.find_last_not_of(" \t") + 1);
        if (trimmed.empty() || trimmed.front() == '#') return;
        const std::vector<std::string> cells = split_csv_row(line, file, number);
        if (header_row == 0) {
            header_row = number;
            const std::vector<std::string> known = answer_columns();
            for (std::size_t i = 0; i < cells.size(); ++i) {
                const std::string name(cells[i]);
                if (name != "id" && std::find(known.begin(), known.end(), name) == known.end())
                    throw input_error(file, number, name, "unknown column (known: id, " + fmt::format("{}", fmt::join(known, ", ")) + ")");
                if (!at.emplace(name, i).second) throw input_error(file, number, name, "column appears twice");
            }
            for (std::string_view required : {std::string_view("id"), required_answer_column})
                if (!at.count(std::string(required)))
                    throw input_error(file, number, std::string(required), "required column is missing from the header");
            columns.assign(cells.begin(), cells.end());
            return;
        }
        if (cells.size() != columns.size())
            throw input_error(file, number, "",
                              fmt::format("found {} fields, expected {} as in the header on line {}", cells.size(),
                                          columns.size(), header_row));
        const auto cell = [&](std::string_view name) -> std::optional<double> {
            const auto found = at.find(std::string(name));
            if (found == at.end() || cells[found->second].empty()) return std::nullopt;
            return answer_number(cells[found->second], file, number, std::string(name), r->prec);
        };
        answer_builder b(file, number, r->prec);
        b.columns(cell, cell);
        add_answer(*r, std::string(cells[at.at("id")]), b.answer(), file);
    });
    if (!r) throw input_error(file, 0, "header", "empty file: expected '# rayverify results v1 ...'");
    if (header_row == 0) throw input_error(file, 0, "header", "no column header row (id,count,t0,t1,...)");
    return std::move(*r);
}

// A JSON value that is a number, or a string holding one (hex, nan, inf); null is absent.
std::optional<double> json_value(const json& v, const std::string& file, std::size_t line, const std::string& field,
                                 precision p) {
    if (v.is_null()) return std::nullopt;
    if (v.is_number()) return v.get<double>();
    if (v.is_string()) return answer_number(v.get<std::string>(), file, line, field, p);
    throw input_error(file, line, field, fmt::format("expected a number, got {}", v.dump()));
}

// A group's values from an answer's JSON line: each of its arrays (absent or
// null: the group is not given), by column name.
std::map<std::string_view, double> json_group(const json& object, const answer_group_columns& g,
                                              const std::string& file, std::size_t line, precision p) {
    std::map<std::string_view, double> values;
    const std::size_t per_array = g.size / g.json_arrays;
    std::size_t given = 0;
    for (std::size_t k = 0; k < g.json_arrays; ++k) {
        const std::string key(g.json_keys[k]);
        if (!object.contains(key) || object[key].is_null()) continue;
        ++given;
        const json& v = object[key];
        if (!v.is_array() || v.size() != per_array)
            throw input_error(file, line, key, fmt::format("expected an array of {} numbers, got {}", per_array, v.dump()));
        for (std::size_t i = 0; i < per_array; ++i) {
            const std::optional<double> x = json_value(v[i], file, line, key, p);
            if (!x) throw input_error(file, line, key, "null inside the array");
            values[g.columns[k * per_array + i]] = *x;
        }
    }
    if (given != 0 && given != g.json_arrays)
        for (std::size_t k = 0; k < g.json_arrays; ++k)
            if (!object.contains(std::string(g.json_keys[k])) || object[std::string(g.json_keys[k])].is_null())
                throw input_error(file, line, std::string(g.json_keys[k]),
                                  fmt::format("missing while others of its group ({}) are given (all or none)",
                                              fmt::join(g.json_keys.begin(), g.json_keys.begin() +
                                                                                 static_cast<std::ptrdiff_t>(g.json_arrays),
                                                        ", ")));
    return values;
}

results_file parse_jsonl_results(const std::string& file, std::string_view text, const results_scope* scope) {
    std::optional<results_file> r;
    static const std::vector<std::string> keys = answer_json_keys();
    for_each_text_line(file, text, [&](std::size_t number, std::string_view line) {
        if (line.find_first_not_of(" \t") == std::string_view::npos) return;
        json object = parse_json_input(line, file, number);
        if (!r) {
            r = start_results(file, exchange_format::jsonl, header_from_json(object, file, number, "results"), number, scope);
            return;
        }
        if (!object.is_object()) throw input_error(file, number, "", "expected a JSON object");
        for (const auto& [key, value] : object.items())
            if (std::find(keys.begin(), keys.end(), key) == keys.end())
                throw input_error(file, number, key, fmt::format("unknown field (known: {})", fmt::join(keys, ", ")));
        if (!object.contains("id") || !object["id"].is_string())
            throw input_error(file, number, "id", "missing, or not a string");
        const auto get = [&](const char* key) -> std::optional<double> {
            return object.contains(key) ? json_value(object[key], file, number, key, r->prec) : std::nullopt;
        };
        std::map<std::string_view, double> group_values;
        for (const answer_group_columns& g : answer_groups) group_values.merge(json_group(object, g, file, number, r->prec));
        answer_builder b(file, number, r->prec);
        b.columns([&](std::string_view key) { return get(std::string(key).c_str()); },
                  [&](std::string_view column) -> std::optional<double> {
                      const auto found = group_values.find(column);
                      return found == group_values.end() ? std::nullopt : std::optional<double>(found->second);
                  });
        add_answer(*r, object["id"].get<std::string>(), b.answer(), file);
    });
    if (!r) throw input_error(file, 0, "rayverify", "empty file: expected the header line {\"rayverify\": \"results\", ...}");
    return std::move(*r);
}

results_file parse_npy_results(const std::string& file, std::string_view bytes, const std::string& sidecar_name,
                               const std::string& sidecar, const results_scope* scope) {
    const json h = parse_json_input(sidecar, sidecar_name);
    results_file r = start_results(sidecar_name, exchange_format::npy, header_from_json(h, sidecar_name, 1, "results"), 1, scope);
    const npy_array a = parse_npy(file, bytes);
    if (scope && a.rows > scope->cases)
        throw input_error(file, scope->cases + 1, "id",
                          fmt::format("row {} answers no case: the input has {} cases", scope->cases + 1, scope->cases));
    if (a.prec != r.prec)
        throw input_error(file, 0, "dtype",
                          fmt::format("{} values, while {} says precision {}", precision_name(a.prec), sidecar_name,
                                      precision_name(r.prec)));
    if (!h.contains("columns") || !h["columns"].is_array())
        throw input_error(sidecar_name, 1, "columns", "needs the list of the array's column names, e.g. [\"count\", \"t0\", \"t1\"]");
    std::unordered_map<std::string, std::size_t> at;
    const std::vector<std::string> known = answer_columns();
    for (std::size_t i = 0; i < h["columns"].size(); ++i) {
        const json& c = h["columns"][i];
        const std::string name = c.is_string() ? c.get<std::string>() : c.dump();
        if (std::find(known.begin(), known.end(), name) == known.end())
            throw input_error(sidecar_name, 1, "columns", fmt::format("unknown column '{}' (known: {})", name, fmt::join(known, ", ")));
        if (!at.emplace(name, i).second) throw input_error(sidecar_name, 1, "columns", fmt::format("'{}' twice", name));
    }
    if (!at.count(std::string(required_answer_column)))
        throw input_error(sidecar_name, 1, "columns",
                          fmt::format("required column '{}' is missing", required_answer_column));
    if (at.size() != a.columns)
        throw input_error(file, 0, "shape",
                          fmt::format("{} columns, while {} names {}", a.columns, sidecar_name, at.size()));
    std::optional<std::vector<std::string>> ids;
    if (h.contains("ids")) {
        if (!h["ids"].is_array() || h["ids"].size() != a.rows)
            throw input_error(sidecar_name, 1, "ids", fmt::format("must list one id per row ({} rows)", a.rows));
        ids.emplace();
        for (const json& id : h["ids"]) {
            if (!id.is_string()) throw input_error(sidecar_name, 1, "ids", fmt::format("{} is not a string", id.dump()));
            ids->push_back(id.get<std::string>());
        }
    }
    r.by_row = !ids;
    for (std::size_t row = 0; row < a.rows; ++row) {
        const auto cell = [&](std::string_view name) -> std::optional<double> {
            const auto found = at.find(std::string(name));
            if (found == at.end()) return std::nullopt;
            return a.at(row, found->second);
        };
        // An absent optional value is NaN in an array.
        const auto optional = [&](std::string_view name) -> std::optional<double> {
            const auto v = cell(name);
            return v && !std::isnan(*v) ? v : std::nullopt;
        };
        answer_builder b(file, row + 1, r.prec);
        b.columns(cell, optional);
        if (ids)
            add_answer(r, (*ids)[row], b.answer(), file);
        else
            r.rows.push_back(b.answer());
    }
    return r;
}

}  // namespace

void check_recorded_values(const contract& promises, const answer_book& book) {
    const recorded_answer* first = nullptr;
    std::string first_id;
    const char* field = nullptr;
    for (const auto& [id, a] : book.by_id) {
        if (first && first->line < a.line) continue;
        const int n = a.roots.count;
        const char* lacks = nullptr;
        switch (promises.query) {
            case query_kind::any_hit: break;
            case query_kind::nearest_hit:
                // A point answer's t is derived from its point (px py pz, required beside a hit).
                lacks = n == 1 && !a.t0_given && promises.answer != answer_kind::point ? "t0" : nullptr;
                break;
            case query_kind::line_roots:
                lacks = (n == 1 || n == 2) && !a.t0_given ? "t0" : n == 2 && !a.t1_given ? "t1" : nullptr;
                break;
        }
        if (!lacks) continue;
        first = &a;
        first_id = id;
        field = lacks;
    }
    if (first)
        throw input_error(book.source, first->line, field,
                          fmt::format("missing: answer '{}' has count {}, and a {} answer with that count needs {}",
                                      first_id, first->roots.count, query_kind_name(promises.query), field));
}

results_file parse_results(const std::string& name, std::string_view text, exchange_format format,
                           const std::optional<std::string>& sidecar, const results_scope* scope) {
    results_file r;
    try {
        switch (format) {
            case exchange_format::csv: r = parse_csv_results(name, text, scope); break;
            case exchange_format::jsonl: r = parse_jsonl_results(name, text, scope); break;
            case exchange_format::npy:
                if (!sidecar) throw input_error(name, 0, "", "an npy file needs its JSON companion");
                r = parse_npy_results(name, text, sidecar_of(name).string(), *sidecar, scope);
                break;
        }
    } catch (const json::exception& e) {
        // Whatever the checks above missed is still a bad input, never an internal error.
        throw input_error(name, 0, "", fmt::format("not a results file: {}", e.what()));
    }
    r.scope = nullptr;
    return r;
}

std::size_t results_scope::max_bytes(exchange_format format, bool companion) const {
    // A header, column names and comments, then per case: every answer
    // column written at full length (with a JSON key, quotes and
    // separators), and the id, escaped (JSON's \uXXXX takes at most six
    // bytes per byte of UTF-8) and indented.
    constexpr std::size_t header = std::size_t{1} << 16, per_value = 48;
    const std::size_t values = answer_columns().size();
    if (format == exchange_format::npy)
        return companion ? header + 6 * id_bytes + 16 * cases : header + cases * values * sizeof(double);
    return header + cases * (values * per_value + 64) + 6 * id_bytes;
}

namespace {

std::string read_whole(const fs::path& path, const char* what, std::optional<std::size_t> max_bytes) {
    std::error_code error;
    if (fs::is_directory(path, error)) throw input_error(path.string(), 0, what, "is a directory, not a file");
    // Never opened: a FIFO would block until a writer comes, a device may never end.
    struct stat s {};
    if (::stat(path.c_str(), &s) == 0 && !S_ISREG(s.st_mode))
        throw input_error(path.string(), 0, what,
                          "is not a regular file (a FIFO, a device or a socket): results are read from a file");
    if (max_bytes && s.st_size >= 0 && static_cast<std::uintmax_t>(s.st_size) > *max_bytes)
        throw input_error(path.string(), 0, what,
                          fmt::format("is {} bytes, more than answers to the input's cases can take (at most {})",
                                      s.st_size, *max_bytes));
    std::ifstream in(path, std::ios::binary);
    if (!in) throw input_error(path.string(), 0, what, "cannot open for reading");
    std::ostringstream bytes;
    bytes << in.rdbuf();
    if (in.bad()) throw input_error(path.string(), 0, what, "read error");
    return bytes.str();
}

}  // namespace

results_file read_results(const fs::path& path, const results_scope* scope) {
    const auto format = exchange_format_of(path);
    if (!format)
        throw input_error(path.string(), 0, "--results", "unknown extension (expected .csv, .jsonl or .npy)");
    const auto bound = [&](bool companion) -> std::optional<std::size_t> {
        if (!scope) return std::nullopt;
        return scope->max_bytes(*format, companion);
    };
    const std::string text = read_whole(path, "--results", bound(false));
    std::optional<std::string> sidecar;
    if (*format == exchange_format::npy) {
        const fs::path companion = sidecar_of(path);
        std::error_code error;
        if (!fs::exists(companion, error))
            throw input_error(companion.string(), 0, "--results",
                              fmt::format("missing: {} needs this JSON companion with the header (rayverify, version, "
                                          "precision, fingerprint) and its column names",
                                          path.filename().string()));
        sidecar = read_whole(companion, "--results", bound(true));
    }
    return parse_results(path.string(), text, *format, sidecar, scope);
}

// ---- Matching answers to the input ---------------------------------------------------

void answer_matcher::add(const corpus_case& c) {
    const std::size_t index = seen_++;
    if (results_.by_row) {
        if (index < results_.rows.size()) {
            if (!results_.book->by_id.emplace(c.id, results_.rows[index]).second)
                throw input_error(c.source, 0, "id", fmt::format("duplicate case id '{}'", c.id));
        } else if (!first_missing_) {
            first_missing_ = fmt::format("'{}' ({}; case {} of the input, the array has {} rows)", c.id, c.source,
                                         index + 1, results_.rows.size());
        }
        return;
    }
    if (results_.book->find(c.id))
        matched_.insert(c.id);
    else if (!first_missing_)
        first_missing_ = fmt::format("'{}' ({})", c.id, c.source);
}

namespace {

// The answers are for this input, in this precision: else an error on the header's line.
void check_fingerprint(const results_file& results_, const std::string& input_fingerprint) {
    const std::string expected = exchange_fingerprint(input_fingerprint, results_.prec);
    if (results_.fingerprint != expected) {
        const precision other = results_.prec == precision::binary32 ? precision::binary64 : precision::binary32;
        if (results_.fingerprint == exchange_fingerprint(input_fingerprint, other))
            throw input_error(results_.file, results_.header_line, "precision",
                              fmt::format("wrong precision: the answers say {}, but their fingerprint is that of the "
                                          "{} export of this input (export again, or compute in {})",
                                          precision_name(results_.prec), precision_name(other), precision_name(other)));
        throw input_error(results_.file, results_.header_line, "fingerprint",
                          fmt::format("{} is not the fingerprint of this input in {} ({}): the answers were "
                                      "computed for other cases (export them again with the same --corpus, "
                                      "--generate or --scene)",
                                      results_.fingerprint, precision_name(results_.prec), expected));
    }
}

}  // namespace

std::shared_ptr<const answer_book> answer_matcher::finish(const std::string& input_fingerprint) {
    check_fingerprint(results_, input_fingerprint);
    const std::string answers = results_.by_row ? sidecar_of(results_.file).replace_extension(".npy").string()
                                                : results_.file;
    if (first_missing_) throw input_error(answers, 0, "id", "no answer for case " + *first_missing_);
    if (results_.by_row && results_.rows.size() > seen_)
        throw input_error(answers, seen_ + 1, "id",
                          fmt::format("row {} answers no case: the input has {} cases", seen_ + 1, seen_));
    if (!results_.by_row && results_.book->by_id.size() > seen_) {
        // Every case answered and answers left over: name the first by line.
        const recorded_answer* extra = nullptr;
        std::string extra_id;
        for (const auto& [id, a] : results_.book->by_id)
            if (!matched_.count(id) && (!extra || a.line < extra->line)) {
                extra = &a;
                extra_id = id;
            }
        if (extra)
            throw input_error(answers, extra->line, "id", fmt::format("answer for '{}', which is not a case of this input", extra_id));
    }
    return results_.book;
}

}  // namespace rayverify
