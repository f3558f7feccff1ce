#!/usr/bin/env bash
# RMSE against samples and against time for two rayes binaries (e.g. the independent sampler
# of an older build and the current low-discrepancy one) on one scene, against ONE shared
# reference, so the two curves are comparable.
# Usage: bench/compare_samplers.sh BEFORE_BIN AFTER_BIN SCENE RES REF.exr SPP RUNS [REF_SPP]
#   REF.exr is rendered by AFTER_BIN at REF_SPP (default 4096) with --seed 1000 if it does not exist.
# Runs alternate before/after (RUNS times each, seeds 1..RUNS, one thread each), so a machine
# shared with other work loads both alike. Time per spp is the process's CPU time (user + sys)
# divided by SPP, which a loaded machine inflates far less than wall time; RMSE(spp) is the
# mean over the runs of the --reference curve (docs/stats.md, error_vs_time).
# Equal-time RMSE: the before curve, interpolated log-log at the spp it would reach in the
# CPU time the after binary spent on each of its points.
set -euo pipefail
before=$1 after=$2 scene=$3 res=$4 ref=$5 spp=$6 runs=$7 refspp=${8:-4096}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
if [ ! -f "$ref" ]; then
  "$after" render "$scene" --res "$res" --spp "$refspp" --seed 1000 -o "$ref" -q
fi
python3 - "$before" "$after" "$scene" "$res" "$ref" "$spp" "$runs" "$out" <<'PY'
import json, math, resource, subprocess, sys
before, after, scene, res, ref, spp, runs, out = sys.argv[1:]
spp, runs = int(spp), int(runs)
curves = {"before": [], "after": []}
cpu = {"before": [], "after": []}
for run in range(1, runs + 1):
    for name, binary in (("before", before), ("after", after)):
        stats = f"{out}/{name}{run}.json"
        t0 = resource.getrusage(resource.RUSAGE_CHILDREN)
        subprocess.run([binary, "render", scene, "--res", res, "--spp", str(spp), "--seed", str(run),
                        "--threads", "1", "-o", f"{out}/{name}.exr", "--reference", ref, "--stats", stats, "-q"],
                       check=True)
        t1 = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu[name].append((t1.ru_utime - t0.ru_utime + t1.ru_stime - t0.ru_stime) / spp)
        curves[name].append(json.load(open(stats))["error_vs_time"])

def mean_curve(name):
    pts = curves[name][0]
    return [(p["spp"], sum(c[i]["rmse"] for c in curves[name]) / runs) for i, p in enumerate(pts)]

b, a = mean_curve("before"), mean_curve("after")
cb, ca = sum(cpu["before"]) / runs, sum(cpu["after"]) / runs
print(f"scene {scene} at {res}, {runs} runs each, reference {ref}")
print("CPU s/spp per run: before " + " ".join(f"{x:.4f}" for x in cpu["before"]) +
      " | after " + " ".join(f"{x:.4f}" for x in cpu["after"]))
print(f"mean CPU s/spp: before {cb:.4f}, after {ca:.4f} (after/before {ca / cb:.3f})")

def before_at(n):  # log-log interpolation of the before curve at spp n
    for (n0, e0), (n1, e1) in zip(b, b[1:]):
        if n0 <= n <= n1:
            f = math.log(n / n0) / math.log(n1 / n0)
            return math.exp(math.log(e0) + f * (math.log(e1) - math.log(e0)))
    return float("nan")

print(f"{'spp':>5} {'rmse_before':>12} {'rmse_after':>12} {'ratio':>7} {'cpu_s_after':>12} {'rmse_before@same_time':>22} {'ratio':>7}")
for (n, eb), (_, ea) in zip(b, a):
    same = before_at(n * ca / cb)
    print(f"{n:>5} {eb:>12.5f} {ea:>12.5f} {ea / eb:>7.3f} {n * ca:>12.2f} {same:>22.5f} {ea / same:>7.3f}")
PY
