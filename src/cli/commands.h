// The rayverify subcommands. Each registers its options on the CLI11 app and
// returns the process exit code: 0 ok, 1 findings, 2 usage or input error
// (input errors are thrown as input_error and mapped to 2 in main).
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>

#include "compare/audit.h"
#include "core/outputs.h"
#include "plugin/plugin_loader.h"
#include "report/markdown_report.h"
#include "scene/scene.h"

namespace rayverify::cli {

inline constexpr int exit_ok = 0;
inline constexpr int exit_findings = 1;
inline constexpr int exit_input_error = 2;

// A subcommand: its parser and the action run when it was chosen.
struct command {
    CLI::App* parser = nullptr;
    std::function<int()> run;
};

command add_variants_command(CLI::App& app);
command add_audit_command(CLI::App& app, const std::string& command_line);
command add_explain_command(CLI::App& app);
command add_corpus_command(CLI::App& app);
command add_bench_command(CLI::App& app, const std::string& command_line);
command add_hunt_command(CLI::App& app, const std::string& command_line);
command add_gate_command(CLI::App& app);
command add_diff_command(CLI::App& app);
command add_merge_command(CLI::App& app);
command add_render_command(CLI::App& app);  // issue 6: cli/render_command.cpp
command add_recommend_command(CLI::App& app);  // issue 6: cli/recommend_command.cpp

// issue 6: `audit --scene FILE` (cli/scene_audit.cpp), called by the audit command.
struct scene_audit_request {
    std::string scene_file;
    std::vector<std::string> variants, plugins, precisions;
    plugin_isolation isolation;
    std::string report_dir;    // scene_report.json goes there when not empty
    std::string command_line;
};
int run_scene_audit(const scene_audit_request& request);
// The chosen variants (all by default), each in the scene's precision.
std::vector<audit_target> scene_audit_targets(const scene& s, const std::vector<std::string>& variant_names,
                                              const std::vector<std::string>& plugin_paths,
                                              const plugin_isolation& isolation = {});

// The corpus a command reads when given none: the installed copy
// (<prefix>/share/rayverify/corpus) when this executable is the installed
// one, else the corpus/ of the source tree this build was configured from.
std::string default_corpus();

// Shared by the commands: the targets named by --variant and --precision
// (all of them when empty). Throws input_error for an unknown name.
std::vector<audit_target> select_targets(const std::vector<std::string>& variant_names,
                                         const std::vector<std::string>& precisions);

// The same with --plugin libraries (plugin/plugin_loader.h) after the named
// variants, loaded as `isolation` says. With plugins and no --variant, only
// the plugins are chosen. Two targets with one name are an input error.
std::vector<audit_target> select_targets(const std::vector<std::string>& variant_names,
                                         const std::vector<std::string>& plugin_paths,
                                         const std::vector<std::string>& precisions,
                                         const plugin_isolation& isolation = {});

// Checks of a numeric option's text (cli/numeric_options.cpp), for every
// numeric option: a whole number in [min, max] written in plain digits (no
// sign, so "-5" is refused instead of wrapping; 2^64 and above refused), or a
// finite number in [min, max] (> min when `above_min`; nan and inf refused).
CLI::Validator whole_number(std::uint64_t min, std::uint64_t max = std::numeric_limits<std::uint64_t>::max());
CLI::Validator finite_number(double min, double max, bool above_min = false);

// --isolate and --plugin-timeout, on every command that takes --plugin.
void add_isolation_options(CLI::App* sub, plugin_isolation& isolation);

// Shared by audit and merge (cli/audit_command.cpp).
// The command line as reports record it: without --threads, --shard,
// --report, --per-case, --plots, --summary, --isolate and --plugin-timeout, which change
// where outputs go or how the work is spread or run, never a figure.
std::string recorded_command(const std::string& command_line);

// An audit's outputs, declared before the work (core/outputs.h): the
// report directory (report.json, report.md, summary.txt, the plots) and the
// per-case file. They appear together when publish_audit commits them, or not
// at all.
struct audit_outputs {
    run_outputs files;
    std::optional<report_bundle> report;
    output_file* summary = nullptr;   // in the report directory
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

// Writes the report files, prints the summary table or one line per variant
// family (and where the report went), checks standard output, commits the
// outputs, and returns
// exit_findings when any target disagrees with the oracle on some case.
int publish_audit(const audit_totals& totals, const std::optional<nlohmann::ordered_json>& report,
                  audit_outputs& outputs, bool plots, const audit_presentation& presentation = {});

// Files a command reads (corpus files and directories, plugins, a baseline,
// a scene), declared as inputs of its run so that no output overwrites them;
// a directory among them is a corpus directory.
void declare_inputs(run_outputs& outputs, const std::vector<std::filesystem::path>& paths, const std::string& option);

}  // namespace rayverify::cli
