// The exact oracle: what a ray–sphere test answers in exact arithmetic.
//
// Every input is a finite double, hence an exact dyadic rational, so the
// quadratic a t² + 2b′t + C = 0 (a = d·d, b′ = d·(o − c), C = |o − c|² − r²)
// has exact coefficients and its roots are exact algebraic numbers
// (−b′ ∓ √Δ′)/a with Δ′ = b′² − aC. The oracle decides the line's class and
// each root's sign exactly, and rounds roots and hit points correctly
// (round-to-nearest-even) to the precision of the variant being judged.
//
// This header exposes no CGAL, GMP or MPFR type: the exact representation
// lives behind `exact_solution`'s private handle, in oracle.cpp.
#pragma once

#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "core/comparison.h"
#include "core/ray_sphere_case.h"

namespace rayverify {

namespace oracle_internal {
struct exact_quadratic;     // the exact route's state (internal/exact_number.h)
struct exact_coefficients;  // the quadratic's coefficients as expansions (refinement.h)
}  // namespace oracle_internal

// Storage for a value built on first use and kept, as std::optional holds
// one, but left untouched until it is built: std::optional, as GCC 12 builds
// it, zeroes its whole storage, and a solution carries eight ULP frames and
// two refined enclosures that most solutions never build (zeroing them was a
// tenth of a filtered solve). For trivially copyable values: a copy copies
// the bytes, built or not.
template <class T>
class built_on_first_use {
    static_assert(std::is_trivially_copyable_v<T> && std::is_trivially_destructible_v<T>);

public:
    built_on_first_use() {}
    built_on_first_use& operator=(const T& v) {
        value_ = v;
        built_ = true;
        return *this;
    }
    explicit operator bool() const { return built_; }
    T& operator*() { return value_; }
    const T& operator*() const { return value_; }
    T* operator->() { return &value_; }
    const T* operator->() const { return &value_; }

private:
    union {
        T value_;
    };
    bool built_ = false;
};

enum class line_class { miss, tangent, two_hit };
const char* line_class_name(line_class c);

enum class root_index { near_root, far_root };

// Which route answers a case: the filtered oracle (solve_exact and its kin:
// the static and double-word filters first, expansions, exact arithmetic
// only where they cannot settle), or the reference route
// (solve_exact_reference and its kin: the class, signs and rounded roots in
// exact arithmetic, and no filter's enclosures kept, so that every later
// question — a ULP figure, a comparison — is decided without the filters, by
// exact expansions where they decide it, else in exact arithmetic). Their
// answers are the same, bit for bit: the tests require it, and `rayverify
// audit --oracle-route reference` shows it on a user's own cases (the same
// report, slower).
enum class oracle_route : std::uint8_t { filtered, reference };
std::string_view oracle_route_name(oracle_route r);
std::optional<oracle_route> oracle_route_from_name(std::string_view name);
// Every route's name, in order (the option's choices, its completion).
std::vector<std::string> oracle_route_names();

// Bounds on a figure that was not computed to every digit: lower ≤ x ≤
// upper, both doubles, so that they also bound x correctly rounded (RN is
// monotonic and fixes doubles). lower == upper: the figure itself.
struct figure_bracket {
    double lower = 0, upper = 0;
    bool exact() const { return lower == upper; }
};

// How far the oracle had to go to settle a case's class, root signs and
// correctly rounded roots: a floating-point filter with rigorous error bounds
// settled everything, or it could not and exact arithmetic ran. (Later ULP
// queries on the solution may still do exact work; that is not counted.)
// `expansion`: the filter, with an exact zero it cannot see (Δ′ = 0 for a
// tangent, C = 0 for an origin on the sphere) decided by floating-point
// expansions, still without big numbers.
enum class oracle_stage { filter, expansion, exact };

struct exact_root {
    int sign = 0;         // exact sign of t*: −1 behind, 0 at the origin, +1 in front
    double rounded = 0;   // RN(t*) in the solution's precision (a float value is exact in double)
};

class exact_solution {
public:
    // The case exactly as given (at the precision's rounding of its inputs).
    invalid_reason invalid = invalid_reason::none;
    precision prec = precision::binary64;
    line_class cls = line_class::miss;
    exact_root near_root;  // the smaller root; equals far_root for a tangent
    exact_root far_root;

    // The nearest root with t > 0.
    std::optional<root_index> nearest_in_front;

    // The deepest stage this answer needed; its rate per family measures how stiff the family is.
    oracle_stage stage = oracle_stage::exact;

