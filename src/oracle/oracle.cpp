// The exact oracle's routes: every answer of exact_solution built filter
// first, in one place each (CGAL's Filtered_predicate is the model). The
// stages, each in its own file:
//   static_filter.h  for double inputs, the class, signs, rounded roots and
//                  hit point from plain double with a-priori error bounds and
//                  one Newton step; all of them or nothing;
//   filter.h       enclosures in double-word arithmetic with rigorous bounds;
//                  they settle what they can, and say "uncertain" otherwise;
//   refinement.h   exact signs and finer enclosures from floating-point
//                  expansions (Shewchuk): exact zeros, roots against a double,
//                  a double's ULP error to every digit; no big numbers;
//   internal/exact_number.h, internal/correct_rounding.h   the exact route:
//                  CGAL::Gmpzf quadratic irrationals and MPFR-proposed,
//                  exactly verified correct rounding (the only big numbers).
// `settle` runs them in that order for one answer and counts the stage that
// answered (oracle_stage_counts). solve_exact_reference takes the exact route
// for everything; the tests require both routes to agree bit for bit.
#include "oracle/oracle.h"

#include "core/fp_environment.h"
#include "core/name_table.h"

#include "oracle/expansion.h"
#include "oracle/filter.h"
#include "oracle/internal/correct_rounding.h"
#include "oracle/internal/exact_number.h"
#include "oracle/refinement.h"
#include "oracle/static_filter.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

namespace rayverify {

const char* line_class_name(line_class c) {
    switch (c) {
        case line_class::miss: return "miss";
        case line_class::tangent: return "tangent";
        case line_class::two_hit: return "two_hit";
    }
    return "?";
}

namespace {
constexpr name_table<oracle_route, 2> route_names{
    {{oracle_route::filtered, "filtered"}, {oracle_route::reference, "reference"}}};
}  // namespace

std::string_view oracle_route_name(oracle_route r) { return name_in(route_names, r); }
std::optional<oracle_route> oracle_route_from_name(std::string_view name) { return value_in(route_names, name); }
std::vector<std::string> oracle_route_names() { return names_in(route_names); }

oracle_stage_counts& oracle_stage_counts_this_thread() {
    thread_local oracle_stage_counts counts;
    return counts;
}

using namespace oracle_internal;

namespace {

// One answer, filter first: `filter` and `expansion` return an uncertain
// answer (an empty optional when they cannot settle it), `exact` always
// answers. The first certain answer is returned, and its stage counted.
template <class Filter, class Expansion, class Exact>
auto settle(stage_tally& tally, Filter&& filter, Expansion&& expansion, Exact&& exact) -> decltype(exact()) {
    if (const auto answer = filter()) return ++tally.filter, *answer;
    if (const auto answer = expansion()) return ++tally.expansion, *answer;
    ++tally.exact;
    return exact();
}

// Whether a filter settled a root of sign 0 (the static filter does, for an
// origin exactly on the sphere, C = 0 decided with an expansion).
bool has_zero_root(const filtered_case& filter) { return filter.sign[0] == 0 || filter.sign[1] == 0; }
// The same for the static filter's class and signs (a miss's signs are unset: 0).
bool has_zero_root(const certified_signs& signs) {
    return signs.discriminant_sign > 0 && (signs.root_sign[0] == 0 || signs.root_sign[1] == 0);
}

// compare(a, b) from a stage's uncertain sign(a − b), and from its uncertain sign(b − a).
uncertain_comparison comparison_from(uncertain_sign s) {
    return s ? uncertain_comparison(comparison_of_sign(*s)) : std::nullopt;
}
uncertain_comparison comparison_from_reversed(uncertain_sign s) {
    return s ? uncertain_comparison(comparison_of_sign(-*s)) : std::nullopt;
}
// compare(b, a) from compare(a, b), when it is settled.
uncertain_comparison opposite(uncertain_comparison c) {
    return c ? uncertain_comparison(rayverify::opposite(*c)) : std::nullopt;
}

// The same with no expansion stage.
template <class Filter, class Exact>
auto settle(stage_tally& tally, Filter&& filter, Exact&& exact) -> decltype(exact()) {
    return settle(tally, filter, [] { return std::optional<decltype(exact())>(); }, exact);
}

invalid_reason check_case(const ray_sphere<double>& g, std::optional<double> tmin, std::optional<double> tmax) {
    invalid_reason reason = validity<double>(g);
    if (reason == invalid_reason::none && (tmin || tmax)) {
        const double lo = tmin.value_or(-std::numeric_limits<double>::infinity());
        const double hi = tmax.value_or(std::numeric_limits<double>::infinity());
        if (std::isnan(lo) || std::isnan(hi) || lo > hi) reason = invalid_reason::bad_interval;
    }
    return reason;
}

// The nearest root with t > 0, from the roots' exact signs.
std::optional<root_index> nearest_root_in_front(int near_sign, int far_sign) {
    if (near_sign > 0) return root_index::near_root;
    if (far_sign > 0) return root_index::far_root;
    return std::nullopt;
}

int slot_of(root_index i) { return i == root_index::near_root ? 0 : 1; }

}  // namespace

// The routes, with access to the solution's enclosures and lazily built states.
struct exact_solution::internal {
    // The case's coefficients as expansions, built on first use and kept.
    static const exact_coefficients& coefficients(const exact_solution& s) {
        if (!s.expansions_) {
            auto formed = std::make_shared<exact_coefficients>();
            form_coefficients(*formed, s.geometry_, s.unit_direction_);
            s.expansions_ = std::move(formed);
        }
        return *s.expansions_;
    }

    static const enclosure& root_enclosure(const exact_solution& s, root_index i) { return s.roots_[slot_of(i)]; }

