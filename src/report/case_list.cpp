#include "report/case_list.h"

#include <fmt/format.h>

#include <limits>

#include "compare/error_figures.h"
#include "corpus/corpus_io.h"
#include "report/audit_report.h"

namespace rayverify {

using json = nlohmann::ordered_json;

namespace {

// `figure` names what e.error measures ("scale_error_radius", "root_error_ulp"); none for the first cases.
json example_json(const case_example& e, const char* figure = nullptr) {
    json out = {{"id", e.kase.id}, {"source", e.kase.source}, {"line", format_case_line(e.kase)}};
    if (e.cause) out["cause"] = std::string(cause_name(*e.cause));
    if (figure) out[figure] = json_number(printed_figure(e.error));
    return out;
}

json examples_json(const std::vector<case_example>& list, const char* figure = nullptr) {
    json out = json::array();
    for (const case_example& e : list) out.push_back(example_json(e, figure));
    return out;
}

std::string ids(const json& list) {
    std::string out;
    for (const json& e : list)
        out += fmt::format("{}{} ({})", out.empty() ? "" : ", ", e["id"].get<std::string>(),
                           e["source"].get<std::string>());
    return out;
}

std::string ulp_text(const json& e) {
    const std::optional<std::optional<double>> ulp = number_from_json(e["root_error_ulp"]);
    return format_figure(ulp && *ulp ? **ulp : std::numeric_limits<double>::quiet_NaN()) + " ulp";
}

// The worst cases of a verdict when they are not the first ones: ids with their errors.
std::string worst_ids(const json& verdict) {
    std::string out;
    for (const json& e : verdict["worst"])
        out += fmt::format("{}{} ({})", out.empty() ? "" : ", ", e["id"].get<std::string>(), ulp_text(e));
    return out;
}

}  // namespace

json cases_to_open_json(const std::vector<audit_target>& targets, const case_examples& examples) {
    json out = json::array();
    for (std::size_t t = 0; t < targets.size() && t < examples.first.size(); ++t) {
        json verdicts = json::array();
        for (int k = 0; k < verdict_kind_count; ++k) {
            if (examples.first[t][k].empty()) continue;
            json verdict = {{"verdict", std::string(verdict_name(static_cast<verdict_kind>(k)))},
                            {"first", examples_json(examples.first[t][k])}};
            if (t < examples.worst.size() && !examples.worst[t][k].empty())
                verdict["worst"] = examples_json(examples.worst[t][k], "root_error_ulp");
            verdicts.push_back(std::move(verdict));
        }
        const json far = examples_json(examples.farthest[t], "scale_error_radius");
        if (verdicts.empty() && far.empty()) continue;
        out.push_back({{"target", targets[t].label()}, {"verdicts", verdicts}, {"agree_far", far}});
    }
    return out;
}

std::string render_cases_to_open(const json& cases, std::size_t most_targets) {
    if (cases.empty() || cases.size() > most_targets) return {};
    std::string out = "cases to open (the first of each verdict, by id; paste a line into rayverify explain \"LINE\"):\n";
    for (const json& target : cases) {
        const std::string label = target["target"].get<std::string>();
        for (const json& v : target["verdicts"]) {
            out += fmt::format("  {} {}: {}\n", label, v["verdict"].get<std::string>(), ids(v["first"]));
            out += fmt::format("    {}\n", v["first"][0]["line"].get<std::string>());
            if (v.contains("worst") && v["worst"][0]["id"] != v["first"][0]["id"]) {
                out += fmt::format("  {} {}, worst by root error: {}\n", label, v["verdict"].get<std::string>(),
                                   worst_ids(v));
                out += fmt::format("    {}\n", v["worst"][0]["line"].get<std::string>());
            }
        }
        if (!target["agree_far"].empty()) {
            out += fmt::format("  {} agree but far ({}), farthest: {}\n", label, agree_far_rule,
                               ids(target["agree_far"]));
            out += fmt::format("    {}\n", target["agree_far"][0]["line"].get<std::string>());
        }
    }
    return out;
}

std::string render_cases_to_open_markdown(const json& cases) {
    if (cases.empty()) return {};
    std::string out = "\n| target | verdict | case | cause | corpus line (paste into `rayverify explain \"LINE\"`) |\n"
                      "|---|---|---|---|---|\n";
    const auto row = [&](const std::string& target, const std::string& verdict, const json& e) {
        out += fmt::format("| {} | {} | {} ({}) | {} | `{}` |\n", target, verdict, e["id"].get<std::string>(),
                           e["source"].get<std::string>(),
                           e.contains("root_error_ulp")
                               ? fmt::format("{}, {}", e.value("cause", std::string("-")), ulp_text(e))
                           : e.contains("cause") ? e["cause"].get<std::string>()
                           : e.contains("scale_error_radius")
                               ? format_figure(e["scale_error_radius"].get<double>()) + " r off"
                               : std::string("-"),
                           e["line"].get<std::string>());
    };
    for (const json& target : cases) {
        const std::string label = target["target"].get<std::string>();
        for (const json& v : target["verdicts"]) {
            for (const json& e : v["first"]) row(label, v["verdict"].get<std::string>(), e);
            if (v.contains("worst"))
                for (const json& e : v["worst"]) row(label, v["verdict"].get<std::string>() + ", worst", e);
        }
        for (const json& e : target["agree_far"]) row(label, "agree but far", e);
    }
    return out + fmt::format("\nThe first cases of each disagreeing verdict in input order; the worst of each "
                             "verdict whose answers have a t judged against an exact root, by its root error in ULPs "
                             "(the larger of the near and far root's); and the agreeing cases whose hit lies farthest "
                             "from the exact one ({}); at most 3 of each. `audit --failures FILE` writes every "
                             "failing case as a corpus.\n",
                             agree_far_rule);
}

}  // namespace rayverify
