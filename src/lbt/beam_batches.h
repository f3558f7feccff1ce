// Beams that do not fit --beam-memory at once (docs/design.md, "Light beam tracing", As built):
// the seed triangles are cut into ranges whose segments and bins each fit, and every batch of
// camera paths is traced once per range, the range's BeamStore built before and freed after.
// At a diffuse vertex the gather continues, in segment order, the sum the previous ranges left
// for that (path, bounce), so the last run holds exactly the sum a single store would have
// made (BeamStore::gather counts the same segments whatever shares the store): the image is
// bit-identical to the unbatched one. Only the last run's paths are written to the film.
#pragma once
#include <vector>
#include "lbt/beam_store.h"

namespace rayes {

class BeamBatches final : public CausticRadiance {
 public:
  // paths: the most paths in one camera batch; bounces: the path tracer's maxDepth.
  BeamBatches(size_t paths, int bounces) : stride_(size_t(std::max(bounces, 1))), partial_(paths * stride_) {}
  // Before the first range of a camera batch: every partial sum back to zero.
  void startPaths() { std::fill(partial_.begin(), partial_.end(), Rgb{}); }
  void use(const BeamStore* store) { store_ = store; }
  // Called for one path by one thread at a time: (path, bounce) slots are never shared.
  Rgb radiance(const DiffuseVertex& v) const override {
    const size_t slot = size_t(v.path) * stride_ + std::min<size_t>(v.bounce, stride_ - 1);
    if (!store_ || slot >= partial_.size()) return {};
    partial_[slot] = store_->radiance(v, partial_[slot]);
    return partial_[slot];
  }
  size_t bytes() const { return partial_.size() * sizeof(Rgb); }
  static size_t bytesFor(size_t paths, int bounces) { return paths * size_t(std::max(bounces, 1)) * sizeof(Rgb); }

 private:
  size_t stride_;
  mutable std::vector<Rgb> partial_;
  const BeamStore* store_ = nullptr;
};

}  // namespace rayes
