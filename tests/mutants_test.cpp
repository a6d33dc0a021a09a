// Deliberately wrong intersectors ("mutants") that the shipped corpus and the
// exact oracle must catch, each by name and by the kind of disagreement its
// bug produces. A mutant that survives means the corpus or the judge is blind.
#include <gtest/gtest.h>

#include <cmath>

#include "compare/audit.h"
#include "corpus/corpus_io.h"

namespace rayverify {
namespace {

// Sign error: b = −2 d·f, so every root comes out negated.
template <class T>
root_pair<T> sign_error(const ray_sphere<T>& s) {
    const vec3<T> f = s.origin - s.centre;
    const T a = dot(s.direction, s.direction);
    const T b = T(-2) * dot(s.direction, f);
    const T C = dot(f, f) - s.radius * s.radius;
    const T disc = b * b - T(4) * a * C;
    if (disc < 0) return {};
    const T root = std::sqrt(disc);
    return {disc == 0 ? 1 : 2, (-b - root) / (T(2) * a), (-b + root) / (T(2) * a)};
}

// Dropped factor: Δ = b² − aC instead of b² − 4aC (the half-b formula with a full b).
template <class T>
root_pair<T> dropped_factor_four(const ray_sphere<T>& s) {
    const vec3<T> f = s.origin - s.centre;
    const T a = dot(s.direction, s.direction);
    const T b = T(2) * dot(s.direction, f);
    const T C = dot(f, f) - s.radius * s.radius;
    const T disc = b * b - a * C;
    if (disc < 0) return {};
    const T root = std::sqrt(disc);
    return {disc == 0 ? 1 : 2, (-b - root) / (T(2) * a), (-b + root) / (T(2) * a)};
}

// Wrong root chosen: the early-out nearest-hit test returning −b + √Δ (the far root).
template <class T>
root_pair<T> far_root_as_nearest(const ray_sphere<T>& s) {
    const vec3<T> v = s.origin - s.centre;
    const T b = dot(v, s.direction);
    const T C = dot(v, v) - s.radius * s.radius;
    if (C > 0 && b > 0) return {};
    const T disc = b * b - C;
    if (disc < 0) return {};
    T t = -b + std::sqrt(disc);
    if (t < 0) t = 0;
    return {1, t, t};
}

// Radius not squared: C = f·f − r.
template <class T>
root_pair<T> radius_not_squared(const ray_sphere<T>& s) {
    const vec3<T> f = s.origin - s.centre;
    const T a = dot(s.direction, s.direction);
    const T b = T(2) * dot(s.direction, f);
    const T C = dot(f, f) - s.radius;
    const T disc = b * b - T(4) * a * C;
    if (disc < 0) return {};
    const T root = std::sqrt(disc);
    return {disc == 0 ? 1 : 2, (-b - root) / (T(2) * a), (-b + root) / (T(2) * a)};
}

// Absolute epsilon: anything with Δ > −1e-6 counts as a (grazing) hit.
template <class T>
root_pair<T> absolute_epsilon(const ray_sphere<T>& s) {
    const vec3<T> f = s.origin - s.centre;
    const T a = dot(s.direction, s.direction);
    const T b = T(2) * dot(s.direction, f);
    const T C = dot(f, f) - s.radius * s.radius;
    const T disc = b * b - T(4) * a * C;
    if (disc < T(-1e-6)) return {};
    const T root = std::sqrt(std::fmax(disc, T(0)));
    return {disc <= T(1e-6) ? 1 : 2, (-b - root) / (T(2) * a), (-b + root) / (T(2) * a)};
}

// Roots returned in the wrong order (far first).
template <class T>
root_pair<T> swapped_roots(const ray_sphere<T>& s) {
    const vec3<T> f = s.origin - s.centre;
    const T a = dot(s.direction, s.direction);
    const T b = T(2) * dot(s.direction, f);
    const T C = dot(f, f) - s.radius * s.radius;
    const T disc = b * b - T(4) * a * C;
    if (disc < 0) return {};
    const T root = std::sqrt(disc);
    return {disc == 0 ? 1 : 2, (-b + root) / (T(2) * a), (-b - root) / (T(2) * a)};
}

struct mutant_case {
    variant subject;
    verdict_kind expected;  // a verdict its bug must produce on the shipped corpus
};

const contract line_roots_any_direction{.query = query_kind::line_roots, .reports_tangent = true};
const contract nearest_clamped{
    .query = query_kind::nearest_on_ray, .assumes_unit_direction = true, .clamps_to_zero = true};

#define MUTANT(name, promises, expected) \
    mutant_case { variant{#name, "mutant", "", promises, &name<float>, &name<double>}, expected }

const mutant_case mutants[] = {
    MUTANT(sign_error, line_roots_any_direction, verdict_kind::wrong_side),
    MUTANT(dropped_factor_four, line_roots_any_direction, verdict_kind::false_hit),
    MUTANT(far_root_as_nearest, nearest_clamped, verdict_kind::wrong_root),
    MUTANT(radius_not_squared, line_roots_any_direction, verdict_kind::false_miss),
    MUTANT(absolute_epsilon, line_roots_any_direction, verdict_kind::false_hit),
    MUTANT(swapped_roots, line_roots_any_direction, verdict_kind::malformed_output),
};

const std::vector<corpus_case>& shipped_corpus() {
    static const std::vector<corpus_case> cases = read_corpus({RAYVERIFY_CORPUS_DIR});
    return cases;
}

class MutantIsKilled : public testing::TestWithParam<mutant_case> {};

TEST_P(MutantIsKilled, InBothPrecisions) {
    const mutant_case& m = GetParam();
    const std::vector<variant> subjects{m.subject};
    const audit_totals totals = run_audit(shipped_corpus(), targets_for(subjects));
    ASSERT_EQ(totals.targets.size(), 2u);
    for (std::size_t i = 0; i < totals.targets.size(); ++i) {
        SCOPED_TRACE(totals.targets[i].label());
        const target_tally& tally = totals.overall[i];
        EXPECT_GT(tally.disagreements(), 0u) << "mutant survived the shipped corpus";
        EXPECT_GT(tally.verdicts[static_cast<int>(m.expected)], 0u)
            << "expected its bug to show as " << verdict_name(m.expected);
    }
}

INSTANTIATE_TEST_SUITE_P(ShippedCorpus, MutantIsKilled, testing::ValuesIn(mutants),
                         [](const testing::TestParamInfo<mutant_case>& info) { return info.param.subject.name; });

}  // namespace
}  // namespace rayverify
