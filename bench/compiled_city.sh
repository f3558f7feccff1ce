#!/usr/bin/env bash
# The compiled-scene goal (issue 32): a city of PATCHES stored Bézier patches (bench/make_city.py)
# rendered from its JSON + .bpt and from its compiled .rayes under --scene-memory, at a small
# resolution: peak RSS and CPU time of each route (/usr/bin/time -v), the description's size,
# the compile's cost, and that both images are the same bytes.
#   bench/compiled_city.sh [PATCHES=10000000] [DIR=/tmp/rayes-city] [SCENE_MEMORY=256M] [RES=160x120]
set -euo pipefail
cd "$(dirname "$0")/.."
patches=${1:-10000000}
dir=${2:-/tmp/rayes-city}
budget=${3:-256M}
res=${4:-160x120}
rayes=${RAYES:-build/bin/rayes}
mkdir -p "$dir"
if [ ! -f "$dir/city.json" ] || [ "$(head -1 "$dir/city.bpt")" -lt "$patches" ]; then
  python3 bench/make_city.py --patches "$patches" --out "$dir"
fi
timed() {  # NAME COMMAND...: runs it under /usr/bin/time -v into $dir/NAME.time
  local name=$1; shift
  /usr/bin/time -v "$@" 2> "$dir/$name.time" || { cat "$dir/$name.time"; exit 1; }
}
field() { grep "$2" "$dir/$1.time" | sed 's/.*: //'; }
timed compile "$rayes" compile "$dir/city.json" -o "$dir/city.rayes" -q
timed json "$rayes" render "$dir/city.json" --res "$res" --spp 1 -q -o "$dir/json.exr" --stats "$dir/json-stats.json"
timed rayes "$rayes" render "$dir/city.rayes" --res "$res" --spp 1 -q --scene-memory "$budget" -o "$dir/rayes.exr" --stats "$dir/rayes-stats.json"
cmp "$dir/json.exr" "$dir/rayes.exr" && same=yes || same=NO
desc=$(( $(stat -c %s "$dir/city.bpt") + $(stat -c %s "$dir/city.json") ))
echo "patches $(head -1 "$dir/city.bpt"); description (city.json + city.bpt) $desc bytes; city.rayes $(stat -c %s "$dir/city.rayes") bytes; images equal: $same"
for run in compile json rayes; do
  cpu=$(python3 -c "print(round($(field $run 'User time') + $(field $run 'System time'), 1))")
  echo "$run: peak RSS $(( $(field $run 'Maximum resident set size') / 1024 )) MiB, CPU $cpu s, wall $(field $run 'Elapsed (wall clock)')"
done
python3 - "$dir" <<'PY'
import json, sys
d = sys.argv[1]
for route in ("json", "rayes"):
    s = json.load(open(f"{d}/{route}-stats.json"))
    m = s["memory"]["by_owner"]
    c = s["scene"].get("compiled", {})
    mib = lambda b: round(b / 2**20, 1)
    print(route, "MiB: scene_description", mib(m["scene_description"]), "top_level", mib(m["top_level"]),
          "ray_buffers", mib(m["ray_buffers"]), "candidates", mib(m["candidates_and_sort"]),
          "dice_buffers", mib(m["dice_buffers"]), "dice_cache", mib(m["dice_cache"]),
          "setup_s", round(s["totals"]["time_s"].get("setup", 0), 1) if "setup" in s["totals"]["time_s"] else "",
          *(["mapped", mib(c["bytes_mapped"]), "resident_peak", mib(c["resident_peak_bytes"]), "read", mib(c["bytes_read"]),
             "at_end", mib(c["resident_at_end_bytes"]), "top_level", c.get("top_level", "built")] if c else []))
PY
