#include "compare/case_examples.h"

#include <algorithm>
#include <cmath>

namespace rayverify {

namespace {

bool earlier(const case_example& a, const case_example& b) { return a.index < b.index; }
bool farther(const case_example& a, const case_example& b) {
    return a.error != b.error ? a.error > b.error : a.index < b.index;
}

// Keeps the `kept` best of `into` and `e` by `better`, sorted.
template <class Better>
void keep(std::vector<case_example>& into, case_example e, Better better) {
    if (into.size() == case_examples::kept && !better(e, into.back())) return;
    // Room for the kept cases and the one that may push the last out, made
    // at the first: growing one at a time reallocated on each of the first three.
    if (into.capacity() == 0) into.reserve(case_examples::kept + 1);
    into.insert(std::upper_bound(into.begin(), into.end(), e, better), std::move(e));
    if (into.size() > case_examples::kept) into.pop_back();
}

// The larger of a disagreeing answer's root errors in ULPs; none when no t was
// judged against an exact root.
std::optional<double> root_error_ulp(const case_score& s) {
    if (!s.near_ulp && !s.far_ulp) return std::nullopt;
    return std::max(s.near_ulp.value_or(0), s.far_ulp.value_or(0));
}

}  // namespace

case_examples::case_examples(std::size_t targets) : first(targets), worst(targets), farthest(targets) {}

void case_examples::add(const audited_case& c, std::size_t index, std::span<const audit_target> targets) {
    for (std::size_t t = 0; t < c.outcomes.size() && t < first.size(); ++t) {
        const case_score& s = c.outcomes[t].score;
        if (is_disagreement(s.verdict)) {
            auto& list = first[t][static_cast<int>(s.verdict)];
            if (list.size() < kept || index < list.back().index)
                keep(list, {index, 0, *c.source, s.cause}, earlier);
            const std::optional<double> ulp = root_error_ulp(s);
            auto& worst_list = worst[t][static_cast<int>(s.verdict)];
            if (ulp && !std::isnan(*ulp) && (worst_list.size() < kept || farther({index, *ulp, {}, {}}, worst_list.back())))
                keep(worst_list, {index, *ulp, *c.source, s.cause}, farther);
        } else if (s.verdict == verdict_kind::agree && s.scale_error_radius) {
            // The figure, or its bounds where it is kept to its printed
            // digits: both in one histogram bucket, so on one side of
            // agree_far_fraction (a bucket's edge).
            const double lower = *s.scale_error_radius;
            const double upper = s.figure_upper_bounds ? s.figure_upper_bounds->scale_error_radius : lower;
            if (upper < agree_far_fraction) continue;
            auto& list = farthest[t];
            if (list.size() == kept && !farther({index, upper, {}, {}}, list.back())) continue;
            const double error = upper == lower ? lower : c.every_digit(t, targets[t]).scale_error_radius.value();
            if (!(error < agree_far_fraction) && (list.size() < kept || farther({index, error, {}, {}}, list.back())))
                keep(list, {index, error, *c.source, std::nullopt}, farther);
        }
    }
}

void case_examples::merge(const case_examples& other) {
    for (std::size_t t = 0; t < first.size() && t < other.first.size(); ++t) {
        for (int k = 0; k < verdict_kind_count; ++k)
            for (const case_example& e : other.first[t][k]) keep(first[t][k], e, earlier);
        for (int k = 0; k < verdict_kind_count && t < worst.size() && t < other.worst.size(); ++k)
            for (const case_example& e : other.worst[t][k]) keep(worst[t][k], e, farther);
        for (const case_example& e : other.farthest[t]) keep(farthest[t], e, farther);
    }
}

}  // namespace rayverify
