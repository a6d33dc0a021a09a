// The exact oracle. The only translation unit (with mpfr_reference.cpp) that
// includes CGAL, GMP or MPFR.
//
// Representation. Every quantity the oracle decides about is a real number of
// the form x = (A + B·√D) / den with A, B, D, den exact dyadic rationals
// (CGAL::Gmpzf: arbitrary mantissa times a power of two; +, −, × are exact),
// D ≥ 0 and den > 0. The roots are (−b′ ∓ √Δ′)/a; a coordinate of the hit
// point o + t·d is (o·a − d·b′ ∓ d·√Δ′)/a. Comparing x with a dyadic m reduces
// to the sign of (A − m·den) + B·√D, which is decided exactly by squaring
// when the two terms have opposite signs. Everything the oracle reports
// (class, signs, correctly rounded values, binades) is decided by such exact
// comparisons; MPFR only supplies first guesses and error magnitudes, and
// every guess is verified exactly before it is used.
#include "oracle/oracle.h"

#include <CGAL/Gmpzf.h>
#include <mpfr.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

namespace rayverify {

const char* line_class_name(line_class c) {
    switch (c) {
        case line_class::miss: return "miss";
        case line_class::tangent: return "tangent";
        case line_class::two_hit: return "two_hit";
    }
    return "?";
}

namespace {

using exact = CGAL::Gmpzf;

int sign_of(const exact& x) { return static_cast<int>(CGAL::sign(x)); }

exact power_of_two(long k) {
    exact result(1.0);
    const exact big_step(std::ldexp(1.0, 1000)), small_step(std::ldexp(1.0, -1000));
    for (; k > 1000; k -= 1000) result = result * big_step;
    for (; k < -1000; k += 1000) result = result * small_step;
    return result * exact(std::ldexp(1.0, static_cast<int>(k)));
}

// sign(A + B·√D), D ≥ 0, exactly.
int sign_of_sum_with_root(const exact& A, const exact& B, const exact& D) {
    const int sign_a = sign_of(A);
    const int sign_root = D.is_zero() ? 0 : sign_of(B);
    if (sign_root == 0) return sign_a;
    if (sign_a == 0 || sign_a == sign_root) return sign_root;
    // Opposite signs: the larger of |A| and |B|·√D wins; compare their squares.
    const exact a_squared = A * A;
    const exact root_term_squared = B * B * D;
    if (a_squared == root_term_squared) return 0;
    return a_squared > root_term_squared ? sign_a : sign_root;
}

struct quadratic_irrational {
    exact A, B, D, den;  // (A + B·√D) / den, den > 0, D ≥ 0

