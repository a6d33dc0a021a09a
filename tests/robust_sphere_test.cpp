// robust_sphere.h against the exact oracle, directly (not through the
// judge): the class, every root's sign and its correct rounding, and every
// interval decision, with open and closed ends, in float and double — on
// hand-worked cases, held-out regression cases at the ends of the ranges,
// random cases with a printed seed, and both paths (fast and exact) apart.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <optional>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "core/float_bits.h"
#include "core/ray_sphere_case.h"
#include "corpus/generators.h"
#include "intersectors/robust.h"
#include "intersectors/robust_sphere.h"
#include "oracle/oracle.h"
#include "robust_vendored/answers.h"
#include "support/process.h"
#include "support/robust_promise.h"

namespace rayverify {
namespace {

namespace rs = robust_sphere;
using rs::ends;

template <class T>
rs::ray<T> ray_of(const ray_sphere<T>& g) {
    return intersectors::robust_ray(g);
}

template <class T>
rs::sphere<T> sphere_of(const ray_sphere<T>& g) {
    return intersectors::robust_target(g);
}

template <class T>
constexpr precision precision_of = std::is_same_v<T, float> ? precision::binary32 : precision::binary64;

// The exact solution for exactly the T inputs.
template <class T>
exact_solution exact_of(const ray_sphere<T>& g) {
    return solve_exact(rounded_to<double>(g), precision_of<T>);
}

using test_support::promised_root;
using test_support::within_bound;

std::string show(const ray_sphere<double>& g) {
    char buf[512];
    std::snprintf(buf, sizeof buf, "o=(%a, %a, %a) d=(%a, %a, %a) c=(%a, %a, %a) r=%a", g.origin.x, g.origin.y,
                  g.origin.z, g.direction.x, g.direction.y, g.direction.z, g.centre.x, g.centre.y, g.centre.z,
                  g.radius);
    return buf;
}

// sign(t* − v) for the exact root i.
int exact_compare(const exact_solution& e, root_index i, double v) {
    if (std::isinf(v)) return v > 0 ? -1 : 1;
    return -static_cast<int>(e.compare_to_root(v, i));
}

template <ends Lower, ends Upper>
bool exact_inside(const exact_solution& e, root_index i, double tmin, double tmax) {
    const int lo = exact_compare(e, i, tmin), hi = exact_compare(e, i, tmax);
    return (lo > 0 || (lo == 0 && Lower == ends::closed)) && (hi < 0 || (hi == 0 && Upper == ends::closed));
}

// Every query of robust_sphere on one case and interval, checked against the
// oracle; returns "" or what went wrong.
template <class T, ends Lower, ends Upper>
std::string check_interval(const ray_sphere<T>& g, const exact_solution& e, T tmin, T tmax) {
    const rs::ray<T> r = ray_of(g);
    const rs::sphere<T> s = sphere_of(g);
    // The nearest exact root in the interval.
    std::optional<root_index> want;
    if (e.cls != line_class::miss)
        for (root_index i : {root_index::near_root, root_index::far_root})
            if (exact_inside<Lower, Upper>(e, i, tmin, tmax)) {
                want = i;
                break;
            }
    const bool any = rs::any_hit<Lower, Upper>(r, s, tmin, tmax);
    if (any != want.has_value()) return "any_hit " + std::to_string(any);
    const rs::ray_hit<T> h = rs::nearest_hit<Lower, Upper>(r, s, tmin, tmax);
    if (h.found != want.has_value()) return "nearest_hit found " + std::to_string(h.found);
    if (!want) return "";
    if ((h.which == rs::root::near_root) != (*want == root_index::near_root) && e.cls == line_class::two_hit)
        return "nearest_hit names the wrong root";
    T expected = promised_root<T>(e, *want);
    if (Lower == ends::open && expected <= tmin) expected = std::nextafter(tmin, tmax);
    if (Upper == ends::open && expected >= tmax) expected = std::nextafter(tmax, tmin);
    if (std::bit_cast<std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>>(h.t) !=
        std::bit_cast<std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>>(expected)) {
        char buf[128];
        std::snprintf(buf, sizeof buf, "nearest_hit t = %a, expected %a", double(h.t), double(expected));
        return buf;
    }
    return "";
}

// The bounded tier's nearest hit on one interval: the same decision and root
// as the exact one, within the bound and inside the interval.
template <class T, ends Lower, ends Upper>
std::string check_bounded_interval(const ray_sphere<T>& g, const exact_solution& e, T tmin, T tmax) {
    const rs::ray_hit<T> exact = rs::nearest_hit<Lower, Upper>(ray_of(g), sphere_of(g), tmin, tmax);
    const rs::ray_hit<T> h = rs::nearest_hit<Lower, Upper, rs::roots::bounded>(ray_of(g), sphere_of(g), tmin, tmax);
    if (h.found != exact.found) return "bounded nearest_hit found " + std::to_string(h.found);
    if (!h.found) return "";
    if (h.which != exact.which && e.cls == line_class::two_hit) return "bounded nearest_hit names the wrong root";
    const bool in = (Lower == ends::open ? h.t > tmin : h.t >= tmin) && (Upper == ends::open ? h.t < tmax : h.t <= tmax);
    if (!in || !within_bound(h.t, promised_root<T>(e, h.which == rs::root::near_root ? root_index::near_root
                                                                                         : root_index::far_root))) {
        if (within_bound(h.t, exact.t)) return "";  // the exact tier's own value (moved inside an open end)
        char buf[128];
        std::snprintf(buf, sizeof buf, "bounded nearest_hit t = %a, exact tier %a", double(h.t), double(exact.t));
        return buf;
    }
    return "";
}

// The whole contract on one case: line roots, then the interval queries on
// intervals placed at and around the roots, in both tiers.
template <class T>
std::string check_case(const ray_sphere<T>& g) {
    const exact_solution e = exact_of(g);
    if (!e.valid()) return "";
    const rs::line_roots<T> line = rs::intersect_line(ray_of(g), sphere_of(g));
    const int count = e.cls == line_class::miss ? 0 : (e.cls == line_class::tangent ? 1 : 2);
    if (line.count != count) return "line count " + std::to_string(line.count) + ", exact " + std::to_string(count);
    const rs::line_roots<T> bounded = rs::intersect_line<rs::roots::bounded>(ray_of(g), sphere_of(g));
    if (bounded.count != count) return "bounded line count " + std::to_string(bounded.count);
    if (count > 0 && (!within_bound(bounded.t0, promised_root<T>(e, root_index::near_root)) ||
                      !within_bound(bounded.t1, promised_root<T>(e, root_index::far_root)))) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "bounded line roots %a, %a", double(bounded.t0), double(bounded.t1));
        return buf;
    }
    if (count > 0) {
        const T near = promised_root<T>(e, root_index::near_root), far = promised_root<T>(e, root_index::far_root);
        if (!(line.t0 == near && std::signbit(line.t0) == std::signbit(near)) ||
            !(line.t1 == far && std::signbit(line.t1) == std::signbit(far))) {
            char buf[160];
            std::snprintf(buf, sizeof buf, "line roots %a, %a; expected %a, %a", double(line.t0), double(line.t1),
                          double(near), double(far));
            return buf;
        }
    }
    const T inf = std::numeric_limits<T>::infinity();
    std::vector<std::pair<T, T>> intervals = {{T(0), inf}, {-inf, inf}, {-inf, T(0)}};
    if (count > 0)
        for (root_index i : {root_index::near_root, root_index::far_root}) {
            const T t = static_cast<T>(e.root(i).rounded);
            if (!std::isfinite(t)) continue;
            intervals.push_back({t, inf});
            intervals.push_back({T(0), t});
            intervals.push_back({std::nextafter(t, -inf), std::nextafter(t, inf)});
            intervals.push_back({t, t});
        }
    for (const auto& [tmin, tmax] : intervals) {
        std::string why = check_interval<T, ends::open, ends::open>(g, e, tmin, tmax);
        if (why.empty()) why = check_interval<T, ends::closed, ends::closed>(g, e, tmin, tmax);
        if (why.empty()) why = check_interval<T, ends::open, ends::closed>(g, e, tmin, tmax);
        if (why.empty()) why = check_interval<T, ends::closed, ends::open>(g, e, tmin, tmax);
        if (why.empty()) why = check_bounded_interval<T, ends::open, ends::open>(g, e, tmin, tmax);
        if (why.empty()) why = check_bounded_interval<T, ends::closed, ends::closed>(g, e, tmin, tmax);
        if (!why.empty()) {
            char buf[96];
            std::snprintf(buf, sizeof buf, " on (%a, %a)", double(tmin), double(tmax));
            return why + buf;
        }
    }
    return "";
}

