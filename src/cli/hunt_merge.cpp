// rayverify merge HUNT_FILE...: the output files of `hunt --shard K/N` (every
// K of one N, or earlier merges of some of them) as one hunt file that keeps
// the worst finds, each with the shard, search seed and evaluation it came from.
#include <fmt/format.h>

#include <algorithm>
#include <map>

#include "cli/commands.h"
#include "core/input_error.h"
#include "corpus/case_stream.h"
#include "corpus/corpus_io.h"
#include "report/hunt_file.h"

namespace rayverify::cli {

namespace {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

struct hunt_input {
    fs::path path;
    hunt_file file;
};

shard_spec shard_of(const json& record, const fs::path& path) {
    try {
        return parse_shard(record.at("shard").get<std::string>());
    } catch (const input_error& e) {
        throw input_error(path.string(), 0, "shard", e.what());
    }
}

// Two files come from one sharded hunt: same build, target, search and start
// family, seed, shard count, and command up to the spelling of paths.
void check_same_hunt(const hunt_input& first, const hunt_input& other) {
    for (const char* field : {"build", "target", "objective", "strategy", "family", "seed", "shards"})
        if (first.file.hunt.at(field) != other.file.hunt.at(field))
            throw input_error(other.path.string(), 0, field,
                              fmt::format("differs from {}: {} vs {} (shards of different hunts cannot be merged)",
                                          first.path.string(), other.file.hunt.at(field).dump(),
                                          first.file.hunt.at(field).dump()));
    if (const auto what = command_difference(first.file.hunt.at("command").get<std::string>(),
                                             other.file.hunt.at("command").get<std::string>(), first.path.string(),
                                             other.path.string()))
        throw input_error(other.path.string(), 0, "command",
                          fmt::format("differs from {}: {} (shards of different hunts cannot be merged)",
                                      first.path.string(), *what));
}

// The runs of all files, each shard K of N exactly once, in shard order.
json all_runs(const std::vector<hunt_input>& inputs) {
    const std::size_t n = inputs.front().file.hunt.at("shards").get<std::size_t>();
    std::map<std::size_t, std::pair<json, const fs::path*>> runs;
    for (const hunt_input& input : inputs)
        for (const json& run : input.file.hunt.at("runs")) {
            const shard_spec shard = shard_of(run, input.path);
            if (shard.count != n)
                throw input_error(input.path.string(), 0, "shard",
                                  fmt::format("a run of shard {}, in a hunt of {} shards", shard.text(), n));
            const auto [at, inserted] = runs.try_emplace(shard.index, run, &input.path);
            if (!inserted)
                throw input_error(input.path.string(), 0, "shard",
                                  fmt::format("shard {} given twice (also in {})", shard.text(),
                                              at->second.second->string()));
        }
    std::string missing;
    for (std::size_t k = 1; k <= n; ++k)
        if (!runs.count(k)) missing += fmt::format("{}{}/{}", missing.empty() ? "" : ", ", k, n);
    if (!missing.empty()) throw input_error("", 0, "shard", fmt::format("missing hunt shard(s) {}", missing));
    json out = json::array();
    for (auto& [k, run] : runs) out.push_back(std::move(run.first));
    return out;
}

// Worst first. ulp: the largest error; misclass: every find is a
// disagreement, kept in shard order. Ties go to the lower shard, then the
// earlier evaluation, so the result does not depend on the order of the files.
void rank_finds(std::vector<hunt_file_find>& finds, bool ulp, const fs::path& any) {
    struct key {
        double error;
        std::size_t shard;
        std::uint64_t evaluation;
    };
    std::vector<std::pair<key, hunt_file_find>> keyed;
    for (hunt_file_find& f : finds)
        keyed.push_back({{ulp ? find_error(f) : 0.0, shard_of(f.provenance, any).index,
                          f.provenance.at("evaluation").get<std::uint64_t>()},
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
    hunt_file merged;
    std::size_t found = 0;
    try {
        for (const hunt_input& input : inputs) check_same_hunt(inputs.front(), input);
        merged.hunt = inputs.front().file.hunt;
        merged.hunt["runs"] = all_runs(inputs);
        for (hunt_input& input : inputs)
            for (hunt_file_find& f : input.file.finds) merged.finds.push_back(std::move(f));
        found = merged.finds.size();
        const bool ulp = merged.hunt.at("objective").get<std::string>() == "ulp";
        rank_finds(merged.finds, ulp, inputs.front().path);
        if (merged.finds.size() > keep) merged.finds.resize(keep);
        render_hunt_file(merged);  // every field the file shows is there
    } catch (const json::exception& e) {
        throw input_error(inputs.front().path.string(), 0, "", fmt::format("a hunt file is malformed: {}", e.what()));
    }
    merged_file.stream() << render_hunt_file(merged);

    std::uint64_t evaluations = 0;
    for (const json& run : merged.hunt.at("runs")) evaluations += run.at("evaluations").get<std::uint64_t>();
    fmt::print("merged {} hunt shards of {} ({} objective): {} evaluations; kept {} of {} finds\n",
               merged.hunt.at("runs").size(), merged.hunt.at("target").get<std::string>(),
               merged.hunt.at("objective").get<std::string>(), evaluations, merged.finds.size(), found);
    std::size_t n = 0;
    for (const hunt_file_find& f : merged.finds) {
        const json& p = f.provenance;
        fmt::print("find {}: {}{} from shard {} (search seed {}), evaluation {}\n  {}\n", ++n,
                   p.at("verdict").get<std::string>(),
                   merged.hunt.at("objective") == "ulp" ? fmt::format(", {:.3g} ulp", find_error(f)) : "",
                   p.at("shard").get<std::string>(), p.at("search_seed").get<std::uint64_t>(),
                   p.at("evaluation").get<std::uint64_t>(), format_case_line(f.shrunk));
    }
    fmt::print("wrote {}\n", output);
    check_standard_output();
    outputs.commit();
    bool disagreement = merged.hunt.at("objective") == "misclass" && !merged.finds.empty();
    for (const json& run : merged.hunt.at("runs")) disagreement = disagreement || run.contains("first_disagreement");
    return disagreement ? exit_findings : exit_ok;
}

}  // namespace rayverify::cli