    int sign() const { return sign_of_sum_with_root(A, B, D); }
    // sign(x − m)
    int compare(const exact& m) const { return sign_of_sum_with_root(A - m * den, B, D); }
    quadratic_irrational negated() const { return {-A, -B, D, den}; }
};

// RAII wrapper for an mpfr_t.
class big_float {
public:
    explicit big_float(mpfr_prec_t precision) { mpfr_init2(value_, precision); }
    ~big_float() { mpfr_clear(value_); }
    big_float(const big_float&) = delete;
    big_float& operator=(const big_float&) = delete;
    mpfr_ptr get() { return value_; }
    mpfr_srcptr get() const { return value_; }

private:
    mpfr_t value_;
};

// out := x exactly (out's precision is widened to hold every bit).
void set_exactly(big_float& out, const exact& x) {
    const auto bits = static_cast<mpfr_prec_t>(mpz_sizeinbase(x.man(), 2));
    mpfr_set_prec(out.get(), std::max<mpfr_prec_t>(bits, MPFR_PREC_MIN));
    mpfr_set_z_2exp(out.get(), x.man(), x.exp(), MPFR_RNDN);
}

// out ≈ x with relative error below 8·2^−precision (5 correctly rounded
// operations, no cancellation: when A and B√D have opposite signs the
// conjugate form (A² − B²D) / ((A − B√D)·den) is used instead).
void approximate(const quadratic_irrational& x, mpfr_prec_t precision, big_float& out) {
    mpfr_set_prec(out.get(), precision);
    const int sign_x = x.sign();
    if (sign_x == 0) {
        mpfr_set_zero(out.get(), +1);
        return;
    }
    big_float A(2), B(2), D(2), den(2), root(precision), term(precision);
    set_exactly(A, x.A);
    set_exactly(B, x.B);
    set_exactly(D, x.D);
    set_exactly(den, x.den);
    mpfr_sqrt(root.get(), D.get(), MPFR_RNDN);
    mpfr_mul(term.get(), B.get(), root.get(), MPFR_RNDN);  // B·√D

    const int sign_a = sign_of(x.A);
    const int sign_root = x.D.is_zero() ? 0 : sign_of(x.B);
    if (sign_root == 0 || sign_a == 0 || sign_a == sign_root) {
        mpfr_add(out.get(), A.get(), term.get(), MPFR_RNDN);
        mpfr_div(out.get(), out.get(), den.get(), MPFR_RNDN);
        return;
    }
    big_float numerator(2), conjugate(precision);
    set_exactly(numerator, x.A * x.A - x.B * x.B * x.D);
    mpfr_sub(conjugate.get(), A.get(), term.get(), MPFR_RNDN);  // same signs: no cancellation
    mpfr_mul(conjugate.get(), conjugate.get(), den.get(), MPFR_RNDN);
    mpfr_div(out.get(), numerator.get(), conjugate.get(), MPFR_RNDN);
}

// Binary format parameters for the precision being judged.
template <class T>
struct format {
    static constexpr int p = std::numeric_limits<T>::digits;            // 24 or 53
    static constexpr int emin = std::numeric_limits<T>::min_exponent - 1;  // −126 or −1022
};

template <class T>
T guess(const big_float& approx);
template <>
float guess<float>(const big_float& approx) {
    return mpfr_get_flt(approx.get(), MPFR_RNDN);
}
template <>
double guess<double>(const big_float& approx) {
    return mpfr_get_d(approx.get(), MPFR_RNDN);
}

template <class T>
bool has_even_significand(T y) {
    using bits = std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>;
    return (std::bit_cast<bits>(y) & 1u) == 0;
}

// max + ulp(max)/2: the smallest magnitude that rounds to infinity.
template <class T>
const exact& overflow_threshold() {
    static const exact threshold = [] {
        const T max = std::numeric_limits<T>::max();
        const T below = std::nextafter(max, T(0));
        return exact(double(max)) + (exact(double(max)) - exact(double(below))) * exact(0.5);
    }();
    return threshold;
}

exact midpoint(double lo, double hi) { return (exact(lo) + exact(hi)) * exact(0.5); }

// Which way to move from a candidate y toward RN(x): 0 when y = RN(x).
template <class T>
int rounding_step(const quadratic_irrational& x, T y) {
    constexpr T inf = std::numeric_limits<T>::infinity();
    const exact& threshold = overflow_threshold<T>();
    if (std::isinf(y)) {
        if (y > 0) return x.compare(threshold) >= 0 ? 0 : -1;
        return x.compare(-threshold) <= 0 ? 0 : +1;
    }
    const T below = std::nextafter(y, -inf), above = std::nextafter(y, inf);
    const exact lo = std::isinf(below) ? -threshold : midpoint(below, y);
    const exact hi = std::isinf(above) ? threshold : midpoint(y, above);
    const int vs_lo = x.compare(lo), vs_hi = x.compare(hi);
    if (vs_lo < 0) return -1;
    if (vs_hi > 0) return +1;
    // A tie goes to the even neighbour; the extreme finite values are odd,
    // so a tie at the overflow threshold goes to infinity, as IEEE 754 says.
    if (vs_lo == 0 && !has_even_significand(y)) return -1;
    if (vs_hi == 0 && !has_even_significand(y)) return +1;
    return 0;
}

// RN(x) in T, verified exactly.
template <class T>
T round_to_nearest(const quadratic_irrational& x) {
    const int sign_x = x.sign();
    if (sign_x == 0) return T(0);
    big_float approx(2);
    approximate(x, 2 * format<T>::p + 64, approx);
    T y = guess<T>(approx);
    constexpr T inf = std::numeric_limits<T>::infinity();
    for (int step = rounding_step(x, y); step != 0; step = rounding_step(x, y))
        y = std::nextafter(y, step > 0 ? inf : -inf);
    if (y == 0) y = sign_x < 0 ? -T(0) : T(0);
    return y;
}

// e with 2^e ≤ |x| < 2^(e+1), exactly; x ≠ 0.
long binade(const quadratic_irrational& x) {
    const quadratic_irrational magnitude = x.sign() < 0 ? x.negated() : x;
    big_float approx(2);
    approximate(magnitude, 64, approx);
    long e = mpfr_get_exp(approx.get()) - 1;
    while (magnitude.compare(power_of_two(e)) < 0) --e;
    while (magnitude.compare(power_of_two(e + 1)) >= 0) ++e;
    return e;
}

// |value − x| / ulp(x) with ulp as glibc defines it: for 2^e ≤ |x| < 2^(e+1),
// ulp(x) = 2^(max(e, emin) − p + 1); ulp(0) is the smallest subnormal.
template <class T>
double ulp_error(const quadratic_irrational& x, double value) {
    if (!std::isfinite(value)) return std::numeric_limits<double>::infinity();
    if (x.compare(exact(value)) == 0) return 0.0;
    const int sign_x = x.sign();
    const long e = sign_x == 0 ? format<T>::emin : binade(x);
    const long ulp_exponent = std::max<long>(e, format<T>::emin) - format<T>::p + 1;

    // Bracket the difference: the approximation's absolute error is below
    // 2^(4 − P + e) (relative 8·2^−P, |x| < 2^(e+1)); stop when the
    // difference is 2^60 times larger than that, so the result's relative
    // error is below 2^−59 and every printed digit is right.
    big_float approx(2), value_big(64), difference(2);
    mpfr_set_d(value_big.get(), value, MPFR_RNDN);
    for (mpfr_prec_t precision = 160;; precision *= 2) {
        approximate(x, precision, approx);
        mpfr_set_prec(difference.get(), precision);
        mpfr_sub(difference.get(), value_big.get(), approx.get(), MPFR_RNDN);
        mpfr_abs(difference.get(), difference.get(), MPFR_RNDN);
        mpfr_mul_2si(difference.get(), difference.get(), -ulp_exponent, MPFR_RNDN);
        const long bound_exponent = 4 - static_cast<long>(precision) + e - ulp_exponent;
        const bool separated =
            sign_x == 0 || (mpfr_get_exp(difference.get()) - 1 > bound_exponent + 60);
        if (separated || precision > (1 << 17)) {
            // An error below the double range is still not 0, which would claim value == x.
            const double error = mpfr_get_d(difference.get(), MPFR_RNDN);
            return error == 0 ? std::numeric_limits<double>::denorm_min() : error;
        }
    }
}

}  // namespace

struct exact_solution::exact_state {
    exact origin[3], direction[3];
    quadratic_irrational near_root, far_root;

