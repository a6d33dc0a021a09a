// The gate: baseline text round trip (comments kept across --update), the
// comparison under a policy, JUnit and diff, the CLI, our own committed
// baseline, and the issue's end-to-end story with a user's plugin.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "compare/gate.h"
#include "core/contract.h"
#include "corpus/corpus_io.h"
#include "report/gate_report.h"
#include "support/process.h"

namespace rayverify {
namespace {

namespace fs = std::filesystem;
using namespace test_support;

std::string parse_error(std::string_view text) {
    try {
        parse_baseline("b.txt", text);
    } catch (const input_error& e) {
        return e.what();
    }
    return "(parsed)";
}

const char* sample = R"(# header comment
rayverify-baseline 1
# loosen ULPs for naive
policy default ulp_slack 1
policy naive ulp_slack 2
policy naive/float count_slack 3
naive/float all cases 1000
naive/float far_sphere cases 500
# 45 known: C loses r² (RTG ch.7)
naive/float far_sphere false_miss 45
naive/float far_sphere near_ulp_max 100
hearn_baker/double far_sphere cases 500
hearn_baker/double far_sphere false_miss 0
# trailing
)";

TEST(Gate, BaselineRoundTripsWithCommentsAndPolicies) {
    const baseline b = parse_baseline("b.txt", sample);
    EXPECT_EQ(b.figures.size(), 6u);
    EXPECT_EQ(b.policy_for("naive/float").ulp_slack, 2);
    EXPECT_EQ(b.policy_for("naive/float").count_slack, 3);
    EXPECT_EQ(b.policy_for("naive/double").count_slack, 0);
    EXPECT_EQ(b.policy_for("hearn_baker/double").ulp_slack, 1);
    const std::string text = format_baseline(b);
    EXPECT_EQ(format_baseline(parse_baseline("again.txt", text)), text);
    for (const char* kept : {"# header comment\nrayverify-baseline 1\n", "# loosen ULPs for naive\npolicy default",
                             "# 45 known: C loses r² (RTG ch.7)\nnaive/float far_sphere false_miss 45\n",
                             "# trailing\n"})
        EXPECT_NE(text.find(kept), std::string::npos) << kept << "\n---\n" << text;
}

TEST(Gate, UpdateKeepsCommentsAndUnrunTargets) {
    const baseline old = parse_baseline("b.txt", sample);
    const figure_table current = {{{"naive/float", "all", "cases"}, 1000},
                                  {{"naive/float", "far_sphere", "cases"}, 500},
                                  {{"naive/float", "far_sphere", "false_miss"}, 40}};
    const std::string text = format_baseline(updated_baseline(old, current));
    EXPECT_NE(text.find("# 45 known: C loses r² (RTG ch.7)\nnaive/float far_sphere false_miss 40\n"),
              std::string::npos) << text;
    EXPECT_EQ(text.find("near_ulp_max"), std::string::npos) << "a figure the run no longer has is dropped";
    EXPECT_NE(text.find("hearn_baker/double far_sphere false_miss 0"), std::string::npos) << "not run: kept";
    EXPECT_NE(text.find("policy naive/float count_slack 3"), std::string::npos);
}

TEST(Gate, MalformedBaselinesNameFileLineAndField) {
    EXPECT_EQ(parse_error("naive/float all cases 3\n"),
              "b.txt:1: field 'format': the first entry must be 'rayverify-baseline 1' (is this a rayverify gate "
              "baseline?)");
    EXPECT_EQ(parse_error("rayverify-baseline 1\nnaive/float all false_mis 3\n"),
              "b.txt:2: field 'figure': unknown figure 'false_mis'");
    EXPECT_EQ(parse_error("rayverify-baseline 1\n\nnaive/float all false_miss x3\n"),
              "b.txt:3: field 'value': 'x3' is not a number ≥ 0 (decimal or inf)");
    EXPECT_EQ(parse_error("rayverify-baseline 1\npolicy default ulp_slack 0.5\n"),
              "b.txt:2: field 'value': ulp_slack is a factor ≥ 1");
    EXPECT_EQ(parse_error("rayverify-baseline 1\npolicy default slack 2\n"),
              "b.txt:2: field 'policy': unknown policy key 'slack' (ulp_slack or count_slack)");
    EXPECT_EQ(parse_error("rayverify-baseline 1\nnaive all cases 3\n"),
              "b.txt:2: field 'target': 'naive' is not a target like naive/float");
    EXPECT_EQ(parse_error("rayverify-baseline 1\nnaive/float all cases 3\nnaive/float all cases 3\n"),
              "b.txt:3: field 'entry': duplicate entry for naive/float all cases");
    EXPECT_EQ(parse_error("# only a comment\n"), "b.txt: field 'format': empty baseline: no 'rayverify-baseline 1' line");
    // Lines as every text reader takes them: CRLF ends read, a carriage return
    // inside a line (a line --update could not write back as it was read) refused.
    EXPECT_EQ(format_baseline(parse_baseline("b.txt", "rayverify-baseline 1\r\nlibrary embree3 kernel avx2\r\n")),
              "rayverify-baseline 1\nlibrary embree3 kernel avx2\n");
    EXPECT_EQ(parse_error("rayverify-baseline 1\r\nlibrary embree3 kernel\r avx2\r\n"),
              "b.txt:2: line contains a carriage return not followed by a newline (CR-only line endings, as old Mac "
              "files have?): save the file with \\n or \\r\\n line endings");
    EXPECT_EQ(parse_error("rayverify-baseline 1\n# a comment\r\r\n"),
              "b.txt:2: line contains a carriage return not followed by a newline (CR-only line endings, as old Mac "
              "files have?): save the file with \\n or \\r\\n line endings");
}

// A library's set-up (the kernel Embree picked for the CPU) is recorded by
// --update, read back, and a run with another set-up fails the gate naming
// both, whatever its figures; a baseline without the line takes a note.
TEST(Gate, LibrarySetUpIsRecordedAndAnotherOneFailsTheGate) {
    const baseline b = parse_baseline("b.txt", sample);
    const configuration_table avx512 = {{"embree3", "kernel avx512, Embree's choice for this CPU"}};
    figure_table current = b.figures;
    current[{"embree3/float", "all", "cases"}] = 1000;
    current[{"embree3/float", "all", "false_miss"}] = 96;
    const baseline recorded = updated_baseline(b, current, avx512);
    const std::string text = format_baseline(recorded);
    EXPECT_NE(text.find("# The set-up embree3's library ran with; a run with another fails the gate.\n"
                        "library embree3 kernel avx512, Embree's choice for this CPU\n"),
              std::string::npos)
        << text;
    const baseline again = parse_baseline("again.txt", text);
    EXPECT_EQ(format_baseline(again), text);
    EXPECT_TRUE(compare_to_baseline(again, current, default_figure_tolerance, avx512).passed());

    const configuration_table avx2 = {{"embree3", "kernel avx2, Embree's choice for this CPU"}};
    const gate_result moved = compare_to_baseline(again, current, default_figure_tolerance, avx2);
    EXPECT_FALSE(moved.passed()) << "same figures, another kernel";
    ASSERT_EQ(moved.configuration_changes.size(), 1u);
    EXPECT_EQ(moved.configuration_changes[0].variant, "embree3");
    EXPECT_EQ(moved.configuration_changes[0].before, "kernel avx512, Embree's choice for this CPU");
    EXPECT_EQ(moved.configuration_changes[0].after, "kernel avx2, Embree's choice for this CPU");
    EXPECT_FALSE(compare_to_baseline(again, current).passed()) << "a run that reports no set-up is another one";

    const gate_result unrecorded = compare_to_baseline(updated_baseline(b, current), current, default_figure_tolerance,
                                                       avx2);
    EXPECT_TRUE(unrecorded.passed());
    ASSERT_FALSE(unrecorded.notes.empty());
    EXPECT_NE(unrecorded.notes.back().find("embree3: the baseline records no library set-up"), std::string::npos);

    EXPECT_EQ(format_baseline(updated_baseline(recorded, current, {})).find("library embree3"), std::string::npos)
        << "a run without a set-up drops the line";
    EXPECT_EQ(parse_error("rayverify-baseline 1\nlibrary embree3\n"),
              "b.txt:2: field 'library': expected 'library VARIANT SET-UP'");
    EXPECT_EQ(parse_error("rayverify-baseline 1\nlibrary embree3/float kernel sse2\n"),
              "b.txt:2: field 'library': 'embree3/float' is a target; a library line names a variant, like embree3");
    EXPECT_EQ(parse_error("rayverify-baseline 1\nlibrary embree3 kernel sse2\nlibrary embree3 kernel avx\n"),
              "b.txt:3: field 'library': duplicate library line for embree3");
}

// The contract each variant was judged by is recorded by --update and read
// back; a run under another contract fails the gate naming both, whatever its
// figures (another contract scores other cases: a run that scores fewer would
// otherwise read as better); a baseline without the line takes a note.
TEST(Gate, ContractIsRecordedAndAnotherOneFailsTheGate) {
    const baseline b = parse_baseline("b.txt", sample);
    const std::string line_roots = format_contract(parse_contract("query=line_roots"));
    const std::string unit_line_roots = format_contract(parse_contract("query=line_roots,unit_direction=yes"));
    ASSERT_NE(line_roots, unit_line_roots);
    const configuration_table judged_by = {{"naive", line_roots}, {"hearn_baker", line_roots}};
    const baseline recorded = updated_baseline(b, b.figures, {}, judged_by);
    const std::string text = format_baseline(recorded);
    EXPECT_NE(text.find("# The contract each variant was judged by; a run under another fails the gate.\n"
                        "contract hearn_baker " + line_roots + "\ncontract naive " + line_roots + "\n"),
              std::string::npos)
        << text;
    const baseline again = parse_baseline("again.txt", text);
    EXPECT_EQ(format_baseline(again), text);
    EXPECT_TRUE(compare_to_baseline(again, b.figures, default_figure_tolerance, {}, {}, judged_by).passed());

    const configuration_table unit = {{"naive", unit_line_roots}, {"hearn_baker", line_roots}};
    const gate_result moved = compare_to_baseline(again, b.figures, default_figure_tolerance, {}, {}, unit);
    EXPECT_FALSE(moved.passed()) << "same figures, another contract";
    ASSERT_EQ(moved.configuration_changes.size(), 1u);
    EXPECT_EQ(moved.configuration_changes[0].aspect, setup_aspect::contract);
    EXPECT_EQ(moved.configuration_changes[0].variant, "naive");
    EXPECT_EQ(moved.configuration_changes[0].before, line_roots);
    EXPECT_EQ(moved.configuration_changes[0].after, unit_line_roots);

    const gate_result unrecorded = compare_to_baseline(b, b.figures, default_figure_tolerance, {}, {}, unit);
    EXPECT_TRUE(unrecorded.passed());
    ASSERT_FALSE(unrecorded.notes.empty());
    EXPECT_NE(unrecorded.notes.front().find("hearn_baker: the baseline records no contract; this run's: " + line_roots),
              std::string::npos)
        << unrecorded.notes.front();

    EXPECT_EQ(parse_error("rayverify-baseline 1\ncontract naive\n"),
              "b.txt:2: field 'contract': expected 'contract VARIANT SPEC'");
    EXPECT_EQ(parse_error("rayverify-baseline 1\ncontract naive/float query=line_roots\n"),
              "b.txt:2: field 'contract': 'naive/float' is a target; a contract line names a variant, like naive");
    EXPECT_NE(parse_error("rayverify-baseline 1\ncontract naive query=sideways\n").find("b.txt:2: field 'contract': "),
              std::string::npos);
    EXPECT_EQ(parse_error("rayverify-baseline 1\ncontract naive query=line_roots\ncontract naive query=any_hit\n"),
              "b.txt:3: field 'contract': duplicate contract line for naive");
}

figure_change find_change(const gate_result& r, const std::string& text) {
    for (const figure_change& c : r.changes)
        if (c.key.text() == text) return c;
    ADD_FAILURE() << "no change for " << text;
    return {};
}

TEST(Gate, WorseFailsBetterPassesWithinSlackPasses) {
    const baseline b = parse_baseline("b.txt", sample);
    figure_table current = b.figures;
    EXPECT_TRUE(compare_to_baseline(b, current).passed());
    EXPECT_TRUE(compare_to_baseline(b, current).changes.empty());

    current[{"naive/float", "far_sphere", "false_miss"}] = 48;  // within count_slack 3
    current[{"naive/float", "far_sphere", "near_ulp_max"}] = 150;  // within ulp_slack 2
    gate_result r = compare_to_baseline(b, current);
    EXPECT_TRUE(r.passed());
    EXPECT_EQ(find_change(r, "naive/float far_sphere false_miss").kind, change_kind::within_slack);

    current[{"naive/float", "far_sphere", "false_miss"}] = 49;
    current[{"hearn_baker/double", "far_sphere", "false_miss"}] = 1;
    r = compare_to_baseline(b, current);
    EXPECT_FALSE(r.passed());
    EXPECT_EQ(find_change(r, "naive/float far_sphere false_miss").kind, change_kind::worse);
    EXPECT_EQ(find_change(r, "naive/float far_sphere false_miss").limit, 48);
    EXPECT_EQ(find_change(r, "hearn_baker/double far_sphere false_miss").kind, change_kind::worse);

    figure_table better = b.figures;
    better[{"naive/float", "far_sphere", "false_miss"}] = 12;
    r = compare_to_baseline(b, better);
    EXPECT_TRUE(r.passed());
    EXPECT_EQ(find_change(r, "naive/float far_sphere false_miss").kind, change_kind::better);
}

// Fewer scored cases is worse, more is better: a contract or an input that
// leaves cases unscored (invalid at the precision, breaking the contract)
// lowers the disagreement counts with them, which must not read as better.
TEST(Gate, FewerScoredCasesFailMoreAreBetter) {
    baseline b = parse_baseline("b.txt", sample);
    b.figures[{"naive/float", "far_sphere", "scored"}] = 500;
    b.figures[{"hearn_baker/double", "far_sphere", "scored"}] = 480;
    figure_table current = b.figures;
    current[{"naive/float", "far_sphere", "scored"}] = 497;  // within count_slack 3
    current[{"hearn_baker/double", "far_sphere", "scored"}] = 490;
    gate_result r = compare_to_baseline(b, current);
    EXPECT_TRUE(r.passed());
    EXPECT_EQ(find_change(r, "naive/float far_sphere scored").kind, change_kind::within_slack);
    EXPECT_EQ(find_change(r, "naive/float far_sphere scored").limit, 497);
    EXPECT_EQ(find_change(r, "hearn_baker/double far_sphere scored").kind, change_kind::better);

    current[{"naive/float", "far_sphere", "scored"}] = 496;
    current[{"naive/float", "far_sphere", "false_miss"}] = 30;  // fewer misses, because fewer cases were judged
    r = compare_to_baseline(b, current);
    EXPECT_FALSE(r.passed());
    EXPECT_EQ(find_change(r, "naive/float far_sphere scored").kind, change_kind::worse);
    EXPECT_EQ(find_change(r, "naive/float far_sphere false_miss").kind, change_kind::better);

    // As an audit counts them: every case judged but the invalid ones.
    audit_totals totals;
    totals.targets.push_back({});
    totals.targets[0].subject.name = "naive";
    totals.overall.resize(1);
    totals.overall[0].cases = 10;
    totals.overall[0].verdicts[static_cast<int>(verdict_kind::agree)] = 6;
    totals.overall[0].verdicts[static_cast<int>(verdict_kind::false_miss)] = 1;
    totals.overall[0].verdicts[static_cast<int>(verdict_kind::invalid)] = 3;
    const figure_table figures = figures_of(totals);
    EXPECT_EQ(figures.at({"naive/double", "all", "cases"}), 10);
    EXPECT_EQ(figures.at({"naive/double", "all", "scored"}), 7);
}

TEST(Gate, NewFamiliesAndTargetsAreNotesAChangedFamilyIsStale) {
    const baseline b = parse_baseline("b.txt", sample);
    figure_table current = b.figures;
    // Another family joined the corpus: the whole-corpus figures are not comparable, the families are.
    current[{"naive/float", "all", "cases"}] = 1500;
    current[{"naive/float", "all", "false_miss"}] = 500;
    current[{"naive/float", "grazing", "cases"}] = 500;
    current[{"naive/float", "grazing", "false_miss"}] = 7;
    current[{"mine/double", "all", "cases"}] = 1500;
    gate_result r = compare_to_baseline(b, current);
    EXPECT_TRUE(r.passed());
    std::string notes;
    for (const std::string& n : r.notes) notes += n + "\n";
    EXPECT_NE(notes.find("naive/float grazing: new family, no baseline"), std::string::npos) << notes;
    EXPECT_NE(notes.find("mine/double: new, no baseline"), std::string::npos) << notes;
    EXPECT_NE(notes.find("naive/float all: corpus has 1500 cases, baseline 1000"), std::string::npos) << notes;

    current[{"naive/float", "far_sphere", "cases"}] = 501;
    r = compare_to_baseline(b, current);
    EXPECT_FALSE(r.passed());
    EXPECT_EQ(find_change(r, "naive/float far_sphere cases").kind, change_kind::stale);

    EXPECT_FALSE(compare_to_baseline(b, {{{"other/double", "all", "cases"}, 3}}).passed()) << "nothing compared";
}

// A gate does not pass on less than its baseline: a family the corpus no
// longer has and a target not run fail, naming them, unless the baseline or
// --allow-missing allows them; a target that scored no case fails too.
TEST(Gate, AnAbsentFamilyOrTargetFailsUnlessAllowed) {
    const baseline b = parse_baseline("b.txt", sample);
    figure_table current = b.figures;
    current.erase({"naive/float", "far_sphere", "cases"});
    current.erase({"naive/float", "far_sphere", "false_miss"});
    current.erase({"naive/float", "far_sphere", "near_ulp_max"});
    gate_result r = compare_to_baseline(b, current);
    EXPECT_FALSE(r.passed()) << "a family left out of the corpus";
    EXPECT_EQ(find_change(r, "naive/float far_sphere cases").kind, change_kind::missing);
    EXPECT_TRUE(compare_to_baseline(b, current, default_figure_tolerance, {}, {"far_sphere"}).passed());
    const baseline allowing = parse_baseline("b.txt", std::string(sample) + "allow-missing far_sphere\n");
    EXPECT_TRUE(compare_to_baseline(allowing, current).passed());
    EXPECT_NE(format_baseline(allowing).find("allow-missing far_sphere\n"), std::string::npos);

    figure_table naive_only = b.figures;
    for (auto it = naive_only.begin(); it != naive_only.end();)
        it = it->first.target == "hearn_baker/double" ? naive_only.erase(it) : std::next(it);
    r = compare_to_baseline(b, naive_only);
    EXPECT_FALSE(r.passed()) << "a target of the baseline not run";
    EXPECT_EQ(find_change(r, "hearn_baker/double all cases").kind, change_kind::missing);
    EXPECT_TRUE(compare_to_baseline(b, naive_only, default_figure_tolerance, {}, {"hearn_baker"}).passed());
    EXPECT_TRUE(compare_to_baseline(b, naive_only, default_figure_tolerance, {}, {"hearn_baker/double"}).passed());
    EXPECT_EQ(parse_error("rayverify-baseline 1\nallow-missing\n"),
              "b.txt:2: field 'allow-missing': expected 'allow-missing FAMILY|VARIANT|TARGET'");
}

// Every case invalid (tmin > tmax on every line): the audit scored nothing,
// which is a finding, and the gate fails instead of passing as "better".
TEST(Gate, ATargetThatScoredNoCaseFailsTheAuditAndTheGate) {
    const scratch_directory dir("gate_unscored");
    const fs::path corpus = dir.path() / "swapped.txt";
    {
        std::ofstream out(corpus);
        for (int i = 0; i < 20; ++i) out << "s" << i << " fam 0 0 -5 0 0 1 0 0 0 1 3 1\n";  // tmin 3 > tmax 1
    }
    const command_result audited = run_cli("audit --variant naive --precision double --corpus '" + corpus.string() + "'");
    EXPECT_EQ(audited.exit_code, 1) << audited.output;
    EXPECT_NE(audited.output.find("audit: naive/double scored no case of 20"), std::string::npos) << audited.output;
    const std::string baseline = (dir.path() / "b.txt").string();
    const std::string good = (dir.path() / "good.txt").string();
    std::ofstream(good) << "s0 fam 0 0 -5 0 0 1 0 0 0 1\n";
    ASSERT_EQ(run_cli("gate --variant naive --precision double --corpus '" + good + "' --baseline '" + baseline +
                      "' --update").exit_code,
              0);
    // The same ids and family, each now invalid: the gate may not read "better".
    std::ofstream(good) << "s0 fam 0 0 -5 0 0 1 0 0 0 1 3 1\n";
    const command_result gated = run_cli("gate --variant naive --precision double --corpus '" + good + "' --baseline '" +
                                         baseline + "'");
    EXPECT_EQ(gated.exit_code, 1) << gated.output;
    EXPECT_NE(gated.output.find("NONE   naive/double: scored no case of this run"), std::string::npos) << gated.output;
}

TEST(Gate, CliUpdateThenGateThenRegressionWithJunitAndDiff) {
    const test_support::scratch_directory dir_scratch("rayverify_gate_cli");
    const fs::path& dir = dir_scratch.path();
    const std::string corpus = std::string(" --corpus ") + RAYVERIFY_CORPUS_DIR + "/far_sphere.txt --corpus " +
                               RAYVERIFY_CORPUS_DIR + "/uniform.txt";
    const std::string baseline = (dir / "baseline.txt").string();

    command_result r = run_cli("gate --baseline " + baseline + corpus + " --variant naive");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("no such baseline; create it with"), std::string::npos) << r.output;

