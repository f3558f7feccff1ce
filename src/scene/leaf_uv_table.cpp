#include "scene/leaf_uv_table.h"
#include "core/error.h"

namespace rayes {

using compiled::SectionKind;

std::shared_ptr<LeafUvTable> LeafUvTable::mapped(std::shared_ptr<const MappedFile> file, size_t leaves,
                                                 std::vector<std::shared_ptr<const SubdivUvSet>> sets) {
  auto t = std::make_shared<LeafUvTable>();
  const uint64_t bytes = file->sectionBytes(SectionKind::UvSets), refs = uint64_t(leaves) * sizeof(Ref);
  if (bytes < refs || (bytes - refs) % sizeof(UvCorners) != 0)
    throw InputError(file->path(), "section uv_sets",
                     "not one 8-byte record per leaf (" + std::to_string(leaves) + " leaves) and whole corners (" +
                         std::to_string(bytes) + " bytes)");
  t->mappedLeaves_ = leaves;
  t->mappedCorners_ = size_t((bytes - refs) / sizeof(UvCorners));
  t->subdiv_ = std::move(sets);
  t->file_ = std::move(file);
  return t;
}

void LeafUvTable::corrupt(uint32_t leaf, const std::string& why) const {
  throw InputError(file_->path(), "section uv_sets (leaf " + std::to_string(leaf) + ")", why + ": the file is corrupt");
}

LeafUvTable::Ref LeafUvTable::ref(uint32_t leaf) const {
  if (!file_) return leaf < refs_.size() ? refs_[leaf] : Ref{};
  if (leaf >= mappedLeaves_) return Ref{};
  Ref r;
  file_->read(SectionKind::UvSets, uint64_t(leaf) * sizeof(Ref), sizeof(Ref), &r, "leaf", leaf);
  if (r.table == kCorners && r.index >= mappedCorners_)
    corrupt(leaf, "uv corners " + std::to_string(r.index) + " of " + std::to_string(mappedCorners_));
  if (r.table >= 2) {
    const size_t k = size_t(r.table) - 2;
    if (k >= subdiv_.size() || !subdiv_[k])
      corrupt(leaf, "the uv set of topology " + std::to_string(k) + ", which has none");
    if (r.index >= uint32_t(subdiv_[k]->leafCount()))
      corrupt(leaf, "leaf " + std::to_string(r.index) + " of a uv set of " + std::to_string(subdiv_[k]->leafCount()));
  }
  return r;
}

UvCorners LeafUvTable::corners(uint32_t index) const {
  if (!file_) return corners_[index];
  UvCorners c;
  file_->read(SectionKind::UvSets, uint64_t(mappedLeaves_) * sizeof(Ref) + uint64_t(index) * sizeof(UvCorners), sizeof c,
              &c, "uv corners", index);
  return c;
}

LeafUvTable::Ref& LeafUvTable::refFor(uint32_t leaf) {
  if (leaf >= refs_.size()) refs_.resize(size_t(leaf) + 1);
  return refs_[leaf];
}

void LeafUvTable::setCorners(uint32_t leaf, const UvCorners& corners) {
  refFor(leaf) = {kCorners, uint32_t(corners_.size())};
  corners_.push_back(corners);
}

void LeafUvTable::setSubdiv(uint32_t leaf, const std::shared_ptr<const SubdivUvSet>& set, uint32_t meshLeaf) {
  // Shapes add their leaves in turn, so a set already known is the last one.
  if (subdiv_.empty() || subdiv_.back() != set) subdiv_.push_back(set);
  refFor(leaf) = {uint32_t(subdiv_.size() - 1) + 2, meshLeaf};
}

TexCoordSample LeafUvTable::at(uint32_t leaf, float u, float v) const {
  const Ref r = ref(leaf);
  TexCoordSample out;
  if (r.table == kCorners) {
    const UvCorners c = corners(r.index);
    for (int k = 0; k < 2; ++k) {
      const float e0 = c[1][k] - c[0][k], e1 = c[3][k] - c[2][k];  // along u at v = 0 and v = 1
      const float along = (1 - v) * e0 + v * e1;
      const float across = (1 - u) * (c[2][k] - c[0][k]) + u * (c[3][k] - c[1][k]);
      const float value = (1 - v) * (c[0][k] + u * e0) + v * (c[2][k] + u * e1);
      (k == 0 ? out.s : out.t) = value;
      (k == 0 ? out.dsdu : out.dtdu) = along;
      (k == 0 ? out.dsdv : out.dtdv) = across;
    }
    return out;
  }
  float st[2], du[2], dv[2];
  subdiv_[r.table - 2]->evaluate(int(r.index), u, v, st, du, dv);
  out.s = st[0]; out.t = st[1];
  out.dsdu = du[0]; out.dtdu = du[1];
  out.dsdv = dv[0]; out.dtdv = dv[1];
  return out;
}

size_t LeafUvTable::bytes() const {
  size_t b = refs_.capacity() * sizeof(Ref) + corners_.capacity() * sizeof(UvCorners) +
             subdiv_.capacity() * sizeof(subdiv_[0]);
  for (const auto& s : subdiv_)
    if (s) b += s->bytes();
  return b;
}

}  // namespace rayes
