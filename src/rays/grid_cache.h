// Diced grids kept between the iterations and generations of the sorted pipeline
// (SortedEngine): a leaf whose rays arrive in several iterations (a camera ray's later
// candidates, shadow and bounce rays through the same canopy) is diced once while its grid stays
// cached, instead of once per iteration that has rays for it.
//
// Contract:
// - Decisions (hit, a new entry to dice into, or not cached) are made by acquire(), serially, in
//   the sorted run order of an iteration, so the cache's history and the dicing counts are the
//   same for every thread count. The entries handed out in one iteration are pinned until
//   nextIteration(): acquire never evicts them, so the parallel dice/intersect step can use them.
// - Images do not depend on the cache or its budget: a grid held at level m serves every ray at a
//   level <= m bit for bit (the coarser levels are exact subgrids; docs/architecture.md), and a
//   leaf needed finer than held is diced again at the finer level.
// - Memory: at most budgetBytes of DiceBuffer::bytesAllocated over the entries (plus each entry's
//   patch, which generated leaves make on demand and which border queries read), least recently
//   used out first. Budget 0: disabled. Not thread-safe; static leaves only (a moving leaf is
//   diced per time interval of its rays).
#pragma once
#include <cstddef>
#include <cstdint>
#include <list>
#include <memory>
#include <unordered_map>
#include "dicing/dice_buffer.h"
#include "geometry/patch.h"

namespace rayes {

class GridCache {
 public:
  struct Entry {
    uint32_t leaf = 0;
    int level = 0;          // the grid's level (its DiceBuffer's maxLevel)
    std::unique_ptr<DiceBuffer> grid;  // null until the caller first dices into the entry
    PatchPtr patch;        // set by whoever dices into `grid`
    bool toDice = false;   // acquire() made or re-made the entry: the caller dices into it
    uint64_t lastUse = 0;  // iteration of the last acquire
    // The grid to dice into, made on first use. The serial acquire() only decides and charges
    // the bytes (DiceBuffer::bytesFor): making each new grid there (allocating it, clearing
    // its border table) was a serial part of every iteration, 2.6 % of forest-100's samples at
    // 2 threads (bench/history/2026-11.md, "1 -> 2 threads"); the parallel step makes it.
    DiceBuffer& gridToDice() {
      if (!grid) grid = std::make_unique<DiceBuffer>(level);
      return *grid;
    }
  };

  explicit GridCache(size_t budgetBytes) : budget_(budgetBytes) {}
  bool enabled() const { return budget_ > 0; }

  // The entry holding `leaf` diced at `level` or finer (toDice false), or one for a new grid of
  // `level` (toDice true: the caller must dice gridToDice() at `level` and set patch before the
  // next acquire of that leaf; entries of one iteration may do so concurrently), evicting least recently used entries that are not pinned;
  // nullptr when the grid does not fit beside the pinned ones.
  Entry* acquire(uint32_t leaf, int level);
  // Ends an iteration: its entries become evictable.
  void nextIteration() { ++iteration_; }
  // A new budget (0: disabled), least recently used entries out until the rest fit. Only between
  // traces: entries handed out in the current iteration are evicted too.
  void setBudget(size_t budgetBytes);

  size_t bytes() const { return bytes_; }
  size_t peakBytes() const { return peakBytes_; }
  size_t entries() const { return lru_.size(); }
  uint64_t hits() const { return hits_; }

 private:
  // Frees least recently used unpinned entries until `need` more bytes fit; false if they cannot.
  bool makeRoom(size_t need);
  void erase(std::list<Entry>::iterator it);

  size_t budget_;
  std::list<Entry> lru_;  // front: most recently used
  std::unordered_map<uint32_t, std::list<Entry>::iterator> index_;
  uint64_t iteration_ = 1;
  size_t bytes_ = 0, peakBytes_ = 0;
  uint64_t hits_ = 0;
};

}  // namespace rayes
