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

// One line of --per-case output (no trailing newline): the case, its exact
// answers, every target's result and the case's stability measures, written
// field by field (report/json_line.h) as nlohmann would dump the same object.
// Written into `buffer`'s storage when one is given (its text is dropped), so
// that a caller writing many lines reuses one allocation.
std::string per_case_line(const audited_case& audited, const std::vector<audit_target>& targets,
                          std::string buffer = {});

// What the p99 and median of every error statistic are (written beside them).
extern const char* const quantile_scope;

// A finite double as a JSON number, ±inf and NaN as strings ("inf", "-inf", "nan").
nlohmann::ordered_json json_number(double x);
// The same value written to a line.
void write_number(json_line& out, double x);
// json_number of a value, null for none.
nlohmann::ordered_json optional_number(const std::optional<double>& x);
// What json_number or optional_number wrote: a JSON number, "inf", "-inf" or
// "nan" (the value), null (nullopt inside); nullopt outside for anything else.
std::optional<std::optional<double>> number_from_json(const nlohmann::ordered_json& j);

// A contract as report.json and shard states record it: its spec
// (format_contract), tangent rule and meaning; and back (a spec that does not
// parse is a json::other_error).
nlohmann::ordered_json contract_json(const contract& c);
contract contract_from_json(const nlohmann::ordered_json& j);

// A shipped library's identity (an --engine target's) as report.json and shard states record it.
nlohmann::ordered_json library_json(const library_identity& library);

}  // namespace rayverify
