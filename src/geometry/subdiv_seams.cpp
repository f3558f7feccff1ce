// Watertight seams of the subdivision mesh (subdiv_mesh.h): every point on a leaf's border is
// evaluated canonically -- a mesh edge's points by the edge's owner face, a vertex's limit point
// from the table its owner filled, a non-quad's centre and internal borders by that face -- so
// two leaves sharing a border produce bit-identical border vertices at every level.
#include "geometry/subdiv_mesh_internal.h"

namespace rayes {

Vec3 MeshView::facePosition(int f, const float uv[2]) const {
  if (const BezierPatch* b = regular(f)) return b->evaluate(uv[0], uv[1]).p;
  return faceCache().get(t, m, f).eval(uv).p;
}

Vec3 MeshView::edgePoint(int e, float x) const {
  const auto ev = t.edgeVerts[size_t(e)];
  if (x == 0.0f) return m.vertexLimit[size_t(ev[0])];
  if (x == 1.0f) return m.vertexLimit[size_t(ev[1])];
  const int f = t.edgeOwner[size_t(e)], k = t.edgeOwnerLocal[size_t(e)];
  const float local = t.faceVerts[size_t(t.faceOffset[size_t(f)] + k)] == ev[0] ? x : 1.0f - x;
  float uv[2];
  t.param(f).GetEdgeCoord(k, local, uv);
  return facePosition(f, uv);
}

Vec3 MeshView::faceEdgePoint(int f, int k, float x) const {
  const int o = t.faceOffset[size_t(f)];
  const int e = t.faceEdges[size_t(o + k)];
  const bool forward = t.faceVerts[size_t(o + k)] == t.edgeVerts[size_t(e)][0];
  return edgePoint(e, forward ? x : 1.0f - x);
}

Vec3 MeshView::internalPoint(int f, int j, float r) const {
  if (r == 0.0f) return faceEdgePoint(f, j, 0.5f);
  if (r == 1.0f) return m.faceCenter[size_t(f)];
  float uv[2];
  leafToFace(t, f, j, 1.0f, r, uv);
  return facePosition(f, uv);
}

Vec3 MeshView::sidePoint(int f, int sub, int side, float p) const {
  if (sub < 0) {  // a quad: its edges 0..3 run (0,0)->(1,0)->(1,1)->(0,1)->(0,0)
    switch (side) {
      case 0: return faceEdgePoint(f, 0, p);
      case 1: return faceEdgePoint(f, 1, p);
      case 2: return faceEdgePoint(f, 2, 1.0f - p);
      default: return faceEdgePoint(f, 3, 1.0f - p);
    }
  }
  const int n = t.faceSize(f), prev = (sub + n - 1) % n;
  switch (side) {
    case 0: return faceEdgePoint(f, sub, p * 0.5f);
    case 1: return internalPoint(f, sub, p);
    case 2: return internalPoint(f, prev, p);
    default: return faceEdgePoint(f, prev, 1.0f - p * 0.5f);
  }
}

}  // namespace rayes
