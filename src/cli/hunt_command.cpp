#include <algorithm>
#include <array>
#include <optional>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "cli/app.h"
#include "cli/commands.h"
#include "cli/shipped_libraries.h"
#include "cli/terminal.h"
#include "compare/hunt.h"
#include "core/input_error.h"
#include "corpus/corpus_io.h"
#include "corpus/exchange.h"
#include "corpus/external_program.h"
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
    bool family_given = false;
    // The user's own cases the searches start from (--corpus), instead of a family's.
    std::vector<std::string> corpus;
    std::string accuracy;  // --accuracy: the contract's accuracy clause for the target
    double budget = 10;
    std::uint64_t evaluations = 0;
    std::string objective = "ulp";
    std::string strategy = "search";
    std::uint64_t seed = 1;
    std::size_t finds = 3;
    bool no_shrink = false;
    bool rounding_only = false;
    std::string cause;
    std::string output;
    std::string shard;
    // An external program hunted instead (corpus/external_program.h).
    std::string command;
    std::string contract_spec, name;
    std::string format = "jsonl";
    double command_timeout = 10;
    std::size_t batch = 0;  // 0: 1 for a variant or plugin, 64 for a command
    bool precision_given = false;
    std::string engine;     // an engine's library as shipped: a plugin or a program (cli/shipped_libraries.h)
};

// An --engine hunted as what it is: its plugin, or its program with the
// contract, name and precision it states.
hunt_command_options with_engine(hunt_command_options o, std::optional<library_identity>& library) {
    if (o.engine.empty()) return o;
    if (!o.variant.empty() || !o.plugin.empty() || !o.command.empty())
        throw input_error("", 0, "--engine",
                          "name exactly one target: --variant NAME, --plugin LIBRARY, --command 'PROGRAM' or "
                          "--engine NAME");
    const shipped_library lib = available_library(o.engine);
    library = lib.identity;
    if (lib.how == shipped_library::runner::plugin) {
        o.plugin = lib.plugin.string();
        return o;
    }
    const std::string prec(precision_name(lib.precisions.front()));
    if (o.precision != prec && o.precision_given)
        throw input_error("", 0, "--precision", fmt::format("engine library '{}' computes in {}", lib.name, prec));
    o.precision = prec;
    o.command = lib.command;
    o.contract_spec = lib.contract;
    o.name = lib.name;
    o.command_timeout = std::max(o.command_timeout, 60.0);  // node starts the library within the first batch
    return o;
}


// The one target hunted: a variant, a plugin or a program (--command), in the
// precision given. Without --precision, a variant or plugin is hunted in
// double where it runs in double and in float where it runs in float alone (a
// float-only plugin, as audit and explain choose); a program in double.
audit_target hunt_target(const hunt_command_options& o, const std::optional<library_identity>& library) {
    if (int(!o.variant.empty()) + int(!o.plugin.empty()) + int(!o.command.empty()) != 1)
        throw input_error("", 0, "--variant",
                          "name exactly one target: --variant NAME, --plugin LIBRARY, --command 'PROGRAM' or --engine NAME");
    const std::vector<std::string> names = o.variant.empty() ? std::vector<std::string>{} : std::vector{o.variant};
    const std::vector<std::string> plugins = o.plugin.empty() ? std::vector<std::string>{} : std::vector{o.plugin};
    const std::vector<std::string> precisions = o.precision_given ? std::vector{o.precision} : precision_names();
    std::vector<audit_target> targets =
        o.command.empty() ? select_targets(names, plugins, precisions, o.isolation)
                          : std::vector<audit_target>{outside_target(o.name, o.contract_spec, "command " + o.command,
                                                                     named_precision(o.precision))};
    if (targets.empty())
        throw input_error("", 0, "--precision",
                          fmt::format("{} does not run in {}", o.variant.empty() ? o.plugin : o.variant, o.precision));
    const auto in_double = std::ranges::find(targets, precision::binary64, &audit_target::prec);
    if (in_double != targets.end()) std::swap(targets.front(), *in_double);
    targets.erase(targets.begin() + 1, targets.end());
    if (library) targets.front().subject.library = library;
    require_clauses(std::span(targets.begin(), 1), o.accuracy, {});
    check_fp_environment_targets(o.isolation.environment, targets);
    return targets.front();
}

