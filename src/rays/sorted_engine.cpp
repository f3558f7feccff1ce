// The SortedEngine's per-generation pipeline (the five steps of rays/sorted_engine.h: collect
// candidates, sort, dice, bottom, reduce) and what every walk of the engine shares: set-up,
// levels of detail, leaf entries, stats. The border-neighbour analysis that lets a ray skip
// crack-closing regions is in rays/border_neighbours.cpp; the one-ray-at-a-time walk (--trace-mode
// alone, the CachingEngine) in rays/single_ray_walk.cpp.
#include "rays/sorted_engine.h"
#include <algorithm>
#include <stdexcept>
#include <atomic>
#include <bit>
#include <limits>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include "core/medium_leaves.h"
#include "geometry/moving_patch.h"
#include "rays/kept_hit.h"
#include "rays/run_chunks.h"

namespace rayes {
namespace {
constexpr float kInf = std::numeric_limits<float>::infinity();

// One iteration of a spin-wait: tells the core this is a wait loop (x86 `pause`).
inline void spinPause() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#endif
}
}  // namespace

SortedEngine::SortedEngine(const TopLevelBvh& top, const LeafSource& leaves, const TraceSettings& s)
    : top_(top), leaves_(leaves), settings_(s), cand_(std::max<size_t>(s.candidateCapacity, 1)),
      cache_(s.gridCacheBytes),
      // A small scene needs a small table: 64 entries per leaf at most, so forest-1's 664 leaves
      // take 2.6 MiB instead of the 160 MiB that forest-100's re-dicings pay for.
      borderBounds_(std::min(s.borderBoundEntries, std::max<size_t>(leaves.size(), 1) * kBorderBoundsPerLeaf)),
      seamGaps_(std::min(s.borderBoundEntries / kSeamGapShare, std::max<size_t>(leaves.size(), 1) * kSeamGapsPerLeaf)) {
  // The top level holds these leaves, then perhaps the bricks of media (core/medium_leaves.h).
  if (top.leafBoxes().size() < leaves.size()) throw std::logic_error("SortedEngine: the top level is not over these leaves");
  leafSize_.resize(leaves.size());
  leafFloor_.resize(leaves.size());
  leafMoving_.resize(leaves.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, leaves.size(), 1024), [&](const auto& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const LeafFacts f = leaves.facts(i);
      leafSize_[i] = f.sizeBound;
      leafFloor_[i] = uint8_t(levelForDicingError(f.sizeBound, f.dicingError, settings_.maxLod));
      leafMoving_[i] = f.timeSamples > 1;
    }
  });
  if (settings_.closeBorders && settings_.lod == LodRule::PerRay) borderNeighbour_ = borderNeighbours(leaves, top, &borderSide_);
  residentLevel_ = residentLevelFor(settings_.residentLod, settings_.maxLod);
}

int SortedEngine::residentLevelFor(int residentLod, int maxLod) {
  // A split ray's level is above the resident level, so above the last thin level: a sub-leaf
  // never needs the seam gaps, which are measured on whole leaves (bordersClosedByNeighbours).
  static_assert(TraceSettings::kMinResidentLod >= BottomQuery::kMaxThinLevel);
  return std::min(maxLod, std::max({residentLod, TraceSettings::kMinResidentLod, (maxLod + 1) / 2}));
}

bool SortedEngine::crossesLeafBox(const RayBoxQuery& q, uint32_t leaf, float& entry) const {
  float exit;
  const Box3& box = top_.leafBoxes()[leaf];
  return intersectBox(q, box.lo, box.hi, 0.0f, kInf, entry, exit);
}

float SortedEngine::leafEntry(const RayBatch& b, uint32_t ray, uint32_t leaf) const {
  return leafEntry(RayBoxQuery(b.ray[ray].org, b.ray[ray].dir()), leaf);
}

float SortedEngine::leafEntry(const RayBoxQuery& q, uint32_t leaf) const {
  float entry;
  return crossesLeafBox(q, leaf, entry) ? entry : 0.0f;
}

size_t SortedEngine::diceBufferBytes() const {
  size_t b = 0;
  for (const auto& d : dice_) if (d) b += d->bytesAllocated();
  for (const auto& d : wholeDice_) if (d) b += d->bytesAllocated();
  return b;
}

