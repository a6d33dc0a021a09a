#include "bench/recommend.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "bench/kernels.h"
#include "compare/judge.h"
#include "core/input_error.h"
#include "scene/scene_audit.h"

namespace rayverify::bench {

std::string recommend_budget::describe() const {
    return fmt::format("at most {} wrong ray{}, root error ≤ {} ulp", max_wrong, max_wrong == 1 ? "" : "s", max_ulp);
}

recommend_budget parse_budget(const std::string& text) {
    recommend_budget budget;
    std::vector<std::string> given;  // keys seen: one given twice would keep the last silently
    std::size_t start = 0;
    while (start <= text.size()) {
        const std::size_t comma = std::min(text.find(',', start), text.size());
        const std::string part = text.substr(start, comma - start);
        start = comma + 1;
        const std::size_t eq = part.find('=');
        const std::string key = part.substr(0, eq), value = eq == std::string::npos ? "" : part.substr(eq + 1);
        const auto bad = [&](const std::string& why) {
            throw input_error("", 0, "--budget", fmt::format("'{}': {} (expected max-ulp=X,max-wrong=N)", part, why));
        };
        if (eq == std::string::npos || value.empty()) bad("not KEY=VALUE");
        if (std::find(given.begin(), given.end(), key) != given.end()) bad("the key is given twice");
        given.push_back(key);
        std::size_t used = 0;
        try {
            if (key == "max-ulp") {
                budget.max_ulp = std::stod(value, &used);
                if (!(budget.max_ulp >= 0) || std::isinf(budget.max_ulp)) bad("must be a finite number ≥ 0");
            } else if (key == "max-wrong") {
                if (value[0] == '-') bad("must be a count ≥ 0");
                budget.max_wrong = std::stoull(value, &used);
            } else {
                bad("unknown key");
            }
        } catch (const std::logic_error&) {  // std::invalid_argument, std::out_of_range
            bad("not a number");
        }
        if (used != value.size()) bad("not a number");
    }
    return budget;
}

bool recommendation::all_met() const {
    return std::all_of(kinds.begin(), kinds.end(), [](const kind_recommendation& k) { return k.winner.has_value(); });
}

namespace {

// One ray's (ray, sphere) pairs, rounded to T once, flat.
template <class T>
struct prepared_ray {
    std::uint32_t first = 0, count = 0;
    T tmin{}, tmax{};
    ray_query query = ray_query::nearest_hit;
};

template <class T>
struct prepared_rays {
    std::vector<prepared_ray<T>> rays;
    std::vector<ray_sphere<T>> pairs;
};

template <class T>
prepared_rays<T> prepare(const scene& s, const std::vector<const scene_ray*>& rays) {
    prepared_rays<T> p;
    for (const scene_ray* r : rays) {
        prepared_ray<T> pr;
        pr.first = static_cast<std::uint32_t>(p.pairs.size());
        pr.count = static_cast<std::uint32_t>(r->spheres.size());
        pr.tmin = static_cast<T>(r->tmin);
        pr.tmax = static_cast<T>(r->tmax);
        pr.query = r->query;
        for (int k : r->spheres) p.pairs.push_back(rounded_to<T>(case_for(s, *r, k).geometry));
        p.rays.push_back(pr);
    }
    return p;
}

// The first root of the answer in (tmin, upper), as a renderer takes it
// (judge.h's renderer_view, without the bookkeeping a judge needs: this is
// the timed loop). An interval contract was asked for (tmin, upper) itself.
template <class T>
bool first_root_in(const contract& promises, const root_pair<T>& a, T tmin, T upper, T& t) {
    if (a.count <= 0) return false;
    const auto inside = [&](T x) { return x > tmin && x < upper; };
    switch (promises.query) {
        case query_kind::any_hit: return true;
        case query_kind::nearest_hit:
            t = a.t0;
            return takes_interval(promises) || inside(t);
        case query_kind::line_roots:
            if (inside(a.t0)) {
                t = a.t0;
                return true;
            }
            t = a.t1;
            return inside(t);
    }
    return false;
}

// Cast every ray once: per sphere, the intersector asked for (tmin, nearest
// so far); an any-hit ray stops at its first hit; a hit_point_normal ray
// also forms its hit point and normal. Returns a sum over every answer.
template <class T, class Kernel>
[[gnu::flatten]] double cast_all(const prepared_rays<T>& p, Kernel kernel, const contract& promises) {
    double sum = 0;
    for (const prepared_ray<T>& r : p.rays) {
        const query_requirements needs = query_needs(r.query);
        T upper = r.tmax;
        bool hit = false;
        std::uint32_t nearest = 0;
        for (std::uint32_t i = r.first; i < r.first + r.count; ++i) {
            const root_pair<T> a = kernel(p.pairs[i], r.tmin, upper);
            if (needs.far_root) {
                if (a.count > 0) sum += static_cast<double>(a.t0) + static_cast<double>(a.t1);
                continue;
            }
            T t{};
            if (!first_root_in(promises, a, r.tmin, upper, t)) continue;
            hit = true;
            if (needs.first_hit_answers) break;
            upper = t;
            nearest = i;
        }
        if (!hit) continue;
        sum += 1;
        if (needs.hit_point) {
            const ray_sphere<T>& s = p.pairs[nearest];
            const vec3<T> point = s.origin + upper * s.direction;
            const vec3<T> normal = (T(1) / s.radius) * (point - s.centre);
            sum += static_cast<double>(normal.x + normal.y + normal.z);
        } else if (needs.nearest_root) {
            sum += static_cast<double>(upper);
        }
    }
    return sum;
}

// ns per ray of one variant on prepared rays: the built-in kernel inlined
// when there is one of that name, else the variant's function.
template <class T>
timing_row time_variant(const variant& v, const prepared_rays<T>& p, const timing_options& options) {
    timing_row row;
    row.variant = v.name;
    row.precision = std::is_same_v<T, float> ? "float" : "double";
    row.family = "scene";
    row.cases = p.rays.size();
    const contract promises = v.promises;
    std::optional<timing_row> timed;
    const variant* builtin = find_builtin_variant(v.name);
    if (builtin && builtin->citation == v.citation)
        for_each_kernel([&](std::string_view name, auto kernel) {
            if (name == v.name)
                timed = time_pass(row, [&p, kernel, promises] { return cast_all(p, kernel, promises); }, options);
        });
    if (!timed) {
        const auto through = [&v](const ray_sphere<T>& s, T tmin, T tmax) {
            return run_in(v, s, ray_interval<T>{tmin, tmax});
        };
        timed = time_pass(row, [&p, through, promises] { return cast_all(p, through, promises); }, options);
        timed->variant += " (called through a function pointer)";
    }
    return *timed;
}

recommend_candidate judged(const scene_target_figures& f, ray_kind kind, ray_query query,
                           const recommend_budget& budget) {
    recommend_candidate c;
    c.variant = f.target.subject.name;
    const ray_kind_figures& k = f.by_kind[static_cast<std::size_t>(kind)];
    c.rays = k.rays;
    c.wrong = k.disagreements();
    c.false_miss = k.verdicts[static_cast<std::size_t>(verdict_kind::false_miss)];
    c.false_hit = k.verdicts[static_cast<std::size_t>(verdict_kind::false_hit)];
    if (query_needs(query).nearest_root && k.nearest_ulp.count > 0) {
        c.max_ulp = k.nearest_ulp.max;
        c.max_ulp_ray = k.nearest_ulp.max_id;
    }
    if (query_needs(query).far_root && k.far_ulp.count > 0 && k.far_ulp.max > c.max_ulp.value_or(-1)) {
        c.max_ulp = k.far_ulp.max;
        c.max_ulp_ray = k.far_ulp.max_id;
    }
    const bool accurate = !c.max_ulp || *c.max_ulp <= budget.max_ulp;
    c.meets_budget = c.wrong <= budget.max_wrong && accurate;
    if (c.meets_budget)
        c.verdict = "meets the budget";
    else if (c.wrong > budget.max_wrong)
        c.verdict = fmt::format("{} wrong ray{} (false miss {}, false hit {}, other {}) > {}", c.wrong,
                                c.wrong == 1 ? "" : "s", c.false_miss, c.false_hit, c.wrong - c.false_miss - c.false_hit,
                                budget.max_wrong);
    else
        c.verdict = fmt::format("root error {:.3g} ulp > {} (ray {})", *c.max_ulp, budget.max_ulp, c.max_ulp_ray);
    return c;
}

template <class T>
kind_recommendation decide_kind(const scene& s, ray_kind kind, const ray_kind_settings& settings,
                                std::span<const scene_ray> rays, std::span<const variant> variants,
                                const recommend_budget& budget, const timing_options& timing) {
    kind_recommendation out;
    out.kind = kind;
    out.query = settings.query;
    std::vector<const scene_ray*> mine;
    for (const scene_ray& r : rays)
        if (r.kind == kind) mine.push_back(&r);
    std::vector<scene_ray> owned;
    owned.reserve(mine.size());
    for (const scene_ray* r : mine) owned.push_back(*r);
    out.rays = owned.size();

    // The scene as this kind alone sees it, so that applicability is per kind.
    scene alone = s;
    alone.primary.enabled = kind == ray_kind::primary;
    alone.shadow.enabled = kind == ray_kind::shadow;
    alone.secondary.enabled = kind == ray_kind::secondary;

    std::vector<audit_target> targets;
    std::vector<recommend_candidate> rejected;
    for (const variant& v : variants) {
        if (!v.runs_in(s.prec)) continue;
        if (auto why = applicable(v, settings.query, s.normalise_directions)) {
            recommend_candidate c;
            c.variant = v.name;
            c.not_applicable = *why;
            rejected.push_back(std::move(c));
            continue;
        }
        targets.push_back({v, s.prec});
    }
    const scene_audit_result audit = audit_scene(alone, owned, targets);
    const prepared_rays<T> prepared = prepare<T>(s, mine);
    for (std::size_t i = 0; i < targets.size(); ++i) {
        recommend_candidate c = judged(audit.targets[i], kind, settings.query, budget);
        c.exact_decisions = targets[i].subject.exact_decisions;
        const timing_row row = time_variant(targets[i].subject, prepared, timing);
        c.variant = row.variant;
        c.ns_per_ray = row.median;
        c.ns_min = row.min;
        c.ns_max = row.max;
        out.candidates.push_back(std::move(c));
    }
    std::stable_sort(out.candidates.begin(), out.candidates.end(),
                     [](const recommend_candidate& a, const recommend_candidate& b) { return a.ns_per_ray < b.ns_per_ray; });
    // No wrong ray allowed: the cheapest variant that decides exactly by construction, if one meets the budget.
    if (budget.max_wrong == 0)
        for (std::size_t i = 0; i < out.candidates.size() && !out.winner; ++i)
            if (out.candidates[i].meets_budget && out.candidates[i].exact_decisions) out.winner = i;
    for (std::size_t i = 0; i < out.candidates.size(); ++i) {
        if (!out.candidates[i].meets_budget || out.winner == i) continue;
        if (!out.winner)
            out.winner = i;
        else if (!out.runner_up)
            out.runner_up = i;
    }
    for (recommend_candidate& c : rejected) out.candidates.push_back(std::move(c));
    return out;
}

}  // namespace

recommendation recommend(const scene& s, std::span<const scene_ray> rays, std::span<const variant> variants,
                         const recommend_budget& budget, const timing_options& timing) {
    recommendation out;
    out.scene_name = s.name;
    out.prec = s.prec;
    out.normalised = s.normalise_directions;
    out.budget = budget;
    for (const ray_kind kind : every_ray_kind) {
        const ray_kind_settings& settings = s.settings(kind);
        if (!settings.enabled) continue;
        out.kinds.push_back(with_precision(s.prec, [&]<class T>(std::type_identity<T>) {
            return decide_kind<T>(s, kind, settings, rays, variants, budget, timing);
        }));
    }
    return out;
}

}  // namespace rayverify::bench
