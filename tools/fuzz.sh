#!/usr/bin/env bash
# Build the libFuzzer targets (fuzz/, clang, ASan+UBSan) in build-fuzz/ and
# run each for a bounded time, starting from the seed corpora in fuzz/seeds/.
# Usage: tools/fuzz.sh [SECONDS_PER_TARGET [TARGET...]]   (default 60, every target)
# FUZZ_BUILD_DIR=DIR builds in DIR instead of build-fuzz/ (so that two people
# fuzzing in one tree do not share a build).
# A crash or a broken invariant stops the script with a non-zero status and
# leaves the input in build-fuzz/artifacts/<target>/: fix the bug and copy the
# input to fuzz/regressions/<target>/, where tests/fuzz_regression_test.cpp
# replays it on every test run.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
all_targets=(corpus_reader oracle scene_reader baseline_reader results_reader)
targets=("${@:2}")
[ ${#targets[@]} -eq 0 ] && targets=("${all_targets[@]}")
build=${FUZZ_BUILD_DIR:-build-fuzz}

tools/setup.sh --fuzz
# Ninja for a new build directory, as tools/build.sh.
generator=()
[ -f "$build/CMakeCache.txt" ] || generator=(-G Ninja)
# -O1 with line tables, as libFuzzer's and OSS-Fuzz's builds are: every
# sanitizer check stays, a crash's stack names files and lines, and it
# compiles in well under -O2 -g's time.
cmake -S fuzz -B "$build" "${generator[@]}" -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -gline-tables-only -DNDEBUG" >/dev/null
cmake --build "$build" -j "$(nproc)" --target "${targets[@]/#/fuzz_}"

export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
# One target, for the time given: its corpus grows across runs; the seeds stay untouched.
fuzz_one() {
  local target=$1
  local corpus=$build/corpus/$target artifacts=$build/artifacts/$target/
  mkdir -p "$corpus" "$artifacts"
  local inputs=("$corpus" "fuzz/seeds/$target")
  [ -d "fuzz/regressions/$target" ] && inputs+=("fuzz/regressions/$target")  # git keeps no empty folder
  local options=(-max_total_time="$seconds" -timeout=20 -rss_limit_mb=2048 -print_final_stats=1
                 -artifact_prefix="$artifacts")
  [ -f "fuzz/$target.dict" ] && options+=(-dict="fuzz/$target.dict")
  echo "fuzz: $target for ${seconds}s" >&2
  local log=$build/$target.log
  if ! "$build/fuzz_$target" "${options[@]}" "${inputs[@]}" >"$log" 2>&1; then
    tail -n 60 "$log" >&2
    echo "fuzz: $target failed; the input is in $artifacts, the log in $log" >&2
    return 1
  fi
  grep -E '^(Done|stat::number_of_executed_units|stat::peak_rss_mb)' "$log" | sed "s/^/$target: /" >&2 || true
}

# The targets side by side, one per core (each fuzzer is one process, one
# thread): every target still runs for the whole time given.
parallel=$(nproc)
running=0 failed=0
for target in "${targets[@]}"; do
  fuzz_one "$target" &
  running=$((running + 1))
  if [ "$running" -ge "$parallel" ]; then
    wait -n || failed=1
    running=$((running - 1))
  fi
done
while [ "$running" -gt 0 ]; do
  wait -n || failed=1
  running=$((running - 1))
done
exit "$failed"
