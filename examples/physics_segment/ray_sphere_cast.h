/* A game-physics segment cast against a sphere, as physics engines write it
 * (the segment form of Jolt's, Bullet's, ODE's and Godot's casts): the user's
 * code that examples/physics_segment audits, unchanged, through a plugin
 * that hands it the segment's end points as given. */
#ifndef RAY_SPHERE_CAST_H
#define RAY_SPHERE_CAST_H

#ifdef __cplusplus
extern "C" {
#endif

/* Cast the segment p0 -> p1 against the sphere |p - c| = r. Returns 1 and the
 * fraction of first contact in [0, 1] (0 at p0, 1 at p1) in *fraction, or 0
 * when the segment does not touch the sphere. A segment starting inside (or
 * on) the sphere makes contact at the start: fraction 0. Both ends count
 * (a contact exactly at p1 is a hit). */
int RaySphere(const float p0[3], const float p1[3], const float c[3], float r, float* fraction);

#ifdef __cplusplus
}
#endif

#endif
