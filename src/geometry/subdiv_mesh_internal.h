// Internals shared by the files of the subdivision mesh, one job each:
//   subdiv_topology.cpp  checking a SubdivMeshDesc and building the SubdivTopology;
//   subdiv_mesh.cpp      the SubdivMesh built on it: Bfr surfaces, regular faces in Bézier form,
//                        limit points, bounds and sizes;
//   subdiv_seams.cpp     canonical evaluation of leaf borders, so that neighbours match bit for bit;
//   subdiv_dice.cpp      a leaf's own evaluation and its dicing (borders from the seams).
// Here: the topology's tables, the mesh's per-face data, a face's Bfr surface and the per-thread
// cache of them, the leaf -> face parameter map, and the MeshView that evaluates leaves. Include
// it only from those files (subdiv_mesh.h is the interface).
#pragma once
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <shared_mutex>
#include <utility>
#include <vector>
#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>
#include <opensubdiv/bfr/surfaceFactoryCache.h>
#include <opensubdiv/far/topologyRefiner.h>
#include "geometry/bezier_patch.h"
#include "geometry/patch_math.h"
#include "geometry/subdiv_mesh.h"

namespace rayes {

namespace Bfr = OpenSubdiv::Bfr;
namespace Far = OpenSubdiv::Far;
namespace Sdc = OpenSubdiv::Sdc;

using ThreadedCache = Bfr::SurfaceFactoryCacheThreaded<std::shared_mutex, std::shared_lock<std::shared_mutex>,
                                                       std::unique_lock<std::shared_mutex>>;
using Factory = Bfr::RefinerSurfaceFactory<ThreadedCache>;
using PointDesc = Bfr::Surface<float>::PointDescriptor;

// How a leaf's unit square maps onto its face's Bfr parameterisation.
enum class LeafKind : uint8_t { Quad, QuadSubface, TriSubquad };

// subdiv_mesh.h's second layer, as buildSubdivTopology (subdiv_topology.cpp) fills it.
class SubdivTopology {
 public:
  uint64_t id = 0;  // process-unique: keys per-thread caches (subdiv_uv.cpp)
  SubdivScheme scheme = SubdivScheme::CatmullClark;
  Sdc::SchemeType sdcScheme = Sdc::SCHEME_CATMARK;
  std::unique_ptr<Far::TopologyRefiner> refiner;
  std::unique_ptr<Factory> factory;
  int numVertices = 0;
  std::vector<int> faceOffset;   // into faceVerts / faceEdges; size faces + 1
  std::vector<int> faceVerts;
  std::vector<int> faceEdges;    // Far edge k of a face joins its vertices k and k+1
  std::vector<uint8_t> hasLimit;
  std::vector<int> regularSlot;  // -1, or the index of the face's 16 B-spline control points
  std::vector<std::array<int, 16>> regularCVs;
  std::vector<std::array<int, 2>> edgeVerts;
  std::vector<int> edgeOwner, edgeOwnerLocal;      // face with a limit surface, its local edge
  std::vector<int> vertexOwner, vertexOwnerLocal;  // likewise for vertices
  std::vector<std::pair<int, int>> leaves;          // (face, sub-face or -1)
  // The uv set's values, s t per value (empty: none); its indices are the refiner's
  // face-varying channel 0.
  std::vector<float> uvs;
  // What the description said beyond faces, positions and uvs (scheme, boundary, creases,
  // corners, holes, uv interpolation; its vectors of faces, positions and uvs left empty), and
  // the regularAsBezier it was built with: with the tables above, the description again
  // (describeTopology), for a compiled scene.
  SubdivMeshDesc tags;
  bool regularAsBezier = true;

