#!/usr/bin/env bash
# Audits every engine library `rayverify engines` lists, as its package
# installs it, on the shipped corpus, on corpus/edge and on every scene of
# corpus/scenes (all libraries in one audit per scene; a library in another
# precision than the scene's is reported not applicable). CI runs it after
# tools/setup.sh has installed them all.
# Usage: tools/engines_audit.sh [RAYVERIFY]   (default build/rayverify)
# Exit 0 when every library is available and every audit ran (an audit's exit
# 1, disagreements found, is what the audits are for); 2 when a library is not
# available here or an audit fails with an error.
set -euo pipefail
cd "$(dirname "$0")/.."
rayverify=${1:-build/rayverify}
listing=$("$rayverify" engines)
echo "$listing"
# The table's rows: from the header to the count line. A pinned kernel this
# CPU does not run ("not runnable here") is not audited: no CPU runs them all.
rows=$(echo "$listing" | sed '1d' | sed '/^[0-9]* of [0-9]* engine /,$d')
names=$(echo "$rows" | grep -v "not runnable here" | awk '{print $1}')
if echo "$rows" | grep -q "not available"; then
  echo "engines_audit.sh: some engine libraries are not available (tools/setup.sh installs them)" >&2
  exit 2
fi
# A library whose answers depend on the CPU is audited as this CPU runs it and
# with each kernel it can pin that this CPU runs (`rayverify engines` names
# the kernel in each row): its figures are this machine's, not every machine's.
echo "$listing" | grep '^answers depend on the CPU: ' || true
audit() {
  local status=0
  "$rayverify" audit "$@" || status=$?
  if [ "$status" -gt 1 ]; then
    echo "engines_audit.sh: rayverify audit $* failed with exit $status" >&2
    exit 2
  fi
}
engines=()
for name in $names; do
  engines+=(--engine "$name")
  echo "== $name: corpus/ and corpus/edge"
  audit --engine "$name" --corpus corpus
  audit --engine "$name" --corpus corpus/edge
done
for scene in corpus/scenes/*.json; do
  echo "== $scene: every engine library"
  audit --scene "$scene" "${engines[@]}"
done
