// The filter (filter.h).
#include "oracle/filter.h"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <type_traits>

#include "core/float_bits.h"
#include "core/fma_clones.h"

namespace rayverify::oracle_internal {
namespace {

// RN(x) in T when the whole enclosure lies strictly inside one rounding
// interval (ties and anything at a boundary are left to the exact route).
// The candidate y is the rounding of xh + xl; its rounding interval runs
// between the midpoints with its neighbours, or to ±(max + ulp(max)/2) at the
// overflow threshold. For float the midpoints are doubles; for double they are
// y ∓ gap/2, exact double-words (y subnormal is excluded: its half gap is not a
// double). `sign` is the known sign of x, for a result that rounds to zero.
template <class T>
std::optional<double> round_enclosure(const enclosure& x, uncertain_sign sign) {
    if (!known(x)) return std::nullopt;
    if (const std::optional<double> y = round_normalised<T>(x)) return y;
    if (!sign) return std::nullopt;
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
    if (y == 0) return *sign < 0 ? -0.0 : 0.0;
    return static_cast<double>(y);
}

// The exponent of ulp(x) in T, when the enclosure settles x's sign and
// binade (2^e ≤ |x| < 2^(e+1), checked on the whole enclosure; |x| = 2^e
// exactly is left to the exact route).
template <class T>
std::optional<int> ulp_exponent_of(const enclosure& x) {
    const uncertain_sign side = sign_of(x);
    if (!side) return std::nullopt;
    const int sign = *side;
    const double approx = x.hi + x.lo;
    const int e = binade_of(approx);
    const double lower = exact_power_of_two(e), upper = exact_power_of_two(e + 1);
    const bool in_binade = sign > 0 ? exceeds(x.hi, x.lo, x.err, lower) && exceeds(-x.hi, -x.lo, x.err, -upper)
                                    : exceeds(-x.hi, -x.lo, x.err, lower) && exceeds(x.hi, x.lo, x.err, -upper);
    if (!in_binade) return std::nullopt;
    return static_cast<int>(ulp_exponent_of_binade<T>(e));
}

// RN(|difference| / 2^ulp_exponent) when the bound settles it, else NaN: the
// difference's sign is certain and the whole scaled enclosure lies inside one
// rounding interval of a double (the contract of ulp_error: every digit right).
// Inlined into ulp_error_or_nan, the hot caller: a `bounded` passed by value
// goes through the stack, built with 8-byte stores and copied with a 16-byte
// load that waits for them.
[[gnu::always_inline]] inline double rounded_ratio(bounded difference, int ulp_exponent) {
    constexpr double undecided = std::numeric_limits<double>::quiet_NaN();
    const uncertain_sign position = sign_of(difference);
    if (!position) return undecided;
    if (*position < 0) difference = -difference;
    // Most ratios settle at once: scaled by 2^−k with one multiplication
    // (exact while the words stay normal), the ratio is h + l within e, and
    // when h + l ∓ e stays inside h's rounding interval (with a margin for
    // the roundings of l ∓ e) h is its rounding. That interval reaches
    // ulp(h)/2 above h and below it, or ulp(h)/4 below a power of two.
    if (ulp_exponent >= -1023 && ulp_exponent <= 1022) {
        const double scale = std::bit_cast<double>(static_cast<std::uint64_t>(1023 - ulp_exponent) << 52);
        const double h = difference.v.h * scale;
        if (h >= 0x1p-900 && h <= 0x1p1000) {
            const double l = difference.v.l * scale, e = std::max(difference.err * scale, 0x1p-1000);
            const std::uint64_t bits = std::bit_cast<std::uint64_t>(h);
            const double half_ulp = std::bit_cast<double>(bits & 0x7FF0000000000000ull) * 0x1p-53;
            const bool power_of_two = (bits & 0x000FFFFFFFFFFFFFull) == 0;
            const double below = power_of_two ? half_ulp / 2 : half_ulp, above = half_ulp;
            if (l + e < above * (1 - 0x1p-50) && l - e > -below * (1 - 0x1p-50)) return h;
            // A bound as wide as half an ulp cannot fit in a rounding interval.
            if (e >= half_ulp) return undecided;
        }
    }
    const int scaled_exponent = std::ilogb(difference.v.h) - ulp_exponent;
    if (scaled_exponent < -900 || scaled_exponent > 1000) return undecided;
    const enclosure ratio{std::ldexp(difference.v.h, -ulp_exponent), std::ldexp(difference.v.l, -ulp_exponent),
                          std::max(std::ldexp(difference.err, -ulp_exponent), 0x1p-1000)};
    return round_enclosure<double>(ratio, +1).value_or(undecided);
}

}  // namespace

double rounded_ulp_ratio_or_nan(bounded difference, int ulp_exponent) { return rounded_ratio(difference, ulp_exponent); }

std::optional<double> round_enclosure(precision p, const enclosure& x, uncertain_sign sign) {
    return with_precision(p, [&]<class T>(std::type_identity<T>) { return round_enclosure<T>(x, sign); });
}

std::optional<int> ulp_exponent_of(precision p, const enclosure& x) {
    return with_precision(p, [&]<class T>(std::type_identity<T>) { return ulp_exponent_of<T>(x); });
}

double ulp_error_or_nan(const enclosure& x, std::optional<int> ulp_exponent, double value) {
    if (!known(x) || (std::isfinite(value) && !ulp_exponent)) return std::numeric_limits<double>::quiet_NaN();
    if (!std::isfinite(value)) return std::numeric_limits<double>::infinity();
    return rounded_ratio(exactly(value) - bounded_of(x), *ulp_exponent);
}

std::optional<figure_bracket> ulp_error_bracket_from(const enclosure& x, std::optional<int> ulp_exponent,
                                                     double value) {
    if (!known(x) || !ulp_exponent || *ulp_exponent < -1023 || *ulp_exponent > 1022) return std::nullopt;
    const bounded difference = exactly(value) - bounded_of(x);
    // |difference| lies within err of |h + l|, and m = RN(|h + l|) within
    // 2^−53·m of that. Upper: (m + err) rounded, widened by 2^−50 (three
    // roundings, each under 2^−53). Lower: m·(1 − 2^−52) − err·(1 + 2^−52),
    // each product rounded to the safe side; their difference is exact when
    // the two are within a factor 2 (Sterbenz) and otherwise within 2^−53 of
    // itself, so the final (1 − 2^−52) keeps it below. Scaling by 2^−e is
    // exact while the result stays normal (checked).
    const double m = std::fabs(difference.v.h + difference.v.l);
    const double scale = std::bit_cast<double>(static_cast<std::uint64_t>(1023 - *ulp_exponent) << 52);
    const double upper = (m + difference.err) * (1 + 0x1p-50) * scale;
    if (!(upper <= 0x1p1000)) return std::nullopt;
    if (upper < 0x1p-900) return figure_bracket{0, 0x1p-900};
    const double lower = (m * (1 - 0x1p-52) - difference.err * (1 + 0x1p-52)) * (1 - 0x1p-52) * scale;
    return figure_bracket{lower < 0x1p-900 ? 0 : lower, upper};
}

std::optional<double> ulp_error_from(precision p, const enclosure& x, double value) {
    return ulp_error_from(x, known(x) ? ulp_exponent_of(p, x) : std::nullopt, value);
}

namespace {

// What the filter computed for one case.
struct filtered_quadratic {
    uncertain_sign discriminant_sign;  // empty: the next stage must classify
    enclosure roots[2];         // near, far; unknown when the root step failed
};

filtered_quadratic filter_quadratic(const ray_sphere<double>& g, const std::optional<bounded>& known_discriminant,
                                    bool unit_direction) {
    filtered_quadratic out;
    const double o[3] = {g.origin.x, g.origin.y, g.origin.z};
    const double d[3] = {g.direction.x, g.direction.y, g.direction.z};
    const double c[3] = {g.centre.x, g.centre.y, g.centre.z};
    if (!in_filter_range(g)) return out;

    // f = o − c exactly, as double-words (two_sum).
    bounded f[3];
    for (int axis = 0; axis < 3; ++axis) f[axis] = exactly(two_sum(o[axis], -c[axis]));

    // a = d·d, b′ = d·f, C = f·f − r², and Δ′ = a·r² − |d × f|² (Lagrange's
    // identity (d·d)(f·f) − (d·f)² = |d × f|² turns b′² − aC into a form
    // without the cancellation b′² − aC suffers for far spheres).
    const bounded r2 = exactly(two_prod(g.radius, g.radius));
    const bounded a = unit_direction ? exactly(1.0)
                                     : exactly(two_prod(d[0], d[0])) + exactly(two_prod(d[1], d[1])) +
                                           exactly(two_prod(d[2], d[2]));
    // Δ′: given, or with a taken to be 1 (unit_direction), where Lagrange's
    // identity does not hold, b′² − C, whose bound settles its sign less
    // often; else Lagrange's form. b′ and C are formed before Δ′ only where it
    // needs them: elsewhere after its sign, which a tangent or a miss stops at.
    std::optional<bounded> b_prime, C;
    const auto form_b_prime_and_C = [&] {
        b_prime = f[0] * d[0] + f[1] * d[1] + f[2] * d[2];
        C = f[0] * f[0] + f[1] * f[1] + f[2] * f[2] - r2;
    };
    const bounded discriminant = [&] {
        if (known_discriminant) return *known_discriminant;
        if (unit_direction) {
            form_b_prime_and_C();
            return *b_prime * *b_prime - *C;
        }
        const bounded cross[3] = {f[2] * d[1] - f[1] * d[2], f[0] * d[2] - f[2] * d[0], f[1] * d[0] - f[0] * d[1]};
        return a * r2 - (cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2]);
    }();

