// Level-of-detail rules and the bias on them; the per-ray rule renders the energy of the fixed
// geometry. The thesis's batch-density LOD rule (--lod density) is available: it renders a finite,
// non-black image and dices coarser than the per-ray footprint rule on a low-spp render (its
// level comes from the ray count per leaf, not from each ray's footprint).
#include <cmath>
#include <gtest/gtest.h>
#include "support/render_fixtures.h"
#include "support/temp_folder.h"

namespace rayes {
namespace {

uint64_t micropolygons(const RenderStats& s) {
  return testing::totalOf(s, &GenerationStats::micropolygonsCreated);
}
uint64_t dicings(const RenderStats& s) { return testing::totalOf(s, &GenerationStats::leavesDiced); }

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

// The teapot inside its closed box, everything grey (albedo 0.5), one ceiling light, 4 bounces:
// a curved, closed scene whose energy reaches the camera through every bounce.
Scene greyTeapotBox(const testing::TempFolder& dir, int w, int h, int spp, uint64_t seed) {
  const std::string quads = R"(
      [[-6, -10, 0], [6, -10, 0], [-6, 6, 0], [6, 6, 0]], [[-6, -10, 8], [-6, 6, 8], [6, -10, 8], [6, 6, 8]],
      [[-6, 6, 0], [6, 6, 0], [-6, 6, 8], [6, 6, 8]], [[-6, -10, 0], [-6, -10, 8], [6, -10, 0], [6, -10, 8]],
      [[-6, -10, 0], [-6, 6, 0], [-6, -10, 8], [-6, 6, 8]], [[6, -10, 0], [6, -10, 8], [6, 6, 0], [6, 6, 8]])";
  const std::string json = R"({
    "camera": {"position": [0.0, -9.5, 4.2], "look_at": [0.25, 0.0, 1.5], "up": [0, 0, 1], "fov": 42},
    "integrator": {"max_depth": 4, "seed": )" + std::to_string(seed) + R"(},
    "materials": {"grey": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}},
    "shapes": [
      {"type": "bezier", "file": ")" + testing::sourcePath("scenes/teapot.bpt") + R"(", "material": "grey"},
      {"type": "bilinear", "material": "grey", "quads": [)" + quads + R"(]}
    ],
    "lights": [{"type": "rect", "corner": [-1.5, 1.0, 7.99], "edge_u": [3, 0, 0], "edge_v": [0, -3, 0],
                "radiance": [14, 14, 14]}]
  })";
  return testing::resized(loadScene(dir.write("grey-teapot-box.json", json)), w, h, spp);
}

// Per-ray level of detail renders the same energy as one fine geometry for every ray (--lod
// fixed) on a curved, closed scene through 4 bounces: the image means of two seeds of each rule
// agree within 4 standard errors. Each rule's seeds are its own, so the two means are
// independent; the standard error of their difference is the sample standard deviation of the
// per-pixel differences over the square root of the pixel count (their spread includes any
// pixel-to-pixel change of the difference, so it can only overstate the error). Main before
// the dicing-error floor (levelForDicingError) was 0.28 % dark here, about 6 standard errors;
// docs/design.md, "Level of detail and energy".
TEST(LodRule, PerRayRuleRendersTheEnergyOfTheFixedGeometryThroughFourBounces) {
  const testing::TempFolder dir;
  constexpr int kWidth = 48, kHeight = 36, kSpp = 512;
  RenderOptions perRay, fixed;
  perRay.maxLod = fixed.maxLod = 8;  // the fixed geometry's dicing error is 2^-16 of the default's level 0
  fixed.lod = LodRule::Fixed;
  // Mean over seeds of the green channel per pixel (the scene is grey).
  auto render = [&](const RenderOptions& o, uint64_t seedA, uint64_t seedB) {
    std::vector<double> mean(size_t(kWidth) * kHeight, 0.0);
    for (const uint64_t seed : {seedA, seedB}) {
      const auto rgba = testing::renderBeauty(greyTeapotBox(dir, kWidth, kHeight, kSpp, seed), o, 2);
      for (size_t p = 0; p < mean.size(); ++p) mean[p] += 0.5 * rgba[4 * p + 1];
    }
    return mean;
  };
  const std::vector<double> a = render(perRay, 1, 2), b = render(fixed, 3, 4);
  const double n = double(a.size());
  double sum = 0, sumSq = 0, meanB = 0;
  for (size_t p = 0; p < a.size(); ++p) {
    const double d = a[p] - b[p];
    sum += d;
    sumSq += d * d;
    meanB += b[p] / n;
  }
  const double meanDiff = sum / n;
  const double standardError = std::sqrt((sumSq - n * meanDiff * meanDiff) / (n - 1) / n);
  ASSERT_GT(meanB, 0.0);
  EXPECT_LE(std::fabs(meanDiff), 4 * standardError)
      << "per-ray mean - fixed mean = " << meanDiff << " (" << 100 * meanDiff / meanB << " % of " << meanB
      << "), standard error " << standardError;
}

}  // namespace
}  // namespace rayes