const family_info& hunt_family(const std::string& name) {
    const family_info* family = find_generator_family(name);
    if (family != nullptr) return *family;
    std::string known;
    for (const family_info& f : generator_families()) known += (known.empty() ? "" : ", ") + std::string(f.name);
    throw input_error("", 0, "--family", fmt::format("unknown generator family '{}' (known: {})", name, known));
}

// The search as the options ask for it (objective, causes, strategy, this
// shard's seed, the budgets, shrinking and the batch size).
hunt_options hunt_options_of(const hunt_command_options& o, const shard_spec& shard) {
    hunt_options options;
    options.objective = *hunt_objective_from_name(o.objective);  // checked by CLI11
    options.rounding_only = o.rounding_only || o.cause == "rounding";
    if (o.cause == "algorithmic") options.only_cause = disagreement_cause::algorithmic;
    options.strategy = *hunt_strategy_from_name(o.strategy);  // checked by CLI11
    options.seed = shard_search_seed(o.seed, shard.index, shard.count);
    options.max_seconds = o.budget;
    options.max_evaluations = o.evaluations;
    options.max_finds = o.finds;
    options.shrink = !o.no_shrink;
    options.batch = o.batch ? o.batch : (o.command.empty() ? 1 : 64);
    return options;
}

// This shard's start cases: the family's cases K − 1, K − 1 + N, ...,
// generated a block of 64 at a time, four side by side (seeding a random
// engine per case is a large part of a random hunt's time).
class shard_start_cases {
public:
    shard_start_cases(std::string family, std::uint64_t seed, const shard_spec& shard)
        : family_(std::move(family)), seed_(seed), shard_(shard) {}
    ray_sphere<double> operator()(std::uint64_t j) {
        const std::uint64_t first = j - j % block_size;
        if (block_first_ != first) {
            std::array<std::size_t, block_size> indices{};
            for (std::uint64_t k = 0; k < block_size; ++k) indices[k] = shard_.global_index(first + k);
            block_.clear();
            append_generated_cases(family_, seed_, indices, block_);
            block_first_ = first;
        }
        const corpus_case& c = block_[j - first];
        return c.is_segment() ? segment_search_inputs(c) : c.geometry;
    }

private:
    static constexpr std::uint64_t block_size = 64;
    std::string family_;
    std::uint64_t seed_;
    shard_spec shard_;
    std::vector<corpus_case> block_;
    std::optional<std::uint64_t> block_first_;
};

// A program's answers judged a batch at a time (--command).
hunt_judge program_judge(external_program& program, const audit_target& target, const std::string& command,
                         hunt_objective objective) {
    return [&program, &target, command, objective](std::span<const corpus_case> cases) {
        audit_target answered = target;
        answered.recorded = program.answer(cases);
        try {
            check_recorded_values(target.subject.promises, *answered.recorded);
        } catch (const input_error& e) {  // named with its batch, as any answer that is not one
            throw case_failure("", "--command",
                               fmt::format("command '{}' left out a value its contract needs ({})", command, e.what()),
                               cases.empty() ? corpus_case{} : cases.front());
        }
        std::vector<hunt_evaluation> evals;
        for (const corpus_case& c : cases) evals.push_back(evaluate_for_hunt(answered, c, objective));
        return evals;
    };
}

