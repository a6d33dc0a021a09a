// PlayCanvas (npm `playcanvas` 2.23.3, pinned in package-lock.json; the code
// below is read from that version's src/core/shape/bounding-sphere.js; the
// adapter is checked with that version only), audited as an application
// calls it:
//
//   boundingSphere.intersectsRay(ray, point)   (src/core/shape/bounding-sphere.js)
//
// with one Ray, one BoundingSphere and one point Vec3 made once and set per
// case (Vec3.set, BoundingSphere.radius): a call allocates nothing and costs
// a normalize (one square root, one division) and about 25 flops more.
//
// What it computes (PlayCanvas's source; Ericson's Real-Time Collision
// Detection §5.3.2, IntersectRaySphere): m = o − c, b = m·(d/|d|),
// C = m·m − r²; false if C > 0 and b > 0 (outside, pointing away); false if
// b² − C < 0 (a tangent, b² − C == 0, is a hit); t = |−b − √(b² − C)|, and the
// point o + t·d. Ericson clamps a negative t to 0 ("ray started inside
// sphere"); PlayCanvas takes its absolute value instead, so from inside the
// point is o + |near root|·d, off the sphere unless the origin is the centre
// (then it is the far root), and from an origin on the surface pointing out
// (C == 0, b > 0: not excluded by the early-out) the point is at t = 2b, off
// the sphere too. The
// contract is Ericson's (inside=clamp), which the code set out to implement;
// the absolute value shows up as wrong roots from inside. t is a distance
// along the normalized direction, while the point is o + t·d: a unit
// direction is assumed (d passed as given).
//
// Answer: the hit POINT (`point`) as hit_point with count 1; false is
// count 0. No t is written: PlayCanvas gives none.
//
// Contract: query=nearest_hit,range=ray,ends=[),inside=clamp,tangent=hit,
//           faces=both,unit_direction=yes,answer=point
// Precision: double (PlayCanvas's Vec3 holds plain JavaScript numbers).
import { BoundingSphere, Ray, Vec3 } from "playcanvas";
import { serve, manifestEntry } from "./protocol.mjs";

const ray = new Ray();
const sphere = new BoundingSphere();
const point = new Vec3();

await serve({
  ...manifestEntry("playcanvas"),
  answer({ o, d, c, r }) {
    ray.origin.set(o[0], o[1], o[2]);
    ray.direction.set(d[0], d[1], d[2]);
    sphere.center.set(c[0], c[1], c[2]);
    sphere.radius = r;
    return sphere.intersectsRay(ray, point) ? { count: 1, point: [point.x, point.y, point.z] } : { count: 0 };
  },
});
