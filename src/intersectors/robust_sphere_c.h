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

#ifdef __cplusplus
}
#endif

#endif /* ROBUST_SPHERE_C_H */
