// The exact oracle checked three ways: hand-worked cases whose arithmetic is
// written out beside them, agreement with the independent MPFR reference on
// random cases from adversarial regimes, and metamorphic identities the exact
// answer must satisfy bit for bit.
//
// Every random case is reproducible from the seed its SCOPED_TRACE prints; a
// failure also prints the case in hex floats.
#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "core/ray_sphere_case.h"
#include "core/vec3.h"
#include "oracle/mpfr_reference.h"
#include "oracle/oracle.h"
#include "support/random_geometry.h"

namespace rayverify {

// GoogleTest prints vec3 values in failure messages through this.
void PrintTo(const vec3<double>& v, std::ostream* out) {
    *out << "(" << v.x << ", " << v.y << ", " << v.z << ")";
}

namespace {

using enum root_index;
using test_support::scaled;
using test_support::uniform;

constexpr double inf = std::numeric_limits<double>::infinity();
constexpr double nan = std::numeric_limits<double>::quiet_NaN();

// ---------------------------------------------------------------------------
// Helpers

std::string hex(double x) {
    char buffer[40];
    std::snprintf(buffer, sizeof buffer, "%a", x);
    return buffer;
}

// The case as one line of hex floats, to paste back into a test or a corpus.
std::string describe(const ray_sphere<double>& g) {
    return "o=(" + hex(g.origin.x) + ", " + hex(g.origin.y) + ", " + hex(g.origin.z) + ") d=(" +
           hex(g.direction.x) + ", " + hex(g.direction.y) + ", " + hex(g.direction.z) + ") c=(" +
           hex(g.centre.x) + ", " + hex(g.centre.y) + ", " + hex(g.centre.z) +
           ") r=" + hex(g.radius);
}

bool same_bits(double a, double b) {
    return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}

// The inputs a binary32 variant receives, widened back to double (exactly).
ray_sphere<double> float_inputs(const ray_sphere<double>& g) {
    const ray_sphere<float> f = rounded_to<float>(g);
    return {vec3_cast<double>(f.origin), vec3_cast<double>(f.direction),
            vec3_cast<double>(f.centre), static_cast<double>(f.radius)};
}

// The neighbouring values of x in the precision (as doubles).
double next_up(precision p, double x) {
    if (p == precision::binary32)
        return std::nextafter(static_cast<float>(x), std::numeric_limits<float>::infinity());
    return std::nextafter(x, inf);
}
double next_down(precision p, double x) {
    if (p == precision::binary32)
        return std::nextafter(static_cast<float>(x), -std::numeric_limits<float>::infinity());
    return std::nextafter(x, -inf);
}

// Signed permutation of the axes: coordinate i of the result is sign[i] times
// coordinate perm[i] of the input. Lengths and dot products are unchanged.
struct axis_map {
    std::array<int, 3> perm{0, 1, 2};
    std::array<double, 3> sign{1, 1, 1};

    vec3<double> operator()(vec3<double> v) const {
        return {sign[0] * v[perm[0]], sign[1] * v[perm[1]], sign[2] * v[perm[2]]};
    }
    ray_sphere<double> operator()(const ray_sphere<double>& g) const {
        return {(*this)(g.origin), (*this)(g.direction), (*this)(g.centre), g.radius};
    }
};

axis_map random_axis_map(std::mt19937_64& rng) {
    static constexpr std::array<std::array<int, 3>, 6> perms{
        {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}}};
    axis_map m;
    m.perm = perms[rng() % 6];
    for (double& s : m.sign) s = (rng() & 1) ? -1.0 : 1.0;
    return m;
}

// Multiply v by 5·R, R the rotation by atan(4/3) in the plane of axes i, j:
// every length scales by exactly 5, so with r → 5r the roots are unchanged,
// and small-integer (times 2^k) inputs stay exact.
vec3<double> rotate_345(vec3<double> v, int i, int j) {
    double out[3] = {5 * v.x, 5 * v.y, 5 * v.z};
    out[i] = 3 * v[i] - 4 * v[j];
    out[j] = 4 * v[i] + 3 * v[j];
    return {out[0], out[1], out[2]};
}

ray_sphere<double> random_rotations_345(ray_sphere<double> g, std::mt19937_64& rng) {
    static constexpr int planes[3][2] = {{0, 1}, {1, 2}, {2, 0}};
    for (int n = static_cast<int>(rng() % 3); n > 0; --n) {
        const auto& plane = planes[rng() % 3];
        g = {rotate_345(g.origin, plane[0], plane[1]), rotate_345(g.direction, plane[0], plane[1]),
             rotate_345(g.centre, plane[0], plane[1]), 5 * g.radius};
    }
    return g;
}

long uniform_int(std::mt19937_64& rng, long lo, long hi) {
    return std::uniform_int_distribution<long>(lo, hi)(rng);
}

// An integer Pythagorean quadruple x² + y² + z² = n² (Euler's parametrisation).
struct quadruple {
    long x, y, z, n;
};
quadruple random_quadruple(std::mt19937_64& rng) {
    for (;;) {
        const long m = uniform_int(rng, -6, 6), n = uniform_int(rng, -6, 6),
                   p = uniform_int(rng, -6, 6), q = uniform_int(rng, -6, 6);
        const long norm = m * m + n * n + p * p + q * q;
        if (norm != 0) return {m * m + n * n - p * p - q * q, 2 * (m * q + n * p), 2 * (n * q - m * p), norm};
    }
}

// ---------------------------------------------------------------------------
// Random regimes. Each returns a valid binary64 case; rounding it to float may
// make it invalid, and the binary32 checks then skip it.

// Everything O(1): a mix of hits, misses, inside and behind.
ray_sphere<double> uniform_case(std::mt19937_64& rng) {
    auto v = [&](double s) {
        return vec3<double>{uniform(rng, -s, s), uniform(rng, -s, s), uniform(rng, -s, s)};
    };
    return {v(10), v(1), v(10), uniform(rng, 0, 10)};
}

// An exact tangent, then r nudged by −1, 0 or +1 ulp (a miss, the tangent,
// or two roots only ~2^−25.5·r/|d| apart). The line runs along z at distance
// |(p, q)|·2^k = n·2^k from the centre, (p, q, n) a Pythagorean triple; 3-4-5
// rotations then tilt it off the axes while keeping every input exact. All
// integers stay below 2^19, so for |k| ≤ 60 the float inputs are the same
// exact tangent.
ray_sphere<double> near_tangent_case(std::mt19937_64& rng) {
    static constexpr long triples[][3] = {{3, 4, 5}, {5, 12, 13}, {8, 15, 17}, {7, 24, 25}, {20, 21, 29}};
    const auto& t = triples[rng() % 5];
    const int k = (rng() % 4 == 0) ? static_cast<int>(uniform_int(rng, -900, 900))
                                   : static_cast<int>(uniform_int(rng, -60, 60));
    const double p = (rng() & 1) ? t[0] : -t[0], q = (rng() & 1) ? t[1] : -t[1];
    const double ox = uniform_int(rng, -1000, 1000), oy = uniform_int(rng, -1000, 1000);
    const double oz = uniform_int(rng, -4096, 4096), cz = uniform_int(rng, -4096, 4096);
    const double s = uniform_int(rng, 1, 1000) * ((rng() & 1) ? 1.0 : -1.0);
    ray_sphere<double> g{{ox, oy, oz}, {0, 0, s}, {ox + p, oy + q, cz}, static_cast<double>(t[2])};
    g = random_axis_map(rng)(random_rotations_345(g, rng));
    g = {scaled(g.origin, k), g.direction, scaled(g.centre, k), std::ldexp(g.radius, k)};
    switch (rng() % 3) {
        case 0: g.radius = std::nextafter(g.radius, 0.0); break;
        case 1: g.radius = std::nextafter(g.radius, inf); break;
        default: break;
    }
    return g;
}

// A sphere of radius ~1 at distance 1e3..1e12, the ray aimed within ~1.5 r
// of its centre: grazing and far, where C = |f|² − r² cancels.
ray_sphere<double> far_case(std::mt19937_64& rng) {
    std::normal_distribution<double> normal;
    vec3<double> u{normal(rng), normal(rng), normal(rng)};
    const double length = std::sqrt(length_squared(u));
    u = (1 / length) * u;
    const double distance = std::pow(10.0, uniform(rng, 3, 12));
    const double r = uniform(rng, 0.25, 4);
    const vec3<double> o{uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1)};
    const vec3<double> miss_by{uniform(rng, -1.5, 1.5) * r, uniform(rng, -1.5, 1.5) * r,
                               uniform(rng, -1.5, 1.5) * r};
    return {o, uniform(rng, 0.5, 2) * u, o + distance * u + miss_by, r};
}

