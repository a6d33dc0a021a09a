// The compact audit summary (`rayverify audit --summary`): families by name,
// each line's best and worst member, hand-built tallies.
#include <gtest/gtest.h>

#include <sstream>

#include "report/audit_summary.h"
#include "support/process.h"

namespace rayverify {
namespace {

TEST(AuditSummary, FamilyIsTheShortestAuditedNameExtendedWithUnderscore) {
    const std::vector<std::string> names = {"hearn_baker", "hearn_baker_unit", "hearn_baker_unit_nearest", "half_b",
                                            "naive", "naiveish", "mine"};
    EXPECT_EQ(variant_family("hearn_baker_unit_nearest", names), "hearn_baker");
    EXPECT_EQ(variant_family("hearn_baker_unit", names), "hearn_baker");
    EXPECT_EQ(variant_family("hearn_baker", names), "hearn_baker");
    EXPECT_EQ(variant_family("naiveish", names), "naiveish");  // a prefix without '_' is another family
    EXPECT_EQ(variant_family("half_b", names), "half_b");      // "half" is not audited
    // Without the base variant, each specialisation is a family of its own.
    EXPECT_EQ(variant_family("hearn_baker_unit_nearest", {"hearn_baker_unit_nearest"}), "hearn_baker_unit_nearest");
}

audit_target target(const std::string& name, precision p) {
    audit_target t;
    t.subject.name = name;
    t.prec = p;
    return t;
}

target_tally tally(std::size_t cases, std::size_t false_hit, std::size_t contract, double max_ulp) {
    target_tally t;
    t.cases = cases;
    t.verdicts[static_cast<int>(verdict_kind::false_hit)] = false_hit;
    t.verdicts[static_cast<int>(verdict_kind::contract_violation)] = contract;
    t.verdicts[static_cast<int>(verdict_kind::agree)] = cases - false_hit - contract;
    if (max_ulp >= 0) {
        t.errors[rayverify::error_figure::near_root_ulp].count = 1;
        t.errors[rayverify::error_figure::near_root_ulp].max = max_ulp;
    }
    return t;
}

TEST(AuditSummary, OneLinePerFamilyNamingItsBestAndWorstMember) {
    audit_totals totals;
    totals.cases = 100;
    totals.targets = {target("base", precision::binary32), target("base", precision::binary64),
                      target("base_fast", precision::binary64), target("other", precision::binary64)};
    // base: 10 + 20 wrong of 200; base_fast: 1 wrong of the 50 it is scored on (50 break its contract).
    totals.overall = {tally(100, 10, 0, 3.5), tally(100, 20, 0, 1e15), tally(100, 1, 50, -1), tally(100, 0, 0, 0.5)};
    const std::string text = render_family_summary(totals);
    SCOPED_TRACE(text);
    // Header, two families, two lines of notes.
    EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 5);
    const std::size_t base_line = text.find("\nbase ");
    ASSERT_NE(base_line, std::string::npos);
    const std::string base = text.substr(base_line + 1, text.find('\n', base_line + 1) - base_line - 1);
    EXPECT_NE(base.find(" 2 "), std::string::npos) << "two variants";
    EXPECT_NE(base.find("base_fast"), std::string::npos) << "fewest wrong: 1 of 50 (2%) beats 30 of 200 (15%)";
    EXPECT_NE(base.find("  2%"), std::string::npos) << "its double share";
    EXPECT_NE(base.find("false_hit 1"), std::string::npos);
    EXPECT_NE(base.find("base 15%"), std::string::npos) << "the worst member, both precisions";
    const std::size_t other_line = text.find("\nother ");
    ASSERT_NE(other_line, std::string::npos);
    const std::string other = text.substr(other_line + 1, text.find('\n', other_line + 1) - other_line - 1);
    EXPECT_NE(other.find(" 0 "), std::string::npos) << "no wrong answer";
    EXPECT_NE(other.find("0.5"), std::string::npos);
    EXPECT_EQ(other.back(), '5') << "no worst member and no trailing blanks for a family of one";
    EXPECT_NE(text.find("100 cases, 3 variants in 2 families"), std::string::npos);
}

TEST(AuditSummary, CommandPrintsTheSummaryAndWritesTheSameReport) {
    namespace fs = std::filesystem;
    const test_support::scratch_directory dir_scratch("rayverify_audit_summary_test");
    const fs::path& dir = dir_scratch.path();
    const std::string corpus = std::string(RAYVERIFY_CORPUS_DIR) + "/far_sphere.txt";
    const auto full = test_support::run_cli("audit --corpus " + corpus + " --report " + (dir / "a").string());
    const auto brief = test_support::run_cli("audit --summary --corpus " + corpus + " --report " + (dir / "b").string());
    EXPECT_EQ(brief.exit_code, full.exit_code);
    EXPECT_EQ(brief.exit_code, 1) << brief.output;
    const std::size_t hearn_baker = brief.output.find("\nhearn_baker ");
    ASSERT_NE(hearn_baker, std::string::npos) << brief.output;
    std::istringstream row(brief.output.substr(hearn_baker + 1));
    std::string family, members;
    row >> family >> members;
    EXPECT_EQ(members, "6") << brief.output;
    EXPECT_EQ(brief.output.find("med_ulp"), std::string::npos) << "not the full table";
    EXPECT_EQ(test_support::read_text(dir / "a" / "report.json"), test_support::read_text(dir / "b" / "report.json"))
        << "--summary changes what is printed, not the report";
}

}  // namespace
}  // namespace rayverify
