// Hostile and broken input, end to end through the rayverify executable:
// every class of bad input we know of gets an answer that names file, line and
// field, exit code 2, and no output file left behind. The table of
// docs/bad-input.md is generated from these very runs, and a test fails when
// the page differs from what the tool answers today.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <set>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "corpus/case_stream.h"
#include "corpus/corpus_io.h"
#include "corpus/exchange.h"
#include "support/process.h"
#include "support/results_program.h"

namespace {

namespace fs = std::filesystem;

using rayverify::test_support::read_text;
using rayverify::test_support::scratch_directory;

struct run_result {
    int exit_code = -1;
    std::string out, err;
    // What the tool answered: the first line of stderr, or else the stdout
    // line starting with `prefix` (for bad input that is accepted and listed).
    std::string answer(const std::string& prefix) const {
        // The summary of what a command read from each corpus argument
        // ("audit: read corpus: 6 files, ...") is a note, not the answer.
        static const std::regex reading_note("^[a-z]+: read .*: [0-9]+ files?, [0-9]+ cases?.*");
        std::istringstream err_lines(err);
        for (std::string line; std::getline(err_lines, line);)
            if (!std::regex_match(line, reading_note)) return line;
        std::istringstream out_lines(out);
        for (std::string line; std::getline(out_lines, line);)
            if (line.starts_with(prefix)) return line;
        return "";
    }
};

// Runs `rayverify <arguments>` in `cwd`, so that messages name files as the
// command does (relative), with stdout and stderr captured apart.
run_result run_in(const fs::path& cwd, const std::string& arguments, bool unprivileged = false,
                  const std::string& environment = "") {
    scratch_directory logs("rayverify_hostile_logs");
    // Root reads a mode-000 file anyway; run as nobody to see what a user sees.
    const std::string prefix =
        unprivileged && geteuid() == 0 ? "setpriv --reuid=65534 --regid=65534 --clear-groups " : "";
    const std::string command =
        fmt::format("cd '{}' && {} {}'{}' {} >'{}' 2>'{}'", cwd.string(), environment, prefix, RAYVERIFY_CLI,
                    arguments, (logs.path() / "out").string(), (logs.path() / "err").string());
    const int status = std::system(command.c_str());
    run_result r;
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = read_text(logs.path() / "out");
    r.err = read_text(logs.path() / "err");
    return r;
}

std::set<std::string> listing(const fs::path& dir) {
    std::set<std::string> names;
    for (const auto& entry : fs::recursive_directory_iterator(dir))
        names.insert(entry.path().lexically_relative(dir).string());
    return names;
}

const std::string good = "good - 0 0 -5 0 0 1 0 0 0 1\n";  // a unit sphere hit at t = 4 and 6
const std::string csv_header = "id,ox,oy,oz,dx,dy,dz,cx,cy,cz,r\n";

// A scene of 2×2 pixels looking at one sphere; bad scenes are edits of it,
// so that each row's message names a line of this text.
const std::string good_scene = R"({
  "precision": "double",
  "camera": {"projection": "perspective", "position": [0, 0, 5], "look_at": [0, 0, 0],
             "fov_degrees": 45, "resolution": [2, 2]},
  "spheres": [
    {"name": "ball", "centre": [0, 0, 0], "radius": 1}
  ]
}
)";

// `text` with the first `from` replaced by `to` (which must be there).
std::string edited(std::string text, const std::string& from, const std::string& to) {
    const std::size_t at = text.find(from);
    if (at == std::string::npos) throw std::logic_error("not in the text: " + from);
    return text.replace(at, from.size(), to);
}

std::string scene_with(const std::string& from, const std::string& to) { return edited(good_scene, from, to); }

// A baseline good.txt's one case passes (naive/double finds it exact).
const std::string baseline_head = "rayverify-baseline 1\n";
const std::string good_baseline = baseline_head + "naive/double all cases 1\n";

// One row of the docs/bad-input.md table: a bad input, the command given it, and what
// the answer must say. The answer itself is whatever the tool prints.
struct bad_input {
    std::string what;     // first column of the table (markdown)
    std::string command;  // as shown in the table; "rayverify" is the binary
    std::vector<std::pair<std::string, std::string>> files;  // created in the row's directory
    int exit_code = 2;
    std::string expect;   // the answer contains this: file:line: field 'name' where there is one
    std::function<void(const fs::path&)> prepare = {};  // for what a file's contents cannot make
    bool unprivileged = false;
    std::string environment = "";  // VAR=value words before the command (a fixture plugin's mode)
    std::string answer_prefix = "invalid cases";  // the stdout line shown when nothing went to stderr
};

// The test fixture plugin (tests/plugin_fixtures) copied into a row's directory, so that the
// table names it as ./NAME; `bytes` > 0 keeps only that many bytes of it (a truncated library).
std::function<void(const fs::path&)> plugin_copy(const std::string& library, const std::string& name,
                                                 std::size_t bytes = 0) {
    return [library, name, bytes](const fs::path& dir) {
        fs::copy_file(library, dir / name);
        if (bytes > 0) fs::resize_file(dir / name, bytes);
    };
}

// A shard of a one-case audit in dir/s1, its shard.json then edited by `edit`.
std::function<void(const fs::path&)> edited_shard(std::function<void(nlohmann::ordered_json&)> edit) {
    return [edit](const fs::path& dir) {
        std::ofstream(dir / "one.txt") << "good - 0 0 -5 0 0 1 0 0 0 1\n";
        const std::string command = fmt::format(
            "cd '{}' && '{}' audit --corpus one.txt --variant naive --precision double --shard 1/1 --report s1 "
            "--per-case s1/cases.jsonl >/dev/null",
            dir.string(), RAYVERIFY_CLI);
        ASSERT_EQ(std::system(command.c_str()), 0);
        std::ifstream in(dir / "s1" / "shard.json");
        nlohmann::ordered_json state = nlohmann::ordered_json::parse(in);  // the keys in their order: merge reads the header first
        edit(state);
        std::ofstream(dir / "s1" / "shard.json") << state.dump() << '\n';
    };
}

// Two one-variant audit reports, a.json and b.json, of the corpus texts given.
std::function<void(const fs::path&)> two_reports(std::string a_corpus, std::string a_variant, std::string b_corpus,
                                                 std::string b_variant) {
    return [=](const fs::path& dir) {
        for (const auto& [name, corpus, variant] :
             {std::tuple{"a", a_corpus, a_variant}, std::tuple{"b", b_corpus, b_variant}}) {
            std::ofstream(dir / (std::string(name) + ".txt")) << corpus;
            const std::string command = fmt::format(
                "cd '{0}' && '{1}' audit --corpus {2}.txt --variant {3} --precision double --report r{2} >/dev/null; "
                "mv r{2}/report.json {2}.json && rm -r r{2} {2}.txt",
                dir.string(), RAYVERIFY_CLI, name, variant);
            ASSERT_LE(WEXITSTATUS(std::system(command.c_str())), 1);
        }
    };
}


// ---- Answers computed outside rayverify for good.txt's one case (hit at 4 and 6) ----

// The fingerprint a results file for good.txt repeats, in precision `p`.
std::string good_fingerprint(rayverify::precision p = rayverify::precision::binary64) {
    rayverify::case_fingerprint fingerprint;
    for (const rayverify::corpus_case& c : rayverify::parse_corpus("good.txt", good, false)) fingerprint.add(c);
    return rayverify::exchange_fingerprint(fingerprint.text(), p);
}

std::string answers_csv(const std::string& rows, rayverify::precision p = rayverify::precision::binary64) {
    return fmt::format("# rayverify results v1 precision={} fingerprint={}\nid,count,t0,t1\n",
                       rayverify::precision_name(p), good_fingerprint(p)) +
           rows;
}
const std::string good_answers = answers_csv("good,2,4,6\n");

std::string answers_jsonl(const std::string& rows) {
    return fmt::format("{{\"rayverify\":\"results\",\"version\":1,\"precision\":\"double\",\"fingerprint\":\"{}\"}}\n",
                       good_fingerprint()) +
           rows;
}

// An npy of float64 rows (count, t0, t1) and its companion, `extra` added to the companion's fields.
std::string answers_npy(const std::vector<std::array<double, 3>>& rows) {
    std::string dict = fmt::format("{{'descr': '<f8', 'fortran_order': False, 'shape': ({}, 3), }}", rows.size());
    dict.append((64 - (10 + dict.size() + 1) % 64) % 64, ' ');
    dict += '\n';
    std::string out = std::string("\x93NUMPY\x01\x00", 8);
    out += static_cast<char>(dict.size() & 0xff);
    out += static_cast<char>(dict.size() >> 8);
    out += dict;
    for (const auto& row : rows)
        for (double v : row) out.append(reinterpret_cast<const char*>(&v), sizeof v);
    return out;
}
std::string answers_companion(const std::string& extra = "") {
    return fmt::format("{{\"rayverify\":\"results\",\"version\":1,\"precision\":\"double\",\"fingerprint\":\"{}\","
                       "\"columns\":[\"count\",\"t0\",\"t1\"]{}}}\n",
                       good_fingerprint(), extra);
}

// Runs rayverify in `dir` while a row is prepared; the setup must succeed (exit 0 or 1).
void setup_run(const fs::path& dir, const std::string& arguments) {
    const int status =
        std::system(fmt::format("cd '{}' && '{}' {} >/dev/null 2>&1", dir.string(), RAYVERIFY_CLI, arguments).c_str());
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) <= 1) << arguments;
}

// A program for `hunt --command` (python3): it answers every batch with a miss per case, then
// writes `after_batch` after each answer and `at_end` when its input ends.
std::string answering_program(const std::string& after_batch, const std::string& at_end) {
    return "import json, sys\n" + rayverify::test_support::miss_answering_loop(after_batch) + "sys.stdout.write(" +
           at_end + ")\n";
}

const std::string modal_plugin = RAYVERIFY_FIXTURE_PLUGIN_MODAL;
const std::string garbage_plugin = RAYVERIFY_FIXTURE_PLUGIN_GARBAGE;
const std::string fp_hostile_plugin = RAYVERIFY_FIXTURE_FP_HOSTILE;
const std::string fp_fast_math_plugin = RAYVERIFY_FIXTURE_FP_FAST_MATH_LINK;

