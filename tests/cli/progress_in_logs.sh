#!/usr/bin/env bash
# Progress in a log, stderr not a terminal: `run` and `accuracy` print a plain line every 5 % of
# their steps, the references' steps included, and the last line says 100 %. (An accuracy
# sweep on the 128 x 128 fabric ran its 17-minute reference without a line, then printed
# "14% ... ETA 6410 s" three seconds before it finished; `run` printed nothing between engines.)
# Usage: progress_in_logs.sh CLOTHBENCH SOURCE_DIR WORK_DIR
set -u
clothbench=$1 source=$2 work=$3
source "$(dirname "$0")/expect.sh"
chain=$source/scenarios/hanging_chain.toml

# the lines' percentages, in order
percents() { sed -n 's/^progress: *\([0-9]*\)% of .*/\1/p' "$work/stderr" | tr '\n' ' '; }
# more than one line, rising, the last at 100
rises_to_100() {
  local p
  p=$(percents)
  [ "$(echo "$p" | wc -w)" -ge 2 ] || fail "$1: fewer than two progress lines: $(head -c 400 "$work/stderr")"
  [ "$(echo "$p" | awk '{print $NF}')" = 100 ] || fail "$1: the last progress line is not 100 %: $p"
  echo "$p" | awk '{for (i = 2; i <= NF; ++i) if ($i < $(i - 1)) exit 1}' ||
    fail "$1: progress went back: $p"
}

expect 0 "$clothbench" run "$chain" -e custom-rk4 -o "$work/run" --set duration=1
rises_to_100 "run"
# a line names the engine and the simulated time
grep -q '^progress: .*(custom-rk4  t = [0-9.]* / 1.00 s)$' "$work/stderr" ||
  fail "run: no progress line names the engine and its time: $(head -c 400 "$work/stderr")"

# the reference is most of this sweep's steps: its own lines come first, before the sweep's
# (the reference made from the symplectic engine's options, so it runs another integrator)
expect 0 "$clothbench" accuracy "$chain" -e custom-symplectic-euler -i symplectic-euler \
  --set duration=0.5 --set reference=custom-symplectic-euler --halvings 1 --repeats 1 -j 1 \
  -o "$work/accuracy"
rises_to_100 "accuracy"
# (a reference's lines carry its simulated time; the sweep's runs are counted as they end)
grep -m1 '^progress: ' "$work/stderr" | grep -q ' t = ' ||
  fail "accuracy: the first progress line is not the reference's: $(head -c 600 "$work/stderr")"
# and names what runs: rk4 at the reference's step, made from the scenario's engine
grep -m1 '^progress: ' "$work/stderr" | grep -q '(custom-symplectic-euler (rk4, dt = [0-9.e-]* s)  t = ' ||
  fail "accuracy: the reference's line does not say it is rk4: $(grep -m1 '^progress: ' "$work/stderr")"

[ "$failures" -eq 0 ] || exit 1
echo "progress in logs: run and accuracy rise to 100 %"
