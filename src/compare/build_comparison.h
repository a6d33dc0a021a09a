// Builds of one source compared with its reference build, case by case
// (`rayverify builds`, docs/builds.md): every target of the audit that is a
// build is paired with the reference build's target of the same precision,
// and each case's answers and verdicts are compared bit for bit. Pure
// computation over audited cases; report/builds_report renders it.
#pragma once

#include <cstddef>
#include <map>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "compare/audit.h"
#include "compare/judge.h"

namespace rayverify {

// Two answers the same to the bit: the hit count, the values counted, and
// every output given beside them (-0 is not +0; any NaN equals any NaN).
bool same_answer(const variant_output& a, const variant_output& b);

// One case whose verdict a build changed, as the report shows it.
struct build_flip {
    std::size_t index = 0;  // in the whole input
    corpus_case source;
    verdict_kind reference_verdict = verdict_kind::agree, build_verdict = verdict_kind::agree;
    variant_output reference_answer, build_answer;
    std::string detail;  // the build's verdict in one sentence (case_score::detail), or the reference's
};

// How a build's answers differ from the reference's at one precision.
struct build_difference {
    std::size_t target = 0;     // the build's index among the audit's targets
    std::size_t reference = 0;  // the reference build's, at the same precision
    std::size_t cases = 0;      // cases both were judged on (scored by both)
    std::size_t answers_changed = 0;
    // (the reference's verdict, the build's) → cases
    std::map<std::pair<verdict_kind, verdict_kind>, std::size_t> flips;
    // Cases both agree on whose root error (the larger of the near and far
    // ULP errors) is smaller / larger in the build.
    std::size_t better = 0, worse = 0;
    // The changed cases with the build's answers and both verdicts, in input
    // order, the first `kept_changes` of them (the bisect re-runs candidate
    // builds on them).
    struct change {
        corpus_case source;
        variant_output answer;
        verdict_kind reference_verdict = verdict_kind::agree, build_verdict = verdict_kind::agree;
    };
    std::vector<change> changes;
    // The first case of each kind of flip (input order).
    std::map<std::pair<verdict_kind, verdict_kind>, build_flip> first_flips;

    // The flipped cases to show: the first of each kind of flip, at most
    // `count`, the worst kinds first (into a misclassification, into another
    // disagreement, out of a disagreement), then the kinds with more cases.
    std::vector<build_flip> worst(std::size_t count) const;

    std::size_t verdicts_flipped() const {
        std::size_t n = 0;
        for (const auto& [kinds, count] : flips) n += count;
        return n;
    }
};

// Accumulates build_difference for each pair (build target, reference target)
// from audited cases given in input order.
class build_comparison {
public:
    // `pairs`: (build target, reference target) indices into the audit's targets.
    build_comparison(std::vector<std::pair<std::size_t, std::size_t>> pairs, std::size_t kept_changes);
    void add(const audited_case& audited, std::size_t index);
    const std::vector<build_difference>& differences() const { return differences_; }

private:
    std::vector<build_difference> differences_;
    std::size_t kept_changes_;
};

// The severity rank of a flip from `reference` to `build` (0 worst), as
// build_difference::worst orders them.
int flip_severity(verdict_kind reference, verdict_kind build);
// Kinds of flip with their case counts, the worst first, then the more frequent.
using flip_count = std::pair<std::pair<verdict_kind, verdict_kind>, std::size_t>;
std::vector<flip_count> flips_worst_first(std::vector<flip_count> flips);

}  // namespace rayverify
