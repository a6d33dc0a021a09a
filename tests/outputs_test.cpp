// The outputs of a run (core/outputs.h, docs/outputs.md): files appear
// together or not at all, temporaries are unique and never follow links,
// devices and pipes are written through, a report directory is locked, a
// full disk, a signal or a plugin's exit() leaves nothing behind, and a
// failed write to standard output is exit 2. Tests make their own FIFOs and
// device nodes in temporary directories and use RLIMIT_FSIZE (`ulimit -f`)
// for a full disk; they never touch the machine's /dev.
#include "core/outputs.h"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <future>
#include <random>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "core/input_error.h"
#include "support/process.h"

namespace {

namespace fs = std::filesystem;
using rayverify::input_error;
using rayverify::run_outputs;
using rayverify::test_support::read_text;
using rayverify::test_support::run_shell;
using rayverify::test_support::scratch_directory;

class Outputs : public ::testing::Test {
protected:
    // Every name under the directory, hidden ones included, with "/" after a directory's.
    std::set<std::string> listing(const fs::path& dir) const {
        std::set<std::string> names;
        for (const auto& entry : fs::recursive_directory_iterator(dir))
            names.insert(entry.path().lexically_relative(dir).string() + (entry.is_directory() ? "/" : ""));
        return names;
    }
    std::set<std::string> listing() const { return listing(dir_); }

    fs::path write(const std::string& name, const std::string& text) const {
        std::ofstream(dir_ / name, std::ios::binary) << text;
        return dir_ / name;
    }

    // `rayverify ARGUMENTS` run by sh in the test directory.
    rayverify::test_support::command_result cli(const std::string& arguments, const std::string& shell_prefix = "") {
        return run_shell(fmt::format("cd '{}' && {} '{}' {}", dir_.string(), shell_prefix, RAYVERIFY_CLI, arguments));
    }

    scratch_directory scratch_{"rayverify_outputs_test"};
    const fs::path dir_ = scratch_.path();
};

std::string message_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const input_error& e) {
        return e.what();
    }
    return "";
}

const std::string good = "good - 0 0 -5 0 0 1 0 0 0 1\n";

// ---- The module itself ----

TEST_F(Outputs, FilesAppearTogetherOnCommitAndNotBefore) {
    write("old.txt", "old\n");
    {
        run_outputs outputs;
        outputs.directory(dir_ / "rep" / "sub", "--report");
        outputs.file(dir_ / "rep" / "sub" / "a.json", "--report").stream() << "{\"a\": 1}\n";
        outputs.file(dir_ / "old.txt", "-o").stream() << "new\n";
        // Before the commit: only the directories, the lock and hidden temporaries.
        for (const std::string& name : listing())
            EXPECT_TRUE(name == "old.txt" || name.starts_with("rep/") || name == "rep/" ||
                        fs::path(name).filename().string().starts_with("."))
                << name;
        EXPECT_EQ(read_text(dir_ / "old.txt"), "old\n");
        EXPECT_FALSE(fs::exists(dir_ / "rep" / "sub" / "a.json"));
        outputs.commit();
    }
    EXPECT_EQ(listing(), (std::set<std::string>{"old.txt", "rep/", "rep/sub/", "rep/sub/a.json"}));
    EXPECT_EQ(read_text(dir_ / "rep" / "sub" / "a.json"), "{\"a\": 1}\n");
    EXPECT_EQ(read_text(dir_ / "old.txt"), "new\n");
}

TEST_F(Outputs, WithoutCommitNothingIsLeftNotEvenTheDirectoriesItMade) {
    write("old.txt", "old\n");
    fs::create_directory(dir_ / "kept");
    {
        run_outputs outputs;
        outputs.directory(dir_ / "made" / "deeper", "--report");
        outputs.directory(dir_ / "kept", "--report");
        outputs.file(dir_ / "made" / "deeper" / "report.json", "--report").stream() << "{}";
        outputs.file(dir_ / "kept" / "summary.txt", "--report").stream() << "table";
        outputs.file(dir_ / "old.txt", "-o").stream() << "new";
        const fs::path stage = outputs.staging_directory(dir_ / "kept");
        std::ofstream(stage / "plot.png") << "png";
        outputs.adopt(stage / "plot.png", dir_ / "kept" / "plot.png");
    }
    EXPECT_EQ(listing(), (std::set<std::string>{"kept/", "old.txt"}));
    EXPECT_EQ(read_text(dir_ / "old.txt"), "old\n");
}

