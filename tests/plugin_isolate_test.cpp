// Plugins that crash or hang. With --isolate a plugin runs in a
// child process: a crash, an exit or a hang stops the run with exit 2, a
// message naming the plugin, what happened and the case, the case as a
// corpus line, and no output left behind. Without it, the crash still names
// the case before rayverify dies. Fixtures: tests/plugin_fixtures/fixture_plugin.c
// ("crashy": radius 3 SIGSEGV, 4 abort(), 5 exit(7); "hangs": radius 3 never returns).
#include <gtest/gtest.h>

#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>

#include "corpus/corpus_io.h"
#include "plugin/plugin_loader.h"
#include "support/process.h"

namespace rayverify {
namespace {

namespace fs = std::filesystem;
using namespace test_support;

const std::string crashy = RAYVERIFY_FIXTURE_PLUGIN_CRASH;
const std::string hangs = RAYVERIFY_FIXTURE_PLUGIN_HANG;
const std::string good = RAYVERIFY_EXAMPLE_PLUGIN;

// A scratch directory of the test's own, removed at the end.
class PluginIsolate : public ::testing::Test {
protected:
    // Two good cases, then one with radius r on line 3.
    fs::path corpus_with_radius(const std::string& r) const {
        const fs::path file = dir_ / "cases.txt";
        std::ofstream(file) << "ok-1 - 0 0 -5 0 0 1 0 0 0 1\n"
                               "ok-2 - 0.5 0 -5 0 0 1 0 0 0 2\n"
                               "boom - 0 0 -9 0 0 1 0 0 0 " + r + "\n";
        return file;
    }

    scratch_directory scratch_{"rayverify_isolate"};
    const fs::path dir_ = scratch_.path();
};

TEST_F(PluginIsolate, CrashIsAnErrorNamingTheCaseWithItsCorpusLineAndLeavesNoOutput) {
    const fs::path corpus = corpus_with_radius("3");
    const fs::path report = dir_ / "report";
    const command_result r = run_cli("audit --plugin " + crashy + " --isolate --corpus " + corpus.string() +
                                     " --report " + report.string() + " --per-case " + (dir_ / "cases.jsonl").string());
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("rayverify: error: " + crashy + ": field '--plugin': plugin 'crashy' was killed by "
                            "SIGSEGV (Segmentation fault) on case boom (" + corpus.string() +
                            ":3), in its float function\n"),
              std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find("  the case, as a corpus line:\n  boom - 0x0p+0 0x0p+0 -0x1.2p+3 0x0p+0 0x0p+0 0x1p+0 "
                            "0x0p+0 0x0p+0 0x0p+0 0x1.8p+1\n"),
              std::string::npos)
        << r.output;
    EXPECT_FALSE(fs::exists(report)) << "a failed audit leaves no report directory";
    EXPECT_FALSE(fs::exists(dir_ / "cases.jsonl"));
    EXPECT_EQ(r.output.find("variant"), std::string::npos) << "no summary table: " << r.output;
}

TEST_F(PluginIsolate, AbortAndExitAreNamedToo) {
    const command_result aborted =
        run_cli("explain \"0 0 -9 0 0 1 0 0 0 4\" --precision double --isolate --plugin " + crashy);
    EXPECT_EQ(aborted.exit_code, 2) << aborted.output;
    EXPECT_NE(aborted.output.find("plugin 'crashy' was killed by SIGABRT (Aborted) on case command-line "
                                  "(<command line>), in its double function"),
              std::string::npos)
        << aborted.output;
    const command_result exited = run_cli("explain \"0 0 -9 0 0 1 0 0 0 5\" --isolate --plugin " + crashy);
    EXPECT_EQ(exited.exit_code, 2) << exited.output;
    EXPECT_NE(exited.output.find("plugin 'crashy' exited with status 7 on case command-line"), std::string::npos)
        << exited.output;
}

// The same misbehaviour in this process and isolated: exit 2 with the same words.
TEST_F(PluginIsolate, WritesOutsideTheRootsAndBrokenLibrariesAreNamedEitherWay) {
    const std::string modal = RAYVERIFY_FIXTURE_PLUGIN_MODAL;
    for (const char* isolate : {"", " --isolate"}) {
        SCOPED_TRACE(isolate);
        for (const char* mode : {"overrun", "underrun"}) {
            const command_result r = run_shell(std::string("FIXTURE_MODE=") + mode + " '" RAYVERIFY_CLI "' explain "
                                               "\"0 0 -9 0 0 1 0 0 0 4\" --precision double --plugin " + modal + isolate);
            EXPECT_EQ(r.exit_code, 2) << r.output;
            EXPECT_NE(r.output.find("rayverify: error: " + modal + ": field '--plugin': plugin 'modal' wrote outside "
                                    "its roots[2] buffer on case command-line (<command line>), in its double function"),
                      std::string::npos)
                << r.output;
        }
        // A library cut after its first page: SIGBUS when dlopen maps the rest.
        const fs::path cut = dir_ / "cut.so";
        fs::copy_file(RAYVERIFY_FIXTURE_PLUGIN_GARBAGE, cut, fs::copy_options::overwrite_existing);
        fs::resize_file(cut, 4096);
        const command_result audit = run_cli("audit --corpus " + corpus_with_radius("1").string() + " --plugin " +
                                             cut.string() + isolate);
        EXPECT_EQ(audit.exit_code, 2) << audit.output;
        EXPECT_NE(audit.output.find(*isolate ? "its process was killed by SIGBUS (Bus error) while loading it"
                                             : "crashed (SIGBUS) while loading it"),
                  std::string::npos)
            << audit.output;
    }
}

TEST_F(PluginIsolate, HangIsKilledAfterTheTimeoutAndNamesTheCase) {
    const fs::path corpus = corpus_with_radius("3");
    const auto began = std::chrono::steady_clock::now();
    const command_result r = run_cli("audit --plugin " + hangs + " --isolate --plugin-timeout 1 --corpus " +
                                     corpus.string() + " --report " + (dir_ / "report").string());
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count();
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("plugin 'hangs' gave no answer within 1 s (its process was killed) on case boom (" +
                            corpus.string() + ":3)"),
              std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find("  boom - "), std::string::npos) << r.output;
    EXPECT_LT(seconds, 8) << "the timeout is 1 s";
    EXPECT_FALSE(fs::exists(dir_ / "report"));
}

