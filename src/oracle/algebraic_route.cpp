// The algebraic route: every exact value is a CGAL::Sqrt_extension over
// CGAL::Gmpq, a0 + a1·√Δ with rational a0, a1, Δ, and every decision is one of
// CGAL's exact comparisons of such a value with a rational (interval filter
// first, then squaring). Nothing here comes from oracle.cpp.
//
// Scaling. The inputs are scaled by powers of two before anything is
// computed, o, c, r by 2^−s and d by 2^−k (s, k the binary exponents of the
// largest position and direction coordinates), so that the scaled values are
// near 1 and CGAL::to_interval gives a useful guess even when the true values
// lie far outside the double range. Scaling is exact: a root is
// t* = t_s·2^(s−k) and a hit coordinate o + t*·d = (o_s + t_s·d_s)·2^s, and a
// comparison of x·2^e with a rational m is that of x with m·2^−e.
//
// Rounding. RN(x) in T is the representable value whose rounding interval
// holds x: between the midpoints with its neighbours, the extreme finite
// values' outer boundary being the overflow threshold max + ulp(max)/2, and a
// tie going to the even significand (so a tie at the threshold goes to
// infinity, as IEEE 754 says). On the ordered line of T (core/float_bits.h)
// that is the smallest index i with x ≤ U(i), U(i) the boundary between i and
// i + 1, moved to i + 1 when x = U(i) and i is odd. The search starts at a
// guess (the middle of CGAL::to_interval; for the root where −b′ and √Δ′
// cancel, C/a divided by the other root's guess), gallops away from it until
// it brackets the answer and bisects the bracket: two exact comparisons when
// the guess is right, never more than about 130 when it is not.
#include "oracle/algebraic_route.h"

#include <CGAL/Gmpq.h>
#include <CGAL/Root_of_traits.h>
#include <CGAL/Sqrt_extension.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>
#include <utility>

#include "core/float_bits.h"

namespace rayverify {
namespace {

using rational = CGAL::Gmpq;
// CGAL's Root_of_2 over the rationals: comparisons with an interval filter,
// values of different extensions comparable (a tangent's root has none).
using root_of_2 = CGAL::Sqrt_extension<rational, rational, CGAL::Tag_true, CGAL::Tag_true>;
static_assert(std::is_same_v<root_of_2, CGAL::Root_of_traits<rational>::Root_of_2>);

int sign_of(CGAL::Sign s) { return static_cast<int>(s); }

// x·2^k, exactly.
rational scaled(const rational& x, long k) {
    rational out;
    if (k >= 0)
        mpq_mul_2exp(out.mpq(), x.mpq(), static_cast<mp_bitcnt_t>(k));
    else
        mpq_div_2exp(out.mpq(), x.mpq(), static_cast<mp_bitcnt_t>(-k));
    return out;
}

// An exact value x·2^exponent, and a guess of x in double to start rounding from.
struct exact_value {
    root_of_2 x;
    long exponent = 0;
    double guess = 0;

