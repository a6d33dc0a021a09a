// protocol.mjs on its own: reading the numbers rayverify exports, writing
// answers, and the segment length of the segment engines.
import { test } from "node:test";
import assert from "node:assert/strict";
import { hexFloat, parseCase, formatAnswer, jsonNumber, segmentLength, ilogb } from "../protocol.mjs";

test("hex floats are read exactly, subnormals and signs included", () => {
  assert.equal(hexFloat("0x1.8p+1"), 3);
  assert.equal(hexFloat("-0x1.4p+2"), -5);
  assert.ok(Object.is(hexFloat("-0x0p+0"), -0));
  assert.equal(hexFloat("0x1p-1074"), 5e-324);
  assert.equal(hexFloat("0x0.0000000000001p-1022"), 5e-324);
  assert.equal(hexFloat("0x1.fffffffffffffp+1023"), Number.MAX_VALUE);
  assert.equal(hexFloat("0x1.999999999999ap-4"), 0.1);
  assert.equal(hexFloat("0x1.99999ap-4"), Math.fround(0.1));
  assert.ok(Number.isNaN(hexFloat("0x")));
});

test("a case's numbers: decimals, hex, nan and infinities; float batches read as float32", () => {
  const line = JSON.stringify({
    id: "a", family: "", ox: "0x1.8p+1", oy: "-inf", oz: "nan", dx: 0.1, dy: "-0", dz: "inf",
    cx: "1e-3", cy: 0, cz: 0, r: 1, tmin: null, tmax: "0x1p+2",
  });
  const d = parseCase(line, "double");
  assert.deepEqual(d.o.slice(0, 2), [3, -Infinity]);
  assert.ok(Number.isNaN(d.o[2]));
  assert.equal(d.d[0], 0.1);
  assert.ok(Object.is(d.d[1], -0));
  assert.equal(d.d[2], Infinity);
  assert.equal(d.c[0], 1e-3);
  assert.equal(d.tmin, null);
  assert.equal(d.tmax, 4);
  const f = parseCase(line, "float");
  assert.equal(f.d[0], Math.fround(0.1));
  assert.equal(f.c[0], Math.fround(1e-3));
  assert.throws(() => parseCase(JSON.stringify({ id: "b", ox: "x" }), "double"), /field 'ox'/);
});

test("answers: JSON has no NaN, infinities or -0, so they go as strings", () => {
  assert.equal(jsonNumber(-0), "-0");
  assert.equal(jsonNumber(NaN), "nan");
  assert.equal(jsonNumber(-Infinity), "-inf");
  assert.equal(formatAnswer("x", { count: 0 }), '{"id":"x","count":0}');
  assert.equal(formatAnswer("x", { count: 1, t0: Infinity }), '{"id":"x","count":1,"t0":"inf"}');
  assert.equal(formatAnswer("x", { count: 1, point: [0, -0, 1.5] }), '{"id":"x","count":1,"hit_point":[0,"-0",1.5]}');
});

test("segmentLength: rayverify's segment_length, a power of two past every root", () => {
  // |o − c|₁ + r = 2001 over |d|∞ = 1: ilogb(2001) = 10, so 2^12.
  assert.equal(segmentLength([0, 0, -1000], [0, 0, 1], [0, 0, 1000], 1, "double"), 4096);
  // over |d|∞ = 0.25: 8004, ilogb 12, so 2^14.
  assert.equal(segmentLength([0, 0, -1000], [0, 0, 0.25], [0, 0, 1000], 1, "double"), 16384);
  assert.equal(segmentLength([0, 0, 0], [0, 0, 0], [0, 0, 1], 1, "double"), 1); // no direction
  // Capped where L·|d|∞ would pass a quarter of the largest value.
  assert.equal(segmentLength([0, 0, 0], [0, 0, 1], [0, 0, 1e308], 1, "double"), 2 ** (ilogb(Number.MAX_VALUE / 4) - 1));
  assert.equal(ilogb(3), 1);
  assert.equal(ilogb(0.75), -1);
  assert.equal(ilogb(1 - 2 ** -53), -1);
  assert.equal(ilogb(2 ** 1023), 1023);
  assert.equal(ilogb(2 ** -1074), -1074);
});
