// Small scenes and helpers shared by the end-to-end tests.
#pragma once
#include <string>
#include <vector>
#include "app/renderer.h"
#include "core/parallel.h"
#include "scene/scene_loader.h"

namespace rayes::testing {

inline std::string sourcePath(const std::string& rel) { return std::string(RAYES_SOURCE_DIR) + "/" + rel; }

// The shipped teapot scene at a small resolution.
inline Scene smallTeapot(int w = 48, int h = 36, int spp = 2) {
  Scene s = loadScene(sourcePath("scenes/teapot.json"));
  s.width = w;
  s.height = h;
  s.samplesPerPixel = spp;
  return s;
}

inline std::vector<float> renderBeauty(const Scene& scene, const RenderOptions& options, int threads,
                                       RenderStats* statsOut = nullptr) {
  ThreadLimit limit(threads);
  Renderer r(scene, options);
  const Film film = r.render();
  if (statsOut) {
    statsOut->generations = r.stats().generations;
    statsOut->batches = r.stats().batches;
  }
  return film.beautyRgba();
}

}  // namespace rayes::testing
