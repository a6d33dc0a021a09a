// Loading a user's intersector from a shared library (rayverify_plugin.h)
// as a registry variant, so that every command audits it like a built-in.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "core/fp_environment.h"
#include "core/input_error.h"
#include "core/ray_sphere_case.h"
#include "intersectors/registry.h"

namespace rayverify {

// Where a plugin runs. In this process (the default) a crash in it ends
// rayverify, but a signal handler installed with the plugin first writes
// which plugin crashed on which case. Isolated, the library is opened and called in
// a child process of rayverify's own (fork, no exec; one per plugin, for all
// its calls), over a socket; a crash, an exit or a call that takes longer
// than the timeout makes the variant's run function throw plugin_failure.
// The child is forked when the plugin is loaded: load it before starting
// threads, as the CLI does.
struct plugin_isolation {
    bool child_process = false;
    double timeout_seconds = 10;  // child_process: the longest wait for one answer, loading included
    // The floating-point environment the plugin's calls run in, chosen by
    // name (--fp-env); a plugin not named runs in the one its library set
    // when it was loaded (the IEEE default unless it changed it).
    fp_environment_choice environment{};
};

// dlopen the library and wrap its functions as a variant: run_double always,
// run_float when the plugin exports rayverify_plugin_intersect_float. The
// variant's functions keep the library loaded (or its child process running)
// for as long as a copy of them exists. Throws input_error naming the path
// (field "--plugin") when the file is missing, is not a loadable library,
// lacks a required symbol, reports another ABI version, or describes itself
// inconsistently (no name, a name with whitespace, an unknown query kind);
// isolated, also when the child process dies or hangs while loading it.
variant load_plugin(const std::filesystem::path& library, const plugin_isolation& isolation = {});

// `v` with each of its functions run in `environment` on the calling thread
// and the IEEE default restored after every call, whatever the call left, so
// that rayverify's own arithmetic never runs in a target's environment. A
// call that leaves another environment than it was given is named once on
// standard error (it is given its own again before each call). `how` is what
// reports say of the environment (variant::fp_environment).
variant in_fp_environment(variant v, const fp_state& environment, std::string how);

// The version 1 query kind (rayverify_plugin.h) whose contract is `c`, with
// its unit-direction flag and clamp, e.g. "RAYVERIFY_NEAREST_IN_INTERVAL";
// nullopt when no version 1 kind says it (a version 2 spec is needed).
std::optional<std::string> version1_query_name(const contract& c);

// A plugin that loaded but says it cannot run on this machine
// (rayverify_plugin_unavailable: a kernel this CPU lacks, say): bad input,
// like any unusable plugin, told apart so that `rayverify engines` can list
// it as not runnable here rather than broken. Thrown in process only.
class plugin_cannot_run_here : public input_error {
public:
    plugin_cannot_run_here(const std::filesystem::path& library, const std::string& reason)
        : input_error(library.string(), 0, "--plugin", "it cannot run on this machine: " + reason), reason_(reason) {}
    const std::string& reason() const { return reason_; }  // as the plugin gives it

private:
    std::string reason_;
};

// An isolated plugin that was killed by a signal, exited, or gave no answer
// within the timeout, on one call. Bad input, so an input_error naming the
// library (exit 2), whose message says what happened and on which case: the
// case announced on the calling thread (core/case_in_progress.h), else the
// inputs the plugin was given. The case is kept whole so that the CLI can
// print it as a corpus line (failing_case(): the announced case, or, with id
// "plugin-failure" and source "", the inputs as given to the plugin, widened
// to double, with their interval). Once it has failed, the plugin's child process is
// gone and every later call throws again.
class plugin_failure : public case_failure {
public:
    plugin_failure(const std::filesystem::path& library, const std::string& problem, corpus_case failing)
        : case_failure(library.string(), "--plugin", problem, std::move(failing)) {}
};

}  // namespace rayverify
