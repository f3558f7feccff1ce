// A caustic that every method can render, for the caustic-path tests: a small area light beside
// a silver mirror throws its reflection onto a diffuse floor. The camera looks straight down
// from above the mirror's plane and sees it edge-on (a camera that sees the mirror sees caustics
// in it, which no light-tracer path reaches), so the light tracer is a complete reference.
#pragma once
#include <string>
#include <cmath>
#include <vector>
#include "support/render_fixtures.h"
#include "scene/scene_loader.h"

namespace rayes::testing {

inline Scene mirrorCausticScene(int width, int height, int spp) {
  Scene s = parseScene(R"({
  "camera": {"position": [1, 0, 6], "look_at": [1, 0, 0], "up": [0, 1, 0], "fov": 40},
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
  return resized(s, width, height, spp);
}

// Block means (4 x 3 blocks, last: the image) of the channel average over `seeds` seeds.
struct BlockEstimate {
  std::vector<double> mean, se;
};
inline BlockEstimate blockEstimate(const Scene& base, const RenderOptions& o, int seeds) {
  constexpr int bx = 4, by = 3;
  std::vector<double> sum(bx * by + 1, 0.0), sum2(sum.size(), 0.0);
  for (int s = 0; s < seeds; ++s) {
    Scene scene = base;
    scene.integrator.seed = uint64_t(500 + s);
    const auto rgba = testing::renderBeauty(scene, o, 2);
    std::vector<double> m(sum.size(), 0.0);
    for (int y = 0; y < scene.height; ++y)
      for (int x = 0; x < scene.width; ++x) {
        const size_t p = size_t(y) * scene.width + x;
        const double v = (double(rgba[4 * p]) + rgba[4 * p + 1] + rgba[4 * p + 2]) / 3;
        m[size_t(y * by / scene.height) * bx + size_t(x * bx / scene.width)] += v / (double(scene.width / bx) * (scene.height / by));
        m.back() += v / (double(scene.width) * scene.height);
      }
    for (size_t b = 0; b < m.size(); ++b) { sum[b] += m[b]; sum2[b] += m[b] * m[b]; }
  }
  BlockEstimate e;
  for (size_t b = 0; b < sum.size(); ++b) {
    const double mean = sum[b] / seeds;
    e.mean.push_back(mean);
    e.se.push_back(std::sqrt(std::max(0.0, (sum2[b] - seeds * mean * mean) / (seeds - 1)) / seeds));
  }
  return e;
}

}  // namespace rayes::testing
