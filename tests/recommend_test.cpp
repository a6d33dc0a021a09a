// `recommend` (bench/recommend.h) on tiny scenes: what it decides, never how
// fast anything is. Budgets parse or fail with the part at fault; the winner
// meets the budget and is the cheapest that does, except that with no wrong
// ray allowed a variant deciding exactly by construction wins; variants that cannot
// answer a kind's query are listed with the reason; the CLI exits 1 when no
// variant fits.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>

#include "bench/recommend.h"
#include "core/input_error.h"
#include "intersectors/registry.h"
#include "scene/scene.h"
#include "support/process.h"

namespace rayverify::bench {
namespace {

using test_support::run_cli;

// Ray Tracing Gems fig. 7-3 in miniature: unit spheres at 100 and 4100 in
// float, seen orthographically; naive loses the far one.
const char* far_spheres = R"({
  "comment": "test: far spheres in float",
  "precision": "float",
  "normalise_directions": true,
  "camera": {"projection": "orthographic", "position": [0, 0, 0], "look_at": [0, 0, -1],
             "view_height": 6, "resolution": [24, 12]},
  "spheres": [{"name": "near", "centre": [-1.5, 0, -100], "radius": 1},
              {"name": "far", "centre": [1.5, 0, -4100], "radius": 1}],
  "rays": {"primary": {"query": "nearest_hit"}}
})";

// A lamp over a ball: primary nearest hits and shadow rays (any_hit).
const char* lamp = R"({
  "comment": "test: shadow rays",
  "precision": "double",
  "normalise_directions": false,
  "camera": {"projection": "perspective", "position": [0, 0, 5], "look_at": [0, 0, 0],
             "fov_degrees": 40, "resolution": [12, 8]},
  "spheres": [{"name": "ball", "centre": [0, 0, 0], "radius": 1},
              {"name": "blocker", "centre": [1.5, 1.5, 1.5], "radius": 0.5}],
  "lights": [{"name": "lamp", "position": [4, 4, 4]}],
  "rays": {"primary": {"query": "nearest_hit"}, "shadow": {"query": "any_hit"}}
})";

timing_options quick() {
    timing_options t;
    t.repetitions = 2;
    t.min_time_s = 0.0005;
    t.warmup_s = 0;
    return t;
}

recommendation decide(const char* text, recommend_budget budget = {}) {
    const scene s = parse_scene(text, "test.json");
    const std::vector<scene_ray> rays = generate_rays(s);
    return recommend(s, rays, builtin_variants(), budget, quick());
}

const recommend_candidate* find(const kind_recommendation& k, const std::string& name) {
    for (const recommend_candidate& c : k.candidates)
        if (c.variant == name) return &c;
    return nullptr;
}

TEST(Recommend, BudgetParses) {
    const recommend_budget d = parse_budget("max-ulp=4,max-wrong=0");
    EXPECT_EQ(d.max_ulp, 4);
    EXPECT_EQ(d.max_wrong, 0u);
    EXPECT_EQ(parse_budget("max-wrong=3").max_wrong, 3u);
    EXPECT_EQ(parse_budget("max-ulp=0.5").max_ulp, 0.5);
    for (const char* bad : {"", "max-ulp", "max-ulp=", "max-ulp=x", "max-ulp=4x", "max-ulp=-1", "max-wrong=-2",
                            "speed=3", "max-ulp=inf", "max-ulp=4,max-ulp=8"}) {
        try {
            parse_budget(bad);
            ADD_FAILURE() << "accepted '" << bad << "'";
        } catch (const input_error& e) {
            EXPECT_NE(std::string(e.what()).find("--budget"), std::string::npos) << e.what();
        }
    }
    try {
        parse_budget("max-wrong=1,max-ulp=2,max-wrong=3");
        ADD_FAILURE() << "accepted a key given twice";
    } catch (const input_error& e) {
        EXPECT_NE(std::string(e.what()).find("'max-wrong=3': the key is given twice"), std::string::npos) << e.what();
    }
}