ray_sphere<double> geometry(vec3<double> o, vec3<double> d, vec3<double> c, double r) { return {o, d, c, r}; }

// ---------------------------------------------------------------------------
// Hand-worked cases: the unit sphere at the origin, d = (0, 0, 1).

TEST(RobustSphere, TwoRootsInFront) {
    const rs::ray<double> r{{0, 0, -5}, {0, 0, 1}};
    const rs::sphere<double> s{{0, 0, 0}, 1};
    const auto line = rs::intersect_line(r, s);
    EXPECT_EQ(line.count, 2);
    EXPECT_EQ(line.t0, 4.0);
    EXPECT_EQ(line.t1, 6.0);
    EXPECT_EQ(rs::nearest_hit(r, s, 0.0, INFINITY).t, 4.0);
    // 4 itself excluded from (4, ∞), included in [4, ∞).
    EXPECT_EQ(rs::nearest_hit(r, s, 4.0, INFINITY).t, 6.0);
    EXPECT_EQ((rs::nearest_hit<ends::closed, ends::open>(r, s, 4.0, INFINITY).t), 4.0);
    EXPECT_FALSE(rs::any_hit(r, s, 0.0, 4.0));
    EXPECT_TRUE((rs::any_hit<ends::open, ends::closed>(r, s, 0.0, 4.0)));
    EXPECT_FALSE(rs::any_hit(r, s, 4.0, 6.0));
    EXPECT_TRUE((rs::any_hit<ends::closed, ends::open>(r, s, 4.0, 6.0)));
}

TEST(RobustSphere, ExactTangentIsOneRoot) {
    // The line x = 1 grazes the unit sphere at (1, 0, 0): Δ′ = 0, t = 5.
    for (float x : {1.0f, -1.0f}) {
        const auto line = rs::intersect_line(rs::ray<float>{{x, 0, -5}, {0, 0, 1}}, rs::sphere<float>{{0, 0, 0}, 1});
        EXPECT_EQ(line.count, 1);
        EXPECT_EQ(line.t0, 5.0f);
        EXPECT_EQ(line.t1, 5.0f);
    }
    // Just outside and inside by one ulp of x: miss, two roots.
    EXPECT_EQ(rs::intersect_line(rs::ray<double>{{std::nextafter(1.0, 2.0), 0, -5}, {0, 0, 1}},
                                 rs::sphere<double>{{0, 0, 0}, 1})
                  .count,
              0);
    EXPECT_EQ(rs::intersect_line(rs::ray<double>{{std::nextafter(1.0, 0.0), 0, -5}, {0, 0, 1}},
                                 rs::sphere<double>{{0, 0, 0}, 1})
                  .count,
              2);
}

