// Segment cases: the cast from p0 to p1, judged exactly on the segment the
// target receives (d = p1 − p0 taken exactly, never rounded). Corpus lines
// and CSV files in the segment form, the oracle on hand-worked segments
// (one whose end lies exactly on the sphere although p1 − p0 is no double),
// both oracle routes agreeing on random segments, and the shipped physics
// example (examples/physics_segment) audited through its segment entry with
// the verdicts worked out by hand in its segments.txt.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>

#include "compare/audit.h"
#include "compare/judge.h"
#include "corpus/generators.h"
#include "corpus/corpus_io.h"
#include "intersectors/registry.h"
#include "oracle/oracle.h"
#include "plugin/plugin_loader.h"
#include "support/process.h"

namespace rayverify {
namespace {

const std::string physics_segments = std::string(RAYVERIFY_SOURCE_DIR) + "/examples/physics_segment/segments.txt";

std::string read_error(const std::string& contents, bool csv) {
    try {
        parse_corpus("mine.txt", contents, csv);
    } catch (const input_error& e) {
        return e.what();
    }
    return "(read)";
}

TEST(SegmentCorpus, TextLinesMixWithRaysAndReadBackExactly) {
    const std::vector<corpus_case> cases = parse_corpus(
        "mine.txt",
        "ray - 0 0 -5 0 0 1 0 0 0 1\n"
        "seg cast segment -3 0 0 -1 0 0 0 0 0 1\n"
        "seg_hex - segment -0x1p+1 0 0 0x1p-60 0 0 0 0 0 0x1p-60\n",
        false);
    ASSERT_EQ(cases.size(), 3u);
    EXPECT_FALSE(cases[0].is_segment());
    ASSERT_TRUE(cases[1].is_segment());
    EXPECT_EQ(cases[1].family, "cast");
    EXPECT_EQ(cases[1].geometry.origin, (vec3<double>{-3, 0, 0}));
    EXPECT_EQ(*cases[1].segment_end, (vec3<double>{-1, 0, 0}));
    EXPECT_EQ(cases[1].geometry.direction, (vec3<double>{2, 0, 0})) << "p1 - p0, rounded to double";
    EXPECT_EQ(cases[1].tmin, 0.0);
    EXPECT_EQ(cases[1].tmax, 1.0);
    // 2 + 2^-60 is no double: the stored direction is rounded, p1 is kept exactly.
    EXPECT_EQ(cases[2].geometry.direction.x, 2.0);
    EXPECT_EQ(cases[2].segment_end->x, 0x1p-60);
    // The written line reads back as the same segment.
    const std::string line = format_case_line(cases[2]);
    EXPECT_EQ(line, "seg_hex - segment -0x1p+1 0x0p+0 0x0p+0 0x1p-60 0x0p+0 0x0p+0 0x0p+0 0x0p+0 0x0p+0 0x1p-60");
    const corpus_case back = parse_corpus("back.txt", line, false).front();
    EXPECT_EQ(*back.segment_end, *cases[2].segment_end);
    EXPECT_EQ(back.geometry.origin, cases[2].geometry.origin);
}

TEST(SegmentCorpus, CsvFilesHoldOneFormAndBadLinesNameTheirField) {
    const std::vector<corpus_case> cases =
        parse_corpus("mine.csv", "id,p0x,p0y,p0z,p1x,p1y,p1z,cx,cy,cz,r\na,-3,0,0,-1,0,0,0,0,0,1\n", true);
    ASSERT_EQ(cases.size(), 1u);
    ASSERT_TRUE(cases[0].is_segment());
    EXPECT_EQ(cases[0].segment_end->x, -1.0);
    EXPECT_NE(read_error("id,p0x,p0y,p0z,p1x,p1y,p1z,ox,cx,cy,cz,r\n", true).find("one form of case"),
              std::string::npos);
    EXPECT_NE(read_error("id,p0x,p0y,p0z,p1x,p1y,p1z,cx,cy,cz,r,tmax\n", true).find("no tmin or tmax"),
              std::string::npos);
    EXPECT_NE(read_error("id,p0x,p0y,p0z,p1x,p1y,cx,cy,cz,r\n", true).find("p1z"), std::string::npos);
    // A segment line has 13 fields: no interval after it.
    EXPECT_NE(read_error("a - segment -3 0 0 -1 0 0 0 0 0 1 0 1\n", false).find("expected 13"), std::string::npos);
    const std::string bad_number = read_error("a - segment -3 0 0 -1 x 0 0 0 0 1\n", false);
    EXPECT_NE(bad_number.find("mine.txt:1"), std::string::npos) << bad_number;
    EXPECT_NE(bad_number.find("p1y"), std::string::npos) << bad_number;
}

TEST(SegmentCorpus, ValidityIsTheSegmentsInTheTargetsPrecision) {
    corpus_case c;
    make_segment(c, {0, 0, 2}, {0, 0, 2});
    c.geometry.radius = 1;
    EXPECT_EQ(case_validity<double>(c), invalid_reason::zero_direction) << "p0 = p1: a zero-length cast";
    // Distinct in double, one point in float.
    make_segment(c, {1, 0, 0}, {1 + 0x1p-40, 0, 0});
    EXPECT_EQ(case_validity<double>(c), invalid_reason::none);
    EXPECT_EQ(case_validity<float>(c), invalid_reason::zero_direction);
    make_segment(c, {0, 0, 0}, {NAN, 0, 0});
    EXPECT_EQ(case_validity<double>(c), invalid_reason::non_finite_input);
    // Finite ends whose difference overflows.
    make_segment(c, {-0x1p1023, 0, 0}, {0x1p1023, 0, 0});
    EXPECT_EQ(case_validity<double>(c), invalid_reason::not_representable);
    // A float target receives p1 - p0 computed in float: one rounding of the rounded ends' difference.
    make_segment(c, {0.1, 0, 0}, {0.7, 0, 0});
    EXPECT_EQ(target_input<float>(c).direction.x, 0.7f - 0.1f);
}

TEST(SegmentOracle, AnEndOnTheSphereIsARootExactly) {
    // The unit sphere, the segment from (-3, 0, 0) to (-1, 0, 0): |-3 + 2f| = 1 at f = 1 and f = 2.
    const exact_solution s = solve_exact_segment({-3, 0, 0}, {-1, 0, 0}, {0, 0, 0}, 1, precision::binary64);
    ASSERT_EQ(s.cls, line_class::two_hit);
    EXPECT_TRUE(s.direction_is_double());
    EXPECT_EQ(s.near_root.rounded, 1.0);
    EXPECT_EQ(s.far_root.rounded, 2.0);
    EXPECT_EQ(s.compare_to_root(1.0, root_index::near_root), comparison::equal);
    EXPECT_EQ(s.hit_point(), (vec3<double>{-1, 0, 0}));
}

TEST(SegmentOracle, TheDirectionIsTheEndsExactDifference) {
    // p1 = (2^-60, 0, 0) lies on the sphere of radius 2^-60 at the origin: the
    // far root is f = 1 exactly. p1 - p0 = 2 + 2^-60 is no double; rounded to
    // 2 it would move that root to 1 + 2^-61, off the segment.
    const vec3<double> p0{-2, 0, 0}, p1{0x1p-60, 0, 0}, centre{0, 0, 0};
    const double r = 0x1p-60;
    const exact_solution s = solve_exact_segment(p0, p1, centre, r, precision::binary64);
    ASSERT_EQ(s.cls, line_class::two_hit);
    EXPECT_FALSE(s.direction_is_double());
    EXPECT_EQ(s.compare_to_root(1.0, root_index::far_root), comparison::equal);
    EXPECT_EQ(s.compare_to_root(1.0, root_index::near_root), comparison::larger);
    EXPECT_EQ(s.rounded_hit_coordinate(root_index::far_root, 0), 0x1p-60);
    // The near root (2 - 2^-60)/(2 + 2^-60) = 1 - 2^-60 + ..., below 1 by about 2^-60.
    EXPECT_EQ(s.near_root.rounded, 1.0) << "1 - 2^-60 rounds to 1 in double";
    EXPECT_EQ(s.compare_to_root(std::nextafter(1.0, 0.0), root_index::near_root), comparison::smaller)
        << "1 - 2^-53 is below the root 1 - 2^-60";
    // The ray with the rounded direction puts its far root past the end.
    const exact_solution rounded = solve_exact({p0, {2, 0, 0}, centre, r}, precision::binary64);
    EXPECT_EQ(rounded.compare_to_root(1.0, root_index::far_root), comparison::smaller);
    EXPECT_EQ(solve_exact_segment_reference(p0, p1, centre, r, precision::binary64).far_root.rounded,
              s.far_root.rounded);
}

TEST(SegmentOracle, BothRoutesAgreeOnRandomSegments) {
    const std::uint64_t seed = std::random_device{}();
    std::mt19937_64 random(seed);
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::printf("segment oracle property test: seed %llu\n", static_cast<unsigned long long>(seed));
    std::uniform_real_distribution<double> coordinate(-10, 10), radius(0.01, 5);
    std::uniform_int_distribution<int> scale(-30, 30);
    int inexact = 0;
    for (int k = 0; k < 400; ++k) {
        const double s = std::ldexp(1.0, scale(random));
        const vec3<double> p0{coordinate(random) * s, coordinate(random), coordinate(random)};
        const vec3<double> p1{coordinate(random), coordinate(random) * s, coordinate(random)};
        const vec3<double> c{coordinate(random), coordinate(random), coordinate(random)};
        const double r = radius(random) * (k % 2 ? 1 : s);
        for (precision p : every_precision) {
            const auto in = [p](const vec3<double>& v) {
                return vec3<double>{rounded_to(p, v.x), rounded_to(p, v.y), rounded_to(p, v.z)};
            };
            const exact_solution fast = solve_exact_segment(in(p0), in(p1), in(c), rounded_to(p, r), p);
            const exact_solution slow = solve_exact_segment_reference(in(p0), in(p1), in(c), rounded_to(p, r), p);
            ASSERT_EQ(fast.invalid, slow.invalid);
            if (!fast.valid()) continue;
            inexact += !fast.direction_is_double();
            ASSERT_EQ(fast.cls, slow.cls) << k;
            if (fast.cls == line_class::miss) continue;
            for (root_index i : {root_index::near_root, root_index::far_root}) {
                EXPECT_EQ(fast.root(i).sign, slow.root(i).sign) << k;
                EXPECT_EQ(fast.root(i).rounded, slow.root(i).rounded) << k;
                for (double v : {0.0, 0.5, 1.0, slow.root(i).rounded})
                    EXPECT_EQ(fast.compare_to_root(v, i), slow.compare_to_root(v, i)) << k << " at " << v;
                EXPECT_EQ(fast.root_ulp_error(i, 0.5), slow.root_ulp_error(i, 0.5)) << k;
            }
            EXPECT_EQ(fast.hit_point(), slow.hit_point()) << k;
        }
    }
    EXPECT_GT(inexact, 100) << "most random ends' differences are no doubles: the exact route was exercised";
}

// The verdict of each hand-worked case in examples/physics_segment/segments.txt.
TEST(PhysicsSegmentExample, AuditedThroughItsSegmentEntryGivesTheHandWorkedVerdicts) {
    const variant physics = load_plugin(RAYVERIFY_PHYSICS_SEGMENT_PLUGIN);
    EXPECT_TRUE(physics.promises.takes_segment_ends);
    EXPECT_EQ(format_contract(physics.promises),
              "query=nearest_hit,range=interval,ends=[],inside=clamp,tangent=hit,faces=both,unit_direction=no,"
              "cast=segment");
    const std::vector<audit_target> targets = targets_for(std::span<const variant>(&physics, 1));
    ASSERT_EQ(targets.size(), 1u);
    EXPECT_EQ(targets[0].prec, precision::binary32);
    const std::map<std::string, verdict_kind> expected = {
        {"ends_on_surface", verdict_kind::agree},
        {"ends_one_ulp_short", verdict_kind::false_hit},  // RaySphere rounds f* = 1 + 2^-24 to 1
        {"ends_one_ulp_inside", verdict_kind::agree},
        {"starts_inside", verdict_kind::agree},
        {"starts_on_surface_leaving", verdict_kind::agree},
        {"grazing_tangent", verdict_kind::agree},
        {"passing_above", verdict_kind::agree},
        {"tiny_sphere_at_end", verdict_kind::agree},
        {"zero_length", verdict_kind::invalid},
    };
    const std::vector<corpus_case> cases = read_corpus({physics_segments});
    ASSERT_EQ(cases.size(), expected.size());
    for (const corpus_case& c : cases) {
        const audited_case audited = audit_case(c, targets);
        EXPECT_EQ(verdict_name(audited.outcomes[0].score.verdict), verdict_name(expected.at(c.id))) << c.id;
    }
    // The end on the surface: contact at f = 1 exactly, the end itself (ends=[]).
    const audited_case on_surface = audit_case(cases[0], targets);
    EXPECT_EQ(on_surface.outcomes[0].output.roots.t0, 1.0);
    EXPECT_EQ(on_surface.outcomes[0].range.upper, 1.0);
}

TEST(PhysicsSegmentExample, AZeroLengthCastUnderDegenerateMissIsFound) {
    // RaySphere on p0 = p1 outside the sphere: a = 0, b = 0, so t = 0/0 and a hit with a NaN fraction.
    variant physics = load_plugin(RAYVERIFY_PHYSICS_SEGMENT_PLUGIN);
    physics.promises.degenerate_is_miss = true;
    const std::vector<audit_target> targets = targets_for(std::span<const variant>(&physics, 1));
    const std::vector<corpus_case> cases = read_corpus({physics_segments});
    const auto zero = std::find_if(cases.begin(), cases.end(), [](const corpus_case& c) { return c.id == "zero_length"; });
    ASSERT_NE(zero, cases.end());
    const audited_case audited = audit_case(*zero, targets);
    EXPECT_EQ(audited.outcomes[0].score.verdict, verdict_kind::degenerate_hit);
    EXPECT_EQ(audited.outcomes[0].output.roots.count, 1);
}

TEST(PhysicsSegmentExample, RayCasesAreNotItsQuestionAndRayTargetsTakeSegments) {
    const variant physics = load_plugin(RAYVERIFY_PHYSICS_SEGMENT_PLUGIN);
    const variant* naive = find_builtin_variant("naive");
    ASSERT_NE(naive, nullptr);
    std::vector<variant> both = {physics, *naive};
    const std::vector<audit_target> targets = targets_for(both);
    const corpus_case ray = parse_corpus("ray.txt", "r - -3 0 0 1 0 0 0 0 0 1 0 1\n", false).front();
    const audited_case on_ray = audit_case(ray, targets);
    for (std::size_t t = 0; t < targets.size(); ++t) {
        if (targets[t].subject.name == "physics_segment") {
            EXPECT_EQ(on_ray.outcomes[t].score.verdict, verdict_kind::contract_violation);
            EXPECT_NE(on_ray.outcomes[t].score.detail.find("cast=segment"), std::string::npos);
        } else {
            EXPECT_EQ(on_ray.outcomes[t].score.verdict, verdict_kind::agree) << targets[t].label();
        }
    }
    // A port whose engine takes two points gets a segment case's ends (variants.def's RAYVERIFY_SEGMENT_ENDS).
    const variant* godot = find_builtin_variant("godot");
    ASSERT_NE(godot, nullptr);
    EXPECT_TRUE(godot->takes_segment_ends && godot->segment_answer_float && godot->segment_answer_double);
    EXPECT_FALSE(naive->takes_segment_ends);
    // A ray-form target on a segment case: o = p0, d = p1 - p0, judged on f in [0, 1].
    const corpus_case segment = read_corpus({physics_segments}).front();
    const audited_case on_segment = audit_case(segment, targets);
    for (std::size_t t = 0; t < targets.size(); ++t) {
        EXPECT_EQ(on_segment.outcomes[t].score.verdict, verdict_kind::agree) << targets[t].label();
        if (targets[t].subject.name == "naive") {
            EXPECT_EQ(on_segment.outcomes[t].output.roots.t0, 1.0) << targets[t].label();
        }
    }
}

}  // namespace
}  // namespace rayverify

