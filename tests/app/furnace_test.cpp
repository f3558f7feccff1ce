// Light transport against an analytic answer (docs/design.md, "Analytic checks", "Furnaces"):
// inside a closed box whose walls all have albedo rho and emit radiance Le, the radiance is
// Le / (1 - rho) everywhere. NEE, Russian roulette and the whole generation pipeline take part;
// the tolerance is 4 standard errors of the pixel mean (pixels are i.i.d. estimates here).
#include <cmath>
#include <gtest/gtest.h>
#include "support/furnace_scene.h"
#include "support/render_fixtures.h"

namespace rayes {
namespace {

void expectFurnace(float rho, float le) {
  const auto rgba = testing::renderBeauty(testing::furnaceScene(rho, le, 7), RenderOptions{}, 2);
  for (size_t p = 0; p < rgba.size() / 4; ++p)
    ASSERT_EQ(rgba[4 * p + 3], 1.0f) << "a camera ray escaped the closed box at pixel " << p;
  testing::expectFurnaceMean(rgba, rho, le, "rho " + std::to_string(rho));
}

TEST(Furnace, ClosedBoxHalfAlbedo) { expectFurnace(0.5f, 1.0f); }
TEST(Furnace, ClosedBoxHighAlbedo) { expectFurnace(0.8f, 0.5f); }

}  // namespace
}  // namespace rayes
