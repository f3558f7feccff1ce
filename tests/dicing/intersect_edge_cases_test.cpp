// Specification of DiceBuffer::intersect / occluded on the stiff cases of
// docs/design.md, "Precision": parallel, in-plane and grazing rays, degenerate patches, bad rays,
// and the fields of GridHit.
#include <gtest/gtest.h>
#include <limits>
#include "geometry/bezier_patch.h"
#include "geometry/bilinear_patch.h"
#include "dicing/dice_buffer.h"
#include "support/patch_test_util.h"

namespace rayes {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

bool finiteHit(const GridHit& h) {
  return std::isfinite(h.t) && std::isfinite(h.u) && std::isfinite(h.v) && isFinite(h.ng) && isFinite(h.ns);
}

class FlatGrid : public ::testing::Test {
 protected:
  FlatGrid() : patch({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}), buffer(4) { buffer.dice(patch, 4); }
  BilinearPatch patch;
  DiceBuffer buffer;
};

TEST_F(FlatGrid, StraightDownHitHasAnalyticFields) {
  test::Random rng(31);
  for (int s = 0; s < 1000; ++s) {
    const float x = rng.uniform(), y = rng.uniform();
    GridHit h;
    ASSERT_TRUE(buffer.intersect({x, y, 2}, {0, 0, -1}, 0, kInf, 4, h));
    EXPECT_EQ(h.t, 2.0f);                 // depths of the plane z = 0 are exact
    // u = (x_quad + s) / 16 with s from barycentrics: a few roundings of values <= 1.
    EXPECT_NEAR(h.u, x, 4 * gammaBound(8));
    EXPECT_NEAR(h.v, y, 4 * gammaBound(8));
    EXPECT_EQ(h.quad, uint32_t(std::min(15, int(h.v * 16))) * 16 + uint32_t(std::min(15, int(h.u * 16))));
    EXPECT_EQ(std::fabs(h.ng.z), 1.0f);
    EXPECT_EQ(std::fabs(h.ns.z), 1.0f);
    EXPECT_TRUE(buffer.occluded({x, y, 2}, {0, 0, -1}, 0, kInf, 4));
    EXPECT_FALSE(buffer.occluded({x, y, 2}, {0, 0, -1}, 0, 2.0f, 4));  // t must be < tmax
    EXPECT_FALSE(buffer.intersect({x, y, 2}, {0, 0, -1}, 2.0f, kInf, 4, h));  // and > tmin
  }
}

TEST_F(FlatGrid, BackfacesCount) {
  GridHit h;
  EXPECT_TRUE(buffer.intersect({0.3f, 0.4f, -1}, {0, 0, 1}, 0, kInf, 4, h));
  EXPECT_EQ(h.t, 1.0f);
}

TEST_F(FlatGrid, ParallelAndInPlaneRaysMissWithoutNaN) {
  GridHit h;
  for (Vec3 dir : {Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{1, 1, 0}, Vec3{-1, 0.3f, 0}}) {
    for (float z : {0.5f, 1e-30f, -1e-30f, 0.0f}) {  // above, just above/below, in the plane
      for (Vec3 org : {Vec3{-1, 0.5f, z}, Vec3{0.5f, 0.5f, z}, Vec3{0.25f, 0.25f, z}, Vec3{0, 0, z}}) {
        EXPECT_FALSE(buffer.intersect(org, dir, 0, kInf, 4, h)) << org.x << " " << org.y << " " << z;
        EXPECT_FALSE(buffer.occluded(org, dir, 0, kInf, 4));
      }
    }
  }
}

TEST_F(FlatGrid, GrazingRaysGiveFiniteHits) {
  test::Random rng(32);
  int hits = 0;
  for (int s = 0; s < 2000; ++s) {
    const float slope = std::ldexp(1.0f, -rng.below(60));  // down to 2^-59
    const Vec3 dir{1, rng.uniform(-1, 1), -slope};
    const Vec3 org{-0.5f, rng.uniform(), 0.5f * slope + rng.uniform(-1e-3f, 1e-3f) * slope};
    GridHit h;
    if (buffer.intersect(org, dir, 0, kInf, 4, h)) {
      ++hits;
      ASSERT_TRUE(finiteHit(h));
      ASSERT_LE(h.u, 1.0f);
      ASSERT_LE(h.v, 1.0f);
      ASSERT_GE(h.u, 0.0f);
      ASSERT_GE(h.v, 0.0f);
    }
  }
  EXPECT_GT(hits, 0);
}

TEST_F(FlatGrid, BadRaysNeverHit) {
  GridHit h;
  const Vec3 org{0.5f, 0.5f, 1};
  EXPECT_FALSE(buffer.intersect(org, {0, 0, 0}, 0, kInf, 4, h));
  EXPECT_FALSE(buffer.intersect(org, {0, 0, kNaN}, 0, kInf, 4, h));
  EXPECT_FALSE(buffer.intersect(org, {0, 0, -kInf}, 0, kInf, 4, h));
  EXPECT_FALSE(buffer.intersect(org, {0, 0, -1e-40f}, 0, kInf, 4, h));  // denormal direction
  EXPECT_FALSE(buffer.intersect({kNaN, 0.5f, 1}, {0, 0, -1}, 0, kInf, 4, h));
  EXPECT_FALSE(buffer.intersect(org, {0, 0, -1}, kNaN, kInf, 4, h));
  EXPECT_FALSE(buffer.intersect(org, {0, 0, -1}, 0, kNaN, 4, h));
  EXPECT_FALSE(buffer.intersect(org, {0, 0, -1}, 3, 2, 4, h));
  EXPECT_FALSE(buffer.occluded(org, {0, 0, 0}, 0, kInf, 4));
  EXPECT_FALSE(buffer.occluded(org, {0, 0, -1}, 5, 5, 4));
}

TEST_F(FlatGrid, RayThroughGridVertexAndDiagonalIsDeterministic) {
  // Exactly through an inner vertex: six triangles tie in t; the smallest quad index wins.
  GridHit h;
  ASSERT_TRUE(buffer.intersect({0.5f, 0.5f, 1}, {0, 0, -1}, 0, kInf, 4, h));
  EXPECT_EQ(h.t, 1.0f);
  EXPECT_EQ(h.quad, 7u * 16 + 7);
  EXPECT_EQ(h.u, 0.5f);
  EXPECT_EQ(h.v, 0.5f);
  // Through a diagonal: both triangles of the quad tie; the first (p00, p10, p11) wins.
  ASSERT_TRUE(buffer.intersect({0.25f + 1.0f / 32, 0.25f + 1.0f / 32, 1}, {0, 0, -1}, 0, kInf, 4, h));
  EXPECT_EQ(h.quad, 4u * 16 + 4);
}

TEST(DegeneratePatch, AllControlPointsEqualGivesNoHitAndNoNaN) {
  std::array<Vec3, 16> cp;
  cp.fill(Vec3{1, 2, 3});
  const BezierPatch bp(cp);
  DiceBuffer buffer(4);
  buffer.dice(bp, 4);
  for (int j = 0; j < buffer.resolution(); ++j)
    for (int i = 0; i < buffer.resolution(); ++i) {
      ASSERT_TRUE(isFinite(buffer.normal(i, j)));
      ASSERT_EQ(buffer.position(i, j), (Vec3{1, 2, 3}));
    }
  test::Random rng(33);
  GridHit h;
  for (int s = 0; s < 1000; ++s) {
    const Vec3 org = Vec3{1, 2, 3} + rng.unitVector() * rng.uniform(0.1f, 10);
    const Vec3 dir = s % 2 ? Vec3{1, 2, 3} - org : rng.unitVector();
    for (int k = 0; k <= 4; ++k) {
      ASSERT_FALSE(buffer.intersect(org, dir, 0, kInf, k, h));
      ASSERT_FALSE(buffer.occluded(org, dir, 0, kInf, k));
    }
  }
}

TEST(DegeneratePatch, PoleQuadsHitWithFiniteNormals) {
  // Teapot lid knob: a pole where a whole control row collapses. Rays straight down the axis
  // hit the pole vertex itself, where every quad has a degenerate triangle.
  const auto patches = test::loadTeapot();
  DiceBuffer buffer(5);
  int poleHits = 0;
  for (const auto& cp : patches) {
    for (int side = 0; side < 4; ++side) {
      const auto b = test::borderControlPoints(cp, side);
      if (!(b[0] == b[1] && b[1] == b[2] && b[2] == b[3])) continue;
      const BezierPatch bp(cp);
      buffer.dice(bp, 5);
      test::Random rng(34);
      for (int s = 0; s < 200; ++s) {
        const Vec3 dir = Vec3{rng.uniform(-0.3f, 0.3f), rng.uniform(-0.3f, 0.3f), b[0].z > 1 ? -1.0f : 1.0f};
        const Vec3 org = b[0] - dir * 2.0f;
        GridHit h;
        if (buffer.intersect(org, dir, 0, kInf, 5, h)) {
          ++poleHits;
          ASSERT_TRUE(finiteHit(h));
          ASSERT_NEAR(length(h.ng), 1.0f, 4 * gammaBound(4));
          ASSERT_NEAR(length(h.ns), 1.0f, 4 * gammaBound(4));
        }
      }
    }
  }
  EXPECT_GT(poleHits, 0);
}

}  // namespace
}  // namespace rayes
