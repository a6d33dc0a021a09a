// The JavaScript engine adapters on hand-worked cases: each adapter is run as
// rayverify runs it (a program reading batches of JSON-lines cases on stdin
// and answering on stdout), and its answers are checked against values worked
// out by hand from the library's own formula. Run from the repository root:
//
//   node --test engines/js/test/
//
// Needs the engines installed (tools/setup.sh: npm ci in engines/js).
import { test } from "node:test";
import assert from "node:assert/strict";
import { spawnSync } from "node:child_process";
import { readFileSync } from "node:fs";
import { dirname, join } from "node:path";
import { fileURLToPath } from "node:url";

const dir = join(dirname(fileURLToPath(import.meta.url)), "..");
const manifest = JSON.parse(readFileSync(join(dir, "engines.json"), "utf8"));
const entry = (name) => manifest.find((e) => e.name === name);

function run(adapter, input, args = []) {
  const r = spawnSync(process.execPath, [join(dir, adapter), ...args], { input, encoding: "utf8", timeout: 60000 });
  if (r.error) throw r.error;
  return r;
}

const header = (precision, cases, fingerprint = "0123456789abcdef") =>
  JSON.stringify({ rayverify: "cases", version: 1, precision, fingerprint, cases, numbers: "decimal" });

// A case: o, d, c as arrays, r, and optionally tmin, tmax.
const kase = (id, o, d, c, r, tmin = null, tmax = null) =>
  JSON.stringify({
    id, family: "", ox: o[0], oy: o[1], oz: o[2], dx: d[0], dy: d[1], dz: d[2],
    cx: c[0], cy: c[1], cz: c[2], r, tmin, tmax,
  });

// The unit sphere at the origin, rays along +z.
const C0 = [0, 0, 0];
const Z = [0, 0, 1];
const cases = {
  hit: kase("hit", [0, 0, -5], Z, C0, 1), // roots 4 and 6: nearest t = 4, point (0, 0, -1)
  miss: kase("miss", [0, 2, -5], Z, C0, 1), // passes 2 from the centre
  near_miss: kase("near_miss", [0, 1.5, -5], Z, C0, 1), // misses r = 1; a sphere √3 too big would be hit
  behind: kase("behind", [0, 0, 5], Z, C0, 1), // roots −6 and −4: behind the origin
  inside: kase("inside", [0, 0, 0.5], Z, C0, 1), // roots −1.5 and 0.5
  centre: kase("centre", [0, 0, 0], Z, C0, 1), // roots −1 and 1
  tangent: kase("tangent", [1, 0, -5], Z, C0, 1), // touches (1, 0, 0) at t = 5, exactly (Δ = 0 in any form)
  off_centre: kase("off_centre", [0, 0, -5], Z, [0, 0, 10], 2), // roots 13 and 17: point (0, 0, 8)
};
const names = Object.keys(cases);

// Runs one batch of the named cases; returns {header, answers by id}.
function answer(adapter, precision, ids, extra = []) {
  const lines = [...ids.map((id) => cases[id]), ...extra];
  const r = run(adapter, [header(precision, lines.length), ...lines].join("\n") + "\n");
  assert.equal(r.status, 0, `${adapter} exited ${r.status}: ${r.stderr}`);
  const out = r.stdout.trim().split("\n").map((l) => JSON.parse(l));
  assert.deepEqual(out[0], { rayverify: "results", version: 1, precision, fingerprint: "0123456789abcdef" });
  assert.equal(out.length, lines.length + 1, "one answer per case");
  const byId = {};
  lines.forEach((l, i) => {
    const id = JSON.parse(l).id;
    assert.equal(out[i + 1].id, id, "answers in the cases' order");
    byId[id] = out[i + 1];
  });
  return byId;
}

const point = (a) => {
  assert.equal(a.count, 1, `expected a hit, got ${JSON.stringify(a)}`);
  assert.ok(Array.isArray(a.hit_point), `a point answer has hit_point: ${JSON.stringify(a)}`);
  assert.equal(a.t0, undefined, "a point engine writes no t");
  return a.hit_point;
};
const miss = (a) => assert.deepEqual(a, { id: a.id, count: 0 });

