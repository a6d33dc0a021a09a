// robust_sphere — a ray–sphere intersector that is never wrong about the
// class of a case, and whose roots are correctly rounded.
//
// Header only, C++20 standard library only: copy this one file into an
// engine. rayverify installs it as <rayverify/robust_sphere.h>; its proofs are
// rayverify's audit, hunts and tests (docs/robust_sphere.md).
//
//   f = o − c,  a = d·d,  b′ = d·f,  C = f·f − r²
//   a t² + 2b′t + C = 0,  Δ′ = b′² − aC = a·r² − |d × f|²   (Lagrange's identity)
//   Δ′ < 0: miss;  Δ′ = 0: tangent, t = −b′/a;  Δ′ > 0: two roots
//   q = −(b′ + σ√Δ′), σ = sign(b′) (+1 for b′ = +0): roots q/a and C/q, never
//   a difference of nearly equal numbers (Numerical Recipes §5.6)
//   root signs from the exact signs of C (the roots' product is C/a) and b′
//   (their sum is −2b′/a)
//
// Promises, for all finite inputs with d ≠ 0 (r is used through r² only):
// - The class (miss, tangent, two roots) is the exact one for the inputs as
//   given, and every returned root has the side of its exact root: t > 0
//   exactly when t* > 0, signbit(t) set exactly when t* < 0 (a positive root
//   too small for T is returned as +denorm_min, not +0, so that it stays in
//   front; a negative one rounds to −0 as usual).
// - A root is RN(t*), the exact root rounded to nearest-even in T, overflow
//   to ±inf included (so it is finite wherever RN(t*) is), except for the
//   +denorm_min rule above and the nearest hit in an open interval, which is
//   moved one ulp inside the interval when RN(t*) falls on its end: always
//   within 1 ulp of t*.
// - Whether a root lies in (tmin, tmax) — or [tmin, tmax], per end — is
//   decided exactly.
//
// How. A fast path evaluates the coefficients with certified error bounds —
// float inputs in double, double inputs in double-word arithmetic (pairs of
// doubles with error-free sums and products; Joldes, Muller and Popescu,
// "Tight and rigorous error bounds for basic building blocks of double-word
// arithmetic", ACM TOMS 2017) — and answers whenever the bounds settle the
// class, the signs, the interval and the rounding of each root it returns.
// Only when they cannot (Δ′ within its bound of 0: tangent or nearly; the
// origin on or within about 2^-48·|f| of the sphere; a root within its bound
// of a rounding boundary or of tmin/tmax; double inputs outside
// [2^-160, 2^160]) an exact path decides: a, b′, C and Δ′ (in Lagrange's
// form, degree 4) as floating-point expansions (Shewchuk, "Adaptive Precision
// Floating-Point Arithmetic and Fast Robust Geometric Predicates", 1997) of
// error-free sums and products, f kept exact as two_sum pairs, with an
// unbounded exponent so that nothing overflows or underflows; roots from
// those to relative 2^-90, and a root that close to a rounding boundary is
// compared with the boundary exactly.
//
// Requirements: IEEE 754 binary32/binary64 with round-to-nearest-even, no
// excess precision (FLT_EVAL_METHOD == 0), no -ffast-math. FMA contraction
// (-ffp-contract=fast) is harmless: with a hardware FMA (__FMA__,
// FP_FAST_FMA, __AVX2__) products are split with std::fma, otherwise with
// Dekker's split, whose exactness contraction could not break anyway because
// then no FMA exists to contract into. The exact path keeps up to 32
// expansion components in place and spills longer expansions to a
// std::vector (it allocates only then); it runs for a small share of cases
// (rayverify bench prints the share per family).
#pragma once

#include <bit>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <optional>
#include <type_traits>
#include <utility>
#include <vector>

static_assert(std::numeric_limits<float>::is_iec559 && std::numeric_limits<double>::is_iec559,
              "robust_sphere.h needs IEEE 754 binary32 and binary64");
static_assert(FLT_EVAL_METHOD == 0, "robust_sphere.h needs float and double evaluated in their own precision");
#if defined(__FAST_MATH__)
#error "robust_sphere.h cannot give its guarantees under -ffast-math"
#endif

// The fast path is meant to be inlined into the caller's loop. A build may
// define ROBUST_SPHERE_INLINE itself (as plain `inline`, say, where compile
// time matters more than speed); the answers do not depend on it.
#if defined(ROBUST_SPHERE_INLINE)
#elif defined(__GNUC__)
#define ROBUST_SPHERE_INLINE [[gnu::always_inline]] inline
#elif defined(_MSC_VER)
#define ROBUST_SPHERE_INLINE __forceinline
#else
#define ROBUST_SPHERE_INLINE inline
#endif

