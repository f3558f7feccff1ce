#!/usr/bin/env bash
# Reordering against caching (issue 10, item 3; the thesis's Table 6.2): dicings of the Rayes
# SortedEngine (rays sorted by patch) and of --dice-cache K (rays one at a time, LRU cache of K grids),
# K = 10, 100, 1000, on each scene at the same image settings. Reordering is run twice: as the
# thesis's (every iteration dices its leaves: --grid-cache 0) and with the default grid cache
# (grids kept across iterations and generations, rays/grid_cache.h). Prints a markdown table for
# bench/RESULTS.md. The cached engine runs on one thread by design (its counts do not depend on
# threads), so it is slow on big scenes: keep RES and SPP small.
# Usage: bench/dice_cache.sh RES SPP SCENE...     e.g. bench/dice_cache.sh 160x64 1 scenes/forest-100.json
# (path depth: the scene's integrator.max_depth)
set -euo pipefail
cd "$(dirname "$0")/.."
res=$1 spp=$2; shift 2
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
echo "| scene | leaves | rays | reorder dicings (grid cache off) | reorder dicings (grid cache) | K=10 | K=100 | K=1000 | reorder / K=1000 (off / cache) | K=1000 hits | seconds reorder (off / cache) / K=1000 |"
echo "|---|---|---|---|---|---|---|---|---|---|---|"
for scene in "$@"; do
  name=$(basename "$scene" .json)
  common=(render "$scene" --res "$res" --spp "$spp" -q)
  build/bin/rayes "${common[@]}" -o "$out/$name-sorted.exr" --stats "$out/$name-sorted.json"
  build/bin/rayes "${common[@]}" --grid-cache 0 -o "$out/$name-off.exr" --stats "$out/$name-off.json"
  cmp -s "$out/$name-sorted.exr" "$out/$name-off.exr" || echo "WARNING: $name: the grid cache changed the image" >&2
  for k in 10 100 1000; do
    build/bin/rayes "${common[@]}" --dice-cache "$k" -o "$out/$name-$k.exr" --stats "$out/$name-$k.json"
    # Same hits, same image: the cache changes the work, never the picture.
    cmp -s "$out/$name-sorted.exr" "$out/$name-$k.exr" || echo "WARNING: $name K=$k image differs from the sorted render" >&2
  done
  python3 - "$out" "$name" <<'PY'
import json, sys
d, name = sys.argv[1], sys.argv[2]
s = {k: json.load(open(f"{d}/{name}-{k}.json")) for k in ["off", "sorted", "10", "100", "1000"]}
dic = {k: v["totals"]["leaves_diced"] for k, v in s.items()}
t = {k: v["totals"]["time_s"]["total"] for k, v in s.items()}
k1000 = max(dic['1000'], 1)
print(f"| {name} | {s['sorted']['scene']['leaves']:,} | {s['sorted']['totals']['rays']:,} | {dic['off']:,} | {dic['sorted']:,} | "
      f"{dic['10']:,} | {dic['100']:,} | {dic['1000']:,} | {dic['off'] / k1000:.2f} / {dic['sorted'] / k1000:.2f} | "
      f"{s['1000']['engine']['cache_hits']:,} | {t['off']:.1f} / {t['sorted']:.1f} / {t['1000']:.1f} |")
PY
done
