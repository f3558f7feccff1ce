// Light transport against an analytic answer (docs/design.md, "Analytic checks", "Furnaces"):
// inside a closed box whose walls all have albedo rho and emit radiance Le, the radiance is
// Le / (1 - rho) everywhere. NEE, Russian roulette and the whole generation pipeline take part;
// the tolerance is 4 standard errors of the pixel mean (pixels are i.i.d. estimates here).
#include <cmath>
#include <gtest/gtest.h>
#include "support/render_fixtures.h"

namespace rayes {
namespace {

Scene furnace(float rho, float le) {
  const std::string r = std::to_string(rho), e = std::to_string(le);
  const std::string text = R"({
    "camera": {"position": [0.1, -0.6, 0.2], "look_at": [-0.2, 1, -0.1], "up": [0, 0, 1], "fov": 100},
    "film": {"resolution": [24, 24], "spp": 16},
    "integrator": {"max_depth": 1000, "seed": 7},
    "materials": {"wall": {"type": "emissive", "radiance": )" + e + R"(, "albedo": )" + r + R"(, "two_sided": true}},
    "shapes": [{"type": "bilinear", "material": "wall", "quads": [
      [[-1,-1,-1],[1,-1,-1],[-1,1,-1],[1,1,-1]],
      [[-1,-1,1],[1,-1,1],[-1,1,1],[1,1,1]],
      [[-1,-1,-1],[1,-1,-1],[-1,-1,1],[1,-1,1]],
      [[-1,1,-1],[1,1,-1],[-1,1,1],[1,1,1]],
      [[-1,-1,-1],[-1,1,-1],[-1,-1,1],[-1,1,1]],
      [[1,-1,-1],[1,1,-1],[1,-1,1],[1,1,1]]
    ]}]
  })";
  return parseScene(text, "furnace.json");
}

void expectFurnace(float rho, float le) {
  const Scene s = furnace(rho, le);
  const auto rgba = testing::renderBeauty(s, RenderOptions{}, 2);
  const size_t n = rgba.size() / 4;
  double sum = 0, sum2 = 0;
  for (size_t p = 0; p < n; ++p) {
    ASSERT_TRUE(std::isfinite(rgba[4 * p]));
    ASSERT_EQ(rgba[4 * p + 3], 1.0f) << "a camera ray escaped the closed box at pixel " << p;
    sum += rgba[4 * p];
    sum2 += double(rgba[4 * p]) * rgba[4 * p];
  }
  const double mean = sum / n;
  const double var = (sum2 - n * mean * mean) / (n - 1);
  const double stderr_ = std::sqrt(var / n);
  const double expected = le / (1.0 - rho);
  EXPECT_GT(stderr_, 0.0);
  EXPECT_NEAR(mean, expected, 4 * stderr_) << "rho " << rho << " stderr " << stderr_;
}

TEST(Furnace, ClosedBoxHalfAlbedo) { expectFurnace(0.5f, 1.0f); }
TEST(Furnace, ClosedBoxHighAlbedo) { expectFurnace(0.8f, 0.5f); }

}  // namespace
}  // namespace rayes
