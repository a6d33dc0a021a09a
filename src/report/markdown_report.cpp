#include "report/markdown_report.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>

#include "compare/error_figures.h"
#include "compare/judge.h"
#include "compare/stability.h"
#include "report/json_line.h"
#include "report/stability_report.h"
#include "core/input_error.h"
#include "core/installed_data.h"
#include "corpus/corpus_io.h"
#include "report/builds_report.h"
#include "report/case_list.h"
#include "report/contract_hints.h"

namespace rayverify {

using json = nlohmann::ordered_json;

namespace {

// The machine and input files of a bench report, as "How this report was
// made" lists them: the CPU with its clock and the feature flags that decide
// floating-point code (the whole list is in report.json), the load as the
// timings began, the kernel; each input file's digest.
std::string machine_lines(const json& report) {
    const json& m = report["machine"];
    std::string out = fmt::format("- CPU: {}", m["cpu"].get<std::string>());
    if (m.contains("cpu_mhz") && m["cpu_mhz"].is_number()) out += fmt::format(", {:.0f} MHz", m["cpu_mhz"].get<double>());
    if (m.contains("cpu_max_mhz") && m["cpu_max_mhz"].is_number())
        out += fmt::format(" (maximum {:.0f} MHz)", m["cpu_max_mhz"].get<double>());
    out += fmt::format(", {} hardware threads", m["hardware_threads"].get<std::size_t>());
    static constexpr std::string_view floating_point_flags[] = {"sse2",    "sse4_1",  "sse4_2",   "avx",  "avx2",
                                                                 "fma",     "f16c",    "avx512f",  "avx512dq",
                                                                 "avx512vl", "asimd",  "fphp"};
    std::vector<std::string> present;
    if (m.contains("cpu_flags"))
        for (const std::string_view flag : floating_point_flags)
            for (const json& f : m["cpu_flags"])
                if (f.get<std::string>() == flag) present.emplace_back(flag);
    if (!present.empty()) out += fmt::format("; floating-point features: {}", fmt::join(present, " "));
    out += "\n";
    if (m.contains("load_average") && m["load_average"].is_array())
        out += fmt::format("- load average as the timings began: {} (1, 5, 15 minutes)\n",
                           fmt::join(m["load_average"].get<std::vector<double>>(), ", "));
    if (m.contains("kernel")) out += fmt::format("- kernel: {}\n", m["kernel"].get<std::string>());
    if (report.contains("input_files"))
        for (const json& f : report["input_files"])
            out += fmt::format("- {} file: `{}`, {} bytes, digest {}\n", f["role"].get<std::string>(),
                               f["path"].get<std::string>(), f["bytes"].is_number() ? f["bytes"].dump() : "?",
                               f["digest"].get<std::string>());
    return out;
}

// An error figure as report.json gives it (a number, "inf", "nan" or null).
std::string figure_text(const json& x) {
    if (x.is_null()) return "-";
    if (x.is_string()) return x.get<std::string>();
    return format_figure(x.get<double>());
}

std::string percent(std::size_t part, std::size_t whole) {
    if (whole == 0) return "-";
    return fmt::format("{:.1f}%", 100.0 * static_cast<double>(part) / static_cast<double>(whole));
}

// What each plot shows, as its image's alt text.
std::string plot_title(const std::string& file) {
    static const std::map<std::string, std::string> titles = {
        {"accuracy_vs_time.png", "Accuracy against run time, one panel per precision"},
        {"error_vs_condition.png", "Nearest-root error against the condition number"},
        {"far_sphere.png", "Far spheres: error and misclassification by distance/radius"},
        {"ulp_histograms.png", "Nearest-root ULP error per variant"}};
    const auto it = titles.find(file);
    return it == titles.end() ? file : it->second;
}

void accuracy_table(std::string& out, const json& results, const std::string& title) {
    out += fmt::format("\n#### {}\n\n", title);
    out += "| variant | precision | scored | agree | agree but far | misclassified | other disagreements | max ulp | "
           "p99 ulp | median ulp |\n";
    out += "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const json& r : results) {
        const std::size_t n = scored_in(r["verdicts"]), mis = misclassified_in(r["verdicts"]);
        const json& u = r["near_root_ulp"];
        out += fmt::format("| {} | {} | {} | {} | {} | {} ({}) | {} | {} | {} | {} |\n", r["variant"].get<std::string>(),
                           r["precision"].get<std::string>(), n, r["verdicts"]["agree"].get<std::size_t>(),
                           r.contains("agree_far") ? std::to_string(r["agree_far"].get<std::size_t>()) : "-", mis,
                           percent(mis, n), r["disagreements"].get<std::size_t>() - mis,
                           figure_text(u.value("max", json())), figure_text(u.value("p99", json())),
                           figure_text(u.value("median", json())));
    }
    out += fmt::format("\nagree but far: agreeing cases whose returned t lies far from the exact hit ({}; the "
                       "verdict asks which root a t stands for, not how close it is; `--accuracy` makes such an "
                       "answer imprecise).",
                       agree_far_rule);
    out += "\nULP columns: nearest root over the agreeing cases; every maximum is over this finite corpus "
           "(sampled: a lower bound on the variant's worst case, not a bound).\n";
}

void stability_tables(std::string& out, const json& stability) {
    out += "\n";
    for (const auto& [name, text] : stability["definitions"].items())
        out += fmt::format("- **{}**: {}\n", name, text.get<std::string>());
    out += "\n| variant | precision | stable | judged | above 16·κ | above, κ < 1e3 | max excess | misclassified | "
           "conditioning-limited | algorithmic |\n|---|---|---|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const json& r : stability["results"]) {
        const json& line = r["reference_line"];
        out += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n", r["variant"].get<std::string>(),
                           r["precision"].get<std::string>(), line["stable"].get<bool>() ? "yes" : "**no**",
                           line["judged"].get<std::size_t>(), line["above_line"].get<std::size_t>(),
                           line["well_conditioned_above_line"].get<std::size_t>(),
                           figure_text(line.value("max_excess", json())), r["misclassified"].get<std::size_t>(),
                           r["conditioning_limited"].get<std::size_t>(), r["algorithmic"].get<std::size_t>());
    }
    out += "\nDisagreements are split into conditioning-limited and algorithmic (every disagreement, not only "
           "wrong classes). Maximum excess is over this finite corpus.\n";

    // Per family: which variants stay on the κ·u line.
    out += "\n#### Stable per family (no agreeing case above 16·κ ulps; unstable lists the count above)\n\n";
    std::map<std::string, std::vector<std::string>> cells;
    std::vector<std::string> families;
    out += "| variant | precision |";
    bool header_done = false;
    for (const json& r : stability["results"]) {
        if (!header_done) {
            for (const auto& [family, _] : r["by_family"].items()) {
                families.push_back(family);
                out += fmt::format(" {} |", family);
            }
            out += "\n|---|---|";
            for (std::size_t i = 0; i < families.size(); ++i) out += "---|";
            out += "\n";
            header_done = true;
        }
        out += fmt::format("| {} | {} |", r["variant"].get<std::string>(), r["precision"].get<std::string>());
        for (const std::string& family : families) {
            const json& line = r["by_family"][family]["reference_line"];
            const std::size_t judged = line["judged"].get<std::size_t>(), above = line["above_line"].get<std::size_t>();
            out += judged == 0 ? " - |" : (above == 0 ? " stable |" : fmt::format(" unstable ({}/{}) |", above, judged));
        }
        out += "\n";
    }

    // Condition buckets, overall.
    out += "\n#### By condition number of the near root (cases · misclassified · median / max ulp)\n\n";
    // Every decade from the lowest to the highest any target has, in the order of κ (then inf, miss).
    int lowest = condition_bucket_count, highest = -1;
    for (const json& r : stability["results"])
        for (const json& b : r["buckets"])
            for (int k = 0; k < condition_bucket_count; ++k)
                if (b["condition"] == condition_bucket_label(k)) {
                    lowest = std::min(lowest, k);
                    highest = std::max(highest, k);
                }
    std::vector<std::string> labels;
    for (int k = lowest; k <= highest; ++k) labels.push_back(condition_bucket_label(k));
    out += "| variant | precision |";
    for (const std::string& l : labels) out += fmt::format(" κ {} |", l);
    out += "\n|---|---|";
    for (std::size_t i = 0; i < labels.size(); ++i) out += "---|";
    out += "\n";
    for (const json& r : stability["results"]) {
        out += fmt::format("| {} | {} |", r["variant"].get<std::string>(), r["precision"].get<std::string>());
        for (const std::string& l : labels) {
            const json* found = nullptr;
            for (const json& b : r["buckets"])
                if (b["condition"] == l) found = &b;
            if (!found) {
                out += " - |";
                continue;
            }
            const json& u = (*found)["near_root_ulp"];
            out += fmt::format(" {} · {} · {} / {} |", (*found)["cases"].get<std::size_t>(),
                               (*found)["misclassified"].get<std::size_t>(), figure_text(u.value("median", json())),
                               figure_text(u.value("max", json())));
        }
        out += "\n";
    }
}

