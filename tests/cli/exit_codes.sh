#!/usr/bin/env bash
# Every exit status the README's table promises: 0 for --help and --version (which prints this
# build's version), 2 for a bad scenario, option or list (one line on stderr), 70 and one line
# for a bug (forced with the test hook CLOTHBENCH_TEST_INTERNAL_ERROR=1), 130 on Ctrl-C.
# Usage: exit_codes.sh CLOTHBENCH SOURCE_DIR WORK_DIR VERSION
set -u
clothbench=$1 source=$2 work=$3 version=$4
source "$(dirname "$0")/expect.sh"
one_line() { [ "$(wc -l <"$work/stderr")" -eq 1 ] || fail "$1: expected one line on stderr: $(cat "$work/stderr")"; }

# 0: --help on every command, --version with the version CMake built
for sub in "" run stability accuracy check list; do
  expect 0 "$clothbench" $sub --help
done
expect 0 "$clothbench" --version
[ "$(cat "$work/stdout")" = "clothbench $version" ] || fail "--version printed \"$(cat "$work/stdout")\", not \"clothbench $version\""

# 2: a bad scenario, a bad option, a bad list, no command
expect 2 "$clothbench" run "$source/tests/data/bad/dt_zero.toml" -o "$work/bad" --quiet
one_line "bad scenario"
expect 2 "$clothbench" run --no-such-option
expect 2 "$clothbench" accuracy "$source/scenarios/hanging_chain.toml" -o "$work/badlist" --dts 1e-3,fast
one_line "bad --dts"
grep -q -- '--dts: .*"fast"' "$work/stderr" || fail "bad --dts: value not named: $(cat "$work/stderr")"
expect 2 "$clothbench"

# 70: a bug, one line that says so and what a bug report needs
CLOTHBENCH_TEST_INTERNAL_ERROR=1 expect 70 "$clothbench" list
one_line "internal error"
grep -q "^clothbench: internal error (a bug in clothbench): .*--version" "$work/stderr" ||
  fail "internal error: message does not say it is a bug and what to report: $(cat "$work/stderr")"
[ ! -s "$work/stdout" ] || fail "internal error: the command ran anyway"

# 130: Ctrl-C, with what is left behind (a run writes nothing, a sweep keeps its rows)
interrupt() {
  local what=$1 note=$2
  shift 2
  "$clothbench" "$@" >/dev/null 2>"$work/stderr" &
  local pid=$!
  sleep 1
  kill -INT "$pid"
  wait "$pid"
  local got=$?
  [ "$got" -eq 130 ] || fail "interrupted $what: expected exit 130, got $got"
  grep -q "^clothbench: interrupted; $note" "$work/stderr" ||
    fail "interrupted $what: no \"$note\": $(cat "$work/stderr")"
}
interrupt run "no output written" run "$source/scenarios/seed_sphere_drape.toml" -o "$work/run" -q
interrupt stability "the finished rows are kept" stability "$source/scenarios/seed_sphere_drape.toml" \
  -o "$work/stability" -q -j 1

echo "exit codes: $failures failed checks"
[ "$failures" -eq 0 ]
