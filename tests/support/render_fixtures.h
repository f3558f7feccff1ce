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

// A scene at another resolution and sample count.
inline Scene resized(Scene s, int w, int h, int spp) {
  s.width = w;
  s.height = h;
  s.samplesPerPixel = spp;
  return s;
}

// The shipped teapot scene at a small resolution.
inline Scene smallTeapot(int w = 48, int h = 36, int spp = 2) {
  return resized(loadScene(sourcePath("scenes/teapot.json")), w, h, spp);
}

inline std::vector<float> renderBeauty(const Scene& scene, const RenderOptions& options, int threads,
                                       RenderStats* statsOut = nullptr) {
  ThreadLimit limit(threads);
  Renderer r(scene, options);
  const Film film = r.render();
  if (statsOut) {
    statsOut->generations = r.stats().generations;
    statsOut->batches = r.stats().batches;
    statsOut->pixelsPerBlock = r.stats().pixelsPerBlock;
    statsOut->memory = r.stats().memory;
  }
  return film.beautyRgba();
}

// The ray memory one path of this scene and method costs (the unit of RenderOptions::rayMemoryBytes).
inline size_t bytesPerPath(const Scene& scene, const RenderOptions& options = {}) {
  return Renderer(scene, options).bytesPerPath();
}

// docs/design.md, invariant 2 on one scene: the image with 2 threads equals, bit for bit, the image
// with 1 thread, with every ray traced alone, and with a ray budget of `budgetPaths` paths
// (all with the other settings of `base`).
inline void expectOrderIndependent(const Scene& scene, size_t budgetPaths, const RenderOptions& base = {}) {
  const auto ref = renderBeauty(scene, base, 2);
  EXPECT_EQ(renderBeauty(scene, base, 1), ref) << "1 thread";
  RenderOptions alone = base;
  alone.sortByLeaf = false;
  EXPECT_EQ(renderBeauty(scene, alone, 2), ref) << "every ray alone";
  RenderOptions small = base;
  small.rayMemoryBytes = budgetPaths * bytesPerPath(scene, base);
  EXPECT_EQ(renderBeauty(scene, small, 2), ref) << budgetPaths << " paths per batch";
}

// A render's per-channel means against a reference measured over many seeds: `mean` is the
// average over 24 seeds of the same render's channel means, `sd` the standard deviation of
// one render's channel mean over those seeds. The tolerance is 5 sd: 4 for this render's
// noise, times sqrt(1 + 1/24) for the reference mean's own, and about 15 % more because sd is
// itself estimated from 24 seeds. Wrong colours, a black or doubled image, a missing light
// fail; a new random sequence (any unbiased one) does not.
struct ChannelMeans {
  double mean[3];
  double sd[3];
};
inline void expectChannelMeans(const std::vector<float>& rgba, const ChannelMeans& expected, const std::string& what) {
  for (int c = 0; c < 3; ++c) {
    double sum = 0;
    for (size_t i = size_t(c); i < rgba.size(); i += 4) sum += rgba[i];
    EXPECT_NEAR(sum / double(rgba.size() / 4), expected.mean[c], 5 * expected.sd[c]) << what << ", channel " << c;
  }
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

// A GenerationStats counter summed over the render's generations.
inline uint64_t totalOf(const RenderStats& s, uint64_t GenerationStats::*counter) {
  uint64_t n = 0;
  for (const auto& g : s.generations) n += g.stats.*counter;
  return n;
}

}  // namespace rayes::testing
