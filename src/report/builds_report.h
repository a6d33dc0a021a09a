// `rayverify builds`' results (docs/builds.md) as one JSON object, report.json's
// "builds", rendered from it as text (the command's output) and as report.md's
// section: per build its compile commands and outcome, and per precision its
// answers and verdicts against the reference build's, the worst flipped cases
// with the command that explains each, and the bisect's smallest set of flags.
#pragma once

#include <cstddef>
#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <vector>

#include "compare/build_comparison.h"

namespace rayverify {

// The bisect of one build: the smallest set of its flag components that
// reproduces its changed answers, and per kind of verdict flip the smallest
// set that reproduces the answers of those cases.
struct build_bisect_result {
    std::vector<std::string> components;  // what was searched over, as printed
    std::string searched;                 // "the components of its flags" or why its own flags instead
    std::vector<std::string> smallest;
    std::size_t cases = 0;                // changed answers the candidates were run on
    std::size_t builds_tried = 0;
    struct by_flip {
        verdict_kind reference = verdict_kind::agree, build = verdict_kind::agree;
        std::size_t cases = 0;
        std::vector<std::string> smallest;
    };
    std::vector<by_flip> flips;
    std::string failure;  // set when the bisect could not run (a candidate did not build or load)
};

// One build's row as the command assembled it.
struct build_row {
    std::string name, compiler, compiler_version, flags;
    bool reference = false;
    bool cached = false;
    // refused_by_source: it did not compile because the source's #error
    // refuses the build (robust_sphere.h under -ffast-math).
    enum class outcome { ran, refused_by_source, did_not_compile, did_not_load, failed_in_audit } status = outcome::ran;
    std::string failure;  // the compiler's first error, or why it did not load or run
    std::vector<std::string> commands;
    std::string plugin;          // the built library
    std::string fp_environment;  // as loaded, when not the IEEE default
    std::optional<build_bisect_result> bisect;
};

std::string_view build_outcome_name(build_row::outcome o);

// report.json's "builds": the rows, each with its differences (those whose
// target is one of its precisions: `targets` are the audit's, whose subject
// names are the builds' names) and, for the worst flipped cases, the explain
// command of each (`rayverify explain --plugin LIBRARY --precision P 'LINE'`).
// `examples`: the flipped cases shown per build and precision (build_difference::worst).
nlohmann::ordered_json builds_json(std::span<const build_row> rows, std::span<const audit_target> targets,
                                   std::span<const build_difference> differences, std::size_t cases,
                                   std::size_t examples);

// The text the command prints after the audit's table, and report.md's section.
std::string render_builds_text(const nlohmann::ordered_json& builds);
std::string render_builds_markdown(const nlohmann::ordered_json& builds);

}  // namespace rayverify