// In process, a crash is bad input as isolated (exit 2, CLARIFICATIONS): named, and no output left.
TEST_F(PluginIsolate, WithoutIsolateACrashStillNamesTheCase) {
    const fs::path corpus = corpus_with_radius("3");
    const command_result r = run_cli("audit --plugin " + crashy + " --corpus " + corpus.string() + " --report " +
                                     (dir_ / "report").string() + " --per-case " + (dir_ / "cases.jsonl").string());
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("rayverify: error: " + crashy + ": field '--plugin': plugin 'crashy' crashed (SIGSEGV) "
                            "on case boom (" + corpus.string() + ":3), in its float function; rerun with --isolate"),
              std::string::npos)
        << r.output;
    EXPECT_FALSE(fs::exists(dir_ / "report"));
    EXPECT_FALSE(fs::exists(dir_ / "cases.jsonl"));
    const command_result aborted = run_cli("explain \"0 0 -9 0 0 1 0 0 0 4\" --plugin " + crashy);
    EXPECT_EQ(aborted.exit_code, 2) << aborted.output;
    EXPECT_NE(aborted.output.find("plugin 'crashy' crashed (SIGABRT) on case command-line (<command line>)"),
              std::string::npos)
        << aborted.output;
}

// Isolation changes where the plugin runs, never a figure: the same report.json and per-case lines, byte for byte.
TEST_F(PluginIsolate, GoodPluginsGiveTheSameReportIsolatedOrNot) {
    const std::string common = "audit --plugin " + good + " --plugin " + crashy + " --corpus " RAYVERIFY_CORPUS_DIR
                               "/uniform.txt --corpus " RAYVERIFY_CORPUS_DIR "/tangent_exact.txt";
    const command_result plain = run_cli(common + " --report " + (dir_ / "plain").string() + " --per-case " +
                                         (dir_ / "plain.jsonl").string());
    const command_result isolated = run_cli(common + " --isolate --plugin-timeout 30 --report " +
                                            (dir_ / "isolated").string() + " --per-case " +
                                            (dir_ / "isolated.jsonl").string());
    ASSERT_EQ(plain.exit_code, 1) << plain.output;  // the textbook fixture disagrees on tangents
    ASSERT_EQ(isolated.exit_code, 1) << isolated.output;
    const std::string report = read_text(dir_ / "plain" / "report.json");
    EXPECT_GT(report.size(), 1000u);
    EXPECT_EQ(report, read_text(dir_ / "isolated" / "report.json"));
    EXPECT_EQ(read_text(dir_ / "plain.jsonl"), read_text(dir_ / "isolated.jsonl"));
}

TEST_F(PluginIsolate, HuntAndGateTakeIsolate) {
    const auto finds = [](const std::string& text) {
        std::istringstream in(text);
        std::string out;
        for (std::string line; std::getline(in, line);)
            if (!line.starts_with("#")) out += line + "\n";
        return out;
    };
    const std::string hunt = "hunt --plugin " + good + " --objective misclass --seconds 0 --evaluations 300 -o ";
    const command_result plain = run_cli(hunt + (dir_ / "plain.txt").string());
    const command_result isolated = run_cli(hunt + (dir_ / "isolated.txt").string() + " --isolate");
    EXPECT_EQ(plain.exit_code, isolated.exit_code) << plain.output << isolated.output;
    EXPECT_EQ(finds(read_text(dir_ / "plain.txt")), finds(read_text(dir_ / "isolated.txt")));

    const command_result gate = run_cli("gate --plugin " + good + " --isolate --corpus " RAYVERIFY_CORPUS_DIR
                                        "/uniform.txt --update --baseline " + (dir_ / "baseline.txt").string());
    EXPECT_EQ(gate.exit_code, 0) << gate.output;

    const command_result needs = run_cli("audit --plugin " + good + " --plugin-timeout 3");
    EXPECT_EQ(needs.exit_code, 2) << needs.output;
    EXPECT_NE(needs.output.find("--plugin-timeout requires --isolate"), std::string::npos) << needs.output;
}

