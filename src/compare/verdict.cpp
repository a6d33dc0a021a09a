#include "compare/verdict.h"

#include <fmt/format.h>

#include <cmath>
#include <limits>

#include "compare/ulp.h"

namespace rayverify {

std::string_view verdict_name(verdict_kind k) {
    switch (k) {
        case verdict_kind::agree: return "agree";
        case verdict_kind::false_miss: return "false_miss";
        case verdict_kind::false_hit: return "false_hit";
        case verdict_kind::tangent_split: return "tangent_split";
        case verdict_kind::tangent_missed: return "tangent_missed";
        case verdict_kind::false_tangent: return "false_tangent";
        case verdict_kind::wrong_root: return "wrong_root";
        case verdict_kind::wrong_side: return "wrong_side";
        case verdict_kind::non_finite: return "non_finite";
        case verdict_kind::malformed_output: return "malformed_output";
        case verdict_kind::contract_violation: return "contract_violation";
        case verdict_kind::invalid: return "invalid";
    }
    return "?";
}

std::string_view verdict_meaning(verdict_kind k) {
    switch (k) {
        case verdict_kind::agree: return "same class as exact, every root on the same side of the origin";
        case verdict_kind::false_miss: return "the exact line/ray hits the sphere; the variant reports a miss";
        case verdict_kind::false_hit: return "the exact line/ray misses the sphere; the variant reports a hit";
        case verdict_kind::tangent_split: return "exactly tangent; the variant returns two distinct roots";
        case verdict_kind::tangent_missed: return "exactly tangent; the variant reports a miss";
        case verdict_kind::false_tangent:
            return "two distinct roots (distinct even after rounding); the variant reports one";
        case verdict_kind::wrong_root: return "a returned root is nearer the other exact root than its own";
        case verdict_kind::wrong_side:
            return "a root is in front of the origin (t > 0) on one side and not the other: self-hit or lost hit";
        case verdict_kind::non_finite: return "NaN or infinity returned where the exact root is finite";
        case verdict_kind::malformed_output:
            return "a hit count the contract does not allow, roots out of order, or a negative ray distance";
        case verdict_kind::contract_violation:
            return "the case breaks the variant's stated assumption (e.g. non-unit direction); not scored";
        case verdict_kind::invalid: return "the case is invalid at this precision (NaN, d = 0, r < 0, overflow); not scored";
    }
    return "?";
}

bool is_disagreement(verdict_kind k) {
    return k != verdict_kind::agree && k != verdict_kind::contract_violation && k != verdict_kind::invalid;
}

namespace {

// Widen a variant's answer and evaluate the hit point it implies.
template <class T>
variant_output widen(const root_pair<T>& r, const contract& promises, const ray_sphere<T>& input) {
    variant_output out;
    out.roots = {r.count, static_cast<double>(r.t0), static_cast<double>(r.t1)};
    if (r.count <= 0 || promises.query == query_kind::any_hit_in_interval) return out;
    if (promises.query == query_kind::nearest_on_ray || promises.query == query_kind::nearest_in_interval) {
        out.front_root = 0;
    } else if (r.t0 > 0) {
        out.front_root = 0;
    } else if (r.count >= 2 && r.t1 > 0) {
        out.front_root = 1;
    }
    if (out.front_root) {
        const T t = *out.front_root == 0 ? r.t0 : r.t1;
        out.hit_point = vec3_cast<double>(input.origin + t * input.direction);
    }
    return out;
}

}  // namespace

template <class T>
variant_output evaluate(const std::function<root_pair<T>(const ray_sphere<T>&)>& run, const contract& promises,
                        const ray_sphere<T>& input) {
    variant_output out = widen(run(input), promises, input);
    if (takes_interval(promises.query)) out.interval = ray_interval<double>{};
    return out;
}

template variant_output evaluate<float>(const std::function<root_pair<float>(const ray_sphere<float>&)>&,
                                        const contract&, const ray_sphere<float>&);
template variant_output evaluate<double>(const std::function<root_pair<double>(const ray_sphere<double>&)>&,
                                         const contract&, const ray_sphere<double>&);

template <class T>
variant_output evaluate(const variant& v, const ray_sphere<T>& input, ray_interval<T> interval) {
    variant_output out = widen(run_in(v, input, interval), v.promises, input);
    if (takes_interval(v.promises.query)) out.interval = ray_interval<double>{interval.tmin, interval.tmax};
    return out;
}

template variant_output evaluate<float>(const variant&, const ray_sphere<float>&, ray_interval<float>);
template variant_output evaluate<double>(const variant&, const ray_sphere<double>&, ray_interval<double>);

bool exact_root_in(const exact_solution& exact, root_index i, ray_interval<double> interval) {
    // t* > tmin and t* < tmax, where compare_root(i, x) = sign(x − t*).
    const auto above = [&](double bound) {
        if (std::isinf(bound)) return bound < 0;
        return exact.compare_root(i, bound) < 0;
    };
    const auto below = [&](double bound) {
        if (std::isinf(bound)) return bound > 0;
        return exact.compare_root(i, bound) > 0;
    };
    return above(interval.tmin) && below(interval.tmax);
}

std::optional<root_index> exact_nearest_in(const exact_solution& exact, ray_interval<double> interval) {
    if (!exact.valid() || exact.cls == line_class::miss) return std::nullopt;
    for (root_index i : {root_index::near_root, root_index::far_root})
        if (exact_root_in(exact, i, interval)) return i;
    return std::nullopt;
}

std::optional<std::string> contract_breach(const contract& promises, const ray_sphere<double>& input,
                                           precision prec) {
    if (!promises.assumes_unit_direction) return std::nullopt;
    // Wider than both precisions, so the deviation itself is not lost to rounding.
    const long double dx = input.direction.x, dy = input.direction.y, dz = input.direction.z;
    const long double deviation = std::fabs(dx * dx + dy * dy + dz * dz - 1.0L);
    const double epsilon = prec == precision::binary32 ? std::numeric_limits<float>::epsilon()
                                                       : std::numeric_limits<double>::epsilon();
    const double tolerance = 8 * epsilon;
    if (deviation <= tolerance) return std::nullopt;
    return fmt::format("assumes a unit direction, but |d|² − 1 = {:.3g} (tolerance 8ε = {:.3g})",
                       static_cast<double>(deviation), tolerance);
}

namespace {

double ulps_between_in(precision prec, double a, double b) {
    return prec == precision::binary32 ? ulps_between(static_cast<float>(a), static_cast<float>(b))
                                       : ulps_between(a, b);
}

double ulp_of_in(precision prec, double x) {
    return prec == precision::binary32 ? ulp_of(static_cast<float>(x)) : ulp_of(x);
}

// What the exact answer expects a variant to return as one of its roots.
struct expected_root {
    std::optional<root_index> root;  // nullopt: the clamped value 0
    double rounded = 0;              // RN of the expected value
    int sign = 0;
};

expected_root expect(const exact_solution& exact, root_index i) {
    return {i, exact.root(i).rounded, exact.root(i).sign};
}

// |value − expected| in ulps of the expected value, and Herbie bits.
void measure(const exact_solution& exact, const expected_root& want, double value,
             std::optional<double>& ulp, std::optional<double>& bits) {
    if (!std::isfinite(value)) return;
    ulp = want.root ? exact.root_ulp_error(*want.root, value)
                    : (value == 0 ? 0.0 : std::fabs(value) / ulp_of_in(exact.prec, 0.0));
    bits = error_bits(ulps_between_in(exact.prec, value, want.rounded));
}

std::string describe_exact(const exact_solution& exact) {
    if (exact.cls == line_class::miss) return "exact: miss";
    if (exact.cls == line_class::tangent) return fmt::format("exact: tangent at t* ≈ {}", exact.near_root.rounded);
    return fmt::format("exact: two roots t* ≈ {}, {}", exact.near_root.rounded, exact.far_root.rounded);
}

std::string describe_output(const variant_output& out, query_kind query) {
    const auto& r = out.roots;
    if (r.count == 0) return "variant: miss";
    if (query == query_kind::nearest_on_ray) return fmt::format("variant: hit at t = {}", r.t0);
    if (r.count == 1 && (r.t0 == r.t1)) return fmt::format("variant: tangent at t = {}", r.t0);
    if (r.count == 1) return fmt::format("variant: tangent reported, roots {}, {}", r.t0, r.t1);
    return fmt::format("variant: roots {}, {}", r.t0, r.t1);
}

// Side of the origin: in front means t > 0.
std::optional<std::string> side_difference(const char* which, int exact_sign, double exact_rounded, double value) {
    const bool exact_front = exact_sign > 0, variant_front = value > 0;
    if (exact_front == variant_front) return std::nullopt;
    if (variant_front)
        return fmt::format("self-hit: {} root t* = {} is not in front (sign {}), variant returns t = {} > 0",
                           which, exact_rounded, exact_sign, value);
    return fmt::format("lost hit: {} root t* ≈ {} is in front, variant returns t = {} ≤ 0", which, exact_rounded,
                       value);
}

// The exact answer and the variant's, side by side: the detail of most disagreements.
std::string both_answers(const exact_solution& exact, const variant_output& out, query_kind query) {
    return describe_exact(exact) + "; " + describe_output(out, query);
}

case_score disagreement(case_score s, verdict_kind k, std::string detail) {
    s.verdict = k;
    s.detail = std::move(detail);
    return s;
}

case_score judge_line_roots(const variant_output& out, const exact_solution& exact) {
    case_score s;
    const auto& r = out.roots;
    const auto fail = [&](verdict_kind k, std::string why) { return disagreement(s, k, std::move(why)); };
    // Formatted only for a disagreement: most cases agree.
    const auto both = [&] { return both_answers(exact, out, query_kind::line_roots); };
    if (r.count < 0 || r.count > 2) return fail(verdict_kind::malformed_output, fmt::format("hit count {}", r.count));
    if (exact.cls == line_class::miss)
        return r.count > 0 ? fail(verdict_kind::false_hit, both()) : s;
    if (r.count == 0)
        return fail(exact.cls == line_class::tangent ? verdict_kind::tangent_missed : verdict_kind::false_miss, both());

    // With count 1 (a reported tangent) t1 is still the variant's far root.
    const double t0 = r.t0, t1 = r.t1;
    const expected_root near = expect(exact, root_index::near_root), far = expect(exact, root_index::far_root);
    measure(exact, near, t0, s.near_ulp, s.near_bits);
    measure(exact, far, t1, s.far_ulp, s.far_bits);

    if ((!std::isfinite(t0) && std::isfinite(near.rounded)) || (!std::isfinite(t1) && std::isfinite(far.rounded)))
        return fail(verdict_kind::non_finite, both());
    if (t0 > t1) return fail(verdict_kind::malformed_output, "roots out of order: " + describe_output(out, query_kind::line_roots));
    if (exact.cls == line_class::tangent && t0 != t1) return fail(verdict_kind::tangent_split, both());
    const bool distinct_after_rounding = near.rounded != far.rounded;
    if (exact.cls == line_class::two_hit && distinct_after_rounding && (r.count == 1 || t0 == t1))
        return fail(verdict_kind::false_tangent, both());
    if (exact.cls == line_class::two_hit && distinct_after_rounding &&
        (std::fabs(t0 - far.rounded) < std::fabs(t0 - near.rounded) ||
         std::fabs(t1 - near.rounded) < std::fabs(t1 - far.rounded)))
        return fail(verdict_kind::wrong_root, both());
    if (auto why = side_difference("near", near.sign, near.rounded, t0)) return fail(verdict_kind::wrong_side, *why);
    if (auto why = side_difference("far", far.sign, far.rounded, t1)) return fail(verdict_kind::wrong_side, *why);
    return s;
}

case_score judge_nearest_on_ray(const contract& promises, const variant_output& out, const exact_solution& exact) {
    case_score s;
    const auto& r = out.roots;
    const auto fail = [&](verdict_kind k, std::string why) { return disagreement(s, k, std::move(why)); };
    // Formatted only for a disagreement: most cases agree.
    const auto both = [&] { return both_answers(exact, out, query_kind::nearest_on_ray); };
    if (r.count < 0 || r.count > 1) return fail(verdict_kind::malformed_output, fmt::format("hit count {}", r.count));
    // The closed ray t ≥ 0 is hit when the far root is not behind the origin.
    const bool exact_hit = exact.cls != line_class::miss && exact.far_root.sign >= 0;
    if (!exact_hit) return r.count > 0 ? fail(verdict_kind::false_hit, both()) : s;
    if (r.count == 0)
        return fail(exact.cls == line_class::tangent ? verdict_kind::tangent_missed : verdict_kind::false_miss, both());

    expected_root want;
    if (exact.near_root.sign >= 0)
        want = expect(exact, root_index::near_root);
    else if (!promises.clamps_to_zero)
        want = expect(exact, root_index::far_root);  // else: origin inside, clamped to 0
    const double t = r.t0;
    measure(exact, want, t, s.near_ulp, s.near_bits);

    if (!std::isfinite(t) && std::isfinite(want.rounded)) return fail(verdict_kind::non_finite, both());
    if (t < 0) return fail(verdict_kind::malformed_output, fmt::format("negative ray distance {}", t));
    if (want.root && exact.cls == line_class::two_hit && exact.near_root.rounded != exact.far_root.rounded) {
        const double other = want.root == root_index::near_root ? exact.far_root.rounded : exact.near_root.rounded;
        if (std::fabs(t - other) < std::fabs(t - want.rounded)) return fail(verdict_kind::wrong_root, both());
    }
    const char* which = !want.root ? "clamped" : (want.root == root_index::near_root ? "near" : "far");
    if (auto why = side_difference(which, want.sign, want.rounded, t)) return fail(verdict_kind::wrong_side, *why);
    return s;
}

// any_hit_in_interval: only whether some root lies in the interval.
case_score judge_any_hit(const variant_output& out, const exact_solution& exact, ray_interval<double> interval) {
    case_score s;
    const auto& r = out.roots;
    if (r.count < 0 || r.count > 1) return disagreement(s, verdict_kind::malformed_output, fmt::format("hit count {}", r.count));
    const bool exact_hit = exact_nearest_in(exact, interval).has_value();
    const auto both = [&] {
        return fmt::format("exact: {} root in ({}, {}); variant: {}", exact_hit ? "a" : "no", interval.tmin,
                           interval.tmax, r.count ? "hit" : "miss");
    };
    if (!exact_hit) return r.count > 0 ? disagreement(s, verdict_kind::false_hit, both()) : s;
    if (r.count == 0)
        return disagreement(s, exact.cls == line_class::tangent ? verdict_kind::tangent_missed : verdict_kind::false_miss,
                            both());
    return s;
}

// nearest_in_interval: the nearest root in the interval, one value.
case_score judge_nearest_in_interval(const variant_output& out, const exact_solution& exact,
                                     ray_interval<double> interval) {
    case_score s;
    const auto& r = out.roots;
    const auto fail = [&](verdict_kind k, std::string why) { return disagreement(s, k, std::move(why)); };
    const std::optional<root_index> wanted = exact_nearest_in(exact, interval);
    const auto both = [&] {
        return fmt::format("{} in ({}, {}); {}", describe_exact(exact), interval.tmin, interval.tmax,
                           describe_output(out, query_kind::nearest_on_ray));
    };
    if (r.count < 0 || r.count > 1) return fail(verdict_kind::malformed_output, fmt::format("hit count {}", r.count));
    if (!wanted) return r.count > 0 ? fail(verdict_kind::false_hit, both()) : s;
    if (r.count == 0)
        return fail(exact.cls == line_class::tangent ? verdict_kind::tangent_missed : verdict_kind::false_miss, both());

    const expected_root want = expect(exact, *wanted);
    const double t = r.t0;
    measure(exact, want, t, s.near_ulp, s.near_bits);
    if (!std::isfinite(t)) return fail(verdict_kind::non_finite, both());
    if (!interval.contains(t))
        return fail(verdict_kind::malformed_output, fmt::format("root {} outside the interval ({}, {})", t,
                                                                interval.tmin, interval.tmax));
    if (exact.cls == line_class::two_hit && exact.near_root.rounded != exact.far_root.rounded) {
        const double other = *wanted == root_index::near_root ? exact.far_root.rounded : exact.near_root.rounded;
        if (std::fabs(t - other) < std::fabs(t - want.rounded)) return fail(verdict_kind::wrong_root, both());
    }
    return s;
}

}  // namespace

case_score score_case(const contract& promises, const variant_output& output, const exact_solution& exact,
                      const ray_sphere<double>& input) {
    if (takes_interval(promises.query)) {
        const ray_interval<double> interval = output.interval.value_or(ray_interval<double>{});
        if (promises.query == query_kind::any_hit_in_interval) return judge_any_hit(output, exact, interval);
        case_score s = judge_nearest_in_interval(output, exact, interval);
        if (s.verdict != verdict_kind::agree || !output.hit_point) return s;
        // Hit point error for the nearest root in the interval.
        const root_index wanted = *exact_nearest_in(exact, interval);
        std::array<double, 3> errors{};
        for (int axis = 0; axis < 3; ++axis)
            errors[axis] = exact.hit_point_ulp_error(wanted, axis, (*output.hit_point)[axis]);
        s.hit_point_ulp = errors;
        return s;
    }
    case_score s = promises.query == query_kind::line_roots ? judge_line_roots(output, exact)
                                                            : judge_nearest_on_ray(promises, output, exact);
    if (s.verdict != verdict_kind::agree || !output.hit_point || !output.front_root) return s;

    // Hit point error, when the variant's front root is the exact front root.
    const vec3<double> hit = *output.hit_point;
    std::array<double, 3> errors{};
    const bool ray_query = promises.query == query_kind::nearest_on_ray;
    const bool expects_origin = ray_query && (exact.near_root.sign == 0 ||
                                              (exact.near_root.sign < 0 && promises.clamps_to_zero));
    if (expects_origin) {
        // Expected t = 0 (origin on the surface, or inside and clamped): the hit point is o itself.
        for (int axis = 0; axis < 3; ++axis)
            errors[axis] = std::fabs(hit[axis] - input.origin[axis]) / ulp_of_in(exact.prec, input.origin[axis]);
    } else {
        const root_index front = (ray_query ? exact.near_root.sign > 0 : *output.front_root == 0)
                                     ? root_index::near_root
                                     : root_index::far_root;
        if (!exact.nearest_in_front || *exact.nearest_in_front != front) return s;
        for (int axis = 0; axis < 3; ++axis) errors[axis] = exact.hit_point_ulp_error(front, axis, hit[axis]);
    }
    s.hit_point_ulp = errors;
    return s;
}

}  // namespace rayverify