// A uniform case with every input scaled by 2^±300..1000 (roots unchanged),
// and sometimes d alone scaled too (roots huge or tiny).
ray_sphere<double> extreme_scale_case(std::mt19937_64& rng) {
    static constexpr int all_scales[] = {-1000, -600, -300, 300, 600, 900};
    static constexpr int direction_scales[] = {0, 0, -200, 200, -900, 900};
    for (;;) {
        const ray_sphere<double> u = uniform_case(rng);
        const int k = all_scales[rng() % 6], j = direction_scales[rng() % 6];
        const ray_sphere<double> g{scaled(u.origin, k), scaled(u.direction, k + j), scaled(u.centre, k),
                                   std::ldexp(u.radius, k)};
        if (validity<double>(g) == invalid_reason::none) return g;
    }
}

// Subnormal inputs or subnormal/overflowing roots, in both formats.
ray_sphere<double> subnormal_case(std::mt19937_64& rng) {
    auto ints = [&](long span, int k) {
        return vec3<double>{std::ldexp(double(uniform_int(rng, -span, span)), k),
                            std::ldexp(double(uniform_int(rng, -span, span)), k),
                            std::ldexp(double(uniform_int(rng, -span, span)), k)};
    };
    auto unit_box = [&] {
        return vec3<double>{uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1)};
    };
    for (;;) {
        ray_sphere<double> g;
        switch (rng() % 5) {
            case 0: {  // double-subnormal o, c, r; roots ~2^−1044, subnormal
                const vec3<double> o = ints(1L << 30, -1074);
                g = {o, unit_box(), o + ints(1L << 28, -1074),
                     std::ldexp(double(uniform_int(rng, 1L << 27, 1L << 29)), -1074)};
                break;
            }
            case 1: {  // float-subnormal o, c, r; roots subnormal in binary32
                const vec3<double> o = ints(1L << 20, -149);
                g = {o, unit_box(), o + ints(1L << 18, -149),
                     std::ldexp(double(uniform_int(rng, 1L << 17, 1L << 19)), -149)};
                break;
            }
            case 2:  // double-subnormal d: roots ~2^1070, beyond DBL_MAX
                g = {unit_box(), ints(1L << 10, -1074), unit_box(), uniform(rng, 0, 2)};
                break;
            case 3:  // |d| ≈ 2^−1023: roots straddle DBL_MAX ≈ 2^1024
                g = {unit_box(), scaled(unit_box(), -1023), unit_box(), uniform(rng, 0, 2)};
                break;
            default:  // float-subnormal d: roots straddle FLT_MAX ≈ 2^128
                g = {unit_box(), scaled(unit_box(), -int(uniform_int(rng, 127, 140))), unit_box(),
                     uniform(rng, 0, 2)};
                break;
        }
        if (validity<double>(g) == invalid_reason::none) return g;
    }
}

// Every input with its own exponent anywhere in the double range (or, half
// the time, the float range): the coefficients then span thousands of bits,
// what the reference's 12000-bit working precision is sized for.
ray_sphere<double> mixed_magnitude_case(std::mt19937_64& rng) {
    const bool float_range = rng() & 1;
    auto value = [&] {
        if (rng() % 8 == 0) return 0.0;
        const double m = uniform(rng, 0.5, 1) * ((rng() & 1) ? 1.0 : -1.0);
        return float_range ? std::ldexp(m, static_cast<int>(uniform_int(rng, -149, 127)))
                           : std::ldexp(m, static_cast<int>(uniform_int(rng, -1074, 1023)));
    };
    auto point = [&] { return vec3<double>{value(), value(), value()}; };
    for (;;) {
        const ray_sphere<double> g{point(), point(), point(), std::fabs(value())};
        if (validity<double>(g) == invalid_reason::none) return g;
    }
}

// A line along an axis, its origin anywhere in the exponent range, passing
// a subnormal distance ρ from the centre of a subnormal sphere. Exactly
// Δ′ = a r² − |d × f|² = s²(r² − ρ²), so the class is the sign of r² − ρ²
// (mixed: tangents too), but computing it as b′² − aC needs every bit from
// 2^−4296 to 2^4094 — the span the reference's 12000 bits are sized for.
ray_sphere<double> grazing_extreme_case(std::mt19937_64& rng) {
    constexpr double tiny = 0x1p-1074;
    auto anywhere = [&] {
        const double m = uniform(rng, 0.5, 1) * ((rng() & 1) ? 1.0 : -1.0);
        return std::ldexp(m, static_cast<int>(uniform_int(rng, -1000, 1023)));
    };
    const double c1 = double(uniform_int(rng, -(1L << 20), 1L << 20));
    const double c2 = double(uniform_int(rng, -(1L << 20), 1L << 20));
    double t1 = double(uniform_int(rng, -50, 50)), t2 = double(uniform_int(rng, -50, 50));
    double r = double(uniform_int(rng, 0, 70));
    if (rng() % 4 == 0) {  // exactly tangent: ρ = r, a Pythagorean triple
        static constexpr double triples[][3] = {{0, 0, 0}, {3, 4, 5}, {5, 12, 13}, {20, 21, 29}, {0, 7, 7}};
        const auto& t = triples[rng() % 5];
        t1 = (rng() & 1) ? t[0] : -t[0];
        t2 = (rng() & 1) ? t[1] : -t[1];
        r = t[2];
    }
    const ray_sphere<double> g{{(c1 + t1) * tiny, (c2 + t2) * tiny, anywhere()},
                               {0, 0, anywhere()},
                               {c1 * tiny, c2 * tiny, 0},
                               r * tiny};
    return random_axis_map(rng)(g);
}

// Δ′ a perfect square: o = (x, y, z0), d = (0, 0, s), c = 0, r = n with
// x² + y² + w² = n² gives a = s², b′ = s·z0, C = z0² − w², Δ′ = s²w², and
// rational roots (−z0 ∓ |w|)/s — non-dyadic for odd s, 0 when z0 = ±w. Then
// rotated, translated by an integer vector, axes permuted, all scaled by 2^k.
ray_sphere<double> integer_case(std::mt19937_64& rng) {
    const quadruple qd = random_quadruple(rng);
    const long along[3] = {qd.x, qd.y, qd.z};
    const int a = static_cast<int>(rng() % 3);
    const long w = along[a], x = along[(a + 1) % 3], y = along[(a + 2) % 3];
    long z0 = uniform_int(rng, -50, 50);
    if (rng() % 8 == 0) z0 = (rng() & 1) ? w : -w;  // origin on the surface
    const double s = double(uniform_int(rng, 1, 12)) * ((rng() & 1) ? 1.0 : -1.0);
    ray_sphere<double> g{{double(x), double(y), double(z0)}, {0, 0, s}, {0, 0, 0}, double(qd.n)};
    g = random_rotations_345(g, rng);
    const vec3<double> shift{double(uniform_int(rng, -1000, 1000)), double(uniform_int(rng, -1000, 1000)),
                             double(uniform_int(rng, -1000, 1000))};
    g = random_axis_map(rng)(ray_sphere<double>{g.origin + shift, g.direction, g.centre + shift, g.radius});
    const int k = static_cast<int>(uniform_int(rng, -30, 30));
    return {scaled(g.origin, k), scaled(g.direction, k), scaled(g.centre, k), std::ldexp(g.radius, k)};
}

