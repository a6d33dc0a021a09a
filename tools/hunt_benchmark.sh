#!/usr/bin/env bash
# The hunter against plain random sampling, same family, same seed, same budget.
# Prints: time to the first misclassification of a variant (default naive) in
# float and in double, and the largest ULP error each strategy reaches in the
# budget (default 10 s). Usage: tools/hunt_benchmark.sh [RAYVERIFY] [VARIANT] [FAMILY] [SECONDS]
# A benchmark, not a test: figures depend on the machine; the README records one run.
set -euo pipefail
cd "$(dirname "$0")/.."
rayverify=${1:-build/rayverify}
variant=${2:-naive}
family=${3:-uniform}
budget=${4:-10}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# "find 1: <what> at evaluation N (S s)" -> fields; "-" when nothing was found.
first_find() { grep -m1 '^find 1:' "$1" || true; }

echo "variant $variant, family $family, seed 1, budget ${budget} s per run"
printf '%-7s %-9s %-8s %-44s %s\n' prec objective strategy "result" "evaluations"
for prec in float double; do
  for objective in misclass ulp; do
    for strategy in search random; do
      out="$work/$prec-$objective-$strategy.log"
      set +e
      "$rayverify" hunt --variant "$variant" --precision "$prec" --family "$family" --objective "$objective" \
        --strategy "$strategy" --finds 1 --seconds "$budget" --seed 1 -o "$work/$prec-$objective-$strategy.txt" >"$out"
      code=$?
      set -e
      [ "$code" -le 1 ] || { cat "$out" >&2; exit "$code"; }
      evaluations=$(sed -n 's/.*: \([0-9]*\) evaluations.*/\1/p' "$out" | head -1)
      find=$(first_find "$out")
      if [ -z "$find" ]; then
        result="none in ${budget} s"
      elif [ "$objective" = misclass ]; then
        result=$(echo "$find" | sed -n 's/^find 1: \([a-z_]*\) at evaluation \([0-9]*\) (\([0-9.]*\) s).*/\1 after \3 s (evaluation \2)/p')
      else
        result=$(echo "$find" | sed -n 's/^find 1: agree, \([^ ]*\) ulp.*/max \1 ulp (a lower bound)/p')
      fi
      printf '%-7s %-9s %-8s %-44s %s\n' "$prec" "$objective" "$strategy" "$result" "$evaluations"
    done
  done
done
