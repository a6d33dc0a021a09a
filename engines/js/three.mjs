// three.js (npm `three` 0.187.0, pinned in package-lock.json; the code below
// is read from that version's src/math/Ray.js; the adapter is checked with
// that version only), audited as an application calls it:
//
//   ray.intersectSphere(sphere, target)   (src/math/Ray.js)
//
// with one Ray, one Sphere and one target Vector3 made once and set per case
// (Vector3.set, Sphere.radius): a call allocates nothing and costs the
// closest-approach formula below and Ray.at, a few dozen flops.
//
// What it computes (three's source): tca = (c − o)·d, d² = |c − o|² − tca²,
// null if d² > r² (a tangent, d² == r², is a hit); t0 = tca − √(r² − d²),
// t1 = tca + √(r² − d²); null if t1 < 0; the point at t1 if t0 < 0 (from
// inside, the far root), else at t0. t = 0 is in range (t0 < 0 is the
// test), so the range is [0, +inf). `Ray.direction` is documented as "the
// (normalized) direction of the ray", and the formula takes |d| = 1: the
// adapter passes d as given (no normalizing), and the contract says the
// direction is assumed unit, so a case with |d| ≠ 1 is scored outside the
// contract.
//
// Answer: the hit POINT three returns (`target`, o + t·d in double), as
// hit_point with count 1; null is count 0. No t is written: three gives none.
//
// Contract: query=nearest_hit,range=ray,ends=[),inside=far_root,tangent=hit,
//           faces=both,unit_direction=yes,answer=point
// Precision: double (JavaScript numbers; three's math classes hold plain
// numbers, never Float32Array). Batches in float are refused.
import { Ray, Sphere, Vector3 } from "three";
import { serve, manifestEntry } from "./protocol.mjs";

const ray = new Ray();
const sphere = new Sphere();
const target = new Vector3();

await serve({
  ...manifestEntry("three"),
  answer({ o, d, c, r }) {
    ray.origin.set(o[0], o[1], o[2]);
    ray.direction.set(d[0], d[1], d[2]);
    sphere.center.set(c[0], c[1], c[2]);
    sphere.radius = r;
    const p = ray.intersectSphere(sphere, target);
    return p === null ? { count: 0 } : { count: 1, point: [p.x, p.y, p.z] };
  },
});
