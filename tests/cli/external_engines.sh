#!/usr/bin/env bash
# Issue 32's user engine by protocol, end to end: the example Python engine
# (examples/external/python) runs only when allowed; beside the custom engine's symplectic Euler
# it ends within round-off of it; stability, accuracy, check and report run on it.
# The C++ example engine runs the same scene through the command line too.
# Usage: external_engines.sh CLOTHBENCH SOURCE_DIR WORK_DIR CPP_EXAMPLE_ENGINE
set -u
clothbench=$1 source=$2 work=$3 cpp_engine=${4:-}
source "$(dirname "$0")/expect.sh"
scenario=$source/examples/external/seed_no_contact.toml
short=(--set duration=0.2 --quiet)
unset CLOTHBENCH_ALLOW_EXTERNAL
# the scenario's "python3" is found on PATH: Debian's, which has numpy
mkdir -p "$work/bin" && ln -s /usr/bin/python3 "$work/bin/python3"
export PATH=$work/bin:$PATH

# not allowed: exit 2, and the message says how to allow it
expect 2 "$clothbench" run "$scenario" -o "$work/refused" "${short[@]}"
grep -q -- "--allow-external" "$work/stderr" && grep -q "CLOTHBENCH_ALLOW_EXTERNAL=1" "$work/stderr" ||
  fail "the refusal does not say how to allow: $(cat "$work/stderr")"
[ ! -e "$work/refused" ] || fail "a refused run wrote $work/refused"

# allowed by the option; --explain shows the command, resolved against the scenario's folder
expect 0 "$clothbench" run "$scenario" -o "$work/run" --allow-external --explain --set duration=0.2
grep -q "engine python-symplectic-euler runs the external program: \"python3\" \"$source/examples/external/python/cloth_engine.py\"" "$work/stderr" ||
  fail "--explain does not show the command: $(cat "$work/stderr")"
# the summary's final distance from the reference (custom symplectic Euler): round-off
rms=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == "final_rms_vs_reference") c = i }
               $1 == "python-symplectic-euler" { print $c }' "$work/stdout")
awk -v r="$rms" 'BEGIN { exit !(r != "" && r + 0 < 1e-9) }' ||
  fail "python engine vs custom symplectic Euler: final RMS '$rms' m, expected < 1e-9 m"

# the C++ example in place of the Python one: round-off as well
[ -x "$cpp_engine" ] || fail "no C++ example engine given: $cpp_engine"
expect 0 "$clothbench" run "$scenario" -o "$work/cpp" --allow-external \
  --set "engine.python-symplectic-euler.command=[\"$cpp_engine\"]" "${short[@]}"
rms=$(awk -F, '$1 == "python-symplectic-euler" { print $7 }' "$work/stdout")
awk -v r="$rms" 'BEGIN { exit !(r != "" && r + 0 < 1e-9) }' ||
  fail "C++ engine vs custom symplectic Euler: final RMS '$rms' m, expected < 1e-9 m"

# no shipped scenario runs a program
! grep -rl 'kind *= *"external"' "$source/scenarios" >/dev/null ||
  fail "a shipped scenario names an external engine: $(grep -rl 'kind *= *"external"' "$source/scenarios")"

# allowed by the environment
CLOTHBENCH_ALLOW_EXTERNAL=1 expect 0 "$clothbench" run "$scenario" -o "$work/env" "${short[@]}"

# the sweeps and the gate run on it (on a 9 x 9 cloth, to be quick; the stability searches on
# 5 x 5, as their growth states come from a fixed window of 40000 rk4 steps); -j 2 runs two
# engine processes at once
small=(--set "cloth.particles=[9,9]")
tiny=(--set "cloth.particles=[5,5]")
expect 0 "$clothbench" stability "$scenario" -e python-symplectic-euler -o "$work/stab" \
  --allow-external "${tiny[@]}" --set duration=0.05 --dt-max 4e-4 --rel-tol 0.2 -j 2 --quiet
grep -q "^python-symplectic-euler," "$work/stab/stability.csv" ||
  fail "stability.csv has no row of the external engine: $(cat "$work/stab/stability.csv")"
expect 0 "$clothbench" accuracy "$scenario" -e python-symplectic-euler -o "$work/acc" \
  --allow-external "${small[@]}" --set duration=0.02 --dts 2e-4,1e-4 -j 2 --quiet
# -j 2 runs two engine processes at once, each with its own socket: the same rows as one at a
# time
same_rows() {  # FILE_J2 FILE_J1
  cmp -s "$1" "$2" || fail "-j 2 and -j 1 differ: $(diff "$1" "$2" | head -5)"
}
expect 0 "$clothbench" stability "$scenario" -e python-symplectic-euler -o "$work/stab1" \
  --allow-external "${tiny[@]}" --set duration=0.05 --dt-max 4e-4 --rel-tol 0.2 -j 1 --quiet
same_rows "$work/stab/stability.csv" "$work/stab1/stability.csv"
expect 0 "$clothbench" accuracy "$scenario" -e python-symplectic-euler -o "$work/acc1" \
  --allow-external "${small[@]}" --set duration=0.02 --dts 2e-4,1e-4 -j 1 --quiet
same_rows "$work/acc/convergence.csv" "$work/acc1/convergence.csv"
# symplectic Euler is first order: the fitted order of the external engine says so
order=$(awk -F, '$1 == "python-symplectic-euler" { print $3 }' "$work/acc/convergence.csv")
awk -v o="$order" 'BEGIN { exit !(o != "" && o > 0.9 && o < 1.1) }' ||
  fail "accuracy: fitted order of the external symplectic Euler '$order', expected 1"
expect 0 "$clothbench" check "$scenario" -b "$work/baseline" --update --allow-external \
  --record-perturbed "${small[@]}" --set duration=0.05 --quiet
expect 0 "$clothbench" check "$scenario" -b "$work/baseline" --allow-external "${small[@]}" \
  --set duration=0.05 --quiet
expect 0 "$clothbench" report "$work/run"
[ -s "$work/run/report.html" ] || fail "report wrote no report.html"

exit $((failures > 0))
