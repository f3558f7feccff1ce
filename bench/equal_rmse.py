#!/usr/bin/env python3
"""Equal-error time ratios from `rayes converge` CSVs (bench/converge_lbt.sh), and one log-log
chart per scene with every method's curve (CPU seconds against RMSE).

Each method X is compared with lbt at the lowest RMSE both reached (the larger of their smallest
RMSEs). A method's time at an RMSE is interpolated linearly in log(time)-log(RMSE) between the two
renders where its running-minimum RMSE first crosses it. When a method is already below it at its
first render, that render's time is an upper bound: a ratio X/lbt is then a lower bound ("≥")
when lbt is the one, an upper bound ("≤") when X is. Ratios are time(X) / time(lbt), CPU seconds.

Usage: bench/equal_rmse.py DIR SCENE...
  reads DIR/SCENE-METHOD.csv for METHOD in lbt, pm, ppm, pt; writes DIR/SCENE-curves.svg (the
  dashed line: the RMSE of the lbt-pm comparison); prints a Markdown table."""
import csv
import math
import os
import sys

METHODS = ["lbt", "pm", "ppm", "pt"]
COLOURS = {"lbt": "#c33", "pm": "#36c", "ppm": "#393", "pt": "#888"}
VARIANT_COLOURS = ["#e83", "#a3a", "#3aa"]


def curve(path):
    with open(path) as f:
        return [(float(r["cpu_seconds"]), float(r["rmse"])) for r in csv.DictReader(f)]


def time_at(points, target):
    """(time, first): when the running-minimum RMSE first reaches target (None if never);
    first: already at the first render (the time is an upper bound)."""
    best_t, best_e = None, None
    for t, e in points:
        if e <= target:
            if best_t is None:
                return t, True
            # log-log interpolation between the previous best and this render
            a = (math.log(best_e) - math.log(target)) / (math.log(best_e) - math.log(e))
            return math.exp(math.log(best_t) + a * (math.log(t) - math.log(best_t))), False
        if best_e is None or e < best_e:
            best_t, best_e = t, e
    return None, False


def svg(scene, curves, target, path):
    W, H, L, R, T, B = 640, 420, 70, 110, 40, 50
    ts = [t for c in curves.values() for t, _ in c if t > 0]
    es = [e for c in curves.values() for _, e in c if e > 0]
    lt0, lt1 = math.floor(math.log10(min(ts))), math.ceil(math.log10(max(ts)))
    le0, le1 = math.floor(math.log10(min(es))), math.ceil(math.log10(max(es)))
    lt1, le1 = max(lt1, lt0 + 1), max(le1, le0 + 1)
    X = lambda t: L + (math.log10(t) - lt0) / (lt1 - lt0) * (W - L - R)
    Y = lambda e: H - B - (math.log10(e) - le0) / (le1 - le0) * (H - T - B)
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" font-family="sans-serif" font-size="12">',
           '<rect width="100%" height="100%" fill="white"/>',
           f'<text x="{L}" y="24" font-size="14">{scene}: RMSE against CPU seconds</text>']
    for d in range(lt0, lt1 + 1):
        x = X(10 ** d)
        out.append(f'<line x1="{x:.1f}" y1="{T}" x2="{x:.1f}" y2="{H - B}" stroke="#ddd"/>'
                   f'<text x="{x:.1f}" y="{H - B + 18}" text-anchor="middle">{10 ** d:g}</text>')
    for d in range(le0, le1 + 1):
        y = Y(10 ** d)
        out.append(f'<line x1="{L}" y1="{y:.1f}" x2="{W - R}" y2="{y:.1f}" stroke="#ddd"/>'
                   f'<text x="{L - 6}" y="{y + 4:.1f}" text-anchor="end">{10 ** d:g}</text>')
    out.append(f'<text x="{(L + W - R) / 2}" y="{H - 12}" text-anchor="middle">CPU seconds</text>')
    out.append(f'<text x="16" y="{(T + H - B) / 2}" transform="rotate(-90 16 {(T + H - B) / 2})" '
               'text-anchor="middle">RMSE</text>')
    if target:
        y = Y(target)
        out.append(f'<line x1="{L}" y1="{y:.1f}" x2="{W - R}" y2="{y:.1f}" stroke="#000" stroke-dasharray="4 3"/>')
    for k, (m, c) in enumerate(curves.items()):
        colour = COLOURS.get(m) or VARIANT_COLOURS[(k - len(COLOURS)) % len(VARIANT_COLOURS)]
        pts = " ".join(f"{X(t):.1f},{Y(e):.1f}" for t, e in c if t > 0 and e > 0)
        out.append(f'<polyline fill="none" stroke="{colour}" stroke-width="1.5" points="{pts}"/>')
        out += [f'<circle cx="{X(t):.1f}" cy="{Y(e):.1f}" r="3" fill="{colour}"/>' for t, e in c if t > 0 and e > 0]
        out.append(f'<line x1="{W - R + 10}" y1="{T + 10 + 18 * k}" x2="{W - R + 30}" y2="{T + 10 + 18 * k}" '
                   f'stroke="{colour}" stroke-width="2"/><text x="{W - R + 36}" y="{T + 14 + 18 * k}">{m}</text>')
    out.append("</svg>")
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


def main(argv):
    folder, scenes = argv[0], argv[1:]
    print("| scene | lbt vs X | RMSE | lbt CPU s | X CPU s | X / lbt | lbt min RMSE | X min RMSE |")
    print("|---|---|---|---|---|---|---|---|")
    for scene in scenes:
        curves = {m: curve(f"{folder}/{scene}-{m}.csv") for m in METHODS if os.path.exists(f"{folder}/{scene}-{m}.csv")}
        # other lbt schedules: SCENE-lbtTAG.csv
        variants = sorted(f[len(scene) + 1:-4] for f in os.listdir(folder)
                          if f.startswith(f"{scene}-lbt") and f.endswith(".csv") and f != f"{scene}-lbt.csv")
        for v in variants:
            curves[v] = curve(f"{folder}/{scene}-{v}.csv")
        lbt = curves.get("lbt")
        line = max(min(e for _, e in lbt), min(e for _, e in curves["pm"])) if lbt and "pm" in curves else None
        svg(scene, curves, line, f"{folder}/{scene}-curves.svg")
        for name in ["lbt"] + variants:
            if name in curves:
                compare(scene, name, curves)


def compare(scene, name, curves):
    lbt = curves[name]
    for m in ["pm", "ppm", "pt"]:
        if m not in curves:
            continue
        lo_l, lo_x = min(e for _, e in lbt), min(e for _, e in curves[m])
        target = max(lo_l, lo_x)
        (tl, first_l), (tx, first_x) = time_at(lbt, target), time_at(curves[m], target)
        bound = "≥ " if first_l and not first_x else "≤ " if first_x and not first_l else "~ " if first_x else ""
        print(f"| {scene} | {name} vs {m} | {target:.4g} | {tl:.3g} | {tx:.3g} | {bound}{tx / tl:.2f} | {lo_l:.4g} | {lo_x:.4g} |")


if __name__ == "__main__":
    main(sys.argv[1:])
