// The one judge (compare/judge.h): every verdict kind from a hand-built answer
// against a hand-worked exact case; the contract semantics (range ends, the
// inside rule, faces, tangents, clamps) in both views; the exact decisions
// (wrong root by the midpoint, the unit-direction check, membership of a
// range); the causes; and every wrong verdict the judge once gave, as a
// literal case.
#include "compare/judge.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <random>
#include <sstream>
#include <limits>
#include <stdexcept>

#include "compare/audit.h"
#include "compare/error_figures.h"
#include "corpus/corpus_io.h"
#include "corpus/generators.h"
#include "intersectors/registry.h"
#include "intersectors/seed004_early_out.h"

namespace rayverify {
namespace {

constexpr double inf = std::numeric_limits<double>::infinity();
constexpr double nan = std::numeric_limits<double>::quiet_NaN();

// Unit sphere at the origin, ray along +z from (x, y, z).
ray_sphere<double> along_z(double x, double y, double z) { return {{x, y, z}, {0, 0, 1}, {0, 0, 0}, 1}; }
const ray_sphere<double> ahead = along_z(0, 0, -5);     // roots 4, 6
const ray_sphere<double> inside = along_z(0, 0, 0);     // roots −1, 1
const ray_sphere<double> behind = along_z(0, 0, 5);     // roots −6, −4
const ray_sphere<double> entering = along_z(0, 0, -1);  // on the surface: roots 0, 2
const ray_sphere<double> leaving = along_z(0, 0, 1);    // on the surface: roots −2, 0
const ray_sphere<double> tangent = along_z(1, 0, -5);   // double root 5
const ray_sphere<double> passing = along_z(2, 0, -5);   // miss

const contract line{.query = query_kind::line_roots, .reports_tangent = true};
const contract nearest{.query = query_kind::nearest_hit};                        // (0, +inf)
const contract nearest_closed{.query = query_kind::nearest_hit, .lower_end = end_kind::closed};  // [0, +inf)
const contract clamped = intersectors::seed004_early_out_contract;               // [0, +inf), clamp, unit
const contract any{.query = query_kind::any_hit};

corpus_case case_of(const ray_sphere<double>& g, std::optional<double> tmin = {}, std::optional<double> tmax = {}) {
    corpus_case c;
    c.id = "hand";
    c.geometry = g;
    c.tmin = tmin;
    c.tmax = tmax;
    return c;
}

case_score judge(const contract& k, const ray_sphere<double>& g, root_pair<double> answer,
                 precision p = precision::binary64, std::optional<double> tmin = {}, std::optional<double> tmax = {}) {
    variant_output out;
    out.roots = answer;
    return judge_output(k, out, solve_exact(g, p), range_of(k, tmin, tmax), g);
}

verdict_kind verdict(const contract& k, const ray_sphere<double>& g, root_pair<double> answer) {
    return judge(k, g, answer).verdict;
}

// A made-up variant answering `answer` whatever it is asked (double only).
variant fixed(const contract& k, root_pair<double> answer) {
    variant v;
    v.name = "fixed";
    v.promises = k;
    v.run_double = [answer](const ray_sphere<double>&) { return answer; };
    if (takes_interval(k)) v.run_double_in = [answer](const ray_sphere<double>&, double, double) { return answer; };
    return v;
}

// ---- Every verdict kind --------------------------------------------------------

TEST(Judge, LineRootsVerdicts) {
    EXPECT_EQ(verdict(line, ahead, {2, 4, 6}), verdict_kind::agree);
    EXPECT_EQ(verdict(line, ahead, {0, 0, 0}), verdict_kind::false_miss);
    EXPECT_EQ(verdict(line, passing, {2, 4, 6}), verdict_kind::false_hit);
    EXPECT_EQ(verdict(line, tangent, {0, 0, 0}), verdict_kind::tangent_missed);
    EXPECT_EQ(verdict(line, tangent, {2, 4.999, 5.001}), verdict_kind::tangent_split);
    EXPECT_EQ(verdict(line, tangent, {1, 5, 5}), verdict_kind::agree);
    EXPECT_EQ(verdict(line, ahead, {1, 5, 5}), verdict_kind::false_tangent);
    EXPECT_EQ(verdict(line, ahead, {2, 5.9, 6}), verdict_kind::wrong_root);
    EXPECT_EQ(verdict(line, ahead, {2, 6, 4}), verdict_kind::malformed_output);
    EXPECT_EQ(verdict(line, ahead, {3, 4, 6}), verdict_kind::malformed_output);
    EXPECT_EQ(verdict(line, ahead, {2, 4, nan}), verdict_kind::non_finite);
    EXPECT_EQ(verdict(line, ahead, {2, -4, 6}), verdict_kind::wrong_side);
    // Origin on the surface, entering: exact roots 0 and 2. A near root of
    // 1e-17 > 0 is a self-hit; −1e-17 is harmless (not in front either way).
    EXPECT_EQ(verdict(line, entering, {2, 1e-17, 2}), verdict_kind::wrong_side);
    EXPECT_EQ(verdict(line, entering, {2, -1e-17, 2}), verdict_kind::agree);
    // With a closed lower end, t* = 0 is in front and so is a returned 0.
    const contract closed_line{.query = query_kind::line_roots, .lower_end = end_kind::closed};
    EXPECT_EQ(verdict(closed_line, entering, {2, 0, 2}), verdict_kind::agree);
    EXPECT_EQ(verdict(closed_line, entering, {2, -1e-17, 2}), verdict_kind::wrong_side);
}

TEST(Judge, NearestHitVerdicts) {
    EXPECT_EQ(verdict(nearest, ahead, {1, 4, 4}), verdict_kind::agree);
    EXPECT_EQ(verdict(nearest, ahead, {1, 6, 6}), verdict_kind::wrong_root);
    EXPECT_EQ(verdict(nearest, ahead, {0, 0, 0}), verdict_kind::false_miss);
    EXPECT_EQ(verdict(nearest, behind, {1, 1, 1}), verdict_kind::false_hit);
    EXPECT_EQ(verdict(nearest, behind, {0, 0, 0}), verdict_kind::agree);
    EXPECT_EQ(verdict(nearest, inside, {1, 1, 1}), verdict_kind::agree);  // the far root, leaving
    EXPECT_EQ(verdict(nearest, tangent, {0, 0, 0}), verdict_kind::tangent_missed);
    EXPECT_EQ(verdict(nearest, ahead, {2, 4, 4}), verdict_kind::malformed_output);
    EXPECT_EQ(verdict(nearest, ahead, {1, nan, nan}), verdict_kind::non_finite);
    EXPECT_EQ(verdict(nearest, ahead, {1, inf, inf}), verdict_kind::non_finite);
    // A value past the range's end, standing for the root asked for: a lost hit.
    const contract in_interval{.query = query_kind::nearest_hit, .range = range_source::interval};
    EXPECT_EQ(judge(in_interval, ahead, {1, 6.5, 6.5}, precision::binary64, 4.5, 6.25).verdict,
              verdict_kind::wrong_side);
    EXPECT_EQ(judge(in_interval, ahead, {1, 6, 6}, precision::binary64, 4.5, 6.25).verdict, verdict_kind::agree);
}

TEST(Judge, AnyHitVerdicts) {
    EXPECT_EQ(verdict(any, ahead, {1, 0, 0}), verdict_kind::agree);
    EXPECT_EQ(verdict(any, ahead, {0, 0, 0}), verdict_kind::false_miss);
    EXPECT_EQ(verdict(any, behind, {1, 0, 0}), verdict_kind::false_hit);
    EXPECT_EQ(verdict(any, passing, {0, 0, 0}), verdict_kind::agree);
    EXPECT_EQ(verdict(any, ahead, {2, 0, 0}), verdict_kind::malformed_output);
    // Its roots are unused: a NaN in them is not a verdict.
    EXPECT_EQ(verdict(any, ahead, {1, nan, nan}), verdict_kind::agree);
}

TEST(Judge, UlpErrorsAreMeasured) {
    const case_score s = judge(line, ahead, {2, std::nextafter(4.0, 5.0), 6});
    ASSERT_TRUE(s.near_ulp && s.far_ulp && s.near_bits);
    EXPECT_EQ(*s.near_ulp, 1.0);  // one step above 4 is 2^−50 = ulp(4)
    EXPECT_EQ(*s.far_ulp, 0.0);
    EXPECT_EQ(*s.near_bits, 1.0);  // log2(1 + 1)
}

TEST(Judge, HitPointErrorForTheHit) {
    variant_output out;
    out.roots = {2, 4, 6};
    out.hit_root = 0;
    out.hit_point = vec3<double>{0, 0, -1};
    const case_score s =
        judge_output(line, out, solve_exact(ahead, precision::binary64), range_of(line, {}, {}), ahead);
    ASSERT_TRUE(s.hit_point_ulp);
    EXPECT_EQ((*s.hit_point_ulp)[2], 0.0);
    // A root 2 ulp(4) = 2^-49 long moves z from −1 to −1 + 2^-49: 8 ulp(1), through the whole path.
    const double four_plus_two = std::nextafter(std::nextafter(4.0, 5.0), 5.0);
    const target_outcome o =
        judge_target({fixed(nearest, {1, four_plus_two, four_plus_two}), precision::binary64}, case_of(ahead),
                     solve_exact(ahead, precision::binary64));
    ASSERT_TRUE(o.score.hit_point_ulp);
    EXPECT_EQ((*o.score.hit_point_ulp)[2], 8.0);
}

// ---- Contract semantics --------------------------------------------------------

TEST(Judge, RangeMembershipIsExactAndHonoursTheEnds) {
    const exact_solution e = solve_exact(ahead, precision::binary64);  // roots 4, 6
    const auto in = [&](root_index i, double lo, double hi, end_kind lower, end_kind upper) {
        return root_in_range(e, i, t_range{lo, hi, lower, upper});
    };
    const root_index near = root_index::near_root, far = root_index::far_root;
    EXPECT_FALSE(in(near, 4, 5, end_kind::open, end_kind::open));
    EXPECT_TRUE(in(near, 4, 5, end_kind::closed, end_kind::open));
    EXPECT_FALSE(in(far, 5, 6, end_kind::closed, end_kind::open));
    EXPECT_TRUE(in(far, 5, 6, end_kind::open, end_kind::closed));
    EXPECT_TRUE(in(near, -inf, inf, end_kind::open, end_kind::open));
    EXPECT_FALSE(in(near, inf, inf, end_kind::closed, end_kind::closed));
    EXPECT_FALSE(in(near, -inf, -inf, end_kind::closed, end_kind::closed));
    EXPECT_TRUE(in(near, std::nextafter(4.0, 0.0), std::nextafter(4.0, 5.0), end_kind::open, end_kind::open));
    // An irrational root against the doubles either side of it: RN(5 − √2) is
    // 0.28 ulp above 5 − √2 (oracle_test), so [RN, 5] just misses it.
    const exact_solution irrational = solve_exact({{0.5, 0, -5}, {0, 0, 1}, {0, 0, 0}, 1.5}, precision::binary64);
    const double rounded = 0x1.cafb0ccc0621ap+1;
    EXPECT_FALSE(root_in_range(irrational, near, {rounded, 5, end_kind::closed, end_kind::closed}));
    EXPECT_TRUE(root_in_range(irrational, near, {std::nextafter(rounded, 0.0), 5, end_kind::open, end_kind::open}));
    EXPECT_TRUE(root_in_range(irrational, near, {0, rounded, end_kind::open, end_kind::open}));
    // A tangent's double root.
    const exact_solution t = solve_exact(tangent, precision::binary64);
    EXPECT_TRUE(root_in_range(t, near, {5, 5, end_kind::closed, end_kind::closed}));
    EXPECT_FALSE(root_in_range(t, near, {std::nextafter(5.0, 6.0), 9, end_kind::closed, end_kind::closed}));
}

TEST(Judge, ExpectedHitUnderEachRule) {
    const exact_solution in = solve_exact(inside, precision::binary64), on = solve_exact(entering, precision::binary64);
    const t_range ray_open = range_of(nearest, {}, {}), ray_closed = range_of(nearest_closed, {}, {});
    EXPECT_EQ(expect_hit(nearest, in, ray_open).root, root_index::far_root);
    EXPECT_EQ(expect_hit(clamped, in, ray_closed).what, expected_hit::kind::clamp);
    EXPECT_EQ(expect_hit(clamped, in, ray_closed).value, 0.0);
    contract inside_miss = nearest;
    inside_miss.inside = inside_rule::miss;
    EXPECT_FALSE(expect_hit(inside_miss, in, ray_open).hit());
    contract front = nearest;
    front.front_faces_only = true;
    EXPECT_FALSE(expect_hit(front, in, ray_open).hit());
    EXPECT_EQ(expect_hit(front, solve_exact(ahead, precision::binary64), ray_open).root, root_index::near_root);
    // On the surface, entering (roots 0 and 2): open, the far root; closed, the near root 0.
    EXPECT_EQ(expect_hit(nearest, on, ray_open).root, root_index::far_root);
    EXPECT_EQ(expect_hit(nearest_closed, on, ray_closed).root, root_index::near_root);
    EXPECT_FALSE(starts_inside(on, ray_open));  // the start is on the near root, not strictly inside
    contract tangent_miss = nearest;
    tangent_miss.tangent_is_hit = false;
    EXPECT_FALSE(expect_hit(tangent_miss, solve_exact(tangent, precision::binary64), ray_open).hit());
    EXPECT_TRUE(expect_hit(nearest, solve_exact(tangent, precision::binary64), ray_open).hit());
}

// Issue item 4: with the nearest t on the closed ray [0, +inf) and the origin
// on the surface, the near root 0 is the answer: the far root is a wrong root,
// and explain's "asks for" names the near root.
TEST(JudgeRegression, ClosedRayOriginOnTheSurfaceWantsTheNearRootZero) {
    EXPECT_EQ(verdict(nearest_closed, entering, {1, 0, 0}), verdict_kind::agree);
    EXPECT_EQ(verdict(nearest_closed, entering, {1, 2, 2}), verdict_kind::wrong_root);
    const exact_solution e = solve_exact(entering, precision::binary64);
    const std::string asks = describe_expected(nearest_closed, e, range_of(nearest_closed, {}, {}));
    EXPECT_NE(asks.find("near root t* ≈ 0"), std::string::npos) << asks;
    // The open ray wants the far root, and a returned 0 is a self-hit on the near root.
    EXPECT_EQ(verdict(nearest, entering, {1, 2, 2}), verdict_kind::agree);
    EXPECT_EQ(verdict(nearest, entering, {1, 1e-17, 1e-17}), verdict_kind::wrong_side);
}

TEST(Judge, SpecRoundTripAndStrictNames) {
    for (const variant& v : builtin_variants()) {
        const contract back = parse_contract(format_contract(v.promises));
        EXPECT_EQ(format_contract(back), format_contract(v.promises)) << v.name;
    }
    EXPECT_THROW(parse_contract("query=nearest"), std::invalid_argument);
    EXPECT_THROW(parse_contract("ends=[["), std::invalid_argument);
    EXPECT_THROW(parse_contract("colour=red"), std::invalid_argument);
    EXPECT_THROW(parse_contract("unit_direction=maybe"), std::invalid_argument);
    EXPECT_THROW(parse_contract("tangent_threshold=-1"), std::invalid_argument);
    EXPECT_THROW(parse_contract("query"), std::invalid_argument);
    const contract c = parse_contract("query=nearest_hit,ends=[),inside=clamp");
    EXPECT_EQ(c.query, query_kind::nearest_hit);
    EXPECT_EQ(c.lower_end, end_kind::closed);
    EXPECT_EQ(c.upper_end, end_kind::open);
    EXPECT_EQ(c.inside, inside_rule::clamp);
    for (int k = 0; k < verdict_kind_count; ++k) {
        const auto kind = static_cast<verdict_kind>(k);
        EXPECT_EQ(verdict_from_name(verdict_name(kind)), kind);
        EXPECT_FALSE(verdict_meaning(kind).empty());
    }
    for (int c = 0; c < disagreement_cause_count; ++c) {
        const auto cause = static_cast<disagreement_cause>(c);
        EXPECT_EQ(cause_from_name(cause_name(cause)), cause);
    }
    EXPECT_EQ(verdict_from_name("other"), std::nullopt);
    EXPECT_EQ(cause_from_name("rounding"), std::nullopt);
    EXPECT_EQ(ray_query_from_name("nearest"), std::nullopt);
    EXPECT_EQ(query_kind_from_name("nearest_on_ray"), std::nullopt);
}

// ---- Wrong verdicts the judge once gave (issue: one judge, exact everywhere) ----

// Item 1: NaN where the exact roots overflow the format was scored agree,
// wrong_side or tangent_split. NaN never agrees; ±inf agrees only where RN(t*) is it.
TEST(JudgeRegression, NanWhereTheExactRootOverflowsIsNonFinite) {
    const auto run = [](const char* name, const ray_sphere<double>& g, precision p) {
        const variant* v = find_builtin_variant(name);
        corpus_case c = case_of(g);
        return judge_target({*v, p}, c, solve_case(c, p)).score;
    };
    const ray_sphere<double> float_case{{0, 0, 0}, {-0x1p-20, 0, 0}, {0x1p+110, 0, 0}, 0x1p+100};
    for (const char* name : {"naive", "half_b", "stable_roots", "hearn_baker", "fma_discriminant"}) {
        const case_score s = run(name, float_case, precision::binary32);
        EXPECT_EQ(s.verdict, verdict_kind::non_finite) << name << ": " << s.detail;
    }
    const ray_sphere<double> behind_case{{0, 0, 0}, {-0x1p-4, 0, 0}, {0x1p+1022, 0, 0}, 0x1p+1000};
    const ray_sphere<double> front_case{{0, 0, 0}, {0x1p-4, 0, 0}, {0x1p+1022, 0, 0}, 0x1p+1000};
    const ray_sphere<double> tangent_case{{0, 0x1p+1000, 0}, {0x1p-4, 0, 0}, {0x1p+1022, 0, 0}, 0x1p+1000};
    for (const auto& g : {behind_case, front_case, tangent_case})
        EXPECT_EQ(run("naive", g, precision::binary64).verdict, verdict_kind::non_finite);
    // The exact roots round to −inf in float: an answer of −inf is the correctly rounded one.
    const exact_solution e = solve_case(case_of(float_case), precision::binary32);
    ASSERT_EQ(e.near_root.rounded, -inf);
    variant_output out;
    out.roots = {2, -inf, -inf};
    const case_score s = judge_output(line, out, e, range_of(line, {}, {}), float_case);
    EXPECT_EQ(s.verdict, verdict_kind::agree) << s.detail;
    EXPECT_FALSE(s.near_ulp);  // not a number of ulps: left out of the figures
    // The largest finite float beside −inf: finite, nearer the far root than the near one.
    out.roots = {2, -inf, std::numeric_limits<float>::lowest()};
    EXPECT_EQ(judge_output(line, out, e, range_of(line, {}, {}), float_case).verdict, verdict_kind::agree);
    out.roots = {2, inf, inf};
    EXPECT_EQ(judge_output(line, out, e, range_of(line, {}, {}), float_case).verdict, verdict_kind::non_finite);
}

// A root in front whose correctly rounded value is +inf (past float's largest
// value): +inf lies outside the open range (0, +inf), yet it is the best
// answer there is, so it agrees; a finite answer is judged as usual.
TEST(JudgeRegression, TheCorrectlyRoundedInfinityOfARootInFrontIsNoLostHit) {
    const ray_sphere<double> g{{0, 0, 0}, {0x1p-20, 0, 0}, {0x1p+110, 0, 0}, 0x1p+100};  // roots 2^130 ± 2^120
    const exact_solution e = solve_case(case_of(g), precision::binary32);
    ASSERT_EQ(e.near_root.rounded, inf);
    ASSERT_GT(e.near_root.sign, 0);
    variant_output out;
    out.roots = {1, inf, inf};
    const case_score s = judge_output(nearest, out, e, range_of(nearest, {}, {}), g);
    EXPECT_EQ(s.verdict, verdict_kind::agree) << s.detail;
    out.roots = {2, inf, inf};
    EXPECT_EQ(judge_output(line, out, e, range_of(line, {}, {}), g).verdict, verdict_kind::agree);
    out.roots = {1, -inf, -inf};  // not the correctly rounded infinity
    EXPECT_EQ(judge_output(nearest, out, e, range_of(nearest, {}, {}), g).verdict, verdict_kind::non_finite);
    out.roots = {1, 0x1p+127, 0x1p+127};  // finite and below the midpoint: it stands for the near root
    EXPECT_EQ(judge_output(nearest, out, e, range_of(nearest, {}, {}), g).verdict, verdict_kind::agree);
}

// Item 2: wrong_root decided exactly, by the side of the exact midpoint −b′/a.
TEST(JudgeRegression, WrongRootIsDecidedByTheExactMidpoint) {
    const variant& seed004 = *find_builtin_variant("seed004_early_out");
    // seed004/double returns exactly −b′/a, the midpoint: equidistant, the root asked for.
    const ray_sphere<double> at_midpoint{{0x1.ap-726, 0x1.3p-726, 0x1.9fd95f672cb19p-724},
                                         {0, 0, -0x1p+0},
                                         {0x1.9p-725, 0x1.3p-726, 0},
                                         0x1.4p-725};
    const exact_solution m = solve_exact(at_midpoint, precision::binary64);
    const root_pair<double> r = seed004.run_double(at_midpoint);
    ASSERT_EQ(r.count, 1);
    EXPECT_EQ(m.compare_to_midpoint(r.t0), comparison::equal);
    EXPECT_NE(r.t0, m.near_root.rounded);
    EXPECT_EQ(stands_for(m, r.t0, root_index::near_root), root_index::near_root);
    EXPECT_EQ(stands_for(m, r.t0, root_index::far_root), root_index::far_root);
    EXPECT_EQ(judge_target({seed004, precision::binary64}, case_of(at_midpoint), m).score.verdict, verdict_kind::agree);
    // One ulp nearer the far root than the near one: wrong_root, though rounded
    // arithmetic could not tell.
    const ray_sphere<double> nearer_far{{-0x1p-147, 0x1.8p-127, 0x1.1p-127},
                                        {-0x1p+0, 0, 0},
                                        {-0x1.a917183ee360cp-94, 0x1.8p-127, 0x1.9p-127},
                                        0x1.4p-128};
    const exact_solution f = solve_exact(nearer_far, precision::binary64);
    const root_pair<double> g = seed004.run_double(nearer_far);
    ASSERT_EQ(g.count, 1);
    EXPECT_EQ(f.compare_to_midpoint(g.t0), comparison::larger);
    const case_score s = judge_target({seed004, precision::binary64}, case_of(nearer_far), f).score;
    EXPECT_EQ(s.verdict, verdict_kind::wrong_root) << s.detail;
    // A correctly rounded root is never a wrong root, even nearer the other one.
    EXPECT_EQ(stands_for(f, f.near_root.rounded, root_index::near_root), root_index::near_root);
}

// Item 3: the unit-direction check is exact: |d|² − 1 = 2^-49 + 2^-101 + 2^-154
// exceeds 8ε = 2^-49 by less than long double can see.
TEST(JudgeRegression, UnitDirectionToleranceIsDecidedExactly) {
    const ray_sphere<double> g{{0, 0, -5}, {0x1.0000000000001p-25, 0x1p-25, 0x1p+0}, {0, 0, 0}, 1};
    const auto breach = contract_breach(clamped, g, precision::binary64);
    ASSERT_TRUE(breach);
    EXPECT_NE(breach->find("above 1 + 8ε"), std::string::npos) << *breach;
    EXPECT_EQ(compare_squared_length(g.direction, 1 + 0x1p-49), comparison::larger);
    // Exactly at the tolerance is within it.
    const ray_sphere<double> edge{{0, 0, -5}, {0x1p-25, 0x1p-25, 0x1p+0}, {0, 0, 0}, 1};  // |d|² = 1 + 2^-49
    EXPECT_EQ(compare_squared_length(edge.direction, 1 + 0x1p-49), comparison::equal);
    EXPECT_FALSE(contract_breach(clamped, edge, precision::binary64));
    // Float's tolerance 8·2^-23.
    EXPECT_FALSE(contract_breach(clamped, edge, precision::binary32));
    EXPECT_FALSE(contract_breach(line, {{0, 0, 0}, {0, 0, 7}, {0, 0, 0}, 1}, precision::binary64));
}

// Item 3, second half: a unit-direction formula fed a direction within
// tolerance but not of length 1 fails in exact arithmetic too: its cause is
// the assumption, not rounding. d = (2^-25, 2^-25, 1), |d|² = 1 + 2^-49; with
// f = (x, 0, 0), r = 1: Δ′ = a − x²(1 + 2^-50) and, with a taken as 1,
// Δ′ = 1 − x²(1 − 2^-50). At x = 1 + 2^-51 (x² = 1 + 2^-50 + 2^-102) the first
// is −2^-100 + O(2^-102) < 0, a miss, and the second +2^-100 + … > 0, a hit.
TEST(JudgeRegression, WithinToleranceDirectionFailureIsByDesign) {
    const ray_sphere<double> g{{1 + 0x1p-51, 0, 0}, {0x1p-25, 0x1p-25, 1}, {0, 0, 0}, 1};
    const exact_solution truth = solve_exact(g, precision::binary64);
    const exact_solution with_unit_a = solve_exact_unit_direction(g, precision::binary64);
    ASSERT_EQ(truth.cls, line_class::miss);
    ASSERT_EQ(with_unit_a.cls, line_class::two_hit);
    ASSERT_FALSE(contract_breach(clamped, g, precision::binary64));
    // What the a = 1 formula says in exact arithmetic (correctly rounded): a hit.
    const contract unit_line{.query = query_kind::line_roots, .assumes_unit_direction = true};
    variant_output out;
    out.roots = {2, with_unit_a.near_root.rounded, with_unit_a.far_root.rounded};
    const case_score s = judge_output(unit_line, out, truth, range_of(unit_line, {}, {}), g);
    EXPECT_EQ(s.verdict, verdict_kind::false_hit);
    EXPECT_EQ(s.cause, disagreement_cause::unit_direction);
    // Without the assumption the same answer is rounding error.
    const case_score plain = judge_output(line, out, truth, range_of(line, {}, {}), g);
    EXPECT_EQ(plain.verdict, verdict_kind::false_hit);
    ASSERT_TRUE(plain.cause);
    EXPECT_FALSE(is_by_design(*plain.cause));
}

// Items 5 and 7: a clamped answer agrees under its own contract (corpus), and
// is a false miss where the renderer's interval excludes 0 (scene), with the
// cause "clamp", never rounding.
TEST(JudgeRegression, ClampAgreesInTheContractViewAndLeaksInTheRenderersView) {
    const variant& seed004 = *find_builtin_variant("seed004_early_out");
    const corpus_case c = case_of(inside, 0.5);  // a shadow ray from inside, tmin = 0.5
    const exact_solution e = solve_case(c, precision::binary64);
    const target_outcome own = judge_target({seed004, precision::binary64}, c, e);
    EXPECT_EQ(own.score.verdict, verdict_kind::agree) << own.score.detail;
    const renderer_outcome seen = judge_for_renderer({seed004, precision::binary64}, c, ray_query::any_hit, e);
    EXPECT_EQ(seen.score.verdict, verdict_kind::false_miss) << seen.score.detail;
    EXPECT_EQ(seen.score.cause, disagreement_cause::clamp);
    // tmin = 0 open: the renderer drops the clamped 0 too.
    const renderer_outcome at_zero =
        judge_for_renderer({seed004, precision::binary64}, case_of(inside), ray_query::nearest_hit,
                           solve_case(case_of(inside), precision::binary64));
    EXPECT_EQ(at_zero.score.verdict, verdict_kind::false_miss);
    EXPECT_EQ(at_zero.score.cause, disagreement_cause::clamp);
}

// Item 7: a nearest-hit formula that returns the line's root behind its range
// fails by design (it tests the line, not the ray), not by rounding.
TEST(JudgeRegression, ARootBehindTheRangeIsTheLineNotTheRay) {
    const case_score s = judge(nearest, inside, {1, -1, -1});
    EXPECT_EQ(s.verdict, verdict_kind::wrong_root);
    EXPECT_EQ(s.cause, disagreement_cause::line_not_ray);
    const case_score leak = judge(nearest, behind, {1, -4, -4});  // nothing in front, returns −4
    EXPECT_EQ(leak.verdict, verdict_kind::false_hit);
}

// Item 7: seed003's absolute epsilon names its false tangents.
TEST(JudgeRegression, AbsoluteTangentEpsilonIsByDesign) {
    const variant& seed003 = *find_builtin_variant("seed003_reduced");
    // Δ = p² − q = 1e-8 with d = ẑ: two roots 1e-4 apart, reported as a tangent.
    const ray_sphere<double> g{{std::sqrt(1 - 1e-8), 0, -5}, {0, 0, 1}, {0, 0, 0}, 1};
    const corpus_case c = case_of(g);
    const case_score s = judge_target({seed003, precision::binary64}, c, solve_case(c, precision::binary64)).score;
    EXPECT_EQ(s.verdict, verdict_kind::false_tangent) << s.detail;
    EXPECT_EQ(s.cause, disagreement_cause::tangent_threshold);
}

// Item 10: the per-case figures carry a count-1 answer's second root (judged too).
TEST(JudgeRegression, CountOneAnswerSecondRootIsJudged) {
    EXPECT_EQ(verdict(line, tangent, {1, 5, 5.5}), verdict_kind::tangent_split);
    const case_score s = judge(line, tangent, {1, 5, 5});
    EXPECT_TRUE(s.far_ulp);
}

// ---- The renderer's view ---------------------------------------------------------

renderer_outcome seen(const variant& v, const ray_sphere<double>& g, ray_query q, std::optional<double> tmin = {},
                      std::optional<double> tmax = {}) {
    const corpus_case c = case_of(g, tmin, tmax);
    return judge_for_renderer({v, precision::binary64}, c, q, solve_case(c, precision::binary64));
}

TEST(RendererView, AnyHitOnTheOpenInterval) {
    const variant hit = fixed({.query = query_kind::any_hit, .range = range_source::interval}, {1, 0, 0});
    const variant miss = fixed({.query = query_kind::any_hit, .range = range_source::interval}, {});
    EXPECT_EQ(seen(hit, ahead, ray_query::any_hit).score.verdict, verdict_kind::agree);
    EXPECT_EQ(seen(miss, ahead, ray_query::any_hit).score.verdict, verdict_kind::false_miss);
    EXPECT_EQ(seen(hit, ahead, ray_query::any_hit, 0.0, 3.0).score.verdict, verdict_kind::false_hit);
    EXPECT_EQ(seen(miss, ahead, ray_query::any_hit, 0.0, 3.0).score.verdict, verdict_kind::agree);
    EXPECT_EQ(seen(hit, ahead, ray_query::any_hit, 4.0, 6.0).score.verdict, verdict_kind::false_hit);  // open
    EXPECT_EQ(seen(hit, behind, ray_query::any_hit).score.verdict, verdict_kind::false_hit);
    EXPECT_EQ(seen(fixed({.query = query_kind::any_hit, .range = range_source::interval}, {2, 0, 0}), ahead,
                   ray_query::any_hit)
                  .score.verdict,
              verdict_kind::malformed_output);
}

TEST(RendererView, LineRootsAreFilteredIntoTheInterval) {
    const variant roots = fixed(line, {2, 4, 6});
    EXPECT_EQ(seen(roots, ahead, ray_query::nearest_hit).score.verdict, verdict_kind::agree);
    EXPECT_EQ(seen(roots, ahead, ray_query::nearest_hit, 4.5).score.verdict, verdict_kind::agree);  // takes 6
    EXPECT_EQ(seen(roots, ahead, ray_query::any_hit, 4.5, 5.5).score.verdict, verdict_kind::agree);
    // A near root landing just past tmin skips to the far root: a wrong root.
    const double past = std::nextafter(4.0, 0.0);
    EXPECT_EQ(seen(fixed(line, {2, past, 6}), ahead, ray_query::nearest_hit, past).score.verdict,
              verdict_kind::wrong_root);
    // A NaN the renderer looks at never agrees, even on a miss.
    EXPECT_EQ(seen(fixed(line, {2, nan, nan}), passing, ray_query::any_hit).score.verdict, verdict_kind::non_finite);
    // Both roots: the line's, whatever their sign.
    EXPECT_EQ(seen(fixed(line, {2, -6, -4}), behind, ray_query::both_roots).score.verdict, verdict_kind::agree);
    EXPECT_EQ(seen(fixed(line, {2, 6, 6}), ahead, ray_query::both_roots).score.verdict, verdict_kind::false_tangent);
}

TEST(RendererView, AnAnswerOutsideTheIntervalIsNotTaken) {
    const variant far_out = fixed({.query = query_kind::nearest_hit, .range = range_source::interval}, {1, 7, 7});
    const renderer_outcome o = seen(far_out, ahead, ray_query::nearest_hit, 5.0, 6.5);
    EXPECT_EQ(o.score.verdict, verdict_kind::false_miss);
    // Its own contract promised a root inside: the cause is what happened there (a lost hit).
    ASSERT_TRUE(o.score.cause);
    EXPECT_FALSE(is_by_design(*o.score.cause));
}

TEST(RendererView, BuiltinsOnTheHandCases) {
    for (const char* name :
         {"naive", "hearn_baker", "hearn_baker_nearest", "hearn_baker_unit_nearest", "hearn_baker_unit"})
        for (const auto& g : {ahead, inside, behind, passing}) {
            const renderer_outcome o = seen(*find_builtin_variant(name), g, ray_query::nearest_hit);
            EXPECT_EQ(o.score.verdict, verdict_kind::agree) << name << ": " << o.score.detail;
        }
    EXPECT_EQ(seen(*find_builtin_variant("seed004_early_out"), ahead, ray_query::nearest_hit).score.verdict,
              verdict_kind::agree);
    for (const char* name : {"hearn_baker_any_hit", "hearn_baker_unit_any_hit"})
        for (const auto& g : {ahead, inside, behind, passing})
            EXPECT_EQ(seen(*find_builtin_variant(name), g, ray_query::any_hit).score.verdict, verdict_kind::agree)
                << name;
    const ray_sphere<double> long_direction{{0, 0, -5}, {0, 0, 2}, {0, 0, 0}, 1};
    EXPECT_EQ(seen(*find_builtin_variant("hearn_baker_unit"), long_direction, ray_query::nearest_hit).score.verdict,
              verdict_kind::contract_violation);
}

TEST(RendererView, Applicability) {
    const auto builtin = [](const char* n) -> const variant& { return *find_builtin_variant(n); };
    EXPECT_EQ(applicable(builtin("naive"), ray_query::both_roots, false), std::nullopt);
    const auto unit = applicable(builtin("hearn_baker_unit"), ray_query::nearest_hit, false);
    ASSERT_TRUE(unit);
    EXPECT_NE(unit->find("not normalised"), std::string::npos) << *unit;
    EXPECT_EQ(applicable(builtin("hearn_baker_unit"), ray_query::nearest_hit, true), std::nullopt);
    const auto only_any = applicable(builtin("hearn_baker_any_hit"), ray_query::nearest_hit, true);
    ASSERT_TRUE(only_any);
    EXPECT_NE(only_any->find("only any_hit"), std::string::npos) << *only_any;
    EXPECT_TRUE(applicable(builtin("hearn_baker_nearest"), ray_query::both_roots, true));
    EXPECT_TRUE(applicable(builtin("seed004_early_out"), ray_query::both_roots, true));
}

// The audit judges the interval variants under their own contract: on the
// hand cases with an interval, every one agrees.
TEST(Judge, AuditScoresIntervalContractsOnTheCaseInterval) {
    std::vector<corpus_case> cases = {case_of(ahead, 0.0, 3.0), case_of(ahead, 5.0, 7.0), case_of(inside),
                                      case_of(behind), case_of(passing)};
    std::vector<variant> chosen = {*find_builtin_variant("hearn_baker_any_hit"),
                                   *find_builtin_variant("hearn_baker_nearest"),
                                   *find_builtin_variant("hearn_baker_unit_nearest")};
    const audit_totals totals = run_audit(cases, targets_for(chosen));
    for (std::size_t t = 0; t < totals.targets.size(); ++t)
        EXPECT_EQ(totals.overall[t].verdicts[static_cast<int>(verdict_kind::agree)], cases.size())
            << totals.targets[t].label();
}

}  // namespace
}  // namespace rayverify

