/* robust_sphere.h for C projects and for projects built with -ffast-math.
 *
 * The same queries and promises as robust_sphere.h (docs/robust_sphere.md):
 * the class of every answer decided exactly, every root on its exact side
 * and correctly rounded (RN(t*)). Plain C99 functions in float and double,
 * defined in one C++17 translation unit, robust_sphere_c.cpp, which must be
 * compiled strictly, as its own object: -ffp-contract=off (or on; fused
 * multiply-adds are harmless) and never -ffast-math. The rest of a project
 * may be compiled with -ffast-math and call these functions; link without
 * -ffast-math, whose start-up code (crtfastmath.o) turns on flush-to-zero
 * for the whole process and changes the arithmetic of every subnormal
 * (docs/robust_sphere.md, "From C and from fast-math projects").
 *
 * A ray is origin + t·direction (direction ≠ 0, any length), a sphere its
 * centre and radius; arrays of three coordinates. Inputs finite. */
#ifndef ROBUST_SPHERE_C_H
#define ROBUST_SPHERE_C_H

#ifdef __cplusplus
extern "C" {
#endif

/* Whether an end of the interval (tmin, tmax) belongs to it. */
enum robust_sphere_end { ROBUST_SPHERE_OPEN = 0, ROBUST_SPHERE_CLOSED = 1 };

/* Both roots of the line, t of any sign: returns the count (0 miss, 1
 * tangent with t[0] = t[1], 2 two roots with t[0] <= t[1]); t[] is written
 * only for a count of 1 or 2. */
int robust_sphere_line_roots(const double origin[3], const double direction[3], const double centre[3],
                             double radius, double t[2]);
int robust_sphere_line_roots_f(const float origin[3], const float direction[3], const float centre[3], float radius,
                               float t[2]);

/* The nearest root t* with tmin < t* < tmax (an end given as
 * ROBUST_SPHERE_CLOSED includes t* equal to it): returns 1 and writes *t,
 * or returns 0. From inside the sphere that is the exit root. */
int robust_sphere_nearest_hit(const double origin[3], const double direction[3], const double centre[3],
                              double radius, double tmin, double tmax, enum robust_sphere_end lower,
                              enum robust_sphere_end upper, double* t);
int robust_sphere_nearest_hit_f(const float origin[3], const float direction[3], const float centre[3], float radius,
                                float tmin, float tmax, enum robust_sphere_end lower, enum robust_sphere_end upper,
                                float* t);

/* Is there a root in the interval (a shadow ray)? 1 or 0, decided exactly. */
int robust_sphere_any_hit(const double origin[3], const double direction[3], const double centre[3], double radius,
                          double tmin, double tmax, enum robust_sphere_end lower, enum robust_sphere_end upper);
int robust_sphere_any_hit_f(const float origin[3], const float direction[3], const float centre[3], float radius,
                            float tmin, float tmax, enum robust_sphere_end lower, enum robust_sphere_end upper);

/* What a segment that starts strictly inside the sphere hits: a contact at
 * its start (fraction 0, the initial overlap physics engines report) or its
 * exit (the far root). */
enum robust_sphere_start_inside { ROBUST_SPHERE_CONTACT = 0, ROBUST_SPHERE_EXIT = 1 };

/* A segment's first contact: the fraction f in [0, 1] of the way from p0 to
 * p1 (an end given as ROBUST_SPHERE_OPEN excludes a contact exactly there),
 * correctly rounded, every decision exact for the segment as given (p1 - p0
 * is never rounded). Returns 1 and writes *fraction, or returns 0 (a miss;
 * also a zero-length segment or a non-finite input). */
int robust_sphere_segment_hit(const double p0[3], const double p1[3], const double centre[3], double radius,
                              enum robust_sphere_end start, enum robust_sphere_end end,
                              enum robust_sphere_start_inside inside, double* fraction);
int robust_sphere_segment_hit_f(const float p0[3], const float p1[3], const float centre[3], float radius,
                                enum robust_sphere_end start, enum robust_sphere_end end,
                                enum robust_sphere_start_inside inside, float* fraction);

#ifdef __cplusplus
}
#endif

#endif /* ROBUST_SPHERE_C_H */
