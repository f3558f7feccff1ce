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
#include "shading/light.h"
#include "shading/material.h"
#include "shading/shading_scene.h"

namespace rayes {

struct CameraDesc {
  Vec3 position{0, 0, 5}, lookAt{0, 0, 0}, up{0, 1, 0};
  float fovYDegrees = 40;
  float apertureRadius = 0;  // 0: pinhole
  float focusDistance = 1;
  float shutterOpen = 0, shutterClose = 0;  // in the time units of shape motion; equal: no blur
};

struct Scene {
  std::string path;  // the scene file, for messages
  CameraDesc camera;
  int width = 640, height = 480, samplesPerPixel = 16;
  IntegratorSettings integrator;
  std::vector<Material> materials;
  LeafList leaves;                        // leaf id = index
  size_t shapeLeaves = 0;                 // leaves [0, shapeLeaves) are the "shapes" section's; lights' follow
  // A compiled scene's mapping (scene/compiled_scene.h), for its stats; null for a JSON scene.
  std::shared_ptr<const MappedFile> compiled;
  std::vector<uint32_t> leafMaterial;     // per leaf
  std::vector<PointLight> pointLights;
  SceneLights moreLights;                 // spot, distant and environment lights
  // What the loader noticed that is not an error (a light that lights nothing), one sentence
  // each naming the file and the place; the program prints them as warnings.
  std::vector<std::string> warnings;
};

}  // namespace rayes
