// The floating-point intersectors of the registry, in float and in double:
// every variant on hand-worked cases under its own contract, then the known
// failures users hit in practice, each pinned to a concrete input and judged
// by the exact oracle on exactly the inputs the variant received.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <string_view>

#include "compare/judge.h"
#include "core/intersection.h"
#include "core/ray_sphere_case.h"
#include "intersectors/registry.h"
#include "oracle/oracle.h"

namespace rayverify {
namespace {

using enum root_index;

constexpr precision both_precisions[] = {precision::binary32, precision::binary64};

// A variant's answer widened to double (exactly), whatever it ran in.
root_pair<double> run(const variant& v, precision p, const ray_sphere<double>& g) {
    if (p == precision::binary32) {
        const root_pair<float> r = v.run_float(rounded_to<float>(g));
        return {r.count, r.t0, r.t1};
    }
    return v.run_double(g);
}

// The exact solution for exactly the inputs the variant receives in p.
exact_solution exact_for(const ray_sphere<double>& g, precision p) {
    if (p == precision::binary64) return solve_exact(g, p);
    const ray_sphere<float> f = rounded_to<float>(g);
    const ray_sphere<double> widened{vec3_cast<double>(f.origin), vec3_cast<double>(f.direction),
                                     vec3_cast<double>(f.centre), static_cast<double>(f.radius)};
    return solve_exact(widened, p);
}

const variant& named(std::string_view name) {
    const variant* v = find_builtin_variant(name);
    if (v == nullptr) throw std::logic_error("no variant " + std::string(name));
    return *v;
}

// What a variant keeping its contract answers, given the exact solution.
root_pair<double> contract_answer(const contract& c, const exact_solution& s) {
    const double near = s.near_root.rounded, far = s.far_root.rounded;
    if (c.query == query_kind::line_roots) {
        switch (s.cls) {
            case line_class::miss: return {0, 0, 0};
            case line_class::tangent: return {c.reports_tangent ? 1 : 2, near, near};
            case line_class::two_hit: return {2, near, far};
        }
    }
    // nearest_hit and any_hit: what the judge expects under the contract, on
    // the range a variant asked without an interval answers for.
    const expected_hit want = expect_hit(c, s, range_of(c, std::nullopt, std::nullopt));
    if (!want.hit()) return {0, 0, 0};
    if (c.query == query_kind::any_hit) return {1, 0, 0};
    return {1, want.value, want.value};
}

std::string label(const variant& v, precision p) { return v.name + "<" + precision_name(p) + ">"; }

// ---------------------------------------------------------------------------
// Hand cases: unit sphere at the origin, d = (0, 0, 1) unless said otherwise.
// Every intermediate of every variant is a small integer (or its exact half),
// so each variant must return the exact roots, bit for bit up to the sign of
// zero. The per-variant arithmetic is worked in the variants' headers; e.g.
// for o = (0, 0, −5): naive b = −10, C = 24, Δ = 100 − 96 = 4, t = (10 ∓ 2)/2;
// half_b h = 5, Δ = 25 − 24 = 1, t = 5 ∓ 1; geometric t_ca = 5, d² = 0,
// t = 5 ∓ 1; stable_roots q = −½(−10 − 2) = 6, t = 6/1, 24/6; hearn_baker
// b′ = 5, l = 0, Δ = 1, q = 6, t = 24/6, 6/1.

struct hand_case {
    const char* name;
    ray_sphere<double> geometry;
    bool unit_direction = true;
};

const hand_case hand_cases[] = {
    {"two_hit", {{0, 0, -5}, {0, 0, 1}, {0, 0, 0}, 1}},      // roots 4, 6
    {"tangent", {{1, 0, -5}, {0, 0, 1}, {0, 0, 0}, 1}},      // double root 5
    {"on_surface_entering", {{0, 0, -1}, {0, 0, 1}, {0, 0, 0}, 1}},  // 0, 2
    {"on_surface_leaving", {{0, 0, 1}, {0, 0, 1}, {0, 0, 0}, 1}},    // −2, 0
    {"inside", {{0, 0, 0}, {0, 0, 1}, {0, 0, 0}, 1}},        // −1, 1
    {"behind", {{0, 0, 5}, {0, 0, 1}, {0, 0, 0}, 1}},        // −6, −4
    {"miss", {{2, 0, -5}, {0, 0, 1}, {0, 0, 0}, 1}},         // Δ′ = 25 − 28 < 0
    {"offset_sphere", {{3, -2, 10}, {-1, 0, 0}, {-4, -2, 10}, 2}},  // roots 5, 9
    {"non_unit_direction", {{0, 0, -5}, {0, 0, 2}, {0, 0, 0}, 1}, false},  // 2, 3
};

// The formulas (engine ports, which run in their engines' precisions and
// have hand cases of their own, are in engines_test.cpp).
std::vector<variant> formulas() {
    std::vector<variant> out;
    for (const variant& v : builtin_variants())
        if (v.build.empty()) out.push_back(v);
    return out;
}

TEST(IntersectorHandCases, EveryVariantIsExactOnIntegerCases) {
    ASSERT_GE(formulas().size(), 14u);
    int checked = 0, expected = 0;
    for (const variant& v : formulas()) {
        for (const precision p : both_precisions) {
            ASSERT_TRUE(v.runs_in(p)) << label(v, p);
            for (const hand_case& h : hand_cases) {
                if (v.promises.assumes_unit_direction && !h.unit_direction) continue;
                ++expected;
                SCOPED_TRACE(label(v, p) + " on " + h.name);
                const exact_solution s = exact_for(h.geometry, p);
                const root_pair<double> want = contract_answer(v.promises, s);
                const root_pair<double> got = run(v, p, h.geometry);
                ++checked;
                ASSERT_EQ(got.count, want.count);
                if (got.count == 0 || v.promises.query == query_kind::any_hit) continue;
                EXPECT_EQ(got.t0, want.t0);
                if (v.promises.query == query_kind::line_roots) {
                    EXPECT_EQ(got.t1, want.t1);
                }
            }
        }
    }
    // Every variant × 2 precisions × 9 cases, less the non-unit case for the
    // variants that assume a unit direction: nothing skipped silently.
    EXPECT_EQ(checked, expected);
    EXPECT_GE(checked, 13 * 2 * 9 - 6 * 2);
}

TEST(IntersectorHandCases, NearestOnRayClampsInsideAndRejectsBehind) {
    // seed004's contract spelled out on the cases where it differs from the roots.
    const variant& v = named("seed004_early_out");
    for (const precision p : both_precisions) {
        SCOPED_TRACE(precision_name(p));
        auto answer = [&](vec3<double> o) { return run(v, p, {o, {0, 0, 1}, {0, 0, 0}, 1}); };
        // Inside: b = 0, C = −1, t = −1 clamped to 0.
        EXPECT_EQ(answer({0, 0, 0}).count, 1);
        EXPECT_EQ(answer({0, 0, 0}).t0, 0.0);
        // On the surface, leaving: t = −1 − 1 = −2 clamped to 0 (C = 0 skips the early-out).
        EXPECT_EQ(answer({0, 0, 1}).t0, 0.0);
        // Outside and pointing away: C = 24 > 0 and b = 5 > 0, rejected before any root.
        EXPECT_EQ(answer({0, 0, 5}).count, 0);
        // Outside, towards: the entry.
        EXPECT_EQ(answer({0, 0, -5}).t0, 4.0);
    }
}

TEST(IntersectorHandCases, LineRootVariantsOrderTheirRoots) {
    // Random-looking but tame cases: every line_roots variant returns t0 ≤ t1.
    const ray_sphere<double> cases[] = {
        {{0.25, -0.5, -3}, {0, 0, 1}, {0, 0, 0}, 1},    {{0.25, -0.5, 3}, {0, 0, -1}, {0, 0, 0}, 1},
        {{0.25, -0.5, 3}, {0, 0, 1}, {0, 0, 0}, 1},     {{0, 0, 0.5}, {0, 0, -1}, {0, 0, 0}, 1},
        {{-7, 0.5, 1}, {1, 0, 0}, {0, 0, 0}, 2},        {{1, 2, 3}, {0, -1, 0}, {1, -5, 3}, 0.75},
    };
    for (const variant& v : formulas()) {
        if (v.promises.query != query_kind::line_roots) continue;
        for (const precision p : both_precisions) {
            for (const ray_sphere<double>& g : cases) {
                SCOPED_TRACE(label(v, p));
                const root_pair<double> got = run(v, p, g);
                ASSERT_EQ(got.count, 2);
                EXPECT_LE(got.t0, got.t1);
            }
        }
    }
}

TEST(IntersectorHandCases, IrrationalRootsWithinTwoUlps) {
    // o = (½, 0, −5), r = 3/2: roots 5 ∓ √2 (worked in oracle_test). Each
    // variant rounds √Δ and one or two more operations: at most 2 ulps here.
    const ray_sphere<double> g{{0.5, 0, -5}, {0, 0, 1}, {0, 0, 0}, 1.5};
    for (const variant& v : formulas()) {
        for (const precision p : both_precisions) {
            SCOPED_TRACE(label(v, p));
            const exact_solution s = exact_for(g, p);
            const root_pair<double> got = run(v, p, g);
            if (v.promises.query == query_kind::any_hit) {
                EXPECT_EQ(got.count, 1);  // both roots 5 ∓ √2 lie in (0, +inf)
                continue;
            }
            if (v.promises.query == query_kind::nearest_hit) {
                ASSERT_EQ(got.count, 1);
                EXPECT_LE(s.root_ulp_error(near_root, got.t0), 2.0);
                continue;
            }
            ASSERT_EQ(got.count, 2);
            EXPECT_LE(s.root_ulp_error(near_root, got.t0), 2.0);
            EXPECT_LE(s.root_ulp_error(far_root, got.t1), 2.0);
        }
    }
}

// ---------------------------------------------------------------------------
// Known failures, reproduced. Each asserts exactly what goes wrong.

// 0.6f and 0.8f: a direction that is unit to float rounding (0.6f² + 0.8f²
// rounds to 1 in float), like a normalised camera ray.
constexpr double six_tenths_f = 0x1.333334p-1;
constexpr double eight_tenths_f = 0x1.99999ap-1;

TEST(KnownFailures, NaiveFloatLosesAUnitSphereAtDistance4100) {
    // RTG ch.7 fig. 7-3: a unit sphere 4100 away along the ray. f = o − c =
    // (0, −2460.5, −3280); |f|² = 16812460.25 rounds to 16812460 (floats in
    // [2^24, 2^25) are 2 apart), and − r² gives 16812459, a tie, back to
    // 16812460: C has lost r² entirely. b² = 67249832 and 4aC = 67249840
    // are each rounded to a multiple of 8, so Δ = −8 while exactly
    // 4(b′² − aC) ≈ +3.36: the sphere vanishes.
    const ray_sphere<double> g{{0, 0, 0}, {0, six_tenths_f, eight_tenths_f}, {0, 2460.5, 3280}, 1};
    const exact_solution s = exact_for(g, precision::binary32);
    ASSERT_EQ(s.cls, line_class::two_hit);
    EXPECT_EQ(s.near_root.rounded, double(4099.3833f));
    EXPECT_EQ(run(named("naive"), precision::binary32, g).count, 0);

    // Hearn–Baker forms Δ = r² − |l|² from the perpendicular vector l, with no
    // cancellation against |f|²: both hits, each within 2 ulps.
    const root_pair<double> hb = run(named("hearn_baker"), precision::binary32, g);
    ASSERT_EQ(hb.count, 2);
    EXPECT_LE(s.root_ulp_error(near_root, hb.t0), 2.0);
    EXPECT_LE(s.root_ulp_error(far_root, hb.t1), 2.0);
    // In double the same formula has 29 more bits to lose and keeps the hit.
    EXPECT_EQ(run(named("naive"), precision::binary64, g).count, 2);
}

TEST(KnownFailures, NaiveFloatFlattensAnAxisAlignedSphereAt4100IntoATangent) {
    // The RTG setup with an axis-aligned ray, o = (x, y, 0), d = (0, 0, 1),
    // cannot vanish: b² = 4·fl(f_z²) exactly and C = fl(fl(x² + y² + f_z²) − 1)
    // ≤ fl(f_z²) when x² + y² < 1, so Δ ≥ 0. But Δ is a multiple of 8 and the
    // true 4(r² − x² − y²) < 4, so every hit comes out as Δ = 0, a tangent at
    // t = 4100, where exactly the ray crosses the sphere at 4100 ∓ √0.6875.
    const ray_sphere<double> g{{0.5, 0.25, 0}, {0, 0, 1}, {0, 0, 4100}, 1};
    const exact_solution s = exact_for(g, precision::binary32);
    ASSERT_EQ(s.cls, line_class::two_hit);
    const root_pair<double> naive = run(named("naive"), precision::binary32, g);
    EXPECT_EQ(naive.count, 1);
    EXPECT_EQ(naive.t0, 4100.0);
    EXPECT_EQ(run(named("hearn_baker"), precision::binary32, g).count, 2);
}

TEST(KnownFailures, StableRootsGivesNaNForATangentRayStartingAtTheTangentPoint) {
    // o = (1, 0, 0), d = (0, 0, 1), unit sphere: f = (1, 0, 0), b = 2 d·f = 0,
    // C = 1 − 1 = 0, Δ = 0: exactly a tangent at t = 0. q = −½(0 + copysign(0, 0))
    // = −0, so t = q/a = −0 but C/q = 0/−0 = NaN; the swap test is false for NaN.
    const ray_sphere<double> g{{1, 0, 0}, {0, 0, 1}, {0, 0, 0}, 1};
    for (const precision p : both_precisions) {
        SCOPED_TRACE(precision_name(p));
        const exact_solution s = exact_for(g, p);
        ASSERT_EQ(s.cls, line_class::tangent);
        ASSERT_EQ(s.near_root.sign, 0);
        const root_pair<double> stable = run(named("stable_roots"), p, g);
        EXPECT_EQ(stable.count, 1);
        EXPECT_EQ(stable.t0, 0.0);
        EXPECT_TRUE(std::isnan(stable.t1));
        // Hearn–Baker's stable roots share the guardless q: b′ = −0, q = −0,
        // t0 = C/q = NaN, t1 = q/a = −0.
        const root_pair<double> hb = run(named("hearn_baker"), p, g);
        EXPECT_EQ(hb.count, 1);
        EXPECT_TRUE(std::isnan(hb.t0));
        EXPECT_EQ(hb.t1, 0.0);
        // naive divides −b by 2a instead and is fine.
        const root_pair<double> naive = run(named("naive"), p, g);
        EXPECT_EQ(naive.count, 1);
        EXPECT_EQ(naive.t0, 0.0);
    }
}

TEST(KnownFailures, Seed003CallsASmallSphereHitDeadCentreATangent) {
    // r = 1e−4, ray through the centre from 1 away: exactly p = −1,
    // q = 1 − r², Δ = p² − q = r² = 1e−8 and two hits at 1 ∓ r. The article's
    // tangent margin Δ ≤ 1e−7 is absolute, so any sphere with r < ~3.2e−4 hit
    // dead centre is "tangent". In float q = fl(1 − 1e−8) = 1 and Δ = 0; in
    // double Δ ≈ 1.000000005e−8, two distinct roots are computed and then
    // labelled a tangent anyway.
    const ray_sphere<double> g{{0, 0, -1}, {0, 0, 1}, {0, 0, 0}, 1e-4};
    const variant& seed003 = named("seed003_reduced");
    for (const precision p : both_precisions) {
        SCOPED_TRACE(precision_name(p));
        ASSERT_EQ(exact_for(g, p).cls, line_class::two_hit);
        EXPECT_EQ(run(seed003, p, g).count, 1);
    }
    const root_pair<double> twice = run(seed003, precision::binary64, g);
    EXPECT_LT(twice.t0, twice.t1);

    // The same picture in units 2^14 times larger (every input scaled exactly,
    // so the exact answer is the same up to scale): Δ ≈ 2.68 and two hits.
    const ray_sphere<double> big{{0, 0, -0x1p14}, {0, 0, 1}, {0, 0, 0}, 0x1p14 * 1e-4};
    EXPECT_EQ(exact_for(big, precision::binary64).cls, line_class::two_hit);
    EXPECT_EQ(run(seed003, precision::binary64, big).count, 2);
}

TEST(KnownFailures, GeometricFloatMisclassifiesFarSpheres) {
    const variant& geometric = named("geometric");
    const variant& hearn_baker = named("hearn_baker");

    // A phantom hit. o = (1.5, 0, 0), d = (0, 0, 1), c = (0, 0, 10⁴), r = 1:
    // the ray passes 1.5 from the centre, a miss. L = (−1.5, 0, 10⁴),
    // L·L = 2.25 + 10⁸ rounds to 10⁸ (floats near 10⁸ are 8 apart) and
    // t_ca² = 10⁸ exactly, so d² = 0: the ray "passes through the centre" and
    // geometric returns two hits at 10⁴ ∓ 1.
    const ray_sphere<double> phantom{{1.5, 0, 0}, {0, 0, 1}, {0, 0, 1e4}, 1};
    ASSERT_EQ(exact_for(phantom, precision::binary32).cls, line_class::miss);
    const root_pair<double> ghost = run(geometric, precision::binary32, phantom);
    EXPECT_EQ(ghost.count, 2);
    EXPECT_EQ(ghost.t0, 9999.0);
    EXPECT_EQ(ghost.t1, 10001.0);
    EXPECT_EQ(run(hearn_baker, precision::binary32, phantom).count, 0);  // Δ = 1 − 2.25 < 0
    EXPECT_EQ(run(geometric, precision::binary64, phantom).count, 0);

    // A lost hit. o = 0, d = (0, 0.6f, 0.8f), c = (0, 5999.75, 8000), r = 1:
    // the centre is 0.2 from the ray (d² = 0.0400… exactly), a clear hit.
    // L·L = 99997000.0625 rounds to 99997000 and t_ca² to 99996992, so the
    // computed d² = 8 > r² = 1 and geometric rejects it.
    const ray_sphere<double> lost{{0, 0, 0}, {0, six_tenths_f, eight_tenths_f}, {0, 5999.75, 8000}, 1};
    const exact_solution s = exact_for(lost, precision::binary32);
    ASSERT_EQ(s.cls, line_class::two_hit);
    EXPECT_EQ(run(geometric, precision::binary32, lost).count, 0);
    const root_pair<double> hb = run(hearn_baker, precision::binary32, lost);
    ASSERT_EQ(hb.count, 2);
    EXPECT_LE(s.root_ulp_error(near_root, hb.t0), 2.0);
    EXPECT_LE(s.root_ulp_error(far_root, hb.t1), 2.0);
    EXPECT_EQ(run(geometric, precision::binary64, lost).count, 2);
}

}  // namespace
}  // namespace rayverify
