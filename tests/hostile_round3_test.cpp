// Hostile round 3 (issue 43), end to end through the rayverify executable:
// a corpus directory never read in part without a word, a closed standard
// output that does not cost the report files, programs whose first line is
// checked at once and whose output is bounded, and children that do not
// outlive rayverify, whether it ends normally or by a signal.
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "support/process.h"
#include "support/results_program.h"
#include "support/sanitized.h"

extern char** environ;

namespace {

namespace fs = std::filesystem;
using rayverify::test_support::miss_answering_loop;
using rayverify::test_support::read_text;
using rayverify::test_support::run_cli;
using rayverify::test_support::run_shell;
using rayverify::test_support::scratch_directory;

const std::string corpus = RAYVERIFY_CORPUS_DIR;
const std::string naive_contract = "query=line_roots,reports_tangent=yes";

// A process is gone once /proc has no entry for it, or only a zombie's.
bool gone_within_seconds(const std::string& pid, int seconds) {
    for (int i = 0; i < seconds * 20; ++i) {
        const std::string stat = read_text("/proc/" + pid + "/stat");
        if (stat.empty() || stat.substr(stat.rfind(')') + 2, 1) == "Z") return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return false;
}

// Waits for a file to hold text (a pid a program wrote); empty after the time.
std::string wait_for_text(const fs::path& file, int seconds) {
    for (int i = 0; i < seconds * 20; ++i) {
        const std::string text = read_text(file);
        if (!text.empty() && text.back() == '\n') return text.substr(0, text.size() - 1);
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return "";
}

// A Python program that escapes twice (a child in a process group of its
// own, a grandchild by double fork into a new session) and writes both pids
// to `pids`, then answers JSON-lines batches with count 0, or (`busy`)
// reads its first line and spins without answering.
void write_escaping_program(const fs::path& file, bool busy) {
    std::ofstream(file) << "import json, os, sys, time\n"
                           "pids = open(sys.argv[1], 'w')\n"
                           "child = os.fork()\n"
                           "if child == 0:\n"
                           "    os.setpgid(0, 0)\n"
                           "    os.close(1)\n"
                           "    time.sleep(300)\n"
                           "    os._exit(0)\n"
                           "r, w = os.pipe()\n"
                           "if os.fork() == 0:\n"
                           "    os.setsid()\n"
                           "    grandchild = os.fork()\n"
                           "    if grandchild == 0:\n"
                           "        os.close(1)\n"
                           "        time.sleep(300)\n"
                           "        os._exit(0)\n"
                           "    os.write(w, str(grandchild).encode())\n"
                           "    os._exit(0)\n"
                           "grandchild = os.read(r, 32).decode()\n"
                           "pids.write(f'{child} {grandchild} {os.getpid()}\\n')\n"
                           "pids.close()\n"
                        << (busy ? "sys.stdin.readline()\n"
                                   "while True:\n"
                                   "    pass\n"
                                 : miss_answering_loop());
}

std::vector<std::string> words_of(const std::string& text) {
    std::vector<std::string> words;
    std::istringstream in(text);
    for (std::string w; in >> w;) words.push_back(w);
    return words;
}

TEST(CorpusArguments, ASubdirectoryHoldingCorpusFilesIsRefusedNamingIt) {
    scratch_directory dir("rayverify_round3");
    fs::create_directories(dir.path() / "top" / "nested" / "deeper");
    fs::copy_file(corpus + "/uniform.txt", dir.path() / "top" / "uniform.txt");
    fs::copy_file(corpus + "/inside.txt", dir.path() / "top" / "nested" / "deeper" / "inside.txt");
    const auto r = run_cli("audit --variant naive --corpus " + (dir.path() / "top").string() + " --report " +
                           (dir.path() / "report").string());
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find((dir.path() / "top" / "nested").string() + ": a subdirectory of " +
                            (dir.path() / "top").string() + " holding 1 corpus file"),
              std::string::npos)
        << r.output;
    EXPECT_FALSE(fs::exists(dir.path() / "report"));
    // Named with a --corpus of its own, it is read, and each argument's files and cases are told.
    const auto both = run_cli("audit --variant naive --corpus " + (dir.path() / "top" / "uniform.txt").string() +
                              " --corpus " + (dir.path() / "top" / "nested" / "deeper").string());
    EXPECT_EQ(both.exit_code, 1) << both.output;  // naive is wrong on some inside cases
    EXPECT_NE(both.output.find("audit: read " + (dir.path() / "top" / "uniform.txt").string() + ": 1 file, 500 cases; " +
                               (dir.path() / "top" / "nested" / "deeper").string() + ": 1 file, 500 cases"),
              std::string::npos)
        << both.output;
}

TEST(CorpusArguments, TheShippedCorpusSaysItsEdgeFamiliesAreACorpusOfTheirOwn) {
    const auto r = run_cli("gate --baseline " + std::string(RAYVERIFY_SOURCE_DIR) + "/gate/baseline.txt --corpus " +
                           corpus);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("gate: read " + corpus + ": 6 files, 3000 cases (edge/ not read: a corpus of its own in " +
                            corpus + "/MANIFEST)"),
              std::string::npos)
        << r.output;
}

// The reader of standard output is gone before the audit prints a line; the
// report files are written all the same, and the broken pipe is exit 2.
TEST(ClosedStandardOutput, TheReportFilesAreWrittenAndTheBrokenPipeIsTheExitStatus) {
    scratch_directory dir("rayverify_round3");
    const fs::path report = dir.path() / "report";
    const auto r = run_shell("(" + std::string(RAYVERIFY_CLI) + " audit --corpus " + corpus + " --report " +
                             report.string() + " 2>" + (dir.path() / "stderr").string() + "; echo $? > " +
                             (dir.path() / "rc").string() + ") | true");
    EXPECT_EQ(read_text(dir.path() / "rc"), "2\n");
    EXPECT_NE(read_text(dir.path() / "stderr").find("standard output: cannot write: Broken pipe (its reader closed it"),
              std::string::npos)
        << read_text(dir.path() / "stderr");
    for (const char* name : {"report.json", "report.md", "summary.txt"})
        EXPECT_TRUE(fs::exists(report / name)) << name;
}

TEST(ProgramStreams, AFirstLineThatIsNoResultsHeaderFailsAtOnceNotAtTheTimeout) {
    const auto start = std::chrono::steady_clock::now();
    const auto r = run_cli("audit --corpus " + corpus + "/uniform.txt --command 'echo garbage; sleep 60' --contract " +
                           naive_contract + " --name liar --command-timeout 50");
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("answered with something that is not an answer to its batch (answer to batch 1:1"),
              std::string::npos)
        << r.output;
    EXPECT_LT(seconds, 30) << "waited for the timeout";
}

