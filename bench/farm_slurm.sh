#!/usr/bin/env bash
# Issue 31's farm goal: a 4-task `rayes farm submit` job's merged image equals the single-machine
# render bit for bit, and its total CPU time (the tasks' rayes processes, summed) is within 1.1x
# of the single render's. Runs on the local one-node test cluster (tests/farm/slurm_cluster.sh;
# root, scripts/setup's Slurm packages), one CPU per task (-- --cpus-per-task=1: each task renders
# with one thread, two at a time on 2 cores); the single render is timed with one thread and with
# every core (/usr/bin/time).
# usage: bench/farm_slurm.sh [SCENE [TASKS [render options...]]]
#   (default: scenes/teapot.json 4, the scene's own settings, as scripts/render renders it)
set -euo pipefail
cd "$(dirname "$0")/.."
scene=${1:-scenes/teapot.json}
tasks=${2:-4}
shift $(($# > 2 ? 2 : $#))
rayes=$(realpath "${RAYES:-build/bin/rayes}")
work=$(mktemp -d /tmp/rayes-farm-bench.XXXXXX)
chmod 755 "$work"  # munged's socket lies below it
cluster=$work/cluster
trap 'tests/farm/slurm_cluster.sh stop "$cluster" >/dev/null 2>&1 || true; rm -rf "$work"' EXIT
tests/farm/slurm_cluster.sh start "$cluster"
export SLURM_CONF=$cluster/slurm.conf

cpu() { awk '{print $2 + $3}' "$1"; }  # "/usr/bin/time -f '%e %U %S'" output: user + system
for threads in 1 0; do
  /usr/bin/time -f '%e %U %S' -o "$work/single-$threads.time" \
    "$rayes" render "$scene" "$@" --threads "$threads" -q -o "$work/single-$threads.exr"
done
cmp -s "$work/single-1.exr" "$work/single-0.exr" || { echo "the single renders differ with the thread count" >&2; exit 1; }

start=$(date +%s.%N)
out=$(/usr/bin/time -f '%e %U %S' -o "$work/submit.time" \
  "$rayes" farm submit "$scene" --tasks "$tasks" "$@" -q --dir "$work/parts" -o "$work/farm.exr" -- --cpus-per-task=1)
merge=$(sed -n 's/^merge job \([0-9]*\):.*/\1/p' <<<"$out")
while :; do
  state=$(scontrol show job "$merge" | grep -o 'JobState=[A-Z_]*' | cut -d= -f2)
  case $state in COMPLETED) break ;; FAILED | CANCELLED | TIMEOUT) echo "merge job $state" >&2; cat "$work"/parts/*.log >&2; exit 1 ;; esac
  sleep 0.2
done
wall=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN {print b - a}')
# Each task's log ends a run with bash's `times`: the shell's user and system time, then its
# children's (rayes): "0m12.345s 0m0.678s". A requeued task has one such pair per run; the merge
# log has one too.
cpu_in_logs() {
  for f in "$@"; do awk '/CPU time \(user system\)/ {getline; getline; print}' "$f"; done |
    sed 's/m/ /g; s/s//g' | awk '{s += $1 * 60 + $2 + $3 * 60 + $4} END {printf "%.2f", s}'
}
farm_cpu=$(cpu_in_logs "$work"/parts/part-*.log)
merge_cpu=$(cpu_in_logs "$work/parts/merge.log")
if cmp -s "$work/single-0.exr" "$work/farm.exr"; then same="bit for bit equal"; else same="DIFFERENT"; fi

printf 'scene %s, %s tasks (%s)\n' "$scene" "$tasks" "$*"
printf 'single render, 1 thread:   %s s wall, %s s CPU\n' "$(cut -d' ' -f1 "$work/single-1.time")" "$(cpu "$work/single-1.time")"
printf 'single render, all cores:  %s s wall, %s s CPU\n' "$(cut -d' ' -f1 "$work/single-0.time")" "$(cpu "$work/single-0.time")"
printf 'farm job:                  %.1f s wall (submit to merged), %s s CPU over the tasks: %.3fx the 1-thread render\n' \
  "$wall" "$farm_cpu" "$(awk -v f="$farm_cpu" -v s="$(cpu "$work/single-1.time")" 'BEGIN {print f / s}')"
printf 'submit (checks, scene loaded once): %s s CPU; merge: %s s CPU\n' "$(cpu "$work/submit.time")" "$merge_cpu"
printf 'merged image against the single render: %s\n' "$same"
