// {"type": "volume"} shapes (docs/scene-format.md): a float density grid of a .vdb file read
// with OpenVDB into a shading Medium (shading/medium.h) of 8³-voxel bricks, one per OpenVDB leaf
// node and one per 8³ block of an active tile. The brick is OpenVDB's own unit of storage and
// delayed loading, so a later brick cache loads exactly what a leaf holds; groups of leaves
// would only coarsen the majorants (more null collisions) for nothing the first slice needs.
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

}  // namespace

// {"type": "volume", "file": F, "grid": "density", "density_scale": 1, "sigma_a": 0, "sigma_s": 1,
//  "g": 0, "transform": [...]}
void readVolumeShape(const JsonReader& r, const json& shape, const std::string& p, Scene& scene,
                     const std::filesystem::path& sceneDir) {
  const Clock::time_point t0 = Clock::now();
  r.object(shape, p, {"type", "file", "grid", "density_scale", "sigma_a", "sigma_s", "g", "transform"});
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
  openvdb::FloatGrid::Ptr grid;
  try {
    openvdb::io::File file(path.string());
    file.open(/*delayLoad=*/true);  // leaf buffers are read when a leaf is first touched
    if (!file.hasGrid(gridName)) {
      std::string names;
      for (auto it = file.beginName(); it != file.endName(); ++it) names += (names.empty() ? "" : ", ") + *it;
      r.fail(at, "'" + path.string() + "' has no grid named '" + gridName + "' (it has: " +
                     (names.empty() ? "none" : names) + ")");
    }
    const openvdb::GridBase::Ptr base = file.readGrid(gridName);
    grid = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
    if (!grid) r.fail(at, named + " holds " + base->valueType() + " values; a density grid holds float");
    file.close();
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {  // openvdb::Exception and std::bad_alloc alike: the file is unreadable
    r.fail(at, "cannot read " + named + ": " + e.what());
  }
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
  if (grid->background() != 0.0f)
    r.fail(at, named + " has background " + std::to_string(grid->background()) + "; a density grid's must be 0");

  // What the bricks will hold, checked against the memory limit before anything is copied.
  const openvdb::FloatTree& tree = grid->tree();
  uint64_t bricks = tree.leafCount();
  auto tiles = tree.cbeginValueOn();
  tiles.setMaxDepth(tiles.getLeafDepth() - 1);  // tiles only, not every active voxel
  for (; tiles; ++tiles) {
    openvdb::CoordBBox box;
    tiles.getBoundingBox(box);
    bricks += box.volume() / Medium::kBrickVoxels;
  }
  const uint64_t needed = bricks * (sizeof(Medium::BrickVoxels) + 16);
  const MemoryLimit memory = readMemoryLimit();
  if (memory.sourceBytes != 0 && needed > memory.available)
    r.failResource(at, named + " has " + std::to_string(bricks) + " bricks of 8³ voxels, " + readableBytes(needed) +
                           ", more than the " + memory.describe() + " allows (a bounded brick cache is not built yet)");

  std::shared_ptr<Medium> medium;
  try {
    medium = std::make_shared<Medium>(indexToWorld, coefficients);
  } catch (const std::invalid_argument& e) {
    r.fail(shape.contains("transform") ? p + "/transform" : at, named + ": " + e.what());
  }
  auto checked = [&](float v, const openvdb::Coord& c) {
    if (!(v >= 0) || !std::isfinite(v))
      r.fail(at, named + " has density " + std::to_string(v) + " at voxel " + coordText(c) +
                     "; densities must be finite and not negative");
    return v;
  };
  Medium::BrickVoxels voxels;
  try {
    for (auto leaf = tree.cbeginLeaf(); leaf; ++leaf) {
      const openvdb::Coord o = leaf->origin();
      for (openvdb::Index i = 0; i < openvdb::FloatTree::LeafNodeType::SIZE; ++i)
        voxels[i] = checked(leaf->getValue(i), leaf->offsetToGlobalCoord(i));
      medium->addBrick({o.x() >> 3, o.y() >> 3, o.z() >> 3}, voxels);
    }
    tiles = tree.cbeginValueOn();
    tiles.setMaxDepth(tiles.getLeafDepth() - 1);
    for (; tiles; ++tiles) {
      openvdb::CoordBBox box;
      tiles.getBoundingBox(box);
      voxels.fill(checked(*tiles, box.min()));
      for (int x = box.min().x(); x <= box.max().x(); x += 8)
        for (int y = box.min().y(); y <= box.max().y(); y += 8)
          for (int z = box.min().z(); z <= box.max().z(); z += 8) medium->addBrick({x >> 3, y >> 3, z >> 3}, voxels);
    }
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {  // a delayed leaf that cannot be read (a truncated file)
    r.fail(at, "cannot read " + named + ": " + e.what());
  }
  medium->finish();
  if (medium->bricks() > 0 && (!isFinite(medium->worldBounds().lo) || !isFinite(medium->worldBounds().hi)))
    r.fail(p, named + ": the volume's world bounds overflow float");
  scene.media.push_back(std::move(medium));
  scene.volumeLoadSeconds += secondsSince(t0);
}

}  // namespace rayes