TEST_F(Outputs, TemporariesAreUniqueAndNeverFollowALink) {
    // The old fixed "<path>.tmp", planted as a link to a victim: never written through.
    const fs::path victim = write("victim.txt", "precious\n");
    fs::create_symlink(victim, dir_ / "out.json.tmp");
    run_outputs first, second;
    first.file(dir_ / "out.json", "-o").stream() << "first\n";
    second.file(dir_ / "out.json", "-o").stream() << "second\n";
    std::set<std::string> temporaries;
    for (const std::string& name : listing())
        if (name.starts_with(".out.json.rayverify-new-")) {
            temporaries.insert(name);
            EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(dir_ / name))) << name;
        }
    EXPECT_EQ(temporaries.size(), 2u) << "one temporary per writer";
    first.commit();
    second.commit();
    EXPECT_EQ(read_text(dir_ / "out.json"), "second\n");
    EXPECT_EQ(read_text(victim), "precious\n");
    EXPECT_TRUE(fs::is_symlink(dir_ / "out.json.tmp"));
    EXPECT_EQ(listing(), (std::set<std::string>{"out.json", "out.json.tmp", "victim.txt"}));
}

TEST_F(Outputs, AnOutputThatIsALinkReplacesItsTargetAndKeepsTheLink) {
    fs::create_directory(dir_ / "real");
    write("real/data.json", "old\n");
    fs::create_symlink("real/data.json", dir_ / "data.json");
    rayverify::write_file_atomically(dir_ / "data.json", "new\n");
    EXPECT_TRUE(fs::is_symlink(dir_ / "data.json"));
    EXPECT_EQ(read_text(dir_ / "real" / "data.json"), "new\n");
    EXPECT_EQ(listing(), (std::set<std::string>{"data.json", "real/", "real/data.json"}));
}

TEST_F(Outputs, AFifoIsWrittenThroughAsTheOutputIsProduced) {
    const fs::path fifo = dir_ / "cases.fifo";
    ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
    // The reader opens the FIFO too, so that opening it for writing does not block.
    std::future<std::string> read = std::async(std::launch::async, [&] { return read_text(fifo); });
    {
        run_outputs outputs;
        rayverify::output_file& f = outputs.file(fifo, "--per-case");
        EXPECT_TRUE(f.written_through());
        for (int i = 0; i < 20000; ++i) f.stream() << "line " << i << '\n';  // more than a pipe buffer
        outputs.commit();
    }
    const std::string text = read.get();
    EXPECT_TRUE(text.starts_with("line 0\nline 1\n"));
    EXPECT_TRUE(text.ends_with("line 19999\n"));
    struct stat s {};
    ASSERT_EQ(stat(fifo.c_str(), &s), 0);
    EXPECT_TRUE(S_ISFIFO(s.st_mode)) << "the FIFO was replaced";
    EXPECT_EQ(listing(), (std::set<std::string>{"cases.fifo"}));
}

// Device nodes of our own (null: 1,3; full: 1,7), made where mknod is allowed (root, CAP_MKNOD).
TEST_F(Outputs, PrivateDeviceNodesAreWrittenThroughAndNeverReplaced) {
    if (mknod((dir_ / "null").c_str(), S_IFCHR | 0666, makedev(1, 3)) != 0 ||
        mknod((dir_ / "full").c_str(), S_IFCHR | 0666, makedev(1, 7)) != 0)
        GTEST_SKIP() << "mknod is not allowed here";
    {
        run_outputs outputs;
        outputs.file(dir_ / "null", "-o").stream() << "gone\n";
        outputs.commit();
    }
    EXPECT_EQ(message_of([&] {
                  run_outputs outputs;
                  outputs.file(dir_ / "full", "-o").stream() << "never\n";
                  outputs.commit();
              }),
              (dir_ / "full").string() + ": field '-o': cannot write: No space left on device");
    for (const char* node : {"null", "full"}) {
        struct stat s {};
        ASSERT_EQ(stat((dir_ / node).c_str(), &s), 0);
        EXPECT_TRUE(S_ISCHR(s.st_mode)) << node << " was replaced";
    }
    EXPECT_EQ(listing(), (std::set<std::string>{"full", "null"}));

    // Through the CLI: -o and --per-case on the node, standard output on it.
    write("good.txt", good);
    EXPECT_EQ(cli("corpus generate --family uniform --count 3 -o null").exit_code, 0);
    const auto full = cli("audit --corpus good.txt --variant naive --per-case full");
    EXPECT_EQ(full.exit_code, 2) << full.output;
    EXPECT_NE(full.output.find("rayverify: error: full: field '--per-case': cannot write: No space left on device"),
              std::string::npos)
        << full.output;
    const auto stdout_full = cli("variants --json >full; }", "{");  // stderr stays the pipe
    EXPECT_EQ(stdout_full.exit_code, 2) << stdout_full.output;
    EXPECT_EQ(stdout_full.output, "rayverify: error: standard output: cannot write: No space left on device\n");
    EXPECT_EQ(listing(), (std::set<std::string>{"full", "good.txt", "null"}));
}

