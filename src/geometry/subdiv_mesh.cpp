#include "geometry/subdiv_mesh.h"
#include <algorithm>
#include <atomic>
#include <cmath>
#include <mutex>
#include <set>
#include <shared_mutex>
#include <unordered_map>
#include <unordered_set>
#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>
#include <opensubdiv/bfr/surfaceFactoryCache.h>
#include <opensubdiv/far/error.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>
#include <tbb/parallel_for.h>
#include "geometry/patch_math.h"
#include "geometry/subdiv_patch.h"

namespace rayes {

namespace Bfr = OpenSubdiv::Bfr;
namespace Far = OpenSubdiv::Far;
namespace Sdc = OpenSubdiv::Sdc;

namespace {

using ThreadedCache = Bfr::SurfaceFactoryCacheThreaded<std::shared_mutex, std::shared_lock<std::shared_mutex>,
                                                       std::unique_lock<std::shared_mutex>>;
using Factory = Bfr::RefinerSurfaceFactory<ThreadedCache>;
using PointDesc = Bfr::Surface<float>::PointDescriptor;

// Far reports topology errors through a process-wide callback. It is installed once and
// collects the messages of the calling thread while a refiner is being built.
thread_local std::string* tFarErrors = nullptr;

void farError(Far::ErrorType, const char* msg) {
  if (tFarErrors) {
    if (!tFarErrors->empty()) *tFarErrors += "; ";
    *tFarErrors += msg;
  } else {
    std::fprintf(stderr, "OpenSubdiv: %s\n", msg);
  }
}
void farWarning(const char* msg) {
  if (!tFarErrors) std::fprintf(stderr, "OpenSubdiv warning: %s\n", msg);
}

void installFarCallbacks() {
  static std::once_flag once;
  std::call_once(once, [] {
    Far::SetErrorCallback(farError);
    Far::SetWarningCallback(farWarning);
  });
}

std::atomic<uint64_t> gNextMeshId{1};

}  // namespace

// How a leaf's unit square maps onto its face's Bfr parameterisation.
enum class LeafKind : uint8_t { Quad, QuadSubface, TriSubquad };

class SubdivTopology {
 public:
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

