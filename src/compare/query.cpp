#include "compare/query.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace rayverify {

const char* ray_query_name(ray_query q) {
    switch (q) {
        case ray_query::any_hit: return "any_hit";
        case ray_query::nearest_hit: return "nearest_hit";
        case ray_query::both_roots: return "both_roots";
        case ray_query::hit_point_normal: return "hit_point_normal";
    }
    return "?";
}

std::string_view query_outcome_name(query_outcome o) {
    switch (o) {
        case query_outcome::correct: return "correct";
        case query_outcome::false_hit: return "false_hit";
        case query_outcome::false_miss: return "false_miss";
        case query_outcome::wrong_root: return "wrong_root";
        case query_outcome::non_finite: return "non_finite";
        case query_outcome::malformed_output: return "malformed_output";
        case query_outcome::contract_violation: return "contract_violation";
        case query_outcome::invalid: return "invalid";
    }
    return "?";
}

bool is_misclassification(query_outcome o) {
    return o == query_outcome::false_hit || o == query_outcome::false_miss;
}

bool is_query_failure(query_outcome o) {
    return o != query_outcome::correct && o != query_outcome::contract_violation && o != query_outcome::invalid;
}

std::optional<std::string> applicable(const variant& v, ray_query q, bool directions_normalised) {
    const contract& c = v.promises;
    if (c.assumes_unit_direction && !directions_normalised)
        return "assumes a unit direction; the scene's directions are not normalised";
    switch (c.query) {
        case query_kind::line_roots: return std::nullopt;
        case query_kind::any_hit_in_interval:
            if (q == ray_query::any_hit) return std::nullopt;
            return fmt::format("answers only any_hit (no root), asked for {}", ray_query_name(q));
        case query_kind::nearest_on_ray:
        case query_kind::nearest_in_interval:
            if (q != ray_query::both_roots) return std::nullopt;
            return "returns only the nearest root, asked for both_roots";
    }
    return std::nullopt;
}

ray_interval<double> interval_of(const corpus_case& c, precision p) {
    const auto at = [p](double t) { return p == precision::binary32 ? static_cast<double>(static_cast<float>(t)) : t; };
    ray_interval<double> interval;
    if (c.tmin) interval.tmin = at(*c.tmin);
    if (c.tmax) interval.tmax = at(*c.tmax);
    return interval;
}

template <class T>
query_answer answer_query(const variant& v, const ray_sphere<T>& input, ray_interval<T> interval, ray_query q) {
    const root_pair<T> r = run_in(v, input, interval);
    query_answer a;
    a.count = r.count;
    if (r.count <= 0) return a;
    std::optional<T> nearest;
    const auto look = [&](T t) {
        if (!std::isfinite(t)) a.examined_non_finite = true;
        return interval.contains(t);
    };
    switch (v.promises.query) {
        case query_kind::any_hit_in_interval: a.hit = true; return a;
        case query_kind::nearest_in_interval:
            if (!std::isfinite(r.t0)) a.examined_non_finite = true;
            nearest = r.t0;  // promised inside; judge_answer checks it
            break;
        case query_kind::nearest_on_ray:
            if (look(r.t0)) nearest = r.t0;
            break;
        case query_kind::line_roots:
            if (look(r.t0))
                nearest = r.t0;
            else if (r.count >= 2 || r.t1 != r.t0) {
                if (look(r.t1)) nearest = r.t1;
            }
            if (q == ray_query::both_roots) {
                a.t0 = r.t0;
                a.t1 = r.t1;
                a.hit = true;  // both_roots asks about the line
            }
            break;
    }
    if (nearest) {
        a.hit = true;
        a.nearest = *nearest;
        a.hit_point = vec3_cast<double>(input.origin + *nearest * input.direction);
    }
    return a;
}

template query_answer answer_query<float>(const variant&, const ray_sphere<float>&, ray_interval<float>, ray_query);
template query_answer answer_query<double>(const variant&, const ray_sphere<double>&, ray_interval<double>,
                                           ray_query);

