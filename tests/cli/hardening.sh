#!/usr/bin/env bash
# The hardening of issue 14 on the command line: a wall-clock budget per run (--max-run-seconds)
# that stops a run as a timeout and lets a sweep go on, a second Ctrl-C that ends at once, an
# output folder that one command holds at a time, and messages that say what is wrong.
# Usage: hardening.sh CLOTHBENCH SOURCE_DIR WORK_DIR
set -u
clothbench=$1 source=$2 work=$3
source "$(dirname "$0")/expect.sh"
seed=$source/scenarios/seed_sphere_drape.toml
has() { grep -q -- "$2" "$work/$1" || fail "$3: no \"$2\" in $1: $(head -c 400 "$work/$1")"; }

# class 9: readable ranges (no 300-digit bound), an unknown command named, nan refused
expect 2 "$clothbench" stability --dt-max -1
has stderr '--dt-max: expected a finite number > 0, got "-1"' "--dt-max -1"
[ "$(wc -c <"$work/stderr")" -lt 200 ] || fail "--dt-max -1: message too long: $(cat "$work/stderr")"
expect 2 "$clothbench" accuracy --halvings 0
has stderr '--halvings: expected a whole number' "--halvings 0"
expect 2 "$clothbench" accuracy "$seed" -o "$work/nan" --tolerance nan
has stderr '--tolerance: expected a finite number > 0, got "nan"' "--tolerance nan"
expect 2 "$clothbench" stability --dt-max nan
has stderr '--dt-max: expected a finite number > 0, got "nan"' "--dt-max nan"
expect 2 "$clothbench" frobnicate
has stderr 'unknown command "frobnicate"; the commands are run, stability, accuracy, check' \
  "unknown command"
expect 2 "$clothbench" run --max-run-seconds 0
has stderr '--max-run-seconds: expected a finite number > 0' "--max-run-seconds 0"

# class 2: a run over its budget stops as a timeout (stable 0, no blow-up time), exit 0
expect 0 "$clothbench" run "$seed" -o "$work/timeout" -q --max-run-seconds 0.2
has stdout '^custom-rk4,rk4,0.0001,timeout,' "run timeout"
awk -F, 'NR > 1 && !($9 == 0 && $10 == "") { bad = 1 } END { exit bad }' \
  "$work/timeout/summary.csv" || fail "run timeout: summary.csv rows not stable=0 with empty blowup_t"
# ... and a stability search records it as the cause and goes on to the next configuration
# (the blow-up method: the growth search's budget is tested in test_growth_search.cpp, and its
# reference trajectory, which no budget bounds, is most of this command's time otherwise)
expect 0 "$clothbench" stability "$seed" -o "$work/stab" -q -j 1 -e custom-rk4 -i rk4 -i \
  symplectic-euler --max-run-seconds 0.05 --method blowup
[ "$(grep -c '^custom-rk4,.*timeout at dt' "$work/stab/stability.csv")" -eq 2 ] ||
  fail "stability timeout: no two timeout rows: $(cat "$work/stab/stability.csv")"

# class 2: a second Ctrl-C ends at once, with exit 130 and no output
"$clothbench" run "$seed" -o "$work/twice" -q >/dev/null 2>&1 &
pid=$!
sleep 1
kill -INT "$pid"
kill -INT "$pid"
wait "$pid"
got=$?
[ "$got" -eq 130 ] || fail "second Ctrl-C: expected exit 130, got $got"
[ -z "$(ls "$work/twice" 2>/dev/null | grep -v '^\.')" ] || fail "second Ctrl-C: output written"

# class 6: a second command on a folder in use fails at once, naming the folder and the first
"$clothbench" run "$seed" -o "$work/busy" -q >/dev/null 2>&1 &
pid=$!
for _ in $(seq 50); do [ -s "$work/busy/.clothbench.lock" ] && break; sleep 0.1; done
expect 2 "$clothbench" stability "$seed" -o "$work/busy" -q
has stderr "output folder $work/busy is in use by another clothbench command (pid $pid: .*run" \
  "second command"
kill -INT "$pid"
wait "$pid"
[ ! -e "$work/busy" ] || fail "interrupted run: its new folder is left behind: $(ls -a "$work/busy")"

# class 7: check --update is all or nothing: a scenario that fails leaves every baseline as it was
mkdir -p "$work/baselines"
cp -r "$source/reference/baselines/free_fall" "$source/reference/baselines/hanging_chain" \
  "$work/baselines/"
