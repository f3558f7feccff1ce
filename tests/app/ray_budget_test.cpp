// The default ray memory budget (renderer.h, defaultRayMemoryBytes): an eighth of the
// machine, never below 256 MiB nor above 2 GiB (peak memory under 4 GiB), 1 GiB when the
// machine's size is unknown. What one path of it costs: the integrator's state and its ray
// slots, each the RayBatch's record and hit and the engine's state and candidate slots.
#include <algorithm>
#include <gtest/gtest.h>
#include "app/renderer.h"
#include "core/ray_batch.h"
#include "rays/sorted_engine.h"
#include "shading/path_tracer.h"
#include "support/render_fixtures.h"

namespace rayes {
namespace {
constexpr uint64_t kMiB = uint64_t(1) << 20, kGiB = uint64_t(1) << 30;

TEST(DefaultRayBudget, AnEighthOfTheMachineWithinTheBounds) {
  EXPECT_EQ(defaultRayMemoryBytes(8 * kGiB), kGiB);
  EXPECT_EQ(defaultRayMemoryBytes(12 * kGiB), 1536 * kMiB);
  EXPECT_EQ(defaultRayMemoryBytes(1 * kGiB), 256 * kMiB);   // small machine: the floor
  EXPECT_EQ(defaultRayMemoryBytes(64 * kGiB), 2 * kGiB);    // large machine: the cap
  EXPECT_EQ(defaultRayMemoryBytes(16 * kGiB + 8), 2 * kGiB);
}

TEST(DefaultRayBudget, UnknownMachineSizeGivesOneGiB) { EXPECT_EQ(defaultRayMemoryBytes(0), kGiB); }

TEST(DefaultRayBudget, IsTheRenderOptionsDefault) {
  EXPECT_EQ(RenderOptions{}.rayMemoryBytes, defaultRayMemoryBytes());
  EXPECT_LE(RenderOptions{}.rayMemoryBytes, 2 * kGiB);
}

// A pt path of a scene where nothing moves and no texture is read: 45 bytes of path state (one
// byte of flags; no first hit: the AOVs get it when the camera rays are shaded, kept meanwhile in
// the spent hit), a pair of ray slots, each a 36-byte ray, half of the pair's 28-byte hit and
// 4-byte occluder (the shadow slot keeps no hit), 12 bytes of trace state and one candidate slot
// (its leaf and its place in the sort's order, 8 bytes); and the batch's sort scratch, 8 bytes:
// the candidate sort's 4 per candidate slot and the shading sort's 8-byte item per path are one
// buffer, taken in turn, counted once. The candidate buffer holds one slot per ray slot of the
// batch.
TEST(RayBudget, APathCostsItsStateAndTwoCompactRaySlots) {
  const Scene scene = testing::smallTeapot();
  const Renderer r(scene, RenderOptions{});
  ASSERT_EQ(r.stats().features.movingLeaves, 0u);  // no shutter time per slot
  ASSERT_EQ(r.stats().features.texturedMaterials, 0u);  // no surface derivatives per slot
  EXPECT_EQ(sizeof(Ray), 36u);
  EXPECT_EQ(SortedEngine::bytesPerRayState(), 12u);
  EXPECT_EQ(RayBatch::bytesPerRay(false, false, true) + SortedEngine::bytesPerRaySlot(LodRule::PerRay),
            36u + 16u + 12u + 8u);
  EXPECT_EQ(PathBatch::bytesPerPath(), 45u);
  EXPECT_EQ(SortedEngine::sortScratchBytesPerRaySlot(LodRule::PerRay), 4u);
  EXPECT_EQ(r.stats().bytesPerPath, 45u + 2 * (36u + 16u + 12u + 8u) + 8u);
  EXPECT_EQ(r.stats().candidateCapacity, r.stats().pathsPerBatch * 2);
  EXPECT_EQ(r.stats().memory.candidatesAndSort, r.stats().pathsPerBatch * (2 * (12u + 8u) + 8u));
  EXPECT_EQ(r.stats().memory.rayBuffers, r.stats().pathsPerBatch * (45u + 2 * (36u + 16u)));
  EXPECT_EQ(r.stats().memory.rayBuffers + r.stats().memory.candidatesAndSort,
            r.stats().pathsPerBatch * r.stats().bytesPerPath);
}

// The sort scratch is counted as the larger of the two sorts' needs: an engine without a
// candidate sort (Embree, the dice cache) leaves the shading sort's 8 bytes per path, and the
// sorted engine's 2 x 4 bytes of candidate-sort scratch per path add nothing to them.
TEST(RayBudget, TheCandidateSortAndTheShadingSortShareOneScratch) {
  const Scene scene = testing::smallTeapot();
  RenderOptions embree, caching;
  embree.engine = EngineKind::Embree;
  caching.diceCacheEntries = 16;
  const Renderer sorted(scene, RenderOptions{}), e(scene, embree), c(scene, caching);
  const uint64_t shadingSort = 8, slots = 2;
  EXPECT_EQ(e.stats().bytesPerPath, 45u + slots * (36u + 16u) + shadingSort);
  EXPECT_EQ(c.stats().bytesPerPath, 45u + slots * (36u + 16u + 4u) + shadingSort);  // the active list
  EXPECT_EQ(sorted.stats().bytesPerPath - e.stats().bytesPerPath, slots * SortedEngine::bytesPerRaySlot(LodRule::PerRay));
  EXPECT_EQ(e.stats().memory.candidatesAndSort, e.stats().pathsPerBatch * shadingSort);
}

// bytes_per_ray (the stats' memory.bytes_per_ray, per ray slot) of pt with the AOVs the EXR
// writes, and without them (a PNG preview alone: RenderOptions::firstHitAovs), pinned so that a
// slot growing again is caught: the same, as the first hits go to the film when the camera rays
// are shaded; the image's radiance is the same either way, and only the first film has AOVs.
TEST(RayBudget, APtPathKeepsNoFirstHitWithOrWithoutAovs) {
  const Scene scene = testing::smallTeapot();
  RenderOptions without;
  without.firstHitAovs = false;
  Renderer withAovs(scene, RenderOptions{}), noAovs(scene, without);
  EXPECT_EQ(withAovs.stats().bytesPerPath / withAovs.stats().raysPerPath, 98u);
  EXPECT_EQ(noAovs.stats().bytesPerPath, withAovs.stats().bytesPerPath);
  const Film a = withAovs.render(), b = noAovs.render();
  EXPECT_EQ(a.sums().rgb, b.sums().rgb);
  EXPECT_EQ(a.sums().count, b.sums().count);
  EXPECT_GT(*std::max_element(a.sums().hits.begin(), a.sums().hits.end()), 0u);
  EXPECT_EQ(*std::max_element(b.sums().hits.begin(), b.sums().hits.end()), 0u);  // no AOV sums kept
}

// The density rule's levels count the rays of a leaf's run, which depend on the candidates per
// ray: it keeps two candidate slots per ray slot (twice the per-ray rule's), and pays for them
// in the budget: 8 bytes each, and their sort's scratch, 2 x 2 x 4 bytes per path, beyond the
// shading sort's 8 that the per-ray rule's scratch covers.
TEST(RayBudget, TheDensityRuleKeepsTwoCandidateSlotsPerRaySlot) {
  const Scene scene = testing::smallTeapot();
  RenderOptions density;
  density.lod = LodRule::Density;
  const Renderer perRay(scene, RenderOptions{}), r(scene, density);
  EXPECT_EQ(r.stats().bytesPerPath, perRay.stats().bytesPerPath + 2 * 8u + (2 * 2 * 4u - 8u));
  EXPECT_EQ(r.stats().candidateCapacity, r.stats().pathsPerBatch * 2 * 2);
}

}  // namespace
}  // namespace rayes
