// rayverify's exchange protocol (JSON lines, schema version 1) for the
// JavaScript engine adapters: read batches of cases on standard input, answer
// each batch with a complete results batch on standard output.
//
//   node engines/js/three.mjs < cases.jsonl > answers.jsonl
//       (rayverify corpus export --format jsonl --precision double), or
//   rayverify hunt --command 'node engines/js/three.mjs' --format jsonl ...
//
// A batch is a header line {"rayverify": "cases", "version": 1, "precision",
// "fingerprint", "cases": K} and then K case lines (id, family, ox … r, tmin,
// tmax); the answer is a header line {"rayverify": "results", "version": 1}
// repeating the batch's precision and fingerprint, then one line per case, in
// the cases' order: {"id", "count", "t0"?, "hit_point"?}. Batches repeat until
// the end of input (docs/other-languages.md, docs/schema/rayverify-exchange-v1.json).
//
// An adapter calls serve() with its engine's name, its package, the precision
// it computes in and an `answer` function from one case to one answer. A
// batch in another precision is refused (a message on stderr, exit 2): the
// engine computes in one precision, and answers judged in the other would
// audit a conversion, not the engine. `--version` prints the installed
// package's version (from its package.json in node_modules).
import { createRequire } from "node:module";
import { readFileSync, existsSync } from "node:fs";
import { dirname, join } from "node:path";
import { createInterface } from "node:readline";

const require = createRequire(import.meta.url);

// The version of `pkg` as installed: its package.json, found by walking up
// from the file node resolves the package to (a package's "exports" may not
// export ./package.json, so it is read as a file, not required).
export function installedVersion(pkg) {
  let dir = dirname(require.resolve(pkg));
  for (;;) {
    const file = join(dir, "package.json");
    if (existsSync(file)) {
      const json = JSON.parse(readFileSync(file, "utf8"));
      if (json.name === pkg) return json.version;
    }
    const up = dirname(dir);
    if (up === dir) throw new Error(`no package.json of ${pkg} above ${require.resolve(pkg)}`);
    dir = up;
  }
}

// A C99 hex float ("0x1.8p+1", "-0x0p+0"), read exactly (the export's
// --numbers hex writes only values of its precision, 53 bits at most).
export function hexFloat(text) {
  const m = /^([-+]?)0[xX]([0-9a-fA-F]*)\.?([0-9a-fA-F]*)(?:[pP]([-+]?[0-9]+))?$/.exec(text);
  if (!m || (m[2] === "" && m[3] === "")) return NaN;
  const mantissa = BigInt("0x" + (m[2] + m[3] || "0"));
  let exponent = (m[4] ? Number(m[4]) : 0) - 4 * m[3].length;
  let x = Number(mantissa); // exact: at most 53 significant bits
  // Scale in steps so that no step under- or overflows on its own.
  while (exponent > 0) {
    const step = Math.min(exponent, 1000);
    x *= 2 ** step;
    exponent -= step;
  }
  while (exponent < 0) {
    const step = Math.max(exponent, -1000);
    x *= 2 ** step;
    exponent -= step;
  }
  return m[1] === "-" ? -x : x;
}

// A case's number: a JSON number, or a string ("nan", "inf", "-inf", "-0", a
// hex float, a decimal), rounded to the batch's precision (a float export's
// shortest decimals read back as float32 through Math.fround).
function caseNumber(v, precision, field) {
  let x;
  if (typeof v === "number") x = v;
  else if (typeof v === "string") {
    const s = v.trim().toLowerCase();
    if (s === "nan" || s === "+nan" || s === "-nan") x = NaN;
    else if (/^[-+]?inf(inity)?$/.test(s)) x = s.startsWith("-") ? -Infinity : Infinity;
    else if (/^[-+]?0x/.test(s)) x = hexFloat(s);
    else x = s === "" ? NaN : Number(s);
  } else throw new Error(`field '${field}': not a number: ${JSON.stringify(v)}`);
  if (Number.isNaN(x) && typeof v === "string" && !/nan/i.test(v)) throw new Error(`field '${field}': not a number: ${JSON.stringify(v)}`);
  return precision === "float" ? Math.fround(x) : x;
}

// JSON has no NaN, infinities or negative zero: those go as strings.
export function jsonNumber(x) {
  if (Object.is(x, -0)) return "-0";
  if (Number.isNaN(x)) return "nan";
  if (!Number.isFinite(x)) return x > 0 ? "inf" : "-inf";
  return x;
}

// One case as the adapters receive it: o, d, c as [x, y, z], r, the case's
// interval (tmin, tmax; null where the case has none), and for a segment case
// p1 = [x, y, z], its end as given (o is then p0; null for a ray case).
export function parseCase(line, precision) {
  const j = JSON.parse(line);
  if (typeof j.id !== "string") throw new Error("a case without an id: " + line);
  const n = (k) => caseNumber(j[k], precision, k);
  return {
    id: j.id,
    o: [n("ox"), n("oy"), n("oz")],
    d: [n("dx"), n("dy"), n("dz")],
    c: [n("cx"), n("cy"), n("cz")],
    r: n("r"),
    tmin: j.tmin === null || j.tmin === undefined ? null : n("tmin"),
    tmax: j.tmax === null || j.tmax === undefined ? null : n("tmax"),
    p1: j.p1x === undefined ? null : [n("p1x"), n("p1y"), n("p1z")],
  };
}