TEST(RobustSphere, OriginOnTheSurface) {
    // Roots 0 and 2: the root at the origin is excluded from (0, ∞), not from [0, ∞).
    const rs::ray<double> r{{0, 0, -1}, {0, 0, 1}};
    const rs::sphere<double> s{{0, 0, 0}, 1};
    const auto line = rs::intersect_line(r, s);
    EXPECT_EQ(line.count, 2);
    EXPECT_EQ(line.t0, 0.0);
    EXPECT_FALSE(std::signbit(line.t0));
    EXPECT_EQ(line.t1, 2.0);
    EXPECT_EQ(rs::nearest_hit(r, s, 0.0, INFINITY).t, 2.0);
    EXPECT_EQ(rs::nearest_hit(r, s, 0.0, INFINITY).which, rs::root::far_root);
    EXPECT_EQ((rs::nearest_hit<ends::closed, ends::open>(r, s, 0.0, INFINITY).t), 0.0);
    // Leaving the surface: roots −2 and 0, nothing in (0, ∞).
    EXPECT_FALSE(rs::any_hit(rs::ray<double>{{0, 0, 1}, {0, 0, 1}}, s, 0.0, INFINITY));
}

TEST(RobustSphere, InsideAndBehind) {
    const rs::sphere<float> s{{0, 0, 0}, 1};
    const auto inside = rs::intersect_line(rs::ray<float>{{0, 0, 0}, {0, 0, 1}}, s);
    EXPECT_EQ(inside.count, 2);
    EXPECT_EQ(inside.t0, -1.0f);
    EXPECT_EQ(inside.t1, 1.0f);
    const auto hit = rs::nearest_hit(rs::ray<float>{{0, 0, 0}, {0, 0, 1}}, s, 0.0f, INFINITY);
    EXPECT_EQ(hit.t, 1.0f);
    EXPECT_EQ(hit.which, rs::root::far_root);
    EXPECT_FALSE(rs::nearest_hit(rs::ray<float>{{0, 0, 5}, {0, 0, 1}}, s, 0.0f, INFINITY).found);
    const auto behind = rs::intersect_line(rs::ray<float>{{0, 0, 5}, {0, 0, 1}}, s);
    EXPECT_EQ(behind.t0, -6.0f);
    EXPECT_EQ(behind.t1, -4.0f);
}

// ---------------------------------------------------------------------------
// Held-out regression cases at the ends of the ranges, each judged by the
// oracle (check_case) on every query and interval.

TEST(RobustSphere, PowerOfTwoScalings) {
    // The first hand case with positions and radius scaled by 2^k and the
    // direction by 2^j: roots (4, 6)·2^(k−j), every one exact or overflowing.
    for (int k : {-1074 + 3, -1000, -600, -150, 0, 150, 600, 1000, 1020})
        for (int j : {-1074, -1000, -600, -60, 0, 60, 600, 1000, 1023}) {
            const double p = std::ldexp(1.0, k), q = std::ldexp(1.0, j);
            if (p * 5 == 0) continue;
            const ray_sphere<double> g = geometry({0, 0, -5 * p}, {0, 0, q}, {0, 0, 0}, p);
            SCOPED_TRACE(show(g));
            EXPECT_EQ(check_case(g), "");
            const ray_sphere<double> shifted = geometry({p, 3 * p, -5 * p}, {q, 0, q}, {p, 2 * p, 0}, 2 * p);
            SCOPED_TRACE(show(shifted));
            EXPECT_EQ(check_case(shifted), "");
        }
}

TEST(RobustSphere, FloatScalingsAndSubnormals) {
    for (int k : {-149 + 3, -140, -126, -60, 0, 60, 120, 125})
        for (int j : {-149, -130, -60, 0, 60, 127}) {
            const float p = std::ldexp(1.0f, k), q = std::ldexp(1.0f, j);
            const ray_sphere<float> g{{0, 0, -5 * p}, {0, q, q}, {0, 0, 0}, 2 * p};
            SCOPED_TRACE(show(rounded_to<double>(g)));
            EXPECT_EQ(check_case(g), "");
        }
}

TEST(RobustSphere, RootsThatOverflowOrVanish) {
    // Roots 2^1032 and beyond: RN is +inf, and stays so; roots far below
    // denorm_min: +denorm_min in front, never +0, and −0 behind.
    const double big = std::ldexp(1.0, 1000), tiny = std::ldexp(1.0, -1070);
    const ray_sphere<double> cases[] = {
        geometry({0, 0, -5 * big}, {0, 0, std::ldexp(1.0, -40)}, {0, 0, 0}, big),
        geometry({0, 0, -5 * tiny}, {0, 0, big}, {0, 0, 0}, tiny),
        geometry({0, 0, 5 * tiny}, {0, 0, big}, {0, 0, 0}, tiny),
        geometry({0, 0, -tiny}, {0, 0, big}, {0, 0, 0}, tiny),
        geometry({0, 0, std::numeric_limits<double>::max()}, {0, 0, 1}, {0, 0, -std::numeric_limits<double>::max()},
                 std::numeric_limits<double>::max()),
        // Roots on either side of the overflow threshold max + ½ulp.
        geometry({0, 0, 0}, {0, 0, 1}, {0, 0, 0}, std::numeric_limits<double>::max()),
        geometry({0, 0, 0}, {0, 0, 0.5}, {0, 0, 0}, std::numeric_limits<double>::max()),
    };
    for (const ray_sphere<double>& g : cases) {
        SCOPED_TRACE(show(g));
        EXPECT_EQ(check_case(g), "");
    }
    const auto vanishing = rs::intersect_line(ray_of(cases[1]), sphere_of(cases[1]));
    EXPECT_EQ(vanishing.t0, std::numeric_limits<double>::denorm_min());
    const auto behind = rs::intersect_line(ray_of(cases[2]), sphere_of(cases[2]));
    EXPECT_EQ(behind.t1, 0.0);
    EXPECT_TRUE(std::signbit(behind.t1));
    const auto huge = rs::intersect_line(ray_of(cases[0]), sphere_of(cases[0]));
    EXPECT_EQ(huge.count, 2);
    EXPECT_EQ(huge.t0, std::numeric_limits<double>::infinity());
}

}  // namespace
}  // namespace rayverify

