// The stats say what a scene used and what was left out because nothing needed it
// (docs/design.md, invariant 4): a static, undisplaced scene skips motion and displacement work; a
// scene with moving shapes and an open shutter dices two time samples and says so.
#include <gtest/gtest.h>
#include "app/stats_json.h"
#include "support/render_fixtures.h"

namespace rayes {
namespace {

nlohmann::json statsOf(const std::string& sceneFile) {
  Scene s = loadScene(testing::sourcePath(sceneFile));
  s.width = 16;
  s.height = 12;
  s.samplesPerPixel = 1;
  ThreadLimit limit(2);
  RenderOptions o;
  Renderer r(s, o);
  r.render();
  return statsToJson(s, o, r.stats(), RunInfo{sceneFile, 2, 16, 12, 1, 0, 0});
}

TEST(StatsFeatures, StaticSceneSkipsMotionAndDisplacement) {
  const auto j = statsOf("scenes/teapot.json");
  EXPECT_FALSE(j["features"]["motion_blur"].get<bool>());
  EXPECT_EQ(j["features"]["moving_dicings"].get<uint64_t>(), 0u);
  EXPECT_TRUE(j["skipped"].contains("motion_blur"));
  EXPECT_TRUE(j["skipped"].contains("displacement"));
  EXPECT_TRUE(j["skipped"].contains("volumes"));
  EXPECT_FALSE(j["skipped"].contains("border_closure"));  // the teapot's borders are curved
}

TEST(StatsFeatures, MovingSceneDicesTwoTimeSamplesAndSaysSo) {
  const auto j = statsOf("scenes/motion-cubes.json");
  EXPECT_TRUE(j["features"]["motion_blur"].get<bool>());
  EXPECT_GT(j["features"]["moving_dicings"].get<uint64_t>(), 0u);
  EXPECT_FALSE(j["skipped"].contains("motion_blur"));
  EXPECT_TRUE(j["skipped"].contains("border_closure"));  // cubes of flat quads
}

// A ray's shutter time is stored only where a leaf moves: both scenes use the path tracer's two
// ray slots per path, so a moving scene's path costs exactly two floats more.
TEST(StatsFeatures, RayTimesAreKeptOnlyWhenSomethingMoves) {
  const auto still = statsOf("scenes/teapot.json"), moving = statsOf("scenes/motion-cubes.json");
  EXPECT_NE(still["skipped"]["motion_blur"].get<std::string>().find("no time per ray"), std::string::npos);
  EXPECT_EQ(moving["memory"]["bytes_per_path"].get<uint64_t>() - still["memory"]["bytes_per_path"].get<uint64_t>(),
            2 * sizeof(float));
}

TEST(StatsFeatures, DisplacedSceneSaysDisplacementWasActive) {
  const auto j = statsOf("scenes/displaced-teapot.json");
  EXPECT_TRUE(j["features"]["displacement"].get<bool>());
  EXPECT_FALSE(j["skipped"].contains("displacement"));
}

}  // namespace
}  // namespace rayes
