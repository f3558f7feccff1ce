// The render frame and the precision rule measured from the camera (docs/design.md, "The render
// frame", "Where float resolves a leaf"): no shipped scene, the forests included, has a leaf
// that float resolves too coarsely for its image, at the scene's own resolution (the set-up
// only: the leaves' boxes and the camera, no ray traced); the rule itself at its edges.
#include <cmath>
#include <filesystem>
#include <limits>
#include <gtest/gtest.h>
#include "app/render_data.h"
#include "app/stats_json.h"
#include "support/render_fixtures.h"

namespace rayes {
namespace {

std::vector<std::string> allShippedScenes() {
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(testing::sourcePath("scenes")))
    if (e.path().extension() == ".json") names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

class ShippedScene : public ::testing::TestWithParam<std::string> {};

// forest-100 and forest-1000 warned on every render before the render frame (their foliage,
// 0.29 units wide, sits 45-300 units from the origin and from any camera: spacing 2^-15.7 of a
// leaf, above the old 2^-16); the ogre of the issue was a downloaded model, not shipped.
TEST_P(ShippedScene, HasNoLowPrecisionLeaf) {
  ThreadLimit limit(2);
  const Scene scene = loadScene(testing::sourcePath("scenes/" + GetParam()));
  const RenderData data(scene);
  EXPECT_EQ(data.features.lowPrecisionLeaves, 0u) << "coarsest relative spacing " << data.features.coarsestRelativeSpacing;
  // A loaded scene's camera is the frame's origin.
  EXPECT_EQ(scene.camera.position, (Vec3{0, 0, 0}));
}

INSTANTIATE_TEST_SUITE_P(Scenes, ShippedScene, ::testing::ValuesIn(allShippedScenes()), [](const auto& info) {
  std::string n = info.param.substr(0, info.param.size() - 5);
  for (char& ch : n) if (ch == '-') ch = '_';
  return n;
});

// Positions are moved into the frame in double: a quad, a Bézier patch placed by a transform, a
// subdivision mesh and the lights written 10^7 out, with the camera beside them, land on the same
// floats as when written near the origin with the camera there (float spacing at 10^7 is 1,
// which would round the quad away entirely). The stats name the frame.
TEST(RenderFrame, PositionsAreCameraRelativeInDouble) {
  const auto text = [](double o) {
    const auto p = [&](double x, double y, double z) {
      return "[" + std::to_string(x + o) + ", " + std::to_string(y + o) + ", " + std::to_string(z + o) + "]";
    };
    return R"({"camera": {"position": )" + p(0.25, -3, 0.5) + R"(, "look_at": )" + p(0.25, 0, 0.5) +
           R"(, "up": [0, 0, 1]}, "materials": {"m": {"type": "diffuse", "albedo": 0.5}},
      "shapes": [{"type": "bilinear", "material": "m", "quads": [[)" + p(0, 0, 0) + ", " + p(0.5, 0, 0) + ", " +
           p(0, 0, 1) + ", " + p(0.5, 0, 1) + R"(]]},
                 {"type": "bezier", "material": "m", "transform": [{"translate": )" + p(0, 1, 0) + R"(}],
                  "patches": [[[0,0,0],[1,0,0],[2,0,0],[3,0,0],[0,1,0],[1,1,1],[2,1,1],[3,1,0],
                               [0,2,0],[1,2,1],[2,2,1],[3,2,0],[0,3,0],[1,3,0],[2,3,0],[3,3,0]]]},
                 {"type": "subdiv", "material": "m", "vertices": [)" + p(0, 5, 0) + ", " + p(1, 5, 0) + ", " +
           p(1, 6, 0.5) + ", " + p(0, 6, 0) + R"(], "faces": [[0, 1, 2, 3]]}],
      "lights": [{"type": "point", "position": )" + p(1, -1, 2) + R"(, "intensity": 1},
                 {"type": "rect", "corner": )" + p(0, 0, 3) + R"(, "edge_u": [1, 0, 0], "edge_v": [0, 1, 0], "radiance": 1}]})";
  };
  const Scene near = parseScene(text(0), "near.json"), far = parseScene(text(1e7), "far.json");
  EXPECT_EQ(far.frame.origin, (Vec3d{1e7 + 0.25, 1e7 - 3, 1e7 + 0.5}));
  EXPECT_EQ(far.camera.lookAt, near.camera.lookAt);
  ASSERT_EQ(far.leaves.size(), near.leaves.size());
  for (size_t i = 0; i < near.leaves.size(); ++i) {
    SCOPED_TRACE(i);
    EXPECT_EQ(far.leaves.bounds(i).lo, near.leaves.bounds(i).lo);
    EXPECT_EQ(far.leaves.bounds(i).hi, near.leaves.bounds(i).hi);
  }
  EXPECT_EQ(far.pointLights[0].position, near.pointLights[0].position);
  const nlohmann::json j = statsToJson(far, RenderOptions{}, RenderStats{}, RunInfo{"far.json", 1, 8, 6, 1, 0, 0});
  EXPECT_EQ(j["scene"]["render_frame_origin"], nlohmann::json::array({1e7 + 0.25, 1e7 - 3, 1e7 + 0.5}));
}

// The rule: a leaf is low-precision when its float spacing exceeds both 2^-16 of its size and
// 2^-8 of a camera pixel's footprint at its distance from the camera.
TEST(RenderFrame, LowPrecisionRuleAtItsEdges) {
  const float spread = 1e-3f;  // a pixel's angle
  const auto unitBoxAt = [](float d) { return Box3{{-0.5f, -0.5f, d}, {0.5f, 0.5f, d + 1}}; };
  // Near: 2^-16 of the leaf resolves it whatever the footprint.
  EXPECT_FALSE(isLowPrecisionLeaf(unitBoxAt(100), {0, 0, 0}, spread));
  // At 10^4: spacing 2^-9.7 of the leaf (above 2^-16) but 2^-7 below a footprint of 10 units.
  EXPECT_FALSE(isLowPrecisionLeaf(unitBoxAt(1e4f), {0, 0, 0}, spread));
  // A telephoto pixel (10^-7 rad) at 10^4: a footprint of 10^-3, spacing 1.2e-3: low.
  EXPECT_TRUE(isLowPrecisionLeaf(unitBoxAt(1e4f), {0, 0, 0}, 1e-7f));
  // The camera inside the box (footprint 0): the size rule alone.
  const Box3 big{{1e4f, 1e4f, 1e4f}, {1e4f + 0.5f, 1e4f + 0.5f, 1e4f + 0.5f}};
  EXPECT_TRUE(isLowPrecisionLeaf(big, {1e4f + 0.25f, 1e4f + 0.25f, 1e4f + 0.25f}, spread));
  // Degenerate boxes: a point (size 0) is low only away from the origin; empty is never.
  EXPECT_FALSE(isLowPrecisionLeaf(Box3{{0, 0, 0}, {0, 0, 0}}, {1, 1, 1}, spread));
  EXPECT_FALSE(isLowPrecisionLeaf(Box3{}, {0, 0, 0}, spread));
  // Huge scales stay finite: distances near 2^60 are taken in double.
  // (A leaf of 2^50 at 2^59: spacing 2^36, above 2^-16 of it.)
  const Box3 huge{{0x1p59f, 0x1p59f, 0x1p59f}, {0x1p59f + 0x1p50f, 0x1p59f + 0x1p50f, 0x1p59f + 0x1p50f}};
  EXPECT_FALSE(isLowPrecisionLeaf(huge, {-0x1p60f, -0x1p60f, -0x1p60f}, spread));
  EXPECT_TRUE(isLowPrecisionLeaf(huge, {-0x1p60f, -0x1p60f, -0x1p60f}, 0x1p-40f));
}

}  // namespace
}  // namespace rayes
