#!/usr/bin/env bash
# The Slurm recipe of docs/scaling_out.md on a real Slurm: an audit submitted
# with tools/slurm/submit_audit.sh as a job array of 4 shards and a dependent
# merge job, waited for with sbatch --wait, must give exactly the files one
# process auditing the whole input writes (report.json, summary.txt,
# report.md, the per-case lines) and its exit code.
#
#   tools/slurm/local_cluster.sh tests/slurm/job_array_test.sh RAYVERIFY
#
# (the CTest test labelled `slurm`; SLURM_CONF must name a running cluster).
set -euo pipefail
rayverify=$1
source_dir="$(cd "$(dirname "$0")/../.." && pwd)"
[ -n "${SLURM_CONF:-}" ] || { echo "job_array_test.sh: SLURM_CONF is not set: run it through tools/slurm/local_cluster.sh" >&2; exit 2; }

work="$(mktemp -d /tmp/rayverify-job-array.XXXXXX)"
trap 'rm -rf "$work"' EXIT
cd "$work"
audit=(audit --generate near_tangent:1500 --generate uniform:1500:7 --generate far_sphere:1000)

status=0
"$source_dir/tools/slurm/submit_audit.sh" --shards 4 --out results --per-case --wait -- "$rayverify" "${audit[@]}" \
  | tee slurm.out || status=$?
single_status=0
"$rayverify" "${audit[@]}" --threads 2 --report single --per-case single/cases.jsonl >single.out || single_status=$?

echo "job array: exit $status; one process: exit $single_status"
[ "$status" -eq "$single_status" ] || { echo "FAIL: the Slurm run exited $status, one process $single_status" >&2; exit 1; }
[ "$status" -le 1 ] || exit 1
for k in 1 2 3 4; do
  grep -q "\"shard\":{\"index\":$k,\"count\":4," "results/shard-$k/shard.json" \
    || { echo "FAIL: results/shard-$k is not shard $k/4" >&2; exit 1; }
done
for file in report.json summary.txt report.md cases.jsonl; do
  cmp "single/$file" "results/merged/$file" || { echo "FAIL: merged $file differs from the single run's" >&2; exit 1; }
done
echo "PASS: 4 array tasks merged into the single run's report.json, summary.txt, report.md and cases.jsonl, byte for byte"
