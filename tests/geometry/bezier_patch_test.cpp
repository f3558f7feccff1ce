// Specification of BezierPatch as a surface: evaluation against a double-precision reference,
// exact corners, and the size bound. Its dicing (bit-exact grids, nested levels, bounds of the
// diced vertices, poles, shared borders) is specified in tests/dicing/bezier_patch_dicing_test.cpp.
#include <gtest/gtest.h>
#include <cmath>
#include "geometry/bezier_patch.h"
#include "support/patch_test_util.h"

namespace rayes {
namespace {

using test::ControlPoints;
using test::randomControlPoints;
using test::sameBits;

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

}  // namespace
}  // namespace rayes
