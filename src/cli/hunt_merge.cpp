// rayverify merge HUNT_FILE...: the output files of `hunt --shard K/N` (every
// K of one N, or earlier merges of some of them) as one hunt file that keeps
// the worst finds, each with the shard, search seed and evaluation it came from.
#include <fmt/format.h>

#include <algorithm>
#include <map>

#include "compare/error_figures.h"
#include "cli/commands.h"
#include "core/input_error.h"
#include "corpus/case_stream.h"
#include "corpus/corpus_io.h"
#include "report/audit_report.h"
#include "report/hunt_file.h"

namespace rayverify::cli {

namespace {

namespace fs = std::filesystem;

struct hunt_input {
    fs::path path;
    hunt_file file;
};

// Two files come from one sharded hunt: same build, target, search and start
// family, seed, shard count, and command up to the spelling of paths.
void check_same_hunt(const hunt_input& first, const hunt_input& other) {
    const auto compare = [&](const char* field, const auto& a, const auto& b) {
        if (a != b)
            throw input_error(other.path.string(), 0, field,
                              fmt::format("differs from {}: {} vs {} (shards of different hunts cannot be merged)",
                                          first.path.string(), to_json_mapped(b).dump(), to_json_mapped(a).dump()));
    };
    const hunt_record &a = first.file.hunt, &b = other.file.hunt;
    compare("build", a.build, b.build);
    compare("target", a.target, b.target);
    compare("objective", a.objective, b.objective);
    compare("strategy", a.strategy, b.strategy);
    compare("family", a.family, b.family);
    compare("seed", a.seed, b.seed);
    compare("shards", a.shards, b.shards);
    if (const auto what = command_difference(a.command, b.command, first.path.string(), other.path.string()))
        throw input_error(other.path.string(), 0, "command",
                          fmt::format("differs from {}: {} (shards of different hunts cannot be merged)",
                                      first.path.string(), *what));
}

// The runs of all files, each shard K of N exactly once, in shard order.
std::vector<hunt_run> all_runs(const std::vector<hunt_input>& inputs) {
    const std::size_t n = inputs.front().file.hunt.shards;
    std::map<std::size_t, std::pair<const hunt_run*, const fs::path*>> runs;
    for (const hunt_input& input : inputs)
        for (const hunt_run& run : input.file.hunt.runs) {
            const auto [at, inserted] = runs.try_emplace(run.shard.index, &run, &input.path);
            if (!inserted)
                throw input_error(input.path.string(), 0, "shard",
                                  fmt::format("shard {} given twice (also in {})", run.shard.text(),
                                              at->second.second->string()));
        }
    std::string missing;
    for (std::size_t k = 1; k <= n; ++k)
        if (!runs.count(k)) missing += fmt::format("{}{}/{}", missing.empty() ? "" : ", ", k, n);
    if (!missing.empty()) throw input_error("", 0, "shard", fmt::format("missing hunt shard(s) {}", missing));
    std::vector<hunt_run> out;
    for (const auto& [k, run] : runs) out.push_back(*run.first);
    return out;
}

// Worst first. ulp: the largest error; misclass: every find is a
// disagreement, kept in shard order. Ties go to the lower shard, then the
// earlier evaluation, so the result does not depend on the order of the files.
void rank_finds(std::vector<hunt_file_find>& finds, bool ulp) {
    struct key {
        double error;
        std::size_t shard;
        std::uint64_t evaluation;
    };
    std::vector<std::pair<key, hunt_file_find>> keyed;
    for (hunt_file_find& f : finds)
        keyed.push_back({{ulp ? f.provenance.error : 0.0, f.provenance.shard.index, f.provenance.evaluation},
                         std::move(f)});
    std::stable_sort(keyed.begin(), keyed.end(), [](const auto& a, const auto& b) {
        if (a.first.error != b.first.error) return a.first.error > b.first.error;
        if (a.first.shard != b.first.shard) return a.first.shard < b.first.shard;
        return a.first.evaluation < b.first.evaluation;
    });
    finds.clear();
    for (auto& [k, f] : keyed) finds.push_back(std::move(f));
}

}  // namespace

int merge_hunts(const std::vector<std::string>& files, const std::string& output, std::size_t keep) {
    // The output, declared before the work: it may not be one of the hunt files it merges.
    run_outputs outputs;
    for (const std::string& path : files) outputs.input(path, "a hunt output");
    output_file& merged_file = outputs.file(output, "-o");
    std::vector<hunt_input> inputs;
    for (const std::string& path : files) inputs.push_back({path, read_hunt_file(path)});
    for (const hunt_input& input : inputs) check_same_hunt(inputs.front(), input);
    hunt_file merged;
    merged.hunt = inputs.front().file.hunt;
    merged.hunt.runs = all_runs(inputs);
    for (hunt_input& input : inputs)
        for (hunt_file_find& f : input.file.finds) merged.finds.push_back(std::move(f));
    const std::size_t found = merged.finds.size();
    rank_finds(merged.finds, merged.hunt.objective == hunt_objective::ulp);
    if (merged.finds.size() > keep) merged.finds.resize(keep);
    merged_file.stream() << render_hunt_file(merged);

    std::uint64_t evaluations = 0;
    for (const hunt_run& run : merged.hunt.runs) evaluations += run.evaluations;
    fmt::print("merged {} hunt shards of {} ({} objective): {} evaluations; kept {} of {} finds\n",
               merged.hunt.runs.size(), merged.hunt.target, hunt_objective_name(merged.hunt.objective), evaluations,
               merged.finds.size(), found);
    std::size_t n = 0;
    for (const hunt_file_find& f : merged.finds) {
        const hunt_find_provenance& p = f.provenance;
        fmt::print("find {}: {}{} from shard {} (search seed {}), evaluation {}\n  {}\n", ++n, verdict_name(p.verdict),
                   merged.hunt.objective == hunt_objective::ulp ? ", " + format_figure(p.error) + " ulp" : "",
                   p.shard.text(), p.search_seed, p.evaluation, format_case_line(f.shrunk));
    }
    fmt::print("wrote {}\n", output);
    check_standard_output();
    outputs.commit();
    bool disagreement = merged.hunt.objective == hunt_objective::misclass && !merged.finds.empty();
    for (const hunt_run& run : merged.hunt.runs) disagreement = disagreement || run.first_disagreement.has_value();
    return disagreement ? exit_findings : exit_ok;
}

}  // namespace rayverify::cli
