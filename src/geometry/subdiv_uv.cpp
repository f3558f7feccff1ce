// The uv set of a subdivision mesh through Bfr's face-varying surfaces (subdiv_uv.h).
#include "geometry/subdiv_uv.h"
#include <stdexcept>
#include "geometry/subdiv_mesh_internal.h"

namespace rayes {
namespace {

// One face's face-varying surface with its patch points (uv values gathered and, at irregular
// corners, computed by Bfr), ready to evaluate.
struct UvFace {
  uint64_t topology = 0;
  int face = -1;
  uint64_t stamp = 0;
  bool ok = false;
  Bfr::Surface<float> surface;
  std::vector<float> points;

  void init(const SubdivTopology& t, int f) {
    topology = t.id;
    face = f;
    ok = t.factory->InitFaceVaryingSurface(f, &surface, 0);
    points.clear();
    if (!ok) return;
    points.resize(size_t(surface.GetNumPatchPoints()) * 2);
    surface.PreparePatchPoints(t.uvs.data(), PointDesc(2), points.data(), PointDesc(2));
  }
};

// Per thread, as BfrFaceCache: a hit's face and its neighbours' are often shaded in turn.
class UvFaceCache {
 public:
  static constexpr int kSlots = 8;
  const UvFace& get(const SubdivTopology& t, int f) {
    int victim = 0;
    for (int s = 0; s < kSlots; ++s) {
      if (slots_[s].topology == t.id && slots_[s].face == f) {
        slots_[s].stamp = ++clock_;
        return slots_[s];
      }
      if (slots_[s].stamp < slots_[victim].stamp) victim = s;
    }
    slots_[victim].init(t, f);
    slots_[victim].stamp = ++clock_;
    return slots_[victim];
  }

 private:
  UvFace slots_[kSlots];
  uint64_t clock_ = 0;
};

UvFaceCache& uvFaceCache() {
  thread_local UvFaceCache cache;
  return cache;
}

}  // namespace

bool hasUvSet(const SubdivTopology& topology) { return !topology.uvs.empty(); }

SubdivUvSet::SubdivUvSet(std::shared_ptr<const SubdivTopology> topology) : topo_(std::move(topology)) {
  if (!topo_ || !hasUvSet(*topo_)) throw std::invalid_argument("SubdivUvSet: the topology has no uv set");
}

int SubdivUvSet::leafCount() const { return int(topo_->leaves.size()); }

size_t SubdivUvSet::bytes() const {
  return topo_->uvs.capacity() * sizeof(float) + topo_->faceVerts.size() * sizeof(int);
}

void SubdivUvSet::evaluate(int leaf, float u, float v, float st[2], float dst_du[2], float dst_dv[2]) const {
  const SubdivTopology& t = *topo_;
  const auto [f, sub] = t.leaves[size_t(leaf)];
  // The leaf's square maps bilinearly (an affine map for quads and quad sub-faces) onto the
  // face's Bfr parameters: its Jacobian from the images of the square's corners.
  float c00[2], c10[2], c01[2], c11[2], uv[2];
  leafToFace(t, f, sub, 0, 0, c00);
  leafToFace(t, f, sub, 1, 0, c10);
  leafToFace(t, f, sub, 0, 1, c01);
  leafToFace(t, f, sub, 1, 1, c11);
  leafToFace(t, f, sub, u, v, uv);
  float dfdu[2], dfdv[2];
  for (int k = 0; k < 2; ++k) {
    dfdu[k] = (1 - v) * (c10[k] - c00[k]) + v * (c11[k] - c01[k]);
    dfdv[k] = (1 - u) * (c01[k] - c00[k]) + u * (c11[k] - c10[k]);
  }
  const UvFace& face = uvFaceCache().get(t, f);
  if (!face.ok) {  // Bfr gives every face with a limit surface a face-varying one; not reached
    st[0] = st[1] = dst_du[0] = dst_du[1] = dst_dv[0] = dst_dv[1] = 0;
    return;
  }
  float alongU[2], alongV[2];  // d(s, t) along the face's own parameters
  face.surface.Evaluate(uv, face.points.data(), PointDesc(2), st, alongU, alongV);
  for (int k = 0; k < 2; ++k) {
    dst_du[k] = alongU[k] * dfdu[0] + alongV[k] * dfdu[1];
    dst_dv[k] = alongU[k] * dfdv[0] + alongV[k] * dfdv[1];
  }
}

}  // namespace rayes
