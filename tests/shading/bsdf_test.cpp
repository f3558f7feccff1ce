// Every BSDF against the analytic checks of docs/design.md, "Analytic checks":
//  - energy: for 100 directions of arriving light, the estimate of the flux reflected and
//    transmitted, ∫ f(w, wIn) |cos θ| dω (times etaRel² for refracted samples: the power form),
//    is ≤ 1, and = 1 for the lossless models, within 4 standard errors (for the reciprocal
//    models the same integral as over the viewer's incoming directions; the glossy lobe is not
//    reciprocal and conserves the flux it reflects, docs/design.md);
//  - sampling agrees with pdf(): a χ² test on a sphere histogram, and the weight of every
//    sample equals f |cos| / pdf (and of every adjoint sample f(out, in) |cos θout| / pdf);
//  - reciprocity for the models that claim it (generalised for refraction; the Gaussian lobe's
//    own documented ratio);
//  - smooth limits against Fresnel's formulas, and no NaN at any edge.
#include <cmath>
#include <string>
#include <vector>
#include <gtest/gtest.h>
#include "chi2.h"
#include "core/rng.h"
#include "shading/bsdf.h"

namespace rayes {
namespace {

struct Case {
  std::string name;
  Bsdf bsdf;
  bool lossless = false;
};

std::vector<Case> cases() {
  return {
      {"lambert_white", Lambert{{1, 1, 1}}, true},
      {"lambert_grey", Lambert{{0.5f, 0.2f, 0.9f}}},
      {"conductor_gold_a0.05", Conductor{{0.2f, 0.92f, 1.1f}, {3.9f, 2.45f, 2.14f}, 0.05f}},
      {"conductor_gold_a0.3", Conductor{{0.2f, 0.92f, 1.1f}, {3.9f, 2.45f, 2.14f}, 0.3f}},
      {"conductor_alu_a1", Conductor{{1.66f, 0.88f, 0.52f}, {9.2f, 6.3f, 4.8f}, 1.0f}},
      {"conductor_smooth", Conductor{{0.2f, 0.92f, 1.1f}, {3.9f, 2.45f, 2.14f}, 0.0f}},
      {"dielectric_smooth_1.5", Dielectric{1.5f, 0}, true},
      {"dielectric_smooth_1.0001", Dielectric{1.0001f, 0}, true},
      {"dielectric_smooth_eta1", Dielectric{1.0f, 0}, true},
      {"dielectric_rough_a0.1", Dielectric{1.5f, 0.1f}},
      {"dielectric_rough_a0.5", Dielectric{1.5f, 0.5f}},
      {"dielectric_rough_a1", Dielectric{1.33f, 1.0f}},
      {"dielectric_rough_eta1.01", Dielectric{1.01f, 0.3f}},
      {"plastic_white", Plastic::make({1, 1, 1}, 1.5f), true},
      {"plastic_red", Plastic::make({0.8f, 0.1f, 0.05f}, 1.5f)},
      {"plastic_eta1.0001", Plastic::make({0.5f, 0.5f, 0.5f}, 1.0001f)},
      {"phong_mixed", Phong{{0.3f, 0.3f, 0.3f}, {0.7f, 0.6f, 0.5f}, 20}},
      {"phong_sharp", Phong{{0, 0, 0}, {1, 1, 1}, 500}},
      {"phong_broad", Phong{{0.2f, 0.1f, 0.0f}, {0.8f, 0.8f, 0.8f}, 1}},
      {"lobe_s0.1", GaussianLobe{{1, 1, 1}, 0.1f}},
      {"lobe_s0.5", GaussianLobe{{0.9f, 0.8f, 0.7f}, 0.5f}},
      {"lobe_delta", GaussianLobe{{1, 1, 1}, 0.0005f}},
  };
}

// A direction with cos θ = c (sign included) and azimuth phi.
Vec3 dirWithCos(float c, float phi) {
  const float s = std::sqrt(std::max(0.0f, 1 - c * c));
  return {s * std::cos(phi), s * std::sin(phi), c};
}

// The viewer directions of the energy test: 100 in the upper hemisphere, cos θ from 0.005 to
// 0.995 (grazing included), and for transmitting models 100 more from inside.
std::vector<Vec3> energyDirections(bool both) {
  std::vector<Vec3> d;
  for (int i = 0; i < 100; ++i) d.push_back(dirWithCos((i + 0.5f) / 100, 2.39996f * i));
  if (both)
    for (int i = 0; i < 100; ++i) d.push_back(dirWithCos(-(i + 0.5f) / 100, 2.39996f * i));
  return d;
}

TEST(BsdfEnergy, AtMostOneAndOneForLosslessWithinFourSigma) {
  const int n = 4000;
  for (const Case& c : cases()) {
    int dirIndex = 0;
    for (Vec3 wo : energyDirections(c.bsdf.transmits())) {
      double sum[3] = {0, 0, 0}, sum2[3] = {0, 0, 0};
      for (int i = 0; i < n; ++i) {
        const RngKey key{uint32_t(i), uint32_t(dirIndex), 1, 11};
        BsdfSample s;
        // Light arriving along wo, scattered: the adjoint (sample() itself for reciprocal models).
        if (!c.bsdf.sampleAdjoint(wo, sampleUniform(key, 0), sampleUniform(key, 1), sampleUniform(key, 2), s)) continue;
        ASSERT_TRUE(isFinite(s.weight)) << c.name;
        const Rgb w = s.weight * (s.etaRel * s.etaRel);  // the power form
        for (int ch = 0; ch < 3; ++ch) { sum[ch] += w[ch]; sum2[ch] += double(w[ch]) * w[ch]; }
      }
      for (int ch = 0; ch < 3; ++ch) {
        const double mean = sum[ch] / n, var = std::max(0.0, sum2[ch] / n - mean * mean);
        // 4 standard errors; for zero-variance estimators the float rounding of the weights
        // (a few ulps, < 1e-6 relative) is the bound instead.
        const double tol = std::max(4 * std::sqrt(var / (n - 1)), 1e-6);
        EXPECT_LE(mean, 1 + tol) << c.name << " wo.z " << wo.z << " channel " << ch;
        if (c.lossless) {
          EXPECT_NEAR(mean, 1.0, tol) << c.name << " wo.z " << wo.z << " channel " << ch;
        }
      }
      ++dirIndex;
    }
  }
}

// The same integral without the BSDF's own sampler, for the non-delta models: cosine-weighted
// directions (and their mirror images below for transmission), f |cos| / pdf. Checks that
// eval() itself, not only sample(), conserves energy (fewer directions: higher variance). For
// the glossy lobe, light arriving along wo: f(wi, wo) (it is not reciprocal).
TEST(BsdfEnergy, EvalIntegratedIndependentlyIsAtMostOne) {
  const int n = 40000;
  for (const Case& c : cases()) {
    if (c.bsdf.isDelta()) continue;
    for (int d = 0; d < 10; ++d) {
      const Vec3 wo = dirWithCos(0.05f + 0.1f * d, 1.3f * d);
      double sum = 0, sum2 = 0;
      for (int i = 0; i < n; ++i) {
        const RngKey key{uint32_t(i), uint32_t(d), 2, 12};
        Vec3 wi = sampleCosineHemisphere(sampleUniform(key, 0), sampleUniform(key, 1));
        float pdf = wi.z * kInvPi;
        if (c.bsdf.transmits()) {
          pdf *= 0.5f;
          if (sampleUniform(key, 2) < 0.5f) wi.z = -wi.z;
        }
        if (!(pdf > 0)) continue;
        const bool lobe = std::holds_alternative<GaussianLobe>(c.bsdf.model());
        const Rgb f = lobe ? c.bsdf.eval(wi, wo) : c.bsdf.eval(wo, wi);
        // Power form for refraction: etaRel = n(wi side) / n(wo side).
        const float eta = c.bsdf.transmits() && wi.z < 0 ? std::get<Dielectric>(c.bsdf.model()).eta : 1.0f;
        const double v = average(f) * std::fabs(wi.z) / pdf * eta * eta;
        sum += v;
        sum2 += v * v;
      }
      const double mean = sum / n, var = std::max(0.0, sum2 / n - mean * mean);
      EXPECT_LE(mean, 1 + 4 * std::sqrt(var / (n - 1))) << c.name << " wo.z " << wo.z;
    }
  }
}

std::vector<Vec3> chi2Directions(bool both) {
  std::vector<Vec3> d = {dirWithCos(0.95f, 0.3f), dirWithCos(0.6f, 1.9f), dirWithCos(0.15f, 4.0f)};
  if (both) { d.push_back(dirWithCos(-0.9f, 0.7f)); d.push_back(dirWithCos(-0.3f, 2.5f)); }
  return d;
}

TEST(BsdfSampling, ChiSquareAgainstPdf) {
  const int n = 200000;
  int tests = 0;
  for (const Case& c : cases())
    if (!c.bsdf.isDelta()) tests += int(chi2Directions(c.bsdf.transmits()).size());
  const double alpha = testing::sidak(0.01, tests);
  for (const Case& c : cases()) {
    if (c.bsdf.isDelta()) continue;
    int di = 0;
    for (Vec3 wo : chi2Directions(c.bsdf.transmits())) {
      const auto r = testing::chi2Test(
          [&](int i, Vec3& d) {
            const RngKey key{uint32_t(i), uint32_t(di), 3, 13};
            BsdfSample s;
            if (!c.bsdf.sample(wo, sampleUniform(key, 0), sampleUniform(key, 1), sampleUniform(key, 2), s) || s.delta)
              return false;
            d = s.wi;
            return true;
          },
          [&](Vec3 wi) { return double(c.bsdf.pdf(wo, wi)); }, n);
      EXPECT_GT(r.pValue, alpha) << c.name << " wo " << wo.x << "," << wo.y << "," << wo.z << " chi2 " << r.chi2
                                 << " dof " << r.dof << " pdf mass " << r.pdfMass;
      ++di;
    }
  }
}

TEST(BsdfSampling, WeightIsEvalCosOverPdf) {
  for (const Case& c : cases()) {
    int checked = 0;
    for (int i = 0; i < 2000; ++i) {
      const RngKey key{uint32_t(i), 0, 4, 14};
      const Vec3 wo = dirWithCos(c.bsdf.transmits() ? 2 * sampleUniform(key, 3) - 1 : sampleUniform(key, 3),
                                 6.28f * sampleUniform(key, 4));
      BsdfSample s;
      if (!c.bsdf.sample(wo, sampleUniform(key, 0), sampleUniform(key, 1), sampleUniform(key, 2), s)) continue;
      EXPECT_NEAR(length(s.wi), 1.0f, 1e-5f) << c.name;
      if (s.delta) continue;
      const float pdf = c.bsdf.pdf(wo, s.wi);
      const Rgb f = c.bsdf.eval(wo, s.wi);
      // Float evaluation of the same quantity by two formulas: agreement to 1e-3 relative.
      EXPECT_NEAR(s.pdf, pdf, 1e-3f * pdf) << c.name;
      const Rgb expect = f * (std::fabs(s.wi.z) / pdf);
      for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(s.weight[ch], expect[ch], 1e-3f * std::max(1.0f, expect[ch])) << c.name;
      ++checked;
    }
    if (!c.bsdf.isDelta()) {
      EXPECT_GT(checked, 500) << c.name;
    }
  }
}

// The glossy lobe's adjoint (light arriving along `in`, leaving along s.wi): the weight is
// f(out, in) |cos θout| / pdf(in, out), with the same density as the camera side's sampler.
TEST(BsdfSampling, GlossyAdjointWeightIsEvalOfTheReversedPairCosOverPdf) {
  for (const GaussianLobe g : {GaussianLobe{{1, 1, 1}, 0.1f}, GaussianLobe{{0.9f, 0.8f, 0.7f}, 0.5f}}) {
    int checked = 0;
    for (int i = 0; i < 2000; ++i) {
      const RngKey key{uint32_t(i), 0, 4, 19};
      const Vec3 in = dirWithCos(sampleUniform(key, 3), 6.28f * sampleUniform(key, 4));
      BsdfSample s;
      if (!Bsdf(g).sampleAdjoint(in, sampleUniform(key, 0), sampleUniform(key, 1), sampleUniform(key, 2), s)) continue;
      const float pdf = g.pdf(in, s.wi);
      EXPECT_NEAR(s.pdf, pdf, 1e-3f * pdf);
      const Rgb expect = g.eval(s.wi, in) * (s.wi.z / pdf);
      for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(s.weight[ch], expect[ch], 1e-3f * std::max(1.0f, expect[ch]));
      ++checked;
    }
    EXPECT_GT(checked, 500);
  }
}

TEST(BsdfReciprocity, ModelsThatClaimIt) {
  for (const Case& c : cases()) {
    if (c.bsdf.isDelta() || std::holds_alternative<GaussianLobe>(c.bsdf.model())) continue;
    for (int i = 0; i < 2000; ++i) {
      const RngKey key{uint32_t(i), 0, 5, 15};
      const bool t = c.bsdf.transmits();
      const Vec3 a = dirWithCos(t ? 2 * sampleUniform(key, 0) - 1 : sampleUniform(key, 0), 6.28f * sampleUniform(key, 1));
      const Vec3 b = dirWithCos(t ? 2 * sampleUniform(key, 2) - 1 : sampleUniform(key, 2), 6.28f * sampleUniform(key, 3));
      Rgb fab = c.bsdf.eval(a, b), fba = c.bsdf.eval(b, a);
      if (t && a.z * b.z < 0) {
        // Generalised reciprocity f(a, b) / n(a)² = f(b, a) / n(b)².
        const float eta = std::get<Dielectric>(c.bsdf.model()).eta;
        const float na = a.z > 0 ? 1 : eta, nb = b.z > 0 ? 1 : eta;
        fab = fab / (na * na);
        fba = fba / (nb * nb);
      }
      for (int ch = 0; ch < 3; ++ch)
        EXPECT_NEAR(fab[ch], fba[ch], 1e-4f * std::max({1.0f, fab[ch], fba[ch]})) << c.name << " " << i;
    }
  }
}

TEST(BsdfReciprocity, GaussianLobeRatioIsCosineRatio) {
  // Not reciprocal: f(wo, wi) / f(wi, wo) = cos θi / cos θo (the cosine divides by θo's).
  const GaussianLobe g{{1, 1, 1}, 0.3f};
  for (int i = 0; i < 1000; ++i) {
    const RngKey key{uint32_t(i), 0, 6, 16};
    const Vec3 a = dirWithCos(sampleUniform(key, 0), 6.28f * sampleUniform(key, 1));
    const Vec3 b = dirWithCos(sampleUniform(key, 2), 6.28f * sampleUniform(key, 3));
    const float fab = g.eval(a, b).x, fba = g.eval(b, a).x;
    EXPECT_NEAR(fab * a.z, fba * b.z, 1e-4f * std::max(1.0f, fab * a.z)) << i;
  }
}

TEST(BsdfSmooth, DielectricFollowsFresnelAndSnell) {
  const float eta = 1.5f;
  const Dielectric d{eta, 0};
  EXPECT_NEAR(fresnelDielectric(1, eta), 0.04f, 1e-6f);
  for (float c : {1.0f, 0.7f, 0.2f, 0.01f}) {
    const Vec3 wo = dirWithCos(c, 0.4f);
    const float r = fresnelDielectric(c, eta);
    BsdfSample s;
    // uc below R reflects, above refracts, each with weight 1 (power form).
    ASSERT_TRUE(d.sample(wo, 0.5f, 0.5f, 0.999f * r, s));
    EXPECT_TRUE(s.delta);
    EXPECT_NEAR(s.wi.z, wo.z, 1e-6f);
    EXPECT_FLOAT_EQ(s.weight.x, 1.0f);
    ASSERT_TRUE(d.sample(wo, 0.5f, 0.5f, r + 0.5f * (1 - r), s));
    EXPECT_LT(s.wi.z, 0);
    const float sinI = std::sqrt(1 - c * c), sinT = std::sqrt(1 - s.wi.z * s.wi.z);
    EXPECT_NEAR(sinT * eta, sinI, 1e-5f);
    EXPECT_NEAR(s.weight.x * s.etaRel * s.etaRel, 1.0f, 1e-5f);
    EXPECT_NEAR(dot(Vec3{wo.x, wo.y, 0}, Vec3{s.wi.x, s.wi.y, 0}), -sinI * sinT, 1e-5f) << "in the plane of incidence";
  }
  // Total internal reflection from inside beyond the critical angle: always reflects.
  const float critical = 1 / eta;
  const Vec3 inside = dirWithCos(-std::sqrt(1 - (critical + 0.1f) * (critical + 0.1f)), 1.0f);
  EXPECT_EQ(fresnelDielectric(inside.z, eta), 1.0f);
  for (float uc : {0.0f, 0.5f, 0.99999994f}) {
    BsdfSample s;
    ASSERT_TRUE(d.sample(inside, 0.5f, 0.5f, uc, s));
    EXPECT_NEAR(s.wi.z, inside.z, 1e-6f);
    EXPECT_EQ(s.weight.x, 1.0f);
  }
  // Rough: TIR from inside (0.1 beyond the critical sine, > 20 alpha of microfacet tilt),
  // nothing is transmitted as the roughness goes to 0.
  const Dielectric rough{eta, 0.002f};
  int transmitted = 0;
  for (int i = 0; i < 1000; ++i) {
    const RngKey key{uint32_t(i), 0, 7, 17};
    BsdfSample s;
    if (rough.sample(inside, sampleUniform(key, 0), sampleUniform(key, 1), sampleUniform(key, 2), s) && s.wi.z > 0)
      ++transmitted;
  }
  EXPECT_EQ(transmitted, 0);
}

TEST(BsdfSmooth, ConductorAndLobeAreMirrors) {
  const Conductor c{{0.2f, 0.92f, 1.1f}, {3.9f, 2.45f, 2.14f}, 0};
  // Normal incidence: |(n - 1 + ik) / (n + 1 + ik)|².
  const float n = 0.2f, k = 3.9f;
  EXPECT_NEAR(fresnelConductor(1, n, k), ((n - 1) * (n - 1) + k * k) / ((n + 1) * (n + 1) + k * k), 1e-5f);
  // A conductor with k = 0 is a dielectric.
  for (float cs : {1.0f, 0.5f, 0.1f}) EXPECT_NEAR(fresnelConductor(cs, 1.5f, 0), fresnelDielectric(cs, 1.5f), 1e-5f);
  const Vec3 wo = dirWithCos(0.3f, 2.0f);
  BsdfSample s;
  ASSERT_TRUE(c.sample(wo, 0.2f, 0.7f, 0.1f, s));
  EXPECT_TRUE(s.delta);
  EXPECT_NEAR(s.wi.x, -wo.x, 1e-6f);
  EXPECT_NEAR(s.weight.y, fresnelConductor(0.3f, 0.92f, 2.45f), 1e-6f);
  const GaussianLobe g{{0.7f, 0.7f, 0.7f}, 0.0005f};
  ASSERT_TRUE(g.sample(wo, 0.2f, 0.7f, 0.1f, s));
  EXPECT_TRUE(s.delta);
  EXPECT_EQ(s.weight.x, 0.7f);
  // A narrow (non-delta) lobe converges to the mirror: the flux weight of every sample (the
  // adjoint's) is within ρ (1 - σ²/6)-ish of ρ, and all samples are within a few σ of the
  // mirror direction. The camera side's weight is that times cos θi / cos θo, which tends to 1
  // with the sample's angle φ ≤ 6σ from the mirror: |cos θi - cos θo| ≤ φ sin θo + φ²/2.
  const GaussianLobe narrow{{1, 1, 1}, 0.002f};
  const Vec3 at = dirWithCos(0.5f, 0);
  const float phiMax = 6 * 0.002f, ratioBound = (phiMax * std::sqrt(0.75f) + phiMax * phiMax / 2) / 0.5f;
  for (int i = 0; i < 100; ++i) {
    const RngKey key{uint32_t(i), 0, 8, 18};
    ASSERT_TRUE(narrow.sampleAdjoint(at, sampleUniform(key, 0), sampleUniform(key, 1), 0, s));
    EXPECT_LT(angleBetween(s.wi, mirrorLocal(at)), phiMax);
    EXPECT_GT(s.weight.x, 1 - 1e-4f);
    EXPECT_LE(s.weight.x, 1.0f);
    BsdfSample camera;
    ASSERT_TRUE(narrow.sample(at, sampleUniform(key, 0), sampleUniform(key, 1), 0, camera));
    EXPECT_EQ(camera.wi, s.wi);  // one sampler: the same direction
    EXPECT_FLOAT_EQ(camera.weight.x, s.weight.x * (camera.wi.z / at.z));
    EXPECT_NEAR(camera.weight.x, 1.0f, ratioBound + 1e-4f);
  }
}

TEST(BsdfEdges, NoNaNAtGrazingDegenerateAndExtremeParameters) {
  std::vector<Bsdf> models;
  for (const Case& c : cases()) models.push_back(c.bsdf);
  for (float a : {0.0f, 1e-4f, Ggx::kSmoothAlpha, 0.999f, 1.0f}) {
    models.push_back(Conductor{{0.2f, 0.9f, 1.1f}, {3.9f, 2.4f, 2.1f}, a});
    for (float eta : {1.0f, 1.0f + 1e-6f, 1.0f - 1e-6f, 1.5f, 1e-3f, 10.0f}) models.push_back(Dielectric{eta, a});
  }
  models.push_back(Plastic::make({0, 0, 0}, 1.0f));
  models.push_back(Plastic::make({1, 1, 1}, 3.0f));
  models.push_back(Phong{{0, 0, 0}, {0, 0, 0}, 1});
  models.push_back(Phong{{0, 0, 0}, {1, 1, 1}, 1e5f});
  models.push_back(GaussianLobe{{1, 1, 1}, 1.0f});
  models.push_back(GaussianLobe{{1, 1, 1}, GaussianLobe::kSmoothSigma});
  const std::vector<Vec3> dirs = {{0, 0, 1},     {0, 0, -1},  {1, 0, 0},           {0, 1, 0},
                                  normalize(Vec3{1, 0, 1e-7f}), normalize(Vec3{1, 0, -1e-7f}),
                                  normalize(Vec3{1, 1, 1}),     normalize(Vec3{-1, 0.5f, -0.2f})};
  const float us[] = {0.0f, 1e-7f, 0.5f, 0.99999994f};
  for (const Bsdf& b : models)
    for (Vec3 wo : dirs) {
      for (Vec3 wi : dirs) {
        for (Vec3 w : {wi, -wi, wo, -wo, mirrorLocal(wo)}) {
          const Rgb f = b.eval(wo, w);
          const float p = b.pdf(wo, w);
          ASSERT_TRUE(isFinite(f) && f.x >= 0 && f.y >= 0 && f.z >= 0) << b.model().index() << " wo.z " << wo.z;
          ASSERT_TRUE(std::isfinite(p) && p >= 0) << b.model().index() << " wo.z " << wo.z;
        }
      }
      for (float u1 : us)
        for (float u2 : us)
          for (float uc : us) {
            BsdfSample s;
            if (!b.sample(wo, u1, u2, uc, s)) continue;
            ASSERT_TRUE(isFinite(s.wi) && isFinite(s.weight) && std::isfinite(s.pdf) && std::isfinite(s.etaRel))
                << b.model().index() << " wo " << wo.x << "," << wo.z << " u " << u1 << "," << u2 << "," << uc;
            ASSERT_TRUE(s.weight.x >= 0 && s.weight.y >= 0 && s.weight.z >= 0 && s.pdf > 0);
          }
    }
}

}  // namespace
}  // namespace rayes

namespace rayes {
namespace {
// The χ² machinery itself: a sampler with the wrong density must be rejected decisively.
TEST(Chi2Test, RejectsWrongDensities) {
  auto cosineSampler = [](int i, Vec3& d) {
    const RngKey key{uint32_t(i), 0, 9, 19};
    d = sampleCosineHemisphere(sampleUniform(key, 0), sampleUniform(key, 1));
    return true;
  };
  auto cosPow = [](double n) {
    return [n](Vec3 w) { return w.z > 0 ? (n + 1) / (2 * std::numbers::pi) * std::pow(double(w.z), n) : 0.0; };
  };
  EXPECT_GT(testing::chi2Test(cosineSampler, cosPow(1.0), 200000).pValue, 1e-3);
  EXPECT_LT(testing::chi2Test(cosineSampler, cosPow(0.0), 200000).pValue, 1e-9);
  EXPECT_LT(testing::chi2Test(cosineSampler, cosPow(1.05), 200000).pValue, 1e-3);
}
}  // namespace
}  // namespace rayes
