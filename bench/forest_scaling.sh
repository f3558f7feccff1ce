#!/usr/bin/env bash
# Scaling tables for a scene (issue 10, item 6; the thesis's Tables 6.1, 6.3, 6.4): renders it with
# 1 and with 2 threads (--stats) and prints markdown for bench/RESULTS.md: micropolygons created
# against potential (6.4), time per stage (6.1), active rays and candidates per ray per iteration
# of every generation of the first batch (6.3), rays per dicing, bytes per ray, peak memory and the
# speed-up from 1 to 2 threads. Extra arguments go to both renders (e.g. --ray-memory 256M).
# Usage: bench/forest_scaling.sh SCENE RES SPP [rayes options...]
#   e.g. nice -n 5 bench/forest_scaling.sh scenes/forest-100.json 320x128 1
set -euo pipefail
cd "$(dirname "$0")/.."
scene=$1 res=$2 spp=$3; shift 3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for t in 1 2; do
  build/bin/rayes render "$scene" --res "$res" --spp "$spp" --threads "$t" -q -o "$tmp/t$t.exr" \
    --stats "$tmp/t$t.json" "$@"
done
python3 - "$tmp" "$scene $res ${spp}spp $*" <<'PY'
import json, sys
tmp, what = sys.argv[1], sys.argv[2]
s1, s2 = (json.load(open(f"{tmp}/t{t}.json")) for t in (1, 2))
t, m = s2["totals"], s2["memory"]
print(f"#### {what} (2 threads unless noted; {s2['scene']['leaves']:,} leaves)\n")
print("| micropolygons created | potential (4^max_lod per leaf) | created / potential | dicings | rays | rays per dicing |")
print("|---|---|---|---|---|---|")
print(f"| {t['micropolygons_created']:,} | {t['micropolygons_potential']:,} | "
      f"{t['micropolygons_created'] / max(1, t['micropolygons_potential']):.3g} | {t['leaves_diced']:,} | "
      f"{t['rays']:,} | {t['rays'] / max(1, t['leaves_diced']):.1f} |\n")
stages = ["toplevel", "sort", "dice", "bottom", "shade", "shade_sort", "film"]
ts = t["time_s"]
print("| stage | " + " | ".join(stages) + " | total (wall) |")
print("|---|" + "---|" * (len(stages) + 1))
for name, s in (("1 thread", s1), ("2 threads", s2)):
    x = s["totals"]["time_s"]
    print(f"| {name} s | " + " | ".join(f"{x[k]:.2f}" for k in stages) + f" | {x['total']:.2f} |")
print(f"\n(toplevel, sort, shade_sort, film: wall clock; dice, bottom, shade: summed over threads, as in Table 6.1)\n")
paths = m["paths_per_batch"]
print(f"| bytes per path | rays per path | bytes per ray slot | paths per batch | batches | peak RSS | speed-up 1 -> 2 threads |")
print("|---|---|---|---|---|---|---|")
print(f"| {m['bytes_per_path']} | 2 | {m['bytes_per_path'] / 2:.0f} | {paths:,} | {t['batches']} | "
      f"{t['peak_rss_bytes'] / 2**20:.0f} MiB | {s1['totals']['time_s']['total'] / max(1e-9, ts['total']):.2f} |\n")
print("Active rays and candidates per ray per iteration (Table 6.3), first batch of the first pass:\n")
print("| generation | iteration | active rays | N (candidates per ray) | candidates |")
print("|---|---|---|---|---|")
for g in s2["generations"]:
    if g["pass"] != 0 or g["batch"] != 0: continue
    for i, it in enumerate(g["iterations"]):
        print(f"| {g['depth']} | {i} | {it['active_rays']:,} | {it['candidates_per_ray']:g} | {it['candidates']:,} |")
print()
PY
