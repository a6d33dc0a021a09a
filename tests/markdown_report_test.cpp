// report.md and --summary-md: the headline first, a compact table, big tables
// folded, images that resolve; and the plots drawn for them.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <regex>

#include "report/markdown_report.h"
#include "support/process.h"

namespace rayverify {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;
using test_support::read_text;
using test_support::run_cli;

json result(const std::string& variant, const std::string& precision, std::size_t wrong, double max_ulp) {
    json verdicts = {{"agree", 100 - wrong}, {"false_hit", wrong}, {"contract_violation", 0}, {"invalid", 0}};
    return {{"variant", variant},
            {"precision", precision},
            {"cases", 100},
            {"disagreements", wrong},
            {"verdicts", verdicts},
            {"near_root_ulp", {{"count", 100 - wrong}, {"max", max_ulp}, {"p99", max_ulp}, {"median", 0.25}}}};
}

json small_report(std::size_t wrong) {
    return {{"tool", "rayverify audit"},
            {"build", {{"rayverify_version", "0.1.0"}, {"compiler", "GNU 12.2.0"}, {"build_type", "Release"},
                       {"flags", "-O2"}}},
            {"command", "rayverify audit --corpus c.txt"},
            {"corpus", {{"cases", 100}, {"cases_by_family", {{"uniform", 100}}}}},
            {"results", {result("naive", "float", wrong, 3.5), result("naive", "double", 0, 0.5)}},
            {"plots", {{"rendered", true}, {"message", "2 plots"}, {"files", {"far_sphere.png", "ulp_histograms.png"}}}}};
}

TEST(MarkdownReport, HeadlineFirstThenCompactTableThenFoldedDetails) {
    const std::string md = render_markdown(small_report(7));
    EXPECT_EQ(md.substr(0, md.find('\n')),
              "## rayverify audit: findings — 1 of 2 targets answer some of the 100 cases wrong");
    EXPECT_NE(md.find("| variant | wrong, float | max ulp, float | wrong, double | max ulp, double |"), std::string::npos);
    EXPECT_NE(md.find("| naive | 7 (7.0%) | 3.5 | 0 (0.0%) | 0.5 |"), std::string::npos) << md;
    // The table of every target is folded; so is how the report was made.
    const std::size_t details = md.find("<details><summary>Accuracy: every target</summary>");
    ASSERT_NE(details, std::string::npos);
    EXPECT_LT(md.find("| naive | 7 (7.0%)"), details) << "the compact table comes before the folded ones";
    EXPECT_NE(md.find("<details><summary>How this report was made</summary>"), std::string::npos);
    EXPECT_NE(md.find("- corpus: 100 cases (uniform 100)"), std::string::npos);
    // Every image is a file the plot step wrote, with a title for alt text.
    EXPECT_NE(md.find("![Far spheres: error and misclassification by distance/radius](far_sphere.png)"),
              std::string::npos);
    EXPECT_EQ(std::count(md.begin(), md.end(), '!'), 2) << md;
}

TEST(MarkdownReport, NoDisagreementHeadlineAndSummaryIsTheTopOfTheReport) {
    const json report = small_report(0);
    const std::string md = render_markdown(report), summary = render_summary_markdown(report);
    EXPECT_TRUE(summary.starts_with(
        "## rayverify audit: no disagreement — all 2 targets agree with the exact answer on all 100 cases\n"));
    EXPECT_TRUE(md.starts_with(summary)) << "--summary-md writes the top of report.md";
    EXPECT_EQ(summary.find("<details>"), std::string::npos);
    EXPECT_EQ(summary.find("!["), std::string::npos);
}

TEST(MarkdownReport, SummaryMdFromTheCommandMatchesReportAndIsAllOrNothing) {
    const test_support::scratch_directory dir_scratch("rayverify_markdown_report_test");
    const fs::path& dir = dir_scratch.path();
    const std::string corpus = std::string(RAYVERIFY_CORPUS_DIR) + "/far_sphere.txt";
    const auto run = run_cli("audit --corpus " + corpus + " --variant hearn_baker_any_hit --plots --report " +
                             (dir / "rep").string() + " --summary-md " + (dir / "step.md").string());
    ASSERT_EQ(run.exit_code, 1) << run.output;
    const std::string md = read_text(dir / "rep" / "report.md"), step = read_text(dir / "step.md");
    ASSERT_FALSE(step.empty());
    EXPECT_TRUE(md.starts_with(step));
    // An any-hit variant returns no root: no empty panels, so no histogram or condition plot at all;
    // the far-sphere plot has misclassification to show. Every image report.md names exists.
    EXPECT_FALSE(fs::exists(dir / "rep" / "ulp_histograms.png"));
    EXPECT_FALSE(fs::exists(dir / "rep" / "error_vs_condition.png"));
    const std::regex image(R"(!\[[^\]]*\]\(([^)]+)\))");
    std::size_t images = 0;
    for (auto it = std::sregex_iterator(md.begin(), md.end(), image); it != std::sregex_iterator(); ++it, ++images)
        EXPECT_TRUE(fs::exists(dir / "rep" / (*it)[1].str())) << (*it)[1].str();
    EXPECT_EQ(images, 1u) << md;
    // A bad corpus leaves no step summary behind.
    const auto bad = run_cli("audit --corpus " + (dir / "missing.txt").string() + " --summary-md " +
                             (dir / "bad.md").string());
    EXPECT_EQ(bad.exit_code, 2);
    EXPECT_FALSE(fs::exists(dir / "bad.md"));
}

}  // namespace
}  // namespace rayverify
