// bench's report: the accuracy and stability of the targets it times, audited
// in one pass beside the timings, and report.json and the text tables from
// them. Rendering and one audit pass only: the timings come from bench/timing.
#pragma once

#include <nlohmann/json.hpp>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "bench/timing.h"
#include "compare/audit.h"
#include "compare/stability.h"
#include "report/audit_report.h"

namespace rayverify {

// The label of the target every ratio of bench is to, timed in the same run.
inline constexpr const char* bench_reference_label = "naive/double";

// The totals of targets [first, first + count), as if audited alone.
audit_totals slice(const audit_totals& all, std::size_t first, std::size_t count);

// Accuracy and stability of `targets` over `cases` (one oracle pass).
struct accuracy_run {
    audit_totals totals;
    stability_totals stability;
    nlohmann::ordered_json points;  // the plots' sample (case_points)
};

// The audit and its stability of `cases` on `threads` threads; with
// `per_case`, each case's per-case line (report/audit_report.h) for the first
// `per_case_targets` targets (bench's float and double ones: the long double
// targets share their labels), in corpus order.
accuracy_run audit_with_stability(const std::vector<corpus_case>& cases, const std::vector<audit_target>& targets,
                                  const std::vector<std::string>& labels, unsigned threads,
                                  std::ostream* per_case = nullptr, std::size_t per_case_targets = 0);

// bench's audit: the first `audited` targets in float and double, the rest
// (if any) the long double forms; each target's precision as its rows say it.
struct bench_accuracy {
    accuracy_run run;
    std::size_t audited = 0;
    std::vector<std::string> precision_labels;
};

// The far-sphere sweep (`bench --sweep N`): its cases, seed and audit.
struct far_sphere_sweep_run {
    std::size_t cases = 0;
    std::uint64_t seed = 0;
    accuracy_run run;
};

// robust_sphere.h's figures: per family, the share of cases its fast path
// left to the exact path, and its cost against naive/double beside the
// target; as report.json's "robust_sphere" (null when none of its variants
// was timed) and as text.
struct robust_sphere_figures {
    nlohmann::ordered_json json;
    std::string text;
};
robust_sphere_figures robust_figures(const std::vector<bench::timing_row>& rows,
                                     const std::map<std::string, std::vector<corpus_case>>& by_family);

// The timing table bench prints: per target, ns per test and the ratio to the reference.
std::string timing_table_text(const nlohmann::ordered_json& timing_section, std::size_t cases, int repetitions);

// Where a bench run's figures come from besides its build: the machine as the
// timings began, and the input files (corpus files and plugins) by path, size
// and digest (core/hash.h), so that a table in a paper names exactly what was run.
struct bench_provenance {
    bench::machine_record machine;
    nlohmann::ordered_json input_files = nlohmann::ordered_json::array();
};

// bench's report.json: the audit's sections (float and double, then long
// double), stability, timing, robust_sphere.h's figures, the plots' sample,
// the sweep, the machine and the input files.
nlohmann::ordered_json bench_report_document(const bench_accuracy& accuracy, const run_context& context,
                                             const nlohmann::ordered_json& timing_section,
                                             const nlohmann::ordered_json& robust,
                                             const std::optional<far_sphere_sweep_run>& sweep,
                                             const bench_provenance& provenance);

// bench.csv: bench's figures as one table, a row per target and family timed
// (the timing's rows, in their order): variant, precision, family, cases
// timed; the CPU time per test as the repetitions' median, the median's
// distribution-free confidence interval and its confidence, the minimum and
// maximum, their count and the ratio to the reference; then, where the
// target was audited, the scored cases, those given the wrong class, a column
// per verdict and, per error
// figure, its count, max, p99 and median (the columns report.json's
// by_family holds). Then a row per target whose family is
// `all_families_row` (report/table_csv.h): the whole corpus (timing.overall's case-weighted
// time and ratio, results' verdicts and figures; no interval, minimum or
// maximum). Numbers as the shortest decimal that reads back to the same
// double (`inf`, `nan`); a figure with no value, or a target not audited
// (the exact oracles), is an empty field.
std::string bench_table_csv(const nlohmann::ordered_json& report);

}  // namespace rayverify
