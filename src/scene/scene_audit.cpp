#include "scene/scene_audit.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "compare/verdict.h"
#include "core/case_in_progress.h"

namespace rayverify {
namespace {

// Is the exact root i inside the open interval (tmin, tmax)?
bool root_inside(const exact_solution& e, root_index i, double tmin, double tmax) {
    if (e.compare_root(i, tmin) >= 0) return false;  // tmin ≥ t*
    return std::isinf(tmax) || e.compare_root(i, tmax) > 0;
}

// The variant's answer to query q on one (ray, sphere) pair, as a renderer
// takes it (compare/query.h): its roots filtered into the ray's interval.
query_answer answer_in(const audit_target& target, const corpus_case& c, ray_query q) {
    const case_in_progress announced(c);  // named by a plugin that crashes or hangs on it
    const ray_interval<double> interval = interval_of(c, target.prec);
    if (target.prec == precision::binary32)
        return answer_query<float>(target.subject, rounded_to<float>(c.geometry),
                                   {static_cast<float>(interval.tmin), static_cast<float>(interval.tmax)}, q);
    return answer_query<double>(target.subject, c.geometry, interval, q);
}

ray_verdict from_outcome(query_outcome o) {
    switch (o) {
        case query_outcome::correct: return ray_verdict::agree;
        case query_outcome::false_miss: return ray_verdict::false_miss;
        case query_outcome::false_hit: return ray_verdict::false_hit;
        case query_outcome::wrong_root: return ray_verdict::wrong_root;
        default: return ray_verdict::other;
    }
}

struct pair_exact {
    corpus_case c;
    exact_solution e;
};

// The exact root the variant's value t stands for: the nearer one.
root_index matching_root(const exact_solution& e, double t) {
    if (e.cls != line_class::two_hit) return root_index::near_root;
    return std::fabs(t - e.near_root.rounded) <= std::fabs(t - e.far_root.rounded) ? root_index::near_root
                                                                                     : root_index::far_root;
}

// Exact nearest-rank order statistics (a scene's samples are small enough to sort).
error_statistics order_statistics(std::vector<std::pair<double, std::size_t>> sample,
                                  const std::vector<std::string>& ids) {
    error_statistics st;
    st.count = sample.size();
    if (sample.empty()) return st;
    std::sort(sample.begin(), sample.end());
    const auto rank = [&](double q) {
        const std::size_t k = static_cast<std::size_t>(std::ceil(q * static_cast<double>(sample.size())));
        return sample[std::max<std::size_t>(k, 1) - 1].first;
    };
    st.max = sample.back().first;
    st.max_case = ids[sample.back().second];
    st.p99 = rank(0.99);
    st.median = rank(0.5);
    return st;
}

struct sample_set {
    std::vector<std::pair<double, std::size_t>> nearest, far, hit_point;
};

}  // namespace

std::string_view ray_verdict_name(ray_verdict v) {
    switch (v) {
        case ray_verdict::agree: return "agree";
        case ray_verdict::false_miss: return "false_miss";
        case ray_verdict::false_hit: return "false_hit";
        case ray_verdict::wrong_sphere: return "wrong_sphere";
        case ray_verdict::wrong_side: return "wrong_side";
        case ray_verdict::wrong_root: return "wrong_root";
        case ray_verdict::other: return "other";
    }
    return "?";
}

std::string_view ray_verdict_meaning(ray_verdict v) {
    switch (v) {
        case ray_verdict::agree: return "same answer as the exact oracle";
        case ray_verdict::false_miss: return "the exact ray hits something in (tmin, tmax); the variant sees nothing";
        case ray_verdict::false_hit: return "the exact ray hits nothing in (tmin, tmax); the variant reports a hit";
        case ray_verdict::wrong_sphere: return "both hit, but the variant's nearest is another sphere";
        case ray_verdict::wrong_side:
            return "a root falls on the other side of tmin or tmax: a self-hit, or a hit lost behind the bound";
        case ray_verdict::wrong_root: return "the variant's nearest hit is the other root of the right sphere";
        case ray_verdict::other: return "both roots: a tangent, non-finite or malformed answer on some pair";
    }
    return "?";
}

std::size_t ray_kind_figures::disagreements() const { return rays - verdicts[0]; }

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
    if (!t.subject.runs_in(s.prec))
        return fmt::format("does not run in {}, the scene's precision", precision_name(s.prec));
    const std::pair<ray_kind, const ray_kind_settings*> kinds[] = {
        {ray_kind::primary, &s.primary}, {ray_kind::shadow, &s.shadow}, {ray_kind::secondary, &s.secondary}};
    for (const auto& [kind, settings] : kinds) {
        if (!settings->enabled) continue;
        if (auto why = applicable(t.subject, settings->query, s.normalise_directions))
            return fmt::format("{} rays ({}): {}", ray_kind_name(kind), ray_query_name(settings->query), *why);
    }
    return std::nullopt;
}

