// The static filter (oracle/static_filter.h) against the exact route: every
// answer it certifies — the class, the roots' signs and correct roundings,
// the front root's hit point — equals solve_exact_reference's bit for bit,
// and every root enclosure it hands on holds the exact root. Random and
// constructed cases: uniform, far spheres, near-tangent lines, origins on,
// at the centre of and near the sphere, b′ = 0, huge and tiny magnitudes
// across the filter range, small integers, roots on rounding midpoints; both
// precisions. Every random test prints its seed; a failure prints the case
// as hex floats.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <sstream>
#include <string>

#include "corpus/corpus_io.h"
#include "oracle/filter.h"
#include "oracle/oracle.h"
#include "oracle/static_filter.h"
#include "support/random_geometry.h"
#include "support/sanitized.h"

namespace rayverify {
namespace {

constexpr double inf = std::numeric_limits<double>::infinity();

std::string describe(const ray_sphere<double>& g) {
    std::ostringstream out;
    out << "o " << hex_float(g.origin.x) << " " << hex_float(g.origin.y) << " " << hex_float(g.origin.z) << "  d " << hex_float(g.direction.x)
        << " " << hex_float(g.direction.y) << " " << hex_float(g.direction.z) << "  c " << hex_float(g.centre.x) << " "
        << hex_float(g.centre.y) << " " << hex_float(g.centre.z) << "  r " << hex_float(g.radius);
    return out.str();
}

bool same_bits(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }

using test_support::aimed_uniform_case;
using test_support::integer_case;
using test_support::near_tangent_case;
using test_support::on_surface_case;
using test_support::scaled;
using test_support::tie_case;
using test_support::uniform;
using test_support::uniform_point;
using test_support::unit_vector;

// Distance/radius 10 to 10^15, origin or centre near 0, d unit or not.
ray_sphere<double> far_case(std::mt19937_64& rng) {
    const double distance = std::pow(10.0, uniform(rng, 1, 15));
    const double r = uniform(rng, 0.5, 2);
    const vec3<double> near = uniform_point(rng, 1);
    const vec3<double> far = near + distance * unit_vector(rng);
    const bool origin_far = rng() & 1;
    const vec3<double> o = origin_far ? far : near, c = origin_far ? near : far;
    const vec3<double> target = c + (r * uniform(rng, 0, 1.5)) * unit_vector(rng);
    const double length = (rng() & 1) ? 1.0 : uniform(rng, 0.1, 10);
    vec3<double> d = target - o;
    const double norm = std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
    return {o, (length / norm) * d, c, r};
}

// Origin within r·2^−k of the surface, inside or out (C cancels): k in [1, 60].
ray_sphere<double> near_surface_case(std::mt19937_64& rng) {
    const vec3<double> c = uniform_point(rng, 10);
    const double r = uniform(rng, 0.1, 5);
    const double eps = std::ldexp((rng() & 1) ? 1.0 : -1.0, -static_cast<int>(1 + rng() % 60));
    return {c + (r * (1 + eps)) * unit_vector(rng), uniform_point(rng, 2), c, r};
}

// b′ = 0 exactly: the origin at the centre, or d ⊥ f with small integers.
ray_sphere<double> zero_b_case(std::mt19937_64& rng) {
    const auto small = [&rng] { return static_cast<double>(static_cast<int>(rng() % 17) - 8); };
    const vec3<double> c{small(), small(), small()};
    if (rng() & 1) return {c, unit_vector(rng), c, uniform(rng, 0.1, 5)};
    vec3<double> f{small(), small(), 0};
    if (f.x == 0 && f.y == 0) f.x = 1;
    const vec3<double> d{-f.y, f.x, small()};
    return {c + f, d, c, std::fabs(small()) + 0.5};
}

// A uniform or far case with positions scaled by 2^s and d by 2^s′, s and s′
// in [−110, 110]: across and beyond the filter range [2^−80, 2^80].
ray_sphere<double> magnitude_case(std::mt19937_64& rng) {
    ray_sphere<double> g = (rng() & 1) ? aimed_uniform_case(rng) : far_case(rng);
    const int s = static_cast<int>(rng() % 221) - 110, sd = static_cast<int>(rng() % 221) - 110;
    g.origin = scaled(g.origin, s);
    g.centre = scaled(g.centre, s);
    g.radius = std::ldexp(g.radius, s);
    g.direction = scaled(g.direction, sd);
    return g;
}

struct regime {
    const char* name;
    ray_sphere<double> (*make)(std::mt19937_64&);
};

const regime regimes[] = {
    {"uniform", aimed_uniform_case},
    {"far", far_case},
    {"near_tangent", near_tangent_case},
    {"on_surface", on_surface_case},
    {"near_surface", near_surface_case},
    {"zero_b", zero_b_case},
    {"magnitudes", magnitude_case},
    {"integers", integer_case},
    {"tie_binary64", [](std::mt19937_64& rng) { return tie_case(rng, 53); }},
    {"tie_binary32", [](std::mt19937_64& rng) { return tie_case(rng, 24); }},
};

struct tally {
    std::size_t solutions = 0, certified = 0, misses = 0;
    std::size_t signs_certified = 0;  // by static_class_and_signs
};

// Whatever the static filter certifies for g in precision p is the exact
// route's answer, and its root enclosures hold the exact roots: t* − y, for
// y = RN(hi + lo) in double, is ±ratio·ulp(t*) with the exact sign of
// compare_to_root(y, i) and the reference's ULP error `ratio` (correctly rounded,
// so within a relative 2^−53), and must meet [hi + lo − y − err, hi + lo − y + err].
testing::AssertionResult certified_answers_are_exact(const ray_sphere<double>& g, precision p, tally& t) {
    ++t.solutions;
    oracle_internal::certified_signs signs;
    const bool signs_certified = oracle_internal::static_class_and_signs(g, signs);
    std::optional<oracle_internal::filtered_case> quick(std::in_place);
    const bool certified = oracle_internal::static_filter_case(g, p, *quick);
    if (!signs_certified && !certified) return testing::AssertionSuccess();
    const exact_solution ref = solve_exact_reference(g, p);
    std::ostringstream why;
    const auto check = [&](bool ok, const std::string& what) {
        if (!ok) why << "\n  " << what;
    };
    // The class and signs alone (static_class_and_signs): the reference's,
    // and settled wherever the whole static filter settles the case.
    check(signs_certified || !certified, "the whole static filter settled a case the class and signs alone did not");
    if (signs_certified) {
        ++t.signs_certified;
        check(ref.valid(), "class and signs certified for an invalid case");
        const line_class cls = signs.discriminant_sign > 0 ? line_class::two_hit : line_class::miss;
        check(cls == ref.cls, std::string("class and signs: class ") + line_class_name(cls) + ", exact " +
                                  line_class_name(ref.cls));
        if (ref.valid() && cls == line_class::two_hit && ref.cls == line_class::two_hit)
            for (root_index i : {root_index::near_root, root_index::far_root})
                check(signs.root_sign[i == root_index::near_root ? 0 : 1] == ref.root(i).sign,
                      std::string("class and signs: ") + (i == root_index::near_root ? "near" : "far") +
                          " sign differs");
    }
    if (!certified) {
        if (why.str().empty()) return testing::AssertionSuccess();
        return testing::AssertionFailure() << precision_name(p) << " " << describe(g) << why.str();
    }
    ++t.certified;
    check(ref.valid(), "certified an invalid case");
    if (!ref.valid()) return testing::AssertionFailure() << describe(g) << why.str();
    const line_class cls = *quick->discriminant_sign > 0 ? line_class::two_hit : line_class::miss;
    check(cls == ref.cls, std::string("class: static ") + line_class_name(cls) + ", exact " + line_class_name(ref.cls));
    if (cls == line_class::miss) ++t.misses;
    if (cls == line_class::two_hit && ref.cls == line_class::two_hit) {
        for (root_index i : {root_index::near_root, root_index::far_root}) {
            const int k = i == root_index::near_root ? 0 : 1;
            const std::string name = k == 0 ? "near" : "far";
            check(quick->sign[k] && *quick->sign[k] == ref.root(i).sign, name + " sign differs");
            check(quick->rounded[k] && same_bits(*quick->rounded[k], ref.root(i).rounded),
                  name + " rounded: static " + (quick->rounded[k] ? hex_float(*quick->rounded[k]) : "-") + ", exact " +
                      hex_float(ref.root(i).rounded));
            // The enclosure holds t*: exactly 0 for a root 0 (an origin on the sphere).
            const exact_solution::enclosure& e = quick->roots[k];
            if (ref.root(i).sign == 0) {
                check(e.hi == 0 && e.lo == 0 && e.err == 0, name + " root is 0, its enclosure " + hex_float(e.hi) +
                                                                " + " + hex_float(e.lo) + " ± " + hex_float(e.err));
                continue;
            }
            const double y = e.hi + e.lo;
            const int side = static_cast<int>(ref.compare_to_root(y, i));  // sign(y − t*)
            const double ratio = solve_exact_reference(g, precision::binary64).root_ulp_error(i, y);
            const double ulp = std::ldexp(1.0, std::ilogb(y) - 52);
            const double exact_offset = -side * ratio * ulp;  // t* − y, within a relative 2^−53
            const double low = (e.hi - y) + e.lo - e.err, high = (e.hi - y) + e.lo + e.err;
            const double slack = std::fabs(exact_offset) * 0x1p-51 + std::fabs(y) * 0x1p-160;
            check(exact_offset + slack >= low && exact_offset - slack <= high,
                  name + " enclosure " + hex_float(e.hi) + " + " + hex_float(e.lo) + " ± " + hex_float(e.err) + " misses t* = y + " +
                      hex_float(exact_offset));
        }
        check(quick->sign[0] && quick->sign[1], "signs not both certified");
        if (ref.nearest_in_front) {
            for (int axis = 0; axis < 3; ++axis)
                check(quick->hit[axis] && same_bits(*quick->hit[axis], ref.hit_point()[axis]),
                      "hit_point[" + std::to_string(axis) + "]: static " +
                          (quick->hit[axis] ? hex_float(*quick->hit[axis]) : "-") + ", exact " + hex_float(ref.hit_point()[axis]));
        }
    }
    if (why.str().empty()) return testing::AssertionSuccess();
    return testing::AssertionFailure() << precision_name(p) << " " << describe(g) << why.str();
}

// `count` cases of every regime from `seed` (stopping after `budget` seconds), both precisions.
tally sweep(std::uint64_t seed, int count, double budget) {
    tally t;
    const auto start = std::chrono::steady_clock::now();
    for (int i = 0; i < count; ++i) {
        for (const regime& r : regimes) {
            const std::uint64_t case_seed = seed + static_cast<std::uint64_t>(i);
            std::mt19937_64 rng(case_seed ^ std::hash<std::string>{}(r.name));
            const ray_sphere<double> g = r.make(rng);
            if (validity<double>(g) != invalid_reason::none) continue;
            EXPECT_TRUE(certified_answers_are_exact(g, precision::binary64, t))
                << "regime " << r.name << ", case seed " << case_seed;
            if (validity<float>(g) == invalid_reason::none) {
                EXPECT_TRUE(certified_answers_are_exact(rounded_to(precision::binary32, g), precision::binary32, t))
                    << "regime " << r.name << ", case seed " << case_seed;
            }
            if (testing::Test::HasFailure()) return t;
        }
        if (i % 1024 == 0 &&
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > budget)
            break;
    }
    return t;
}

TEST(StaticFilter, CertifiedAnswersAreExact) {
    const std::uint64_t seed = 20261127;
    std::printf("seed %llu\n", static_cast<unsigned long long>(seed));
    const tally t = sweep(seed, test_support::sweep_size(20000), 1e9);
    std::printf("%zu solutions, %zu certified by the static filter (%zu misses), %zu classes and signs\n",
                t.solutions, t.certified, t.misses, t.signs_certified);
    EXPECT_GT(t.certified, t.solutions / 3);
    EXPECT_GE(t.signs_certified, t.certified);
}

TEST(LongSweepStaticFilter, CertifiedAnswersAreExactOnMillions) {
    const std::uint64_t seed = std::random_device{}();
    std::printf("seed %llu\n", static_cast<unsigned long long>(seed));
    const tally t = sweep(seed, 400000, 80);
    std::printf("%zu solutions, %zu certified by the static filter (%zu misses), %zu classes and signs\n",
                t.solutions, t.certified, t.misses, t.signs_certified);
}

// The filter range of one input and of a whole case (two inputs at a time)
// against its definition: every input 0 or 2^−80 ≤ |x| ≤ 2^80. Each case
// puts one value from the range's edges (and beyond them: subnormals,
// infinities, NaN) into a random slot among in-range values, or two such
// values, or none.
TEST(FilterRange, AWholeCaseIsInRangeWhenEachInputIs) {
    const std::uint64_t seed = std::random_device{}();
    std::printf("seed %llu\n", static_cast<unsigned long long>(seed));
    std::mt19937_64 rng(seed);
    const double edges[] = {0.0, -0.0, 0x1p-80, -0x1p-80, std::nextafter(0x1p-80, 0.0), std::nextafter(0x1p-80, 1.0),
                            0x1p80, -0x1p80, std::nextafter(0x1p80, inf), std::nextafter(0x1p80, 0.0), 0x1p-1074,
                            -0x1p-1022, inf, -inf, std::numeric_limits<double>::quiet_NaN(), 1.5, -3.0, 0x1p-81,
                            0x1.8p80, std::numeric_limits<double>::max()};
    const auto defined_in_range = [](double x) {
        return x == 0 || (std::fabs(x) >= 0x1p-80 && std::fabs(x) <= 0x1p80);
    };
    const auto random_in_range = [&rng] {
        return std::ldexp(test_support::uniform(rng, 1, 2), static_cast<int>(rng() % 161) - 80) * ((rng() & 1) ? 1 : -1);
    };
    int failures = 0, inside = 0;
    for (int i = 0; i < 200000 && failures < 5; ++i) {
        double inputs[10];
        for (double& x : inputs) x = random_in_range();
        for (int k = static_cast<int>(rng() % 3); k > 0; --k) inputs[rng() % 10] = edges[rng() % std::size(edges)];
        const ray_sphere<double> g{{inputs[0], inputs[1], inputs[2]},
                                   {inputs[3], inputs[4], inputs[5]},
                                   {inputs[6], inputs[7], inputs[8]},
                                   inputs[9]};
        bool expected = true;
        for (const double x : inputs) {
            expected = expected && defined_in_range(x);
            if (oracle_internal::in_filter_range(x) != defined_in_range(x))
                ++failures, ADD_FAILURE() << "input " << hex_float(x);
        }
        inside += expected;
        if (oracle_internal::in_filter_range(g) != expected) ++failures, ADD_FAILURE() << describe(g);
    }
    EXPECT_EQ(failures, 0) << "seed " << seed;
    EXPECT_GT(inside, 20000);
}

// What it settles and what it leaves: ordinary cases all certified, and an
// origin exactly on the sphere (C = 0 decided exactly); a tangent, an origin
// near the sphere, a root on a rounding midpoint, inputs outside the filter
// range and the unit-direction idealisation never.
TEST(StaticFilter, SettlesOrdinaryCasesAndDeclinesStiffOnes) {
    std::mt19937_64 rng(5);
    int certified = 0;
    oracle_internal::filtered_case out;
    for (int i = 0; i < 2000; ++i) certified += oracle_internal::static_filter_case(aimed_uniform_case(rng), precision::binary64, out);
    EXPECT_GE(certified, 1990) << certified << " of 2000";
    const auto certifies = [](const ray_sphere<double>& g, precision p = precision::binary64) {
        oracle_internal::filtered_case out;
        return oracle_internal::static_filter_case(g, p, out);
    };
    EXPECT_FALSE(certifies({{1, 0, -5}, {0, 0, 1}, {0, 0, 0.25}, 1}));          // tangent: Δ′ = 0
    EXPECT_FALSE(certifies({{0, 0, -(1 + 0x1p-52)}, {0, 0, 1}, {0, 0, 0}, 1}));  // origin near the sphere: C ≈ 2^−51
    EXPECT_FALSE(certifies({{0, 0x1p-30, -1}, {0, 0, 1}, {0, 0, 0}, 1}));        // the same, C = 2^−60
    EXPECT_FALSE(certifies(tie_case(rng, 53)));                                  // a root on a midpoint
    EXPECT_FALSE(certifies({{0, 0, -0x1p900}, {0, 0, 1}, {0, 0, 0}, 0x1p899}));  // outside [2^−80, 2^80]
    EXPECT_FALSE(certifies({{1, 0, -(1 + 0x1p-24)}, {0, 0, 1}, {0, 0, 0}, 1}, precision::binary32));
    EXPECT_TRUE(certifies({{0.25, 0.125, -5}, {0, 0, 1}, {0, 0, 0}, 1}));
    // An origin on the sphere, worked by hand: o = (0, 0, −1), d = (0, 0, 1),
    // c = 0, r = 1: a = 1, b′ = −1, C = 0, so t = 0 (sign 0, +0) and t = 2,
    // the hit point (0, 0, 1).
    oracle_internal::filtered_case on_sphere;
    ASSERT_TRUE(oracle_internal::static_filter_case({{0, 0, -1}, {0, 0, 1}, {0, 0, 0}, 1}, precision::binary64, on_sphere));
    EXPECT_EQ(*on_sphere.discriminant_sign, 1);
    EXPECT_EQ(*on_sphere.sign[0], 0);
    EXPECT_TRUE(same_bits(*on_sphere.rounded[0], 0.0));
    EXPECT_EQ(on_sphere.roots[0].hi, 0);
    EXPECT_EQ(on_sphere.roots[0].err, 0);
    EXPECT_EQ(*on_sphere.sign[1], 1);
    EXPECT_EQ(*on_sphere.rounded[1], 2.0);
    EXPECT_EQ(*on_sphere.hit[2], 1.0);
    // Behind it, d reversed: t = −2 and t = 0; no root in front, no hit point.
    ASSERT_TRUE(oracle_internal::static_filter_case({{0, 0, -1}, {0, 0, -1}, {0, 0, 0}, 1}, precision::binary64, on_sphere = {}));
    EXPECT_EQ(*on_sphere.rounded[0], -2.0);
    EXPECT_EQ(*on_sphere.sign[1], 0);
    EXPECT_TRUE(same_bits(*on_sphere.rounded[1], 0.0));
    EXPECT_FALSE(on_sphere.hit[2]);
    // The oracle counts a zero root as settled by expansions (C = 0 exactly).
    EXPECT_EQ(solve_exact({{0, 0, -1}, {0, 0, 1}, {0, 0, 0}, 1}, precision::binary64).stage, oracle_stage::expansion);
    // A miss, certified.
    oracle_internal::filtered_case miss;
    ASSERT_TRUE(oracle_internal::static_filter_case({{3, 0, -5}, {0, 0, 1}, {0, 0, 0}, 1}, precision::binary64, miss));
    EXPECT_EQ(*miss.discriminant_sign, -1);
    // The oracle counts it as its filter stage.
    EXPECT_EQ(solve_exact({{0.25, 0.125, -5}, {0, 0, 1}, {0, 0, 0}, 1}, precision::binary64).stage,
              oracle_stage::filter);
}

// The class and signs alone, worked by hand: d = (0, 0, 1), c = 0, r = 1, so
// a = 1, b′ = o_z, C = |o|² − 1 and Δ′ = 1 − o_x² − o_y².
TEST(StaticFilter, ClassAndSignsWorkedByHand) {
    const auto signs_of = [](const ray_sphere<double>& g) {
        oracle_internal::certified_signs signs;
        return oracle_internal::static_class_and_signs(g, signs) ? std::optional(signs) : std::nullopt;
    };
    // In front: b′ = −5, C = 24.078125 > 0, Δ′ = 0.921875: both roots ahead.
    const auto ahead = signs_of({{0.25, 0.125, -5}, {0, 0, 1}, {0, 0, 0}, 1});
    ASSERT_TRUE(ahead);
    EXPECT_EQ(ahead->discriminant_sign, 1);
    EXPECT_EQ(ahead->root_sign[0], 1);
    EXPECT_EQ(ahead->root_sign[1], 1);
    // Behind: b′ = 5, the same C: both roots behind.
    const auto behind = signs_of({{0.25, 0.125, 5}, {0, 0, 1}, {0, 0, 0}, 1});
    ASSERT_TRUE(behind);
    EXPECT_EQ(behind->root_sign[0], -1);
    EXPECT_EQ(behind->root_sign[1], -1);
    // Inside: C = −0.75: one root behind, one ahead, whatever b′.
    const auto inside = signs_of({{0, 0, 0.5}, {0, 0, 1}, {0, 0, 0}, 1});
    ASSERT_TRUE(inside);
    EXPECT_EQ(inside->root_sign[0], -1);
    EXPECT_EQ(inside->root_sign[1], 1);
    // A miss: Δ′ = 1 − 9 < 0.
    const auto miss = signs_of({{3, 0, -5}, {0, 0, 1}, {0, 0, 0}, 1});
    ASSERT_TRUE(miss);
    EXPECT_EQ(miss->discriminant_sign, -1);
    // On the sphere: C = 0 exactly, b′ = −1: the roots 0 and 2; b′ = 1: −2 and 0.
    const auto on_sphere = signs_of({{0, 0, -1}, {0, 0, 1}, {0, 0, 0}, 1});
    ASSERT_TRUE(on_sphere);
    EXPECT_EQ(on_sphere->discriminant_sign, 1);
    EXPECT_EQ(on_sphere->root_sign[0], 0);
    EXPECT_EQ(on_sphere->root_sign[1], 1);
    const auto on_sphere_behind = signs_of({{0, 0, 1}, {0, 0, 1}, {0, 0, 0}, 1});
    ASSERT_TRUE(on_sphere_behind);
    EXPECT_EQ(on_sphere_behind->root_sign[0], -1);
    EXPECT_EQ(on_sphere_behind->root_sign[1], 0);
    // Declined: a tangent (Δ′ = 0), an origin near the sphere (C = 2^−60), a
    // zero direction and a negative radius (not valid), an input outside the range.
    EXPECT_FALSE(signs_of({{1, 0, -5}, {0, 0, 1}, {0, 0, 0}, 1}));
    EXPECT_FALSE(signs_of({{0, 0x1p-30, -1}, {0, 0, 1}, {0, 0, 0}, 1}));
    EXPECT_FALSE(signs_of({{0.25, 0.125, -5}, {0, 0, 0}, {0, 0, 0}, 1}));
    EXPECT_FALSE(signs_of({{0.25, 0.125, -5}, {0, 0, 1}, {0, 0, 0}, -1}));
    EXPECT_FALSE(signs_of({{0, 0, -0x1p900}, {0, 0, 1}, {0, 0, 0}, 0x1p899}));
    // A far sphere, where b′² − aC cancels: Lagrange's form settles it.
    const auto far = signs_of({{0, 0.5, -0x1p40}, {0, 0, 1}, {0, 0, 0}, 1});
    ASSERT_TRUE(far);
    EXPECT_EQ(far->discriminant_sign, 1);
    EXPECT_EQ(far->root_sign[0], 1);
}

}  // namespace
}  // namespace rayverify
