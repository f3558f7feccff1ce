// A sparse float grid cut into bricks of 8³ voxels (one OpenVDB leaf node each), as the volume
// trackers read it: a dense table from brick cell to brick, and per brick where its voxels are
// (resident in memory, stored in a file and read through the render's BrickCache, or one
// constant value: an active tile's block) and a conservative majorant. Immutable after finish();
// read concurrently (voxels through shading/grid_reader.h).
//
// Index space: voxel (i, j, k)'s value sits at the point (i, j, k) (OpenVDB's convention). Brick
// cell c covers [8c − ½, 8c + 7.5)³, so voxel v lies in cell floor(v / 8). The value at a point
// of a cell with a brick is the trilinear interpolation of the eight voxels around it (absent
// voxels read 0); in a cell without one it is 0. A brick's majorant is the largest voxel of it
// and of its 26 neighbours, which bounds that interpolation anywhere in its cell.
//
// Costs: 20 bytes per brick (its cell, kind and index, majorant) + 4 bytes per cell of the
// bricks' bounding grid (O(1) lookup) + 2 KiB per resident brick; stored bricks cost nothing
// here (their voxels are the cache's), constant ones nothing beyond their value.
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <vector>
#include "shading/brick_cache.h"

namespace rayes {

struct BrickCoord {
  int32_t x = 0, y = 0, z = 0;  // brick cell coordinate: voxel origin / 8
};

class BrickGrid {
 public:
  static constexpr int kBrickSide = 8, kBrickVoxels = kBrickSide * kBrickSide * kBrickSide;
  static_assert(kBrickVoxels == BrickCache::kBrickVoxels);
  using BrickVoxels = std::array<float, kBrickVoxels>;  // x-major: index (x·8 + y)·8 + z, as an OpenVDB leaf
  enum class Kind : uint8_t { Resident, Stored, Constant };

  // `source` serves the stored bricks (null when there are none).
  explicit BrickGrid(std::shared_ptr<const BrickSource> source = nullptr);
  void addResident(BrickCoord c, const BrickVoxels& voxels);
  // Brick `stored` of the source, whose largest voxel is `maxVoxel` (found when the file was
  // first read: the majorants need every voxel once).
  void addStored(BrickCoord c, uint32_t stored, float maxVoxel);
  void addConstant(BrickCoord c, float value);
  void finish();

  // A number no other grid of the process has: the brick cache's key.
  uint32_t id() const { return id_; }
  size_t bricks() const { return coords_.size(); }
  size_t storedBricks() const { return stored_; }
  // What the grid keeps resident (not the cache's slots), its source's resident part included.
  size_t bytes() const;

  // The grid of cells [cellLo, cellLo + cellCount): the bricks' bounding grid in cell units.
  BrickCoord cellLo() const { return cellLo_; }
  BrickCoord cellCount() const { return cellCount_; }
  // The brick in cell c, or −1 (outside the grid or empty).
  int32_t brickAt(int32_t cx, int32_t cy, int32_t cz) const;
  float majorant(int32_t brick) const { return majorant_[size_t(brick)]; }
  const BrickCoord& coord(int32_t brick) const { return coords_[size_t(brick)]; }
  Kind kind(int32_t brick) const { return kind_[size_t(brick)]; }
  // Resident: the voxels; Stored: the source's index; Constant: the value (bit-cast).
  const float* residentVoxels(int32_t brick) const { return resident_[index_[size_t(brick)]].data(); }
  uint32_t storedIndex(int32_t brick) const { return index_[size_t(brick)]; }
  float constantValue(int32_t brick) const { return value_[size_t(brick)]; }
  const BrickSource* source() const { return source_.get(); }

 private:
  uint32_t id_;
  std::shared_ptr<const BrickSource> source_;
  std::vector<BrickCoord> coords_;
  std::vector<Kind> kind_;
  std::vector<uint32_t> index_;
  std::vector<float> value_;  // constant: the value; otherwise the brick's largest voxel
  std::vector<BrickVoxels> resident_;
  std::vector<float> majorant_;
  size_t stored_ = 0;
  BrickCoord cellLo_, cellCount_;
  std::vector<int32_t> cells_;  // brick per cell, x-major
};

}  // namespace rayes
