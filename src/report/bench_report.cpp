#include "report/bench_report.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <optional>
#include <thread>

#include "bench/robust_fallback.h"
#include "compare/error_figures.h"
#include "report/stability_report.h"
#include "report/table_csv.h"

namespace rayverify {

using json = nlohmann::ordered_json;

audit_totals slice(const audit_totals& all, std::size_t first, std::size_t count) {
    audit_totals out = all;
    const auto cut = [&](auto& v) { v = {v.begin() + first, v.begin() + first + count}; };
    cut(out.targets);
    cut(out.overall);
    for (auto& [family, tallies] : out.by_family) cut(tallies);
    return out;
}

accuracy_run audit_with_stability(const std::vector<corpus_case>& cases, const std::vector<audit_target>& targets,
                                  const std::vector<std::string>& labels, unsigned threads, std::ostream* per_case,
                                  std::size_t per_case_targets) {
    stability_accumulator stability(targets);
    case_points points(targets, labels);
    const std::vector<audit_target> lined(targets.begin(),
                                          targets.begin() + static_cast<long>(std::min(per_case_targets, targets.size())));
    std::string line;
    std::size_t index = 0;
    const auto on_case = [&](const audited_case& c) {
        stability.add(c, index);
        points.add(c, index++);
        if (per_case == nullptr) return;
        line = per_case_line(c, lined, std::move(line));
        *per_case << line << '\n';
    };
    accuracy_run run;
    // on_case sees the cases in corpus order whatever the thread count: the same figures.
    run.totals = run_audit(cases, targets, on_case, {}, threads);
    run.stability = stability.finish();
    run.points = points.to_json();
    return run;
}

namespace {

// Why a robust_sphere.h query missed its cost target, from this run's figures:
// where its cases went (the fallback rows), what the decisions alone cost
// (robust_any_hit in the same precision; for the segment query, the ray's
// nearest hit), and the cheaper tier measured beside it where there is one.
std::string missed_reason(const std::string& variant, const std::string& precision, double ratio,
                          const bench::robust_fallback_row* stages, const std::optional<double>& decisions_ratio,
                          const std::optional<double>& bounded_ratio) {
    const double target = bench::robust_target_ratio;
    std::string why;
    if (stages != nullptr && stages->cases > 0) {
        const std::size_t left = stages->refined + stages->exact;
        if (left * 20 < stages->cases) {
            why = fmt::format("the static filter settles {} of {} cases, so the cost is the filter's own: ",
                              stages->cases - left, stages->cases);
            if (variant == bench::robust_segment_name) {
                // Its reference is naive_segment, not naive: the ray figures do not subtract from its ratio.
                why += "the ray's nearest-hit work on RN(p1 − p0) with that rounding in the bounds";
                if (decisions_ratio)
                    why += fmt::format(" (robust_nearest/{} costs {:.2f}× naive here: its reasons hold for this query)",
                                       precision, *decisions_ratio);
            } else if (variant == "robust_any_hit" || !decisions_ratio) {
                why += "naive's coefficients plus their error bounds and the comparisons against them";
                if (precision == "float") why += ", the float inputs converted to double";
                why += fmt::format("; meeting {:g}× needs a filter of fewer operations", target);
            } else if (*decisions_ratio < target) {
                why += fmt::format("the decisions alone (robust_any_hit) cost {:.2f}× here, the root with its "
                                   "certificate (q's bound, the rounding checked at both ends of the root's "
                                   "enclosure) the other {:.2f}×; meeting {:g}× needs that root for at most {:.2f}×",
                                   *decisions_ratio, ratio - *decisions_ratio, target, target - *decisions_ratio);
            } else {
                why += fmt::format("the decisions alone (robust_any_hit) already cost {:.2f}× here; meeting {:g}× "
                                   "needs a filter of fewer operations before any root",
                                   *decisions_ratio, target);
            }
        } else {
            why = fmt::format("{} of {} cases go to the double-word stage, {} to the exact path", stages->refined,
                              stages->cases, stages->exact);
            if (precision == "double" && variant != "robust_any_hit" && variant.find("bounded") == std::string::npos)
                why += " (a correctly rounded double root needs the double-word stage wherever one is returned; "
                       "without FMA each exact product is Dekker's split)";
        }
    }
    if (bounded_ratio)
        why += fmt::format("; where a root within 2^-44 will do, the bounded tier (the same decisions) costs {:.2f}×",
                           *bounded_ratio);
    return why;
}

}  // namespace

robust_sphere_figures robust_figures(const std::vector<bench::timing_row>& rows,
                                     const std::map<std::string, std::vector<corpus_case>>& by_family) {
    std::vector<std::string> names(std::begin(bench::robust_variant_names), std::end(bench::robust_variant_names));
    names.push_back(bench::robust_segment_name);
    std::vector<std::string> labels;
    for (const std::string& name : names)
        for (const precision prec : every_precision) labels.push_back(name + "/" + precision_name(prec));
    const auto find_row = [&](const std::string& label, const std::string& family) -> const bench::timing_row* {
        const auto row = std::find_if(rows.begin(), rows.end(), [&](const bench::timing_row& r) {
            return r.label() == label && r.family == family;
        });
        return row == rows.end() ? nullptr : &*row;
    };
    const auto timed = [&](const std::string& label) {
        return std::any_of(rows.begin(), rows.end(), [&](const bench::timing_row& r) { return r.label() == label; });
    };
    if (std::none_of(labels.begin(), labels.end(), timed)) return {nullptr, ""};
    std::string text;

    const std::vector<bench::robust_fallback_row> fallbacks = bench::robust_fallbacks(by_family);
    const auto stages_of = [&](const std::string& family, const std::string& variant,
                               const std::string& prec) -> const bench::robust_fallback_row* {
        for (const bench::robust_fallback_row& r : fallbacks)
            if (r.family == family && r.variant == variant && r.precision == prec) return &r;
        return nullptr;
    };
    text += fmt::format("\nrobust_sphere.h: cases its static filter left to the double-word stage + the exact path "
                        "(refined + exact / valid cases), per family; {} on each ray as a segment to o + L·d\n",
                        bench::robust_segment_name);
    text += fmt::format("{:<22}", "family");
    for (const std::string& l : labels) text += fmt::format(" {:>24}", l);
    text += fmt::format("\n");
    json fallback_json = json::array();
    for (const auto& [family, cases] : by_family) {
        text += fmt::format("{:<22}", family);
        for (const bench::robust_fallback_row& r : fallbacks) {
            if (r.family != family) continue;
            text += fmt::format(" {:>24}", fmt::format("{} + {}/{}", r.refined, r.exact, r.cases));
            fallback_json.push_back({{"family", r.family}, {"variant", r.variant}, {"precision", r.precision},
                                     {"cases", r.cases}, {"refined", r.refined}, {"exact_path", r.exact}});
        }
        text += fmt::format("\n");
    }

    text += fmt::format("\nrobust_sphere.h against its target: ns per test / naive/double's ({}: / {}/double's, "
                        "the same segments), this run, target ≤ {:g}; under a MISSED one, why, measured in this run\n",
                        bench::robust_segment_name, bench::naive_segment_name, bench::robust_target_ratio);
    json target_json = json::array();
    for (const char* family : bench::robust_target_families) {
        const bench::timing_row* naive = find_row(bench_reference_label, family);
        if (naive == nullptr || naive->median <= 0) continue;
        const bench::timing_row* naive_segment = find_row(std::string(bench::naive_segment_name) + "/double", family);
        const auto against_naive = [&](const std::string& label) -> std::optional<double> {
            const bench::timing_row* r = find_row(label, family);
            return r == nullptr ? std::nullopt : std::optional<double>(r->median / naive->median);
        };
        for (const std::string& label : labels) {
            const bench::timing_row* row = find_row(label, family);
            const bool segment = row != nullptr && row->variant == bench::robust_segment_name;
            const bench::timing_row* reference = segment ? naive_segment : naive;
            if (row == nullptr || reference == nullptr || reference->median <= 0) continue;
            const double ratio = row->median / reference->median;
            const bool met = bench::target_met(ratio, bench::robust_target_ratio, bench::target_direction::at_most);
            text += fmt::format("  {:<44} {:>8.2f}×  {}\n", fmt::format("{}, {}", label, family), ratio,
                                met ? "met" : "MISSED");
            json entry = {{"family", family},
                          {"variant", row->variant},
                          {"precision", row->precision},
                          {"reference", reference->label()},
                          {"ratio_to_naive_double", ratio},
                          {"met", met}};
            if (!met) {
                // The bounded tier beside a correctly rounded double query (in
                // float the two tiers are one: its roots are correctly rounded).
                const std::string bounded = row->precision != "double"         ? ""
                                            : row->variant == "robust"         ? "robust_bounded"
                                            : row->variant == "robust_nearest" ? "robust_bounded_nearest"
                                                                               : "";
                const std::optional<double> bounded_ratio =
                    bounded.empty() ? std::nullopt : against_naive(bounded + "/" + row->precision);
                // What the decisions alone cost (robust_any_hit); for the segment
                // query, what the ray's nearest hit costs, the same work on a ray.
                const std::optional<double> decisions_ratio =
                    against_naive((segment ? "robust_nearest/" : "robust_any_hit/") + row->precision);
                const std::string why =
                    missed_reason(row->variant, row->precision, ratio, stages_of(family, row->variant, row->precision),
                                  decisions_ratio, bounded_ratio);
                text += fmt::format("    {}\n", why);
                entry["reason"] = why;
            }
            target_json.push_back(std::move(entry));
        }
    }
    return {{{"description", "robust_sphere.h (variants robust, robust_nearest, robust_any_hit, robust_bounded, "
                            "robust_bounded_nearest, and robust_segment: segment_hit on each ray as the segment o to "
                            "o + L·d): cases its static filter left to the double-word stage and to the exact path "
                            "per family, and ns per test against naive/double (robust_segment: against naive_segment, "
                            "the textbook quadratic on the same segments) in this run, with the measured reason "
                            "where a target is missed"},
             {"target_ratio", bench::robust_target_ratio},
             {"exact_path", fallback_json},
             {"against_target", target_json}},
            text};
}


std::string timing_table_text(const json& timing_section, std::size_t cases, int repetitions) {
    std::string text = fmt::format("{:<26} {:<12} {:>12} {:>10}\n", "variant", "precision", "ns/test", "ratio");
    for (const json& r : timing_section["overall"])
        text += fmt::format("{:<26} {:<12} {:>12.2f} {:>10}\n", r["variant"].get<std::string>(),
                            r["precision"].get<std::string>(), r["ns_per_test"].get<double>(),
                            r["ratio_to_reference"].is_null() ? std::string("-")
                                                              : fmt::format("{:.2f}", r["ratio_to_reference"].get<double>()));
    text += fmt::format("{} cases; ns per ray–sphere test, CPU time, median of {} repetitions per family, "
                        "case-weighted; ratio to {} in this run.\n",
                        cases, repetitions, bench_reference_label);
    return text;
}

json bench_report_document(const bench_accuracy& accuracy, const run_context& context, const json& timing_section,
                           const json& robust, const std::optional<far_sphere_sweep_run>& sweep,
                           const bench_provenance& provenance) {
    const accuracy_run& all = accuracy.run;
    const std::size_t audited = accuracy.audited, targets = all.totals.targets.size();
    json report = audit_report_json(slice(all.totals, 0, audited), context);
    report["tool"] = "rayverify bench";
    const bench::machine_record& m = provenance.machine;
    report["machine"] = {{"cpu", m.cpu},
                         {"hardware_threads", m.hardware_threads},
                         {"cpu_flags", m.cpu_flags},
                         {"cpu_mhz", optional_number(m.cpu_mhz)},
                         {"cpu_max_mhz", optional_number(m.cpu_max_mhz)},
                         {"load_average", m.load_average ? json(*m.load_average) : json()},
                         {"kernel", m.kernel},
                         {"when", "read as the timings began"}};
    report["input_files"] = provenance.input_files;
    if (audited < targets) {
        json long_double = audit_report_json(slice(all.totals, audited, targets - audited), context);
        for (json& r : long_double["results"]) r["precision"] = "long double";
        report["long_double"] = {{"description", "x87 80-bit long double arithmetic on the double inputs, roots "
                                                 "rounded to double, judged against the exact roots of the double "
                                                 "inputs"},
                                 {"results", long_double["results"]}};
    }
    report["stability"] = stability_json(all.totals, all.stability, accuracy.precision_labels);
    report["timing"] = timing_section;
    if (!robust.is_null()) report["robust_sphere"] = robust;
    report["case_points"] = all.points;
    if (sweep)
        report["far_sphere_sweep"] = {
            {"description", fmt::format("{} far_sphere cases (rayverify corpus generate --family far_sphere --count {} "
                                        "--seed {}), grouped by decade of |o - c| / r; every maximum is over this "
                                        "finite sample",
                                        sweep->cases, sweep->cases, sweep->seed)},
            {"results", audit_report_json(sweep->run.totals, context)["results"]},
            {"case_points", sweep->run.points}};
    return report;
}

std::string bench_table_csv(const json& report) {
    // The audited targets' sections by "variant/precision": float and double, then long double.
    std::map<std::string, const json*> audited;
    const auto add = [&](const json* results) {
        if (results == nullptr) return;
        for (const json& r : *results)
            audited[r["variant"].get<std::string>() + "/" + r["precision"].get<std::string>()] = &r;
    };
    add(json_member(&report, "results"));
    add(json_member(json_member(&report, "long_double"), "results"));
    const auto audited_section = [&](const std::string& variant, const std::string& precision) -> const json* {
        const auto found = audited.find(variant + "/" + precision);
        return found == audited.end() ? nullptr : found->second;
    };

    std::vector<std::string> header{"variant",
                                    "precision",
                                    "family",
                                    "cases_timed",
                                    "ns_per_test_median",
                                    "ns_per_test_median_low",
                                    "ns_per_test_median_high",
                                    "median_interval_confidence",
                                    "ns_per_test_min",
                                    "ns_per_test_max",
                                    "repetitions",
                                    "ratio_to_reference"};
    for (std::string& column : audit_csv_header()) header.push_back(std::move(column));
    std::string out = fmt::format("{}\n", fmt::join(header, ","));
    const auto write_row = [&](std::vector<std::string> fields, const json* section) {
        for (std::string& field : audit_csv_fields(section)) fields.push_back(std::move(field));
        out += fmt::format("{}\n", fmt::join(fields, ","));
    };
    for (const json& row : report["timing"]["rows"]) {
        const json& ns = row["ns_per_test"];
        const json* interval = json_member(&ns, "median_interval");
        write_row({csv_field(&row["variant"]), csv_field(&row["precision"]), csv_field(&row["family"]),
                   csv_field(&row["cases"]), csv_field(json_member(&ns, "median")),
                   csv_field(json_member(interval, "low")), csv_field(json_member(interval, "high")),
                   csv_field(json_member(interval, "confidence")), csv_field(json_member(&ns, "min")),
                   csv_field(json_member(&ns, "max")),
                   std::to_string(json_member(&ns, "repetitions") ? ns["repetitions"].size() : 0),
                   csv_field(json_member(&row, "ratio_to_reference"))},
                  json_member(json_member(audited_section(row["variant"], row["precision"]), "by_family"),
                              row["family"].get<std::string>()));
    }
    // Then a row per target over every family (report.json's timing.overall and results): the
    // case-weighted mean of the families' medians, its ratio, and the whole corpus's verdicts and figures.
    for (const json& row : report["timing"]["overall"])
        write_row({csv_field(&row["variant"]), csv_field(&row["precision"]), std::string(all_families_row),
                   csv_field(&row["cases"]), csv_field(json_member(&row, "ns_per_test")), "", "", "", "", "", "",
                   csv_field(json_member(&row, "ratio_to_reference"))},
                  audited_section(row["variant"], row["precision"]));
    return out;
}

}  // namespace rayverify
