// Rendering of gate results: the readable diff, JUnit XML, and the figures of
// a report.json read back for `rayverify diff`.
#pragma once

#include <nlohmann/json.hpp>
#include <span>
#include <string>

#include "compare/gate.h"

namespace rayverify {

// "naive/float far_sphere: false_miss 45 → 48 (allowed ≤ 45)" lines, worst
// first, each failing figure followed by its first cases as corpus lines,
// then improvements, new entries and notes, then a one-line verdict.
std::string render_gate_text(const gate_run& run, std::span<const corpus_case> corpus);

// JUnit XML: one <testsuite> per target, one <testcase> per family.
std::string render_junit(const gate_run& run, std::span<const corpus_case> corpus);

// The figures of a report.json written by `rayverify audit --report`.
// Throws input_error naming the file and the field (a path such as
// "results[2].by_family.uniform.verdicts.false_miss") when it is not such a report.
figure_table figures_from_report_json(const nlohmann::ordered_json& report, const std::string& file);

// Every changed figure of `rayverify diff A B`, grouped by target and family.
std::string render_figure_diff(const gate_result& result);

}  // namespace rayverify
