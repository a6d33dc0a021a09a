#!/usr/bin/env bash
# Set up, build and run the whole default test suite through CTest.
# Usage: tools/test.sh [--sanitize]   (ASan+UBSan build in build-sanitize/)
# The long randomized sweeps are labelled "long" (ctest --test-dir build -L long),
# the test on a real Slurm "slurm" (tools/setup.sh --slurm; ctest --test-dir build -L slurm).
set -euo pipefail
cd "$(dirname "$0")/.."
tools/build.sh "$@"
build_dir=build
[ "${1:-}" = "--sanitize" ] && build_dir=build-sanitize
ctest --test-dir "$build_dir" --output-on-failure -j "$(nproc)" -LE 'long|slurm'
