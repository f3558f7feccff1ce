// Specification of BilinearPatch as a surface: exact corners, bilinear interior, a fully
// degenerate patch. Its dicing (canonical shared borders, a collapsed edge's normals) is
// specified in tests/dicing/bilinear_patch_dicing_test.cpp.
#include <gtest/gtest.h>
#include "geometry/bilinear_patch.h"
#include "support/patch_test_util.h"

namespace rayes {
namespace {

using test::randomPoint;
using test::sameBits;

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
