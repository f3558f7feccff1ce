// Runs of rays finer than the resident level (issue 33, item 2): the leaf is diced as 4^d
// sub-leaves (geometry/sub_patch.h), each into a grid of the grid cache or this thread's dice
// buffer, which then needs to hold only the resident level (TraceSettings::residentLod). A ray at level l on the leaf sees
// each sub-leaf at l - d: the vertices of those grids are the leaf's level-l grid, bit for bit,
// and the hits are reported on it (DiceBuffer, "Sub-leaves"), so a split run finds the hits the
// whole leaf would. Seams between sub-leaves need no crack-closing regions (both sides are the
// same vertices at the same level for every ray); the leaf's own borders keep theirs, which
// are the whole leaf's regions (SubPatch::borderPieceBoundsAt).
//
// Which sub-leaves are diced is a function of the run alone (its rays' boxes crossings and
// the hits this run has found so far, in a fixed order), never of what other threads' leaves
// offered meanwhile: the dicing counts stay the same at any thread count. With the grid cache,
// the sub-leaves are keyed (leaf, depth, x, y) and asked for in the serial cache pass, before
// any hit is known: so the run is planned first, each sub-leaf some fine ray's box test reaches
// up to the ray's tmax (a superset of those diced), at the finest of those rays' levels; the
// entries made for sub-leaves the run then does not dice are discarded after the step.
#include <algorithm>
#include <bit>
#include <limits>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include "geometry/moving_patch.h"
#include "rays/kept_hit.h"
#include "rays/run_chunks.h"
#include "rays/sorted_engine.h"

namespace rayes {
namespace {
constexpr float kInf = std::numeric_limits<float>::infinity();

// Whether a ray may hit a sub-leaf before `limit`: its box grown by the margin the dicing's
// traversal takes for that ray from the leaf's box (DiceBuffer), so a sub-leaf whose traversal
// could report a hit is never skipped. One test for the plan and the run, so the run's
// sub-leaves are among the plan's.
class SubLeafReach {
 public:
  explicit SubLeafReach(const Patch& leaf)
      : whole_(leaf.bounds()), magnitude_(maxComponent(vmax(vabs(whole_.lo), vabs(whole_.hi)))) {}
  bool crosses(Vec3 org, Vec3 dir, const Box3& box, float limit) const {
    const float farthest = maxComponent(vmax(vabs(whole_.lo - org), vabs(whole_.hi - org)));
    const float margin = gammaBound(16) * farthest + 0x1p-22f * magnitude_;
    const Vec3 pad{margin, margin, margin};
    float entry, exit;
    return intersectBox(RayBoxQuery(org, dir), box.lo - pad, box.hi + pad, 0.0f, limit, entry, exit);
  }

