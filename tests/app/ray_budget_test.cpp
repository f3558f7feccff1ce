// The default ray memory budget (renderer.h, defaultRayMemoryBytes): an eighth of the
// machine, never below 256 MiB nor above 2 GiB (peak memory under 4 GiB), 1 GiB when the
// machine's size is unknown.
#include <gtest/gtest.h>
#include "app/renderer.h"

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

}  // namespace
}  // namespace rayes
