// The glossy gather's footprint integral (lbt/gaussian_triangle.h): Owen's T against direct
// quadrature of its angular form, the triangle mass against closed forms (half-plane, wedge,
// full plane), against Monte Carlo within 4 standard errors, and at its stiff cases (origin on
// a corner or an edge, collinear and inverted corners, huge and tiny scales, σ → 0).
#include <gtest/gtest.h>
#include <cmath>
#include <numbers>
#include "core/rng.h"
#include "lbt/gaussian_triangle.h"

namespace rayes {
namespace {
constexpr double kPi = std::numbers::pi;

// T(h, a) = (1/2π) ∫_0^atan(a) exp(-h² / 2cos²θ) dθ: a bounded integrand on a finite range,
// integrated by composite Simpson in long double. Independent of the implementation, which
// uses the x-form, Gauss-Legendre and Owen's reflection.
double owenTReference(double h, double a) {
  const long double top = std::atan((long double)a);
  const int n = 20000;
  const long double step = top / n;
  long double sum = 0;
  for (int i = 0; i <= n; ++i) {
    const long double th = step * i, c = std::cos(th);
    const long double f = std::exp(-(long double)h * h / (2 * c * c));
    sum += f * (i == 0 || i == n ? 1 : (i % 2 ? 4 : 2));
  }
  return double(sum * step / 3 / (2 * std::numbers::pi_v<long double>));
}

TEST(OwenT, AgreesWithDirectQuadratureOfItsAngularForm) {
  for (double h : {0.0, 0.1, 0.5, 1.0, 2.0, 3.5, 6.0})
    for (double a : {0.01, 0.3, 0.999, 1.0, 1.001, 2.5, 10.0, 300.0})
      EXPECT_NEAR(owenT(h, a), owenTReference(h, a), 1e-13) << "h=" << h << " a=" << a;
}

TEST(OwenT, ClosedFormsAndSymmetries) {
  for (double a : {0.2, 1.0, 7.0}) EXPECT_NEAR(owenT(0, a), std::atan(a) / (2 * kPi), 1e-15);
  for (double h : {0.3, 1.0, 2.0}) {
    const double q = normalTail(h);
    EXPECT_NEAR(owenT(h, 1), 0.5 * q * (1 - q), 1e-15);                       // T(h, 1)
    EXPECT_NEAR(owenT(h, std::numeric_limits<double>::infinity()), 0.5 * q, 1e-15);  // T(h, inf)
    EXPECT_EQ(owenT(h, -0.7), -owenT(h, 0.7));
    EXPECT_EQ(owenT(-h, 0.7), owenT(h, 0.7));
  }
  EXPECT_EQ(owenT(1, 0), 0);
}

// At 9σ from every edge P is 0 or 1 to within the mass of a half-plane 9σ away, Q(9).
TEST(GaussianTriangle, FarFromEveryEdgeIsZeroOrOneWithinTheTail) {
  const FlatPoint a{-20, -20}, b{20, -20}, c{0, 20};
  EXPECT_EQ(gaussianTriangleMass(a, b, c), 1.0);
  EXPECT_NEAR(gaussianTriangleMass({a.x, -8.99}, {b.x, -8.99}, c), 1 - normalTail(8.99), 1e-15);  // an edge closer
  EXPECT_EQ(gaussianTriangleMass({30, 30}, {40, 30}, {35, 40}), 0.0);
  EXPECT_LE(gaussianTriangleMass({-50, 8.99}, {50, 8.99}, {0, 50}), normalTail(8.99) * (1 + 1e-9));
}

// Far from the centre T is below Q(h)/2 (< 6e-20 at h = 9), and is returned as 0 there: no jump
// larger than that bound at the cut, nothing negative, nothing that is not finite.
TEST(OwenT, VanishesFarFromTheCentreWithinItsBound) {
  for (double a : {0.3, 1.0, 40.0, std::numeric_limits<double>::infinity()}) {
    const double below = owenT(8.999, a);
    EXPECT_GE(below, 0.0);
    EXPECT_LE(below, 0.5 * normalTail(8.999) * (1 + 1e-9)) << a;
    EXPECT_EQ(owenT(9.0, a), 0.0);
    EXPECT_EQ(owenT(1e6, a), 0.0);
  }
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
