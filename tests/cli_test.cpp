// The rayverify executable end to end: exit codes, messages naming file,
// line and field, no partial output on error, and the shape of its outputs.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "compare/judge.h"
#include "intersectors/registry.h"
#include "support/process.h"

namespace {

namespace fs = std::filesystem;
using namespace rayverify::test_support;
using rayverify::is_misclassification, rayverify::is_scored, rayverify::verdict_kind, rayverify::verdict_kind_count,
    rayverify::verdict_name;

class Cli : public testing::Test {
protected:
    fs::path write(const std::string& name, const std::string& contents) {
        const fs::path p = dir_ / name;
        std::ofstream(p) << contents;
        return p;
    }
    scratch_directory scratch_{"rayverify_cli_test"};
    const fs::path dir_ = scratch_.path();
};

// Unit sphere at the origin; exact roots 4 and 6 along +z from z = −5.
const char* simple_case = "hit-4-6 - 0 0 -5 0 0 1 0 0 0 1\n";

TEST_F(Cli, VariantsListsEveryBuiltIn) {
    const command_result r = run_cli("variants");
    EXPECT_EQ(r.exit_code, 0);
    for (const char* name : {"naive", "half_b", "seed003_reduced", "seed004_early_out", "geometric", "stable_roots",
                             "hearn_baker", "fma_discriminant"})
        EXPECT_NE(r.output.find(name), std::string::npos) << name;
    const command_result json = run_cli("variants --json");
    EXPECT_EQ(nlohmann::json::parse(json.output)["variants"].size(), rayverify::builtin_variants().size());
}

TEST_F(Cli, AuditWithoutDisagreementExitsZeroAndWritesReports) {
    // Off the z axis: on it pbrt_v4 in double moves its hit point to x = 1e-5·r, off the sphere by more than
    // the bound it claims (engines_test.cpp), a finding.
    const fs::path corpus = write("ok.txt", "hit-6-14 - 3 0 -10 0 0 1 0 0 0 5\n");
    const command_result r = run_cli("audit --corpus " + corpus.string() + " --report " + (dir_ / "rep").string() +
                         " --per-case " + (dir_ / "cases.jsonl").string());
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("naive"), std::string::npos);
    EXPECT_NE(r.output.find("-ffp-contract=off"), std::string::npos) << "flags must be recorded";

    const auto report = nlohmann::json::parse(read_text(dir_ / "rep" / "report.json"));
    EXPECT_EQ(report["corpus"]["cases"], 1);
    std::size_t targets = 0;  // every variant in each precision it runs in
    for (const rayverify::variant& v : rayverify::builtin_variants())
        targets += v.runs_in(rayverify::precision::binary32) + v.runs_in(rayverify::precision::binary64);
    EXPECT_EQ(report["results"].size(), targets);
    EXPECT_NE(report["build"]["flags"].get<std::string>().find("-ffp-contract=off"), std::string::npos);
    // audit.csv: a row per target and family, then one per target over every family, report.json's figures.
    std::istringstream csv(read_text(dir_ / "rep" / "audit.csv"));
    std::string header, row;
    ASSERT_TRUE(std::getline(csv, header));
    EXPECT_TRUE(header.starts_with("variant,precision,family,cases,cases_scored,misclassified,agree,")) << header;
    std::size_t rows = 0, all_rows = 0;
    for (; std::getline(csv, row); ++rows) {
        if (row.find(",(all),") == std::string::npos) continue;
        const nlohmann::json& entry = report["results"][all_rows++];
        EXPECT_TRUE(row.starts_with(entry["variant"].get<std::string>() + "," + entry["precision"].get<std::string>() +
                                    ",(all),1,"))
            << row;
    }
    EXPECT_EQ(all_rows, targets);
    EXPECT_EQ(rows, 2 * targets) << "one family (\"-\") and the whole corpus per target";

    const auto line = nlohmann::json::parse(read_text(dir_ / "cases.jsonl"));
    EXPECT_EQ(line["id"], "hit-6-14");
    EXPECT_EQ(line["exact"]["class"], "two_hit");
    EXPECT_EQ(line["exact"]["t_near"], "0x1.8p+2");
    EXPECT_EQ(line["exact"]["t_far"], "0x1.cp+3");
    EXPECT_EQ(line["results"]["naive/double"]["verdict"], "agree");
}

