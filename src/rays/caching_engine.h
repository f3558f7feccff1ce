// The thesis's alternative to reordering (§6.2.2, Table 6.2): rays traced one at a time in batch
// order, without sorting, each walking the top level front to back; the diced grids are kept in
// a least-recently-used cache of K entries, so a patch is re-diced only when it fell out of the
// cache (or a ray needs it finer than it is held). It exists to count dicings against the
// SortedEngine's reordering (--dice-cache K); it is not a fast engine.
//
// Hits: the SortedEngine's traceRayAlone, so every hit is the SortedEngine's (a pure function of
// ray, scene and maxLod under per-ray LOD): a grid diced at level m holds every coarser level
// exactly.
// Determinism: rays are traced sequentially in batch order, on one thread, so the cache's
// history, hence the dicing, hit and miss counts, are the same for every thread count. (Per-thread
// caches would make the counts depend on which thread took which rays.)
// Memory: the entries (each a DiceBuffer sized for the level it holds) and nothing per ray.
#pragma once
#include <cstdint>
#include <list>
#include <memory>
#include <unordered_map>
#include <vector>
#include "rays/ray_engine.h"
#include "rays/sorted_engine.h"

namespace rayes {

class CachingEngine : public RayEngine {
 public:
  // entries >= 1 (std::invalid_argument otherwise).
  CachingEngine(const TopLevelBvh& top, const LeafSource& leaves, const TraceSettings& settings,
                size_t entries);

  void trace(RayBatch& batch, GenerationStats& stats, TraceTimes& times) override;
  size_t bytesPerRay() const override { return bytesPerRaySlot(); }
  size_t fixedBytes() const override { return bytes_; }
  EngineStats engineStats() const override;

  static constexpr size_t bytesPerRaySlot() { return sizeof(uint32_t); }  // the active list
  uint64_t hits() const { return hits_; }
  uint64_t misses() const { return misses_; }  // = dicings
  size_t peakBytes() const { return peakBytes_; }

 private:
  struct Entry {
    uint64_t key;  // leaf << 32 | time interval
    std::unique_ptr<DiceBuffer> grid;
    PatchPtr patch;  // the patch the grid was diced from: its queries read it (border radii), and
                     // a generated leaf's patch would die with the ray that made it
  };
  // The grid of (leaf, interval) at `level` or finer: from the cache (moved to the front), or
  // diced into the entry it had, the least recently used one, or a new one.
  const DiceBuffer& gridFor(uint32_t leaf, const PatchPtr& patch, int interval, int level, GenerationStats& stats, TraceTimes& times);
  void diceInto(Entry& e, const PatchPtr& patch, int interval, int level, GenerationStats& stats, TraceTimes& times);

  SortedEngine sorted_;  // its per-ray walk (levels, border regions); its candidate buffer holds one slot
  size_t capacity_;
  std::list<Entry> lru_;  // front: most recently used
  std::unordered_map<uint64_t, std::list<Entry>::iterator> index_;
  std::vector<uint32_t> active_;
  TraversalScratch scratch_;
  LeafQueryRuns queries_;
  uint64_t hits_ = 0, misses_ = 0;
  size_t bytes_ = 0, peakBytes_ = 0;
};

}  // namespace rayes