  int faces() const { return int(faceOffset.size()) - 1; }
  int faceSize(int f) const { return faceOffset[f + 1] - faceOffset[f]; }
  LeafKind leafKind(int f) const {
    if (scheme == SubdivScheme::Loop) return LeafKind::TriSubquad;
    return faceSize(f) == 4 ? LeafKind::Quad : LeafKind::QuadSubface;
  }
  Bfr::Parameterization param(int f) const { return Bfr::Parameterization(sdcScheme, faceSize(f)); }
};

// What SubdivMesh::build (subdiv_mesh.cpp) computes from the control points.
struct SubdivMesh::Impl {
  uint64_t id = 0;
  std::vector<float> points;  // x y z per vertex
  std::vector<Vec3> vertexLimit;
  std::vector<Vec3> faceCenter;  // non-quad faces
  std::vector<std::optional<BezierPatch>> regular;  // by regular slot
  std::vector<Box3> faceBounds;
  std::vector<float> faceError;
  std::vector<float> leafSize;
  std::vector<float> faceTiny;  // degenerate-normal threshold
};

// A face's Bfr surface with its patch points, ready to evaluate.
struct BfrFace {
  uint64_t mesh = 0;
  int face = -1;
  uint64_t stamp = 0;
  Bfr::Surface<float> surface;
  std::vector<float> points;  // relative to anchor: Bfr's blends round at the face's own scale
  Box3 hull;                  // of the patch points (absolute)
  Vec3 anchor;                // the hull's centre
  float anchoredMagnitude = 0;

  void init(const SubdivTopology& t, const SubdivMesh::Impl& m, int f) {
    mesh = m.id;
    face = f;
    t.factory->InitVertexSurface(f, &surface);
    points.resize(size_t(surface.GetNumPatchPoints()) * 3);
    surface.PreparePatchPoints(m.points.data(), PointDesc(3), points.data(), PointDesc(3));
    hull = Box3{};
    for (size_t k = 0; k + 2 < points.size(); k += 3) hull.extend(Vec3{points[k], points[k + 1], points[k + 2]});
    anchor = hull.center();
    anchoredMagnitude = 0;
    for (size_t k = 0; k < points.size(); ++k) {
      points[k] -= anchor[int(k % 3)];
      anchoredMagnitude = std::max(anchoredMagnitude, std::fabs(points[k]));
    }
  }
  // Rounding of a limit point: a blend of the N patch points (anchored) with weights whose
  // absolute sum we take as at most 4 (B-spline weights are positive and sum to 1; Gregory
  // patches at extraordinary vertices mix in negative ones): gamma(2N) * 4 * the anchored
  // magnitude -- an estimate from the evaluation's form, not a proof over Bfr's code.
  float evaluationError() const {
    return gammaBound(2 * surface.GetNumPatchPoints()) * 4.0f * anchoredMagnitude;
  }
  // Position and dP/du x dP/dv at face coordinates.
  SurfacePoint eval(const float uv[2]) const {
    float P[3], Du[3], Dv[3];
    surface.Evaluate(uv, points.data(), PointDesc(3), P, Du, Dv);
    return {anchor + Vec3{P[0], P[1], P[2]}, cross(Vec3{Du[0], Du[1], Du[2]}, Vec3{Dv[0], Dv[1], Dv[2]})};
  }
  // Position and the magnitudes of the second derivatives (uu, uv, vv) at face coordinates.
  Vec3 eval2(const float uv[2], float second[3]) const {
    float P[3], Du[3], Dv[3], Duu[3], Duv[3], Dvv[3];
    surface.Evaluate(uv, points.data(), PointDesc(3), P, Du, Dv, Duu, Duv, Dvv);
    second[0] = length(Vec3{Duu[0], Duu[1], Duu[2]});
    second[1] = length(Vec3{Duv[0], Duv[1], Duv[2]});
    second[2] = length(Vec3{Dvv[0], Dvv[1], Dvv[2]});
    return anchor + Vec3{P[0], P[1], P[2]};
  }
};

// Per-thread cache of initialised Bfr surfaces: a dicing needs its own face and up to four
// edge owners; neighbouring leaves are often diced by the same thread in turn. Fixed size
// (docs/design.md, invariant 3), least recently used replaced. Keyed by a process-unique mesh id, so a
// new mesh at a freed mesh's address never sees stale surfaces.
class BfrFaceCache {
 public:
  static constexpr int kSlots = 8;
  const BfrFace& get(const SubdivTopology& t, const SubdivMesh::Impl& m, int f) {
    int victim = 0;
    for (int s = 0; s < kSlots; ++s) {
      if (slots_[s].mesh == m.id && slots_[s].face == f) {
        slots_[s].stamp = ++clock_;
        return slots_[s];
      }
      if (slots_[s].stamp < slots_[victim].stamp) victim = s;
    }
    slots_[victim].init(t, m, f);
    slots_[victim].stamp = ++clock_;
    return slots_[victim];
  }