TEST_F(Cli, AuditWithFindingsExitsOne) {
    // A unit sphere 4100 away, hit off-centre: naive float loses the two roots.
    const fs::path corpus = write("far.txt", "far - 0.5 0.25 0 0 0 1 0 0 4100 1\n");
    const command_result r = run_cli("audit --corpus " + corpus.string() + " --variant naive --precision float");
    EXPECT_EQ(r.exit_code, 1) << r.output;
}

TEST_F(Cli, MalformedCorpusNamesFileLineAndFieldAndWritesNothing) {
    const fs::path corpus = write("bad.txt", std::string(simple_case) + "b - 0 0 -5 0 0 1x 0 0 0 1\n");
    const command_result r = run_cli("audit --corpus " + corpus.string() + " --report " + (dir_ / "rep").string() +
                         " --per-case " + (dir_ / "cases.jsonl").string());
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.output.find("bad.txt:2: field 'dz'"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir_ / "cases.jsonl"));
    EXPECT_FALSE(fs::exists(dir_ / "cases.jsonl.tmp"));
    EXPECT_FALSE(fs::exists(dir_ / "rep" / "report.json"));
}

TEST_F(Cli, MissingCorpusAndUnknownVariantAreInputErrors) {
    const command_result missing = run_cli("audit --corpus " + (dir_ / "nope.txt").string());
    EXPECT_EQ(missing.exit_code, 2);
    EXPECT_NE(missing.output.find("nope.txt"), std::string::npos);
    const command_result unknown = run_cli("audit --variant no_such_variant");
    EXPECT_EQ(unknown.exit_code, 2);
    EXPECT_NE(unknown.output.find("unknown variant 'no_such_variant'"), std::string::npos);
    EXPECT_EQ(run_cli("").exit_code, 2);
    EXPECT_EQ(run_cli("audit --precision quad").exit_code, 2);
}

// A misspelt variant or family name is answered with the nearest known one;
// --plots without --report, which would draw nothing, is refused.
TEST_F(Cli, MisspeltNamesGetDidYouMeanAndPlotsNeedAReport) {
    const command_result variant = run_cli("audit --variant naiv --generate uniform:2");
    EXPECT_EQ(variant.exit_code, 2);
    EXPECT_NE(variant.output.find("unknown variant 'naiv' (did you mean 'naive'?)"), std::string::npos)
        << variant.output;
    const command_result far = run_cli("audit --variant naive --generate far_spere:2");
    EXPECT_EQ(far.exit_code, 2);
    EXPECT_NE(far.output.find("unknown family 'far_spere' (did you mean 'far_sphere'?)"), std::string::npos)
        << far.output;
    const command_result nothing_near = run_cli("audit --variant zzzzzzzzzz --generate uniform:2");
    EXPECT_EQ(nothing_near.output.find("did you mean"), std::string::npos) << nothing_near.output;
    const command_result plots = run_cli("audit --variant naive --generate uniform:2 --plots");
    EXPECT_EQ(plots.exit_code, 2);
    EXPECT_NE(plots.output.find("field '--plots': the plots are drawn into the report directory: add --report DIR"),
              std::string::npos)
        << plots.output;
}

TEST_F(Cli, InvalidCasesAreCountedNotScored) {
    const fs::path corpus = write("mixed.txt", std::string(simple_case) +
                                                   "nan-origin - nan 0 -5 0 0 1 0 0 0 1\n"
                                                   "zero-dir - 0 0 -5 0 0 0 0 0 0 1\n"
                                                   "neg-r - 0 0 -5 0 0 1 0 0 0 -1\n"
                                                   "float-overflow - 0 0 -5 0 0 1 0 0 1e300 1\n");
    const command_result r = run_cli("audit --corpus " + corpus.string() + " --variant naive --report " + (dir_ / "rep").string());
    // The 1e300 centre overflows naive's f·f in double: a real finding, so exit 1.
    EXPECT_EQ(r.exit_code, 1) << r.output;
    const auto report = nlohmann::json::parse(read_text(dir_ / "rep" / "report.json"));
    EXPECT_EQ(report["corpus"]["invalid_cases"]["double"], 3);
    EXPECT_EQ(report["corpus"]["invalid_cases"]["float"], 4);
    for (const auto& entry : report["results"])
        EXPECT_EQ(entry["verdicts"]["invalid"], entry["precision"] == "float" ? 4 : 3);
}

