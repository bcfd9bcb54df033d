#!/usr/bin/env bash
# Regenerate the fixture folders that are real clothbench output (the others come from
# make_fixtures.py). Each is a short run of a shipped scenario, small enough to keep in git.
#
#   analysis/tests/make_real_fixtures.sh CLOTHBENCH      # from the repository root
#
# Folders written under analysis/tests/fixtures/:
#   chain/            hanging_chain (a 1 x 11 grid: no triangles, no shadow from above), 1 s
#   edge_on/          flag on a 6 x 4 grid, 0.4 s: a vertical cloth, edge-on from above
#   stability_chain/  stability on hanging_chain up to --dt-max 0.003 s: one limit found, one
#                     search stopped at dt-max (censored), implicit Euler predicted infinite
#   accuracy_flag/    accuracy on flag with --tolerance 1e-30 (nothing meets it) and
#                     --resolutions 5,9,13 (resolution.csv)
set -euo pipefail
[[ $# -eq 1 ]] || { echo "usage: analysis/tests/make_real_fixtures.sh CLOTHBENCH" >&2; exit 2; }
clothbench=$1
fixtures=analysis/tests/fixtures
[[ -d $fixtures && -d scenarios ]] || { echo "run from the repository root" >&2; exit 2; }
rm -rf "$fixtures/chain" "$fixtures/edge_on" "$fixtures/stability_chain" "$fixtures/accuracy_flag"

"$clothbench" run scenarios/hanging_chain.toml --quiet -o "$fixtures/chain" \
  --set duration=1.0 --set frame_interval=0.02 \
  -e custom-rk4 -e custom-implicit-euler -e bullet-deformable-explicit >/dev/null
"$clothbench" run scenarios/flag.toml --quiet -o "$fixtures/edge_on" \
  --set duration=0.4 --set frame_interval=0.02 --set snapshot_interval=0.2 \
  --set 'cloth.particles=[6,4]' \
  -e custom-rk4 -e custom-symplectic-euler -e bullet-deformable-explicit >/dev/null
"$clothbench" stability scenarios/hanging_chain.toml --quiet -o "$fixtures/stability_chain" \
  --set duration=0.3 --dt-max 0.003 --rel-tol 0.05 \
  -e custom-rk4 -i symplectic-euler -i rk4 -i implicit-euler >/dev/null
"$clothbench" accuracy scenarios/flag.toml --quiet -o "$fixtures/accuracy_flag" \
  --set duration=0.2 --halvings 2 --repeats 1 --tolerance 1e-30 --resolutions 5,9,13 \
  -e custom-rk4 -e bullet-deformable-explicit -i symplectic-euler -i midpoint >/dev/null
echo "wrote $fixtures/chain, edge_on, stability_chain, accuracy_flag"
