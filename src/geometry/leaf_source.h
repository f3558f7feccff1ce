// START HERE for where leaves come from. A LeafSource is the scene's list of top-level leaves:
// how many, each one's conservative box, its Patch when it is to be diced, and the few facts a
// render needs at setup (LeafFacts) without keeping patches. Two kinds of leaves:
// - stored: a Patch built by the scene loader and kept for the whole render (patch(i) returns the
//   stored pointer);
// - generated: a compact record from which the Patch is made on demand (the forest; patch(i)
//   builds it, and the caller drops it after dicing), so memory grows with the leaf count,
//   never with the patches' control points or micropolygons.
// A LeafList concatenates sources: leaf ids run through its parts in the order they were added.
//
// Contracts: bounds(i) contains every point patch(i) can produce (docs/design.md, invariant 1);
// facts(i) equals what the Patch itself reports; patch(i) is a pure function of i (the same
// surface, bit for bit, every time it is made). Immutable once built; every const method is
// thread-safe.
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>
#include "core/box.h"
#include "geometry/patch.h"

namespace rayes {

// What a leaf's Patch says of itself, for setup (level of detail, offsets, features, stats).
struct LeafFacts {
  float sizeBound = 0;         // Patch::sizeBound
  float dicingError = 0;       // Patch::dicingErrorCoefficient
  int timeSamples = 1;         // Patch::timeSamples
  const char* kind = "";       // Patch::kind; valid while the source lives
  bool displaced = false;      // Patch::isDisplaced
  bool subdivision = false;    // Patch::isSubdivision
  bool borderClosure = false;  // Patch::needsBorderClosure

  static LeafFacts of(const Patch& patch);
};

class LeafSource {
 public:
  virtual ~LeafSource() = default;
  virtual size_t size() const = 0;
  virtual Box3 bounds(size_t i) const = 0;
  virtual PatchPtr patch(size_t i) const = 0;
  virtual LeafFacts facts(size_t i) const = 0;
  // Bytes this source keeps to describe its leaves (records, boxes, stored patches' objects).
  virtual size_t descriptionBytes() const = 0;
};
using LeafSourcePtr = std::shared_ptr<const LeafSource>;

// Stored patches, kept for the whole render.
class StoredLeaves final : public LeafSource {
 public:
  StoredLeaves() = default;
  explicit StoredLeaves(std::vector<PatchPtr> patches) : patches_(std::move(patches)) {}
  void add(PatchPtr patch) { patches_.push_back(std::move(patch)); }
  size_t size() const override { return patches_.size(); }
  Box3 bounds(size_t i) const override { return patches_[i]->bounds(); }
  PatchPtr patch(size_t i) const override { return patches_[i]; }
  LeafFacts facts(size_t i) const override { return LeafFacts::of(*patches_[i]); }
  size_t descriptionBytes() const override;

 private:
  std::vector<PatchPtr> patches_;
};

// The scene's leaves: stored patches and generated sources, concatenated in the order added.
class LeafList final : public LeafSource {
 public:
  void add(PatchPtr patch);            // appends one stored leaf
  void add(LeafSourcePtr generated);   // appends every leaf of `generated`
  size_t size() const override { return size_; }
  Box3 bounds(size_t i) const override;
  PatchPtr patch(size_t i) const override;
  LeafFacts facts(size_t i) const override;
  size_t descriptionBytes() const override;
  bool empty() const { return size_ == 0; }
  // The part holding leaf i and i's index inside it (a compiled scene stores a forest's leaves
  // by their forest: scene/compiled_scene.cpp). O(log parts).
  std::pair<const LeafSource*, size_t> locate(size_t i) const;

 private:

  std::vector<LeafSourcePtr> parts_;
  std::vector<size_t> first_;  // first leaf id of each part
  std::shared_ptr<StoredLeaves> open_;  // the last part when it is stored: add(patch) extends it
  size_t size_ = 0;
};

}  // namespace rayes
