#!/usr/bin/env bash
# How `rayverify merge` scales with the number of shards. For each N given, the
# same input is audited as N shards (GNU parallel, one thread per shard), the
# N are merged, and the merge's wall time and peak RSS (GNU time) are printed
# with the shards' total state size. The merged report of the largest N is
# checked byte for byte against one process auditing the whole input.
#
#   tools/merge_benchmark.sh RAYVERIFY WORK_DIR "AUDIT ARGS" N...
#   e.g. tools/merge_benchmark.sh build/rayverify /tmp/mb "--generate uniform:1000000" 10 100 1000
#
# WORK_DIR is created and left in place (delete it afterwards); shards already
# there from an earlier run with the same arguments are merged again, not
# audited again. docs/scaling_out.md shows a run.
set -euo pipefail
[ $# -ge 4 ] || { sed -n '2,12p' "$0" >&2; exit 2; }
rayverify="$(cd "$(dirname "$1")" && pwd)/$(basename "$1")"
work=$2
read -r -a audit <<<"$3"
shift 3
command -v parallel >/dev/null || { echo "merge_benchmark.sh: needs GNU parallel (tools/setup.sh)" >&2; exit 2; }
[ -x /usr/bin/time ] || { echo "merge_benchmark.sh: needs GNU time (Debian package time)" >&2; exit 2; }
mkdir -p "$work"
cd "$work"

echo "| shards | state per shard (MiB) | all states (MiB) | merge CPU time (s) | merge wall time (s) | merge peak RSS (MiB) |"
echo "|---:|---:|---:|---:|---:|---:|"
largest=0
for n in "$@"; do
  rm -rf "merged-$n"
  if [ "$(ls "shards-$n"/*/shard.json 2>/dev/null | wc -l)" -ne "$n" ]; then
    rm -rf "shards-$n"
    seq 1 "$n" | parallel --will-cite -j "$(nproc)" \
      "$rayverify" audit "${audit[@]}" --threads 1 --shard {}/"$n" --report "shards-$n/{}" '>/dev/null' '||' '[ $? -eq 1 ]'
  fi
  bytes=$(cat "shards-$n"/*/shard.json | wc -c)
  status=0
  /usr/bin/time -f '%e %U %S %M' -o "time-$n.txt" "$rayverify" merge -o "merged-$n" "shards-$n"/* >/dev/null || status=$?
  [ "$status" -le 1 ] || { echo "merge_benchmark.sh: the merge of $n shards failed ($status)" >&2; exit 1; }
  read -r wall user system kib < <(tail -n 1 "time-$n.txt")  # after "Command exited with non-zero status 1"
  awk -v n="$n" -v b="$bytes" -v w="$wall" -v c="$user + $system" -v k="$kib" \
    'BEGIN { split(c, t, " + "); printf "| %d | %.2f | %.0f | %.2f | %.2f | %.0f |\n", n, b / n / 1048576, b / 1048576,
             t[1] + t[2], w, k / 1024 }'
  [ "$n" -gt "$largest" ] && largest=$n
done

[ -f single/report.json ] || "$rayverify" audit "${audit[@]}" --report single >/dev/null || [ $? -eq 1 ]
for file in report.json summary.txt report.md; do
  cmp -s "single/$file" "merged-$largest/$file" || { echo "merge_benchmark.sh: $file of $largest shards differs from one process's" >&2; exit 1; }
done
echo
echo "The merge of $largest shards wrote the same report.json, summary.txt and report.md as one process."
echo "$(nproc) CPUs; load average at the end: $(cut -d' ' -f1-3 /proc/loadavg)"
