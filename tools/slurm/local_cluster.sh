#!/usr/bin/env bash
# Run a command inside a throwaway single-node Slurm cluster on this machine:
#
#   tools/slurm/local_cluster.sh COMMAND [ARGS...]
#
# e.g. tools/slurm/local_cluster.sh tools/slurm/submit_audit.sh --wait -- build/rayverify audit
# to try the recipe of docs/scaling_out.md; the CTest test labelled `slurm` runs
# tests/slurm/job_array_test.sh this way. Needs Debian 12's slurm-wlm and munge
# (tools/setup.sh --slurm) and root: Slurm 22.05 runs here with SlurmUser=root,
# AuthType=auth/munge, ProctrackType=proctrack/linuxproc, TaskPlugin=task/none.
#
# Everything lives in a new temporary directory: munged with its own key and
# socket; slurmctld and slurmd from a generated slurm.conf (SLURM_CONF points at
# it, for the daemons and the COMMAND) with free loopback ports, their own
# spool, state, logs and an empty plugstack.conf. The machine's /etc/slurm and
# /etc/munge are neither read nor changed. On exit, however it comes, a trap
# cancels what is left in the queue, stops every daemon this script started,
# by pid, and removes the directory; then it checks that none of those
# processes, no job step and no file outside the directory is left, and fails
# if one is. Exit status: the COMMAND's (above 1, the daemons' last log lines
# are printed), or 3 when the cluster did not start or did not clean up.
# COMMAND gets RAYVERIFY_SLURM_TIMEOUT seconds (default 300).
set -uo pipefail

fail() { echo "local_cluster.sh: $*" >&2; exit 3; }
[ "$#" -ge 1 ] || fail "usage: $0 COMMAND [ARGS...]"
[ "$(id -u)" -eq 0 ] || fail "needs root (Slurm 22.05 runs here with SlurmUser=root)"
for tool in munged mungekey munge slurmctld slurmd sbatch sinfo scancel python3; do
  command -v "$tool" >/dev/null || fail "$tool not found: install Slurm and MUNGE with tools/setup.sh --slurm"
done

# What exists before we start, to tell afterwards what we left.
snapshot() {
  find /var/spool /var/lib/slurm /var/lib/munge /var/log/slurm /var/log/munge /etc/slurm /etc/munge -maxdepth 3 \
    2>/dev/null | sort
  find /run /dev/shm /tmp -maxdepth 2 \( -iname '*slurm*' -o -iname '*munge*' \) 2>/dev/null | sort
}
steps_before=" $(pgrep -x slurmstepd | tr '\n' ' ') "
files_before="$(snapshot)"

cluster="$(mktemp -d /tmp/rayverify-slurm.XXXXXX)"
chmod 755 "$cluster"  # munged requires its socket's directory to be searchable by all
pids=()               # daemons started here, stopped in reverse order

