#!/usr/bin/env bash
# Set up, build and run the whole default test suite through CTest.
# Usage: tools/test.sh [--sanitize]   (ASan+UBSan build in build-sanitize/)
# The long randomized sweeps are labelled "long" (ctest --test-dir build -L long),
# the test on a real Slurm "slurm" (tools/setup.sh --slurm; ctest --test-dir build -L slurm).
set -euo pipefail
cd "$(dirname "$0")/.."
tools/build.sh "$@"
build_dir=build
excluded='long|slurm'
if [ "${1:-}" = "--sanitize" ]; then
  build_dir=build-sanitize
  # The docs-run test checks the documents against the binary: once, in the
  # default suite, is enough (its commands' code paths have tests of their own).
  excluded='long|slurm|docs'
  # What the engines' libraries keep until the process ends is theirs, not a
  # leak of rayverify's (tools/lsan_suppressions.txt says which libraries).
  export LSAN_OPTIONS="suppressions=$PWD/tools/lsan_suppressions.txt${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
fi
ctest --test-dir "$build_dir" --output-on-failure -j "$(nproc)" -LE "$excluded"