namespace {

std::string describe_exact(const exact_solution& exact) {
    if (exact.cls == line_class::miss) return "exact: line misses";
    if (exact.cls == line_class::tangent) return fmt::format("exact: tangent at t* ≈ {}", exact.near_root.rounded);
    return fmt::format("exact: roots t* ≈ {}, {}", exact.near_root.rounded, exact.far_root.rounded);
}

std::string describe_answer(const query_answer& a, ray_query q) {
    if (!a.hit) return "variant: no root";
    if (q == ray_query::both_roots && a.t0 && a.t1) return fmt::format("variant: roots {}, {}", *a.t0, *a.t1);
    if (a.nearest) return fmt::format("variant: nearest root {}", *a.nearest);
    return "variant: hit";
}

// Is `value` nearer the other exact root than the wanted one? Only when the
// two exact roots are distinct after rounding.
bool nearer_other(const exact_solution& exact, root_index wanted, double value) {
    if (exact.cls != line_class::two_hit || exact.near_root.rounded == exact.far_root.rounded) return false;
    const double want = exact.root(wanted).rounded;
    const double other = exact.root(wanted == root_index::near_root ? root_index::far_root : root_index::near_root).rounded;
    return std::fabs(value - other) < std::fabs(value - want);
}

query_verdict judge_both_roots(const query_answer& a, const exact_solution& exact) {
    query_verdict v;
    v.exact_hit = exact.cls != line_class::miss;
    v.variant_hit = a.count > 0;
    const auto fail = [&](query_outcome o, std::string why) {
        v.outcome = o;
        v.detail = std::move(why);
        return v;
    };
    const auto both = [&] { return describe_exact(exact) + "; " + describe_answer(a, ray_query::both_roots); };
    if (a.count < 0 || a.count > 2) return fail(query_outcome::malformed_output, fmt::format("hit count {}", a.count));
    if (!v.exact_hit) return v.variant_hit ? fail(query_outcome::false_hit, both()) : v;
    if (!v.variant_hit) return fail(query_outcome::false_miss, both());
    const double t0 = *a.t0, t1 = *a.t1;
    if (std::isfinite(t0)) v.nearest_ulp = exact.root_ulp_error(root_index::near_root, t0);
    if (std::isfinite(t1)) v.far_ulp = exact.root_ulp_error(root_index::far_root, t1);
    if (!std::isfinite(t0) || !std::isfinite(t1)) return fail(query_outcome::non_finite, both());
    if (t0 > t1) return fail(query_outcome::malformed_output, "roots out of order: " + describe_answer(a, ray_query::both_roots));
    if (nearer_other(exact, root_index::near_root, t0) || nearer_other(exact, root_index::far_root, t1))
        return fail(query_outcome::wrong_root, both());
    return v;
}

}  // namespace

query_verdict judge_answer(const contract& promises, const query_answer& a, const exact_solution& exact,
                           ray_interval<double> interval, ray_query q) {
    if (q == ray_query::both_roots) return judge_both_roots(a, exact);
    query_verdict v;
    const std::optional<root_index> wanted = exact_nearest_in(exact, interval);
    v.exact_hit = wanted.has_value();
    v.variant_hit = a.hit;
    const auto fail = [&](query_outcome o, std::string why) {
        v.outcome = o;
        v.detail = std::move(why);
        return v;
    };
    const auto both = [&] {
        return fmt::format("{}, {} in ({}, {}); {}", describe_exact(exact), wanted ? "one" : "none", interval.tmin,
                           interval.tmax, describe_answer(a, q));
    };
    const int allowed = promises.query == query_kind::line_roots ? 2 : 1;
    if (a.count < 0 || a.count > allowed) return fail(query_outcome::malformed_output, fmt::format("hit count {}", a.count));
    if (!v.exact_hit) {
        return v.variant_hit ? fail(query_outcome::false_hit, both()) : v;
    }
    if (!v.variant_hit) return fail(a.examined_non_finite ? query_outcome::non_finite : query_outcome::false_miss, both());
    if (q == ray_query::any_hit) return v;

    // nearest_hit, hit_point_normal: the nearest root in the interval.
    if (!a.nearest) return fail(query_outcome::malformed_output, "no root returned (an any-hit answer)");
    const double t = *a.nearest;
    if (!std::isfinite(t)) return fail(query_outcome::non_finite, both());
    v.nearest_ulp = exact.root_ulp_error(*wanted, t);
    if (!interval.contains(t))
        return fail(query_outcome::malformed_output,
                    fmt::format("root {} outside the interval ({}, {})", t, interval.tmin, interval.tmax));
    if (nearer_other(exact, *wanted, t)) return fail(query_outcome::wrong_root, both());
    if (q == ray_query::hit_point_normal && a.hit_point) {
        double worst = 0;
        for (int axis = 0; axis < 3; ++axis)
            worst = std::max(worst, exact.hit_point_ulp_error(*wanted, axis, (*a.hit_point)[axis]));
        v.hit_point_ulp = worst;
    }
    return v;
}

query_verdict judge_query(const variant& v, precision p, const corpus_case& c, ray_query q,
                          const exact_solution& exact) {
    query_verdict out;
    if (!exact.valid()) {
        out.outcome = query_outcome::invalid;
        out.detail = invalid_reason_name(exact.invalid);
        return out;
    }
    const ray_interval<double> interval = interval_of(c, p);
    if (p == precision::binary32) {
        const ray_sphere<float> input = rounded_to<float>(c.geometry);
        if (auto breach = contract_breach(v.promises, rounded_to<double>(input), p)) {
            out.outcome = query_outcome::contract_violation;
            out.detail = *breach;
            return out;
        }
        const ray_interval<float> asked{static_cast<float>(interval.tmin), static_cast<float>(interval.tmax)};
        return judge_answer(v.promises, answer_query(v, input, asked, q), exact, interval, q);
    }
    if (auto breach = contract_breach(v.promises, c.geometry, p)) {
        out.outcome = query_outcome::contract_violation;
        out.detail = *breach;
        return out;
    }
    return judge_answer(v.promises, answer_query(v, c.geometry, interval, q), exact, interval, q);
}

}  // namespace rayverify
