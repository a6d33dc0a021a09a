// The command line as a person meets it: --version, errors prefixed
// "rayverify:" with a did-you-mean, help wrapped to the terminal, deprecated
// spellings, progress, --quiet and colour on a terminal (a pseudo-terminal
// from script(1)), the figure tolerance of diff, and the completions and man
// page generated from the command-line definition.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/build_info.h"
#include "support/process.h"

namespace rayverify {
namespace {

namespace fs = std::filesystem;
using test_support::command_result;
using test_support::read_text;
using test_support::run_cli;
using test_support::run_shell;

const std::string cli = RAYVERIFY_CLI;
const std::string corpus_dir = RAYVERIFY_CORPUS_DIR;

// The command run on a pseudo-terminal: its stdout and stderr are a tty.
command_result on_terminal(const std::string& arguments, const std::string& environment = "") {
    return run_shell("script -qec \"" + environment + " '" + cli + "' " + arguments + "\" /dev/null");
}

class Terminal : public ::testing::Test {
protected:
    test_support::scratch_directory scratch_{"rayverify_terminal_test"};
    const fs::path& dir_ = scratch_.path();
};

TEST_F(Terminal, VersionNamesTheReleaseAndTheBuild) {
    const command_result r = run_cli("--version");
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_TRUE(r.output.starts_with(std::string("rayverify ") + build_info::version + "\nbuild: " +
                                     build_info::compiler + " "))
        << r.output;
    EXPECT_NE(r.output.find("-ffp-contract=off"), std::string::npos);
}

TEST_F(Terminal, ParseErrorsArePrefixedAndSuggestTheNearestName) {
    const struct {
        const char* arguments;
        const char* error;
        const char* hint;
    } rows[] = {
        {"audti", "rayverify: error: 'audti' is not a rayverify command\n", "did you mean 'rayverify audit'?"},
        {"corpus genrate", "rayverify: error: 'genrate' is not a rayverify corpus command\n",
         "did you mean 'rayverify corpus generate'?"},
        {"audit --corpsu x", "rayverify: error: The following arguments were not expected: x --corpsu\n",
         "did you mean '--corpus' for '--corpsu'?"},
        {"gate --basline b.txt", "rayverify: error: ", "did you mean '--baseline' for '--basline'?"},
        {"audit --precision quad", "rayverify: error: --precision: quad not in {float,double}\n",
         "run 'rayverify audit --help' for the options"},
        {"", "rayverify: error: a command (rayverify --help lists them) is required\n", "run 'rayverify --help'"},
    };
    for (const auto& row : rows) {
        SCOPED_TRACE(row.arguments);
        const command_result r = run_cli(std::string(row.arguments));
        EXPECT_EQ(r.exit_code, 2);
        EXPECT_EQ(run_shell("{ '" + cli + "' " + row.arguments + " 2>/dev/null; }").output, "") << "nothing on stdout";
        const std::string& err = r.output;
        EXPECT_TRUE(err.starts_with(row.error)) << err;
        EXPECT_NE(err.find(row.hint), std::string::npos) << err;
    }
    // Far from every name: no guess.
    const command_result far = run_cli("zzzzzzzz");
    EXPECT_EQ(far.output.find("did you mean"), std::string::npos) << far.output;
}

TEST_F(Terminal, HelpIsWrappedToTheTerminalWidth) {
    for (const char* command : {"", "audit", "gate", "hunt", "merge", "corpus generate", "bench", "explain"}) {
        for (const int width : {60, 100}) {
            const command_result r = run_shell("COLUMNS=" + std::to_string(width) + " '" + cli + "' " + command +
                                               " --help");
            ASSERT_EQ(r.exit_code, 0) << command;
            std::istringstream lines(r.output);
            std::size_t longest = 0;
            for (std::string line; std::getline(lines, line);) longest = std::max(longest, line.size());
            EXPECT_LE(longest, static_cast<std::size_t>(width)) << command << "\n" << r.output;
            if (width == 100) {
                EXPECT_GT(longest, 60u) << "the width is used: " << command;
            }
        }
    }
}

TEST_F(Terminal, DeprecatedSpellingsStillWorkWithANote) {
    const command_result hunt = run_cli("hunt --variant naive --budget 0 --evaluations 200 -o " +
                                        (dir_ / "finds.txt").string());
    EXPECT_EQ(hunt.exit_code, 0) << hunt.output;
    EXPECT_NE(hunt.output.find("rayverify hunt: --budget is deprecated, use --seconds"), std::string::npos);
    EXPECT_TRUE(fs::exists(dir_ / "finds.txt"));

    const std::string shard = (dir_ / "shard").string();
    ASSERT_EQ(run_cli("audit --corpus " + corpus_dir + "/inside.txt --variant naive --shard 1/1 --report " + shard)
                  .exit_code,
              1);
    const command_result merge = run_cli("merge -o " + (dir_ / "merged").string() + " " + shard);
    EXPECT_EQ(merge.exit_code, 1) << merge.output;
    EXPECT_NE(merge.output.find("rayverify merge: -o,--output DIR for audit shards is deprecated, use --report DIR"), std::string::npos);
    EXPECT_TRUE(fs::exists(dir_ / "merged" / "report.json"));
    EXPECT_TRUE(fs::exists(dir_ / "merged" / "report.md"));
    EXPECT_EQ(run_cli("merge " + shard).exit_code, 2) << "the report directory is required";
}

TEST_F(Terminal, ProgressOnATerminalWithTotalAndEtaAndQuietSilencesIt) {
    const std::string audit = "audit --generate uniform:9000 --variant naive --threads 1";
    const command_result shown = on_terminal(audit);
    EXPECT_NE(shown.output.find("audit: 9000/9000 cases (100.0%)"), std::string::npos) << shown.output;
    EXPECT_NE(shown.output.find("ETA"), std::string::npos) << shown.output;
    const command_result quiet = on_terminal("-q " + audit);
    EXPECT_EQ(quiet.output.find("audit: "), std::string::npos) << quiet.output;
    EXPECT_NE(quiet.output.find("naive   double"), std::string::npos) << "stdout is unchanged";
    const command_result after = on_terminal(audit + " --quiet");
    EXPECT_EQ(after.output.find("audit: "), std::string::npos) << "--quiet after the command too";
    // Not a terminal: no progress.
    EXPECT_EQ(run_cli(audit).output.find("audit: "), std::string::npos);

    const command_result hunt = on_terminal("hunt --variant naive --seconds 1 -o " + (dir_ / "h.txt").string());
    EXPECT_NE(hunt.output.find("/1 s ("), std::string::npos) << hunt.output;
    EXPECT_NE(hunt.output.find("best so far"), std::string::npos) << hunt.output;
}

TEST_F(Terminal, GateColoursItsVerdictOnATerminalUnlessNoColor) {
    // A baseline of this run's target and family alone: a gate of part of a
    // larger baseline fails on what it leaves out (docs/gate.md).
    const std::string run = " --variant hearn_baker --corpus " + corpus_dir + "/far_sphere.txt";
    const std::string baseline = (dir_ / "baseline.txt").string();
    ASSERT_EQ(run_cli("gate --baseline " + baseline + run + " --update").exit_code, 0);
    const std::string gate = "gate --baseline " + baseline + run;
    EXPECT_NE(on_terminal(gate).output.find("\033[32mgate: passed"), std::string::npos);
    EXPECT_EQ(on_terminal(gate, "NO_COLOR=1").output.find('\033'), std::string::npos);
    EXPECT_EQ(on_terminal(gate, "TERM=dumb").output.find('\033'), std::string::npos);
    EXPECT_EQ(run_cli(gate).output.find('\033'), std::string::npos) << "not a terminal";
}

TEST_F(Terminal, DiffIgnoresLastDigitNoiseInUlpFiguresOnly) {
    ASSERT_EQ(run_cli("audit --corpus " + corpus_dir + "/far_sphere.txt --variant naive --report " +
                      (dir_ / "a").string()).exit_code,
              1);
    nlohmann::json report = nlohmann::json::parse(read_text(dir_ / "a" / "report.json"));
    auto& max = report["results"][1]["near_root_ulp"]["max"];
    const double exact = max.get<double>();
    const auto write = [&](const char* name, double value, int false_hit_delta) {
        nlohmann::json copy = report;
        copy["results"][1]["near_root_ulp"]["max"] = value;
        copy["results"][1]["verdicts"]["false_hit"] = copy["results"][1]["verdicts"]["false_hit"].get<int>() +
                                                      false_hit_delta;
        std::ofstream(dir_ / name) << copy.dump(2);
        return (dir_ / name).string();
    };
    const std::string a = write("a.json", exact, 0);
    const std::string noise = write("noise.json", exact * (1 + 1e-13), 0);
    const std::string worse = write("worse.json", exact * (1 + 1e-6), 0);
    const std::string count = write("count.json", exact, 1);
    EXPECT_EQ(run_cli("diff " + a + " " + noise).exit_code, 0) << run_cli("diff " + a + " " + noise).output;
    EXPECT_EQ(run_cli("diff --tolerance 0 " + a + " " + noise).exit_code, 1);
    EXPECT_EQ(run_cli("diff " + a + " " + worse).exit_code, 1);
    EXPECT_EQ(run_cli("diff --tolerance 1e-3 " + a + " " + count).exit_code, 1) << "counts are exact";
}

// Every visible option `rayverify COMMAND --help` lists.
std::vector<std::string> listed_options(const std::string& command) {
    const command_result help = run_cli(command + " --help");
    std::vector<std::string> out;
    std::istringstream lines(help.output);
    for (std::string line; std::getline(lines, line);) {
        std::istringstream words(line);
        std::string first;
        words >> first;
        for (std::size_t at = 0; at < first.size();) {
            const std::size_t comma = std::min(first.find(',', at), first.size());
            const std::string name = first.substr(at, comma - at);
            if (name.starts_with("--")) out.push_back(name);
            at = comma + 1;
        }
    }
    return out;
}

TEST_F(Terminal, BashCompletionIsGeneratedFromTheDefinitionAndCompletes) {
    const fs::path script = dir_ / "rayverify.bash";
    ASSERT_EQ(run_shell("'" + cli + "' --generate-completion bash > " + script.string()).exit_code, 0);
    ASSERT_EQ(run_shell("bash -n " + script.string()).exit_code, 0);
    const auto complete = [&](const std::string& words) {
        return run_shell("bash -c 'source " + script.string() + "; COMP_WORDS=(" + words +
                         "); COMP_CWORD=$((${#COMP_WORDS[@]} - 1)); _rayverify; echo \"${COMPREPLY[*]}\"'")
            .output;
    };
    EXPECT_EQ(complete("rayverify au"), "audit\n");
    EXPECT_EQ(complete("rayverify corpus ge"), "generate\n");
    EXPECT_EQ(complete("rayverify corpus generate --fam"), "--family\n");
    EXPECT_EQ(complete("rayverify audit --precision d"), "double\n");
    EXPECT_EQ(complete("rayverify audit --variant hearn_baker_unit_n"), "hearn_baker_unit_nearest\n");
    EXPECT_EQ(complete("rayverify hunt --sec"), "--seconds\n");
    EXPECT_EQ(complete("rayverify hunt --budg"), "\n") << "deprecated spellings are not offered";
    // Every word the option takes, from the one list its check uses (it offered 2 of 4).
    EXPECT_EQ(complete("rayverify hunt --objective \"\""), "ulp misclass scale_radius scale_distance\n");
    EXPECT_EQ(complete("rayverify hunt --objective sc"), "scale_radius scale_distance\n");
    EXPECT_EQ(complete("rayverify hunt --strategy \"\""), "search random\n");
    const std::string text = read_text(script);
    for (const char* command : {"audit", "gate", "hunt", "merge", "bench", "explain", "render", "recommend"})
        for (const std::string& option : listed_options(command)) {
            SCOPED_TRACE(std::string(command) + " " + option);
            EXPECT_NE(text.find(" " + option), std::string::npos);
        }
}

TEST_F(Terminal, ZshCompletionAndManPageAreGeneratedAndWellFormed) {
    const fs::path zsh = dir_ / "_rayverify", man = dir_ / "rayverify.1";
    ASSERT_EQ(run_shell("'" + cli + "' --generate-completion zsh > " + zsh.string()).exit_code, 0);
    ASSERT_EQ(run_shell("'" + cli + "' --generate-man > " + man.string()).exit_code, 0);
    const command_result zsh_syntax = run_shell("zsh -n " + zsh.string());
    EXPECT_EQ(zsh_syntax.exit_code, 0) << zsh_syntax.output;
    EXPECT_TRUE(read_text(zsh).starts_with("#compdef rayverify\n"));
    const command_result roff = run_shell("groff -man -Tutf8 -ww -z " + man.string());
    EXPECT_EQ(roff.exit_code, 0);
    EXPECT_EQ(roff.output, "") << "groff warnings";
    const std::string page = read_text(man), zsh_text = read_text(zsh);
    for (const char* command : {"audit", "gate", "hunt", "merge", "bench", "diff", "corpus generate"}) {
        EXPECT_NE(page.find(std::string(".SS \"rayverify ") + command + "\""), std::string::npos) << command;
        for (const std::string& option : listed_options(command)) {
            std::string escaped;
            for (char c : option) escaped += c == '-' ? std::string("\\-") : std::string(1, c);
            EXPECT_NE(page.find("\\fB" + escaped + "\\fR"), std::string::npos) << command << " " << option;
            EXPECT_NE(zsh_text.find(option + "["), std::string::npos) << command << " " << option;
        }
    }
}

}  // namespace
}  // namespace rayverify
