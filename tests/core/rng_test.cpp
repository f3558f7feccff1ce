// Random numbers (core/rng.h, core/sobol.h). The renderer's sampler is scrambled Sobol: the
// raw sequence is Sobol's, every power-of-two block of a pixel's samples is a net after
// scrambling and shuffling, values are uniform in [0, 1) and decorrelated across pixels,
// bounces and dimensions, and integrals converge faster than with independent samples. The
// independent sampler stays a pure function of its key, uniform in [0, 1).
#include <cmath>
#include <numbers>
#include <vector>
#include <gtest/gtest.h>
#include "core/rng.h"

namespace rayes {
namespace {

// Upper quantile of the chi-square distribution with k degrees of freedom at the standard
// normal quantile z (Wilson and Hilferty 1931; relative error below 1 % for k >= 30).
double chiSquareQuantile(double k, double z) {
  const double c = 2.0 / (9.0 * k);
  return k * std::pow(1.0 - c + z * std::sqrt(c), 3.0);
}
constexpr double kZ1e6 = 4.753;  // P(N(0,1) > z) = 1e-6: the false-alarm rate of each check

// Pearson's chi-square of counts against equal expected counts.
double chiSquare(const std::vector<int>& counts, double total) {
  const double expected = total / double(counts.size());
  double x2 = 0;
  for (int c : counts) x2 += (c - expected) * (c - expected) / expected;
  return x2;
}

double correlation(const std::vector<double>& a, const std::vector<double>& b) {
  const double n = double(a.size());
  double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    sa += a[i], sb += b[i], saa += a[i] * a[i], sbb += b[i] * b[i], sab += a[i] * b[i];
  }
  const double cov = sab / n - sa / n * (sb / n);
  return cov / std::sqrt((saa / n - sa / n * (sa / n)) * (sbb / n - sb / n * (sb / n)));
}

TEST(Rng, FloatsAreBuiltFromTheTop24BitsAndStayBelowOne) {
  EXPECT_LT(bitsToUnitFloat(~uint64_t(0)), 1.0f);
  EXPECT_EQ(bitsToUnitFloat(0), 0.0f);
  EXPECT_LT(fixedToUnitFloat(0xFFFFFFFFu), 1.0f);
  EXPECT_EQ(fixedToUnitFloat(0x80000000u), 0.5f);
  // The float-from-32-bits pitfall (docs/design.md): v * 2^-32 rounds to 1.0f for v >= 0xFFFFFF80.
  EXPECT_EQ(static_cast<float>(0xFFFFFF80u * (1.0 / 4294967296.0)), 1.0f);
}

TEST(Sobol, UnscrambledPointsAreTheKnownSobolSequence) {
  // Natural (not Gray-code) order; dimension 1 has direction numbers 1/2, 3/4, 5/8, 15/16, 17/32.
  const double x[8] = {0, 0.5, 0.25, 0.75, 0.125, 0.625, 0.375, 0.875};
  const double y[8] = {0, 0.5, 0.75, 0.25, 0.625, 0.125, 0.375, 0.875};
  for (uint32_t i = 0; i < 8; ++i) {
    EXPECT_EQ(sobolPoint(i, 0) * 0x1p-32, x[i]) << i;
    EXPECT_EQ(sobolPoint(i, 1) * 0x1p-32, y[i]) << i;
  }
  EXPECT_EQ(kSobolPascalColumns[3], 0xF0000000u);
  EXPECT_EQ(kSobolPascalColumns[4], 0x88000000u);
  EXPECT_EQ(kSobolPascalColumns[31], 0xFFFFFFFFu);  // row 31 of Pascal's triangle is all odd
  // The fast form equals the matrix product. Both are linear over GF(2), so agreeing on the 32
  // single bits proves it for every index; random indices check the linearity of the fast form.
  for (uint32_t i = 0; i < 100000; ++i) {
    const uint32_t index = i < 32 ? 1u << i : uint32_t(mix64(i));
    ASSERT_EQ(sobolPoint(index, 1), sobolPascalProduct(index)) << index;
  }
  EXPECT_EQ(reverseBits(1u), 0x80000000u);
  EXPECT_EQ(reverseBits(0x12345678u), 0x1E6A2C48u);
}

TEST(Sobol, NestedScrambleKeepsEveryTopBitPrefixAFunctionOfTheInputsPrefix) {
  for (uint32_t seed : {0u, 1u, 0xdeadbeefu}) {
    // Inputs equal in their top j bits give outputs equal in their top j bits, for every j.
    for (uint32_t i = 0; i < 20000; ++i) {
      const uint32_t x = uint32_t(mix64(i)), j = i % 32, low = j == 0 ? ~0u : (1u << (32 - j)) - 1;
      const uint32_t y = x ^ (uint32_t(mix64(i + 7777)) & low);
      const uint32_t fx = nestedUniformScramble(x, seed), fy = nestedUniformScramble(y, seed);
      ASSERT_EQ((fx ^ fy) & ~low, 0u) << i;
    }
    // So the top 16 bits of the output are a function of the top 16 of the input: a bijection.
    std::vector<char> seen(1 << 16, 0);
    for (uint32_t top = 0; top < (1u << 16); ++top) {
      const uint32_t y = nestedUniformScramble(top << 16 | uint32_t(mix64(top) & 0xffff), seed) >> 16;
      ASSERT_FALSE(seen[y]) << top;
      seen[y] = 1;
    }
  }
}

// Every elementary interval [a 2^-i, (a+1) 2^-i) x [b 2^-(k-i), (b+1) 2^-(k-i)) holds exactly one
// of the 2^k points, for every shape i = 0..k.
bool isZeroKTwoNet(const std::vector<Sample2D>& pts, int k) {
  for (int i = 0; i <= k; ++i) {
    std::vector<int> cells(size_t(1) << k, 0);
    for (const Sample2D& p : pts) {
      const uint32_t a = uint32_t(std::ldexp(p.u, i)), b = uint32_t(std::ldexp(p.v, k - i));
      if (++cells[size_t(a) << (k - i) | b] > 1) return false;
    }
  }
  return true;
}

TEST(Sobol, EveryPowerOfTwoBlockOfAPixelsSamplesIsANetAfterScrambling) {
  // Blocks [2^k, 2^(k+1)) are the renderer's passes (1, 1, 2, 4, ... samples); blocks from 0
  // are the prefixes a progressive render has after each pass.
  const int kMax = 10;
  for (uint32_t pixel : {0u, 1u, 77777u}) {
    for (uint32_t bounce : {0u, 3u}) {
      for (uint32_t dim : {0u, 5u}) {
        for (uint64_t seed : {0ull, 42ull}) {
          for (int k = 0; k <= kMax; ++k) {
            for (uint32_t first : {0u, 1u << k, 3u << k}) {
              std::vector<Sample2D> pts;
              std::vector<int> strata(size_t(1) << k, 0);
              for (uint32_t s = first; s < first + (1u << k); ++s) {
                const RngKey key{pixel, s, bounce, seed};
                pts.push_back(sample2D(key, dim));
                ++strata[size_t(std::ldexp(sample1D(key, dim + 1), k))];
              }
              ASSERT_TRUE(isZeroKTwoNet(pts, k)) << pixel << " " << bounce << " " << dim << " " << k << " " << first;
              for (int c : strata) ASSERT_EQ(c, 1) << "1D " << pixel << " " << k << " " << first;
            }
          }
        }
      }
    }
  }
}

TEST(Sobol, ValuesAreInTheUnitIntervalAndAPureFunctionOfTheKey) {
  static_assert(sample1D(RngKey{3, 9, 1, 7}, 4) == sample1D(RngKey{3, 9, 1, 7}, 4));  // constexpr: no state
  const RngKey a{12, 3, 1, 0};
  EXPECT_NE(sample1D(a, 5), sample1D(a, 6));
  EXPECT_NE(sample1D(a, 5), sample1D(RngKey{12, 4, 1, 0}, 5));
  EXPECT_NE(sample1D(a, 5), sample1D(RngKey{13, 3, 1, 0}, 5));
  EXPECT_NE(sample1D(a, 5), sample1D(RngKey{12, 3, 2, 0}, 5));
  EXPECT_NE(sample1D(a, 5), sample1D(RngKey{12, 3, 1, 9}, 5));
  for (uint32_t i = 0; i < 100000; ++i) {
    const RngKey k{i % 97, i, i % 5, i};
    const Sample2D p = sample2D(k, i % 7);
    const float u = sample1D(k, i % 11);
    ASSERT_TRUE(p.u >= 0 && p.u < 1 && p.v >= 0 && p.v < 1 && u >= 0 && u < 1) << i;
  }
}

TEST(Sobol, MarginalsOverPixelsPassAChiSquareTest) {
  // For one sample index the pixels' scrambles are independent: the values of many pixels must
  // be uniform in 1D and jointly in 2D.
  const int pixels = 1 << 15, bins = 64;
  const double limit = chiSquareQuantile(bins - 1, kZ1e6);
  for (uint32_t sample : {0u, 1u, 6u, 1000u}) {
    std::vector<int> u(bins, 0), v(bins, 0), w(bins, 0), joint(bins, 0);
    for (uint32_t p = 0; p < uint32_t(pixels); ++p) {
      const RngKey key{p, sample, 2, 1};
      const Sample2D s = sample2D(key, 3);
      ++u[int(s.u * bins)], ++v[int(s.v * bins)], ++w[int(sample1D(key, 2) * bins)];
      ++joint[int(s.u * 8) * 8 + int(s.v * 8)];
    }
    EXPECT_LT(chiSquare(u, pixels), limit) << sample;
    EXPECT_LT(chiSquare(v, pixels), limit) << sample;
    EXPECT_LT(chiSquare(w, pixels), limit) << sample;
    EXPECT_LT(chiSquare(joint, pixels), limit) << sample;
  }
}

TEST(Sobol, PixelsBouncesAndDimensionsAreDecorrelated) {
  // The correlation coefficient of n independent pairs has standard error 1/sqrt(n).
  const int n = 1 << 14;
  const double bound = 4 / std::sqrt(double(n));
  std::vector<double> a(n), neighbour(n), otherDim(n), otherBounce(n), otherSeed(n), v(n);
  for (uint32_t p = 0; p < uint32_t(n); ++p) {
    const RngKey key{p, 5, 1, 3};
    a[p] = sample2D(key, 3).u;
    v[p] = sample2D(key, 3).v;
    neighbour[p] = sample2D(RngKey{p + 1, 5, 1, 3}, 3).u;
    otherDim[p] = sample2D(key, 5).u;
    otherBounce[p] = sample2D(RngKey{p, 5, 2, 3}, 3).u;
    otherSeed[p] = sample2D(RngKey{p, 5, 1, 4}, 3).u;
  }
  EXPECT_LT(std::fabs(correlation(a, neighbour)), bound);
  EXPECT_LT(std::fabs(correlation(a, otherDim)), bound);
  EXPECT_LT(std::fabs(correlation(a, otherBounce)), bound);
  EXPECT_LT(std::fabs(correlation(a, otherSeed)), bound);
  EXPECT_LT(std::fabs(correlation(a, v)), bound);

  // Within one pixel, over its samples: different dimensions (their own shuffles) and one
  // dimension at consecutive bounces must not move together.
  for (uint32_t pixel : {0u, 12345u}) {
    std::vector<double> light(n), bsdf(n), pick(n), next(n);
    for (uint32_t s = 0; s < uint32_t(n); ++s) {
      const RngKey key{pixel, s, 1, 3};
      light[s] = sample2D(key, 3).u;
      bsdf[s] = sample2D(key, 5).u;
      pick[s] = sample1D(key, 2);
      next[s] = sample2D(RngKey{pixel, s, 2, 3}, 3).u;
    }
    EXPECT_LT(std::fabs(correlation(light, bsdf)), bound) << pixel;
    EXPECT_LT(std::fabs(correlation(light, pick)), bound) << pixel;
    EXPECT_LT(std::fabs(correlation(light, next)), bound) << pixel;
  }
}

// RMSE over `pixels` independent scrambles of the n-sample estimate of the integral of f.
template <class F>
double rmseOfScrambledSobol(F f, double integral, int n, int pixels) {
  double se = 0;
  for (uint32_t p = 0; p < uint32_t(pixels); ++p) {
    double sum = 0;
    for (uint32_t s = 0; s < uint32_t(n); ++s) {
      const Sample2D x = sample2D(RngKey{p, s, 0, 0}, 0);
      sum += f(x.u, x.v);
    }
    se += (sum / n - integral) * (sum / n - integral);
  }
  return std::sqrt(se / pixels);
}

TEST(Sobol, IntegratesFasterThanIndependentSamples) {
  // Independent samples have standard error sigma / sqrt(n). Scrambled (0,m,2)-nets have RMSE
  // O(n^-1.5) (up to log factors) for smooth integrands and O(n^-0.75) for a discontinuity along
  // a smooth curve (Owen 1997; Burley 2020, figure 9). At n = 1 both are one uniform point, so
  // with equal constants the ratio at n = 256 would be n^-1 = 1/256 (smooth) and n^-0.25 = 1/4
  // (discontinuous). The test asks for the square root of those factors, 1/16 and 1/2: the rest
  // is left to the constants and log factors, and independent sampling could not pass (its RMSE
  // estimate over 256 pixels is within 20 % of sigma / sqrt(n) at 4 standard errors).
  const int n = 256, pixels = 256;
  const double pi = std::numbers::pi;
  auto smooth = [&](double x, double y) { return pi * pi / 4 * std::sin(pi * x) * std::sin(pi * y); };
  const double sigmaSmooth = std::sqrt(std::pow(pi, 4) / 64 - 1);  // E f^2 = pi^4/16 * 1/4
  auto disk = [](double x, double y) { return x * x + y * y < 1 ? 1.0 : 0.0; };
  const double sigmaDisk = std::sqrt(pi / 4 * (1 - pi / 4));

  const double smoothRmse = rmseOfScrambledSobol(smooth, 1.0, n, pixels);
  const double diskRmse = rmseOfScrambledSobol(disk, pi / 4, n, pixels);
  EXPECT_LT(smoothRmse, sigmaSmooth / std::sqrt(n) / 16);
  EXPECT_LT(diskRmse, sigmaDisk / std::sqrt(n) / 2);

  // The rate itself: from n = 16 to 256 the smooth error falls by more than 16^1 (independent:
  // 16^0.5 = 4), the discontinuous one by more than 16^0.5.
  EXPECT_GT(rmseOfScrambledSobol(smooth, 1.0, 16, pixels) / smoothRmse, 16);
  EXPECT_GT(rmseOfScrambledSobol(disk, pi / 4, 16, pixels) / diskRmse, 4);
}

TEST(IndependentRng, SameKeySameValueDifferentKeysDiffer) {
  const RngKey a{12, 3, 1, 0};
  EXPECT_EQ(sampleUniform(a, 5), sampleUniform(a, 5));
  EXPECT_NE(sampleUniform(a, 5), sampleUniform(a, 6));
  EXPECT_NE(sampleUniform(a, 5), sampleUniform(RngKey{12, 4, 1, 0}, 5));
  EXPECT_NE(sampleUniform(a, 5), sampleUniform(RngKey{12, 3, 2, 0}, 5));
  EXPECT_NE(sampleUniform(a, 5), sampleUniform(RngKey{12, 3, 1, 9}, 5));
}

TEST(IndependentRng, UniformByChiSquareAndUncorrelatedAcrossSamples) {
  const int n = 1 << 16, bins = 64;
  std::vector<int> counts(bins, 0);
  std::vector<double> a(n), b(n);
  for (uint32_t i = 0; i < uint32_t(n); ++i) {
    a[i] = sampleUniform(RngKey{7, i, 0, 1}, 0);
    b[i] = sampleUniform(RngKey{7, i + 1, 0, 1}, 0);
    ASSERT_TRUE(a[i] >= 0 && a[i] < 1);
    ++counts[int(a[i] * bins)];
  }
  EXPECT_LT(chiSquare(counts, n), chiSquareQuantile(bins - 1, kZ1e6));
  EXPECT_LT(std::fabs(correlation(a, b)), 4 / std::sqrt(double(n)));
}

}  // namespace
}  // namespace rayes