std::string bytes(const char* data, std::size_t size) { return std::string(data, size); }

std::vector<bad_input> bad_inputs() {
    const auto one = [](std::string name, std::string contents) {
        return std::vector<std::pair<std::string, std::string>>{{std::move(name), std::move(contents)}};
    };
    return {
        // Lines and fields of a text corpus.
        {"truncated line (11 of 12 fields)", "rayverify audit --corpus cut.txt",
         one("cut.txt", good + "cut - 0 0 -5 0 0 1 0 0 0\n"), 2, "cut.txt:2: found 11 fields"},
        {"13 fields (tmin without tmax)", "rayverify audit --corpus half.txt",
         one("half.txt", good + "half - 0 0 -5 0 0 1 0 0 0 1 0\n"), 2, "field 'tmax' is missing"},
        {"15 fields", "rayverify audit --corpus long.txt",
         one("long.txt", good + "long - 0 0 -5 0 0 1 0 0 0 1 0 9 7\n"), 2, "long.txt:2: found 15 fields"},
        {"text in a number field (`one`)", "rayverify audit --corpus word.txt",
         one("word.txt", good + "word - 0 0 -5 0 0 one 0 0 0 1\n"), 2, "word.txt:2: field 'dz'"},
        {"number with trailing junk (`1.5x`)", "rayverify audit --corpus junk.txt",
         one("junk.txt", good + "junk - 0 0 -5 0 0 1 0 0 0 1.5x\n"), 2, "junk.txt:2: field 'r'"},
        {"decimal comma (`0,5`)", "rayverify audit --corpus comma.txt",
         one("comma.txt", good + "comma - 0,5 0 -5 0 0 1 0 0 0 1\n"), 2, "comma.txt:2: field 'ox'"},
        {"decimal overflow (`1e999`)", "rayverify audit --corpus over.txt",
         one("over.txt", good + "over - 0 0 -5 0 0 1 0 0 0 1e999\n"), 2, "over.txt:2: field 'r'"},
        {"decimal underflow (`1e-400`)", "rayverify audit --corpus under.txt",
         one("under.txt", good + "under - 0 0 -5 0 0 1 1e-400 0 0 1\n"), 2, "under.txt:2: field 'cx'"},
        {"30-digit exponent", "rayverify audit --corpus exp.txt",
         one("exp.txt", good + "exp - 0 0 -5 0 0 1 0 0 0 1e999999999999999999999999999999\n"), 2,
         "exp.txt:2: field 'r'"},
        {"hex float with 54 significant bits", "rayverify audit --corpus bits.txt",
         one("bits.txt", good + "bits - 0 0 -5 0 0 1 0 0 0 0x1.00000000000008p0\n"), 2, "bits.txt:2: field 'r'"},
        {"hex float below the least subnormal (`0x1p-1075`)", "rayverify audit --corpus sub.txt",
         one("sub.txt", good + "sub - 0x1p-1075 0 -5 0 0 1 0 0 0 1\n"), 2, "sub.txt:2: field 'ox'"},
        {"hex float above the double range (`0x1p+1024`)", "rayverify audit --corpus big.txt",
         one("big.txt", good + "big - 0 0 -5 0 0 1 0 0 0x1p+1024 1\n"), 2, "big.txt:2: field 'cz'"},
        {"hex float without digits (`0x`, `0x1p`)", "rayverify audit --corpus hex.txt",
         one("hex.txt", good + "hex - 0 0 -5 0 0 1 0 0 0x 0x1p\n"), 2, "hex.txt:2: field 'cz'"},
        {"NaN with a payload (`nan(7)`)", "rayverify audit --corpus payload.txt",
         one("payload.txt", good + "payload - nan(7) 0 -5 0 0 1 0 0 0 1\n"), 2, "payload.txt:2: field 'ox'"},
        {"`nan`, `inf`, zero direction, negative radius in a good corpus: accepted, listed as invalid, "
         "never scored",
         "rayverify audit --corpus invalid.txt --variant hearn_baker --precision double",
         one("invalid.txt", good + "nan-origin - nan 0 -5 0 0 1 0 0 0 1\n"
                                   "inf-radius - 0 0 -5 0 0 1 0 0 0 inf\n"
                                   "zero-dir - 0 0 -5 0 0 0 0 0 0 1\n"
                                   "neg-radius - 0 0 -5 0 0 1 0 0 0 -1\n"),
         0, "invalid cases (4, not scored): nan-origin"},
        {"a value that overflows float (`1e300`): invalid in float only",
         "rayverify audit --corpus huge.txt --variant hearn_baker --precision float",
         one("huge.txt", good + "huge - 0 0 -5 0 0 1 0 0 1e300 1\n"), 0, "huge (float: not_representable"},
        {"an invalid case among many: the first five are named", "rayverify audit --corpus many.txt --variant naive",
         one("many.txt", [] {
             std::string s = good;
             for (int i = 0; i < 7; ++i) s += fmt::format("zero-{} - 0 0 -5 0 0 0 0 0 0 1\n", i);
             return s;
         }()),
         0, "and 2 more (all listed in report.json)"},
        // Ids.
        {"duplicate id in one file", "rayverify audit --corpus dup.txt", one("dup.txt", good + good), 2,
         "dup.txt:2: field 'id': duplicate id 'good', first defined at dup.txt:1"},
        {"duplicate id across files", "rayverify audit --corpus a.txt --corpus b.txt",
         {{"a.txt", good}, {"b.txt", good}}, 2, "b.txt:1: field 'id'"},
        {"a corpus directory with a subdirectory of corpus files (never skipped in silence)",
         "rayverify audit --corpus dir", {}, 2, "dir/sub: a subdirectory of dir holding 1 corpus file",
         [](const fs::path& dir) {
             fs::create_directories(dir / "dir" / "sub");
             std::ofstream(dir / "dir" / "a.txt") << good;
             std::ofstream(dir / "dir" / "sub" / "b.txt") << good;
         }},
        // Whole files.
        {"empty file", "rayverify audit --corpus empty.txt", one("empty.txt", ""), 2, "empty.txt: empty corpus"},
        {"comments and blank lines only", "rayverify audit --corpus notes.txt",
         one("notes.txt", "# nothing here\n\n   \n"), 2, "notes.txt: empty corpus"},
        {"binary garbage (an ELF header)", "rayverify audit --corpus elf.txt",
         one("elf.txt", bytes("\x7f" "ELF\x02\x01\x01\0\0\0\n", 11)), 2, "elf.txt:1: line contains a NUL byte"},
        {"UTF-16 text", "rayverify audit --corpus wide.txt",
         one("wide.txt", bytes("\xff\xfeg\0o\0o\0d\0", 10)), 2, "wide.txt:1: line"},
        {"a byte order mark inside the file (two files concatenated; found by fuzzing)",
         "rayverify audit --corpus joined.txt", one("joined.txt", "\xEF\xBB\xBF" + good + "\xEF\xBB\xBF" + good), 2,
         "joined.txt:2: line contains a byte order mark"},
        {"Latin-1 bytes (not UTF-8)", "rayverify audit --corpus latin.txt",
         one("latin.txt", good + "caf\xe9 - 0 0 -5 0 0 1 0 0 0 1\n"), 2, "latin.txt:2: line is not valid UTF-8"},
        {"a 2 MB line without newline", "rayverify audit --corpus line.txt",
         one("line.txt", good + std::string(2 << 20, '7')), 2, "line.txt:2: line is longer than 1 MB"},
        {"a file over the 64 MiB limit (sparse, 64 MiB + 1 byte; 2 GB in the long test)",
         "rayverify audit --corpus large.txt", {}, 2, "large.txt: is 67108865 bytes, over the 64 MiB limit",
         [](const fs::path& dir) {
             std::ofstream(dir / "large.txt") << good;
             fs::resize_file(dir / "large.txt", rayverify::max_corpus_file_bytes + 1);
         }},
        // Paths.
        {"missing file", "rayverify audit --corpus nowhere.txt", {}, 2, "nowhere.txt: no such file"},
        {"a path through a file", "rayverify audit --corpus good.txt/x.txt", one("good.txt", good), 2,
         "good.txt/x.txt: no such file"},
        {"unreadable file (mode 000, as a user)", "rayverify audit --corpus locked.txt", one("locked.txt", good), 2,
         "locked.txt: cannot open: Permission denied",
         [](const fs::path& dir) { fs::permissions(dir / "locked.txt", fs::perms::none); }, true},
        {"a directory without .txt or .csv files", "rayverify audit --corpus dir", {}, 2, "dir: empty corpus",
         [](const fs::path& dir) { fs::create_directory(dir / "dir"); }},
        {"a named pipe", "rayverify audit --corpus pipe.txt", {}, 2, "pipe.txt: is not a regular file",
         [](const fs::path& dir) { ASSERT_EQ(mkfifo((dir / "pipe.txt").c_str(), 0600), 0); }},
        {"a device", "rayverify audit --corpus /dev/zero", {}, 2, "/dev/zero: is not a regular file"},
        // CSV.
        {"CSV header without a required column", "rayverify audit --corpus norad.csv",
         one("norad.csv", "id,ox,oy,oz,dx,dy,dz,cx,cy,cz\ngood,0,0,-5,0,0,1,0,0,0\n"), 2,
         "norad.csv:1: field 'r': required column is missing"},
        {"CSV column named twice", "rayverify audit --corpus twice.csv",
         one("twice.csv", "id,ox,oy,oz,dx,dy,dz,cx,cy,cz,r,OX\n"), 2, "twice.csv:1: field 'ox'"},
        {"CSV row with a cell missing", "rayverify audit --corpus short.csv",
         one("short.csv", csv_header + "good,0,0,-5,0,0,1,0,0,0,1\ncut,0,0,-5,0,0,1,0,0,0\n"), 2,
         "short.csv:3: found 10 fields"},
        {"CSV row with text in a cell", "rayverify audit --corpus text.csv",
         one("text.csv", csv_header + "good,0,0,-5,0,0,1,0,0,0,1\nword,0,0,-5,0,0,1,zero,0,0,1\n"), 2,
         "text.csv:3: field 'cx'"},
        {"CSV with a header and no rows", "rayverify audit --corpus header.csv", one("header.csv", csv_header), 2,
         "header.csv: empty corpus"},
        // Command line.
        {"unknown variant", "rayverify audit --corpus good.txt --variant nosuch", one("good.txt", good), 2,
         "field '--variant': unknown variant 'nosuch'"},
        {"unknown precision", "rayverify audit --precision quad", {}, 2, "--precision"},
        {"unknown option", "rayverify audit --bogus", {}, 2, "--bogus"},
        {"negative count", "rayverify corpus generate --family uniform --count -1", {}, 2, "--count"},
        {"count beyond the bound", "rayverify corpus generate --family uniform --count 99999999999999999999", {},
         2, "--count"},
        {"unknown family", "rayverify corpus generate --family nosuch", {}, 2, "unknown generator family"},
        {"explain with 3 numbers", "rayverify explain 1 2 3", {}, 2, "field 'case'"},
        {"explain with text for a number", "rayverify explain 0 0 -5 0 0 1 0 0 0 one", {}, 2, "field 'r'"},
        {"explain an id not in the corpus", "rayverify explain --case nosuch --corpus good.txt",
         one("good.txt", good), 2, "field '--case'"},
        // Outputs.
        {"`--per-case` names a directory", "rayverify audit --corpus good.txt --per-case out",
         one("good.txt", good), 2, "out: field '--per-case': is a directory",
         [](const fs::path& dir) { fs::create_directory(dir / "out"); }},
        {"`--per-case` in a missing directory", "rayverify audit --corpus good.txt --per-case no/cases.jsonl",
         one("good.txt", good), 2, "no/cases.jsonl: field '--per-case': cannot write into directory 'no'"},
        {"`--report` names a file", "rayverify audit --corpus good.txt --report notes.md",
         {{"good.txt", good}, {"notes.md", "# notes\n"}}, 2,
         "notes.md: field '--report': cannot create directory: 'notes.md' exists and is not a directory"},
        {"`--report` holds a directory named report.json", "rayverify audit --corpus good.txt --report rep",
         one("good.txt", good), 2, "rep/report.json: field '--report': is a directory",
         [](const fs::path& dir) { fs::create_directories(dir / "rep" / "report.json"); }},
        {"`corpus generate -o` names a directory", "rayverify corpus generate --family uniform -o out", {}, 2,
         "out: field '-o': is a directory, expected a file to write",
         [](const fs::path& dir) { fs::create_directory(dir / "out"); }},
        {"`corpus generate -o` in a missing directory", "rayverify corpus generate --family uniform -o no/c.txt",
         {}, 2, "no/c.txt: field '-o': cannot write into directory 'no'"},
        // Outputs that would destroy an input or another output: refused before any work.
        {"`--per-case` is the corpus file", "rayverify audit --corpus self.txt --per-case self.txt",
         one("self.txt", good), 2,
         "self.txt: field '--per-case': is the same file as the input self.txt (--corpus)"},
        {"`--summary-md` is the corpus file", "rayverify audit --corpus self.txt --summary-md self.txt",
         one("self.txt", good), 2,
         "self.txt: field '--summary-md': is the same file as the input self.txt (--corpus)"},
        {"`--per-case` is the corpus file by another name (a hard link)",
         "rayverify audit --corpus self.txt --per-case link.txt", one("self.txt", good), 2,
         "link.txt: field '--per-case': is the same file as the input self.txt (--corpus)",
         [](const fs::path& dir) { fs::create_hard_link(dir / "self.txt", dir / "link.txt"); }},
        {"`gate --junit` is the baseline", "rayverify gate --baseline b.txt --corpus good.txt --junit b.txt",
         {{"b.txt", good_baseline}, {"good.txt", good}}, 2,
         "b.txt: field '--junit': is the same file as the input b.txt (--baseline)"},
        {"`--report` is a corpus directory (its summary.txt would be read as a corpus file)",
         "rayverify audit --corpus cases --report cases", {}, 2,
         "cases: field '--report': is the corpus directory cases (--corpus)",
         [](const fs::path& dir) {
             fs::create_directory(dir / "cases");
             std::ofstream(dir / "cases" / "good.txt") << good;
         }},
        {"`--per-case` named *.txt in a corpus directory", "rayverify audit --corpus cases --per-case cases/out.txt",
         {}, 2, "cases/out.txt: field '--per-case': lies in the corpus directory cases (--corpus)",
         [](const fs::path& dir) {
             fs::create_directory(dir / "cases");
             std::ofstream(dir / "cases" / "good.txt") << good;
         }},
        {"two outputs name one file", "rayverify audit --corpus good.txt --report rep --per-case rep/summary.txt",
         one("good.txt", good), 2, "rep/summary.txt: field '--per-case': is named by another output of this command"},
        {"`--per-case` is a dangling symbolic link", "rayverify audit --corpus good.txt --per-case gone.jsonl",
         one("good.txt", good), 2, "gone.jsonl: field '--per-case': is a symbolic link to a missing file",
         [](const fs::path& dir) { fs::create_symlink("nowhere/x.jsonl", dir / "gone.jsonl"); }},
        {"`--report` directory in use by another run (its lock file)", "rayverify audit --corpus good.txt --report rep",
         one("good.txt", good), 2,
         "rep: field '--report': is in use by another rayverify run (pid 4242 on elsewhere, started "
         "2024-01-01T00:00:00Z: rayverify audit --report rep); wait for it to finish, or remove rep/.rayverify-lock",
         [](const fs::path& dir) {
             fs::create_directory(dir / "rep");
             std::ofstream(dir / "rep" / ".rayverify-lock") << "rayverify run in progress\npid 4242\nhost elsewhere\n"
                                                              "started 2024-01-01T00:00:00Z\n"
                                                              "command rayverify audit --report rep\n";
         }},
        {"`--shard` with `--per-case` outside the `--report` directory (merge reads only shard directories)",
         "rayverify audit --corpus good.txt --shard 1/2 --report s1 --per-case cases.jsonl", one("good.txt", good), 2,
         "cases.jsonl: field '--per-case': with --shard, the per-case file goes inside the --report directory"},
        // Scene files (corpus/scenes/README.md).
        {"scene: truncated JSON (cut after `\"radius\":`)", "rayverify audit --scene cut.json",
         one("cut.json", good_scene.substr(0, good_scene.find("\"radius\": 1") + 10)), 2,
         "cut.json:6: field 'spheres[0].radius': not valid JSON: syntax error"},
        {"scene: text in a number field (`\"radius\": \"one\"`)", "rayverify audit --scene word.json",
         one("word.json", scene_with("\"radius\": 1", "\"radius\": \"one\"")), 2,
         "word.json:6: field 'spheres[0].radius'"},
        {"scene: a number field holding `true`", "rayverify audit --scene bool.json",
         one("bool.json", scene_with("\"fov_degrees\": 45", "\"fov_degrees\": true")), 2,
         "bool.json:4: field 'camera.fov_degrees': must be a finite number"},
        {"scene: negative radius", "rayverify audit --scene neg.json",
         one("neg.json", scene_with("\"radius\": 1", "\"radius\": -1")), 2,
         "neg.json:6: field 'spheres[0].radius': must be a finite number ≥ 0 (got -1)"},
        {"scene: a required field missing (no `radius`)", "rayverify audit --scene norad.json",
         one("norad.json", scene_with(", \"radius\": 1", "")), 2,
         "norad.json:6: field 'spheres[0].radius': is required"},
        {"scene: `NaN` (not JSON)", "rayverify audit --scene nan.json",
         one("nan.json", scene_with("\"radius\": 1", "\"radius\": NaN")), 2, "nan.json:6: field 'spheres[0].radius': not valid JSON: syntax error"},
        {"scene: `\"nan\"` and `\"inf\"` as number strings", "rayverify audit --scene nanstr.json",
         one("nanstr.json", scene_with("\"radius\": 1", "\"radius\": \"nan\"")), 2,
         "nanstr.json:6: field 'spheres[0].radius': must be a finite number"},
        {"scene: a number beyond the double range (`1e999`; found by fuzzing)", "rayverify audit --scene e999.json",
         one("e999.json", scene_with("\"radius\": 1", "\"radius\": 1e999")), 2,
         "e999.json:6: field 'spheres[0].radius': number overflow parsing '1e999'"},
        {"scene: a float scene with a value beyond float (`1e300`)", "rayverify audit --scene float.json",
         one("float.json", edited(scene_with("\"double\"", "\"float\""), "[0, 0, 0], \"radius\"",
                                  "[0, 0, 1e300], \"radius\"")),
         2, "float.json:6: field 'spheres[0].centre': overflows the scene's precision"},
        {"scene: a camera too far out for its rays to stay finite (`1e308`)", "rayverify audit --scene far.json",
         one("far.json", scene_with("\"position\": [0, 0, 5]", "\"position\": [0, 0, 1e308]")), 2,
         "far.json:3: field 'camera.position': the camera reaches 1e+308 from the origin"},
        {"scene: an orthographic view too wide for its rays to stay finite", "rayverify audit --scene wide.json",
         one("wide.json", edited(scene_with("\"perspective\"", "\"orthographic\""), "\"fov_degrees\": 45",
                                 "\"view_height\": 1e308")),
         2, "wide.json:4: field 'camera.view_height': the ray of pixel (0, 0) starts at a point that reaches"},
        {"scene: `up` parallel to the view direction", "rayverify audit --scene up.json",
         one("up.json", scene_with("\"look_at\": [0, 0, 0],", "\"look_at\": [0, 0, 0], \"up\": [0, 0, 1e-300],")), 2,
         "up.json:3: field 'camera.up': must not be parallel to the view direction"},
        {"scene: zero resolution", "rayverify audit --scene res.json",
         one("res.json", scene_with("[2, 2]", "[0, 2]")), 2,
         "res.json:4: field 'camera.resolution[0]': must be an integer from 1 to 4096"},
        {"scene: unknown ray kind (`\"tertiary\"`)", "rayverify audit --scene kind.json",
         one("kind.json", scene_with("\"precision\"", "\"rays\": {\"tertiary\": {}},\n  \"precision\"")), 2,
         "kind.json:2: field 'rays.tertiary': unknown field"},
        {"scene: unknown query name (`\"first_hit\"`)", "rayverify audit --scene query.json",
         one("query.json",
             scene_with("\"precision\"", "\"rays\": {\"primary\": {\"query\": \"first_hit\"}},\n  \"precision\"")),
         2, "query.json:2: field 'rays.primary.query': must be one of"},
        {"scene: a misspelt field (`\"centre\"` as `\"center\"`)", "rayverify audit --scene center.json",
         one("center.json", scene_with("\"centre\"", "\"center\"")), 2,
         "center.json:6: field 'spheres[0].center': unknown field"},
        {"scene: a key given twice in one object", "rayverify audit --scene twice.json",
         one("twice.json", scene_with("\"radius\": 1", "\"radius\": 1, \"radius\": 2")), 2,
         "twice.json:6: field 'spheres[0].radius': the key \"radius\" is given twice in one object"},
        {"scene: two spheres with one name", "rayverify audit --scene names.json",
         one("names.json", scene_with("\"radius\": 1}",
                                      "\"radius\": 1},\n    {\"name\": \"ball\", "
                                      "\"centre\": [0, 0, -4], \"radius\": 1}")),
         2, "names.json:7: field 'spheres[1].name': names another sphere too"},
        {"scene: shadow rays without lights", "rayverify audit --scene dark.json",
         one("dark.json", scene_with("\"precision\"", "\"rays\": {\"shadow\": {}},\n  \"precision\"")), 2,
         "dark.json:2: field 'rays.shadow': shadow rays need at least one entry in \"lights\""},
        {"scene: a JSON array instead of an object", "rayverify audit --scene array.json",
         one("array.json", "[1, 2]\n"), 2, "array.json:1: a scene is a JSON object"},
        {"scene: JSON nested 100000 levels deep", "rayverify audit --scene deep.json",
         one("deep.json", std::string(100000, '[') + std::string(100000, ']')), 2,
         "deep.json:1: nested more than 64 levels deep"},
        {"scene: empty file", "rayverify audit --scene empty.json", one("empty.json", ""), 2,
         "empty.json: empty file"},
        {"scene: binary garbage (an ELF header)", "rayverify audit --scene elf.json",
         one("elf.json", bytes("\x7f" "ELF\x02\x01\x01\0\0\0\n", 11)), 2, "elf.json:1: not valid JSON"},
        {"scene: a file over the 16 MiB limit (sparse)", "rayverify audit --scene large.json", {}, 2,
         "large.json: is 16777217 bytes, over the 16 MiB limit",
         [](const fs::path& dir) {
             std::ofstream(dir / "large.json") << good_scene;
             fs::resize_file(dir / "large.json", (std::uintmax_t{16} << 20) + 1);
         }},
        {"scene: missing file", "rayverify audit --scene nowhere.json", {}, 2, "nowhere.json: no such file"},
        {"scene: unreadable file (mode 000, as a user)", "rayverify audit --scene locked.json",
         one("locked.json", good_scene), 2, "locked.json: cannot open: Permission denied",
         [](const fs::path& dir) { fs::permissions(dir / "locked.json", fs::perms::none); }, true},
        {"scene: a device", "rayverify audit --scene /dev/zero", {}, 2, "/dev/zero: is not a regular file"},
        {"scene: a directory", "rayverify audit --scene dir", {}, 2, "dir: is a directory",
         [](const fs::path& dir) { fs::create_directory(dir / "dir"); }},
        // Gate baselines (src/compare/gate.h).
        {"baseline: a line of 3 fields", "rayverify gate --baseline short.txt --corpus good.txt",
         {{"short.txt", baseline_head + "naive/double all cases\n"}, {"good.txt", good}}, 2,
         "short.txt:2: field 'entry': expected 'TARGET FAMILY FIGURE VALUE', got 3 fields"},
        {"baseline: unknown figure name", "rayverify gate --baseline figure.txt --corpus good.txt",
         {{"figure.txt", good_baseline + "naive/double all false_mis 0\n"}, {"good.txt", good}}, 2,
         "figure.txt:3: field 'figure': unknown figure 'false_mis'"},
        {"baseline: text where a number goes", "rayverify gate --baseline word.txt --corpus good.txt",
         {{"word.txt", baseline_head + "naive/double all cases one\n"}, {"good.txt", good}}, 2,
         "word.txt:2: field 'value': 'one' is not a number"},
        {"baseline: `nan` as a value", "rayverify gate --baseline nan.txt --corpus good.txt",
         {{"nan.txt", good_baseline + "naive/double all near_ulp_max nan\n"}, {"good.txt", good}}, 2,
         "nan.txt:3: field 'value': 'nan' is not a number"},
        {"baseline: a negative count", "rayverify gate --baseline neg.txt --corpus good.txt",
         {{"neg.txt", good_baseline + "naive/double all false_miss -1\n"}, {"good.txt", good}}, 2,
         "neg.txt:3: field 'value': '-1' is not a number ≥ 0"},
        {"baseline: a value beyond the double range (`1e999`)", "rayverify gate --baseline huge.txt --corpus good.txt",
         {{"huge.txt", good_baseline + "naive/double all near_ulp_max 1e999\n"}, {"good.txt", good}}, 2,
         "huge.txt:3: field 'value': '1e999' is not a number"},
        {"baseline: a duplicate line", "rayverify gate --baseline dup.txt --corpus good.txt",
         {{"dup.txt", good_baseline + "naive/double all cases 1\n"}, {"good.txt", good}}, 2,
         "dup.txt:3: field 'entry': duplicate entry for naive/double all cases"},
        {"baseline: a target without its precision", "rayverify gate --baseline target.txt --corpus good.txt",
         {{"target.txt", baseline_head + "naive all cases 1\n"}, {"good.txt", good}}, 2,
         "target.txt:2: field 'target': 'naive' is not a target like naive/float"},
        {"baseline: unknown policy key", "rayverify gate --baseline policy.txt --corpus good.txt",
         {{"policy.txt", baseline_head + "policy default slack 2\n"}, {"good.txt", good}}, 2,
         "policy.txt:2: field 'policy': unknown policy key 'slack'"},
        {"baseline: `ulp_slack` below 1", "rayverify gate --baseline slack.txt --corpus good.txt",
         {{"slack.txt", baseline_head + "policy default ulp_slack 0.5\n"}, {"good.txt", good}}, 2,
         "slack.txt:2: field 'value': ulp_slack is a factor ≥ 1"},
        {"baseline: a later format version", "rayverify gate --baseline v2.txt --corpus good.txt",
         {{"v2.txt", "rayverify-baseline 2\n"}, {"good.txt", good}}, 2,
         "v2.txt:1: field 'format': baseline format version '2'"},
        {"baseline: a corpus given as the baseline", "rayverify gate --baseline good.txt --corpus good.txt",
         one("good.txt", good), 2, "good.txt:1: field 'format': the first entry must be 'rayverify-baseline 1'"},
        {"baseline: empty file", "rayverify gate --baseline empty.txt --corpus good.txt",
         {{"empty.txt", ""}, {"good.txt", good}}, 2, "empty.txt: field 'format': empty baseline"},
        {"baseline: binary garbage (an ELF header)", "rayverify gate --baseline elf.txt --corpus good.txt",
         {{"elf.txt", bytes("\x7f" "ELF\x02\x01\x01\0\0\0\n", 11)}, {"good.txt", good}}, 2,
         "elf.txt:1: line contains a NUL byte"},
        {"baseline: a carriage return inside a line (a line `--update` could not write back as it was read)",
         "rayverify gate --baseline cr.txt --corpus good.txt",
         {{"cr.txt", "rayverify-baseline 1\r\nlibrary embree3 kernel\r avx2\r\n"}, {"good.txt", good}}, 2,
         "cr.txt:2: line contains a carriage return not followed by a newline"},
        {"baseline: missing file", "rayverify gate --baseline nowhere.txt --corpus good.txt", one("good.txt", good), 2,
         "nowhere.txt: field '--baseline': no such baseline"},
        {"baseline: unreadable file (mode 000, as a user)", "rayverify gate --baseline locked.txt --corpus good.txt",
         {{"locked.txt", good_baseline}, {"good.txt", good}}, 2, "locked.txt: field '--baseline': cannot open",
         [](const fs::path& dir) { fs::permissions(dir / "locked.txt", fs::perms::none); }, true},
        {"baseline: a directory", "rayverify gate --baseline dir --corpus good.txt", one("good.txt", good), 2,
         "dir: ", [](const fs::path& dir) { fs::create_directory(dir / "dir"); }},
        {"baseline: `inf` as a count (`false_miss inf`, which no count could fail)",
         "rayverify gate --baseline inf.txt --corpus good.txt",
         {{"inf.txt", good_baseline + "naive/double all false_miss inf\n"}, {"good.txt", good}}, 2,
         "inf.txt:3: field 'value': false_miss is a whole number of cases, got 'inf'"},
        {"baseline: a fractional count (`0.5`)", "rayverify gate --baseline half.txt --corpus good.txt",
         {{"half.txt", good_baseline + "naive/double all false_hit 0.5\n"}, {"good.txt", good}}, 2,
         "half.txt:3: field 'value': false_hit is a whole number of cases, got '0.5'"},
        {"baseline: `count_slack inf` (it would disable the gate)", "rayverify gate --baseline slackinf.txt --corpus good.txt",
         {{"slackinf.txt", baseline_head + "policy default count_slack inf\n"}, {"good.txt", good}}, 2,
         "slackinf.txt:2: field 'value': count_slack is a whole number of cases, got 'inf'"},
        {"baseline: a policy given twice", "rayverify gate --baseline twice.txt --corpus good.txt",
         {{"twice.txt", baseline_head + "policy default ulp_slack 2\npolicy default ulp_slack 4\n"}, {"good.txt", good}},
         2, "twice.txt:3: field 'policy': duplicate policy line for default ulp_slack"},
        {"baseline: an unknown precision (`naive/quad`)", "rayverify gate --baseline quad.txt --corpus good.txt",
         {{"quad.txt", baseline_head + "naive/quad all cases 1\n"}, {"good.txt", good}}, 2,
         "quad.txt:2: field 'target': 'naive/quad': unknown precision 'quad' (float or double)"},
        // Stricter parsing of corpus files.
        {"hex float exponent with two signs (`0x1p+-5`)", "rayverify audit --corpus signs.txt",
         one("signs.txt", good + "signs - 0x1p+-5 0 -5 0 0 1 0 0 0 1\n"), 2, "signs.txt:2: field 'ox'"},
        {"decimal exponent with two signs (`1e+-5`)", "rayverify audit --corpus esigns.txt",
         one("esigns.txt", good + "esigns - 1e+-5 0 -5 0 0 1 0 0 0 1\n"), 2, "esigns.txt:2: field 'ox'"},
        {"CR-only line endings (old Mac files)", "rayverify audit --corpus mac.txt", one("mac.txt", "a - 0 0 -5 0 0 1 0 0 0 1\rb - 0 0 -5 0 0 1 0 0 0 1\r"), 2,
         "mac.txt:1: line contains a carriage return not followed by a newline"},
        {"CSV: a quoted cell that never closes", "rayverify audit --corpus open.csv",
         one("open.csv", csv_header + "\"good,0,0,-5,0,0,1,0,0,0,1\n"), 2,
         "open.csv:2: cell 1 opens a double quote that the line never closes"},
        {"CSV: a stray double quote inside a cell", "rayverify audit --corpus stray.csv",
         one("stray.csv", csv_header + "go\"od,0,0,-5,0,0,1,0,0,0,1\n"), 2,
         "stray.csv:2: cell 1 holds a double quote without being quoted"},
        {"CSV: text after a quoted cell", "rayverify audit --corpus after.csv",
         one("after.csv", csv_header + "\"go\"od,0,0,-5,0,0,1,0,0,0,1\n"), 2,
         "after.csv:2: cell 1 has text after its closing double quote"},
        {"a corpus directory holding a dangling link named *.txt", "rayverify audit --corpus cases", {}, 2,
         "cases/gone.txt: is a symbolic link to a missing file",
         [](const fs::path& dir) {
             fs::create_directory(dir / "cases");
             std::ofstream(dir / "cases" / "good.txt") << good;
             fs::create_symlink("nowhere.txt", dir / "cases" / "gone.txt");
         }},
        {"a corpus directory holding a named pipe named *.txt", "rayverify audit --corpus cases", {}, 2,
         "cases/pipe.txt: is not a regular file",
         [](const fs::path& dir) {
             fs::create_directory(dir / "cases");
             std::ofstream(dir / "cases" / "good.txt") << good;
             ASSERT_EQ(mkfifo((dir / "cases" / "pipe.txt").c_str(), 0600), 0);
         }},
        // Numeric options: checked as written, never wrapped, saturated or compared with NaN.
        {"`--plugin-timeout nan`", "rayverify audit --corpus good.txt --isolate --plugin-timeout nan",
         one("good.txt", good), 2, "--plugin-timeout: 'nan' is not a number ≥ 0.001 and ≤ 86400"},
        {"`hunt --evaluations -5` (would wrap to 2^64 − 5)", "rayverify hunt --variant naive --evaluations -5 -o f.txt",
         {}, 2, "--evaluations: '-5' is not a whole number ≥ 0 and < 2^64"},
        {"`hunt --seconds inf`", "rayverify hunt --variant naive --seconds inf -o f.txt", {}, 2,
         "--seconds: 'inf' is not a number ≥ 0 and ≤ 1000000000"},
        {"`bench --min-time 0` (Google Benchmark would abort)", "rayverify bench --min-time 0", {}, 2,
         "--min-time: '0' is not a number > 0 and ≤ 3600"},
        {"`recommend --min-time nan`", "rayverify recommend --scene s.json --min-time nan", {}, 2,
         "--min-time: 'nan' is not a number > 0 and ≤ 3600"},
        {"a negative seed", "rayverify corpus generate --family uniform --seed -1", {}, 2,
         "--seed: '-1' is not a whole number ≥ 0 and < 2^64"},
        {"a seed of 2^64 (would saturate to 2^64 − 1)",
         "rayverify corpus generate --family uniform --seed 18446744073709551616", {}, 2,
         "--seed: '18446744073709551616' is not a whole number ≥ 0 and < 2^64"},
        {"`bench --sweep -1`", "rayverify bench --sweep -1", {}, 2, "--sweep: '-1' is not a whole number ≥ 0 and ≤ 100000000"},
        // Plugins that misbehave in this process (the test fixture's modes; with --isolate the same is caught in
        // a child process).
        {"a plugin that calls `exit(0)` in a call", "rayverify audit --plugin ./modal.so --corpus good.txt --threads 1",
         one("good.txt", good), 2,
         "./modal.so: field '--plugin': plugin 'modal' called exit() on case good (good.txt:1), in its float function",
         plugin_copy(modal_plugin, "modal.so"), false, "FIXTURE_MODE=call_exit"},
        {"a plugin that calls `exit(0)` in `describe()`", "rayverify audit --plugin ./modal.so --corpus good.txt --threads 1",
         one("good.txt", good), 2, "./modal.so: field '--plugin': called exit() while loading it",
         plugin_copy(modal_plugin, "modal.so"), false, "FIXTURE_MODE=describe_exit"},
        {"a plugin that calls `exit(0)` in a constructor", "rayverify audit --plugin ./modal.so --corpus good.txt --threads 1",
         one("good.txt", good), 2, "./modal.so: field '--plugin': called exit() while loading it",
         plugin_copy(modal_plugin, "modal.so"), false, "FIXTURE_MODE=ctor_exit"},
        {"a plugin whose constructor crashes", "rayverify audit --plugin ./modal.so --corpus good.txt --threads 1",
         one("good.txt", good), 2, "./modal.so: field '--plugin': crashed (SIGSEGV) while loading it",
         plugin_copy(modal_plugin, "modal.so"), false, "FIXTURE_MODE=ctor_crash"},
        {"a truncated plugin library (its first 4096 bytes: SIGBUS in dlopen)",
         "rayverify audit --plugin ./cut.so --corpus good.txt", one("good.txt", good), 2,
         "./cut.so: field '--plugin': crashed (SIGBUS) while loading it", plugin_copy(garbage_plugin, "cut.so", 4096)},
        {"a plugin that writes `roots[2]`", "rayverify audit --plugin ./modal.so --corpus good.txt --threads 1",
         one("good.txt", good), 2,
         "./modal.so: field '--plugin': plugin 'modal' wrote outside its roots[2] buffer on case good (good.txt:1)",
         plugin_copy(modal_plugin, "modal.so"), false, "FIXTURE_MODE=overrun"},
        {"a plugin that writes `roots[-1]`", "rayverify audit --plugin ./modal.so --corpus good.txt --threads 1",
         one("good.txt", good), 2, "plugin 'modal' wrote outside its roots[2] buffer on case good (good.txt:1)",
         plugin_copy(modal_plugin, "modal.so"), false, "FIXTURE_MODE=underrun"},
        {"a plugin named with a terminal escape sequence", "rayverify audit --plugin ./modal.so --corpus good.txt --threads 1",
         one("good.txt", good), 2,
         "./modal.so: field '--plugin': the plugin's name '\\x1B[31mred' must be one token without '/', '#' or "
         "control characters",
         plugin_copy(modal_plugin, "modal.so"), false, "FIXTURE_MODE=escape_name"},
        // What the user typed reaches the terminal escaped: no newline of theirs starts a line, no
        // escape sequence colours it (one function: escaped_control, for every error).
        {"a corpus id holding an escape sequence", "rayverify audit --corpus esc.txt",
         one("esc.txt", good + "bad\x1b[31m - 0 0 -5 0 0 1 0 0 0 1\n"), 2,
         "esc.txt:2: field 'id': expected a token without spaces or control characters, got 'bad\\x1B[31m'"},
        {"`--variant` holding a newline and a line of its own",
         "rayverify audit --variant \"$(printf 'naive\\nall checks passed')\"", {}, 2,
         "field '--variant': unknown variant 'naive\\x0Aall checks passed'"},
        {"`--precision` holding an escape sequence", "rayverify audit --precision \"$(printf '\\033[31mfloat')\"", {},
         2, "--precision: \\x1B[31mfloat not in {float,double}"},
        // The floating-point environment (core/fp_environment.h): what a library sets at load is the
        // environment its calls run in, named; what a call changes is undone after it, with a warning.
        {"a plugin that sets FTZ+DAZ when it loads (as a library linked with `-ffast-math` does)",
         "rayverify audit --plugin ./hostile.so --corpus good.txt", one("good.txt", good), 0,
         "fp environment: fp_hostile runs in FTZ+DAZ, set when the library loaded (what GCC's crtfastmath.o sets: "
         "linked with -ffast-math?); rayverify's own arithmetic in the IEEE default",
         plugin_copy(fp_hostile_plugin, "hostile.so"), false, "FIXTURE_FP_MODE=load_ftz_daz", "fp environment:"},
        {"a plugin linked with `-ffast-math` (GCC's crtfastmath.o sets FTZ+DAZ)",
         "rayverify audit --plugin ./fastmath.so --corpus good.txt", one("good.txt", good), 0,
         "fp environment: fp_fast_math_link runs in FTZ+DAZ, set when the library loaded",
         plugin_copy(fp_fast_math_plugin, "fastmath.so"), false, "", "fp environment:"},
        {"a plugin that sets rounding upward when it loads", "rayverify audit --plugin ./hostile.so --corpus good.txt",
         one("good.txt", good), 0, "fp environment: fp_hostile runs in rounding upward, set when the library loaded",
         plugin_copy(fp_hostile_plugin, "hostile.so"), false, "FIXTURE_FP_MODE=load_upward", "fp environment:"},
        {"a plugin that leaves the x87 unit at single precision when it loads",
         "rayverify audit --plugin ./hostile.so --corpus good.txt", one("good.txt", good), 0,
         "fp environment: fp_hostile runs in x87 precision single, set when the library loaded",
         plugin_copy(fp_hostile_plugin, "hostile.so"), false, "FIXTURE_FP_MODE=load_x87", "fp environment:"},
        {"a plugin that traps FE_INVALID from its load, then makes a NaN",
         "rayverify audit --plugin ./hostile.so --corpus nan.txt --precision double",
         one("nan.txt", "nan - 0 0 -5 0 0 1e300 0 0 0 1\n"), 2,
         "./hostile.so: field '--plugin': plugin 'fp_hostile' crashed (SIGFPE) on case nan (nan.txt:1)",
         plugin_copy(fp_hostile_plugin, "hostile.so"), false, "FIXTURE_FP_MODE=load_unmask_invalid"},
        {"a plugin that sets FTZ+DAZ in every batch", "rayverify audit --plugin ./hostile.so --corpus good.txt",
         one("good.txt", good), 0,
         "warning: target 'fp_hostile' changed the floating-point environment in a call, to FTZ+DAZ (it was given "
         "the IEEE default)",
         plugin_copy(fp_hostile_plugin, "hostile.so"), false, "FIXTURE_FP_MODE=batch_ftz_daz"},
        {"a plugin that rounds toward zero after every batch", "rayverify audit --plugin ./hostile.so --corpus good.txt",
         one("good.txt", good), 0, "changed the floating-point environment in a call, to rounding toward zero",
         plugin_copy(fp_hostile_plugin, "hostile.so"), false, "FIXTURE_FP_MODE=batch_toward_zero"},
        {"a plugin that unmasks FE_INVALID, FE_DIVBYZERO and FE_OVERFLOW after every batch",
         "rayverify audit --plugin ./hostile.so --corpus good.txt", one("good.txt", good), 0,
         "changed the floating-point environment in a call, to FE_INVALID trapped, FE_DIVBYZERO trapped, "
         "FE_OVERFLOW trapped",
         plugin_copy(fp_hostile_plugin, "hostile.so"), false, "FIXTURE_FP_MODE=batch_unmask"},
        {"a plugin that leaves the x87 unit at single precision after every batch",
         "rayverify audit --plugin ./hostile.so --corpus good.txt", one("good.txt", good), 0,
         "changed the floating-point environment in a call, to x87 precision single",
         plugin_copy(fp_hostile_plugin, "hostile.so"), false, "FIXTURE_FP_MODE=batch_x87"},
        {"`--fp-env` naming no environment", "rayverify audit --variant naive --fp-env fast", {}, 2,
         "field '--fp-env': 'fast' is not an environment"},
        {"`--fp-env` naming no target of the run", "rayverify audit --variant naive --fp-env robust=ftz+daz", {}, 2,
         "field '--fp-env': 'robust=ftz+daz' names no target of this run"},
        {"`hunt` a plugin whose every answer is NaN: a finding, not \"no agreeing answer\"",
         "rayverify hunt --plugin ./modal.so --seconds 0 --evaluations 20 -o finds.txt", {}, 1,
         "20 of 20 evaluations disagreed with the exact answer; the first (non_finite) at evaluation 1",
         plugin_copy(modal_plugin, "modal.so"), false, "FIXTURE_MODE=nan", "20 of 20"},
        {"`explain --plugin LIB \"<corpus line>\"`: the line is the case, not a second library",
         "rayverify explain --plugin ./modal.so \"good - 0 0 -5 0 0 1 0 0 0 1 - 0x1p+3\" --precision double", {}, 0,
         "corpus line: good - 0x0p+0 0x0p+0 -0x1.4p+2 0x0p+0 0x0p+0 0x1p+0 0x0p+0 0x0p+0 0x0p+0 0x1p+0 - 0x1p+3",
         plugin_copy(modal_plugin, "modal.so"), false, "", "corpus line:"},
        // Shard states given to merge (each a one-case shard, then edited).
        {"merge: a negative verdict count", "rayverify merge --report out s1", {}, 2,
         "s1/shard.json: field 'state.audit.overall[0].verdicts[1] (false_miss)': is -1, expected a whole number ≥ 0",
         edited_shard([](nlohmann::ordered_json& j) { j["state"]["audit"]["overall"][0]["verdicts"][1] = -1; })},
        {"merge: verdict counts that do not add up to the cases", "rayverify merge --report out s1", {}, 2,
         "s1/shard.json: field 'state.audit.overall[0].verdicts': add up to 2, but the target has 1 cases",
         edited_shard([](nlohmann::ordered_json& j) { j["state"]["audit"]["overall"][0]["verdicts"][1] = 1; })},
        {"merge: disagreement causes that do not add up to the disagreements", "rayverify merge --report out s1", {}, 2,
         "s1/shard.json: field 'state.audit.overall[0].causes': add up to 1, but the target has 0 disagreements",
         edited_shard([](nlohmann::ordered_json& j) { j["state"]["audit"]["overall"][0]["causes"][0] = 1; })},
        {"merge: a case to open of no known kind", "rayverify merge --report out s1", {}, 2,
         "s1/shard.json: field 'state.cases_to_open[0].kind': 'nearest' is not first, worst or farthest",
         edited_shard([](nlohmann::ordered_json& j) {
             j["state"]["cases_to_open"] = nlohmann::ordered_json::array({{{"target", 0}, {"kind", "nearest"}}});
         })},
        {"merge: a contract that is not a contract", "rayverify merge --report out s1", {}, 2,
         "s1/shard.json: field 'targets[0].contract.spec': 'query=teleport'",
         edited_shard([](nlohmann::ordered_json& j) { j["targets"][0]["contract"]["spec"] = "query=teleport"; })},
        {"merge: a `nan` maximum", "rayverify merge --report out s1", {}, 2,
         "s1/shard.json: field 'state.audit.overall[0].near_root_ulp.max': is nan, expected an error ≥ 0 (never NaN)",
         edited_shard([](nlohmann::ordered_json& j) { j["state"]["audit"]["overall"][0]["near_root_ulp"]["max"] = "nan"; })},
        {"merge: a histogram bucket index of 2^62", "rayverify merge --report out s1", {}, 2,
         "s1/shard.json: field 'state.audit.overall[0].near_root_ulp.buckets (key 4611686018427387904)': is beyond the "
         "last bucket",
         edited_shard([](nlohmann::ordered_json& j) {
             j["state"]["audit"]["overall"][0]["near_root_ulp"]["buckets"] = "4611686018427387904:1";
         })},
        {"merge: a plotted case's verdict that is no verdict", "rayverify merge --report out s1", {}, 2,
         "s1/shard.json: field 'state.case_points[0].verdict[0]': 'teleported' is not a verdict",
         edited_shard([](nlohmann::ordered_json& j) { j["state"]["case_points"][0]["verdict"][0] = "teleported"; })},
        {"merge: a plotted case's near-root error that is no number", "rayverify merge --report out s1", {}, 2,
         "s1/shard.json: field 'state.case_points[0].near_ulp[0]': is \"0x1p+0\", expected a number, \"inf\", "
         "\"-inf\", \"nan\" or null",
         edited_shard([](nlohmann::ordered_json& j) { j["state"]["case_points"][0]["near_ulp"][0] = "0x1p+0"; })},
        {"merge: a per-case path outside the shard directory (`/etc/hostname`)",
         "rayverify merge --report out --per-case out.jsonl s1", {}, 2,
         "s1/shard.json: field 'per_case_file': '/etc/hostname' is not a path inside the shard directory",
         edited_shard([](nlohmann::ordered_json& j) { j["per_case_file"] = "/etc/hostname"; })},
        {"merge: into a shard's own directory", "rayverify merge --report s1 s1", {}, 2,
         "s1: field '-o': is the same directory as the input s1 (a shard directory)",
         edited_shard([](nlohmann::ordered_json&) {})},
        // Inputs that are not corpus files: results files and companions, shard contents, hunt outputs.
        {"audit: `--per-case` onto the `--results` file",
         "rayverify audit --corpus good.txt --results ans.csv --contract query=line_roots --name mine --per-case ans.csv",
         {{"good.txt", good}, {"ans.csv", good_answers}}, 2,
         "ans.csv: field '--per-case': is the same file as the input ans.csv (--results)"},
        {"audit: `--per-case` through a symbolic link to the `--results` file",
         "rayverify audit --corpus good.txt --results ans.csv --contract query=line_roots --name mine --per-case "
         "link.jsonl",
         {{"good.txt", good}, {"ans.csv", good_answers}}, 2,
         "link.jsonl: field '--per-case': is the same file as the input ans.csv (--results)",
         [](const fs::path& dir) { fs::create_symlink("ans.csv", dir / "link.jsonl"); }},
        {"audit: `--report DIR` whose report.json is the `--results` npy's companion",
         "rayverify audit --corpus good.txt --results report.npy --contract query=line_roots --name mine --report .",
         {{"good.txt", good}, {"report.npy", answers_npy({{2, 4, 6}})}, {"report.json", answers_companion()}}, 2,
         "is the same file as the input report.json (--results, its JSON companion)"},
        {"gate: `--junit` onto the `--results` file",
         "rayverify gate --corpus good.txt --results ans.csv --contract query=line_roots --name mine --baseline b.txt "
         "--junit ans.csv",
         {{"good.txt", good}, {"ans.csv", good_answers}, {"b.txt", baseline_head + "mine/double all cases 1\n"}}, 2,
         "ans.csv: field '--junit': is the same file as the input ans.csv (--results)"},
        {"merge: `--per-case` onto a shard's own per-case file",
         "rayverify merge --report out --per-case s1/cases.jsonl s1", {}, 2,
         "s1/cases.jsonl: field '--per-case': is the same file as the input s1/cases.jsonl (a shard's per-case file)",
         edited_shard([](nlohmann::ordered_json&) {})},
        {"merge: `-o` onto one of the hunt outputs it merges", "rayverify merge -o h1.txt h1.txt h2.txt", {}, 2,
         "h1.txt: field '-o': is the same file as the input h1.txt (a hunt output)",
         [](const fs::path& dir) {
             for (int k : {1, 2})
                 setup_run(dir, fmt::format("hunt --variant naive --seconds 0 --evaluations 4 --shard {}/2 -o h{}.txt",
                                            k, k));
         }},
        // JSON in results files, companions and a program's answers.
        {"results JSON lines: a number beyond double range (`1e400`)",
         "rayverify audit --corpus good.txt --results ans.jsonl --contract query=line_roots --name mine",
         {{"good.txt", good}, {"ans.jsonl", answers_jsonl("{\"id\":\"good\",\"count\":2,\"t0\":1e400,\"t1\":6}\n")}}, 2,
         "ans.jsonl:2: field 't0': number overflow parsing '1e400'"},
        {"results JSON lines: a key given twice",
         "rayverify audit --corpus good.txt --results ans.jsonl --contract query=line_roots --name mine",
         {{"good.txt", good},
          {"ans.jsonl", answers_jsonl("{\"id\":\"good\",\"count\":2,\"t0\":4,\"t0\":5,\"t1\":6}\n")}}, 2,
         "ans.jsonl:2: field 't0': the key \"t0\" is given twice in one object"},
        {"npy companion: a number beyond double range (`1e400`)",
         "rayverify audit --corpus good.txt --results ans.npy --contract query=line_roots --name mine",
         {{"good.txt", good}, {"ans.npy", answers_npy({{2, 4, 6}})}, {"ans.json", answers_companion(",\"note\":1e400")}},
         2, "ans.json:1: field 'note': number overflow parsing '1e400'"},
        {"`hunt --command`: an answer beyond double range (`1e400`)",
         "rayverify hunt --command 'python3 big.py' --contract query=line_roots --name prog --seconds 0 "
         "--evaluations 1 -o finds.txt",
         {{"big.py", edited(answering_program("''", "''"), "json.dumps({'id': i, 'count': 0})",
                                  "json.dumps({'id': i, 'count': 0})[:-1] + ', \"t0\": 1e400}'")}}, 2,
         "number overflow parsing '1e400'"},
        // Results files that are not files, or larger than their input can need.
        {"`--results` a FIFO (would block until a writer comes)",
         "rayverify audit --corpus good.txt --results ans.csv --contract query=line_roots --name mine",
         {{"good.txt", good}}, 2, "ans.csv: field '--results': is not a regular file",
         [](const fs::path& dir) { ASSERT_EQ(::mkfifo((dir / "ans.csv").c_str(), 0600), 0); }},
        {"`--results` a 300 MB (sparse) npy for one case",
         "rayverify audit --corpus good.txt --results ans.npy --contract query=line_roots --name mine",
         {{"good.txt", good}, {"ans.json", answers_companion()}}, 2,
         "ans.npy: field '--results': is 300000000 bytes, more than answers to the input's cases can take",
         [](const fs::path& dir) {
             std::ofstream(dir / "ans.npy", std::ios::binary) << answers_npy({{2, 4, 6}});
             fs::resize_file(dir / "ans.npy", 300000000);
         }},
        {"results: reading stops at the first answer to no case (line 4), before the bad line 5",
         "rayverify audit --corpus good.txt --results ans.csv --contract query=line_roots --name mine",
         {{"good.txt", good}, {"ans.csv", answers_csv("good,2,4,6\nother,0,,\nbad,one,,\n")}}, 2,
         "ans.csv:4: field 'id': answer for 'other', which is not a case of this input"},
        {"npy: more rows than the input has cases",
         "rayverify audit --corpus good.txt --results ans.npy --contract query=line_roots --name mine",
         {{"good.txt", good}, {"ans.npy", answers_npy({{2, 4, 6}, {0, 0, 0}})}, {"ans.json", answers_companion()}}, 2,
         "ans.npy:2: field 'id': row 2 answers no case: the input has 1 cases"},
        // A program's output beyond its answers.
        {"`hunt --command`: an extra answer after the last batch's",
         "rayverify hunt --command 'python3 extra.py' --contract query=line_roots --name prog --seconds 0 "
         "--evaluations 1 --no-shrink -o finds.txt",
         {{"extra.py", answering_program("json.dumps({'id': 'extra', 'count': 0}) + '\\n'", "''")}}, 2,
         "field '--command': command 'python3 extra.py' wrote more after its answer to the last batch"},
        {"`hunt --command`: trailing output when its input ends",
         "rayverify hunt --command 'python3 trailing.py' --contract query=line_roots --name prog --seconds 0 "
         "--evaluations 1 --no-shrink -o finds.txt",
         {{"trailing.py", answering_program("''", "'done\\n'")}}, 2,
         "field '--command': command 'python3 trailing.py' wrote more after its answer to the last batch"},
        // Names and values.
        {"`--name` with a newline (it would split a gate baseline's line)",
         "rayverify audit --corpus good.txt --results ans.csv --contract query=line_roots --name \"$(printf 'a\\nb')\"",
         {{"good.txt", good}, {"ans.csv", good_answers}}, 2,
         "field '--name': 'a\\x0Ab' must be one token without spaces, '/', '#' or control characters"},
        {"`hunt --command --name` with a terminal escape sequence",
         "rayverify hunt --command 'python3 p.py' --contract query=line_roots --name \"$(printf '\\033[31mred')\" "
         "--seconds 0 --evaluations 1 -o finds.txt",
         {{"p.py", answering_program("''", "''")}}, 2,
         "field '--name': '\\x1B[31mred' must be one token without spaces, '/', '#' or control characters"},
        {"`--contract` with a key given twice",
         "rayverify audit --corpus good.txt --results ans.csv --contract query=line_roots,query=any_hit --name mine",
         {{"good.txt", good}, {"ans.csv", good_answers}}, 2, "field '--contract': contract: 'query' is given twice"},
        {"a hex double in a float results file (`0x1.999999999999ap-4`, the double nearest 0.1)",
         "rayverify audit --corpus good.txt --results ans.csv --contract query=line_roots --name mine",
         {{"good.txt", good},
          {"ans.csv", answers_csv("good,2,0x1.999999999999ap-4,6\n", rayverify::precision::binary32)}}, 2,
         "ans.csv:3: field 't0': 0x1.999999999999ap-4 is a hex double that is not a float (binary32) value"},
        {"a CSV id with RFC 4180's `\"\"` escape (`\"q\"\"uote\"` is `q\"uote`)",
         "rayverify audit --corpus q.txt --results q.csv --contract query=line_roots --name mine --summary",
         {{"q.txt", "q\"uote - 0 0 -5 0 0 1 0 0 0 1\n"}}, 0, "mine", 
         [](const fs::path& dir) {
             rayverify::case_fingerprint fingerprint;
             for (const auto& c : rayverify::parse_corpus("q.txt", "q\"uote - 0 0 -5 0 0 1 0 0 0 1\n", false))
                 fingerprint.add(c);
             std::ofstream(dir / "q.csv") << "# rayverify results v1 precision=double fingerprint="
                                          << rayverify::exchange_fingerprint(fingerprint.text(),
                                                                             rayverify::precision::binary64)
                                          << "\nid,count,t0,t1\n\"q\"\"uote\",2,4,6\n";
         },
         false, "", "mine"},
        {"gate: `--baseline` a FIFO (would block until a writer comes)",
         "rayverify gate --corpus good.txt --baseline b.txt", {{"good.txt", good}}, 2,
         "b.txt: field '--baseline': is not a regular file",
         [](const fs::path& dir) { ASSERT_EQ(::mkfifo((dir / "b.txt").c_str(), 0600), 0); }},
        {"diff: a report that is a FIFO", "rayverify diff a.json b.json", {}, 2,
         "b.json: field 'report': is not a regular file",
         [](const fs::path& dir) {
             two_reports(good, "naive", good, "naive")(dir);
             fs::remove(dir / "b.json");
             ASSERT_EQ(::mkfifo((dir / "b.json").c_str(), 0600), 0);
         }},
        {"diff: a report with a number beyond double range (`1e400`)", "rayverify diff a.json b.json", {}, 2,
         "b.json:1: field 'overflow': number overflow parsing '1e400'",
         [](const fs::path& dir) {
             two_reports(good, "naive", good, "naive")(dir);
             std::string text = read_text(dir / "b.json");
             text.insert(text.find('{') + 1, "\"overflow\": 1e400, ");
             std::ofstream(dir / "b.json", std::ios::trunc) << text;
         }},
        // diff exits as gate would fail.
        {"diff: two reports with no figure in common", "rayverify diff a.json b.json", {}, 1,
         "diff: no figure of B has a counterpart in A with the same case count",
         two_reports(good, "naive", good, "half_b"), false, "", "diff: no figure"},
        {"diff: a family whose case count changed", "rayverify diff a.json b.json", {}, 1,
         "cases  naive/double -: cases 1 → 2",
         two_reports(good, "naive", good + "two - 0 0 -5 0 0 1 0 0 0 2\n", "naive"), false, "", "cases "},
        {"diff: a directory instead of a report", "rayverify diff a.json b", {}, 2,
         "b: field 'report': is a directory, expected a report.json file",
         [](const fs::path& dir) {
             two_reports(good, "naive", good, "naive")(dir);
             fs::create_directory(dir / "b");
         }},
        // builds: what it refuses before it compiles anything.
        {"builds: a source that does not exist", "rayverify builds nosuch.c", {}, 2,
         "nosuch.c: field 'SOURCE': no such file"},
        {"builds: a source that is neither C nor C++ (`.py`)", "rayverify builds p.py", one("p.py", "print(1)\n"),
         2, "p.py: field 'SOURCE': is neither a C source"},
        {"builds: a flag that puts code into the build (`-fplugin=`)",
         "rayverify builds mine.c --flags=\"-O2 -fplugin=./evil.so\"", one("mine.c", "int x;\n"), 2,
         "field '--flags': '-fplugin=./evil.so' puts code of its choosing into the build"},
        {"builds: a flag that changes what is built (`-Wl,`)", "rayverify builds mine.c --flags=\"-O2 -Wl,-init,f\"",
         one("mine.c", "int x;\n"), 2, "field '--flags': '-Wl,-init,f' changes what is built"},
    };
}

