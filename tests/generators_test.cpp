#include "corpus/generators.h"

#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <algorithm>
#include <iostream>
#include <limits>
#include <random>
#include <utility>
#include <set>
#include <string>

#include "core/float_bits.h"
#include "core/hash.h"
#include "core/input_error.h"
#include "corpus/mersenne_twister.h"
#include "oracle/oracle.h"

namespace rayverify {
namespace {

std::array<std::uint64_t, 10> bits_of(const ray_sphere<double>& g) {
    return {std::bit_cast<std::uint64_t>(g.origin.x),    std::bit_cast<std::uint64_t>(g.origin.y),
            std::bit_cast<std::uint64_t>(g.origin.z),    std::bit_cast<std::uint64_t>(g.direction.x),
            std::bit_cast<std::uint64_t>(g.direction.y), std::bit_cast<std::uint64_t>(g.direction.z),
            std::bit_cast<std::uint64_t>(g.centre.x),    std::bit_cast<std::uint64_t>(g.centre.y),
            std::bit_cast<std::uint64_t>(g.centre.z),    std::bit_cast<std::uint64_t>(g.radius)};
}

bool same_case(const corpus_case& a, const corpus_case& b) {
    return a.id == b.id && a.family == b.family && a.source == b.source &&
           bits_of(a.geometry) == bits_of(b.geometry);
}

// FNV-1a over the ids and input bits of a batch: a fingerprint of the output.
std::uint64_t fingerprint(const std::vector<corpus_case>& cases) {
    fnv1a_digest digest;
    for (const corpus_case& c : cases) {
        digest.add(c.id);
        for (const std::uint64_t word : bits_of(c.geometry))
            for (int i = 0; i < 64; i += 8) digest.add(std::string(1, static_cast<char>((word >> i) & 0xff)));
    }
    return digest.value();
}

// Each input survives rounding to float. Component by component through a
// volatile: GCC 12 at -O2 drops the round trip on some lanes of a whole-struct
// rounded_to<double>(rounded_to<float>(g)).
bool float_exact(const ray_sphere<double>& g) {
    for (const std::uint64_t word : bits_of(g)) {
        const double x = std::bit_cast<double>(word);
        const volatile float rounded = static_cast<float>(x);
        if (std::bit_cast<std::uint64_t>(static_cast<double>(rounded)) != word) return false;
    }
    return true;
}

struct class_counts {
    int miss = 0, tangent = 0, two_hit = 0;
    void add(line_class c) {
        (c == line_class::miss ? miss : c == line_class::tangent ? tangent : two_hit)++;
    }
};

std::ostream& operator<<(std::ostream& out, const class_counts& n) {
    return out << "miss " << n.miss << ", tangent " << n.tangent << ", two_hit " << n.two_hit;
}

class_counts classify(const std::vector<corpus_case>& cases, precision p) {
    class_counts n;
    for (const corpus_case& c : cases) n.add(solve_exact(c.geometry, p).cls);
    return n;
}

// The class a (non-"any") claim promises.
line_class claimed_class(class_claim c) {
    if (c == class_claim::miss) return line_class::miss;
    if (c == class_claim::tangent) return line_class::tangent;
    return line_class::two_hit;
}

constexpr std::uint64_t oracle_seed = 20240611;

// ---------------------------------------------------------------------------
// The family table and errors.

// The generators' engine draws std::mt19937_64's sequence, before and after
// it hands over to the standard engine (output 157 on), for seeds at the ends
// of the range and random ones.
TEST(LazilySeededMersenneTwister, DrawsStdMt19937_64sSequence) {
    const std::uint64_t seed = std::random_device{}();
    std::printf("seed %llu\n", static_cast<unsigned long long>(seed));
    std::mt19937_64 seeds(seed);
    std::vector<std::uint64_t> engine_seeds = {0, 1, 5489, ~std::uint64_t{0}};
    for (int i = 0; i < 300; ++i) engine_seeds.push_back(seeds());
    for (const std::uint64_t s : engine_seeds) {
        std::mt19937_64 standard(s);
        lazily_seeded_mt19937_64 lazy(s);
        for (int draw = 0; draw < 700; ++draw) ASSERT_EQ(lazy(), standard()) << "engine seed " << s << " draw " << draw;
    }
}

TEST(Generators, FamiliesAreNamedAndDescribedOnce) {
    std::set<std::string_view> names;
    for (const family_info& f : generator_families()) {
        EXPECT_TRUE(names.insert(f.name).second) << f.name;
        EXPECT_FALSE(f.description.empty()) << f.name;
        EXPECT_EQ(find_generator_family(f.name), &f);
    }
    EXPECT_GE(names.size(), 6u);
    EXPECT_EQ(find_generator_family("nope"), nullptr);
}

TEST(Generators, UnknownFamilyThrowsAndListsTheKnownOnes) {
    try {
        generate_family("nope", 1, 1);
        FAIL() << "no exception";
    } catch (const input_error& e) {
        EXPECT_EQ(e.field(), "family");
        const std::string what = e.what();
        EXPECT_NE(what.find("unknown generator family 'nope'"), std::string::npos) << what;
        for (const family_info& f : generator_families())
            EXPECT_NE(what.find(std::string(f.name)), std::string::npos) << what;
    }
}

TEST(Generators, ZeroCountIsEmpty) { EXPECT_TRUE(generate_family("uniform", 0, 1).empty()); }

// ---------------------------------------------------------------------------
// Determinism.

TEST(Generators, SameSeedGivesTheSameBits) {
    for (const family_info& f : generator_families()) {
        SCOPED_TRACE(std::string(f.name) + ", seed 7");
        const auto a = generate_family(f.name, 300, 7);
        const auto b = generate_family(f.name, 300, 7);
        ASSERT_EQ(a.size(), 300u);
        ASSERT_EQ(b.size(), 300u);
        for (std::size_t i = 0; i < a.size(); ++i) EXPECT_TRUE(same_case(a[i], b[i])) << a[i].id;
    }
}

TEST(Generators, CaseDoesNotDependOnCount) {
    for (const family_info& f : generator_families()) {
        SCOPED_TRACE(std::string(f.name) + ", seed 7");
        const auto few = generate_family(f.name, 10, 7);
        const auto many = generate_family(f.name, 100, 7);
        for (std::size_t i = 0; i < few.size(); ++i) EXPECT_TRUE(same_case(few[i], many[i])) << few[i].id;
    }
}

TEST(Generators, DifferentSeedsGiveDifferentCases) {
    for (const family_info& f : generator_families()) {
        SCOPED_TRACE(std::string(f.name) + ", seeds 7 and 8");
        const auto a = generate_family(f.name, 100, 7);
        const auto b = generate_family(f.name, 100, 8);
        for (std::size_t i = 0; i < a.size(); ++i)
            EXPECT_NE(bits_of(a[i].geometry), bits_of(b[i].geometry)) << a[i].id;
    }
}

// Output bits recorded once; a change here means every generated corpus
// changes (other platform, other libstdc++, or an edited generator).
TEST(Generators, OutputMatchesTheRecordedFingerprints) {
    const std::array<std::pair<std::string_view, std::uint64_t>, 6> expected{{
        {"uniform", 0x471d3a496623252cULL},
        {"tangent_exact", 0x08f9d7d556592a5cULL},
        {"near_tangent", 0x40ebc10dc0a831f1ULL},
        {"far_sphere", 0xafe2d9f2ddff82a3ULL},
        {"on_surface", 0x2074a813e75e77b1ULL},
        {"inside", 0xc826a31d55114dfdULL},
    }};
    for (const auto& [name, print] : expected) {
        SCOPED_TRACE(std::string(name) + ", 64 cases, seed 1");
        EXPECT_EQ(fingerprint(generate_family(name, 64, 1)), print)
            << std::hex << fingerprint(generate_family(name, 64, 1));
    }
}

// ---------------------------------------------------------------------------
// Well-formed cases.

TEST(Generators, CasesAreWellFormed) {
    for (const family_info& f : generator_families()) {
        const std::uint64_t seed = 3;
        SCOPED_TRACE(std::string(f.name) + ", seed 3");
        const auto cases = generate_family(f.name, 1000, seed);
        std::set<std::string> ids;
        for (std::size_t i = 0; i < cases.size(); ++i) {
            const corpus_case& c = cases[i];
            SCOPED_TRACE(c.id);
            const std::string index = std::to_string(i);
            EXPECT_EQ(c.id, std::string(f.name) + "-3-" + std::string(6 - index.size(), '0') + index);
            EXPECT_TRUE(ids.insert(c.id).second);
            EXPECT_EQ(c.family, f.name);
            EXPECT_EQ(c.source, "generated");
            EXPECT_EQ(c.tmin.has_value(), f.interval);
            EXPECT_EQ(c.tmax.has_value(), f.interval);
            if (f.interval) {
                EXPECT_LE(*c.tmin, *c.tmax);
            }
            EXPECT_EQ(c.is_segment(), f.segment);
            for (const std::uint64_t word : bits_of(c.geometry))
                EXPECT_TRUE(std::isfinite(std::bit_cast<double>(word)));
            EXPECT_GE(c.geometry.radius, 0);
            if (f.segment) {
                // A zero-length segment (p1 = p0) is one of the family's casts: no geometry, on purpose.
                EXPECT_EQ(*c.tmin, 0.0);
                EXPECT_EQ(*c.tmax, 1.0);
                const invalid_reason why = case_validity<double>(c);
                EXPECT_TRUE(why == invalid_reason::none ||
                            (why == invalid_reason::zero_direction && *c.segment_end == c.geometry.origin));
                continue;
            }
            EXPECT_EQ(validity<double>(c.geometry), invalid_reason::none);
            EXPECT_NE(c.geometry.direction, (vec3<double>{}));
            if (f.unit_direction) {
                EXPECT_LE(std::fabs(length_squared(c.geometry.direction) - 1), 4 * 0x1p-53);
            }
        }
    }
}

// ---------------------------------------------------------------------------
// Claims, confirmed by the exact oracle.

TEST(Generators, ClaimedClassHoldsExactly) {
    for (const family_info& f : generator_families()) {
        if (f.claim == class_claim::any) continue;
        SCOPED_TRACE(std::string(f.name) + ", seed " + std::to_string(oracle_seed));
        for (const corpus_case& c : generate_family(f.name, 300, oracle_seed)) {
            const exact_solution s = solve_exact(c.geometry, precision::binary64);
            ASSERT_TRUE(s.valid()) << c.id;
            EXPECT_EQ(s.cls, claimed_class(f.claim)) << c.id << " claim " << class_claim_name(f.claim)
                                                     << ", got " << line_class_name(s.cls);
        }
    }
}

TEST(Generators, TangentExactIsTangentInDoubleAndFloat) {
    SCOPED_TRACE("seed " + std::to_string(oracle_seed));
    int at_origin = 0, ahead = 0, behind = 0, unit = 0;
    for (const corpus_case& c : generate_family("tangent_exact", 1000, oracle_seed)) {
        SCOPED_TRACE(c.id);
        const exact_solution s = solve_exact(c.geometry, precision::binary64);
        ASSERT_EQ(s.cls, line_class::tangent);
        EXPECT_EQ(s.near_root.sign, s.far_root.sign);
        (s.near_root.sign == 0 ? at_origin : s.near_root.sign > 0 ? ahead : behind)++;
        if (length_squared(c.geometry.direction) == 1) ++unit;

        ASSERT_TRUE(float_exact(c.geometry));
        EXPECT_EQ(solve_exact(c.geometry, precision::binary32).cls, line_class::tangent);
    }
    std::cout << "tangent_exact: root 0: " << at_origin << ", > 0: " << ahead << ", < 0: " << behind
              << ", unit direction: " << unit << " of 1000\n";
    EXPECT_GT(at_origin, 100);
    EXPECT_GT(ahead, 100);
    EXPECT_GT(behind, 100);
    EXPECT_GT(unit, 300);
    EXPECT_LT(unit, 700);
}

TEST(Generators, NearTangentIsNeverTangentAndGoesBothWays) {
    SCOPED_TRACE("seed " + std::to_string(oracle_seed));
    const auto cases = generate_family("near_tangent", 1000, oracle_seed);
    const class_counts n = classify(cases, precision::binary64);
    std::cout << "near_tangent: " << n << "\n";
    EXPECT_EQ(n.tangent, 0);
    EXPECT_GT(n.miss, 300);
    EXPECT_GT(n.two_hit, 300);
}

TEST(Generators, OnSurfaceHasAZeroRootInDoubleAndFloat) {
    SCOPED_TRACE("seed " + std::to_string(oracle_seed));
    int entering = 0, leaving = 0;
    for (const corpus_case& c : generate_family("on_surface", 1000, oracle_seed)) {
        SCOPED_TRACE(c.id);
        const exact_solution s = solve_exact(c.geometry, precision::binary64);
        ASSERT_NE(s.cls, line_class::miss);
        EXPECT_EQ(s.cls, line_class::two_hit);
        if (s.near_root.sign == 0 && s.far_root.sign > 0) ++entering;
        else if (s.near_root.sign < 0 && s.far_root.sign == 0) ++leaving;
        else ADD_FAILURE() << "root signs " << s.near_root.sign << ", " << s.far_root.sign;

        // Origin and centre are float-exact; d moves by 2^-24 but d·f keeps its sign.
        const ray_sphere<double> in_float = rounded_to<double>(rounded_to<float>(c.geometry));
        EXPECT_EQ(in_float.origin, c.geometry.origin);
        EXPECT_EQ(in_float.centre, c.geometry.centre);
        EXPECT_EQ(in_float.radius, c.geometry.radius);
        const exact_solution f = solve_exact(in_float, precision::binary32);
        EXPECT_EQ(f.cls, line_class::two_hit);
        EXPECT_EQ(f.near_root.sign, s.near_root.sign);
        EXPECT_EQ(f.far_root.sign, s.far_root.sign);
    }
    std::cout << "on_surface: entering " << entering << ", leaving " << leaving << "\n";
    EXPECT_GT(entering, 400);
    EXPECT_GT(leaving, 400);
}

TEST(Generators, InsideHasRootsOfOppositeSigns) {
    SCOPED_TRACE("seed " + std::to_string(oracle_seed));
    for (const corpus_case& c : generate_family("inside", 1000, oracle_seed)) {
        SCOPED_TRACE(c.id);
        const exact_solution s = solve_exact(c.geometry, precision::binary64);
        ASSERT_EQ(s.cls, line_class::two_hit);
        EXPECT_LT(s.near_root.sign, 0);
        EXPECT_GT(s.far_root.sign, 0);
    }
}

TEST(Generators, UniformAndFarSphereBothHitAndMiss) {
    SCOPED_TRACE("seed " + std::to_string(oracle_seed));
    for (const std::string_view name : {"uniform", "far_sphere"}) {
        SCOPED_TRACE(name);
        const class_counts n = classify(generate_family(name, 1000, oracle_seed), precision::binary64);
        std::cout << name << ": " << n << "\n";
        EXPECT_GT(n.miss, 200);
        EXPECT_GT(n.two_hit, 200);
    }
}

// ---------------------------------------------------------------------------
// The edge-case families.

// The smallest and largest magnitude among the nonzero inputs o, c, r.
std::pair<double, double> position_range(const ray_sphere<double>& g) {
    double lo = std::numeric_limits<double>::infinity(), hi = 0;
    for (double v : {g.origin.x, g.origin.y, g.origin.z, g.centre.x, g.centre.y, g.centre.z, g.radius}) {
        if (v == 0) continue;
        lo = std::min(lo, std::fabs(v));
        hi = std::max(hi, std::fabs(v));
    }
    return {lo, hi};
}

double largest_direction_component(const ray_sphere<double>& g) {
    return std::max({std::fabs(g.direction.x), std::fabs(g.direction.y), std::fabs(g.direction.z)});
}

TEST(Generators, EveryFamilyNamedF32IsFloatExactAndValidInFloat) {
    int f32 = 0;
    for (const family_info& f : generator_families()) {
        const bool named = f.name.ends_with("_f32");
        if (named) {
            ++f32;
            EXPECT_TRUE(f.float_exact) << f.name;
        }
        if (!f.float_exact) continue;
        SCOPED_TRACE(std::string(f.name) + ", seed " + std::to_string(oracle_seed));
        for (const corpus_case& c : generate_family(f.name, 300, oracle_seed)) {
            if (c.is_segment()) {  // its ends (the direction is p1 − p0 rounded to double)
                ray_sphere<double> ends = c.geometry;
                ends.direction = *c.segment_end;
                ASSERT_TRUE(float_exact(ends)) << c.id;
                EXPECT_NE(case_validity<float>(c), invalid_reason::not_representable) << c.id;
                continue;
            }
            ASSERT_TRUE(float_exact(c.geometry)) << c.id;
            EXPECT_EQ(validity<float>(c.geometry), invalid_reason::none) << c.id;
        }
    }
    EXPECT_GE(f32, 10);
}

// A float-exact family's claim holds for float variants too: they see the same inputs.
TEST(Generators, FloatExactClaimsHoldInFloat) {
    for (const family_info& f : generator_families()) {
        if (!f.float_exact || f.claim == class_claim::any) continue;
        SCOPED_TRACE(std::string(f.name) + ", seed " + std::to_string(oracle_seed));
        for (const corpus_case& c : generate_family(f.name, 300, oracle_seed)) {
            const exact_solution s = solve_exact(c.geometry, precision::binary32);
            ASSERT_TRUE(s.valid()) << c.id;
            EXPECT_EQ(s.cls, claimed_class(f.claim)) << c.id;
        }
    }
}

TEST(Generators, NearTangentSidesNudgeTheRadiusAboutAThirdOfTheTime) {
    // The radius is nudged a third of the time, origin or centre otherwise; the claim is checked
    // by ClaimedClassHoldsExactly and FloatExactClaimsHoldInFloat.
    for (const char* name : {"near_tangent_hit", "near_tangent_miss", "near_tangent_hit_f32", "near_tangent_miss_f32"}) {
        SCOPED_TRACE(name);
        const auto nudged = generate_family(name, 300, oracle_seed);
        // Whether each is one double (or float) ulp from a tangent line: the
        // tangent_exact case with the same random draws differs in one input.
        int differing_radius = 0;
        for (const corpus_case& c : nudged) {
            const double r = c.geometry.radius;
            // r = w·2^k with w < 2^15 has a short significand unless it was nudged.
            int e = 0;
            const double m = std::frexp(r, &e);
            if (std::ldexp(m, 20) != std::floor(std::ldexp(m, 20))) ++differing_radius;
        }
        EXPECT_GT(differing_radius, 50);
        EXPECT_LT(differing_radius, 150);
    }
}

TEST(Generators, TangentClosestHasItsDoubleRootAtTheOrigin) {
    for (const corpus_case& c : generate_family("tangent_closest", 500, oracle_seed)) {
        SCOPED_TRACE(c.id);
        ASSERT_TRUE(float_exact(c.geometry));
        for (const precision p : {precision::binary64, precision::binary32}) {
            const exact_solution s = solve_exact(c.geometry, p);
            ASSERT_EQ(s.cls, line_class::tangent);
            EXPECT_EQ(s.near_root.sign, 0);
            EXPECT_EQ(s.near_root.rounded, 0);
        }
    }
}

TEST(Generators, BehindHasBothRootsBehindTheOrigin) {
    for (const char* name : {"behind", "behind_f32"}) {
        SCOPED_TRACE(std::string(name) + ", seed " + std::to_string(oracle_seed));
        for (const corpus_case& c : generate_family(name, 500, oracle_seed)) {
            const exact_solution s = solve_exact(c.geometry, precision::binary64);
            ASSERT_EQ(s.cls, line_class::two_hit) << c.id;
            EXPECT_LT(s.near_root.sign, 0) << c.id;
            EXPECT_LT(s.far_root.sign, 0) << c.id;
            EXPECT_FALSE(s.nearest_in_front.has_value()) << c.id;
        }
    }
}

TEST(Generators, SecondaryRayHasARootWithinRoundingOfTheOrigin) {
    for (const auto& [name, p] : {std::pair{"secondary_ray", precision::binary64},
                                  std::pair{"secondary_ray_f32", precision::binary32}}) {
        SCOPED_TRACE(std::string(name) + ", seed " + std::to_string(oracle_seed));
        int self_hit_side = 0, entering = 0;
        for (const corpus_case& c : generate_family(name, 500, oracle_seed)) {
            const exact_solution s = solve_exact(c.geometry, p);
            ASSERT_EQ(s.cls, line_class::two_hit) << c.id;
            const double nearest = std::min(std::fabs(s.near_root.rounded), std::fabs(s.far_root.rounded));
            EXPECT_LE(nearest, 0x1p-10 * c.geometry.radius) << c.id;
            // The origin is outside (root near 0 ahead or both behind) or inside, by rounding.
            if (s.near_root.sign > 0) ++self_hit_side;
            if (s.near_root.sign < 0 && s.far_root.sign > 0) ++entering;
        }
        std::cout << name << ": origin outside " << self_hit_side << ", inside " << entering << " of 500\n";
    }
}

TEST(Generators, ScaledDirectionsSpanTwoToTheMinusTwoHundredToTwoHundredAndKeepTheClass) {
    for (const auto& [name, reach] : {std::pair{"scaled_direction", 190}, std::pair{"scaled_direction_f32", 90}}) {
        SCOPED_TRACE(name);
        int smallest = 0, largest = 0;
        for (const corpus_case& c : generate_family(name, 500, oracle_seed)) {
            const int k = std::ilogb(largest_direction_component(c.geometry));
            smallest = std::min(smallest, k);
            largest = std::max(largest, k);
            // Scaling d back by 2^-k is exact: the class cannot change.
            ray_sphere<double> unit = c.geometry;
            unit.direction = std::ldexp(1.0, -k) * unit.direction;
            EXPECT_EQ(solve_exact(c.geometry, precision::binary64).cls, solve_exact(unit, precision::binary64).cls)
                << c.id;
        }
        EXPECT_LT(smallest, -reach);
        EXPECT_GT(largest, reach);
    }
}

TEST(Generators, NearOverflowAndSubnormalReachTheEndsOfTheRange) {
    for (const corpus_case& c : generate_family("near_overflow", 300, oracle_seed)) {
        EXPECT_GE(position_range(c.geometry).second, 0x1p990) << c.id;
        EXPECT_EQ(validity<float>(c.geometry), invalid_reason::not_representable) << c.id;
    }
    for (const corpus_case& c : generate_family("near_overflow_f32", 300, oracle_seed))
        EXPECT_GE(position_range(c.geometry).second, 0x1p100) << c.id;
    for (const corpus_case& c : generate_family("subnormal", 300, oracle_seed)) {
        EXPECT_LT(position_range(c.geometry).second, std::numeric_limits<double>::min()) << c.id;
        EXPECT_GT(c.geometry.radius, 0) << c.id;
    }
    for (const corpus_case& c : generate_family("subnormal_f32", 300, oracle_seed)) {
        EXPECT_LT(position_range(c.geometry).second, std::numeric_limits<float>::min()) << c.id;
        EXPECT_GT(c.geometry.radius, 0) << c.id;
    }
}

TEST(Generators, WideAndOffsetFamiliesHitAndMiss) {
    for (const char* name : {"far_sphere_wide", "tiny_sphere", "ground_plane", "world_offset", "uniform_f32",
                             "far_sphere_f32", "tiny_sphere_f32", "ground_plane_f32", "world_offset_f32"}) {
        SCOPED_TRACE(std::string(name) + ", seed " + std::to_string(oracle_seed));
        const class_counts n = classify(generate_family(name, 500, oracle_seed), precision::binary64);
        std::cout << name << ": " << n << "\n";
        EXPECT_GT(n.miss, 50);
        EXPECT_GT(n.two_hit, 50);
    }
}

TEST(Generators, FarSphereWideSpansTwoToFifteenOrdersAndGroundPlaneOriginsAreOutside) {
    double lo = 1e300, hi = 0;
    for (const corpus_case& c : generate_family("far_sphere_wide", 1000, oracle_seed)) {
        const double distance = std::sqrt(length_squared(c.geometry.origin - c.geometry.centre));
        lo = std::min(lo, distance / c.geometry.radius);
        hi = std::max(hi, distance / c.geometry.radius);
    }
    EXPECT_LT(lo, 1e3);
    EXPECT_GT(hi, 1e14);
    for (const char* name : {"ground_plane", "ground_plane_f32"})
        for (const corpus_case& c : generate_family(name, 300, oracle_seed)) {
            const exact_solution s = solve_exact(c.geometry, precision::binary64);
            if (s.cls != line_class::two_hit) continue;
            EXPECT_EQ(s.near_root.sign, s.far_root.sign) << c.id << ": origin not outside";
            EXPECT_NE(s.near_root.sign, 0) << c.id;
        }
}

TEST(Generators, WorldOffsetsReachTheirMagnitudes) {
    double largest = 0;
    for (const corpus_case& c : generate_family("world_offset", 500, oracle_seed))
        largest = std::max(largest, position_range(c.geometry).second);
    EXPECT_GT(largest, 1e11);
}

}  // namespace
}  // namespace rayverify

