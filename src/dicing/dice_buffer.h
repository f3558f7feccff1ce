// START HERE for the bottom level. A DiceBuffer holds one diced patch: the (2^m+1)^2 vertex
// grid and the complete quad-tree BVH over its 4^m micro-quads (thesis §6.1.1).
//
// Ownership and threads: one DiceBuffer per thread, allocated once for the largest level and
// reused for every patch that thread dices (DESIGN invariant 3: memory does not grow with the
// scene). A DiceBuffer is not thread-safe; intersect() is const and may be called many times
// after one dice().
//
// Complexity: dice() evaluates (2^m+1)^2 points and builds the tree bottom-up in O(4^m) with no
// sorting; node count is exactly sum_{i=0..m} 4^i. The tree is implicit: node (level i, x, y)
// lives at a fixed offset, children are (i+1, 2x+{0,1}, 2y+{0,1}).
//
// Level of detail: intersect(..., rayLevel = k) with k <= m traverses only down to level k and
// intersects the coarse micro-quads made of every 2^(m-k)-th vertex. Those vertices have the
// same parameters as a level-k dicing, so the hit is exactly the hit on a level-k dicing: a
// ray's hit never depends on which other rays made the patch be diced finer.
#pragma once
#include <cstdint>
#include <vector>
#include "core/box.h"
#include "dicing/patch.h"

namespace rayes {

// A hit on a diced grid.
struct GridHit {
  float t = 0;          // ray parameter
  float u = 0, v = 0;   // patch parameters of the hit point
  uint32_t quad = 0;    // micro-quad index at the ray's level: y * 2^k + x
  Vec3 ng;              // geometric normal of the micro-triangle hit (unit, facing unspecified);
                        // for a zero-area triangle the watertight test still claims (rounding
                        // gives it a sliver), the other triangle's, else the blended vertex normal
  Vec3 ns;              // shading normal: bilinear blend of the quad's vertex normals (unit)
};

class DiceBuffer {
 public:
  // Allocates for levels up to maxLevel (0..12; std::invalid_argument otherwise).
  explicit DiceBuffer(int maxLevel);

  // Dices `patch` at `level` (<= maxLevel, else std::invalid_argument) and builds the
  // implicit BVH. Vertex normals are stored unit length.
  void dice(const Patch& patch, int level);

  int level() const { return level_; }
  int maxLevel() const { return maxLevel_; }

  // Nearest hit with t in (tmin, tmax) at the ray's own level (0 <= rayLevel <= level(); a
  // rayLevel outside is clamped). A non-finite origin, a zero/non-finite direction or an empty
  // (tmin, tmax) gives no hit.
  // Ties in t are broken by the smaller micro-quad index, so the result does not depend on
  // traversal order. Watertight: a ray through a shared edge or vertex hits at least one of
  // the micro-quads that share it.
  bool intersect(Vec3 org, Vec3 dir, float tmin, float tmax, int rayLevel, GridHit& hit) const;

  // Any hit with t in (tmin, tmax) at the ray's level (shadow rays).
  bool occluded(Vec3 org, Vec3 dir, float tmin, float tmax, int rayLevel) const;

  // Grid access for tests and debugging.
  int resolution() const { return (1 << level_) + 1; }      // vertices per side
  Vec3 position(int i, int j) const;
  Vec3 normal(int i, int j) const;
  // Node box of the implicit tree at (treeLevel, x, y).
  Box3 node(int treeLevel, int x, int y) const;
  size_t nodeCount() const;                                  // sum_{i<=level} 4^i
  size_t bytesAllocated() const;

 private:
  void buildTree();
  template <bool AnyHit>
  bool traverse(Vec3 org, Vec3 dir, float tmin, float tmax, int rayLevel, GridHit* hit) const;

  int maxLevel_ = 0;
  int level_ = 0;
  std::vector<Vec3> positions_;
  std::vector<Vec3> normals_;  // unit (or zero where the patch is degenerate as a whole)
  // The tree, stored by sibling groups: group g of level i (i < level_) holds the boxes of the
  // 4 children (level i+1, Z-order 4g..4g+3) of node g of level i as structure of arrays,
  // kNodeGroupFloats floats: lo.x[4] hi.x[4] lo.y[4] hi.y[4] lo.z[4] hi.z[4]. Groups of level i
  // start at group (4^i - 1) / 3; the root box (lo, hi: 6 floats) follows the groups of the
  // largest level. One traversal step is then one 4-wide slab test on 96 contiguous bytes.
  // Same size as one Box3 per node: sum_{i<=maxLevel} 4^i boxes.
  static constexpr size_t kNodeGroupFloats = 24;
  static size_t groupOffset(int level, uint32_t g) {
    return kNodeGroupFloats * (((size_t(1) << (2 * level)) - 1) / 3 + g);
  }
  const float* nodeGroup(int level, uint32_t g) const { return nodes_.data() + groupOffset(level, g); }
  float* nodeGroup(int level, uint32_t g) { return nodes_.data() + groupOffset(level, g); }
  const float* rootBox() const { return nodes_.data() + groupOffset(maxLevel_, 0); }
  float* rootBox() { return nodes_.data() + groupOffset(maxLevel_, 0); }
  std::vector<float> nodes_;
  Box3 patchBounds_;         // the diced patch's bounds(): sets the per-ray box margin
};

// Level of detail, per ray: the smallest m with patchSize / 2^m <= footprintWidth, clamped to
// [0, maxLevel]. footprintWidth <= 0 or non-finite gives maxLevel; patchSize <= 0 gives 0.
// (Precedence: maxLevel <= 0 gives 0, then patchSize <= 0 gives 0; a NaN or infinite
// patchSize gives maxLevel, the safe choice for an unknown size.)
int levelForFootprint(float patchSize, float footprintWidth, int maxLevel);

// The thesis's batch-density rule (--lod density): the smallest m with 4^m >= rays / spp,
// clamped to [0, maxLevel]. spp <= 0 counts as 1; rays == 0 gives 0.
int levelForDensity(uint64_t rays, int spp, int maxLevel);

}  // namespace rayes
