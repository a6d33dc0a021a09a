// The rayverify subcommands. Each registers its options on the CLI11 app and
// returns the process exit code: 0 ok, 1 findings, 2 usage or input error
// (input errors are thrown as input_error and mapped to 2 in main).
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <string>
#include <vector>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>

#include "compare/audit.h"
#include "corpus/case_stream.h"
#include "plugin/plugin_loader.h"
#include "report/atomic_file.h"
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

// `merge` of hunt outputs (cli/hunt_merge.cpp): the files of one sharded
// hunt, every shard once, as one hunt file at `output` keeping the `keep`
// worst finds. Returns exit_findings when a disagreement is kept.
int merge_hunts(const std::vector<std::string>& files, const std::string& output, std::size_t keep);

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

// --isolate and --plugin-timeout, on every command that takes --plugin.
void add_isolation_options(CLI::App* sub, plugin_isolation& isolation);

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

// An audit's output files, opened (as temporaries) before the work.
// A report directory that open_report had to create is removed again (when
// empty) unless publish_audit committed into it, so a failed audit leaves no
// directory behind either.
struct audit_outputs {
    struct created_directory {
        std::filesystem::path path;  // empty: nothing was created
        bool keep = false;
        // Creates `dir` (and its parents) for --report, remembering it when it
        // did not exist. Throws input_error when it cannot be created.
        void create(const std::filesystem::path& dir);
        created_directory() = default;
        created_directory(const created_directory&) = delete;
        created_directory& operator=(const created_directory&) = delete;
        ~created_directory();
    };
    std::filesystem::path dir;
    created_directory created;  // declared first: removed after the temporaries inside it
    std::optional<atomic_file> per_case, report_json, summary, summary_md;
    void open_report(const std::filesystem::path& report_dir);  // nothing when empty
};

// An output path naming an existing directory fails before the work, not at
// the rename after it (input_error naming `option`).
void refuse_directory(const std::filesystem::path& path, const char* option);

// How an audit's results are shown beside its report files (audit and merge;
// cli/report_options.cpp).
struct audit_presentation {
    bool summary = false;    // --summary: one line per variant family instead of the full table
    std::string summary_md;  // --summary-md FILE: the headline and compact table of report.md
};
void add_presentation_options(CLI::App* sub, audit_presentation& presentation);
// Opens --summary-md's file (as a temporary) when one is named.
void open_presentation(audit_outputs& outputs, const audit_presentation& presentation);

// Commits the outputs (report.json and summary.txt when the report is open,
// the Markdown summary when asked), prints the summary table (or one line per
// variant family), renders report.md (and the plots), and returns
// exit_findings when any target disagrees with the oracle on some case.
int publish_audit(const audit_totals& totals, const std::optional<nlohmann::ordered_json>& report,
                  const std::filesystem::path& report_dir, audit_outputs& outputs, bool plots,
                  const audit_presentation& presentation = {});

}  // namespace rayverify::cli
