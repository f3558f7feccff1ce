#!/usr/bin/env bash
# The forests at scale (issue 10): per scene, one small render with the Rayes engine and the
# Embree engine's up-front refusal. Prints a Markdown table row per scene: leaves, setup time
# (load + setup), wall and CPU time (/usr/bin/time -v), peak RSS, memory by owner (stats file,
# docs/stats.md: scene description and its bytes per leaf, top level, ray buffers, candidates,
# dice buffers), dicings, rays and rays per dicing; then what `--engine embree` said.
#
# usage: bench/forest_scale.sh [--res WxH] [--spp N] [--threads T] [scene.json ...]
# Defaults: 320x128, 1 spp, all threads; scenes/forest-100.json and scenes/forest-1000.json.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
rayes="${RAYES:-$root/build/bin/rayes}"
res=320x128 spp=1 threads=0
scenes=()
while [ $# -gt 0 ]; do
  case "$1" in
    --res) res="$2"; shift 2 ;;
    --spp) spp="$2"; shift 2 ;;
    --threads) threads="$2"; shift 2 ;;
    -h|--help) sed -n 2,9p "$0"; exit 0 ;;
    *) scenes+=("$1"); shift ;;
  esac
done
[ ${#scenes[@]} -eq 0 ] && scenes=("$root/scenes/forest-100.json" "$root/scenes/forest-1000.json")
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
echo "load: $(uptime | sed 's/.*load average: //'); $res, $spp spp, threads $threads (0: all), $(nproc) cores"
echo
echo "| scene | leaves | setup s (load+setup) | wall s | CPU s | peak RSS MiB | scene descr. MiB | B/leaf | top level MiB | ray buffers MiB | candidates+sort MiB | dice buffers MiB | dicings | rays | rays/dicing |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
for scene in "${scenes[@]}"; do
  name="$(basename "$scene" .json)"
  /usr/bin/time -v "$rayes" render "$scene" --res "$res" --spp "$spp" --threads "$threads" -q \
    --stats "$work/$name.json" -o "$work/$name.png" 2> "$work/$name.time"
  python3 - "$work/$name.json" "$work/$name.time" "$name" <<'PY'
import json, re, sys
s = json.load(open(sys.argv[1])); t = open(sys.argv[2]).read()
def tv(key):
    m = re.search(re.escape(key) + r":\s*([0-9.:]+)", t); return m.group(1)
def secs(v):
    parts = [float(x) for x in v.split(':')]; r = 0
    for p in parts: r = r * 60 + p
    return r
mib = lambda b: b / 2**20
tot, mem = s["totals"], s["memory"]; own = mem["by_owner"]
cpu = float(tv("User time (seconds)")) + float(tv("System time (seconds)"))
rays = tot["rays"]; diced = tot["leaves_diced"]
print(f"| {sys.argv[3]} | {s['scene']['leaves']} | {tot['time_s']['load'] + tot['time_s']['setup']:.2f} "
      f"| {secs(tv('Elapsed (wall clock) time (h:mm:ss or m:ss)')):.2f} | {cpu:.2f} | {int(tv('Maximum resident set size (kbytes)')) / 1024:.0f} "
      f"| {mib(own['scene_description']):.1f} | {mem['scene_bytes_per_leaf']:.1f} | {mib(own['top_level']):.1f} "
      f"| {mib(own['ray_buffers']):.1f} | {mib(own['candidates_and_sort']):.1f} | {mib(own['dice_buffers']):.1f} "
      f"| {diced} | {rays} | {rays / max(diced, 1):.1f} |")
PY
done
echo
for scene in "${scenes[@]}"; do
  name="$(basename "$scene" .json)"
  set +e
  /usr/bin/time -v "$rayes" render "$scene" --res "$res" --spp "$spp" --engine embree -q -o "$work/e-$name.png" \
    2> "$work/e-$name.err"
  code=$?
  set -e
  msg="$(grep -v '^\s' "$work/e-$name.err" | grep -v 'Command exited' | head -1)"
  rss="$(sed -n 's/.*Maximum resident set size (kbytes): //p' "$work/e-$name.err")"
  wall="$(sed -n 's/.*Elapsed (wall clock) time (h:mm:ss or m:ss): //p' "$work/e-$name.err")"
  written="$(ls "$work" | grep -c "^e-$name.png" || true)"
  echo "- $name, --engine embree: exit $code after $wall (peak RSS $((rss / 1024)) MiB), files written: $written; \"$msg\""
done
