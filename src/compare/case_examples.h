// Cases to open: per target and verdict, the first few disagreeing cases in
// input order and the worst few by their root error in ULPs (the verdicts
// whose answer has a t judged against an exact root: wrong_root, wrong_side,
// tangent_split, false_tangent, ...), and the agreeing cases whose hit lies
// farthest from the exact one (agree but far, compare/audit.h). Bounded (a few
// cases per target and verdict) and mergeable: the same cases whatever the
// threads, chunks or shards.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <span>
#include <vector>

#include "compare/audit.h"

namespace rayverify {

struct case_example {
    std::size_t index = 0;  // global case index
    double error = 0;       // farthest: |t − t*|·|d| / r; worst: the larger root error in ULPs; else 0
    corpus_case kase;
    std::optional<disagreement_cause> cause;
};

struct case_examples {
    static constexpr std::size_t kept = 3;

    explicit case_examples(std::size_t targets = 0);
    // `targets`: those `c` was judged for. An agreeing answer's scale error
    // kept to its printed digits (case_score::figure_upper_bounds) is judged
    // again to every digit only where it may enter the farthest list.
    void add(const audited_case& c, std::size_t index, std::span<const audit_target> targets);
    void merge(const case_examples& other);

    // [target][verdict]: the first `kept` cases of each disagreeing verdict, by index.
    std::vector<std::array<std::vector<case_example>, verdict_kind_count>> first;
    // [target][verdict]: the `kept` disagreeing cases of each verdict with the
    // largest root error in ULPs (the larger of near_ulp and far_ulp), the
    // largest first (ties: the lower index); none where the verdict's answers
    // have no root error (false_miss, false_hit: no t against an exact root).
    std::vector<std::array<std::vector<case_example>, verdict_kind_count>> worst;
    // [target]: the `kept` agreeing cases with the largest scale error at or
    // above agree_far_fraction, the largest first (ties: the lower index).
    std::vector<std::vector<case_example>> farthest;
};

}  // namespace rayverify
