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

#include "core/double_word.h"
#include "core/float_bits.h"
#include "oracle/expansion.h"

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

// sign(x − y) for x = (A1 + B1√D1)/den1, y = (A2 + B2√D2)/den2, exactly: with
// P = A1·den2 − A2·den1, Q = B1·den2, R = −B2·den1 it is the sign of
// u + v, u = P + Q√D1, v = R√D2. When u and v have opposite signs the larger
// magnitude wins: u² − v² = (P² + Q²D1 − R²D2) + 2PQ√D1, one more square root
// term, whose sign sign_of_sum_with_root decides.
int sign_of_difference(const quadratic_irrational& x, const quadratic_irrational& y) {
    const exact P = x.A * y.den - y.A * x.den, Q = x.B * y.den, R = -(y.B * x.den);
    const int sign_u = sign_of_sum_with_root(P, Q, x.D);
    const int sign_v = y.D.is_zero() ? 0 : sign_of(R);
    if (sign_v == 0) return sign_u;
    if (sign_u == 0 || sign_u == sign_v) return sign_v;
    const int larger_u = sign_of_sum_with_root(P * P + Q * Q * x.D - R * R * y.D, exact(2.0) * P * Q, x.D);
    if (larger_u == 0) return 0;
    return larger_u > 0 ? sign_u : sign_v;
}

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
        // Once separated, also require the bracket difference ∓ (2^(bound + 1)
        // + 2^(1 − P)·difference) (the approximation's error, then the
        // subtraction's rounding) to round to one double: the result is then
        // RN of the exact ratio, the value the filter's enclosures certify.
        // An exact tie never settles; the cap then returns RN of the estimate.
        if (separated && sign_x != 0 && precision <= (1 << 17)) {
            big_float lo(precision), hi(precision), slack(2), rounding(precision);
            mpfr_set_ui_2exp(slack.get(), 1, bound_exponent + 1, MPFR_RNDN);
            mpfr_mul_2si(rounding.get(), difference.get(), 1 - static_cast<long>(precision), MPFR_RNDN);
            mpfr_sub(lo.get(), difference.get(), rounding.get(), MPFR_RNDD);
            mpfr_sub(lo.get(), lo.get(), slack.get(), MPFR_RNDD);
            mpfr_add(hi.get(), difference.get(), rounding.get(), MPFR_RNDU);
            mpfr_add(hi.get(), hi.get(), slack.get(), MPFR_RNDU);
            const double low = mpfr_get_d(lo.get(), MPFR_RNDN), high = mpfr_get_d(hi.get(), MPFR_RNDN);
            if (low != high) {
                // A rounding boundary B lies in the bracket. If the ratio is
                // exactly B (x = value ∓ B·ulp, decided exactly), it is a tie:
                // round B to even. Otherwise a finer bracket will clear it.
                const double next = std::nextafter(low, std::numeric_limits<double>::infinity());
                if (std::isfinite(next) && next == high) {
                    const exact boundary = midpoint(low, next) * power_of_two(ulp_exponent);
                    const exact candidate =
                        x.compare(exact(value)) < 0 ? exact(value) - boundary : exact(value) + boundary;
                    if (x.compare(candidate) == 0) {
                        big_float tie(2);
                        set_exactly(tie, midpoint(low, next));
                        return mpfr_get_d(tie.get(), MPFR_RNDN);
                    }
                }
                continue;
            }
        }
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
    exact discriminant;  // Δ′
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

// The exact quadratic a t² + 2b′t + C = 0 with f = o − c, Δ′ = b′² − aC;
// with `unit_direction`, a is taken to be 1 (what a unit-direction formula solves).
std::shared_ptr<exact_solution::exact_state> build_exact_state(const ray_sphere<double>& g,
                                                               bool unit_direction = false) {
    auto state = std::make_shared<exact_solution::exact_state>();
    const double o[3] = {g.origin.x, g.origin.y, g.origin.z};
    const double d[3] = {g.direction.x, g.direction.y, g.direction.z};
    const double c[3] = {g.centre.x, g.centre.y, g.centre.z};
    exact a(0.0), b_prime(0.0), f_squared(0.0);
    for (int axis = 0; axis < 3; ++axis) {
        state->origin[axis] = exact(o[axis]);
        state->direction[axis] = exact(d[axis]);
        const exact f = state->origin[axis] - exact(c[axis]);
        a = a + state->direction[axis] * state->direction[axis];
        b_prime = b_prime + state->direction[axis] * f;
        f_squared = f_squared + f * f;
    }
    if (unit_direction) a = exact(1.0);
    const exact r(g.radius);
    const exact C = f_squared - r * r;
    state->discriminant = b_prime * b_prime - a * C;
    // Roots (−b′ ∓ √Δ′)/a.
    state->near_root = {-b_prime, exact(-1.0), state->discriminant, a};
    state->far_root = {-b_prime, exact(1.0), state->discriminant, a};
    return state;
}

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

invalid_reason check_case(const ray_sphere<double>& g, std::optional<double> tmin, std::optional<double> tmax) {
    invalid_reason reason = validity<double>(g);
    if (reason == invalid_reason::none && (tmin || tmax)) {
        const double lo = tmin.value_or(-std::numeric_limits<double>::infinity());
        const double hi = tmax.value_or(std::numeric_limits<double>::infinity());
        if (std::isnan(lo) || std::isnan(hi) || lo > hi) reason = invalid_reason::bad_interval;
    }
    return reason;
}


