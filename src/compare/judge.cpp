#include "compare/judge.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "compare/stability.h"
#include "core/case_in_progress.h"
#include "core/float_bits.h"

namespace rayverify {

// ---- Vocabulary ---------------------------------------------------------------

namespace {

struct verdict_entry {
    verdict_kind kind;
    std::string_view name, column, meaning;
};

constexpr verdict_entry verdict_table[verdict_kind_count] = {
    {verdict_kind::agree, "agree", "agree", "the answer the contract asks for, every root on the same side of every range bound"},
    {verdict_kind::false_miss, "false_miss", "f_miss", "the exact answer is a hit (in the range); the variant reports none"},
    {verdict_kind::false_hit, "false_hit", "f_hit", "the exact answer is no hit (in the range); the variant reports one"},
    {verdict_kind::tangent_split, "tangent_split", "t_split", "exactly tangent; the variant returns two distinct roots"},
    {verdict_kind::tangent_missed, "tangent_missed", "t_miss", "exactly tangent, a hit; the variant reports a miss"},
    {verdict_kind::false_tangent, "false_tangent", "f_tan",
     "two roots distinct even after rounding; the variant reports one (a tangent)"},
    {verdict_kind::wrong_root, "wrong_root", "w_root",
     "a returned t stands for another exact root than the one asked for (it is strictly nearer that root, by "
     "the exact midpoint −b′/a; a t at the midpoint counts as the root asked for)"},
    {verdict_kind::wrong_sphere, "wrong_sphere", "w_sph", "both hit, but the variant's nearest sphere is not the exact nearest"},
    {verdict_kind::wrong_side, "wrong_side", "w_side",
     "a returned t and the exact root it stands for lie on opposite sides of a range bound (the origin for "
     "line roots): a self-hit or a lost hit"},
    {verdict_kind::non_finite, "non_finite", "nonfin",
     "NaN, or an infinity that is not the correctly rounded root (±inf agrees only where RN(t*) is that "
     "infinity)"},
    {verdict_kind::malformed_output, "malformed_output", "malf", "a hit count the contract does not allow, or roots out of order"},
    {verdict_kind::contract_violation, "contract_violation", "contract",
     "the case breaks the variant's stated assumption (a direction not within 8ε of unit length); not scored"},
    {verdict_kind::invalid, "invalid", "invalid",
     "the case is invalid at this precision (NaN or infinite input, d = 0, r < 0, overflow, bad interval); not "
     "scored"},
};

struct cause_entry {
    disagreement_cause cause;
    std::string_view name, meaning;
    bool by_design;
};

constexpr cause_entry cause_table[disagreement_cause_count] = {
    {disagreement_cause::conditioning_limited, "conditioning_limited",
     "rounding error: the case is within the backward error of the other answer at this precision", false},
    {disagreement_cause::algorithmic, "algorithmic",
     "rounding error (or a formula defect) that a backward-stable formula would not make", false},
    {disagreement_cause::clamp, "clamp",
     "by design: the contract clamps t to the range start when the origin is inside, and the renderer's "
     "interval excludes that start",
     true},
    {disagreement_cause::contract_semantics, "contract_semantics",
     "by design: the contract answers another question than the renderer asks (inside a miss, front faces "
     "only, tangent a miss, other range ends)",
     true},
    {disagreement_cause::unit_direction, "unit_direction",
     "by design: assumes |d| = 1 while |d|² is only within tolerance of 1; the formula with a = 1 gives this "
     "answer in exact arithmetic",
     true},
    {disagreement_cause::tangent_threshold, "tangent_threshold",
     "by design: reports a tangent whenever its discriminant is below an absolute threshold, as the exact "
     "discriminant is",
     true},
    {disagreement_cause::line_not_ray, "line_not_ray",
     "by design: returns a root that lies outside its range exactly (it tests the line, not the ray)", true},
};

const verdict_entry& entry(verdict_kind k) { return verdict_table[static_cast<int>(k)]; }
const cause_entry& entry(disagreement_cause c) { return cause_table[static_cast<int>(c)]; }

}  // namespace

std::string_view verdict_name(verdict_kind k) { return entry(k).name; }
std::string_view verdict_meaning(verdict_kind k) { return entry(k).meaning; }
std::string_view verdict_column(verdict_kind k) { return entry(k).column; }

std::optional<verdict_kind> verdict_from_name(std::string_view name) {
    for (const verdict_entry& e : verdict_table)
        if (e.name == name) return e.kind;
    return std::nullopt;
}

bool is_disagreement(verdict_kind k) {
    return k != verdict_kind::agree && k != verdict_kind::contract_violation && k != verdict_kind::invalid;
}

bool is_misclassification(verdict_kind k) {
    return k == verdict_kind::false_miss || k == verdict_kind::false_hit || k == verdict_kind::tangent_split ||
           k == verdict_kind::tangent_missed || k == verdict_kind::false_tangent;
}

std::string_view cause_name(disagreement_cause c) { return entry(c).name; }
std::string_view cause_meaning(disagreement_cause c) { return entry(c).meaning; }
bool is_by_design(disagreement_cause c) { return entry(c).by_design; }

std::optional<disagreement_cause> cause_from_name(std::string_view name) {
    for (const cause_entry& e : cause_table)
        if (e.name == name) return e.cause;
    return std::nullopt;
}

// ---- Exact facts under a contract ----------------------------------------------

bool root_in_range(const exact_solution& exact, root_index i, const t_range& range) {
    // compare_root(i, x) = sign(x − t*).
    const auto above_lower = [&] {
        if (std::isinf(range.lower)) return range.lower < 0;
        const int side = exact.compare_root(i, range.lower);
        return side < 0 || (side == 0 && range.lower_end == end_kind::closed);
    };
    const auto below_upper = [&] {
        if (std::isinf(range.upper)) return range.upper > 0;
        const int side = exact.compare_root(i, range.upper);
        return side > 0 || (side == 0 && range.upper_end == end_kind::closed);
    };
    return above_lower() && below_upper();
}

bool starts_inside(const exact_solution& exact, const t_range& range) {
    if (exact.cls != line_class::two_hit || std::isinf(range.lower)) return false;
    return exact.compare_root(root_index::near_root, range.lower) > 0 &&
           exact.compare_root(root_index::far_root, range.lower) < 0;
}

expected_hit expect_hit(const contract& promises, const exact_solution& exact, const t_range& range) {
    expected_hit none;
    if (exact.cls == line_class::miss) return none;
    const auto root = [&](root_index i) {
        return expected_hit{expected_hit::kind::root, i, exact.root(i).rounded};
    };
    if (exact.cls == line_class::tangent) {
        if (!promises.tangent_is_hit || !root_in_range(exact, root_index::near_root, range)) return none;
        return root(root_index::near_root);
    }
    if (root_in_range(exact, root_index::near_root, range)) return root(root_index::near_root);
    if (starts_inside(exact, range)) {
        switch (promises.inside) {
            case inside_rule::clamp: return {expected_hit::kind::clamp, root_index::near_root, range.lower};
            case inside_rule::miss: return none;
            case inside_rule::far_root: break;
        }
    }
    if (promises.front_faces_only) return none;
    return root_in_range(exact, root_index::far_root, range) ? root(root_index::far_root) : none;
}

root_index stands_for(const exact_solution& exact, double t, root_index wanted) {
    if (exact.cls != line_class::two_hit || t == exact.root(wanted).rounded) return wanted;
    const int side = exact.compare_midpoint(t);
    if (side == 0) return wanted;  // equidistant: the benefit of the doubt
    return side < 0 ? root_index::near_root : root_index::far_root;
}

// ---- Running a variant ------------------------------------------------------------

template <class T>
variant_output evaluate(const variant& v, const ray_sphere<T>& input, ray_interval<T> interval, const t_range& range) {
    const root_pair<T> r = run_in(v, input, interval);
    variant_output out;
    out.roots = {r.count, static_cast<double>(r.t0), static_cast<double>(r.t1)};
    if (r.count <= 0) return out;
    switch (v.promises.query) {
        case query_kind::any_hit: return out;
        case query_kind::nearest_hit: out.hit_root = 0; break;
        case query_kind::line_roots:
            if (range.contains(r.t0))
                out.hit_root = 0;
            else if (range.contains(r.t1))
                out.hit_root = 1;
            break;
    }
    if (out.hit_root) {
        const T t = *out.hit_root == 0 ? r.t0 : r.t1;
        out.hit_point = vec3_cast<double>(input.origin + t * input.direction);
    }
    return out;
}

template variant_output evaluate<float>(const variant&, const ray_sphere<float>&, ray_interval<float>, const t_range&);
template variant_output evaluate<double>(const variant&, const ray_sphere<double>&, ray_interval<double>,
                                         const t_range&);

// ---- Judging -------------------------------------------------------------------------

namespace {

std::uint64_t ulps_between_in(precision p, double a, double b) {
    return p == precision::binary32 ? ulps_between(static_cast<float>(a), static_cast<float>(b)) : ulps_between(a, b);
}

double ulp_of_in(precision p, double x) {
    return p == precision::binary32 ? ulp_of(static_cast<float>(x)) : ulp_of(x);
}

// The error of a finite value against root i: ULPs of t* and Herbie bits.
void measure_root(const exact_solution& exact, root_index i, double value, std::optional<double>& ulp,
                  std::optional<double>& bits) {
    if (!std::isfinite(value)) return;
    ulp = exact.root_ulp_error(i, value);
    bits = error_bits(ulps_between_in(exact.prec, value, exact.root(i).rounded));
}

// The error of a finite value against an exact double (a clamp's range start).
void measure_value(precision p, double want, double value, std::optional<double>& ulp, std::optional<double>& bits) {
    if (!std::isfinite(value)) return;
    ulp = value == want ? 0.0 : std::fabs(value - want) / ulp_of_in(p, want);
    bits = error_bits(ulps_between_in(p, value, want));
}

std::string describe_output(const variant_output& out, query_kind query) {
    const auto& r = out.roots;
    if (r.count == 0) return "variant: miss";
    switch (query) {
        case query_kind::any_hit: return "variant: hit";
        case query_kind::nearest_hit: return fmt::format("variant: hit at t = {}", r.t0);
        case query_kind::line_roots: break;
    }
    if (r.count == 1 && r.t0 == r.t1) return fmt::format("variant: tangent at t = {}", r.t0);
    if (r.count == 1) return fmt::format("variant: tangent reported, roots {}, {}", r.t0, r.t1);
    return fmt::format("variant: roots {}, {}", r.t0, r.t1);
}

const char* root_word(root_index i) { return i == root_index::near_root ? "near" : "far"; }

case_score disagreement(case_score s, verdict_kind k, std::string detail) {
    s.verdict = k;
    s.detail = std::move(detail);
    return s;
}

// Which side of the range a root and a value are on, and the verdict when
// they differ: an exact root outside with the value inside is a self-hit.
std::optional<std::string> side_difference(const exact_solution& exact, root_index k, double t, const t_range& range) {
    const bool root_inside = root_in_range(exact, k, range), value_inside = range.contains(t);
    if (root_inside == value_inside) return std::nullopt;
    if (value_inside)
        return fmt::format("self-hit: t = {} stands for the {} root t* ≈ {}, which is outside {}", t, root_word(k),
                           exact.root(k).rounded, format_range(range));
    return fmt::format("lost hit: the {} root t* ≈ {} is in {}, the variant's t = {} is not", root_word(k),
                       exact.root(k).rounded, format_range(range), t);
}

// Both roots of the line.
case_score judge_line_roots(const variant_output& out, const exact_solution& exact, const t_range& range) {
    case_score s;
    const auto& r = out.roots;
    const auto fail = [&](verdict_kind k, std::string why) { return disagreement(s, k, std::move(why)); };
    const auto both = [&] { return describe_exact(exact) + "; " + describe_output(out, query_kind::line_roots); };
    if (r.count < 0 || r.count > 2) return fail(verdict_kind::malformed_output, fmt::format("hit count {}", r.count));
    if (exact.cls == line_class::miss) return r.count > 0 ? fail(verdict_kind::false_hit, both()) : s;
    if (r.count == 0)
        return fail(exact.cls == line_class::tangent ? verdict_kind::tangent_missed : verdict_kind::false_miss, both());

    // With count 1 (a reported tangent) t1 is still the variant's far root.
    const double t[2] = {r.t0, r.t1};
    const root_index wanted[2] = {root_index::near_root, root_index::far_root};
    measure_root(exact, wanted[0], t[0], s.near_ulp, s.near_bits);
    measure_root(exact, wanted[1], t[1], s.far_ulp, s.far_bits);
    for (int i = 0; i < 2; ++i)
        if (std::isnan(t[i]) || (std::isinf(t[i]) && t[i] != exact.root(wanted[i]).rounded))
            return fail(verdict_kind::non_finite, both());
    if (t[0] > t[1]) return fail(verdict_kind::malformed_output, "roots out of order: " + describe_output(out, query_kind::line_roots));
    if (exact.cls == line_class::tangent && t[0] != t[1]) return fail(verdict_kind::tangent_split, both());
    const bool distinct_after_rounding = exact.near_root.rounded != exact.far_root.rounded;
    if (exact.cls == line_class::two_hit && distinct_after_rounding && (r.count == 1 || t[0] == t[1]))
        return fail(verdict_kind::false_tangent, both());
    const root_index stands[2] = {stands_for(exact, t[0], wanted[0]), stands_for(exact, t[1], wanted[1])};
    for (int i = 0; i < 2; ++i)
        if (auto why = side_difference(exact, stands[i], t[i], range)) return fail(verdict_kind::wrong_side, *why);
    for (int i = 0; i < 2; ++i)
        if (stands[i] != wanted[i])
            return fail(verdict_kind::wrong_root,
                        fmt::format("t{} = {} stands for the {} root: {}", i, t[i], root_word(stands[i]), both()));
    return s;
}

// nearest_hit and any_hit.
case_score judge_hit(const contract& promises, const variant_output& out, const exact_solution& exact,
                     const t_range& range) {
    case_score s;
    const auto& r = out.roots;
    const auto fail = [&](verdict_kind k, std::string why) { return disagreement(s, k, std::move(why)); };
    const expected_hit want = expect_hit(promises, exact, range);
    const auto both = [&] {
        return describe_expected(promises, exact, range) + "; " + describe_output(out, promises.query);
    };
    if (r.count < 0 || r.count > 1) return fail(verdict_kind::malformed_output, fmt::format("hit count {}", r.count));
    const bool any = promises.query == query_kind::any_hit;
    // A NaN the answer rests on (any_hit: one the renderer looked at) never agrees.
    if (r.count == 1 && (any ? out.nan_seen : std::isnan(r.t0))) return fail(verdict_kind::non_finite, both());
    if (!want.hit()) return r.count > 0 ? fail(verdict_kind::false_hit, both()) : s;
    if (r.count == 0)
        return fail(exact.cls == line_class::tangent ? verdict_kind::tangent_missed : verdict_kind::false_miss, both());
    if (any) return s;

    const double t = r.t0;
    if (want.what == expected_hit::kind::clamp) {
        measure_value(exact.prec, want.value, t, s.near_ulp, s.near_bits);
        if (t == want.value) return s;
        if (std::isinf(t)) return fail(verdict_kind::non_finite, both());
        const root_index k = stands_for(exact, t, root_index::far_root);
        if (!root_in_range(exact, k, range) && !range.contains(t)) s.cause = disagreement_cause::line_not_ray;
        return fail(verdict_kind::wrong_root,
                    fmt::format("t = {} stands for the {} root, where the contract clamps to {}: {}", t, root_word(k),
                                want.value, both()));
    }
    measure_root(exact, want.root, t, s.near_ulp, s.near_bits);
    if (std::isinf(t) && t != want.value) return fail(verdict_kind::non_finite, both());
    const root_index k = stands_for(exact, t, want.root);
    if (auto why = side_difference(exact, k, t, range)) return fail(verdict_kind::wrong_side, *why);
    if (k != want.root) {
        // Both outside the range: the formula returns a root its range excludes.
        if (!root_in_range(exact, k, range)) s.cause = disagreement_cause::line_not_ray;
        return fail(verdict_kind::wrong_root, fmt::format("t = {} stands for the {} root: {}", t, root_word(k), both()));
    }
    return s;
}

// The verdict and errors, and a cause only where the verdict itself shows it
// (line_not_ray).
case_score judge_verdict(const contract& promises, const variant_output& output, const exact_solution& exact,
                         const t_range& range) {
    return promises.query == query_kind::line_roots ? judge_line_roots(output, exact, range)
                                                    : judge_hit(promises, output, exact, range);
}

// Hit point error of an agreeing answer: for the root that is the hit, when
// the variant's hit is that root.
void measure_hit_point(const contract& promises, const variant_output& output, const exact_solution& exact,
                       const t_range& range, const ray_sphere<double>& input, case_score& s) {
    if (!output.hit_point || promises.query == query_kind::any_hit) return;
    const vec3<double>& hit = *output.hit_point;
    std::array<double, 3> errors{};
    if (promises.query == query_kind::nearest_hit) {
        const expected_hit want = expect_hit(promises, exact, range);
        if (want.what == expected_hit::kind::clamp) {
            if (want.value != 0) return;  // o + tmin·d is not an exact point the oracle holds
            for (int axis = 0; axis < 3; ++axis)
                errors[axis] = std::fabs(hit[axis] - input.origin[axis]) / ulp_of_in(exact.prec, input.origin[axis]);
            s.hit_point_ulp = errors;
            return;
        }
        if (want.what != expected_hit::kind::root) return;
        for (int axis = 0; axis < 3; ++axis) errors[axis] = exact.hit_point_ulp_error(want.root, axis, hit[axis]);
        s.hit_point_ulp = errors;
        return;
    }
    // line_roots: the first exact root in the range, when the variant's hit is the same one.
    std::optional<root_index> first;
    for (root_index i : {root_index::near_root, root_index::far_root})
        if (root_in_range(exact, i, range)) {
            first = i;
            break;
        }
    if (!first || !output.hit_root || *output.hit_root != (*first == root_index::near_root ? 0 : 1)) return;
    for (int axis = 0; axis < 3; ++axis) errors[axis] = exact.hit_point_ulp_error(*first, axis, hit[axis]);
    s.hit_point_ulp = errors;
}

// The rounding cause: conditioning-limited when the case is within the
// backward error of the other answer (stability.h): a class verdict when the
// tangency margin is ≤ γ; a root or side verdict also when γ·u·κ ≥ 1.
// Non-finite and malformed outputs are always algorithmic.
disagreement_cause rounding_cause(verdict_kind k, const ray_sphere<double>& input, const exact_solution& exact) {
    const stability_measures m = measure_stability(input, exact.prec, exact);
    if (!m.valid) return disagreement_cause::algorithmic;
    const bool ambiguous_class = m.tangency_margin <= conditioning_gamma;
    if (is_misclassification(k))
        return ambiguous_class ? disagreement_cause::conditioning_limited : disagreement_cause::algorithmic;
    if (k == verdict_kind::wrong_root || k == verdict_kind::wrong_side || k == verdict_kind::wrong_sphere) {
        const double u = std::ldexp(1.0, -significand_bits(exact.prec));
        const bool ambiguous_root = m.near_condition && conditioning_gamma * u * *m.near_condition >= 1;
        return ambiguous_class || ambiguous_root ? disagreement_cause::conditioning_limited
                                                 : disagreement_cause::algorithmic;
    }
    return disagreement_cause::algorithmic;
}

// Why the variant disagreed, by design before rounding.
disagreement_cause cause_of(const contract& promises, const variant_output& output, const exact_solution& exact,
                            const t_range& range, const ray_sphere<double>& input, verdict_kind k) {
    std::optional<exact_solution> unit_design;
    const auto design = [&]() -> const exact_solution& {
        if (!unit_design) unit_design = solve_exact_unit_direction(input, exact.prec);
        return *unit_design;
    };
    const bool unit_assumed_wrongly =
        promises.assumes_unit_direction && compare_squared_length(input.direction, 1.0) != 0;
    if (k == verdict_kind::false_tangent && promises.tangent_threshold) {
        const exact_solution& solved = promises.assumes_unit_direction ? design() : exact;
        if (solved.valid() && solved.compare_discriminant(*promises.tangent_threshold) <= 0)
            return disagreement_cause::tangent_threshold;
    }
    if (unit_assumed_wrongly) {
        const exact_solution& solved = design();
        if (solved.valid() && judge_verdict(promises, output, solved, range).verdict == verdict_kind::agree)
            return disagreement_cause::unit_direction;
    }
    return rounding_cause(k, input, exact);
}

}  // namespace

case_score judge_output(const contract& promises, const variant_output& output, const exact_solution& exact,
                        const t_range& range, const ray_sphere<double>& input) {
    case_score s = judge_verdict(promises, output, exact, range);
    if (s.verdict == verdict_kind::agree) {
        measure_hit_point(promises, output, exact, range, input, s);
        return s;
    }
    if (!s.cause) s.cause = cause_of(promises, output, exact, range, input, s.verdict);
    return s;
}

std::optional<std::string> contract_breach(const contract& promises, const ray_sphere<double>& input,
                                           precision prec) {
    if (!promises.assumes_unit_direction) return std::nullopt;
    // |d|² within [1 − 8ε, 1 + 8ε], both ends exact doubles, decided exactly.
    const double tolerance = 8 * (prec == precision::binary32 ? 0x1p-23 : 0x1p-52);
    const int above = compare_squared_length(input.direction, 1 + tolerance);
    const int below = compare_squared_length(input.direction, 1 - tolerance);
    if (above <= 0 && below >= 0) return std::nullopt;
    const double squared = dot(input.direction, input.direction);
    return fmt::format("assumes a unit direction, but |d|² ≈ {:.17g} is {} 1 {} 8ε (8ε = {:.3g})", squared,
                       above > 0 ? "above" : "below", above > 0 ? "+" : "−", tolerance);
}

exact_solution solve_case(const corpus_case& c, precision p) {
    const invalid_reason reason = p == precision::binary32 ? validity<float>(c.geometry) : validity<double>(c.geometry);
    if (reason != invalid_reason::none) {
        exact_solution invalid;
        invalid.prec = p;
        invalid.invalid = reason;
        return invalid;
    }
    const ray_sphere<double> input =
        p == precision::binary32 ? rounded_to<double>(rounded_to<float>(c.geometry)) : c.geometry;
    const auto bound = [p](std::optional<double> t) -> std::optional<double> {
        if (!t || p == precision::binary64) return t;
        return static_cast<double>(static_cast<float>(*t));
    };
    return solve_exact(input, p, bound(c.tmin), bound(c.tmax));
}

t_range range_for(const contract& promises, const corpus_case& c, precision p) {
    const auto at = [p](std::optional<double> t) -> std::optional<double> {
        if (!t || p == precision::binary64) return t;
        return static_cast<double>(static_cast<float>(*t));
    };
    return range_of(promises, at(c.tmin), at(c.tmax));
}

namespace {

template <class T>
ray_interval<T> interval_in(const t_range& range) {
    return {static_cast<T>(range.lower), static_cast<T>(range.upper)};
}

// Invalid or outside the contract: the outcome, else nullopt.
std::optional<case_score> unscored(const contract& promises, const exact_solution& exact,
                                   const ray_sphere<double>& widened, precision p) {
    case_score s;
    if (!exact.valid()) {
        s.verdict = verdict_kind::invalid;
        s.detail = invalid_reason_name(exact.invalid);
        return s;
    }
    if (auto breach = contract_breach(promises, widened, p)) {
        s.verdict = verdict_kind::contract_violation;
        s.detail = *breach;
        return s;
    }
    return std::nullopt;
}

template <class T>
target_outcome judge_target_in(const audit_target& target, const corpus_case& c, const exact_solution& exact) {
    target_outcome outcome;
    const ray_sphere<T> input = rounded_to<T>(c.geometry);
    const ray_sphere<double> widened = rounded_to<double>(input);
    const contract& promises = target.subject.promises;
    if (auto s = unscored(promises, exact, widened, target.prec)) {
        outcome.score = std::move(*s);
        return outcome;
    }
    outcome.range = range_for(promises, c, target.prec);
    outcome.output = evaluate(target.subject, input, interval_in<T>(outcome.range), outcome.range);
    outcome.score = judge_output(promises, outcome.output, exact, outcome.range, widened);
    return outcome;
}

}  // namespace

target_outcome judge_target(const audit_target& target, const corpus_case& c, const exact_solution& exact) {
    return target.prec == precision::binary32 ? judge_target_in<float>(target, c, exact)
                                              : judge_target_in<double>(target, c, exact);
}

// ---- The renderer's view --------------------------------------------------------

const char* ray_query_name(ray_query q) {
    switch (q) {
        case ray_query::any_hit: return "any_hit";
        case ray_query::nearest_hit: return "nearest_hit";
        case ray_query::both_roots: return "both_roots";
        case ray_query::hit_point_normal: return "hit_point_normal";
    }
    return "?";
}

std::optional<ray_query> ray_query_from_name(std::string_view name) {
    for (ray_query q : {ray_query::any_hit, ray_query::nearest_hit, ray_query::both_roots, ray_query::hit_point_normal})
        if (name == ray_query_name(q)) return q;
    return std::nullopt;
}

contract renderer_contract(ray_query q, end_kind lower_end, end_kind upper_end) {
    contract c;
    c.query = q == ray_query::any_hit      ? query_kind::any_hit
              : q == ray_query::both_roots ? query_kind::line_roots
                                           : query_kind::nearest_hit;
    c.range = range_source::interval;
    c.lower_end = lower_end;
    c.upper_end = upper_end;
    c.reports_tangent = true;
    c.tangent_rule = "as the variant";
    return c;
}

std::optional<std::string> applicable(const variant& v, ray_query q, bool directions_normalised) {
    const contract& c = v.promises;
    if (c.assumes_unit_direction && !directions_normalised)
        return "assumes a unit direction; the scene's directions are not normalised";
    switch (c.query) {
        case query_kind::line_roots: return std::nullopt;
        case query_kind::any_hit:
            if (q == ray_query::any_hit) return std::nullopt;
            return fmt::format("answers only any_hit (no root), asked for {}", ray_query_name(q));
        case query_kind::nearest_hit:
            if (q != ray_query::both_roots) return std::nullopt;
            return "returns only the nearest root, asked for both_roots";
    }
    return std::nullopt;
}

template <class T>
variant_output renderer_view(const contract& promises, const root_pair<T>& raw, const ray_sphere<T>& input,
                             const t_range& ray_range, ray_query q) {
    variant_output out;
    out.roots = {raw.count, static_cast<double>(raw.t0), static_cast<double>(raw.t1)};
    if (q == ray_query::both_roots) {  // the line's roots as returned; the hit is the first in the range
        if (raw.count > 0) {
            if (ray_range.contains(raw.t0))
                out.hit_root = 0;
            else if (ray_range.contains(raw.t1))
                out.hit_root = 1;
        }
    } else {
        const int allowed = promises.query == query_kind::line_roots ? 2 : 1;
        if (raw.count < 0 || raw.count > allowed) return out;  // malformed, judged as such
        std::optional<T> nearest;
        const auto look = [&](T t) {
            if (std::isnan(t)) out.nan_seen = true;
            return ray_range.contains(t);
        };
        if (raw.count > 0) switch (promises.query) {
                case query_kind::any_hit: out.roots = {1, 0.0, 0.0}; return out;
                case query_kind::nearest_hit:
                    if (look(raw.t0)) nearest = raw.t0;
                    break;
                case query_kind::line_roots:
                    if (look(raw.t0))
                        nearest = raw.t0;
                    else if (look(raw.t1))
                        nearest = raw.t1;
                    break;
            }
        const bool nan_answer = !nearest && out.nan_seen;  // kept: a NaN never agrees
        const double value = nearest ? static_cast<double>(*nearest) : std::numeric_limits<double>::quiet_NaN();
        out.roots = {nearest || nan_answer ? 1 : 0, value, value};
        if (nearest) out.hit_root = 0;
    }
    if (out.hit_root) {
        const T t = *out.hit_root == 0 ? static_cast<T>(out.roots.t0) : static_cast<T>(out.roots.t1);
        out.hit_point = vec3_cast<double>(input.origin + t * input.direction);
    }
    return out;
}

template variant_output renderer_view<float>(const contract&, const root_pair<float>&, const ray_sphere<float>&,
                                             const t_range&, ray_query);
template variant_output renderer_view<double>(const contract&, const root_pair<double>&, const ray_sphere<double>&,
                                              const t_range&, ray_query);

namespace {

template <class T>
renderer_outcome judge_for_renderer_in(const audit_target& target, const corpus_case& c, ray_query q,
                                       const exact_solution& exact, end_kind lower_end, end_kind upper_end) {
    renderer_outcome outcome;
    const ray_sphere<T> input = rounded_to<T>(c.geometry);
    const ray_sphere<double> widened = rounded_to<double>(input);
    const contract& promises = target.subject.promises;
    if (auto s = unscored(promises, exact, widened, target.prec)) {
        outcome.score = std::move(*s);
        return outcome;
    }
    const contract renderer = renderer_contract(q, lower_end, upper_end);
    outcome.range = range_for(renderer, c, target.prec);
    // The variant is asked as its contract says: an interval contract on the ray's interval.
    const t_range own_range = range_for(promises, c, target.prec);
    const root_pair<T> raw = run_in(target.subject, input, interval_in<T>(own_range));
    outcome.view = renderer_view(promises, raw, input, outcome.range, q);
    case_score s = judge_verdict(renderer, outcome.view, exact, outcome.range);
    if (s.verdict == verdict_kind::agree) {
        measure_hit_point(renderer, outcome.view, exact, outcome.range, widened, s);
    } else if (!s.cause) {
        // What the variant's own contract says of the same answer: agreement
        // there makes the renderer's disagreement the contract's design.
        variant_output own;
        own.roots = {raw.count, static_cast<double>(raw.t0), static_cast<double>(raw.t1)};
        const case_score own_score = judge_output(promises, own, exact, own_range, widened);
        if (!is_disagreement(own_score.verdict)) {
            const bool clamped = promises.inside == inside_rule::clamp &&
                                 expect_hit(promises, exact, own_range).what == expected_hit::kind::clamp;
            s.cause = clamped ? disagreement_cause::clamp : disagreement_cause::contract_semantics;
        } else {
            s.cause = own_score.cause;
        }
    }
    outcome.score = std::move(s);
    return outcome;
}

}  // namespace

renderer_outcome judge_for_renderer(const audit_target& target, const corpus_case& c, ray_query q,
                                    const exact_solution& exact, end_kind lower_end, end_kind upper_end) {
    const case_in_progress announced(c);  // named by a plugin that crashes or hangs on it
    return target.prec == precision::binary32 ? judge_for_renderer_in<float>(target, c, q, exact, lower_end, upper_end)
                                              : judge_for_renderer_in<double>(target, c, q, exact, lower_end, upper_end);
}

// ---- Descriptions ------------------------------------------------------------------

std::string describe_exact(const exact_solution& exact) {
    if (exact.cls == line_class::miss) return "exact: miss";
    if (exact.cls == line_class::tangent) return fmt::format("exact: tangent at t* ≈ {}", exact.near_root.rounded);
    return fmt::format("exact: two roots t* ≈ {}, {}", exact.near_root.rounded, exact.far_root.rounded);
}

std::string describe_expected(const contract& promises, const exact_solution& exact, const t_range& range) {
    if (promises.query == query_kind::line_roots) return describe_exact(exact);
    const expected_hit want = expect_hit(promises, exact, range);
    const std::string where = format_range(range);
    switch (want.what) {
        case expected_hit::kind::none: return fmt::format("{}; no hit in {}", describe_exact(exact), where);
        case expected_hit::kind::clamp:
            return fmt::format("{}; starts inside {}: clamped to t = {}", describe_exact(exact), where, want.value);
        case expected_hit::kind::root:
            return fmt::format("{}; nearest hit in {}: the {} root t* ≈ {}", describe_exact(exact), where,
                               root_word(want.root), want.value);
    }
    return describe_exact(exact);
}

}  // namespace rayverify
