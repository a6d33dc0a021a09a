// Condition numbers and the conditioning-limited criterion, against
// hand-worked cases and against finite differences of the closed-form root.
#include "compare/stability.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "corpus/generators.h"

namespace rayverify {
namespace {

constexpr double inf = std::numeric_limits<double>::infinity();

ray_sphere<double> make(vec3<double> o, vec3<double> d, vec3<double> c, double r) { return {o, d, c, r}; }

stability_measures measure(const ray_sphere<double>& g, precision p = precision::binary64) {
    return measure_stability(g, p, solve_exact(g, p));
}

// The judge's cause for a line-roots answer made up on the case (the inputs
// exactly representable in p).
std::optional<disagreement_cause> cause_of(const ray_sphere<double>& g, root_pair<double> answer,
                                           precision p = precision::binary64) {
    const contract line{.query = query_kind::line_roots, .reports_tangent = true};
    variant_output out;
    out.roots = answer;
    return judge_output(line, out, solve_exact(g, p), range_of(line, std::nullopt, std::nullopt), g).cause;
}

// o = 0, d = x̂, c = (5, 0, 0), r = 3: roots 2 and 8, Δ′ = 9. Along the axis
// t = (c_x − o_x ∓ r)/d_x, so for t = 2: |∂t/∂c_x|·5 + |∂t/∂r|·3 + |∂t/∂d_x|·1
// = 5 + 3 + 2 = 10 and κ = 10/2 = 5; for t = 8: (5 + 3 + 8)/8 = 2.
// M: Δ′ = d_x²·r², so M = |2d_x r²|·1 + |2d_x² r|·3 = 18 + 18 = 36.
TEST(Stability, HandWorkedAxisCase) {
    const stability_measures m = measure(make({0, 0, 0}, {1, 0, 0}, {5, 0, 0}, 3));
    ASSERT_TRUE(m.valid);
    EXPECT_EQ(m.cls, line_class::two_hit);
    ASSERT_TRUE(m.near_condition && m.far_condition);
    EXPECT_NEAR(*m.near_condition, 5.0, 1e-14);
    EXPECT_NEAR(*m.far_condition, 2.0, 1e-14);
    EXPECT_DOUBLE_EQ(m.near_root, 2.0);
    EXPECT_NEAR(m.tangency_distance, 9.0 / 41.0, 1e-15);  // 9 / (25 + 16)
    EXPECT_NEAR(m.tangency_margin, 9.0 / (std::ldexp(1.0, -53) * 36.0), 1.0);
    EXPECT_NEAR(m.distance_ratio, 5.0 / 3.0, 1e-15);
    // Scaling every position by 2^40 and the direction by 2^-7 changes nothing.
    const stability_measures scaled =
        measure(make({0, 0, 0}, {0x1p-7, 0, 0}, {0x1p40 * 5, 0, 0}, 0x1p40 * 3));
    EXPECT_NEAR(*scaled.near_condition, 5.0, 1e-14);
    EXPECT_DOUBLE_EQ(scaled.near_root, 0x1p47 * 2);
}

// The origin on the sphere: the near root is exactly 0 (κ = ∞); the far root
// t = c_x − o_x + r = 6 has κ = (5 + 2 + 3 + 6)/6 = 8/3.
TEST(Stability, ZeroRootHasInfiniteCondition) {
    const stability_measures m = measure(make({2, 0, 0}, {1, 0, 0}, {5, 0, 0}, 3));
    ASSERT_TRUE(m.near_condition && m.far_condition);
    EXPECT_EQ(*m.near_condition, inf);
    EXPECT_NEAR(*m.far_condition, 8.0 / 3.0, 1e-14);
    EXPECT_EQ(condition_bucket(m), condition_decades);
}

// The same case's absolute conditions κ·|t|, finite at the zero root: for
// t = 0, p = f = (−3, 0, 0): (|p_x|·(|o_x| + |c_x|) + r²)/√Δ′ = (3·7 + 9)/3 = 10;
// for t = 6, p = (3, 0, 0): (3·(2 + 5 + 6) + 9)/3 = 16 = κ·t.
TEST(Stability, ZeroRootHasAFiniteAbsoluteCondition) {
    const stability_measures m = measure(make({2, 0, 0}, {1, 0, 0}, {5, 0, 0}, 3));
    ASSERT_TRUE(m.near_absolute_condition && m.far_absolute_condition);
    EXPECT_NEAR(*m.near_absolute_condition, 10.0, 1e-13);
    EXPECT_NEAR(*m.far_absolute_condition, 16.0, 1e-13);
    // Scaling positions by 2^30 scales t, and κ·|t| with it.
    const stability_measures scaled = measure(make({0x1p30 * 2, 0, 0}, {1, 0, 0}, {0x1p30 * 5, 0, 0}, 0x1p30 * 3));
    EXPECT_NEAR(*scaled.far_absolute_condition, 0x1p30 * 16.0, 1e-3);
}

// An agreeing answer at a root exactly at 0 is held to the line in absolute
// terms: |t| / (u·κ·|t|), here 10·u·0.5 / (u·10) = 0.5, though its ulps are of 0.
TEST(Stability, AZeroRootsAnswerIsJudgedAgainstTheLineInAbsoluteTerms) {
    const ray_sphere<double> g = make({2, 0, 0}, {1, 0, 0}, {5, 0, 0}, 3);
    const exact_solution exact = solve_exact(g, precision::binary64);
    case_score score;
    score.zero_root_error = 5 * std::ldexp(1.0, -53);
    score.near_ulp = score.zero_root_error.value() / std::numeric_limits<double>::denorm_min();
    const std::optional<double> excess = excess_over_line(score, measure(g), exact, precision::binary64);
    ASSERT_TRUE(excess);
    EXPECT_NEAR(*excess, 0.5, 1e-12);
    // Far above: a self-hit t = 1e-6 is 10^9 times the line.
    score.zero_root_error = 1e-6;
    EXPECT_GT(*excess_over_line(score, measure(g), exact, precision::binary64), 1e8);
}

// near_root_scaled_ulp counts a zero root's error in ulps of r/|d| = 3
// (binade 1: ulp 2^-51), where near_root_ulp counts ulps of 0 (2^-1074).
TEST(Stability, AZeroRootsErrorIsCountedInUlpsOfTheRadiusAlongTheRay) {
    const contract closed{.query = query_kind::nearest_hit, .lower_end = end_kind::closed};
    const ray_sphere<double> g = make({2, 0, 0}, {1, 0, 0}, {5, 0, 0}, 3);
    variant_output out;
    out.roots = {1, 0x1p-50, 0};
    const case_score s = judge_output(closed, out, solve_exact(g, precision::binary64),
                                      range_of(closed, std::nullopt, std::nullopt), g);
    EXPECT_EQ(s.verdict, verdict_kind::agree);
    ASSERT_TRUE(s.near_scaled_ulp && s.near_ulp);
    EXPECT_EQ(*s.near_scaled_ulp, 2.0);
    EXPECT_EQ(*s.near_ulp, inf);  // 2^-50 / 2^-1074 overflows
    // In float the ulp of 3 is 2^-22; a direction of length 2 halves r/|d| to 1.5 (binade 0: 2^-23).
    const ray_sphere<double> slow = make({2, 0, 0}, {2, 0, 0}, {5, 0, 0}, 3);
    out.roots = {1, 0x1p-20f, 0};
    const case_score f = judge_output(closed, out, solve_exact(slow, precision::binary32),
                                      range_of(closed, std::nullopt, std::nullopt), slow);
    ASSERT_TRUE(f.near_scaled_ulp);
    EXPECT_EQ(*f.near_scaled_ulp, 8.0);
}

// A self-hit (a ray from a point exactly on the sphere answered by a tiny
// positive t standing for the root at 0) gets one cause whichever root is 0:
// entering (roots 0 and 6: wrong_side) and leaving (roots −6 and 0: a false
// hit) are both within the backward error of the range's end at 0.
TEST(Stability, ASelfHitHasOneCauseWhicheverRootIsZero) {
    const contract nearest{.query = query_kind::nearest_hit};
    const auto judged = [&](const ray_sphere<double>& g) {
        variant_output out;
        out.roots = {1, 1e-17, 0};
        return judge_output(nearest, out, solve_exact(g, precision::binary64), range_of(nearest, std::nullopt, std::nullopt), g);
    };
    const case_score entering = judged(make({2, 0, 0}, {1, 0, 0}, {5, 0, 0}, 3));
    const case_score leaving = judged(make({8, 0, 0}, {1, 0, 0}, {5, 0, 0}, 3));
    EXPECT_EQ(entering.verdict, verdict_kind::wrong_side);
    EXPECT_EQ(leaving.verdict, verdict_kind::false_hit);
    EXPECT_EQ(entering.cause, disagreement_cause::conditioning_limited);
    EXPECT_EQ(leaving.cause, disagreement_cause::conditioning_limited);
    // Where no root is near an end (roots 2 and 8), the far root answered for
    // the near one is algorithmic: a stable formula tells them apart.
    variant_output far_root;
    far_root.roots = {1, 8, 0};
    const ray_sphere<double> g = make({0, 0, 0}, {1, 0, 0}, {5, 0, 0}, 3);
    const case_score wrong = judge_output(nearest, far_root, solve_exact(g, precision::binary64),
                                          range_of(nearest, std::nullopt, std::nullopt), g);
    EXPECT_EQ(wrong.verdict, verdict_kind::wrong_root);
    EXPECT_EQ(wrong.cause, disagreement_cause::algorithmic);
}

// An exact tangent (Δ′ = 0) is a double root: κ = ∞, distance to tangency 0,
// and any wrong class is conditioning-limited.
TEST(Stability, TangentIsInfinitelyIllConditioned) {
    const stability_measures m = measure(make({0, 3, 0}, {1, 0, 0}, {5, 0, 0}, 3));
    EXPECT_EQ(m.cls, line_class::tangent);
    EXPECT_EQ(*m.near_condition, inf);
    EXPECT_EQ(m.tangency_distance, 0);
    EXPECT_EQ(m.tangency_margin, 0);
    const ray_sphere<double> g = make({0, 3, 0}, {1, 0, 0}, {5, 0, 0}, 3);
    EXPECT_EQ(cause_of(g, {2, 4.999, 5.001}), disagreement_cause::conditioning_limited);  // tangent_split
    const double nan = std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(cause_of(g, {2, nan, nan}), disagreement_cause::algorithmic);  // non_finite
    EXPECT_EQ(cause_of(g, {1, 5, 5}), std::nullopt);                       // agree
}

// Issue item 8: at distance/radius 10^15 the cancelling b′² − aC in
// double-double is off by several percent; the Lagrange form a·r² − |d × f|²
// the oracle uses is not. f = (10^15, 1/2, 0), d = −x̂, r = 1: Δ′ = 1 − 1/4
// exactly, b′² = 10^30 and aC = 10^30 − 3/4, so ρ = 0.75 / (2·10^30 − 0.75).
TEST(Stability, FarSphereDiscriminantDoesNotCancel) {
    const stability_measures m = measure(make({1e15, 0.5, 0}, {-1, 0, 0}, {0, 0, 0}, 1));
    EXPECT_EQ(m.cls, line_class::two_hit);
    EXPECT_NEAR(m.tangency_distance * 2e30, 0.75, 1e-9);
    // κ of the near root t = 10^15 − √0.75: (|p|·(|o| + |t||d|) + r²)/(√Δ′·t) with
    // p = f + t·d = (√0.75, 1/2, 0): (√0.75·2·10^15 + 1)/(√0.75·10^15) ≈ 2.
    ASSERT_TRUE(m.near_condition);
    EXPECT_NEAR(*m.near_condition, 2.0, 1e-9);
}

TEST(Stability, MissHasNoConditionNumber) {
    const stability_measures m = measure(make({0, 4, 0}, {1, 0, 0}, {5, 0, 0}, 3));
    EXPECT_EQ(m.cls, line_class::miss);
    EXPECT_FALSE(m.near_condition);
    EXPECT_EQ(condition_bucket(m), condition_decades + 1);
    // Δ′ = −7 against b′² + |aC| = 25 + 32.
    EXPECT_NEAR(m.tangency_distance, 7.0 / 57.0, 1e-15);
}

// A unit sphere at distance D, the ray through its centre: Δ′ = r², and
// M ≈ 4r² + 2·2rD·0 ... the class is safe; but a graze at one double ulp from
// tangency is conditioning-limited in double and far more so in float.
TEST(Stability, FarSphereIsWellConditionedForTheClass) {
    const stability_measures through = measure(make({-4096, 0, 0}, {1, 0, 0}, {0, 0, 0}, 1), precision::binary32);
    EXPECT_GT(through.tangency_margin, 1e5);  // naive float's false miss here is algorithmic
    EXPECT_EQ(cause_of(make({-4096, 0, 0}, {1, 0, 0}, {0, 0, 0}, 1), {0, 0, 0}, precision::binary32),
              disagreement_cause::algorithmic);
    const stability_measures graze = measure(make({-4096, std::nextafter(1.0, 2.0), 0}, {1, 0, 0}, {0, 0, 0}, 1));
    EXPECT_EQ(graze.cls, line_class::miss);
    EXPECT_LE(graze.tangency_margin, conditioning_gamma);
    EXPECT_EQ(cause_of(make({-4096, std::nextafter(1.0, 2.0), 0}, {1, 0, 0}, {0, 0, 0}, 1), {2, 4096, 4096}),
              disagreement_cause::conditioning_limited);
}

// The closed-form root (stable formula in long double) differentiated by
// central differences, on random cases with a seed per iteration.
long double near_root_of(const long double x[10]) {
    long double f[3], a = 0, b = 0, C = -x[9] * x[9];
    for (int k = 0; k < 3; ++k) {
        f[k] = x[k] - x[6 + k];
        a += x[3 + k] * x[3 + k];
        b += x[3 + k] * f[k];
        C += f[k] * f[k];
    }
    const long double disc = b * b - a * C;
    const long double q = b >= 0 ? -(b + std::sqrt(disc)) : std::sqrt(disc) - b;
    return std::min(q / a, C / q);
}

TEST(Stability, ConditionMatchesFiniteDifferences) {
    int checked = 0;
    for (std::uint64_t seed = 1; seed <= 200; ++seed) {
        std::mt19937_64 rng(seed);
        std::uniform_real_distribution<double> u(-4, 4);
        const ray_sphere<double> g = make({u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)},
                                          {u(rng), u(rng), u(rng)}, 1 + std::fabs(u(rng)));
        const stability_measures m = measure(g);
        if (m.cls != line_class::two_hit || *m.near_condition > 1e4) continue;
        long double x[10] = {g.origin.x, g.origin.y, g.origin.z,       g.direction.x, g.direction.y,
                             g.direction.z, g.centre.x, g.centre.y, g.centre.z,    g.radius};
        const long double t = near_root_of(x);
        long double sum = 0;
        for (int i = 0; i < 10; ++i) {
            const long double h = 1e-7L * std::max(1.0L, std::fabs(x[i]));
            long double up[10], down[10];
            std::copy(x, x + 10, up);
            std::copy(x, x + 10, down);
            up[i] += h;
            down[i] -= h;
            sum += std::fabs((near_root_of(up) - near_root_of(down)) / (2 * h)) * std::fabs(x[i]);
        }
        ++checked;
        const double finite_difference = static_cast<double>(sum / std::fabs(t));
        EXPECT_NEAR(*m.near_condition / finite_difference, 1.0, 1e-5) << "seed " << seed;
        EXPECT_NEAR(m.near_root, static_cast<double>(t), 1e-12 * std::fabs(static_cast<double>(t)) + 1e-15)
            << "seed " << seed;
    }
    EXPECT_GT(checked, 40);
}

// The double-double root agrees with the oracle's correctly rounded root on
// the stiff families (a check of the dd evaluation, not of the oracle).
TEST(Stability, RootMatchesOracleOnGeneratedFamilies) {
    int checked = 0;
    for (const char* family : {"uniform", "far_sphere", "near_tangent", "inside"}) {
        for (const corpus_case& c : generate_family(family, 60, 7)) {
            const exact_solution exact = solve_exact(c.geometry, precision::binary64);
            const stability_measures m = measure_stability(c.geometry, precision::binary64, exact);
            if (exact.cls == line_class::miss) continue;
            ++checked;
            EXPECT_LE(std::fabs(m.near_root - exact.near_root.rounded),
                      std::ldexp(std::fabs(exact.near_root.rounded), -50))
                << c.id;
        }
    }
    EXPECT_GT(checked, 100);
}

TEST(Stability, BucketLabels) {
    EXPECT_EQ(condition_bucket_label(0), "<1e1");
    EXPECT_EQ(condition_bucket_label(3), "1e3..1e4");
    EXPECT_EQ(condition_bucket_label(condition_decades), "inf");
    EXPECT_EQ(condition_bucket_label(condition_decades + 1), "miss");
    stability_measures m;
    m.valid = true;
    m.near_condition = 999.0;
    EXPECT_EQ(condition_bucket(m), 2);
    m.near_condition = 1000.0;
    EXPECT_EQ(condition_bucket(m), 3);
    m.near_condition = 0.5;
    EXPECT_EQ(condition_bucket(m), 0);
}

}  // namespace
}  // namespace rayverify