// In the library: the bits cross the socket exactly (NaN, subnormals, signed zeros), and a failed
// plugin keeps failing. Outside an audited case, the failure carries the inputs it was given.
TEST(PluginIsolateLibrary, InputsAndResultsCrossExactly) {
    const variant in_process = load_plugin(crashy);
    const variant isolated = load_plugin(crashy, {.child_process = true, .timeout_seconds = 30});
    std::mt19937_64 random(8);
    const auto any_double = [&] {
        const double specials[] = {0.0, -0.0, 1.0, 2.0, 0x1p-1074, -0x1p-1022, std::numeric_limits<double>::quiet_NaN(),
                                   std::numeric_limits<double>::infinity(), 1e300};
        if (random() % 4 == 0) return specials[random() % std::size(specials)];
        return std::ldexp(static_cast<double>(random() % 2000001) - 1e6, static_cast<int>(random() % 80) - 40);
    };
    for (int i = 0; i < 2000; ++i) {
        ray_sphere<double> s{{any_double(), any_double(), any_double()},
                             {any_double(), any_double(), any_double()},
                             {any_double(), any_double(), any_double()},
                             any_double()};
        if (s.radius == 3 || s.radius == 4 || s.radius == 5) s.radius = 6;
        const root_pair<double> a = in_process.run_double(s), b = isolated.run_double(s);
        ASSERT_EQ(a.count, b.count) << "case " << i;
        ASSERT_EQ(std::bit_cast<std::uint64_t>(a.t0), std::bit_cast<std::uint64_t>(b.t0)) << "case " << i;
        ASSERT_EQ(std::bit_cast<std::uint64_t>(a.t1), std::bit_cast<std::uint64_t>(b.t1)) << "case " << i;
        const ray_sphere<float> f = rounded_to<float>(s);
        if (f.radius == 3 || f.radius == 4 || f.radius == 5) continue;
        const root_pair<float> x = in_process.run_float(f), y = isolated.run_float(f);
        ASSERT_EQ(x.count, y.count) << "case " << i;
        ASSERT_EQ(std::bit_cast<std::uint32_t>(x.t0), std::bit_cast<std::uint32_t>(y.t0)) << "case " << i;
        ASSERT_EQ(std::bit_cast<std::uint32_t>(x.t1), std::bit_cast<std::uint32_t>(y.t1)) << "case " << i;
    }

    const ray_sphere<double> boom{{0, 0, -9}, {0, 0, 1}, {0, 0, 0}, 3};
    try {
        isolated.run_double(boom);
        FAIL() << "the crash must throw";
    } catch (const plugin_failure& e) {
        EXPECT_NE(std::string(e.what()).find("plugin 'crashy' was killed by SIGSEGV (Segmentation fault) on inputs "
                                             "given outside any audited case, in its double function"),
                  std::string::npos)
            << e.what();
        EXPECT_EQ(format_case_line(e.failing_case()),
                  "plugin-failure - 0x0p+0 0x0p+0 -0x1.2p+3 0x0p+0 0x0p+0 0x1p+0 0x0p+0 0x0p+0 0x0p+0 0x1.8p+1");
    }
    try {
        isolated.run_double({{0, 0, -5}, {0, 0, 1}, {0, 0, 0}, 1});
        FAIL() << "a failed plugin keeps failing";
    } catch (const plugin_failure& e) {
        EXPECT_NE(std::string(e.what()).find("is no longer running (it failed on an earlier call)"), std::string::npos)
            << e.what();
    }
}

TEST(PluginIsolateLibrary, UnusableLibrariesGiveTheSameErrorsIsolated) {
    for (const std::string& library : {std::string(RAYVERIFY_FIXTURE_PLUGIN_BAD_ABI),
                                       std::string(RAYVERIFY_FIXTURE_PLUGIN_NO_DOUBLE), std::string("./nowhere.so")}) {
        std::string plain, isolated;
        try {
            load_plugin(library);
        } catch (const input_error& e) {
            plain = e.what();
        }
        try {
            load_plugin(library, {.child_process = true});
        } catch (const input_error& e) {
            isolated = e.what();
        }
        EXPECT_FALSE(plain.empty()) << library;
        EXPECT_EQ(plain, isolated);
    }
}

}  // namespace
}  // namespace rayverify
