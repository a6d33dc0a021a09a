// The textbook quadratic (rayverify's built-in `naive`) in JavaScript, on JS
// doubles, audited by rayverify through a results file or as a hunted command.
//
//   node naive.js < cases.jsonl > answers.jsonl
//       (rayverify corpus export --format jsonl --precision double), or
//   rayverify hunt --command 'node naive.js' --format jsonl ...
// Reads batches of cases as JSON lines (each a header line, then its cases)
// and writes one results batch per batch.
//
// Contract: query=line_roots,reports_tangent=yes (both roots of the line).
"use strict";
const readline = require("readline");

function naive(o, d, c, r) {
  const f = [o[0] - c[0], o[1] - c[1], o[2] - c[2]];
  const a = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
  const b = 2 * (d[0] * f[0] + d[1] * f[1] + d[2] * f[2]);
  const C = f[0] * f[0] + f[1] * f[1] + f[2] * f[2] - r * r;
  const D = b * b - 4 * a * C;
  if (D < 0) return [0, 0, 0];
  if (D === 0) {
    const t = -b / (2 * a);
    return [1, t, t];
  }
  const s = Math.sqrt(D);
  return [2, (-b - s) / (2 * a), (-b + s) / (2 * a)];
}

// JSON has no NaN, infinities or negative zero: those go as strings.
function number(x) {
  if (Object.is(x, -0)) return "-0";
  if (Number.isNaN(x)) return "nan";
  if (!Number.isFinite(x)) return x > 0 ? "inf" : "-inf";
  return x;
}
const value = (x) => (typeof x === "string" ? Number(x.replace("inf", "Infinity").replace("nan", "NaN")) : x);

let header = null;
let cases = [];
const out = [];
readline.createInterface({ input: process.stdin }).on("line", (line) => {
  if (!line.trim()) return;
  if (header === null) {
    header = JSON.parse(line);
    if (header.precision !== "double") throw new Error("naive.js computes in double: export with --precision double");
  } else {
    cases.push(JSON.parse(line));
  }
  if (header !== null && cases.length === header.cases) {
    out.push(JSON.stringify({ rayverify: "results", version: 1, precision: "double", fingerprint: header.fingerprint }));
    for (const c of cases) {
      const v = ["ox", "oy", "oz", "dx", "dy", "dz", "cx", "cy", "cz", "r"].map((k) => value(c[k]));
      const [count, t0, t1] = naive(v.slice(0, 3), v.slice(3, 6), v.slice(6, 9), v[9]);
      out.push(JSON.stringify({ id: c.id, count, t0: number(t0), t1: number(t1) }));
    }
    process.stdout.write(out.join("\n") + "\n");
    out.length = 0;
    header = null;
    cases = [];
  }
});
