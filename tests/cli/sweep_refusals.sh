#!/usr/bin/env bash
# Sweeps that would lie (issue 27): a map whose --vary gives one key twice, a key --set also
# sets, a key the search sets itself (an engine's dt or integrator, frame_interval, name, an
# engine left out by -e) or one value in two spellings is refused before any work, naming
# the option; nothing is written.
# Usage: sweep_refusals.sh CLOTHBENCH SOURCE_DIR WORK_DIR
set -u
clothbench=$1 source=$2 work=$3
source "$(dirname "$0")/expect.sh"
chain=$source/scenarios/hanging_chain.toml
has() { grep -q -- "$2" "$work/$1" || fail "$3: no \"$2\" in $1: $(head -c 400 "$work/$1")"; }
refused() {  # refused WHAT EXPECTED-MESSAGE ARGS...
  local what=$1 message=$2
  shift 2
  expect 2 "$clothbench" map "$chain" -q -o "$work/map" "$@"
  has stderr "$message" "$what"
  [ ! -e "$work/map" ] || fail "$what: $work/map was written"
}
refused "one key twice" "--vary cloth.damping=0,1: cloth.damping is varied twice (--vary cloth.damping=2,3)" \
  --vary cloth.damping=2,3 --vary cloth.damping=0,1
refused "--set and --vary" "--vary cloth.damping=0,1: cloth.damping is also set by --set cloth.damping=5" \
  --set cloth.damping=5 --vary cloth.damping=0,1
refused "an engine's dt" "cannot be varied: the search sets each engine's dt itself" \
  --vary engine.custom-rk4.dt=1e-3,2e-3
refused "an engine's integrator" "cannot be varied: -i chooses the integrators" \
  --vary engine.custom-rk4.integrator='"rk4","midpoint"'
refused "frame_interval" "cannot be varied: the search sets the frame interval itself" \
  --vary frame_interval=0.01,0.02
refused "name" "cannot be varied: the scenario's name labels the sweep" --vary 'name="a","b"'
refused "an engine left out by -e" "cannot be varied: the engine custom-rk4 is left out by -e" \
  -e custom-symplectic-euler --vary engine.custom-rk4.damping=0,1
refused "one value in two spellings" "the value '1.0' is given twice (as '1')" \
  --vary cloth.damping=1,1.0
refused "one value in two spellings" "the value '1e0' is given twice (as '1')" \
  --vary cloth.damping=1,2,1e0

# merge names what is wrong with a folder it is given
expect 2 "$clothbench" merge "$work/merged" "$work/no-such-folder"
has stderr "$work/no-such-folder: no such folder" "merge of a missing folder"
echo x >"$work/plain-file"
expect 2 "$clothbench" merge "$work/merged" "$work/plain-file"
has stderr "$work/plain-file: a file, not the folder of a sharded sweep" "merge of a plain file"

# a string value is written alike on stdout and in map.csv (a TOML string keeps its quotes,
# quoted again for CSV), so that map.csv reads back as what was given
expect 0 "$clothbench" map "$chain" -o "$work/strings" -j 1 -e custom-rk4 -i symplectic-euler \
  --method blowup --vary 'description="c",d'
[ "$(cut -d, -f1 "$work/stdout")" = "$(cut -d, -f1 "$work/strings/map.csv")" ] ||
  fail "string values: stdout $(cut -d, -f1 "$work/stdout" | tr '\n' ' ') but map.csv $(cut -d, -f1 "$work/strings/map.csv" | tr '\n' ' ')"
/usr/bin/python3 -c 'import csv,sys; v=[r["description"] for r in csv.DictReader(open(sys.argv[1]))]; sys.exit(v != ["\"c\"", "d"])' \
  "$work/strings/map.csv" || fail "string values: map.csv does not read back as given"

# a sweep's wall-clock budget is part of what it is: --resume and merge keep to one budget
quick=(-q -j 1 -e custom-rk4 -i symplectic-euler --method blowup)
expect 0 "$clothbench" stability "$chain" -o "$work/budget" "${quick[@]}" --max-run-seconds 100
expect 2 "$clothbench" stability "$chain" -o "$work/budget" "${quick[@]}" --resume
has stderr "--max-run-seconds 100 then" "stability --resume without the budget"
expect 0 "$clothbench" stability "$chain" -o "$work/budget" "${quick[@]}" --resume \
  --max-run-seconds 100
expect 0 "$clothbench" accuracy "$chain" -o "$work/acc-budget" -q -j 1 --halvings 1 \
  -e custom-rk4 -i symplectic-euler --max-run-seconds 100
expect 2 "$clothbench" accuracy "$chain" -o "$work/acc-budget" -q -j 1 --halvings 1 \
  -e custom-rk4 -i symplectic-euler --resume
has stderr "cannot resume: the folder holds a sweep of another --max-run-seconds" \
  "accuracy --resume without the budget"
for k in 1 2; do
  budget=()
  [ "$k" -eq 1 ] && budget=(--max-run-seconds 100)
  expect 0 "$clothbench" stability "$chain" -o "$work/shard$k" "${quick[@]}" -i rk4 \
    --shard "$k/2" "${budget[@]}"
done
expect 2 "$clothbench" merge "$work/merged-budget" "$work/shard1" "$work/shard2"
has stderr "they are shards of different sweeps" "merge of shards with two budgets"

# a command owns what it writes: a sweep into a run's folder keeps the run's record ...
expect 0 "$clothbench" run "$chain" -o "$work/with-run" -q
cp "$work/with-run/run.json" "$work/run.json.before"
expect 0 "$clothbench" stability "$chain" -o "$work/with-run" "${quick[@]}"
cmp -s "$work/with-run/run.json" "$work/run.json.before" ||
  fail "stability into a run's folder rewrote its run.json"
# ... a map into a stability shard's folder is refused and leaves its shard record ...
expect 2 "$clothbench" map "$chain" -o "$work/shard1" -q -j 1 -e custom-rk4 \
  -i symplectic-euler --vary cloth.damping=0,1
has stderr "shard1/shard.toml: the folder holds a shard of a stability sweep" "map into a shard"
[ -s "$work/shard1/shard.toml" ] || fail "map into a stability shard deleted its shard.toml"
# ... and a merge into an earlier map's folder is refused, naming what it would leave stale
expect 0 "$clothbench" map "$chain" -o "$work/old-map" -q -j 1 -e custom-rk4 \
  -i symplectic-euler --vary cloth.damping=0,1
expect 0 "$clothbench" stability "$chain" -o "$work/shard2" "${quick[@]}" -i rk4 --shard 2/2 \
  --max-run-seconds 100
expect 2 "$clothbench" merge "$work/old-map" "$work/shard1" "$work/shard2"
has stderr "old-map holds .*, which a merged stability sweep would not replace" \
  "merge into an old map"
expect 0 "$clothbench" merge "$work/merged-ok" "$work/shard1" "$work/shard2"
expect 0 "$clothbench" merge "$work/merged-ok" "$work/shard1" "$work/shard2"

[ "$failures" -eq 0 ] || exit 1
echo "every lying map is refused before any work; merge names a missing folder and a file;"
echo "a budget is part of a sweep for --resume and merge; a command owns what it writes"