EngineStats SortedEngine::engineStats() const {
  EngineStats s;
  s.name = "rayes";
  s.fixedBytes = fixedBytes();
  s.leafTableBytes = leafSize_.capacity() * sizeof(float) + leafMoving_.capacity() + leafFloor_.capacity() +
                     borderNeighbour_.capacity() * sizeof(borderNeighbour_[0]);
  s.maxLevel = settings_.maxLod;
  s.cacheHits = cache_.hits();
  s.cachePeakBytes = cache_.peakBytes();
  s.cacheBytes = cache_.bytes();
  s.borderBoundBytes = borderBounds_.bytes() + seamGaps_.bytes();
  return s;
}

DiceBuffer& SortedEngine::localDiceBuffer(bool whole) {
  auto& d = whole ? wholeDice_.local() : dice_.local();
  if (!d) d = std::make_unique<DiceBuffer>(whole ? settings_.maxLod : residentLevel_);
  return *d;
}

int SortedEngine::levelFor(const RayBatch& b, uint32_t ray, uint32_t leaf, float entry) const {
  int level;
  if (settings_.lod == LodRule::Fixed) {
    level = biasedLevel(settings_.maxLod, settings_.lodBias, settings_.maxLod);
  } else if (leaf == b.ray[ray].originLeaf()) {
    level = std::min<int>(b.ray[ray].originLevel, settings_.maxLod);  // carries the bias already
  } else {
    const float width = b.ray[ray].coneWidth + std::max(entry, 0.0f) * b.ray[ray].coneSpread();
    // No coarser than the patch's dicing error allows at this distance (docs/design.md, "Level of
    // detail and energy").
    const int floor = floorAtDistance(leafFloor_[leaf], leafSize_[leaf], entry);
    const int footprint = std::max(levelForFootprint(leafSize_[leaf], width, settings_.maxLod), floor);
    level = biasedLevel(footprint, settings_.lodBias, settings_.maxLod);
  }
  if (settings_.levelHook) level = std::clamp(settings_.levelHook(ray, leaf, level), 0, settings_.maxLod);
  return level;
}

void SortedEngine::trace(RayBatch& batch, GenerationStats& stats, TraceTimes& times) {
  const size_t n = batch.size();
  nextEntry_.assign(n, -kInf);  // the first candidate is at or after (-inf, 0): any; no lock held
  nextLeaf_.assign(n, 0);
  activeRays(batch, stats, active_);
  {
    ScopedTimer timer(times.sort);
    if (batch.queries) queries_.group(*batch.queries);
  }
  // Brick leaves are run only by the sorted pipeline, over a top level that holds them.
  if (batch.media)
    batch.media->tracked = settings_.sortByLeaf && batch.media->firstLeaf == leaves_.size() &&
                           top_.leafBoxes().size() == leaves_.size() + batch.media->bricks;
  if (settings_.sortByLeaf) traceSorted(batch, stats, times);
  else traceAlone(batch, stats, times);
  // No iteration ran them: no rays to trace, or rays traced alone.
  if (queries_.runs()) queries_.runAll(times.leafQueries);
}

// Bottom level for one candidate slot: the ray against the diced leaf at the ray's level (and
// its time, on a moving leaf), a hit offered to the ray.
void SortedEngine::intersectSlot(RayBatch& b, const DiceBuffer& dice, uint32_t s, uint32_t leaf, const Patch& patch,
                                 int m, float entry) {
  const uint32_t i = rayOfSlot(s);
  // What another leaf of this iteration already offered the ray: a hit this leaf cannot beat
  // makes its intersection moot (see offerHit).
  const bool shadow = b.ray[i].kind == RayKind::Shadow;
  float offered = kInf;
  if (shadow) {
    const uint32_t occluder = std::atomic_ref<uint32_t>(b.occluderOf(i)).load(std::memory_order_relaxed);
    if (occluder < leaf) return;  // occluders all have t = 0: the smallest leaf wins
  } else {
    offered = std::atomic_ref<float>(b.hitOf(i).t).load(std::memory_order_relaxed);
    if (entry > offered) return;  // every hit here is kept at t >= entry
  }
  const int level = settings_.lod == LodRule::Density ? m : levelFor(b, i, leaf, entry);
  // The offered hit is the nearest any leaf has found so far, so it bounds the search.
  const float limit = searchLimit(b, i, offered);
  BottomQuery query;
  query.alpha = dice.moving() ? timeInterval(patch, b.timeOf(i)).alpha : 0.0f;
  const Vec3 dir = b.ray[i].dir();  // decoded once for the slot
  query.closeBorders = closeBordersFor(b, i, leaf);
  if (query.closeBorders) bordersClosedByNeighbours(b, i, RayBoxQuery(b.ray[i].org, dir), leaf, level, patch, dice, query);
  if (shadow) {
    if (dice.occluded(b.ray[i].org, dir, 0.0f, limit, level, query)) offerOccluder(b, i, leaf, level);
    return;
  }
  GridHit h;
  if (dice.intersect(b.ray[i].org, dir, 0.0f, limit, level, h, query)) {
    const HitDerivatives d = keptDerivatives(h);
    offerHit(b, i, hitRecord(h, leaf, level, entry), &d);
  }
}

