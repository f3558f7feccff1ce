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
// The patches are made by ForestPatches (geometry/forest_patches.h) over the forest's tables,
// the one maker a compiled scene uses too over the same tables mapped from its file.
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
#include <memory>
#include <vector>
#include "core/box.h"
#include "core/transform.h"
#include "core/vec.h"
#include "geometry/displacement.h"
#include "geometry/forest_patches.h"
#include "geometry/patch.h"

namespace rayes {

class Forest {
 public:
  // Throws std::invalid_argument for parameters out of range, or when the forest would have
  // more than maxLeaves leaves (the caller's memory limit for the description).
  explicit Forest(const ForestParams& params, uint64_t maxLeaves = uint64_t(1) << 32);
  Forest(const Forest&) = delete;  // patches_ reads branches_ and foliage_ in place
  Forest& operator=(const Forest&) = delete;

  size_t size() const { return leaves_.size(); }
  const ForestLeaf& leaf(size_t i) const { return leaves_[i]; }
  const Box3& bounds(size_t i) const { return bounds_[i]; }
  // The patch's sizeBound() and dicingErrorCoefficient(), recorded at generation.
  float sizeBound(size_t i) const { return size_[i].sizeBound; }
  float dicingError(size_t i) const { return size_[i].dicingError; }
  PatchPtr makePatch(size_t i) const { return patches_->make(leaves_[i]); }

  // The uniform scale of a placement (0 for the identity); std::invalid_argument for anything
  // but a similarity with positive determinant.
  static float placementScale(const Transform& placement) { return forestPlacementScale(placement); }
  // Leaves of a forest with these parameters, without growing it (for limits and stats).
  static uint64_t leafCount(const ForestParams& params);
  // Bytes the description holds per leaf (records, boxes, branches and foliage shared out).
  double bytesPerLeaf() const;
  size_t branchCount() const { return branches_.size(); }
  size_t foliageCount() const { return foliage_.size(); }
  uint64_t countOf(ForestLeaf::Part part) const;

  using Branch = ForestBranch;
  using Foliage = ForestFoliage;
  const ForestParams& params() const { return params_; }
  const Branch& branch(size_t i) const { return branches_[i]; }
  const Foliage& foliage(size_t i) const { return foliage_[i]; }

 private:
  float groundHeight(float x, float z) const;

  ForestParams params_;
  DisplacementPtr terrainNoise_;  // unplaced: where the trees stand
  std::vector<Branch> branches_;
  std::vector<Foliage> foliage_;
  std::vector<ForestLeaf> leaves_;
  std::vector<Box3> bounds_;
  struct LeafSize {
    float sizeBound, dicingError;
  };
  std::vector<LeafSize> size_;
  std::unique_ptr<const ForestPatches> patches_;  // over branches_ and foliage_, made once they are grown
};

}  // namespace rayes