    // sign(value − m) for a finite double m.
    int compare(double m) const { return sign_of(x.compare(scaled(rational(m), -exponent))); }
    // sign(value − m) for a rational m.
    int compare(const rational& m) const { return sign_of(x.compare(scaled(m, -exponent))); }
};

// x·2^exponent with the middle of CGAL's interval of x (outward rounded; an
// end may be infinite) as its guess.
exact_value with_interval_guess(root_of_2 x, long exponent) {
    const std::pair<double, double> interval = CGAL::to_interval(x);
    double middle = interval.first / 2 + interval.second / 2;
    if (!std::isfinite(middle)) middle = std::isfinite(interval.first) ? interval.first : interval.second;
    if (!std::isfinite(middle)) middle = 0;
    return {std::move(x), exponent, middle};
}

// The boundary U(i) between positions i and i + 1 of T's ordered line
// (−infinity_index ≤ i < infinity_index): the midpoint of the two values, or
// ∓(max + ulp(max)/2) next to an infinity.
template <class T>
rational upper_boundary(std::int64_t i) {
    constexpr std::int64_t inf = infinity_index<T>();
    if (i + 1 == inf || i == -inf) {
        constexpr T max = std::numeric_limits<T>::max();
        const rational threshold = rational(double(max)) + rational(ulp_of(max) / 2);
        return i == -inf ? -threshold : threshold;
    }
    return (rational(double(from_ordered_index<T>(i))) + rational(double(from_ordered_index<T>(i + 1)))) / 2;
}

// RN(value) in T, decided by exact comparisons with the rounding boundaries;
// `sign` is the value's exact sign.
template <class T>
T round_to_nearest(const exact_value& v, int sign) {
    if (sign == 0) return T(0);
    constexpr std::int64_t inf = infinity_index<T>();
    // sign(value − U(i)); U(infinity_index) = +∞.
    const auto versus_boundary = [&v](std::int64_t i) { return i >= inf ? -1 : v.compare(upper_boundary<T>(i)); };

    // Invariant: value > U(lo) (or lo = −inf − 1) and value ≤ U(hi); hi_tie: value = U(hi).
    std::int64_t lo = -inf - 1, hi = inf;
    bool hi_tie = false;
    // Moves the end of the bracket that i replaces; true when that is hi.
    const auto probe = [&](std::int64_t i) {
        const int side = versus_boundary(i);
        if (side <= 0) {
            hi = i;
            hi_tie = side == 0;
        } else {
            lo = i;
        }
        return side <= 0;
    };
    const std::int64_t guess =
        ordered_index(static_cast<T>(std::ldexp(v.guess, static_cast<int>(std::clamp(v.exponent, -4000L, 4000L)))));
    const bool down = probe(guess);
    // Gallop away from the guess, doubling the step, until a candidate passes
    // the value or the line's end is reached. Positions and the room to the
    // end (< 2^64) are stepped in unsigned arithmetic, where nothing overflows.
    const auto from = static_cast<std::uint64_t>(guess), end = static_cast<std::uint64_t>(inf);
    const std::uint64_t room = down ? from + end : end - from;
    for (std::uint64_t step = 1; room > 0; step = step >= room - step ? room : 2 * step) {
        const auto candidate = static_cast<std::int64_t>(down ? from - step : from + step);
        if (probe(candidate) != down || step == room) break;
    }
    // Bisect (lo, hi]; the span can exceed 2^63, so it is halved unsigned.
    while (static_cast<std::uint64_t>(hi) - static_cast<std::uint64_t>(lo) > 1)
        probe(lo + static_cast<std::int64_t>((static_cast<std::uint64_t>(hi) - static_cast<std::uint64_t>(lo)) / 2));
    // A tie goes to the even significand: position parity is significand parity.
    const std::int64_t position = (hi_tie && (hi & 1) != 0) ? hi + 1 : hi;
    const T y = from_ordered_index<T>(position);
    if (y == 0) return sign < 0 ? -T(0) : T(0);
    return y;
}

double round_in(precision p, const exact_value& v, int sign) {
    return with_precision(p, [&]<class T>(std::type_identity<T>) { return double(round_to_nearest<T>(v, sign)); });
}

// sign(value − bound) for a bound that may be infinite.
int versus(const exact_value& v, double bound) {
    if (std::isinf(bound)) return bound > 0 ? -1 : +1;
    return v.compare(bound);
}

invalid_reason check(const ray_sphere<double>& g, std::optional<double> tmin, std::optional<double> tmax) {
    const invalid_reason reason = validity<double>(g);
    if (reason != invalid_reason::none) return reason;
    const bool nan_bound = (tmin && std::isnan(*tmin)) || (tmax && std::isnan(*tmax));
    if (nan_bound || (tmin && tmax && *tmin > *tmax)) return invalid_reason::bad_interval;
    return invalid_reason::none;
}

// The binary exponent of the largest |x|, 0 when all are 0.
int largest_exponent(std::initializer_list<double> values) {
    double largest = 0;
    for (double x : values) largest = std::max(largest, std::fabs(x));
    return largest == 0 ? 0 : std::ilogb(largest);
}

}  // namespace

algebraic_answer solve_algebraic(const ray_sphere<double>& g, precision prec, std::optional<double> tmin,
                                 std::optional<double> tmax) {
    algebraic_answer out;
    out.prec = prec;
    out.invalid = check(g, tmin, tmax);
    if (!out.valid()) return out;

    // Scaled inputs, exactly: o_s, c_s, r_s = (o, c, r)·2^−s, d_s = d·2^−k.
    const int s = largest_exponent({g.origin.x, g.origin.y, g.origin.z, g.centre.x, g.centre.y, g.centre.z, g.radius});
    const int k = largest_exponent({g.direction.x, g.direction.y, g.direction.z});
    rational o[3], d[3];
    rational a(0), b_prime(0), f_squared(0);
    for (int axis = 0; axis < 3; ++axis) {
        o[axis] = scaled(rational(g.origin[axis]), -s);
        d[axis] = scaled(rational(g.direction[axis]), -k);
        const rational f = o[axis] - scaled(rational(g.centre[axis]), -s);
        a += d[axis] * d[axis];
        b_prime += d[axis] * f;
        f_squared += f * f;
    }
    const rational r = scaled(rational(g.radius), -s);
    const rational C = f_squared - r * r;
    const rational discriminant = b_prime * b_prime - a * C;

    // Class.
    out.discriminant_sign = sign_of(CGAL::sign(discriminant));
    if (out.discriminant_sign < 0) return out;

    // Roots (−b′ ∓ √Δ′)/a; a tangent's double root −b′/a has no square root.
    const long root_exponent = long{s} - k;
    exact_value roots[2];
    if (out.discriminant_sign == 0) {
        roots[0] = roots[1] = with_interval_guess(root_of_2(-b_prime / a), root_exponent);
    } else {
        roots[0] = with_interval_guess(root_of_2(-b_prime, rational(-1), discriminant) / a, root_exponent);
        roots[1] = with_interval_guess(root_of_2(-b_prime, rational(1), discriminant) / a, root_exponent);
        // The root where −b′ and ∓√Δ′ cancel is guessed better from the
        // product of the roots, C/a, and the other root (Vieta).
        const int cancelling = CGAL::sign(b_prime) > 0 ? 1 : 0;
        const double product = CGAL::to_double(C / a), other = roots[1 - cancelling].guess;
        if (other != 0 && std::isfinite(product / other)) roots[cancelling].guess = product / other;
    }
    for (int i = 0; i < 2; ++i) {
        algebraic_root& root = out.roots[i];
        root.sign = sign_of(roots[i].x.sign());
        root.rounded = round_in(prec, roots[i], root.sign);
        if (tmin) root.versus_tmin = versus(roots[i], *tmin);
        if (tmax) root.versus_tmax = versus(roots[i], *tmax);
    }

    // The nearest root in front, and its hit point (o_s + t_s·d_s)·2^s.
    if (out.roots[0].sign > 0) out.nearest_in_front = 0;
    else if (out.roots[1].sign > 0) out.nearest_in_front = 1;
    if (!out.nearest_in_front) return out;
    const root_of_2& t = roots[*out.nearest_in_front].x;
    double hit[3];
    for (int axis = 0; axis < 3; ++axis) {
        const exact_value coordinate = with_interval_guess(t * d[axis] + o[axis], s);
        hit[axis] = round_in(prec, coordinate, sign_of(coordinate.x.sign()));
    }
    out.hit_point = {hit[0], hit[1], hit[2]};
    return out;
}

}  // namespace rayverify
