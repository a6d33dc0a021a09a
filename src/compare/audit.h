// The audit: every case through the exact oracle and every target variant,
// judged and tallied. Pure computation; reports render what this produces.
#pragma once

#include <array>
#include <functional>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "compare/verdict.h"
#include "core/ray_sphere_case.h"
#include "intersectors/registry.h"
#include "oracle/oracle.h"

namespace rayverify {

// One variant in one precision, e.g. naive/float.
struct audit_target {
    variant subject;
    precision prec = precision::binary64;
    std::string label() const { return subject.name + "/" + precision_name(prec); }
};

// Every variant of `variants` in each precision it runs in, float first.
std::vector<audit_target> targets_for(std::span<const variant> variants);

struct target_outcome {
    case_score score;
    variant_output output;  // empty for invalid or contract-violating cases
};

struct audited_case {
    const corpus_case* source = nullptr;
    exact_solution exact_double;                 // for the double inputs
    std::optional<exact_solution> exact_float;   // for the float-rounded inputs (when a target runs in float)
    std::vector<target_outcome> outcomes;        // aligned with the targets

    const exact_solution& exact_for(precision p) const {
        return p == precision::binary32 ? *exact_float : exact_double;
    }
};

audited_case audit_case(const corpus_case& c, std::span<const audit_target> targets);

// Order statistics of a sample of errors, with the case that attains the maximum.
struct error_statistics {
    std::size_t count = 0;
    double max = 0, p99 = 0, median = 0;
    std::string max_case;  // id of the case with the largest error
};

// Order statistics of (error, case index) pairs, nearest rank; `ids` names
// the cases by index.
error_statistics statistics_of(std::vector<std::pair<double, std::size_t>> sample,
                               const std::vector<std::string>& ids);

// Everything tallied for one target over a set of cases.
struct target_tally {
    std::size_t cases = 0;
    std::array<std::size_t, verdict_kind_count> verdicts{};
    // Errors over the cases whose verdict is agree (disagreements are counted above).
    error_statistics near_root_ulp, far_root_ulp, hit_point_ulp, near_root_bits;
    std::size_t disagreements() const;
};

// A case that is invalid in some precision: listed in reports, never scored.
struct invalid_case {
    std::string id;
    std::string source;  // "file:line"
    invalid_reason at_float = invalid_reason::none;   // none when valid there or not run in float
    invalid_reason at_double = invalid_reason::none;
};

struct audit_totals {
    std::vector<audit_target> targets;
    std::size_t cases = 0;
    std::map<std::string, std::size_t> cases_by_family;
    std::vector<target_tally> overall;                             // aligned with targets
    std::map<std::string, std::vector<target_tally>> by_family;   // family → aligned with targets
    std::array<std::size_t, 2> invalid_cases{};                    // [float, double]
    std::vector<invalid_case> invalid_list;                       // every invalid case, in corpus order
};

// Accumulates audited cases, then computes the statistics.
class audit_accumulator {
public:
    explicit audit_accumulator(std::vector<audit_target> targets);
    void add(const audited_case& c);
    audit_totals finish() const;

private:
    struct samples {
        std::array<std::size_t, verdict_kind_count> verdicts{};
        std::size_t cases = 0;
        std::vector<std::pair<double, std::size_t>> near_ulp, far_ulp, hit_ulp, near_bits;  // (error, case index)
    };
    std::vector<audit_target> targets_;
    std::vector<std::string> case_ids_;
    std::map<std::string, std::size_t> cases_by_family_;
    std::array<std::size_t, 2> invalid_{};
    std::vector<invalid_case> invalid_list_;
    std::vector<samples> overall_;
    std::map<std::string, std::vector<samples>> by_family_;

    target_tally summarise(const samples& s) const;
};

// Run the whole audit. `on_case` sees every audited case in corpus order (for
// per-case output); `on_progress(done, total)` is called now and then.
audit_totals run_audit(std::span<const corpus_case> cases, const std::vector<audit_target>& targets,
                       const std::function<void(const audited_case&)>& on_case = {},
                       const std::function<void(std::size_t, std::size_t)>& on_progress = {});

}  // namespace rayverify
