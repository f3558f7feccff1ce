#include "rays/caching_engine.h"
#include <algorithm>
#include <iterator>
#include <stdexcept>
#include "geometry/moving_patch.h"

namespace rayes {
namespace {
TraceSettings withOneCandidateSlot(TraceSettings s) {
  s.candidateCapacity = 1;  // traceRayAlone uses none
  return s;
}
}  // namespace

CachingEngine::CachingEngine(const TopLevelBvh& top, const LeafSource& leaves,
                             const TraceSettings& settings, size_t entries)
    : sorted_(top, leaves, withOneCandidateSlot(settings)), capacity_(entries) {
  if (entries < 1) throw std::invalid_argument("CachingEngine: the cache needs at least one entry");
}

void CachingEngine::trace(RayBatch& batch, GenerationStats& stats, TraceTimes& times) {
  SortedEngine::activeRays(batch, stats, active_);
  const SortedEngine::GridSource source = [&](uint32_t leaf, const PatchPtr& patch, int interval, int level) -> const DiceBuffer& {
    return gridFor(leaf, patch, interval, level, stats, times);
  };
  // times.bottom includes the dicing; times.dice holds the dicing alone.
  {
    ScopedTimer timer(times.bottom);
    for (uint32_t i : active_) {
      const uint64_t missesBefore = misses_;  // a miss is a dicing for this ray alone
      sorted_.traceRayAlone(batch, i, source, scratch_);
      if (batch.chargeDicings && misses_ > missesBefore) batch.chargeDicing(i, (misses_ - missesBefore) * RayBatch::kDicingShareOne);
    }
  }
  stats.iterations.push_back({active_.size(), 0.0, 0});
  // No per-leaf stage: the leaf queries grouped by leaf, in a plain loop.
  if (batch.queries && queries_.group(*batch.queries)) queries_.runAll(times.leafQueries);
}

const DiceBuffer& CachingEngine::gridFor(uint32_t leaf, const PatchPtr& patch, int interval, int level, GenerationStats& stats,
                                         TraceTimes& times) {
  const uint64_t key = uint64_t(leaf) << 32 | uint32_t(interval);
  if (auto found = index_.find(key); found != index_.end()) {
    lru_.splice(lru_.begin(), lru_, found->second);
    Entry& e = lru_.front();
    if (e.grid->level() >= level) {
      ++hits_;
      return *e.grid;
    }
    diceInto(e, patch, interval, level, stats, times);  // held too coarse for this ray
    return *e.grid;
  }
  if (lru_.size() < capacity_) {
    lru_.push_front(Entry{key, nullptr, nullptr});
  } else {
    index_.erase(lru_.back().key);
    lru_.splice(lru_.begin(), lru_, std::prev(lru_.end()));
    lru_.front().key = key;
  }
  index_[key] = lru_.begin();
  diceInto(lru_.front(), patch, interval, level, stats, times);
  return *lru_.front().grid;
}

// A buffer is reused only at its own level: a finer one would hold an evicted fine grid's memory
// for every later coarse one, and K such entries add up.
void CachingEngine::diceInto(Entry& e, const PatchPtr& patch, int interval, int level, GenerationStats& stats,
                                         TraceTimes& times) {
  ++misses_;
  if (!e.grid || e.grid->maxLevel() != level) {
    if (e.grid) bytes_ -= e.grid->bytesAllocated();
    e.grid = std::make_unique<DiceBuffer>(level);
    bytes_ += e.grid->bytesAllocated();
  }
  const size_t before = e.grid->bytesAllocated();
  {
    ScopedTimer timer(times.dice);
    e.grid->diceInterval(*patch, interval, level);
    e.patch = patch;
  }
  bytes_ += e.grid->bytesAllocated() - before;  // a moving patch's second sample, allocated on first use
  peakBytes_ = std::max(peakBytes_, bytes_);
  ++stats.leavesDiced;
  stats.micropolygonsCreated += uint64_t(e.grid->moving() ? 2 : 1) << (2 * level);
  if (e.grid->moving()) ++stats.movingDicings;
}

EngineStats CachingEngine::engineStats() const {
  EngineStats s;
  s.name = "dice-cache";
  s.fixedBytes = peakBytes_;
  s.maxLevel = sorted_.settings().maxLod;
  s.cacheEntries = capacity_;
  s.cacheHits = hits_;
  s.cacheMisses = misses_;
  s.cachePeakBytes = peakBytes_;
  s.cacheBytes = bytes_;
  return s;
}

}  // namespace rayes