scene_audit_result audit_scene(const scene& s, std::span<const scene_ray> rays,
                               const std::vector<audit_target>& targets,
                               const std::function<void(const judged_ray&)>& on_ray) {
    scene_audit_result result;
    std::vector<std::optional<std::string>> skip(targets.size());
    for (std::size_t i = 0; i < targets.size(); ++i) {
        scene_target_figures f;
        f.target = targets[i];
        f.not_applicable = skip[i] = not_applicable_reason(s, targets[i]);
        result.targets.push_back(f);
    }
    std::vector<std::array<sample_set, 3>> samples(targets.size());
    std::vector<std::string> ids;
    ids.reserve(rays.size());

    for (const scene_ray& r : rays) {
        const std::size_t ray_index = ids.size();
        ids.push_back(r.id());
        if (r.kind == ray_kind::primary) ++result.pixels;
        const std::size_t kind = static_cast<std::size_t>(r.kind);

        // Exact: every sphere, then the nearest root in the interval.
        std::vector<pair_exact> pairs;
        judged_ray judged;
        judged.ray = &r;
        exact_ray_answer& ex = judged.exact;
        for (int k : r.spheres) {
            pair_exact p{case_for(s, r, k), {}};
            p.e = solve_exact(p.c.geometry, s.prec);
            ++result.pairs;
            if (p.e.valid() && p.e.cls != line_class::miss) {
                for (root_index i : {root_index::near_root, root_index::far_root}) {
                    const exact_root& root = p.e.root(i);
                    if (r.tmin > 0 && root.sign > 0 && p.e.compare_root(i, r.tmin) >= 0) ex.lost_to_tmin = true;
                    if (!root_inside(p.e, i, r.tmin, r.tmax)) continue;
                    if (!ex.hit || root.rounded < ex.t) {
                        ex.hit = true;
                        ex.sphere = k;
                        ex.root = i;
                        ex.t = root.rounded;
                    }
                    break;
                }
            }
            pairs.push_back(std::move(p));
        }
        if (ex.hit) {
            const exact_solution& e = pairs[static_cast<std::size_t>(
                std::find(r.spheres.begin(), r.spheres.end(), ex.sphere) - r.spheres.begin())].e;
            const vec3<double> point{e.rounded_hit_coordinate(ex.root, 0), e.rounded_hit_coordinate(ex.root, 1),
                                     e.rounded_hit_coordinate(ex.root, 2)};
            const vec3<double> n = point - s.spheres[static_cast<std::size_t>(ex.sphere)].centre;
            const double len = std::sqrt(length_squared(n));
            if (len > 0) ex.normal = {n.x / len, n.y / len, n.z / len};
        }
        exact_kind_figures& exact_fig = result.exact[kind];
        ++exact_fig.rays;
        exact_fig.hits += ex.hit ? 1 : 0;
        exact_fig.lost_to_tmin += ex.lost_to_tmin ? 1 : 0;

        // Each applicable target.
        judged.answers.resize(targets.size());
        for (std::size_t ti = 0; ti < targets.size(); ++ti) {
            if (skip[ti]) continue;
            const audit_target& target = targets[ti];
            variant_ray_answer& ans = judged.answers[ti];
            ray_kind_figures& fig = result.targets[ti].by_kind[kind];
            sample_set& sample = samples[ti][kind];
            ++fig.rays;

            if (r.query == ray_query::both_roots) {
                // Judge every pair on the line's roots; the ray takes the first disagreement.
                for (std::size_t pi = 0; pi < pairs.size(); ++pi) {
                    const pair_exact& p = pairs[pi];
                    if (!p.e.valid()) continue;
                    const query_verdict v = judge_query(target.subject, target.prec, p.c, r.query, p.e);
                    const ray_verdict rv = from_outcome(v.outcome);
                    if (rv != ray_verdict::agree && ans.verdict == ray_verdict::agree) {
                        ans.verdict = rv;
                        ans.detail = std::string(query_outcome_name(v.outcome)) + " on " + p.c.id + ": " + v.detail;
                    }
                    if (v.outcome == query_outcome::correct) {
                        if (v.nearest_ulp) sample.nearest.emplace_back(*v.nearest_ulp, ray_index);
                        if (v.far_ulp) sample.far.emplace_back(*v.far_ulp, ray_index);
                    }
                }
                // What a picture shows: the nearest hit in the interval, as a renderer would take it.
                for (std::size_t pi = 0; pi < pairs.size(); ++pi) {
                    if (!pairs[pi].e.valid()) continue;
                    const query_answer a = answer_in(target, pairs[pi].c, ray_query::nearest_hit);
                    if (a.nearest && (!ans.hit || *a.nearest < ans.t)) {
                        ans.hit = true;
                        ans.t = *a.nearest;
                        ans.sphere = r.spheres[pi];
                    }
                }
                ++fig.verdicts[static_cast<std::size_t>(ans.verdict)];
                continue;
            }

            // any_hit / nearest_hit / hit_point_normal: compose over the spheres.
            std::size_t nearest_pair = 0;
            query_answer nearest_answer;
            for (std::size_t pi = 0; pi < pairs.size(); ++pi) {
                const pair_exact& p = pairs[pi];
                if (!p.e.valid()) continue;
                query_answer a = answer_in(target, p.c, r.query);
                if (!a.hit) continue;
                if (r.query == ray_query::any_hit) {  // any hit settles the answer
                    ans.hit = true;
                    ans.sphere = r.spheres[pi];
                    break;
                }
                if (a.nearest && (!ans.hit || *a.nearest < ans.t)) {
                    ans.hit = true;
                    ans.t = *a.nearest;
                    ans.sphere = r.spheres[pi];
                    nearest_pair = pi;
                    nearest_answer = std::move(a);
                }
            }

            if (ex.hit != ans.hit) {
                ans.verdict = ex.hit ? ray_verdict::false_miss : ray_verdict::false_hit;
            } else if (!ex.hit || r.query == ray_query::any_hit) {
                ans.verdict = ray_verdict::agree;
            } else if (ans.sphere != ex.sphere) {
                ans.verdict = ray_verdict::wrong_sphere;
            } else {
                const pair_exact& p = pairs[nearest_pair];
                const root_index k = matching_root(p.e, ans.t);
                if (k == ex.root) {
                    ans.verdict = ray_verdict::agree;
                    ans.nearest_ulp = p.e.root_ulp_error(k, ans.t);
                    sample.nearest.emplace_back(*ans.nearest_ulp, ray_index);
                    if (r.query == ray_query::hit_point_normal && nearest_answer.hit_point) {
                        const vec3<double> h = *nearest_answer.hit_point;
                        double worst = 0;
                        for (int axis = 0; axis < 3; ++axis)
                            worst = std::max(worst, p.e.hit_point_ulp_error(k, axis, h[axis]));
                        ans.hit_point_ulp = worst;
                        sample.hit_point.emplace_back(worst, ray_index);
                    }
                } else {
                    // The variant's value stands for the other exact root: one
                    // that lies exactly outside the interval (a root crossed a
                    // bound: wrong side), or the other root inside it.
                    ans.verdict = root_inside(p.e, k, r.tmin, r.tmax) ? ray_verdict::wrong_root
                                                                      : ray_verdict::wrong_side;
                }
            }
            ++fig.verdicts[static_cast<std::size_t>(ans.verdict)];
        }
        if (on_ray) on_ray(judged);
    }

    for (std::size_t ti = 0; ti < targets.size(); ++ti)
        for (std::size_t kind = 0; kind < 3; ++kind) {
            ray_kind_figures& fig = result.targets[ti].by_kind[kind];
            fig.nearest_ulp = order_statistics(samples[ti][kind].nearest, ids);
            fig.far_ulp = order_statistics(samples[ti][kind].far, ids);
            fig.hit_point_ulp = order_statistics(samples[ti][kind].hit_point, ids);
        }
    return result;
}

}  // namespace rayverify
