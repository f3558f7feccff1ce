// {"type": "volume"} shapes (docs/scene-format.md): a float density grid of a .vdb file read
// with OpenVDB into a shading Medium (shading/medium.h) of 8³-voxel bricks, one per OpenVDB leaf
// node and one per 8³ block of an active tile (a constant brick). The brick is OpenVDB's own
// unit of storage and delayed loading, so the brick cache (shading/brick_cache.h) loads exactly
// one leaf per miss; groups of leaves would only coarsen the majorants (more null collisions).
//
// The grid is opened with delayed loading and its tree kept with every leaf out of core (each
// leaf holds only its file offsets): a leaf's voxels are decoded into a copy of its buffer
// (LeafBuffer's copy keeps the file reference and loads itself), so the tree never grows. At
// load every leaf is decoded once, in parallel, for its largest voxel (the majorants) and to
// refuse bad values before anything renders; while rendering, only the cache's misses read.
//
// The only file that includes OpenVDB: a scene without a volume never initialises it.
#include <algorithm>
#include <chrono>
#include <limits>
#include <cmath>
#include <mutex>
#include <stdexcept>
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>
#include <tbb/parallel_for.h>
#include "core/memory.h"
#include "core/timer.h"
#include "scene/scene_sections.h"
#include "scene/shape_kinds.h"

namespace rayes {
namespace {

std::string coordText(const openvdb::Coord& c) {
  return "(" + std::to_string(c.x()) + ", " + std::to_string(c.y()) + ", " + std::to_string(c.z()) + ")";
}

// The grid's index-to-world map as our Transform (OpenVDB multiplies row vectors: world = index · M).
bool linearIndexToWorld(const openvdb::GridBase& grid, TransformD& out) {
  const openvdb::math::Transform& t = grid.transform();
  if (!t.isLinear()) return false;
  const openvdb::math::Mat4d m = t.baseMap()->getAffineMap()->getMat4();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) out.m[i][j] = m(j, i);
    out.m[i][3] = m(3, i);
  }
  return true;
}

using FloatLeaf = openvdb::FloatTree::LeafNodeType;

// The stored bricks of one grid: its leaves, out of core, in leaf order.
class VdbBrickSource final : public BrickSource {
 public:
  explicit VdbBrickSource(openvdb::FloatGrid::Ptr grid) : grid_(std::move(grid)) {
    leaves_.reserve(grid_->tree().leafCount());
    for (auto leaf = grid_->tree().cbeginLeaf(); leaf; ++leaf) leaves_.push_back(leaf.getLeaf());
    residentBytes_ = grid_->memUsage() + leaves_.capacity() * sizeof(const FloatLeaf*);
  }
  size_t leaves() const { return leaves_.size(); }
  const FloatLeaf& leaf(uint32_t i) const { return *leaves_[i]; }
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

}  // namespace

