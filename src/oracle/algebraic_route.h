// A second exact route to the oracle's answers, built only from CGAL's own
// algebraic number type: the roots (−b′ ∓ √Δ′)/a of a t² + 2b′t + C = 0 as
// CGAL::Sqrt_extension<Gmpq, Gmpq> values (CGAL's Root_of_2 over the
// rationals), compared exactly with rounding boundaries for every decision.
// It shares no code with oracle.cpp (neither its arithmetic nor its
// rounding), so that the two can check each other: tests/algebraic_route_test.cpp
// requires the same answers, bit for bit, as solve_exact.
//
// This header exposes no CGAL or GMP type and no type of oracle.h: inputs and
// outputs are core/ types only.
#pragma once

#include <optional>

#include "core/ray_sphere_case.h"

namespace rayverify {

// One root t* of the quadratic.
struct algebraic_root {
    int sign = 0;        // exact sign of t*: −1 behind, 0 at the origin, +1 in front
    double rounded = 0;  // RN(t*) in the answer's precision (ties to even, ±inf past the
                         // overflow threshold, ±0 by sign for an underflow, +0 for t* = 0)
    // sign(t* − tmin) and sign(t* − tmax) exactly, when the bound was given
    // (an infinite bound compares as such): either end semantics follows.
    std::optional<int> versus_tmin, versus_tmax;

    // tmin ≤ t* ≤ tmax, a missing bound being no bound.
    bool in_closed_interval() const { return versus_tmin.value_or(+1) >= 0 && versus_tmax.value_or(-1) <= 0; }
};

struct algebraic_answer {
    invalid_reason invalid = invalid_reason::none;
    precision prec = precision::binary64;
    // The class is the sign of Δ′ = b′² − aC: −1 the line misses, 0 it is
    // tangent, +1 it crosses the sphere twice.
    int discriminant_sign = -1;
    // Near and far root (equal for a tangent); left at their defaults for a miss.
    algebraic_root roots[2];
    // Index (0 near, 1 far) of the nearest root with t* > 0, if any, and
    // RN(o + t*·d) per coordinate for it (left at 0 when there is none).
    std::optional<int> nearest_in_front;
    vec3<double> hit_point{};

    bool valid() const { return invalid == invalid_reason::none; }
};

// Solves one case exactly; `geometry` holds exactly the values solved (for
// binary32, the inputs already rounded to float). An invalid case (core's
// validity<double>, or a NaN bound or tmin > tmax) comes back with `invalid`
// set and nothing solved. Never throws for bad geometry.
algebraic_answer solve_algebraic(const ray_sphere<double>& geometry, precision prec,
                                 std::optional<double> tmin = std::nullopt, std::optional<double> tmax = std::nullopt);

}  // namespace rayverify
