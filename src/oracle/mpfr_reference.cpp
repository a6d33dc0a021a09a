// Independent reference oracle: MPFR only, no CGAL, no code shared with
// oracle.cpp. Written to be obviously right rather than fast.
//
// Why the precision suffices. A finite double is m·2^k with |m| < 2^53 and
// −1074 ≤ k ≤ 971, so every input has its bits between 2^−1074 and 2^1024.
// f = o − c then spans at most 2100 bits, products of two such values at most
// 4200 bits, and b′², a·C and Δ′ = b′² − aC at most 8400 + a few bits. With a
// working precision of 12000 bits every coefficient and Δ′ are therefore
// computed exactly, and the class (the sign of Δ′) is exact. A root is then
// either exact (√Δ′ exact and the division exact, which MPFR reports) or
// carries a relative error below 2^−11990, far too small to move a rounding
// decision except for a root within that distance of a rounding boundary.
#include "oracle/mpfr_reference.h"

#include <mpfr.h>

namespace rayverify {
namespace {

constexpr mpfr_prec_t working_precision = 12000;

struct mp {
    mpfr_t v;
    // mpfr_init2 leaves NaN; the accumulators below start from +0.
    mp() {
        mpfr_init2(v, working_precision);
        mpfr_set_zero(v, +1);
    }
    explicit mp(double x) : mp() { mpfr_set_d(v, x, MPFR_RNDN); }
    ~mp() { mpfr_clear(v); }
    mp(const mp&) = delete;
    mp& operator=(const mp&) = delete;
};

// An exact zero is +0, as RN(0) in the oracle; the sign of an MPFR zero here
// is an accident of the operations (−b′ − √Δ′ with b′ = +0 gives −0). A
// nonzero value that underflows keeps its sign (−0 for a tiny negative root).
double to_precision(mp& x, precision prec) {
    if (mpfr_zero_p(x.v)) mpfr_set_zero(x.v, +1);
    if (prec == precision::binary32) return static_cast<double>(mpfr_get_flt(x.v, MPFR_RNDN));
    return mpfr_get_d(x.v, MPFR_RNDN);
}

}  // namespace

reference_answer solve_with_mpfr_reference(const ray_sphere<double>& g, precision prec) {
    const double o[3] = {g.origin.x, g.origin.y, g.origin.z};
    const double d[3] = {g.direction.x, g.direction.y, g.direction.z};
    const double c[3] = {g.centre.x, g.centre.y, g.centre.z};

    mp a, b_prime, C, term, f;
    for (int i = 0; i < 3; ++i) {
        mp oi(o[i]), di(d[i]), ci(c[i]);
        mpfr_sub(f.v, oi.v, ci.v, MPFR_RNDN);
        mpfr_fma(a.v, di.v, di.v, a.v, MPFR_RNDN);
        mpfr_fma(b_prime.v, di.v, f.v, b_prime.v, MPFR_RNDN);
        mpfr_fma(C.v, f.v, f.v, C.v, MPFR_RNDN);
    }
    mp r(g.radius);
    mpfr_sqr(term.v, r.v, MPFR_RNDN);
    mpfr_sub(C.v, C.v, term.v, MPFR_RNDN);

    mp disc;
    mpfr_sqr(disc.v, b_prime.v, MPFR_RNDN);
    mpfr_mul(term.v, a.v, C.v, MPFR_RNDN);
    mpfr_sub(disc.v, disc.v, term.v, MPFR_RNDN);

    reference_answer answer;
    const int s = mpfr_sgn(disc.v);
    answer.cls = s < 0 ? line_class::miss : (s == 0 ? line_class::tangent : line_class::two_hit);
    if (answer.cls == line_class::miss) return answer;

    mp root, near, far, minus_b;
    const bool root_exact = mpfr_sqrt(root.v, disc.v, MPFR_RNDN) == 0;
    mpfr_neg(minus_b.v, b_prime.v, MPFR_RNDN);
    if (root_exact) {
        // Numerators are exact; each quotient is correctly rounded (exact when dyadic).
        mpfr_sub(near.v, minus_b.v, root.v, MPFR_RNDN);
        mpfr_div(near.v, near.v, a.v, MPFR_RNDN);
        mpfr_add(far.v, minus_b.v, root.v, MPFR_RNDN);
        mpfr_div(far.v, far.v, a.v, MPFR_RNDN);
    } else if (mpfr_sgn(b_prime.v) > 0) {
        // −b′ − √Δ′ has no cancellation; the far root from t_near·t_far = C/a.
        mpfr_sub(near.v, minus_b.v, root.v, MPFR_RNDN);
        mpfr_div(near.v, near.v, a.v, MPFR_RNDN);
        mpfr_mul(term.v, a.v, near.v, MPFR_RNDN);
        mpfr_div(far.v, C.v, term.v, MPFR_RNDN);
    } else {
        mpfr_add(far.v, minus_b.v, root.v, MPFR_RNDN);
        mpfr_div(far.v, far.v, a.v, MPFR_RNDN);
        mpfr_mul(term.v, a.v, far.v, MPFR_RNDN);
        mpfr_div(near.v, C.v, term.v, MPFR_RNDN);
    }
    answer.near_sign = mpfr_sgn(near.v);
    answer.far_sign = mpfr_sgn(far.v);
    answer.near_rounded = to_precision(near, prec);
    answer.far_rounded = to_precision(far, prec);
    return answer;
}

}  // namespace rayverify
