// A subdivision leaf's points: its own evaluation (Bézier form or Bfr, with a non-degenerate
// normal), evaluateLeaf and the dicing. The two take their border positions from the canonical
// seam evaluation (subdiv_seams.cpp) with the same calls, so a leaf's evaluate() and its dicing
// agree bit for bit (the Patch contract), and so do neighbours along their shared borders.
#include "geometry/subdiv_mesh_internal.h"

namespace rayes {

SurfacePoint MeshView::own(int f, int sub, const BfrFace* bfr, float s, float tt) const {
  if (const BezierPatch* b = regular(f)) return b->evaluate(s, tt);
  auto at = [&](float ss, float ts) {
    float uv[2];
    leafToFace(t, f, sub, ss, ts, uv);
    return bfr->eval(uv);
  };
  SurfacePoint sp = at(s, tt);
  sp.n = detail::nonDegenerateNormal([&](float a, float b) { return at(a, b).n; }, sp.n, s, tt,
                                     m.faceTiny[size_t(f)]);
  return sp;
}

SurfacePoint SubdivMesh::evaluateLeaf(int leaf, float u, float v) const {
  const auto [f, sub] = topo_->leaves[size_t(leaf)];
  const MeshView view{*topo_, *impl_};
  const BfrFace* bfr = view.regular(f) ? nullptr : &faceCache().get(*topo_, *impl_, f);
  SurfacePoint sp = view.own(f, sub, bfr, u, v);
  if (v == 0.0f) sp.p = view.sidePoint(f, sub, 0, u);
  else if (v == 1.0f) sp.p = view.sidePoint(f, sub, 2, u);
  else if (u == 0.0f) sp.p = view.sidePoint(f, sub, 3, v);
  else if (u == 1.0f) sp.p = view.sidePoint(f, sub, 1, v);
  return sp;
}

void SubdivMesh::diceLeaf(int leaf, int level, Vec3* positions, Vec3* normals) const {
  const auto [f, sub] = topo_->leaves[size_t(leaf)];
  const MeshView view{*topo_, *impl_};
  const int n = 1 << level;
  const float fn = float(n);
  const size_t row = size_t(n) + 1;
  if (const BezierPatch* b = view.regular(f)) {
    b->dice(level, positions, normals);
  } else {
    // Used only here: the borders below may replace the cache slot while fetching owners.
    const BfrFace& bfr = faceCache().get(*topo_, *impl_, f);
    for (int j = 0; j <= n; ++j) {
      const float v = float(j) / fn;
      for (int i = 0; i <= n; ++i) {
        const SurfacePoint sp = view.own(f, sub, &bfr, float(i) / fn, v);
        positions[size_t(j) * row + size_t(i)] = sp.p;
        normals[size_t(j) * row + size_t(i)] = sp.n;
      }
    }
  }
  // Borders in canonical form (the same calls evaluateLeaf makes).
  for (int k = 0; k <= n; ++k) {
    const float p = float(k) / fn;
    positions[size_t(k)] = view.sidePoint(f, sub, 0, p);
    positions[size_t(n) * row + size_t(k)] = view.sidePoint(f, sub, 2, p);
    positions[size_t(k) * row] = view.sidePoint(f, sub, 3, p);
    positions[size_t(k) * row + size_t(n)] = view.sidePoint(f, sub, 1, p);
  }
}

}  // namespace rayes
