// Procedural textures filtered over the footprint (shading/texture.cpp): the checkerboard's
// exact box filter, the noise's octaves faded above the footprint's frequency; a zero footprint
// is the point sample bit for bit. And the test: a footprint-filtered checkerboard on a
// plane seen at grazing angles converges to the box-filtered reference (each pixel's preimage
// integrated), within the render's standard error plus the filter's analytic bound, where the
// point-sampled render at the same samples per pixel does not (it aliases); close to the camera,
// where a check covers many pixels, the filtered contrast is the reference's (no over-blur).
#include <cmath>
#include <vector>
#include <gtest/gtest.h>
#include "core/rng.h"
#include "shading/camera.h"
#include "shading/footprint.h"
#include "shading/texture.h"
#include "support/grazing_checker.h"

namespace rayes {
namespace {
using namespace test;

Texture checker(float scale) { return checkerTexture(scale); }

// The mean of (-1)^floor(t) over [x - h, x + h] by the midpoint rule with n points: the
// integrand is ±1 with at most 2h + 1 jumps, each spoiling one interval of width 2h / n, so the
// rule errs by at most (2h + 1) * 2 / n.
double squareWaveMeanNumeric(double x, double h, int n) {
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    const double t = x - h + (i + 0.5) * 2 * h / n;
    sum += std::fmod(std::fabs(std::floor(t)), 2.0) >= 1.0 ? -1.0 : 1.0;
  }
  return sum / n;
}

TEST(TextureFilter, SquareWaveMeanIsTheIntegral) {
  const int n = 1 << 20;
  for (const double x : {0.0, 0.3, 1.7, -2.25, 1000.5})
    for (const double h : {0.01, 0.2, 0.5, 0.99, 1.0, 3.3, 17.0}) {
      const double bound = (2 * h + 1) * 2.0 / n;
      EXPECT_NEAR(Texture::squareWaveMean(x, h), squareWaveMeanNumeric(x, h, n), bound) << x << " " << h;
    }
}

TEST(TextureFilter, SquareWaveMeanAtItsEdges) {
  EXPECT_EQ(Texture::squareWaveMean(0.5, 0.0), 1.0);
  EXPECT_EQ(Texture::squareWaveMean(1.5, 0.0), -1.0);
  EXPECT_EQ(Texture::squareWaveMean(1.5, 0.25), -1.0);  // inside one cell
  EXPECT_EQ(Texture::squareWaveMean(1.0, 1.0), 0.0);    // [0, 2]: one period
  EXPECT_NEAR(Texture::squareWaveMean(0.0, 1e30), 0.0, 1e-29);
  EXPECT_TRUE(std::isfinite(Texture::squareWaveMean(0.5, INFINITY)));
  EXPECT_TRUE(std::isfinite(Texture::squareWaveMean(1e30, 1e-30)));
  EXPECT_TRUE(std::isfinite(Texture::squareWaveMean(0.5, 1e-300)));
}

TEST(TextureFilter, AZeroFootprintIsThePointSampleBitForBit) {
  const Texture t = checker(3);
  for (float u = -1.3f; u < 1.3f; u += 0.0731f)
    for (float v = -1.3f; v < 1.3f; v += 0.0917f) {
      TextureQuery q = TextureQuery::at(u, v);
      const float x = std::floor(u * 3), y = std::floor(v * 3);
      const bool odd = std::fmod(std::fabs(x + y), 2.0f) >= 1.0f;
      EXPECT_EQ(t.eval(q).x, odd ? 1.0f : 0.0f);
      // A footprint inside one check gives the same colour.
      q.patch.dxA = 1e-6f;
      q.patch.dyB = 1e-6f;
      if (std::floor(u * 3 - 1.5e-6f) == x && std::floor(u * 3 + 1.5e-6f) == x &&
          std::floor(v * 3 - 1.5e-6f) == y && std::floor(v * 3 + 1.5e-6f) == y) {
        EXPECT_EQ(t.eval(q).x, odd ? 1.0f : 0.0f);
      }
    }
  // The noise too.
  for (float x = 0; x < 3; x += 0.37f) EXPECT_EQ(Texture::noise(x, 0.3f * x, 5, 0.0f), Texture::noise(x, 0.3f * x, 5));
}

TEST(TextureFilter, ACheckerboardFootprintCoveringManyChecksIsGrey) {
  const Texture t = checker(1);
  TextureQuery q = TextureQuery::at(0.37f, 0.61f);
  q.patch.dxA = 1000;
  q.patch.dyB = 1000;
  // The mean over a 1000 x 1000 box: within 1 / 1000 of each axis's half.
  EXPECT_NEAR(t.eval(q).x, 0.5f, 1e-3f);
  q.patch.dxA = INFINITY;
  EXPECT_TRUE(std::isfinite(t.eval(q).x));
}

TEST(TextureFilter, NoiseFadesItsFineOctavesToTheirMean) {
  // Over a footprint wider than the coarsest lattice, every octave is its mean: 0.5.
  EXPECT_EQ(Texture::noise(0.3f, 0.7f, 6, 2.0f), 0.5f);
  // The spread of the values falls as the footprint grows (fewer octaves left).
  auto spread = [](float width) {
    double s = 0, s2 = 0;
    const int n = 4000;
    for (int i = 0; i < n; ++i) {
      const double v = Texture::noise(0.173f * float(i), 0.311f * float(i), 8, width);
      s += v;
      s2 += v * v;
    }
    return std::sqrt(std::max(0.0, s2 / n - (s / n) * (s / n)));
  };
  EXPECT_GT(spread(0.0f), spread(0.3f));
  EXPECT_GT(spread(0.3f), spread(0.9f));
  EXPECT_TRUE(std::isfinite(Texture::noise(0.3f, 0.7f, 6, INFINITY)));
  EXPECT_TRUE(std::isfinite(Texture::noise(0.3f, 0.7f, 6, 1e-38f)));
}

// The tolerance of a filtered pixel: four standard errors of its samples (the iid estimate, an
// upper bound for stratified ones; zero for one sample), the reference's own error bound, and
// the filter's bias against the pixel's box: at most E_k(|zx| + |zy|) (PixelEstimate::
// filterBias), and where the footprint covers many checks at most how far its lookups can stray
// from grey plus how far the reference does (|mean - ref| <= mean |w - 1/2| + |ref - 1/2|).
double tolerance(const PixelEstimate& f, double ref, double refBound) {
  return 4 * f.standardError + refBound + std::min(f.filterBias, f.attenuation + std::fabs(ref - 0.5));
}

struct ImageErrors {
  int filteredOutside = 0, pointOutside = 0;
  double filteredRmse = 0, pointRmse = 0;
};

ImageErrors renderAgainstReference(int strata) {
  const Ground g;
  const Texture tex = checker(2000);
  ImageErrors e;
  for (int j = 0; j < kH; ++j)
    for (int i = 0; i < kW; ++i) {
      double refBound;
      const double ref = referenceWeight(g, i, j, refBound);
      const PixelEstimate f = renderPixel(g, tex, i, j, strata, true);
      const PixelEstimate p = renderPixel(g, tex, i, j, strata, false);
      const double tau = tolerance(f, ref, refBound);
      e.filteredOutside += std::fabs(f.mean - ref) > tau;
      e.pointOutside += std::fabs(p.mean - ref) > tau;
      EXPECT_LE(std::fabs(f.mean - ref), tau) << strata * strata << " spp, pixel " << i << ", " << j;
      e.filteredRmse += (f.mean - ref) * (f.mean - ref);
      e.pointRmse += (p.mean - ref) * (p.mean - ref);
    }
  e.filteredRmse = std::sqrt(e.filteredRmse / (kW * kH));
  e.pointRmse = std::sqrt(e.pointRmse / (kW * kH));
  return e;
}

// Every pixel within its tolerance at 1, 4, 16 and 64 spp; the error falls with the samples
// and stays below the point samples' at each count.
TEST(TextureFilter, GrazingCheckerboardConvergesToTheBoxFilteredReference) {
  double previous = 1;
  for (const int strata : {1, 2, 4, 8}) {
    const ImageErrors e = renderAgainstReference(strata);
    EXPECT_EQ(e.filteredOutside, 0) << strata * strata << " spp";
    EXPECT_LT(e.filteredRmse, e.pointRmse) << strata * strata << " spp";
    EXPECT_LT(e.filteredRmse, previous) << strata * strata << " spp";
    previous = e.filteredRmse;
  }
}

// At one sample per pixel the point samples alias: far rows, whose pixels hold tens of checks,
// come out black or white where the reference is grey, outside what the filtered render keeps to.
TEST(TextureFilter, PointSamplesAliasWhereTheFilteredRenderDoesNot) {
  const ImageErrors e = renderAgainstReference(1);
  EXPECT_EQ(e.filteredOutside, 0);
  EXPECT_GT(e.pointOutside, kW * kH / 20);
  EXPECT_LT(e.filteredRmse, 0.5 * e.pointRmse);
}

// Near the camera (the bottom rows: a check covers several pixels) the filtered render keeps the
// reference's contrast, the mean of |2 w - 1| over the pixels (1: every pixel inside one check),
// to within the filter's bias bound: the footprint does not blur more than its own reach.
TEST(TextureFilter, NearTheCameraTheFilteredContrastIsTheReferences) {
  const Ground g;
  const Texture tex = checker(2000);
  double contrastRef = 0, contrastFiltered = 0, allowed = 0;
  int n = 0;
  for (int j = kH - 4; j < kH; ++j)
    for (int i = 0; i < kW; ++i) {
      double refBound;
      const double ref = referenceWeight(g, i, j, refBound);
      const PixelEstimate f = renderPixel(g, tex, i, j, 4, true);
      contrastRef += std::fabs(2 * ref - 1);
      contrastFiltered += std::fabs(2 * f.mean - 1);
      allowed += 2 * (f.filterBias + refBound);
      ++n;
    }
  EXPECT_GT(contrastRef / n, 0.8);  // most of these pixels lie inside one check
  EXPECT_GE(contrastFiltered / n, contrastRef / n - allowed / n);
}

}  // namespace
}  // namespace rayes
