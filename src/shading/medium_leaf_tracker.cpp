#include "shading/medium_leaf_tracker.h"
#include <algorithm>
#include "shading/grid_reader.h"
#include "shading/ray_spawning.h"
#include "shading/shading_scene.h"

namespace rayes {

void BrickLeafTracker::setScene(const ShadingScene& scene) {
  scene_ = &scene;
  firstLeaf = scene.firstBrickLeaf;
  bricks = scene.bricks.leaves();
}

void BrickLeafTracker::prepare(size_t paths, std::function<RngKey(uint32_t slot)> keyOf) {
  product_.assign(paths, 0);
  tracked = false;
  keyOf_ = std::move(keyOf);
}

void BrickLeafTracker::track(uint32_t leaf, const RayBatch& b, std::span<const uint32_t> rays,
                             std::span<const float> limits, std::span<float> collisions) {
  ScopedTimer timer(time);
  const uint32_t l = leaf - firstLeaf;
  const Medium& m = *scene_->media[scene_->bricks.mediumOfLeaf(l)];
  const bool delta = scene_->integrator.deltaTransmittance;
  // One reader for the run: each brick is looked up in the cache once, when the first tentative
  // collision of any of the run's rays lands in it, and held pinned while its rays are tracked.
  GridReader reader(m.densityGrid(), scene_->volumeCache.get());
  TrackingCounts counts;
  const std::span<const uint32_t> leafBricks = scene_->bricks.bricksOfLeaf(l);
  // Brick by brick (a leaf of several bricks keeps one pinned at a time), each ray with the
  // brick's own stream: a closest ray's collision is the minimum over the bricks, searched in
  // each only up to the nearest found so far; a shadow ray's factors multiply.
  for (const uint32_t global : leafBricks) {
    const int32_t brick = scene_->bricks.brickOf(global).brick;
    for (size_t k = 0; k < rays.size(); ++k) {
      const uint32_t i = rays[k];
      const Ray& ray = b.ray[i];
      const IndexRay r = toIndex(m, ray.org, ray.dir());
      if (ray.kind == RayKind::Shadow) {
        const float T = brickTransmittance(m, brick, r, limits[k], delta,
                                           brickStream(keyOf_(i), kTransmittanceDimensions, global), counts, reader);
        TransmittanceProduct::add(product_[i / kRaysPerPath], TransmittanceProduct::term(T));
      } else {
        const float t = brickCollision(m, brick, r, std::min(limits[k], collisions[k]),
                                       brickStream(keyOf_(i), kFreeFlightDimensions, global), counts, reader);
        collisions[k] = std::min(collisions[k], t);
      }
    }
  }
  lookups.fetch_add(counts.lookups, std::memory_order_relaxed);
  cells.fetch_add(rays.size() * leafBricks.size(), std::memory_order_relaxed);
}

}  // namespace rayes
