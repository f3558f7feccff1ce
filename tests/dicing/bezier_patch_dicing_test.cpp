// Specification of BezierPatch diced: bit-exact dicing (the grid equals evaluate(), finer levels
// contain coarser ones), the diced vertices inside bounds(), finite normals at poles, and
// bit-identical shared borders (the base of watertight seams). Its evaluation alone is specified
// in tests/geometry/bezier_patch_test.cpp.
#include <gtest/gtest.h>
#include <cmath>
#include "geometry/bezier_patch.h"
#include "dicing/dice_buffer.h"
#include "support/patch_test_util.h"

namespace rayes {
namespace {

using test::ControlPoints;
using test::randomControlPoints;
using test::sameBits;

// "Grid vertices equal direct patch evaluation" is what lets any module re-evaluate a hit
// point's (u, v) and land exactly on the diced surface.
TEST(BezierPatch, DicedVerticesEqualEvaluateBitwise) {
  std::vector<ControlPoints> patches = test::loadTeapot();
  test::Random rng(3);
  for (int k = 0; k < 4; ++k) patches.push_back(randomControlPoints(rng));
  const int m = 5, n = 1 << m;
  std::vector<Vec3> pos((n + 1) * (n + 1)), nrm(pos.size());
  DiceBuffer buffer(m);
  for (const ControlPoints& cp : patches) {
    const BezierPatch bp(cp);
    bp.dice(m, pos.data(), nrm.data());
    buffer.dice(bp, m);
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        const SurfacePoint sp = bp.evaluate(float(i) / float(n), float(j) / float(n));
        ASSERT_TRUE(sameBits(pos[j * (n + 1) + i], sp.p)) << i << "," << j;
        ASSERT_TRUE(sameBits(nrm[j * (n + 1) + i], sp.n)) << i << "," << j;
        ASSERT_TRUE(sameBits(buffer.position(i, j), sp.p));
      }
  }
}

TEST(BezierPatch, FinerDicingContainsCoarserDicingBitwise) {
  const std::vector<ControlPoints> patches = test::loadTeapot();
  DiceBuffer fine(6), coarse(6);
  for (int p : {0, 5, 12, 20, 28}) {
    const BezierPatch bp(patches[p]);
    fine.dice(bp, 6);
    for (int k = 0; k <= 5; ++k) {
      coarse.dice(bp, k);
      const int s = 1 << (6 - k);
      for (int j = 0; j <= (1 << k); ++j)
        for (int i = 0; i <= (1 << k); ++i) {
          ASSERT_TRUE(sameBits(fine.position(i * s, j * s), coarse.position(i, j)));
          ASSERT_TRUE(sameBits(fine.normal(i * s, j * s), coarse.normal(i, j)));
        }
    }
  }
}

// docs/design.md, invariant 1, by sampling: 1e5 random points and every vertex of an m = 6 dicing.
TEST(BezierPatch, TeapotBoundsContainPatch) {
  const std::vector<ControlPoints> patches = test::loadTeapot();
  ASSERT_EQ(patches.size(), 32u);
  test::Random rng(4);
  DiceBuffer buffer(6);
  for (size_t p = 0; p < patches.size(); ++p) {
    const BezierPatch bp(patches[p]);
    const Box3 b = bp.bounds();
    int outside = 0;
    for (int s = 0; s < 100000; ++s) outside += !b.contains(bp.evaluate(rng.uniform(), rng.uniform()).p);
    buffer.dice(bp, 6);
    for (int j = 0; j < buffer.resolution(); ++j)
      for (int i = 0; i < buffer.resolution(); ++i) outside += !b.contains(buffer.position(i, j));
    EXPECT_EQ(outside, 0) << "patch " << p;
  }
}

TEST(BezierPatch, TeapotPolesHaveFiniteNonZeroNormals) {
  const std::vector<ControlPoints> patches = test::loadTeapot();
  const int m = 6, n = 1 << m;
  std::vector<Vec3> pos((n + 1) * (n + 1)), nrm(pos.size());
  DiceBuffer buffer(m);
  int poles = 0;
  for (const ControlPoints& cp : patches) {
    const BezierPatch bp(cp);
    bp.dice(m, pos.data(), nrm.data());
    buffer.dice(bp, m);
    for (size_t k = 0; k < nrm.size(); ++k) {
      ASSERT_TRUE(isFinite(nrm[k]));
      ASSERT_GT(maxComponent(vabs(nrm[k])), 0.0f);
      ASSERT_TRUE(isFinite(buffer.normal(int(k) % (n + 1), int(k) / (n + 1))));
    }
    for (int side = 0; side < 4; ++side) {
      const auto b = test::borderControlPoints(cp, side);
      if (!(b[0] == b[1] && b[1] == b[2] && b[2] == b[3])) continue;
      ++poles;
      // The teapot's poles sit on the z axis, a rotation axis of the surface, so the limit
      // normal there is +-z. The nudge of 2^-12 in parameter tilts it by about 2^-12 times
      // |dP/dv| / radius of curvature (both O(1) on the teapot): far below 1e-3 rad, so
      // |n.z| >= cos(1e-3) > 1 - 1e-6; we allow 1 - 1e-4 for the float normalisation.
      if (b[0].x == 0.0f && b[0].y == 0.0f)
        for (int k = 0; k <= n; ++k) {
          const auto ij = test::borderVertex(side, k, n);
          EXPECT_GT(std::fabs(buffer.normal(ij[0], ij[1]).z), 1.0f - 1e-4f);
        }
    }
  }
  EXPECT_GE(poles, 4);  // the lid knob and the bottom collapse a row each
}

TEST(BezierPatch, TeapotSharedBordersAreBitIdentical) {
  const std::vector<ControlPoints> patches = test::loadTeapot();
  const auto shared = test::findSharedBorders(patches);
  ASSERT_GE(shared.size(), 16u);  // body, rim, handle, spout and lid all stitch together
  DiceBuffer a(6), b(6);
  for (const auto& s : shared) {
    for (int m = 0; m <= 6; ++m) {
      a.dice(BezierPatch(patches[s.patchA]), m);
      b.dice(BezierPatch(patches[s.patchB]), m);
      const int n = 1 << m;
      for (int k = 0; k <= n; ++k) {
        const auto ia = test::borderVertex(s.sideA, k, n);
        const auto ib = test::borderVertex(s.sideB, s.reversed ? n - k : k, n);
        ASSERT_TRUE(sameBits(a.position(ia[0], ia[1]), b.position(ib[0], ib[1])))
            << "patches " << s.patchA << "/" << s.patchB << " m=" << m << " k=" << k;
      }
    }
  }
}

// The canonical orientation must also cover a border shared in opposite directions and a
// symmetric (palindromic) border, which the teapot may not contain.
TEST(BezierPatch, ReversedAndPalindromicSharedBordersAreBitIdentical) {
  test::Random rng(6);
  for (int trial = 0; trial < 20; ++trial) {
    ControlPoints a = randomControlPoints(rng), b = randomControlPoints(rng);
    if (trial % 2) {  // make a's u=1 column a palindrome
      a[11] = a[7];
      a[15] = a[3];
    }
    // b's v=0 row is a's u=1 column, reversed.
    for (int k = 0; k < 4; ++k) b[k] = a[4 * (3 - k) + 3];
    DiceBuffer da(5), db(5);
    for (int m = 1; m <= 5; ++m) {
      da.dice(BezierPatch(a), m);
      db.dice(BezierPatch(b), m);
      const int n = 1 << m;
      for (int k = 0; k <= n; ++k)
        ASSERT_TRUE(sameBits(da.position(n, k), db.position(n - k, 0))) << trial << " " << m << " " << k;
    }
  }
}

}  // namespace
}  // namespace rayes
