// rayverify merge: the shards of one audit (`audit --shard K/N --report DIR`)
// combined into the report a single run over the whole input would have
// written, byte for byte.
#include <fmt/format.h>
#include <sys/resource.h>

#include <algorithm>
#include <atomic>
#include <exception>
#include <filesystem>
#include <fstream>
#include <map>
#include <thread>

#include "cli/app.h"
#include "cli/commands.h"
#include "core/input_error.h"
#include "corpus/case_stream.h"
#include "report/case_list.h"
#include "report/contract_hints.h"
#include "report/hunt_file.h"
#include "report/shard_state.h"

namespace rayverify::cli {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

struct merge_options {
    std::string output;
    std::string per_case_file;
    std::vector<std::string> shards;
    bool plots = false;
    audit_presentation presentation;
    std::optional<std::size_t> keep_finds;  // hunts
};

struct shard_input {
    fs::path dir;
    shard_header header;
    fs::path file() const { return dir / shard_state_file; }
    // The per-case file as the shard recorded it, inside its directory; nullopt: none.
    std::optional<fs::path> per_case() const {
        if (!header.per_case_file) return std::nullopt;
        return dir / fs::path(*header.per_case_file);
    }
};

// The shards' states merged. Parsing them is nearly all of a merge's time, so
// every hardware thread takes shards in turn, parses each and merges it into
// a state of its own; those are merged at the end. Merging is exact and
// order-independent: the result does not depend on which thread took which
// shard. Memory: per thread one parsed document and one state, however many
// shards there are. Of the malformed shards met, the first in shard order is named.
audit_state merged_states(const std::vector<shard_input>& shards) {
    const std::vector<audit_target>& targets = shards.front().header.targets;
    const std::size_t threads = std::min<std::size_t>(thread_count(), std::max<std::size_t>(shards.size(), 1));
    std::vector<audit_state> partial(threads, audit_state(targets));
    std::vector<std::exception_ptr> failure(shards.size());
    std::atomic<std::size_t> next{0};
    std::atomic<bool> failed{false};
    const auto work = [&](audit_state& mine) {
        for (std::size_t i; !failed && (i = next++) < shards.size();) {
            try {
                const std::string file = shards[i].file().string();
                const json document = read_shard_document(file, false);
                mine.merge(read_shard_state(document, file, read_shard_header(document, file)));
            } catch (...) {
                failure[i] = std::current_exception();
                failed = true;
            }
        }
    };
    {
        std::vector<std::jthread> workers;
        for (std::size_t t = 1; t < threads; ++t) workers.emplace_back(work, std::ref(partial[t]));
        work(partial[0]);
    }
    for (const std::exception_ptr& e : failure)
        if (e) std::rethrow_exception(e);
    for (std::size_t t = 1; t < threads; ++t) partial[0].merge(partial[t]);
    return std::move(partial[0]);
}

// The targets as merge compares them: a results file's target cites the file
// by the path its shard spelled, which the digest of its contents stands for.
json targets_up_to_spelling(const std::vector<audit_target>& list) {
    json targets = to_json_mapped(list);
    for (json& t : targets)
        if (t.is_object() && t.contains("citation") && t["citation"].is_string() &&
            t["citation"].get<std::string>().starts_with("results file "))
            t["citation"] = "results file PATH";
    return targets;
}

// Two shards come from one audit: the same build, input (by its size and
// fingerprint: the paths that named it may be spelled differently), command
// (up to the spelling of paths and of the executable) and targets.
void check_same_audit(const shard_header& first, const fs::path& first_file, const shard_header& other,
                      const fs::path& other_file) {
    const auto differs = [&](const char* field, const std::string& what) {
        return input_error(other_file.string(), 0, field,
                           fmt::format("differs from {}: {} (shards of different audits cannot be merged)",
                                       first_file.string(), what));
    };
    const auto compare = [&](const char* field, const json& a, const json& b) {
        if (a != b) throw differs(field, fmt::format("{} vs {}", b.dump(), a.dump()));
    };
    compare("build", first.build, other.build);
    compare("input", first.input.cases, other.input.cases);
    compare("input", first.input.fingerprint, other.input.fingerprint);
    compare("input", first.input.generated, other.input.generated);
    compare("input", to_json_mapped(first.input.digests), to_json_mapped(other.input.digests));
    if (const auto what = command_difference(first.command, other.command, first_file.string(), other_file.string()))
        throw differs("command", *what);
    compare("targets", targets_up_to_spelling(first.targets), targets_up_to_spelling(other.targets));
    if (other.shard.count != first.shard.count)
        throw input_error(other_file.string(), 0, "shard",
                          fmt::format("shard {} of a split in {}, {} is of a split in {}", other.shard.text(),
                                      other.shard.count, first_file.string(), first.shard.count));
}

// Every K of the N once, each holding the cases shard K of the input has.
void check_complete(const std::vector<shard_input>& shards, std::size_t total) {
    std::map<std::size_t, const shard_input*> by_index;
    for (const shard_input& s : shards)
        if (const auto [at, inserted] = by_index.emplace(s.header.shard.index, &s); !inserted)
            throw input_error(s.dir.string(), 0, "shard", fmt::format("shard {} given twice (also {})",
                                                                      s.header.shard.text(), at->second->dir.string()));
    const std::size_t n = shards.front().header.shard.count;
    std::string missing;
    for (std::size_t k = 1; k <= n; ++k)
        if (!by_index.count(k)) missing += fmt::format("{}{}/{}", missing.empty() ? "" : ", ", k, n);
    if (!missing.empty()) throw input_error("", 0, "shard", fmt::format("missing shard(s) {}", missing));
    for (const shard_input& s : shards)
        if (s.header.cases != s.header.shard.size_of(total))
            throw input_error(s.file().string(), 0, "shard",
                              fmt::format("holds {} cases, shard {} of {} cases has {}", s.header.cases,
                                          s.header.shard.text(), total, s.header.shard.size_of(total)));
}

// Per-case files are read side by side, one open file per shard.
void allow_open_files(std::size_t shards) {
    rlimit limit{};
    const rlim_t wanted = static_cast<rlim_t>(shards) + 64;
    if (getrlimit(RLIMIT_NOFILE, &limit) != 0 || limit.rlim_cur >= wanted) return;
    limit.rlim_cur = std::min(wanted, limit.rlim_max);
    setrlimit(RLIMIT_NOFILE, &limit);
    if (limit.rlim_cur < wanted)
        throw input_error("", 0, "--per-case",
                          fmt::format("merging the per-case files of {} shards needs {} open files, and this "
                                      "process may open {} (ulimit -n)",
                                      shards, wanted, limit.rlim_max));
}

// A shard's per-case file, checked as its state is: a regular file inside the
// shard directory once links are resolved (a link out of it, a FIFO or a
// device is refused before it is opened).
fs::path per_case_path(const shard_input& s) {
    if (!s.per_case())
        throw input_error(s.file().string(), 0, "--per-case",
                          "this shard wrote no per-case file (run every shard with --per-case)");
    const fs::path path = *s.per_case();
    std::error_code error;
    const fs::path real = fs::canonical(path, error);
    if (error) throw input_error(path.string(), 0, "--per-case", "cannot open the shard's per-case file: " + error.message());
    const fs::path dir = fs::canonical(s.dir, error);
    const fs::path relative = real.lexically_relative(dir);
    if (error || relative.empty() || *relative.begin() == ".." || relative.is_absolute())
        throw input_error(path.string(), 0, "--per-case",
                          fmt::format("leads to {}, outside the shard directory {}", real.string(), s.dir.string()));
    if (!fs::is_regular_file(real, error))
        throw input_error(path.string(), 0, "--per-case",
                          "is not a regular file (a FIFO, a device or a socket): a shard's per-case file is a file");
    return path;
}

// The whole run's per-case lines: case i is line i div N of shard (i mod N) + 1.
// Each file must be, byte for byte, the one its shard's audit wrote (the
// digest its state records): a file swapped between shards, from another run
// or edited is refused, and nothing is committed.
void interleave_per_case(const std::vector<shard_input>& shards, std::size_t total, std::ostream& out) {
    allow_open_files(shards.size());
    std::vector<std::ifstream> files;
    std::vector<fs::path> names;
    for (const shard_input& s : shards) {
        const fs::path path = per_case_path(s);
        files.emplace_back(path, std::ios::binary);
        if (!files.back()) throw input_error(path.string(), 0, "--per-case", "cannot open the shard's per-case file");
        names.push_back(path);
    }
    std::vector<fnv1a_digest> digests(files.size());
    std::string line;
    for (std::size_t i = 0; i < total; ++i) {
        const std::size_t k = i % shards.size();
        if (!std::getline(files[k], line))
            throw input_error(names[k].string(), i / shards.size() + 1, "--per-case",
                              "ends early: the shard's per-case file does not match its state");
        line += '\n';
        digests[k].add(line);
        out << line;
    }
    for (std::size_t k = 0; k < files.size(); ++k) {
        if (std::getline(files[k], line))
            throw input_error(names[k].string(), 0, "--per-case",
                              "has more lines than the shard has cases: it does not match its state");
        if (digests[k].text() != shards[k].header.per_case_digest)
            throw input_error(names[k].string(), 0, "--per-case",
                              fmt::format("its digest is {}, its shard's state records {}: not the per-case file "
                                          "that shard's audit wrote (swapped, from another run, or edited)",
                                          digests[k].text(), shards[k].header.per_case_digest.value_or("none")));
    }
}

// First every shard's header (checked against the first shard's, then
// dropped), then the states (merged_states): memory does not grow with the
// number of shards.
int merge_audits(const merge_options& options) {
    std::vector<shard_input> shards;
    for (const std::string& dir : options.shards) {
        const fs::path file = fs::path(dir) / shard_state_file;
        shard_header header = read_shard_header(read_shard_document(file, true), file.string());
        if (!shards.empty()) check_same_audit(shards.front().header, shards.front().file(), header, file);
        shards.push_back({dir, std::move(header)});
    }
    std::sort(shards.begin(), shards.end(), [](const shard_input& a, const shard_input& b) {
        return a.header.shard.index < b.header.shard.index;
    });
    const std::size_t total = shards.front().header.input.cases;
    check_complete(shards, total);

    const audit_state merged = merged_states(shards);

    // As shard 1 spelled the command and input, whatever the order given.
    const shard_header& first = shards.front().header;
    const run_context context{first.command, first.input.paths, first.input.generated};

    audit_outputs outputs;
    for (const shard_input& s : shards) {
        outputs.files.input(s.dir, "a shard directory");
        outputs.files.input(s.file(), "a shard's state");
        if (const auto per_case = s.per_case()) outputs.files.input(*per_case, "a shard's per-case file");
    }
    outputs.open_report(options.output, "-o");
    if (!options.per_case_file.empty()) outputs.per_case = &outputs.files.file(options.per_case_file, "--per-case");
    open_presentation(outputs, options.presentation);
    if (outputs.per_case != nullptr) interleave_per_case(shards, total, outputs.per_case->stream());

    const unsigned threads = thread_count();
    const audit_totals totals = merged.audit.finish(threads);
    std::optional<json> report = audit_report_document(merged, totals, context, threads);
    // Read from the report before it is moved into publish_audit.
    std::string hints = render_contract_hints(report->at("contract_hints")) +
                        render_cases_to_open(report->at("cases_to_open"));
    return publish_audit(totals, std::move(report), outputs, options.plots, options.presentation, hints);
}

// Audit shards are directories; hunt outputs are files.
int run(const merge_options& options, bool output_given_as_o) {
    std::size_t hunts = 0;
    for (const std::string& input : options.shards) {
        std::error_code error;
        if (fs::is_regular_file(input, error) && looks_like_hunt_file(input))
            ++hunts;
        else if (fs::is_regular_file(input, error))
            throw input_error(input, 0, "",
                              "neither an audit shard's report directory nor the output of `rayverify hunt`");
    }
    if (hunts == 0) {
        if (options.keep_finds) throw input_error("", 0, "--finds", "only hunt outputs are merged by their finds");
        if (options.output.empty()) throw input_error("", 0, "--report", "name the directory of the merged report");
        if (output_given_as_o) note_deprecated("merge", "-o,--output DIR for audit shards", "--report DIR");
        return merge_audits(options);
    }
    if (options.output.empty()) throw input_error("", 0, "-o", "name the merged corpus file");
    if (hunts != options.shards.size())
        throw input_error("", 0, "", "give either audit shards (directories) or hunt outputs (files), not both");
    if (!options.per_case_file.empty() || options.plots)
        throw input_error("", 0, options.plots ? "--plots" : "--per-case",
                          "hunt outputs merge into one corpus file (-o FILE): no --per-case or --plots");
    return merge_hunts(options.shards, options.output, options.keep_finds.value_or(3));
}

}  // namespace