void timing_tables(std::string& out, const json& timing) {
    out += "\n";
    for (const auto& [name, text] : timing["harness"].items())
        out += fmt::format("- {}: {}\n", name, text.is_string() ? text.get<std::string>() : text.dump());
    out += fmt::format("\nRatios are to `{}` measured in the same run, family by family. ns are CPU time per "
                       "ray–sphere test, median over the repetitions.\n\n",
                       timing["reference"].get<std::string>());
    out += "| variant | precision | ns per test (all cases) | ratio to reference |\n|---|---|---:|---:|\n";
    for (const json& r : timing["overall"])
        out += fmt::format("| {} | {} | {:.2f} | {} |\n", r["variant"].get<std::string>(),
                           r["precision"].get<std::string>(), r["ns_per_test"].get<double>(),
                           r["ratio_to_reference"].is_number() ? fmt::format("{:.3g}", r["ratio_to_reference"].get<double>()) : std::string("-"));
    out += fmt::format("\n({})\n\n#### Per family: median ns per test [min–max over repetitions]\n\n",
                       timing["overall_definition"].get<std::string>());
    std::vector<std::string> families, labels;
    std::map<std::string, std::map<std::string, const json*>> cell;
    for (const json& r : timing["rows"]) {
        const std::string family = r["family"], label = r["variant"].get<std::string>() + "/" + r["precision"].get<std::string>();
        if (std::find(families.begin(), families.end(), family) == families.end()) families.push_back(family);
        if (std::find(labels.begin(), labels.end(), label) == labels.end()) labels.push_back(label);
        cell[label][family] = &r;
    }
    out += "| variant/precision |";
    for (const auto& f : families) out += fmt::format(" {} |", f);
    out += "\n|---|";
    for (std::size_t i = 0; i < families.size(); ++i) out += "---:|";
    out += "\n";
    for (const auto& label : labels) {
        out += fmt::format("| {} |", label);
        for (const auto& f : families) {
            const json* r = cell[label][f];
            if (!r) {
                out += " |";
                continue;
            }
            const json& ns = (*r)["ns_per_test"];
            out += fmt::format(" {:.2f} [{:.2f}–{:.2f}] |", ns["median"].get<double>(), ns["min"].get<double>(),
                               ns["max"].get<double>());
        }
        out += "\n";
    }
}

