// What an intersector promises: which question it answers, on which range of
// t, with which semantics at the ends of the range, inside the sphere and at
// a tangent; and what it assumes of its inputs. One set of contract semantics
// for every judge (corpus audits, scenes, plugins, the hunter, results files):
// the exact answer a variant is judged against is computed from its contract
// (compare/judge.h), never from a judge's own convention.
//
// Every enum has one strict name table: an unknown name is an error, never a
// default. A contract is written as a spec, e.g.
//   query=nearest_hit,range=ray,ends=[),inside=clamp,tangent=hit,faces=both,unit_direction=yes
// (format_contract / parse_contract), which `variants` and `explain` print.
// Optional outputs (t_bounds, hit_point, point_error, normal) and a point
// answer appear in the spec only when a variant gives them.
#pragma once

#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <string_view>

namespace rayverify {

// Which answer the intersector gives.
enum class query_kind {
    // Both roots of the line o + t·d (t of any sign), ordered t0 ≤ t1.
    // count: 0 miss, 1 tangent reported, 2 two roots. Whatever the count, t0
    // and t1 are the variant's near and far roots and both are judged.
    line_roots,
    // The nearest hit in the variant's range of t (see range_source): count 0
    // (none) or 1 with the distance in t0.
    nearest_hit,
    // Whether some hit lies in the variant's range: count 0 or 1; roots unused.
    any_hit,
};

// Where the range of t comes from.
enum class range_source {
    ray,        // a fixed range: from 0 to +inf (line_roots: only what "in front" means)
    interval,   // the ray's own (tmin, tmax), passed to the variant; (0, +inf) when a case has none
    tmax_only,  // from 0 (fixed: the variant has no tmin) to the ray's tmax, passed to the variant
                // (Mitsuba 3's maxt); +inf when a case has none
    segment,    // the ray's range as a segment: the variant gets from = o + tmin·d and to = o + tmax·d
                // (or o and the direction times the segment's length), and answers on it; judged on
                // (tmin, tmax) like an interval. A case without tmax gets segment_length(): a
                // segment past every root (see there)
};

// What a variant's answer is: distances t along the ray, or a hit point
// (three.js, raylib, Godot), whose t is derived (parameter_of_point in
// core/intersection.h) and judged like a returned t, and whose coordinates
// are judged as a point.
enum class answer_kind { t, point };

// What an error bound per coordinate of the hit point claims to hold (spec
// names no, yes, surface): nothing (none); the exact hit point o + t*·d (hit);
// some point of the exact sphere (surface): pbrt-v4's bound after
// reprojection, γ₅·|p|, bounds the distance to the surface, which is what its
// spawned rays need, not the distance along the ray to o + t*·d.
enum class point_bound { none, hit, surface };

// What a variant hands over beside t, each checked against the exact answer
// when given: a conservative interval for each returned t (pbrt-v4's
// Interval), the hit point it computes (reprojected or not), an absolute
// error bound per coordinate of that point, and the normal there (any length).
struct output_set {
    bool t_bounds = false;
    bool hit_point = false;
    point_bound point_error = point_bound::none;  // requires hit_point
    bool normal = false;
    constexpr bool any() const { return t_bounds || hit_point || point_error != point_bound::none || normal; }
};

// Whether a range end belongs to the range: open (t > tmin) or closed (t ≥ tmin).
enum class end_kind { open, closed };

// What a nearest_hit or any_hit variant answers when its range starts inside
// the sphere (near root < range start < far root).
enum class inside_rule {
    far_root,  // the far root, the next root in the range (a ray leaving the sphere)
    clamp,     // a hit at the range start itself (t = 0 for a ray): "the origin is inside"
    miss,      // no hit
};

// An accuracy the user requires of an answer (the accuracy clause): a
// returned t that stands for the right root on the right side of every range
// bound but lies farther from it than this is a disagreement, `imprecise`
// (compare/judge.h), decided exactly. Spec `accuracy=UNIT:BOUND`:
//   ulp:N        |t − t*| ≤ N·ulp(t*) in the target's precision (root_ulp_error)
//   radius:x     |t − t*|·|d| ≤ x·r, the error along the ray in radii (scale_error_radius)
//   distance:x   |t − t*|·|d| ≤ x, in the case's units
// A value judged against a clamp's range start (inside=clamp) is exact or
// wrong, so the clause does not apply to it; an any_hit contract returns no t.
enum class accuracy_unit { none, ulp, radius, distance };

struct accuracy_requirement {
    accuracy_unit unit = accuracy_unit::none;
    double bound = 0;  // finite, ≥ 0
    constexpr bool required() const { return unit != accuracy_unit::none; }
};

std::string_view accuracy_unit_name(accuracy_unit u);
// "radius:0.001"; "none" when nothing is required.
std::string format_accuracy(const accuracy_requirement& a);
// Parse "UNIT:BOUND" or "none"; throws std::invalid_argument naming the clause
// (an unknown unit, a bound that is negative, NaN, infinite or not a number).
accuracy_requirement parse_accuracy(std::string_view text);

struct contract {
    query_kind query = query_kind::line_roots;
    range_source range = range_source::ray;
    end_kind lower_end = end_kind::open;  // at tmin (0 for a ray)
    end_kind upper_end = end_kind::open;  // at tmax (+inf for a ray)
    inside_rule inside = inside_rule::far_root;
    bool tangent_is_hit = true;     // nearest_hit/any_hit: an exactly tangent line touching the range is a hit
    bool front_faces_only = false;  // nearest_hit/any_hit: only the near root (entering the sphere) counts
    // Assumptions (how the formula approximates; a case may break them):
    bool assumes_unit_direction = false;  // a = d·d is taken to be 1 (|d|² within 8ε of 1, else not scored)
    // line_roots: may return count 1 for a tangent, and when.
    bool reports_tangent = false;
    std::string_view tangent_rule = "never";
    // line_roots: reports a tangent (count 1) whenever the reduced
    // discriminant b′² − aC (a = 1 when a unit direction is assumed) is at
    // most this absolute value: a deliberate epsilon, named as the cause of
    // the false tangents it makes.
    std::optional<double> tangent_threshold{};
    answer_kind answer = answer_kind::t;
    output_set outputs{};
    // What the user requires beyond the right root on the right side (not a
    // promise of the formula's: audit's --accuracy sets it for every target).
    accuracy_requirement accuracy{};
    // degenerate=miss: a degenerate cast (degenerate_cast in core/ray_sphere_case.h:
    // a zero direction, a non-finite input or bound, an empty or reversed
    // interval) is handed to the target, which must answer a miss; without
    // it (degenerate=invalid) such a case is invalid and never run.
    bool degenerate_is_miss = false;
    // cast=segment: the target takes a segment case's end points p0 and p1
    // as given (a plugin's segment entry, rayverify_plugin.h) and answers t
    // along p1 − p0, the fraction of the segment, on the case's [0, 1] with
    // the contract's ends (range=interval). It runs on segment cases only: a
    // ray case is not scored (contract_violation). cast=ray (the default):
    // the target takes o and d; on a segment case it gets o = p0 and
    // d = p1 − p0 rounded in its precision (core/ray_sphere_case.h's
    // target_input), that rounding counted as its own.
    bool takes_segment_ends = false;
};

// contract::tangent_rule is a string_view (so that built-in contracts are
// constants): a rule read from a plugin, a shard or a results file is kept
// alive here for the life of the program (equal texts share one copy).
std::string_view interned_text(std::string text);

std::string_view query_kind_name(query_kind k);
std::string_view range_source_name(range_source r);
std::string_view inside_rule_name(inside_rule i);
std::string_view answer_kind_name(answer_kind a);
std::string_view point_bound_name(point_bound b);

// The value named `name`; nullopt for an unknown name.
std::optional<query_kind> query_kind_from_name(std::string_view name);
std::optional<range_source> range_source_from_name(std::string_view name);
std::optional<inside_rule> inside_rule_from_name(std::string_view name);
std::optional<answer_kind> answer_kind_from_name(std::string_view name);
std::optional<point_bound> point_bound_from_name(std::string_view name);

// True for the kinds that are passed the ray's range (its interval, its
// tmax, or its segment) rather than answering on a fixed one.
constexpr bool takes_interval(const contract& c) { return c.range != range_source::ray; }

// The range of t a contract answers on, with its ends' semantics.
struct t_range {
    double lower = 0;
    double upper = std::numeric_limits<double>::infinity();
    end_kind lower_end = end_kind::open;
    end_kind upper_end = end_kind::open;