// What the hunt found, as printed: each find as found and shrunk, or that
// none was, and the first disagreement of an error hunt.
void print_finds(const hunt_result& result, const hunt_file& file, const hunt_options& options) {
    const bool ulp = maximises_error(options.objective);
    const auto failure = [](const hunt_evaluation& e) {
        std::string text(verdict_name(e.verdict));
        if (e.cause) text += fmt::format(" ({})", cause_name(*e.cause));
        return text;
    };
    for (std::size_t i = 0; i < result.finds.size(); ++i) {
        const hunt_find& f = result.finds[i];
        const std::string what =
            ulp ? fmt::format("agree, {} (lower bound)", hunt_error_text(options.objective, f.found_eval.error))
                : failure(f.found_eval);
        const std::string shrunk_what =
            ulp ? fmt::format("agree, {}", hunt_error_text(options.objective, f.shrunk_eval.error)) : failure(f.shrunk_eval);
        fmt::print("find {}: {} at evaluation {} ({:.3f} s)\n", i + 1, what, f.evaluation, f.seconds);
        if (!f.found_eval.detail.empty()) fmt::print("  as found: {}\n", f.found_eval.detail);
        // The line printed is the shrunk case, and what it replays as is said under it.
        const hunt_find_provenance& p = file.finds[i].provenance;
        if (p.inputs_changed && p.steps_from_start)
            fmt::print("  shrunk toward {} ({} of the ten inputs differ from it, by {} steps in all; still {}):\n  {}\n",
                       p.start, *p.inputs_changed, *p.steps_from_start, shrunk_what,
                       format_case_line(file.finds[i].shrunk));
        else
            fmt::print("  shrunk ({} -> {} significant bits, still {}):\n  {}\n", f.found_bits, f.shrunk_bits,
                       shrunk_what, format_case_line(file.finds[i].shrunk));
        if (!f.shrunk_eval.detail.empty()) fmt::print("  replays as: {}\n", f.shrunk_eval.detail);
    }
    if (result.finds.empty())
        fmt::print("{}\n", ulp ? "no agreeing answer with a nonzero error was seen" : "no disagreement found");
    // An answer that disagrees has no ULP error to maximise, but it is a finding, never a pass.
    if (const auto& d = file.hunt.runs[0].first_disagreement)
        fmt::print("{} of {} evaluations disagreed with the exact answer; the first ({}) at evaluation {}:\n  {}\n"
                   "  (--objective misclass hunts for them)\n",
                   result.disagreements, result.evaluations, verdict_name(d->verdict), d->evaluation, d->case_line);
}

