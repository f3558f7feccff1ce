// The SortedEngine's one-ray-at-a-time walk: a ray's candidates front to back, each leaf diced
// (or taken from the caller's grid source) at that ray's own level. No sorting and no sharing:
// the reference the sorted pipeline must match (--trace-mode alone), and the walk the
// CachingEngine runs every ray through (rays/caching_engine.h). It records hits as the pipeline
// does (rays/kept_hit.h), so the two agree bit for bit.
#include "rays/sorted_engine.h"
#include <atomic>
#include <limits>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include "geometry/moving_patch.h"
#include "rays/kept_hit.h"

namespace rayes {
namespace {
constexpr float kInf = std::numeric_limits<float>::infinity();
}  // namespace

// Debug mode: every ray alone, its candidates in order, each leaf diced for that ray only at
// that ray's level. No sorting, no sharing: the reference the sorted pipeline must match.
void SortedEngine::traceAlone(RayBatch& b, GenerationStats& stats, TraceTimes& times) {
  std::atomic<uint64_t> diced{0}, micropolygons{0}, moving{0};
  ScopedTimer timer(times.bottom);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, active_.size(), 16), [&](const auto& r) {
    auto& scratch = scratch_.local();
    DiceBuffer& dice = localDiceBuffer(true);  // at any level: this debug walk does not split leaves
    uint64_t dicedForThisRay = 0;  // each dicing here is one ray's alone (RayBatch::chargeDicings)
    const GridSource diceForThisRay = [&](uint32_t leaf, const PatchPtr& patch, int interval, int level) -> const DiceBuffer& {
      dice.diceInterval(*patch, interval, level, sharedBorders(leaf));
      ++dicedForThisRay;
      diced.fetch_add(1, std::memory_order_relaxed);
      micropolygons.fetch_add(uint64_t(dice.moving() ? 2 : 1) << (2 * level), std::memory_order_relaxed);
      if (dice.moving()) moving.fetch_add(1, std::memory_order_relaxed);
      return dice;
    };
    for (size_t a = r.begin(); a != r.end(); ++a) {
      dicedForThisRay = 0;
      traceRayAlone(b, active_[a], diceForThisRay, scratch);
      if (b.chargeDicings && dicedForThisRay) b.chargeDicing(active_[a], dicedForThisRay * RayBatch::kDicingShareOne);
    }
  });
  stats.leavesDiced += diced.load();
  stats.micropolygonsCreated += micropolygons.load();
  stats.movingDicings += moving.load();
  stats.iterations.push_back({active_.size(), 16.0, 0});
}

void SortedEngine::traceRayAlone(RayBatch& b, uint32_t i, const GridSource& gridFor, TraversalScratch& scratch) const {
  // A shadow slot that keeps only its occluder (RayBatch::shadowPairs) walks with a local record.
  RayHit walked;
  RayHit& best = b.keepsFullHit(i) ? b.hitOf(i) : walked;
  float resumeEntry = -kInf;
  uint32_t resumeLeaf = 0;
  Candidate local[16];
  const Vec3 dir = b.ray[i].dir();  // decoded once for the walk
  const RayBoxQuery q(b.ray[i].org, dir);
  for (;;) {
    float next = kInf;
    const int got = top_.collect(b.ray[i].org, dir, 0.0f, searchLimit(b, i, best.t), resumeEntry, resumeLeaf, local, 16,
                                 next, scratch);
    for (int j = 0; j < got; ++j) {
      const uint32_t leaf = local[j].leaf;
      // Brick leaves are the sorted pipeline's; a ray walked alone is tracked by its owner.
      if (leaf == b.ray[i].ignoreLeaf || isBrickLeaf(leaf)) continue;
      const float entry = leafEntry(q, leaf);  // the level's footprint distance and the hit's floor
      const int level = levelFor(b, i, leaf, entry);
      const PatchPtr made = leaves_.patch(leaf);  // generated leaves: made here, dropped after
      const TimeInterval when = timeInterval(*made, b.timeOf(i));
      const DiceBuffer& dice = gridFor(leaf, made, when.interval, level);
      const float limit = searchLimit(b, i, best.t);
      BottomQuery query;
      query.alpha = when.alpha;
      query.closeBorders = closeBordersFor(b, i, leaf);
      if (query.closeBorders) bordersClosedByNeighbours(b, i, q, leaf, level, *made, dice, query);
      if (b.ray[i].kind == RayKind::Shadow) {
        if (dice.occluded(b.ray[i].org, dir, 0.0f, limit, level, query)) {
          best.t = 0; best.leaf = leaf; best.level = static_cast<uint8_t>(level);
          b.occluderOf(i) = leaf;
          break;
        }
        continue;
      }
      GridHit h;
      if (dice.intersect(b.ray[i].org, dir, 0.0f, limit, level, h, query) &&
          nearerHit(keptDistance(h.t, entry), leaf, h.quad, best)) {
        best = hitRecord(h, leaf, level, entry);
        if (HitDerivatives* kept = b.derivativesOf(i)) *kept = keptDerivatives(h);
      }
    }
    if (got > 0) { resumeEntry = local[got - 1].entry; resumeLeaf = local[got - 1].leaf; }
    const bool exhausted = !(next < kInf);
    if (b.ray[i].kind == RayKind::Shadow ? (best.valid() || exhausted) : (exhausted || best.t < next)) break;
  }
}

}  // namespace rayes