    // Does the value t (any precision, widened exactly) lie in the range? NaN never does.
    template <class T>
    bool contains(T t) const {
        const double x = static_cast<double>(t);
        const bool above = lower_end == end_kind::closed ? x >= lower : x > lower;
        const bool below = upper_end == end_kind::closed ? x <= upper : x < upper;
        return above && below;
    }
};

// The range a contract answers on: a ray contract's is from 0 to +inf, an
// interval or segment contract's is (tmin, tmax) as given (each defaulting to
// 0 and +inf), a tmax_only contract's from 0 to tmax; each with the
// contract's end semantics.
// (Inline: the judge forms one for every case and target.)
inline t_range range_of(const contract& c, const std::optional<double>& tmin, const std::optional<double>& tmax) {
    t_range r;
    r.lower_end = c.lower_end;
    r.upper_end = c.upper_end;
    switch (c.range) {
        case range_source::ray: break;
        case range_source::interval:
        case range_source::segment:
            if (tmin) r.lower = *tmin;
            if (tmax) r.upper = *tmax;
            break;
        case range_source::tmax_only:
            if (tmax) r.upper = *tmax;
            break;
    }
    return r;
}

// "(0, +inf)", "[tmin, tmax)" with the values: how explain and details print a range.
std::string format_range(const t_range& r);

// The canonical spec: every field, in the order of the struct.
std::string format_contract(const contract& c);
// One sentence for people, e.g. "nearest hit in [0, +inf); inside: clamp; ...".
std::string describe_contract(const contract& c);

// Parse a spec (comma-separated key=value; keys: query, range, ends, inside,
// tangent, faces, unit_direction, reports_tangent, tangent_threshold, answer,
// t_bounds, hit_point, point_error, normal, accuracy, degenerate, cast). Fields not given keep
// `defaults`' values. Throws std::invalid_argument naming the key and the
// allowed values on anything else, and on a combination that cannot be
// answered (point_error without hit_point, a point answer or hit point for
// any_hit, t_bounds with a point answer, an accuracy for any_hit).
contract parse_contract(std::string_view spec, contract defaults = {});

// Why a contract cannot be answered as stated, or nullopt: the combinations
// parse_contract refuses (a plugin's v2 fields are checked the same way).
std::optional<std::string> contract_problem(const contract& c);

// A point answer gives the hit point by definition.
constexpr bool gives_hit_point(const contract& c) {
    return c.answer == answer_kind::point || c.outputs.hit_point;
}

}  // namespace rayverify
