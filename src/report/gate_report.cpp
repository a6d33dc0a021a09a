#include "report/gate_report.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <string_view>
#include <vector>

#include "core/input_error.h"
#include "corpus/corpus_io.h"
#include "corpus/json_mapping.h"

namespace rayverify {
namespace {

std::string value_text(const std::optional<double>& x) {
    if (!x) return "-";
    if (std::isinf(*x)) return *x > 0 ? "inf" : "-inf";
    return fmt::format("{}", *x);
}

std::string change_line(const figure_change& c) {
    std::string line = fmt::format("{} {}: {} {} → {}", c.key.target, c.key.family, c.key.figure,
                                   value_text(c.before), value_text(c.after));
    if (c.kind == change_kind::worse || c.kind == change_kind::within_slack)
        line += fmt::format(" (allowed {} {})", c.key.figure == scored_figure ? "≥" : "≤", value_text(c.limit));
    if (c.kind == change_kind::stale) line += " (the family's cases changed: figures not comparable; review, then --update)";
    if (c.kind == change_kind::missing)
        line = fmt::format("{} {}: in the baseline ({} cases), {} (a gate does not pass on less than its baseline; "
                           "--allow-missing {} or an 'allow-missing' line allows it)",
                           c.key.target, c.key.family, value_text(c.before),
                           c.key.family == all_families ? "not run" : "not in this corpus",
                           c.key.family == all_families ? c.key.target.substr(0, c.key.target.find('/')) : c.key.family);
    return line;
}

std::string xml_escaped(std::string_view text) {
    std::string out;
    for (char ch : text) {
        switch (ch) {
            case '&': out += "&amp;"; break;
            case '<': out += "&lt;"; break;
            case '>': out += "&gt;"; break;
            case '"': out += "&quot;"; break;
            default: out += ch;
        }
    }
    return out;
}

bool fails(const figure_change& c) {
    return c.kind == change_kind::worse || c.kind == change_kind::stale || c.kind == change_kind::missing;
}

std::string unscored_line(const std::string& target) {
    return fmt::format("{}: scored no case of this run (each is invalid at its precision or breaks its contract): it "
                       "passed nothing",
                       target);
}

std::string configuration_change_line(const configuration_change& c) {
    if (c.aspect == setup_aspect::contract)
        return fmt::format("{}: contract {} in the baseline, {} in this run (another contract scores other cases: "
                           "its figures are not comparable; review and --update)",
                           c.variant, c.before, c.after);
    return fmt::format("{}: library set-up '{}' in the baseline, '{}' in this run (its answers depend on it: gate a "
                       "pinned set-up, e.g. one of `rayverify engines`' pinned kernels, or review and --update on "
                       "this machine)",
                       c.variant, c.before, c.after.empty() ? "none reported" : c.after);
}

// The failing figure's first cases, as corpus lines that paste back into a corpus file.
std::string example_lines(const gate_run& run, const figure_change& c, std::span<const corpus_case> corpus,
                          std::string_view indent) {
    std::string out;
    const auto cases = run.examples.cases_for(c.key, run.totals, corpus);
    if (cases.empty()) return out;
    out += fmt::format("{}# {}:\n", indent,
                       is_ulp_figure(c.key.figure) ? "the case with the largest error" : "first cases, as corpus lines");
    for (const corpus_case* k : cases) out += fmt::format("{}{}\n", indent, format_case_line(*k));
    return out;
}

// ", 1 library set-up(s) and 2 contract(s) not the baseline's", or nothing.
std::string setup_changes_text(std::span<const configuration_change> changes) {
    const auto count = [&](setup_aspect aspect) {
        return std::ranges::count(changes, aspect, &configuration_change::aspect);
    };
    std::vector<std::string> parts;
    if (const auto n = count(setup_aspect::library); n > 0) parts.push_back(fmt::format("{} library set-up(s)", n));
    if (const auto n = count(setup_aspect::contract); n > 0) parts.push_back(fmt::format("{} contract(s)", n));
    return parts.empty() ? std::string() : fmt::format(", {} not the baseline's", fmt::join(parts, " and "));
}

}  // namespace

std::string render_gate_text(const gate_run& run, std::span<const corpus_case> corpus) {
    const gate_result& r = run.result;
    std::string out;
    std::size_t worse = 0, absent = 0, better = 0, slack = 0, fresh = 0;
    for (const configuration_change& c : r.configuration_changes)
        out += fmt::format("{} {}\n", c.aspect == setup_aspect::contract ? "CONTRACT" : "SETUP ",
                           configuration_change_line(c));
    for (const std::string& t : r.unscored) out += fmt::format("NONE   {}\n", unscored_line(t));
    for (const figure_change& c : r.changes) {
        if (!fails(c)) continue;
        ++(c.kind == change_kind::missing ? absent : worse);
        out += fmt::format("{} {}\n", c.kind == change_kind::missing ? "ABSENT" : "WORSE ", change_line(c));
        out += example_lines(run, c, corpus, "    ");
    }
    for (const figure_change& c : r.changes) {
        if (c.kind == change_kind::within_slack) {
            ++slack;
            out += fmt::format("slack  {}\n", change_line(c));
        } else if (c.kind == change_kind::better) {
            ++better;
            out += fmt::format("better {}\n", change_line(c));
        } else if (c.kind == change_kind::new_entry) {
            ++fresh;
        }
    }
    for (const std::string& note : r.notes) out += fmt::format("note   {}\n", note);
    if (fresh > 0) out += fmt::format("note   {} figure(s) new, no baseline (--update adds them)\n", fresh);
    if (r.compared == 0)
        out += "gate: FAILED: no figure of this run has a baseline value (wrong baseline, or create it with --update)\n";
    else if (!r.passed())
        out += fmt::format("gate: FAILED: {} figure(s) worse than the baseline allows{}{}{}; {} compared\n", worse,
                           absent == 0 ? std::string() : fmt::format(", {} family or target group(s) absent", absent),
                           setup_changes_text(r.configuration_changes),
                           r.unscored.empty() ? std::string()
                                              : fmt::format(", {} target(s) scored no case", r.unscored.size()),
                           r.compared);
    else
        out += fmt::format("gate: passed: {} figures compared, {} better{}, {} worse within the policy's slack\n",
                           r.compared, better, better > 0 ? " (the baseline can be tightened: --update)" : "", slack);
    return out;
}

std::string render_junit(const gate_run& run, std::span<const corpus_case> corpus) {
    // target → family → changes; every compared (target, family) is a test case.
    std::map<std::string, std::map<std::string, std::vector<const figure_change*>>> groups;
    for (const auto& [key, value] : run.current) groups[key.target][key.family];
    for (const figure_change& c : run.result.changes) groups[c.key.target][c.key.family].push_back(&c);

    std::string suites;
    std::size_t total_tests = 0, total_failures = 0;
    if (!run.result.unscored.empty()) {
        std::string cases;
        for (const std::string& t : run.result.unscored)
            cases += fmt::format("    <testcase classname=\"scored cases\" name=\"{}\">\n      <failure message=\"scored no "
                                 "case\">{}</failure>\n    </testcase>\n",
                                 xml_escaped(t), xml_escaped(unscored_line(t)));
        total_tests += run.result.unscored.size();
        total_failures += run.result.unscored.size();
        suites += fmt::format("  <testsuite name=\"scored cases\" tests=\"{0}\" failures=\"{0}\">\n{1}  </testsuite>\n",
                              run.result.unscored.size(), cases);
    }
    for (const setup_aspect aspect : {setup_aspect::library, setup_aspect::contract}) {
        std::string cases;
        std::size_t failures = 0;
        for (const configuration_change& c : run.result.configuration_changes) {
            if (c.aspect != aspect) continue;
            ++failures;
            cases += fmt::format("    <testcase classname=\"{0}\" name=\"{1}\">\n      <failure message=\"{0} "
                                 "differs from the baseline's\">{2}</failure>\n    </testcase>\n",
                                 setup_aspect_name(aspect), xml_escaped(c.variant), xml_escaped(configuration_change_line(c)));
        }
        if (failures == 0) continue;
        total_tests += failures;
        total_failures += failures;
        suites += fmt::format("  <testsuite name=\"{0}\" tests=\"{1}\" failures=\"{1}\">\n{2}  </testsuite>\n",
                              setup_aspect_name(aspect), failures, cases);
    }
    for (const auto& [target, families] : groups) {
        std::string cases;
        std::size_t failures = 0;
        for (const auto& [family, changes] : families) {
            std::string failure_text, other_text;
            for (const figure_change* c : changes) {
                if (fails(*c))
                    failure_text += change_line(*c) + "\n" + example_lines(run, *c, corpus, "    ");
                else
                    other_text += fmt::format("{}{}\n", c->kind == change_kind::new_entry ? "new: " : "",
                                              change_line(*c));
            }
            cases += fmt::format("    <testcase classname=\"{}\" name=\"{}\">\n", xml_escaped(target),
                                 xml_escaped(family));
            if (!failure_text.empty()) {
                ++failures;
                cases += fmt::format("      <failure message=\"worse than the baseline\">{}</failure>\n",
                                     xml_escaped(failure_text));
            }
            if (!other_text.empty()) cases += fmt::format("      <system-out>{}</system-out>\n", xml_escaped(other_text));
            cases += "    </testcase>\n";
        }
        total_tests += families.size();
        total_failures += failures;
        suites += fmt::format("  <testsuite name=\"{}\" tests=\"{}\" failures=\"{}\">\n{}  </testsuite>\n",
                              xml_escaped(target), families.size(), failures, cases);
    }
    return fmt::format("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
                       "<testsuites name=\"rayverify gate\" tests=\"{}\" failures=\"{}\">\n{}</testsuites>\n",
                       total_tests, total_failures, suites);
}

namespace {

// What gate and diff read of report.json (a view: the report is written by
// audit_report.cpp, which these mappings never write for).
struct gated_summary {
    std::size_t count = 0;
    std::optional<double> max, p99;
};

struct gated_tally {
    std::size_t cases = 0;
    std::map<std::string, std::size_t> verdicts;
    per_error_figure<std::optional<gated_summary>> errors;
};

struct gated_entry {
    std::string variant, precision;
    gated_tally all;
    std::optional<std::map<std::string, gated_tally>> by_family;
};

void map_json(json_io& io, gated_summary& s) {
    io.field("count", s.count);
    if (s.count == 0) return;
    io.field("max", s.max);
    io.field("p99", s.p99);
    if (io.reading() && (!s.max || !s.p99)) io.fail(s.max ? "p99" : "max", "is null, expected a number");
}

void map_json(json_io& io, gated_tally& t) {
    io.field("cases", t.cases);
    io.field("verdicts", t.verdicts);
    for (const error_figure_definition& f : error_figures)
        if (f.gated) io.optional_field(std::string(f.name).c_str(), t.errors[f.figure]);
}

void map_json(json_io& io, gated_entry& e) {
    io.field("variant", e.variant);
    io.field("precision", e.precision);
    map_json(io, e.all);  // the whole run's tally is the entry's own fields
    io.optional_field("by_family", e.by_family);
}

void add_figures(figure_table& table, const std::string& target, const std::string& family, const gated_tally& t) {
    table[{target, family, "cases"}] = static_cast<double>(t.cases);
    for (int k = 0; k < verdict_kind_count; ++k) {
        const auto kind = static_cast<verdict_kind>(k);
        const std::string name(verdict_name(kind));
        if (const auto it = t.verdicts.find(name); is_disagreement(kind) && it != t.verdicts.end())
            table[{target, family, name}] = static_cast<double>(it->second);
    }
    for (const error_figure_definition& f : error_figures) {
        const std::optional<gated_summary>& s = t.errors[f.figure];
        if (!f.gated || !s || s->count == 0) continue;
        table[{target, family, std::string(f.case_name) + "_max"}] = *s->max;
        table[{target, family, std::string(f.case_name) + "_p99"}] = *s->p99;
    }
}

}  // namespace

figure_table figures_from_report_json(const nlohmann::ordered_json& report, const std::string& file) {
    if (!report.is_object() || report.value("tool", "") != "rayverify audit")
        throw input_error(file, 0, "tool", "not a report.json written by rayverify audit --report");
    json_io io(report, file);
    std::vector<gated_entry> results;
    io.field("results", results);
    figure_table table;
    for (const gated_entry& entry : results) {
        const std::string target = entry.variant + "/" + entry.precision;
        add_figures(table, target, std::string(all_families), entry.all);
        if (entry.by_family)
            for (const auto& [family, tally] : *entry.by_family) add_figures(table, target, family, tally);
    }
    return table;
}

std::string render_figure_diff(const gate_result& result) {
    std::string out;
    std::size_t worse = 0, better = 0;
    for (const figure_change& c : result.changes) {
        const char* tag = "";
        switch (c.kind) {
            case change_kind::worse: tag = "worse "; ++worse; break;
            case change_kind::within_slack: tag = "worse "; ++worse; break;
            case change_kind::better: tag = "better"; ++better; break;
            case change_kind::stale: tag = "cases "; break;
            case change_kind::missing: tag = "only A"; break;
            case change_kind::new_entry: tag = "only B"; break;
        }
        out += fmt::format("{} {}\n", tag, change_line(figure_change{c.key, c.before, c.after, change_kind::better, 0}));
    }
    for (const std::string& note : result.notes) out += fmt::format("note   {}\n", note);
    out += fmt::format("diff: {} figures compared, {} worse, {} better\n", result.compared, worse, better);
    return out;
}

}  // namespace rayverify
