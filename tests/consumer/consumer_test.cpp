// A user's test suite against an installed rayverify: their own intersector,
// called directly against the oracle, and gated with the GoogleTest helper.
#include <rayverify/testing/gtest_gate.h>

#include <cmath>
#include <utility>

#include <rayverify/compare/judge.h>
#include <rayverify/oracle/oracle.h>

namespace {

using rayverify::ray_sphere;
using rayverify::root_pair;

// The user's intersector: the Ray Tracing Gems final form, in their own code.
template <class T>
root_pair<T> user_sphere(const ray_sphere<T>& s) {
    const auto f = s.origin - s.centre;
    const T a = dot(s.direction, s.direction);
    const T b = -dot(f, s.direction);
    const T C = dot(f, f) - s.radius * s.radius;
    const auto l = f + (b / a) * s.direction;
    const T disc = s.radius * s.radius - dot(l, l);
    if (disc < 0) return {};
    const T q = b + std::copysign(std::sqrt(a * disc), b);
    T t0 = C / q, t1 = q / a;
    if (t0 > t1) std::swap(t0, t1);
    return {disc == 0 ? 1 : 2, t0, t1};
}

// The same after a "simplification": the textbook discriminant b² − aC.
template <class T>
root_pair<T> user_sphere_naive_discriminant(const ray_sphere<T>& s) {
    const auto f = s.origin - s.centre;
    const T a = dot(s.direction, s.direction);
    const T b = -dot(f, s.direction);
    const T C = dot(f, f) - s.radius * s.radius;
    const T disc = (b * b - a * C) / a;
    if (disc < 0) return {};
    const T q = b + std::copysign(std::sqrt(a * disc), b);
    T t0 = C / q, t1 = q / a;
    if (t0 > t1) std::swap(t0, t1);
    return {disc == 0 ? 1 : 2, t0, t1};
}

rayverify::variant as_variant(root_pair<float> (*f)(const ray_sphere<float>&),
                              root_pair<double> (*d)(const ray_sphere<double>&)) {
    // As docs/gate.md writes it; the baseline's entries are named by `name`.
    return rayverify::variant{.name = "user_sphere",
                              .citation = "our renderer, sphere.h",
                              .formula = "RTG ch.7 final form",
                              .promises = {.reports_tangent = true, .tangent_rule = "disc == 0"},
                              .run_float = f,
                              .run_double = d};
}

const std::vector<std::filesystem::path> corpus = {CONSUMER_CORPUS_DIR "/uniform.txt",
                                                   CONSUMER_CORPUS_DIR "/far_sphere.txt"};

TEST(Consumer, CallsTheOracleAndTheJudgeDirectly) {
    // Unit sphere at the origin, ray along +z from z = −5: exact roots 4 and 6.
    const ray_sphere<double> input{{0, 0, -5}, {0, 0, 1}, {0, 0, 0}, 1};
    const rayverify::exact_solution exact = rayverify::solve_exact(input, rayverify::precision::binary64);
    ASSERT_EQ(exact.cls, rayverify::line_class::two_hit);
    const rayverify::variant v = as_variant(&user_sphere<float>, &user_sphere<double>);
    rayverify::corpus_case c;
    c.id = "consumer";
    c.geometry = input;
    const auto score = rayverify::judge_target({v, rayverify::precision::binary64}, c, exact).score;
    EXPECT_EQ(score.verdict, rayverify::verdict_kind::agree) << score.detail;
    EXPECT_EQ(*score.near_ulp, 0);
}

TEST(Consumer, UserIntersectorHasNoRegressions) {
    EXPECT_NO_NUMERIC_REGRESSIONS(as_variant(&user_sphere<float>, &user_sphere<double>), CONSUMER_BASELINE, corpus);
}

TEST(Consumer, NaiveDiscriminantIsCaughtWithPasteableCases) {
    const auto worse = as_variant(&user_sphere_naive_discriminant<float>, &user_sphere_naive_discriminant<double>);
    const testing::AssertionResult result =
        rayverify::gate_testing::has_no_numeric_regressions(worse, corpus, CONSUMER_BASELINE);
    ASSERT_FALSE(result);
    const std::string message = result.message();
    EXPECT_NE(message.find("WORSE  user_sphere/double far_sphere: false_miss 0 → "), std::string::npos) << message;
    EXPECT_NE(message.find("# first cases, as corpus lines:\n    far_sphere-1-"), std::string::npos) << message;
}

}  // namespace
