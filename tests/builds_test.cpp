// `rayverify builds` (plugin/plugin_builds, cli/builds_command, docs/builds.md):
// the delta-debugging search and the flag rules by hand, then the command on
// small plugins written here: one build that does not compile while the
// others run, one that crashes while audited, the cache (reused, and rebuilt
// when a header changes), the reference that does not compile, refused
// flags, the gate pinned to a build; and the shipped physics example's
// fast-math NaN turned into a hit at 0, bisected to the flags that do it.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "compare/build_comparison.h"
#include "core/input_error.h"
#include "plugin/plugin_builds.h"
#include "support/process.h"

namespace rayverify {
namespace {

using test_support::run_cli;

TEST(BuildsBisect, FindsTheSmallestReproducingSubsetAskingEachOnce) {
    // The change needs components 2 and 5 together.
    std::set<std::vector<std::size_t>> asked;
    const auto needs_2_and_5 = [&](const std::vector<std::size_t>& s) {
        EXPECT_TRUE(asked.insert(s).second) << "asked twice";
        return std::find(s.begin(), s.end(), 2) != s.end() && std::find(s.begin(), s.end(), 5) != s.end();
    };
    EXPECT_EQ(smallest_reproducing_subset(9, needs_2_and_5), (std::vector<std::size_t>{2, 5}));
    // One component alone.
    EXPECT_EQ(smallest_reproducing_subset(7, [](const std::vector<std::size_t>& s) {
                  return std::find(s.begin(), s.end(), 6) != s.end();
              }),
              (std::vector<std::size_t>{6}));
    // Nothing needed: the compiler alone (the empty set reproduces).
    EXPECT_TRUE(smallest_reproducing_subset(4, [](const std::vector<std::size_t>&) { return true; }).empty());
    // Every component needed.
    EXPECT_EQ(smallest_reproducing_subset(3, [](const std::vector<std::size_t>& s) { return s.size() == 3; }),
              (std::vector<std::size_t>{0, 1, 2}));
}

TEST(BuildsComparison, AnswersAreTheSameBitForBitAndAnyNanIsTheSame) {
    variant_output a, b;
    a.roots = {1, 0.5, 0};
    b.roots = {1, 0.5, 0};
    EXPECT_TRUE(same_answer(a, b));
    b.roots.t0 = std::nextafter(0.5, 1.0);
    EXPECT_FALSE(same_answer(a, b));
    a.roots.t0 = 0.0;
    b.roots.t0 = -0.0;
    EXPECT_FALSE(same_answer(a, b));  // a sign a caller may read
    a.roots.t0 = std::numeric_limits<double>::quiet_NaN();
    b.roots.t0 = -std::numeric_limits<double>::quiet_NaN();
    EXPECT_TRUE(same_answer(a, b));   // no NaN is an answer of its own
    b.roots.count = 2;
    EXPECT_FALSE(same_answer(a, b));
    a.roots.count = b.roots.count = 0;
    a.roots.t0 = 1;  // values not counted are no answer
    EXPECT_TRUE(same_answer(a, b));
    a.hit_point = vec3<double>{1, 2, 3};
    EXPECT_FALSE(same_answer(a, b));
}

TEST(BuildsFlags, RefusesFlagsThatInjectCodeOrChangeWhatIsBuilt) {
    for (const char* refused : {"-include", "-includefoo.h", "-fplugin=evil.so", "-specs=x", "-B/tmp", "@flags.txt",
                                "-o", "-c", "-Wl,-init,evil", "-shared", "-wrapper", "-imacros"}) {
        const std::vector<std::string> flags = {"-O2", refused};
        EXPECT_THROW(check_build_flags(flags, "--flags"), input_error) << refused;
    }
    const std::vector<std::string> fine = {"-O3", "-ffast-math", "-march=native", "-mfma", "-ffp-contract=fast",
                                           "-fno-signed-zeros", "-Ofast", "-O0", "-fexcess-precision=fast"};
    EXPECT_NO_THROW(check_build_flags(fine, "--flags"));
    const std::vector<std::string> flags = {"-O2", "-ffast-math"};
    EXPECT_EQ(build_name("gcc", flags), "gcc-O2-ffast-math");
}

TEST(BuildsFlags, FastMathBreaksIntoItsComponents) {
    build_spec spec;
    spec.compiler.name = "gcc";
    spec.flags = {"-O2", "-ffast-math"};
    std::vector<std::string> labels;
    for (const flag_component& c : flag_components(spec, true)) labels.push_back(c.label);
    for (const char* expected : {"-O2", "-ffinite-math-only", "-fno-signed-zeros", "-freciprocal-math",
                                 "-fassociative-math", "-ffp-contract=fast", "FTZ/DAZ at load"})
        EXPECT_NE(std::find(labels.begin(), labels.end(), expected), labels.end()) << expected;
    EXPECT_EQ(std::find(labels.begin(), labels.end(), "-ffast-math"), labels.end());
}

// A version 1 plugin in C: the textbook nearest hit in double, with a
// header of the test's (behaviour.h) and code that only some builds see.
void write_plugin(const std::filesystem::path& dir, const std::string& extra) {
    std::ofstream(dir / "behaviour.h") << "#define SCALE 1.0\n";
    std::ofstream(dir / "plugin.c") << R"(#include <math.h>
#include <signal.h>
#include "rayverify_plugin.h"
#include "behaviour.h"
)" << extra << R"(
RAYVERIFY_PLUGIN_EXPORT const rayverify_plugin_info* rayverify_plugin_describe(void) {
    static const rayverify_plugin_info info = {RAYVERIFY_PLUGIN_ABI_VERSION, "test_plugin", "textbook", "b' = d.f",
                                               RAYVERIFY_NEAREST_IN_INTERVAL, 0, 0, 0, NULL};
    return &info;
}
RAYVERIFY_PLUGIN_EXPORT int rayverify_plugin_intersect_double(const double o[3], const double d[3], const double c[3],
                                                              double r, double tmin, double tmax, double roots[2]) {
    CRASH_HERE
    const double f[3] = {o[0] - c[0], o[1] - c[1], o[2] - c[2]};
    const double a = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    const double b = d[0] * f[0] + d[1] * f[1] + d[2] * f[2];
    const double C = f[0] * f[0] + f[1] * f[1] + f[2] * f[2] - r * r;
    const double disc = b * b - a * C;
    if (disc < 0) return 0;
    const double t0 = SCALE * (-b - sqrt(disc)) / a, t1 = SCALE * (-b + sqrt(disc)) / a;
    if (tmin < t0 && t0 < tmax) { roots[0] = t0; return 1; }
    if (tmin < t1 && t1 < tmax) { roots[0] = t1; return 1; }
    return 0;
}
)";
}

std::string builds_command(const test_support::scratch_directory& scratch, const std::string& rest) {
    return "builds " + (scratch / "plugin.c").string() + " --cache " + (scratch / "cache").string() +
           " --compiler gcc --corpus " RAYVERIFY_CORPUS_DIR "/uniform.txt --precision double " + rest;
}

TEST(BuildsCommand, ABuildThatDoesNotCompileIsNamedAndTheOthersRun) {
    test_support::scratch_directory scratch("builds_compile_failure");
    write_plugin(scratch.path(), "#define CRASH_HERE\n#ifndef __OPTIMIZE__\nthis is not C;\n#endif\n");
    const auto ran = run_cli(builds_command(scratch, "--flags=-O0 --flags=-O3 --report " + (scratch / "r").string()));
    ASSERT_EQ(ran.exit_code, 0) << ran.output;
    EXPECT_NE(ran.output.find("gcc-O0"), std::string::npos);
    EXPECT_NE(ran.output.find("did not compile: plugin.c:"), std::string::npos) << ran.output;
    EXPECT_NE(ran.output.find("gcc-O3                                 same answers as the reference"), std::string::npos)
        << ran.output;
    const nlohmann::json report = nlohmann::json::parse(test_support::read_text(scratch / "r" / "report.json"));
    const nlohmann::json& rows = report["builds"]["rows"];
    ASSERT_EQ(rows.size(), 3u);
    EXPECT_EQ(rows[1]["name"], "gcc-O0");
    EXPECT_EQ(rows[1]["status"], "did_not_compile");
    EXPECT_NE(rows[1]["failure"].get<std::string>().find("error"), std::string::npos);
    EXPECT_EQ(rows[2]["status"], "ran");
    EXPECT_EQ(rows[2]["precisions"][0]["answers_changed"], 0);
    EXPECT_NE(test_support::read_text(scratch / "r" / "report.md").find("### Builds"), std::string::npos);
}

TEST(BuildsCommand, ABuildThatCrashesWhileAuditedFailsItsRowAlone) {
    test_support::scratch_directory scratch("builds_crash");
    write_plugin(scratch.path(), "#ifndef __OPTIMIZE__\n#define CRASH_HERE raise(SIGSEGV);\n#else\n#define CRASH_HERE\n#endif\n");
    const auto ran = run_cli(builds_command(scratch, "--flags=-O0 --flags=-O2 --report " + (scratch / "r").string()));
    ASSERT_EQ(ran.exit_code, 1) << ran.output;  // a failed build is a finding
    EXPECT_NE(ran.output.find("gcc-O0 failed while audited, and is left out"), std::string::npos) << ran.output;
    EXPECT_NE(ran.output.find("SIGSEGV"), std::string::npos) << ran.output;
    const nlohmann::json report = nlohmann::json::parse(test_support::read_text(scratch / "r" / "report.json"));
    EXPECT_EQ(report["builds"]["rows"][1]["status"], "failed_in_audit");
    EXPECT_EQ(report["builds"]["rows"][2]["status"], "ran");
    for (const nlohmann::json& r : report["results"]) EXPECT_NE(r["variant"], "gcc-O0");  // nothing partial
}

TEST(BuildsCommand, ABuildThatHangsIsStoppedAndFailsItsRowAlone) {
    test_support::scratch_directory scratch("builds_hang");
    write_plugin(scratch.path(),
                 "#ifndef __OPTIMIZE__\n#define CRASH_HERE for (volatile int spin = 1; spin;) {}\n#else\n"
                 "#define CRASH_HERE\n#endif\n");
    const auto ran = run_cli(builds_command(scratch, "--flags=-O0 --flags=-O1 --plugin-timeout 1"));
    ASSERT_EQ(ran.exit_code, 1) << ran.output;
    EXPECT_NE(ran.output.find("gcc-O0 failed while audited, and is left out"), std::string::npos) << ran.output;
    EXPECT_NE(ran.output.find("gcc-O1                                 same answers as the reference"), std::string::npos)
        << ran.output;
}

TEST(BuildsCommand, NoCompilerLeftIsAnInputError) {
    test_support::scratch_directory scratch("builds_no_compiler");
    write_plugin(scratch.path(), "#define CRASH_HERE\n");
    const auto ran = test_support::run_shell("PATH=/nonexistent " RAYVERIFY_CLI " builds " +
                                             (scratch / "plugin.c").string() + " --cache " +
                                             (scratch / "cache").string());
    EXPECT_EQ(ran.exit_code, 2) << ran.output;
    EXPECT_NE(ran.output.find("builds: gcc is not on this machine"), std::string::npos) << ran.output;
    EXPECT_NE(ran.output.find("builds: clang is not on this machine"), std::string::npos) << ran.output;
    EXPECT_NE(ran.output.find("none of the compilers asked for is on this machine"), std::string::npos) << ran.output;
}

TEST(BuildsCommand, TheCacheReusesBuildsUntilAHeaderChanges) {
    test_support::scratch_directory scratch("builds_cache");
    write_plugin(scratch.path(), "#define CRASH_HERE\n");
    const std::string command = builds_command(scratch, "--flags=-O1 -I " + scratch.path().string());
    const auto first = run_cli(command);
    ASSERT_EQ(first.exit_code, 0) << first.output;
    EXPECT_NE(first.output.find("(2 compiled now, 0 from the cache"), std::string::npos) << first.output;
    const auto second = run_cli(command);
    ASSERT_EQ(second.exit_code, 0) << second.output;
    EXPECT_NE(second.output.find("(0 compiled now, 2 from the cache"), std::string::npos) << second.output;
    // A header the source includes changes the answers: both builds are rebuilt, and agree again.
    std::ofstream(scratch / "behaviour.h") << "#define SCALE 1.0000001\n";
    const auto third = run_cli(command);
    ASSERT_EQ(third.exit_code, 0) << third.output;
    EXPECT_NE(third.output.find("(2 compiled now, 0 from the cache"), std::string::npos) << third.output;
}

TEST(BuildsCommand, BadInputIsRefusedWithExitTwo) {
    test_support::scratch_directory scratch("builds_bad_input");
    write_plugin(scratch.path(), "#define CRASH_HERE\n#ifdef __OPTIMIZE__\nthis is not C;\n#endif\n");
    // The reference build itself does not compile: nothing to compare with.
    auto ran = run_cli(builds_command(scratch, "--flags=-O0"));
    EXPECT_EQ(ran.exit_code, 2) << ran.output;
    EXPECT_NE(ran.output.find("the reference build (gcc -O2 -ffp-contract=off -fno-fast-math) does not compile"),
              std::string::npos)
        << ran.output;
    ran = run_cli(builds_command(scratch, "--flags=\"-O2 -fplugin=./evil.so\""));
    EXPECT_EQ(ran.exit_code, 2) << ran.output;
    EXPECT_NE(ran.output.find("puts code of its choosing into the build"), std::string::npos) << ran.output;
    ran = run_cli("builds " + (scratch / "missing.c").string());
    EXPECT_EQ(ran.exit_code, 2) << ran.output;
    EXPECT_NE(ran.output.find("missing.c"), std::string::npos) << ran.output;
}

TEST(BuildsCommand, GatesAPinnedBuildAgainstItsBaseline) {
    test_support::scratch_directory scratch("builds_gate");
    write_plugin(scratch.path(), "#define CRASH_HERE\n");
    const std::string baseline = (scratch / "baseline.txt").string();
    auto ran = run_cli(builds_command(scratch, "--flags=\"release=-O3 -ffast-math\" --baseline " + baseline +
                                                   " --gate-build release --update"));
    ASSERT_EQ(ran.exit_code, 0) << ran.output;
    const std::string text = test_support::read_text(baseline);
    EXPECT_NE(text.find("release/double"), std::string::npos) << text;
    EXPECT_EQ(text.find("gcc-O2-ffp-contract"), std::string::npos) << text;  // only the pinned build
    ran = run_cli(builds_command(scratch, "--flags=\"release=-O3 -ffast-math\" --baseline " + baseline +
                                              " --gate-build release"));
    EXPECT_EQ(ran.exit_code, 0) << ran.output;
    ran = run_cli(builds_command(scratch, "--flags=\"release=-O3 -ffast-math\" --baseline " + baseline +
                                              " --gate-build relaese"));
    EXPECT_EQ(ran.exit_code, 2) << ran.output;
    EXPECT_NE(ran.output.find("no build is named 'relaese'"), std::string::npos) << ran.output;
}

// The shipped physics example (examples/physics_segment): under -ffast-math
// the clamp `if (t < 0) t = 0` becomes a max, which turns the NaN of an
// overflowing far start into a hit at 0, and the bisect names the flags.
TEST(BuildsCommand, PhysicsExampleFastMathNanBecomesAHitBisectedToItsFlags) {
    test_support::scratch_directory scratch("builds_physics");
    const std::string example = RAYVERIFY_SOURCE_DIR "/examples/physics_segment/";
    const auto ran = run_cli("builds " + example + "ray_sphere_cast.c --harness " + example +
                             "physics_segment_plugin.c --compiler gcc --flags=-O2 --flags=\"-O2 -ffast-math\" --cache " +
                             (scratch / "cache").string() + " --report " + (scratch / "r").string());
    ASSERT_EQ(ran.exit_code, 1) << ran.output;
    const nlohmann::json report = nlohmann::json::parse(test_support::read_text(scratch / "r" / "report.json"));
    const nlohmann::json& rows = report["builds"]["rows"];
    ASSERT_EQ(rows.size(), 3u);
    EXPECT_EQ(rows[1]["name"], "gcc-O2");
    EXPECT_EQ(rows[1]["precisions"][0]["answers_changed"], 0);
    const nlohmann::json& fast = rows[2];
    EXPECT_EQ(fast["name"], "gcc-O2-ffast-math");
    EXPECT_NE(fast["fp_environment"].get<std::string>().find("FTZ+DAZ"), std::string::npos);
    bool nan_to_hit = false;
    for (const nlohmann::json& f : fast["bisect"]["flips"])
        if (f["reference"] == "non_finite" && f["build"] == "false_hit") {
            nan_to_hit = true;
            const std::vector<std::string> smallest = f["smallest"];
            EXPECT_NE(std::find(smallest.begin(), smallest.end(), "-ffinite-math-only"), smallest.end()) << f.dump();
        }
    EXPECT_TRUE(nan_to_hit) << fast.dump();
    const auto valid = test_support::run_shell("/usr/bin/python3 " RAYVERIFY_SOURCE_DIR
                                               "/tests/support/validate_json.py " RAYVERIFY_SOURCE_DIR
                                               "/docs/schema report " +
                                               (scratch / "r" / "report.json").string());
    EXPECT_EQ(valid.exit_code, 0) << valid.output;
    for (const nlohmann::json& w : fast["precisions"][0]["worst"])
        if (w["reference_verdict"] == "non_finite" && w["build_verdict"] == "false_hit") {
            EXPECT_EQ(w["build_answer"], "t = 0") << w.dump();
        }
}

}  // namespace
}  // namespace rayverify
