// The first corner rays of light beams (lbt/beam_seeds.h): a grid over each scatterer leaf's own
// (u, v) square per light, cells no wider than 2/N as the light sees them, aim points inset from
// the leaf's borders, a quarter cell of tolerance for where a corner ray must land, and the
// flux of the whole grid equal to the light's power into the (inset) leaf.
#include <gtest/gtest.h>
#include <cmath>
#include "lbt/beam_seeds.h"

namespace rayes {
namespace {

// The square [-h, h]² at height z, u along x and v along y.
ScattererSurface square(uint32_t leaf, float h, float z) {
  return {leaf, [h, z](float u, float v) { return Vec3{-h + 2 * h * u, -h + 2 * h * v, z}; }};
}

// I·Ω of the square's inset part seen from the origin (the light).
double insetSolidAngle(float h, float z) {
  const float a = h * (1 - 2 * kSeedInset);
  const Vec3 c[4] = {{-a, -a, z}, {a, -a, z}, {a, a, z}, {-a, a, z}};
  Vec3 d[4];
  for (int k = 0; k < 4; ++k) d[k] = normalize(c[k]);
  return sphericalTriangleArea(d[0], d[1], d[2]) + sphericalTriangleArea(d[0], d[2], d[3]);
}

TEST(BeamSeeds, ALeafsGridIsAsFineAsTheLightSeesItsDensestPart) {
  // The square [-1, 1]² one unit below a point light: at its foot a unit of u spans 2 rad, so
  // cells of at most 2/N rad need N cells a side (N = 8 here), the same in v.
  BeamLights lights;
  lights.points.push_back({{0, 0, 0}, {3, 3, 3}});
  const ScattererSurface leaf = square(7, 1, -1);
  const Box3 scene{{-5, -5, -5}, {5, 5, 5}};
  const BeamSeeds seeds = seedBeams(lights, std::span(&leaf, 1), scene, 8);
  ASSERT_EQ(seeds.org.size(), 81u);  // (8 + 1)² corner rays, shared by neighbouring cells
  ASSERT_EQ(seeds.triangles.size(), 128u);
  double power = 0;
  for (const Rgb& f : seeds.flux) power += f.x;
  EXPECT_NEAR(power, 3 * insetSolidAngle(1, -1), 1e-5 * power);
  float uMin = 1, uMax = 0;
  for (size_t i = 0; i < seeds.aim.size(); ++i) {
    const SeedAim& a = seeds.aim[i];
    EXPECT_EQ(a.leaf, 7u);
    EXPECT_FLOAT_EQ(a.tolU, 0.25f / 8);
    EXPECT_FLOAT_EQ(a.tolV, 0.25f / 8);
    uMin = std::min(uMin, a.u), uMax = std::max(uMax, a.u);
    // The ray points at the leaf's surface at its aim.
    const Vec3 p = leaf.position(a.u, a.v);
    EXPECT_NEAR(dot(normalize(p - seeds.org[i]), seeds.dir[i]), 1.0f, 1e-6f);
  }
  EXPECT_FLOAT_EQ(uMin, kSeedInset);
  EXPECT_FLOAT_EQ(uMax, 1 - kSeedInset);
  // Twice as far, half the angle: half the cells a side.
  const ScattererSurface far = square(7, 1, -2);
  EXPECT_EQ(seedBeams(lights, std::span(&far, 1), scene, 8).triangles.size(), 2u * 4 * 4);
}

TEST(BeamSeeds, EachLeafHasItsOwnGridAndADistantLightsFluxIsItsIrradianceTimesTheArea) {
  // Two squares under a distant light straight down: cells of (extent of both)/N, flux E·A of
  // each inset square, every corner aimed at its own leaf.
  BeamLights lights;
  lights.distants.push_back({{0, 0, 1}, {2, 2, 2}});
  const ScattererSurface leaves[2] = {square(0, 1, 0), {1, [](float u, float v) { return Vec3{3 + u, v, 0.5f}; }}};
  const Box3 scene{{-5, -5, -5}, {5, 5, 5}};
  const BeamSeeds seeds = seedBeams(lights, leaves, scene, 8);
  // Extent across the light: x from -1 to 4 (5 units): cells of 5/8; the first square spans 2
  // (4 cells a side), the second 1 (2 cells).
  EXPECT_EQ(seeds.triangles.size(), 2u * (4 * 4 + 2 * 2));
  double power[2] = {0, 0};
  for (size_t t = 0; t < seeds.triangles.size(); ++t) {
    const uint32_t leaf = seeds.aim[seeds.triangles[t][0]].leaf;
    for (uint32_t c : seeds.triangles[t]) EXPECT_EQ(seeds.aim[c].leaf, leaf);
    EXPECT_EQ(seeds.dir[seeds.triangles[t][0]], (Vec3{0, 0, -1}));
    power[leaf] += seeds.flux[t].x;
  }
  const double inset = (1 - 2 * kSeedInset) * (1 - 2 * kSeedInset);
  EXPECT_NEAR(power[0], 2 * 4 * inset, 1e-5);
  EXPECT_NEAR(power[1], 2 * 1 * inset, 1e-5);
}

TEST(BeamSeeds, ACornerRayLandsOnItsAimOnlyOnItsLeafWithinAQuarterCell) {
  const SeedAim aim{3, 0.5f, 0.25f, 0.01f, 0.02f};
  EXPECT_TRUE(aim.hits(3, 0.5f, 0.25f));
  EXPECT_TRUE(aim.hits(3, 0.509f, 0.269f));
  EXPECT_FALSE(aim.hits(3, 0.52f, 0.25f)) << "the same leaf far from the aim: a fold in front";
  EXPECT_FALSE(aim.hits(4, 0.5f, 0.25f)) << "another leaf in front";
  EXPECT_FALSE(SeedAim{}.hits(3, 0.5f, 0.25f)) << "no aim: after a scattering";
}

}  // namespace
}  // namespace rayes