namespace rayverify {
namespace {

// Which exact root an end is on (0 steps), or next to (its steps), in T, when
// the root is a value of T: the nearest over both roots, else nullopt.
template <class T>
std::optional<std::uint64_t> steps_to_exact_root(const exact_solution& s, double end) {
    std::optional<std::uint64_t> best;
    for (const root_index k : {root_index::near_root, root_index::far_root}) {
        const double root = s.root(k).rounded;
        if (s.compare_to_root(root, k) != comparison::equal) continue;  // not exactly representable
        const std::uint64_t steps = ulps_between<T>(static_cast<T>(end), static_cast<T>(root));
        if (!best || steps < *best) best = steps;
    }
    return best;
}

// The range-end families are what they say, decided by the oracle: their
// roots are exact values, an end sits on one or within a step or four of it,
// and the short casts are zero-length or the shortest nonzero.
TEST(Generators, RangeEndFamiliesPutTheirEndsOnExactRoots) {
    for (const auto& [family, in_float] : {std::pair{"range_end", false}, std::pair{"range_end_f32", true}}) {
        std::array<int, 6> by_steps{};
        for (const corpus_case& c : generate_family(family, 300, oracle_seed)) {
            ASSERT_TRUE(c.tmin && c.tmax) << c.id;
            EXPECT_LE(*c.tmin, *c.tmax) << c.id;
            const exact_solution s = solve_exact(c.geometry, precision::binary64, c.tmin, c.tmax);
            ASSERT_TRUE(s.valid()) << c.id;
            ASSERT_EQ(s.cls, line_class::two_hit) << c.id;
            std::optional<std::uint64_t> nearest;
            for (const double end : {*c.tmin, *c.tmax}) {
                const auto steps = in_float ? steps_to_exact_root<float>(s, end) : steps_to_exact_root<double>(s, end);
                ASSERT_TRUE(steps) << c.id << ": the roots are not exact values";
                if (!nearest || *steps < *nearest) nearest = steps;
            }
            ASSERT_LE(*nearest, 4u) << c.id;
            ++by_steps[*nearest];
        }
        // Ends on a root, one step off, and straddles, each well represented.
        EXPECT_GT(by_steps[0], 60) << family;
        EXPECT_GT(by_steps[1], 60) << family;
        EXPECT_GT(by_steps[2] + by_steps[3] + by_steps[4], 20) << family;
    }
    int zero_length = 0, shortest = 0;
    for (const corpus_case& c : generate_family("short_cast", 300, oracle_seed)) {
        ASSERT_TRUE(c.tmin && c.tmax) << c.id;
        const exact_solution s = solve_exact(c.geometry, precision::binary64, c.tmin, c.tmax);
        ASSERT_TRUE(s.valid()) << c.id;
        ASSERT_EQ(s.cls, line_class::two_hit) << c.id;
        if (*c.tmin == *c.tmax) {
            ++zero_length;
            continue;
        }
        const double length = *c.tmax - *c.tmin;
        EXPECT_TRUE(length <= 4 * std::numeric_limits<double>::denorm_min() ||
                    *c.tmax == std::nextafter(*c.tmin, std::numeric_limits<double>::infinity()))
            << c.id;
        ++shortest;
    }
    EXPECT_GT(zero_length, 100);
    EXPECT_GT(shortest, 100);
    // Grazing casts end at the tangent point of a tangent line, or one step from it.
    int tangent = 0;
    for (const corpus_case& c : generate_family("grazing_end", 300, oracle_seed)) {
        ASSERT_TRUE(c.tmin && c.tmax) << c.id;
        const exact_solution s = solve_exact(c.geometry, precision::binary64, c.tmin, c.tmax);
        ASSERT_TRUE(s.valid()) << c.id;
        if (s.cls != line_class::tangent) continue;
        ++tangent;
        EXPECT_LE(*steps_to_exact_root<double>(s, *c.tmax), 1u) << c.id;
    }
    EXPECT_GT(tangent, 60);
}

}  // namespace
}  // namespace rayverify
