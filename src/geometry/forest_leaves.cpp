#include "geometry/forest_leaves.h"
#include <cmath>

namespace rayes {

ForestLeaves::ForestLeaves(std::shared_ptr<const Forest> forest) : forest_(std::move(forest)) {
  // One patch of each part says what every patch of that part is.
  std::array<bool, 3> seen{};
  for (size_t i = 0; i < forest_->size(); ++i) {
    const size_t part = size_t(forest_->leaf(i).part);
    if (seen[part]) continue;
    seen[part] = true;
    const PatchPtr p = forest_->makePatch(i);
    part_[part].kind = p->kind();
    part_[part].facts = LeafFacts::of(*p);
    if (seen[0] && seen[1] && seen[2]) break;
  }
  for (PartFacts& pf : part_) pf.facts.kind = pf.kind.c_str();
}

LeafFacts ForestLeaves::facts(size_t i) const {
  LeafFacts f = part_[size_t(forest_->leaf(i).part)].facts;
  f.sizeBound = forest_->sizeBound(i);
  f.dicingError = forest_->dicingError(i);
  return f;
}

size_t ForestLeaves::descriptionBytes() const {
  return size_t(std::llround(forest_->bytesPerLeaf() * double(forest_->size())));
}

}  // namespace rayes
