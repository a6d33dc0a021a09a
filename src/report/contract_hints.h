// The contract lint's hints (compare/contract_lint.h) rendered: in
// report.json ("contract_hints"), as lines after the summary table, and in
// report.md (from report.json).
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "compare/audit.h"
#include "compare/contract_lint.h"

namespace rayverify {

// One object per target with a hint: target, declared and suggested specs,
// the version 1 query kind that says the suggestion (null when none does),
// the pattern, and the counts.
nlohmann::ordered_json contract_hints_json(const std::vector<audit_target>& targets,
                                           const std::vector<std::optional<contract_hint>>& hints);

// One paragraph per hint of report.json's "contract_hints", each line
// starting with "hint: " or two spaces; empty when there is none.
std::string render_contract_hints(const nlohmann::ordered_json& hints);

}  // namespace rayverify
