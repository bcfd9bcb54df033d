#!/usr/bin/env bash
# Writing where a command must not (issue 27): every output path is checked before any work
# starts. check --junit/--json never replace an input (the scenario, a baseline file), never
# write into a folder another command holds, never share one file, and "-" is standard output;
# a symlink given as an output (run -o LINK, --junit LINK) is written through, never replaced.
# Usage: output_paths.sh CLOTHBENCH SOURCE_DIR WORK_DIR
set -u
clothbench=$1 source=$2 work=$3
source "$(dirname "$0")/expect.sh"
has() { grep -q -- "$2" "$work/$1" || fail "$3: no \"$2\" in $1: $(head -c 400 "$work/$1")"; }
chain=$source/scenarios/hanging_chain.toml

# a copy of a scenario and of its baseline, so that a wrong write would show and harm nothing
cp "$chain" "$work/chain.toml"
mkdir -p "$work/baselines"
cp -r "$source/reference/baselines/hanging_chain" "$work/baselines/"
sum_before=$(cat "$work/chain.toml" "$work/baselines/hanging_chain"/* | md5sum)
unchanged() {
  [ "$(cat "$work/chain.toml" "$work/baselines/hanging_chain"/* | md5sum)" = "$sum_before" ] ||
    fail "$1: an input was written"
}

# the scenario being checked, a baseline's file, a folder: refused before any run, exit 2
expect 2 "$clothbench" check "$work/chain.toml" -b "$work/baselines" --junit "$work/chain.toml"
has stderr "--junit $work/chain.toml is the scenario file" "--junit SCENARIO"
unchanged "--junit SCENARIO"
expect 2 "$clothbench" check "$work/chain.toml" -b "$work/baselines" \
  --json "$work/baselines/hanging_chain/metrics.csv"
has stderr "lies in the folder $work/baselines" "--json BASELINE/metrics.csv"
unchanged "--json BASELINE/metrics.csv"
expect 2 "$clothbench" check "$work/chain.toml" -b "$work/baselines" --json "$work"
has stderr "is a folder" "--json FOLDER"
# ... and a symlink to the scenario is the scenario
ln -s "$work/chain.toml" "$work/link-to-scenario.xml"
expect 2 "$clothbench" check "$work/chain.toml" -b "$work/baselines" --junit "$work/link-to-scenario.xml"
has stderr "is the scenario file" "--junit LINK-TO-SCENARIO"
unchanged "--junit LINK-TO-SCENARIO"

# one file for both reports, or "-" twice: refused at once, naming both options
expect 2 "$clothbench" check "$work/chain.toml" -b "$work/baselines" --junit "$work/g" --json "$work/g"
has stderr "--json and --junit both name $work/g" "same file twice"
[ ! -e "$work/g" ] || fail "same file twice: $work/g was written"
expect 2 "$clothbench" check "$work/chain.toml" -b "$work/baselines" --junit - --json -
has stderr "both name standard output" "- twice"

# a folder another clothbench command holds (its lock, taken here by flock(1) as a command would)
mkdir -p "$work/busy"
echo "pid 1: clothbench run -o busy" >"$work/busy/.clothbench.lock"
flock -o "$work/busy/.clothbench.lock" sleep 60 >/dev/null 2>&1 &
holder=$!
sleep 0.3
expect 2 "$clothbench" check "$work/chain.toml" -b "$work/baselines" --junit "$work/busy/gates.xml"
has stderr "the folder $work/busy is in use by another clothbench command" "--junit LOCKED/x"
[ ! -e "$work/busy/gates.xml" ] || fail "--junit LOCKED/x: written"
pkill -P "$holder" 2>/dev/null
kill "$holder" 2>/dev/null
wait "$holder" 2>/dev/null

# the same file twice, or two scenarios of one name: refused, naming them
expect 2 "$clothbench" check "$work/chain.toml" "$work/chain.toml" -b "$work/baselines"
has stderr "is given twice" "one scenario twice"
cp "$work/chain.toml" "$work/chain2.toml"
expect 2 "$clothbench" check "$work/chain.toml" "$work/chain2.toml" -b "$work/baselines"
has stderr 'are both named "hanging_chain"' "two scenarios of one name"

# "-" is standard output: the JSON there (and only it), the gate table on stderr
expect 0 "$clothbench" check "$work/chain.toml" -b "$work/baselines" -q --json -
/usr/bin/python3 -c 'import json,sys; json.load(open(sys.argv[1]))' "$work/stdout" ||
  fail "--json -: stdout is not JSON: $(head -c 300 "$work/stdout")"
has stderr "gates passed" "--json -: the table on stderr"
[ ! -e "$work/-" ] && [ ! -e "./-" ] || fail "--json -: a file named - was written"

# --junit LINK writes the file the link points to and keeps the link
: >"$work/target.xml"
ln -s target.xml "$work/link.xml"
expect 0 "$clothbench" check "$work/chain.toml" -b "$work/baselines" -q --junit "$work/link.xml"
[ -L "$work/link.xml" ] || fail "--junit LINK: the link was replaced"
grep -q "<testsuites" "$work/target.xml" || fail "--junit LINK: its target was not written"
unchanged "the checks above"

# run -o LINK writes into the folder the link points to and keeps the link; a dangling one is
# refused
mkdir -p "$work/real-out"
ln -s real-out "$work/out-link"
expect 0 "$clothbench" run "$chain" -q -o "$work/out-link" --set duration=0.05
[ -L "$work/out-link" ] || fail "run -o LINK: the link was replaced"
[ -f "$work/real-out/summary.csv" ] || fail "run -o LINK: no summary.csv in the link's folder"
ln -s nowhere "$work/dangling"
expect 2 "$clothbench" run "$chain" -q -o "$work/dangling" --set duration=0.05
has stderr "is a symlink to nowhere, which does not exist" "run -o DANGLING"

[ "$failures" -eq 0 ] || exit 1
echo "every output path is checked before any work, and symlinks are written through"
