// The judge: one variant's answer on one case against the exact answer, under
// the variant's contract (core/contract.h). The only place verdicts are made:
// corpus audits, scenes (per sphere, composed in scene/scene_audit), the
// hunter, explain and plugins all call it. Every decision is exact: which
// roots lie in a range is decided by exact comparison with its bounds
// (exact_solution::compare_to_root), which root a returned t stands for by its
// side of the exact midpoint −b′/a (compare_to_midpoint), the unit-direction
// assumption by the exact |d|² (compare_squared_length). Rounded values only
// appear where a rounded value is what is meant (RN(t*) as the best answer).
// Pure functions: no I/O, no state.
//
// Semantics, in one place:
// - The range. A variant answers on the range of t its contract names: a ray
//   contract on (0, +inf) or [0, +inf) (its lower end), an interval contract on
//   the case's (tmin, tmax) with its ends. For line_roots the range only says
//   what "in front" means (wrong_side and the hit point).
// - The expected answer of nearest_hit and any_hit (expected_hit): the nearest
//   exact root in the range; when the range starts strictly inside the sphere
//   (near root < start < far root) the contract's inside rule decides (the far
//   root, a clamped hit at the start, or a miss); faces=front drops the far
//   root; tangent=miss drops an exact tangent.
// - Which root a returned t stands for: its own when t = RN(t*) or t is the
//   exact midpoint (equidistant: the benefit of the doubt); otherwise the root
//   on t's side of the midpoint, decided exactly.
// - Non-finite values: NaN never agrees; ±inf agrees only where the
//   correctly rounded root is that infinity (its ULP error is not a number
//   and is left out of the figures).
// - Outputs beside t (contract::outputs): an agreeing answer whose claimed
//   interval for a t, or error bound for its hit point, leaves out the exact
//   value is unsound_bound (decided exactly; a point bound's ends p ∓ e are
//   rounded outward to double). The bound's width in ULPs, the hit point's
//   ULP error and the normal's angle to the exact normal are figures.
// - A point answer (answer=point) is judged through the t derived from the
//   point (parameter_of_point, core/intersection.h), and the point itself by
//   its ULP error per coordinate.
// - Errors in the scene's length scale, beside ULPs: |t − t*|·|d| over r and
//   over |o − c| (ULPs of t explode as t* → 0; these do not).
// - The renderer's view (scenes, interval queries): what a renderer computes
//   from the variant's answer — its values filtered into the ray's (tmin,
//   tmax) — judged against the nearest exact root in that interval. A
//   disagreement there that the variant's own contract explains (a clamped 0
//   with tmin > 0: a light leak) is reported with a by-design cause.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <variant>

#include "compare/conditioning.h"
#include "compare/scaled.h"
#include "core/contract.h"
#include "core/intersection.h"
#include "core/ray_sphere_case.h"
#include "core/recorded_answer.h"
#include "intersectors/registry.h"
#include "oracle/oracle.h"

