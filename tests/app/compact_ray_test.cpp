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
#include "support/render_fixtures.h"

namespace rayes {
namespace {

Scene furnace(int seed) {
  const std::string text = R"({
    "camera": {"position": [0.1, -0.6, 0.2], "look_at": [-0.2, 1, -0.1], "up": [0, 0, 1], "fov": 100},
    "film": {"resolution": [24, 24], "spp": 16},
    "integrator": {"max_depth": 1000, "seed": )" + std::to_string(seed) + R"(},
    "materials": {"wall": {"type": "emissive", "radiance": 1, "albedo": 0.7, "two_sided": true}},
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

// Pixels are i.i.d. estimates of Le / (1 - rho) here: the standard error is the pixels' sample
// standard deviation over sqrt(n).
void expectFurnaceMean(const std::vector<float>& rgba, const std::string& what) {
  const size_t n = rgba.size() / 4;
  double sum = 0, sum2 = 0;
  for (size_t p = 0; p < n; ++p) {
    ASSERT_TRUE(std::isfinite(rgba[4 * p])) << what;
    sum += rgba[4 * p];
    sum2 += double(rgba[4 * p]) * rgba[4 * p];
  }
  const double mean = sum / double(n);
  const double standardError = std::sqrt((sum2 - double(n) * mean * mean) / double(n - 1) / double(n));
  EXPECT_GT(standardError, 0.0) << what;
  EXPECT_NEAR(mean, 1.0 / (1.0 - 0.7), 4 * standardError) << what;
}

TEST(CompactRays, AFurnaceMatchesItsClosedFormAtTwoSeedsWithAndWithoutAovs) {
  RenderOptions noAovs;
  noAovs.firstHitAovs = false;
  for (int seed : {11, 12}) {
    const Scene s = furnace(seed);
    const auto withAovs = testing::renderBeauty(s, RenderOptions{}, 2);
    expectFurnaceMean(withAovs, "seed " + std::to_string(seed));
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
