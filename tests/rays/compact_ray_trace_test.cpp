// The engine traces the ray record's decoded direction (core/ray_batch.h, Ray: a 48-bit
// octahedral code, within kOctahedral48MaxError of the direction aimed). At the code's stiff
// cases: a shadow ray to a point on a light 10^4 units away reaches it (it is neither short of
// the light nor falsely occluded by the light's own leaf, which it ignores); a ray parallel to a
// floor at a tiny height stays above it; a grazing ray meets the floor where the aimed one
// would, within the bound stretched by the grazing angle.
#include <cfloat>
#include <cmath>
#include <limits>
#include <gtest/gtest.h>
#include "geometry/bilinear_patch.h"
#include "rays/sorted_engine.h"
#include "rays/teapot_on_floor.h"

namespace rayes {
namespace {
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kFar = 1e4f;

// Leaf 0: the floor z = 0 over [-20, 20]^2 and beyond toward the light; leaf 1: a light square
// in the plane x = 10^4, y in [-1, 1], z in [1, 3].
struct FarLight : test::TracedWorld {
  FarLight()
      : TracedWorld({std::make_shared<BilinearPatch>(Vec3{-20, -20, 0}, Vec3{kFar, -20, 0}, Vec3{-20, 20, 0},
                                                     Vec3{kFar, 20, 0}),
                     std::make_shared<BilinearPatch>(Vec3{kFar, -1, 1}, Vec3{kFar, 1, 1}, Vec3{kFar, -1, 3},
                                                     Vec3{kFar, 1, 3})}) {}
};

void trace(const FarLight& w, RayBatch& b) {
  TraceSettings s;
  s.maxLod = 4;
  SortedEngine engine(w.top, w.source, s);
  GenerationStats stats;
  TraceTimes times;
  engine.trace(b, stats, times);
}

// Shadow rays as shadowSegment writes them: the unnormalised segment to the point and tmax 1.
// `reach` scales tmax: the relative margin 10^-5 is 10^-1 units at 10^4, 14 times the end's
// bound (kOctahedral48MaxError * 10^4 and 4 ulps of 10^4: tests/core/octahedral_test.cpp) so that
// the micro-quad test's own roundings at 10^4 cannot decide it.
RayBatch shadowRaysToTheLight(float reach, uint32_t ignore) {
  RayBatch b;
  const int n = 400;
  b.resize(n);
  for (int i = 0; i < n; ++i) {
    const Vec3 o{-5 + 0.37f * float(i % 20), -3 + 0.29f * float(i / 20), 0.01f + 0.05f * float(i % 7)};
    const Vec3 target{kFar, -0.95f + 1.9f * float(i % 13) / 12, 1.05f + 1.9f * float(i % 11) / 10};
    b.set(i, RayKind::Shadow, o, target - o, reach, 0, 0, ignore, 0, 0, 0.0f);  // leaving the floor
  }
  return b;
}

TEST(CompactRayTrace, AShadowRayToAFarLightReachesItAndItsOwnLeafDoesNotOccludeIt) {
  const FarLight w;
  RayBatch ignoring = shadowRaysToTheLight(1.0f, 1), shortOf = shadowRaysToTheLight(1 - 1e-5f, kNoLeaf),
           past = shadowRaysToTheLight(1 + 1e-5f, kNoLeaf);
  trace(w, ignoring);
  trace(w, shortOf);
  trace(w, past);
  for (size_t i = 0; i < ignoring.size(); ++i) {
    EXPECT_FALSE(ignoring.occluded(i)) << "ray " << i << ": falsely occluded";
    EXPECT_FALSE(shortOf.occluded(i)) << "ray " << i << ": reached the light before its end";
    ASSERT_TRUE(past.occluded(i)) << "ray " << i << ": did not reach the light";
    EXPECT_EQ(past.occluderOf(i), 1u) << "ray " << i;
  }
}

// Parallel to the floor 10^-4 above it, along directions off every axis: the decoded z is exactly
// 0 (the code keeps a coordinate plane), so no ray comes down to the floor over 10^4 units.
TEST(CompactRayTrace, ARayParallelToTheFloorStaysAboveIt) {
  const FarLight w;
  RayBatch b;
  const int n = 64;
  b.resize(n);
  for (int i = 0; i < n; ++i) {
    const float a = 0.02f + 1.5f * float(i) / n;  // toward +x, off the axis by 1 to 88 degrees
    b.setFromNowhere(i, RayKind::Closest, {-19, 0, 1e-4f}, {std::cos(a), std::sin(a) * (i % 2 ? 1 : -1), 0}, kInf, 0,
                     0);
  }
  trace(w, b);
  for (int i = 0; i < n; ++i) EXPECT_FALSE(b.hitOf(i).valid()) << "ray " << i;
}

// Down onto the floor at grazing angles of 10^-4 to 10^-2 rad from 10^-3 above it: the hit lies
// where the aimed direction meets the floor, within the code's angle times the distance over the
// sine of the grazing angle, plus the micro-quad test's roundings (a few ulps of the distance).
TEST(CompactRayTrace, AGrazingRayMeetsTheFloorWhereTheAimedDirectionWould) {
  const FarLight w;
  RayBatch b;
  const int n = 64;
  b.resize(n);
  const Vec3 o{-19, 0.3f, 1e-3f};
  for (int i = 0; i < n; ++i) {
    const double slope = std::pow(10.0, -4 + 2.0 * i / (n - 1));  // tan of the grazing angle
    const Vec3 d{0.8f, 0.6f, float(-slope)};
    b.setFromNowhere(i, RayKind::Closest, o, d, kInf, 0, 0);
  }
  trace(w, b);
  for (int i = 0; i < n; ++i) {
    const RayHit& h = b.hitOf(i);
    ASSERT_TRUE(h.valid()) << "ray " << i;
    ASSERT_EQ(h.leaf, 0u);
    const double slope = std::pow(10.0, -4 + 2.0 * i / (n - 1)), run = 1e-3 / slope;  // horizontal distance
    const double ex = -19 + 0.8 * run, ey = 0.3 + 0.6 * run;
    const Vec3 p = b.ray[i].org + b.ray[i].dir() * h.t;
    const double sine = slope / std::sqrt(1 + slope * slope), dist = run / std::cos(std::atan(slope));
    const double bound = kOctahedral48MaxError * dist / sine + 8 * FLT_EPSILON * (20 + dist) / sine;
    EXPECT_LE(std::hypot(p.x - ex, p.y - ey), bound) << "ray " << i << " run " << run;
  }
}

}  // namespace
}  // namespace rayes