struct row_outcome {
    run_result result;
    std::set<std::string> before, after;  // the row's directory around the run
    std::vector<std::string> contents_after;  // of row.files, in order
};

row_outcome run_row(const bad_input& row, const std::string& extra_arguments = "") {
    scratch_directory dir("rayverify_hostile_row");
    for (const auto& [name, contents] : row.files) std::ofstream(dir.path() / name, std::ios::binary) << contents;
    if (row.prepare) row.prepare(dir.path());
    row_outcome o;
    o.before = listing(dir.path());
    const std::string arguments = row.command.substr(std::string("rayverify ").size()) + extra_arguments;
    o.result = run_in(dir.path(), arguments, row.unprivileged, row.environment);
    o.after = listing(dir.path());
    for (const auto& [name, contents] : row.files) o.contents_after.push_back(read_text(dir.path() / name));
    return o;
}

std::string escape_cell(std::string s) {
    for (std::size_t i = 0; (i = s.find('|', i)) != std::string::npos; i += 2) s.replace(i, 1, "\\|");
    return s;
}

// Long answers (lists of every family) are cut, so the table stays readable and stable.
std::string shortened(std::string s) {
    constexpr std::size_t width = 200;
    return s.size() <= width ? s : s.substr(0, width) + " …";
}

// A markdown code span around `s`; one that holds a backtick needs a longer fence.
std::string code_span(const std::string& s) {
    return s.find('`') == std::string::npos ? "`" + s + "`" : "`` " + s + " ``";
}

