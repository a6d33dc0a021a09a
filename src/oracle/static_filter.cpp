// The static filter (static_filter.h).
//
// Notation: u = 2^−53, γ_n = n·u/(1 − n·u) (Higham, Accuracy and Stability of
// Numerical Algorithms, §3.1): a value computed through n roundings of sums
// and products of exact inputs is within γ_n·(the same expression with every
// input and operation taken in absolute value) of the exact one. Each bound
// below is first order in u with a constant rounded up by at least one u (or
// a relative 2^−18 where a bound is a ratio); that slack covers the
// second-order terms and the roundings of the bound's own evaluation (each a
// factor (1 ± u), a few dozen at most: (1 + u)^64 < 1 + 2^−46). A decision
// is taken only when a value exceeds its bound strictly.
//
// Range: every input 0 or of magnitude in [2^−80, 2^80] (filter.h's note):
// every nonzero value formed below is far from the underflow threshold and
// nothing overflows, so every rounding is relative.
#include "oracle/static_filter.h"

#include <cmath>

#include "core/double_word.h"
#include "core/fma_clones.h"
#include "oracle/expansion.h"

namespace rayverify::oracle_internal {
namespace {

constexpr double u = 0x1p-53;
constexpr double u2 = 0x1p-106;
// A relative bound is used only where it is at most 2^−20, so that its
// second-order terms stay below 2^−20 of it: the factor 1 + 2^−18 covers them.
constexpr double small = 0x1p-20;
constexpr double second_order = 1 + 0x1p-18;

// A root's first approximation t̂ with |t* − t̂| ≤ err.
struct approximation {
    double t = 0, err = 0;
};

// The near and the far root's values side by side, one per lane (lane 0 the
// near root's): both roots are corrected by the same operations at once
// (double_word.h's two lanes), which cost little more than one root's.
constexpr int near_lane = 0, far_lane = 1;

// At t̂ (a double in each lane): P(t̂) = |f + t̂·d|² − r² = a·t̂² + 2b′·t̂ + C
// within `bound` of `value`, and β = P′(t̂)/2 = d·(f + t̂·d) within
// `slope_bound` of `slope`.
struct residual {
    double_pair value, bound;
    double_pair slope, slope_bound;
};

// The residual at t̂, from f = o − c exactly (f.h + f.l) and r² exactly.
//
// Per axis, p = f + t̂·d = s + g + ε: (ph, pl) = two_prod(t̂, d) and
// (s, e) = two_sum(fh, ph) are exact; g = RN(RN(e + fl) + pl) is within
// γ2·(|e| + |fl| + |pl|) of e + fl + pl, and |e| ≤ u|s|, |fl| ≤ u|fh|,
// |pl| ≤ u|ph|: with W = |s| + |fh| + |ph| (computed), |g| ≤ 1.01u·W and
// |ε| ≤ 2.02u²·W.
//
// P = Σs² − r² + Σ(2s + g)·g + Σ(2(s + g) + ε)·ε. The first sum is an
// expansion: (qh, ql) = two_prod(s, s), (rh, rl) = r², and two_sums in a
// tree, qh0 + qh1 (error e1) and qh2 − rh (e2), then their sum a3 (e3), leave
// a3 and errors e1, e2, e3, exactly (a tree, not a chain, so that a3 waits for
// two two_sums, not three).
// With V = Σ(|s| + u·W)·W and M = Σqh + rh:
//   - |(2s + g)·g| ≤ 2.03u·(|s| + uW)·W, so |Σ(2s + g)g| ≤ 2.03u·V, and its
//     evaluation (an add, a product, two sums: γ4) errs by ≤ 8.15u²·V;
//   - |(2(s + g) + ε)·ε| ≤ 2.02u²W·(2|s| + 2.03uW), summed ≤ 4.1u²·V;
//   - the low sum λ of e1, e2, e3, ql0, ql1, ql2, −rl and T2 = Σ(2s + g)g
//     (7 additions, in any order: γ7) errs by ≤ 7.01u·(3.01u·M + u·|a3| +
//     2.04u·V), since |e1| + |e2| + |ql| + |rl| ≤ 3.01u·M and |e3| ≤ u|a3|;
//     e3 is added last, so that the rest of λ does not wait for a3;
//   - R = RN(a3 + λ) adds u·|R|.
// Total ≤ u|R| + 21.1u²·M + 7.01u²·|a3| + 26.6u²·V, rounded up below.
// A square s² or a product (2s + g)·g of tiny values may underflow (s can be
// a cancellation's small remainder): each such rounding errs by less than
// 2^−1074, and the floor 2^−1000 covers them all.
//
// β = d·p: p̂ = RN(s + g) is within u|p̂| + |ε| of p, and Σd·p̂ (three
// products, two sums: γ3) within γ3·Σ|d·p̂|: |β̂ − β| ≤ 5u·Σ|d||p̂| +
// 3u²·Σ|d|·W (slack included), plus the floor.
residual residual_at(double_pair t, const dword f[3], const double d[3], dword r_squared) {
    double_pair s[3], g[3], V{}, slope{}, slope_magnitude{}, slope_low{};
    for (int axis = 0; axis < 3; ++axis) {
        const double_pair d_axis = both_lanes(d[axis]), fh = both_lanes(f[axis].h);
        const dword_pair p = two_prod(t, d_axis);
        const dword_pair sum = two_sum(fh, p.h);
        s[axis] = sum.h;
        g[axis] = (sum.l + f[axis].l) + p.l;
        const double_pair W = (fabs_lanes(sum.h) + fabs_lanes(fh)) + fabs_lanes(p.h);
        V += (fabs_lanes(sum.h) + u * W) * W;
        const double_pair point = s[axis] + g[axis];
        slope += d_axis * point;
        slope_magnitude += fabs_lanes(d_axis * point);
        slope_low += fabs_lanes(d_axis) * W;
    }
    const dword_pair q0 = two_prod(s[0], s[0]), q1 = two_prod(s[1], s[1]), q2 = two_prod(s[2], s[2]);
    const dword_pair a1 = two_sum(q0.h, q1.h);
    const dword_pair a2 = two_sum(q2.h, both_lanes(-r_squared.h));
    const dword_pair a3 = two_sum(a1.h, a2.h);
    const double_pair T2 = (2.0 * s[0] + g[0]) * g[0] + (2.0 * s[1] + g[1]) * g[1] + (2.0 * s[2] + g[2]) * g[2];
    const double_pair low = (((q0.l + q1.l) + (q2.l - r_squared.l)) + ((a1.l + a2.l) + T2)) + a3.l;
    const double_pair R = a3.h + low;
    const double_pair M = ((q0.h + q1.h) + q2.h) + r_squared.h;
    return {R, (2.0 * u * fabs_lanes(R) + u2 * ((24.0 * M + 8.0 * fabs_lanes(a3.h)) + 30.0 * V)) + 0x1p-1000, slope,
            (5.0 * u * slope_magnitude + 3.0 * u2 * slope_low) + 0x1p-1000};
}

// One Newton step, with its second-order term, for the root t* that an
// approximation t̂ holds within err. With δ = t* − t̂ and β = P′(t̂)/2,
// P(t̂ + δ) = 0 reads, exactly (P is quadratic),
//     P(t̂) + 2β·δ + a·δ² = 0.
// The term a·δ² matters where t is large beside the roots' gap (far spheres).
// Write ι = RN(1/(2β̂)) and â′ = RN(â(1 + 8u)) ≥ â(1 + 3.01u) ≥ a. Then δ is
// bounded in three steps:
//   1. With D = 2β + a·δ (= a·(t̂ − t_o), t_o the other root), P(t̂) = −D·δ:
//      |D| ≥ L1 = 2|β̂| − 2E_β − â′·err > |β̂| (required), as |δ| ≤ err; so
//      |δ| ≤ e1 = (|R| + E_R)·2|ι|, since 1/L1 < 1/|β̂| ≤ 2|ι|(1 + u).
//   2. Likewise L2 = 2|β̂| − 2E_β − â′·e1 > |β̂| (required) bounds |D| below,
//      and |D − 2β̂| ≤ 2E_β + a·|δ|. So δ0 = RN(−R·ι) (two roundings) is
//      within e2 = (E_R + |δ0|(1 + u)·(2E_β + â′·e1))·2|ι| + 3u|δ0| of δ.
//   3. The identity with 2β = 2β̂ + ε_β (|ε_β| ≤ 2E_β) and δ* = −R/(2β̂):
//          δ = δ* − (P(t̂) − R)/(2β̂) − a·δ²/(2β̂) − δ·ε_β/(2β̂).
//      The computed δ1 = RN(δ0 − w), with w = RN(RN(κ·δ0)·δ0) and
//      κ = RN(â·ι), stands for δ* − a·δ²/(2β̂). Term by term, with
//      m = |δ0| + e2 ≥ |δ| and 1/(2|β̂|) ≤ |ι|(1 + 1.01u):
//        - |δ* − δ0| ≤ 2.02u·|δ0| (two roundings);
//        - |(P(t̂) − R)/(2β̂)| ≤ E_R·|ι|(1 + 1.01u);
//        - |a·δ² − â·δ0²| ≤ |a − â|·δ² + â·|δ − δ0|·|δ + δ0|
//                         ≤ â′·(3.01u·m² + e2·(2|δ0| + e2));
//        - w is â·δ0²/(2β̂) with four roundings: within 4.02u·|w|;
//        - |δ·ε_β/(2β̂)| ≤ m·2E_β·|ι|(1 + 1.01u);
//        - the subtraction's rounding adds u·|δ1|.
//      So |δ − δ1| ≤ (E_R + m·2E_β + â′·(3.01u·m² + e2·(2|δ0| + e2)))·|ι| +
//      2.02u|δ0| + 4.02u|w| + u|δ1|, times 1 + 2^−18 for the factor
//      1 + 1.01u and the roundings of the bound's own evaluation (each a
//      factor 1 ± u, a few dozen at most).
// Where a·δ²/(2β) is negligible (most cases) δ1 is Newton's step δ0; where it
// is not, the bound's second-order terms are products of small errors (e2
// times a·δ/β), as small as a second Newton step's, without its division.
// The enclosure is t̂ + δ1 normalised by fast_two_sum (|δ1| ≤ 2^−10·|t̂| is
// required), so that the double-word operations later applied to it keep
// their bounds.
//
// Both roots at once, a lane each (near_lane, far_lane): false unless every
// requirement above holds for both, as the filter needs both roots.
bool corrected(const approximation& near, const approximation& far, double a, const dword f[3], const double d[3],
               dword r_squared, enclosure roots[2]) {
    const double_pair t = {near.t, far.t}, t_err = {near.err, far.err};
    const residual P = residual_at(t, f, d, r_squared);
    const double a_up = a * (1 + 8 * u);
    const double_pair inverse = 1.0 / (2.0 * P.slope);
    const double_pair two_beta = 2.0 * fabs_lanes(P.slope), two_err_beta = 2.0 * P.slope_bound;
    const double_pair R = P.value, E_R = P.bound;
    const double_pair e1 = (fabs_lanes(R) + E_R) * 2.0 * fabs_lanes(inverse) * second_order;
    const double_pair delta0 = -R * inverse;
    const double_pair e2 =
        ((E_R + fabs_lanes(delta0) * (1 + u) * (two_err_beta + a_up * e1)) * 2.0 * fabs_lanes(inverse) +
         3 * u * fabs_lanes(delta0)) *
        second_order;
    const double_pair kappa = a * inverse;
    const double_pair w = (kappa * delta0) * delta0;
    const double_pair delta = delta0 - w;
    // The requirements, tested once: a lane that fails one may have computed
    // nonsense (an infinity, a NaN) after it, but no answer is taken from it.
    const bool required = in_both_lanes((two_beta - two_err_beta) - a_up * t_err > 0.5 * two_beta) &&
                          in_both_lanes((two_beta - two_err_beta) - a_up * e1 > 0.5 * two_beta) &&
                          in_both_lanes(fabs_lanes(delta) <= 0x1p-10 * fabs_lanes(t));
    if (!required) return false;
    const double_pair m = fabs_lanes(delta0) + e2;
    const double_pair err =
        (((E_R + m * two_err_beta) + a_up * (3.01 * u * m * m + e2 * (2.0 * fabs_lanes(delta0) + e2))) *
             fabs_lanes(inverse) +
         ((2.02 * u * fabs_lanes(delta0) + 4.02 * u * fabs_lanes(w)) + u * fabs_lanes(delta))) *
        second_order;
    const dword_pair corrected_t = fast_two_sum(t, delta);
    for (int lane : {near_lane, far_lane})
        roots[lane] = enclosure{corrected_t.h[lane], corrected_t.l[lane], err[lane]};
    return true;
}

// A hit coordinate o + t*·d (d ≠ 0) from t*'s enclosure y + e ± E:
// (ph, pl) = two_prod(y, d) and (h, he) = two_sum(o, ph) are exact; the low
// part RN(RN(he + pl) + RN(e·d)) is within γ2 of |he| + |pl| + |e·d| plus
// the rounding of e·d, ≤ 4u·(|he| + |pl| + |e·d|) with slack; t*'s own error
// adds |d|·E (times 1 + 2^−18 for the rounding of the product). The result
// is normalised with two_sum (o and t·d may cancel). The floor 2^−1000
// covers a product e·d or pl that underflows.
enclosure hit_enclosure(double o, double d, const enclosure& t) {
    const dword p = two_prod(t.hi, d);
    const dword h = two_sum(o, p.h);
    const double ed = t.lo * d;
    const double low = (h.l + p.l) + ed;
    const double err =
        (4 * u * ((std::fabs(h.l) + std::fabs(p.l)) + std::fabs(ed)) + std::fabs(d) * t.err * second_order) + 0x1p-1000;
    const dword z = two_sum(h.h, low);
    return {z.h, z.l, err};
}

// The quadratic's coefficients in plain double, each with its a-priori
// bound: the first part of every answer below.
struct plain_quadratic {
    dword f[3];  // f = o − c exactly (two_sum): f = fh + fl, |fl| ≤ u·|fh|
    double N = 0;  // (Σ|fh_i|)·(Σ|d_i|), which bounds Σ|d_i·fh_i| and each |fh_j·d_i| + |fh_i·d_j|
    double a = 0;  // |â − a| ≤ 3.01u·â
    double b = 0, err_b = 0;
    double ff = 0, rr = 0, C = 0, err_C = 0;  // Σfh², r², Ĉ = ff − rr
};

// The coefficients of g, when every input is in the filter range and the
// radius is not negative (an invalid case is never settled here; a zero
// direction has Δ′ = 0, whose sign no bound settles).
bool plain_quadratic_of(const ray_sphere<double>& g, plain_quadratic& q) {
    if (!in_filter_range(g) || !(g.radius >= 0)) return false;
    const double o[3] = {g.origin.x, g.origin.y, g.origin.z};
    const double d[3] = {g.direction.x, g.direction.y, g.direction.z};
    const double c[3] = {g.centre.x, g.centre.y, g.centre.z};
    const double r = g.radius;

    // The plain evaluations below use fh; fl is an input perturbation of relative size u.
#pragma GCC unroll 3
    for (int axis = 0; axis < 3; ++axis) q.f[axis] = two_sum(o[axis], -c[axis]);
    const double fh[3] = {q.f[0].h, q.f[1].h, q.f[2].h};
    q.N = ((std::fabs(fh[0]) + std::fabs(fh[1])) + std::fabs(fh[2])) *
          ((std::fabs(d[0]) + std::fabs(d[1])) + std::fabs(d[2]));

    // a = d·d: three squares and two sums of non-negative terms, at most 3
    // roundings each: |â − a| ≤ γ3·a, so a = â·(1 + η_a) with |η_a| ≤ 3.01u.
    q.a = (d[0] * d[0] + d[1] * d[1]) + d[2] * d[2];

    // b′ = d·f: a sum of three products (γ3 of Σ|d_i·fh_i|) plus the
    // perturbation d·fl (u of the same): |b̂ − b′| ≤ 5u·N.
    q.b = (d[0] * fh[0] + d[1] * fh[1]) + d[2] * fh[2];
    q.err_b = 5 * u * q.N;

    // C = f·f − r²: fh_i² through 4 roundings (square, two sums, the final
    // difference), r² through 2: γ4·(Σfh² + r²); f² = fh²·(1 + φ)², |φ| ≤ u,
    // adds (2u + u²)·Σfh²: |Ĉ − C| ≤ 7u·(Σfh² + r²).
    q.ff = (fh[0] * fh[0] + fh[1] * fh[1]) + fh[2] * fh[2];
    q.rr = r * r;
    q.C = q.ff - q.rr;
    q.err_C = 7 * u * (q.ff + q.rr);
    return true;
}

// A value in plain double within `err` of an exact one.
struct bounded_value {
    double value = 0, err = 0;
};

// Δ′ = b′² − aC as the formula reads, for its sign alone: it cancels where
// b′² and aC nearly agree (a far sphere, a near-tangent line), and there its
// bound leaves the sign open; elsewhere it settles it with two products.
// |b̂² − b′²| = |b̂ − b′|·|b̂ + b′| ≤ e_b·(2|b̂| + e_b); |âĈ − aC| ≤
// â·e_C·(1 + 3.01u) + 3.01u·â|Ĉ|; the roundings of b̂², âĈ and their
// difference add u·b̂², u·|âĈ| and u·|Δ̂|. With B = RN(b̂²) and A = RN(âĈ)
// (b̂² ≤ B(1 + u), â|Ĉ| ≤ |A|(1 + u)) that is at most
// e_b·(2|b̂| + e_b) + â·e_C + 2u·B + 5u·|A| + 2u·|Δ̂|, times 1 + 2^−18 for
// the factor 1 + 3.01u and the roundings of the bound's own evaluation.
bounded_value discriminant_as_written(const plain_quadratic& q) {
    const double B = q.b * q.b, A = q.a * q.C;
    const double value = B - A;
    const double err = (((q.err_b * (2 * std::fabs(q.b) + q.err_b) + q.a * q.err_C) + 2 * u * B) +
                        (5 * u * std::fabs(A) + 2 * u * std::fabs(value))) *
                       second_order;
    return {value, err};
}

// Δ′ = a·r² − |d × f|² (Lagrange's identity, as the double-word filter:
// b′² − aC cancels for far spheres, this form only near tangency).
// Each component x_k = fh_j·d_i − fh_i·d_j: two products and a
// difference (γ2 of |fh_j·d_i| + |fh_i·d_j|) plus the fl perturbation
// (u of the same): |x̂_k − x_k| ≤ 4u·N =: e_x.
// s = Σx̂_k² (γ3: ≤ 4u·ŝ), and |Σx̂_k² − Σx_k²| ≤ Σe_x·(2|x̂_k| + e_x).
// â·r̂² goes through 5 roundings of non-negative terms (γ5: ≤ 6u·âr̂²),
// and Δ̂ = RN(âr̂² − ŝ) adds u·|Δ̂| (2u with slack).
bounded_value discriminant_by_lagrange(const plain_quadratic& q, const double d[3]) {
    const double fh[3] = {q.f[0].h, q.f[1].h, q.f[2].h};
    const double x0 = fh[2] * d[1] - fh[1] * d[2];
    const double x1 = fh[0] * d[2] - fh[2] * d[0];
    const double x2 = fh[1] * d[0] - fh[0] * d[1];
    const double s = (x0 * x0 + x1 * x1) + x2 * x2;
    const double ar = q.a * q.rr;
    const double value = ar - s;
    const double err_x = 4 * u * q.N;
    const double err = (2 * u * std::fabs(value) + (6 * u * ar + 4 * u * s)) +
                       err_x * (2 * ((std::fabs(x0) + std::fabs(x1)) + std::fabs(x2)) + 3 * err_x);
    return {value, err};
}

// C = |o − c|² − r² exactly 0: an origin exactly on the sphere. Decided
// where f = o − c is exact in double (two_sum's low words all 0, as they are
// whenever o and c are within a factor 2 of each other on each axis, or one
// of them is 0): C is then the sum of the words of four error-free squares,
// eight doubles, and an expansion of them (expansion.h; no allocation) has
// its exact sign. In the filter range no square underflows. False where C is
// not 0 or f is not exact (the double-word filter, then C's own expansion,
// decide those).
// Out of line, from the case itself: inlined, or given the filters' words of
// f, it kept them live through the filters' common path, spilled to the
// stack (the class and signs on `uniform` about 1 ns slower).
[[gnu::noinline]] bool origin_exactly_on_sphere(const ray_sphere<double>& g) {
    double f[3];
    for (int axis = 0; axis < 3; ++axis) {
        const dword difference = two_sum(g.origin[axis], -g.centre[axis]);
        if (difference.l != 0) return false;
        f[axis] = difference.h;
    }
    const double r = g.radius;
    const expansion<8> C = (expansion_of(f[0]) * f[0] + expansion_of(f[1]) * f[1]) +
                           (expansion_of(f[2]) * f[2] - expansion_of(r) * r);
    return sign_of(C) == 0;
}

// static_class_and_signs' last question, where C is within its bound of 0:
// with C = 0 exactly the roots are 0 and −2b′/a, on `side` (−b′'s sign).
// Called last, so that the common path keeps nothing for it.
[[gnu::noinline]] bool signs_on_sphere(const ray_sphere<double>& g, int side, certified_signs& out) {
    if (!origin_exactly_on_sphere(g)) return false;
    out.root_sign[0] = side < 0 ? -1 : 0;
    out.root_sign[1] = side < 0 ? 0 : +1;
    return true;
}

// The sign of a bounded value, when it exceeds its bound strictly.
uncertain_sign certain_sign_of(const bounded_value& x) {
    if (x.value > x.err) return +1;
    if (x.value < -x.err) return -1;
    return std::nullopt;
}

}  // namespace

// The roots' signs follow from the coefficients once Δ′ > 0: their product
// is C/a and their sum −2b′/a (a > 0). C < 0: one behind, one in front.
// C > 0: both on the side of −b′ (b′ ≠ 0 then, as b′² > aC > 0). C = 0
// (an origin on the sphere, decided exactly): 0 and −2b′/a, on the side of
// −b′. Each sign is taken only where |Ĉ| exceeds e_C (or C is exactly 0),
// and for C ≥ 0 |b̂| exceeds e_b.
RAYVERIFY_CLONED_FOR_FMA bool static_class_and_signs(const ray_sphere<double>& g, certified_signs& out) {
    plain_quadratic q;
    if (!plain_quadratic_of(g, q)) return false;
    uncertain_sign discriminant_sign = certain_sign_of(discriminant_as_written(q));
    if (!discriminant_sign) {
        const double d[3] = {g.direction.x, g.direction.y, g.direction.z};
        discriminant_sign = certain_sign_of(discriminant_by_lagrange(q, d));
        if (!discriminant_sign) return false;  // a tangent, a near-tangent line, or a zero direction
    }
    out.discriminant_sign = *discriminant_sign;
    if (out.discriminant_sign < 0) return true;
    if (q.C < -q.err_C) {
        out.root_sign[0] = -1;
        out.root_sign[1] = +1;
        return true;
    }
    if (!(std::fabs(q.b) > q.err_b)) return false;
    const int side = q.b > 0 ? -1 : +1;
    if (q.C > q.err_C) {
        out.root_sign[0] = out.root_sign[1] = side;
        return true;
    }
    // C = 0 exactly (an origin on the sphere): the roots 0 and −2b′/a.
    return signs_on_sphere(g, side, out);
}

namespace {

// q = −(b′ + σ√Δ′) (σ the sign of b̂) and its relative bound, for Δ̂ > 0.
struct plain_q {
    bool positive_b = false;
    double q = 0, inverse_q = 0, relative_q = 0;
};

// √Δ′: |√Δ′ − √Δ̂| = |Δ′ − Δ̂|/(√Δ′ + √Δ̂) ≤ E_Δ/√Δ̂ ≤ (1 + u)·E_Δ/ŝq,
// plus the rounding of the square root, u·ŝq: computed as
// E_Δ·RN(1/ŝq)·(1 + 2^−50) + 2u·ŝq (the factor covers (1 + u) and the
// two roundings of E_Δ·RN(1/ŝq)).
// q = −(b′ + σ√Δ′), σ the sign of b̂, so that |q̂| = |b̂| + ŝq without
// cancellation: one rounding, |q̂ − q| ≤ 2u|q̂| + e_b + e_sq =: E_q. Its
// relative bound ε_q = E_q·|RN(1/q̂)| (within 2u of E_q/|q̂|, which the
// factor 1 + 2^−18 below covers) must be at most 2^−20 (q ≠ 0, and
// first order holds): false where it is not.
[[gnu::always_inline]] inline bool plain_q_of(const plain_quadratic& c, const bounded_value& discriminant, plain_q& out) {
    const double sq = std::sqrt(discriminant.value);
    const double err_sq = discriminant.err * (1 / sq) * (1 + 0x1p-50) + 2 * u * sq;
    out.positive_b = c.b >= 0;
    out.q = out.positive_b ? -(c.b + sq) : sq - c.b;
    out.inverse_q = 1 / out.q;
    out.relative_q = (2 * u * std::fabs(out.q) + c.err_b + err_sq) * std::fabs(out.inverse_q);
    return out.relative_q <= small;
}

// The root q/a as q̂·RN(1/â) (two roundings): with a = â(1 + η_a) and
// q = q̂(1 + η_q), |t* − t̂| ≤ |t̂|·(ε_q + 3.01u + 2u)·(1 + 2^−18).
[[gnu::always_inline]] inline approximation root_by_q(const plain_quadratic& c, const plain_q& q) {
    const double t = q.q * (1 / c.a);
    return {t, std::fabs(t) * (q.relative_q + 6 * u) * second_order};
}

// Each root rounded from its enclosure (a root of sign 0 is 0 exactly:
// RN(0) = +0); false where one does not round.
[[gnu::always_inline]] inline bool round_roots(precision prec, filtered_case& out) {
    for (int k = 0; k < 2; ++k) {
        if (*out.sign[k] == 0) {
            out.rounded[k] = 0.0;
            continue;
        }
        out.rounded[k] = oracle_internal::round_normalised(prec, out.roots[k]);
        if (!out.rounded[k]) out.rounded[k] = oracle_internal::round_enclosure(prec, out.roots[k], out.sign[k]);
        if (!out.rounded[k]) return false;
    }
    return true;
}

// The front root's hit point: o exactly where d's coordinate is 0 (RN(0)
// is +0), else from the coordinate's enclosure; a coordinate that does
// not settle there gets the double-word filter's rounding from the same
// root enclosure, and if that fails too, the double-word filter runs
// from the start (its own root enclosures may be tighter).
[[gnu::always_inline]] inline bool round_front_hit_point(const ray_sphere<double>& g, precision prec,
                                                         filtered_case& out) {
    const int front = *out.sign[0] > 0 ? 0 : *out.sign[1] > 0 ? 1 : -1;
    if (front < 0) return true;
    for (int axis = 0; axis < 3; ++axis) {
        const double o = g.origin[axis], d = g.direction[axis];
        if (d == 0) {
            out.hit[axis] = rounded_to(prec, o) + 0.0;
            continue;
        }
        const enclosure h = hit_enclosure(o, d, out.roots[front]);
        out.hit[axis] = oracle_internal::round_normalised(prec, h);
        if (!out.hit[axis]) out.hit[axis] = oracle_internal::round_enclosure(prec, h, sign_of(h));
        if (!out.hit[axis]) out.hit[axis] = round_hit_coordinate(prec, g, out.roots[front], axis);
        if (!out.hit[axis]) return false;
    }
    return true;
}

// static_filter_case where Ĉ is within its bound of 0 (Δ̂ > 0 certified, q
// settled): an origin exactly on the sphere (a ray spawned from a point of
// its surface), C = 0 decided exactly (origin_exactly_on_sphere). Its roots
// are then 0 exactly (C/q) and q/a = −2b′/a (q = −2b′ when C = 0; b′ ≠ 0, as
// Δ′ = b′² > 0), q/a corrected and rounded as any root. An origin near the
// sphere is left to the double-word filter, then to C's expansion.
// Its own function, called last, from the case itself (the coefficients
// formed again: the same operations, the same values): so the common path
// keeps nothing live for it. A cloned function is not inlined (g++ calls the
// clone of the caller's target), so it needs no noinline, which clang
// rejects beside target_clones.
RAYVERIFY_CLONED_FOR_FMA bool static_filter_on_sphere(const ray_sphere<double>& g, precision prec,
                                                      filtered_case& out, oracle_depth depth) {
    if (!origin_exactly_on_sphere(g)) return false;
    plain_quadratic coefficients;
    plain_quadratic_of(g, coefficients);
    const double d[3] = {g.direction.x, g.direction.y, g.direction.z};
    plain_q q;
    if (!plain_q_of(coefficients, discriminant_by_lagrange(coefficients, d), q)) return false;
    const int zero = q.positive_b ? 1 : 0;  // q < 0 when b̂ ≥ 0: q/a the near root, 0 the far one
    out.sign[zero] = 0;
    out.sign[1 - zero] = q.positive_b ? -1 : +1;
    if (depth == oracle_depth::class_and_signs) return true;
    // q/a corrected in both lanes (the same operations as two roots').
    const approximation by_q = root_by_q(coefficients, q);
    enclosure lanes[2];
    if (!corrected(by_q, by_q, coefficients.a, coefficients.f, d, two_prod(g.radius, g.radius), lanes)) return false;
    out.roots[1 - zero] = lanes[near_lane];
    out.roots[zero] = enclosure{0, 0, 0};
    if (!round_roots(prec, out)) return false;
    return depth == oracle_depth::roots_rounded || round_front_hit_point(g, prec, out);
}

}  // namespace

RAYVERIFY_CLONED_FOR_FMA bool static_filter_case(const ray_sphere<double>& g, precision prec, filtered_case& out,
                                                  oracle_depth depth) {
    if (depth == oracle_depth::class_and_signs) {
        certified_signs signs;
        if (!static_class_and_signs(g, signs)) return false;
        out.discriminant_sign = signs.discriminant_sign;
        if (signs.discriminant_sign > 0)
            for (int k = 0; k < 2; ++k) out.sign[k] = signs.root_sign[k];
        return true;
    }
    plain_quadratic coefficients;
    if (!plain_quadratic_of(g, coefficients)) return false;
    const double d[3] = {g.direction.x, g.direction.y, g.direction.z};
    const double r = g.radius;
    const dword(&f)[3] = coefficients.f;
    const double a = coefficients.a, C = coefficients.C, err_C = coefficients.err_C;
    const bounded_value lagrange = discriminant_by_lagrange(coefficients, d);

    // Class: the sign of Δ′ where |Δ̂| exceeds its bound.
    out.discriminant_sign = certain_sign_of(lagrange);
    if (!out.discriminant_sign) return false;
    if (*out.discriminant_sign < 0) return true;

    plain_q q;
    if (!plain_q_of(coefficients, lagrange, q)) return false;
    // C's sign decides the sign of C/q: |Ĉ| must exceed 2^20·E_C. Where it
    // does not, an origin exactly on the sphere is settled apart.
    if (!(err_C <= small * std::fabs(C))) return static_filter_on_sphere(g, prec, out, depth);

    // The roots q/a (root_by_q) and C/q as Ĉ·RN(1/q̂) (two roundings): with
    // C = Ĉ(1 + η_C), |t* − t̂| ≤ (|t̂|·(ε_q + 2u) + E_C/|q̂|)·(1 + 2^−18)
    // (|t̂|·ε_C = E_C/|q̂| to first order, E_C·|RN(1/q̂)| within 2u of it).
    const double t_c = C * q.inverse_q;
    const approximation by_q = root_by_q(coefficients, q);
    const approximation by_c{t_c, (std::fabs(t_c) * (q.relative_q + 2 * u) + err_C * std::fabs(q.inverse_q)) *
                                      second_order};
    // σ = +1: q < 0 and q/a is the near root; σ = −1: q > 0 and q/a is the far root.
    const approximation& near = q.positive_b ? by_q : by_c;
    const approximation& far = q.positive_b ? by_c : by_q;
    const int sign_q = q.positive_b ? -1 : +1;
    const int sign_c = (C > 0 ? 1 : -1) * sign_q;
    out.sign[0] = q.positive_b ? sign_q : sign_c;
    out.sign[1] = q.positive_b ? sign_c : sign_q;
    if (depth == oracle_depth::class_and_signs) return true;

    // Both roots corrected once, together, and each rounded from its enclosure.
    const dword r_squared = two_prod(r, r);
    if (!corrected(near, far, a, f, d, r_squared, out.roots)) return false;
    if (!round_roots(prec, out)) return false;
    return depth == oracle_depth::roots_rounded || round_front_hit_point(g, prec, out);
}

}  // namespace rayverify::oracle_internal
