#!/usr/bin/env bash
# A one-node Slurm cluster on this machine (munged, slurmctld and slurmd on localhost with a
# slurm.conf generated in a temporary folder) runs a small sharded stability sweep through
# scripts/slurm-sweep: a job array of three shards and a dependent merge job. The merged
# stability.csv must equal the unsharded sweep's, byte for byte.
# Skipped (exit 77, with the reason) when not root, when Slurm or munge is not installed
# (scripts/install-deps installs slurm-wlm and munge), or when slurmd cannot start because the
# machine has no cgroup file system (most containers).
# Usage: slurm_cluster.sh CLOTHBENCH SOURCE_DIR WORK_DIR
set -u
clothbench=$1 src=$2 work=$3
skip() { echo "SKIPPED: the slurm test: $*"; exit 77; }
[ "$(id -u)" -eq 0 ] || skip "needs root to start munged, slurmctld and slurmd"
for c in munged mungekey slurmctld slurmd sbatch sinfo squeue scancel; do
  command -v "$c" >/dev/null || PATH=$PATH:/usr/sbin command -v "$c" >/dev/null ||
    skip "$c not found (apt-get install slurm-wlm munge, or scripts/install-deps)"
done
export PATH=$PATH:/usr/sbin

rm -rf "$work"
mkdir -p "$work"
chmod 700 "$work"
t=$(mktemp -d /tmp/clothbench-slurm.XXXXXX)
pids=()
cleanup() {
  scancel --quiet --user=root 2>/dev/null
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null; done
  for p in "${pids[@]}"; do wait "$p" 2>/dev/null; done
  rm -rf "$t"
}
trap cleanup EXIT
mkdir -p "$t/munge" "$t/state" "$t/spool"
chmod 700 "$t/munge"

# munge: a fresh key and a private socket
mungekey --create --keyfile="$t/munge/munge.key" || skip "mungekey could not make a key"
munged --foreground --force --key-file="$t/munge/munge.key" --socket="$t/munge/socket" \
  --pid-file="$t/munge/munged.pid" --log-file="$t/munge/munged.log" \
  --seed-file="$t/munge/seed" >"$t/munge/out.log" 2>&1 &
pids+=($!)

# slurm: one node, this machine, two free ports
host=$(hostname -s)
port() { python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])'; }
cpus=$(nproc)
cat >"$t/slurm.conf" <<CONF
ClusterName=clothbench-test
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$(port)
SlurmdPort=$(port)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$t/munge/socket
CredType=cred/munge
StateSaveLocation=$t/state
SlurmdSpoolDir=$t/spool
SlurmctldPidFile=$t/slurmctld.pid
SlurmdPidFile=$t/slurmd.pid
SlurmctldLogFile=$t/slurmctld.log
SlurmdLogFile=$t/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
MpiDefault=none
ReturnToService=2
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus State=UNKNOWN
PartitionName=test Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF=$t/slurm.conf
for i in $(seq 50); do [ -S "$t/munge/socket" ] && break; sleep 0.1; done
[ -S "$t/munge/socket" ] || { echo "FAIL: munged did not start: $(cat "$t/munge/out.log" "$t/munge/munged.log" 2>/dev/null)"; exit 1; }
slurmctld -D -i -f "$t/slurm.conf" >"$t/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -f "$t/slurm.conf" >"$t/slurmd.out" 2>&1 &
pids+=($!)
for i in $(seq 60); do
  state=$(sinfo -h -n "$host" -o %t 2>/dev/null)
  [ "$state" = "idle" ] && break
  kill -0 "${pids[2]}" 2>/dev/null || break  # slurmd gave up
  sleep 0.5
done
if [ "$state" != "idle" ]; then
  # slurmd (22.05) needs a mounted cgroup file system, which most containers lack: then the
  # machine cannot give this test a node, which is a skip with slurmd's own words, not a failure
  why=$(grep -h -m 1 -i "cgroup" "$t/slurmd.log" "$t/slurmd.out" 2>/dev/null | head -n 1)
  if [ -n "$why" ] && ! kill -0 "${pids[2]}" 2>/dev/null; then
    skip "slurmd cannot start on this machine without cgroups (it said: ${why#*error: })"
  fi
  echo "FAIL: the one-node cluster did not come up (node state '$state')"
  tail -n 5 "$t/slurmctld.log" "$t/slurmd.log" "$t"/*.out 2>/dev/null
  exit 1
fi
echo "a one-node Slurm cluster is up on $host ($cpus CPUs)"

# the sweep: unsharded here, then three shards and a merge on the cluster
scen=$src/scenarios/hanging_chain.toml
sweep=(stability "$scen" -e custom-symplectic-euler --dt-max 0.05 -j 1)
"$clothbench" "${sweep[@]}" -q -o "$work/local" >/dev/null || { echo "FAIL: the local sweep failed"; exit 1; }
timeout 600 "$src/scripts/slurm-sweep" -n 3 -o "$work/cluster" --clothbench "$clothbench" --wait \
  "${sweep[@]}"
status=$?
if [ "$status" -ne 0 ]; then
  echo "FAIL: slurm-sweep exit status $status"
  tail -n 20 "$work/cluster/logs"/*.log "$t/slurmctld.log" 2>/dev/null
  exit 1
fi
squeue -h -o '%i %T' | grep . && echo "note: jobs still listed"
for k in 1 2 3; do
  [ -f "$work/cluster/shard-$k/shard.toml" ] || { echo "FAIL: shard $k did not run"; exit 1; }
done
if ! cmp "$work/local/stability.csv" "$work/cluster/stability.csv"; then
  echo "FAIL: the merged cluster sweep differs from the local one"
  exit 1
fi
cmp "$work/local/stability_scenario.toml" "$work/cluster/stability_scenario.toml" ||
  { echo "FAIL: the merged sidecar differs"; exit 1; }
echo "three Slurm array tasks and a dependent merge job gave the unsharded sweep's stability.csv ($(($(wc -l <"$work/local/stability.csv") - 1)) rows)"
