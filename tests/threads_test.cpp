// Threads that fail cleanly: an exception on a helper thread (std::bad_alloc,
// a hook's) reaches the calling thread instead of ending the process in
// std::terminate, and a thread that cannot be created (a container's pid
// limit) is left out, never waited for: the audit runs on the threads it got,
// with the same report.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <new>
#include <stdexcept>
#include <thread>

#include "compare/audit.h"
#include "intersectors/registry.h"
#include "support/process.h"
#include "support/sanitized.h"

namespace rayverify {
namespace {

using namespace test_support;

TEST(Threads, AnExceptionOnAHelperThreadOfRunInParallelReachesTheCaller) {
    // The calling thread takes its items slowly, so that the helpers take
    // most; the first item a helper takes throws.
    const std::thread::id caller = std::this_thread::get_id();
    std::atomic<int> ran{0};
    const auto job = [&](std::size_t) {
        ++ran;
        if (std::this_thread::get_id() == caller)
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        else
            throw std::bad_alloc();
    };
    EXPECT_THROW(run_in_parallel(200, 4, job), std::bad_alloc);
    EXPECT_GE(ran.load(), 1);
    EXPECT_NO_THROW(run_in_parallel(0, 4, [](std::size_t) {}));
}

TEST(Threads, AnExceptionOnAnAuditHelperReachesTheCallerOnceTheChunkIsDone) {
    std::vector<corpus_case> chunk(64);
    for (std::size_t i = 0; i < chunk.size(); ++i) {
        chunk[i].id = "c" + std::to_string(i);
        chunk[i].geometry = {{0, 0, -5}, {0, 0, 1}, {0, 0, static_cast<double>(i) / 64}, 1};
    }
    bool given = false;
    const case_source source = [&](std::vector<corpus_case>& cases, std::vector<std::size_t>& indices) {
        if (given) return false;
        given = true;
        cases = chunk;
        for (std::size_t i = 0; i < chunk.size(); ++i) indices.push_back(i);
        return true;
    };
    audit_hooks hooks;
    std::atomic<int> seen{0};
    std::atomic<bool> helper_ran{false};
    hooks.parallel = [&](const audited_case&, std::size_t, std::size_t, unsigned worker) {
        ++seen;
        if (worker == 1) {
            helper_ran = true;
            throw std::bad_alloc();
        }
        // The calling thread holds back until the helper has a case of its own: on a
        // loaded machine it could otherwise take the whole chunk before the helper starts.
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
        while (!helper_ran && std::chrono::steady_clock::now() < deadline) std::this_thread::yield();
    };
    const std::vector<variant> naive = {*find_builtin_variant("naive")};
    const std::vector<audit_target> targets = targets_for(naive);
    EXPECT_THROW(audit_stream(source, targets, 2, hooks), std::bad_alloc);
    EXPECT_GE(seen.load(), 1);
}

// Under a limit that lets no thread (or one) be created, `--threads 4` runs on
// the threads it got, says so, and writes the report a one-thread run writes.
TEST(Threads, ThreadsThatCannotBeCreatedAreLeftOutNeverWaitedFor) {
    if (sanitized_build) GTEST_SKIP() << "the sanitizers' runtime creates threads of its own";
    const scratch_directory out("thread_limit");
    const std::string corpus = " --variant naive --variant robust --corpus " RAYVERIFY_CORPUS_DIR "/near_tangent.txt";
    const command_result one = run_cli("audit" + corpus + " --threads 1 --report '" + (out.path() / "one").string() + "'");
    ASSERT_EQ(one.exit_code, 1) << one.output;
    for (const char* allowed : {"0", "1"}) {
        const std::string dir = (out.path() / (std::string("limited") + allowed)).string();
        const command_result limited = run_shell(std::string("LD_PRELOAD=") + RAYVERIFY_THREAD_LIMIT_PRELOAD +
                                                 " FIXTURE_THREADS_ALLOWED=" + allowed + " timeout 120 " RAYVERIFY_CLI
                                                 " audit" + corpus + " --threads 4 --report '" + dir + "'");
        EXPECT_EQ(limited.exit_code, 1) << allowed << "\n" << limited.output;
        EXPECT_NE(limited.output.find("rayverify: note: could start"), std::string::npos) << limited.output;
        const auto without_command = [](std::string report) {
            return report.substr(report.find("\"results\""));  // the command line differs (--threads)
        };
        EXPECT_EQ(without_command(read_text(dir + "/report.json")),
                  without_command(read_text(out.path() / "one" / "report.json")));
    }
}

}  // namespace
}  // namespace rayverify
