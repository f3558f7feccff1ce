// Runs of rays finer than the resident level (issue 33, item 2): the leaf is diced as 4^d
// sub-leaves (geometry/sub_patch.h), each into this thread's dice buffer, which then needs to
// hold only the resident level (TraceSettings::residentLod). A ray at level l on the leaf sees
// each sub-leaf at l - d: the vertices of those grids are the leaf's level-l grid, bit for bit,
// and the hits are reported on it (DiceBuffer, "Sub-leaves"), so a split run finds the hits the
// whole leaf would. Seams between sub-leaves need no crack-closing regions (both sides are the
// same vertices at the same level for every ray); the leaf's own borders keep theirs, which
// are the whole leaf's regions (SubPatch::borderPieceBoundsAt).
//
// Which sub-leaves are diced is a function of the run alone (its rays' boxes crossings and
// the hits this run has found so far, in a fixed order), never of what other threads' leaves
// offered meanwhile: the dicing counts stay the same at any thread count.
#include <algorithm>
#include <bit>
#include <limits>
#include "geometry/moving_patch.h"
#include "rays/kept_hit.h"
#include "rays/sorted_engine.h"

namespace rayes {
namespace {
constexpr float kInf = std::numeric_limits<float>::infinity();
}  // namespace

void SortedEngine::diceAndIntersectSplit(RayBatch& b, DiceBuffer& dice, const uint32_t* slots, size_t count,
                                         uint32_t leaf, const PatchPtr& patch, int interval, int m,
                                         const uint32_t* entryBits, TraceTimes& times, DicingCounters& counters) {
  SplitScratch& sc = split_.local();
  const bool density = settings_.lod == LodRule::Density;
  const int resident = residentLevel_;
  sc.coarse.clear();
  sc.fine.clear();
  sc.level.resize(count);
  sc.entry.resize(count);
  int coarseLevel = 0;
  for (size_t k = 0; k < count; ++k) {
    const uint32_t i = rayOfSlot(slots[k]);
    const float entry = entryBits ? std::bit_cast<float>(entryBits[k]) : leafEntry(b, i, leaf);
    const int level = density ? m : levelFor(b, i, leaf, entry);
    sc.entry[k] = entry;
    sc.level[k] = uint8_t(level);
    if (level <= resident) {
      sc.coarse.push_back(slots[k]);
      coarseLevel = std::max(coarseLevel, level);
    } else {
      sc.fine.push_back(uint32_t(k));
    }
  }
  counters.splitRuns.fetch_add(1, std::memory_order_relaxed);
  // The run's rays that need no more than the resident level: the whole leaf, as usual.
  if (!sc.coarse.empty()) {
    diceRun(b, dice, sc.coarse.data(), sc.coarse.size(), leaf, *patch, interval, coarseLevel, times, counters);
    ScopedTimer timer(times.bottom);
    size_t c = 0;
    for (size_t k = 0; k < count; ++k)
      if (sc.level[k] <= resident) intersectSlot(b, dice, sc.coarse[c++], leaf, *patch, coarseLevel, sc.entry[k]);
  }
  if (sc.fine.empty()) return;
  // The others: sub-leaves of depth d, row by row. A ray's nearest hit in this run so far
  // bounds its search in the sub-leaves after (a shadow ray's first occluder ends it).
  const int d = subLeafDepth(m, resident);
  const uint32_t n = 1u << d;
  sc.best.assign(sc.fine.size(), kInf);
  // Each ray's box margin as the dicing's traversal takes it from the leaf's box (DiceBuffer):
  // a sub-leaf whose traversal could report a hit is never skipped by this test.
  const Box3 whole = patch->bounds();
  const float magnitude = maxComponent(vmax(vabs(whole.lo), vabs(whole.hi)));
  auto marginOf = [&](Vec3 org) {
    const float farthest = maxComponent(vmax(vabs(whole.lo - org), vabs(whole.hi - org)));
    return gammaBound(16) * farthest + 0x1p-22f * magnitude;
  };
  for (uint32_t y = 0; y < n; ++y)
    for (uint32_t x = 0; x < n; ++x) {
      const SubPatch sub(patch, d, x, y);
      const Box3 box = sub.bounds();
      sc.sub.clear();
      sc.subSlot.clear();
      int subLevel = 0;
      for (size_t f = 0; f < sc.fine.size(); ++f) {
        if (sc.best[f] < 0) continue;  // a shadow ray already occluded
        const uint32_t k = sc.fine[f], i = rayOfSlot(slots[k]);
        float entry, exit;
        const float margin = marginOf(b.ray[i].org);
        const Vec3 pad{margin, margin, margin};
        if (!intersectBox(RayBoxQuery(b.ray[i].org, b.ray[i].dir), box.lo - pad, box.hi + pad, 0.0f,
                          searchLimit(b, i, sc.best[f]), entry, exit))
          continue;
        sc.sub.push_back(uint32_t(f));
        sc.subSlot.push_back(slots[k]);
        subLevel = std::max(subLevel, int(sc.level[k]) - d);
      }
      if (sc.sub.empty()) continue;
      diceRun(b, dice, sc.subSlot.data(), sc.subSlot.size(), leaf, sub, interval, subLevel, times, counters);
      ScopedTimer timer(times.bottom);
      for (const uint32_t f : sc.sub) {
        const uint32_t k = sc.fine[f];
        const float t = intersectSubLeafSlot(b, dice, slots[k], leaf, *patch, sub, sc.level[k], sc.entry[k], sc.best[f]);
        sc.best[f] = std::min(sc.best[f], t);
      }
    }
}

float SortedEngine::intersectSubLeafSlot(RayBatch& b, const DiceBuffer& dice, uint32_t s, uint32_t leaf,
                                         const Patch& patch, const SubPatch& sub, int level, float entry, float best) {
  const uint32_t i = rayOfSlot(s);
  const bool shadow = b.ray[i].kind == RayKind::Shadow;
  BottomQuery query;
  query.alpha = dice.moving() ? timeInterval(patch, b.timeOf(i)).alpha : 0.0f;
  query.closeBorders = closeBordersFor(b, i, leaf);
  if (query.closeBorders) {
    // The leaf's borders as for the whole leaf (level > the thin levels: `dice` is not read);
    // the seams between sub-leaves need no region.
    bordersClosedByNeighbours(b, i, leaf, level, patch, dice, query);
    for (int e = 0; e < 4; ++e)
      if (!sub.onParentBorder(e)) query.skipBorders |= uint8_t(1u << e);
  }
  const int subLevel = level - sub.depth();
  const float limit = searchLimit(b, i, best);
  if (shadow) {
    if (!dice.occluded(b.ray[i].org, b.ray[i].dir, 0.0f, limit, subLevel, query)) return kInf;
    offerOccluder(b, i, leaf, level);
    return -1.0f;  // done: no later sub-leaf can matter
  }
  GridHit h;
  if (!dice.intersect(b.ray[i].org, b.ray[i].dir, 0.0f, limit, subLevel, h, query)) return kInf;
  const HitDerivatives d = keptDerivatives(h);
  const RayHit r = hitRecord(h, leaf, level, entry);
  offerHit(b, i, r, &d);
  return r.t;
}

}  // namespace rayes