namespace robust_sphere {

template <class T>
struct vec3 {
    T x{}, y{}, z{};
};

// The ray o + t·d (any length of d other than 0) and the sphere |p − c| = r.
template <class T>
struct ray {
    vec3<T> origin;
    vec3<T> direction;
};

template <class T>
struct sphere {
    vec3<T> centre;
    T radius{};
};

// Whether an end of the interval (tmin, tmax) belongs to it.
enum class ends { open, closed };

// Which root of the line: the smaller or the larger t.
enum class root { near_root, far_root };

// Both roots of the line o + t·d, t of any sign. count 0: miss; 1: tangent
// (t0 = t1); 2: two distinct exact roots, t0 ≤ t1 (equal only when both
// round to the same value).
template <class T>
struct line_roots {
    int count = 0;
    T t0{}, t1{};
};

// The nearest root in an interval: found, its t, and which root it is (the
// far root when the origin is inside the sphere, or the near one is excluded).
template <class T>
struct ray_hit {
    bool found = false;
    T t{};
    root which = root::near_root;
};

// A hit point and a per-coordinate bound: some point q exactly on the sphere
// has |point.x − q.x| ≤ error.x, and so on. Offset a secondary ray's origin
// by (|n.x|·error.x + |n.y|·error.y + |n.z|·error.z)·n along the normal n
// to the side it leaves from (pbrt-v4, OffsetRayOrigin).
template <class T>
struct surface_point {
    vec3<T> point;
    vec3<T> error;
};

namespace detail {

template <class T>
inline constexpr bool supported = std::is_same_v<T, float> || std::is_same_v<T, double>;

// A decision the fast path may leave open (CGAL's Uncertain<Sign>): a sign
// or a class, or unknown. Plain values, not std::optional: an optional is
// written whole and read back in parts, which costs a store-forwarding stall
// per decision in an inlined loop.
struct uncertain {
    static constexpr int unknown = -128;
    int value = unknown;
    constexpr explicit operator bool() const { return value != unknown; }
    constexpr int operator*() const { return value; }
};

// A value the fast path may leave open: NaN, which no returned root is.
template <class T>
struct uncertain_value {
    T value = std::numeric_limits<T>::quiet_NaN();
    constexpr explicit operator bool() const { return value == value; }
    constexpr T operator*() const { return value; }
};

// ---------------------------------------------------------------------------
// Error-free transformations on double (Knuth's TwoSum, Dekker's FastTwoSum,
// split and TwoProduct).

struct dd {
    double hi = 0, lo = 0;
};

ROBUST_SPHERE_INLINE dd two_sum(double a, double b) {
    const double s = a + b;
    const double bb = s - a;
    return {s, (a - (s - bb)) + (b - bb)};
}

// Exact when a = 0 or exponent(a) ≥ exponent(b).
ROBUST_SPHERE_INLINE dd fast_two_sum(double a, double b) {
    const double s = a + b;
    return {s, b - (s - a)};
}

#if defined(__FMA__) || defined(FP_FAST_FMA) || defined(__AVX2__)
ROBUST_SPHERE_INLINE dd two_prod(double a, double b) {
    const double p = a * b;
    return {p, std::fma(a, b, -p)};
}
#else
// Veltkamp's split: hi has 26 significant bits, lo the rest; |a| < 2^996.
ROBUST_SPHERE_INLINE dd split(double a) {
    const double t = 134217729.0 * a;  // 2^27 + 1
    const double hi = t - (t - a);
    return {hi, a - hi};
}

ROBUST_SPHERE_INLINE dd two_prod(double a, double b) {
    const double p = a * b;
    const dd x = split(a), y = split(b);
    return {p, ((x.hi * y.hi - p) + x.hi * y.lo + x.lo * y.hi) + x.lo * y.lo};
}
#endif

ROBUST_SPHERE_INLINE dd negate(dd x) { return {-x.hi, -x.lo}; }

// ---------------------------------------------------------------------------
// Double-word arithmetic (Joldes, Muller, Popescu 2017). Relative error
// bounds, u = 2^-53: add 3u² (AccurateDWPlusDW), mul 7u² (DWTimesDW1),
// div 15u² + 56u³ (DWDivDW2), sqrt below 4u²; all under 2^-100, the bound the
// fast path's analysis uses per operation.

ROBUST_SPHERE_INLINE dd dw_add(dd x, dd y) {
    const dd s = two_sum(x.hi, y.hi);
    const dd t = two_sum(x.lo, y.lo);
    const dd v = fast_two_sum(s.hi, s.lo + t.hi);
    return fast_two_sum(v.hi, t.lo + v.lo);
}

ROBUST_SPHERE_INLINE dd dw_mul(dd x, dd y) {
    const dd c = two_prod(x.hi, y.hi);
    const double cl = c.lo + (x.hi * y.lo + x.lo * y.hi);
    return fast_two_sum(c.hi, cl);
}

// DWTimesFP1.
ROBUST_SPHERE_INLINE dd dw_mul(dd x, double y) {
    const dd c = two_prod(x.hi, y);
    const dd t = fast_two_sum(c.hi, x.lo * y);
    return fast_two_sum(t.hi, t.lo + c.lo);
}

ROBUST_SPHERE_INLINE dd dw_div(dd x, dd y) {
    const double th = x.hi / y.hi;
    const dd r = dw_mul(y, th);
    const dd pi = two_sum(x.hi, -r.hi);
    const double delta = pi.lo + (x.lo - r.lo);
    return fast_two_sum(th, (pi.hi + delta) / y.hi);
}

// One Newton step from √hi: √x ≈ s + (x − s²)/(2s), x − s² exact in its
// first two terms (s² is within an ulp of hi).
ROBUST_SPHERE_INLINE dd dw_sqrt(dd x) {
    const double s = std::sqrt(x.hi);
    const dd s2 = two_prod(s, s);
    const double r = ((x.hi - s2.hi) - s2.lo) + x.lo;
    return fast_two_sum(s, r / (2 * s));
}

// Σ p_i + extra as a double-word number: the high parts summed with exact
// two_sum errors, everything small in one double (Ogita, Rump, Oishi's Sum2).
// |result − exact| ≤ γ_(2N)·u·Σ|p_i| + rounding of extra's terms, at most
// 2N²·u²·Σ|p_i| when |extra| ≤ 2u·Σ|p_i|.
template <int N>
ROBUST_SPHERE_INLINE dd sum2(const dd (&p)[N], double extra) {
    double s = p[0].hi, c = p[0].lo + extra;
    for (int i = 1; i < N; ++i) {
        const dd t = two_sum(s, p[i].hi);
        s = t.hi;
        c += t.lo + p[i].lo;
    }
    return two_sum(s, c);
}

// ---------------------------------------------------------------------------
// Rounding a root t̃ with |t* − t̃| ≤ w to T, or nothing when some value within
// w of it rounds differently (then the exact path decides).

// RN to float of a double, overflow to ±inf spelled out (a conversion out of
// range is undefined behaviour in C++).
ROBUST_SPHERE_INLINE float round_to_float(double x) {
    constexpr double overflow = 0x1.ffffffp127;  // FLT_MAX + ½ulp: RN is ±inf from here on (ties to even)
    if (x >= overflow) return std::numeric_limits<float>::infinity();
    if (x <= -overflow) return -std::numeric_limits<float>::infinity();
    return static_cast<float>(x);
}

// t̃ = t.hi + t.lo, a normal double: RN(t*) when both ends of [t̃ − w, t̃ + w]
// round to the same double. The margin 2^-104·|t.hi| covers the rounding of
// the ends' offsets.
ROBUST_SPHERE_INLINE uncertain_value<double> certified_rounding(dd t, double w) {
    const double v = w * 1.0001 + 0x1p-104 * std::fabs(t.hi);
    const double low = t.hi + (t.lo - v), high = t.hi + (t.lo + v);
    if (low != high) return {};
    return {low};
}

// Float from a double t̃. The margin 2^-50·|t̃| covers the double rounding of
// the ends (a float rounding boundary within w of t* is then at least two
// double ulps inside the ends, so they round apart).
ROBUST_SPHERE_INLINE uncertain_value<float> certified_rounding(double t, double w) {
    const double v = w + 0x1p-50 * std::fabs(t);
    const float low = round_to_float(t - v), high = round_to_float(t + v);
    if (low != high) return {};
    return {low};
}

// ---------------------------------------------------------------------------
// The fast path. It leaves a decision open ("cannot decide") wherever its
// certified bounds do not settle the answer; detail::query_* then ask the
// exact solver, which always answers.
//
// Stage 1, for float and double inputs alike, in double arithmetic: a, b′,
// C and Δ′ (Lagrange's form) with bounds from the standard model
// |fl(x ∘ y) − x ∘ y| ≤ u|fl(x ∘ y)|, u = 2^-53, γ_n = nu/(1 − nu) (Higham,
// Accuracy and Stability of Numerical Algorithms, §3.1), each constant
// rounded up with room for the rounding of the bound itself. f = o − c is
// rounded once: |f̃ − f| ≤ u|f̃|. An overflow leaves an infinity or NaN in a
// value or its bound, and every comparison with it fails (undecided); an
// underflowing product is off by at most 2^-1075 more, which η = 2^-1000
// (times the factors such an error is multiplied by) covers. Float inputs
// never underflow or overflow here. This stage decides the class, the signs
// of C and b′, and for float the roots themselves (to 2^-30, then rounded
// to float with a certificate).
//
// Stage 2, double inputs only, when a root's value is asked or stage 1
// cannot decide: a, b′, C and Δ′ = b′² − aC again in double-word
// arithmetic, with f exact (two_sum), to 2^-93·a·M_C at worst; the roots to
// 2^-60; rounded with a certificate. Every nonzero input must lie in
// [2^-160, 2^160]: then no product overflows and no low part underflows (f
// is on the grid 2^-212, degree-4 terms are 0 or above 2^-848, roots above
// 2^-800), so every double-word operation keeps its relative bound.
template <class T>
class fast_solver {
public:
    ROBUST_SPHERE_INLINE fast_solver(const ray<T>& r, const sphere<T>& s) : ray_(r), sphere_(s) {
        const double dx = r.direction.x, dy = r.direction.y, dz = r.direction.z;
        const double fx = double(r.origin.x) - s.centre.x, fy = double(r.origin.y) - s.centre.y,
                     fz = double(r.origin.z) - s.centre.z;
        const double rr = double(s.radius) * s.radius;

        // a = d·d: |ã − a| ≤ γ_3·a (exact squares for float: γ_2).
        a_ = dx * dx + dy * dy + dz * dz;

        // b′ = d·f: |b̃′ − b′| ≤ (u + γ_3)·Σ|d_i f̃_i| ≤ 5u·M_b.
        const double px = dx * fx, py = dy * fy, pz = dz * fz;
        b_ = px + py + pz;
        eb_ = 5 * u * (std::fabs(px) + std::fabs(py) + std::fabs(pz)) + eta;

        // C = f·f − r²: f̃_i² is off by 2.01u·f̃_i², the dot product by γ_4: 7u·M_C.
        const double ff = fx * fx + fy * fy + fz * fz;
        C_ = ff - rr;
        MC_ = ff + rr;
        eC_ = 7 * u * MC_ + eta;

        d_[0] = dx, d_[1] = dy, d_[2] = dz, f_[0] = fx, f_[1] = fy, f_[2] = fz, rr_ = rr;
    }

