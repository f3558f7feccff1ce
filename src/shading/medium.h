// A heterogeneous participating medium as shading sees it: a density grid of 8³-voxel bricks
// (shading/brick_grid.h: index space, interpolation, majorants; scene/volume_shape_reader.cpp
// fills it from an OpenVDB grid), placed in the world by an affine transform, and the
// coefficients per unit density (σ_a, σ_s, Henyey-Greenstein g). Owned by the ShadingScene,
// immutable after the loader built it, read concurrently by every shading thread (no mutable
// state: stored bricks' voxels are read through the render's BrickCache).
//
// Costs: the grid's (brick_grid.h); density() and voxel() are the tests' uncached route.
#pragma once
#include <array>
#include <cstdint>
#include <vector>
#include "core/box.h"
#include "core/transform.h"
#include "core/vec.h"
#include "shading/brick_grid.h"

namespace rayes {

struct MediumCoefficients {
  float sigmaA = 0, sigmaS = 1;  // per unit density (after the shape's density scale), per world unit
  float g = 0;                   // Henyey-Greenstein asymmetry in (−1, 1)
  float sigmaT() const { return sigmaA + sigmaS; }
  // The scattering albedo σ_s / σ_t (a collision scatters with this weight; 0 when σ_t is 0).
  float albedo() const { return sigmaT() > 0 ? sigmaS / sigmaT() : 0.0f; }
};

// Emission (optional): the radiance a unit of absorption emits, Le(x) = color · e(x) +
// blackbodyScale · blackbodyRgb(temperatureScale · T(x)) from an emission grid e and a
// temperature grid T (each optional, in the density grid's index space); the medium's source
// term is σ_a(x) · Le(x) (pbrt's convention: where nothing absorbs, nothing emits).
struct MediumEmission {
  std::unique_ptr<BrickGrid> intensity;    // e; null: no emission grid
  Rgb color{1, 1, 1};
  std::unique_ptr<BrickGrid> temperature;  // T in kelvin / temperatureScale; null: none
  float temperatureScale = 1, blackbodyScale = 1;
};

class Medium {
 public:
  static constexpr int kBrickSide = BrickGrid::kBrickSide, kBrickVoxels = BrickGrid::kBrickVoxels;
  using BrickVoxels = BrickGrid::BrickVoxels;

  // `indexToWorld` must be invertible (the reader checks). Bricks are added to density(), or
  // with addBrick (resident), then finish() builds the cell table and the majorants.
  Medium(const Transform& indexToWorld, MediumCoefficients c, std::shared_ptr<const BrickSource> source = nullptr);
  void addBrick(BrickCoord c, const BrickVoxels& voxels) { density_.addResident(c, voxels); }
  BrickGrid& densityGrid() { return density_; }
  void setEmission(MediumEmission e) { emission_ = std::move(e); }
  void finish();

  const MediumCoefficients& coefficients() const { return coefficients_; }
  const Transform& worldToIndex() const { return worldToIndex_; }
  // The bricks' union in world space (conservative: the transformed corners of the cells).
  const Box3& worldBounds() const { return worldBounds_; }
  // Brick `brick`'s cell in world space, padded for the rounding of the corners' transform: the
  // box of its top-level leaf (core/medium_leaves.h). Conservative: tracking clips the ray to the
  // cell itself in index space (brickSegment), the box only selects the bricks a ray may cross.
  Box3 brickWorldBounds(int32_t brick) const;
  const BrickGrid& densityGrid() const { return density_; }
  const MediumEmission& emission() const { return emission_; }
  bool emits() const { return emission_.intensity || emission_.temperature; }
  size_t bricks() const { return density_.bricks(); }
  uint64_t voxels() const { return uint64_t(bricks()) * kBrickVoxels; }
  size_t bytes() const {
    return density_.bytes() + (emission_.intensity ? emission_.intensity->bytes() : 0) +
           (emission_.temperature ? emission_.temperature->bytes() : 0);
  }

  BrickCoord cellLo() const { return density_.cellLo(); }
  BrickCoord cellCount() const { return density_.cellCount(); }
  int32_t brickAt(int32_t cx, int32_t cy, int32_t cz) const { return density_.brickAt(cx, cy, cz); }
  float majorant(int32_t brick) const { return density_.majorant(brick); }
  // The density (unscaled voxel units) at an index-space point inside cell `brick`'s cell, and
  // voxel v's value (0 where no brick holds it): uncached reads, for tests.
  float density(int32_t brick, Vec3 index) const;
  float voxel(int32_t x, int32_t y, int32_t z) const;

 private:
  MediumCoefficients coefficients_;
  Transform worldToIndex_, indexToWorld_;
  BrickGrid density_;
  MediumEmission emission_;
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
