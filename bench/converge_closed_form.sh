#!/usr/bin/env bash
# Error against time for every method on the closed-form caustic of scenes/caustic-closed-form.json
# (a point light in a tilted planar mirror on a diffuse ceiling; tests/support/closed_form_caustic.h),
# the caustic estimate alone (--caustic-paths only), against the closed-form image that
# bench_app_closed_form_caustic writes: `rayes converge` per method, BUDGET seconds each, RMSE over
# the whole image (edges included) and the mean signed error in the interior box REGION. pt cannot
# sample a point light through a mirror (a delta lobe meets a delta light): its curve stays at
# the closed form's own RMSE. Then bench/equal_rmse.py-style reading: CPU seconds to a given RMSE.
# Usage: bench/converge_closed_form.sh OUT [RES] [BUDGET]   env: METHODS ("lt pm ppm lbt pt"),
#   PHOTONS (20000), BEAM_RES (32), REGION (the interior box of the default 80x80 image)
set -euo pipefail
cd "$(dirname "$0")/.."
out=$1 res=${2:-80x80} budget=${3:-20}
scene=scenes/caustic-closed-form.json
mkdir -p "$out"
build/bin/bench_app_closed_form_caustic reference "$scene" "$res" "$out/closed-form.exr" "$out/interior.exr" 0.3
for m in ${METHODS:-lt pm ppm lbt pt}; do
  uptime
  nice -n 5 build/bin/rayes converge "$scene" --reference "$out/closed-form.exr" --res "$res" --caustic-paths only \
    --budget "$budget" --region "${REGION:-24,24,56,56}" --seed 1 --photons "${PHOTONS:-20000}" \
    --beam-resolution "${BEAM_RES:-32}" --method "$m" -o "$out/$m.csv" -q
  echo "== $m"; cat "$out/$m.csv"
done