TEST(ProgramStreams, AnEndlessLineIsStoppedAtOneMebibyte) {
    const auto r = run_cli("audit --corpus " + corpus + "/uniform.txt --command 'yes | tr -d \"\\n\"' --contract " +
                           naive_contract + " --name flood --format csv");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("answer to batch 1:1: a line longer than 1 MiB"), std::string::npos) << r.output;
}

TEST(ProgramStreams, AnAnswerLongerThanItsBatchCanNeedIsStopped) {
    // A valid header, then endless lines of 1000 blanks (blank lines are not answers).
    scratch_directory dir("rayverify_round3");
    std::ofstream(dir.path() / "padder.py")
        << "import sys\n"
           "sys.stdin.readline()\n"
           "print('# rayverify results v1 precision=double fingerprint=0123456789abcdef', flush=True)\n"
           "while True:\n"
           "    print(' ' * 1000)\n";
    const auto r = run_cli("audit --corpus " + corpus + "/uniform.txt --command 'python3 " +
                           (dir.path() / "padder.py").string() + "' --contract " + naive_contract +
                           " --name padder --format csv");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("more than a batch of 500 cases can need"), std::string::npos) << r.output;
}

// The peak memory (KiB) of `rayverify audit` over `count` generated cases
// with a --command program that answers count 0 for every case.
long audit_peak_kib(const fs::path& dir, std::size_t count) {
    std::ofstream(dir / "zero.py") << "import json, sys\n" << miss_answering_loop();
    std::ofstream(dir / "peak.py") << "import resource, subprocess, sys\n"
                                      "subprocess.run(sys.argv[1:], stdout=subprocess.DEVNULL)\n"
                                      "print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)\n";
    const auto r = run_shell("/usr/bin/python3 " + (dir / "peak.py").string() + " " + RAYVERIFY_CLI +
                             " audit --generate uniform:" + std::to_string(count) +
                             " --variant naive --precision double --command 'python3 " + (dir / "zero.py").string() +
                             "' --contract query=line_roots --name zero --quiet");
    return std::atol(r.output.c_str());
}

