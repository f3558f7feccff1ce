// The thesis's batch-density LOD rule (--lod density) is available: it renders a finite,
// non-black image and dices coarser than the per-ray footprint rule on a low-spp render (its
// level comes from the ray count per leaf, not from each ray's footprint).
#include <cmath>
#include <gtest/gtest.h>
#include "render_fixtures.h"

namespace rayes {
namespace {

uint64_t micropolygons(const RenderStats& s) {
  uint64_t n = 0;
  for (const auto& g : s.generations) n += g.stats.micropolygonsCreated;
  return n;
}

TEST(LodRule, DensityRuleRendersAndDicesByRayCount) {
  const Scene s = testing::smallTeapot(32, 24, 1);
  ThreadLimit limit(2);
  RenderOptions perRay, density;
  density.lod = LodRule::Density;
  Renderer a(s, perRay), b(s, density);
  const auto imgA = a.render().beautyRgba();
  const auto imgB = b.render().beautyRgba();
  double sum = 0;
  for (size_t i = 0; i < imgB.size(); ++i) {
    ASSERT_TRUE(std::isfinite(imgB[i]));
    sum += imgB[i];
  }
  EXPECT_GT(sum, 0.0);
  // 768 camera rays over 39 leaves: 4^m >= R/spp gives m <= 5 everywhere, while pixel-sized
  // footprints on the walls of a 32x24 image need about m = 5..7.
  EXPECT_LT(micropolygons(b.stats()), micropolygons(a.stats()));
}

}  // namespace
}  // namespace rayes
