#!/usr/bin/env bash
# bench/farm_split.sh OUT [RES SPP PAIRS]: what batch jobs cost (docs/batch-and-farm.md), in CPU
# seconds (user + sys of /usr/bin/time: the machine may be shared, so CPU time, not wall time).
#   1. checkpoints: scenes/forest-100.json at RES, SPP (default 480x192, 6: a minute or two of
#      CPU), PAIRS (default 2) pairs of runs alternating without and with --checkpoint-every 10;
#      the images must be the same bits.
#   2. resume after SIGKILL: the same render with --checkpoint-every 10, killed with SIGKILL
#      after KILL_AT (default 45) wall seconds, then resumed: the two runs' CPU against an
#      uninterrupted one (the work lost is at most what ran since the last checkpoint, plus the
#      setup done again).
#   3. a 4-part split of scenes/teapot.json at its own settings: each part's CPU (the balance of
#      pixel bands) and their total against one run (goal: within 1.1x), merged = single.
#   4. what every part repeats: pm's photons and lbt's beams on scenes/lbt-ring.json (RING_RES,
#      RING_SPP), one run against 4 parts.
# SECTIONS="1 3" runs only those; KILL_AT, RING_RES, RING_SPP, BIN as above.
# Writes OUT/farm_split.txt (the figures) and the images and logs beside it.
set -euo pipefail
cd "$(dirname "$0")/.."
out=$1; res=${2:-480x192}; spp=${3:-6}; pairs=${4:-2}; killAt=${KILL_AT:-45}
bin=${BIN:-build/bin/rayes}
mkdir -p "$out"
report="$out/farm_split.txt"
: > "$report"
say() { echo "$*" | tee -a "$report"; }
# cpu NAME CMD...: runs CMD under /usr/bin/time; prints "NAME cpu_s wall_s maxrss_kb exit".
cpu() {
  local name=$1; shift
  local code=0
  /usr/bin/time -f "%U %S %e %M" -o "$out/$name.time" "$@" 2> "$out/$name.log" || code=$?
  # The last line: a run that failed or was killed gets a line saying so first.
  tail -n 1 "$out/$name.time" | awk -v n="$name" -v c="$code" '{printf "%s cpu %.2f wall %.2f rss_kb %d exit %d\n", n, $1 + $2, $3, $4, c}' | tee -a "$report"
}
# killed NAME SECONDS CMD...: as cpu, the command killed with SIGKILL after SECONDS of wall time.
killed() {
  local name=$1 after=$2; shift 2
  /usr/bin/time -f "%U %S %e %M" -o "$out/$name.time" "$@" 2> "$out/$name.log" &
  local timer=$!
  sleep "$after"
  pkill -KILL -P "$timer" || true  # rayes, the child of this /usr/bin/time
  say "  killed at $(date +%T)"
  wait "$timer" || true
  tail -n 1 "$out/$name.time" | awk -v n="$name" '{printf "%s cpu %.2f wall %.2f rss_kb %d killed\n", n, $1 + $2, $3, $4}' | tee -a "$report"
}
# stat FILE.json: the deterministic work of a render (dicings, batches), from its stats.
work() { python3 -c "
import json, sys
j = json.load(open(sys.argv[1])); t = j['totals']; c = j.get('checkpoints')
print('  dicings', t['leaves_diced'], 'batches', t['batches'], 'pixels_per_block', t['pixels_per_block'],
      *(['checkpoints', c['written'], 'in', round(c['time_s'], 2), 's'] if c else []))" "$1" | tee -a "$report"; }
same() { cmp -s "$1" "$2" && say "  $1 = $2 (same bits)" || say "  $1 != $2 (DIFFERENT)"; }
forest=(render scenes/forest-100.json --res "$res" --spp "$spp" -q)
sections=${SECTIONS:-1 2 3 4}
on() { [[ " $sections " == *" $1 "* ]]; }
say "# $(date -u +%FT%TZ) $(git rev-parse --short HEAD) nproc=$(nproc) load: $(cut -d' ' -f1-3 /proc/loadavg)"
if on 1; then
say "## 1. forest-100 $res $spp spp: without / with --checkpoint-every 10"
for p in $(seq "$pairs"); do
  cpu "plain-$p" "$bin" "${forest[@]}" -o "$out/plain.exr" --stats "$out/plain.json"
  work "$out/plain.json"
  rm -f "$out/ck.film"
  cpu "ckpt-$p" "$bin" "${forest[@]}" --checkpoint "$out/ck.film" --checkpoint-every 10 -o "$out/ckpt.exr" --stats "$out/ckpt.json"
  work "$out/ckpt.json"
  same "$out/plain.exr" "$out/ckpt.exr"
done
# The checkpoint's batches alone (16 a pass), no checkpoint written: what the smaller batches cost.
cpu "batches-only" "$bin" "${forest[@]}" --checkpoint "$out/never.film" --checkpoint-every 1e9 -o "$out/batches.exr" --stats "$out/batches.json"
work "$out/batches.json"
fi
if on 2; then
say "## 2. SIGKILL after ${killAt} s, then --resume"
rm -f "$out/kill.film"
killed "killed" "$killAt" "$bin" "${forest[@]}" --checkpoint "$out/kill.film" --checkpoint-every 10 -o "$out/killed.exr"
ls -l --time-style=+%T "$out/kill.film" 2>/dev/null | tee -a "$report" || say "  (no checkpoint was written before the kill)"
cpu "resumed" "$bin" "${forest[@]}" --checkpoint "$out/kill.film" --checkpoint-every 10 --resume -o "$out/killed.exr" --stats "$out/resumed.json"
work "$out/resumed.json"
same "$out/plain.exr" "$out/killed.exr"
fi
if on 3; then
say "## 3. scenes/teapot.json: one run, then 4 parts and the merge"
cpu "teapot-single" "$bin" render scenes/teapot.json -q -o "$out/teapot.exr"
for i in 1 2 3 4; do cpu "teapot-part-$i" "$bin" render scenes/teapot.json -q --part "$i/4" -o "$out/teapot-$i.film"; done
cpu "teapot-merge" "$bin" merge -q "$out"/teapot-[1-4].film -o "$out/teapot-merged.exr"
same "$out/teapot.exr" "$out/teapot-merged.exr"
fi
if on 4; then
say "## 4. what every part repeats (photons, beams): scenes/lbt-ring.json ${RING_RES:=200x150} ${RING_SPP:=16} spp, one run and 4 parts"
for m in pm lbt; do
  ring=(render scenes/lbt-ring.json -q --method "$m" --res "$RING_RES" --spp "$RING_SPP")
  cpu "ring-$m-single" "$bin" "${ring[@]}" -o "$out/ring-$m.exr"
  for i in 1 2 3 4; do cpu "ring-$m-part-$i" "$bin" "${ring[@]}" --part "$i/4" -o "$out/ring-$m-$i.film"; done
  "$bin" merge -q "$out"/ring-$m-[1-4].film -o "$out/ring-$m-merged.exr"
  same "$out/ring-$m.exr" "$out/ring-$m-merged.exr"
done
fi
say "# end $(date -u +%FT%TZ) load: $(cut -d' ' -f1-3 /proc/loadavg)"
