// Deliberately wrong intersectors ("mutants") that the shipped corpus and the
// exact oracle must catch, each by name and by the kind of disagreement its
// bug produces. A mutant is killed when on some shipped case it disagrees
// with the exact answer while the correct code it mutates (its parent)
// agrees; the kill rate is printed and must be 100%. A mutant that survives
// means the corpus or the judge is blind.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <ostream>
#include <span>
#include <cstdio>
#include <iterator>
#include <map>
#include <stdexcept>
#include <string>

#include "compare/audit.h"
#include "corpus/corpus_io.h"
#include "intersectors/registry.h"
#include "intersectors/seed004_early_out.h"
#include "intersectors/stable_roots.h"

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

// Dropped factor 2 in the denominator: t = (−b ∓ √Δ)/a, every root doubled.
template <class T>
root_pair<T> dropped_factor_two(const ray_sphere<T>& s) {
    const vec3<T> f = s.origin - s.centre;
    const T a = dot(s.direction, s.direction);
    const T b = T(2) * dot(s.direction, f);
    const T C = dot(f, f) - s.radius * s.radius;
    const T disc = b * b - T(4) * a * C;
    if (disc < 0) return {};
    const T root = std::sqrt(disc);
    return {disc == 0 ? 1 : 2, (-b - root) / a, (-b + root) / a};
}

// Wrong sign in the discriminant: Δ = b² + 4aC, so spheres ahead of a miss are hit.
template <class T>
root_pair<T> discriminant_sign(const ray_sphere<T>& s) {
    const vec3<T> f = s.origin - s.centre;
    const T a = dot(s.direction, s.direction);
    const T b = T(2) * dot(s.direction, f);
    const T C = dot(f, f) - s.radius * s.radius;
    const T disc = b * b + T(4) * a * C;
    if (disc < 0) return {};
    const T root = std::sqrt(disc);
    return {disc == 0 ? 1 : 2, (-b - root) / (T(2) * a), (-b + root) / (T(2) * a)};
}

// Wrong sign of r²: C = f·f + r², a sphere turned inside out.
template <class T>
root_pair<T> radius_sign(const ray_sphere<T>& s) {
    const vec3<T> f = s.origin - s.centre;
    const T a = dot(s.direction, s.direction);
    const T b = T(2) * dot(s.direction, f);
    const T C = dot(f, f) + s.radius * s.radius;
    const T disc = b * b - T(4) * a * C;
    if (disc < 0) return {};
    const T root = std::sqrt(disc);
    return {disc == 0 ? 1 : 2, (-b - root) / (T(2) * a), (-b + root) / (T(2) * a)};
}

// Wrong root: the near root returned for both.
template <class T>
root_pair<T> near_root_twice(const ray_sphere<T>& s) {
    const vec3<T> f = s.origin - s.centre;
    const T a = dot(s.direction, s.direction);
    const T b = T(2) * dot(s.direction, f);
    const T C = dot(f, f) - s.radius * s.radius;
    const T disc = b * b - T(4) * a * C;
    if (disc < 0) return {};
    const T t = (-b - std::sqrt(disc)) / (T(2) * a);
    return {disc == 0 ? 1 : 2, t, t};
}

// Float accumulation: the double variant computes everything in float (a
// float temporary in the middle of double code), as naive<float> does.
template <class T>
root_pair<T> float_accumulation(const ray_sphere<T>& s) {
    const ray_sphere<float> g = rounded_to<float>(s);
    const vec3<float> f = g.origin - g.centre;
    const float a = dot(g.direction, g.direction);
    const float b = 2.0f * dot(g.direction, f);
    const float C = dot(f, f) - g.radius * g.radius;
    const float disc = b * b - 4.0f * a * C;
    if (disc < 0) return {};
    const float root = std::sqrt(disc);
    return {disc == 0 ? 1 : 2, static_cast<T>((-b - root) / (2.0f * a)), static_cast<T>((-b + root) / (2.0f * a))};
}

// The textbook nearest hit on the ray t > 0 (not clamped): the parent of the next mutant.
template <class T>
root_pair<T> nearest_hit(const ray_sphere<T>& s) {
    const root_pair<T> line = intersectors::stable_roots(s);
    if (line.count == 0) return {};
    if (line.t0 > 0) return {1, line.t0, line.t0};
    if (line.t1 > 0) return {1, line.t1, line.t1};
    return {};
}