 private:
  Box3 whole_;
  float magnitude_;
};
}  // namespace

void SortedEngine::diceAndIntersectSplit(RayBatch& b, DiceBuffer& dice, const uint32_t* slots, size_t count,
                                         uint32_t leaf, const PatchPtr& patch, int interval, int m,
                                         const uint32_t* entryBits, TraceTimes& times, DicingCounters& counters) {
  SplitPlan& plan = split_.local().plan;
  planSplitRun(b, slots, count, leaf, patch, m, entryBits, plan);
  runSplitPlan(b, &dice, slots, leaf, plan, interval, times, counters);
  plan.subs.clear();  // a generated leaf's patch lives only for its run
  plan.patch.reset();
}

void SortedEngine::planSplitRun(const RayBatch& b, const uint32_t* slots, size_t count, uint32_t leaf, PatchPtr patch,
                                int m, const uint32_t* entryBits, SplitPlan& p) const {
  const bool density = settings_.lod == LodRule::Density;
  const int resident = residentLevel_;
  p.patch = std::move(patch);
  p.depth = subLeafDepth(m, resident);
  p.coarseLevel = -1;
  p.coarse.clear();
  p.coarseEntry.clear();
  p.fine.clear();
  p.subs.clear();
  p.whole = nullptr;
  p.level.resize(count);
  p.entry.resize(count);
  // A close-up leaf's run holds most of a generation's rays, so its plan, like its run, goes
  // in chunks and sub-leaves that other threads may take: one thread alone was a serial tail
  // of the parallel pass (bench/history/2026-11.md, "The split run's serial tail").
  forRunChunks(count, [&](size_t k0, size_t k1) {
    for (size_t k = k0; k < k1; ++k) {
      const float entry = entryBits ? std::bit_cast<float>(entryBits[k]) : leafEntry(b, rayOfSlot(slots[k]), leaf);
      p.entry[k] = entry;
      p.level[k] = uint8_t(density ? m : levelFor(b, rayOfSlot(slots[k]), leaf, entry));
    }
  });
  for (size_t k = 0; k < count; ++k) {
    const int level = p.level[k];
    if (level <= resident) {
      p.coarse.push_back(slots[k]);
      p.coarseEntry.push_back(p.entry[k]);
      p.coarseLevel = std::max(p.coarseLevel, level);
    } else {
      p.fine.push_back(uint32_t(k));
    }
  }
  if (p.fine.empty()) return;
  const SubLeafReach reach(*p.patch);
  const uint32_t n = 1u << p.depth;
  // The finest level any fine ray asks: a sub-leaf one of those rays reaches needs no more, so
  // its search stops there. Without the stop the plan tests every fine ray against every
  // sub-leaf (bench/history/2026-11.md, "the split run's plan").
  int finest = -1;
  for (const uint32_t k : p.fine) finest = std::max(finest, int(p.level[k]) - p.depth);
  // Each sub-leaf's search is its own: they run in parallel, kept in row order.
  p.subs.resize(size_t(n) * n);
  tbb::this_task_arena::isolate([&] {
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, n * n, 1), [&](const tbb::blocked_range<uint32_t>& r) {
      for (uint32_t j = r.begin(); j != r.end(); ++j) {
        auto sub = std::make_shared<const SubPatch>(p.patch, p.depth, j % n, j / n);
        const Box3 box = sub->bounds();
        int level = -1;
        for (const uint32_t k : p.fine) {
          const uint32_t i = rayOfSlot(slots[k]);
          // levelFor > resident >= depth (residentLevelFor): each level on a sub-leaf is >= 0.
          const int needs = int(p.level[k]) - p.depth;
          if (needs > level && reach.crosses(b.ray[i].org, b.ray[i].dir(), box, searchLimit(b, i, kInf))) {
            level = needs;
            if (level == finest) break;
          }
        }
        p.subs[j] = {level >= 0 ? std::move(sub) : nullptr, level, nullptr};
      }
    });
  });
  std::erase_if(p.subs, [](const SplitPlan::Sub& s) { return s.level < 0; });
}

uint64_t SortedEngine::acquireSplitGrids(uint32_t leaf, SplitPlan& p) {
  uint64_t hit = 0;
  if (p.coarseLevel >= 0) {
    p.whole = cache_.acquire(leaf, p.coarseLevel);
    hit = p.whole && !p.whole->toDice;
  }
  for (SplitPlan::Sub& s : p.subs) s.grid = cache_.acquire(GridKey(leaf, p.depth, s.patch->x(), s.patch->y()), s.level);
  return hit;
}

