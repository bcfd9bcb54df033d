#!/usr/bin/env bash
# --shard K/N and `clothbench merge`: the merged shards of a stability sweep and of a map are
# the unsharded sweep's files byte for byte; merge refuses a missing or doubled shard, shards
# of different sweeps, and a missing, doubled or misplaced row, each with one line saying so.
# Usage: shard_merge.sh CLOTHBENCH SOURCE_DIR WORK_DIR
set -u
clothbench=$1 src=$2 work=$3
. "$src/tests/cli/expect.sh"
scen=$src/scenarios/hanging_chain.toml
pick=(-e custom-symplectic-euler -i explicit-euler -i symplectic-euler -i picard-implicit -i midpoint
  -i rk4 -i implicit-euler --dt-max 0.05 -q -j 2)

# stability: six searches over three shards
expect 0 "$clothbench" stability "$scen" "${pick[@]}" -o "$work/full"
for k in 1 2 3; do
  expect 0 "$clothbench" stability "$scen" "${pick[@]}" --shard $k/3 -o "$work/s$k"
  [ "$(tail -n +2 "$work/s$k/stability.csv" | wc -l)" -eq 2 ] || fail "shard $k/3 does not hold 2 of the 6 rows"
done
expect 0 "$clothbench" merge "$work/merged" "$work/s3" "$work/s1" "$work/s2"
grep -q "merged 3 shards of a stability sweep: 6 rows" "$work/stdout" || fail "merge said: $(cat "$work/stdout")"
for f in stability.csv stability_scenario.toml; do
  cmp "$work/full/$f" "$work/merged/$f" || fail "merged $f differs from the unsharded sweep's"
done
# a finished shard resumed runs nothing and stays; another shard's --resume in its folder is refused
cp "$work/s1/stability.csv" "$work/s1-before.csv"
expect 0 "$clothbench" stability "$scen" "${pick[@]}" --shard 1/3 -o "$work/s1" --resume
cmp -s "$work/s1/stability.csv" "$work/s1-before.csv" || fail "a resumed finished shard changed"
expect 0 "$clothbench" stability "$scen" "${pick[@]}" --shard 2/3 -o "$work/fresh" --resume  # as a cluster task starts
cmp -s "$work/fresh/stability.csv" "$work/s2/stability.csv" || fail "a shard started with --resume differs"
expect 2 "$clothbench" stability "$scen" "${pick[@]}" --shard 2/3 -o "$work/s1" --resume
grep -q "cannot resume.*another shard" "$work/stderr" || fail "resume of another shard: $(cat "$work/stderr")"

# merge refuses ...
refused() {  # refused PATTERN MERGE_ARGS...: exit 2, one line matching PATTERN, no output folder
  local pattern=$1
  shift
  rm -rf "$work/bad"
  expect 2 "$clothbench" merge "$work/bad" "$@"
  grep -q "$pattern" "$work/stderr" || fail "merge $*: expected '$pattern', got: $(cat "$work/stderr")"
  [ "$(wc -l <"$work/stderr")" -eq 1 ] || fail "merge $*: not one line"
  [ ! -e "$work/bad" ] || fail "merge $* left $work/bad behind"
}
refused "shard 3/3 is missing" "$work/s1" "$work/s2"
refused "are both shard 1/3" "$work/s1" "$work/s1" "$work/s2" "$work/s3"
refused "not the folder of a sharded sweep" "$work/full"
expect 0 "$clothbench" stability "$scen" "${pick[@]}" --rel-tol 0.05 --shard 2/3 -o "$work/other"
refused "different sweeps" "$work/s1" "$work/other" "$work/s3"
for k in 1 2 3; do cp -r "$work/s$k" "$work/m$k"; done
sed -i '$d' "$work/m2/stability.csv"  # a row lost
refused "1 of 6 rows are missing.*shard 2/3" "$work/m1" "$work/m2" "$work/m3"
tail -1 "$work/s2/stability.csv" >>"$work/m2/stability.csv"
tail -1 "$work/s2/stability.csv" >>"$work/m2/stability.csv"  # ... and then doubled
refused "a second row for" "$work/m1" "$work/m2" "$work/m3"
cp "$work/s2/stability.csv" "$work/m2/stability.csv"
tail -1 "$work/s1/stability.csv" >>"$work/m2/stability.csv"  # a row of shard 1 in shard 2
refused "belongs to shard 1/3, not to this shard 2/3" "$work/m1" "$work/m2" "$work/m3"
for bad in 0/3 4/3 3 x/y 1/0; do
  expect 2 "$clothbench" stability "$scen" "${pick[@]}" --shard "$bad" -o "$work/bad"
  grep -q "shard $bad: expected K/N" "$work/stderr" || fail "--shard $bad: $(cat "$work/stderr")"
