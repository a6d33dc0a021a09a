// The judge at the ends of the exponent range and where several verdicts could
// apply: the scale-error figures worked by hand at 2^±1000, the one order of
// verdicts (docs/verdicts.md) on answers that meet more than one row, and the
// side-preserving rounding robust_sphere.h documents for roots beyond the
// range of T.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "compare/judge.h"
#include "intersectors/seed004_early_out.h"

namespace rayverify {
namespace {

constexpr double inf = std::numeric_limits<double>::infinity();
constexpr double nan = std::numeric_limits<double>::quiet_NaN();

const contract line{.query = query_kind::line_roots, .reports_tangent = true};

case_score judge(const contract& k, const ray_sphere<double>& g, root_pair<double> answer,
                 precision p = precision::binary64, std::optional<double> tmin = {}, std::optional<double> tmax = {}) {
    variant_output out;
    out.roots = answer;
    return judge_output(k, out, solve_exact(g, p), range_of(k, tmin, tmax), g);
}

// ---- Scale-error figures ---------------------------------------------------------

// d = (0, 2^1000, 0) from (0, −2, 0) at the unit sphere: roots 2^−1000 and
// 3·2^−1000. t0 one ulp (2^−1052) above its root: |t − t*|·|d| = 2^−52, over
// r = 1 and over |o − c| = 2. |d|² = 2^2000 overflows a double.
TEST(ScaleError, HandWorkedWhereTheDirectionsSquareOverflows) {
    const ray_sphere<double> g{{0, -2, 0}, {0, 0x1p1000, 0}, {0, 0, 0}, 1};
    const double t0 = 0x1p-1000 + 0x1p-1052, t1 = 0x3p-1000;
    const case_score s = judge(line, g, {2, t0, t1});
    ASSERT_EQ(s.verdict, verdict_kind::agree) << s.detail;
    ASSERT_TRUE(s.scale_error_radius && s.scale_error_distance);
    EXPECT_EQ(*s.scale_error_radius, 0x1p-52);
    EXPECT_EQ(*s.scale_error_distance, 0x1p-53);
}

// The first example, by hand: an exact tangent at t* = −2^−1100
// (below the smallest subnormal, so RN(t*) = −0) with |d| = 2^1000 and
// r = 2^−100. Answered by ±0: |t − t*| = 2^−1100, times |d| over r is 1
// radius exactly; over |o − c| = 2^−100·√2 it is 1/√2. Formed in doubles,
// |t − t*| underflowed to 0.
TEST(ScaleError, HandWorkedTangentBelowTheSubnormals) {
    const ray_sphere<double> g{{0x1p-100, 0x1p-100, 0}, {0x1p1000, 0, 0}, {0, 0, 0}, 0x1p-100};
    for (const double zero : {-0.0, 0.0}) {
        const case_score s = judge(line, g, {1, zero, zero});
        ASSERT_EQ(s.verdict, verdict_kind::agree) << s.detail;
        ASSERT_TRUE(s.scale_error_radius && s.scale_error_distance);
        EXPECT_EQ(*s.scale_error_radius, 1.0);
        EXPECT_DOUBLE_EQ(*s.scale_error_distance, 1 / std::sqrt(2.0));
    }
}

// At 2^+1000: from (−2^41, 0, 0) along d = (2^30, 0, 0) at a sphere of radius
// 2^40 about 0 the roots are 1024 and 3072. A far root answered 2^1000
// stands for the far root (above the midpoint 2048): agree, with |t − t*| =
// 2^1000 − 3072, whose ULP error overflows; times |d| = 2^30 over r = 2^40
// it rounds to 2^990, over |o − c| = 2^41 to 2^989.
TEST(ScaleError, HandWorkedAtTwoToTheThousand) {
    const ray_sphere<double> g{{-0x1p41, 0, 0}, {0x1p30, 0, 0}, {0, 0, 0}, 0x1p40};
    const case_score s = judge(line, g, {2, 1024, 0x1p1000});
    ASSERT_EQ(s.verdict, verdict_kind::agree) << s.detail;
    ASSERT_TRUE(s.scale_error_radius && s.scale_error_distance);
    EXPECT_EQ(*s.scale_error_radius, 0x1p990);
    EXPECT_EQ(*s.scale_error_distance, 0x1p989);
}

// The figure is a length ratio: scaling the direction by 2^k scales the roots
// by 2^−k and leaves it unchanged. Roots 2 ∓ √0.75 (irrational), answered
// correctly rounded: the figure is RN(t*)'s own rounding error, about 1e-16,
// at every scale (the second example: inf at d = (0, 2^945, 0)).
TEST(ScaleError, InvariantUnderPowerOfTwoScaling) {
    const auto figures = [](double scale) {
        const ray_sphere<double> g{{0.5, -2, 0}, {0, scale, 0}, {0, 0, 0}, 1};
        const exact_solution exact = solve_exact(g, precision::binary64);
        const case_score s = judge(line, g, {2, exact.near_root.rounded, exact.far_root.rounded});
        EXPECT_EQ(s.verdict, verdict_kind::agree) << s.detail;
        return std::pair{s.scale_error_radius.value_or(-1), s.scale_error_distance.value_or(-1)};
    };
    const auto unit = figures(1);
    EXPECT_GT(unit.first, 1e-18);
    EXPECT_LT(unit.first, 1e-15);
    for (const double scale : {0x1p945, 0x1p1000, 0x1p-1000}) {
        const auto scaled = figures(scale);
        EXPECT_EQ(scaled.first, unit.first) << scale;
        EXPECT_EQ(scaled.second, unit.second) << scale;
    }
}

// 0 only where the answer is exact.
TEST(ScaleError, ZeroOnlyForTheExactAnswer) {
    const ray_sphere<double> g{{0, -2, 0}, {0, 0x1p1000, 0}, {0, 0, 0}, 1};
    const case_score exact = judge(line, g, {2, 0x1p-1000, 0x3p-1000});
    ASSERT_TRUE(exact.scale_error_radius);
    EXPECT_EQ(*exact.scale_error_radius, 0.0);
    // An origin on the surface (roots 0 and 2^1001 along d = (0, 2^−1000, 0)) answered −2^−1074 for the
    // root 0 (behind the origin, as the root is not in front: agree): the figure 2^−1074·2^−1000 is below
    // every double, so it shows as the smallest subnormal, not 0.
    const ray_sphere<double> surface{{0, -1, 0}, {0, 0x1p-1000, 0}, {0, 0, 0}, 1};
    const double tiny = std::numeric_limits<double>::denorm_min();
    const case_score s = judge(line, surface, {2, -tiny, 0x1p1001});
    ASSERT_EQ(s.verdict, verdict_kind::agree) << s.detail;
    ASSERT_TRUE(s.scale_error_radius && s.scale_error_distance);
    EXPECT_EQ(*s.scale_error_radius, tiny);
    EXPECT_EQ(*s.scale_error_distance, tiny);
}

// ---- One order of verdicts -------------------------------------------------------
// docs/verdicts.md: one table read top to bottom, the first row that holds is
// the verdict, the same for every query. Pairs of verdicts that can both apply:

// Unit sphere at the origin, ray along +z from (x, y, z).
ray_sphere<double> along_z(double x, double y, double z) { return {{x, y, z}, {0, 0, 1}, {0, 0, 0}, 1}; }
const ray_sphere<double> ahead = along_z(0, 0, -5);     // roots 4, 6
const ray_sphere<double> entering = along_z(0, 0, -1);  // on the surface: roots 0, 2
const ray_sphere<double> tangent = along_z(1, 0, -5);   // double root 5
const ray_sphere<double> passing = along_z(2, 0, -5);   // miss
// From the origin inside a sphere of radius 5 about (0, 0, 4): roots −1 and 9, midpoint 4.
const ray_sphere<double> off_centre{{0, 0, 0}, {0, 0, 1}, {0, 0, 4}, 5};

const contract nearest{.query = query_kind::nearest_hit};  // (0, +inf), inside: the far root
const contract nearest_closed{.query = query_kind::nearest_hit, .lower_end = end_kind::closed};
const contract clamped = intersectors::seed004_early_out_contract;  // [0, +inf), clamp
const contract any{.query = query_kind::any_hit};

verdict_kind verdict(const contract& k, const ray_sphere<double>& g, root_pair<double> answer) {
    return judge(k, g, answer).verdict;
}

// A clamping contract answered t = 1 from inside: t stands for the root −1
// (below the midpoint 4), which is behind the origin while t is in front: a
// self-hit, so wrong_side (row 10) before wrong_root (row 11) — as a
// far-root contract says of the same t. It was wrong_root.
TEST(VerdictOrder, ClampedAnswerChecksTheSideBeforeTheRoot) {
    const case_score s = judge(clamped, off_centre, {1, 1, 1});
    EXPECT_EQ(s.verdict, verdict_kind::wrong_side) << s.detail;
    EXPECT_EQ(verdict(nearest, off_centre, {1, 1, 1}), verdict_kind::wrong_side);
    // t = 5 stands for the far root 9, which is in front as t is: only the root is wrong.
    EXPECT_EQ(verdict(clamped, off_centre, {1, 5, 5}), verdict_kind::wrong_root);
    EXPECT_EQ(verdict(clamped, off_centre, {1, 0, 0}), verdict_kind::agree);
    // −2 stands for −1, both behind: the clamp, not the side, is what is wrong.
    EXPECT_EQ(verdict(clamped, off_centre, {1, -2, -2}), verdict_kind::wrong_root);
    EXPECT_EQ(verdict(clamped, off_centre, {1, inf, inf}), verdict_kind::non_finite);
    EXPECT_EQ(verdict(clamped, off_centre, {1, nan, nan}), verdict_kind::non_finite);
}

// A NaN among the judged values is non_finite (row 2) before any class row,
// under every query that judges values; count 0 judges none, and any_hit's
// contract view judges only the count.
TEST(VerdictOrder, NanAnswersUnderEachQuery) {
    // No hit expected: was false_hit under line_roots, non_finite under nearest_hit.
    EXPECT_EQ(verdict(line, passing, {2, nan, nan}), verdict_kind::non_finite);
    EXPECT_EQ(verdict(line, passing, {1, nan, nan}), verdict_kind::non_finite);
    EXPECT_EQ(verdict(nearest, passing, {1, nan, nan}), verdict_kind::non_finite);
    EXPECT_EQ(verdict(any, passing, {1, nan, nan}), verdict_kind::false_hit);
    EXPECT_EQ(verdict(line, passing, {0, nan, nan}), verdict_kind::agree);
    // A hit expected.
    EXPECT_EQ(verdict(line, ahead, {2, 4, nan}), verdict_kind::non_finite);
    EXPECT_EQ(verdict(line, ahead, {1, nan, nan}), verdict_kind::non_finite);  // not false_tangent
    EXPECT_EQ(verdict(line, tangent, {2, nan, 5}), verdict_kind::non_finite);  // not tangent_split
    EXPECT_EQ(verdict(nearest, ahead, {1, nan, nan}), verdict_kind::non_finite);
    EXPECT_EQ(verdict(any, ahead, {1, nan, nan}), verdict_kind::agree);
    EXPECT_EQ(verdict(line, ahead, {0, nan, nan}), verdict_kind::false_miss);
    // A count the query does not allow comes first of all.
    EXPECT_EQ(verdict(line, ahead, {3, nan, nan}), verdict_kind::malformed_output);
    EXPECT_EQ(verdict(nearest, passing, {2, nan, nan}), verdict_kind::malformed_output);
    // The renderer's view of any_hit judges a NaN it looked at.
    variant_output seen;
    seen.roots = {1, 0, 0};
    seen.nan_seen = true;
    for (const ray_sphere<double>& g : {ahead, passing})
        EXPECT_EQ(judge_output(any, seen, solve_exact(g, precision::binary64), range_of(any, {}, {}), g).verdict,
                  verdict_kind::non_finite);
}

// Infinities are judged after the class (row 6): an infinity where no hit is
// expected is a false hit; where one is, non_finite unless it is RN(t*).
TEST(VerdictOrder, InfinitiesAfterTheClass) {
    EXPECT_EQ(verdict(line, passing, {2, -inf, inf}), verdict_kind::false_hit);
    EXPECT_EQ(verdict(nearest, passing, {1, inf, inf}), verdict_kind::false_hit);
    EXPECT_EQ(verdict(line, ahead, {2, 4, inf}), verdict_kind::non_finite);
    EXPECT_EQ(verdict(line, ahead, {2, inf, 4}), verdict_kind::non_finite);  // before out of order
    EXPECT_EQ(verdict(line, tangent, {1, 5, inf}), verdict_kind::non_finite);  // before tangent_split
}

// The line_roots rows 7–11 in order.
TEST(VerdictOrder, LineRootsRowsInOrder) {
    EXPECT_EQ(verdict(line, ahead, {2, 6, 4}), verdict_kind::malformed_output);    // out of order, not wrong_root
    EXPECT_EQ(verdict(line, tangent, {2, 7, -1}), verdict_kind::malformed_output);  // before tangent_split
    EXPECT_EQ(verdict(line, tangent, {2, -1, 5}), verdict_kind::tangent_split);   // before wrong_side
    EXPECT_EQ(verdict(line, ahead, {1, -6, -6}), verdict_kind::false_tangent);    // before wrong_side
    EXPECT_EQ(verdict(line, ahead, {2, -4, 4.5}), verdict_kind::wrong_side);      // t0 behind: before wrong_root
    EXPECT_EQ(verdict(line, ahead, {2, 5.5, 6}), verdict_kind::wrong_root);       // t0 above the midpoint 5
}

// ±0 and ties. Roots 0 and 2 (an origin on the surface), midpoint 1.
TEST(VerdictOrder, SignedZerosAndTies) {
    // The root 0 is not in (0, +inf): the far root 2 is asked for. ±0 stand for the root 0 and are
    // outside with it: wrong_root. +denorm_min is in front while its root is not: wrong_side first.
    EXPECT_EQ(verdict(nearest, entering, {1, 0.0, 0.0}), verdict_kind::wrong_root);
    EXPECT_EQ(verdict(nearest, entering, {1, -0.0, -0.0}), verdict_kind::wrong_root);
    EXPECT_EQ(verdict(nearest, entering, {1, std::numeric_limits<double>::denorm_min(), 0}), verdict_kind::wrong_side);
    // On [0, +inf) the root 0 is the hit, and −0 is in [0, +inf) as +0 is.
    EXPECT_EQ(verdict(nearest_closed, entering, {1, 0.0, 0.0}), verdict_kind::agree);
    EXPECT_EQ(verdict(nearest_closed, entering, {1, -0.0, -0.0}), verdict_kind::agree);
    EXPECT_EQ(verdict(nearest_closed, entering, {1, -std::numeric_limits<double>::denorm_min(), 0}),
              verdict_kind::wrong_side);
    EXPECT_EQ(verdict(line, entering, {2, -0.0, 2}), verdict_kind::agree);
    // The exact midpoint stands for the root asked for (the benefit of the doubt); one step past it does not.
    EXPECT_EQ(verdict(line, ahead, {2, 5, 6}), verdict_kind::agree);
    EXPECT_EQ(verdict(nearest, ahead, {1, 5, 5}), verdict_kind::agree);
    EXPECT_EQ(verdict(nearest, ahead, {1, std::nextafter(5.0, 6.0), 0}), verdict_kind::wrong_root);
}

// ---- robust_sphere.h's side-preserving rounding ----------------------------------

// Roots 2^−1099 and 2^−1098 (from (−3·2^−100, 0, 0) along (2^1000, 0, 0) at a sphere of radius 2^−100
// about 0), both below half the smallest subnormal: RN = +0 for each. robust_sphere.h returns
// +denorm_min for each (so that they stay in front); the midpoint 1.5·2^−1099 lies below it, so the
// near root's answer was wrong_root (conditioning_limited).
TEST(SidePreservingRounding, PositiveRootsBelowTheSubnormalsAnsweredDenormMinAgree) {
    const ray_sphere<double> g{{-0x3p-100, 0, 0}, {0x1p1000, 0, 0}, {0, 0, 0}, 0x1p-100};
    const exact_solution e = solve_exact(g, precision::binary64);
    ASSERT_EQ(e.cls, line_class::two_hit);
    ASSERT_EQ(e.near_root.rounded, 0.0);
    const double tiny = std::numeric_limits<double>::denorm_min();
    EXPECT_TRUE(side_preserving_rounding(e, root_index::near_root, tiny));
    EXPECT_FALSE(side_preserving_rounding(e, root_index::near_root, -tiny));
    const case_score s = judge(line, g, {2, tiny, tiny});
    EXPECT_EQ(s.verdict, verdict_kind::agree) << s.detail;
    EXPECT_EQ(verdict(nearest, g, {1, tiny, tiny}), verdict_kind::agree);
    EXPECT_EQ(verdict(line, g, {2, 0.0, 0.0}), verdict_kind::agree);  // RN itself still agrees
    // Two steps up is no rounding of either root: it stands for the far root.
    EXPECT_EQ(verdict(nearest, g, {1, 2 * tiny, 0}), verdict_kind::wrong_root);
    // The header's own answer, through the registry, in both precisions.
    const variant robust = *find_builtin_variant("robust");
    for (const precision p : {precision::binary64, precision::binary32}) {
        corpus_case c;
        c.id = "tiny";
        c.geometry = p == precision::binary64
                         ? g
                         : ray_sphere<double>{{-0x3p-60, 0, 0}, {0x1p100, 0, 0}, {0, 0, 0}, 0x1p-60};  // 2^−159, 2^−158
        const target_outcome o = judge_target({robust, p}, c, solve_case(c, p));
        EXPECT_EQ(o.score.verdict, verdict_kind::agree) << precision_name(p) << ": " << o.score.detail;
        EXPECT_GT(o.output.roots.t0, 0) << precision_name(p);
    }
}

// Roots on either side of half the smallest float subnormal, in float: from (0, 0, 0) along (2^11, 0, 0)
// at a sphere of radius 2^−140 about (2^−139, 0, 0), t* = (2^−139 ∓ 2^−140)/2^11 = 2^−151 (RN = +0) and
// 3·2^−151 = 0.75·2^−149 (RN = denorm_min). Distinct after rounding, yet +denorm_min for both is each
// root's side-preserving rounding or its RN: two roots, not a tangent. A count of 1 still reports one root,
// and 0 for both is no rounding of the far root.
TEST(SidePreservingRounding, TwoTinyRootsBothAnsweredDenormMinAreNotATangent) {
    const double tiny = std::numeric_limits<float>::denorm_min();
    const ray_sphere<double> g{{0, 0, 0}, {0x1p11, 0, 0}, {0x1p-139, 0, 0}, 0x1p-140};
    const exact_solution e = solve_exact(g, precision::binary32);
    ASSERT_EQ(e.cls, line_class::two_hit);
    ASSERT_EQ(e.near_root.rounded, 0.0);
    ASSERT_EQ(e.far_root.rounded, tiny);
    const auto verdict_f = [&](root_pair<double> r) { return judge(line, g, r, precision::binary32).verdict; };
    EXPECT_EQ(verdict_f({2, tiny, tiny}), verdict_kind::agree);
    EXPECT_EQ(verdict_f({2, 0.0, tiny}), verdict_kind::agree);
    EXPECT_EQ(verdict_f({1, tiny, tiny}), verdict_kind::false_tangent);
    EXPECT_EQ(verdict_f({2, 0.0, 0.0}), verdict_kind::false_tangent);
    // The header's own answer, through the registry.
    corpus_case c;
    c.id = "tiny_pair";
    c.geometry = g;
    const target_outcome o = judge_target({*find_builtin_variant("robust"), precision::binary32}, c, e);
    EXPECT_EQ(o.score.verdict, verdict_kind::agree) << o.score.detail;
    EXPECT_EQ(o.output.roots.t0, tiny);
}

// Overflow, symmetrically: roots 2^1050 and 2^1051 round to +inf; +inf agrees, and so does the largest
// double (one step inside the range, which robust_sphere.h's nearest_hit on an open interval returns).
TEST(SidePreservingRounding, RootsBeyondTheRangeAnsweredInfOrTheLargestValueAgree) {
    const ray_sphere<double> g{{-0x3p950, 0, 0}, {0x1p-100, 0, 0}, {0, 0, 0}, 0x1p950};
    const exact_solution e = solve_exact(g, precision::binary64);
    ASSERT_EQ(e.near_root.rounded, inf);
    const double big = std::numeric_limits<double>::max();
    EXPECT_EQ(verdict(line, g, {2, inf, inf}), verdict_kind::agree);
    EXPECT_EQ(verdict(line, g, {2, big, big}), verdict_kind::agree);  // t1 stood for the near root
    EXPECT_EQ(verdict(line, g, {2, big, inf}), verdict_kind::agree);
    EXPECT_EQ(verdict(nearest, g, {1, big, big}), verdict_kind::agree);
    EXPECT_EQ(verdict(line, g, {2, -big, big}), verdict_kind::wrong_side);
    const case_score far_answer = judge(line, g, {2, std::nextafter(big, 0.0), big});
    EXPECT_EQ(far_answer.verdict, verdict_kind::agree) << far_answer.detail;
    // In float: roots 2^140 and 2^141 round to +inf; FLT_MAX is the float one step inside, DBL_MAX is not a float.
    const ray_sphere<double> f{{-0x3p40, 0, 0}, {0x1p-100, 0, 0}, {0, 0, 0}, 0x1p40};
    const double flt_max = std::numeric_limits<float>::max();
    EXPECT_EQ(judge(line, f, {2, flt_max, flt_max}, precision::binary32).verdict, verdict_kind::agree);
    EXPECT_EQ(judge(line, f, {2, flt_max, inf}, precision::binary32).verdict, verdict_kind::agree);
    EXPECT_EQ(judge(line, f, {2, -flt_max, flt_max}, precision::binary32).verdict, verdict_kind::wrong_side);
}

}  // namespace
}  // namespace rayverify
