#include <fmt/format.h>

#include "cli/commands.h"
#include "compare/hunt.h"
#include "core/input_error.h"
#include "corpus/corpus_io.h"
#include "corpus/generators.h"
#include "report/audit_report.h"
#include "report/hunt_file.h"

namespace rayverify::cli {
namespace {

struct hunt_command_options {
    std::string variant;
    std::string plugin;  // a plugin library hunted instead of a built-in variant
    plugin_isolation isolation;
    std::string precision = "double";
    std::string family = "uniform";
    double budget = 10;
    std::uint64_t evaluations = 0;
    std::string objective = "ulp";
    std::string strategy = "search";
    std::uint64_t seed = 1;
    std::size_t finds = 3;
    bool no_shrink = false;
    std::string output;
    std::string shard;
};

std::string error_text(double ulps) { return fmt::format("{:.3g} ulp", ulps); }

int run(const hunt_command_options& o, const std::string& command_line) {
    if (o.variant.empty() == o.plugin.empty())
        throw input_error("", 0, "--variant", "name exactly one target: --variant NAME or --plugin LIBRARY");
    const std::vector<std::string> names = o.variant.empty() ? std::vector<std::string>{} : std::vector{o.variant};
    const std::vector<std::string> plugins = o.plugin.empty() ? std::vector<std::string>{} : std::vector{o.plugin};
    const std::vector<audit_target> targets = select_targets(names, plugins, {o.precision}, o.isolation);
    if (targets.empty())
        throw input_error("", 0, "--precision",
                          fmt::format("{} does not run in {}", o.variant.empty() ? o.plugin : o.variant, o.precision));
    const audit_target& target = targets.front();
    const family_info* family = find_generator_family(o.family);
    if (family == nullptr) {
        std::string known;
        for (const family_info& f : generator_families()) known += (known.empty() ? "" : ", ") + std::string(f.name);
        throw input_error("", 0, "--family", fmt::format("unknown generator family '{}' (known: {})", o.family, known));
    }
    if (!(o.budget >= 0)) throw input_error("", 0, "--budget", "must be a number of seconds >= 0");
    if (o.budget == 0 && o.evaluations == 0)
        throw input_error("", 0, "--budget", "give a time budget (--budget) or an evaluation budget (--evaluations)");

    const shard_spec shard = o.shard.empty() ? shard_spec{} : chosen_shard(o.shard, "hunt");
    hunt_options options;
    options.objective = o.objective == "ulp" ? hunt_objective::ulp : hunt_objective::misclass;
    options.strategy = o.strategy == "search" ? hunt_strategy::search : hunt_strategy::random;
    options.seed = shard_search_seed(o.seed, shard.index, shard.count);
    options.max_seconds = o.budget;
    options.max_evaluations = o.evaluations;
    options.max_finds = o.finds;
    options.shrink = !o.no_shrink;
    const std::string family_name(family->name);
    // This shard's start cases: the family's cases K − 1, K − 1 + N, ...
    const auto start_index = [&](std::uint64_t j) { return shard.index - 1 + j * shard.count; };
    const hunt_start start = [&](std::uint64_t j) { return generate_case(family_name, o.seed, start_index(j)).geometry; };
    const hunt_result result = hunt(target, start, options);

    const std::string label = target.label();
    const bool ulp = options.objective == hunt_objective::ulp;
    std::string shard_note;
    if (shard.count > 1) shard_note = fmt::format(", shard {} (search seed {})", shard.text(), options.seed);
    fmt::print("hunt {} ({} objective, {} strategy, family {}, seed {}{}): {} evaluations, {} starts, {:.2f} s\n",
               label, o.objective, o.strategy, family_name, o.seed, shard_note, result.evaluations, result.starts,
               result.seconds);

    hunt_file file;
    file.hunt = {{"format", hunt_file_format},
                 {"build", build_json()},
                 {"command", recorded_command(command_line)},
                 {"target", label},
                 {"objective", o.objective},
                 {"strategy", o.strategy},
                 {"family", family_name},
                 {"seed", o.seed},
                 {"shards", shard.count},
                 {"runs", nlohmann::ordered_json::array({{{"shard", shard.text()},
                                                          {"search_seed", options.seed},
                                                          {"evaluations", result.evaluations},
                                                          {"starts", result.starts},
                                                          {"shrink_evaluations", result.shrink_evaluations},
                                                          {"seconds", result.seconds}}})}};
    std::string id_stem = fmt::format("hunt-{}-{}-{}-{}-{}", target.subject.name, precision_name(target.prec),
                                      o.objective, o.strategy, o.seed);
    if (shard.count > 1) id_stem += fmt::format("-shard{}of{}", shard.index, shard.count);
    for (const hunt_find& f : result.finds) {
        hunt_file_find entry;
        entry.shrunk.id = fmt::format("{}-{}", id_stem, file.finds.size() + 1);
        entry.shrunk.family = "hunt_" + family_name;
        entry.shrunk.geometry = f.shrunk;
        entry.found = entry.shrunk;
        entry.found.id += "-found";
        entry.found.geometry = f.found;
        entry.provenance = {{"shard", shard.text()},
                            {"search_seed", options.seed},
                            {"evaluation", f.evaluation},
                            {"seconds", f.seconds},
                            {"start", generate_case(family_name, o.seed, start_index(f.start_index)).id},
                            {"verdict", verdict_name(f.found_eval.verdict)},
                            {"error", hex_float(f.found_eval.error)},
                            {"detail", f.found_eval.detail},
                            {"found_bits", f.found_bits},
                            {"shrunk_verdict", verdict_name(f.shrunk_eval.verdict)},
                            {"shrunk_error", hex_float(f.shrunk_eval.error)},
                            {"shrunk_bits", f.shrunk_bits}};
        const std::string what = ulp ? fmt::format("agree, {} (lower bound)", error_text(f.found_eval.error))
                                     : std::string(verdict_name(f.found_eval.verdict));
        const std::string shrunk_what = ulp ? fmt::format("agree, {}", error_text(f.shrunk_eval.error))
                                            : std::string(verdict_name(f.shrunk_eval.verdict));
        fmt::print("find {}: {} at evaluation {} ({:.3f} s)\n", file.finds.size() + 1, what, f.evaluation, f.seconds);
        if (!f.found_eval.detail.empty()) fmt::print("  {}\n", f.found_eval.detail);
        fmt::print("  shrunk ({} -> {} significant bits, still {}):\n  {}\n", f.found_bits, f.shrunk_bits,
                   shrunk_what, format_case_line(entry.shrunk));
        file.finds.push_back(std::move(entry));
    }
    if (result.finds.empty())
        fmt::print("{}\n", ulp ? "no agreeing answer with a nonzero error was seen" : "no disagreement found");
    write_file_atomically(o.output, render_hunt_file(file));
    fmt::print("wrote {}\n", o.output);
    const bool disagreement = !ulp && !result.finds.empty();
    return disagreement ? exit_findings : exit_ok;
}

}  // namespace

command add_hunt_command(CLI::App& app, const std::string& command_line) {
    auto o = std::make_shared<hunt_command_options>();
    auto* sub = app.add_subcommand(
        "hunt", "Search for inputs that maximise a variant's error (--objective ulp) or make it disagree with the "
                "exact answer (--objective misclass): random restarts from a family's cases, local search by ulp "
                "moves judged by the exact oracle, then shrinking. Writes the finds as corpus lines. Exit 1 when "
                "a disagreement was found");
    sub->add_option("--variant", o->variant, "Variant to hunt");
    sub->add_option("--plugin", o->plugin,
                    "Hunt a plugin (rayverify_plugin.h) instead: its functions are called through a function pointer");
    add_isolation_options(sub, o->isolation);
    sub->add_option("--precision", o->precision, "float or double")
        ->check(CLI::IsMember({"float", "double"}))
        ->capture_default_str();
    sub->add_option("--family", o->family, "Generator family the searches start from")->capture_default_str();
    sub->add_option("--budget", o->budget, "Search time in seconds (0: no time limit)")->capture_default_str();
    sub->add_option("--evaluations", o->evaluations,
                    "Search evaluations (0: no limit); with --budget 0 the result is reproducible")
        ->capture_default_str();
    sub->add_option("--objective", o->objective, "ulp or misclass")
        ->check(CLI::IsMember({"ulp", "misclass"}))
        ->capture_default_str();
    sub->add_option("--strategy", o->strategy, "search, or random (plain sampling of the family: the baseline)")
        ->check(CLI::IsMember({"search", "random"}))
        ->capture_default_str();
    sub->add_option("--seed", o->seed, "Seed of the start cases and of the search")->capture_default_str();
    sub->add_option("--finds", o->finds, "misclass: stop after this many disagreements")->capture_default_str();
    sub->add_flag("--no-shrink", o->no_shrink, "Keep the finds as found");
    sub->add_option("--shard", o->shard,
                    "Be shard K of N independent hunts (K/N, auto or auto/N as for audit): start from the family's "
                    "cases K-1, K-1+N, ... and search with a seed derived from --seed and K; each shard has the "
                    "whole budget. `rayverify merge` keeps the worst finds of the N output files");
    sub->add_option("-o,--output", o->output, "Corpus file to write the finds to (atomically)")->required();
    return {sub, [o, command_line] { return run(*o, command_line); }};
}

}  // namespace rayverify::cli
