// Every JSON and JSON Lines output carries a schema_version and validates
// against its schema in docs/schema/ (JSON Schema 2020-12, checked with
// Debian's python3-jsonschema through tests/support/validate_json.py).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "report/schema.h"
#include "support/process.h"
#include "support/sampled_corpus.h"

namespace rayverify {
namespace {

namespace fs = std::filesystem;
using test_support::command_result;
using test_support::read_text;
using test_support::run_cli;
using test_support::run_shell;

const std::string source_dir = RAYVERIFY_SOURCE_DIR;
const std::string corpus_dir = RAYVERIFY_CORPUS_DIR;

command_result validate(const std::string& schema, const fs::path& file, bool lines = false) {
    return run_shell("/usr/bin/python3 " + source_dir + "/tests/support/validate_json.py " + source_dir +
                     "/docs/schema " + schema + " " + file.string() + (lines ? " --lines" : ""));
}

class Schema : public ::testing::Test {
protected:
    test_support::scratch_directory scratch_{"rayverify_schema_test"};
    const fs::path& dir_ = scratch_.path();
    // The output's first key is schema_version, equal to the version the code writes.
    static void expect_versioned(const std::string& json_text, int version) {
        EXPECT_TRUE(json_text.starts_with("{\"schema_version\":") || json_text.starts_with("{\n  \"schema_version\":"))
            << json_text.substr(0, 80);
        EXPECT_EQ(nlohmann::json::parse(json_text)["schema_version"], version);
    }
};

TEST_F(Schema, EverySchemaIsAValidSchemaNamedByItsFile) {
    const command_result r = run_shell("/usr/bin/python3 " + source_dir + "/tests/support/validate_json.py " +
                                       source_dir + "/docs/schema --check-schemas");
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("schemas: 7 valid"), std::string::npos) << r.output;
}

TEST_F(Schema, AuditReportPerCaseLinesAndShardStateValidate) {
    const std::string corpus = " --corpus " + corpus_dir + "/near_tangent.txt --corpus " + corpus_dir +
                               "/inside.txt --variant naive --variant hearn_baker --variant hearn_baker_any_hit";
    const command_result audit = run_cli("audit" + corpus + " --report " + (dir_ / "whole").string() +
                                         " --per-case " + (dir_ / "whole" / "cases.jsonl").string());
    ASSERT_EQ(audit.exit_code, 1) << audit.output;
    for (int k = 1; k <= 2; ++k) {
        const std::string shard = (dir_ / ("shard-" + std::to_string(k))).string();
        const command_result r = run_cli("audit" + corpus + " --shard " + std::to_string(k) + "/2 --report " + shard +
                                         " --per-case " + shard + "/cases.jsonl");
        ASSERT_EQ(r.exit_code, 1) << r.output;
        EXPECT_EQ(validate("shard-state", fs::path(shard) / "shard.json").exit_code, 0)
            << validate("shard-state", fs::path(shard) / "shard.json").output;
        expect_versioned(read_text(fs::path(shard) / "shard.json"), schema_version::shard_state);
    }
    const command_result merge = run_cli("merge --report " + (dir_ / "merged").string() + " " +
                                         (dir_ / "shard-1").string() + " " + (dir_ / "shard-2").string());
    ASSERT_EQ(merge.exit_code, 1) << merge.output;
    for (const fs::path& report : {dir_ / "whole" / "report.json", dir_ / "merged" / "report.json"}) {
        const command_result r = validate("report", report);
        EXPECT_EQ(r.exit_code, 0) << report << "\n" << r.output;
        expect_versioned(read_text(report), schema_version::report);
    }
    const command_result lines = validate("per-case", dir_ / "whole" / "cases.jsonl", true);
    EXPECT_EQ(lines.exit_code, 0) << lines.output;
    EXPECT_NE(lines.output.find("valid: 1000 object(s)"), std::string::npos) << lines.output;
    std::ifstream in(dir_ / "whole" / "cases.jsonl");
    std::string first;
    std::getline(in, first);
    expect_versioned(first, schema_version::per_case);
}

TEST_F(Schema, SceneReportAndVariantsValidate) {
    const command_result scene = run_cli("audit --scene " + corpus_dir +
                                         "/scenes/ground_sphere.json --variant naive --variant hearn_baker_any_hit "
                                         "--report " + dir_.string());
    ASSERT_LE(scene.exit_code, 1) << scene.output;
    EXPECT_EQ(validate("scene-report", dir_ / "scene_report.json").exit_code, 0)
        << validate("scene-report", dir_ / "scene_report.json").output;
    expect_versioned(read_text(dir_ / "scene_report.json"), schema_version::scene_report);

    const command_result variants = run_cli("variants --json > " + (dir_ / "variants.json").string());
    ASSERT_EQ(variants.exit_code, 0) << variants.output;
    EXPECT_EQ(validate("variants", dir_ / "variants.json").exit_code, 0);
    expect_versioned(read_text(dir_ / "variants.json"), schema_version::variants);
}

TEST_F(Schema, BenchReportAndGoogleBenchmarkJsonValidate) {
    const command_result bench =
        run_cli("bench --corpus " + corpus_dir + "/uniform.txt --variant naive --repetitions 3 --min-time 0.001 "
                "--sweep 100 --report " + (dir_ / "rep").string() + " --benchmark-json " +
                (dir_ / "gb.json").string());
    ASSERT_EQ(bench.exit_code, 0) << bench.output;
    EXPECT_EQ(validate("report", dir_ / "rep" / "report.json").exit_code, 0)
        << validate("report", dir_ / "rep" / "report.json").output;
    const command_result gb = validate("benchmark", dir_ / "gb.json");
    EXPECT_EQ(gb.exit_code, 0) << gb.output;
    const std::string text = read_text(dir_ / "gb.json");
    expect_versioned(text, schema_version::benchmark);
    // Google Benchmark's aggregates, recomputed from the repetitions of each benchmark.
    const auto doc = nlohmann::json::parse(text);
    std::map<std::string, std::vector<double>> cpu;
    std::size_t checked = 0;
    for (const auto& b : doc["benchmarks"]) {
        const std::string run = b["run_name"];
        if (b["run_type"] == "iteration") {
            cpu[run].push_back(b["cpu_time"].get<double>());
            continue;
        }
        const std::vector<double>& v = cpu[run];
        ASSERT_EQ(v.size(), 3u) << run;
        const double mean = (v[0] + v[1] + v[2]) / 3;
        const double var = ((v[0] - mean) * (v[0] - mean) + (v[1] - mean) * (v[1] - mean) +
                            (v[2] - mean) * (v[2] - mean)) / 2;
        std::vector<double> sorted = v;
        std::sort(sorted.begin(), sorted.end());
        const std::string name = b["aggregate_name"];
        const double expected = name == "mean" ? mean : name == "median" ? sorted[1]
                                : name == "stddev" ? std::sqrt(var) : std::sqrt(var) / mean;
        EXPECT_NEAR(b["cpu_time"].get<double>(), expected, 1e-9 * std::max(1.0, expected)) << run << " " << name;
        ++checked;
    }
    // naive in float, double and long double on one family, and the two exact oracles: 5 benchmarks × 4 aggregates.
    EXPECT_EQ(checked, 20u);
}

// The shipped corpus and corpus/edge, whole: the report with every variant,
// and the per-case lines of one target of each output shape (line roots with
// t1, a clamping nearest hit with its expected answer, t intervals and a point
// bound, a normal): python's validator takes about 10 ms per line with every
// target, so the lines carry four. The edge families hold the extremes: roots
// near overflow and below the subnormals, NaN answers, infinities as figures.
// The sanitized suite reads one case in eight of each file (sampled_corpus.h):
// every family and output shape still (this file's tests took 59 s sanitized
// on the whole corpora, 31 s so).
TEST_F(Schema, ReportAndPerCaseLinesOfTheShippedCorpusAndEdgeCasesValidate) {
    for (const std::string& whole_corpus : {corpus_dir, corpus_dir + "/edge"}) {
        SCOPED_TRACE(whole_corpus);
        const test_support::sampled_corpus corpus(whole_corpus);  // every case, but in the sanitized suite
        const fs::path whole = dir_ / "whole", lines = dir_ / "lines";
        fs::remove_all(whole);
        fs::remove_all(lines);
        const command_result all = run_cli("audit --corpus " + corpus.path().string() + " --report " + whole.string());
        ASSERT_EQ(all.exit_code, 1) << all.output;
        const command_result report = validate("report", whole / "report.json");
        EXPECT_EQ(report.exit_code, 0) << report.output;
        const command_result some =
            run_cli("audit --corpus " + corpus.path().string() +
                    " --variant naive --variant seed004_early_out --variant pbrt_v4 --variant embree4 --report " +
                    lines.string() + " --per-case " + (lines / "cases.jsonl").string());
        ASSERT_EQ(some.exit_code, 1) << some.output;
        const command_result per_case = validate("per-case", lines / "cases.jsonl", true);
        EXPECT_EQ(per_case.exit_code, 0) << per_case.output;
        // A line per case, its four targets inside: every one was read and validated.
        EXPECT_NE(per_case.output.find("valid: " + std::to_string(corpus.case_count()) + " object(s)"),
                  std::string::npos)
            << per_case.output;
    }
}

// Every scene of the shipped corpus: its report.
TEST_F(Schema, EveryShippedSceneReportValidates) {
    for (const auto& entry : fs::directory_iterator(corpus_dir + "/scenes")) {
        if (entry.path().extension() != ".json") continue;
        SCOPED_TRACE(entry.path());
        const fs::path out = dir_ / entry.path().stem();
        const command_result scene =
            run_cli("audit --scene " + entry.path().string() + " --variant naive --variant seed004_early_out "
                    "--variant hearn_baker_any_hit --variant pbrt_v4 --report " + out.string());
        ASSERT_LE(scene.exit_code, 1) << scene.output;
        const command_result r = validate("scene-report", out / "scene_report.json");
        EXPECT_EQ(r.exit_code, 0) << r.output;
    }
}

// The exchange files (docs/schema/rayverify-exchange-v1.json): the shipped
// corpus, corpus/edge and corpus/segments exported as JSON lines and as .npy (its companion),
// and a results file with every shape of answer, absent values included.
TEST_F(Schema, ExchangeFilesOfTheShippedCorpusAndEdgeCasesValidate) {
    const std::string check = "/usr/bin/python3 " + source_dir + "/tests/support/check_exchange_schema.py " +
                              source_dir + "/docs/schema/rayverify-exchange-v1.json ";
    std::string files;
    for (const auto& [corpus, name] : {std::pair{corpus_dir, std::string("corpus")},
                                       std::pair{corpus_dir + "/edge", std::string("edge")},
                                       std::pair{corpus_dir + "/segments", std::string("segments")}}) {
        for (const std::string format : {"jsonl", "npy"}) {
            const fs::path out = dir_ / (name + "." + format);
            const command_result r = run_cli("corpus export --corpus " + corpus + " -o " + out.string());
            ASSERT_EQ(r.exit_code, 0) << r.output;
            files += " " + (format == "npy" ? (dir_ / (name + ".json")).string() : out.string());
        }
    }
    const command_result float_export =
        run_cli("corpus export --corpus " + corpus_dir + "/edge --precision float --numbers hex -o " +
                (dir_ / "edge_f32.jsonl").string());
    ASSERT_EQ(float_export.exit_code, 0) << float_export.output;
    files += " " + (dir_ / "edge_f32.jsonl").string();
    std::ofstream(dir_ / "results.jsonl")
        << R"({"rayverify": "results", "version": 1, "precision": "double", "fingerprint": "0123456789abcdef"})" "\n"
        << R"({"id": "miss", "count": 0})" "\n"
        << R"({"id": "tangent", "count": 1, "t0": 5})" "\n"
        << R"({"id": "nearest", "count": 1, "t0": "0x1.8p+2", "t1": null})" "\n"
        << R"({"id": "two", "count": 2, "t0": 4, "t1": "inf", "t0_bounds": [3.5, 4.5], "t1_bounds": ["nan", "inf"],)"
           R"( "hit_point": [0, 0, -1], "normal": [0, 0, -1]})" "\n";
    files += " " + (dir_ / "results.jsonl").string();
    const command_result checked = run_shell(check + files);
    EXPECT_EQ(checked.exit_code, 0) << checked.output;
}

// A key the schema does not declare is an error: an output cannot drift from
// its schema unseen (the per-case schema once named front_root, hit_point and
// hits_interval while the tool wrote hit_points).
TEST_F(Schema, ValidatorRejectsAKeyItsSchemaDoesNotDeclare) {
    std::ofstream(dir_ / "drift.json")
        << R"({"schema_version": 1, "variants": [{"name": "naive", "citation": "", "formula": "",)"
           R"( "contract": {"spec": "query=line_roots", "tangent_rule": "", "meaning": ""},)"
           R"( "precisions": ["double"], "front_root": "near"}]})";
    const command_result r = validate("variants", dir_ / "drift.json");
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_NE(r.output.find("at '/variants/0/front_root': not declared in the schema"), std::string::npos)
        << r.output;
}

TEST_F(Schema, ValidatorRejectsAnOutputWithoutItsVersion) {
    std::ofstream(dir_ / "old.json") << R"({"variants": [{"name": "naive"}]})";
    const command_result r = validate("variants", dir_ / "old.json");
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_NE(r.output.find("'schema_version' is a required property"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace rayverify