    // Class: the sign of Δ′ when its bound settles it.
    out.discriminant_sign = sign_of(discriminant);
    if (!out.discriminant_sign || *out.discriminant_sign < 0) return out;
    if (!b_prime) form_b_prime_and_C();

    // Roots without cancellation: q = −(b′ + σ√Δ′), σ the sign of b′'s
    // estimate (either choice is rigorous, this one keeps |q| ≥ √Δ′); the
    // roots are q/a and C/q. σ = +1: q/a is the near root; σ = −1: the far.
    const std::optional<bounded> root = square_root(discriminant);
    if (!root) return out;
    const bool positive_b = b_prime->v.h >= 0;
    const bounded q = positive_b ? -(*b_prime + *root) : *root - *b_prime;
    const std::optional<bounded> t_q = quotient(q, a), t_c = quotient(*C, q);
    if (!t_q || !t_c) return out;
    const bounded& near = positive_b ? *t_q : *t_c;
    const bounded& far = positive_b ? *t_c : *t_q;
    out.roots[0] = {near.v.h, near.v.l, near.err};
    out.roots[1] = {far.v.h, far.v.l, far.err};
    return out;
}

}  // namespace

enclosure hit_coordinate_enclosure(const ray_sphere<double>& g, const enclosure& t, int axis) {
    const double o = g.origin[axis], d = g.direction[axis];
    if (d == 0) return {o, 0, 0};
    if (!known(t)) return {};
    const bounded h = bounded{{t.hi, t.lo}, t.err} * d + exactly(o);
    return {h.v.h, h.v.l, h.err};
}

std::optional<double> round_hit_coordinate(precision prec, const ray_sphere<double>& g, const enclosure& t, int axis) {
    const enclosure h = hit_coordinate_enclosure(g, t, axis);
    // d's coordinate 0: the coordinate is o's, rounded (a −0 becomes +0, as RN(0) = +0).
    if (known(h) && h.err == 0 && h.lo == 0)
        return rounded_to(prec, h.hi) + 0.0;
    return round_enclosure(prec, h, sign_of(h));
}

RAYVERIFY_CLONED_FOR_FMA filtered_case
filter_case(const ray_sphere<double>& g, precision prec, const std::optional<bounded>& discriminant,
            bool unit_direction) {
    filtered_case out;
    const filtered_quadratic q = filter_quadratic(g, discriminant, unit_direction);
    out.discriminant_sign = q.discriminant_sign;
    if (!q.discriminant_sign || *q.discriminant_sign < 0) return out;
    for (int i = 0; i < 2; ++i) {
        out.roots[i] = q.roots[i];
        out.sign[i] = sign_of(q.roots[i]);
        out.rounded[i] = round_enclosure(prec, q.roots[i], out.sign[i]);
    }
    return out;
}

}  // namespace rayverify::oracle_internal