// --accuracy radius:2^-10 turns exactly the "agree but far" answers into
// imprecise ones: the count the table shows without the clause (from the
// rounded scale figure) and the exact decision under it agree, target by
// target, on the shipped far-sphere family.
TEST_F(Cli, AccuracyClauseMakesTheFarAgreementsImprecise) {
    const std::string corpus = std::string(RAYVERIFY_SOURCE_DIR) + "/corpus/far_sphere.txt";
    const std::string run = "audit --corpus " + corpus + " --variant naive --variant hearn_baker --variant robust";
    ASSERT_EQ(run_cli(run + " --report " + (dir_ / "plain").string()).exit_code, 1);
    const command_result strict =
        run_cli(run + " --accuracy radius:0.0009765625 --report " + (dir_ / "strict").string());
    ASSERT_EQ(strict.exit_code, 1) << strict.output;
    const auto plain = nlohmann::json::parse(read_text(dir_ / "plain" / "report.json"));
    const auto required = nlohmann::json::parse(read_text(dir_ / "strict" / "report.json"));
    ASSERT_EQ(plain["results"].size(), required["results"].size());
    std::size_t imprecise = 0;
    for (std::size_t i = 0; i < plain["results"].size(); ++i) {
        const auto& before = plain["results"][i];
        const auto& after = required["results"][i];
        const std::size_t far = before["agree_far"];
        EXPECT_EQ(after["verdicts"]["imprecise"], far) << before["variant"] << "/" << before["precision"];
        EXPECT_EQ(after["verdicts"]["agree"].get<std::size_t>() + far, before["verdicts"]["agree"].get<std::size_t>());
        EXPECT_EQ(after["agree_far"], 0u);
        imprecise += far;
        EXPECT_NE(after["contract"]["spec"].get<std::string>().find("accuracy=radius:0.0009765625"), std::string::npos);
    }
    EXPECT_GT(imprecise, 0u);  // naive/float grazes far spheres several radii off
    EXPECT_NE(strict.output.find(" imprec "), std::string::npos);
    // Scenes judge each ray under the clause too: robust_sphere.h's correctly
    // rounded hits are within an ulp, naive's float hits often are not.
    const command_result scene = run_cli("audit --scene " + std::string(RAYVERIFY_SOURCE_DIR) +
                                         "/corpus/scenes/secondary_self_hit.json --variant naive --variant "
                                         "robust_nearest --accuracy ulp:1 --report " + (dir_ / "scene").string());
    ASSERT_EQ(scene.exit_code, 1) << scene.output;
    const auto scene_report = nlohmann::json::parse(read_text(dir_ / "scene" / "scene_report.json"));
    for (const auto& target : scene_report["targets"]) {
        const std::size_t scene_imprecise = target["primary"]["verdicts"]["imprecise"];
        if (target["target"] == "robust_nearest/float")
            EXPECT_EQ(scene_imprecise, 0u);
        else
            EXPECT_GT(scene_imprecise, 0u) << target["target"];
    }
    // A clause that cannot be read: exit 2 naming it, no report.
    for (const char* bad : {"radius:-1", "radius:nan", "furlong:1", "ulp"}) {
        const command_result r = run_cli(run + " --accuracy " + bad + " --report " + (dir_ / "bad").string());
        EXPECT_EQ(r.exit_code, 2) << bad;
        EXPECT_NE(r.output.find("field '--accuracy'"), std::string::npos) << r.output;
        EXPECT_NE(r.output.find(std::string("accuracy='") + bad + "'"), std::string::npos) << r.output;
        EXPECT_FALSE(fs::exists(dir_ / "bad"));
    }
}

// --degenerate miss hands the zero direction and the NaN origin to every
// target; the textbook formula reports hits there, robust_sphere.h misses. A
// negative radius stays invalid.
TEST_F(Cli, DegenerateCastsAreHandedOverOnRequest) {
    const fs::path corpus = write("degenerate.txt", std::string(simple_case) +
                                                        "nan-origin - nan 0 -5 0 0 1 0 0 0 1\n"
                                                        "zero-dir - 0 0 -5 0 0 0 0 0 0 1\n"
                                                        "neg-r - 0 0 -5 0 0 1 0 0 0 -1\n");
    const std::string run = "audit --corpus " + corpus.string() + " --variant naive --variant robust --precision double";
    const command_result plain = run_cli(run + " --report " + (dir_ / "plain").string());
    EXPECT_EQ(plain.exit_code, 0) << plain.output;
    const command_result asked = run_cli(run + " --degenerate miss --report " + (dir_ / "asked").string());
    EXPECT_EQ(asked.exit_code, 1) << asked.output;
    const auto report = nlohmann::json::parse(read_text(dir_ / "asked" / "report.json"));
    for (const auto& entry : report["results"]) {
        const bool naive = entry["variant"] == "naive";
        EXPECT_EQ(entry["verdicts"]["degenerate_hit"], naive ? 2 : 0) << entry["variant"];
        EXPECT_EQ(entry["verdicts"]["agree"], naive ? 1 : 3) << entry["variant"];
        EXPECT_EQ(entry["verdicts"]["invalid"], 1) << entry["variant"];
        EXPECT_NE(entry["contract"]["spec"].get<std::string>().find("degenerate=miss"), std::string::npos);
    }
    EXPECT_NE(asked.output.find("naive/double degenerate_hit: nan-origin"), std::string::npos) << asked.output;
    EXPECT_EQ(run_cli(run + " --degenerate hit").exit_code, 2);
}

