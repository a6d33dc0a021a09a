#!/bin/sh
# The audit's speed-up from threads, measured in one run: the same audit of
# generated cases on 1 thread, then on N (default 2), wall-clock time of
# each and their ratio; the two reports are compared byte for byte.
#   tools/thread_speedup.sh BUILD_DIR [THREADS] [GENERATE_SPEC]
# e.g. tools/thread_speedup.sh build 2 uniform:20000
set -eu
build=${1:?usage: tools/thread_speedup.sh BUILD_DIR [THREADS] [FAMILY:COUNT[:SEED]]}
threads=${2:-2}
spec=${3:-uniform:20000}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
seconds() { date +%s.%N; }
run() {  # $1 threads, $2 report dir; the exit code (1 = findings) is not a failure here
    "$build/rayverify" audit --generate "$spec" --threads "$1" --report "$work/$2" >"$work/$2.out" || [ $? -eq 1 ]
}
t0=$(seconds); run 1 one; t1=$(seconds); run "$threads" many; t2=$(seconds)
cmp -s "$work/one/report.json" "$work/many/report.json" || { echo "report.json differs between 1 and $threads threads"; exit 1; }
awk -v a="$t0" -v b="$t1" -v c="$t2" -v n="$threads" -v spec="$spec" 'BEGIN {
    printf "audit --generate %s: 1 thread %.2f s, %d threads %.2f s, speed-up %.2fx (report.json identical)\n",
           spec, b - a, n, c - b, (b - a) / (c - b) }'
echo "machine: $(nproc) hardware threads; load average $(cut -d' ' -f1-3 /proc/loadavg)"
