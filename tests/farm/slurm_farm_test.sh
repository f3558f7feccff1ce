#!/usr/bin/env bash
# `rayes farm submit` on a real one-node Slurm cluster (tests/farm/slurm_cluster.sh), end to end:
#  1. a 4-task job of a small scene; its merged image equals a single `rayes render` of the same
#     scene and settings bit for bit (cmp of the EXRs: the writer puts nothing but the film in
#     them, no time or host, so equal films give equal files; every channel is compared);
#  2. the same job again, two array tasks killed mid-way once their checkpoint exists (one with
#     `scancel --signal=KILL`, one with SIGKILL to its processes), then `scontrol requeue`d: they
#     resume from their checkpoints and the merged image is again the same.
# usage: slurm_farm_test.sh RAYES_BINARY WORK_FOLDER   (ctest runs it as `farm_slurm`)
# Exit 77 (ctest: skipped) when it cannot run here: not root, Slurm or munge not installed, or
# the daemons do not start; with RAYES_REQUIRE_SLURM=1 (.ci/run sets it) those fail instead.
set -euo pipefail
[ $# -eq 2 ] || { echo "usage: $0 RAYES_BINARY WORK_FOLDER" >&2; exit 2; }
rayes=$(realpath "$1")
work=$2
here=$(cd "$(dirname "$0")" && pwd)
scene=$(realpath "$here/../../scenes/teapot.json")
# Each part takes a few seconds on one thread (-- --cpus-per-task=1 below: two tasks at a time
# on 2 cores), long enough to be killed after its first checkpoint (--checkpoint-every 1).
settings=(--res 160x120 --spp 128 --seed 7)

skip() {
  if [ "${RAYES_REQUIRE_SLURM:-0}" = 1 ]; then echo "FAIL (RAYES_REQUIRE_SLURM=1): $*" >&2; exit 1; fi
  echo "SKIP: $*"
  exit 77
}
[ "$(id -u)" -eq 0 ] || skip "the Slurm test cluster needs root"

rm -rf "$work"
mkdir -p "$work"
work=$(cd "$work" && pwd)
cluster=$work/cluster
stop() { "$here/slurm_cluster.sh" stop "$cluster" || true; }
trap stop EXIT
start_rc=0
"$here/slurm_cluster.sh" start "$cluster" || start_rc=$?
[ $start_rc -eq 77 ] && skip "Slurm or munge is not installed (scripts/setup installs them)"
[ $start_rc -eq 0 ] || skip "the Slurm daemons did not start (their logs are above)"
export SLURM_CONF=$cluster/slurm.conf

fail() {
  echo "FAIL: $*" >&2
  for f in "$work"/*/part-*.log "$work"/*/merge.log; do
    [ -f "$f" ] && { echo "---- $f" >&2; cat "$f" >&2; }
  done
  echo "---- squeue" >&2
  squeue -t all >&2 || true
  exit 1
}

job_state() { scontrol show job "$1" 2>/dev/null | grep -o 'JobState=[A-Z_]*' | head -n 1 | cut -d= -f2; }

# Waits until job $1 has ended (at most $2 s); fails unless it COMPLETED.
wait_completed() {
  local state="" t
  for ((t = 0; t < $2 * 5; t++)); do
    state=$(job_state "$1")
    case $state in
      COMPLETED) return 0 ;;
      FAILED | CANCELLED | TIMEOUT | NODE_FAIL | OUT_OF_MEMORY | BOOT_FAIL | DEADLINE) break ;;
    esac
    sleep 0.2
  done
  fail "job $1 ended ${state:-unknown} (expected COMPLETED within $2 s)"
}

# Submits the 4-task job into folder $1 with output $2; sets render_job and merge_job.
submit() {
  local out
  out=$("$rayes" farm submit "$scene" --tasks 4 "${settings[@]}" --checkpoint-every 1 -q --dir "$1" -o "$2" \
    -- --cpus-per-task=1) \
    || fail "rayes farm submit exited $?"
  echo "$out"
  render_job=$(sed -n 's/^render job \([0-9]*\):.*/\1/p' <<<"$out")
  merge_job=$(sed -n 's/^merge job \([0-9]*\):.*/\1/p' <<<"$out")
  [ -n "$render_job" ] && [ -n "$merge_job" ] || fail "no job ids in farm submit's output"
}

