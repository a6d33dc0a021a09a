// What `bench --audit` measures: what a user waits for, the whole audit's cost
// per case-target in multiples of the naive double intersector, per family;
// where that time goes (the targets' answers, the oracle, the judge, the
// tallies, stability and the plot sample); the cost of the per-case lines;
// the share of each exact figure the oracle's filter settled; and the cost of
// generating a corpus. Measuring only: report/audit_timing_report.h renders
// the rows and the targets they are held to.
#pragma once

#include <cstddef>
#include <functional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "compare/audit.h"
#include "core/ray_sphere_case.h"
#include "oracle/oracle.h"

namespace rayverify::bench {

// The targets the per case-target ratio is measured with: the textbook
// formulas (textbook_variant_names, intersectors/variants.def) in both
// precisions, so that adding an engine port does not move the figure
// (docs/oracle.md).
std::vector<audit_target> audit_timing_targets();

// The goals the figures are held to (bench prints met or MISSED beside each).
struct audit_cost_goals {
    double ordinary_family = 40;  // audit / naive double on uniform and far_sphere
    double stiff_family = 100;    // on every other family (the stiff ones)
    double per_case_lines = 2;    // the audit writing --per-case lines, over the audit alone
    double generation_us = 1;     // corpus generate --family uniform, CPU µs per case
    double limit_for(const std::string& family) const {
        return family == "uniform" || family == "far_sphere" ? ordinary_family : stiff_family;
    }
};

// Where a whole audit's time goes, per case-target in multiples of naive
// double's time per case. The targets' answers and the oracle are timed on
// their own; the other three are differences of neighbouring timings of ever
// larger parts of the pass (audit_case, audit_stream, the whole pass), so on
// a noisy machine a small part may come out a little below 0.
struct audit_parts {
    double targets = 0;     // every target's own answers (answer_of on run_input's inputs)
    double oracle = 0;      // solve_case on the double and the float inputs
    double verdicts = 0;    // audit_case asked for verdicts alone, less the two above: outputs widened, verdicts
    double figures = 0;     // audit_case less audit_case asked for verdicts alone: every error figure, exactly
    double accumulate = 0;  // audit_stream less audit_case: verdict tallies, error histograms
    double stability = 0;   // the whole pass less audit_stream: stability figures, plot sample
    double sum() const { return targets + oracle + verdicts + figures + accumulate + stability; }
    // The parts in the order they are printed, with their names.
    std::vector<std::pair<std::string, double>> named() const;
};

struct audit_timing_row {
    std::string family;
    std::size_t cases = 0;
    double naive_ns = 0;        // per case, median over the repetitions
    double audit_ns = 0;        // per case-target, the audit as `rayverify audit --report` runs it, median
    double audit_ratio = 0;     // audit_ns / naive_ns, median of the repetitions' ratios
    double per_case_ratio = 0;  // the audit writing --per-case lines over the audit alone, median of ratios
    double per_case_bytes = 0;  // bytes of per-case lines per case-target
    audit_parts parts;          // where the audit's time goes, × naive, medians of each repetition's ratios
    oracle_stage_counts counts;
    double checksum = 0;  // sums figures of every timed result: proves the results were used
};

// CPU µs per case of `corpus generate --family uniform`, the text written to nowhere.
struct generation_timing {
    double us_per_case = 0;     // median
    double bytes_per_case = 0;  // of the text written
};

struct audit_timing {
    std::vector<audit_timing_row> rows;  // per family in name order, then "all"
    std::size_t target_count = 0;
    int repetitions = 0;
    generation_timing generation;
    audit_cost_goals goals;
};

// One whole pass of the audit over the cases `next` gives, as the audit
// command runs it (report/audit_pass.h, a layer above this one, so the caller
// hands it in), on one thread, per-case lines to `per_case` when not null;
// returns the number of cases audited.
using whole_audit_pass =
    std::function<std::size_t(const case_source& next, const std::vector<audit_target>& targets, std::ostream* per_case)>;

// Times the audit (one thread) of `cases` per family and over all of them,
// `repetitions` times, each timing at least `min_time_s` of CPU.
audit_timing measure_audit_timing(const std::vector<corpus_case>& cases, int repetitions, double min_time_s,
                                  const whole_audit_pass& pass);

}  // namespace rayverify::bench
