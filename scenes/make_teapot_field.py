#!/usr/bin/env python3
"""Writes a teapot field scene (default scenes/teapot-field.json; or the path given): a 10 x 10 grid of noise-displaced Utah teapots (teapot.bpt,
one transform per shape, each with its own noise seed and a turn about z) on a floor, lit by a
low sun. The larger scene of the peer comparison (bench/peer_render.sh): 3200 displaced patches,
far more than an up-front tessellation at a fine level holds easily (at --max-lod 8 for every
patch: 211 M vertices, 8.7 GB). Generated, not shipped: the tests render every shipped scene."""
import json
import os
import sys

N = 10
SPACING = 5.0
shapes = []
for i in range(N):
    for j in range(N):
        x = (i - (N - 1) / 2) * SPACING
        y = j * SPACING
        shapes.append({
            "type": "bezier", "file": "teapot.bpt", "material": "clay" if (i + j) % 2 == 0 else "copper",
            "transform": [{"rotate": {"axis": [0, 0, 1], "degrees": (37 * (i * N + j)) % 360}},
                          {"translate": [x, y, 0.0]}],
            "displacement": {"type": "noise", "amplitude": 0.06, "frequency": 2.5, "octaves": 4, "gain": 0.5,
                             "seed": i * N + j + 1}})
half = N * SPACING
shapes.append({"type": "bilinear", "material": "ground", "quads": [
    [[-half, -10, 0], [half, -10, 0], [-half, 2 * half, 0], [half, 2 * half, 0]]]})
scene = {
    "camera": {"position": [0.0, -14.0, 9.0], "look_at": [0.0, 14.0, 0.0], "up": [0, 0, 1], "fov": 50},
    "film": {"resolution": [640, 360], "spp": 16},
    "integrator": {"max_depth": 3, "seed": 0},
    "materials": {
        "clay": {"type": "diffuse", "albedo": [0.80, 0.55, 0.30]},
        "copper": {"type": "diffuse", "albedo": [0.55, 0.30, 0.20]},
        "ground": {"type": "diffuse", "albedo": [0.60, 0.60, 0.58]},
    },
    "shapes": shapes,
    "lights": [{"type": "distant", "direction": [-0.4, -0.5, 0.75], "irradiance": [3.0, 2.9, 2.7],
                "angular_radius": 0.27}],
}
here = os.path.dirname(os.path.abspath(__file__))
out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "teapot-field.json")
# The patches are the shipped teapot's, found relative to the scene file.
teapot = os.path.relpath(os.path.join(here, "teapot.bpt"), os.path.dirname(os.path.abspath(out)))
for shape in shapes:
    if shape["type"] == "bezier":
        shape["file"] = teapot
with open(out, "w") as f:
    json.dump(scene, f, indent=1)
    f.write("\n")
print("wrote", out)
