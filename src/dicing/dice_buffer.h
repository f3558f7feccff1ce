// START HERE for the bottom level. A DiceBuffer holds one diced patch: the (2^m+1)^2 vertex
// grid and the complete quad-tree BVH over its 4^m micro-quads (thesis §6.1.1).
//
// Ownership and threads: one DiceBuffer per thread, allocated once for the largest level and
// reused for every patch that thread dices (docs/design.md, invariant 3: memory does not grow with the
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
//
// Motion (thesis §6.3): diceInterval() dices the two time samples bracketing an interval into
// two grids with two trees (the second allocated on first use); a query at time weight alpha
// traverses boxes and micro-quads interpolated as (1-alpha)*a + alpha*b. That blend is
// monotone in a and b, so an interpolated box contains the interpolated points of the boxes
// it interpolates and the traversal stays exact. A static dicing never touches the second
// grid: its traversal is the static code path, unchanged.
//
// Crack-free borders (docs/architecture.md): for a patch whose borders are curved
// (Patch::needsBorderClosure) a query with closeBorders also hits the border region of each
// border segment at the ray's level k: a box that holds the true border curve over that
// segment (Patch::boundsOver on the degenerate rectangle) and its chord, cut down to a cylinder
// about the chord that still holds the curve. Whatever level a neighbour was intersected at,
// the slit between the two dicings lies in these regions. A static dicing computes a segment's
// box and radius only when a ray first reaches it (a dicing of a displaced leaf serves a few
// rays, and the bounds of its borders cost far more than its micro-polygons), as pure
// functions of (border, level, segment): the ray walks the segments' boxes of levels 0..k, so
// neither pruning nor the region depends on the level the patch was diced at. A moving dicing
// builds, per time sample, the binary tree of those boxes up front (each node united with its
// children) and blends it per query. The patch must outlive the queries of its dicing. See
// intersect().
//
// Sub-leaves (geometry/sub_patch.h): a dicing of a SubPatch reports its hits on the parent's
// grid -- u, v in the parent's parameters, quad numbered on the parent's grid of level
// k + depth, dpdu and dpdv per unit of the parent's parameters -- computed by the same
// operations as the parent diced whole, so a split leaf's hits have the same bits.
#pragma once
#include <algorithm>
#include <atomic>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>
#include "core/box.h"
#include "dicing/border_bound_cache.h"
#include "dicing/micro_quad.h"
#include "geometry/patch.h"

namespace rayes {

// A hit on a diced grid.
struct GridHit {
  float t = 0;          // ray parameter
  float u = 0, v = 0;   // patch parameters of the hit point
  uint32_t quad = 0;    // micro-quad index at the ray's level: y * 2^k + x (a sub-leaf: on its parent's grid)
  Vec3 ng;              // geometric normal of the micro-triangle hit (unit, facing unspecified);
                        // for a zero-area triangle the watertight test still claims (rounding
                        // gives it a sliver), the other triangle's, else the blended vertex normal
  Vec3 ns;              // shading normal: bilinear blend of the quad's vertex normals (unit)
  Vec3 dpdu, dpdv;      // the quad's bilinear partials at the hit per unit (u, v) (quadPartials;
                        // a border hit: its border micro-quad's, at the blended time)
  bool border = false;  // the hit is on a border box (crack closure), not on a micro-triangle
};

// What a query needs besides the ray. The defaults: the micro-polygons alone, first sample.
struct BottomQuery {
  float alpha = 0;            // time weight of the second sample of diceInterval() (0 for dice())
  bool closeBorders = false;  // also hit the border boxes (ignored where the patch needs none);
                              // the SortedEngine sets it (SortedEngine::closeBordersFor)
  uint8_t skipBorders = 0;    // with closeBorders: bit e set = not border e (its neighbour's
                              // coarser or equal dicing closes that seam for this ray)
  // With closeBorders, for a border not skipped: bit e set = border e's region is thin, a
  // cylinder of radius thinRadius[e] about each chord at the ray's level, for a seam whose
  // neighbour is seen at the same level with border vertices at most that far from this
  // dicing's (the slit between the two polylines lies within it; the SortedEngine measures it).
  // Only static dicings at levels <= kMaxThinLevel have thin regions (the walk is linear).
  uint8_t thinBorders = 0;
  double thinRadius[4] = {0, 0, 0, 0};
  static constexpr int kMaxThinLevel = 6;
};

// Where a static dicing keeps its border bounds beyond itself: the render's shared table and
// the key of the diced leaf in it (no cache: each dicing computes its own).
struct SharedBorderBounds {
  BorderBoundCache* cache = nullptr;
  uint32_t leaf = 0;
};

class DiceBuffer {
 public:
  // Allocates for levels up to maxLevel (0..12; std::invalid_argument otherwise).
  explicit DiceBuffer(int maxLevel);
  DiceBuffer(const DiceBuffer&) = delete;
  DiceBuffer& operator=(const DiceBuffer&) = delete;

