#!/usr/bin/env bash
# Each engine port's cost as rayverify compiles it (-O2, the SLP vectoriser
# off: what `rayverify bench` times) and as the engine's own CMake Release
# build compiles the same code (-O3, vectoriser on, no -march), against naive
# double in the same build, with whether the two builds answer alike
# (tools/port_timing/port_timing.cpp says how). A benchmark, not a test: the
# figures are this machine's. The two builds run alternately, three times each,
# and each figure is the median of its three.
# Usage: tools/port_build_benchmark.sh [BUILD_DIR] [SECONDS_PER_PASS]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
seconds=${2:-0.1}
for exe in "$build/port_timing_rayverify" "$build/port_timing_release"; do
  [ -x "$exe" ] || { echo "port_build_benchmark: no $exe (build the project first: tools/build.sh)" >&2; exit 2; }
done
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for round in 1 2 3; do
  "$build/port_timing_rayverify" --seconds "$seconds" > "$work/rayverify.$round"
  "$build/port_timing_release" --seconds "$seconds" > "$work/release.$round"
done
echo "engine ports, ns per test (median of 3 runs) and x naive double of the same build; $(nproc) cores, one thread"
awk '
  function median(a, b, c) { return a < b ? (b < c ? b : (a < c ? c : a)) : (a < c ? a : (b < c ? c : b)) }
  { key = $1 " " $2; build = FILENAME; sub(/.*\//, "", build); sub(/\..*/, "", build)
    run = FILENAME; sub(/.*\./, "", run)
    ns[build, key, run] = $3; sum[build, key] = $4; if (!(key in seen)) { seen[key] = 1; order[++n] = key } }
  END {
    printf "%-22s %-7s %12s %9s %12s %9s %9s  %s\n", "port", "prec", "rayverify_ns", "x_naive", "release_ns", "x_naive", "rel/rv", "answers"
    for (b = 1; b <= 2; ++b) {
      build = b == 1 ? "rayverify" : "release"
      naive[build] = median(ns[build, "naive double", 1], ns[build, "naive double", 2], ns[build, "naive double", 3])
    }
    for (i = 1; i <= n; ++i) {
      key = order[i]
      if (key == "naive double") continue
      rv = median(ns["rayverify", key, 1], ns["rayverify", key, 2], ns["rayverify", key, 3])
      rl = median(ns["release", key, 1], ns["release", key, 2], ns["release", key, 3])
      split(key, part, " ")
      printf "%-22s %-7s %12.2f %8.1fx %12.2f %8.1fx %8.2fx  %s\n", part[1], part[2], rv, rv / naive["rayverify"], rl,
             rl / naive["release"], rl / rv, sum["rayverify", key] == sum["release", key] ? "same" : "DIFFER"
    }
  }' "$work"/rayverify.1 "$work"/rayverify.2 "$work"/rayverify.3 "$work"/release.1 "$work"/release.2 "$work"/release.3
echo "build: rayverify = $(grep -o -- '-O2[^"]*-fno-tree-slp-vectorize' "$build/compile_commands.json" | head -1); release = the same then -O3 -ftree-slp-vectorize"
