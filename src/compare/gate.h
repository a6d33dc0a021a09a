// The numeric gate: an audit's figures (per target, family and figure: the
// count of each disagreement kind, max and p99 ULP error of each root)
// compared with a reviewed baseline under a policy. Pure functions over
// strings and audit results; the CLI reads and writes the files.
//
// Baseline text, one entry a line (glibc's libm-test-ulps habit: `#` comment
// lines belong to the entry below them and survive --update):
//
//     rayverify-baseline 1
//     policy default ulp_slack 1          # a ULP figure may grow to baseline × slack
//     policy default count_slack 0        # a count may grow by this many cases
//     policy naive/float ulp_slack 2      # per variant ("naive") or target ("naive/float")
//     library embree3 kernel avx512, Embree's choice for this CPU
//     contract naive query=line_roots,range=ray,ends=(),...
//     naive/float all cases 3000
//     naive/float far_sphere false_miss 45
//     naive/float far_sphere near_ulp_max 1.2e+08
//
// A `library VARIANT TEXT` line records the set-up of the library a target
// ran (library_identity::configuration: the kernel Embree picked for the CPU,
// say), which decides its answers as much as the code does: a run whose
// set-up differs from the baseline's fails the gate, naming both, instead of
// failing on figures that moved for that reason. A `contract VARIANT SPEC`
// line records the contract the variant was judged by (its canonical spec,
// core/contract.h): a run under another contract scores other cases, so
// its figures are not comparable and the gate fails, naming both, instead
// of reporting the cases it no longer scores as "better".
#pragma once

#include <cstddef>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "compare/audit.h"

namespace rayverify {

// The family name of the figures over the whole corpus.
inline constexpr std::string_view all_families = "all";

// The gated figures, in file order: "cases" (how many cases the figures are
// over), "scored" (how many of them were judged: not invalid at the precision,
// not breaking the contract; fewer is worse), one count per disagreement
// verdict, then near_ulp_max, near_ulp_p99, far_ulp_max, far_ulp_p99 (over
// agreeing cases; absent when there are none).
inline constexpr std::string_view scored_figure = "scored";
std::span<const std::string_view> figure_names();
bool is_ulp_figure(std::string_view figure);

struct figure_key {
    std::string target;  // "naive/float"
    std::string family;  // a corpus family, or all_families
    std::string figure;  // one of figure_names()
    // Target, then the whole corpus before its families, then figure_names() order.
    bool operator<(const figure_key& other) const;
    bool operator==(const figure_key& other) const = default;
    std::string text() const;  // "naive/float far_sphere false_miss"
};

using figure_table = std::map<figure_key, double>;

figure_table figures_of(const audit_totals& totals);

// How much worse a figure may get before the gate fails.
struct gate_policy {
    double ulp_slack = 1;    // a ULP figure fails when it exceeds baseline × ulp_slack
    double count_slack = 0;  // a count fails when it exceeds baseline + count_slack
};

struct policy_line {
    std::string scope;  // "default", a variant name, or a target label
    std::string key;    // "ulp_slack" or "count_slack"
    double value = 0;
    std::vector<std::string> comments;  // the comment lines above it, verbatim
};

// The library set-up each target ran with (library_identity::configuration),
// by variant name; only targets whose library reports one.
using configuration_table = std::map<std::string, std::string>;
configuration_table configurations_of(std::span<const audit_target> targets);
// The contract each target was judged by (format_contract), by variant name.
configuration_table contracts_of(std::span<const audit_target> targets);

struct configuration_line {
    std::string text;
    std::vector<std::string> comments;  // the comment lines above it, verbatim

    bool operator==(const configuration_line&) const = default;
};

struct baseline {
    std::vector<std::string> format_comments;  // comment lines above the format line
    std::vector<policy_line> policies;          // in file order; the last matching line wins
    std::map<std::string, configuration_line> configurations;  // `library VARIANT TEXT` lines, by variant
    std::map<std::string, configuration_line> contracts;       // `contract VARIANT SPEC` lines, by variant
    // `allow-missing NAME` lines: a family, a variant or a target the baseline
    // holds that a run may leave out (each with the comment lines above it).
    std::vector<std::pair<std::string, std::vector<std::string>>> allowed_missing;
    figure_table figures;
    std::map<figure_key, std::vector<std::string>> comments;  // comment lines above each figure
    std::vector<std::string> trailing_comments;                // after the last entry, or orphaned by --update