    static const ulp_frame& root_frame(const exact_solution& s, root_index i) {
        built_on_first_use<ulp_frame>& frame = s.root_frames_[slot_of(i)];
        if (!frame) frame = framed(s.prec, root_enclosure(s, i));
        return *frame;
    }

    static const ulp_frame& hit_frame(const exact_solution& s, root_index i, int axis) {
        built_on_first_use<ulp_frame>& frame = s.hit_frames_[slot_of(i)][axis];
        if (!frame) frame = framed(s.prec, hit_coordinate_enclosure(s.geometry_, root_enclosure(s, i), axis));
        return *frame;
    }

    static ulp_frame framed(precision p, const enclosure& x) {
        return {x, known(x) ? ulp_exponent_of(p, x) : std::nullopt};
    }

    static const enclosure& hit_enclosure(const exact_solution& s, root_index i, int axis) {
        return hit_frame(s, i, axis).x;
    }

    // |value| / ulp(0): the ULP error against an exact zero, ulp(0) being the
    // precision's smallest subnormal (a power of two: exact unless it overflows).
    static double error_against_zero(precision p, double value) {
        return std::ldexp(std::fabs(value), -ulp_exponent_in(p, std::numeric_limits<long>::min()));
    }

    static bool exact_zero_root(const exact_solution& s, root_index i) {
        const enclosure& root = root_enclosure(s, i);
        return root.err == 0 && root.hi == 0;
    }

    // compare(t_i, m) exactly with expansions: a tangent's root against m;
    // one of two roots once the other root's enclosure parts m from t_j.
    // Needs the roots' enclosures (the filter range) and m refinable.
    // When the other root's enclosure cannot part m from t_j (the roots are
    // close), the midpoint −b′/a does: t_near < −b′/a < t_far, and which side
    // of it m lies on is the sign of 2b′ + 2a·m. (refinement.h's *_side
    // functions answer signs of differences: sign(t − m).)
    static uncertain_comparison compare_root_by_expansion(const exact_solution& s, root_index i, double m) {
        const int k = slot_of(i);
        if (s.cls == line_class::miss || !known(s.roots_[k]) || !refinable(m)) return std::nullopt;
        if (s.cls == line_class::tangent) return comparison_of_sign(tangent_root_side(coefficients(s), m));
        const uncertain_comparison other = compare(s.roots_[1 - k], m);  // compare(t_j, m)
        int other_side = other ? static_cast<int>(*other) : 0;
        if (!other) {
            const int midpoint_side = tangent_root_side(coefficients(s), m);  // sign(−b′/a − m)
            const bool near = i == root_index::near_root;
            // m beyond the midpoint from t_i: t_i's side is the midpoint's; else t_j's is.
            if (near && midpoint_side < 0) return comparison::smaller;
            if (!near && midpoint_side > 0) return comparison::larger;
            other_side = near ? +1 : -1;
        }
        return comparison_from(root_side(coefficients(s), m, other_side));
    }

    // compare(p_i, v) exactly with expansions, p_i coordinate `axis` of root
    // i's hit point: a tangent's from its root −b′/a; one of two roots' once
    // the other's coordinate enclosure parts it from v. Needs the roots'
    // enclosures (the filter range) and v refinable.
    static uncertain_comparison compare_hit_by_expansion(const exact_solution& s, root_index i, int axis, double v) {
        const int k = slot_of(i);
        if (s.cls == line_class::miss || !known(s.roots_[k]) || !refinable(v)) return std::nullopt;
        const double o = s.geometry_.origin[axis], d = s.geometry_.direction[axis];
        if (d == 0) return compare(o, v);
        if (s.cls == line_class::tangent) return comparison_from(tangent_hit_side(coefficients(s), o, d, v));
        const uncertain_comparison other = compare(
            hit_enclosure(s, i == root_index::near_root ? root_index::far_root : root_index::near_root, axis), v);
        if (!other) return std::nullopt;
        return comparison_from(hit_side(coefficients(s), o, d, v, static_cast<int>(*other)));
    }

    // |value − p_i| / ulp(p_i) from expansions: the refined enclosure for the
    // ratio; where the coordinate's enclosure leaves value = p_i or p_i's
    // binade open (an exactly representable coordinate, one at a power of
    // two, an exact 0), both decided with compare_hit_by_expansion.
    static std::optional<double> hit_ulp_error_by_expansion(const exact_solution& s, root_index i, int axis,
                                                            double value) {
        const double o = s.geometry_.origin[axis], d = s.geometry_.direction[axis];
        const refined_enclosure* fine = refined(s, i);
        const ulp_frame& frame = hit_frame(s, i, axis);
        if (fine && frame.ulp_exponent)
            if (const std::optional<double> e = rounded_ulp_ratio(hit_difference(*fine, o, d, value), *frame.ulp_exponent))
                return e;
        if (!std::isfinite(value)) return std::nullopt;
        const uncertain_comparison position = compare_hit_by_expansion(s, i, axis, value);  // compare(p, value)
        if (!position) return std::nullopt;
        if (*position == comparison::equal) return 0.0;
        if (!fine) return std::nullopt;
        const uncertain_comparison against_zero = compare_hit_by_expansion(s, i, axis, 0.0);
        if (!against_zero) return std::nullopt;
        const int sign = static_cast<int>(*against_zero);  // sign(p)
        if (sign == 0) return error_against_zero(s.prec, value);
        const double guess = frame.x.hi + frame.x.lo;
        if (!(guess != 0 && std::isfinite(guess))) return std::nullopt;
        const int binade = binade_of(guess);
        for (int e = binade - 1; e <= binade + 1; ++e) {
            // 2^e ≤ |p| < 2^(e+1), decided exactly.
            const uncertain_comparison low = compare_hit_by_expansion(s, i, axis, sign * std::ldexp(1.0, e));
            const uncertain_comparison high = compare_hit_by_expansion(s, i, axis, sign * std::ldexp(1.0, e + 1));
            if (!low || !high) return std::nullopt;
            if (sign * static_cast<int>(*low) < 0 || sign * static_cast<int>(*high) >= 0) continue;
            return rounded_ulp_ratio(hit_difference(*fine, o, d, value), ulp_exponent_in(s.prec, e));
        }
        return std::nullopt;
    }

