// Reading and writing corpora of ray–sphere cases, exactly.
//
// Text corpus (any extension but .csv): one case a line,
//     id family ox oy oz dx dy dz cx cy cz r [tmin tmax]
// separated by whitespace; `#` starts a comment (a whole line, or from a
// token that begins with `#` to the end of the line); blank lines are ignored.
// `-` as family means unknown; `-` as tmin or tmax means that bound is absent.
// A segment case (core/ray_sphere_case.h) is the line
//     id family segment p0x p0y p0z p1x p1y p1z cx cy cz r
// (the keyword `segment` third; no tmin or tmax: its range is the fractions
// [0, 1]); ray and segment lines may mix in one text file.
//
// CSV corpus (.csv, any case): a header line names the columns id, ox, oy, oz,
// dx, dy, dz, cx, cy, cz, r (required) and family, tmin, tmax (optional), in
// any order; other columns are ignored. Cells are trimmed of whitespace; a
// cell in double quotes may hold commas, with "" for a quote (RFC 4180, one
// line per row). An empty or '-' tmin or tmax cell means absent. A segment
// file names p0x, p0y, p0z, p1x, p1y, p1z in place of ox..dz, and no tmin or
// tmax; a header naming both forms is refused (one form a CSV file).
//
// Numbers are read exactly: shortest round-trip decimals, C99 hex floats
// (which must fit a double without rounding), and nan / inf / infinity.
// Every problem is an input_error naming file, line and field.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "core/input_error.h"
#include "core/outputs.h"
#include "core/ray_sphere_case.h"

namespace rayverify {

// Parse one number field exactly (decimal or C99 hex float, nan/inf allowed).
// Throws input_error(file, line, field, ...) on anything else: a token that is
// not entirely a number, a value out of double range, a decimal that
// underflows to zero, a hex float with more significant bits than a double.
double parse_exact_double(std::string_view token, const std::string& file, std::size_t line,
                          const std::string& field);

// The text format of a double that reads back bit-exactly: C99 hex float like
// "0x1.8p+1", "-0x0p+0", "inf", "-inf", "nan" (C's %a, written from the bits;
// tests/corpus_io_test.cpp checks it against printf's and parse_exact_double).
std::string hex_float(double x);
// The same, appended to `out`.
void append_hex_float(std::string& out, double x);
// The same, written at `at` (room for hex_float_max_size characters, no
// terminating zero); returns the end of the text.
inline constexpr std::size_t hex_float_max_size = 24;  // "-0x1.fffffffffffffp-1022"
char* write_hex_float(char* at, double x);

// Shortest round-trip decimal, e.g. "0.1", "5e-324".
std::string shortest_decimal(double x);

// One case as a text-corpus line (hex floats, family "-" when empty, tmin and
// tmax appended when either is present, "-" for the absent one). Pasteable
// back into a corpus file; parses back to an identical case. Throws
// input_error when the id or family could not be read back as one token.
std::string format_case_line(const corpus_case& c);
// The same, appended to `line` (no newline).
void append_case_line(std::string& line, const corpus_case& c);

// The comment header every written corpus file starts with (column names),
// without a trailing newline.
std::string corpus_header_comment();
// The comment naming a segment line's columns, which a written corpus holding
// segments carries after corpus_header_comment() (no trailing newline).
std::string segment_header_comment();

// The largest corpus file read_corpus_file accepts. A larger file is refused
// before anything is read (a parsed case takes up to ~10x its line in memory,
// and 64 MiB is already ~300 000 cases of hex floats): split it, and pass the
// parts or their directory.
inline constexpr std::uintmax_t max_corpus_file_bytes = std::uintmax_t{64} << 20;

// Read one file, text or CSV by extension. Each case gets source "file:line".
// A file without cases gives an empty vector; duplicate ids are an error.
std::vector<corpus_case> read_corpus_file(const std::filesystem::path& path);

// Parse a corpus held in memory, as read_corpus_file would parse a file named
// `file` with that contents (`csv`: the CSV format, else the text format).
std::vector<corpus_case> parse_corpus(const std::string& file, std::string_view contents, bool csv);

// One --corpus argument as listed: a file names itself; a directory gives its
// own *.txt and *.csv files, sorted by name. A subdirectory holding corpus
// files (at any depth) is never skipped in silence: it is refused
// (input_error naming it) unless the directory's MANIFEST lists files in it,
// which makes it a corpus of its own (corpus/edge beside the shipped
// corpus), kept in `separate_subdirectories` for the reading summary. Also
// refused: a directory that cannot be listed, or something named *.txt or
// *.csv that is not a regular file (a dangling link, a pipe, a device).
struct corpus_argument {
    std::filesystem::path path;
    std::vector<std::filesystem::path> files;
    std::vector<std::filesystem::path> separate_subdirectories;
};
corpus_argument list_corpus_argument(const std::filesystem::path& path);
std::vector<std::filesystem::path> corpus_files(const std::filesystem::path& path);

// What was read from each argument, for the line every command that reads a
// corpus prints on stderr: "corpus: 6 files, 3000 cases (edge/ not read: …)".
struct corpus_reading {
    struct argument_tally {
        corpus_argument argument;
        std::size_t cases = 0;
    };
    std::vector<argument_tally> arguments;
    std::string text() const;
};

// Read files and directories (as list_corpus_argument lists them), in the
// order given. Duplicate ids across everything read, or no case at all, are
// errors. `reading`, when given, gets each argument's files and cases.
std::vector<corpus_case> read_corpus(const std::vector<std::filesystem::path>& paths,
                                     corpus_reading* reading = nullptr);

// One CSV row's cells, as RFC 4180 quotes them on one line: a cell in double
// quotes may hold commas, and "" in it stands for a quote; blanks around a
// cell are trimmed. Throws input_error for a quote left open, text after a
// closing quote, or a quote in an unquoted cell.
std::vector<std::string> split_csv_row(std::string_view line, const std::string& file, std::size_t number);

// Write cases as a text corpus, whole or not at all (write_file_atomically,
// core/outputs.h): corpus_header_comment(), then each of header_comments
// prefixed by "# ", then one format_case_line per case.
void write_corpus_file(const std::filesystem::path& path, const std::vector<corpus_case>& cases,
                       const std::vector<std::string>& header_comments);

}  // namespace rayverify