TEST_F(Outputs, AFailedRenameRestoresTheFilesAlreadyInPlace) {
    write("a.txt", "old a\n");
    std::string message;
    {
        run_outputs outputs;
        outputs.file(dir_ / "a.txt", "-o").stream() << "new a\n";
        outputs.file(dir_ / "b.txt", "-o").stream() << "new b\n";
        outputs.file(dir_ / "c.txt", "-o").stream() << "new c\n";
        fs::create_directories(dir_ / "c.txt" / "blocker");  // appears after the check: the rename fails
        message = message_of([&] { outputs.commit(); });
    }
    EXPECT_NE(message.find("c.txt: cannot rename into place"), std::string::npos) << message;
    EXPECT_NE(message.find("(no output of this run was kept)"), std::string::npos) << message;
    EXPECT_EQ(read_text(dir_ / "a.txt"), "old a\n");
    EXPECT_EQ(listing(), (std::set<std::string>{"a.txt", "c.txt/", "c.txt/blocker/"}));
}

TEST_F(Outputs, ASecondRunIsLockedOutAndAStaleLockIsTakenOver) {
    {
        run_outputs first;
        first.directory(dir_ / "rep", "--report");
        const std::string message = message_of([&] {
            run_outputs second;
            second.directory(dir_ / "rep", "--report");
        });
        EXPECT_NE(message.find(fmt::format("field '--report': is in use by another rayverify run (pid {} on ",
                                           getpid())),
                  std::string::npos)
            << message;
        EXPECT_NE(message.find("remove " + (dir_ / "rep" / ".rayverify-lock").string() + " if that run is gone"),
                  std::string::npos)
            << message;
        EXPECT_TRUE(fs::exists(dir_ / "rep" / ".rayverify-lock")) << "the second run left the first one's lock";
    }
    EXPECT_FALSE(fs::exists(dir_ / "rep"));

    // A lock whose process is gone (a killed run on this host) is taken over.
    const pid_t gone = fork();
    if (gone == 0) _exit(0);
    waitpid(gone, nullptr, 0);
    char host[256] = {};
    gethostname(host, sizeof host - 1);
    fs::create_directory(dir_ / "rep");
    write("rep/.rayverify-lock", fmt::format("rayverify run in progress\npid {}\nhost {}\n", gone, host));
    run_outputs outputs;
    outputs.directory(dir_ / "rep", "--report");
    outputs.file(dir_ / "rep" / "report.json", "--report").stream() << "{}";
    outputs.commit();
    EXPECT_EQ(listing(), (std::set<std::string>{"rep/", "rep/report.json"}));
}

TEST_F(Outputs, AnOutputThatReachesAnInputThroughALinkIsRefused) {
    write("corpus.txt", good);
    fs::create_symlink("corpus.txt", dir_ / "alias.jsonl");
    run_outputs outputs;
    outputs.input(dir_ / "corpus.txt", "--corpus");
    EXPECT_NE(message_of([&] { outputs.file(dir_ / "alias.jsonl", "--per-case"); })
                  .find("alias.jsonl: field '--per-case': is the same file as the input"),
              std::string::npos);
    EXPECT_EQ(read_text(dir_ / "corpus.txt"), good);
}

// ---- Through the CLI ----