    const quadratic_irrational& root(root_index i) const {
        return i == root_index::near_root ? near_root : far_root;
    }
    // Coordinate `axis` of o + t·d for t = (A + B√D)/den: (o·den + d·A + d·B√D)/den.
    quadratic_irrational hit_coordinate(root_index i, int axis) const {
        const quadratic_irrational& t = root(i);
        return {origin[axis] * t.den + direction[axis] * t.A, direction[axis] * t.B, t.D, t.den};
    }
};

namespace {

template <class T>
double round_in(const quadratic_irrational& x) {
    return static_cast<double>(round_to_nearest<T>(x));
}

double round_in(precision p, const quadratic_irrational& x) {
    return p == precision::binary32 ? round_in<float>(x) : round_in<double>(x);
}

double ulp_error_in(precision p, const quadratic_irrational& x, double value) {
    return p == precision::binary32 ? ulp_error<float>(x, value) : ulp_error<double>(x, value);
}

}  // namespace

int exact_solution::compare_root(root_index i, double value) const {
    return -exact_->root(i).compare(exact(value));
}

double exact_solution::root_ulp_error(root_index i, double value) const {
    return ulp_error_in(prec, exact_->root(i), value);
}

double exact_solution::hit_point_ulp_error(root_index i, int axis, double value) const {
    return ulp_error_in(prec, exact_->hit_coordinate(i, axis), value);
}

double exact_solution::rounded_hit_coordinate(root_index i, int axis) const {
    return round_in(prec, exact_->hit_coordinate(i, axis));
}

exact_solution solve_exact(const ray_sphere<double>& g, precision prec, std::optional<double> tmin,
                           std::optional<double> tmax) {
    exact_solution solution;
    solution.prec = prec;
    solution.invalid = validity<double>(g);
    if (solution.valid() && (tmin || tmax)) {
        const double lo = tmin.value_or(-std::numeric_limits<double>::infinity());
        const double hi = tmax.value_or(std::numeric_limits<double>::infinity());
        if (std::isnan(lo) || std::isnan(hi) || lo > hi) solution.invalid = invalid_reason::bad_interval;
    }
    if (!solution.valid()) return solution;

    auto state = std::make_shared<exact_solution::exact_state>();
    const double o[3] = {g.origin.x, g.origin.y, g.origin.z};
    const double d[3] = {g.direction.x, g.direction.y, g.direction.z};
    const double c[3] = {g.centre.x, g.centre.y, g.centre.z};

    // Exact quadratic a t² + 2b′t + C = 0 with f = o − c.
    exact a(0.0), b_prime(0.0), f_squared(0.0);
    for (int axis = 0; axis < 3; ++axis) {
        state->origin[axis] = exact(o[axis]);
        state->direction[axis] = exact(d[axis]);
        const exact f = state->origin[axis] - exact(c[axis]);
        a = a + state->direction[axis] * state->direction[axis];
        b_prime = b_prime + state->direction[axis] * f;
        f_squared = f_squared + f * f;
    }
    const exact r(g.radius);
    const exact C = f_squared - r * r;
    const exact discriminant = b_prime * b_prime - a * C;  // Δ′ = Δ/4

    const int sign_discriminant = sign_of(discriminant);
    solution.cls = sign_discriminant < 0   ? line_class::miss
                   : sign_discriminant == 0 ? line_class::tangent
                                            : line_class::two_hit;
    if (solution.cls == line_class::miss) {
        if (tmin || tmax) solution.hits_interval = false;
        return solution;
    }

    // Roots (−b′ ∓ √Δ′)/a.
    state->near_root = {-b_prime, exact(-1.0), discriminant, a};
    state->far_root = {-b_prime, exact(1.0), discriminant, a};
    for (root_index i : {root_index::near_root, root_index::far_root}) {
        exact_root& out = i == root_index::near_root ? solution.near_root : solution.far_root;
        out.sign = state->root(i).sign();
        out.rounded = round_in(prec, state->root(i));
    }
    if (solution.near_root.sign > 0)
        solution.nearest_in_front = root_index::near_root;
    else if (solution.far_root.sign > 0)
        solution.nearest_in_front = root_index::far_root;

    if (tmin || tmax) {
        bool inside = false;
        // An infinite bound admits every root on its side (or none beyond it).
        const auto at_least = [](const quadratic_irrational& t, std::optional<double> bound) {
            if (!bound || std::isinf(*bound)) return !bound || *bound < 0;
            return t.compare(exact(*bound)) >= 0;
        };
        const auto at_most = [](const quadratic_irrational& t, std::optional<double> bound) {
            if (!bound || std::isinf(*bound)) return !bound || *bound > 0;
            return t.compare(exact(*bound)) <= 0;
        };
        for (const quadratic_irrational* t : {&state->near_root, &state->far_root})
            inside = inside || (at_least(*t, tmin) && at_most(*t, tmax));
        solution.hits_interval = inside;
    }

    solution.exact_ = std::move(state);
    if (solution.nearest_in_front) {
        const root_index front = *solution.nearest_in_front;
        solution.hit_point = {solution.rounded_hit_coordinate(front, 0),
                              solution.rounded_hit_coordinate(front, 1),
                              solution.rounded_hit_coordinate(front, 2)};
    }
    return solution;
}

}  // namespace rayverify
