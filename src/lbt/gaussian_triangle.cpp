#include "lbt/gaussian_triangle.h"
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace rayes {
namespace {
constexpr double kTwoPi = 2 * std::numbers::pi;
constexpr double kNegligibleOwenH = 9;

// Owen's series for |a| <= 1, x = h²/2, N ~ Poisson(x):
//
//   2π·G(h, a) = Σ_j (-1)^j · a^(2j+1)/(2j+1) · P(N > j)
//
// (expand 1/(1+t²) in T's x-form and integrate term by term). The terms alternate in sign and
// shrink in magnitude (|a| <= 1, P(N > j) falls with j), so stopping before a term below
// kSeriesTolerance leaves an error below it: a proven bound, not a tuned one. The number of
// terms grows with h and |a|; the worst case, h just below 9 and |a| = 1, needs about 100.
constexpr int kMaxSeriesTerms = 128;
constexpr double kSeriesTolerance = 1e-16;

struct SeriesTables {
  std::array<double, kMaxSeriesTerms + 1> oddReciprocal{}, reciprocal{};
  constexpr SeriesTables() {
    for (int j = 0; j <= kMaxSeriesTerms; ++j) {
      oddReciprocal[j] = 1.0 / (2 * j + 1);
      reciprocal[j] = j > 0 ? 1.0 / j : 0;
    }
  }
};
constexpr SeriesTables kSeries;

// 2π·[G(h, a1) - G(h, a0)] for 0 < h < 9 and |a0|, |a1| <= 1: one pass, the coefficients
// shared by both ends. The error is below 2·kSeriesTolerance plus rounding (the Poisson tail
// is carried by subtraction: its absolute error stays near 1e-16·x).
double seriesDifference(double h, double a0, double a1) {
  const double x = 0.5 * h * h;
  // P(N = j) and P(N > j); 1 - e^(-x) loses relative accuracy for tiny x, not absolute.
  double pmf = std::exp(-x), tail = 1 - pmf;
  const double step0 = a0 * a0, step1 = a1 * a1, stepMax = std::max(step0, step1);
  double pow0 = a0, pow1 = a1, powMax = std::max(std::fabs(a0), std::fabs(a1));  // a^(2j+1)
  double sum = 0, sign = 1;
  for (int j = 0; j < kMaxSeriesTerms; ++j) {
    const double c = tail * kSeries.oddReciprocal[j];
    if (!(c * powMax > kSeriesTolerance)) break;
    sum += sign * c * (pow1 - pow0);
    sign = -sign;
    pow0 *= step0;
    pow1 *= step1;
    powMax *= stepMax;
    pmf *= x * kSeries.reciprocal[j + 1];
    tail -= pmf;
  }
  return sum;
}

// G(h, a) for 0 < h < cut <= 9 and |a| > 1, by Owen's reflection T(h, a) = ½(Q(h) + Q(ah)) -
// Q(h)·Q(ah) - T(ah, 1/a) and atan(a) = π/2 - atan(1/a), written with tails so that nothing
// cancels for large h: G(h, a) = 1/4 - ½Q(h) - ½Q(ah) + Q(h)·Q(ah) - G(ah, 1/a). tailH = Q(h).
// Past the cut (|a|h >= cut) Q(|a|h) and T(|a|h, 1/|a|) are dropped: that changes G by
// -Q(|a|h)·(½ - Q(h)) + T(|a|h, 1/|a|), both parts in [0, ½Q(|a|h)], so at most ½Q(cut).
double reflectedComplement(double h, double a, double tailH, double cut) {
  const double b = std::fabs(a), hb = h * b;  // hb = inf for a = ±inf
  // Written atan(a)/2π - T(h, a) like the terms of edges past the cut, so that a sum of such
  // terms that should cancel (a centre far outside a triangle) cancels to rounding of the
  // tiny T, not of 1/4.
  if (hb >= cut) return std::atan(a) / kTwoPi - std::copysign(0.5 * tailH, a);
  const double tailHb = normalTail(hb);
  const double outer = 0.5 * tailH + 0.5 * tailHb - tailH * tailHb;
  return std::copysign(0.25 - outer - seriesDifference(hb, 0, 1 / b) / kTwoPi, a);
}

// One end's G for 0 < h < cut <= 9, tailH = Q(h) (only read for |a| > 1).
double complementBelowCut(double h, double a, double tailH, double cut) {
  if (std::fabs(a) <= 1) return seriesDifference(h, 0, a) / kTwoPi;
  return reflectedComplement(h, a, tailH, cut);
}

bool finite(FlatPoint p) { return std::isfinite(p.x) && std::isfinite(p.y); }

// An edge seen from the origin: d its signed distance (> 0 on the inner side of a
// counter-clockwise triangle), s0 and s1 its ends' coordinates along it from the origin's foot.
struct EdgeFrame {
  double d, s0, s1;
};

// False for an edge of zero length.
bool edgeFrame(FlatPoint p, FlatPoint q, EdgeFrame& e) {
  double tx = q.x - p.x, ty = q.y - p.y;
  double len = std::sqrt(tx * tx + ty * ty);
  // The squares overflow or underflow for corners ~1e154 or ~1e-154 apart; hypot does not,
  // and costs several times more, so it is asked only there.
  if (!(len > 1e-150 && len < 1e150)) len = std::hypot(tx, ty);
  if (!(len > 0)) return false;
  tx /= len;
  ty /= len;
  // d is taken at the end nearer the origin, where its rounding error is smallest (exactly 0
  // when that end is the origin: a gather point on a corner ray). An edge through the origin
  // (d = 0) contributes nothing.
  const double np = p.x * p.x + p.y * p.y, nq = q.x * q.x + q.y * q.y;
  const bool pNearer = std::isnormal(np) && std::isnormal(nq) ? np <= nq
                                                              : std::hypot(p.x, p.y) <= std::hypot(q.x, q.y);
  const FlatPoint near = pNearer ? p : q;
  e = {near.x * ty - near.y * tx, p.x * tx + p.y * ty, q.x * tx + q.y * ty};
  return true;
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

// Radon's 7-point rule of degree 5 on one triangle with centroid c: ∬ e^(-|φ|²/2) dφ, to be
// divided by 2π.
double rule7(const FlatPoint (&v)[3], FlatPoint c) {
  constexpr double a1 = 0.10128650732345633880, w1 = 0.12593918054482715260;
  constexpr double a2 = 0.47014206410511508977, w2 = 0.13239415278850618074;
  constexpr double w0 = 0.225;
  auto density = [](double x, double y) { return std::exp(-0.5 * (x * x + y * y)); };
  auto orbit = [&](double a) {  // the three points with barycentrics (1 - 2a, a, a) and their turns
    const double b = 1 - 2 * a;
    double sum = 0;
    for (int i = 0; i < 3; ++i) {
      const FlatPoint& p = v[i];
      const FlatPoint& q = v[(i + 1) % 3];
      const FlatPoint& r = v[(i + 2) % 3];
      sum += density(b * p.x + a * (q.x + r.x), b * p.y + a * (q.y + r.y));
    }
    return sum;
  };
  const double area = std::fabs((v[1].x - v[0].x) * (v[2].y - v[0].y) - (v[1].y - v[0].y) * (v[2].x - v[0].x)) / 2;
  return area * (w0 * density(c.x, c.y) + w1 * orbit(a1) + w2 * orbit(a2));
}

// The lobe's mass over a triangle small against σ by the 7-point rule of degree 5 (Radon 1948,
// as tabulated by Dunavant 1985; positive weights, exact for polynomials up to degree 5), when
// its error bound allows:
//
// With p5 the Taylor polynomial of degree 5 of the density g about the centroid c, the rule
// and the integral are both exact on p5, and both weigh |g - p5| with total weight A, so the
// error is at most 2A·sup_T|g - p5| <= 2A·M6·R⁶/6!, R the largest distance from c to a corner
// and M6 the largest sixth derivative of g along a line in T. Along a unit direction u,
// ∂_u⁶ g = He6(u·φ)·g(φ) (g factors into the two 1D densities along u and across it), and
// |He6(s)|·e^(-s²/2) peaks at s = 0 with 15, so M6 <= 15/2π everywhere. The rule is taken
// when that bound is at most `allowed`·A/2π: the error is at most `allowed` times the peak
// density's mass over the triangle. Returns false (and leaves `mass`) when it is not.
//
// Written by hand, not from a library: none of the five has it, and it replaces the three
// edges' Owen series (their exp, erfc and up to ~40 series terms each) by seven exps where the
// gather's triangles are small against σ (most of lbt-discoball-glossy's:
// bench/history/2026-11.md).
bool smallTriangleMass(const FlatPoint (&v)[3], double allowed, double& mass) {
  const FlatPoint c{(v[0].x + v[1].x + v[2].x) / 3, (v[0].y + v[1].y + v[2].y) / 3};
  double r2 = 0;
  for (const FlatPoint& p : v) r2 = std::max(r2, (p.x - c.x) * (p.x - c.x) + (p.y - c.y) * (p.y - c.y));
  // 2·M6·R⁶/6! <= allowed/2π with M6 = 15/2π: R⁶ <= allowed·6!/30.
  const double r6 = r2 * r2 * r2, limit = allowed * 24;
  if (!(r6 <= limit)) return false;
  mass = rule7(v, c) / kTwoPi;
  return true;
}

double specularMass(FlatPoint a, FlatPoint b, FlatPoint c) {
  FlatPoint v[3];
  if (!counterClockwise(a, b, c, v)) return 0;
  // The σ → 0 limit of G is atan(a)/2π: the winding angle, with 1/2 on an edge and the
  // interior angle / 2π on a corner.
  double p = 0;
  for (int i = 0; i < 3; ++i) {
    EdgeFrame e;
    if (!edgeFrame(v[i], v[(i + 1) % 3], e) || e.d == 0) continue;
    const double h = std::fabs(e.d);
    p += std::copysign(1.0, e.d) * (std::atan2(e.s1, h) / kTwoPi - std::atan2(e.s0, h) / kTwoPi);
  }
  return std::clamp(p, 0.0, 1.0);
}
}  // namespace

double normalTail(double x) { return 0.5 * std::erfc(x / std::numbers::sqrt2); }

double owenTComplement(double h, double a) {
  h = std::fabs(h);
  if (!(h > 0) || a == 0 || std::isnan(a)) return 0;
  // T(h, a) <= T(h, inf) = Q(h)/2 < 6e-20 past h = 9: far below the 1e-14 promised.
  if (h >= kNegligibleOwenH) return std::atan(a) / kTwoPi;
  return complementBelowCut(h, a, std::fabs(a) > 1 ? normalTail(h) : 0, kNegligibleOwenH);
}

double owenTComplementDifference(double h, double a0, double a1, double cut) {
  h = std::fabs(h);
  cut = std::min(cut, kNegligibleOwenH);
  if (!(h > 0)) return 0;
  // T(h, a1) - T(h, a0) is dropped: T is odd and monotone in a and below Q(h)/2.
  if (h >= cut) return (std::atan(a1) - std::atan(a0)) / kTwoPi;
  const bool series0 = std::fabs(a0) <= 1, series1 = std::fabs(a1) <= 1;
  if (series0 && series1) return seriesDifference(h, a0, a1) / kTwoPi;
  const double tailH = normalTail(h);
  return complementBelowCut(h, a1, tailH, cut) - complementBelowCut(h, a0, tailH, cut);
}

double gaussianTriangleMass(FlatPoint a, FlatPoint b, FlatPoint c) {
  return gaussianTriangleMassWithin(a, b, c, kNegligibleOwenH);
}

double gaussianTriangleMassWithin(FlatPoint a, FlatPoint b, FlatPoint c, double reach) {
  if (!finite(a) || !finite(b) || !finite(c)) return 0;
  FlatPoint v[3];
  if (!counterClockwise(a, b, c, v)) return 0;
  // Cut at reach < 9 (the gather's cheap mode, already within 3·Q(reach)), a triangle small
  // against σ takes the cubature if it is within Q(reach) of the peak density's mass over it.
  // (Q(reach) is kept per thread: the gather asks with one reach, and erfc is what the
  // cubature saves.)
  thread_local double tailReach = -1, tail = 0;
  if (reach != tailReach) tailReach = reach, tail = normalTail(reach);
  double small;
  if (reach < kNegligibleOwenH && smallTriangleMass(v, tail, small)) return std::min(small, 1.0);
  // A centre at least `reach` from every edge's line gets 1 (inside) or 0 (outside) to within
  // Q(reach) per edge, without the edge terms: the usual case for narrow lobes. (The triangle
  // lies on the inner side of each edge's line, so a centre that far beyond one line sees at
  // most the mass of a half-plane that far away.) Otherwise each edge's term is cut at the
  // same reach, again to within Q(reach) per edge (owenTComplementDifference).
  EdgeFrame edges[3];
  bool has[3];
  bool inside = true;
  for (int i = 0; i < 3; ++i) {
    has[i] = edgeFrame(v[i], v[(i + 1) % 3], edges[i]);
    if (has[i] && edges[i].d <= -reach) return 0;
    inside = inside && has[i] && edges[i].d >= reach;
  }
  if (inside) return 1;
  double p = 0;
  for (int i = 0; i < 3; ++i) {
    if (!has[i] || edges[i].d == 0) continue;
    // s/h may overflow to ±inf for an edge passing within 1e-300 of the centre: G(h, ±inf) is
    // still defined, and such an edge's term is ~h anyway.
    const double h = std::fabs(edges[i].d);
    p += std::copysign(1.0, edges[i].d) * owenTComplementDifference(h, edges[i].s0 / h, edges[i].s1 / h, reach);
  }
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