    bool valid() const { return invalid == invalid_reason::none; }
    // The route that solved this case; a later solve for the same case (the
    // judge's a = 1 idealisation) takes the same one.
    oracle_route route() const { return route_; }
    // False for a segment whose exact direction p1 − p0 is not a double.
    bool direction_is_double() const { return direction_low_ == vec3<double>{}; }
    const exact_root& root(root_index i) const {
        return i == root_index::near_root ? near_root : far_root;
    }

    // Exact comparisons (core/comparison.h: compare(a, b) is sign(a − b)),
    // the value first: compare(value, t*ᵢ); value finite. Requires cls != miss.
    comparison compare_to_root(double value, root_index i) const;

    // compare(value, m), m = −b′/a the midpoint of the two roots; value
    // finite. Below the midpoint a value is nearer the near root, above it
    // the far root. Requires cls != miss.
    comparison compare_to_midpoint(double value) const;

    // compare(x, Δ′), Δ′ = b′² − aC of this solution's quadratic; x finite.
    comparison compare_to_discriminant(double x) const;

    // |value − t*| / ulp(t*) in the solution's precision, with every printed
    // digit right (the exact difference is bracketed adaptively). 0 exactly
    // when value == t* (an error below the double range is the smallest
    // subnormal, not 0); +inf for a non-finite value. Requires cls != miss.
    double root_ulp_error(root_index i, double value) const;

    // Bounds on root_ulp_error(i, value) from the root's enclosure alone (no
    // refinement, no exact arithmetic): for a double root about 2^−47 wide
    // relative, which orders two errors as root_ulp_error would wherever they
    // differ by more. nullopt where the enclosure does not settle t*'s binade
    // (then root_ulp_error must answer). Requires cls != miss; value finite.
    std::optional<figure_bracket> root_ulp_error_bracket(root_index i, double value) const;

    // compare(root_ulp_error(i, value), bound), exactly: whether a returned
    // value lies within bound·ulp(t*) of root i (the accuracy clause's
    // ulp:N). value finite; bound finite, ≥ 0. Requires cls != miss.
    comparison compare_root_ulp_error(root_index i, double value, double bound) const;

    // compare(|value − t*ᵢ|·|d|, length·scale), exactly (the product too):
    // how far along the ray a returned value lies from root i, against a
    // length (the accuracy clause's radius:x as x·r, distance:x as x·1).
    // value finite; length and scale finite, ≥ 0. Requires cls != miss.
    comparison compare_root_distance(root_index i, double value, double length, double scale) const;

    // Same for coordinate `axis` of o + t·d with t the root i.
    double hit_point_ulp_error(root_index i, int axis, double value) const;
    // Bounds on hit_point_ulp_error(i, axis, value) from the coordinate's
    // enclosure alone, as root_ulp_error_bracket's; nullopt where it does not
    // settle the coordinate's binade. value finite; requires cls != miss.
    std::optional<figure_bracket> hit_point_ulp_error_bracket(root_index i, int axis, double value) const;

    // RN of coordinate `axis` of o + t·d for root i, in the solution's precision.
    double rounded_hit_coordinate(root_index i, int axis) const;
    // The nearest root in front's hit point, o + t·d rounded per coordinate
    // (rounded_hit_coordinate of nearest_in_front's root), formed when asked:
    // solving rounds no hit point, since only the per-case lines' exact
    // block, explain and scenes read one. (0, 0, 0) when no root is in front.
    vec3<double> hit_point() const;

    // compare(value, p*), p* coordinate `axis` of o + t·d for root i; value
    // finite. Requires cls != miss.
    comparison compare_to_hit_coordinate(double value, root_index i, int axis) const;

    // RN to double of that coordinate, whatever the solution's precision (a
    // reference a float variant's normal is measured against).
    double hit_coordinate_in_double(root_index i, int axis) const;

    struct internal;  // the routes, defined in oracle.cpp

    // An enclosure of an exact value: |x − (hi + lo)| ≤ err; err = +inf when
    // the filter could not bound x (the exact state then answers).
    struct enclosure {
        double hi = 0, lo = 0;
        double err = std::numeric_limits<double>::infinity();
    };

    // A finer enclosure of a root: t* within correction.err of base +
    // correction.hi + correction.lo, base a double next to t*, the correction
    // from base's exact residual (about 2^−150 relative where an enclosure
    // holds 2^−100: what a double's ULP error needs to every digit).
    struct refined_enclosure {
        double base = 0;
        enclosure correction;
    };

