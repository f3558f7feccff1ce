// The glossy resolution rule (lbt/beam_resolution.h): a beam's footprint angle, and the grid
// resolution at which first-bounce glossy beams are about cellsPerSigma lobe widths wide.
#include <gtest/gtest.h>
#include <vector>
#include "lbt/beam_resolution.h"

namespace rayes {
namespace {
constexpr float kFar = 1e6f;

// Parallel corner rays up +z from a right triangle with legs `side` at z = 0, ending at z = 2.
BeamSegment parallelBeam(float side, float sigma, uint8_t scatterings = 1) {
  BeamSegment s;
  s.o[0] = {0, 0, 0};
  s.o[1] = {side, 0, 0};
  s.o[2] = {0, side, 0};
  for (int i = 0; i < 3; ++i) s.d[i] = {0, 0, 1}, s.t[i] = 2;
  s.sigma = sigma;
  s.scatterings = scatterings;
  return s;
}

TEST(BeamResolution, FootprintAngleIsTheLongestEndSideOverTheLength) {
  // Longest side: the hypotenuse side·√2, over the length 2.
  EXPECT_NEAR(footprintAngle(parallelBeam(0.1f, 0.05f), kFar), 0.1 * std::sqrt(2.0) / 2, 1e-6);
  BeamSegment escaping = parallelBeam(0.1f, 0.05f);
  escaping.t[1] = kFar;
  EXPECT_EQ(footprintAngle(escaping, kFar), 0.0) << "a corner that left the scene";
  BeamSegment focus = parallelBeam(0.1f, 0.05f);
  for (int i = 0; i < 3; ++i) focus.d[i] = normalize(Vec3{0, 0, 2} - focus.o[i]), focus.t[i] = length(Vec3{0, 0, 2} - focus.o[i]);
  EXPECT_NEAR(footprintAngle(focus, kFar), 0.0, 1e-6) << "ends meeting at a focus";
}

TEST(BeamResolution, GridMakesGlossyBeamsCellsPerSigmaWide) {
  // Width/σ = (0.1·√2/2)/0.05 = √2 at probe resolution 16: 2 lobe widths need 16·√2/2 → 12.
  const std::vector<BeamSegment> probe(5, parallelBeam(0.1f, 0.05f));
  EXPECT_EQ(lobeResolution(probe, 16, 2.0, kFar), 12);
  EXPECT_EQ(lobeResolution(probe, 16, 0.5, kFar), 46);  // ceil(45.25)
  EXPECT_EQ(lobeResolution(probe, 16, 64.0, kFar), 1) << "never below one cell";
  EXPECT_EQ(lobeResolution(probe, 16, 0.0, kFar), 0) << "0: the rule is off";
}

TEST(BeamResolution, SpecularMajoritiesAndLaterBouncesDoNotDecide) {
  std::vector<BeamSegment> probe(3, parallelBeam(0.1f, 0.05f));
  for (int i = 0; i < 4; ++i) probe.push_back(parallelBeam(0.1f, 0.0f));
  EXPECT_EQ(lobeResolution(probe, 16, 2.0, kFar), 0) << "more specular beams than glossy: keep the grid";
  const std::vector<BeamSegment> second(4, parallelBeam(0.1f, 0.05f, 2));
  EXPECT_EQ(lobeResolution(second, 16, 2.0, kFar), 0) << "only first-bounce segments count";
  EXPECT_EQ(lobeResolution({}, 16, 2.0, kFar), 0);
}

}  // namespace
}  // namespace rayes
