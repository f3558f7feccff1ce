// The scene's uv sets by leaf: shading's TexCoordSource (shading/texture_query.h) over every
// leaf. Per leaf one 8-byte record (which table, which entry) up to the last leaf with a uv
// set; the entries are plain tables: four (s, t) corners per Bézier or bilinear patch (bilinear
// in the patch's (u, v)), or a leaf of a subdivision mesh's uv set (geometry/subdiv_uv.h).
// Generated leaves (the forest) have none. A scene without uv sets builds no table at all.
//
// Built by the scene loader while shapes are added, immutable afterwards: has() and at() are
// const and thread-safe; at() is O(1) (a subdivision leaf: one Bfr face-varying evaluation).
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>
#include "geometry/subdiv_uv.h"
#include "shading/texture_query.h"

namespace rayes {

// (s, t) at the patch corners (u, v) = (0, 0), (1, 0), (0, 1), (1, 1).
using UvCorners = std::array<std::array<float, 2>, 4>;

// What one shape gives its patches (ShapeSource::uvs): patch k of the shape's build() output
// reads corners[k], or leaf k of `subdiv`.
struct ShapeUvs {
  std::vector<UvCorners> corners;
  std::shared_ptr<const SubdivUvSet> subdiv;
};

class LeafUvTable final : public TexCoordSource {
 public:
  // Leaf `leaf` reads the corners; leaves added earlier and not given a uv set have none.
  void setCorners(uint32_t leaf, const UvCorners& corners);
  // Leaf `leaf` is leaf `meshLeaf` of `set` (registered once per set).
  void setSubdiv(uint32_t leaf, const std::shared_ptr<const SubdivUvSet>& set, uint32_t meshLeaf);

  bool has(uint32_t leaf) const override { return leaf < refs_.size() && refs_[leaf].table != kNone; }
  TexCoordSample at(uint32_t leaf, float u, float v) const override;

  // The per-leaf records, corners and subdivision uv sets.
  size_t bytes() const;

 private:
  static constexpr uint32_t kNone = 0, kCorners = 1;  // table >= 2: subdivision set table - 2
  struct Ref {
    uint32_t table = kNone;
    uint32_t index = 0;  // into corners_, or the leaf in its mesh
  };
  Ref& refFor(uint32_t leaf);

  std::vector<Ref> refs_;
  std::vector<UvCorners> corners_;
  std::vector<std::shared_ptr<const SubdivUvSet>> subdiv_;
};

}  // namespace rayes
