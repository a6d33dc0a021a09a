#!/usr/bin/env bash
# The main job: set up, build, and audit the shipped corpus with every variant
# in float and double. Prints the summary table; writes report/report.json,
# report/summary.txt and report/cases.jsonl (one line per case).
# Extra arguments go to `rayverify audit` (e.g. --variant naive).
# Exit status is rayverify's: 0 no disagreement, 1 findings, 2 input error.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/build.sh >/dev/null
mkdir -p report
exec build/rayverify audit --corpus corpus --report report --plots --per-case report/cases.jsonl "$@"
