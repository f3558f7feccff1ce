#!/usr/bin/env python3
"""Writes the mask scene of an lbt scene (bench/converge_lbt.sh): every caustic scatterer (glossy,
mirror, dielectric, conductor) black, every other material black but emitting 1 from both sides,
and a uniform environment of 1 as the only light. Rendered, a pixel's value is the fraction of it
where the camera sees a diffuse surface (or the background) first; bench_app_mask_threshold
keeps the pixels where that fraction is 1 (bench/lbt_references.sh). Those are the pixels where
the reference (pt --caustic-paths without plus lt --caustic-paths only) is complete: it lacks
caustics seen through a scatterer, which the light tracer cannot connect to the camera (a delta
or near-delta lobe), and at a scatterer's edge the light tracer's connections through a
near-delta lobe are fireflies. `rayes converge --error-mask` leaves the other pixels out of RMSE
and relMSE.
Usage: bench/lbt_error_mask_scene.py SCENE.json OUT.json"""
import json
import sys

SCATTERERS = {"glossy", "mirror", "dielectric", "conductor", "glass"}

scene = json.load(open(sys.argv[1]))
for name, m in scene["materials"].items():
    seen = m.get("type") not in SCATTERERS
    scene["materials"][name] = {"type": "diffuse", "albedo": [0.0] * 3}
    if seen:
        scene["materials"][name].update({"emission": [1.0] * 3, "two_sided": True})
scene["lights"] = [{"type": "environment", "radiance": [1.0, 1.0, 1.0]}]
for shape in scene["shapes"]:
    shape.pop("emission", None)
with open(sys.argv[2], "w") as f:
    json.dump(scene, f, indent=1)
