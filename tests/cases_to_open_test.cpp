// Failing cases you can open: the summary and report.md name the first cases
// of each verdict as corpus lines that explain takes back, `audit --failures`
// writes every failing case as a corpus (whole or not at all), and an
// agreeing answer far from the exact hit is counted and listed.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "compare/audit.h"
#include "compare/case_examples.h"
#include "corpus/corpus_io.h"
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
        examples.add(c, index++);
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