// 4, reduction: the ray keeps the nearest hit under the total order, whichever leaf's task
// offers first. The lock is per ray and held for a compare and a copy, so a waiter spins:
// atomic_flag::wait/notify_one cost a locked add on a waiter-pool word every thread shares on
// every offer (46 % of offerHit's samples on subdiv-creature; bench/RESULTS.md).
void SortedEngine::offerHit(RayBatch& b, uint32_t i, const RayHit& h, const HitDerivatives* d) {
  std::atomic_ref<uint32_t> lock(nextLeaf_[i]);
  while (lock.fetch_or(kHitLockBit, std::memory_order_acquire) & kHitLockBit)
    while (lock.load(std::memory_order_relaxed) & kHitLockBit) spinPause();
  if (nearerHit(h.t, h.leaf, h.quad, b.hitOf(i))) {
    // t and leaf are read without the lock (intersectSlot), so they are stored atomically.
    RayHit& dst = b.hitOf(i);
    dst.u = h.u; dst.v = h.v; dst.quad = h.quad; dst.ngCode = h.ngCode; dst.nsCode = h.nsCode; dst.level = h.level;
    dst.border = h.border;
    if (HitDerivatives* kept = b.derivativesOf(i)) *kept = d ? *d : HitDerivatives{};
    std::atomic_ref<float>(dst.t).store(h.t, std::memory_order_relaxed);
    std::atomic_ref<uint32_t>(dst.leaf).store(h.leaf, std::memory_order_relaxed);
  }
  lock.fetch_and(~kHitLockBit, std::memory_order_release);
}

// A shadow ray's occluder: the smallest leaf wins (every occluder is at t = 0), as offerHit
// would order it. A slot that keeps only the leaf (RayBatch::shadowPairs) takes it by a
// compare-and-swap, without the lock.
void SortedEngine::offerOccluder(RayBatch& b, uint32_t i, uint32_t leaf, int level) {
  if (b.keepsFullHit(i)) {
    RayHit occluder;
    occluder.t = 0; occluder.leaf = leaf; occluder.level = static_cast<uint8_t>(level);
    offerHit(b, i, occluder, nullptr);
    return;
  }
  std::atomic_ref<uint32_t> kept(b.occluderOf(i));
  uint32_t now = kept.load(std::memory_order_relaxed);
  while (leaf < now && !kept.compare_exchange_weak(now, leaf, std::memory_order_relaxed)) {}
}

// One iteration of the sorted pipeline per loop, in the five steps of the header comment.
void SortedEngine::traceSorted(RayBatch& b, GenerationStats& stats, TraceTimes& times) {
  const size_t capacity = cand_.capacity();
  while (!active_.empty()) {
    const size_t nActive = active_.size();
    const int N = static_cast<int>(std::clamp<size_t>(capacity / nActive, 1,
                                                      std::min<size_t>(settings_.maxCandidatesPerRay, kMaxCandidatesPerIteration)));
    // Rays beyond capacity (only when capacity < active rays) wait for the next iteration.
    const size_t nNow = std::min(nActive, capacity / size_t(N));
    IterationStats it;
    it.activeRays = nActive;
    it.candidatesPerRay = N;
    collectCandidates(b, nNow, N, times);
    it.candidates = sortCandidates(b, nNow, N, times);
    const uint64_t dicedBefore = stats.leavesDiced, hitsBefore = stats.gridCacheHits;
    diceAndIntersectRuns(b, stats, times);
    it.dicings = stats.leavesDiced - dicedBefore;
    it.cacheHits = stats.gridCacheHits - hitsBefore;
    stats.borderHits += keepUnfinishedRays(b, nActive, nNow);
    stats.iterations.push_back(it);
  }
}

