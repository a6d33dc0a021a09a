// Double-word ("double-double") arithmetic, and values with a rigorous error
// bound: the building blocks of every filtered exact decision (the oracle's
// filter) and of the double-double estimates in stability. One place for them
// (as pbrt-v4's TwoSum/TwoProd in util/math.h); tests/double_word_test.cpp
// checks each against exact rational arithmetic on a million operands.
//
// Notation: u = 2^−53. A double-word x = xh + xl is a pair of doubles read as
// their exact sum.
//
// Error-free transformations (exact in the absence of overflow, and of
// underflow for two_prod; Knuth, Dekker, and with an FMA, Ogita–Rump–Oishi):
// two_sum(a, b) = (s, e) with s = RN(a + b), s + e = a + b; fast_two_sum the
// same when |a| ≥ |b| (or a = 0); two_prod(a, b) = (p, e) with p = RN(ab),
// p + e = ab.
//
// Double-word operations and their proven relative error bounds (Joldes,
// Muller, Popescu, "Tight and rigorous error bounds for basic building blocks
// of double-word arithmetic", ACM TOMS 44(2), 2017): AccurateDWPlusDW
// (Alg. 6) ≤ 3u²/(1 − 4u); DWTimesDW3 (Alg. 12) ≤ 4u² [Muller & Rideau,
// 2022, confirm it]; DWTimesFP3 (Alg. 9) ≤ 2u². These assume no underflow.
//
// `bounded`: a double-word v with a bound err such that the exact quantity X
// it stands for satisfies |X − (vh + vl)| ≤ err. The bound used for every
// double-word operation is op_error·|zh| = 16u²·|zh| = 2^−102·|zh|, at least
// four times the proven one (|exact| ≤ |zh|(1 + 2u)(1 + 4u²), so the factor 4
// covers reading the bound off the computed result). Propagation:
// |XY − xy| ≤ |x|·ey + |y|·ex + ex·ey and |(X + Y) − (x + y)| ≤ ex + ey. Every
// error bound is itself computed in double from non-negative terms (at most 7
// roundings, each a factor ≤ 1 + u), then passed through widen():
// × (1 + 2^−45) > (1 + u)^8, plus 2^−600 for any term that underflowed. The
// caller keeps operands in a range where nothing overflows and the products
// stay far from the underflow threshold (the oracle's filter: inputs 0 or in
// [2^−80, 2^80]); division and square root carry a posteriori bounds.
#pragma once

#include <cmath>
#include <cstdint>
#include <optional>