// Answers are judged as they arrive: ten times the cases, the same memory
// (about 250 bytes a case were kept before: 22 MB more for 90,000 cases).
TEST(ProgramStreams, MemoryDoesNotGrowWithTheCasesAProgramAnswers) {
    if (rayverify::test_support::sanitized_build) GTEST_SKIP() << "ASan's quarantine keeps what was freed: peak memory grows with any allocation";
    scratch_directory dir("rayverify_round3");
    const long small = audit_peak_kib(dir.path(), 10000), large = audit_peak_kib(dir.path(), 100000);
    ASSERT_GT(small, 0);
    EXPECT_LT(large, small + 8 * 1024) << "peak " << small << " KiB for 10,000 cases, " << large
                                       << " KiB for 100,000";
}

TEST(Children, WhatAProgramStartsDoesNotOutliveTheAuditEvenInANewSession) {
    scratch_directory dir("rayverify_round3");
    write_escaping_program(dir.path() / "p.py", false);
    const auto r = run_cli("audit --corpus " + corpus + "/uniform.txt --command 'python3 " +
                           (dir.path() / "p.py").string() + " " + (dir.path() / "pids").string() + "' --contract " +
                           naive_contract + " --name leaver");
    ASSERT_NE(r.exit_code, 2) << r.output;
    const std::vector<std::string> pids = words_of(read_text(dir.path() / "pids"));
    ASSERT_EQ(pids.size(), 3u);
    for (const std::string& pid : pids) {
        EXPECT_TRUE(gone_within_seconds(pid, 10)) << "process " << pid << " outlived the audit";
        ::kill(std::stoi(pid), SIGKILL);
    }
}

// rayverify is ended by a signal while a busy program answers nothing: the
// program and everything it started end with it.
TEST(Children, ASignalEndsTheProgramAndEverythingItStarted) {
    for (const int signal : {SIGTERM, SIGINT}) {
        scratch_directory dir("rayverify_round3");
        write_escaping_program(dir.path() / "p.py", true);
        const std::string command =
            "python3 " + (dir.path() / "p.py").string() + " " + (dir.path() / "pids").string();
        std::vector<std::string> arguments = {RAYVERIFY_CLI, "audit",     "--corpus", corpus + "/uniform.txt",
                                              "--command",   command,     "--contract", naive_contract,
                                              "--name",      "busy",      "--report",   (dir.path() / "r").string()};
        std::vector<char*> argv;
        for (std::string& a : arguments) argv.push_back(a.data());
        argv.push_back(nullptr);
        pid_t rayverify = 0;
        ASSERT_EQ(::posix_spawn(&rayverify, RAYVERIFY_CLI, nullptr, nullptr, argv.data(), environ), 0);
        const std::vector<std::string> pids = words_of(wait_for_text(dir.path() / "pids", 30));
        ASSERT_EQ(pids.size(), 3u) << "the program did not start";
        ::kill(rayverify, signal);
        int status = 0;
        ::waitpid(rayverify, &status, 0);
        EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == signal) << status;
        for (const std::string& pid : pids) {
            EXPECT_TRUE(gone_within_seconds(pid, 10)) << "process " << pid << " outlived rayverify (signal " << signal
                                                      << ")";
            ::kill(std::stoi(pid), SIGKILL);
        }
        EXPECT_FALSE(fs::exists(dir.path() / "r"));
    }
}

}  // namespace
