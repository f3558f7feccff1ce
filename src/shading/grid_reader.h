// Reads a BrickGrid's values for one thread's walk (shading/volume_tracking.cpp): enter(brick)
// makes a brick current (pinned in the BrickCache while it is, when stored), sample(p) is the
// trilinear interpolation at an index point of its cell (docs/design.md, "Volumes"). A cached
// brick's voxels one beyond it are the slot's apron (brick_cache.h): a region the slot lacks is
// copied once from the neighbour, then every lookup reads the slot alone. Resident and constant
// bricks (and a point a rounding put outside its cell) read the voxels one beyond from the
// neighbour itself, held pinned until another neighbour is needed. So a reader pins at most two
// bricks (BrickCache's bound rests on it). Without a cache, stored bricks are read from their
// source at every enter (the tests' route; same values).
// Not thread-safe: one reader per thread and walk; the grid and cache may be shared.
#pragma once
#include <cstdint>
#include "core/vec.h"
#include "shading/brick_grid.h"

namespace rayes {

class GridReader {
 public:
  GridReader(const BrickGrid& grid, BrickCache* cache) : grid_(grid), cache_(cache) {}
  ~GridReader();
  GridReader(const GridReader&) = delete;
  GridReader& operator=(const GridReader&) = delete;

  void enter(int32_t brick) { fetch(brick, current_); }
  // The value at index point p inside the current brick's cell; never negative.
  float sample(Vec3 p);
  // The value at any index point p (0 in a cell without a brick): the brick found, then sample.
  float at(Vec3 p);
  // The voxel v's value (0 where no brick holds it).
  float voxel(int32_t x, int32_t y, int32_t z);

 private:
  struct Held {
    int32_t brick = -1;
    const float* voxels = nullptr;  // null: a constant brick
    float constant = 0;
    BrickCache::Slot* slot = nullptr;  // set: voxels are the slot's, padded (10³ with the apron)
    uint32_t apron = 0;                // the slot's regions known filled (BrickCache::apronFilled)
    BrickGrid::BrickVoxels scratch;    // the uncached route's copy
    // Local voxel (lx, ly, lz): 0 … 7, or −1 … 8 within the regions `apron` holds.
    float at(int32_t lx, int32_t ly, int32_t lz) const {
      if (!voxels) return constant;
      return voxels[size_t(slot ? BrickCache::paddedIndex(lx, ly, lz) : (lx * 8 + ly) * 8 + lz)];
    }
  };
  void fetch(int32_t brick, Held& h);
  void drop(Held& h);
  // Fills the regions of `need` (apron bits) that the current slot lacks, from the neighbours.
  void fillApron(uint32_t need);

  const BrickGrid& grid_;
  BrickCache* cache_;
  Held current_, neighbour_;
};

}  // namespace rayes
