// The light tracer (`--method lt`) converges to the path tracer's image: on the Cornell box
// and the teapot (area lights, diffuse surfaces: no delta-only path reaches the camera) the
// image mean and the mean of every 4x4 block of the image agree within 4 standard errors. The
// standard errors come from independent seeds of each method (the spread of the K per-seed
// block means, divided by sqrt(K)), so the tolerance is the estimators' own noise. K = 64: with
// a standard error estimated from K runs the test statistic is Student-t with K - 1 degrees of
// freedom, and with 8 seeds |t| > 4 happens for one of the 17 comparisons in about 8 % of runs
// (it did, after the sampler changed); with 64, in about 0.3 %.
// Light tracing is order independent too: the splats of a batch are added in path-id order.
#include <cmath>
#include <gtest/gtest.h>
#include "support/render_fixtures.h"

namespace rayes {
namespace {

constexpr int kBlocks = 4;  // per side

// The image mean (last) and the 4x4 block means of the red + green + blue average.
std::vector<double> blockMeans(const std::vector<float>& rgba, int w, int h) {
  std::vector<double> sums(kBlocks * kBlocks + 1, 0.0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t p = size_t(y) * w + x;
      const double v = (double(rgba[4 * p]) + rgba[4 * p + 1] + rgba[4 * p + 2]) / 3;
      sums[size_t(y * kBlocks / h) * kBlocks + size_t(x * kBlocks / w)] += v;
      sums.back() += v;
    }
  const double perBlock = double(w / kBlocks) * double(h / kBlocks);
  for (int b = 0; b < kBlocks * kBlocks; ++b) sums[b] /= perBlock;
  sums.back() /= double(w) * h;
  return sums;
}

struct Estimate {
  std::vector<double> mean, stderr_;
};

Estimate estimate(Scene scene, const std::string& method, int seeds) {
  RenderOptions o;
  o.method.name = method;
  // Both methods must see one geometry: with per-ray LOD the camera's rays and the lights' rays
  // see the curved teapot at the levels of their own footprints, so the two images converge to
  // renders of different surfaces (11-15 % apart on the teapot at this resolution).
  o.lod = LodRule::Fixed;
  o.maxLod = 5;
  std::vector<std::vector<double>> runs;
  for (int s = 0; s < seeds; ++s) {
    scene.integrator.seed = uint64_t(1000 + s);
    runs.push_back(blockMeans(testing::renderBeauty(scene, o, 2), scene.width, scene.height));
  }
  Estimate e;
  for (size_t b = 0; b < runs[0].size(); ++b) {
    double sum = 0, sum2 = 0;
    for (const auto& r : runs) { sum += r[b]; sum2 += r[b] * r[b]; }
    const double m = sum / seeds;
    e.mean.push_back(m);
    e.stderr_.push_back(std::sqrt(std::max(0.0, (sum2 - seeds * m * m) / (seeds - 1)) / seeds));
  }
  return e;
}

void expectSameImage(const Scene& scene, int seeds) {
  const Estimate pt = estimate(scene, "pt", seeds);
  const Estimate lt = estimate(scene, "lt", seeds);
  for (size_t b = 0; b < pt.mean.size(); ++b) {
    const double se = std::hypot(pt.stderr_[b], lt.stderr_[b]);
    const std::string what = b + 1 == pt.mean.size() ? "image mean" : "block " + std::to_string(b);
    EXPECT_GT(se, 0) << what;
    EXPECT_LE(std::fabs(pt.mean[b] - lt.mean[b]), 4 * se)
        << what << ": pt " << pt.mean[b] << " +- " << pt.stderr_[b] << ", lt " << lt.mean[b] << " +- " << lt.stderr_[b];
  }
}

Scene small(const std::string& file, int w, int h, int spp) {
  Scene s = loadScene(testing::sourcePath(file));
  s.width = w;
  s.height = h;
  s.samplesPerPixel = spp;
  return s;
}

TEST(LightTracer, CornellBoxConvergesToThePathTracersImage) {
  expectSameImage(small("scenes/cornell-box.json", 16, 16, 8), 64);
}

TEST(LightTracer, TeapotConvergesToThePathTracersImage) {
  expectSameImage(small("scenes/teapot.json", 16, 12, 8), 64);
}

TEST(LightTracer, OrderIndependent) {
  RenderOptions lt;
  lt.method.name = "lt";
  testing::expectOrderIndependent(small("scenes/cornell-box.json", 12, 12, 2), 37, lt);
}

}  // namespace
}  // namespace rayes