// ===========================================================================
// The nearest root with t > 0, from the roots' exact signs.
std::optional<root_index> nearest_root_in_front(int near_sign, int far_sign) {
    if (near_sign > 0) return root_index::near_root;
    if (far_sign > 0) return root_index::far_root;
    return std::nullopt;
}

// ===========================================================================
// The filter: double-word arithmetic with rigorous error bounds
// (core/double_word.h: two_sum, two_prod, the double-word operations, and
// `bounded` values whose error bounds propagate through +, −, ×, √ and ÷).
//
// Range. The filter runs only when every input is 0 or has magnitude in
// [2^−80, 2^80] (otherwise the exact route runs). Every input is then an
// integer multiple of 2^−132, so every exact polynomial quantity of degree k
// (a, b′, C: 2; Δ′: 4) is 0 or at least 2^−132k in magnitude, and all of them
// stay below 2^330: every product the filter forms is far from the underflow
// threshold (the smallest nonzero root is above 2^−440, a hit-point term
// above 2^−520, their low words above 2^−630), and nothing overflows. The
// relative bounds of the double-word operations, which assume no underflow,
// therefore hold.
// ===========================================================================

using enclosure = exact_solution::enclosure;

inline bool known(const enclosure& x) { return x.err < std::numeric_limits<double>::infinity(); }

// sign(x − m) when the enclosure decides it, else 0.
inline int side_of(const enclosure& x, double m) {
    if (!known(x)) return 0;
    if (exceeds(x.hi, x.lo, x.err, m)) return +1;
    if (exceeds(-x.hi, -x.lo, x.err, -m)) return -1;
    return 0;
}

// RN(x) in T when the whole enclosure lies strictly inside one rounding
// interval (ties and anything at a boundary are left to the exact route).
// The candidate y is the rounding of xh + xl; its rounding interval runs
// between the midpoints with its neighbours, or to ±(max + ulp(max)/2) at the
// overflow threshold. For float the midpoints are doubles; for double they are
// y ∓ gap/2, exact double-words (y subnormal is excluded: its half gap is not a
// double). `sign` is the known sign of x, for a result that rounds to zero.
template <class T>
std::optional<double> round_enclosure(const enclosure& x, int sign) {
    if (!known(x) || sign == 0) return std::nullopt;
    const double approx = x.hi + x.lo;
    const T y = static_cast<T>(approx);
    if (!std::isfinite(y)) return std::nullopt;
    const T below = next_down(y), above = next_up(y);
    // Gap to the neighbour; at ±max the neighbour beyond is the threshold's twin.
    const double gap_below = std::isinf(below) ? double(above) - double(y) : double(y) - double(below);
    const double gap_above = std::isinf(above) ? double(y) - double(below) : double(above) - double(y);
    bool inside = false;
    if constexpr (std::is_same_v<T, float>) {
        inside = exceeds(x.hi, x.lo, x.err, double(y) - 0.5 * gap_below) &&
                 exceeds(-x.hi, -x.lo, x.err, -(double(y) + 0.5 * gap_above));
    } else {
        if (std::fabs(y) < 0x1p-1000) return std::nullopt;
        inside = exceeds(x.hi, x.lo, x.err, y, -0.5 * gap_below) && exceeds(-x.hi, -x.lo, x.err, -y, -0.5 * gap_above);
    }
    if (!inside) return std::nullopt;
    if (y == 0) return sign < 0 ? -0.0 : 0.0;
    return static_cast<double>(y);
}

// The exponent of ulp(x) in T, when the enclosure settles x's sign and
// binade (2^e ≤ |x| < 2^(e+1), checked on the whole enclosure; |x| = 2^e
// exactly is left to the exact route).
template <class T>
std::optional<int> ulp_exponent_of(const enclosure& x) {
    const int sign = side_of(x, 0.0);
    if (sign == 0) return std::nullopt;
    const double approx = x.hi + x.lo;
    const int e = std::ilogb(approx);
    const double lower = std::ldexp(1.0, e), upper = std::ldexp(1.0, e + 1);
    const bool in_binade = sign > 0 ? exceeds(x.hi, x.lo, x.err, lower) && exceeds(-x.hi, -x.lo, x.err, -upper)
                                    : exceeds(-x.hi, -x.lo, x.err, lower) && exceeds(x.hi, x.lo, x.err, -upper);
    if (!in_binade) return std::nullopt;
    return std::max(e, format<T>::emin) - format<T>::p + 1;
}

// RN(|difference| / 2^ulp_exponent) when the bound settles it: the
// difference's sign is certain and the whole scaled enclosure lies inside one
// rounding interval of a double (the contract of ulp_error: every digit right).
std::optional<double> rounded_ulp_ratio(bounded difference, int ulp_exponent) {
    const int position = certain_sign(difference);
    if (position == 0) return std::nullopt;
    if (position < 0) difference = -difference;
    const int scaled_exponent = std::ilogb(difference.v.h) - ulp_exponent;
    if (scaled_exponent < -900 || scaled_exponent > 1000) return std::nullopt;
    const enclosure ratio{std::ldexp(difference.v.h, -ulp_exponent), std::ldexp(difference.v.l, -ulp_exponent),
                          std::max(std::ldexp(difference.err, -ulp_exponent), 0x1p-1000)};
    return round_enclosure<double>(ratio, +1);
}

