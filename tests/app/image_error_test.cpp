// The error of a render against a reference (app/image_error.h): the RMSE counts the error
// mask's pixels; the largest squared errors are named with their share of the sum; the clamped
// RMSE caps each pixel's squared error at the nearest-rank quantile, never above the RMSE, and
// equals it when the quantile leaves no pixel above its rank.
#include <algorithm>
#include <cmath>
#include <random>
#include <gtest/gtest.h>
#include "app/image_error.h"

namespace rayes {
namespace {

// Two pixels, errors (1, 1, 1) and (3, 3, 3): over both RMSE = sqrt(5); the mask keeps the second.
TEST(ImageError, CountsOnlyTheErrorMasksPixels) {
  const std::vector<float> rgba{1, 1, 1, 1, 3, 3, 3, 1}, ref(6, 0.0f);
  const PixelRegion all{0, 0, 2, 1, {}};
  EXPECT_DOUBLE_EQ(errorAgainst(rgba, ref, all, 2, 1).rmse, std::sqrt(5.0));
  EXPECT_DOUBLE_EQ(errorAgainst(rgba, ref, all, 2, 1).relMse, (1 + 9) / 2 / 0.01);
  const PixelRegion second{0, 0, 0, 0, {0, 0, 0, 1, 0, 0}};
  EXPECT_DOUBLE_EQ(errorAgainst(rgba, ref, second, 2, 1).rmse, 3.0);
  EXPECT_DOUBLE_EQ(errorAgainst(rgba, ref, PixelRegion{0, 0, 0, 0, {0, 0, 0, 0, 0, 0}}, 2, 1).rmse, 0.0);
}

// An image of `w` x `h` whose render differs from a black reference by `d[p]` in every channel.
struct Pair {
  int w, h;
  std::vector<float> rgba, ref;
  PixelRegion all() const { return {0, 0, w, h, {}}; }
};
Pair imageWithDifferences(int w, int h, const std::vector<float>& d) {
  Pair p{w, h, std::vector<float>(4 * d.size(), 1.0f), std::vector<float>(3 * d.size(), 0.0f)};
  for (size_t i = 0; i < d.size(); ++i)
    for (int c = 0; c < 3; ++c) p.rgba[4 * i + c] = d[i];
  return p;
}

// The case: one pixel of value 107 among pixels off by 0.5 holds most of the squared error.
TEST(LargestErrors, NamesTheFireflyAndItsShare) {
  std::vector<float> d(20 * 10, 0.5f);
  d[3 * 20 + 7] = 107;
  const Pair p = imageWithDifferences(20, 10, d);
  const LargestErrors l = largestErrors(p.rgba, p.ref, p.all(), 20, 10, 3);
  ASSERT_EQ(l.pixels.size(), 3u);
  EXPECT_EQ(l.pixels[0].x, 7);
  EXPECT_EQ(l.pixels[0].y, 3);
  EXPECT_DOUBLE_EQ(l.pixels[0].squared, 107.0 * 107.0);
  EXPECT_DOUBLE_EQ(l.pixels[0].value, 107);
  EXPECT_DOUBLE_EQ(l.pixels[0].reference, 0);
  // Ties keep scan order: the next two are the first pixels.
  EXPECT_EQ(l.pixels[1].x, 0);
  EXPECT_EQ(l.pixels[2].x, 1);
  EXPECT_EQ(l.counted, 200u);
  const double total = 107.0 * 107.0 + 199 * 0.25;
  EXPECT_DOUBLE_EQ(l.total, total);
  EXPECT_DOUBLE_EQ(l.share, (107.0 * 107.0 + 2 * 0.25) / total);
}

TEST(LargestErrors, OfFewerPixelsThanAskedAndOfNoError) {
  const Pair p = imageWithDifferences(2, 1, {0, 0});
  const LargestErrors l = largestErrors(p.rgba, p.ref, p.all(), 2, 1, 3);
  EXPECT_EQ(l.pixels.size(), 2u);
  EXPECT_EQ(l.share, 0.0) << "no error: no share, not 0/0";
  EXPECT_EQ(largestErrors(p.rgba, p.ref, PixelRegion{0, 0, 0, 0, {}}, 2, 1, 3).counted, 0u);
}

// 999 pixels off by 1 and one off by 100: the 0.999 quantile is the 999th smallest (1), so the
// outlier is clamped to 1 and the clamped RMSE is 1; at 0.9995 the rank is the 1000th: no clamp.
TEST(ClampedRmse, ClampsAtTheNearestRankQuantile) {
  std::vector<float> d(1000, 1.0f);
  d[500] = 100;
  const Pair p = imageWithDifferences(1000, 1, d);
  const double rmse = errorAgainst(p.rgba, p.ref, p.all(), 1000, 1).rmse;
  EXPECT_DOUBLE_EQ(rmse, std::sqrt((999 + 1e4) / 1000));
  EXPECT_DOUBLE_EQ(clampedRmse(p.rgba, p.ref, p.all(), 1000, 1, 0.999), 1.0);
  EXPECT_DOUBLE_EQ(clampedRmse(p.rgba, p.ref, p.all(), 1000, 1, 0.9995), rmse);
  // Below 1 / (1 - q) pixels nothing is clamped.
  const Pair small = imageWithDifferences(10, 1, {1, 1, 1, 1, 1, 1, 1, 1, 1, 30});
  EXPECT_DOUBLE_EQ(clampedRmse(small.rgba, small.ref, small.all(), 10, 1, 0.95),
                   errorAgainst(small.rgba, small.ref, small.all(), 10, 1).rmse);
  EXPECT_EQ(clampedRmse(p.rgba, p.ref, PixelRegion{0, 0, 0, 0, {}}, 1000, 1, 0.999), 0.0);
}

// Over heavy-tailed random errors, for several quantiles: the mean of the sorted squared errors
// with those above rank k = ceil(q n) replaced by the k-th, and never above the RMSE. The two
// sums differ only in order: relative rounding below n ulp (1200 x 1.1e-16 < 1e-12).
TEST(ClampedRmse, IsTheMeanWithTheLargestCappedAtTheRank) {
  std::mt19937 rng(7);
  std::lognormal_distribution<float> heavy(0, 2);
  std::vector<float> d(40 * 30);
  for (float& v : d) v = heavy(rng);
  const Pair p = imageWithDifferences(40, 30, d);
  const double rmse = errorAgainst(p.rgba, p.ref, p.all(), 40, 30).rmse;
  std::vector<double> sq;
  for (float v : d) sq.push_back(double(v) * v);
  std::sort(sq.begin(), sq.end());
  const size_t n = sq.size();
  for (double q : {0.5, 0.9, 0.99, 0.999}) {
    const size_t k = size_t(std::ceil(q * double(n)));
    double sum = 0;
    for (size_t i = 0; i < n; ++i) sum += std::min(sq[i], sq[k - 1]);
    const double c = clampedRmse(p.rgba, p.ref, p.all(), 40, 30, q);
    EXPECT_NEAR(c * c * double(n), sum, 1e-12 * sum) << q;
    EXPECT_LE(c, rmse) << q;
  }
}

}  // namespace
}  // namespace rayes
