// robust_sphere — a ray–sphere intersector that is never wrong about the
// class of a case, and whose roots are correctly rounded.
//
// Header only, C++17 (or later) standard library only (and not even that on a GPU's
// path): copy this one file into an engine, CPU or CUDA/HIP kernel. rayverify
// installs it as <rayverify/robust_sphere.h>; its proofs are rayverify's
// audit, hunts and tests (docs/robust_sphere.md).
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
// The bounded tier (roots::bounded: intersect_line<roots::bounded>,
// nearest_hit<…, roots::bounded>) keeps the first and last promise and
// relaxes the second for double: a root there is within
// bounded_relative_error (2^-44) of t* instead of correctly rounded, which
// spares the extra-precise refinement of every root; for float both tiers
// answer alike (correctly rounded).
//
// How. A static filter first: a, b′, C and Δ′ in plain double (float inputs
// are exact in double) with error bounds derived a priori from the inputs'
// magnitudes (Shewchuk's and CGAL's static filters), a cheap one
// (Δ′ = b′² − aC) and, where that is too loose (far spheres, near-tangent
// rays), Lagrange's form with a bound that grows like |f|/r only. It settles
// the class, the signs and, from q, q/a and C/q computed once in double, the
// interval decisions and the float roots (certified to 2^-31, then rounded
// to float with a certificate). Double roots are refined by one Newton step
// on a residual |f + t̃·d|² − r² evaluated with error-free transformations,
// else in double-word arithmetic (pairs of doubles; Joldes, Muller and
// Popescu, "Tight and rigorous error bounds for basic building blocks of
// double-word arithmetic", ACM TOMS 2017), each with a certified bound and
// returned only when that bound shows which way the root rounds. Only when
// no stage can decide (Δ′ within its bound of 0: tangent or nearly; the
// origin on or within about 2^-48·|f| of the sphere; a root within its bound
// of a rounding boundary or of tmin/tmax; double inputs outside
// [2^-160, 2^160]) an exact path decides: a, b′, C and Δ′ (in Lagrange's
// form, degree 4) as floating-point expansions (Shewchuk, "Adaptive
// Precision Floating-Point Arithmetic and Fast Robust Geometric Predicates",
// 1997) of error-free sums and products, f kept exact as two_sum pairs, with
// an unbounded exponent so that nothing overflows or underflows; roots from
// those to relative 2^-90, and a root that close to a rounding boundary is
// compared with the boundary exactly.
//
// Requirements: IEEE 754 binary32/binary64 with round-to-nearest-even, no
// excess precision (FLT_EVAL_METHOD == 0), no -ffast-math. FMA contraction
// (-ffp-contract=fast, nvcc's default -fmad=true) is harmless: every bound
// holds with fewer roundings, and with a hardware FMA (__FMA__, FP_FAST_FMA,
// __AVX2__, any CUDA or HIP device) products are split with fma, otherwise
// with Dekker's split, whose exactness contraction could not break anyway
// because then no FMA exists to contract into.
//
// GPUs. Under CUDA (nvcc or clang) and HIP every function is host and
// device: no heap, no exceptions, no std:: call on a kernel's path (the
// compiler's builtins, or CUDA's own math functions under nvcc). The exact
// path keeps its expansions in fixed arrays whose capacities follow from the
// operations that build them (Shewchuk's bounds: a sum of m and n components
// has at most m + n, a product at most 2mn); the largest is 408 components,
// about 30 KB of a thread's local memory in all, touched only by the few
// cases that reach it. The *_fast functions (std::optional, for measuring)
// are host only.
#pragma once

#include <cfloat>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <type_traits>

static_assert(std::numeric_limits<float>::is_iec559 && std::numeric_limits<double>::is_iec559,
              "robust_sphere.h needs IEEE 754 binary32 and binary64");
static_assert(FLT_EVAL_METHOD == 0, "robust_sphere.h needs float and double evaluated in their own precision");
#if defined(__FAST_MATH__)
#error "robust_sphere.h cannot give its guarantees under -ffast-math"
#endif

// Host and device under CUDA (nvcc: __CUDACC__; clang: __CUDA__) and HIP,
// spelled as each compiler spells it (clang's attributes need no SDK
// header), and nothing elsewhere.
#if defined(ROBUST_SPHERE_HD)
#elif (defined(__CUDACC__) || defined(__CUDA__) || defined(__HIP__)) && defined(__clang__)
#define ROBUST_SPHERE_HD __attribute__((host)) __attribute__((device))
#elif defined(__CUDACC__) || defined(__HIP__)
#define ROBUST_SPHERE_HD __host__ __device__
#else
#define ROBUST_SPHERE_HD
#endif

// nvcc's device pass: CUDA's own math functions (host and device) rather
// than the compiler builtins, which its front end does not lower on device.
#if defined(__CUDACC__) && !defined(__clang__)
#define ROBUST_SPHERE_NVCC 1
#endif

// The fast path is meant to be inlined into the caller's loop. A build may
// define ROBUST_SPHERE_INLINE itself (as plain `inline`, say, where compile
// time matters more than speed); the answers do not depend on it.
#if defined(ROBUST_SPHERE_INLINE)
#elif defined(__GNUC__) || defined(__clang__)
#define ROBUST_SPHERE_INLINE [[gnu::always_inline]] inline
#elif defined(_MSC_VER)
#define ROBUST_SPHERE_INLINE __forceinline
#else
#define ROBUST_SPHERE_INLINE inline
#endif

// The exact path runs for few cases and is large: out of line.
#if defined(__GNUC__) || defined(__clang__)
#define ROBUST_SPHERE_COLD __attribute__((noinline, cold))
#else
#define ROBUST_SPHERE_COLD
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

// How a returned root relates to the exact one: correctly rounded (RN(t*),
// the promise above), or within bounded_relative_error of it (the bounded
// tier: the same exact class, sides and interval decisions; for float both
// are correctly rounded).
enum class roots { correctly_rounded, bounded };

// The bounded tier's promise for double: |t − t*| ≤ 2^-44·|t*|.
inline constexpr double bounded_relative_error = 0x1p-44;

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

// The segment from p0 to p1: the points p0 + f·(p1 − p0), f ∈ [0, 1] the
// fraction of the way (a physics engine's cast). p1 − p0 is taken exactly,
// never rounded: the answer is the segment's, not that of a ray through a
// rounded p1 − p0.
template <class T>
struct segment {
    vec3<T> p0, p1;
};

// What a segment that starts strictly inside the sphere hits: a contact at
// its start (f = 0, the initial overlap physics engines report), or the
// exit (the far root, as a renderer's interval query answers).
enum class start_inside { contact, exit };

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

// T as a parameter that takes no part in deducing T (std::type_identity_t of
// C++20): a query's tmin and tmax follow the ray's type.
template <class T>
struct same_type {
    using type = T;
};
template <class T>
using same_t = typename same_type<T>::type;

// ---------------------------------------------------------------------------
// The few operations of <cmath> and <bit> the header needs, as every
// compiler in question lowers them to one instruction on a GPU as on a CPU
// (std:: has no device versions without the CUDA SDK's headers).

template <class To, class From>
ROBUST_SPHERE_HD constexpr To bits_of(const From& x) {
    return __builtin_bit_cast(To, x);
}

template <class T>
using bits_type = std::conditional_t<std::is_same_v<T, float>, std::uint32_t, std::uint64_t>;

template <class T>
ROBUST_SPHERE_HD constexpr T infinity() {
    if constexpr (std::is_same_v<T, float>)
        return __builtin_huge_valf();
    else
        return __builtin_huge_val();
}
template <class T>
ROBUST_SPHERE_HD constexpr T largest() {
    if constexpr (std::is_same_v<T, float>)
        return 0x1.fffffep127f;
    else
        return 0x1.fffffffffffffp1023;
}
template <class T>
ROBUST_SPHERE_HD constexpr T denorm_min() {
    if constexpr (std::is_same_v<T, float>)
        return 0x1p-149f;
    else
        return 0x1p-1074;
}
ROBUST_SPHERE_HD constexpr double quiet_nan() { return __builtin_nan(""); }

ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD double abs(double x) {
#if defined(ROBUST_SPHERE_NVCC)
    return ::fabs(x);
#else
    return __builtin_fabs(x);
#endif
}
ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD float abs(float x) {
#if defined(ROBUST_SPHERE_NVCC)
    return ::fabsf(x);
#else
    return __builtin_fabsf(x);
#endif
}
ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD double sqrt(double x) {
#if defined(ROBUST_SPHERE_NVCC)
    return ::sqrt(x);
#else
    return __builtin_sqrt(x);
#endif
}
ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD double fma(double a, double b, double c) {
#if defined(ROBUST_SPHERE_NVCC)
    return ::fma(a, b, c);
#else
    return __builtin_fma(a, b, c);
#endif
}
ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD double copysign(double x, double s) {
#if defined(ROBUST_SPHERE_NVCC)
    return ::copysign(x, s);
#else
    return __builtin_copysign(x, s);
#endif
}
template <class T>
ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD bool signbit(T x) {
    return (bits_of<bits_type<T>>(x) >> (sizeof(T) * 8 - 1)) != 0;
}
template <class T>
ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD bool isinf(T x) {
    return abs(x) == infinity<T>();
}
template <class T>
ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD bool isfinite(T x) {
    return abs(x) <= largest<T>();  // false for NaN
}

// nextafter(x, y): the T next to x in the direction of y.
template <class T>
ROBUST_SPHERE_HD T next_toward(T x, T y) {
    if (!(x == x) || !(y == y)) return x + y;
    if (x == y) return y;
    if (x == 0) return y > 0 ? denorm_min<T>() : -denorm_min<T>();
    bits_type<T> b = bits_of<bits_type<T>>(x);
    if ((x < y) == (x > 0))
        ++b;
    else
        --b;
    return bits_of<T>(b);
}

// 2^k for −1022 ≤ k ≤ 1023, exactly.
ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD double power_of_two(int k) {
    return bits_of<double>(static_cast<std::uint64_t>(k + 1023) << 52);
}

// x·2^k, rounded once (ldexp): scaled in steps that are exact until the last.
ROBUST_SPHERE_HD inline double scale_by(double x, int k) {
    while (k > 1000) x *= power_of_two(1000), k -= 1000;
    while (k < -1000) x *= power_of_two(-1000), k += 1000;
    if (k < -1022) return (x * power_of_two(k + 1000)) * power_of_two(-1000);
    return x * power_of_two(k);
}

