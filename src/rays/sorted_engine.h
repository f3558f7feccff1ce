// START HERE for the pipeline. The SortedEngine traces one generation of rays (a RayBatch) through
// both levels, in iterations (thesis §6.2):
//
//   1. toplevel   every active ray collects up to N candidate leaves, front to back, resuming
//                 after the last leaf it got in the previous iteration; N = capacity / active.
//                 A candidate slot is the leaf id alone (4 bytes).
//   2. sort       the candidate slots are grouped by leaf (CandidateSort).
//   3. dice       one oneTBB task per leaf dices the patch at the finest level its rays need
//                 into this thread's DiceBuffer, or takes it from the GridCache (a static leaf
//                 diced in an earlier iteration or generation of the batch at that level or
//                 finer; rays/grid_cache.h, --grid-cache), and
//   4. bottom     intersects every ray at its own level, searching up to the ray's best hit of
//                 the previous iterations, and offers each hit to the ray's RayHit: kept when
//                 nearer under nearerHit's total order (t, leaf, micro-quad; t clamped to at
//                 least the ray's entry into the leaf's box, see keptDistance), under a per-ray
//                 lock because two leaves of a ray may finish at once on two threads.
//                 A slot whose leaf cannot beat what another leaf already offered (its box
//                 entry lies beyond that hit; a shadow ray occluded by a smaller leaf id) is
//                 skipped, and a hit offered so far bounds the search: either way only losers
//                 are dropped, so the kept hit is the same (6 % of a forest's closest-hit slots,
//                 13 % of its shadow slots).
//   5. finish     a ray is finished once its hit is nearer than its next candidate's entry
//                 distance; the others stay active with more candidates each.
//
// Leaf queries (core/leaf_queries.h, the caustic gathers of light beams) are grouped by leaf
// with the same sort and run in the first iteration's per-leaf stage, in the task of their
// leaf next to its rays, or in a task of their own on a leaf no ray reaches; with no rays to
// trace (the last gathers of a batch) or rays traced alone they run in a plain parallel loop.
//
// The Rayes implementation of RayEngine (rays/ray_engine.h).
//
// Guarantees: the hit of every ray is a pure function of (ray, scene, maxLod) under the
// default per-ray LOD: independent of thread count, sort order, N and batch size (the hit kept
// is the minimum of a total order, whatever order the offers come in). Shadow rays stop at
// their first occluder. Memory: the candidate buffer with its sort (bytesPerCandidate() per
// slot of fixed capacity, and the sort's scratch in the batch's RayBatch::sortScratch,
// sortScratchBytesPerRaySlot()), per-ray state (bytesPerRayState() per ray of the largest batch) and
// one DiceBuffer per thread of the resident level (residentLevel(): a run needing a leaf finer
// dices it as sub-leaves, rays/sub_leaf_runs.cpp), allocated on first use and kept, plus the grid
// cache of whole leaves and sub-leaves (bounded by TraceSettings::gridCacheBytes; fixedBytes()
// counts its peak). Not thread-safe: one trace() at
// a time; trace() itself is parallel.
//
// Motion blur (thesis §6.3): a leaf whose patch has K > 1 time samples has its rays regrouped,
// within the leaf's run, by the time interval [t_i, t_i+1] their time falls in (a stable
// counting sort); each interval present is diced once, both samples (DiceBuffer::diceInterval),
// and its rays are intersected at their own time weight. A static leaf takes the static path
// unchanged.
#pragma once
#include <algorithm>
#include <atomic>
#include <functional>
#include <memory>
#include <array>
#include <vector>
#include <tbb/enumerable_thread_specific.h>
#include "core/ray_batch.h"
#include "dicing/dice_buffer.h"
#include "geometry/leaf_source.h"
#include "geometry/sub_patch.h"
#include "rays/candidate_buffer.h"
#include "rays/candidate_sort.h"
#include "rays/grid_cache.h"
#include "rays/leaf_query_runs.h"
#include "rays/ray_engine.h"
#include "rays/trace_settings.h"
#include "toplevel/toplevel_bvh.h"

