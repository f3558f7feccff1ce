// The compact ray record (core/ray_batch.h, Ray: a 48-bit octahedral direction, a half spread)
// changes image bits but not what they estimate: a render's means stay within the estimator's
// error of the unquantised rays', at two seeds, with and without the first-hit AOVs; and the
// bits stay deterministic across threads and ray budgets. The unquantised references: the closed
// form of a furnace (a closed box of albedo rho emitting Le: Le / (1 - rho) everywhere), and the
// teapot's channel means measured with float rays (main at bb30306, before the record was
// quantised, `bench_app_channel_means scenes/teapot.json 48 36 4 24`).
#include <cmath>
#include <string>
#include <gtest/gtest.h>
#include "support/furnace_scene.h"
#include "support/render_fixtures.h"

namespace rayes {
namespace {

TEST(CompactRays, AFurnaceMatchesItsClosedFormAtTwoSeedsWithAndWithoutAovs) {
  RenderOptions noAovs;
  noAovs.firstHitAovs = false;
  for (int seed : {11, 12}) {
    const Scene s = testing::furnaceScene(0.7f, 1.0f, uint64_t(seed));
    const auto withAovs = testing::renderBeauty(s, RenderOptions{}, 2);
    testing::expectFurnaceMean(withAovs, 0.7f, 1.0f, "seed " + std::to_string(seed));
    // The radiance, not the alpha: alpha is a first-hit AOV, not kept without them.
    const auto without = testing::renderBeauty(s, noAovs, 2);
    ASSERT_EQ(without.size(), withAovs.size());
    for (size_t i = 0; i < withAovs.size(); ++i)
      if (i % 4 != 3) ASSERT_EQ(without[i], withAovs[i]) << "the AOVs change no radiance, seed " << seed << ", at " << i;
  }
}

// The teapot's means depend on every direction a path takes (camera rays, BSDF samples, shadow
// rays to the light, their cones' levels of detail): within the reference's 5 sd (4 standard
// errors, widened for the reference's own noise: render_fixtures.h) at two seeds outside the
// reference's, with the AOVs and without.
TEST(CompactRays, TheTeapotsMeansMatchTheFloatRaysAtTwoSeedsWithAndWithoutAovs) {
  const testing::ChannelMeans floatRays{{0.309256, 0.258422, 0.174952}, {0.001788, 0.001519, 0.000899}};
  RenderOptions noAovs;
  noAovs.firstHitAovs = false;
  for (int seed : {11, 12}) {
    Scene s = testing::smallTeapot(48, 36, 4);
    s.integrator.seed = uint64_t(seed);
    const auto image = testing::renderBeauty(s, RenderOptions{}, 2);
    testing::expectChannelMeans(image, floatRays, "teapot 48x36, 4 spp, seed " + std::to_string(seed));
    testing::expectChannelMeans(testing::renderBeauty(s, noAovs, 2), floatRays,
                                "without AOVs, seed " + std::to_string(seed));
  }
}

// Quantising happens as a ray is written, from that ray's own values alone: the same bits at 1
// and 2 threads, every ray alone, and under a budget of a few dozen paths per batch.
TEST(CompactRays, ImagesStayBitIdenticalAcrossThreadsAndBudgets) {
  testing::expectOrderIndependent(testing::smallTeapot(24, 18, 2), 40);
}

}  // namespace
}  // namespace rayes
