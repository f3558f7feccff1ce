// The shapes and displacements the DisplacedPatch tests run over (geometry/displace_patch_test.cpp,
// dicing/displaced_patch_dicing_test.cpp): a teapot body patch, a teapot pole patch and a twisted
// bilinear patch; moderate noise, extreme noise and a height map, scaled to a patch's size.
#pragma once
#include <gtest/gtest.h>
#include <algorithm>
#include <memory>
#include <utility>
#include <vector>
#include "geometry/bilinear_patch.h"
#include "geometry/displaced_patch.h"
#include "support/patch_test_util.h"

namespace rayes::test {

struct Shape {
  const char* name;
  PatchPtr patch;
};

inline std::vector<Shape> testShapes() {
  const auto teapot = test::loadTeapot();
  int pole = -1;
  for (int k = 0; k < int(teapot.size()) && pole < 0; ++k)
    for (int side = 0; side < 4; ++side) {
      const auto b = test::borderControlPoints(teapot[size_t(k)], side);
      if (b[0] == b[1] && b[1] == b[2] && b[2] == b[3]) { pole = k; break; }
    }
  EXPECT_GE(pole, 0);
  return {{"teapot body", std::make_shared<BezierPatch>(teapot[0])},
          {"teapot pole", std::make_shared<BezierPatch>(teapot[size_t(std::max(pole, 0))])},
          {"twisted bilinear", std::make_shared<BilinearPatch>(Vec3{0, 0, 0}, Vec3{2, 0, 0.3f}, Vec3{0, 2, -0.2f}, Vec3{2, 2.2f, 0.4f})}};
}

inline std::shared_ptr<HeightMap> randomMap(int w, int h, uint64_t seed) {
  Random rng(seed);
  std::vector<float> t(size_t(w) * h);
  for (auto& x : t) x = rng.uniform(0.0f, 1.0f);
  return std::make_shared<HeightMap>(w, h, std::move(t));
}

struct Displaced {
  const char* name;
  DisplacementPtr d;
};

inline std::vector<Displaced> testDisplacements(float size) {
  NoiseParams moderate;
  moderate.amplitude = 0.1f * size;
  moderate.frequency = 4.0f / size;
  moderate.octaves = 5;
  NoiseParams extreme;
  extreme.amplitude = size;              // as large as the patch
  extreme.frequency = 256.0f / size;     // a lattice cell per micro-quad at level 8 ...
  extreme.octaves = 4;                   // ... and 8x finer in the last octave
  extreme.ridged = true;
  return {{"moderate noise", std::make_shared<NoiseDisplacement>(moderate)},
          {"extreme noise", std::make_shared<NoiseDisplacement>(extreme)},
          {"height map", std::make_shared<HeightMapDisplacement>(randomMap(64, 48, 7), 0.5f * size, -0.1f * size)}};
}

}  // namespace rayes::test
