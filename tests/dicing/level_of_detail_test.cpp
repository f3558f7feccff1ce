// Specification of per-ray level of detail: a ray traced at level k on a finer dicing gets
// exactly the hit of a level-k dicing (docs/design.md, invariant 2), and the level rules.
#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include "geometry/bezier_patch.h"
#include "dicing/dice_buffer.h"
#include "support/patch_test_util.h"

namespace rayes {
namespace {

using test::sameBits;

TEST(LevelOfDetail, CoarseLevelOfFineDicingEqualsCoarseDicingBitwise) {
  const auto patches = test::loadTeapot();
  test::Random rng(21);
  DiceBuffer fine(7), coarse(7);
  int hits = 0, rays = 0;
  for (int p : {0, 10, 17, 21, 28}) {
    const BezierPatch bp(patches[p]);
    const Box3 b = bp.bounds();
    const Vec3 c = b.center();
    const float r = length(b.extent());
    for (auto [m, k] : {std::pair{7, 0}, {7, 3}, {6, 2}, {6, 5}, {5, 5}, {4, 1}}) {
      fine.dice(bp, m);
      coarse.dice(bp, k);
      for (int s = 0; s < 600; ++s, ++rays) {
        const Vec3 org = c + rng.unitVector() * (r * rng.uniform(0.6f, 2.0f));
        // Aim at the surface (or, one ray in 4, anywhere in the box) so that most rays hit.
        const Vec3 target = s % 4 ? bp.evaluate(rng.uniform(), rng.uniform()).p
                                  : b.lo + b.extent() * Vec3{rng.uniform(), rng.uniform(), rng.uniform()};
        const Vec3 dir = target - org;
        const float tmax = s % 5 ? std::numeric_limits<float>::infinity() : rng.uniform(0.5f, 1.5f);
        GridHit hf, hc;
        const bool f = fine.intersect(org, dir, 0.0f, tmax, k, hf);
        const bool g = coarse.intersect(org, dir, 0.0f, tmax, k, hc);
        ASSERT_EQ(f, g) << "patch " << p << " m " << m << " k " << k << " ray " << s;
        EXPECT_EQ(fine.occluded(org, dir, 0.0f, tmax, k), f);
        EXPECT_EQ(coarse.occluded(org, dir, 0.0f, tmax, k), f);
        if (!f) continue;
        ++hits;
        ASSERT_TRUE(sameBits(hf.t, hc.t));
        ASSERT_TRUE(sameBits(hf.u, hc.u));
        ASSERT_TRUE(sameBits(hf.v, hc.v));
        ASSERT_EQ(hf.quad, hc.quad);
        ASSERT_TRUE(sameBits(hf.ng, hc.ng));
        ASSERT_TRUE(sameBits(hf.ns, hc.ns));
        ASSERT_LT(hf.quad, 1u << (2 * k));
      }
    }
  }
  EXPECT_GT(hits, rays / 2);
}

TEST(LevelOfDetail, RayLevelAboveDicedLevelIsClamped) {
  const BezierPatch bp(test::loadTeapot()[0]);
  DiceBuffer buffer(4);
  buffer.dice(bp, 3);
  const Vec3 target = bp.evaluate(0.3f, 0.6f).p;
  const Vec3 org = target + Vec3{3, 1, 0.5f};
  GridHit a, b;
  ASSERT_TRUE(buffer.intersect(org, target - org, 0, 10, 3, a));
  ASSERT_TRUE(buffer.intersect(org, target - org, 0, 10, 9, b));
  EXPECT_TRUE(sameBits(a.t, b.t));
  EXPECT_EQ(a.quad, b.quad);
}

TEST(LevelOfDetail, FootprintRule) {
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(levelForFootprint(1, 1, 8), 0);
  EXPECT_EQ(levelForFootprint(1, 2, 8), 0);
  EXPECT_EQ(levelForFootprint(1, 0.5f, 8), 1);
  EXPECT_EQ(levelForFootprint(1, 0.25f, 8), 2);      // exactly on the boundary
  EXPECT_EQ(levelForFootprint(1, 0.2499999f, 8), 3);
  EXPECT_EQ(levelForFootprint(1, 1e-30f, 8), 8);     // clamped
  EXPECT_EQ(levelForFootprint(1, 1e-45f, 300), 149); // denormal width: 2^-149 * 2^149 = 1
  // Documented edge cases.
  EXPECT_EQ(levelForFootprint(1, 0, 8), 8);
  EXPECT_EQ(levelForFootprint(1, -1, 8), 8);
  EXPECT_EQ(levelForFootprint(1, inf, 8), 8);
  EXPECT_EQ(levelForFootprint(1, nan, 8), 8);
  EXPECT_EQ(levelForFootprint(0, 1, 8), 0);
  EXPECT_EQ(levelForFootprint(-1, 1, 8), 0);
  EXPECT_EQ(levelForFootprint(0, 0, 8), 0);
  EXPECT_EQ(levelForFootprint(nan, 1, 8), 8);
  EXPECT_EQ(levelForFootprint(inf, 1, 8), 8);
  EXPECT_EQ(levelForFootprint(1, 0.1f, 0), 0);
  EXPECT_EQ(levelForFootprint(1, 0.1f, -3), 0);
  EXPECT_EQ(levelForFootprint(3e38f, 1e-38f, 1000), 255);  // 2^255 * 1e-38 overflows to inf: still >=
}

// The per-ray rule's floor: the coarsest m with C / 4^m <= size / 256, so a curved patch is
// never seen as chords that stray more than 2^-8 of its size (docs/design.md, "Level of detail
// and energy"); planar patches keep level 0.
TEST(LevelOfDetail, DicingErrorFloor) {
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(kRelativeDicingError, 1.0 / 256);
  EXPECT_EQ(levelForDicingError(1, 0, 10), 0);                 // planar
  EXPECT_EQ(levelForDicingError(256, 1, 10), 0);               // C = size / 256: level 0 suffices
  EXPECT_EQ(levelForDicingError(1, 1, 10), 4);                 // 4^4 = 256, exactly on the boundary
  EXPECT_EQ(levelForDicingError(1, 1.0001f, 10), 5);
  EXPECT_EQ(levelForDicingError(1, 0.25f, 10), 3);
  EXPECT_EQ(levelForDicingError(1, 1, 3), 3);                  // clamped
  for (int m = 0; m <= 10; ++m) {                              // the definition, level by level
    const int level = levelForDicingError(3, 0.7f, 10);
    EXPECT_EQ(m >= level, 0.7 * std::ldexp(1.0, -2 * m) <= 3.0 / 256 || m == 10) << m;
  }
  // Documented edge cases: finite, in [0, maxLevel], for any input.
  EXPECT_EQ(levelForDicingError(1, -1, 10), 0);
  EXPECT_EQ(levelForDicingError(1, nan, 10), 0);
  EXPECT_EQ(levelForDicingError(1, inf, 10), 10);
  EXPECT_EQ(levelForDicingError(0, 1, 10), 10);
  EXPECT_EQ(levelForDicingError(nan, 1, 10), 10);
  EXPECT_EQ(levelForDicingError(inf, 1, 10), 0);
  EXPECT_EQ(levelForDicingError(1e-45f, 3e38f, 300), 143);  // in double: neither underflows to 0
  EXPECT_EQ(levelForDicingError(1, 1, 0), 0);
  EXPECT_EQ(levelForDicingError(1, 1, -3), 0);
}

// Beyond the patch's own size the floor bounds the error as an angle from the ray's origin:
// it is levelForDicingError against the size quadrupled as often as the distance allows, so a
// patch far away is not diced finer than a pixel-wide cone needs (forest-100: 49x the
// micropolygons otherwise), and a near one (distance <= size) keeps its floor.
TEST(LevelOfDetail, DicingErrorFloorRelaxesWithDistanceAsAnAngle) {
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  for (float c : {0.0f, 0.01f, 0.3f, 1.0f, 2.5f})
    for (float size : {0.5f, 1.0f, 3.0f})
      for (float distance : {0.0f, 0.1f, 1.0f, 3.9f, 4.0f, 17.0f, 64.0f, 300.0f, 1e5f}) {
        const int atSize = levelForDicingError(size, c, 30);
        // The size quadrupled k times, k the most that stays within the distance.
        float reach = size;
        while (4 * reach <= distance) reach *= 4;
        const int floor = floorAtDistance(atSize, size, distance);
        EXPECT_EQ(floor, levelForDicingError(reach, c, 30)) << c << " " << size << " " << distance;
        // Never coarser than the rule against the distance itself, and at most one level finer.
        const int againstDistance = levelForDicingError(std::max(size, distance), c, 30);
        EXPECT_GE(floor, againstDistance);
        EXPECT_LE(floor, againstDistance + 1);
      }
  EXPECT_EQ(floorAtDistance(5, 1, 3.99f), 5);  // not yet four times the size
  EXPECT_EQ(floorAtDistance(5, 1, 4), 4);      // exactly on the boundary
  EXPECT_EQ(floorAtDistance(5, 1, 1e30f), 0);  // never below 0
  // Edge cases keep the floor at the size (a NaN distance, a degenerate size) and stay finite.
  EXPECT_EQ(floorAtDistance(5, 1, nan), 5);
  EXPECT_EQ(floorAtDistance(5, 1, -7), 5);
  EXPECT_EQ(floorAtDistance(5, 0, 100), 5);
  EXPECT_EQ(floorAtDistance(5, nan, 100), 5);
  EXPECT_EQ(floorAtDistance(5, inf, inf), 5);
  EXPECT_EQ(floorAtDistance(5, 1, inf), 0);
  EXPECT_EQ(floorAtDistance(5, 3e38f, 3.4e38f), 5);  // 4 x size overflows to inf: never reached
  EXPECT_EQ(floorAtDistance(-2, 1, 100), 0);
}

// The rule doubles the width instead of calling ldexp per level; doubling is exact, so the two
// must agree everywhere, including subnormal widths and widths that overflow on the way.
TEST(LevelOfDetail, FootprintRuleEqualsTheLdexpDefinition) {
  auto byLdexp = [](float size, float width, int maxLevel) {
    for (int m = 0; m < maxLevel; ++m)
      if (size <= std::ldexp(width, m)) return m;
    return maxLevel;
  };
  uint32_t state = 12345u;
  auto next = [&] { state = state * 1664525u + 1013904223u; return state; };
  for (int i = 0; i < 200000; ++i) {
    const float size = std::ldexp(float(next() >> 8) * 0x1p-24f + 0.5f, int(next() % 300) - 150);
    const float width = std::ldexp(float(next() >> 8) * 0x1p-24f + 0.5f, int(next() % 300) - 150);
    const int maxLevel = int(next() % 400);
    if (!(size > 0) || !(width > 0) || !std::isfinite(size) || !std::isfinite(width)) continue;
    ASSERT_EQ(levelForFootprint(size, width, maxLevel), byLdexp(size, width, maxLevel)) << size << " " << width;
  }
}

TEST(LevelOfDetail, DensityRule) {
  EXPECT_EQ(levelForDensity(0, 1, 8), 0);
  EXPECT_EQ(levelForDensity(1, 1, 8), 0);
  EXPECT_EQ(levelForDensity(4, 1, 8), 1);
  EXPECT_EQ(levelForDensity(5, 1, 8), 2);
  EXPECT_EQ(levelForDensity(16, 1, 8), 2);
  EXPECT_EQ(levelForDensity(17, 1, 8), 3);
  EXPECT_EQ(levelForDensity(100, 4, 8), 3);   // 25 rays per sample: 4^3 = 64 >= 25 > 16
  EXPECT_EQ(levelForDensity(65, 4, 8), 3);    // 16.25 -> 4^3
  EXPECT_EQ(levelForDensity(64, 4, 8), 2);
  EXPECT_EQ(levelForDensity(1000, 0, 8), 5);  // spp <= 0 counts as 1
  EXPECT_EQ(levelForDensity(1000, -7, 8), 5);
  EXPECT_EQ(levelForDensity(UINT64_MAX, 1, 12), 12);
  EXPECT_EQ(levelForDensity(UINT64_MAX, 1, 40), 32);  // 4^32 > any uint64
  EXPECT_EQ(levelForDensity(1000, 1, 0), 0);
  EXPECT_EQ(levelForDensity(1000, 1, -1), 0);
}

TEST(LevelOfDetail, BiasShiftsAndClampsToTheLevelsThereAre) {
  EXPECT_EQ(biasedLevel(5, 0, 10), 5);
  EXPECT_EQ(biasedLevel(5, -2, 10), 3);
  EXPECT_EQ(biasedLevel(5, 3, 10), 8);
  EXPECT_EQ(biasedLevel(5, 6, 10), 10);   // never finer than the buffer holds
  EXPECT_EQ(biasedLevel(1, -3, 10), 0);   // never below level 0
  EXPECT_EQ(biasedLevel(0, 12, 0), 0);
  EXPECT_EQ(biasedLevel(3, 2, -1), 0);    // maxLevel < 0 counts as 0
  EXPECT_EQ(biasedLevel(INT32_MAX, INT32_MAX, 12), 12);  // no overflow
  EXPECT_EQ(biasedLevel(INT32_MIN, INT32_MIN, 12), 0);
}

}  // namespace
}  // namespace rayes