// 1. Top level: up to N candidates per ray into its own slots.
void SortedEngine::collectCandidates(const RayBatch& b, size_t nNow, int N, TraceTimes& times) {
  ScopedTimer timer(times.toplevel);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, nNow, 256), [&](const auto& r) {
    auto& scratch = scratch_.local();
    Candidate local[128];
    for (size_t a = r.begin(); a != r.end(); ++a) {
      const uint32_t i = active_[a];
      float next = kInf;
      // The hit kept from earlier iterations bounds the search (no other thread writes it now);
      // a shadow ray searches to its tmax.
      const float best = b.keepsFullHit(i) ? b.hitOf(i).t : kInf;
      float resumeEntry;
      uint32_t resumeLeaf;
      TopLevelBvh::resumeBefore(nextEntry_[i], nextLeaf_[i], resumeEntry, resumeLeaf);
      const int got = top_.collect(b.ray[i].org, b.ray[i].dir(), 0.0f, searchLimit(b, i, best), resumeEntry,
                                   resumeLeaf, local, N, next, scratch, &nextLeaf_[i]);
      const size_t base = a * size_t(N);
      for (int j = 0; j < got; ++j) cand_.leaf[base + j] = local[j].leaf == b.ray[i].ignoreLeaf ? kNoLeaf : local[j].leaf;
      std::fill(cand_.leaf.begin() + ptrdiff_t(base + size_t(got)), cand_.leaf.begin() + ptrdiff_t(base + size_t(N)),
                kNoLeaf);  // the slots past those got: no count is kept
      nextEntry_[i] = next;  // with nextLeaf_[i], written by collect when there is a next candidate
    }
  });
}

// 2. Sort the filled slots by leaf, with the batch's sort scratch (the shading sort's memory,
// free while the batch is traced). Returns how many slots were filled.
size_t SortedEngine::sortCandidates(RayBatch& b, size_t nNow, int N, TraceTimes& times) {
  ScopedTimer timer(times.sort);
  std::vector<uint32_t>& filled = sort_.order;
  filled.clear();
  slotsPerRay_ = uint32_t(N);
  for (size_t a = 0; a < nNow; ++a) {
    const size_t base = a * size_t(N);
    for (size_t j = 0; j < size_t(N); ++j)
      if (cand_.leaf[base + j] != kNoLeaf) filled.push_back(static_cast<uint32_t>(base + j));
  }
  sort_.sort(cand_.leaf, b.sortScratch.take<uint32_t>(filled.size()));
  return sort_.sorted.size();
}

