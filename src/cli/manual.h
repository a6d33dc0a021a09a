// The bash and zsh completion scripts and the man page, generated from the
// CLI11 definition of every subcommand and option (CLI11 2.1.2 has no
// generators of its own). The build runs `rayverify --generate-completion
// bash|zsh` and `rayverify --generate-man`; cmake --install installs them.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace rayverify::cli {

std::string bash_completion(const CLI::App& app);
std::string zsh_completion(const CLI::App& app);
std::string man_page(const CLI::App& app);

}  // namespace rayverify::cli
