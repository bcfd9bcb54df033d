#!/usr/bin/env bash
# The command line's contract: bad input is one line on stderr naming the file, line and key,
# exit status 2 and nothing written; an interrupted run exits 130 and leaves no CSV behind.
# Usage: exit_codes_and_no_partial_output.sh CLOTHBENCH SOURCE_DIR WORK_DIR
set -u
clothbench=$1 source=$2 work=$3
source "$(dirname "$0")/expect.sh"

# a malformed scenario: exit 2, one line naming file:line: key, no output folder
bad=$source/tests/data/bad/dt_zero.toml
expect 2 "$clothbench" run "$bad" -o "$work/bad" --quiet
[ "$(wc -l <"$work/stderr")" -eq 1 ] || fail "bad scenario: expected one line on stderr"
grep -q "^clothbench: $bad:[0-9]*: engine\..*dt" "$work/stderr" || fail "bad scenario: message does not name file, line and key: $(cat "$work/stderr")"
[ ! -e "$work/bad" ] || fail "bad scenario: output folder was created"

# a bad override: the same
expect 2 "$clothbench" run "$source/scenarios/flag.toml" -o "$work/badset" --set duration=0.005 --quiet
grep -q "duration" "$work/stderr" || fail "bad override: message does not name the key"
[ ! -e "$work/badset" ] || fail "bad override: output folder was created"

# an unknown command-line option
expect 2 "$clothbench" run --no-such-option

# an unwritable output folder: exit 2 naming it
expect 2 "$clothbench" run "$source/scenarios/hanging_chain.toml" -o /proc/clothbench-out --quiet
grep -q "/proc/clothbench-out" "$work/stderr" || fail "unwritable folder: not named: $(cat "$work/stderr")"

# --help answers on every command
for sub in "" run list stability accuracy check; do
  expect 0 "$clothbench" $sub --help
  [ -s "$work/stdout" ] || fail "clothbench $sub --help printed nothing"
done

# an interrupted run: exit 130 and no CSV anywhere in its output folder
"$clothbench" run "$source/scenarios/seed_sphere_drape.toml" -o "$work/interrupted" --quiet \
  >/dev/null 2>"$work/stderr" &
pid=$!
sleep 1
kill -INT "$pid"
wait "$pid"
status=$?
[ "$status" -eq 130 ] || fail "interrupted run: expected exit 130, got $status"
if [ -e "$work/interrupted" ] && [ -n "$(find "$work/interrupted" -type f)" ]; then
  fail "interrupted run left files: $(find "$work/interrupted" -type f)"
fi

# a good run: exit 0, every file there and no temporary file left
expect 0 "$clothbench" run "$source/scenarios/hanging_chain.toml" -o "$work/good" --quiet --set duration=0.1
for f in frames.csv divergence.csv snapshots.csv summary.csv scenario.toml run.json; do
  [ -s "$work/good/$f" ] || fail "good run: $f missing"
done
[ -z "$(find "$work/good" -name '.*')" ] || fail "good run: temporary files left"

echo "command-line contract: $failures failed checks"
[ "$failures" -eq 0 ]
