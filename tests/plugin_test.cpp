// Plugins: a user's intersector loaded from a shared library is audited like
// a built-in; garbage answers are verdicts, case by case; a library that
// cannot be used is an input error naming it.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "compare/audit.h"
#include "corpus/corpus_io.h"
#include "intersectors/registry.h"
#include "plugin/plugin_loader.h"
#include "support/process.h"

namespace rayverify {
namespace {

namespace fs = std::filesystem;

std::string load_error(const fs::path& library) {
    try {
        load_plugin(library);
    } catch (const input_error& e) {
        return e.what();
    }
    return "(loaded)";
}

using namespace test_support;

TEST(Plugin, ExampleDescribesItselfAndRunsInDoubleOnly) {
    const variant v = load_plugin(RAYVERIFY_EXAMPLE_PLUGIN);
    EXPECT_EQ(v.name, "rtg_sphere");
    EXPECT_EQ(v.promises.query, query_kind::line_roots);
    EXPECT_FALSE(v.promises.assumes_unit_direction);
    EXPECT_TRUE(v.promises.reports_tangent);
    EXPECT_EQ(v.promises.tangent_rule, "disc == 0");
    EXPECT_TRUE(v.runs_in(precision::binary64));
    EXPECT_FALSE(v.runs_in(precision::binary32));
    const root_pair<double> r = v.run_double({{0, 0, -5}, {0, 0, 1}, {0, 0, 0}, 1});
    EXPECT_EQ(r.count, 2);
    EXPECT_EQ(r.t0, 4);
    EXPECT_EQ(r.t1, 6);
}

// The example is the Ray Tracing Gems final form written in C; on the shipped
// corpus it must agree with the built-in hearn_baker<double> figure for figure.
TEST(Plugin, ExampleMatchesBuiltinHearnBakerOnTheShippedCorpus) {
    const std::vector<corpus_case> cases = read_corpus({RAYVERIFY_CORPUS_DIR});
    const variant chosen[] = {load_plugin(RAYVERIFY_EXAMPLE_PLUGIN), *find_builtin_variant("hearn_baker")};
    std::vector<audit_target> targets;
    for (const audit_target& t : targets_for(chosen))
        if (t.prec == precision::binary64) targets.push_back(t);
    ASSERT_EQ(targets.size(), 2u);
    const audit_totals totals = run_audit(cases, targets);
    EXPECT_EQ(totals.overall[0].verdicts, totals.overall[1].verdicts);
    EXPECT_EQ(totals.overall[0].errors[rayverify::error_figure::near_root_ulp].max, totals.overall[1].errors[rayverify::error_figure::near_root_ulp].max);
    EXPECT_EQ(totals.overall[0].errors[rayverify::error_figure::far_root_ulp].p99, totals.overall[1].errors[rayverify::error_figure::far_root_ulp].p99);
    EXPECT_GT(totals.overall[0].disagreements(), 0u) << "hearn_baker's known 0/0 tangent NaN must show";
}

// bench times a plugin in a pass of its own (registry.h, timed_pass_fn): the
// pass calls the same function on the same cases, so its hit count is the sum
// of the counts the per-case calls return, pass after pass.
TEST(Plugin, TimedPassCallsTheEntryPointOnEveryCase) {
    const variant v = load_plugin(RAYVERIFY_EXAMPLE_PLUGIN);
    ASSERT_TRUE(v.timed_pass_double);
    EXPECT_FALSE(v.timed_pass_float) << "the example has no float function";
    std::vector<ray_sphere<double>> cases;
    long long expected = 0;
    for (const corpus_case& c : read_corpus({RAYVERIFY_CORPUS_DIR})) {
        cases.push_back(c.geometry);
        expected += v.run_double(c.geometry).count;
    }
    ASSERT_GT(expected, 0);
    const std::function<long long()> pass = v.timed_pass_double(cases);
    EXPECT_EQ(pass(), expected);
    EXPECT_EQ(pass(), expected);
    EXPECT_EQ(v.timed_pass_double({})(), 0);
}

// The guard areas around the roots are checked once per timed pass: a plugin
// that writes outside them still fails the pass, naming it.
TEST(Plugin, TimedPassCatchesAWriteOutsideTheRoots) {
    ASSERT_EQ(::setenv("FIXTURE_MODE", "overrun", 1), 0);  // read when the library loads
    const variant v = load_plugin(RAYVERIFY_FIXTURE_PLUGIN_MODAL);
    ::unsetenv("FIXTURE_MODE");
    const std::vector<ray_sphere<double>> cases(3, ray_sphere<double>{{0, 0, -5}, {0, 0, 1}, {0, 0, 0}, 1});
    const std::function<long long()> pass = v.timed_pass_double(cases);
    try {
        pass();
        ADD_FAILURE() << "the overrun went unnoticed";
    } catch (const plugin_failure& e) {
        EXPECT_NE(std::string(e.what()).find("wrote outside its roots[2] buffer in a timed pass over 3 cases"),
                  std::string::npos)
            << e.what();
    }
}

// The garbage fixture answers by origin.x: 0 → count 3, 1 → NaN roots, 2 → roots out of order, 3 → right.
TEST(Plugin, GarbageAnswersAreVerdictsCaseByCase) {
    const std::vector<corpus_case> cases = parse_corpus("garbage.txt",
                                                        "count3 - 0 0 -5 0 0 1 0 0 0 1\n"
                                                        "nan    - 1 0 -5 0 0 1 1 0 0 1\n"
                                                        "order  - 2 0 -5 0 0 1 2 0 0 1\n"
                                                        "right  - 3 0 -5 0 0 1 3 0 0 1\n",
                                                        false);
    const variant chosen[] = {load_plugin(RAYVERIFY_FIXTURE_PLUGIN_GARBAGE)};
    const std::vector<audit_target> targets = targets_for(chosen);
    ASSERT_EQ(targets.size(), 2u) << "float and double";
    const verdict_kind expected[] = {verdict_kind::malformed_output, verdict_kind::non_finite,
                                     verdict_kind::malformed_output, verdict_kind::agree};
    for (std::size_t i = 0; i < cases.size(); ++i) {
        const audited_case audited = audit_case(cases[i], targets);
        for (std::size_t t = 0; t < targets.size(); ++t)
            EXPECT_EQ(verdict_name(audited.outcomes[t].score.verdict), verdict_name(expected[i]))
                << cases[i].id << " " << targets[t].label() << ": " << audited.outcomes[t].score.detail;
    }
    EXPECT_EQ(audit_case(cases[0], targets).outcomes[1].score.detail, "hit count 3");
    EXPECT_NE(audit_case(cases[2], targets).outcomes[1].score.detail.find("roots out of order"), std::string::npos);
}

TEST(Plugin, UnusableLibrariesAreInputErrorsNamingTheFile) {
    const test_support::scratch_directory dir_scratch("rayverify_plugin_test");
    const fs::path& dir = dir_scratch.path();
    const fs::path not_a_library = dir / "libnot.so";
    std::ofstream(not_a_library) << "not an ELF file\n";

    EXPECT_EQ(load_error(dir / "libmissing.so"),
              (dir / "libmissing.so").string() + ": field '--plugin': no such file (expected a shared library)");
    EXPECT_NE(load_error(not_a_library).find(not_a_library.string() + ": field '--plugin': cannot load: "),
              std::string::npos)
        << load_error(not_a_library);
    EXPECT_NE(load_error(RAYVERIFY_FIXTURE_PLUGIN_BAD_ABI)
                  .find("plugin ABI version 999, this rayverify reads version 1; rebuild the plugin"),
              std::string::npos);
    EXPECT_NE(load_error(RAYVERIFY_FIXTURE_PLUGIN_NO_DOUBLE).find("missing symbol rayverify_plugin_intersect_double"),
              std::string::npos);
    EXPECT_NE(load_error(RAYVERIFY_FIXTURE_PLUGIN_BAD_NAME).find("name 'two words' must be one token"),
              std::string::npos);
}

TEST(Plugin, CliAuditAndExplainAcceptPlugins) {
    const test_support::scratch_directory dir("rayverify_plugin_cli");
    const fs::path corpus = dir / "cases.txt";
    std::ofstream(corpus) << "count3 - 0 0 -5 0 0 1 0 0 0 1\nright - 3 0 -5 0 0 1 3 0 0 1\n";
    const command_result audit = run_cli("audit --plugin " + std::string(RAYVERIFY_FIXTURE_PLUGIN_GARBAGE) +
                                     " --corpus " + corpus.string());
    EXPECT_EQ(audit.exit_code, 1) << audit.output;
    EXPECT_NE(audit.output.find("garbage"), std::string::npos) << audit.output;
    EXPECT_EQ(audit.output.find("naive"), std::string::npos) << "only the plugin when no --variant is given";

    const command_result both = run_cli("audit --variant hearn_baker --plugin " + std::string(RAYVERIFY_EXAMPLE_PLUGIN) +
                                    " --corpus " + corpus.string() + " --precision double");
    EXPECT_EQ(both.exit_code, 0) << both.output;
    EXPECT_NE(both.output.find("rtg_sphere"), std::string::npos) << both.output;
    EXPECT_NE(both.output.find("hearn_baker"), std::string::npos) << both.output;

    const command_result explain = run_cli("explain \"0 0 -5 0 0 1 0 0 0 1\" --plugin " + std::string(RAYVERIFY_EXAMPLE_PLUGIN));
    EXPECT_EQ(explain.exit_code, 0) << explain.output;
    EXPECT_NE(explain.output.find("rtg_sphere/double"), std::string::npos) << explain.output;
    // No formula to trace: what its answer implies, beside the exact class.
    EXPECT_NE(explain.output.find("derived (no formula to trace): the answer implies Δ′ > 0; exact Δ′ > 0"),
              std::string::npos)
        << explain.output;

    const command_result missing = run_cli("audit --plugin ./no_such_plugin.so --corpus " + corpus.string());
    EXPECT_EQ(missing.exit_code, 2) << missing.output;
    EXPECT_NE(missing.output.find("./no_such_plugin.so: field '--plugin': no such file"), std::string::npos)
        << missing.output;
    const command_result twice = run_cli("audit --plugin " + std::string(RAYVERIFY_EXAMPLE_PLUGIN) + " --plugin " +
                                     RAYVERIFY_EXAMPLE_PLUGIN + " --corpus " + corpus.string());
    EXPECT_EQ(twice.exit_code, 2) << twice.output;
    EXPECT_NE(twice.output.find("two targets named 'rtg_sphere'"), std::string::npos) << twice.output;
    fs::remove(corpus);
}

}  // namespace
}  // namespace rayverify