// Absolute epsilon on t: hits nearer than 1e-4 are skipped (the usual
// self-intersection fudge), whatever the scene's scale.
template <class T>
root_pair<T> absolute_epsilon_t(const ray_sphere<T>& s) {
    const root_pair<T> line = intersectors::stable_roots(s);
    if (line.count == 0) return {};
    if (line.t0 > T(1e-4)) return {1, line.t0, line.t0};
    if (line.t1 > T(1e-4)) return {1, line.t1, line.t1};
    return {};
}

// A mutant, the correct code it mutates, and the verdict its bug must produce.
struct mutant_case {
    variant subject;
    verdict_kind expected;  // a verdict its bug must produce on the shipped corpus
    std::string parent;     // the correct variant it mutates
};

const contract line_roots_any_direction{.query = query_kind::line_roots, .reports_tangent = true};
const contract nearest_clamped = intersectors::seed004_early_out_contract;
// The nearest hit on the open ray t > 0, any direction length.
const contract nearest_any_direction{.query = query_kind::nearest_hit};

#define MUTANT(name, promises, expected, parent) \
    mutant_case { variant{#name, "mutant", "", promises, &name<float>, &name<double>}, expected, parent }

const mutant_case mutants[] = {
    MUTANT(sign_error, line_roots_any_direction, verdict_kind::wrong_side, "naive"),
    MUTANT(dropped_factor_four, line_roots_any_direction, verdict_kind::false_hit, "naive"),
    MUTANT(dropped_factor_two, line_roots_any_direction, verdict_kind::wrong_root, "naive"),
    MUTANT(discriminant_sign, line_roots_any_direction, verdict_kind::false_hit, "naive"),
    MUTANT(radius_sign, line_roots_any_direction, verdict_kind::false_miss, "naive"),
    MUTANT(radius_not_squared, line_roots_any_direction, verdict_kind::false_miss, "naive"),
    MUTANT(far_root_as_nearest, nearest_clamped, verdict_kind::wrong_root, "seed004_early_out"),
    MUTANT(near_root_twice, line_roots_any_direction, verdict_kind::false_tangent, "naive"),
    MUTANT(swapped_roots, line_roots_any_direction, verdict_kind::malformed_output, "naive"),
    MUTANT(float_accumulation, line_roots_any_direction, verdict_kind::false_miss, "naive"),
    MUTANT(absolute_epsilon, line_roots_any_direction, verdict_kind::false_hit, "naive"),
    MUTANT(absolute_epsilon_t, nearest_any_direction, verdict_kind::wrong_root, "nearest_hit"),
};

const variant nearest_hit_parent{"nearest_hit", "test", "", nearest_any_direction, &nearest_hit<float>,
                                 &nearest_hit<double>};

const std::vector<corpus_case>& shipped_corpus() {
    static const std::vector<corpus_case> cases = read_corpus({RAYVERIFY_CORPUS_DIR});
    return cases;
}

// How one mutant fared in one precision against its parent on the shipped corpus.
struct precision_outcome {
    std::size_t disagreements = 0;
    std::size_t expected_verdicts = 0;  // cases showing the verdict its bug should produce
    std::size_t caught = 0;             // cases where the mutant disagrees and its parent agrees
    std::string first_caught;           // id of the first such case
    std::array<std::size_t, verdict_kind_count> verdicts{};
};

struct mutant_outcome {
    precision_outcome at[2];  // float, double
    bool killed() const { return at[0].caught + at[1].caught > 0; }
    // The disagreement it shows most often, over both precisions.
    verdict_kind main_verdict() const {
        verdict_kind best = verdict_kind::agree;
        std::size_t most = 0;
        for (int k = 0; k < verdict_kind_count; ++k) {
            const std::size_t n = at[0].verdicts[k] + at[1].verdicts[k];
            if (is_disagreement(static_cast<verdict_kind>(k)) && n > most) best = static_cast<verdict_kind>(k), most = n;
        }
        return best;
    }
};

// One audit over the shipped corpus of the given mutants and their parents.
std::map<std::string, mutant_outcome> outcomes_of(std::span<const mutant_case> chosen) {
    std::vector<variant> subjects;
    for (const mutant_case& m : chosen) subjects.push_back(m.subject);
    for (const mutant_case& m : chosen) {
        const bool listed = std::any_of(subjects.begin(), subjects.end(),
                                        [&](const variant& v) { return v.name == m.parent; });
        if (!listed)
            subjects.push_back(m.parent == nearest_hit_parent.name ? nearest_hit_parent
                                                                   : *find_builtin_variant(m.parent));
    }
    const std::vector<audit_target> targets = targets_for(subjects);
    const auto index_of = [&](const std::string& name, precision p) {
        for (std::size_t i = 0; i < targets.size(); ++i)
            if (targets[i].subject.name == name && targets[i].prec == p) return i;
        throw std::logic_error("no target " + name);
    };
    std::map<std::string, mutant_outcome> out;
    run_audit(shipped_corpus(), targets, [&](const audited_case& c) {
        for (const mutant_case& m : chosen)
            for (precision p : {precision::binary32, precision::binary64}) {
                precision_outcome& o = out[m.subject.name].at[p == precision::binary32 ? 0 : 1];
                const verdict_kind mine = c.outcomes[index_of(m.subject.name, p)].score.verdict;
                const verdict_kind parents = c.outcomes[index_of(m.parent, p)].score.verdict;
                o.disagreements += is_disagreement(mine);
                ++o.verdicts[static_cast<int>(mine)];
                o.expected_verdicts += mine == m.expected;
                if (is_disagreement(mine) && parents == verdict_kind::agree && o.caught++ == 0)
                    o.first_caught = c.source->id;
            }
    });
    return out;
}

void PrintTo(const mutant_case& m, std::ostream* out) { *out << m.subject.name; }

class MutantIsKilled : public testing::TestWithParam<mutant_case> {};

// Killed: on some shipped case the mutant disagrees with the exact answer
// where the correct code it mutates agrees; and its bug shows as expected.
TEST_P(MutantIsKilled, WhereItsParentIsRight) {
    const mutant_case& m = GetParam();
    const mutant_outcome o = outcomes_of({&m, 1}).at(m.subject.name);
    EXPECT_TRUE(o.killed()) << m.subject.name << " survived the shipped corpus: nowhere wrong where "
                            << m.parent << " is right";
    EXPECT_GT(o.at[0].expected_verdicts + o.at[1].expected_verdicts, 0u)
        << "expected its bug to show as " << verdict_name(m.expected);
}

INSTANTIATE_TEST_SUITE_P(ShippedCorpus, MutantIsKilled, testing::ValuesIn(mutants),
                         [](const testing::TestParamInfo<mutant_case>& info) { return info.param.subject.name; });

// The kill-rate report: every mutant by name; the rate must be 100%.
TEST(MutationScore, KillRateIsOneHundredPercent) {
    const std::map<std::string, mutant_outcome> all = outcomes_of(mutants);
    std::size_t killed = 0;
    std::printf("%-22s %-18s %-7s %21s %23s  %-17s %s\n", "mutant", "parent", "killed", "caught float/double",
                "disagree float/double", "mostly", "first case caught");
    for (const mutant_case& m : mutants) {
        const mutant_outcome& o = all.at(m.subject.name);
        killed += o.killed();
        const std::string& first = o.at[0].caught ? o.at[0].first_caught : o.at[1].first_caught;
        std::printf("%-22s %-18s %-7s %10zu / %-9zu %11zu / %-10zu  %-17s %s\n", m.subject.name.c_str(),
                    m.parent.c_str(), o.killed() ? "yes" : "NO", o.at[0].caught, o.at[1].caught,
                    o.at[0].disagreements, o.at[1].disagreements,
                    std::string(verdict_name(o.main_verdict())).c_str(), first.c_str());
        EXPECT_TRUE(o.killed()) << m.subject.name;
    }
    const std::size_t total = std::size(mutants);
    std::printf("kill rate: %zu/%zu = %.0f%%\n", killed, total, 100.0 * static_cast<double>(killed) / total);
    EXPECT_EQ(killed, total);
}

}  // namespace
}  // namespace rayverify