// 3+4. One task per leaf: dice once (or take the cached grid), intersect all of its rays; a
// moving leaf once per time interval its rays fall in; and, in the first iteration, run the
// leaf's queries. The cache is asked serially, in run
// order, so its history does not depend on the thread count (rays/grid_cache.h).
void SortedEngine::diceAndIntersectRuns(RayBatch& b, GenerationStats& stats, TraceTimes& times) {
  const size_t nRuns = sort_.runs.empty() ? 0 : sort_.runs.size() - 1;
  auto runSlots = [&](size_t run) { return sort_.sorted.data() + sort_.runs[run]; };
  auto runCount = [&](size_t run) { return size_t(sort_.runs[run + 1] - sort_.runs[run]); };
  // Each sorted slot's entry into its leaf's box (SortedEngine::leafEntry, as float bits),
  // written by runLevel and read by the intersection, in the sort's spare buffer: free until the
  // next sort, and as long as `sorted`.
  auto runEntries = [&](size_t run) { return sort_.spare.data() + sort_.runs[run]; };
  runEntry_.assign(nRuns, nullptr);
  runPlan_.clear();
  if (cache_.enabled()) {
    // The level of every static run (a moving leaf's levels are per time interval, later),
    // computed once: for the cache's decision and for the dicing, cached or not; a run finer
    // than the resident level is planned here, so that its grids can be asked for serially.
    runLevel_.assign(nRuns, -1);
    runPlan_.resize(nRuns);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, nRuns, 64), [&](const auto& r) {
      for (size_t run = r.begin(); run != r.end(); ++run) {
        const uint32_t leaf = cand_.leaf[runSlots(run)[0]];
        if (isBrickLeaf(leaf) || leafMoving_[leaf]) continue;
        runLevel_[run] = runLevel(b, runSlots(run), runCount(run), leaf, runEntries(run));
        if (runLevel_[run] <= residentLevel_) continue;
        runPlan_[run] = std::make_unique<SplitPlan>();
        planSplitRun(b, runSlots(run), runCount(run), leaf, leaves_.patch(leaf), runLevel_[run], runEntries(run), *runPlan_[run]);
      }
    });
    uint64_t hits = 0;
    for (size_t run = 0; run < nRuns; ++run) {
      const uint32_t leaf = cand_.leaf[runSlots(run)[0]];
      if (isBrickLeaf(leaf) || leafMoving_[leaf]) continue;
      if (runPlan_[run]) {
        hits += acquireSplitGrids(leaf, *runPlan_[run]);
        continue;
      }
      runEntry_[run] = cache_.acquire(leaf, runLevel_[run]);
      hits += runEntry_[run] && !runEntry_[run]->toDice;
    }
    cache_.nextIteration();
    stats.gridCacheHits += hits;
  }
  // The per-leaf tasks: the ray runs merged by leaf with the query runs (both in increasing leaf
  // order), which only the first iteration of a trace has.
  tasks_.clear();
  const size_t nQueryRuns = queries_.runs();
  for (size_t run = 0, q = 0; run < nRuns || q < nQueryRuns;) {
    const uint32_t rayLeaf = run < nRuns ? cand_.leaf[runSlots(run)[0]] : kNoLeaf;
    const uint32_t queryLeaf = q < nQueryRuns ? queries_.leafOf(q) : kNoLeaf;
    const bool rays = rayLeaf <= queryLeaf, queries = queryLeaf <= rayLeaf;
    tasks_.push_back({rays ? uint32_t(run++) : kNoRun, queries ? uint32_t(q++) : kNoRun});
  }
  DicingCounters counters;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, tasks_.size(), 1), [&](const auto& r) {
    for (size_t task = r.begin(); task != r.end(); ++task) {
      const LeafTask t = tasks_[task];
      if (t.queries != kNoRun) queries_.run(t.queries, times.leafQueries);
      if (t.rays == kNoRun) continue;
      const size_t run = t.rays;
      const uint32_t* slots = runSlots(run);
      const size_t count = runCount(run);
      const uint32_t leaf = cand_.leaf[slots[0]];
      if (isBrickLeaf(leaf)) {
        trackBrickRun(b, slots, count, leaf);
        continue;
      }
      if (GridCache::Entry* e = runEntry_[run]) {
        if (e->toDice) {
          e->patch = leaves_.patch(leaf);  // kept with the grid: border queries read it
          diceRun(b, e->gridToDice(), slots, count, leaf, *e->patch, -1, runLevel_[run], times, counters);
        }
        intersectRun(b, *e->grid, slots, count, leaf, *e->patch, runLevel_[run], runEntries(run), times, counters);
        continue;
      }
      if (!runPlan_.empty() && runPlan_[run]) {
        runSplitPlan(b, nullptr, slots, leaf, *runPlan_[run], -1, times, counters);
        continue;
      }
      DiceBuffer& dice = localDiceBuffer();
      // A generated leaf's patch lives only for this run.
      const PatchPtr patch = leaves_.patch(leaf);
      if (leafMoving_[leaf]) {
        diceAndIntersectMoving(b, dice, slots, count, leaf, patch, times, counters);
      } else {
        const int m = cache_.enabled() ? runLevel_[run] : runLevel(b, slots, count, leaf, runEntries(run));
        if (m > residentLevel_) diceAndIntersectSplit(b, dice, slots, count, leaf, patch, -1, m, runEntries(run), times, counters);
        else diceAndIntersect(b, dice, slots, count, leaf, *patch, -1, m, runEntries(run), times, counters);
      }
    }
  });
  queries_.clear();
  // Grids acquired for sub-leaves no ray of their run reached after all go back, in run order.
  for (const auto& plan : runPlan_)
    if (plan)
      for (const SplitPlan::Sub& sub : plan->subs) cache_.discard(sub.grid);
  runPlan_.clear();  // with the plans, the generated leaves' patches
  stats.gridCacheHits += counters.subLeafCacheHits.load();
  stats.subLeafCacheHits += counters.subLeafCacheHits.load();
  stats.leavesDiced += counters.dicings.load();
  stats.micropolygonsCreated += counters.micropolygons.load();
  stats.movingDicings += counters.movingDicings.load();
  stats.originLeafDicings += counters.originLeafDicings.load();
  stats.splitRuns += counters.splitRuns.load();
  stats.subLeafDicings += counters.subLeafDicings.load();
  for (size_t m = 0; m < counters.byLevel.size(); ++m) stats.dicingsByLevel[m] += counters.byLevel[m].load();
}