  int faces() const { return int(faceOffset.size()) - 1; }
  int faceSize(int f) const { return faceOffset[f + 1] - faceOffset[f]; }
  LeafKind leafKind(int f) const {
    if (scheme == SubdivScheme::Loop) return LeafKind::TriSubquad;
    return faceSize(f) == 4 ? LeafKind::Quad : LeafKind::QuadSubface;
  }
  Bfr::Parameterization param(int f) const { return Bfr::Parameterization(sdcScheme, faceSize(f)); }
};

namespace {

void validate(const SubdivMeshDesc& d) {
  using Item = SubdivInputError::Item;
  const int nv = int(d.positions.size());
  if (nv == 0) throw SubdivInputError(Item::Mesh, -1, "the mesh has no vertices");
  for (int v = 0; v < nv; ++v)
    if (!isFinite(d.positions[v])) throw SubdivInputError(Item::Vertex, v, "vertex position is not finite");
  if (d.faceSizes.empty()) throw SubdivInputError(Item::Mesh, -1, "the mesh has no faces");
  size_t total = 0;
  for (int s : d.faceSizes) total += size_t(std::max(s, 0));
  if (total != d.faceVertices.size())
    throw SubdivInputError(Item::Mesh, -1, "face sizes do not add up to the number of face vertices");
  // Faces per undirected edge, and each directed edge once: a third face on an edge, or an edge
  // run twice in one direction, makes the mesh non-manifold there.
  std::unordered_map<uint64_t, int> edges;
  std::unordered_set<uint64_t> directed;
  int nonManifoldFace = -1, nonManifoldA = 0, nonManifoldB = 0;
  auto key = [](int a, int b) { return (uint64_t(uint32_t(std::min(a, b))) << 32) | uint32_t(std::max(a, b)); };
  size_t off = 0;
  for (int f = 0; f < int(d.faceSizes.size()); ++f) {
    const int n = d.faceSizes[f];
    if (n < 3) throw SubdivInputError(Item::Face, f, "a face needs at least 3 vertices");
    if (n > 64) throw SubdivInputError(Item::Face, f, "a face may have at most 64 vertices");
    if (d.scheme == SubdivScheme::Loop && n != 3)
      throw SubdivInputError(Item::Face, f,
                             "scheme 'loop' needs an all-triangle mesh; this face has " + std::to_string(n) + " vertices");
    for (int k = 0; k < n; ++k) {
      const int v = d.faceVertices[off + k];
      if (v < 0 || v >= nv)
        throw SubdivInputError(Item::Face, f,
                               "vertex index " + std::to_string(v) + " out of range (0.." + std::to_string(nv - 1) + ")");
      for (int k2 = 0; k2 < k; ++k2)
        if (d.faceVertices[off + k2] == v) throw SubdivInputError(Item::Face, f, "the face uses the same vertex twice");
      const int w = d.faceVertices[off + (k + 1) % n];
      const bool twice = !directed.insert((uint64_t(uint32_t(v)) << 32) | uint32_t(w)).second;
      if ((++edges[key(v, w)] > 2 || twice) && nonManifoldFace < 0) nonManifoldFace = f, nonManifoldA = v, nonManifoldB = w;
    }
    off += size_t(n);
  }
  // OpenSubdiv 3.5's Bfr reads out of bounds building the irregular patch of a face next to a
  // non-manifold edge when the mesh has sharp edges (IrregularPatchBuilder's sharp-edge pairs in
  // its overlapping-faces case; found by fuzz/obj_fuzz). Non-manifold meshes without creases and
  // creased manifold meshes (valence-2 vertices included) are fine, so only the pair is refused.
  if (!d.creases.empty() && nonManifoldFace >= 0)
    throw SubdivInputError(Item::Face, nonManifoldFace,
                           "creases need a manifold mesh, and this face makes edge " + std::to_string(nonManifoldA) +
                               "-" + std::to_string(nonManifoldB) +
                               " non-manifold (a third face on it, or a second in the same direction)");
  for (int c = 0; c < int(d.creases.size()); ++c) {
    const SubdivCrease& cr = d.creases[c];
    if (cr.v0 < 0 || cr.v0 >= nv || cr.v1 < 0 || cr.v1 >= nv)
      throw SubdivInputError(Item::Crease, c, "crease vertex index out of range (0.." + std::to_string(nv - 1) + ")");
    if (!edges.count(key(cr.v0, cr.v1)))
      throw SubdivInputError(Item::Crease, c,
                             "no edge joins vertices " + std::to_string(cr.v0) + " and " + std::to_string(cr.v1));
    if (!std::isfinite(cr.sharpness) || cr.sharpness < 0)
      throw SubdivInputError(Item::Crease, c, "crease sharpness must be finite and >= 0");
  }
  for (int c = 0; c < int(d.corners.size()); ++c) {
    const SubdivCorner& co = d.corners[c];
    if (co.v < 0 || co.v >= nv)
      throw SubdivInputError(Item::Corner, c, "corner vertex index out of range (0.." + std::to_string(nv - 1) + ")");
    if (!std::isfinite(co.sharpness) || co.sharpness < 0)
      throw SubdivInputError(Item::Corner, c, "corner sharpness must be finite and >= 0");
  }
  for (int h = 0; h < int(d.holes.size()); ++h)
    if (d.holes[h] < 0 || d.holes[h] >= int(d.faceSizes.size()))
      throw SubdivInputError(Item::Hole, h,
                             "hole face index out of range (0.." + std::to_string(d.faceSizes.size() - 1) + ")");
}

}  // namespace

std::shared_ptr<const SubdivTopology> buildSubdivTopology(const SubdivMeshDesc& d, bool regularAsBezier) {
  using Item = SubdivInputError::Item;
  validate(d);
  installFarCallbacks();
  auto topo = std::make_shared<SubdivTopology>();
  topo->scheme = d.scheme;
  topo->sdcScheme = d.scheme == SubdivScheme::Loop ? Sdc::SCHEME_LOOP : Sdc::SCHEME_CATMARK;
  topo->numVertices = int(d.positions.size());

  std::vector<int> creaseVerts, cornerVerts;
  std::vector<float> creaseW, cornerW;
  for (const auto& c : d.creases) {
    creaseVerts.push_back(c.v0);
    creaseVerts.push_back(c.v1);
    creaseW.push_back(c.sharpness);
  }
  for (const auto& c : d.corners) {
    cornerVerts.push_back(c.v);
    cornerW.push_back(c.sharpness);
  }
  Far::TopologyDescriptor desc;
  desc.numVertices = int(d.positions.size());
  desc.numFaces = int(d.faceSizes.size());
  desc.numVertsPerFace = d.faceSizes.data();
  desc.vertIndicesPerFace = d.faceVertices.data();
  desc.numCreases = int(d.creases.size());
  desc.creaseVertexIndexPairs = creaseVerts.data();
  desc.creaseWeights = creaseW.data();
  desc.numCorners = int(d.corners.size());
  desc.cornerVertexIndices = cornerVerts.data();
  desc.cornerWeights = cornerW.data();
  desc.numHoles = int(d.holes.size());
  desc.holeIndices = d.holes.data();

  Sdc::Options sdc;
  sdc.SetVtxBoundaryInterpolation(d.boundary == SubdivBoundary::None       ? Sdc::Options::VTX_BOUNDARY_NONE
                                  : d.boundary == SubdivBoundary::EdgeOnly ? Sdc::Options::VTX_BOUNDARY_EDGE_ONLY
                                                                           : Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER);
  sdc.SetFVarLinearInterpolation(Sdc::Options::FVAR_LINEAR_ALL);
  using RF = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
  std::string errors;
  tFarErrors = &errors;
  topo->refiner.reset(RF::Create(desc, RF::Options(topo->sdcScheme, sdc)));
  tFarErrors = nullptr;
  if (!topo->refiner || !errors.empty())
    throw SubdivInputError(Item::Mesh, -1,
                           std::string("OpenSubdiv rejects the topology: ") + (errors.empty() ? "(no reason given)" : errors));

  const Far::TopologyLevel& level = topo->refiner->GetLevel(0);
  const int nf = level.GetNumFaces();
  topo->faceOffset.assign(size_t(nf) + 1, 0);
  for (int f = 0; f < nf; ++f) {
    const auto fv = level.GetFaceVertices(f);
    const auto fe = level.GetFaceEdges(f);
    for (int k = 0; k < fv.size(); ++k) {
      topo->faceVerts.push_back(fv[k]);
      topo->faceEdges.push_back(fe[k]);
    }
    topo->faceOffset[size_t(f) + 1] = int(topo->faceVerts.size());
  }
  const int ne = level.GetNumEdges();
  topo->edgeVerts.resize(size_t(ne));
  for (int e = 0; e < ne; ++e) {
    const auto ev = level.GetEdgeVertices(e);
    topo->edgeVerts[size_t(e)] = {ev[0], ev[1]};
  }

  topo->factory = std::make_unique<Factory>(*topo->refiner, Bfr::SurfaceFactory::Options());
  // Which faces have a limit surface, and which are regular (16 distinct B-spline control
  // points: Bfr's regular interior case; regular boundary patches carry phantom points and
  // stay with Bfr).
  topo->hasLimit.assign(size_t(nf), 0);
  std::vector<std::array<int, 16>> cvs(static_cast<size_t>(nf));
  std::vector<uint8_t> isRegular(size_t(nf), 0);
  tbb::parallel_for(0, nf, [&](int f) {
    Bfr::Surface<float> s;
    if (!topo->factory->InitVertexSurface(f, &s)) return;
    topo->hasLimit[size_t(f)] = 1;
    if (!regularAsBezier || d.scheme != SubdivScheme::CatmullClark || !s.IsRegular() || s.GetNumControlPoints() != 16)
      return;
    std::array<int, 16> idx;
    s.GetControlPointIndices(idx.data());
    std::array<int, 16> sorted = idx;
    std::sort(sorted.begin(), sorted.end());
    if (sorted[0] < 0 || std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) return;
    cvs[size_t(f)] = idx;
    isRegular[size_t(f)] = 1;
  });
  topo->regularSlot.assign(size_t(nf), -1);
  for (int f = 0; f < nf; ++f)
    if (isRegular[size_t(f)]) {
      topo->regularSlot[size_t(f)] = int(topo->regularCVs.size());
      topo->regularCVs.push_back(cvs[size_t(f)]);
    }

  topo->edgeOwner.assign(size_t(ne), -1);
  topo->edgeOwnerLocal.assign(size_t(ne), -1);
  topo->vertexOwner.assign(size_t(topo->numVertices), -1);
  topo->vertexOwnerLocal.assign(size_t(topo->numVertices), -1);
  for (int f = 0; f < nf; ++f) {
    if (!topo->hasLimit[size_t(f)]) continue;
    const int n = topo->faceSize(f), o = topo->faceOffset[size_t(f)];
    for (int k = 0; k < n; ++k) {
      const int e = topo->faceEdges[size_t(o + k)], v = topo->faceVerts[size_t(o + k)];
      if (topo->edgeOwner[size_t(e)] < 0) topo->edgeOwner[size_t(e)] = f, topo->edgeOwnerLocal[size_t(e)] = k;
      if (topo->vertexOwner[size_t(v)] < 0) topo->vertexOwner[size_t(v)] = f, topo->vertexOwnerLocal[size_t(v)] = k;
    }
    if (topo->leafKind(f) == LeafKind::Quad) {
      topo->leaves.push_back({f, -1});
    } else {
      for (int k = 0; k < n; ++k) topo->leaves.push_back({f, k});
    }
  }
  if (topo->leaves.empty()) throw SubdivInputError(Item::Mesh, -1, "no face of the mesh has a limit surface");
  return topo;
}

// ---------------------------------------------------------------------------------------------

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

namespace {

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

BfrFaceCache& faceCache() {
  thread_local BfrFaceCache cache;
  return cache;
}

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

// Leaf (s, t) -> face coordinates of the face's Bfr parameterisation.
void leafToFace(const SubdivTopology& t, int f, int sub, float s, float tt, float uv[2]) {
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

}  // namespace

// ---------------------------------------------------------------------------------------------
// Evaluation helpers with access to the mesh internals.

namespace {

struct MeshView {
  const SubdivTopology& t;
  const SubdivMesh::Impl& m;

