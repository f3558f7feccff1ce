#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include "core/memory.h"
#include "geometry/forest_leaves.h"
#include "scene/scene_sections.h"
#include "scene/shape_kinds.h"

namespace rayes {
namespace {

// Leaves no scene can hold (leaf ids are 32-bit): bad input on any machine.
constexpr uint64_t kMaxLeaves = uint64_t(1) << 32;

// A leaf count whose description and per-leaf tables could not fit what the memory limit
// (core/memory.h: the cgroup's, RLIMIT_AS or physical memory) has available is refused before
// anything is grown.
uint64_t maxForestLeaves(const MemoryLimit& limit) {
  return limit.sourceBytes == 0 ? uint64_t(1) << 28 : limit.available / kForestBoundBytesPerLeaf;
}

}  // namespace

// {"type": "forest", "trees": N, "seed": S, "detail": D, "area": A, ...,
//  "materials": {"bark": ..., "foliage": ..., "terrain": ...}} (docs/scene-format.md). A forest
// takes a similarity "transform", but no displacement or motion.
void readForestShape(const JsonReader& r, const json& shape, const std::string& p, Scene& scene,
                     const MaterialIndex& materials) {
  r.object(shape, p, {"type", "trees", "seed", "detail", "branching", "area", "tree_height", "terrain_tiles",
                      "terrain_amplitude", "leaves_per_twig", "materials", "transform"});
  ForestParams fp;
  auto integerIn = [&](const char* key, int lo, int hi, int fallback) {
    if (!shape.contains(key)) return fallback;
    const std::string at = p + "/" + key;
    const int v = r.integer(shape[key], at);
    if (v < lo || v > hi) r.fail(at, "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return v;
  };
  auto positive = [&](const char* key, float fallback, bool zeroAllowed) {
    if (!shape.contains(key)) return fallback;
    const std::string at = p + "/" + key;
    const double v = r.number(shape[key], at);
    if (v < 0 || (!zeroAllowed && v == 0) || v > 1e6) r.fail(at, zeroAllowed ? "must be in [0, 1e6]" : "must be in (0, 1e6]");
    return float(v);
  };
  fp.trees = uint32_t(integerIn("trees", 0, 1 << 24, int(fp.trees)));
  if (shape.contains("seed")) {
    const json& s = shape["seed"];
    if (!s.is_number_unsigned()) r.fail(p + "/seed", "expected a non-negative integer, got " + JsonReader::typeName(s));
    fp.seed = s.get<uint64_t>();
  }
  fp.detail = integerIn("detail", 0, ForestParams::kMaxDetail, fp.detail);
  fp.branching = integerIn("branching", 1, ForestParams::kMaxBranching, fp.branching);
  fp.area = positive("area", fp.area, false);
  fp.treeHeight = positive("tree_height", fp.treeHeight, false);
  fp.terrainTiles = integerIn("terrain_tiles", 1, ForestParams::kMaxTerrainTiles, fp.terrainTiles);
  fp.terrainAmplitude = positive("terrain_amplitude", fp.terrainAmplitude, true);
  {
    // The placement is the forest's world transform followed by the move into the render frame,
    // composed in double and rounded once (RenderFrame): the forest's records are generated
    // unplaced and placed relative to the camera.
    const TransformD world = shape.contains("transform") ? readTransform(r, shape["transform"], p + "/transform") : TransformD{};
    fp.placement = Transform(scene.frame.fromWorld() * world);
    try {
      Forest::placementScale(fp.placement);
    } catch (const std::invalid_argument& e) {
      r.fail(p + "/transform", e.what());
    }
  }
  fp.leavesPerTwig = integerIn("leaves_per_twig", 0, ForestParams::kMaxLeavesPerTwig, fp.leavesPerTwig);

  // One material per part, by ForestLeaf::Part.
  const std::string mp = p + "/materials";
  const json& mats = r.member(shape, p, "materials");
  r.object(mats, mp, {"terrain", "bark", "foliage"});
  uint32_t partMaterial[3];
  const char* partName[3] = {"terrain", "bark", "foliage"};
  for (int k = 0; k < 3; ++k) partMaterial[k] = materialRef(r, mats, mp, materials, partName[k]);

  const uint64_t leaves = Forest::leafCount(fp);
  const std::string needs = "this forest would have " + std::to_string(leaves) + " leaves; describing them needs about " +
                            readableBytes(std::min(leaves, UINT64_MAX / kForestBoundBytesPerLeaf) * kForestBoundBytesPerLeaf);
  if (leaves > kMaxLeaves)
    r.fail(p, needs + ", and a scene holds at most 2^32 leaves: lower trees, detail, branching or leaves_per_twig");
  const MemoryLimit memory = readMemoryLimit();
  const uint64_t limit = std::min(kMaxLeaves, maxForestLeaves(memory));
  if (leaves > limit)
    r.failResource(p, needs + " (" + std::to_string(kForestBoundBytesPerLeaf) + " B per leaf), more than the " +
                          memory.describe() + " allows (" + std::to_string(limit) +
                          " leaves): lower trees, detail, branching or leaves_per_twig");
  std::shared_ptr<const Forest> forest;
  try {
    forest = std::make_shared<const Forest>(fp, limit);
  } catch (const std::invalid_argument& e) {
    r.fail(p, e.what());
  }
  const size_t first = scene.leaves.size();
  scene.leaves.add(std::make_shared<const ForestLeaves>(forest));
  scene.leafMaterial.resize(scene.leaves.size());
  for (size_t i = 0; i < forest->size(); ++i) scene.leafMaterial[first + i] = partMaterial[size_t(forest->leaf(i).part)];
  for (size_t i = 0; i < forest->size(); ++i) checkRepresentable(r, p, first + i, forest->bounds(i));
}

}  // namespace rayes
