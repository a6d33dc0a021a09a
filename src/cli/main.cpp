// rayverify: audit floating-point ray–sphere intersectors against exact arithmetic.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>

#include "cli/app.h"
#include "cli/commands.h"
#include "cli/manual.h"
#include "cli/terminal.h"
#include "core/input_error.h"
#include "corpus/corpus_io.h"
#include "plugin/plugin_loader.h"

namespace {

// The case a plugin failed on as a line to paste into a corpus; an id that
// could not be read back as one token is replaced.
std::string corpus_line_of(rayverify::corpus_case c) {
    try {
        return rayverify::format_case_line(c);
    } catch (const rayverify::input_error&) {
        c.id = "plugin-failure";
        c.family.clear();
        return rayverify::format_case_line(c);
    }
}

}  // namespace

int main(int argc, char** argv) {
    using namespace rayverify;
    std::string command_line;
    for (int i = 0; i < argc; ++i) command_line += (i ? " " : "") + std::string(argv[i]);

    CLI::App app{"rayverify — the truth about floating-point ray–sphere intersection code.\n"
                 "Exit codes: 0 ok, 1 findings (disagreements with the exact answer), 2 usage or input error, "
                 "3 internal error.",
                 "rayverify"};
    cli::global_options global;
    cli::configure_app(app, global);
    const cli::command commands[] = {cli::add_variants_command(app), cli::add_audit_command(app, command_line),
                                     cli::add_explain_command(app), cli::add_corpus_command(app),
                                     cli::add_bench_command(app, command_line), cli::add_gate_command(app), cli::add_diff_command(app),
                                     cli::add_hunt_command(app, command_line),
                                     cli::add_merge_command(app),
                                     cli::add_render_command(app), cli::add_recommend_command(app)};
    try {
        app.parse(argc, argv);
        if (global.completion.empty() && !global.man && app.get_subcommands().empty())
            throw CLI::RequiredError("a command (rayverify --help lists them)");
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        fmt::print(stderr, "{}", cli::parse_error_text(app, e, std::vector<std::string>(argv + 1, argv + argc)));
        return cli::exit_input_error;
    }
    cli::terminal::configure(global.quiet);
    if (global.completion == "bash") fmt::print("{}", cli::bash_completion(app));
    if (global.completion == "zsh") fmt::print("{}", cli::zsh_completion(app));
    if (global.man) fmt::print("{}", cli::man_page(app));
    if (!global.completion.empty() || global.man) return cli::exit_ok;
    try {
        for (const cli::command& command : commands)
            if (command.parser->parsed()) return command.run();
        return cli::exit_input_error;
    } catch (const plugin_failure& e) {
        fmt::print(stderr, "rayverify: error: {}\n  the case, as a corpus line:\n  {}\n", e.what(),
                   corpus_line_of(e.failing_case()));
        return cli::exit_input_error;
    } catch (const input_error& e) {
        fmt::print(stderr, "rayverify: error: {}\n", e.what());
        return cli::exit_input_error;
    } catch (const std::exception& e) {
        fmt::print(stderr, "rayverify: internal error: {}\n", e.what());
        return 3;
    }
}