    r = run_cli("gate --baseline " + baseline + corpus + " --variant naive --update");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const std::string written = read_text(baseline);
    EXPECT_NE(written.find("\nnaive/float far_sphere false_miss 45\n"), std::string::npos) << written;

    r = run_cli("gate --baseline " + baseline + corpus + " --variant naive --junit " + (dir / "ok.xml").string());
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("gate: passed: "), std::string::npos) << r.output;

    // The baseline records naive's contract; judged by another (here the
    // line edited, as a plugin's changed contract would read), the gate fails
    // naming both, in the text and in the JUnit file.
    const std::string contract_line = "\ncontract naive query=line_roots,";
    ASSERT_NE(written.find(contract_line), std::string::npos) << written;
    std::string other_contract = written;
    const std::size_t unit_at = other_contract.find("unit_direction=no", other_contract.find(contract_line));
    ASSERT_NE(unit_at, std::string::npos) << written;
    other_contract.replace(unit_at, 17, "unit_direction=yes");
    const std::string other_baseline = (dir / "other_contract.txt").string();
    std::ofstream(other_baseline) << other_contract;
    r = run_cli("gate --baseline " + other_baseline + corpus + " --variant naive --junit " +
                (dir / "contract.xml").string());
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_NE(r.output.find("CONTRACT naive: contract query=line_roots,"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("unit_direction=yes,reports_tangent=yes in the baseline, query=line_roots,"),
              std::string::npos) << r.output;
    EXPECT_NE(r.output.find(", 1 contract(s) not the baseline's;"), std::string::npos) << r.output;
    EXPECT_NE(read_text(dir / "contract.xml").find("<testsuite name=\"contract\" tests=\"1\" failures=\"1\">"),
              std::string::npos);

    // A baseline tighter than the truth: the gate fails with a readable diff and pasteable cases.
    std::string tighter = written;
    const std::string line = "naive/float far_sphere false_miss 45\n";
    tighter.replace(tighter.find(line), line.size(), "# a reviewer's note\nnaive/float far_sphere false_miss 42\n");
    std::ofstream(baseline) << tighter;
    r = run_cli("gate --baseline " + baseline + corpus + " --variant naive --junit " + (dir / "fail.xml").string());
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_NE(r.output.find("WORSE  naive/float far_sphere: false_miss 42 → 45 (allowed ≤ 42)\n"
                            "    # first cases, as corpus lines:\n    far_sphere-1-"),
              std::string::npos)
        << r.output;
    const std::string junit = read_text(dir / "fail.xml");
    EXPECT_NE(junit.find("<testcase classname=\"naive/float\" name=\"far_sphere\">\n      <failure"),
              std::string::npos) << junit;
    EXPECT_NE(junit.find("failures=\"1\""), std::string::npos) << junit;

    // A looser baseline passes and says it can be tightened; --update keeps the reviewer's note.
    std::ofstream(baseline) << tighter.replace(tighter.find("false_miss 42"), 13, "false_miss 50");
    r = run_cli("gate --baseline " + baseline + corpus + " --variant naive");
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("better naive/float far_sphere: false_miss 50 → 45"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("the baseline can be tightened"), std::string::npos) << r.output;
    r = run_cli("gate --baseline " + baseline + corpus + " --variant naive --update");
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(read_text(baseline).find("# a reviewer's note\nnaive/float far_sphere false_miss 45\n"),
              std::string::npos);

    // diff of two audit reports, figure by figure: B is A with three more false misses on far_sphere.
    r = run_cli("audit --variant naive --precision float --corpus " + std::string(RAYVERIFY_CORPUS_DIR) +
                "/far_sphere.txt --report " + (dir / "a").string());
    ASSERT_EQ(r.exit_code, 1) << r.output;
    const fs::path a_json = dir / "a" / "report.json", b_json = dir / "b.json";
    nlohmann::json report = nlohmann::json::parse(read_text(a_json));
    auto& misses = report["results"][0]["by_family"]["far_sphere"]["verdicts"]["false_miss"];
    ASSERT_EQ(misses, 45);
    misses = 48;
    std::ofstream(b_json) << report.dump(2);
    r = run_cli("diff " + a_json.string() + " " + b_json.string());
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_NE(r.output.find("worse  naive/float far_sphere: false_miss 45 → 48\n"), std::string::npos) << r.output;
    r = run_cli("diff " + b_json.string() + " " + a_json.string());
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("better naive/float far_sphere: false_miss 48 → 45\n"), std::string::npos) << r.output;
    r = run_cli("diff " + a_json.string() + " " + baseline);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find(baseline + ":1: not valid JSON: syntax error"), std::string::npos) << r.output;
}