// Roots exactly halfway between two numbers of the format (p significant
// bits): o = (x·h, y·h, −W), d = (0, 0, 1), c = 0, r = n·h with
// x² + y² + w² = n², w odd, W a p-bit number in [2^e, 2^(e+1)) and h = 2^(e−p)
// half its ulp. Then b′ = −W, Δ′ = w²h², and the roots W ∓ |w|·h are odd
// multiples of h: ties (the near one may fall below 2^e and be exact).
struct tie_case_parts {
    ray_sphere<double> geometry;
    double far_root_lo, far_root_hi;  // the two numbers the far root lies halfway between
};
tie_case_parts tie_case(std::mt19937_64& rng, int p) {
    quadruple qd = random_quadruple(rng);
    while ((qd.x & 1) == 0) qd = random_quadruple(rng);  // only x can be odd
    const long w = std::labs(qd.x);
    const int e = static_cast<int>(uniform_int(rng, -20, 20));
    const double h = std::ldexp(1.0, e - p);
    // W = (2^(p−1) + j)·2h with room above so that W + (|w|+1)·h < 2^(e+1).
    const long j = uniform_int(rng, 0, (1L << (p - 1)) - 4096);
    const double W = std::ldexp(double((1L << (p - 1)) + j), e - p + 1);
    return {{{double(qd.y) * h, double(qd.z) * h, -W}, {0, 0, 1}, {0, 0, 0}, double(qd.n) * h},
            W + double(w - 1) * h,
            W + double(w + 1) * h};
}

struct regime {
    const char* name;
    ray_sphere<double> (*make)(std::mt19937_64&);
};

const std::vector<regime>& regimes() {
    static const std::vector<regime> all{
        {"uniform", uniform_case},
        {"near_tangent", near_tangent_case},
        {"far", far_case},
        {"extreme_scale", extreme_scale_case},
        {"subnormal", subnormal_case},
        {"mixed_magnitude", mixed_magnitude_case},
        {"grazing_extreme", grazing_extreme_case},
        {"integer", integer_case},
        {"tie_binary64", [](std::mt19937_64& rng) { return tie_case(rng, 53).geometry; }},
        {"tie_binary32", [](std::mt19937_64& rng) { return tie_case(rng, 24).geometry; }},
    };
    return all;
}

// solve_exact and the MPFR reference agree on class, both root signs and both
// rounded roots, bit for bit.
testing::AssertionResult agrees_with_reference(const ray_sphere<double>& g, precision p) {
    const exact_solution exact = solve_exact(g, p);
    if (!exact.valid())
        return testing::AssertionFailure() << "invalid: " << invalid_reason_name(exact.invalid) << "\n  "
                                           << describe(g);
    const reference_answer reference = solve_with_mpfr_reference(g, p);
    const bool agree =
        exact.cls == reference.cls &&
        (exact.cls == line_class::miss ||
         (exact.near_root.sign == reference.near_sign && exact.far_root.sign == reference.far_sign &&
          same_bits(exact.near_root.rounded, reference.near_rounded) &&
          same_bits(exact.far_root.rounded, reference.far_rounded)));
    if (agree) return testing::AssertionSuccess();
    return testing::AssertionFailure()
           << precision_name(p) << "\n  " << describe(g) << "\n  oracle:    " << line_class_name(exact.cls)
           << " near " << exact.near_root.sign << " " << hex(exact.near_root.rounded) << " far "
           << exact.far_root.sign << " " << hex(exact.far_root.rounded) << "\n  reference: "
           << line_class_name(reference.cls) << " near " << reference.near_sign << " "
           << hex(reference.near_rounded) << " far " << reference.far_sign << " "
           << hex(reference.far_rounded);
}

struct sweep_tally {
    int checked[2] = {0, 0};  // binary64, binary32
    int by_class[3] = {0, 0, 0};
    int subnormal_roots = 0, infinite_roots = 0, zero_roots = 0;
};

// Runs `count` cases of one regime, seeds first_seed, first_seed + 1, ...
sweep_tally cross_check(const regime& r, std::uint64_t first_seed, int count) {
    sweep_tally tally;
    for (int i = 0; i < count; ++i) {
        const std::uint64_t seed = first_seed + static_cast<std::uint64_t>(i);
        SCOPED_TRACE(testing::Message() << "regime " << r.name << ", seed " << seed);
        std::mt19937_64 rng(seed);
        const ray_sphere<double> g = r.make(rng);
        EXPECT_TRUE(agrees_with_reference(g, precision::binary64));
        ++tally.checked[0];
        const exact_solution s = solve_exact(g, precision::binary64);
        ++tally.by_class[static_cast<int>(s.cls)];
        if (s.cls != line_class::miss) {
            for (const exact_root& root : {s.near_root, s.far_root}) {
                if (root.rounded != 0 && std::fabs(root.rounded) < std::numeric_limits<double>::min())
                    ++tally.subnormal_roots;
                if (std::isinf(root.rounded)) ++tally.infinite_roots;
                if (root.sign == 0) ++tally.zero_roots;
            }
        }
        if (validity<float>(g) == invalid_reason::none) {
            EXPECT_TRUE(agrees_with_reference(float_inputs(g), precision::binary32));
            ++tally.checked[1];
        }
    }
    return tally;
}

// ---------------------------------------------------------------------------
// 1. Hand-worked exact cases. Unless said otherwise: unit sphere at the
// origin, d = (0, 0, 1), so a = 1, b′ = d·f = f_z, C = |f|² − 1, Δ′ = b′² − C.

ray_sphere<double> unit_sphere_ray(vec3<double> origin, vec3<double> direction = {0, 0, 1}) {
    return {origin, direction, {0, 0, 0}, 1};
}

void expect_roots(const exact_solution& s, line_class cls, exact_root near, exact_root far) {
    ASSERT_TRUE(s.valid()) << invalid_reason_name(s.invalid);
    EXPECT_EQ(s.cls, cls);
    EXPECT_EQ(s.near_root.sign, near.sign);
    EXPECT_EQ(s.far_root.sign, far.sign);
    EXPECT_TRUE(same_bits(s.near_root.rounded, near.rounded)) << hex(s.near_root.rounded);
    EXPECT_TRUE(same_bits(s.far_root.rounded, far.rounded)) << hex(s.far_root.rounded);
}

TEST(OracleHandCases, TwoHitsFromOutside) {
    // f = (0, 0, −5): b′ = −5, C = 25 − 1 = 24, Δ′ = 25 − 24 = 1,
    // roots 5 ∓ 1 = 4, 6; hit o + 4d = (0, 0, −1).
    const exact_solution s = solve_exact(unit_sphere_ray({0, 0, -5}), precision::binary64);
    expect_roots(s, line_class::two_hit, {1, 4.0}, {1, 6.0});
    EXPECT_EQ(s.nearest_in_front, near_root);
    EXPECT_EQ(s.hit_point(), (vec3<double>{0, 0, -1}));
    // compare_to_root(value, i) is compare(value, t*ᵢ).
    EXPECT_EQ(s.compare_to_root(4.0, near_root), comparison::equal);
    EXPECT_EQ(s.compare_to_root(std::nextafter(4.0, 0.0), near_root), comparison::smaller);
    EXPECT_EQ(s.compare_to_root(std::nextafter(6.0, inf), far_root), comparison::larger);
}

