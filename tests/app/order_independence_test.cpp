// docs/design.md, invariant 2: the image is a pure function of (scene, settings, seed). With the
// default per-ray level of detail it must be bit-identical for any thread count, with the
// debug mode that traces every ray alone (no sorting, each patch diced per ray), and for ray
// memory budgets that force different batch sizes and numbers of iterations, and in progressive
// passes.
#include <gtest/gtest.h>
#include "support/render_fixtures.h"

namespace rayes {
namespace {
using testing::renderBeauty;
using testing::smallTeapot;
using testing::bytesPerPath;

class OrderIndependence : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scene_ = new Scene(smallTeapot());
    reference_ = new std::vector<float>(renderBeauty(*scene_, RenderOptions{}, 2, &referenceStats_));
  }
  static void TearDownTestSuite() { delete scene_; delete reference_; }
  static Scene* scene_;
  static std::vector<float>* reference_;
  static RenderStats referenceStats_;
};
Scene* OrderIndependence::scene_ = nullptr;
std::vector<float>* OrderIndependence::reference_ = nullptr;
RenderStats OrderIndependence::referenceStats_;

// The image the other tests compare against is the teapot, not just bit-identical noise.
// Reference: `bench_app_channel_means scenes/teapot.json 48 36 2 24`.
TEST_F(OrderIndependence, ImageChannelMeansInMeasuredRange) {
  testing::expectChannelMeans(*reference_, {{0.307819, 0.257822, 0.175309}, {0.003302, 0.002730, 0.001750}},
                              "teapot 48x36, 2 spp");
}

TEST_F(OrderIndependence, OneThreadEqualsTwoThreads) {
  EXPECT_EQ(renderBeauty(*scene_, RenderOptions{}, 1), *reference_);
}

TEST_F(OrderIndependence, EveryRayTracedAloneEqualsSortedPipeline) {
  RenderOptions o;
  o.sortByLeaf = false;
  EXPECT_EQ(renderBeauty(*scene_, o, 2), *reference_);
}

TEST_F(OrderIndependence, SmallRayMemoryForcesMoreBatchesAndIterationsButSameImage) {
  RenderOptions o;
  o.rayMemoryBytes = 300 * bytesPerPath(*scene_);  // 300 paths per batch, N small
  RenderStats small;
  EXPECT_EQ(renderBeauty(*scene_, o, 2, &small), *reference_);
  // The budget really did change how the work was split.
  EXPECT_GT(small.batches, referenceStats_.batches);
  size_t maxIterSmall = 0, maxIterRef = 0;
  for (const auto& g : small.generations) maxIterSmall = std::max(maxIterSmall, g.stats.iterations.size());
  for (const auto& g : referenceStats_.generations) maxIterRef = std::max(maxIterRef, g.stats.iterations.size());
  EXPECT_GT(maxIterSmall + small.batches, maxIterRef + referenceStats_.batches);
}

// Batches by pixel blocks (a pass that needs several batches): every sample of as many pixels
// as fit, here 7 pixels of 48x36 (a block count that does not divide the image), against the
// reference's one batch of sample-major ids.
TEST_F(OrderIndependence, BatchesByPixelBlocksGiveTheSameImage) {
  RenderOptions o;
  o.rayMemoryBytes = 14 * bytesPerPath(*scene_);  // 2 spp: 7 pixels per batch
  RenderStats blocks;
  EXPECT_EQ(renderBeauty(*scene_, o, 2, &blocks), *reference_);
  EXPECT_EQ(blocks.pixelsPerBlock, 7u);
  EXPECT_EQ(blocks.batches, (48u * 36u + 6u) / 7u);
  EXPECT_EQ(referenceStats_.pixelsPerBlock, 0u);
}

TEST_F(OrderIndependence, ProgressivePassesGiveTheSameImageAsOnePass) {
  RenderOptions o;
  o.progressive = true;
  RenderStats progressive;
  EXPECT_EQ(renderBeauty(*scene_, o, 2, &progressive), *reference_);
  // 2 spp: passes of 1 and 1 sample, against one pass of both.
  EXPECT_EQ(progressive.generations.back().pass, 1);
  EXPECT_EQ(referenceStats_.generations.back().pass, 0);
}

TEST_F(OrderIndependence, TinyCandidateBufferOneCandidatePerIteration) {
  // With a budget of a single path's worth of memory per batch the candidate buffer holds a
  // handful of slots: every iteration sees N = 1..4, the extreme of Table 6.3.
  Scene s = smallTeapot(8, 6, 1);
  const auto ref = renderBeauty(s, RenderOptions{}, 2);
  RenderOptions o;
  o.rayMemoryBytes = bytesPerPath(s);
  RenderStats stats;
  EXPECT_EQ(renderBeauty(s, o, 2, &stats), ref);
  bool sawN1 = false;
  for (const auto& g : stats.generations)
    for (const auto& it : g.stats.iterations) sawN1 |= it.candidatesPerRay <= 4;
  EXPECT_TRUE(sawN1);
}

}  // namespace
}  // namespace rayes