    ROBUST_SPHERE_INLINE uncertain line_class() {
        delta();
        if (D_ > eD_) return {2};
        if (D_ < -eD_) return {0};
        if constexpr (std::is_same_v<T, double>) {  // closer to tangency: the double-word Δ′
            const words& w = words_D();
            if (!w.in_range) return {};
            if (w.D.hi > w.eD) return {2};
            if (w.D.hi < -w.eD) return {0};
        }
        return {};  // also NaN from invalid inputs
    }

    ROBUST_SPHERE_INLINE uncertain sign_C() {
        if (C_ > eC_) return {1};
        if (C_ < -eC_) return {-1};
        if constexpr (std::is_same_v<T, double>)
            if (words_bC().in_range) return sign_of(words_.C.hi, words_.eC);
        return {};
    }

    ROBUST_SPHERE_INLINE uncertain sign_b() {
        if (b_ > eb_) return {1};
        if (b_ < -eb_) return {-1};
        if constexpr (std::is_same_v<T, double>)
            if (words_bC().in_range) return sign_of(words_.b.hi, words_.eb);
        return {};
    }

    // RN(t*) of a root (requires line_class() == 2).
    ROBUST_SPHERE_INLINE uncertain_value<T> rounded(root which) {
        const estimate& e = root_estimate(which);
        if (!e.ok) return {};
        return certified_rounding(e.t, e.w);
    }

    // sign(t* − v) from the root's enclosure alone, when v lies clear of it
    // (a secondary ray's tmin beside a root next to the origin that is
    // known too loosely to be rounded).
    ROBUST_SPHERE_INLINE uncertain sign_against(root which, T v) {
        const estimate& e = root_estimate(which);
        if (!e.valid) return {};
        double t, lo = 0;
        if constexpr (std::is_same_v<T, double>)
            t = e.t.hi, lo = e.t.lo;
        else
            t = e.t;
        const double gap = (t - double(v)) + lo;  // two roundings: within 2u(|t| + |v|) + 2u|lo|
        const double margin = e.w * 1.0001 + 4 * u * (std::fabs(t) + std::fabs(double(v)));
        if (gap > margin) return {1};
        if (gap < -margin) return {-1};
        return {};
    }

    // sign(t* − c) for c = rounded(which).
    ROBUST_SPHERE_INLINE uncertain sign_after(root which, T c) {
        const estimate& e = root_estimate(which);
        double residual;  // t̃ − c, exact: c is t̃'s rounding (Sterbenz) or 0
        if constexpr (std::is_same_v<T, double>) {
            if (c != e.t.hi) return {};
            residual = e.t.lo;
        } else {
            residual = e.t - double(c);
        }
        if (std::fabs(residual) <= e.w * 1.0001 + 0x1p-104 * std::fabs(double(c))) return {};
        return {residual > 0 ? 1 : -1};
    }

private:
    // eta is far above the underflow errors it covers (2^-1075 each) and keeps
    // every bound a normal number: subnormal arithmetic is slow.
    static constexpr double u = 0x1p-53, eta = 0x1p-1000;
    using value = std::conditional_t<std::is_same_v<T, double>, dd, double>;

    ROBUST_SPHERE_INLINE static bool covered(double x) {
        const double m = std::fabs(x);
        return (m >= 0x1p-160 && m <= 0x1p160) || m == 0;
    }

    // Δ′ = a·r² − |d × f|², when first needed (a query may settle from the
    // signs of C and b′ alone). Its error grows like |f|/r, not like (|f|/r)²
    // as b′² − aC's does, so far spheres stay on the fast path.
    // X_i = d_j f_k − d_k f_j is off by 3.01u·m_i, m_i = |d_j f_k| + |d_k f_j|;
    // |X̃ − |x|²| ≤ 3.01u·X̃ + 6.02u·Σ m_i|X_i| + 9.1u²·Σ m_i², Σ m_i² ≤ 2a·M_C;
    // ã·r̃² is off by 5.02u·ã·r²; the difference adds u|Δ̃′|.
    ROBUST_SPHERE_INLINE void delta() {
        if (have_D_) return;
        have_D_ = true;
        const double dx = d_[0], dy = d_[1], dz = d_[2], fx = f_[0], fy = f_[1], fz = f_[2];
        const double u1 = dy * fz, u2 = dz * fy, v1 = dz * fx, v2 = dx * fz, w1 = dx * fy, w2 = dy * fx;
        const double X1 = u1 - u2, X2 = v1 - v2, X3 = w1 - w2;
        const double X = X1 * X1 + X2 * X2 + X3 * X3;
        const double Y = a_ * rr_;
        D_ = Y - X;
        const double S = (std::fabs(u1) + std::fabs(u2)) * std::fabs(X1) +
                         (std::fabs(v1) + std::fabs(v2)) * std::fabs(X2) +
                         (std::fabs(w1) + std::fabs(w2)) * std::fabs(X3);
        eD_ = u * (2 * std::fabs(D_) + 6 * Y + 4 * X + 7 * S) + 32 * u * u * a_ * MC_ +
              eta * (std::fabs(X1) + std::fabs(X2) + std::fabs(X3) + a_ + rr_ + 1);
    }

    ROBUST_SPHERE_INLINE static uncertain sign_of(double x, double bound) {
        if (x > bound) return {1};
        if (x < -bound) return {-1};
        return {};
    }

    // Stage 2 (double inputs): the coefficients in double-word arithmetic,
    // Sum2-style (Ogita, Rump, Oishi), u = 2^-53, each computed once and
    // only when needed. Each bound is at least 4× the derived one: a to
    // 2^-98·a (18u²), b′ to 2^-96·M_b (about 21u²), C to 2^-96·M_C (about
    // 35u²), Δ′ = b′² − aC to 2^-93·a·M_C (using M_b² ≤ a·M_C and 2^-100 per
    // double-word operation).
    struct words {
        dd a, b, C, D;
        double eb = 0, eC = 0, eD = 0, MC = 0;
        bool have_bC = false, have_a = false, have_D = false, in_range = false;
    };

    ROBUST_SPHERE_INLINE const words& words_bC() {
        if (words_.have_bC) return words_;
        words_.have_bC = true;
        const vec3<T>& o = ray_.origin;
        const vec3<T>& d = ray_.direction;
        const vec3<T>& c = sphere_.centre;
        words_.in_range = covered(o.x) & covered(o.y) & covered(o.z) & covered(d.x) & covered(d.y) & covered(d.z) &
                          covered(c.x) & covered(c.y) & covered(c.z) & covered(sphere_.radius);
        if (!words_.in_range) return words_;
        // f = o − c exactly: f_i = fh_i + fl_i, |fl_i| ≤ u|fh_i|.
        const dd fx = two_sum(o.x, -c.x), fy = two_sum(o.y, -c.y), fz = two_sum(o.z, -c.z);
        // b′ = d·fh + d·fl; the second part is below u·M_b, its rounding below u²·M_b.
        const dd products[3] = {two_prod(d.x, fx.hi), two_prod(d.y, fy.hi), two_prod(d.z, fz.hi)};
        words_.b = sum2(products, d.x * fx.lo + d.y * fy.lo + d.z * fz.lo);
        words_.eb = 0x1p-96 * (std::fabs(products[0].hi) + std::fabs(products[1].hi) + std::fabs(products[2].hi));
        // C = fh·fh + 2 fh·fl − r² (fl·fl ≤ u²·M_C left out).
        const dd r2 = two_prod(sphere_.radius, sphere_.radius);
        const dd terms[4] = {two_prod(fx.hi, fx.hi), two_prod(fy.hi, fy.hi), two_prod(fz.hi, fz.hi), negate(r2)};
        words_.C = sum2(terms, 2 * (fx.hi * fx.lo + fy.hi * fy.lo + fz.hi * fz.lo));
        words_.MC = terms[0].hi + terms[1].hi + terms[2].hi + r2.hi;
        words_.eC = 0x1p-96 * words_.MC;
        return words_;
    }

