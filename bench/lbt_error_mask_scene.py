#!/usr/bin/env python3
"""Writes the mask scene of an lbt scene (bench/converge_lbt.sh): every caustic scatterer (glossy,
mirror, dielectric, conductor) black, every other material white, and a uniform environment as
the only light. Rendered, its non-zero pixels are those where the camera sees a diffuse surface
(or the background) first: the pixels where the reference (pt --caustic-paths without plus lt
--caustic-paths only) is complete. It lacks caustics seen through a scatterer, which the light
tracer cannot connect to the camera (a delta or near-delta lobe), so `rayes converge
--error-mask` leaves those pixels out of RMSE and relMSE.
Usage: bench/lbt_error_mask_scene.py SCENE.json OUT.json"""
import json
import sys

SCATTERERS = {"glossy", "mirror", "dielectric", "conductor", "glass"}

scene = json.load(open(sys.argv[1]))
for name, m in scene["materials"].items():
    black = m.get("type") in SCATTERERS
    scene["materials"][name] = {"type": "diffuse", "albedo": [0.0] * 3 if black else [1.0] * 3}
scene["lights"] = [{"type": "environment", "radiance": [1.0, 1.0, 1.0]}]
for shape in scene["shapes"]:
    shape.pop("emission", None)
with open(sys.argv[2], "w") as f:
    json.dump(scene, f, indent=1)
