// The shared geometric helpers: the conservative slab test, normal packing, frames.
#include <cmath>
#include <limits>
#include <gtest/gtest.h>
#include "core/box.h"
#include "core/octahedral.h"
#include "core/rng.h"
#include "core/transform.h"

namespace rayes {
namespace {
constexpr float kInf = std::numeric_limits<float>::infinity();

TEST(BoxTest, RayThroughBoxCornerAndFaceIsNotCulled) {
  const Box3 b{{-1, -1, -1}, {1, 1, 1}};
  float t0, t1;
  // Exactly through a corner, along a diagonal, from far away.
  RayBoxQuery q({-5, -5, -5}, normalize(Vec3{1, 1, 1}));
  EXPECT_TRUE(intersectBox(q, b.lo, b.hi, 0, kInf, t0, t1));
  // Grazing along a face plane with zero direction components.
  RayBoxQuery g({-5, 1, 1}, {1, 0, 0});
  EXPECT_TRUE(intersectBox(g, b.lo, b.hi, 0, kInf, t0, t1));
  EXPECT_FLOAT_EQ(t0, 4.0f);
  // A flat box (zero thickness) hit head-on.
  const Box3 flat{{-1, -1, 0}, {1, 1, 0}};
  RayBoxQuery f({0.2f, 0.3f, 5}, {0, 0, -1});
  EXPECT_TRUE(intersectBox(f, flat.lo, flat.hi, 0, kInf, t0, t1));
  EXPECT_FLOAT_EQ(t0, 5.0f);
}

TEST(BoxTest, MissesAreMissesAndNothingIsNaN) {
  const Box3 b{{-1, -1, -1}, {1, 1, 1}};
  float t0, t1;
  RayBoxQuery q({-5, 2, 0}, {1, 0, 0});
  EXPECT_FALSE(intersectBox(q, b.lo, b.hi, 0, kInf, t0, t1));
  // Origin on a slab plane with a zero direction component: 0 * inf = NaN must not leak.
  RayBoxQuery z({-5, 1, 0}, {1, 0, 0});
  EXPECT_TRUE(intersectBox(z, b.lo, b.hi, 0, kInf, t0, t1));
  EXPECT_FALSE(std::isnan(t0));
  EXPECT_FALSE(std::isnan(t1));
}

TEST(Octahedral, RoundTripErrorIsBounded) {
  // 16-bit snorm per component: the angular error is below 1e-4 rad everywhere.
  for (uint32_t i = 0; i < 20000; ++i) {
    const RngKey k{i, 0, 0, 3};
    const float z = 2 * sampleUniform(k, 0) - 1, phi = 6.2831853f * sampleUniform(k, 1);
    const float r = std::sqrt(std::max(0.0f, 1 - z * z));
    const Vec3 n{r * std::cos(phi), r * std::sin(phi), z};
    const Vec3 d = decodeOctahedral(encodeOctahedral(n));
    EXPECT_NEAR(length(d), 1.0f, 1e-6f);
    EXPECT_LT(length(cross(d, n)), 1e-4f);  // sin of the angle between them
  }
  for (Vec3 axis : {Vec3{0, 0, 1}, Vec3{0, 0, -1}, Vec3{1, 0, 0}, Vec3{0, -1, 0}})
    EXPECT_GT(dot(decodeOctahedral(encodeOctahedral(axis)), axis), 0.9999999f);
  // Zero and NaN encode to some unit vector, never NaN.
  EXPECT_NEAR(length(decodeOctahedral(encodeOctahedral({0, 0, 0}))), 1.0f, 1e-6f);
  EXPECT_NEAR(length(decodeOctahedral(encodeOctahedral({NAN, 0, 0}))), 1.0f, 1e-6f);
}

TEST(Frame, OrthonormalForEveryNormalIncludingPoles) {
  for (Vec3 n : {Vec3{0, 0, 1}, Vec3{0, 0, -1}, normalize(Vec3{1e-8f, 0, -1}), normalize(Vec3{1, 2, 3})}) {
    Vec3 t, b;
    orthonormalBasis(n, t, b);
    EXPECT_NEAR(length(t), 1, 1e-5);
    EXPECT_NEAR(length(b), 1, 1e-5);
    EXPECT_NEAR(dot(t, n), 0, 1e-5);
    EXPECT_NEAR(dot(b, n), 0, 1e-5);
    EXPECT_NEAR(dot(t, b), 0, 1e-5);
  }
}

TEST(TransformTest, ComposesInOrderAndRotatesRightHanded) {
  const Transform r = Transform::rotate({0, 0, 1}, 90);
  const Vec3 p = r.point({1, 0, 0});
  EXPECT_NEAR(p.x, 0, 1e-6);
  EXPECT_NEAR(p.y, 1, 1e-6);
  const Transform ts = Transform::translate({1, 0, 0}) * Transform::scale({2, 2, 2});  // scale, then move
  EXPECT_NEAR(ts.point({1, 1, 1}).x, 3, 1e-6);
  EXPECT_NEAR(normalize(Vec3{0, 0, 0}).x, 0.0f, 0.0f);  // normalize of zero is zero, not NaN
}

}  // namespace
}  // namespace rayes
