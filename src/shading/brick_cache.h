// The render's bounded cache of volume bricks (`--volume-memory BYTES`): dense blocks of 8³
// float voxels read from their file (a BrickSource: scene/volume_shape_reader.cpp reads one
// OpenVDB leaf node per block) only when a ray's tracking needs them, and evicted under the
// budget. One cache serves every brick grid of the scene (keys are grid id and brick).
//
// A slot holds its brick with a one-voxel apron (10³ voxels, local coordinates −1 … 8 on each
// axis), so a trilinear lookup anywhere in the brick's cell (docs/design.md, "Volumes") reads
// the slot alone. The 26 apron regions (6 faces, 12 edges, 8 corners, each the voxels of one
// neighbour brick) are filled when a lookup first needs them while the slot holds this brick
// (fillApron, by the reader that found the region empty, from the neighbour), not at the load:
// filling all of them would read up to 26 neighbours per miss, most of whose faces no sample
// ever reaches. The apron is counted in kSlotBytes, so in the budget and the memory plan.
//
// Why our own cache of dense blocks rather than OpenVDB's own delayed loading alone: OpenVDB
// loads an out-of-core leaf into that leaf and never releases it, so a tree it delay-loads only
// grows. The reader keeps the tree with every leaf out of core and loads a copy of one leaf's
// buffer per miss (LeafBuffer's copy keeps the file reference), so what is resident is exactly
// this cache's slots.
//
// Thread-safe: shards (by key hash), each a mutex, a CLOCK ring of slots and a key → slot map.
// A reader pins a slot (its voxels stay put) and releases it; a miss takes a new slot while the
// budget has one, else evicts an unpinned slot of its shard whose reference bit is clear, then
// reads the brick while holding the shard's lock. Each thread pins at most six bricks at once
// (a GridReader pins the brick it walks and one neighbour; at most three readers at once: the
// density, emission and temperature grids), so every shard may always grow to 6·threads + 1
// slots (reserved out of the budget) and then always has a victim; the rest
// of the budget is a pool any shard grows into, so bricks hashed unevenly still fill the whole
// budget, and a budget that holds every brick never evicts. The values a
// lookup returns never depend on the cache's size or state: images are bit-identical for any
// budget and thread count. Costs: O(1) expected per acquire; memory = slots · kSlotBytes at most.
#pragma once
#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

namespace rayes {

// Where the voxels of a grid's file-backed bricks come from; `read` is called concurrently.
class BrickSource {
 public:
  virtual ~BrickSource() = default;
  // Fills `voxels` (512 floats, x-major as an OpenVDB leaf) with stored brick `stored`.
  virtual void read(uint32_t stored, float* voxels) const = 0;
  // Bytes the source keeps resident whatever the cache holds (the out-of-core tree).
  virtual uint64_t residentBytes() const = 0;
};

struct BrickCacheStats {
  uint64_t budgetBytes = 0, slots = 0;  // the bound, and the slots it allows
  uint64_t slotsUsed = 0;               // slots ever filled (their bytes are the cache's peak)
  uint64_t hits = 0, loads = 0, evictions = 0;
  uint64_t voxelsRead = 0, bytesRead = 0;  // by loads (bytes: decoded voxels, 4 per voxel)
  double loadSeconds = 0;                  // summed over threads, inside BrickSource::read
  double hitRate() const { return hits + loads ? double(hits) / double(hits + loads) : 0.0; }
};

class BrickCache {
 public:
  static constexpr uint32_t kBrickVoxels = 512;
  // A slot's voxels: the brick and its apron, x-major, local voxel (x, y, z) at
  // paddedIndex(x, y, z) for x, y, z in [−1, 8].
  static constexpr int32_t kPaddedSide = 10;
  static constexpr uint32_t kSlotVoxels = kPaddedSide * kPaddedSide * kPaddedSide;
  static constexpr int32_t paddedIndex(int32_t x, int32_t y, int32_t z) {
    return ((x + 1) * kPaddedSide + (y + 1)) * kPaddedSide + (z + 1);
  }
  // A slot's voxels and bookkeeping, and its share of the key map.
  static constexpr uint64_t kSlotBytes = kSlotVoxels * sizeof(float) + 64;
  // Apron region (ax, ay, az), each 0 (the neighbour below: local −1), 1 (the brick's own
  // range 0 … 7) or 2 (the neighbour above: local 8), is bit ax·9 + ay·3 + az of a slot's mask;
  // (1, 1, 1) is the brick itself, always present.
  static constexpr uint32_t apronRegion(int ax, int ay, int az) { return uint32_t(ax * 9 + ay * 3 + az); }
  static constexpr uint32_t kInterior = 1u << (1 * 9 + 1 * 3 + 1);  // apronRegion(1, 1, 1)
  // A region's parts and its box in local voxel coordinates, inclusive (part 0: −1; 1: 0 … 7;
  // 2: 8); its voxels are those of the neighbour brick at cell offset part − 1, at local
  // coordinate + 8·(1 − part).
  struct ApronBox {
    int32_t part[3], lo[3], hi[3];
  };
  static ApronBox apronBox(uint32_t region);
  // The smallest budget `threads` threads can work in (a slot per pin, one to evict into).
  static uint64_t minimumBytes(int threads);

  // budgetBytes ≥ minimumBytes(threads) unless it holds all `totalBricks` bricks the scene
  // stores (the app checks and names the option).
  BrickCache(uint64_t budgetBytes, int threads, uint64_t totalBricks);
  ~BrickCache();
  BrickCache(const BrickCache&) = delete;
  BrickCache& operator=(const BrickCache&) = delete;

  struct Slot;
  // The padded voxels of (grid, stored brick), pinned until release(slot); on a miss the brick
  // is read from `source` and its apron is empty (apronFilled has kInterior alone).
  const float* acquire(uint32_t grid, uint32_t stored, const BrickSource& source, Slot*& slot);
  void release(Slot* slot);
  // The regions of a pinned slot whose voxels may be read (bits as apronRegion; kInterior
  // always). Only grows while the slot is pinned.
  static uint32_t apronFilled(const Slot* slot);
  // Writes apron region `region` of a pinned slot from `values` (its voxels in x-major order of
  // the region's box) unless another reader filled it first, then marks it filled. Serialised
  // with the slot's shard; readers of other regions proceed meanwhile (they touch other voxels).
  void fillApron(Slot* slot, uint32_t region, const float* values);

  BrickCacheStats stats() const;

 private:
  struct Shard;
  std::vector<std::unique_ptr<Shard>> shards_;
  uint64_t budgetBytes_ = 0, slots_ = 0;
  uint64_t reserved_ = 0;            // slots every shard may take whatever the pool holds
  std::atomic<int64_t> pool_{0};     // the budget's other slots, taken by any shard
  bool holdsEverything_ = false;     // the budget holds every brick: no eviction ever
};

}  // namespace rayes
