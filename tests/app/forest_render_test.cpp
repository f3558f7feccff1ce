// The forest end to end: scenes/forest-1.json renders at a small resolution with both engines,
// which see the same micro-geometry at a fixed level (the SortedEngine makes each patch from
// its compact record when it dices it; the Embree engine tessellates every patch up front), so
// their image means agree within the noise; the memory of a render does not grow with the
// forest, only its scene description does, within the bound the loader refuses forests by; and
// the Embree engine refuses forest-100 up front, naming the memory it would need.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include "core/vector_isa.h"
#include "dicing/border_bound_cache.h"
#include "dicing/dice_buffer.h"
#include "geometry/forest_leaves.h"
#include "rays/trace_settings.h"
#include "rays/sorted_engine.h"
#include "support/render_fixtures.h"
#include "scene/scene_loader.h"

namespace rayes {
namespace {
namespace fs = std::filesystem;

Scene smallForest(int trees) {
  std::ifstream in(testing::sourcePath("scenes/forest-1.json"));
  std::stringstream text;
  text << in.rdbuf();
  std::string s = text.str();
  const std::string key = R"("trees": 1)";
  s.replace(s.find(key), key.size(), R"("trees": )" + std::to_string(trees));
  Scene scene = parseScene(s, "forest-" + std::to_string(trees) + ".json");
  scene.width = 32;
  scene.height = 24;
  scene.samplesPerPixel = 2;
  return scene;
}

double channelMean(const std::vector<float>& rgba, int c) {
  double sum = 0;
  for (size_t i = size_t(c); i < rgba.size(); i += 4) sum += rgba[i];
  return sum / double(rgba.size() / 4);
}

// Both engines at one fixed level: the same micro-quads, so the image means differ only by the
// crack-closing regions Rayes adds at borders (rare hits) and the noise. The noise's standard
// error is estimated from two seeds per engine, as in engine_test.cpp.
TEST(ForestRender, BothEnginesRenderForest1WithTheSameMean) {
  Scene scene = smallForest(1);
  RenderOptions rayes, embree;
  rayes.lod = embree.lod = LodRule::Fixed;
  rayes.maxLod = embree.maxLod = 4;
  embree.engine = EngineKind::Embree;
  double r[2][3], e[2][3];
  for (int k = 0; k < 2; ++k) {
    scene.integrator.seed = uint64_t(k + 1);
    const auto ir = testing::renderBeauty(scene, rayes, 2), ie = testing::renderBeauty(scene, embree, 2);
    for (int c = 0; c < 3; ++c) {
      r[k][c] = channelMean(ir, c);
      e[k][c] = channelMean(ie, c);
    }
  }
  for (int c = 0; c < 3; ++c) {
    const double mr = 0.5 * (r[0][c] + r[1][c]), me = 0.5 * (e[0][c] + e[1][c]);
    const double dr = r[0][c] - r[1][c], de = e[0][c] - e[1][c];
    const double se = std::sqrt((dr * dr + de * de) / 4);
    EXPECT_GT(mr, 0.0) << "channel " << c;  // sky, sun and the tree are seen
    EXPECT_NEAR(me, mr, 4 * se) << "channel " << c;
  }
}

TEST(ForestRender, ImageIsTheSameOnAnyThreadCountAndBudget) {
  testing::expectOrderIndependent(smallForest(1), 97);
}

// The row kernels (value noise, displaced base frames) run on AVX2 or on the baseline
// (core/vector_isa.h): the image is the same bits on both, so it does not depend on the CPU.
TEST(ForestRender, ImageIsTheSameOnEveryInstructionSet) {
  if (!cpuHasAvx2()) GTEST_SKIP() << "this CPU runs the baseline kernels only";
  const Scene scene = smallForest(1);
  auto render = [&](VectorIsa isa) {
    ScopedVectorIsa scoped(isa);
    return testing::renderBeauty(scene, RenderOptions{}, 2);
  };
  const std::vector<float> base = render(VectorIsa::Baseline), avx2 = render(VectorIsa::Avx2);
  ASSERT_EQ(base.size(), avx2.size());
  EXPECT_EQ(0, std::memcmp(base.data(), avx2.data(), base.size() * sizeof(float)));
}

// Memory by owner: a forest of 6 trees against one, at the same image settings. What a render
// holds for rays, candidates and the film is the same; the dice buffers are at most one per
// thread whatever the forest, the grid cache within its budget; only the scene description and
// the top level grow, by at most the bytes per leaf the loader assumes when it refuses a forest
// too large to describe, and the border-bound table, by a fixed count per leaf up to its cap.
TEST(ForestRender, MemoryGrowsOnlyWithTheSceneDescription) {
  const Scene one = smallForest(1), six = smallForest(6);
  ASSERT_GT(six.leaves.size(), 5 * one.leaves.size() / 2);
  auto memoryOf = [](const Scene& s) {
    ThreadLimit limit(2);
    Renderer r(s, RenderOptions{});
    r.render();
    return r.stats().memory;
  };
  const MemoryByOwner a = memoryOf(one), b = memoryOf(six);
  EXPECT_EQ(a.rayBuffers, b.rayBuffers);
  EXPECT_EQ(a.candidatesAndSort, b.candidatesAndSort);
  EXPECT_EQ(a.film, b.film);
  EXPECT_LE(a.diceCache, RenderOptions{}.gridCacheBytes);  // bounded whatever the forest
  EXPECT_LE(b.diceCache, RenderOptions{}.gridCacheBytes);
  const size_t oneBuffer = DiceBuffer(RenderOptions{}.maxLod).bytesAllocated();
  EXPECT_LE(a.diceBuffers, 2 * oneBuffer);
  EXPECT_LE(b.diceBuffers, 2 * oneBuffer);
  // The border bounds kept across dicings: one table of SortedEngine::kBorderBoundsPerLeaf entries per
  // leaf (a power of two), never more than TraceSettings::borderBoundEntries, and the displaced
  // seams' gaps (the bark's rings are displaced), kSeamGapsPerLeaf entries per leaf, never more
  // than 1/kSeamGapShare of that.
  for (const MemoryByOwner* m : {&a, &b}) {
    const size_t cap = TraceSettings{}.borderBoundEntries;
    const size_t entries = std::bit_ceil(std::min(cap, m->leaves * SortedEngine::kBorderBoundsPerLeaf));
    const size_t seamGaps =
        std::bit_ceil(std::min(cap / SortedEngine::kSeamGapShare, m->leaves * SortedEngine::kSeamGapsPerLeaf));
    EXPECT_EQ(m->borderBounds, (entries + seamGaps) * BorderBoundCache::entryBytes()) << m->leaves << " leaves";
  }
  EXPECT_GT(b.borderBounds, a.borderBounds);
  for (const MemoryByOwner* m : {&a, &b}) {
    EXPECT_GT(m->sceneDescription, 0u);
    EXPECT_LE(m->sceneDescription + m->topLevel, kForestBoundBytesPerLeaf * m->leaves) << m->leaves << " leaves";
  }
}

TEST(ForestRender, EmbreeRefusesForest100UpFrontNamingTheMemoryItNeeds) {
  const fs::path dir = fs::temp_directory_path() / ("rayes-forest-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const testing::RunResult r =
      testing::runRayes({"render", testing::sourcePath("scenes/forest-100.json"), "-o", (dir / "o.exr").string(),
                         "-q", "--res", "8x4", "--spp", "1", "--engine", "embree", "--memory-limit", "64G"});
  EXPECT_EQ(r.code, 3);  // a resource limit
  EXPECT_THAT(r.err, ::testing::HasSubstr("--memory-limit"));
  EXPECT_THAT(r.err, ::testing::HasSubstr("full tessellation needs about"));
  EXPECT_TRUE(fs::is_empty(dir));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace rayes
