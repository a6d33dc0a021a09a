// The command-line application around the subcommands: help wrapped to the
// terminal, --version, --quiet, parser errors prefixed "rayverify:" with a
// did-you-mean for a mistyped subcommand or option, deprecated option
// spellings, and the hidden generators of the completions and man page.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <string_view>
#include <vector>

namespace rayverify::cli {

// Options of the application itself, given before or after the subcommand.
struct global_options {
    bool quiet = false;
    std::string completion;  // --generate-completion bash|zsh (hidden)
    bool man = false;        // --generate-man (hidden)
};

// "rayverify 0.1.0" and the build line.
std::string version_text();

// The threads a command runs on: those --threads asked for, or, when it was
// not given (0), every hardware thread (one where their number is unknown).
unsigned thread_count(unsigned requested = 0);

// Sets the help formatter, --version, --quiet and the hidden generators on the
// top-level app. Call before adding the subcommands: they inherit the
// formatter and let unknown options fall through to the app.
void configure_app(CLI::App& app, global_options& options);

// The message for a parse error, "rayverify: error: ..." with a did-you-mean
// when a subcommand or option name is close to the one given, and where to
// find the options. `args` are argv[1..].
std::string parse_error_text(const CLI::App& app, const CLI::ParseError& error, const std::vector<std::string>& args);

// The closest of `candidates` to `word` (edit distance at most 2, or a prefix
// of at least 3 characters); empty when none is.
std::string closest(std::string_view word, const std::vector<std::string>& candidates);

// An old spelling of an option kept working: hidden from help, bound to the
// same variable, and noted on stderr as deprecated (docs/versioning.md).
// Returns the option, for the checks its replacement has.
void note_deprecated(const std::string& command, const std::string& old_names, const std::string& replacement);
template <class T>
CLI::Option* add_deprecated_alias(CLI::App* sub, const std::string& old_names, T& target,
                                  const std::string& replacement) {
    return sub->add_option(old_names, target, "Deprecated: " + replacement)
        ->group("")
        ->each([command = sub->get_name(), old_names, replacement](const std::string&) {
            note_deprecated(command, old_names, replacement);
        });
}

}  // namespace rayverify::cli
