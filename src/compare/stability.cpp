#include "compare/stability.h"

#include <algorithm>
#include <cmath>
#include <tuple>

namespace rayverify {

int condition_bucket(const stability_measures& s) {
    if (!s.near_condition) return condition_decades + 1;
    const double kappa = *s.near_condition;
    if (std::isinf(kappa)) return condition_decades;
    if (kappa < 10) return 0;
    return std::min(static_cast<int>(std::floor(std::log10(kappa))), condition_decades - 1);
}

std::string condition_bucket_label(int bucket) {
    if (bucket == condition_decades + 1) return "miss";
    if (bucket == condition_decades) return "inf";
    if (bucket == 0) return "<1e1";
    if (bucket == condition_decades - 1) return ">=1e" + std::to_string(bucket);
    return "1e" + std::to_string(bucket) + "..1e" + std::to_string(bucket + 1);
}

void stability_samples::merge(const stability_samples& other) {
    for (int b = 0; b < condition_bucket_count; ++b) {
        bucket_tally& mine = buckets[b];
        const bucket_tally& theirs = other.buckets[b];
        mine.cases += theirs.cases;
        mine.misclassified += theirs.misclassified;
        mine.disagreements += theirs.disagreements;
        mine.conditioning_limited += theirs.conditioning_limited;
        mine.algorithmic += theirs.algorithmic;
        mine.by_design += theirs.by_design;
        near_ulp[b].merge(other.near_ulp[b]);
    }
    excess.merge(other.excess);
    above_line += other.above_line;
    well_conditioned += other.well_conditioned;
    well_conditioned_above += other.well_conditioned_above;
}

stability_accumulator::stability_accumulator(std::vector<audit_target> t) : targets(std::move(t)) {}

void stability_accumulator::add(const audited_case& c, std::size_t index) {
    const case_stability& s = c.stability;
    auto& family_samples = by_family[family_key(*c.source)];
    family_samples.resize(targets.size());
    const std::string& id = c.source->id;
    // The case's κ decade at each precision, found once for its targets (a log10 each).
    std::optional<int> float_bucket, double_bucket;
    for (std::size_t t = 0; t < targets.size(); ++t) {
        const case_score& score = c.outcomes[t].score;
        if (!is_scored(score.verdict)) continue;
        const precision prec = targets[t].prec;
        const stability_measures& m = s.at(prec);
        std::optional<int>& found = prec == precision::binary32 ? float_bucket : double_bucket;
        if (!found) found = condition_bucket(m);
        const int bucket = *found;
        stability_samples& out = family_samples[t];
        bucket_tally& b = out.buckets[bucket];
        ++b.cases;
        if (is_misclassification(score.verdict)) ++b.misclassified;
        if (is_disagreement(score.verdict)) ++b.disagreements;
        if (const auto& cause = score.cause) {
            if (*cause == disagreement_cause::conditioning_limited) ++b.conditioning_limited;
            if (*cause == disagreement_cause::algorithmic) ++b.algorithmic;
            if (is_by_design(*cause)) ++b.by_design;
        }
        if (score.verdict != verdict_kind::agree) continue;
        const exact_solution& exact = c.exact_for(prec);
        // The near root's error and its excess over the line, kept to their
        // printed digits (case_score::figure_upper_bounds), are tallied by
        // their bounds; the case is judged again to every digit only where a
        // maximum, or on which side of the line it lies, needs it.
        std::optional<double> near_upper;
        if (score.near_ulp) {
            near_upper = definition_of(error_figure::near_root_ulp).upper_of_case(score);
            out.near_ulp[bucket].add_bounded(*score.near_ulp, *near_upper, index, id,
                                             [&] { return c.every_digit(t, targets[t]).near_ulp.value(); });
        }
        std::optional<double> excess = excess_over_line(score, m, exact, prec);
        if (!excess) continue;
        double excess_upper =
            score.figure_upper_bounds ? excess_over_line(near_upper, score, m, exact, prec).value() : *excess;
        const auto exact_excess = [&] { return excess_over_line(c.every_digit(t, targets[t]), m, exact, prec).value(); };
        if (!bounds_in_one_bucket(*excess, excess_upper) ||
            (*excess <= stability_factor) != (excess_upper <= stability_factor))
            excess = excess_upper = exact_excess();
        out.excess.add_bounded(*excess, excess_upper, index, id, exact_excess);
        const bool above = !(*excess <= stability_factor);
        out.above_line += above;
        if (m.near_condition && *m.near_condition < 1e3) {
            ++out.well_conditioned;
            out.well_conditioned_above += above;
        }
    }
}

void stability_accumulator::merge(const stability_accumulator& other) {
    merge_families(by_family, other.by_family, targets.size());
}

namespace {

stability_tally summarise_stability(const stability_samples& s) {
    stability_tally tally;
    error_summary all_ulp;
    for (int b = 0; b < condition_bucket_count; ++b) {
        tally.buckets[b] = s.buckets[b];
        tally.buckets[b].near_root_ulp = s.near_ulp[b].statistics();
        all_ulp.merge(s.near_ulp[b]);
        tally.all.cases += s.buckets[b].cases;
        tally.all.misclassified += s.buckets[b].misclassified;
        tally.all.disagreements += s.buckets[b].disagreements;
        tally.all.conditioning_limited += s.buckets[b].conditioning_limited;
        tally.all.algorithmic += s.buckets[b].algorithmic;
        tally.all.by_design += s.buckets[b].by_design;
    }
    tally.all.near_root_ulp = all_ulp.statistics();
    tally.judged = s.excess.count;
    tally.above_line = s.above_line;
    tally.well_conditioned = s.well_conditioned;
    tally.well_conditioned_above = s.well_conditioned_above;
    tally.excess = s.excess.statistics();
    return tally;
}

}  // namespace

stability_totals stability_accumulator::finish(unsigned threads) const {
    stability_totals totals;
    std::tie(totals.overall, totals.by_family) =
        summarised(merged_over_families(by_family, targets.size(), threads), by_family, threads, summarise_stability);
    return totals;
}

}  // namespace rayverify
