// The worst-case hunter: it finds a known failure within a small evaluation
// budget (reproducible: no time limit), shrinks it without losing it, beats
// random sampling, and is deterministic.
#include "compare/hunt.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <span>
#include <string>
#include <vector>

#include "compare/audit.h"
#include "corpus/corpus_io.h"
#include "corpus/generators.h"
#include "core/float_bits.h"

namespace rayverify {
namespace {

audit_target target(const char* name, precision p) { return {*find_builtin_variant(name), p}; }

hunt_start from_family(const char* family, std::uint64_t seed) {
    return [family, seed](std::uint64_t i) { return generate_case(family, seed, i).geometry; };
}

bool same_bits(const ray_sphere<double>& a, const ray_sphere<double>& b) {
    return format_case_line({"x", "", a, {}, {}, "", {}}) == format_case_line({"x", "", b, {}, {}, "", {}});
}

// Component by component through a volatile (GCC 12 at -O2 may drop a
// whole-struct double → float → double round trip on some lanes).
bool float_exact(const ray_sphere<double>& g) {
    for (const double x : {g.origin.x, g.origin.y, g.origin.z, g.direction.x, g.direction.y, g.direction.z,
                           g.centre.x, g.centre.y, g.centre.z, g.radius}) {
        const volatile float rounded = static_cast<float>(x);
        if (std::bit_cast<std::uint64_t>(static_cast<double>(rounded)) != std::bit_cast<std::uint64_t>(x)) return false;
    }
    return true;
}

// The verdict of a case through the audit engine: an independent path from the hunter's.
verdict_kind audited_verdict(const audit_target& t, const ray_sphere<double>& g) {
    corpus_case c;
    c.id = "check";
    c.geometry = g;
    const audit_target targets[] = {t};
    return audit_case(c, targets).outcomes.front().score.verdict;
}

// A misclass hunt of seed 1 within 5000 evaluations, stopping at `finds`.
hunt_options misclass_hunt(std::size_t finds) {
    hunt_options options;
    options.objective = hunt_objective::misclass;
    options.max_evaluations = 5000;
    options.max_finds = finds;
    options.seed = 1;
    return options;
}

TEST(Hunt, FindsAndShrinksAMisclassificationOfNaiveInFloat) {
    const hunt_options options = misclass_hunt(2);
    const audit_target naive = target("naive", precision::binary32);
    const hunt_result r = hunt(naive, from_family("uniform", 1), options);
    ASSERT_EQ(r.finds.size(), 2u) << r.evaluations << " evaluations";
    for (const hunt_find& f : r.finds) {
        SCOPED_TRACE(format_case_line({"found", "", f.found, {}, {}, "", {}}));
        EXPECT_TRUE(is_disagreement(f.found_eval.verdict));
        EXPECT_EQ(f.shrunk_eval.verdict, f.found_eval.verdict);
        EXPECT_EQ(audited_verdict(naive, f.found), f.found_eval.verdict);
        EXPECT_EQ(audited_verdict(naive, f.shrunk), f.found_eval.verdict);
        EXPECT_LT(f.shrunk_bits, f.found_bits);
        EXPECT_EQ(f.shrunk_bits, significant_bits(f.shrunk));
        EXPECT_TRUE(float_exact(f.found));
        EXPECT_TRUE(float_exact(f.shrunk));
        EXPECT_GT(f.evaluation, 0u);
        EXPECT_LE(f.evaluation, r.evaluations);
    }
}

// Steps of float between two cases' inputs, in all.
std::uint64_t float_steps_between(const ray_sphere<double>& a, const ray_sphere<double>& b) {
    const double x[10] = {a.origin.x, a.origin.y, a.origin.z, a.direction.x, a.direction.y,
                          a.direction.z, a.centre.x, a.centre.y, a.centre.z, a.radius};
    const double y[10] = {b.origin.x, b.origin.y, b.origin.z, b.direction.x, b.direction.y,
                          b.direction.z, b.centre.x, b.centre.y, b.centre.z, b.radius};
    std::uint64_t steps = 0;
    for (int i = 0; i < 10; ++i) steps += ulps_between<float>(static_cast<float>(x[i]), static_cast<float>(y[i]));
    return steps;
}

// Start cases of the user's (hunt --corpus): a find is shrunk toward the
// case it was searched from, never away from it, and a user case that fails
// as it is comes back unchanged (0 inputs, 0 steps from it).
TEST(Hunt, FindsFromTheUsersCasesShrinkTowardThem) {
    hunt_options options = misclass_hunt(3);
    options.shrink_toward_start = true;
    const audit_target naive = target("naive", precision::binary32);
    std::vector<ray_sphere<double>> users;
    for (std::uint64_t i = 0; i < 4; ++i) users.push_back(rounded_to(precision::binary32, generate_case("uniform", 7, i).geometry));
    const hunt_start from_users = [&](std::uint64_t i) { return users[i % users.size()]; };
    const hunt_result r = hunt(naive, from_users, options);
    ASSERT_EQ(r.finds.size(), 3u) << r.evaluations << " evaluations";
    for (const hunt_find& f : r.finds) {
        const ray_sphere<double>& start = users[f.start_index % users.size()];
        EXPECT_EQ(audited_verdict(naive, f.shrunk), f.found_eval.verdict);
        EXPECT_LE(float_steps_between(f.shrunk, start), float_steps_between(f.found, start));
        EXPECT_EQ(f.steps_from_start, float_steps_between(f.shrunk, start));
        EXPECT_LE(f.inputs_changed, 10);
    }
    // A far sphere naive/float misjudges as given: found at the first evaluation, unchanged.
    ray_sphere<double> failing{};
    for (std::uint64_t i = 0;; ++i) {
        failing = rounded_to(precision::binary32, generate_case("far_sphere", 1, i).geometry);
        if (is_disagreement(audited_verdict(naive, failing))) break;
    }
    options.max_finds = 1;
    const hunt_result as_given = hunt(naive, [&](std::uint64_t) { return failing; }, options);
    ASSERT_EQ(as_given.finds.size(), 1u);
    EXPECT_EQ(as_given.finds[0].evaluation, 1u);
    EXPECT_EQ(as_given.finds[0].inputs_changed, 0);
    EXPECT_EQ(as_given.finds[0].steps_from_start, 0u);
    EXPECT_TRUE(same_bits(as_given.finds[0].shrunk, failing));
}

// --cause algorithmic keeps only finds a better formula avoids; every find,
// shrunk, keeps its verdict and cause on replay and a sphere of radius > 0.
TEST(Hunt, CauseFilterKeepsOnlyThatCauseAndShrinkingKeepsTheCaseValid) {
    hunt_options options;
    options.objective = hunt_objective::misclass;
    options.max_evaluations = 4000;
    options.max_finds = 3;
    options.seed = 1;
    options.only_cause = disagreement_cause::algorithmic;
    const audit_target naive = target("naive", precision::binary64);
    const hunt_result r = hunt(naive, from_family("far_sphere", 1), options);
    ASSERT_FALSE(r.finds.empty()) << r.evaluations << " evaluations";
    for (const hunt_find& f : r.finds) {
        SCOPED_TRACE(format_case_line({"shrunk", "", f.shrunk, {}, {}, "", {}}));
        EXPECT_EQ(f.found_eval.cause, disagreement_cause::algorithmic);
        EXPECT_EQ(f.shrunk_eval.cause, disagreement_cause::algorithmic);
        EXPECT_GT(f.shrunk.radius, 0);
        const hunt_evaluation replay = evaluate_for_hunt(naive, f.shrunk, options.objective);
        EXPECT_EQ(replay.verdict, f.found_eval.verdict);
        EXPECT_EQ(replay.cause, f.found_eval.cause);
    }
}

TEST(Hunt, FindsAMisclassificationOfNaiveInDoubleWhereRandomSamplingDoesNot) {
    hunt_options options;
    options.objective = hunt_objective::misclass;
    options.max_evaluations = 20000;
    options.seed = 1;
    const audit_target naive = target("naive", precision::binary64);
    const hunt_result searched = hunt(naive, from_family("uniform", 1), options);
    ASSERT_EQ(searched.finds.size(), 1u);
    EXPECT_EQ(audited_verdict(naive, searched.finds[0].shrunk), searched.finds[0].found_eval.verdict);

    options.strategy = hunt_strategy::random;
    options.shrink = false;
    const hunt_result sampled = hunt(naive, from_family("uniform", 1), options);
    EXPECT_TRUE(sampled.finds.empty() || sampled.finds[0].evaluation > searched.finds[0].evaluation);
}

TEST(Hunt, ReachesFarLargerUlpErrorsThanRandomSamplingWithTheSameBudget) {
    for (const precision p : {precision::binary32, precision::binary64}) {
        SCOPED_TRACE(precision_name(p));
        hunt_options options;
        options.objective = hunt_objective::ulp;
        options.max_evaluations = 6000;
        options.shrink = false;
        const audit_target naive = target("naive", p);
        const hunt_result searched = hunt(naive, from_family("uniform", 1), options);
        options.strategy = hunt_strategy::random;
        const hunt_result sampled = hunt(naive, from_family("uniform", 1), options);
        ASSERT_EQ(searched.finds.size(), 1u);
        ASSERT_EQ(sampled.finds.size(), 1u);
        EXPECT_EQ(sampled.starts, 6000u);
        std::cout << precision_name(p) << ": search " << searched.finds[0].found_eval.error << " ulp, random "
                  << sampled.finds[0].found_eval.error << " ulp in 6000 evaluations\n";
        EXPECT_GT(searched.finds[0].found_eval.error, 100 * sampled.finds[0].found_eval.error);
    }
}

TEST(Hunt, UlpFindsShrinkKeepingAtLeastHalfTheError) {
    hunt_options options;
    options.max_evaluations = 3000;
    const audit_target naive = target("naive", precision::binary64);
    const hunt_result r = hunt(naive, from_family("far_sphere", 2), options);
    ASSERT_EQ(r.finds.size(), 1u);
    const hunt_find& f = r.finds[0];
    EXPECT_EQ(f.shrunk_eval.verdict, verdict_kind::agree);
    EXPECT_GE(f.shrunk_eval.error, f.found_eval.error / 2);
    EXPECT_LE(f.shrunk_bits, f.found_bits);
    EXPECT_EQ(evaluate_for_hunt(naive, f.shrunk).error, f.shrunk_eval.error);
}

TEST(Hunt, IsDeterministicForASeedAndAnEvaluationBudget) {
    hunt_options options;
    options.objective = hunt_objective::misclass;
    options.max_evaluations = 4000;
    options.max_finds = 3;
    options.seed = 7;
    const audit_target t = target("half_b", precision::binary32);
    const hunt_result a = hunt(t, from_family("far_sphere", 7), options);
    const hunt_result b = hunt(t, from_family("far_sphere", 7), options);
    ASSERT_EQ(a.finds.size(), b.finds.size());
    EXPECT_EQ(a.evaluations, b.evaluations);
    for (std::size_t i = 0; i < a.finds.size(); ++i) {
        EXPECT_TRUE(same_bits(a.finds[i].found, b.finds[i].found));
        EXPECT_TRUE(same_bits(a.finds[i].shrunk, b.finds[i].shrunk));
        EXPECT_EQ(a.finds[i].evaluation, b.finds[i].evaluation);
    }
    EXPECT_FALSE(a.finds.empty());
}

TEST(Hunt, EveryFindNearExactTangentsIsAConfirmedDisagreement) {
    // hearn_baker in double near the tangent_exact family: the hunter must
    // find disagreements (its documented NaN at the tangent point b = 0, and
    // false hits just off tangency), and every one it reports must be what the
    // audit engine says of the same case.
    hunt_options options;
    options.objective = hunt_objective::misclass;
    options.max_evaluations = 1500;
    options.max_finds = 5;
    const audit_target t = target("hearn_baker", precision::binary64);
    const hunt_result r = hunt(t, from_family("tangent_exact", 3), options);
    ASSERT_FALSE(r.finds.empty()) << "no find in " << r.evaluations << " evaluations";
    bool documented_nan = false;
    for (const hunt_find& f : r.finds) {
        EXPECT_TRUE(is_disagreement(f.found_eval.verdict)) << f.found_eval.detail;
        EXPECT_EQ(audited_verdict(t, f.found), f.found_eval.verdict);
        EXPECT_EQ(audited_verdict(t, f.shrunk), f.shrunk_eval.verdict);
        documented_nan = documented_nan || f.found_eval.verdict == verdict_kind::non_finite;
    }
    EXPECT_TRUE(documented_nan) << "the NaN at the tangent point was not found";
}

// The search ranks ULP errors by brackets and settles them only where two
// overlap or a find needs the error: it must search exactly as a judge that
// measures every error to every digit (an external judge's path, which ranks
// by exact errors) does, whatever the variant, precision, family and strategy.
TEST(Hunt, RankingByBracketedErrorsSearchesAsExactErrorsDo) {
    struct setting {
        const char* variant;
        precision prec;
        const char* family;
        hunt_strategy strategy;
    };
    const setting settings[] = {
        {"naive", precision::binary64, "uniform", hunt_strategy::search},
        {"naive", precision::binary32, "near_tangent", hunt_strategy::search},
        {"half_b", precision::binary64, "far_sphere", hunt_strategy::random},
        {"hearn_baker_unit", precision::binary64, "on_surface", hunt_strategy::search},
        {"stable_roots", precision::binary32, "uniform", hunt_strategy::search},
        {"seed004_early_out", precision::binary32, "inside", hunt_strategy::search},
        {"robust", precision::binary64, "tangent_exact", hunt_strategy::search},
    };
    for (const setting& s : settings) {
        SCOPED_TRACE(std::string(s.variant) + "/" + precision_name(s.prec) + " from " + s.family);
        const audit_target t = target(s.variant, s.prec);
        hunt_options options;
        options.objective = hunt_objective::ulp;
        options.strategy = s.strategy;
        options.max_evaluations = 3000;
        options.patience = 150;
        options.seed = 5;
        const hunt_judge exact_judge = [&](std::span<const corpus_case> cases) {
            std::vector<hunt_evaluation> evals;
            for (const corpus_case& c : cases) evals.push_back(evaluate_for_hunt(t, c, options.objective));
            return evals;
        };
        const hunt_result ranked = hunt(t, from_family(s.family, 2), options);
        const hunt_result exact = hunt(t, from_family(s.family, 2), options, exact_judge);
        EXPECT_EQ(ranked.evaluations, exact.evaluations);
        EXPECT_EQ(ranked.starts, exact.starts);
        EXPECT_EQ(ranked.shrink_evaluations, exact.shrink_evaluations);
        EXPECT_EQ(ranked.disagreements, exact.disagreements);
        ASSERT_EQ(ranked.finds.size(), exact.finds.size());
        for (std::size_t k = 0; k < ranked.finds.size(); ++k) {
            const hunt_find &a = ranked.finds[k], &b = exact.finds[k];
            EXPECT_TRUE(same_bits(a.found, b.found));
            EXPECT_TRUE(same_bits(a.shrunk, b.shrunk));
            EXPECT_EQ(std::bit_cast<std::uint64_t>(a.found_eval.error), std::bit_cast<std::uint64_t>(b.found_eval.error));
            EXPECT_EQ(std::bit_cast<std::uint64_t>(a.shrunk_eval.error), std::bit_cast<std::uint64_t>(b.shrunk_eval.error));
            EXPECT_EQ(a.evaluation, b.evaluation);
        }
        ASSERT_EQ(ranked.first_disagreement.has_value(), exact.first_disagreement.has_value());
        if (ranked.first_disagreement) {
            EXPECT_TRUE(same_bits(ranked.first_disagreement->found, exact.first_disagreement->found));
        }
    }
}

TEST(Hunt, SignificantBitsCountsEachInput) {
    const ray_sphere<double> g{{1, 0.5, 3}, {0, 0, 1}, {0, 0, 0}, 0.75};
    // 1, 1, 2 | 0, 0, 1 | 0, 0, 0 | 2
    EXPECT_EQ(significant_bits(g), 7);
}

}  // namespace
}  // namespace rayverify
