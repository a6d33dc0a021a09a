// Intersectors that do not run in rayverify's process, audited end to end:
// the textbook quadratic (the built-in `naive`) written in C (built strictly,
// and with -ffast-math -ffp-contract=fast as a GPU compiler would), in NumPy
// float32 and in JavaScript on Node.js (examples/other_languages/). Each
// exports cases, computes answers in its own language, and is audited with
// `audit --results` and hunted with `hunt --command`; the strict ones must
// give exactly the built-in variant's (or the same C compiled as a plugin's)
// table, gate and finds, the fast-math build must not.
#include <gtest/gtest.h>

#include <signal.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "support/process.h"
#include "support/results_program.h"

namespace {

namespace fs = std::filesystem;
using rayverify::test_support::read_text;
using rayverify::test_support::run_cli;
using rayverify::test_support::run_shell;
using rayverify::test_support::scratch_directory;

const std::string corpus = RAYVERIFY_CORPUS_DIR;
const std::string examples = std::string(RAYVERIFY_SOURCE_DIR) + "/examples/other_languages";
const std::string python = "/usr/bin/python3";
const std::string node = "node";
// The contract of naive, as `rayverify variants` states it.
const std::string naive_contract = "query=line_roots,reports_tangent=yes";

class OtherLanguages : public ::testing::Test {
protected:
    std::string at(const std::string& name) const { return (dir_ / name).string(); }

