#!/usr/bin/env bash
# Figures that are undefined read empty, never 0 (issue 27): when the reference blows up in
# its first step, no engine has a final (or largest) distance from it, and the engine that blew
# up before its first frame has no energy error.
# Usage: undefined_metrics.sh CLOTHBENCH SOURCE_DIR WORK_DIR
set -u
clothbench=$1 source=$2 work=$3
source "$(dirname "$0")/expect.sh"
expect 0 "$clothbench" run "$source/scenarios/hanging_chain.toml" -q -o "$work/run" \
  -e custom-midpoint --set engine.custom-rk4.dt=0.05 --set frame_interval=0.05
/usr/bin/python3 - "$work/run/summary.csv" "$work/stdout" <<'PY' || fail "an undefined figure is not empty"
import csv, io, sys
rows = {r["engine"]: r for r in csv.DictReader(open(sys.argv[1]))}
out = {r["engine"]: r for r in csv.DictReader(io.StringIO(open(sys.argv[2]).read()))}
bad = []
if rows["custom-rk4"]["stable"] != "0":
    bad.append("the reference custom-rk4 did not blow up: the test's premise is gone")
for engine in ("custom-rk4", "custom-midpoint"):
    for col in ("final_rms_vs_reference", "max_rms_vs_reference"):
        if rows[engine][col] != "":
            bad.append(f"summary.csv {engine} {col} = {rows[engine][col]!r}, expected empty")
    if out[engine]["final_rms_vs_reference"] != "":
        bad.append(f"stdout {engine} final_rms_vs_reference = {out[engine]['final_rms_vs_reference']!r}")
for where, table in (("summary.csv", rows), ("stdout", out)):
    if table["custom-rk4"]["max_energy_error"] != "":
        bad.append(f"{where}: custom-rk4 max_energy_error = "
                   f"{table['custom-rk4']['max_energy_error']!r}, expected empty")
if rows["custom-midpoint"]["max_energy_error"] in ("", "0"):
    bad.append("custom-midpoint ran stably, yet its energy error is not a number")
print("\n".join(bad) or "undefined figures are empty")
sys.exit(1 if bad else 0)
PY
[ "$failures" -eq 0 ] || exit 1