 private:
  BfrFace slots_[kSlots];
  uint64_t clock_ = 0;
};

BfrFaceCache& faceCache();  // this thread's (subdiv_mesh.cpp)

// Leaf (s, t) -> face coordinates of the face's Bfr parameterisation.
inline void leafToFace(const SubdivTopology& t, int f, int sub, float s, float tt, float uv[2]) {
  switch (t.leafKind(f)) {
    case LeafKind::Quad:
      uv[0] = s;
      uv[1] = tt;
      return;
    case LeafKind::QuadSubface: {
      const float st[2] = {s, tt};
      t.param(f).ConvertNormalizedSubFaceToCoord(sub, st, uv);
      return;
    }
    case LeafKind::TriSubquad: {
      // Corners: vertex sub, midpoint of edge sub, centroid, midpoint of edge sub-1.
      static const float V[3][2] = {{0, 0}, {1, 0}, {0, 1}};
      const int a = sub, b = (sub + 1) % 3, c = (sub + 2) % 3;
      const float c0[2] = {V[a][0], V[a][1]};
      const float c1[2] = {0.5f * (V[a][0] + V[b][0]), 0.5f * (V[a][1] + V[b][1])};
      const float c2[2] = {1.0f / 3.0f, 1.0f / 3.0f};
      const float c3[2] = {0.5f * (V[a][0] + V[c][0]), 0.5f * (V[a][1] + V[c][1])};
      for (int x = 0; x < 2; ++x)
        uv[x] = (1 - s) * (1 - tt) * c0[x] + s * (1 - tt) * c1[x] + s * tt * c2[x] + (1 - s) * tt * c3[x];
      return;
    }
  }
}

// A mesh's leaves evaluated: the leaf's own points, and the canonical points of its borders
// (subdiv_seams.cpp), which every leaf sharing a border takes from the same owner.
struct MeshView {
  const SubdivTopology& t;
  const SubdivMesh::Impl& m;

  const BezierPatch* regular(int f) const {
    const int s = t.regularSlot[size_t(f)];
    return s < 0 ? nullptr : &*m.regular[size_t(s)];
  }

  // The limit position of face f at face coordinates uv (the face's own evaluation).
  Vec3 facePosition(int f, const float uv[2]) const;
  // Point of mesh edge e at parameter x in [0,1] from its first vertex to its second: always
  // the owner's evaluation, so every leaf along the edge gets the same bits.
  Vec3 edgePoint(int e, float x) const;
  // Point of face f's local edge k at local parameter x (from vertex k to vertex k+1).
  Vec3 faceEdgePoint(int f, int k, float x) const;
  // Internal border j of a non-quad face: from the midpoint of its edge j (r = 0) to its
  // centre (r = 1), evaluated as sub-face j's side s = 1.
  Vec3 internalPoint(int f, int j, float r) const;
  // Canonical position of a point on a leaf's border. side: 0: t=0, 1: s=1, 2: t=1, 3: s=0;
  // p: the parameter along the side (s for sides 0 and 2, t for 1 and 3).
  Vec3 sidePoint(int f, int sub, int side, float p) const;
  // The leaf's own evaluation (position and normal) at leaf coordinates (subdiv_dice.cpp).
  SurfacePoint own(int f, int sub, const BfrFace* bfr, float s, float tt) const;
};

}  // namespace rayes
