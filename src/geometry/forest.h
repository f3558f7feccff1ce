// START HERE for procedural scenes. A Forest is a scene part generated from a handful of
// parameters: a displaced terrain, and trees grown by a branching rule (an L-system: every
// branch ends in `branching` children, `detail` levels deep) whose branches are tubes of
// displaced bicubic patches (bark) and whose twigs carry small flat leaves.
//
// What it keeps is compact: per leaf of the top level an 8-byte record, its box and its patch's
// size bound and dicing error (8 bytes, for level of detail and ray offsets), per branch
// its spine (a cubic Bézier) and radii, per foliage leaf its centre and two half axes. A leaf's
// Patch is made by makePatch() when it is needed — to dice it — and may be dropped right after:
// the memory of a forest grows with its leaf count, never with the micropolygons it can make.
//
// Contracts:
// - bounds(i) contains every point makePatch(i) can produce (docs/design.md, invariant 1): it is
//   that patch's own conservative bounds(), computed at generation.
// - Generation is a pure function of the parameters: the same records, bit for bit, for any
//   thread count (trees are grown in parallel into their own lists, joined in tree order).
// - Watertight tubes: the segments of one branch share their border rings bit for bit, and so do
//   the four quarters of a ring (the ring is evaluated from exact quarter angles).
// - Immutable after construction; makePatch() is const and thread-safe.
// Cost: generation O(leaves) (one patch construction per leaf, for its box); makePatch O(1).
#pragma once
#include <cstdint>
#include <vector>
#include "core/box.h"
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

// Which part of the forest a top-level leaf is, and which piece of it.
struct ForestLeaf {
  enum class Part : uint8_t { Terrain, Bark, Foliage };
  Part part;
  uint8_t quarter;   // bark: quarter of the ring (0..3)
  uint16_t segment;  // bark: segment along the branch
  uint32_t index;    // terrain: tile; bark: branch; foliage: foliage leaf
};

class Forest {
 public:
  // Throws std::invalid_argument for parameters out of range, or when the forest would have
  // more than maxLeaves leaves (the caller's memory limit for the description).
  explicit Forest(const ForestParams& params, uint64_t maxLeaves = uint64_t(1) << 32);

  size_t size() const { return leaves_.size(); }
  const ForestLeaf& leaf(size_t i) const { return leaves_[i]; }
  const Box3& bounds(size_t i) const { return bounds_[i]; }
  // The patch's sizeBound() and dicingErrorCoefficient(), recorded at generation.
  float sizeBound(size_t i) const { return size_[i].sizeBound; }
  float dicingError(size_t i) const { return size_[i].dicingError; }
  PatchPtr makePatch(size_t i) const;

  // The uniform scale of a placement (0 for the identity); std::invalid_argument for anything
  // but a similarity with positive determinant.
  static float placementScale(const Transform& placement);
  // Leaves of a forest with these parameters, without growing it (for limits and stats).
  static uint64_t leafCount(const ForestParams& params);
  // Bytes the description holds per leaf (records, boxes, branches and foliage shared out).
  double bytesPerLeaf() const;
  size_t branchCount() const { return branches_.size(); }
  size_t foliageCount() const { return foliage_.size(); }
  uint64_t countOf(ForestLeaf::Part part) const;

  // A branch: a tube around a cubic Bézier spine with a linearly tapering radius, cut into
  // `segments` pieces along the spine and four quarters around it.
  struct Branch {
    Vec3 spine[4];
    Vec3 up;          // a unit vector not parallel to the spine: fixes the rings' orientation
    float r0, r1;     // radius at the spine's start and end
    uint16_t segments;
    uint32_t tree;
  };
  struct Foliage {
    Vec3 centre, halfU, halfV;
  };
  const Branch& branch(size_t i) const { return branches_[i]; }

 private:
  PatchPtr makeTerrain(uint32_t tile) const;
  PatchPtr makeBark(const ForestLeaf& leaf) const;
  bool placed() const { return placementScale_ != 0; }
  Vec3 place(Vec3 p) const { return placed() ? params_.placement.point(p) : p; }
  float groundHeight(float x, float z) const;

  ForestParams params_;
  DisplacementPtr terrainNoise_;        // unplaced: where the trees stand
  DisplacementPtr placedTerrainNoise_;  // its heights scaled by the placement
  float placementScale_ = 0;            // the placement's uniform scale; 0: no placement
  std::vector<Branch> branches_;
  std::vector<Foliage> foliage_;
  std::vector<ForestLeaf> leaves_;
  std::vector<Box3> bounds_;
  struct LeafSize {
    float sizeBound, dicingError;
  };
  std::vector<LeafSize> size_;
};

}  // namespace rayes