// |value − x| / ulp(x) correctly rounded, from an enclosure of x, when the
// enclosure settles x's sign, its binade, value ≠ x and the rounding of the
// ratio.
template <class T>
std::optional<double> ulp_error_from(const enclosure& x, double value) {
    if (!known(x)) return std::nullopt;
    if (!std::isfinite(value)) return std::numeric_limits<double>::infinity();
    if (side_of(x, value) == 0) return std::nullopt;
    const std::optional<int> ulp_exponent = ulp_exponent_of<T>(x);
    if (!ulp_exponent) return std::nullopt;
    return rounded_ulp_ratio(exactly(value) - bounded{{x.hi, x.lo}, x.err}, *ulp_exponent);
}

std::optional<double> ulp_error_from(precision p, const enclosure& x, double value) {
    return p == precision::binary32 ? ulp_error_from<float>(x, value) : ulp_error_from<double>(x, value);
}

// The same from a bounded value − x and an enclosure of x for its binade.
std::optional<double> ulp_error_from(precision p, const enclosure& x, const bounded& difference) {
    const std::optional<int> ulp_exponent =
        p == precision::binary32 ? ulp_exponent_of<float>(x) : ulp_exponent_of<double>(x);
    if (!ulp_exponent) return std::nullopt;
    return rounded_ulp_ratio(difference, *ulp_exponent);
}

// Filter range: 0 or 2^−80 ≤ |x| ≤ 2^80 (see the range note above).
inline bool in_filter_range(double x) {
    const double m = std::fabs(x);
    return m == 0 || (m >= 0x1p-80 && m <= 0x1p80);
}

// What the filter computed for one case.
struct filtered_quadratic {
    int discriminant_sign = 0;  // 0: undecided, the exact route must classify
    enclosure roots[2];         // near, far; unknown when the root step failed
};

filtered_quadratic filter_quadratic(const ray_sphere<double>& g) {
    filtered_quadratic out;
    const double o[3] = {g.origin.x, g.origin.y, g.origin.z};
    const double d[3] = {g.direction.x, g.direction.y, g.direction.z};
    const double c[3] = {g.centre.x, g.centre.y, g.centre.z};
    for (int axis = 0; axis < 3; ++axis)
        if (!in_filter_range(o[axis]) || !in_filter_range(d[axis]) || !in_filter_range(c[axis])) return out;
    if (!in_filter_range(g.radius)) return out;

    // f = o − c exactly, as double-words (two_sum).
    bounded f[3];
    for (int axis = 0; axis < 3; ++axis) f[axis] = exactly(two_sum(o[axis], -c[axis]));

    // a = d·d, b′ = d·f, C = f·f − r², and Δ′ = a·r² − |d × f|² (Lagrange's
    // identity (d·d)(f·f) − (d·f)² = |d × f|² turns b′² − aC into a form
    // without the cancellation b′² − aC suffers for far spheres).
    const bounded r2 = exactly(two_prod(g.radius, g.radius));
    const bounded a = exactly(two_prod(d[0], d[0])) + exactly(two_prod(d[1], d[1])) + exactly(two_prod(d[2], d[2]));
    const bounded b_prime = f[0] * d[0] + f[1] * d[1] + f[2] * d[2];
    const bounded C = f[0] * f[0] + f[1] * f[1] + f[2] * f[2] - r2;
    const bounded cross[3] = {f[2] * d[1] - f[1] * d[2], f[0] * d[2] - f[2] * d[0], f[1] * d[0] - f[0] * d[1]};
    const bounded discriminant = a * r2 - (cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2]);

    // Class: the sign of Δ′ when its bound settles it.
    out.discriminant_sign = certain_sign(discriminant);
    if (out.discriminant_sign <= 0) return out;

    // Roots without cancellation: q = −(b′ + σ√Δ′), σ the sign of b′'s
    // estimate (either choice is rigorous, this one keeps |q| ≥ √Δ′); the
    // roots are q/a and C/q. σ = +1: q/a is the near root; σ = −1: the far.
    const std::optional<bounded> root = square_root(discriminant);
    if (!root) return out;
    const bool positive_b = b_prime.v.h >= 0;
    const bounded q = positive_b ? -(b_prime + *root) : *root - b_prime;
    const std::optional<bounded> t_q = quotient(q, a), t_c = quotient(C, q);
    if (!t_q || !t_c) return out;
    const bounded& near = positive_b ? *t_q : *t_c;
    const bounded& far = positive_b ? *t_c : *t_q;
    out.roots[0] = {near.v.h, near.v.l, near.err};
    out.roots[1] = {far.v.h, far.v.l, far.err};
    return out;
}

// Coordinate `axis` of o + t·d from an enclosure of t: o exactly when d's
// coordinate is 0, else o + t·d in double-words.
enclosure hit_coordinate_enclosure(const ray_sphere<double>& g, const enclosure& t, int axis) {
    const double o = g.origin[axis], d = g.direction[axis];
    if (d == 0) return {o, 0, 0};
    if (!known(t)) return {};
    const bounded h = bounded{{t.hi, t.lo}, t.err} * d + exactly(o);
    return {h.v.h, h.v.l, h.err};
}

