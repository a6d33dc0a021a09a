// Auditing a scene: each ray the renderer casts is answered exactly (over all
// the spheres it can meet, by the oracle) and by each variant, and the two
// answers are compared at the level the ray's query needs. Each (ray, sphere)
// pair is judged by the one judge in the renderer's view (judge_for_renderer:
// the variant's answer filtered into the ray's (tmin, tmax)); this file only
// composes the pairs into the ray's answer:
//   any_hit          — only whether something lies in (tmin, tmax);
//   nearest_hit      — which sphere is nearest in (tmin, tmax) (exact roots of
//                      different spheres compared exactly), and the ULP error
//                      of that root;
//   hit_point_normal — as nearest_hit, plus the ULP error of the hit point
//                      o + t·d the variant's root gives (in its precision);
//   both_roots       — each (ray, sphere) pair judged on the line's two roots;
//                      the ray takes the first pair's disagreement.
// Pure computation: the CLI prints and renders what this returns.
#pragma once

#include <array>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "compare/audit.h"
#include "compare/judge.h"
#include "intersectors/registry.h"
#include "oracle/oracle.h"
#include "scene/scene.h"

namespace rayverify {

// The exact answer to one ray (its nearest hit over its spheres, in the
// interval), with what a picture needs.
struct exact_ray_answer {
    bool hit = false;
    int sphere = -1;
    root_index root = root_index::near_root;
    double t = 0;             // the root, correctly rounded to the scene's precision
    vec3<double> normal{};    // outward unit normal at the (rounded) hit point
    bool lost_to_tmin = false;  // a root lies in (0, tmin]: a hit the ray's epsilon discards
};

// One variant's answer to one ray and its verdict.
struct variant_ray_answer {
    verdict_kind verdict = verdict_kind::agree;
    std::optional<disagreement_cause> cause;  // for a disagreement
    bool hit = false;
    int sphere = -1;
    double t = 0;
    std::optional<double> nearest_ulp;    // |t − t*| / ulp(t*) when the verdict is agree
    std::optional<double> far_ulp;        // both_roots only
    std::optional<double> hit_point_ulp;  // hit_point_normal only: max over the coordinates
    std::string detail;                   // for a disagreement: the sphere and what the judge found there
};

struct judged_ray {
    const scene_ray* ray = nullptr;
    exact_ray_answer exact;
    std::vector<variant_ray_answer> answers;  // aligned with the targets; empty entries for not applicable
};

// The figures of one ray kind for one target: only those its query needs.
struct ray_kind_figures {
    std::size_t rays = 0;
    std::array<std::size_t, verdict_kind_count> verdicts{};
    std::array<std::size_t, disagreement_cause_count> causes{};  // of the disagreements
    error_summary nearest_ulp;    // nearest_hit, hit_point_normal, both_roots
    error_summary far_ulp;        // both_roots only
    error_summary hit_point_ulp;  // hit_point_normal only
    std::size_t disagreements() const;
};

struct scene_target_figures {
    audit_target target;
    std::optional<std::string> not_applicable;  // why the scene breaks its contract
    std::array<ray_kind_figures, 3> by_kind;    // indexed by ray_kind
    std::size_t disagreements() const;
};

// The exact side of each ray kind: how many rays, exact hits, hits lost to tmin.
struct exact_kind_figures {
    std::size_t rays = 0, hits = 0, lost_to_tmin = 0;
};

struct scene_audit_result {
    std::size_t pixels = 0;
    std::size_t pairs = 0;  // (ray, sphere) pairs audited
    std::array<exact_kind_figures, 3> exact;
    std::vector<scene_target_figures> targets;
};

// Every variant of `variants` in the scene's precision (a variant that does
// not run in it is left out).
std::vector<audit_target> scene_targets(const scene& s, std::span<const variant> variants);

// Why a target cannot answer the scene's queries, or nothing: a unit-direction
// formula on unnormalised rays; a nearest-only variant where both roots are
// needed; a variant that does not run in the scene's precision.
std::optional<std::string> not_applicable_reason(const scene& s, const audit_target& t);

// Judges rays one at a time, as for_each_ray streams them: memory is the
// figures (bounded accumulators), whatever the number of rays. Each ray's
// spheres are solved on `route` (the rays themselves are the scene's, spawned
// as for_each_ray makes them).
class scene_auditor {
public:
    scene_auditor(const scene& s, const std::vector<audit_target>& targets,
                  oracle_route route = oracle_route::filtered);
    // Judge one ray; `on_ray` (if given) sees it judged (for pictures).
    void judge(const scene_ray& r, const std::function<void(const judged_ray&)>& on_ray = {});
    const scene_audit_result& result() const { return result_; }

private:
    const scene& scene_;
    const std::vector<audit_target>& targets_;
    std::vector<std::optional<std::string>> skip_;  // why a target is not applicable
    scene_audit_result result_;
    std::size_t ray_index_ = 0;
    oracle_route route_;
};

// Judge every ray the scene casts, streamed. `on_ray` sees each judged ray in
// order (for pictures).
scene_audit_result audit_scene(const scene& s, const std::vector<audit_target>& targets,
                               const std::function<void(const judged_ray&)>& on_ray = {},
                               oracle_route route = oracle_route::filtered);

// Judge the given rays (a scene's, or some of them).
scene_audit_result audit_scene(const scene& s, std::span<const scene_ray> rays,
                               const std::vector<audit_target>& targets,
                               const std::function<void(const judged_ray&)>& on_ray = {});

}  // namespace rayverify
