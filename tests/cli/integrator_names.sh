#!/usr/bin/env bash
# --integrator takes the integrators' own names: an unknown one is refused (exit 2) with the
# list of them, and the sweeps' --help lists every one with their count.
# Usage: integrator_names.sh CLOTHBENCH SOURCE_DIR WORK_DIR
set -u
clothbench=$1 source=$2 work=$3
source "$(dirname "$0")/expect.sh"
chain=$source/scenarios/hanging_chain.toml

for command in stability map accuracy; do
  vary=()
  [ "$command" != map ] || vary=(--vary cloth.damping=1,2)
  expect 2 "$clothbench" "$command" "$chain" -o "$work/$command" -i rk5 "${vary[@]}"
  grep -q "^clothbench: --integrator rk5: no such integrator (expected one of: explicit-euler, .*, projective)$" \
    "$work/stderr" || fail "$command -i rk5: $(cat "$work/stderr")"
  [ ! -e "$work/$command" ] || fail "$command -i rk5 wrote $work/$command"
  expect 0 "$clothbench" "$command" --help
  count=$("$clothbench" list | sed -n 's/^integrators (kind = "custom")://p' | wc -w)
  grep -q "default: all $count)" "$work/stdout" || fail "$command --help: no 'all $count'"
done
exit $((failures > 0))