    // default, overridden by the variant's lines, overridden by the target's.
    gate_policy policy_for(const std::string& target) const;
};

// Throws input_error(file, line, field, ...) on any malformed line.
baseline parse_baseline(const std::string& file, std::string_view text);
std::string format_baseline(const baseline& b);

// A baseline for a file that does not exist yet: the format explained in
// comments and the default policy.
baseline new_baseline();

// --update: every figure of a target in `current` is replaced by the current
// value (figures that vanished are dropped, their comments kept at the end);
// targets not run keep their lines; policies and comments are kept. A
// variant run with a library set-up records it (`library` line); one run
// without drops the line. Every variant run records its contract (`contract` line).
baseline updated_baseline(const baseline& old, const figure_table& current,
                          const configuration_table& current_configurations = {},
                          const configuration_table& current_contracts = {});

enum class change_kind {
    worse,         // beyond the policy: fails the gate
    within_slack,  // worse than the baseline but within the policy
    better,        // the baseline can be tightened
    stale,         // the family's case count changed: figures not comparable, fails
    new_entry,     // no baseline for it: reported, not a failure
    missing,       // in the baseline, absent from the run (a family not in the corpus, a target not run):
                   // fails unless allowed (`allow-missing NAME`, --allow-missing NAME)
};

struct figure_change {
    figure_key key;
    std::optional<double> before, after;
    change_kind kind = change_kind::worse;
    double limit = 0;  // for worse and within_slack: the largest value the policy allows (scored: the smallest)
};

// What a variant ran under besides its code, recorded in the baseline.
enum class setup_aspect {
    library,   // its library's set-up (`library` line)
    contract,  // the contract it was judged by (`contract` line)
};

// "library set-up" or "contract", as reports and notes name them.
std::string_view setup_aspect_name(setup_aspect aspect);

// A variant whose library ran with another set-up, or that was judged by
// another contract, than the baseline records.
struct configuration_change {
    std::string variant;
    std::string before, after;  // the baseline's; this run's (empty: none reported)
    setup_aspect aspect = setup_aspect::library;
};

struct gate_result {
    std::vector<figure_change> changes;  // every figure that differs, in figure_key order
    std::vector<configuration_change> configuration_changes;  // library set-ups, then contracts: each fails the gate
    // Targets (labels) that scored no case of the run (each invalid at its
    // precision or breaking its contract): they passed nothing, and fail.
    std::vector<std::string> unscored;
    std::vector<std::string> notes;      // what was not compared, and why
    std::size_t compared = 0;            // figures compared with a baseline value
    bool passed() const;
};

// The comparison proper. A family whose "cases" differ is stale (a failure);
// the whole-corpus figures of a target whose case count differs are not
// compared (the corpus grew or shrank: a note, since its families still are);
// targets and families without a baseline are new (a note); baseline entries
// for targets not run are ignored. Nothing compared at all is a failure.
// ULP figures are decimal approximations of exact errors: two that differ by
// at most `tolerance` relative to the larger are the same figure (last-digit
// noise); counts are compared exactly.
// A variant run whose library set-up differs from the baseline's `library`
// line, or whose contract differs from its `contract` line, is a
// configuration_change (a failure); one the baseline has figures for but no
// such line, while this run reports a set-up or a contract, a note. A family or
// target of the baseline that the run lacks is `missing` (a failure: a gate
// does not pass on less than it was asked to judge) unless the baseline's
// `allow-missing` lines or `allow_missing` name it (a family, a variant or a
// target), which makes it a note.
inline constexpr double default_figure_tolerance = 1e-9;
gate_result compare_to_baseline(const baseline& base, const figure_table& current,
                                double tolerance = default_figure_tolerance,
                                const configuration_table& current_configurations = {},
                                const std::vector<std::string>& allow_missing = {},
                                const configuration_table& current_contracts = {});

// Every difference between two figure tables, judged with one policy
// (`rayverify diff`: before = A, after = B).
gate_result compare_figures(const figure_table& before, const figure_table& after, const gate_policy& policy,
                            double tolerance = default_figure_tolerance);

// The first cases of each (target, family, verdict) and the case attaining
// each ULP maximum, so that a failing figure can be shown as corpus lines.
class gate_examples {
public:
    explicit gate_examples(std::size_t per_figure) : per_figure_(per_figure) {}
    void add(const audited_case& c, const std::vector<audit_target>& targets);
    // The cases behind a figure (a verdict count; for a ULP figure, the maximum's case).
    std::vector<const corpus_case*> cases_for(const figure_key& key, const audit_totals& totals,
                                              std::span<const corpus_case> corpus) const;

private:
    std::size_t per_figure_;
    std::map<figure_key, std::vector<const corpus_case*>> cases_;
};

// An audit run against a baseline: what `rayverify gate` and the GoogleTest
// helper both do.
struct gate_run {
    audit_totals totals;
    figure_table current;
    configuration_table configurations;  // the library set-up each variant ran with
    configuration_table contracts;       // the contract each variant was judged by
    gate_result result;
    gate_examples examples{0};
};
gate_run run_gate(std::span<const corpus_case> cases, const std::vector<audit_target>& targets,
                  const baseline& base, std::size_t examples_per_figure, unsigned threads = 1,
                  double tolerance = default_figure_tolerance, const std::vector<std::string>& allow_missing = {});

}  // namespace rayverify
