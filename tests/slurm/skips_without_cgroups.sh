#!/usr/bin/env bash
# The slurm test on a machine without cgroups (most containers) must skip with slurmd's reason,
# never fail and never pass: here a private mount namespace without /sys/fs/cgroup stands in
# for such a machine. Skipped itself (exit 77) where that namespace cannot be made (not root,
# no unshare) or where Slurm is not installed.
# Usage: skips_without_cgroups.sh SOURCE_DIR WORK_DIR
set -u
src=$1 work=$2
skip() { echo "SKIPPED: the no-cgroups slurm check: $*"; exit 77; }
[ "$(id -u)" -eq 0 ] || skip "needs root for a mount namespace"
command -v unshare >/dev/null || skip "unshare not found"
PATH=$PATH:/usr/sbin command -v slurmd >/dev/null || skip "slurmd not found (scripts/install-deps)"
unshare -m true 2>/dev/null || skip "this machine refuses a new mount namespace"
out=$(unshare -m bash -c '
  if mountpoint -q /sys/fs/cgroup; then umount -R /sys/fs/cgroup || exit 3; fi
  exec "$0" /bin/false "$1" "$2"' "$src/tests/slurm/slurm_cluster.sh" "$src" "$work" 2>&1)
status=$?
echo "$out" | tail -n 5
[ "$status" -eq 3 ] && skip "could not unmount /sys/fs/cgroup in the namespace"
if [ "$status" -ne 77 ]; then
  echo "FAIL: without cgroups the slurm test ended with $status, not 77 (skipped)"
  exit 1
fi
echo "$out" | grep -q "SKIPPED: the slurm test: slurmd cannot start on this machine without cgroups" ||
  { echo "FAIL: the skip does not give slurmd's reason"; exit 1; }
echo "without cgroups the slurm test skips and says why"
