// rayverify: audit floating-point ray–sphere intersectors against exact arithmetic.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cerrno>
#include <cstdio>
#include <exception>
#include <new>
#include <sstream>
#include <system_error>

#include "cli/app.h"
#include "cli/commands.h"
#include "cli/manual.h"
#include "cli/terminal.h"
#include "core/child_processes.h"
#include "core/input_error.h"
#include "core/outputs.h"
#include "corpus/corpus_io.h"
#include "plugin/plugin_loader.h"

namespace {

// The case an intersector failed on as a line to paste into a corpus; an id
// that could not be read back as one token is replaced.
std::string corpus_line_of(rayverify::corpus_case c) {
    try {
        return rayverify::format_case_line(c);
    } catch (const rayverify::input_error&) {
        c.id = "plugin-failure";
        c.family.clear();
        return rayverify::format_case_line(c);
    }
}

// A message on stderr; never throws (stderr may be as full as stdout).
void tell(const std::string& text) { std::fputs(text.c_str(), stderr); }

// --help and --version: printed, then standard output checked (--help into a full disk is exit 2).
// The text is written in one call, so that the error of a failed write is
// the one reported (a long help fails inside the write, not at the flush).
int printed(const CLI::App& app, const CLI::ParseError& e) {
    std::ostringstream text, errors;
    app.exit(e, text, errors);
    tell(errors.str());
    const std::string out = text.str();
    errno = 0;
    if (std::fwrite(out.data(), 1, out.size(), stdout) != out.size() || std::fflush(stdout) != 0 ||
        rayverify::standard_output_closed_by_reader()) {
        const int error = rayverify::standard_output_closed_by_reader() ? EPIPE : errno;
        tell(fmt::format("rayverify: error: standard output: cannot write: {}\n",
                         error != 0 ? std::generic_category().message(error) : std::string("a write failed")));
        return rayverify::cli::exit_input_error;
    }
    return rayverify::cli::exit_ok;
}

}  // namespace

int main(int argc, char** argv) {
    using namespace rayverify;
    // From here on, an exit() is not the command's own (a plugin's: plugin/plugin_loader.cpp),
    // and a signal removes the outputs a command left unfinished.
    const running_command running;
    guard_standard_output();
    become_child_subreaper();  // what a program started and left behind comes back to rayverify (core/child_processes.h)
    std::string command_line;
    for (int i = 0; i < argc; ++i) command_line += (i ? " " : "") + std::string(argv[i]);

    CLI::App app{"rayverify — the truth about floating-point ray–sphere intersection code.\n"
                 "Exit codes: 0 ok, 1 findings (disagreements with the exact answer), 2 usage or input error, "
                 "3 internal error.",
                 "rayverify"};
    cli::global_options global;
    cli::configure_app(app, global);
    const cli::command commands[] = {cli::add_variants_command(app), cli::add_engines_command(app),
                                     cli::add_audit_command(app, command_line),
                                     cli::add_explain_command(app), cli::add_corpus_command(app),
                                     cli::add_bench_command(app, command_line), cli::add_gate_command(app), cli::add_diff_command(app),
                                     cli::add_hunt_command(app, command_line),
                                     cli::add_merge_command(app),
                                     cli::add_render_command(app), cli::add_recommend_command(app),
                                     cli::add_builds_command(app, command_line)};
    try {
        app.parse(argc, argv);
        if (global.completion.empty() && !global.man && app.get_subcommands().empty())
            throw CLI::RequiredError("a command (rayverify --help lists them)");
    } catch (const CLI::CallForHelp& e) {
        return printed(app, e);
    } catch (const CLI::CallForAllHelp& e) {
        return printed(app, e);
    } catch (const CLI::CallForVersion& e) {
        return printed(app, e);
    } catch (const CLI::ParseError& e) {
        tell(cli::parse_error_text(app, e, std::vector<std::string>(argv + 1, argv + argc)));
        return cli::exit_input_error;
    }
    cli::terminal::configure(global.quiet);
    if (global.completion == "bash") fmt::print("{}", cli::bash_completion(app));
    if (global.completion == "zsh") fmt::print("{}", cli::zsh_completion(app));
    if (global.man) fmt::print("{}", cli::man_page(app));
    if (!global.completion.empty() || global.man) return cli::exit_ok;
    try {
        for (const cli::command& command : commands)
            if (command.parser->parsed()) {
                const int code = command.run();
                check_standard_output_at_exit();  // a lost table is not a success
                return code;
            }
        return cli::exit_input_error;
    } catch (const case_failure& e) {  // an isolated plugin or an external program
        tell(fmt::format("rayverify: error: {}\n  the case, as a corpus line:\n  {}\n", e.what(),
                         corpus_line_of(e.failing_case())));
        return cli::exit_input_error;
    } catch (const input_error& e) {
        tell(fmt::format("rayverify: error: {}\n", e.what()));
        return cli::exit_input_error;
    } catch (const std::system_error& e) {
        // fmt::print throws this when a write to standard output fails.
        if (std::ferror(stdout)) {
            tell(fmt::format("rayverify: error: standard output: cannot write: {}\n", e.code().message()));
            return cli::exit_input_error;
        }
        tell(fmt::format("rayverify: internal error: {}\n", e.what()));
        return cli::exit_internal_error;
    } catch (const std::bad_alloc&) {  // on any thread of the audit: the workers pass theirs on
        tell("rayverify: error: out of memory (std::bad_alloc): give it more memory, or fewer --threads; no output "
             "was written\n");
        return cli::exit_internal_error;
    } catch (const std::exception& e) {
        tell(fmt::format("rayverify: internal error: {}\n", e.what()));
        return cli::exit_internal_error;
    }
}
