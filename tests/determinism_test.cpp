// Determinism: the same inputs give the same report, summary, per-case lines
// and stdout, byte for byte, run after run and whatever the thread count,
// through the CLI.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "support/process.h"
#include "support/sampled_corpus.h"

namespace {

namespace fs = std::filesystem;

using rayverify::test_support::read_text;
using rayverify::test_support::scratch_directory;

class Determinism : public testing::Test {
protected:
    // Runs `rayverify <arguments>` in dir_ (same paths every time, so the
    // recorded command line is the same); returns the exit code, stdout in `out`.
    int run(const std::string& arguments, std::string& out) {
        const std::string command =
            fmt::format("cd '{}' && '{}' {} >stdout.txt 2>/dev/null", dir_.string(), RAYVERIFY_CLI, arguments);
        const int status = std::system(command.c_str());
        out = read_text(dir_ / "stdout.txt");
        fs::remove(dir_ / "stdout.txt");
        return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    }

    // Every output of one audit run (cases.jsonl and the whole report
    // directory), moved aside into `name`/.
    void keep_outputs(const std::string& name) {
        fs::create_directories(dir_ / name);
        fs::rename(dir_ / "cases.jsonl", dir_ / name / "cases.jsonl");
        fs::rename(dir_ / "rep", dir_ / name / "rep");
    }

    scratch_directory scratch_{"rayverify_determinism"};
    const fs::path dir_ = scratch_.path();
};

// The whole shipped corpus, every variant: stdout and every per-case line,
// on one thread and then on two.
TEST_F(Determinism, AuditOfTheShippedCorpusIsByteIdenticalAcrossRuns) {
    const std::string arguments = fmt::format("audit --corpus '{}' --per-case cases.jsonl", RAYVERIFY_CORPUS_DIR);
    std::string first_out, second_out;
    const int first = run(arguments + " --threads 1", first_out);
    ASSERT_NE(first, 2) << first_out;
    const std::string first_cases = read_text(dir_ / "cases.jsonl");
    fs::remove(dir_ / "cases.jsonl");
    const int second = run(arguments + " --threads 2", second_out);
    const std::string second_cases = read_text(dir_ / "cases.jsonl");

    EXPECT_EQ(first, second);
    EXPECT_EQ(first_out, second_out) << "stdout differs between runs";
    EXPECT_FALSE(first_cases.empty());
    EXPECT_TRUE(first_cases == second_cases) << "cases.jsonl differs between runs";
}

// A generated corpus, and the full report of its audit (every file --report
// writes), audited on two threads and then on one.
TEST_F(Determinism, GeneratedCorpusAndItsReportAreByteIdentical) {
    std::string out;
    for (const char* name : {"a.txt", "b.txt"})
        ASSERT_EQ(run(fmt::format("corpus generate --family near_tangent --count 300 --seed 11 -o {}", name), out), 0);
    EXPECT_EQ(read_text(dir_ / "a.txt"), read_text(dir_ / "b.txt"));

    std::string first_out, second_out;
    run("audit --corpus a.txt --report rep --per-case cases.jsonl --threads 2", first_out);
    keep_outputs("first");
    run("audit --corpus a.txt --report rep --per-case cases.jsonl --threads 1", second_out);
    keep_outputs("second");
    EXPECT_EQ(first_out, second_out);
    std::size_t compared = 0;
    for (const auto& entry : fs::recursive_directory_iterator(dir_ / "first")) {
        if (!entry.is_regular_file()) continue;
        const fs::path file = fs::relative(entry.path(), dir_ / "first");
        const std::string a = read_text(entry.path()), b = read_text(dir_ / "second" / file);
        EXPECT_FALSE(a.empty()) << file;
        EXPECT_TRUE(a == b) << file << " differs between runs (" << a.size() << " vs " << b.size() << " bytes)";
        ++compared;
    }
    for (const char* file : {"cases.jsonl", "rep/report.json", "rep/summary.txt"})
        EXPECT_TRUE(fs::exists(dir_ / "first" / file)) << file;
    EXPECT_GE(compared, 3u);
}

// The same audit on 1, 2 and 3 threads, every output byte for byte. The edge
// corpus is more than one chunk of cases and holds invalid cases.
TEST_F(Determinism, AuditIsByteIdenticalWhateverTheThreadCount) {
    const rayverify::test_support::sampled_corpus edge(RAYVERIFY_CORPUS_DIR "/edge");
    std::string outputs[3];
    for (int threads = 1; threads <= 3; ++threads) {
        const int code = run(fmt::format("audit --corpus '{}' --threads {} --report rep --per-case cases.jsonl",
                                         edge.path().string(), threads),
                             outputs[threads - 1]);
        ASSERT_NE(code, 2) << outputs[threads - 1];
        keep_outputs(fmt::format("t{}", threads));
    }
    for (int threads = 2; threads <= 3; ++threads) {
        EXPECT_EQ(outputs[0], outputs[threads - 1]) << "stdout differs with " << threads << " threads";
        for (const char* file : {"cases.jsonl", "rep/report.json", "rep/report.md", "rep/summary.txt"}) {
            const std::string a = read_text(dir_ / "t1" / file), b = read_text(dir_ / fmt::format("t{}", threads) / file);
            EXPECT_FALSE(a.empty()) << file;
            EXPECT_TRUE(a == b) << file << " differs between 1 and " << threads << " threads";
        }
    }
}

}  // namespace
