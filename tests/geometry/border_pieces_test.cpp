// Patch::borderPieceBoundsAt, the boxes of consecutive pieces of one border that crack-closing
// regions take their radii from (dicing/border_regions.cpp): every box holds the evaluated
// border curve over its piece (what the neighbour's finer dicing puts there), at extreme
// scales and far from the origin, for Bézier, displaced (noise, extreme noise, height map;
// with and without a reference surface), bilinear-based and moving patches; a Bézier kind's
// boxes, made by restricting the border curve once and halving it, are the restricted hulls
// boundsOver gives up to both computations' counted rounding; a moving patch gives each
// time sample's own.
#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>
#include "geometry/bilinear_patch.h"
#include "geometry/displaced_patch.h"
#include "geometry/moving_patch.h"
#include "support/patch_test_util.h"

namespace rayes {
namespace {

using test::Random;

struct Named {
  std::string name;
  PatchPtr patch;
};

// (u, v) at parameter t along border e (0: v = 0, 1: u = 1, 2: v = 1, 3: u = 0).
void borderParam(int e, float t, float& u, float& v) {
  u = e == 0 || e == 2 ? t : e == 1 ? 1.0f : 0.0f;
  v = e == 1 || e == 3 ? t : e == 2 ? 1.0f : 0.0f;
}

test::ControlPoints transformed(test::ControlPoints cp, float scale, Vec3 offset) {
  for (Vec3& p : cp) p = p * scale + offset;
  return cp;
}

std::vector<Named> bezierPatches() {
  const auto teapot = test::loadTeapot();
  std::vector<Named> out;
  for (float scale : {1e-6f, 1.0f, 1e6f})
    for (float far : {0.0f, 1e5f})
      for (size_t p : {size_t(0), size_t(20), teapot.size() - 1}) {
        const Vec3 offset = Vec3{1, -2, 3} * (far * scale);
        out.push_back({"teapot " + std::to_string(p) + " x" + std::to_string(scale) + " at " + std::to_string(far),
                       std::make_shared<BezierPatch>(transformed(teapot[p], scale, offset))});
      }
  return out;
}

std::vector<Named> displacedPatches() {
  const auto teapot = test::loadTeapot();
  std::vector<Named> out;
  for (float scale : {1e-4f, 1.0f, 1e4f}) {
    const auto cp = transformed(teapot[0], scale, Vec3{3, 1, -2} * scale);
    const float size = 3 * scale;
    NoiseParams moderate;
    moderate.amplitude = 0.1f * size;
    moderate.frequency = 4.0f / size;
    moderate.octaves = 5;
    NoiseParams extreme;  // as deep as the patch is large, a lattice cell per level-8 micro-quad
    extreme.amplitude = size;
    extreme.frequency = 256.0f / size;
    extreme.octaves = 4;
    extreme.ridged = true;
    std::vector<float> texels(64 * 48);
    Random rng(9);
    for (float& t : texels) t = rng.uniform();
    const DisplacementPtr maps[] = {
        std::make_shared<NoiseDisplacement>(moderate), std::make_shared<NoiseDisplacement>(extreme),
        std::make_shared<HeightMapDisplacement>(std::make_shared<HeightMap>(64, 48, texels), 0.5f * size, -0.1f * size)};
    const char* names[] = {"moderate noise", "extreme noise", "height map"};
    for (int d = 0; d < 3; ++d) {
      const std::string at = " x" + std::to_string(scale);
      out.push_back({std::string("displaced teapot, ") + names[d] + at,
                     std::make_shared<DisplacedPatch>(std::make_shared<BezierPatch>(cp), maps[d])});
      // The pattern attached to an unmoved reference, the surface placed elsewhere.
      out.push_back({std::string("displaced teapot with reference, ") + names[d] + at,
                     std::make_shared<DisplacedPatch>(
                         std::make_shared<BezierPatch>(transformed(cp, 2.0f, Vec3{1, 1, 1} * scale)), maps[d],
                         std::make_shared<BezierPatch>(cp))});
      out.push_back({std::string("displaced twisted bilinear, ") + names[d] + at,
                     std::make_shared<DisplacedPatch>(
                         std::make_shared<BilinearPatch>(Vec3{0, 0, 0} * scale, Vec3{2, 0, 0.3f} * scale,
                                                         Vec3{0, 2, -0.2f} * scale, Vec3{2, 2.2f, 0.4f} * scale),
                         maps[d])});
    }
  }
  return out;
}

// (level, segment, split) triples: a whole border in 128 pieces, halves and quarters, a deep
// segment as a fine ray's region sees it.
struct Segment {
  int k;
  uint32_t j;
  int split;
};
const Segment kSegments[] = {{0, 0, 7}, {1, 1, 6}, {2, 2, 5}, {4, 9, 3}, {10, 777, 3}};

::testing::AssertionResult piecesHoldTheCurve(const Patch& patch, Random& rng) {
  Box3 boxes[128];
  for (int e = 0; e < 4; ++e)
    for (const Segment& s : kSegments) {
      patch.borderPieceBoundsAt(0, e, s.k, s.j, s.split, boxes);
      const uint32_t pieces = 1u << s.split;
      const float inv = 1.0f / float(1u << (s.k + s.split));
      for (uint32_t i = 0; i < pieces; ++i) {
        const float t0 = float(s.j * pieces + i) * inv, t1 = float(s.j * pieces + i + 1) * inv;
        for (int q = 0; q < 6; ++q) {
          const float t = q == 0 ? t0 : q == 1 ? t1 : std::min(t1, t0 + (t1 - t0) * rng.uniform());
          float u, v;
          borderParam(e, t, u, v);
          const Vec3 p = patch.evaluate(u, v).p;
          if (!boxes[i].contains(p))
            return ::testing::AssertionFailure() << "border " << e << ", level " << s.k << " segment " << s.j
                                                 << ", piece " << i << " of " << pieces << ": (" << p.x << ", "
                                                 << p.y << ", " << p.z << ") at t = " << t << " outside";
        }
      }
    }
  return ::testing::AssertionSuccess();
}

TEST(BorderPieces, HoldTheEvaluatedBorderCurve) {
  Random rng(11);
  for (const Named& n : bezierPatches()) EXPECT_TRUE(piecesHoldTheCurve(*n.patch, rng)) << n.name;
  for (const Named& n : displacedPatches()) EXPECT_TRUE(piecesHoldTheCurve(*n.patch, rng)) << n.name;
}

// A Bézier border restricted once and halved gives the restricted hulls of boundsOver (the
// default, one restriction of the whole patch per piece) up to both sides' counted rounding:
// gamma(24 + 9 split) and gamma(48) of the anchored magnitude (at most the longest side of the
// control box), and half an ulp of the coordinates for each box's last rounding.
TEST(BorderPieces, BezierPiecesAreTheRestrictedHullsUpToTheirRounding) {
  for (const Named& n : bezierPatches()) {
    const Patch& patch = *n.patch;
    const float side = patch.bounds().longestSide();
    Box3 fast[128], slow[128];
    for (int e = 0; e < 4; ++e)
      for (const Segment& s : kSegments) {
        patch.borderPieceBoundsAt(0, e, s.k, s.j, s.split, fast);
        patch.Patch::borderPieceBoundsAt(0, e, s.k, s.j, s.split, slow);
        const float slack = (gammaBound(24 + 9 * s.split) + gammaBound(48)) * side;
        for (uint32_t i = 0; i < (1u << s.split); ++i) {
          const float ulps = 2 * 0x1p-23f * std::max(fast[i].magnitude(), slow[i].magnitude());
          for (int a = 0; a < 3; ++a) {
            ASSERT_LE(std::fabs(fast[i].lo[a] - slow[i].lo[a]), slack + ulps) << n.name << " e " << e << " piece " << i;
            ASSERT_LE(std::fabs(fast[i].hi[a] - slow[i].hi[a]), slack + ulps) << n.name << " e " << e << " piece " << i;
          }
        }
      }
  }
}

TEST(BorderPieces, MovingPatchGivesEachSamplesOwn) {
  const auto teapot = test::loadTeapot();
  const PatchPtr a = std::make_shared<BezierPatch>(teapot[3]);
  const PatchPtr b = std::make_shared<BezierPatch>(transformed(teapot[3], 1.5f, Vec3{0.2f, 0, 0}));
  const MovingPatch moving({a, b}, {0.0f, 1.0f});
  Box3 got[8], want[8];
  for (int s = 0; s < 2; ++s) {
    moving.borderPieceBoundsAt(s, 2, 3, 5, 3, got);
    (s == 0 ? a : b)->borderPieceBoundsAt(0, 2, 3, 5, 3, want);
    for (int i = 0; i < 8; ++i) {
      EXPECT_TRUE(got[i].lo == want[i].lo && got[i].hi == want[i].hi) << "sample " << s << " piece " << i;
    }
  }
}

}  // namespace
}  // namespace rayes