// The docs/bad-input.md table, rendered from the outcomes.
std::string render_table(const std::vector<bad_input>& rows, const std::vector<row_outcome>& outcomes) {
    std::string table = "| bad input | command | exit | what rayverify answers |\n|---|---|---|---|\n";
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const std::string command = rows[i].environment.empty() ? rows[i].command
                                                                : rows[i].environment + " " + rows[i].command;
        table += fmt::format("| {} | {} | {} | {} |\n", escape_cell(rows[i].what), code_span(escape_cell(command)),
                             outcomes[i].result.exit_code,
                             code_span(escape_cell(shortened(outcomes[i].result.answer(rows[i].answer_prefix)))));
    }
    return table;
}

const char* table_begin = "<!-- bad-input-table:begin (generated by tests/hostile_input_test.cpp) -->\n";
const char* table_end = "<!-- bad-input-table:end -->";

TEST(BadInput, EveryRowAnswersAsExpectedAndLeavesNothingBehind) {
    for (const bad_input& row : bad_inputs()) {
        SCOPED_TRACE(row.command);
        const row_outcome o = run_row(row);
        EXPECT_EQ(o.result.exit_code, row.exit_code) << o.result.err;
        const std::string answer = o.result.answer(row.answer_prefix);
        EXPECT_NE(answer.find(row.expect), std::string::npos) << "answer: " << answer;
        if (row.exit_code == 2) {
            EXPECT_EQ(o.after, o.before) << "a file appeared or vanished";
            for (std::size_t i = 0; i < row.files.size() && !row.unprivileged; ++i)  // mode 000: unreadable
                EXPECT_EQ(o.contents_after[i], row.files[i].second) << row.files[i].first << " was rewritten";
            EXPECT_EQ(o.result.out, "") << "nothing on stdout after an input error";
            EXPECT_EQ(answer.find("internal error"), std::string::npos);
        }
    }
}