// One answer line: {count, t0?, point?} from the adapter.
export function formatAnswer(id, a) {
  const out = { id, count: a.count };
  if (a.t0 !== undefined && a.t0 !== null) out.t0 = jsonNumber(a.t0);
  if (a.point) out.hit_point = a.point.map(jsonNumber);
  return JSON.stringify(out);
}

function fail(name, message) {
  process.stderr.write(`${name}: ${message}\n`);
  process.exit(2);
}

// Run the adapter: `engine` {name, package, precision, answer(case), setup?()}.
// setup() (may be async) runs once before the first batch; answer() may
// return a value or a promise.
export async function serve(engine) {
  const args = process.argv.slice(2);
  if (args.includes("--version")) {
    process.stdout.write(installedVersion(engine.package) + "\n");
    return;
  }
  if (args.includes("--help") || args.length > 0) {
    const text =
      `usage: node engines/js/${engine.adapter} [--version] < cases.jsonl > answers.jsonl\n` +
      `${engine.package} ${engine.api} in ${engine.precision}; contract ${engine.contract}\n`;
    if (args.includes("--help")) return void process.stdout.write(text);
    fail(engine.name, `unknown argument '${args.find((a) => a !== "--help")}'\n${text}`);
  }
  if (engine.setup) await engine.setup();

  let header = null;
  let lineNo = 0;
  let out = [];
  const rl = createInterface({ input: process.stdin, crlfDelay: Infinity });
  const flush = () => {
    process.stdout.write(out.join("\n") + "\n");
    out = [];
    header = null;
  };
  for await (const line of rl) {
    ++lineNo;
    if (!line.trim()) continue;
    let j;
    if (header === null) {
      try {
        j = JSON.parse(line);
      } catch (e) {
        fail(engine.name, `stdin:${lineNo}: not a JSON header line: ${e.message}`);
      }
      if (j.rayverify !== "cases" || j.version !== 1)
        fail(engine.name, `stdin:${lineNo}: expected a header {"rayverify": "cases", "version": 1, ...}, got ${line.slice(0, 200)}`);
      if (j.precision !== engine.precision)
        fail(
          engine.name,
          `stdin:${lineNo}: the cases are in ${j.precision}, but ${engine.package} computes in ${engine.precision}: ` +
            `export them with --precision ${engine.precision} (hunt: --precision ${engine.precision})`,
        );
      if (!Number.isInteger(j.cases) || j.cases < 0) fail(engine.name, `stdin:${lineNo}: the header's 'cases' is not a count`);
      header = j;
      header.seen = 0;
      out.push(JSON.stringify({ rayverify: "results", version: 1, precision: j.precision, fingerprint: j.fingerprint }));
      if (header.cases === 0) flush();
      continue;
    }
    let c;
    try {
      c = parseCase(line, header.precision);
    } catch (e) {
      fail(engine.name, `stdin:${lineNo}: ${e.message}`);
    }
    let a;
    try {
      a = await engine.answer(c);
    } catch (e) {
      fail(engine.name, `stdin:${lineNo}: case ${c.id}: ${engine.api} threw: ${e && e.stack ? e.stack : e}`);
    }
    out.push(formatAnswer(c.id, a));
    if (++header.seen === header.cases) flush();
  }
  if (header !== null) fail(engine.name, `end of input after ${header.seen} of the batch's ${header.cases} cases`);
}

// The segment length a segment engine gets for a ray without tmax, as
// rayverify's segment_length() (src/core/intersection.h) computes it: a power
// of two L with L·|d|∞ ≥ 2(|o − c|₁ + r), so every root t* (|t*|·|d| ≤
// |o − c| + r) lies within [−L, L]; capped where L·|d|∞ would pass a quarter
// of the precision's largest value. Scaling d by L is exact.
export function segmentLength(o, d, c, r, precision) {
  let extent = r;
  let reach = 0;
  for (let k = 0; k < 3; ++k) {
    extent += Math.abs(o[k] - c[k]);
    reach = Math.max(reach, Math.abs(d[k]));
  }
  if (!(extent > 0) || !(reach > 0) || !Number.isFinite(extent / reach)) return 1;
  const wanted = ilogb(extent / reach) + 2;
  const max = precision === "float" ? 3.4028234663852886e38 : Number.MAX_VALUE;
  const cap = ilogb(max / 4) - ilogb(reach) - 1;
  return 2 ** Math.min(wanted, cap);
}

// floor(log2(|x|)) for a finite nonzero x, exactly (subnormals included).
export function ilogb(x) {
  x = Math.abs(x);
  let e = Math.floor(Math.log2(x));
  // log2 may be off by one next to a power of two: correct it exactly.
  if (2 ** e > x) --e;
  else if (2 ** (e + 1) <= x) ++e;
  return e;
}

// The adapter's entry in engines.json (name, library, package, adapter,
// precision, contract, api): one source for the catalogue and the adapters.
export function manifestEntry(name) {
  const file = join(dirname(new URL(import.meta.url).pathname), "engines.json");
  const entry = JSON.parse(readFileSync(file, "utf8")).find((e) => e.name === name);
  if (!entry) throw new Error(`${file}: no engine named '${name}'`);
  return entry;
}
