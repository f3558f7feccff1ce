// PerspectiveCamera::connect, the light tracer's view of the camera: it inverts generate()
// (a point on a camera ray maps back to that ray's film position and lens point, pinhole and
// thin lens), refuses what no camera ray can reach, and its importance integrates to the
// pixel mean (a uniformly emitting plane filling the view is seen at its radiance).
#include <cmath>
#include <vector>
#include <gtest/gtest.h>
#include "core/rng.h"
#include "shading/camera.h"

namespace rayes {
namespace {

void expectConnectInvertsGenerate(const PerspectiveCamera& cam) {
  for (uint32_t i = 0; i < 200; ++i) {
    const RngKey key{i, 0, 0, 7};
    const float px = 40 * sampleUniform(key, 0), py = 30 * sampleUniform(key, 1);
    const float lu = sampleUniform(key, 2), lv = sampleUniform(key, 3);
    const CameraRay r = cam.generate(px, py, lu, lv, 0);
    const Vec3 x = r.org + r.dir * (2 + 10 * sampleUniform(key, 4));
    CameraConnection c;
    ASSERT_TRUE(cam.connect(x, lu, lv, c)) << i;
    // Rounding in both maps: a few ulps of the film size and of the lens position.
    EXPECT_NEAR(c.px, px, 1e-3f) << i;
    EXPECT_NEAR(c.py, py, 1e-3f) << i;
    EXPECT_NEAR(length(c.lens - r.org), 0.0f, 1e-5f) << i;
    EXPECT_TRUE(std::isfinite(c.importance) && c.importance > 0) << i;
  }
}

TEST(CameraConnect, InvertsGenerateForPinholeAndThinLens) {
  expectConnectInvertsGenerate(PerspectiveCamera({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 40, 40, 30));
  expectConnectInvertsGenerate(PerspectiveCamera({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 40, 40, 30, 0.3f, 6.0f));
}

TEST(CameraConnect, RefusesPointsNoCameraRayReaches) {
  const PerspectiveCamera cam({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 40, 40, 30);
  CameraConnection c;
  EXPECT_FALSE(cam.connect({0, 0, 5}, 0.5f, 0.5f, c)) << "at the pinhole: d = 0";
  EXPECT_FALSE(cam.connect({0, 0, 6}, 0.5f, 0.5f, c)) << "behind the camera";
  EXPECT_FALSE(cam.connect({1, 0, 5}, 0.5f, 0.5f, c)) << "in the lens plane: cos = 0";
  EXPECT_FALSE(cam.connect({100, 0, 0}, 0.5f, 0.5f, c)) << "outside the field of view";
  EXPECT_FALSE(cam.connect({NAN, 0, 0}, 0.5f, 0.5f, c)) << "not a point";
}

// A plane z = 0 facing the pinhole, emitting radiance 1 toward it: the light tracer's splats
// sum Le |cos| W over the plane's area; per pixel (the film's splat scale: 1 / paths per pixel
// with N x spp paths, i.e. N x the mean) the integral over the pixel's footprint must be 1.
TEST(CameraConnect, ImportanceIntegratesToThePixelMean) {
  const int w = 8, h = 6;
  const PerspectiveCamera cam({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 40, w, h);
  // Midpoint rule over a grid on the plane covering the view.
  const int n = 1200;
  const float half = 3.0f, cell = 2 * half / n;
  std::vector<double> sum(size_t(w) * h, 0.0);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const Vec3 x{-half + (i + 0.5f) * cell, -half + (j + 0.5f) * cell, 0};
      CameraConnection c;
      if (!cam.connect(x, 0.5f, 0.5f, c)) continue;
      const float cosX = dot(normalize(c.lens - x), Vec3{0, 0, 1});
      sum[size_t(c.py) * w + size_t(c.px)] += double(cosX) * c.importance * cell * cell;
    }
  // Midpoint rule: a cell goes to the pixel holding its centre, so a pixel can gain or lose
  // at most half a cell along its border: relative error <= perimeter x cell / 2 / area
  // (the pixel's footprint on the plane is a square of side 2 * 5 * tan(20°) / h).
  const double side = 2 * 5 * std::tan(20 * 3.14159265358979 / 180) / h;
  const double bound = 4 * side * (cell / 2) / (side * side);
  double total = 0;
  for (size_t p = 0; p < sum.size(); ++p) {
    EXPECT_NEAR(sum[p] * double(w) * h, 1.0, bound) << p;
    total += sum[p];
  }
  // The whole image: only its outer border is cut by cells.
  const double outer = 2 * (w + h) * side * (cell / 2) / (w * h * side * side);
  EXPECT_NEAR(total, 1.0, outer);
}

}  // namespace
}  // namespace rayes
