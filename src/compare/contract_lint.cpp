#include "compare/contract_lint.h"

#include <limits>

#include "core/intersection.h"
#include "intersectors/registry.h"

namespace rayverify {

namespace {

// A nearest_hit or any_hit contract keeps only what a line_roots one shares with it.
contract without_line_fields(contract c) {
    const contract defaults;
    c.reports_tangent = defaults.reports_tangent;
    c.tangent_rule = defaults.tangent_rule;
    c.tangent_threshold = defaults.tangent_threshold;
    return c;
}

std::string_view inside_pattern(inside_rule rule) {
    switch (rule) {
        case inside_rule::far_root: return "the exit root where the range starts inside the sphere";
        case inside_rule::clamp: return "a hit at the range start (t = 0, clamped) where it starts inside the sphere";
        case inside_rule::miss: return "no hit where the range starts inside the sphere";
    }
    return "";
}

}  // namespace

std::vector<lint_candidate> lint_candidates(const contract& declared) {
    std::vector<lint_candidate> out;
    const std::string declared_spec = format_contract(declared);
    const auto add = [&](const contract& c, std::string pattern, bool judges_t = true) {
        if (format_contract(c) == declared_spec || contract_problem(c)) return;
        out.push_back({c, std::move(pattern), judges_t});
    };
    if (declared.query == query_kind::line_roots) {
        if (declared.answer != answer_kind::t || declared.outputs.any()) return out;
        contract nearest = without_line_fields(declared);
        nearest.query = query_kind::nearest_hit;
        nearest.range = range_source::interval;
        nearest.lower_end = nearest.upper_end = end_kind::open;
        add(nearest, "one root, the nearest in the interval it was given, where the line has two");
        contract on_ray = nearest;
        on_ray.range = range_source::ray;
        on_ray.lower_end = end_kind::closed;
        add(on_ray, "one root, the nearest with t >= 0, where the line has two");
        contract clamped = on_ray;
        clamped.inside = inside_rule::clamp;
        add(clamped, "one root, the nearest with t >= 0, and t = 0 where the ray starts inside the sphere");
        contract any = nearest;
        any.query = query_kind::any_hit;
        add(any, "a hit count and no roots", false);
        return out;
    }
    for (inside_rule rule : {inside_rule::clamp, inside_rule::far_root, inside_rule::miss}) {
        contract c = declared;
        c.inside = rule;
        add(c, std::string(inside_pattern(rule)));
    }
    if (declared.lower_end == end_kind::open) {
        contract c = declared;
        c.lower_end = end_kind::closed;
        add(c, "a hit exactly at the range start counted");
    }
    if (declared.range != range_source::ray) {
        contract c = declared;
        c.range = range_source::ray;
        c.upper_end = end_kind::open;
        add(c, "hits outside the interval it was given (the interval ignored)");
    }
    {
        contract c = declared;
        c.tangent_is_hit = !declared.tangent_is_hit;
        add(c, c.tangent_is_hit ? "a hit at an exact tangent" : "no hit at an exact tangent");
    }
    if (!declared.front_faces_only) {
        contract c = declared;
        c.front_faces_only = true;
        add(c, "only roots where the ray enters the sphere (front faces)");
    }
    // A t beside a hit point: the point may be the answer, its t in other
    // units (a normalised direction's) or of another step. The reverse, a
    // point answer whose own t would fit, cannot be seen: a point answer's t
    // is derived from its point before anything judges it (judge.h).
    if (declared.answer == answer_kind::t && declared.outputs.hit_point) {
        contract c = declared;
        c.answer = answer_kind::point;
        c.outputs.hit_point = false;
        c.outputs.point_error = point_bound::none;
        add(c, "hit points that are right where the t beside them is not (the point is the answer)");
    }
    return out;
}

t_range lint_range(const contract& declared, const contract& candidate, const t_range& judged) {
    t_range range = judged;
    if (candidate.range == range_source::ray) {
        range = range_of(candidate, std::nullopt, std::nullopt);
    } else if (declared.query == query_kind::line_roots) {
        // What a line_roots target's entry points are given (rayverify_plugin.h).
        range.lower = -std::numeric_limits<double>::infinity();
        range.upper = std::numeric_limits<double>::infinity();
    }
    range.lower_end = candidate.lower_end;
    range.upper_end = candidate.upper_end;
    return range;
}

void contract_lint_tally::merge(const contract_lint_tally& other) {
    scored += other.scored;
    wrong += other.wrong;
    if (fixed.size() < other.fixed.size()) {
        fixed.resize(other.fixed.size());
        broken.resize(other.broken.size());
    }
    for (std::size_t k = 0; k < other.fixed.size(); ++k) {
        fixed[k] += other.fixed[k];
        broken[k] += other.broken[k];
    }
}

namespace {

// The output as a target answering under `candidate` would have given it: a
// candidate that takes the hit point for the answer judges the t derived from
// it (parameter_of_point), as answer_of does for a declared point answer.
variant_output as_answered_under(const contract& declared, const contract& candidate, const variant_output& output,
                                 const ray_sphere<double>& input) {
    if (candidate.answer != answer_kind::point || declared.answer == answer_kind::point || !output.hit_point ||
        output.roots.count == 0)
        return output;
    variant_output derived = output;
    derived.roots.t0 = derived.roots.t1 = parameter_of_point(input, *output.hit_point);
    return derived;
}

}  // namespace

void lint_case(const contract& declared, std::span<const lint_candidate> candidates, const case_score& score,
               const variant_output& output, const exact_solution& exact, const t_range& range,
               const ray_sphere<double>& input, contract_lint_tally& into) {
    if (!is_scored(score.verdict)) return;
    if (into.fixed.size() < candidates.size()) {
        into.fixed.resize(candidates.size());
        into.broken.resize(candidates.size());
    }
    const bool agreed = score.verdict == verdict_kind::agree;
    ++into.scored;
    if (!agreed) ++into.wrong;
    for (std::size_t k = 0; k < candidates.size(); ++k) {
        const contract& promises = candidates[k].promises;
        const bool agrees =
            judge_output(promises, as_answered_under(declared, promises, output, input), exact,
                         lint_range(declared, promises, range), input)
                .verdict == verdict_kind::agree;
        if (agrees && !agreed) ++into.fixed[k];
        if (agreed && !agrees) ++into.broken[k];
    }
}

std::optional<contract_hint> strongest_hint(std::span<const lint_candidate> candidates,
                                            const contract_lint_tally& tally) {
    std::optional<contract_hint> best;
    for (std::size_t k = 0; k < candidates.size() && k < tally.fixed.size(); ++k) {
        const std::size_t fixed = tally.fixed[k], broken = tally.broken[k];
        if (fixed < lint_minimum_fixed || 2 * fixed < tally.wrong || fixed <= 4 * broken) continue;
        if (best && best->candidate.judges_t && !candidates[k].judges_t) continue;
        const bool asks_more = best && candidates[k].judges_t && !best->candidate.judges_t;
        if (best && !asks_more && fixed - broken <= best->fixed - best->broken) continue;
        best = contract_hint{candidates[k], tally.scored, tally.wrong, fixed, broken};
    }
    return best;
}

contract_lint_accumulator::contract_lint_accumulator(const std::vector<audit_target>& targets) {
    for (const audit_target& t : targets) {
        const bool builtin = !t.recorded && find_builtin_variant(t.subject.name) != nullptr;
        declared.push_back(t.subject.promises);
        precisions.push_back(t.prec);
        candidates.push_back(builtin ? std::vector<lint_candidate>{} : lint_candidates(t.subject.promises));
        tallies.emplace_back();
    }
}

void contract_lint_accumulator::add(const audited_case& c) {
    for (std::size_t t = 0; t < candidates.size() && t < c.outcomes.size(); ++t) {
        if (candidates[t].empty()) continue;
        const target_outcome& outcome = c.outcomes[t];
        if (!is_scored(outcome.score.verdict)) continue;
        const ray_sphere<double> input = target_input(precisions[t], *c.source);
        lint_case(declared[t], candidates[t], outcome.score, outcome.output, c.exact_for(precisions[t]), outcome.range,
                  input, tallies[t]);
    }
}

void contract_lint_accumulator::merge(const contract_lint_accumulator& other) {
    for (std::size_t t = 0; t < tallies.size() && t < other.tallies.size(); ++t) tallies[t].merge(other.tallies[t]);
}

std::vector<std::optional<contract_hint>> contract_lint_accumulator::hints() const {
    std::vector<std::optional<contract_hint>> out;
    for (std::size_t t = 0; t < tallies.size(); ++t) out.push_back(strongest_hint(candidates[t], tallies[t]));
    return out;
}

}  // namespace rayverify
