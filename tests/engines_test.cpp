// The engine ports: each pinned on a few cases worked out by hand from the
// engine's own formula (integers where the arithmetic is exact, and the cases
// where the engine's design shows: clamps, culled back faces, a shift that is
// not to the centre's plane, a hit behind the origin), each judged under its
// contract, and every engine on the shipped corpus and every shipped scene.
#include <gtest/gtest.h>

#include <cfloat>
#include <filesystem>

#include "compare/audit.h"
#include "compare/judge.h"
#include "corpus/corpus_io.h"
#include "intersectors/cycles_point.h"
#include "intersectors/embree4_sphere.h"
#include "intersectors/neon_recip.h"
#include "intersectors/godot_segment.h"
#include "intersectors/jolt_ray_sphere.h"
#include "intersectors/mitsuba3_sphere.h"
#include "intersectors/naive.h"
#include "intersectors/pbrt_v4_sphere.h"
#include "intersectors/raylib_collision.h"
#include "intersectors/registry.h"
#include "intersectors/threejs_ray.h"
#include "intersectors/wald_origin_shift.h"
#include "oracle/oracle.h"
#include "scene/scene.h"
#include "scene/scene_audit.h"
#include "core/input_error.h"

namespace rayverify {
namespace {

using namespace intersectors;

constexpr float inf_f = std::numeric_limits<float>::infinity();
constexpr double inf_d = std::numeric_limits<double>::infinity();

// The unit sphere at the origin seen from z = −5 along +z: roots 4 and 6.
template <class T>
ray_sphere<T> towards(vec3<T> origin = {0, 0, -5}, vec3<T> direction = {0, 0, 1}, T radius = 1) {
    return {origin, direction, {0, 0, 0}, radius};
}

const std::vector<variant> engines() {
    std::vector<variant> out;
    for (const variant& v : builtin_variants())
        if (!v.build.empty()) out.push_back(v);
    return out;
}

TEST(Engines, RegistryListsEveryEngineWithItsBuild) {
    std::vector<std::string> names;
    for (const variant& v : engines()) names.push_back(v.name);
    const std::vector<std::string> expected{"pbrt_v4", "mitsuba3_preliminary", "mitsuba3_ray_test", "embree4",
                                            "cycles_point", "jolt", "jolt_fma", "threejs", "godot", "raylib"};
    EXPECT_EQ(names, expected);
    ASSERT_NE(find_builtin_variant("wald_origin_shift"), nullptr);
    // Float-only and double-only engines have only those rows.
    for (const char* float_only : {"embree4", "cycles_point", "jolt", "jolt_fma", "raylib"}) {
        EXPECT_TRUE(find_builtin_variant(float_only)->runs_in(precision::binary32)) << float_only;
        EXPECT_FALSE(find_builtin_variant(float_only)->runs_in(precision::binary64)) << float_only;
    }
    EXPECT_FALSE(find_builtin_variant("threejs")->runs_in(precision::binary32));
    for (const variant& v : engines()) {
        EXPECT_EQ(contract_problem(v.promises), std::nullopt) << v.name;
        EXPECT_EQ(format_contract(parse_contract(format_contract(v.promises))), format_contract(v.promises)) << v.name;
    }
}

TEST(Engines, PbrtV4IntervalsAndDesign) {
    // Roots 4 and 6: the interval midpoint, an interval holding 4, a few ulps wide.
    for (const answer<float> a : {pbrt_v4(towards<float>(), 0.0f, inf_f)}) {
        ASSERT_EQ(a.roots.count, 1);
        EXPECT_EQ(a.roots.t0, (a.t_lower[0] + a.t_upper[0]) / 2);
        EXPECT_LE(a.t_lower[0], 4.0f);
        EXPECT_GE(a.t_upper[0], 4.0f);
        EXPECT_LT(a.t_upper[0] - a.t_lower[0], 64 * 0x1p-21f);
        // The reprojected point lies within its own bound of (0, 0, −1).
        EXPECT_LE(std::abs(a.point.z + 1), a.point_error.z);
        EXPECT_EQ(a.point.x, 1e-5f) << "a hit on the z axis is moved to x = 1e-5·r";
    }
    // tMax is closed, judged on the interval's upper end: tMax = 3 misses the root 4.
    EXPECT_EQ(pbrt_v4(towards<double>(), 0.0, 3.0).roots.count, 0);
    // From the centre: the near root's interval lies below 0, so the far root 1.
    const answer<double> inside = pbrt_v4(towards<double>({0, 0, 0}), 0.0, inf_d);
    ASSERT_EQ(inside.roots.count, 1);
    EXPECT_LE(inside.t_lower[0], 1.0);
    EXPECT_GE(inside.t_upper[0], 1.0);
    // An exact tangent at t = 5: the discriminant's interval reaches below 0, a miss by design.
    EXPECT_EQ(pbrt_v4(towards<double>({1, 0, -5}), 0.0, inf_d).roots.count, 0);
    EXPECT_FALSE(pbrt_v4_contract.tangent_is_hit);
    // A root at the origin (o on the surface): its interval holds 0, so it is behind; the far root 2.
    const answer<double> surface = pbrt_v4(towards<double>({0, 0, -1}), 0.0, inf_d);
    ASSERT_EQ(surface.roots.count, 1);
    EXPECT_NEAR(surface.roots.t0, 2.0, 1e-14);
}

// pbrt-v4's point bound γ₅·|p| is the reprojected point's distance to the
// surface (point_error=surface): judged by whether its box holds a point of
// the sphere, decided exactly. On the z axis pbrt moves the point to
// x = 1e-5·r, off the sphere by r·(1 − √(1 − 10⁻¹⁰)) ≈ 5e-11·r: inside the box
// in float (γ₅ ≈ 3e-7), outside it in double (γ₅ ≈ 6e-16).
TEST(Engines, PbrtV4PointBoundHoldsTheSurface) {
    const contract c = parse_contract("query=nearest_hit,hit_point=yes,point_error=surface");
    EXPECT_EQ(c.outputs.point_error, point_bound::surface);
    EXPECT_EQ(parse_contract(format_contract(c)).outputs.point_error, point_bound::surface);
    EXPECT_EQ(pbrt_v4_contract.outputs.point_error, point_bound::surface);
    try {
        parse_contract("query=nearest_hit,hit_point=yes,point_error=maybe");
        ADD_FAILURE() << "point_error=maybe parsed";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("expected no, yes, surface"), std::string::npos) << e.what();
    }
    // The unit sphere at the origin: a box across the surface meets it, boxes wholly inside or outside do not;
    // a degenerate box meets it only on it.
    const vec3<double> centre{0, 0, 0};
    EXPECT_TRUE(box_meets_sphere({0.9, -0.1, -0.1}, {1.1, 0.1, 0.1}, centre, 1));
    EXPECT_FALSE(box_meets_sphere({0.1, 0.1, 0.1}, {0.2, 0.2, 0.2}, centre, 1));
    EXPECT_FALSE(box_meets_sphere({2, 2, 2}, {3, 3, 3}, centre, 1));
    EXPECT_TRUE(box_meets_sphere({0, 1, 0}, {0, 1, 0}, centre, 1));
    EXPECT_FALSE(box_meets_sphere({0, 1 + 0x1p-52, 0}, {0, 1 + 0x1p-52, 0}, centre, 1));
    EXPECT_FALSE(box_meets_sphere({0.6, 0.8, 0}, {0.6, 0.8, 0}, centre, 1))
        << "0.6 and 0.8 are not binary fractions: the point is off the sphere by about 1e-17";
    // The axis hit in both precisions.
    corpus_case axis;
    axis.id = "axis";
    axis.geometry = towards<double>();
    const auto score = [&](precision p) {
        return judge_target({*find_builtin_variant("pbrt_v4"), p}, axis, solve_case(axis, p)).score;
    };
    EXPECT_EQ(score(precision::binary32).verdict, verdict_kind::agree);
    const case_score in_double = score(precision::binary64);
    EXPECT_EQ(in_double.verdict, verdict_kind::unsound_bound);
    EXPECT_NE(in_double.detail.find("holds no point of the sphere"), std::string::npos) << in_double.detail;
}

TEST(Engines, Mitsuba3ShiftsByOverLengthOfD) {
    // plane_t = dot(−l, d)/|d| = 5, o′ = 0: A = 1, B = 0, C = −1, Δ = 4, temp = −1, roots −1, 1; + 5.
    EXPECT_EQ(mitsuba3_preliminary(towards<double>(), 0.0, inf_d).t0, 4.0);
    EXPECT_EQ(mitsuba3_preliminary(towards<float>(), 0.0f, inf_f).t0, 4.0f);
    // d = (0, 0, 2): plane_t = 10/|d| = 5 (not 10/|d|² = 2.5), o′ = (0, 0, 5): A = 4, B = 20,
    // C = 24, Δ = 16, temp = −12, roots −3 and −2; + 5: 2, 3, the true roots.
    EXPECT_EQ(mitsuba3_preliminary(towards<double>({0, 0, -5}, {0, 0, 2}), 0.0, inf_d).t0, 2.0);
    // From the centre: near −1 < 0, far 1: the far root; with maxt = 0.5 the segment lies inside: a miss.
    EXPECT_EQ(mitsuba3_preliminary(towards<double>({0, 0, 0}), 0.0, inf_d).t0, 1.0);
    EXPECT_EQ(mitsuba3_preliminary(towards<double>({0, 0, 0}), 0.0, 0.5).count, 0);
    // maxt is closed: a root exactly at maxt = 4 is a hit.
    EXPECT_EQ(mitsuba3_preliminary(towards<double>(), 0.0, 4.0).count, 1);
    // ray_test: the same decisions without the shift.
    EXPECT_EQ(mitsuba3_ray_test(towards<float>(), 0.0f, inf_f).count, 1);
    EXPECT_EQ(mitsuba3_ray_test(towards<float>({0, 0, 0}), 0.0f, 0.5f).count, 0);
    EXPECT_EQ(mitsuba3_ray_test(towards<float>(), 0.0f, 3.5f).count, 0);
}

// FRECPE by the Arm ARM's pseudocode, worked by hand: the fraction's top 8
// bits m give scaled = 256 + m, RecipEstimate(a) = ((2^19 div (2a + 1)) + 1) div 2,
// result_exp = 253 − exp, and the estimate's low 8 bits the new fraction.
TEST(Engines, NeonReciprocalEstimate) {
    EXPECT_EQ(neon::recip_estimate(256), 511);  // 2^19 div 513 = 1022, (1022 + 1) div 2 = 511
    EXPECT_EQ(neon::recip_estimate(258), 507);  // 2^19 div 517 = 1014
    EXPECT_EQ(neon::recip_estimate(384), 341);  // 2^19 div 769 = 681
    EXPECT_EQ(neon::frecpe(1.0f), 0.998046875f);    // 2^-1·(1 + 255/256)
    EXPECT_EQ(neon::frecpe(2.0f), 0.4990234375f);   // 2^-2·(1 + 255/256)
    EXPECT_EQ(neon::frecpe(3.0f), 0.3330078125f);   // m = 128: 2^-2·(1 + 85/256)
    EXPECT_EQ(neon::frecpe(-1.5f), -0.666015625f);  // m = 128, exp 127: −2^-1·(1 + 85/256)
    EXPECT_EQ(neon::frecpe(0x1.02p0f), 0x1.fbp-1f);  // m = 2: 2^-1·(1 + 251/256)
    // Subnormal in (2^-128 is scaled = 256 with exp −1) and out (2^127: result_exp −1).
    EXPECT_EQ(neon::frecpe(0x1p-128f), 0x1.ffp127f);
    EXPECT_EQ(neon::frecpe(0x1p-127f), 0x1.ffp126f);
    EXPECT_EQ(neon::frecpe(0x1p127f), 0x1.ffp-128f);
    // Specials: below 2^-128 it overflows to ∞ (round to nearest); ±0 → ±∞; ∞ → 0.
    EXPECT_EQ(neon::frecpe(0x1p-129f), inf_f);
    EXPECT_EQ(neon::frecpe(-0.0f), -inf_f);
    EXPECT_EQ(neon::frecpe(inf_f), 0.0f);
    EXPECT_TRUE(std::isnan(neon::frecpe(std::numeric_limits<float>::quiet_NaN())));
    EXPECT_EQ(neon::frecps(inf_f, 0.0f), 2.0f);
    EXPECT_EQ(neon::frecps(3.0f, 0.3330078125f), 1.0009765625f);  // 2 − 1023/1024, exact
    // Embree's rcp: estimate and two Newton steps. For 1: 0.998046875 → 1 − 2^-18 → 1 − 2^-36,
    // rounded to 1. For 3: 341/1024 → (2^20 − 1)/(3·2^20) → (1 − 2^-40)/3, rounded as 1/3 is.
    EXPECT_EQ(embree::rcp(1.0f), 1.0f);
    EXPECT_EQ(embree::rcp(3.0f), 1.0f / 3.0f);
    // For 1 + 2^-7 the two steps land one ulp below the quotient (checked in exact rationals).
    EXPECT_EQ(embree::rcp(0x1.02p0f), 0x1.fc07eep-1f);
    EXPECT_EQ(1.0f / 0x1.02p0f, 0x1.fc07f0p-1f);
}

// Embree's d·d on aarch64 is the Vec3ff dot, products then (x·x + y·y) + z·z;
// its other dots are madd chains. They differ here (exact rationals: the
// plain sum 0x1.03b124p+3, the fused chain 0x1.03b126p+3).
TEST(Engines, Embree4DotOrder) {
    const vec3<float> d{0x1.227p0f, 0x1.f11p0f, 0x1.bfbp0f};
    EXPECT_EQ(embree::dot_vec3ff(d, d), 0x1.03b124p+3f);
    EXPECT_EQ(embree::dot(d, d), 0x1.03b126p+3f);
    // The port's rd2 is rcp of the plain sum: its hit on a sphere straight ahead uses it.
    const ray_sphere<float> s{{0, 0, 0}, d, {4 * d.x, 4 * d.y, 4 * d.z}, 1};
    const float rd2 = embree::rcp(embree::dot_vec3ff(d, d));
    const float proj = embree::dot(s.centre - s.origin, d) * rd2;
    const vec3<float> perp = (s.centre - s.origin) - proj * d;
    const float td = std::sqrt((1.0f - embree::dot(perp, perp)) * rd2);
    EXPECT_EQ(embree4(s, 0.0f, inf_f).roots.t0, proj - td);
    // rd2 = 0x1.f8b896p-4, t = 0x1.d3116cp+1; 1.0f over the fused chain (the port before it
    // followed upstream) gave rd2 = 0x1.f8b894p-4 and t = 0x1.d31168p+1.
    EXPECT_EQ(rd2, 0x1.f8b896p-4f);
    EXPECT_EQ(1.0f / embree::dot(d, d), 0x1.f8b894p-4f);
    EXPECT_EQ(embree4(s, 0.0f, inf_f).roots.t0, 0x1.d3116cp+1f);
}

TEST(Engines, Embree4AndCycles) {
    // rd2 = 1, c0 = (0, 0, 5), projC0 = 5, perp = 0, l2 = 0, td = 1: t_front = 4, Ng = −td·d − perp.
    const answer<float> front = embree4(towards<float>(), 0.0f, inf_f);
    EXPECT_EQ(front.roots.t0, 4.0f);
    EXPECT_EQ(front.normal, (vec3<float>{0, 0, -1}));
    // From the centre t_front = −1 < tnear: the back hit 1, Ng = +td·d.
    const answer<float> back = embree4(towards<float>({0, 0, 0}), 0.0f, inf_f);
    EXPECT_EQ(back.roots.t0, 1.0f);
    EXPECT_EQ(back.normal, (vec3<float>{0, 0, 1}));
    // Both ends closed: tnear = 4 and tfar = 4 still hit the root 4.
    EXPECT_EQ(embree4(towards<float>(), 4.0f, 4.0f).roots.count, 1);
    // Cycles culls the back face: from the centre, nothing.
    EXPECT_EQ(cycles_point(towards<float>(), 0.0f, inf_f).t0, 4.0f);
    EXPECT_EQ(cycles_point(towards<float>({0, 0, 0}), 0.0f, inf_f).count, 0);
    // d = (0, 0, 2): rd2 = 1/4, projC0 = 10/4 = 2.5, td = √(1/4) = 0.5: t = 2.
    EXPECT_EQ(cycles_point(towards<float>({0, 0, -5}, {0, 0, 2}), 0.0f, inf_f).t0, 2.0f);
}

TEST(Engines, JoltFractionsOfASegment) {
    // No tmax: the unbounded ray, direction d itself: a = 1, b = −10, C = 24, det = 4,
    // q = (−10 − 2)/−2 = 6, fractions 6 and 24/6 = 4: the nearer, 4, is t.
    EXPECT_EQ(jolt(towards<float>(), 0.0f, inf_f).t0, 4.0f);
    EXPECT_EQ(jolt_fma(towards<float>(), 0.0f, inf_f).t0, 4.0f);
    // tmin = 2 moves the origin to z = −3: the fraction 2 is t − tmin.
    EXPECT_EQ(jolt(towards<float>(), 2.0f, inf_f).t0, 4.0f);
    // From the centre: C < 0, the fractions straddle 0: clamped to 0.
    const root_pair<float> inside = jolt(towards<float>({0, 0, 0}), 0.0f, inf_f);
    EXPECT_EQ(inside.count, 1);
    EXPECT_EQ(inside.t0, 0.0f);
    // A finite tmax is the segment's end: tmax = 3 stops before the root 4 (fraction 4/3 ≥ 1 + ε).
    EXPECT_EQ(jolt(towards<float>(), 0.0f, 3.0f).count, 0);
    EXPECT_EQ(jolt(towards<float>(), 0.0f, 8.0f).t0, 4.0f);
    EXPECT_EQ(jolt_contract.inside, inside_rule::clamp);
}

// The wrapper must not make Jolt overflow where Jolt, given the ray, does not.
// A unit sphere 2^32 along the axis: given d, a = 1, b = −2^33, C = 2^64 − 1 →
// 2^64 (float), det = 2^66 − 2^66 = 0, q = 2^32: t = 2^32 (the roots 2^32 ∓ 1,
// within half an ulp of float at 2^32). The old wrapper stretched d to the
// segment L·d with L = segment_length = 2^34: b = −2^67, b² = inf, 4aC = inf,
// det = NaN, and Jolt answered a miss it never gives for this ray.
TEST(Engines, JoltWrapperDoesNotInventOverflow) {
    const ray_sphere<float> far = towards<float>({0, 0, -0x1p32f});
    EXPECT_EQ(segment_length(far), 0x1p34f);
    EXPECT_EQ(jolt_math::ray_sphere<jolt_build::deterministic>(far.origin, segment_length(far) * far.direction, far.centre,
                                                               far.radius),
              FLT_MAX)
        << "the old mapping: the stretched segment overflows";
    for (const auto port : {&jolt<float>, &jolt_fma<float>}) {
        const root_pair<float> hit = port(far, 0.0f, inf_f);
        ASSERT_EQ(hit.count, 1);
        EXPECT_EQ(hit.t0, 0x1p32f);
    }
    // A shipped case the old mapping lost the same way: tangent_exact-1-000025, an exact
    // tangent 2^33 away along d = (0, 0, 1) (L = 2^36): tangent_missed then, agree now.
    const std::vector<corpus_case> cases = parse_corpus(
        "regression",
        "tangent_exact-1-000025 tangent_exact -0x1.75p+29 -0x1.d44p+31 -0x1.cf6cp+33 0x0p+0 0x0p+0 0x1p+0 "
        "-0x1p+19 -0x1p+21 0x1.8p+20 0x1.dd3p+31\n",
        false);
    ASSERT_EQ(cases.size(), 1u);
    for (const char* name : {"jolt", "jolt_fma"}) {
        const case_score s = judge_target({*find_builtin_variant(name), precision::binary32}, cases[0],
                                          solve_case(cases[0], precision::binary32))
                                 .score;
        EXPECT_EQ(s.verdict, verdict_kind::agree) << name;
    }
}

// jolt and jolt_fma differ only in the build: a far sphere (float inputs,
// far_sphere-1-000000 rounded) where b² and 4aC ≈ 2^91 cancel. Unfused, both
// products round to the same float and det = 0: a hit (at the double root,
// between the two exact roots: wrong_root). With Kahan's DifferenceOfProducts
// (and C = fma(−r, r, |f|²)) det = −0x1.c0e458p+20: a miss (false_miss); the
// exact answer is two hits.
TEST(Engines, JoltFmaBuildChangesTheAnswer) {
    const ray_sphere<float> s{{-0x1.753a14p-1f, 0x1.87d92ap-1f, 0x1.7d859ap-2f},
                              {0x1.130bap-3f, 0x1.be9c6ap-3f, 0x1.eeec7cp-1f},
                              {0x1.2ef9a2p+19f, 0x1.ebf68cp+19f, 0x1.10973ap+22f},
                              0x1.dcafep-1f};
    const vec3<float> f = s.origin - s.centre;
    const float a = jolt_math::dot<jolt_build::deterministic>(s.direction, s.direction);
    const float b = 2.0f * jolt_math::dot<jolt_build::deterministic>(s.direction, f);
    const float c = jolt_math::dot<jolt_build::deterministic>(f, f) - s.radius * s.radius;
    EXPECT_EQ(jolt_math::difference_of_products<jolt_build::deterministic>(b, b, 4.0f * a, c), 0.0f);
    EXPECT_EQ(jolt_math::difference_of_products<jolt_build::fma>(b, b, 4.0f * a, c), -0x1.c0e458p+20f);
    EXPECT_EQ(jolt(s, 0.0f, inf_f).count, 1);
    EXPECT_EQ(jolt_fma(s, 0.0f, inf_f).count, 0);
}

TEST(Engines, PointAnswersThreeJsGodotRaylib) {
    // three.js: tca = 5, d2 = 0, thc = 1, t0 = 4: the point (0, 0, −1), its t derived: 4.
    const answer<double> three = threejs(towards<double>(), 0, inf_d);
    EXPECT_EQ(three.point, (vec3<double>{0, 0, -1}));
    EXPECT_EQ(three.roots.t0, 4.0);
    EXPECT_EQ(threejs(towards<double>({0, 0, 5}), 0, inf_d).roots.count, 0) << "t1 < 0: behind";
    // Godot: to = o + 16·d; n = (0, 0, 1), s = 5, dist = 0, h² = 1: t = 4, normal (0, 0, −1).
    const answer<float> godot_f = godot(towards<float>(), 0.0f, inf_f);
    EXPECT_EQ(godot_f.point, (vec3<float>{0, 0, -1}));
    EXPECT_EQ(godot_f.normal, (vec3<float>{0, 0, -1}));
    EXPECT_EQ(godot_f.roots.t0, 4.0f);
    // Starting inside: the near root −1 is before `from`: a miss.
    EXPECT_EQ(godot(towards<double>({0, 0, 0}), 0.0, inf_d).roots.count, 0);
    // Near a tangent (r² − dist² = 1 − 0.999999² ≈ 2e-6 < CMP_EPSILON) the point is the closest approach, t = 5.
    const answer<double> grazing = godot(towards<double>({0, 0.999999, -5}), 0.0, inf_d);
    ASSERT_EQ(grazing.roots.count, 1);
    EXPECT_EQ(grazing.roots.t0, 5.0);
    // raylib: b = 5, |v| = 5, disc = 1: t = 4, point (0, 0, −1), normal (0, 0, −1).
    const answer<float> ray_f = raylib(towards<float>(), 0.0f, inf_f);
    EXPECT_EQ(ray_f.point, (vec3<float>{0, 0, -1}));
    EXPECT_EQ(ray_f.normal, (vec3<float>{0, 0, -1}));
    // A sphere behind the origin is a hit at t = −5 − 1 = −6 (no sign test).
    const answer<float> behind = raylib(towards<float>({0, 0, 5}), 0.0f, inf_f);
    ASSERT_EQ(behind.roots.count, 1);
    EXPECT_EQ(behind.roots.t0, -6.0f);
    // From the centre: |v| = 0 < r, t = 0 + 1, the normal negated: (0, 0, −1).
    const answer<float> from_centre = raylib(towards<float>({0, 0, 0}), 0.0f, inf_f);
    EXPECT_EQ(from_centre.roots.t0, 1.0f);
    EXPECT_EQ(from_centre.normal, (vec3<float>{0, 0, -1}));
}

TEST(Engines, WaldOriginShiftKeepsFarSpheres) {
    // t_s = 5, o′ = 0: b = 0, C = −1, Δ = 4: t = 5 ∓ 1.
    const root_pair<double> r = wald_origin_shift(towards<double>());
    EXPECT_EQ(r.count, 2);
    EXPECT_EQ(r.t0, 4.0);
    EXPECT_EQ(r.t1, 6.0);
    // A unit sphere 2^13 away, half a radius off the axis: in float the textbook C = |f|² − r²
    // rounds to 2^26, Δ to 0, and the two roots 8192 ∓ √0.75 collapse to a tangent; after the
    // shift |f| = 0.5, C = −0.75, and both roots are there.
    const ray_sphere<float> far{{0, 0, 0}, {1, 0, 0}, {8192, 0.5f, 0}, 1};
    EXPECT_EQ(naive(far).count, 1) << "the textbook form reports a tangent";
    const root_pair<float> shifted = wald_origin_shift(far);
    ASSERT_EQ(shifted.count, 2);
    const exact_solution e = solve_exact(rounded_to<double>(far), precision::binary32);
    EXPECT_LE(e.root_ulp_error(root_index::near_root, shifted.t0), 1.0);
    EXPECT_LE(e.root_ulp_error(root_index::far_root, shifted.t1), 1.0);
}

// The judge applies each engine's contract: raylib's hit behind the origin is
// a false hit by design (line_not_ray); pbrt's missed tangent agrees; Cycles
// from inside agrees (front faces only), while a renderer asking for the exit
// sees a by-design miss.
TEST(Engines, JudgedUnderTheirContracts) {
    const auto judged = [](const char* name, precision p, ray_sphere<double> g) {
        corpus_case c;
        c.id = name;
        c.geometry = g;
        return judge_target({*find_builtin_variant(name), p}, c, solve_case(c, p)).score;
    };
    const case_score behind = judged("raylib", precision::binary32, towards<double>({0, 0, 5}));
    EXPECT_EQ(behind.verdict, verdict_kind::false_hit);
    EXPECT_EQ(behind.cause, disagreement_cause::line_not_ray);
    EXPECT_EQ(judged("pbrt_v4", precision::binary64, towards<double>({1, 0, -5})).verdict, verdict_kind::agree);
    EXPECT_EQ(judged("cycles_point", precision::binary32, towards<double>({0, 0, 0})).verdict, verdict_kind::agree);
    const case_score jolt_inside = judged("jolt", precision::binary32, towards<double>({0, 0, 0}));
    EXPECT_EQ(jolt_inside.verdict, verdict_kind::agree);
    // Points are judged as points: three.js's hit point is exact here.
    const case_score three = judged("threejs", precision::binary64, towards<double>());
    ASSERT_TRUE(three.hit_point_ulp);
    EXPECT_EQ((*three.hit_point_ulp)[2], 0.0);
    // Embree's normal is exactly the outward normal here: angle 0.
    const case_score embree = judged("embree4", precision::binary32, towards<double>());
    ASSERT_TRUE(embree.normal_angle);
    EXPECT_EQ(*embree.normal_angle, 0.0);
    // pbrt's bound holds the root; the error in the length scale of an exact-ish answer is tiny.
    const case_score pbrt = judged("pbrt_v4", precision::binary32, towards<double>({0.25, 0, -5}));
    EXPECT_EQ(pbrt.verdict, verdict_kind::agree);
    ASSERT_TRUE(pbrt.bound_ulp && pbrt.scale_error_radius);
    EXPECT_GE(*pbrt.bound_ulp, 1);
    EXPECT_LT(*pbrt.scale_error_radius, 1e-5);
}

// The length-scale error where ULPs cannot count: an origin exactly on the
// sphere has the root t* = 0, where three.js's derived t is about 1e-8 (the
// regression case on_surface-1-000024), infinitely many ULPs but about 1e-16
// radii away.
TEST(EnginesRegression, ScaleErrorAtAnExactZeroRoot) {
    const std::vector<corpus_case> cases =
        parse_corpus("regression", "on_surface-1-000024 on_surface -0x1p+22 0x1.4p+23 -0x1.3ap+26 -0x1.c667ce253d78fp-1 "
                         "-0x1.79ea1ea41f766p-2 0x1.1a85df94e49acp-2 0x1.cp+21 0x1.ep+23 0x1.4p+21 0x1.46p+26\n",
                     false);
    ASSERT_EQ(cases.size(), 1u);
    const case_score s =
        judge_target({*find_builtin_variant("threejs"), precision::binary64}, cases[0], solve_case(cases[0], precision::binary64))
            .score;
    ASSERT_EQ(s.verdict, verdict_kind::agree);
    ASSERT_TRUE(s.scale_error_radius && s.scale_error_distance);
    // |t|·|d|/r with |t| < 1e-7, |d| ≈ 1, r = 85458944.
    EXPECT_GT(*s.scale_error_radius, 0);
    EXPECT_LT(*s.scale_error_radius, 1e-7 * 1.0000001 / 85458944);
    EXPECT_TRUE(std::isfinite(*s.scale_error_distance));
}

// Every engine on the shipped corpus (the audit of corpus_regression_test
// covers the formulas): no malformed answer, no unsound pbrt bound, most
// cases agree, and the by-design findings carry their causes.
TEST(Engines, EveryEngineOnTheShippedCorpus) {
    const std::vector<corpus_case> cases = read_corpus({RAYVERIFY_CORPUS_DIR});
    const std::vector<variant> all = engines();
    const audit_totals totals = run_audit(cases, targets_for(all));
    ASSERT_EQ(totals.targets.size(), 14u) << "pbrt, mitsuba ×2 and godot in both precisions, six in one";
    for (std::size_t t = 0; t < totals.targets.size(); ++t) {
        const target_tally& tally = totals.overall[t];
        const std::string label = totals.targets[t].label();
        SCOPED_TRACE(label);
        EXPECT_EQ(tally.verdicts[static_cast<int>(verdict_kind::malformed_output)], 0u);
        EXPECT_EQ(tally.verdicts[static_cast<int>(verdict_kind::unsound_bound)], 0u);
        EXPECT_GT(tally.verdicts[static_cast<int>(verdict_kind::agree)], tally.cases / 2);
        if (totals.targets[t].subject.promises.query != query_kind::any_hit) {
            EXPECT_GT(tally.errors[rayverify::error_figure::scale_error_radius].count, 0u);
        }
    }
    // raylib's hits behind the origin are by design.
    for (std::size_t t = 0; t < totals.targets.size(); ++t) {
        if (totals.targets[t].subject.name == "raylib") {
            EXPECT_GT(totals.overall[t].causes[static_cast<int>(disagreement_cause::line_not_ray)], 0u);
        }
    }
}

// Every engine on every shipped scene where it applies: the audit runs, every
// ray is judged, and the rays an engine is not asked (a unit-direction engine
// on unnormalised rays, a float engine in a double scene) are named.
TEST(Engines, EveryEngineOnEveryShippedScene) {
    const std::vector<variant> all = engines();
    int audited = 0;
    for (const auto& entry : std::filesystem::directory_iterator(std::filesystem::path(RAYVERIFY_CORPUS_DIR) / "scenes")) {
        if (entry.path().extension() != ".json") continue;
        scene s = read_scene(entry.path());
        s.sample = {false, 200, 1};  // 200 pixels of each: bounded time
        const std::vector<scene_ray> rays = generate_rays(s);
        const std::vector<audit_target> targets = scene_targets(s, all);
        ASSERT_FALSE(targets.empty()) << entry.path();
        const scene_audit_result r = audit_scene(s, rays, targets);
        EXPECT_EQ(r.pixels, 200u) << entry.path();
        for (const audit_target& t : targets) {
            if (not_applicable_reason(s, t)) continue;
            ++audited;
        }
    }
    EXPECT_GT(audited, 6 * 4);
}

// An engine's own spawn rule in a scene: the reflected rays of
// secondary_self_hit.json start at the rounded hit point, about half of them
// just inside the sphere, which exactly they then hit again. pbrt-v4's offset
// by the point's error bound along the normal and Mitsuba 3's epsilon both
// move every origin out; the exact audit sees no re-hit.
TEST(Engines, SpawnRulesOfPbrtAndMitsubaLeaveTheSurface) {
    const scene base = read_scene(std::filesystem::path(RAYVERIFY_CORPUS_DIR) / "scenes" / "secondary_self_hit.json");
    const auto exact_rehits = [&](offset_rule rule) {
        scene s = base;
        s.sample = {false, 400, 3};
        s.secondary_spawn.rule = rule;
        const std::vector<scene_ray> rays = generate_rays(s);
        return audit_scene(s, rays, {}).exact[static_cast<int>(ray_kind::secondary)];
    };
    const exact_kind_figures none = exact_rehits(offset_rule::none);
    ASSERT_GT(none.rays, 100u);
    EXPECT_GT(none.hits, none.rays / 4) << "without an offset, rounding puts origins inside";
    for (offset_rule rule : {offset_rule::pbrt_v4, offset_rule::mitsuba3}) {
        const exact_kind_figures moved = exact_rehits(rule);
        EXPECT_EQ(moved.rays, none.rays);
        EXPECT_EQ(moved.hits, 0u) << static_cast<int>(rule);
    }
    // pbrt's offset is one float step past |n|·error: small against Mitsuba's (1 + max|P|)·1500·2^-24.
    const auto first_secondary_lift = [&](offset_rule rule) {
        scene s = base;
        s.sample = {false, 400, 3};
        s.secondary_spawn.rule = rule;
        for (const scene_ray& r : generate_rays(s))
            if (r.kind == ray_kind::secondary) return std::sqrt(length_squared(r.origin)) - 1000;
        return -1.0;
    };
    const double pbrt_lift = first_secondary_lift(offset_rule::pbrt_v4);
    const double mitsuba_lift = first_secondary_lift(offset_rule::mitsuba3);
    EXPECT_GT(pbrt_lift, 0);
    EXPECT_LT(pbrt_lift, 1e-2);
    EXPECT_GT(mitsuba_lift, 5 * pbrt_lift);
    // The engines' rules take no offset of their own.
    EXPECT_THROW(parse_scene(R"({"camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "resolution": [2, 2]},
      "spheres": [{"centre": [0, 0, 0], "radius": 1}],
      "rays": {"secondary": {"offset": {"rule": "pbrt_v4", "absolute": 0.1}}}})",
                             "engine_rule.json"),
                 input_error);
}

}  // namespace
}  // namespace rayverify