TEST(OracleHandCases, TangentLine) {
    // o = (1, 0, −5): b′ = −5, C = 1 + 25 − 1 = 25, Δ′ = 25 − 25 = 0,
    // double root 5; hit (1, 0, 0).
    const exact_solution s = solve_exact(unit_sphere_ray({1, 0, -5}), precision::binary64);
    expect_roots(s, line_class::tangent, {1, 5.0}, {1, 5.0});
    EXPECT_EQ(s.nearest_in_front, near_root);
    EXPECT_EQ(s.hit_point(), (vec3<double>{1, 0, 0}));
}

TEST(OracleHandCases, OriginOnSurfaceEntering) {
    // o = (0, 0, −1): b′ = −1, C = 0, Δ′ = 1, roots 1 ∓ 1 = 0, 2. t = 0 is not
    // in front (sign 0), so the nearest root in front is the far one.
    const exact_solution s = solve_exact(unit_sphere_ray({0, 0, -1}), precision::binary64);
    expect_roots(s, line_class::two_hit, {0, 0.0}, {1, 2.0});
    EXPECT_EQ(s.nearest_in_front, far_root);
    EXPECT_EQ(s.hit_point(), (vec3<double>{0, 0, 1}));
}

TEST(OracleHandCases, OriginOnSurfaceLeaving) {
    // o = (0, 0, 1): b′ = 1, C = 0, Δ′ = 1, roots −1 ∓ 1 = −2, 0: nothing in front.
    const exact_solution s = solve_exact(unit_sphere_ray({0, 0, 1}), precision::binary64);
    expect_roots(s, line_class::two_hit, {-1, -2.0}, {0, 0.0});
    EXPECT_FALSE(s.nearest_in_front.has_value());
}

TEST(OracleHandCases, OriginInside) {
    // o = 0: b′ = 0, C = −1, Δ′ = 1, roots ∓1; the exit is in front.
    const exact_solution s = solve_exact(unit_sphere_ray({0, 0, 0}), precision::binary64);
    expect_roots(s, line_class::two_hit, {-1, -1.0}, {1, 1.0});
    EXPECT_EQ(s.nearest_in_front, far_root);
    EXPECT_EQ(s.hit_point(), (vec3<double>{0, 0, 1}));
}

TEST(OracleHandCases, SphereBehind) {
    // o = (0, 0, 5): b′ = 5, C = 24, Δ′ = 1, roots −5 ∓ 1 = −6, −4.
    const exact_solution s = solve_exact(unit_sphere_ray({0, 0, 5}), precision::binary64);
    expect_roots(s, line_class::two_hit, {-1, -6.0}, {-1, -4.0});
    EXPECT_FALSE(s.nearest_in_front.has_value());
}

TEST(OracleHandCases, Miss) {
    // o = (2, 0, −5): b′ = −5, C = 4 + 25 − 1 = 28, Δ′ = 25 − 28 = −3 < 0.
    const exact_solution s = solve_exact(unit_sphere_ray({2, 0, -5}), precision::binary64);
    ASSERT_TRUE(s.valid());
    EXPECT_EQ(s.cls, line_class::miss);
    EXPECT_FALSE(s.nearest_in_front.has_value());
}

TEST(OracleHandCases, NonUnitDirectionHalvesRoots) {
    // d = (0, 0, 2): a = 4, b′ = 2·(−5) = −10, C = 24, Δ′ = 100 − 4·24 = 4,
    // roots (10 ∓ 2)/4 = 2, 3 — half of 4, 6. The hit point is unchanged.
    const exact_solution s = solve_exact(unit_sphere_ray({0, 0, -5}, {0, 0, 2}), precision::binary64);
    expect_roots(s, line_class::two_hit, {1, 2.0}, {1, 3.0});
    EXPECT_EQ(s.hit_point(), (vec3<double>{0, 0, -1}));
}

TEST(OracleHandCases, NonDyadicRationalRootsAreRoundedToNearest) {
    // d = (0, 0, 3): a = 9, b′ = −15, C = 24, Δ′ = 225 − 216 = 9, roots
    // (15 ∓ 3)/9 = 4/3, 2. 4/3 = 1.0101…₂ has no exact binary form: RN rounds
    // 4/3 − 1 = 0.0101…₂ at bit 52, where the pattern 01 ends in 1 and the
    // rest (0101… < ½ ulp) is dropped — the same as the division 4.0 / 3.0.
    const exact_solution s = solve_exact(unit_sphere_ray({0, 0, -5}, {0, 0, 3}), precision::binary64);
    expect_roots(s, line_class::two_hit, {1, 4.0 / 3.0}, {1, 2.0});
    EXPECT_EQ(s.compare_to_root(4.0 / 3.0, near_root), comparison::smaller);  // RN(4/3) < 4/3
    const exact_solution f = solve_exact(unit_sphere_ray({0, 0, -5}, {0, 0, 3}), precision::binary32);
    expect_roots(f, line_class::two_hit, {1, double(4.0f / 3.0f)}, {1, 2.0});
}

TEST(OracleHandCases, PointSphereIsTangentOnlyThroughItsCentre) {
    // r = 0: C = |f|², Δ′ = (d·f)² − |d|²|f|² ≤ 0 (Cauchy–Schwarz), zero iff f ∥ d.
    const exact_solution through = solve_exact({{0, 0, -5}, {0, 0, 1}, {0, 0, 0}, 0}, precision::binary64);
    expect_roots(through, line_class::tangent, {1, 5.0}, {1, 5.0});
    const exact_solution beside =
        solve_exact({{0x1p-1074, 0, -5}, {0, 0, 1}, {0, 0, 0}, 0}, precision::binary64);
    EXPECT_EQ(beside.cls, line_class::miss);
}

// o = (½, 0, −5), d = (0, 0, 1), c = 0, r = 3/2: f = (½, 0, −5), b′ = −5,
// C = ¼ + 25 − 9/4 = 23, Δ′ = 25 − 23 = 2: roots 5 ∓ √2, hit points
// (½, 0, ∓√2).
const ray_sphere<double> irrational_case{{0.5, 0, -5}, {0, 0, 1}, {0, 0, 0}, 1.5};

TEST(OracleHandCases, IrrationalRootsAreCorrectlyRounded) {
    // 5 − √2 = 3.58578643762690495119831127579…; in [2, 4) doubles are 2^−51
    // apart and the nearest is 0x1.cafb0ccc0621ap+1 = 3.585786437626905,
    // which is 1.2537…e−16 = 0.28231190717926… ulp ABOVE 5 − √2 (60-digit
    // decimal arithmetic). 5 + √2 rounds to 0x1.9a827999fcef3p+2.
    const exact_solution s = solve_exact(irrational_case, precision::binary64);
    expect_roots(s, line_class::two_hit, {1, 0x1.cafb0ccc0621ap+1}, {1, 0x1.9a827999fcef3p+2});

    // Independent confirmations: the MPFR reference gives the same doubles,
    // and the exact comparison puts the rounded value above the root.
    const reference_answer reference = solve_with_mpfr_reference(irrational_case, precision::binary64);
    EXPECT_EQ(reference.near_rounded, s.near_root.rounded);
    EXPECT_EQ(reference.far_rounded, s.far_root.rounded);
    EXPECT_EQ(s.compare_to_root(s.near_root.rounded, near_root), comparison::larger);
    EXPECT_EQ(s.compare_to_root(std::nextafter(s.near_root.rounded, 0.0), near_root), comparison::smaller);

    // Nearest, not merely adjacent: both neighbours are more than ½ ulp away.
    const double rounded = s.near_root.rounded;
    EXPECT_NEAR(s.root_ulp_error(near_root, rounded), 0.28231190717926087, 1e-15);
    EXPECT_NEAR(s.root_ulp_error(near_root, std::nextafter(rounded, 0.0)), 1 - 0.28231190717926087, 1e-15);
    EXPECT_NEAR(s.root_ulp_error(near_root, std::nextafter(rounded, inf)), 1 + 0.28231190717926087, 1e-15);
    EXPECT_GT(s.root_ulp_error(far_root, s.far_root.rounded), 0.0);
    EXPECT_LE(s.root_ulp_error(far_root, s.far_root.rounded), 0.5);
}

