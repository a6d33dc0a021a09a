// Random geometry for the oracle's property tests (fast_oracle_test,
// static_filter_test): the primitives their regimes are drawn from, the small-
// integer regime, and the case whose near root lies exactly on a rounding midpoint.
#pragma once

#include <cmath>
#include <cstdint>
#include <random>

#include "core/ray_sphere_case.h"
#include "core/vec3.h"

namespace rayverify::test_support {

inline double uniform(std::mt19937_64& rng, double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng);
}

// A direction uniform on the unit sphere.
inline vec3<double> unit_vector(std::mt19937_64& rng) {
    std::normal_distribution<double> n;
    for (;;) {
        const vec3<double> v{n(rng), n(rng), n(rng)};
        const double length = std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
        if (length > 1e-3) return (1 / length) * v;
    }
}

// A point uniform in [−half, half]³.
inline vec3<double> uniform_point(std::mt19937_64& rng, double half) {
    return {uniform(rng, -half, half), uniform(rng, -half, half), uniform(rng, -half, half)};
}

// Small integers: exact roots, tangents, ties, zero components, all frequent.
inline ray_sphere<double> integer_case(std::mt19937_64& rng) {
    const auto small = [&rng] { return static_cast<double>(static_cast<int>(rng() % 9) - 4); };
    ray_sphere<double> g{{small(), small(), small()}, {small(), small(), small()}, {small(), small(), small()},
                         std::fabs(small())};
    if (g.direction.x == 0 && g.direction.y == 0 && g.direction.z == 0) g.direction.z = 1;
    return g;
}

// A root exactly on a rounding midpoint: o = 0, d = ẑ·2^k, c = (0, 0, 2·2^j),
// r = (2 − m)·2^j with m = y + ulp(y)/2, y in [1, 1.5) with p bits: roots m
// and 4 − m (in units of 2^(j − k)), the near one a tie in the precision with
// p bits (every input is a float when p = 24). No enclosure can round it.
inline ray_sphere<double> tie_case(std::mt19937_64& rng, int p) {
    const double y = 1 + std::ldexp(static_cast<double>(rng() % (std::uint64_t{1} << (p - 2))), 1 - p);
    const double r = (2 - y) - std::ldexp(1.0, -p);  // 2 − m, exact (in [0.5, 1), bits down to 2^−p)
    const int j = static_cast<int>(rng() % 21) - 10, k = static_cast<int>(rng() % 21) - 10;
    return {{0, 0, 0}, {0, 0, std::ldexp(1.0, k)}, {0, 0, std::ldexp(2.0, j)}, std::ldexp(r, j)};
}

}  // namespace rayverify::test_support
