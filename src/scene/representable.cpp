#include <cmath>
#include <sstream>
#include "scene/scene_sections.h"

namespace rayes {

// Where float stops holding a scene (docs/design.md, "Precision"). Leaf boxes are in the render
// frame (scene.h, RenderFrame), whose origin is the camera, so "magnitude" below is a distance
// from the camera, not from the world's origin:
// - A leaf box must be finite, and no coordinate may exceed 2^60 (about 1.2e18): products of
//   two coordinates -- the surface areas of the top-level build's SAH, the edge functions of
//   the watertight test, squared distances -- must stay below FLT_MAX (about 2^128) with room
//   for the sums of a few dozen of them.
// - The float spacing at a leaf's position (its ulp) must be at most 2^-8 of the leaf's
//   extent. Beyond that, rounding the control points alone moves the surface by more than
//   0.2 % of the patch, the traversal's margins and the crack-closing regions (each one or two
//   spacings) widen silhouettes by about 1 %, and micro-quads of level 8 have corners one
//   spacing apart: the micro-geometry is no longer resolved.
constexpr float kMaxCoordinate = 0x1p60f;
constexpr float kMinResolution = 0x1p-8f;

void checkRepresentable(const JsonReader& r, const std::string& ptr, size_t leaf, const Box3& b) {
  if (b.empty() || !isFinite(b.lo) || !isFinite(b.hi))
    r.fail(ptr, "patch " + std::to_string(leaf) + "'s bounding box overflows float (inf or NaN coordinates)");
  const float magnitude = b.magnitude();
  if (magnitude > kMaxCoordinate) {
    std::ostringstream m;
    m << "a coordinate reaches " << magnitude << ", beyond 2^60 (1.2e18): float products of coordinates would overflow";
    r.fail(ptr, m.str());
  }
  if (b.relativeSpacing() > kMinResolution) {
    std::ostringstream m;
    m << "a patch of size " << b.longestSide() << " at distance " << magnitude
      << " from the camera (the render frame's origin): float resolves only " << magnitude * 0x1p-23f
      << " there, more than 1/256 of the patch, so its micro-geometry cannot be represented"
         " (move the camera nearer or scale the scene up)";
    r.fail(ptr, m.str());
  }
}

void addPatch(const JsonReader& r, const std::string& ptr, Scene& scene, PatchPtr patch, uint32_t material) {
  checkRepresentable(r, ptr, scene.leaves.size(), patch->bounds());
  scene.leaves.add(std::move(patch));
  scene.leafMaterial.push_back(material);
}

}  // namespace rayes
