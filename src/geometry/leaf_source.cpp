#include "geometry/leaf_source.h"
#include <algorithm>

namespace rayes {

LeafFacts LeafFacts::of(const Patch& p) {
  LeafFacts f;
  f.sizeBound = p.sizeBound();
  f.dicingError = p.dicingErrorCoefficient();
  f.timeSamples = p.timeSamples();
  f.kind = p.kind();
  f.displaced = p.isDisplaced();
  f.subdivision = p.isSubdivision();
  f.borderClosure = p.needsBorderClosure();
  return f;
}

size_t StoredLeaves::descriptionBytes() const {
  // Pointers and the patch objects' own sizes are not known exactly (each kind has its own
  // layout); a Bézier patch's 16 control points are a fair per-patch figure.
  return patches_.capacity() * sizeof(PatchPtr) + patches_.size() * (16 * sizeof(Vec3) + 64);
}

void LeafList::add(PatchPtr patch) {
  if (!open_) {
    open_ = std::make_shared<StoredLeaves>();
    first_.push_back(size_);
    parts_.push_back(open_);
  }
  open_->add(std::move(patch));
  ++size_;
}

void LeafList::add(LeafSourcePtr generated) {
  open_.reset();
  first_.push_back(size_);
  size_ += generated->size();
  parts_.push_back(std::move(generated));
}

std::pair<const LeafSource*, size_t> LeafList::locate(size_t i) const {
  const size_t part = size_t(std::upper_bound(first_.begin(), first_.end(), i) - first_.begin()) - 1;
  return {parts_[part].get(), i - first_[part]};
}

Box3 LeafList::bounds(size_t i) const {
  const auto [part, k] = locate(i);
  return part->bounds(k);
}

PatchPtr LeafList::patch(size_t i) const {
  const auto [part, k] = locate(i);
  return part->patch(k);
}

LeafFacts LeafList::facts(size_t i) const {
  const auto [part, k] = locate(i);
  return part->facts(k);
}

size_t LeafList::descriptionBytes() const {
  size_t bytes = 0;
  for (const LeafSourcePtr& p : parts_) bytes += p->descriptionBytes();
  return bytes;
}

}  // namespace rayes
