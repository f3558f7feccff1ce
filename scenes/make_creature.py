#!/usr/bin/env python3
"""Writes scenes/creature.obj: a Catmull-Clark control cage of a four-legged creature.

Deterministic (no randomness, fixed float formatting), so the committed OBJ is reproducible:
    python3 scenes/make_creature.py > scenes/creature.obj

Construction: a box body on a coarse grid; legs, neck + head and tail extruded from its faces
(tapering, bending); one smooth Catmull-Clark step in Python to get a denser, rounder cage;
two horns extruded from the head of that cage. Creases, in OpenSubdiv's tag form: the ridge
along the spine (infinitely sharp), the rims of the soles (sharpness 2), the horn tips
(infinitely sharp). The cage is closed and all quads; its extraordinary vertices (valence 3
and 5) sit where the limbs leave the body.

Uv set (vt lines, f v/vt): a cylindrical projection about the body's long axis, s the angle
around it (a full turn over [0, 1]) and t the position along it over [0, 1]. Each face takes
its corners' angles within half a turn of its centre's, so the faces on either side of the
bottom line (the angle's wrap, between the legs) get different uv values for the same vertices:
a uv seam, continuous everywhere else. Textures repeat in s, so an image that tiles in s shows
no seam in the render.
"""
import math
import sys


class Mesh:
    def __init__(self):
        self.v = []      # [x, y, z]
        self.f = []      # vertex index lists (counter-clockwise seen from outside)
        self.crease = {}  # (min, max) vertex pair -> sharpness

    def add(self, p):
        self.v.append(list(p))
        return len(self.v) - 1


def box(m, lo, hi, n):
    """Closed box [lo, hi] with n = (nx, ny, nz) quads per side; returns {(axis, sign, i, j): face}."""
    index = {}

    def vid(p):
        key = tuple(round(c, 9) for c in p)
        if key not in index:
            index[key] = m.add(p)
        return index[key]

    faces = {}
    for axis in range(3):
        a1, a2 = (axis + 1) % 3, (axis + 2) % 3
        for sign in (0, 1):
            for i in range(n[a1]):
                for j in range(n[a2]):
                    corners = []
                    for di, dj in ((0, 0), (1, 0), (1, 1), (0, 1)):
                        p = [0.0, 0.0, 0.0]
                        p[axis] = hi[axis] if sign else lo[axis]
                        p[a1] = lo[a1] + (hi[a1] - lo[a1]) * (i + di) / n[a1]
                        p[a2] = lo[a2] + (hi[a2] - lo[a2]) * (j + dj) / n[a2]
                        corners.append(vid(p))
                    if not sign:
                        corners.reverse()
                    faces[(axis, sign, i, j)] = len(m.f)
                    m.f.append(corners)
    return faces


def centroid(m, face):
    vs = [m.v[i] for i in face]
    return [sum(p[k] for p in vs) / len(vs) for k in range(3)]


def normal(m, face):
    p = [m.v[i] for i in face]
    n = [0.0, 0.0, 0.0]
    for k in range(len(p)):
        a, b = p[k], p[(k + 1) % len(p)]
        n[0] += (a[1] - b[1]) * (a[2] + b[2])
        n[1] += (a[2] - b[2]) * (a[0] + b[0])
        n[2] += (a[0] - b[0]) * (a[1] + b[1])
    length = math.sqrt(sum(c * c for c in n))
    return [c / length for c in n]


def extrude(m, fi, offset, scale):
    """Extrudes face fi by `offset` (a vector), scaling the new cap about its centre.
    Returns the index of the new cap face (which replaces fi)."""
    face = m.f[fi]
    c = centroid(m, face)
    newc = [c[k] + offset[k] for k in range(3)]
    cap = [m.add([newc[k] + (m.v[i][k] - c[k]) * scale for k in range(3)]) for i in face]
    n = len(face)
    for k in range(n):
        a, b = face[k], face[(k + 1) % n]
        m.f.append([a, b, cap[(k + 1) % n], cap[k]])
    m.f[fi] = cap
    return fi


