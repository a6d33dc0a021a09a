#!/bin/sh
# The audit's speed-up from threads, measured as ratios in one run: PAIRS
# times, the same audit of generated cases on 1 thread and on N (default 2),
# in alternating order, wall-clock time of each and their ratio; the median
# ratio is the figure. Beside it, as the machine's own ceiling, N copies of
# the 1-thread audit run at once against one alone (the speed-up N processes
# get). Every N-thread report is compared byte for byte with the 1-thread one.
#   tools/thread_speedup.sh BUILD_DIR [THREADS] [GENERATE_SPEC] [PAIRS]
# e.g. tools/thread_speedup.sh build 2 uniform:50000 5
set -eu
build=${1:?usage: tools/thread_speedup.sh BUILD_DIR [THREADS] [FAMILY:COUNT[:SEED]] [PAIRS]}
threads=${2:-2}
spec=${3:-uniform:50000}
pairs=${4:-5}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
seconds() { date +%s.%N; }
run() {  # $1 threads, $2 report dir; the exit code (1 = findings) is not a failure here
    "$build/rayverify" audit --generate "$spec" --threads "$1" --report "$work/$2" >"$work/$2.out" || [ $? -eq 1 ]
}
elapsed() {  # seconds taken by the command "$@"
    start=$(seconds)
    "$@"
    awk -v a="$start" -v b="$(seconds)" 'BEGIN { printf "%.3f", b - a }'
}
copies() {  # $1 copies of the 1-thread audit at once
    i=1
    while [ "$i" -le "$1" ]; do run 1 "copy$i" & i=$((i + 1)); done
    wait
}
median() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }

: >"$work/thread_ratios"
: >"$work/process_ratios"
p=1
while [ "$p" -le "$pairs" ]; do
    if [ $((p % 2)) -eq 1 ]; then
        one=$(elapsed run 1 one); many=$(elapsed run "$threads" many)
    else
        many=$(elapsed run "$threads" many); one=$(elapsed run 1 one)
    fi
    cmp -s "$work/one/report.json" "$work/many/report.json" || { echo "report.json differs between 1 and $threads threads"; exit 1; }
    alone=$(elapsed copies 1); together=$(elapsed copies "$threads")
    echo "pair $p: 1 thread $one s, $threads threads $many s; 1 process $alone s, $threads processes at once $together s"
    awk -v a="$one" -v b="$many" 'BEGIN { printf "%.4f\n", a / b }' >>"$work/thread_ratios"
    # N processes do N times the work: their speed-up is N·alone/together.
    awk -v a="$alone" -v b="$together" -v n="$threads" 'BEGIN { printf "%.4f\n", n * a / b }' >>"$work/process_ratios"
    p=$((p + 1))
done
printf "audit --generate %s: %d threads give %.2fx one thread (median of %d pairs, report.json identical); %d processes give %.2fx one (the machine's ceiling, same pairs)\n" \
    "$spec" "$threads" "$(median <"$work/thread_ratios")" "$pairs" "$threads" "$(median <"$work/process_ratios")"
echo "machine: $(nproc) hardware threads; load average $(cut -d' ' -f1-3 /proc/loadavg)"
