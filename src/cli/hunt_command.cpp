#include <fmt/format.h>

#include "cli/app.h"
#include "cli/commands.h"
#include "cli/terminal.h"
#include "compare/hunt.h"
#include "core/input_error.h"
#include "corpus/corpus_io.h"
#include "corpus/generators.h"

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
    if (!(o.budget >= 0)) throw input_error("", 0, "--seconds", "must be a number of seconds >= 0");
    if (o.budget == 0 && o.evaluations == 0)
        throw input_error("", 0, "--seconds", "give a time budget (--seconds) or an evaluation budget (--evaluations)");

    hunt_options options;
    options.objective = o.objective == "ulp" ? hunt_objective::ulp : hunt_objective::misclass;
    options.strategy = o.strategy == "search" ? hunt_strategy::search : hunt_strategy::random;
    options.seed = o.seed;
    options.max_seconds = o.budget;
    options.max_evaluations = o.evaluations;
    options.max_finds = o.finds;
    options.shrink = !o.no_shrink;
    const std::string family_name(family->name);
    const hunt_start start = [&](std::uint64_t index) { return generate_case(family_name, o.seed, index).geometry; };
    // Live: how far the budget is spent, and the best found so far.
    const bool timed = o.budget > 0;
    terminal::progress progress("hunt", timed ? "s" : "evaluations",
                                timed ? o.budget : static_cast<double>(o.evaluations));
    options.on_progress = [&](const hunt_progress& p) {
        const std::string best = options.objective == hunt_objective::ulp
                                     ? fmt::format("best so far {}", p.best_error > 0 ? error_text(p.best_error) : "-")
                                     : fmt::format("{} disagreement(s) found", p.finds);
        progress.update(timed ? p.seconds : static_cast<double>(p.evaluations),
                        timed ? fmt::format("{} evaluations, {}", p.evaluations, best) : best);
    };
    const hunt_result result = hunt(target, start, options);
    progress.finish();

    const std::string label = target.label();
    const bool ulp = options.objective == hunt_objective::ulp;
    std::string text = corpus_header_comment() + '\n';
    text += fmt::format("# rayverify hunt: {}, objective {}, strategy {}, start family {} (seed {})\n", label,
                        o.objective, o.strategy, family_name, o.seed);
    text += fmt::format("# command: {}\n", command_line);
    text += fmt::format("# searched {} evaluations from {} start cases in {:.2f} s; {} shrinking evaluations\n",
                        result.evaluations, result.starts, result.seconds, result.shrink_evaluations);
    if (ulp)
        text += "# the error below is the largest FOUND BY SEARCH: a lower bound on the variant's maximum over all "
                "inputs, not the maximum\n";
    fmt::print("hunt {} ({} objective, {} strategy, family {}, seed {}): {} evaluations, {} starts, {:.2f} s\n",
               label, o.objective, o.strategy, family_name, o.seed, result.evaluations, result.starts,
               result.seconds);

    const std::string id_stem = fmt::format("hunt-{}-{}-{}-{}-{}", target.subject.name, precision_name(target.prec),
                                            o.objective, o.strategy, o.seed);
    std::size_t n = 0;
    for (const hunt_find& f : result.finds) {
        ++n;
        corpus_case shrunk;
        shrunk.id = fmt::format("{}-{}", id_stem, n);
        shrunk.family = "hunt_" + family_name;
        shrunk.geometry = f.shrunk;
        corpus_case found = shrunk;
        found.id += "-found";
        found.geometry = f.found;
        const std::string what = ulp ? fmt::format("agree, {} (lower bound)", error_text(f.found_eval.error))
                                     : std::string(verdict_name(f.found_eval.verdict));
        const std::string shrunk_what = ulp ? fmt::format("agree, {}", error_text(f.shrunk_eval.error))
                                            : std::string(verdict_name(f.shrunk_eval.verdict));
        text += fmt::format("# find {}: {} at evaluation {} ({:.3f} s), searching from {}-{}-{:06}\n", n, what,
                            f.evaluation, f.seconds, family_name, o.seed, f.start_index);
        if (!f.found_eval.detail.empty()) text += fmt::format("#   {}\n", f.found_eval.detail);
        text += fmt::format("#   shrunk from {} to {} significant bits, still {}\n", f.found_bits, f.shrunk_bits,
                            shrunk_what);
        text += format_case_line(shrunk) + '\n';
        text += fmt::format("# find {} as found, before shrinking:\n", n);
        text += format_case_line(found) + '\n';

        fmt::print("find {}: {} at evaluation {} ({:.3f} s)\n", n, what, f.evaluation, f.seconds);
        if (!f.found_eval.detail.empty()) fmt::print("  {}\n", f.found_eval.detail);
        fmt::print("  shrunk ({} -> {} significant bits, still {}):\n  {}\n", f.found_bits, f.shrunk_bits,
                   shrunk_what, format_case_line(shrunk));
    }
    if (result.finds.empty())
        fmt::print("{}\n", ulp ? "no agreeing answer with a nonzero error was seen" : "no disagreement found");
    write_file_atomically(o.output, text);
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
    sub->add_option("--seconds", o->budget, "Search time in seconds (0: no time limit)")->capture_default_str();
    add_deprecated_alias(sub, "--budget", o->budget, "--seconds");
    sub->add_option("--evaluations", o->evaluations,
                    "Search evaluations (0: no limit); with --seconds 0 the result is reproducible")
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
    sub->add_option("-o,--output", o->output, "Corpus file to write the finds to (atomically)")->required();
    return {sub, [o, command_line] { return run(*o, command_line); }};
}

}  // namespace rayverify::cli