using refined_enclosure = exact_solution::refined_enclosure;

// The quadratic's coefficients as exact expansions: f = o − c, a = d·d,
// 2b′ = 2d·f, C = f·f − r², and Δ′ = a·r² − |d × f|² (Lagrange's identity, as
// the filter). Exact for inputs in the filter range, where every product
// stays far from underflow and overflow (degree 4: above 2^−528, below 2^330).
struct exact_coefficients {
    expansion<2> f[3];
    expansion<6> a;
    expansion<12> two_b_prime;
    expansion<26> C;
};

exact_coefficients coefficients_of(const ray_sphere<double>& g) {
    exact_coefficients k;
    const double d[3] = {g.direction.x, g.direction.y, g.direction.z};
    for (int axis = 0; axis < 3; ++axis) k.f[axis] = expansion_of(g.origin[axis]) - expansion_of(g.centre[axis]);
    const expansion<2>* f = k.f;
    k.a = expansion_of(d[0]) * d[0] + expansion_of(d[1]) * d[1] + expansion_of(d[2]) * d[2];
    k.two_b_prime = f[0] * (2 * d[0]) + f[1] * (2 * d[1]) + f[2] * (2 * d[2]);
    k.C = f[0] * f[0] + f[1] * f[1] + f[2] * f[2] - expansion_of(g.radius) * g.radius;
    return k;
}

int discriminant_sign(const ray_sphere<double>& g, const exact_coefficients& k) {
    const double d[3] = {g.direction.x, g.direction.y, g.direction.z};
    const expansion<2>* f = k.f;
    const expansion<8> cross[3] = {f[2] * d[1] - f[1] * d[2], f[0] * d[2] - f[2] * d[0], f[1] * d[0] - f[0] * d[1]};
    const expansion<408> discriminant =
        k.a * (expansion_of(g.radius) * g.radius) - (cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2]);
    return sign_of(discriminant);
}

bool in_filter_range(const ray_sphere<double>& g) {
    for (int axis = 0; axis < 3; ++axis)
        if (!in_filter_range(g.origin[axis]) || !in_filter_range(g.direction[axis]) || !in_filter_range(g.centre[axis]))
            return false;
    return in_filter_range(g.radius);
}

// Roots with |u| in [2^−200, 2^200] only: beside the inputs' range, that
// keeps the expansions of P(u) exact (every component above 2^−720, below 2^570).
bool refinable(double u) { return std::fabs(u) >= 0x1p-200 && std::fabs(u) <= 0x1p200; }

// A finer enclosure of the root t_i from its enclosure's high word u = xh:
// with P(t) = a t² + 2b′t + C = a(t − t_i)(t − t_j), the correction is
// t_i − u = −P(u) / (a (u − t_j)). P(u) is evaluated exactly as an expansion
// (degree 4 in the inputs and u: nothing rounds), so the correction, about
// 2^−53·|t_i|, is known to about 2^−100 of itself. Needs both roots'
// enclosures (hence the filter range for the inputs) and 2^−200 ≤ |u| ≤ 2^200,
// where no product of the expansion underflows or overflows (every component
// stays above 2^−720 and below 2^570); err = +inf otherwise, or when u − t_j's
// sign is uncertain (roots too close for the enclosures to part).
refined_enclosure refine_root(const exact_coefficients& k, const enclosure& root, const enclosure& other) {
    refined_enclosure out;
    const double u = root.hi;
    if (!known(root) || !known(other) || !refinable(u)) return out;
    out.base = u;
    const expansion<74> P = (k.a * u) * u + k.two_b_prime * u + k.C;
    const bounded gap = exactly(u) - bounded{{other.hi, other.lo}, other.err};  // u − t_j
    const std::optional<bounded> offset = quotient(approximate(P), approximate(k.a) * gap);  // u − t_i
    if (!offset) return out;
    out.correction = {-offset->v.h, -offset->v.l, offset->err};
    return out;
}

// The same for a tangent's root t = −b′/a: t − u = −(2b′ + 2a·u) / 2a, the
// numerator exact.
refined_enclosure refine_tangent_root(const exact_coefficients& k, const enclosure& root) {
    refined_enclosure out;
    const double u = root.hi;
    if (!known(root) || !refinable(u)) return out;
    out.base = u;
    const expansion<36> numerator = k.two_b_prime + (k.a * u) * 2.0;
    const std::optional<bounded> offset = quotient(approximate(numerator), approximate(k.a) * 2.0);  // u − t
    if (!offset) return out;
    out.correction = {-offset->v.h, -offset->v.l, offset->err};
    return out;
}

// value − t_i from a refined enclosure, as a bounded double-word: (value − u)
// is exact, the correction carries the bound.
bounded root_difference(const refined_enclosure& t, double value) {
    return exactly(two_sum(value, -t.base)) - bounded{{t.correction.hi, t.correction.lo}, t.correction.err};
}

// value − p* for p* = o + d·t_i: (value − o − d·u) in double-words, whose
// operations err relative to the (small) result only, minus d·correction.
bounded hit_difference(const refined_enclosure& t, double o, double d, double value) {
    const bounded residual = exactly(two_sum(value, -o)) - exactly(two_prod(d, t.base));
    return residual - bounded{{t.correction.hi, t.correction.lo}, t.correction.err} * d;
}

