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
#include "mirror_caustic_scene.h"
#include "render_fixtures.h"
#include "shading/material.h"

namespace rayes {
namespace {

RenderOptions methodWith(IntegratorMethod method, CausticPaths which) {
  RenderOptions o;
  o.method = method;
  o.integrator.causticPaths = which;
  o.lod = LodRule::Fixed;  // one geometry for camera and light paths
  o.maxLod = 3;
  return o;
}

TEST(CausticPaths, OnlyAndWithoutPartitionThePathTracer) {
  const Scene scene = testing::mirrorCausticScene(16, 12, 4);
  const auto all = testing::renderBeauty(scene, methodWith(IntegratorMethod::PathTracing, CausticPaths::All), 2);
  const auto only = testing::renderBeauty(scene, methodWith(IntegratorMethod::PathTracing, CausticPaths::Only), 2);
  const auto without =
      testing::renderBeauty(scene, methodWith(IntegratorMethod::PathTracing, CausticPaths::Without), 2);
  double caustic = 0;
  for (size_t i = 0; i < all.size(); i += 4)
    for (int c = 0; c < 3; ++c) {
      // Each is a mean of 4 samples; the sum rounds once more than each part.
      EXPECT_NEAR(only[i + c] + without[i + c], all[i + c], 4e-6 * (std::fabs(all[i + c]) + 1e-3)) << i / 4;
      caustic += only[i + c];
    }
  EXPECT_GT(caustic, 0) << "the scene has no caustic the path tracer finds";
}

// Block means (4 x 3 blocks, last: the image) of the channel average over `seeds` seeds.
struct Estimate {
  std::vector<double> mean, se;
};
Estimate estimate(const Scene& base, const RenderOptions& o, int seeds) {
  constexpr int bx = 4, by = 3;
  std::vector<double> sum(bx * by + 1, 0.0), sum2(sum.size(), 0.0);
  for (int s = 0; s < seeds; ++s) {
    Scene scene = base;
    scene.integrator.seed = uint64_t(500 + s);
    const auto rgba = testing::renderBeauty(scene, o, 2);
    std::vector<double> m(sum.size(), 0.0);
    for (int y = 0; y < scene.height; ++y)
      for (int x = 0; x < scene.width; ++x) {
        const size_t p = size_t(y) * scene.width + x;
        const double v = (double(rgba[4 * p]) + rgba[4 * p + 1] + rgba[4 * p + 2]) / 3;
        m[size_t(y * by / scene.height) * bx + size_t(x * bx / scene.width)] += v / (double(scene.width / bx) * (scene.height / by));
        m.back() += v / (double(scene.width) * scene.height);
      }
    for (size_t b = 0; b < m.size(); ++b) { sum[b] += m[b]; sum2[b] += m[b] * m[b]; }
  }
  Estimate e;
  for (size_t b = 0; b < sum.size(); ++b) {
    const double mean = sum[b] / seeds;
    e.mean.push_back(mean);
    e.se.push_back(std::sqrt(std::max(0.0, (sum2[b] - seeds * mean * mean) / (seeds - 1)) / seeds));
  }
  return e;
}

TEST(CausticPaths, PathTracerWithoutThemPlusLightTracedCausticsIsThePathTracer) {
  const Scene scene = testing::mirrorCausticScene(16, 12, 4);
  constexpr int kSeeds = 64;
  const Estimate all = estimate(scene, methodWith(IntegratorMethod::PathTracing, CausticPaths::All), kSeeds);
  const Estimate without = estimate(scene, methodWith(IntegratorMethod::PathTracing, CausticPaths::Without), kSeeds);
  const Estimate caustic = estimate(scene, methodWith(IntegratorMethod::LightTracing, CausticPaths::Only), kSeeds);
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
