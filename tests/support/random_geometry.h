// Random geometry for the oracle's property tests (oracle_test,
// fast_oracle_test, static_filter_test): the primitives their regimes are
// drawn from and the regimes more than one of them draws: aimed uniform cases,
// near tangents, origins exactly on the surface, small integers, and the case
// whose near root lies exactly on a rounding midpoint.
#pragma once

#include <algorithm>
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

// v·2^k, exact (short of overflow and underflow).
inline vec3<double> scaled(vec3<double> v, int k) { return {std::ldexp(v.x, k), std::ldexp(v.y, k), std::ldexp(v.z, k)}; }

// Uniform: o, c in [−10, 10]³, r in [0.1, 5], d of length 2^[−4, 4] aimed within 2r of c.
inline ray_sphere<double> aimed_uniform_case(std::mt19937_64& rng) {
    const vec3<double> o = uniform_point(rng, 10), c = uniform_point(rng, 10);
    const double r = uniform(rng, 0.1, 5);
    const vec3<double> target = c + (2 * r * uniform(rng, 0, 1)) * unit_vector(rng);
    const double length = std::ldexp(uniform(rng, 0.5, 1), static_cast<int>(rng() % 9) - 4);
    return {o, length * (target - o), c, r};
}

// Near-tangent: a line through a point at distance r(1 + ε) from c, ⊥ to the
// offset, ε = ±2^−k, k in [8, 60].
inline ray_sphere<double> near_tangent_case(std::mt19937_64& rng) {
    const vec3<double> c = uniform_point(rng, 10);
    const double r = uniform(rng, 0.1, 5);
    const vec3<double> n = unit_vector(rng);
    vec3<double> d = unit_vector(rng);
    d = d - (d.x * n.x + d.y * n.y + d.z * n.z) * n;
    const double eps = std::ldexp((rng() & 1) ? 1.0 : -1.0, -static_cast<int>(8 + rng() % 53));
    const vec3<double> touch = c + (r * (1 + eps)) * n;
    return {touch - uniform(rng, 1, 20) * d, d, c, r};
}

// Origin exactly on the sphere (C = 0: a root is 0): o = c + r·(±3/5, ±4/5, 0)
// permuted, r a multiple of 5 so that every coordinate is exact.
inline ray_sphere<double> on_surface_case(std::mt19937_64& rng) {
    const double unit = std::ldexp(1.0, static_cast<int>(rng() % 41) - 20);
    const double r = 5 * unit * static_cast<double>(1 + rng() % 1000);
    const vec3<double> c{std::round(uniform(rng, -1e3, 1e3)) * unit, std::round(uniform(rng, -1e3, 1e3)) * unit,
                         std::round(uniform(rng, -1e3, 1e3)) * unit};
    double offset[3] = {(rng() & 1 ? 3 : -3) * r / 5, (rng() & 1 ? 4 : -4) * r / 5, 0};
    std::shuffle(offset, offset + 3, rng);
    return {{c.x + offset[0], c.y + offset[1], c.z + offset[2]}, uniform_point(rng, 2), c, r};
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
