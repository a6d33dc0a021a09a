// Cases out, answers in: the exchange formats through which an intersector
// that does not run in rayverify's process (a GPU kernel, a shader, NumPy,
// JavaScript) is audited. Schema version 1, described field by field in
// docs/schema/rayverify-exchange-v1.json and docs/other-languages.md.
//
// Three formats, each for cases and for answers:
// - CSV: a first line "# rayverify KIND v1 key=value ...", a header row naming
//   the columns, one row per case or answer;
// - JSON lines: a first line {"rayverify": KIND, "version": 1, ...}, one
//   object per case or answer;
// - NumPy .npy: a 2-D little-endian float32 or float64 array, one row per case
//   or answer, and beside it a JSON file (same stem, .json) with the header
//   and the column names (and, for cases, the ids in row order).
// KIND is "cases" or "results". A header states the precision of the values
// and the fingerprint of the cases (the input's fingerprint and that
// precision), which answers must repeat: answers computed for other inputs,
// or in another precision, are refused.
#pragma once

#include <cstddef>
#include <filesystem>
#include <iosfwd>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_set>
#include <vector>

#include "core/contract.h"
#include "core/ray_sphere_case.h"
#include "core/recorded_answer.h"

namespace rayverify {

enum class exchange_format { csv, jsonl, npy };

std::string_view exchange_format_name(exchange_format f);
// Every format's name, in enum order (export --format's choices).
std::vector<std::string> every_exchange_format_name();
std::optional<exchange_format> exchange_format_from_name(std::string_view name);
// By the file's extension (.csv, .jsonl, .npy; any case); nullopt for another.
std::optional<exchange_format> exchange_format_of(const std::filesystem::path& path);

// How numbers are written to CSV and JSON lines: shortest round-trip
// decimals (of the value's own precision) or C99 hex floats. Both are exact.
enum class number_style { decimal, hex };

inline constexpr int exchange_version = 1;

// The npy file's companion: "cases.npy" → "cases.json".
std::filesystem::path sidecar_of(const std::filesystem::path& npy);

// 16 hex digits naming an export: the input's fingerprint (corpus/case_stream.h)
// and the precision its values were rounded to.
std::string exchange_fingerprint(std::string_view input_fingerprint, precision p);

struct cases_header {
    precision prec = precision::binary64;
    std::string fingerprint;  // exchange_fingerprint of the input
    std::size_t cases = 0;
    number_style numbers = number_style::decimal;
    // Some case is a segment: CSV and npy files then carry the columns p1x,
    // p1y, p1z (its end as given; empty / NaN on a ray case's row). JSON
    // lines give them on a segment's line whatever this says.
    bool segments = false;
};

// Writes the cases of an export, one at a time, in memory that does not grow
// with their number. Every value is rounded to the header's precision, as an
// intersector running in it receives it (a segment case in its ray form:
// o = p0, d = p1 − p0 computed in that precision, tmin 0, tmax 1, and
// p1x, p1y, p1z, its end as given (cases_header::segments); the answers are
// judged on the exact segment, a rounding of d counted as the program's). npy: `sidecar` receives the JSON
// companion (header, columns, ids in row order); unused otherwise.
class case_writer {
public:
    case_writer(std::ostream& out, std::ostream* sidecar, exchange_format format, const cases_header& header);
    void write(const corpus_case& c);
    // Closes the npy companion's id list. Throws std::logic_error when the
    // number of cases written differs from the header's.
    void finish();

private:
    std::ostream& out_;
    std::ostream* sidecar_;
    exchange_format format_;
    cases_header header_;
    std::size_t written_ = 0;
};

// The columns an answer may have: count (required), t0, t1 (as the contract
// needs them: check_recorded_values), then the optional groups t0_lo t0_hi
// t1_lo t1_hi, px py pz, nx ny nz (each group all or none).
std::vector<std::string> answer_columns();

// The cases a results file may answer, known before it is read: an answer
// to any other id is refused at its row, before the rest is read, and the
// file may be no larger than answers to these cases can take.
struct results_scope {
    std::unordered_set<std::string> ids;
    std::size_t cases = 0;
    std::size_t id_bytes = 0;  // the ids' total length
    std::string input_fingerprint;  // checked against the header as soon as it is read
    void add(const std::string& id) {
        ids.insert(id);
        ++cases;
        id_bytes += id.size();
    }
    // The most bytes answers to these cases can take in a file of `format`
    // (its companion's, for npy with `companion`).
    std::size_t max_bytes(exchange_format format, bool companion = false) const;
};

// A results file, read and checked on its own (header, columns, every value).
struct results_file {
    std::string file;          // the file the header is in (an npy's companion)
    std::size_t header_line = 0;
    exchange_format format = exchange_format::csv;
    precision prec = precision::binary64;
    std::string fingerprint;
    // Answers by id (CSV, JSON lines, npy with "ids"), or by row in the
    // cases' order (npy without ids): then `rows` holds them and `book` is
    // filled by match_answers.
    std::shared_ptr<answer_book> book;
    std::vector<recorded_answer> rows;
    bool by_row = false;
    const results_scope* scope = nullptr;  // while reading: the ids it may answer
};

// Reads a results file in the format of its extension. Throws input_error
// naming file, line (or npy row) and field: an unknown header or version,
// an unknown or incomplete column group, a value that is not a number or not
// of the stated precision, a count other than 0, 1 or 2, a duplicate id;
// with a scope, an answer to no case of it (or an npy of more rows than it
// has cases) and a file larger than its answers can take. Only regular files
// are read: a FIFO or a device (which could block, or never end) is refused.
results_file read_results(const std::filesystem::path& path, const results_scope* scope = nullptr);

// Throws input_error (file, line) unless `text` is a results file's header
// line in `format` (csv or jsonl): a stream's first line, checked on arrival.
void check_results_header(std::string_view text, exchange_format format, const std::string& file, std::size_t line);

// The same from memory: `text` is the file's contents, `sidecar` the npy
// companion's (required for npy).
results_file parse_results(const std::string& name, std::string_view text, exchange_format format,
                           const std::optional<std::string>& sidecar = std::nullopt,
                           const results_scope* scope = nullptr);

// Every value the contract needs is given (docs/other-languages.md): a
// line_roots answer with count 1 or 2 needs t0 (count 1 without t1 was read
// as t1 = t0), with count 2 also t1; a nearest_hit answer with count 1 needs
// t0; an any_hit answer only its count. Throws input_error naming the file,
// the line of the first answer (in the file's order) that leaves one out, and
// the field, so that no absent value is ever judged.
void check_recorded_values(const contract& promises, const answer_book& book);

// Ties a results file to the input it must answer: every case of the input,
// in order, then finish() with the input's fingerprint. Throws input_error
// (no answer is judged) when the answers are for another input or precision
// (the header's line), when a case has no answer (its id and where it was
// read), when an answer has no case (its id and line), or when an npy has
// more or fewer rows than the input has cases.
class answer_matcher {
public:
    explicit answer_matcher(results_file& results) : results_(results) {}
    void add(const corpus_case& c);
    std::shared_ptr<const answer_book> finish(const std::string& input_fingerprint);

private:
    results_file& results_;
    std::size_t seen_ = 0;
    std::optional<std::string> first_missing_;  // "'id' (where)"
    std::unordered_set<std::string> matched_;   // by id: the answers that have a case
};

}  // namespace rayverify
