// START HERE for the top level. A 4-wide BVH over the conservative boxes of all leaves (one
// patch per leaf), built once per render with Embree's rtcBuildBVH (binned SAH) into our own
// node layout, and a traversal that hands out a ray's candidate leaves front to back, a few at
// a time, resuming where the previous call stopped.
//
// Order and resumption: candidates come in increasing (entry distance, leaf id) order. A call
// returns those strictly after the resume point (resumeEntry, resumeLeaf) and no later than
// tmax, at most maxCount of them, plus nextEntry: a lower bound on the entry distance of every
// leaf not yet returned (+inf when none is left); this implementation returns the exact entry
// of the next candidate. So a ray whose best hit is nearer than nextEntry is finished
// (conservative termination), and the result of a whole trace does not depend on how many
// candidates each call returned. Entry distances are bit-identical to intersectBox (core/box.h)
// on the leaf's box, so callers and tests may compare them exactly.
//
// Threads: the BVH is immutable after build() or adopt(); collect() is const and thread-safe,
// each thread passing its own TraversalScratch. Memory: 128 bytes per inner node (about n/2
// inner nodes for n leaves: SAH leaves many 2- and 3-child nodes near the leaves) and the leaf
// boxes it was built over (24 bytes per leaf: the one copy of them a render keeps, read by the
// engine and lbt); no geometry is stored here and nothing of Embree is kept after build().
// A tree built earlier and stored (a compiled scene, `rayes compile`) is adopted instead: its
// nodes and boxes are then read in place through their gates (core/gated_span.h) and this
// object holds none of them. Node layout: toplevel_node.h.
#pragma once
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>
#include "core/box.h"
#include "core/gated_span.h"

namespace rayes {

namespace toplevel { struct Inspector; }

struct Candidate {
  uint32_t leaf;
  float entry;  // entry distance into the leaf's box, clamped to the ray's tmin
};

// Reusable per-thread storage for the traversal: its node stack (the member keeps the name
// `heap` from an earlier best-first design). No allocation per ray once warmed up.
struct TraversalScratch {
  struct Item { float entry; uint32_t ref; };
  std::vector<Item> heap;
};

class TopLevelBvh {
 public:
  TopLevelBvh();
  ~TopLevelBvh();
  TopLevelBvh(const TopLevelBvh&) = delete;
  TopLevelBvh& operator=(const TopLevelBvh&) = delete;

  // Builds over leafBoxes[i] for leaf id i (fewer than 2^31 of them). Empty boxes (and boxes
  // with a NaN bound) are left out: never candidates. Boxes must otherwise be finite.
  // Rebuilding replaces the previous tree. The boxes are kept (leafBoxes()): copied, or taken.
  void build(std::span<const Box3> leafBoxes);
  void build(std::vector<Box3>&& leafBoxes);
  // The boxes of the last build, by leaf id (empty ones included).
  GatedSpan<Box3> leafBoxes() const;

  // The tree to store: `nodeCount` nodes of kNodeBytes each at `nodes`, depth first (a parent
  // before its children, the root first), and the root's ref. Valid until the next build.
  static constexpr size_t kNodeBytes = 128;
  struct Stored {
    const void* nodes = nullptr;
    size_t nodeCount = 0;
    uint32_t root = 0;
  };
  Stored stored() const;
  // Takes a stored tree over `leafBoxes` in place, read through `nodeGate` (may be null):
  // the same traversal, the same candidates in the same order as the tree that was stored.
  // Every node is checked once here (a child after its parent and in range, a leaf id below
  // leafBoxes.size(), unused slots empty), so that no stored tree, however made, leads the
  // traversal out of bounds or into a loop: std::invalid_argument naming the node otherwise.
  // `nodeOffset`: where the first node lies in the gate's range.
  void adopt(const void* nodes, size_t nodeCount, const BlockGate* nodeGate, uint64_t nodeOffset, uint32_t root,
             GatedSpan<Box3> leafBoxes);
  bool adopted() const;

  // See the contract above. Start a trace with resumeEntry = -inf (any resumeLeaf); tmin must
  // be finite (entries are clamped to it, so they then exceed -inf). Returns the number of
  // candidates written to out; maxCount <= 0 only computes nextEntry. With `nextLeaf`, also the
  // leaf of that next candidate (the (maxCount + 1)-th; unchanged when there is none): a caller
  // may then keep (nextEntry, nextLeaf) alone and resume at it (resumeBefore).
  int collect(Vec3 org, Vec3 dir, float tmin, float tmax, float resumeEntry, uint32_t resumeLeaf,
              Candidate* out, int maxCount, float& nextEntry, TraversalScratch& scratch,
              uint32_t* nextLeaf = nullptr) const;
  // The resume point (resumeEntry, resumeLeaf) whose candidates are exactly those at or after
  // (entry, leaf) in candidate order: the one just before it (the float below entry with any
  // leaf, when leaf is 0). Exact: no float lies between entry and the one below it.
  static void resumeBefore(float entry, uint32_t leaf, float& resumeEntry, uint32_t& resumeLeaf) {
    if (leaf > 0 || entry == -std::numeric_limits<float>::infinity()) {  // (-inf, 0): from the start
      resumeEntry = entry;
      resumeLeaf = leaf > 0 ? leaf - 1 : 0;
    } else {
      resumeEntry = std::nextafter(entry, -std::numeric_limits<float>::infinity());
      resumeLeaf = std::numeric_limits<uint32_t>::max();
    }
  }

  // The leaves whose boxes overlap `box` (closed: touching counts), appended to `out` in
  // increasing leaf id. Thread-safe; a box query for what is not a ray (light beam segments).
  void overlapping(const Box3& box, std::vector<uint32_t>& out, TraversalScratch& scratch) const;

  // Whether a leaf other than `except` has a box that meets `box` (closed boxes: touching
  // counts). For set-up questions such as "can anything lie across this border", not per ray.
  bool anyOtherLeafMeets(const Box3& box, uint32_t except) const;

  size_t leafCount() const { return leafCount_; }  // leaf ids, empty boxes included
  size_t nodeCount() const;
  size_t bytes() const;     // memory held by the nodes and the leaf boxes (0 when adopted: they are the mapping's)
  Box3 bounds() const;      // scene bounds (union of all leaf boxes)

 private:
  friend struct toplevel::Inspector;  // tests and statistics read the nodes (toplevel_node.h)
  struct Impl;
  Impl* impl_ = nullptr;
  size_t leafCount_ = 0;
};

}  // namespace rayes