done

# map: three points over two shards (two searches per point)
vary=(--vary cloth.stiffness.structural=500,1000,2000 -e custom-symplectic-euler -i symplectic-euler
  -i rk4 --dt-max 0.05 -q -j 2)
expect 0 "$clothbench" map "$scen" "${vary[@]}" -o "$work/map"
for k in 1 2; do
  expect 0 "$clothbench" map "$scen" "${vary[@]}" --shard $k/2 -o "$work/map$k"
done
expect 0 "$clothbench" merge "$work/map-merged" "$work/map1" "$work/map2"
for f in map.csv map_scenario.toml; do
  cmp "$work/map/$f" "$work/map-merged/$f" || fail "merged $f differs from the unsharded map's"
done
refused "different sweeps" "$work/map1" "$work/s2"
# --resume on the merged map searches nothing again (no points/ appears) and keeps map.csv
expect 0 "$clothbench" map "$scen" "${vary[@]}" --resume -o "$work/map-merged"
[ ! -e "$work/map-merged/points" ] || fail "map --resume on a merged map searched its points again"
cmp "$work/map/map.csv" "$work/map-merged/map.csv" || fail "map --resume changed the merged map.csv"

# accuracy: six rows over two shards; after the merge, --resume on the merged folder fits and
# recommends without running anything, and every file equals the unsharded sweep's apart from
# the wall-time columns
without_timing() {  # the CSV without its wall-time columns
  python3 -c 'import csv,sys
rows = list(csv.reader(open(sys.argv[1])))
keep = [k for k, c in enumerate(rows[0]) if not c.startswith("wall_s")]
for r in rows: print(",".join(r[k] for k in keep))' "$1"
}
acc=(accuracy "$scen" -e custom-symplectic-euler -i symplectic-euler -i midpoint --dts 2e-3,1e-3,5e-4
  --tolerance 1e-3 --repeats 1 -q -j 2)
expect 0 "$clothbench" "${acc[@]}" -o "$work/acc"
for k in 1 2; do expect 0 "$clothbench" "${acc[@]}" --shard $k/2 -o "$work/acc$k"; done
[ ! -e "$work/acc1/convergence.csv" ] || fail "a shard wrote convergence.csv from its share of the rows"
expect 0 "$clothbench" merge "$work/acc-merged" "$work/acc2" "$work/acc1"
grep -q "merged 2 shards of an accuracy sweep: 6 rows" "$work/stdout" || fail "merge said: $(cat "$work/stdout")"
expect 0 "$clothbench" "${acc[@]}" --resume -o "$work/acc-merged"
for f in scenario.toml reference.csv convergence.csv; do
  cmp "$work/acc/$f" "$work/acc-merged/$f" || fail "merged accuracy $f differs"
done
for f in work_precision.csv recommendation.csv; do
  diff <(without_timing "$work/acc/$f") <(without_timing "$work/acc-merged/$f") ||
    fail "merged accuracy $f differs apart from wall times"
done
expect 2 "$clothbench" accuracy "$src/scenarios/flag.toml" -e custom-rk4 -i rk4 --resolutions 5,9 --shard 1/2 -o "$work/bad" -q
grep -q "only the time-step study can be sharded" "$work/stderr" || fail "--shard with --resolutions: $(cat "$work/stderr")"
[ ! -e "$work/bad" ] || fail "a refused accuracy shard left $work/bad behind"

[ "$failures" -eq 0 ] && echo "merged shards equal the unsharded stability sweep, map and accuracy sweep; merge refusals as documented"
exit $((failures > 0))
