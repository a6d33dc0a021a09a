// The specialised intersectors (any-hit, nearest-in-interval, unit
// direction) on hand-worked cases, and the query-level judge (compare/query.h)
// on every query and outcome, with answers made up to be exactly right or
// wrong in a known way.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "compare/audit.h"
#include "compare/query.h"
#include "intersectors/hearn_baker.h"
#include "intersectors/hearn_baker_any_hit.h"
#include "intersectors/hearn_baker_nearest.h"
#include "intersectors/hearn_baker_unit.h"
#include "intersectors/registry.h"
#include "oracle/oracle.h"

namespace rayverify {
namespace {

constexpr double inf = std::numeric_limits<double>::infinity();

// Unit sphere at the origin; the ray along +z from z = −5 meets it at t = 4 and 6.
const ray_sphere<double> ahead{{0, 0, -5}, {0, 0, 1}, {0, 0, 0}, 1};
// Origin inside: roots −1 and 1.
const ray_sphere<double> inside{{0, 0, 0}, {0, 0, 1}, {0, 0, 0}, 1};
// Sphere behind: roots −6 and −4.
const ray_sphere<double> behind{{0, 0, 5}, {0, 0, 1}, {0, 0, 0}, 1};
// Direction of length 2: roots 2 and 3.
const ray_sphere<double> long_direction{{0, 0, -5}, {0, 0, 2}, {0, 0, 0}, 1};
// Passes at distance 2: a miss.
const ray_sphere<double> passing{{0, 2, -5}, {0, 0, 1}, {0, 0, 0}, 1};

template <class T>
bool any_hit(const ray_sphere<double>& g, double tmin, double tmax) {
    return intersectors::hearn_baker_any_hit(rounded_to<T>(g), static_cast<T>(tmin), static_cast<T>(tmax)).count == 1;
}

template <class T>
std::optional<double> nearest(const ray_sphere<double>& g, double tmin, double tmax) {
    const root_pair<T> r =
        intersectors::hearn_baker_nearest(rounded_to<T>(g), static_cast<T>(tmin), static_cast<T>(tmax));
    if (r.count == 0) return std::nullopt;
    return static_cast<double>(r.t0);
}

template <class T>
class Specialised : public testing::Test {};
using precisions = testing::Types<float, double>;
TYPED_TEST_SUITE(Specialised, precisions);

TYPED_TEST(Specialised, AnyHitDecidesTheOpenInterval) {
    using T = TypeParam;
    EXPECT_TRUE(any_hit<T>(ahead, 0, inf));
    EXPECT_FALSE(any_hit<T>(ahead, 0, 3));    // both roots beyond tmax
    EXPECT_FALSE(any_hit<T>(ahead, 4.5, 5));  // between the roots
    EXPECT_TRUE(any_hit<T>(ahead, 5, 7));     // the far root only
    EXPECT_FALSE(any_hit<T>(ahead, 4, 6));    // roots exactly on the open bounds
    EXPECT_TRUE(any_hit<T>(ahead, 3.5, 4.5));
    EXPECT_TRUE(any_hit<T>(inside, 0, inf));  // decided from the sign of C
    EXPECT_FALSE(any_hit<T>(inside, 0, 0.5));
    EXPECT_TRUE(any_hit<T>(inside, -2, 0));   // the root behind, in a backward interval
    EXPECT_FALSE(any_hit<T>(behind, 0, inf));  // decided from the signs of C and b′
    EXPECT_TRUE(any_hit<T>(behind, -5, inf));
    EXPECT_TRUE(any_hit<T>(long_direction, 0, inf));
    EXPECT_FALSE(any_hit<T>(long_direction, 0, 1.5));
    EXPECT_TRUE(any_hit<T>(long_direction, 2.5, 3.5));
    EXPECT_FALSE(any_hit<T>(passing, 0, inf));
    EXPECT_FALSE(any_hit<T>(passing, -inf, inf));
}

TYPED_TEST(Specialised, NearestReturnsTheFirstRootInTheInterval) {
    using T = TypeParam;
    EXPECT_EQ(nearest<T>(ahead, 0, inf), 4.0);
    EXPECT_EQ(nearest<T>(ahead, 4, inf), 6.0);  // open: the root at tmin is excluded
    EXPECT_EQ(nearest<T>(ahead, 0, 4), std::nullopt);
    EXPECT_EQ(nearest<T>(ahead, 4.5, 5), std::nullopt);
    EXPECT_EQ(nearest<T>(inside, 0, inf), 1.0);
    EXPECT_EQ(nearest<T>(inside, -inf, inf), -1.0);
    EXPECT_EQ(nearest<T>(behind, 0, inf), std::nullopt);
    EXPECT_EQ(nearest<T>(behind, -5, inf), -4.0);
    EXPECT_EQ(nearest<T>(long_direction, 0, inf), 2.0);
    EXPECT_EQ(nearest<T>(long_direction, 2, inf), 3.0);
    EXPECT_EQ(nearest<T>(passing, -inf, inf), std::nullopt);
}

TYPED_TEST(Specialised, UnitDirectionFormsMatchTheGeneralForm) {
    using T = TypeParam;
    for (const auto& g : {ahead, inside, behind, passing}) {
        const ray_sphere<T> s = rounded_to<T>(g);
        const root_pair<T> general = intersectors::hearn_baker(s), unit = intersectors::hearn_baker_unit(s);
        EXPECT_EQ(unit.count, general.count);
        if (general.count) {
            EXPECT_EQ(unit.t0, general.t0);
            EXPECT_EQ(unit.t1, general.t1);
        }
        const root_pair<T> n = intersectors::hearn_baker_unit_nearest(s);
        const root_pair<T> m = intersectors::hearn_baker_nearest(s);
        EXPECT_EQ(n.count, m.count);
        if (m.count) {
            EXPECT_EQ(n.t0, m.t0);
        }
    }
}

// On random unit-direction cases the specialisations answer exactly what
// hearn_baker's roots, filtered into the interval, answer (same formulas; the
// sign early-outs must never contradict them away from ties).
TYPED_TEST(Specialised, AgreeWithFilteredHearnBakerOnRandomCases) {
    using T = TypeParam;
    const unsigned seed = 20261122;
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> coordinate(-10, 10), radius(0.1, 5), bound(-20, 20);
    std::normal_distribution<double> normal;
    int disagreements = 0;
    for (int i = 0; i < 20000; ++i) {
        vec3<double> d{normal(rng), normal(rng), normal(rng)};
        const double length = std::sqrt(dot(d, d));
        d = (1 / length) * d;
        const ray_sphere<T> s = rounded_to<T>(ray_sphere<double>{
            {coordinate(rng), coordinate(rng), coordinate(rng)}, d, {coordinate(rng), coordinate(rng), coordinate(rng)},
            radius(rng)});
        double lo = bound(rng), hi = bound(rng);
        if (lo > hi) std::swap(lo, hi);
        if (i % 3 == 0) lo = 0, hi = inf;
        const ray_interval<T> interval{static_cast<T>(lo), static_cast<T>(hi)};
        const root_pair<T> line = intersectors::hearn_baker(s);
        std::optional<T> filtered;
        if (line.count && interval.contains(line.t0))
            filtered = line.t0;
        else if (line.count && interval.contains(line.t1))
            filtered = line.t1;
        const root_pair<T> hit = intersectors::hearn_baker_any_hit(s, interval.tmin, interval.tmax);
        const root_pair<T> near = intersectors::hearn_baker_nearest(s, interval.tmin, interval.tmax);
        const root_pair<T> unit_near = intersectors::hearn_baker_unit_nearest(s, interval.tmin, interval.tmax);
        const root_pair<T> unit_hit = intersectors::hearn_baker_unit_any_hit(s, interval.tmin, interval.tmax);
        const bool same = (hit.count == 1) == filtered.has_value() && (near.count == 1) == filtered.has_value() &&
                          (!filtered || near.t0 == *filtered) && (unit_near.count == 1) == filtered.has_value() &&
                          (unit_hit.count == 1) == filtered.has_value();
        if (!same && ++disagreements <= 5) ADD_FAILURE() << "seed " << seed << " case " << i;
    }
    EXPECT_EQ(disagreements, 0) << "seed " << seed;
}

// --- the query judge ---

exact_solution solve(const ray_sphere<double>& g) { return solve_exact(g, precision::binary64); }

corpus_case case_of(const ray_sphere<double>& g, std::optional<double> tmin = {}, std::optional<double> tmax = {}) {
    corpus_case c;
    c.id = "hand";
    c.geometry = g;
    c.tmin = tmin;
    c.tmax = tmax;
    return c;
}

// A made-up variant of kind k answering `answer` (double only).
variant fixed(query_kind k, root_pair<double> answer, bool unit = false) {
    variant v;
    v.name = "fixed";
    v.promises.query = k;
    v.promises.assumes_unit_direction = unit;
    v.run_double = [answer](const ray_sphere<double>&) { return answer; };
    if (takes_interval(k)) v.run_double_in = [answer](const ray_sphere<double>&, double, double) { return answer; };
    return v;
}

const variant& builtin(const char* name) { return *find_builtin_variant(name); }

query_verdict judge(const variant& v, const ray_sphere<double>& g, ray_query q, std::optional<double> tmin = {},
                    std::optional<double> tmax = {}) {
    return judge_query(v, precision::binary64, case_of(g, tmin, tmax), q, solve(g));
}

TEST(QueryJudge, AnyHitCorrectFalseHitFalseMiss) {
    const variant hit = fixed(query_kind::any_hit_in_interval, {1, 0, 0});
    const variant miss = fixed(query_kind::any_hit_in_interval, {});
    EXPECT_EQ(judge(hit, ahead, ray_query::any_hit).outcome, query_outcome::correct);
    EXPECT_EQ(judge(miss, ahead, ray_query::any_hit).outcome, query_outcome::false_miss);
    EXPECT_EQ(judge(hit, ahead, ray_query::any_hit, 0.0, 3.0).outcome, query_outcome::false_hit);
    EXPECT_EQ(judge(miss, ahead, ray_query::any_hit, 0.0, 3.0).outcome, query_outcome::correct);
    // Roots exactly on the open bounds are outside.
    EXPECT_EQ(judge(hit, ahead, ray_query::any_hit, 4.0, 6.0).outcome, query_outcome::false_hit);
    EXPECT_EQ(judge(hit, behind, ray_query::any_hit).outcome, query_outcome::false_hit);
    const query_verdict v = judge(miss, inside, ray_query::any_hit);
    EXPECT_EQ(v.outcome, query_outcome::false_miss);
    EXPECT_TRUE(v.exact_hit);
    EXPECT_FALSE(v.variant_hit);
    EXPECT_NE(v.detail.find("variant: no root"), std::string::npos) << v.detail;
    EXPECT_EQ(judge(fixed(query_kind::any_hit_in_interval, {2, 0, 0}), ahead, ray_query::any_hit).outcome,
              query_outcome::malformed_output);
}

TEST(QueryJudge, NearestHitRootAndUlpError) {
    // 4 + 2 ulp(4): an error of exactly 2 ulp.
    const double four_plus_two = std::nextafter(std::nextafter(4.0, 5.0), 5.0);
    const query_verdict close = judge(fixed(query_kind::nearest_in_interval, {1, four_plus_two, four_plus_two}), ahead,
                                      ray_query::nearest_hit);
    EXPECT_EQ(close.outcome, query_outcome::correct);
    EXPECT_EQ(close.nearest_ulp, 2.0);
    EXPECT_EQ(judge(fixed(query_kind::nearest_in_interval, {1, 6, 6}), ahead, ray_query::nearest_hit).outcome,
              query_outcome::wrong_root);
    // In (5, +inf) the wanted root is the far one.
    const query_verdict far = judge(fixed(query_kind::nearest_in_interval, {1, 6, 6}), ahead, ray_query::nearest_hit, 5.0);
    EXPECT_EQ(far.outcome, query_outcome::correct);
    EXPECT_EQ(far.nearest_ulp, 0.0);
    EXPECT_EQ(judge(fixed(query_kind::nearest_in_interval, {1, 7, 7}), ahead, ray_query::nearest_hit, 5.0, 6.5).outcome,
              query_outcome::malformed_output);  // outside the interval it was asked
    const double nan = std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(judge(fixed(query_kind::nearest_in_interval, {1, nan, nan}), ahead, ray_query::nearest_hit).outcome,
              query_outcome::non_finite);
    EXPECT_EQ(judge(fixed(query_kind::nearest_in_interval, {}), ahead, ray_query::nearest_hit).outcome,
              query_outcome::false_miss);
}

TEST(QueryJudge, LineRootsAreFilteredIntoTheInterval) {
    const variant roots = fixed(query_kind::line_roots, {2, 4, 6});
    EXPECT_EQ(judge(roots, ahead, ray_query::nearest_hit).outcome, query_outcome::correct);
    EXPECT_EQ(judge(roots, ahead, ray_query::nearest_hit, 4.5).outcome, query_outcome::correct);  // takes 6
    EXPECT_EQ(judge(roots, ahead, ray_query::any_hit, 4.5, 5.5).outcome, query_outcome::correct);
    // A line_roots variant whose near root lands just past tmin skips to the far root: wrong root.
    const double past = std::nextafter(4.0, 0.0);
    EXPECT_EQ(judge(fixed(query_kind::line_roots, {2, past, 6}), ahead, ray_query::nearest_hit, past).outcome,
              query_outcome::wrong_root);
}

TEST(QueryJudge, BothRootsJudgesBothUlpErrors) {
    const double six_minus_one = std::nextafter(6.0, 0.0);  // 6 − 2^-50, one ulp(6) below
    const query_verdict v = judge(fixed(query_kind::line_roots, {2, 4, six_minus_one}), ahead, ray_query::both_roots);
    EXPECT_EQ(v.outcome, query_outcome::correct);
    EXPECT_EQ(v.nearest_ulp, 0.0);
    EXPECT_EQ(v.far_ulp, 1.0);
    EXPECT_EQ(judge(fixed(query_kind::line_roots, {2, 6, 4}), ahead, ray_query::both_roots).outcome,
              query_outcome::malformed_output);
    EXPECT_EQ(judge(fixed(query_kind::line_roots, {2, 6, 6}), ahead, ray_query::both_roots).outcome,
              query_outcome::wrong_root);
    EXPECT_EQ(judge(fixed(query_kind::line_roots, {2, -6, -4}), behind, ray_query::both_roots).outcome,
              query_outcome::correct);  // the line's roots, whatever their sign
    EXPECT_EQ(judge(fixed(query_kind::line_roots, {}), behind, ray_query::both_roots).outcome,
              query_outcome::false_miss);
}

TEST(QueryJudge, HitPointNormalMeasuresTheHitPoint) {
    const query_verdict v = judge(builtin("hearn_baker_nearest"), ahead, ray_query::hit_point_normal);
    EXPECT_EQ(v.outcome, query_outcome::correct);
    EXPECT_EQ(v.hit_point_ulp, 0.0);  // o + 4d = (0, 0, −1) exactly
    // A root 2 ulp(4) = 2^-49 long moves z from −1 to −1 + 2^-49: 8 ulp(1).
    const double four_plus_two = std::nextafter(std::nextafter(4.0, 5.0), 5.0);
    const query_verdict off = judge(fixed(query_kind::nearest_in_interval, {1, four_plus_two, four_plus_two}), ahead,
                                    ray_query::hit_point_normal);
    EXPECT_EQ(off.outcome, query_outcome::correct);
    EXPECT_EQ(off.hit_point_ulp, 8.0);
}

TEST(QueryJudge, BuiltinsOnTheHandCases) {
    for (const char* name :
         {"naive", "hearn_baker", "hearn_baker_nearest", "hearn_baker_unit_nearest", "hearn_baker_unit"})
        for (const auto& g : {ahead, inside, behind, passing}) {
            const query_verdict v = judge(builtin(name), g, ray_query::nearest_hit);
            EXPECT_EQ(v.outcome, query_outcome::correct) << name << ": " << v.detail;
        }
    // seed004 clamps an inside origin to t = 0, which (0, +inf) excludes: the exit point is lost.
    EXPECT_EQ(judge(builtin("seed004_early_out"), ahead, ray_query::nearest_hit).outcome, query_outcome::correct);
    EXPECT_EQ(judge(builtin("seed004_early_out"), inside, ray_query::nearest_hit).outcome, query_outcome::false_miss);
    for (const char* name : {"hearn_baker_any_hit", "hearn_baker_unit_any_hit"})
        for (const auto& g : {ahead, inside, behind, passing})
            EXPECT_EQ(judge(builtin(name), g, ray_query::any_hit).outcome, query_outcome::correct) << name;
    // A unit-direction variant on a direction of length 2 is not scored.
    EXPECT_EQ(judge(builtin("hearn_baker_unit"), long_direction, ray_query::nearest_hit).outcome,
              query_outcome::contract_violation);
    // In float too.
    const corpus_case c = case_of(ahead, 0.0, 5.0);
    EXPECT_EQ(judge_query(builtin("hearn_baker_any_hit"), precision::binary32, c, ray_query::any_hit,
                          solve_exact(ahead, precision::binary32))
                  .outcome,
              query_outcome::correct);
}

TEST(QueryJudge, Applicability) {
    EXPECT_EQ(applicable(builtin("naive"), ray_query::both_roots, false), std::nullopt);
    const auto unit = applicable(builtin("hearn_baker_unit"), ray_query::nearest_hit, false);
    ASSERT_TRUE(unit);
    EXPECT_NE(unit->find("not normalised"), std::string::npos) << *unit;
    EXPECT_EQ(applicable(builtin("hearn_baker_unit"), ray_query::nearest_hit, true), std::nullopt);
    const auto any = applicable(builtin("hearn_baker_any_hit"), ray_query::nearest_hit, true);
    ASSERT_TRUE(any);
    EXPECT_NE(any->find("only any_hit"), std::string::npos) << *any;
    EXPECT_EQ(applicable(builtin("hearn_baker_any_hit"), ray_query::any_hit, false), std::nullopt);
    EXPECT_TRUE(applicable(builtin("hearn_baker_nearest"), ray_query::both_roots, true));
    EXPECT_EQ(applicable(builtin("hearn_baker_nearest"), ray_query::hit_point_normal, false), std::nullopt);
    EXPECT_TRUE(applicable(builtin("seed004_early_out"), ray_query::both_roots, true));
}

// exact_root_in decides the open interval exactly; away from the bounds it
// agrees with the oracle's (closed) hits_interval.
TEST(QueryJudge, ExactIntervalMembershipAgreesWithTheOracle) {
    const unsigned seed = 7;
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> coordinate(-4, 4), bound(-10, 10);
    for (int i = 0; i < 2000; ++i) {
        const ray_sphere<double> g{{coordinate(rng), coordinate(rng), coordinate(rng)},
                                   {coordinate(rng), coordinate(rng), coordinate(rng)},
                                   {coordinate(rng), coordinate(rng), coordinate(rng)},
                                   std::fabs(coordinate(rng))};
        double lo = bound(rng), hi = bound(rng);
        if (lo > hi) std::swap(lo, hi);
        const exact_solution e = solve_exact(g, precision::binary64, lo, hi);
        ASSERT_TRUE(e.hits_interval) << "seed " << seed << " case " << i;
        EXPECT_EQ(exact_nearest_in(e, {lo, hi}).has_value(), *e.hits_interval) << "seed " << seed << " case " << i;
    }
    // On the bound: the oracle's interval is closed, the query's open.
    const exact_solution on = solve_exact(ahead, precision::binary64, 4.0, 4.5);
    EXPECT_EQ(on.hits_interval, true);
    EXPECT_FALSE(exact_nearest_in(on, {4.0, 4.5}));
}

// The audit judges the new variants under their own contract: on the hand
// cases with an interval, every one agrees.
TEST(QueryJudge, AuditScoresIntervalKindsOnTheCaseInterval) {
    std::vector<corpus_case> cases = {case_of(ahead, 0.0, 3.0), case_of(ahead, 5.0, 7.0), case_of(inside),
                                      case_of(behind), case_of(passing)};
    std::vector<variant> chosen = {builtin("hearn_baker_any_hit"), builtin("hearn_baker_nearest"),
                                   builtin("hearn_baker_unit_nearest")};
    const audit_totals totals = run_audit(cases, targets_for(chosen));
    for (std::size_t t = 0; t < totals.targets.size(); ++t)
        EXPECT_EQ(totals.overall[t].verdicts[static_cast<int>(verdict_kind::agree)], cases.size())
            << totals.targets[t].label();
}

}  // namespace
}  // namespace rayverify
