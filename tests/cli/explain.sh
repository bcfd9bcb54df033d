#!/usr/bin/env bash
# clothbench run --explain (issue 13, part 1): it adds the matched custom engine of each Bullet
# engine and writes attribution.csv; without --explain there is no such file; a scenario.toml
# written by --explain reruns with --explain.
# Usage: explain.sh CLOTHBENCH SOURCE_DIR WORK_DIR
set -u
clothbench=$1 source=$2 work=$3
source "$(dirname "$0")/expect.sh"
flag=$source/scenarios/flag.toml
short=(--set duration=0.2 --quiet)

expect 0 "$clothbench" run "$flag" -o "$work/plain" -e bullet-deformable-explicit "${short[@]}"
[ ! -e "$work/plain/attribution.csv" ] || fail "attribution.csv written without --explain"

expect 0 "$clothbench" run "$flag" -o "$work/ex" --explain -e bullet-deformable-explicit \
  -e bullet-softbody-matched "${short[@]}"
grep -q "^custom-as-bullet-deformable-explicit,imex-euler,0.001,yes," "$work/stdout" ||
  fail "--explain did not run custom-as-bullet-deformable-explicit: $(cat "$work/stdout")"
csv=$work/ex/attribution.csv
[ "$(head -1 "$csv")" = "engine,reference,matched,at,t,total_rms,scheme_rms,model_rms,note" ] ||
  fail "attribution.csv header: $(head -1 "$csv")"
[ "$(grep -c '^bullet-deformable-explicit,custom-rk4,custom-as-bullet-deformable-explicit,' "$csv")" -eq 2 ] ||
  fail "attribution.csv: no final and max rows for the explicit mode: $(cat "$csv")"
grep -q '^bullet-softbody-matched,custom-rk4,,final,0.2,[0-9.e-]*,,,"position-based' "$csv" ||
  fail "attribution.csv: the soft body row is not unsplit with its note: $(cat "$csv")"
grep -q 'custom-as-bullet-deformable-explicit' "$work/ex/scenario.toml" ||
  fail "scenario.toml does not hold the matched engine"

expect 0 "$clothbench" run "$work/ex/scenario.toml" -o "$work/again" --explain \
  -e bullet-deformable-explicit --quiet
[ "$(grep -c '^bullet-deformable-explicit,' "$work/again/attribution.csv")" -eq 2 ] ||
  fail "rerun of the explained scenario: $(cat "$work/again/attribution.csv")"

exit $((failures > 0))