namespace rayverify {

struct dword {
    double h = 0, l = 0;
};

// ---- Two lanes -----------------------------------------------------------------
// Two doubles side by side (GCC's vector extension, which clang reads too), for
// one formula evaluated for two inputs at once: the static filter corrects the
// near and the far root together. Each lane's operations are the scalar code's,
// rounded alike, so a lane holds the bits the scalar code would compute;
// tests/float_primitives_test.cpp checks that for the transformations below.
typedef double double_pair __attribute__((vector_size(16)));
// Two 64-bit lanes of bits: a lane's bit pattern, or a comparison's result
// (all ones where it holds).
typedef std::int64_t double_pair_bits __attribute__((vector_size(16)));

struct dword_pair {
    double_pair h, l;
};

inline double_pair both_lanes(double x) { return double_pair{x, x}; }
inline double_pair fabs_lanes(double_pair x) {
    return (double_pair)((double_pair_bits)x & INT64_C(0x7fffffffffffffff));
}
inline double fused_multiply_add(double a, double b, double c) { return std::fma(a, b, c); }
// One correctly rounded fma per lane: without SLP vectorisation (CMakeLists.txt)
// GCC issues two scalar ones, a lane each.
inline double_pair fused_multiply_add(double_pair a, double_pair b, double_pair c) {
    return double_pair{std::fma(a[0], b[0], c[0]), std::fma(a[1], b[1], c[1])};
}
// Whether a comparison of two lanes holds in both.
template <class Mask>
inline bool in_both_lanes(Mask holds) {
    return holds[0] && holds[1];
}

// The transformations' bodies, for a double (Word = dword) or two lanes
// (Word = dword_pair): the same operations on each lane.
template <class Word, class T>
inline Word two_sum_of(T a, T b) {
    const T s = a + b;
    const T bb = s - a;
    return {s, (a - (s - bb)) + (b - bb)};
}
template <class Word, class T>
inline Word fast_two_sum_of(T a, T b) {
    const T s = a + b;
    return {s, b - (s - a)};
}
template <class Word, class T>
inline Word two_prod_of(T a, T b) {
    const T p = a * b;
    return {p, fused_multiply_add(a, b, -p)};
}

inline dword two_sum(double a, double b) { return two_sum_of<dword>(a, b); }
inline dword_pair two_sum(double_pair a, double_pair b) { return two_sum_of<dword_pair>(a, b); }

// Requires |a| ≥ |b| or a = 0 (in each lane).
inline dword fast_two_sum(double a, double b) { return fast_two_sum_of<dword>(a, b); }
inline dword_pair fast_two_sum(double_pair a, double_pair b) { return fast_two_sum_of<dword_pair>(a, b); }

inline dword two_prod(double a, double b) { return two_prod_of<dword>(a, b); }
inline dword_pair two_prod(double_pair a, double_pair b) { return two_prod_of<dword_pair>(a, b); }

// AccurateDWPlusDW.
inline dword dw_add(dword x, dword y) {
    const dword s = two_sum(x.h, y.h);
    const dword t = two_sum(x.l, y.l);
    const dword v = fast_two_sum(s.h, s.l + t.h);
    return fast_two_sum(v.h, t.l + v.l);
}

// DWTimesDW3.
inline dword dw_mul(dword x, dword y) {
    const dword c = two_prod(x.h, y.h);
    const double tl1 = std::fma(x.h, y.l, x.l * y.l);
    const double cl2 = std::fma(x.l, y.h, tl1);
    return fast_two_sum(c.h, c.l + cl2);
}

// DWTimesFP3.
inline dword dw_mul(dword x, double y) {
    const dword c = two_prod(x.h, y);
    return fast_two_sum(c.h, std::fma(x.l, y, c.l));
}

inline dword dw_negate(dword x) { return {-x.h, -x.l}; }
inline dword dw_sub(dword x, dword y) { return dw_add(x, dw_negate(y)); }

// x / y, one correction step (about 2^−104 relative; no proven bound: used
// only for estimates, the bounded quotient below carries its own bound).
inline dword dw_div(dword x, dword y) {
    const double q1 = x.h / y.h;
    const dword r = dw_sub(x, dw_mul(y, q1));
    return fast_two_sum(q1, r.h / y.h);
}

// √x for x ≥ 0, one Newton correction (about 2^−104 relative; an estimate,
// as dw_div).
inline dword dw_sqrt(dword x) {
    if (!(x.h > 0)) return {};
    const double s = std::sqrt(x.h);
    const dword r = dw_sub(x, two_prod(s, s));
    return fast_two_sum(s, r.h / (2 * s));
}

inline double dw_value(dword x) { return x.h + x.l; }

// Operators for estimates in double-word arithmetic (no bound carried).
inline dword operator+(dword x, dword y) { return dw_add(x, y); }
inline dword operator-(dword x) { return dw_negate(x); }
inline dword operator-(dword x, dword y) { return dw_sub(x, y); }
inline dword operator*(dword x, dword y) { return dw_mul(x, y); }
inline dword operator/(dword x, dword y) { return dw_div(x, y); }

// ---- Values with a rigorous error bound --------------------------------------

inline constexpr double op_error = 0x1p-102;  // 16u², per double-word operation, relative to |zh|

// The floor 2^−600 bounds whatever a bound's terms lost to underflow (< 2^−1022
// each); it is far above the subnormal range, so that multiplying a bound by a
// value of ordinary size never produces a subnormal (which costs a microcode
// assist per operation on x86), and far below any ordinary value's error.
inline double widen(double bound) { return bound * (1 + 0x1p-45) + 0x1p-600; }

struct bounded {
    dword v;
    double err = 0;
};

inline bounded exactly(double x) { return {{x, 0}, 0}; }
inline bounded exactly(dword x) { return {x, 0}; }
inline bounded operator-(bounded x) { return {dw_negate(x.v), x.err}; }

inline bounded operator+(bounded x, bounded y) {
    const dword z = dw_add(x.v, y.v);
    return {z, widen(x.err + y.err + op_error * std::fabs(z.h))};
}
inline bounded operator-(bounded x, bounded y) { return x + (-y); }

inline bounded operator*(bounded x, bounded y) {
    const dword z = dw_mul(x.v, y.v);
    // |x| ≤ |xh|(1 + u): the factor is inside widen's margin.
    return {z, widen(std::fabs(x.v.h) * y.err + std::fabs(y.v.h) * x.err + x.err * y.err +
                     op_error * std::fabs(z.h))};
}

inline bounded operator*(bounded x, double y) {
    const dword z = dw_mul(x.v, y);
    return {z, widen(std::fabs(y) * x.err + op_error * std::fabs(z.h))};
}

// Upper bound of |xh + xl| + err.
inline double magnitude_bound(const bounded& x) { return widen(std::fabs(x.v.h) + std::fabs(x.v.l) + x.err); }

// Is every real within err of xh + xl strictly greater than mh + ml?
// With (s, e) = two_sum(xh, −mh) the exact difference is s + e + xl − ml;
// T = RN(s + RN(RN(e + xl) − ml)) is within 2.01u·(|T| + |e| + |xl| + |ml|)
// of it, so T > 2err + 2^−48·(…) proves difference > err (the slack also
// absorbs the roundings of the test itself).
inline bool exceeds(double xh, double xl, double err, double mh, double ml = 0) {
    const dword s = two_sum(xh, -mh);
    const double t = s.h + ((s.l + xl) - ml);
    const double margin = 2 * err + 0x1p-48 * (std::fabs(t) + std::fabs(s.l) + std::fabs(xl) + std::fabs(ml));
    return t > margin + 0x1p-1000;
}

// sign(X) when the bound decides it (|xh| > 2·err: |xh + xl| ≥ |xh|(1 − u) > err), else 0.
inline int certain_sign(const bounded& x) {
    if (!(std::fabs(x.v.h) > 2 * x.err)) return 0;
    return x.v.h > 0 ? 1 : -1;
}

// √x for xh > 2·err (so X > 0); nullopt when the bound cannot be certified.
// The approximation s (one Newton step from √xh) need not be accurate for the
// bound to hold: with R ≥ |x − s²| computed rigorously, |√x − s| =
// |x − s²|/(√x + s) ≤ R/s, and for the exact X, |√X − √x| = |X − x|/(√X + √x)
// ≤ err/√x with √x ≥ s − R/s.
inline std::optional<bounded> square_root(const bounded& x) {
    const double s0 = std::sqrt(x.v.h);
    const dword square = two_prod(s0, s0);
    const dword s = fast_two_sum(s0, (((x.v.h - square.h) - square.l) + x.v.l) / (2 * s0));
    const bounded residual = exactly(x.v) - exactly(s) * exactly(s);
    const double R = magnitude_bound(residual);
    const double sh = s.h;
    if (!(sh > 0) || !(R < sh * sh * 0x1p-40)) return std::nullopt;
    const double root_lower = sh * (1 - 0x1p-39);  // ≤ s − R/s ≤ √x
    return bounded{s, widen(R / root_lower + x.err / root_lower)};
}

// x / y for |yh| > 4·y.err; nullopt otherwise. With q ≈ x/y (two Newton-free
// steps) and R ≥ |x − q·y| computed rigorously, |x/y − q| ≤ R/|y|; for the
// exact X, Y: |X/Y − x/y| ≤ (ex + |x/y|·ey)/(|y| − ey).
inline std::optional<bounded> quotient(const bounded& x, const bounded& y) {
    const double yh = y.v.h;
    if (!(std::fabs(yh) > 4 * y.err)) return std::nullopt;
    const double q0 = x.v.h / yh;
    const bounded first = exactly(x.v) - exactly(y.v) * q0;
    const dword q = fast_two_sum(q0, first.v.h / yh);
    const bounded residual = exactly(x.v) - exactly(y.v) * exactly(q);
    const double R = magnitude_bound(residual);
    const double y_lower = std::fabs(yh) * (1 - 0x1p-50);  // ≤ |y|
    const double rounding = R / y_lower;
    const double ratio = std::fabs(q.h) * (1 + 0x1p-50) + rounding;  // ≥ |x/y|
    const double denominator = (y_lower - y.err) * (1 - 0x1p-50);   // ≤ |y| − ey
    return bounded{q, widen(rounding + (x.err + ratio * y.err) / denominator)};
}

}  // namespace rayverify
