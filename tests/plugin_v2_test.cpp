// Plugin ABI version 2: the examples (one per kind of contract) load with the
// contract their spec states and only the precisions they run in, are audited
// on the shipped corpus in process and isolated alike (batch calls, the same
// figures), their outputs beside t are checked; a bound that is too tight is
// unsound_bound; a contract that cannot be used is an input error naming the
// plugin; version 1 keeps loading.
#include <gtest/gtest.h>

#include <algorithm>

#include "compare/audit.h"
#include "corpus/corpus_io.h"
#include "intersectors/registry.h"
#include "plugin/plugin_loader.h"
#include "support/process.h"

namespace rayverify {
namespace {

using namespace test_support;

const std::vector<corpus_case>& shipped_corpus() {
    static const std::vector<corpus_case> cases = read_corpus({RAYVERIFY_CORPUS_DIR});
    return cases;
}

std::string load_error(const std::string& library) {
    try {
        load_plugin(library);
    } catch (const input_error& e) {
        return e.what();
    }
    return "(loaded)";
}

std::size_t verdicts(const target_tally& t, verdict_kind k) { return t.verdicts[static_cast<int>(k)]; }

TEST(PluginV2, ExamplesStateTheirContractsAndPrecisions) {
    const variant nearest = load_plugin(RAYVERIFY_EXAMPLE_NEAREST_SPHERE);
    EXPECT_EQ(nearest.name, "nearest_sphere");
    EXPECT_EQ(format_contract(nearest.promises),
              "query=nearest_hit,range=interval,ends=[],inside=far_root,tangent=hit,faces=both,unit_direction=no,"
              "normal=yes");
    EXPECT_TRUE(nearest.runs_in(precision::binary32) && nearest.runs_in(precision::binary64));
    EXPECT_EQ(nearest.build, "plain C, no FMA contraction");

    const variant shadow = load_plugin(RAYVERIFY_EXAMPLE_SHADOW_SPHERE);
    EXPECT_EQ(shadow.promises.query, query_kind::any_hit);
    EXPECT_EQ(shadow.promises.range, range_source::tmax_only);
    EXPECT_TRUE(shadow.runs_in(precision::binary32));
    EXPECT_FALSE(shadow.runs_in(precision::binary64)) << "a float-only plugin has no double function";

    const variant point = load_plugin(RAYVERIFY_EXAMPLE_POINT_SPHERE);
    EXPECT_EQ(point.promises.answer, answer_kind::point);
    EXPECT_TRUE(point.promises.assumes_unit_direction);
    EXPECT_FALSE(point.runs_in(precision::binary32));
    // The answer is a point; its t is derived from it: 4 for the unit sphere seen from z = −5.
    const root_pair<double> r = point.run_double({{0, 0, -5}, {0, 0, 1}, {0, 0, 0}, 1});
    EXPECT_EQ(r.count, 1);
    EXPECT_EQ(r.t0, 4);

    const variant bounds = load_plugin(RAYVERIFY_EXAMPLE_BOUNDS_SPHERE);
    EXPECT_TRUE(bounds.promises.outputs.t_bounds);
    EXPECT_EQ(bounds.promises.outputs.point_error, point_bound::hit);
    const answer<double> a = answer_in(bounds, ray_sphere<double>{{0, 0, -5}, {0, 0, 1}, {0, 0, 0}, 1},
                                       ray_interval<double>{0, 100});
    ASSERT_EQ(a.roots.count, 1);
    EXPECT_LE(a.t_lower[0], 4);
    EXPECT_GE(a.t_upper[0], 4);
    EXPECT_LT(a.t_upper[0] - a.t_lower[0], 1e-12);
}

TEST(PluginV2, FloatOnlyPluginGetsFloatRowsOnly) {
    const variant shadow = load_plugin(RAYVERIFY_EXAMPLE_SHADOW_SPHERE);
    const std::vector<audit_target> targets = targets_for(std::span<const variant>(&shadow, 1));
    ASSERT_EQ(targets.size(), 1u);
    EXPECT_EQ(targets[0].prec, precision::binary32);

    const std::filesystem::path corpus = std::filesystem::path(RAYVERIFY_CORPUS_DIR) / "uniform.txt";
    const command_result audit =
        run_cli("audit --plugin " + std::string(RAYVERIFY_EXAMPLE_SHADOW_SPHERE) + " --corpus " + corpus.string());
    EXPECT_NE(audit.output.find("shadow_sphere float"), std::string::npos) << audit.output;
    EXPECT_EQ(audit.output.find("shadow_sphere double"), std::string::npos) << audit.output;
}

// hunt works the precision out as audit does: a float-only plugin is hunted in
// float without --precision, and --precision double on it is an input error
// that writes no file.
TEST(PluginV2, FloatOnlyPluginIsHuntedInFloatWithoutPrecision) {
    const scratch_directory scratch("rayverify_hunt_float_only");
    const std::string hunt = "hunt --plugin " + std::string(RAYVERIFY_EXAMPLE_SHADOW_SPHERE) +
                             " --objective misclass --seconds 0 --evaluations 300 --finds 1 -o ";
    const std::filesystem::path worked_out = scratch.path() / "worked_out.txt";
    const command_result found = run_cli(hunt + worked_out.string());
    EXPECT_LE(found.exit_code, 1) << found.output;
    EXPECT_TRUE(found.output.starts_with("hunt shadow_sphere/float ")) << found.output;
    EXPECT_TRUE(std::filesystem::exists(worked_out));

    const std::filesystem::path in_double = scratch.path() / "in_double.txt";
    const command_result refused = run_cli(hunt + in_double.string() + " --precision double");
    EXPECT_EQ(refused.exit_code, 2) << refused.output;
    EXPECT_NE(refused.output.find("field '--precision'"), std::string::npos) << refused.output;
    EXPECT_NE(refused.output.find("does not run in double"), std::string::npos) << refused.output;
    EXPECT_FALSE(std::filesystem::exists(in_double));
}

// Every example on the shipped corpus: its outputs beside t are checked, its
// bounds are sound, and the isolated run (batches over a socket) gives the
// same figures as the run in process.
TEST(PluginV2, ExamplesAuditedInProcessAndIsolatedAlike) {
    for (const char* library : {RAYVERIFY_EXAMPLE_NEAREST_SPHERE, RAYVERIFY_EXAMPLE_SHADOW_SPHERE,
                                RAYVERIFY_EXAMPLE_POINT_SPHERE, RAYVERIFY_EXAMPLE_BOUNDS_SPHERE}) {
        const variant in_process = load_plugin(library);
        const variant isolated = load_plugin(library, plugin_isolation{true, 30});
        const audit_totals a = run_audit(shipped_corpus(), targets_for(std::span<const variant>(&in_process, 1)));
        const audit_totals b = run_audit(shipped_corpus(), targets_for(std::span<const variant>(&isolated, 1)));
        ASSERT_EQ(a.targets.size(), b.targets.size()) << library;
        for (std::size_t t = 0; t < a.targets.size(); ++t) {
            const std::string label = a.targets[t].label();
            EXPECT_EQ(a.overall[t].verdicts, b.overall[t].verdicts) << label;
            EXPECT_EQ(a.overall[t].errors[rayverify::error_figure::near_root_ulp].max, b.overall[t].errors[rayverify::error_figure::near_root_ulp].max) << label;
            EXPECT_EQ(a.overall[t].errors[rayverify::error_figure::hit_point_ulp].max, b.overall[t].errors[rayverify::error_figure::hit_point_ulp].max) << label;
            EXPECT_EQ(a.overall[t].errors[rayverify::error_figure::bound_width_ulp].max, b.overall[t].errors[rayverify::error_figure::bound_width_ulp].max) << label;
            EXPECT_EQ(verdicts(a.overall[t], verdict_kind::malformed_output), 0u) << label;
            EXPECT_GT(verdicts(a.overall[t], verdict_kind::agree), a.overall[t].cases / 2) << label;
        }
    }
}

// bench's timed pass of a version 2 plugin is one call of its batch function
// on every case, each asked on the interval its plain calls are: the same
// answers as those calls, summed, in each precision it has. The isolated
// plugin has none (its calls cross a socket; bench times them as they are).
TEST(PluginV2, TimedPassIsOneBatchOfThePlainCalls) {
    for (const char* library : {RAYVERIFY_EXAMPLE_NEAREST_SPHERE, RAYVERIFY_EXAMPLE_SHADOW_SPHERE,
                                RAYVERIFY_EXAMPLE_POINT_SPHERE, RAYVERIFY_EXAMPLE_BOUNDS_SPHERE}) {
        const variant v = load_plugin(library);
        for (const precision p : every_precision) with_precision(p, [&]<class T>(std::type_identity<T>) {
            const auto& timed_pass = [&]() -> const timed_pass_fn<T>& {
                if constexpr (std::is_same_v<T, float>) return v.timed_pass_float; else return v.timed_pass_double;
            }();
            ASSERT_EQ(static_cast<bool>(timed_pass), v.runs_in(p)) << library;
            if (!timed_pass) return;
            std::vector<ray_sphere<T>> cases;
            long long expected = 0;
            for (const corpus_case& c : shipped_corpus()) {
                cases.push_back(rounded_to<T>(c.geometry));
                expected += run_in(v, cases.back(), ray_interval<T>{}).count;
            }
            EXPECT_EQ(timed_pass(cases)(), expected) << library;
        });
        EXPECT_FALSE(load_plugin(library, plugin_isolation{true, 30}).timed_pass_double) << library;
    }
}

TEST(PluginV2, OutputsBesideTAreMeasured) {
    const variant bounds = load_plugin(RAYVERIFY_EXAMPLE_BOUNDS_SPHERE);
    const variant nearest = load_plugin(RAYVERIFY_EXAMPLE_NEAREST_SPHERE);
    const variant point = load_plugin(RAYVERIFY_EXAMPLE_POINT_SPHERE);
    const std::vector<variant> plugins{bounds, nearest, point};
    const audit_totals totals = run_audit(shipped_corpus(), targets_for(plugins));
    for (std::size_t t = 0; t < totals.targets.size(); ++t) {
        const std::string& name = totals.targets[t].subject.name;
        const target_tally& tally = totals.overall[t];
        SCOPED_TRACE(totals.targets[t].label());
        if (name == "bounds_sphere") {
            // Intervals computed with outward rounding contain the exact roots and points.
            EXPECT_EQ(verdicts(tally, verdict_kind::unsound_bound), 0u);
            EXPECT_GT(tally.errors[rayverify::error_figure::bound_width_ulp].count, 0u);
            EXPECT_GE(tally.errors[rayverify::error_figure::bound_width_ulp].max, 1) << "an interval holds at least its two ends";
            EXPECT_GT(tally.errors[rayverify::error_figure::hit_point_ulp].count, 0u);
        }
        if (name == "nearest_sphere") {
            EXPECT_GT(tally.errors[rayverify::error_figure::normal_angle].count, 0u);
        }
        if (name == "point_sphere") {
            EXPECT_GT(tally.errors[rayverify::error_figure::hit_point_ulp].count, 0u);
        }
        EXPECT_GT(tally.errors[rayverify::error_figure::scale_error_radius].count, 0u);
    }
}

TEST(PluginV2, TooTightBoundIsUnsound) {
    const variant tight = load_plugin(RAYVERIFY_FIXTURE_V2_TIGHT_BOUND);
    const audit_totals totals = run_audit(shipped_corpus(), targets_for(std::span<const variant>(&tight, 1)));
    ASSERT_EQ(totals.targets.size(), 2u);
    for (std::size_t t = 0; t < 2; ++t) {
        const std::size_t unsound = verdicts(totals.overall[t], verdict_kind::unsound_bound);
        EXPECT_GT(unsound, 100u) << totals.targets[t].label();
        EXPECT_EQ(totals.overall[t].causes[static_cast<int>(disagreement_cause::algorithmic)] +
                      totals.overall[t].causes[static_cast<int>(disagreement_cause::conditioning_limited)],
                  totals.overall[t].disagreements())
            << "an unsound bound is the variant's rounding, never by design";
    }
    // One case by hand: the root 5 − √0.99 is irrational, so no [t, t] holds it.
    corpus_case c;
    c.id = "tight";
    c.geometry = {{0.1, 0, -5}, {0, 0, 1}, {0, 0, 0}, 1};
    const audit_target target{tight, precision::binary64};
    const target_outcome o = judge_target(target, c, solve_case(c, precision::binary64));
    EXPECT_EQ(o.score.verdict, verdict_kind::unsound_bound);
    EXPECT_NE(o.score.detail.find("leaves out the near root"), std::string::npos) << o.score.detail;
    // An exact root: [4, 4] holds 4, and the answer agrees.
    c.geometry = {{0, 0, -5}, {0, 0, 1}, {0, 0, 0}, 1};
    EXPECT_EQ(judge_target(target, c, solve_case(c, precision::binary64)).score.verdict, verdict_kind::agree);
}

TEST(PluginV2, UnusableDescriptionsAreInputErrors) {
    const std::string bad_contract = load_error(RAYVERIFY_FIXTURE_V2_BAD_CONTRACT);
    EXPECT_NE(bad_contract.find("query=sideways"), std::string::npos) << bad_contract;
    EXPECT_NE(bad_contract.find("line_roots, nearest_hit, any_hit"), std::string::npos) << bad_contract;
    const std::string no_precision = load_error(RAYVERIFY_FIXTURE_V2_NO_PRECISION);
    EXPECT_NE(no_precision.find("precisions = 0"), std::string::npos) << no_precision;
    // A misspelt describe_v2 is named as version 2's symbol, beside version 1's.
    const std::string misspelt = load_error(RAYVERIFY_FIXTURE_V2_MISSPELT);
    EXPECT_NE(misspelt.find("missing symbol rayverify_plugin_describe_v2: the library exports version 2's batch "
                            "functions"),
              std::string::npos)
        << misspelt;
    EXPECT_NE(misspelt.find("rayverify_plugin_describe)"), std::string::npos) << misspelt;
    // Version 1 keeps loading next to version 2.
    EXPECT_EQ(load_error(RAYVERIFY_EXAMPLE_PLUGIN), "(loaded)");
}

TEST(PluginV2, IsolatedBatchCrashIsAnInputErrorNamingTheBatch) {
    const variant crashy = load_plugin(RAYVERIFY_FIXTURE_V2_BATCH_CRASH, plugin_isolation{true, 10});
    std::vector<corpus_case> cases(3);
    for (std::size_t i = 0; i < cases.size(); ++i) {
        cases[i].id = "case" + std::to_string(i);
        cases[i].source = "memory";
        cases[i].geometry = {{0, 0, -9}, {0, 0, 1}, {0, 0, 0}, static_cast<double>(i + 1)};
    }
    try {
        run_audit(cases, targets_for(std::span<const variant>(&crashy, 1)));
        FAIL() << "the batch with a radius-3 case must crash the plugin";
    } catch (const plugin_failure& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("batch_crash"), std::string::npos) << what;
        EXPECT_NE(what.find("batch of 3 cases"), std::string::npos) << what;
        EXPECT_NE(what.find("SIGSEGV"), std::string::npos) << what;
    }
}

}  // namespace
}  // namespace rayverify
