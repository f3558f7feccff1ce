// Area lights as beam sources (lbt/beam_seeds.h): k×k points per emissive patch, each a point
// light with a cosine lobe whose power π·L·A_i adds up to the patch's π·L·A; two-sided patches
// get a point per side; a degenerate patch gives none (no division by its zero area).
#include <gtest/gtest.h>
#include <numbers>
#include "lbt/beam_seeds.h"

namespace rayes {
namespace {

PatchLight rect(Vec3 corner, Vec3 eu, Vec3 ev, Rgb radiance, bool twoSided) {
  return {[=](float u, float v, Vec3& p, Vec3& n) {
            p = corner + eu * u + ev * v;
            n = cross(eu, ev);
          },
          radiance, twoSided, 0};
}

TEST(AreaLightPoints, PowersAddUpToTheLightsAndLieOnItsEmittingSide) {
  const Box3 scene{{-5, -5, -5}, {5, 5, 5}};
  const PatchLight light = rect({0, 0, 2}, {0.5f, 0, 0}, {0, 0.25f, 0}, {4, 2, 1}, false);
  const auto points = areaLightPoints(std::span(&light, 1), 3, scene);
  ASSERT_EQ(points.size(), 9u);
  double power = 0;
  for (const AreaLightPoint& p : points) {
    power += std::numbers::pi * p.intensity.x;  // ∫ I·cos dω over the hemisphere = π·I
    EXPECT_EQ(p.normal.z, 1.0f);
    EXPECT_GT(p.position.z, 2.0f);  // lifted off the surface toward where it emits
    EXPECT_LT(p.position.z, 2.001f);
  }
  EXPECT_NEAR(power, std::numbers::pi * 4 * 0.125, 1e-6);
}

TEST(AreaLightPoints, TwoSidedLightsGetAPointPerSideAndDegenerateOnesNone) {
  const Box3 scene{{-5, -5, -5}, {5, 5, 5}};
  const PatchLight both = rect({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 1}, true);
  const auto points = areaLightPoints(std::span(&both, 1), 2, scene);
  ASSERT_EQ(points.size(), 8u);
  int down = 0;
  for (const AreaLightPoint& p : points) down += p.normal.z < 0 && p.position.z < 0;
  EXPECT_EQ(down, 4);
  const PatchLight flat = rect({0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {1, 1, 1}, false);  // zero area
  EXPECT_TRUE(areaLightPoints(std::span(&flat, 1), 2, scene).empty());
  EXPECT_TRUE(areaLightPoints(std::span(&both, 1), 0, scene).empty());
}

TEST(AreaLightPoints, SeedBeamsFromThemCarryTheirCosineLobe) {
  // A light facing down over a scatterer below it: beams; over one above it (behind the light):
  // the cosine lobe gives every cell zero flux, so no generator triangle.
  const Box3 scene{{-5, -5, -5}, {5, 5, 5}};
  BeamLights lights;
  lights.patches.push_back(rect({-0.1f, -0.1f, 1}, {0, 0.2f, 0}, {0.2f, 0, 0}, {1, 1, 1}, false));
  lights.areaSamples = 1;
  const auto square = [](float z) {
    return ScattererSurface{0, [z](float u, float v) { return Vec3{-1 + 2 * u, -1 + 2 * v, z}; }};
  };
  const ScattererSurface below = square(0), above = square(3);
  const BeamSeeds seen = seedBeams(lights, std::span(&below, 1), scene, 8);
  EXPECT_FALSE(seen.triangles.empty());
  for (const Rgb& f : seen.flux) EXPECT_TRUE(isFinite(f) && f.x > 0);
  EXPECT_TRUE(seedBeams(lights, std::span(&above, 1), scene, 8).triangles.empty());
}

}  // namespace
}  // namespace rayes
