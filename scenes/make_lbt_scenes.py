#!/usr/bin/env python3
"""Writes the light-beam-tracing scenes (docs/design.md, "Light beam tracing"): for each of
mirror, ring, pool, gears and discoball, scenes/lbt-NAME.json with glossy lobes of sigma = 0.001
rad and scenes/lbt-NAME-glossy.json with sigma = 0.05 rad (the pool's water is a smooth
dielectric in both: only its second file differs, by a glossy pool floor rim). Run from the
repository root: python3 scenes/make_lbt_scenes.py"""
import json
import math

K = 0.5522847498  # cubic Bezier quarter circle


def write(name, scene):
    with open(f"scenes/{name}.json", "w") as f:
        json.dump(scene, f, indent=1)
        f.write("\n")


def quad(p00, p10, p01, p11):
    return [p00, p10, p01, p11]


def tiles(p00, p10, p01, n):
    """The planar parallelogram p00, p10, p01 as n x n quads. A receiver's beam segments are binned
    per top-level leaf (at most 64 cells a side each), so one big quad under thousands of thin
    beams makes every gather visit hundreds of them; the same surface in n² leaves does not."""
    u = [(p10[k] - p00[k]) / n for k in range(3)]
    v = [(p01[k] - p00[k]) / n for k in range(3)]
    at = lambda i, j: [p00[k] + i * u[k] + j * v[k] for k in range(3)]
    return [quad(at(i, j), at(i + 1, j), at(i, j + 1), at(i + 1, j + 1)) for j in range(n) for i in range(n)]


def base(camera, res=(320, 240), spp=16, depth=6):
    return {"camera": camera, "film": {"resolution": list(res), "spp": spp},
            "integrator": {"max_depth": depth, "seed": 0}}


def mirror(sigma):
    s = base({"position": [0, -6, 0.3], "look_at": [0, 0, 1.6], "up": [0, 0, 1], "fov": 55})
    s["materials"] = {"mirror": {"type": "glossy", "specular": [0.9, 0.9, 0.9], "sigma": sigma},
                      "ceiling": {"type": "diffuse", "albedo": [0.8, 0.8, 0.8]}}
    s["shapes"] = [
        {"type": "bilinear", "material": "mirror", "quads": [quad([-1, -1, 0], [1, -1, 0], [-1, 1, 0], [1, 1, 0])]},
        {"type": "bilinear", "material": "ceiling", "quads": [quad([-4, -4, 2], [4, -4, 2], [-4, 4, 2], [4, 4, 2])]}]
    s["lights"] = [{"type": "point", "position": [0, 0, 1], "intensity": [10, 10, 10]}]
    return s


def cylinder(radius, height, cx=0.0, cy=0.0, z0=0.0):
    """Four bicubic Bezier patches: a cylinder wall of the given radius and height."""
    patches = []
    for q in range(4):
        a0 = q * math.pi / 2
        c0, s0 = math.cos(a0), math.sin(a0)
        c1, s1 = math.cos(a0 + math.pi / 2), math.sin(a0 + math.pi / 2)
        ring = [(c0, s0), (c0 - K * s0, s0 + K * c0), (c1 + K * s1, s1 - K * c1), (c1, s1)]
        rows = []
        for j in range(4):
            z = z0 + height * j / 3
            rows += [[cx + radius * x, cy + radius * y, z] for x, y in ring]
        patches.append(rows)
    return patches


def ring(sigma):
    s = base({"position": [-3.2, -3.4, 3.4], "look_at": [0.1, 0, 0.1], "up": [0, 0, 1], "fov": 38}, depth=5)
    s["materials"] = {"metal": {"type": "glossy", "specular": [0.95, 0.8, 0.5], "sigma": sigma},
                      "floor": {"type": "diffuse", "albedo": [0.7, 0.7, 0.7]}}
    s["shapes"] = [{"type": "bezier", "material": "metal", "patches": cylinder(1.0, 0.5)},
                   {"type": "bilinear", "material": "floor", "quads": tiles([-3, -3, 0], [3, -3, 0], [-3, 3, 0], 8)}]
    alpha = math.radians(25)
    s["lights"] = [{"type": "distant", "direction": [-math.cos(alpha), 0, math.sin(alpha)], "irradiance": [3, 3, 3]}]
    return s


