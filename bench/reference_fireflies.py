#!/usr/bin/env python3
"""Refuse a reference with fireflies before error curves are measured against it.

A reference and its independent check (another seed, a quarter of the samples) are compared
pixel by pixel with bench_app_image_diff. With N pixels of independent, roughly Gaussian noise,
the largest single pixel carries about 2 ln(N) / N of the squared difference (0.1 % at 160x120);
a pixel carrying more than SHARE (default 5 %, fifty times that) holds one sample of huge weight,
a firefly, which floors every method's RMSE against the reference (bench/history/2026-11.md, "lbt-ring
(σ = 0.001) against pm: a failed re-measurement"). Looks at the pixels the tool lists (the five
largest differences); prints each such pixel, says which image holds it, and exits 1; exits 0
when there is none.

With --mask M.exr only the pixels the error counts are compared (those with non-zero red in M,
as `rayes converge --error-mask`).

Usage: bench/reference_fireflies.py REFERENCE.exr CHECK.exr [SHARE_PERCENT] [--mask M.exr]"""
import os
import re
import subprocess
import sys


def main():
    args = sys.argv[1:]
    mask = []
    if "--mask" in args:
        k = args.index("--mask")
        if k + 1 >= len(args):
            sys.exit(__doc__)
        mask = [args[k + 1]]
        del args[k:k + 2]
    if len(args) not in (2, 3):
        sys.exit(__doc__)
    ref, check = args[0], args[1]
    limit = float(args[2]) if len(args) == 3 else 5.0
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    tool = os.environ.get("IMAGE_DIFF", os.path.join(root, "build", "bin", "bench_app_image_diff"))
    out = subprocess.run([tool, ref, check] + mask, check=True, capture_output=True, text=True).stdout
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
