// A subdivision mesh's uv set (SubdivMeshDesc::uvs, the refiner's face-varying channel 0),
// evaluated at a leaf's (u, v) through OpenSubdiv Bfr's face-varying surfaces, with the
// interpolation the mesh chose (SubdivUvInterpolation: seams and creases of the uv set follow
// OpenSubdiv's rules). Depends on the topology only, so every transform and time sample of a
// shape shares one.
//
// Immutable; evaluate() is const and thread-safe: each thread keeps a few initialised
// face-varying surfaces with their patch points (a fixed-size, least-recently-used cache, as
// the vertex surfaces' BfrFaceCache), so hits shaded in (material, leaf) order pay Bfr's
// surface set-up once per face and thread. O(1) memory per thread; the set itself holds the
// uv values and (in the refiner) one index per face vertex.
#pragma once
#include <cstddef>
#include <memory>
#include "geometry/subdiv_mesh.h"

namespace rayes {

// Whether a topology carries a uv set.
bool hasUvSet(const SubdivTopology& topology);

class SubdivUvSet {
 public:
  // topology must carry a uv set (std::invalid_argument otherwise).
  explicit SubdivUvSet(std::shared_ptr<const SubdivTopology> topology);

  // Leaves in SubdivMesh::patches() order.
  int leafCount() const;
  // (s, t) at the leaf's parameters (u, v) in [0, 1]^2, and d(s, t)/du, d(s, t)/dv there.
  void evaluate(int leaf, float u, float v, float st[2], float dst_du[2], float dst_dv[2]) const;
  // The uv values and their per-face-vertex indices.
  size_t bytes() const;
  const SubdivTopology& topology() const { return *topo_; }

 private:
  std::shared_ptr<const SubdivTopology> topo_;
};

}  // namespace rayes
