// The OpenVDB module (librayes_openvdb.so): scene/vdb_grid.h's VdbGrid over an OpenVDB float grid,
// and its one exported entry point. Only the module links OpenVDB; the program loads it when a
// scene names a volume (core/plugin_module.h).
#include <algorithm>
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>
#include "scene/vdb_grid.h"

namespace rayes {
namespace {

using FloatLeaf = openvdb::FloatTree::LeafNodeType;

VoxelCoord coordOf(const openvdb::Coord& c) { return {c.x(), c.y(), c.z()}; }

// The stored bricks of one grid: its leaves, out of core, in leaf order.
class VdbBrickSource final : public BrickSource {
 public:
  explicit VdbBrickSource(openvdb::FloatGrid::Ptr grid) : grid_(std::move(grid)) {
    leaves_.reserve(grid_->tree().leafCount());
    for (auto leaf = grid_->tree().cbeginLeaf(); leaf; ++leaf) leaves_.push_back(leaf.getLeaf());
    residentBytes_ = grid_->memUsage() + leaves_.capacity() * sizeof(const FloatLeaf*);
  }
  size_t leaves() const { return leaves_.size(); }
  const FloatLeaf& leaf(size_t i) const { return *leaves_[i]; }
  void read(uint32_t stored, float* voxels) const override {
    const FloatLeaf::Buffer copy(leaves_[stored]->buffer());  // out of core: the copy loads, the tree does not
    const float* v = copy.data();
    std::copy(v, v + FloatLeaf::SIZE, voxels);
  }
  uint64_t residentBytes() const override { return residentBytes_; }

 private:
  openvdb::FloatGrid::Ptr grid_;
  std::vector<const FloatLeaf*> leaves_;
  uint64_t residentBytes_ = 0;
};

class OpenVdbGrid final : public VdbGrid {
 public:
  explicit OpenVdbGrid(openvdb::FloatGrid::Ptr grid)
      : grid_(std::move(grid)), bricks_(std::make_shared<VdbBrickSource>(grid_)) {}
  float background() const override { return grid_->background(); }
  // OpenVDB multiplies row vectors: world = index · M.
  bool indexToWorld(TransformD& out) const override {
    const openvdb::math::Transform& t = grid_->transform();
    if (!t.isLinear()) return false;
    const openvdb::math::Mat4d m = t.baseMap()->getAffineMap()->getMat4();
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) out.m[i][j] = m(j, i);
      out.m[i][3] = m(3, i);
    }
    return true;
  }
  bool sameTransform(const VdbGrid& other) const override {
    return grid_->transform() == static_cast<const OpenVdbGrid&>(other).grid_->transform();
  }
  bool activeBox(VoxelCoord& lo, VoxelCoord& hi) const override {
    const openvdb::CoordBBox active = grid_->evalActiveVoxelBoundingBox();
    if (active.empty()) return false;
    lo = coordOf(active.min());
    hi = coordOf(active.max());
    return true;
  }
  size_t leafCount() const override { return bricks_->leaves(); }
  VoxelCoord leafOrigin(size_t leaf) const override { return coordOf(bricks_->leaf(leaf).origin()); }
  std::shared_ptr<BrickSource> bricks() const override { return bricks_; }
  std::vector<VdbTile> tiles() const override {
    std::vector<VdbTile> out;
    auto it = grid_->tree().cbeginValueOn();
    it.setMaxDepth(it.getLeafDepth() - 1);  // tiles only, not every active voxel
    for (; it; ++it) {
      openvdb::CoordBBox box;
      it.getBoundingBox(box);
      out.push_back({coordOf(box.min()), coordOf(box.max()), *it});
    }
    return out;
  }
  uint64_t leafNodeBytes() const override { return sizeof(FloatLeaf); }

 private:
  openvdb::FloatGrid::Ptr grid_;
  std::shared_ptr<VdbBrickSource> bricks_;
};

void readGrid(const std::string& path, const std::string& name, VdbGridRead& out) {
  openvdb::initialize();  // thread-safe and idempotent
  openvdb::io::File file(path);
  // Mapped in place: OpenVDB would otherwise copy a file below 500 MB to a temporary one first
  // (a second copy of the whole grid on disk, or in memory on a tmpfs).
  file.setCopyMaxBytes(0);
  file.open(/*delayLoad=*/true);  // leaf buffers are read when a leaf is first touched
  if (!file.hasGrid(name)) {
    for (auto it = file.beginName(); it != file.endName(); ++it) out.names.push_back(*it);
    return;
  }
  out.found = true;
  const openvdb::GridBase::Ptr base = file.readGrid(name);
  openvdb::FloatGrid::Ptr grid = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
  file.close();
  if (!grid) {
    out.valueType = base->valueType();
    return;
  }
  out.grid = std::make_unique<OpenVdbGrid>(std::move(grid));
}

}  // namespace
}  // namespace rayes

// The module's entry point (scene/vdb_grid.h, ReadVdbGridFn): exceptions stay inside.
extern "C" __attribute__((visibility("default"))) void rayes_openvdb_read_grid(const std::string* file,
                                                                               const std::string* name,
                                                                               rayes::VdbGridRead* out) {
  try {
    rayes::readGrid(*file, *name, *out);
  } catch (const std::exception& e) {  // openvdb::Exception and std::bad_alloc alike: the file is unreadable
    out->grid.reset();
    out->error = e.what();
  }
}
