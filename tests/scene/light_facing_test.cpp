// A one-sided area light that faces away from every shape lights nothing; the usual cause is a
// rect light whose edges were given in the other order (it emits toward edge_u x edge_v). The
// loader notes it in Scene::warnings (the program prints them), naming the file, the place and
// the light; a light that faces any part of the scene, or is two-sided, gets none.
#include <filesystem>
#include <string>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include "scene/scene_loader.h"

namespace rayes {
namespace {
using ::testing::HasSubstr;

// A floor at z = 0 (x, y in [-1, 1]) and the lights given, one per line from line 6 on.
std::string sceneWith(const std::string& lights) {
  return "{\"camera\": {\"position\": [0, -3, 1], \"look_at\": [0, 0, 0], \"up\": [0, 0, 1]},\n"
         "\"film\": {\"resolution\": [8, 6], \"spp\": 1},\n"
         "\"materials\": {\"m\": {\"type\": \"diffuse\", \"albedo\": 0.5}},\n"
         "\"shapes\": [{\"type\": \"bilinear\", \"material\": \"m\", \"quads\": [[[-1,-1,0],[1,-1,0],[-1,1,0],[1,1,0]]]}],\n"
         "\"lights\": [\n" + lights + "]}\n";
}

// Above the floor at z = 2: edges x then y emit toward +z (away), y then x toward -z (the floor).
const std::string kRectUp = R"({"type": "rect", "corner": [-0.5, -0.5, 2], "edge_u": [1, 0, 0], "edge_v": [0, 1, 0], "radiance": 5})";
const std::string kRectDown = R"({"type": "rect", "corner": [-0.5, -0.5, 2], "edge_u": [0, 1, 0], "edge_v": [1, 0, 0], "radiance": 5})";

TEST(LightFacing, ARectLightWithItsEdgesSwappedIsNamed) {
  const Scene s = parseScene(sceneWith("  " + kRectDown + ",\n  " + kRectUp + "\n"), "room.json");
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_THAT(s.warnings[0], HasSubstr("room.json:7:"));
  EXPECT_THAT(s.warnings[0], HasSubstr("/lights/1: this rect light emits away from every shape"));
  EXPECT_THAT(s.warnings[0], HasSubstr("swap edge_u and edge_v"));
}

TEST(LightFacing, LightsThatFaceTheSceneOrAreTwoSidedAreNotNamed) {
  const std::string twoSided = R"({"type": "rect", "corner": [-0.5, -0.5, 2], "edge_u": [1, 0, 0], "edge_v": [0, 1, 0], "radiance": 5, "two_sided": true})";
  // Facing away from the floor's centre but toward a part of it: it lights that part.
  const std::string grazing = R"({"type": "rect", "corner": [0.9, -0.5, 0.5], "edge_u": [0, 1, 0], "edge_v": [0.1, 0, 1], "radiance": 5})";
  const std::string diskDown = R"({"type": "disk", "center": [0, 0, 2], "normal": [0, 0, -1], "radius": 0.5, "radiance": 5})";
  const Scene s = parseScene(sceneWith(kRectDown + ",\n" + twoSided + ",\n" + grazing + ",\n" + diskDown + "\n"), "ok.json");
  EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
}

TEST(LightFacing, ADiskLightFacingAwayIsNamed) {
  const std::string diskUp = R"({"type": "disk", "center": [0, 0, 2], "normal": [0, 0, 1], "radius": 0.5, "radiance": 5})";
  const Scene s = parseScene(sceneWith(diskUp + "\n"), "d.json");
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_THAT(s.warnings[0], HasSubstr("/lights/0: this disk light emits away from every shape"));
}

// On the scene's boundary facing out (a ceiling light above everything, facing up): lights nothing.
TEST(LightFacing, ALightInTheBoxsFaceFacingOutIsNamed) {
  const std::string onFloorFacingDown = R"({"type": "rect", "corner": [-0.5, -0.5, 0], "edge_u": [0, 1, 0], "edge_v": [1, 0, 0], "radiance": 5})";
  const Scene s = parseScene(sceneWith(onFloorFacingDown + "\n"), "f.json");
  EXPECT_EQ(s.warnings.size(), 1u);
}

}  // namespace
}  // namespace rayes