namespace rayverify {
namespace {

// The one verdict table drives every list of verdicts; docs/verdicts.md's
// column table must name each corpus verdict's column, in the summary's order.
TEST(VerdictTable, DocsColumnTableListsEveryCorpusVerdictInOrder) {
    std::ifstream in(std::string(RAYVERIFY_SOURCE_DIR) + "/docs/verdicts.md");
    ASSERT_TRUE(in) << "docs/verdicts.md";
    std::vector<std::string> documented;
    for (std::string line; std::getline(in, line);)
        if (line.starts_with("| ") && line.find(" | ", 2) != std::string::npos)
            documented.push_back(line.substr(2, line.find(" | ", 2) - 2));
    std::vector<std::string> wanted;
    for (int k = 0; k < verdict_kind_count; ++k)
        if (is_corpus_verdict(static_cast<verdict_kind>(k))) wanted.emplace_back(verdict_column(static_cast<verdict_kind>(k)));
    std::size_t at = 0;
    for (const std::string& column : wanted) {
        const auto found = std::find(documented.begin() + static_cast<std::ptrdiff_t>(at), documented.end(), column);
        ASSERT_NE(found, documented.end()) << "docs/verdicts.md has no row for column " << column << " (in order)";
        at = static_cast<std::size_t>(found - documented.begin()) + 1;
    }
}

// The schemas name what the tables define: the per-case verdict and cause
// enums are the tables' names, in order, and every error figure is a
// property of a per-case result (its case name) and of a tally (its name).
TEST(VerdictTable, SchemasNameEveryVerdictCauseAndFigure) {
    const auto schema = [](const char* name) {
        std::ifstream in(std::string(RAYVERIFY_SOURCE_DIR) + "/docs/schema/" + name);
        EXPECT_TRUE(in) << name;
        return nlohmann::json::parse(in);
    };
    const nlohmann::json per_case = schema("per-case.schema.json"), common = schema("common.schema.json");
    const nlohmann::json& result = per_case.at("$defs").at("result").at("properties");
    std::vector<std::string> verdicts, causes;
    for (int k = 0; k < verdict_kind_count; ++k) verdicts.emplace_back(verdict_name(static_cast<verdict_kind>(k)));
    for (int c = 0; c < disagreement_cause_count; ++c) causes.emplace_back(cause_name(static_cast<disagreement_cause>(c)));
    EXPECT_EQ(result.at("verdict").at("enum").get<std::vector<std::string>>(), verdicts);
    EXPECT_EQ(result.at("cause").at("enum").get<std::vector<std::string>>(), causes);
    const nlohmann::json& tally = common.at("$defs").at("tally").at("properties");
    for (const error_figure_definition& f : error_figures) {
        EXPECT_TRUE(result.contains(std::string(f.case_name))) << "per-case.schema.json lacks " << f.case_name;
        EXPECT_TRUE(tally.contains(std::string(f.name))) << "common.schema.json's tally lacks " << f.name;
    }
}

// The derived lists: a disagreement is scored and not agree; a wrong class is a disagreement; only
// wrong_sphere is a scene's; an any-hit scene table shows no root verdicts.
TEST(VerdictTable, DerivedListsAreConsistent) {
    for (int k = 0; k < verdict_kind_count; ++k) {
        const auto v = static_cast<verdict_kind>(k);
        SCOPED_TRACE(std::string(verdict_name(v)));
        EXPECT_EQ(verdict_from_name(verdict_name(v)), v);
        if (is_misclassification(v)) {
            EXPECT_TRUE(is_disagreement(v));
        }
        EXPECT_EQ(is_corpus_verdict(v), v != verdict_kind::wrong_sphere);
        if (!is_disagreement(v) && v != verdict_kind::agree) {
            for (const ray_query q : {ray_query::any_hit, ray_query::nearest_hit, ray_query::both_roots}) {
                EXPECT_FALSE(scene_table_shows(v, q));
            }
        }
    }
    EXPECT_FALSE(scene_table_shows(verdict_kind::wrong_root, ray_query::any_hit));
    EXPECT_TRUE(scene_table_shows(verdict_kind::wrong_sphere, ray_query::nearest_hit));
    EXPECT_FALSE(scene_table_shows(verdict_kind::wrong_sphere, ray_query::both_roots));
}

// The audit judges every target of a case against one frame per precision
// (case_frame: the stability measures, the unit-direction checks and the
// a = 1 idealisation formed once and shared). Each target's judgement must
// be exactly what it gets judged alone, with a frame of its own, and the
// case's stability measures exactly measure_stability's: on the shipped
// corpus (every verdict and cause the built-in variants reach there) and on
// directions that break the unit-direction assumption in double only.
bool same_figure(const std::optional<double>& a, const std::optional<double>& b) {
    if (a.has_value() != b.has_value()) return false;
    return !a || std::bit_cast<std::uint64_t>(*a) == std::bit_cast<std::uint64_t>(*b);
}

void expect_same_stability(const stability_measures& shared, const stability_measures& own) {
    EXPECT_EQ(shared.valid, own.valid);
    EXPECT_EQ(shared.cls, own.cls);
    EXPECT_TRUE(same_figure(shared.near_condition, own.near_condition));
    EXPECT_TRUE(same_figure(shared.far_condition, own.far_condition));
    for (const auto& [a, b] : {std::pair{shared.tangency_distance, own.tangency_distance},
                              {shared.tangency_margin, own.tangency_margin},
                              {shared.discriminant_sign, own.discriminant_sign},
                              {shared.near_root, own.near_root},
                              {shared.distance_ratio, own.distance_ratio}})
        EXPECT_TRUE(same_figure(a, b)) << a << " vs " << b;
}

TEST(CaseFrame, EveryTargetIsJudgedOnTheSharedFrameAsOnItsOwn) {
    std::vector<corpus_case> cases = read_corpus({RAYVERIFY_CORPUS_DIR});
    // |d|² = 1 + 2^-44: beyond 8ε of double, within 8ε of float.
    for (const double y : {0x1p-22, -0x1p-22, 0x1p-30}) {
        corpus_case c;
        c.id = "unit-" + std::to_string(cases.size());
        c.geometry = {{0.25, -5, 0.5}, {0, 1, y}, {0, 0, 0}, 1};
        cases.push_back(c);
    }
    const std::vector<audit_target> targets = targets_for(builtin_variants());
    std::size_t judged = 0, breaches = 0, by_design = 0;
    for (const corpus_case& c : cases) {
        const audited_case audited = audit_case(c, targets);
        ASSERT_EQ(audited.outcomes.size(), targets.size());
        for (const precision p : every_precision) {
            SCOPED_TRACE(c.id + " " + std::string(precision_name(p)));
            const exact_solution exact = solve_case(c, p);
            expect_same_stability(audited.stability.at(p), measure_stability(rounded_to(p, c.geometry), p, exact));
        }
        for (std::size_t t = 0; t < targets.size(); ++t) {
            SCOPED_TRACE(c.id + " " + targets[t].label());
            const case_score& shared = audited.outcomes[t].score;
            const case_score own = judge_target(targets[t], c, solve_case(c, targets[t].prec)).score;
            EXPECT_EQ(shared.verdict, own.verdict);
            EXPECT_EQ(shared.cause, own.cause);
            EXPECT_EQ(shared.detail, own.detail);
            for (const error_figure_definition& f : error_figures)
                EXPECT_TRUE(same_figure(f.of_case(shared), f.of_case(own))) << f.name;
            EXPECT_TRUE(same_figure(shared.far_bits, own.far_bits));
            EXPECT_EQ(shared.hit_point_ulp, own.hit_point_ulp);
            ++judged;
            breaches += shared.verdict == verdict_kind::contract_violation;
            by_design += shared.cause && is_by_design(*shared.cause);
        }
    }
    // The shared facts were used: unit-direction breaches and causes by design among them.
    EXPECT_GT(breaches, 100u);
    EXPECT_GT(by_design, 100u);
    EXPECT_GT(judged, 100000u);
}

}  // namespace
}  // namespace rayverify

