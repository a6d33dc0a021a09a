// Failing cases you can open: the summary and report.md name the first cases
// of each verdict as corpus lines that explain takes back, `audit --failures`
// writes every failing case as a corpus (whole or not at all), and an
// agreeing answer far from the exact hit is counted and listed.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "compare/audit.h"
#include "compare/case_examples.h"
#include "corpus/corpus_io.h"
#include "corpus/generators.h"
#include "intersectors/registry.h"
#include "plugin/plugin_loader.h"
#include "support/process.h"

namespace rayverify {
namespace {

namespace fs = std::filesystem;
using namespace test_support;

TEST(CasesToOpen, FailuresFileHoldsEveryFailingCaseAndTheSummaryNamesTheFirst) {
    const scratch_directory scratch("rayverify_cases_to_open");
    const fs::path failures = scratch.path() / "failures.txt", report = scratch.path() / "out";
    const command_result audit = run_cli(std::string("audit --plugin ") + RAYVERIFY_FIXTURE_RTIOW_LINE_ROOTS +
                                         " --failures " + failures.string() + " --report " + report.string());
    ASSERT_EQ(audit.exit_code, 1) << audit.output;

    // The same audit in process: which cases disagree, and the first of each verdict.
    const std::vector<corpus_case> cases = read_corpus({RAYVERIFY_CORPUS_DIR});
    const std::vector<audit_target> targets =
        targets_for(std::vector<variant>{load_plugin(RAYVERIFY_FIXTURE_RTIOW_LINE_ROOTS)});
    std::vector<std::string> failing;
    case_examples examples(targets.size());
    std::size_t index = 0;
    run_audit(cases, targets, [&](const audited_case& c) {
        examples.add(c, index++, targets);
        if (is_disagreement(c.outcomes[0].score.verdict)) failing.push_back(c.source->id);
    });
    const std::vector<corpus_case> written = read_corpus_file(failures);
    ASSERT_EQ(written.size(), failing.size());
    for (std::size_t i = 0; i < written.size(); ++i) EXPECT_EQ(written[i].id, failing[i]) << i;

    const auto& first = examples.first[0][static_cast<int>(verdict_kind::false_miss)];
    ASSERT_FALSE(first.empty());
    const std::string line = format_case_line(first[0].kase);
    EXPECT_NE(audit.output.find("rtiow_pasted/double false_miss: " + first[0].kase.id), std::string::npos)
        << audit.output;
    EXPECT_NE(audit.output.find("    " + line + "\n"), std::string::npos) << audit.output;
    const std::string markdown = read_text(report / "report.md");
    EXPECT_NE(markdown.find("Cases to open"), std::string::npos);
    EXPECT_NE(markdown.find("`" + line + "`"), std::string::npos) << markdown;

    // The line is ready for explain: the same verdict comes back.
    const command_result explain =
        run_cli("explain \"" + line + "\" --plugin " + std::string(RAYVERIFY_FIXTURE_RTIOW_LINE_ROOTS));
    EXPECT_NE(explain.output.find("false_miss"), std::string::npos) << explain.output;
}

// The worst cases of a verdict by brute force: the largest of max(near_ulp,
// far_ulp), ties by index, at most case_examples::kept.
std::vector<std::size_t> worst_by_brute_force(const std::vector<std::pair<double, std::size_t>>& errors) {
    std::vector<std::pair<double, std::size_t>> sorted = errors;
    std::sort(sorted.begin(), sorted.end(), [](const auto& a, const auto& b) {
        return a.first != b.first ? a.first > b.first : a.second < b.second;
    });
    std::vector<std::size_t> indices;
    for (std::size_t i = 0; i < sorted.size() && i < case_examples::kept; ++i) indices.push_back(sorted[i].second);
    return indices;
}

std::vector<std::size_t> indices_of(const std::vector<case_example>& list) {
    std::vector<std::size_t> indices;
    for (const case_example& e : list) indices.push_back(e.index);
    return indices;
}

TEST(CasesToOpen, WorstCasesAreTheLargestRootErrorsWhateverTheShardsAndMergeOrder) {
    const std::vector<corpus_case> cases = read_corpus({RAYVERIFY_CORPUS_DIR});
    const std::vector<audit_target> targets = targets_for(std::vector<variant>{*find_builtin_variant("naive")});
    case_examples whole(targets.size());
    std::vector<case_examples> shards(3, case_examples(targets.size()));
    // [target][verdict]: every (root error in ULPs, index) of a disagreement with one.
    std::vector<std::array<std::vector<std::pair<double, std::size_t>>, verdict_kind_count>> errors(targets.size());
    std::size_t index = 0;
    run_audit(cases, targets, [&](const audited_case& c) {
        whole.add(c, index, targets);
        shards[index % shards.size()].add(c, index, targets);
        for (std::size_t t = 0; t < targets.size(); ++t) {
            const case_score& s = c.outcomes[t].score;
            if (is_disagreement(s.verdict) && (s.near_ulp || s.far_ulp))
                errors[t][static_cast<int>(s.verdict)].push_back(
                    {std::max(s.near_ulp.value_or(0), s.far_ulp.value_or(0)), index});
        }
        ++index;
    });
    case_examples forward(targets.size()), backward(targets.size());
    for (const case_examples& shard : shards) forward.merge(shard);
    for (auto shard = shards.rbegin(); shard != shards.rend(); ++shard) backward.merge(*shard);
    std::size_t verdicts_with_worst = 0;
    for (std::size_t t = 0; t < targets.size(); ++t)
        for (int k = 0; k < verdict_kind_count; ++k) {
            const std::vector<std::size_t> expected = worst_by_brute_force(errors[t][k]);
            verdicts_with_worst += !expected.empty();
            const std::string where = targets[t].label() + " " + std::string(verdict_name(static_cast<verdict_kind>(k)));
            EXPECT_EQ(indices_of(whole.worst[t][k]), expected) << where;
            EXPECT_EQ(indices_of(forward.worst[t][k]), expected) << where;
            EXPECT_EQ(indices_of(backward.worst[t][k]), expected) << where;
        }
    EXPECT_GE(verdicts_with_worst, 4u) << "naive's wrong roots, splits and sides on the shipped corpus";
    // A false miss has no t to measure: first cases, no worst.
    EXPECT_FALSE(whole.first[0][static_cast<int>(verdict_kind::false_miss)].empty());
    EXPECT_TRUE(whole.worst[0][static_cast<int>(verdict_kind::false_miss)].empty());
}

// The audit keeps an agreeing answer's scale error to its printed digits
// (bounds in one histogram bucket); the farthest list is still the cases
// with the largest exact figures at or above agree_far_fraction, ties by
// index, whatever the shards and the order they merge in.
TEST(CasesToOpen, FarthestAgreeingCasesAreTheLargestExactScaleErrorsWhateverTheShards) {
    std::vector<corpus_case> cases = generate_family("near_tangent", 1500, 21);
    for (corpus_case& c : generate_family("far_sphere", 1500, 22)) cases.push_back(std::move(c));
    const std::vector<audit_target> targets = targets_for(builtin_variants());
    case_examples whole(targets.size());
    std::vector<case_examples> shards(3, case_examples(targets.size()));
    // [target]: every (exact scale error in radii, index) at or above agree_far_fraction.
    std::vector<std::vector<std::pair<double, std::size_t>>> errors(targets.size());
    std::size_t index = 0, bounded_far = 0;
    run_audit(cases, targets, [&](const audited_case& c) {
        whole.add(c, index, targets);
        shards[index % shards.size()].add(c, index, targets);
        for (std::size_t t = 0; t < targets.size(); ++t) {
            const case_score& s = c.outcomes[t].score;
            if (s.verdict != verdict_kind::agree || !s.scale_error_radius) continue;
            const bool bounded = s.figure_upper_bounds && s.figure_upper_bounds->scale_error_radius != *s.scale_error_radius;
            const double exact =
                bounded ? exact_figures(targets[t], *c.source, c.outcomes[t], c.exact_for(targets[t].prec))
                              .scale_error_radius.value()
                        : *s.scale_error_radius;
            if (exact < agree_far_fraction) continue;
            bounded_far += bounded;
            errors[t].push_back({exact, index});
        }
        ++index;
    });
    case_examples forward(targets.size()), backward(targets.size());
    for (const case_examples& shard : shards) forward.merge(shard);
    for (auto shard = shards.rbegin(); shard != shards.rend(); ++shard) backward.merge(*shard);
    std::size_t targets_with_far = 0;
    for (std::size_t t = 0; t < targets.size(); ++t) {
        const std::vector<std::size_t> expected = worst_by_brute_force(errors[t]);
        targets_with_far += !expected.empty();
        const std::string where = targets[t].label();
        EXPECT_EQ(indices_of(whole.farthest[t]), expected) << where;
        EXPECT_EQ(indices_of(forward.farthest[t]), expected) << where;
        EXPECT_EQ(indices_of(backward.farthest[t]), expected) << where;
        for (const case_example& e : whole.farthest[t]) {
            const auto exact = std::find_if(errors[t].begin(), errors[t].end(),
                                            [&](const auto& error) { return error.second == e.index; });
            ASSERT_NE(exact, errors[t].end()) << where;
            EXPECT_EQ(e.error, exact->first) << where << " case " << e.index;
        }
    }
    EXPECT_GE(targets_with_far, 10u);
    EXPECT_GT(bounded_far, 100u) << "far agreeing figures kept to their printed digits";
}

TEST(CasesToOpen, TheSummaryAndReportNameTheWorstCaseWithItsCorpusLine) {
    const scratch_directory scratch("rayverify_cases_to_open_worst");
    const fs::path report = scratch.path() / "out";
    const command_result audit =
        run_cli("audit --variant naive --precision float --report " + report.string());
    ASSERT_EQ(audit.exit_code, 1) << audit.output;
    const std::string marker = "naive/float wrong_side, worst by root error: ";
    const std::size_t at = audit.output.find(marker);
    ASSERT_NE(at, std::string::npos) << audit.output;
    const std::string id = audit.output.substr(at + marker.size(), audit.output.find(' ', at + marker.size()) -
                                                                       (at + marker.size()));
    const std::size_t line_at = audit.output.find("\n    " + id + " ", at);
    ASSERT_NE(line_at, std::string::npos) << "the worst case's corpus line follows its ids\n" << audit.output;
    const std::string line = audit.output.substr(line_at + 5, audit.output.find('\n', line_at + 1) - line_at - 5);
    EXPECT_NE(read_text(report / "report.md").find("| naive/float | wrong_side, worst | " + id), std::string::npos);
    // The line explains back to the same verdict.
    const command_result explain = run_cli("explain \"" + line + "\" --variant naive --precision float");
    EXPECT_NE(explain.output.find("wrong_side"), std::string::npos) << explain.output;
}

TEST(CasesToOpen, AFailedAuditLeavesNoFailuresFile) {
    const scratch_directory scratch("rayverify_cases_to_open");
    const fs::path failures = scratch.path() / "failures.txt";
    const command_result audit =
        run_cli("audit --plugin ./no_such_plugin.so --failures " + failures.string());
    EXPECT_EQ(audit.exit_code, 2) << audit.output;
    EXPECT_FALSE(fs::exists(failures));
}

TEST(CasesToOpen, FarAgreementsAreCountedFromTheExactHistogram) {
    error_summary s;
    s.add(0x1p-11, 0, "a");
    s.add(0x1p-10, 1, "b");  // exactly the line: counted
    s.add(6.66, 2, "c");
    s.add(std::numeric_limits<double>::infinity(), 3, "d");
    EXPECT_EQ(s.count_at_least(agree_far_fraction), 3u);
    EXPECT_EQ(s.count_at_least(8), 1u);
}

}  // namespace
}  // namespace rayverify