// x = m·2^k with ½ ≤ |m| < 1 (frexp), for finite x; m = 0, k = 0 for 0.
ROBUST_SPHERE_HD inline double split_exponent(double x, int& k) {
    if (x == 0 || !isfinite(x)) {
        k = 0;
        return x;
    }
    int bias = 0;
    if (abs(x) < 0x1p-1022) x *= 0x1p64, bias = 64;  // subnormal: make it normal first
    const std::uint64_t bits = bits_of<std::uint64_t>(x);
    k = static_cast<int>((bits >> 52) & 0x7ff) - 1022 - bias;
    return bits_of<double>((bits & ~(std::uint64_t{0x7ff} << 52)) | (std::uint64_t{1022} << 52));
}

// A decision the fast path may leave open (CGAL's Uncertain<Sign>): a sign
// or a class, or unknown. Plain values, not std::optional: an optional is
// written whole and read back in parts, which costs a store-forwarding stall
// per decision in an inlined loop (and has no device version).
struct uncertain {
    static constexpr int unknown = -128;
    int value = unknown;
    ROBUST_SPHERE_HD constexpr explicit operator bool() const { return value != unknown; }
    ROBUST_SPHERE_HD constexpr int operator*() const { return value; }
};

// A value the fast path may leave open: NaN, which no returned root is.
template <class T>
struct uncertain_value {
    T value = T(quiet_nan());
    ROBUST_SPHERE_HD constexpr explicit operator bool() const { return value == value; }
    ROBUST_SPHERE_HD constexpr T operator*() const { return value; }
};

// ---------------------------------------------------------------------------
// Error-free transformations on double (Knuth's TwoSum, Dekker's FastTwoSum,
// split and TwoProduct).

struct dd {
    double hi, lo;
};

ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD dd two_sum(double a, double b) {
    const double s = a + b;
    const double bb = s - a;
    return {s, (a - (s - bb)) + (b - bb)};
}

// Exact when a = 0 or exponent(a) ≥ exponent(b).
ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD dd fast_two_sum(double a, double b) {
    const double s = a + b;
    return {s, b - (s - a)};
}

#if defined(__FMA__) || defined(FP_FAST_FMA) || defined(__AVX2__) || defined(__CUDA_ARCH__) || \
    defined(__HIP_DEVICE_COMPILE__)
#define ROBUST_SPHERE_HARDWARE_FMA 1
#endif

ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD dd split(double a) {
    // Veltkamp's split: hi has 26 significant bits, lo the rest; |a| < 2^996.
    const double t = 134217729.0 * a;  // 2^27 + 1
    const double hi = t - (t - a);
    return {hi, a - hi};
}

ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD dd two_prod(double a, double b) {
    const double p = a * b;
#if defined(ROBUST_SPHERE_HARDWARE_FMA)
    return {p, fma(a, b, -p)};
#else
    const dd x = split(a), y = split(b);
    return {p, ((x.hi * y.hi - p) + x.hi * y.lo + x.lo * y.hi) + x.lo * y.lo};
#endif
}

ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD dd negate(dd x) { return {-x.hi, -x.lo}; }

// ---------------------------------------------------------------------------
// Double-word arithmetic (Joldes, Muller, Popescu 2017). Relative error
// bounds, u = 2^-53: add 3u² (AccurateDWPlusDW), mul 7u² (DWTimesDW1),
// div 15u² + 56u³ (DWDivDW2), sqrt below 4u²; all under 2^-100, the bound the
// fast path's analysis uses per operation.

ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD dd dw_add(dd x, dd y) {
    const dd s = two_sum(x.hi, y.hi);
    const dd t = two_sum(x.lo, y.lo);
    const dd v = fast_two_sum(s.hi, s.lo + t.hi);
    return fast_two_sum(v.hi, t.lo + v.lo);
}

ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD dd dw_mul(dd x, dd y) {
    const dd c = two_prod(x.hi, y.hi);
    const double cl = c.lo + (x.hi * y.lo + x.lo * y.hi);
    return fast_two_sum(c.hi, cl);
}

// DWTimesFP1.
ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD dd dw_mul(dd x, double y) {
    const dd c = two_prod(x.hi, y);
    const dd t = fast_two_sum(c.hi, x.lo * y);
    return fast_two_sum(t.hi, t.lo + c.lo);
}

ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD dd dw_div(dd x, dd y) {
    const double th = x.hi / y.hi;
    const dd r = dw_mul(y, th);
    const dd pi = two_sum(x.hi, -r.hi);
    const double delta = pi.lo + (x.lo - r.lo);
    return fast_two_sum(th, (pi.hi + delta) / y.hi);
}

// One Newton step from √hi: √x ≈ s + (x − s²)/(2s), x − s² exact in its
// first two terms (s² is within an ulp of hi).
ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD dd dw_sqrt(dd x) {
    const double s = sqrt(x.hi);
    const dd s2 = two_prod(s, s);
    const double r = ((x.hi - s2.hi) - s2.lo) + x.lo;
    return fast_two_sum(s, r / (2 * s));
}