TEST(OracleHandCases, IrrationalRootsInBinary32) {
    // In float the neighbours of 5 − √2 are 2^−22 apart; RN is
    // 0x1.cafb0cp+1 = 3.5857863426208496, 0.39848427794443… float ulp below
    // the root. Float midpoints are doubles, so here the bracketing is exact:
    // the root lies strictly between the midpoints around the rounded value.
    const exact_solution s = solve_exact(irrational_case, precision::binary32);
    expect_roots(s, line_class::two_hit, {1, double(0x1.cafb0cp+1f)}, {1, double(5.0f + std::sqrt(2.0f))});
    const double rounded = s.near_root.rounded;
    const double below = next_down(precision::binary32, rounded);
    const double above = next_up(precision::binary32, rounded);
    EXPECT_EQ(s.compare_to_root((below + rounded) / 2, near_root), comparison::smaller);
    EXPECT_EQ(s.compare_to_root((rounded + above) / 2, near_root), comparison::larger);
    // Errors are in float ulps (2^−22 here).
    EXPECT_NEAR(s.root_ulp_error(near_root, rounded), 0.39848427794443088, 1e-14);
    EXPECT_NEAR(s.root_ulp_error(near_root, above), 1 - 0.39848427794443088, 1e-14);
    // The double RN is a tiny fraction of a float ulp away: 0.2823…·2^−51/2^−22.
    EXPECT_NEAR(s.root_ulp_error(near_root, 0x1.cafb0ccc0621ap+1), 0.28231190717926087 * 0x1p-29, 1e-22);
    EXPECT_EQ(solve_with_mpfr_reference(irrational_case, precision::binary32).near_rounded, rounded);
}

TEST(OracleHandCases, UlpErrorIsMeasuredInUlpsOfTheExactRoot) {
    const exact_solution s = solve_exact(unit_sphere_ray({0, 0, -5}), precision::binary64);
    // t* = 4 lies in [4, 8), where ulp = 2^(2 − 52) = 2^−50 = nextafter(4, 5) − 4.
    EXPECT_EQ(s.root_ulp_error(near_root, 4.0), 0.0);
    EXPECT_EQ(s.root_ulp_error(near_root, std::nextafter(4.0, 5.0)), 1.0);
    // The double just below 4 is 2^−51 away, half of ulp(t*) (not of its own ulp).
    EXPECT_EQ(s.root_ulp_error(near_root, std::nextafter(4.0, 0.0)), 0.5);
    EXPECT_EQ(s.root_ulp_error(far_root, 6.0 + 3 * 0x1p-50), 3.0);
    EXPECT_EQ(s.root_ulp_error(near_root, 5.0), 0x1p50);
    EXPECT_EQ(s.root_ulp_error(near_root, inf), inf);
    EXPECT_EQ(s.root_ulp_error(near_root, nan), inf);

    // In binary32, ulp(4) = 2^(2 − 23) = 2^−21.
    const exact_solution f = solve_exact(unit_sphere_ray({0, 0, -5}), precision::binary32);
    EXPECT_EQ(f.root_ulp_error(near_root, double(std::nextafter(4.0f, 5.0f))), 1.0);
    EXPECT_EQ(f.root_ulp_error(near_root, std::nextafter(4.0, 5.0)), 0x1p-29);  // 2^−50 / 2^−21

    // ulp(0) is the smallest subnormal of the format.
    const exact_solution on_surface = solve_exact(unit_sphere_ray({0, 0, -1}), precision::binary64);
    EXPECT_EQ(on_surface.root_ulp_error(near_root, 0x1p-1074), 1.0);
    EXPECT_EQ(on_surface.root_ulp_error(near_root, -0.0), 0.0);
    const exact_solution on_surface32 = solve_exact(unit_sphere_ray({0, 0, -1}), precision::binary32);
    EXPECT_EQ(on_surface32.root_ulp_error(near_root, 0x1p-149), 1.0);

    // Subnormal roots: with δ = 2^−1074, o = (0, 0, −5δ), r = δ gives
    // b′ = −5δ, C = 24δ², Δ′ = δ², roots 4δ and 6δ. Below 2^−1022 the ulp is
    // δ itself (not 2^(e − 52)), so 5δ is 1 ulp from 4δ.
    const exact_solution tiny = solve_exact({{0, 0, -5 * 0x1p-1074}, {0, 0, 1}, {0, 0, 0}, 0x1p-1074},
                                            precision::binary64);
    expect_roots(tiny, line_class::two_hit, {1, 4 * 0x1p-1074}, {1, 6 * 0x1p-1074});
    EXPECT_EQ(tiny.root_ulp_error(near_root, 5 * 0x1p-1074), 1.0);
    // The same in float units, 2^−149.
    const exact_solution tiny32 = solve_exact({{0, 0, -5 * 0x1p-149}, {0, 0, 1}, {0, 0, 0}, 0x1p-149},
                                              precision::binary32);
    expect_roots(tiny32, line_class::two_hit, {1, 4 * 0x1p-149}, {1, 6 * 0x1p-149});
    EXPECT_EQ(tiny32.root_ulp_error(far_root, 8 * 0x1p-149), 2.0);
}

TEST(OracleHandCases, RootsBeyondTheFormatRoundToInfinity) {
    // d = (0, 0, 2^−1074): a = 2^−2148, b′ = −5·2^−1074, roots (4, 6)·2^1074,
    // past DBL_MAX < 2^1024; in binary32 the inputs give d = 0 instead.
    const ray_sphere<double> g = unit_sphere_ray({0, 0, -5}, {0, 0, 0x1p-1074});
    const exact_solution s = solve_exact(g, precision::binary64);
    expect_roots(s, line_class::two_hit, {1, inf}, {1, inf});
    // t* = 2^1076, ulp(t*) = 2^1024: DBL_MAX = 2^1024 − 2^971 is
    // 2^52 − 1 + 2^−53 ulps short, which prints as 2^52 − 1.
    EXPECT_EQ(s.root_ulp_error(near_root, std::numeric_limits<double>::max()), 0x1p52 - 1);
    EXPECT_EQ(s.root_ulp_error(near_root, inf), 0.0 + inf);
    EXPECT_EQ(validity<float>(g), invalid_reason::zero_direction);
    // d = (0, 0, 2^−127): roots (4, 6)·2^127 = 2^129, 1.5·2^129; float max is
    // (2 − 2^−23)·2^127, so both round to +inf in binary32, not in binary64.
    const ray_sphere<double> h = unit_sphere_ray({0, 0, -5}, {0, 0, 0x1p-127});
    expect_roots(solve_exact(h, precision::binary32), line_class::two_hit, {1, inf}, {1, inf});
    expect_roots(solve_exact(h, precision::binary64), line_class::two_hit, {1, 0x1p129}, {1, 0x1.8p129});
}

