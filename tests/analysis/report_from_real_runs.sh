#!/usr/bin/env bash
# The report, built from a small real run and a small real sweep made by this build.
# Usage: report_from_real_runs.sh CLOTHBENCH SOURCE_DIR WORK_DIR
# Runs the flag for 0.3 s on a custom and a Bullet engine, sweeps two integrators' accuracy and
# stability on it, then runs analysis/tests' real-folder checks (RealRun, RealSweep) on them.
set -euo pipefail
clothbench=$1 source=$2 work=$3
rm -rf "$work"
mkdir -p "$work"
flag=$source/scenarios/flag.toml
short=(--set duration=0.3 --quiet)

"$clothbench" run "$flag" "${short[@]}" -o "$work/run" \
  -e custom-symplectic-euler -e bullet-deformable-explicit >/dev/null
"$clothbench" accuracy "$flag" "${short[@]}" -o "$work/sweep" -e custom-rk4 \
  -i symplectic-euler -i midpoint --halvings 3 --repeats 1 --tolerance 1e-4 >/dev/null
"$clothbench" stability "$flag" "${short[@]}" -o "$work/sweep" -e custom-rk4 \
  -i symplectic-euler -i midpoint --rel-tol 0.05 >/dev/null

cd "$source"
CLOTHBENCH_RUN_DIR=$work/run CLOTHBENCH_SWEEP_DIR=$work/sweep \
  /usr/bin/python3 -m unittest -v analysis.tests.test_report.RealRun analysis.tests.test_report.RealSweep
