// The truth sealed from the code it judges: a plugin that changes the
// floating-point environment (FTZ+DAZ, a rounding mode, trapped exceptions,
// the x87 control word), at load or in every batch, in process or isolated,
// on one thread or two, leaves every other target's verdicts, figures and
// per-case lines byte for byte those of a run without it; its own answers
// are those of its environment, which the report names. --fp-env runs a
// target in an environment of the user's choosing; the oracle stays exact.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "core/fp_environment.h"
#include "support/process.h"
#include "support/sampled_corpus.h"

namespace rayverify {
namespace {

using namespace test_support;

TEST(FpEnvironment, NamesParseAndPrintOneWay) {
    for (const char* name : {"ieee", "ftz", "daz", "ftz+daz", "upward", "downward", "toward_zero", "ftz+daz+upward"}) {
        const auto spec = parse_fp_environment(name);
        ASSERT_TRUE(spec) << name;
        EXPECT_EQ(fp_environment_name(*spec), name);
    }
    EXPECT_EQ(fp_environment_name(*parse_fp_environment("daz+ftz")), "ftz+daz");
    for (const char* bad : {"", "fast", "ftz+", "upward+downward", "FTZ", "ftz+daz+ieee"})
        EXPECT_FALSE(parse_fp_environment(bad)) << bad;
#if defined(__x86_64__)
    EXPECT_EQ(describe_fp_state(*fp_state_for(*parse_fp_environment("ftz+daz"))), "FTZ+DAZ");
    EXPECT_EQ(describe_fp_state(*fp_state_for(*parse_fp_environment("upward"))), "rounding upward");
    EXPECT_EQ(describe_fp_state(ieee_default_fp_state()), "the IEEE default");
#endif
}

TEST(FpEnvironment, RestoringTheDefaultUndoesWhatForeignCodeSet) {
    ASSERT_TRUE(is_ieee_default(current_fp_state()));
    const fp_state hostile = *fp_state_for(*parse_fp_environment("ftz+daz+toward_zero"));
    set_fp_state(hostile);
    EXPECT_EQ(current_fp_state(), hostile);
    volatile float tiny = 1e-40f;  // subnormal: flushed under DAZ
    EXPECT_EQ(tiny * 1.0f, 0.0f);
    EXPECT_TRUE(restore_ieee_default());
    EXPECT_TRUE(is_ieee_default(current_fp_state()));
    EXPECT_NE(tiny * 1.0f, 0.0f);
    EXPECT_FALSE(restore_ieee_default()) << "nothing left to restore";
}

struct audit_run {
    command_result ran;
    nlohmann::json report;
    std::vector<nlohmann::json> cases;
};

audit_run audit(const std::string& environment, const std::string& arguments, const std::string& tag) {
    const scratch_directory out("fp_env_" + tag);
    audit_run run;
    run.ran = run_shell(environment + " " RAYVERIFY_CLI " audit " + arguments + " --report '" +
                        (out.path() / "r").string() + "' --per-case '" + (out.path() / "cases.jsonl").string() + "'");
    if (run.ran.exit_code == 1) {
        run.report = nlohmann::json::parse(read_text(out.path() / "r" / "report.json"));
        std::istringstream lines(read_text(out.path() / "cases.jsonl"));
        for (std::string line; std::getline(lines, line);) run.cases.push_back(nlohmann::json::parse(line));
    }
    return run;
}

// The built-ins' results and per-case lines, with every trace of `plugin` removed.
std::string others_of(const audit_run& run, const std::string& plugin) {
    std::string out;
    for (const auto& r : run.report.at("results"))
        if (r.at("variant") != plugin) out += r.dump() + "\n";
    for (nlohmann::json c : run.cases) {
        for (const char* prec : {"/float", "/double"}) c.at("results").erase(plugin + prec);
        out += c.dump() + "\n";
    }
    return out;
}

std::string builtins_on(const std::filesystem::path& corpus) {
    return "--variant naive --variant robust --corpus '" + corpus.string() + "'";
}
const std::string builtins = builtins_on(RAYVERIFY_CORPUS_DIR "/edge");

struct hostile {
    const char* fixture;
    const char* name;
    const char* mode;
    const char* report_says;  // in the report's fp_environment of the plugin, or a warning on stderr
    bool at_load;
};

const hostile hostile_plugins[] = {
    {RAYVERIFY_FIXTURE_FP_HOSTILE, "fp_hostile", "load_ftz_daz",
     "FTZ+DAZ, set when the library loaded (what GCC's crtfastmath.o sets: linked with -ffast-math?)", true},
    {RAYVERIFY_FIXTURE_FP_HOSTILE, "fp_hostile", "load_upward", "rounding upward, set when the library loaded", true},
    {RAYVERIFY_FIXTURE_FP_HOSTILE, "fp_hostile", "load_x87", "x87 precision single, set when the library loaded", true},
    {RAYVERIFY_FIXTURE_FP_FAST_MATH_LINK, "fp_fast_math_link", "",
     "FTZ+DAZ, set when the library loaded (what GCC's crtfastmath.o sets: linked with -ffast-math?)", true},
    {RAYVERIFY_FIXTURE_FP_HOSTILE, "fp_hostile", "batch_ftz_daz", "to FTZ+DAZ (it was given the IEEE default)", false},
    {RAYVERIFY_FIXTURE_FP_HOSTILE, "fp_hostile", "batch_downward", "to rounding downward", false},
    {RAYVERIFY_FIXTURE_FP_HOSTILE, "fp_hostile", "batch_toward_zero", "to rounding toward zero", false},
    {RAYVERIFY_FIXTURE_FP_HOSTILE, "fp_hostile", "batch_unmask",
     "to FE_INVALID trapped, FE_DIVBYZERO trapped, FE_OVERFLOW trapped", false},
    {RAYVERIFY_FIXTURE_FP_HOSTILE, "fp_hostile", "batch_x87", "to x87 precision single", false},
};

// Every environment change, at load and in every batch, in process on one
// thread and two, and isolated: the built-ins' verdicts, figures and per-case
// lines are byte for byte those of a run without the plugin, and the report
// (or, for a change in a batch, one warning) names what the plugin did.
TEST(FpEnvironment, AHostilePluginLeavesEveryOtherTargetAsARunWithoutIt) {
    const sampled_corpus edge(RAYVERIFY_CORPUS_DIR "/edge");  // 29 audits of it
    const std::string builtins_on_edge = builtins_on(edge.path());
    std::map<std::string, std::string> clean;
    for (const char* threads : {"1", "2"}) {
        const audit_run run = audit("", builtins_on_edge + " --threads " + threads, std::string("clean") + threads);
        ASSERT_EQ(run.ran.exit_code, 1) << run.ran.output;
        clean[threads] = others_of(run, "-");
    }
    EXPECT_EQ(clean["1"], clean["2"]);
    for (const hostile& h : hostile_plugins) {
        for (const char* how : {"--threads 1", "--threads 2", "--isolate"}) {
            SCOPED_TRACE(std::string(h.name) + " " + h.mode + " " + how);
            const audit_run run = audit(std::string("FIXTURE_FP_MODE=") + h.mode,
                                        builtins_on_edge + " --plugin '" + h.fixture + "' " + how, h.mode);
            ASSERT_EQ(run.ran.exit_code, 1) << run.ran.output;
            EXPECT_EQ(others_of(run, h.name), clean[std::string(how) == "--threads 2" ? "2" : "1"]);
            std::string said;
            for (const auto& r : run.report.at("results"))
                if (r.at("variant") == h.name) said = r.value("fp_environment", std::string());
            if (h.at_load) {
                EXPECT_EQ(said, h.report_says);
                EXPECT_NE(run.ran.output.find(std::string("fp environment: ") + h.name + " runs in " + h.report_says),
                          std::string::npos)
                    << run.ran.output;
            } else {
                EXPECT_EQ(said, "") << "it was given the IEEE default";
                if (std::string(how) != "--isolate") {
                    const std::string warning = std::string("warning: target '") + h.name +
                                                "' changed the floating-point environment in a call, " + h.report_says;
                    const std::size_t first = run.ran.output.find(warning);
                    EXPECT_NE(first, std::string::npos) << run.ran.output;
                    EXPECT_EQ(run.ran.output.find(warning, first + 1), std::string::npos) << "once per target";
                }
            }
        }
    }
}

// A plugin that traps FE_INVALID from its load runs in that environment: its
// first NaN is a SIGFPE inside its own batch, that target's failure (exit 2,
// named), never the tool's.
TEST(FpEnvironment, AnExceptionTheLibraryTrapsIsItsOwnFailure) {
    for (const char* how : {"", "--isolate"}) {
        const command_result ran = run_shell("FIXTURE_FP_MODE=load_unmask_invalid " RAYVERIFY_CLI " audit " + builtins +
                                             " --plugin '" RAYVERIFY_FIXTURE_FP_HOSTILE "' " + how);
        EXPECT_EQ(ran.exit_code, 2) << how << "\n" << ran.output;
        EXPECT_NE(ran.output.find("SIGFPE"), std::string::npos) << how << "\n" << ran.output;
        EXPECT_NE(ran.output.find("fp_hostile"), std::string::npos) << how << "\n" << ran.output;
    }
}

// -ffast-math on a plugin's link line through the CMake package: plugin_api's
// -fno-fast-math keeps crtfastmath.o out, and the plugin leaves the IEEE default.
TEST(FpEnvironment, ThePackagesPluginApiKeepsCrtfastmathOutOfTheLink) {
    const audit_run run = audit("", builtins + " --plugin '" RAYVERIFY_FIXTURE_FP_FAST_MATH_PACKAGE "'", "package");
    ASSERT_EQ(run.ran.exit_code, 1) << run.ran.output;
    for (const auto& r : run.report.at("results")) EXPECT_FALSE(r.contains("fp_environment")) << r.at("variant");
    EXPECT_EQ(run.ran.output.find("fp environment:"), std::string::npos) << run.ran.output;
}

// --fp-env: a built-in run under FTZ+DAZ answers as that environment makes it
// (it flushes the edge corpus's subnormals), the exact answers stay the same
// bit for bit, and the report names the environment; a target named alone
// keeps the others in the IEEE default.
TEST(FpEnvironment, FpEnvRunsATargetAsDeployedAndTheOracleStaysExact) {
    const audit_run ieee = audit("", "--variant naive " + std::string("--corpus " RAYVERIFY_CORPUS_DIR "/edge"), "ieee");
    const audit_run flushed =
        audit("", "--variant naive --fp-env ftz+daz --corpus " RAYVERIFY_CORPUS_DIR "/edge", "flushed");
    ASSERT_EQ(ieee.ran.exit_code, 1) << ieee.ran.output;
    ASSERT_EQ(flushed.ran.exit_code, 1) << flushed.ran.output;
    ASSERT_EQ(ieee.cases.size(), flushed.cases.size());
    std::size_t answers_changed = 0;
    for (std::size_t i = 0; i < ieee.cases.size(); ++i) {
        EXPECT_EQ(ieee.cases[i].value("exact", nlohmann::json()), flushed.cases[i].value("exact", nlohmann::json()))
            << ieee.cases[i].at("id");
        answers_changed += ieee.cases[i].at("results") != flushed.cases[i].at("results");
    }
    EXPECT_GT(answers_changed, 0u) << "FTZ+DAZ changes the textbook formula's answers on subnormal inputs";
    EXPECT_EQ(flushed.report.at("results").at(0).at("fp_environment"), "FTZ+DAZ (--fp-env ftz+daz)");
    EXPECT_NE(flushed.ran.output.find("fp environment: naive runs in FTZ+DAZ (--fp-env ftz+daz)"), std::string::npos);

    const audit_run one = audit("", "--variant naive --variant robust --fp-env naive=ftz+daz --corpus " RAYVERIFY_CORPUS_DIR
                                     "/edge",
                                "one");
    ASSERT_EQ(one.ran.exit_code, 1) << one.ran.output;
    for (const auto& r : one.report.at("results"))
        EXPECT_EQ(r.contains("fp_environment"), r.at("variant") == "naive") << r.at("variant");

    for (const std::string& bad : {std::string("--fp-env fast"), std::string("--fp-env nosuch=ftz"),
                                   std::string("--fp-env ftz --fp-env daz"), std::string("--fp-env upward+downward")}) {
        const command_result refused = run_cli("audit --variant naive " + bad);
        EXPECT_EQ(refused.exit_code, 2) << bad << "\n" << refused.output;
        EXPECT_NE(refused.output.find("--fp-env"), std::string::npos) << bad << "\n" << refused.output;
    }
}

}  // namespace
}  // namespace rayverify