TEST(OracleHandCases, RoundingAtTheOverflowThreshold) {
    // o = (2h, 2h, −M), r = 3h, M the largest finite value, h = ulp(M)/2:
    // b′ = −M, C = 8h² + M² − 9h², Δ′ = h², roots M ∓ h. M − h is halfway
    // between M and its (even) predecessor M − 2h; M + h is the overflow
    // threshold, which IEEE 754 rounds to +∞.
    for (const precision p : {precision::binary64, precision::binary32}) {
        SCOPED_TRACE(precision_name(p));
        const double M = p == precision::binary64 ? std::numeric_limits<double>::max()
                                                  : double(std::numeric_limits<float>::max());
        const double h = p == precision::binary64 ? 0x1p970 : 0x1p103;
        const ray_sphere<double> g{{2 * h, 2 * h, -M}, {0, 0, 1}, {0, 0, 0}, 3 * h};
        const exact_solution s = solve_exact(g, p);
        expect_roots(s, line_class::two_hit, {1, next_down(p, M)}, {1, inf});
        EXPECT_EQ(s.root_ulp_error(near_root, M), 0.5);
        EXPECT_EQ(s.root_ulp_error(far_root, M), 0.5);
        EXPECT_TRUE(agrees_with_reference(g, p));
        // One ulp of r less: Δ′ < h², the far root falls short of the threshold.
        const ray_sphere<double> below{g.origin, g.direction, g.centre, next_down(p, 3 * h)};
        EXPECT_EQ(solve_exact(below, p).far_root.rounded, M);
        EXPECT_TRUE(agrees_with_reference(below, p));
    }
}

TEST(OracleHandCases, ExactTiesRoundToEven) {
    // o = (0, 4h, −1), r = 5h, h = 2^−53: b′ = −1, C = 1 + 16h² − 25h²,
    // Δ′ = 9h², roots 1 ∓ 3h. 1 − 3h is a double (ulp 2^−53 below 1); 1 + 3h
    // is halfway between 1 + 2h and 1 + 4h (ulp 2^−52 above 1), and
    // 1 + 4h = 1 + 2·2^−52 has the even significand.
    constexpr double h = 0x1p-53;
    const exact_solution s = solve_exact({{0, 4 * h, -1}, {0, 0, 1}, {0, 0, 0}, 5 * h}, precision::binary64);
    expect_roots(s, line_class::two_hit, {1, 1 - 3 * h}, {1, 1 + 4 * h});
    EXPECT_EQ(s.root_ulp_error(far_root, 1 + 4 * h), 0.5);
    EXPECT_EQ(s.root_ulp_error(far_root, 1 + 2 * h), 0.5);
    // With o_z = −(1 + 2h) the far root is 1 + 5h, between 1 + 4h and 1 + 6h:
    // now 1 + 6h = 1 + 3·2^−52 is odd and 1 + 4h wins.
    const exact_solution t =
        solve_exact({{0, 4 * h, -(1 + 2 * h)}, {0, 0, 1}, {0, 0, 0}, 5 * h}, precision::binary64);
    expect_roots(t, line_class::two_hit, {1, 1 - h}, {1, 1 + 4 * h});
}

TEST(OracleCrossCheck, RandomTiesRoundToEven) {
    // The tie construction (see tie_case), checked against the even neighbour
    // directly rather than against the reference.
    for (const int p : {53, 24}) {
        const precision prec = p == 53 ? precision::binary64 : precision::binary32;
        for (std::uint64_t seed = 1; seed <= 300; ++seed) {
            SCOPED_TRACE(testing::Message() << "p = " << p << ", seed " << seed);
            std::mt19937_64 rng(seed);
            const tie_case_parts tie = tie_case(rng, p);
            const double lo = tie.far_root_lo, hi = tie.far_root_hi;
            ASSERT_EQ(next_up(prec, lo), hi) << describe(tie.geometry);
            const double lo_significand = std::ldexp(lo, -std::ilogb(lo) + (p - 1));
            const double even = std::fmod(lo_significand, 2.0) == 0 ? lo : hi;
            const exact_solution s = solve_exact(tie.geometry, prec);
            ASSERT_EQ(s.cls, line_class::two_hit);
            EXPECT_EQ(s.far_root.rounded, even) << describe(tie.geometry);
            if (p == 24) {  // (lo + hi)/2 is then a double
                EXPECT_EQ(s.compare_to_root((lo + hi) / 2, far_root), comparison::equal);
            }
            EXPECT_EQ(s.root_ulp_error(far_root, lo), 0.5);
        }
    }
}

// ---------------------------------------------------------------------------
// 2. Invalid inputs are flagged, never crash.

TEST(OracleInvalidInputs, NonFiniteInEveryField) {
    for (int field = 0; field < 10; ++field) {
        for (const double bad : {nan, inf, -inf}) {
            ray_sphere<double> g = unit_sphere_ray({0, 0, -5});
            double* fields[10] = {&g.origin.x, &g.origin.y,    &g.origin.z, &g.direction.x, &g.direction.y,
                                  &g.direction.z, &g.centre.x, &g.centre.y, &g.centre.z,    &g.radius};
            *fields[field] = bad;
            SCOPED_TRACE(testing::Message() << "field " << field << " = " << bad);
            for (const precision p : {precision::binary64, precision::binary32}) {
                const exact_solution s = solve_exact(g, p, 0.0, inf);
                EXPECT_EQ(s.invalid, invalid_reason::non_finite_input);
                EXPECT_FALSE(s.valid());
            }
        }
    }
}

TEST(OracleInvalidInputs, DegenerateGeometry) {
    EXPECT_EQ(solve_exact(unit_sphere_ray({0, 0, -5}, {0, 0, 0}), precision::binary64).invalid,
              invalid_reason::zero_direction);
    EXPECT_EQ(solve_exact(unit_sphere_ray({0, 0, -5}, {-0.0, 0, -0.0}), precision::binary64).invalid,
              invalid_reason::zero_direction);
    EXPECT_EQ(solve_exact({{0, 0, -5}, {0, 0, 1}, {0, 0, 0}, -1}, precision::binary64).invalid,
              invalid_reason::negative_radius);
    EXPECT_EQ(solve_exact({{0, 0, -5}, {0, 0, 1}, {0, 0, 0}, -0x1p-1074}, precision::binary64).invalid,
              invalid_reason::negative_radius);
    // −0 is not negative: a point sphere, valid.
    EXPECT_TRUE(solve_exact({{0, 0, -5}, {0, 0, 1}, {0, 0, 0}, -0.0}, precision::binary64).valid());
    // A finite double can be out of float range, or a direction can flush to 0 in float.
    EXPECT_EQ(validity<float>(unit_sphere_ray({0, 0, -1e39})), invalid_reason::not_representable);
    EXPECT_EQ(validity<float>(unit_sphere_ray({0, 0, -5}, {0, 0, 1e-50})), invalid_reason::zero_direction);
}

TEST(OracleInvalidInputs, BadInterval) {
    const ray_sphere<double> g = unit_sphere_ray({0, 0, -5});
    EXPECT_EQ(solve_exact(g, precision::binary64, 5.0, 4.0).invalid, invalid_reason::bad_interval);
    EXPECT_EQ(solve_exact(g, precision::binary64, inf, -inf).invalid, invalid_reason::bad_interval);
    EXPECT_EQ(solve_exact(g, precision::binary64, nan, 4.0).invalid, invalid_reason::bad_interval);
    EXPECT_EQ(solve_exact(g, precision::binary64, std::nullopt, nan).invalid, invalid_reason::bad_interval);
    // tmin = tmax is a valid (one-point) interval; a bad geometry is reported first.
    EXPECT_TRUE(solve_exact(g, precision::binary64, 4.0, 4.0).valid());
    EXPECT_EQ(solve_exact(unit_sphere_ray({0, 0, -5}, {0, 0, 0}), precision::binary64, 5.0, 4.0).invalid,
              invalid_reason::zero_direction);
}

// ---------------------------------------------------------------------------
// 3. (Which roots lie in a range is the judge's question: judge_test.cpp.)

// ---------------------------------------------------------------------------
// 4. Independent cross-check against the MPFR reference.