TEST(BadInput, AuditWithOutputsWritesNothingOnAnyBadCorpus) {
    for (const bad_input& row : bad_inputs()) {
        if (row.exit_code != 2 || !row.command.starts_with("rayverify audit --corpus") ||
            row.command.find("--per-case") != std::string::npos || row.command.find("--report") != std::string::npos)
            continue;
        SCOPED_TRACE(row.command);
        const row_outcome o = run_row(row, " --report rep --per-case cases.jsonl");
        EXPECT_EQ(o.result.exit_code, 2) << o.result.err;
        EXPECT_EQ(o.after, o.before) << "partial output left behind";
    }
}

// A CSV with a tmin column and no tmax (tmax is then +inf): explain prints the
// case as a corpus line that explain reads back as the same case (it used to
// print a line of 13 fields).
TEST(BadInput, CsvWithTminOnlyExplainsAsALineThatReadsBack) {
    scratch_directory dir("rayverify_hostile_tmin");
    std::ofstream(dir.path() / "half.csv") << "id,ox,oy,oz,dx,dy,dz,cx,cy,cz,r,tmin\nhalf,0,0,-5,0,0,1,0,0,0,1,5\n";
    // One variant that agrees here (exit 0): the line is what matters, not the verdicts.
    const run_result first = run_in(dir.path(), "explain --case half --corpus half.csv --precision double --variant naive");
    ASSERT_EQ(first.exit_code, 0) << first.err;
    const std::string line = first.answer("corpus line: ").substr(std::string("corpus line: ").size());
    EXPECT_EQ(line, "half - 0x0p+0 0x0p+0 -0x1.4p+2 0x0p+0 0x0p+0 0x1p+0 0x0p+0 0x0p+0 0x0p+0 0x1p+0 0x1.4p+2 -");
    const run_result again = run_in(dir.path(), "explain \"" + line + "\" --precision double --variant naive");
    ASSERT_EQ(again.exit_code, 0) << again.err;
    EXPECT_EQ(again.out, first.out);
}

