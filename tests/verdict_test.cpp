// Each verdict kind produced from a hand-built variant answer against a
// hand-worked exact case, and the contract check.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "compare/verdict.h"

namespace rayverify {
namespace {

// Unit sphere at the origin, ray along +z.
ray_sphere<double> along_z(double x, double y, double z) { return {{x, y, z}, {0, 0, 1}, {0, 0, 0}, 1}; }

const contract line{.query = query_kind::line_roots, .reports_tangent = true};
const contract ray_clamped{.query = query_kind::nearest_on_ray, .assumes_unit_direction = true, .clamps_to_zero = true};

verdict_kind judge(const contract& k, const ray_sphere<double>& s, int count, double t0, double t1) {
    variant_output out;
    out.roots = {count, t0, t1};
    return score_case(k, out, solve_exact(s, precision::binary64), s).verdict;
}

TEST(Verdict, AgreeOnExactRoots) {
    // o = (0,0,−5): (−5 + t)² = 1 ⇒ t = 4, 6.
    EXPECT_EQ(judge(line, along_z(0, 0, -5), 2, 4, 6), verdict_kind::agree);
}

TEST(Verdict, ClassMismatches) {
    EXPECT_EQ(judge(line, along_z(0, 0, -5), 0, 0, 0), verdict_kind::false_miss);
    EXPECT_EQ(judge(line, along_z(2, 0, -5), 2, 4, 6), verdict_kind::false_hit);
    // x = 1: the line x = 1 touches the unit sphere at t = 5 exactly.
    EXPECT_EQ(judge(line, along_z(1, 0, -5), 0, 0, 0), verdict_kind::tangent_missed);
    EXPECT_EQ(judge(line, along_z(1, 0, -5), 2, 4.999, 5.001), verdict_kind::tangent_split);
    EXPECT_EQ(judge(line, along_z(1, 0, -5), 1, 5, 5), verdict_kind::agree);
    EXPECT_EQ(judge(line, along_z(0, 0, -5), 1, 5, 5), verdict_kind::false_tangent);
}

TEST(Verdict, RootIdentityAndSide) {
    EXPECT_EQ(judge(line, along_z(0, 0, -5), 2, 5.9, 6), verdict_kind::wrong_root);
    EXPECT_EQ(judge(line, along_z(0, 0, -5), 2, 6, 4), verdict_kind::malformed_output);
    // Origin on the surface, entering: exact roots 0 and 2. A near root of
    // 1e-17 > 0 is a self-hit; −1e-17 is harmless (not in front either way).
    EXPECT_EQ(judge(line, along_z(0, 0, -1), 2, 1e-17, 2), verdict_kind::wrong_side);
    EXPECT_EQ(judge(line, along_z(0, 0, -1), 2, -1e-17, 2), verdict_kind::agree);
    EXPECT_EQ(judge(line, along_z(0, 0, -5), 2, -4, 6), verdict_kind::wrong_side);
}

TEST(Verdict, NonFiniteAndMalformed) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(judge(line, along_z(0, 0, -5), 2, 4, nan), verdict_kind::non_finite);
    EXPECT_EQ(judge(line, along_z(0, 0, -5), 3, 4, 6), verdict_kind::malformed_output);
    EXPECT_EQ(judge(ray_clamped, along_z(0, 0, -5), 2, 4, 4), verdict_kind::malformed_output);
}

TEST(Verdict, NearestOnRayWithClamp) {
    EXPECT_EQ(judge(ray_clamped, along_z(0, 0, -5), 1, 4, 4), verdict_kind::agree);
    EXPECT_EQ(judge(ray_clamped, along_z(0, 0, -5), 1, 6, 6), verdict_kind::wrong_root);
    // Inside (roots −1, 1): the contract clamps to 0.
    EXPECT_EQ(judge(ray_clamped, along_z(0, 0, 0), 1, 0, 0), verdict_kind::agree);
    // Sphere behind (roots −6, −4): no hit on the ray.
    EXPECT_EQ(judge(ray_clamped, along_z(0, 0, 5), 0, 0, 0), verdict_kind::agree);
    EXPECT_EQ(judge(ray_clamped, along_z(0, 0, 5), 1, 0, 0), verdict_kind::false_hit);
    // Leaving from the surface (roots −2, 0): the closed ray t ≥ 0 is hit at 0.
    EXPECT_EQ(judge(ray_clamped, along_z(0, 0, 1), 0, 0, 0), verdict_kind::false_miss);
}

TEST(Verdict, UlpErrorsAreMeasured) {
    const ray_sphere<double> s = along_z(0, 0, -5);
    variant_output out;
    out.roots = {2, std::nextafter(4.0, 5.0), 6};
    const case_score score = score_case(line, out, solve_exact(s, precision::binary64), s);
    ASSERT_TRUE(score.near_ulp && score.far_ulp && score.near_bits);
    EXPECT_EQ(*score.near_ulp, 1.0);  // one step above 4 is 2^−50 = ulp(4)
    EXPECT_EQ(*score.far_ulp, 0.0);
    EXPECT_EQ(*score.near_bits, 1.0);  // log2(1 + 1)
}

TEST(Verdict, HitPointErrorForAgreeingFrontRoot) {
    ray_sphere<double> s = along_z(0, 0, -5);
    variant_output out;
    out.roots = {2, 4, 6};
    out.front_root = 0;
    out.hit_point = vec3<double>{0, 0, -1};
    const case_score score = score_case(line, out, solve_exact(s, precision::binary64), s);
    ASSERT_TRUE(score.hit_point_ulp);
    EXPECT_EQ((*score.hit_point_ulp)[2], 0.0);
}

TEST(Contract, UnitDirectionTolerance) {
    const contract unit{.assumes_unit_direction = true};
    ray_sphere<double> s = along_z(0, 0, -5);
    EXPECT_FALSE(contract_breach(unit, s, precision::binary64));
    s.direction = {0, 0, 2};
    const auto breach = contract_breach(unit, s, precision::binary64);
    ASSERT_TRUE(breach);
    EXPECT_NE(breach->find("unit direction"), std::string::npos);
    // A direction normalised in double is unit within tolerance in both precisions.
    const double n = std::sqrt(1.0 + 4.0 + 9.0);
    s.direction = {1 / n, 2 / n, 3 / n};
    EXPECT_FALSE(contract_breach(unit, s, precision::binary64));
    EXPECT_FALSE(contract_breach(line, {{0, 0, 0}, {0, 0, 7}, {0, 0, 0}, 1}, precision::binary64));
}

}  // namespace
}  // namespace rayverify