    // The root's refined enclosure, built on first use; nullptr when it
    // cannot be (a segment whose direction is not a double: expansions take
    // the coefficients from a double d).
    static const refined_enclosure* refined(const exact_solution& s, root_index i) {
        if (!s.direction_is_double()) return nullptr;
        const int k = slot_of(i);
        built_on_first_use<refined_enclosure>& fine = s.refined_[k];
        if (!fine)
            fine = s.cls == line_class::tangent ? refine_tangent_root(coefficients(s), s.roots_[k])
                                                : refine_root(coefficients(s), s.roots_[k], s.roots_[1 - k]);
        return known(fine->correction) ? &*fine : nullptr;
    }

    // |value − t_i| / ulp(t_i) from the root's enclosure (an exact zero root
    // included: ulp(0) is the format's smallest subnormal, the ratio |value|
    // scaled by a power of two, exact unless it overflows).
    static std::optional<double> root_ulp_error_from_enclosure(const exact_solution& s, root_index i, double value) {
        if (exact_zero_root(s, i) && std::isfinite(value)) return error_against_zero(s.prec, value);
        const ulp_frame& frame = root_frame(s, i);
        return ulp_error_from(frame.x, frame.ulp_exponent, value);
    }

    // The same from expansions: the refined enclosure for the ratio; where
    // the enclosure leaves value = t_i or t_i's binade open (an exactly
    // representable root, one at a power of two), both decided with
    // compare_root_by_expansion.
    static std::optional<double> root_ulp_error_by_expansion(const exact_solution& s, root_index i, double value) {
        const refined_enclosure* fine = refined(s, i);
        const ulp_frame& frame = root_frame(s, i);
        if (fine && frame.ulp_exponent)
            if (const std::optional<double> e = rounded_ulp_ratio(root_difference(*fine, value), *frame.ulp_exponent))
                return e;
        if (!std::isfinite(value)) return std::nullopt;
        const uncertain_comparison position = compare_root_by_expansion(s, i, value);
        if (!position) return std::nullopt;
        if (*position == comparison::equal) return 0.0;
        const exact_root& root = s.root(i);
        if (root.sign == 0 || fine == nullptr) return std::nullopt;
        const enclosure& coarse = root_enclosure(s, i);
        const int guess = std::ilogb(coarse.hi + coarse.lo);
        for (int e = guess - 1; e <= guess + 1; ++e) {
            // 2^e ≤ |t_i| < 2^(e+1), decided exactly.
            const uncertain_comparison low = compare_root_by_expansion(s, i, root.sign * std::ldexp(1.0, e));
            const uncertain_comparison high = compare_root_by_expansion(s, i, root.sign * std::ldexp(1.0, e + 1));
            if (!low || !high) return std::nullopt;
            if (root.sign * static_cast<int>(*low) < 0 || root.sign * static_cast<int>(*high) >= 0) continue;
            return rounded_ulp_ratio(root_difference(*fine, value), ulp_exponent_in(s.prec, e));
        }
        return std::nullopt;
    }

    static comparison compare_roots(const exact_solution& a, root_index i, const exact_solution& b, root_index j) {
        return settle(
            oracle_stage_counts_this_thread().comparisons,
            [&]() -> uncertain_comparison {
                const enclosure& x = root_enclosure(a, i);
                const enclosure& y = root_enclosure(b, j);
                if (!known(x) || !known(y)) return std::nullopt;
                return comparison_from(sign_of(bounded_of(x) - bounded_of(y)));
            },
            [&] { return comparison_of_sign(sign_of_difference(a.state().root(i), b.state().root(j))); });
    }

    static exact_solution reference(const ray_sphere<double>& g, precision prec, std::optional<double> tmin,
                                    std::optional<double> tmax, bool unit_direction = false,
                                    const vec3<double>& direction_low = {}) {
        exact_solution solution;
        solution.prec = prec;
        solution.geometry_ = g;
        solution.direction_low_ = direction_low;
        solution.route_ = oracle_route::reference;
        solution.unit_direction_ = unit_direction;
        solution.invalid = check_case(g, tmin, tmax);
        if (!solution.valid()) return solution;
        solution.stage = oracle_stage::exact;

        std::shared_ptr<const exact_quadratic> state = exact_quadratic_of(g, unit_direction, direction_low);
        const int sign_discriminant = sign_of(state->discriminant);
        solution.cls = sign_discriminant < 0   ? line_class::miss
                       : sign_discriminant == 0 ? line_class::tangent
                                                : line_class::two_hit;
        if (solution.cls == line_class::miss) return solution;
        for (root_index i : {root_index::near_root, root_index::far_root}) {
            exact_root& out = i == root_index::near_root ? solution.near_root : solution.far_root;
            out.sign = state->root(i).sign();
            out.rounded = round_in(prec, state->root(i));
        }
        solution.nearest_in_front = nearest_root_in_front(solution.near_root.sign, solution.far_root.sign);

        solution.exact_ = std::move(state);
        return solution;
    }

