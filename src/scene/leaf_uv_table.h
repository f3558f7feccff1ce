// The scene's uv sets by leaf: shading's TexCoordSource (shading/texture_query.h) over every
// leaf. Per leaf one 8-byte record (which table, which entry) up to the last leaf with a uv
// set; the entries are plain tables: four (s, t) corners per Bézier or bilinear patch (bilinear
// in the patch's (u, v)), or a leaf of a subdivision mesh's uv set (geometry/subdiv_uv.h).
// Generated leaves (the forest) have none. A scene without uv sets builds no table at all.
//
// Two storages, one table: built in memory by the scene loader while shapes are added, or read
// from a compiled scene's UvSets section (geometry/compiled_file.h: the same 8-byte records,
// then the corners) through its mapping, record by record as leaves are asked about, never
// copied whole (mapped()); then only the subdivision uv sets are in memory. A mapped record
// that names no table or entry is an InputError naming the file and the leaf (at first touch).
//
// Immutable once built: has() and at() are const and thread-safe; O(1) (a subdivision leaf:
// one Bfr face-varying evaluation; a mapped record: one or two reads of the mapping).
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>
#include "geometry/compiled_file.h"
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
  LeafUvTable() = default;
  // The UvSets section of `file`, for leaves [0, leaves): `sets[k]` is the uv set of the
  // file's topology k (null where it has none). InputError when the section's size is not
  // `leaves` records and whole corners.
  static std::shared_ptr<LeafUvTable> mapped(std::shared_ptr<const MappedFile> file, size_t leaves,
                                             std::vector<std::shared_ptr<const SubdivUvSet>> sets);

  // Leaf `leaf` reads the corners; leaves added earlier and not given a uv set have none.
  void setCorners(uint32_t leaf, const UvCorners& corners);
  // Leaf `leaf` is leaf `meshLeaf` of `set` (registered once per set).
  void setSubdiv(uint32_t leaf, const std::shared_ptr<const SubdivUvSet>& set, uint32_t meshLeaf);

  bool has(uint32_t leaf) const override { return ref(leaf).table != kNone; }
  TexCoordSample at(uint32_t leaf, float u, float v) const override;

  // The per-leaf records, corners and subdivision uv sets held in memory (a mapped table: the
  // sets only; its records count in the mapping).
  size_t bytes() const;

  // What a compiled scene stores (scene/compiled_scene.cpp): leaf's record (table kNone
  // beyond the last leaf with a uv set), corners by index, the subdivision set of table t >= 2.
  static constexpr uint32_t kNone = 0, kCorners = 1;  // table >= 2: subdivision set table - 2
  using Ref = compiled::UvRef;  // index: into the corners, or the leaf in its mesh
  Ref ref(uint32_t leaf) const;
  UvCorners corners(uint32_t index) const;
  size_t cornerCount() const { return file_ ? mappedCorners_ : corners_.size(); }
  const SubdivUvSet* subdivSet(uint32_t table) const { return subdiv_[table - 2].get(); }

 private:
  Ref& refFor(uint32_t leaf);
  [[noreturn]] void corrupt(uint32_t leaf, const std::string& why) const;

  std::vector<Ref> refs_;
  std::vector<UvCorners> corners_;
  std::vector<std::shared_ptr<const SubdivUvSet>> subdiv_;
  // Mapped: the file, its leaves' records, its corners after them.
  std::shared_ptr<const MappedFile> file_;
  size_t mappedLeaves_ = 0, mappedCorners_ = 0;
};

}  // namespace rayes
