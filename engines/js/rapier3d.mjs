// Rapier 3D (npm `@dimforge/rapier3d-compat` 0.21.0, pinned in
// package-lock.json: Rust compiled to WebAssembly, the wasm inlined; the
// adapter is checked with that version only: older releases name the hit's
// field `toi`, not `timeOfImpact`), audited as an application calls it:
//
//   world.castRay(ray, maxToi, solid = true)   → RayColliderHit.timeOfImpact
//   (parry3d's ray_toi_with_ball through the world's broad-phase BVH)
//
// after `await RAPIER.init()` (once), on a World made per case (gravity 0)
// holding one ball collider (ColliderDesc.ball(r).setTranslation(c), no
// rigid body), freed after the cast (World.free). castRay answers from the
// broad phase, which only sees a collider after world.step() (0.21 has no
// separate scene-query update): without the step it misses (tested). One
// World is not reused across cases on purpose: once its ball had been given
// an infinite centre and radius (corpus/edge's near_overflow exported in
// float, where every coordinate overflows to inf) and stepped, the world
// missed every later case, the ball moved back and stepped again (its
// broad phase never recovered: tested), so reusing it would make answers
// depend on earlier cases. Cost per case: a World (wasm allocations), a collider, one
// step (no bodies: the broad-phase insertion of one collider), a Ray and the
// cast; about 1.5 ms on the shared 2-core VM, the step most of it.
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
// f32 (built from the f32 crates, rapier3d and parry3d, not their -f64
// twins; its answers are float32 values, tested), so the batch must be a
// float export; double batches are refused.
import RAPIER from "@dimforge/rapier3d-compat";
import { serve, manifestEntry } from "./protocol.mjs";

await serve({
  ...manifestEntry("rapier3d"),
  async setup() {
    await RAPIER.init();
  },
  answer({ o, d, c, r, tmax }) {
    const world = new RAPIER.World({ x: 0, y: 0, z: 0 });
    try {
      world.createCollider(RAPIER.ColliderDesc.ball(r).setTranslation(c[0], c[1], c[2]));
      world.step();
      const ray = new RAPIER.Ray({ x: o[0], y: o[1], z: o[2] }, { x: d[0], y: d[1], z: d[2] });
      const hit = world.castRay(ray, tmax === null ? Infinity : tmax, true);
      return hit === null ? { count: 0 } : { count: 1, t0: hit.timeOfImpact };
    } finally {
      world.free();
    }
  },
});
