// Specification of BilinearPatch diced: canonical borders (bit-identical in either orientation)
// and finite normals along a collapsed edge. Its evaluation alone is specified in
// tests/geometry/bilinear_patch_test.cpp.
#include <gtest/gtest.h>
#include "geometry/bilinear_patch.h"
#include "dicing/dice_buffer.h"
#include "support/patch_test_util.h"

namespace rayes {
namespace {

using test::randomPoint;
using test::sameBits;

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

}  // namespace
}  // namespace rayes
