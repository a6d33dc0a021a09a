// The streaming engine's pieces: error summaries (bounded, mergeable, quantiles
// as stated upper bounds), and shards run in parallel by xargs -P and merged
// into exactly the report of one run.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <random>
#include <sstream>

#include <nlohmann/json.hpp>

#include "compare/audit.h"
#include "compare/error_figures.h"
#include "support/process.h"

namespace {

namespace fs = std::filesystem;
using rayverify::error_summary;
using namespace rayverify::test_support;

double exact_nearest_rank(std::vector<double> v, double q) {
    std::sort(v.begin(), v.end());
    const auto k = static_cast<std::size_t>(std::ceil(q * static_cast<double>(v.size())));
    return v[std::clamp<std::size_t>(k, 1, v.size()) - 1];
}

TEST(ErrorSummary, QuantilesAreUpperBoundsWithinTheStatedResolution) {
    const std::uint64_t seed = std::random_device{}();
    SCOPED_TRACE(fmt::format("seed {}", seed));
    std::mt19937_64 random(seed);
    for (int round = 0; round < 50; ++round) {
        error_summary s;
        std::vector<double> values;
        const std::size_t n = 1 + random() % 2000;
        for (std::size_t i = 0; i < n; ++i) {
            // Zeros, sub-ulp errors and huge ones, as audits see them.
            const double v = random() % 7 == 0 ? 0.0 : std::ldexp(static_cast<double>(random() % 1000000) / 1e6 + 0.5,
                                                                  static_cast<int>(random() % 120) - 60);
            values.push_back(v);
            s.add(v, i, fmt::format("case-{}", i));
        }
        for (double q : {0.5, 0.99, 1.0}) {
            const double exact = exact_nearest_rank(values, q), bound = s.quantile(q);
            EXPECT_GE(bound, exact) << "round " << round << " q " << q;
            EXPECT_LE(bound, exact * (1 + std::ldexp(1.0, -error_summary::resolution_bits))) << "round " << round;
            if (exact == 0) {
                EXPECT_EQ(bound, 0);
            }
        }
        EXPECT_EQ(s.max, *std::max_element(values.begin(), values.end()));
        EXPECT_EQ(s.quantile(1.0), s.max);
    }
}

TEST(ErrorSummary, MergingAnySplitGivesTheWholeAndTiesGoToTheFirstCase) {
    const std::uint64_t seed = std::random_device{}();
    SCOPED_TRACE(fmt::format("seed {}", seed));
    std::mt19937_64 random(seed);
    error_summary whole, parts[3];
    std::size_t zeros = 0;
    for (std::size_t i = 0; i < 3000; ++i) {
        const double v = static_cast<double>(random() % 50) * 0.25;  // many ties, including at the maximum
        zeros += v == 0;
        whole.add(v, i, fmt::format("c{}", i));
        parts[random() % 3].add(v, i, fmt::format("c{}", i));
    }
    error_summary merged;  // the first merge into an empty summary copies, the others add
    for (int k : {2, 0, 1}) merged.merge(parts[k]);
    EXPECT_EQ(merged.count, whole.count);
    EXPECT_EQ(merged.histogram(), whole.histogram());
    // Exact zeros are counted apart from the table, and still bucket 0 of the histogram.
    ASSERT_GT(zeros, 0u);
    EXPECT_EQ(whole.histogram().begin()->first, 0u);
    EXPECT_EQ(whole.histogram().begin()->second, zeros);
    EXPECT_EQ(merged.max, whole.max);
    EXPECT_EQ(merged.max_id, whole.max_id);
    // The first case attaining the maximum, replayed from the seed.
    std::mt19937_64 again(seed);
    std::size_t first_at_max = 0;
    double best = -1;
    for (std::size_t i = 0; i < 3000; ++i) {
        const double v = static_cast<double>(again() % 50) * 0.25;
        again();
        if (v > best) {
            best = v;
            first_at_max = i;
        }
    }
    EXPECT_EQ(whole.max_index, first_at_max);
}

// Counters are a byte wide, the count above it kept in blocks of carries of
// their own: counts beyond 2^32 in one bucket, added one by one, in bulk (a
// shard's histogram read back) and merged, stay whole.
TEST(ErrorSummary, CountsBeyondThirtyTwoBitsCarry) {
    constexpr std::uint64_t two_32 = std::uint64_t{1} << 32;
    const std::uint64_t bucket = error_summary::bucket_of(1.5);
    error_summary a;
    a.add_to_bucket(bucket, two_32 - 1);
    a.add(1.5, 0, "a");  // the counter wraps: its carry holds 1
    EXPECT_EQ(a.histogram().at(bucket), two_32);
    a.add_to_bucket(bucket, 3 * two_32 + 7);
    EXPECT_EQ(a.histogram().at(bucket), 4 * two_32 + 7);
    error_summary b;  // as a shard's summary is read back: its count, then its buckets
    b.count = two_32 + 4;
    b.add_to_bucket(bucket, two_32 - 1);
    b.add_to_bucket(error_summary::bucket_of(2.5), 5);
    error_summary merged;  // the first merge copies, carries and all; the second adds
    merged.merge(a);
    merged.merge(b);
    EXPECT_EQ(merged.histogram().at(bucket), 5 * two_32 + 6);
    EXPECT_EQ(merged.histogram().at(error_summary::bucket_of(2.5)), 5u);
    error_summary copied;
    copied.merge(merged);
    EXPECT_EQ(copied.histogram(), merged.histogram());
}

// A byte's carries, as an audit makes them: many errors, some buckets far
// past 255 and most not, in binades whose blocks carry and whose blocks do
// not, added one by one, in bulk and merged (into a summary with blocks and
// into an empty one), against a plain count of each bucket.
TEST(ErrorSummary, CountsPastAByteMatchAPlainCount) {
    const std::uint64_t seed = std::random_device{}();
    SCOPED_TRACE(fmt::format("seed {}", seed));
    std::mt19937_64 random(seed);
    std::map<std::uint64_t, std::size_t> expected;
    error_summary one_by_one, in_bulk, merged_into_blocks;
    // Hot values (a few buckets with thousands of errors each) and a spread
    // over 2^-40 to 2^40 (most buckets with a few).
    const double hot[] = {0.5, 0.75, 1.0, 0x1.0101p3, 0x1.ffp-20};
    std::uniform_real_distribution<double> exponent(-40, 40);
    for (std::size_t i = 0; i < 60'000; ++i) {
        const double error = random() % 3 == 0 ? std::exp2(exponent(random)) : hot[random() % std::size(hot)];
        ++expected[error_summary::bucket_of(error)];
        one_by_one.add(error, i, "c");
        (i % 2 ? merged_into_blocks : in_bulk).add(error, i, "c");
    }
    EXPECT_EQ(one_by_one.histogram(), error_summary::histogram_map(expected.begin(), expected.end()));
    error_summary copied;  // the first merge copies its blocks, carries and all
    copied.merge(in_bulk);
    merged_into_blocks.merge(copied);  // the second adds block by block, carrying
    EXPECT_EQ(merged_into_blocks.histogram(), one_by_one.histogram());
    error_summary read_back;  // a shard's histogram read back: bulk adds of any size
    for (const auto& [bucket, n] : one_by_one.histogram()) read_back.add_to_bucket(bucket, n);
    for (const auto& [bucket, n] : one_by_one.histogram()) read_back.add_to_bucket(bucket, 255 * n);
    for (const auto& [bucket, n] : one_by_one.histogram()) EXPECT_EQ(read_back.histogram().at(bucket), 256 * n);

    // The statistics walk the counters (carries and all) without building
    // the histogram: each quantile is the plain count's nearest-rank bucket
    // (its upper edge, or the maximum in the maximum's bucket), several in one
    // walk the same as each alone, and the counts at least a threshold the
    // plain count's.
    const double qs[] = {0.001, 0.25, 0.5, 0.9, 0.99, 1.0};
    double together[std::size(qs)];
    for (const error_summary* s : {&one_by_one, &merged_into_blocks}) {
        s->quantiles(qs, together);
        for (std::size_t k = 0; k < std::size(qs); ++k) {
            const auto rank = static_cast<std::size_t>(std::ceil(qs[k] * static_cast<double>(s->count)));
            std::size_t seen = 0;
            std::uint64_t holding = 0;
            for (const auto& [bucket, n] : expected)
                if ((seen += n) >= rank) {
                    holding = bucket;
                    break;
                }
            const double bound =
                holding == error_summary::bucket_of(s->max) ? s->max : error_summary::upper_edge(holding);
            EXPECT_EQ(s->quantile(qs[k]), bound) << "q " << qs[k];
            EXPECT_EQ(together[k], bound) << "q " << qs[k];
        }
        const rayverify::error_statistics stats = s->statistics();
        EXPECT_EQ(stats.median, s->quantile(0.5));
        EXPECT_EQ(stats.p99, s->quantile(0.99));
        for (const double threshold : {0x1p-41, 0x1p-20, 0.5, 1.0, 8.0, 0x1p40}) {
            std::size_t at_least = 0;
            for (const auto& [bucket, n] : expected)
                if (bucket >= error_summary::bucket_of(threshold)) at_least += n;
            EXPECT_EQ(s->count_at_least(threshold), at_least) << "threshold " << threshold;
        }
    }
}

TEST(ErrorSummary, InfinityAndZeroAreExact) {
    error_summary s;
    for (std::size_t i = 0; i < 10; ++i) s.add(0, i, "z");
    EXPECT_EQ(s.quantile(0.5), 0);
    for (std::size_t i = 10; i < 30; ++i) s.add(std::numeric_limits<double>::infinity(), i, "inf");
    EXPECT_EQ(s.quantile(0.99), std::numeric_limits<double>::infinity());
    EXPECT_EQ(s.max_index, 10u);
}

class ShardMerge : public testing::Test {
protected:
    command_result in_dir(const std::string& command) {
        return run_shell(fmt::format("cd '{}' && {}", dir_.string(), command));
    }
    scratch_directory scratch_{"rayverify_shards"};
    const fs::path dir_ = scratch_.path();
};

// Shards through xargs -P, merged, equal the single run byte for byte: every
// report file, the per-case lines and the summary on stdout.
TEST_F(ShardMerge, ShardsRunByXargsMergeIntoTheSingleRunByteForByte) {
    const std::string input = fmt::format("--corpus '{}/near_tangent.txt' --corpus '{}/edge/behind.txt'",
                                          RAYVERIFY_CORPUS_DIR, RAYVERIFY_CORPUS_DIR);
    const command_result single =
        in_dir(fmt::format("'{}' audit {} --threads 2 --report single --per-case single/cases.jsonl", RAYVERIFY_CLI,
                           input));
    ASSERT_NE(single.exit_code, 2) << single.output;
    const command_result shards = in_dir(fmt::format(
        "seq 1 5 | xargs -P 3 -I K '{}' audit {} --threads 1 --shard K/5 --report shard-K "
        "--per-case shard-K/cases.jsonl >/dev/null; echo done",
        RAYVERIFY_CLI, input));
    ASSERT_NE(shards.output.find("done"), std::string::npos) << shards.output;
    const command_result merged = in_dir(fmt::format(
        "'{}' merge --report merged --per-case merged/cases.jsonl shard-4 shard-2 shard-1 shard-5 shard-3", RAYVERIFY_CLI));
    EXPECT_EQ(merged.exit_code, single.exit_code) << merged.output;
    for (const char* file : {"report.json", "report.md", "summary.txt", "audit.csv", "cases.jsonl"}) {
        const std::string a = read_text(dir_ / "single" / file), b = read_text(dir_ / "merged" / file);
        EXPECT_FALSE(a.empty()) << file;
        EXPECT_TRUE(a == b) << file << " differs (" << a.size() << " vs " << b.size() << " bytes)";
    }
    // The output differs only in the report path it names, and the audit's
    // note of what it read (merge reads no corpus).
    const auto without_path = [](std::string out, const std::string& dir) {
        if (out.starts_with("audit: read ")) out.erase(0, out.find('\n') + 1);
        return out.replace(out.find(dir + "/report.json"), dir.size(), "DIR");
    };
    EXPECT_EQ(without_path(single.output, "single"), without_path(merged.output, "merged"));
}

TEST_F(ShardMerge, GeneratedCasesShardAndMergeWithoutACorpusFile) {
    const std::string input = "--generate near_tangent:300:7 --generate uniform:150";
    ASSERT_NE(in_dir(fmt::format("'{}' audit {} --report single", RAYVERIFY_CLI, input)).exit_code, 2);
    for (int k = 1; k <= 4; ++k)
        ASSERT_NE(in_dir(fmt::format("'{}' audit {} --shard {}/4 --report s{}", RAYVERIFY_CLI, input, k, k)).exit_code, 2);
    ASSERT_NE(in_dir(fmt::format("'{}' merge --report merged s1 s2 s3 s4", RAYVERIFY_CLI)).exit_code, 2);
    EXPECT_TRUE(read_text(dir_ / "single/report.json") == read_text(dir_ / "merged/report.json"));
    EXPECT_NE(read_text(dir_ / "single/report.json").find("\"near_tangent:300:7\""), std::string::npos);
}

TEST_F(ShardMerge, MergeRefusesShardsThatDoNotBelongTogether) {
    const auto shard = [&](const std::string& input, const std::string& spec, const std::string& dir) {
        ASSERT_NE(in_dir(fmt::format("'{}' audit {} --shard {} --report {}", RAYVERIFY_CLI, input, spec, dir)).exit_code,
                  2);
    };
    shard("--generate uniform:40", "1/3", "a1");
    shard("--generate uniform:40", "2/3", "a2");
    shard("--generate uniform:40", "3/3", "a3");
    shard("--generate uniform:41", "3/3", "b3");
    shard("--generate uniform:40 --variant naive", "3/3", "c3");
    const auto refused = [&](const std::string& shards, const std::string& message) {
        const command_result r = in_dir(fmt::format("'{}' merge --report out {}", RAYVERIFY_CLI, shards));
        EXPECT_EQ(r.exit_code, 2) << shards << ": " << r.output;
        EXPECT_NE(r.output.find(message), std::string::npos) << shards << ": " << r.output;
        EXPECT_FALSE(fs::exists(dir_ / "out" / "report.json")) << shards;
    };
    refused("a1 a2", "missing shard(s) 3/3");
    refused("a1 a2 a3 a3", "shard 3/3 given twice");
    refused("a1 a2 b3", "field 'input': differs");
    refused("a1 a2 c3", "differs from");
    refused("a1 a2 nowhere", "not the report directory");
    EXPECT_EQ(in_dir(fmt::format("'{}' merge --report out a3 a1 a2", RAYVERIFY_CLI)).exit_code, 0);
}

// Report.json without what names the run's spelling: its command and input paths.
std::string figures_of(const fs::path& report) {
    nlohmann::ordered_json j = nlohmann::ordered_json::parse(read_text(report));
    j.erase("command");
    j["corpus"].erase("paths");
    // Where a case to open was read is a path as spelled, like the corpus paths.
    for (auto& target : j["cases_to_open"]) {
        for (auto& verdict : target["verdicts"])
            for (const char* list : {"first", "worst"})
                if (verdict.contains(list))
                    for (auto& c : verdict[list]) c.erase("source");
        for (auto& c : target["agree_far"]) c.erase("source");
    }
    return j.dump(1);
}

// Shards started from other working directories, through another copy of the
// executable (another install) and of the corpus, with paths spelled
// relative, absolute, with ./ and as --option=value, merge into the single
// run's figures; an option that changes the audit is named precisely.
TEST_F(ShardMerge, ShardsSpelledFromOtherDirectoriesAndInstallsMerge) {
    fs::create_directories(dir_ / "opt/bin");
    fs::create_directories(dir_ / "data");
    fs::create_directories(dir_ / "elsewhere");
    fs::copy_file(RAYVERIFY_CLI, dir_ / "opt/bin/rayverify");
    fs::copy_file(fs::path(RAYVERIFY_CORPUS_DIR) / "near_tangent.txt", dir_ / "data/near_tangent.txt");
    const std::string options = "--variant naive --variant half_b";
    const command_result single = in_dir(fmt::format("'{}' audit --corpus '{}/near_tangent.txt' {} --report single",
                                                     RAYVERIFY_CLI, RAYVERIFY_CORPUS_DIR, options));
    ASSERT_NE(single.exit_code, 2) << single.output;
    const std::string shards[] = {
        fmt::format("./opt/bin/rayverify audit --corpus ./data/near_tangent.txt {} --shard 1/3 --report s1", options),
        fmt::format("cd data && ../opt/bin/rayverify audit --corpus=near_tangent.txt {} --shard=2/3 --report ../s2",
                    options),
        fmt::format("cd elsewhere && '{}' audit --corpus '{}/data/near_tangent.txt' {} --report '{}/s3' --shard 3/3",
                    RAYVERIFY_CLI, dir_.string(), options, dir_.string()),
    };
    for (const std::string& shard : shards) ASSERT_NE(in_dir(shard).exit_code, 2) << shard;
    const command_result merged = in_dir(fmt::format("'{}' merge -o merged s3 s1 s2", RAYVERIFY_CLI));
    ASSERT_EQ(merged.exit_code, single.exit_code) << merged.output;
    EXPECT_EQ(figures_of(dir_ / "single/report.json"), figures_of(dir_ / "merged/report.json"));
    EXPECT_TRUE(read_text(dir_ / "single/summary.txt") == read_text(dir_ / "merged/summary.txt"));
    // The merged report records shard 1's spelling, whatever the order of the directories.
    EXPECT_NE(read_text(dir_ / "merged/report.json").find("\"command\": \"./opt/bin/rayverify audit --corpus "
                                                          "./data/near_tangent.txt --variant naive"),
              std::string::npos);

    // A shard of another audit: the option it adds (or changes) is named, and nothing is written.
    ASSERT_NE(in_dir(fmt::format("./opt/bin/rayverify audit --corpus data/near_tangent.txt --variant naive "
                                 "--variant half_b --precision float --shard 3/3 --report t3"))
                  .exit_code,
              2);
    const command_result other = in_dir(fmt::format("'{}' merge -o refused s1 s2 t3", RAYVERIFY_CLI));
    EXPECT_EQ(other.exit_code, 2) << other.output;
    EXPECT_NE(other.output.find("t3/shard.json: field 'command': differs from s1/shard.json: t3/shard.json has "
                                "'--precision float'"),
              std::string::npos)
        << other.output;
    EXPECT_FALSE(fs::exists(dir_ / "refused"));
    ASSERT_NE(in_dir("./opt/bin/rayverify audit --corpus data/near_tangent.txt --variant half_b --variant naive "
                     "--shard 3/3 --report u3")
                  .exit_code,
              2);
    const command_result order = in_dir(fmt::format("'{}' merge -o refused s1 s2 u3", RAYVERIFY_CLI));
    EXPECT_EQ(order.exit_code, 2) << order.output;
    EXPECT_NE(order.output.find("the same options in another order"), std::string::npos) << order.output;
}

// Shards judged against answers computed outside rayverify: the state
// records a digest of the answers, and merge compares digests, not the
// spelling of the --results path. Shards of different answers are refused
// (they used to merge into a report of no single run); the same answers
// under another path merge.
TEST_F(ShardMerge, ShardsOfOtherAnswersAreRefusedAndTheSameAnswersElsewhereMerge) {
    const std::string input = "--generate uniform:6:3";
    ASSERT_EQ(in_dir(fmt::format("'{}' corpus export {} -o cases.csv", RAYVERIFY_CLI, input)).exit_code, 0);
    std::istringstream cases(read_text(dir_ / "cases.csv"));
    std::string header, columns, line;
    std::getline(cases, header);
    std::getline(cases, columns);
    const std::size_t at = header.find("fingerprint=");
    ASSERT_NE(at, std::string::npos) << header;
    const std::string head = "# rayverify results v1 precision=double " + header.substr(at, 28) + "\nid,count,t0,t1\n";
    std::string misses = head, other = head;
    for (bool first = true; std::getline(cases, line); first = false) {
        const std::string id = line.substr(0, line.find(','));
        misses += id + ",0,,\n";
        other += id + (first ? ",1,1,\n" : ",0,,\n");
    }
    fs::create_directories(dir_ / "elsewhere");
    std::ofstream(dir_ / "a.csv") << misses;
    std::ofstream(dir_ / "elsewhere/a.csv") << misses;
    std::ofstream(dir_ / "b.csv") << other;
    const auto shard = [&](const std::string& results, const std::string& spec, const std::string& dir) {
        const command_result r =
            in_dir(fmt::format("'{}' audit {} --results {} --contract query=line_roots --name mine --shard {} --report {}",
                               RAYVERIFY_CLI, input, results, spec, dir));
        ASSERT_NE(r.exit_code, 2) << r.output;
    };
    shard("a.csv", "1/2", "s1");
    shard("b.csv", "2/2", "other2");
    shard("./elsewhere/../elsewhere/a.csv", "2/2", "same2");
    const command_result mixed = in_dir(fmt::format("'{}' merge --report out s1 other2", RAYVERIFY_CLI));
    EXPECT_EQ(mixed.exit_code, 2) << mixed.output;
    EXPECT_NE(mixed.output.find("other2/shard.json: field 'input': differs from s1/shard.json"), std::string::npos)
        << mixed.output;
    EXPECT_FALSE(fs::exists(dir_ / "out"));
    const command_result same = in_dir(fmt::format("'{}' merge --report out s1 same2", RAYVERIFY_CLI));
    EXPECT_NE(same.exit_code, 2) << same.output;
    EXPECT_TRUE(fs::exists(dir_ / "out/report.json"));
}

// merge --per-case reads each shard's per-case file as it reads its state:
// the very file the shard's audit wrote (by its digest), a regular file
// inside the shard directory once links are resolved. Each refusal leaves
// no output.
TEST_F(ShardMerge, PerCaseFilesAreCheckedAsStatesAre) {
    for (int k = 1; k <= 2; ++k)
        ASSERT_NE(in_dir(fmt::format("'{}' audit --generate uniform:40 --variant naive --shard {}/2 --report s{} "
                                     "--per-case s{}/cases.jsonl",
                                     RAYVERIFY_CLI, k, k, k))
                      .exit_code,
                  2);
    const std::string one = read_text(dir_ / "s1/cases.jsonl"), two = read_text(dir_ / "s2/cases.jsonl");
    const auto refused = [&](const std::string& message) {
        // timeout: a FIFO used to block the merge for ever
        const command_result r = in_dir(
            fmt::format("timeout 60 '{}' merge --report out --per-case out.jsonl s1 s2", RAYVERIFY_CLI));
        EXPECT_EQ(r.exit_code, 2) << r.output;
        EXPECT_NE(r.output.find(message), std::string::npos) << r.output;
        EXPECT_FALSE(fs::exists(dir_ / "out.jsonl"));
        EXPECT_FALSE(fs::exists(dir_ / "out"));
    };
    // Swapped between the shards (the same number of lines).
    std::ofstream(dir_ / "s1/cases.jsonl", std::ios::trunc) << two;
    std::ofstream(dir_ / "s2/cases.jsonl", std::ios::trunc) << one;
    refused("s1/cases.jsonl: field '--per-case': its digest is");
    std::ofstream(dir_ / "s2/cases.jsonl", std::ios::trunc) << two;
    // One line edited.
    std::string edited = one;
    edited[edited.find("\"id\":") + 6] ^= 1;
    std::ofstream(dir_ / "s1/cases.jsonl", std::ios::trunc) << edited;
    refused("not the per-case file that shard's audit wrote");
    // A link out of the shard directory (to a copy of the right file).
    std::ofstream(dir_ / "copy.jsonl") << one;
    fs::remove(dir_ / "s1/cases.jsonl");
    fs::create_symlink("../copy.jsonl", dir_ / "s1/cases.jsonl");
    refused("outside the shard directory");
    // A FIFO.
    fs::remove(dir_ / "s1/cases.jsonl");
    ASSERT_EQ(::mkfifo((dir_ / "s1/cases.jsonl").c_str(), 0600), 0);
    refused("s1/cases.jsonl: field '--per-case': is not a regular file");
    // Put back: the merge succeeds.
    fs::remove(dir_ / "s1/cases.jsonl");
    std::ofstream(dir_ / "s1/cases.jsonl") << one;
    const command_result ok = in_dir(fmt::format("'{}' merge --report out --per-case out.jsonl s1 s2", RAYVERIFY_CLI));
    EXPECT_NE(ok.exit_code, 2) << ok.output;
    // A state that is a FIFO is refused before it is opened, too.
    fs::rename(dir_ / "s2/shard.json", dir_ / "s2.json");
    ASSERT_EQ(::mkfifo((dir_ / "s2/shard.json").c_str(), 0600), 0);
    const command_result fifo = in_dir(fmt::format("timeout 60 '{}' merge --report fifo s1 s2", RAYVERIFY_CLI));
    EXPECT_EQ(fifo.exit_code, 2) << fifo.output;
    EXPECT_NE(fifo.output.find("s2/shard.json: is not a regular file"), std::string::npos) << fifo.output;
}

// Every error figure's summary, in each family's tally and in the whole
// run's, refuses an edited value: a negative maximum, a count its buckets do
// not hold, and (the whole run's, which merge forms again from the families)
// any value that differs from the families' merge. The figures come from the
// one table, so a new figure is covered without a change here.
TEST_F(ShardMerge, EveryErrorFigureOfEveryTallyRefusesATamperedValue) {
    ASSERT_NE(in_dir(fmt::format("'{}' audit --generate uniform:30 --generate near_tangent:30 --variant naive "
                                 "--variant embree4 --shard 1/1 --report s1",
                                 RAYVERIFY_CLI))
                  .exit_code,
              2);
    const std::string original = read_text(dir_ / "s1/shard.json");
    const auto refused = [&](const std::string& what, const std::function<void(nlohmann::ordered_json&)>& edit,
                             const std::string& field) {
        nlohmann::ordered_json state = nlohmann::ordered_json::parse(original);
        edit(state);
        std::ofstream(dir_ / "s1/shard.json", std::ios::trunc) << state.dump();
        const command_result r = in_dir(fmt::format("'{}' merge --report out s1", RAYVERIFY_CLI));
        EXPECT_EQ(r.exit_code, 2) << what << ": " << r.output;
        EXPECT_NE(r.output.find("field '" + field), std::string::npos) << what << ": " << r.output;
        EXPECT_FALSE(fs::exists(dir_ / "out")) << what;
    };
    std::size_t edits = 0;
    for (const rayverify::error_figure_definition& f : rayverify::error_figures) {
        const std::string name(f.name);
        const std::string family_path = "state.audit.by_family.uniform[1]." + name,
                          whole_path = "state.audit.overall[1]." + name;
        const auto family = [&](nlohmann::ordered_json& j) -> nlohmann::ordered_json& {
            return j["state"]["audit"]["by_family"]["uniform"][1][name];
        };
        const auto whole = [&](nlohmann::ordered_json& j) -> nlohmann::ordered_json& {
            return j["state"]["audit"]["overall"][1][name];
        };
        refused(name + ": a family's negative max", [&](nlohmann::ordered_json& j) { family(j)["max"] = "-0x1p+0"; }, family_path + ".max");
        refused(name + ": a family's count", [&](nlohmann::ordered_json& j) { family(j)["count"] = family(j)["count"].get<int>() + 1; },
                family_path + ".count");
        refused(name + ": the whole run's negative max", [&](nlohmann::ordered_json& j) { whole(j)["max"] = "-0x1p+0"; }, whole_path + ".max");
        refused(name + ": the whole run's count", [&](nlohmann::ordered_json& j) { whole(j)["count"] = whole(j)["count"].get<int>() + 1; },
                whole_path + ".count");
        // (with no error in it, a case named for the max is refused as a max set)
        refused(name + ": the whole run's case of the max", [&](nlohmann::ordered_json& j) { whole(j)["max_id"] = "elsewhere"; },
                whole_path + ".max");
        edits += 5;
    }
    EXPECT_EQ(edits, 5 * rayverify::error_figure_count);
    // Untouched, it merges.
    std::ofstream(dir_ / "s1/shard.json", std::ios::trunc) << original;
    EXPECT_NE(in_dir(fmt::format("'{}' merge --report out s1", RAYVERIFY_CLI)).exit_code, 2);
}

TEST_F(ShardMerge, ThePlotSampleIsBoundedPerFamily) {
    ASSERT_NE(in_dir(fmt::format("'{}' audit --generate uniform:1100 --variant naive --report r", RAYVERIFY_CLI))
                  .exit_code,
              2);
    const std::string report = read_text(dir_ / "r/report.json");
    EXPECT_NE(report.find("\"cases\": 1024,\n    \"sample\""), std::string::npos);
}

}  // namespace