def catmull_clark(m):
    """One smooth Catmull-Clark step of a closed manifold mesh; creases map to child edges
    with the same sharpness (a modelling choice for the new cage, not OpenSubdiv's rule)."""
    out = Mesh()
    nv = len(m.v)
    fpts = [centroid(m, f) for f in m.f]
    edge_faces = {}
    for fi, f in enumerate(m.f):
        for k in range(len(f)):
            e = (min(f[k], f[(k + 1) % len(f)]), max(f[k], f[(k + 1) % len(f)]))
            edge_faces.setdefault(e, []).append(fi)
    edges = sorted(edge_faces)
    for e, fs in edge_faces.items():
        assert len(fs) == 2, "the cage must be closed and manifold"
    vert_faces = [[] for _ in range(nv)]
    vert_edges = [[] for _ in range(nv)]
    for fi, f in enumerate(m.f):
        for i in f:
            vert_faces[i].append(fi)
    for e in edges:
        vert_edges[e[0]].append(e)
        vert_edges[e[1]].append(e)
    # vertex points
    for i in range(nv):
        n = len(vert_faces[i])
        F = [sum(fpts[f][k] for f in vert_faces[i]) / n for k in range(3)]
        R = [sum((m.v[a][k] + m.v[b][k]) / 2 for a, b in vert_edges[i]) / n for k in range(3)]
        out.add([(F[k] + 2 * R[k] + (n - 3) * m.v[i][k]) / n for k in range(3)])
    eid = {}
    for e in edges:
        fa, fb = edge_faces[e]
        eid[e] = out.add([(m.v[e[0]][k] + m.v[e[1]][k] + fpts[fa][k] + fpts[fb][k]) / 4 for k in range(3)])
    fid = [out.add(p) for p in fpts]
    for fi, f in enumerate(m.f):
        n = len(f)
        for k in range(n):
            prev, cur, nxt = f[(k - 1) % n], f[k], f[(k + 1) % n]
            e_in = eid[(min(prev, cur), max(prev, cur))]
            e_out = eid[(min(cur, nxt), max(cur, nxt))]
            out.f.append([cur, e_out, fid[fi], e_in])
    for (a, b), s in m.crease.items():
        mid = eid[(a, b)]
        out.crease[(min(a, mid), max(a, mid))] = s
        out.crease[(min(b, mid), max(b, mid))] = s
    return out


def build():
    m = Mesh()
    # Body: x is the length (head at +x), z up. 6 x 2 x 2 quads, so y = 0 is a row of edges.
    faces = box(m, [-1.2, -0.55, 0.7], [1.2, 0.55, 1.4], (6, 2, 2))
    # Spine ridge: top edges along y = 0.
    top_mid = [i for i, p in enumerate(m.v) if abs(p[1]) < 1e-9 and abs(p[2] - 1.4) < 1e-9]
    top_mid.sort(key=lambda i: m.v[i][0])
    for a, b in zip(top_mid, top_mid[1:]):
        m.crease[(min(a, b), max(a, b))] = 10.0
    # Round the box into an ellipsoid-like barrel (a box cage would give a rounded box).
    centre, radii = [0.0, 0.0, 1.05], [1.25, 0.6, 0.42]
    for p in m.v:
        q = [(p[k] - centre[k]) / radii[k] for k in range(3)]
        q[0] *= 0.8  # flatter ends, so the limbs attach to a long barrel rather than a ball
        length = math.sqrt(sum(c * c for c in q))
        for k in range(3):
            p[k] = centre[k] + q[k] / length * radii[k]
    # Legs: bottom faces (axis 2, sign 0) at the four corners of the 6 x 2 grid.
    soles = []
    for i in (0, 5):
        for j in (0, 1):
            f = faces[(2, 0, i, j)]
            splay = -0.06 if j == 0 else 0.06
            for seg in range(4):
                fwd = 0.06 if seg == 3 else 0.0
                extrude(m, f, [fwd, splay * (seg < 2), -0.16], (0.9, 0.85, 0.95, 1.05)[seg])
            soles.append(f)
    for f in soles:
        face = m.f[f]
        for k in range(4):
            a, b = face[k], face[(k + 1) % 4]
            m.crease[(min(a, b), max(a, b))] = 2.0
    # Neck and head from the upper front faces (+x): both of the 2 x 2 upper row, so the
    # head is two quads wide and keeps the y = 0 symmetry.
    neck = [faces[(0, 1, j, 1)] for j in (0, 1)]
    # Merge the two neck faces' extrusion by extruding each with the same offsets.
    steps = [([0.22, 0, 0.16], 0.92), ([0.18, 0, 0.2], 0.9), ([0.18, 0, 0.12], 1.0),
             ([0.22, 0, 0.02], 1.12), ([0.24, 0, -0.04], 0.95), ([0.2, 0, -0.06], 0.7)]
    for off, sc in steps:
        # Scale both faces about their common centre so the pair stays joined.
        c = [sum(centroid(m, m.f[f])[k] for f in neck) / 2 for k in range(3)]
        for f in neck:
            fc = centroid(m, m.f[f])
            extrude(m, f, [off[k] + (fc[k] - c[k]) * (sc - 1) for k in range(3)], sc)
    # Tail from the upper back faces (-x).
    tail = [faces[(0, 0, j, 1)] for j in (0, 1)]
    for seg in range(6):
        c = [sum(centroid(m, m.f[f])[k] for f in tail) / 2 for k in range(3)]
        sc = 0.8
        for f in tail:
            fc = centroid(m, m.f[f])
            off = [-0.2, 0.0, 0.06 + 0.03 * seg]
            extrude(m, f, [off[k] + (fc[k] - c[k]) * (sc - 1) for k in range(3)], sc)
    m = join_pairs(m)
    fine = catmull_clark(m)
    # Horns: the two head faces of the fine cage highest above the head, one per side.
    head_x = max(p[0] for p in fine.v) - 0.35
    cands = [(centroid(fine, f)[2], fi) for fi, f in enumerate(fine.f)
             if centroid(fine, f)[0] > head_x - 0.25 and centroid(fine, f)[0] < head_x and normal(fine, f)[2] > 0.8]
    left = max((c for c in cands if centroid(fine, fine.f[c[1]])[1] > 0.08), default=None)
    right = max((c for c in cands if centroid(fine, fine.f[c[1]])[1] < -0.08), default=None)
    for pick in (left, right):
        f = pick[1]
        side = 1.0 if centroid(fine, fine.f[f])[1] > 0 else -1.0
        for seg in range(3):
            extrude(fine, f, [-0.03, side * 0.04, 0.13], 0.72)
        tip = fine.f[f]
        for k in range(4):
            a, b = tip[k], tip[(k + 1) % 4]
            fine.crease[(min(a, b), max(a, b))] = 10.0
    # Stand on z = 0: the soles' limit lies a little above their cage.
    for p in fine.v:
        p[2] -= 0.1
    return fine