namespace rayverify {
namespace {

// The segment templates (C and C++, one formula) load as segment plugins in
// both precisions, answer the same on every hand-worked segment, and take
// the end on the surface exactly.
TEST(SegmentTemplates, CAndCppAnswerAlikeInBothPrecisions) {
    const variant in_c = load_plugin(RAYVERIFY_TEMPLATE_SEGMENT_C);
    const variant in_cpp = load_plugin(RAYVERIFY_TEMPLATE_SEGMENT_CPP, plugin_isolation{true, 30});
    for (const variant* v : {&in_c, &in_cpp}) {
        EXPECT_TRUE(v->promises.takes_segment_ends) << v->name;
        EXPECT_TRUE(v->runs_in(precision::binary32) && v->runs_in(precision::binary64)) << v->name;
    }
    const std::vector<variant> both = {in_c, in_cpp};
    const std::vector<audit_target> targets = targets_for(both);
    ASSERT_EQ(targets.size(), 4u);
    for (const corpus_case& c : read_corpus({physics_segments})) {
        const audited_case audited = audit_case(c, targets);
        for (std::size_t t = 0; t < targets.size(); ++t) {
            for (std::size_t u = t + 1; u < targets.size(); ++u) {
                if (targets[t].prec != targets[u].prec) continue;
                const variant_output &a = audited.outcomes[t].output, &b = audited.outcomes[u].output;
                EXPECT_EQ(audited.outcomes[t].score.verdict, audited.outcomes[u].score.verdict) << c.id;
                EXPECT_EQ(a.roots.count, b.roots.count) << c.id;
                if (a.roots.count == 1) {
                    EXPECT_EQ(a.roots.t0, b.roots.t0) << c.id;
                }
            }
        }
        if (c.id == "ends_on_surface") {
            for (const target_outcome& o : audited.outcomes) EXPECT_EQ(o.output.roots.t0, 1.0);
        }
    }
}

}  // namespace
}  // namespace rayverify