  const BezierPatch* regular(int f) const {
    const int s = t.regularSlot[size_t(f)];
    return s < 0 ? nullptr : &*m.regular[size_t(s)];
  }

  // The limit position of face f at face coordinates uv (the face's own evaluation).
  Vec3 facePosition(int f, const float uv[2]) const {
    if (const BezierPatch* b = regular(f)) return b->evaluate(uv[0], uv[1]).p;
    return faceCache().get(t, m, f).eval(uv).p;
  }

  // Point of mesh edge e at parameter x in [0,1] from its first vertex to its second: always
  // the owner's evaluation, so every leaf along the edge gets the same bits.
  Vec3 edgePoint(int e, float x) const {
    const auto ev = t.edgeVerts[size_t(e)];
    if (x == 0.0f) return m.vertexLimit[size_t(ev[0])];
    if (x == 1.0f) return m.vertexLimit[size_t(ev[1])];
    const int f = t.edgeOwner[size_t(e)], k = t.edgeOwnerLocal[size_t(e)];
    const float local = t.faceVerts[size_t(t.faceOffset[size_t(f)] + k)] == ev[0] ? x : 1.0f - x;
    float uv[2];
    t.param(f).GetEdgeCoord(k, local, uv);
    return facePosition(f, uv);
  }

  // Point of face f's local edge k at local parameter x (from vertex k to vertex k+1).
  Vec3 faceEdgePoint(int f, int k, float x) const {
    const int o = t.faceOffset[size_t(f)];
    const int e = t.faceEdges[size_t(o + k)];
    const bool forward = t.faceVerts[size_t(o + k)] == t.edgeVerts[size_t(e)][0];
    return edgePoint(e, forward ? x : 1.0f - x);
  }

  // Internal border j of a non-quad face: from the midpoint of its edge j (r = 0) to its
  // centre (r = 1), evaluated as sub-face j's side s = 1.
  Vec3 internalPoint(int f, int j, float r) const {
    if (r == 0.0f) return faceEdgePoint(f, j, 0.5f);
    if (r == 1.0f) return m.faceCenter[size_t(f)];
    float uv[2];
    leafToFace(t, f, j, 1.0f, r, uv);
    return facePosition(f, uv);
  }

  // Canonical position of a point on a leaf's border. side: 0: t=0, 1: s=1, 2: t=1, 3: s=0;
  // p: the parameter along the side (s for sides 0 and 2, t for 1 and 3).
  Vec3 sidePoint(int f, int sub, int side, float p) const {
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

  // The leaf's own evaluation (position and normal) at leaf coordinates.
  SurfacePoint own(int f, int sub, const BfrFace* bfr, float s, float tt) const {
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
};

}  // namespace

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

std::vector<PatchPtr> makeSubdivPatches(const SubdivMeshDesc& desc) {
  return SubdivMesh::build(buildSubdivTopology(desc), desc.positions)->patches();
}

}  // namespace rayes