// RN of a hit coordinate when its enclosure settles it.
std::optional<double> round_hit_coordinate(precision prec, const ray_sphere<double>& g, const enclosure& t, int axis) {
    const enclosure h = hit_coordinate_enclosure(g, t, axis);
    // d's coordinate 0: the coordinate is o's, rounded (a −0 becomes +0, as RN(0) = +0).
    if (known(h) && h.err == 0 && h.lo == 0)
        return (prec == precision::binary32 ? double(static_cast<float>(h.hi)) : h.hi) + 0.0;
    return prec == precision::binary32 ? round_enclosure<float>(h, side_of(h, 0.0))
                                       : round_enclosure<double>(h, side_of(h, 0.0));
}

// Everything the filter settles for one case; what it leaves unknown (a sign
// 0 with a root not provably nonzero, an empty optional) the exact state
// answers.
struct filtered_case {
    int discriminant_sign = 0;  // 0: undecided, the exact route must run
    enclosure roots[2];
    int sign[2] = {0, 0};
    std::optional<double> rounded[2];
    std::optional<double> hit[3];  // the front root's, when both signs are known
};

// Flattened into one function and cloned for FMA hardware (std::fma inlines
// to one instruction there; elsewhere it is a library call). Both clones
// compute the same bits: every operation is correctly rounded. clang (the
// fuzz build) rejects flatten beside target_clones, so it only clones.
#if defined(__clang__)
#define RAYVERIFY_FILTER_ATTRIBUTES __attribute__((target_clones("fma", "default")))
#else
#define RAYVERIFY_FILTER_ATTRIBUTES [[gnu::flatten]] __attribute__((target_clones("fma", "default")))
#endif
RAYVERIFY_FILTER_ATTRIBUTES filtered_case
filter_case(const ray_sphere<double>& g, precision prec) {
    filtered_case out;
    const filtered_quadratic q = filter_quadratic(g);
    out.discriminant_sign = q.discriminant_sign;
    if (q.discriminant_sign <= 0) return out;
    for (int i = 0; i < 2; ++i) {
        out.roots[i] = q.roots[i];
        out.sign[i] = side_of(q.roots[i], 0.0);
        if (out.sign[i] != 0)
            out.rounded[i] = prec == precision::binary32 ? round_enclosure<float>(q.roots[i], out.sign[i])
                                                         : round_enclosure<double>(q.roots[i], out.sign[i]);
    }
    if (out.sign[0] == 0 || out.sign[1] == 0) return out;
    const int front = out.sign[0] > 0 ? 0 : out.sign[1] > 0 ? 1 : -1;
    if (front >= 0)
        for (int axis = 0; axis < 3; ++axis) out.hit[axis] = round_hit_coordinate(prec, g, q.roots[front], axis);
    return out;
}

}  // namespace

struct exact_solution::expansion_state {
    exact_coefficients coefficients;
};

// The filter route and the lazy exact route, with access to the solution.
struct exact_solution::internal {
    // The case's coefficients as expansions, built on first use and kept.
    static const exact_coefficients& coefficients(const exact_solution& s) {
        if (!s.expansions_) s.expansions_ = std::make_shared<const expansion_state>(expansion_state{coefficients_of(s.geometry_)});
        return s.expansions_->coefficients;
    }

    static const enclosure& root_enclosure(const exact_solution& s, root_index i) {
        return s.roots_[i == root_index::near_root ? 0 : 1];
    }

    static enclosure hit_enclosure(const exact_solution& s, root_index i, int axis) {
        return hit_coordinate_enclosure(s.geometry_, root_enclosure(s, i), axis);
    }

    // sign(t_i − m) exactly with expansions, no big numbers: a tangent's root
    // −b′/a against m from the sign of 2b′ + 2a·m; one of two roots from
    // P(m) = a(m − t_i)(m − t_j) once the other root's enclosure parts m from
    // t_j. Needs the roots' enclosures (the filter range) and m = 0 or
    // refinable; nullopt otherwise.
    static std::optional<int> compare_root_by_expansion(const exact_solution& s, root_index i, double m) {
        const int k = i == root_index::near_root ? 0 : 1;
        if (s.cls == line_class::miss || !known(s.roots_[k]) || !(m == 0 || refinable(m))) return std::nullopt;
        const exact_coefficients& c = coefficients(s);
        if (s.cls == line_class::tangent) return -sign_of(c.two_b_prime + (c.a * m) * 2.0);
        const int other_side = side_of(s.roots_[1 - k], m);  // sign(t_j − m)
        if (other_side == 0) return std::nullopt;
        const int p = sign_of((c.a * m) * m + c.two_b_prime * m + c.C);  // sign(m − t_i)·sign(m − t_j)
        return -p * -other_side;
    }