namespace rayverify {
namespace {

// The segment families do what they say, as the exact oracle sees it: ends
// exactly on the sphere (f = 1 a root), starts on it (f = 0 a root),
// zero-length casts, and differences p1 − p0 that are no double (the exact
// route) or no float.
TEST(SegmentFamilies, EndsSitOnTheSphereAndDifferencesAreMostlyInexact) {
    for (const char* family : {"segment_end", "segment_end_f32"}) {
        SCOPED_TRACE(family);
        const precision p = std::string_view(family).ends_with("_f32") ? precision::binary32 : precision::binary64;
        int end_on_sphere = 0, start_on_sphere = 0, zero_length = 0, inexact = 0, valid = 0;
        const std::vector<corpus_case> cases = generate_family(family, 300, 11);
        for (const corpus_case& c : cases) {
            ASSERT_TRUE(c.is_segment()) << c.id;
            const exact_solution s = solve_case(c, p);
            if (!s.valid()) {
                EXPECT_EQ(s.invalid, invalid_reason::zero_direction) << c.id;
                zero_length += s.invalid == invalid_reason::zero_direction;
                continue;
            }
            ++valid;
            const ray_sphere<double> input = target_input(p, c);
            const vec3<double> d = target_input(precision::binary64, c).direction;
            inexact += p == precision::binary64 ? !s.direction_is_double()
                                                : d != input.direction;  // p1 − p0 no float
            if (s.cls == line_class::miss) continue;
            const auto a_root_is = [&](double f) {
                return s.compare_to_root(f, root_index::near_root) == comparison::equal ||
                       s.compare_to_root(f, root_index::far_root) == comparison::equal;
            };
            end_on_sphere += a_root_is(1.0);
            start_on_sphere += a_root_is(0.0);
            // The two routes agree on these too.
            const vec3<double> p1 = *c.segment_end;
            const exact_solution reference =
                solve_exact_segment_reference(input.origin, p1, input.centre, input.radius, p);
            EXPECT_EQ(s.cls, reference.cls) << c.id;
            EXPECT_EQ(s.near_root.rounded, reference.near_root.rounded) << c.id;
            EXPECT_EQ(s.far_root.rounded, reference.far_root.rounded) << c.id;
        }
        EXPECT_GE(end_on_sphere, 90) << "two fifths end exactly on the sphere";
        EXPECT_GE(start_on_sphere, 25) << "three twentieths start on it";
        EXPECT_GE(zero_length, 10) << "a tenth are zero-length";
        EXPECT_GE(inexact, valid / 3) << "p1 - p0 is often no number of the precision";
    }
}

}  // namespace
}  // namespace rayverify

