#!/usr/bin/env bash
# Submit a rayverify audit to Slurm: a job array of N shards, and a merge job
# that runs once every shard has succeeded.
#
#   tools/slurm/submit_audit.sh [--shards N] [--out DIR] [--per-case] [--wait]
#                               [--sbatch "SBATCH OPTIONS"] -- RAYVERIFY audit ARGS...
#
#   --shards N   array tasks, one shard each (default 8)
#   --out DIR    results (default rayverify-audit): DIR/shard-K per task,
#                DIR/merged the merged report, DIR/logs the jobs' output
#   --per-case   also write and merge the per-case lines (DIR/merged/cases.jsonl)
#   --wait       return when the merge job has ended, print its output, and
#                exit with its code: 0 no findings, 1 findings, else a failure
#   --sbatch     more options for both sbatch calls (partition, account, time)
#
# Task K runs tools/slurm/audit_shard.sbatch: `RAYVERIFY audit ARGS... --shard
# auto` in DIR/shard-K; the merge job (tools/slurm/merge.sbatch) runs
# `RAYVERIFY merge --report DIR/merged DIR/shard-*` after all of them (afterok: a
# failed shard cancels it). docs/scaling_out.md shows a run.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"

shards=8
out=rayverify-audit
per_case=()
wait=()
extra=()
while [ $# -gt 0 ]; do
  case "$1" in
    --shards) shards=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --per-case) per_case=(--per-case); shift ;;
    --wait) wait=(--wait); shift ;;
    --sbatch) read -r -a extra <<<"$2"; shift 2 ;;
    --) shift; break ;;
    *) echo "submit_audit.sh: unknown option '$1' (see the comment at the top of $0)" >&2; exit 2 ;;
  esac
done
if [ $# -lt 2 ] || [ "$2" != audit ]; then
  echo "submit_audit.sh: give the audit after --, e.g. -- rayverify audit --generate uniform:1000000" >&2
  exit 2
fi
if ! [[ "$shards" =~ ^[1-9][0-9]*$ ]]; then
  echo "submit_audit.sh: --shards '$shards' is not a whole number >= 1" >&2
  exit 2
fi
mkdir -p "$out/logs"
out="$(cd "$out" && pwd)"

array=$(sbatch --parsable "${extra[@]}" --array="1-$shards" --output="$out/logs/audit-%A_%a.out" \
  "$here/audit_shard.sbatch" "$out" "${per_case[@]}" "$@")
array=${array%%;*}
echo "submitted the audit as job array $array (tasks 1-$shards)"
status=0
merge=$(sbatch --parsable "${extra[@]}" "${wait[@]}" --dependency="afterok:$array" --kill-on-invalid-dep=yes \
  --output="$out/logs/merge-%j.out" "$here/merge.sbatch" "$out" "${per_case[@]}" "$1") || status=$?
merge=${merge%%;*}
if [ ${#wait[@]} -eq 0 ]; then
  echo "submitted the merge as job $merge; it writes $out/merged once every shard has succeeded"
  exit 0
fi
echo "merge job $merge ended with exit code $status"
if [ -f "$out/logs/merge-$merge.out" ]; then
  cat "$out/logs/merge-$merge.out"
else  # cancelled: some shard failed
  for log in "$out"/logs/audit-"$array"_*.out; do
    [ -s "$log" ] && { echo "== $log"; tail -n 5 "$log"; }
  done
fi
exit "$status"