  // Dices `patch` at `level` (<= maxLevel, else std::invalid_argument) and builds the
  // implicit BVH. Vertex normals are stored unit length. With `shared`, the border regions' boxes
  // and radii are looked up in and added to shared.cache under shared.leaf (which must name
  // this patch, the same one every time): the same values, computed once per leaf.
  void dice(const Patch& patch, int level, SharedBorderBounds shared = {});

  // Dices time samples `interval` and `interval`+1 of a moving patch (0 <= interval <
  // timeSamples()-1) at `level`, for queries with alpha in [0, 1]. A static patch: dice(),
  // with `shared`; a moving one does not use it.
  void diceInterval(const Patch& patch, int interval, int level, SharedBorderBounds shared = {});

  int level() const { return level_; }
  bool moving() const { return moving_; }
  bool hasBorders() const { return borders_; }
  int maxLevel() const { return maxLevel_; }

  // Nearest hit with t in (tmin, tmax) at the ray's own level (0 <= rayLevel <= level(); a
  // rayLevel outside is clamped). A non-finite origin, a zero/non-finite direction or an empty
  // (tmin, tmax) gives no hit.
  // Ties in t are broken by the smaller micro-quad index, so the result does not depend on
  // traversal order. Watertight: a ray through a shared edge or vertex hits at least one of
  // the micro-quads that share it.
  //
  // Border regions (query.closeBorders, on a patch that needs them): the region of border
  // segment j at the ray's level k -- its box intersected with a cylinder about its chord
  // (traverseBorders) -- is hit when the ray enters it within (tmin, tmax) from outside (a
  // ray starting inside one -- a secondary ray leaving the surface near a seam -- is not
  // stopped by it). The hit distance is the ray's crossing of the adjacent micro-triangle's
  // plane clamped to the region's entry/exit, so the point lies as close to the surface as
  // the region allows; the normals are that quad's; quad is the border micro-quad; border is
  // set. The result is still a pure function of (ray, patch, k, alpha): a static dicing's
  // segment boxes and radii are functions of (e, level, j) alone (a moving dicing's tree
  // nodes contain every finer level's box).
  bool intersect(Vec3 org, Vec3 dir, float tmin, float tmax, int rayLevel, GridHit& hit,
                 BottomQuery query = {}) const;

  // Any hit with t in (tmin, tmax) at the ray's level (shadow rays).
  bool occluded(Vec3 org, Vec3 dir, float tmin, float tmax, int rayLevel, BottomQuery query = {}) const;

  // Grid access for tests and debugging.
  int resolution() const { return (1 << level_) + 1; }      // vertices per side
  // (position, normal and node: of the first time sample.)
  Vec3 position(int i, int j) const;
  Vec3 normal(int i, int j) const;
  // Node box of the implicit tree at (treeLevel, x, y).
  Box3 node(int treeLevel, int x, int y) const;
  // Border box of segment j (0 <= j < 2^treeLevel) of border e (0: v=0, 1: u=1, 2: v=1,
  // 3: u=0) at treeLevel <= level(), for the first time sample: a static dicing's region box,
  // a moving dicing's tree node; empty when hasBorders() is false.
  Box3 borderNode(int e, int treeLevel, int j) const;
  size_t nodeCount() const;                                  // sum_{i<=level} 4^i
  size_t bytesAllocated() const;
  // bytesAllocated() of a new DiceBuffer(maxLevel) (before a moving dicing allocates its second
  // sample): what a cache can charge for a grid before it makes it.
  static size_t bytesFor(int maxLevel);

