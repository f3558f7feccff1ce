// The `forest` shape kind (docs/scene-format.md): a shipped forest loads as generated leaves
// (leaf ids after the shapes before it), each part gets its own material, every patch the scene
// hands out lies inside the box the scene recorded for it, and the same file gives the same
// leaves on any thread count.
#include <gtest/gtest.h>
#include <cstring>
#include <set>
#include <tbb/global_control.h>
#include "geometry/forest_leaves.h"
#include "scene/scene_loader.h"
#include "scene_text.h"
#include "support/patch_test_util.h"

namespace rayes {
namespace {

const std::string kForest1 = std::string(RAYES_SOURCE_DIR) + "/scenes/forest-1.json";

TEST(ForestShape, ShippedForestLoadsAsGeneratedLeavesWithAMaterialPerPart) {
  const Scene s = loadScene(kForest1);
  ForestParams p;
  p.trees = 1;
  p.detail = 3;
  p.terrainTiles = 4;
  ASSERT_EQ(s.leaves.size(), Forest::leafCount(p));
  ASSERT_EQ(s.leafMaterial.size(), s.leaves.size());
  // Materials in file order: bark 0, foliage 1, ground 2; leaves in forest order: terrain first.
  std::set<std::pair<std::string, uint32_t>> kindMaterial;
  for (size_t i = 0; i < s.leaves.size(); ++i) kindMaterial.insert({s.leaves.facts(i).kind, s.leafMaterial[i]});
  const std::set<std::pair<std::string, uint32_t>> expected = {
      {"displaced-bilinear", 2}, {"displaced-bezier", 0}, {"bilinear", 1}};
  EXPECT_EQ(kindMaterial, expected);
}

TEST(ForestShape, EveryPatchTheSceneMakesLiesInsideItsRecordedBound) {
  const Scene s = loadScene(kForest1);
  test::Random rnd(11);
  for (size_t i = 0; i < s.leaves.size(); ++i) {
    const PatchPtr patch = s.leaves.patch(i);
    const Box3 box = s.leaves.bounds(i);
    for (int k = 0; k < 16; ++k) {
      const SurfacePoint sp = patch->evaluate(rnd.uniform(), rnd.uniform());
      ASSERT_TRUE(box.contains(sp.p)) << "leaf " << i << " (" << patch->kind() << ")";
    }
  }
}

TEST(ForestShape, ForestAfterAShapeTakesTheIdsAfterIt) {
  const std::string text = test::minimalScene() ;
  const std::string withForest = text.substr(0, text.rfind("}]")) +
      R"(}, {"type": "forest", "detail": 1, "materials": {"terrain": "m", "bark": "m", "foliage": "m"}}]})";
  const Scene s = parseScene(withForest, "mixed.json");
  ForestParams p;
  p.detail = 1;
  ASSERT_EQ(s.leaves.size(), 1 + Forest::leafCount(p));
  EXPECT_STREQ(s.leaves.facts(0).kind, "bilinear");
  EXPECT_EQ(s.leaves.patch(0)->evaluate(1, 1).p.x, 1.0f);  // the quad stays leaf 0
  EXPECT_STREQ(s.leaves.facts(1).kind, "displaced-bilinear");  // the forest's first terrain tile
}

TEST(ForestShape, SameFileSameLeavesOnAnyThreadCount) {
  auto boxes = [](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
    const Scene s = loadScene(kForest1);
    std::vector<Box3> b;
    for (size_t i = 0; i < s.leaves.size(); ++i) b.push_back(s.leaves.bounds(i));
    return b;
  };
  const std::vector<Box3> one = boxes(1), two = boxes(2);
  ASSERT_EQ(one.size(), two.size());
  EXPECT_EQ(std::memcmp(one.data(), two.data(), one.size() * sizeof(Box3)), 0);
}

}  // namespace
}  // namespace rayes
