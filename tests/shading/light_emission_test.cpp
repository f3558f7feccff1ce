// LightSampler::sampleEmission, the first ray of a light path: the weights are the lights'
// power, and degenerate lights (zero area, zero cone)
// give no sample instead of a non-finite one.
#include <cmath>
#include <numbers>
#include <gtest/gtest.h>
#include "core/rng.h"
#include "shading/light.h"

namespace rayes {
namespace {
constexpr double kPi = std::numbers::pi;

// A unit square at z = 0 facing +z with radiance L: power π L (one side).
PatchLight square(Rgb radiance, float size) {
  return {[size](float u, float v, Vec3& p, Vec3& n) {
            p = {u * size, v * size, 0};
            n = {0, 0, size * size};
          },
          radiance, false, 0};
}

// Picked by power (grey lights: luminance is the radiance), every light path carries the
// total power exactly: the pick probability cancels each light's own power. So every weight
// equals the total, up to the float roundings of the pick CDF and the weight (a few 2^-23).
TEST(LightEmission, EveryWeightIsTheTotalPowerWhenPickedByPower) {
  const LightSampler lights({{{0, 0, 5}, {2, 2, 2}}}, {square({3, 3, 3}, 1)});
  const double power = 4 * kPi * 2 + kPi * 3;  // point 4π I, one-sided square π L A
  int emitted = 0;
  for (uint32_t i = 0; i < 2000; ++i) {
    const RngKey key{i, 0, 0, 1};
    EmissionSample e;
    if (!lights.sampleEmission(sampleUniform(key, 0), sampleUniform(key, 1), sampleUniform(key, 2),
                               sampleUniform(key, 3), sampleUniform(key, 4), e))
      continue;
    ++emitted;
    ASSERT_TRUE(isFinite(e.weight) && isFinite(e.dir) && isFinite(e.org)) << i;
    EXPECT_NEAR(length(e.dir), 1.0f, 1e-6f) << i;
    EXPECT_NEAR(e.weight.x, power, power * 8 * 1.2e-7) << i;
    if (e.onSurface) {
      EXPECT_GT(dot(e.dir, e.normal), 0.0f) << "one-sided: leaves on the normal's side";
    }
  }
  EXPECT_EQ(emitted, 2000);
}

TEST(LightEmission, DegenerateLightsGiveNoSample) {
  EmissionSample e;
  const LightSampler flat({}, {square({1, 1, 1}, 0)});  // zero area: Jacobian 0
  EXPECT_FALSE(flat.sampleEmission(0.5f, 0.5f, 0.5f, 0.5f, 0.5f, e));
  SceneLights spot;
  spot.spots.push_back({{0, 0, 0}, {0, 0, -1}, {1, 1, 1}, 1.0f, 1.0f});  // a cone of angle 0
  const LightSampler narrow({}, {}, spot);
  EXPECT_FALSE(narrow.sampleEmission(0.5f, 0.5f, 0.5f, 0.5f, 0.5f, e));
  const LightSampler none;
  EXPECT_FALSE(none.sampleEmission(0.5f, 0.5f, 0.5f, 0.5f, 0.5f, e));
}

}  // namespace
}  // namespace rayes
