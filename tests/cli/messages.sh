#!/usr/bin/env bash
# Messages that name the right thing (issue 27): a bad --vary value is the --vary option's,
# a grid of --resolutions is that option's (both are applied as overrides, never given as
# --set), an infinite number "must be finite", an integer past the range "too large: at most
# N", and running out of memory is the user's input (exit 2 with what to change), not a bug.
# Usage: messages.sh CLOTHBENCH SOURCE_DIR WORK_DIR
set -u
clothbench=$1 source=$2 work=$3
source "$(dirname "$0")/expect.sh"
has() { grep -q -- "$2" "$work/$1" || fail "$3: no \"$2\" in $1: $(head -c 400 "$work/$1")"; }
lacks() { ! grep -q -- "$2" "$work/$1" || fail "$3: \"$2\" in $1: $(head -c 400 "$work/$1")"; }
chain=$source/scenarios/hanging_chain.toml

expect 2 "$clothbench" map "$chain" -q -o "$work/map" --vary cloth.damping=0,abc
has stderr "clothbench: --vary cloth.damping=0,abc: the value abc: expected a number >= 0" "bad --vary value"
lacks stderr "--set" "bad --vary value"
expect 2 "$clothbench" accuracy "$source/scenarios/flag.toml" -q -o "$work/acc" --resolutions 5,5000
has stderr "clothbench: --resolutions 5000: expected at most 10000000 particles in all" "--resolutions too fine"
lacks stderr "--set" "--resolutions too fine"
expect 2 "$clothbench" run "$chain" -q -o "$work/run" --set blowup_strain=inf
has stderr "blowup_strain: must be finite (a number > 0), got inf" "infinite blowup_strain"
expect 2 "$clothbench" run "$chain" -q -o "$work/run" --set "cloth.particles=[99999999999,2]"
has stderr "cloth.particles: too large: at most 10000000 particles in all" "huge integer"

# an option the parser refuses is one line in clothbench's form, naming the command's --help
expect 2 "$clothbench" stability "$chain" -q -o "$work/x" --growth-tol -1
[ "$(wc -l <"$work/stderr")" -eq 1 ] || fail "option error: not one line: $(cat "$work/stderr")"
has stderr '^clothbench: --growth-tol: expected a finite number > 0, got "-1" (see clothbench stability --help)$' \
  "option error"

# a line of the file that an override made wrong says which overrides were applied
expect 2 "$clothbench" run "$chain" -q -o "$work/run" --set "cloth.particles=[1,2]"
has stderr "hanging_chain.toml:[0-9]*: constraint.0.list.0: .* (with --set cloth.particles=\[1,2\] applied)" \
  "a file line made wrong by an override"

# a damaged baseline (a row deleted, a row given twice) is an error naming file and line,
# before any run, never a failing gate
mkdir -p "$work/damaged"
cp -r "$source/reference/baselines/hanging_chain" "$work/damaged/"
metrics=$work/damaged/hanging_chain/metrics.csv
cp "$metrics" "$work/metrics.good"
grep -v '^custom-rk4,drape_coefficient,' "$work/metrics.good" >"$metrics"
expect 2 "$clothbench" check -q -b "$work/damaged" "$chain"
has stderr "hanging_chain/metrics.csv: no row for custom-rk4,drape_coefficient (custom-rk4's rows: lines 2 to" \
  "baseline with a deleted row"
lacks stdout "FAIL" "baseline with a deleted row"
cp "$work/metrics.good" "$metrics"
sed -n 2p "$work/metrics.good" >>"$metrics"
expect 2 "$clothbench" check -q -b "$work/damaged" "$chain"
has stderr "hanging_chain/metrics.csv:$(wc -l <"$metrics"): a second row for custom-rk4,.* (the first is line 2)" \
  "baseline with a row twice"
# ... which --update rewrites (a short run: the baseline's form is tested here, not the chain)
expect 0 "$clothbench" check -q --update --record-perturbed -b "$work/damaged" "$chain" --set duration=0.2
expect 0 "$clothbench" check -q -b "$work/damaged" "$chain" --set duration=0.2

# a row gated by an ensemble: check runs the ensemble and gates it by default, --no-ensemble
# shows the row without gating it (and says so)
cat >>"$work/damaged/hanging_chain/tolerances.toml" <<'TOML'
[ensemble.custom-symplectic-euler]
members = 3
quantities = ["final_com_y"]
reason = "a check of the command line's default"
TOML
expect 0 "$clothbench" check -q --update --record-perturbed -b "$work/damaged" "$chain" --set duration=0.2
expect 0 "$clothbench" check -q -b "$work/damaged" "$chain" --set duration=0.2
has stdout "custom-symplectic-euler .*final_com_y .*ensemble of 3" "an ensemble row gated by default"
lacks stdout "not run (--no-ensemble)" "an ensemble row gated by default"
expect 0 "$clothbench" check -q --no-ensemble -b "$work/damaged" "$chain" --set duration=0.2
has stdout "final_com_y .*gated by its ensemble, not run (--no-ensemble)" \
  "an ensemble row with --no-ensemble"

# out of memory: a cloth that cannot fit under a 1 GiB address-space limit (not under a
# sanitizer, which reserves far more address space than that on its own)
if ldd "$clothbench" 2>/dev/null | grep -q libasan; then
  echo "out-of-memory case not run under AddressSanitizer"
else
  ( ulimit -v 1048576; exec "$clothbench" run "$source/scenarios/seed_sphere_drape.toml" -q -o "$work/oom" \
      --set "cloth.particles=[3000,3000]" --set duration=0.01 --set frame_interval=0.01 ) \
    >"$work/stdout" 2>"$work/stderr"
  status=$?
  [ "$status" -eq 2 ] || fail "out of memory: exit $status, expected 2: $(head -c 300 "$work/stderr")"
  has stderr "clothbench: out of memory" "out of memory"
  lacks stderr "bug" "out of memory"
fi
[ "$failures" -eq 0 ] || exit 1
echo "every message names the option or key the user gave"
