// The rayverify subcommands. Each registers its options on the CLI11 app and
// returns the process exit code: 0 ok, 1 findings, 2 usage or input error
// (input errors are thrown as input_error and mapped to 2 in main).
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <string>
#include <vector>

#include "compare/audit.h"

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

// Shared by the commands: the targets named by --variant and --precision
// (all of them when empty). Throws input_error for an unknown name.
std::vector<audit_target> select_targets(const std::vector<std::string>& variant_names,
                                         const std::vector<std::string>& precisions);

// The same with --plugin libraries (plugin/plugin_loader.h) after the named
// variants. With plugins and no --variant, only the plugins are chosen. Two
// targets with one name are an input error.
std::vector<audit_target> select_targets(const std::vector<std::string>& variant_names,
                                         const std::vector<std::string>& plugin_paths,
                                         const std::vector<std::string>& precisions);

}  // namespace rayverify::cli
