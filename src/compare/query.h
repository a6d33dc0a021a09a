// Judging a variant on the one question a renderer asks of a ray: any hit in
// the ray's interval, the nearest hit in it, both roots, or the nearest hit's
// point. A renderer uses only that answer, so only that answer is judged: a
// shadow ray's wrong far root does not matter, a false miss does.
//
// Every query is asked on the ray's open interval (tmin, tmax) (a case
// without one: (0, +inf); see ray_interval). Any variant whose kind is
// line_roots answers every query by filtering its roots into the interval, as
// a renderer would: the first of t0, t1 inside it is the nearest hit. A
// nearest_on_ray variant answers with its t0 when it is inside. The exact
// side is decided exactly: which exact roots lie in the open interval comes
// from exact comparisons of the roots with the bounds (exact_root_in), not
// from rounded roots. Pure functions: no I/O, no state.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "compare/verdict.h"
#include "core/intersection.h"
#include "core/ray_sphere_case.h"
#include "intersectors/registry.h"
#include "oracle/oracle.h"

namespace rayverify {

const char* ray_query_name(ray_query q);

// The verdict on one query, in report order.
enum class query_outcome {
    correct,             // the answer the query needs is right (roots: the right root; errors measured)
    false_hit,           // no exact root in the interval (both_roots: the line misses); the variant reports one
    false_miss,          // an exact root is in the interval (both_roots: the line hits); the variant reports none
    wrong_root,          // a returned root is nearer another exact root than the one the query wants
    non_finite,          // NaN or infinity where the wanted exact root is finite
    malformed_output,    // a count the variant's contract does not allow, roots out of order, or a
                         // nearest_in_interval root outside the interval
    contract_violation,  // the case breaks the variant's assumption (a non-unit direction); not scored
    invalid,             // the case is invalid at this precision; not scored
};
inline constexpr int query_outcome_count = 8;

std::string_view query_outcome_name(query_outcome o);
// A misclassification: false_hit or false_miss.
bool is_misclassification(query_outcome o);
// Scored and not correct.
bool is_query_failure(query_outcome o);

struct query_verdict {
    query_outcome outcome = query_outcome::correct;
    std::string detail;         // one sentence naming the exact and the variant's answer; empty when correct
    bool exact_hit = false;     // an exact root in the interval (both_roots: the line meets the sphere)
    bool variant_hit = false;   // the variant's answer, filtered into the interval as a renderer would
    // |t − t*| / ulp(t*) (exact, in the precision), present when both hit and t is finite:
    // nearest_hit and hit_point_normal: the nearest root in the interval; both_roots: near root.
    std::optional<double> nearest_ulp;
    std::optional<double> far_ulp;        // both_roots: the far root
    std::optional<double> hit_point_ulp;  // hit_point_normal: largest of the three coordinates of
                                          // o + t·d (computed in the variant's precision), when correct
};

// Can this variant answer this query for a scene whose directions are (or are
// not) normalised? nullopt when it can; otherwise the reason, e.g. a unit-
// direction variant on unnormalised rays, an any-hit variant asked for the
// nearest hit, a nearest-root variant asked for both roots.
std::optional<std::string> applicable(const variant& v, ray_query q, bool directions_normalised);

// The interval a case is asked on, at precision p: the case's tmin and tmax
// (rounded to float for float, as the variant receives them), each defaulting
// to (0, +inf) when absent.
ray_interval<double> interval_of(const corpus_case& c, precision p);

// Run `v` in precision `p` on `c` (inputs rounded to p) for query `q` and
// judge its answer. `exact` must be the oracle's answer for the same rounded
// inputs at precision p (solve_exact on rounded_to<double>(rounded_to<float>(...))
// for float); its own interval, if any, is not used. A variant that cannot
// answer q (applicable) is judged anyway: check applicable first.
query_verdict judge_query(const variant& v, precision p, const corpus_case& c, ray_query q,
                          const exact_solution& exact);

// What a renderer takes from a variant's answer: hit or not, and the roots it
// uses, in double (float values are exact). Exposed for tests and timing.
struct query_answer {
    int count = 0;                    // the variant's own count (for malformed_output)
    bool hit = false;                 // the filtered answer
    std::optional<double> nearest;    // nearest root in the interval (not for any-hit variants)
    std::optional<double> t0, t1;     // both_roots: the line's roots as returned
    std::optional<vec3<double>> hit_point;  // o + nearest·d in the variant's precision
    bool examined_non_finite = false;  // a root the filter looked at is NaN or infinite
};

template <class T>
query_answer answer_query(const variant& v, const ray_sphere<T>& input, ray_interval<T> interval, ray_query q);

// Judge an answer (from answer_query) on `exact`, for the variant's contract.
query_verdict judge_answer(const contract& promises, const query_answer& answer, const exact_solution& exact,
                           ray_interval<double> interval, ray_query q);

}  // namespace rayverify
