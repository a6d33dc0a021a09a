#include "report/table_csv.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "compare/error_figures.h"
#include "compare/judge.h"
#include "report/audit_report.h"

namespace rayverify {

using json = nlohmann::ordered_json;

namespace {

constexpr const char* statistics[] = {"count", "max", "p99", "median"};

}  // namespace

std::string csv_text(const std::string& text) {
    if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
    std::string quoted = "\"";
    for (const char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
    return quoted + "\"";
}

std::string csv_field(const json* value) {
    if (value == nullptr || value->is_null()) return "";
    if (value->is_number_integer() || value->is_number_unsigned()) return value->dump();
    if (value->is_number_float()) return fmt::format("{}", value->get<double>());
    return csv_text(value->is_string() ? value->get<std::string>() : value->dump());
}

const json* json_member(const json* object, const std::string& key) {
    if (object == nullptr || !object->is_object()) return nullptr;
    const auto at = object->find(key);
    return at == object->end() ? nullptr : &*at;
}

std::vector<std::string> audit_csv_header() {
    std::vector<std::string> header{"cases_scored", "misclassified"};
    for (int k = 0; k < verdict_kind_count; ++k) header.emplace_back(verdict_name(static_cast<verdict_kind>(k)));
    for (const error_figure_definition& figure : error_figures)
        for (const char* statistic : statistics) header.push_back(fmt::format("{}_{}", figure.name, statistic));
    return header;
}

std::vector<std::string> audit_csv_fields(const json* section) {
    std::vector<std::string> fields;
    const json* verdicts = json_member(section, "verdicts");
    fields.push_back(verdicts == nullptr ? "" : std::to_string(scored_in(*verdicts)));
    fields.push_back(verdicts == nullptr ? "" : std::to_string(misclassified_in(*verdicts)));
    for (int k = 0; k < verdict_kind_count; ++k)
        fields.push_back(csv_field(json_member(verdicts, std::string(verdict_name(static_cast<verdict_kind>(k))))));
    for (const error_figure_definition& figure : error_figures) {
        const json* tally = json_member(section, std::string(figure.name));
        for (const char* statistic : statistics) fields.push_back(csv_field(json_member(tally, statistic)));
    }
    return fields;
}

std::string audit_table_csv(const json& report) {
    std::vector<std::string> header{"variant", "precision", "family", "cases"};
    for (std::string& column : audit_csv_header()) header.push_back(std::move(column));
    std::string out = fmt::format("{}\n", fmt::join(header, ","));
    const auto write_row = [&](const json& entry, const std::string& family, const json& section) {
        std::vector<std::string> fields{csv_field(json_member(&entry, "variant")),
                                        csv_field(json_member(&entry, "precision")), family,
                                        csv_field(json_member(&section, "cases"))};
        for (std::string& field : audit_csv_fields(&section)) fields.push_back(std::move(field));
        out += fmt::format("{}\n", fmt::join(fields, ","));
    };
    const json* results = json_member(&report, "results");
    if (results == nullptr) return out;
    for (const json& entry : *results)
        if (const json* by_family = json_member(&entry, "by_family"))
            for (const auto& [family, section] : by_family->items()) write_row(entry, csv_text(family), section);
    for (const json& entry : *results) write_row(entry, std::string(all_families_row), entry);
    return out;
}

}  // namespace rayverify
