#include "shading/blackbody.h"
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace rayes {
namespace {

constexpr double kStepKelvin = 20, kMaxKelvin = 40000;

double gaussian(double x, double mu, double s1, double s2) {
  const double t = (x - mu) / (x < mu ? s1 : s2);
  return std::exp(-0.5 * t * t);
}

// CIE 1931 2° matching functions, Wyman, Sloan and Shirley (2013), multi-lobe fit (nm).
std::array<double, 3> cie(double nm) {
  const double x = 1.056 * gaussian(nm, 599.8, 37.9, 31.0) + 0.362 * gaussian(nm, 442.0, 16.0, 26.7) -
                   0.065 * gaussian(nm, 501.1, 20.4, 26.2);
  const double y = 0.821 * gaussian(nm, 568.8, 46.9, 40.5) + 0.286 * gaussian(nm, 530.9, 16.3, 31.1);
  const double z = 1.217 * gaussian(nm, 437.0, 11.8, 36.0) + 0.681 * gaussian(nm, 459.0, 26.0, 13.8);
  return {x, y, z};
}

// Planck's law per metre of wavelength (the constant factors cancel in the normalisation).
double planck(double nm, double kelvin) {
  const double l = nm * 1e-9, c = 299792458.0, h = 6.62606957e-34, kb = 1.3806488e-23;
  return 2 * h * c * c / (std::pow(l, 5) * (std::exp(h * c / (l * kb * kelvin)) - 1));
}

Rgb computeRgb(double kelvin) {
  if (kelvin <= 0) return {};
  const double peakNm = 2.8977721e-3 / kelvin * 1e9;  // Wien's displacement law
  const double peak = planck(peakNm, kelvin);
  double X = 0, Y = 0, Z = 0, ySum = 0;
  for (int nm = 360; nm <= 830; ++nm) {
    const std::array<double, 3> m = cie(nm);
    const double s = planck(nm, kelvin) / peak;
    X += s * m[0], Y += s * m[1], Z += s * m[2], ySum += m[1];
  }
  X /= ySum, Y /= ySum, Z /= ySum;
  // XYZ → linear Rec. 709 (sRGB primaries, D65).
  const double r = 3.2404542 * X - 1.5371385 * Y - 0.4985314 * Z;
  const double g = -0.9692660 * X + 1.8760108 * Y + 0.0415560 * Z;
  const double b = 0.0556434 * X - 0.2040259 * Y + 1.0572252 * Z;
  // Outside the gamut (deep red at low temperatures) a channel goes slightly negative: clamped,
  // emission is never negative.
  return {float(std::max(0.0, r)), float(std::max(0.0, g)), float(std::max(0.0, b))};
}

const std::vector<Rgb>& table() {
  static const std::vector<Rgb> t = [] {
    std::vector<Rgb> v(size_t(kMaxKelvin / kStepKelvin) + 1);
    for (size_t i = 0; i < v.size(); ++i) v[i] = computeRgb(double(i) * kStepKelvin);
    return v;
  }();
  return t;
}

}  // namespace

Rgb blackbodyRgb(float kelvin) {
  if (!(kelvin > 0)) return {};
  const std::vector<Rgb>& t = table();
  const double x = std::min(double(kelvin), kMaxKelvin) / kStepKelvin;
  const size_t i = std::min(size_t(x), t.size() - 2);
  const float f = float(x - double(i));
  return t[i] * (1 - f) + t[i + 1] * f;
}

}  // namespace rayes
