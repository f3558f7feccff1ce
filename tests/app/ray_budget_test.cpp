// The default ray memory budget (renderer.h, defaultRayMemoryBytes): an eighth of the
// machine, never below 256 MiB nor above 2 GiB (peak memory under 4 GiB), 1 GiB when the
// machine's size is unknown. What one path of it costs: the integrator's state and its ray
// slots, each the RayBatch's record and hit and the engine's state and candidate slots.
#include <gtest/gtest.h>
#include "app/renderer.h"
#include "core/ray_batch.h"
#include "rays/sorted_engine.h"
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

// A pt path of a scene where nothing moves and no texture is read: 83 bytes of path state and
// two slots of a 48-byte ray, a 28-byte hit, 19 bytes of trace state and one 12-byte candidate
// slot; the candidate buffer holds one slot per ray slot of the batch.
TEST(RayBudget, APathCostsItsStateAndTwoCompactRaySlots) {
  const Scene scene = testing::smallTeapot();
  const Renderer r(scene, RenderOptions{});
  ASSERT_EQ(r.stats().features.movingLeaves, 0u);  // no shutter time per slot
  ASSERT_EQ(r.stats().features.texturedMaterials, 0u);  // no surface derivatives per slot
  EXPECT_EQ(sizeof(Ray) + sizeof(RayHit) + SortedEngine::bytesPerRaySlot(LodRule::PerRay), 48u + 28u + 19u + 12u);
  EXPECT_EQ(r.stats().bytesPerPath, 83u + 2 * (48u + 28u + 19u + 12u));
  EXPECT_EQ(r.stats().candidateCapacity, r.stats().pathsPerBatch * 2);
  EXPECT_EQ(r.stats().memory.candidatesAndSort, r.stats().pathsPerBatch * 2 * (19u + 12u));
}

// The density rule's levels count the rays of a leaf's run, which depend on the candidates per
// ray: it keeps two candidate slots per ray slot, and pays for them in the budget.
TEST(RayBudget, TheDensityRuleKeepsTwoCandidateSlotsPerRaySlot) {
  const Scene scene = testing::smallTeapot();
  RenderOptions density;
  density.lod = LodRule::Density;
  const Renderer perRay(scene, RenderOptions{}), r(scene, density);
  EXPECT_EQ(r.stats().bytesPerPath, perRay.stats().bytesPerPath + 2 * 12u);
  EXPECT_EQ(r.stats().candidateCapacity, r.stats().pathsPerBatch * 2 * 2);
}

}  // namespace
}  // namespace rayes
