// The rayverify subcommands. Each registers its options on the CLI11 app and
// returns the process exit code: 0 ok, 1 findings, 2 usage or input error
// (input errors are thrown as input_error and mapped to 2 in main).
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>

#include "cli/terminal.h"
#include "compare/audit.h"
#include "corpus/case_stream.h"
#include "corpus/exchange.h"
#include "core/exit_codes.h"
#include "core/outputs.h"
#include "plugin/plugin_loader.h"
#include "report/markdown_report.h"
#include "scene/scene.h"

namespace rayverify::cli {

using rayverify::exit_findings;
using rayverify::exit_input_error;
using rayverify::exit_internal_error;
using rayverify::exit_ok;

// A subcommand: its parser and the action run when it was chosen.
struct command {
    CLI::App* parser = nullptr;
    std::function<int()> run;
};

command add_variants_command(CLI::App& app);
command add_engines_command(CLI::App& app);  // cli/engines_command.cpp
command add_audit_command(CLI::App& app, const std::string& command_line);
command add_explain_command(CLI::App& app);
command add_corpus_command(CLI::App& app);
command add_export_subcommand(CLI::App* corpus);  // `corpus export` (cli/export_command.cpp)
command add_bench_command(CLI::App& app, const std::string& command_line);
command add_hunt_command(CLI::App& app, const std::string& command_line);
command add_gate_command(CLI::App& app);
command add_diff_command(CLI::App& app);
command add_merge_command(CLI::App& app);
command add_render_command(CLI::App& app);  // cli/render_command.cpp
command add_recommend_command(CLI::App& app);  // cli/recommend_command.cpp
command add_builds_command(CLI::App& app, const std::string& command_line);  // cli/builds_command.cpp

// `merge` of hunt outputs (cli/hunt_merge.cpp): the files of one sharded
// hunt, every shard once, as one hunt file at `output` keeping the `keep`
// worst finds. Returns exit_findings when a disagreement is kept.
int merge_hunts(const std::vector<std::string>& files, const std::string& output, std::size_t keep);
// Targets answered outside rayverify's process (audit, gate, explain, audit
// --scene): a results file (--results FILE --contract SPEC --name NAME), a
// program asked batch by batch (--command PROGRAM --contract SPEC --name
// NAME), and the engines' libraries as shipped (--engine NAME: a plugin or a
// program, cli/shipped_libraries.h).
struct results_options {
    std::string file, contract_spec, name;
    std::string command;
    std::string format = "jsonl";  // of --command's batches
    // Seconds a --command program or an engine's program may take over one
    // batch before it is killed; unset: 60 for --command, 300 for an engine.
    std::optional<double> command_timeout;
    std::vector<std::string> engines;
    // --accuracy: the accuracy clause (core/contract.h) required of every
    // target that returns a t; empty: each target's own contract's.
    std::string accuracy;
    // --degenerate miss|invalid: the degenerate clause for every target; empty: each target's own.
    std::string degenerate;
};

// The clauses the user requires of every target, replacing those its
// contract names: `--accuracy` for each target that returns a t (not
// any_hit), `--degenerate` for all; nothing for an option not given. A
// malformed clause is an input error naming the option.
void require_clauses(std::vector<audit_target>& targets, const results_options& options);
// The same from the two options' texts (empty: not given).
void require_clauses(std::span<audit_target> targets, const std::string& accuracy, const std::string& degenerate);

// `audit --scene FILE` (cli/scene_audit.cpp), called by the audit command.
struct scene_audit_request {
    std::string scene_file;
    std::vector<std::string> variants, plugins, precisions;
    plugin_isolation isolation;
    std::string report_dir;    // scene_report.json goes there when not empty
    std::string command_line;
    results_options results;  // answers for the scene's (ray, sphere) pairs
    oracle_route route = oracle_route::filtered;
};
int run_scene_audit(const scene_audit_request& request);
// The chosen variants (all by default), each in the scene's precision.
std::vector<audit_target> scene_audit_targets(const scene& s, const std::vector<std::string>& variant_names,
                                              const std::vector<std::string>& plugin_paths,
                                              const plugin_isolation& isolation = {},
                                              const std::vector<std::string>& engine_names = {});

// The corpus a command reads when given none: the installed copy
// (<prefix>/share/rayverify/corpus) when this executable is the installed
// one, else the corpus/ of the source tree this build was configured from.
std::string default_corpus();

// The precision --precision names ("float" or "double", precision_from_name);
// any other name is a usage error (exit 2), never a default.
precision named_precision(std::string_view name);
// Every precision's name, in the table's order: what --precision accepts.
std::vector<std::string> precision_names();

// Shared by the commands: the targets named by --variant and --precision
// (all of them when empty). Throws input_error for an unknown name.
// (--engine NAME: the libraries called through plugins are chosen here, those
// run as programs by outside_targets.)
std::vector<audit_target> select_targets(const std::vector<std::string>& variant_names,
                                         const std::vector<std::string>& precisions);

// The same with --plugin libraries (plugin/plugin_loader.h) after the named
// variants, loaded as `isolation` says, then the --engine libraries that are
// plugins. With plugins or engines and no --variant, only those are chosen.
// Two targets with one name are an input error.
std::vector<audit_target> select_targets(const std::vector<std::string>& variant_names,
                                         const std::vector<std::string>& plugin_paths,
                                         const std::vector<std::string>& precisions,
                                         const plugin_isolation& isolation = {},
                                         const std::vector<std::string>& engine_names = {});

// Every variant of `variants` in each precision it runs in, float first,
// kept when --precision (`precisions`, names) chose it or chose none.
std::vector<audit_target> targets_in_precisions(std::span<const variant> variants,
                                                const std::vector<std::string>& precisions);

// The cases a command reads: corpus files (the shipped corpus when neither is
// given) or generated families (cli/results_target.cpp).
struct case_input {
    std::vector<std::filesystem::path> paths;
    std::vector<generate_spec> specs;
    case_stream open(shard_spec shard = {}) const;
};
// Throws input_error when both --corpus and --generate are given, or a spec is malformed.
case_input select_input(const std::vector<std::string>& corpus, const std::vector<std::string>& generate);

// Every (ray, sphere) pair a scene's rays meet, as cases, in ray order.
std::vector<corpus_case> scene_cases(const scene& s);
// The fingerprint of cases held in memory, as case_stream computes it for files.
std::string fingerprint_of(std::span<const corpus_case> cases);

void add_results_options(CLI::App* sub, results_options& options);
// Declares the results file (and an npy's JSON companion) as inputs of the
// run, so that no output overwrites them.
void declare_results_inputs(run_outputs& outputs, const results_options& options);

// The targets answered outside rayverify's process, in this order: the
// results file, the --command program, the --engine libraries run as
// programs; none without those options. `feed` passes every case of the
// command's input, in order, to its argument and returns the input's
// fingerprint (it is called once per target). Answers that do not match that
// input exactly are an input_error (corpus/exchange.h), before anything is
// judged; the input is read first, so that a file is read only as far as it
// answers cases of it. A program answers the input in batches, in one
// precision: the one --precision names (double when none), or the scene's
// (`scene_precision`); an engine's program in its own, left out when
// --precision leaves that out, and not run on a scene of another precision
// (its target then has no answers, and the scene audit says why).
// With programs_answer::chunk_by_chunk (audit), a program is started here
// but asked nothing: the audit asks it each chunk's cases as it judges them
// (audit_target::answer_chunk), and calls finish_outside_answers at the end.
using case_sink = std::function<void(const corpus_case&)>;
using case_feed = std::function<std::string(const case_sink&)>;
enum class programs_answer { whole_input_first, chunk_by_chunk };
std::vector<audit_target> outside_targets(const results_options& options, const std::vector<std::string>& precisions,
                                          const case_feed& feed,
                                          std::optional<precision> scene_precision = std::nullopt,
                                          programs_answer how = programs_answer::whole_input_first);
// After the last chunk: every chunk-by-chunk program must have said nothing more.
void finish_outside_answers(const std::vector<audit_target>& targets);

// A target answering from outside rayverify (a results file, a --command):
// its name (one token, not a built-in's), contract spec (core/contract.h's
// parse_contract) and precision; no functions.
audit_target outside_target(const std::string& name, const std::string& contract_spec, const std::string& citation,
                            precision prec);

// `outside` after `targets`; a name both use is an input error (field --name).
void append_outside_targets(std::vector<audit_target>& targets, const std::vector<audit_target>& outside);

// select_targets (with `options.engines`), then the outside targets; with
// outside targets and no --variant, --plugin or --engine, those alone.
std::vector<audit_target> targets_with_results(const std::vector<std::string>& variant_names,
                                               const std::vector<std::string>& plugin_paths,
                                               const std::vector<std::string>& precisions,
                                               const plugin_isolation& isolation, const results_options& options,
                                               const std::vector<audit_target>& outside);

// Checks of a numeric option's text (cli/numeric_options.cpp), for every
// numeric option: a whole number in [min, max] written in plain digits (no
// sign, so "-5" is refused instead of wrapping; 2^64 and above refused), or a
// finite number in [min, max] (> min when `above_min`; nan and inf refused).
CLI::Validator whole_number(std::uint64_t min, std::uint64_t max = std::numeric_limits<std::uint64_t>::max());
CLI::Validator finite_number(double min, double max, bool above_min = false);
// The one spelling of a numeric option's limits, in its help and its errors:
// "KIND ≥ MIN and ≤ MAX" (> MIN when `above_min`, < MAX when `below_max`).
std::string numeric_limits_text(std::string_view kind, std::string_view min, bool above_min, std::string_view max,
                                bool below_max = false);

// The audit's progress line on a terminal (cli/audit_progress.cpp): cases
// done out of the input's cases (generated: their counts; files: their case
// lines), % and ETA; finished on destruction.
class audit_progress {
public:
    audit_progress(const std::vector<std::filesystem::path>& paths, const std::vector<generate_spec>& specs,
                   const shard_spec& shard);
    // For audit_hooks::progress; empty when no one watches stderr.
    std::function<void(std::size_t)> reporter();
    void finish() { line_.finish(); }

private:
    terminal::progress line_;
};

// --tolerance, on gate and diff: ULP figures within it (relative) are equal.
void add_tolerance_option(CLI::App* sub, double& tolerance);

// --isolate, --plugin-timeout and --fp-env, on every command that takes --plugin.
void add_isolation_options(CLI::App* sub, plugin_isolation& isolation);

// --fp-env: one value ("ftz+daz", or "TARGET=ftz+daz") into `choice`; throws
// input_error (field --fp-env) for a name that is no environment, one this
// machine cannot set, or a second one for the same scope.
void add_fp_environment(fp_environment_choice& choice, const std::string& value);
// The state of a spec this machine can set; input_error (--fp-env) otherwise.
fp_state settable_fp_state(const fp_environment_spec& spec);
// Every TARGET=ENV names a target of `targets` run in this process (not one
// answering from a results file, a program or a JavaScript engine); an
// environment for every target is noted on stderr for those it cannot reach.
void check_fp_environment_targets(const fp_environment_choice& choice, const std::vector<audit_target>& targets);

// Shared by audit and hunt (cli/audit_command.cpp): the shard `--shard`
// names, "K/N", "auto" or "auto/N" (corpus/shard_environment.h); an automatic
// choice is reported on stderr, prefixed by the command's name.
shard_spec chosen_shard(const std::string& text, const char* command);

// Shared by audit, hunt and merge (cli/audit_command.cpp).
// The command line as reports record it: without --threads, --shard,
// --report, --per-case, -o/--output, --plots, --summary, --summary-md, --isolate and
// --plugin-timeout, which change where outputs go or how the work is spread or run, never a figure.
std::string recorded_command(const std::string& command_line);

// cli/command_spelling.cpp: comparing the recorded commands of shards.
// A command line's words (main joins argv with single spaces).
std::vector<std::string> command_words(const std::string& command_line);
// A recorded command without what the shards of one run may spell
// differently: the executable's path is dropped and the value of --corpus,
// --plugin and --scene becomes PATH; `--option=value` is split in two.
std::vector<std::string> normalised_command(const std::string& recorded);
// nullopt when two recorded commands are equal once normalised; else which
// options only `a` and only `b` have (or that their order differs), naming
// them by `a_name` and `b_name`.
std::optional<std::string> command_difference(const std::string& a, const std::string& b, const std::string& a_name,
                                              const std::string& b_name);

// An audit's outputs, declared before the work (core/outputs.h): the
// report directory (report.json, report.md, summary.txt, the plots) and the
// per-case file. They appear together when publish_audit commits them, or not
// at all.
struct audit_outputs {
    run_outputs files;
    std::optional<report_bundle> report;
    output_file* summary = nullptr;   // in the report directory
    output_file* table_csv = nullptr; // audit.csv, in the report directory (report/table_csv.h)
    output_file* per_case = nullptr;  // --per-case
    output_file* summary_md = nullptr;  // --summary-md
    // Declares the report directory and its files (nothing when `dir` is empty).
    void open_report(const std::filesystem::path& dir, const std::string& option);
};

// How an audit's results are shown beside its report files (audit and merge;
// cli/report_options.cpp).
struct audit_presentation {
    bool summary = false;    // --summary: one line per variant family instead of the full table
    std::string summary_md;  // --summary-md FILE: the headline and compact table of report.md
};
void add_presentation_options(CLI::App* sub, audit_presentation& presentation);
// Declares --summary-md's file as an output of the run when one is named.
void open_presentation(audit_outputs& outputs, const audit_presentation& presentation);

// One line per target that is a library as shipped: its name, version and source.
void print_libraries(const std::vector<audit_target>& targets);

// Writes the report files, prints the summary table or one line per variant
// family (and where the report went), checks standard output, commits the
// outputs, and returns
// exit_findings when any target disagrees with the oracle on some case.
// `hints`: the contract lint's lines (report/contract_hints.h), printed after the table.
// `report` is taken whole (a large document: the plot sample, every target's
// tallies) and moved into report.json rather than copied.
int publish_audit(const audit_totals& totals, std::optional<nlohmann::ordered_json> report,
                  audit_outputs& outputs, bool plots, const audit_presentation& presentation = {},
                  const std::string& hints = {});

// Files a command reads (corpus files and directories, plugins, a baseline,
// a scene), declared as inputs of its run so that no output overwrites them;
// a directory among them is a corpus directory.
void declare_inputs(run_outputs& outputs, const std::vector<std::filesystem::path>& paths, const std::string& option);
// The digest (core/hash.h) of the files' contents, one after the other, read
// in pieces; a file that cannot be read is an input_error naming `option`.
std::string files_digest(const std::vector<std::filesystem::path>& paths, const std::string& option);
// A baseline or other small text input read whole (cli/gate_command.cpp): a
// directory, a FIFO, a device or a file that cannot be read is an input_error
// naming it and `field`.
std::string read_text_file(const std::filesystem::path& path, const std::string& field);

}  // namespace rayverify::cli
