#!/usr/bin/env bash
# A deliberately perturbed engine must fail `clothbench check`, with the right quantity named.
# Usage: expect_gate_failure.sh CLOTHBENCH SCENARIO QUANTITY OVERRIDE...
# The perturbation comes in through --set overrides; no code is edited.
set -u
clothbench=$1 scenario=$2 quantity=$3
shift 3
sets=()
for o in "$@"; do sets+=(--set "$o"); done
out=$("$clothbench" check "$scenario" -q "${sets[@]}")
status=$?
echo "$out" | grep -E "FAIL|passed"
if [ "$status" -ne 1 ]; then
  echo "expected exit status 1 (a gate failed), got $status" >&2
  exit 1
fi
if ! echo "$out" | grep -E "^[^ ]+ +[^ ]+ +$quantity .*FAIL" >/dev/null; then
  echo "expected a failing gate on $quantity" >&2
  exit 1
fi
echo "the perturbation ($*) failed the $quantity gate as it should"
