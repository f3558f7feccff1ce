// Counter-based random numbers: pure functions of their key, in [0, 1), uniform.
#include <cmath>
#include <gtest/gtest.h>
#include "core/rng.h"

namespace rayes {
namespace {

TEST(Rng, LargestBitsStayBelowOne) {
  EXPECT_LT(bitsToUnitFloat(~uint64_t(0)), 1.0f);
  EXPECT_EQ(bitsToUnitFloat(0), 0.0f);
  // The float-from-32-bits pitfall (precision.md): v * 2^-32 rounds to 1.0f for v >= 0xFFFFFF80.
  EXPECT_EQ(static_cast<float>(0xFFFFFF80u * (1.0 / 4294967296.0)), 1.0f);
}

TEST(Rng, SameKeySameValueDifferentKeysDiffer) {
  const RngKey a{12, 3, 1, 0};
  EXPECT_EQ(sampleUniform(a, 5), sampleUniform(a, 5));
  EXPECT_NE(sampleUniform(a, 5), sampleUniform(a, 6));
  EXPECT_NE(sampleUniform(a, 5), sampleUniform(RngKey{12, 4, 1, 0}, 5));
  EXPECT_NE(sampleUniform(a, 5), sampleUniform(RngKey{12, 3, 2, 0}, 5));
  EXPECT_NE(sampleUniform(a, 5), sampleUniform(RngKey{12, 3, 1, 9}, 5));
}

TEST(Rng, MeanAndVarianceOfUniformWithinFourSigma) {
  const int n = 200000;
  double s = 0, s2 = 0;
  for (int i = 0; i < n; ++i) {
    const double u = sampleUniform(RngKey{uint32_t(i), 0, 0, 1}, 0);
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    s += u;
    s2 += u * u;
  }
  // mean 1/2 with standard error sqrt(1/12 / n); E[u^2] = 1/3 with sd sqrt(4/45 / n).
  EXPECT_NEAR(s / n, 0.5, 4 * std::sqrt(1.0 / 12.0 / n));
  EXPECT_NEAR(s2 / n, 1.0 / 3.0, 4 * std::sqrt(4.0 / 45.0 / n));
}

}  // namespace
}  // namespace rayes
