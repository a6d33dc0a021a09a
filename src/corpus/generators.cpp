#include "corpus/generators.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <span>
#include <random>
#include <type_traits>
#include <string>
#include <utility>

#include "core/hash.h"
#include "core/input_error.h"
#include "core/spelling.h"
#include "corpus/mersenne_twister.h"

namespace rayverify {

namespace {

using v3 = vec3<double>;

// ---------------------------------------------------------------------------
// Randomness: raw mt19937_64 outputs (corpus/mersenne_twister.h), converted by hand.
// A case is its draws in order, so each draw is a statement of its own (or an
// element of a braced list, which C++ evaluates left to right): two draws in
// the arguments of one call, or the operands of one operator, are made in an
// order each compiler chooses (g++ and clang++ differed, and regenerated
// different corpora from one manifest).

// splitmix64: the golden-ratio step, then the finaliser.
std::uint64_t splitmix64(std::uint64_t x) { return splitmix64_finalise(x + 0x9e3779b97f4a7c15ULL); }

class random_source {
public:
    // One engine per case, so a case depends on (family, seed, index) only.
    random_source(std::string_view family, std::uint64_t seed, std::uint64_t index)
        : engine_(splitmix64(splitmix64(fnv1a(family) ^ seed) ^ index)) {}

    // Uniform on [0, 1) with step 2^-53: 53 random bits × 2^-53.
    double unit() { return std::ldexp(static_cast<double>(engine_() >> 11), -53); }

    double uniform(double lo, double hi) { return lo + (hi - lo) * unit(); }

    // Uniform on [lo, hi] without bias: the low partial block of 2^64 is rejected.
    std::int64_t integer(std::int64_t lo, std::int64_t hi) {
        const std::uint64_t span = static_cast<std::uint64_t>(hi - lo) + 1;
        const std::uint64_t threshold = (0 - span) % span;
        for (;;) {
            const std::uint64_t x = engine_();
            if (x >= threshold) return lo + static_cast<std::int64_t>(x % span);
        }
    }

    bool coin() { return (engine_() >> 63) != 0; }

