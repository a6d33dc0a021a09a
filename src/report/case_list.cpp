#include "report/case_list.h"

#include <fmt/format.h>

#include "corpus/corpus_io.h"

namespace rayverify {

using json = nlohmann::ordered_json;

namespace {

json example_json(const case_example& e) {
    json out = {{"id", e.kase.id}, {"source", e.kase.source}, {"line", format_case_line(e.kase)}};
    if (e.cause) out["cause"] = std::string(cause_name(*e.cause));
    if (e.error != 0) out["scale_error_radius"] = e.error;
    return out;
}

std::string ids(const json& list) {
    std::string out;
    for (const json& e : list)
        out += fmt::format("{}{} ({})", out.empty() ? "" : ", ", e["id"].get<std::string>(),
                           e["source"].get<std::string>());
    return out;
}

}  // namespace

json cases_to_open_json(const std::vector<audit_target>& targets, const case_examples& examples) {
    json out = json::array();
    for (std::size_t t = 0; t < targets.size() && t < examples.first.size(); ++t) {
        json verdicts = json::array();
        for (int k = 0; k < verdict_kind_count; ++k) {
            if (examples.first[t][k].empty()) continue;
            json first = json::array();
            for (const case_example& e : examples.first[t][k]) first.push_back(example_json(e));
            verdicts.push_back({{"verdict", std::string(verdict_name(static_cast<verdict_kind>(k)))}, {"first", first}});
        }
        json far = json::array();
        for (const case_example& e : examples.farthest[t]) far.push_back(example_json(e));
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
        }
        if (!target["agree_far"].empty()) {
            out += fmt::format("  {} agree but far (|t - t*|·|d| >= 2^-10 r), farthest: {}\n", label,
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
                           e.contains("cause") ? e["cause"].get<std::string>()
                           : e.contains("scale_error_radius")
                               ? fmt::format("{:.3g} r off", e["scale_error_radius"].get<double>())
                               : std::string("-"),
                           e["line"].get<std::string>());
    };
    for (const json& target : cases) {
        const std::string label = target["target"].get<std::string>();
        for (const json& v : target["verdicts"])
            for (const json& e : v["first"]) row(label, v["verdict"].get<std::string>(), e);
        for (const json& e : target["agree_far"]) row(label, "agree but far", e);
    }
    return out + "\nThe first cases of each disagreeing verdict in input order, and the agreeing cases whose hit "
                 "lies farthest from the exact one (|t − t*|·|d| ≥ 2^-10 r), at most 3 of each; `audit --failures "
                 "FILE` writes every failing case as a corpus.\n";
}

}  // namespace rayverify