    // A tangent (Δ′ = 0, decided with an expansion): the root −b′/a enclosed,
    // signed and rounded in double-words; false (the exact route) when the
    // root's enclosure cannot be rounded (a tie).
    static bool settle_tangent(exact_solution& solution) {
        const exact_coefficients& k = coefficients(solution);
        solution.cls = line_class::tangent;
        exact_root root;
        enclosure t{0, 0, 0};
        root.sign = -sign_of(k.two_b_prime) * sign_of(k.a);
        if (root.sign != 0) {
            const std::optional<bounded> quotient_found = quotient(-approximate_compressed(k.two_b_prime),
                                                                         approximate_compressed(k.a) * 2.0);
            if (!quotient_found) return false;
            t = {quotient_found->v.h, quotient_found->v.l, quotient_found->err};
            const std::optional<double> rounded = round_enclosure(solution.prec, t, root.sign);
            if (!rounded) return false;
            root.rounded = *rounded;
        }
        solution.roots_[0] = solution.roots_[1] = t;
        solution.near_root = solution.far_root = root;
        solution.nearest_in_front = nearest_root_in_front(root.sign, root.sign);
        solution.stage = oracle_stage::expansion;
        return true;
    }

    static exact_solution filtered(const ray_sphere<double>& g, precision prec, std::optional<double> tmin,
                                   std::optional<double> tmax, bool unit_direction = false) {
        // Every return returns `solution` (the exact route assigned to it
        // where it runs), so that it is built in the caller's storage (NRVO):
        // a copy of the 800-byte solution was a tenth of a filtered solve.
        exact_solution solution;
        solution.prec = prec;
        solution.unit_direction_ = unit_direction;
        solution.invalid = check_case(g, tmin, tmax);
        if (!solution.valid()) return solution;
        // The static filter first (plain double, a-priori bounds), then the
        // double-word filter when a static bound straddles a decision.
        filtered_case filter;
        // No hit point: rounded when asked (hit_point, rounded_hit_coordinate).
        if (unit_direction || !static_filter_case(g, prec, filter, oracle_depth::roots_rounded))
            filter = filter_case(g, prec, std::nullopt, unit_direction);
        // A root of sign 0 (an origin on the sphere, which the static filter
        // settles) rests on C = 0, decided with an expansion.
        bool expanded = has_zero_root(filter);
        if (!filter.discriminant_sign) {
            // Δ′ within the filter's bound of 0 (or inputs outside its range):
            // Δ′'s exact sign from an expansion; a tangent's root from its
            // coefficients, else the filter again with Δ′'s tight approximation.
            if (!in_filter_range(g)) {
                solution = reference(g, prec, tmin, tmax, unit_direction);
                return solution;
            }
            solution.geometry_ = g;
            const exact_discriminant discriminant = discriminant_of(g, coefficients(solution), unit_direction);
            if (discriminant.sign == 0) {
                if (settle_tangent(solution)) return solution;
                solution = reference(g, prec, tmin, tmax, unit_direction);
                return solution;
            }
            filter = filter_case(g, prec, discriminant.approximation, unit_direction);
            if (!filter.discriminant_sign) {
                solution = reference(g, prec, tmin, tmax, unit_direction);
                return solution;
            }
            expanded = true;
        }

        solution.geometry_ = g;
        solution.roots_[0] = filter.roots[0];
        solution.roots_[1] = filter.roots[1];
        if (*filter.discriminant_sign < 0) {
            solution.cls = line_class::miss;
            solution.stage = expanded ? oracle_stage::expansion : oracle_stage::filter;
            return solution;
        }
        solution.cls = line_class::two_hit;
        // The midpoint's enclosure: the mean of the roots'.
        if (known(filter.roots[0]) && known(filter.roots[1])) {
            // Halving is exact (the filter range keeps every word far from underflow).
            const bounded sum = bounded_of(filter.roots[0]) + bounded_of(filter.roots[1]);
            solution.midpoint_ = {0.5 * sum.v.h, 0.5 * sum.v.l, 0.5 * sum.err};
        }

        // A root whose sign the enclosure leaves open while the other's is
        // known is exactly 0 when C = 0 (an origin on the sphere): decided
        // with an expansion, the root is then the exact enclosure 0.
        int zero_root = -1;
        if (!filter.sign[0] != !filter.sign[1] && sign_of(coefficients(solution).C()) == 0) {
            zero_root = filter.sign[0] ? 1 : 0;
            solution.roots_[zero_root] = {0, 0, 0};
        }
        // A root the filter's enclosure cannot round (C or b′ loose where the
        // line is nearly tangent, a root near a rounding boundary): its
        // refined enclosure, from P(u) as an expansion, takes its place.
        for (root_index i : {root_index::near_root, root_index::far_root}) {
            const int k = slot_of(i);
            if (k == zero_root || !filter.sign[k] || filter.rounded[k]) continue;
            if (const refined_enclosure* fine = refined(solution, i)) {
                const bounded t = exactly(fine->base) + bounded_of(fine->correction);
                solution.roots_[k] = {t.v.h, t.v.l, t.err};
                filter.rounded[k] = round_enclosure(prec, solution.roots_[k], filter.sign[k]);
                expanded = true;
            }
        }
        // Signs and correctly rounded roots: from the filter, else exactly.
        for (root_index i : {root_index::near_root, root_index::far_root}) {
            const int k = slot_of(i);
            exact_root& out = k == 0 ? solution.near_root : solution.far_root;
            if (k == zero_root) {
                out = {0, 0.0};  // RN(0) = +0
                continue;
            }
            out.sign = filter.sign[k] ? *filter.sign[k] : solution.state().root(i).sign();
            out.rounded = filter.rounded[k] ? *filter.rounded[k] : round_in(prec, solution.state().root(i));
        }
        solution.nearest_in_front = nearest_root_in_front(solution.near_root.sign, solution.far_root.sign);
        // Exact arithmetic ran iff the exact state was needed.
        solution.stage = solution.exact_                  ? oracle_stage::exact
                         : zero_root >= 0 || expanded ? oracle_stage::expansion
                                                      : oracle_stage::filter;
        return solution;
    }
};

const exact_quadratic& exact_solution::state() const {
    if (!exact_) exact_ = exact_quadratic_of(geometry_, unit_direction_, direction_low_);
    return *exact_;
}

comparison exact_solution::compare_to_root(double value, root_index i) const {
    // The stages answer sign(t* − value): compare(value, t*) is its opposite.
    return settle(
        oracle_stage_counts_this_thread().comparisons,
        [&] {
            // Against 0, the root's exact sign answers.
            return value == 0 ? uncertain_comparison(comparison_of_sign(-root(i).sign))
                              : opposite(compare(internal::root_enclosure(*this, i), value));
        },
        [&] { return opposite(internal::compare_root_by_expansion(*this, i, value)); },
        [&] { return comparison_of_sign(-state().root(i).compare(exact(value))); });
}

comparison exact_solution::compare_to_midpoint(double value) const {
    return settle(
        oracle_stage_counts_this_thread().comparisons,
        [&] { return opposite(compare(midpoint_, value)); },
        [&]() -> uncertain_comparison {
            // m = −b′/a: sign(m − value) from 2b′ + 2a·value.
            if (!known(internal::root_enclosure(*this, root_index::near_root)) || !refinable(value)) return std::nullopt;
            return comparison_of_sign(-tangent_root_side(internal::coefficients(*this), value));
        },
        [&] {
            // m = A/den for the roots (A ∓ B√D)/den, so sign(value − m) = sign(value·den − A).
            const quadratic_irrational& root = state().near_root;
            return comparison_of_sign(sign_of(exact(value) * root.den - root.A));
        });
}

comparison exact_solution::compare_to_discriminant(double x) const {
    return settle(
        oracle_stage_counts_this_thread().comparisons, [] { return uncertain_comparison(); },
        [&]() -> uncertain_comparison {
            if (!direction_is_double() || !in_filter_range(geometry_) || !in_filter_range(x)) return std::nullopt;
            // discriminant_side: sign(Δ′ − x).
            return comparison_from_reversed(discriminant_side(geometry_, internal::coefficients(*this), unit_direction_, x));
        },
        [&] { return comparison_of_sign(sign_of(exact(x) - state().discriminant)); });
}

double exact_solution::root_ulp_error(root_index i, double value) const {
    built_on_first_use<ulp_frame>& frame = root_frames_[slot_of(i)];
    if (frame && frame->last_value == value) return frame->last_error;
    const double error = settle(
        oracle_stage_counts_this_thread().ulp_errors,
        [&] { return internal::root_ulp_error_from_enclosure(*this, i, value); },
        [&] { return internal::root_ulp_error_by_expansion(*this, i, value); },
        [&] { return ulp_error_in(prec, state().root(i), value); });
    // The frame is built by now unless an exact zero root answered first.
    if (frame) {
        frame->last_value = value;
        frame->last_error = error;
    }
    return error;
}

std::optional<figure_bracket> exact_solution::root_ulp_error_bracket(root_index i, double value) const {
    if (internal::exact_zero_root(*this, i)) {
        const double error = internal::error_against_zero(prec, value);
        return figure_bracket{error, error};
    }
    const ulp_frame& frame = internal::root_frame(*this, i);
    return ulp_error_bracket_from(frame.x, frame.ulp_exponent, value);
}

comparison exact_solution::compare_root_ulp_error(root_index i, double value, double bound) const {
    return settle(
        oracle_stage_counts_this_thread().comparisons,
        [&]() -> uncertain_comparison {
            const std::optional<figure_bracket> b = root_ulp_error_bracket(i, value);
            if (!b) return std::nullopt;
            if (b->upper < bound) return comparison::smaller;
            if (b->lower > bound) return comparison::larger;
            if (b->lower == b->upper && internal::exact_zero_root(*this, i)) return compare(b->lower, bound);
            return std::nullopt;
        },
        [&] { return comparison_of_sign(compare_ulp_error_in(prec, state().root(i), value, bound)); });
}

comparison exact_solution::compare_root_distance(root_index i, double value, double length, double scale) const {
    return settle(
        oracle_stage_counts_this_thread().comparisons,
        [&]() -> uncertain_comparison {
            // sign(a·(value − t*)² − (length·scale)²) in double-words, where
            // nothing underflows: the values in [2^−150, 2^150] or 0, the gap
            // not below 2^−300 (the filter range bounds the root and |d|).
            const enclosure& root = internal::root_enclosure(*this, i);
            const auto in_range = [](double x) { return x == 0 || (std::fabs(x) >= 0x1p-150 && std::fabs(x) <= 0x1p150); };
            if (!known(root) || !in_filter_range(geometry_) || !in_range(value) || !in_range(length) ||
                !in_range(scale))
                return std::nullopt;
            const bounded gap = exactly(value) - bounded_of(root);
            if (magnitude_bound(gap) < 0x1p-300) return std::nullopt;
            const vec3<double>& d = geometry_.direction;
            const bounded a = exactly(d.x) * exactly(d.x) + exactly(d.y) * exactly(d.y) + exactly(d.z) * exactly(d.z);
            const bounded allowed = exactly(length) * exactly(scale);
            const int s = certain_sign(gap * gap * a - allowed * allowed);
            return s != 0 ? uncertain_comparison(comparison_of_sign(s)) : std::nullopt;
        },
        [&] {
            return comparison_of_sign(state().compare_distance_along(i, exact(value), exact(length) * exact(scale)));
        });
}

double exact_solution::hit_point_ulp_error(root_index i, int axis, double value) const {
    built_on_first_use<ulp_frame>& frame = hit_frames_[slot_of(i)][axis];
    if (frame && frame->last_value == value) return frame->last_error;
    const double o = geometry_.origin[axis], d = geometry_.direction[axis];
    const double error = settle(
        oracle_stage_counts_this_thread().ulp_errors,
        [&]() -> std::optional<double> {
            if ((d == 0 || internal::exact_zero_root(*this, i)) && value == o) return 0.0;  // the coordinate is o's
            const ulp_frame& frame = internal::hit_frame(*this, i, axis);
            return ulp_error_from(frame.x, frame.ulp_exponent, value);
        },
        [&] { return internal::hit_ulp_error_by_expansion(*this, i, axis, value); },
        [&] { return ulp_error_in(prec, state().hit_coordinate(i, axis), value); });
    // The frame is built by now unless the exact route answered first (d = 0).
    if (frame) {
        frame->last_value = value;
        frame->last_error = error;
    }
    return error;
}

std::optional<figure_bracket> exact_solution::hit_point_ulp_error_bracket(root_index i, int axis, double value) const {
    const double o = geometry_.origin[axis], d = geometry_.direction[axis];
    if ((d == 0 || internal::exact_zero_root(*this, i)) && value == o) return figure_bracket{0, 0};  // o's coordinate
    const ulp_frame& frame = internal::hit_frame(*this, i, axis);
    return ulp_error_bracket_from(frame.x, frame.ulp_exponent, value);
}

double exact_solution::rounded_hit_coordinate(root_index i, int axis) const {
    return hit_coordinate_in(i, axis, prec);
}

vec3<double> exact_solution::hit_point() const {
    if (!nearest_in_front) return {};
    const root_index front = *nearest_in_front;
    return {rounded_hit_coordinate(front, 0), rounded_hit_coordinate(front, 1), rounded_hit_coordinate(front, 2)};
}

double exact_solution::hit_coordinate_in(root_index i, int axis, precision p) const {
    return settle(
        oracle_stage_counts_this_thread().roundings,
        [&] { return round_hit_coordinate(p, geometry_, internal::root_enclosure(*this, i), axis); },
        [&] { return round_in(p, state().hit_coordinate(i, axis)); });
}

comparison exact_solution::compare_to_hit_coordinate(double value, root_index i, int axis) const {
    // The stages answer sign(p* − value): compare(value, p*) is its opposite.
    return settle(
        oracle_stage_counts_this_thread().comparisons,
        [&] { return opposite(compare(internal::hit_enclosure(*this, i, axis), value)); },
        [&] { return opposite(internal::compare_hit_by_expansion(*this, i, axis, value)); },
        [&] { return comparison_of_sign(-state().hit_coordinate(i, axis).compare(exact(value))); });
}

double exact_solution::hit_coordinate_in_double(root_index i, int axis) const {
    return hit_coordinate_in(i, axis, precision::binary64);
}

exact_solution solve_exact_unit_direction(const ray_sphere<double>& g, precision prec) {
    return exact_solution::internal::filtered(g, prec, std::nullopt, std::nullopt, true);
}

exact_solution solve_exact_unit_direction_reference(const ray_sphere<double>& g, precision prec) {
    return exact_solution::internal::reference(g, prec, std::nullopt, std::nullopt, true);
}

comparison compare_squared_length(const vec3<double>& d, double x) {
    const bool in_range = in_filter_range(d.x) && in_filter_range(d.y) && in_filter_range(d.z) && in_filter_range(x);
    return settle(
        oracle_stage_counts_this_thread().comparisons,
        [&]() -> uncertain_comparison {
            if (!in_range) return std::nullopt;
            // In plain double first: s = |d|² with 5 roundings is within
            // 4.01·2^−53·|d|² < 0.55·2^−50·s of the exact value (no underflow
            // in the filter range), and s − x rounds by at most 2^−53 of itself.
            const double s = d.x * d.x + d.y * d.y + d.z * d.z;
            if (s - x > 0x1p-50 * s) return comparison::larger;
            if (x - s > 0x1p-50 * s) return comparison::smaller;
            const bounded length =
                exactly(two_prod(d.x, d.x)) + exactly(two_prod(d.y, d.y)) + exactly(two_prod(d.z, d.z));
            return comparison_from(sign_of(length - exactly(x)));
        },
        [&]() -> uncertain_comparison {
            // Equal, or within the double-word bound of it (a unit axis
            // direction against 1): the exact sign of the sum of the three
            // error-free squares less x, an expansion (no product underflows
            // in the filter range).
            if (!in_range) return std::nullopt;
            const expansion<7> difference = (expansion_of(d.x) * d.x + expansion_of(d.y) * d.y) +
                                            (expansion_of(d.z) * d.z - expansion_of(x));
            return comparison_of_sign(sign_of(difference));
        },
        [&] {
            const exact dx(d.x), dy(d.y), dz(d.z);
            return comparison_of_sign(sign_of(dx * dx + dy * dy + dz * dz - exact(x)));
        });
}

namespace {

// box_meets_sphere's exact route.
bool box_meets_sphere_exactly(const vec3<double>& lower, const vec3<double>& upper, const vec3<double>& centre,
                              double radius) {
    exact nearest(0.0), farthest(0.0);
    for (int axis = 0; axis < 3; ++axis) {
        const exact below = exact(lower[axis]) - exact(centre[axis]), above = exact(upper[axis]) - exact(centre[axis]);
        // The nearest coordinate is c's own when the slab holds it, else the nearer end.
        if (sign_of(below) > 0) nearest = nearest + below * below;
        else if (sign_of(above) < 0) nearest = nearest + above * above;
        const exact low_squared = below * below, high_squared = above * above;
        farthest = farthest + (low_squared < high_squared ? high_squared : low_squared);
    }
    const exact r_squared = exact(radius) * exact(radius);
    return sign_of(nearest - r_squared) <= 0 && sign_of(farthest - r_squared) >= 0;
}

}  // namespace

bool box_meets_sphere(const vec3<double>& lower, const vec3<double>& upper, const vec3<double>& centre, double radius) {
    return settle(
        oracle_stage_counts_this_thread().comparisons,
        [&]() -> std::optional<bool> {
            for (int axis = 0; axis < 3; ++axis)
                if (!in_filter_range(lower[axis]) || !in_filter_range(upper[axis]) || !in_filter_range(centre[axis]))
                    return std::nullopt;
            if (!in_filter_range(radius)) return std::nullopt;
            // In plain double, as the exact route: a difference rounds once
            // (keeping its sign, 0 only when exact), a square and the larger
            // of two squares are within 3·2^−53 of the exact ones, and a sum
            // of three such non-negative terms within 5·2^−53 of the exact
            // sum; r² within 2^−53 (no underflow or overflow in the filter
            // range). So s − r² has the sign of the exact difference once it
            // exceeds 2^−50·(s + r²); 2^−49 leaves a factor of two.
            double nearest = 0, farthest = 0;
            for (int axis = 0; axis < 3; ++axis) {
                const double below = lower[axis] - centre[axis], above = upper[axis] - centre[axis];
                if (below > 0) nearest += below * below;
                else if (above < 0) nearest += above * above;
                farthest += std::max(below * below, above * above);
            }
            const double r_squared = radius * radius;
            const auto against_r_squared = [&](double s) -> uncertain_sign {
                const double difference = s - r_squared, bound = 0x1p-49 * (s + r_squared);
                if (difference > bound) return +1;
                if (-difference > bound) return -1;
                return std::nullopt;
            };
            const auto decided = [](uncertain_sign near, uncertain_sign far) -> std::optional<bool> {
                if ((near && *near > 0) || (far && *far < 0)) return false;
                if (near && far) return true;  // nearest < r² < farthest
                return std::nullopt;
            };
            if (const std::optional<bool> answer = decided(against_r_squared(nearest), against_r_squared(farthest)))
                return answer;
            // Then in double-words (an engine's bounds are often a few ulps
            // around the surface): the differences exact, their squares and
            // sums with rigorous bounds; the larger square chosen by the sign
            // of below + above, left to the exact route when it is uncertain.
            bounded nearest_dw = exactly(0.0), farthest_dw = exactly(0.0);
            for (int axis = 0; axis < 3; ++axis) {
                const bounded below = exactly(two_sum(lower[axis], -centre[axis])),
                              above = exactly(two_sum(upper[axis], -centre[axis]));
                if (below.v.h > 0) nearest_dw = nearest_dw + below * below;
                else if (above.v.h < 0) nearest_dw = nearest_dw + above * above;
                const uncertain_sign below_nearer = sign_of(below + above);  // > 0: |above| is the larger
                if (!below_nearer) return std::nullopt;
                farthest_dw = farthest_dw + (*below_nearer > 0 ? above * above : below * below);
            }
            const bounded r_squared_dw = exactly(two_prod(radius, radius));
            return decided(sign_of(nearest_dw - r_squared_dw), sign_of(farthest_dw - r_squared_dw));
        },
        [&] { return box_meets_sphere_exactly(lower, upper, centre, radius); });
}

bool box_meets_sphere_reference(const vec3<double>& lower, const vec3<double>& upper, const vec3<double>& centre,
                                double radius) {
    return box_meets_sphere_exactly(lower, upper, centre, radius);
}

comparison compare_roots(const exact_solution& a, root_index i, const exact_solution& b, root_index j) {
    return exact_solution::internal::compare_roots(a, i, b, j);
}

namespace {

// A valid solution counted by the deepest stage it needed (oracle_stage_counts).
void count_solved(const exact_solution& solution) {
    if (!solution.valid()) return;
    stage_tally& solutions = oracle_stage_counts_this_thread().solutions;
    ++(solution.stage == oracle_stage::filter      ? solutions.filter
       : solution.stage == oracle_stage::expansion ? solutions.expansion
                                                   : solutions.exact);
}

}  // namespace

namespace {

// solve_exact's answer, in the IEEE default its caller has made sure of.
exact_solution solved_in_ieee_default(const ray_sphere<double>& g, precision prec, std::optional<double> tmin,
                                      std::optional<double> tmax) {
    exact_solution solution = exact_solution::internal::filtered(g, prec, tmin, tmax);
    count_solved(solution);
    return solution;
}

// solve_exact_roots' answer, likewise; `solutions` is this thread's tally.
exact_roots roots_in_ieee_default(const ray_sphere<double>& g, precision prec, oracle_depth depth,
                                  stage_tally& solutions) {
    exact_roots out;
    // The static filter settles valid cases only: a case it settles needs no validity check.
    if (depth == oracle_depth::class_and_signs) {
        if (oracle_internal::certified_signs signs; oracle_internal::static_class_and_signs(g, signs)) {
            ++(has_zero_root(signs) ? solutions.expansion : solutions.filter);
            if (signs.discriminant_sign < 0) return out;
            out.cls = line_class::two_hit;
            out.near_root.sign = signs.root_sign[0];
            out.far_root.sign = signs.root_sign[1];
            return out;
        }
    }
    oracle_internal::filtered_case filter;
    if (depth == oracle_depth::roots_rounded && oracle_internal::static_filter_case(g, prec, filter, depth)) {
        ++(has_zero_root(filter) ? solutions.expansion : solutions.filter);
        if (*filter.discriminant_sign < 0) return out;
        out.cls = line_class::two_hit;  // the static filter certifies no tangent
        out.near_root.sign = *filter.sign[0];
        out.far_root.sign = *filter.sign[1];
        out.near_root.rounded = *filter.rounded[0];
        out.far_root.rounded = *filter.rounded[1];
        return out;
    }
    // What the static filter cannot certify (or everything): the whole
    // solution's answer, an invalid case's reason among them.
    const exact_solution whole = solved_in_ieee_default(g, prec, std::nullopt, std::nullopt);
    out.invalid = whole.invalid;
    out.cls = whole.cls;
    if (whole.cls == line_class::miss) return out;
    out.near_root = whole.near_root;
    out.far_root = whole.far_root;
    if (depth == oracle_depth::class_and_signs) out.near_root.rounded = out.far_root.rounded = 0;
    return out;
}

}  // namespace

exact_solution solve_exact(const ray_sphere<double>& g, precision prec, std::optional<double> tmin,
                           std::optional<double> tmax) {
    // The filters' error bounds assume rounding to nearest and gradual
    // underflow: whatever foreign code left on this thread, the truth is
    // computed in the IEEE default (core/fp_environment.h; a few instructions).
    // Every audited case, hunted candidate and explained case is solved here
    // first, and each target's calls restore the default after them, so the
    // judge and the measures that follow run in it too.
    restore_ieee_default();
    return solved_in_ieee_default(g, prec, tmin, tmax);
}

exact_roots solve_exact_roots(const ray_sphere<double>& g, precision prec, oracle_depth depth) {
    restore_ieee_default();  // as solve_exact: the filters' bounds assume the IEEE default
    return roots_in_ieee_default(g, prec, depth, oracle_stage_counts_this_thread().solutions);
}

void solve_exact_roots(std::span<const ray_sphere<double>> cases, precision prec, oracle_depth depth,
                       std::span<exact_roots> out) {
    assert(out.size() == cases.size() && "a batch's answers are as many as its cases");
    restore_ieee_default();  // once: nothing but the oracle runs until the batch is answered
    stage_tally& solutions = oracle_stage_counts_this_thread().solutions;
    const std::size_t n = std::min(cases.size(), out.size());
    if (depth != oracle_depth::roots_rounded) {
        for (std::size_t i = 0; i < n; ++i) out[i] = roots_in_ieee_default(cases[i], prec, depth, solutions);
        return;
    }
    // Both roots rounded, a chunk of cases at a time: first each case's class
    // alone (static_class_and_signs, no root), which answers the misses it
    // certifies, then the roots of the others. Taken case by case, a miss
    // (class and signs, some 150 instructions) and a hit (some 800) took one
    // branch or the other at random on `uniform`, and each mispredicted
    // branch threw away the start of the next case.
    constexpr std::size_t chunk = 64;
    std::uint8_t others[chunk];  // offsets in the chunk of the cases left after the first pass
    for (std::size_t begin = 0; begin < n; begin += chunk) {
        const std::size_t end = std::min(n, begin + chunk);
        std::size_t kept = 0;
        for (std::size_t i = begin; i < end; ++i) {
            oracle_internal::certified_signs signs;
            const bool miss = oracle_internal::static_class_and_signs(cases[i], signs) && signs.discriminant_sign < 0;
            out[i] = exact_roots{};  // a miss's answer, counted as roots_in_ieee_default counts it
            solutions.filter += miss;
            others[kept] = static_cast<std::uint8_t>(i - begin);
            kept += !miss;  // written always, kept where not a miss: no branch
        }
        for (std::size_t k = 0; k < kept; ++k) {
            const std::size_t i = begin + others[k];
            out[i] = roots_in_ieee_default(cases[i], prec, depth, solutions);
        }
    }
}

namespace {

// The segment from p0 to p1 as the ray o = p0, d = p1 − p0, the difference
// split into its double and the exact remainder (two_sum: exact unless it
// overflows, which check_case then refuses as a non-finite direction).
struct segment_as_ray {
    ray_sphere<double> geometry;
    vec3<double> direction_low;
    bool direction_is_double() const { return direction_low == vec3<double>{}; }
};

segment_as_ray segment_ray(const vec3<double>& p0, const vec3<double>& p1, const vec3<double>& centre, double radius) {
    double high[3], low[3];
    for (int axis = 0; axis < 3; ++axis) {
        const dword difference = two_sum(p1[axis], -p0[axis]);
        high[axis] = difference.h;
        low[axis] = std::isfinite(difference.h) ? difference.l : 0.0;
    }
    return {{p0, {high[0], high[1], high[2]}, centre, radius}, {low[0], low[1], low[2]}};
}

}  // namespace

exact_solution solve_exact_segment(const vec3<double>& p0, const vec3<double>& p1, const vec3<double>& centre,
                                   double radius, precision prec) {
    const segment_as_ray s = segment_ray(p0, p1, centre, radius);
    if (s.direction_is_double()) return solve_exact(s.geometry, prec, 0.0, 1.0);
    restore_ieee_default();
    exact_solution solution = exact_solution::internal::reference(s.geometry, prec, 0.0, 1.0, false, s.direction_low);
    count_solved(solution);  // the exact stage
    return solution;
}

exact_solution solve_exact_segment_reference(const vec3<double>& p0, const vec3<double>& p1,
                                             const vec3<double>& centre, double radius, precision prec) {
    const segment_as_ray s = segment_ray(p0, p1, centre, radius);
    return exact_solution::internal::reference(s.geometry, prec, 0.0, 1.0, false, s.direction_low);
}

exact_solution solve_exact_reference(const ray_sphere<double>& g, precision prec, std::optional<double> tmin,
                                     std::optional<double> tmax) {
    return exact_solution::internal::reference(g, prec, tmin, tmax);
}

}  // namespace rayverify
