// The glossy BRDF of light beam tracing (docs/design.md, "Light beam tracing"; Duvenhage ch. 8-11):
//   f = ρs exp(-φ² / 2σ²) / (2π σ² |cos θi|),  φ = angle between wi and the mirror of wo.
// A Gaussian in the angle from the mirror direction, normalised on the tangent plane, so
// ∫ f cos dωi = ρs ∫ exp(-φ²/2σ²) dω / (2πσ²) ≤ ρs (sin φ ≤ φ, and the lobe below the
// horizon is lost): never above 1 for ρs ≤ 1, close to ρs for σ ≪ π/4. Tends to the mirror
// as σ → 0: below Ggx-like kSmoothSigma it is a delta mirror of weight ρs. Not reciprocal:
// f(wo, wi) / f(wi, wo) = cos θo / cos θi (the model's own claim, tested).
// Sampling: φ from the Rayleigh distribution truncated to [0, π], azimuth uniform about the
// mirror direction: pdf = φ exp(-φ²/2σ²) / (2π σ² sin φ (1 - exp(-π²/2σ²))), weight
// ρs (sin φ / φ)(1 - exp(-π²/2σ²)) for wi above the horizon. cos θi below kMinCos gives f = 0
// (the 1/cos pole is integrable; its contribution there is below float resolution).
// Conventions: bsdf_common.h.
#pragma once
#include "shading/bsdf_common.h"

namespace rayes {

struct GaussianLobe {
  static constexpr float kSmoothSigma = 1e-3f;
  static constexpr float kMinCos = 1e-7f;
  Rgb rho{1, 1, 1};
  float sigma = 0.1f;  // radians

  bool smooth() const { return sigma < kSmoothSigma; }
  Rgb eval(Vec3 wo, Vec3 wi) const {
    if (smooth() || !(wo.z > 0) || !(wi.z > kMinCos)) return {};
    const float phi = angleBetween(wi, mirrorLocal(wo));
    const float f = std::exp(-phi * phi / (2 * sigma * sigma)) / (2 * kPi * sigma * sigma * wi.z);
    return std::isfinite(f) ? rho * f : Rgb{};
  }
  float pdf(Vec3 wo, Vec3 wi) const {
    if (smooth() || !(wo.z > 0) || !(wi.z > 0)) return 0;
    return pdfOfAngle(angleBetween(wi, mirrorLocal(wo)));
  }
  bool sample(Vec3 wo, float u1, float u2, float, BsdfSample& s) const {
    if (!(wo.z > 0)) return false;
    s.etaRel = 1;
    if (smooth()) {
      s.wi = mirrorLocal(wo);
      s.weight = rho;
      s.pdf = 1;
      s.delta = true;
      return true;
    }
    const float tail = truncation();
    // Inverse CDF of the truncated Rayleigh distribution; log1p keeps small u accurate.
    const float phi = std::min(kPi, sigma * std::sqrt(std::max(0.0f, -2.0f * std::log1p(-u1 * (1 - tail)))));
    const float sinPhi = std::sin(phi);
    s.wi = aroundAxis(mirrorLocal(wo), std::cos(phi), sinPhi, 2 * kPi * u2);
    if (!(s.wi.z > kMinCos)) return false;
    s.pdf = pdfOfAngle(phi);
    if (!(s.pdf > 0) || !std::isfinite(s.pdf)) return false;
    s.weight = rho * (sincRatio(phi) * (1 - tail));
    s.delta = false;
    return true;
  }
  Rgb reflectance() const { return rho; }
  bool isDelta() const { return smooth(); }
  bool transmits() const { return false; }

 private:
  float truncation() const { return std::exp(-kPi * kPi / (2 * sigma * sigma)); }
  // sin φ / φ, 1 at φ = 0.
  static float sincRatio(float phi) { return phi < 1e-4f ? 1.0f - phi * phi / 6 : std::sin(phi) / phi; }
  float pdfOfAngle(float phi) const {
    const float s = sincRatio(phi);
    if (!(s > 0)) return 0;  // φ = π: the antipode of the mirror direction, measure zero
    const float p = std::exp(-phi * phi / (2 * sigma * sigma)) / (2 * kPi * sigma * sigma * s * (1 - truncation()));
    return std::isfinite(p) ? p : 0.0f;
  }
};

}  // namespace rayes