def pool(sigma):
    s = base({"position": [0, -5.5, 3.5], "look_at": [0, 0, -0.6], "up": [0, 0, 1], "fov": 40}, depth=6)
    quads = []
    n = 4
    for i in range(n):
        for j in range(n):
            x0, y0 = -2 + 4 * i / n, -2 + 4 * j / n
            x1, y1 = x0 + 4 / n, y0 + 4 / n
            quads.append(quad([x0, y0, 0], [x1, y0, 0], [x0, y1, 0], [x1, y1, 0]))
    s["materials"] = {"water": {"type": "dielectric", "ior": 1.33},
                      "tiles": {"type": "diffuse", "albedo": [0.55, 0.7, 0.75]},
                      "rim": {"type": "glossy", "specular": [0.8, 0.8, 0.8], "sigma": sigma}}
    # Everything under the water is lit only through it (caustic paths: a point light seen
    # through a smooth surface, which the path tracer can never sample), so the pool has side
    # walls and a deck lit directly: without them pt and lt rendered it black.
    deck = [quad([-3.5, -3.5, 0.05], [3.5, -3.5, 0.05], [-3.5, -2, 0.05], [3.5, -2, 0.05]),
            quad([-3.5, 2, 0.05], [3.5, 2, 0.05], [-3.5, 3.5, 0.05], [3.5, 3.5, 0.05]),
            quad([-3.5, -2, 0.05], [-2, -2, 0.05], [-3.5, 2, 0.05], [-2, 2, 0.05]),
            quad([2, -2, 0.05], [3.5, -2, 0.05], [2, 2, 0.05], [3.5, 2, 0.05])]
    walls = [quad([-2, -2, -1], [2, -2, -1], [-2, -2, 0.05], [2, -2, 0.05]),
             quad([-2, -2, -1], [-2, 2, -1], [-2, -2, 0.05], [-2, 2, 0.05]),
             quad([2, -2, -1], [2, 2, -1], [2, -2, 0.05], [2, 2, 0.05])]
    s["materials"]["deck"] = {"type": "diffuse", "albedo": [0.8, 0.78, 0.72]}
    s["shapes"] = [
        {"type": "bilinear", "material": "water", "quads": quads,
         "displacement": {"type": "noise", "amplitude": 0.06, "offset": -0.03, "frequency": 1.2, "octaves": 3,
                          "gain": 0.5, "lacunarity": 2, "seed": 3}},
        {"type": "bilinear", "material": "tiles", "quads": [quad([-2, -2, -1], [2, -2, -1], [-2, 2, -1], [2, 2, -1])]
         + walls},
        {"type": "bilinear", "material": "deck", "quads": deck},
        {"type": "bilinear", "material": "rim", "quads": [quad([-2, 2, -1], [2, 2, -1], [-2, 2, 0.3], [2, 2, 0.3])]}]
    s["lights"] = [{"type": "point", "position": [0.8, -1.0, 4.0], "intensity": [40, 38, 34]}]
    return s


def gear(cx, cy, r, teeth, h, z0=0.0):
    """A gear's rim as flat facets: 2*teeth planar quads alternating between r and 1.15 r."""
    quads = []
    for k in range(2 * teeth):
        a0, a1 = 2 * math.pi * k / (2 * teeth), 2 * math.pi * (k + 1) / (2 * teeth)
        r0 = r if k % 2 == 0 else 1.15 * r
        p0 = [cx + r0 * math.cos(a0), cy + r0 * math.sin(a0)]
        p1 = [cx + r0 * math.cos(a1), cy + r0 * math.sin(a1)]
        quads.append(quad(p0 + [z0], p1 + [z0], p0 + [z0 + h], p1 + [z0 + h]))
    return quads


def gears(sigma):
    s = base({"position": [0, -5.5, 4.5], "look_at": [0, 0.2, 0], "up": [0, 0, 1], "fov": 40}, depth=5)
    s["materials"] = {"brass": {"type": "glossy", "specular": [0.9, 0.75, 0.4], "sigma": sigma},
                      "floor": {"type": "diffuse", "albedo": [0.7, 0.7, 0.7]}}
    quads = gear(-0.9, 0.0, 0.7, 12, 0.3) + gear(0.85, 0.3, 0.5, 9, 0.3) + gear(0.2, 1.3, 0.35, 7, 0.3)
    s["shapes"] = [{"type": "bilinear", "material": "brass", "quads": quads},
                   {"type": "bilinear", "material": "floor", "quads": tiles([-4, -4, 0], [4, -4, 0], [-4, 4, 0], 8)}]
    s["lights"] = [{"type": "spot", "position": [-2.5, -2.0, 2.0], "look_at": [0, 0.3, 0], "intensity": [30, 30, 30],
                    "cone_angle": 45, "falloff_start": 35}]
    return s


def discoball(sigma):
    s = base({"position": [0, -5.8, 1.6], "look_at": [0, 0, 1.4], "up": [0, 0, 1], "fov": 60}, depth=5)
    s["materials"] = {"facet": {"type": "glossy", "specular": [0.9, 0.9, 0.9], "sigma": sigma},
                      "room": {"type": "diffuse", "albedo": [0.75, 0.75, 0.75]}}
    quads = []
    rings, sectors, r, c = 10, 20, 0.5, [0, 0, 2.0]

    def point(i, j):
        th, ph = math.pi * i / rings, 2 * math.pi * j / sectors
        return [c[0] + r * math.sin(th) * math.cos(ph), c[1] + r * math.sin(th) * math.sin(ph),
                c[2] + r * math.cos(th)]
    # Flat facets that tile the sphere: a latitude-longitude cell's corners form an isosceles
    # trapezoid (symmetric about its middle meridian plane), so it is planar, and neighbouring cells
    # share their edges. (Parallelograms on three of the corners, as before, overlapped their
    # neighbours, and lbt lost about 2 % of the caustic where a facet hid part of another;
    # bench/history/2026-11.md.) The polar caps are left open (seen from below: dark).
    for i in range(1, rings - 1):
        for j in range(sectors):
            quads.append(quad(point(i, j), point(i, j + 1), point(i + 1, j), point(i + 1, j + 1)))
    room = (tiles([-4, -4, 0], [4, -4, 0], [-4, 4, 0], 6) + tiles([-4, 4, 0], [4, 4, 0], [-4, 4, 4], 6)
            + tiles([-4, -4, 0], [-4, 4, 0], [-4, -4, 4], 6) + tiles([4, -4, 0], [4, 4, 0], [4, -4, 4], 6)
            + tiles([-4, -4, 4], [4, -4, 4], [-4, 4, 4], 6))
    s["shapes"] = [{"type": "bilinear", "material": "facet", "quads": quads},
                   {"type": "bilinear", "material": "room", "quads": room}]
    s["lights"] = [{"type": "spot", "position": [1.5, -2.5, 3.2], "look_at": c, "intensity": [60, 55, 50],
                    "cone_angle": 20}]
    return s


for name, make in [("mirror", mirror), ("ring", ring), ("pool", pool), ("gears", gears), ("discoball", discoball)]:
    write(f"lbt-{name}", make(0.001))
    write(f"lbt-{name}-glossy", make(0.05))
