// Subdivision surfaces (Catmull-Clark, Loop for all-triangle meshes, and the bilinear scheme for
// plain polygon meshes) through OpenSubdiv's Bfr API, diced on demand like every other Patch.
//
// Three layers, each immutable once built and shared by pointer:
//  - SubdivMeshDesc: plain topology + positions + tags, as the OBJ or JSON reader produces it.
//  - SubdivTopology: the Far::TopologyRefiner (with the uv set as its face-varying channel 0,
//    when the mesh has one), the thread-safe Bfr surface factory (its cache of irregular patch
//    topologies is shared by every thread), and the tables that make seams watertight (which
//    face owns each edge and vertex). The uv set is evaluated by SubdivUvSet (subdiv_uv.h). It does not depend on positions, so a
//    moving shape builds it once and one SubdivMesh per time sample.
//  - SubdivMesh: the topology + control points (already transformed) + what depends on them:
//    the limit position of every vertex, a bicubic Bézier form of every regular face, and
//    per-face bounds. Its leaves are SubdivFacePatch objects (subdiv_patch.h): one per quad
//    face, one per sub-face of a non-quad (Catmull-Clark: Bfr's QUAD_SUBFACES; Loop: three
//    quads per triangle, corner / edge midpoint / centroid / edge midpoint).
//
// Watertight seams: Bfr evaluated from the two faces of an edge is not bit-identical, so every
// point on a leaf's border is evaluated canonically: a point of mesh edge E at parameter e
// (from E's first vertex to its second, an exact dyadic number) is always evaluated by E's
// owner (the smallest face with a limit surface), a vertex's limit point is taken from a table
// filled by the vertex's owner, a non-quad's centre and its internal sub-face borders by that
// face. Two leaves sharing a border thus produce bit-identical border vertices at every level.
//
// Files: subdiv_topology.cpp (checking and building the topology), subdiv_mesh.cpp (the mesh
// and its Bfr evaluation), subdiv_seams.cpp (the canonical border points), subdiv_dice.cpp (a
// leaf's points and dicing); their shared internals in subdiv_mesh_internal.h.
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>
#include "core/box.h"
#include "geometry/bezier_patch.h"
#include "geometry/patch.h"