// Standard output on a full disk: every command, a write error and exit 2
// (RLIMIT_FSIZE of 0 blocks makes every write to the redirected file fail).
TEST_F(Outputs, AFailedWriteToStandardOutputIsExitTwoForEveryCommand) {
    write("good.txt", good);
    ASSERT_EQ(cli("audit --corpus good.txt --variant naive --precision double --report rep >/dev/null").exit_code, 0);
    write("base.txt", "rayverify-baseline 1\nnaive/double all cases 1\n");
    for (const std::string command :
         {"variants", "variants --json", "audit --corpus good.txt --variant naive", "gate --baseline base.txt "
          "--corpus good.txt --variant naive --precision double",
          "explain 0 0 -5 0 0 1 0 0 0 1", "corpus generate --family uniform --count 3",
          "diff rep/report.json rep/report.json", "hunt --variant naive --budget 0 --evaluations 50 -o hunt.txt",
          "audit --scene " RAYVERIFY_SOURCE_DIR "/corpus/scenes/four_spheres.json --variant naive",
          "--help"}) {
        SCOPED_TRACE(command);
        const auto r = cli(command + " >out.txt; }", "{ ulimit -f 0;");  // stderr stays the pipe
        EXPECT_EQ(r.exit_code, 2) << r.output;
        EXPECT_NE(r.output.find("rayverify: error: standard output: cannot write: File too large"), std::string::npos)
            << r.output;
        EXPECT_FALSE(fs::exists(dir_ / "hunt.txt")) << "an output committed after a lost table";
    }
}

// A full disk during any output of a run: none appears (the cases: a
// per-case file kept when the report failed, a shard.json merge would take,
// render's first images).
TEST_F(Outputs, AFullDiskLeavesNoOutputOfTheRun) {
    write("good.txt", good);
    const std::string scene = RAYVERIFY_SOURCE_DIR "/corpus/scenes/four_spheres.json";
    struct attempt {
        std::string command;
        int blocks;  // ulimit -f: the largest file, in KiB
    };
    for (const attempt& a : {
             // The per-case file fits; report.json does not.
             attempt{"audit --generate uniform:40 --variant naive --per-case pc.jsonl --report rep", 24},
             attempt{"audit --generate uniform:40 --variant naive --shard 1/2 --per-case rep/pc.jsonl --report rep", 24},
             attempt{"render --scene " + scene + " --variant naive -o out", 2},
             attempt{"gate --baseline base.txt --corpus good.txt --update", 0},
         }) {
        SCOPED_TRACE(a.command);
        const std::set<std::string> before = listing();
        const auto r = cli(a.command, fmt::format("ulimit -f {};", a.blocks));  // stdout: a pipe, no limit
        EXPECT_EQ(r.exit_code, 2) << r.output;
        EXPECT_NE(r.output.find("cannot write: File too large"), std::string::npos) << r.output;
        EXPECT_EQ(listing(), before);
    }
}

// An in-process plugin that calls exit(0) in the middle of an audit: exit 2,
// named, and no output (the README's CI step used to pass).
TEST_F(Outputs, APluginsExitDuringTheRunIsExitTwoWithNoOutput) {
    write("good.txt", good);
    for (const std::string command : {"audit --corpus good.txt --report rep --per-case pc.jsonl",
                                      "gate --baseline base.txt --corpus good.txt --update"}) {
        SCOPED_TRACE(command);
        const auto r = cli(command + " --plugin " RAYVERIFY_FIXTURE_PLUGIN_MODAL, "FIXTURE_MODE=call_exit");
        EXPECT_EQ(r.exit_code, 2) << r.output;
        EXPECT_NE(r.output.find("plugin 'modal' called exit() on case good (good.txt:1)"), std::string::npos)
            << r.output;
        EXPECT_EQ(listing(), (std::set<std::string>{"good.txt"}));
    }
}

// ---- Stress: two audits into one report directory, and signals ----

pid_t spawn(const std::string& command) {
    const pid_t pid = fork();
    if (pid == 0) {
        execl("/bin/sh", "sh", "-c", command.c_str(), static_cast<char*>(nullptr));
        _exit(127);
    }
    return pid;
}

int wait_for(pid_t pid) {
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    return status;
}