    ROBUST_SPHERE_INLINE const dd& words_a() {
        if (!words_.have_a) {
            words_.have_a = true;
            const vec3<T>& d = ray_.direction;
            const dd squares[3] = {two_prod(d.x, d.x), two_prod(d.y, d.y), two_prod(d.z, d.z)};
            words_.a = sum2(squares, 0.0);
        }
        return words_.a;
    }

    ROBUST_SPHERE_INLINE const words& words_D() {
        if (words_.have_D) return words_;
        words_.have_D = true;
        if (!words_bC().in_range) return words_;
        const dd a = words_a();
        words_.D = dw_add(dw_mul(words_.b, words_.b), negate(dw_mul(a, words_.C)));
        words_.eD = 0x1p-93 * a.hi * words_.MC;
        return words_;
    }

    struct estimate {
        bool done = false;
        bool valid = false;  // w bounds the error (relative bound below 2^-20: first order holds)
        bool ok = false;     // and is small enough to round t̃ with a certificate
        value t{};           // t̃
        double w = 0;        // |t* − t̃| ≤ w
    };

    // The roots q/a and C/q, q = −(b′ + σ√Δ′), from stage 1 (float) or stage 2
    // (double). With e_s ≥ |√Δ̃′ − √Δ′| + rounding = e_Δ/√Δ̃′ + rounding and
    // e_q = e_b + e_s + rounding ≥ |q̃ − q|, a quotient's relative error is
    // its operands' plus its rounding (first order, ×1.01 for the rest while
    // the sum stays below 2^-20).
    ROBUST_SPHERE_INLINE const estimate& root_estimate(root which) {
        if (!have_q_) {
            have_q_ = true;
            delta();
            if constexpr (std::is_same_v<T, double>) {
                const words& w = words_bC();
                q_known_ = w.in_range;
                if (!q_known_) return undecided_;
                sigma_ = std::signbit(w.b.hi) ? -1 : 1;
                // √Δ′ from stage 1 where its error is negligible beside |q| ≥ |b′|
                // (far spheres); else from the double-word Δ′ (stage 1's when that
                // one is not positive: then stage 1 certified Δ′ > 0).
                dd s{std::sqrt(D_), 0};
                double es = 1.01 * eD_ / s.hi + u * s.hi;
                if (!(es <= 0x1p-64 * (std::fabs(w.b.hi) + s.hi)) && words_D().D.hi > 0) {
                    s = dw_sqrt(w.D);
                    es = 1.01 * w.eD / s.hi + 0x1p-100 * s.hi;
                }
                q_ = negate(dw_add(w.b, sigma_ > 0 ? s : negate(s)));
                xq_ = (w.eb + es) / std::fabs(q_.hi) + 0x1p-100;
            } else {
                const double s = std::sqrt(D_);
                sigma_ = std::signbit(b_) ? -1 : 1;
                q_ = -(b_ + std::copysign(s, b_));
                // One division for 1/|q| and 1/s: r1 = 1/(s·|q|), each product adding a rounding.
                const double aq = std::fabs(q_);
                const double r1 = 1 / (s * aq);
                inv_q_ = s * r1;
                // e_q/|q| = e_b/|q| + 1.01·e_Δ/(s·|q|) + u·s/|q| + u, every term within 3u of its computed value.
                xq_ = (eb_ * inv_q_ + 1.01 * eD_ * r1 + u * s * inv_q_) * (1 + 8 * u) + u;
            }
        }
        if (!q_known_) return undecided_;
        // σ = +1: q/a is the near root; σ = −1: the far one.
        const bool q_over_a = (which == root::near_root) == (sigma_ > 0);
        estimate& e = cache_[q_over_a ? 0 : 1];
        if (e.done) return e;
        e.done = true;
        if constexpr (std::is_same_v<T, double>) {
            const words& w = words_;
            if (q_over_a) {
                e.t = dw_div(q_, words_a());
                e.w = 1.02 * (xq_ + 0x1p-98 + 0x1p-100) * std::fabs(e.t.hi);
            } else {
                e.t = dw_div(w.C, q_);
                e.w = 1.02 * (w.eC / std::fabs(w.C.hi) + xq_ + 0x1p-100) * std::fabs(e.t.hi);
            }
            e.valid = e.w <= 0x1p-20 * std::fabs(e.t.hi);
            e.ok = e.w <= 0x1p-60 * std::fabs(e.t.hi);
        } else {
            if (q_over_a) {
                // ã is off by γ_3·a ≤ 3.01u·a; the division adds u.
                e.t = q_ / a_;
                e.w = 1.01 * (xq_ + 4.1 * u) * std::fabs(e.t);
            } else {
                // C/q as C·(1/|q|) with q's sign: 1/|q| is off by 3.01u, the product adds u;
                // |t|·e_C/|C| = e_C/|q|.
                e.t = std::copysign(C_ * inv_q_, C_ * q_);
                e.w = 1.01 * (eC_ * inv_q_ * (1 + 4.1 * u) + (xq_ + 4.1 * u) * std::fabs(e.t));
            }
            e.valid = e.w <= 0x1p-20 * std::fabs(e.t);  // also false for NaN
            e.ok = e.w <= 0x1p-30 * std::fabs(e.t);
        }
        return e;
    }

