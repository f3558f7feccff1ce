// Thin-lens camera (issue 3, item 5): a lens of aperture 0 is the pinhole, bit for bit; a small
// emitter off the focus plane spreads into a disk whose size is the predicted circle of
// confusion; on the focus plane it stays sharp.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <unistd.h>
#include <gtest/gtest.h>
#include "support/render_fixtures.h"
#include "support/temp_folder.h"

namespace rayes {
namespace {
namespace fs = std::filesystem;

constexpr int kRes = 64;
constexpr double kFov = 30, kSide = 0.1;

// A small emissive square of side kSide facing the camera on its axis at distance z; camera
// keys `lens` (e.g. "aperture_radius": 0.2, "focus_distance": 2).
std::string emitterScene(double z, const std::string& lens) {
  const std::string h = std::to_string(kSide / 2), d = std::to_string(-z);
  return R"({
  "camera": {"position": [0, 0, 0], "look_at": [0, 0, -1], "up": [0, 1, 0], "fov": )" + std::to_string(kFov) +
         lens + R"(},
  "film": {"resolution": [)" + std::to_string(kRes) + ", " + std::to_string(kRes) + R"(], "spp": 1},
  "integrator": {"max_depth": 1},
  "materials": {"glow": {"type": "emissive", "radiance": 1, "two_sided": true}},
  "shapes": [{"type": "bilinear", "material": "glow", "quads": [[[-)" + h + ", -" + h + ", " + d + "], [" + h +
         ", -" + h + ", " + d + "], [-" + h + ", " + h + ", " + d + "], [" + h + ", " + h + ", " + d + R"(]]]}]
})";
}

class ThinLens : public ::testing::Test {
 protected:
  std::vector<float> render(const std::string& json, int spp) {
    Scene s = loadScene(temp_.write("s.json", json));
    s.samplesPerPixel = spp;
    RenderOptions options;
    options.rayMemoryBytes = size_t(64) << 20;
    return testing::renderBeauty(s, options, 2);
  }
  // Energy-weighted mean squared distance (pixels^2) from the image centre, and the energy.
  static double secondMoment(const std::vector<float>& rgba, double* energy = nullptr) {
    double e = 0, m = 0;
    for (int y = 0; y < kRes; ++y)
      for (int x = 0; x < kRes; ++x) {
        const double v = rgba[4 * (size_t(y) * kRes + x)];
        const double dx = x + 0.5 - kRes / 2.0, dy = y + 0.5 - kRes / 2.0;
        e += v;
        m += v * (dx * dx + dy * dy);
      }
    if (energy) *energy = e;
    return m / e;
  }
  testing::TempFolder temp_;
};

TEST_F(ThinLens, ApertureZeroIsThePinhole) {
  const std::vector<float> pinhole = render(emitterScene(3, ""), 16);
  const std::vector<float> lens = render(emitterScene(3, R"(, "aperture_radius": 0, "focus_distance": 1.7)"), 16);
  ASSERT_EQ(pinhole.size(), lens.size());
  for (size_t i = 0; i < pinhole.size(); ++i) ASSERT_EQ(pinhole[i], lens[i]) << i;
}

TEST_F(ThinLens, OutOfFocusEmitterSpreadsIntoThePredictedCircleOfConfusion) {
  const double aperture = 0.2, focus = 2, z = 4;
  const double pixel = 2 * std::tan(kFov / 2 * std::numbers::pi / 180) / kRes;  // focus-plane size per unit distance
  // A point at depth z seen through lens point L lands where the ray from L meets the focus
  // plane: offset |L| (1 - F/z) from the pinhole image, so a disk of radius A |1 - F/z|.
  const double coc = aperture * std::fabs(1 - focus / z) / (focus * pixel);
  // The image is that disk convolved with the emitter's own image (a square of side w) and
  // the pixel box: second moments add.
  const double w = kSide / (z * pixel);
  const double expected = coc * coc / 2 + w * w / 6 + 1.0 / 6;
  const std::string lens = R"(, "aperture_radius": )" + std::to_string(aperture) + R"(, "focus_distance": )" +
                           std::to_string(focus);
  double energyBlur = 0, energySharp = 0;
  const double blurred = secondMoment(render(emitterScene(z, lens), 256), &energyBlur);
  EXPECT_NEAR(blurred, expected, 0.05 * expected) << "CoC radius " << coc << " px";
  RecordProperty("second_moment", std::to_string(blurred) + " expected " + std::to_string(expected));
  EXPECT_NEAR(std::sqrt(2 * (blurred - w * w / 6 - 1.0 / 6)), coc, 0.03 * coc);
  // In focus (z = F) the lens changes nothing but noise: the emitter stays a w x w square.
  const double wf = kSide / (focus * pixel);
  const double sharp = secondMoment(render(emitterScene(focus, lens), 64), &energySharp);
  EXPECT_NEAR(sharp, wf * wf / 6 + 1.0 / 6, 0.1 * (wf * wf / 6 + 1.0 / 6));
  EXPECT_GT(coc, 4.0);  // the test is meaningful: a blur of several pixels
}

}  // namespace
}  // namespace rayes
