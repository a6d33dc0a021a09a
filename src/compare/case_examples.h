// Cases to open: per target and verdict, the first few disagreeing cases in
// input order, and the agreeing cases whose hit lies farthest from the exact
// one (agree but far, compare/audit.h). Bounded (a few cases per target and
// verdict) and mergeable: the same cases whatever the threads or chunks.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <vector>

#include "compare/audit.h"

namespace rayverify {

struct case_example {
    std::size_t index = 0;  // global case index
    double error = 0;       // farthest: |t − t*|·|d| / r; else 0
    corpus_case kase;
    std::optional<disagreement_cause> cause;
};

struct case_examples {
    static constexpr std::size_t kept = 3;

    explicit case_examples(std::size_t targets = 0);
    void add(const audited_case& c, std::size_t index);
    void merge(const case_examples& other);

    // [target][verdict]: the first `kept` cases of each disagreeing verdict, by index.
    std::vector<std::array<std::vector<case_example>, verdict_kind_count>> first;
    // [target]: the `kept` agreeing cases with the largest scale error at or
    // above agree_far_fraction, the largest first (ties: the lower index).
    std::vector<std::vector<case_example>> farthest;
};

}  // namespace rayverify
