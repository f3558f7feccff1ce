// Specification of BezierPatch: evaluation, bit-exact dicing, conservative bounds, poles, and
// bit-identical shared borders (the base of watertight seams).
#include <gtest/gtest.h>
#include <cmath>
#include "geometry/bezier_patch.h"
#include "dicing/dice_buffer.h"
#include "support/patch_test_util.h"

namespace rayes {
namespace {

using test::ControlPoints;
using test::sameBits;

ControlPoints randomControlPoints(test::Random& rng) {
  ControlPoints cp;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i)
      cp[j * 4 + i] = Vec3{float(i), float(j), 0.0f} + Vec3{rng.uniform(-0.8f, 0.8f), rng.uniform(-0.8f, 0.8f),
                                                           rng.uniform(-1.5f, 1.5f)};
  return cp;
}

struct DVec {
  double x, y, z;
};

// Reference: tensor-product Bernstein sums in double.
void referenceEvaluate(const ControlPoints& cp, double u, double v, DVec& p, DVec& n) {
  auto bern = [](double t, double b[4], double db[4]) {
    const double s = 1 - t;
    b[0] = s * s * s; b[1] = 3 * t * s * s; b[2] = 3 * t * t * s; b[3] = t * t * t;
    db[0] = -3 * s * s; db[1] = 3 * s * s - 6 * t * s; db[2] = 6 * t * s - 3 * t * t; db[3] = 3 * t * t;
  };
  double bu[4], dbu[4], bv[4], dbv[4];
  bern(u, bu, dbu);
  bern(v, bv, dbv);
  DVec du{0, 0, 0}, dv{0, 0, 0};
  p = {0, 0, 0};
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) {
      const Vec3 c = cp[j * 4 + i];
      p.x += bu[i] * bv[j] * c.x; p.y += bu[i] * bv[j] * c.y; p.z += bu[i] * bv[j] * c.z;
      du.x += dbu[i] * bv[j] * c.x; du.y += dbu[i] * bv[j] * c.y; du.z += dbu[i] * bv[j] * c.z;
      dv.x += bu[i] * dbv[j] * c.x; dv.y += bu[i] * dbv[j] * c.y; dv.z += bu[i] * dbv[j] * c.z;
    }
  n = {du.y * dv.z - du.z * dv.y, du.z * dv.x - du.x * dv.z, du.x * dv.y - du.y * dv.x};
}

float maxAbsCoordinate(const ControlPoints& cp) {
  float m = 0;
  for (Vec3 p : cp) m = std::max(m, maxComponent(vabs(p)));
  return m;
}

TEST(BezierPatch, EvaluateMatchesDoubleReference) {
  test::Random rng(1);
  for (int patch = 0; patch < 50; ++patch) {
    const ControlPoints cp = randomControlPoints(rng);
    const BezierPatch bp(cp);
    const float M = maxAbsCoordinate(cp);
    // Each stage (basis: <= 5 ops, 4 products summed: 4 more) loses at most gamma(9) of the
    // sum of |terms|; two stages and the Bernstein weights summing to 1 give gamma(20) * M.
    const double posTol = gammaBound(20) * M;
    // Derivative weights sum in magnitude to at most 6 per direction, so |dP| <= 6M per
    // component with error gamma(20) * 6M; a cross-product component is two products of
    // these, with its own 3 roundings.
    const double nTol = 2.0 * (2.0 * 6 * M * gammaBound(20) * 6 * M) + gammaBound(3) * 2 * 36 * M * M;
    for (int s = 0; s < 200; ++s) {
      const float u = rng.uniform(), v = rng.uniform();
      const SurfacePoint sp = bp.evaluate(u, v);
      DVec p, n;
      referenceEvaluate(cp, u, v, p, n);
      EXPECT_NEAR(sp.p.x, p.x, posTol);
      EXPECT_NEAR(sp.p.y, p.y, posTol);
      EXPECT_NEAR(sp.p.z, p.z, posTol);
      if (std::max({std::fabs(n.x), std::fabs(n.y), std::fabs(n.z)}) > 1e-3 * M * M) {
        EXPECT_NEAR(sp.n.x, n.x, nTol);
        EXPECT_NEAR(sp.n.y, n.y, nTol);
        EXPECT_NEAR(sp.n.z, n.z, nTol);
      }
    }
  }
}

TEST(BezierPatch, CornersAreControlPointsExactly) {
  test::Random rng(2);
  const ControlPoints cp = randomControlPoints(rng);
  const BezierPatch bp(cp);
  EXPECT_TRUE(sameBits(bp.evaluate(0, 0).p, cp[0]));
  EXPECT_TRUE(sameBits(bp.evaluate(1, 0).p, cp[3]));
  EXPECT_TRUE(sameBits(bp.evaluate(0, 1).p, cp[12]));
  EXPECT_TRUE(sameBits(bp.evaluate(1, 1).p, cp[15]));
}

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

TEST(BezierPatch, SizeBoundBoundsIsoCurveLengths) {
  std::vector<ControlPoints> patches = test::loadTeapot();
  test::Random rng(5);
  for (int k = 0; k < 8; ++k) patches.push_back(randomControlPoints(rng));
  for (const ControlPoints& cp : patches) {
    const BezierPatch bp(cp);
    double longest = 0;
    for (int c = 0; c < 16; ++c) {
      const float fixed = rng.uniform();
      for (int dir = 0; dir < 2; ++dir) {
        double len = 0;
        Vec3 prev = dir ? bp.evaluate(fixed, 0).p : bp.evaluate(0, fixed).p;
        for (int s = 1; s <= 256; ++s) {
          const float t = float(s) / 256.0f;
          const Vec3 p = dir ? bp.evaluate(fixed, t).p : bp.evaluate(t, fixed).p;
          len += length(p - prev);
          prev = p;
        }
        longest = std::max(longest, len);
      }
    }
    // A sampled polyline is no longer than the curve; the float sums behind sizeBound() and
    // behind each sample lose at most gamma(32) relatively.
    EXPECT_LE(longest, bp.sizeBound() * (1.0 + gammaBound(32)));
    EXPECT_GT(bp.sizeBound(), 0.0f);
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
