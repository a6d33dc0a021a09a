// The recipes of docs/scaling_out.md, run as the page writes them (only the
// input made smaller and the Kubernetes volume put in a temporary directory):
// GNU parallel, and the commands of the Kubernetes Indexed Job manifest with
// JOB_COMPLETION_INDEX set as Kubernetes sets it. Each must give the report one
// process auditing the same input writes, byte for byte. (The Slurm recipe
// runs on a real Slurm in the test labelled `slurm`.) Also: a merge of more
// shards' per-case files than the open-file limit allows at first.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <regex>

#include "support/process.h"

namespace {

namespace fs = std::filesystem;
using namespace rayverify::test_support;

// The lines of the docs page's fenced block that follows `marker`.
std::string block_after(const std::string& marker) {
    const std::string page = read_text(fs::path(RAYVERIFY_SOURCE_DIR) / "docs/scaling_out.md");
    const std::size_t at = page.find(marker);
    EXPECT_NE(at, std::string::npos) << marker;
    const std::size_t open = page.find("```", at);
    const std::size_t body = page.find('\n', open) + 1;
    return page.substr(body, page.find("```", body) - body);
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
    for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
        text.replace(at, from.size(), to);
    return text;
}

class ScalingOut : public testing::Test {
protected:
    // A shell command in the temporary directory, finding `rayverify` on the PATH as the page does.
    command_result in_dir(const std::string& command) {
        const std::string path = fs::path(RAYVERIFY_CLI).parent_path().string();
        return run_shell(fmt::format("cd '{}' && PATH='{}':\"$PATH\" && {}", dir_.string(), path, command));
    }
    void expect_same_report(const fs::path& a, const fs::path& b) {
        for (const char* file : {"report.json", "summary.txt", "report.md", "audit.csv"}) {
            const std::string x = read_text(a / file), y = read_text(b / file);
            EXPECT_FALSE(x.empty()) << a / file;
            EXPECT_TRUE(x == y) << (a / file) << " and " << (b / file) << " differ";
        }
    }
    scratch_directory scratch_{"rayverify_scaling"};
    const fs::path dir_ = scratch_.path();
};

TEST_F(ScalingOut, TheGnuParallelRecipeMergesIntoTheSingleRun) {
    const std::string recipe = block_after("<!-- recipe: gnu-parallel -->");
    ASSERT_NE(recipe.find("parallel"), std::string::npos) << recipe;
    ASSERT_NE(recipe.find("uniform:10000000"), std::string::npos) << recipe;
    const command_result run = in_dir(replaced(recipe, "uniform:10000000", "uniform:2400"));
    ASSERT_NE(run.output.find("report: merged/report.json"), std::string::npos) << recipe << run.output;
    const command_result single = in_dir("rayverify audit --generate uniform:2400 --report single");
    ASSERT_NE(single.exit_code, 2) << single.output;
    expect_same_report(dir_ / "single", dir_ / "merged");
}

TEST_F(ScalingOut, TheKubernetesManifestsCommandsRunAsAnIndexedJob) {
    // The commands of the Indexed Job's pods and of the merge Job, as `args: ["..."]` lines.
    const std::string manifest = block_after("<!-- recipe: kubernetes -->");
    const std::regex args_line(R"re(args: \["(.*)"\])re");
    std::vector<std::string> commands;
    for (std::sregex_iterator m(manifest.begin(), manifest.end(), args_line), end; m != end; ++m)
        commands.push_back(replaced(replaced((*m)[1], "/results", dir_.string() + "/results"), "uniform:100000000",
                                    "uniform:1800"));
    ASSERT_EQ(commands.size(), 2u) << manifest;
    const std::regex completions(R"(completions: (\d+))");
    std::smatch n;
    ASSERT_TRUE(std::regex_search(manifest, n, completions)) << manifest;
    ASSERT_NE(commands[0].find(fmt::format("--shard auto/{}", n[1].str())), std::string::npos) << commands[0];
    for (int index = 0; index < std::stoi(n[1]); ++index) {
        const command_result pod = in_dir(
            fmt::format("env -u SLURM_ARRAY_TASK_ID JOB_COMPLETION_INDEX={} /bin/sh -c '{}'", index, commands[0]));
        ASSERT_EQ(pod.exit_code, 0) << "index " << index << ": " << commands[0] << "\n" << pod.output;
    }
    const command_result merge = in_dir(fmt::format("/bin/sh -c '{}'", commands[1]));
    ASSERT_NE(merge.exit_code, 2) << commands[1] << "\n" << merge.output;
    const command_result single = in_dir("rayverify audit --generate uniform:1800 --report single");
    expect_same_report(dir_ / "single", dir_ / "results/merged");
}

// 100 shards' per-case files are read side by side; with a soft limit of 40
// open files the merge raises it (up to the hard limit), and names the limit
// when even the hard limit is too low.
TEST_F(ScalingOut, PerCaseFilesOfMoreShardsThanTheOpenFileLimitMerge) {
    const std::string audit = "rayverify audit --generate uniform:500 --variant naive --precision double";
    const command_result shards = in_dir(
        fmt::format("seq 1 100 | parallel --will-cite -j 2 -n 25 'for k in {{}}; do {} --threads 1 --shard $k/100 "
                    "--report shard-$k --per-case shard-$k/cases.jsonl >/dev/null; [ $? -le 1 ] || exit 2; done'",
                    audit));
    ASSERT_EQ(shards.exit_code, 0) << shards.output;
    const command_result single = in_dir(audit + " --report single --per-case single/cases.jsonl");
    ASSERT_NE(single.exit_code, 2) << single.output;
    const command_result merged =
        in_dir("ulimit -S -n 40 && rayverify merge -o merged --per-case merged/cases.jsonl shard-*");
    ASSERT_EQ(merged.exit_code, single.exit_code) << merged.output;
    EXPECT_TRUE(read_text(dir_ / "single/cases.jsonl") == read_text(dir_ / "merged/cases.jsonl"));
    expect_same_report(dir_ / "single", dir_ / "merged");
    const command_result refused =
        in_dir("ulimit -n 40 && rayverify merge -o refused --per-case refused/cases.jsonl shard-*");
    EXPECT_EQ(refused.exit_code, 2) << refused.output;
    EXPECT_NE(refused.output.find("merging the per-case files of 100 shards needs 164 open files, and this process "
                                  "may open 40 (ulimit -n)"),
              std::string::npos)
        << refused.output;
    EXPECT_FALSE(fs::exists(dir_ / "refused"));
}

}  // namespace
