// The exit statuses of rayverify, one list (docs/cli.md and docs/outputs.md
// tabulate them): main returns them, and the plugin loader's crash and exit()
// hooks end the process with exit_input_error.
#pragma once

namespace rayverify {

inline constexpr int exit_ok = 0;
inline constexpr int exit_findings = 1;       // disagreements found, a gate failed
inline constexpr int exit_input_error = 2;    // usage, input, a plugin or program that failed, a lost output
inline constexpr int exit_internal_error = 3; // a bug of rayverify's, or out of memory

}  // namespace rayverify
