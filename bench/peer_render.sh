#!/usr/bin/env bash
# End-to-end peer comparison (issue 9): each scene rendered whole, same settings and shading,
# with `--engine rayes` (patches diced on demand, per-ray LOD) and `--engine embree` (every patch
# diced up front into Embree grids at `--embree-lod auto`). Prints, per scene and engine, the wall
# time and peak RSS (/usr/bin/time -v), the rays traced and the micropolygons (stats file), then
# the ratios time(rayes)/time(embree) and peak RSS(rayes)/peak RSS(embree), and the RMSE between
# the two images and the relative difference of their means (they differ by the LOD choice), from
# bench_app_image_diff (build it: scripts/build --target bench_app_image_diff).
# The two engines are run alternately, REPEAT times each (best wall time kept), so both see the
# same load on a shared machine.
#
# usage: bench/peer_render.sh [--res WxH] [--spp N] [--max-lod M] [--repeat R] [--threads T] [scene.json ...]
# Defaults: 320x240, 16 spp, max-lod 10, repeat 1, all threads; teapot, displaced-teapot,
# displaced-terrain, subdiv-creature and teapot-field (written by scenes/make_teapot_field.py).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
rayes="${RAYES:-$root/build/bin/rayes}"
res=320x240 spp=16 maxlod=10 repeat=1 threads=0
scenes=()
while [ $# -gt 0 ]; do
  case "$1" in
    --res) res="$2"; shift 2 ;;
    --spp) spp="$2"; shift 2 ;;
    --max-lod) maxlod="$2"; shift 2 ;;
    --repeat) repeat="$2"; shift 2 ;;
    --threads) threads="$2"; shift 2 ;;
    -h|--help) sed -n 2,14p "$0"; exit 0 ;;
    *) scenes+=("$1"); shift ;;
  esac
done
if [ ${#scenes[@]} -eq 0 ]; then
  [ -f "$root/scenes/teapot-field.json" ] || python3 "$root/scenes/make_teapot_field.py" >/dev/null
  for s in teapot displaced-teapot displaced-terrain subdiv-creature teapot-field; do scenes+=("$root/scenes/$s.json"); done
fi
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
threadArgs=()
[ "$threads" -gt 0 ] && threadArgs=(--threads "$threads")

# run ENGINE SCENE TAG: renders, leaves $work/TAG.{exr,json,time}
run() {
  local engine="$1" scene="$2" tag="$3" extra=()
  [ "$engine" = embree ] && extra=(--embree-lod auto)
  /usr/bin/time -v -o "$work/$tag.time" "$rayes" render "$scene" --engine "$engine" "${extra[@]}" --res "$res" \
    --spp "$spp" --max-lod "$maxlod" "${threadArgs[@]}" -q -o "$work/$tag.exr" --stats "$work/$tag.json"
}
wall() {  # seconds from "Elapsed (wall clock) time (h:mm:ss or m:ss): m:ss.ss"
  awk -F': ' '/Elapsed/ {n = split($2, p, ":"); s = 0; for (i = 1; i <= n; i++) s = s * 60 + p[i]; print s}' "$1"
}
rss() { awk -F': ' '/Maximum resident/ {printf "%.1f", $2 / 1024}' "$1"; }  # MiB

echo "# peer_render: $(date -u +%FT%TZ), $(nproc) cores, $(awk -F': ' '/model name/ {print $2; exit}' /proc/cpuinfo)"
echo "# load average before: $(cut -d' ' -f1-3 /proc/loadavg); res $res, spp $spp, max-lod $maxlod, repeat $repeat (best wall), engines alternated"
echo
echo "| scene | rayes s | embree s | time ratio | rayes MiB | embree MiB | memory ratio | rays rayes / embree | embree micropolygons (levels) | embree tess+build s | RMSE | mean diff |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|"
for scene in "${scenes[@]}"; do
  name="$(basename "$scene" .json)"
  best_r=inf best_e=inf
  for ((k = 0; k < repeat; ++k)); do
    run rayes "$scene" r; run embree "$scene" e
    best_r=$(python3 -c "print(min(float('$best_r'), $(wall "$work/r.time")))")
    best_e=$(python3 -c "print(min(float('$best_e'), $(wall "$work/e.time")))")
  done
  diff=$("$(dirname "$rayes")/bench_app_image_diff" "$work/r.exr" "$work/e.exr")
  python3 - "$work" "$name" "$best_r" "$best_e" "$(rss "$work/r.time")" "$(rss "$work/e.time")" "$diff" <<'PY'
import json, sys
work, name = sys.argv[1], sys.argv[2]
tr, te, mr, me = (float(x) for x in sys.argv[3:7])
d = sys.argv[7].split()
rmse, rel = float(d[d.index("rmse") + 1]), d[d.index("relative_mean_diff") + 1]
sr, se = json.load(open(f"{work}/r.json")), json.load(open(f"{work}/e.json"))
eng = se["engine"]
print(f"| {name} | {tr:.2f} | {te:.2f} | {tr / te:.2f} | {mr:.0f} | {me:.0f} | {mr / me:.2f} | "
      f"{sr['totals']['rays']:,} / {se['totals']['rays']:,} | {eng['micropolygons']:,} ({eng['min_level']}-{eng['max_level']}) | "
      f"{eng['time_s']['tessellate']:.2f}+{eng['time_s']['build']:.2f} | {rmse:.4f} | {rel} % |")
PY
done
echo
echo "# load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