void sweep_table(std::string& out, const json& sweep) {
    out += fmt::format("\n{}\n\n", sweep["description"].get<std::string>());
    out += "Misclassified / scored cases per decade of distance/radius (|o − c| / r):\n\n| d/r |";
    const json& results = sweep["results"];
    for (const json& r : results)
        out += fmt::format(" {}/{} |", r["variant"].get<std::string>(), r["precision"].get<std::string>());
    out += "\n|---|";
    for (std::size_t i = 0; i < results.size(); ++i) out += "---:|";
    out += "\n";
    if (results.empty()) return;
    for (const auto& [decade, _] : results[0]["by_family"].items()) {
        out += fmt::format("| {} |", decade);
        for (const json& r : results) {
            const json& f = r["by_family"][decade];
            out += fmt::format(" {}/{} |", misclassified_in(f["verdicts"]), scored_in(f["verdicts"]));
        }
        out += "\n";
    }
}

// The headline: whether any target disagrees with the exact answer.
std::string headline(const json& report) {
    const std::string tool = report.value("tool", std::string("rayverify report"));
    std::size_t targets = 0, wrong = 0;
    for (const json& r : report.value("results", json::array())) {
        ++targets;
        if (r["disagreements"].get<std::size_t>() > 0) ++wrong;
    }
    const std::size_t cases = report.contains("corpus") ? report["corpus"]["cases"].get<std::size_t>() : 0;
    if (wrong == 0)
        return fmt::format("## {}: no disagreement — all {} targets agree with the exact answer on all {} cases\n",
                           tool, targets, cases);
    return fmt::format("## {}: findings — {} of {} targets answer some of the {} cases wrong\n", tool, wrong,
                       targets, cases);
}

