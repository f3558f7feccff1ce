// What makes a forest leaf's Patch (geometry/forest.h): the forest's parameters and its
// generator tables — per branch its spine and radii, per foliage leaf its centre and half axes —
// and, per leaf, an 8-byte ForestLeaf naming which part and piece it is. ForestPatches::make is
// the one implementation of a forest's patches: the JSON route's Forest reads its own vectors
// through it, a compiled scene (scene/compiled_scene.h) the same tables in place from its
// mapping (GatedSpans: every read verified and counted under --scene-memory), so both make the
// same patches bit for bit.
//
// Contracts: the table types are stored as they are in a .rayes (little-endian, no implicit
// padding: their bytes are the file's); immutable after construction; make() is const and
// thread-safe, O(1) (one branch or foliage record read). ForestPatches holds `owner` (the
// memory its spans point into) for as long as it lives.
#pragma once
#include <cstdint>
#include <memory>
#include "core/gated_span.h"
#include "core/transform.h"
#include "core/vec.h"
#include "geometry/displacement.h"
#include "geometry/patch.h"

namespace rayes {

struct ForestParams {
  uint32_t trees = 1;
  uint64_t seed = 1;
  int detail = 4;            // branching levels below the trunk, 0..kMaxDetail
  int branching = 3;         // children per branch, 1..kMaxBranching
  float area = 60;           // side of the square the trees stand on (world units), > 0
  float treeHeight = 8;      // about the height of a grown tree, > 0
  int terrainTiles = 16;     // terrain patches per side, 1..kMaxTerrainTiles
  float terrainAmplitude = 1.5f;  // >= 0
  int leavesPerTwig = 12;    // 0..kMaxLeavesPerTwig
  // Where the grown forest is placed: a similarity (rotation, uniform scale, translation),
  // so that the whole forest, its displacement heights included, is mapped exactly -- its
  // noise stays a function of the unplaced position. Checked by the constructor.
  Transform placement;
  static constexpr int kMaxDetail = 8;
  static constexpr int kMaxBranching = 6;
  static constexpr int kMaxTerrainTiles = 4096;
  static constexpr int kMaxLeavesPerTwig = 64;
};

// Throws std::invalid_argument naming the first parameter out of range (the placement
// included: forestPlacementScale).
void checkForestParams(const ForestParams& params);
// The uniform scale of a placement (0 for the identity); std::invalid_argument for anything
// but a similarity with positive determinant.
float forestPlacementScale(const Transform& placement);
// The unplaced terrain's noise (where the trees stand; the terrain patches' displacement).
NoiseParams forestTerrainNoise(const ForestParams& params);

// Which part of the forest a top-level leaf is, and which piece of it.
struct ForestLeaf {
  enum class Part : uint8_t { Terrain, Bark, Foliage };
  Part part;
  uint8_t quarter;   // bark: quarter of the ring (0..3)
  uint16_t segment;  // bark: segment along the branch
  uint32_t index;    // terrain: tile; bark: branch; foliage: foliage leaf
};
static_assert(sizeof(ForestLeaf) == 8);

// A branch: a tube around a cubic Bézier spine with a linearly tapering radius, cut into
// `segments` pieces along the spine and four quarters around it.
struct ForestBranch {
  Vec3 spine[4];
  Vec3 up;          // a unit vector not parallel to the spine: fixes the rings' orientation
  float r0, r1;     // radius at the spine's start and end
  uint16_t segments;
  uint16_t reserved = 0;  // explicit padding: a stored branch's bytes are all defined
  uint32_t tree;
};
static_assert(sizeof(ForestBranch) == 76);

// A foliage leaf: a flat quad, centre ± halfU ± halfV.
struct ForestFoliage {
  Vec3 centre, halfU, halfV;
};
static_assert(sizeof(ForestFoliage) == 36);

class ForestPatches {
 public:
  // Checks the parameters (std::invalid_argument, as checkForestParams).
  ForestPatches(const ForestParams& params, GatedSpan<ForestBranch> branches, GatedSpan<ForestFoliage> foliage,
                std::shared_ptr<const void> owner = nullptr);

  // The leaf's patch. Throws std::invalid_argument for a leaf the tables do not hold (a tile,
  // branch, segment, quarter or foliage index out of range: a corrupt compiled record), and
  // whatever the gated reads throw (InputError for a corrupt block).
  PatchPtr make(const ForestLeaf& leaf) const;

  const ForestParams& params() const { return params_; }
  float placementScale() const { return placementScale_; }
  size_t branchCount() const { return branches_.size(); }
  size_t foliageCount() const { return foliage_.size(); }

 private:
  PatchPtr makeTerrain(uint32_t tile) const;
  PatchPtr makeBark(const ForestLeaf& leaf) const;
  bool placed() const { return placementScale_ != 0; }
  Vec3 place(Vec3 p) const { return placed() ? params_.placement.point(p) : p; }

  ForestParams params_;
  GatedSpan<ForestBranch> branches_;
  GatedSpan<ForestFoliage> foliage_;
  std::shared_ptr<const void> owner_;
  DisplacementPtr placedTerrainNoise_;  // the terrain's noise, its heights scaled by the placement
  float placementScale_ = 0;            // the placement's uniform scale; 0: no placement
};

}  // namespace rayes