test("engines.json: one entry per adapter, with exactly the catalogue's keys", () => {
  assert.deepEqual(manifest.map((e) => e.name), ["three", "babylonjs", "playcanvas", "cannon_es", "rapier3d"]);
  for (const e of manifest) {
    assert.deepEqual(Object.keys(e).sort(), ["adapter", "api", "contract", "library", "name", "package", "precision"]);
    assert.ok(["float", "double"].includes(e.precision));
    assert.match(e.contract, /^query=(nearest_hit|any_hit|line_roots),range=/);
    // The adapter's opening comment states the same contract.
    const source = readFileSync(join(dir, e.adapter), "utf8");
    const comment = source.match(/^\/\/ Contract: ([^\n]*(?:\n\/\/ {11}[^\n]*)*)/m);
    assert.ok(comment, `${e.adapter}: no '// Contract:' line`);
    assert.equal(comment[1].replace(/\n\/\/ {11}/g, ""), e.contract, `${e.adapter}: the comment's contract`);
  }
});

for (const e of manifest) {
  test(`${e.name}: --version prints the installed package's version`, () => {
    const pkg = JSON.parse(readFileSync(join(dir, "node_modules", e.package, "package.json"), "utf8"));
    const r = run(e.adapter, "", ["--version"]);
    assert.equal(r.status, 0, r.stderr);
    assert.equal(r.stdout, pkg.version + "\n");
  });

  test(`${e.name}: refuses a batch in the other precision`, () => {
    const other = e.precision === "double" ? "float" : "double";
    const r = run(e.adapter, [header(other, 1), cases.hit].join("\n") + "\n");
    assert.notEqual(r.status, 0);
    assert.equal(r.stdout, "");
    assert.match(r.stderr, new RegExp(`computes in ${e.precision}: export them with --precision ${e.precision}`));
  });

  test(`${e.name}: answers batch after batch, an empty batch too, and stops on a cut batch`, () => {
    const input = [header(e.precision, 1), cases.hit, header(e.precision, 0), header(e.precision, 2), cases.miss, cases.hit].join("\n") + "\n";
    const r = run(e.adapter, input);
    assert.equal(r.status, 0, r.stderr);
    const out = r.stdout.trim().split("\n").map((l) => JSON.parse(l));
    assert.deepEqual(out.map((o) => o.rayverify ?? o.id), ["results", "hit", "results", "results", "miss", "hit"]);
    const cut = run(e.adapter, [header(e.precision, 2), cases.hit].join("\n") + "\n");
    assert.notEqual(cut.status, 0);
    assert.match(cut.stderr, /end of input after 1 of the batch's 2 cases/);
  });
}

test("three: Ray.intersectSphere's points", () => {
  const a = answer("three.mjs", "double", names);
  assert.deepEqual(point(a.hit), [0, 0, -1]);
  miss(a.miss);
  miss(a.near_miss);
  miss(a.behind);
  assert.deepEqual(point(a.inside), [0, 0, 1]); // from inside: the far root
  assert.deepEqual(point(a.centre), [0, 0, 1]);
  assert.deepEqual(point(a.tangent), [1, 0, 0]); // d² == r²: a hit
  assert.deepEqual(point(a.off_centre), [0, 0, 8]);
});

test("three: an origin on the surface is a hit at t = 0 (ends [) ), the exit too", () => {
  const a = answer("three.mjs", "double", [], [kase("enter", [0, 0, -1], Z, C0, 1), kase("leave", [0, 0, 1], Z, C0, 1)]);
  assert.deepEqual(point(a.enter), [0, 0, -1]);
  assert.deepEqual(point(a.leave), [0, 0, 1]); // roots −2 and 0: t1 = 0 is not < 0
});

test("babylonjs: Ray.intersectsSphere on BoundingSphere.CreateFromCenterAndRadius", () => {
  const a = answer("babylonjs.mjs", "double", names);
  for (const id of ["hit", "inside", "centre", "tangent", "off_centre"]) assert.deepEqual(a[id], { id, count: 1 }, id);
  for (const id of ["miss", "near_miss", "behind"]) miss(a[id]);
});

test("babylonjs: the sphere has radius r, not the box diagonal's √3·r", () => {
  // Lines 1.01 and 1.7 from the centre of spheres of radius 1 and 2 (a sphere
  // built from the box c ∓ (r, r, r) would have radius 1.73 and 3.46).
  const a = answer("babylonjs.mjs", "double", [], [
    kase("r1", [0, 1.01, -5], Z, C0, 1),
    kase("r1_corner", [1.0, 1.0, -5], Z, C0, 1),
    kase("r2", [0, 1.99, -5], Z, C0, 2),
    kase("r2_out", [0, 2.01, -5], Z, [0, 0, 7], 2),
  ]);
  miss(a.r1);
  miss(a.r1_corner);
  assert.equal(a.r2.count, 1);
  miss(a.r2_out);
});

test("babylonjs: an origin on the surface is a hit, also leaving; a centre behind is a miss", () => {
  const a = answer("babylonjs.mjs", "double", [], [
    kase("enter", [0, 0, -1], Z, C0, 1),
    kase("leave", [0, 0, 1], Z, C0, 1),
    kase("away", [0, 0, 1.000001], Z, C0, 1),
  ]);
  assert.equal(a.enter.count, 1);
  assert.equal(a.leave.count, 1);
  miss(a.away);
});

test("playcanvas: BoundingSphere.intersectsRay's points", () => {
  const a = answer("playcanvas.mjs", "double", names);
  assert.deepEqual(point(a.hit), [0, 0, -1]);
  miss(a.miss);
  miss(a.near_miss);
  miss(a.behind);
  // From inside: t = |−b − √(b² − C)| with b = 0.5, C = −0.75: |−1.5| = 1.5,
  // the point (0, 0, 2), off the sphere (PlayCanvas's abs where Ericson clamps).
  assert.deepEqual(point(a.inside), [0, 0, 2]);
  assert.deepEqual(point(a.centre), [0, 0, 1]);
  assert.deepEqual(point(a.tangent), [1, 0, 0]);
  assert.deepEqual(point(a.off_centre), [0, 0, 8]);
});

test("playcanvas: t is along the normalized direction, the point along d itself", () => {
  // d = (0, 0, 2): t = 4 (a distance), the point o + 4·d = (0, 0, 3).
  const a = answer("playcanvas.mjs", "double", [], [kase("long_d", [0, 0, -5], [0, 0, 2], C0, 1)]);
  assert.deepEqual(point(a.long_d), [0, 0, 3]);
});

test("cannon_es: World.raycastClosest's hitPointWorld, on the segment the mapping gives", () => {
  const a = answer("cannon_es.mjs", "double", names);
  assert.deepEqual(point(a.hit), [0, 0, -1]);
  miss(a.miss);
  miss(a.near_miss);
  miss(a.behind);
  assert.deepEqual(point(a.inside), [0, 0, 1]); // the far root: the near one is before `from`
  assert.deepEqual(point(a.centre), [0, 0, 1]);
  // Δ == 0 exactly: cannon-es lerps by Δ (0), not by the root: the point is `from`.
  assert.deepEqual(point(a.tangent), [1, 0, -5]);
  assert.deepEqual(point(a.off_centre), [0, 0, 8]);
});

test("cannon_es: a segment case is cast between its two points as given", () => {
  // The case line carries its ray form (o = p0, d = p1 - p0, [0, 1]) and p1x..p1z:
  // the adapter casts to p1 itself, not to o + 1·d (which rounds where p1 - p0 is no double).
  const segment = (id, p0, p1) => {
    const j = JSON.parse(kase(id, p0, [p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]], C0, 1, 0, 1));
    return JSON.stringify({ ...j, p1x: p1[0], p1y: p1[1], p1z: p1[2] });
  };
  const a = answer("cannon_es.mjs", "double", [], [
    segment("ends_on_surface", [0, 0, -5], [0, 0, -1]),
    segment("ends_short", [0, 0, -5], [0, 0, -1.5]),
    segment("tiny_at_end", [-2, 0, 0], [2 ** -60, 0, 0]),
  ]);
  assert.deepEqual(point(a.ends_on_surface), [0, 0, -1]);
  miss(a.ends_short);
  // The unit sphere from (-2, 0, 0) towards (2^-60, 0, 0): contact at (-1, 0, 0).
  assert.deepEqual(point(a.tiny_at_end), [-1, 0, 0]);
});

