#!/usr/bin/env bash
# The report, built from small real runs and a small real sweep made by this build.
# Usage: report_from_real_runs.sh CLOTHBENCH SOURCE_DIR WORK_DIR
# Runs the flag for 0.3 s on a custom and a Bullet engine, the hanging chain (a 1 x 11 grid)
# for 0.5 s, sweeps two integrators' accuracy (time steps and grid resolutions) and stability
# on the flag, then runs analysis/tests' real-folder checks (RealRun on both runs, RealSweep).
# Both runs are seen edge-on from above, so their reports must leave the shadow plot out.
set -euo pipefail
clothbench=$1 source=$2 work=$3
rm -rf "$work"
mkdir -p "$work"
flag=$source/scenarios/flag.toml
chain=$source/scenarios/hanging_chain.toml
short=(--set duration=0.3 --quiet)

"$clothbench" run "$flag" "${short[@]}" -o "$work/run" \
  -e custom-symplectic-euler -e bullet-deformable-explicit >/dev/null
"$clothbench" run "$chain" --set duration=0.5 --quiet -o "$work/chain" >/dev/null
"$clothbench" accuracy "$flag" "${short[@]}" -o "$work/sweep" -e custom-rk4 \
  -i symplectic-euler -i midpoint --halvings 3 --repeats 1 --tolerance 1e-4 \
  --resolutions 5,9 >/dev/null
"$clothbench" stability "$flag" "${short[@]}" -o "$work/sweep" -e custom-rk4 \
  -i symplectic-euler -i midpoint --rel-tol 0.05 >/dev/null

cd "$source"
CLOTHBENCH_RUN_DIR=$work/run CLOTHBENCH_RUN_SKIPPED=shadow CLOTHBENCH_SWEEP_DIR=$work/sweep \
  /usr/bin/python3 -m unittest -v analysis.tests.test_report.RealRun analysis.tests.test_report.RealSweep
CLOTHBENCH_RUN_DIR=$work/chain CLOTHBENCH_RUN_SKIPPED=shadow \
  /usr/bin/python3 -m unittest -v analysis.tests.test_report.RealRun
