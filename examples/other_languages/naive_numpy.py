"""The textbook quadratic (rayverify's built-in `naive`) in NumPy float32,
audited by rayverify through a results file or as a hunted command.

  python3 naive_numpy.py cases.npy answers.npy
      reads `rayverify corpus export --format npy --precision float` output
      (cases.npy and its companion cases.json) and writes answers.npy with
      its companion answers.json;
  python3 naive_numpy.py --jsonl
      reads batches of cases as JSON lines on stdin (a whole exported .jsonl
      file, or `rayverify hunt --command ... --format jsonl`) and writes one
      results batch per batch on stdout.

Contract: query=line_roots,reports_tangent=yes (both roots of the line).
"""
import json
import math
import sys

import numpy as np

F = np.float32


def naive(o, d, c, r):
    """Rows of float32 inputs -> count, t0, t1 (float32), evaluated as the C
    code does: f = o - c, a = d.d, b = 2 d.f, C = f.f - r^2, D = b^2 - 4aC."""
    f = o - c
    a = (d[:, 0] * d[:, 0] + d[:, 1] * d[:, 1]) + d[:, 2] * d[:, 2]
    b = F(2) * ((d[:, 0] * f[:, 0] + d[:, 1] * f[:, 1]) + d[:, 2] * f[:, 2])
    C = ((f[:, 0] * f[:, 0] + f[:, 1] * f[:, 1]) + f[:, 2] * f[:, 2]) - r * r
    D = b * b - F(4) * a * C
    with np.errstate(all="ignore"):
        s = np.sqrt(D)
        two_a = F(2) * a
        tangent = -b / two_a
        t0 = np.where(D == 0, tangent, (-b - s) / two_a)
        t1 = np.where(D == 0, tangent, (-b + s) / two_a)
    count = np.where(D < 0, 0, np.where(D == 0, 1, 2))
    return count, t0.astype(F), t1.astype(F)


def files(cases_path, answers_path):
    meta = json.load(open(cases_path[:-4] + ".json"))
    if meta["precision"] != "float":
        sys.exit("naive_numpy: this intersector computes in float32: export with --precision float")
    x = np.load(cases_path)
    count, t0, t1 = naive(x[:, 0:3], x[:, 3:6], x[:, 6:9], x[:, 9])
    np.save(answers_path, np.stack([count.astype(F), t0, t1], axis=1))
    with open(answers_path[:-4] + ".json", "w") as out:
        json.dump({"rayverify": "results", "version": 1, "precision": "float",
                   "fingerprint": meta["fingerprint"], "columns": ["count", "t0", "t1"],
                   "ids": meta["ids"]}, out)


def number(x):
    x = float(x)  # a float32 widened exactly
    return x if math.isfinite(x) else str(x)  # "nan", "inf", "-inf"


def batches():
    lines = (line for line in sys.stdin if line.strip())
    for text in lines:
        header = json.loads(text)
        if header.get("precision") != "float":
            sys.exit("naive_numpy: this intersector computes in float32")
        cases = [json.loads(next(lines)) for _ in range(header["cases"])]
        v = np.array([[float(c[k]) for k in ("ox", "oy", "oz", "dx", "dy", "dz", "cx", "cy", "cz", "r")]
                      for c in cases], dtype=F).reshape(-1, 10)
        count, t0, t1 = naive(v[:, 0:3], v[:, 3:6], v[:, 6:9], v[:, 9])
        out = [json.dumps({"rayverify": "results", "version": 1, "precision": "float",
                           "fingerprint": header["fingerprint"]})]
        for c, n, a, b in zip(cases, count, t0, t1):
            out.append(json.dumps({"id": c["id"], "count": int(n), "t0": number(a), "t1": number(b)}))
        sys.stdout.write("\n".join(out) + "\n")
        sys.stdout.flush()


if __name__ == "__main__":
    if sys.argv[1:] == ["--jsonl"]:
        batches()
    elif len(sys.argv) == 3:
        files(sys.argv[1], sys.argv[2])
    else:
        sys.exit(__doc__)
