// The algebraic route (CGAL::Sqrt_extension over Gmpq, src/oracle/algebraic_route.cpp)
// against hand-worked exact answers, then against the exact oracle
// (solve_exact), bit for bit: class, signs, rounded roots, nearest root in
// front, hit point and the comparisons with an interval's ends, on every
// shipped corpus file and on random and constructed cases in both precisions.
// Random tests print their seed (RAYVERIFY_ALGEBRAIC_SEED replays one); a
// failure prints the case as a corpus line.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <span>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "corpus/corpus_io.h"
#include "corpus/generators.h"
#include "oracle/algebraic_route.h"
#include "oracle/oracle.h"
#include "support/sanitized.h"

namespace rayverify {
namespace {

namespace fs = std::filesystem;
constexpr double inf = std::numeric_limits<double>::infinity();

bool same_bits(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }

// ---------------------------------------------------------------------------
// Hand-worked cases: answers written down, not computed by another route.

algebraic_answer solve(const ray_sphere<double>& g, precision p = precision::binary64,
                       std::optional<double> tmin = std::nullopt, std::optional<double> tmax = std::nullopt) {
    return solve_algebraic(g, p, tmin, tmax);
}

TEST(AlgebraicRoute, TangentHasOneDoubleRoot) {
    // x = 1 touches the unit sphere at (1, 0, 0), five units along the ray.
    const algebraic_answer e = solve({{1, 0, -5}, {0, 0, 1}, {0, 0, 0}, 1});
    ASSERT_TRUE(e.valid());
    EXPECT_EQ(e.discriminant_sign, 0);
    for (const algebraic_root& r : e.roots) {
        EXPECT_EQ(r.sign, 1);
        EXPECT_EQ(r.rounded, 5.0);
    }
    EXPECT_EQ(e.nearest_in_front, 0);
    EXPECT_EQ(e.hit_point, (vec3<double>{1, 0, 0}));
}

TEST(AlgebraicRoute, MissHasNoRoot) {
    const algebraic_answer e = solve({{2, 0, -5}, {0, 0, 1}, {0, 0, 0}, 1}, precision::binary64, 0.0, inf);
    ASSERT_TRUE(e.valid());
    EXPECT_EQ(e.discriminant_sign, -1);
    EXPECT_FALSE(e.nearest_in_front);
    EXPECT_FALSE(e.roots[0].versus_tmin);
}

TEST(AlgebraicRoute, OriginOnTheSurface) {
    // Roots 0 and 2: the near one exactly at the origin, rounded to +0.
    for (precision p : {precision::binary32, precision::binary64}) {
        const algebraic_answer e = solve({{0, 0, -1}, {0, 0, 1}, {0, 0, 0}, 1}, p, 0.0, 2.0);
        ASSERT_EQ(e.discriminant_sign, 1);
        EXPECT_EQ(e.roots[0].sign, 0);
        EXPECT_TRUE(same_bits(e.roots[0].rounded, 0.0));
        EXPECT_EQ(e.roots[1].rounded, 2.0);
        EXPECT_EQ(e.roots[0].versus_tmin, 0);
        EXPECT_EQ(e.roots[1].versus_tmax, 0);
        EXPECT_TRUE(e.roots[0].in_closed_interval() && e.roots[1].in_closed_interval());
        EXPECT_EQ(e.nearest_in_front, 1);
        EXPECT_EQ(e.hit_point, (vec3<double>{0, 0, 1}));
    }
}

// On the z axis from o = 0 to c = (0, 0, 2) with radius 2 − m the roots are m
// and 4 − m: a rounding midpoint m is a root exactly.
ray_sphere<double> axis_case(double m) { return {{0, 0, 0}, {0, 0, 1}, {0, 0, 2}, 2 - m}; }

TEST(AlgebraicRoute, RootOnAFloatMidpointTiesToEven) {
    // 1 + 2^−24 lies halfway between 1 (even) and 1 + 2^−23 (odd): down to 1.
    algebraic_answer e = solve(axis_case(1 + 0x1p-24), precision::binary32, 1.0, 1 + 0x1p-24);
    EXPECT_EQ(e.roots[0].rounded, 1.0);
    EXPECT_EQ(e.roots[0].versus_tmin, 1);
    EXPECT_EQ(e.roots[0].versus_tmax, 0);
    EXPECT_EQ(e.hit_point.z, 1.0);  // the hit point is the root itself
    EXPECT_EQ(e.roots[1].rounded, 3.0);  // 3 − 2^−24 is nearer 3 than 3 − 2^−22
    // 1 + 3·2^−24 lies halfway between 1 + 2^−23 (odd) and 1 + 2^−22 (even): up.
    e = solve(axis_case(1 + 0x3p-24), precision::binary32);
    EXPECT_EQ(e.roots[0].rounded, 1 + 0x1p-22);
    // In double the same roots are exact.
    e = solve(axis_case(1 + 0x3p-24));
    EXPECT_EQ(e.roots[0].rounded, 1 + 0x3p-24);
    // A double midpoint: 1 + 2^−53, down to 1.
    e = solve(axis_case(1 + 0x1p-53));
    EXPECT_EQ(e.roots[0].rounded, 1.0);
    EXPECT_EQ(e.roots[1].rounded, 3.0);
}

TEST(AlgebraicRoute, OverflowRoundsToInfinityPastTheThreshold) {
    // c = 2^127, r = 2^127 − 2^103: the far root is 2^128 − 2^103 = FLT_MAX +
    // ulp/2 exactly, a tie between FLT_MAX (odd) and infinity: infinity.
    const ray_sphere<double> threshold{{0, 0, 0}, {0, 0, 1}, {0, 0, 0x1p127}, 0x1p127 - 0x1p103};
    algebraic_answer e = solve(threshold, precision::binary32);
    EXPECT_EQ(e.roots[0].rounded, 0x1p103);
    EXPECT_EQ(e.roots[1].rounded, inf);
    e = solve(threshold);  // exact in double
    EXPECT_EQ(e.roots[1].rounded, 0x1p128 - 0x1p103);
    // Just below the threshold: FLT_MAX.
    e = solve({{0, 0, 0}, {0, 0, 1}, {0, 0, 0x1p127}, 0x1p127 - 0x1p103 - 0x1p80}, precision::binary32);
    EXPECT_EQ(e.roots[1].rounded, double(std::numeric_limits<float>::max()));
    // Looking the other way the roots are negative: −infinity.
    e = solve({{0, 0, 0}, {0, 0, -1}, {0, 0, 0x1p127}, 0x1p127 - 0x1p103}, precision::binary32);
    EXPECT_EQ(e.roots[0].rounded, -inf);
    EXPECT_EQ(e.roots[0].sign, -1);
    // Double: d = 1/4 puts the roots at 2^1023 and 3·2^1023, the far one past DBL_MAX.
    e = solve({{0, 0, 0}, {0, 0, 0.25}, {0, 0, 0x1p1022}, 0x1p1021});
    EXPECT_EQ(e.roots[0].rounded, 0x1p1023);
    EXPECT_EQ(e.roots[1].rounded, inf);
    EXPECT_EQ(e.roots[1].versus_tmax, std::nullopt);
    EXPECT_EQ(e.hit_point.z, 0x1p1021);  // o + t·d = 2^1023/4
}

TEST(AlgebraicRoute, UnderflowKeepsTheSign) {
    // Roots (2^−49 ∓ (2^−49 − 2^−73))/±2^100: ±2^−173 is below float's range.
    algebraic_answer e = solve({{0, 0, 0}, {0, 0, 0x1p100}, {0, 0, 0x1p-49}, 0x1p-49 - 0x1p-73}, precision::binary32);
    EXPECT_EQ(e.roots[0].sign, 1);
    EXPECT_TRUE(same_bits(e.roots[0].rounded, 0.0));
    EXPECT_EQ(e.hit_point.z, 0x1p-73);
    e = solve({{0, 0, 0}, {0, 0, -0x1p100}, {0, 0, 0x1p-49}, 0x1p-49 - 0x1p-73}, precision::binary32);
    EXPECT_EQ(e.roots[1].sign, -1);
    EXPECT_TRUE(same_bits(e.roots[1].rounded, -0.0));
    EXPECT_FALSE(e.nearest_in_front);
    // In double 2^−173 is a normal number.
    e = solve({{0, 0, 0}, {0, 0, 0x1p100}, {0, 0, 0x1p-49}, 0x1p-49 - 0x1p-73});
    EXPECT_EQ(e.roots[0].rounded, 0x1p-173);
}

TEST(AlgebraicRoute, InvalidCasesAreReportedNotSolved) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(solve({{0, 0, 0}, {0, 0, 0}, {0, 0, 5}, 1}).invalid, invalid_reason::zero_direction);
    EXPECT_EQ(solve({{nan, 0, 0}, {0, 0, 1}, {0, 0, 5}, 1}).invalid, invalid_reason::non_finite_input);
    EXPECT_EQ(solve({{0, 0, 0}, {0, 0, 1}, {0, 0, 5}, -1}).invalid, invalid_reason::negative_radius);
    EXPECT_EQ(solve({{0, 0, 0}, {0, 0, 1}, {0, 0, 5}, 1}, precision::binary64, 2.0, 1.0).invalid,
              invalid_reason::bad_interval);
    EXPECT_EQ(solve({{0, 0, 0}, {0, 0, 1}, {0, 0, 5}, 1}, precision::binary64, nan).invalid,
              invalid_reason::bad_interval);
    const algebraic_answer e = solve({{0, 0, 0}, {0, 0, 0}, {0, 0, 5}, 1});
    EXPECT_FALSE(e.nearest_in_front);
    EXPECT_EQ(e.roots[0].versus_tmin, std::nullopt);
}

// Inputs far outside double's range of squares: the scaling keeps the route exact.
TEST(AlgebraicRoute, HugeAndTinyInputs) {
    const algebraic_answer huge = solve({{0, 0, -0x1p1000}, {0, 0, 0x1p-60}, {0, 0, 0}, 0x1p999});
    EXPECT_EQ(huge.roots[0].rounded, inf);  // 2^999·2^60
    const algebraic_answer big = solve({{0, 0, -0x1p900}, {0, 0, 1}, {0, 0, 0}, 0x1p899});
    EXPECT_EQ(big.roots[0].rounded, 0x1p899);
    EXPECT_EQ(big.roots[1].rounded, 0x3p899);
    EXPECT_EQ(big.hit_point.z, -0x1p899);
    const algebraic_answer tiny = solve({{0, 0, -0x1p-1060}, {0, 0, 0x1p-1070}, {0, 0, 0}, 0x1p-1062});
    EXPECT_EQ(tiny.roots[0].rounded, 0x3p8);  // (2^−1060 ∓ 2^−1062)/2^−1070
    EXPECT_EQ(tiny.roots[1].rounded, 0x5p8);
}

// ---------------------------------------------------------------------------
// Agreement with the exact oracle.

struct tally {
    std::size_t solutions = 0, comparisons = 0;
};

std::string precision_and_case(precision p, const ray_sphere<double>& g, std::optional<double> tmin,
                               std::optional<double> tmax) {
    corpus_case c;
    c.id = "algebraic";
    c.geometry = g;
    c.tmin = tmin;
    c.tmax = tmax;
    return std::string(precision_name(p)) + ": " + format_case_line(c);
}

// solve_algebraic and solve_exact agree on every field, and on the exact
// comparisons of each root with the interval's ends; a second solution with the
// interval [RN(near), RN(far)] checks those comparisons where they are 0 or close.
testing::AssertionResult agree(const ray_sphere<double>& g, precision p, std::optional<double> tmin,
                               std::optional<double> tmax, tally& count) {
    const exact_solution ref = solve_exact(g, p, tmin, tmax);
    const algebraic_answer alg = solve_algebraic(g, p, tmin, tmax);
    ++count.solutions;
    std::ostringstream why;
    const auto check = [&why](bool ok, const std::string& what) {
        if (!ok) why << "\n  " << what;
    };
    const auto bounds_agree = [&](const algebraic_answer& a, std::optional<double> lo, std::optional<double> hi) {
        for (int i = 0; i < 2; ++i) {
            const root_index index = i == 0 ? root_index::near_root : root_index::far_root;
            for (const auto& [bound, got, name] : {std::tuple{lo, a.roots[i].versus_tmin, "tmin"},
                                                   std::tuple{hi, a.roots[i].versus_tmax, "tmax"}}) {
                check(bound.has_value() == got.has_value(), std::string("comparison with ") + name + " missing");
                if (!bound || !got) continue;
                ++count.comparisons;
                const int expected = std::isinf(*bound) ? (*bound > 0 ? -1 : 1) : -static_cast<int>(ref.compare_to_root(*bound, index));
                check(*got == expected, "root " + std::to_string(i) + " against " + name + " " + hex_float(*bound) +
                                            ": algebraic " + std::to_string(*got) + ", oracle " +
                                            std::to_string(expected));
            }
        }
    };
    check(alg.invalid == ref.invalid, std::string("invalid: algebraic ") + invalid_reason_name(alg.invalid) +
                                          ", oracle " + invalid_reason_name(ref.invalid));
    if (alg.valid() && ref.valid()) {
        const int ref_sign = ref.cls == line_class::miss ? -1 : ref.cls == line_class::tangent ? 0 : 1;
        check(alg.discriminant_sign == ref_sign, "class: algebraic " + std::to_string(alg.discriminant_sign) +
                                                     ", oracle " + line_class_name(ref.cls));
        if (ref_sign == alg.discriminant_sign && ref_sign >= 0) {
            for (int i = 0; i < 2; ++i) {
                const exact_root& r = ref.root(i == 0 ? root_index::near_root : root_index::far_root);
                const std::string name = i == 0 ? "near" : "far";
                check(alg.roots[i].sign == r.sign, name + " sign: algebraic " + std::to_string(alg.roots[i].sign) +
                                                       ", oracle " + std::to_string(r.sign));
                check(same_bits(alg.roots[i].rounded, r.rounded), name + " rounded: algebraic " +
                                                                      hex_float(alg.roots[i].rounded) + ", oracle " +
                                                                      hex_float(r.rounded));
            }
            const int front = !ref.nearest_in_front                        ? -1
                              : *ref.nearest_in_front == root_index::near_root ? 0
                                                                               : 1;
            check(alg.nearest_in_front.value_or(-1) == front, "nearest_in_front differs");
            for (int axis = 0; axis < 3; ++axis)
                check(same_bits(alg.hit_point[axis], ref.hit_point()[axis]),
                      "hit_point[" + std::to_string(axis) + "]: algebraic " + hex_float(alg.hit_point[axis]) +
                          ", oracle " + hex_float(ref.hit_point()[axis]));
            bounds_agree(alg, tmin, tmax);
            // Each root against its own rounding and the other's.
            const double lo = ref.near_root.rounded, hi = ref.far_root.rounded;
            if (std::isfinite(lo) && std::isfinite(hi)) {
                bounds_agree(solve_algebraic(g, p, lo, hi), lo, hi);
                ++count.solutions;
            }
        }
    }
    if (why.str().empty()) return testing::AssertionSuccess();
    return testing::AssertionFailure() << precision_and_case(p, g, tmin, tmax) << why.str();
}

// Both precisions of a case (float when its inputs are floats after rounding).
bool agree_in_both(const ray_sphere<double>& g, std::optional<double> tmin, std::optional<double> tmax,
                   tally& count) {
    const testing::AssertionResult in_double = agree(g, precision::binary64, tmin, tmax, count);
    EXPECT_TRUE(in_double);
    if (validity<float>(g) != invalid_reason::none) return in_double;
    const auto narrow = [](std::optional<double> t) { return t ? std::optional<double>(float(*t)) : t; };
    const testing::AssertionResult in_float =
        agree(rounded_to<double>(rounded_to<float>(g)), precision::binary32, narrow(tmin), narrow(tmax), count);
    EXPECT_TRUE(in_float);
    return in_double && in_float;
}

TEST(AlgebraicRouteCorpus, AgreesWithTheOracleOnEveryShippedFile) {
    const fs::path root = fs::path(RAYVERIFY_SOURCE_DIR) / "corpus";
    std::vector<fs::path> files = corpus_files(root);
    for (const fs::path& f : corpus_files(root / "edge")) files.push_back(f);
    ASSERT_GE(files.size(), 20u);
    tally count;
    std::size_t cases = 0, at = 0;
    for (const fs::path& file : files)
        for (const corpus_case& c : read_corpus_file(file)) {
            if (at++ % test_support::sanitized_stride != 0) continue;
            ++cases;
            if (!agree_in_both(c.geometry, c.tmin, c.tmax, count)) ADD_FAILURE() << c.source;
        }
    std::printf("corpus: %zu files, %zu cases (one in %zu), %zu solutions compared, %zu comparisons with interval "
                "ends\n",
                files.size(), cases, test_support::sanitized_stride, count.solutions, count.comparisons);
    EXPECT_GT(cases, 9000u / test_support::sanitized_stride);
}

// Cases that once went wrong, kept as corpus lines.
TEST(AlgebraicRouteCorpus, KnownHardCases) {
    // Far root 2^192, near root −2^137: in the scaled quadratic −b′/a and
    // √Δ′/a cancel to 2^−57 and CGAL's interval of the near root has the wrong
    // sign; the search from that guess galloped forever at the line's end.
    const char* lines = "hard-1 - -0x1.db8ceebb6f6b8p+32 -0x1.47b2c52664bc1p+35 0x1.e30bf68311ffcp+33 "
                        "0x1.33dc0a207d42ap-159 0x1.03d0e07f97874p-161 -0x1.93ea4aad20b6bp-159 0x1.05add6bf42138p+33 "
                        "-0x1.19a79f43a0d21p+35 0x1.c2e8291add30cp+33 0x1.0aa64256182eep+34 0x0p+0 inf\n";
    tally count;
    for (const corpus_case& c : parse_corpus("known", lines, false)) agree_in_both(c.geometry, c.tmin, c.tmax, count);
    EXPECT_GE(count.solutions, 2u);
}

// ---------------------------------------------------------------------------
// Random and constructed cases.

std::uint64_t seed_for_run(std::uint64_t fallback) {
    if (const char* s = std::getenv("RAYVERIFY_ALGEBRAIC_SEED")) return std::strtoull(s, nullptr, 10);
    return fallback;
}

int pick(std::mt19937_64& rng, int lo, int hi) { return lo + static_cast<int>(rng() % static_cast<unsigned>(hi - lo + 1)); }

vec3<double> scale(vec3<double> v, int k) { return {std::ldexp(v.x, k), std::ldexp(v.y, k), std::ldexp(v.z, k)}; }

// A case of a generator family (generators.h), as shipped.
ray_sphere<double> generated(std::mt19937_64& rng) {
    const std::span<const family_info> families = generator_families();
    const family_info& f = families[rng() % families.size()];
    return generate_case(f.name, rng(), rng() % 100000).geometry;
}

// A generated case with positions scaled by 2^s and the direction by 2^k,
// far beyond the range where squares fit in a double.
ray_sphere<double> rescaled(std::mt19937_64& rng) {
    ray_sphere<double> g = generated(rng);
    const int s = pick(rng, -1000, 1000), k = pick(rng, -200, 200);
    return {scale(g.origin, s), scale(g.direction, k), scale(g.centre, s), std::ldexp(g.radius, s)};
}

// A root on a rounding midpoint m of the precision with p bits, on a random
// axis and direction, translated by an integer and scaled by powers of two:
// o_axis = T, c_axis = T + 2, r = 2 − m, the other coordinates equal, so the
// roots are (m and 4 − m)·2^(j − k). Float-exact when p = 24.
ray_sphere<double> midpoint_root(std::mt19937_64& rng, int p) {
    // m = y + ulp(y)/2 for y in [1, 1.5) with p bits; 2 − m then has p bits.
    const double y = 1 + std::ldexp(static_cast<double>(rng() >> (64 - (p - 2))), 1 - p);
    const double m = y + std::ldexp(1.0, -p);
    const double shift = pick(rng, -8, 8), side_a = pick(rng, -8, 8), side_b = pick(rng, -8, 8);
    const int axis = pick(rng, 0, 2);
    const auto along = [axis](double a, double b, double c) {
        return axis == 0 ? vec3<double>{c, a, b} : axis == 1 ? vec3<double>{a, c, b} : vec3<double>{a, b, c};
    };
    const double direction = (rng() & 1) ? 1 : -1;
    const vec3<double> o = along(side_a, side_b, shift);
    const vec3<double> c = along(side_a, side_b, shift + 2 * direction);
    const vec3<double> d = along(0, 0, direction);
    const int j = pick(rng, -20, 20), k = pick(rng, -20, 20);
    return {scale(o, j), scale(d, k), scale(c, j), std::ldexp(2 - m, j)};
}

// The origin exactly on the surface: o = c + r·(a, b, h)/n for a Pythagorean
// quadruple a² + b² + h² = n², permuted and signed; r a multiple of n.
ray_sphere<double> on_surface(std::mt19937_64& rng) {
    static constexpr int quadruples[][4] = {{1, 2, 2, 3}, {2, 3, 6, 7}, {1, 4, 8, 9}, {4, 4, 7, 9}, {2, 6, 9, 11}};
    const auto& q = quadruples[rng() % 5];
    const double unit = std::ldexp(1.0, pick(rng, -30, 30));
    const double n = q[3], r = n * unit * pick(rng, 1, 500);
    double offset[3] = {q[0] * r / n, q[1] * r / n, q[2] * r / n};
    for (double& x : offset)
        if (rng() & 1) x = -x;
    std::shuffle(offset, offset + 3, rng);
    const vec3<double> c{unit * pick(rng, -999, 999), unit * pick(rng, -999, 999), unit * pick(rng, -999, 999)};
    const vec3<double> d{double(pick(rng, -9, 9)), double(pick(rng, -9, 9)), double(pick(rng, 1, 9))};
    return {c + vec3<double>{offset[0], offset[1], offset[2]}, d, c, r};
}

// Small integers and halves: exact roots, tangents, ties and zeros are common.
ray_sphere<double> small_integers(std::mt19937_64& rng) {
    const auto v = [&rng] { return pick(rng, -6, 6) / 2.0; };
    ray_sphere<double> g{{v(), v(), v()}, {v(), v(), v()}, {v(), v(), v()}, std::fabs(v())};
    if (g.direction == vec3<double>{}) g.direction.x = 1;
    return g;
}

struct regime {
    const char* name;
    ray_sphere<double> (*make)(std::mt19937_64&);
};
const regime regimes[] = {
    {"generated", generated},
    {"rescaled", rescaled},
    {"midpoint_binary64", [](std::mt19937_64& rng) { return midpoint_root(rng, 53); }},
    {"midpoint_binary32", [](std::mt19937_64& rng) { return midpoint_root(rng, 24); }},
    {"on_surface", on_surface},
    {"small_integers", small_integers},
};

// No interval, [0, ∞), a one-sided or a two-sided random one, or both ends infinite.
std::pair<std::optional<double>, std::optional<double>> random_interval(std::mt19937_64& rng) {
    const double t = std::ldexp(static_cast<double>(rng() >> 11), -53) * 40 - 10;
    switch (rng() % 6) {
        case 0: return {0.0, inf};
        case 1: return {t, t + std::ldexp(static_cast<double>(rng() >> 11), -50)};
        case 2: return {std::nullopt, t};
        case 3: return {-inf, inf};
        default: return {};
    }
}

struct sweep_result {
    std::size_t cases = 0, failures = 0;
    tally count;
};

// Cases seed + i, i < cases (the regime is i's), for at most `seconds` (0: no limit).
sweep_result sweep(std::uint64_t seed, std::size_t cases, double seconds) {
    sweep_result out;
    const auto start = std::chrono::steady_clock::now();
    for (std::size_t i = 0; i < cases; ++i) {
        const regime& r = regimes[i % std::size(regimes)];
        std::mt19937_64 rng(seed + i);
        const ray_sphere<double> g = r.make(rng);
        const auto [tmin, tmax] = random_interval(rng);
        ++out.cases;
        if (!agree_in_both(g, tmin, tmax, out.count)) {
            ADD_FAILURE() << "regime " << r.name << ", seed " << seed << ", case " << i;
            if (++out.failures >= 10) break;
        }
        if (seconds > 0 && (i & 255) == 0 &&
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > seconds)
            break;
    }
    return out;
}

TEST(AlgebraicRouteRandom, AgreesWithTheOracle) {
    const std::uint64_t seed = seed_for_run(20260511);
    std::printf("seed %llu (RAYVERIFY_ALGEBRAIC_SEED replays it)\n", static_cast<unsigned long long>(seed));
    const sweep_result r = sweep(seed, test_support::sweep_size(60000), 0);
    std::printf("random: %zu cases, %zu solutions compared, %zu comparisons with interval ends\n", r.cases,
                r.count.solutions, r.count.comparisons);
    EXPECT_EQ(r.failures, 0u);
}

// CI's long run: a million cases, one thread, bounded to about 80 s.
TEST(LongSweepAlgebraicRoute, AgreesWithTheOracleOnAMillion) {
    const std::uint64_t seed = seed_for_run(std::random_device{}());
    std::printf("seed %llu (RAYVERIFY_ALGEBRAIC_SEED replays it)\n", static_cast<unsigned long long>(seed));
    const auto start = std::chrono::steady_clock::now();
    const sweep_result r = sweep(seed, 1'000'000, 80);
    std::printf("random: %zu cases, %zu solutions compared, %zu comparisons with interval ends, %.1f s\n", r.cases,
                r.count.solutions, r.count.comparisons,
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    EXPECT_EQ(r.failures, 0u);
}

}  // namespace
}  // namespace rayverify
