// The oracle's first stage for double inputs: a static filter. The
// quadratic's coefficients, Δ′ and C are computed in plain double, each with
// an error bound fixed a priori as a constant times a magnitude of the inputs
// or of the computed values (the semi-static filters of Shewchuk, "Adaptive
// precision floating-point arithmetic and fast robust geometric predicates",
// 1997, and of CGAL's Static_filtered_predicate); a root is then corrected
// once by Newton's step, whose residual P(t̂) is formed with error-free
// transformations (two_sum, two_prod: core/double_word.h), and rounded from
// the resulting enclosure. Every bound is derived beside its computation in
// static_filter.cpp.
//
// It answers all of filter_case's questions (the class, the roots'
// enclosures, signs and roundings, the front root's hit point) or none: when
// a bound straddles a decision it returns nothing and the double-word filter
// (filter.h) runs instead, then expansions, then the exact route. Only for
// the true quadratic (not the unit-direction idealisation) and for inputs in
// the filter range (filter.h), where no product underflows or overflows, so
// that every rounding error below is relative: |RN(x) − x| ≤ u·|x|, u = 2^−53.
// One exact test sits in it: where Ĉ's bound leaves C's sign open and o − c
// is exact in double, whether C = 0 exactly (an origin on the sphere, a ray
// spawned from its surface), from an expansion of eight doubles; the roots
// are then 0 exactly and −2b′/a, which is corrected and rounded as any root
// (the oracle counts such a solution as its expansion stage).
#pragma once

#include <optional>

#include "core/ray_sphere_case.h"
#include "oracle/filter.h"
#include "oracle/oracle.h"

namespace rayverify::oracle_internal {

// What filter_case(g, prec) settles, all of it, or nothing: the class (a
// miss ends there), both roots' enclosures, signs and correct roundings, and
// the front root's hit point (a coordinate the static enclosure cannot round
// is tried with the filter's double-word rounding, round_hit_coordinate, from
// the same root enclosure).
// It writes into the caller's `out` (a default filtered_case) and says
// whether it settled the case; when it did not, `out` holds partial answers
// the caller must discard (the double-word filter then fills a fresh one).
// Written in place rather than returned: building and copying the result
// cost a fifth of the whole stage.
// `depth`: how much it must settle before it answers true: the class and
// the roots' signs (class_and_signs, as static_class_and_signs answers them;
// roots, roundings and hit point left unset), those and the rounded roots (roots_rounded; no hit point), or all
// of the above (everything).
// The class and the roots' signs alone, what a question about where a line
// meets the sphere needs: Δ′'s sign from b′² − aC where its bound settles it
// (two products; it cancels for far spheres and near tangency), else from
// Lagrange's identity as static_filter_case computes it, and the roots'
// signs from C's and b′'s (their product is C/a, their sum −2b′/a): no
// square root, no division, no root. False where a bound straddles a
// decision, an input is outside the filter range, or the case is not valid
// (a negative radius, a zero direction): a case it settles is valid. The
// roots' signs are set only when Δ′ > 0 (a tangent is never certified).
// Written into the caller's `out`, as static_filter_case's answers are
// (returned, the small struct was assembled through the stack, a sixth of
// the function's time).
struct certified_signs {
    int discriminant_sign = 0;
    int root_sign[2] = {0, 0};  // near, far
};
bool static_class_and_signs(const ray_sphere<double>& g, certified_signs& out);

bool static_filter_case(const ray_sphere<double>& g, precision prec, filtered_case& out,
                        oracle_depth depth = oracle_depth::everything);

}  // namespace rayverify::oracle_internal
