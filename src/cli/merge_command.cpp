// rayverify merge: the shards of one audit (`audit --shard K/N --report DIR`)
// combined into the report a single run over the whole input would have
// written, byte for byte.
#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "cli/commands.h"
#include "core/input_error.h"
#include "corpus/case_stream.h"
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
};

struct shard_input {
    fs::path dir;
    json state;
    shard_spec shard;
};

shard_input read_shard(const fs::path& dir) {
    const fs::path file = dir / shard_state_file;
    std::ifstream in(file, std::ios::binary);
    if (!in)
        throw input_error(file.string(), 0, "",
                          "cannot open: not the report directory of a `rayverify audit --shard K/N --report DIR` run");
    shard_input input{dir, {}, {}};
    try {
        input.state = json::parse(in);
        if (input.state.at("format").get<std::string>() != shard_state_format)
            throw input_error(file.string(), 0, "format",
                              fmt::format("'{}', this rayverify reads '{}'", input.state.at("format").dump(),
                                          shard_state_format));
        input.shard.index = input.state.at("shard").at("index").get<std::size_t>();
        input.shard.count = input.state.at("shard").at("count").get<std::size_t>();
    } catch (const json::exception& e) {
        throw input_error(file.string(), 0, "", fmt::format("not a shard state: {}", e.what()));
    }
    return input;
}

// Every shard must come from the same audit: same build, command, input and targets.
void check_consistent(const std::vector<shard_input>& shards) {
    const shard_input& first = shards.front();
    for (const shard_input& s : shards) {
        for (const char* field : {"build", "input", "command", "targets"})
            if (s.state.at(field) != first.state.at(field))
                throw input_error((s.dir / shard_state_file).string(), 0, field,
                                  fmt::format("differs from {}: {} vs {} (shards of different audits cannot be "
                                              "merged)",
                                              (first.dir / shard_state_file).string(), s.state.at(field).dump(),
                                              first.state.at(field).dump()));
        if (s.shard.count != first.shard.count)
            throw input_error((s.dir / shard_state_file).string(), 0, "shard",
                              fmt::format("shard {} of a split in {}, {} is of a split in {}", s.shard.text(),
                                          s.shard.count, (first.dir / shard_state_file).string(), first.shard.count));
    }
    std::map<std::size_t, const shard_input*> by_index;
    for (const shard_input& s : shards)
        if (const auto [at, inserted] = by_index.emplace(s.shard.index, &s); !inserted)
            throw input_error(s.dir.string(), 0, "shard",
                              fmt::format("shard {} given twice (also {})", s.shard.text(), at->second->dir.string()));
    std::string missing;
    for (std::size_t k = 1; k <= first.shard.count; ++k)
        if (!by_index.count(k)) missing += fmt::format("{}{}/{}", missing.empty() ? "" : ", ", k, first.shard.count);
    if (!missing.empty()) throw input_error("", 0, "shard", fmt::format("missing shard(s) {}", missing));
    const std::size_t total = first.state.at("input").at("cases").get<std::size_t>();
    for (const shard_input& s : shards)
        if (s.state.at("shard").at("cases").get<std::size_t>() != s.shard.size_of(total))
            throw input_error((s.dir / shard_state_file).string(), 0, "shard",
                              fmt::format("holds {} cases, shard {} of {} cases has {}",
                                          s.state.at("shard").at("cases").get<std::size_t>(), s.shard.text(), total,
                                          s.shard.size_of(total)));
}

// The whole run's per-case lines: case i is line i div N of shard (i mod N) + 1.
void interleave_per_case(const std::vector<shard_input>& shards, std::size_t total, std::ostream& out) {
    std::vector<std::ifstream> files;
    std::vector<fs::path> names;
    for (const shard_input& s : shards) {
        const json& recorded = s.state.at("per_case_file");
        if (recorded.is_null())
            throw input_error((s.dir / shard_state_file).string(), 0, "--per-case",
                              "this shard wrote no per-case file (run every shard with --per-case)");
        fs::path path(recorded.get<std::string>());
        if (path.is_relative()) path = s.dir / path;
        files.emplace_back(path, std::ios::binary);
        if (!files.back()) throw input_error(path.string(), 0, "--per-case", "cannot open the shard's per-case file");
        names.push_back(path);
    }
    std::string line;
    for (std::size_t i = 0; i < total; ++i) {
        const std::size_t k = i % shards.size();
        if (!std::getline(files[k], line))
            throw input_error(names[k].string(), i / shards.size() + 1, "--per-case",
                              "ends early: the shard's per-case file does not match its state");
        out << line << '\n';
    }
    for (std::size_t k = 0; k < files.size(); ++k)
        if (std::getline(files[k], line))
            throw input_error(names[k].string(), 0, "--per-case",
                              "has more lines than the shard has cases: it does not match its state");
}

int run(const merge_options& options) {
    std::vector<shard_input> shards;
    for (const std::string& dir : options.shards) shards.push_back(read_shard(dir));
    check_consistent(shards);
    std::sort(shards.begin(), shards.end(),
              [](const shard_input& a, const shard_input& b) { return a.shard.index < b.shard.index; });
    const json& first = shards.front().state;

    std::vector<audit_target> targets;
    std::optional<audit_state> merged;
    try {
        targets = targets_from_json(first.at("targets"));
        merged.emplace(targets);
        for (const shard_input& s : shards) merged->merge(state_from_json(s.state.at("state"), targets));
    } catch (const json::exception& e) {
        throw input_error("", 0, "state", fmt::format("a shard state is malformed: {}", e.what()));
    }

    audit_outputs outputs;
    outputs.open_report(options.output);
    if (!options.per_case_file.empty()) outputs.per_case.emplace(options.per_case_file);
    open_presentation(outputs, options.presentation);
    if (outputs.per_case)
        interleave_per_case(shards, first.at("input").at("cases").get<std::size_t>(), outputs.per_case->stream());

    run_context context{first.at("command").get<std::string>(),
                        first.at("input").at("paths").get<std::vector<std::string>>(),
                        first.at("input").at("generated").get<std::vector<std::string>>()};
    const std::optional<json> report = audit_report_document(*merged, context);
    return publish_audit(merged->audit.finish(), report, options.output, outputs, options.plots,
                         options.presentation);
}

}  // namespace

command add_merge_command(CLI::App& app) {
    auto options = std::make_shared<merge_options>();
    auto* sub = app.add_subcommand(
        "merge", "Combine the report directories of `rayverify audit --shard K/N --report DIR` runs (every K of "
                 "one N, from the same audit) into exactly the report one run over the whole input writes. Exit 1 "
                 "when the merged audit has findings, 2 when the shards do not belong together.");
    sub->add_option("-o,--output", options->output, "Directory for the merged report.json, summary.txt, report.md")
        ->required();
    sub->add_option("--per-case", options->per_case_file,
                    "Also merge the shards' per-case files (each shard run with --per-case) into this file");
    sub->add_flag("--plots", options->plots, "Also draw the PNG plots, as `audit --plots`");
    add_presentation_options(sub, options->presentation);
    sub->add_option("shards", options->shards, "The shards' report directories")->required();
    return {sub, [options] { return run(*options); }};
}

}  // namespace rayverify::cli
