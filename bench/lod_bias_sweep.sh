#!/usr/bin/env bash
# Level of detail: error against run time (issue 10, item 7). Renders SCENE at several
# --lod-bias values and once with every ray at the finest level (--lod fixed, the reference),
# all with the same seed, so the RMSE between a biased render and the reference is the error the
# coarser geometry makes (the sampling noise is shared, not measured). Writes OUT.csv (bias,
# seconds, dicings, micropolygons, rmse), OUT.svg (rmse and seconds against bias) and OUT.html
# (the report: the chart, the table, the command and each render's preview).
# Usage: bench/lod_bias_sweep.sh SCENE RES SPP OUT [BIASES...] [-- RAYES_OPTIONS...]
#   e.g. nice -n 5 bench/lod_bias_sweep.sh scenes/displaced-terrain.json 160x90 4 bench/lod-bias-terrain \
#          -4 -3 -2 -1 0 1 -- --max-lod 8
# (the reference at every ray's finest level is the slow part: --max-lod bounds it)
set -euo pipefail
cd "$(dirname "$0")/.."
command="$*"
scene=$1 res=$2 spp=$3 out=$4; shift 4
biases=(); extra=()
while [ $# -gt 0 ] && [ "$1" != "--" ]; do biases+=("$1"); shift; done
[ $# -gt 0 ] && { shift; extra=("$@"); }
[ ${#biases[@]} -gt 0 ] || biases=(-4 -3 -2 -1 0 1)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$(dirname "$out")"
previews="$out-previews"
mkdir -p "$previews"
common=(render "$scene" --res "$res" --spp "$spp" --seed 7 -q "${extra[@]}")
build/bin/rayes "${common[@]}" --lod fixed -o "$tmp/ref.exr" --stats "$tmp/ref.json"
for b in "${biases[@]}"; do
  build/bin/rayes "${common[@]}" --lod-bias "$b" --reference "$tmp/ref.exr" -o "$tmp/b$b.exr" --stats "$tmp/b$b.json"
  cp "$tmp/b$b.png" "$previews/b$b.png"
done
cp "$tmp/ref.png" "$previews/reference.png"
python3 - "$tmp" "$out" "$command" "${biases[@]}" <<'PY'
import html, json, os, sys
tmp, out, command, biases = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
ref = json.load(open(f"{tmp}/ref.json"))
rows = []
for b in biases:
    s = json.load(open(f"{tmp}/b{b}.json"))
    t = s["totals"]
    rows.append((int(b), t["time_s"]["total"], t["leaves_diced"], t["micropolygons_created"], s["error_vs_time"][-1]["rmse"]))
with open(out + ".csv", "w") as f:
    f.write("bias,seconds,dicings,micropolygons,rmse\n")
    for r in rows: f.write(f"{r[0]},{r[1]:.3f},{r[2]},{r[3]},{r[4]:.6g}\n")
    rt = ref["totals"]
    f.write(f"# reference (--lod fixed): {rt['time_s']['total']:.3f} s, {rt['leaves_diced']} dicings, "
            f"{rt['micropolygons_created']} micropolygons\n")
# The chart: RMSE (left axis, blue) and seconds (right axis, orange) against the bias.
W, H, L, R, T, B = 480, 300, 60, 60, 20, 40
bx = [r[0] for r in rows]; xs = lambda b: L + (b - min(bx)) / max(1, max(bx) - min(bx)) * (W - L - R)
emax = max(r[4] for r in rows) or 1; smax = max(r[1] for r in rows) or 1
ye = lambda e: H - B - e / emax * (H - T - B); ys = lambda s: H - B - s / smax * (H - T - B)
svg = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" font-family="sans-serif" font-size="11">',
       f'<rect width="{W}" height="{H}" fill="white"/>',
       f'<line x1="{L}" y1="{H-B}" x2="{W-R}" y2="{H-B}" stroke="black"/>',
       f'<line x1="{L}" y1="{T}" x2="{L}" y2="{H-B}" stroke="#1f77b4"/>',
       f'<line x1="{W-R}" y1="{T}" x2="{W-R}" y2="{H-B}" stroke="#ff7f0e"/>',
       f'<text x="{W/2}" y="{H-8}" text-anchor="middle">--lod-bias</text>',
       f'<text x="{L-5}" y="{T+4}" text-anchor="end" fill="#1f77b4">{emax:.3g}</text>',
       f'<text x="{L-5}" y="{H-B}" text-anchor="end" fill="#1f77b4">0</text>',
       f'<text x="{L-5}" y="{T+18}" text-anchor="end" fill="#1f77b4">RMSE</text>',
       f'<text x="{W-R+5}" y="{T+4}" fill="#ff7f0e">{smax:.3g} s</text>',
       f'<text x="{W-R+5}" y="{H-B}" fill="#ff7f0e">0 s</text>']
for b in bx: svg.append(f'<text x="{xs(b):.1f}" y="{H-B+14}" text-anchor="middle">{b}</text>')
svg.append('<polyline fill="none" stroke="#1f77b4" stroke-width="2" points="' +
           " ".join(f"{xs(r[0]):.1f},{ye(r[4]):.1f}" for r in rows) + '"/>')
svg.append('<polyline fill="none" stroke="#ff7f0e" stroke-width="2" points="' +
           " ".join(f"{xs(r[0]):.1f},{ys(r[1]):.1f}" for r in rows) + '"/>')
svg.append("</svg>")
open(out + ".svg", "w").write("\n".join(svg) + "\n")
# The report: one self-contained page beside the CSV (previews linked from OUT-previews/).
pre = os.path.basename(out) + "-previews"
rows_html = "".join(
    f"<tr><td>{r[0]}</td><td>{r[1]:.2f}</td><td>{r[2]:,}</td><td>{r[3]:,}</td><td>{r[4]:.4g}</td>"
    f'<td><img src="{pre}/b{r[0]}.png" height="60"></td></tr>' for r in rows)
rt = ref["totals"]
page = f"""<!doctype html><html><head><meta charset="utf-8"><title>Level of detail: error against run time</title>
<style>body{{font-family:sans-serif;margin:2em;max-width:60em}} td,th{{padding:2px 10px;text-align:right}}
table{{border-collapse:collapse}} tr:nth-child(even){{background:#f4f4f4}}</style></head><body>
<h1>Level of detail: error against run time</h1>
<p>{html.escape(ref["scene"]["file"] if "scene" in ref and "file" in ref["scene"] else "")}
rendered at several <code>--lod-bias</code> values; RMSE against the same seed with every ray at the finest
level (<code>--lod fixed</code>: {rt['time_s']['total']:.2f} s, {rt['leaves_diced']:,} dicings,
{rt['micropolygons_created']:,} micropolygons). Negative biases dice coarser: faster, with more error.</p>
{chr(10).join(svg)}
<table><tr><th>bias</th><th>seconds</th><th>dicings</th><th>micropolygons</th><th>RMSE</th><th>image</th></tr>
{rows_html}
<tr><td>reference</td><td>{rt['time_s']['total']:.2f}</td><td>{rt['leaves_diced']:,}</td>
<td>{rt['micropolygons_created']:,}</td><td>0</td><td><img src="{pre}/reference.png" height="60"></td></tr></table>
<p>Command: <code>bench/lod_bias_sweep.sh {html.escape(command)}</code></p></body></html>
"""
open(out + ".html", "w").write(page)
print(open(out + ".csv").read(), end="")
PY
