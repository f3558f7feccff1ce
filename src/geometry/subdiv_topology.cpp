// Subdivision topology: checking a SubdivMeshDesc (every index, face, crease, corner and hole,
// with the item at fault named for the reader) and building the SubdivTopology from it: the
// OpenSubdiv refiner and Bfr surface factory, which faces have a limit surface and which are
// regular, the owner of every edge and vertex (subdiv_seams.cpp evaluates through them), and the
// leaves. Nothing here depends on positions.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <opensubdiv/far/error.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>
#include <tbb/parallel_for.h>
#include "geometry/subdiv_mesh_internal.h"

namespace rayes {

namespace {

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

// A uv set: one value index per face vertex, in range, and finite values (a NaN would reach
// every texture lookup on the faces using it).
void validateUvs(const SubdivMeshDesc& d) {
  using Item = SubdivInputError::Item;
  if (d.uvs.empty() && d.uvIndices.empty()) return;
  if (d.uvs.empty()) throw SubdivInputError(Item::Mesh, -1, "the mesh has uv indices but no uv values");
  const int nuv = int(d.uvs.size());
  for (int k = 0; k < nuv; ++k)
    if (!std::isfinite(d.uvs[size_t(k)][0]) || !std::isfinite(d.uvs[size_t(k)][1]))
      throw SubdivInputError(Item::Uv, k, "uv value is not finite");
  if (d.uvIndices.size() != d.faceVertices.size())
    throw SubdivInputError(Item::Mesh, -1,
                           "the mesh has " + std::to_string(d.uvIndices.size()) + " uv indices for " +
                               std::to_string(d.faceVertices.size()) + " face vertices (one per face vertex)");
  size_t off = 0;
  for (int f = 0; f < int(d.faceSizes.size()); ++f) {
    for (int k = 0; k < d.faceSizes[size_t(f)]; ++k) {
      const int i = d.uvIndices[off + size_t(k)];
      if (i < 0 || i >= nuv)
        throw SubdivInputError(Item::UvFace, f,
                               "uv index " + std::to_string(i) + " out of range (0.." + std::to_string(nuv - 1) + ")");
    }
    off += size_t(d.faceSizes[size_t(f)]);
  }
}

Sdc::Options::FVarLinearInterpolation fvarInterpolation(SubdivUvInterpolation i) {
  switch (i) {
    case SubdivUvInterpolation::None: return Sdc::Options::FVAR_LINEAR_NONE;
    case SubdivUvInterpolation::CornersOnly: return Sdc::Options::FVAR_LINEAR_CORNERS_ONLY;
    case SubdivUvInterpolation::CornersPlus1: return Sdc::Options::FVAR_LINEAR_CORNERS_PLUS1;
    case SubdivUvInterpolation::CornersPlus2: return Sdc::Options::FVAR_LINEAR_CORNERS_PLUS2;
    case SubdivUvInterpolation::Boundaries: return Sdc::Options::FVAR_LINEAR_BOUNDARIES;
    case SubdivUvInterpolation::All: return Sdc::Options::FVAR_LINEAR_ALL;
  }
  return Sdc::Options::FVAR_LINEAR_ALL;
}

std::atomic<uint64_t> gNextTopologyId{1};

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
  validateUvs(d);
}

}  // namespace

std::shared_ptr<const SubdivTopology> buildSubdivTopology(const SubdivMeshDesc& d, bool regularAsBezier) {
  using Item = SubdivInputError::Item;
  validate(d);
  installFarCallbacks();
  auto topo = std::make_shared<SubdivTopology>();
  topo->id = gNextTopologyId++;
  topo->scheme = d.scheme;
  topo->sdcScheme = d.scheme == SubdivScheme::Loop       ? Sdc::SCHEME_LOOP
                    : d.scheme == SubdivScheme::Bilinear ? Sdc::SCHEME_BILINEAR
                                                         : Sdc::SCHEME_CATMARK;
  topo->numVertices = int(d.positions.size());
  topo->tags.scheme = d.scheme;
  topo->tags.boundary = d.boundary;
  topo->tags.creases = d.creases;
  topo->tags.corners = d.corners;
  topo->tags.holes = d.holes;
  topo->tags.uvInterpolation = d.uvInterpolation;
  topo->regularAsBezier = regularAsBezier;

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
  Far::TopologyDescriptor::FVarChannel uvChannel;
  if (!d.uvs.empty()) {
    uvChannel.numValues = int(d.uvs.size());
    uvChannel.valueIndices = d.uvIndices.data();
    desc.numFVarChannels = 1;
    desc.fvarChannels = &uvChannel;
    topo->uvs.reserve(d.uvs.size() * 2);
    for (const auto& st : d.uvs) topo->uvs.insert(topo->uvs.end(), st.begin(), st.end());
  }

  Sdc::Options sdc;
  sdc.SetVtxBoundaryInterpolation(d.boundary == SubdivBoundary::None       ? Sdc::Options::VTX_BOUNDARY_NONE
                                  : d.boundary == SubdivBoundary::EdgeOnly ? Sdc::Options::VTX_BOUNDARY_EDGE_ONLY
                                                                           : Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER);
  sdc.SetFVarLinearInterpolation(fvarInterpolation(d.uvInterpolation));
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

}  // namespace rayes

namespace rayes {

SubdivMeshDesc describeTopology(const SubdivTopology& t) {
  SubdivMeshDesc d = t.tags;
  d.positions.assign(size_t(t.numVertices), Vec3{});
  const int nf = t.faces();
  d.faceSizes.resize(size_t(nf));
  for (int f = 0; f < nf; ++f) d.faceSizes[size_t(f)] = t.faceSize(f);
  d.faceVertices = t.faceVerts;
  if (!t.uvs.empty()) {
    d.uvs.resize(t.uvs.size() / 2);
    for (size_t k = 0; k < d.uvs.size(); ++k) d.uvs[k] = {t.uvs[2 * k], t.uvs[2 * k + 1]};
    const Far::TopologyLevel& level = t.refiner->GetLevel(0);
    d.uvIndices.reserve(d.faceVertices.size());
    for (int f = 0; f < nf; ++f) {
      const auto fv = level.GetFaceFVarValues(f, 0);
      for (int k = 0; k < fv.size(); ++k) d.uvIndices.push_back(fv[k]);
    }
  }
  return d;
}

bool builtRegularAsBezier(const SubdivTopology& t) { return t.regularAsBezier; }

}  // namespace rayes
