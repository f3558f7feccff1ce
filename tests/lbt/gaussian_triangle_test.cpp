// The glossy gather's footprint integral (lbt/gaussian_triangle.h): G = atan/2π - Owen's T
// against adaptive quadrature of its angular form, the triangle mass against closed forms
// (half-plane, wedge, full plane), against Monte Carlo within 4 standard errors, and at its stiff cases (origin on
// a corner or an edge, collinear and inverted corners, huge and tiny scales, σ → 0).
#include <gtest/gtest.h>
#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <numbers>
#include <utility>
#include <vector>
#include "core/rng.h"
#include "lbt/gaussian_triangle.h"

namespace rayes {
namespace {
constexpr double kPi = std::numbers::pi;

// G(h, a) = atan(a)/2π - T(h, a) = (1/2π) ∫_0^atan(a) (1 - e^(-h²/2cos²θ)) dθ: a bounded
// integrand on a finite range, integrated by adaptive Simpson in long double to 1e-17 (it
// resolves the near-step at θ ≈ π/2 - h that a tiny h and a huge a give). Independent of the
// implementation, which uses Owen's series in the x-form and Owen's reflection.
long double simpson(long double h2, long double lo, long double hi, long double flo, long double fmid,
                    long double fhi, long double whole, long double tolerance, int depth) {
  auto f = [h2](long double th) {
    const long double c = std::cos(th);
    return -std::expm1(-h2 / (2 * c * c));
  };
  const long double mid = (lo + hi) / 2, left = f((lo + mid) / 2), right = f((mid + hi) / 2);
  const long double l = (mid - lo) / 6 * (flo + 4 * left + fmid), r = (hi - mid) / 6 * (fmid + 4 * right + fhi);
  if (depth == 0 || std::fabs(l + r - whole) <= 15 * tolerance) return l + r + (l + r - whole) / 15;
  return simpson(h2, lo, mid, flo, left, fmid, l, tolerance / 2, depth - 1) +
         simpson(h2, mid, hi, fmid, right, fhi, r, tolerance / 2, depth - 1);
}

double owenTComplementReference(double h, double a) {
  const long double top = std::atan((long double)a), h2 = (long double)h * h;
  auto f = [h2](long double th) {
    const long double c = std::cos(th);
    return -std::expm1(-h2 / (2 * c * c));
  };
  const long double flo = f(0), fmid = f(top / 2), fhi = f(top);
  const long double whole = top / 6 * (flo + 4 * fmid + fhi);
  return double(simpson(h2, 0, top, flo, fmid, fhi, whole, 1e-17L, 60) / (2 * std::numbers::pi_v<long double>));
}

constexpr double kInf = std::numeric_limits<double>::infinity();

// The grid covers every branch and edge: h = 0, tiny, ordinary, near and past the 9 cut;
// a = 0, tiny, inside (0, 1), 1 and just past it, large, huge and infinite; both signs of both.
const double kGridH[] = {0.0, 1e-300, 1e-8, 0.01, 0.1, 0.5, 1.0, 2.0, 3.5, 5.0, 6.5, 8.5, 8.999, 9.0, 12.0};
const double kGridA[] = {0.0, 1e-12, 0.01, 0.3, 0.7, 0.999, 1.0, 1.001, 2.5, 10.0, 300.0, 1e8, kInf};

// The references on the grid, computed once for the tests below (the quadrature is slow).
constexpr int kGridHCount = std::size(kGridH), kGridACount = std::size(kGridA);
const std::array<std::array<double, kGridACount>, kGridHCount>& gridReferences() {
  static const auto table = [] {
    std::array<std::array<double, kGridACount>, kGridHCount> t{};
    for (int i = 0; i < kGridHCount; ++i)
      for (int j = 0; j < kGridACount; ++j) t[i][j] = owenTComplementReference(kGridH[i], kGridA[j]);
    return t;
  }();
  return table;
}

TEST(OwenTComplement, AgreesWithAdaptiveQuadratureOfItsAngularForm) {
  for (int i = 0; i < kGridHCount; ++i)
    for (int j = 0; j < kGridACount; ++j) {
      const double h = kGridH[i], a = kGridA[j], ref = gridReferences()[i][j];
      EXPECT_NEAR(owenTComplement(h, a), ref, 1e-14) << "h=" << h << " a=" << a;
      EXPECT_NEAR(owenTComplement(-h, -a), -ref, 1e-14) << "h=" << -h << " a=" << -a;
    }
}

// The edge term shares the series' coefficients between both ends: each pair of grid ends, in
// both orders and of either sign, against the difference of the references (each end's
// error is at most 1e-14).
TEST(OwenTComplement, DifferenceOfBothEndsAgreesWithTheReference) {
  for (int i = 0; i < kGridHCount; ++i) {
    const double h = kGridH[i];
    std::vector<std::pair<double, double>> ends;  // (a, reference G)
    for (int j = 0; j < kGridACount; ++j) {
      ends.push_back({kGridA[j], gridReferences()[i][j]});
      ends.push_back({-kGridA[j], -gridReferences()[i][j]});
    }
    for (const auto& [a0, g0] : ends)
      for (const auto& [a1, g1] : ends)
        EXPECT_NEAR(owenTComplementDifference(h, a0, a1), g1 - g0, 2e-14) << "h=" << h << " a0=" << a0 << " a1=" << a1;
  }
}

// Cut at c, an edge's term drops T beyond c: it moves by at most Q(c) from the reference, and
// not at all where the edge and both ends' reflections lie within c.
TEST(OwenTComplement, CutDropsAtMostTheTailBeyondIt) {
  for (double cut : {2.0, 5.0})
    for (int i = 0; i < kGridHCount; ++i) {
      const double h = kGridH[i];
      for (int j0 = 0; j0 < kGridACount; ++j0)
        for (int j1 = 0; j1 < kGridACount; ++j1) {
          const double a0 = -kGridA[j0], a1 = kGridA[j1];
          const double exact = gridReferences()[i][j1] + gridReferences()[i][j0];
          const double cutTerm = owenTComplementDifference(h, a0, a1, cut);
          EXPECT_NEAR(cutTerm, exact, normalTail(cut) + 2e-14) << "cut=" << cut << " h=" << h << " a0=" << a0 << " a1=" << a1;
          if (h < cut && std::fabs(a0 * h) < cut && std::fabs(a1 * h) < cut) {
            EXPECT_EQ(cutTerm, owenTComplementDifference(h, a0, a1));
          }
        }
    }
}

TEST(OwenTComplement, ClosedFormsAndSymmetries) {
  for (double a : {0.2, 1.0, 7.0, kInf}) EXPECT_EQ(owenTComplement(0, a), 0.0);
  for (double h : {0.3, 1.0, 2.0, 4.0, 8.0}) {
    const double q = normalTail(h);
    EXPECT_NEAR(owenTComplement(h, 1), 0.125 - 0.5 * q * (1 - q), 1e-15);  // T(h, 1) = Q(1-Q)/2
    EXPECT_NEAR(owenTComplement(h, kInf), 0.25 - 0.5 * q, 1e-15);          // T(h, inf) = Q/2
    EXPECT_EQ(owenTComplement(h, -0.7), -owenTComplement(h, 0.7));
    EXPECT_EQ(owenTComplement(h, -3.0), -owenTComplement(h, 3.0));
    EXPECT_EQ(owenTComplement(-h, 0.7), owenTComplement(h, 0.7));
    EXPECT_EQ(owenTComplement(h, 0), 0.0);
    EXPECT_EQ(owenTComplementDifference(h, 0.4, 0.4), 0.0);
    EXPECT_EQ(owenTComplementDifference(h, 0.4, -0.2), -owenTComplementDifference(h, -0.2, 0.4));
  }
}

// Past h = 9, G is atan(a)/2π (T < Q(9)/2 < 6e-20 is dropped); just below it differs from that
// by T alone, at most Q(h)/2, plus rounding: no jump larger than that bound at the cut.
TEST(OwenTComplement, IsTheWholeAngleFarFromTheCentreWithinItsBound) {
  for (double a : {0.3, 1.0, 40.0, kInf}) {
    const double angle = std::atan(a) / (2 * kPi);
    EXPECT_NEAR(owenTComplement(8.999, a), angle, 0.5 * normalTail(8.999) + 1e-16) << a;
    EXPECT_EQ(owenTComplement(9.0, a), angle);
    EXPECT_EQ(owenTComplement(1e6, a), angle);
    EXPECT_EQ(owenTComplementDifference(9.0, -a, a), 2 * angle);
  }
}

// At 9σ from every edge P is 0 or 1 to within the mass of a half-plane 9σ away, Q(9).
TEST(GaussianTriangle, FarFromEveryEdgeIsZeroOrOneWithinTheTail) {
  const FlatPoint a{-20, -20}, b{20, -20}, c{0, 20};
  EXPECT_EQ(gaussianTriangleMass(a, b, c), 1.0);
  EXPECT_NEAR(gaussianTriangleMass({a.x, -8.99}, {b.x, -8.99}, c), 1 - normalTail(8.99), 1e-15);  // an edge closer
  EXPECT_EQ(gaussianTriangleMass({30, 30}, {40, 30}, {35, 40}), 0.0);
  EXPECT_LE(gaussianTriangleMass({-50, 8.99}, {50, 8.99}, {0, 50}), normalTail(8.99) * (1 + 1e-9));
}

// Cut at `reach`, P loses at most the lobe's mass beyond reach of each edge: 3·Q(reach).
TEST(GaussianTriangle, CutAtTheReachLosesAtMostThreeTails) {
  for (double reach : {1.5, 5.0})
    for (uint32_t i = 0; i < 2000; ++i) {
      FlatPoint v[3];
      for (uint32_t k = 0; k < 3; ++k) {
        const RngKey key{i, k, 0, 91};
        v[k] = {12 * sampleUniform(key, 0) - 6, 12 * sampleUniform(key, 1) - 6};
      }
      const double exact = gaussianTriangleMass(v[0], v[1], v[2]);
      EXPECT_NEAR(gaussianTriangleMassWithin(v[0], v[1], v[2], reach), exact, 3 * normalTail(reach) + 1e-13)
          << "reach " << reach << " triangle " << i;
    }
}

// Cut at reach < 9, a triangle whose corners lie within R of its centroid, R⁶ <= 24·Q(reach),
// takes a 7-point cubature whose error bound is Q(reach) times the peak density's mass over
// it, Q(reach)·A/2π. Triangles around that size, all over the lobe: each within its own bound
// of the exact mass, and the bound is where the cheap mode's promise of 3·Q(reach) needs it.
TEST(GaussianTriangle, SmallTrianglesStayWithinTheCubaturesBound) {
  for (double reach : {3.0, 5.0}) {
    const double tail = normalTail(reach), rLimit = std::pow(24 * tail, 1.0 / 6);
    int small = 0;
    for (uint32_t i = 0; i < 4000; ++i) {
      const RngKey key{i, 0, 0, 92};
      const FlatPoint centre{14 * sampleUniform(key, 0) - 7, 14 * sampleUniform(key, 1) - 7};
      const double size = rLimit * (0.2 + 1.6 * sampleUniform(key, 2));  // both sides of the limit
      FlatPoint v[3];
      double r2 = 0;
      for (uint32_t k = 0; k < 3; ++k) {
        const double angle = 2 * kPi * (k + 0.8 * sampleUniform(key, 3 + k)) / 3;
        const double radius = size * (0.3 + 0.7 * sampleUniform(key, 6 + k));
        v[k] = {centre.x + radius * std::cos(angle), centre.y + radius * std::sin(angle)};
      }
      const FlatPoint c{(v[0].x + v[1].x + v[2].x) / 3, (v[0].y + v[1].y + v[2].y) / 3};
      for (const FlatPoint& p : v) r2 = std::max(r2, (p.x - c.x) * (p.x - c.x) + (p.y - c.y) * (p.y - c.y));
      const double area =
          std::fabs((v[1].x - v[0].x) * (v[2].y - v[0].y) - (v[1].y - v[0].y) * (v[2].x - v[0].x)) / 2;
      const double exact = gaussianTriangleMass(v[0], v[1], v[2]);
      const double cut = gaussianTriangleMassWithin(v[0], v[1], v[2], reach);
      if (r2 * r2 * r2 <= 24 * tail) {
        ++small;
        EXPECT_NEAR(cut, exact, tail * area / (2 * kPi) + 1e-16) << "reach " << reach << " triangle " << i;
        EXPECT_LE(tail * area / (2 * kPi), tail);  // inside the cheap mode's 3·Q(reach)
      } else {
        EXPECT_NEAR(cut, exact, 3 * tail + 1e-13) << "reach " << reach << " triangle " << i;
      }
    }
    EXPECT_GT(small, 1000) << "too few triangles took the cubature to test it";
    EXPECT_LT(small, 3500) << "too few triangles took the exact path to test the limit";
  }
  // Exact mode (reach 9, gaussianTriangleMass) never takes the cubature: a tiny triangle at the
  // centre holds its area times the peak density to the promised 1e-13.
  const double tiny = 1e-3;
  EXPECT_NEAR(gaussianTriangleMass({0, 0}, {tiny, 0}, {0, tiny}), tiny * tiny / 2 / (2 * kPi), 1e-13);
}

// Degenerate and extreme small triangles in the cheap mode: collinear corners hold nothing, a
// triangle 1e-200 across at the centre holds its area times the peak density, and one far out
// holds nothing (every value finite).
TEST(GaussianTriangle, SmallTrianglesAtTheirEdgeCases) {
  EXPECT_EQ(gaussianTriangleMassWithin({0.1, 0.1}, {0.12, 0.12}, {0.14, 0.14}, 5), 0.0);
  const double t = 1e-200;
  const double p = gaussianTriangleMassWithin({0, 0}, {t, 0}, {0, t}, 5);
  EXPECT_TRUE(std::isfinite(p));
  EXPECT_GE(p, 0);
  EXPECT_LE(p, 1e-300);  // its area underflows: 0, never negative or NaN
  const double area = 0.5e-10;
  EXPECT_NEAR(gaussianTriangleMassWithin({0, 0}, {1e-5, 0}, {0, 1e-5}, 5),
              gaussianTriangleMass({0, 0}, {1e-5, 0}, {0, 1e-5}), normalTail(5) * area / (2 * kPi));
  EXPECT_EQ(gaussianTriangleMassWithin({1e6, 1e6}, {1e6 + 0.01, 1e6}, {1e6, 1e6 + 0.01}, 5), 0.0);
}

TEST(GaussianTriangle, HalfPlaneIsTheNormalTail) {
  // One edge on the line x = d, the other corners far beyond: the mass of {x >= d}.
  for (double d : {-2.0, -0.5, 0.0, 0.25, 1.0, 3.0}) {
    const double far = 1e7;
    const double p = gaussianTriangleMass({d, -far}, {d + 3 * far, 0}, {d, far});
    EXPECT_NEAR(p, normalTail(d), 1e-12) << d;
  }
  EXPECT_NEAR(gaussianTriangleMass({1, -1e7}, {3e7, 0}, {1, 1e7}), 0.158655253931457, 1e-12);
}

TEST(GaussianTriangle, WedgeAtTheCentreHoldsItsAngle) {
  // A corner exactly at the lobe's centre (a gather point on a corner ray): the isotropic lobe
  // puts angle/2π of its mass in the wedge. Both edges through the centre contribute nothing.
  for (double angle : {0.1, 1.0, kPi / 2, 2.5}) {
    const double r = 1e6;
    const double p = gaussianTriangleMass({0, 0}, {r, 0}, {r * std::cos(angle), r * std::sin(angle)});
    EXPECT_NEAR(p, angle / (2 * kPi), 1e-12) << angle;
  }
}

TEST(GaussianTriangle, WholePlaneAndNothing) {
  EXPECT_NEAR(gaussianTriangleMass({-1e8, -1e8}, {1e8, -1e8}, {0, 1e8}), 1.0, 1e-14);
  EXPECT_LT(gaussianTriangleMass({40, 40}, {41, 40}, {40, 41}), 1e-300);
  EXPECT_EQ(gaussianTriangleMass({0, 0}, {1, 1}, {2, 2}), 0);         // collinear
  EXPECT_EQ(gaussianTriangleMass({0.3, 0.1}, {0.3, 0.1}, {1, 2}), 0);  // repeated corner
}

TEST(GaussianTriangle, OrientationDoesNotMatter) {
  // Past a focus the flux triangle inverts; its mass is that of the mirror order.
  const FlatPoint a{-0.3, -0.8}, b{1.2, 0.1}, c{-0.2, 1.4};
  EXPECT_EQ(gaussianTriangleMass(a, b, c), gaussianTriangleMass(a, c, b));
  EXPECT_NEAR(gaussianTriangleMass(a, b, c), gaussianTriangleMass(b, c, a), 1e-15);  // summed in another order
}

TEST(GaussianTriangle, AdditiveUnderSplitting) {
  const FlatPoint a{-0.7, -0.4}, b{1.5, -0.2}, c{0.1, 1.3};
  for (double t : {0.0001, 0.3, 0.5, 0.9}) {
    const FlatPoint d{b.x + t * (c.x - b.x), b.y + t * (c.y - b.y)};
    EXPECT_NEAR(gaussianTriangleMass(a, b, c), gaussianTriangleMass(a, b, d) + gaussianTriangleMass(a, d, c), 1e-14);
  }
}

TEST(GaussianTriangle, AgreesWithMonteCarloWithinFourStandardErrors) {
  struct Case { FlatPoint a, b, c; double sigma; };
  const Case cases[] = {{{-0.3, -0.8}, {1.2, 0.1}, {-0.2, 1.4}, 1.0},      // contains the centre
                        {{0.5, 0.2}, {2.0, 0.4}, {0.9, 1.9}, 1.0},         // beside it
                        {{0.01, -0.02}, {0.05, 0.01}, {0.0, 0.04}, 0.03},  // narrow lobe (σ scales)
                        {{3, 3}, {0.2, 5}, {4, 0.1}, 2.0}};
  const int n = 1 << 20;
  for (const Case& k : cases) {
    const double p = gaussianTriangleMass(k.a, k.b, k.c, k.sigma);
    auto side = [](FlatPoint p, FlatPoint q, double x, double y) {
      return (q.x - p.x) * (y - p.y) - (q.y - p.y) * (x - p.x);
    };
    int inside = 0;
    for (int i = 0; i < n; ++i) {
      const RngKey key{uint32_t(i), 0, 0, 77};
      const double u1 = 1.0 - sampleUniform(key, 0), u2 = sampleUniform(key, 1);  // u1 in (0, 1]
      const double r = k.sigma * std::sqrt(-2 * std::log(u1)), phi = 2 * kPi * u2;
      const double x = r * std::cos(phi), y = r * std::sin(phi);
      const double s0 = side(k.a, k.b, x, y), s1 = side(k.b, k.c, x, y), s2 = side(k.c, k.a, x, y);
      inside += (s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0);
    }
    const double est = double(inside) / n, se = std::sqrt(p * (1 - p) / n);
    EXPECT_NEAR(est, p, 4 * se) << "sigma " << k.sigma;
  }
}

TEST(GaussianTriangle, ScaleInvarianceAndTheSpecularLimit) {
  const FlatPoint a{-0.3, -0.8}, b{1.2, 0.1}, c{-0.2, 1.4};
  for (double s : {1e-6, 0.05, 30.0}) {
    const FlatPoint as{a.x * s, a.y * s}, bs{b.x * s, b.y * s}, cs{c.x * s, c.y * s};
    EXPECT_NEAR(gaussianTriangleMass(as, bs, cs, s), gaussianTriangleMass(a, b, c), 1e-13);
  }
  // σ → 0 tends to the indicator: 1 inside, 1/2 on an edge, the angle on a corner, 0 outside.
  EXPECT_NEAR(gaussianTriangleMass(a, b, c, 1e-9), 1.0, 1e-12);
  EXPECT_EQ(gaussianTriangleMass(a, b, c, 0.0), 1.0);
  const FlatPoint e0{-1, 0}, e1{1, 0}, e2{0, 2};  // the centre on edge e0-e1
  EXPECT_NEAR(gaussianTriangleMass(e0, e1, e2, 0.0), 0.5, 1e-15);
  EXPECT_NEAR(gaussianTriangleMass(e0, e1, e2, 1e-9), 0.5, 1e-12);
  EXPECT_NEAR(gaussianTriangleMass({0, 0}, {1, 0}, {0, 1}, 0.0), 0.25, 1e-15);  // right-angle corner
  EXPECT_EQ(gaussianTriangleMass({1, 1}, {2, 1}, {1, 2}, 0.0), 0.0);
  // A lobe so narrow that the scaled corners overflow falls back to the same limit.
  EXPECT_NEAR(gaussianTriangleMass(a, b, c, 1e-310), 1.0, 1e-15);
}

TEST(GaussianTriangle, ContinuousAcrossAnEdge) {
  // E has no jump across a glossy flux-triangle edge: moving the triangle by ±ε across the
  // centre changes P by O(ε) (its density at the edge is at most 1/2π per unit length).
  const double eps = 1e-9;
  for (double off : {-eps, 0.0, eps}) {
    const double p = gaussianTriangleMass({-1, off}, {1, off}, {0, 2 + off});
    EXPECT_NEAR(p, gaussianTriangleMass({-1, 0}, {1, 0}, {0, 2}), 2 * eps / (2 * kPi) + 1e-15);
  }
}

TEST(GaussianTriangle, StaysFiniteAtExtremeInputs) {
  const double big = 1e300, tiny = 1e-300, inf = std::numeric_limits<double>::infinity();
  for (const double p : {gaussianTriangleMass({-big, -big}, {big, -big}, {0, big}),
                         gaussianTriangleMass({tiny, 0}, {2 * tiny, 0}, {tiny, tiny}),
                         gaussianTriangleMass({-1, tiny}, {1, tiny}, {0, 1}),
                         gaussianTriangleMass({0, 0}, {inf, 0}, {0, 1}),
                         gaussianTriangleMass({0, 0}, {std::nan(""), 0}, {0, 1}),
                         gaussianTriangleMass({-1, -1}, {1, -1}, {0, 1}, big)}) {
    EXPECT_TRUE(std::isfinite(p));
    EXPECT_GE(p, 0);
    EXPECT_LE(p, 1);
  }
  // An edge 1e-300 from the centre: half the mass, to rounding.
  EXPECT_NEAR(gaussianTriangleMass({-1e8, tiny}, {1e8, tiny}, {0, 1e8}), 0.5, 1e-14);
}

}  // namespace
}  // namespace rayes