TEST(BadInput, SceneAuditAndGateWithOutputsWriteNothingOnBadInput) {
    for (const bad_input& row : bad_inputs()) {
        if (row.exit_code != 2) continue;
        std::vector<std::string> outputs;
        if (row.command.starts_with("rayverify audit --scene"))
            outputs = {" --report rep"};
        else if (row.command.starts_with("rayverify gate"))
            outputs = {" --junit junit.xml", " --update"};
        for (const std::string& extra : outputs) {
            // --update of a missing baseline creates it: that is what it is for; --update writes no --junit;
            // a row that gives the option already is about that option.
            if (extra == " --update" && (row.command.find("--baseline nowhere") != std::string::npos ||
                                         row.command.find("--junit") != std::string::npos))
                continue;
            if (row.command.find(extra.substr(1, extra.find(' ', 1) - 1)) != std::string::npos) continue;
            SCOPED_TRACE(row.command + extra);
            const row_outcome o = run_row(row, extra);
            EXPECT_EQ(o.result.exit_code, 2) << o.result.err;
            EXPECT_EQ(o.after, o.before) << "partial output left behind";
            for (std::size_t i = 0; i < row.files.size() && !row.unprivileged; ++i)  // mode 000: unreadable
                EXPECT_EQ(o.contents_after[i], row.files[i].second) << row.files[i].first << " was rewritten";
        }
    }
}