namespace rayes {

class SortedEngine : public RayEngine {
 public:
  // `leaves` must outlive the SortedEngine; a generated leaf's patch is made once per dicing and
  // dropped after its rays are intersected.
  SortedEngine(const TopLevelBvh& top, const LeafSource& leaves, const TraceSettings& settings);

  // Traces every ray of `batch` whose kind is not Inactive and fills its hits and occluders.
  void trace(RayBatch& batch, GenerationStats& stats, TraceTimes& times) override;
  size_t bytesPerRay() const override { return bytesPerRaySlot(settings_.lod); }
  size_t sortScratchBytesPerRay() const override { return sortScratchBytesPerRaySlot(settings_.lod); }
  size_t fixedBytes() const override {
    return diceBufferBytes() + cache_.peakBytes() + borderBounds_.bytes() + seamGaps_.bytes();
  }
  EngineStats engineStats() const override;
  size_t limitKeptGrids(size_t bytes) override {
    cache_.setBudget(std::min(bytes, settings_.gridCacheBytes));
    return cache_.bytes();
  }

  const TraceSettings& settings() const { return settings_; }
  // The rays of `batch` to trace (kind not Inactive) into `active`, in batch order; their hits
  // reset and counted into stats. The first step of every engine built on this SortedEngine.
  static void activeRays(RayBatch& batch, GenerationStats& stats, std::vector<uint32_t>& active);
  // Where traceRayAlone gets a leaf's grid: a DiceBuffer holding that leaf's time interval (0 for
  // a static leaf) diced at `level` or finer (the coarser levels are exact subgrids). `patch` is the
  // leaf's patch as the source made it: a source that holds the grid past this call holds it too.
  using GridSource = std::function<const DiceBuffer&(uint32_t leaf, const PatchPtr& patch, int interval, int level)>;
  // Traces ray i of `b` alone and fills its result (hit or occluder): its candidates front to
  // back, each leaf at the ray's own level, the same hit as the sorted pipeline (a pure function of ray, scene, maxLod).
  // Used by the debug mode (--trace-mode alone) and the CachingEngine (rays/caching_engine.h).
  // Defined, with traceAlone, in rays/single_ray_walk.cpp.
  void traceRayAlone(RayBatch& b, uint32_t i, const GridSource& gridFor, TraversalScratch& scratch) const;
  // Per leaf and border e (DiceBuffer's numbering: v = 0, u = 1, v = 1, u = 0), the static
  // Bézier leaf across it; kFreeBorder where no other leaf's box meets the border's box (an
  // outline: no neighbour can leave a crack there, so its regions would only widen the
  // silhouette); else kNoLeaf (other kinds, moving leaves, borders shared in other ways).
  // Empty when no leaf has a neighbour or a free border. `top` is built over the leaves' boxes.
  // Displaced Bézier leaves are paired by their bases' borders. With `sides`, per leaf and
  // border the neighbour's border (bits 0-1), whether it runs the other way (bit 2) and whether
  // the pair is displaced (bit 3); 0 where there is no neighbour. Defined, with
  // bordersClosedByNeighbours and seamGap, in rays/border_neighbours.cpp.
  static constexpr uint32_t kFreeBorder = 0xfffffffeu;  // leaf ids stay below 2^31
  static constexpr uint8_t kReversedSeam = 4, kDisplacedSeam = 8;
  static std::vector<std::array<uint32_t, 4>> borderNeighbours(const LeafSource& leaves, const TopLevelBvh& top,
                                                               std::vector<std::array<uint8_t, 4>>* sides = nullptr);
  // The seam-gap table's key of the displaced seam on `leaf`'s border e at level k, given the
  // neighbour across it and borderNeighbours' `side` byte: the same key from either side (the
  // side with the smaller leaf id, then the smaller border, names it), since the gap is the
  // same number from either side (seamGap).
  static BorderBoundCache::Key seamKey(uint32_t leaf, int e, uint32_t neighbour, uint8_t side, int k) {
    const int across = side & 3;
    const bool mine = leaf < neighbour || (leaf == neighbour && e < across);
    return {mine ? leaf : neighbour, BorderBoundCache::Kind::SeamGap, mine ? e : across, k, 0};
  }
  // Per ray: its next candidate (entry and leaf: the one the top level would give it next,
  // where the next iteration resumes, and whose entry ends the ray once its hit is nearer), the
  // hit lock as the top bit of that leaf word, and its place in the active list (compacted in
  // place each iteration). The search limit is the ray's own hit; a ray's slots past the
  // candidates it got are marked kNoLeaf rather than counted. 12 bytes: the resume point the
  // traversal needs is the one just before the next candidate (TopLevelBvh::resumeBefore), so
  // it is not kept apart (bench/history/2026-11.md, "Compact ray slots, third part").
  static constexpr size_t bytesPerRayState() { return sizeof(float) + 2 * sizeof(uint32_t); }
  static constexpr size_t kMaxCandidatesPerIteration = 65535;  // N per ray at most
  // What one candidate slot costs the engine: the slot itself and, when it is filled, its place
  // in the sort's order. The sort's scratch for it (CandidateSort::scratchBytesPerSlot) is the
  // batch's RayBatch::sortScratch, which the shading sort reuses (core/sort_scratch.h).
  static constexpr size_t bytesPerCandidate() {
    return CandidateBuffer::bytesPerSlot() + CandidateSort::bytesPerSlot();
  }
  // The candidate buffer holds this many slots per ray slot of a full batch: the first
  // iteration of the camera generation then gets N = 2 candidates per ray (2 ray slots per
  // path, the shadow slots empty), later generations N = 1 at first and up to the clip
  // (TraceSettings::maxCandidatesPerRay) as rays finish. 1 instead of 2 saved 12 bytes per ray
  // slot for a few more iterations (bench/history/2026-11.md, "Compact ray slots"); the hits do
  // not depend on N. One slot per path was measured too ("... third part": the same images,
  // callgrind -0.4 to +0.6 %), but then the camera generation's rays reach their second leaf in
  // a second iteration, where a moving leaf (never in the grid cache) is diced again, as often
  // as rounding sends rays there: motion-cubes scaled by 1e4 and 1e8 diced 26 and 28 leaves for
  // its camera rays against the unmoved scene's 30, outside the 5 % that StiffTransform allows.
  // The density rule (--lod density) dices a leaf for the rays of its run in one iteration, and
  // fewer candidates per ray make shorter runs and coarser grids, so it keeps the 2 slots per
  // ray slot its images were made with.
  static constexpr size_t candidatesPerRaySlot(LodRule lod) { return lod == LodRule::Density ? 2 : 1; }
  // Border-bound table entries per leaf at most (TraceSettings::borderBoundEntries caps the total).
  static constexpr size_t kBorderBoundsPerLeaf = 64;
  // The seam gaps' own table: entries per leaf at most (a leaf has at most 2 seams of its own,
  // each with a gap per level <= BottomQuery::kMaxThinLevel: 14), and at most this share of
  // TraceSettings::borderBoundEntries.
  static constexpr size_t kSeamGapsPerLeaf = 16, kSeamGapShare = 16;
  // Per ray slot: the trace state and candidatesPerRaySlot candidate slots. (bytesPerRay() of a
  // SortedEngine; static so the budget can be set before the SortedEngine exists.)
  static constexpr size_t bytesPerRaySlot(LodRule lod) {
    return bytesPerRayState() + candidatesPerRaySlot(lod) * bytesPerCandidate();
  }
  // Per ray slot, what trace() takes of RayBatch::sortScratch: the candidate sort's scratch
  // for candidatesPerRaySlot slots (sortScratchBytesPerRay() of a SortedEngine).
  static constexpr size_t sortScratchBytesPerRaySlot(LodRule lod) {
    return candidatesPerRaySlot(lod) * CandidateSort::scratchBytesPerSlot();
  }
  // Bytes held by dice buffers (all threads so far) and the candidate buffer with its sort.
  size_t diceBufferBytes() const;
  // The finest level a dice buffer holds (TraceSettings::residentLod, raised to
  // kMinResidentLod and ceil(maxLod / 2), at most maxLod).
  int residentLevel() const { return residentLevel_; }
  static int residentLevelFor(int residentLod, int maxLod);
  // The candidate buffer with its sort, counting the sort's scratch (the batch's) at capacity.
  size_t candidateBufferBytes() const {
    return cand_.capacity() * (bytesPerCandidate() + CandidateSort::scratchBytesPerSlot());
  }

