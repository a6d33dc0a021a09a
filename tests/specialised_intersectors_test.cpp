// The specialised intersectors (any-hit, nearest-in-interval, unit
// direction) on hand-worked cases and against hearn_baker's roots filtered
// into the interval. (The renderer's judge of these answers: judge_test.cpp.)
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "compare/audit.h"
#include "intersectors/hearn_baker.h"
#include "intersectors/hearn_baker_any_hit.h"
#include "intersectors/hearn_baker_nearest.h"
#include "intersectors/hearn_baker_unit.h"
#include "intersectors/registry.h"
#include "oracle/oracle.h"

namespace rayverify {
namespace {

constexpr double inf = std::numeric_limits<double>::infinity();

// Unit sphere at the origin; the ray along +z from z = −5 meets it at t = 4 and 6.
const ray_sphere<double> ahead{{0, 0, -5}, {0, 0, 1}, {0, 0, 0}, 1};
// Origin inside: roots −1 and 1.
const ray_sphere<double> inside{{0, 0, 0}, {0, 0, 1}, {0, 0, 0}, 1};
// Sphere behind: roots −6 and −4.
const ray_sphere<double> behind{{0, 0, 5}, {0, 0, 1}, {0, 0, 0}, 1};
// Direction of length 2: roots 2 and 3.
const ray_sphere<double> long_direction{{0, 0, -5}, {0, 0, 2}, {0, 0, 0}, 1};
// Passes at distance 2: a miss.
const ray_sphere<double> passing{{0, 2, -5}, {0, 0, 1}, {0, 0, 0}, 1};

template <class T>
bool any_hit(const ray_sphere<double>& g, double tmin, double tmax) {
    return intersectors::hearn_baker_any_hit(rounded_to<T>(g), static_cast<T>(tmin), static_cast<T>(tmax)).count == 1;
}

template <class T>
std::optional<double> nearest(const ray_sphere<double>& g, double tmin, double tmax) {
    const root_pair<T> r =
        intersectors::hearn_baker_nearest(rounded_to<T>(g), static_cast<T>(tmin), static_cast<T>(tmax));
    if (r.count == 0) return std::nullopt;
    return static_cast<double>(r.t0);
}

template <class T>
class Specialised : public testing::Test {};
using precisions = testing::Types<float, double>;
TYPED_TEST_SUITE(Specialised, precisions);

TYPED_TEST(Specialised, AnyHitDecidesTheOpenInterval) {
    using T = TypeParam;
    EXPECT_TRUE(any_hit<T>(ahead, 0, inf));
    EXPECT_FALSE(any_hit<T>(ahead, 0, 3));    // both roots beyond tmax
    EXPECT_FALSE(any_hit<T>(ahead, 4.5, 5));  // between the roots
    EXPECT_TRUE(any_hit<T>(ahead, 5, 7));     // the far root only
    EXPECT_FALSE(any_hit<T>(ahead, 4, 6));    // roots exactly on the open bounds
    EXPECT_TRUE(any_hit<T>(ahead, 3.5, 4.5));
    EXPECT_TRUE(any_hit<T>(inside, 0, inf));  // decided from the sign of C
    EXPECT_FALSE(any_hit<T>(inside, 0, 0.5));
    EXPECT_TRUE(any_hit<T>(inside, -2, 0));   // the root behind, in a backward interval
    EXPECT_FALSE(any_hit<T>(behind, 0, inf));  // decided from the signs of C and b′
    EXPECT_TRUE(any_hit<T>(behind, -5, inf));
    EXPECT_TRUE(any_hit<T>(long_direction, 0, inf));
    EXPECT_FALSE(any_hit<T>(long_direction, 0, 1.5));
    EXPECT_TRUE(any_hit<T>(long_direction, 2.5, 3.5));
    EXPECT_FALSE(any_hit<T>(passing, 0, inf));
    EXPECT_FALSE(any_hit<T>(passing, -inf, inf));
}

TYPED_TEST(Specialised, NearestReturnsTheFirstRootInTheInterval) {
    using T = TypeParam;
    EXPECT_EQ(nearest<T>(ahead, 0, inf), 4.0);
    EXPECT_EQ(nearest<T>(ahead, 4, inf), 6.0);  // open: the root at tmin is excluded
    EXPECT_EQ(nearest<T>(ahead, 0, 4), std::nullopt);
    EXPECT_EQ(nearest<T>(ahead, 4.5, 5), std::nullopt);
    EXPECT_EQ(nearest<T>(inside, 0, inf), 1.0);
    EXPECT_EQ(nearest<T>(inside, -inf, inf), -1.0);
    EXPECT_EQ(nearest<T>(behind, 0, inf), std::nullopt);
    EXPECT_EQ(nearest<T>(behind, -5, inf), -4.0);
    EXPECT_EQ(nearest<T>(long_direction, 0, inf), 2.0);
    EXPECT_EQ(nearest<T>(long_direction, 2, inf), 3.0);
    EXPECT_EQ(nearest<T>(passing, -inf, inf), std::nullopt);
}

TYPED_TEST(Specialised, UnitDirectionFormsMatchTheGeneralForm) {
    using T = TypeParam;
    for (const auto& g : {ahead, inside, behind, passing}) {
        const ray_sphere<T> s = rounded_to<T>(g);
        const root_pair<T> general = intersectors::hearn_baker(s), unit = intersectors::hearn_baker_unit(s);
        EXPECT_EQ(unit.count, general.count);
        if (general.count) {
            EXPECT_EQ(unit.t0, general.t0);
            EXPECT_EQ(unit.t1, general.t1);
        }
        const root_pair<T> n = intersectors::hearn_baker_unit_nearest(s);
        const root_pair<T> m = intersectors::hearn_baker_nearest(s);
        EXPECT_EQ(n.count, m.count);
        if (m.count) {
            EXPECT_EQ(n.t0, m.t0);
        }
    }
}

// On random unit-direction cases the specialisations answer exactly what
// hearn_baker's roots, filtered into the interval, answer (same formulas; the
// sign early-outs must never contradict them away from ties).
TYPED_TEST(Specialised, AgreeWithFilteredHearnBakerOnRandomCases) {
    using T = TypeParam;
    const unsigned seed = 20261122;
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> coordinate(-10, 10), radius(0.1, 5), bound(-20, 20);
    std::normal_distribution<double> normal;
    int disagreements = 0;
    for (int i = 0; i < 20000; ++i) {
        vec3<double> d{normal(rng), normal(rng), normal(rng)};
        const double length = std::sqrt(dot(d, d));
        d = (1 / length) * d;
        const ray_sphere<T> s = rounded_to<T>(ray_sphere<double>{
            {coordinate(rng), coordinate(rng), coordinate(rng)}, d, {coordinate(rng), coordinate(rng), coordinate(rng)},
            radius(rng)});
        double lo = bound(rng), hi = bound(rng);
        if (lo > hi) std::swap(lo, hi);
        if (i % 3 == 0) lo = 0, hi = inf;
        const ray_interval<T> interval{static_cast<T>(lo), static_cast<T>(hi)};
        const t_range open{static_cast<double>(interval.tmin), static_cast<double>(interval.tmax)};
        const root_pair<T> line = intersectors::hearn_baker(s);
        std::optional<T> filtered;
        if (line.count && open.contains(line.t0))
            filtered = line.t0;
        else if (line.count && open.contains(line.t1))
            filtered = line.t1;
        const root_pair<T> hit = intersectors::hearn_baker_any_hit(s, interval.tmin, interval.tmax);
        const root_pair<T> near = intersectors::hearn_baker_nearest(s, interval.tmin, interval.tmax);
        const root_pair<T> unit_near = intersectors::hearn_baker_unit_nearest(s, interval.tmin, interval.tmax);
        const root_pair<T> unit_hit = intersectors::hearn_baker_unit_any_hit(s, interval.tmin, interval.tmax);
        const bool same = (hit.count == 1) == filtered.has_value() && (near.count == 1) == filtered.has_value() &&
                          (!filtered || near.t0 == *filtered) && (unit_near.count == 1) == filtered.has_value() &&
                          (unit_hit.count == 1) == filtered.has_value();
        if (!same && ++disagreements <= 5) ADD_FAILURE() << "seed " << seed << " case " << i;
    }
    EXPECT_EQ(disagreements, 0) << "seed " << seed;
}

}  // namespace
}  // namespace rayverify
