// The audit's figures as CSV tables for a paper or a spreadsheet: one
// mapping from report.json's results to CSV columns, which audit.csv (audit
// and merge) and bench.csv (bench, timing columns before them) both write.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

namespace rayverify {

// The family column's value on a row over every family (the whole corpus).
inline constexpr std::string_view all_families_row = "(all)";

// A JSON value as a CSV field: numbers in their shortest round-trip decimal,
// strings as themselves (quoted where they hold a comma, a quote or a line
// break), null and absent as nothing.
std::string csv_field(const nlohmann::ordered_json* value);
std::string csv_text(const std::string& text);  // a string as a field

// The member `key` of an object, or null when `object` is null, not an object or lacks it.
const nlohmann::ordered_json* json_member(const nlohmann::ordered_json* object, const std::string& key);

// An audited section's columns (report.json's results entry or one of its
// by_family entries): the scored cases, those given the wrong class, a
// column per verdict, and per error figure its count, max, p99 and median.
std::vector<std::string> audit_csv_header();
std::vector<std::string> audit_csv_fields(const nlohmann::ordered_json* section);  // empty fields for null

// audit.csv: a row per target and family (report.json's results and their
// by_family, in that order), then a row per target over every family
// (family `all_families_row`): variant, precision, family, cases, then the
// audited section's columns.
std::string audit_table_csv(const nlohmann::ordered_json& report);

}  // namespace rayverify
