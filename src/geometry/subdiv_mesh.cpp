// The SubdivMesh: a SubdivTopology with its control points, and what depends on them, built once
// (regular faces in Bézier form, Bfr bounds, vertex limit points, face centres, leaf sizes); the
// per-thread cache of Bfr surfaces every evaluation goes through; and the leaves' bounds, sizes
// and patches. A leaf's points are in subdiv_dice.cpp, its borders' in subdiv_seams.cpp.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <stdexcept>
#include <string>
#include <tbb/parallel_for.h>
#include "geometry/subdiv_mesh_internal.h"
#include "geometry/subdiv_patch.h"

namespace rayes {

namespace {

std::atomic<uint64_t> gNextMeshId{1};

// Uniform cubic B-spline segment -> Bézier, in double.
void bsplineToBezier(const double p[4][3], double b[4][3]) {
  for (int c = 0; c < 3; ++c) {
    b[0][c] = (p[0][c] + 4.0 * p[1][c] + p[2][c]) / 6.0;
    b[1][c] = (2.0 * p[1][c] + p[2][c]) / 3.0;
    b[2][c] = (p[1][c] + 2.0 * p[2][c]) / 3.0;
    b[3][c] = (p[1][c] + 4.0 * p[2][c] + p[3][c]) / 6.0;
  }
}

// Bfr's regular patch: 4x4 row-major, the face's corners at 5, 6, 10, 9 (u along a row).
std::array<Vec3, 16> regularBezier(const std::array<int, 16>& cv, const std::vector<float>& pts) {
  double rows[4][4][3];  // [row][bezier u-index][xyz]
  for (int r = 0; r < 4; ++r) {
    double p[4][3];
    for (int c = 0; c < 4; ++c)
      for (int x = 0; x < 3; ++x) p[c][x] = pts[size_t(cv[size_t(r * 4 + c)]) * 3 + size_t(x)];
    bsplineToBezier(p, rows[r]);
  }
  std::array<Vec3, 16> out;
  for (int i = 0; i < 4; ++i) {
    double p[4][3], b[4][3];
    for (int r = 0; r < 4; ++r)
      for (int x = 0; x < 3; ++x) p[r][x] = rows[r][i][x];
    bsplineToBezier(p, b);
    for (int j = 0; j < 4; ++j) out[size_t(j * 4 + i)] = {float(b[j][0]), float(b[j][1]), float(b[j][2])};
  }
  return out;
}

}  // namespace

BfrFaceCache& faceCache() {
  thread_local BfrFaceCache cache;
  return cache;
}

SubdivMesh::~SubdivMesh() = default;

std::shared_ptr<const SubdivMesh> SubdivMesh::build(std::shared_ptr<const SubdivTopology> topology,
                                                    std::vector<Vec3> positions) {
  static_assert(sizeof(Vec3) == 3 * sizeof(float));
  const SubdivTopology& t = *topology;
  if (int(positions.size()) != t.numVertices)
    throw std::invalid_argument("SubdivMesh: expected " + std::to_string(t.numVertices) + " positions");
  std::shared_ptr<SubdivMesh> mesh(new SubdivMesh());
  mesh->topo_ = topology;
  mesh->impl_ = std::make_unique<Impl>();
  Impl& m = *mesh->impl_;
  m.id = gNextMeshId++;
  m.points.resize(positions.size() * 3);
  for (size_t v = 0; v < positions.size(); ++v) {
    m.points[v * 3] = positions[v].x;
    m.points[v * 3 + 1] = positions[v].y;
    m.points[v * 3 + 2] = positions[v].z;
  }
  const int nf = t.faces();
  m.vertexLimit.assign(positions.size(), Vec3{});
  m.faceCenter.assign(size_t(nf), Vec3{});
  m.regular.resize(t.regularCVs.size());
  m.faceBounds.assign(size_t(nf), Box3{});
  m.faceError.assign(size_t(nf), 0.0f);
  m.faceTiny.assign(size_t(nf), 0.0f);

  // Per face: Bézier form or Bfr bounds, the limit points of the vertices it owns, its centre.
  tbb::parallel_for(0, nf, [&](int f) {
    if (!t.hasLimit[size_t(f)]) return;
    const int slot = t.regularSlot[size_t(f)];
    BfrFace local;
    const BezierPatch* bez = nullptr;
    if (slot >= 0) {
      m.regular[size_t(slot)].emplace(regularBezier(t.regularCVs[size_t(slot)], m.points));
      bez = &*m.regular[size_t(slot)];
      m.faceBounds[size_t(f)] = bez->bounds();
      m.faceError[size_t(f)] = bez->dicingErrorCoefficient();
    } else {
      local.init(t, m, f);
      m.faceBounds[size_t(f)] = local.hull.grownBy(local.evaluationError());
      m.faceError[size_t(f)] = local.hull.longestSide();
    }
    m.faceTiny[size_t(f)] = detail::degenerateNormalThreshold(m.faceBounds[size_t(f)].longestSide());
    auto position = [&](const float uv[2]) { return bez ? bez->evaluate(uv[0], uv[1]).p : local.eval(uv).p; };
    const Bfr::Parameterization param = t.param(f);
    const int n = t.faceSize(f), o = t.faceOffset[size_t(f)];
    for (int k = 0; k < n; ++k) {
      const int v = t.faceVerts[size_t(o + k)];
      if (t.vertexOwner[size_t(v)] != f || t.vertexOwnerLocal[size_t(v)] != k) continue;
      float uv[2];
      param.GetVertexCoord(k, uv);
      m.vertexLimit[size_t(v)] = position(uv);
    }
    if (t.leafKind(f) != LeafKind::Quad) {
      float uv[2];
      param.GetCenterCoord(uv);
      m.faceCenter[size_t(f)] = position(uv);
    }
  });

  // Leaf size estimates: Bézier control polylines, or 1.25 x the longest iso-polyline through
  // a 5 x 5 grid of limit points.
  m.leafSize.assign(t.leaves.size(), 0.0f);
  const MeshView view{t, m};
  tbb::parallel_for(0, int(t.leaves.size()), [&](int leaf) {
    const auto [f, sub] = t.leaves[size_t(leaf)];
    if (const BezierPatch* b = view.regular(f)) {
      m.leafSize[size_t(leaf)] = b->sizeBound();
      return;
    }
    BfrFace local;
    local.init(t, m, f);
    Vec3 g[5][5];
    for (int j = 0; j < 5; ++j)
      for (int i = 0; i < 5; ++i) {
        float uv[2];
        leafToFace(t, f, sub, float(i) / 4.0f, float(j) / 4.0f, uv);
        g[j][i] = local.eval(uv).p;
      }
    float longest = 0;
    for (int a = 0; a < 5; ++a) {
      float row = 0, col = 0;
      for (int k = 0; k < 4; ++k) {
        row += length(g[a][k + 1] - g[a][k]);
        col += length(g[k + 1][a] - g[k][a]);
      }
      longest = std::max(longest, std::max(row, col));
    }
    m.leafSize[size_t(leaf)] = 1.25f * longest;
  });
  return mesh;
}

std::vector<PatchPtr> SubdivMesh::patches() const {
  std::vector<PatchPtr> out;
  out.reserve(topo_->leaves.size());
  const SubdivMeshPtr self = shared_from_this();
  for (int leaf = 0; leaf < int(topo_->leaves.size()); ++leaf) out.push_back(std::make_shared<SubdivFacePatch>(self, leaf));
  return out;
}

SubdivStats SubdivMesh::stats() const {
  SubdivStats s;
  const SubdivTopology& t = *topo_;
  s.faces = t.faces();
  s.leaves = int(t.leaves.size());
  for (int f = 0; f < s.faces; ++f) {
    if (!t.hasLimit[size_t(f)]) ++s.facesWithoutLimit;
    else if (t.regularSlot[size_t(f)] >= 0) ++s.regularFaces;
    else ++s.irregularFaces;
  }
  return s;
}

int SubdivMesh::leafCount() const { return int(topo_->leaves.size()); }
std::pair<int, int> SubdivMesh::leafFace(int leaf) const { return topo_->leaves[size_t(leaf)]; }
std::vector<Vec3> SubdivMesh::controlPoints() const {
  std::vector<Vec3> out(impl_->points.size() / 3);
  for (size_t v = 0; v < out.size(); ++v) out[v] = {impl_->points[3 * v], impl_->points[3 * v + 1], impl_->points[3 * v + 2]};
  return out;
}

Vec3 SubdivMesh::vertexLimit(int v) const { return impl_->vertexLimit[size_t(v)]; }

Box3 SubdivMesh::leafBounds(int leaf) const { return impl_->faceBounds[size_t(topo_->leaves[size_t(leaf)].first)]; }

Box3 SubdivMesh::leafBoundsOver(int leaf, float u0, float u1, float v0, float v1) const {
  const int f = topo_->leaves[size_t(leaf)].first;
  const MeshView view{*topo_, *impl_};
  if (const BezierPatch* b = view.regular(f)) return b->boundsOver(u0, u1, v0, v1);
  // Bfr faces: a 3 x 3 grid of limit points over the rectangle (3 points along a degenerate
  // one, a border piece), whose cells the surface leaves by at most the bilinear
  // interpolation error h_s^2 |P_ss| / 8 + h_t^2 |P_tt| / 8. The second derivatives are taken
  // at the samples with a safety factor of 2 (Bfr's patches are piecewise polynomial with
  // smooth second derivatives over a leaf's small pieces), so this bound is sampled, not
  // proven; it is intersected with bounds(), which is proven. Tests check it by sampling.
  const BfrFace& bfr = faceCache().get(*topo_, *impl_, f);
  const int sub = topo_->leaves[size_t(leaf)].second;
  const LeafKind kind = topo_->leafKind(f);
  const int gs = u1 > u0 ? 2 : 0, gt = v1 > v0 ? 2 : 0;
  Box3 box;
  float mss = 0, mtt = 0;
  for (int j = 0; j <= gt; ++j)
    for (int i = 0; i <= gs; ++i) {
      float uv[2], d2[3];
      const float s = gs ? u0 + (u1 - u0) * float(i) / float(gs) : u0, t = gt ? v0 + (v1 - v0) * float(j) / float(gt) : v0;
      leafToFace(*topo_, f, sub, s, t, uv);
      box.extend(bfr.eval2(uv, d2));
      if (kind == LeafKind::Quad) {  // s = u, t = v
        mss = std::max(mss, d2[0]);
        mtt = std::max(mtt, d2[2]);
      } else {  // |d(u,v)/ds|, |d(u,v)/dt| <= 1/2 per component (sub-face tiles, triangle sub-quads)
        const float mixed = 0.25f * (d2[0] + 2.0f * d2[1] + d2[2]);
        mss = std::max(mss, mixed);
        mtt = std::max(mtt, mixed);
      }
    }
  const float hs = gs ? (u1 - u0) / float(gs) : 0.0f, ht = gt ? (v1 - v0) / float(gt) : 0.0f;
  const float margin = 2.0f * (hs * hs * mss + ht * ht * mtt) / 8.0f;
  box = box.grownBy(margin + bfr.evaluationError());
  const Box3 all = leafBounds(leaf);
  return {vmax(box.lo, all.lo), vmin(box.hi, all.hi)};
}

float SubdivMesh::leafSizeBound(int leaf) const { return impl_->leafSize[size_t(leaf)]; }
float SubdivMesh::leafErrorCoefficient(int leaf) const {
  return impl_->faceError[size_t(topo_->leaves[size_t(leaf)].first)];
}

std::vector<PatchPtr> makeSubdivPatches(const SubdivMeshDesc& desc) {
  return SubdivMesh::build(buildSubdivTopology(desc), desc.positions)->patches();
}

}  // namespace rayes