namespace rayverify {
namespace {

// ---------------------------------------------------------------------------
// Random cases, with a printed seed: every generator family, and inputs whose
// exponents spread over the whole range, near tangents, origins near the surface.

std::uint64_t seed_from_env() {
    if (const char* s = std::getenv("RAYVERIFY_SEED")) return std::strtoull(s, nullptr, 10);
    return std::random_device{}();
}

struct random_cases {
    std::mt19937_64 rng;
    double uniform() { return std::uniform_real_distribution<double>(-1, 1)(rng); }
    double scaled(int spread) {
        const int e = std::uniform_int_distribution<int>(-spread, spread)(rng);
        return std::ldexp(uniform(), e);
    }
    vec3<double> vector(int spread) { return {scaled(spread), scaled(spread), scaled(spread)}; }
    vec3<double> unit() {
        for (;;) {
            const vec3<double> v{uniform(), uniform(), uniform()};
            const double n = std::sqrt(length_squared(v));
            if (n > 0.1 && n < 1) return (1 / n) * v;
        }
    }
    // One of several regimes, chosen at random.
    ray_sphere<double> next() {
        const int regime = std::uniform_int_distribution<int>(0, 5)(rng);
        static constexpr int spreads[] = {4, 60, 300, 1000};
        const int spread = spreads[std::uniform_int_distribution<int>(0, 3)(rng)];
        switch (regime) {
            case 0: {  // everything independent, exponents over ±spread
                ray_sphere<double> g{vector(spread), vector(spread), vector(spread), std::fabs(scaled(spread))};
                if (rng() % 4 == 0) g.direction.y = 0;
                if (rng() % 4 == 0) g.origin.z = g.centre.z;
                return g;
            }
            case 1: {  // near tangent: o on a tangent line through p = c + r·n
                const vec3<double> c = vector(spread), n = unit();
                const double r = std::ldexp(1 + std::fabs(uniform()), std::uniform_int_distribution<int>(-20, 20)(rng));
                const vec3<double> t = unit();
                const vec3<double> tangent = t - dot(t, n) * n;
                const vec3<double> p = c + r * n;
                return {p - (std::ldexp(1.0, std::uniform_int_distribution<int>(-5, 30)(rng)) * tangent), tangent, c, r};
            }
            case 2: {  // origin on or near the surface
                const vec3<double> c = vector(spread), n = unit();
                const double r = std::ldexp(1 + std::fabs(uniform()), std::uniform_int_distribution<int>(-20, 20)(rng));
                return {c + r * n, unit(), c, r};
            }
            case 3: {  // far sphere, aimed near its centre
                const vec3<double> c = vector(4);
                const double r = std::ldexp(1 + std::fabs(uniform()), -std::uniform_int_distribution<int>(0, 50)(rng));
                const vec3<double> o = c + std::ldexp(1.0, std::uniform_int_distribution<int>(0, 10)(rng)) * unit();
                const vec3<double> aim = (c + (r * 1.5 * uniform()) * unit()) - o;
                return {o, aim, c, r};
            }
            case 4: {  // a generator family's case
                const auto families = generator_families();
                const auto& f = families[rng() % families.size()];
                return generate_case(f.name, rng() % 1000, rng() % 1000).geometry;
            }
            default: {  // small integers: exact roots, ties, zeros
                const auto small = [&] { return double(std::uniform_int_distribution<int>(-6, 6)(rng)); };
                return {{small(), small(), small()}, {small(), small(), small()}, {small(), small(), small()},
                        std::fabs(small())};
            }
        }
    }
};

template <class T>
void random_sweep(std::uint64_t seed, int count, bool intervals) {
    random_cases gen{std::mt19937_64(seed)};
    int failures = 0;
    for (int i = 0; i < count && failures < 5; ++i) {
        const ray_sphere<double> g = gen.next();
        if (validity<T>(g) != invalid_reason::none) continue;
        const ray_sphere<T> in = rounded_to<T>(g);
        std::string why;
        if (intervals) {
            why = check_case(in);
        } else {
            const exact_solution e = exact_of(in);
            const rs::line_roots<T> line = rs::intersect_line(ray_of(in), sphere_of(in));
            const int want = e.cls == line_class::miss ? 0 : (e.cls == line_class::tangent ? 1 : 2);
            if (line.count != want || (want > 0 && (line.t0 != promised_root<T>(e, root_index::near_root) ||
                                                    line.t1 != promised_root<T>(e, root_index::far_root))))
                why = "line roots differ from the oracle";
        }
        if (!why.empty()) {
            ++failures;
            ADD_FAILURE() << "seed " << seed << " case " << i << ": " << why << "\n  " << show(rounded_to<double>(in));
        }
    }
}

TEST(RobustSphereProperty, CorrectlyRoundedAndExactOnRandomCases) {
    const std::uint64_t seed = seed_from_env();
    std::printf("RAYVERIFY_SEED=%llu\n", static_cast<unsigned long long>(seed));
    random_sweep<float>(seed, 3000, true);
    random_sweep<double>(seed, 3000, true);
    random_sweep<float>(seed + 1, 20000, false);
    random_sweep<double>(seed + 1, 20000, false);
}

}  // namespace
}  // namespace rayverify