// Both at once, several times: one writes the report, the other is refused
// naming it; the report is whole and the run's own, never a mix.
TEST_F(Outputs, StressTwoAuditsIntoOneReportDirectory) {
    const std::string audit = fmt::format("cd '{}' && exec '{}' audit --generate uniform:3000 --variant naive "
                                          "--precision double --threads 1 --report rep --per-case rep/pc.jsonl",
                                          dir_.string(), RAYVERIFY_CLI);
    int refused = 0;
    for (int round = 0; round < 4; ++round) {
        SCOPED_TRACE(round);
        fs::remove_all(dir_ / "rep");
        const pid_t a = spawn(audit + " >out-a.txt 2>err-a.txt"), b = spawn(audit + " >out-b.txt 2>err-b.txt");
        const int status_a = wait_for(a), status_b = wait_for(b);
        ASSERT_TRUE(WIFEXITED(status_a) && WIFEXITED(status_b));
        const int code_a = WEXITSTATUS(status_a), code_b = WEXITSTATUS(status_b);
        // The first to lock the directory runs (exit 0 or 1, the same for both); the other is refused (2),
        // unless it started after the first had finished.
        const int ran = std::min(code_a, code_b);
        EXPECT_LE(ran, 1);
        EXPECT_TRUE(code_a == ran || code_a == 2) << code_a << " " << code_b;
        EXPECT_TRUE(code_b == ran || code_b == 2) << code_a << " " << code_b;
        refused += (code_a == 2) + (code_b == 2);
        for (const char* refused : {"err-a.txt", "err-b.txt"}) {
            const std::string err = read_text(dir_ / refused);
            if (err.empty()) continue;
            EXPECT_NE(err.find("rayverify: error: rep: field '--report': is in use by another rayverify run (pid "),
                      std::string::npos)
                << err;
        }
        EXPECT_EQ(listing(dir_ / "rep"),
                  (std::set<std::string>{"audit.csv", "pc.jsonl", "report.json", "report.md", "summary.txt"}));
        const std::string lines = read_text(dir_ / "rep" / "pc.jsonl");
        EXPECT_EQ(std::count(lines.begin(), lines.end(), '\n'), 3000);
        const std::string winner = read_text(dir_ / (code_a == ran ? "out-a.txt" : "out-b.txt"));
        EXPECT_TRUE(winner.starts_with(read_text(dir_ / "rep" / "summary.txt"))) << "a summary from another run";
    }
    std::printf("%d of 4 rounds ran the two audits at the same time\n", refused);
    EXPECT_GT(refused, 0) << "the two audits never overlapped: the test tested nothing";
}

// SIGINT or SIGTERM in the middle of an audit: the process ends by the signal
// and leaves nothing: no temporary, no lock, no directory it made, and a
// report directory that existed keeps its old files untouched.
TEST_F(Outputs, StressASignalDuringAnAuditLeavesNothing) {
    fs::create_directory(dir_ / "old");
    write("old/summary.txt", "the previous run\n");
    write("log.txt", "");  // where the audits' output goes: there before and after
    for (const int signal : {SIGINT, SIGTERM}) {
        for (const char* report : {"new/deeper", "old"}) {
            SCOPED_TRACE(fmt::format("{} into {}", strsignal(signal), report));
            const std::set<std::string> before = listing();
            const pid_t pid = spawn(fmt::format("cd '{}' && exec '{}' audit --generate uniform:2000000 --variant naive "
                                                "--precision double --threads 2 --report {} --per-case {}/pc.jsonl "
                                                ">/dev/null 2>&1",
                                                dir_.string(), RAYVERIFY_CLI, report, report));
            // Signalled once the per-case temporary exists and holds some lines.
            const auto started = std::chrono::steady_clock::now();
            for (bool writing = false; !writing;) {
                ASSERT_LT(std::chrono::steady_clock::now() - started, std::chrono::seconds(60));
                std::this_thread::sleep_for(std::chrono::milliseconds(20));
                std::error_code ignored;
                for (const auto& entry : fs::recursive_directory_iterator(dir_, ignored))
                    writing = writing || (entry.path().filename().string().starts_with(".pc.jsonl.rayverify-new-") &&
                                          fs::file_size(entry.path(), ignored) > 0);
            }
            ASSERT_EQ(kill(pid, signal), 0);
            const int status = wait_for(pid);
            EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == signal) << status;
            EXPECT_EQ(listing(), before);
            EXPECT_EQ(read_text(dir_ / "old" / "summary.txt"), "the previous run\n");
        }
    }
}

}  // namespace