// One row per variant, a pair of columns per precision: what a reviewer reads first.
void compact_table(std::string& out, const json& report) {
    std::vector<std::string> variants, precisions;
    std::map<std::pair<std::string, std::string>, const json*> cell;
    const auto add = [&](const json& r, const std::string& precision) {
        const std::string v = r["variant"].get<std::string>();
        if (std::find(variants.begin(), variants.end(), v) == variants.end()) variants.push_back(v);
        if (std::find(precisions.begin(), precisions.end(), precision) == precisions.end())
            precisions.push_back(precision);
        cell[{v, precision}] = &r;
    };
    if (report.contains("results"))
        for (const json& r : report.at("results")) add(r, r["precision"].get<std::string>());
    if (report.contains("long_double") && report.at("long_double").contains("results"))
        for (const json& r : report.at("long_double").at("results")) add(r, "long double");
    if (variants.empty()) return;
    out += "\n| variant |";
    for (const std::string& p : precisions) out += fmt::format(" wrong, {0} | max ulp, {0} |", p);
    out += "\n|---|";
    for (std::size_t i = 0; i < precisions.size(); ++i) out += "---:|---:|";
    out += "\n";
    for (const std::string& v : variants) {
        out += fmt::format("| {} |", v);
        for (const std::string& p : precisions) {
            const auto it = cell.find({v, p});
            if (it == cell.end()) {
                out += " | |";
                continue;
            }
            const json& r = *it->second;
            const std::size_t wrong = r["disagreements"].get<std::size_t>(), n = scored_in(r["verdicts"]);
            out += fmt::format(" {} ({}) | {} |", wrong, percent(wrong, n),
                               figure_text(r["near_root_ulp"].value("max", json())));
        }
        out += "\n";
    }
    out += "\nwrong: answers that disagree with the exact one, of the cases each target is scored on; max ulp: "
           "the nearest root's largest error where the answer agrees (- when the variant returns no root), over "
           "this finite corpus.\n";
}

// A folded section: GitHub renders the summary line and hides the rest.
std::string folded(const std::string& summary, const std::string& body) {
    return fmt::format("\n<details><summary>{}</summary>\n{}\n</details>\n", summary, body);
}

}  // namespace

std::string render_summary_markdown(const json& report) {
    std::string out = headline(report);
    compact_table(out, report);
    return out;
}

// The contract each target was judged under, once per variant (its precisions share it).
void contracts_judged(std::string& out, const json& results) {
    std::vector<std::string> seen;
    std::string rows;
    for (const json& r : results) {
        const std::string v = r["variant"].get<std::string>();
        if (std::find(seen.begin(), seen.end(), v) != seen.end() || !r.contains("contract")) continue;
        seen.push_back(v);
        rows += fmt::format("| {} | `{}` | {} |\n", v, r["contract"]["spec"].get<std::string>(),
                            r["contract"].value("meaning", std::string()));
    }
    if (rows.empty()) return;
    out += "\n| variant | contract judged | meaning |\n|---|---|---|\n" + rows;
}

