// Patch::dicingErrorCoefficient C bounds how far the level-m dicing (micro-quads split into
// two triangles) strays from the true surface: C / 4^m. Secondary-ray offsets rely on it.
// Checked where the error peaks for smooth patches: the micro-quad centre (bilinear blend of
// the corners) and the midpoints of both diagonals (the triangles' shared edge, whichever
// diagonal the split uses).
#include <cmath>
#include <gtest/gtest.h>
#include "core/rng.h"
#include "geometry/bezier_patch.h"
#include "geometry/bilinear_patch.h"

namespace rayes {
namespace {

void expectBound(const Patch& patch, int level, int samples) {
  const float c = patch.dicingErrorCoefficient();
  const float bound = c * std::ldexp(1.0f, -2 * level);
  const int n = 1 << level;
  const float h = 1.0f / float(n);
  float worst = 0;
  for (int s = 0; s < samples; ++s) {
    const RngKey k{uint32_t(s), uint32_t(level), 0, 77};
    const int i = std::min(n - 1, int(sampleUniform(k, 0) * n)), j = std::min(n - 1, int(sampleUniform(k, 1) * n));
    const Vec3 p00 = patch.evaluate(i * h, j * h).p, p10 = patch.evaluate((i + 1) * h, j * h).p;
    const Vec3 p01 = patch.evaluate(i * h, (j + 1) * h).p, p11 = patch.evaluate((i + 1) * h, (j + 1) * h).p;
    const Vec3 centre = patch.evaluate((i + 0.5f) * h, (j + 0.5f) * h).p;
    const Vec3 blended = (p00 + p10 + p01 + p11) * 0.25f;
    // Rounding of the evaluation itself: a few ulps of the coordinates.
    const float slack = 8 * std::numeric_limits<float>::epsilon() * maxComponent(vabs(centre)) + 1e-30f;
    for (Vec3 q : {blended, (p00 + p11) * 0.5f, (p10 + p01) * 0.5f}) {
      const float e = length(q - centre);
      worst = std::max(worst, e);
      ASSERT_LE(e, bound + slack) << "level " << level << " quad " << i << "," << j;
    }
  }
  // The bound is not absurdly loose either (it is what the offsets are made of).
  if (c > 0 && level >= 2) {
    EXPECT_GT(worst, bound * 1e-3f);
  }
}

TEST(DicingError, TeapotPatchesStayWithinTheirBound) {
  for (const auto& cp : loadBezierPatchFile(std::string(RAYES_SOURCE_DIR) + "/scenes/teapot.bpt")) {
    const BezierPatch patch(cp);
    for (int level : {0, 2, 4, 7}) expectBound(patch, level, 400);
  }
}

TEST(DicingError, TwistedBilinearWithinBoundAndPlanarIsZero) {
  const BilinearPatch twisted({0, 0, 0}, {1, 0, 0.7f}, {0, 1, -0.4f}, {1, 1, 0.2f});
  for (int level : {0, 1, 3, 6}) expectBound(twisted, level, 400);
  const BilinearPatch planar({0, 0, 1}, {2, 0, 1}, {0, 3, 1}, {2, 3, 1});
  EXPECT_EQ(planar.dicingErrorCoefficient(), 0.0f);
}

// A planar quad that is not a parallelogram (twist w != 0) still dices into triangles in its
// plane: C is exactly 0, also when its corners are decimals rounded to float on a tilted plane.
TEST(DicingError, PlanarTrapezoidsAreZeroEvenWithRoundedCorners) {
  const BilinearPatch cornellFloor({552.8f, 0, 0}, {0, 0, 0}, {549.6f, 0, 559.2f}, {0, 0, 559.2f});
  EXPECT_EQ(cornellFloor.dicingErrorCoefficient(), 0.0f);
  // The plane x + 2y + 3z = 1.7 through decimal corners: each z rounds to float.
  auto onPlane = [](double x, double y) { return Vec3{float(x), float(y), float((1.7 - x - 2 * y) / 3)}; };
  for (double scale : {1e-3, 1.0, 1e3, 1e6}) {
    const BilinearPatch tilted(onPlane(0.1 * scale, 0.3 * scale), onPlane(2.9 * scale, 0.3 * scale),
                               onPlane(0.7 * scale, 1.9 * scale), onPlane(2.2 * scale, 1.9 * scale));
    EXPECT_EQ(tilted.dicingErrorCoefficient(), 0.0f) << scale;
  }
  // A trapezoid lifted out of its plane by a thousandth of its size is not planar, and its
  // bound holds.
  const BilinearPatch bent({0, 0, 0}, {4, 0, 0}, {1, 3, 0}, {3, 3, 0.004f});
  EXPECT_GT(bent.dicingErrorCoefficient(), 0.0f);
  for (int level : {0, 2, 5, 10}) expectBound(bent, level, 200);
}

}  // namespace
}  // namespace rayes

namespace rayes {
namespace {

// Patch::boundsOver contains the true surface over its parameter rectangle.
void expectBoundsOverContainsSurface(const Patch& patch) {
  for (uint32_t s = 0; s < 300; ++s) {
    const RngKey k{s, 0, 0, 91};
    float u0 = sampleUniform(k, 0), u1 = sampleUniform(k, 1), v0 = sampleUniform(k, 2), v1 = sampleUniform(k, 3);
    if (u0 > u1) std::swap(u0, u1);
    if (v0 > v1) std::swap(v0, v1);
    const Box3 box = patch.boundsOver(u0, u1, v0, v1);
    ASSERT_TRUE(patch.bounds().contains(box.center()));
    for (uint32_t i = 0; i < 64; ++i) {
      const float u = u0 + (u1 - u0) * sampleUniform(k, 10 + 2 * i), v = v0 + (v1 - v0) * sampleUniform(k, 11 + 2 * i);
      ASSERT_TRUE(box.contains(patch.evaluate(u, v).p)) << "rect " << u0 << ".." << u1 << " x " << v0 << ".." << v1;
    }
  }
}

TEST(BoundsOver, TeapotSubPatchHullsContainTheSurface) {
  for (const auto& cp : loadBezierPatchFile(std::string(RAYES_SOURCE_DIR) + "/scenes/teapot.bpt"))
    expectBoundsOverContainsSurface(BezierPatch(cp));
}

TEST(BoundsOver, BilinearAndTightOnSmallRectangles) {
  const BilinearPatch twisted({0, 0, 0}, {1, 0, 0.7f}, {0, 1, -0.4f}, {1, 1, 0.2f});
  expectBoundsOverContainsSurface(twisted);
  // A tiny rectangle gives a tiny box, not the whole patch's.
  const auto cps = loadBezierPatchFile(std::string(RAYES_SOURCE_DIR) + "/scenes/teapot.bpt");
  const BezierPatch p(cps[0]);
  EXPECT_LT(p.boundsOver(0.5f, 0.51f, 0.5f, 0.51f).longestSide(), 0.05f * p.bounds().longestSide());
}

}  // namespace
}  // namespace rayes
