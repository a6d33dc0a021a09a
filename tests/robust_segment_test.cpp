// robust_sphere.h's segment query (segment_hit, issue 47): a physics
// engine's cast from p0 to p1, answered for the segment as given (p1 − p0
// never rounded), the fraction correctly rounded, both ends and the start
// rule decided exactly. Hand-worked segments through the header itself, then
// the query built as a user's C++17 plugin by gcc and clang (contact at the
// start with closed ends; the exit with open ends) and called from a
// -ffast-math C caller through robust_sphere_c.h, each audited through the
// CLI on the shipped segment corpus, the physics example's hand cases and
// generated segment families, and the rays of the shipped corpus and of
// corpus/edge cast as segments: no disagreement with the exact answer.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "core/intersection.h"
#include "corpus/corpus_io.h"
#include "robust_sphere.h"
#include "support/process.h"

namespace rayverify {
namespace {

namespace rs = robust_sphere;
using rs::ends;
using rs::start_inside;

template <class T>
rs::ray_hit<T> closed_contact(rs::vec3<T> p0, rs::vec3<T> p1, rs::vec3<T> c, T r) {
    return rs::segment_hit(rs::segment<T>{p0, p1}, rs::sphere<T>{c, r});
}

TEST(RobustSegment, HandWorkedSegments) {
    const rs::vec3<double> origin{0, 0, 0};
    // p1 exactly on the unit sphere: the contact is the end itself, f = 1.
    rs::ray_hit<double> h = closed_contact<double>({-3, 0, 0}, {-1, 0, 0}, origin, 1);
    EXPECT_TRUE(h.found);
    EXPECT_EQ(h.t, 1.0);
    // ... which an open end excludes.
    h = rs::segment_hit<ends::closed, ends::open>(rs::segment<double>{{-3, 0, 0}, {-1, 0, 0}},
                                                   rs::sphere<double>{origin, 1});
    EXPECT_FALSE(h.found);
    // p1 one float ulp short of the surface: the segment stops before it.
    const rs::ray_hit<float> short_f = closed_contact<float>({-3, 0, 0}, {-0x1.000002p+0f, 0, 0}, {0, 0, 0}, 1);
    EXPECT_FALSE(short_f.found);
    // p1 = 2^-60 on the sphere of radius 2^-60 at the origin, p0 = -2: p1 − p0 = 2 + 2^-60 is no double;
    // rounded, the root would be 1 + 2^-61, past the end. The segment's own contact is f = 1.
    h = closed_contact<double>({-2, 0, 0}, {0x1p-60, 0, 0}, origin, 0x1p-60);
    EXPECT_TRUE(h.found);
    EXPECT_EQ(h.t, 1.0);
    // Starting inside: a contact at the start, or the exit at f = 1/5 (rounded).
    h = closed_contact<double>({0, 0, 0}, {5, 0, 0}, origin, 1);
    EXPECT_TRUE(h.found);
    EXPECT_EQ(h.t, 0.0);
    h = rs::segment_hit<ends::closed, ends::closed, start_inside::exit>(rs::segment<double>{{0, 0, 0}, {5, 0, 0}},
                                                                          rs::sphere<double>{origin, 1});
    EXPECT_TRUE(h.found);
    EXPECT_EQ(h.t, 0.2);
    EXPECT_EQ(h.which, rs::root::far_root);
    // Starting on the surface, leaving it: the root f = 0 is the start, which an open start excludes.
    h = closed_contact<double>({1, 0, 0}, {3, 0, 0}, origin, 1);
    EXPECT_TRUE(h.found);
    EXPECT_EQ(h.t, 0.0);
    h = rs::segment_hit<ends::open, ends::closed>(rs::segment<double>{{1, 0, 0}, {3, 0, 0}},
                                                   rs::sphere<double>{origin, 1});
    EXPECT_FALSE(h.found);
    // Grazing: tangent at (0, 1, 0), f = 1/2 exactly.
    h = closed_contact<double>({-2, 1, 0}, {2, 1, 0}, origin, 1);
    EXPECT_TRUE(h.found);
    EXPECT_EQ(h.t, 0.5);
    // A difference beyond the double range (2·10^308), taken exactly: the contact just before the middle.
    h = closed_contact<double>({-1e308, 0, 0}, {1e308, 0, 0}, origin, 1);
    EXPECT_TRUE(h.found);
    EXPECT_EQ(h.t, 0.5);  // 1/2 − 1/(2·10^308) rounds to 1/2
    // ... and beyond the float range (6·10^38 > FLT_MAX): the same in float.
    const rs::ray_hit<float> wide_f = closed_contact<float>({-3e38f, 0, 0}, {3e38f, 0, 0}, {0, 0, 0}, 1);
    EXPECT_TRUE(wide_f.found);
    EXPECT_EQ(wide_f.t, 0.5f);
    // At the double-word stage's range edge, p1 − p0 = 2^160 + 2^-160 no double: from −2^160 to the far
    // side of the sphere of radius 2^-160 at the origin, the contact at f = (1 − 2^-320)/(1 + 2^-320),
    // which rounds to 1; an open end excludes 1 itself, and the contact is answered one ulp inside it.
    const rs::segment<double> edge{{-0x1p160, 0, 0}, {0x1p-160, 0, 0}};
    const rs::sphere<double> tiny{origin, 0x1p-160};
    h = rs::segment_hit(edge, tiny);
    EXPECT_TRUE(h.found);
    EXPECT_EQ(h.t, 1.0);
    h = rs::segment_hit<ends::closed, ends::open>(edge, tiny);
    EXPECT_TRUE(h.found);
    EXPECT_EQ(h.t, 1.0 - 0x1p-53);
    // A segment of one grid step 2^-212 ending exactly on the sphere of radius 2^-160 at the origin: f = 1.
    h = closed_contact<double>({-0x1p-160 - 0x1p-212, 0, 0}, {-0x1p-160, 0, 0}, origin, 0x1p-160);
    EXPECT_TRUE(h.found);
    EXPECT_EQ(h.t, 1.0);
    // Zero length, and non-finite inputs: no geometry, a miss.
    EXPECT_FALSE((closed_contact<double>({0, 0, 2}, {0, 0, 2}, origin, 1).found));
    EXPECT_FALSE((closed_contact<double>({0, 0, 0}, {0, 0, 2}, origin, std::nan("")).found));
    EXPECT_FALSE((closed_contact<float>({0, 0, 0}, {INFINITY, 0, 0}, {0, 0, 0}, 1).found));
}

std::vector<std::string> segment_plugins() {
    std::vector<std::string> paths;
    std::istringstream list(RAYVERIFY_ROBUST_SEGMENT_PLUGINS);
    for (std::string path; std::getline(list, path, ':');) paths.push_back(path);
    return paths;
}

// Every target of the audit disagrees on no case.
void expect_no_disagreement(const std::string& input, const char* scratch_name) {
    test_support::scratch_directory scratch(scratch_name);
    std::string arguments = "audit " + input + " --report " + scratch.path().string() + " --threads 2";
    for (const std::string& p : segment_plugins()) arguments += " --plugin " + p;
    const test_support::command_result ran = test_support::run_cli(arguments);
    ASSERT_EQ(ran.exit_code, 0) << ran.output;  // 0: no target disagrees, every target scored cases
    const nlohmann::json report = nlohmann::json::parse(test_support::read_text(scratch.path() / "report.json"));
    std::size_t targets = 0;
    for (const nlohmann::json& r : report["results"]) {
        ++targets;
        SCOPED_TRACE(r["variant"].get<std::string>() + "/" + r["precision"].get<std::string>());
        EXPECT_EQ(r["disagreements"], 0);
        EXPECT_GT(r["verdicts"]["agree"].get<std::size_t>(), 0u);
    }
    EXPECT_EQ(targets, 2 * segment_plugins().size());
}

TEST(RobustSegment, ShippedSegmentsAndTheExampleAsAuditedPlugins) {
    expect_no_disagreement("--corpus " RAYVERIFY_CORPUS_DIR "/segments --corpus " RAYVERIFY_SOURCE_DIR
                           "/examples/physics_segment/segments.txt",
                           "robust_segment_shipped");
}

TEST(RobustSegment, GeneratedSegmentFamiliesAsAuditedPlugins) {
    expect_no_disagreement("--generate segment_end:4000:23 --generate segment_end_f32:4000:23", "robust_segment_generated");
}

// The rays of the shipped corpus and corpus/edge as the segments an engine
// casts along them: to o + L·d (past every root), to o + t0·d rounded (an end
// on or next to the surface, t0 the near root), and over the case's own
// interval where it has one; p1 − p0 in general no double.
TEST(RobustSegment, CorpusAndEdgeRaysAsSegmentsAsAuditedPlugins) {
    std::vector<corpus_case> segments;
    for (const corpus_case& c : read_corpus({RAYVERIFY_CORPUS_DIR, RAYVERIFY_CORPUS_DIR "/edge"})) {
        if (c.is_segment()) continue;
        const ray_sphere<double>& g = c.geometry;
        const auto add = [&](const char* suffix, double from, double to) {
            const vec3<double> p0 = g.origin + from * g.direction, p1 = g.origin + to * g.direction;
            for (int axis = 0; axis < 3; ++axis)
                if (!std::isfinite(p0[axis]) || !std::isfinite(p1[axis])) return;
            if (p0 == p1) return;
            corpus_case s = c;
            s.id = c.id + suffix;
            make_segment(s, p0, p1);
            segments.push_back(std::move(s));
        };
        if (validity<double>(g) != invalid_reason::none) continue;
        add("_to_far", 0, static_cast<double>(segment_length(g)));
        const rs::line_roots<double> roots =
            rs::intersect_line(rs::ray<double>{{g.origin.x, g.origin.y, g.origin.z}, {g.direction.x, g.direction.y, g.direction.z}},
                               rs::sphere<double>{{g.centre.x, g.centre.y, g.centre.z}, g.radius});
        if (roots.count > 0 && roots.t0 > 0) add("_to_surface", 0, roots.t0);
        if (c.tmin && c.tmax && std::isfinite(*c.tmin) && std::isfinite(*c.tmax)) add("_interval", *c.tmin, *c.tmax);
    }
    ASSERT_GT(segments.size(), 5000u);
    std::printf("%zu segments from the rays of corpus and corpus/edge\n", segments.size());
    test_support::scratch_directory scratch("robust_segment_from_rays");
    const std::filesystem::path file = scratch.path() / "segments.txt";
    write_corpus_file(file, segments, {"the shipped corpus's and corpus/edge's rays as segments"});
    expect_no_disagreement("--corpus " + file.string(), "robust_segment_from_rays_audit");
}

}  // namespace
}  // namespace rayverify
