// The scene format v1 (docs/scene-format.md) and its errors: every bad input names the file,
// the line:column and the JSON pointer of the offending value.
#include <gtest/gtest.h>
#include <gmock/gmock.h>
#include "core/error.h"
#include "scene/scene_loader.h"
#include "scene_text.h"

namespace rayes {
namespace {
using ::testing::HasSubstr;

using test::errorOf;
const std::string kMinimal = test::minimalScene();

std::string replaced(std::string s, const std::string& from, const std::string& to) {
  const auto at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return s.replace(at, from.size(), to);
}

TEST(SceneLoader, MinimalSceneLoads) {
  const Scene s = parseScene(kMinimal, "ok.json");
  EXPECT_EQ(s.width, 32);
  EXPECT_EQ(s.height, 24);
  EXPECT_EQ(s.samplesPerPixel, 4);
  ASSERT_EQ(s.leaves.size(), 1u);
  EXPECT_STREQ(s.leaves.patch(0)->kind(), "bilinear");
}

TEST(SceneLoader, ShippedScenesLoad) {
  const Scene teapot = loadScene(std::string(RAYES_SOURCE_DIR) + "/scenes/teapot.json");
  EXPECT_EQ(teapot.leaves.size(), 32u + 6u + 1u);  // teapot, box, the rect light
  const Scene one = loadScene(std::string(RAYES_SOURCE_DIR) + "/scenes/one-patch.json");
  EXPECT_EQ(one.leaves.size(), 2u);
  EXPECT_EQ(one.pointLights.size(), 1u);
}

TEST(SceneLoader, TransformsApplyInOrder) {
  const std::string t = replaced(kMinimal, R"("quads")",
                                 R"("transform": [{"scale": 2}, {"translate": [0, 0, 5]}], "quads")");
  const Scene s = parseScene(t, "t.json");
  const Box3 b = s.leaves.patch(0)->bounds();  // in the render frame: world minus the camera
  EXPECT_NEAR(b.lo.x, -2.0 - s.frame.origin.x, 1e-3);
  EXPECT_NEAR(b.hi.z, 5.0 - s.frame.origin.z, 1e-3);
}

TEST(SceneLoader, SyntaxErrorNamesLineAndColumn) {
  const std::string t = replaced(kMinimal, R"("fov": 40})", R"("fov": 40,})");
  EXPECT_THAT(errorOf(t), HasSubstr("bad.json:2:"));
  EXPECT_THAT(errorOf(t), HasSubstr("syntax error"));
}

TEST(SceneLoader, UnknownKeyNamesPlace) {
  const std::string t = replaced(kMinimal, R"("fov": 40)", R"("fvo": 40)");
  const std::string e = errorOf(t);
  EXPECT_THAT(e, HasSubstr("bad.json:2:"));
  EXPECT_THAT(e, HasSubstr("/camera/fvo"));
  EXPECT_THAT(e, HasSubstr("unknown key"));
}

TEST(SceneLoader, WrongTypeNamesPlace) {
  const std::string e = errorOf(replaced(kMinimal, R"("spp": 4)", R"("spp": "4")"));
  EXPECT_THAT(e, HasSubstr("bad.json:3:"));
  EXPECT_THAT(e, HasSubstr("/film/spp: expected an integer, got string"));
}

TEST(SceneLoader, ImpossibleValuesAreRejected) {
  EXPECT_THAT(errorOf(replaced(kMinimal, R"("spp": 4)", R"("spp": 0)")), HasSubstr("/film/spp"));
  EXPECT_THAT(errorOf(replaced(kMinimal, R"("spp": 4)", R"("spp": -2)")), HasSubstr("/film/spp"));
  EXPECT_THAT(errorOf(replaced(kMinimal, "[32, 24]", "[0, 24]")), HasSubstr("/film/resolution"));
  EXPECT_THAT(errorOf(replaced(kMinimal, "[32, 24]", "[32, -1]")), HasSubstr("/film/resolution"));
  EXPECT_THAT(errorOf(replaced(kMinimal, R"("up": [0, 0, 1])", R"("up": [0, 3, -1])")),
              HasSubstr("looks along its up vector"));
  EXPECT_THAT(errorOf(replaced(kMinimal, R"("look_at": [0, 0, 0])", R"("look_at": [0, -3, 1])")),
              HasSubstr("/camera/look_at"));
  EXPECT_THAT(errorOf(replaced(kMinimal, R"("fov": 40)", R"("fov": 180)")), HasSubstr("/camera/fov"));
  EXPECT_THAT(errorOf(replaced(kMinimal, "[0.5, 0.5, 0.5]", "[0.5, 1.5, 0.5]")), HasSubstr("/materials/m/albedo"));
  EXPECT_THAT(errorOf(replaced(kMinimal, R"("material": "m")", R"("material": "nope")")),
              HasSubstr("no material named 'nope'"));
  EXPECT_THAT(errorOf(replaced(kMinimal, R"("type": "diffuse")", R"("type": "velvet")")),
              HasSubstr("unknown material type 'velvet'"));
  EXPECT_THAT(errorOf(replaced(kMinimal, R"("type": "bilinear")", R"("type": "nurbs")")),
              HasSubstr("/shapes/0/type"));
}

TEST(SceneLoader, MissingFilesAreNamed) {
  try {
    loadScene("/nonexistent/scene.json");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_THAT(e.message(), HasSubstr("/nonexistent/scene.json"));
  }
  const std::string t = replaced(kMinimal, R"({"type": "bilinear", "material": "m", "quads": [[[-1,-1,0],[1,-1,0],[-1,1,0],[1,1,0]]]})",
                                 R"({"type": "bezier", "material": "m", "file": "missing.bpt"})");
  const std::string e = errorOf(t);
  EXPECT_THAT(e, HasSubstr("/shapes/0/file"));
  EXPECT_THAT(e, HasSubstr("missing.bpt"));
}

}  // namespace
}  // namespace rayes
