#!/usr/bin/env bash
# pm and ppm against the closed-form caustic of scenes/caustic-closed-form.json (a point light in a
# tilted planar mirror on a diffuse ceiling; tests/support/closed_form_caustic.h), the caustic
# estimate alone (--caustic-paths only):
#   1. the closed-form reference image and its interior mask (pixels at least MARGIN ceiling units
#      inside the footprint) by bench_app_closed_form_caustic;
#   2. bias: pm at each K of KS, SEEDS seeds at SPP samples (PHOTONS per sample): the interior
#      ratio (image / closed form over the mask) and the flux ratio (the image's flux over
#      ρ·I·Ω), mean ± standard error over the seeds; BIN picks the rayes binary (a build of the
#      commit before, for "before" figures; its name goes into the output files' names via TAG);
#   3. error against time (unless CONVERGE=0): `rayes converge` for pm (k = 32) and ppm at each
#      ALPHA x RADIUS setting of PPM (default the shipped one plus candidates), BUDGET seconds each,
#      RMSE over the whole image (edges included) and the mean signed error in the interior box
#      REGION.
# Usage: bench/converge_pm.sh OUT [RES] [SPP] [SEEDS] [BUDGET]
#   env: BIN (build/bin/rayes), TAG, KS ("32 128"; " ": none), PHOTONS (20000), MARGIN (0.3), CONVERGE (1),
#        PM (1; 0: no pm curve),
#        PPM ("0.6667:0 0.5:0 0.8:0 0.6667:0.05 0.6667:0.2": alpha:radius, radius 0 = automatic),
#        REGION (the interior box of the default 80x80 image)
set -euo pipefail
cd "$(dirname "$0")/.."
out=$1 res=${2:-80x80} spp=${3:-16} seeds=${4:-8} budget=${5:-30}
bin=${BIN:-build/bin/rayes}
tag=${TAG:-}
scene=scenes/caustic-closed-form.json
mkdir -p "$out"
build/bin/bench_app_closed_form_caustic reference "$scene" "$res" "$out/closed-form.exr" "$out/interior.exr" "${MARGIN:-0.3}"
uptime
for k in ${KS:-32 128}; do
  images=()
  for s in $(seq 1 "$seeds"); do
    img="$out/pm$tag-k$k-s$s.exr"
    nice -n 5 "$bin" render "$scene" --method pm --caustic-paths only --photon-k "$k" --photons "${PHOTONS:-20000}" \
      --res "$res" --spp "$spp" --seed "$s" -q -o "$img"
    images+=("$img")
  done
  echo "== pm$tag k = $k, $seeds seeds, $spp spp, ${PHOTONS:-20000} photons per sample"
  build/bin/bench_app_closed_form_caustic measure "$scene" "$res" "$out/interior.exr" "${images[@]}" | tail -2
done
uptime
[ "${CONVERGE:-1}" = 0 ] && exit 0
run() {  # NAME, then rayes options
  local name=$1
  shift
  nice -n 5 "$bin" converge "$scene" --reference "$out/closed-form.exr" --res "$res" --caustic-paths only \
    --budget "$budget" --region "${REGION:-24,24,56,56}" --seed 1 --photons "${PHOTONS:-20000}" "$@" \
    -o "$out/$name.csv" -q
  echo "== $name"; cat "$out/$name.csv"
}
[ "${PM:-1}" = 0 ] || run "pm$tag" --method pm
for setting in ${PPM:-0.6667:0 0.5:0 0.8:0 0.6667:0.05 0.6667:0.2}; do
  alpha=${setting%%:*} radius=${setting#*:}
  run "ppm$tag-a$alpha-r$radius" --method ppm --photon-alpha "$alpha" --photon-radius "$radius"
done
uptime
