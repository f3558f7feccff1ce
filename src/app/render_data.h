// What a render builds from a Scene once, before any ray: the leaves' conservative boxes and
// the top-level BVH over them, shading's view of the scene (camera, materials per leaf, the
// light sampler over point, spot, area, distant and environment lights) and the counts of what
// the scene uses (for the stats' "features" and "skipped", docs/design.md, invariant 4).
// Immutable after construction; holds a reference to nothing but what it owns (the lights'
// surface functions share ownership of their patches).
#pragma once
#include <cstdint>
#include <string>
#include <utility>
#include <vector>
#include "core/box.h"
#include "scene/scene.h"
#include "shading/shading_scene.h"
#include "toplevel/toplevel_bvh.h"

namespace rayes {

// What the scene uses, counted once at setup: the stats say what was done and what was left
// out because nothing needed it (docs/design.md, invariant 4).
struct SceneFeatures {
  uint64_t movingLeaves = 0;         // leaves with more than one time sample
  bool shutterOpen = false;          // the camera's shutter has an interval
  uint64_t displacedLeaves = 0;
  uint64_t subdivisionLeaves = 0;
  uint64_t borderClosureLeaves = 0;  // leaves whose borders need crack-closing regions
  uint64_t uvLeaves = 0;             // leaves with a uv set that a texture reads
  bool uvSetsDropped = false;        // Scene::uvSetsDropped
  bool environment = false;
  uint64_t distantLights = 0;
  // Materials that read a texture: only then do the ray batches keep the surface derivatives
  // at the hits that filtering takes (RayBatch::derivatives).
  uint64_t texturedMaterials = 0;
  // Precision (docs/design.md, "Precision"): the coarsest float spacing over a leaf's size (the
  // loader refuses beyond 2^-8; in the render frame, whose origin is the camera), and the leaves
  // float does not resolve finely enough for the image (isLowPrecisionLeaf).
  double coarsestRelativeSpacing = 0;
  uint64_t lowPrecisionLeaves = 0;
  // Volumes (Scene::media): their bricks, the voxels read into them, their bytes, and the load time.
  uint64_t volumes = 0, volumeBricks = 0, volumeVoxels = 0, volumeBytes = 0;
  uint64_t emittingVolumes = 0;  // with an emission or temperature grid
  double volumeLoadSeconds = 0;
};

struct RenderData {
  explicit RenderData(const Scene& scene);
  RenderData(const RenderData&) = delete;
  RenderData& operator=(const RenderData&) = delete;

  TopLevelBvh top;              // with the leaf boxes (Patch::bounds per leaf): top.leafBoxes()
  ShadingScene shading;
  SceneFeatures features;
  std::vector<std::pair<std::string, uint64_t>> leafKinds;  // (Patch::kind, leaves), by name

  // Bytes of the per-leaf tables above (shading's material, size and dicing error; the boxes
  // count in the top level).
  size_t leafTableBytes() const;
};

// Whether float resolves a leaf too coarsely for the image (docs/design.md, "Where float
// resolves a leaf"): its float spacing (magnitude * 2^-23, the leaf's coordinates in the render
// frame) exceeds both 2^-16 of the leaf's longest side and 2^-8 of a camera pixel's footprint at
// the leaf (pixelSpread, the angle of a pixel, times the camera's distance to the box). The
// first alone flags every small leaf far from the camera; but a leaf at distance d is seen
// through footprints at least pixelSpread * d wide (cones only widen along a path), its float
// spacing is about d * 2^-23 there, so its rounding is a fixed 2^-23 / pixelSpread of a pixel,
// whatever d: at 768 rows and 40 degrees, 2^-13 of a pixel. Finite for every box: a point
// (side 0) or the camera inside the box falls back on the first rule alone.
bool isLowPrecisionLeaf(const Box3& box, Vec3 camera, float pixelSpread);

// Every emissive patch is an area light; shading sees it only through its surface function.
std::vector<PatchLight> patchLightsOf(const Scene& scene);

}  // namespace rayes
