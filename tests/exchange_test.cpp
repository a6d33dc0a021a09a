// The exchange formats (corpus/exchange.h): cases written exactly, answers
// read strictly, and answers matched to their input; a target with recorded
// answers judged exactly as the built-in variant that computed them.
#include <gtest/gtest.h>

#include <charconv>
#include <cmath>
#include <filesystem>
#include <cstring>
#include <fstream>
#include <sstream>

#include "compare/audit.h"
#include "core/input_error.h"
#include "corpus/case_stream.h"
#include "corpus/corpus_io.h"
#include "corpus/exchange.h"
#include "support/process.h"

#include <nlohmann/json.hpp>

namespace rayverify {
namespace {

namespace fs = std::filesystem;

corpus_case unit_case() {
    corpus_case c;
    c.id = "c1";
    c.family = "hand";
    c.geometry = {{0, 0, -5}, {0, 0, 1}, {0, 0, 0}, 1};
    c.source = "hand:1";
    return c;
}

std::string written(exchange_format format, precision p, const std::vector<corpus_case>& cases,
                    std::string* sidecar = nullptr, number_style numbers = number_style::decimal) {
    std::ostringstream out, companion;
    case_writer writer(out, &companion, format, {p, "0123456789abcdef", cases.size(), numbers});
    for (const corpus_case& c : cases) writer.write(c);
    writer.finish();
    if (sidecar) *sidecar = companion.str();
    return out.str();
}

// A segment case goes out in its ray form (o = p0, d = p1 − p0 computed in
// the export's precision, on (0, 1)), and in JSON lines with its end p1 as
// given, for a program that casts between two points.
TEST(ExchangeCases, ASegmentGoesOutInItsRayFormAndInJsonLinesWithItsEnd) {
    corpus_case c = unit_case();
    make_segment(c, {0.1, 0, 0}, {0.7, 0, 0});
    const std::string jsonl = written(exchange_format::jsonl, precision::binary32, {c});
    const nlohmann::json line = nlohmann::json::parse(jsonl.substr(jsonl.find('\n') + 1));
    // A float export's decimals read back as the nearest float.
    EXPECT_EQ(static_cast<float>(line["dx"].get<double>()), 0.7f - 0.1f) << "computed in float";
    EXPECT_EQ(static_cast<float>(line["p1x"].get<double>()), 0.7f);
    EXPECT_EQ(line["tmin"].get<double>(), 0.0);
    EXPECT_EQ(line["tmax"].get<double>(), 1.0);
    // CSV and npy: the ray form, and p1x..p1z when the file holds a segment (empty / NaN on a ray's row).
    const std::string rays_only = written(exchange_format::csv, precision::binary64, {unit_case()});
    EXPECT_EQ(rays_only.find("p1x"), std::string::npos) << rays_only;
    std::ostringstream out, companion;
    case_writer writer(out, &companion, exchange_format::csv, {precision::binary64, "0123456789abcdef", 2,
                                                               number_style::decimal, true});
    corpus_case ray = unit_case();
    ray.id = "c0";
    writer.write(ray);
    writer.write(c);
    writer.finish();
    const std::string csv = out.str();
    EXPECT_NE(csv.find("tmin,tmax,p1x,p1y,p1z\n"), std::string::npos) << csv;
    EXPECT_NE(csv.find(",,,,\n"), std::string::npos) << "a ray's row: no bounds, no end\n" << csv;
    EXPECT_NE(csv.find(",0.6,0,0,0,0,0,1,0,1,0.7,0,0\n"), std::string::npos) << csv;  // d = 0.7 - 0.1 in double
}

TEST(ExchangeCases, CsvAndJsonLinesAreExactInTheirPrecision) {
    corpus_case c = unit_case();
    c.geometry.origin.x = 0.1;  // not a float: rounded to 0.1f in a float export
    c.tmax = 7.5;
    EXPECT_EQ(written(exchange_format::csv, precision::binary32, {c}),
              "# rayverify cases v1 precision=float fingerprint=0123456789abcdef cases=1 numbers=decimal\n"
              "id,family,ox,oy,oz,dx,dy,dz,cx,cy,cz,r,tmin,tmax\n"
              "c1,hand,0.1,0,-5,0,0,1,0,0,0,1,,7.5\n");
    const std::string hex = written(exchange_format::csv, precision::binary64, {c}, nullptr, number_style::hex);
    EXPECT_EQ(hex.substr(hex.find("\nc1,") + 1),
              "c1,hand,0x1.999999999999ap-4,0x0p+0,-0x1.4p+2,0x0p+0,0x0p+0,0x1p+0,0x0p+0,0x0p+0,0x0p+0,0x1p+0,,0x1."
              "ep+2\n");
    const std::string jsonl = written(exchange_format::jsonl, precision::binary32, {c});
    EXPECT_EQ(jsonl,
              "{\"rayverify\":\"cases\",\"version\":1,\"precision\":\"float\",\"fingerprint\":\"0123456789abcdef\","
              "\"cases\":1,\"numbers\":\"decimal\"}\n"
              "{\"id\":\"c1\",\"family\":\"hand\",\"ox\":0.1,\"oy\":0,\"oz\":-5,\"dx\":0,\"dy\":0,\"dz\":1,"
              "\"cx\":0,\"cy\":0,\"cz\":0,\"r\":1,\"tmin\":null,\"tmax\":7.5}\n");
}

TEST(ExchangeCases, NpyHasNumpysHeaderAndTheRowsInThePrecision) {
    corpus_case c = unit_case();
    c.tmin = 0.25;
    std::string sidecar;
    const std::string npy = written(exchange_format::npy, precision::binary32, {c, c}, &sidecar);
    ASSERT_GE(npy.size(), 64u);
    EXPECT_EQ(npy.substr(0, 8), std::string("\x93NUMPY\x01\x00", 8));
    const std::size_t header = static_cast<unsigned char>(npy[8]) | static_cast<unsigned char>(npy[9]) << 8;
    EXPECT_EQ((10 + header) % 64, 0u);
    EXPECT_NE(npy.find("{'descr': '<f4', 'fortran_order': False, 'shape': (2, 12), }"), std::string::npos);
    ASSERT_EQ(npy.size(), 10 + header + 2 * 12 * 4);
    float row[12];
    std::memcpy(row, npy.data() + 10 + header, sizeof row);
    EXPECT_EQ(row[2], -5.0f);
    EXPECT_EQ(row[10], 0.25f);
    EXPECT_TRUE(std::isnan(row[11]));  // no tmax
    EXPECT_NE(sidecar.find("\"ids\":[\"c1\",\"c1\"]"), std::string::npos) << sidecar;
    EXPECT_NE(sidecar.find("\"columns\":[\"ox\""), std::string::npos) << sidecar;
}

const std::string csv_head = "# rayverify results v1 precision=float fingerprint=0123456789abcdef\n";

TEST(ExchangeResults, CsvAnswersAreReadExactlyWithTheirOptionalGroups) {
    const results_file r = parse_results("a.csv",
                                         csv_head +
                                             "id,count,t0,t1,px,py,pz\n"
                                             "a,2,0x1.8p+1,0.1,1,2,3\n"
                                             "b,0,,,,,\n",
                                         exchange_format::csv);
    EXPECT_EQ(r.prec, precision::binary32);
    const recorded_answer* a = r.book->find("a");
    ASSERT_NE(a, nullptr);
    EXPECT_EQ(a->roots.count, 2);
    EXPECT_EQ(a->roots.t0, 3.0);
    EXPECT_EQ(a->roots.t1, static_cast<double>(0.1f));  // a float's 9-digit decimal is that float
    ASSERT_TRUE(a->hit_point);
    EXPECT_EQ(a->hit_point->z, 3.0);
    EXPECT_EQ(a->line, 3u);
    const recorded_answer* b = r.book->find("b");
    ASSERT_NE(b, nullptr);
    EXPECT_EQ(b->roots.count, 0);
    EXPECT_FALSE(b->hit_point);
}

// The input_error message of parsing `text`.
std::string error_of(const std::string& text, exchange_format f = exchange_format::csv) {
    try {
        parse_results("a." + std::string(exchange_format_name(f)), text, f);
    } catch (const input_error& e) {
        return e.what();
    }
    return "(no error)";
}

TEST(ExchangeResults, BadAnswersAreInputErrorsNamingLineAndField) {
    EXPECT_EQ(error_of(csv_head + "id,count,t0,t1\na,2,1,2\na,2,1,2\n"),
              "a.csv:4: field 'id': duplicate answer for case 'a', first given on line 3");
    EXPECT_EQ(error_of(csv_head + "id,count,t0,t1\na,2.5,1,2\n"), "a.csv:3: field 'count': '2.5' is not a whole number");
    EXPECT_NE(error_of(csv_head + "id,count,t0,t1\na,2,0.12345678912345,2\n")
                  .find("a.csv:3: field 't0': 0.12345678912345 is not a float (binary32) value"),
              std::string::npos);
    EXPECT_EQ(error_of(csv_head + "id,count,t0,t1,px,py\na,2,1,2,1,2\n"),
              "a.csv:3: field 'pz': missing while others of its group are given (all or none)");
    EXPECT_EQ(error_of(csv_head + "id,count,t0,t1,foo\n"),
              "a.csv:2: field 'foo': unknown column (known: id, count, t0, t1, t0_lo, t0_hi, t1_lo, t1_hi, px, py, pz, "
              "nx, ny, nz)");
    EXPECT_EQ(error_of(csv_head + "id,count,t0,t1,px,py,pz\na,2,1,2,1,,3\n"),
              "a.csv:3: field 'py': missing while others of its group are given (all or none)");
    EXPECT_EQ(error_of(csv_head + "id,t0,t1\n"), "a.csv:2: field 'count': required column is missing from the header");
    EXPECT_EQ(error_of("# rayverify cases v1 precision=float fingerprint=0123456789abcdef cases=1\n"),
              "a.csv:1: field 'header': 'cases' (expected results: a cases file is not an answer file)");
    EXPECT_EQ(error_of("{\"rayverify\":\"results\",\"version\":2,\"precision\":\"float\",\"fingerprint\":"
                       "\"0123456789abcdef\"}\n",
                       exchange_format::jsonl),
              "a.jsonl:1: field 'version': schema version 2 (this rayverify reads version 1)");
    EXPECT_EQ(error_of("{\"rayverify\":\"results\",\"version\":1,\"precision\":\"double\",\"fingerprint\":"
                       "\"0123456789abcdef\"}\n{\"id\":\"a\",\"count\":1,\"t0\":1,\"t1\":1,\"bounds\":[1,2]}\n",
                       exchange_format::jsonl),
              "a.jsonl:2: field 'bounds': unknown field (known: id, count, t0, t1, t0_bounds, t1_bounds, hit_point, "
              "normal)");
    const std::string jsonl_head = "{\"rayverify\":\"results\",\"version\":1,\"precision\":\"double\",\"fingerprint\":"
                                   "\"0123456789abcdef\"}\n";
    EXPECT_EQ(error_of(jsonl_head + "{\"id\":\"a\",\"count\":2,\"t0\":1,\"t1\":2,\"t0_bounds\":[1,1]}\n",
                       exchange_format::jsonl),
              "a.jsonl:2: field 't1_bounds': missing while others of its group (t0_bounds, t1_bounds) are given (all or "
              "none)");
    EXPECT_EQ(error_of(jsonl_head + "{\"id\":\"a\",\"count\":2,\"t0\":1,\"t1\":2,\"hit_point\":[1,2]}\n",
                       exchange_format::jsonl),
              "a.jsonl:2: field 'hit_point': expected an array of 3 numbers, got [1,2]");
}

TEST(ExchangeResults, JsonLinesCarryNonFiniteValuesAsStrings) {
    const results_file r = parse_results(
        "a.jsonl",
        "{\"rayverify\":\"results\",\"version\":1,\"precision\":\"double\",\"fingerprint\":\"0123456789abcdef\"}\n"
        "{\"id\":\"a\",\"count\":2,\"t0\":\"-inf\",\"t1\":\"nan\",\"t0_bounds\":[1,2],\"t1_bounds\":[3,\"0x1p+2\"],"
        "\"normal\":[0,0,-1]}\n",
        exchange_format::jsonl);
    const recorded_answer* a = r.book->find("a");
    ASSERT_NE(a, nullptr);
    EXPECT_EQ(a->roots.t0, -INFINITY);
    EXPECT_TRUE(std::isnan(a->roots.t1));
    ASSERT_TRUE(a->t1_bounds);
    EXPECT_EQ((*a->t1_bounds)[1], 4.0);
    ASSERT_TRUE(a->normal);
    EXPECT_EQ(a->normal->z, -1.0);
}

// Answers for the cases `ids`, in double, with the fingerprint of exactly those cases.
results_file answers_for(const std::vector<std::string>& ids, const std::string& fingerprint) {
    std::string text = "# rayverify results v1 precision=double fingerprint=" + fingerprint + "\nid,count,t0,t1\n";
    for (const std::string& id : ids) text += id + ",0,,\n";
    return parse_results("a.csv", text, exchange_format::csv);
}

std::string match_error(results_file r, const std::vector<corpus_case>& input, const std::string& fingerprint) {
    try {
        answer_matcher m(r);
        for (const corpus_case& c : input) m.add(c);
        m.finish(fingerprint);
    } catch (const input_error& e) {
        return e.what();
    }
    return "(no error)";
}

TEST(ExchangeResults, AnswersMustMatchTheirInputExactly) {
    corpus_case a = unit_case(), b = unit_case();
    b.id = "c2";
    b.source = "hand:2";
    case_fingerprint f;
    f.add(a);
    f.add(b);
    const std::string input = f.text();
    const std::string mine = exchange_fingerprint(input, precision::binary64);
    EXPECT_EQ(match_error(answers_for({"c1", "c2"}, mine), {a, b}, input), "(no error)");
    EXPECT_EQ(match_error(answers_for({"c1"}, mine), {a, b}, input), "a.csv: field 'id': no answer for case 'c2' (hand:2)");
    EXPECT_EQ(match_error(answers_for({"c1", "c2", "c9"}, mine), {a, b}, input),
              "a.csv:5: field 'id': answer for 'c9', which is not a case of this input");
    EXPECT_NE(match_error(answers_for({"c1", "c2"}, exchange_fingerprint(input, precision::binary32)), {a, b}, input)
                  .find("a.csv:1: field 'precision': wrong precision: the answers say double, but their fingerprint is "
                        "that of the float export"),
              std::string::npos);
    EXPECT_NE(match_error(answers_for({"c1", "c2"}, "0123456789abcdef"), {a, b}, input)
                  .find("a.csv:1: field 'fingerprint': 0123456789abcdef is not the fingerprint of this input"),
              std::string::npos);
}

// The whole shipped corpus through a results file built from naive's own
// answers: the same tallies, verdict for verdict and ULP for ULP.
TEST(ExchangeResults, RecordedAnswersAreJudgedExactlyAsTheVariantThatComputedThem) {
    const std::vector<corpus_case> cases = read_corpus({RAYVERIFY_CORPUS_DIR});
    for (precision p : {precision::binary32, precision::binary64}) {
        const audit_target builtin{*find_builtin_variant("naive"), p};
        auto book = std::make_shared<answer_book>();
        book->prec = p;
        for (const corpus_case& c : cases) {
            recorded_answer a;
            const ray_sphere<double> g = c.geometry;
            if (p == precision::binary32) {
                const root_pair<float> r = builtin.subject.run_float(rounded_to<float>(g));
                a.roots = {r.count, r.t0, r.t1};
            } else {
                a.roots = builtin.subject.run_double(g);
            }
            book->by_id.emplace(c.id, a);
        }
        audit_target recorded;
        recorded.subject.name = "naive";
        recorded.subject.promises = builtin.subject.promises;
        recorded.prec = p;
        recorded.recorded = book;
        const audit_totals want = run_audit(cases, {builtin}), got = run_audit(cases, {recorded});
        ASSERT_EQ(got.overall.size(), 1u);
        EXPECT_EQ(got.overall[0].verdicts, want.overall[0].verdicts) << precision_name(p);
        EXPECT_EQ(got.overall[0].causes, want.overall[0].causes) << precision_name(p);
        EXPECT_EQ(got.overall[0].errors[rayverify::error_figure::near_root_ulp].max, want.overall[0].errors[rayverify::error_figure::near_root_ulp].max) << precision_name(p);
        EXPECT_EQ(got.overall[0].errors[rayverify::error_figure::far_root_ulp].max, want.overall[0].errors[rayverify::error_figure::far_root_ulp].max) << precision_name(p);
        EXPECT_EQ(got.overall[0].errors[rayverify::error_figure::hit_point_ulp].max, want.overall[0].errors[rayverify::error_figure::hit_point_ulp].max) << precision_name(p);
        EXPECT_GT(want.overall[0].disagreements(), 0u);
    }
}

// The outputs beside t a results file carries are judged, answer by answer,
// as a plugin's are (the engines' judge): a t interval that
// leaves out the exact root is unsound_bound, its width is reported in ULPs,
// a normal gets its angle. A --contract that names an output the hits do not
// carry is an input error naming the answer, its line and the columns.
TEST(ExchangeResults, OutputsBesideTAreJudgedAndTheContractsOutputsRequired) {
    using test_support::run_cli;
    const test_support::scratch_directory dir_scratch("rayverify_exchange_outputs");
    const fs::path& dir = dir_scratch.path();
    // Two cases with roots t* = 4 and 6: o = (0, 0, -5), d = (0, 0, 1), a unit sphere at (x, 0, 0).
    std::ofstream(dir / "two.txt") << "sound hand 0 0 -5 0 0 1 0 0 0 1 - -\n"
                                      "loose hand 3 0 -5 0 0 1 3 0 0 1 - -\n";
    const std::string corpus = (dir / "two.txt").string();
    ASSERT_EQ(run_cli("corpus export --corpus " + corpus + " -o " + (dir / "cases.csv").string()).exit_code, 0);
    const std::string text = test_support::read_text(dir / "cases.csv");
    const std::string fingerprint = text.substr(text.find("fingerprint=") + 12, 16);
    const std::string header = "# rayverify results v1 precision=double fingerprint=" + fingerprint + "\n";
    const auto audit = [&](const std::string& body, const std::string& contract) {
        std::ofstream(dir / "answers.csv") << header << body;
        fs::remove(dir / "cases.jsonl");
        return run_cli("audit --corpus " + corpus + " --results " + (dir / "answers.csv").string() +
                       " --contract " + contract + " --name mine --per-case " + (dir / "cases.jsonl").string());
    };
    const auto result_of = [&](const std::string& id) {
        std::istringstream lines(test_support::read_text(dir / "cases.jsonl"));
        for (std::string line; std::getline(lines, line);)
            if (line.find("\"" + id + "\"") != std::string::npos) return line;
        return std::string();
    };
    // The first interval holds both roots; the second's t0 interval [4.5, 5] leaves out t* = 4.
    const auto judged = audit("id,count,t0,t1,t0_lo,t0_hi,t1_lo,t1_hi,nx,ny,nz\n"
                              "sound,2,4,6,3.5,4.5,5.5,6.5,0,0,-1\n"
                              "loose,2,4,6,4.5,5,5.5,6.5,0,0,-2\n",
                              "query=line_roots");
    EXPECT_EQ(judged.exit_code, 1) << judged.output;
    const std::string sound = result_of("sound"), loose = result_of("loose");
    EXPECT_NE(sound.find("\"verdict\":\"agree\""), std::string::npos) << sound;
    EXPECT_NE(sound.find("\"bound_width_ulp\""), std::string::npos) << sound;
    EXPECT_NE(sound.find("\"normal_angle\":0"), std::string::npos) << sound;
    EXPECT_NE(loose.find("\"verdict\":\"unsound_bound\""), std::string::npos) << loose;
    // A contract naming the normal: every hit must carry it.
    const auto lacking = audit("id,count,t0,t1,nx,ny,nz\nsound,2,4,6,0,0,-1\nloose,2,4,6,,,\n",
                               "query=line_roots,normal=yes");
    EXPECT_EQ(lacking.exit_code, 2) << lacking.output;
    EXPECT_NE(lacking.output.find("answers.csv:4: field 'nx ny nz'"), std::string::npos) << lacking.output;
    EXPECT_NE(lacking.output.find("answer 'loose' is a hit without"), std::string::npos) << lacking.output;
    EXPECT_FALSE(fs::exists(dir / "cases.jsonl")) << "a refused results file leaves no output";
}

// An absent t0 or t1 has one meaning or is refused, never judged: count 1
// without t1 is a tangent's root written once (t1 = t0); a nearest_hit
// answer needs no t1 column and an any_hit answer no t at all; a value the
// contract needs and the answer leaves out is an input error naming the
// file, line and field.
TEST(ExchangeResults, AbsentValuesHaveOneMeaningOrAreInputErrors) {
    const std::string head = "# rayverify results v1 precision=double fingerprint=0123456789abcdef\n";
    const results_file r = parse_results("a.csv", head + "id,count,t0,t1\ntan,1,5,\nmiss,0,,\nhalf,2,4,\n",
                                         exchange_format::csv);
    const recorded_answer* tan = r.book->find("tan");
    ASSERT_NE(tan, nullptr);
    EXPECT_EQ(tan->roots.t1, 5.0);
    EXPECT_TRUE(tan->t0_given && tan->t1_given);
    const recorded_answer* half = r.book->find("half");
    ASSERT_NE(half, nullptr);
    EXPECT_FALSE(half->t1_given);
    const auto refusal = [&](const std::string& spec) -> std::string {
        try {
            check_recorded_values(parse_contract(spec), *r.book);
        } catch (const input_error& e) {
            return e.what();
        }
        return "(no error)";
    };
    EXPECT_EQ(refusal("query=line_roots"),
              "a.csv:5: field 't1': missing: answer 'half' has count 2, and a line_roots answer with that count needs t1");
    EXPECT_EQ(refusal("query=any_hit"), "(no error)");
    // nearest_hit: no t1 column at all; a hit without t0 is refused (JSON lines: a null is absent too).
    const results_file nearest = parse_results("a.csv", head + "id,count,t0\nhit,1,4\nnone,0,\n", exchange_format::csv);
    EXPECT_NO_THROW(check_recorded_values(parse_contract("query=nearest_hit"), *nearest.book));
    const results_file lost = parse_results(
        "a.jsonl",
        "{\"rayverify\":\"results\",\"version\":1,\"precision\":\"double\",\"fingerprint\":\"0123456789abcdef\"}\n"
        "{\"id\":\"a\",\"count\":0}\n{\"id\":\"b\",\"count\":1,\"t0\":null}\n",
        exchange_format::jsonl);
    try {
        check_recorded_values(parse_contract("query=nearest_hit"), *lost.book);
        ADD_FAILURE() << "an absent t0 of a hit was judged";
    } catch (const input_error& e) {
        EXPECT_STREQ(e.what(),
                     "a.jsonl:3: field 't0': missing: answer 'b' has count 1, and a nearest_hit answer with that count "
                     "needs t0");
    }
}

// The whole command: a tangent written once agrees (it was non_finite, t1 read as NaN), and a hit
// without its t0 is exit 2 with no report.
TEST(ExchangeResults, ATangentsRootWrittenOnceAgrees) {
    using test_support::run_cli;
    const test_support::scratch_directory dir_scratch("rayverify_exchange_absent");
    const fs::path& dir = dir_scratch.path();
    // A tangent at t* = 5 and two roots 4, 6.
    std::ofstream(dir / "two.txt") << "tan hand 1 0 -5 0 0 1 0 0 0 1 - -\n"
                                      "two hand 0 0 -5 0 0 1 0 0 0 1 - -\n";
    const std::string corpus = (dir / "two.txt").string();
    ASSERT_EQ(run_cli("corpus export --corpus " + corpus + " -o " + (dir / "cases.csv").string()).exit_code, 0);
    const std::string text = test_support::read_text(dir / "cases.csv");
    const std::string fingerprint = text.substr(text.find("fingerprint=") + 12, 16);
    const auto audit = [&](const std::string& body, const std::string& contract) {
        std::ofstream(dir / "answers.csv") << "# rayverify results v1 precision=double fingerprint=" << fingerprint
                                           << "\n" << body;
        return run_cli("audit --corpus " + corpus + " --results " + (dir / "answers.csv").string() + " --contract " +
                       contract + " --name mine --report " + (dir / "report").string());
    };
    const auto line = audit("id,count,t0,t1\ntan,1,5,\ntwo,2,4,6\n", "query=line_roots,reports_tangent=yes");
    EXPECT_EQ(line.exit_code, 0) << line.output;
    const auto nearest = audit("id,count,t0\ntan,1,5\ntwo,1,4\n", "query=nearest_hit");
    EXPECT_EQ(nearest.exit_code, 0) << nearest.output;
    fs::remove_all(dir / "report");
    const auto missing = audit("id,count,t0,t1\ntan,1,5,\ntwo,2,4,\n", "query=line_roots");
    EXPECT_EQ(missing.exit_code, 2) << missing.output;
    EXPECT_NE(missing.output.find("answers.csv:4: field 't1': missing: answer 'two' has count 2"), std::string::npos)
        << missing.output;
    EXPECT_FALSE(fs::exists(dir / "report" / "report.json")) << "a refused results file leaves no report";
}

TEST(ExchangeResults, ResultsThatDoNotMatchTheExportAreRefusedWithNoReport) {
    using test_support::run_cli;
    const test_support::scratch_directory dir_scratch("rayverify_exchange_cli");
    const fs::path& dir = dir_scratch.path();
    const std::string cases = (dir / "cases.csv").string();
    ASSERT_EQ(run_cli("corpus export --generate uniform:5 -o " + cases).exit_code, 0);
    const std::string text = test_support::read_text(cases);
    const std::string fingerprint = text.substr(text.find("fingerprint=") + 12, 16);
    std::string answers = "# rayverify results v1 precision=double fingerprint=" + fingerprint + "\nid,count,t0,t1\n";
    for (int i = 0; i < 4; ++i) answers += "uniform-1-00000" + std::to_string(i) + ",0,,\n";
    const auto audit = [&](const std::string& body, const std::string& input) {
        const fs::path file = dir / "answers.csv";
        std::ofstream(file) << body;
        return run_cli("audit " + input + " --results " + file.string() +
                       " --contract query=line_roots --name mine --report " + (dir / "report").string());
    };
    const auto missing = audit(answers, "--generate uniform:5");
    EXPECT_EQ(missing.exit_code, 2) << missing.output;
    EXPECT_NE(missing.output.find("no answer for case 'uniform-1-000004'"), std::string::npos) << missing.output;
    EXPECT_FALSE(fs::exists(dir / "report")) << "a refused results file leaves no report";
    const auto other = audit(answers + "uniform-1-000004,0,,\n", "--generate uniform:5:2");
    EXPECT_EQ(other.exit_code, 2) << other.output;
    EXPECT_NE(other.output.find("answers.csv:1: field 'fingerprint'"), std::string::npos) << other.output;
    EXPECT_FALSE(fs::exists(dir / "report"));
    const auto ok = audit(answers + "uniform-1-000004,0,,\n", "--generate uniform:5");
    EXPECT_NE(ok.exit_code, 2) << ok.output;
    EXPECT_TRUE(fs::exists(dir / "report" / "report.json")) << ok.output;
}

}  // namespace
}  // namespace rayverify

