/* rayverify plugin ABI: your own ray–sphere intersector, audited by rayverify.
 *
 * Pure C (C89 types, no C++, no CGAL): implement it in a shared library and
 * run `rayverify audit --plugin ./libmine.so` (or `gate`, `explain`).
 *
 *   rayverify_plugin_describe          required: name and contract
 *   rayverify_plugin_intersect_double  required: the intersector in double
 *   rayverify_plugin_intersect_float   optional: the same in float
 *
 * A plugin is audited exactly like a built-in variant: a float function
 * receives the case's inputs rounded to float and is judged against the exact
 * answer for those float inputs. Whatever it returns is judged, case by case:
 * a count its contract does not allow, roots out of order or NaN roots are
 * verdicts (malformed_output, non_finite), not errors. A plugin that cannot be
 * loaded (missing file or symbol, another ABI version) is an input error.
 * A plugin that crashes takes rayverify down, naming the case it was on; with
 * --isolate it runs in a child process, and a crash, an exit() or a call
 * longer than --plugin-timeout is an input error naming the case.
 *
 * ABI version 1. rayverify refuses a plugin whose describe() reports another
 * version; abi_version stays the first member of rayverify_plugin_info in
 * every version so that the check itself never breaks. */
#ifndef RAYVERIFY_PLUGIN_H
#define RAYVERIFY_PLUGIN_H

#define RAYVERIFY_PLUGIN_ABI_VERSION 1

/* Which answer the intersector gives (rayverify_plugin_info.query). */
#define RAYVERIFY_LINE_ROOTS 0     /* both roots of the line o + t·d, any sign, t0 <= t1;
                                      count 0 miss, 1 tangent reported, 2 two roots */
#define RAYVERIFY_NEAREST_ON_RAY 1 /* the nearest hit with t >= 0 in roots[0]; count 0 or 1 */
#define RAYVERIFY_ANY_HIT_IN_INTERVAL 2 /* count 1 when some root lies in the open interval
                                           (tmin, tmax), else 0; roots unused */
#define RAYVERIFY_NEAREST_IN_INTERVAL 3 /* the nearest root in (tmin, tmax) in roots[0]; count 0 or 1 */

#if defined(_WIN32)
#define RAYVERIFY_PLUGIN_EXPORT __declspec(dllexport)
#else
#define RAYVERIFY_PLUGIN_EXPORT __attribute__((visibility("default")))
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* What the plugin is and what it promises. Returned by describe(); must stay
 * valid while the library is loaded (a static object is the usual way). */
typedef struct rayverify_plugin_info {
    int abi_version;            /* RAYVERIFY_PLUGIN_ABI_VERSION; always the first member */
    const char* name;           /* one token, e.g. "mine": used in reports and baselines */
    const char* citation;       /* where the formula comes from; may be NULL */
    const char* formula;        /* one line in the paper's notation; may be NULL */
    int query;                  /* RAYVERIFY_LINE_ROOTS or RAYVERIFY_NEAREST_ON_RAY */
    int assumes_unit_direction; /* nonzero: |d| = 1 is assumed; other cases are not scored */
    int reports_tangent;        /* nonzero: may return count 1 for a tangent line */
    int clamps_to_zero;         /* NEAREST_ON_RAY only: an inside origin gives t = 0 */
    const char* tangent_rule;   /* when it reports a tangent, e.g. "disc == 0"; may be NULL */
} rayverify_plugin_info;

/* Intersect the ray o + t·d with the sphere |p − c| = r. Write the roots to
 * roots[0] <= roots[1] (for a tangent, both; for NEAREST_ON_RAY and
 * NEAREST_IN_INTERVAL, roots[0]) and return the hit count. rayverify passes
 * the interval its contract is judged on: tmin = -INFINITY, tmax = +INFINITY
 * for LINE_ROOTS and tmin = 0 for NEAREST_ON_RAY (a plugin may ignore them);
 * for the two *_IN_INTERVAL kinds, the case's or the ray's own interval,
 * (0, +INFINITY) when it has none, which the plugin must honour. Called from
 * one thread. */
typedef int (*rayverify_intersect_double_fn)(const double origin[3], const double direction[3],
                                             const double centre[3], double radius, double tmin,
                                             double tmax, double roots[2]);
typedef int (*rayverify_intersect_float_fn)(const float origin[3], const float direction[3],
                                            const float centre[3], float radius, float tmin, float tmax,
                                            float roots[2]);
typedef const rayverify_plugin_info* (*rayverify_describe_fn)(void);

/* The symbols rayverify looks up. Declared here so that a plugin including
 * this header gets its definitions type-checked. */
RAYVERIFY_PLUGIN_EXPORT const rayverify_plugin_info* rayverify_plugin_describe(void);
RAYVERIFY_PLUGIN_EXPORT int rayverify_plugin_intersect_double(const double origin[3], const double direction[3],
                                                              const double centre[3], double radius,
                                                              double tmin, double tmax, double roots[2]);
RAYVERIFY_PLUGIN_EXPORT int rayverify_plugin_intersect_float(const float origin[3], const float direction[3],
                                                             const float centre[3], float radius, float tmin,
                                                             float tmax, float roots[2]);

#ifdef __cplusplus
}
#endif

#endif /* RAYVERIFY_PLUGIN_H */
