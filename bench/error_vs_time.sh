#!/usr/bin/env bash
# Error against run time for the path tracer on a scene (standing requirement 1):
# renders a high-spp reference, then an independent render (another seed) with --reference,
# and prints the RMSE after every pass against the time spent.
# Usage: bench/error_vs_time.sh [SCENE] [RES] [REF_SPP] [SPP]
# The reference's own noise is RMSE(1 spp) / sqrt(REF_SPP): the curve is only meaningful
# well above that floor (printed as well).
set -euo pipefail
cd "$(dirname "$0")/.."
scene=${1:-scenes/teapot.json}
res=${2:-160x120}
refspp=${3:-1024}
spp=${4:-64}
out=$(mktemp -d)
build/bin/rayes render "$scene" --res "$res" --spp "$refspp" --seed 1000 -o "$out/ref.exr" -q
build/bin/rayes render "$scene" --res "$res" --spp "$spp" --seed 1 -o "$out/run.exr" \
  --reference "$out/ref.exr" --stats "$out/stats.json" -q
python3 - "$out/stats.json" "$refspp" <<'PY'
import json, math, sys
s = json.load(open(sys.argv[1])); refspp = int(sys.argv[2])
curve = s["error_vs_time"]
print(f"{'spp':>5} {'time_s':>8} {'rmse':>10} {'rmse*sqrt(spp)':>15}")
for e in curve:
    print(f"{e['spp']:>5} {e['time_s']:>8.2f} {e['rmse']:>10.5f} {e['rmse']*math.sqrt(e['spp']):>15.5f}")
floor = curve[0]["rmse"] / math.sqrt(refspp)
print(f"reference noise floor ~ {floor:.5f} (RMSE at 1 spp / sqrt({refspp}))")
PY
rm -rf "$out"
