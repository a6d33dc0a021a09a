/* An intersector that hands over what it knows of its own error, as pbrt-v4
 * does: every quantity is an interval [lo, hi] that encloses the exact value
 * (each operation rounded to nearest, then widened one step outward with
 * nextafter), so each returned t comes with an interval that must contain the
 * exact root, and the hit point with an error bound per coordinate. rayverify
 * checks both against the exact answer (unsound_bound when one leaves the
 * exact value out) and reports the bounds' width in ULPs. Version 2.
 *
 *   f = o − c, a = d·d, b′ = d·f, C = f·f − r², Δ = b′² − aC;  miss when Δ.hi < 0
 *   q = −(b′ + s√Δ) with s the sign of b′'s midpoint;  roots q/a and C/q
 *   t = the midpoint of the first root interval whose midpoint lies in (tmin, tmax);
 *   overlapping root intervals are both claimed as their hull (near a tangent
 *   the two enclosures cannot be told apart)
 *   point = o + t·d over the interval, returned as its midpoint ± half its width
 *
 * Contract: query=nearest_hit,range=interval (open ends), the far root from
 * inside, a tangent a hit, any direction length; t_bounds, hit_point and
 * point_error given. Runs in float and in double. */
#include <math.h>

#include "rayverify_plugin.h"

RAYVERIFY_PLUGIN_EXPORT const rayverify_plugin_info_v2* rayverify_plugin_describe_v2(void) {
    static const rayverify_plugin_info_v2 info = {
        RAYVERIFY_PLUGIN_ABI_VERSION_2,
        "bounds_sphere",
        "interval arithmetic, as pbrt-v4 (examples/plugin_v2/bounds_sphere.c)",
        "in intervals: b' = d.f, C = f.f - r^2, q = -(b' + s sqrt(b'^2 - aC)), t in q/a, C/q; point o + t d",
        "plain C; outward rounding by nextafter after each rounded operation",
        "query=nearest_hit,range=interval,t_bounds=yes,hit_point=yes,point_error=yes",
        NULL,
        RAYVERIFY_FLOAT | RAYVERIFY_DOUBLE};
    return &info;
}

/* One interval type and its operations per precision T; NEXT is nextafter or nextafterf. */
#define INTERVAL_OPS(T, P, NEXT, SQRT, BIG)                                                                   \
    typedef struct {                                                                                          \
        T lo, hi;                                                                                             \
    } P##_ival;                                                                                               \
    static P##_ival P##_exact(T x) {                                                                          \
        P##_ival r = {x, x};                                                                                  \
        return r;                                                                                             \
    }                                                                                                         \
    static P##_ival P##_add(P##_ival a, P##_ival b) {                                                         \
        P##_ival r = {NEXT(a.lo + b.lo, -BIG), NEXT(a.hi + b.hi, BIG)};                                       \
        return r;                                                                                             \
    }                                                                                                         \
    static P##_ival P##_sub(P##_ival a, P##_ival b) {                                                         \
        P##_ival r = {NEXT(a.lo - b.hi, -BIG), NEXT(a.hi - b.lo, BIG)};                                       \
        return r;                                                                                             \
    }                                                                                                         \
    static P##_ival P##_mul(P##_ival a, P##_ival b) {                                                         \
        const T p[4] = {a.lo * b.lo, a.lo * b.hi, a.hi * b.lo, a.hi * b.hi};                                  \
        T lo = p[0], hi = p[0];                                                                               \
        int k;                                                                                                \
        P##_ival r;                                                                                           \
        for (k = 1; k < 4; ++k) {                                                                             \
            if (p[k] < lo) lo = p[k];                                                                         \
            if (p[k] > hi) hi = p[k];                                                                         \
        }                                                                                                     \
        r.lo = NEXT(lo, -BIG);                                                                                \
        r.hi = NEXT(hi, BIG);                                                                                 \
        return r;                                                                                             \
    }                                                                                                         \
    static P##_ival P##_div(P##_ival a, P##_ival b) {                                                         \
        P##_ival r = {-BIG, BIG};                                                                             \
        if (b.lo <= 0 && b.hi >= 0) return r;                                                                 \
        {                                                                                                     \
            const T q[4] = {a.lo / b.lo, a.lo / b.hi, a.hi / b.lo, a.hi / b.hi};                              \
            T lo = q[0], hi = q[0];                                                                           \
            int k;                                                                                            \
            for (k = 1; k < 4; ++k) {                                                                         \
                if (q[k] < lo) lo = q[k];                                                                     \
                if (q[k] > hi) hi = q[k];                                                                     \
            }                                                                                                 \
            r.lo = NEXT(lo, -BIG);                                                                            \
            r.hi = NEXT(hi, BIG);                                                                             \
        }                                                                                                     \
        return r;                                                                                             \
    }                                                                                                         \
    static P##_ival P##_sqrt(P##_ival a) { /* a.hi >= 0 */                                                    \
        P##_ival r;                                                                                           \
        r.lo = a.lo > 0 ? NEXT(SQRT(a.lo), 0) : 0;                                                            \
        r.hi = NEXT(SQRT(a.hi), BIG);                                                                         \
        return r;                                                                                             \
    }                                                                                                         \
    static P##_ival P##_dot(const T x[3], const P##_ival y[3]) {                                              \
        P##_ival s = P##_mul(P##_exact(x[0]), y[0]);                                                          \
        s = P##_add(s, P##_mul(P##_exact(x[1]), y[1]));                                                       \
        return P##_add(s, P##_mul(P##_exact(x[2]), y[2]));                                                    \
    }                                                                                                         \
    static T P##_mid(P##_ival a) { return a.lo / 2 + a.hi / 2; }

