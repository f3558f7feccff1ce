// Specification of BilinearPatch: exact corners, bilinear interior, canonical borders,
// degenerate corners.
#include <gtest/gtest.h>
#include "geometry/bilinear_patch.h"
#include "dicing/dice_buffer.h"
#include "support/patch_test_util.h"

namespace rayes {
namespace {

using test::sameBits;

Vec3 randomPoint(test::Random& rng) { return {rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(-2, 2)}; }

TEST(BilinearPatch, CornersExactInteriorBilinear) {
  test::Random rng(11);
  for (int trial = 0; trial < 20; ++trial) {
    const Vec3 p00 = randomPoint(rng), p10 = randomPoint(rng), p01 = randomPoint(rng), p11 = randomPoint(rng);
    const BilinearPatch bp(p00, p10, p01, p11);
    EXPECT_TRUE(sameBits(bp.evaluate(0, 0).p, p00));
    EXPECT_TRUE(sameBits(bp.evaluate(1, 0).p, p10));
    EXPECT_TRUE(sameBits(bp.evaluate(0, 1).p, p01));
    EXPECT_TRUE(sameBits(bp.evaluate(1, 1).p, p11));
    // Two lerps of 3 roundings each on coordinates of magnitude <= 2: gamma(6) * 2 per lerp
    // level, twice.
    const double tol = 2 * gammaBound(6) * 2.0 * 2;
    for (int s = 0; s < 100; ++s) {
      const double u = rng.uniform(), v = rng.uniform();
      const Vec3 p = bp.evaluate(float(u), float(v)).p;
      for (int c = 0; c < 3; ++c) {
        const double ref = (1 - u) * (1 - v) * p00[c] + u * (1 - v) * p10[c] + (1 - u) * v * p01[c] + u * v * p11[c];
        EXPECT_NEAR(p[c], ref, tol);
      }
    }
    EXPECT_GT(bp.sizeBound(), 0.0f);
    for (Vec3 p : {p00, p10, p01, p11}) EXPECT_TRUE(bp.bounds().contains(p));
  }
}

TEST(BilinearPatch, SharedBorderInEitherOrientationIsBitIdentical) {
  test::Random rng(12);
  DiceBuffer a(5), b(5);
  for (int trial = 0; trial < 20; ++trial) {
    const Vec3 p00 = randomPoint(rng), p10 = randomPoint(rng), p01 = randomPoint(rng), p11 = randomPoint(rng);
    const Vec3 q = randomPoint(rng), r = randomPoint(rng);
    // b shares a's u=1 border (p10 -> p11) as its v=0 border, run backwards (p11 -> p10).
    const BilinearPatch pa(p00, p10, p01, p11), pb(p11, p10, q, r);
    for (int m = 0; m <= 5; ++m) {
      a.dice(pa, m);
      b.dice(pb, m);
      const int n = 1 << m;
      for (int k = 0; k <= n; ++k) ASSERT_TRUE(sameBits(a.position(n, k), b.position(n - k, 0)));
    }
  }
}

TEST(BilinearPatch, CollapsedEdgeHasFiniteNormals) {
  // A triangle as a bilinear patch: the v=1 border collapses to one point (a pole).
  const BilinearPatch bp({0, 0, 0}, {1, 0, 0}, {0.5f, 1, 0}, {0.5f, 1, 0});
  DiceBuffer buffer(4);
  buffer.dice(bp, 4);
  for (int j = 0; j < buffer.resolution(); ++j)
    for (int i = 0; i < buffer.resolution(); ++i) {
      const Vec3 n = buffer.normal(i, j);
      ASSERT_TRUE(isFinite(n));
      ASSERT_EQ(n.x, 0.0f);
      ASSERT_EQ(n.y, 0.0f);
      ASSERT_EQ(std::fabs(n.z), 1.0f);  // a flat patch in z = 0: exactly +-z after scaling
    }
}

TEST(BilinearPatch, FullyDegenerateHasZeroNotNaNNormal) {
  const Vec3 p{3, 4, 5};
  const BilinearPatch bp(p, p, p, p);
  const SurfacePoint sp = bp.evaluate(0.25f, 0.75f);
  EXPECT_TRUE(sameBits(sp.p, p));
  EXPECT_TRUE(isFinite(sp.n));
  EXPECT_EQ(sp.n, (Vec3{0, 0, 0}));
  EXPECT_EQ(bp.sizeBound(), 0.0f);
}

}  // namespace
}  // namespace rayes