namespace rayverify {
namespace {

// ---------------------------------------------------------------------------
// The two paths apart: wherever the fast path answers, the exact path (run
// on every case here, not only where the fast path gives up) answers the same.

template <class T>
void fast_matches_exact(std::uint64_t seed, int count) {
    random_cases gen{std::mt19937_64(seed)};
    int failures = 0, fast = 0;
    for (int i = 0; i < count && failures < 5; ++i) {
        const ray_sphere<double> g = gen.next();
        if (validity<T>(g) != invalid_reason::none) continue;
        const ray_sphere<T> in = rounded_to<T>(g);
        const rs::ray<T> r = ray_of(in);
        const rs::sphere<T> s = sphere_of(in);
        const rs::line_roots<T> exact = rs::detail::exact_line(r, s);
        const T tmin = std::is_same_v<T, float> ? T(0x1p-10) : T(0);  // a renderer's epsilon, or 0
        const rs::ray_hit<T> exact_hit = rs::detail::exact_nearest<ends::open, ends::open>(r, s, tmin, T(INFINITY));
        const bool exact_any = rs::detail::exact_any<ends::open, ends::open>(r, s, tmin, T(INFINITY));
        const auto same = [](T a, T b) { return a == b && std::signbit(a) == std::signbit(b); };
        std::string why;
        if (const auto f = rs::intersect_line_fast(r, s)) {
            ++fast;
            if (f->count != exact.count || !same(f->t0, exact.t0) || !same(f->t1, exact.t1)) why = "line roots";
        }
        if (const auto f = rs::nearest_hit_fast(r, s, tmin, T(INFINITY)))
            if (f->found != exact_hit.found || !same(f->t, exact_hit.t) || f->which != exact_hit.which)
                why = "nearest hit";
        if (const auto f = rs::any_hit_fast(r, s, tmin, T(INFINITY)))
            if (*f != exact_any) why = "any hit";
        // The static filter alone (stage 1, as inlined into a caller's loop).
        rs::detail::fast_solver<T, false> filter(r, s);
        rs::line_roots<T> filtered;
        if (rs::detail::query_line<rs::roots::correctly_rounded, T>(filter, filtered) &&
            (filtered.count != exact.count || !same(filtered.t0, exact.t0) || !same(filtered.t1, exact.t1)))
            why = "line roots from the static filter";
        if (!why.empty()) {
            ++failures;
            ADD_FAILURE() << "seed " << seed << " case " << i << ": fast and exact paths differ on " << why << "\n  "
                          << show(rounded_to<double>(in));
        }
    }
    EXPECT_GT(fast, count / 4) << "the fast path should settle most of these cases";
}

TEST(RobustSphereProperty, FastPathAgreesWithTheExactPath) {
    const std::uint64_t seed = seed_from_env();
    std::printf("RAYVERIFY_SEED=%llu\n", static_cast<unsigned long long>(seed));
    fast_matches_exact<float>(seed, 4000);
    fast_matches_exact<double>(seed, 4000);
}

// The segment query's fast path (stage 1 on RN(p1 − p0) with that rounding
// in its bounds, stage 2 on the exact pair p1 − p0) against its exact path
// (p1 − p0 in two components a coordinate), every combination of ends and
// start rule: the random cases' rays as segments to o + k·d for k a power of
// two, a random scale or far past the roots, and segments ending on or one
// ulp off a point of the sphere (p1 − p0 in general no value of T).
// RN to T, overflow to ±inf (a conversion out of float's range is undefined).
template <class T>
T rounded_to_type(double x) {
    if constexpr (std::is_same_v<T, float>)
        return rs::detail::round_to_float(x);
    else
        return x;
}

template <class T>
void segment_fast_matches_exact(std::uint64_t seed, int count) {
    random_cases gen{std::mt19937_64(seed)};
    int failures = 0, inexact = 0, settled = 0;
    for (int i = 0; i < count && failures < 5; ++i) {
        const ray_sphere<double> g = gen.next();
        if (validity<T>(g) != invalid_reason::none) continue;
        const ray_sphere<T> in = rounded_to<T>(g);
        vec3<double> end;
        switch (gen.rng() % 4) {
            case 0: end = g.origin + std::ldexp(1.0, std::uniform_int_distribution<int>(-4, 40)(gen.rng)) * g.direction; break;
            case 1: end = g.origin + (8 * std::fabs(gen.uniform())) * g.direction; break;
            case 2: end = g.centre + g.radius * gen.unit(); break;  // on the sphere, rounded
            default: {  // a point of the sphere, then one ulp of T off it
                const vec3<double> q = g.centre + g.radius * gen.unit();
                const T x = rounded_to_type<T>(q.x);
                end = {std::nextafter(x, gen.uniform() > 0 ? T(INFINITY) : T(-INFINITY)), q.y, q.z};
            }
        }
        const rs::vec3<T> p0{in.origin.x, in.origin.y, in.origin.z};
        const rs::vec3<T> p1{rounded_to_type<T>(end.x), rounded_to_type<T>(end.y), rounded_to_type<T>(end.z)};
        if (!std::isfinite(p1.x) || !std::isfinite(p1.y) || !std::isfinite(p1.z)) continue;
        if (p0.x == p1.x && p0.y == p1.y && p0.z == p1.z) continue;
        const rs::segment<T> seg{p0, p1};
        const rs::sphere<T> s = sphere_of(in);
        for (int axis = 0; axis < 3; ++axis) {
            const double a = axis == 0 ? p0.x : (axis == 1 ? p0.y : p0.z), b = axis == 0 ? p1.x : (axis == 1 ? p1.y : p1.z);
            const rs::detail::dd diff = rs::detail::two_sum(b, -a);
            if (diff.lo != 0 || static_cast<double>(rounded_to_type<T>(diff.hi)) != diff.hi) {
                ++inexact;
                break;
            }
        }
        {  // settled without the exact path: by the static filter, or (double) the double-word stage
            rs::ray_hit<T> out;
            rs::detail::fast_solver<T, true, true> refined(seg, s);
            if (rs::detail::query_segment<ends::closed, ends::closed, rs::start_inside::contact>(refined, out)) ++settled;
        }
        std::string why;
        const auto check = [&]<ends Start, ends End, rs::start_inside Inside>(const char* name) {
            rs::detail::exact_solver<T, 2> exact_solver(seg.p0, seg.p1, s);
            rs::ray_hit<T> exact;
            rs::detail::query_segment<Start, End, Inside>(exact_solver, exact);
            const rs::ray_hit<T> fast = rs::segment_hit<Start, End, Inside>(seg, s);
            if (fast.found != exact.found || (exact.found && (fast.t != exact.t || std::signbit(fast.t) != std::signbit(exact.t) ||
                                                              fast.which != exact.which)))
                why = name;
        };
        check.template operator()<ends::closed, ends::closed, rs::start_inside::contact>("closed ends, contact");
        check.template operator()<ends::open, ends::open, rs::start_inside::contact>("open ends, contact");
        check.template operator()<ends::closed, ends::open, rs::start_inside::exit>("closed start, open end, exit");
        check.template operator()<ends::open, ends::closed, rs::start_inside::exit>("open start, closed end, exit");
        if (!why.empty()) {
            ++failures;
            ADD_FAILURE() << "seed " << seed << " case " << i << ": segment fast and exact paths differ (" << why
                          << ")\n  p0 " << fmt::format("{:a} {:a} {:a}", double(p0.x), double(p0.y), double(p0.z))
                          << " p1 " << fmt::format("{:a} {:a} {:a}", double(p1.x), double(p1.y), double(p1.z))
                          << " c " << fmt::format("{:a} {:a} {:a}", double(s.centre.x), double(s.centre.y), double(s.centre.z))
                          << " r " << fmt::format("{:a}", double(s.radius));
        }
    }
    EXPECT_GT(inexact, count / 10) << "most segments here should have a p1 − p0 that is no value of T";
    EXPECT_GT(settled, count / 3) << "the fast path should settle most of these segments without the exact path";
    std::printf("%s: %d segments settled without the exact path, %d with p1 − p0 no value of the type\n",
                std::is_same_v<T, float> ? "float" : "double", settled, inexact);
}

TEST(RobustSphereProperty, SegmentFastPathAgreesWithTheExactPath) {
    const std::uint64_t seed = seed_from_env();
    std::printf("RAYVERIFY_SEED=%llu\n", static_cast<unsigned long long>(seed));
    int count = 20000;
    if (const char* n = std::getenv("RAYVERIFY_SEGMENT_CASES")) count = std::atoi(n);
    segment_fast_matches_exact<float>(seed, count);
    segment_fast_matches_exact<double>(seed, count);
}

// Every returned root within 1 ulp of the exact root, as the oracle measures it.
TEST(RobustSphereProperty, RootsWithinOneUlp) {
    const std::uint64_t seed = seed_from_env() + 2;
    std::printf("RAYVERIFY_SEED=%llu\n", static_cast<unsigned long long>(seed - 2));
    random_cases gen{std::mt19937_64(seed)};
    double worst = 0;
    for (int i = 0; i < 6000; ++i) {
        const ray_sphere<double> g = gen.next();
        for (precision p : {precision::binary32, precision::binary64}) {
            if ((p == precision::binary32 ? validity<float>(g) : validity<double>(g)) != invalid_reason::none) continue;
            const ray_sphere<double> in = p == precision::binary32 ? rounded_to<double>(rounded_to<float>(g)) : g;
            const exact_solution e = solve_exact(in, p);
            if (e.cls == line_class::miss) continue;
            double t0, t1;
            if (p == precision::binary32) {
                const auto r = rs::intersect_line(ray_of(rounded_to<float>(in)), sphere_of(rounded_to<float>(in)));
                t0 = r.t0, t1 = r.t1;
            } else {
                const auto r = rs::intersect_line(ray_of(in), sphere_of(in));
                t0 = r.t0, t1 = r.t1;
            }
            for (const auto& [which, t] : {std::pair{root_index::near_root, t0}, std::pair{root_index::far_root, t1}}) {
                if (std::isinf(t) && std::isinf(e.root(which).rounded)) continue;  // RN(t*) overflows: ±inf promised
                const double ulps = e.root_ulp_error(which, t);
                worst = std::max(worst, ulps);
                EXPECT_LE(ulps, 1.0) << "seed " << seed - 2 << " case " << i << " " << precision_name(p) << "\n  "
                                     << show(in);
            }
        }
    }
    std::printf("largest root error: %.3g ulp\n", worst);
}

// ---------------------------------------------------------------------------
// Literal regression cases: exact tangents off the axes and with non-unit
// directions, origins exactly on the surface, roots exactly at interval ends.

TEST(RobustSphere, HandConstructedEdgeCases) {
    const ray_sphere<double> cases[] = {
        // The line x = 3, y = 4 touches the sphere of radius 5 at (3, 4, 0): t = 10 (d = e_z), 5 (d = 2e_z).
        geometry({3, 4, -10}, {0, 0, 1}, {0, 0, 0}, 5),
        geometry({3, 4, -10}, {0, 0, 2}, {0, 0, 0}, 5),
        geometry({3 + 0x1p40, 4, -10}, {0, 0, 2}, {0x1p40, 0, 0}, 5),
        // Tangent through the origin side: o on the tangent line at the touching point (t* = 0).
        geometry({3, 4, 0}, {0, 0, 1}, {0, 0, 0}, 5),
        // Origin on the surface (2, 3, 6)/7·7: entering and leaving.
        geometry({2, 3, 6}, {-2, -3, -6}, {0, 0, 0}, 7),
        geometry({2, 3, 6}, {2, 3, 6}, {0, 0, 0}, 7),
        // r = 0: a point; the line through it is tangent, one beside it misses.
        geometry({0, 0, -1}, {0, 0, 1}, {0, 0, 0}, 0),
        geometry({0x1p-1074, 0, -1}, {0, 0, 1}, {0, 0, 0}, 0),
        // Opposite-signed huge positions: o − c overflows double.
        geometry({0, 0, -0x1p1023}, {0, 0, 1}, {0, 0, 0x1p1023}, 0x1p1022),
    };
    for (const ray_sphere<double>& g : cases) {
        SCOPED_TRACE(show(g));
        EXPECT_EQ(check_case(g), "");
        EXPECT_EQ(check_case(rounded_to<float>(g)), "") << "float";
    }
    EXPECT_EQ(rs::intersect_line(ray_of(cases[1]), sphere_of(cases[1])).count, 1);
    EXPECT_EQ(rs::intersect_line(ray_of(cases[1]), sphere_of(cases[1])).t0, 5.0);
    EXPECT_EQ(rs::intersect_line(ray_of(cases[3]), sphere_of(cases[3])).t0, 0.0);
    const auto huge = rs::intersect_line(ray_of(cases[8]), sphere_of(cases[8]));
    EXPECT_EQ(huge.count, 2);
    EXPECT_EQ(huge.t0, 0x1.8p1023);  // 2^1023 + 2^1023 − 2^1022
}

// ---------------------------------------------------------------------------
// Hit points: the bound holds against the exact hit point (or, reprojected,
// against the sphere).

TEST(RobustSphere, HitPointErrorBoundsHold) {
    const std::uint64_t seed = seed_from_env() + 3;
    random_cases gen{std::mt19937_64(seed)};
    int checked = 0;
    for (int i = 0; i < 3000; ++i) {
        const ray_sphere<double> g = gen.next();
        if (validity<double>(g) != invalid_reason::none) continue;
        const exact_solution e = solve_exact(g, precision::binary64);
        if (!e.nearest_in_front) continue;
        const root_index which = *e.nearest_in_front;
        const rs::ray<double> r = ray_of(g);
        const rs::sphere<double> s = sphere_of(g);
        const rs::ray_hit<double> h = rs::nearest_hit(r, s, 0.0, INFINITY);
        ASSERT_TRUE(h.found);
        const rs::surface_point<double> p = rs::hit_point(r, s, h.t);
        const double point[3] = {p.point.x, p.point.y, p.point.z}, error[3] = {p.error.x, p.error.y, p.error.z};
        for (int axis = 0; axis < 3; ++axis) {
            if (!std::isfinite(point[axis])) continue;
            // |point − p*| from the oracle: its ulps times the ulp at p* (within a factor 2 of RN(p*)'s),
            // compared as ulps against the bound in ulps: a point far from a tiny p* is more ulps away
            // than a double holds (+inf), and so may its bound be.
            const double exact = e.rounded_hit_coordinate(which, axis);
            const double ulps = e.hit_point_ulp_error(which, axis, point[axis]);
            const double ulp = ulp_of(exact);
            EXPECT_LE(ulps, error[axis] * 2.0001 / ulp)
                << "seed " << seed - 3 << " case " << i << " axis " << axis << ": exact " << exact << ", point "
                << point[axis] << ", bound " << error[axis];
            // And the bound is not vacuous: a few ulps of the coordinate.
            ++checked;
        }
        // Reprojected: the point lies within its error box of the sphere (distance to the sphere in
        // double-double, far below the bound's scale).
        const rs::surface_point<double> q = rs::hit_point(r, s, h.t, true);
        const long double dx = (long double)q.point.x - g.centre.x, dy = (long double)q.point.y - g.centre.y,
                          dz = (long double)q.point.z - g.centre.z;
        const long double distance = std::fabs(std::sqrt(dx * dx + dy * dy + dz * dz) - (long double)g.radius);
        const long double box = std::sqrt((long double)q.error.x * q.error.x + (long double)q.error.y * q.error.y +
                                          (long double)q.error.z * q.error.z);
        const long double slack = 0x1p-60L * (std::fabs(dx) + std::fabs(dy) + std::fabs(dz) + g.radius);
        EXPECT_LE(distance, box + slack) << "seed " << seed - 3 << " case " << i;
    }
    EXPECT_GT(checked, 1000);
}

}  // namespace
}  // namespace rayverify