// Motion: regroups a moving leaf's run by time interval (a stable counting sort, so no order
// changes) and dices each interval present once.
void SortedEngine::diceAndIntersectMoving(RayBatch& b, DiceBuffer& dice, const uint32_t* slots, size_t count,
                                          uint32_t leaf, const PatchPtr& patchPtr, TraceTimes& times,
                                          DicingCounters& counters) {
  const Patch& patch = *patchPtr;
  IntervalScratch& sc = intervals_.local();
  const int intervals = patch.timeSamples() - 1;
  sc.interval.resize(count);
  sc.start.assign(size_t(intervals) + 1, 0);
  for (size_t k = 0; k < count; ++k) {
    sc.interval[k] = uint32_t(timeInterval(patch, b.timeOf(rayOfSlot(slots[k]))).interval);
    ++sc.start[sc.interval[k] + 1];
  }
  for (int iv = 0; iv < intervals; ++iv) sc.start[size_t(iv) + 1] += sc.start[size_t(iv)];
  sc.slots.resize(count);
  {
    std::vector<uint32_t> next(sc.start.begin(), sc.start.end() - 1);
    for (size_t k = 0; k < count; ++k) sc.slots[next[sc.interval[k]]++] = slots[k];
  }
  for (int iv = 0; iv < intervals; ++iv) {
    const size_t k0 = sc.start[size_t(iv)], k1 = sc.start[size_t(iv) + 1];
    if (k1 > k0) {
      const uint32_t* part = sc.slots.data() + k0;
      const int m = runLevel(b, part, k1 - k0, leaf, nullptr);
      if (m > residentLevel_) diceAndIntersectSplit(b, dice, part, k1 - k0, leaf, patchPtr, iv, m, nullptr, times, counters);
      else diceAndIntersect(b, dice, part, k1 - k0, leaf, patch, iv, m, nullptr, times, counters);
    }
  }
}

// Dices `leaf` (its time interval, or static when interval < 0) at level m, the finest level of
// `count` slots (runLevel), and intersects them all.
void SortedEngine::diceAndIntersect(RayBatch& b, DiceBuffer& dice, const uint32_t* slots, size_t count, uint32_t leaf,
                                    const Patch& patch, int interval, int m, const uint32_t* entryBits, TraceTimes& times,
                                    DicingCounters& counters) {
  diceRun(b, dice, slots, count, leaf, patch, interval, m, times, counters);
  intersectRun(b, dice, slots, count, leaf, patch, m, entryBits, times, counters);
}

int SortedEngine::runLevel(const RayBatch& b, const uint32_t* slots, size_t count, uint32_t leaf, uint32_t* entryBits) const {
  const bool density = settings_.lod == LodRule::Density;
  int m = 0;
  if (!density || entryBits)
    for (size_t k = 0; k < count; ++k) {
      const uint32_t i = rayOfSlot(slots[k]);
      const float entry = leafEntry(b, i, leaf);
      if (entryBits) entryBits[k] = std::bit_cast<uint32_t>(entry);
      if (!density) m = std::max(m, levelFor(b, i, leaf, entry));
    }
  if (density)
    return biasedLevel(levelForDensity(count, settings_.samplesPerPixel, settings_.maxLod), settings_.lodBias,
                       settings_.maxLod);
  return m;
}

