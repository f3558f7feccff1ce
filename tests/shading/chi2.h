// A χ² goodness-of-fit test of a direction sampler against its density (after pbrt-v3's
// chi2test): the sphere is cut into cells in (θ, φ); the expected count of a cell is N times
// the density integrated over it (nested adaptive Simpson); samples that produce no direction
// or a delta direction go into one extra cell whose expectation is N (1 - ∫ pdf). Cells
// expecting fewer than 5 are pooled. The p-value comes from the regularised upper incomplete
// gamma function; tests compare it with a significance level corrected for the number of
// tests (Šidák), so the suite as a whole has a 1 % false-alarm rate.
#pragma once
#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <vector>
#include "core/vec.h"

namespace rayes::testing {

// Regularised lower incomplete gamma P(a, x) (Numerical Recipes: series / continued fraction).
inline double gammaP(double a, double x) {
  if (x <= 0) return 0;
  const double gln = std::lgamma(a);
  if (x < a + 1) {
    double ap = a, sum = 1 / a, del = sum;
    for (int n = 0; n < 10000; ++n) {
      ap += 1; del *= x / ap; sum += del;
      if (std::fabs(del) < std::fabs(sum) * 1e-15) break;
    }
    return sum * std::exp(-x + a * std::log(x) - gln);
  }
  double b = x + 1 - a, c = 1 / 1e-300, d = 1 / b, h = d;
  for (int i = 1; i < 10000; ++i) {
    const double an = -i * (i - a);
    b += 2;
    d = an * d + b; if (std::fabs(d) < 1e-300) d = 1e-300;
    c = b + an / c; if (std::fabs(c) < 1e-300) c = 1e-300;
    d = 1 / d;
    const double del = d * c;
    h *= del;
    if (std::fabs(del - 1) < 1e-15) break;
  }
  return 1 - std::exp(-x + a * std::log(x) - gln) * h;
}

inline double chi2PValue(double chi2, int dof) { return dof > 0 ? 1 - gammaP(0.5 * dof, 0.5 * chi2) : 1.0; }

// Significance level per test so that `tests` independent tests together reach `overall`.
inline double sidak(double overall, int tests) { return 1 - std::pow(1 - overall, 1.0 / tests); }

inline double adaptiveSimpson(const std::function<double(double)>& f, double a, double b, double fa, double fm,
                              double fb, double whole, double eps, int depth) {
  const double m = 0.5 * (a + b), lm = 0.5 * (a + m), rm = 0.5 * (m + b);
  const double flm = f(lm), frm = f(rm);
  const double left = (m - a) / 6 * (fa + 4 * flm + fm), right = (b - m) / 6 * (fm + 4 * frm + fb);
  const double diff = left + right - whole;
  if (depth <= 0 || std::fabs(diff) <= 15 * eps) return left + right + diff / 15;
  return adaptiveSimpson(f, a, m, fa, flm, fm, left, eps / 2, depth - 1) +
         adaptiveSimpson(f, m, b, fm, frm, fb, right, eps / 2, depth - 1);
}
// Minimum subdivision first (so narrow peaks are seen), then adaptive.
inline double integrate(const std::function<double(double)>& f, double a, double b, double eps, int minSplit = 8) {
  double sum = 0;
  for (int i = 0; i < minSplit; ++i) {
    const double x0 = a + (b - a) * i / minSplit, x1 = a + (b - a) * (i + 1) / minSplit;
    const double f0 = f(x0), f1 = f(x1), fm = f(0.5 * (x0 + x1));
    sum += adaptiveSimpson(f, x0, x1, f0, fm, f1, (x1 - x0) / 6 * (f0 + 4 * fm + f1), eps / minSplit, 10);
  }
  return sum;
}

struct Chi2Result {
  double chi2 = 0, pValue = 1, pdfMass = 0;
  int dof = 0;
};

// sampler(i, dir) returns false for "no direction / delta"; pdf(dir) is the solid-angle density.
inline Chi2Result chi2Test(const std::function<bool(int, Vec3&)>& sampler, const std::function<double(Vec3)>& pdf,
                           int n, int thetaRes = 10, int phiRes = 20) {
  const double pi = std::numbers::pi;
  auto dirOf = [](double theta, double phi) {
    return Vec3{float(std::sin(theta) * std::cos(phi)), float(std::sin(theta) * std::sin(phi)), float(std::cos(theta))};
  };
  std::vector<double> observed(size_t(thetaRes) * phiRes + 1, 0.0), expected(observed.size(), 0.0);
  for (int i = 0; i < n; ++i) {
    Vec3 d;
    if (!sampler(i, d)) { observed.back() += 1; continue; }
    const double theta = std::atan2(std::sqrt(double(d.x) * d.x + double(d.y) * d.y), double(d.z));
    double phi = std::atan2(double(d.y), double(d.x));
    if (phi < 0) phi += 2 * pi;
    const int ti = std::clamp(int(theta / pi * thetaRes), 0, thetaRes - 1);
    const int pj = std::clamp(int(phi / (2 * pi) * phiRes), 0, phiRes - 1);
    observed[size_t(ti) * phiRes + pj] += 1;
  }
  double mass = 0;
  for (int ti = 0; ti < thetaRes; ++ti)
    for (int pj = 0; pj < phiRes; ++pj) {
      const double t0 = pi * ti / thetaRes, t1 = pi * (ti + 1) / thetaRes;
      const double p0 = 2 * pi * pj / phiRes, p1 = 2 * pi * (pj + 1) / phiRes;
      const double v = integrate([&](double t) {
        return integrate([&](double p) { return pdf(dirOf(t, p)); }, p0, p1, 1e-5, 4) * std::sin(t);
      }, t0, t1, 1e-6, 4);
      expected[size_t(ti) * phiRes + pj] = v * n;
      mass += v;
    }
  expected.back() = std::max(0.0, (1 - mass) * n);
  // Pool the cells expecting fewer than 5 samples.
  std::vector<size_t> idx(observed.size());
  for (size_t i = 0; i < idx.size(); ++i) idx[i] = i;
  std::sort(idx.begin(), idx.end(), [&](size_t a, size_t b) { return expected[a] < expected[b]; });
  Chi2Result r;
  r.pdfMass = mass;
  double pooledE = 0, pooledO = 0;
  int cells = 0;
  for (size_t i : idx) {
    if (expected[i] == 0) {
      // A sample where the density is zero is an outright failure.
      if (observed[i] > 0) { r.chi2 = 1e30; r.pValue = 0; return r; }
      continue;
    }
    if (expected[i] < 5) { pooledE += expected[i]; pooledO += observed[i]; continue; }
    r.chi2 += (observed[i] - expected[i]) * (observed[i] - expected[i]) / expected[i];
    ++cells;
  }
  if (pooledE > 0) {
    r.chi2 += (pooledO - pooledE) * (pooledO - pooledE) / pooledE;
    ++cells;
  }
  r.dof = cells - 1;
  r.pValue = chi2PValue(r.chi2, r.dof);
  return r;
}

}  // namespace rayes::testing
