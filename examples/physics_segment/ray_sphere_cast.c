/* The segment cast of ray_sphere_cast.h, in float, written the way game
 * physics code usually is: Ericson, "Real-Time Collision Detection" (2005),
 * section 5.3.2, IntersectRaySphere, restricted to the segment (t <= 1) and
 * with the direction left unnormalised (t is then the segment's fraction).
 * m = p0 - c, d = p1 - p0, b = m.d, C = m.m - r^2: outside and moving away
 * (C > 0 and b > 0) is a miss; else the discriminant b^2 - (d.d) C, the near
 * root t = (-b - sqrt(disc)) / (d.d), clamped to 0 when the start is inside.
 * Every step rounds in float: d, m, both dot products and the discriminant. */
#include "ray_sphere_cast.h"

#include <math.h>

static float dot3(const float a[3], const float b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

int RaySphere(const float p0[3], const float p1[3], const float c[3], float r, float* fraction) {
    const float d[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
    const float m[3] = {p0[0] - c[0], p0[1] - c[1], p0[2] - c[2]};
    const float a = dot3(d, d);
    const float b = dot3(m, d);
    const float C = dot3(m, m) - r * r;
    if (C > 0.0f && b > 0.0f) return 0; /* outside, moving away */
    const float disc = b * b - a * C;
    if (disc < 0.0f) return 0; /* the line misses */
    float t = (-b - sqrtf(disc)) / a;
    if (t < 0.0f) t = 0.0f; /* started inside: contact at the start */
    if (t > 1.0f) return 0; /* beyond the end of the segment */
    *fraction = t;
    return 1;
}
