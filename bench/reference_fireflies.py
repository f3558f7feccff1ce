#!/usr/bin/env python3
"""Refuse a reference with fireflies before error curves are measured against it.

A reference and its independent check (another seed, a quarter of the samples) are compared
pixel by pixel with bench_app_image_diff. With N pixels of independent, roughly Gaussian noise,
the largest single pixel carries about 2 ln(N) / N of the squared difference (0.1 % at 160x120);
a pixel carrying more than SHARE (default 5 %, fifty times that) holds one sample of huge weight,
a firefly, which floors every method's RMSE against the reference (bench/RESULTS.md, "lbt-ring
(σ = 0.001) against pm: a failed re-measurement"). Looks at the pixels the tool lists (the five
largest differences); prints each such pixel, says which image holds it, and exits 1; exits 0
when there is none.

Usage: bench/reference_fireflies.py REFERENCE.exr CHECK.exr [SHARE_PERCENT]"""
import os
import re
import subprocess
import sys


def main():
    if len(sys.argv) not in (3, 4):
        sys.exit(__doc__)
    ref, check = sys.argv[1], sys.argv[2]
    limit = float(sys.argv[3]) if len(sys.argv) == 4 else 5.0
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    tool = os.environ.get("IMAGE_DIFF", os.path.join(root, "build", "bin", "bench_app_image_diff"))
    out = subprocess.run([tool, ref, check], check=True, capture_output=True, text=True).stdout
    pixel = re.compile(r"pixel (\d+),(\d+) a ([-\d.e+]+) [-\d.e+]+ [-\d.e+]+ b ([-\d.e+]+) [-\d.e+]+ [-\d.e+]+ "
                       r"\(share of the squared error ([\d.]+) %\)")
    fireflies = []
    for m in pixel.finditer(out):
        x, y, a, b, share = int(m[1]), int(m[2]), float(m[3]), float(m[4]), float(m[5])
        if share > limit:
            fireflies.append((x, y, ref if a > b else check, max(a, b), min(a, b), share))
    for x, y, where, high, low, share in fireflies:
        print(f"{where}: firefly at pixel {x},{y}: {high:.4g} against {low:.4g} in the other image, "
              f"{share:.1f} % of the squared difference (limit {limit:g} %)")
    if fireflies:
        print("re-render the image named with another seed or more samples before measuring against it")
        sys.exit(1)


if __name__ == "__main__":
    main()
