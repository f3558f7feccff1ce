// Small scenes and helpers shared by the end-to-end tests.
#pragma once
#include <string>
#include <vector>
#include <gtest/gtest.h>
#include "app/command_line.h"
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

// docs/design.md, invariant 2 on one scene: the image with 2 threads equals, bit for bit, the image
// with 1 thread, with every ray traced alone, and with a ray budget of `budgetPaths` paths.
inline void expectOrderIndependent(const Scene& scene, size_t budgetPaths) {
  const auto ref = renderBeauty(scene, RenderOptions{}, 2);
  EXPECT_EQ(renderBeauty(scene, RenderOptions{}, 1), ref) << "1 thread";
  RenderOptions alone;
  alone.sortByLeaf = false;
  EXPECT_EQ(renderBeauty(scene, alone, 2), ref) << "every ray alone";
  RenderOptions small;
  small.rayMemoryBytes = budgetPaths * Renderer::bytesPerPath();
  EXPECT_EQ(renderBeauty(scene, small, 2), ref) << budgetPaths << " paths per batch";
}

// Runs `rayes ARGS...` in process and captures what it printed on stderr.
struct RunResult {
  int code;
  std::string err;
};
inline RunResult runRayes(std::vector<std::string> args) {
  args.insert(args.begin(), "rayes");
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  ::testing::internal::CaptureStderr();
  const int code = runCommandLine(int(argv.size()), argv.data());
  return {code, ::testing::internal::GetCapturedStderr()};
}

}  // namespace rayes::testing
