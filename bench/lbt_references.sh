#!/usr/bin/env bash
# References and error masks for the lbt error-against-time curves (bench/converge_lbt.sh).
# At RES with one geometry for every ray (--lod fixed --max-lod 6: per-ray LOD would give camera
# and light paths different dicings of the curved scatterers), a scene's reference is the sum of
#   NAME-ref-pt.exr  pt --caustic-paths without, PT_SPP samples (seed 1000): everything but caustic paths
#   NAME-ref-lt.exr  lt --caustic-paths only, LT_SPP light paths per pixel (seed 1000): the caustic paths
# plus NAME-ref-lt-check.exr (lt only, LT_SPP/4, seed 2000) to measure the reference's own noise:
# RMSE(check, ref-lt)² = 5 · (RMSE of ref-lt)², and NAME-mask.exr: the pixels that see no
# scatterer anywhere (bench/lbt_error_mask_scene.py renders NAME-coverage.exr, the fraction of
# each pixel that does not; bench_app_mask_threshold keeps those at 1).
# Stops (exit 1) when the two lt images differ by fireflies in the masked pixels
# (bench/reference_fireflies.py).
# Usage: bench/lbt_references.sh OUT RES PT_SPP LT_SPP SCENE...
set -euo pipefail
cd "$(dirname "$0")/.."
out=$1 res=$2 ptspp=$3 ltspp=$4
shift 4
mkdir -p "$out"
geometry=(--res "$res" --lod fixed --max-lod 6 -q)
for scene in "$@"; do
  name=$(basename "$scene" .json)
  uptime
  [ -f "$out/$name-ref-pt.exr" ] || /usr/bin/time -f "$name pt: %U+%S s CPU, %e s wall" nice -n 5 build/bin/rayes render \
    "$scene" "${geometry[@]}" --method pt --caustic-paths without --spp "$ptspp" --seed 1000 -o "$out/$name-ref-pt.exr"
  [ -f "$out/$name-ref-lt.exr" ] || /usr/bin/time -f "$name lt: %U+%S s CPU, %e s wall" nice -n 5 build/bin/rayes render \
    "$scene" "${geometry[@]}" --method lt --caustic-paths only --spp "$ltspp" --seed 1000 -o "$out/$name-ref-lt.exr"
  [ -f "$out/$name-ref-lt-check.exr" ] || nice -n 5 build/bin/rayes render "$scene" "${geometry[@]}" --method lt \
    --caustic-paths only --spp $((ltspp / 4)) --seed 2000 -o "$out/$name-ref-lt-check.exr"
  if [ ! -f "$out/$name-mask.exr" ]; then
    python3 bench/lbt_error_mask_scene.py "$scene" "$out/$name-mask.json"
    nice -n 5 build/bin/rayes render "$out/$name-mask.json" "${geometry[@]}" --spp 16 --seed 1000 \
      -o "$out/$name-coverage.exr"
    build/bin/bench_app_mask_threshold "$out/$name-coverage.exr" "$out/$name-mask.exr"
  fi
  # A firefly in either image floors every method's RMSE: refuse it here, not after hours of curves.
  python3 bench/reference_fireflies.py "$out/$name-ref-lt.exr" "$out/$name-ref-lt-check.exr" --mask "$out/$name-mask.exr"
done
uptime
