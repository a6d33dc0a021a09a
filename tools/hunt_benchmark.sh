#!/usr/bin/env bash
# The hunter against plain random sampling, same family, same seed, same budget,
# and its speed in evaluations per second.
#
# Usage: tools/hunt_benchmark.sh [RAYVERIFY] [VARIANT] [FAMILY] [SECONDS] [BASELINE]
#
# First table: time to the first misclassification of a variant (default naive)
# in float and in double, and the largest ULP error each strategy reaches in the
# budget (default 10 s).
# Second table: evaluations per second of search time, per precision, objective
# and strategy (misclass runs keep searching past their finds, unshrunk). With
# BASELINE, another build's rayverify runs the same hunts, each right beside
# this build's, and the ratio is checked against the target of at least 3x the
# baseline (met / MISSED); a missed target is followed by what meeting it needs,
# from the same run's figures (the exact oracle's cost from `bench --oracle`).
# A benchmark, not a test: figures depend on the machine; docs/hunt.md records one run.
set -euo pipefail
cd "$(dirname "$0")/.."
rayverify=${1:-build/rayverify}
variant=${2:-naive}
family=${3:-uniform}
budget=${4:-10}
baseline=${5:-}
target_ratio=3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for program in "$rayverify" ${baseline:+"$baseline"}; do
  [ -x "$program" ] || { echo "hunt_benchmark.sh: $program: not an executable rayverify" >&2; exit 2; }
done

# "find 1: <what> at evaluation N (S s)" -> fields; "-" when nothing was found.
first_find() { grep -m1 '^find 1:' "$1" || true; }

# run_hunt PROGRAM LOG PREC OBJECTIVE STRATEGY FINDS [OPTION...]: one hunt, its
# output in LOG; exits on anything but 0 (nothing found) or 1 (findings).
run_hunt() {
  local program=$1 log=$2 prec=$3 objective=$4 strategy=$5 finds=$6
  shift 6
  set +e
  "$program" hunt --variant "$variant" --precision "$prec" --family "$family" --objective "$objective" \
    --strategy "$strategy" --finds "$finds" --seconds "$budget" --seed 1 -o "$log.txt" "$@" >"$log"
  local code=$?
  set -e
  [ "$code" -le 1 ] || { cat "$log" >&2; exit "$code"; }
}

# "...: N evaluations, M starts, S s" -> N / S.
evaluations_per_second() {
  sed -n 's/.*: \([0-9]*\) evaluations, [0-9]* starts, \([0-9.]*\) s$/\1 \2/p' "$1" | head -1 |
    awk '{ if ($2 > 0) printf "%.0f", $1 / $2; else print 0 }'
}

echo "variant $variant, family $family, seed 1, budget ${budget} s per run"
printf '%-7s %-9s %-8s %-44s %s\n' prec objective strategy "result" "evaluations"
for prec in float double; do
  for objective in misclass ulp; do
    for strategy in search random; do
      out="$work/$prec-$objective-$strategy.log"
      run_hunt "$rayverify" "$out" "$prec" "$objective" "$strategy" 1
      evaluations=$(sed -n 's/.*: \([0-9]*\) evaluations.*/\1/p' "$out" | head -1)
      find=$(first_find "$out")
      if [ -z "$find" ]; then
        result="none in ${budget} s"
      elif [ "$objective" = misclass ]; then
        result=$(echo "$find" | sed -n 's/^find 1: \([a-z_]*\)\( ([a-z_]*)\)\{0,1\} at evaluation \([0-9]*\) (\([0-9.]*\) s).*/\1 after \4 s (evaluation \3)/p')
      else
        result=$(echo "$find" | sed -n 's/^find 1: agree, \([^ ]*\) ulp.*/max \1 ulp (a lower bound)/p')
      fi
      printf '%-7s %-9s %-8s %-44s %s\n' "$prec" "$objective" "$strategy" "$result" "$evaluations"
    done
  done
done

echo
echo "evaluations per second of search time (misclass: searching on past its finds, unshrunk)"
if [ -n "$baseline" ]; then
  printf '%-7s %-9s %-8s %12s %12s %8s\n' prec objective strategy "this build" "baseline" ratio
else
  printf '%-7s %-9s %-8s %12s\n' prec objective strategy "this build"
fi
rows=()
for prec in float double; do
  for objective in misclass ulp; do
    for strategy in search random; do
      log="$work/rate-$prec-$objective-$strategy"
      run_hunt "$rayverify" "$log.new" "$prec" "$objective" "$strategy" 1000000 --no-shrink
      new_rate=$(evaluations_per_second "$log.new")
      if [ -z "$baseline" ]; then
        printf '%-7s %-9s %-8s %12s\n' "$prec" "$objective" "$strategy" "$new_rate"
        continue
      fi
      run_hunt "$baseline" "$log.old" "$prec" "$objective" "$strategy" 1000000 --no-shrink
      old_rate=$(evaluations_per_second "$log.old")
      ratio=$(awk -v n="$new_rate" -v o="$old_rate" 'BEGIN { if (o > 0) printf "%.2f", n / o; else print "inf" }')
      printf '%-7s %-9s %-8s %12s %12s %7sx\n' "$prec" "$objective" "$strategy" "$new_rate" "$old_rate" "$ratio"
      rows+=("$prec $objective $strategy $new_rate $old_rate $ratio")
    done
  done
done
[ -n "$baseline" ] || exit 0

# The exact oracle's cost per case of the family (double inputs), this run.
oracle_ns=$("$rayverify" bench --oracle --family "$family" --repetitions 3 2>/dev/null |
  awk -v f="$family" '$1 == f { print $4 }')
echo
echo "targets, this run (evaluations per second against the baseline's):"
for row in "${rows[@]}"; do
  read -r prec objective strategy new_rate old_rate ratio <<<"$row"
  verdict=$(awk -v r="$ratio" -v t="$target_ratio" 'BEGIN { print (r >= t) ? "met" : "MISSED" }')
  printf '  hunt %-6s %-8s %-6s %6sx  target >= %sx  %s\n' "$prec" "$objective" "$strategy" "$ratio" "$target_ratio" "$verdict"
  [ "$verdict" = MISSED ] || continue
  awk -v n="$new_rate" -v o="$old_rate" -v t="$target_ratio" -v oracle="${oracle_ns:-0}" -v f="$family" 'BEGIN {
    now = 1e9 / n; need = 1e9 / (t * o); rest = now - oracle;
    printf "      needs an evaluation in %.0f ns, not %.0f (%.0f%% less); the exact oracle alone takes %.0f ns a case of %s (bench --oracle, this run), the rest of an evaluation (drawing or moving the case, the variant, the verdict, the error'"'"'s bracket, the bookkeeping) %.0f ns: ", need, now, 100 * (1 - need / now), oracle, f, rest;
    if (oracle >= need)
      print "the oracle alone is over the budget, so meeting it needs a cheaper certified answer first (docs/oracle.md: the class and signs up front, roots and hit point rounded only when asked), then the rest cut to fit";
    else
      printf "the rest must fall to %.0f ns, which needs (docs/hunt.md) a solution that rounds roots and hit point only when asked and only to the precision asked (the search walks to ill-conditioned cases, where the oracle costs more than on the family'"'"'s own) and, for random sampling, a generator without a per-case seeding of its random engine\n", need - oracle;
  }'
done
