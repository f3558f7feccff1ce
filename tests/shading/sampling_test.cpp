// Sampling routines and light selection against analytic moments (analytic-checks.md).
#include <cmath>
#include <numbers>
#include <gtest/gtest.h>
#include "core/rng.h"
#include "shading/light.h"
#include "shading/sampling.h"

namespace rayes {
namespace {

TEST(CosineHemisphere, MomentsWithinFourSigmaAndEdgesFinite) {
  const int n = 200000;
  double s = 0, s2 = 0;
  for (int i = 0; i < n; ++i) {
    const RngKey k{uint32_t(i), 0, 0, 5};
    const Vec3 d = sampleCosineHemisphere(sampleUniform(k, 0), sampleUniform(k, 1));
    ASSERT_GE(d.z, 0.0f);
    s += d.z;
    s2 += double(d.z) * d.z;
  }
  // E[cos] = 2/3, Var[cos] = 1/2 - 4/9 = 1/18. E[cos^2] = 1/2, Var = 1/3 - 1/4 = 1/12.
  EXPECT_NEAR(s / n, 2.0 / 3.0, 4 * std::sqrt(1.0 / 18.0 / n));
  EXPECT_NEAR(s2 / n, 0.5, 4 * std::sqrt(1.0 / 12.0 / n));
  for (float u : {0.0f, 0.99999994f})
    for (float v : {0.0f, 0.99999994f}) {
      const Vec3 d = sampleCosineHemisphere(u, v);
      EXPECT_TRUE(isFinite(d));
      EXPECT_NEAR(length(d), 1.0f, 1e-5f);
    }
}

PatchLight parallelogram(Vec3 o, Vec3 a, Vec3 b, Rgb le, uint32_t leaf) {
  return {[=](float u, float v, Vec3& p, Vec3& n) { p = o + a * u + b * v; n = cross(a, b); }, le, false, leaf};
}

TEST(LightSampler, PatchLightAreaIsRecoveredExactlyFromItsPdf) {
  // Uniform (u, v) on a parallelogram: 1 / pdfArea is its area for every sample.
  // Seen from straight above at height h the solid-angle density is pdfArea h^2 / cos = h^2 / 6.
  LightSampler s({}, {parallelogram({0, 0, 0}, {2, 0, 0}, {0.5f, 3, 0}, {1, 1, 1}, 4)});
  LightSample ls;
  const Vec3 p00{0, 0, 0}, a{2, 0, 0}, b{0.5f, 3, 0};
  const Vec3 onLight = p00 + a * 0.1f + b * 0.9f;
  ASSERT_FALSE(s.sample(onLight - Vec3{0, 0, 2}, 0.3f, 0.1f, 0.9f, ls)) << "behind the one-sided light";
  ASSERT_TRUE(s.sample(onLight + Vec3{0, 0, 2}, 0.3f, 0.1f, 0.9f, ls));
  EXPECT_FLOAT_EQ(ls.pdf, 4.0f / 6.0f);
  EXPECT_FLOAT_EQ(ls.distance, 2.0f);
  EXPECT_FLOAT_EQ(s.patchPdf(0, 0.1f, 0.9f, ls.wi, ls.distance), ls.pdf);
  EXPECT_EQ(ls.leaf, 4u);
  EXPECT_EQ(s.patchLightOfLeaf(4), 0);
  EXPECT_EQ(s.patchLightOfLeaf(3), -1);
}

TEST(LightSampler, PickProbabilitiesArePowerProportionalAndSumToOne) {
  // Point light of 4*pi*I = 4*pi; a one-sided unit square of radiance 1 has power pi.
  LightSampler s({{{0, 0, 5}, {1, 1, 1}}}, {parallelogram({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 1}, 0)});
  // Seen from (0.5, 0.5, 1): the square's solid-angle density is pick * 1 / cos = pick.
  LightSample a, b;
  ASSERT_TRUE(s.sample({0.5f, 0.5f, 1}, 0.1f, 0.5f, 0.5f, a));
  ASSERT_TRUE(s.sample({0.5f, 0.5f, 1}, 0.9f, 0.5f, 0.5f, b));
  EXPECT_TRUE(a.delta);
  EXPECT_FALSE(b.delta);
  EXPECT_NEAR(a.pdf, 0.8f, 1e-5f);
  EXPECT_NEAR(a.pdf + b.pdf, 1.0f, 1e-6f);
  EXPECT_NEAR(length(a.radiance), std::sqrt(3.0f) / 16.5f, 1e-6f);  // I / d^2, d^2 = 16.5
}

TEST(LightSampler, DegenerateLightIsRejectedNotNaN) {
  LightSampler s({}, {parallelogram({0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {1, 1, 1}, 0)});  // zero area
  LightSample ls;
  EXPECT_FALSE(s.sample({0, 0, -1}, 0.5f, 0.5f, 0.5f, ls));
  LightSampler none;
  EXPECT_FALSE(none.sample({0, 0, -1}, 0.5f, 0.5f, 0.5f, ls));
}

}  // namespace
}  // namespace rayes
