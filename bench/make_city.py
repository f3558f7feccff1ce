#!/usr/bin/env python3
"""Writes a city of stored Bezier patches for the compiled-scene bench (bench/compiled_city.sh):
CITY.bpt (every patch stored: 16 control points each, shared within a facade) and CITY.json
referring to it. Buildings stand on a square grid of lots; each is a box whose four walls and
roof are tiled with flat bicubic patches 3 units wide, control points on the integer lattice
(so every patch is exactly planar: no border closure, dicing error 0). Heights come from a
fixed hash of the lot: the same file for the same arguments.

  bench/make_city.py --patches 10000000 --out /tmp/city   # -> /tmp/city/city.bpt, city.json
"""
import argparse
import math
import os

WIDTH = 8                # patches along a wall and a roof side
PITCH = 3 * WIDTH + 12   # lot: the building and a street
MIN_H, MAX_H = 4, 40     # wall heights in patches


def height(i, j):
    h = (i * 73856093) ^ (j * 19349663) ^ 0x5bd1e995
    h = (h * 2654435761) & 0xFFFFFFFF
    return MIN_H + (h >> 8) % (MAX_H - MIN_H + 1)


def faces(i, j, half):
    """The faces of lot (i, j): (origin, u step, v step, patches along u, along v)."""
    x0, z0 = (i - half) * PITCH, (j - half) * PITCH
    w, h = 3 * WIDTH, 3 * height(i, j)
    nh = height(i, j)
    return [((x0, 0, z0), (1, 0, 0), (0, 1, 0), WIDTH, nh),          # front (z = z0)
            ((x0 + w, 0, z0), (0, 0, 1), (0, 1, 0), WIDTH, nh),      # right
            ((x0 + w, 0, z0 + w), (-1, 0, 0), (0, 1, 0), WIDTH, nh),  # back
            ((x0, 0, z0 + w), (0, 0, -1), (0, 1, 0), WIDTH, nh),     # left
            ((x0, h, z0), (1, 0, 0), (0, 0, 1), WIDTH, WIDTH)]       # roof


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--patches", type=int, default=10_000_000, help="at least this many patches")
    ap.add_argument("--out", required=True, help="folder for city.bpt and city.json")
    ap.add_argument("--name", default="city")
    a = ap.parse_args()
    mean = 4 * WIDTH * (MIN_H + MAX_H) / 2 + WIDTH * WIDTH
    side = max(1, math.ceil(math.sqrt(a.patches / mean)))
    half = side // 2
    lots = [(i, j) for j in range(side) for i in range(side)]
    # Grow the grid's last row until the count is reached (whole lots).
    count = sum(4 * WIDTH * height(i, j) + WIDTH * WIDTH for i, j in lots)
    while count < a.patches:
        side += 1
        half = side // 2
        lots = [(i, j) for j in range(side) for i in range(side)]
        count = sum(4 * WIDTH * height(i, j) + WIDTH * WIDTH for i, j in lots)
    os.makedirs(a.out, exist_ok=True)
    bpt = os.path.join(a.out, a.name + ".bpt")
    with open(bpt, "w", buffering=1 << 24) as f:
        f.write(f"{count}\n")
        base = 1  # one-based point indices
        for i, j in lots:
            for (_, _, _, nu, nv) in faces(i, j, half):
                row = 3 * nu + 1
                lines = []
                for pv in range(nv):
                    for pu in range(nu):
                        b = base + 3 * pv * row + 3 * pu
                        lines.append(",".join(str(b + r * row + c) for r in range(4) for c in range(4)))
                f.write("\n".join(lines))
                f.write("\n")
                base += row * (3 * nv + 1)
        f.write(f"{base - 1}\n")
        for i, j in lots:
            for ((ox, oy, oz), (ux, uy, uz), (vx, vy, vz), nu, nv) in faces(i, j, half):
                f.write("".join(f"{ox + a_ * ux + b_ * vx},{oy + a_ * uy + b_ * vy},{oz + a_ * uz + b_ * vz}\n"
                                for b_ in range(3 * nv + 1) for a_ in range(3 * nu + 1)))
    extent = side * PITCH / 2
    scene = f"""{{
  "camera": {{"position": [{-0.9 * extent:.1f}, {0.35 * extent:.1f}, {-0.9 * extent:.1f}], "look_at": [0, 0, 0], "fov": 40}},
  "film": {{"resolution": [320, 240], "spp": 1}},
  "integrator": {{"max_depth": 2}},
  "materials": {{"concrete": {{"type": "diffuse", "albedo": [0.55, 0.52, 0.48]}}}},
  "shapes": [{{"type": "bezier", "file": "{a.name}.bpt", "material": "concrete"}}],
  "lights": [{{"type": "distant", "direction": [0.35, 0.8, 0.45], "irradiance": [3, 2.9, 2.7], "angular_radius": 0.27}},
             {{"type": "environment", "radiance": [0.3, 0.4, 0.6]}}]
}}
"""
    with open(os.path.join(a.out, a.name + ".json"), "w") as f:
        f.write(scene)
    print(f"{bpt}: {count} patches, {base - 1} points, {side}x{side} lots, {os.path.getsize(bpt)} bytes")


if __name__ == "__main__":
    main()
