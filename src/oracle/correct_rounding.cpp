// Correct rounding in the exact route (internal/correct_rounding.h).
#include "oracle/internal/correct_rounding.h"

#include <mpfr.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include "core/float_bits.h"

namespace rayverify::oracle_internal {
namespace {

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
    approximate(x, 2 * std::numeric_limits<T>::digits + 64, approx);
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
    const long e = sign_x == 0 ? std::numeric_limits<T>::min_exponent - 1 : binade(x);
    const long ulp_exponent = ulp_exponent_of_binade<T>(e);

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

// sign(|value − x| − bound·ulp(x)): x against value ∓ bound·ulp(x), exactly.
template <class T>
int compare_ulp_error(const quadratic_irrational& x, double value, double bound) {
    const int side = x.compare(exact(value));  // sign(x − value)
    if (side == 0) return bound > 0 ? -1 : 0;
    const long e = x.sign() == 0 ? std::numeric_limits<T>::min_exponent - 1 : binade(x);
    const exact allowed = exact(bound) * power_of_two(ulp_exponent_of_binade<T>(e));
    // x above value: |value − x| − allowed = x − (value + allowed); below: (value − allowed) − x.
    return side > 0 ? x.compare(exact(value) + allowed) : -x.compare(exact(value) - allowed);
}

template <class T>
double round_in(const quadratic_irrational& x) {
    return static_cast<double>(round_to_nearest<T>(x));
}

}  // namespace

double round_in(precision p, const quadratic_irrational& x) {
    return with_precision(p, [&]<class T>(std::type_identity<T>) { return round_in<T>(x); });
}

int compare_ulp_error_in(precision p, const quadratic_irrational& x, double value, double bound) {
    return with_precision(p, [&]<class T>(std::type_identity<T>) { return compare_ulp_error<T>(x, value, bound); });
}

double ulp_error_in(precision p, const quadratic_irrational& x, double value) {
    return with_precision(p, [&]<class T>(std::type_identity<T>) { return ulp_error<T>(x, value); });
}

}  // namespace rayverify::oracle_internal
