// `rayverify recommend`: for one scene, the cheapest variant that is accurate
// enough on the scene's own rays. Each ray kind the scene casts (primary,
// shadow, secondary) is decided apart, since a renderer may use a different
// intersector for each: a shadow ray only asks "anything in (tmin, tmax)?".
//
// For each kind, every variant that can answer its query (compare/judge.h
// `applicable`) in the scene's precision is
//   - audited on exactly those rays (scene/scene_audit.h: each ray against
//     every sphere it can meet, judged at the level of its query), and
//   - timed on them (bench/timing.h, Google Benchmark, median over
//     repetitions): one pass casts every ray of the kind as a renderer would,
//     the intersector inlined into the loop (kernels.h), the ray's interval
//     shrunk to the nearest hit so far, an any-hit ray stopping at its first
//     hit, roots of line-roots variants filtered into the interval.
// The cheapest (median ns per ray) that meets the budget wins; the runner-up
// is the next cheapest that meets it. When the budget allows no wrong ray, a
// variant whose decisions are exact by construction (variant::exact_decisions,
// robust_sphere.h) wins if it meets the budget, however cheaper the others
// are: a variant without wrong rays on this scene's rays may still have them
// on the next frame's; the cheapest other one is then the runner-up.
// Measuring and deciding only: the CLI prints what this returns.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "bench/timing.h"
#include "intersectors/registry.h"
#include "scene/scene.h"

namespace rayverify::bench {

// What "accurate enough" means. Default: no wrong ray (every ray's answer
// agrees with the exact one at the level of its query) and the nearest root
// (and, for both_roots, the far root) within 4 ulp on every agreeing ray.
struct recommend_budget {
    std::size_t max_wrong = 0;
    double max_ulp = 4;
    std::string describe() const;
};

// Parse "max-ulp=4", "max-wrong=0" or both, comma separated. Throws
// input_error (field "--budget") naming the bad part.
recommend_budget parse_budget(const std::string& text);

struct recommend_candidate {
    std::string variant;
    std::optional<std::string> not_applicable;  // why it cannot answer this kind's query
    double ns_per_ray = 0;                       // median CPU time over repetitions
    double ns_min = 0, ns_max = 0;               // over repetitions
    std::size_t rays = 0;
    std::size_t wrong = 0;                       // rays whose verdict is not agree
    std::size_t false_miss = 0, false_hit = 0;   // of them
    std::optional<double> max_ulp;               // largest root error over agreeing rays (none for any_hit)
    std::string max_ulp_ray;                     // the ray attaining it
    bool meets_budget = false;
    bool exact_decisions = false;                // variant::exact_decisions
    std::string verdict;                         // "meets the budget" or why not
};

struct kind_recommendation {
    ray_kind kind = ray_kind::primary;
    ray_query query = ray_query::nearest_hit;
    std::size_t rays = 0;
    std::vector<recommend_candidate> candidates;  // applicable ones by time, then the others
    std::optional<std::size_t> winner, runner_up;  // indices into candidates
};

struct recommendation {
    std::string scene_name;
    precision prec = precision::binary64;
    bool normalised = false;
    recommend_budget budget;
    std::vector<kind_recommendation> kinds;  // the kinds the scene casts, in ray_kind order
    bool all_met() const;                    // every kind has a winner
};

// Decide for every ray kind of `s`, over `variants` (the built-ins timed
// inlined; any other variant, e.g. a plugin, through its function). `rays`
// must be generate_rays(s).
recommendation recommend(const scene& s, std::span<const scene_ray> rays, std::span<const variant> variants,
                         const recommend_budget& budget, const timing_options& timing);

}  // namespace rayverify::bench
