#!/usr/bin/env bash
# clothbench fit refuses what it cannot do before any run, in one line naming the option:
# a malformed --target or --range, a metric no scenario gives, an engine no scenario has, more
# ranges than targets, a metric given twice, a length that is not positive, a --range key the
# scenario lacks; nothing is written then. An engine without a metric's scenario is a
# row "no engine", not an error; a target the scenario cannot show is unreachable at once.
# Usage: fit_refusals.sh CLOTHBENCH SOURCE_DIR WORK_DIR
set -u
clothbench=$1 source=$2 work=$3
source "$(dirname "$0")/expect.sh"
has() { grep -q -- "$2" "$work/$1" || fail "$3: no \"$2\" in $1: $(head -c 400 "$work/$1")"; }
cantilever=$source/scenarios/fabric/cantilever.toml
chain=$source/scenarios/hanging_chain.toml

expect 2 "$clothbench" fit "$cantilever" -q -o "$work/f" --target bending_length
has stderr "clothbench: --target bending_length: expected METRIC=VALUE" "no value"
expect 2 "$clothbench" fit "$cantilever" -q -o "$work/f" --target bending_length=abc
has stderr "expected a finite number, got \"abc\"" "bad value"
expect 2 "$clothbench" fit "$cantilever" -q -o "$work/f" --target drape_coefficient=0.7
has stderr "none of the scenarios gives drape_coefficient (they give chord_angle" "metric not given"
expect 2 "$clothbench" fit "$cantilever" -q -o "$work/f" --target bending_length=0.03 -e nosuch
has stderr "clothbench: --engine nosuch: no scenario has an engine of that name" "unknown engine"
expect 2 "$clothbench" fit "$cantilever" -q -o "$work/f" --target bending_length=0.03 \
  --range cloth.stiffness.bend=10:1
has stderr "expected 0 < LO < HI" "empty range"
expect 2 "$clothbench" fit "$cantilever" -q -o "$work/f" --target bending_length=0.03 \
  --range cloth.stiffness.bend=10:100 --range cloth.damping=1:2
has stderr "2 ranges for 1 targets" "more ranges than targets"
# a metric given two targets, a length that is not positive, a --range key the scenario lacks
# (named as the --range, not as the --set it becomes)
expect 2 "$clothbench" fit "$cantilever" -q -o "$work/f" --target bending_length=0.03 \
  --target bending_length=0.04
has stderr "clothbench: --target bending_length: given twice (0.03 and 0.04)" "two targets"
expect 2 "$clothbench" fit "$cantilever" -q -o "$work/f" --target bending_length=-1
has stderr "clothbench: --target bending_length=-1: expected a number > 0" "negative length"
expect 2 "$clothbench" fit "$cantilever" -q -o "$work/f" --target bending_length=0.03 \
  --range cloth.no_such_key=1:2 -e custom-rk4
has stderr "clothbench: --range cloth.no_such_key=1:2: unknown key \"no_such_key\"" "range key"
[ ! -e "$work/f/fit.csv" ] || fail "a refused fit wrote fit.csv"

# the chain has no custom-implicit-euler: its row says so, the cantilever's engine is fitted
# (one short run: the row's form is tested here, the fit's numbers in the fit tests)
expect 0 "$clothbench" fit "$chain" "$cantilever" -q -o "$work/g" --target bending_length=0.03 \
  -e custom-implicit-euler --max-runs 1 --set duration=0.2
has g/fit.csv "^custom-implicit-euler,cloth.stiffness.bend,1000,bending_length,0.03,.*,1,,,budget$" "one run at the start"
has stdout "custom-implicit-euler: bending_length" "summary"
[ -f "$work/g/fitted/hanging_chain.toml" ] || fail "no fitted hanging_chain.toml"

# a bending length below what the 0.1 m overhang can show (l / 6: the chord passes 83.9
# degrees) is unreachable before any run, with the reason on stderr and no value in fit.csv
expect 0 "$clothbench" fit "$cantilever" -q -o "$work/u" --target bending_length=0.01 \
  -e custom-implicit-euler
has stderr "unreachable before any run: bending_length 0.01 lies below what the 0.1 m overhang" "reason"
has stderr "shorten the overhang" "what to change"
has u/fit.csv "^custom-implicit-euler,cloth.stiffness.bend,,bending_length,0.01,,,0,,,unreachable$" "no run"
exit $((failures > 0))
