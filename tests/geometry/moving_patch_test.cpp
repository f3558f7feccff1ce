// MovingPatch (geometry/moving_patch.h) as a patch: its bounds cover every keyframe, a time maps
// to its interval and weight (clamped to the keyframes), and bad keyframes are refused. Its
// dicing over a time interval is specified in tests/dicing/motion_dice_test.cpp.
#include <gtest/gtest.h>
#include <memory>
#include <stdexcept>
#include "core/transform.h"
#include "geometry/bilinear_patch.h"
#include "geometry/moving_patch.h"
#include "support/moving_teapot.h"

namespace rayes {
namespace {

using test::movingTeapotPatch;
using test::teapotPatchAt;

TEST(MovingPatch, BoundsCoverEverySampleAndTimeClampsToTheKeyframes) {
  const auto mp = movingTeapotPatch();
  EXPECT_EQ(mp->timeSamples(), 3);
  for (int s = 0; s < 3; ++s) EXPECT_TRUE(mp->bounds().contains(mp->sample(s).bounds()));
  EXPECT_STREQ(mp->kind(), "bezier");
  const TimeInterval before = timeInterval(*mp, -1.0f), after = timeInterval(*mp, 2.0f);
  EXPECT_EQ(before.interval, 0);
  EXPECT_EQ(before.alpha, 0.0f);
  EXPECT_EQ(after.interval, 1);
  EXPECT_EQ(after.alpha, 1.0f);
  const TimeInterval mid = timeInterval(*mp, 0.75f);
  EXPECT_EQ(mid.interval, 1);
  EXPECT_FLOAT_EQ(mid.alpha, 0.5f);
  EXPECT_EQ(timeInterval(*mp, 0.5f).interval, 1);
  EXPECT_EQ(timeInterval(mp->sample(0), 0.3f).interval, 0);  // a static patch
  EXPECT_EQ(timeInterval(mp->sample(0), 0.3f).alpha, 0.0f);
  EXPECT_THROW(MovingPatch({teapotPatchAt(Transform{})}, {0.0f}), std::invalid_argument);
  EXPECT_THROW(MovingPatch({teapotPatchAt(Transform{}), teapotPatchAt(Transform{})}, {1.0f, 1.0f}),
               std::invalid_argument);
  const auto bil = std::make_shared<BilinearPatch>(Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{1, 1, 0});
  EXPECT_THROW(MovingPatch({teapotPatchAt(Transform{}), bil}, {0.0f, 1.0f}), std::invalid_argument);
}

}  // namespace
}  // namespace rayes