// hunt --corpus starts from the user's cases, says so in its file and
// shrinks each find toward the case it came from.
TEST_F(Cli, HuntStartsFromTheUsersCorpus) {
    const fs::path corpus = write("mine.txt",
                                  "mine-far - 0x1.ff2a5ep-2 -0x1.22d66cp-1 -0x1.bd5cap-1 -0x1.b4e04cp-1 "
                                  "0x1.dd5fcp-2 -0x1.0845d8p-2 0x1.6fa572p+27 -0x1.0b99e8p+26 0x1.12c8ccp+25 "
                                  "0x1.6b3c7cp-1\n" + std::string(simple_case));
    const std::string hunt = "hunt --variant naive --precision float --objective misclass --evaluations 400 --corpus " +
                             corpus.string() + " -o " + (dir_ / "finds.txt").string();
    const command_result r = run_cli(hunt);
    ASSERT_EQ(r.exit_code, 1) << r.output;
    EXPECT_NE(r.output.find("2 start cases from " + corpus.string()), std::string::npos) << r.output;
    const std::string finds = read_text(dir_ / "finds.txt");
    EXPECT_NE(finds.find("\"start_corpus\":\"" + corpus.string() + "\""), std::string::npos) << finds;
    EXPECT_NE(finds.find("\"start\":\"mine-"), std::string::npos) << finds;
    EXPECT_NE(finds.find("shrunk toward mine-"), std::string::npos) << finds;
    // Under an accuracy no rounded root meets (distance:0), the first hit is a find: imprecise.
    const command_result strict = run_cli("hunt --variant naive --precision float --objective misclass --finds 1 "
                                          "--accuracy distance:0 --evaluations 200 --seconds 0 -o " +
                                          (dir_ / "strict.txt").string());
    ASSERT_EQ(strict.exit_code, 1) << strict.output;
    EXPECT_NE(read_text(dir_ / "strict.txt").find("\"verdict\":\"imprecise\""), std::string::npos) << strict.output;
    const command_result both = run_cli(hunt + " --family uniform");
    EXPECT_EQ(both.exit_code, 2);
    EXPECT_NE(both.output.find("field '--corpus'"), std::string::npos) << both.output;
    EXPECT_EQ(run_cli("hunt --variant naive --evaluations 10 --corpus " + (dir_ / "none.txt").string() + " -o " +
                      (dir_ / "f2.txt").string())
                  .exit_code,
              2);
    EXPECT_FALSE(fs::exists(dir_ / "f2.txt"));
}

