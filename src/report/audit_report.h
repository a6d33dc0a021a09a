// Rendering of audit results: the summary table, the JSON report and the
// per-case JSON lines. Rendering only: every figure comes from audit_totals
// or audited_case, computed in the compare layer.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "compare/audit.h"
#include "compare/stability.h"
#include "corpus/json_mapping.h"
#include "report/json_line.h"

namespace rayverify {

// How the run was made, recorded in every report.
struct run_context {
    std::string command_line;
    std::vector<std::string> corpus_paths;
    std::vector<std::string> generated;  // --generate specs, "FAMILY:COUNT:SEED"
};

// Build facts (compiler, flags, build type, version) as JSON.
nlohmann::ordered_json build_json();
// The same facts as one line of text: "COMPILER FLAGS [BUILD_TYPE]", as every command prints them.
std::string build_summary();

// The width of a verdict's count column in a text table (the summary's, a
// scene's): its heading's, and at least 6.
std::size_t verdict_column_width(std::string_view heading);

// The fixed-width table printed on stdout after an audit.
std::string render_summary_table(const audit_totals& totals);

// The machine-readable report (report.json).
nlohmann::ordered_json audit_report_json(const audit_totals& totals, const run_context& context);

// The scored cases of a "verdicts" object of report.json (a target's, or one
// family's): the counts of the verdicts the verdict table scores.
std::size_t scored_in(const nlohmann::ordered_json& verdicts);
// The cases given the wrong class in such an object: the counts of the verdicts the table calls misclassifications.
std::size_t misclassified_in(const nlohmann::ordered_json& verdicts);

// One line of --per-case output (no trailing newline): the case, its exact
// answers, every target's result and the case's stability measures, written
// field by field (report/json_line.h) as nlohmann would dump the same object.
// Written into `buffer`'s storage when one is given (its text is dropped), so
// that a caller writing many lines reuses one allocation.
std::string per_case_line(const audited_case& audited, const std::vector<audit_target>& targets,
                          std::string buffer = {});

// What the p99 and median of every error statistic are (written beside them).
extern const std::string quantile_scope;

// The same value as json_number (corpus/json_mapping.h), written to a line.
void write_number(json_line& out, double x);

// A contract as report.json, `variants --json` and shard states record it:
// its spec (format_contract), tangent rule and meaning; read back from the
// spec (one that does not parse is an input error at "spec").
void map_json(json_io& io, contract& c);
// A shipped library's identity (an --engine target's).
void map_json(json_io& io, library_identity& library);
// A target as report.json's results and shard states name it: variant,
// precision, citation, formula, contract, library and floating-point
// environment when set. Read back, it describes and never runs (merge renders, it does not audit).
void map_json(json_io& io, audit_target& target);
void map_json(json_io& io, precision& p);
// Verdicts, causes and reasons a case is invalid, by name.
void map_json(json_io& io, verdict_kind& v);
void map_json(json_io& io, disagreement_cause& c);
void map_json(json_io& io, invalid_reason& r);

}  // namespace rayverify