command add_merge_command(CLI::App& app) {
    auto options = std::make_shared<merge_options>();
    auto* sub = app.add_subcommand(
        "merge", "Combine the report directories of `rayverify audit --shard K/N --report DIR` runs (every K of "
                 "one N, from the same audit) into exactly the report one run over the whole input writes; or the "
                 "output files of `rayverify hunt --shard K/N` into one, keeping the worst finds with their "
                 "provenance. The shards may have been run from other directories or installs. Exit 1 when the "
                 "merged audit has findings or the hunts a disagreement, 2 when the shards do not belong together.");
    sub->add_option("--report", options->output, "Audit shards: the directory for the merged report.json, "
                                                 "summary.txt, report.md");
    CLI::Option* o = sub->add_option("-o,--output", options->output,
                    "Hunt outputs: the merged corpus file (for audit shards, a deprecated spelling of --report)");
    sub->add_option("--per-case", options->per_case_file,
                    "Also merge the shards' per-case files (each shard run with --per-case) into this file");
    sub->add_flag("--plots", options->plots, "Also draw the PNG plots, as `audit --plots`");
    add_presentation_options(sub, options->presentation);
    sub->add_option("--finds", options->keep_finds,
                    "Hunts: keep this many finds, the worst first (ulp: largest error; misclass: in shard order). "
                    "Default 3")
        ->check(whole_number(1, 1000000));
    sub->add_option("shards", options->shards, "The shards' report directories, or the hunts' output files")
        ->required();
    return {sub, [options, o] { return run(*options, o->count() > 0); }};
}

}  // namespace rayverify::cli
