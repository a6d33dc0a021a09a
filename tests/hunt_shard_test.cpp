// Sharded hunts: N independent hunts with disjoint start cases and distinct
// search seeds, and `merge` of their output files keeping the worst finds
// with their provenance (shard, search seed, evaluation, start case).
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <set>

#include "compare/hunt.h"
#include "report/hunt_file.h"
#include "support/process.h"

namespace {

namespace fs = std::filesystem;
using namespace rayverify;
using namespace rayverify::test_support;

TEST(HuntShards, SearchSeedsAreDistinctPerShardAndTheSeedItselfUnsharded) {
    for (const std::uint64_t seed : {std::uint64_t{1}, std::uint64_t{0}, ~std::uint64_t{0}}) {
        EXPECT_EQ(shard_search_seed(seed, 1, 1), seed);
        std::set<std::uint64_t> seen;
        for (std::size_t k = 1; k <= 1000; ++k) seen.insert(shard_search_seed(seed, k, 1000));
        EXPECT_EQ(seen.size(), 1000u) << "seed " << seed;
    }
}

class HuntMerge : public testing::Test {
protected:
    command_result in_dir(const std::string& command) {
        return run_shell(fmt::format("cd '{}' && {}", dir_.string(), command));
    }
    // Shard k of n of a reproducible ulp hunt of naive in double.
    void hunt_shard(std::size_t k, std::size_t n, const std::string& extra = "") {
        const command_result r =
            in_dir(fmt::format("'{}' hunt --variant naive --budget 0 --evaluations 1500 --shard {}/{} {} -o h{}.txt",
                               RAYVERIFY_CLI, k, n, extra, k));
        ASSERT_NE(r.exit_code, 2) << r.output;
    }
    scratch_directory scratch_{"rayverify_hunt_shards"};
    const fs::path dir_ = scratch_.path();
};

TEST_F(HuntMerge, ShardsStartFromDisjointCasesAndTheMergeKeepsTheWorstWithProvenance) {
    for (std::size_t k = 1; k <= 3; ++k) hunt_shard(k, 3);
    double worst = 0;
    std::size_t worst_shard = 0;
    std::set<std::uint64_t> seeds;
    for (std::size_t k = 1; k <= 3; ++k) {
        const hunt_file shard = read_hunt_file(dir_ / fmt::format("h{}.txt", k));
        ASSERT_EQ(shard.hunt.runs.size(), 1u);
        seeds.insert(shard.hunt.runs.at(0).search_seed);
        ASSERT_EQ(shard.finds.size(), 1u);
        // Start case uniform-1-<index>: index = k − 1 modulo 3.
        const std::string start = shard.finds[0].provenance.start;
        EXPECT_EQ(std::stoul(start.substr(start.rfind('-') + 1)) % 3, k - 1) << start;
        EXPECT_EQ(shard.finds[0].provenance.shard.text(), fmt::format("{}/3", k));
        if (shard.finds[0].provenance.error > worst) {
            worst = shard.finds[0].provenance.error;
            worst_shard = k;
        }
    }
    EXPECT_EQ(seeds.size(), 3u);

    const command_result merged = in_dir(fmt::format("'{}' merge -o m.txt h2.txt h3.txt h1.txt", RAYVERIFY_CLI));
    ASSERT_EQ(merged.exit_code, 0) << merged.output;
    EXPECT_NE(merged.output.find("merged 3 hunt shards of naive/double (ulp objective): 4500 evaluations; kept 3 of 3"),
              std::string::npos)
        << merged.output;
    const hunt_file m = read_hunt_file(dir_ / "m.txt");
    ASSERT_EQ(m.finds.size(), 3u);
    EXPECT_EQ(m.finds[0].provenance.error, worst);
    EXPECT_EQ(m.finds[0].provenance.shard.text(), fmt::format("{}/3", worst_shard));
    EXPECT_GE(m.finds[0].provenance.error, m.finds[1].provenance.error);
    EXPECT_GE(m.finds[1].provenance.error, m.finds[2].provenance.error);
    EXPECT_EQ(m.hunt.runs.size(), 3u);
    const std::string text = read_text(dir_ / "m.txt");
    EXPECT_NE(text.find(fmt::format("in shard {}/3 (search seed ", worst_shard)), std::string::npos) << text;
    EXPECT_NE(text.find("# merged from 3 shards"), std::string::npos) << text;

    // The finds are corpus lines: the merged file audits as a corpus.
    EXPECT_NE(run_cli("audit --variant naive --precision double --corpus " + (dir_ / "m.txt").string()).exit_code, 2);
    // The order of the files does not matter; a merge merges again; --finds keeps fewer.
    ASSERT_EQ(in_dir(fmt::format("'{}' merge -o again.txt h1.txt h3.txt h2.txt", RAYVERIFY_CLI)).exit_code, 0);
    EXPECT_TRUE(read_text(dir_ / "again.txt") == text);
    ASSERT_EQ(in_dir(fmt::format("'{}' merge -o h12.txt h1.txt h2.txt", RAYVERIFY_CLI)).exit_code, 2);  // 3/3 missing
    ASSERT_EQ(in_dir(fmt::format("'{}' merge -o one.txt --finds 1 h1.txt h2.txt h3.txt", RAYVERIFY_CLI)).exit_code, 0);
    EXPECT_EQ(read_hunt_file(dir_ / "one.txt").finds.size(), 1u);
}

TEST_F(HuntMerge, MergesOfSomeShardsMergeAgain) {
    for (std::size_t k = 1; k <= 4; ++k) hunt_shard(k, 4);
    ASSERT_EQ(in_dir(fmt::format("'{}' merge -o all.txt --finds 4 h1.txt h2.txt h3.txt h4.txt", RAYVERIFY_CLI))
                  .exit_code,
              0);
    // Two partial merges (each missing shards) are refused alone, but merge together.
    const command_result partial = in_dir(fmt::format("'{}' merge -o a.txt h1.txt h3.txt", RAYVERIFY_CLI));
    EXPECT_EQ(partial.exit_code, 2);
    EXPECT_NE(partial.output.find("missing hunt shard(s) 2/4, 4/4"), std::string::npos) << partial.output;
    EXPECT_FALSE(fs::exists(dir_ / "a.txt"));
}

TEST_F(HuntMerge, HuntsThatDoNotBelongTogetherAreRefusedNamingWhatDiffers) {
    hunt_shard(1, 2);
    hunt_shard(2, 2);
    const auto refused = [&](const std::string& files, const std::string& message) {
        const command_result r = in_dir(fmt::format("'{}' merge -o out.txt {}", RAYVERIFY_CLI, files));
        EXPECT_EQ(r.exit_code, 2) << files << ": " << r.output;
        EXPECT_NE(r.output.find(message), std::string::npos) << files << ": " << r.output;
        EXPECT_FALSE(fs::exists(dir_ / "out.txt")) << files;
    };
    refused("h1.txt h1.txt h2.txt", "shard 1/2 given twice");
    fs::rename(dir_ / "h2.txt", dir_ / "keep.txt");
    hunt_shard(2, 2, "--finds 5");
    refused("h1.txt h2.txt", "field 'command': differs from h1.txt: h2.txt has '--finds 5' (shards of different hunts");
    hunt_shard(2, 2, "--seed 5");
    refused("h1.txt h2.txt", "field 'seed': differs from h1.txt: 5 vs 1");
    hunt_shard(2, 2, "--objective misclass");
    refused("h1.txt h2.txt", "field 'objective'");
    hunt_shard(2, 3);
    refused("h1.txt h2.txt", "field 'shards'");
    fs::create_directories(dir_ / "a_directory");
    refused("h1.txt a_directory", "either audit shards (directories) or hunt outputs (files), not both");
    refused("h1.txt " RAYVERIFY_CORPUS_DIR "/uniform.txt", "neither an audit shard's report directory nor the output");
    refused("--per-case x.jsonl h1.txt keep.txt", "no --per-case or --plots");
    EXPECT_EQ(in_dir(fmt::format("'{}' merge -o out.txt keep.txt h1.txt", RAYVERIFY_CLI)).exit_code, 0);
}

TEST_F(HuntMerge, MisclassShardsMergeWithExit1AndTakeTheShardFromTheEnvironment) {
    for (int index = 0; index < 2; ++index) {
        const command_result r = in_dir(fmt::format(
            "RAYVERIFY_SHARD_INDEX={} RAYVERIFY_TOTAL_SHARDS=2 '{}' hunt --variant naive --precision float "
            "--objective misclass --budget 0 --evaluations 3000 --finds 2 --shard auto -o m{}.txt",
            index, RAYVERIFY_CLI, index));
        EXPECT_EQ(r.exit_code, 1) << r.output;
        EXPECT_NE(r.output.find(fmt::format("hunt: --shard auto: shard {}/2 from RAYVERIFY_SHARD_INDEX={}", index + 1,
                                            index)),
                  std::string::npos)
            << r.output;
    }
    const command_result merged = in_dir(fmt::format("'{}' merge -o m.txt --finds 3 m1.txt m0.txt", RAYVERIFY_CLI));
    EXPECT_EQ(merged.exit_code, 1) << merged.output;
    const hunt_file m = read_hunt_file(dir_ / "m.txt");
    ASSERT_EQ(m.finds.size(), 3u);
    // Disagreements in shard order: both of shard 1, then the first of shard 2.
    EXPECT_EQ(m.finds[0].provenance.shard.text(), "1/2");
    EXPECT_EQ(m.finds[1].provenance.shard.text(), "1/2");
    EXPECT_EQ(m.finds[2].provenance.shard.text(), "2/2");
    EXPECT_LT(m.finds[0].provenance.evaluation, m.finds[1].provenance.evaluation);
    // The kept finds still disagree when audited.
    EXPECT_EQ(run_cli("audit --variant naive --precision float --corpus " + (dir_ / "m.txt").string()).exit_code, 1);
}

TEST_F(HuntMerge, AMalformedHuntFileIsAnInputErrorWithItsLine) {
    hunt_shard(1, 1);
    {  // a field of the wrong type, named by its path on its line
        std::string text = read_text(dir_ / "h1.txt");
        const std::size_t at = text.find("\"found_bits\":");
        ASSERT_NE(at, std::string::npos);
        text.insert(at + 13, "-");
        std::ofstream(dir_ / "bad.txt", std::ios::binary) << text;
        const command_result r = in_dir(fmt::format("'{}' merge -o out.txt bad.txt", RAYVERIFY_CLI));
        EXPECT_EQ(r.exit_code, 2) << r.output;
        const auto line = 1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n');
        EXPECT_NE(r.output.find(fmt::format("bad.txt:{}: field 'found_bits': is -", line)), std::string::npos)
            << r.output;
        EXPECT_FALSE(fs::exists(dir_ / "out.txt"));
    }
    std::string text = read_text(dir_ / "h1.txt");
    const std::size_t at = text.find("# rayverify-find {");
    ASSERT_NE(at, std::string::npos);
    text.insert(at + 18, "oops");
    std::ofstream(dir_ / "bad.txt", std::ios::binary) << text;
    const command_result r = in_dir(fmt::format("'{}' merge -o out.txt bad.txt", RAYVERIFY_CLI));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    const auto line = 1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n');
    EXPECT_NE(r.output.find(fmt::format("bad.txt:{}: ", line)), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("syntax error"), std::string::npos) << r.output;
}

}  // namespace
