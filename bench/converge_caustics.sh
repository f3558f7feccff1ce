#!/usr/bin/env bash
# Error against run time for every caustic-capable method with `rayes converge`:
# a high-spp path-traced reference (seed 1000; the path tracer finds glass-caustic's caustic
# from its area light, slowly), then pt, lt, pm and ppm at doubling effort until BUDGET seconds
# each, with the mean signed error inside the caustic box REGION. CSVs and SVGs go to OUT.
# Usage: bench/converge_caustics.sh [SCENE] [RES] [REF_SPP] [BUDGET] [REGION] [OUT] [METHODS...]
# lbt is passed through like the others (add it to METHODS); for the lbt scenes, with references
# that see their caustics and error masks, use bench/converge_lbt.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
scene=${1:-scenes/glass-caustic.json}
res=${2:-120x90}
refspp=${3:-1024}
budget=${4:-40}
region=${5:-62,50,84,66}
out=${6:-out/converge}
shift $(( $# < 6 ? $# : 6 ))
methods=("$@")
[ ${#methods[@]} -eq 0 ] && methods=(pt lt pm ppm)
mkdir -p "$out"
name=$(basename "$scene" .json)
ref="$out/$name-ref.exr"
[ -f "$ref" ] || nice -n 5 build/bin/rayes render "$scene" --res "$res" --spp "$refspp" --seed 1000 -o "$ref" -q
uptime
for m in "${methods[@]}"; do
  nice -n 5 build/bin/rayes converge "$scene" --reference "$ref" --res "$res" --method "$m" --budget "$budget" \
    --region "$region" --seed 1 -o "$out/$name-$m.csv" -q
  echo "== $m"; cat "$out/$name-$m.csv"
done
uptime
