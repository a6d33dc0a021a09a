// The cases to open (compare/case_examples.h) rendered: report.json's
// "cases_to_open", lines after the summary table, and report.md's section;
// each case with its id, where it was read, and its corpus line, ready to
// paste into `rayverify explain`.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "compare/audit.h"
#include "compare/case_examples.h"

namespace rayverify {

// One object per target with something to open: its first cases per
// disagreeing verdict and its farthest agreeing cases.
nlohmann::ordered_json cases_to_open_json(const std::vector<audit_target>& targets, const case_examples& examples);

// The summary's lines: per target and verdict, the count and the first
// case's corpus line (the others by id). Empty when there is nothing to open
// or more than `most_targets` targets have something (report.md lists them).
std::string render_cases_to_open(const nlohmann::ordered_json& cases, std::size_t most_targets = 4);

// report.md's section (empty when there is nothing to open).
std::string render_cases_to_open_markdown(const nlohmann::ordered_json& cases);

}  // namespace rayverify
