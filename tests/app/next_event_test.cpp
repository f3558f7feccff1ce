// Next-event estimation through the whole renderer against a closed form. A closed box whose
// floor and ceiling are planar trapezoids (not parallelograms) has a square light hanging a
// hundredth below the ceiling; a camera under the light looks straight down at the floor.
// With direct lighting only, a Lambertian floor point reflects rho * L * F, F the form factor
// from the point to the parallel square. A shadow ray that overshoots the light point by its
// origin offset is stopped by the ceiling just behind it and darkens the floor: this is the
// bias the shadow-ray segment (path_tracer.cpp) and the zero dicing error of planar
// trapezoids (bilinear_patch.cpp) remove.
#include <cmath>
#include <cstdio>
#include <numbers>
#include <gtest/gtest.h>
#include "support/render_fixtures.h"

namespace rayes {
namespace {

constexpr double kHeight = 2, kGap = 0.01, kHalfLight = 0.25, kAlbedo = 0.5, kRadiance = 10;

// Form factor from a point to the rectangle [0, a] x [0, b] parallel to it at height h, one
// corner straight above the point; odd in a and in b, so signed sides superpose.
double cornerFormFactor(double a, double b, double h) {
  const double ra = std::sqrt(a * a + h * h), rb = std::sqrt(b * b + h * h);
  return (a / ra * std::atan(b / ra) + b / rb * std::atan(a / rb)) / (2 * std::numbers::pi);
}

// Form factor from the floor point (x, z) to the light square.
double lightFormFactor(double x, double z) {
  const double h = kHeight - kGap, s = kHalfLight;
  return cornerFormFactor(s - x, s - z, h) - cornerFormFactor(-s - x, s - z, h) -
         cornerFormFactor(s - x, -s - z, h) + cornerFormFactor(-s - x, -s - z, h);
}

std::string boxScene(int size, int spp, int seed) {
  // Trapezoids: the far side (z = 2) is narrower than the near one.
  const std::string floor = "[[-2,0,-2],[2,0,-2],[-1.5,0,2],[1.5,0,2]]";
  const std::string ceiling = "[[-2,2,-2],[-1.5,2,2],[2,2,-2],[1.5,2,2]]";
  const std::string walls =
      "[[-2,0,-2],[-2,2,-2],[2,0,-2],[2,2,-2]], [[2,0,-2],[2,2,-2],[1.5,0,2],[1.5,2,2]],"
      "[[1.5,0,2],[1.5,2,2],[-1.5,0,2],[-1.5,2,2]], [[-1.5,0,2],[-1.5,2,2],[-2,0,-2],[-2,2,-2]]";
  const std::string y = std::to_string(kHeight - kGap);
  return R"({"camera": {"position": [0, 1, 0], "look_at": [0, 0, 0], "up": [0, 0, 1], "fov": 30},
    "film": {"resolution": [)" + std::to_string(size) + "," + std::to_string(size) + R"(], "spp": )" +
         std::to_string(spp) + R"(},
    "integrator": {"max_depth": 1, "seed": )" + std::to_string(seed) + R"(},
    "materials": {"grey": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}},
    "shapes": [{"type": "bilinear", "material": "grey", "quads": [)" + floor + "," + ceiling + "," + walls + R"(]}],
    "lights": [{"type": "rect", "corner": [0.25, )" + y + R"(, -0.25], "edge_u": [0, 0, 0.5],
                "edge_v": [-0.5, 0, 0], "radiance": [10, 10, 10]}]})";
}

// The analytic pixel value: rho L F averaged over the pixel's footprint on the floor by an
// n x n midpoint rule.
double expectedPixel(const PerspectiveCamera& camera, int px, int py, int n) {
  double sum = 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const CameraRay r = camera.generate(px + (i + 0.5f) / n, py + (j + 0.5f) / n, 0.5f, 0.5f, 0);
      const double t = -double(r.org.y) / r.dir.y;
      sum += kAlbedo * kRadiance * lightFormFactor(r.org.x + t * r.dir.x, r.org.z + t * r.dir.z);
    }
  return sum / (n * n);
}

// Renders the box with the given options and compares the floor with the form factor.
void expectFloorMatchesFormFactor(const RenderOptions& options) {
  const int size = 16, spp = 16;
  const Scene scene = parseScene(boxScene(size, spp, 0), "next-event-box.json");
  const CameraDesc& c = scene.camera;
  // In world coordinates, where the form factor is written (the scene's camera is in its render frame).
  const PerspectiveCamera camera(scene.frame.toWorld(c.position), scene.frame.toWorld(c.lookAt), c.up, c.fovYDegrees, size, size);
  const std::vector<float> image = testing::renderBeauty(scene, options, 2);

  // Pixels are independent estimates of their own expected values: the mean residual has the
  // standard error of the residuals' spread over sqrt(pixels).
  double sum = 0, sumSq = 0, expectedSum = 0, quadrature = 0;
  const int pixels = size * size;
  for (int py = 0; py < size; ++py)
    for (int px = 0; px < size; ++px) {
      const double expected = expectedPixel(camera, px, py, 8);
      // The midpoint rule's own error, bounded by its change from 4 x 4 to 8 x 8 points.
      quadrature += std::fabs(expected - expectedPixel(camera, px, py, 4));
      const double r = image[4 * size_t(py * size + px)] - expected;
      sum += r;
      sumSq += r * r;
      expectedSum += expected;
    }
  const double meanResidual = sum / pixels, meanExpected = expectedSum / pixels;
  const double variance = (sumSq - sum * sum / pixels) / (pixels - 1);
  const double standardError = std::sqrt(variance / pixels);
  std::printf("[ max LOD %d ] floor mean %.6f, form factor %.6f, relative %+.3f %% +- %.3f %% (SE)\n", options.maxLod,
              meanExpected + meanResidual, meanExpected, 100 * meanResidual / meanExpected,
              100 * standardError / meanExpected);
  EXPECT_LT(standardError, 0.005 * meanExpected) << "too noisy to see a bias of a percent";
  EXPECT_LE(std::fabs(meanResidual), 4 * standardError + quadrature / pixels)
      << "max LOD " << options.maxLod << ": mean " << meanExpected + meanResidual << ", expected "
      << meanExpected << " (standard error " << standardError << ")";
}

// At the finest levels the camera rays' own offsets are small; at level 0 (the coarse levels
// secondary rays use, forced here for camera rays) a trapezoid's twist made the old offset
// half a unit, fifty times the light's gap to the ceiling.
TEST(NextEvent, FloorUnderALightJustBelowATrapezoidCeilingMatchesTheFormFactor) {
  for (int maxLod : {10, 0}) {
    RenderOptions options;
    options.maxLod = maxLod;
    expectFloorMatchesFormFactor(options);
  }
}

}  // namespace
}  // namespace rayes
