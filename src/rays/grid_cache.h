// Diced grids kept between the iterations and generations of the sorted pipeline
// (SortedEngine): a leaf whose rays arrive in several iterations (a camera ray's later
// candidates, shadow and bounce rays through the same canopy) is diced once while its grid stays
// cached, instead of once per iteration that has rays for it. A grid is a leaf diced whole or
// one of its sub-leaves (a run finer than the resident level; geometry/sub_patch.h), each its
// own entry under its GridKey.
//
// Contract:
// - Decisions (hit, a new entry to dice into, or not cached) are made by acquire(), serially, in
//   the sorted run order of an iteration (a split run's sub-leaves in row order after its whole
//   leaf), so the cache's history and the dicing counts are the same for every thread count.
//   The entries handed out in one iteration are pinned until nextIteration(): acquire never
//   evicts them, so the parallel dice/intersect step can use them. An entry made to dice into
//   that the step did not dice after all is given back by discard(), serially, before the next
//   acquire.
// - Images do not depend on the cache or its budget: a grid held at level m serves every ray at a
//   level <= m bit for bit (the coarser levels are exact subgrids; docs/architecture.md; a
//   sub-leaf's too, its vertices being the leaf's), and a grid needed finer than held is diced
//   again at the finer level.
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
#include "geometry/sub_patch.h"

namespace rayes {

// What a cached grid is a dicing of: leaf `leaf` whole (depth 0), or its sub-leaf (depth, x, y),
// x, y < 2^depth (SubPatch). Sub-leaves of different depths are different grids.
struct GridKey {
  uint32_t leaf = 0;
  uint8_t depth = 0, x = 0, y = 0;
  GridKey(uint32_t wholeLeaf) : leaf(wholeLeaf) {}  // NOLINT: a leaf id names its whole grid
  GridKey(uint32_t leaf_, int depth_, uint32_t x_, uint32_t y_)
      : leaf(leaf_), depth(uint8_t(depth_)), x(uint8_t(x_)), y(uint8_t(y_)) {}
  uint64_t packed() const { return uint64_t(leaf) << 24 | uint64_t(depth) << 16 | uint64_t(x) << 8 | y; }
  bool operator==(const GridKey&) const = default;
};
static_assert(SubPatch::kMaxDepth <= 8, "GridKey: a sub-leaf's x and y fit a byte");

class GridCache {
 public:
  struct Entry {
    GridKey key = 0;
    int level = 0;          // the grid's level (its DiceBuffer's maxLevel)
    std::unique_ptr<DiceBuffer> grid;  // null until the caller first dices into the entry
    PatchPtr patch;        // set by whoever dices into `grid`
    bool toDice = false;   // acquire() made or re-made the entry: the caller dices into it
    uint64_t lastUse = 0;  // iteration of the last acquire
    // The grid to dice into, made on first use. The serial acquire() only decides and charges
    // the bytes (DiceBuffer::bytesFor): making each new grid there (allocating it, clearing
    // its border table) was a serial part of every iteration, 2.6 % of forest-100's samples at
    // 2 threads (bench/history/2026-11.md, "quiet figures at 7069dff"); the parallel step makes it.
    DiceBuffer& gridToDice() {
      if (!grid) grid = std::make_unique<DiceBuffer>(level);
      return *grid;
    }
  };

  explicit GridCache(size_t budgetBytes) : budget_(budgetBytes) {}
  bool enabled() const { return budget_ > 0; }

  // The entry holding the grid `key` names diced at `level` or finer (toDice false), or one for
  // a new grid of `level` (toDice true: the caller must dice gridToDice() at `level` and set
  // patch, or discard it, before the next acquire of that key; entries of one iteration may do
  // so concurrently), evicting least recently used
  // entries that are not pinned; nullptr when the grid does not fit beside the pinned ones. A
  // leaf whole and its sub-leaves are separate entries: neither serves the other.
  Entry* acquire(GridKey key, int level);
  // Gives back an entry acquire() made in this iteration for the caller to dice into (toDice)
  // that it did not dice (patch still null): freed, its bytes no longer counted. Not counted
  // as a hit; entries evicted to make room for it stay evicted.
  void discard(Entry* entry);
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
  std::unordered_map<uint64_t, std::list<Entry>::iterator> index_;  // by GridKey::packed
  uint64_t iteration_ = 1;
  size_t bytes_ = 0, peakBytes_ = 0;
  uint64_t hits_ = 0;
};

}  // namespace rayes
