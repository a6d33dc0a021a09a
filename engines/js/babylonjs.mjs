// Babylon.js (npm `@babylonjs/core` 9.35.0, pinned in package-lock.json; the
// code below is read from that version's Culling/ray.core.js and
// Culling/boundingSphere.js; the adapter is checked with that version only),
// audited as an application calls it:
//
//   BoundingSphere.CreateFromCenterAndRadius(center, radius)
//   ray.intersectsSphere(boundingSphere)      (Culling/ray.core.ts; the
//                                             intersectionTreshold left at 0)
//
// imported from the ES modules' documented deep paths (Culling/ray.js,
// Culling/boundingSphere.js, Maths/math.vector.js). The BoundingSphere
// constructor takes the min and max corners of a BOX (its radius is half the
// box's diagonal: a sphere of centre c and radius r given as c ∓ (r, r, r)
// would be √3 too big); CreateFromCenterAndRadius builds it from the corners
// c ± (0, 0, r), so Babylon's own centre is ((c_z − r) + (c_z + r))/2 and its
// radius |2r′|/2, both rounded in double: when |c_z| ≫ r the sphere Babylon
// tests is not exactly the case's (that is how an application gets a sphere
// from centre and radius, and it is audited as such).
//
// Cost: CreateFromCenterAndRadius allocates a BoundingSphere (four Vector3s
// and an identity Matrix) per case; the Ray and its two Vector3s are made
// once and set per case. intersectsSphere itself allocates nothing: about 20
// flops.
//
// What it computes (Babylon's source): with v = c − o, |v|² ≤ r² → true (the
// origin inside or on the sphere); v·d < 0 → false (the centre behind);
// else |v|² − (v·d)² ≤ r² → true (a tangent is a hit). The ray's `length`
// (default Number.MAX_VALUE) is not consulted: the range is the whole ray,
// [0, +inf), the origin on the surface a hit. |v|² − (v·d)² is the squared
// distance from the centre to the line only when |d| = 1: the direction is
// assumed unit (passed as given, not normalized).
//
// Answer: a boolean, judged as any hit (count 1 or 0).
//
// Contract: query=any_hit,range=ray,ends=[),inside=far_root,tangent=hit,
//           faces=both,unit_direction=yes
// Precision: double (Babylon's Vector3 holds plain JavaScript numbers).
import { Ray } from "@babylonjs/core/Culling/ray.js";
import { BoundingSphere } from "@babylonjs/core/Culling/boundingSphere.js";
import { Vector3 } from "@babylonjs/core/Maths/math.vector.js";
import { serve, manifestEntry } from "./protocol.mjs";

const ray = new Ray(Vector3.Zero(), Vector3.Zero());
const centre = Vector3.Zero();

await serve({
  ...manifestEntry("babylonjs"),
  answer({ o, d, c, r }) {
    ray.origin.copyFromFloats(o[0], o[1], o[2]);
    ray.direction.copyFromFloats(d[0], d[1], d[2]);
    centre.copyFromFloats(c[0], c[1], c[2]);
    const sphere = BoundingSphere.CreateFromCenterAndRadius(centre, r);
    return { count: ray.intersectsSphere(sphere) ? 1 : 0 };
  },
});
