// Caustic paths (light -> (mirror, glass or glossy)+ -> diffuse -> ...) are split out of the
// path tracer exactly: `pt --caustic-paths without` plus a caustic estimate is the whole image,
// so the caustic methods (pm, ppm, lbt) count nothing twice.
//  - Only and Without of the same seed partition the path tracer's paths: their sum is its
//    image up to float rounding of one addition per pixel.
//  - pt without caustic paths plus the light tracer's caustic paths alone converges to the full
//    path tracer: block means agree within 4 standard errors measured over independent seeds
//    (Student-t with 63 degrees of freedom: |t| > 4 for one of 13 comparisons in about 0.2 % of
//    runs). The caustic must be there for the test to mean anything: its mean is checked to
//    stand more than 4 standard errors above zero.
#include <cmath>
#include <gtest/gtest.h>
#include "support/mirror_caustic_scene.h"
#include "support/render_fixtures.h"
#include "shading/material.h"

namespace rayes {
namespace {

RenderOptions methodWith(const std::string& method, CausticPaths which) {
  RenderOptions o;
  o.method.name = method;
  o.method.causticPaths = which;
  o.lod = LodRule::Fixed;  // one geometry for camera and light paths
  o.maxLod = 3;
  return o;
}

TEST(CausticPaths, OnlyAndWithoutPartitionThePathTracer) {
  const Scene scene = testing::mirrorCausticScene(16, 12, 4);
  const auto all = testing::renderBeauty(scene, methodWith("pt", CausticPaths::All), 2);
  const auto only = testing::renderBeauty(scene, methodWith("pt", CausticPaths::Only), 2);
  const auto without =
      testing::renderBeauty(scene, methodWith("pt", CausticPaths::Without), 2);
  double caustic = 0;
  for (size_t i = 0; i < all.size(); i += 4)
    for (int c = 0; c < 3; ++c) {
      // Each is a mean of 4 samples; the sum rounds once more than each part.
      EXPECT_NEAR(only[i + c] + without[i + c], all[i + c], 4e-6 * (std::fabs(all[i + c]) + 1e-3)) << i / 4;
      caustic += only[i + c];
    }
  EXPECT_GT(caustic, 0) << "the scene has no caustic the path tracer finds";
}

// --caustic-paths only for the caustic methods keeps their estimate alone (and, for lbt, the path
// tracer's caustic paths of lights without beams: none here), so with pt --caustic-paths without
// of the same seed it sums to the method's own image, per pixel up to float rounding.
TEST(CausticPaths, CausticMethodsOnlyPlusThePathTracerWithoutIsTheMethod) {
  const Scene scene = testing::mirrorCausticScene(16, 12, 4);
  const auto without =
      testing::renderBeauty(scene, methodWith("pt", CausticPaths::Without), 2);
  for (const char* m : {"lbt", "pm"}) {
    RenderOptions all = methodWith(m, CausticPaths::All), only = methodWith(m, CausticPaths::Only);
    all.method.beams.resolution = only.method.beams.resolution = 16;
    all.method.photons.photonsPerSample = only.method.photons.photonsPerSample = 200;
    const auto full = testing::renderBeauty(scene, all, 2), caustic = testing::renderBeauty(scene, only, 2);
    double sum = 0;
    for (size_t i = 0; i < full.size(); i += 4)
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(caustic[i + c] + without[i + c], full[i + c], 1e-5 * (std::fabs(full[i + c]) + 1e-3))
            << m << ": pixel " << i / 4;
        sum += caustic[i + c];
      }
    EXPECT_GT(sum, 0) << m << ": no caustic estimate";
  }
}

TEST(CausticPaths, PathTracerWithoutThemPlusLightTracedCausticsIsThePathTracer) {
  const Scene scene = testing::mirrorCausticScene(16, 12, 4);
  constexpr int kSeeds = 64;
  const testing::BlockEstimate all = testing::blockEstimate(scene, methodWith("pt", CausticPaths::All), kSeeds);
  const testing::BlockEstimate without = testing::blockEstimate(scene, methodWith("pt", CausticPaths::Without), kSeeds);
  const testing::BlockEstimate caustic = testing::blockEstimate(scene, methodWith("lt", CausticPaths::Only), kSeeds);
  EXPECT_GT(caustic.mean.back(), 4 * caustic.se.back()) << "no caustic to split";
  for (size_t b = 0; b < all.mean.size(); ++b) {
    const double se = std::sqrt(all.se[b] * all.se[b] + without.se[b] * without.se[b] + caustic.se[b] * caustic.se[b]);
    EXPECT_LE(std::fabs(without.mean[b] + caustic.mean[b] - all.mean[b]), 4 * se)
        << "block " << b << ": pt " << all.mean[b] << ", pt without " << without.mean[b] << " + lt caustics "
        << caustic.mean[b];
  }
}

TEST(CausticPaths, CausticScatterersAreSmoothMirrorsGlassAndGlossyLobes) {
  Material m;
  m.type = MaterialType::Conductor;
  m.roughness = 0;
  EXPECT_TRUE(isCausticScatterer(m));
  m.roughness = 0.2f;
  EXPECT_FALSE(isCausticScatterer(m)) << "rough metal";
  m.type = MaterialType::Dielectric;
  m.roughness = 0;
  EXPECT_TRUE(isCausticScatterer(m));
  m.type = MaterialType::Glossy;
  m.sigma = 0.05f;
  EXPECT_TRUE(isCausticScatterer(m));
  m.sigma = 0;
  EXPECT_TRUE(isCausticScatterer(m)) << "the glossy lobe's mirror limit";
  for (MaterialType t : {MaterialType::Diffuse, MaterialType::Plastic, MaterialType::Phong}) {
    m.type = t;
    m.albedo = Rgb{0.5f, 0.5f, 0.5f};
    EXPECT_FALSE(isCausticScatterer(m)) << int(t);
  }
}

}  // namespace
}  // namespace rayes
