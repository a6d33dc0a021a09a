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
  # Left to the default suite: the docs-run test, which checks the documents
  # against the binary (once is enough; its commands' code paths have tests
  # of their own), and the tests labelled external, which run none of
  # rayverify's code (nothing for the sanitizers to check).
  excluded='long|slurm|docs|external'
  # What the engines' libraries keep until the process ends is theirs, not a
  # leak of rayverify's (tools/lsan_suppressions.txt says which libraries).
  export LSAN_OPTIONS="suppressions=$PWD/tools/lsan_suppressions.txt${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
fi
ctest --test-dir "$build_dir" --output-on-failure -j "$(nproc)" -LE "$excluded"