 private:
  // An array a dicing writes before anything reads it: resize() constructs nothing (Vec3 and
  // float are implicit-lifetime types), so a buffer sized for --max-lod touches only the pages
  // the levels actually diced use. Zeroing all of it up front touched each thread's level-10
  // buffer whole (59 MiB), which the first touch of memory costs on this machine
  // (bench/history/2026-11.md, "Smaller ray slots, and less work per (ray, leaf) pair").
  template <class T>
  struct UninitializedAllocator : std::allocator<T> {
    template <class U>
    struct rebind { using other = UninitializedAllocator<U>; };
    UninitializedAllocator() = default;
    template <class U>
    UninitializedAllocator(const UninitializedAllocator<U>&) noexcept {}
    template <class U, class... Args>
    void construct(U* p, Args&&... args) {
      if constexpr (sizeof...(Args) > 0) ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
  };
  template <class T>
  using GridArray = std::vector<T, UninitializedAllocator<T>>;
  // One time sample's grid, tree and (moving dicings) border trees.
  struct Sample {
    GridArray<Vec3> positions;
    GridArray<Vec3> normals;  // unit (or zero where the patch is degenerate as a whole)
    GridArray<float> nodes;   // the tree, see kNodeGroupFloats below
    GridArray<float> borders; // 4 binary trees of boxes (6 floats), see borderOffset()
  };
  struct Best;
  // What a static dicing has computed of one border segment (border e, level i, segment j),
  // each value valid while its stamp equals the dicing's: the box of the true curve over it
  // (Patch::boundsOverAt, without the chord) and the two radius bounds of its region (a
  // cheap one first, see traverseBorders), and a coarse box around the region box
  // (mayEnterRegionBox) while that is not known. Filled on first use
  // by whichever query gets there; concurrent queries of one dicing may race on an entry
  // harmlessly (idempotent writes of a pure function, each value its own atomic, the stamp
  // published last).
  // 16-bit stamps keep an entry at 72 bytes with the coarse box (56 without it, when stamps
  // were 32-bit): the border tables stay a small part of a buffer, which grows 4x per level.
  struct BorderSegment {
    std::atomic<uint16_t> boxStamp{0}, radiusStamp[2] = {0, 0}, coarseStamp{0};
    std::atomic<float> box[6];
    std::atomic<float> coarse[6];  // Patch::coarseBoundsOverAt and the chord's two vertices
    std::atomic<double> radius[2] = {0, 0};  // from pieces of level k + 3 and k + radiusSplit(k)
  };
  void allocate(Sample& s) const;
  void newStamp();
  void diceSample(const Patch& patch, int sample, int level, Sample& out);
  void buildTree(const GridArray<Vec3>& positions, GridArray<float>& nodes) const;
  void buildBorders(int sample, const Sample& s, GridArray<float>& borders) const;  // reads patch_
  void buildThinBounds();  // thinBounds_ of a static dicing with borders
  // The borders a query tests: bit e of `mask` for border e, of `thin` for a thin region
  // (BottomQuery::thinBorders) of radius thinRadius[e].
  struct BorderRegions {
    unsigned mask = 0, thin = 0;
    const double* thinRadius = nullptr;
  };
  // The query's borders; thin regions only on a static dicing.
  static BorderRegions regionsOf(const BottomQuery& q, bool moving);
  template <bool AnyHit, bool Moving>
  bool traverse(Vec3 org, Vec3 dir, float tmin, float tmax, int rayLevel, float alpha, const BorderRegions& regions,
                GridHit* hit) const;
  template <bool AnyHit, bool Moving>
  bool traverseBorders(const RayBoxQuery& q, Vec3 dir, const Vec3& pad, float watertightError, float tmin,
                       float tmax, int k, float w0, float w1, const BorderRegions& regions, Best& best) const;
  // The box of the true border curve over segment j of border e at level i, of time sample
  // `sample` (Patch::boundsOverAt on the degenerate rectangle); of a static dicing's sample,
  // cached for i <= maxLevel in the dicing and in the shared table. (The radii's pieces are
  // Patch::borderPieceBoundsAt's, not these.)
  Box3 curveBox(int e, int i, uint32_t j, int sample) const;
  // A static dicing's region box of segment j of border e at level i <= level(): curveBox and
  // the chord's two grid vertices.
  Box3 regionBox(int e, int i, uint32_t j) const;
  // False only when the ray misses regionBox(e, i, j) grown by `pad` over [tmin, tmax]: tested
  // on a coarse box around it (Patch::coarseBoundsOverAt and the chord, kept per dicing) while
  // the region box itself is not known, so a box no ray reaches is never computed (a displaced
  // patch's boundsOver was a third of teapot-field's bottom stage, bench/history/2026-11.md,
  // "Curve boxes only where a ray may reach them"). True for a moving dicing, a segment whose box is known and a
  // patch without a coarse box: the caller's own test of the region box decides.
  bool mayEnterRegionBox(int e, int i, uint32_t j, const RayBoxQuery& q, const Vec3& pad, float tmin,
                         float tmax) const {
    if (moving_ || i > maxLevel_ ||
        segments_[borderOffset(e, i, j) / 6].boxStamp.load(std::memory_order_acquire) == stamp_)
      return true;
    return mayEnterCoarseBox(e, i, j, q, pad, tmin, tmax);
  }
  bool mayEnterCoarseBox(int e, int i, uint32_t j, const RayBoxQuery& q, const Vec3& pad, float tmin,
                         float tmax) const;
  // Radius about the chord's line (a, b) that holds the true border curve of segment j of
  // border e at level k, from its pieces of level k + split (with `blend`, the pieces blended
  // at time weights w0, w1): see border_regions.cpp.
  double borderRadius(int e, int k, uint32_t j, Vec3 a, Vec3 b, int split, bool blend, float w0, float w1) const;
  // A static region's pieces are of level k + radiusSplit(k) = max(k + 3, 6).
  static int radiusSplit(int k) { return std::max(3, 6 - k); }
  // The same at time weight 0, with split 3 (`coarse`) or radiusSplit(k), cached per dicing.
  double cachedRadius(int e, int k, uint32_t j, Vec3 a, Vec3 b, bool coarse) const;
  // Grid indices of the two ends of segment j of border e at level i of a level-m grid.
  static void chordEnds(int e, int i, uint32_t j, int m, size_t& v0, size_t& v1);
  size_t borderOffset(int e, int level, uint32_t j) const {
    return 6 * (size_t(e) * ((size_t(2) << maxLevel_) - 1) + ((size_t(1) << level) - 1) + j);
  }