echo "custom-rk4,steps,0" >>"$work/baselines/free_fall/metrics.csv"  # an update would change it
cp "$work/baselines/free_fall/metrics.csv" "$work/free_fall_metrics.csv"
sed -i '/^steps = /d' "$work/baselines/hanging_chain/tolerances.toml"
expect 2 "$clothbench" check --update -q -b "$work/baselines" "$source/scenarios/free_fall.toml" \
  "$source/scenarios/hanging_chain.toml"
has stderr "hanging_chain/tolerances.toml: no tolerance for steps" "check --update, bad tolerances"
cmp -s "$work/baselines/free_fall/metrics.csv" "$work/free_fall_metrics.csv" ||
  fail "check --update that failed on its second scenario rewrote the first one's baseline"

# class 8: an input is never overwritten: -o set to the scenario's own folder is refused
chain=$source/scenarios/hanging_chain.toml
mkdir -p "$work/own"
cp "$chain" "$work/own/scenario.toml"
echo "# the user's own comment" >>"$work/own/scenario.toml"
cp "$work/own/scenario.toml" "$work/own_copy.toml"
expect 2 "$clothbench" run "$work/own/scenario.toml" -o "$work/own" -q
has stderr "$work/own/scenario.toml is the scenario file .* itself" "run -o its own folder"
expect 2 "$clothbench" accuracy "$work/own/scenario.toml" -o "$work/own" -q
cmp -s "$work/own/scenario.toml" "$work/own_copy.toml" || fail "the scenario file was overwritten"
# ... a duplicated row in a resumed CSV is refused, naming its line
expect 0 "$clothbench" stability "$chain" -o "$work/dup" -q -j 1 -e custom-rk4 -i symplectic-euler
sed -n 2p "$work/dup/stability.csv" >>"$work/dup/stability.csv"
expect 2 "$clothbench" stability "$chain" -o "$work/dup" -q -j 1 -e custom-rk4 -i symplectic-euler \
  --resume
has stderr "dup/stability.csv:3: cannot resume: a second row for custom-rk4,symplectic-euler" \
  "duplicated row"
# class 9: a garbage number in a resumed row is an error naming the file, line, column and value
cp -r "$work/dup" "$work/garbage"
sed -i '3d' "$work/garbage/stability.csv"
sed -i '2s/^\(custom-rk4,symplectic-euler,\)[^,]*/\10.00x1/' "$work/garbage/stability.csv"
expect 2 "$clothbench" stability "$chain" -o "$work/garbage" -q -j 1 -e custom-rk4 \
  -i symplectic-euler --resume
has stderr 'garbage/stability.csv:2: stable_dt: expected a number, got "0.00x1"' "garbage row"
# ... an accuracy sweep that stops with exit 2 (its reference blows up) leaves nothing it made,
# and no fits of an older sweep beside its rows
expect 2 "$clothbench" accuracy "$chain" -o "$work/acc" -q -j 1 --set blowup_strain=1e-12
[ ! -e "$work/acc" ] || fail "failed accuracy sweep left $(ls -a "$work/acc")"
mkdir -p "$work/acc2"
echo "engine,integrator,order,points" >"$work/acc2/convergence.csv"
expect 2 "$clothbench" accuracy "$chain" -o "$work/acc2" -q -j 1 --set blowup_strain=1e-12
[ ! -e "$work/acc2/convergence.csv" ] || fail "an older sweep's convergence.csv was left"

# class 3: a sweep whose runs would take more than 1e9 steps is refused, naming the option
expect 2 "$clothbench" stability "$chain" -o "$work/steps1" -q --dt-max 1e-300
has stderr "^clothbench: --dt-max 1e-300: every run would take at least 3e+300 steps" "--dt-max 1e-300"
expect 2 "$clothbench" accuracy "$chain" -o "$work/steps2" -q --dts 1e-12
has stderr "dt = 1e-12 s would take duration / dt = 3000000000000 steps, more than" "--dts 1e-12"
expect 2 "$clothbench" accuracy "$chain" -o "$work/steps3" -q --halvings 40
has stderr "fewer --halvings" "--halvings 40"
expect 2 "$clothbench" accuracy "$chain" -o "$work/steps4" -q --halvings 1000000
has stderr "^clothbench: --halvings 1000000: expected at most 60" "--halvings 1000000"
for d in steps1 steps2 steps3 steps4; do [ ! -e "$work/$d" ] || fail "refused sweep left $d"; done

echo "hardening: $failures failed checks"
[ "$failures" -eq 0 ]
