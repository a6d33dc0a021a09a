#include "compare/judge.h"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <tuple>
#include <limits>
#include <utility>
#include <vector>

#include "compare/audit.h"
#include "compare/error_figures.h"
#include "core/case_in_progress.h"
#include "core/float_bits.h"

namespace rayverify {

// ---- Vocabulary ---------------------------------------------------------------

namespace {

// Which scene tables (by the ray's query) show a verdict as a column.
constexpr unsigned shown_for(std::initializer_list<ray_query> queries) {
    unsigned mask = 0;
    for (const ray_query q : queries) mask |= 1u << static_cast<unsigned>(q);
    return mask;
}
constexpr unsigned all_scene_queries = [] {
    unsigned mask = 0;
    for (const ray_query q : every_ray_query) mask |= shown_for({q});
    return mask;
}();
constexpr unsigned root_queries = shown_for({ray_query::nearest_hit, ray_query::both_roots, ray_query::hit_point_normal});
constexpr unsigned nearest_queries = shown_for({ray_query::nearest_hit, ray_query::hit_point_normal});

// Every fact about a verdict, in one row: its names, its meaning, whether it
// is scored and a disagreement, whether it is a wrong class, whether a corpus
// case can get it (wrong_sphere is a scene's), its colour in rendered scenes,
// and which scene tables show it. Every list of verdicts derives from this.
enum class scoring { agreement, disagreement, not_scored };

struct verdict_entry {
    verdict_kind kind;
    std::string_view name, column;
    scoring scored;
    bool misclassification;
    bool scene_only;
    std::array<std::uint8_t, 3> colour;
    unsigned scene_columns;
    std::string_view meaning;
};

constexpr verdict_entry verdict_table[verdict_kind_count] = {
    {verdict_kind::agree, "agree", "agree", scoring::agreement, false, false, {50, 50, 50}, all_scene_queries,
     "the answer the contract asks for, every root on the same side of every range bound"},
    {verdict_kind::false_miss, "false_miss", "f_miss", scoring::disagreement, true, false, {230, 30, 30}, all_scene_queries,
     "the exact answer is a hit (in the range); the variant reports none"},
    {verdict_kind::false_hit, "false_hit", "f_hit", scoring::disagreement, true, false, {40, 110, 255}, all_scene_queries,
     "the exact answer is no hit (in the range); the variant reports one"},
    {verdict_kind::tangent_split, "tangent_split", "t_split", scoring::disagreement, true, false, {255, 230, 0},
     shown_for({ray_query::both_roots}), "exactly tangent; the variant returns two distinct roots"},
    {verdict_kind::tangent_missed, "tangent_missed", "t_miss", scoring::disagreement, true, false, {150, 0, 40},
     all_scene_queries, "exactly tangent, a hit; the variant reports a miss"},
    {verdict_kind::false_tangent, "false_tangent", "f_tan", scoring::disagreement, true, false, {180, 170, 90},
     shown_for({ray_query::both_roots}), "two roots distinct even after rounding; the variant reports one (a tangent)"},
    {verdict_kind::wrong_root, "wrong_root", "w_root", scoring::disagreement, false, false, {255, 140, 0}, root_queries,
     "a returned t stands for another exact root than the one asked for (it is strictly nearer that root, by "
     "the exact midpoint −b′/a; a t at the midpoint counts as the root asked for)"},
    {verdict_kind::imprecise, "imprecise", "imprec", scoring::disagreement, false, false, {255, 200, 150}, root_queries,
     "a returned t stands for the root asked for, on the right side of every range bound, but lies farther from "
     "it than the contract's accuracy clause allows (accuracy=ulp:N, radius:x or distance:x; decided exactly)"},
    {verdict_kind::wrong_sphere, "wrong_sphere", "w_sph", scoring::disagreement, false, true, {40, 200, 40},
     nearest_queries, "both hit, but the variant's nearest sphere is not the exact nearest"},
    {verdict_kind::wrong_side, "wrong_side", "w_side", scoring::disagreement, false, false, {255, 0, 255}, root_queries,
     "a returned t and the exact root it stands for lie on opposite sides of a range bound (the origin for "
     "line roots): a self-hit or a lost hit"},
    {verdict_kind::unsound_bound, "unsound_bound", "unsnd", scoring::disagreement, false, false, {140, 60, 200}, 0,
     "the answer agrees, but an interval the variant claims for a t, or an error bound it claims for its hit "
     "point, does not contain the exact value"},
    {verdict_kind::non_finite, "non_finite", "nonfin", scoring::disagreement, false, false, {255, 255, 255},
     all_scene_queries,
     "NaN, or an infinity that is not the correctly rounded root (±inf agrees only where RN(t*) is that "
     "infinity)"},
    {verdict_kind::malformed_output, "malformed_output", "malf", scoring::disagreement, false, false, {0, 220, 220},
     all_scene_queries, "a hit count the contract does not allow, or roots out of order"},
    {verdict_kind::degenerate_hit, "degenerate_hit", "degen", scoring::disagreement, false, false, {255, 120, 200}, 0,
     "a degenerate cast (zero direction, non-finite input or bound, reversed interval) that the contract's "
     "degenerate=miss asks to be answered with a miss got a hit or a malformed count"},
    {verdict_kind::contract_violation, "contract_violation", "contract", scoring::not_scored, false, false, {90, 90, 90},
     0, "the case breaks the variant's stated assumption (a direction not within 8ε of unit length); not scored"},
    {verdict_kind::invalid, "invalid", "invalid", scoring::not_scored, false, false, {60, 60, 60}, 0,
     "the case is invalid at this precision (NaN or infinite input, d = 0, r < 0, overflow, bad interval); not "
     "scored"},
};

constexpr bool verdict_table_in_enum_order() {
    for (int k = 0; k < verdict_kind_count; ++k)
        if (static_cast<int>(verdict_table[k].kind) != k) return false;
    return true;
}
static_assert(verdict_table_in_enum_order(), "verdict_table lists every verdict once, in the enum's order");

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

bool is_disagreement(verdict_kind k) { return entry(k).scored == scoring::disagreement; }
bool is_scored(verdict_kind k) { return entry(k).scored != scoring::not_scored; }
bool is_misclassification(verdict_kind k) { return entry(k).misclassification; }
bool is_corpus_verdict(verdict_kind k) { return !entry(k).scene_only; }
std::array<std::uint8_t, 3> verdict_colour_rgb(verdict_kind k) { return entry(k).colour; }
bool scene_table_shows(verdict_kind k, ray_query q) { return (entry(k).scene_columns >> static_cast<unsigned>(q)) & 1u; }

std::string_view cause_name(disagreement_cause c) { return entry(c).name; }
std::string_view cause_meaning(disagreement_cause c) { return entry(c).meaning; }
bool is_by_design(disagreement_cause c) { return entry(c).by_design; }

std::size_t by_design_count(const std::array<std::size_t, disagreement_cause_count>& causes) {
    std::size_t n = 0;
    for (const cause_entry& e : cause_table)
        if (e.by_design) n += causes[static_cast<std::size_t>(e.cause)];
    return n;
}

std::optional<disagreement_cause> cause_from_name(std::string_view name) {
    for (const cause_entry& e : cause_table)
        if (e.name == name) return e.cause;
    return std::nullopt;
}

// ---- Exact facts under a contract ----------------------------------------------

bool root_in_range(const exact_solution& exact, root_index i, const t_range& range) {
    // compare(0, t*) is the root's exact sign, negated.
    const auto above_lower = [&] {
        if (std::isinf(range.lower)) return range.lower < 0;
        const comparison side =
            range.lower == 0 ? comparison_of_sign(-exact.root(i).sign) : exact.compare_to_root(range.lower, i);
        return side == comparison::smaller || (side == comparison::equal && range.lower_end == end_kind::closed);
    };
    const auto below_upper = [&] {
        if (std::isinf(range.upper)) return range.upper > 0;
        const comparison side = exact.compare_to_root(range.upper, i);
        return side == comparison::larger || (side == comparison::equal && range.upper_end == end_kind::closed);
    };
    return above_lower() && below_upper();
}

bool starts_inside(const exact_solution& exact, const t_range& range) {
    if (exact.cls != line_class::two_hit || std::isinf(range.lower)) return false;
    return exact.compare_to_root(range.lower, root_index::near_root) == comparison::larger &&
           exact.compare_to_root(range.lower, root_index::far_root) == comparison::smaller;
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

bool side_preserving_rounding(const exact_solution& exact, root_index i, double t) {
    const exact_root& root = exact.root(i);
    const auto [smallest, largest] = with_precision(exact.prec, []<class T>(std::type_identity<T>) {
        return std::pair<double, double>(std::numeric_limits<T>::denorm_min(), std::numeric_limits<T>::max());
    });
    if (root.rounded == 0 && root.sign != 0) return t == std::copysign(smallest, static_cast<double>(root.sign));
    if (std::isinf(root.rounded)) return t == std::copysign(largest, root.rounded);
    return false;
}

root_index stands_for(const exact_solution& exact, double t, root_index wanted) {
    if (exact.cls != line_class::two_hit || t == exact.root(wanted).rounded ||
        side_preserving_rounding(exact, wanted, t))
        return wanted;
    const comparison side = exact.compare_to_midpoint(t);
    if (side == comparison::equal) return wanted;  // equidistant: the benefit of the doubt
    return side == comparison::smaller ? root_index::near_root : root_index::far_root;
}

// ---- Running a variant ------------------------------------------------------------

template <class T>
answer<T> answer_of(const audit_target& target, const corpus_case& c, const ray_sphere<T>& input,
                    ray_interval<T> interval) {
    if (!target.recorded && target.subject.takes_segment_ends && c.is_segment()) {
        // A target that takes segment ends is asked with them: a port through
        // its own segment function, a plugin through its batch entry (which carries p1).
        const auto& [batch, from_ends] = [&]() {
            if constexpr (std::is_same_v<T, float>)
                return std::tie(target.subject.batch_float, target.subject.segment_answer_float);
            else
                return std::tie(target.subject.batch_double, target.subject.segment_answer_double);
        }();
        if (from_ends) return from_ends(input, segment_end_input<T>(c));
        const batch_case<T> asked{input, interval, segment_end_input<T>(c), true};
        answer<T> a{{-1, T(0), T(0)}};
        if (batch) batch(std::span<const batch_case<T>>(&asked, 1), std::span<answer<T>>(&a, 1));
        return a;
    }
    if (!target.recorded) return answer_in(target.subject, input, interval);
    const recorded_answer* r = target.recorded->find(c.id);
    if (!r) return {{-1, T(0), T(0)}};
    // Exact: a recorded answer in precision T holds values of T (the reader checks).
    answer<T> a;
    a.roots = {r->roots.count, static_cast<T>(r->roots.t0), static_cast<T>(r->roots.t1)};
    const std::optional<std::array<double, 2>>* bounds[2] = {&r->t0_bounds, &r->t1_bounds};
    for (int i = 0; i < 2; ++i)
        if (*bounds[i]) {
            a.t_lower[i] = static_cast<T>((**bounds[i])[0]);
            a.t_upper[i] = static_cast<T>((**bounds[i])[1]);
        }
    if (r->hit_point) a.point = vec3_cast<T>(*r->hit_point);
    if (r->normal) a.normal = vec3_cast<T>(*r->normal);
    // A point answer stands for the t derived from its point, as a built-in
    // point engine's or a plugin's does (a t written beside it is not judged).
    if (target.subject.promises.answer == answer_kind::point && r->hit_point)
        a.roots.t0 = a.roots.t1 = parameter_of_point(input, a.point);
    return a;
}

template answer<float> answer_of<float>(const audit_target&, const corpus_case&, const ray_sphere<float>&,
                                        ray_interval<float>);
template answer<double> answer_of<double>(const audit_target&, const corpus_case&, const ray_sphere<double>&,
                                          ray_interval<double>);

namespace {

// A whole answer as the judge takes it: widened, with the outputs beside t
// its contract names, and its hit point — the answer's own when the contract
// says it gives one, else o + t·d evaluated in T for the value the contract
// makes the hit (see variant_output). Written into `out`, an empty
// variant_output (a target_outcome's, as made): returned, it was zeroed and
// copied again for every case-target.
template <class T>
void widen_answer_into(variant_output& out, const contract& promises, const answer<T>& a,
                       const ray_sphere<T>& input, const t_range& range) {
    const root_pair<T>& r = a.roots;
    out.roots = {r.count, static_cast<double>(r.t0), static_cast<double>(r.t1)};
    if (r.count <= 0) return;
    switch (promises.query) {
        case query_kind::any_hit: return;
        case query_kind::nearest_hit: out.hit_root = 0; break;
        case query_kind::line_roots:
            if (range.contains(r.t0))
                out.hit_root = 0;
            else if (range.contains(r.t1))
                out.hit_root = 1;
            break;
    }
    const auto widened = [](vec3<T> p) { return vec3_cast<double>(p); };
    if (promises.outputs.t_bounds)
        out.t_bounds = {{{static_cast<double>(a.t_lower[0]), static_cast<double>(a.t_upper[0])},
                         {static_cast<double>(a.t_lower[1]), static_cast<double>(a.t_upper[1])}}};
    if (promises.outputs.normal) out.normal = widened(a.normal);
    if (!out.hit_root) return;
    if (gives_hit_point(promises)) {
        out.hit_point = widened(a.point);
        if (promises.outputs.point_error != point_bound::none) out.point_error = widened(a.point_error);
    } else {
        const T t = *out.hit_root == 0 ? r.t0 : r.t1;
        out.hit_point = widened(input.origin + t * input.direction);
    }
}

// A recorded answer's outputs beside t are judged as it gives them, answer by
// answer (a miss may leave them out): its bounds, its normal, and its own hit
// point in place of o + t·d. results_target checks that every hit
// carries what the contract names.
void add_recorded_outputs(variant_output& out, const recorded_answer* r) {
    if (!r || out.roots.count <= 0) return;
    if (r->t0_bounds && r->t1_bounds) out.t_bounds = {{*r->t0_bounds, *r->t1_bounds}};
    if (r->normal) out.normal = r->normal;
    if (out.hit_root && r->hit_point) out.hit_point = r->hit_point;
}

}  // namespace


// ---- Judging -------------------------------------------------------------------------

namespace {

double ulp_of_in(precision p, double x) {
    return with_precision(p, [&]<class T>(std::type_identity<T>) { return static_cast<double>(ulp_of(static_cast<T>(x))); });
}

// A figure as far as the audit reads it (figure_request::root_errors::
// to_printed_digits): the lower end of `bounds` where they lie in one
// histogram bucket (bounds_in_one_bucket), their upper end into `upper`
// (what prints the figure checks that the two print alike:
// printed_as_exact); else every_digit(), into both. Bounds from the
// oracle's enclosures cost a few operations; the figure to every digit,
// expansions (a fifth to a third of an audit of ordinary cases, by
// docs/oracle.md, most of it for digits nothing prints).
template <class EveryDigit>
double to_printed_digits(const std::optional<figure_bracket>& bounds, double& upper, EveryDigit every_digit) {
    if (bounds && bounds_in_one_bucket(bounds->lower, bounds->upper)) {
        upper = bounds->upper;
        return bounds->lower;
    }
    upper = every_digit();
    return upper;
}

// The error of a finite value against root i: ULPs of t* and Herbie bits.
// With `upper`, the ULP error to its printed digits (to_printed_digits).
void measure_root(const exact_solution& exact, root_index i, double value, std::optional<double>& ulp,
                  std::optional<double>& bits, double* upper = nullptr) {
    if (!std::isfinite(value)) return;
    if (upper)
        ulp = to_printed_digits(exact.root_ulp_error_bracket(i, value), *upper,
                                [&] { return exact.root_ulp_error(i, value); });
    else
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

void disagree(case_score& s, verdict_kind k, std::string detail) {
    s.verdict = k;
    s.detail = std::move(detail);
}

// Which side of the range a root and a value are on, and the verdict when
// they differ: an exact root outside with the value inside is a self-hit.
// A root whose correctly rounded value is an infinity or a zero (past the
// format's largest value, below its smallest) is answered best by that value,
// which is on the root's side whatever range it rounds out of.
std::optional<std::string> side_difference(const exact_solution& exact, root_index k, double t, const t_range& range) {
    const double rounded = exact.root(k).rounded;
    if ((std::isinf(rounded) || rounded == 0) && t == rounded && std::signbit(t) == std::signbit(rounded))
        return std::nullopt;
    const bool root_inside = root_in_range(exact, k, range), value_inside = range.contains(t);
    if (root_inside == value_inside) return std::nullopt;
    if (value_inside)
        return fmt::format("self-hit: t = {} stands for the {} root t* ≈ {}, which is outside {}", t, root_word(k),
                           exact.root(k).rounded, format_range(range));
    return fmt::format("lost hit: the {} root t* ≈ {} is in {}, the variant's t = {} is not", root_word(k),
                       exact.root(k).rounded, format_range(range), t);
}

// What each returned t is judged against: its slot (t0
// or t1) and the exact root, or the exact range start of a clamp.
struct judged_value {
    int slot = 0;
    std::optional<root_index> root;  // empty: a clamp to `start`
    double start = 0;
};

// At most two (line_roots), so kept in place.
struct judged_list {
    std::array<judged_value, 2> values{};
    std::size_t size = 0;
    const judged_value* begin() const { return values.data(); }
    const judged_value* end() const { return values.data() + size; }
};

// `want`: expect_hit's answer (nearest_hit; unused otherwise).
judged_list judged_values(query_kind query, const exact_solution& exact, const expected_hit& want) {
    switch (query) {
        case query_kind::any_hit: return {};
        case query_kind::line_roots:
            if (exact.cls == line_class::miss) return {};
            return {{{{0, root_index::near_root}, {1, root_index::far_root}}}, 2};
        case query_kind::nearest_hit: break;
    }
    if (want.what == expected_hit::kind::root) return {{{{0, want.root}}}, 1};
    if (want.what == expected_hit::kind::clamp) return {{{{0, std::nullopt, want.value}}}, 1};
    return {};
}

// The exact answer the contract asks for on the range: nothing for
// line_roots (every root is judged), expect_hit's for the other queries.
expected_hit expected_answer(const contract& promises, const exact_solution& exact, const t_range& range) {
    return promises.query == query_kind::line_roots ? expected_hit{} : expect_hit(promises, exact, range);
}

// Whether the contract expects a hit: line_roots a real root, the other
// queries expect_hit's answer (`want`).
bool hit_expected(const contract& promises, const exact_solution& exact, const expected_hit& want) {
    return promises.query == query_kind::line_roots ? exact.cls != line_class::miss : want.hit();
}

// The values an answer's t are judged by: none for a miss, or where no hit is expected.
judged_list judged_values_of(const contract& promises, const variant_output& out, const exact_solution& exact,
                             const expected_hit& want) {
    return out.roots.count > 0 && hit_expected(promises, exact, want) ? judged_values(promises.query, exact, want)
                                                                       : judged_list{};
}

// The root errors of the values judged (measure_root, measure_value), to
// every digit or, asked to_printed_digits, to their printed digits
// (case_score::figure_upper_bounds, set only where a value is judged). Only
// where the filters settled the case: where expansions had to (a tangent, an
// origin on the sphere), the answers' errors are mostly exactly 0 or need them
// too, and a bracket tried first would only add its cost.
void measure_root_errors(case_score& s, const judged_list& judged, const double (&t)[2], const exact_solution& exact,
                         figure_request::root_errors measure) {
    s.figure_upper_bounds.reset();
    if (measure == figure_request::root_errors::to_printed_digits && judged.size &&
        exact.stage == oracle_stage::filter)
        s.figure_upper_bounds.emplace();
    for (const judged_value& j : judged) {
        std::optional<double>& ulp = j.slot == 0 ? s.near_ulp : s.far_ulp;
        std::optional<double>& bits = j.slot == 0 ? s.near_bits : s.far_bits;
        double* upper = !s.figure_upper_bounds ? nullptr
                        : j.slot == 0          ? &s.figure_upper_bounds->near_ulp
                                               : &s.figure_upper_bounds->far_ulp;
        if (j.root) {
            measure_root(exact, *j.root, t[j.slot], ulp, bits, upper);
        } else {
            measure_value(exact.prec, j.start, t[j.slot], ulp, bits);
            if (upper && ulp) *upper = *ulp;
        }
    }
}

// The bracketed form of the root errors: bounds on the largest of the
// errors measure_root and measure_value give the judged values, each from
// the root's enclosure where it brackets it, else the error itself.
figure_bracket bracket_root_errors(const judged_list& judged, const double (&t)[2], const exact_solution& exact) {
    figure_bracket largest;
    for (const judged_value& j : judged) {
        const double value = t[j.slot];
        if (!std::isfinite(value)) continue;
        figure_bracket b;
        if (!j.root) {
            std::optional<double> ulp, bits;
            measure_value(exact.prec, j.start, value, ulp, bits);
            b = {*ulp, *ulp};
        } else if (const std::optional<figure_bracket> cheap = exact.root_ulp_error_bracket(*j.root, value)) {
            b = *cheap;
        } else {
            const double error = exact.root_ulp_error(*j.root, value);
            b = {error, error};
        }
        largest = {std::max(largest.lower, b.lower), std::max(largest.upper, b.upper)};
    }
    return largest;
}

// The verdict, as the one table in docs/verdicts.md reads, top to bottom: the
// first row whose condition holds is the verdict. Every query runs the same
// rows (a row that cannot apply to a query is skipped). `want` is
// expected_answer's. `measure` says how the root errors are measured (none:
// only the verdict is formed); a cause is set only where the verdict itself
// shows it (line_not_ray); `details`, whether a disagreement's sentence is
// formed (figure_request::details). It writes into `s`, the caller's fresh
// score: returned, a score (about 280 bytes) was moved on every judgement,
// 3% of an audit's instructions.
void judge_verdict(case_score& s, const contract& promises, const variant_output& out, const exact_solution& exact,
                   const t_range& range, const expected_hit& want,
                   figure_request::root_errors measure = figure_request::root_errors::exact, bool details = true) {
    const auto& r = out.roots;
    const query_kind query = promises.query;
    const bool line = query == query_kind::line_roots, any = query == query_kind::any_hit;
    // A disagreement, its sentence formed only when it is read (`details`).
    const auto fail = [&](verdict_kind k, const auto& sentence) {
        disagree(s, k, details ? sentence() : std::string());
    };
    const auto both = [&] {
        return (line ? describe_exact(exact) : describe_expected(promises, exact, range)) + "; " +
               describe_output(out, query);
    };
    // 1. malformed_output: a hit count the query does not allow.
    const int allowed = line ? 2 : 1;
    if (r.count < 0 || r.count > allowed)
        return fail(verdict_kind::malformed_output, [&] { return fmt::format("hit count {}", r.count); });
    // The values judged (line_roots: t0 and t1 whatever the count, t1 of a
    // reported tangent too; nearest_hit: t0) and what each is judged against.
    const int values = r.count == 0 || any ? 0 : (line ? 2 : 1);
    const double t[2] = {r.t0, r.t1};
    const judged_list judged = judged_values_of(promises, out, exact, want);
    if (measure == figure_request::root_errors::exact || measure == figure_request::root_errors::to_printed_digits)
        measure_root_errors(s, judged, t, exact, measure);
    if (measure == figure_request::root_errors::bracketed) s.root_ulp_bracket = bracket_root_errors(judged, t, exact);
    if (measure != figure_request::root_errors::none)
        for (const judged_value& j : judged)
            if (j.root && exact.root(*j.root).sign == 0 && std::isfinite(t[j.slot]))
                s.zero_root_error = std::max(s.zero_root_error.value_or(0.0), std::fabs(t[j.slot]));
    // 2. non_finite: a NaN among the values judged (any_hit: one the renderer looked at).
    for (int i = 0; i < values; ++i)
        if (std::isnan(t[i])) return fail(verdict_kind::non_finite, both);
    if (any && r.count == 1 && out.nan_seen) return fail(verdict_kind::non_finite, both);
    // 3. false_hit: no hit expected, one reported.
    if (!hit_expected(promises, exact, want)) {
        if (r.count == 0) return;
        // A t that stands for a root outside the range, itself outside it: the formula tests the line.
        if (query == query_kind::nearest_hit && exact.cls != line_class::miss && std::isfinite(r.t0) &&
            !root_in_range(exact, stands_for(exact, r.t0, root_index::near_root), range) && !range.contains(r.t0))
            s.cause = disagreement_cause::line_not_ray;
        return fail(verdict_kind::false_hit, both);
    }
    // 4, 5. tangent_missed, false_miss: a hit expected, none reported.
    if (r.count == 0)
        return fail(exact.cls == line_class::tangent ? verdict_kind::tangent_missed : verdict_kind::false_miss, both);
    if (any) return;
    // 6. non_finite: an infinity that is not the value it is judged against.
    for (const judged_value& j : judged) {
        const double want_value = j.root ? exact.root(*j.root).rounded : j.start;
        if (std::isinf(t[j.slot]) && t[j.slot] != want_value) return fail(verdict_kind::non_finite, both);
    }
    if (line) {
        // 7. malformed_output: roots out of order.
        if (t[0] > t[1])
            return fail(verdict_kind::malformed_output,
                        [&] { return "roots out of order: " + describe_output(out, query); });
        // 8. tangent_split: exactly tangent, two distinct roots.
        if (exact.cls == line_class::tangent && t[0] != t[1]) return fail(verdict_kind::tangent_split, both);
        // 9. false_tangent: two roots distinct after rounding, one reported
        // (two equal values that are the side-preserving rounding of both
        // roots, say +denorm_min for two positive roots below it, are two).
        const auto answers = [&](root_index k, double v) {
            return v == exact.root(k).rounded || side_preserving_rounding(exact, k, v);
        };
        const bool distinct_after_rounding = exact.near_root.rounded != exact.far_root.rounded;
        const bool one_value_for_both = r.count == 2 && t[0] == t[1] && answers(root_index::near_root, t[0]) &&
                                        answers(root_index::far_root, t[0]);
        if (exact.cls == line_class::two_hit && distinct_after_rounding && (r.count == 1 || t[0] == t[1]) &&
            !one_value_for_both)
            return fail(verdict_kind::false_tangent, both);
    }
    // Which exact root each t stands for: a clamp's range start stands for
    // itself; any other t of a clamp for the root on its side of the midpoint.
    struct stand {
        const judged_value* j;
        root_index root;
    };
    std::array<stand, 2> stands{};
    std::size_t standing = 0;
    for (const judged_value& j : judged) {
        if (!j.root && t[j.slot] == j.start) continue;
        stands[standing++] = {&j, stands_for(exact, t[j.slot], j.root.value_or(root_index::far_root))};
    }
    // 10. wrong_side: a t and the exact root it stands for on opposite sides of a range bound.
    for (std::size_t i = 0; i < standing; ++i)
        if (auto why = side_difference(exact, stands[i].root, t[stands[i].j->slot], range))
            return fail(verdict_kind::wrong_side, [&] { return std::move(*why); });
    // 11. wrong_root: a t stands for another root than the one asked for (a clamp: any t but the start).
    for (std::size_t i = 0; i < standing; ++i) {
        const judged_value& j = *stands[i].j;
        const root_index k = stands[i].root;
        const double value = t[j.slot];
        if (j.root && k == *j.root) continue;
        // Both outside the range: the formula returns a root its range excludes.
        if (!line && !root_in_range(exact, k, range) && (j.root || !range.contains(value)))
            s.cause = disagreement_cause::line_not_ray;
        if (line)
            return fail(verdict_kind::wrong_root, [&] {
                return fmt::format("t{} = {} stands for the {} root: {}", j.slot, value, root_word(k), both());
            });
        if (!j.root)
            return fail(verdict_kind::wrong_root, [&] {
                return fmt::format("t = {} stands for the {} root, where the contract clamps to {}: {}", value,
                                   root_word(k), j.start, both());
            });
        return fail(verdict_kind::wrong_root, [&] {
            return fmt::format("t = {} stands for the {} root: {}", value, root_word(k), both());
        });
    }
    // 12. imprecise is decided on the contract's accuracy clause (accuracy_shortfall); 13. unsound_bound on the
    // outputs beside t (measure_outputs); 14. agree.
}

// Hit point error of an agreeing answer: for the root that is the hit, when
// the variant's hit is that root.
// The exact point a variant's hit point is judged against: the root that is
// its hit (nearest_hit: the expected root; line_roots: the first exact root
// in the range, when the variant's hit is that one too), or the origin for a
// clamp to t = 0; none for any_hit, a miss, or a clamp to another start.
// An enum, so that it comes back in a register: an optional of a struct of
// an optional came back through the stack, written in pieces and read whole,
// a load that waited for the stores (two thirds of exact_hit_of's time).
enum class exact_hit { none, origin, near_root, far_root };

exact_hit hit_at(root_index i) { return i == root_index::near_root ? exact_hit::near_root : exact_hit::far_root; }

// The root an exact hit is at; nothing for none and the origin.
std::optional<root_index> root_of(exact_hit h) {
    if (h == exact_hit::near_root) return root_index::near_root;
    if (h == exact_hit::far_root) return root_index::far_root;
    return std::nullopt;
}

exact_hit exact_hit_of(const contract& promises, const variant_output& output, const exact_solution& exact,
                       const t_range& range, const expected_hit& want) {
    if (!output.hit_point || promises.query == query_kind::any_hit) return exact_hit::none;
    if (promises.query == query_kind::nearest_hit) {
        if (want.what == expected_hit::kind::clamp)  // o + tmin·d is not an exact point the oracle holds
            return want.value == 0 ? exact_hit::origin : exact_hit::none;
        if (want.what != expected_hit::kind::root) return exact_hit::none;
        return hit_at(want.root);
    }
    std::optional<root_index> first;
    for (root_index i : {root_index::near_root, root_index::far_root})
        if (root_in_range(exact, i, range)) {
            first = i;
            break;
        }
    if (!first || !output.hit_root || *output.hit_root != (*first == root_index::near_root ? 0 : 1)) return exact_hit::none;
    return hit_at(*first);
}

// Hit point error of an agreeing answer, per coordinate in ulps; with the
// score's upper bounds (case_score::figure_upper_bounds), each coordinate's
// and the largest to their printed digits (to_printed_digits).
void measure_hit_point(const contract& promises, const variant_output& output, const exact_solution& exact,
                       const t_range& range, const expected_hit& want, const ray_sphere<double>& input,
                       case_score& s) {
    const exact_hit hit = exact_hit_of(promises, output, exact, range, want);
    if (hit == exact_hit::none) return;
    const std::optional<root_index> root = root_of(hit);
    const vec3<double>& p = *output.hit_point;
    const auto every_digit = [&](int axis) {
        return root ? exact.hit_point_ulp_error(*root, axis, p[axis])
                    : std::fabs(p[axis] - input.origin[axis]) / ulp_of_in(exact.prec, input.origin[axis]);
    };
    std::array<double, 3> errors{}, uppers{};
    for (int axis = 0; axis < 3; ++axis) {
        if (s.figure_upper_bounds && root && std::isfinite(p[axis]))
            errors[axis] = to_printed_digits(exact.hit_point_ulp_error_bracket(*root, axis, p[axis]), uppers[axis],
                                             [&] { return every_digit(axis); });
        else
            errors[axis] = uppers[axis] = every_digit(axis);
    }
    double worst = std::max({errors[0], errors[1], errors[2]});
    const double worst_upper = std::max({uppers[0], uppers[1], uppers[2]});
    if (s.figure_upper_bounds) {
        // Each coordinate decided alone, their largest may still straddle a bucket's edge.
        if (!bounds_in_one_bucket(worst, worst_upper)) {
            for (int axis = 0; axis < 3; ++axis) errors[axis] = uppers[axis] = every_digit(axis);
            worst = std::max({errors[0], errors[1], errors[2]});
            s.figure_upper_bounds->hit_point_worst_ulp = worst;
        } else {
            s.figure_upper_bounds->hit_point_worst_ulp = worst_upper;
        }
        s.figure_upper_bounds->hit_point_ulp = uppers;
    }
    s.hit_point_ulp = errors;
    s.hit_point_worst_ulp = worst;
}

// ulp(t*) of the exact root as the oracle's ULP errors use it: RN(t*)'s,
// halved when t* lies below a power of two that it rounds up to.
double ulp_of_root(const exact_solution& exact, root_index i) {
    const double rounded = exact.root(i).rounded;
    const double ulp = ulp_of_in(exact.prec, rounded);
    int exponent = 0;
    const bool power_of_two = rounded != 0 && std::fabs(std::frexp(rounded, &exponent)) == 0.5;
    if (!power_of_two) return ulp;
    const bool rounded_away = exact.compare_to_root(rounded, i) == (rounded > 0 ? comparison::larger : comparison::smaller);
    return rounded_away && ulp > ulp_of_in(exact.prec, std::nextafter(rounded, 0.0)) ? ulp / 2 : ulp;
}

// Does the exact value lie in [lower, upper]? Infinite ends by sign; a NaN end never holds it.
// `compare_to_exact(x)` is compare(x, x*).
bool holds(double lower, double upper, const std::function<comparison(double)>& compare_to_exact) {
    if (std::isnan(lower) || std::isnan(upper)) return false;
    const bool above = std::isinf(lower) ? lower < 0 : compare_to_exact(lower) != comparison::larger;
    const bool below = std::isinf(upper) ? upper > 0 : compare_to_exact(upper) != comparison::smaller;
    return above && below;
}

// |a − b| for finite doubles, without overflow: halved first where either is
// that large (halving is exact there).
scaled distance_between(double a, double b) {
    const double huge = 0x1p1022;
    if (std::fabs(a) < huge && std::fabs(b) < huge) return scaled::of(a - b);
    scaled s = scaled::of(a / 2 - b / 2);
    if (s.m != 0) ++s.e;
    return s;
}

// The Euclidean length of v (finite components), scaled by the largest
// component's binade first so that neither the squares nor their sum leave
// the range; sqrt(4^k·x) = 2^k·sqrt(x) exactly.
scaled euclidean_length(const vec3<double>& v) {
    const double largest = std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
    if (largest == 0) return {};
    const int k = binade_of(largest);
    // Scaled by 2^−k: a product with a power of two rounds as ldexp does.
    const double scale = k >= -1023 ? exact_power_of_two(-k) : 0;
    const vec3<double> w = k >= -1023 ? vec3<double>{v.x * scale, v.y * scale, v.z * scale}
                                      : vec3<double>{std::ldexp(v.x, -k), std::ldexp(v.y, -k), std::ldexp(v.z, -k)};
    scaled s = scaled::of(std::sqrt(dot(w, w)));
    s.e += k;
    return s;
}

// |o − c| alike, each difference formed without overflow.
scaled origin_to_centre(const ray_sphere<double>& input) {
    const double huge = 0x1p1022;
    bool halve = false;
    for (int axis = 0; axis < 3; ++axis)
        halve = halve || std::fabs(input.origin[axis]) >= huge || std::fabs(input.centre[axis]) >= huge;
    const double h = halve ? 0.5 : 1.0;
    scaled s = euclidean_length({input.origin.x * h - input.centre.x * h, input.origin.y * h - input.centre.y * h,
                                 input.origin.z * h - input.centre.z * h});
    if (halve && s.m != 0) ++s.e;
    return s;
}

// |t − t*| for a finite t: |t| where t* is exactly 0; the ULP error times
// ulp(t*) (a power of two: the product kept as m·2^e); where the ULP error
// itself overflows (t beyond 2^1024 ulps of t*: |t − t*| > 2^−50), t − RN(t*),
// whose relative error is then below 2^−1000.
// `ulps`: the ULP error of t against root i, or a bound on it (the result
// then bounds |t − t*| alike).
scaled root_error_from_ulps(const exact_solution& exact, root_index i, double t, double ulps) {
    if (exact.root(i).sign == 0) return scaled::of(t);
    if (!std::isfinite(ulps)) return distance_between(t, exact.root(i).rounded);
    scaled s = scaled::of(ulps);
    s.e += binade_of(ulp_of_root(exact, i));
    return s;
}

scaled root_error(const exact_solution& exact, root_index i, double t) {
    return root_error_from_ulps(exact, i, t, exact.root(i).sign == 0 ? 0.0 : exact.root_ulp_error(i, t));
}

// The largest of the figures `measure` gives, over the values it gives one for.
// Written in place: an optional assigned whole was assembled on the stack
// from two stores and read back as one, a stall in the judge's figures.
void keep_max(std::optional<double>& figure, double x) {
    const double larger = std::max(figure.value_or(0), x);
    if (figure)
        *figure = larger;
    else
        figure.emplace(larger);
}

// An agreeing answer's error in the scene's length scale: |t − t*|·|d| over
// the radius and over |o − c|, the largest over the values judged (each
// where its length is not 0: a point sphere, an origin at the centre). None
// for a t* that rounds to an infinity (beyond the precision, no length to
// measure) or a non-finite t.
// They are written in the score in place (scale_error_radius,
// scale_error_distance): returned in a struct of optionals, they were
// assembled on the stack and read back whole, a stall in the judge's
// figures. Returned: their upper bounds (each the figure itself, to every
// digit; 0 where the figure is absent).
struct scale_error_uppers {
    double radius = 0, distance = 0;
};
// With the score's root errors to their printed digits (measure_root_errors,
// case_score::figure_upper_bounds), the scale errors are bounded alike, from
// those bounds; each to every digit where its bounds straddle a bucket's edge
// (agree_far_fraction is one: the agree-but-far count is the histogram's;
// the farthest agreeing cases, ranked by the radius figure, are judged again
// where they may enter that list, case_examples.h). `every_digit`: to every
// digit whatever the score holds.
scale_error_uppers measure_scale_errors(const judged_list& judged, const double (&t)[2], const exact_solution& exact,
                                        const ray_sphere<double>& input, const input_lengths& lengths, case_score& s,
                                        bool every_digit = false) {
    scale_error_uppers out;
    s.scale_error_radius.reset();
    s.scale_error_distance.reset();
    if (!judged.size) return out;
    const scaled& d_length = lengths.direction;
    const scaled& distance = lengths.origin_to_centre;
    const bool bounded = s.figure_upper_bounds && !every_digit;
    for (const judged_value& j : judged) {
        const double value = t[j.slot];
        if (!std::isfinite(value) || (j.root && !std::isfinite(exact.root(*j.root).rounded))) continue;
        // |t − t*|: ULPs of t* times ulp(t*), or |t| itself where t* is exactly 0 (no ulp to count in).
        scaled error;
        // Where the ULP error is bounded (kept to its printed digits), so is
        // each figure. With |t − t*| known within a factor 1 + 2^−24, each
        // figure is within a factor 1 + 2^−22 of its value at the lower
        // bound: the factor and the roundings between (a few, each 2^−53 at
        // most, the figures normal; a bucket is 2^−7 wide). Where the bounds
        // are wider (a root whose enclosure is wide, near a tangent), the
        // figure is formed again from the upper one: every step (a product,
        // a quotient, a rounding to double) is monotone, so a larger error
        // gives a figure no smaller, and the bounds hold the figure formed
        // from the exact ULP error.
        bool widened = false;
        std::optional<scaled> error_upper;
        const std::optional<double>& ulps = j.slot == 0 ? s.near_ulp : s.far_ulp;
        // The score's ULP error of this value is exact where no upper bound
        // stands beside it, or where the bound is the figure itself.
        const double* upper = !s.figure_upper_bounds ? nullptr
                              : j.slot == 0          ? &s.figure_upper_bounds->near_ulp
                                                     : &s.figure_upper_bounds->far_ulp;
        if (!j.root) {
            error = distance_between(value, j.start);
        } else if (bounded && upper && ulps && exact.root(*j.root).sign != 0) {
            if (!std::isfinite(*upper)) return measure_scale_errors(judged, t, exact, input, lengths, s, true);
            error = root_error_from_ulps(exact, *j.root, value, *ulps);
            if (*upper <= *ulps + *ulps * 0x1p-24)
                widened = *upper != *ulps;
            else
                error_upper = root_error_from_ulps(exact, *j.root, value, *upper);
        } else if (ulps && (!upper || *upper == *ulps)) {
            // measure_root_errors judged this value against this root (the
            // same list): its exact ULP error, not formed a second time.
            error = root_error_from_ulps(exact, *j.root, value, *ulps);
        } else {
            error = root_error(exact, *j.root, value);
        }
        // A figure's upper bound: `figure` itself, formed from `error`, and
        // `over` what it was divided by.
        const auto upper_of = [&](double figure, const scaled& over) {
            if (error_upper) return (*error_upper * d_length / over).value();
            if (!widened) return figure;
            return figure >= 0x1p-1000 && figure <= 0x1p1000 ? figure * (1 + 0x1p-22)
                                                             : std::numeric_limits<double>::infinity();
        };
        if (input.radius > 0) {
            const scaled radius_length = scaled::of(input.radius);
            const double radius = (error * d_length / radius_length).value();
            keep_max(s.scale_error_radius, radius);
            out.radius = std::max(out.radius, upper_of(radius, radius_length));
        }
        if (distance.m != 0) {
            const double along = (error * d_length / distance).value();
            keep_max(s.scale_error_distance, along);
            out.distance = std::max(out.distance, upper_of(along, distance));
        }
    }
    if (!bounded) return out;
    const bool radius_decided =
        !s.scale_error_radius || bounds_in_one_bucket(*s.scale_error_radius, out.radius);
    const bool distance_decided =
        !s.scale_error_distance || bounds_in_one_bucket(*s.scale_error_distance, out.distance);
    return radius_decided && distance_decided ? out : measure_scale_errors(judged, t, exact, input, lengths, s, true);
}

// 12. imprecise: why an agreeing answer misses the contract's accuracy
// clause (core/contract.h), or nullopt. Each finite value judged against a
// root (a clamp's start is exact or wrong) is compared with its root exactly:
// |t − t*| against N·ulp(t*), or |t − t*|·|d| against x·r or x. The detail
// gives the value's figure in the clause's unit (rounded: the decision is the
// exact comparison's).
std::optional<std::string> accuracy_shortfall(const contract& promises, const variant_output& output,
                                              const exact_solution& exact, const expected_hit& want,
                                              const case_frame& frame) {
    const ray_sphere<double>& input = frame.input();
    const accuracy_requirement& required = promises.accuracy;
    if (!required.required() || output.roots.count <= 0) return std::nullopt;
    const double t[2] = {output.roots.t0, output.roots.t1};
    for (const judged_value& j : judged_values(promises.query, exact, want)) {
        const double value = t[j.slot];
        if (!j.root || !std::isfinite(value)) continue;
        const root_index k = *j.root;
        comparison against = comparison::equal;
        std::string figure;
        switch (required.unit) {
            case accuracy_unit::none: continue;
            case accuracy_unit::ulp:
                against = exact.compare_root_ulp_error(k, value, required.bound);
                if (against == comparison::larger)
                    figure = format_figure(exact.root_ulp_error(k, value)) + " ulp";
                break;
            case accuracy_unit::radius:
            case accuracy_unit::distance: {
                const bool radii = required.unit == accuracy_unit::radius;
                against = exact.compare_root_distance(k, value, required.bound, radii ? input.radius : 1.0);
                if (against != comparison::larger) break;
                const scaled along = root_error(exact, k, value) * frame.lengths().direction;
                figure = radii ? format_figure((along / scaled::of(input.radius)).value()) + " r"
                               : format_figure(along.value());
                break;
            }
        }
        if (against != comparison::larger) continue;
        return fmt::format("t{} = {} stands for the {} root t* ≈ {} but lies {} from it, farther than "
                           "accuracy={} allows",
                           promises.query == query_kind::line_roots ? std::to_string(j.slot) : std::string(), value,
                           root_word(k), exact.root(k).rounded, figure, format_accuracy(required));
    }
    return std::nullopt;
}

// |t| in ulps of r/|d| (the radius measured along the ray, the length scale a
// formula works at) in precision p: the error of a value judged against a
// root exactly at 0, whose own ulp is the smallest subnormal. The ulp is that
// of the binade holding r/|d| (2^(max(E, emin) − p + 1) for 2^E ≤ r/|d| < 2^(E+1)).
double zero_root_error_in_radius_ulps(double t, const ray_sphere<double>& input, const input_lengths& lengths,
                                      precision p) {
    const scaled along = scaled::of(input.radius) / lengths.direction;
    if (along.m == 0 || !std::isfinite(along.m)) return std::numeric_limits<double>::infinity();
    int k = 0;
    std::frexp(along.m, &k);
    const int binade = along.e + k - 1;  // E above
    const int min_binade = with_precision(p, []<class T>(std::type_identity<T>) { return std::numeric_limits<T>::min_exponent - 1; });
    return (scaled::of(t) / scaled{1.0, std::max(binade, min_binade) - significand_bits(p) + 1}).value();
}

// The t bounds an answer gives beside its roots (outputs t_bounds): the
// widest in ULPs of the precision, and the first that leaves out the exact
// value it stands for, said in words.
struct t_bounds_check {
    std::optional<double> width_ulp;
    std::optional<std::string> unsound;
};
t_bounds_check check_t_bounds(const judged_list& judged, const variant_output& output, const exact_solution& exact) {
    t_bounds_check out;
    if (!output.t_bounds) return out;
    const double t[2] = {output.roots.t0, output.roots.t1};
    for (const judged_value& j : judged) {
        const double value = t[j.slot];
        if (!std::isfinite(value)) continue;
        const auto [lower, upper] = (*output.t_bounds)[static_cast<std::size_t>(j.slot)];
        const bool sound = holds(lower, upper, [&](double x) {
            return j.root ? exact.compare_to_root(x, *j.root) : compare(x, j.start);
        });
        keep_max(out.width_ulp, std::isfinite(lower) && std::isfinite(upper) && lower <= upper
                                    ? static_cast<double>(ulps_between_in(exact.prec, lower, upper))
                                    : std::numeric_limits<double>::infinity());
        if (!sound && !out.unsound)
            out.unsound = fmt::format("t{} = {} claims [{}, {}], which leaves out {}", j.slot, value, lower, upper,
                                      j.root ? fmt::format("the {} root t* ≈ {}", root_word(*j.root),
                                                           exact.root(*j.root).rounded)
                                             : fmt::format("the clamp t = {}", j.start));
    }
    return out;
}

// The hit point's error bound (outputs point_error): the box p ∓ e, its ends
// rounded outward to double, must hold the exact hit point, or under a
// point_error=surface contract some point of the sphere. What is wrong, in
// words, when it does not.
std::optional<std::string> check_point_bound(const contract& promises, const variant_output& output,
                                             const exact_solution& exact, root_index root,
                                             const ray_sphere<double>& input) {
    double lower[3], upper[3];
    std::optional<int> bad_axis;
    for (int axis = 2; axis >= 0; --axis) {
        const double p = (*output.hit_point)[axis], e = (*output.point_error)[axis];
        const dword low = two_sum(p, -e), high = two_sum(p, e);
        lower[axis] = low.l < 0 ? std::nextafter(low.h, -INFINITY) : low.h;
        upper[axis] = high.l > 0 ? std::nextafter(high.h, INFINITY) : high.h;
        if (!(e >= 0) || !std::isfinite(lower[axis]) || !std::isfinite(upper[axis])) bad_axis = axis;
    }
    const auto axis_text = [&](int axis) {
        return fmt::format("{} = {} ± {}", "xyz"[axis], (*output.hit_point)[axis], (*output.point_error)[axis]);
    };
    if (bad_axis) return fmt::format("hit point coordinate {} is no bound", axis_text(*bad_axis));
    if (promises.outputs.point_error == point_bound::surface) {
        if (!box_meets_sphere({lower[0], lower[1], lower[2]}, {upper[0], upper[1], upper[2]}, input.centre,
                              input.radius))
            return fmt::format("hit point ({}, {}, {}) holds no point of the sphere", axis_text(0), axis_text(1),
                               axis_text(2));
        return std::nullopt;
    }
    for (int axis = 0; axis < 3; ++axis)
        if (!holds(lower[axis], upper[axis], [&](double x) { return exact.compare_to_hit_coordinate(x, root, axis); }))
            return fmt::format("hit point coordinate {} leaves out p* ≈ {}", axis_text(axis),
                               exact.hit_coordinate_in_double(root, axis));
    return std::nullopt;
}

// The angle between the answer's normal and the exact normal's direction
// p* − c, from p* rounded to double (good to about 2^-53·|p*|/r radians);
// +inf for a normal of no direction or a NaN.
double normal_angle(const vec3<double>& normal, const exact_solution& exact, root_index root,
                    const ray_sphere<double>& input) {
    const auto exact_minus_centre = [&](int axis) {
        return static_cast<long double>(exact.hit_coordinate_in_double(root, axis)) - input.centre[axis];
    };
    const vec3<long double> n = vec3_cast<long double>(normal);
    const vec3<long double> m{exact_minus_centre(0), exact_minus_centre(1), exact_minus_centre(2)};
    const vec3<long double> cross{n.y * m.z - n.z * m.y, n.z * m.x - n.x * m.z, n.x * m.y - n.y * m.x};
    const long double along = std::fabs(dot(n, m)), across = std::sqrt(dot(cross, cross));
    const double angle = static_cast<double>(std::atan2(across, along));
    return std::isnan(angle) || (along == 0 && across == 0) ? std::numeric_limits<double>::infinity() : angle;
}

// An agreeing answer's outputs beside t (contract::outputs) measured, and,
// when asked, its error in the scene's length scale; where a bound it gives
// leaves out the exact value, what is wrong, in words (verdict row 12,
// unsound_bound).
std::optional<std::string> measure_outputs(const contract& promises, const variant_output& output,
                                           const case_frame& frame, const t_range& range, const expected_hit& want,
                                           bool with_scale_errors, case_score& s) {
    const exact_solution& exact = frame.exact();
    const ray_sphere<double>& input = frame.input();
    const judged_list judged = judged_values(promises.query, exact, want);
    const double t[2] = {output.roots.t0, output.roots.t1};
    case_score::upper_bounds* upper = s.figure_upper_bounds ? &*s.figure_upper_bounds : nullptr;
    s.near_scaled_ulp = s.near_ulp;
    if (upper) upper->near_scaled_ulp = upper->near_ulp;
    for (const judged_value& j : judged)
        if (j.slot == 0 && j.root && exact.root(*j.root).sign == 0 && s.near_ulp) {
            s.near_scaled_ulp = zero_root_error_in_radius_ulps(t[0], input, frame.lengths(), exact.prec);
            if (upper) upper->near_scaled_ulp = *s.near_scaled_ulp;
        }
    if (with_scale_errors) {
        const scale_error_uppers scale = measure_scale_errors(judged, t, exact, input, frame.lengths(), s);
        if (upper) {
            upper->scale_error_radius = scale.radius;
            upper->scale_error_distance = scale.distance;
        }
    }
    const t_bounds_check bounds = check_t_bounds(judged, output, exact);
    s.bound_ulp = bounds.width_ulp;
    std::optional<std::string> unsound = bounds.unsound;
    if (!output.point_error && !output.normal) return unsound;
    const std::optional<root_index> root = root_of(exact_hit_of(promises, output, exact, range, want));
    if (root && output.point_error && !unsound) unsound = check_point_bound(promises, output, exact, *root, input);
    if (root && output.normal) s.normal_angle = normal_angle(*output.normal, exact, *root, input);
    return unsound;
}

// A root within the backward error of an end of the range: relative input
// perturbations of γ·u move a root by up to γ·u·κ·|t| (conditioning.h), so
// a root that close to an end may lie on either side of it for a
// backward-stable formula. A root exactly at an end (a root exactly at 0 on a
// ray starting at 0: a self-hit) always is, whichever of the two roots it is.
bool root_at_range_end_within_backward_error(const case_frame& frame, const t_range& range) {
    const stability_measures& m = frame.stability();
    const exact_solution& exact = frame.exact();
    if (exact.cls == line_class::miss) return false;
    const double u = unit_roundoff(frame.prec());
    for (const root_index k : {root_index::near_root, root_index::far_root}) {
        const std::optional<double>& absolute_condition =
            k == root_index::near_root ? m.near_absolute_condition : m.far_absolute_condition;
        const exact_root& root = exact.root(k);
        for (const double end : {range.lower, range.upper}) {
            if (!std::isfinite(end)) continue;
            if (end == 0 && root.sign == 0) return true;
            if (absolute_condition && std::fabs(root.rounded - end) <= conditioning_gamma * u * *absolute_condition)
                return true;
        }
    }
    return false;
}

// The rounding cause: conditioning-limited when the case is within the
// backward error of the other answer (conditioning.h): a class verdict when the
// tangency margin is ≤ γ; a root or side verdict also when γ·u·κ ≥ 1; either
// when a root lies within its backward error of an end of the range (above).
// Non-finite and malformed outputs are always algorithmic.
disagreement_cause rounding_cause(verdict_kind k, const case_frame& frame, const t_range& range) {
    const stability_measures& m = frame.stability();
    if (!m.valid) return disagreement_cause::algorithmic;
    const bool ambiguous_class = m.tangency_margin <= conditioning_gamma;
    const auto limited_by = [](bool ambiguous) {
        return ambiguous ? disagreement_cause::conditioning_limited : disagreement_cause::algorithmic;
    };
    if (is_misclassification(k))
        return limited_by(ambiguous_class || root_at_range_end_within_backward_error(frame, range));
    if (k == verdict_kind::wrong_root || k == verdict_kind::wrong_side || k == verdict_kind::wrong_sphere ||
        k == verdict_kind::imprecise) {
        const double u = unit_roundoff(frame.prec());
        const bool ambiguous_root = m.near_condition && conditioning_gamma * u * *m.near_condition >= 1;
        return limited_by(ambiguous_class || ambiguous_root || root_at_range_end_within_backward_error(frame, range));
    }
    return disagreement_cause::algorithmic;
}

// Why the variant disagreed, by design before rounding.
disagreement_cause cause_of(const contract& promises, const variant_output& output, const case_frame& frame,
                            const t_range& range, verdict_kind k) {
    const bool unit_assumed_wrongly =
        promises.assumes_unit_direction && frame.squared_length_against_one() != comparison::equal;
    if (k == verdict_kind::false_tangent && promises.tangent_threshold) {
        const exact_solution& solved = promises.assumes_unit_direction ? frame.unit_direction_design() : frame.exact();
        if (solved.valid() && solved.compare_to_discriminant(*promises.tangent_threshold) != comparison::smaller)
            return disagreement_cause::tangent_threshold;
    }
    if (unit_assumed_wrongly) {
        const exact_solution& solved = frame.unit_direction_design();
        if (solved.valid()) {
            const expected_hit want = expected_answer(promises, solved, range);
            case_score designed;
            judge_verdict(designed, promises, output, solved, range, want, figure_request::root_errors::none, false);
            if (designed.verdict == verdict_kind::agree) return disagreement_cause::unit_direction;
        }
    }
    return rounding_cause(k, frame, range);
}

}  // namespace

const stability_measures& case_frame::stability() const {
    if (!stability_) stability_ = measure_stability(input_, exact_.prec, exact_);
    return *stability_;
}

const input_lengths& case_frame::lengths() const {
    if (!lengths_) lengths_ = input_lengths{euclidean_length(input_.direction), origin_to_centre(input_)};
    return *lengths_;
}

bool case_frame::unit_direction_breached() const {
    if (!unit_direction_breached_) unit_direction_breached_ = breaches_unit_direction(input_, exact_.prec);
    return *unit_direction_breached_;
}

const std::optional<std::string>& case_frame::unit_direction_breach() const {
    if (!unit_direction_breach_) unit_direction_breach_ = unit_direction_breach_of(input_, exact_.prec);
    return *unit_direction_breach_;
}

comparison case_frame::squared_length_against_one() const {
    if (!squared_length_against_one_) squared_length_against_one_ = compare_squared_length(input_.direction, 1.0);
    return *squared_length_against_one_;
}

const exact_solution& case_frame::unit_direction_design() const {
    if (!unit_direction_design_)
        unit_direction_design_ = exact_.route() == oracle_route::reference
                                     ? solve_exact_unit_direction_reference(input_, exact_.prec)
                                     : solve_exact_unit_direction(input_, exact_.prec);
    return *unit_direction_design_;
}

namespace {

// judge_output into `s`, a fresh score (judge_target_into's, in place).
void judge_output_into(case_score& s, const contract& promises, const variant_output& output, const case_frame& frame,
                       const t_range& range, const figure_request& wanted) {
    const exact_solution& exact = frame.exact();
    const expected_hit want = expected_answer(promises, exact, range);
    judge_verdict(s, promises, output, exact, range, want, wanted.roots, wanted.details);
    if (s.verdict == verdict_kind::agree)
        if (std::optional<std::string> shortfall = accuracy_shortfall(promises, output, exact, want, frame))
            disagree(s, verdict_kind::imprecise, std::move(*shortfall));
    if (s.verdict == verdict_kind::agree) {
        if (wanted.hit_point) measure_hit_point(promises, output, exact, range, want, frame.input(), s);
        const std::optional<std::string> unsound =
            measure_outputs(promises, output, frame, range, want, wanted.scale_errors, s);
        if (!unsound) return;
        disagree(s, verdict_kind::unsound_bound, *unsound);
    }
    // Only agreeing answers keep figures to their printed digits: the worst
    // disagreeing cases are ranked by their root errors, to every digit.
    if (s.figure_upper_bounds) {
        figure_request every_digit = wanted;
        every_digit.roots = figure_request::root_errors::exact;
        if (s.verdict == verdict_kind::unsound_bound) {  // measured as an agreeing answer's: judged again, rarely
            s = case_score{};
            return judge_output_into(s, promises, output, frame, range, every_digit);
        }
        const double t[2] = {output.roots.t0, output.roots.t1};
        measure_root_errors(s, judged_values_of(promises, output, exact, want), t, exact, every_digit.roots);
    }
    if (!s.cause) s.cause = cause_of(promises, output, frame, range, s.verdict);
}

}  // namespace

case_score judge_output(const contract& promises, const variant_output& output, const case_frame& frame,
                        const t_range& range, const figure_request& wanted) {
    case_score s;
    judge_output_into(s, promises, output, frame, range, wanted);
    return s;
}

case_score judge_output(const contract& promises, const variant_output& output, const exact_solution& exact,
                        const t_range& range, const ray_sphere<double>& input) {
    return judge_output(promises, output, case_frame(exact, input), range);
}

std::optional<std::string> contract_breach(const contract& promises, const ray_sphere<double>& input,
                                           precision prec) {
    if (!promises.assumes_unit_direction) return std::nullopt;
    return unit_direction_breach_of(input, prec);
}

namespace {

// A unit direction's tolerance, 8ε of the precision: 1 ± 8ε are both exact doubles.
double unit_direction_tolerance(precision prec) {
    return 8 * with_precision(prec, []<class T>(std::type_identity<T>) { return double(std::numeric_limits<T>::epsilon()); });
}

}  // namespace

bool breaches_unit_direction(const ray_sphere<double>& input, precision prec) {
    const double tolerance = unit_direction_tolerance(prec);
    return compare_squared_length(input.direction, 1 + tolerance) == comparison::larger ||
           compare_squared_length(input.direction, 1 - tolerance) == comparison::smaller;
}

std::optional<std::string> unit_direction_breach_of(const ray_sphere<double>& input, precision prec) {
    if (!breaches_unit_direction(input, prec)) return std::nullopt;
    const double tolerance = unit_direction_tolerance(prec);
    const comparison above = compare_squared_length(input.direction, 1 + tolerance);
    const double squared = dot(input.direction, input.direction);
    return fmt::format("assumes a unit direction, but |d|² ≈ {:.17g} is {} 1 {} 8ε (8ε = {:.3g})", squared,
                       above == comparison::larger ? "above" : "below", above == comparison::larger ? "+" : "−", tolerance);
}

exact_solution solve_case(const corpus_case& c, precision p, oracle_route route) {
    const invalid_reason reason = with_precision(p, [&]<class T>(std::type_identity<T>) { return case_validity<T>(c); });
    if (reason != invalid_reason::none) {
        exact_solution invalid;
        invalid.prec = p;
        invalid.invalid = reason;
        return invalid;
    }
    const ray_sphere<double> input = target_input(p, c);
    if (c.segment_end) {
        // The segment between the ends as the target receives them, its
        // direction their exact difference (not input.direction, rounded).
        const vec3<double> p1 = with_precision(
            p, [&]<class T>(std::type_identity<T>) { return vec3_cast<double>(segment_end_input<T>(c)); });
        return route == oracle_route::reference
                   ? solve_exact_segment_reference(input.origin, p1, input.centre, input.radius, p)
                   : solve_exact_segment(input.origin, p1, input.centre, input.radius, p);
    }
    const auto solve = [&](const std::optional<double>& tmin, const std::optional<double>& tmax) {
        return route == oracle_route::reference ? solve_exact_reference(input, p, tmin, tmax)
                                                : solve_exact(input, p, tmin, tmax);
    };
    // The case's range ends rounded to p. Where rounding leaves them as they
    // are (double inputs, or no end), the case's own are passed: an optional
    // formed on the stack was read back whole, a store-forwarding stall.
    if (p == precision::binary64 || (!c.tmin && !c.tmax)) return solve(c.tmin, c.tmax);
    const auto bound = [p](std::optional<double> t) -> std::optional<double> {
        return t ? std::optional<double>(rounded_to(p, *t)) : t;
    };
    return solve(bound(c.tmin), bound(c.tmax));
}

namespace {

template <class T>
ray_interval<T> interval_in(const t_range& range) {
    return {static_cast<T>(range.lower), static_cast<T>(range.upper)};
}

// A ray case handed to a target that takes segment end points (cast=segment):
// not its question, so neither run nor scored.
bool ray_case_for_segment_target(const contract& promises, const corpus_case& c) {
    return promises.takes_segment_ends && !c.is_segment();
}

// A case the target is handed although it has no exact answer: a
// degenerate cast under degenerate=miss.
bool runs_degenerate(const contract& promises, const exact_solution& exact) {
    return promises.degenerate_is_miss && degenerate_cast(exact.invalid);
}

// The verdict on a degenerate cast: a miss (count 0: the values beside it
// are unused, as for any miss) agrees; anything else is degenerate_hit, a
// defect of the formula's (no rounding explains a hit where there is no
// geometry).
case_score judge_degenerate(const variant_output& output, invalid_reason why) {
    case_score s;
    if (output.roots.count == 0) return s;
    s.cause = disagreement_cause::algorithmic;
    if (output.roots.count < 0)
        disagree(s, verdict_kind::degenerate_hit,
                 fmt::format("degenerate cast ({}): no answer (count {}), where degenerate=miss asks for a miss",
                             invalid_reason_name(why), output.roots.count));
    else
        disagree(s, verdict_kind::degenerate_hit,
                 fmt::format("degenerate cast ({}): answered count {}, t0 = {}, t1 = {}, where degenerate=miss "
                             "asks for a miss",
                             invalid_reason_name(why), output.roots.count, output.roots.t0, output.roots.t1));
    return s;
}

// Invalid or outside the contract: the outcome written into `score` (a
// default one), and true; else false, `score` untouched. Written in place:
// returned, the optional case_score (about 250 bytes, a string among them)
// was built, cleared and destroyed for every case-target, most of which it
// does not concern. A unit-direction breach's words are formed only where
// they are read (`details`, figure_request::details): they print |d|² to 17
// digits, and formatting them for every frame of near_tangent (half of its
// directions are not unit) was a twelfth of its audit's instructions.
bool judged_unscored(const contract& promises, const corpus_case& c, const case_frame& frame, case_score& score,
                     bool details = true) {
    const auto set = [&score](verdict_kind verdict, std::string detail) {
        score.verdict = verdict;
        score.detail = std::move(detail);
        return true;
    };
    if (ray_case_for_segment_target(promises, c))
        return set(verdict_kind::contract_violation,
                   "a ray case: this target takes a segment's end points (cast=segment) and runs on segment cases only");
    if (!frame.exact().valid() && !runs_degenerate(promises, frame.exact()))
        return set(verdict_kind::invalid, invalid_reason_name(frame.exact().invalid));
    if (!promises.assumes_unit_direction || !frame.unit_direction_breached()) return false;
    return set(verdict_kind::contract_violation, details ? *frame.unit_direction_breach() : std::string());
}

template <class T>
void judge_target_in(target_outcome& outcome, const audit_target& target, const corpus_case& c,
                     const case_frame& frame, const given_answer& given, const figure_request& wanted) {
    const contract& promises = target.subject.promises;
    if (judged_unscored(promises, c, frame, outcome.score, wanted.details)) return;
    const ray_sphere<T> input = target_input<T>(c);
    outcome.range = range_for(promises, c, target.prec);
    const answer<T>* ahead = std::get_if<answer<T>>(&given);
    const answer<T> given_answer = ahead ? *ahead : answer_of(target, c, input, interval_in<T>(outcome.range));
    if (runs_degenerate(promises, frame.exact())) {
        outcome.output.roots = {given_answer.roots.count, static_cast<double>(given_answer.roots.t0),
                                static_cast<double>(given_answer.roots.t1)};
        outcome.score = judge_degenerate(outcome.output, frame.exact().invalid);
        return;
    }
    widen_answer_into(outcome.output, promises, given_answer, input, outcome.range);
    if (target.recorded && !ahead) add_recorded_outputs(outcome.output, target.recorded->find(c.id));
    judge_output_into(outcome.score, promises, outcome.output, frame, outcome.range, wanted);
}

}  // namespace

void judge_target_into(target_outcome& outcome, const audit_target& target, const corpus_case& c,
                       const case_frame& frame, const given_answer& given, const figure_request& wanted) {
    with_precision(target.prec, [&]<class T>(std::type_identity<T>) {
        judge_target_in<T>(outcome, target, c, frame, given, wanted);
    });
}

target_outcome judge_target(const audit_target& target, const corpus_case& c, const case_frame& frame,
                            const given_answer& given, const figure_request& wanted) {
    target_outcome outcome;
    judge_target_into(outcome, target, c, frame, given, wanted);
    return outcome;
}

target_outcome judge_target(const audit_target& target, const corpus_case& c, const exact_solution& exact,
                            const given_answer& given, const figure_request& wanted) {
    return judge_target(target, c, case_frame(exact, target_input(target.prec, c)), given, wanted);
}

case_score exact_figures(const audit_target& target, const corpus_case& c, const target_outcome& outcome,
                         const exact_solution& exact) {
    const case_frame frame(exact, target_input(target.prec, c));
    figure_request every_digit;
    every_digit.details = false;
    case_score s;
    judge_output_into(s, target.subject.promises, outcome.output, frame, outcome.range, every_digit);
    return s;
}

template <class T>
std::optional<batch_case<T>> run_input(const audit_target& target, const corpus_case& c) {
    if (ray_case_for_segment_target(target.subject.promises, c)) return std::nullopt;
    const t_range range = range_for(target.subject.promises, c, target.prec);
    const ray_sphere<T> input = target_input<T>(c);
    // A segment case reaches a target that takes segment ends with them; any other target gets its ray form.
    const bool with_ends = c.is_segment() && target.subject.takes_segment_ends;
    const vec3<T> segment_end = with_ends ? segment_end_input<T>(c) : vec3<T>{};
    const invalid_reason reason = case_validity<T>(c);
    const auto bound_invalid = [](std::optional<double> t) { return t && std::isnan(*t); };
    const bool bad_interval =
        bound_invalid(c.tmin) || bound_invalid(c.tmax) || (c.tmin && c.tmax && *c.tmin > *c.tmax);
    if (reason != invalid_reason::none || bad_interval) {
        // Handed over only as a degenerate cast, as judge_target_in decides
        // from the oracle's reason (validity's first, then the interval's).
        const invalid_reason why = reason != invalid_reason::none ? reason : invalid_reason::bad_interval;
        if (target.subject.promises.degenerate_is_miss && degenerate_cast(why))
            return batch_case<T>{input, interval_in<T>(range), segment_end, with_ends};
        return std::nullopt;
    }
    // Whether the contract is breached, not why: no sentence formed for a case not run.
    if (target.subject.promises.assumes_unit_direction && breaches_unit_direction(rounded_to<double>(input), target.prec))
        return std::nullopt;
    return batch_case<T>{input, interval_in<T>(range), segment_end, with_ends};
}

template std::optional<batch_case<float>> run_input<float>(const audit_target&, const corpus_case&);
template std::optional<batch_case<double>> run_input<double>(const audit_target&, const corpus_case&);

// ---- The renderer's view --------------------------------------------------------

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
    const ray_sphere<T> input = target_input<T>(c);
    const case_frame frame(exact, rounded_to<double>(input));
    const contract& promises = target.subject.promises;
    if (judged_unscored(promises, c, frame, outcome.score)) return outcome;
    contract renderer = renderer_contract(q, lower_end, upper_end);
    renderer.accuracy = q == ray_query::any_hit ? accuracy_requirement{} : promises.accuracy;
    outcome.range = range_for(renderer, c, target.prec);
    // The variant is asked as its contract says: an interval contract on the ray's interval.
    const t_range own_range = range_for(promises, c, target.prec);
    const root_pair<T> raw = answer_of(target, c, input, interval_in<T>(own_range)).roots;
    outcome.view = renderer_view(promises, raw, input, outcome.range, q);
    const expected_hit want = expected_answer(renderer, exact, outcome.range);
    case_score s;
    judge_verdict(s, renderer, outcome.view, exact, outcome.range, want);
    if (s.verdict == verdict_kind::agree)
        if (std::optional<std::string> shortfall = accuracy_shortfall(renderer, outcome.view, exact, want, frame))
            disagree(s, verdict_kind::imprecise, std::move(*shortfall));
    if (s.verdict == verdict_kind::agree) {
        measure_hit_point(renderer, outcome.view, exact, outcome.range, want, frame.input(), s);
    } else if (!s.cause) {
        // What the variant's own contract says of the same answer: agreement
        // there makes the renderer's disagreement the contract's design.
        variant_output own;
        own.roots = {raw.count, static_cast<double>(raw.t0), static_cast<double>(raw.t1)};
        const case_score own_score = judge_output(promises, own, frame, own_range);
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
    return with_precision(target.prec, [&]<class T>(std::type_identity<T>) {
        return judge_for_renderer_in<T>(target, c, q, exact, lower_end, upper_end);
    });
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