namespace rayes {

// Bilinear: OpenSubdiv's bilinear scheme, the control mesh itself (flat faces; a non-quad face
// is split into quads about its centroid like Catmull-Clark's).
enum class SubdivScheme { CatmullClark, Loop, Bilinear };

// How boundary vertices are interpolated (OpenSubdiv's Sdc::Options::VtxBoundaryInterpolation).
enum class SubdivBoundary { None, EdgeOnly, EdgeAndCorner };

// How the uv set (face-varying data) is interpolated: OpenSubdiv's
// Sdc::Options::FVarLinearInterpolation, from smooth everywhere (None) to bilinear in every face
// (All, OpenSubdiv's default).
enum class SubdivUvInterpolation { None, CornersOnly, CornersPlus1, CornersPlus2, Boundaries, All };

struct SubdivCrease {
  int v0 = 0, v1 = 0;   // an existing edge
  float sharpness = 0;  // >= 0; 10 and above is infinitely sharp
};

struct SubdivCorner {
  int v = 0;
  float sharpness = 0;
};

// Zero-based indices throughout.
struct SubdivMeshDesc {
  SubdivScheme scheme = SubdivScheme::CatmullClark;
  SubdivBoundary boundary = SubdivBoundary::EdgeAndCorner;
  std::vector<Vec3> positions;
  std::vector<int> faceSizes;     // vertices per face, each >= 3
  std::vector<int> faceVertices;  // concatenated, counter-clockwise seen from outside
  std::vector<SubdivCrease> creases;
  std::vector<SubdivCorner> corners;
  std::vector<int> holes;         // face indices
  // The uv set, optional (both empty: none): values (s, t), and one value index per face
  // vertex (parallel to faceVertices). Where two faces sharing an edge give its ends different
  // values, the uv set has a seam there.
  std::vector<std::array<float, 2>> uvs;
  std::vector<int> uvIndices;
  SubdivUvInterpolation uvInterpolation = SubdivUvInterpolation::All;
};

// Bad topology: which item of the description (so a reader can name the line it came from).
class SubdivInputError : public std::runtime_error {
 public:
  // Uv: a uv value; UvFace: a face's uv indices.
  enum class Item { Mesh, Vertex, Face, Crease, Corner, Hole, Uv, UvFace };
  SubdivInputError(Item item, int index, const std::string& msg) : std::runtime_error(msg), item(item), index(index) {}
  Item item;
  int index;  // -1 for Item::Mesh
};

class SubdivTopology;

// Checks the description (indices in range, faces of >= 3 distinct vertices, creases on
// existing edges, finite non-negative sharpness, Loop only on triangles; a uv set with one
// index per face vertex, each in range, and finite values) and builds the
// refiner and the surface factory. Throws SubdivInputError; also for topology OpenSubdiv
// itself rejects. Positions are only used for their count.
// regularAsBezier: evaluate regular faces (16 distinct B-spline control points) in Bézier form
// instead of through Bfr; false only to measure the difference (bench/dicing_subdiv.cpp).
std::shared_ptr<const SubdivTopology> buildSubdivTopology(const SubdivMeshDesc& desc, bool regularAsBezier = true);

// The description `topology` was built from, again (positions: as many as it has, all zero;
// faces, creases, corners, holes, the uv set and the options as given): buildSubdivTopology of
// it builds the same topology (a compiled scene stores a mesh's topology so).
SubdivMeshDesc describeTopology(const SubdivTopology& topology);
// The regularAsBezier the topology was built with.
bool builtRegularAsBezier(const SubdivTopology& topology);

struct SubdivStats {
  int faces = 0, leaves = 0, regularFaces = 0, irregularFaces = 0, facesWithoutLimit = 0;
};

class SubdivMesh : public std::enable_shared_from_this<SubdivMesh> {
 public:
  // positions: one per vertex of the topology (std::invalid_argument otherwise), finite.
  static std::shared_ptr<const SubdivMesh> build(std::shared_ptr<const SubdivTopology> topology,
                                                 std::vector<Vec3> positions);
  ~SubdivMesh();

  // One Patch per leaf (faces without a limit surface, such as holes, have none).
  std::vector<PatchPtr> patches() const;
  SubdivStats stats() const;

  // --- used by SubdivFacePatch ---
  int leafCount() const;
  Box3 leafBounds(int leaf) const;
  Box3 leafBoundsOver(int leaf, float u0, float u1, float v0, float v1) const;
  float leafSizeBound(int leaf) const;
  float leafErrorCoefficient(int leaf) const;
  SurfacePoint evaluateLeaf(int leaf, float u, float v) const;
  void diceLeaf(int leaf, int level, Vec3* positions, Vec3* normals) const;
  // The limit point of base vertex v (its owner's evaluation), for tests.
  Vec3 vertexLimit(int v) const;
  // (face, sub-face) of a leaf; sub-face -1 for a whole quad.
  std::pair<int, int> leafFace(int leaf) const;
  const SubdivTopology& topology() const { return *topo_; }
  const std::shared_ptr<const SubdivTopology>& topologyPtr() const { return topo_; }
  // The control points it was built with (x y z per vertex, as given).
  std::vector<Vec3> controlPoints() const;

  struct Impl;

 private:
  SubdivMesh() = default;
  std::shared_ptr<const SubdivTopology> topo_;
  std::unique_ptr<Impl> impl_;
};

using SubdivMeshPtr = std::shared_ptr<const SubdivMesh>;

// Convenience: topology + mesh + patches in one call.
std::vector<PatchPtr> makeSubdivPatches(const SubdivMeshDesc& desc);

}  // namespace rayes
