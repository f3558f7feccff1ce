// Level-of-detail rules and the bias on them. The thesis's batch-density LOD rule (--lod density) is available: it renders a finite,
// non-black image and dices coarser than the per-ray footprint rule on a low-spp render (its
// level comes from the ray count per leaf, not from each ray's footprint).
#include <cmath>
#include <gtest/gtest.h>
#include "support/render_fixtures.h"

namespace rayes {
namespace {

// A GenerationStats counter summed over the render.
uint64_t total(const RenderStats& s, uint64_t GenerationStats::*counter) {
  uint64_t n = 0;
  for (const auto& g : s.generations) n += g.stats.*counter;
  return n;
}
uint64_t micropolygons(const RenderStats& s) { return total(s, &GenerationStats::micropolygonsCreated); }
uint64_t dicings(const RenderStats& s) { return total(s, &GenerationStats::leavesDiced); }

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

// --lod-bias B shifts every ray's level: coarser dicings for B < 0, finer for B > 0; at the
// most negative bias every dicing is at level 0 (one micropolygon each). The biased level is
// still a function of (ray, leaf), so the image stays independent of threads and batching.
TEST(LodRule, BiasShiftsEveryLevelAndKeepsTheImageOrderIndependent) {
  const Scene s = testing::smallTeapot(16, 12, 1);
  ThreadLimit limit(2);
  RenderOptions coarser, none, finer, coarsest;
  for (RenderOptions* o : {&coarser, &none, &finer, &coarsest}) o->maxLod = 6;  // room for +1 at 16x12
  coarser.lodBias = -2;
  finer.lodBias = 1;
  coarsest.lodBias = -TraceSettings::kMaxLodBias;
  Renderer a(s, coarser), b(s, none), c(s, finer), d(s, coarsest);
  a.render(); b.render(); c.render(); d.render();
  EXPECT_LT(micropolygons(a.stats()), micropolygons(b.stats()));
  EXPECT_LT(micropolygons(b.stats()), micropolygons(c.stats()));
  EXPECT_EQ(micropolygons(d.stats()), dicings(d.stats()));
  const auto image = testing::renderBeauty(s, coarser, 2);
  EXPECT_EQ(testing::renderBeauty(s, coarser, 1), image) << "1 thread";
  RenderOptions small = coarser;
  small.rayMemoryBytes = 30 * testing::bytesPerPath(s, coarser);
  EXPECT_EQ(testing::renderBeauty(s, small, 2), image) << "30 paths per batch";
}

}  // namespace
}  // namespace rayes