TEST(BadInput, DocumentedTableIsWhatTheToolAnswers) {
    const std::vector<bad_input> rows = bad_inputs();
    std::vector<row_outcome> outcomes;
    for (const bad_input& row : rows) outcomes.push_back(run_row(row));
    const std::string generated = render_table(rows, outcomes);

    const std::string page = read_text(fs::path(RAYVERIFY_SOURCE_DIR) / "docs" / "bad-input.md");
    const std::size_t begin = page.find(table_begin), end = page.find(table_end);
    ASSERT_NE(begin, std::string::npos) << "docs/bad-input.md lacks the marker " << table_begin;
    ASSERT_NE(end, std::string::npos) << "docs/bad-input.md lacks the marker " << table_end;
    const std::string documented =
        page.substr(begin + std::string(table_begin).size(), end - begin - std::string(table_begin).size());
    if (documented != generated) {
        ADD_FAILURE() << "docs/bad-input.md's table differs from what rayverify answers; replace what is "
                         "between its markers with the table printed below";
        std::printf("%s", generated.c_str());
    }
}

// A larger corpus of ordinary lines is read whole and quickly; the limit is
// far above what the shipped families produce.
TEST(LargeInput, ManyThousandLinesReadInBoundedTime) {
    scratch_directory dir("rayverify_hostile_large");
    std::string text;
    for (int i = 0; i < 40000; ++i)
        text += fmt::format("c{} far 0x1.9caf561af412ep+28 -0x1.e44e4bde22242p+27 -0x1.eb3bc9645ddcep+28 "
                            "-0x1.341ee24486583p-1 0x1.69983663db4bep-2 0x1.6ec458382440fp-1 0x1.2841e1100c488p-1 "
                            "-0x1.789da90131056p-1 -0x1.a8782c9b166fp-3 0x1.aee8db0b40b16p+0\n",
                            i);
    std::ofstream(dir.path() / "large.txt") << text;
    const auto start = std::chrono::steady_clock::now();
    const auto cases = rayverify::read_corpus_file(dir.path() / "large.txt");
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_EQ(cases.size(), 40000u);
    EXPECT_LT(seconds, 10.0) << text.size() << " bytes";
}