namespace rayverify {
namespace {

// ---- The accuracy clause (accuracy=ulp:N, radius:x, distance:x) -----------------

contract with_accuracy(contract k, std::string_view clause) {
    k.accuracy = parse_accuracy(clause);
    return k;
}

// Worked by hand: the ray (0, 0, −10) + t·(0, 0, 2) meets the sphere of radius
// 2 at the origin at t* = 4 and 6, with |d| = 2: |t − 4|·|d| = 0.5 at t = 4.25,
// a quarter of the radius. Exactly at the bound agrees; one double beyond
// is imprecise, on either side of the root.
TEST(Accuracy, DistanceAndRadiusAreDecidedExactlyAtTheBound) {
    const ray_sphere<double> g{{0, 0, -10}, {0, 0, 2}, {0, 0, 0}, 2};
    for (const char* clause : {"distance:0.5", "radius:0.25"}) {
        const contract k = with_accuracy(nearest, clause);
        const auto verdict_at = [&](double t) { return judge(k, g, {1, t, t}).verdict; };
        EXPECT_EQ(verdict_at(4.25), verdict_kind::agree) << clause;
        EXPECT_EQ(verdict_at(3.75), verdict_kind::agree) << clause;
        EXPECT_EQ(verdict_at(std::nextafter(4.25, 5.0)), verdict_kind::imprecise) << clause;
        EXPECT_EQ(verdict_at(std::nextafter(3.75, 3.0)), verdict_kind::imprecise) << clause;
        EXPECT_EQ(verdict_at(4.0), verdict_kind::agree) << clause;
        // Nearer the far root: still wrong_root, which comes first.
        EXPECT_EQ(verdict_at(5.5), verdict_kind::wrong_root) << clause;
    }
    // Both roots of a line_roots answer are held to it.
    const contract both = with_accuracy(line, "distance:0.5");
    EXPECT_EQ(judge(both, g, {2, 4.25, 6.25}).verdict, verdict_kind::agree);
    EXPECT_EQ(judge(both, g, {2, 4, std::nextafter(6.25, 7.0)}).verdict, verdict_kind::imprecise);
    const case_score far = judge(both, g, {2, 4, 6.5});
    EXPECT_EQ(far.verdict, verdict_kind::imprecise);
    EXPECT_NE(far.detail.find("t1 = 6.5"), std::string::npos) << far.detail;
    EXPECT_NE(far.detail.find("accuracy=distance:0.5"), std::string::npos) << far.detail;
    EXPECT_TRUE(is_disagreement(verdict_kind::imprecise));
    EXPECT_FALSE(is_misclassification(verdict_kind::imprecise));
}

// ulp(4) in double is 2^−50 (4 opens its binade); below 4 a double steps by 2^−51.
TEST(Accuracy, UlpBoundCountsUlpsOfTheExactRoot) {
    const contract k = with_accuracy(nearest, "ulp:4");
    const auto verdict_at = [&](double t) { return judge(k, ahead, {1, t, t}).verdict; };
    EXPECT_EQ(verdict_at(4 + 4 * 0x1p-50), verdict_kind::agree);
    EXPECT_EQ(verdict_at(4 + 5 * 0x1p-50), verdict_kind::imprecise);
    EXPECT_EQ(verdict_at(4 - 8 * 0x1p-51), verdict_kind::agree);    // 4 ulps of t*, 8 steps below it
    EXPECT_EQ(verdict_at(4 - 9 * 0x1p-51), verdict_kind::imprecise);  // 4.5 ulps
    // An irrational root (5 − √0.75): its correctly rounded value is within
    // half an ulp, and no double is within 0 ulps.
    const ray_sphere<double> off_axis = along_z(0.5, 0, -5);
    const exact_solution exact = solve_exact(off_axis, precision::binary64);
    const double rounded = exact.near_root.rounded;
    EXPECT_EQ(judge(with_accuracy(nearest, "ulp:0.5"), off_axis, {1, rounded, rounded}).verdict, verdict_kind::agree);
    EXPECT_EQ(judge(with_accuracy(nearest, "ulp:0"), off_axis, {1, rounded, rounded}).verdict,
              verdict_kind::imprecise);
    // The exact comparison and the figure agree wherever the figure is not the bound itself.
    for (int steps = -6; steps <= 6; ++steps) {
        double t = rounded;
        for (int i = 0; i < std::abs(steps); ++i) t = std::nextafter(t, steps < 0 ? 0.0 : 10.0);
        const double figure = exact.root_ulp_error(root_index::near_root, t);
        for (const double bound : {0.25, 1.0, 2.5, 4.0}) {
            if (figure == bound) continue;
            EXPECT_EQ(exact.compare_root_ulp_error(root_index::near_root, t, bound),
                      figure < bound ? comparison::smaller : comparison::larger)
                << "t " << t << " bound " << bound;
        }
    }
}

// A clamp's start is exact or wrong; an any_hit contract has no t and refuses the clause.
TEST(Accuracy, ClampsAreExactAndAnyHitRefusesTheClause) {
    const contract k = with_accuracy(clamped, "distance:0");
    EXPECT_EQ(judge(k, inside, {1, 0, 0}).verdict, verdict_kind::agree);
    EXPECT_THROW(parse_contract("query=any_hit,accuracy=ulp:1"), std::invalid_argument);
}

TEST(Accuracy, ClauseSpellingRoundTripsAndBadClausesAreRefused) {
    const contract k = parse_contract("query=nearest_hit,accuracy=radius:0.001");
    EXPECT_EQ(k.accuracy.unit, accuracy_unit::radius);
    EXPECT_EQ(k.accuracy.bound, 0.001);
    EXPECT_EQ(parse_contract(format_contract(k)).accuracy.bound, 0.001);
    EXPECT_NE(format_contract(k).find(",accuracy=radius:0.001"), std::string::npos);
    EXPECT_EQ(format_contract(nearest).find("accuracy"), std::string::npos);  // only when required
    EXPECT_FALSE(parse_accuracy("none").required());
    for (const char* bad : {"ulp:-1", "ulp:nan", "radius:inf", "furlong:3", "radius", "distance:", "ulp:1e", ""}) {
        try {
            parse_accuracy(bad);
            ADD_FAILURE() << bad << " was taken";
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find("accuracy="), std::string::npos) << e.what();
        }
    }
}

// The exact distance comparison against the scale figure (|t − t*|·|d| / r,
// rounded) on random cases: they agree wherever the figure is not within
// 2^-40 of the bound. Seed printed; RAYVERIFY_ACCURACY_SEED replays one.
TEST(Accuracy, DistanceComparisonAgreesWithTheScaleFigure) {
    std::uint64_t seed = std::random_device{}();
    if (const char* given = std::getenv("RAYVERIFY_ACCURACY_SEED")) seed = std::stoull(given);
    std::cout << "seed " << seed << " (RAYVERIFY_ACCURACY_SEED)\n";
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> unit(-1, 1), scale(-12, 12);
    int compared = 0;
    for (int i = 0; i < 2000; ++i) {
        const double r = std::exp2(scale(rng) / 2);
        const vec3<double> centre{unit(rng) * 4, unit(rng) * 4, std::exp2(scale(rng))};
        const vec3<double> d{unit(rng) * r / centre.z, unit(rng) * r / centre.z, std::exp2(scale(rng) / 4)};
        const ray_sphere<double> g{{0, 0, 0}, d, centre, r};
        const exact_solution exact = solve_exact(g, precision::binary64);
        if (!exact.valid() || exact.cls == line_class::miss) continue;
        const double root = exact.near_root.rounded;
        const double t = root * (1 + unit(rng) * std::exp2(scale(rng) - 14));
        const case_score agreeing = judge(line, g, {2, t, exact.far_root.rounded});
        if (agreeing.verdict != verdict_kind::agree || !agreeing.scale_error_radius) continue;
        const double figure = *agreeing.scale_error_radius;
        for (const double bound : {figure * 0.5, figure * 2, 1e-3, 0.25}) {
            std::ostringstream clause;
            clause << "radius:" << std::setprecision(17) << bound;
            const contract bounded = with_accuracy(line, clause.str());
            if (std::fabs(figure - bounded.accuracy.bound) <= 0x1p-40 * bounded.accuracy.bound) continue;
            EXPECT_EQ(judge(bounded, g, {2, t, exact.far_root.rounded}).verdict,
                      figure > bounded.accuracy.bound ? verdict_kind::imprecise : verdict_kind::agree)
                << "seed " << seed << " case " << i << " figure " << figure << " " << clause.str();
            ++compared;
        }
    }
    EXPECT_GT(compared, 1000);
}


// ---- Degenerate casts (degenerate=miss) ------------------------------------------

// Hand-made degenerate casts: each is invalid and never run without the
// clause; with it, the target is called and must answer a miss.
TEST(Degenerate, CastsAreHandedOverOnlyUnderTheClause) {
    const double zero_length[3] = {0, 0, 0};
    std::vector<corpus_case> casts;
    casts.push_back(case_of({{0, 0, -5}, {zero_length[0], zero_length[1], zero_length[2]}, {0, 0, 0}, 1}));
    casts.push_back(case_of({{0, 0, nan}, {0, 0, 1}, {0, 0, 0}, 1}));
    casts.push_back(case_of({{0, 0, -5}, {0, 0, inf}, {0, 0, 0}, 1}));
    casts.push_back(case_of(ahead, 6.0, 4.0));   // a reversed interval
    casts.push_back(case_of(ahead, nan, 4.0));   // a NaN bound
    const contract strict{.query = query_kind::nearest_hit, .range = range_source::interval};
    contract asks = strict;
    asks.degenerate_is_miss = true;
    int calls = 0;
    const auto target_of = [&](const contract& k, root_pair<double> answer) {
        variant v = fixed(k, answer);
        v.run_double_in = [&calls, answer](const ray_sphere<double>&, double, double) { return ++calls, answer; };
        return audit_target{v, precision::binary64};
    };
    for (const corpus_case& c : casts) {
        const exact_solution exact = solve_case(c, precision::binary64);
        ASSERT_FALSE(exact.valid());
        calls = 0;
        EXPECT_EQ(judge_target(target_of(strict, {1, nan, nan}), c, exact).score.verdict, verdict_kind::invalid);
        EXPECT_EQ(calls, 0);
        EXPECT_FALSE(run_input<double>(target_of(strict, {0, 0, 0}), c));
        const target_outcome hit = judge_target(target_of(asks, {1, nan, nan}), c, exact);
        EXPECT_EQ(calls, 1);
        EXPECT_EQ(hit.score.verdict, verdict_kind::degenerate_hit) << invalid_reason_name(exact.invalid);
        EXPECT_NE(hit.score.detail.find(invalid_reason_name(exact.invalid)), std::string::npos) << hit.score.detail;
        EXPECT_EQ(judge_target(target_of(asks, {0, nan, nan}), c, exact).score.verdict, verdict_kind::agree);
        const target_outcome unanswered = judge_target(target_of(asks, {-1, 0, 0}), c, exact);
        EXPECT_EQ(unanswered.score.verdict, verdict_kind::degenerate_hit);
        EXPECT_NE(unanswered.score.detail.find("no answer"), std::string::npos) << unanswered.score.detail;
        EXPECT_TRUE(run_input<double>(target_of(asks, {0, 0, 0}), c));
    }
    // A negative radius is the sphere's fault: invalid under the clause too.
    const corpus_case negative = case_of({{0, 0, -5}, {0, 0, 1}, {0, 0, 0}, -1});
    EXPECT_EQ(judge_target(target_of(asks, {0, 0, 0}), negative, solve_case(negative, precision::binary64)).score.verdict,
              verdict_kind::invalid);
    EXPECT_FALSE(run_input<double>(target_of(asks, {0, 0, 0}), negative));
    EXPECT_EQ(format_contract(parse_contract("query=nearest_hit,degenerate=miss")).find("degenerate=miss") !=
                  std::string::npos,
              true);
    EXPECT_THROW(parse_contract("degenerate=hit"), std::invalid_argument);
    EXPECT_TRUE(is_disagreement(verdict_kind::degenerate_hit));
}

// The textbook formula divides by a = 0 for a zero direction: NaN roots and
// a count of 2, which the clause catches; robust_sphere.h answers a miss.
TEST(Degenerate, TheTextbookFormulaHitsAZeroLengthCastAndRobustDoesNot) {
    const corpus_case zero = case_of({{0, 0, 0.5}, {0, 0, 0}, {0, 0, 0}, 1});
    for (const char* name : {"naive", "robust", "robust_nearest"}) {
        const variant* v = find_builtin_variant(name);
        ASSERT_NE(v, nullptr);
        audit_target target{*v, precision::binary64};
        target.subject.promises.degenerate_is_miss = true;
        const verdict_kind got = judge_target(target, zero, solve_case(zero, precision::binary64)).score.verdict;
        EXPECT_EQ(got, std::string_view(name) == "naive" ? verdict_kind::degenerate_hit : verdict_kind::agree) << name;
    }
}

// An audit that prints no per-case line asks the judge to leave each
// disagreement's sentence unformed (figure_request::details): everything
// else it decides is the same. Every shipped case with every built-in
// variant, judged both ways.
TEST(Judge, SentencesLeftOutChangeNothingElse) {
    const std::vector<audit_target> targets = targets_for(builtin_variants());
    figure_request without;
    without.details = false;
    std::size_t disagreements = 0, breaches = 0;
    for (const corpus_case& c : read_corpus({RAYVERIFY_CORPUS_DIR})) {
        const audited_case with = audit_case(c, targets);
        const audited_case bare = audit_case(c, targets, {}, without);
        ASSERT_EQ(with.outcomes.size(), bare.outcomes.size());
        for (std::size_t t = 0; t < targets.size(); ++t) {
            const case_score& a = with.outcomes[t].score;
            const case_score& b = bare.outcomes[t].score;
            const std::string where = c.id + " " + targets[t].subject.name;
            ASSERT_EQ(a.verdict, b.verdict) << where;
            ASSERT_EQ(a.cause, b.cause) << where;
            for (const error_figure_definition& f : error_figures)
                ASSERT_EQ(f.of_case(a), f.of_case(b)) << where << " " << f.name;
            ASSERT_EQ(a.hit_point_ulp, b.hit_point_ulp) << where;
            ASSERT_EQ(a.far_bits, b.far_bits) << where;
            ASSERT_EQ(a.zero_root_error, b.zero_root_error) << where;
            if (a.verdict == verdict_kind::contract_violation && targets[t].subject.promises.assumes_unit_direction) {
                // A unit-direction breach: its words (|d|² to 17 digits) only when asked.
                ++breaches;
                EXPECT_TRUE(a.detail.starts_with("assumes a unit direction, but |d|² ≈ ")) << where << ": " << a.detail;
                EXPECT_TRUE(b.detail.empty()) << where;
                continue;
            }
            if (!is_disagreement(a.verdict) || a.verdict == verdict_kind::imprecise ||
                a.verdict == verdict_kind::unsound_bound)
                continue;
            // The judge's own rows: their sentence formed only when asked.
            ++disagreements;
            EXPECT_FALSE(a.detail.empty()) << where;
            EXPECT_TRUE(b.detail.empty()) << where;
        }
    }
    EXPECT_GT(disagreements, 1000u);
    EXPECT_GT(breaches, 1000u);
}

// The audit asks for an agreeing answer's figures to their printed digits
// (figure_request::audit): each may be a lower bound, with its upper bound
// kept. Against the figures to every digit, on the shipped corpus and
// generated ordinary cases with every built-in variant: the same verdicts,
// causes and figures present; each exact figure within its bounds, and both
// bounds in its bucket; a disagreement's figures exact; and exact_figures
// gives the figures to every digit, bit for bit.
TEST(Judge, FiguresToPrintedDigitsBoundTheExactOnes) {
    const std::vector<audit_target> targets = targets_for(builtin_variants());
    std::vector<corpus_case> cases = generate_family("uniform", 300, 5);
    for (corpus_case& c : generate_family("far_sphere", 300, 5)) cases.push_back(std::move(c));
    // Near a tangent, root enclosures are wide: scale figures bounded from both ends.
    for (corpus_case& c : generate_family("near_tangent", 300, 5)) cases.push_back(std::move(c));
    for (corpus_case& c : read_corpus({RAYVERIFY_CORPUS_DIR})) cases.push_back(std::move(c));
    figure_request audit_request = figure_request::audit(), every_digit;
    audit_request.details = every_digit.details = false;
    std::size_t bounded = 0, scale_from_wide_bounds = 0;
    for (const corpus_case& c : cases) {
        const audited_case fast = audit_case(c, targets, {}, audit_request);
        const audited_case exact = audit_case(c, targets, {}, every_digit);
        for (std::size_t t = 0; t < targets.size(); ++t) {
            const case_score& a = fast.outcomes[t].score;
            const case_score& b = exact.outcomes[t].score;
            const std::string where = c.id + " " + targets[t].label();
            ASSERT_EQ(a.verdict, b.verdict) << where;
            ASSERT_EQ(a.cause, b.cause) << where;
            ASSERT_FALSE(b.figure_upper_bounds) << where;
            if (a.verdict != verdict_kind::agree) {
                ASSERT_FALSE(a.figure_upper_bounds) << where;
            }
            for (const error_figure_definition& f : error_figures) {
                ASSERT_EQ(f.of_case(a).has_value(), f.of_case(b).has_value()) << where << " " << f.name;
                if (!f.of_case(a)) continue;
                const double lower = *f.of_case(a), upper = f.upper_of_case(a), value = *f.of_case(b);
                ASSERT_TRUE(lower <= value && value <= upper) << where << " " << f.name << std::hexfloat << " ["
                                                              << lower << ", " << upper << "] " << value;
                ASSERT_EQ(error_summary::bucket_of(lower), error_summary::bucket_of(upper)) << where << " " << f.name;
                bounded += lower != upper;
                // Wider than the factor 1 + 2^-22 a tight root bracket allows.
                const bool scale = f.figure == error_figure::scale_error_radius ||
                                   f.figure == error_figure::scale_error_distance;
                scale_from_wide_bounds += scale && upper > lower * (1 + 0x1p-21);
            }
            if (!a.figure_upper_bounds) continue;
            const case_score settled = exact_figures(targets[t], c, fast.outcomes[t], fast.exact_for(targets[t].prec));
            for (const error_figure_definition& f : error_figures)
                ASSERT_EQ(f.of_case(settled), f.of_case(b)) << where << " " << f.name;
            ASSERT_EQ(settled.hit_point_ulp, b.hit_point_ulp) << where;
            ASSERT_FALSE(settled.figure_upper_bounds) << where;
            if (printed_as_exact(a))
                for (const error_figure_definition& f : error_figures)
                    if (f.of_case(a)) {
                        ASSERT_EQ(printed_figure(*f.of_case(a)), printed_figure(*f.of_case(b))) << where;
                    }
        }
    }
    EXPECT_GT(bounded, 10000u);  // figures were taken from bounds
    EXPECT_GT(scale_from_wide_bounds, 100u);
}

}  // namespace
}  // namespace rayverify
