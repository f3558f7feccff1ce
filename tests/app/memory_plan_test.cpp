// The render's memory plan (app/memory_plan.h): the film's bytes per pixel are what the Film
// holds, the parts add up, and a plan over the limit names the option of its largest part.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include "app/memory_plan.h"
#include "app/renderer.h"
#include "core/error.h"
#include "core/memory.h"
#include "shading/film.h"

namespace rayes {
namespace {

TEST(MemoryPlan, FilmBytesPerPixelAreTheFilmsOwn) {
  EXPECT_EQ(Film(5, 3).bytes(), 15 * kFilmBytesPerPixel);
}

TEST(MemoryPlan, DiceBuffersScaleWithTheGridAndTheThreads) {
  EXPECT_EQ(diceBufferEstimate(10, 2), 2 * 1025 * 1025 * kDiceBytesPerVertex);
  EXPECT_EQ(diceBufferEstimate(0, 0), 4 * kDiceBytesPerVertex);  // 0 threads: one
}

TEST(MemoryPlan, PartsOfARenderAndTheOptionOfTheLargest) {
  Scene scene;
  scene.width = 16384;
  scene.height = 16384;
  RenderOptions options;
  options.method.name = "lbt";
  const RenderMemoryPlan p = planRenderMemory(scene, options, 1 << 20, 2);
  const uint64_t pixels = uint64_t(1) << 28;
  EXPECT_EQ(p.film, pixels * kFilmBytesPerPixel);
  EXPECT_EQ(p.outputs, pixels * kOutputBytesPerPixel);
  EXPECT_EQ(p.beams, options.method.beams.memoryBytes);
  EXPECT_EQ(p.gridCache, options.gridCacheBytes);
  EXPECT_EQ(p.total(), p.film + p.outputs + p.rays + p.diceBuffers + p.gridCache + p.beams);
  EXPECT_EQ(p.largestOption(), "--res");
  // 50 GiB: more than any machine this runs on has available (a test machine with more would
  // need a larger figure).
  ASSERT_GT(p.total(), readMemoryLimit().available);
  try {
    checkRenderMemory(p);
    FAIL();
  } catch (const ResourceError& e) {
    EXPECT_EQ(e.file(), "--res");
    EXPECT_THAT(e.what(), ::testing::HasSubstr("16384x16384"));
    EXPECT_THAT(e.what(), ::testing::HasSubstr("lower --res"));
  }
  RenderOptions embree;
  embree.engine = EngineKind::Embree;
  const RenderMemoryPlan q = planRenderMemory(scene, embree, 0, 2);
  EXPECT_EQ(q.diceBuffers, 0u);  // the Embree engine checks its own tessellation
  EXPECT_EQ(q.gridCache, 0u);
  EXPECT_EQ(q.beams, 0u);
}

}  // namespace
}  // namespace rayes
