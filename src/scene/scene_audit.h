// Auditing a scene: each ray the renderer casts is answered exactly (over all
// the spheres it can meet, by the oracle) and by each variant, and the two
// answers are compared at the level the ray's query needs:
//   any_hit          — only whether something lies in (tmin, tmax);
//   nearest_hit      — which sphere is nearest in (tmin, tmax), and the ULP
//                      error of that root;
//   hit_point_normal — as nearest_hit, plus the ULP error of the hit point
//                      o + t·d the variant's root gives (in its precision);
//   both_roots       — each (ray, sphere) pair judged by score_case on the
//                      line's two roots, with both roots' ULP errors.
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
#include "compare/query.h"
#include "intersectors/registry.h"
#include "oracle/oracle.h"
#include "scene/scene.h"

namespace rayverify {

// How a variant's answer to one ray differs from the exact one.
enum class ray_verdict {
    agree,
    false_miss,    // exact: a hit in the interval; variant: none
    false_hit,     // exact: none; variant: a hit
    wrong_sphere,  // both hit, but a different sphere is nearest
    wrong_side,    // a root's side of tmin or tmax differs: a self-hit, or a hit lost behind the bound
    wrong_root,    // the variant's nearest is the other root of the same sphere
    other,         // both_roots only: a tangent, non-finite or malformed pair verdict
};
inline constexpr int ray_verdict_count = 7;
std::string_view ray_verdict_name(ray_verdict v);
std::string_view ray_verdict_meaning(ray_verdict v);

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
    ray_verdict verdict = ray_verdict::agree;
    bool hit = false;
    int sphere = -1;
    double t = 0;
    std::optional<double> nearest_ulp;    // |t − t*| / ulp(t*) when the verdict is agree
    std::optional<double> far_ulp;        // both_roots only
    std::optional<double> hit_point_ulp;  // hit_point_normal only: max over the coordinates
    std::string detail;                   // both_roots: the pair verdict behind `other`
};

struct judged_ray {
    const scene_ray* ray = nullptr;
    exact_ray_answer exact;
    std::vector<variant_ray_answer> answers;  // aligned with the targets; empty entries for not applicable
};

// The figures of one ray kind for one target: only those its query needs.
struct ray_kind_figures {
    std::size_t rays = 0;
    std::array<std::size_t, ray_verdict_count> verdicts{};
    error_statistics nearest_ulp;    // nearest_hit, hit_point_normal, both_roots
    error_statistics far_ulp;        // both_roots only
    error_statistics hit_point_ulp;  // hit_point_normal only
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

// Judge every ray. `on_ray` sees each judged ray in order (for pictures).
scene_audit_result audit_scene(const scene& s, std::span<const scene_ray> rays,
                               const std::vector<audit_target>& targets,
                               const std::function<void(const judged_ray&)>& on_ray = {});

}  // namespace rayverify