    // |value − t_i| / ulp(t_i) when the enclosure leaves value = t_i or t_i's
    // binade open (an exactly representable root, one at a power of two):
    // both decided with compare_root_by_expansion, the ratio from the refined
    // enclosure.
    static std::optional<double> root_ulp_error_by_expansion(const exact_solution& s, root_index i, double value) {
        const std::optional<int> position = compare_root_by_expansion(s, i, value);
        if (!position) return std::nullopt;
        if (*position == 0) return 0.0;
        const exact_root& root = s.root(i);
        const refined_enclosure* fine = refined(s, i);
        if (root.sign == 0 || fine == nullptr) return std::nullopt;
        const enclosure& coarse = root_enclosure(s, i);
        const int guess = std::ilogb(coarse.hi + coarse.lo);
        for (int e = guess - 1; e <= guess + 1; ++e) {
            // 2^e ≤ |t_i| < 2^(e+1), decided exactly.
            const std::optional<int> low = compare_root_by_expansion(s, i, root.sign * std::ldexp(1.0, e));
            const std::optional<int> high = compare_root_by_expansion(s, i, root.sign * std::ldexp(1.0, e + 1));
            if (!low || !high) return std::nullopt;
            if (root.sign * *low < 0 || root.sign * *high >= 0) continue;
            const int ulp_exponent = s.prec == precision::binary32
                                         ? std::max(e, format<float>::emin) - format<float>::p + 1
                                         : std::max(e, format<double>::emin) - format<double>::p + 1;
            return rounded_ulp_ratio(root_difference(*fine, value), ulp_exponent);
        }
        return std::nullopt;
    }

    // The root's refined enclosure, built on first use; nullptr when it cannot be.
    static const refined_enclosure* refined(const exact_solution& s, root_index i) {
        const int k = i == root_index::near_root ? 0 : 1;
        if (!s.refined_built_[k]) {
            s.refined_[k] = s.cls == line_class::tangent ? refine_tangent_root(coefficients(s), s.roots_[k])
                                                          : refine_root(coefficients(s), s.roots_[k], s.roots_[1 - k]);
            s.refined_built_[k] = true;
        }
        return known(s.refined_[k].correction) ? &s.refined_[k] : nullptr;
    }

    static int compare_roots(const exact_solution& a, root_index i, const exact_solution& b, root_index j) {
        const enclosure& x = root_enclosure(a, i);
        const enclosure& y = root_enclosure(b, j);
        if (known(x) && known(y)) {
            const bounded difference = bounded{{x.hi, x.lo}, x.err} - bounded{{y.hi, y.lo}, y.err};
            if (const int sign = certain_sign(difference); sign != 0) return sign;
        }
        return sign_of_difference(a.state().root(i), b.state().root(j));
    }

    static exact_solution reference(const ray_sphere<double>& g, precision prec, std::optional<double> tmin,
                                    std::optional<double> tmax, bool unit_direction = false) {
        exact_solution solution;
        solution.prec = prec;
        solution.geometry_ = g;
        solution.invalid = check_case(g, tmin, tmax);
        if (!solution.valid()) return solution;
        solution.stage = oracle_stage::exact;

        std::shared_ptr<exact_state> state = build_exact_state(g, unit_direction);
        const int sign_discriminant = sign_of(state->discriminant);
        solution.cls = sign_discriminant < 0   ? line_class::miss
                       : sign_discriminant == 0 ? line_class::tangent
                                                : line_class::two_hit;
        if (solution.cls == line_class::miss) return solution;
        for (root_index i : {root_index::near_root, root_index::far_root}) {
            exact_root& out = i == root_index::near_root ? solution.near_root : solution.far_root;
            out.sign = state->root(i).sign();
            out.rounded = round_in(prec, state->root(i));
        }
        solution.nearest_in_front = nearest_root_in_front(solution.near_root.sign, solution.far_root.sign);

        solution.exact_ = std::move(state);
        if (solution.nearest_in_front) {
            const root_index front = *solution.nearest_in_front;
            const auto coordinate = [&](int axis) {
                return round_in(prec, solution.exact_->hit_coordinate(front, axis));
            };
            solution.hit_point = {coordinate(0), coordinate(1), coordinate(2)};
        }
        return solution;
    }

    // Δ′ = 0 decided with an expansion (the filter range only): the root −b′/a
    // enclosed, signed and rounded in double-words, and the hit point (a
    // coordinate its enclosure cannot round, such as an exact 0, from the
    // exact state); nullopt (the exact route) when Δ′ ≠ 0 or the root's
    // enclosure cannot be rounded (a tie).
    static std::optional<exact_solution> exact_tangent(const ray_sphere<double>& g, precision prec) {
        if (!in_filter_range(g)) return std::nullopt;
        exact_solution solution;
        solution.prec = prec;
        solution.geometry_ = g;
        const exact_coefficients& k = coefficients(solution);
        if (discriminant_sign(g, k) != 0) return std::nullopt;
        solution.cls = line_class::tangent;
        exact_root root;
        enclosure t{0, 0, 0};
        root.sign = -sign_of(k.two_b_prime) * sign_of(k.a);
        if (root.sign != 0) {
            const std::optional<bounded> quotient_found = quotient(-approximate(k.two_b_prime), approximate(k.a) * 2.0);
            if (!quotient_found) return std::nullopt;
            t = {quotient_found->v.h, quotient_found->v.l, quotient_found->err};
            const std::optional<double> rounded = prec == precision::binary32 ? round_enclosure<float>(t, root.sign)
                                                                               : round_enclosure<double>(t, root.sign);
            if (!rounded) return std::nullopt;
            root.rounded = *rounded;
        }
        solution.roots_[0] = solution.roots_[1] = t;
        solution.near_root = solution.far_root = root;
        solution.nearest_in_front = nearest_root_in_front(root.sign, root.sign);
        if (solution.nearest_in_front) {
            const root_index front = *solution.nearest_in_front;
            solution.hit_point = {solution.rounded_hit_coordinate(front, 0), solution.rounded_hit_coordinate(front, 1),
                                  solution.rounded_hit_coordinate(front, 2)};
        }
        // A coordinate its enclosure could not round needed the exact state.
        solution.stage = solution.exact_ ? oracle_stage::exact : oracle_stage::expansion;
        return solution;
    }

