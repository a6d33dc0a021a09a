/* rayverify plugin ABI: your own ray–sphere intersector, audited by rayverify.
 *
 * Pure C (C89 types, no C++, no CGAL): implement it in a shared library and
 * run `rayverify audit --plugin ./libmine.so` (or `gate`, `explain`).
 *
 * Two versions; a library implements one of them.
 *
 * Version 2 (a library that exports rayverify_plugin_describe_v2):
 *   rayverify_plugin_describe_v2             required: name, contract spec, precisions
 *   rayverify_plugin_intersect_batch_float   when precisions has RAYVERIFY_FLOAT
 *   rayverify_plugin_intersect_batch_double  when precisions has RAYVERIFY_DOUBLE
 * The contract is the spec string `rayverify variants` prints (query, range,
 * ends, inside, tangent, faces, unit_direction, ... ; see docs/plugins.md):
 * every contract rayverify can judge, the engines' included (a point answer,
 * segments, no tmin, closed ends, front faces, inside a miss or clamped). A
 * plugin runs in float only, double only or both, and only those are
 * audited. Beside t it may hand over the outputs its spec names: an interval
 * for each t (t_bounds), the hit point (hit_point) and an error bound for it
 * (point_error), the normal (normal); each is checked against the exact
 * answer (a bound that leaves out the exact value is the verdict
 * unsound_bound). One call answers an array of cases.
 *
 * Version 1 (rayverify_plugin_describe): the original fields below; still
 * loaded as before.
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
 * rayverify refuses a plugin whose describe function reports another version
 * than its struct's; abi_version is the first member of every version's
 * struct so that the check itself never breaks. */
#ifndef RAYVERIFY_PLUGIN_H
#define RAYVERIFY_PLUGIN_H

#include <stddef.h>

/* The version rayverify_plugin_info (version 1) declares; unchanged so that
 * a version 1 plugin rebuilt against this header still says 1. */
#define RAYVERIFY_PLUGIN_ABI_VERSION 1
/* The version rayverify_plugin_info_v2 declares. */
#define RAYVERIFY_PLUGIN_ABI_VERSION_2 2

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
    int query;                  /* which question it answers (examples/templates/ has one per kind):
                                   RAYVERIFY_LINE_ROOTS           both roots of the line, any sign
                                                                  (examples/plugin_rtg/rtg_sphere.c)
                                   RAYVERIFY_NEAREST_ON_RAY       the nearest root with t >= 0
                                   RAYVERIFY_NEAREST_IN_INTERVAL  the nearest root in (tmin, tmax): a path
                                                                  tracer's hit(), e.g. "Ray Tracing in One
                                                                  Weekend" (templates/nearest_in_interval.c)
                                   RAYVERIFY_ANY_HIT_IN_INTERVAL  whether a root lies in (tmin, tmax): a
                                                                  shadow ray (templates/any_hit.c)
                                   An audit whose answers fit another kind better says so. */
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

/* ---- Version 2 ------------------------------------------------------------ */

/* rayverify_plugin_info_v2.precisions: a bit set. */
#define RAYVERIFY_FLOAT 1
#define RAYVERIFY_DOUBLE 2

/* What a version 2 plugin is and what it promises. */
typedef struct rayverify_plugin_info_v2 {
    int abi_version;          /* RAYVERIFY_PLUGIN_ABI_VERSION_2; always the first member */
    const char* name;         /* one token: used in reports and baselines */
    const char* citation;     /* where the formula comes from; may be NULL */
    const char* formula;      /* one line in the paper's notation; may be NULL */
    const char* build;        /* the build it models (precisions, FMAs, flags); may be NULL */
    const char* contract;     /* the contract spec, e.g. "query=nearest_hit,range=interval,ends=[]";
                                 keys not given keep their defaults (query=line_roots, range=ray,
                                 ends=(), inside=far_root, tangent=hit, faces=both, unit_direction=no) */
    const char* tangent_rule; /* line_roots with reports_tangent=yes: when; may be NULL */
    int precisions;           /* RAYVERIFY_FLOAT, RAYVERIFY_DOUBLE or both */
} rayverify_plugin_info_v2;

/* One case: the ray o + t·d, the sphere |p − c| = r, and the range the
 * contract is asked on: range=ray: tmin = 0, tmax = +INFINITY (line_roots:
 * tmin = -INFINITY); interval and segment: the case's own (tmin, tmax),
 * (0, +INFINITY) when it has none; tmax_only: tmax (tmin = 0, to be ignored).
 * A segment plugin maps (tmin, tmax) to its segment itself; for tmax =
 * +INFINITY docs/plugins.md gives the mapping rayverify's engines use. */
typedef struct rayverify_case_double {
    double origin[3], direction[3], centre[3], radius, tmin, tmax;
} rayverify_case_double;
typedef struct rayverify_case_float {
    float origin[3], direction[3], centre[3], radius, tmin, tmax;
} rayverify_case_float;

/* One answer. rayverify fills every member with NaN and count with -1
 * before the call; the plugin writes count and what its contract names:
 *   count         line_roots: 0 miss, 1 tangent, 2 two roots; nearest_hit, any_hit: 0 or 1
 *   t[2]          the roots, t[0] <= t[1] (nearest_hit: t[0]; answer=point: unused)
 *   t_lower[2], t_upper[2]   t_bounds=yes: t[i] lies in [t_lower[i], t_upper[i]]
 *   point[3]      hit_point=yes or answer=point: the hit point
 *   point_error[3]           point_error=yes: |exact − point[k]| <= point_error[k];
 *                            point_error=surface: that box holds a point of the sphere
 *   normal[3]     normal=yes: the normal at the hit, any length */