test("cannon_es: the case's interval is the segment, ends closed; d need not be unit", () => {
  const a = answer("cannon_es.mjs", "double", [], [
    kase("short", [0, 0, -5], Z, C0, 1, 0, 3), // [0, 3]: ends before the sphere
    kase("to_root", [0, 0, -5], Z, C0, 1, 0, 4), // ends exactly on the near root
    kase("from_inside", [0, 0, -5], Z, C0, 1, 4.5, 10), // starts inside: the exit
    kase("past", [0, 0, -5], Z, C0, 1, 6.5, 10), // starts past the sphere
    kase("long_d", [0, 0, -5], [0, 0, 2], C0, 1), // t = 2, the point (0, 0, −1)
    kase("far", [0, 0, -1000], Z, [0, 0, 1000], 1), // the segment [0, L] reaches t = 1999
  ]);
  miss(a.short);
  assert.deepEqual(point(a.to_root), [0, 0, -1]);
  assert.deepEqual(point(a.from_inside), [0, 0, 1]);
  miss(a.past);
  assert.deepEqual(point(a.long_d), [0, 0, -1]);
  assert.deepEqual(point(a.far), [0, 0, 999]);
});

test("rapier3d: World.castRay's time of impact, in float", () => {
  const a = answer("rapier3d.mjs", "float", names, [
    kase("long_d", [0, 0, -5], [0, 0, 2], C0, 1), // t in units of d: 2
    kase("tmax_short", [0, 0, -5], Z, C0, 1, 0, 3.5),
    kase("tmax_root", [0, 0, -5], Z, C0, 1, 0, 4), // world.castRay: open at tmax
    kase("tmax_past", [0, 0, -5], Z, C0, 1, 0, 4.0000005), // the next float up
    kase("tmin_ignored", [0, 0, -5], Z, C0, 1, 4.5, 10), // no tmin: still t = 4
    kase("leave", [0, 0, 1], Z, C0, 1), // on the surface, leaving: solid, t = 0
    kase("tenth", [0.1, 0.1, -5], Z, C0, 1), // float inputs: 0.1 read as float32
    // A ball at an infinite centre with an infinite radius (a double case
    // overflowed to float), then the plain hit again: each case is answered
    // on its own (a reused World's broad phase kept missing after such a case).
    kase("overflowed", ["inf", "inf", "-inf"], [1, 0, 0], ["inf", "-inf", "inf"], "inf"),
    kase("hit_again", [0, 0, -5], Z, C0, 1),
  ]);
  const t = (x) => {
    assert.equal(x.count, 1, JSON.stringify(x));
    assert.equal(x.hit_point, undefined);
    return x.t0;
  };
  assert.equal(t(a.hit), 4);
  miss(a.miss);
  miss(a.near_miss);
  miss(a.behind);
  assert.equal(t(a.inside), 0); // solid: from inside, t = 0
  assert.equal(t(a.centre), 0);
  assert.equal(t(a.tangent), 5);
  assert.equal(t(a.off_centre), 13);
  assert.equal(t(a.long_d), 2);
  miss(a.tmax_short);
  miss(a.tmax_root);
  assert.equal(t(a.tmax_past), 4);
  assert.equal(t(a.tmin_ignored), 4);
  assert.equal(t(a.leave), 0);
  assert.equal(t(a.hit_again), 4);
  // |(0.1, 0.1)|² in float32 arithmetic: the nearest root is 5 − √(1 − 0.02) in
  // f32; it must be a float32 value, within a few float ulps of the exact root.
  const tenth = t(a.tenth);
  assert.equal(Math.fround(tenth), tenth, "an f32 answer");
  const x = Math.fround(0.1);
  assert.ok(Math.abs(tenth - (5 - Math.sqrt(1 - 2 * x * x))) < 4e-6, String(tenth));
});
