#!/usr/bin/env bash
# Regenerate the fixture folders that are real clothbench output (the others come from
# make_fixtures.py). Each is a short run of a shipped scenario, small enough to keep in git.
#
#   analysis/tests/make_real_fixtures.sh CLOTHBENCH      # from the repository root
#
# Folders written under analysis/tests/fixtures/:
#   chain/            hanging_chain (a 1 x 11 grid: no triangles, no shadow from above), 1 s
#   edge_on/          flag on a 6 x 4 grid, 0.4 s: a vertical cloth, edge-on from above
set -euo pipefail
[[ $# -eq 1 ]] || { echo "usage: analysis/tests/make_real_fixtures.sh CLOTHBENCH" >&2; exit 2; }
clothbench=$1
fixtures=analysis/tests/fixtures
[[ -d $fixtures && -d scenarios ]] || { echo "run from the repository root" >&2; exit 2; }
rm -rf "$fixtures/chain" "$fixtures/edge_on"

"$clothbench" run scenarios/hanging_chain.toml --quiet -o "$fixtures/chain" \
  --set duration=1.0 --set frame_interval=0.02 \
  -e custom-rk4 -e custom-implicit-euler -e bullet-deformable-explicit >/dev/null
"$clothbench" run scenarios/flag.toml --quiet -o "$fixtures/edge_on" \
  --set duration=0.4 --set frame_interval=0.02 --set snapshot_interval=0.2 \
  --set 'cloth.particles=[6,4]' \
  -e custom-rk4 -e custom-symplectic-euler -e bullet-deformable-explicit >/dev/null
echo "wrote $fixtures/chain, edge_on"
