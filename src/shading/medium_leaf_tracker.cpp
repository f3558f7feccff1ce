#include "shading/medium_leaf_tracker.h"
#include "shading/grid_reader.h"
#include "shading/ray_spawning.h"
#include "shading/shading_scene.h"

namespace rayes {

void BrickLeafTracker::setScene(const ShadingScene& scene) {
  scene_ = &scene;
  firstLeaf = scene.firstBrickLeaf;
  bricks = scene.bricks.total();
}

void BrickLeafTracker::prepare(size_t paths, std::function<RngKey(uint32_t slot)> keyOf) {
  product_.assign(paths, 0);
  tracked = false;
  keyOf_ = std::move(keyOf);
}

void BrickLeafTracker::track(uint32_t leaf, const RayBatch& b, std::span<const uint32_t> rays,
                             std::span<const float> limits, std::span<float> collisions) {
  ScopedTimer timer(time);
  const uint32_t global = leaf - firstLeaf;
  const BrickNumbering::Brick at = scene_->bricks.brickOf(global);
  const Medium& m = *scene_->media[at.medium];
  const bool delta = scene_->integrator.deltaTransmittance;
  // One reader for the run: the brick is looked up in the cache once, when the first tentative
  // collision of any of its rays lands, and held pinned until the run ends.
  GridReader reader(m.densityGrid(), scene_->volumeCache.get());
  TrackingCounts counts;
  uint64_t shadows = 0;
  for (size_t k = 0; k < rays.size(); ++k) {
    const uint32_t i = rays[k];
    const Ray& ray = b.ray[i];
    const IndexRay r = toIndex(m, ray.org, ray.dir);
    if (ray.kind == RayKind::Shadow) {
      const float T = brickTransmittance(m, at.brick, r, limits[k], delta,
                                         brickStream(keyOf_(i), kTransmittanceDimensions, global), counts, reader);
      TransmittanceProduct::add(product_[i / kRaysPerPath], TransmittanceProduct::term(T));
      ++shadows;
    } else {
      collisions[k] = brickCollision(m, at.brick, r, limits[k], brickStream(keyOf_(i), kFreeFlightDimensions, global),
                                     counts, reader);
    }
  }
  lookups.fetch_add(counts.lookups, std::memory_order_relaxed);
  cells.fetch_add(rays.size(), std::memory_order_relaxed);
  (void)shadows;
}

}  // namespace rayes
