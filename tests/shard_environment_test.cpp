// `--shard auto`: the shard read from a fake environment as Slurm, a
// Kubernetes Indexed Job or a plain launcher would set it, and every way the
// environment can be missing, malformed or inconsistent.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <map>
#include <set>

#include "core/input_error.h"
#include "corpus/shard_environment.h"
#include "support/process.h"

namespace {

using rayverify::environment_lookup;
using rayverify::input_error;
using rayverify::resolve_shard;
using rayverify::shard_spec;
using environment = std::map<std::string, std::string>;

environment_lookup fake(const environment& variables) {
    return [variables](const std::string& name) -> std::optional<std::string> {
        const auto at = variables.find(name);
        if (at == variables.end()) return std::nullopt;
        return at->second;
    };
}

shard_spec resolved(const char* text, const environment& variables) {
    return resolve_shard(text, fake(variables)).shard;
}

// The message of the input_error `resolve_shard` throws ("" when it does not).
std::string refusal(const char* text, const environment& variables) {
    try {
        resolve_shard(text, fake(variables));
    } catch (const input_error& e) {
        EXPECT_EQ(e.field(), "--shard");
        return e.what();
    }
    return "";
}

// What sbatch --array=MIN-MAX:STEP sets in task `id`.
environment slurm_task(std::size_t min, std::size_t max, std::size_t step, std::size_t id) {
    return {{"SLURM_JOB_ID", "1234"},
            {"SLURM_ARRAY_JOB_ID", "1230"},
            {"SLURM_ARRAY_TASK_ID", std::to_string(id)},
            {"SLURM_ARRAY_TASK_MIN", std::to_string(min)},
            {"SLURM_ARRAY_TASK_MAX", std::to_string(max)},
            {"SLURM_ARRAY_TASK_STEP", std::to_string(step)},
            {"SLURM_ARRAY_TASK_COUNT", std::to_string((max - min) / step + 1)}};
}

TEST(ShardEnvironment, ExplicitShardIgnoresTheEnvironment) {
    const shard_spec s = resolved("2/5", slurm_task(1, 8, 1, 7));
    EXPECT_EQ(s.index, 2u);
    EXPECT_EQ(s.count, 5u);
}

TEST(ShardEnvironment, SlurmArraysFromOneFromZeroAndWithAStep) {
    // --array=1-8: task 1 is shard 1/8, task 8 is 8/8.
    for (std::size_t id = 1; id <= 8; ++id) {
        const shard_spec s = resolved("auto", slurm_task(1, 8, 1, id));
        EXPECT_EQ(s.index, id) << id;
        EXPECT_EQ(s.count, 8u);
    }
    // --array=0-3
    EXPECT_EQ(resolved("auto", slurm_task(0, 3, 1, 0)).index, 1u);
    EXPECT_EQ(resolved("auto", slurm_task(0, 3, 1, 3)).index, 4u);
    // --array=10-40:10 is 4 tasks; id 30 is the third.
    const shard_spec step = resolved("auto", slurm_task(10, 40, 10, 30));
    EXPECT_EQ(step.index, 3u);
    EXPECT_EQ(step.count, 4u);
    // Every task of a range, each once: the N shards cover the input.
    std::set<std::size_t> seen;
    for (std::size_t id = 5; id <= 29; id += 3) seen.insert(resolved("auto", slurm_task(5, 29, 3, id)).index);
    EXPECT_EQ(seen.size(), 9u);
    EXPECT_EQ(*seen.begin(), 1u);
    EXPECT_EQ(*seen.rbegin(), 9u);
}

TEST(ShardEnvironment, SlurmWithCountAloneCountsFromZero) {
    const shard_spec s = resolved("auto", {{"SLURM_ARRAY_TASK_ID", "2"}, {"SLURM_ARRAY_TASK_COUNT", "6"}});
    EXPECT_EQ(s.index, 3u);
    EXPECT_EQ(s.count, 6u);
    EXPECT_NE(refusal("auto", {{"SLURM_ARRAY_TASK_ID", "6"}, {"SLURM_ARRAY_TASK_COUNT", "6"}})
                  .find("taken as 0 to COUNT-1"),
              std::string::npos);
}

TEST(ShardEnvironment, SlurmArraysThatAreNotOneRangeAreRefused) {
    // --array=1,5,9: MIN 1, MAX 9, 3 tasks.
    environment list = slurm_task(1, 9, 1, 5);
    list["SLURM_ARRAY_TASK_COUNT"] = "3";
    const std::string why = refusal("auto", list);
    EXPECT_NE(why.find("3 tasks, but MIN-MAX:STEP has 9"), std::string::npos) << why;
    EXPECT_NE(why.find("SLURM_ARRAY_TASK_ID=5"), std::string::npos) << why;
    EXPECT_NE(refusal("auto", {{"SLURM_ARRAY_TASK_ID", "3"}}).find("neither SLURM_ARRAY_TASK_MIN/MAX nor"),
              std::string::npos);
    EXPECT_NE(refusal("auto", {{"SLURM_ARRAY_TASK_ID", "3"}, {"SLURM_ARRAY_TASK_MIN", "1"}}).find("come together"),
              std::string::npos);
    EXPECT_NE(refusal("auto", slurm_task(10, 40, 10, 25)).find("not in the range"), std::string::npos);
}

TEST(ShardEnvironment, KubernetesNeedsTheCountOnTheCommandLine) {
    const shard_spec s = resolved("auto/16", {{"JOB_COMPLETION_INDEX", "0"}});
    EXPECT_EQ(s.index, 1u);
    EXPECT_EQ(s.count, 16u);
    EXPECT_EQ(resolved("auto/16", {{"JOB_COMPLETION_INDEX", "15"}}).index, 16u);
    const std::string no_count = refusal("auto", {{"JOB_COMPLETION_INDEX", "3"}});
    EXPECT_NE(no_count.find("use --shard auto/N"), std::string::npos) << no_count;
    EXPECT_NE(no_count.find("JOB_COMPLETION_INDEX=3"), std::string::npos) << no_count;
    EXPECT_NE(refusal("auto/16", {{"JOB_COMPLETION_INDEX", "16"}}).find("beyond 16 shards"), std::string::npos);
}

TEST(ShardEnvironment, RayverifyVariablesAreZeroBasedAsGoogleTests) {
    const shard_spec s = resolved("auto", {{"RAYVERIFY_SHARD_INDEX", "0"}, {"RAYVERIFY_TOTAL_SHARDS", "3"}});
    EXPECT_EQ(s.index, 1u);
    EXPECT_EQ(s.count, 3u);
    EXPECT_EQ(resolved("auto/3", {{"RAYVERIFY_SHARD_INDEX", "2"}}).index, 3u);
    EXPECT_NE(refusal("auto", {{"RAYVERIFY_TOTAL_SHARDS", "3"}}).find("without RAYVERIFY_SHARD_INDEX"),
              std::string::npos);
    EXPECT_NE(refusal("auto", {{"RAYVERIFY_SHARD_INDEX", "3"}, {"RAYVERIFY_TOTAL_SHARDS", "3"}}).find("beyond 3"),
              std::string::npos);
}

TEST(ShardEnvironment, SourcesThatAgreeAreAcceptedAndThoseThatDisagreeNamed) {
    environment both = slurm_task(1, 4, 1, 2);
    both["RAYVERIFY_SHARD_INDEX"] = "1";
    both["RAYVERIFY_TOTAL_SHARDS"] = "4";
    EXPECT_EQ(resolved("auto", both).index, 2u);
    both["RAYVERIFY_SHARD_INDEX"] = "0";
    const std::string why = refusal("auto", both);
    EXPECT_NE(why.find("names different shards"), std::string::npos) << why;
    EXPECT_NE(why.find("says 2/4"), std::string::npos) << why;
    EXPECT_NE(why.find("RAYVERIFY_SHARD_INDEX=0 RAYVERIFY_TOTAL_SHARDS=4 says 1/4"), std::string::npos) << why;

    // auto/N against a count in the environment.
    const std::string count = refusal("auto/8", slurm_task(1, 4, 1, 2));
    EXPECT_NE(count.find("--shard auto/8 says N = 8"), std::string::npos) << count;
    EXPECT_EQ(resolved("auto/4", slurm_task(1, 4, 1, 2)).index, 2u);
    // Kubernetes and the RAYVERIFY variables together.
    EXPECT_NE(refusal("auto/4", {{"JOB_COMPLETION_INDEX", "1"}, {"RAYVERIFY_SHARD_INDEX", "2"}})
                  .find("names different shards"),
              std::string::npos);
}

TEST(ShardEnvironment, NothingSetOrMalformedIsAClearError) {
    const std::string none = refusal("auto", {});
    EXPECT_NE(none.find("no shard in the environment"), std::string::npos) << none;
    EXPECT_NE(none.find("SLURM_ARRAY_TASK_ID"), std::string::npos) << none;
    EXPECT_NE(none.find("JOB_COMPLETION_INDEX"), std::string::npos) << none;
    EXPECT_NE(none.find("RAYVERIFY_SHARD_INDEX"), std::string::npos) << none;
    // A Slurm job that is not an array says so.
    EXPECT_NE(refusal("auto", {{"SLURM_JOB_ID", "7"}}).find("sbatch --array=1-N"), std::string::npos);
    EXPECT_NE(refusal("auto", {{"JOB_COMPLETION_INDEX", "x1"}}).find("JOB_COMPLETION_INDEX='x1' is not a whole number"),
              std::string::npos);
    EXPECT_NE(refusal("auto", {{"RAYVERIFY_SHARD_INDEX", ""}, {"RAYVERIFY_TOTAL_SHARDS", "2"}})
                  .find("RAYVERIFY_SHARD_INDEX='' is not a whole number"),
              std::string::npos);
    EXPECT_NE(refusal("auto/0", {}).find("not auto/N"), std::string::npos);
    EXPECT_NE(refusal("automatic", {}).find("auto or auto/N"), std::string::npos);
    EXPECT_NE(refusal("0/3", {}).find("1 <= K <= N"), std::string::npos);
}

// Through the executable: exit 2 with the message, and no report directory.
TEST(ShardEnvironment, TheAuditRefusesWithExit2AndTakesTheShardFromTheEnvironment) {
    using namespace rayverify::test_support;
    const std::string dir = testing::TempDir() + "rayverify_shard_env_" + std::to_string(getpid());
    const command_result none =
        run_shell("env -u SLURM_ARRAY_TASK_ID -u JOB_COMPLETION_INDEX -u RAYVERIFY_SHARD_INDEX -u "
                  "RAYVERIFY_TOTAL_SHARDS -u SLURM_JOB_ID " RAYVERIFY_CLI " audit --generate uniform:10 --shard auto "
                  "--report " + dir);
    EXPECT_EQ(none.exit_code, 2) << none.output;
    EXPECT_NE(none.output.find("no shard in the environment"), std::string::npos) << none.output;
    EXPECT_FALSE(std::filesystem::exists(dir));

    const command_result slurm = run_shell(
        "SLURM_ARRAY_TASK_ID=3 SLURM_ARRAY_TASK_MIN=1 SLURM_ARRAY_TASK_MAX=3 SLURM_ARRAY_TASK_COUNT=3 " RAYVERIFY_CLI
        " audit --generate uniform:10 --variant naive --shard auto --report " + dir);
    EXPECT_NE(slurm.exit_code, 2) << slurm.output;
    EXPECT_NE(slurm.output.find("audit: --shard auto: shard 3/3 from Slurm job array"), std::string::npos)
        << slurm.output;
    const std::string state = read_text(std::filesystem::path(dir) / "shard.json");
    EXPECT_NE(state.find(R"("shard":{"index":3,"count":3,"cases":3})"), std::string::npos) << state;
    std::filesystem::remove_all(dir);
}

}  // namespace
