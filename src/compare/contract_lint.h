// The contract lint: a target whose answers contradict its declared contract
// in a pattern another contract explains (one root where the line has two,
// t = 0 where the ray starts inside, roots outside the interval it was given,
// a hit count without roots, a t beside a hit point that is right where the t
// is not), and the contract that fits. Every answer is
// judged again, by the one judge (judge_output), under each neighbouring
// contract (lint_candidates), on the range the target was asked; the verdicts
// that would change are counted. Pure functions and a mergeable tally.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "compare/audit.h"
#include "compare/judge.h"
#include "core/contract.h"
#include "core/ray_sphere_case.h"

namespace rayverify {

// A contract the answers might fit, and the pattern of answers it explains.
struct lint_candidate {
    contract promises;
    std::string pattern;  // e.g. "one root, the nearest in the interval it was given, where the line has two"
    // any_hit from line_roots judges a count and no t: it explains more
    // answers than a candidate that judges t, by asking less, so it is
    // suggested only when no candidate that judges t fits.
    bool judges_t = true;
};

// The neighbours of `declared` worth judging again under: another query
// (line_roots → nearest hit in the given interval, nearest hit on the ray,
// any hit), another inside rule, closed ends, tangent a miss, front faces
// only, the interval ignored, and a t beside a hit point: the point the
// answer. In a fixed order, the most specific first (a tie between two
// candidates goes to the earlier).
std::vector<lint_candidate> lint_candidates(const contract& declared);

// The range a candidate is judged on for an answer given under `declared`:
// the interval the target was asked (its entry points get (−inf, +inf) for
// line_roots, (0, +inf) for a ray, the case's own for an interval), with
// the candidate's ends; a candidate on a ray ignores what it was given.
t_range lint_range(const contract& declared, const contract& candidate, const t_range& judged);

// One target's answers, judged again: per candidate, how many of the scored
// cases it would turn from a disagreement into agree (fixed), and from agree
// into a disagreement (broken). Mergeable; the same for any split of the cases.
struct contract_lint_tally {
    std::size_t scored = 0;  // cases judged under the declared contract (not invalid or outside it)
    std::size_t wrong = 0;   // of those, disagreements
    std::vector<std::size_t> fixed, broken;  // aligned with the candidates
    void merge(const contract_lint_tally& other);
};

// Adds one judged case: `score` and `output` the target's outcome under
// `declared` on `range`, `exact` and `input` as the judge had them.
void lint_case(const contract& declared, std::span<const lint_candidate> candidates, const case_score& score,
               const variant_output& output, const exact_solution& exact, const t_range& range,
               const ray_sphere<double>& input, contract_lint_tally& into);

// The candidate that explains the answers, when one does: it fixes at least
// half of the disagreements (and at least `minimum_fixed` cases) and more
// than four times as many cases as it breaks; of those, the ones that judge t
// first, then the one with the largest fixed − broken, the earlier on a tie.
struct contract_hint {
    lint_candidate candidate;
    std::size_t scored = 0, wrong = 0, fixed = 0, broken = 0;
};
inline constexpr std::size_t lint_minimum_fixed = 5;
std::optional<contract_hint> strongest_hint(std::span<const lint_candidate> candidates,
                                            const contract_lint_tally& tally);

// The lint over an audit: every target whose contract was declared outside
// rayverify (a plugin, a results file; not a built-in variant, whose contract
// is reviewed beside its source) has its candidates and a tally; the others
// have neither. Mergeable, like the audit's other accumulators.
struct contract_lint_accumulator {
    explicit contract_lint_accumulator(const std::vector<audit_target>& targets = {});
    void add(const audited_case& c);
    void merge(const contract_lint_accumulator& other);
    // The hint for each target (aligned with the targets; nullopt for none).
    std::vector<std::optional<contract_hint>> hints() const;

    std::vector<contract> declared;                       // aligned with the targets
    std::vector<precision> precisions;                    // aligned with the targets
    std::vector<std::vector<lint_candidate>> candidates;  // empty for a built-in
    std::vector<contract_lint_tally> tallies;
};

}  // namespace rayverify