int run(const hunt_command_options& given, const std::string& command_line) {
    std::optional<library_identity> library;
    const hunt_command_options o = with_engine(given, library);
    const audit_target target = hunt_target(o, library);
    if (!o.corpus.empty() && o.family_given)
        throw input_error("", 0, "--corpus", "the searches start from --corpus or from --family, not both");
    const std::string family_name(o.corpus.empty() ? hunt_family(o.family).name : std::string_view("corpus"));
    std::vector<corpus_case> user_cases;
    if (!o.corpus.empty()) user_cases = read_corpus({o.corpus.begin(), o.corpus.end()});
    // Segments are hunted as segments (their ends moved), rays as rays: one form a hunt.
    const bool segments = o.corpus.empty() ? hunt_family(o.family).segment
                                           : !user_cases.empty() && user_cases.front().is_segment();
    for (const corpus_case& c : user_cases)
        if (c.is_segment() != segments)
            throw input_error(c.source, 0, "--corpus",
                              fmt::format("case '{}' is a {} and '{}' a {}: a hunt searches one form of case, rays "
                                          "or segments (give them in two hunts)",
                                          c.id, c.is_segment() ? "segment" : "ray", user_cases.front().id,
                                          segments ? "segment" : "ray"));
    if (o.budget == 0 && o.evaluations == 0)
        throw input_error("", 0, "--seconds", "give a time budget (--seconds) or an evaluation budget (--evaluations)");
    run_outputs outputs;  // declared before the search, committed after it
    if (!o.plugin.empty()) declare_inputs(outputs, {o.plugin}, "--plugin");
    declare_inputs(outputs, {o.corpus.begin(), o.corpus.end()}, "--corpus");
    output_file& finds_file = outputs.file(o.output, "-o");

    const shard_spec shard = o.shard.empty() ? shard_spec{} : chosen_shard(o.shard, "hunt");
    hunt_options options = hunt_options_of(o, shard);
    options.shrink_toward_start = !user_cases.empty();
    options.segments = segments;
    shard_start_cases start_cases(family_name, o.seed, shard);
    const hunt_start start = [&](std::uint64_t j) {
        if (user_cases.empty()) return start_cases(j);
        const corpus_case& c = user_cases[shard.global_index(j) % user_cases.size()];
        return segments ? segment_search_inputs(c) : c.geometry;
    };
    std::optional<external_program> program;
    hunt_judge judge;
    if (!o.command.empty()) {
        program.emplace(o.command, *exchange_format_from_name(o.format), target.prec, o.command_timeout);
        judge = program_judge(*program, target, o.command, options.objective);
    }
    // Live: how far the budget is spent, and the best found so far.
    const bool timed = o.budget > 0;
    terminal::progress progress("hunt", timed ? "s" : "evaluations",
                                timed ? o.budget : static_cast<double>(o.evaluations));
    options.on_progress = [&](const hunt_progress& p) {
        const std::string best =
            maximises_error(options.objective)
                ? fmt::format("best so far {}", p.best_error > 0 ? hunt_error_text(options.objective, p.best_error) : "-")
                : fmt::format("{} disagreement(s) found", p.finds);
        progress.update(timed ? p.seconds : static_cast<double>(p.evaluations),
                        timed ? fmt::format("{} evaluations, {}", p.evaluations, best) : best);
    };
    const hunt_result result = hunt(target, start, options, judge);
    progress.finish();
    if (program) program->finish();  // nothing may follow its last answer

    std::string shard_note;
    if (shard.count > 1) shard_note = fmt::format(", shard {} (search seed {})", shard.text(), options.seed);
    const std::string start_corpus = fmt::format("{}", fmt::join(o.corpus, " "));
    const std::string starts =
        user_cases.empty() ? fmt::format("family {}, seed {}", family_name, o.seed)
                           : fmt::format("{} start cases from {}, seed {}", user_cases.size(), start_corpus, o.seed);
    fmt::print("hunt {} ({} objective{}, {} strategy, {}{}): {} evaluations, {} starts, {:.2f} s\n", target.label(),
               o.objective,
               o.cause == "algorithmic"                   ? ", algorithmic causes only"
               : o.rounding_only || o.cause == "rounding" ? ", rounding causes only"
                                                          : "",
               o.strategy, starts, shard_note, result.evaluations, result.starts, result.seconds);
    if (program)
        fmt::print("command '{}' answered {} batches of up to {} cases\n", o.command, program->batches(), options.batch);
    hunt_setting setting{recorded_command(command_line), &target, options, family_name, o.seed, shard, nullptr, {}};
    if (!user_cases.empty()) {
        setting.start_cases = &user_cases;
        setting.start_corpus = start_corpus;
    }
    const hunt_file file = hunt_file_of(result, setting);
    print_finds(result, file, options);
    finds_file.stream() << render_hunt_file(file);
    fmt::print("wrote {}\n", o.output);
    check_standard_output();
    outputs.commit();
    const bool disagreement = (!maximises_error(options.objective) && !result.finds.empty()) || result.disagreements > 0;
    return disagreement ? exit_findings : exit_ok;
}

}  // namespace

