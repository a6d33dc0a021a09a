// The oracle's second stage: exact signs and finer root enclosures from
// floating-point expansions (expansion.h), with no big numbers. The case's
// quadratic has exact coefficients as expansions (the inputs are doubles in
// the filter range), so a polynomial of the inputs and of a double m can be
// evaluated exactly: whether Δ′ or C is exactly 0, which side of m a root
// lies on, and P(u) at a root's approximation u, from which the root is known
// to about 2^−150 relative (what a double's ULP error needs to every digit).
#pragma once

#include <mutex>

#include "oracle/expansion.h"
#include "oracle/filter.h"

namespace rayverify::oracle_internal {

using refined_enclosure = exact_solution::refined_enclosure;

struct exact_coefficients;

// C = f·f − r² from k's f and radius, cloned for FMA where it is defined.
// exact_coefficients::C() calls it and is itself inline and not cloned:
// clang++-14 refused that member function cloned, used in oracle.cpp before
// refinement.cpp defines it in the unity file (docs/testing.md).
expansion<26> constant_term_of(const exact_coefficients& k);

// The quadratic's coefficients as exact expansions: f = o − c, a = d·d,
// 2b′ = 2d·f, C = f·f − r² (Δ′ = a·r² − |d × f|², Lagrange's identity as in
// the filter, is formed by discriminant_of); a, 2b′ and C compressed, so
// that approximate_compressed reads them directly. Exact for inputs in the
// filter range, where every product stays far from underflow and overflow
// (degree 4: above 2^−528, below 2^330).
struct exact_coefficients {
    expansion<2> f[3];
    expansion<6> a;
    expansion<12> two_b_prime;
    double radius = 0;

    // C, formed on first use and kept: a tangent (Δ′ from f and a with a
    // direction not unit, its root −b′/a) never reads it. Once, whichever
    // thread asks first: copies of a solution share these coefficients.
    const expansion<26>& C() const {
        std::call_once(C_formed_, [this] { C_ = constant_term_of(*this); });
        return C_;
    }

  private:
    mutable std::once_flag C_formed_;
    mutable expansion<26> C_;
};

// k's coefficients formed from g, in place (k is held by the solution: formed
// there, nothing is copied). With `unit_direction`, a is taken to be 1 (what
// a unit-direction formula solves).
void form_coefficients(exact_coefficients& k, const ray_sphere<double>& g, bool unit_direction = false);

// Δ′ = a·r² − |d × f|² from its exact expansion: its sign, and a
// double-word approximation whose bound is about 2^−100 of |Δ′| (tight enough
// for the filter's roots where Δ′ is too near 0 for its own bound).
struct exact_discriminant {
    int sign = 0;
    bounded approximation;
};
// With `unit_direction` (k's a is 1), Δ′ = b′² − C.
exact_discriminant discriminant_of(const ray_sphere<double>& g, const exact_coefficients& k,
                                   bool unit_direction = false);

// sign(Δ′ − x) exactly, x in the filter range (filter.h).
int discriminant_side(const ray_sphere<double>& g, const exact_coefficients& k, bool unit_direction, double x);

// Whether a double u may be substituted into the quadratic's expansions:
// |u| in [2^−200, 2^200] (or 0) keeps every product exact beside the inputs' range.
bool refinable(double u);

// sign(t − m) for a tangent's root t = −b′/a, from the sign of 2b′ + 2a·m; m refinable.
int tangent_root_side(const exact_coefficients& k, double m);

// sign(t_i − m) for one of two roots, given sign(t_j − m) ≠ 0 of the other:
// P(m) = a(m − t_i)(m − t_j) exactly; m refinable.
int root_side(const exact_coefficients& k, double m, int other_side);

// sign(p − v) for the coordinate p = o + d·t of a tangent's root t = −b′/a:
// p − v = ((o − v)·2a − d·2b′) / 2a, a > 0; v refinable.
int tangent_hit_side(const exact_coefficients& k, double o, double d, double v);

// sign(p_i − v) for the coordinate p_i = o + d·t_i of one of two roots, d ≠ 0,
// given sign(p_j − v) ≠ 0 of the other root's: with m = (v − o)/d,
// Q = d²·P(m) = a(v − o)² + 2b′(v − o)d + C·d² exactly, and sign(p − v) =
// sign(d)·sign(t − m), so sign(p_i − v) = sign(Q)·sign(p_j − v); v refinable.
int hit_side(const exact_coefficients& k, double o, double d, double v, int other_side);

// A finer enclosure of the root t_i (of two) from its enclosure's high word,
// or of a tangent's root; err = +inf where it cannot be built.
refined_enclosure refine_root(const exact_coefficients& k, const enclosure& root, const enclosure& other);
refined_enclosure refine_tangent_root(const exact_coefficients& k, const enclosure& root);

// value − t_i from a refined enclosure, as a bounded double-word.
bounded root_difference(const refined_enclosure& t, double value);

// value − p* for p* = o + d·t_i, from a refined enclosure of t_i.
bounded hit_difference(const refined_enclosure& t, double o, double d, double value);

}  // namespace rayverify::oracle_internal
