// The path tracer's side of the brick leaves (core/medium_leaves.h): what the sorted engine
// runs for a run of rays of one brick leaf (a brick, or a block of them: BrickNumbering) — each
// closest ray's delta tracking and each shadow ray's ratio (or delta) tracking restricted to
// each of its bricks, with the brick's stream of each ray's vertex (shading/volume_tracking.h:
// brickCollision, brickTransmittance, brickStream, the one implementation the per-ray walk calls
// too). One GridReader per call, so a run's rays share one cache lookup of each brick's voxels
// (and its slot's apron, filled once from the neighbours).
//
// Owned by a PathBatch; the path tracer sets the vertex keys of the generation in flight before
// each trace (keyOf) and reads the shadow rays' products after it. Thread-safe: track() may run
// concurrently (the products are atomic TransmittanceProduct sums, the counts atomics).
// Memory: 8 bytes per path (its shadow ray's product), only in a scene with media.
#pragma once
#include <atomic>
#include <cstdint>
#include <functional>
#include <vector>
#include "core/medium_leaves.h"
#include "core/rng.h"
#include "core/timer.h"
#include "shading/volume_tracking.h"

namespace rayes {

struct ShadingScene;

class BrickLeafTracker final : public MediumLeafTracker {
 public:
  // The scene's media, their bricks numbered from leaf scene.firstBrickLeaf.
  void setScene(const ShadingScene& scene);
  // Before a trace: every path's product reset, `tracked` cleared, and the key of each ray
  // slot's vertex for this trace.
  void prepare(size_t paths, std::function<RngKey(uint32_t slot)> keyOf);
  void track(uint32_t leaf, const RayBatch& b, std::span<const uint32_t> rays, std::span<const float> limits,
             std::span<float> collisions) override;
  // Path k's shadow ray's transmittance after a tracked trace.
  float transmittance(uint32_t path) const { return TransmittanceProduct::valueOf(product_[path]); }

  // What the runs did since the last take (the shading stats' volume counts and time).
  std::atomic<uint64_t> lookups{0}, cells{0}, estimates{0};
  TimeAccumulator time;

 private:
  const ShadingScene* scene_ = nullptr;
  std::function<RngKey(uint32_t)> keyOf_;
  std::vector<uint64_t> product_;  // per path: TransmittanceProduct terms of its shadow ray
};

}  // namespace rayes
