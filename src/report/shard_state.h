// The state of an audit run: its accumulators (compare/audit, compare/stability)
// and plot sample (case_points), which is everything its reports are rendered
// from. A shard (`rayverify audit --shard K/N`) saves it as JSON beside its
// report; `rayverify merge` reads the shards' states back, merges them and
// renders exactly the report one run over the whole input would have written.
// Every double is stored as a hex float, so nothing is rounded on the way.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "compare/audit.h"
#include "compare/case_examples.h"
#include "compare/contract_lint.h"
#include "compare/stability.h"
#include "report/audit_report.h"
#include "report/stability_report.h"

namespace rayverify {

inline constexpr const char* shard_state_format = "rayverify-shard-state 4";
inline constexpr const char* shard_state_file = "shard.json";

// Everything an audit accumulates (one per thread, one per shard).
struct audit_state {
    explicit audit_state(const std::vector<audit_target>& targets);
    void merge(const audit_state& other);

    audit_accumulator audit;
    stability_accumulator stability;
    case_points points;
    contract_lint_accumulator lint;
    case_examples examples;
};

// The labels the plots and per-case lines use for the targets.
std::vector<std::string> target_labels(const std::vector<audit_target>& targets);

// The whole report.json of an audit: audit_report_json of `totals` (the
// state's audit.finish(), formed once by the caller), then "stability" (its
// statistics formed on `threads` threads), "case_points" and
// "contract_hints" (compare/contract_lint.h) and "cases_to_open" (compare/case_examples.h).
nlohmann::ordered_json audit_report_document(const audit_state& state, const audit_totals& totals,
                                             const run_context& context, unsigned threads = 1);

// Targets as JSON (name, precision, citation, formula, contract) and back
// (variants that describe, never run: merge renders, it does not audit).
nlohmann::ordered_json targets_json(const std::vector<audit_target>& targets);
std::vector<audit_target> targets_from_json(const nlohmann::ordered_json& j);

// Checks a shard's whole state document (shard.json, as `rayverify merge`
// reads it) before anything of it is used: the type and range of every field
// and the consistency of the figures (counts that add up over verdicts,
// families and histogram buckets; maxima that are numbers in their
// histogram's last bucket; case indices inside the input and the shard; a
// per-case file inside the shard directory). Throws input_error(file, 0,
// FIELD, problem), FIELD a path such as "state.audit.overall[0].verdicts[1]".
// `header_only`: everything but "state" (merge reads the headers first).
void check_shard_state(const nlohmann::ordered_json& doc, const std::string& file, bool header_only = false);

// The accumulated state as JSON and back. `from_json` throws
// nlohmann::json::exception on a malformed document (the caller names the file).
nlohmann::ordered_json state_json(const audit_state& state);
audit_state state_from_json(const nlohmann::ordered_json& j, const std::vector<audit_target>& targets);

}  // namespace rayverify