namespace rayverify {
namespace {

// Every value of the shipped corpus, exported to JSON lines in decimal (the
// format `hunt --command` sends), reads back as the same bits in the export's
// precision: a negative zero stays negative (it used to be written as 0).
TEST(ExchangeCases, JsonLinesDecimalKeepsEveryValueOfTheShippedCorpusNegativeZeroIncluded) {
    std::vector<corpus_case> cases =
        read_corpus({fs::path(RAYVERIFY_CORPUS_DIR), fs::path(RAYVERIFY_CORPUS_DIR) / "edge"});
    ASSERT_GT(cases.size(), 1000u);
    corpus_case zeros = unit_case();  // negative zeros in double too
    zeros.id = "negative-zeros";
    zeros.geometry.origin = {-0.0, 0.0, -5};
    zeros.geometry.centre = {-0.0, -0.0, 0};
    cases.push_back(zeros);
    for (const precision p : {precision::binary32, precision::binary64}) {
        SCOPED_TRACE(precision_name(p));
        std::istringstream lines(written(exchange_format::jsonl, p, cases));
        std::string line;
        std::getline(lines, line);  // the header
        std::size_t negative_zeros = 0;
        for (const corpus_case& c : cases) {
            ASSERT_TRUE(std::getline(lines, line));
            const auto j = nlohmann::json::parse(line);
            ASSERT_EQ(j.at("id").get<std::string>(), c.id);
            const auto& g = c.geometry;
            const double values[10] = {g.origin.x, g.origin.y, g.origin.z, g.direction.x, g.direction.y,
                                       g.direction.z, g.centre.x, g.centre.y, g.centre.z, g.radius};
            const char* names[10] = {"ox", "oy", "oz", "dx", "dy", "dz", "cx", "cy", "cz", "r"};
            for (int i = 0; i < 10; ++i) {
                const double expected =
                    p == precision::binary64 ? values[i] : static_cast<double>(static_cast<float>(values[i]));
                const auto& v = j.at(names[i]);
                const double back = v.is_string() ? parse_exact_double(v.get<std::string>(), "", 0, names[i])
                                                   : v.get<double>();
                const double read = p == precision::binary64 ? back : static_cast<double>(static_cast<float>(back));
                if (std::isnan(expected)) continue;
                EXPECT_EQ(std::signbit(read), std::signbit(expected)) << c.id << " " << names[i] << ": " << line;
                EXPECT_EQ(read, expected) << c.id << " " << names[i];
                if (expected == 0 && std::signbit(expected)) ++negative_zeros;
            }
        }
        EXPECT_GE(negative_zeros, 3u);
    }
}

// The same in every other format and number style: CSV and JSON lines in
// decimal and hex, and npy, each value read back as the same bits.
TEST(ExchangeCases, EveryFormatKeepsEveryValueNegativeZeroIncluded) {
    std::vector<corpus_case> cases =
        read_corpus({fs::path(RAYVERIFY_CORPUS_DIR), fs::path(RAYVERIFY_CORPUS_DIR) / "edge"});
    corpus_case zeros = unit_case();
    zeros.id = "negative-zeros";
    zeros.geometry.origin = {-0.0, 0.0, -5};
    zeros.geometry.centre = {-0.0, -0.0, 0};
    cases.push_back(zeros);
    const auto values_of = [](const corpus_case& c, precision p) {
        const auto& g = c.geometry;
        std::vector<double> v = {g.origin.x, g.origin.y, g.origin.z, g.direction.x, g.direction.y,
                                 g.direction.z, g.centre.x, g.centre.y, g.centre.z, g.radius};
        for (double& x : v)
            if (p == precision::binary32) x = static_cast<double>(static_cast<float>(x));
        return v;
    };
    const auto same_bits = [](double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; };
    // As a reader in the export's precision reads it (a float decimal with strtof, as documented).
    const auto read_back = [](const std::string& text, precision p) {
        if (p == precision::binary32 && text.find('x') == std::string::npos) {
            float f = 0;
            std::from_chars(text.data(), text.data() + text.size(), f);
            return static_cast<double>(f);
        }
        return parse_exact_double(text, "", 0, "v");
    };
    for (const precision p : {precision::binary32, precision::binary64}) {
        for (const number_style style : {number_style::decimal, number_style::hex}) {
            SCOPED_TRACE(std::string(precision_name(p)) + (style == number_style::hex ? " hex" : " decimal"));
            // CSV: the cells ox … r after id and family.
            std::istringstream csv(written(exchange_format::csv, p, cases, nullptr, style));
            std::string line;
            std::getline(csv, line);
            std::getline(csv, line);
            for (const corpus_case& c : cases) {
                ASSERT_TRUE(std::getline(csv, line));
                const std::vector<std::string> cells = split_csv_row(line, "csv", 0);
                ASSERT_EQ(cells[0], c.id);
                const std::vector<double> expected = values_of(c, p);
                for (std::size_t i = 0; i < expected.size(); ++i)
                    EXPECT_TRUE(same_bits(read_back(cells[2 + i], p), expected[i]))
                        << c.id << " column " << i << ": " << cells[2 + i];
            }
            // JSON lines in hex: strings.
            if (style == number_style::hex) {
                std::istringstream jsonl(written(exchange_format::jsonl, p, cases, nullptr, style));
                std::getline(jsonl, line);
                const char* names[10] = {"ox", "oy", "oz", "dx", "dy", "dz", "cx", "cy", "cz", "r"};
                for (const corpus_case& c : cases) {
                    ASSERT_TRUE(std::getline(jsonl, line));
                    const auto j = nlohmann::json::parse(line);
                    const std::vector<double> expected = values_of(c, p);
                    for (int i = 0; i < 10; ++i)
                        EXPECT_TRUE(same_bits(read_back(j.at(names[i]).get<std::string>(), p),
                                              expected[static_cast<std::size_t>(i)]))
                            << c.id << " " << names[i];
                }
            }
        }
        // npy: the values' own bits, row by row.
        std::string sidecar;
        const std::string npy = written(exchange_format::npy, p, cases, &sidecar);
        const std::size_t header = 10 + (static_cast<unsigned char>(npy[8]) | static_cast<unsigned char>(npy[9]) << 8);
        const std::size_t size = p == precision::binary32 ? 4 : 8;
        ASSERT_EQ(npy.size(), header + cases.size() * 12 * size);
        for (std::size_t row = 0; row < cases.size(); ++row) {
            const std::vector<double> expected = values_of(cases[row], p);
            for (std::size_t i = 0; i < expected.size(); ++i) {
                const char* at = npy.data() + header + (row * 12 + i) * size;
                double back;
                if (size == 4) {
                    float f;
                    std::memcpy(&f, at, 4);
                    back = f;
                } else {
                    std::memcpy(&back, at, 8);
                }
                EXPECT_TRUE(same_bits(back, expected[i])) << cases[row].id << " column " << i;
            }
        }
    }
}

// A results file is read with the input's ids known: reading stops at the
// first answer to no case, an npy of more rows than cases is refused by its
// header, and a file larger than the answers can take is not read.
TEST(ExchangeResults, ReadingIsBoundedByTheInput) {
    results_scope scope;
    scope.add("a");
    const std::string head = "# rayverify results v1 precision=double fingerprint=0123456789abcdef\nid,count,t0,t1\n";
    try {
        parse_results("a.csv", head + "a,0,,\nb,0,,\nbad,one,,\n", exchange_format::csv, std::nullopt, &scope);
        ADD_FAILURE() << "an answer to no case was accepted";
    } catch (const input_error& e) {
        EXPECT_EQ(std::string(e.what()), "a.csv:4: field 'id': answer for 'b', which is not a case of this input");
    }
    EXPECT_LT(scope.max_bytes(exchange_format::csv), std::size_t{1} << 20);
    EXPECT_EQ(scope.max_bytes(exchange_format::npy), (std::size_t{1} << 16) + answer_columns().size() * 8);
    EXPECT_EQ(scope.max_bytes(exchange_format::npy, true), (std::size_t{1} << 16) + 6 + 16);
}

// JSON: a number beyond double range and a key given twice are input errors
// naming line and field (they were an internal error, and last-wins).
TEST(ExchangeResults, JsonOverflowAndDuplicateKeysAreInputErrors) {
    const std::string head =
        "{\"rayverify\":\"results\",\"version\":1,\"precision\":\"double\",\"fingerprint\":\"0123456789abcdef\"}\n";
    const auto error = [](const std::string& text, exchange_format f, const std::optional<std::string>& sidecar) {
        try {
            parse_results(f == exchange_format::npy ? "a.npy" : "a.jsonl", text, f, sidecar);
        } catch (const input_error& e) {
            return std::string(e.what());
        }
        return std::string("accepted");
    };
    EXPECT_EQ(error(head + "{\"id\":\"a\",\"count\":2,\"t0\":4,\"t1\":1e400}\n", exchange_format::jsonl, std::nullopt),
              "a.jsonl:2: field 't1': number overflow parsing '1e400'");
    EXPECT_EQ(error(head + "{\"id\":\"a\",\"count\":2,\"t0\":4,\"hit_point\":[1,-1e999,0],\"t1\":5}\n",
                    exchange_format::jsonl, std::nullopt),
              "a.jsonl:2: field 'hit_point[1]': number overflow parsing '-1e999'");
    EXPECT_EQ(error(head + "{\"id\":\"a\",\"id\":\"b\",\"count\":0}\n", exchange_format::jsonl, std::nullopt),
              "a.jsonl:2: field 'id': the key \"id\" is given twice in one object");
    EXPECT_EQ(error(std::string("\x93NUMPY\x01\x00", 8), exchange_format::npy,
                    std::string("{\"rayverify\":\"results\",\n\"version\":1e400}")),
              "a.json:2: field 'version': number overflow parsing '1e400'");
    // A count is 0, 1 or 2, as the format says (the results-reader fuzzer found 3 accepted).
    EXPECT_EQ(error(head + "{\"id\":\"a\",\"count\":3,\"t0\":4,\"t1\":5}\n", exchange_format::jsonl, std::nullopt),
              "a.jsonl:2: field 'count': 3 is not 0 (a miss), 1 or 2 (hits)");
    EXPECT_EQ(error(head + "{\"id\":\"a\",\"count\":-1}\n", exchange_format::jsonl, std::nullopt),
              "a.jsonl:2: field 'count': -1 is not 0 (a miss), 1 or 2 (hits)");
}

// RFC 4180: in a quoted cell, "" is a quote (and a comma is text).
TEST(ExchangeResults, CsvIdsAreUnescapedAsRfc4180Says) {
    const results_file r = parse_results(
        "a.csv",
        "# rayverify results v1 precision=double fingerprint=0123456789abcdef\nid,count,t0,t1\n\"q\"\"uote\",0,,\n"
        "\"a\"\",b\",0,,\n",
        exchange_format::csv);
    EXPECT_NE(r.book->find("q\"uote"), nullptr);
    EXPECT_NE(r.book->find("a\",b"), nullptr);
    // And the export writes such ids so: "q""uote".
    corpus_case c = unit_case();
    c.id = "q\"uote";
    EXPECT_NE(written(exchange_format::csv, precision::binary64, {c}).find("\n\"q\"\"uote\",hand,"), std::string::npos);
}

// A hex value is exact: in a float file it must be a float. A decimal of at
// most 9 significant digits is still read as the nearest float.
TEST(ExchangeResults, HexDoublesInAFloatFileAreRefused) {
    const std::string head = "# rayverify results v1 precision=float fingerprint=0123456789abcdef\nid,count,t0,t1\n";
    EXPECT_THROW(parse_results("a.csv", head + "a,1,0x1.999999999999ap-4,\n", exchange_format::csv), input_error);
    const results_file decimal = parse_results("a.csv", head + "a,1,0.1,\n", exchange_format::csv);
    EXPECT_EQ(decimal.book->find("a")->roots.t0, static_cast<double>(0.1f));
    const results_file hex_float = parse_results("a.csv", head + "a,1,0x1.99999ap-4,\n", exchange_format::csv);
    EXPECT_EQ(hex_float.book->find("a")->roots.t0, static_cast<double>(0.1f));
}

}  // namespace
}  // namespace rayverify
