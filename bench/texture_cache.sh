#!/usr/bin/env bash
# Textures larger than the texture cache (issue 32's texture goal): a scene of COUNT quads, each
# with its own SIZE x SIZE procedural texture (scenes/make_textures.sh: tiled MIP-mapped half
# floats, made once into build/bench-textures/), rendered three ways at the same settings:
#   resident  --texture-memory 4G: every tile read once and kept;
#   16x       --texture-memory = the textures' bytes / 16;
#   unsorted  the same with the shading sort off (RAYES_SHADING_SORT=off, bench only: paths shaded
#             in id order instead of by (material, leaf); same image).
# Prints a markdown row per run: seconds (stats totals.time_s.total), speed against resident,
# tile-cache hit rate, tiles read, bytes read, I/O seconds, peak RSS; and checks the three images
# are the same bits. A warm-up render first, so the page cache holds the files for every run.
# Usage: bench/texture_cache.sh [SIZE] [COUNT] [RES] [SPP]     (default 4096 4 640x320 4)
# With SCENE=FILE, that scene instead of the quads, its textures made into the folder `textures`
# beside it (bench/creature-textured.json: `SCENE=bench/creature-textured.json
# bench/texture_cache.sh 8192 2 320x240 4`, the uv-mapped creature with two 8K textures).
set -euo pipefail
cd "$(dirname "$0")/.."
size=${1:-4096} count=${2:-4} res=${3:-640x320} spp=${4:-4}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
if [ -n "${SCENE:-}" ]; then
  tex=$(dirname "$SCENE")/textures
  scenes/make_textures.sh "$tex" "$size" "$count"
  scene=$SCENE
else
scene=$out/scene.json
tex=build/bench-textures/$size
scenes/make_textures.sh "$tex" "$size" "$count"
python3 - "$out/scene.json" "$tex" "$count" <<'PY'
import json, os, sys
path, tex, count = sys.argv[1], os.path.abspath(sys.argv[2]), int(sys.argv[3])
materials, shapes = {}, []
for k in range(count):
    materials[f"m{k}"] = {"type": "diffuse", "albedo": {"type": "image", "file": f"{tex}/tex{k}.tx"}}
    x0 = -count / 2 + k
    shapes.append({"type": "bilinear", "material": f"m{k}",
                   "quads": [[[x0, -0.5, 0], [x0 + 1, -0.5, 0], [x0, 0.5, 0], [x0 + 1, 0.5, 0]]]})
scene = {"camera": {"position": [0, -1.6, 1.4], "look_at": [0, 0.1, 0], "up": [0, 0, 1], "fov": 60},
         "film": {"resolution": [640, 320], "spp": 4}, "integrator": {"max_depth": 3},
         "materials": materials, "shapes": shapes,
         "lights": [{"type": "environment", "radiance": [1, 1, 1]}]}
json.dump(scene, open(path, "w"), indent=1)
PY
fi
bytes=$(python3 -c "import os,sys; print(sum(os.path.getsize(f'$tex/tex{k}.tx') for k in range($count)))")
common=(render "$scene" --res "$res" --spp "$spp" --threads 2 -q)
build/bin/rayes "${common[@]}" -o "$out/warm.exr" --texture-memory 4G --stats "$out/warm.json"
image=$(python3 -c "import json; print(json.load(open('$out/warm.json'))['textures']['image_bytes'])")
small=$((image / 16))
build/bin/rayes "${common[@]}" -o "$out/resident.exr" --texture-memory 4G --stats "$out/resident.json"
build/bin/rayes "${common[@]}" -o "$out/16x.exr" --texture-memory "$small" --stats "$out/16x.json"
RAYES_SHADING_SORT=off build/bin/rayes "${common[@]}" -o "$out/unsorted.exr" --texture-memory "$small" --stats "$out/unsorted.json"
for r in 16x unsorted; do
  cmp -s "$out/resident.exr" "$out/$r.exr" || echo "WARNING: $r image differs from the resident one" >&2
done
echo "textures: $count x ${size}^2 half RGB, $((image >> 20)) MiB of texels with MIP levels ($((bytes >> 20)) MiB of zip files); 16x cache: $((small >> 20)) MiB; $res, $spp spp, depth 3, 2 threads"
python3 - "$out" <<'PY'
import json, sys
out = sys.argv[1]
runs = {r: json.load(open(f"{out}/{r}.json")) for r in ("resident", "16x", "unsorted")}
base = runs["resident"]["totals"]["time_s"]["total"]
print("| run | --texture-memory | seconds | speed vs resident | hit rate | tiles read | MiB read | I/O s | peak RSS MiB |")
print("|---|---|---|---|---|---|---|---|---|")
for r, j in runs.items():
    t, s = j["textures"], j["totals"]["time_s"]["total"]
    print(f"| {r} | {t['texture_memory_bytes'] >> 20} MiB | {s:.2f} | {base / s:.2f} | {100 * t['hit_rate']:.2f} % | "
          f"{t['tiles_read']} | {t['bytes_read'] / 2**20:.0f} | {t['io_time_s']:.2f} | {j['memory']['peak_rss_bytes'] / 2**20:.0f} |")
PY