    const ray<T>& ray_;
    const sphere<T>& sphere_;
    double d_[3], f_[3], rr_;
    double a_, b_, C_, MC_, eb_, eC_;
    bool have_D_ = false;
    double D_ = 0, eD_ = 0;
    words words_;
    bool have_q_ = false, q_known_ = true;
    int sigma_ = 1;
    value q_{};
    double xq_ = 0, inv_q_ = 0;
    estimate cache_[2]{};
    estimate undecided_{};  // ok = false
};

// ---------------------------------------------------------------------------
// The exact path: floating-point expansions (Shewchuk 1997) whose components
// carry their own exponent, so that no product or sum of the inputs can
// overflow or underflow. An xfloat m·2^e (m = 0 or ½ ≤ |m| < 1) behaves as a
// binary64 number with an unbounded exponent; two_sum and two_prod on it are
// error-free, which is all Shewchuk's algorithms need.

struct xfloat {
    double m = 0;
    int e = 0;
};

// 2^k for −1022 ≤ k ≤ 1023, exactly.
inline double power_of_two(int k) { return std::bit_cast<double>(static_cast<std::uint64_t>(k + 1023) << 52); }

inline xfloat to_xfloat(double v, int scale = 0) {
    const std::uint64_t bits = std::bit_cast<std::uint64_t>(v);
    const int biased = static_cast<int>((bits >> 52) & 0x7ff);
    if (biased != 0 && biased != 0x7ff)  // normal: set the exponent field to that of [½, 1)
        return {std::bit_cast<double>((bits & ~(std::uint64_t{0x7ff} << 52)) | (std::uint64_t{1022} << 52)),
                biased - 1022 + scale};
    int k = 0;
    const double m = std::frexp(v, &k);  // 0 or subnormal
    return m == 0 ? xfloat{} : xfloat{m, k + scale};
}

inline bool magnitude_less(const xfloat& a, const xfloat& b) {
    if (a.m == 0) return b.m != 0;
    if (b.m == 0) return false;
    if (a.e != b.e) return a.e < b.e;
    return std::fabs(a.m) < std::fabs(b.m);
}

struct xpair {
    xfloat hi, lo;  // hi = RN(x), lo = x − hi
};

inline xpair two_sum(xfloat a, xfloat b) {
    if (a.m == 0) return {b, {}};
    if (b.m == 0) return {a, {}};
    const bool a_big = a.e >= b.e;
    const xfloat& big = a_big ? a : b;
    const xfloat& small = a_big ? b : a;
    const int gap = big.e - small.e;
    // Below ½ulp(big): RN(big + small) = big, the error is small itself.
    if (gap > 1000) return {big, small};
    const dd s = two_sum(big.m, small.m * power_of_two(-gap));  // exact: the product is at least 2^-1001
    return {to_xfloat(s.hi, big.e), to_xfloat(s.lo, big.e)};
}

inline xpair two_prod(xfloat a, xfloat b) {
    if (a.m == 0 || b.m == 0) return {};
    const dd p = two_prod(a.m, b.m);
    return {to_xfloat(p.hi, a.e + b.e), to_xfloat(p.lo, a.e + b.e)};
}

// Nonoverlapping components in increasing magnitude, no zeros; empty is 0.
// Up to 32 components in place, more on the heap.
class expansion {
public:
    expansion() = default;
    expansion(std::initializer_list<xfloat> components) {
        for (const xfloat& x : components) push_back(x);
    }
    std::size_t size() const { return size_; }
    bool empty() const { return size_ == 0; }
    xfloat* begin() { return spill_.empty() ? local_ : spill_.data(); }
    xfloat* end() { return begin() + size_; }
    const xfloat* begin() const { return spill_.empty() ? local_ : spill_.data(); }
    const xfloat* end() const { return begin() + size_; }
    xfloat& operator[](std::size_t i) { return begin()[i]; }
    const xfloat& operator[](std::size_t i) const { return begin()[i]; }
    const xfloat& back() const { return begin()[size_ - 1]; }
    void push_back(xfloat x) {
        if (spill_.empty() && size_ < local) {
            local_[size_++] = x;
            return;
        }
        if (spill_.empty()) spill_.assign(local_, local_ + size_);
        spill_.push_back(x);
        ++size_;
    }
    // n zero components (compress fills them from the top).
    void resize(std::size_t n) {
        while (size_ < n) push_back({});
    }
    void truncate(std::size_t n) {
        size_ = n;
        if (!spill_.empty()) spill_.resize(n);
    }

private:
    static constexpr std::size_t local = 32;
    xfloat local_[local];
    std::vector<xfloat> spill_;  // all components, once there are more than `local`
    std::size_t size_ = 0;
};

inline int sign(const expansion& e) { return e.empty() ? 0 : (e.back().m > 0 ? 1 : -1); }

inline expansion negated(expansion e) {
    for (xfloat& x : e) x.m = -x.m;
    return e;
}

// e += b in place: GROW-EXPANSION with zero elimination (Shewchuk,
// Theorem 10); the output index never passes the input index.
inline void grow(expansion& e, xfloat b) {
    xfloat Q = b;
    std::size_t h = 0;
    for (std::size_t i = 0; i < e.size(); ++i) {
        const xpair s = two_sum(Q, e[i]);
        if (s.lo.m != 0) e[h++] = s.lo;
        Q = s.hi;
    }
    e.truncate(h);
    if (Q.m != 0) e.push_back(Q);
}

inline void add(expansion& e, const expansion& f) {
    for (const xfloat& x : f) grow(e, x);
}

// SCALE-EXPANSION with zero elimination (Theorem 19).
inline expansion scale(const expansion& e, xfloat b) {
    expansion h;
    if (e.empty() || b.m == 0) return h;
    xpair p = two_prod(e[0], b);
    if (p.lo.m != 0) h.push_back(p.lo);
    xfloat Q = p.hi;
    for (std::size_t i = 1; i < e.size(); ++i) {
        p = two_prod(e[i], b);
        const xpair s = two_sum(Q, p.lo);
        if (s.lo.m != 0) h.push_back(s.lo);
        const xpair t = two_sum(p.hi, s.hi);
        if (t.lo.m != 0) h.push_back(t.lo);
        Q = t.hi;
    }
    if (Q.m != 0) h.push_back(Q);
    return h;
}

// COMPRESS (Shewchuk §2.8): the same value in as few components as it takes,
// the largest within an ulp of the whole.
inline expansion compress(const expansion& e) {
    if (e.size() < 2) return e;
    expansion g;
    g.resize(e.size());
    std::size_t bottom = e.size() - 1;
    xfloat Q = e.back();
    for (std::size_t i = e.size() - 1; i-- > 0;) {
        const xpair s = two_sum(Q, e[i]);
        if (s.lo.m != 0) {
            g[bottom--] = s.hi;
            Q = s.lo;
        } else {
            Q = s.hi;
        }
    }
    g[bottom] = Q;
    expansion h;
    for (std::size_t i = bottom + 1; i < e.size(); ++i) {
        const xpair s = two_sum(g[i], Q);
        if (s.lo.m != 0) h.push_back(s.lo);
        Q = s.hi;
    }
    if (Q.m != 0) h.push_back(Q);
    return h;
}

inline expansion product(const expansion& e, const expansion& f) {
    expansion acc;
    for (const xfloat& x : f) {
        add(acc, scale(e, x));
        acc = compress(acc);
    }
    return acc;
}

inline expansion difference(expansion e, const expansion& f) {
    add(e, negated(f));
    return compress(e);
}

// The exact value a − b of two doubles (in xfloats: no overflow).
inline expansion exact_difference(double a, double b) {
    const xpair s = two_sum(to_xfloat(a), to_xfloat(-b));
    expansion e;
    if (s.lo.m != 0) e.push_back(s.lo);
    if (s.hi.m != 0) e.push_back(s.hi);
    return e;
}

inline expansion single(double a) { return a == 0 ? expansion{} : expansion{to_xfloat(a)}; }

// A double-word mantissa with an unbounded exponent: (m.hi + m.lo)·2^e,
// ½ ≤ |m.hi| < 1 or zero. Each operation below has relative error under
// 2^-100 (the double-word bounds; exponents never overflow).
struct xdd {
    dd m;
    int e = 0;
    bool zero() const { return m.hi == 0; }
};

inline xdd normalized(dd m, int e) {
    if (m.hi == 0) return {};
    int k = 0;
    const double hi = std::frexp(m.hi, &k);
    return {{hi, std::ldexp(m.lo, -k)}, e + k};
}

// The value of an expansion to relative 2^-100: its top three components
// after compression (each nonoverlapping component is below an ulp of the next).
inline xdd approximate(const expansion& x) {
    const expansion e = compress(x);
    if (e.empty()) return {};
    const int top = e.back().e;
    dd m{e.back().m, 0};
    for (std::size_t k = 1; k <= 2 && k < e.size(); ++k) {
        const xfloat& c = e[e.size() - 1 - k];
        m = dw_add(m, {std::ldexp(c.m, c.e - top), 0});
    }
    return normalized(m, top);
}

inline xdd x_negate(xdd x) { return {negate(x.m), x.e}; }
inline xdd x_mul(xdd x, xdd y) { return x.zero() || y.zero() ? xdd{} : normalized(dw_mul(x.m, y.m), x.e + y.e); }
inline xdd x_div(xdd x, xdd y) { return x.zero() ? xdd{} : normalized(dw_div(x.m, y.m), x.e - y.e); }

inline xdd x_sqrt(xdd x) {
    if (x.zero()) return {};
    const bool odd = (x.e & 1) != 0;  // make the exponent even: m·2 in [1, 2)
    const dd m = odd ? dd{x.m.hi * 2, x.m.lo * 2} : x.m;
    return normalized(dw_sqrt(m), (x.e - (odd ? 1 : 0)) / 2);
}

// x + y for x, y of the same sign (no cancellation).
inline xdd x_add_same_sign(xdd x, xdd y) {
    if (x.zero()) return y;
    if (y.zero()) return x;
    if (x.e < y.e) std::swap(x, y);
    const int gap = x.e - y.e;
    if (gap > 200) return x;  // y is below 2^-199·|x|
    return normalized(dw_add(x.m, {std::ldexp(y.m.hi, -gap), std::ldexp(y.m.lo, -gap)}), x.e);
}

// The exact solver: every sign from expansions, every root to relative 2^-90
// from their approximations, and the rounding of a root settled by comparing
// it exactly with the rounding boundaries when that bound leaves it open.
template <class T>
class exact_solver {
public:
    exact_solver(const ray<T>& ray_, const sphere<T>& s) {
        const double o[3] = {ray_.origin.x, ray_.origin.y, ray_.origin.z};
        const double d[3] = {ray_.direction.x, ray_.direction.y, ray_.direction.z};
        const double c[3] = {s.centre.x, s.centre.y, s.centre.z};
        const double r = s.radius;
        bool finite = std::isfinite(r);
        for (int i = 0; i < 3; ++i) finite = finite && std::isfinite(o[i]) && std::isfinite(d[i]) && std::isfinite(c[i]);
        valid_ = finite && (d[0] != 0 || d[1] != 0 || d[2] != 0);
        if (!valid_) return;

        // f = o − c as exact two_sum pairs.
        const expansion f[3] = {exact_difference(o[0], c[0]), exact_difference(o[1], c[1]),
                                exact_difference(o[2], c[2])};
        const xfloat dx[3] = {to_xfloat(d[0]), to_xfloat(d[1]), to_xfloat(d[2])};
        const expansion r2 = product(single(r), single(r));

        // a = d·d, b′ = d·f, C = f·f − r².
        expansion a, b, C;
        for (int i = 0; i < 3; ++i) {
            add(a, product(single(d[i]), single(d[i])));
            add(b, scale(f[i], dx[i]));
            add(C, product(f[i], f[i]));
        }
        a_ = compress(a);
        b_ = compress(b);
        C_ = difference(C, r2);

        // Δ′ = a·r² − |d × f|², degree 4, exact.
        expansion cross2;
        for (int i = 0; i < 3; ++i) {
            const int j = (i + 1) % 3, k = (i + 2) % 3;
            const expansion x = difference(scale(f[k], dx[j]), scale(f[j], dx[k]));
            add(cross2, product(x, x));
            cross2 = compress(cross2);
        }
        D_ = difference(product(a_, r2), cross2);
    }