// What .ci/run does: our own variants on the shipped corpus against the committed baseline.
TEST(Gate, OwnVariantsPassTheCommittedBaseline) {
    const command_result r = run_cli(std::string("gate --baseline ") + RAYVERIFY_BASELINE + " --corpus " +
                                 RAYVERIFY_CORPUS_DIR);
    EXPECT_EQ(r.exit_code, 0) << r.output;
}

// The issue's "done when": a user's intersector in its own directory, built
// as a plugin with docs/gate.md's command, audited, baselined; then the naive
// discriminant goes in and the gate fails.
TEST(Gate, EndToEndUserPluginBaselineThenNaiveDiscriminantFails) {
    const test_support::scratch_directory user_scratch("rayverify_gate_user");
    const fs::path& user = user_scratch.path();
    const fs::path source = user / "mine.c";
    const std::string original = read_text(std::string(RAYVERIFY_SOURCE_DIR) + "/examples/plugin_rtg/rtg_sphere.c");
    std::ofstream(source) << original;
    const std::string build = "cd " + user.string() + " && " + RAYVERIFY_C_COMPILER + " -O2 -shared -fPIC -I " +
                              RAYVERIFY_SOURCE_DIR + "/src/plugin mine.c -o libmine.so -lm";
    const std::string gate = "cd " + user.string() + " && " + RAYVERIFY_CLI + " gate --plugin ./libmine.so --corpus " +
                             RAYVERIFY_CORPUS_DIR + " --baseline baseline.txt";
    command_result r = run_shell(build);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    r = run_shell("cd " + user.string() + " && " + RAYVERIFY_CLI + " audit --plugin ./libmine.so --corpus " +
                  RAYVERIFY_CORPUS_DIR);
    EXPECT_EQ(r.exit_code, 1) << r.output;  // the RTG form's known 0/0 at exact tangents
    EXPECT_NE(r.output.find("rtg_sphere"), std::string::npos) << r.output;
    r = run_shell(gate + " --update");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    r = run_shell(gate);
    EXPECT_EQ(r.exit_code, 0) << r.output;

    // The "simplification": the textbook discriminant instead of Hearn–Baker's.
    const std::string hearn_baker = "const double disc = r * r - dot3(l, l);";
    std::string naive = original;
    ASSERT_NE(naive.find(hearn_baker), std::string::npos);
    naive.replace(naive.find(hearn_baker), hearn_baker.size(), "const double disc = (b * b - a * C) / a;");
    std::ofstream(source) << naive;
    r = run_shell(build);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    r = run_shell(gate + " --junit junit.xml");
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_NE(r.output.find("WORSE  rtg_sphere/double far_sphere: false_miss 0 → "), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("gate: FAILED"), std::string::npos) << r.output;
    EXPECT_NE(read_text(user / "junit.xml").find("<failure"), std::string::npos);
}

}  // namespace
}  // namespace rayverify
