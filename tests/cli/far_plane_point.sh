#!/usr/bin/env bash
# A floor is the whole plane, wherever its `point` lies on it (issue 27): with the floor of
# floor_drop given by the point [0, 0, 500] (still the plane y = 0), every engine's cloth must
# come to rest on it, as with [0, 0, 0]. Bullet's floor is a finite box; one centred on the
# point let both Bullet engines fall 0.43 m through the floor and still call the run stable.
# Usage: far_plane_point.sh CLOTHBENCH SOURCE_DIR WORK_DIR
set -u
clothbench=$1 source=$2 work=$3
source "$(dirname "$0")/expect.sh"
expect 0 "$clothbench" run "$source/scenarios/floor_drop.toml" -q -o "$work/far" \
  --set "plane.0.point=[0,0,500]" -e custom-rk4 -e bullet-deformable-explicit \
  -e bullet-softbody-matched
# the last frame of each engine: its lowest particle lies on the floor (within the 1 cm
# contact margin), not below it
/usr/bin/python3 - "$work/far/frames.csv" <<'PY' || fail "a cloth went through the floor"
import csv, sys
last = {}
for row in csv.DictReader(open(sys.argv[1])):
    last[row["engine"]] = row
bad = [f"{e}: min_y {float(r['min_y']):.4g} m at t = {r['t']} s" for e, r in last.items()
       if not float(r["min_y"]) > -0.005]
print("\n".join(bad) or "every cloth rests on the floor: " +
      ", ".join(f"{e} {float(r['min_y']):.4g} m" for e, r in last.items()))
sys.exit(1 if bad or len(last) != 3 else 0)
PY
[ "$failures" -eq 0 ] || exit 1
