#!/usr/bin/env bash
# Error against CPU time for lbt, pm, ppm and pt on the lbt scenes (bench/history/2026-11.md, "Light
# beam tracing measured"): references and error masks by bench/lbt_references.sh, then `rayes
# converge` per method with one geometry for every ray (--lod fixed --max-lod 6, as the references),
# the error counted where the reference is complete (--error-mask) and the bias inside the caustic
# box REGION, then bench/equal_rmse.py for the equal-RMSE ratios and the charts. Effort per step
# (docs/design.md, "Caustic paths"): spp doubles; pm and ppm trace PHOTONS per sample (so their
# photons double); lbt starts at BEAM_RES cells per side and grows by sqrt 2 per step (twice the
# beams), BEAM_GROWTH overriding it. Usage: bench/converge_lbt.sh OUT RES BUDGET SCENE=REGION...
# (env: PHOTONS, BEAM_RES, BEAM_GROWTH, METHODS, LOBE_CELLS (lbt's --beam-lobe-cells, default 2),
# CAUSTIC_PATHS=only (the caustic estimate alone, against the reference's caustic part
# NAME-ref-lt.exr alone; CSVs named NAME-M-only.csv); TAG is appended to lbt's CSV name: another lbt
# schedule, compared as its own row by equal_rmse.py)
set -euo pipefail
cd "$(dirname "$0")/.."
out=$1 res=$2 budget=$3
shift 3
photons=${PHOTONS:-20000}
beamres=${BEAM_RES:-32}
growth=${BEAM_GROWTH:-1.4142135623730951}
read -r -a methods <<< "${METHODS:-lbt pm ppm pt}"
names=()
for arg in "$@"; do
  scene=${arg%%=*} region=${arg#*=}
  name=$(basename "$scene" .json)
  names+=("$name")
  for m in "${methods[@]}"; do
    only=${CAUSTIC_PATHS:+-$CAUSTIC_PATHS}
    file="$out/$name-$m$only.csv"
    [ "$m" = lbt ] && file="$out/$name-lbt${TAG:-}$only.csv"
    refs=(--reference "$out/$name-ref-pt.exr" --reference "$out/$name-ref-lt.exr")
    [ -n "$only" ] && refs=(--reference "$out/$name-ref-lt.exr")
    uptime
    nice -n 5 build/bin/rayes converge "$scene" "${refs[@]}" \
      --error-mask "$out/$name-mask.exr" --region "$region" --res "$res" --lod fixed --max-lod 6 --method "$m" \
      --budget "$budget" --seed 1 --photons "$photons" --beam-resolution "$beamres" --beam-growth "$growth" \
      --beam-lobe-cells "${LOBE_CELLS:-2}" ${CAUSTIC_PATHS:+--caustic-paths "$CAUSTIC_PATHS"} -o "$file" -q
    echo "== $file"; cat "$file"
  done
done
uptime
python3 bench/equal_rmse.py "$out" "${names[@]}"