constexpr int cases_per_regime = 4000;  // full size under the sanitizers too: the coverage checks below need it

TEST(OracleCrossCheck, AgreesWithMpfrReferenceInEveryRegime) {
    std::uint64_t first_seed = 1;
    for (const regime& r : regimes()) {
        const sweep_tally tally = cross_check(r, first_seed, cases_per_regime);
        first_seed += cases_per_regime;
        std::printf("  %-16s binary64 %d, binary32 %d; miss %d tangent %d two_hit %d; roots: "
                    "subnormal %d, infinite %d, zero %d\n",
                    r.name, tally.checked[0], tally.checked[1], tally.by_class[0], tally.by_class[1],
                    tally.by_class[2], tally.subnormal_roots, tally.infinite_roots, tally.zero_roots);
        // The regimes cover what they claim.
        const std::string name = r.name;
        if (name == "near_tangent") {
            EXPECT_GT(tally.by_class[static_cast<int>(line_class::tangent)], cases_per_regime / 5);
            EXPECT_GT(tally.by_class[static_cast<int>(line_class::miss)], cases_per_regime / 5);
            EXPECT_GT(tally.by_class[static_cast<int>(line_class::two_hit)], cases_per_regime / 5);
        }
        if (name == "far" || name == "uniform") {
            EXPECT_GT(tally.by_class[static_cast<int>(line_class::miss)], cases_per_regime / 10);
            EXPECT_GT(tally.by_class[static_cast<int>(line_class::two_hit)], cases_per_regime / 10);
        }
        if (name == "subnormal") {
            EXPECT_GT(tally.subnormal_roots, cases_per_regime / 10);
            EXPECT_GT(tally.infinite_roots, cases_per_regime / 10);
        }
        if (name == "grazing_extreme") {
            for (const int n : tally.by_class) EXPECT_GT(n, cases_per_regime / 50);
        }
        if (name == "integer") {
            EXPECT_GT(tally.zero_roots, cases_per_regime / 20);
        }
        if (name != "extreme_scale" && name != "tie_binary64" && name != "grazing_extreme") {
            EXPECT_GT(tally.checked[1], cases_per_regime / 2);
        }
    }
}

// 200 000 cases; labelled as a long test by the build.
TEST(LongSweepOracle, AgreesWithMpfrReference) {
    constexpr int per_regime = 20'000;  // × 10 regimes
    std::uint64_t first_seed = 1'000'000;
    for (const regime& r : regimes()) {
        cross_check(r, first_seed, per_regime);
        first_seed += per_regime;
    }
}

// ---------------------------------------------------------------------------
// 5. Metamorphic identities, exact on the rounded values.

// Inputs on a grid k·2^−s with |k| < 2^b, so that sums of two stay exact in
// the precision (b + 2 < p) and translations are exact.
ray_sphere<double> grid_case(std::mt19937_64& rng, precision p) {
    const long span = p == precision::binary64 ? (1L << 30) : (1L << 10);
    const int shift = p == precision::binary64 ? -20 : -6;
    auto coordinate = [&] { return std::ldexp(double(uniform_int(rng, -span, span)), shift); };
    auto point = [&] { return vec3<double>{coordinate(), coordinate(), coordinate()}; };
    vec3<double> d = point();
    while (d == vec3<double>{}) d = point();
    const vec3<double> o = point();
    // Aim near the centre half of the time so that hits are common.
    const vec3<double> c = (rng() & 1) ? point() : o + vec3<double>{coordinate(), coordinate(), coordinate()};
    return {o, d, c, std::ldexp(double(uniform_int(rng, 1, span)), shift)};
}

// The metamorphic inputs: grid cases and exact near-tangents.
ray_sphere<double> metamorphic_case(std::mt19937_64& rng, precision p) {
    if (rng() % 3 == 0) {
        ray_sphere<double> g = near_tangent_case(rng);
        if (validity<float>(g) == invalid_reason::none && std::abs(std::ilogb(g.radius)) < 100) return g;
    }
    return grid_case(rng, p);
}

testing::AssertionResult same_solution(const exact_solution& a, const exact_solution& b) {
    if (a.cls == b.cls &&
        (a.cls == line_class::miss ||
         (a.near_root.sign == b.near_root.sign && a.far_root.sign == b.far_root.sign &&
          a.near_root.rounded == b.near_root.rounded && a.far_root.rounded == b.far_root.rounded)))
        return testing::AssertionSuccess();
    return testing::AssertionFailure() << line_class_name(a.cls) << " " << hex(a.near_root.rounded) << " "
                                       << hex(a.far_root.rounded) << " vs " << line_class_name(b.cls) << " "
                                       << hex(b.near_root.rounded) << " " << hex(b.far_root.rounded);
}

constexpr int metamorphic_cases = 400;

template <class Check>
void for_metamorphic_cases(std::uint64_t first_seed, Check check) {
    for (const precision p : {precision::binary64, precision::binary32}) {
        for (int i = 0; i < metamorphic_cases; ++i) {
            const std::uint64_t seed = first_seed + static_cast<std::uint64_t>(i);
            SCOPED_TRACE(testing::Message() << precision_name(p) << ", seed " << seed);
            std::mt19937_64 rng(seed);
            ray_sphere<double> g = metamorphic_case(rng, p);
            ASSERT_EQ(validity<float>(g), invalid_reason::none) << describe(g);
            if (p == precision::binary32) g = float_inputs(g);
            check(g, p, rng);
        }
    }
}

TEST(OracleMetamorphic, NegatingDirectionSwapsAndNegatesRoots) {
    // t ↦ −t maps the line o + t·d onto o + t·(−d); RN is odd, so the
    // rounded roots negate exactly too.
    for_metamorphic_cases(10'000, [](const ray_sphere<double>& g, precision p, std::mt19937_64&) {
        const exact_solution s = solve_exact(g, p);
        const exact_solution m = solve_exact({g.origin, -1.0 * g.direction, g.centre, g.radius}, p);
        ASSERT_EQ(s.cls, m.cls) << describe(g);
        if (s.cls == line_class::miss) return;
        EXPECT_EQ(m.near_root.sign, -s.far_root.sign) << describe(g);
        EXPECT_EQ(m.far_root.sign, -s.near_root.sign) << describe(g);
        EXPECT_EQ(m.near_root.rounded, -s.far_root.rounded) << describe(g);
        EXPECT_EQ(m.far_root.rounded, -s.near_root.rounded) << describe(g);
    });
}

TEST(OracleMetamorphic, ScalingEverythingLeavesRootsAndScalingDirectionDividesThem) {
    // o, d, c, r all times 2^k: a, b′, C and Δ′ all gain 4^k, roots unchanged.
    // d alone times 2^k: a → 4^k a, b′ → 2^k b′, Δ′ → 4^k Δ′, roots t/2^k —
    // and RN(t/2^k) = RN(t)/2^k while nothing reaches the subnormals.
    for_metamorphic_cases(20'000, [](const ray_sphere<double>& g, precision p, std::mt19937_64& rng) {
        // Float roots can be as small as ~2^−102: |k| ≤ 20 keeps them normal.
        const int k_max = p == precision::binary64 ? 40 : 20;
        const int k = static_cast<int>(uniform_int(rng, -k_max, k_max));
        const exact_solution s = solve_exact(g, p);
        const ray_sphere<double> all_scaled{scaled(g.origin, k), scaled(g.direction, k), scaled(g.centre, k),
                                            std::ldexp(g.radius, k)};
        const exact_solution all = solve_exact(all_scaled, p);
        EXPECT_TRUE(same_solution(s, all)) << describe(g) << " k = " << k;
        const exact_solution dir = solve_exact({g.origin, scaled(g.direction, k), g.centre, g.radius}, p);
        ASSERT_EQ(s.cls, dir.cls) << describe(g) << " k = " << k;
        if (s.cls == line_class::miss) return;
        EXPECT_EQ(dir.near_root.rounded, std::ldexp(s.near_root.rounded, -k)) << describe(g) << " k = " << k;
        EXPECT_EQ(dir.far_root.rounded, std::ldexp(s.far_root.rounded, -k)) << describe(g) << " k = " << k;
        EXPECT_EQ(dir.near_root.sign, s.near_root.sign);
        EXPECT_EQ(dir.far_root.sign, s.far_root.sign);
    });
}