cleanup() {
  local status=$? leftover="" new_steps step
  trap - EXIT INT TERM
  if [ -f "$cluster/slurm.conf" ] && [ ${#pids[@]} -ge 2 ]; then
    scancel --quiet --full "--user=$(id -un)" 2>/dev/null
    for _ in $(seq 1 30); do
      [ -z "$(squeue -h 2>/dev/null)" ] && break
      sleep 1
    done
  fi
  # A job's slurmstepd outlives the job's end by a moment (its own cleanup).
  for _ in $(seq 1 40); do
    new_steps=""
    for step in $(pgrep -x slurmstepd); do
      case "$steps_before" in *" $step "*) ;; *) new_steps+=" $step" ;; esac
    done
    [ -z "$new_steps" ] && break
    sleep 0.5
  done
  for ((i = ${#pids[@]} - 1; i >= 0; i--)); do
    kill "${pids[i]}" 2>/dev/null
    for _ in $(seq 1 50); do
      kill -0 "${pids[i]}" 2>/dev/null || break
      sleep 0.2
    done
    if kill -0 "${pids[i]}" 2>/dev/null; then
      leftover+=" daemon ${pids[i]} (killed)"
      kill -KILL "${pids[i]}" 2>/dev/null
    fi
    wait "${pids[i]}" 2>/dev/null
  done
  for step in $(pgrep -x slurmstepd); do
    case "$steps_before" in *" $step "*) ;; *) leftover+=" slurmstepd $step (killed)"; kill -KILL "$step" ;; esac
  done
  for pid in $(pgrep -f "$cluster"); do leftover+=" process $pid ($(ps -o args= -p "$pid"))"; kill -KILL "$pid"; done
  if [ "$status" -gt 1 ] && [ -d "$cluster" ]; then  # 1: an audit's findings, no failure
    for log in "$cluster"/*.log; do
      [ -s "$log" ] && { echo "== $log (last lines)" >&2; tail -n 15 "$log" >&2; }
    done
  fi
  rm -rf "$cluster"
  [ -e "$cluster" ] && leftover+=" $cluster"
  local new_files
  new_files="$(comm -13 <(echo "$files_before") <(snapshot))"
  [ -n "$new_files" ] && leftover+=" files:$(echo "$new_files" | tr '\n' ' ')"
  if [ -n "$leftover" ]; then
    echo "local_cluster.sh: left behind:$leftover" >&2
    status=3
  fi
  exit "$status"
}
trap cleanup EXIT
trap 'exit 130' INT
trap 'exit 143' TERM

free_port() {
  python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'
}

# MUNGE, with its own key, socket, pid, seed and log files.
mungekey --create --keyfile="$cluster/munge.key" || fail "mungekey failed"
munged --foreground --socket="$cluster/munge.socket" --key-file="$cluster/munge.key" \
  --pid-file="$cluster/munged.pid" --seed-file="$cluster/munged.seed" --log-file="$cluster/munged.file.log" \
  >"$cluster/munged.log" 2>&1 &
pids+=($!)
for _ in $(seq 1 50); do
  munge --socket="$cluster/munge.socket" --no-input >/dev/null 2>&1 && break
  sleep 0.2
done
munge --socket="$cluster/munge.socket" --no-input >/dev/null 2>&1 || fail "munged did not start"

# One node, this machine, with all its CPUs.
host="$(hostname -s)"
mkdir -p "$cluster/state" "$cluster/spool"
: >"$cluster/plugstack.conf"
cat >"$cluster/slurm.conf" <<EOF
ClusterName=rayverify
SlurmctldHost=$host(127.0.0.1)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$cluster/munge.socket
SlurmctldPort=$(free_port)
SlurmdPort=$(free_port)
StateSaveLocation=$cluster/state
SlurmdSpoolDir=$cluster/spool
SlurmctldPidFile=$cluster/slurmctld.pid
SlurmdPidFile=$cluster/slurmd.pid
SlurmctldLogFile=$cluster/slurmctld.log
SlurmdLogFile=$cluster/slurmd.log
PlugStackConfig=$cluster/plugstack.conf
MailProg=/bin/true
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
NodeName=rayverify-node NodeHostname=$host NodeAddr=127.0.0.1 CPUs=$(nproc) State=UNKNOWN
PartitionName=local Nodes=rayverify-node Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF="$cluster/slurm.conf"
slurmctld -D >/dev/null 2>&1 &
pids+=($!)
slurmd -D -N rayverify-node >/dev/null 2>&1 &
pids+=($!)
for _ in $(seq 1 60); do
  [ "$(sinfo -h -o %T 2>/dev/null)" = idle ] && break
  sleep 1
done
[ "$(sinfo -h -o %T 2>/dev/null)" = idle ] || fail "the node did not come up: $(sinfo 2>&1)"
echo "local_cluster.sh: Slurm $(sinfo --version | cut -d' ' -f2), one node of $(nproc) CPUs, SLURM_CONF=$SLURM_CONF" >&2

timeout --kill-after=10 "${RAYVERIFY_SLURM_TIMEOUT:-300}" "$@"