 private:
  struct RayState;
  void traceSorted(RayBatch& batch, GenerationStats& stats, TraceTimes& times);
  // The steps of one traceSorted iteration (the header comment's numbers) over the first nNow
  // active rays with N candidate slots each.
  struct DicingCounters {
    std::atomic<uint64_t> micropolygons{0}, dicings{0}, movingDicings{0}, originLeafDicings{0}, splitRuns{0},
        subLeafDicings{0}, subLeafCacheHits{0};
    std::array<std::atomic<uint64_t>, GenerationStats::kLevels> byLevel{};  // the level-of-detail histogram
  };
  void collectCandidates(const RayBatch& b, size_t nNow, int N, TraceTimes& times);       // 1
  size_t sortCandidates(RayBatch& b, size_t nNow, int N, TraceTimes& times);             // 2
  void diceAndIntersectRuns(RayBatch& b, GenerationStats& stats, TraceTimes& times);     // 3, 4
  void diceAndIntersectMoving(RayBatch& b, DiceBuffer& dice, const uint32_t* slots, size_t count,
                              uint32_t leaf, const PatchPtr& patch, TraceTimes& times, DicingCounters& counters);
  void diceAndIntersect(RayBatch& b, DiceBuffer& dice, const uint32_t* slots, size_t count, uint32_t leaf,
                        const Patch& patch, int interval, int m, const uint32_t* entryBits, TraceTimes& times,
                        DicingCounters& counters);
  // The finest level the run's rays need on `leaf` (the level the leaf is diced at).
  // With `entryBits`, also each slot's leafEntry there (as float bits), for the intersection.
  int runLevel(const RayBatch& b, const uint32_t* slots, size_t count, uint32_t leaf, uint32_t* entryBits) const;
  void diceRun(RayBatch& b, DiceBuffer& dice, const uint32_t* slots, size_t count, uint32_t leaf,
               const Patch& patch, int interval, int m, TraceTimes& times, DicingCounters& counters);
  // A run finer than residentLevel() (its time interval, or static when interval < 0), in
  // rays/sub_leaf_runs.cpp: its rays at levels <= residentLevel() against the leaf diced
  // whole, the others against the 4^d sub-leaves their rays cross (d = the run's level minus
  // residentLevel()), each ray at its own level minus d: the same micro-triangles as the whole
  // leaf at its level, the hit reported in the leaf's own parameters and quad numbering.
  // Planned first (planSplitRun), then run (runSplitPlan): with the grid cache the plan is made
  // before the serial cache pass, which acquires its grids (acquireSplitGrids).
  struct SplitPlan {
    PatchPtr patch;                      // the leaf's
    int depth = 0, coarseLevel = -1;     // coarseLevel: the coarse rays' finest; -1: none
    std::vector<uint32_t> coarse, fine;  // coarse: slots; fine: indices k into the run
    std::vector<float> coarseEntry;      // per coarse slot: leafEntry
    std::vector<uint8_t> level;          // per slot k of the run: its level on the leaf
    std::vector<float> entry;            // per slot k: leafEntry
    struct Sub {
      std::shared_ptr<const SubPatch> patch;
      int level = 0;                      // the finest of its fine rays' levels, minus depth
      GridCache::Entry* grid = nullptr;   // from the cache (toDice: to be diced), or none
    };
    std::vector<Sub> subs;               // those some fine ray's box test reaches, row order
    GridCache::Entry* whole = nullptr;   // the coarse rays' grid from the cache, or none
  };
  void diceAndIntersectSplit(RayBatch& b, DiceBuffer& dice, const uint32_t* slots, size_t count, uint32_t leaf,
                             const PatchPtr& patch, int interval, int m, const uint32_t* entryBits, TraceTimes& times,
                             DicingCounters& counters);
  // The plan of a run at level m > residentLevel(): a function of the run's rays alone (each
  // fine ray's box test up to its own tmax), so a superset of the sub-leaves runSplitPlan dices.
  void planSplitRun(const RayBatch& b, const uint32_t* slots, size_t count, uint32_t leaf, PatchPtr patch, int m,
                    const uint32_t* entryBits, SplitPlan& plan) const;
  // The serial cache pass for a split run: its whole leaf at coarseLevel, then its sub-leaves
  // in row order, keyed (leaf, depth, x, y). Returns the whole leaf's hit (0 or 1).
  uint64_t acquireSplitGrids(uint32_t leaf, SplitPlan& plan);
  // Dices and intersects a planned run; sub-leaves in row order, each diced (into its cache
  // entry, or into `dice`, or this thread's buffer when null) only when a fine ray crosses its
  // box before the nearest hit this run has found for that ray. A long run's rays are tested
  // and intersected in chunks that other threads may take (forRunChunks), as intersectRun's.
  void runSplitPlan(RayBatch& b, DiceBuffer* dice, const uint32_t* slots, uint32_t leaf, SplitPlan& plan, int interval,
                    TraceTimes& times, DicingCounters& counters);
  // One slot against sub-leaf `sub` of `leaf` (diced in `dice`), the ray at `level` on the leaf,
  // searching up to `best` (its nearest hit in this run so far). Returns the kept distance of
  // the hit offered, infinity for none, -1 for a shadow ray occluded.
  float intersectSubLeafSlot(RayBatch& b, const DiceBuffer& dice, uint32_t slot, uint32_t leaf, const Patch& patch,
                             const SubPatch& sub, int level, float entry, float best);
  // With RayBatch::chargeDicings: one dicing split among the run's rays (RayBatch::dicingShare).
  void chargeRun(RayBatch& b, const uint32_t* slots, size_t count) const;
  // Every slot of the run against the diced leaf (rays at their own level <= m); entryBits as
  // runLevel wrote them, or null (then computed here).
  void intersectRun(RayBatch& b, const DiceBuffer& dice, const uint32_t* slots, size_t count, uint32_t leaf,
                    const Patch& patch, int m, const uint32_t* entryBits, TraceTimes& times, DicingCounters& counters);
  void offerHit(RayBatch& b, uint32_t ray, const RayHit& h, const HitDerivatives* d);  // 4
  void offerOccluder(RayBatch& b, uint32_t ray, uint32_t leaf, int level);         // 4, a shadow ray
  // A brick leaf's run (rays/brick_leaf_runs.cpp): the batch's MediumLeafTracker over all its
  // rays, each closest ray's collision offered as a hit on the leaf.
  void trackBrickRun(RayBatch& b, const uint32_t* slots, size_t count, uint32_t leaf);
  // Leaves past the patches are bricks of media (core/medium_leaves.h).
  bool isBrickLeaf(uint32_t leaf) const { return leaf >= leaves_.size(); }
  uint64_t keepUnfinishedRays(const RayBatch& b, size_t nActive, size_t nNow);           // 5
  // The ray a candidate slot of this iteration belongs to (slots are N per active ray).
  uint32_t rayOfSlot(uint32_t slot) const { return active_[slot / slotsPerRay_]; }
  void traceAlone(RayBatch& batch, GenerationStats& stats, TraceTimes& times);
  int levelFor(const RayBatch& b, uint32_t ray, uint32_t leaf, float entry) const;
  // The ray's entry into the leaf's box (0 when the slab test misses): the same operations on
  // the same box as the top level's candidate entry, so the two agree bit for bit. A ray's
  // level on a leaf is levelFor at this entry, one function of (ray, leaf) whichever leaf
  // asks, so two neighbours agree on each other's level (see bordersClosedByNeighbours).
  float leafEntry(const RayBatch& b, uint32_t ray, uint32_t leaf) const;
  // The same for a ray whose box query is made already (its direction decoded once: Ray::dir).
  float leafEntry(const RayBoxQuery& q, uint32_t leaf) const;
  // Whether the ray of `q` crosses the leaf's box, and then its entry: leafEntry's slab test.
  bool crossesLeafBox(const RayBoxQuery& q, uint32_t leaf, float& entry) const;
  // Borders of `leaf` whose regions ray i need not test at `level` (BottomQuery::skipBorders),
  // and those whose regions can be thin (thinBorders): free borders need none; of a Bézier seam
  // only the coarser side does (its regions hold the finer side's chord), and Bézier neighbours
  // at equal levels share their border vertices bit for bit. A displaced seam keeps its regions
  // unless both sides are seen at the same level (<= BottomQuery::kMaxThinLevel): then its
  // vertices lie within seamGap of the neighbour's, and a region of that radius closes the slit
  // (P and h agree across it, the normal N of P + N h does not, and the forest's rings are only
  // nearly G1). A border is treated so only when its neighbour is known (borderNeighbour_),
  // reachable by the ray and tests its own regions (not the ray's origin or ignored leaf).
  // q: ray i's box query (made by the caller, which decodes the ray's direction once per slot).
  void bordersClosedByNeighbours(const RayBatch& b, uint32_t i, const RayBoxQuery& q, uint32_t leaf, int level,
                                 const Patch& patch, const DiceBuffer& dice, BottomQuery& query) const;
  // The largest distance between the level-k vertices of border e of `leaf` (its `patch`, diced
  // in `dice`) and those of its displaced neighbour across it at the same parameters, from both
  // patches' evaluate(), which their dicings equal bit for bit (Patch contract): this side's are
  // read from `dice` when it holds level k, the neighbour's evaluated (its patch is made for it).
  // A pure function of the seam and k, the same number from either side: kept once per seam and
  // level (seamKey) in a table of its own, seamGaps_ (in the border-bound table the far more
  // numerous curve boxes evicted it, and teapot-field measured 5,888 gaps of ~2,500 seams:
  // bench/history/2026-11.md, "Seam gaps once per seam"). Not finite when a vertex is not (then
  // the seam keeps its full region).
  double seamGap(uint32_t leaf, const Patch& patch, const DiceBuffer& dice, int e, int k) const;
  double measuredSeamGap(uint32_t leaf, const Patch& patch, const DiceBuffer& dice, int e,
                         int k) const;  // seamGap without the table
  // Whether ray i also tests the border boxes of `leaf`: not on the leaf it leaves from (it
  // sees that grid exactly as it left it and starts on its outside; docs/architecture.md).
  bool closeBordersFor(const RayBatch& b, uint32_t i, uint32_t leaf) const {
    return settings_.closeBorders && leaf != b.ray[i].originLeaf();
  }
  // `entry`: leafEntry(b, ray of slot, leaf), the level's footprint distance and the hit's floor.
  void intersectSlot(RayBatch& b, const DiceBuffer& dice, uint32_t slot, uint32_t leaf, const Patch& patch, int m,
                     float entry);
  // This thread's dice buffer: sized for residentLevel(), or (`whole`, the one-ray debug walk
  // only) for maxLod.
  DiceBuffer& localDiceBuffer(bool whole = false);

