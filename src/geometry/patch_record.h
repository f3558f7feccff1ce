// A Patch as a flat byte record, and back: what a compiled scene (geometry/compiled_file.h)
// stores per leaf. A record holds exactly the values the patch's constructor was given
// (control points, corners, the displacement's parameters, the motion's times and samples),
// so decoding rebuilds the same patch bit for bit through the same constructors, and the
// compiled render equals the JSON render.
//
// Kinds encoded: Bézier, bilinear, subdivision faces, and the decorators over them: noise and
// height-map displacement (with its reference surface) and motion. What many leaves share is
// stored once, outside the records, and a record names it by index (RecordTables): a
// subdivision face its mesh (the mesh's topology once more apart: encodeSubdivTopology, shared
// by a moving mesh's time samples), a height-map displacement its map (the file and channel
// the scene named, opened once by the loader), a forest's leaf its forest (the generator tables
// a ForestPatches makes its patch from: encodeForestLeaf, 13 bytes). Not encoded (encodePatch
// says which, naming the kind): disks (only lights make them, and lights are not leaves of the
// compiled shapes).
//
// Format (little-endian, floats as IEEE bits): a one-byte tag, then the kind's fields;
// decorators nest the records of the patches they wrap. Pure functions, thread-safe (the
// index's add() excepted).
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>
#include <unordered_map>
#include "geometry/displacement.h"
#include "geometry/forest.h"
#include "geometry/forest_patches.h"
#include "geometry/patch.h"
#include "geometry/subdiv_mesh.h"

namespace rayes {

// The shared objects records refer to, by index: what decoding needs.
struct RecordTables {
  std::vector<SubdivMeshPtr> meshes;
  std::vector<std::shared_ptr<const HeightMapDisplacement>> heightMaps;
  std::vector<std::shared_ptr<const ForestPatches>> forests;
};

// The shared objects of a set of patches, numbered in order of first appearance (so a file is
// the same bytes whatever the thread count): add() every patch first (one thread), then
// encode them in any order on any thread.
class RecordTableIndex {
 public:
  void add(const Patch& patch);
  // A forest whose leaves are encoded by encodeForestLeaf: its index (the same forest, the same index).
  uint32_t addForest(const Forest& forest);
  uint32_t forestIndex(const Forest* f) const { return forestIndex_.at(f); }
  const std::vector<const Forest*>& forests() const { return forests_; }
  const std::vector<const SubdivMesh*>& meshes() const { return meshes_; }
  // The meshes' distinct topologies, in order of first appearance, and each mesh's topology.
  const std::vector<const SubdivTopology*>& topologies() const { return topologies_; }
  uint32_t topologyOfMesh(uint32_t mesh) const { return meshTopology_[mesh]; }
  uint32_t topologyIndex(const SubdivTopology* t) const { return topologyIndex_.at(t); }
  const std::vector<const HeightMapDisplacement*>& heightMaps() const { return heightMaps_; }
  uint32_t meshIndex(const SubdivMesh* m) const { return meshIndex_.at(m); }
  uint32_t heightMapIndex(const HeightMapDisplacement* d) const { return heightMapIndex_.at(d); }

 private:
  std::vector<const SubdivMesh*> meshes_;
  std::vector<const SubdivTopology*> topologies_;
  std::vector<uint32_t> meshTopology_;
  std::vector<const HeightMapDisplacement*> heightMaps_;
  std::vector<const Forest*> forests_;
  std::unordered_map<const Forest*, uint32_t> forestIndex_;
  std::unordered_map<const SubdivMesh*, uint32_t> meshIndex_;
  std::unordered_map<const SubdivTopology*, uint32_t> topologyIndex_;
  std::unordered_map<const HeightMapDisplacement*, uint32_t> heightMapIndex_;
};

// Appends `patch`'s record to `out`. Returns "" on success, else why it cannot be encoded
// (out is then unspecified). `shared`: the index the patch was added to; without it, patches
// that share objects (subdivision faces, height maps) cannot be encoded.
std::string encodePatch(const Patch& patch, std::vector<uint8_t>& out, const RecordTableIndex* shared = nullptr);

// Appends the record of a forest's leaf: forest `forest` (RecordTableIndex::addForest) and which leaf
// of it; decoded by RecordTables::forests[forest]->make(leaf).
void encodeForestLeaf(uint32_t forest, const ForestLeaf& leaf, std::vector<uint8_t>& out);

// The patch of a record of exactly `bytes` bytes. Throws std::invalid_argument naming what is
// wrong (an unknown tag, a record shorter or longer than its fields, an index outside
// `shared`, a value its constructor refuses); the caller names the file and the leaf.
PatchPtr decodePatch(const uint8_t* data, size_t bytes, const RecordTables* shared = nullptr);

// A subdivision topology as a record (describeTopology's description, without positions), and
// back: decodeSubdivTopology builds it (buildSubdivTopology), std::invalid_argument naming what
// is wrong, for a record that does not decode or a topology OpenSubdiv refuses.
void encodeSubdivTopology(const SubdivTopology& topology, std::vector<uint8_t>& out);
std::shared_ptr<const SubdivTopology> decodeSubdivTopology(const uint8_t* data, size_t bytes);

}  // namespace rayes
