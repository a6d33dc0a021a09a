// The oracle's exact numbers: dyadic rationals (CGAL::Gmpzf: an arbitrary
// mantissa times a power of two; +, −, × are exact) and the quadratic
// irrationals (A + B·√D)/den built from them, with exact sign decisions.
//
// Private to the oracle: only src/oracle/*.cpp include this header (it
// includes CGAL), and it is not installed (tests/architecture_test.cpp).
#pragma once

#include <CGAL/Gmpzf.h>

#include <memory>

#include "core/ray_sphere_case.h"
#include "oracle/oracle.h"

namespace rayverify::oracle_internal {

using exact = CGAL::Gmpzf;

inline int sign_of(const exact& x) { return static_cast<int>(CGAL::sign(x)); }

// 2^k exactly, for any k.
exact power_of_two(long k);

// (lo + hi) / 2 exactly.
exact midpoint(double lo, double hi);

// sign(A + B·√D), D ≥ 0, exactly.
int sign_of_sum_with_root(const exact& A, const exact& B, const exact& D);

struct quadratic_irrational {
    exact A, B, D, den;  // (A + B·√D) / den, den > 0, D ≥ 0

    int sign() const { return sign_of_sum_with_root(A, B, D); }
    // sign(x − m)
    int compare(const exact& m) const { return sign_of_sum_with_root(A - m * den, B, D); }
    quadratic_irrational negated() const { return {-A, -B, D, den}; }
};

// sign(x − y) exactly, for two quadratic irrationals with any radicands.
int sign_of_difference(const quadratic_irrational& x, const quadratic_irrational& y);

// A case's quadratic a t² + 2b′t + C = 0 in exact arithmetic: its
// discriminant Δ′ = b′² − aC, its roots (−b′ ∓ √Δ′)/a, and the inputs the
// hit point o + t·d is formed from.
struct exact_quadratic {
    exact origin[3], direction[3];
    exact discriminant;  // Δ′
    quadratic_irrational near_root, far_root;

    const quadratic_irrational& root(root_index i) const {
        return i == root_index::near_root ? near_root : far_root;
    }
    // sign(|value − t*ᵢ|·|d| − length), length ≥ 0 exact: with t*ᵢ = (A + B√D)/den,
    // a(value − t*)² − length² has the sign of (P + Q√D)²·a − length²·den²,
    // P = value·den − A, Q = −B, a = |d|².
    int compare_distance_along(root_index i, const exact& value, const exact& length) const {
        const quadratic_irrational& t = root(i);
        const exact a = direction[0] * direction[0] + direction[1] * direction[1] + direction[2] * direction[2];
        const exact P = value * t.den - t.A, Q = -t.B;
        return sign_of_sum_with_root((P * P + Q * Q * t.D) * a - length * length * t.den * t.den,
                                     exact(2.0) * P * Q * a, t.D);
    }
    // Coordinate `axis` of o + t·d for t = (A + B√D)/den: (o·den + d·A + d·B√D)/den.
    quadratic_irrational hit_coordinate(root_index i, int axis) const {
        const quadratic_irrational& t = root(i);
        return {origin[axis] * t.den + direction[axis] * t.A, direction[axis] * t.B, t.D, t.den};
    }
};

// The exact quadratic with f = o − c; with `unit_direction`, a is taken to be
// 1 (what a unit-direction formula solves).
// `direction_low`: a segment's direction is g.direction + direction_low
// exactly (p1 − p0 as two doubles a coordinate); zero for a ray.
std::shared_ptr<const exact_quadratic> exact_quadratic_of(const ray_sphere<double>& g, bool unit_direction = false,
                                                          const vec3<double>& direction_low = {});

}  // namespace rayverify::oracle_internal
