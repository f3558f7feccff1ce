// START HERE for scenes. A Scene is everything a render needs, already resolved: its leaves
// (geometry/leaf_source.h: patches built with transforms applied, and generated parts such as a
// forest, whose patches are made only when diced), materials are indexed, rectangle lights
// have become emissive bilinear patches (so they are seen by camera rays and sampled by NEE
// through one code path). Produced by loadScene() (scene_loader.h) from the JSON format of
// docs/scene-format.md; immutable afterwards.
#pragma once
#include <string>
#include <vector>
#include "geometry/compiled_file.h"
#include "geometry/leaf_source.h"
#include "core/transform.h"
#include "core/vec.h"
#include "scene/leaf_uv_table.h"
#include "shading/light.h"
#include "shading/material.h"
#include "shading/shading_scene.h"
#include "texture/texture_cache.h"

namespace rayes {

// The frame the render works in (docs/design.md, "The render frame"): world coordinates minus
// `origin`, the camera's position, subtracted in double before anything is rounded to float. So
// float's spacing at a point grows with its distance from the camera, not from the world's
// origin: a scene 10^6 units out renders as it does at the origin when the camera moves with
// it. The camera does not move during the shutter (only shapes do), so its position is the one
// origin for the whole exposure. Leaf boxes, patches, lights, media and the CameraDesc below
// are all in this frame; directions (distant lights, the environment map) are the same in both.
struct RenderFrame {
  Vec3d origin;  // in world coordinates
  Vec3 point(Vec3d world) const { return (world - origin).toFloat(); }
  // A render-frame point back in world coordinates (for checks against world-space formulas).
  Vec3 toWorld(Vec3 p) const { return (Vec3d(p) + origin).toFloat(); }
  // World -> render frame, to compose after a shape's own transform.
  TransformD fromWorld() const { return TransformD::translate(-origin.x, -origin.y, -origin.z); }
};

struct CameraDesc {
  Vec3 position{0, 0, 5}, lookAt{0, 0, 0}, up{0, 1, 0};
  float fovYDegrees = 40;
  float apertureRadius = 0;  // 0: pinhole
  float focusDistance = 1;
  float shutterOpen = 0, shutterClose = 0;  // in the time units of shape motion; equal: no blur
};

struct Scene {
  std::string path;  // the scene file, for messages
  RenderFrame frame;  // identity for scenes made in code; the camera's position for a loaded one
  CameraDesc camera;  // in the render frame: a loaded scene's camera sits at (0, 0, 0)
  int width = 640, height = 480, samplesPerPixel = 16;
  IntegratorSettings integrator;
  std::vector<Material> materials;
  LeafList leaves;                        // leaf id = index
  size_t shapeLeaves = 0;                 // leaves [0, shapeLeaves) are the "shapes" section's; lights' follow
  // A compiled scene's mapping (scene/compiled_scene.h), for its stats; null for a JSON scene.
  std::shared_ptr<const MappedFile> compiled;
  std::vector<uint32_t> leafMaterial;     // per leaf
  std::shared_ptr<LeafUvTable> uvs;       // the leaves' uv sets; null when no leaf has one or none is read
  bool uvSetsDropped = false;             // shapes had uv sets, but no texture reads uv coordinates
  std::vector<PointLight> pointLights;
  SceneLights moreLights;                 // spot, distant and environment lights
  // What the loader noticed that is not an error (a light that lights nothing), one sentence
  // each naming the file and the place; the program prints them as warnings.
  std::vector<std::string> warnings;
  // Participating media, one per "volume" shape (shading/medium.h); empty: OpenVDB never ran.
  std::vector<std::shared_ptr<const Medium>> media;
  double volumeLoadSeconds = 0;  // reading the .vdb files and building the bricks
  // The render's texture cache (texture/texture_cache.h): made by the loader at the first image
  // file the scene names, with textureOptions; null when the scene names none (it then pays
  // nothing for textures). Every image texture, the environment map and height maps read it.
  std::shared_ptr<TextureCache> textures;
  TextureCacheOptions textureOptions;
  TextureCache& textureCache() {
    if (!textures) textures = TextureCache::make(textureOptions);
    return *textures;
  }
};

}  // namespace rayes
