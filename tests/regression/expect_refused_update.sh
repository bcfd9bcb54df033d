#!/usr/bin/env bash
# `clothbench check --update` with a --set override must refuse to record (exit status 2, a
# message naming --record-perturbed) and leave the baseline as it was.
# Usage: expect_refused_update.sh CLOTHBENCH SCENARIO BASELINE_DIR
set -u
clothbench=$1 scenario=$2 baselines=$3
work=$(mktemp -d "${TMPDIR:-/tmp}/clothbench-refused-update-XXXXXX") || exit 1
trap 'rm -rf "$work"' EXIT
cp -r "$baselines" "$work/baselines"
err=$("$clothbench" check "$scenario" -q --update --baseline "$work/baselines" \
  --set cloth.damping=10 2>&1 >/dev/null)
status=$?
echo "$err"
if [ "$status" -ne 2 ]; then
  echo "expected exit status 2 (refused), got $status" >&2
  exit 1
fi
if ! grep -q -- "--record-perturbed" <<<"$err"; then
  echo "expected the message to name --record-perturbed" >&2
  exit 1
fi
if ! diff -r "$baselines" "$work/baselines"; then
  echo "the baseline changed although the update was refused" >&2
  exit 1
fi
echo "--update with --set was refused and the baseline left alone"