    scratch_directory scratch_{"rayverify_other"};
    const fs::path dir_ = scratch_.path();
};

// The summary table's row of `name` in `precision`, without the name: the figures.
std::string row_of(const std::string& output, const std::string& name, const std::string& precision) {
    std::istringstream lines(output);
    for (std::string line; std::getline(lines, line);) {
        std::istringstream words(line);
        std::string first, second;
        words >> first >> second;
        if (first == name && second == precision) {
            std::string rest, w;
            while (words >> w) rest += " " + w;
            return second + rest;
        }
    }
    return "(no row for " + name + "/" + precision + " in:\n" + output + ")";
}

std::string export_cases(const std::string& format, const std::string& precision, const std::string& out) {
    const auto r = run_cli("corpus export --corpus " + corpus + " --format " + format + " --precision " + precision +
                           " -o " + out);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return r.output;
}

TEST_F(OtherLanguages, StrictCResultsGiveExactlyThePluginsTableDiffAndGate) {
    export_cases("csv", "float", at("cases.csv"));
    const auto computed = run_shell(std::string(RAYVERIFY_NAIVE_C_STRICT) + " < " + at("cases.csv") + " > " + at("answers.csv"));
    ASSERT_EQ(computed.exit_code, 0) << computed.output;

    const auto plugin = run_cli("audit --corpus " + corpus + " --plugin " + RAYVERIFY_NAIVE_C_PLUGIN +
                                " --precision float --plots --report " + at("plugin"));
    const auto results = run_cli("audit --corpus " + corpus + " --results " + at("answers.csv") + " --contract " +
                                 naive_contract + " --name c_naive --plots --report " + at("results"));
    ASSERT_EQ(plugin.exit_code, 1) << plugin.output;  // naive disagrees somewhere on the shipped corpus
    ASSERT_EQ(results.exit_code, 1) << results.output;
    EXPECT_EQ(row_of(results.output, "c_naive", "float"), row_of(plugin.output, "c_naive", "float"));
    // Every figure of report.json, family by family, is the same.
    const auto diff = run_cli("diff " + at("plugin/report.json") + " " + at("results/report.json"));
    EXPECT_EQ(diff.exit_code, 0) << diff.output;
    EXPECT_NE(diff.output.find("0 worse, 0 better"), std::string::npos) << diff.output;
    // The same plots, drawn from the same figures.
    std::vector<std::string> plots;
    for (const auto& entry : fs::directory_iterator(at("plugin")))
        if (entry.path().extension() == ".png") plots.push_back(entry.path().filename().string());
    EXPECT_FALSE(plots.empty()) << plugin.output;
    for (const std::string& png : plots)
        EXPECT_EQ(read_text(at("results/" + png)), read_text(at("plugin/" + png))) << png;

    // The gate: a baseline made from the plugin passes the results, figure for figure.
    const auto made = run_cli("gate --baseline " + at("baseline.txt") + " --update --corpus " + corpus + " --plugin " +
                              RAYVERIFY_NAIVE_C_PLUGIN + " --precision float");
    ASSERT_EQ(made.exit_code, 0) << made.output;
    const auto gated = run_cli("gate --baseline " + at("baseline.txt") + " --corpus " + corpus + " --results " +
                               at("answers.csv") + " --contract " + naive_contract + " --name c_naive");
    EXPECT_EQ(gated.exit_code, 0) << gated.output;
}

TEST_F(OtherLanguages, FastMathBuildOfTheSameCFindsOtherThanTheStrictBuild) {
    export_cases("csv", "float", at("cases.csv"));
    for (const std::string build : {RAYVERIFY_NAIVE_C_STRICT, RAYVERIFY_NAIVE_C_FAST}) {
        const auto computed = run_shell(build + " < " + at("cases.csv") + " > " + at(fs::path(build).filename().string() + ".csv"));
        ASSERT_EQ(computed.exit_code, 0) << computed.output;
    }
    const auto strict = run_cli("audit --corpus " + corpus + " --results " + at("naive_c_strict.csv") + " --contract " +
                                naive_contract + " --name strict");
    const auto fast = run_cli("audit --corpus " + corpus + " --results " + at("naive_c_fast.csv") + " --contract " +
                              naive_contract + " --name fast");
    ASSERT_NE(strict.exit_code, 2) << strict.output;
    ASSERT_NE(fast.exit_code, 2) << fast.output;
    const std::string strict_row = row_of(strict.output, "strict", "float"), fast_row = row_of(fast.output, "fast", "float");
    EXPECT_NE(strict_row, fast_row) << "strict: " << strict_row << "\nfast:   " << fast_row;
    // The strict build is the built-in naive/float, verdict for verdict.
    const auto builtin = run_cli("audit --corpus " + corpus + " --variant naive --precision float");
    EXPECT_EQ(strict_row, row_of(builtin.output, "naive", "float"));
}

TEST_F(OtherLanguages, NumpyFloat32ThroughNpyFilesIsTheBuiltinNaiveInFloat) {
    export_cases("npy", "float", at("cases.npy"));
    ASSERT_TRUE(fs::exists(at("cases.json")));
    const auto computed = run_shell(python + " " + examples + "/naive_numpy.py " + at("cases.npy") + " " + at("answers.npy"));
    ASSERT_EQ(computed.exit_code, 0) << computed.output;
    const auto results = run_cli("audit --corpus " + corpus + " --results " + at("answers.npy") + " --contract " +
                                 naive_contract + " --name numpy_naive");
    const auto builtin = run_cli("audit --corpus " + corpus + " --variant naive --precision float");
    ASSERT_EQ(results.exit_code, 1) << results.output;
    EXPECT_EQ(row_of(results.output, "numpy_naive", "float"), row_of(builtin.output, "naive", "float"));
}

TEST_F(OtherLanguages, JavaScriptThroughJsonLinesIsTheBuiltinNaiveInDouble) {
    export_cases("jsonl", "double", at("cases.jsonl"));
    const auto computed = run_shell(node + " " + examples + "/naive.js < " + at("cases.jsonl") + " > " + at("answers.jsonl"));
    ASSERT_EQ(computed.exit_code, 0) << computed.output;
    const auto results = run_cli("audit --corpus " + corpus + " --results " + at("answers.jsonl") + " --contract " +
                                 naive_contract + " --name js_naive");
    const auto builtin = run_cli("audit --corpus " + corpus + " --variant naive --precision double");
    ASSERT_EQ(results.exit_code, 1) << results.output;
    EXPECT_EQ(row_of(results.output, "js_naive", "double"), row_of(builtin.output, "naive", "double"));
}

// explain's row of `label` ("naive/float"), without the label: verdict, cause, answer, ULPs.
std::string explain_row(const std::string& output, const std::string& label) {
    std::istringstream lines(output);
    for (std::string line; std::getline(lines, line);)
        if (line.starts_with(label + " ")) return line.substr(line.find_first_not_of(' ', label.size()));
    return "(no row for " + label + " in:\n" + output + ")";
}

TEST_F(OtherLanguages, ExplainAndSceneAuditJudgeResultsAsTheBuiltinVariant) {
    export_cases("csv", "float", at("cases.csv"));
    ASSERT_EQ(run_shell(std::string(RAYVERIFY_NAIVE_C_STRICT) + " < " + at("cases.csv") + " > " + at("answers.csv"))
                  .exit_code, 0);
    // far_sphere-1-000001: naive in float hits a sphere the exact ray misses.
    const auto explained = run_cli("explain --case far_sphere-1-000001 --corpus " + corpus + " --variant naive "
                                   "--precision float --results " + at("answers.csv") + " --contract " +
                                   naive_contract + " --name c_naive");
    ASSERT_EQ(explained.exit_code, 1) << explained.output;
    EXPECT_NE(explain_row(explained.output, "c_naive/float").find("false_hit"), std::string::npos) << explained.output;
    EXPECT_EQ(explain_row(explained.output, "c_naive/float"), explain_row(explained.output, "naive/float"));

    // A scene's (ray, sphere) pairs, whose ids hold commas ("px3,7/shadow/..."): quoted CSV cells.
    const std::string scene = corpus + "/scenes/secondary_self_hit.json";
    const auto exported = run_cli("corpus export --scene " + scene + " -o " + at("scene.csv"));
    ASSERT_EQ(exported.exit_code, 0) << exported.output;
    ASSERT_EQ(run_shell(std::string(RAYVERIFY_NAIVE_C_STRICT) + " < " + at("scene.csv") + " > " + at("scene_answers.csv"))
                  .exit_code, 0);
    const auto audited = run_cli("audit --scene " + scene + " --variant naive --results " + at("scene_answers.csv") +
                                 " --contract " + naive_contract + " --name c_naive");
    ASSERT_NE(audited.exit_code, 2) << audited.output;
    // Every table (primary, shadow, secondary rays) has both rows, figure for figure.
    std::istringstream lines(audited.output);
    std::vector<std::string> builtin_rows, results_rows;
    for (std::string line; std::getline(lines, line);) {
        const std::size_t first = line.find_first_not_of(' ');
        if (first == std::string::npos) continue;
        if (line.compare(first, 12, "naive/float ") == 0) builtin_rows.push_back(line.substr(first + 12));
        if (line.compare(first, 14, "c_naive/float ") == 0) results_rows.push_back(line.substr(first + 14));
    }
    ASSERT_GE(builtin_rows.size(), 2u) << audited.output;
    ASSERT_EQ(results_rows.size(), builtin_rows.size()) << audited.output;
    for (std::size_t i = 0; i < builtin_rows.size(); ++i) {
        // The label's padding differs by the two characters of "c_".
        const std::string want = builtin_rows[i].substr(builtin_rows[i].find_first_not_of(' '));
        EXPECT_EQ(results_rows[i].substr(results_rows[i].find_first_not_of(' ')), want) << audited.output;
    }
}

// Exported cases, the answers of the JavaScript and NumPy programs, and the .npy
// companions all conform to docs/schema (checked with Debian's python3-jsonschema).
TEST_F(OtherLanguages, ExportsAndAnswersFollowTheSchemaFile) {
    const std::string check = python + " " + RAYVERIFY_SOURCE_DIR + "/tests/support/check_exchange_schema.py " +
                              RAYVERIFY_SOURCE_DIR + "/docs/schema/rayverify-exchange-v1.json ";
    ASSERT_EQ(run_cli("corpus export --generate uniform:40 --generate inside:20 --format jsonl -o " + at("cases.jsonl")).exit_code, 0);
    ASSERT_EQ(run_cli("corpus export --generate uniform:40 --format jsonl --numbers hex -o " + at("hex.jsonl")).exit_code, 0);
    ASSERT_EQ(run_shell(node + " " + examples + "/naive.js < " + at("cases.jsonl") + " > " + at("answers.jsonl")).exit_code, 0);
    ASSERT_EQ(run_cli("corpus export --generate uniform:40 --precision float -o " + at("cases.npy")).exit_code, 0);
    ASSERT_EQ(run_shell(python + " " + examples + "/naive_numpy.py " + at("cases.npy") + " " + at("answers.npy")).exit_code, 0);
    const auto checked = run_shell(check + at("cases.jsonl") + " " + at("hex.jsonl") + " " + at("answers.jsonl") + " " +
                                   at("cases.json") + " " + at("answers.json"));
    EXPECT_EQ(checked.exit_code, 0) << checked.output;
    // The check can fail: a count that is not an integer.
    std::ofstream(at("bad.jsonl")) << read_text(at("answers.jsonl")) << "{\"id\":\"x\",\"count\":\"two\"}\n";
    const auto bad = run_shell(check + at("bad.jsonl"));
    EXPECT_EQ(bad.exit_code, 1) << bad.output;
    EXPECT_NE(bad.output.find("bad.jsonl:"), std::string::npos) << bad.output;
}

// The finds of a hunt, without its comments (which name the target and command).
std::string finds_of(const std::string& path) {
    std::istringstream lines(read_text(path));
    std::string out;
    for (std::string line; std::getline(lines, line);)
        if (!line.starts_with("#")) out += line.substr(line.find(' ')) + "\n";  // without the id (it names the target)
    return out;
}

TEST_F(OtherLanguages, HuntCommandInBatchesFindsWhatThePluginFinds) {
    const std::string common = " --precision float --objective misclass --family near_tangent --evaluations 400 "
                               "--budget 0 --batch 16 --finds 2 --seed 3";
    const auto plugin = run_cli("hunt --plugin " + std::string(RAYVERIFY_NAIVE_C_PLUGIN) + common + " -o " + at("plugin.txt"));
    const auto command = run_cli("hunt --command " + std::string(RAYVERIFY_NAIVE_C_STRICT) +
                                 " --format csv --contract " + naive_contract + " --name c_naive" + common + " -o " +
                                 at("command.txt"));
    ASSERT_NE(plugin.exit_code, 2) << plugin.output;
    ASSERT_EQ(command.exit_code, plugin.exit_code) << command.output;
    EXPECT_NE(command.output.find("batches of up to 16 cases"), std::string::npos) << command.output;
    EXPECT_EQ(finds_of(at("command.txt")), finds_of(at("plugin.txt")));
}

TEST_F(OtherLanguages, HuntCommandRunsNumpyAndNodeAndFastMathC) {
    const struct {
        std::string command, format, precision, name;
    } programs[] = {
        {python + " " + examples + "/naive_numpy.py --jsonl", "jsonl", "float", "numpy_naive"},
        {node + " " + examples + "/naive.js", "jsonl", "double", "js_naive"},
        {RAYVERIFY_NAIVE_C_FAST, "csv", "float", "fast_naive"},
    };
    for (const auto& p : programs) {
        const auto r = run_cli("hunt --command '" + p.command + "' --format " + p.format + " --precision " + p.precision +
                               " --contract " + naive_contract + " --name " + p.name +
                               " --objective misclass --family near_tangent --evaluations 200 --budget 0 --finds 1 "
                               "--no-shrink -o " + at(p.name + ".txt"));
        EXPECT_EQ(r.exit_code, 1) << p.command << "\n" << r.output;  // near tangents make naive disagree
        EXPECT_NE(r.output.find("answered"), std::string::npos) << r.output;
        EXPECT_TRUE(fs::exists(at(p.name + ".txt")));
    }
}

TEST_F(OtherLanguages, ProgramThatDiesHangsOrAnswersGarbageIsNamedWithItsCase) {
    const struct {
        std::string command, extra, expected;
    } programs[] = {
        {"exit 3", "", "exited with status 3"},
        {"sleep 30", " --command-timeout 0.5", "gave no answer within 0.5 s"},
        {"yes garbage", "", "answered with something that is not an answer to its batch"},
        {"head -c 10 /dev/zero; sleep 30", " --command-timeout 0.5", "gave no answer within 0.5 s"},
    };
    for (const auto& p : programs) {
        const auto r = run_cli("hunt --command '" + p.command + "' --format csv --contract " + naive_contract +
                               " --name broken --evaluations 20 --budget 0 --batch 1 -o " + at("finds.txt") + p.extra);
        EXPECT_EQ(r.exit_code, 2) << p.command << "\n" << r.output;
        EXPECT_NE(r.output.find("command '" + p.command + "' " + p.expected), std::string::npos) << r.output;
        EXPECT_NE(r.output.find("on case hunt-evaluation-1"), std::string::npos) << r.output;
        EXPECT_NE(r.output.find("the case, as a corpus line"), std::string::npos) << r.output;
        EXPECT_FALSE(fs::exists(at("finds.txt")));
    }
}

// A program that leaves out a value its contract needs (count 2 without t1
// under line_roots) is stopped and named with its case, as for any answer that
// is not one: no value it left out is judged.
TEST_F(OtherLanguages, ProgramThatLeavesOutAValueItsContractNeedsIsNamedWithItsCase) {
    // A shell loop, line by line (mawk would wait for more input than a batch).
    std::ofstream(at("half.sh")) << R"(while IFS= read -r line; do
  case $line in
    "# rayverify cases"*) h=""; for w in $line; do case $w in fingerprint=*|precision=*) h="$h $w";; esac; done
                          echo "# rayverify results v1$h";;
    id,*) echo "id,count,t0,t1";;
    *) echo "${line%%,*},2,1,";;
  esac
