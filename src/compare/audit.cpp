#include "compare/audit.h"

#include <algorithm>
#include <cmath>

namespace rayverify {

std::vector<audit_target> targets_for(std::span<const variant> variants) {
    std::vector<audit_target> targets;
    for (const variant& v : variants)
        for (precision p : {precision::binary32, precision::binary64})
            if (v.runs_in(p)) targets.push_back({v, p});
    return targets;
}

namespace {

template <class T>
target_outcome run_target(const audit_target& target, const corpus_case& c, const exact_solution& exact) {
    target_outcome outcome;
    if (!exact.valid()) {
        outcome.score.verdict = verdict_kind::invalid;
        outcome.score.detail = invalid_reason_name(exact.invalid);
        return outcome;
    }
    const ray_sphere<T> input = rounded_to<T>(c.geometry);
    const ray_sphere<double> widened = rounded_to<double>(input);
    if (auto breach = contract_breach(target.subject.promises, widened, target.prec)) {
        outcome.score.verdict = verdict_kind::contract_violation;
        outcome.score.detail = *breach;
        return outcome;
    }
    if constexpr (std::is_same_v<T, float>)
        outcome.output = evaluate(target.subject.run_float, target.subject.promises, input);
    else
        outcome.output = evaluate(target.subject.run_double, target.subject.promises, input);
    outcome.score = score_case(target.subject.promises, outcome.output, exact, widened);
    return outcome;
}

exact_solution solve_at(const corpus_case& c, precision p) {
    // A case that overflows float is invalid there; the oracle then never sees it.
    const invalid_reason reason =
        p == precision::binary32 ? validity<float>(c.geometry) : validity<double>(c.geometry);
    if (reason != invalid_reason::none) {
        exact_solution invalid;
        invalid.prec = p;
        invalid.invalid = reason;
        return invalid;
    }
    const ray_sphere<double> input = p == precision::binary32 ? rounded_to<double>(rounded_to<float>(c.geometry))
                                                              : c.geometry;
    const auto bound = [p](std::optional<double> t) -> std::optional<double> {
        if (!t || p == precision::binary64) return t;
        return static_cast<double>(static_cast<float>(*t));
    };
    return solve_exact(input, p, bound(c.tmin), bound(c.tmax));
}

}  // namespace

audited_case audit_case(const corpus_case& c, std::span<const audit_target> targets) {
    audited_case result;
    result.source = &c;
    result.exact_double = solve_at(c, precision::binary64);
    if (std::any_of(targets.begin(), targets.end(),
                    [](const audit_target& t) { return t.prec == precision::binary32; }))
        result.exact_float = solve_at(c, precision::binary32);
    result.outcomes.reserve(targets.size());
    for (const audit_target& target : targets) {
        const exact_solution& exact = result.exact_for(target.prec);
        result.outcomes.push_back(target.prec == precision::binary32 ? run_target<float>(target, c, exact)
                                                                     : run_target<double>(target, c, exact));
    }
    return result;
}

std::size_t target_tally::disagreements() const {
    std::size_t n = 0;
    for (int k = 0; k < verdict_kind_count; ++k)
        if (is_disagreement(static_cast<verdict_kind>(k))) n += verdicts[k];
    return n;
}

audit_accumulator::audit_accumulator(std::vector<audit_target> targets)
    : targets_(std::move(targets)), overall_(targets_.size()) {}

void audit_accumulator::add(const audited_case& c) {
    const std::size_t index = case_ids_.size();
    case_ids_.push_back(c.source->id);
    const std::string family = c.source->family.empty() ? "-" : c.source->family;
    ++cases_by_family_[family];
    if (!c.exact_double.valid()) ++invalid_[1];
    if (c.exact_float && !c.exact_float->valid()) ++invalid_[0];
    if (!c.exact_double.valid() || (c.exact_float && !c.exact_float->valid()))
        invalid_list_.push_back({c.source->id, c.source->source,
                                 c.exact_float ? c.exact_float->invalid : invalid_reason::none,
                                 c.exact_double.invalid});

    auto& family_samples = by_family_[family];
    family_samples.resize(targets_.size());
    for (std::size_t t = 0; t < targets_.size(); ++t) {
        const case_score& score = c.outcomes[t].score;
        for (samples* s : {&overall_[t], &family_samples[t]}) {
            ++s->cases;
            ++s->verdicts[static_cast<int>(score.verdict)];
            if (score.verdict != verdict_kind::agree) continue;
            if (score.near_ulp) s->near_ulp.emplace_back(*score.near_ulp, index);
            if (score.far_ulp) s->far_ulp.emplace_back(*score.far_ulp, index);
            if (score.near_bits) s->near_bits.emplace_back(*score.near_bits, index);
            if (score.hit_point_ulp) {
                const auto& e = *score.hit_point_ulp;
                s->hit_ulp.emplace_back(std::max({e[0], e[1], e[2]}), index);
            }
        }
    }
}

// Nearest-rank quantiles; ties in the maximum go to the earliest case.
error_statistics statistics_of(std::vector<std::pair<double, std::size_t>> sample,
                               const std::vector<std::string>& ids) {
    error_statistics stats;
    stats.count = sample.size();
    if (sample.empty()) return stats;
    std::sort(sample.begin(), sample.end(), [](const auto& a, const auto& b) {
        return a.first != b.first ? a.first < b.first : a.second > b.second;
    });
    const auto rank = [&](double q) {
        const auto k = static_cast<std::size_t>(std::ceil(q * static_cast<double>(sample.size())));
        return sample[std::clamp<std::size_t>(k, 1, sample.size()) - 1].first;
    };
    stats.max = sample.back().first;
    stats.max_case = ids[sample.back().second];
    stats.p99 = rank(0.99);
    stats.median = rank(0.5);
    return stats;
}

target_tally audit_accumulator::summarise(const samples& s) const {
    target_tally tally;
    tally.cases = s.cases;
    tally.verdicts = s.verdicts;
    tally.near_root_ulp = statistics_of(s.near_ulp, case_ids_);
    tally.far_root_ulp = statistics_of(s.far_ulp, case_ids_);
    tally.hit_point_ulp = statistics_of(s.hit_ulp, case_ids_);
    tally.near_root_bits = statistics_of(s.near_bits, case_ids_);
    return tally;
}

audit_totals audit_accumulator::finish() const {
    audit_totals totals;
    totals.targets = targets_;
    totals.cases = case_ids_.size();
    totals.cases_by_family = cases_by_family_;
    totals.invalid_cases = invalid_;
    totals.invalid_list = invalid_list_;
    for (const samples& s : overall_) totals.overall.push_back(summarise(s));
    for (const auto& [family, per_target] : by_family_) {
        auto& out = totals.by_family[family];
        for (const samples& s : per_target) out.push_back(summarise(s));
    }
    return totals;
}

audit_totals run_audit(std::span<const corpus_case> cases, const std::vector<audit_target>& targets,
                       const std::function<void(const audited_case&)>& on_case,
                       const std::function<void(std::size_t, std::size_t)>& on_progress) {
    audit_accumulator accumulator(targets);
    for (std::size_t i = 0; i < cases.size(); ++i) {
        const audited_case audited = audit_case(cases[i], targets);
        accumulator.add(audited);
        if (on_case) on_case(audited);
        if (on_progress && (i % 256 == 0 || i + 1 == cases.size())) on_progress(i + 1, cases.size());
    }
    return accumulator.finish();
}

}  // namespace rayverify
