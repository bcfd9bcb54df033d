#!/usr/bin/env bash
# scripts/large-steps-cost (issue 30, part 2) on small grids and a short run: symplectic Euler's
# step is the largest that divides a frame and is at most 0.9 of the limit the blow-up search
# measured (and the next larger divisor is not), each table row is its run's summary.csv row,
# the explicit run is stable, and bad options are refused before any work. With --accuracy
# each precision row is its accuracy sweep's work_precision.csv row with the sweep's reference;
# --explicit-dt replaces the search for its size.
# Usage: large_steps_cost.sh CLOTHBENCH SOURCE_DIR WORK_DIR
set -u
clothbench=$1 source=$2 work=$3
source "$(dirname "$0")/expect.sh"
script=$source/scripts/large-steps-cost

expect 2 "$script" --clothbench "$clothbench" --sizes 8,x --out "$work/bad"
grep -q "sizes" "$work/stderr" || fail "--sizes 8,x: $(cat "$work/stderr")"
[ ! -e "$work/bad" ] || fail "--sizes 8,x wrote $work/bad"
expect 2 "$script" --clothbench "$clothbench" --fraction 1.5 --out "$work/bad"
[ ! -e "$work/bad" ] || fail "--fraction 1.5 wrote $work/bad"

expect 2 "$script" --clothbench "$clothbench" --sizes 8 --explicit-dt 6=1e-3 --out "$work/bad"
grep -q "not among --sizes" "$work/stderr" || fail "--explicit-dt 6=: $(cat "$work/stderr")"
expect 2 "$script" --clothbench "$clothbench" --sizes 8 --explicit-dt 8=x --out "$work/bad"
expect 2 "$script" --clothbench "$clothbench" --sizes 8 --explicit-dt 8=7e-4 --out "$work/bad"
grep -q "does not divide a frame" "$work/stderr" || fail "--explicit-dt 8=7e-4: $(cat "$work/stderr")"

expect 0 "$script" --clothbench "$clothbench" --sizes 6,8 --set duration=0.1 --accuracy \
  --out "$work/cost"
/usr/bin/python3 - "$work/cost" <<'PY' || fail "large_steps_cost.csv does not hold"
import csv, math, sys
out = sys.argv[1]
rows = list(csv.DictReader(open(f"{out}/large_steps_cost.csv")))
assert sorted({r["particles_per_side"] for r in rows}) == ["6", "8"], rows
frame = 1 / 30
for n in ("6", "8"):
    mine = [r for r in rows if r["particles_per_side"] == n]
    summary = {r["engine"]: r for r in csv.DictReader(open(f"{out}/{n}/run/summary.csv"))}
    assert {r["engine"] for r in mine} == set(summary), (mine, summary)
    limit = float(next(csv.DictReader(open(f"{out}/{n}/stability/stability.csv")))["stable_dt"])
    for r in mine:
        s = summary[r["engine"]]
        for k in ("dt", "wall_s", "steps", "newton_iterations", "cg_iterations"):
            assert float(r[k]) == float(s[k]), (k, r[k], s[k])
        assert math.isclose(float(r["wall_per_simulated_s"]),
                            float(s["wall_s"]) / (int(s["steps"]) * float(s["dt"])), rel_tol=1e-12)
        if r["engine"] == "custom-symplectic-euler":
            dt, k = float(r["dt"]), round(frame / float(r["dt"]))
            assert math.isclose(dt * k, frame, rel_tol=1e-12), dt
            assert dt <= 0.9 * limit * (1 + 1e-12) < frame / (k - 1), (dt, limit)
            assert r["stable"] == "1" and float(r["limit_dt"]) == limit
        else:
            assert int(r["newton_iterations"]) > 0, r
PY
[ -s "$work/cost/large_steps_cost.png" ] || fail "no large_steps_cost.png"
[ -s "$work/cost/large_steps_precision.png" ] || fail "no large_steps_precision.png"
/usr/bin/python3 - "$work/cost" <<'PY' || fail "large_steps_precision.csv does not hold"
import csv, sys
out = sys.argv[1]
rows = list(csv.DictReader(open(f"{out}/large_steps_precision.csv")))
cost = {(r["particles_per_side"], r["engine"]): r
        for r in csv.DictReader(open(f"{out}/large_steps_cost.csv"))}
assert {(r["particles_per_side"], r["engine"]) for r in rows} == set(cost), rows
for r in rows:
    folder = f"{out}/{r['particles_per_side']}/{r['folder']}"
    w = next(x for x in csv.DictReader(open(f"{folder}/work_precision.csv"))
             if x["engine"] == r["engine"])
    ref = next(x for x in csv.DictReader(open(f"{folder}/reference.csv")) if x["study"] == "dt")
    assert float(r["dt"]) == float(w["dt"]) == float(cost[r["particles_per_side"], r["engine"]]["dt"])
    assert float(r["error_max"]) == float(w["error_max"]) > float(ref["error_floor"]), (r, ref)
    assert float(r["reference_dt"]) == float(ref["dt"]) < float(r["dt"]), (r, ref)
    # counted work a simulated second: the run's over its 0.1 s
    work = int(w["force_evals"]) + 3 * int(w["cg_iterations"])
    assert abs(float(r["work_per_simulated_s"]) - work / 0.1) < 1e-9 * work / 0.1, r
    n = int(r["particles_per_side"])
    assert abs(float(r["particle_work_per_simulated_s"]) - work * n * n / 0.1) < 1e-9 * work * n * n / 0.1, r
PY

# --resume reads what finished: nothing runs again, and the tables are the same
before=$(cat "$work/cost/large_steps_cost.csv" "$work/cost/large_steps_precision.csv")
expect 0 "$script" --clothbench "$clothbench" --sizes 6,8 --set duration=0.1 --accuracy --resume \
  --out "$work/cost"
grep -q '^\$ .* run ' "$work/stdout" && fail "--resume ran a finished run again"
grep -q '^\$ .* stability ' "$work/stdout" && fail "--resume ran a finished search again"
[ "$before" = "$(cat "$work/cost/large_steps_cost.csv" "$work/cost/large_steps_precision.csv")" ] ||
  fail "--resume changed the tables"

# a step given for a size replaces its search: no stability folder, no limit in the table
expect 0 "$script" --clothbench "$clothbench" --sizes 6 --set duration=0.1 \
  --explicit-dt 6=0.0016666666666666668 --out "$work/given"
[ ! -e "$work/given/6/stability" ] || fail "--explicit-dt ran the blow-up search"
/usr/bin/python3 - "$work/given" <<'PY' || fail "--explicit-dt's step is not the run's"
import csv, sys
r = next(r for r in csv.DictReader(open(f"{sys.argv[1]}/large_steps_cost.csv"))
         if r["engine"] == "custom-symplectic-euler")
assert float(r["dt"]) == 0.0016666666666666668 and r["limit_dt"] == "", r
PY

exit $((failures > 0))