void SortedEngine::diceRun(RayBatch& b, DiceBuffer& dice, const uint32_t* slots, size_t count, uint32_t leaf,
                           const Patch& patch, int interval, int m, TraceTimes& times, DicingCounters& counters) {
  const bool sub = dynamic_cast<const SubPatch*>(&patch) != nullptr;
  {
    ScopedTimer timer(times.dice);
    // A sub-leaf's border bounds are not its leaf's: they are not kept in the leaf's table.
    const SharedBorderBounds shared = sub ? SharedBorderBounds{} : sharedBorders(leaf);
    if (interval < 0) dice.dice(patch, m, shared);
    else dice.diceInterval(patch, interval, m, shared);
  }
  if (sub) counters.subLeafDicings.fetch_add(1, std::memory_order_relaxed);
  const uint64_t grids = interval < 0 ? 1 : 2;
  counters.micropolygons.fetch_add(grids << (2 * m), std::memory_order_relaxed);
  counters.dicings.fetch_add(1, std::memory_order_relaxed);
  counters.byLevel[size_t(m)].fetch_add(1, std::memory_order_relaxed);
  if (interval >= 0) counters.movingDicings.fetch_add(1, std::memory_order_relaxed);
  if (std::all_of(slots, slots + count, [&](uint32_t s) { return b.ray[rayOfSlot(s)].originLeaf() == leaf; }))
    counters.originLeafDicings.fetch_add(1, std::memory_order_relaxed);
  if (b.chargeDicings) chargeRun(b, slots, count);
}

// The dicing shared among the run's rays: integer shares summing to exactly one dicing, the
// remainder to the first rays of the run (its order is the sort's, the same at any thread count).
void SortedEngine::chargeRun(RayBatch& b, const uint32_t* slots, size_t count) const {
  const uint64_t share = RayBatch::kDicingShareOne / count, extra = RayBatch::kDicingShareOne % count;
  for (size_t k = 0; k < count; ++k) b.chargeDicing(rayOfSlot(slots[k]), share + (k < extra ? 1 : 0));
}

// A leaf with many rays (a wall seen by most of the image) would serialise the iteration on one
// thread, so its rays are split into chunks that other threads intersect against the same, now
// read-only, buffer; the chunk loop is isolated so this thread cannot pick up another leaf's task
// (which would re-dice its buffer) while it waits.
void SortedEngine::intersectRun(RayBatch& b, const DiceBuffer& dice, const uint32_t* slots, size_t count, uint32_t leaf,
                                const Patch& patch, int m, const uint32_t* entryBits, TraceTimes& times,
                                DicingCounters& counters) {
  auto intersectRange = [&](size_t k0, size_t k1) {
    ScopedTimer timer(times.bottom);
    for (size_t k = k0; k < k1; ++k) {
      const float entry = entryBits ? std::bit_cast<float>(entryBits[k]) : leafEntry(b, rayOfSlot(slots[k]), leaf);
      intersectSlot(b, dice, slots[k], leaf, patch, m, entry);
    }
  };
  forRunChunks(count, intersectRange);
}

// 5. A ray stays active while a leaf it has not seen could still hold a nearer hit (a shadow
// ray: until its first occluder); rays that got no turn stay too. The survivors' hit distance
// becomes their search limit for the next iteration. Returns how many of the finished rays'
// hits lie in a border region: counted on the final hits, so the figure does not depend on
// which leaf's intersection a thread happened to run first.
uint64_t SortedEngine::keepUnfinishedRays(const RayBatch& b, size_t nActive, size_t nNow) {
  size_t kept = 0;  // compacted in place: kept <= a, so no ray is overwritten before it is read
  uint64_t borderHits = 0;
  for (size_t a = 0; a < nActive; ++a) {
    const uint32_t i = active_[a];
    if (a >= nNow) { active_[kept++] = i; continue; }
    const bool exhausted = !(nextEntry_[i] < kInf);
    const bool done = b.ray[i].kind == RayKind::Shadow ? (b.occluded(i) || exhausted)
                                                   : (exhausted || b.hitOf(i).t < nextEntry_[i]);
    if (done) {
      borderHits += b.keepsFullHit(i) && b.hitOf(i).border;
      continue;
    }
    active_[kept++] = i;
  }
  active_.resize(kept);
  return borderHits;
}

void SortedEngine::activeRays(RayBatch& batch, GenerationStats& stats, std::vector<uint32_t>& active) {
  active.clear();
  for (uint32_t i = 0; i < batch.size(); ++i) {
    if (batch.ray[i].kind == RayKind::Inactive) continue;
    batch.clearForTrace(i);
    active.push_back(i);
    ++stats.rays;
    if (batch.ray[i].kind == RayKind::Shadow) ++stats.shadowRays;
  }
}

}  // namespace rayes