std::string render_markdown(const json& report) {
    std::string out = render_summary_markdown(report);
    if (report.contains("contract_hints") && !report["contract_hints"].empty()) {
        out += "\n### The contract\n\n```\n" + render_contract_hints(report["contract_hints"]) + "```\n";
    }
    if (report.contains("cases_to_open") && !report["cases_to_open"].empty())
        out += folded("Cases to open: the first of each verdict, and agreeing hits far from the exact one",
                      render_cases_to_open_markdown(report["cases_to_open"]));

    if (report.contains("builds")) out += "\n### Builds\n\n" + render_builds_markdown(report["builds"]);

    if (report.contains("plots")) {
        const json& plots = report["plots"];
        if (!plots["rendered"].get<bool>()) {
            out += fmt::format("\n**No plots:** {}\n", plots["message"].get<std::string>());
        } else {
            out += fmt::format("\n### Plots\n\nPer-case points (error against condition, ULP histograms) are drawn "
                               "from the plot sample: at most {} cases per family, the ones with the smallest hash "
                               "of their id, so the same cases whatever the threads or shards; totals and maxima "
                               "are over every case.\n\n",
                               case_points::per_family);
            for (const json& f : plots["files"]) {
                const std::string name = f.get<std::string>();
                out += fmt::format("![{}]({})\n\n", plot_title(name), name);
            }
        }
    }

    std::string contracts;
    if (report.contains("results")) contracts_judged(contracts, report["results"]);
    if (!contracts.empty()) out += folded("Contracts judged: what each target promises", contracts);
    std::string accuracy;
    if (report.contains("results")) accuracy_table(accuracy, report["results"], "float and double (the audit)");
    if (report.contains("long_double") && report["long_double"].contains("results"))
        accuracy_table(accuracy, report["long_double"]["results"],
                       "long double arithmetic on double inputs, roots rounded to double");
    if (!accuracy.empty()) out += folded("Accuracy: every target", accuracy);
    if (report.contains("stability")) {
        std::string stability;
        stability_tables(stability, report["stability"]);
        out += folded("Stability: conditioning-limited or algorithmic", stability);
    }
    if (report.contains("timing")) {
        std::string timing;
        timing_tables(timing, report["timing"]);
        out += folded("Run time", timing);
    }
    if (report.contains("far_sphere_sweep")) {
        std::string sweep;
        sweep_table(sweep, report["far_sphere_sweep"]);
        out += folded("Far-sphere sweep", sweep);
    }

    std::string run = fmt::format("\n- command: `{}`\n", report.value("command", std::string()));
    const json& build = report["build"];
    run += fmt::format("- rayverify's build (the flags of the built-in variants, not of a plugin, results file or "
                       "program, whose build is its own): {} `{}` [{}], rayverify {}\n",
                       build["compiler"].get<std::string>(), build["flags"].get<std::string>(), build["build_type"].get<std::string>(),
                       build["rayverify_version"].get<std::string>());
    if (report.contains("machine")) run += machine_lines(report);
    if (report.contains("results")) {
        // Each library audited as shipped once, with the set-up it ran (Embree's kernel).
        std::vector<std::string> named;
        for (const json& r : report["results"]) {
            if (!r.contains("library")) continue;
            const std::string variant = r["variant"].get<std::string>();
            if (std::find(named.begin(), named.end(), variant) != named.end()) continue;
            named.push_back(variant);
            const json& l = r["library"];
            run += fmt::format("- library: `{}` is {} {} ({}){}\n", variant, l["name"].get<std::string>(),
                               l["version"].get<std::string>(), l["source"].get<std::string>(),
                               l.contains("configuration") ? ", " + l["configuration"].get<std::string>() : "");
        }
        named.clear();
        for (const json& r : report["results"]) {
            if (!r.contains("fp_environment")) continue;
            const std::string variant = r["variant"].get<std::string>();
            if (std::find(named.begin(), named.end(), variant) != named.end()) continue;
            named.push_back(variant);
            run += fmt::format("- floating-point environment: `{}` runs in {} (rayverify's own arithmetic in the IEEE "
                               "default)\n",
                               variant, r["fp_environment"].get<std::string>());
        }
    }
    if (report.contains("corpus")) {
        run += fmt::format("- corpus: {} cases", report["corpus"]["cases"].get<std::size_t>());
        if (report["corpus"].contains("cases_by_family")) {
            std::string families;
            for (const auto& [family, count] : report["corpus"]["cases_by_family"].items())
                families += fmt::format("{}{} {}", families.empty() ? "" : ", ", family, count.get<std::size_t>());
            run += " (" + families + ")";
        }
        run += "\n";
    }
    out += folded("How this report was made", run);
    return out;
}

plot_choices plot_choices_of(const std::vector<std::string>& formats, const std::string& error_measure) {
    plot_choices choices;
    if (!formats.empty()) choices.formats.clear();
    for (const std::string& format : formats) {
        if (format != "png" && format != "svg" && format != "pdf")
            throw input_error("", 0, "--plot-format", fmt::format("'{}' is not png, svg or pdf", printable(format)));
        if (std::find(choices.formats.begin(), choices.formats.end(), format) == choices.formats.end())
            choices.formats.push_back(format);
    }
    if (error_measure.empty()) return choices;
    const auto colon = error_measure.find(':');
    const std::string figure = error_measure.substr(0, colon),
                      statistic = colon == std::string::npos ? "" : error_measure.substr(colon + 1);
    const bool known = std::any_of(error_figures.begin(), error_figures.end(),
                                   [&](const error_figure_definition& f) { return f.name == figure; });
    if (!known) {
        std::vector<std::string_view> names;
        for (const error_figure_definition& f : error_figures) names.push_back(f.name);
        throw input_error("", 0, "--error-measure",
                          fmt::format("'{}' is not an error figure ({})", printable(figure), fmt::join(names, ", ")));
    }
    if (statistic != "max" && statistic != "p99" && statistic != "median")
        throw input_error("", 0, "--error-measure",
                          fmt::format("'{}' is not FIGURE:max, FIGURE:p99 or FIGURE:median", printable(error_measure)));
    choices.error_measure = error_measure;
    return choices;
}