    static exact_solution filtered(const ray_sphere<double>& g, precision prec, std::optional<double> tmin,
                                   std::optional<double> tmax) {
        exact_solution solution;
        solution.prec = prec;
        solution.invalid = check_case(g, tmin, tmax);
        if (!solution.valid()) return solution;
        const filtered_case filter = filter_case(g, prec);
        if (filter.discriminant_sign == 0) {
            if (std::optional<exact_solution> tangent = exact_tangent(g, prec)) return std::move(*tangent);
            return reference(g, prec, tmin, tmax);
        }

        solution.geometry_ = g;
        solution.roots_[0] = filter.roots[0];
        solution.roots_[1] = filter.roots[1];
        if (filter.discriminant_sign < 0) {
            solution.cls = line_class::miss;
            solution.stage = oracle_stage::filter;
            return solution;
        }
        solution.cls = line_class::two_hit;

        // A root whose sign the enclosure leaves open while the other's is
        // known is exactly 0 when C = 0 (an origin on the sphere): decided
        // with an expansion, the root is then the exact enclosure 0.
        int zero_root = -1;
        if ((filter.sign[0] == 0) != (filter.sign[1] == 0) && sign_of(coefficients(solution).C) == 0) {
            zero_root = filter.sign[0] == 0 ? 0 : 1;
            solution.roots_[zero_root] = {0, 0, 0};
        }
        // Signs and correctly rounded roots: from the filter, else exactly.
        for (root_index i : {root_index::near_root, root_index::far_root}) {
            const int k = i == root_index::near_root ? 0 : 1;
            exact_root& out = k == 0 ? solution.near_root : solution.far_root;
            if (k == zero_root) {
                out = {0, 0.0};  // RN(0) = +0
                continue;
            }
            out.sign = filter.sign[k] != 0 ? filter.sign[k] : solution.state().root(i).sign();
            out.rounded = filter.rounded[k] ? *filter.rounded[k] : round_in(prec, solution.state().root(i));
        }
        solution.nearest_in_front = nearest_root_in_front(solution.near_root.sign, solution.far_root.sign);

        if (solution.nearest_in_front) {
            const root_index front = *solution.nearest_in_front;
            const auto coordinate = [&](int axis) {
                return filter.hit[axis] ? *filter.hit[axis] : solution.rounded_hit_coordinate(front, axis);
            };
            solution.hit_point = {coordinate(0), coordinate(1), coordinate(2)};
        }
        // Exact arithmetic ran iff the exact state was needed.
        solution.stage = solution.exact_ ? oracle_stage::exact
                         : zero_root >= 0 ? oracle_stage::expansion
                                          : oracle_stage::filter;
        return solution;
    }
};

const exact_solution::exact_state& exact_solution::state() const {
    if (!exact_) exact_ = build_exact_state(geometry_);
    return *exact_;
}

int exact_solution::compare_root(root_index i, double value) const {
    const int side = side_of(internal::root_enclosure(*this, i), value);  // sign(t* − value)
    if (side != 0) return -side;
    if (const std::optional<int> sign = internal::compare_root_by_expansion(*this, i, value)) return -*sign;
    return -state().root(i).compare(exact(value));
}

int exact_solution::compare_midpoint(double value) const {
    // The midpoint's enclosure from the roots' (their mean), when the filter has them.
    const enclosure& near = internal::root_enclosure(*this, root_index::near_root);
    const enclosure& far = internal::root_enclosure(*this, root_index::far_root);
    if (known(near) && known(far)) {
        const bounded mean = (bounded{{near.hi, near.lo}, near.err} + bounded{{far.hi, far.lo}, far.err}) * 0.5;
        const int side = side_of({mean.v.h, mean.v.l, mean.err}, value);  // sign(m − value)
        if (side != 0) return -side;
    }
    // Exactly: m = A/den for the roots (A ∓ B√D)/den, so sign(value − m) = sign(value·den − A).
    const quadratic_irrational& root = state().near_root;
    return sign_of(exact(value) * root.den - root.A);
}

int exact_solution::compare_discriminant(double x) const { return sign_of(state().discriminant - exact(x)); }

oracle_stage_counts& oracle_stage_counts_this_thread() {
    thread_local oracle_stage_counts counts;
    return counts;
}

double exact_solution::root_ulp_error(root_index i, double value) const {
    oracle_stage_counts& counts = oracle_stage_counts_this_thread();
    const enclosure& root = internal::root_enclosure(*this, i);
    if (root.err == 0 && root.hi == 0 && std::isfinite(value)) {
        // An exact zero root (C = 0): ulp(0) is T's smallest subnormal, the
        // ratio |value| scaled by a power of two, exact unless it overflows.
        ++counts.ulp_enclosure;
        const int ulp_exponent = prec == precision::binary32 ? format<float>::emin - format<float>::p + 1
                                                             : format<double>::emin - format<double>::p + 1;
        return std::ldexp(std::fabs(value), -ulp_exponent);
    }
    if (const std::optional<double> e = ulp_error_from(prec, root, value)) return ++counts.ulp_enclosure, *e;
    if (const refined_enclosure* fine = internal::refined(*this, i))
        if (const std::optional<double> e = ulp_error_from(prec, root, root_difference(*fine, value)))
            return ++counts.ulp_refined, *e;
    if (std::isfinite(value))
        if (const std::optional<double> e = internal::root_ulp_error_by_expansion(*this, i, value))
            return ++counts.ulp_refined, *e;
    ++counts.ulp_exact;
    return ulp_error_in(prec, state().root(i), value);
}

