#!/usr/bin/env python3
"""How often two targets of one audit give the same answer, case by case.

Usage: tools/same_answers.py PER_CASE.jsonl A B
  PER_CASE.jsonl   `rayverify audit --per-case FILE` with both targets in it
  A, B             target labels as the file names them, e.g. embree3/float embree4/float

Two answers are the same when their count, their t values (as hex floats) and
their hit points (when given) are identical. Prints the share of identical
answers, then the cases whose verdicts differ, counted by (verdict of A,
verdict of B) and by family. Exit 2 on a missing file or target.
"""
import collections
import json
import sys


def answer(result):
    return (result.get("count"), result.get("t0"), result.get("t1"), json.dumps(result.get("hit_point")))


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    path, a, b = sys.argv[1:]
    same = total = 0
    verdicts = collections.Counter()
    differ_by_family = collections.Counter()
    try:
        lines = open(path, encoding="utf-8")
    except OSError as e:
        print(f"same_answers.py: {path}: {e.strerror}", file=sys.stderr)
        sys.exit(2)
    with lines:
        for number, line in enumerate(lines, 1):
            case = json.loads(line)
            results = case["results"]
            if a not in results or b not in results:
                print(f"same_answers.py: {path}:{number}: no result for {a if a not in results else b}", file=sys.stderr)
                sys.exit(2)
            ra, rb = results[a], results[b]
            total += 1
            if answer(ra) == answer(rb):
                same += 1
            else:
                differ_by_family[case.get("family", "-")] += 1
            if ra["verdict"] != rb["verdict"]:
                verdicts[(ra["verdict"], rb["verdict"])] += 1
    print(f"{a} and {b}: {same} of {total} answers identical ({100.0 * same / max(total, 1):.1f}%), "
          f"{total - same} differ; verdicts differ on {sum(verdicts.values())}")
    for family, n in sorted(differ_by_family.items(), key=lambda kv: -kv[1]):
        print(f"  answers differ in {family}: {n}")
    for (va, vb), n in verdicts.most_common():
        print(f"  {a} {va}, {b} {vb}: {n}")


if __name__ == "__main__":
    main()
