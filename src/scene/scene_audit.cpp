#include "scene/scene_audit.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

namespace rayverify {

std::size_t ray_kind_figures::disagreements() const {
    std::size_t n = 0;
    for (int k = 0; k < verdict_kind_count; ++k)
        if (is_disagreement(static_cast<verdict_kind>(k))) n += verdicts[static_cast<std::size_t>(k)];
    return n;
}

std::size_t scene_target_figures::disagreements() const {
    std::size_t n = 0;
    for (const ray_kind_figures& k : by_kind) n += k.disagreements();
    return n;
}

std::vector<audit_target> scene_targets(const scene& s, std::span<const variant> variants) {
    std::vector<audit_target> targets;
    for (const variant& v : variants)
        if (v.runs_in(s.prec)) targets.push_back({v, s.prec});
    return targets;
}

std::optional<std::string> not_applicable_reason(const scene& s, const audit_target& t) {
    if (t.recorded ? t.prec != s.prec : !t.subject.runs_in(s.prec))
        return fmt::format("does not {} in {}, the scene's precision", t.recorded ? "answer" : "run",
                           precision_name(s.prec));
    for (const ray_kind kind : every_ray_kind) {
        const ray_kind_settings& settings = s.settings(kind);
        if (!settings.enabled) continue;
        if (auto why = applicable(t.subject, settings.query, s.normalise_directions))
            return fmt::format("{} rays ({}): {}", ray_kind_name(kind), ray_query_name(settings.query), *why);
    }
    return std::nullopt;
}

namespace {

// The ray's verdict from one pair's judgement, naming the sphere.
void take_pair(variant_ray_answer& answer, const renderer_outcome& pair, const sphere_solution& on) {
    answer.verdict = pair.score.verdict;
    answer.cause = pair.score.cause;
    answer.detail = fmt::format("on {}: {}", on.pair.id, pair.score.detail);
}

// The variant's hit on one pair as the renderer takes it: a finite root in the interval.
std::optional<double> renderer_hit(const renderer_outcome& pair) {
    const root_pair<double>& r = pair.view.roots;
    if (r.count != 1 || !std::isfinite(r.t0)) return std::nullopt;
    return r.t0;
}

// both_roots: every pair judged on the line's roots; the ray takes the first
// disagreement. What a picture shows is the nearest root in the interval.
void judge_both_roots(const std::vector<renderer_outcome>& pairs, std::span<const sphere_solution> solved,
                      variant_ray_answer& answer, ray_kind_figures& figures, std::size_t ray_index,
                      const std::string& ray_id) {
    for (std::size_t i = 0; i < pairs.size(); ++i) {
        const renderer_outcome& p = pairs[i];
        if (!solved[i].exact.valid()) continue;
        if (is_disagreement(p.score.verdict) && answer.verdict == verdict_kind::agree) take_pair(answer, p, solved[i]);
        if (p.score.verdict == verdict_kind::agree) {
            if (p.score.near_ulp) figures.nearest_ulp.add(*p.score.near_ulp, ray_index, ray_id);
            if (p.score.far_ulp) figures.far_ulp.add(*p.score.far_ulp, ray_index, ray_id);
        }
        if (p.view.hit_root) {
            const double t = *p.view.hit_root == 0 ? p.view.roots.t0 : p.view.roots.t1;
            if (!answer.hit || t < answer.t) {
                answer.hit = true;
                answer.t = t;
                answer.sphere = solved[i].sphere;
            }
        }
    }
}

// any_hit, nearest_hit, hit_point_normal: the pairs composed as a renderer
// composes them (any hit settles a shadow ray; otherwise the smallest t,
// the first sphere on a tie), judged against the exact nearest hit.
void judge_nearest(ray_query q, const std::vector<renderer_outcome>& pairs, std::span<const sphere_solution> solved,
                   const std::optional<exact_nearest>& exact, variant_ray_answer& answer, ray_kind_figures& figures,
                   std::size_t ray_index, const std::string& ray_id) {
    // A NaN never agrees, even where the renderer's picture would come out right.
    for (std::size_t i = 0; i < pairs.size(); ++i)
        if (pairs[i].score.verdict == verdict_kind::non_finite) {
            take_pair(answer, pairs[i], solved[i]);
            return;
        }
    std::optional<std::size_t> chosen;
    for (std::size_t i = 0; i < pairs.size(); ++i) {
        const std::optional<double> t = renderer_hit(pairs[i]);
        if (!t) continue;
        if (!chosen || *t < answer.t) {
            chosen = i;
            answer.hit = true;
            answer.t = *t;
            answer.sphere = solved[i].sphere;
        }
        if (query_needs(q).first_hit_answers) break;
    }
    // The pair that decides a wrong answer: the one the variant hit, else the exact nearest.
    if (!exact && !chosen) return;
    if (!chosen) {  // false miss (or a NaN, a malformed count) on the exact nearest sphere
        take_pair(answer, pairs[exact->index], solved[exact->index]);
        return;
    }
    const renderer_outcome& mine = pairs[*chosen];
    if (!exact) {  // false hit on the sphere the variant hit
        take_pair(answer, mine, solved[*chosen]);
        return;
    }
    if (query_needs(q).first_hit_answers) return;  // both hit: that is all an any-hit ray asks
    // A sphere whose expected root ties the nearest exactly, or rounds to the
    // same value in the scene's precision (no renderer can order them), counts
    // as the nearest sphere.
    const exact_solution& nearest_exact = solved[exact->index].exact;
    const expected_hit tied = expect_hit(renderer_contract(q), solved[*chosen].exact, mine.range);
    const bool same_hit = *chosen == exact->index ||
                          (tied.hit() && (tied.value == nearest_exact.root(exact->root).rounded ||
                                          compare_roots(solved[*chosen].exact, tied.root, nearest_exact, exact->root) == comparison::equal));
    if (same_hit || mine.score.verdict == verdict_kind::wrong_side) {
        // The right sphere (or an exact tie), or a self-hit on the sphere it
        // chose: that pair's verdict is the ray's.
        take_pair(answer, mine, solved[*chosen]);
        if (answer.verdict != verdict_kind::agree) return;
        if (mine.score.near_ulp) figures.nearest_ulp.add(*mine.score.near_ulp, ray_index, ray_id);
        answer.nearest_ulp = mine.score.near_ulp;
        if (query_needs(q).hit_point && mine.score.hit_point_worst_ulp) {
            answer.hit_point_ulp = mine.score.hit_point_worst_ulp;
            figures.hit_point_ulp.add(*answer.hit_point_ulp, ray_index, ray_id);
        }
        return;
    }
    // Another sphere than the exact nearest: the cause is whatever went wrong
    // on the sphere it chose, or on the one it passed over.
    const renderer_outcome& passed = pairs[exact->index];
    answer.verdict = verdict_kind::wrong_sphere;
    answer.cause = is_disagreement(mine.score.verdict)     ? mine.score.cause
                   : is_disagreement(passed.score.verdict) ? passed.score.cause
                                                           : std::optional(disagreement_cause::conditioning_limited);
    answer.detail = fmt::format("nearest is {} (t* ≈ {}), the variant's {} at t = {}{}", solved[exact->index].pair.id,
                                solved[exact->index].exact.root(exact->root).rounded, solved[*chosen].pair.id, answer.t,
                                is_disagreement(passed.score.verdict) ? "; there: " + passed.score.detail
                                : is_disagreement(mine.score.verdict) ? "; " + mine.score.detail
                                                                      : "");
}

}  // namespace

scene_auditor::scene_auditor(const scene& s, const std::vector<audit_target>& targets, oracle_route route)
    : scene_(s), targets_(targets), skip_(targets.size()), route_(route) {
    for (std::size_t i = 0; i < targets.size(); ++i) {
        scene_target_figures f;
        f.target = targets[i];
        f.not_applicable = skip_[i] = not_applicable_reason(s, targets[i]);
        result_.targets.push_back(f);
    }
}

void scene_auditor::judge(const scene_ray& r, const std::function<void(const judged_ray&)>& on_ray) {
    const scene& s = scene_;
    const std::string ray_id = r.id();
    const std::size_t ray_index = ray_index_++;
    if (r.kind == ray_kind::primary) ++result_.pixels;
    const std::size_t kind = static_cast<std::size_t>(r.kind);

    // Exact: every sphere, then the nearest root in the interval.
    const std::vector<sphere_solution> solved = solve_spheres(s, r, route_);
    result_.pairs += solved.size();
    const std::optional<exact_nearest> nearest = exact_nearest_hit(r, solved);
    judged_ray judged;
    judged.ray = &r;
    exact_ray_answer& ex = judged.exact;
    for (const sphere_solution& one : solved) {
        const exact_solution& e = one.exact;
        if (!e.valid() || e.cls == line_class::miss || !(r.tmin > 0)) continue;
        for (root_index i : {root_index::near_root, root_index::far_root})
            if (e.root(i).sign > 0 && e.compare_to_root(r.tmin, i) != comparison::smaller) ex.lost_to_tmin = true;
    }
    if (nearest) {
        const sphere_solution& hit = solved[nearest->index];
        ex.hit = true;
        ex.sphere = hit.sphere;
        ex.root = nearest->root;
        ex.t = hit.exact.root(nearest->root).rounded;
        const vec3<double> point{hit.exact.rounded_hit_coordinate(ex.root, 0),
                                 hit.exact.rounded_hit_coordinate(ex.root, 1),
                                 hit.exact.rounded_hit_coordinate(ex.root, 2)};
        const vec3<double> n = point - s.spheres[static_cast<std::size_t>(ex.sphere)].centre;
        const double len = std::sqrt(length_squared(n));
        if (len > 0) ex.normal = {n.x / len, n.y / len, n.z / len};
    }
    exact_kind_figures& exact_fig = result_.exact[kind];
    ++exact_fig.rays;
    exact_fig.hits += ex.hit ? 1 : 0;
    exact_fig.lost_to_tmin += ex.lost_to_tmin ? 1 : 0;

    // Each applicable target: every pair judged, then composed.
    judged.answers.resize(targets_.size());
    std::vector<renderer_outcome> pairs(solved.size());
    for (std::size_t ti = 0; ti < targets_.size(); ++ti) {
        if (skip_[ti]) continue;
        variant_ray_answer& answer = judged.answers[ti];
        ray_kind_figures& figures = result_.targets[ti].by_kind[kind];
        ++figures.rays;
        for (std::size_t i = 0; i < solved.size(); ++i)
            pairs[i] = judge_for_renderer(targets_[ti], solved[i].pair, r.query, solved[i].exact);
        if (query_needs(r.query).far_root)
            judge_both_roots(pairs, solved, answer, figures, ray_index, ray_id);
        else
            judge_nearest(r.query, pairs, solved, nearest, answer, figures, ray_index, ray_id);

        ++figures.verdicts[static_cast<std::size_t>(answer.verdict)];
        if (answer.cause) ++figures.causes[static_cast<std::size_t>(*answer.cause)];
    }
    if (on_ray) on_ray(judged);
}

scene_audit_result audit_scene(const scene& s, const std::vector<audit_target>& targets,
                               const std::function<void(const judged_ray&)>& on_ray, oracle_route route) {
    scene_auditor auditor(s, targets, route);
    for_each_ray(s, [&](const scene_ray& r) { auditor.judge(r, on_ray); });
    return auditor.result();
}

scene_audit_result audit_scene(const scene& s, std::span<const scene_ray> rays,
                               const std::vector<audit_target>& targets,
                               const std::function<void(const judged_ray&)>& on_ray) {
    scene_auditor auditor(s, targets);
    for (const scene_ray& r : rays) auditor.judge(r, on_ray);
    return auditor.result();
}

}  // namespace rayverify
