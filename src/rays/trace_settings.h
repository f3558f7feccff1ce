// Settings and statistics of the bottom-level / top-level tracing of one generation.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>
#include "core/timer.h"

namespace rayes {

enum class LodRule {
  PerRay,   // default: each ray's level from its own footprint (order independent)
  Density,  // thesis §6.1.2: smallest m with 4^m >= R/spp; ties the image to batching
  Fixed,    // every ray at maxLod: one geometry for every ray, as a full tessellation has (the
            // Embree engine's fixed level); for comparing integrators and making references
};

struct TraceSettings {
  int maxLod = 10;
  LodRule lod = LodRule::PerRay;
  // Added to every level the rule chooses, then clamped to [0, maxLod] (biasedLevel): negative
  // is coarser and faster, positive finer. A secondary ray still sees the leaf it leaves at the
  // level it hit it (that level already carries the bias).
  int lodBias = 0;
  static constexpr int kMaxLodBias = 12;  // |lodBias| beyond the finest level changes nothing
  // The finest level a dice buffer holds (--resident-lod; issue 33 item 2): a run of rays that
  // needs a leaf finer than this dices it as 4^d sub-leaves (geometry/sub_patch.h, d = the
  // excess), each at most at this level, the same micro-triangles for every ray. The per-thread
  // dice buffers are sized for min(maxLod, the effective level): SortedEngine::residentLevel,
  // which is never below kMinResidentLod (the thin seam regions end there) nor below
  // ceil(maxLod / 2) (each ray's level on a sub-leaf must stay >= 0).
  // 8, not 7, with sub-leaf grids cached too (history/2026-11.md, "Sub-leaf grids in the grid
  // cache"): against no split, R = 7 costs displaced-terrain +18 % CPU (teapot-field +11 %) for
  // 0.97x the peak of R = 8, which costs +4 % (+3 %) for 0.90x (0.98x) the peak of no split.
  static constexpr int kDefaultResidentLod = 8;
  static constexpr int kMinResidentLod = 6;
  int residentLod = kDefaultResidentLod;
  int samplesPerPixel = 1;          // only for LodRule::Density
  size_t candidateCapacity = 1 << 20;
  // N, the candidate leaves a ray gets per iteration, is capacity / active rays clipped to this
  // (--candidates-per-ray). The thesis clips at 100 (Table 6.3), so rays left active after the
  // first iteration -- through a canopy, past leaves whose boxes they cross without a hit --
  // got dozens of leaves at once, and every one was diced although the nearest few usually
  // held the hit. A small clip costs the other way once the grid cache cannot hold a leaf
  // from one iteration to the next: forest-100 dicings at N = 4 / 8 / 16 / 100 were 79 k /
  // 84 k / 91 k / 136 k at 480x192 1 spp, but 768 k / 664 k / 635 k / 679 k at 1920x768.
  // 8 is within 7 % of the fewest at both sizes (bench/RESULTS.md). Hits do not depend on it
  // (tests/rays/sorted_engine_test.cpp).
  static constexpr int kDefaultCandidatesPerRay = 8;
  int maxCandidatesPerRay = kDefaultCandidatesPerRay;
  // Bytes of diced grids the sorted pipeline keeps across iterations and generations
  // (rays/grid_cache.h); 0: every iteration dices every leaf it has rays for.
  size_t gridCacheBytes = 0;
  // Entries of the table of static dicings' border bounds kept across dicings
  // (dicing/border_bound_cache.h; 40 bytes each, allocated on first use; at most
  // SortedEngine::kBorderBoundsPerLeaf per leaf of the scene); 0: every dicing
  // computes its own. A displaced leaf's border radii cost more than its micro-polygons, and the
  // sorted pipeline re-dices a leaf in every iteration and generation that has rays for it.
  size_t borderBoundEntries = size_t(1) << 22;
  bool sortByLeaf = true;           // false: debug mode, every ray traced alone, unsorted
  // Crack-free level of detail: curved patches are also intersected as their conservative
  // border boxes (DiceBuffer::intersect). Off only to show, in tests, the slits it closes.
  bool closeBorders = true;
  // Test hook: replaces the level of ray `ray` (index in the batch) on `leaf`, given the level
  // the rule chose; the result is clamped to [0, maxLod]. Empty in renders.
  std::function<int(uint32_t ray, uint32_t leaf, int level)> levelHook;
};

struct IterationStats {
  uint64_t activeRays = 0;
  double candidatesPerRay = 0;  // N chosen for this iteration
  uint64_t candidates = 0;      // candidates actually recorded
  uint64_t dicings = 0;         // leaves diced in this iteration (cache hits not counted)
  uint64_t cacheHits = 0;       // leaves whose grid came from the grid cache
};

struct GenerationStats {
  uint64_t rays = 0;
  uint64_t shadowRays = 0;
  std::vector<IterationStats> iterations;
  uint64_t leavesDiced = 0;          // dicings (a moving leaf: one per time interval its rays need)
  uint64_t micropolygonsCreated = 0; // a moving leaf's dicing counts both of its time samples
  uint64_t movingDicings = 0;        // dicings of two time samples (motion blur)
  uint64_t borderHits = 0;           // rays whose hit lies in a border region (sorted pipeline)
  // Dicings whose rays all leave from that leaf: what the thesis's second optimisation
  // (§6.2.1: continuation rays intersected with their still-diced leaf) could save at most.
  uint64_t originLeafDicings = 0;
  uint64_t gridCacheHits = 0;        // leaf visits served by the grid cache instead of a dicing
  // Runs of rays that needed a leaf finer than the resident level, and the sub-leaves they
  // diced (each also one of leavesDiced, at its own level in dicingsByLevel).
  uint64_t splitRuns = 0;
  uint64_t subLeafDicings = 0;
  uint64_t subLeafCacheHits = 0;  // sub-leaf grids a split run took from the grid cache (also in gridCacheHits)
  // Dicings per level of detail m (4^m micro-quads), the sorted pipeline's; --max-lod is at most 12.
  static constexpr size_t kLevels = 13;
  std::array<uint64_t, kLevels> dicingsByLevel{};
};

// Times of the tracing stages. toplevel and sort are wall clock; dice and bottom are summed
// over threads (as in the thesis's Table 6.1), and so is leafQueries (the runners' per-leaf
// queries: caustic gathers, core/leaf_queries.h).
struct TraceTimes {
  TimeAccumulator toplevel, sort, dice, bottom, leafQueries;
};

}  // namespace rayes