same_image() {
  cmp "$1" "$2" || fail "$2 differs from the single render $1"
  echo "ok: $2 equals $1 byte for byte"
}

# The single-machine render.
"$rayes" render "$scene" "${settings[@]}" -q -o "$work/single.exr" || fail "the single render exited $?"

# 1. Four tasks, merged.
submit "$work/parts-1" "$work/farm-1.exr"
wait_completed "$merge_job" 240
same_image "$work/single.exr" "$work/farm-1.exr"

# 2. Two tasks killed after their first checkpoint, then requeued; both resume. The first with
#    the issue's `scancel --signal=KILL`, which Slurm carries out as a cancel: TERM to every
#    process of the task first, so rayes writes a checkpoint as it stops (exit code 4) and the
#    task ends CANCELLED. The second with SIGKILL to the task's processes themselves (a node's
#    OOM killer, a crash): no checkpoint at that moment, the last periodic one is resumed, and
#    the task ends FAILED. (If a task finishes between its checkpoint and the kill, the next
#    task is taken.)
task_pids() {  # the processes of array task $1 on this node
  local id
  id=$(scontrol show job "$1" | sed -n 's/^JobId=\([0-9]*\) .*/\1/p' | head -n 1)
  scontrol listpids "$id" 2>/dev/null | awk 'NR > 1 && $1 ~ /^[0-9]+$/ {print $1}'
}
# kill_after_checkpoint I HOW (scancel or sigkill): 0 when task I was killed mid-way.
kill_after_checkpoint() {
  local i=$1 how=$2 task=${render_job}_$1 t state pids
  for ((t = 0; t < 600; t++)); do
    [ -f "$work/parts-2/part-$i.checkpoint" ] && break
    [ -f "$work/parts-2/part-$i.film" ] && return 1
    sleep 0.1
  done
  [ -f "$work/parts-2/part-$i.checkpoint" ] || fail "part $i wrote no checkpoint within 60 s"
  if [ "$how" = scancel ]; then
    scancel --signal=KILL "$task"
  else
    pids=$(task_pids "$task")
    [ -n "$pids" ] && kill -KILL $pids
  fi
  for ((t = 0; t < 100; t++)); do
    case $(job_state "$task") in RUNNING | COMPLETING) sleep 0.1 ;; *) break ;; esac
  done
  state=$(job_state "$task")
  [ "$state" = COMPLETED ] && return 1
  if [ "$how" = scancel ]; then
    [ "$state" = CANCELLED ] || fail "task $task is $state after scancel --signal=KILL (expected CANCELLED)"
  else
    [ "$state" = FAILED ] || fail "task $task is $state after SIGKILL (expected FAILED)"
  fi
  [ -f "$work/parts-2/part-$i.film" ] && fail "part $i was written although its task was killed"
  echo "killed task $task ($how) after its first checkpoint: $state"
  return 0
}
submit "$work/parts-2" "$work/farm-2.exr"
killed=()
for i in 1 2 3 4; do
  how=sigkill
  [ ${#killed[@]} -eq 0 ] && how=scancel
  if kill_after_checkpoint "$i" "$how"; then
    killed+=("$i")
    # It runs again cred_expire + 1 s later (6 s on the test cluster), resuming from its checkpoint.
    scontrol requeue "${render_job}_$i"
  fi
  [ ${#killed[@]} -eq 2 ] && break
done
[ ${#killed[@]} -eq 2 ] || fail "tasks finished before they could be killed: give the test render more work"
wait_completed "$merge_job" 240
for i in "${killed[@]}"; do
  grep -q "resuming from" "$work/parts-2/part-$i.log" || fail "the requeued task $i did not resume from its checkpoint"
done
same_image "$work/single.exr" "$work/farm-2.exr"
echo "ok: tasks ${killed[*]}, killed mid-way and requeued, resumed from their checkpoints; the image is the same"
