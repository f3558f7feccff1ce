// A furnace (docs/design.md, "Analytic checks", "Furnaces"): inside a closed box whose six
// two-sided walls all have albedo rho and emit radiance Le, the radiance is Le / (1 - rho)
// everywhere, so every pixel is an i.i.d. estimate of it and a render's mean is checked against
// the closed form within 4 standard errors of the pixel mean.
#pragma once
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>
#include <gtest/gtest.h>
#include "scene/scene_loader.h"

namespace rayes::testing {

inline Scene furnaceScene(float rho, float le, uint64_t seed) {
  const std::string text = R"({
    "camera": {"position": [0.1, -0.6, 0.2], "look_at": [-0.2, 1, -0.1], "up": [0, 0, 1], "fov": 100},
    "film": {"resolution": [24, 24], "spp": 16},
    "integrator": {"max_depth": 1000, "seed": )" + std::to_string(seed) + R"(},
    "materials": {"wall": {"type": "emissive", "radiance": )" + std::to_string(le) + R"(, "albedo": )" +
                           std::to_string(rho) + R"(, "two_sided": true}},
    "shapes": [{"type": "bilinear", "material": "wall", "quads": [
      [[-1,-1,-1],[1,-1,-1],[-1,1,-1],[1,1,-1]],
      [[-1,-1,1],[1,-1,1],[-1,1,1],[1,1,1]],
      [[-1,-1,-1],[1,-1,-1],[-1,-1,1],[1,-1,1]],
      [[-1,1,-1],[1,1,-1],[-1,1,1],[1,1,1]],
      [[-1,-1,-1],[-1,1,-1],[-1,-1,1],[-1,1,1]],
      [[1,-1,-1],[1,1,-1],[1,-1,1],[1,1,1]]
    ]}]
  })";
  return parseScene(text, "furnace.json");
}

// The red channel's pixel mean of an RGBA image against Le / (1 - rho), within 4 standard errors
// (the pixels' sample standard deviation over sqrt(n)).
inline void expectFurnaceMean(const std::vector<float>& rgba, float rho, float le, const std::string& what) {
  const size_t n = rgba.size() / 4;
  double sum = 0, sum2 = 0;
  for (size_t p = 0; p < n; ++p) {
    ASSERT_TRUE(std::isfinite(rgba[4 * p])) << what << ", pixel " << p;
    sum += rgba[4 * p];
    sum2 += double(rgba[4 * p]) * rgba[4 * p];
  }
  const double mean = sum / double(n);
  const double standardError = std::sqrt((sum2 - double(n) * mean * mean) / double(n - 1) / double(n));
  EXPECT_GT(standardError, 0.0) << what;
  EXPECT_NEAR(mean, le / (1.0 - rho), 4 * standardError) << what << ", standard error " << standardError;
}

}  // namespace rayes::testing