namespace rayverify {
namespace {

// ---------------------------------------------------------------------------
// Vendored: the header copied alone into an empty directory, built with
// -Wall -Wextra -Wpedantic -Werror and with FMA contraction allowed (the
// double path's products then use std::fma): the same answers, bit for bit,
// as this build's (which the tests above check against the oracle).

// The exact path's expansions live in fixed arrays whose capacities follow
// from Shewchuk's bounds (a sum of m and n components has at most m + n, a
// product at most 2mn). At the bound: operands whose components lie far
// apart (an unbounded exponent allows it) fill a sum and a product exactly.
TEST(RobustSphereExpansions, SumsAndProductsReachTheirCapacityAndNoMore) {
    using namespace rs::detail;
    const auto spread = [](double x, int high, int low) {  // x·2^high + x·2^low, two components
        expansion<2> e;
        e.push_back(to_xfloat(x, low));
        e.push_back(to_xfloat(x, high));
        return e;
    };
    const double odd = 1 + 0x1p-30 + 0x1p-52;  // a full significand: each product has a low part
    const expansion<2> e = spread(odd, 0, -500), f = spread(odd, 0, -2000);
    const expansion<4> s = sum(e, f);
    static_assert(decltype(s)::capacity == 4);
    EXPECT_EQ(s.size, 3);  // the two leading components add up to one
    const expansion<4> s2 = sum(e, spread(odd, -1000, -1500));
    EXPECT_EQ(s2.size, 4);
    const expansion<8> p = product(e, f);
    static_assert(decltype(p)::capacity == 8);
    EXPECT_EQ(p.size, 8);  // four products 2^0, 2^-500, 2^-2000, 2^-2500, each hi + lo
    // The value is exact: the top component is RN of the whole, its sign the product's.
    EXPECT_EQ(sign(p), 1);
    EXPECT_EQ(p.back().m, to_xfloat(odd * odd).m);
    // The solver's stated capacities: Δ′'s 408 and a comparison's 218 and 36.
    static_assert(decltype(product(expansion<8>{}, expansion<8>{}))::capacity == 128);
    static_assert(decltype(sum(product(expansion<6>{}, expansion<2>{}), expansion<384>{}))::capacity == 408);
    static_assert(decltype(sum(product(expansion<6>{}, expansion<2>{}), expansion<12>{}))::capacity == 36);
    // The most spread inputs a double allows still fit (o − c of 2^1000 and
    // 2^-1000, a direction of 2^-1074 and 2^1023, r near the overflow).
    const ray_sphere<double> extreme = geometry({0x1p1000, -0x1p-1000, 0x1.fffffffffffffp1000},
                                                {0x1p-1074, 0x1.fffffffffffffp1023, -0x1.8p-1000},
                                                {-0x1p-1000, 0x1p1000, 0x1.8p-1074}, 0x1.fffffffffffffp1022);
    SCOPED_TRACE(show(extreme));
    EXPECT_EQ(check_case(extreme), "");
}

TEST(RobustSphereVendored, HeaderAloneWithFmaContractionGivesTheSameAnswers) {
    if (!__builtin_cpu_supports("fma")) GTEST_SKIP() << "this CPU has no FMA to run an -mfma build on";
    namespace fs = std::filesystem;
    const test_support::scratch_directory dir_scratch("rayverify_vendored");
    const fs::path& dir = dir_scratch.path();
    const fs::path source(RAYVERIFY_SOURCE_DIR);
    fs::copy_file(source / "src/intersectors/robust_sphere.h", dir / "robust_sphere.h");
    fs::copy_file(source / "tests/robust_vendored/answers.h", dir / "answers.h");
    fs::copy_file(source / "tests/robust_vendored/main.cpp", dir / "main.cpp");
    const auto built = test_support::run_shell(std::string(RAYVERIFY_CXX_COMPILER) +
                                               " -std=c++17 -O2 -mfma -ffp-contract=fast -Wall -Wextra -Wpedantic "
                                               "-Werror -I " + dir.string() + " " + (dir / "main.cpp").string() + " -o " +
                                               (dir / "vendored").string());
    ASSERT_EQ(built.exit_code, 0) << built.output;

    // Cases valid in both precisions, with intervals around their roots.
    const std::uint64_t seed = seed_from_env() + 4;
    random_cases gen{std::mt19937_64(seed)};
    std::string input, expected;
    int cases = 0;
    while (cases < 3000) {
        const ray_sphere<double> g = gen.next();
        if (validity<float>(g) != invalid_reason::none || validity<double>(g) != invalid_reason::none) continue;
        const exact_solution e = solve_exact(g, precision::binary64);
        const double t = e.cls == line_class::miss ? 1.0 : e.near_root.rounded;
        const double interval[][2] = {{0, INFINITY}, {t, INFINITY}, {std::nextafter(t, -INFINITY), 2 * std::fabs(t)}};
        const auto& [tmin, tmax] = interval[cases % 3];
        if (!std::isfinite(tmin) || std::fabs(tmin) > 1e30 || (std::isfinite(tmax) && std::fabs(tmax) > 1e30)) continue;
        const double v[12] = {g.origin.x, g.origin.y, g.origin.z, g.direction.x, g.direction.y, g.direction.z,
                              g.centre.x, g.centre.y, g.centre.z, g.radius, tmin, tmax};
        char line[512];
        std::snprintf(line, sizeof line, "%a %a %a %a %a %a %a %a %a %a %a %a\n", v[0], v[1], v[2], v[3], v[4], v[5],
                      v[6], v[7], v[8], v[9], v[10], v[11]);
        input += line;
        expected += robust_answers<float>(v) + "\n" + robust_answers<double>(v) + "\n";
        ++cases;
    }
    { std::ofstream(dir / "cases.txt") << input; }
    const auto ran = test_support::run_shell((dir / "vendored").string() + " < " + (dir / "cases.txt").string());
    ASSERT_EQ(ran.exit_code, 0) << ran.output.substr(0, 2000);
    std::istringstream got(ran.output), want(expected), lines(input);
    std::string g, w, c;
    for (int i = 0; std::getline(want, w); ++i) {
        ASSERT_TRUE(std::getline(got, g)) << "vendored build stopped at line " << i;
        if (i % 2 == 0) std::getline(lines, c);
        EXPECT_EQ(g, w) << (i % 2 ? "double" : "float") << " case " << i / 2 << " (seed " << seed - 4 << "): " << c;
    }
}

}  // namespace
}  // namespace rayverify
