#!/usr/bin/env python3
"""Writes scenes/teapot-field.json: a 10 x 10 grid of noise-displaced Utah teapots (teapot.bpt,
one transform per shape, each with its own noise seed and a turn about z) on a floor, lit by a
low sun. The larger scene of the peer comparison (bench/peer_render.sh): 3200 displaced patches,
far more than an up-front tessellation at a fine level holds easily."""
import json
import os

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
out = os.path.join(os.path.dirname(os.path.abspath(__file__)), "teapot-field.json")
with open(out, "w") as f:
    json.dump(scene, f, indent=1)
    f.write("\n")
print("wrote", out)
