// Rapier 3D (npm `@dimforge/rapier3d-compat`, 0.21: Rust compiled to
// WebAssembly, the wasm inlined; pinned in package-lock.json), audited as an
// application calls it:
//
//   world.castRay(ray, maxToi, solid = true)   → RayColliderHit.timeOfImpact
//   (parry3d's ray_toi_with_ball through the world's broad-phase BVH)
//
// after `await RAPIER.init()`, on a World made once (gravity 0) holding one
// ball collider (ColliderDesc.ball, no rigid body), moved and resized per
// case (Collider.setTranslation, Collider.setRadius). castRay answers from
// the broad phase, which only sees a collider's new position and radius after
// world.step() (0.21 has no separate scene-query update): without the step it
// misses (tested), so each case costs one step (no bodies: the broad-phase
// update of one collider) besides the cast; the Ray object is reused.
//
// What it computes (parry's source): in the collider's frame (o − c in f32),
// a = d·d, b = (o − c)·d, C = |o − c|² − r²; a miss if C > 0 and b > 0;
// a miss if b² − aC < 0 (a tangent is a hit); t = (−b − √(b² − aC))/a, and
// with solid = true t ≤ 0 (inside, or on the surface) is a hit at 0. t is in
// units of d (the point is o + t·d), no unit direction assumed. There is no
// tmin: maxToi is the case's tmax (+inf when the case has none; Infinity
// reaches the f32 as +inf and works). The ball's own test keeps t ≤ maxToi
// (Collider.castRay answers t = maxToi), but world.castRay's traversal only
// keeps a hit closer than maxToi: a hit at exactly t = maxToi is a miss
// through the world (tested; also t = 0 with maxToi = 0), so the range is
// [0, tmax), open at tmax.
//
// Answer: timeOfImpact, an f32 widened to a JavaScript number (exactly a
// float), as t0 with count 1; null is count 0.
//
// Contract: query=nearest_hit,range=tmax_only,ends=[),inside=clamp,
//           tangent=hit,faces=both,unit_direction=no
// Precision: float. The WebAssembly build is parry3d with f32 reals: every
// coordinate the API takes is converted to f32 and every computation is in
// f32 (the f64 build is another package), so the batch must be a float
// export; double batches are refused.
import RAPIER from "@dimforge/rapier3d-compat";
import { serve, manifestEntry } from "./protocol.mjs";

let world, collider, ray;

await serve({
  ...manifestEntry("rapier3d"),
  async setup() {
    await RAPIER.init();
    world = new RAPIER.World({ x: 0, y: 0, z: 0 });
    collider = world.createCollider(RAPIER.ColliderDesc.ball(1));
    ray = new RAPIER.Ray({ x: 0, y: 0, z: 0 }, { x: 0, y: 0, z: 1 });
  },
  answer({ o, d, c, r, tmax }) {
    collider.setTranslation({ x: c[0], y: c[1], z: c[2] });
    collider.setRadius(r);
    world.step();
    ray.origin = { x: o[0], y: o[1], z: o[2] };
    ray.dir = { x: d[0], y: d[1], z: d[2] };
    const hit = world.castRay(ray, tmax === null ? Infinity : tmax, true);
    return hit === null ? { count: 0 } : { count: 1, t0: hit.timeOfImpact };
  },
});
