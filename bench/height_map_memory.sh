#!/usr/bin/env bash
# Peak RSS of a render displaced by a large height map (issue 32: height maps through the
# texture cache). An SIZE x SIZE float EXR (a gradient plus uniform noise, made by oiiotool into
# build/bench-heightmap/) displaces one quad; the scene is rendered with --texture-memory MEM
# twice: the first run converts the plain EXR into the cache folder (the conversion holds the
# whole image, once), the second reads the conversion: its peak is the figure. Prints the two
# peaks and the stats' textures section.
# Usage: bench/height_map_memory.sh [SIZE] [MEM]     (default 8192 32M)
set -euo pipefail
cd "$(dirname "$0")/.."
size=${1:-8192} mem=${2:-32M}
dir=build/bench-heightmap
mkdir -p "$dir"
map=$dir/h$size.exr
[ -f "$map" ] || oiiotool --pattern fill:topleft=0:topright=1:bottomleft=0.5:bottomright=0.2 "${size}x${size}" 1 \
  --pattern noise:type=uniform:min=0:max=0.3 "${size}x${size}" 1 --add -d float --chnames Y -o "$map"
cat > "$dir/scene.json" <<JSON
{
  "camera": {"position": [0.0, -3.2, 2.4], "look_at": [0, 0, 0.2], "up": [0, 0, 1], "fov": 45},
  "film": {"resolution": [160, 120], "spp": 4},
  "integrator": {"max_depth": 3, "seed": 0},
  "materials": {"m": {"type": "diffuse", "albedo": [0.7, 0.7, 0.7]}},
  "shapes": [
    {"type": "bilinear", "material": "m", "quads": [[[-1.5, -1.5, 0], [1.5, -1.5, 0], [-1.5, 1.5, 0], [1.5, 1.5, 0]]],
     "displacement": {"type": "image", "file": "h$size.exr", "amplitude": 0.6, "offset": -0.1}}
  ],
  "lights": [{"type": "environment", "radiance": [1, 1, 1]}]
}
JSON
cache=$(mktemp -d)
trap 'rm -rf "$cache"' EXIT
for run in converting converted; do
  /usr/bin/time -f %M -o "$cache/peak.txt" build/bin/rayes render "$dir/scene.json" -o "$cache/out.exr" --threads 2 -q \
    --texture-memory "$mem" --texture-cache-dir "$cache" --stats "$cache/stats.json" 2>/dev/null
  echo "$run: peak RSS $(( $(tail -1 "$cache/peak.txt") / 1024 )) MiB"
done
python3 -c "import json; print(json.dumps(json.load(open('$cache/stats.json'))['textures']))"