command add_hunt_command(CLI::App& app, const std::string& command_line) {
    auto o = std::make_shared<hunt_command_options>();
    auto* sub = app.add_subcommand(
        "hunt", "Search for inputs that maximise a variant's error (--objective ulp, scale_radius or scale_distance) "
                "or make it disagree with the exact answer (--objective misclass): random restarts from a family's cases, local search by ulp "
                "moves judged by the exact oracle, then shrinking. Writes the finds as corpus lines. Exit 1 when "
                "a disagreement was found");
    sub->add_option("--variant", o->variant, "Variant to hunt");
    sub->add_option("--plugin", o->plugin,
                    "Hunt a plugin (rayverify_plugin.h) instead: its functions are called through a function pointer");
    add_isolation_options(sub, o->isolation);
    CLI::Option* command = sub->add_option(
        "--command", o->command,
        "Hunt a program instead, in any language: run once with /bin/sh -c, it reads batches of cases on stdin and "
        "answers each on stdout, in --format (docs/other-languages.md); it dying, hanging or answering garbage "
        "is an input error naming it and the case (exit 2)");
    sub->add_option("--contract", o->contract_spec, "With --command: the program's contract, e.g. query=line_roots")
        ->needs(command);
    sub->add_option("--name", o->name, "With --command: the name its finds are reported under")->needs(command);
    sub->add_option("--format", o->format, "With --command: jsonl or csv")
        ->check(CLI::IsMember({"jsonl", "csv"}))
        ->needs(command)
        ->capture_default_str();
    sub->add_option("--command-timeout", o->command_timeout,
                    "With --command: seconds the program may take over one batch before it is killed")
        ->check(finite_number(0.001, 86400))
        ->needs(command)
        ->capture_default_str();
    sub->add_option("--batch", o->batch,
                    "Cases judged together (start cases, or candidates moved from the same case); default 1, and "
                    "64 with --command")
        ->check(whole_number(1, std::uint64_t{1} << 20));
    sub->add_option("--precision", o->precision,
                    "float or double (default: double, or float for a target that computes in float alone)")
        ->check(CLI::IsMember(precision_names()))
        ->each([o](const std::string&) { o->precision_given = true; });
    sub->add_option("--engine", o->engine,
                    "Hunt an engine's library as its package installs it instead (`rayverify engines` lists them)");
    sub->add_option("--family", o->family, "Generator family the searches start from")
        ->capture_default_str()
        ->each([o](const std::string&) { o->family_given = true; });
    sub->add_option("--accuracy", o->accuracy,
                    "The accuracy the target's answers must have (ulp:N, radius:X or distance:X, the contract's "
                    "accuracy clause): under --objective misclass an answer farther from its root is a find "
                    "(`imprecise`)");
    sub->add_option("--corpus", o->corpus,
                    "Start from your own cases instead of a family's (corpus files or directories, repeatable): "
                    "start case j is the file's case j, cycling, and each find is shrunk toward the case it was "
                    "searched from (the least change to your case that fails; their intervals are not used)");
    sub->add_option("--seconds", o->budget, "Search time in seconds (0: no time limit)")
        ->check(finite_number(0, 1e9))
        ->capture_default_str();
    add_deprecated_alias(sub, "--budget", o->budget, "--seconds")->check(finite_number(0, 1e9));
    sub->add_option("--evaluations", o->evaluations,
                    "Search evaluations (0: no limit); with --seconds 0 the result is reproducible")
        ->check(whole_number(0))
        ->capture_default_str();
    sub->add_option("--objective", o->objective,
                    "ulp (largest ULP error), scale_radius (largest |t - t*|·|d|/r, which does not explode as t* -> 0), "
                    "scale_distance (largest |t - t*|·|d|/|o - c|) or misclass (disagreements)")
        ->check(CLI::IsMember(hunt_objective_names()))
        ->capture_default_str();
    sub->add_flag("--rounding-only", o->rounding_only,
                  "misclass: keep only disagreements whose cause is rounding (not by design: clamp, contract "
                  "semantics, unit direction, tangent threshold, line not ray)");
    sub->add_option("--cause", o->cause,
                    "misclass: keep only disagreements of this cause: algorithmic (rounding a backward-stable formula "
                    "avoids: fix the formula) or rounding (either rounding cause: as --rounding-only)")
        ->check(CLI::IsMember({"algorithmic", "rounding"}));
    sub->add_option("--strategy", o->strategy, "search, or random (plain sampling of the family: the baseline)")
        ->check(CLI::IsMember(hunt_strategy_names()))
        ->capture_default_str();
    sub->add_option("--seed", o->seed, "Seed of the start cases and of the search")
        ->check(whole_number(0))
        ->capture_default_str();
    sub->add_option("--finds", o->finds, "misclass: stop after this many disagreements")
        ->check(whole_number(1, 1000000))
        ->capture_default_str();
    sub->add_flag("--no-shrink", o->no_shrink, "Keep the finds as found");
    sub->add_option("--shard", o->shard,
                    "Be shard K of N independent hunts (K/N, auto or auto/N as for audit): start from the family's "
                    "cases K-1, K-1+N, ... and search with a seed derived from --seed and K; each shard has the "
                    "whole budget. `rayverify merge` keeps the worst finds of the N output files");
    sub->add_option("-o,--output", o->output, "Corpus file to write the finds to (atomically)")->required();
    return {sub, [o, command_line] { return run(*o, command_line); }};
}

}  // namespace rayverify::cli
