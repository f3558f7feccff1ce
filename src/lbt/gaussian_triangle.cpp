#include "lbt/gaussian_triangle.h"
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace rayes {
namespace {
constexpr double kTwoPi = 2 * std::numbers::pi;
constexpr double kNegligibleOwenH = 9;

// 20-point Gauss-Legendre rule on [-1, 1], computed once by Newton's method on P_20 (the
// standard construction; no table to mistype). On [0, a] with |a| <= 1 the Owen integrand
// e^(-h²(1+x²)/2)/(1+x²) is analytic with its nearest poles at ±i, so 20 points give ~1e-17.
struct GaussLegendre20 {
  static constexpr int n = 20;
  std::array<double, n> x{}, w{};
  GaussLegendre20() {
    for (int i = 0; i < n; ++i) {
      double z = std::cos(std::numbers::pi * (i + 0.75) / (n + 0.5)), dp = 0;
      for (int it = 0; it < 100; ++it) {
        double p0 = 1, p1 = z;
        for (int k = 2; k <= n; ++k) {
          const double p2 = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k;
          p0 = p1;
          p1 = p2;
        }
        dp = n * (z * p1 - p0) / (z * z - 1);
        const double step = p1 / dp;
        z -= step;
        if (std::fabs(step) < 1e-16) break;
      }
      x[i] = z;
      w[i] = 2 / ((1 - z * z) * dp * dp);
    }
  }
};

const GaussLegendre20& rule() {
  static const GaussLegendre20 r;
  return r;
}

// T(h, a) for h >= 0 and 0 <= a <= 1, by quadrature.
double owenTQuadrature(double h, double a) {
  const GaussLegendre20& g = rule();
  double sum = 0;
  for (int i = 0; i < GaussLegendre20::n; ++i) {
    const double x = 0.5 * a * (g.x[i] + 1);
    const double q = 1 + x * x;
    sum += g.w[i] * std::exp(-0.5 * h * h * q) / q;
  }
  return 0.5 * a * sum / kTwoPi;
}

// G(h, a) = atan(a)/2π - T(h, a) = (1/2π) ∫_0^atan(a) (1 - e^(-h²/2cos²θ)) dθ, h > 0:
// the part of an edge's subtended angle that the lobe's mass covers.
double edgeTerm(double h, double a) { return std::atan(a) / kTwoPi - owenT(h, a); }

bool finite(FlatPoint p) { return std::isfinite(p.x) && std::isfinite(p.y); }

// Sum over the edges of a counter-clockwise triangle; `term(h, s, d)` is one edge end's value.
template <class Term>
double sumOverEdges(const FlatPoint (&v)[3], Term term) {
  double sum = 0;
  for (int e = 0; e < 3; ++e) {
    const FlatPoint p = v[e], q = v[(e + 1) % 3];
    double tx = q.x - p.x, ty = q.y - p.y;
    const double len = std::hypot(tx, ty);
    if (!(len > 0)) continue;
    tx /= len;
    ty /= len;
    // Outward normal (ty, -tx) of a counter-clockwise triangle: the origin is inside when
    // every edge has d > 0. An edge through the origin (d = 0) contributes nothing. d is
    // taken at the end nearer the origin, where its rounding error is smallest (exactly 0
    // when that end is the origin: a gather point on a corner ray).
    const FlatPoint near = std::hypot(p.x, p.y) <= std::hypot(q.x, q.y) ? p : q;
    const double d = near.x * ty - near.y * tx;
    if (d == 0) continue;
    const double s0 = p.x * tx + p.y * ty, s1 = q.x * tx + q.y * ty;
    sum += std::copysign(1.0, d) * (term(std::fabs(d), s1) - term(std::fabs(d), s0));
  }
  return sum;
}

// Orders the corners counter-clockwise; false when they are collinear (zero area).
bool counterClockwise(FlatPoint a, FlatPoint b, FlatPoint c, FlatPoint (&v)[3]) {
  const double cross = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
  if (!(cross != 0)) return false;
  v[0] = a;
  v[1] = cross > 0 ? b : c;
  v[2] = cross > 0 ? c : b;
  return true;
}

double specularMass(FlatPoint a, FlatPoint b, FlatPoint c) {
  FlatPoint v[3];
  if (!counterClockwise(a, b, c, v)) return 0;
  // The σ → 0 limit of G is atan(a)/2π: the winding angle, with 1/2 on an edge and the
  // interior angle / 2π on a corner.
  const double p = sumOverEdges(v, [](double h, double s) { return std::atan2(s, h) / kTwoPi; });
  return std::clamp(p, 0.0, 1.0);
}
}  // namespace

double normalTail(double x) { return 0.5 * std::erfc(x / std::numbers::sqrt2); }

double owenT(double h, double a) {
  h = std::fabs(h);
  if (a < 0) return -owenT(h, -a);
  if (!(a > 0)) return 0;  // a = 0 (or NaN)
  if (h == 0) return std::atan(a) / kTwoPi;
  // 0 <= T(h, a) <= T(h, inf) = Q(h)/2 < 6e-20 past h = 9: far below the 1e-14 promised, and
  // it skips the quadrature's exp calls, which underflow (glibc's slow errno path) for the
  // narrow lobes where almost every gather point lies many σ from every edge.
  if (h >= kNegligibleOwenH) return 0;
  if (a <= 1) return owenTQuadrature(h, a);
  // Owen's reflection for a > 1, written with tails so that nothing cancels for large h:
  // T(h, a) = ½(Q(h) + Q(ah)) - Q(h)·Q(ah) - T(ah, 1/a).
  const double q1 = normalTail(h), q2 = normalTail(a * h);
  const double rest = std::isinf(a) ? 0.0 : owenTQuadrature(a * h, 1 / a);
  return 0.5 * (q1 + q2) - q1 * q2 - rest;
}

double gaussianTriangleMass(FlatPoint a, FlatPoint b, FlatPoint c) {
  return gaussianTriangleMassWithin(a, b, c, kNegligibleOwenH);
}

double gaussianTriangleMassWithin(FlatPoint a, FlatPoint b, FlatPoint c, double reach) {
  if (!finite(a) || !finite(b) || !finite(c)) return 0;
  FlatPoint v[3];
  if (!counterClockwise(a, b, c, v)) return 0;
  // A centre at least kNegligibleOwenH from every edge's line gets 1 (inside) or 0 (outside)
  // to within Q(9) < 1.2e-19, without the six atan calls of the edge terms: the usual case for
  // narrow lobes. (The triangle lies on the inner side of each edge's line, so a centre that far
  // beyond one line sees at most the mass of a half-plane that far away.)
  bool inside = true;
  for (int e = 0; e < 3; ++e) {
    const FlatPoint p = v[e], q = v[(e + 1) % 3];
    const double length = std::sqrt((q.x - p.x) * (q.x - p.x) + (q.y - p.y) * (q.y - p.y));
    const double d = (p.x * q.y - p.y * q.x) / length;  // > 0 on the inner side
    if (d <= -reach) return 0;
    inside = inside && d >= reach;
  }
  if (inside) return 1;
  // s/h may overflow to ±inf for an edge passing within 1e-300 of the centre: G(h, ±inf) is
  // still defined (owenT handles a = inf), and such an edge's term is ~h anyway.
  const double p = sumOverEdges(v, [](double h, double s) { return edgeTerm(h, s / h); });
  return std::clamp(p, 0.0, 1.0);
}

double gaussianTriangleMass(FlatPoint a, FlatPoint b, FlatPoint c, double sigma, double reach) {
  if (!finite(a) || !finite(b) || !finite(c)) return 0;
  if (!(sigma > 0)) return specularMass(a, b, c);
  const double k = 1 / sigma;
  const FlatPoint as{a.x * k, a.y * k}, bs{b.x * k, b.y * k}, cs{c.x * k, c.y * k};
  // A lobe so narrow that the scaled corners overflow is the specular limit.
  if (!finite(as) || !finite(bs) || !finite(cs)) return specularMass(a, b, c);
  return gaussianTriangleMassWithin(as, bs, cs, std::min(reach, kNegligibleOwenH));
}

}  // namespace rayes