namespace rayverify {

// ---- Vocabulary ---------------------------------------------------------------

// The verdict kinds, in report order. Each has a one-line meaning
// (verdict_meaning) that the docs and `explain` print.
enum class verdict_kind {
    agree,
    false_miss,          // exact: a hit (in the range); variant: none
    false_hit,           // exact: none; variant: a hit
    tangent_split,       // exact: tangent; variant: two distinct roots
    tangent_missed,      // exact: tangent (a hit); variant: miss
    false_tangent,       // exact: two roots distinct even after rounding; variant: one
    wrong_root,          // a returned t stands for another exact root than the one asked for
    imprecise,           // the right root on the right side, but farther from it than the contract's
                         // accuracy clause allows
    wrong_sphere,        // scene: both hit, but the variant's nearest sphere is not the exact nearest
    wrong_side,          // a returned t and the exact root it stands for lie on opposite sides of a range
                         // bound (the origin for line roots): a self-hit or a lost hit
    unsound_bound,       // the answer agrees, but an interval it claims for a t, or an error bound it
                         // claims for its hit point, does not contain the exact value
    non_finite,          // NaN, or an infinity that is not the correctly rounded root
    malformed_output,    // a hit count the contract does not allow, or roots out of order
    degenerate_hit,      // a degenerate cast that the contract's degenerate=miss asks to be a miss was not
    contract_violation,  // the case breaks the variant's assumption (not scored)
    invalid,             // the case is invalid at this precision (not scored)
};
inline constexpr int verdict_kind_count = static_cast<int>(verdict_kind::invalid) + 1;

std::string_view verdict_name(verdict_kind k);
std::optional<verdict_kind> verdict_from_name(std::string_view name);
std::string_view verdict_meaning(verdict_kind k);
// The short column heading of the summary tables, e.g. "f_miss".
std::string_view verdict_column(verdict_kind k);
// Neither agree nor one of the two kinds that are not scored.
bool is_disagreement(verdict_kind k);
// Agree or a disagreement: not contract_violation or invalid, which say the
// case is not one the variant can be held to.
bool is_scored(verdict_kind k);
// A wrong class: false miss or hit, tangent split or missed, false tangent.
bool is_misclassification(verdict_kind k);
// A verdict a corpus case can get (every kind but wrong_sphere, a scene's): a column of the corpus tables.
bool is_corpus_verdict(verdict_kind k);
// The colour of a ray with this verdict in a rendered scene (sRGB, 0–255).
std::array<std::uint8_t, 3> verdict_colour_rgb(verdict_kind k);
// Whether a scene's table for rays asking `q` has a column for this verdict.
bool scene_table_shows(verdict_kind k, ray_query q);

// Why a variant disagreed: rounding error (two kinds, told apart by the
// case's conditioning, compare/stability.h) or what the formula does by design
// (decided exactly: the formula's own idealisation, evaluated in exact
// arithmetic, fails the same way).
enum class disagreement_cause {
    conditioning_limited,  // rounding: the case is within the backward error of the other answer
    algorithmic,           // rounding (or a formula defect) that a backward-stable formula avoids
    clamp,                 // by design: the contract clamps t to the range start (origin inside), and the
                           // renderer's interval excludes that start (tmin > 0: a light leak)
    contract_semantics,    // by design: the contract answers another question than the renderer asks
                           // (inside is a miss, front faces only, a tangent is a miss, other range ends)
    unit_direction,        // by design: assumes |d| = 1; |d|² is within tolerance of 1 but not 1, and the
                           // formula with a = 1 gives this answer in exact arithmetic
    tangent_threshold,     // by design: reports a tangent whenever its discriminant is below an absolute
                           // threshold, and the exact discriminant is
    line_not_ray,          // by design: returns a root that lies outside its range exactly (it tests the
                           // line, not the ray)
};
inline constexpr int disagreement_cause_count = 7;

std::string_view cause_name(disagreement_cause c);
std::optional<disagreement_cause> cause_from_name(std::string_view name);
std::string_view cause_meaning(disagreement_cause c);
bool is_by_design(disagreement_cause c);
// How many of the disagreements counted per cause (indexed by disagreement_cause) are by design.
std::size_t by_design_count(const std::array<std::size_t, disagreement_cause_count>& causes);

// ---- Answers ------------------------------------------------------------------

// A variant's answer, widened to double (float values are exact in double),
// with the hit point o + t·d it implies, evaluated in the variant's own
// precision, for the value its contract makes the hit: line_roots, the first
// returned root in its range; nearest_hit, t0.
struct variant_output {
    root_pair<double> roots;
    std::optional<int> hit_root;              // 0 or 1: which value the hit point is for
    std::optional<vec3<double>> hit_point;    // the variant's own when it gives one (gives_hit_point)
    bool nan_seen = false;  // renderer_view: a NaN among the values the renderer looked at
    // What the variant gave beside t (contract::outputs), widened exactly: its
    // own outputs, or a recorded answer's (core/recorded_answer.h).
    std::optional<std::array<std::array<double, 2>, 2>> t_bounds;  // [root][lower, upper]
    std::optional<vec3<double>> point_error;
    std::optional<vec3<double>> normal;
};

// The exact answer to a nearest_hit or any_hit question.
struct expected_hit {
    enum class kind { none, root, clamp } what = kind::none;
    root_index root = root_index::near_root;  // what == root
    double value = 0;  // root: RN(t*) in the precision; clamp: the range start (exact)
    bool hit() const { return what != kind::none; }
};

// Does exact root i lie in the range (ends as the range says, infinite bounds
// by sign)? Exact. Requires cls != miss.
bool root_in_range(const exact_solution& exact, root_index i, const t_range& range);
// Does the range start strictly inside the sphere: near root < start < far root?
bool starts_inside(const exact_solution& exact, const t_range& range);
// The nearest exact root (or clamp) in the range under the contract (see above).
expected_hit expect_hit(const contract& promises, const exact_solution& exact, const t_range& range);
// Is t the side-preserving rounding of exact root i, the answer one step
// inside T's range for a root beyond it: ±denorm_min of T for a root t* ≠ 0
// whose RN(t*) is ±0 (robust_sphere.h returns +denorm_min for a positive
// root too small for T, so that it stays in front), ±max of T for a root
// whose RN(t*) is ±inf? Signs as t*'s.
bool side_preserving_rounding(const exact_solution& exact, root_index i, double t);
// Which exact root the finite value t stands for when root `wanted` is asked
// for: `wanted` when t is RN(t*), its side-preserving rounding, or the exact
// midpoint (equidistant: the benefit of the doubt); otherwise the root on
// t's side of the midpoint, decided exactly.
root_index stands_for(const exact_solution& exact, double t, root_index wanted);

// ---- Judging --------------------------------------------------------------------

// The upper bounds of a case_score's figures held as bounds
// (case_score::figure_upper_bounds). At namespace scope: nested in case_score,
// clang 14 would not construct it inside the class's own optional member.
struct case_figure_upper_bounds {
    double near_ulp = 0, far_ulp = 0, near_scaled_ulp = 0, hit_point_worst_ulp = 0, scale_error_radius = 0,
           scale_error_distance = 0;
    std::array<double, 3> hit_point_ulp{};  // per coordinate
};

struct case_score {
    verdict_kind verdict = verdict_kind::agree;
    std::optional<disagreement_cause> cause;  // set for every disagreement
    // One sentence a person can act on; empty for agree, and for a verdict
    // of the table's rows before imprecise (docs/verdicts.md) where it was
    // not asked for (figure_request::details).
    std::string detail;
    // Error of each returned root against the exact root it is judged against:
    // |t − t*| / ulp(t*) and Herbie bits log2(1 + ulps between t and RN(t*)).
    // Present when both exist and t is finite.
    std::optional<double> near_ulp, far_ulp, near_bits, far_bits;
    // |t| of a returned value judged against a root exactly at 0 (whose ulp
    // is the smallest subnormal, so its ULP error says little): the larger of
    // two. Set when the root errors are measured.
    std::optional<double> zero_root_error;
    // near_ulp, except that a near value judged against a root exactly at 0
    // is counted in ulps of r/|d| (the radius along the ray) instead of ulps
    // of 0: a figure a zero root cannot blow up (agree).
    std::optional<double> near_scaled_ulp;
    // Error of the hit point per coordinate, in ulps (agree, and a hit), and
    // the largest of the three (the figure tallied), set together.
    std::optional<std::array<double, 3>> hit_point_ulp;
    std::optional<double> hit_point_worst_ulp;
    // The largest of |t − t*|·|d|/r and of |t − t*|·|d|/|o − c| over the
    // returned roots (agree; finite t; each when its length is not 0): the
    // error in the scene's length scale.
    std::optional<double> scale_error_radius, scale_error_distance;
    // Outputs beside t (agree): the widest claimed t interval in ULPs of the
    // precision (representable values between its ends), and the angle in
    // radians between the returned normal and the exact one (either
    // orientation: the nearer of ±n*).
    std::optional<double> bound_ulp, normal_angle;
    // With the root errors asked bracketed (figure_request): bounds on the
    // largest of near_ulp and far_ulp (0 when no returned value has one),
    // which are then left empty, as are their bits.
    std::optional<figure_bracket> root_ulp_bracket;
    // With the figures asked to their printed digits (figure_request::
    // root_errors::to_printed_digits) and the answer agreeing: each figure
    // below may hold a lower bound on its exact value, from the oracle's
    // enclosures, and this its upper bound. Every value between the two
    // falls in one histogram bucket (bounds_in_one_bucket), so whatever counts
    // a figure by bucket reads the member; what prints a case's own figures
    // (per-case lines, the plot sample) or orders cases by one (the case that
    // holds a maximum, the farthest agreeing cases) asks for the exact figures
    // (exact_figures) where the bounds print apart (printed_as_exact) or leave
    // the order open. Empty where every figure is exact.
    using upper_bounds = case_figure_upper_bounds;
    std::optional<upper_bounds> figure_upper_bounds;
};

// What a judgement measures beside its verdict and cause, which it always
// decides (the outputs beside t too: they decide unsound_bound). The audit,
// scenes and explain take every figure, the default; the hunter asks only
// for the one its objective ranks by.
struct figure_request {
    enum class root_errors {
        none,
        exact,      // near_ulp, far_ulp and their bits, every digit right
        bracketed,  // root_ulp_bracket alone, from the oracle's enclosures (exact where they cannot bracket)
        // As exact, but where the filters settled the case an agreeing
        // answer's ULP, hit-point and scale figures are taken from the
        // oracle's enclosures where those fall in one histogram bucket
        // (case_score::figure_upper_bounds); what prints one checks that its
        // bounds print alike (printed_as_exact). The audit's way.
        to_printed_digits,
    };
    root_errors roots = root_errors::exact;
    bool hit_point = true;     // hit_point_ulp
    bool scale_errors = true;  // scale_error_radius, scale_error_distance
    // A disagreement's sentence (case_score::detail, whose verdict is decided
    // either way): per-case lines, explain, the hunter and the builds
    // comparison print it; an audit that prints none leaves it unformed for
    // the verdicts of the table's rows before imprecise (on far spheres,
    // where most formulas miss, formatting them was a seventh of an audit's
    // instructions), and a unit-direction breach's words. The rarer verdicts
    // decided with their sentence (imprecise, unsound_bound, degenerate_hit,
    // an invalid case, a ray case given to a segment target) keep it.
    bool details = true;
    static constexpr figure_request verdict_only() { return {root_errors::none, false, false}; }
    // The audit's: every figure, an agreeing answer's to its printed digits.
    static constexpr figure_request audit() { return {root_errors::to_printed_digits}; }
};

// The lengths of a case's input that the scale figures divide by, each as
// m·2^e, formed without overflow.
struct input_lengths {
    scaled direction;         // |d|
    scaled origin_to_centre;  // |o − c|
};

// What judging one case at one precision needs that no target changes,
// formed once and shared by every target judged on the case: the inputs as
// a variant in that precision receives them (widened to double), their
// exact answer, and, each on first use, the stability measures (the
// rounding cause of a disagreement; the audit keeps them for its stability
// tallies, plot sample and per-case lines), the input's lengths (the scale
// figures' and the accuracy clause's), the unit-direction assumption's
// check (|d|² against 1 ± 8ε and against 1) and the a = 1 idealisation of a
// unit-direction formula. It refers to `exact`, which must outlive it; it is
// not shared between threads.
class case_frame {
public:
    case_frame(const exact_solution& exact, const ray_sphere<double>& input) : exact_(exact), input_(input) {}
    case_frame(const case_frame&) = delete;
    case_frame& operator=(const case_frame&) = delete;