TEST_F(Cli, ExplainShowsExactAndVariantsSideBySide) {
    const command_result r = run_cli("explain 0.5 0.25 0 0 0 1 0 0 4100 1 --variant naive --variant hearn_baker");
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_NE(r.output.find("exact, double inputs: two_hit"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("naive/float"), std::string::npos);
    EXPECT_NE(r.output.find("corpus line:"), std::string::npos);
    const command_result negative = run_cli("explain -5 0 0 1 0 0 0 0 0 1 --variant naive --precision double");
    EXPECT_EQ(negative.exit_code, 0) << negative.output;
    const command_result wrong = run_cli("explain 1 2 3");
    EXPECT_EQ(wrong.exit_code, 2);
    EXPECT_NE(wrong.output.find("got 3 fields"), std::string::npos);
}

TEST_F(Cli, ExplainPrintsAPasteableCorpusLine) {
    const command_result r = run_cli("explain 0x1p-1 0.25 0 0 0 1 0 0 4100 1 --variant naive --precision double");
    const auto start = r.output.find("corpus line: ") + std::string("corpus line: ").size();
    const std::string line = r.output.substr(start, r.output.find('\n', start) - start);
    const fs::path corpus = write("pasted.txt", line + "\n");
    const command_result again = run_cli("audit --corpus " + corpus.string() + " --variant naive --precision double");
    EXPECT_EQ(again.exit_code, 0) << again.output;
}

TEST_F(Cli, CorpusGenerateIsDeterministicAndReadable) {
    const fs::path a = dir_ / "a.txt", b = dir_ / "b.txt";
    ASSERT_EQ(run_cli("corpus generate --family far_sphere --count 50 --seed 7 -o " + a.string()).exit_code, 0);
    ASSERT_EQ(run_cli("corpus generate --family far_sphere --count 50 --seed 7 -o " + b.string()).exit_code, 0);
    EXPECT_EQ(read_text(a), read_text(b));
    EXPECT_NE(read_text(a).find("--seed 7"), std::string::npos) << "provenance must be recorded";
    const command_result audit = run_cli("audit --corpus " + a.string() + " --variant hearn_baker --precision double");
    EXPECT_NE(audit.exit_code, 2) << audit.output;
    const command_result unknown = run_cli("corpus generate --family nope --count 5");
    EXPECT_EQ(unknown.exit_code, 2);
    EXPECT_NE(unknown.output.find("unknown generator family"), std::string::npos);
}

// bench --precision times and audits only the chosen precisions, with
// naive/double (the ratios' reference) timed in the same run; --threads runs
// the accuracy audit on more threads without changing a figure; --seed
// chooses the far-sphere sweep's cases and nothing else.
TEST_F(Cli, BenchPrecisionChoosesTheRowsAndThreadsChangeNoFigure) {
    const std::string corpus = std::string(RAYVERIFY_CORPUS_DIR) + "/uniform.txt";
    const auto bench = [&](const std::string& threads, const std::string& dir, const std::string& extra = "") {
        return run_cli("bench --corpus " + corpus + " --variant naive --variant hearn_baker --precision float "
                       "--repetitions 1 --min-time 0.001 --sweep 200 --threads " + threads + " --report " +
                       (dir_ / dir).string() + extra);
    };
    const command_result one = bench("1", "one"), two = bench("2", "two");
    ASSERT_EQ(one.exit_code, 0) << one.output;
    ASSERT_EQ(two.exit_code, 0) << two.output;
    const auto report = [&](const std::string& dir) {
        return nlohmann::json::parse(std::ifstream(dir_ / dir / "report.json"));
    };
    const nlohmann::json a = report("one"), b = report("two");
    for (const auto& r : a["results"]) EXPECT_EQ(r["precision"], "float") << r.dump();
    EXPECT_FALSE(a.contains("long_double"));
    std::set<std::string> timed;
    for (const auto& r : a["timing"]["overall"])
        timed.insert(r["variant"].get<std::string>() + "/" + r["precision"].get<std::string>());
    EXPECT_TRUE(timed.count("naive/float") && timed.count("hearn_baker/float")) << a["timing"]["overall"].dump();
    EXPECT_TRUE(timed.count("naive/double")) << "the reference is timed whatever --precision says";
    EXPECT_FALSE(timed.count("hearn_baker/double") || timed.count("naive/long double"));
    EXPECT_EQ(a["results"], b["results"]);
    EXPECT_EQ(a["stability"], b["stability"]);
    EXPECT_EQ(a["far_sphere_sweep"]["results"], b["far_sphere_sweep"]["results"]);
    // bench.csv: a row per timing row, in its order, its figures report.json's.
    std::istringstream csv(read_text(dir_ / "one" / "bench.csv"));
    std::string header, line;
    ASSERT_TRUE(std::getline(csv, header));
    EXPECT_TRUE(header.starts_with("variant,precision,family,cases_timed,ns_per_test_median,")) << header;
    EXPECT_NE(header.find(",false_hit,"), std::string::npos) << header;
    EXPECT_NE(header.find(",near_root_ulp_max,"), std::string::npos) << header;
    const auto column = [&](const std::string& name) {
        std::istringstream names(header);
        std::string n;
        for (std::size_t i = 0; std::getline(names, n, ','); ++i)
            if (n == name) return i;
        ADD_FAILURE() << "no column " << name;
        return std::size_t{0};
    };
    const auto field = [](const std::string& row, std::size_t i) {
        std::istringstream fields(row);
        std::string f;
        for (std::size_t k = 0; k <= i; ++k) std::getline(fields, f, ',');
        return f;
    };
    std::size_t rows = 0;
    for (; rows < a["timing"]["rows"].size() && std::getline(csv, line); ++rows) {
        const nlohmann::json& timed = a["timing"]["rows"][rows];
        EXPECT_EQ(field(line, 0) + "/" + field(line, 1) + "/" + field(line, 2),
                  timed["variant"].get<std::string>() + "/" + timed["precision"].get<std::string>() + "/" +
                      timed["family"].get<std::string>());
        EXPECT_EQ(std::stod(field(line, column("ns_per_test_median"))), timed["ns_per_test"]["median"].get<double>());
        // The median's interval holds the median; with fewer than 6 repetitions it is the minimum and
        // maximum, whose coverage is 1 − 2·2^-n (n = 1 here: 0).
        const double low = std::stod(field(line, column("ns_per_test_median_low"))),
                     high = std::stod(field(line, column("ns_per_test_median_high")));
        EXPECT_LE(low, timed["ns_per_test"]["median"].get<double>());
        EXPECT_GE(high, timed["ns_per_test"]["median"].get<double>());
        const auto repetitions = static_cast<int>(std::stoul(field(line, column("repetitions"))));
        ASSERT_LT(repetitions, 6);
        EXPECT_EQ(std::stod(field(line, column("median_interval_confidence"))), 1 - 2 * std::ldexp(1.0, -repetitions))
            << line;
        if (timed["variant"] == "naive" && timed["precision"] == "float") {
            const nlohmann::json& audited = a["results"][0]["by_family"]["uniform"];
            ASSERT_EQ(a["results"][0]["variant"], "naive");
            EXPECT_EQ(field(line, column("false_hit")), audited["verdicts"]["false_hit"].dump()) << line;
            EXPECT_EQ(std::stod(field(line, column("near_root_ulp_max"))),
                      audited["near_root_ulp"]["max"].get<double>()) << line;
        }
    }
    EXPECT_EQ(rows, a["timing"]["rows"].size());
    // Then a row per target over every family: timing.overall's time, results' verdicts and figures.
    std::size_t overall = 0;
    for (; std::getline(csv, line); ++overall) {
        ASSERT_LT(overall, a["timing"]["overall"].size()) << line;
        const nlohmann::json& timed = a["timing"]["overall"][overall];
        EXPECT_EQ(field(line, 2), "(all)") << line;
        EXPECT_EQ(field(line, 0) + "/" + field(line, 1),
                  timed["variant"].get<std::string>() + "/" + timed["precision"].get<std::string>());
        EXPECT_EQ(std::stod(field(line, column("ns_per_test_median"))), timed["ns_per_test"].get<double>());
        if (timed["variant"] == "naive" && timed["precision"] == "float") {
            EXPECT_EQ(std::stod(field(line, column("near_root_ulp_max"))),
                      a["results"][0]["near_root_ulp"]["max"].get<double>()) << line;
        }
    }
    EXPECT_EQ(overall, a["timing"]["overall"].size());
    const command_result seeded = bench("1", "seven", " --seed 7");
    ASSERT_EQ(seeded.exit_code, 0) << seeded.output;
    const nlohmann::json c = report("seven");
    EXPECT_NE(a["far_sphere_sweep"]["description"].get<std::string>().find("--seed 2)"), std::string::npos)
        << a["far_sphere_sweep"]["description"];
    EXPECT_NE(c["far_sphere_sweep"]["description"].get<std::string>().find("--seed 7)"), std::string::npos)
        << c["far_sphere_sweep"]["description"];
    EXPECT_NE(c["far_sphere_sweep"]["case_points"], a["far_sphere_sweep"]["case_points"]);
    EXPECT_EQ(c["results"], a["results"]) << "the seed is the sweep's alone";
    const command_result oracle = run_cli("bench --oracle --precision float");
    EXPECT_EQ(oracle.exit_code, 2) << oracle.output;
}

// The plots as a paper wants them: --plot-format and --error-measure reach the
// plot script; an unknown measure is an input error before any work; and
// bench.csv round-trips into the plot script: the accuracy-against-time
// plot drawn from it has the points of the plot drawn from report.json.
TEST_F(Cli, BenchPlotsTakeFormatsAndAMeasureAndDrawTheSameFromTheCsv) {
    const std::string corpus = std::string(RAYVERIFY_CORPUS_DIR) + "/on_surface.txt";
    const std::filesystem::path dir = dir_ / "paper";
    const command_result drawn =
        run_cli("bench --corpus " + corpus + " --variant naive --variant wald_origin_shift --repetitions 1 "
                "--min-time 0.001 --sweep 100 --plot-format svg --plot-format pdf --error-measure "
                "scale_error_radius:p99 --report " + dir.string() + " --per-case " + (dir_ / "cases.jsonl").string());
    ASSERT_EQ(drawn.exit_code, 0) << drawn.output;
    // --per-case: a line per case with every float and double target, as audit --per-case writes them.
    std::istringstream lines(read_text(dir_ / "cases.jsonl"));
    std::size_t lined = 0;
    for (std::string line; std::getline(lines, line); ++lined) {
        const nlohmann::json c = nlohmann::json::parse(line);
        EXPECT_TRUE(c["results"].contains("wald_origin_shift/double")) << line;
        EXPECT_EQ(c["results"].size(), 4u) << line;  // two variants in float and double
    }
    EXPECT_EQ(lined, 500u);
    EXPECT_TRUE(std::filesystem::exists(dir / "accuracy_vs_time.svg")) << drawn.output;
    EXPECT_TRUE(std::filesystem::exists(dir / "error_vs_condition.pdf")) << drawn.output;
    EXPECT_FALSE(std::filesystem::exists(dir / "accuracy_vs_time.png"));
    // The machine and the inputs, recorded: the corpus file by size and digest.
    const nlohmann::json report = nlohmann::json::parse(std::ifstream(dir / "report.json"));
    EXPECT_FALSE(report["machine"]["kernel"].get<std::string>().empty()) << report["machine"].dump();
    EXPECT_TRUE(report["machine"]["cpu_flags"].is_array());
    EXPECT_TRUE(report["machine"]["load_average"].is_null() || report["machine"]["load_average"].size() == 3);
    ASSERT_EQ(report["input_files"].size(), 1u) << report["input_files"].dump();
    EXPECT_EQ(report["input_files"][0]["role"], "corpus");
    EXPECT_EQ(report["input_files"][0]["bytes"].get<std::uintmax_t>(), std::filesystem::file_size(corpus));
    EXPECT_EQ(report["input_files"][0]["digest"].get<std::string>().size(), 16u);
    EXPECT_NE(read_text(dir / "report.md").find("digest " + report["input_files"][0]["digest"].get<std::string>()),
              std::string::npos);
    const command_result unknown = run_cli("bench --corpus " + corpus + " --error-measure near_root_ulp:p50 --report " +
                                           (dir_ / "unknown").string());
    EXPECT_EQ(unknown.exit_code, 2) << unknown.output;
    EXPECT_NE(unknown.output.find("--error-measure"), std::string::npos) << unknown.output;
    EXPECT_FALSE(std::filesystem::exists(dir_ / "unknown"));

    const auto names_where = [](auto holds) {
        std::string names;
        for (int k = 0; k < verdict_kind_count; ++k)
            if (holds(static_cast<verdict_kind>(k)))
                names += (names.empty() ? "" : ",") + std::string(verdict_name(static_cast<verdict_kind>(k)));
        return names;
    };
    const std::string script = "/usr/bin/python3 " + std::string(RAYVERIFY_SOURCE_DIR) + "/tools/plot_report.py ",
                      measure = " --error-measure near_root_ulp:max",
                      lists = measure + " --misclassifications " + names_where(is_misclassification) +
                              " --unscored " + names_where([](verdict_kind k) { return !is_scored(k); });
    std::filesystem::create_directories(dir / "from_csv");
    const command_result from_csv = run_shell(script + (dir / "from_csv").string() + measure + " --from-csv " +
                                                (dir / "bench.csv").string() + " --points " +
                                                (dir / "csv_points.json").string());
    ASSERT_EQ(from_csv.exit_code, 0) << from_csv.output;
    const command_result from_json =
        run_shell(script + dir.string() + lists + " --points " + (dir / "json_points.json").string());
    ASSERT_EQ(from_json.exit_code, 0) << from_json.output;
    const auto sorted_points = [](const std::filesystem::path& file) {
        std::vector<std::string> points;
        const nlohmann::json drawn = nlohmann::json::parse(std::ifstream(file));
        for (const auto& p : drawn["points"]) points.push_back(p.dump());
        std::sort(points.begin(), points.end());
        return points;
    };
    const std::vector<std::string> csv_points = sorted_points(dir / "csv_points.json");
    EXPECT_GE(csv_points.size(), 6u);  // naive and wald_origin_shift in three precisions, two panels each
    EXPECT_EQ(csv_points, sorted_points(dir / "json_points.json"));
}

// bench --audit: the whole audit's cost per case-target for each family and
// all, the share of solutions and ULP errors each oracle stage settled (each
// set of shares sums to 100%), and the targets with met or MISSED.
TEST_F(Cli, BenchAuditTimesTheWholeAuditPerFamilyWithItsStages) {
    const std::string corpus = std::string(RAYVERIFY_CORPUS_DIR);
    const command_result run = run_cli("bench --audit --corpus " + corpus + "/uniform.txt --corpus " + corpus +
                                       "/tangent_exact.txt --repetitions 1 --min-time 0.001 2>/dev/null");
    ASSERT_EQ(run.exit_code, 0) << run.output;
    std::istringstream lines(run.output);
    std::string line;
    std::set<std::string> rows;
    while (std::getline(lines, line)) {
        std::istringstream fields(line);
        std::string family, cases, naive, audit, ratio, per_case;
        std::array<std::string, 8> stages;  // expansion and exact shares of solutions, ULP errors, comparisons, roundings
        if (!(fields >> family >> cases >> naive >> audit >> ratio >> per_case)) continue;
        bool read = true;
        for (std::string& s : stages) read = read && static_cast<bool>(fields >> s) && s.back() == '%';
        if (!read) continue;
        rows.insert(family);
        const auto percent = [](const std::string& f) { return std::stod(f.substr(0, f.size() - 1)); };
        for (std::size_t k = 0; k < stages.size(); k += 2)
            EXPECT_LE(percent(stages[k]) + percent(stages[k + 1]), 100.0 + 1e-9) << line;
        EXPECT_GT(std::stod(audit), 0) << line;
        if (family == "tangent_exact") {
            EXPECT_GT(percent(stages[0]), 50) << "Δ′ = 0 is an expansion's to decide: " << line;
        }
        if (family == "uniform") {
            EXPECT_EQ(percent(stages[1]), 0) << line;
            EXPECT_EQ(percent(stages[3]), 0) << "a double's ULP errors need no GMP: " << line;
        }
    }
    EXPECT_EQ(rows, (std::set<std::string>{"uniform", "tangent_exact", "all"})) << run.output;
    EXPECT_NE(run.output.find("audit / naive double, uniform"), std::string::npos) << run.output;
    // Where the time goes: a row per family, six parts and their sum (each printed to 0.1x).
    const std::size_t parts_at = run.output.find("where the audit's time goes");
    ASSERT_NE(parts_at, std::string::npos) << run.output;
    std::istringstream parts(run.output.substr(parts_at));
    std::getline(parts, line);  // the title
    std::getline(parts, line);  // the header
    std::set<std::string> part_rows;
    for (int k = 0; k < 3 && std::getline(parts, line); ++k) {
        std::istringstream fields(line);
        std::string family;
        std::array<double, 8> x{};  // six parts (the judge's verdicts and figures apart), their sum, the audit
        fields >> family;
        for (double& v : x) {
            std::string f;
            ASSERT_TRUE(static_cast<bool>(fields >> f)) << line;
            ASSERT_EQ(f.back(), 'x') << line;
            v = std::stod(f);
        }
        part_rows.insert(family);
        EXPECT_NEAR(x[0] + x[1] + x[2] + x[3] + x[4] + x[5], x[6], 0.35) << line;
        EXPECT_GT(x[0], 0) << "the targets' own answers take time: " << line;
        EXPECT_GT(x[1], 0) << "the oracle takes time: " << line;
    }
    EXPECT_EQ(part_rows, (std::set<std::string>{"uniform", "tangent_exact", "all"})) << run.output;
    // Every missed target is followed by what meeting it would take.
    std::istringstream targets_part(run.output.substr(run.output.find("targets, this run:")));
    std::string previous;
    while (std::getline(targets_part, line)) {
        if (previous.find("MISSED") != std::string::npos) {
            EXPECT_TRUE(line.rfind("      needs ", 0) == 0 || line.rfind("      the lines cost ", 0) == 0 ||
                        line.find(" bytes of text per case, ") != std::string::npos)
                << previous << "\n" << line;
        }
        previous = line;
    }
    EXPECT_NE(run.output.find("per-case output / audit, all"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("corpus generate, uniform, per case"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("build: "), std::string::npos) << run.output;
    EXPECT_EQ(run_cli("bench --audit --oracle").exit_code, 2);
}

}  // namespace
