// A heterogeneous participating medium as shading sees it: a density grid cut into bricks of
// 8³ voxels (an OpenVDB leaf node each; scene/volume_shape_reader.cpp fills them), each with a
// conservative majorant, placed in the world by an affine transform, and the coefficients per
// unit density (σ_a, σ_s, Henyey-Greenstein g). Owned by the ShadingScene, immutable after the
// loader built it, read concurrently by every shading thread (no mutable state).
//
// Index space: voxel (i, j, k)'s value sits at the point (i, j, k) (OpenVDB's convention). Brick
// cell c covers [8c − ½, 8c + 7.5)³, so voxel v lies in cell floor(v / 8). The density at a point
// of a cell with a brick is the trilinear interpolation of the eight voxels around it (absent
// voxels read 0); in a cell without a brick it is 0. A brick's majorant is the largest voxel of
// it and of its 26 neighbours, which bounds that interpolation anywhere in its cell: the bound
// delta and ratio tracking need (shading/volume_tracking.h).
//
// Costs: 2 KiB of voxels and 16 bytes per brick, 4 bytes per cell of the bricks' bounding grid
// (a dense table: O(1) lookup; the next step, a bounded brick cache, replaces the voxels by
// bricks loaded on demand). density() is O(1).
#pragma once
#include <array>
#include <cstdint>
#include <vector>
#include "core/box.h"
#include "core/transform.h"
#include "core/vec.h"

namespace rayes {

struct MediumCoefficients {
  float sigmaA = 0, sigmaS = 1;  // per unit density (after the shape's density scale), per world unit
  float g = 0;                   // Henyey-Greenstein asymmetry in (−1, 1)
  float sigmaT() const { return sigmaA + sigmaS; }
  // The scattering albedo σ_s / σ_t (a collision scatters with this weight; 0 when σ_t is 0).
  float albedo() const { return sigmaT() > 0 ? sigmaS / sigmaT() : 0.0f; }
};

struct BrickCoord {
  int32_t x = 0, y = 0, z = 0;  // brick cell coordinate: voxel origin / 8
};

class Medium {
 public:
  static constexpr int kBrickSide = 8, kBrickVoxels = kBrickSide * kBrickSide * kBrickSide;
  using BrickVoxels = std::array<float, kBrickVoxels>;  // x-major: index (x·8 + y)·8 + z, as an OpenVDB leaf

  // `indexToWorld` must be invertible (the reader checks). Bricks are added with addBrick, then
  // finish() builds the cell table and the majorants.
  Medium(const Transform& indexToWorld, MediumCoefficients c);
  void addBrick(BrickCoord c, const BrickVoxels& voxels);
  void finish();

  const MediumCoefficients& coefficients() const { return coefficients_; }
  const Transform& worldToIndex() const { return worldToIndex_; }
  // The bricks' union in world space (conservative: the transformed corners of the cells).
  const Box3& worldBounds() const { return worldBounds_; }
  size_t bricks() const { return coords_.size(); }
  uint64_t voxels() const { return uint64_t(bricks()) * kBrickVoxels; }
  size_t bytes() const;

  // The grid of cells [cellLo, cellLo + cellCount): the bricks' bounding grid in cell units.
  BrickCoord cellLo() const { return cellLo_; }
  BrickCoord cellCount() const { return cellCount_; }
  // The brick in cell c, or −1 (outside the grid or empty).
  int32_t brickAt(int32_t cx, int32_t cy, int32_t cz) const;
  float majorant(int32_t brick) const { return majorant_[size_t(brick)]; }
  // The density (unscaled voxel units) at an index-space point inside cell `brick`'s cell.
  float density(int32_t brick, Vec3 index) const;
  // The voxel v's value (0 where no brick holds it).
  float voxel(int32_t x, int32_t y, int32_t z) const;

 private:
  MediumCoefficients coefficients_;
  Transform worldToIndex_, indexToWorld_;
  std::vector<BrickCoord> coords_;
  std::vector<BrickVoxels> voxels_;
  std::vector<float> majorant_;
  BrickCoord cellLo_, cellCount_;
  std::vector<int32_t> cells_;  // brick per cell, x-major
  Box3 worldBounds_;
};

// The inverse of an affine transform, or false when it is not invertible (|det| tiny against
// the matrix's scale, or not finite).
bool invertAffine(const Transform& m, Transform& inverse);
// The transform's linear part applied to a direction.
inline Vec3 applyLinear(const Transform& t, Vec3 d) {
  return {t.m[0][0] * d.x + t.m[0][1] * d.y + t.m[0][2] * d.z, t.m[1][0] * d.x + t.m[1][1] * d.y + t.m[1][2] * d.z,
          t.m[2][0] * d.x + t.m[2][1] * d.y + t.m[2][2] * d.z};
}

}  // namespace rayes