void SortedEngine::runSplitPlan(RayBatch& b, DiceBuffer* dice, const uint32_t* slots, uint32_t leaf, SplitPlan& p,
                                int interval, TraceTimes& times, DicingCounters& counters) {
  SplitScratch& sc = split_.local();
  auto buffer = [&]() -> DiceBuffer& { return dice ? *dice : localDiceBuffer(); };
  counters.splitRuns.fetch_add(1, std::memory_order_relaxed);
  // The run's rays that need no more than the resident level: the whole leaf, as usual.
  if (!p.coarse.empty()) {
    const DiceBuffer* grid;
    if (p.whole) {
      if (p.whole->toDice && !p.whole->patch) {
        p.whole->patch = p.patch;  // kept with the grid: border queries read it
        diceRun(b, p.whole->gridToDice(), p.coarse.data(), p.coarse.size(), leaf, *p.patch, interval, p.coarseLevel, times,
                counters);
      }
      grid = p.whole->grid.get();
    } else {
      DiceBuffer& d = buffer();
      diceRun(b, d, p.coarse.data(), p.coarse.size(), leaf, *p.patch, interval, p.coarseLevel, times, counters);
      grid = &d;
    }
    // A close-up leaf's run is most of a generation's rays on one leaf: one thread alone would
    // be a serial tail of the parallel step (bench/history/2026-11.md, "The split run's serial
    // tail"), so its slots go in chunks, as intersectRun's.
    forRunChunks(p.coarse.size(), [&](size_t c0, size_t c1) {
      ScopedTimer timer(times.bottom);
      for (size_t c = c0; c < c1; ++c) intersectSlot(b, *grid, p.coarse[c], leaf, *p.patch, p.coarseLevel, p.coarseEntry[c]);
    });
  }
  if (p.fine.empty()) return;
  // The others: the planned sub-leaves, row by row. A ray's nearest hit in this run so far
  // bounds its search in the sub-leaves after (a shadow ray's first occluder ends it). Each
  // ray's `best` depends on its own hits alone, so chunks of rays may run on any thread.
  sc.best.assign(p.fine.size(), kInf);
  sc.reaches.resize(p.fine.size());
  const SubLeafReach reach(*p.patch);
  for (SplitPlan::Sub& s : p.subs) {
    const SubPatch& sub = *s.patch;
    const Box3 box = sub.bounds();
    forRunChunks(p.fine.size(), [&](size_t f0, size_t f1) {
      for (size_t f = f0; f < f1; ++f) {
        const uint32_t i = rayOfSlot(slots[p.fine[f]]);
        // best < 0: a shadow ray already occluded.
        sc.reaches[f] = sc.best[f] >= 0 && reach.crosses(b.ray[i].org, b.ray[i].dir(), box, searchLimit(b, i, sc.best[f]));
      }
    });
    sc.sub.clear();
    sc.subSlot.clear();
    int subLevel = 0;
    for (size_t f = 0; f < p.fine.size(); ++f) {
      if (!sc.reaches[f]) continue;
      const uint32_t k = p.fine[f];
      sc.sub.push_back(uint32_t(f));
      sc.subSlot.push_back(slots[k]);
      subLevel = std::max(subLevel, int(p.level[k]) - p.depth);
    }
    if (sc.sub.empty()) continue;
    const DiceBuffer* grid;
    if (s.grid) {
      // Diced at the planned level, which serves every ray of the plan (subLevel <= s.level).
      if (s.grid->toDice && !s.grid->patch) {
        s.grid->patch = s.patch;
        diceRun(b, s.grid->gridToDice(), sc.subSlot.data(), sc.subSlot.size(), leaf, sub, interval, s.level, times, counters);
      } else {
        counters.subLeafCacheHits.fetch_add(1, std::memory_order_relaxed);
      }
      grid = s.grid->grid.get();
    } else {
      DiceBuffer& d = buffer();
      diceRun(b, d, sc.subSlot.data(), sc.subSlot.size(), leaf, sub, interval, subLevel, times, counters);
      grid = &d;
    }
    forRunChunks(sc.sub.size(), [&](size_t j0, size_t j1) {
      ScopedTimer timer(times.bottom);
      for (size_t j = j0; j < j1; ++j) {
        const uint32_t f = sc.sub[j], k = p.fine[f];
        const float t = intersectSubLeafSlot(b, *grid, slots[k], leaf, *p.patch, sub, p.level[k], p.entry[k], sc.best[f]);
        sc.best[f] = std::min(sc.best[f], t);
      }
    });
  }
}

float SortedEngine::intersectSubLeafSlot(RayBatch& b, const DiceBuffer& dice, uint32_t s, uint32_t leaf,
                                         const Patch& patch, const SubPatch& sub, int level, float entry, float best) {
  const uint32_t i = rayOfSlot(s);
  const bool shadow = b.ray[i].kind == RayKind::Shadow;
  const Vec3 dir = b.ray[i].dir();  // decoded once for the slot
  BottomQuery query;
  query.alpha = dice.moving() ? timeInterval(patch, b.timeOf(i)).alpha : 0.0f;
  query.closeBorders = closeBordersFor(b, i, leaf);
  if (query.closeBorders) {
    // The leaf's borders as for the whole leaf (level > the thin levels: `dice` is not read);
    // the seams between sub-leaves need no region.
    bordersClosedByNeighbours(b, i, RayBoxQuery(b.ray[i].org, dir), leaf, level, patch, dice, query);
    for (int e = 0; e < 4; ++e)
      if (!sub.onParentBorder(e)) query.skipBorders |= uint8_t(1u << e);
  }
  const int subLevel = level - sub.depth();
  const float limit = searchLimit(b, i, best);
  if (shadow) {
    if (!dice.occluded(b.ray[i].org, dir, 0.0f, limit, subLevel, query)) return kInf;
    offerOccluder(b, i, leaf, level);
    return -1.0f;  // done: no later sub-leaf can matter
  }
  GridHit h;
  if (!dice.intersect(b.ray[i].org, dir, 0.0f, limit, subLevel, h, query)) return kInf;
  const HitDerivatives d = keptDerivatives(h);
  const RayHit r = hitRecord(h, leaf, level, entry);
  offerHit(b, i, r, &d);
  return r.t;
}

}  // namespace rayes
