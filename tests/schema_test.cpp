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

TEST_F(Schema, ValidatorRejectsAnOutputWithoutItsVersion) {
    std::ofstream(dir_ / "old.json") << R"({"variants": [{"name": "naive"}]})";
    const command_result r = validate("variants", dir_ / "old.json");
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_NE(r.output.find("'schema_version' is a required property"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace rayverify
