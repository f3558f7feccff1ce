#include "scene/leaf_uv_table.h"

namespace rayes {

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
  const Ref r = refs_[leaf];
  TexCoordSample out;
  if (r.table == kCorners) {
    const UvCorners& c = corners_[r.index];
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
  for (const auto& s : subdiv_) b += s->bytes();
  return b;
}

}  // namespace rayes
