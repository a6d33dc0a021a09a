// cannon-es (npm `cannon-es` 0.20.0, pinned in package-lock.json; the code
// below is read from that version's dist/cannon-es.js; the adapter is
// checked with that version only), audited as an application calls it:
//
//   world.raycastClosest(from, to, {}, result)   (World, Ray.intersectWorld,
//                                                 Ray._intersectSphere)
//
// on a World made once (default options: NaiveBroadphase), holding one static
// Body ({mass: 0, shape: new Sphere(r), position: c}) made, added and removed
// per case. No world.step() is needed: the broadphase's aabbQuery updates a
// body's AABB when `aabbNeedsUpdate` is set, which a new Body is. Cost per
// case: a Body and a Sphere allocated (mass properties, bounding radius,
// AABB), the broadphase's AABB test, the ray's bounding-sphere pre-test and
// the quadratic below; raycastClosest's options object and the
// RaycastResult are reused.
//
// A segment case (p1 given) is cast from p0 = o to p1 as given. On ray cases,
// the segment: from = o + tmin·d (o itself when tmin is 0 or absent) and
// to = o + tmax·d, each coordinate rounded once in double; for a case
// without tmax, to = o + L·d with L = segmentLength() (protocol.mjs, as
// rayverify's segment_length() for its segment engines): the power of two
// with L·|d|∞ ≥ 2(|o − c|₁ + r), so every root t* (|t*|·|d| ≤ |o − c| + r)
// lies on [−L, L] and the segment [0, L] holds every root in front.
//
// What it computes (cannon-es's source): the ray's AABB against the body's;
// the distance from c to the line (normalized direction) against the
// sphere's bounding radius (r), a miss if larger; then the quadratic in the
// segment fraction f ∈ [0, 1]: a = |to − from|², b = 2(to − from)·(from − c),
// C = |from − c|² − r², Δ = b² − 4aC; a miss if Δ < 0; both roots
// f = (−b ∓ √Δ)/2a reported where 0 ≤ f ≤ 1 (ends closed), and the closest
// to `from` kept: from inside, the far root. When Δ == 0 exactly (a tangent)
// the point is from.lerp(to, Δ), that is `from` itself (it lerps by Δ = 0,
// not by the root): an upstream bug, judged as a wrong root.
//
// Answer: result.hitPointWorld, the point from + f·(to − from), as hit_point
// with count 1 (no hit: count 0). The point is what cannon-es gives
// (result.distance is |hitPointWorld − from|, derived from it); no t is
// written.
//
// Contract: query=nearest_hit,range=segment,ends=[],inside=far_root,
//           tangent=hit,faces=both,unit_direction=no,answer=point
// Precision: double (cannon-es's Vec3 holds plain JavaScript numbers).
import { Body, RaycastResult, Sphere, Vec3, World } from "cannon-es";
import { serve, manifestEntry, segmentLength } from "./protocol.mjs";

const world = new World();
const from = new Vec3();
const to = new Vec3();
const result = new RaycastResult();
const options = {};

await serve({
  ...manifestEntry("cannon_es"),
  answer({ o, d, c, r, tmin, tmax, p1 }) {
    const body = new Body({ mass: 0, shape: new Sphere(r), position: new Vec3(c[0], c[1], c[2]) });
    world.addBody(body);
    if (tmin === null || tmin === 0) from.set(o[0], o[1], o[2]);
    else from.set(o[0] + tmin * d[0], o[1] + tmin * d[1], o[2] + tmin * d[2]);
    const length = tmax === null || tmax === Infinity ? segmentLength(o, d, c, r, "double") : tmax;
    // A segment case is cast between its two points as given, as a game casts.
    if (p1 !== null) to.set(p1[0], p1[1], p1[2]);
    else to.set(o[0] + length * d[0], o[1] + length * d[1], o[2] + length * d[2]);
    for (const key of Object.keys(options)) delete options[key]; // raycastClosest writes into it
    const hit = world.raycastClosest(from, to, options, result);
    world.removeBody(body);
    if (!hit) return { count: 0 };
    const p = result.hitPointWorld;
    return { count: 1, point: [p.x, p.y, p.z] };
  },
});
