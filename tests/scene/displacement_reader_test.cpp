// The "displacement" modifier of shapes (docs/scene-format.md): noise and OpenEXR height maps,
// and their errors (a missing or unreadable height map names the file and the JSON pointer).
#include <gtest/gtest.h>
#include <gmock/gmock.h>
#include <filesystem>
#include <unistd.h>
#include "core/error.h"
#include "geometry/displaced_patch.h"
#include "scene/scene_loader.h"
#include "scene_text.h"
#include "support/exr_test_file.h"
#include "support/temp_folder.h"

namespace rayes {
namespace {
using ::testing::HasSubstr;

using test::errorOf;

using testing::writeOneChannelExr;

TEST(DisplacementReader, NoiseWrapsEveryPatch) {
  const Scene s = parseScene(test::minimalScene(R"(, "displacement": {"type": "noise", "amplitude": 0.5, "frequency": 2,
      "octaves": 3, "ridged": true, "seed": 4})"), "ok.json");
  ASSERT_EQ(s.leaves.size(), 1u);
  EXPECT_STREQ(s.leaves.patch(0)->kind(), "displaced-bilinear");
  const Box3 b = s.leaves.patch(0)->bounds();
  const float z0 = float(-s.frame.origin.z);  // the quad's plane z = 0, in the render frame
  EXPECT_GT(b.hi.z, z0);
  EXPECT_LE(b.hi.z, z0 + 0.51f);
  EXPECT_GE(b.lo.z, z0 - 0.01f);  // ridged noise is in [0, 1]
}

TEST(DisplacementReader, TransformedShapeKeepsItsPattern) {
  const std::string d = R"(, "displacement": {"type": "noise", "amplitude": 0.3, "frequency": 3})";
  const Scene a = parseScene(test::minimalScene(d), "a.json");
  const Scene b = parseScene(test::minimalScene(R"(, "transform": [{"translate": [50, 0, 0]}])" + d), "b.json");
  for (float u : {0.2f, 0.6f}) {
    const Vec3 pa = a.leaves.patch(0)->evaluate(u, 0.4f).p, pb = b.leaves.patch(0)->evaluate(u, 0.4f).p;
    EXPECT_NEAR(pa.z, pb.z, 1e-5f);
    EXPECT_TRUE(b.leaves.patch(0)->bounds().contains(pb));
  }
}

TEST(DisplacementReader, HeightMapFromExr) {
  const testing::TempFolder temp;
  const auto& dir = temp.dir();
  writeOneChannelExr((dir / "h.exr").string(), 4, 3, "Y", {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11});
  const Scene s = parseScene(test::minimalScene(R"(, "displacement": {"type": "image", "file": ")" + (dir / "h.exr").string() +
                                       R"(", "amplitude": 0.1, "offset": -0.5})"),
                             "ok.json");
  ASSERT_EQ(s.leaves.size(), 1u);
  const auto* d = dynamic_cast<const DisplacedPatch*>(s.leaves.patch(0).get());
  ASSERT_NE(d, nullptr);
  EXPECT_STREQ(d->displacement().kind(), "image");
  // The first texel row is v = 0; the corner (0, 0) reads texel (0, 0) = 0: h = -0.5.
  const float z0 = float(-s.frame.origin.z);  // the quad's plane z = 0, in the render frame
  EXPECT_NEAR(s.leaves.patch(0)->evaluate(0, 0).p.z, z0 - 0.5f, 1e-5f);
  EXPECT_NEAR(s.leaves.patch(0)->evaluate(1, 1).p.z, z0 - 0.5f + 1.1f, 1e-5f);
  // Its texels came through the scene's texture cache (one image, tiles read).
  ASSERT_TRUE(s.textures);
  EXPECT_EQ(s.textures->stats().files, 1u);
  EXPECT_GT(s.textures->stats().tilesRead, 0u);
  // A relative name is relative to the scene file.
  const std::string scenePath = (dir / "scene.json").string();
  FILE* f = std::fopen(scenePath.c_str(), "w");
  const std::string text = test::minimalScene(R"(, "displacement": {"type": "image", "file": "h.exr", "channel": "Y"})");
  std::fwrite(text.data(), 1, text.size(), f);
  std::fclose(f);
  EXPECT_STREQ(loadScene(scenePath).leaves.patch(0)->kind(), "displaced-bilinear");
  std::filesystem::remove_all(dir);
}

TEST(DisplacementReader, MissingHeightMapNamesTheFileAndPlace) {
  const std::string e = errorOf(test::minimalScene(R"(, "displacement": {"type": "image", "file": "no-such-map.exr"})"));
  EXPECT_THAT(e, HasSubstr("bad.json:"));
  EXPECT_THAT(e, HasSubstr("/shapes/0/displacement/file"));
  EXPECT_THAT(e, HasSubstr("no-such-map.exr"));
}

TEST(DisplacementReader, UnreadableHeightMapNamesTheFile) {
  const testing::TempFolder temp;
  const auto& dir = temp.dir();
  const std::string path = (dir / "broken.exr").string();
  FILE* f = std::fopen(path.c_str(), "w");
  std::fputs("not an exr", f);
  std::fclose(f);
  const std::string e = errorOf(test::minimalScene(R"(, "displacement": {"type": "image", "file": ")" + path + R"("})"));
  EXPECT_THAT(e, HasSubstr("cannot read height map"));
  EXPECT_THAT(e, HasSubstr("broken.exr"));
  writeOneChannelExr((dir / "rgb.exr").string(), 2, 2, "G", {0, 1, 2, 3});
  const std::string e2 = errorOf(test::minimalScene(R"(, "displacement": {"type": "image", "file": ")" + (dir / "rgb.exr").string() +
                                           R"(", "channel": "Z"})"));
  EXPECT_THAT(e2, HasSubstr("no channel 'Z'"));
  std::filesystem::remove_all(dir);
}

TEST(DisplacementReader, BadParametersAreInputErrors) {
  EXPECT_THAT(errorOf(test::minimalScene(R"(, "displacement": {"type": "noise", "frequency": 0})")),
              HasSubstr("/shapes/0/displacement/frequency"));
  EXPECT_THAT(errorOf(test::minimalScene(R"(, "displacement": {"type": "noise", "octaves": 40})")),
              HasSubstr("/shapes/0/displacement/octaves"));
  EXPECT_THAT(errorOf(test::minimalScene(R"(, "displacement": {"type": "noise", "amplitud": 1})")),
              HasSubstr("unknown key 'amplitud'"));
  EXPECT_THAT(errorOf(test::minimalScene(R"(, "displacement": {"type": "bumps"})")),
              HasSubstr("unknown displacement type 'bumps'"));
  EXPECT_THAT(errorOf(test::minimalScene(R"(, "displacement": 3)")), HasSubstr("/shapes/0/displacement"));
}

}  // namespace
}  // namespace rayes