    uncertain line_class() const {
        if (!valid_) return {0};
        const int s = sign(D_);
        return {s < 0 ? 0 : (s == 0 ? 1 : 2)};
    }
    uncertain sign_C() const { return {sign(C_)}; }
    uncertain sign_b() const { return {sign(b_)}; }

    uncertain_value<T> rounded(root which) {
        const xdd& t = root_estimate(which);
        if (t.zero()) return {T(0)};
        // Small margin where rounding to T is one rounding of the mantissa
        // (double, normal or overflowing result); 2^-50 where a second
        // rounding follows (float, or a subnormal double).
        const bool one_rounding = std::is_same_v<T, double> && t.e >= -1020;
        const double w = (rho + (one_rounding ? 0x1p-100 : 0x1p-50)) * std::fabs(t.m.hi);
        const T low = scaled(t.m.hi + (t.m.lo - w), t.e), high = scaled(t.m.hi + (t.m.lo + w), t.e);
        if (low == high) return {low};
        // Walk the candidates, comparing t* exactly with each midpoint.
        for (T c = low; c < high;) {
            const T next = std::nextafter(c, std::numeric_limits<T>::infinity());
            const int s = compare(which, midpoint(c, next));
            if (s < 0) return {c};
            if (s == 0) return {even(c) ? c : next};
            c = next;
        }
        return {high};
    }

    uncertain sign_against(root, T) const { return {}; }  // rounded() settles it

    uncertain sign_after(root which, T c) {
        if (std::isinf(c)) return {c > 0 ? -1 : 1};
        return {compare(which, single(double(c)))};
    }

private:
    static constexpr double rho = 0x1p-90;

    // RN_T(x·2^e) for x within 2^-50 of its double: one rounding to double
    // (exact in double's normal range), then to T.
    static T scaled(double x, int e) {
        const double v = std::ldexp(x, e < -4000 ? -4000 : (e > 4000 ? 4000 : e));
        if constexpr (std::is_same_v<T, float>)
            return round_to_float(v);
        else
            return v;
    }

    static bool even(T c) {
        using bits = std::conditional_t<std::is_same_v<T, float>, std::uint32_t, std::uint64_t>;
        return std::isinf(c) || (std::bit_cast<bits>(c) & 1u) == 0;
    }

    // (c + next)/2 exactly, next = the T after c; beside an infinity, the
    // overflow threshold ±(max + ½ulp(max)).
    static expansion midpoint(T c, T next) {
        const T max = std::numeric_limits<T>::max();
        const double ulp_max = double(max) - double(std::nextafter(max, T(0)));
        double base = c, gap = double(next) - double(c);  // one ulp, exact in double
        if (std::isinf(next)) gap = ulp_max;                                     // c = max
        if (std::isinf(c)) base = next, gap = -ulp_max;                          // next = −max
        expansion e{to_xfloat(gap, -1)};  // ½ulp, below base's last bit, exact even under denorm_min
        if (base != 0) e.push_back(to_xfloat(base));
        return e;
    }

    // sign(t* − v) for the root `which` and an exact value v: with
    // w = a·v + b′, t* − v = (σ√Δ′ − w)/a, σ = −1 for the near root, +1 far.
    int compare(root which, const expansion& v) const {
        expansion w = product(a_, v);
        add(w, b_);
        w = compress(w);
        const int sw = sign(w), sD = sign(D_);
        if (which == root::far_root) {
            if (sw <= 0) return (sD > 0 || sw < 0) ? 1 : 0;
            return sign(difference(D_, product(w, w)));
        }
        if (sw >= 0) return (sD > 0 || sw > 0) ? -1 : 0;
        return -sign(difference(D_, product(w, w)));
    }

    // The roots to relative 2^-90 (a handful of operations under 2^-100 each).
    const xdd& root_estimate(root which) {
        if (!have_roots_) {
            have_roots_ = true;
            const xdd a = approximate(a_), b = approximate(b_), C = approximate(C_), D = approximate(D_);
            if (sign(D_) == 0) {
                roots_[0] = roots_[1] = x_div(x_negate(b), a);
            } else {
                const int sigma = sign(b_) < 0 ? -1 : 1;
                const xdd s = x_sqrt(D);
                const xdd q = x_negate(x_add_same_sign(b, sigma > 0 ? s : x_negate(s)));
                const xdd A = x_div(q, a), B = x_div(C, q);
                roots_[0] = sigma > 0 ? A : B;
                roots_[1] = sigma > 0 ? B : A;
            }
        }
        return roots_[which == root::near_root ? 0 : 1];
    }

