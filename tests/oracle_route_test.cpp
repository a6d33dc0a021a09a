// The oracle's two routes give the same audit, byte for byte: the filtered
// oracle (static and double-word filters, expansions, exact arithmetic only
// where they cannot settle an answer) and the reference route (no filter: the
// class, the signs and the rounded roots in exact arithmetic, and every ULP
// figure and comparison a verdict is decided by without the filters'
// enclosures). Every verdict count and
// every printed figure of every output must be the same on the shipped
// corpus, the edge and segment corpora, generated cases, a scene and a
// sharded run merged: a change in how the filtered route computes a figure
// (a bracket where an exact value was) that moves one printed digit fails here.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "support/process.h"

namespace {

namespace fs = std::filesystem;
using namespace rayverify::test_support;

// `text` without what names the route or the directory a run wrote to: the
// option on the command line (report.json's and report.md's record of it)
// and the report paths printed on stdout.
std::string without_route(std::string text, const std::string& directory) {
    for (const std::string& spelling : {std::string(" --oracle-route reference"), std::string(" --oracle-route filtered")})
        for (std::size_t at; (at = text.find(spelling)) != std::string::npos;) text.erase(at, spelling.size());
    for (std::size_t at; (at = text.find(directory)) != std::string::npos;) text.replace(at, directory.size(), "DIR");
    return text;
}

class OracleRoutes : public testing::Test {
protected:
    // A run's directory: its report in report/, its per-case lines beside it.
    struct run {
        command_result result;
        fs::path root;
    };

    // Where the per-case lines go: nowhere, to cases.jsonl, or to standard
    // output, which is digested into stdout.sha256 with the summary table
    // (100,000 cases of every variant are about a gigabyte of lines).
    enum class per_case_lines { none, file, digest };

    // `rayverify audit ARGUMENTS` on `route`, run in a directory named after the route.
    run audit_on(const std::string& route, const std::string& arguments, per_case_lines lines = per_case_lines::file) {
        const fs::path root = scratch_ / route;
        fs::create_directories(root);
        const std::string audit = fmt::format("'{}' audit {} --threads 2 --oracle-route {} --report report",
                                              RAYVERIFY_CLI, arguments, route);
        std::string command = audit;
        if (lines == per_case_lines::file) command += " --per-case cases.jsonl";
        if (lines == per_case_lines::digest)
            command = fmt::format("{{ {} --per-case /dev/stdout; echo $? > status; }} | sha256sum > stdout.sha256; "
                                  "exit $(cat status)",
                                  audit);
        run r{run_shell(fmt::format("cd '{}' && {}", root.string(), command)), root};
        EXPECT_TRUE(r.result.exit_code == 0 || r.result.exit_code == 1) << route << ": " << r.result.output;
        return r;
    }

    // The files under two directories, each equal but for the route's name
    // and the directory.
    static void expect_files_alike(const fs::path& a_root, const fs::path& b_root,
                                   const std::vector<std::string>& files) {
        for (const std::string& file : files) {
            const std::string a = read_text(a_root / file), b = read_text(b_root / file);
            EXPECT_FALSE(a.empty()) << file;
            // Compared whole (EXPECT_EQ would print megabytes on a difference).
            EXPECT_TRUE(without_route(a, a_root.string()) == without_route(b, b_root.string()))
                << file << " differs between the routes (" << a.size() << " vs " << b.size() << " bytes)";
        }
    }

    // Both routes' outputs, file by file (paths under the run's directory)
    // and on the terminal, equal but for the route's name and directory.
    static void expect_alike(const run& filtered, const run& reference, const std::vector<std::string>& files) {
        EXPECT_EQ(filtered.result.exit_code, reference.result.exit_code);
        EXPECT_EQ(without_route(filtered.result.output, filtered.root.string()),
                  without_route(reference.result.output, reference.root.string()));
        expect_files_alike(filtered.root, reference.root, files);
    }

    static std::vector<std::string> audit_files() {
        return {"report/report.json", "report/report.md", "report/summary.txt", "report/audit.csv", "cases.jsonl"};
    }

    void expect_audits_alike(const std::string& arguments) {
        expect_alike(audit_on("filtered", arguments), audit_on("reference", arguments), audit_files());
    }

    scratch_directory scratch_{"rayverify_oracle_routes"};
};

TEST_F(OracleRoutes, ShippedCorpusAuditsAlikeWithEveryVariant) {
    expect_audits_alike(fmt::format("--corpus '{}'", RAYVERIFY_CORPUS_DIR));
}

TEST_F(OracleRoutes, EdgeAndSegmentCorporaAuditAlike) {
    expect_audits_alike(fmt::format("--corpus '{}/edge' --corpus '{}/segments'", RAYVERIFY_CORPUS_DIR, RAYVERIFY_CORPUS_DIR));
}

// A scene's every ray, its spheres solved on either route (the nearest of
// them decided by comparing exact roots of two quadratics).
TEST_F(OracleRoutes, SceneAuditsAlike) {
    for (const char* scene : {"four_spheres", "secondary_self_hit"}) {
        SCOPED_TRACE(scene);
        const std::string arguments = fmt::format("--scene '{}/scenes/{}.json'", RAYVERIFY_CORPUS_DIR, scene);
        expect_alike(audit_on("filtered", arguments, per_case_lines::none),
                     audit_on("reference", arguments, per_case_lines::none),
                     {"report/scene_report.json"});
    }
}

// Shards audited on the reference route and merged give the report of one
// run on the filtered route.
TEST_F(OracleRoutes, ReferenceShardsMergeIntoTheFilteredRun) {
    const std::string input = "--generate uniform:1500:3 --generate near_tangent:900:5 --generate tangent_exact:600:7";
    const run single = audit_on("filtered", input);  // in filtered/
    for (int k = 1; k <= 3; ++k) {
        const fs::path shard = scratch_ / fmt::format("shard-{}", k);
        const command_result r = run_shell(fmt::format(
            "'{}' audit {} --threads 1 --oracle-route reference --shard {}/3 --report '{}' --per-case '{}'",
            RAYVERIFY_CLI, input, k, shard.string(), (shard / "cases.jsonl").string()));
        ASSERT_NE(r.exit_code, 2) << r.output;
    }
    const fs::path merged = scratch_ / "merged";
    const command_result m = run_shell(fmt::format(
        "cd '{}' && '{}' merge --report merged --per-case merged/cases.jsonl shard-2 shard-3 shard-1",
        scratch_.path().string(), RAYVERIFY_CLI));
    EXPECT_EQ(m.exit_code, single.result.exit_code) << m.output;
    expect_files_alike(single.root / "report", merged, {"report.json", "report.md", "summary.txt", "audit.csv"});
    EXPECT_TRUE(read_text(single.root / "cases.jsonl") == read_text(merged / "cases.jsonl"));
}

// 100,000 generated cases of six families, every built-in variant in float
// and double (25 s alone on 2 cores, 44 s beside the other long sweeps in CI).
class LongSweepOracleRoutes : public OracleRoutes {};

TEST_F(LongSweepOracleRoutes, HundredThousandGeneratedCasesAuditAlike) {
    const std::string arguments =
        "--generate uniform:40000:11 --generate far_sphere:15000:12 --generate near_tangent:15000:13 "
        "--generate tangent_exact:10000:14 --generate inside:10000:15 --generate on_surface:10000:16";
    expect_alike(audit_on("filtered", arguments, per_case_lines::digest),
                 audit_on("reference", arguments, per_case_lines::digest),
                 {"report/report.json", "report/report.md", "report/summary.txt", "report/audit.csv", "stdout.sha256"});
}

}  // namespace