INTERVAL_OPS(double, d, nextafter, sqrt, HUGE_VAL)
INTERVAL_OPS(float, f, nextafterf, sqrtf, HUGE_VALF)

#define BOUNDS_BODY(T, P, NEXT, BIG)                                                                                   \
    for (size_t i = 0; i < n; ++i) {                                                                          \
        const T* o = cases[i].origin;                                                                         \
        const T* d = cases[i].direction;                                                                      \
        const T* c = cases[i].centre;                                                                         \
        const P##_ival f[3] = {P##_sub(P##_exact(o[0]), P##_exact(c[0])), P##_sub(P##_exact(o[1]), P##_exact(c[1])), \
                               P##_sub(P##_exact(o[2]), P##_exact(c[2]))};                                    \
        const P##_ival dd[3] = {P##_exact(d[0]), P##_exact(d[1]), P##_exact(d[2])};                           \
        const P##_ival r = P##_exact(cases[i].radius);                                                        \
        const P##_ival a = P##_dot(d, dd), b = P##_dot(d, f);                                                 \
        const P##_ival C = P##_sub(P##_add(P##_add(P##_mul(f[0], f[0]), P##_mul(f[1], f[1])), P##_mul(f[2], f[2])), \
                                   P##_mul(r, r));                                                            \
        const P##_ival disc = P##_sub(P##_mul(b, b), P##_mul(a, C));                                          \
        answers[i].count = 0;                                                                                 \
        if (disc.hi < 0) continue;                                                                            \
        {                                                                                                     \
            const P##_ival root = P##_sqrt(disc);                                                             \
            const P##_ival q = P##_mid(b) < 0 ? P##_sub(root, b) : P##_sub(P##_exact(0), P##_add(b, root));   \
            P##_ival t0 = P##_div(q, a), t1 = P##_div(C, q), hit;                                             \
            T m0, m1, t;                                                                                      \
            int k;                                                                                            \
            if (P##_mid(t0) > P##_mid(t1)) {                                                                  \
                const P##_ival swap = t0;                                                                     \
                t0 = t1;                                                                                      \
                t1 = swap;                                                                                    \
            }                                                                                                 \
            if (t0.hi >= t1.lo) { /* overlapping enclosures: claim their hull for both */                     \
                t0.lo = t0.lo < t1.lo ? t0.lo : t1.lo;                                                        \
                t0.hi = t0.hi > t1.hi ? t0.hi : t1.hi;                                                        \
                t1 = t0;                                                                                      \
            }                                                                                                 \
            m0 = P##_mid(t0);                                                                                 \
            m1 = P##_mid(t1);                                                                                 \
            if (m0 > cases[i].tmin && m0 < cases[i].tmax)                                                     \
                hit = t0;                                                                                     \
            else if (m1 > cases[i].tmin && m1 < cases[i].tmax)                                                \
                hit = t1;                                                                                     \
            else                                                                                              \
                continue;                                                                                     \
            t = P##_mid(hit);                                                                                 \
            answers[i].count = 1;                                                                             \
            answers[i].t[0] = answers[i].t[1] = t;                                                            \
            answers[i].t_lower[0] = answers[i].t_lower[1] = hit.lo;                                           \
            answers[i].t_upper[0] = answers[i].t_upper[1] = hit.hi;                                           \
            for (k = 0; k < 3; ++k) {                                                                         \
                const P##_ival p = P##_add(P##_exact(o[k]), P##_mul(hit, P##_exact(d[k])));                   \
                const T mid = P##_mid(p);                                                                     \
                const T above = p.hi - mid, below = mid - p.lo;                                               \
                answers[i].point[k] = mid;                                                                    \
                answers[i].point_error[k] = NEXT(above > below ? above : below, BIG);                        \
            }                                                                                                 \
        }                                                                                                     \
    }

RAYVERIFY_PLUGIN_EXPORT void rayverify_plugin_intersect_batch_double(const rayverify_case_double* cases,
                                                                     rayverify_answer_double* answers, size_t n) {
    BOUNDS_BODY(double, d, nextafter, HUGE_VAL)
}

RAYVERIFY_PLUGIN_EXPORT void rayverify_plugin_intersect_batch_float(const rayverify_case_float* cases,
                                                                    rayverify_answer_float* answers, size_t n) {
    BOUNDS_BODY(float, f, nextafterf, HUGE_VALF)
}