done
)";
    const auto r = run_cli("hunt --command 'sh " + at("half.sh") + "' --format csv --contract " + naive_contract +
                           " --name half --evaluations 20 --budget 0 --batch 1 -o " + at("finds.txt"));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("left out a value its contract needs"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("field 't1': missing: answer 'hunt-evaluation-1' has count 2"), std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find("the case, as a corpus line"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(at("finds.txt")));
}

// The program runs in a session of its own, and the whole session is killed
// when the hunt ends: a process it started in another process group (which
// a kill of its group missed) does not outlive the hunt.
TEST_F(OtherLanguages, WhatTheProgramStartsDoesNotOutliveTheHunt) {
    std::ofstream(at("p.py")) << "import json, os, sys, time\n"
                                 "child = os.fork()\n"
                                 "if child == 0:\n"
                                 "    os.setpgid(0, 0)\n"
                                 "    sys.stdout.close()\n"
                                 "    os.close(1)\n"
                                 "    open(sys.argv[1], 'w').write(str(os.getpid()))\n"
                                 "    time.sleep(120)\n"
                                 "    os._exit(0)\n"
                              << rayverify::test_support::miss_answering_loop();
    const auto r = run_cli("hunt --command 'python3 " + at("p.py") + " " + at("pid") + "' --contract " +
                           naive_contract + " --name leaver --evaluations 4 --budget 0 --no-shrink -o " + at("f.txt"));
    ASSERT_NE(r.exit_code, 2) << r.output;
    const std::string pid = read_text(at("pid"));
    ASSERT_FALSE(pid.empty());
    // Killed, then reaped by whoever inherited it: gone, or at most a zombie, within seconds.
    bool gone = false;
    for (int i = 0; i < 100 && !gone; ++i) {
        const std::string stat = read_text("/proc/" + pid + "/stat");
        gone = stat.empty() || stat.substr(stat.rfind(')') + 2, 1) == "Z";
        if (!gone) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    EXPECT_TRUE(gone) << "process " << pid << " outlived the hunt";
    if (!gone) ::kill(std::stoi(pid), SIGKILL);
}

}  // namespace
