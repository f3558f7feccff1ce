// The sorted pipeline's brick leaves (core/medium_leaves.h): a brick's run of rays handed to the
// batch's MediumLeafTracker at once, so the brick's voxels are looked up once per run (or per
// chunk of a long one) rather than once per ray, and each closest ray's collision offered as a
// hit on the brick's leaf, where it competes with surface hits under the total order like any
// hit. Shadow rays' transmittance the tracker keeps itself.
#include <atomic>
#include <limits>
#include <vector>
#include <tbb/enumerable_thread_specific.h>
#include "core/medium_leaves.h"
#include "rays/kept_hit.h"
#include "rays/run_chunks.h"
#include "rays/sorted_engine.h"

namespace rayes {
namespace {
constexpr float kInf = std::numeric_limits<float>::infinity();

struct BrickRunScratch {
  std::vector<uint32_t> rays;
  std::vector<float> limits, collisions;
};
}  // namespace

void SortedEngine::trackBrickRun(RayBatch& b, const uint32_t* slots, size_t count, uint32_t leaf) {
  MediumLeafTracker* tracker = b.media;
  if (!tracker || !tracker->tracked) return;  // no tracking asked: the brick is empty space
  static tbb::enumerable_thread_specific<BrickRunScratch> scratchOf;
  auto trackRange = [&](size_t k0, size_t k1) {
    BrickRunScratch& sc = scratchOf.local();
    sc.rays.clear();
    sc.limits.clear();
    for (size_t k = k0; k < k1; ++k) {
      const uint32_t i = rayOfSlot(slots[k]);
      // A shadow ray already occluded is left out (its contribution is 0 whatever its
      // transmittance); a closest ray searches up to the hit offered so far.
      float limit;
      if (b.ray[i].kind == RayKind::Shadow) {
        if (std::atomic_ref<uint32_t>(b.occluderOf(i)).load(std::memory_order_relaxed) != kNoLeaf) continue;
        limit = b.ray[i].tmax;
      } else {
        limit = searchLimit(b, i, std::atomic_ref<float>(b.hitOf(i).t).load(std::memory_order_relaxed));
      }
      sc.rays.push_back(i);
      sc.limits.push_back(limit);
    }
    sc.collisions.assign(sc.rays.size(), kInf);
    tracker->track(leaf, b, sc.rays, sc.limits, sc.collisions);
    for (size_t k = 0; k < sc.rays.size(); ++k) {
      if (!(sc.collisions[k] < kInf)) continue;
      RayHit h;
      h.t = sc.collisions[k];
      h.leaf = leaf;
      offerHit(b, sc.rays[k], h, nullptr);
    }
  };
  forRunChunks(count, trackRange);
}

}  // namespace rayes