typedef struct rayverify_answer_double {
    int count;
    double t[2], t_lower[2], t_upper[2], point[3], point_error[3], normal[3];
} rayverify_answer_double;
typedef struct rayverify_answer_float {
    int count;
    float t[2], t_lower[2], t_upper[2], point[3], point_error[3], normal[3];
} rayverify_answer_float;

typedef const rayverify_plugin_info_v2* (*rayverify_describe_v2_fn)(void);
typedef void (*rayverify_batch_double_fn)(const rayverify_case_double* cases, rayverify_answer_double* answers,
                                          size_t count);
typedef void (*rayverify_batch_float_fn)(const rayverify_case_float* cases, rayverify_answer_float* answers,
                                         size_t count);

/* Answer cases[0..count) into answers[0..count), in one call (an audit
 * passes up to a few thousand cases at once; explain and hunt pass one).
 * Called from one thread. */
RAYVERIFY_PLUGIN_EXPORT const rayverify_plugin_info_v2* rayverify_plugin_describe_v2(void);
RAYVERIFY_PLUGIN_EXPORT void rayverify_plugin_intersect_batch_double(const rayverify_case_double* cases,
                                                                     rayverify_answer_double* answers, size_t count);
RAYVERIFY_PLUGIN_EXPORT void rayverify_plugin_intersect_batch_float(const rayverify_case_float* cases,
                                                                    rayverify_answer_float* answers, size_t count);

/* ---- Version 2: segments, as physics engines cast them ------------------- */

/* A plugin whose contract says cast=segment (with range=interval) exports
 * these in place of the two batch functions above: it is handed each
 * segment case's end points exactly as the corpus gives them (rounded to its
 * precision, nothing computed from them: no wrapper of yours rounds
 * p1 = o + L·d) and answers t along p1 − p0, the fraction f of the segment
 * (0 at p0, 1 at p1), on f in [0, 1] with the ends its contract states:
 * e.g. "query=nearest_hit,range=interval,ends=[],inside=clamp,cast=segment".
 * The answer struct is the one above (t[0] the fraction for nearest_hit,
 * the point for answer=point). rayverify judges it against the exact
 * segment between the two ends (its direction p1 − p0 taken exactly, not
 * rounded), so that every verdict is about the segment the function
 * received. A cast=segment plugin runs on segment cases only (a corpus line
 * "id family segment p0x p0y p0z p1x p1y p1z cx cy cz r"); ray cases are not
 * scored. examples/templates/segment.c and segment.cpp are the templates. */
typedef struct rayverify_segment_double {
    double p0[3], p1[3], centre[3], radius;
} rayverify_segment_double;
typedef struct rayverify_segment_float {
    float p0[3], p1[3], centre[3], radius;
} rayverify_segment_float;

typedef void (*rayverify_segments_double_fn)(const rayverify_segment_double* segments,
                                             rayverify_answer_double* answers, size_t count);
typedef void (*rayverify_segments_float_fn)(const rayverify_segment_float* segments, rayverify_answer_float* answers,
                                            size_t count);
RAYVERIFY_PLUGIN_EXPORT void rayverify_plugin_intersect_segments_double(const rayverify_segment_double* segments,
                                                                        rayverify_answer_double* answers,
                                                                        size_t count);
RAYVERIFY_PLUGIN_EXPORT void rayverify_plugin_intersect_segments_float(const rayverify_segment_float* segments,
                                                                       rayverify_answer_float* answers, size_t count);

/* ---- Either version: thread safety --------------------------------------- */

/* Optional. Nonzero: the intersect (or batch) functions may be called from
 * several threads at once (they keep no state, or guard it), and an audit
 * runs on every thread it is given. Absent or 0: every call comes from one
 * thread, as above, and an audit says so and runs on one thread. Ignored
 * with --isolate, where one child process answers one call at a time. A
 * function, not a field, so that neither version's struct changes. */
typedef int (*rayverify_thread_safe_fn)(void);
RAYVERIFY_PLUGIN_EXPORT int rayverify_plugin_thread_safe(void);

/* ---- Either version: the library a plugin calls ------------------------- */

/* Optional. A plugin that wraps a library (an engine as its package installs
 * it: Embree, Bullet, ...) may say which version of it answered, as the
 * library itself reports it at run time (e.g. "3.13.5"); rayverify records it
 * in reports and `rayverify engines` prints it. NULL or absent: not known. */
typedef const char* (*rayverify_library_version_fn)(void);
RAYVERIFY_PLUGIN_EXPORT const char* rayverify_plugin_library_version(void);

/* Optional. What of the library's own set-up decides its answers and can
 * differ between machines running the same binary, as one line: the kernel
 * a library picked for this CPU (e.g. "kernel avx2, Embree's choice for this
 * CPU"), or one the plugin pinned ("kernel sse2, pinned with isa=sse2").
 * rayverify records it beside the version in reports, summaries and gate
 * baselines, and a gate fails when it differs from the baseline's. NULL or
 * absent: nothing of the kind. */
typedef const char* (*rayverify_library_configuration_fn)(void);
RAYVERIFY_PLUGIN_EXPORT const char* rayverify_plugin_library_configuration(void);

/* Optional. NULL when the plugin can answer here; otherwise why it cannot
 * on this machine (e.g. "this CPU does not run Embree's avx512 kernel"):
 * loading it is then an input error with that reason, and `rayverify
 * engines` lists it as not runnable here. Asked once, after loading. */
typedef const char* (*rayverify_unavailable_fn)(void);
RAYVERIFY_PLUGIN_EXPORT const char* rayverify_plugin_unavailable(void);

#ifdef __cplusplus
}
#endif

#endif /* RAYVERIFY_PLUGIN_H */
