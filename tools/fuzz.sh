#!/usr/bin/env bash
# Build the libFuzzer targets (fuzz/, clang, ASan+UBSan) in build-fuzz/ and
# run each for a bounded time, starting from the seed corpora in fuzz/seeds/.
# Usage: tools/fuzz.sh [SECONDS_PER_TARGET]   (default 60)
# A crash or a broken invariant stops the script with a non-zero status and
# leaves the input in build-fuzz/artifacts/<target>/: fix the bug and copy the
# input to fuzz/regressions/<target>/, where tests/fuzz_regression_test.cpp
# replays it on every test run.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}

tools/setup.sh --fuzz
cmake -S fuzz -B build-fuzz -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build build-fuzz -j "$(nproc)" --target fuzz_corpus_reader fuzz_oracle

export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
for target in corpus_reader oracle; do
  corpus=build-fuzz/corpus/$target        # grows across runs; the seeds stay untouched
  artifacts=build-fuzz/artifacts/$target/
  mkdir -p "$corpus" "$artifacts"
  options=(-max_total_time="$seconds" -timeout=20 -rss_limit_mb=2048 -print_final_stats=1
           -artifact_prefix="$artifacts")
  [ -f "fuzz/$target.dict" ] && options+=(-dict="fuzz/$target.dict")
  echo "fuzz: $target for ${seconds}s" >&2
  log=build-fuzz/$target.log
  if ! "build-fuzz/fuzz_$target" "${options[@]}" "$corpus" "fuzz/seeds/$target" "fuzz/regressions/$target" \
       >"$log" 2>&1; then
    tail -n 60 "$log" >&2
    echo "fuzz: $target failed; the input is in $artifacts, the log in $log" >&2
    exit 1
  fi
  grep -E '^(Done|stat::number_of_executed_units|stat::peak_rss_mb)' "$log" >&2 || true
done