def join_pairs(m):
    """Extruding two neighbouring faces separately duplicates the vertices of their shared
    edge and leaves two inner walls; merge coincident vertices and drop faces that collapse
    or appear twice (the walls), keeping the mesh closed."""
    key = {}
    remap = []
    newv = []
    for p in m.v:
        k = tuple(round(c, 7) for c in p)
        if k not in key:
            key[k] = len(newv)
            newv.append(p)
        remap.append(key[k])
    seen = {}
    faces = []
    for f in m.f:
        g = [remap[i] for i in f]
        if len(set(g)) < len(g):
            continue
        s = tuple(sorted(g))
        seen.setdefault(s, []).append(len(faces))
        faces.append(g)
    drop = set()
    for s, idx in seen.items():
        if len(idx) > 1:
            drop.update(idx)
    out = Mesh()
    out.v = newv
    used = sorted({i for fi, f in enumerate(faces) if fi not in drop for i in f})
    compact = {old: new for new, old in enumerate(used)}
    out.v = [newv[i] for i in used]
    out.f = [[compact[i] for i in f] for fi, f in enumerate(faces) if fi not in drop]
    for (a, b), s in m.crease.items():
        a2, b2 = remap[a], remap[b]
        if a2 in compact and b2 in compact:
            out.crease[(min(compact[a2], compact[b2]), max(compact[a2], compact[b2]))] = s
    return out


def uv_set(m):
    """(values, per-face value indices) of the cylindrical projection described above."""
    axis_y, axis_z = 0.0, 0.95
    xs = [p[0] for p in m.v]
    x0, x1 = min(xs), max(xs)

    def angle(p):
        return math.atan2(p[1] - axis_y, p[2] - axis_z)

    values, index, faces = [], {}, []
    for f in m.f:
        c = angle(centroid(m, f))
        ids = []
        for i in f:
            a = angle(m.v[i])
            while a - c > math.pi:
                a -= 2 * math.pi
            while a - c <= -math.pi:
                a += 2 * math.pi
            st = (round(a / (2 * math.pi) + 0.5, 6), round((m.v[i][0] - x0) / (x1 - x0), 6))
            key = (i, st)
            if key not in index:
                index[key] = len(values)
                values.append(st)
            ids.append(index[key])
        faces.append(ids)
    return values, faces


def main():
    m = build()
    uvs, uv_faces = uv_set(m)
    w = sys.stdout.write
    w("# Catmull-Clark cage of a creature, written by scenes/make_creature.py (do not edit).\n")
    w("# %d vertices, %d faces, %d creased edges, %d uv values.\n" % (len(m.v), len(m.f), len(m.crease), len(uvs)))
    for p in m.v:
        w("v %.6f %.6f %.6f\n" % tuple(0.0 if abs(c) < 5e-7 else c for c in p))
    for st in uvs:
        w("vt %.6f %.6f\n" % tuple(0.0 if abs(c) < 5e-7 else c for c in st))
    for f, t in zip(m.f, uv_faces):
        w("f %s\n" % " ".join("%d/%d" % (i + 1, k + 1) for i, k in zip(f, t)))
    by_sharpness = {}
    for e, s in sorted(m.crease.items()):
        by_sharpness.setdefault(s, []).append(e)
    for s, es in sorted(by_sharpness.items()):
        for e in es:
            w("t crease 2/1/0 %d %d %g\n" % (e[0], e[1], s))


if __name__ == "__main__":
    main()
