// The engines' libraries as their packages install them (cli/shipped_libraries.h):
// `rayverify engines` lists each with version, source, precision, contract and
// status; --engine audits one like a variant; `audit --command` asks a program
// for the whole input batch by batch; a results file of hit points
// (answer=point) is judged through the t derived from each point, as the
// built-in point engines are. tools/setup.sh installs the libraries (apt and
// `npm ci`): the tests that need one say so when it is missing.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "support/process.h"

namespace {

namespace fs = std::filesystem;
using rayverify::test_support::read_text;
using rayverify::test_support::run_cli;
using rayverify::test_support::run_shell;
using rayverify::test_support::scratch_directory;

const std::string corpus = RAYVERIFY_CORPUS_DIR;
const std::string js_engines = std::string(RAYVERIFY_SOURCE_DIR) + "/engines/js";

class ShippedLibraries : public ::testing::Test {
protected:
    std::string at(const std::string& name) const { return (dir_ / name).string(); }
    void write(const std::string& name, const std::string& text) const { std::ofstream(at(name)) << text; }

    scratch_directory scratch_{"rayverify_shipped"};
    const fs::path dir_ = scratch_.path();
};

// The summary table's row of `name`, without the name, one space between figures.
std::string row_of(const std::string& output, const std::string& name) {
    std::istringstream lines(output);
    for (std::string line; std::getline(lines, line);) {
        std::istringstream words(line);
        std::string first, rest;
        words >> first;
        if (first != name) continue;
        for (std::string w; words >> w;) rest += " " + w;
        return rest;
    }
    return "(no row for " + name + " in:\n" + output + ")";
}

// `rayverify engines`' line for `name`, empty when there is none.
std::string engine_line(const std::string& listing, const std::string& name) {
    std::istringstream lines(listing);
    for (std::string line; std::getline(lines, line);)
        if (line.rfind(name + " ", 0) == 0) return line;
    return {};
}

bool javascript_installed() { return fs::exists(js_engines + "/node_modules/three/package.json"); }

TEST_F(ShippedLibraries, EnginesListsEveryLibraryWithVersionSourcePrecisionContractAndStatus) {
    const auto r = run_cli("engines");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    // Each line: name, version, source (two words), precision, contract, then the status.
    const std::regex line_form(R"(^(\S+) +(\S+) +(Debian package \S+|npm package \S+) +(float|double|float,double|-) +)"
                               R"((\S+) +(available|not available: .+)$)");
    for (const std::string name : {"three", "babylonjs", "playcanvas", "cannon_es", "rapier3d"}) {
        const std::string line = engine_line(r.output, name);
        ASSERT_FALSE(line.empty()) << name << " is not listed:\n" << r.output;
        std::smatch m;
        ASSERT_TRUE(std::regex_match(line, m, line_form)) << line;
        EXPECT_NE(m[5].str().find("query="), std::string::npos) << line;
    }
    // Each npm package's version is the installed package.json's.
    if (javascript_installed()) {
        const std::string pinned = read_text(js_engines + "/node_modules/three/package.json");
        std::smatch version;
        ASSERT_TRUE(std::regex_search(pinned, version, std::regex(R"re("version"\s*:\s*"([^"]+)")re")));
        EXPECT_NE(engine_line(r.output, "three").find(" " + version[1].str() + " "), std::string::npos)
            << engine_line(r.output, "three");
    }
}

TEST_F(ShippedLibraries, AnUnknownOrMissingEngineIsAnInputErrorSayingWhatToDo) {
    const auto unknown = run_cli("audit --engine no_such_engine");
    EXPECT_EQ(unknown.exit_code, 2) << unknown.output;
    EXPECT_NE(unknown.output.find("unknown engine library 'no_such_engine'"), std::string::npos) << unknown.output;
    EXPECT_NE(unknown.output.find("three"), std::string::npos) << "the known ones are listed:\n" << unknown.output;
}

// The three.js library from npm, whose point answers are judged through the
// derived t, and the built-in port of the same code agree case for case.
TEST_F(ShippedLibraries, ThreeFromNpmIsJudgedLikeTheBuiltInPortOfTheSameCode) {
    if (!javascript_installed()) GTEST_FAIL() << "npm packages missing: run tools/setup.sh (npm ci in engines/js)";
    const auto library = run_cli("audit --corpus " + corpus + " --engine three");
    const auto port = run_cli("audit --corpus " + corpus + " --variant threejs --precision double");
    ASSERT_EQ(library.exit_code, 1) << library.output;
    ASSERT_EQ(port.exit_code, 1) << port.output;
    EXPECT_EQ(row_of(library.output, "three"), row_of(port.output, "threejs"));
    EXPECT_NE(library.output.find("library: three is three.js "), std::string::npos) << library.output;
}

// The engines' node runs in an environment rayverify builds: a caller's
// NODE_OPTIONS that replaces Math.sqrt changes nothing audited, and one with
// a typo does not make node look missing.
TEST_F(ShippedLibraries, TheCallersNodeOptionsNeverReachTheEnginesNode) {
    if (!javascript_installed()) GTEST_FAIL() << "npm packages missing: run tools/setup.sh (npm ci in engines/js)";
    const scratch_directory dir("node_options");
    std::ofstream(dir.path() / "sqrt.js") << "Math.sqrt = (x) => 1;\n";
    const auto clean = run_cli("audit --corpus " + corpus + " --engine three");
    const auto preloaded = run_shell("NODE_OPTIONS='--require " + (dir.path() / "sqrt.js").string() + "' " RAYVERIFY_CLI
                                     " audit --corpus " + corpus + " --engine three");
    ASSERT_EQ(clean.exit_code, 1) << clean.output;
    ASSERT_EQ(preloaded.exit_code, 1) << preloaded.output;
    EXPECT_EQ(row_of(preloaded.output, "three"), row_of(clean.output, "three"));
    const auto typo = run_shell("NODE_OPTIONS=--no-such-option " RAYVERIFY_CLI " engines");
    EXPECT_NE(engine_line(typo.output, "three").find("  available"), std::string::npos) << typo.output;
}

// Hit points alone, worked by hand: o = (0, 0, −5), d = (0, 0, 1), c = 0, r = 1
// meets the sphere at t = 4, the point (0, 0, −1), and leaves it at t = 6,
// (0, 0, 1): a nearest hit answered with the far point is a wrong root.
TEST_F(ShippedLibraries, AResultsFileOfHitPointsIsJudgedThroughTheDerivedT) {
    write("cases.txt",
          "hit hand 0 0 -5 0 0 1 0 0 0 1\n"
          "far hand 0 0 -5 0 0 1 0 0 0 1\n"
          "miss hand 0 5 -5 0 0 1 0 0 0 1\n");
    const auto exported = run_cli("corpus export --corpus " + at("cases.txt") + " --format jsonl --precision double -o " +
                                  at("cases.jsonl"));
    ASSERT_EQ(exported.exit_code, 0) << exported.output;
    std::istringstream header(read_text(at("cases.jsonl")));
    std::string first;
    std::getline(header, first);
    std::smatch fingerprint;
    ASSERT_TRUE(std::regex_search(first, fingerprint, std::regex(R"re("fingerprint"\s*:\s*"([^"]+)")re"))) << first;
    write("answers.jsonl",
          R"({"rayverify": "results", "version": 1, "precision": "double", "fingerprint": ")" + fingerprint[1].str() +
              "\"}\n"
              R"({"id": "hit", "count": 1, "hit_point": [0, 0, -1]})"
              "\n"
              R"({"id": "far", "count": 1, "hit_point": [0, 0, 1]})"
              "\n"
              R"({"id": "miss", "count": 0})"
              "\n");
    const std::string contract = "query=nearest_hit,range=ray,ends=[),unit_direction=yes,answer=point";
    const auto r = run_cli("audit --corpus " + at("cases.txt") + " --results " + at("answers.jsonl") + " --contract " +
                           "'" + contract + "' --name points --per-case " + at("per_case.jsonl"));
    ASSERT_EQ(r.exit_code, 1) << r.output;
    const std::string lines = read_text(at("per_case.jsonl"));
    const auto verdict_of = [&](const std::string& id) {
        std::istringstream in(lines);
        for (std::string line; std::getline(in, line);)
            if (std::regex_search(line, std::regex("\"id\": ?\"" + id + "\""))) {
                std::smatch m;
                if (std::regex_search(line, m, std::regex(R"re("verdict": ?"([a-z_]+)")re"))) return m[1].str();
            }
        return std::string("(no verdict for " + id + ")");
    };
    EXPECT_EQ(verdict_of("hit"), "agree");
    EXPECT_EQ(verdict_of("far"), "wrong_root");
    EXPECT_EQ(verdict_of("miss"), "agree");
}

// A program asked for the whole input, batch by batch, is judged exactly as
// the same answers read from a results file: the textbook quadratic in
// JavaScript gives the built-in naive's table.
TEST_F(ShippedLibraries, AuditCommandGivesTheTableOfTheSameProgramsResultsFile) {
    const std::string program = "node " + std::string(RAYVERIFY_SOURCE_DIR) + "/examples/other_languages/naive.js";
    const std::string contract = "query=line_roots,reports_tangent=yes";
    const auto asked = run_cli("audit --corpus " + corpus + " --command '" + program + "' --contract " + contract +
                               " --name naive_js --precision double");
    const auto builtin = run_cli("audit --corpus " + corpus + " --variant naive --precision double");
    ASSERT_EQ(asked.exit_code, 1) << asked.output;
    EXPECT_EQ(row_of(asked.output, "naive_js"), row_of(builtin.output, "naive"));
    // Two precisions cannot be one program's.
    const auto both = run_cli("audit --corpus " + corpus + " --command '" + program + "' --contract " + contract +
                              " --name naive_js --precision double --precision float");
    EXPECT_EQ(both.exit_code, 2) << both.output;
    EXPECT_NE(both.output.find("one precision"), std::string::npos) << both.output;
    // A contract without answers to name is a usage error.
    const auto stray = run_cli("audit --corpus " + corpus + " --variant naive --contract " + contract);
    EXPECT_EQ(stray.exit_code, 2) << stray.output;
}

TEST_F(ShippedLibraries, AProgramThatDiesIsAnInputErrorNamingItAndNoOutputIsLeft) {
    const auto r = run_cli("audit --corpus " + corpus + " --command 'exit 3' --contract query=line_roots --name dead" +
                           " --report " + at("report"));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("exit 3"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(at("report")));
}

}  // namespace