    const exact_solution& exact() const { return exact_; }
    const ray_sphere<double>& input() const { return input_; }
    precision prec() const { return exact_.prec; }
    const stability_measures& stability() const;
    // |d| and |o − c|, formed on first use: every agreeing answer's scale
    // errors, and an accuracy clause's figure, are measured against them.
    const input_lengths& lengths() const;
    // Whether the case breaks a unit-direction assumption at this precision
    // (breaches_unit_direction), and why (contract_breach's words), or
    // nullopt when |d|² is within 1 ± 8ε; each formed on first use.
    bool unit_direction_breached() const;
    const std::optional<std::string>& unit_direction_breach() const;
    // compare(|d|², 1), exactly.
    comparison squared_length_against_one() const;
    // The a = 1 idealisation (solve_exact_unit_direction) of the inputs, on
    // the route that solved the case.
    const exact_solution& unit_direction_design() const;

private:
    const exact_solution& exact_;
    ray_sphere<double> input_;
    mutable std::optional<stability_measures> stability_;
    mutable std::optional<input_lengths> lengths_;
    mutable std::optional<bool> unit_direction_breached_;
    mutable std::optional<std::optional<std::string>> unit_direction_breach_;
    mutable std::optional<comparison> squared_length_against_one_;
    mutable std::optional<exact_solution> unit_direction_design_;
};

// Judge `output` against the frame's exact answer (valid, at the precision
// the variant ran in) under `promises` on `range`; the frame's input is the
// case as the variant received it. Decides the verdict, measures the errors,
// and names the cause of a disagreement.
case_score judge_output(const contract& promises, const variant_output& output, const case_frame& frame,
                        const t_range& range, const figure_request& wanted = {});
// The same for one answer: `input` is the case as the variant received it,
// widened to double.
case_score judge_output(const contract& promises, const variant_output& output, const exact_solution& exact,
                        const t_range& range, const ray_sphere<double>& input);

// One variant in one precision, e.g. naive/float. A target with recorded
// answers (a results file, an external program's batch) takes each case's
// answer from them, looked up by the case's id, instead of running
// subject's functions (which it has none of); everything else about it —
// contract, verdicts, figures — is a variant's.
struct audit_target {
    variant subject;
    precision prec = precision::binary64;
    std::shared_ptr<const answer_book> recorded{};
    // A target answered from outside chunk by chunk (a --command program, an
    // engine's node, in an audit): called with each chunk's cases before any
    // of them is judged, it fills `recorded` with their answers, so that
    // memory holds one chunk's answers, never the input's. `finish_answers`,
    // after the last chunk, checks that nothing followed the last answer.
    std::function<void(std::span<const corpus_case>)> answer_chunk{};
    std::function<void()> finish_answers{};
    // "name/precision": label() whole, label_parts() in pieces (written
    // without building the string, as per-case lines do for every case).
    std::array<std::string_view, 3> label_parts() const { return {subject.name, "/", precision_name(prec)}; }
    std::string label() const {
        std::string out;
        for (std::string_view part : label_parts()) out += part;
        return out;
    }
};

// The target's whole answer on a case, in precision T: its function run on the
// inputs (an interval contract asked for `interval`), or the case's recorded
// answer with the outputs beside t it carries (count −1, judged malformed,
// when the book has none: callers check that every case has one before they
// judge).
template <class T>
answer<T> answer_of(const audit_target& target, const corpus_case& c, const ray_sphere<T>& input,
                       ray_interval<T> interval);

// Does the case satisfy the variant's assumptions at this precision? A unit
// direction means |d·d − 1| ≤ 8ε, decided exactly (ε of the precision).
std::optional<std::string> contract_breach(const contract& promises, const ray_sphere<double>& input,
                                           precision prec);
// The unit-direction assumption's check alone: whether |d|² lies outside
// [1 − 8ε, 1 + 8ε], decided exactly; and why, or nullopt (contract_breach of
// a unit-direction contract).
bool breaches_unit_direction(const ray_sphere<double>& input, precision prec);
std::optional<std::string> unit_direction_breach_of(const ray_sphere<double>& input, precision prec);

// The oracle's answer for a case at precision p: on the inputs rounded to p
// (a float target's exact answer is for its float inputs); invalid when the
// case is invalid at p (then the oracle never sees it). On the route asked
// for: the filtered oracle, or the reference route (the same answers).
exact_solution solve_case(const corpus_case& c, precision p, oracle_route route = oracle_route::filtered);

// The range a target answers on for a case: its contract's, with the case's
// tmin and tmax rounded to the target's precision (as the variant receives them).
// (Inline: formed in registers for every case and target; returned through
// memory, its fields stored apart and read back whole stalled the judge.)
inline t_range range_for(const contract& promises, const corpus_case& c, precision p) {
    t_range range = range_of(promises, c.tmin, c.tmax);
    if (p == precision::binary32) {  // the bounds as a float variant receives them (0 and +inf stay)
        range.lower = static_cast<double>(static_cast<float>(range.lower));
        range.upper = static_cast<double>(static_cast<float>(range.upper));
    }
    return range;
}

struct target_outcome {
    // Provided, so that a value-initialised outcome (the audit's
    // outcomes.emplace_back()) runs the members' initializers alone: with the
    // implicit constructor it was zeroed whole first, some 560 bytes per
    // target and case (every member has an initializer).
    target_outcome() {}
    case_score score;
    variant_output output;  // empty for invalid or contract-violating cases
    t_range range;          // the range the target answered on
};

// An answer computed ahead of judging (a batch call, variant::batch_*), for
// one target on one case; monostate: none, the variant is called.
using given_answer = std::variant<std::monostate, answer<float>, answer<double>>;

// What a target is run on for a case: the inputs rounded to its precision and
// the range its contract is asked on; nullopt when the case is not run
// (invalid at that precision, or outside the contract), as judge_target decides.
template <class T>
std::optional<batch_case<T>> run_input(const audit_target& target, const corpus_case& c);

// The whole judgement of one target on one case: invalid, outside the
// contract, or run and judged. `exact` is the oracle's answer at the target's
// precision (for float: on the float-rounded inputs). `given`, when set, is
// the target's answer on run_input, computed ahead; otherwise it is called.
// `wanted`: the figures measured (all, unless the caller, as the hunter,
// asks for fewer).
target_outcome judge_target(const audit_target& target, const corpus_case& c, const exact_solution& exact,
                            const given_answer& given = {}, const figure_request& wanted = {});
// An outcome judged to its printed digits (case_score::figure_upper_bounds)
// with every figure exact: its answer judged again, every figure measured to
// the last bit (the verdict is the same). `exact` as judge_target's.
case_score exact_figures(const audit_target& target, const corpus_case& c, const target_outcome& outcome,
                         const exact_solution& exact);
// The same with the case's frame at the target's precision (the audit judges
// every target of a case against one frame per precision).
target_outcome judge_target(const audit_target& target, const corpus_case& c, const case_frame& frame,
                            const given_answer& given = {}, const figure_request& wanted = {});
// The same into `outcome`, a fresh (default) one: the audit judges into its
// case's outcomes in place, where a returned outcome (about 400 bytes) was
// moved there on every judgement.
void judge_target_into(target_outcome& outcome, const audit_target& target, const corpus_case& c,
                       const case_frame& frame, const given_answer& given = {}, const figure_request& wanted = {});

// ---- The renderer's view ------------------------------------------------------

// The contract a renderer judges by: the query's answer on the ray's interval
// with the given ends, the far root from inside, both faces, a tangent a hit
// (both_roots: the line's roots, "in front" meaning past tmin).
contract renderer_contract(ray_query q, end_kind lower_end = end_kind::open, end_kind upper_end = end_kind::open);

// Can this variant answer this query for rays whose directions are (or are
// not) normalised? nullopt when it can; otherwise why not (a unit-direction
// variant on unnormalised rays, an any-hit variant asked for the nearest hit,
// a nearest-root variant asked for both roots).
std::optional<std::string> applicable(const variant& v, ray_query q, bool directions_normalised);

// The variant's answer as a renderer takes it: its values filtered into the
// ray's range (line_roots: the first of t0, t1 inside; nearest_hit: t0 when
// inside; any_hit: its count), in the shape of an answer to renderer_contract.
// A NaN among the values the renderer looks at is kept (it never agrees).
template <class T>
variant_output renderer_view(const contract& promises, const root_pair<T>& raw, const ray_sphere<T>& input,
                             const t_range& ray_range, ray_query q);

// The renderer's judgement of one target on one (ray, sphere) case for query
// q: the variant is asked as its contract says (an interval contract gets the
// ray's interval), its answer filtered as renderer_view, and judged under
// renderer_contract. A disagreement its own contract explains gets a
// by-design cause. `exact` as for judge_target.
struct renderer_outcome {
    case_score score;
    variant_output view;  // what the renderer took from the answer
    t_range range;        // the ray's range
};
renderer_outcome judge_for_renderer(const audit_target& target, const corpus_case& c, ray_query q,
                                    const exact_solution& exact, end_kind lower_end = end_kind::open,
                                    end_kind upper_end = end_kind::open);

// ---- Descriptions ---------------------------------------------------------------

// "two roots t* ≈ 4, 6", "tangent at t* ≈ 5", "miss": the exact answer in a detail.
std::string describe_exact(const exact_solution& exact);
// The exact answer a contract asks for, e.g. "nearest root in [0, +inf): far root 6".
std::string describe_expected(const contract& promises, const exact_solution& exact, const t_range& range);

}  // namespace rayverify
