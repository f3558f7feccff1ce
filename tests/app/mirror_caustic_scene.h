// A caustic that every method can render, for the caustic-path tests: a small area light beside
// a silver mirror throws its reflection onto a diffuse floor. The camera looks straight down
// and sees the floor alone (the mirror and the light stand edge-on to it), so the light tracer,
// which cannot see a mirror, is a complete reference too.
#pragma once
#include <string>
#include "scene/scene_loader.h"

namespace rayes::testing {

inline Scene mirrorCausticScene(int width, int height, int spp) {
  Scene s = parseScene(R"({
  "camera": {"position": [-0.3, 0, 6], "look_at": [-0.3, 0, 0], "up": [0, 1, 0], "fov": 40},
  "film": {"resolution": [16, 12], "spp": 4},
  "integrator": {"max_depth": 6},
  "materials": {
    "floor": {"type": "diffuse", "albedo": [0.7, 0.7, 0.7]},
    "mirror": {"type": "conductor", "metal": "silver"}
  },
  "shapes": [
    {"type": "bilinear", "material": "floor", "quads": [[[-3,-3,0],[3,-3,0],[-3,3,0],[3,3,0]]]},
    {"type": "bilinear", "material": "mirror", "quads": [[[1,-1,0.1],[1,1,0.1],[1,-1,1.6],[1,1,1.6]]]}
  ],
  "lights": [{"type": "disk", "center": [-0.8, 0, 1.0], "normal": [1, 0, -0.4], "radius": 0.5,
              "radiance": [10, 10, 10]}]
})", "mirror-caustic.json");
  s.width = width;
  s.height = height;
  s.samplesPerPixel = spp;
  return s;
}

}  // namespace rayes::testing