  const TopLevelBvh& top_;
  const LeafSource& leaves_;
  TraceSettings settings_;
  std::vector<float> leafSize_;  // LeafFacts::sizeBound per leaf, for LOD
  std::vector<uint8_t> leafFloor_;  // levelForDicingError per leaf: the per-ray rule's coarsest level
  std::vector<uint8_t> leafMoving_;  // more than one time sample: diced per time interval
  std::vector<std::array<uint32_t, 4>> borderNeighbour_;  // borderNeighbours(leaves), per-ray LOD only
  std::vector<std::array<uint8_t, 4>> borderSide_;        // its `sides`

  CandidateBuffer cand_;
  CandidateSort sort_;
  std::vector<uint32_t> active_;
  uint32_t slotsPerRay_ = 1;  // N of the current iteration
  // Per ray: its next candidate's entry and leaf (bytesPerRayState); the leaf word's top bit is
  // the ray's hit lock, held while a hit is offered to it (leaf ids are below 2^31, and the
  // word is read for resuming only between the bottom steps that take the lock).
  std::vector<float> nextEntry_;
  std::vector<uint32_t> nextLeaf_;
  static constexpr uint32_t kHitLockBit = 0x80000000u;
  tbb::enumerable_thread_specific<std::unique_ptr<DiceBuffer>> dice_, wholeDice_;
  int residentLevel_ = 0;  // residentLevel()
  // Per thread: an uncached split run's plan, a sub-leaf's rays, each fine ray's nearest hit
  // so far and whether it reaches the sub-leaf at hand (rays/sub_leaf_runs.cpp).
  struct SplitScratch {
    SplitPlan plan;
    std::vector<uint32_t> sub, subSlot;
    std::vector<float> best;
    std::vector<uint8_t> reaches;
  };
  tbb::enumerable_thread_specific<SplitScratch> split_;
  tbb::enumerable_thread_specific<TraversalScratch> scratch_;
  // Per thread: a moving leaf's slots regrouped by time interval (stable), and the counts.
  struct IntervalScratch {
    std::vector<uint32_t> slots, interval, start;
  };
  tbb::enumerable_thread_specific<IntervalScratch> intervals_;
  GridCache cache_;
  // Mutable: seamGap fills it from const queries (the table is lock-free and its values are
  // pure functions of their keys).
  mutable BorderBoundCache borderBounds_;
  // The displaced seams' gaps, one entry per seam and level (seamKey); bounded like the table
  // above (kSeamGapsPerLeaf, kSeamGapShare), allocated on the first displaced seam's gap. A
  // dense per-seam array was measured too: it cost forest-1000 62 bytes a leaf (121 MB).
  mutable BorderBoundCache seamGaps_;
  // Per thread, the seam gaps of the last leaf asked: a run's rays all ask about one leaf, so
  // they need not each read the table (a random access) per border.
  struct SeamGapMemo {
    uint32_t leaf = kNoLeaf;
    uint32_t known = 0;  // bit e * 8 + k
    double gap[4][BottomQuery::kMaxThinLevel + 1] = {};
  };
  mutable tbb::enumerable_thread_specific<SeamGapMemo> seamGapMemo_;
  SharedBorderBounds sharedBorders(uint32_t leaf) {
    return {settings_.borderBoundEntries ? &borderBounds_ : nullptr, leaf};
  }
  std::vector<int> runLevel_;                  // per static run of the current iteration (cache on)
  std::vector<GridCache::Entry*> runEntry_;    // its cache entry, or nullptr (diced per thread)
  std::vector<std::unique_ptr<SplitPlan>> runPlan_;  // a static run finer than residentLevel() (cache on)
  // The batch's leaf queries grouped by leaf, run in the first iteration's per-leaf tasks; and
  // those tasks: a run of rays, of queries or both on one leaf (kNoRun: none).
  LeafQueryRuns queries_;
  static constexpr uint32_t kNoRun = 0xffffffffu;
  struct LeafTask { uint32_t rays, queries; };
  std::vector<LeafTask> tasks_;
};

// True when hit (t, leaf, quad) is nearer than `best` under the total order used everywhere:
// distance, then leaf id, then micro-quad index.
inline bool nearerHit(float t, uint32_t leaf, uint32_t quad, const RayHit& best) {
  if (t != best.t) return t < best.t;
  if (leaf != best.leaf) return leaf < best.leaf;
  return quad < best.quad;
}

}  // namespace rayes
