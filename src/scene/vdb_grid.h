// A float grid of a .vdb file as the volume reader (scene/volume_shape_reader.cpp) sees it. The
// grid is read by the OpenVDB module (scene/openvdb/, librayes_openvdb.so), which readVdbGrid
// loads at the first volume a scene names, so a scene without volumes never loads OpenVDB
// (core/plugin_module.h).
//
// The grid is opened with delayed loading and its tree kept with every leaf out of core (each
// leaf holds only its file offsets): bricks() reads a leaf's voxels into a copy of its buffer,
// so the tree never grows. Ownership: a VdbGrid owns its OpenVDB grid; the BrickSource of
// bricks() shares it, so a medium's bricks outlive the reader. Thread safety: every const
// member may run on any thread (bricks()->read concurrently: OpenVDB's delayed loading is
// thread-safe for distinct buffer copies). Cost: leafOrigin is O(1) (a table of the leaves made
// at read), tiles() walks the tree's internal nodes once.
#pragma once
#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>
#include "core/transform.h"
#include "shading/brick_cache.h"

namespace rayes {

using VoxelCoord = std::array<int32_t, 3>;

// An active tile above the leaf level: the voxels lo..hi (inclusive) all hold `value`.
struct VdbTile {
  VoxelCoord lo{}, hi{};
  float value = 0;
};

class VdbGrid {
 public:
  virtual ~VdbGrid() = default;
  virtual float background() const = 0;
  // Index to world (OpenVDB's row-vector matrix turned into our column form); false when the
  // grid's transform is not linear (a frustum).
  virtual bool indexToWorld(TransformD& out) const = 0;
  // Whether `other` (of the same module) has the same transform: its voxels coincide with ours.
  virtual bool sameTransform(const VdbGrid& other) const = 0;
  // The active voxels' bounding box, inclusive; false when nothing is active.
  virtual bool activeBox(VoxelCoord& lo, VoxelCoord& hi) const = 0;
  // The stored leaves (8³ voxels each), in the tree's order: their origins, and their voxels
  // through bricks() (stored brick i is leaf i; x-major as an OpenVDB leaf).
  virtual size_t leafCount() const = 0;
  virtual VoxelCoord leafOrigin(size_t leaf) const = 0;
  virtual std::shared_ptr<BrickSource> bricks() const = 0;
  virtual std::vector<VdbTile> tiles() const = 0;
  // The bytes one out-of-core leaf node keeps resident (the memory check before anything is built).
  virtual uint64_t leafNodeBytes() const = 0;
};

// What reading a grid by name gave: the grid, or why not.
struct VdbGridRead {
  std::unique_ptr<VdbGrid> grid;
  std::string error;               // the file cannot be read (OpenVDB's message)
  bool found = false;              // the file has a grid of that name
  std::vector<std::string> names;  // when not found: the file's grids
  std::string valueType;           // when found but not float: its value type
};

// Reads grid `name` of `file` (loading the OpenVDB module at the first call; InputError when it
// cannot be loaded). Never throws for a bad file: VdbGridRead says what is wrong.
VdbGridRead readVdbGrid(const std::filesystem::path& file, const std::string& name);

// The OpenVDB module's file and its one entry point (scene/openvdb/vdb_grid_reader.cpp).
inline constexpr const char* kVdbModuleName = "librayes_openvdb.so";
inline constexpr const char* kReadVdbGridSymbol = "rayes_openvdb_read_grid";
using ReadVdbGridFn = void (*)(const std::string* file, const std::string* name, VdbGridRead* out);

}  // namespace rayes