    // Several sources' engines seeded side by side, before any draws.
    static void seed_together(std::span<random_source* const> sources) {
        std::array<lazily_seeded_mt19937_64*, 8> engines{};
        for (std::size_t k = 0; k < sources.size(); ++k) engines[k] = &sources[k]->engine_;
        lazily_seeded_mt19937_64::seed_together(std::span(engines.data(), sources.size()));
    }

private:
    lazily_seeded_mt19937_64 engine_;
};

// Uniform in the cube [lo, hi)^3, components drawn x, then y, then z.
v3 cube_point(random_source& g, double lo, double hi) {
    const double x = g.uniform(lo, hi);
    const double y = g.uniform(lo, hi);
    const double z = g.uniform(lo, hi);
    return {x, y, z};
}

// Uniform in the closed unit ball: rejection from the cube [-1, 1)^3.
v3 ball_point(random_source& g) {
    for (;;) {
        const v3 p = cube_point(g, -1, 1);
        if (length_squared(p) <= 1) return p;
    }
}

// d / √(d·d), componentwise in double.
v3 normalised(v3 d) {
    const double n = std::sqrt(length_squared(d));
    return {d.x / n, d.y / n, d.z / n};
}

// The promise of every unit-direction family (4 units of 2^-53).
bool unit_enough(v3 d) { return std::fabs(length_squared(d) - 1) <= 0x1p-51; }

// Uniform random direction: a ball point away from 0, normalised; the rare
// normalisation that misses unit_enough is redrawn.
v3 random_unit(random_source& g) {
    for (;;) {
        const v3 p = ball_point(g);
        if (length_squared(p) < 0x1p-20) continue;
        const v3 d = normalised(p);
        if (unit_enough(d)) return d;
    }
}

// Normalised direction from `from` towards `to`, if it is usable.
bool unit_towards(v3 from, v3 to, v3& out) {
    const v3 v = to - from;
    if (!(length_squared(v) > 1e-12)) return false;
    out = normalised(v);
    return unit_enough(out);
}

// ---------------------------------------------------------------------------
// Integer constructions, scaled by exact powers of two.

using i3 = std::array<std::int64_t, 3>;

i3 add(const i3& a, const i3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
i3 scaled(std::int64_t s, const i3& a) { return {s * a[0], s * a[1], s * a[2]}; }
i3 cross(const i3& a, const i3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

// v·2^k, exact while |v| < 2^53 (all our integers stay below 2^22).
v3 dyadic(const i3& v, int k) {
    return {std::ldexp(static_cast<double>(v[0]), k), std::ldexp(static_cast<double>(v[1]), k),
            std::ldexp(static_cast<double>(v[2]), k)};
}

// A translation of random magnitude: each component in [−2^e, 2^e], e in [0, 20].
i3 random_offset(random_source& g) {
    const std::int64_t bound = std::int64_t{1} << g.integer(0, 20);
    const std::int64_t x = g.integer(-bound, bound);
    const std::int64_t y = g.integer(-bound, bound);
    const std::int64_t z = g.integer(-bound, bound);
    return {x, y, z};
}

// u² + v² = w² by Euclid: (m² − n², 2mn, m² + n²)·j, 40 ≥ m > n > 0, j in [1, 3].
struct triple {
    std::int64_t u, v, w;
};
triple pythagorean_triple(random_source& g) {
    const std::int64_t m = g.integer(2, 40);
    const std::int64_t n = g.integer(1, m - 1);
    const std::int64_t j = g.integer(1, 3);
    triple t{j * (m * m - n * n), j * 2 * m * n, j * (m * m + n * n)};
    if (g.coin()) std::swap(t.u, t.v);
    return t;
}

// x² + y² + z² = w² from the quaternion-norm identity:
// (m²+n²−p²−q², 2(mq+np), 2(nq−mp)), w = m²+n²+p²+q², m, n, p, q in [−b, b],
// not all zero (so w > 0).
struct quadruple {
    i3 v;
    std::int64_t w;
};
quadruple pythagorean_quadruple(random_source& g, std::int64_t b) {
    for (;;) {
        const std::int64_t m = g.integer(-b, b);
        const std::int64_t n = g.integer(-b, b);
        const std::int64_t p = g.integer(-b, b);
        const std::int64_t q = g.integer(-b, b);
        const std::int64_t w = m * m + n * n + p * p + q * q;
        if (w == 0) continue;
        return {{m * m + n * n - p * p - q * q, 2 * (m * q + n * p), 2 * (n * q - m * p)}, w};
    }
}

// An exactly tangent line, in integers: centre c, perpendicular offset f′
// (|f′| = w, f′·d = 0), integer direction d and tangent parameter t, so that
// o = c + f′ − t·d touches the sphere at o + t·d = c + f′. Inputs are these
// integers × 2^k (d unscaled), so the tangent root is t·2^k.
struct tangent_construction {
    i3 centre, perpendicular, direction;
    std::int64_t w, t;
    int k;

    ray_sphere<double> geometry() const {
        const i3 origin = add(add(centre, perpendicular), scaled(-t, direction));
        return {dyadic(origin, k), dyadic(direction, 0), dyadic(centre, k),
                std::ldexp(static_cast<double>(w), k)};
    }
};

// A tangent parameter: 0 (the origin at the tangent point) one time in four,
// otherwise uniform in [−bound, bound].
std::int64_t tangent_parameter(random_source& g, std::int64_t bound) {
    return g.integer(0, 3) == 0 ? 0 : g.integer(-bound, bound);
}

// `closest`: t = 0 always (the origin is the tangent point: b = 0 and Δ = 0),
// without drawing the tangent parameter.
tangent_construction make_tangent(random_source& g, bool closest = false) {
    tangent_construction c{};
    c.k = static_cast<int>(g.integer(-20, 20));
    c.centre = random_offset(g);
    if (g.coin()) {
        // Unit axis direction ±e_a; f′ from a triple in the other two axes.
        const int axis = static_cast<int>(g.integer(0, 2));
        const triple tr = pythagorean_triple(g);
        c.direction[axis] = g.coin() ? 1 : -1;
        c.perpendicular[(axis + 1) % 3] = g.coin() ? tr.u : -tr.u;
        c.perpendicular[(axis + 2) % 3] = g.coin() ? tr.v : -tr.v;
        c.w = tr.w;
        c.t = closest ? 0 : tangent_parameter(g, 4 * tr.w);
    } else {
        // Integer direction d = f′ × g ⟂ f′, f′ from a quadruple.
        const quadruple q = pythagorean_quadruple(g, 6);
        i3 d{};
        while (d == i3{}) {
            const std::int64_t x = g.integer(-6, 6);
            const std::int64_t y = g.integer(-6, 6);
            const std::int64_t z = g.integer(-6, 6);
            d = cross(q.v, {x, y, z});
        }
        c.perpendicular = q.v;
        c.direction = d;
        c.w = q.w;
        c.t = closest ? 0 : tangent_parameter(g, 16);
    }
    return c;
}

// ---------------------------------------------------------------------------
// The families.

ray_sphere<double> make_uniform(random_source& g) {
    const v3 origin = cube_point(g, -10, 10);
    const v3 centre = cube_point(g, -10, 10);
    const double radius = g.uniform(0.1, 5);
    v3 direction;
    for (;;) {
        const v3 aim = centre + (2 * radius) * ball_point(g);
        if (unit_towards(origin, aim, direction)) break;
    }
    return {origin, direction, centre, radius};
}

ray_sphere<double> make_tangent_exact(random_source& g) { return make_tangent(g).geometry(); }

ray_sphere<double> make_near_tangent(random_source& g) {
    const tangent_construction c = make_tangent(g);
    ray_sphere<double> s = c.geometry();
    const double towards = g.coin() ? std::numeric_limits<double>::infinity()
                                    : -std::numeric_limits<double>::infinity();
    const std::int64_t what = g.integer(0, 2);
    if (what == 0) {
        s.radius = std::nextafter(s.radius, towards);
        return s;
    }
    // A coordinate i with f′_i ≠ 0: the squared distance of the line from the
    // centre moves by 2δf′_i + O(δ²) ≠ 0, so the line is never tangent.
    std::array<int, 3> moving{};
    int n = 0;
    for (int i = 0; i < 3; ++i)
        if (c.perpendicular[i] != 0) moving[n++] = i;
    const int i = moving[g.integer(0, n - 1)];
    v3& point = what == 1 ? s.origin : s.centre;
    double* coordinate = i == 0 ? &point.x : (i == 1 ? &point.y : &point.z);
    *coordinate = std::nextafter(*coordinate, towards);
    return s;
}

// 10^k, exact for 0 ≤ k ≤ 22.
double power_of_ten(int k) {
    double p = 1;
    for (int i = 0; i < k; ++i) p *= 10;
    return p;
}

// Rounds to T and back: the identity for double, float snapping for float.
// The volatile store is needed: GCC 12 at -O2 (SLP vectorizer) drops the
// double → float → double round trip on some lanes of a struct copy.
template <class T>
double snap(double x) {
    const volatile T rounded = static_cast<T>(x);
    return static_cast<double>(rounded);
}
template <class T>
v3 snap(v3 v) {
    return {snap<T>(v.x), snap<T>(v.y), snap<T>(v.z)};
}

// A small sphere far away, D/r log-uniform on [10^e_lo, 10^(e_hi+1)). For T =
// float, o, c and r are snapped to float before d is aimed, so the aim is
// computed for the inputs a float intersector sees.
template <class T>
ray_sphere<double> far_sphere_case(random_source& g, std::int64_t e_lo, std::int64_t e_hi) {
    const double radius = snap<T>(g.uniform(0.5, 2));

    // D/r = x·10^e: e uniform in [e_lo, e_hi], x in [1, 10) with density ∝ 1/x
    // (uniform x accepted with probability 1/x), so D/r is log-uniform.
    const int e = static_cast<int>(g.integer(e_lo, e_hi));
    double x;
    do x = g.uniform(1, 10);
    while (!(g.unit() * x < 1));
    const double distance = x * power_of_ten(e) * radius;

    // One end of the line of sight near the coordinate origin, the other far.
    const v3 sight = random_unit(g);
    const v3 near_end = cube_point(g, -1, 1);
    const bool origin_near = g.coin();
    const v3 origin = snap<T>(origin_near ? near_end : near_end - distance * sight);
    const v3 centre = snap<T>(origin_near ? near_end + distance * sight : near_end);

    // Aim at c + ρ·w, ρ/r uniform in [0, 1.5), w a unit vector ⟂ the line of sight.
    v3 direction;
    for (;;) {
        const v3 s = random_unit(g);
        const v3 across = s - dot(s, sight) * sight;
        if (length_squared(across) < 0.01) continue;
        const v3 w = normalised(across);
        const double rho = 1.5 * radius * g.unit();
        if (unit_towards(origin, centre + rho * w, direction)) break;
    }
    return {origin, direction, centre, radius};
}

ray_sphere<double> make_far_sphere(random_source& g) { return far_sphere_case<double>(g, 1, 8); }

ray_sphere<double> make_on_surface(random_source& g) {
    const int k = static_cast<int>(g.integer(-20, 20));
    const i3 centre = random_offset(g);
    const quadruple q = pythagorean_quadruple(g, 8);
    const bool entering = g.coin();

    // d·f is kept away from 0 (|cos| ≥ 2^-16), so its sign is exact in double
    // and survives rounding d to float; negating d is exact.
    const v3 f = dyadic(q.v, 0);
    const double w = static_cast<double>(q.w);
    v3 direction;
    for (;;) {
        direction = random_unit(g);
        const double df = dot(direction, f);
        if (std::fabs(df) < 0x1p-16 * w) continue;
        if ((df < 0) != entering) direction = -1.0 * direction;
        break;
    }
    return {dyadic(add(centre, q.v), k), direction, dyadic(centre, k),
            std::ldexp(w, k)};
}

ray_sphere<double> make_inside(random_source& g) {
    const v3 centre = cube_point(g, -10, 10);
    const double radius = g.uniform(0.1, 5);
    v3 origin = centre;
    switch (g.integer(0, 2)) {
        case 0: break;  // at the centre
        case 1: origin = centre + (0.9 * radius) * ball_point(g); break;
        default: {
            // |f| = r(1 − 2^-j): the gap r·2^-j ≥ 0.1·2^-40 ≈ 9e-14 is ≥ 50× the
            // rounding of c + f (|c_i| ≤ 10) and of the unit vector.
            const int j = static_cast<int>(g.integer(10, 40));
            const double scale = radius * (1 - std::ldexp(1.0, -j));
            origin = centre + scale * random_unit(g);
        }
    }
    return {origin, random_unit(g), centre, radius};
}

// ---------------------------------------------------------------------------
// Edge-case families (generator version 1). Each maker is a template on the
// precision T whose inputs it builds: T = float makes the "_f32" variant,
// whose every input is exactly a float, so float intersectors see exact inputs.

// Every input rounded to T (exact for T = double).
template <class T>
ray_sphere<double> exactly_in(const ray_sphere<double>& s) {
    return {snap<T>(s.origin), snap<T>(s.direction), snap<T>(s.centre), snap<T>(s.radius)};
}

// One step of T's ulp from x towards ±infinity.
template <class T>
double ulp_step(double x, bool up) {
    const T inf = std::numeric_limits<T>::infinity();
    return static_cast<double>(std::nextafter(static_cast<T>(x), up ? inf : -inf));
}

// A tangent_exact line moved by one ulp of T to one known side. The squared
// distance of the line from c is w² exactly; moving r up (down) puts the line
// inside (outside); moving origin coordinate i by δ changes the squared
// distance by 2δf′_i + δ²|P e_i|² (P projects ⟂ d), moving centre coordinate
// i by δ changes it by −2δf′_i + δ²|P e_i|². Coordinates are integers below
// 2^22 times 2^k and |f′_i| ≥ 2^k, so |δ| ≤ 2^(k−2) even in float and the
// linear term decides the side.
template <class T>
ray_sphere<double> nudged_tangent(random_source& g, bool inside) {
    const tangent_construction c = make_tangent(g);
    ray_sphere<double> s = c.geometry();
    const std::int64_t what = g.integer(0, 2);
    if (what == 0) {
        s.radius = ulp_step<T>(s.radius, inside);
        return s;
    }
    std::array<int, 3> moving{};
    int n = 0;
    for (int i = 0; i < 3; ++i)
        if (c.perpendicular[i] != 0) moving[n++] = i;
    const int i = moving[g.integer(0, n - 1)];
    const bool positive = c.perpendicular[i] > 0;
    // Origin: inside needs δf′_i < 0; centre: inside needs δf′_i > 0.
    const bool up = what == 1 ? (positive != inside) : (positive == inside);
    v3& point = what == 1 ? s.origin : s.centre;
    double* coordinate = i == 0 ? &point.x : (i == 1 ? &point.y : &point.z);
    *coordinate = ulp_step<T>(*coordinate, up);
    return s;
}

template <class T>
ray_sphere<double> make_near_tangent_hit(random_source& g) { return nudged_tangent<T>(g, true); }
template <class T>
ray_sphere<double> make_near_tangent_miss(random_source& g) { return nudged_tangent<T>(g, false); }

ray_sphere<double> make_tangent_closest(random_source& g) { return make_tangent(g, true).geometry(); }

// The sphere behind the origin: d points from a point p with |p − c| ≤ 0.9r
// to o with |o − c| ≥ 1.5r, so (o − c)·(o − p) > 0 and both roots are < 0.
template <class T>
ray_sphere<double> make_behind(random_source& g) {
    const v3 centre = snap<T>(cube_point(g, -10, 10));
    const double radius = snap<T>(g.uniform(0.1, 5));
    const double distance = radius * g.uniform(1.5, 20);
    const v3 origin = snap<T>(centre + distance * random_unit(g));
    v3 direction;
    for (;;) {
        const v3 aim = centre + (0.9 * radius) * ball_point(g);
        if (unit_towards(aim, origin, direction)) break;
    }
    return exactly_in<T>({origin, direction, centre, radius});
}

// Far spheres over a wider range than far_sphere: D/r from 10^2 to 10^15 in
// double; 10^2 to 10^7 in float (beyond, rounding d to float alone moves the
// line by more than r).
template <class T>
ray_sphere<double> make_far_sphere_wide(random_source& g) {
    return exactly_in<T>(far_sphere_case<T>(g, 2, std::is_same_v<T, float> ? 6 : 14));
}

// A sphere of radius r = u·2^-j, u in [1, 2), j in [20, 40] (float: [6, 14]),
// centre within 4r of the coordinate origin (so c itself is exact to ~2^-53 r),
// seen from o in [-8, 8]^3 and aimed at c + ρw, ρ/r uniform in [0, 1.5).
template <class T>
ray_sphere<double> make_tiny_sphere(random_source& g) {
    const bool single = std::is_same_v<T, float>;
    const int j = static_cast<int>(g.integer(single ? 6 : 20, single ? 14 : 40));
    const double radius = snap<T>(std::ldexp(g.uniform(1, 2), -j));
    const v3 centre = snap<T>(radius * cube_point(g, -4, 4));
    v3 origin;
    do origin = snap<T>(cube_point(g, -8, 8));
    while (length_squared(origin - centre) < 1);
    const v3 sight = normalised(centre - origin);
    v3 direction;
    for (;;) {
        const v3 s = random_unit(g);
        const v3 across = s - dot(s, sight) * sight;
        if (length_squared(across) < 0.01) continue;
        const v3 aim = centre + (1.5 * radius * g.unit()) * normalised(across);
        if (unit_towards(origin, aim, direction)) break;
    }
    return exactly_in<T>({origin, direction, centre, radius});
}

// RTG ch.7 fig. 7-4: a huge sphere as a ground plane, the origin at height h
// above it. R = u·2^e, e in [8, 30] (float: [8, 16]); h = u·2^j, j in [-4, 4]
// (float: [-2, 4]), well above the rounding of c. Half the directions are
// steep (almost always two roots close to the origin: the near root cancels),
// half graze the horizon with slope ±u·2√(2h/R) (hits and misses).
template <class T>
ray_sphere<double> make_ground_plane(random_source& g) {
    const bool single = std::is_same_v<T, float>;
    const int e = static_cast<int>(g.integer(8, single ? 16 : 30));
    const double big = snap<T>(std::ldexp(g.uniform(1, 2), e));
    const int j = static_cast<int>(g.integer(single ? -2 : -4, 4));
    const double height = std::ldexp(g.uniform(1, 2), j);
    const v3 up = random_unit(g);
    const v3 origin = snap<T>(cube_point(g, -1, 1));
    const v3 centre = snap<T>(origin - (big + height) * up);
    v3 horizontal;
    for (;;) {
        const v3 s = random_unit(g);
        const v3 across = s - dot(s, up) * up;
        if (length_squared(across) < 0.01) continue;
        horizontal = normalised(across);
        break;
    }
    double slope;
    if (g.coin()) {
        slope = g.uniform(-4, 1);  // mostly downwards
    } else {
        const double critical = std::sqrt(2 * height / big);
        const double sign = g.coin() ? 1 : -1;
        slope = sign * 2 * critical * g.unit();
    }
    const v3 direction = normalised(horizontal + slope * up);
    return exactly_in<T>({origin, direction, centre, big});
}

// A uniform-like scene (o, c in a box of side 20, r in [0.5, 2], d aimed at the
// ball of radius 2r around c) translated by T with |T_i| up to 10^e, e in
// [6, 12] (float: [4, 7]); o and c are rounded there before d is aimed.
template <class T>
ray_sphere<double> make_world_offset(random_source& g) {
    const bool single = std::is_same_v<T, float>;
    const int e = static_cast<int>(g.integer(single ? 4 : 6, single ? 7 : 12));
    const v3 offset = power_of_ten(e) * cube_point(g, -1, 1);
    const v3 origin = snap<T>(offset + cube_point(g, -10, 10));
    const v3 centre = snap<T>(offset + cube_point(g, -10, 10));
    const double radius = snap<T>(g.uniform(0.5, 2));
    v3 direction;
    for (;;) {
        const v3 aim = centre + (2 * radius) * ball_point(g);
        if (unit_towards(origin, aim, direction)) break;
    }
    return exactly_in<T>({origin, direction, centre, radius});
}

// A uniform case with d scaled by 2^k, k in [-200, 200] (float: [-100, 100]):
// exact scaling, so the class is the unscaled case's and every root is scaled
// by 2^-k; a = d·d over- or underflows in the intersector, not in the input.
template <class T>
ray_sphere<double> make_scaled_direction(random_source& g) {
    const bool single = std::is_same_v<T, float>;
    ray_sphere<double> s = exactly_in<T>(make_uniform(g));
    const int k = static_cast<int>(g.integer(single ? -100 : -200, single ? 100 : 200));
    s.direction = std::ldexp(1.0, k) * s.direction;
    return s;
}

// A uniform case with o, c and r scaled by 2^k (exact: the class is kept, every
// root scales by 2^k): k in [990, 1010] puts coordinates within 2^-10 of the
// double overflow threshold, where f·f and b² overflow (float: k in [100, 120]).
template <class T>
ray_sphere<double> make_near_overflow(random_source& g) {
    const bool single = std::is_same_v<T, float>;
    ray_sphere<double> s = exactly_in<T>(make_uniform(g));
    const int k = static_cast<int>(g.integer(single ? 100 : 990, single ? 120 : 1010));
    s.origin = std::ldexp(1.0, k) * s.origin;
    s.centre = std::ldexp(1.0, k) * s.centre;
    s.radius = std::ldexp(s.radius, k);
    return s;
}

// A uniform case with o, c and r scaled into the subnormal range, 2^-k with k
// in [1050, 1070] (float: [130, 145]): the scaling rounds (fewer significant
// bits are left), so the oracle decides the class; every product underflows.
template <class T>
ray_sphere<double> make_subnormal(random_source& g) {
    const bool single = std::is_same_v<T, float>;
    const ray_sphere<double> u = exactly_in<T>(make_uniform(g));
    const int k = -static_cast<int>(g.integer(single ? 130 : 1050, single ? 145 : 1070));
    ray_sphere<double> s = u;
    s.origin = {snap<T>(std::ldexp(u.origin.x, k)), snap<T>(std::ldexp(u.origin.y, k)),
                snap<T>(std::ldexp(u.origin.z, k))};
    s.centre = {snap<T>(std::ldexp(u.centre.x, k)), snap<T>(std::ldexp(u.centre.y, k)),
                snap<T>(std::ldexp(u.centre.z, k))};
    s.radius = snap<T>(std::ldexp(u.radius, k));
    return s;
}

// A secondary ray spawned from a hit point computed in T (the
// self-intersection case). A primary ray from outside (|o − c| in [1.5r, 20r])
// aimed inside (line distance ≤ 0.9r) is solved in T with the Hearn–Baker
// discriminant and stable roots; p = o + t·d is rounded in T. From p, a quarter
// each: the reflection (leaving), the primary direction continued (entering),
// a random direction leaving or entering with |d·n| ≥ 1/8. The line through p
// crosses the surface at an angle, so it has two roots, one within rounding
// of 0 whose sign is the self-hit question.
template <class T>
ray_sphere<double> make_secondary_ray(random_source& g) {
    const ray_sphere<double> primary = make_behind<T>(g);  // d points away from the sphere
    const vec3<T> o = vec3_cast<T>(primary.origin);
    const vec3<T> d = T(-1) * vec3_cast<T>(primary.direction);
    const vec3<T> c = vec3_cast<T>(primary.centre);
    const T r = static_cast<T>(primary.radius);

    // Nearest root: b′ = −f·d > 0, Δ = r² − |f + (b′/a)d|², q = b′ + √(aΔ), t = C/q.
    const vec3<T> f = o - c;
    const T a = dot(d, d);
    const T b = -dot(f, d);
    const vec3<T> perpendicular = f + (b / a) * d;
    const T delta = r * r - dot(perpendicular, perpendicular);
    const T q = b + std::sqrt(a * (delta > 0 ? delta : T(0)));
    const T t = (dot(f, f) - r * r) / q;
    const vec3<T> p = o + t * d;
    const vec3<T> pc = p - c;
    const vec3<T> n = (T(1) / std::sqrt(dot(pc, pc))) * pc;

    vec3<T> out;
    switch (g.integer(0, 3)) {
        case 0: out = d - (T(2) * dot(d, n)) * n; break;
        case 1: out = d; break;
        default: {
            const bool leaving = g.coin();
            for (;;) {
                const v3 s = random_unit(g);
                const T cosine = dot(vec3_cast<T>(s), n);
                if (cosine < T(0.125) && cosine > T(-0.125)) continue;
                out = (cosine > 0) == leaving ? vec3_cast<T>(s) : T(-1) * vec3_cast<T>(s);
                break;
            }
        }
    }
    const vec3<T> unit = (T(1) / std::sqrt(dot(out, out))) * out;
    return exactly_in<T>({vec3_cast<double>(p), vec3_cast<double>(unit), primary.centre, primary.radius});
}

// ---------------------------------------------------------------------------
// Casts with range ends: a line with two roots that are exact integers ×
// 2^k, and an interval whose ends sit on them, one ulp off, around them or
// at no distance from each other. Exact by construction, in float too.

// A family's case: the ray and the sphere, and the interval when the family gives one.
struct generated_cast {
    ray_sphere<double> geometry;
    std::optional<double> tmin{}, tmax{};
    std::optional<vec3<double>> segment_end{};  // a segment from geometry.origin (p0) to here (p1)
};

// u² + v² = w² with small legs (m ≤ 8, no multiple): every input of a chord
// construction then stays below 2^24, exact in float.
triple small_triple(random_source& g) {
    const std::int64_t m = g.integer(2, 8);
    const std::int64_t n = g.integer(1, m - 1);
    triple t{m * m - n * n, 2 * m * n, m * m + n * n};
    if (g.coin()) std::swap(t.u, t.v);
    return t;
}

// A line meeting the sphere at two exact parameters, in integers: a
// direction d with integer length w_d (±e_a, or a triple's legs in a
// coordinate plane), a unit of length w_d perpendicular to it, e, and a
// triple (P, Q, R): the line passes P·e from c, the sphere has radius R·w_d,
// so the half chord is Q·w_d = Q·|d| and the roots are t_mid ∓ Q. Inputs are
// these integers × 2^k (d unscaled), the roots (t_mid ∓ Q)·2^k.
struct chord_construction {
    i3 centre{}, perpendicular{}, direction{};
    std::int64_t radius = 0, t_mid = 0, half = 0;
    int k = 0;

    ray_sphere<double> geometry() const {
        const i3 origin = add(add(centre, perpendicular), scaled(-t_mid, direction));
        return {dyadic(origin, k), dyadic(direction, 0), dyadic(centre, k),
                std::ldexp(static_cast<double>(radius), k)};
    }
    double root(bool near) const { return std::ldexp(static_cast<double>(near ? t_mid - half : t_mid + half), k); }
};

// `origin_on_surface`: t_mid = ±Q, so that one root is exactly 0 (the cast starts on the surface).
chord_construction make_chord(random_source& g, bool origin_on_surface) {
    chord_construction c;
    c.k = static_cast<int>(g.integer(-12, 12));
    c.centre = {g.integer(-1024, 1024), g.integer(-1024, 1024), g.integer(-1024, 1024)};
    const int axis = static_cast<int>(g.integer(0, 2));
    const int next = (axis + 1) % 3, last = (axis + 2) % 3;
    std::int64_t length = 1;
    i3 unit_across{};
    if (g.coin()) {
        c.direction[axis] = g.coin() ? 1 : -1;
        unit_across[next] = g.coin() ? 1 : -1;
    } else {
        const triple d = small_triple(g);
        c.direction[axis] = g.coin() ? d.u : -d.u;
        c.direction[next] = g.coin() ? d.v : -d.v;
        length = d.w;
        // (−d_next, d_axis, 0) or the third axis times w_d: both ⟂ d, both of length w_d.
        if (g.coin()) {
            unit_across[axis] = -c.direction[next];
            unit_across[next] = c.direction[axis];
        } else {
            unit_across[last] = g.coin() ? d.w : -d.w;
        }
    }
    const triple chord = small_triple(g);
    c.perpendicular = scaled(chord.u, unit_across);
    c.radius = chord.w * length;
    c.half = chord.v;
    c.t_mid = origin_on_surface ? (g.coin() ? chord.v : -chord.v) : g.integer(-4 * chord.w, 4 * chord.w);
    return c;
}

// x moved `steps` ulps of T (up for steps > 0).
template <class T>
double ulps_from(double x, int steps) {
    for (int i = 0; i < std::abs(steps); ++i) x = ulp_step<T>(x, steps > 0);
    return x;
}

// An end exactly on a root, one ulp of T inside or outside it, or two ends a
// few ulps around it (straddling); the other end beyond both roots or between
// them; a sixth of the casts start on the surface (a root at 0, tmin = 0).
template <class T>
generated_cast make_range_end(random_source& g) {
    const bool on_surface = g.integer(0, 5) == 0;
    const chord_construction c = make_chord(g, on_surface);
    const double near = c.root(true), far = c.root(false), span = far - near;
    generated_cast out{c.geometry()};
    if (on_surface) {
        out.tmin = 0.0;
        out.tmax = ulps_from<T>(near == 0 ? far : span, static_cast<int>(g.integer(-1, 1)));
        return out;
    }
    const bool at_near = g.coin();
    const double root = at_near ? near : far;
    switch (g.integer(0, 2)) {
        case 0: {  // the upper end on the root, or one ulp off
            out.tmax = ulps_from<T>(root, static_cast<int>(g.integer(-1, 1)));
            out.tmin = at_near || g.coin() ? near - span : near + span / 2;
            break;
        }
        case 1: {  // the lower end on the root, or one ulp off
            out.tmin = ulps_from<T>(root, static_cast<int>(g.integer(-1, 1)));
            out.tmax = !at_near || g.coin() ? far + span : near + span / 2;
            break;
        }
        default: {  // both ends within four ulps of the root, on either side
            const int below = static_cast<int>(g.integer(1, 4));
            const int above = static_cast<int>(g.integer(1, 4));
            out.tmin = ulps_from<T>(root, -below);
            out.tmax = ulps_from<T>(root, above);
        }
    }
    return out;
}

// A tangent_exact line, or one moved one double ulp off tangency (r up or
// down), cast up to its tangent point: the upper end exactly at t_tan, or
// one ulp before or after it; the lower end 2^k before t_tan, or at 0 when
// that is earlier still.
generated_cast make_grazing_end(random_source& g) {
    const tangent_construction c = make_tangent(g);
    ray_sphere<double> geometry = c.geometry();
    const std::int64_t nudge = g.integer(-1, 1);
    if (nudge != 0) geometry.radius = ulp_step<double>(geometry.radius, nudge > 0);
    const double tangent_point = std::ldexp(static_cast<double>(c.t), c.k);
    generated_cast out{geometry};
    out.tmax = ulps_from<double>(tangent_point, static_cast<int>(g.integer(-1, 1)));
    const double before = tangent_point - std::ldexp(1.0, c.k);  // (t − 1)·2^k, exact
    out.tmin = g.coin() ? std::min(0.0, before) : before;
    return out;
}

// Casts of zero or subnormal length: tmin = tmax on a root, between the
// roots or outside them; or tmax = tmin + j·2^-1074, j in [1, 4], from a root
// (a cast starting on the surface when the root is 0) or from just before it.
generated_cast make_short_cast(random_source& g) {
    const chord_construction c = make_chord(g, g.integer(0, 3) == 0);
    const double near = c.root(true), far = c.root(false), span = far - near;
    generated_cast out{c.geometry()};
    const double places[] = {near, far, near + span / 2, near - span, far + span};
    const double at = places[g.integer(0, 4)];
    if (g.coin()) {
        out.tmin = out.tmax = at;
    } else {
        const double start = g.coin() ? at : ulp_step<double>(at, false);
        out.tmin = start;
        out.tmax = start + static_cast<double>(g.integer(1, 4)) * std::numeric_limits<double>::denorm_min();
        if (*out.tmax == start) out.tmax = ulp_step<double>(start, true);  // beyond the subnormal range: one ulp
    }
    return out;
}

// ---------------------------------------------------------------------------
// The table.

constexpr std::array<family_info, 36> families{{
    {"uniform",
     "baseline: o, c uniform in [-10,10]^3, r uniform in [0.1,5], unit d aimed at a uniform "
     "point of the ball of radius 2r around c (hits and misses, origin sometimes inside)",
     class_claim::any, true},
    {"tangent_exact",
     "exactly tangent lines (Delta = 0): integers < 2^22 times 2^k, k in [-20,20], so exact in "
     "float too; half unit axis directions +-e_a with a Pythagorean-triple offset, half NON-UNIT "
     "integer directions d = f' x g with a Pythagorean-quadruple offset f'; tangent root t*2^k, "
     "t = 0 one time in four (b = 0 and Delta = 0)",
     class_claim::tangent, false, true},
    {"near_tangent",
     "a tangent_exact line with r, or an origin or centre coordinate off the line's axis, moved "
     "1 ulp (double) up or down: never tangent, miss or two_hit about half each; directions as "
     "tangent_exact (half NON-UNIT); in float the inputs round back to the tangent line",
     class_claim::any, false},
    {"far_sphere",
     "small far spheres (C = |f|^2 - r^2 cancels): r uniform in [0.5,2], D/r log-uniform on "
     "[10,1e9), unit d aimed at c + rho*w with w unit _|_ the line of sight, rho/r uniform in "
     "[0,1.5) (about 2/3 hits); origin or centre in [-1,1]^3, the other one far",
     class_claim::any, true},
    {"on_surface",
     "origin exactly on the sphere (a root is exactly 0): f = (x,y,z)*2^k, r = w*2^k from a "
     "Pythagorean quadruple, k in [-20,20], integer centre offset; unit d with d.f < 0 "
     "(entering, near root 0) or d.f > 0 (leaving, far root 0) half each, |cos| >= 2^-16; "
     "exact in float too",
     class_claim::two_hit, true},
    {"inside",
     "origin strictly inside (roots of opposite signs): c uniform in [-10,10]^3, r uniform in "
     "[0.1,5]; o at c, uniform with |f| <= 0.9r, or |f| = r(1 - 2^-j), j in [10,40], a third "
     "each; unit d uniform",
     class_claim::two_hit, true},
    {"near_tangent_hit",
     "a tangent_exact line moved one double ulp inwards (r up, or an origin or centre coordinate "
     "moved so that the line's distance from c drops below r): two roots the last bit decides",
     class_claim::two_hit, false},
    {"near_tangent_miss",
     "a tangent_exact line moved one double ulp outwards (r down, or a coordinate moved so that "
     "the line's distance from c exceeds r): a miss the last bit decides",
     class_claim::miss, false},
    {"tangent_closest",
     "tangent_exact with the origin at the tangent point: b = 0 and Delta = 0, the double root is "
     "t = 0 (0/0 in the stable-roots form); float-exact",
     class_claim::tangent, false, true},
    {"behind",
     "the sphere behind the origin: |o - c| in [1.5r, 20r], unit d pointing away from a point "
     "within 0.9r of c, so both roots are negative",
     class_claim::two_hit, true},
    {"far_sphere_wide",
     "far_sphere with D/r log-uniform on [1e2, 1e15): C = |f|^2 - r^2 loses all of r^2 in double "
     "beyond 1e8",
     class_claim::any, true},
    {"tiny_sphere",
     "radius u*2^-j, j in [20,40], centre within 4r of the coordinate origin, seen from [-8,8]^3 "
     "and aimed within 1.5r of c: r^2 is below the rounding of every other term",
     class_claim::any, true},
    {"ground_plane",
     "a huge sphere (R = u*2^e, e in [8,30]) as a ground plane with the origin at height u*2^j, "
     "j in [-4,4]; half steep rays, half grazing the horizon: the near root cancels",
     class_claim::any, false},
    {"world_offset",
     "a unit-scale scene (r in [0.5,2], o and c within 20) translated by up to 10^e, e in [6,12]: "
     "coordinates carry the offset, the geometry lives in the low bits",
     class_claim::any, true},
    {"scaled_direction",
     "a uniform case with d scaled by 2^k, k in [-200,200] (|d| from 2^-200 to 2^200): same class, "
     "roots scaled by 2^-k; a = d.d over- or underflows",
     class_claim::any, false},
    {"near_overflow",
     "a uniform case with o, c, r scaled by 2^k, k in [990,1010]: coordinates near the double "
     "overflow threshold, |f|^2 and b^2 overflow; invalid in float",
     class_claim::any, true},
    {"subnormal",
     "a uniform case with o, c, r scaled by 2^-k, k in [1050,1070]: subnormal coordinates, every "
     "product underflows; in float every input but d rounds to 0",
     class_claim::any, true},
    {"secondary_ray",
     "a secondary ray from a hit point p = o + t*d computed in double (reflected, continued, or "
     "random leaving/entering with |cos| >= 1/8): one root is within rounding of 0 (self-hit)",
     class_claim::two_hit, false},
    {"uniform_f32", "uniform with every input rounded to float (float-exact)", class_claim::any, false, true},
    {"near_tangent_hit_f32",
     "near_tangent_hit with a one-FLOAT-ulp step: float-exact, two roots decided by the last float bit",
     class_claim::two_hit, false, true},
    {"near_tangent_miss_f32",
     "near_tangent_miss with a one-FLOAT-ulp step: float-exact, a miss decided by the last float bit",
     class_claim::miss, false, true},
    {"behind_f32", "behind, float-exact (o, c, r rounded to float before d is aimed)", class_claim::two_hit,
     false, true},
    {"far_sphere_f32",
     "far_sphere with D/r log-uniform on [1e2, 1e7), float-exact (o, c, r rounded to float before d is "
     "aimed)",
     class_claim::any, false, true},
    {"tiny_sphere_f32", "tiny_sphere with j in [6,14], float-exact", class_claim::any, false, true},
    {"ground_plane_f32", "ground_plane with e in [8,16], j in [-2,4], float-exact", class_claim::any, false,
     true},
    {"world_offset_f32",
     "world_offset with offsets up to 10^e, e in [4,7] (float ulp 2^-20 r to 8 r), float-exact",
     class_claim::any, false, true},
    {"scaled_direction_f32", "scaled_direction with k in [-100,100], float-exact", class_claim::any, false,
     true},
    {"near_overflow_f32",
     "near_overflow with k in [100,120]: coordinates near the FLOAT overflow threshold, float-exact",
     class_claim::any, false, true},
    {"subnormal_f32", "subnormal with k in [130,145]: FLOAT subnormal coordinates, float-exact",
     class_claim::any, false, true},
    {"secondary_ray_f32",
     "secondary_ray with the primary hit point computed in FLOAT: the float self-intersection case, "
     "float-exact",
     class_claim::two_hit, false, true},
    {"range_end",
     "casts whose interval ends on the sphere: two exact roots (integers x 2^k on an axis or a "
     "Pythagorean direction, a triple's chord); tmax or tmin exactly on a root or one double ulp "
     "off, or both within 4 ulps around it (straddling); a sixth start on the surface (root 0, "
     "tmin = 0); float-exact inputs, double ends",
     class_claim::two_hit, false, true, true},
    {"range_end_f32",
     "range_end with the ends one FLOAT ulp off (or within 4 float ulps): ends and inputs float-exact",
     class_claim::two_hit, false, true, true},
    {"grazing_end",
     "a tangent_exact line (or one moved one double ulp off tangency by r) cast up to its tangent "
     "point: tmax exactly at t_tan or one ulp before or after it",
     class_claim::any, false, false, true},
    {"short_cast",
     "zero-length casts (tmin = tmax on a root, between or outside the roots) and the shortest "
     "nonzero ones (tmax = tmin + j*2^-1074 from a root or one ulp before it: subnormal-length from a "
     "root at 0, one ulp from any other; a quarter start on the surface); float-exact inputs, double ends",
     class_claim::two_hit, false, true, true},
    {"segment_end",
     "segments (p0, p1) ending exactly on the sphere (a triple's point: f = 1 a root whatever p0 is), one "
     "double ulp off it, starting on it (f = 0), zero-length or one ulp long; p0 drawn with a full "
     "significand up to 2^90 r away, so that p1 - p0 is often no double",
     class_claim::any, false, false, true, true},
    {"segment_end_f32",
     "segment_end with float ends and float ulp steps: every input float-exact, p1 - p0 mostly no float",
     class_claim::any, false, true, true, true},
}};

// Segments whose ends sit on the sphere. A surface point s = c + (u, v, 0)·2^k
// (permuted and signed; u² + v² = w² a triple, r = w·2^k) is exact, so a
// segment ending there has the root f = 1 exactly whatever p0 is. p0 is
// drawn with a full significand of T anywhere within about 2^j·r of the
// centre (j in [0, 90]): p1 − p0 is no T once p0's last bit is coarser than
// p1's and their span passes T's significand (for about half the double
// cases and most float ones). Of the cases: two fifths end on the sphere; a fifth end one ulp of
// T off it (one coordinate of p1 stepped up or down: inside or outside as
// the geometry has it); three twentieths start on it (p0 = s: f = 0 a root);
// a tenth are zero-length (p1 = p0, on the sphere or off it: no geometry);
// three twentieths are one ulp of T long (p1 = p0 with a coordinate stepped),
// from s or from a drawn point.
template <class T>
generated_cast make_segment_end(random_source& g) {
    const int k = static_cast<int>(g.integer(-12, 12));
    const i3 centre = {g.integer(-1024, 1024), g.integer(-1024, 1024), g.integer(-1024, 1024)};
    const triple t = small_triple(g);
    const int axis = static_cast<int>(g.integer(0, 2)), other = (axis + 1 + static_cast<int>(g.integer(0, 1))) % 3;
    i3 offset{};
    offset[axis] = g.coin() ? t.u : -t.u;
    offset[other] = g.coin() ? t.v : -t.v;
    const ray_sphere<double> sphere{{}, {}, dyadic(centre, k), std::ldexp(static_cast<double>(t.w), k)};
    const vec3<double> surface = dyadic(add(centre, offset), k);
    constexpr int digits = std::numeric_limits<T>::digits - 1;
    const int j = static_cast<int>(g.integer(0, 90));
    const auto drawn = [&] {
        // A point with a full significand of T, within 2^j·r of the centre in each coordinate.
        const auto coordinate = [&](double c) {
            const double x =
                c + std::ldexp(static_cast<double>(g.integer(-(std::int64_t{1} << digits), std::int64_t{1} << digits)),
                               k + j + 7 - digits);
            return static_cast<double>(static_cast<T>(x));
        };
        return vec3<double>{coordinate(sphere.centre.x), coordinate(sphere.centre.y), coordinate(sphere.centre.z)};
    };
    const auto stepped = [&](vec3<double> p) {
        const int at = static_cast<int>(g.integer(0, 2));
        const bool up = g.coin();
        if (at == 0) p.x = ulp_step<T>(p.x, up);
        if (at == 1) p.y = ulp_step<T>(p.y, up);
        if (at == 2) p.z = ulp_step<T>(p.z, up);
        return p;
    };
    vec3<double> p0 = drawn(), p1 = surface;
    const std::int64_t kind = g.integer(0, 19);
    if (kind < 8) {
        // p1 on the sphere
    } else if (kind < 12) {
        p1 = stepped(surface);
    } else if (kind < 15) {
        p1 = p0;
        p0 = surface;
    } else if (kind < 17) {
        if (g.coin()) p0 = surface;
        p1 = p0;
    } else {
        if (g.coin()) p0 = surface;
        p1 = stepped(p0);
    }
    generated_cast out{{p0, p1 - p0, sphere.centre, sphere.radius}};
    out.segment_end = p1;
    return out;
}

ray_sphere<double> make_uniform_f32(random_source& g) { return exactly_in<float>(make_uniform(g)); }

// A family that makes rays without an interval, as a maker of casts.
template <ray_sphere<double> (*make)(random_source&)>
generated_cast ray_only(random_source& g) {
    return {make(g)};
}

using maker = generated_cast (*)(random_source&);
constexpr std::array<maker, families.size()> makers{
    ray_only<make_uniform>,
    ray_only<make_tangent_exact>,
    ray_only<make_near_tangent>,
    ray_only<make_far_sphere>,
    ray_only<make_on_surface>,
    ray_only<make_inside>,
    ray_only<make_near_tangent_hit<double>>,
    ray_only<make_near_tangent_miss<double>>,
    ray_only<make_tangent_closest>,
    ray_only<make_behind<double>>,
    ray_only<make_far_sphere_wide<double>>,
    ray_only<make_tiny_sphere<double>>,
    ray_only<make_ground_plane<double>>,
    ray_only<make_world_offset<double>>,
    ray_only<make_scaled_direction<double>>,
    ray_only<make_near_overflow<double>>,
    ray_only<make_subnormal<double>>,
    ray_only<make_secondary_ray<double>>,
    ray_only<make_uniform_f32>,
    ray_only<make_near_tangent_hit<float>>,
    ray_only<make_near_tangent_miss<float>>,
    ray_only<make_behind<float>>,
    ray_only<make_far_sphere_wide<float>>,
    ray_only<make_tiny_sphere<float>>,
    ray_only<make_ground_plane<float>>,
    ray_only<make_world_offset<float>>,
    ray_only<make_scaled_direction<float>>,
    ray_only<make_near_overflow<float>>,
    ray_only<make_subnormal<float>>,
    ray_only<make_secondary_ray<float>>,
    make_range_end<double>,
    make_range_end<float>,
    make_grazing_end,
    make_short_cast,
    make_segment_end<double>,
    make_segment_end<float>,
};

std::string case_id(std::string_view family, std::uint64_t seed, std::size_t index) {
    std::string digits = std::to_string(index);
    if (digits.size() < 6) digits.insert(0, 6 - digits.size(), '0');
    return std::string(family) + "-" + std::to_string(seed) + "-" + digits;
}

}  // namespace

const char* class_claim_name(class_claim c) {
    switch (c) {
        case class_claim::any: return "any";
        case class_claim::miss: return "miss";
        case class_claim::tangent: return "tangent";
        case class_claim::two_hit: return "two_hit";
    }
    return "?";
}

std::span<const family_info> generator_families() { return families; }

const family_info* find_generator_family(std::string_view name) {
    for (const family_info& f : families)
        if (f.name == name) return &f;
    return nullptr;
}

namespace {

const family_info& known_family(std::string_view family) {
    const family_info* info = find_generator_family(family);
    if (info == nullptr) {
        std::string known;
        std::vector<std::string> names;
        for (const family_info& f : families) {
            known += (known.empty() ? "" : ", ") + std::string(f.name);
            names.emplace_back(f.name);
        }
        throw input_error("", 0, "family",
                          "unknown generator family '" + std::string(family) + "'" + did_you_mean(family, names) +
                              " (known: " + known + ")");
    }
    return *info;
}

corpus_case make_case(const family_info& info, std::uint64_t seed, std::size_t index, random_source& g) {
    const maker make = makers[static_cast<std::size_t>(&info - families.data())];
    corpus_case c;
    c.id = case_id(info.name, seed, index);
    c.family = std::string(info.name);
    const generated_cast made = make(g);
    c.geometry = made.geometry;
    c.tmin = made.tmin;
    c.tmax = made.tmax;
    if (made.segment_end) make_segment(c, made.geometry.origin, *made.segment_end);
    c.source = "generated";
    return c;
}

corpus_case make_case(const family_info& info, std::uint64_t seed, std::size_t index) {
    random_source g(info.name, seed, index);
    return make_case(info, seed, index, g);
}

}  // namespace

void append_generated_cases(std::string_view family, std::uint64_t seed, std::span<const std::size_t> indices,
                            std::vector<corpus_case>& out) {
    const family_info& info = known_family(family);
    constexpr std::size_t together = 4;
    for (std::size_t first = 0; first < indices.size(); first += together) {
        const std::size_t n = std::min(together, indices.size() - first);
        std::array<std::optional<random_source>, together> sources;
        std::array<random_source*, together> seeded{};
        for (std::size_t k = 0; k < n; ++k) seeded[k] = &sources[k].emplace(info.name, seed, indices[first + k]);
        random_source::seed_together(std::span(seeded.data(), n));
        for (std::size_t k = 0; k < n; ++k) out.push_back(make_case(info, seed, indices[first + k], *seeded[k]));
    }
}

std::vector<corpus_case> generate_family(std::string_view family, std::size_t count,
                                         std::uint64_t seed) {
    const family_info& info = known_family(family);
    std::vector<std::size_t> indices(count);
    for (std::size_t i = 0; i < count; ++i) indices[i] = i;
    std::vector<corpus_case> cases;
    cases.reserve(count);
    append_generated_cases(info.name, seed, indices, cases);
    return cases;
}

corpus_case generate_case(std::string_view family, std::uint64_t seed, std::size_t index) {
    return make_case(known_family(family), seed, index);
}

}  // namespace rayverify