  int maxLevel_ = 0;
  int level_ = 0;
  bool moving_ = false;   // the second sample (b_) holds this dicing's other time sample
  const Patch* patch_ = nullptr;  // the diced patch (border regions query it; must outlive the queries)
  int sampleA_ = 0;       // its time samples in a_ and b_
  SharedBorderBounds shared_;  // a static dicing's shared table (cache null: none)
  bool borders_ = false;  // this dicing has border regions
  // Per (border, level <= maxLevel, segment), index borderOffset() / 6: what this dicing has
  // computed of its borders (a moving dicing uses only the radii, at alpha 0).
  std::unique_ptr<BorderSegment[]> segments_;
  uint16_t stamp_ = 0;    // this dicing's serial number (entries with another stamp are stale)
  Sample a_;              // first (or only) time sample
  Sample b_;              // second time sample: allocated by the first diceInterval()
  // The tree, stored by sibling groups: group g of level i (i < level_) holds the boxes of the
  // 4 children (level i+1, Z-order 4g..4g+3) of node g of level i as structure of arrays,
  // kNodeGroupFloats floats: lo.x[4] hi.x[4] lo.y[4] hi.y[4] lo.z[4] hi.z[4]. Groups of level i
  // start at group (4^i - 1) / 3; the root box (lo, hi: 6 floats) follows the groups of the
  // largest level. One traversal step is then one 4-wide slab test on 96 contiguous bytes.
  // Same size as one Box3 per node: sum_{i<=maxLevel} 4^i boxes.
  static constexpr size_t kNodeGroupFloats = 24;
  // Groups before level i, (4^i - 1) / 3, from a table: the division was 5 % of a traversal's
  // instructions (callgrind, bench/history/2026-11.md, "Where the bottom level's instructions go").
  static constexpr uint32_t kLevelGroups[14] = {0, 1, 5, 21, 85, 341, 1365, 5461, 21845, 87381, 349525,
                                                1398101, 5592405, 22369621};
  static size_t groupOffset(int level, uint32_t g) { return kNodeGroupFloats * (size_t(kLevelGroups[level]) + g); }
  const float* nodeGroup(int level, uint32_t g) const { return a_.nodes.data() + groupOffset(level, g); }
  const float* rootBox() const { return a_.nodes.data() + groupOffset(maxLevel_, 0); }
  Box3 patchBounds_;         // the diced patch's bounds(): sets the per-ray box margin
  // A SubPatch's place in its parent (all 0 for any other patch): where its hits are reported;
  // a SubPatch's patchBounds_ are its parent's.
  uint32_t subX_ = 0, subY_ = 0;
  int subDepth_ = 0;
  void setPlace(const Patch& patch);
  // A static dicing with borders: per border e and level k <= min(level(), kMaxThinLevel), the
  // bounds of its level-k border vertices. It contains every thin segment box of (e, k) (grown
  // and padded alike, rounding being monotone), so a ray that misses it grown skips the linear
  // walk over the 2^k segments (traverseBorders).
  Box3 thinBounds_[4][BottomQuery::kMaxThinLevel + 1];
};

// Level of detail, per ray: the smallest m with patchSize / 2^m <= footprintWidth, clamped to
// [0, maxLevel]. footprintWidth <= 0 or non-finite gives maxLevel; patchSize <= 0 gives 0.
// (Precedence: maxLevel <= 0 gives 0, then patchSize <= 0 gives 0; a NaN or infinite
// patchSize gives maxLevel, the safe choice for an unknown size.)
int levelForFootprint(float patchSize, float footprintWidth, int maxLevel);
// The coarsest level at which a patch's dicing error bound, errorCoefficient / 4^m
// (Patch::dicingErrorCoefficient), is at most kRelativeDicingError of its size: the per-ray
// rule's floor (docs/design.md, "Level of detail and energy"). A footprint as wide as a curved
// patch would otherwise see it as a few chords, which lie inside a convex surface (its shadow
// shrinks) and whose planes lean tens of degrees off its normals (reflections lost); both err
// by about the dicing error over the size, so this bounds them. Planar patches (C = 0) get 0;
// a non-finite C gets maxLevel; clamped to [0, maxLevel].
// 2^-8: at 2^-10 the bias was -0.04 %, at 2^-8 -0.07 % and at 2^-6 -0.06 %, all within the
// 0.045 % standard error of tests/app/lod_rule_test.cpp and the 0.1 % goal, while forest-100's
// displaced bark (C its box's side) made 138 M, 32 M and 8 M micropolygons at 480x192 4 spp
// (5.6 M without a floor); docs/design.md, "The floor at a distance".
inline constexpr double kRelativeDicingError = 1.0 / 256;
int levelForDicingError(float patchSize, float errorCoefficient, int maxLevel);
// The floor for a ray that meets the patch at `distance` (its entry into the leaf's box): the
// tolerance is kRelativeDicingError of max(patchSize, distance), so beyond the patch's own size
// the error is bounded as an angle seen from the ray's origin (2^-8 rad, about a pixel of a
// 180-row 40-degree camera; a camera ray's own footprint asks more wherever it resolves more)
// rather than against the patch. Each quadrupling of the distance past patchSize lowers
// `floorAtSize` (levelForDicingError of the patch) by one: exactly the level against a size
// S 4^k (C / 4^m <= S 4^k / 256 iff m + k >= the floor), k the most quadruplings within the
// distance, so never coarser than the rule against the distance itself and at most one level
// finer, with integer steps and no division. Measured (docs/design.md, "The floor at a
// distance"): on forest-100 a floor of the patch alone diced every displaced leaf at level 5
// wherever it stood; near patches (distance <= size) keep the floor unchanged.
// A NaN or non-positive distance, or a size <= 0 or non-finite, keeps floorAtSize.
int floorAtDistance(int floorAtSize, float patchSize, float distance);
// `level` shifted by `bias` (--lod-bias), clamped to [0, maxLevel] (maxLevel < 0 counts as 0).
int biasedLevel(int level, int bias, int maxLevel);

// The thesis's batch-density rule (--lod density): the smallest m with 4^m >= rays / spp,
// clamped to [0, maxLevel]. spp <= 0 counts as 1; rays == 0 gives 0.
int levelForDensity(uint64_t rays, int spp, int maxLevel);

}  // namespace rayes
