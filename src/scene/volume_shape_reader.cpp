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
// OpenVDB itself is read through scene/vdb_grid.h, in a module loaded at the first volume: a
// scene without a volume never loads it.
#include <algorithm>
#include <chrono>
#include <limits>
#include <cmath>
#include <mutex>
#include <stdexcept>
#include <tbb/parallel_for.h>
#include "core/memory.h"
#include "core/timer.h"
#include "scene/scene_sections.h"
#include "scene/shape_kinds.h"
#include "scene/vdb_grid.h"

namespace rayes {
namespace {

std::string coordText(const VoxelCoord& c) {
  return "(" + std::to_string(c[0]) + ", " + std::to_string(c[1]) + ", " + std::to_string(c[2]) + ")";
}

// The voxel at offset v of the leaf at `origin` (an OpenVDB leaf is x-major: v = x·64 + y·8 + z).
VoxelCoord voxelOf(const VoxelCoord& origin, int32_t v) {
  return {origin[0] + (v >> 6), origin[1] + ((v >> 3) & 7), origin[2] + (v & 7)};
}

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
  // A float grid of the file by name, with delayed loading; `role` says what it is for.
  auto readGrid = [&](const std::string& name, const std::string& role) {
    const std::string gridNamed = "'" + path.string() + "', grid '" + name + "'";
    VdbGridRead read = readVdbGrid(path, name);
    if (!read.error.empty()) r.fail(at, "cannot read " + gridNamed + ": " + read.error);
    if (!read.found) {
      std::string names;
      for (const std::string& n : read.names) names += (names.empty() ? "" : ", ") + n;
      r.fail(at, "'" + path.string() + "' has no grid named '" + name + "' (it has: " + (names.empty() ? "none" : names) + ")");
    }
    if (!read.grid) r.fail(at, gridNamed + " holds " + read.valueType + " values; a " + role + " grid holds float");
    if (read.grid->background() != 0.0f)
      r.fail(at, gridNamed + " has background " + std::to_string(read.grid->background()) + "; a " + role +
                     " grid's must be 0");
    return std::shared_ptr<const VdbGrid>(std::move(read.grid));
  };
  const std::shared_ptr<const VdbGrid> grid = readGrid(gridName, "density");
  TransformD gridToWorld;
  if (!grid->indexToWorld(gridToWorld)) r.fail(at, named + " has a non-linear (frustum) transform");
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
    VoxelCoord lo, hi;
    Box3 world;
    if (grid->activeBox(lo, hi))
      for (int corner = 0; corner < 8; ++corner)
        world.extend(indexToWorld.point({float(corner & 1 ? hi[0] + 1 : lo[0] - 1), float(corner & 2 ? hi[1] + 1 : lo[1] - 1),
                                         float(corner & 4 ? hi[2] + 1 : lo[2] - 1)}));
    const float magnitude = world.magnitude();
    if (!world.empty() && (!(magnitude <= 0x1p60f) || !(magnitude * 0x1p-23f <= voxelEdge * 0x1p-8f)))
      r.fail(at, named + ": voxels of size " + std::to_string(voxelEdge) + " at distance " + std::to_string(magnitude) +
                     " from the camera (the render frame's origin), where float resolves only " + std::to_string(magnitude * 0x1p-23f) +
                     ", more than 1/256 of a voxel, so the grid cannot be represented (move the volume nearer the "
                     "camera or scale it up)");
  }

  // What the medium keeps resident (its brick table and the out-of-core tree's leaf nodes, not
  // their voxels: those are the cache's), checked against the memory limit before it is built.
  uint64_t bricks = grid->leafCount();
  for (const VdbTile& tile : grid->tiles())
    bricks += uint64_t(tile.hi[0] - tile.lo[0] + 1) * uint64_t(tile.hi[1] - tile.lo[1] + 1) *
              uint64_t(tile.hi[2] - tile.lo[2] + 1) / Medium::kBrickVoxels;
  constexpr uint64_t kBrickTableBytes = 24;
  const uint64_t outOfCoreLeafBytes = grid->leafNodeBytes() + 64;
  const uint64_t needed = bricks * kBrickTableBytes + uint64_t(grid->leafCount()) * outOfCoreLeafBytes;
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
  auto bricksOf = [&](const VdbGrid& g, const std::string& gridNamed, const std::string& what) {
    const std::shared_ptr<BrickSource> source = g.bricks();
    auto out = std::make_unique<BrickGrid>(source);
    auto checkValue = [&](float v, const VoxelCoord& c) {
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
    std::vector<LeafScan> scans(g.leafCount());
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
        const VoxelCoord o = g.leafOrigin(i);
        if (!scans[i].error.empty()) r.fail(at, "cannot read " + gridNamed + ": " + scans[i].error);
        if (scans[i].bad >= 0) {
          source->read(uint32_t(i), voxels.data());
          checkValue(voxels[size_t(scans[i].bad)], voxelOf(o, scans[i].bad));
        }
        out->addStored({o[0] >> 3, o[1] >> 3, o[2] >> 3}, uint32_t(i), scans[i].maxVoxel);
      }
      for (const VdbTile& tile : g.tiles()) {
        checkValue(tile.value, tile.lo);
        for (int x = tile.lo[0]; x <= tile.hi[0]; x += 8)
          for (int y = tile.lo[1]; y <= tile.hi[1]; y += 8)
            for (int z = tile.lo[2]; z <= tile.hi[2]; z += 8) out->addConstant({x >> 3, y >> 3, z >> 3}, tile.value);
      }
    } catch (const InputError&) {
      throw;
    } catch (const std::exception& e) {
      r.fail(at, "cannot read " + gridNamed + ": " + e.what());
    }
    return out;
  };
  medium->densityGrid() = std::move(*bricksOf(*grid, named, "density"));
  // Emission: optional grids of the same file in the density grid's index space.
  MediumEmission emission;
  auto emissionGrid = [&](const char* key, const std::string& role) -> std::unique_ptr<BrickGrid> {
    if (!shape.contains(key)) return nullptr;
    const std::string name = r.string(shape[key], p + "/" + key);
    const std::shared_ptr<const VdbGrid> g = readGrid(name, role);
    const std::string gridNamed = "'" + path.string() + "', grid '" + name + "'";
    if (!g->sameTransform(*grid))
      r.fail(p + "/" + key, gridNamed + " has a transform other than the density grid's; an " + role +
                                " grid must share its voxels");
    return bricksOf(*g, gridNamed, role);
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