namespace rayverify {
namespace {

// hunt --corpus of segment cases hunts segments: it moves the end points and
// judges each candidate as the segment between them; its finds are segment
// lines. One form a hunt: rays and segments together are refused.
TEST(SegmentHunt, TheUsersSegmentsAreHuntedAsSegments) {
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / "rayverify_segment_hunt";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    const std::string out = (dir / "finds.txt").string();
    const test_support::command_result r =
        test_support::run_cli("hunt --plugin " + std::string(RAYVERIFY_PHYSICS_SEGMENT_PLUGIN) + " --corpus " +
                              physics_segments + " --objective misclass --evaluations 300 --seed 3 -o " + out);
    ASSERT_LE(r.exit_code, 1) << r.output;
    const std::vector<corpus_case> finds = read_corpus({out});
    ASSERT_FALSE(finds.empty()) << r.output << "\nRaySphere's one-ulp-short false hit is among the starts";
    for (const corpus_case& c : finds) EXPECT_TRUE(c.is_segment()) << c.id;

    const std::string mixed = (dir / "mixed.txt").string();
    std::ofstream(mixed) << "ray - -3 0 0 1 0 0 0 0 0 1\nseg - segment -3 0 0 -1 0 0 0 0 0 1\n";
    const test_support::command_result refused = test_support::run_cli(
        "hunt --variant naive --corpus " + mixed + " --evaluations 10 -o " + (dir / "none.txt").string());
    EXPECT_EQ(refused.exit_code, 2) << refused.output;
    EXPECT_NE(refused.output.find("one form of case"), std::string::npos) << refused.output;
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace rayverify
