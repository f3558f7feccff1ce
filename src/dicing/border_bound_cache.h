// A fixed-capacity table of the border bounds of static dicings (DiceBuffer's border regions),
// shared by every dicing of one render so that re-dicing a leaf does not recompute them.
//
// Contract:
// - What it holds: per (leaf, border e, level, segment j) the box of the true border curve over
//   the segment and the two radii of its region (DiceBuffer::curveBox, cachedRadius); or, in a
//   table of its own, per displaced seam and level the gap between its two sides' border
//   vertices (SortedEngine::seamGap, segment 0, under SortedEngine::seamKey). Each is a
//   pure function of its key (the leaf's patch is generated the same way every time), so a hit
//   returns exactly the value a recomputation would give: images do not depend on the table,
//   its capacity or which thread filled an entry (docs/design.md, invariant on determinism).
// - Bound: `capacity` entries (a power of two) of entryBytes() each, allocated on the first
//   insert and never grown: it does not grow with the micro-polygons (the SortedEngine chooses the
//   capacity from the leaf count, SortedEngine::kBorderBoundsPerLeaf, up to a cap). Direct mapped:
//   an insert overwrites whatever entry its key hashes to (eviction by collision).
// - Threads: lookup and insert may run concurrently from any thread without locks. Each entry
//   is a seqlock: a writer that finds it being written gives up (the value is simply not kept),
//   and a reader that sees it change reports a miss. Either way the caller recomputes.
#pragma once
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include "core/box.h"

namespace rayes {

class BorderBoundCache {
 public:
  enum class Kind : uint32_t { CurveBox = 0, CoarseRadius = 1, FineRadius = 2, SeamGap = 3 };
  struct Key {
    uint32_t leaf = 0;
    Kind kind = Kind::CurveBox;
    int border = 0;    // 0..3
    int level = 0;     // 0..15
    uint32_t segment = 0;  // < 2^16
  };

  // `capacity` is rounded up to a power of two (at least 1).
  explicit BorderBoundCache(size_t capacity);
  BorderBoundCache(const BorderBoundCache&) = delete;
  BorderBoundCache& operator=(const BorderBoundCache&) = delete;

  bool find(const Key& key, Box3& box) const;
  bool find(const Key& key, double& radius) const;
  void insert(const Key& key, const Box3& box);
  void insert(const Key& key, double radius);

  size_t capacity() const { return mask_ + 1; }
  static constexpr size_t entryBytes() { return sizeof(Entry); }
  // Bytes held: 0 until the first insert, then capacity() * entryBytes().
  size_t bytes() const { return allocated_.load(std::memory_order_acquire) ? capacity() * entryBytes() : 0; }

 private:
  // seq is odd while a writer fills the entry; key 0 is never a valid key (bit 63 is set).
  struct Entry {
    std::atomic<uint64_t> seq{0};
    std::atomic<uint64_t> key{0};
    std::atomic<uint32_t> words[6] = {0, 0, 0, 0, 0, 0};  // a box's 6 floats, or a double in 2
  };
  static uint64_t pack(const Key& key);
  bool read(uint64_t key, uint32_t (&words)[6]) const;
  void write(uint64_t key, const uint32_t (&words)[6]);

  size_t mask_;
  std::unique_ptr<Entry[]> entries_;
  std::atomic<bool> allocated_{false};
  std::once_flag allocate_;
};

}  // namespace rayes
