// A Forest as a LeafSource (geometry/leaf_source.h): its leaves in the forest's own order, each
// patch made on demand by Forest::makePatch, the facts from what the forest recorded at
// generation (size bound, dicing error per leaf) and from its part (kind and flags are the same
// for every leaf of a part). Shares ownership of the forest; immutable.
#pragma once
#include <array>
#include <memory>
#include <string>
#include "geometry/forest.h"
#include "geometry/leaf_source.h"

namespace rayes {

// What a render holds per forest leaf at most: the description (Forest::bytesPerLeaf, about
// 60 B), the per-leaf tables of the render (box, material, size, dicing error: about 70 B), the
// top level's share of nodes and the setup's transient facts. The loader refuses a forest whose
// leaves times this exceeds what the memory limit has available (core/memory.h), before growing it.
constexpr uint64_t kForestBoundBytesPerLeaf = 256;

class ForestLeaves final : public LeafSource {
 public:
  explicit ForestLeaves(std::shared_ptr<const Forest> forest);
  ForestLeaves(const ForestLeaves&) = delete;  // facts point into part_
  ForestLeaves& operator=(const ForestLeaves&) = delete;
  size_t size() const override { return forest_->size(); }
  Box3 bounds(size_t i) const override { return forest_->bounds(i); }
  PatchPtr patch(size_t i) const override { return forest_->makePatch(i); }
  LeafFacts facts(size_t i) const override;
  size_t descriptionBytes() const override;
  const Forest& forest() const { return *forest_; }

 private:
  std::shared_ptr<const Forest> forest_;
  struct PartFacts {
    std::string kind;
    LeafFacts facts;  // kind points into `kind`
  };
  std::array<PartFacts, 3> part_;  // by ForestLeaf::Part
};

}  // namespace rayes