// Σ p_i + extra as a double-word number: the high parts summed with exact
// two_sum errors, everything small in one double (Ogita, Rump, Oishi's Sum2).
// |result − exact| ≤ γ_(2N)·u·Σ|p_i| + rounding of extra's terms, at most
// 2N²·u²·Σ|p_i| when |extra| ≤ 2u·Σ|p_i|.
template <int N>
ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD dd sum2(const dd (&p)[N], double extra) {
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
ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD float round_to_float(double x) {
    constexpr double overflow = 0x1.ffffffp127;  // FLT_MAX + ½ulp: RN is ±inf from here on (ties to even)
    if (x >= overflow) return infinity<float>();
    if (x <= -overflow) return -infinity<float>();
    return static_cast<float>(x);
}

// t̃ = t.hi + t.lo, a normal double: RN(t*) when both ends of [t̃ − w, t̃ + w]
// round to the same double. The margin 2^-104·|t.hi| covers the rounding of
// the ends' offsets.
ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD uncertain_value<double> certified_rounding(dd t, double w) {
    const double v = w * 1.0001 + 0x1p-104 * abs(t.hi);
    const double low = t.hi + (t.lo - v), high = t.hi + (t.lo + v);
    if (low != high) return {};
    return {low};
}

// Float from a double t̃. The margin 2^-50·|t̃| covers the double rounding of
// the ends (a float rounding boundary within w of t* is then at least two
// double ulps inside the ends, so they round apart).
ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD uncertain_value<float> certified_rounding(double t, double w) {
    const double v = w + 0x1p-50 * abs(t);
    const float low = round_to_float(t - v), high = round_to_float(t + v);
    if (low != high) return {};
    return {low};
}

// ---------------------------------------------------------------------------
// The fast path. It leaves a decision open ("cannot decide") wherever its
// certified bounds do not settle the answer; detail::query_* then ask the
// exact solver, which always answers.
//
// Stage 1, the static filter, for float and double inputs alike, in double
// arithmetic: a, b′, C and Δ′ with bounds from the standard model
// |fl(x ∘ y) − x ∘ y| ≤ u|fl(x ∘ y)|, u = 2^-53, γ_n = nu/(1 − nu) (Higham,
// Accuracy and Stability of Numerical Algorithms, §3.1), each constant
// rounded up with room for the rounding of the bound itself. f = o − c is
// rounded once: |f̃ − f| ≤ u|f̃|. An overflow leaves an infinity or NaN in a
// value or its bound, and every comparison with it fails (undecided); an
// underflowing product is off by at most 2^-1075 more, which η = 2^-1000
// (times the factors such an error is multiplied by) covers. Float inputs
// never underflow or overflow here. Δ′ comes first as b′² − aC (five
// operations, bound 2^-48·a·M_C), and only where that bound is too loose in
// Lagrange's form. This stage decides the class, the signs of C and b′,
// and, from q, q/a and C/q in double with their bounds, most interval
// decisions, the float roots (to 2^-30, then rounded to float with a
// certificate) and the bounded tier's double roots (to 2^-45).
//
// Stage 2, double inputs only, when a correctly rounded root is asked or
// stage 1 cannot decide: a, b′, C and Δ′ = b′² − aC again in double-word
// arithmetic, with f exact (two_sum), to 2^-93·a·M_C at worst; the roots to
// 2^-60; rounded with a certificate. Every nonzero input must lie in
// [2^-160, 2^160]: then no product overflows and no low part underflows (f
// is on the grid 2^-212, degree-4 terms are 0 or above 2^-848, roots above
// 2^-800), so every double-word operation keeps its relative bound.
// Refine = false: stage 1 alone, inlined into the caller, its state in
// registers; Refine = true (double): stage 2 as well, out of line
// (detail::refined_*), where stage 1 could not answer.
//
// Segment = true: the line p0 + t·(p1 − p0) of a segment, its direction d =
// p1 − p0 never rounded as a value of T. Stage 1 works on d̃ = RN(p1 − p0) in
// double, d̃_i = d_i(1 + δ_i), |δ_i| ≤ u_d = u, and its bounds carry u_d: ã
// is off by (3.01u + 2.01u_d)·a, each product d̃_i·f̃_i by u + u_d more than
// f̃'s rounding alone (e_b = (5u + u_d)·M_b), Δ′ = b′² − aC by (24.01u +
// 4.01u_d)·a·M_C ≤ 28.02u·a·M_C, inside the same 2^-48·a·M_C; Lagrange's
// form below. Stage 2 takes d exactly as two_sum's pair d_h + d_l, the
// same kind of pair as f = o − c (on the inputs' grid, so the range
// argument above holds for it as it does for f).
template <class T, bool Refine, bool Segment = false>
class fast_solver {
    static_assert(supported<T>, "robust_sphere.h answers in float or double");
    static constexpr bool words_allowed = Refine && std::is_same_v<T, double>;

public:
    ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD fast_solver(const ray<T>& r, const sphere<T>& s) : origin_(r.origin), sphere_(s) {
        static_assert(!Segment, "a ray: its direction as given");
        start(r.direction.x, r.direction.y, r.direction.z);
    }

    // The segment's line p0 + t·(p1 − p0) (finite end points).
    ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD fast_solver(const segment<T>& g, const sphere<T>& s) : origin_(g.p0), sphere_(s) {
        static_assert(Segment, "a segment: its direction p1 − p0 taken exactly");
        const dd dx = two_sum(double(g.p1.x), -double(g.p0.x)), dy = two_sum(double(g.p1.y), -double(g.p0.y)),
                 dz = two_sum(double(g.p1.z), -double(g.p0.z));
        if constexpr (words_allowed) end_ = &g.p1, dl_[0] = dx.lo, dl_[1] = dy.lo, dl_[2] = dz.lo;
        start(dx.hi, dy.hi, dz.hi);
    }

    ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD uncertain line_class() {
        if (D_ > eD_) return {2};
        if (D_ < -eD_) return {0};
        if (!lagrange_) {  // far spheres, near tangents: Δ′ in Lagrange's form
            lagrange();
            if (D_ > eD_) return {2};
            if (D_ < -eD_) return {0};
        }
        if constexpr (words_allowed) {  // closer to tangency: the double-word Δ′
            const words& w = words_D();
            if (!w.in_range) return {};
            if (w.D.hi > w.eD) return {2};
            if (w.D.hi < -w.eD) return {0};
        }
        return {};  // also NaN from invalid inputs
    }

    ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD uncertain sign_C() {
        if (C_ > eC_) return {1};
        if (C_ < -eC_) return {-1};
        if constexpr (words_allowed)
            if (words_bC().in_range) return sign_of(words_.C.hi, words_.eC);
        return {};
    }

    ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD uncertain sign_b() {
        if (b_ > eb_) return {1};
        if (b_ < -eb_) return {-1};
        if constexpr (words_allowed)
            if (words_bC().in_range) return sign_of(words_.b.hi, words_.eb);
        return {};
    }

    // RN(t*) of a root (requires line_class() == 2).
    ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD uncertain_value<T> rounded(root which) {
        if constexpr (std::is_same_v<T, float>) {
            const estimate1& e = stage1(which);
            if (!(e.w <= 0x1p-30 * abs(e.t))) return {};
            return certified_rounding(e.t, e.w);
        } else if constexpr (words_allowed) {
            const estimate2& e = stage2(which);
            if (!e.ok) return {};
            return certified_rounding(e.t, e.w);
        } else {
            return {};
        }
    }

    // The bounded tier's root (requires line_class() == 2): for double, t̃
    // itself when |t* − t̃| ≤ 2^-45·|t̃| (so within 2^-44·|t*|), else RN(t*)
    // from stage 2; for float RN(t*).
    ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD uncertain_value<T> bounded(root which) {
        if constexpr (std::is_same_v<T, float>) {
            return rounded(which);
        } else {
            const estimate1& e = stage1(which);
            if (e.w <= 0x1p-45 * abs(e.t) && abs(e.t) >= 0x1p-1000 && abs(e.t) <= 0x1p1000) return {e.t};
            return rounded(which);  // correctly rounded keeps the promise too
        }
    }

    // sign(t* − v) from the root's enclosure alone, when v lies clear of it
    // (a secondary ray's tmin beside a root next to the origin that is
    // known too loosely to be rounded).
    ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD uncertain sign_against(root which, T v) {
        const estimate1& e = stage1(which);
        if (e.valid) {
            const double gap = e.t - double(v);  // within u(|t̃| + |v|)
            const double margin = e.w * 1.0001 + 2 * u * (abs(e.t) + abs(double(v)));
            if (gap > margin) return {1};
            if (gap < -margin) return {-1};
        }
        if constexpr (words_allowed) {
            const estimate2& e2 = stage2(which);
            if (!e2.valid) return {};
            const double gap = (e2.t.hi - v) + e2.t.lo;  // two roundings: within 2u(|t| + |v|) + 2u|lo|
            const double margin = e2.w * 1.0001 + 4 * u * (abs(e2.t.hi) + abs(v));
            if (gap > margin) return {1};
            if (gap < -margin) return {-1};
        }
        return {};
    }

    // sign(t* − c) for c = rounded(which).
    ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD uncertain sign_after(root which, T c) {
        double residual = 0, w = 0;  // t̃ − c, exact: c is t̃'s rounding (Sterbenz) or 0
        if constexpr (words_allowed) {
            const estimate2& e = stage2(which);
            if (c != e.t.hi) return {};
            residual = e.t.lo, w = e.w;
        } else if constexpr (std::is_same_v<T, double>) {
            return {};  // c came from stage 2
        } else {
            const estimate1& e = stage1(which);
            residual = e.t - double(c), w = e.w;
        }
        if (abs(residual) <= w * 1.0001 + 0x1p-104 * abs(double(c))) return {};
        return {residual > 0 ? 1 : -1};
    }

    // What the static filter decides on, for a caller that shows it: a, b′ = d·f,
    // C and Δ′ as computed in double, Δ′'s error bound, and whether Δ′ is
    // Lagrange's form a·r² − |d × f|² (tried once b′² − aC could not decide).
    struct filter_values {
        double a, b_prime, C, discriminant, discriminant_bound;
        bool lagrange;
    };
    ROBUST_SPHERE_HD filter_values filter_state() const { return {a_, b_, C_, D_, eD_, lagrange_}; }

private:
    // eta is far above the underflow errors it covers (2^-1075 each) and keeps
    // every bound a normal number: subnormal arithmetic is slow.
    static constexpr double u = 0x1p-53, eta = 0x1p-1000;
    // The relative rounding of each component of the direction stage 1 works
    // on: none for a ray, u for a segment's RN(p1 − p0).
    static constexpr double ud = Segment ? u : 0;

    // Stage 1's coefficients for the direction d̃ (d̃ = d for a ray).
    ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD void start(double dx, double dy, double dz) {
        const vec3<T>& o = origin_;
        const sphere<T>& s = sphere_;
        const double fx = double(o.x) - s.centre.x, fy = double(o.y) - s.centre.y, fz = double(o.z) - s.centre.z;
        const double rr = double(s.radius) * s.radius;

        // a = d·d: |ã − a| ≤ γ_3·a (exact squares for float: γ_2).
        a_ = dx * dx + dy * dy + dz * dz;

        // b′ = d·f: |b̃′ − b′| ≤ (u + γ_3)·Σ|d_i f̃_i| ≤ 5u·M_b (a segment: (5u + u_d)·M_b).
        const double px = dx * fx, py = dy * fy, pz = dz * fz;
        b_ = px + py + pz;
        eb_ = (5 * u + ud) * (abs(px) + abs(py) + abs(pz)) + eta;

        // C = f·f − r²: f̃_i² is off by 2.01u·f̃_i², the dot product by γ_4: 7u·M_C.
        const double ff = fx * fx + fy * fy + fz * fz;
        C_ = ff - rr;
        MC_ = ff + rr;
        eC_ = 7 * u * MC_ + eta;

        // Δ′ = b′² − aC: b̃′² is off by 2|b′|·5u·M_b + u·b̃′² ≤ 11u·a·|f|² (M_b² ≤ a·|f|²),
        // ã·C̃ by a·7u·M_C + 3.01u·a|C| + u·a·M_C, the difference by u|Δ̃′| ≤ 2u·a·M_C:
        // 24.01u·a·M_C in all, 2^-48·a·M_C with room for the bound's own roundings.
        // Underflows in b̃′ and C̃ reach it through |b′| + a ≤ a + M_C.
        D_ = b_ * b_ - a_ * C_;
        eD_ = 0x1p-48 * a_ * MC_ + eta * (a_ + MC_ + 1);

        d_[0] = dx, d_[1] = dy, d_[2] = dz, f_[0] = fx, f_[1] = fy, f_[2] = fz, rr_ = rr;
        lagrange_ = have_q_ = have_q2_ = false;
        q2_known_ = true;
        sigma_ = sigma2_ = 1;
        q_ = xq_ = inv_q_ = xq2_ = 0;
        cache1_[0].done = cache1_[1].done = false;
        if constexpr (words_allowed) {
            words_.have_bC = words_.have_a = words_.have_D = false;
            cache2_[0].done = cache2_[1].done = false;
            undecided_.done = undecided_.valid = undecided_.ok = false;
            undecided_.t = {0, 0}, undecided_.w = 0;
        }
    }

    ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD static bool covered(double x) {
        const double m = abs(x);
        return (m >= 0x1p-160 && m <= 0x1p160) || m == 0;
    }

    // Δ′ = a·r² − |d × f|², where b′² − aC cannot decide. Its error grows like
    // |f|/r, not like (|f|/r)² as b′² − aC's does, so far spheres stay on the
    // fast path.
    // X_i = d_j f_k − d_k f_j is off by 3.01u·m_i, m_i = |d_j f_k| + |d_k f_j|;
    // |X̃ − |x|²| ≤ 3.01u·X̃ + 6.02u·Σ m_i|X_i| + 9.1u²·Σ m_i², Σ m_i² ≤ 2a·M_C;
    // ã·r̃² is off by 5.02u·ã·r²; the difference adds u|Δ̃′|. A segment's
    // rounded d̃ adds u_d·m_i to X_i's error (so 2.02u_d·Σ m_i|X_i| and a
    // square term under 32(u + u_d)²·a·M_C) and 2.01u_d·ã·r² to ã·r̃²'s.
    ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD void lagrange() {
        lagrange_ = true;
        const double dx = d_[0], dy = d_[1], dz = d_[2], fx = f_[0], fy = f_[1], fz = f_[2];
        const double u1 = dy * fz, u2 = dz * fy, v1 = dz * fx, v2 = dx * fz, w1 = dx * fy, w2 = dy * fx;
        const double X1 = u1 - u2, X2 = v1 - v2, X3 = w1 - w2;
        const double X = X1 * X1 + X2 * X2 + X3 * X3;
        const double Y = a_ * rr_;
        const double D = Y - X;
        const double S = (abs(u1) + abs(u2)) * abs(X1) + (abs(v1) + abs(v2)) * abs(X2) + (abs(w1) + abs(w2)) * abs(X3);
        const double eD = u * (2 * abs(D) + 4 * X) + (6 * u + 2.1 * ud) * Y + (7 * u + 2.1 * ud) * S +
                          32 * (u + ud) * (u + ud) * a_ * MC_ + eta * (abs(X1) + abs(X2) + abs(X3) + a_ + rr_ + 1);
        if (!(eD >= eD_)) {  // the tighter bound wins (NaN keeps the first)
            D_ = D, eD_ = eD;
            have_q_ = false;
            cache1_[0].done = cache1_[1].done = false;
        }
    }

    ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD static uncertain sign_of(double x, double bound) {
        if (x > bound) return {1};
        if (x < -bound) return {-1};
        return {};
    }

    // Stage 1's roots q/a and C/q, q = −(b′ + σ√Δ′) (requires Δ̃′ > e_Δ). With
    // e_s ≥ |√Δ̃′ − √Δ′| + rounding = e_Δ/√Δ̃′ + rounding and
    // e_q = e_b + e_s + rounding ≥ |q̃ − q|, a quotient's relative error is
    // its operands' plus its rounding (first order, ×1.01 for the rest while
    // the sum stays below 2^-20).
    // The fast solver's state has no default member initializers: the
    // constructor sets the flags, and every value is written before it is
    // read (LLVM 14's NVPTX back end cannot lower the block zeroing they
    // would become in a thread's local memory).
    struct estimate1 {
        bool done;
        bool valid;  // w bounds the error (relative bound below 2^-20: first order holds)
        double t;    // t̃
        double w;    // |t* − t̃| ≤ w
    };

    ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD void form_q() {
        have_q_ = true;
        const double s = sqrt(D_);
        sigma_ = signbit(b_) ? -1 : 1;
        q_ = -(b_ + copysign(s, b_));
        // One division for 1/|q| and 1/s: r1 = 1/(s·|q|), each product adding a
        // rounding; two where s·|q| leaves the normal range (it would overflow to
        // inf, making 1/|q| zero and every bound below zero, or lose bits below it).
        const double aq = abs(q_);
        const double sq = s * aq;
        double r1;
        if (sq >= 0x1p-1000 && sq <= 0x1p1000) {
            r1 = 1 / sq;
            inv_q_ = s * r1;
        } else {
            inv_q_ = 1 / aq;
            r1 = inv_q_ / s;
        }
        // e_q/|q| = e_b/|q| + 1.01·e_Δ/(s·|q|) + u·s/|q| + u, every term within 3u of its computed value.
        xq_ = (eb_ * inv_q_ + 1.01 * eD_ * r1 + u * s * inv_q_) * (1 + 8 * u) + u;
    }

    ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD void form_root(bool q_over_a, estimate1& e) {
        e.done = true;
        if (q_over_a) {
            // ã is off by γ_3·a ≤ 3.01u·a (a segment: 2.01u_d·a more); the division adds u.
            e.t = q_ / a_;
            e.w = 1.01 * (xq_ + 4.1 * u + 2.1 * ud) * abs(e.t);
        } else {
            // C/q as C·(1/|q|) with q's sign: 1/|q| is off by 3.01u, the product adds u;
            // |t|·e_C/|C| = e_C/|q|.
            e.t = copysign(C_ * inv_q_, C_ * q_);
            e.w = 1.01 * (eC_ * inv_q_ * (1 + 4.1 * u) + (xq_ + 4.1 * u) * abs(e.t));
        }
        e.valid = e.w <= 0x1p-20 * abs(e.t);  // also false for NaN
    }

    // The estimate of a root: from the Δ′ at hand, and once more from
    // Lagrange's form when that one's bound is too loose for the precision asked.
    ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD const estimate1& stage1(root which) {
        constexpr double wanted = std::is_same_v<T, float> ? 0x1p-30 : 0x1p-45;
        if (!have_q_) {
            // √Δ′'s share of q's error is about e_Δ/(√Δ′·max(|b′|, √Δ′)): where
            // b′² − aC's bound makes it too large for the precision asked, Lagrange's form first.
            if (!lagrange_ && eD_ * eD_ > (wanted * wanted / 64) * D_ * (b_ * b_ > D_ ? b_ * b_ : D_)) lagrange();
            if (!have_q_) form_q();
        }
        // σ = +1: q/a is the near root; σ = −1: the far one.
        const bool q_over_a = (which == root::near_root) == (sigma_ > 0);
        estimate1& e = cache1_[q_over_a ? 0 : 1];
        if (e.done) return e;
        form_root(q_over_a, e);
        if (!(e.w <= wanted * abs(e.t)) && !lagrange_) {
            lagrange();  // resets the estimates when its bound is tighter
            if (!have_q_) form_q();
            if (!e.done) form_root(q_over_a, e);
        }
        return e;
    }

    // Stage 2 (double inputs): the coefficients in double-word arithmetic,
    // Sum2-style (Ogita, Rump, Oishi), u = 2^-53, each computed once and
    // only when needed. Each bound is at least 4× the derived one: a to
    // 2^-98·a (18u²), b′ to 2^-96·M_b (about 21u²), C to 2^-96·M_C (about
    // 35u²), Δ′ = b′² − aC to 2^-93·a·M_C (using M_b² ≤ a·M_C and 2^-100 per
    // double-word operation).
    struct words {
        dd a, b, C, D;
        double eb, eC, eD, MC;
        bool have_bC, have_a, have_D, in_range;
    };

    ROBUST_SPHERE_HD const words& words_bC() {
        if (words_.have_bC) return words_;
        words_.have_bC = true;
        const vec3<T>& o = origin_;
        const vec3<T>& c = sphere_.centre;
        // A ray's direction, or a segment's end point p1 (d_h = RN(p1 − p0) is
        // then at most 2^161 and on the inputs' grid, as f is).
        const vec3<T>& e = Segment ? *end_ : vec3<T>{T(d_[0]), T(d_[1]), T(d_[2])};
        words_.in_range = covered(o.x) && covered(o.y) && covered(o.z) && covered(e.x) && covered(e.y) &&
                          covered(e.z) && covered(c.x) && covered(c.y) && covered(c.z) && covered(sphere_.radius);
        if (!words_.in_range) return words_;
        // f = o − c exactly: f_i = fh_i + fl_i, |fl_i| ≤ u|fh_i|.
        const dd fx = two_sum(o.x, -c.x), fy = two_sum(o.y, -c.y), fz = two_sum(o.z, -c.z);
        // b′ = d·fh + d·fl (a segment: d_h·fh + (d_h·fl + d_l·fh), d_l·fl ≤ u²·M_b left
        // out); the second part is below u·M_b (2u·M_b), its rounding below u²·M_b (12u²·M_b).
        const dd products[3] = {two_prod(d_[0], fx.hi), two_prod(d_[1], fy.hi), two_prod(d_[2], fz.hi)};
        double second = d_[0] * fx.lo + d_[1] * fy.lo + d_[2] * fz.lo;
        if constexpr (Segment) second += dl_[0] * fx.hi + dl_[1] * fy.hi + dl_[2] * fz.hi;
        words_.b = sum2(products, second);
        words_.eb = 0x1p-96 * (abs(products[0].hi) + abs(products[1].hi) + abs(products[2].hi));
        // C = fh·fh + 2 fh·fl − r² (fl·fl ≤ u²·M_C left out).
        const dd r2 = two_prod(sphere_.radius, sphere_.radius);
        const dd terms[4] = {two_prod(fx.hi, fx.hi), two_prod(fy.hi, fy.hi), two_prod(fz.hi, fz.hi), negate(r2)};
        words_.C = sum2(terms, 2 * (fx.hi * fx.lo + fy.hi * fy.lo + fz.hi * fz.lo));
        words_.MC = terms[0].hi + terms[1].hi + terms[2].hi + r2.hi;
        words_.eC = 0x1p-96 * words_.MC;
        return words_;
    }

    ROBUST_SPHERE_HD const dd& words_a() {
        if (!words_.have_a) {
            words_.have_a = true;
            // A segment's a = Σ(d_h + d_l)² = Σd_h² + 2Σd_h·d_l, Σd_l² ≤ u²·a left out.
            const dd squares[3] = {two_prod(d_[0], d_[0]), two_prod(d_[1], d_[1]), two_prod(d_[2], d_[2])};
            double second = 0;
            if constexpr (Segment) second = 2 * (d_[0] * dl_[0] + d_[1] * dl_[1] + d_[2] * dl_[2]);
            words_.a = sum2(squares, second);
        }
        return words_.a;
    }

    ROBUST_SPHERE_HD const words& words_D() {
        if (words_.have_D) return words_;
        words_.have_D = true;
        if (!words_bC().in_range) return words_;
        const dd a = words_a();
        words_.D = dw_add(dw_mul(words_.b, words_.b), negate(dw_mul(a, words_.C)));
        words_.eD = 0x1p-93 * a.hi * words_.MC;
        return words_;
    }

    struct estimate2 {
        bool done;
        bool valid;  // w bounds the error (relative bound below 2^-20: first order holds)
        bool ok;     // and is small enough to round t̃ with a certificate
        dd t;        // t̃
        double w;    // |t* − t̃| ≤ w
    };

    // Stage 2's roots q/a and C/q in double-word arithmetic, with the bounds
    // of stage 1's (relative errors of the operands plus each rounding).
    ROBUST_SPHERE_HD const estimate2& stage2(root which) {
        if (!have_q2_) {
            have_q2_ = true;
            const words& w = words_bC();
            q2_known_ = w.in_range;
            if (!q2_known_) return undecided_;
            sigma2_ = signbit(w.b.hi) ? -1 : 1;
            // √Δ′ from stage 1 where its error is negligible beside |q| ≥ |b′|
            // (far spheres); else from the double-word Δ′ (stage 1's when that
            // one is not positive: then stage 1 certified Δ′ > 0).
            if (!lagrange_ && !(D_ > 0x1p20 * eD_)) lagrange();
            dd s{sqrt(D_), 0};
            double es = 1.01 * eD_ / s.hi + u * s.hi;
            if (!(es <= 0x1p-64 * (abs(w.b.hi) + s.hi)) && words_D().D.hi > 0) {
                s = dw_sqrt(w.D);
                es = 1.01 * w.eD / s.hi + 0x1p-100 * s.hi;
            }
            q2_ = negate(dw_add(w.b, sigma2_ > 0 ? s : negate(s)));
            xq2_ = (w.eb + es) / abs(q2_.hi) + 0x1p-100;
        }
        if (!q2_known_) return undecided_;
        const bool q_over_a = (which == root::near_root) == (sigma2_ > 0);
        estimate2& e = cache2_[q_over_a ? 0 : 1];
        if (e.done) return e;
        e.done = true;
        if (q_over_a) {
            e.t = dw_div(q2_, words_a());
            e.w = 1.02 * (xq2_ + 0x1p-98 + 0x1p-100) * abs(e.t.hi);
        } else {
            e.t = dw_div(words_.C, q2_);
            e.w = 1.02 * (words_.eC / abs(words_.C.hi) + xq2_ + 0x1p-100) * abs(e.t.hi);
        }
        e.valid = e.w <= 0x1p-20 * abs(e.t.hi);
        e.ok = e.w <= 0x1p-60 * abs(e.t.hi);
        return e;
    }

    const vec3<T>& origin_;
    const sphere<T>& sphere_;
    const vec3<T>* end_;  // a segment's p1 (stage 2)
    double dl_[3];        // a segment's p1 − p0 − d_ (stage 2)
    double d_[3], f_[3], rr_;
    double a_, b_, C_, MC_, eb_, eC_;
    double D_, eD_;
    bool lagrange_, have_q_, have_q2_, q2_known_;
    int sigma_, sigma2_;
    double q_, xq_, inv_q_;
    estimate1 cache1_[2];
    words words_;
    dd q2_;
    double xq2_;
    estimate2 cache2_[2];
    estimate2 undecided_;  // valid = ok = false
};

// ---------------------------------------------------------------------------
// The exact path: floating-point expansions (Shewchuk 1997) whose components
// carry their own exponent, so that no product or sum of the inputs can
// overflow or underflow. An xfloat m·2^e (m = 0 or ½ ≤ |m| < 1) behaves as a
// binary64 number with an unbounded exponent; two_sum and two_prod on it are
// error-free, which is all Shewchuk's algorithms need.

struct xfloat {
    double m;
    int e;
};

// to = from, field by field: LLVM 14's NVPTX back end cannot lower the block
// copy a struct assignment into a thread's local memory becomes.
ROBUST_SPHERE_HD inline void store(xfloat& to, const xfloat& from) {
    to.m = from.m;
    to.e = from.e;
}

ROBUST_SPHERE_HD inline xfloat to_xfloat(double v, int scale = 0) {
    const std::uint64_t bits = bits_of<std::uint64_t>(v);
    const int biased = static_cast<int>((bits >> 52) & 0x7ff);
    if (biased != 0 && biased != 0x7ff)  // normal: set the exponent field to that of [½, 1)
        return {bits_of<double>((bits & ~(std::uint64_t{0x7ff} << 52)) | (std::uint64_t{1022} << 52)),
                biased - 1022 + scale};
    int k = 0;
    const double m = split_exponent(v, k);  // 0 or subnormal
    return m == 0 ? xfloat{0, 0} : xfloat{m, k + scale};
}

struct xpair {
    xfloat hi, lo;  // hi = RN(x), lo = x − hi
};

ROBUST_SPHERE_HD inline xpair two_sum(xfloat a, xfloat b) {
    if (a.m == 0) return {b, {0, 0}};
    if (b.m == 0) return {a, {0, 0}};
    const bool a_big = a.e >= b.e;
    const xfloat& big = a_big ? a : b;
    const xfloat& small = a_big ? b : a;
    const int gap = big.e - small.e;
    // Below ½ulp(big): RN(big + small) = big, the error is small itself.
    if (gap > 1000) return {big, small};
    const dd s = two_sum(big.m, small.m * power_of_two(-gap));  // exact: the product is at least 2^-1001
    return {to_xfloat(s.hi, big.e), to_xfloat(s.lo, big.e)};
}

ROBUST_SPHERE_HD inline xpair two_prod(xfloat a, xfloat b) {
    if (a.m == 0 || b.m == 0) return {{0, 0}, {0, 0}};
    const dd p = two_prod(a.m, b.m);
    return {to_xfloat(p.hi, a.e + b.e), to_xfloat(p.lo, a.e + b.e)};
}

// Nonoverlapping components in increasing magnitude, no zeros; empty is 0.
// At most N components, a capacity each operation below derives from its
// operands' (Shewchuk's bounds: GROW-EXPANSION adds at most one component,
// SCALE-EXPANSION at most doubles them, COMPRESS never adds one), so that no
// operation can run out of room whatever the inputs.
template <int N>
struct expansion {
    static constexpr int capacity = N;
    xfloat c[N];
    int size = 0;

    ROBUST_SPHERE_HD bool empty() const { return size == 0; }
    ROBUST_SPHERE_HD const xfloat& back() const { return c[size - 1]; }
    ROBUST_SPHERE_HD void push_back(xfloat x) { store(c[size++], x); }
};

template <int N>
ROBUST_SPHERE_HD inline int sign(const expansion<N>& e) {
    return e.empty() ? 0 : (e.back().m > 0 ? 1 : -1);
}

// e += b in place: GROW-EXPANSION with zero elimination (Shewchuk,
// Theorem 10); the output index never passes the input index. Needs room
// for one more component.
template <int N>
ROBUST_SPHERE_HD inline void grow(expansion<N>& e, xfloat b) {
    xfloat Q = b;
    int h = 0;
    for (int i = 0; i < e.size; ++i) {
        const xpair s = two_sum(Q, e.c[i]);
        if (s.lo.m != 0) store(e.c[h++], s.lo);
        Q = s.hi;
    }
    e.size = h;
    if (Q.m != 0) e.push_back(Q);
}

// out = e, component by component (a GPU compiler may not lower a block
// copy of a large array in a thread's local memory).
template <int N, int M>
ROBUST_SPHERE_HD inline void assign(expansion<N>& out, const expansion<M>& e) {
    static_assert(M <= N, "the destination holds every component");
    for (int i = 0; i < e.size; ++i) store(out.c[i], e.c[i]);
    out.size = e.size;
}

// out = e + f, or e − f: M + N components at most.
template <int K, int M, int N>
ROBUST_SPHERE_HD inline void sum_into(expansion<K>& out, const expansion<M>& e, const expansion<N>& f,
                                      bool subtract = false) {
    static_assert(M + N <= K, "room for every component of the sum");
    assign(out, e);
    for (int i = 0; i < f.size; ++i) grow(out, subtract ? xfloat{-f.c[i].m, f.c[i].e} : f.c[i]);
}

template <int M, int N>
ROBUST_SPHERE_HD inline expansion<M + N> sum(const expansion<M>& e, const expansion<N>& f, bool subtract = false) {
    expansion<M + N> out;
    sum_into(out, e, f, subtract);
    return out;
}

// COMPRESS (Shewchuk §2.8): the same value in as few components as it takes,
// the largest within an ulp of the whole. In place.
template <int N>
ROBUST_SPHERE_HD inline void compress(expansion<N>& e) {
    if (e.size < 2) return;
    xfloat g[N];
    int bottom = e.size - 1;
    xfloat Q = e.back();
    for (int i = e.size - 1; i-- > 0;) {
        const xpair s = two_sum(Q, e.c[i]);
        if (s.lo.m != 0) {
            store(g[bottom--], s.hi);
            Q = s.lo;
        } else {
            Q = s.hi;
        }
    }
    store(g[bottom], Q);
    int h = 0;
    for (int i = bottom + 1; i < e.size; ++i) {
        const xpair s = two_sum(g[i], Q);
        if (s.lo.m != 0) store(e.c[h++], s.lo);
        Q = s.hi;
    }
    if (Q.m != 0) store(e.c[h++], Q);
    e.size = h;
}

// SCALE-EXPANSION with zero elimination (Theorem 19): 2N components at most.
template <int N>
ROBUST_SPHERE_HD inline expansion<2 * N> scale(const expansion<N>& e, xfloat b) {
    expansion<2 * N> h;
    if (e.empty() || b.m == 0) return h;
    xpair p = two_prod(e.c[0], b);
    if (p.lo.m != 0) h.push_back(p.lo);
    xfloat Q = p.hi;
    for (int i = 1; i < e.size; ++i) {
        p = two_prod(e.c[i], b);
        const xpair s = two_sum(Q, p.lo);
        if (s.lo.m != 0) h.push_back(s.lo);
        const xpair t = two_sum(p.hi, s.hi);
        if (t.lo.m != 0) h.push_back(t.lo);
        Q = t.hi;
    }
    if (Q.m != 0) h.push_back(Q);
    return h;
}

// e·f: one scaled copy of e per component of f, 2MN components at most.
template <int M, int N>
ROBUST_SPHERE_HD inline expansion<2 * M * N> product(const expansion<M>& e, const expansion<N>& f) {
    expansion<2 * M * N> acc;
    for (int j = 0; j < f.size; ++j) {
        const expansion<2 * M> part = scale(e, f.c[j]);
        for (int i = 0; i < part.size; ++i) grow(acc, part.c[i]);
        compress(acc);
    }
    return acc;
}

// The exact value a − b of two doubles (in xfloats: no overflow).
ROBUST_SPHERE_HD inline expansion<2> exact_difference(double a, double b) {
    const xpair s = two_sum(to_xfloat(a), to_xfloat(-b));
    expansion<2> e;
    if (s.lo.m != 0) e.push_back(s.lo);
    if (s.hi.m != 0) e.push_back(s.hi);
    return e;
}

ROBUST_SPHERE_HD inline expansion<1> single(double a) {
    expansion<1> e;
    if (a != 0) e.push_back(to_xfloat(a));
    return e;
}

// A double-word mantissa with an unbounded exponent: (m.hi + m.lo)·2^e,
// ½ ≤ |m.hi| < 1 or zero. Each operation below has relative error under
// 2^-100 (the double-word bounds; exponents never overflow).
struct xdd {
    dd m;
    int e = 0;
    ROBUST_SPHERE_HD bool zero() const { return m.hi == 0; }
};

ROBUST_SPHERE_HD inline void store(xdd& to, const xdd& from) {
    to.m.hi = from.m.hi;
    to.m.lo = from.m.lo;
    to.e = from.e;
}

ROBUST_SPHERE_HD inline xdd normalized(dd m, int e) {
    if (m.hi == 0) return {};
    int k = 0;
    const double hi = split_exponent(m.hi, k);
    return {{hi, scale_by(m.lo, -k)}, e + k};
}

// The value of an expansion to relative 2^-100: its top three components
// after compression (each nonoverlapping component is below an ulp of the next).
template <int N>
ROBUST_SPHERE_HD inline xdd approximate(const expansion<N>& x) {
    expansion<N> e;
    assign(e, x);
    compress(e);
    if (e.empty()) return {};
    const int top = e.back().e;
    dd m{e.back().m, 0};
    for (int k = 1; k <= 2 && k < e.size; ++k) {
        const xfloat& c = e.c[e.size - 1 - k];
        m = dw_add(m, {scale_by(c.m, c.e - top), 0});
    }
    return normalized(m, top);
}

ROBUST_SPHERE_HD inline xdd x_negate(xdd x) { return {negate(x.m), x.e}; }
ROBUST_SPHERE_HD inline xdd x_div(xdd x, xdd y) {
    return x.zero() ? xdd{} : normalized(dw_div(x.m, y.m), x.e - y.e);
}

ROBUST_SPHERE_HD inline xdd x_sqrt(xdd x) {
    if (x.zero()) return {};
    const bool odd = (x.e & 1) != 0;  // make the exponent even: m·2 in [1, 2)
    const dd m = odd ? dd{x.m.hi * 2, x.m.lo * 2} : x.m;
    return normalized(dw_sqrt(m), (x.e - (odd ? 1 : 0)) / 2);
}

// x + y for x, y of the same sign (no cancellation).
ROBUST_SPHERE_HD inline xdd x_add_same_sign(xdd x, xdd y) {
    if (x.zero()) return y;
    if (y.zero()) return x;
    if (x.e < y.e) {
        const xdd t = x;
        x = y, y = t;
    }
    const int gap = x.e - y.e;
    if (gap > 200) return x;  // y is below 2^-199·|x|
    return normalized(dw_add(x.m, {scale_by(y.m.hi, -gap), scale_by(y.m.lo, -gap)}), x.e);
}

// The exact solver: every sign from expansions, every root to relative 2^-90
// from their approximations, and the rounding of a root settled by comparing
// it exactly with the rounding boundaries when that bound leaves it open.
// P = 1: a ray, its direction d one double a coordinate. P = 2: a segment,
// d = p1 − p0 taken exactly, two components a coordinate (exact_difference).
// Capacities (components), P = 1 (P = 2): f_i 2, r² 2, a 6P² (24), b′ 12P
// (24), C 26, d × f 8P per coordinate, Δ′ 24P² + 3·128P² = 408P² (1632); a
// comparison with a value v of 2 components: a·v + b′ 24P² + 12P (120),
// |f + v·d|² − r² 3·2(2 + 4P)² + 2 = 218 (602).
template <class T, int P = 1>
class exact_solver {
    static_assert(P == 1 || P == 2, "a ray's direction or a segment's exact difference");
    using direction_part = std::conditional_t<P == 1, xfloat, expansion<2>>;

public:
    ROBUST_SPHERE_HD exact_solver(const ray<T>& ray_, const sphere<T>& s) {
        static_assert(P == 1, "a ray: one double a coordinate of its direction");
        const double o[3] = {ray_.origin.x, ray_.origin.y, ray_.origin.z};
        const double d[3] = {ray_.direction.x, ray_.direction.y, ray_.direction.z};
        const double c[3] = {s.centre.x, s.centre.y, s.centre.z};
        const double r = s.radius;
        bool finite = isfinite(r);
        for (int i = 0; i < 3; ++i) finite = finite && isfinite(o[i]) && isfinite(d[i]) && isfinite(c[i]);
        valid_ = finite && (d[0] != 0 || d[1] != 0 || d[2] != 0);
        if (!valid_) return;
        // f = o − c as exact two_sum pairs.
        for (int i = 0; i < 3; ++i) assign(f_[i], exact_difference(o[i], c[i])), store(d_[i], to_xfloat(d[i]));
        form_coefficients(r);
    }

    // The segment p0 + t·(p1 − p0), t the fraction of the segment.
    ROBUST_SPHERE_HD exact_solver(const vec3<T>& p0, const vec3<T>& p1, const sphere<T>& s) {
        static_assert(P == 2, "a segment: its difference p1 − p0 in two components a coordinate");
        const double a[3] = {p0.x, p0.y, p0.z}, b[3] = {p1.x, p1.y, p1.z};
        const double c[3] = {s.centre.x, s.centre.y, s.centre.z};
        const double r = s.radius;
        bool finite = isfinite(r);
        for (int i = 0; i < 3; ++i) finite = finite && isfinite(a[i]) && isfinite(b[i]) && isfinite(c[i]);
        valid_ = finite && (a[0] != b[0] || a[1] != b[1] || a[2] != b[2]);
        if (!valid_) return;
        for (int i = 0; i < 3; ++i) assign(f_[i], exact_difference(a[i], c[i])), assign(d_[i], exact_difference(b[i], a[i]));
        form_coefficients(r);
    }

    ROBUST_SPHERE_HD uncertain line_class() const {
        if (!valid_) return {0};
        const int s = sign(D_);
        return {s < 0 ? 0 : (s == 0 ? 1 : 2)};
    }
    ROBUST_SPHERE_HD uncertain sign_C() const { return {sign(C_)}; }
    ROBUST_SPHERE_HD uncertain sign_b() const { return {sign(b_)}; }

    ROBUST_SPHERE_HD uncertain_value<T> rounded(root which) {
        const xdd& t = root_estimate(which);
        if (t.zero()) return {T(0)};
        // Small margin where rounding to T is one rounding of the mantissa
        // (double, normal or overflowing result); 2^-50 where a second
        // rounding follows (float, or a subnormal double).
        const bool one_rounding = std::is_same_v<T, double> && t.e >= -1020;
        const double w = (rho + (one_rounding ? 0x1p-100 : 0x1p-50)) * abs(t.m.hi);
        const T low = scaled(t.m.hi + (t.m.lo - w), t.e), high = scaled(t.m.hi + (t.m.lo + w), t.e);
        if (low == high) return {low};
        // Walk the candidates, comparing t* exactly with each midpoint.
        for (T c = low; c < high;) {
            const T next = next_toward(c, infinity<T>());
            const int s = compare(which, midpoint(c, next));
            if (s < 0) return {c};
            if (s == 0) return {even(c) ? c : next};
            c = next;
        }
        return {high};
    }

    // The bounded tier's root: the correctly rounded one satisfies it.
    ROBUST_SPHERE_HD uncertain_value<T> bounded(root which) { return rounded(which); }

    ROBUST_SPHERE_HD uncertain sign_against(root, T) const { return {}; }  // rounded() settles it

    ROBUST_SPHERE_HD uncertain sign_after(root which, T c) {
        if (isinf(c)) return {c > 0 ? -1 : 1};
        expansion<2> v;
        if (c != 0) v.push_back(to_xfloat(double(c)));
        return {compare(which, v)};
    }

private:
    static constexpr double rho = 0x1p-90;
    // e · d_i, exactly.
    template <int N>
    ROBUST_SPHERE_HD auto times_d(const expansion<N>& e, int i) const {
        if constexpr (P == 1)
            return scale(e, d_[i]);
        else
            return product(e, d_[i]);
    }

    // d_i as an expansion.
    ROBUST_SPHERE_HD expansion<P> direction(int i) const {
        expansion<P> e;
        if constexpr (P == 1) {
            if (d_[i].m != 0) e.push_back(d_[i]);
        } else {
            assign(e, d_[i]);
        }
        return e;
    }

    // a = d·d, b′ = d·f, C = f·f − r², Δ′ = a·r² − |d × f|² (degree 4), exactly.
    ROBUST_SPHERE_HD void form_coefficients(double r) {
        assign(r2_, product(single(r), single(r)));
        expansion<24> C;
        for (int i = 0; i < 3; ++i) {
            const auto dd_i = times_d(direction(i), i);
            for (int k = 0; k < dd_i.size; ++k) grow(a_, dd_i.c[k]);
            const auto df = times_d(f_[i], i);
            for (int k = 0; k < df.size; ++k) grow(b_, df.c[k]);
            const expansion<8> ff = product(f_[i], f_[i]);
            for (int k = 0; k < ff.size; ++k) grow(C, ff.c[k]);
        }
        compress(a_), compress(b_);
        sum_into(C_, C, r2_, true);
        compress(C_);

        expansion<384 * P * P> cross2;
        for (int i = 0; i < 3; ++i) {
            const int j = (i + 1) % 3, k = (i + 2) % 3;
            expansion<8 * P> x = sum(times_d(f_[k], j), times_d(f_[j], k), true);
            compress(x);
            const expansion<128 * P * P> x2 = product(x, x);
            for (int m = 0; m < x2.size; ++m) grow(cross2, x2.c[m]);
            compress(cross2);
        }
        sum_into(D_, product(a_, r2_), cross2, true);
        compress(D_);
    }


    // RN_T(x·2^e) for x within 2^-50 of its double: one rounding to double
    // (exact in double's normal range), then to T.
    ROBUST_SPHERE_HD static T scaled(double x, int e) {
        const double v = scale_by(x, e < -4000 ? -4000 : (e > 4000 ? 4000 : e));
        if constexpr (std::is_same_v<T, float>)
            return round_to_float(v);
        else
            return v;
    }

    ROBUST_SPHERE_HD static bool even(T c) { return isinf(c) || (bits_of<bits_type<T>>(c) & 1u) == 0; }

    // (c + next)/2 exactly, next = the T after c; beside an infinity, the
    // overflow threshold ±(max + ½ulp(max)).
    ROBUST_SPHERE_HD static expansion<2> midpoint(T c, T next) {
        const T max = largest<T>();
        const double ulp_max = double(max) - double(next_toward(max, T(0)));
        double base = c, gap = double(next) - double(c);  // one ulp, exact in double
        if (isinf(next)) gap = ulp_max;                     // c = max
        if (isinf(c)) base = next, gap = -ulp_max;          // next = −max
        expansion<2> e;
        e.push_back(to_xfloat(gap, -1));  // ½ulp, below base's last bit, exact even under denorm_min
        if (base != 0) e.push_back(to_xfloat(base));
        return e;
    }

    // sign(t* − v) for the root `which` and an exact value v: with
    // w = a·v + b′, t* − v = (σ√Δ′ − w)/a, σ = −1 for the near root, +1 far;
    // where w has σ's sign, sign(Δ′ − w²) decides, and Δ′ − w² = −a·P(v) for
    // P(v) = |f + v·d|² − r².
    ROBUST_SPHERE_HD int compare(root which, const expansion<2>& v) const {
        expansion<24 * P * P + 12 * P> w = sum(product(a_, v), b_);
        compress(w);
        const int sw = sign(w), sD = sign(D_);
        if (which == root::far_root) {
            if (sw <= 0) return (sD > 0 || sw < 0) ? 1 : 0;
            return -residual_sign(v);
        }
        if (sw >= 0) return (sD > 0 || sw > 0) ? -1 : 0;
        return residual_sign(v);
    }

    // sign(P(v)), P(v) = Σ (f_i + v·d_i)² − r², exactly.
    ROBUST_SPHERE_HD int residual_sign(const expansion<2>& v) const {
        constexpr int g_size = 2 + 4 * P;
        expansion<6 * g_size * g_size + 2> residual;
        for (int k = 0; k < r2_.size; ++k) residual.push_back({-r2_.c[k].m, r2_.c[k].e});
        for (int i = 0; i < 3; ++i) {
            expansion<g_size> g = sum(f_[i], times_d(v, i));
            compress(g);
            const expansion<2 * g_size * g_size> g2 = product(g, g);
            for (int k = 0; k < g2.size; ++k) grow(residual, g2.c[k]);
            compress(residual);
        }
        return sign(residual);
    }

    // The roots to relative 2^-90 (a handful of operations under 2^-100 each).
    ROBUST_SPHERE_HD const xdd& root_estimate(root which) {
        if (!have_roots_) {
            have_roots_ = true;
            const xdd a = approximate(a_), b = approximate(b_), C = approximate(C_), D = approximate(D_);
            if (sign(D_) == 0) {
                store(roots_[0], x_div(x_negate(b), a));
                store(roots_[1], roots_[0]);
            } else {
                const int sigma = sign(b_) < 0 ? -1 : 1;
                const xdd s = x_sqrt(D);
                const xdd q = x_negate(x_add_same_sign(b, sigma > 0 ? s : x_negate(s)));
                const xdd A = x_div(q, a), B = x_div(C, q);
                store(roots_[0], sigma > 0 ? A : B);
                store(roots_[1], sigma > 0 ? B : A);
            }
        }
        return roots_[which == root::near_root ? 0 : 1];
    }

    bool valid_ = false;
    expansion<2> f_[3];
    direction_part d_[3];
    expansion<2> r2_;
    expansion<6 * P * P> a_;
    expansion<12 * P> b_;
    expansion<26> C_;
    expansion<408 * P * P> D_;
    bool have_roots_ = false;
    xdd roots_[2];
};

// ---------------------------------------------------------------------------
// The queries, written once over a solver: a fast_solver (any step may be
// left open, and the query gives up: it returns false) or an exact_solver
// (never leaves one open).

template <class S>
ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD uncertain root_sign(S& s, root which) {
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
ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD uncertain compare(S& s, root which, T v) {
    if (isinf(v)) return {v > 0 ? -1 : 1};
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

// The value returned for a root: RN(t*) (or the bounded tier's value), but
// +denorm_min for a positive root that rounds to 0 (it stays in front) and
// −0 for a negative one.
template <roots R, class T, class S>
ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD uncertain_value<T> returned(S& s, root which) {
    const uncertain_value<T> c = R == roots::bounded ? s.bounded(which) : s.rounded(which);
    if (!c || *c != 0) return c;
    const uncertain sg = root_sign(s, which);
    if (!sg) return {};
    return {*sg == 0 ? T(0) : (*sg > 0 ? denorm_min<T>() : -T(0))};
}

// The class: two roots whenever C < 0 (the origin inside: Δ′ = b′² − aC > 0),
// without computing Δ′.
template <class S>
ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD uncertain line_class(S& s) {
    const uncertain sc = s.sign_C();
    if (sc && *sc < 0) return {2};
    return s.line_class();
}

// C > 0 and b′ > 0: any roots are both behind the origin (product C/a > 0,
// sum −2b′/a < 0), so an interval with tmin ≥ 0 holds none.
template <class T, class S>
ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD bool behind(S& s, T tmin) {
    if (!(tmin >= 0)) return false;
    const uncertain sc = s.sign_C();
    if (!sc || *sc <= 0) return false;
    const uncertain sb = s.sign_b();
    return sb && *sb > 0;
}

template <roots R, class T, class S>
ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD bool query_line(S& s, line_roots<T>& out) {
    const uncertain cls = line_class(s);
    if (!cls) return false;
    if (*cls == 0) {
        out = {};
        return true;
    }
    const uncertain_value<T> t0 = returned<R, T>(s, root::near_root);
    if (!t0) return false;
    if (*cls == 1) {
        out = {1, *t0, *t0};
        return true;
    }
    const uncertain_value<T> t1 = returned<R, T>(s, root::far_root);
    if (!t1) return false;
    if (*t1 < *t0) return false;  // bounded roots of a line that nearly touches: let a finer stage order them
    out = {2, *t0, *t1};
    return true;
}

// Is root `which` in the interval? 0 or 1, or unknown.
template <ends Lower, ends Upper, class T, class S>
ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD uncertain inside(S& s, root which, T tmin, T tmax) {
    const uncertain lower = compare(s, which, tmin);
    if (!lower) return {};
    if (*lower < 0 || (*lower == 0 && Lower == ends::open)) return {0};
    const uncertain upper = compare(s, which, tmax);
    if (!upper) return {};
    return {*upper < 0 || (*upper == 0 && Upper == ends::closed)};
}

template <ends Lower, ends Upper, roots R, class T, class S>
ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD bool query_nearest(S& s, T tmin, T tmax, ray_hit<T>& out) {
    out = {};
    if (behind(s, tmin)) return true;
    const uncertain cls = line_class(s);
    if (!cls) return false;
    if (*cls == 0) return true;
    for (int k = 0; k < *cls; ++k) {
        const root which = k == 0 ? root::near_root : root::far_root;
        const uncertain in = inside<Lower, Upper>(s, which, tmin, tmax);
        if (!in) return false;
        if (!*in) continue;
        const uncertain_value<T> found = returned<R, T>(s, which);
        if (!found) return false;
        // RN(t*) may fall on an open end: one ulp inside (within 1 ulp of t*);
        // a bounded root outside the interval (t* is inside) onto its end.
        T t = *found;
        if (Lower == ends::open ? t <= tmin : t < tmin) t = Lower == ends::open ? next_toward(tmin, tmax) : tmin;
        if (Upper == ends::open ? t >= tmax : t > tmax) t = Upper == ends::open ? next_toward(tmax, tmin) : tmax;
        out = {true, t, which};
        return true;
    }
    return true;
}

template <ends Lower, ends Upper, class T, class S>
ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD bool query_any(S& s, T tmin, T tmax, bool& out) {
    out = false;
    if (behind(s, tmin)) return true;
    const uncertain cls = line_class(s);
    if (!cls) return false;
    if (*cls == 0) return true;
    for (int k = 0; k < *cls; ++k) {
        const root which = k == 0 ? root::near_root : root::far_root;
        const uncertain in = inside<Lower, Upper>(s, which, tmin, tmax);
        if (!in) return false;
        if (*in) {
            out = true;
            return true;
        }
    }
    return true;
}

// The exact path, out of line: it runs for few cases and is large. Its roots
// are correctly rounded, which also keeps the bounded tier's promise.
template <class T>
ROBUST_SPHERE_COLD ROBUST_SPHERE_HD line_roots<T> exact_line(const ray<T>& r, const sphere<T>& s) {
    exact_solver<T> e(r, s);
    line_roots<T> out;
    query_line<roots::correctly_rounded, T>(e, out);
    return out;
}

template <ends Lower, ends Upper, class T>
ROBUST_SPHERE_COLD ROBUST_SPHERE_HD ray_hit<T> exact_nearest(const ray<T>& r, const sphere<T>& s, T tmin, T tmax) {
    exact_solver<T> e(r, s);
    ray_hit<T> out;
    query_nearest<Lower, Upper, roots::correctly_rounded>(e, tmin, tmax, out);
    return out;
}

template <ends Lower, ends Upper, class T>
ROBUST_SPHERE_COLD ROBUST_SPHERE_HD bool exact_any(const ray<T>& r, const sphere<T>& s, T tmin, T tmax) {
    exact_solver<T> e(r, s);
    bool out = false;
    query_any<Lower, Upper>(e, tmin, tmax, out);
    return out;
}

// Stage 1 and 2 (double), out of line, then the exact path: where the
// inlined stage 1 could not answer.
template <roots R, class T>
ROBUST_SPHERE_COLD ROBUST_SPHERE_HD line_roots<T> refined_line(const ray<T>& r, const sphere<T>& s) {
    if constexpr (std::is_same_v<T, double>) {
        fast_solver<T, true> refined(r, s);
        line_roots<T> out;
        if (query_line<R, T>(refined, out)) return out;
    }
    return exact_line(r, s);
}

template <ends Lower, ends Upper, roots R, class T>
ROBUST_SPHERE_COLD ROBUST_SPHERE_HD ray_hit<T> refined_nearest(const ray<T>& r, const sphere<T>& s, T tmin, T tmax) {
    if constexpr (std::is_same_v<T, double>) {
        fast_solver<T, true> refined(r, s);
        ray_hit<T> out;
        if (query_nearest<Lower, Upper, R>(refined, tmin, tmax, out)) return out;
    }
    return exact_nearest<Lower, Upper>(r, s, tmin, tmax);
}

template <ends Lower, ends Upper, class T>
ROBUST_SPHERE_COLD ROBUST_SPHERE_HD bool refined_any(const ray<T>& r, const sphere<T>& s, T tmin, T tmax) {
    if constexpr (std::is_same_v<T, double>) {
        fast_solver<T, true> refined(r, s);
        bool out = false;
        if (query_any<Lower, Upper>(refined, tmin, tmax, out)) return out;
    }
    return exact_any<Lower, Upper>(r, s, tmin, tmax);
}

// A segment's nearest hit on f ∈ [0, 1] (ends as given), after the start
// rule: strictly inside (C < 0) is a contact at f = 0 under
// start_inside::contact.
template <ends Start, ends End, start_inside Inside, class T, class S>
ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD bool query_segment(S& s, ray_hit<T>& out) {
    if constexpr (Inside == start_inside::contact) {
        const uncertain sc = s.sign_C();
        if (!sc) return false;
        if (*sc < 0) {
            out = {true, T(0), root::near_root};
            return true;
        }
    }
    return query_nearest<Start, End, roots::correctly_rounded>(s, T(0), T(1), out);
}

// Stage 2 (double) on the segment's exact difference, then the exact path
// (with p1 − p0 in one component a coordinate where it is a value of T: the
// smaller expansions), out of line.
template <ends Start, ends End, start_inside Inside, class T>
ROBUST_SPHERE_COLD ROBUST_SPHERE_HD ray_hit<T> refined_segment(const segment<T>& g, const sphere<T>& s) {
    ray_hit<T> out;
    if constexpr (std::is_same_v<T, double>) {
        fast_solver<T, true, true> refined(g, s);
        if (query_segment<Start, End, Inside>(refined, out)) return out;
    }
    const T a[3] = {g.p0.x, g.p0.y, g.p0.z}, b[3] = {g.p1.x, g.p1.y, g.p1.z};
    T d[3];
    bool representable = true;
    for (int i = 0; i < 3; ++i) {
        const dd diff = two_sum(double(b[i]), -double(a[i]));  // float: exact in double or not
        if constexpr (std::is_same_v<T, float>)
            d[i] = round_to_float(diff.hi);  // a difference of floats may pass FLT_MAX
        else
            d[i] = diff.hi;
        representable = representable && diff.lo == 0 && double(d[i]) == diff.hi && isfinite(d[i]);
    }
    if (representable) {
        const ray<T> r{g.p0, {d[0], d[1], d[2]}};
        exact_solver<T> e(r, s);
        query_segment<Start, End, Inside>(e, out);
    } else {
        exact_solver<T, 2> e(g.p0, g.p1, s);
        query_segment<Start, End, Inside>(e, out);
    }
    return out;
}

// ulp above |x|: the largest distance from x to a real that rounds to it.
template <class T>
ROBUST_SPHERE_HD double ulp_above(T x) {
    const T m = abs(x);
    const T next = next_toward(m, infinity<T>());
    return isinf(next) ? double(m) - double(next_toward(m, T(0))) : double(next) - double(m);
}

// A bound in double, rounded up to T.
template <class T>
ROBUST_SPHERE_HD T rounded_up(double bound) {
    const double b = bound * (1 + 0x1p-40);
    if constexpr (std::is_same_v<T, float>) {
        const float f = round_to_float(b);
        return double(f) >= b ? f : next_toward(f, infinity<float>());
    } else {
        return b;
    }
}

}  // namespace detail

// ---------------------------------------------------------------------------
// The queries. T is float or double; tmin ≤ tmax, either may be infinite.
// R = roots::bounded asks for the bounded tier (see the top of the file).

// Both roots of the line (t of any sign): exact class, roots as promised above.
template <roots R = roots::correctly_rounded, class T>
ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD line_roots<T> intersect_line(const ray<T>& r, const sphere<T>& s) {
    detail::fast_solver<T, false> fast(r, s);
    line_roots<T> out;
    if (detail::query_line<R, T>(fast, out)) return out;
    return detail::refined_line<R>(r, s);
}

// The nearest root t* with tmin < t* < tmax; an end given as ends::closed
// includes t* equal to it. Decided exactly.
template <ends Lower = ends::open, ends Upper = ends::open, roots R = roots::correctly_rounded, class T>
ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD ray_hit<T> nearest_hit(const ray<T>& r, const sphere<T>& s,
                                                             detail::same_t<T> tmin,
                                                             detail::same_t<T> tmax) {
    detail::fast_solver<T, false> fast(r, s);
    ray_hit<T> out;
    if (detail::query_nearest<Lower, Upper, R>(fast, tmin, tmax, out)) return out;
    return detail::refined_nearest<Lower, Upper, R, T>(r, s, tmin, tmax);
}

// Is there a root in the interval (a shadow ray)? Decided exactly.
template <ends Lower = ends::open, ends Upper = ends::open, class T>
ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD bool any_hit(const ray<T>& r, const sphere<T>& s,
                                                   detail::same_t<T> tmin, detail::same_t<T> tmax) {
    detail::fast_solver<T, false> fast(r, s);
    bool out = false;
    if (detail::query_any<Lower, Upper>(fast, tmin, tmax, out)) return out;
    return detail::refined_any<Lower, Upper, T>(r, s, tmin, tmax);
}

// A segment's first contact with the sphere: the fraction f ∈ [0, 1] of the
// way from p0 to p1 (an end given as ends::open excludes a contact exactly
// there), correctly rounded, every decision exact for the segment as given
// (p1 − p0 is never rounded). A segment starting strictly inside touches at
// f = 0 (start_inside::contact) or hits its exit (start_inside::exit). A
// zero-length segment (p0 = p1) or a non-finite input is a miss. The ray's
// three stages answer, on RN(p1 − p0) with its rounding in stage 1's bounds
// and on the exact pair in stage 2; the exact path, where they cannot,
// takes p1 − p0 in two components a coordinate where it is no value of T
// (about 60 KB of stack then, also on a GPU).
template <ends Start = ends::closed, ends End = ends::closed, start_inside Inside = start_inside::contact, class T>
ROBUST_SPHERE_INLINE ROBUST_SPHERE_HD ray_hit<T> segment_hit(const segment<T>& g, const sphere<T>& s) {
    static_assert(detail::supported<T>, "robust_sphere.h answers in float or double");
    const T a[3] = {g.p0.x, g.p0.y, g.p0.z}, b[3] = {g.p1.x, g.p1.y, g.p1.z};
    bool finite = detail::isfinite(s.radius), moves = false;
    for (int i = 0; i < 3; ++i) {
        finite = finite && detail::isfinite(a[i]) && detail::isfinite(b[i]);
        moves = moves || a[i] != b[i];
    }
    if (!finite || !moves) return {};
    detail::fast_solver<T, false, true> fast(g, s);
    ray_hit<T> out;
    if (detail::query_segment<Start, End, Inside>(fast, out)) return out;
    return detail::refined_segment<Start, End, Inside>(g, s);
}

// The fast path alone: what it settles, and nullopt where the exact path
// would run. For measuring the fallback rate (host only); the answers are
// the same.
template <roots R = roots::correctly_rounded, class T>
std::optional<line_roots<T>> intersect_line_fast(const ray<T>& r, const sphere<T>& s) {
    detail::fast_solver<T, true> fast(r, s);
    line_roots<T> out;
    if (detail::query_line<R, T>(fast, out)) return out;
    return std::nullopt;
}

template <ends Lower = ends::open, ends Upper = ends::open, roots R = roots::correctly_rounded, class T>
std::optional<ray_hit<T>> nearest_hit_fast(const ray<T>& r, const sphere<T>& s, detail::same_t<T> tmin,
                                           detail::same_t<T> tmax) {
    detail::fast_solver<T, true> fast(r, s);
    ray_hit<T> out;
    if (detail::query_nearest<Lower, Upper, R>(fast, tmin, tmax, out)) return out;
    return std::nullopt;
}

template <ends Lower = ends::open, ends Upper = ends::open, class T>
std::optional<bool> any_hit_fast(const ray<T>& r, const sphere<T>& s, detail::same_t<T> tmin,
                                 detail::same_t<T> tmax) {
    detail::fast_solver<T, true> fast(r, s);
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
ROBUST_SPHERE_HD surface_point<T> hit_point(const ray<T>& r, const sphere<T>& s, detail::same_t<T> t, bool reproject = false) {
    static_assert(detail::supported<T>, "robust_sphere.h answers in float or double");
    using detail::dd;
    const T o[3] = {r.origin.x, r.origin.y, r.origin.z};
    const T d[3] = {r.direction.x, r.direction.y, r.direction.z};
    const T c[3] = {s.centre.x, s.centre.y, s.centre.z};
    dd p[3];  // o + t·d to relative 2^-100 (double) or as rounded in double (float)
    double slack[3];  // a bound on |p_i − (o_i + t·d_i)| beyond p's own rounding to T
    for (int i = 0; i < 3; ++i) {
        if constexpr (std::is_same_v<T, float>) {
            p[i] = {double(o[i]) + double(t) * d[i], 0};  // t·d exact in double
            slack[i] = 0x1p-53 * detail::abs(p[i].hi);
        } else if (detail::abs(t) < 0x1p995 && detail::abs(d[i]) < 0x1p995) {
            const dd td = detail::two_prod(t, d[i]);
            const dd sum = detail::two_sum(o[i], td.hi);
            p[i] = detail::fast_two_sum(sum.hi, sum.lo + td.lo);
            slack[i] = 0x1p-100 * (detail::abs(o[i]) + detail::abs(td.hi)) + 0x1p-1060;
        } else {
            p[i] = {o[i] + t * d[i], 0};
            slack[i] = 0x1p-52 * (detail::abs(o[i]) + 2 * detail::abs(t * d[i]));
        }
    }
    // t = ±the largest finite value may stand for a root past the format's
    // range (nearest_hit answers so on an open interval when RN(t*) = ±inf):
    // |t − t*| has no bound there, and neither has the point's error.
    const bool unbounded = detail::abs(t) == detail::largest<T>();
    const T no_bound = detail::infinity<T>();
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
                                  : detail::rounded_up<T>(detail::abs(double(d[i])) * detail::ulp_above(t) + half_ulp +
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
    const double r_abs = detail::abs(double(s.radius));
    bool scaled_well = r_abs >= 0x1p-400 && r_abs <= 0x1p400;
    for (int i = 0; i < 3; ++i) {
        const double values[2] = {p[i].hi, double(c[i])};
        for (const double v : values)
            scaled_well = scaled_well && (v == 0 || (detail::abs(v) >= 0x1p-400 && detail::abs(v) <= 0x1p400));
    }
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
                                                      eps * (r_abs + detail::abs(double(c[i]))) + 0x1p-1060);
    }
    return out;
}

}  // namespace robust_sphere