    // An enclosure with the exponent of ulp(x) in the solution's precision,
    // when the enclosure settles x's binade: found once per root and per hit
    // coordinate, since the ULP errors of every variant's answers are measured
    // against the same exact values.
    struct ulp_frame {
        enclosure x;
        std::optional<int> ulp_exponent;
        // The last ULP error measured against this value, and for which
        // answer: variants often return the same double, and the judge asks
        // for a root's error more than once.
        double last_value = std::numeric_limits<double>::quiet_NaN(), last_error = 0;
    };

private:
    // The queries above answer from the roots' enclosures when those settle
    // the answer, and otherwise from the exact state, which is built on first
    // use and kept. That lazy build mutates the solution without a lock: a
    // solution (and its copies, which share a built state) must be used by
    // one thread at a time, as the audit does.
    const oracle_internal::exact_quadratic& state() const;
    // RN of coordinate `axis` of root i's hit point in precision p.
    double hit_coordinate_in(root_index i, int axis, precision p) const;

    ray_sphere<double> geometry_{};
    // A segment's exact direction is geometry_.direction + direction_low_
    // (p1 − p0 as two doubles a coordinate); zero for a ray, and for a
    // segment whose difference is a double. Nonzero: only the exact route
    // answers (the filters and expansions take d to be a double).
    vec3<double> direction_low_{};
    oracle_route route_ = oracle_route::filtered;
    bool unit_direction_ = false;  // a taken to be 1 (solve_exact_unit_direction)
    enclosure roots_[2];  // near, far
    enclosure midpoint_;  // of the two roots, −b′/a
    // Built on first use by a ULP query roots_ cannot settle, kept like exact_.
    mutable built_on_first_use<refined_enclosure> refined_[2];
    mutable built_on_first_use<ulp_frame> root_frames_[2];    // near, far
    mutable built_on_first_use<ulp_frame> hit_frames_[2][3];  // per root, per axis
    mutable std::shared_ptr<const oracle_internal::exact_coefficients> expansions_;  // built on first use, like exact_
    mutable std::shared_ptr<const oracle_internal::exact_quadratic> exact_;
};

// How much of a case's exact answer a question needs: the class and each
// root's sign (where a ray meets the sphere, and which roots lie in front),
// those and each root correctly rounded, or everything solve_exact answers.
enum class oracle_depth { class_and_signs, roots_rounded, everything };

// The class and roots of a case, with nothing kept beyond them: no
// enclosures, no hit point, no state for later questions (40 bytes against
// exact_solution's 808, GCC 12 on x86-64). `rounded` is set at oracle_depth::roots_rounded
// only (0 at class_and_signs); both roots equal for a tangent, nothing for a
// miss.
struct exact_roots {
    invalid_reason invalid = invalid_reason::none;
    line_class cls = line_class::miss;
    exact_root near_root, far_root;
    bool valid() const { return invalid == invalid_reason::none; }
};

// The case's class and root signs (class_and_signs), or those and the
// correctly rounded roots (roots_rounded), exactly: the static filter
// answers where its bounds certify everything asked, which for ordinary
// cases is all of them; otherwise solve_exact does (the same values: the
// tests require them equal to solve_exact's). `everything` is solve_exact's
// whole answer, of which this returns the same fields. `geometry` as for
// solve_exact (for a float variant: the inputs rounded to float).
exact_roots solve_exact_roots(const ray_sphere<double>& geometry, precision prec, oracle_depth depth);
// The same for many cases at once: out[i] answers cases[i]. `out` must be
// as long as `cases` (asserted; a release build answers as many cases as
// `out` has room for). The environment is checked once for the batch rather
// than once a case: reading MXCSR waits for the floating-point operations
// in flight, 1.2–1.6 times a naive intersection on the machine measured
// (bench --oracle prints both). With both roots rounded, a batch also takes
// each 64 cases in two passes: the class alone answers the misses it
// certifies, then the others' roots are rounded; case by case, the branch
// between a miss and a hit mispredicted wherever the two mix (`uniform`).
// Nothing else may run on the thread meanwhile, so a batch is for cases
// already in hand, not for cases interleaved with calls into the code under
// audit.
void solve_exact_roots(std::span<const ray_sphere<double>> cases, precision prec, oracle_depth depth,
                       std::span<exact_roots> out);

// Solve one case exactly. `geometry` must hold exactly the values the variant
// receives (for a float variant: the inputs already rounded to float). Never
// throws for bad geometry: an invalid case comes back with `invalid` set. A
// case's interval, when it has one, is only checked here (a NaN bound or
// tmin > tmax makes it invalid); which roots lie in a range is the judge's
// question, asked under a contract's end semantics (compare/judge.h).
//
// The filtered oracle: a double-double evaluation with rigorous error bounds
// settles what it can (`stage == filter`); exact arithmetic runs only for what
// it cannot (`stage == exact`). No heap allocation when the filter settles
// everything. Its answers are those of solve_exact_reference, bit for bit.
// What a formula that takes a = d·d to be 1 solves, exactly: t² + 2b′t + C = 0
// for the given inputs (the roots of the true quadratic when |d| = 1). Its
// class, signs, roots and discriminant say what such a formula gets in exact
// arithmetic when |d| is only near 1: a failure it shares is the formula's
// design, not rounding. Filtered like solve_exact (Δ′ = b′² − C);
// solve_exact_unit_direction_reference takes the exact route, and the tests
// require both to agree.
exact_solution solve_exact_unit_direction(const ray_sphere<double>& geometry, precision prec);
exact_solution solve_exact_unit_direction_reference(const ray_sphere<double>& geometry, precision prec);

// compare(|d|², x) exactly, for finite d and x.
comparison compare_squared_length(const vec3<double>& d, double x);

// Whether the box [lower, upper] (finite ends, lower ≤ upper per coordinate)
// holds some point of the sphere |x − c| = r, exactly: its nearest point to c
// is at most r away and its farthest at least r.
// Filter first (plain double, then double-words, with error bounds), exact when it cannot
// settle; box_meets_sphere_reference always takes the exact route (the tests
// require both to agree).
bool box_meets_sphere(const vec3<double>& lower, const vec3<double>& upper, const vec3<double>& centre, double radius);
bool box_meets_sphere_reference(const vec3<double>& lower, const vec3<double>& upper, const vec3<double>& centre,
                                double radius);

// compare(t*ᵢ of `a`, t*ⱼ of `b`) exactly: roots of two cases' quadratics
// (two spheres on one ray) compared without rounding. Requires both classes
// != miss.
comparison compare_roots(const exact_solution& a, root_index i, const exact_solution& b, root_index j);

// How the oracle settled what it was asked, on the calling thread since it
// started (or since the caller reset it): per kind of answer, how many the
// filter settled (double-word enclosures), how many needed floating-point
// expansions (no big numbers; for ULP errors, the refined enclosures), and
// how many exact arithmetic (GMP). The share beyond the filter measures a
// family's stiffness; `bench --audit` prints it. Counting costs an increment
// per answer computed (a ULP error asked again for the same value is
// answered from the last one and not counted).
struct stage_tally {
    std::uint64_t filter = 0, expansion = 0, exact = 0;
    std::uint64_t total() const { return filter + expansion + exact; }
};
struct oracle_stage_counts {
    stage_tally solutions;    // solve_exact: class, root signs and rounded roots (the deepest stage)
    stage_tally ulp_errors;   // root_ulp_error and hit_point_ulp_error
    stage_tally comparisons;  // a root, the midpoint, Δ′, a hit coordinate or |d|² against a value; two roots
    stage_tally roundings;    // rounded hit coordinates asked for after solving
};
oracle_stage_counts& oracle_stage_counts_this_thread();

exact_solution solve_exact(const ray_sphere<double>& geometry, precision prec,
                           std::optional<double> tmin = std::nullopt,
                           std::optional<double> tmax = std::nullopt);

// A segment case: the cast from p0 to p1, solved in the fraction f of
// d = p1 − p0 taken exactly (a difference of doubles, not rounded), on the
// interval f ∈ [0, 1]: roots, their ULP errors and every comparison are in
// f, hit points p0 + f·d. The ends must hold exactly the values the variant
// receives (for a float variant: rounded to float). A segment whose
// difference is a double in every coordinate is the ray (p0, p1 − p0) and
// takes solve_exact's filtered route; any other, the exact route for every
// answer (its stage `exact`). Invalid as solve_exact says for that ray (a
// difference that overflows: non-finite; p0 = p1: a zero direction).
exact_solution solve_exact_segment(const vec3<double>& p0, const vec3<double>& p1, const vec3<double>& centre,
                                   double radius, precision prec);
// The same on the exact route for every segment (the tests require both to agree).
exact_solution solve_exact_segment_reference(const vec3<double>& p0, const vec3<double>& p1,
                                             const vec3<double>& centre, double radius, precision prec);

// The reference route: exact CGAL::Gmpzf coefficients for everything, MPFR
// proposals verified by exact comparison, no filter (`stage == exact`). Same
// contract as solve_exact; the tests require both to agree.
exact_solution solve_exact_reference(const ray_sphere<double>& geometry, precision prec,
                                     std::optional<double> tmin = std::nullopt,
                                     std::optional<double> tmax = std::nullopt);

}  // namespace rayverify