    bool valid_ = false;
    expansion a_, b_, C_, D_;
    bool have_roots_ = false;
    xdd roots_[2];
};

// ---------------------------------------------------------------------------
// The queries, written once over a solver: a fast_solver (any step may be
// left open, and the query gives up: it returns false) or an exact_solver
// (never leaves one open).

template <class S>
ROBUST_SPHERE_INLINE uncertain root_sign(S& s, root which) {
    // Product of the roots C/a, sum −2b′/a.
    const uncertain sc = s.sign_C();
    if (!sc) return {};
    if (*sc < 0) return {which == root::near_root ? -1 : 1};
    const uncertain sb = s.sign_b();
    if (!sb) return {};
    if (*sc > 0) return {-*sb};
    // C = 0: the roots are 0 and −2b′/a.
    if (*sb > 0) return {which == root::near_root ? -1 : 0};
    if (*sb < 0) return {which == root::near_root ? 0 : 1};
    return {0};
}

// sign(t* − v) for a T value v, exactly.
template <class T, class S>
ROBUST_SPHERE_INLINE uncertain compare(S& s, root which, T v) {
    if (std::isinf(v)) return {v > 0 ? -1 : 1};
    const uncertain sg = root_sign(s, which);
    if (!sg) return {};
    if (v == 0) return sg;
    if (*sg <= 0 && v > 0) return {-1};
    if (*sg >= 0 && v < 0) return {1};
    if (const uncertain clear = s.sign_against(which, v)) return clear;
    const uncertain_value<T> c = s.rounded(which);
    if (!c) return {};
    // v < RN(t*) means v ≤ the T below it, which t* exceeds; likewise above.
    if (v < *c) return {1};
    if (v > *c) return {-1};
    return s.sign_after(which, *c);
}

// The value returned for a root: RN(t*), but +denorm_min for a positive root
// that rounds to 0 (it stays in front) and −0 for a negative one.
template <class T, class S>
ROBUST_SPHERE_INLINE uncertain_value<T> returned(S& s, root which) {
    const uncertain_value<T> c = s.rounded(which);
    if (!c || *c != 0) return c;
    const uncertain sg = root_sign(s, which);
    if (!sg) return {};
    return {*sg == 0 ? T(0) : (*sg > 0 ? std::numeric_limits<T>::denorm_min() : -T(0))};
}

// The class: two roots whenever C < 0 (the origin inside: Δ′ = b′² − aC > 0),
// without computing Δ′.
template <class S>
ROBUST_SPHERE_INLINE uncertain line_class(S& s) {
    const uncertain sc = s.sign_C();
    if (sc && *sc < 0) return {2};
    return s.line_class();
}

// C > 0 and b′ > 0: any roots are both behind the origin (product C/a > 0,
// sum −2b′/a < 0), so an interval with tmin ≥ 0 holds none.
template <class T, class S>
ROBUST_SPHERE_INLINE bool behind(S& s, T tmin) {
    if (!(tmin >= 0)) return false;
    const uncertain sc = s.sign_C();
    if (!sc || *sc <= 0) return false;
    const uncertain sb = s.sign_b();
    return sb && *sb > 0;
}

template <class T, class S>
ROBUST_SPHERE_INLINE bool query_line(S& s, line_roots<T>& out) {
    const uncertain cls = line_class(s);
    if (!cls) return false;
    if (*cls == 0) {
        out = {};
        return true;
    }
    const uncertain_value<T> t0 = returned<T>(s, root::near_root);
    if (!t0) return false;
    if (*cls == 1) {
        out = {1, *t0, *t0};
        return true;
    }
    const uncertain_value<T> t1 = returned<T>(s, root::far_root);
    if (!t1) return false;
    out = {2, *t0, *t1};
    return true;
}

// Is root `which` in the interval? 0 or 1, or unknown.
template <ends Lower, ends Upper, class T, class S>
ROBUST_SPHERE_INLINE uncertain inside(S& s, root which, T tmin, T tmax) {
    const uncertain lower = compare(s, which, tmin);
    if (!lower) return {};
    if (*lower < 0 || (*lower == 0 && Lower == ends::open)) return {0};
    const uncertain upper = compare(s, which, tmax);
    if (!upper) return {};
    return {*upper < 0 || (*upper == 0 && Upper == ends::closed)};
}

template <ends Lower, ends Upper, class T, class S>
ROBUST_SPHERE_INLINE bool query_nearest(S& s, T tmin, T tmax, ray_hit<T>& out) {
    out = {};
    if (behind(s, tmin)) return true;
    const uncertain cls = line_class(s);
    if (!cls) return false;
    if (*cls == 0) return true;
    for (root which : {root::near_root, root::far_root}) {
        if (which == root::far_root && *cls == 1) break;
        const uncertain in = inside<Lower, Upper>(s, which, tmin, tmax);
        if (!in) return false;
        if (!*in) continue;
        const uncertain_value<T> found = returned<T>(s, which);
        if (!found) return false;
        // RN(t*) may fall on an open end: one ulp inside (within 1 ulp of t*).
        T t = *found;
        if (Lower == ends::open && t <= tmin) t = std::nextafter(tmin, tmax);
        if (Upper == ends::open && t >= tmax) t = std::nextafter(tmax, tmin);
        out = {true, t, which};
        return true;
    }
    return true;
}

template <ends Lower, ends Upper, class T, class S>
ROBUST_SPHERE_INLINE bool query_any(S& s, T tmin, T tmax, bool& out) {
    out = false;
    if (behind(s, tmin)) return true;
    const uncertain cls = line_class(s);
    if (!cls) return false;
    if (*cls == 0) return true;
    for (root which : {root::near_root, root::far_root}) {
        if (which == root::far_root && *cls == 1) break;
        const uncertain in = inside<Lower, Upper>(s, which, tmin, tmax);
        if (!in) return false;
        if (*in) {
            out = true;
            return true;
        }
    }
    return true;
}

// The exact path, out of line: it runs for few cases and is large.
template <class T>
[[gnu::noinline, gnu::cold]] line_roots<T> exact_line(const ray<T>& r, const sphere<T>& s) {
    exact_solver<T> e(r, s);
    line_roots<T> out;
    query_line<T>(e, out);
    return out;
}

template <ends Lower, ends Upper, class T>
[[gnu::noinline, gnu::cold]] ray_hit<T> exact_nearest(const ray<T>& r, const sphere<T>& s, T tmin, T tmax) {
    exact_solver<T> e(r, s);
    ray_hit<T> out;
    query_nearest<Lower, Upper>(e, tmin, tmax, out);
    return out;
}

template <ends Lower, ends Upper, class T>
[[gnu::noinline, gnu::cold]] bool exact_any(const ray<T>& r, const sphere<T>& s, T tmin, T tmax) {
    exact_solver<T> e(r, s);
    bool out = false;
    query_any<Lower, Upper>(e, tmin, tmax, out);
    return out;
}

// ulp above |x|: the largest distance from x to a real that rounds to it.
template <class T>
double ulp_above(T x) {
    const T m = std::fabs(x);
    const T next = std::nextafter(m, std::numeric_limits<T>::infinity());
    return std::isinf(next) ? double(m) - double(std::nextafter(m, T(0))) : double(next) - double(m);
}

// A bound in double, rounded up to T.
template <class T>
T rounded_up(double bound) {
    const double b = bound * (1 + 0x1p-40);
    if constexpr (std::is_same_v<T, float>) {
        const float f = round_to_float(b);
        return double(f) >= b ? f : std::nextafter(f, std::numeric_limits<float>::infinity());
    } else {
        return b;
    }
}

}  // namespace detail

// ---------------------------------------------------------------------------
// The queries. T is float or double; tmin ≤ tmax, either may be infinite.

// Both roots of the line (t of any sign): exact class, roots as promised above.
template <class T>
    requires detail::supported<T>
ROBUST_SPHERE_INLINE line_roots<T> intersect_line(const ray<T>& r, const sphere<T>& s) {
    detail::fast_solver<T> fast(r, s);
    line_roots<T> out;
    if (detail::query_line<T>(fast, out)) return out;
    return detail::exact_line(r, s);
}

// The nearest root t* with tmin < t* < tmax; an end given as ends::closed
// includes t* equal to it. Decided exactly.
template <ends Lower = ends::open, ends Upper = ends::open, class T>
    requires detail::supported<T>
ROBUST_SPHERE_INLINE ray_hit<T> nearest_hit(const ray<T>& r, const sphere<T>& s, std::type_identity_t<T> tmin,
                                            std::type_identity_t<T> tmax) {
    detail::fast_solver<T> fast(r, s);
    ray_hit<T> out;
    if (detail::query_nearest<Lower, Upper>(fast, tmin, tmax, out)) return out;
    return detail::exact_nearest<Lower, Upper>(r, s, tmin, tmax);
}

// Is there a root in the interval (a shadow ray)? Decided exactly.
template <ends Lower = ends::open, ends Upper = ends::open, class T>
    requires detail::supported<T>
ROBUST_SPHERE_INLINE bool any_hit(const ray<T>& r, const sphere<T>& s, std::type_identity_t<T> tmin,
                                  std::type_identity_t<T> tmax) {
    detail::fast_solver<T> fast(r, s);
    bool out = false;
    if (detail::query_any<Lower, Upper>(fast, tmin, tmax, out)) return out;
    return detail::exact_any<Lower, Upper>(r, s, tmin, tmax);
}

// The fast path alone: what it settles, and nullopt where the exact path
// would run. For measuring the fallback rate; the answers are the same.
template <class T>
    requires detail::supported<T>
std::optional<line_roots<T>> intersect_line_fast(const ray<T>& r, const sphere<T>& s) {
    detail::fast_solver<T> fast(r, s);
    line_roots<T> out;
    if (detail::query_line<T>(fast, out)) return out;
    return std::nullopt;
}

template <ends Lower = ends::open, ends Upper = ends::open, class T>
    requires detail::supported<T>
std::optional<ray_hit<T>> nearest_hit_fast(const ray<T>& r, const sphere<T>& s, std::type_identity_t<T> tmin,
                                           std::type_identity_t<T> tmax) {
    detail::fast_solver<T> fast(r, s);
    ray_hit<T> out;
    if (detail::query_nearest<Lower, Upper>(fast, tmin, tmax, out)) return out;
    return std::nullopt;
}

template <ends Lower = ends::open, ends Upper = ends::open, class T>
    requires detail::supported<T>
std::optional<bool> any_hit_fast(const ray<T>& r, const sphere<T>& s, std::type_identity_t<T> tmin,
                                 std::type_identity_t<T> tmax) {
    detail::fast_solver<T> fast(r, s);
    bool out = false;
    if (detail::query_any<Lower, Upper>(fast, tmin, tmax, out)) return out;
    return std::nullopt;
}

// The hit point o + t·d for a root t returned above (|t − t*| ≤ 1 ulp), and
// its error bound. Without reprojection the point is o + t·d rounded once
// (computed in double for float, double-word for double), and q is the exact
// hit point o + t*·d: error_i = |d_i|·ulp(t) + ½ulp(point_i) + ε. With
// reprojection the point is c + r·g/|g| for g = (o + t·d) − c, rounded once,
// and q is that expression evaluated exactly: error_i = ½ulp(point_i) + ε,
// smaller where |d_i|·ulp(t) dominates (grazing hits, hits far along the ray).
// For t = ±the largest finite T (a root past the range) the error is +inf.
template <class T>
    requires detail::supported<T>
surface_point<T> hit_point(const ray<T>& r, const sphere<T>& s, std::type_identity_t<T> t, bool reproject = false) {
    using detail::dd;
    const T o[3] = {r.origin.x, r.origin.y, r.origin.z};
    const T d[3] = {r.direction.x, r.direction.y, r.direction.z};
    const T c[3] = {s.centre.x, s.centre.y, s.centre.z};
    dd p[3];  // o + t·d to relative 2^-100 (double) or as rounded in double (float)
    double slack[3];  // a bound on |p_i − (o_i + t·d_i)| beyond p's own rounding to T
    for (int i = 0; i < 3; ++i) {
        if constexpr (std::is_same_v<T, float>) {
            p[i] = {double(o[i]) + double(t) * d[i], 0};  // t·d exact in double
            slack[i] = 0x1p-53 * std::fabs(p[i].hi);
        } else if (std::fabs(t) < 0x1p995 && std::fabs(d[i]) < 0x1p995) {
            const dd td = detail::two_prod(t, d[i]);
            const dd sum = detail::two_sum(o[i], td.hi);
            p[i] = detail::fast_two_sum(sum.hi, sum.lo + td.lo);
            slack[i] = 0x1p-100 * (std::fabs(o[i]) + std::fabs(td.hi)) + 0x1p-1060;
        } else {
            p[i] = {o[i] + t * d[i], 0};
            slack[i] = 0x1p-52 * (std::fabs(o[i]) + 2 * std::fabs(t * d[i]));
        }
    }
    // t = ±the largest finite value may stand for a root past the format's
    // range (nearest_hit answers so on an open interval when RN(t*) = ±inf):
    // |t − t*| has no bound there, and neither has the point's error.
    const bool unbounded = std::fabs(t) == std::numeric_limits<T>::max();
    const T no_bound = std::numeric_limits<T>::infinity();
    surface_point<T> out;
    T* point[3] = {&out.point.x, &out.point.y, &out.point.z};
    T* error[3] = {&out.error.x, &out.error.y, &out.error.z};
    const auto to_T = [](double v) {
        if constexpr (std::is_same_v<T, float>)
            return detail::round_to_float(v);
        else
            return v;
    };
    if (!reproject) {
        for (int i = 0; i < 3; ++i) {
            *point[i] = to_T(p[i].hi + p[i].lo);
            const double half_ulp = detail::ulp_above(*point[i]) / 2;
            *error[i] = unbounded ? no_bound
                                  : detail::rounded_up<T>(std::fabs(double(d[i])) * detail::ulp_above(t) + half_ulp +
                                                          slack[i]);
        }
        return out;
    }
    // Reprojection onto the sphere: g = p − c, point = c + (r/|g|)·g.
    dd g[3];
    for (int i = 0; i < 3; ++i) g[i] = detail::dw_add(p[i], {-double(c[i]), 0});
    const dd norm2 = detail::dw_add(detail::dw_add(detail::dw_mul(g[0], g[0]), detail::dw_mul(g[1], g[1])),
                                    detail::dw_mul(g[2], g[2]));
    // Inside [2^-400, 2^400] no double-word step overflows or loses its low part.
    const double r_abs = std::fabs(double(s.radius));
    bool scaled_well = r_abs >= 0x1p-400 && r_abs <= 0x1p400;
    for (int i = 0; i < 3; ++i)
        for (double v : {p[i].hi, double(c[i])}) scaled_well = scaled_well && (v == 0 || (std::fabs(v) >= 0x1p-400 && std::fabs(v) <= 0x1p400));
    if (!scaled_well) return hit_point(r, s, t, false);
    if (!(norm2.hi > 0)) return hit_point(r, s, t, false);
    const dd k = detail::dw_div({r_abs, 0}, detail::dw_sqrt(norm2));
    // Seven double-word operations of relative error under 2^-100 each, on
    // values no larger than r and |c_i|: 2^-95·(r + |c_i|) bounds them all.
    const double eps = 0x1p-95;
    for (int i = 0; i < 3; ++i) {
        const dd v = detail::dw_add(detail::dw_mul(k, g[i]), {double(c[i]), 0});
        *point[i] = to_T(v.hi + v.lo);
        *error[i] = unbounded ? no_bound
                              : detail::rounded_up<T>(detail::ulp_above(*point[i]) / 2 +
                                                      eps * (r_abs + std::fabs(double(c[i]))) + 0x1p-1060);
    }
    return out;
}

}  // namespace robust_sphere