TEST(Recommend, FarSpheresInFloatRejectNaive) {
    const recommendation r = decide(far_spheres);
    ASSERT_EQ(r.kinds.size(), 1u);
    const kind_recommendation& k = r.kinds[0];
    EXPECT_EQ(k.kind, ray_kind::primary);
    ASSERT_TRUE(k.winner);
    const recommend_candidate& w = k.candidates[*k.winner];
    EXPECT_TRUE(w.meets_budget);
    EXPECT_EQ(w.wrong, 0u);
    ASSERT_TRUE(w.max_ulp);
    EXPECT_LE(*w.max_ulp, 4);
    // No wrong ray allowed: the winner is the variant that decides exactly by construction, and the runner-up
    // the cheapest other one within the budget on these rays.
    EXPECT_EQ(w.variant.rfind("robust", 0), 0u) << w.variant;  // robust or robust_nearest, whichever is cheaper
    EXPECT_TRUE(w.exact_decisions);
    ASSERT_TRUE(k.runner_up);
    EXPECT_TRUE(k.candidates[*k.runner_up].meets_budget);
    EXPECT_FALSE(k.candidates[*k.runner_up].exact_decisions);
    for (std::size_t i = 0; i < *k.runner_up; ++i)
        EXPECT_TRUE(i == *k.winner || !k.candidates[i].meets_budget) << k.candidates[i].variant;
    const recommend_candidate* naive = find(k, "naive");
    ASSERT_TRUE(naive);
    EXPECT_FALSE(naive->meets_budget);
    EXPECT_GT(naive->wrong, 0u);
    EXPECT_NE(naive->verdict.find("wrong ray"), std::string::npos) << naive->verdict;
    const recommend_candidate* any = find(k, "hearn_baker_any_hit");
    ASSERT_TRUE(any);
    ASSERT_TRUE(any->not_applicable);
    EXPECT_NE(any->not_applicable->find("only any_hit"), std::string::npos);
    for (const recommend_candidate& c : k.candidates)
        if (!c.not_applicable) {
            EXPECT_EQ(c.rays, 24u * 12u) << c.variant;
            EXPECT_GT(c.ns_per_ray, 0) << c.variant;
        }
}

TEST(Recommend, WithWrongRaysAllowedTheCheapestWithinTheBudgetWins) {
    const recommendation r = decide(far_spheres, parse_budget("max-ulp=4,max-wrong=1000"));
    const kind_recommendation& k = r.kinds[0];
    ASSERT_TRUE(k.winner);
    // Candidates are sorted by time: nothing before the winner meets the budget, the runner-up is not cheaper.
    for (std::size_t i = 0; i < *k.winner; ++i) EXPECT_FALSE(k.candidates[i].meets_budget) << k.candidates[i].variant;
    if (k.runner_up) {
        EXPECT_GE(k.candidates[*k.runner_up].ns_per_ray, k.candidates[*k.winner].ns_per_ray);
    }
}

TEST(Recommend, ShadowRaysAreDecidedApartAndAdmitAnyHitVariants) {
    const recommendation r = decide(lamp);
    ASSERT_EQ(r.kinds.size(), 2u);
    EXPECT_EQ(r.kinds[1].kind, ray_kind::shadow);
    const recommend_candidate* any = find(r.kinds[1], "hearn_baker_any_hit");
    ASSERT_TRUE(any);
    EXPECT_FALSE(any->not_applicable);
    EXPECT_FALSE(any->max_ulp);  // any_hit takes no root error
    const recommend_candidate* unit = find(r.kinds[1], "hearn_baker_unit_any_hit");
    ASSERT_TRUE(unit);
    ASSERT_TRUE(unit->not_applicable);  // directions not normalised
    EXPECT_NE(unit->not_applicable->find("not normalised"), std::string::npos);
    EXPECT_TRUE(find(r.kinds[0], "hearn_baker_any_hit")->not_applicable);  // primary rays need the root
}

TEST(Recommend, ImpossibleBudgetFindsNoWinner) {
    const recommendation r = decide(far_spheres, parse_budget("max-ulp=0"));
    // Some agreeing ray has a nonzero root error for every variant, so none fits.
    EXPECT_FALSE(r.all_met());
    EXPECT_FALSE(r.kinds[0].winner);
}

TEST(RecommendCli, PrintsTheDecisionAndExitsOneWhenNothingFits) {
    const test_support::scratch_directory dir_scratch("rayverify_recommend_test");
    const std::filesystem::path& dir = dir_scratch.path();
    const std::filesystem::path file = dir / "far.json";
    { std::ofstream(file) << far_spheres; }
    const auto ok = run_cli("recommend --scene " + file.string() + " --repetitions 2 --min-time 0.001");
    EXPECT_EQ(ok.exit_code, 0) << ok.output;
    EXPECT_NE(ok.output.find("recommended for primary rays: robust"), std::string::npos) << ok.output;
    EXPECT_NE(ok.output.find("exact for every input"), std::string::npos) << ok.output;
    EXPECT_NE(ok.output.find("runner-up"), std::string::npos) << ok.output;
    const auto none = run_cli("recommend --scene " + file.string() + " --variant naive --repetitions 2 --min-time 0.001");
    EXPECT_EQ(none.exit_code, 1) << none.output;
    EXPECT_NE(none.output.find("no variant meets the budget"), std::string::npos) << none.output;
    const auto bad = run_cli("recommend --scene " + file.string() + " --budget max-ulp=banana");
    EXPECT_EQ(bad.exit_code, 2) << bad.output;
    EXPECT_NE(bad.output.find("--budget"), std::string::npos) << bad.output;
}

}  // namespace
}  // namespace rayverify::bench
