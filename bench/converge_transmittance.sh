#!/usr/bin/env bash
# Error against run time of the shadow rays' transmittance estimators through a heterogeneous
# cloud (issue 34's goal: ratio tracking's RMSE at equal time <= 0.5x delta tracking's): the
# ground under scenes/cloud.json's cloud seen from below it, lit by the distant light alone,
# direct light only (max_depth 1), so the noise is the shadow rays' (the camera rays do not cross
# the cloud). A ratio-tracking reference of REF_SPP, then `rayes converge` with
# integrator.transmittance "ratio" and "delta" for BUDGET seconds each. CSVs go to OUT.
# Usage: bench/converge_transmittance.sh [RES] [REF_SPP] [BUDGET] [OUT]
set -euo pipefail
cd "$(dirname "$0")/.."
res=${1:-96x60}
refspp=${2:-4096}
budget=${3:-30}
out=${4:-out/transmittance}
mkdir -p "$out"
[ -f scenes/cloud.vdb ] || build/bin/make_cloud_vdb scenes/cloud.vdb
cp scenes/cloud.vdb "$out/"
for t in ratio delta; do
  python3 - "$out/shadow-$t.json" "$t" <<'PY'
import json, sys
s = json.load(open("scenes/cloud.json"))
s["camera"] = {"position": [-1.05, 0.7, -0.6], "look_at": [-1.05, 0, -0.84], "up": [0, 0, -1], "fov": 70}
s["integrator"]["max_depth"] = 1
s["integrator"]["transmittance"] = sys.argv[2]
s["lights"] = [l for l in s["lights"] if l["type"] == "distant"]
json.dump(s, open(sys.argv[1], "w"), indent=1)
PY
done
ref="$out/shadow-ref.exr"
[ -f "$ref" ] || build/bin/rayes render "$out/shadow-ratio.json" --res "$res" --spp "$refspp" -o "$ref" -q
uptime
for t in ratio delta; do
  build/bin/rayes converge "$out/shadow-$t.json" --reference "$ref" --budget "$budget" --res "$res" -q \
    -o "$out/shadow-$t.csv"
done
uptime
