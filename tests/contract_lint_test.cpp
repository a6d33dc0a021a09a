// The contract lint: a target whose answers fit another contract than the one
// it declares gets one hint naming that contract and how many verdicts it
// would change, checked by judging the answers again; a target whose answers
// fit its own contract gets none.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>

#include "compare/audit.h"
#include "compare/contract_lint.h"
#include "corpus/corpus_io.h"
#include "oracle/oracle.h"
#include "plugin/plugin_loader.h"
#include "support/process.h"

namespace rayverify {
namespace {

namespace fs = std::filesystem;
using namespace test_support;

TEST(ContractLint, LineRootsCandidatesStartWithTheNearestRootInTheGivenInterval) {
    const std::vector<lint_candidate> candidates = lint_candidates(contract{});
    ASSERT_FALSE(candidates.empty());
    EXPECT_EQ(candidates.front().promises.query, query_kind::nearest_hit);
    EXPECT_EQ(candidates.front().promises.range, range_source::interval);
    EXPECT_EQ(version1_query_name(candidates.front().promises), "RAYVERIFY_NEAREST_IN_INTERVAL");
    for (const lint_candidate& c : candidates) {
        EXPECT_NE(format_contract(c.promises), format_contract(contract{})) << "the declared contract is no candidate";
        EXPECT_FALSE(contract_problem(c.promises)) << format_contract(c.promises);
    }
}

TEST(ContractLint, AHintNeedsHalfTheDisagreementsFixedAndFewBroken) {
    const std::vector<lint_candidate> candidates = lint_candidates(contract{});
    contract_lint_tally tally;
    tally.scored = 100;
    tally.wrong = 40;
    tally.fixed.assign(candidates.size(), 0);
    tally.broken.assign(candidates.size(), 0);
    EXPECT_FALSE(strongest_hint(candidates, tally));
    tally.fixed[1] = 19;  // fewer than half of 40
    EXPECT_FALSE(strongest_hint(candidates, tally));
    tally.fixed[1] = 20;
    tally.broken[1] = 5;  // not more than four times as many fixed as broken
    EXPECT_FALSE(strongest_hint(candidates, tally));
    tally.broken[1] = 4;
    ASSERT_TRUE(strongest_hint(candidates, tally));
    EXPECT_EQ(strongest_hint(candidates, tally)->fixed, 20u);
    tally.fixed[0] = 20;  // 20 − 4 ties 20 − 4: the earlier candidate wins
    tally.broken[0] = 4;
    EXPECT_EQ(format_contract(strongest_hint(candidates, tally)->candidate.promises),
              format_contract(candidates[0].promises));
    // A candidate that judges only a count is suggested only when none that judges t fits.
    const std::size_t any = candidates.size() - 1;
    ASSERT_FALSE(candidates[any].judges_t);
    tally.fixed[any] = 40;
    EXPECT_EQ(strongest_hint(candidates, tally)->candidate.promises.query, query_kind::nearest_hit);
    tally.fixed[0] = tally.fixed[1] = 0;
    EXPECT_EQ(strongest_hint(candidates, tally)->candidate.promises.query, query_kind::any_hit);
}

// A target declared to answer t beside a hit point whose points are right and
// whose t is not (here twice t*, as a t measured along a direction of half the
// length would be) gets the point-answer hint; without a hit point there is no
// such candidate to judge.
TEST(ContractLint, RightPointsBesideWrongTGetThePointAnswerHint) {
    const contract declared = parse_contract("query=nearest_hit,range=ray,hit_point=yes");
    const std::vector<lint_candidate> candidates = lint_candidates(declared);
    const auto point_answer = std::find_if(candidates.begin(), candidates.end(), [](const lint_candidate& c) {
        return c.promises.answer == answer_kind::point;
    });
    ASSERT_NE(point_answer, candidates.end());
    EXPECT_FALSE(contract_problem(point_answer->promises)) << format_contract(point_answer->promises);
    for (const lint_candidate& c : lint_candidates(parse_contract("query=nearest_hit,range=ray")))
        EXPECT_EQ(c.promises.answer, answer_kind::t) << "no hit point, no point answer to judge";

    const std::vector<corpus_case> cases = read_corpus({fs::path(RAYVERIFY_CORPUS_DIR) / "uniform.txt"});
    const t_range range = range_of(declared, std::nullopt, std::nullopt);
    contract_lint_tally tally;
    std::size_t hits = 0;
    for (const corpus_case& c : cases) {
        const exact_solution exact = solve_exact(c.geometry, precision::binary64);
        if (!exact.valid()) continue;
        variant_output output;
        if (exact.nearest_in_front) {
            const double t = 2 * exact.root(*exact.nearest_in_front).rounded;
            output.roots = {1, t, t};
            output.hit_root = 0;
            output.hit_point = exact.hit_point();
            ++hits;
        }
        const case_score score = judge_output(declared, output, exact, range, c.geometry);
        lint_case(declared, candidates, score, output, exact, range, c.geometry, tally);
    }
    ASSERT_GT(hits, 100u);
    EXPECT_GE(tally.wrong, hits * 9 / 10) << "twice t* is a wrong root or a false miss";
    const std::optional<contract_hint> hint = strongest_hint(candidates, tally);
    ASSERT_TRUE(hint);
    EXPECT_EQ(hint->candidate.promises.answer, answer_kind::point) << format_contract(hint->candidate.promises);
    EXPECT_EQ(hint->fixed, hint->wrong) << "every right point agrees under answer=point";
    EXPECT_EQ(hint->broken, 0u);
}

// The README's quick start with the code a path tracer has: the "Ray Tracing
// in One Weekend" sphere pasted into the line-roots template.
TEST(ContractLint, RtiowPastedIntoTheLineRootsTemplateGetsTheNearestInIntervalHint) {
    const scratch_directory scratch("rayverify_contract_lint");
    const fs::path& dir = scratch.path();
    const command_result audit = run_cli(std::string("audit --plugin ") + RAYVERIFY_FIXTURE_RTIOW_LINE_ROOTS +
                                         " --report " + (dir / "out").string());
    EXPECT_EQ(audit.exit_code, 1) << audit.output;
    EXPECT_NE(audit.output.find("hint: rtiow_pasted/double answers as another contract would: one root, the nearest "
                                "in the interval it was given, where the line has two."),
              std::string::npos)
        << audit.output;
    EXPECT_NE(audit.output.find("fits:      query=nearest_hit,range=interval"), std::string::npos) << audit.output;
    EXPECT_NE(audit.output.find("(RAYVERIFY_NEAREST_IN_INTERVAL in rayverify_plugin.h)"), std::string::npos)
        << audit.output;
    const std::string report = read_text(dir / "out" / "report.md");
    EXPECT_NE(report.find("### The contract"), std::string::npos) << report;
    EXPECT_NE(report.find("RAYVERIFY_NEAREST_IN_INTERVAL"), std::string::npos) << report;

    // The counts are what the suggested contract would make of the same answers.
    const std::vector<corpus_case> cases = read_corpus({RAYVERIFY_CORPUS_DIR});
    const std::vector<audit_target> targets = targets_for(std::vector<variant>{load_plugin(RAYVERIFY_FIXTURE_RTIOW_LINE_ROOTS)});
    contract_lint_accumulator lint(targets);
    const audit_totals totals = run_audit(cases, targets, [&](const audited_case& c) { lint.add(c); });
    const std::optional<contract_hint> hint = lint.hints().at(0);
    ASSERT_TRUE(hint);
    EXPECT_EQ(hint->wrong, totals.overall[0].disagreements());
    EXPECT_GT(hint->fixed, totals.overall[0].verdicts[static_cast<int>(verdict_kind::false_tangent)] / 2);
    EXPECT_NE(audit.output.find(fmt::format("{} of its {} disagreements would agree", hint->fixed, hint->wrong)),
              std::string::npos)
        << audit.output;
}

// `variants --plugin` prints the contract as rayverify reads it, with its version 1 kind.
TEST(ContractLint, VariantsPrintsAPluginsParsedContract) {
    const command_result listed = run_cli(std::string("variants --plugin ") + RAYVERIFY_TEMPLATE_NEAREST_IN_INTERVAL);
    EXPECT_EQ(listed.exit_code, 0) << listed.output;
    EXPECT_NE(listed.output.find("rtiow_sphere\n"), std::string::npos) << listed.output;
    EXPECT_NE(listed.output.find("  contract:  query=nearest_hit,range=interval,ends=(),"), std::string::npos)
        << listed.output;
    EXPECT_NE(listed.output.find("  kind:      RAYVERIFY_NEAREST_IN_INTERVAL\n"), std::string::npos) << listed.output;
    EXPECT_EQ(listed.output.find("naive"), std::string::npos) << "only the plugin";
}

// The same code in the nearest-in-interval template, and the other templates,
// declare what they answer: no hint.
TEST(ContractLint, TemplatesThatDeclareTheirContractGetNoHint) {
    for (const char* plugin : {RAYVERIFY_TEMPLATE_NEAREST_IN_INTERVAL, RAYVERIFY_TEMPLATE_ANY_HIT,
                               RAYVERIFY_EXAMPLE_PLUGIN}) {
        const command_result audit = run_cli(std::string("audit --plugin ") + plugin);
        EXPECT_EQ(audit.output.find("hint:"), std::string::npos) << plugin << "\n" << audit.output;
        EXPECT_NE(audit.exit_code, 2) << audit.output;
    }
}

// A plugin that exports rayverify_plugin_thread_safe() returning nonzero is
// audited on every thread asked for, with the same figures; one without it
// (or isolated) on one thread, saying so.
TEST(ContractLint, APluginThatDeclaresThreadSafetyIsAuditedOnEveryThread) {
    const std::string safe = std::string(RAYVERIFY_TEMPLATE_NEAREST_IN_INTERVAL);
    EXPECT_TRUE(load_plugin(safe).thread_safe);
    EXPECT_FALSE(load_plugin(safe, plugin_isolation{true, 10}).thread_safe);
    EXPECT_FALSE(load_plugin(RAYVERIFY_EXAMPLE_PLUGIN).thread_safe);
    const command_result four = run_cli("audit --threads 4 --plugin " + safe);
    const command_result one = run_cli("audit --threads 1 --plugin " + safe);
    EXPECT_EQ(four.output.find("not thread-safe"), std::string::npos) << four.output;
    EXPECT_EQ(four.output, one.output);
    const command_result unsafe = run_cli(std::string("audit --threads 4 --plugin ") + RAYVERIFY_EXAMPLE_PLUGIN);
    EXPECT_NE(unsafe.output.find("a plugin is not thread-safe"), std::string::npos) << unsafe.output;
}

}  // namespace
}  // namespace rayverify
