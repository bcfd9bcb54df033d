#!/usr/bin/env bash
# `clothbench map` over two values of one key gives the rows of two `clothbench stability`
# sweeps with that key set by --set, field for field; a resumed map is the same map; bad --vary
# values are refused before anything is written.
# Usage: map_equals_stability.sh CLOTHBENCH SOURCE_DIR WORK_DIR
set -u
clothbench=$1 src=$2 work=$3
. "$src/tests/cli/expect.sh"
scen=$src/scenarios/hanging_chain.toml
pick=(-e custom-symplectic-euler -i symplectic-euler -i implicit-euler --dt-max 0.05 --method both -q)

expect 0 "$clothbench" map "$scen" --vary cloth.stiffness.structural=500,2000 "${pick[@]}" -o "$work/map"
for k in 500 2000; do
  expect 0 "$clothbench" stability "$scen" --set cloth.stiffness.structural=$k "${pick[@]}" -o "$work/s$k"
  tail -n +2 "$work/s$k/stability.csv" | sed "s/^/$k,/" >>"$work/expected"
done
[ "$(head -1 "$work/map/map.csv")" = "cloth.stiffness.structural,$(head -1 "$work/s500/stability.csv")" ] ||
  fail "map.csv header: $(head -1 "$work/map/map.csv")"
[ "$(wc -l <"$work/expected")" -eq 4 ] || fail "expected 4 stability rows, got $(wc -l <"$work/expected")"
diff <(tail -n +2 "$work/map/map.csv") "$work/expected" || fail "map.csv differs from the two stability sweeps"
# the stiffer chain has the smaller explicit limit (a fact, so the rows are not both empty)
awk -F, '$3=="symplectic-euler" {print $4}' "$work/map/map.csv" >"$work/limits"
[ "$(sort -g "$work/limits" | head -1)" = "$(tail -1 "$work/limits")" ] ||
  fail "the 2000 N/m chain's symplectic limit is not the smaller one: $(tr '\n' ' ' <"$work/limits")"

# resuming a finished map runs nothing new and writes the same map
cp "$work/map/map.csv" "$work/map-before.csv"
expect 0 "$clothbench" map "$scen" --vary cloth.stiffness.structural=500,2000 "${pick[@]}" -o "$work/map" --resume
cmp -s "$work/map/map.csv" "$work/map-before.csv" || fail "a resumed map differs"
expect 2 "$clothbench" map "$scen" --vary cloth.stiffness.structural=500,3000 "${pick[@]}" -o "$work/map" --resume
grep -q "cannot resume" "$work/stderr" || fail "resume of another map: $(cat "$work/stderr")"

# bad --vary values: exit 2, one line naming the option, no folder
for bad in cloth.particles=9.5,17 cloth.damping=1:10:log:1 cloth.damping=0:10:log:3 cloth.damping=1,1 \
  cloth.no_such_key=1,2 cloth.damping=; do
  expect 2 "$clothbench" map "$scen" --vary "$bad" -e custom-rk4 -o "$work/bad" -q
  [ "$(wc -l <"$work/stderr")" -eq 1 ] || fail "--vary $bad: not one line: $(cat "$work/stderr")"
  [ ! -e "$work/bad" ] || fail "--vary $bad left $work/bad behind"
done
expect 0 "$clothbench" map --help
grep -q "A:B:log:N" "$work/stdout" || fail "map --help does not show the range syntax"

[ "$failures" -eq 0 ] && echo "map over two values equals two stability sweeps; resume and refusals as documented"
exit $((failures > 0))