// Peak resident memory of this process, in bytes.
std::size_t peak_rss() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return static_cast<std::size_t>(usage.ru_maxrss) * 1024;
}

// A 2 GB file: refused by its size before a byte is read.
TEST(LongSweepLargeInput, TwoGigabyteFileIsRefusedAtOnce) {
    scratch_directory dir("rayverify_hostile_2g");
    std::ofstream(dir.path() / "2g.txt") << good;
    fs::resize_file(dir.path() / "2g.txt", std::uintmax_t{2} << 30);  // sparse: no disk used
    const auto start = std::chrono::steady_clock::now();
    const run_result r = run_in(dir.path(), "audit --corpus 2g.txt --report rep --per-case cases.jsonl");
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_EQ(r.answer(""), "rayverify: error: 2g.txt: is 2147483648 bytes, over the 64 MiB limit for one "
                            "corpus file; split it into several files");
    EXPECT_LT(seconds, 5.0);
    EXPECT_EQ(listing(dir.path()), std::set<std::string>{"2g.txt"});
}

// The worst case the limit lets through: a file just under 64 MiB of the
// shortest possible lines (~2.4 million cases). Bounded time and memory.
TEST(LongSweepLargeInput, LargestAcceptedFileOfShortLines) {
    scratch_directory dir("rayverify_hostile_64m");
    std::string text;
    text.reserve(rayverify::max_corpus_file_bytes);
    for (std::size_t i = 0;; ++i) {
        const std::string line = fmt::format("{:x} - 0 0 0 1 0 0 0 0 0 1\n", i);
        if (text.size() + line.size() > rayverify::max_corpus_file_bytes) break;
        text += line;
    }
    std::ofstream(dir.path() / "short.txt") << text;
    const std::size_t text_bytes = text.size();
    std::string().swap(text);
    const auto start = std::chrono::steady_clock::now();
    const auto cases = rayverify::read_corpus_file(dir.path() / "short.txt");
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("read %zu bytes, %zu cases in %.1f s, peak RSS %.0f MB\n", text_bytes, cases.size(), seconds,
                static_cast<double>(peak_rss()) / 1e6);
    EXPECT_GT(cases.size(), 2'000'000u);
    EXPECT_LT(seconds, 120.0);
    EXPECT_LT(peak_rss(), std::size_t{3} << 30);
}

}  // namespace
