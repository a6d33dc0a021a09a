// The floating-point primitives that live once (core/float_bits.h,
// core/double_word.h), each against exact arithmetic written apart
// (Boost.Multiprecision cpp_int on dyadic rationals) or against the C
// library, over a million random and boundary operands with a printed seed
// (RAYVERIFY_PRIMITIVES_SEED replays one).
#include <gtest/gtest.h>

#include <boost/multiprecision/cpp_int.hpp>

#include <bit>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <random>
#include <vector>

#include "core/double_word.h"
#include "core/float_bits.h"
#include "oracle/expansion.h"
#include "support/sanitized.h"

namespace rayverify {
namespace {

using boost::multiprecision::cpp_int;
constexpr int operands = static_cast<int>(test_support::sweep_size(1'000'000));

std::uint64_t seed_for_run() {
    if (const char* s = std::getenv("RAYVERIFY_PRIMITIVES_SEED")) return std::strtoull(s, nullptr, 10);
    const auto seed = static_cast<std::uint64_t>(std::chrono::steady_clock::now().time_since_epoch().count());
    std::printf("seed %llu (RAYVERIFY_PRIMITIVES_SEED replays it)\n", static_cast<unsigned long long>(seed));
    return seed;
}

// An exact dyadic rational n·2^k.
struct exact {
    cpp_int n;
    int k = 0;
};

exact of(double x) {
    if (x == 0) return {0, 0};
    int e = 0;
    const double m = std::frexp(x, &e);
    return {cpp_int(static_cast<long long>(std::ldexp(m, 53))), e - 53};
}
exact aligned(const exact& x, int k) { return {x.n << (x.k - k), k}; }
exact operator+(const exact& a, const exact& b) {
    const int k = std::min(a.k, b.k);
    return {aligned(a, k).n + aligned(b, k).n, k};
}
exact operator-(const exact& a) { return {-a.n, a.k}; }
exact operator-(const exact& a, const exact& b) { return a + (-b); }
exact operator*(const exact& a, const exact& b) { return {a.n * b.n, a.k + b.k}; }
int compare(const exact& a, const exact& b) {
    const exact d = a - b;
    return d.n.sign();
}
exact abs(const exact& a) { return {a.n < 0 ? cpp_int(-a.n) : a.n, a.k}; }

// Random doubles: uniform significands, exponents spread over ±spread, both signs,
// with boundary values mixed in.
struct operand_source {
    std::mt19937_64 rng;
    int spread;
    operand_source(std::uint64_t seed, int s) : rng(seed), spread(s) {}
    double next() {
        const std::uint64_t r = rng();
        switch (r % 16) {
            case 0: return 0.0;
            case 1: return (r & 16) ? 1.0 : -1.0;
            case 2: return std::ldexp((r & 16) ? 1.0 : -1.0, static_cast<int>((r >> 8) % (2 * spread + 1)) - spread);
            case 3: return std::nextafter(std::ldexp(1.0, static_cast<int>((r >> 8) % 64) - 32), 0.0);
            default: {
                const double m = 1 + std::ldexp(static_cast<double>(r >> 12), -52);  // [1, 2)
                const int e = static_cast<int>((r >> 4) % (2 * spread + 1)) - spread;
                return ((r & 8) ? -1 : 1) * std::ldexp(m, e);
            }
        }
    }
};

// ---- float_bits ---------------------------------------------------------------------

template <class T>
T random_value(std::mt19937_64& rng) {
    using bits = float_bits_t<T>;
    // Every finite value, uniformly over bit patterns, with the boundaries mixed in.
    static const T boundary[] = {T(0),
                                 -T(0),
                                 std::numeric_limits<T>::denorm_min(),
                                 -std::numeric_limits<T>::denorm_min(),
                                 std::numeric_limits<T>::min(),
                                 std::numeric_limits<T>::max(),
                                 -std::numeric_limits<T>::max(),
                                 T(1),
                                 std::nextafter(T(1), T(0))};
    const std::uint64_t r = rng();
    if (r % 8 == 0) return boundary[(r >> 8) % std::size(boundary)];
    T x;
    do x = std::bit_cast<T>(static_cast<bits>(rng())); while (!std::isfinite(x));
    return x;
}

// The ordered index written apart: from the value's binade and significand
// (frexp), not from its bits.
template <class T>
cpp_int independent_index(T x) {
    constexpr int p = std::numeric_limits<T>::digits;
    constexpr int emin = std::numeric_limits<T>::min_exponent - 1;  // −126, −1022
    if (x == 0) return 0;
    const T a = std::fabs(x);
    int e = 0;
    const T m = std::frexp(a, &e);  // a = m·2^e, m in [0.5, 1)
    cpp_int index;
    if (e - 1 < emin) {  // subnormal: a = k·2^(emin − p + 1)
        index = cpp_int(static_cast<long long>(std::ldexp(a, -(emin - p + 1))));
    } else {  // normal: binade e − 1 − emin + 1 steps of 2^(p−1), then the significand's fraction
        const auto fraction = static_cast<long long>(std::ldexp(m, p) - std::ldexp(T(1), p - 1));
        index = cpp_int(e - 1 - emin + 1) * (cpp_int(1) << (p - 1)) + fraction;
    }
    return x < 0 ? cpp_int(-index) : index;
}

TEST(FloatBits, ExactPowersOfTwoAreLdexpsOfOne) {
    for (int k = -1074; k <= 1024; ++k) ASSERT_EQ(exact_power_of_two(k), std::ldexp(1.0, k)) << k;
}

template <class T>
void check_float_bits(std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    int failures = 0;
    const auto fail = [&](const char* what, T x, T y) {
        if (++failures <= 5) ADD_FAILURE() << what << " at " << x << ", " << y << " (seed " << seed << ")";
    };
    for (int i = 0; i < operands; ++i) {
        const T x = random_value<T>(rng), y = random_value<T>(rng);
        const cpp_int ix = independent_index(x), iy = independent_index(y);
        if (cpp_int(ordered_index(x)) != ix) fail("ordered_index", x, y);
        const T back = from_ordered_index<T>(ordered_index(x));
        if (!(back == x)) fail("from_ordered_index", x, y);
        if (!(next_up(x) == std::nextafter(x, std::numeric_limits<T>::infinity()))) fail("next_up", x, y);
        if (!(next_down(x) == std::nextafter(x, -std::numeric_limits<T>::infinity()))) fail("next_down", x, y);
        const cpp_int distance = ix > iy ? cpp_int(ix - iy) : cpp_int(iy - ix);
        if (cpp_int(ulps_between(x, y)) != distance) fail("ulps_between", x, y);
        // ulp(x): the gap above |x| in its binade (below, at the largest value).
        const T a = std::fabs(x);
        const double gap = a == std::numeric_limits<T>::max()
                               ? static_cast<double>(a) - static_cast<double>(std::nextafter(a, T(0)))
                               : static_cast<double>(std::nextafter(a, std::numeric_limits<T>::infinity())) -
                                     static_cast<double>(a);
        if (ulp_of(x) != gap) fail("ulp_of", x, y);
        if (x != 0 && binade_of(x) != std::ilogb(x)) fail("binade_of", x, y);
        // step_by over a short walk matches repeated nextafter.
        const int steps = static_cast<int>(rng() % 7) - 3;
        T walked = x;
        for (int s = 0; s < std::abs(steps); ++s)
            walked = std::nextafter(walked, steps > 0 ? std::numeric_limits<T>::infinity() : -std::numeric_limits<T>::infinity());
        const T stepped = step_by(x, steps);
        const cpp_int end = ix + steps, line_end = independent_index(std::numeric_limits<T>::max()) + 1;
        if (end > line_end || end < -line_end ? !std::isnan(stepped) : !(stepped == walked)) fail("step_by", x, y);
        // A long step lands where the index says, or NaN past infinity.
        const auto far = static_cast<std::int64_t>(rng() >> 2) * ((rng() & 1) ? 1 : -1);
        const cpp_int target = ix + far;
        const cpp_int limit = independent_index(std::numeric_limits<T>::max()) + 1;
        const T long_step = step_by(x, far);
        if (target > limit || target < -limit) {
            if (!std::isnan(long_step)) fail("step_by past infinity", x, y);
        } else if (std::isnan(long_step) || independent_index(long_step) != target) {
            if (!(std::isinf(long_step) && (target == limit || target == -limit))) fail("step_by far", x, y);
        }
    }
    EXPECT_EQ(failures, 0) << "seed " << seed;
    // Infinity is one step beyond the largest finite value; the walk ends there.
    EXPECT_EQ(next_up(std::numeric_limits<T>::max()), std::numeric_limits<T>::infinity());
    EXPECT_EQ(ulps_between(std::numeric_limits<T>::max(), std::numeric_limits<T>::infinity()), 1u);
    EXPECT_EQ(ulps_between(-T(0), T(0)), 0u);
    EXPECT_EQ(ulps_between(-std::numeric_limits<T>::denorm_min(), std::numeric_limits<T>::denorm_min()), 2u);
    EXPECT_TRUE(std::isnan(step_by(std::numeric_limits<T>::max(), 2)));
}

TEST(FloatBits, FloatAgainstAnIndependentIndexOnAMillionValues) { check_float_bits<float>(seed_for_run()); }
TEST(FloatBits, DoubleAgainstAnIndependentIndexOnAMillionValues) { check_float_bits<double>(seed_for_run()); }

TEST(FloatBits, UlpsBetweenDoesNotNeedLongDouble) {
    // The full span of the line: −inf to +inf, beyond 2^63.
    const double inf = std::numeric_limits<double>::infinity();
    EXPECT_EQ(ulps_between(-inf, inf), 2 * static_cast<std::uint64_t>(infinity_index<double>()));
    // One ulp apart at 2^60, where a double-rounded difference of bit patterns would lose it.
    const double big = std::ldexp(1.0, 60);
    EXPECT_EQ(ulps_between(big, std::nextafter(big, inf)), 1u);
}

// ---- double_word ------------------------------------------------------------------

// |x − exact| ≤ bound·|exact|, decided exactly (bound a power of two or a small multiple).
bool within_relative(const dword& x, const exact& truth, const exact& bound) {
    const exact error = abs(of(x.h) + of(x.l) - truth);
    return compare(error, bound * abs(truth)) <= 0;
}

TEST(DoubleWord, ErrorFreeTransformationsAreExact) {
    const std::uint64_t seed = seed_for_run();
    operand_source source(seed, 300);
    int failures = 0;
    for (int i = 0; i < operands && failures < 5; ++i) {
        const double a = source.next(), b = source.next();
        const dword s = two_sum(a, b);
        if (compare(of(s.h) + of(s.l), of(a) + of(b)) != 0 || s.h != a + b) ++failures, ADD_FAILURE() << "two_sum " << a << " " << b;
        const double big = std::fabs(a) >= std::fabs(b) ? a : b, small = std::fabs(a) >= std::fabs(b) ? b : a;
        const dword f = fast_two_sum(big, small);
        if (compare(of(f.h) + of(f.l), of(a) + of(b)) != 0) ++failures, ADD_FAILURE() << "fast_two_sum " << a << " " << b;
        const dword p = two_prod(a, b);
        if (compare(of(p.h) + of(p.l), of(a) * of(b)) != 0 || p.h != a * b)
            ++failures, ADD_FAILURE() << "two_prod " << a << " " << b;
    }
    EXPECT_EQ(failures, 0) << "seed " << seed;
}

// Two lanes (double_word.h) hold, lane by lane, the bits the scalar code computes.
TEST(DoubleWord, TwoLanesComputeWhatTheScalarCodeComputes) {
    const std::uint64_t seed = seed_for_run();
    operand_source source(seed, 300);
    const auto same = [](double x, double y) { return std::bit_cast<std::uint64_t>(x) == std::bit_cast<std::uint64_t>(y); };
    int failures = 0;
    for (int i = 0; i < operands && failures < 5; ++i) {
        const double a[2] = {source.next(), source.next()}, b[2] = {source.next(), source.next()};
        const double_pair x = {a[0], a[1]}, y = {b[0], b[1]};
        const dword_pair s = two_sum(x, y), p = two_prod(x, y);
        const double_pair magnitude = fabs_lanes(x);
        for (int lane = 0; lane < 2; ++lane) {
            const dword scalar_sum = two_sum(a[lane], b[lane]), scalar_product = two_prod(a[lane], b[lane]);
            const double big = std::fabs(a[lane]) >= std::fabs(b[lane]) ? a[lane] : b[lane];
            const double small = std::fabs(a[lane]) >= std::fabs(b[lane]) ? b[lane] : a[lane];
            const dword scalar_fast = fast_two_sum(big, small);
            const dword_pair fast = fast_two_sum(double_pair{big, big}, double_pair{small, small});
            if (!same(s.h[lane], scalar_sum.h) || !same(s.l[lane], scalar_sum.l) || !same(p.h[lane], scalar_product.h) ||
                !same(p.l[lane], scalar_product.l) || !same(fast.h[lane], scalar_fast.h) ||
                !same(fast.l[lane], scalar_fast.l) || !same(magnitude[lane], std::fabs(a[lane])))
                ++failures, ADD_FAILURE() << "lane " << lane << ": " << a[lane] << " " << b[lane];
        }
        const bool both_greater = a[0] > b[0] && a[1] > b[1];
        if (in_both_lanes(x > y) != both_greater) ++failures, ADD_FAILURE() << "in_both_lanes " << a[0] << " " << a[1];
    }
    EXPECT_EQ(failures, 0) << "seed " << seed;
}

// A double-word with |l| ≤ ulp(h)/2 (what the operations produce).
dword random_dword(operand_source& source) {
    const double h = source.next();
    const double l = h == 0 ? 0 : std::ldexp(source.next() == 0 ? 0.0 : 0.75, std::ilogb(h) - 54) *
                                          ((source.rng() & 1) ? 1 : -1);
    return fast_two_sum(h, l);
}

TEST(DoubleWord, OperationsMeetTheirProvenBounds) {
    const std::uint64_t seed = seed_for_run();
    operand_source source(seed, 200);
    const exact u2{1, -106};  // u² = 2^−106
    const exact add_bound = exact{3, 0} * u2 + exact{1, -150};      // 3u²/(1 − 4u) < 3u² + 2^−150
    const exact mul_bound = exact{4, 0} * u2, fp_bound = exact{2, 0} * u2;
    int failures = 0;
    for (int i = 0; i < operands && failures < 5; ++i) {
        const dword x = random_dword(source), y = random_dword(source);
        const double z = source.next();
        const exact ex = of(x.h) + of(x.l), ey = of(y.h) + of(y.l);
        if (!within_relative(dw_add(x, y), ex + ey, add_bound)) ++failures, ADD_FAILURE() << "dw_add, operand " << i;
        if (!within_relative(dw_mul(x, y), ex * ey, mul_bound)) ++failures, ADD_FAILURE() << "dw_mul, operand " << i;
        if (!within_relative(dw_mul(x, z), ex * of(z), fp_bound)) ++failures, ADD_FAILURE() << "dw_mul fp, operand " << i;
    }
    EXPECT_EQ(failures, 0) << "seed " << seed;
}

// Bounded values: after a chain of operations the exact result lies within
// the carried bound; √ and ÷ contain the exact root and quotient.
TEST(DoubleWord, BoundedArithmeticContainsTheExactValue) {
    const std::uint64_t seed = seed_for_run();
    operand_source source(seed, 60);  // the filter's range keeps products far from under- and overflow
    int failures = 0, roots = 0, quotients = 0;
    const auto contains = [](const bounded& b, const exact& truth) {
        return compare(abs(of(b.v.h) + of(b.v.l) - truth), of(b.err)) <= 0;
    };
    for (int i = 0; i < operands / 4 && failures < 5; ++i) {
        const double a = source.next(), b = source.next(), c = source.next(), d = source.next();
        // (a·b − c)·d + a: every operator once.
        const bounded r = (exactly(a) * exactly(b) - exactly(c)) * d + exactly(a);
        const exact truth = (of(a) * of(b) - of(c)) * of(d) + of(a);
        if (!contains(r, truth)) ++failures, ADD_FAILURE() << "bounded chain at operand " << i;
        if (const auto q = quotient(r, exactly(two_prod(b, d)))) {
            // |X/Y − q| ≤ err ⇔ |X − q·Y| ≤ err·|Y|, with Y = b·d exactly.
            ++quotients;
            const exact y = of(b) * of(d);
            const exact residual = abs(truth - (of(q->v.h) + of(q->v.l)) * y);
            if (compare(residual, of(q->err) * abs(y)) > 0) ++failures, ADD_FAILURE() << "quotient at operand " << i;
        }
        if (const auto s = square_root(r); s && certain_sign(r) > 0) {
            // (s − err)² ≤ X ≤ (s + err)², the lower end clamped at 0.
            ++roots;
            const exact centre = of(s->v.h) + of(s->v.l), err = of(s->err);
            exact low = centre - err;
            if (low.n < 0) low = {0, 0};
            const exact high = centre + err;
            if (compare(low * low, truth) > 0 || compare(truth, high * high) > 0)
                ++failures, ADD_FAILURE() << "square_root at operand " << i;
        }
    }
    EXPECT_EQ(failures, 0) << "seed " << seed;
    EXPECT_GT(roots, operands / 40);
    EXPECT_GT(quotients, operands / 40);
}

// Expansions (oracle/expansion.h): the degree-4 polynomial the oracle's
// refined enclosures evaluate, P(u) = a·u² + 2b′·u + C from seven random
// doubles, equals its exact value; its components stay nonoverlapping (the
// sign is the largest's), and approximate() bounds the value to 2^−100. So
// do a product of two expansions of several components each (2b′·C, the
// partial sums accumulated in turn in two buffers) and their compressions.
TEST(Expansion, PolynomialOfDoublesIsExactAndApproximatedWithinItsBound) {
    const std::uint64_t seed = seed_for_run();
    operand_source source(seed, 60);
    int failures = 0;
    for (int trial = 0; trial < 100'000 && failures < 5; ++trial) {
        double o[3], d[3], c[3];
        for (int k = 0; k < 3; ++k) o[k] = source.next(), d[k] = source.next(), c[k] = source.next();
        const double r = source.next(), u = source.next();
        expansion<2> f[3];
        exact f_exact[3];
        for (int k = 0; k < 3; ++k) {
            f[k] = expansion_of(o[k]) - expansion_of(c[k]);
            f_exact[k] = of(o[k]) - of(c[k]);
        }
        const expansion<6> a = expansion_of(d[0]) * d[0] + expansion_of(d[1]) * d[1] + expansion_of(d[2]) * d[2];
        const expansion<12> two_b = f[0] * (2 * d[0]) + f[1] * (2 * d[1]) + f[2] * (2 * d[2]);
        const expansion<26> C = f[0] * f[0] + f[1] * f[1] + f[2] * f[2] - expansion_of(r) * r;
        const expansion<74> P = (a * u) * u + two_b * u + C;
        exact a_exact = of(0), b_exact = of(0), C_exact = -(of(r) * of(r));
        for (int k = 0; k < 3; ++k) {
            a_exact = a_exact + of(d[k]) * of(d[k]);
            b_exact = b_exact + of(2 * d[k]) * f_exact[k];
            C_exact = C_exact + f_exact[k] * f_exact[k];
        }
        const exact P_exact = a_exact * of(u) * of(u) + b_exact * of(u) + C_exact;
        exact sum = of(0);
        for (int k = 0; k < P.n; ++k) sum = sum + of(P.c[k]);
        const bounded approx = approximate(P);
        const exact approx_error = abs(P_exact - of(approx.v.h) - of(approx.v.l));
        const expansion<624> product = compressed(two_b) * compressed(C);
        exact product_sum = of(0);
        for (int k = 0; k < product.n; ++k) product_sum = product_sum + of(product.c[k]);
        const exact product_exact = b_exact * C_exact;
        const bool ok = compare(sum, P_exact) == 0 && sign_of(P) == P_exact.n.sign() &&
                        compare(product_sum, product_exact) == 0 && sign_of(product) == product_exact.n.sign() &&
                        compare(approx_error, of(approx.err)) <= 0 &&
                        approx.err <= 0x1p-100 * std::fabs(approx.v.h) + 0x1p-599;
        if (!ok && ++failures <= 5) ADD_FAILURE() << "trial " << trial << " (seed " << seed << ")";
    }
}

}  // namespace
}  // namespace rayverify