plot_outcome render_plots(const std::filesystem::path& dir, const plot_choices& choices) {
    plot_outcome outcome;
    const std::string python = RAYVERIFY_PLOT_PYTHON, script = data_file("plot_report.py", RAYVERIFY_PLOT_SCRIPT).string();
    if (!std::filesystem::exists(python)) {
        outcome.message = python + " not found: install python3-matplotlib (tools/setup.sh) for the plots";
        return outcome;
    }
    if (std::system((python + " -c 'import matplotlib' >/dev/null 2>&1").c_str()) != 0) {
        outcome.message = "matplotlib is not installed for " + python +
                          ": install python3-matplotlib (tools/setup.sh) for the plots";
        return outcome;
    }
    // The wrong-class and the unscored verdicts from the one verdict table, so
    // that the script keeps no list of its own.
    const auto names_where = [](bool (*holds)(verdict_kind)) {
        std::string names;
        for (int k = 0; k < verdict_kind_count; ++k)
            if (holds(static_cast<verdict_kind>(k)))
                names += (names.empty() ? "" : ",") + std::string(verdict_name(static_cast<verdict_kind>(k)));
        return names;
    };
    const std::string command = fmt::format(
        "'{}' '{}' '{}' --misclassifications {} --unscored {} --format {} --error-measure {} 2>&1", python,
        script, dir.string(), names_where(is_misclassification),
        names_where([](verdict_kind k) { return !is_scored(k); }), fmt::join(choices.formats, ","),
        choices.error_measure);
    std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(command.c_str(), "r"), pclose);
    if (!pipe) {
        outcome.message = "cannot run " + script;
        return outcome;
    }
    std::string output;
    std::array<char, 512> buffer{};
    while (fgets(buffer.data(), buffer.size(), pipe.get())) output += buffer.data();
    const int status = pclose(pipe.release());
    std::size_t start = 0;
    std::vector<std::string> lines;
    while (start < output.size()) {
        const std::size_t end = output.find('\n', start);
        lines.push_back(output.substr(start, end - start));
        start = end == std::string::npos ? output.size() : end + 1;
    }
    if (status != 0) {
        outcome.message = "the plotting script failed: " + output;
        return outcome;
    }
    for (const std::string& line : lines)
        if (line.rfind("wrote ", 0) == 0) outcome.files.push_back(line.substr(6));
    outcome.rendered = true;
    outcome.message = fmt::format("{} plots drawn with matplotlib (plot_report.py)", outcome.files.size());
    return outcome;
}

namespace {

// The directory is declared (created, locked) before the files in it.
run_outputs& with_directory(run_outputs& outputs, const std::filesystem::path& dir, const std::string& option) {
    outputs.directory(dir, option);
    return outputs;
}

}  // namespace

report_bundle::report_bundle(run_outputs& outputs, const std::filesystem::path& dir, const std::string& option)
    : outputs_(with_directory(outputs, dir, option)),
      dir_(dir),
      option_(option),
      json_(outputs.file(dir / "report.json", option)),
      markdown_(outputs.file(dir / "report.md", option)) {}

plot_outcome report_bundle::write(json report, bool draw, const plot_choices& choices) {
    plot_outcome plots;
    if (draw) {
        const std::filesystem::path stage = outputs_.staging_directory(dir_);
        {
            std::ofstream copy(stage / "report.json", std::ios::binary);
            copy << json_text(report, 2) << '\n';
            if (!copy.flush()) throw input_error((stage / "report.json").string(), 0, option_, "cannot write");
        }
        plots = render_plots(stage, choices);
        for (const std::string& file : plots.files) {
            if (std::filesystem::path(file).filename() != file)
                throw input_error(RAYVERIFY_PLOT_SCRIPT, 0, "", "wrote a file outside its directory: " + file);
            outputs_.adopt(stage / file, dir_ / file);
        }
    } else {
        plots.message = "not drawn (rayverify audit draws them with --plots; rayverify bench always does)";
    }
    report["plots"] = {{"rendered", plots.rendered}, {"message", plots.message}, {"files", plots.files}};
    json_.stream() << json_text(report, 2) << '\n';
    markdown_.stream() << render_markdown(report);
    return plots;
}

}  // namespace rayverify