// {"type": "volume", "file": F, "grid": "density", "density_scale": 1, "sigma_a": 0, "sigma_s": 1,
//  "g": 0, "transform": [...]}
void readVolumeShape(const JsonReader& r, const json& shape, const std::string& p, Scene& scene,
                     const std::filesystem::path& sceneDir) {
  const Clock::time_point t0 = Clock::now();
  r.object(shape, p, {"type", "file", "grid", "density_scale", "sigma_a", "sigma_s", "g", "transform", "emission_grid",
                      "emission", "temperature_grid", "temperature_scale", "blackbody_scale"});
  const ShapeContext ctx{r, shape, p, sceneDir};
  const std::filesystem::path path = ctx.file("file");
  const std::string gridName = shape.contains("grid") ? r.string(shape["grid"], p + "/grid") : std::string("density");
  auto number = [&](const char* key, float fallback, float lo, float hi, const char* range) {
    if (!shape.contains(key)) return fallback;
    const std::string at = p + "/" + key;
    const double v = r.number(shape[key], at);
    if (!(v >= lo && v <= hi)) r.fail(at, std::string("must be in ") + range);
    return float(v);
  };
  const float scale = number("density_scale", 1, 0, 1e9f, "[0, 1e9] (a density scale is not negative)");
  MediumCoefficients coefficients;
  coefficients.sigmaA = number("sigma_a", 0, 0, 1e9f, "[0, 1e9]") * scale;
  coefficients.sigmaS = number("sigma_s", 1, 0, 1e9f, "[0, 1e9]") * scale;
  coefficients.g = number("g", 0, -0.99f, 0.99f, "[-0.99, 0.99]");
  const TransformD xf = shape.contains("transform") ? readTransform(r, shape["transform"], p + "/transform") : TransformD{};

  const std::string named = "'" + path.string() + "', grid '" + gridName + "'";
  const std::string at = p + "/file";
  openvdb::initialize();  // thread-safe and idempotent; here, so a scene without volumes never calls it
  // A float grid of the file by name, with delayed loading; `role` says what it is for.
  auto readGrid = [&](const std::string& name, const std::string& role) {
    const std::string gridNamed = "'" + path.string() + "', grid '" + name + "'";
    openvdb::FloatGrid::Ptr g;
    try {
      openvdb::io::File file(path.string());
      // Mapped in place: OpenVDB would otherwise copy a file below 500 MB to a temporary one first
      // (a second copy of the whole grid on disk, or in memory on a tmpfs).
      file.setCopyMaxBytes(0);
      file.open(/*delayLoad=*/true);  // leaf buffers are read when a leaf is first touched
      if (!file.hasGrid(name)) {
        std::string names;
        for (auto it = file.beginName(); it != file.endName(); ++it) names += (names.empty() ? "" : ", ") + *it;
        r.fail(at, "'" + path.string() + "' has no grid named '" + name + "' (it has: " +
                       (names.empty() ? "none" : names) + ")");
      }
      const openvdb::GridBase::Ptr base = file.readGrid(name);
      g = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
      if (!g) r.fail(at, gridNamed + " holds " + base->valueType() + " values; a " + role + " grid holds float");
      file.close();
    } catch (const InputError&) {
      throw;
    } catch (const std::exception& e) {  // openvdb::Exception and std::bad_alloc alike: the file is unreadable
      r.fail(at, "cannot read " + gridNamed + ": " + e.what());
    }
    if (g->background() != 0.0f)
      r.fail(at, gridNamed + " has background " + std::to_string(g->background()) + "; a " + role + " grid's must be 0");
    return g;
  };
  const openvdb::FloatGrid::Ptr grid = readGrid(gridName, "density");
  TransformD gridToWorld;
  if (!linearIndexToWorld(*grid, gridToWorld)) r.fail(at, named + " has a non-linear (frustum) transform");
  // Index -> world -> render frame, composed in double and rounded once (RenderFrame); the
  // medium's "world" is the render frame.
  const Transform indexToWorld(scene.frame.fromWorld() * xf * gridToWorld);
  // Where float stops resolving the voxels (docs/design.md, "Precision", the rule for patches with
  // a voxel's shortest world edge as the size): the float spacing at the volume's position must
  // be at most 1/256 of it. Checked on the grid's bounding box, before any voxel is read.
  {
    float voxelEdge = std::numeric_limits<float>::infinity();
    for (int j = 0; j < 3; ++j)
      voxelEdge = std::min(voxelEdge, length(Vec3{indexToWorld.m[0][j], indexToWorld.m[1][j], indexToWorld.m[2][j]}));
    const openvdb::CoordBBox active = grid->evalActiveVoxelBoundingBox();
    Box3 world;
    if (!active.empty())
      for (int corner = 0; corner < 8; ++corner)
        world.extend(indexToWorld.point({float(corner & 1 ? active.max().x() + 1 : active.min().x() - 1),
                                         float(corner & 2 ? active.max().y() + 1 : active.min().y() - 1),
                                         float(corner & 4 ? active.max().z() + 1 : active.min().z() - 1)}));
    const float magnitude = world.magnitude();
    if (!world.empty() && (!(magnitude <= 0x1p60f) || !(magnitude * 0x1p-23f <= voxelEdge * 0x1p-8f)))
      r.fail(at, named + ": voxels of size " + std::to_string(voxelEdge) + " at distance " + std::to_string(magnitude) +
                     " from the camera (the render frame's origin), where float resolves only " + std::to_string(magnitude * 0x1p-23f) +
                     ", more than 1/256 of a voxel, so the grid cannot be represented (move the volume nearer the "
                     "camera or scale it up)");
  }

  // What the medium keeps resident (its brick table and the out-of-core tree's leaf nodes, not
  // their voxels: those are the cache's), checked against the memory limit before it is built.
  const openvdb::FloatTree& tree = grid->tree();
  uint64_t bricks = tree.leafCount();
  auto tiles = tree.cbeginValueOn();
  tiles.setMaxDepth(tiles.getLeafDepth() - 1);  // tiles only, not every active voxel
  for (; tiles; ++tiles) {
    openvdb::CoordBBox box;
    tiles.getBoundingBox(box);
    bricks += box.volume() / Medium::kBrickVoxels;
  }
  constexpr uint64_t kBrickTableBytes = 24, kOutOfCoreLeafBytes = sizeof(FloatLeaf) + 64;
  const uint64_t needed = bricks * kBrickTableBytes + uint64_t(tree.leafCount()) * kOutOfCoreLeafBytes;
  const MemoryLimit memory = readMemoryLimit();
  if (memory.sourceBytes != 0 && needed > memory.available)
    r.failResource(at, named + " has " + std::to_string(bricks) + " bricks of 8³ voxels, whose table takes " +
                           readableBytes(needed) + ", more than the " + memory.describe() + " allows");

  std::shared_ptr<Medium> medium;
  try {
    medium = std::make_shared<Medium>(indexToWorld, coefficients);
  } catch (const std::invalid_argument& e) {
    r.fail(shape.contains("transform") ? p + "/transform" : at, named + ": " + e.what());
  }
  // The bricks of grid g: one stored brick per leaf (read from the file through the cache), one
  // constant brick per 8³ block of an active tile.
  auto bricksOf = [&](const openvdb::FloatGrid::Ptr& g, const std::string& gridNamed, const std::string& what) {
    const auto source = std::make_shared<VdbBrickSource>(g);
    auto out = std::make_unique<BrickGrid>(source);
    const openvdb::FloatTree& t = g->tree();
    auto checkValue = [&](float v, const openvdb::Coord& c) {
      if (!(v >= 0) || !std::isfinite(v))
        r.fail(at, gridNamed + " has " + what + " " + std::to_string(v) + " at voxel " + coordText(c) + "; " + what +
                       "s must be finite and not negative");
    };
    // Every leaf decoded once, in parallel: its largest voxel, its first bad voxel (or a read
    // error); the first of those in leaf order is reported, so the message does not depend on
    // the thread count.
    struct LeafScan {
      float maxVoxel = 0;
      int32_t bad = -1;  // the first voxel that is negative or not finite
      std::string error;
    };
    std::vector<LeafScan> scans(source->leaves());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, scans.size(), 64), [&](const tbb::blocked_range<size_t>& range) {
      Medium::BrickVoxels voxels;
      for (size_t i = range.begin(); i != range.end(); ++i) {
        LeafScan& scan = scans[i];
        try {
          source->read(uint32_t(i), voxels.data());
        } catch (const std::exception& e) {  // a delayed leaf that cannot be read (a truncated file)
          scan.error = e.what();
          continue;
        }
        for (int32_t v = 0; v < Medium::kBrickVoxels; ++v) {
          if (!(voxels[size_t(v)] >= 0) || !std::isfinite(voxels[size_t(v)])) {
            scan.bad = v;
            break;
          }
          scan.maxVoxel = std::max(scan.maxVoxel, voxels[size_t(v)]);
        }
      }
    });
    try {
      Medium::BrickVoxels voxels;
      for (size_t i = 0; i < scans.size(); ++i) {
        const FloatLeaf& leaf = source->leaf(uint32_t(i));
        if (!scans[i].error.empty()) r.fail(at, "cannot read " + gridNamed + ": " + scans[i].error);
        if (scans[i].bad >= 0) {
          source->read(uint32_t(i), voxels.data());
          checkValue(voxels[size_t(scans[i].bad)], leaf.offsetToGlobalCoord(openvdb::Index(scans[i].bad)));
        }
        const openvdb::Coord o = leaf.origin();
        out->addStored({o.x() >> 3, o.y() >> 3, o.z() >> 3}, uint32_t(i), scans[i].maxVoxel);
      }
      auto tileIt = t.cbeginValueOn();
      tileIt.setMaxDepth(tileIt.getLeafDepth() - 1);
      for (; tileIt; ++tileIt) {
        openvdb::CoordBBox box;
        tileIt.getBoundingBox(box);
        checkValue(*tileIt, box.min());
        for (int x = box.min().x(); x <= box.max().x(); x += 8)
          for (int y = box.min().y(); y <= box.max().y(); y += 8)
            for (int z = box.min().z(); z <= box.max().z(); z += 8) out->addConstant({x >> 3, y >> 3, z >> 3}, *tileIt);
      }
    } catch (const InputError&) {
      throw;
    } catch (const std::exception& e) {
      r.fail(at, "cannot read " + gridNamed + ": " + e.what());
    }
    return out;
  };
  medium->densityGrid() = std::move(*bricksOf(grid, named, "density"));
  // Emission: optional grids of the same file in the density grid's index space.
  MediumEmission emission;
  auto emissionGrid = [&](const char* key, const std::string& role) -> std::unique_ptr<BrickGrid> {
    if (!shape.contains(key)) return nullptr;
    const std::string name = r.string(shape[key], p + "/" + key);
    const openvdb::FloatGrid::Ptr g = readGrid(name, role);
    const std::string gridNamed = "'" + path.string() + "', grid '" + name + "'";
    if (g->transform() != grid->transform())
      r.fail(p + "/" + key, gridNamed + " has a transform other than the density grid's; an " + role +
                                " grid must share its voxels");
    return bricksOf(g, gridNamed, role);
  };
  emission.intensity = emissionGrid("emission_grid", "emission");
  emission.temperature = emissionGrid("temperature_grid", "temperature");
  if (shape.contains("emission")) {
    if (!emission.intensity) r.fail(p + "/emission", "applies to an \"emission_grid\"; there is none");
    emission.color = r.color(shape["emission"], p + "/emission", false);
  }
  for (const char* key : {"temperature_scale", "blackbody_scale"})
    if (shape.contains(key) && !emission.temperature)
      r.fail(p + "/" + key, "applies to a \"temperature_grid\"; there is none");
  emission.temperatureScale = number("temperature_scale", 1, 0, 1e6f, "[0, 1e6] (kelvin per voxel unit)");
  emission.blackbodyScale = number("blackbody_scale", 1, 0, 1e9f, "[0, 1e9]");
  medium->setEmission(std::move(emission));
  medium->finish();
  if (medium->bricks() > 0 && (!isFinite(medium->worldBounds().lo) || !isFinite(medium->worldBounds().hi)))
    r.fail(p, named + ": the volume's world bounds overflow float");
  scene.media.push_back(std::move(medium));
  scene.volumeLoadSeconds += secondsSince(t0);
}

}  // namespace rayes
