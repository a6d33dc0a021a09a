#include "corpus/generators.h"

#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <utility>

#include "core/input_error.h"

namespace rayverify {

namespace {

using v3 = vec3<double>;

// ---------------------------------------------------------------------------
// Randomness: raw mt19937_64 outputs, converted by hand.

std::uint64_t splitmix64(std::uint64_t x) {
    std::uint64_t z = x + 0x9e3779b97f4a7c15ULL;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

std::uint64_t fnv1a(std::string_view s) {
    std::uint64_t h = 0xcbf29ce484222325ULL;
    for (const char ch : s) {
        h ^= static_cast<unsigned char>(ch);
        h *= 0x100000001b3ULL;
    }
    return h;
}

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

private:
    std::mt19937_64 engine_;
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

tangent_construction make_tangent(random_source& g) {
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
        c.t = tangent_parameter(g, 4 * tr.w);
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
        c.t = tangent_parameter(g, 16);
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

ray_sphere<double> make_far_sphere(random_source& g) {
    const double radius = g.uniform(0.5, 2);

    // D/r = x·10^e: e uniform in [1, 8], x in [1, 10) with density ∝ 1/x
    // (uniform x accepted with probability 1/x), so D/r is log-uniform on [10, 10^9).
    const int e = static_cast<int>(g.integer(1, 8));
    double x;
    do x = g.uniform(1, 10);
    while (!(g.unit() * x < 1));
    const double distance = x * power_of_ten(e) * radius;

    // One end of the line of sight near the coordinate origin, the other far.
    const v3 sight = random_unit(g);
    const v3 near_end = cube_point(g, -1, 1);
    const bool origin_near = g.coin();
    const v3 origin = origin_near ? near_end : near_end - distance * sight;
    const v3 centre = origin_near ? near_end + distance * sight : near_end;

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
// The table.

constexpr std::array<family_info, 6> families{{
    {"uniform",
     "baseline: o, c uniform in [-10,10]^3, r uniform in [0.1,5], unit d aimed at a uniform "
     "point of the ball of radius 2r around c (hits and misses, origin sometimes inside)",
     class_claim::any, true},
    {"tangent_exact",
     "exactly tangent lines (Delta = 0): integers < 2^22 times 2^k, k in [-20,20], so exact in "
     "float too; half unit axis directions +-e_a with a Pythagorean-triple offset, half NON-UNIT "
     "integer directions d = f' x g with a Pythagorean-quadruple offset f'; tangent root t*2^k, "
     "t = 0 one time in four (b = 0 and Delta = 0)",
     class_claim::tangent, false},
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
}};

using maker = ray_sphere<double> (*)(random_source&);
constexpr std::array<maker, families.size()> makers{
    make_uniform,    make_tangent_exact, make_near_tangent,
    make_far_sphere, make_on_surface,    make_inside,
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

std::vector<corpus_case> generate_family(std::string_view family, std::size_t count,
                                         std::uint64_t seed) {
    const family_info* info = find_generator_family(family);
    if (info == nullptr) {
        std::string known;
        for (const family_info& f : families) known += (known.empty() ? "" : ", ") + std::string(f.name);
        throw input_error("", 0, "family",
                          "unknown generator family '" + std::string(family) + "' (known: " + known + ")");
    }
    const maker make = makers[static_cast<std::size_t>(info - families.data())];

    std::vector<corpus_case> cases;
    cases.reserve(count);
    for (std::size_t i = 0; i < count; ++i) {
        random_source g(info->name, seed, i);
        corpus_case c;
        c.id = case_id(info->name, seed, i);
        c.family = std::string(info->name);
        c.geometry = make(g);
        c.source = "generated";
        cases.push_back(std::move(c));
    }
    return cases;
}

}  // namespace rayverify