// x + y is exact in the precision (Knuth's TwoSum error is zero).
bool sum_is_exact(double x, double y, precision p) {
    if (p == precision::binary32) {
        const float fx = static_cast<float>(x), fy = static_cast<float>(y), s = fx + fy;
        return double(s) == x + y;
    }
    const double s = x + y, yy = s - x, xx = s - yy;
    return (x - xx) + (y - yy) == 0;
}

// Exponent of the lowest set bit of x ≠ 0.
int lowest_bit(double x) {
    int e = 0;
    const double m = std::frexp(std::fabs(x), &e);
    return e - 53 + std::countr_zero(static_cast<std::uint64_t>(std::ldexp(m, 53)));
}

TEST(OracleMetamorphic, TranslatingOriginAndCentreChangesNothing) {
    for_metamorphic_cases(30'000, [](const ray_sphere<double>& g, precision p, std::mt19937_64& rng) {
        // v = integers times 2^lo, lo the lowest bit of any coordinate of o or
        // c, and no larger than 2^(p−3+lo): o + v and c + v then span at most
        // p − 1 bits and are exact.
        int lo = std::numeric_limits<int>::max(), hi = std::numeric_limits<int>::min();
        for (const vec3<double>& point : {g.origin, g.centre})
            for (int axis = 0; axis < 3; ++axis)
                if (point[axis] != 0) {
                    lo = std::min(lo, lowest_bit(point[axis]));
                    hi = std::max(hi, std::ilogb(point[axis]));
                }
        if (lo > hi) lo = hi = 0;  // o = c = 0
        const int bits = std::max(0, significand_bits(p) - 3 - (hi - lo));
        const long span = (1L << std::min(bits, 40)) - 1;
        const vec3<double> v{std::ldexp(double(uniform_int(rng, -span, span)), lo),
                             std::ldexp(double(uniform_int(rng, -span, span)), lo),
                             std::ldexp(double(uniform_int(rng, -span, span)), lo)};
        for (int axis = 0; axis < 3; ++axis) {
            ASSERT_TRUE(sum_is_exact(g.origin[axis], v[axis], p)) << describe(g);
            ASSERT_TRUE(sum_is_exact(g.centre[axis], v[axis], p)) << describe(g);
        }
        const exact_solution s = solve_exact(g, p);
        const exact_solution moved = solve_exact({g.origin + v, g.direction, g.centre + v, g.radius}, p);
        EXPECT_TRUE(same_solution(s, moved)) << describe(g) << " moved by (" << hex(v.x) << ", " << hex(v.y)
                                             << ", " << hex(v.z) << ")";
    });
}

TEST(OracleMetamorphic, PermutingAndReflectingAxesChangesNothing) {
    for_metamorphic_cases(40'000, [](const ray_sphere<double>& g, precision p, std::mt19937_64& rng) {
        const axis_map m = random_axis_map(rng);
        const exact_solution s = solve_exact(g, p);
        const exact_solution mapped = solve_exact(m(g), p);
        EXPECT_TRUE(same_solution(s, mapped)) << describe(g);
        // The hit point moves with the axes (RN is odd, so reflection commutes with it).
        if (s.nearest_in_front) {
            EXPECT_EQ(mapped.hit_point(), m(s.hit_point())) << describe(g);
        }
    });
}

// ---------------------------------------------------------------------------
// 6. Hit points and ulp errors are consistent with the rounding.

TEST(OracleHitPoint, HandCases) {
    // Irrational case: o + (5 ∓ √2)·d = (½, 0, ∓√2). std::sqrt is correctly
    // rounded (IEEE 754), so RN(−√2) = −std::sqrt(2.0). Note that −5 + RN(5 − √2)
    // = −0x1.6a09e667f3bccp+0 is one ulp off: the hit point is rounded from
    // the exact root, not computed from the rounded one.
    const exact_solution s = solve_exact(irrational_case, precision::binary64);
    EXPECT_EQ(s.hit_point(), (vec3<double>{0.5, 0, -std::sqrt(2.0)}));
    EXPECT_NE(s.hit_point().z, -5 + s.near_root.rounded);
    EXPECT_EQ(s.rounded_hit_coordinate(far_root, 2), std::sqrt(2.0));
    EXPECT_EQ(s.rounded_hit_coordinate(far_root, 0), 0.5);
    EXPECT_EQ(s.hit_point_ulp_error(near_root, 0, 0.5), 0.0);
    EXPECT_LE(s.hit_point_ulp_error(near_root, 2, -std::sqrt(2.0)), 0.5);
    EXPECT_GT(s.hit_point_ulp_error(near_root, 2, -5 + s.near_root.rounded), 0.5);

    const exact_solution f = solve_exact(irrational_case, precision::binary32);
    EXPECT_EQ(f.hit_point(), (vec3<double>{0.5, 0, double(-std::sqrt(2.0f))}));
    EXPECT_LE(f.hit_point_ulp_error(near_root, 2, double(-std::sqrt(2.0f))), 0.5);

    // Integer cases are exact: error 0 at the exact coordinate, 1 one ulp off.
    const exact_solution t = solve_exact(unit_sphere_ray({1, 0, -5}), precision::binary64);
    EXPECT_EQ(t.hit_point(), (vec3<double>{1, 0, 0}));
    EXPECT_EQ(t.hit_point_ulp_error(near_root, 0, 1.0), 0.0);
    EXPECT_EQ(t.hit_point_ulp_error(near_root, 0, std::nextafter(1.0, 2.0)), 1.0);
    EXPECT_EQ(t.hit_point_ulp_error(near_root, 2, 0x1p-1074), 1.0);  // z = 0: ulp(0) = 2^−1074
}

TEST(OracleHitPoint, RoundedValuesAreNearestByUlpError) {
    // For every root and hit coordinate: the rounded value is within ½ ulp and
    // both of its neighbours are at least ½ ulp away.
    int checked = 0;
    for (const precision p : {precision::binary64, precision::binary32}) {
        for (std::uint64_t seed = 50'000; seed < 50'300; ++seed) {
            SCOPED_TRACE(testing::Message() << precision_name(p) << ", seed " << seed);
            std::mt19937_64 rng(seed);
            ray_sphere<double> g = metamorphic_case(rng, p);
            if (p == precision::binary32) g = float_inputs(g);
            const exact_solution s = solve_exact(g, p);
            if (s.cls == line_class::miss) continue;
            auto check = [&](double rounded, auto error_of) {
                if (!std::isfinite(rounded)) return;
                EXPECT_LE(error_of(rounded), 0.5) << describe(g);
                EXPECT_GE(error_of(next_up(p, rounded)), 0.5) << describe(g);
                EXPECT_GE(error_of(next_down(p, rounded)), 0.5) << describe(g);
                ++checked;
            };
            for (const root_index i : {near_root, far_root}) {
                check(s.root(i).rounded, [&](double v) { return s.root_ulp_error(i, v); });
                for (int axis = 0; axis < 3; ++axis) {
                    check(s.rounded_hit_coordinate(i, axis),
                          [&](double v) { return s.hit_point_ulp_error(i, axis, v); });
                }
            }
        }
    }
    EXPECT_GT(checked, 1000);
}

}  // namespace
}  // namespace rayverify