double exact_solution::hit_point_ulp_error(root_index i, int axis, double value) const {
    oracle_stage_counts& counts = oracle_stage_counts_this_thread();
    const double o = geometry_.origin[axis], d = geometry_.direction[axis];
    const enclosure& root = internal::root_enclosure(*this, i);
    const bool exact_zero_root = root.err == 0 && root.hi == 0;
    if ((d == 0 || exact_zero_root) && value == o) return ++counts.ulp_enclosure, 0.0;  // the coordinate is o's
    const enclosure coordinate = internal::hit_enclosure(*this, i, axis);
    if (const std::optional<double> e = ulp_error_from(prec, coordinate, value)) return ++counts.ulp_enclosure, *e;
    if (const refined_enclosure* fine = internal::refined(*this, i))
        if (const std::optional<double> e = ulp_error_from(prec, coordinate, hit_difference(*fine, o, d, value)))
            return ++counts.ulp_refined, *e;
    ++counts.ulp_exact;
    return ulp_error_in(prec, state().hit_coordinate(i, axis), value);
}

double exact_solution::rounded_hit_coordinate(root_index i, int axis) const {
    if (const std::optional<double> r = round_hit_coordinate(prec, geometry_, internal::root_enclosure(*this, i), axis))
        return *r;
    return round_in(prec, state().hit_coordinate(i, axis));
}

int exact_solution::compare_hit_coordinate(root_index i, int axis, double value) const {
    const int side = side_of(internal::hit_enclosure(*this, i, axis), value);  // sign(p* − value)
    if (side != 0) return -side;
    return -state().hit_coordinate(i, axis).compare(exact(value));
}

double exact_solution::hit_coordinate_in_double(root_index i, int axis) const {
    if (prec == precision::binary64) return rounded_hit_coordinate(i, axis);
    if (const std::optional<double> r =
            round_hit_coordinate(precision::binary64, geometry_, internal::root_enclosure(*this, i), axis))
        return *r;
    return round_in(precision::binary64, state().hit_coordinate(i, axis));
}

exact_solution solve_exact_unit_direction(const ray_sphere<double>& g, precision prec) {
    return exact_solution::internal::reference(g, prec, std::nullopt, std::nullopt, true);
}

int compare_squared_length(const vec3<double>& d, double x) {
    const bool filterable = in_filter_range(d.x) && in_filter_range(d.y) && in_filter_range(d.z) && in_filter_range(x);
    if (filterable) {
        const bounded length = exactly(two_prod(d.x, d.x)) + exactly(two_prod(d.y, d.y)) + exactly(two_prod(d.z, d.z));
        if (const int sign = certain_sign(length - exactly(x)); sign != 0) return sign;
    }
    const exact dx(d.x), dy(d.y), dz(d.z);
    return sign_of(dx * dx + dy * dy + dz * dz - exact(x));
}

bool box_meets_sphere(const vec3<double>& lower, const vec3<double>& upper, const vec3<double>& centre, double radius) {
    exact nearest(0.0), farthest(0.0);
    for (int axis = 0; axis < 3; ++axis) {
        const exact below = exact(lower[axis]) - exact(centre[axis]), above = exact(upper[axis]) - exact(centre[axis]);
        // The nearest coordinate is c's own when the slab holds it, else the nearer end.
        if (sign_of(below) > 0) nearest = nearest + below * below;
        else if (sign_of(above) < 0) nearest = nearest + above * above;
        const exact low_squared = below * below, high_squared = above * above;
        farthest = farthest + (low_squared < high_squared ? high_squared : low_squared);
    }
    const exact r_squared = exact(radius) * exact(radius);
    return sign_of(nearest - r_squared) <= 0 && sign_of(farthest - r_squared) >= 0;
}

int compare_roots(const exact_solution& a, root_index i, const exact_solution& b, root_index j) {
    return exact_solution::internal::compare_roots(a, i, b, j);
}

exact_solution solve_exact(const ray_sphere<double>& g, precision prec, std::optional<double> tmin,
                           std::optional<double> tmax) {
    exact_solution solution = exact_solution::internal::filtered(g, prec, tmin, tmax);
    if (solution.valid()) {
        oracle_stage_counts& counts = oracle_stage_counts_this_thread();
        ++(solution.stage == oracle_stage::filter      ? counts.solutions_filter
           : solution.stage == oracle_stage::expansion ? counts.solutions_expansion
                                                       : counts.solutions_exact);
    }
    return solution;
}

exact_solution solve_exact_reference(const ray_sphere<double>& g, precision prec, std::optional<double> tmin,
                                     std::optional<double> tmax) {
    return exact_solution::internal::reference(g, prec, tmin, tmax);
}

}  // namespace rayverify
