#!/usr/bin/env bash
# Lost writes (issue 14, class 7): on a full disk (a 64 KiB tmpfs, filled) every command fails
# with exit 2 naming the file it could not write, and a sweep never claims to keep rows it
# could not write. Skipped (exit 77) when tmpfs cannot be mounted (not root, or in a container
# that forbids it). Usage: full_disk.sh CLOTHBENCH SOURCE_DIR WORK_DIR
set -u
clothbench=$1 source=$2 work=$3
source "$(dirname "$0")/expect.sh"
disk=$work/disk
mkdir -p "$disk"
if ! mount -t tmpfs -o size=64k tmpfs "$disk" 2>/dev/null; then
  echo "full disk: skipped: cannot mount a tmpfs on $disk (needs root)"
  exit 77
fi
trap 'umount "$disk"' EXIT
chain=$source/scenarios/hanging_chain.toml

# leave free pages of the 16 so that a command fails at different writes: none (the first
# file), the sidecars but not the rows, and so on
for free in 0 1 2 3 4; do
  rm -rf "${disk:?}"/*
  dd if=/dev/zero of="$disk/fill" bs=4k count=$((16 - free)) 2>/dev/null
  expect 2 "$clothbench" stability "$chain" -o "$disk/st" -q -j 1 -e custom-rk4 -i rk4 -i midpoint
  grep -q "^clothbench: cannot write $disk/st/.*: No space left on device" "$work/stderr" ||
    fail "stability, $free pages free: no file named: $(cat "$work/stderr")"
  ! grep -q "kept" "$work/stderr" || fail "stability, $free pages free: claims rows are kept"
  rm -rf "${disk:?}"/st
  expect 2 "$clothbench" run "$chain" -o "$disk/run" -q
  grep -q "^clothbench: cannot write $disk/run/.*: No space left on device" "$work/stderr" ||
    fail "run, $free pages free: no file named: $(cat "$work/stderr")"
  rm -rf "${disk:?}"/run
  expect 2 "$clothbench" accuracy "$chain" -o "$disk/acc" -q -j 1 -e custom-rk4 -i rk4 \
    --halvings 2 --repeats 1
  grep -q "^clothbench: cannot write $disk/acc/.*: No space left on device" "$work/stderr" ||
    fail "accuracy, $free pages free: no file named: $(cat "$work/stderr")"
done

echo "full disk: $failures failed checks"
[ "$failures" -eq 0 ]
